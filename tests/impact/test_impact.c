/* test_impact.c - the restitution law (WB 2), its energy loss (WB 10) and
 * WB 13, on diagonal and non-diagonal mass matrices. */
#include <math.h>

#include "vi_testutil.h"

static double kinetic(int n, const double *M, const double *v)
{
  double e = 0;
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) e += 0.5 * v[i] * M[i + j * n] * v[j];
  return e;
}

static vi_model *model3(const double *M, const double *w, double r)
{
  const double K[9] = {2, -1, 0, -1, 2, -1, 0, -1, 1};
  return vi_test_model(3, M, NULL, K, 0.0, NULL, NULL, w, 0.1, r);
}

/* Diagonal M, w = e_N: R = diag(1, ..., 1, -r) exactly as in the paper. */
static void test_diagonal_is_paper_R(void **state)
{
  (void)state;
  const double M[9] = {1.5, 0, 0, 0, 2.0, 0, 0, 0, 0.7};
  const double w[3] = {0, 0, 1};
  vi_model *m = model3(M, w, 0.6);
  const double vm[3] = {0.3, -0.2, 1.25};
  double vp[3], vn, ie;
  assert_int_equal(vi_impact_apply(m, vm, vp, &vn, &ie), VI_OK);
  assert_close(vn, 1.25, 0);
  assert_close(vp[0], 0.3, 0);
  assert_close(vp[1], -0.2, 0);
  assert_close(vp[2], -0.6 * 1.25, 1e-15);
  /* IE = 1/2 m_N v_N^2 (1 - r^2) */
  assert_close(ie, 0.5 * 0.7 * 1.25 * 1.25 * (1 - 0.36), 1e-15);
  assert_close(kinetic(3, M, vm) - kinetic(3, M, vp), ie, 1e-15);
  vi_model_destroy(&m);
}

/* Non-diagonal M, non-unit w: w.v+ = -r v_n, the loss matches WB 10, the
 * velocity jump lies along M^-1 w (an impulse along w). */
static void test_general_mass_and_stop(void **state)
{
  (void)state;
  const double M[9] = {2.0, 0.3, 0.1, 0.3, 1.5, -0.2, 0.1, -0.2, 1.0};
  const double w[3] = {0.5, -1.2, 2.0};
  for (int k = 0; k <= 4; k++) {
    double r = 0.25 * k;
    vi_model *m = model3(M, w, r);
    const double vm[3] = {0.4, -0.3, 0.8};
    double vp[3], vn, ie;
    assert_int_equal(vi_impact_apply(m, vm, vp, &vn, &ie), VI_OK);
    double wvm = w[0] * vm[0] + w[1] * vm[1] + w[2] * vm[2];
    double wvp = w[0] * vp[0] + w[1] * vp[1] + w[2] * vp[2];
    assert_close(vn, wvm, 1e-15);
    assert_close(wvp, -r * vn, 1e-14);
    double wMw = vi_model_stop_compliance(m);
    assert_close(ie, 0.5 * vn * vn * (1 - r * r) / wMw, 1e-14);
    assert_close(kinetic(3, M, vm) - kinetic(3, M, vp), ie, 1e-14);
    if (r == 1.0) assert_close(ie, 0.0, 0.0);
    /* M (v+ - v-) is parallel to w: M dv x w = 0 */
    double Mdv[3];
    for (int i = 0; i < 3; i++) {
      Mdv[i] = 0;
      for (int j = 0; j < 3; j++) Mdv[i] += M[i + j * 3] * (vp[j] - vm[j]);
    }
    assert_close(Mdv[1] * w[2] - Mdv[2] * w[1], 0.0, 1e-14);
    assert_close(Mdv[2] * w[0] - Mdv[0] * w[2], 0.0, 1e-14);
    /* in modal coordinates the same map is I - (1+r) psi psi^T / psi.psi */
    double qm[3], qp[3];
    const double *psi = vi_model_modal_stop(m);
    vi_model_to_modal(m, vm, qm);
    vi_model_to_modal(m, vp, qp);
    double pq = psi[0] * qm[0] + psi[1] * qm[1] + psi[2] * qm[2];
    for (int j = 0; j < 3; j++)
      assert_close(qp[j], qm[j] - (1 + r) * psi[j] * pq / wMw, 1e-14);
    vi_model_destroy(&m);
  }
}

static void test_separating_is_not_an_impact(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  const double vm[2] = {0.3, -0.1};
  double vp[2], vn, ie;
  assert_int_equal(vi_impact_apply(m, vm, vp, &vn, &ie), VI_OK);
  assert_close(vp[0], vm[0], 0);
  assert_close(vp[1], vm[1], 0);
  assert_close(ie, 0, 0);
  assert_int_equal(vi_impact_apply_r(m, 1.2, vm, vp, NULL, NULL),
                   VI_ERR_RESTITUTION);
  vi_model_destroy(&m);
}

/* WB 13 inverts WB 10 / WB 12: RE = KE_i (1 - r^2). */
static void test_restitution_from_energy(void **state)
{
  (void)state;
  double r;
  for (int k = 0; k <= 10; k++) {
    double r0 = 0.1 * k, ke = 1.7;
    assert_int_equal(vi_restitution_from_energy(ke * (1 - r0 * r0), ke, &r), VI_OK);
    assert_close(r, r0, 1e-8); /* sqrt amplifies round-off near r = 0 */
  }
  assert_int_equal(vi_restitution_from_energy(2.0, 1.0, &r), VI_ERR_ARG);
  assert_int_equal(vi_restitution_from_energy(-0.1, 1.0, &r), VI_ERR_ARG);
  assert_int_equal(vi_restitution_from_energy(0.1, 0.0, &r), VI_ERR_ARG);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_diagonal_is_paper_R),
      cmocka_unit_test(test_general_mass_and_stop),
      cmocka_unit_test(test_separating_is_not_an_impact),
      cmocka_unit_test(test_restitution_from_energy),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
