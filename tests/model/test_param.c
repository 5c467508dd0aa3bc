/* test_param.c - parameters by key (vi_param.h) on set-up models, against
 * closed forms: the steady harmonic response x = Re(H a e^{i Omega t}),
 * H = (K - Omega^2 M + i Omega C)^-1, of a changed model started on it
 * (stop out of reach), and the modal damping ratios of Rayleigh damping,
 * zeta_j = alpha / (2 omega_j) + beta omega_j / 2 (MODEL.md section 3). */
#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vi_testutil.h"

/* Fig. 2's chain: omega_1,2 = (sqrt 5 -+ 1) / 2 (K = [2 -1; -1 1], M = I) */
#define W1 0.61803398874989484820
#define W2 1.61803398874989484820

/* Harmonic response of the 2-mass chain (M = I, K = [2 -1; -1 1]) with
 * C = [c11 c12; c12 c22] to a cos(Om t), at time t: x [2], v [2]. */
static void harmonic2(double Om, double c11, double c12, double c22,
                      const double *a, double t, double *x, double *v)
{
  double complex h11 = 2 - Om * Om + I * Om * c11, h12 = -1 + I * Om * c12,
                 h22 = 1 - Om * Om + I * Om * c22, det = h11 * h22 - h12 * h12;
  double complex X1 = (h22 * a[0] - h12 * a[1]) / det,
                 X2 = (h11 * a[1] - h12 * a[0]) / det, e = cexp(I * Om * t);
  x[0] = creal(X1 * e);
  x[1] = creal(X2 * e);
  v[0] = creal(I * Om * X1 * e);
  v[1] = creal(I * Om * X2 * e);
}

/* Run m from its harmonic response at t = 0 for 7.3 time units and compare
 * with the closed form there; C given by c11, c12, c22. */
static void check_steady(const vi_model *m, int method, double tol, double Om,
                         double c11, double c12, double c22, const double *a)
{
  double x0[2], v0[2], x[2], v[2], xr[2], vr[2], t_end = 7.3;
  harmonic2(Om, c11, c12, c22, a, 0.0, x0, v0);
  vi_sim *s = vi_test_sim(m, method, 1e-11, 1e-13, x0, v0, NULL);
  assert_int_equal(vi_sim_run(s, t_end), VI_OK);
  assert_int_equal(vi_sim_state(s, NULL, x, v), VI_OK);
  harmonic2(Om, c11, c12, c22, a, t_end, xr, vr);
  for (int i = 0; i < 2; i++) {
    assert_close(x[i], xr[i], tol);
    assert_close(v[i], vr[i], tol);
  }
  vi_sim_destroy(&s);
}

/* Omega, a and x_s changed on the set-up Fig. 2 model: the motion is the
 * harmonic response at the new values (C = 0.1 K).  The exact flow's
 * error is round-off: 1e-12. */
static void forcing_and_stop(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  double a[2] = {0.3, 0.2}, val;
  assert_int_equal(vi_model_set_param(m, "forcing.omega", 1.3), VI_OK);
  assert_int_equal(vi_model_set_param(m, "forcing.a[1]", a[0]), VI_OK);
  assert_int_equal(vi_model_set_param(m, "forcing.a[2]", a[1]), VI_OK);
  assert_int_equal(vi_model_set_param(m, "stop.xs", 100.0), VI_OK);
  assert_int_equal(vi_model_param(m, "stops[1].xs", &val), VI_OK);
  assert_true(val == 100.0);
  assert_true(vi_model_clearance(m) == 100.0);
  assert_true(vi_model_omega_forcing(m) == 1.3);
  /* M^-1 a = a (M = I) and Psi^T a from the modes */
  const double *Fa = vi_model_modal_forcing_cos(m), *Psi;
  int ld;
  Psi = vi_model_modal_shapes(m, &ld);
  for (int j = 0; j < 2; j++)
    assert_close(Fa[j], Psi[0 + j * ld] * a[0] + Psi[1 + j * ld] * a[1], 1e-15);
  check_steady(m, VI_METHOD_EXACT, 1e-12, 1.3, 0.2, -0.1, 0.1, a);
  check_steady(m, VI_METHOD_ADAMS, 1e-8, 1.3, 0.2, -0.1, 0.1, a);
  vi_model_destroy(&m);
}

/* Rayleigh damping set on a model whose C was a matrix: the closed-form
 * ratios, C itself, and the harmonic response with that C; on the band
 * chain too (Adams, tolerance from rtol 1e-11 over a few periods). */
static void rayleigh(void **state)
{
  (void)state;
  const double al = 0.02, be = 0.03, a[2] = {0.5, 0.0};
  vi_model *m = vi_test_fig2();
  double val;
  assert_int_equal(vi_model_param(m, "damping.alpha", &val), VI_OK);
  assert_true(isnan(val)); /* C was given as a matrix */
  assert_int_equal(vi_model_set_param(m, "damping.alpha", al), VI_OK);
  assert_int_equal(vi_model_set_param(m, "damping.beta", be), VI_OK);
  assert_int_equal(vi_model_param(m, "damping.alpha", &val), VI_OK);
  assert_true(val == al);
  const double *z = vi_model_zeta(m), *C = vi_model_damping(m);
  assert_close(z[0], al / (2 * W1) + be * W1 / 2, 1e-15);
  assert_close(z[1], al / (2 * W2) + be * W2 / 2, 1e-15);
  assert_true(vi_model_is_proportional(m));
  assert_close(C[0], al + 2 * be, 1e-16);
  assert_close(C[2], -be, 1e-16);
  assert_close(C[3], al + be, 1e-16);
  assert_int_equal(vi_model_set_param(m, "stop.xs", 50.0), VI_OK);
  check_steady(m, VI_METHOD_EXACT, 1e-12, 0.9, al + 2 * be, -be, al + be, a);
  check_steady(m, VI_METHOD_BDF, 1e-8, 0.9, al + 2 * be, -be, al + be, a);
  vi_model_destroy(&m);

  double mass[2] = {1, 1}, k[2] = {1, 1}, c[2] = {0.1, 0.1}, w[2] = {0, 1};
  assert_int_equal(vi_model_create_chain(2, mass, k, c, &m), VI_OK);
  assert_int_equal(vi_model_set_forcing(m, 0.9, a, NULL, NULL), VI_OK);
  assert_int_equal(vi_model_set_stop(m, w, 100.0, 0.7), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  assert_int_equal(vi_model_set_param(m, "damping.beta", be), VI_OK);
  assert_int_equal(vi_model_set_param(m, "damping.alpha", al), VI_OK);
  assert_int_equal(vi_model_set_param(m, "forcing.omega", 1.1), VI_OK);
  check_steady(m, VI_METHOD_ADAMS, 1e-8, 1.1, al + 2 * be, -be, al + be, a);
  assert_int_equal(vi_model_set_param(m, "damping.zeta", 0.1),
                   VI_ERR_UNSUPPORTED); /* a band model has no modes */
  assert_non_null(strstr(vi_model_errmsg(m), "damping.zeta"));
  vi_model_destroy(&m);
}

/* Modal ratios: two ratios on two modes are one Rayleigh pair,
 * alpha = 2 w1 w2 (z1 w2 - z2 w1) / (w2^2 - w1^2),
 * beta = 2 (z2 w2 - z1 w1) / (w2^2 - w1^2). */
static void modal_zeta(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  const double z1 = 0.05, z2 = 0.02, a[2] = {0.5, 0.0};
  double val;
  assert_int_equal(vi_model_set_param(m, "damping.zeta[1]", z1), VI_OK);
  assert_int_equal(vi_model_set_param(m, "damping.zeta[2]", z2), VI_OK);
  assert_int_equal(vi_model_param(m, "damping.zeta[1]", &val), VI_OK);
  assert_close(val, z1, 1e-16);
  double d = W2 * W2 - W1 * W1, al = 2 * W1 * W2 * (z1 * W2 - z2 * W1) / d,
         be = 2 * (z2 * W2 - z1 * W1) / d;
  const double *C = vi_model_damping(m);
  assert_close(C[0], al + 2 * be, 1e-15);
  assert_close(C[1], -be, 1e-15);
  assert_close(C[3], al + be, 1e-15);
  assert_int_equal(vi_model_set_param(m, "stop.xs", 100.0), VI_OK);
  check_steady(m, VI_METHOD_EXACT, 1e-12, 0.9, al + 2 * be, -be, al + be, a);
  assert_int_equal(vi_model_param(m, "damping.zeta", &val), VI_ERR_UNSUPPORTED);
  assert_int_equal(vi_model_set_param(m, "damping.zeta", 0.03), VI_OK);
  assert_int_equal(vi_model_param(m, "damping.zeta", &val), VI_OK);
  assert_close(val, 0.03, 1e-16);
  vi_model_destroy(&m);
}

/* A copy is independent: changed, it leaves the original as it was. */
static void copies(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2(), *c = NULL;
  assert_int_equal(vi_model_copy(m, &c), VI_OK);
  assert_int_equal(vi_model_set_param(c, "forcing.omega", 1.3), VI_OK);
  assert_int_equal(vi_model_set_param(c, "stop.xs", 100.0), VI_OK);
  assert_int_equal(vi_model_set_param(c, "forcing.a[2]", 0.2), VI_OK);
  assert_true(vi_model_omega_forcing(m) == 0.9);
  assert_true(vi_model_clearance(m) == 0.1);
  assert_true(vi_model_forcing_cos(m)[1] == 0.0);
  assert_true(vi_model_modal_forcing_cos(m) != vi_model_modal_forcing_cos(c));
  vi_model_destroy(&m); /* the copy outlives its original */
  const double a[2] = {0.5, 0.2};
  check_steady(c, VI_METHOD_EXACT, 1e-12, 1.3, 0.2, -0.1, 0.1, a);
  vi_model_destroy(&c);
}

/* Bad keys and values: clear errors naming the key, the model unchanged. */
static void bad_keys(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  double val, t0 = 0, x[2] = {0, 0}, v[2] = {0, 0};
  assert_int_equal(vi_model_set_param(m, "forcing.omgea", 1.0), VI_ERR_ARG);
  assert_non_null(strstr(vi_model_errmsg(m), "forcing.omgea"));
  assert_non_null(strstr(vi_model_errmsg(m), "forcing.a[i]"));
  assert_int_equal(vi_model_set_param(m, "run.method", 1.0), VI_ERR_ARG);
  assert_int_equal(vi_model_set_param(m, "forcing.a[x]", 1.0), VI_ERR_ARG);
  assert_int_equal(vi_model_set_param(m, "forcing.a[3]", 1.0), VI_ERR_DIM);
  assert_int_equal(vi_model_set_param(m, "forcing.a[0]", 1.0), VI_ERR_DIM);
  assert_int_equal(vi_model_set_param(m, "stops[2].xs", 1.0), VI_ERR_DIM);
  assert_int_equal(vi_model_set_param(m, "stop.r", 1.5), VI_ERR_RESTITUTION);
  assert_non_null(strstr(vi_model_errmsg(m), "stop.r"));
  assert_int_equal(vi_model_set_param(m, "forcing.omega", -1), VI_ERR_FREQUENCY);
  assert_int_equal(vi_model_set_param(m, "forcing.omega", 0), VI_ERR_FREQUENCY);
  assert_int_equal(vi_model_set_param(m, "forcing.omega", NAN), VI_ERR_NONFINITE);
  assert_int_equal(vi_model_set_param(m, "damping.beta", -1), VI_ERR_NOT_PSD);
  assert_int_equal(vi_model_set_param(m, "initial.x[1]", 1), VI_ERR_ARG);
  assert_true(vi_model_restitution(m) == 0.7);
  assert_true(vi_model_omega_forcing(m) == 0.9);
  assert_int_equal(vi_model_param(m, "stop.r", &val), VI_OK);
  assert_true(val == 0.7);
  /* the initial state */
  assert_int_equal(vi_param_kind("initial.v[2]"), VI_PARAM_INITIAL_STATE);
  assert_int_equal(vi_param_kind("stops[3].r"), VI_PARAM_MODEL);
  assert_int_equal(vi_param_kind("model.chain.k"), VI_PARAM_UNKNOWN);
  assert_int_equal(vi_param_set_initial("initial.v[2]", 0.4, 2, &t0, x, v), VI_OK);
  assert_true(v[1] == 0.4);
  assert_int_equal(vi_param_set_initial("initial.t0", 2.5, 2, &t0, x, v), VI_OK);
  assert_true(t0 == 2.5);
  assert_int_equal(vi_param_set_initial("initial.x[3]", 0.4, 2, &t0, x, v), VI_ERR_DIM);
  assert_int_equal(vi_param_set_initial("forcing.omega", 0.4, 2, &t0, x, v), VI_ERR_ARG);
  assert_int_equal(vi_param_initial("initial.v[2]", 2, t0, x, v, &val), VI_OK);
  assert_true(val == 0.4);
  for (int i = 0; i < vi_param_key_count(); i++)
    assert_non_null(vi_param_key_name(i));
  assert_null(vi_param_key_name(vi_param_key_count()));
  vi_model_destroy(&m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(forcing_and_stop), cmocka_unit_test(rayleigh),
      cmocka_unit_test(modal_zeta), cmocka_unit_test(copies),
      cmocka_unit_test(bad_keys)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
