/* test_xseg_run.c - a flight evaluated at a run of uniform times
 * (vi_xseg_modal_run, internal: the identification's samples) against the
 * closed form at each time (vi_xseg_modal): the flow's semigroup property,
 * carried over 64 steps, in every damping regime the propagator has and
 * with a constant force; and the run's last state against Runge-Kutta on
 * the physical equations, which shares no code with either. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "vibroimpact.h"
#include "vi_flow_internal.h"

/* A damped 2-mass chain (masses 1, springs k, dashpots c beside them:
 * proportional, C = (c / k) K), forced by a cos + b sin + f0 on mass 1, its
 * stop far away; dense storage, which has modes. */
static vi_model *chain(double k, double c, double f0)
{
  const double M[4] = {1.0, 0.0, 0.0, 1.0}, E[4] = {2.0, -1.0, -1.0, 1.0};
  const double a[2] = {0.5, 0.0}, b[2] = {0.2, 0.0}, f[2] = {f0, 0.0};
  const double w[2] = {0.0, 1.0};
  double K[4], C[4];
  for (int i = 0; i < 4; i++) K[i] = k * E[i], C[i] = c * E[i];
  vi_model *m = NULL;
  assert_int_equal(vi_model_create(2, &m), VI_OK);
  assert_int_equal(vi_model_set_mass(m, M, 2), VI_OK);
  assert_int_equal(vi_model_set_stiffness(m, K, 2), VI_OK);
  assert_int_equal(vi_model_set_damping(m, C, 2), VI_OK);
  assert_int_equal(vi_model_set_forcing(m, 0.8, a, b, f), VI_OK);
  assert_int_equal(vi_model_set_stop(m, w, 10.0, 0.7), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  return m;
}

/* An independent reference: x'' = f(t) - C x' - K x (M = I) by classical
 * Runge-Kutta from (t0, x0, v0) to t, steps of 0.002 / omega_max (its
 * global error some 1e-10 of the motion over these runs). */
static void rk4(const vi_model *m, double t0, const double *x0, const double *v0, double t,
                double *x, double *v)
{
  const double *K = m->K, *C = m->C, *a = m->a, *b = m->b, *f0 = m->f0, W = m->omega_f;
  double z[4] = {x0[0], x0[1], v0[0], v0[1]}, k[4][4], y[4];
  int steps = (int)ceil((t - t0) * vi_model_omega(m)[1] / 0.002);
  double h = (t - t0) / steps;
  for (int s = 0; s < steps; s++)
    for (int st = 0; st < 4; st++) {
      double c = st == 0 ? 0.0 : st == 3 ? 1.0 : 0.5, tt = t0 + (s + c) * h;
      for (int i = 0; i < 4; i++) y[i] = z[i] + (st ? c * h * k[st - 1][i] : 0.0);
      for (int i = 0; i < 2; i++) {
        k[st][i] = y[2 + i];
        k[st][2 + i] = a[i] * cos(W * tt) + b[i] * sin(W * tt) + f0[i];
        for (int j = 0; j < 2; j++)
          k[st][2 + i] -= C[i + 2 * j] * y[2 + j] + K[i + 2 * j] * y[j];
      }
      if (st == 3)
        for (int i = 0; i < 4; i++)
          z[i] += h / 6.0 * (k[0][i] + 2.0 * k[1][i] + 2.0 * k[2][i] + k[3][i]);
    }
  x[0] = z[0], x[1] = z[1], v[0] = z[2], v[1] = z[3];
}

/* 64 samples from t0 + 0.37 at step h: q, q' and the transition matrices
 * of the run against the closed form at each time, relative to the run's
 * largest |q|, |q'| and to each matrix's largest entry; the run's last
 * state in physical coordinates against Runge-Kutta (rk4). */
static void check_run(vi_model *m, double h)
{
  const int n = 2, k = VI_XSEG_RUN;
  vi_xflow *xf = NULL;
  assert_int_equal(vi_xflow_create(m, &xf), VI_OK);
  assert_true(xf->ok); /* proportional damping: the modal closed form */
  double buf[6], x0[2] = {0.05, -0.02}, v0[2] = {0.1, 0.3};
  vi_xseg s;
  assert_int_equal(vi_xseg_init(&s, xf, m, buf), VI_OK);
  vi_xseg_start(&s, 1.1, x0, v0);
  double Q[VI_XSEG_RUN * 4], C[VI_XSEG_RUN * 8], q[2], qd[2], c[8];
  double t = 1.1 + 0.37;
  vi_xseg_modal_run(&s, t, h, k, Q, Q + n, 2 * (size_t)n, C);
  double scale = 0.0, worst = 0.0, worst_c = 0.0;
  for (int i = 0; i < k * 2 * n; i++) scale = fmax(scale, fabs(Q[i]));
  for (int i = 0; i < k; i++) {
    vi_xseg_modal(&s, t + i * h, q, qd, c);
    for (int j = 0; j < n; j++) {
      worst = fmax(worst, fabs(Q[2 * n * i + j] - q[j]) / scale);
      worst = fmax(worst, fabs(Q[2 * n * i + n + j] - qd[j]) / scale);
    }
    for (int j = 0; j < n; j++) { /* each mode's matrix, norm-wise */
      double nc = 0.0, dc = 0.0;
      for (int e = 4 * j; e < 4 * j + 4; e++) {
        nc = fmax(nc, fabs(c[e]));
        dc = fmax(dc, fabs(C[4 * n * i + e] - c[e]));
      }
      worst_c = fmax(worst_c, dc / nc);
    }
  }
  /* the last sample, x = Psi q, against the reference */
  double xr[2], vr[2], tl = t + (k - 1) * h, worst_rk = 0.0;
  const double *ql = Q + (size_t)(2 * n) * (k - 1), *P = m->Psi;
  rk4(m, 1.1, x0, v0, tl, xr, vr);
  for (int i = 0; i < n; i++) {
    double xi = P[i] * ql[0] + P[i + n] * ql[1], vi = P[i] * ql[2] + P[i + n] * ql[3];
    worst_rk = fmax(worst_rk, fmax(fabs(xi - xr[i]), fabs(vi - vr[i])) / scale);
  }
  print_message("zeta %.3g, %.3g, h = %g: q, q' within %.2e, transitions %.2e, "
                "Runge-Kutta at t = %.4g within %.2e\n", vi_model_zeta(m)[0],
                vi_model_zeta(m)[1], h, worst, worst_c, tl, worst_rk);
  assert_true(worst_rk < 1e-10);
  /* 64 steps of a few ulp each; a transition matrix's entries span 1 to
   * lambda B ~ omega, so its own round-off is relative to lambda */
  double lam = vi_model_omega(m)[1] * vi_model_omega(m)[1];
  assert_true(worst < 1e-13);
  assert_true(worst_c < VI_XSEG_RUN * 2.2e-16 * (1.0 + lam));
  vi_xseg_release(&s);
  vi_xflow_destroy(&xf);
}

/* underdamped (zeta 0.03 and 0.08), steps from the short-time series'
 * range (D, L <= 1) to a sixth of the higher mode's period */
static void test_underdamped(void **state)
{
  (void)state;
  vi_model *m = chain(1.0, 0.1, 0.0);
  const double hs[3] = {1e-3, 0.05, 0.4};
  for (int i = 0; i < 3; i++) check_run(m, hs[i]);
  vi_model_destroy(&m);
}

/* a constant force, and the stiff chain (k = 400, zeta 0.008 and 0.02):
 * more steps per period */
static void test_constant_force(void **state)
{
  (void)state;
  vi_model *m = chain(400.0, 0.5, 0.3);
  check_run(m, 0.01);
  check_run(m, 0.002);
  vi_model_destroy(&m);
}

/* overdamped modes (zeta 2.2 and 5.7): the hyperbolic branch */
static void test_overdamped(void **state)
{
  (void)state;
  vi_model *m = chain(1.0, 7.0, 0.2);
  check_run(m, 0.05);
  check_run(m, 0.5);
  vi_model_destroy(&m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_underdamped),
      cmocka_unit_test(test_constant_force),
      cmocka_unit_test(test_overdamped),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
