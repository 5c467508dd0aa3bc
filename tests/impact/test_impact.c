/* test_impact.c - Newton's law as the simulation runs it: the one solver
 * of simultaneous contacts (MODEL.md section 11), of which the single-stop
 * law (WB 2, energy loss WB 10) is the case nc = 1, on diagonal and
 * non-diagonal mass matrices; two-contact cases against hand-solved 2 x 2
 * LCPs; the impacts a simulation reports; WB 13. */
#include <float.h>
#include <math.h>

#include "vi_testutil.h"

static double kinetic(int n, const double *M, const double *v)
{
  double e = 0;
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) e += 0.5 * v[i] * M[i + j * n] * v[j];
  return e;
}

/* inverse of a 3 x 3 matrix by cofactors (the test's own M^-1) */
static void inv3(const double *A, double *B)
{
#define E(i, j) A[(i) + 3 * (j)]
  double c[9];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      c[i + 3 * j] = E(i1, j1) * E(i2, j2) - E(i1, j2) * E(i2, j1);
    }
  double det = E(0, 0) * c[0] + E(0, 1) * c[3] + E(0, 2) * c[6];
#undef E
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) B[j + 3 * i] = c[i + 3 * j] / det;
}

static void mv3(const double *A, const double *x, double *y)
{
  for (int i = 0; i < 3; i++)
    y[i] = A[i] * x[0] + A[i + 3] * x[1] + A[i + 6] * x[2];
}

static double dot3(const double *a, const double *b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
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

/* The impulse is along w: the momentum p = M v changes by -P w, so every
 * component y.v with y orthogonal to w in the M^-1 metric (y^T M^-1 w = 0)
 * is conserved: y_j = e_j - ((M^-1 w)_j / w^T M^-1 w) w spans them. */
static void test_momentum_orthogonal(void **state)
{
  (void)state;
  const double M[9] = {2.0, 0.3, 0.1, 0.3, 1.5, -0.2, 0.1, -0.2, 1.0};
  const double w[3] = {0.5, -1.2, 2.0};
  double Mi[9], Mw[3];
  inv3(M, Mi);
  mv3(Mi, w, Mw);
  double G = dot3(w, Mw);
  for (int k = 0; k <= 4; k++) {
    double r = 0.25 * k;
    vi_model *m = model3(M, w, r);
    const double vm[3] = {-0.7, 0.9, 1.3};
    double vp[3], vn, ie;
    assert_int_equal(vi_impact_apply(m, vm, vp, &vn, &ie), VI_OK);
    assert_true(vn > 0.0);
    /* the test's own G agrees with the model's (WB 2's denominator) */
    assert_close(vi_model_stop_compliance(m), G, 1e-14);
    for (int j = 0; j < 3; j++) {
      double y[3] = {0, 0, 0};
      y[j] = 1.0;
      for (int i = 0; i < 3; i++) y[i] -= Mw[j] / G * w[i];
      assert_close(dot3(y, Mw), 0.0, 1e-15);
      assert_close(dot3(y, vp), dot3(y, vm), 1e-14);
    }
    /* and the impulse: M (v+ - v-) = -P w with P = (1 + r) v_n / G */
    double dv[3] = {vp[0] - vm[0], vp[1] - vm[1], vp[2] - vm[2]}, Mdv[3];
    mv3(M, dv, Mdv);
    for (int i = 0; i < 3; i++)
      assert_close(Mdv[i], -(1.0 + r) * vn / G * w[i], 1e-14);
    vi_model_destroy(&m);
  }
}

/* Two coupled stops on a non-diagonal M.  The LCP 0 <= P perp G P - e >= 0
 * (MODEL.md section 11) solved by hand with the test's own G = W^T M^-1 W:
 * both active, P = G^-1 e by Cramer's rule; or one active, P_1 = e_1 / G_11,
 * P_2 = 0 where that leaves y_2 = G_21 P_1 - e_2 >= 0. */
typedef struct lcp2 {
  double G[4], u[2], e[2], P[2];
} lcp2;

static void hand_lcp(const double *M, const double *W, const double *r,
                     const double *v, lcp2 *L)
{
  double Mi[9], MW[6];
  inv3(M, Mi);
  for (int k = 0; k < 2; k++) mv3(Mi, W + 3 * (size_t)k, MW + 3 * (size_t)k);
  for (int a = 0; a < 2; a++) {
    for (int b = 0; b < 2; b++) L->G[a + 2 * b] = dot3(W + 3 * (size_t)a, MW + 3 * (size_t)b);
    L->u[a] = dot3(W + 3 * (size_t)a, v);
    L->e[a] = L->u[a] > 0.0 ? (1.0 + r[a]) * L->u[a] : L->u[a];
  }
  const double *G = L->G;
  double det = G[0] * G[3] - G[1] * G[2];
  L->P[0] = (G[3] * L->e[0] - G[2] * L->e[1]) / det;
  L->P[1] = (G[0] * L->e[1] - G[1] * L->e[0]) / det;
  if (L->P[1] < 0.0) { /* contact 2 lifts off */
    L->P[0] = L->e[0] / G[0];
    L->P[1] = 0.0;
  }
}

static void check_two(const double *M, const double *W, const double *r,
                      const double *vm, const lcp2 *L, int active2)
{
  const double K[9] = {2, -1, 0, -1, 2, -1, 0, -1, 1}, xs[2] = {0.1, 0.2};
  vi_model *m = vi_test_model_stops(3, M, NULL, K, 0.0, NULL, NULL, 2, W, xs, r);
  const int both[2] = {0, 1};
  double vp[3], P[2], ie[2];
  assert_int_equal(vi_impact_apply_multi(m, 2, both, vm, vp, P, ie), VI_OK);
  double scale = fabs(L->P[0]) + fabs(L->P[1]);
  assert_close(P[0], L->P[0], 1e-14 * scale);
  assert_close(P[1], L->P[1], 1e-14 * scale);
  assert_true(active2 ? P[1] > 0.0 : P[1] == 0.0);
  /* v+ = v- - M^-1 W P: the momentum jump M dv = -W P */
  double dv[3] = {vp[0] - vm[0], vp[1] - vm[1], vp[2] - vm[2]}, Mdv[3];
  mv3(M, dv, Mdv);
  for (int i = 0; i < 3; i++)
    assert_close(Mdv[i], -(W[i] * P[0] + W[3 + i] * P[1]), 1e-14 * scale);
  /* complementarity on the post-impact velocities u+ = W^T v+: the slack
   * y_k = -(u+_k + r_k u_k) >= 0 (r_k -> 0 for a contact not approaching)
   * vanishes where the contact takes an impulse */
  for (int k = 0; k < 2; k++) {
    double up = dot3(W + 3 * (size_t)k, vp), y = -(up + (L->u[k] > 0 ? r[k] * L->u[k] : 0.0));
    if (P[k] > 0.0) assert_close(y, 0.0, 1e-14 * (fabs(L->u[0]) + fabs(L->u[1])));
    else assert_true(y > 0.0);
  }
  /* energy: the contacts' shares sum to the kinetic energy lost */
  assert_close(kinetic(3, M, vm) - kinetic(3, M, vp), ie[0] + ie[1], 1e-14);
  for (int k = 0; k < 2; k++)
    if (L->u[k] > 0.0)
      assert_close(ie[k], 0.5 * P[k] * L->u[k] * (1.0 - r[k]), 1e-14);
  vi_model_destroy(&m);
}

static void test_two_contacts_hand_lcp(void **state)
{
  (void)state;
  const double M[9] = {2.0, 0.3, 0.1, 0.3, 1.5, -0.2, 0.1, -0.2, 1.0};
  /* w_1 = e_3, w_2 = +-e_2: G_12 = -+(M^-1)_23, one sign of each */
  double W[6] = {0, 0, 1, 0, 1, 0}, Mi[9];
  inv3(M, Mi);
  if (Mi[1 + 3 * 2] < 0.0) W[4] = -1.0; /* now G_12 > 0 */
  const double r[2] = {0.7, 0.4};
  lcp2 L;
  /* (i) both approaching, both take an impulse */
  double v1[3] = {0.2, 0.8 * W[4], 1.0};
  hand_lcp(M, W, r, v1, &L);
  assert_true(L.P[0] > 0.0 && L.P[1] > 0.0);
  check_two(M, W, r, v1, &L, 1);
  /* (ii) contact 2 approaches slowly: contact 1's impulse (G_12 > 0)
   * throws it back faster than -r_2 u_2, so it takes none */
  double v2[3] = {0.2, 0.01 * W[4], 1.0};
  hand_lcp(M, W, r, v2, &L);
  assert_true(L.u[1] > 0.0 && L.P[1] == 0.0);
  check_two(M, W, r, v2, &L, 0);
  /* (iii) contact 2 closed and at rest (u_2 = 0), G_12 < 0: contact 1's
   * impulse would drive it into the stop; the plastic rule holds it at
   * u+_2 = 0 with an impulse of its own */
  W[4] = -W[4];
  double v3[3] = {0.2, 0.0, 1.0};
  hand_lcp(M, W, r, v3, &L);
  assert_true(L.u[1] == 0.0 && L.P[1] > 0.0);
  check_two(M, W, r, v3, &L, 1);
}

/* The impacts a simulation reports obey the law: Fig. 2 (M = I, w = e_2,
 * r = 0.7) under the closed-form and the CVODE backends: w.v+ = -r w.v-,
 * v_1 unchanged, IE = 1/2 v_n^2 (1 - r^2) (WB 10, G = 1), the kinetic
 * energy lost.  The closed form takes the bounce in modes: its v_n is
 * psi.q' and the event's v- the physical view Psi q', the same sum in
 * another order, so they agree to a rounding (CVODE's exactly). */
static void test_simulation_impacts(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  const int methods[2] = {VI_METHOD_EXACT, VI_METHOD_ADAMS};
  for (int k = 0; k < 2; k++) {
    vi_test_rec ev = {0};
    vi_sim *s = vi_test_sim_stops(m, methods[k], 1e-12, 1e-14, 0.0, NULL, NULL, &ev);
    assert_int_equal(vi_sim_run(s, 30.0 * 2.0 * M_PI / 0.9), VI_OK);
    assert_true(ev.count > 20);
    for (int i = 0; i < ev.count; i++) {
      const double *vm = ev.vm + 2 * (size_t)i, *vp = ev.vp + 2 * (size_t)i;
      assert_int_equal(ev.kind[i], VI_EVENT_IMPACT);
      assert_int_equal(ev.stop[i], 0);
      assert_close(ev.vn[i], vm[1], k == 0 ? 4.0 * DBL_EPSILON * vm[1] : 0.0);
      assert_true(vm[1] > 0.0);
      assert_close(vp[1], -0.7 * vm[1], 1e-15 * vm[1]);
      assert_close(vp[0], vm[0], 0.0);
      double ie = 0.5 * vm[1] * vm[1] * (1.0 - 0.49);
      assert_close(ev.ie[i], ie, 1e-15);
      double ke = 0.5 * (vm[0] * vm[0] + vm[1] * vm[1] - vp[0] * vp[0] - vp[1] * vp[1]);
      assert_close(ke, ie, 1e-15);
    }
    vi_sim_destroy(&s);
    vi_test_rec_free(&ev);
  }
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
      cmocka_unit_test(test_momentum_orthogonal),
      cmocka_unit_test(test_two_contacts_hand_lcp),
      cmocka_unit_test(test_simulation_impacts),
      cmocka_unit_test(test_restitution_from_energy),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
