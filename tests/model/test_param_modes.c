/* test_param_modes.c - the structural keys of vi_param.h (mass.scale,
 * stiffness.scale, damping.scale): a set-up model whose M or K changes has
 * its modes redone, against closed forms and against a model built
 * directly with the new matrices:
 * - one mass on a spring: omega_n = sqrt(k / m);
 * - the 2-mass chain M = m I, K = k [2 -1; -1 1]: omega^2 = (k / m)
 *   (3 -+ sqrt 5) / 2, and M^-1 K, Psi^T a, the stop's compliance w^T M^-1 w
 *   = 1 / m;
 * - a changed model and one built with the same k, m: the same matrices
 *   and derived arrays bit for bit (a chain's K = k T with T's entries 2,
 *   -1, 1 is exact), and the same impacts over 30 periods;
 * - Rayleigh damping follows M and K, modal ratios stay, C as a matrix
 *   stays; the band set-up is redone too;
 * - bad values leave the model as it was. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vi_testutil.h"
#include "vibroimpact/vi_param.h"

static void sdof_frequency(void **state)
{
  (void)state;
  vi_model *m = vi_test_sdof(1.0, 0.0, 1.0, 0.3, 0.0, 0.5, 1.0, 0.8);
  double val;
  assert_int_equal(vi_model_param(m, "stiffness.scale", &val), VI_OK);
  assert_true(val == 1.0);
  static const double kk[3] = {4.0, 0.25, 7.3}, mm[3] = {1.0, 2.0, 0.3};
  for (int i = 0; i < 3; i++) {
    assert_int_equal(vi_model_set_param(m, "stiffness.scale", kk[i]), VI_OK);
    assert_int_equal(vi_model_set_param(m, "mass.scale", mm[i]), VI_OK);
    assert_close(vi_model_omega(m)[0], sqrt(kk[i] / mm[i]), 1e-15 * sqrt(kk[i] / mm[i]));
    assert_close(vi_model_stop_compliance(m), 1.0 / mm[i], 1e-15 / mm[i]);
    assert_int_equal(vi_model_param(m, "mass.scale", &val), VI_OK);
    assert_true(val == mm[i]);
  }
  vi_model_destroy(&m);
}

/* The 2-mass chain's closed-form eigenvalues after k and m change. */
static void chain_eigenvalues(void **state)
{
  (void)state;
  const double a[2] = {0.5, 0.0};
  vi_model *m = vi_test_chain(2, 1.0, 1.0, 0.0, 0.1, 0.7, 0.9, a);
  static const double kk[4] = {2.5, 0.4, 1.0, 9.0}, mm[4] = {0.5, 1.0, 3.0, 1.7};
  for (int i = 0; i < 4; i++) {
    assert_int_equal(vi_model_set_param(m, "stiffness.scale", kk[i]), VI_OK);
    assert_int_equal(vi_model_set_param(m, "mass.scale", mm[i]), VI_OK);
    double r = kk[i] / mm[i], w1 = sqrt(r * (3 - sqrt(5)) / 2),
           w2 = sqrt(r * (3 + sqrt(5)) / 2);
    const double *om = vi_model_omega(m);
    assert_close(om[0], w1, 1e-14 * w2);
    assert_close(om[1], w2, 1e-14 * w2);
    /* Psi is M-orthonormal: Psi^T a with a = (0.5, 0): the first row */
    int ld;
    const double *Psi = vi_model_modal_shapes(m, &ld), *Fa = vi_model_modal_forcing_cos(m);
    for (int j = 0; j < 2; j++) {
      double nrm = mm[i] * (Psi[0 + j * ld] * Psi[0 + j * ld] + Psi[1 + j * ld] * Psi[1 + j * ld]);
      assert_close(nrm, 1.0, 1e-14);
      assert_close(Fa[j], 0.5 * Psi[0 + j * ld], 1e-15);
    }
    assert_close(vi_model_stop_compliance(m), 1.0 / mm[i], 1e-15 / mm[i]);
  }
  vi_model_destroy(&m);
}

typedef struct hits {
  int n;
  double t[64], vn[64];
} hits;

static int on_hit(const vi_event *ev, void *user)
{
  hits *h = user;
  if (ev->kind == VI_EVENT_IMPACT && h->n < 64) {
    h->t[h->n] = ev->t;
    h->vn[h->n++] = ev->vn;
  }
  return 0;
}

/* The impacts over 30 forcing periods from rest: the closed-form flow,
 * or (band storage, no modes) Adams at rtol 1e-12. */
static void impacts(const vi_model *m, int method, hits *h)
{
  vi_sim *s = NULL;
  memset(h, 0, sizeof *h);
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_sim_set_method(s, method), VI_OK);
  assert_int_equal(vi_sim_set_tolerances(s, 1e-12, 1e-14), VI_OK);
  assert_int_equal(vi_sim_set_event_callback(s, on_hit, h, NULL), VI_OK);
  assert_int_equal(vi_sim_run(s, 30 * 2 * M_PI / vi_model_omega_forcing(m)), VI_OK);
  vi_sim_destroy(&s);
  assert_true(h->n > 10);
}

/* Fig. 2 changed to k = 1.3, m = 0.8, c = 0.07 against Fig. 2 built with
 * them: the same model bit for bit, so the same impacts. */
static void same_as_built(void **state)
{
  (void)state;
  const double a[2] = {0.5, 0.0};
  vi_model *m = vi_test_fig2();
  vi_model *d = vi_test_chain(2, 0.8, 1.3, 0.07, 0.1, 0.7, 0.9, a);
  /* Fig. 2's C = 0.1 T: damping.scale 0.7 gives 0.07 T */
  assert_int_equal(vi_model_set_param(m, "stiffness.scale", 1.3), VI_OK);
  assert_int_equal(vi_model_set_param(m, "mass.scale", 0.8), VI_OK);
  assert_int_equal(vi_model_set_param(m, "damping.scale", 0.7), VI_OK);
  const double *pm[] = {vi_model_mass(m), vi_model_stiffness(m), vi_model_omega(m),
                        vi_model_modal_forcing_cos(m), vi_model_modal_stop(m)};
  const double *pd[] = {vi_model_mass(d), vi_model_stiffness(d), vi_model_omega(d),
                        vi_model_modal_forcing_cos(d), vi_model_modal_stop(d)};
  static const int len[] = {4, 4, 2, 2, 2};
  for (int q = 0; q < 5; q++)
    for (int i = 0; i < len[q]; i++) assert_true(pm[q][i] == pd[q][i]);
  /* C: 0.1 * 0.7 against 0.07 differ in the last bit; one ulp */
  for (int i = 0; i < 4; i++)
    assert_close(vi_model_damping(m)[i], vi_model_damping(d)[i], 3e-17);
  hits hm, hd;
  impacts(m, VI_METHOD_EXACT, &hm);
  impacts(d, VI_METHOD_EXACT, &hd);
  assert_int_equal(hm.n, hd.n);
  for (int i = 0; i < hm.n; i++) {
    assert_close(hm.t[i], hd.t[i], 1e-12);
    assert_close(hm.vn[i], hd.vn[i], 1e-12);
  }
  vi_model_destroy(&m);
  vi_model_destroy(&d);
}

/* Rayleigh C = alpha M + beta K follows; modal ratios stay on the new
 * modes; damping.scale is refused for both. */
static void damping_follows(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  assert_int_equal(vi_model_set_param(m, "damping.alpha", 0.02), VI_OK);
  assert_int_equal(vi_model_set_param(m, "damping.beta", 0.03), VI_OK);
  assert_int_equal(vi_model_set_param(m, "stiffness.scale", 4.0), VI_OK);
  assert_int_equal(vi_model_set_param(m, "mass.scale", 2.0), VI_OK);
  const double *C = vi_model_damping(m), *z = vi_model_zeta(m), *om = vi_model_omega(m);
  assert_close(C[0], 0.02 * 2 + 0.03 * 8, 1e-16);
  assert_close(C[2], -0.03 * 4, 1e-16);
  for (int j = 0; j < 2; j++) /* zeta_j = alpha / (2 w_j) + beta w_j / 2 */
    assert_close(z[j], 0.02 / (2 * om[j]) + 0.03 * om[j] / 2, 1e-15);
  assert_int_equal(vi_model_set_param(m, "damping.scale", 2.0), VI_ERR_UNSUPPORTED);
  assert_non_null(strstr(vi_model_errmsg(m), "damping.alpha"));
  vi_model_destroy(&m);

  m = vi_test_fig2();
  assert_int_equal(vi_model_set_param(m, "damping.zeta", 0.05), VI_OK);
  assert_int_equal(vi_model_set_param(m, "stiffness.scale", 9.0), VI_OK);
  z = vi_model_zeta(m);
  om = vi_model_omega(m);
  assert_close(om[0], 3 * (sqrt(5) - 1) / 2, 1e-14);
  for (int j = 0; j < 2; j++) {
    assert_close(z[j], 0.05, 1e-16);
    /* D = Psi^T C Psi = diag(2 zeta_j omega_j): Psi^T C Psi from C */
    int ld;
    const double *Psi = vi_model_modal_shapes(m, &ld);
    C = vi_model_damping(m);
    double d = 0;
    for (int p = 0; p < 2; p++)
      for (int q = 0; q < 2; q++) d += Psi[p + j * ld] * C[p + 2 * q] * Psi[q + j * ld];
    assert_close(d, 2 * 0.05 * om[j], 1e-14);
  }
  assert_int_equal(vi_model_set_param(m, "damping.scale", 2.0), VI_ERR_UNSUPPORTED);
  vi_model_destroy(&m);
}

/* The band chain: the band set-up is redone (its frequency bound scales
 * as sqrt(k / m)), and the impacts match a band chain built with k. */
static void band_chain(void **state)
{
  (void)state;
  const double a[3] = {0.0, 0.0, 0.4};
  double mass[3] = {1, 1, 1}, k[3] = {1, 1, 1}, k2[3] = {2.25, 2.25, 2.25},
         c[3] = {0.05, 0.05, 0.05}, w[3] = {0, 0, 1};
  vi_model *m = NULL, *d = NULL;
  assert_int_equal(vi_model_create_chain(3, mass, k, c, &m), VI_OK);
  assert_int_equal(vi_model_create_chain(3, mass, k2, c, &d), VI_OK);
  vi_model *both[2] = {m, d};
  for (int i = 0; i < 2; i++) {
    assert_int_equal(vi_model_set_forcing(both[i], 0.7, a, NULL, NULL), VI_OK);
    assert_int_equal(vi_model_set_stop(both[i], w, 0.2, 0.8), VI_OK);
    assert_int_equal(vi_model_setup(both[i]), VI_OK);
  }
  double b1 = vi_model_omega_bound(m);
  assert_int_equal(vi_model_set_param(m, "stiffness.scale", 2.25), VI_OK);
  assert_close(vi_model_omega_bound(m), 1.5 * b1, 1e-14 * b1);
  hits hm, hd;
  impacts(m, VI_METHOD_ADAMS, &hm);
  impacts(d, VI_METHOD_ADAMS, &hd);
  assert_int_equal(hm.n, hd.n);
  /* the same model, so the same steps: round-off only */
  for (int i = 0; i < hm.n; i++) assert_close(hm.t[i], hd.t[i], 1e-10);
  vi_model_destroy(&m);
  vi_model_destroy(&d);
}

/* Bad values: the model is as it was; a copy carries its base. */
static void bad_values(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2(), *c = NULL;
  double w0 = vi_model_omega(m)[0], val;
  assert_int_equal(vi_model_set_param(m, "mass.scale", 0.0), VI_ERR_NOT_SPD);
  assert_non_null(strstr(vi_model_errmsg(m), "mass.scale"));
  assert_int_equal(vi_model_set_param(m, "stiffness.scale", -1.0), VI_ERR_NOT_PSD);
  assert_int_equal(vi_model_set_param(m, "stiffness.scale", NAN), VI_ERR_NONFINITE);
  assert_int_equal(vi_model_set_param(m, "damping.scale", -0.5), VI_ERR_NOT_PSD);
  assert_true(vi_model_omega(m)[0] == w0);
  assert_int_equal(vi_model_param(m, "stiffness.scale", &val), VI_OK);
  assert_true(val == 1.0);
  assert_int_equal(vi_model_set_param(m, "stiffness.scale", 4.0), VI_OK);
  assert_int_equal(vi_model_copy(m, &c), VI_OK);
  vi_model_destroy(&m);
  assert_int_equal(vi_model_set_param(c, "stiffness.scale", 1.0), VI_OK);
  assert_close(vi_model_omega(c)[0], w0, 1e-15); /* back to Fig. 2 */
  vi_model_destroy(&c);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(sdof_frequency),
      cmocka_unit_test(chain_eigenvalues),
      cmocka_unit_test(same_as_built),
      cmocka_unit_test(damping_follows),
      cmocka_unit_test(band_chain),
      cmocka_unit_test(bad_values),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
