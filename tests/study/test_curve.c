/* test_curve.c - special points solved exactly and two-parameter curves
 * (vi_cont_curve.h, src/study/vi_curve.c) on the Fig. 2 chain:
 *  - the period doubling at r = 0.7, from vi_cont_refine and from the
 *    one-parameter continuation's event, at the 24-digit closed-form value
 *    of tests/study/curves_check.py (Omega = 1.613045409627374), with its
 *    multiplier at -1;
 *  - the non-impacting orbit's grazing curve in (x_s, Omega) against
 *    x_s = |w^T (K - W^2 M + i W C)^-1 a|, the 2 x 2 inverse written out
 *    here (Cramer's rule), over the whole range through the resonance;
 *  - the fold curve in (Omega, x_s) ending (v_N = 0, a codimension-two
 *    point) on that same closed-form grazing curve;
 *  - the P(2,2) orbit (two impacts per 2T, born at that period doubling)
 *    and its own period-doubling curve in (Omega, r): at every point the
 *    orbit's equations hold, a multiplier is -1, and the product of the
 *    multipliers is Liouville's r^4 exp(-tr(M^-1 C) 2T) (each impact
 *    scales the phase volume by r, the damping by exp(-tr ...) per time).
 *  - the lightly damped chain (c = 0.02, r = 0.8): its P(1,1) period-
 *    doubling curve in (Omega, x_s) passes two 1:2 points (a second
 *    multiplier through -1), located at codim2_check.py's 24-digit
 *    closed-form points; there the orbit has two multipliers at -1 and
 *    their product is Liouville's r^2 exp(-tr(M^-1 C) T); the
 *    Neimark-Sacker curve born at the upper one ends on it, at the same
 *    point to round-off;
 *  - the P(2,2) grazing point (largest gap over both flights at the stop)
 *    at its closed-form Omega, and its curve in (Omega, r);
 *  - a cusp of a P(2,2) fold curve (Fig. 2's chain, c = 0.05), located
 *    at cusp_check.py's 60-digit closed-form point;
 *  - an oscillator between two stops: the grazing curve of its P(1,1)
 *    orbit (impacting the upper stop) in (lower clearance, Omega) is
 *    where the flight touches the lower stop, against the closed-form
 *    flight's lowest point.
 * The independent mpmath checks of every curve are curves_check.py's,
 * codim2_check.py's and cusp_check.py's. */
#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vi_testutil.h"

#define OMEGA_PD 1.613045409627374 /* curves_check.py, 24 digits, 16 kept */

/* A P(1,1) seed of Fig. 2 at Omega = 0.9 (Newton refines it). */
static const double X0[2] = {-0.0563, 0.1}, V0[2] = {0.11, 0.79}, T0 = 0.68;

/* |x_2| of the free harmonic response of the Fig. 2 chain at W. */
static double free_amp(double W)
{
  /* K = [2 -1; -1 1], C = 0.1 K, M = I, a = (0.5, 0): Z = K - W^2 + i W C */
  double complex z11 = 2 - W * W + 0.2 * I * W, z12 = -1 - 0.1 * I * W,
                 z22 = 1 - W * W + 0.1 * I * W;
  double complex det = z11 * z22 - z12 * z12;
  return cabs(-z12 * 0.5 / det); /* (Z^-1)_21 a_1 */
}

static void test_pd_refined(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  double p = 1.61, t = T0, x[2], v[2], re[4], im[4];
  memcpy(x, X0, sizeof x);
  memcpy(v, V0, sizeof v);
  /* a seed at 1.61 (|mu + 1| 0.04): the orbit there, then the point */
  assert_int_equal(vi_orbit_pnm_solve(m, 1, 1, &t, x, v, 2, 0, NULL), VI_OK);
  for (int k = 1; k <= 6; k++) { /* up the branch, 1.0 to 1.5 */
    assert_int_equal(vi_model_set_param(m, "forcing.omega", 0.9 + 0.1 * k), VI_OK);
    assert_int_equal(vi_orbit_pnm_solve(m, 1, 1, &t, x, v, 2, 0, NULL), VI_OK);
  }
  assert_int_equal(vi_model_set_param(m, "forcing.omega", 1.61), VI_OK);
  assert_int_equal(vi_orbit_pnm_solve(m, 1, 1, &t, x, v, 2, 0, NULL), VI_OK);
  assert_int_equal(vi_cont_refine(m, "forcing.omega", 1, VI_CONT_CURVE_PD, &p, &t, x, v), VI_OK);
  printf("  refined PD at Omega = %.15f (reference %.15f)\n", p, OMEGA_PD);
  assert_true(fabs(p - OMEGA_PD) < 1e-11);
  assert_int_equal(vi_model_set_param(m, "forcing.omega", p), VI_OK);
  assert_int_equal(vi_orbit_pnm_multipliers(m, 1, 1, &t, x, v, 2, re, im), VI_OK);
  double d = HUGE_VAL;
  for (int i = 0; i < 4; i++) d = fmin(d, hypot(re[i] + 1, im[i]));
  printf("  |mu + 1| = %.2e\n", d);
  assert_true(d < 1e-10);
  /* the natural continuation's event, refined the same way */
  vi_cont *c = NULL;
  assert_int_equal(vi_model_set_param(m, "forcing.omega", 0.9), VI_OK);
  assert_int_equal(vi_cont_create(m, "forcing.omega", 1, VI_CONT_NATURAL, &c), VI_OK);
  assert_int_equal(vi_cont_set_range(c, 1.8, 50), VI_OK);
  assert_int_equal(vi_cont_set_orbit(c, T0, X0, V0), VI_OK);
  int found = 0;
  while (!vi_cont_done(c) && !found) {
    if (vi_cont_iterate(c) < 0) break;
    for (int i = 0; i < vi_cont_num_events(c); i++) {
      int type;
      double pe, er, ei;
      vi_cont_event(c, i, &type, &pe, NULL, &er, &ei, NULL);
      if (type != VI_CONT_PERIOD_DOUBLING) continue;
      printf("  continuation's PD at %.15f, multiplier %.15f%+.1ei\n", pe, er, ei);
      assert_true(fabs(pe - OMEGA_PD) < 1e-11);
      assert_true(fabs(er + 1) < 1e-10);
      found = 1;
    }
  }
  assert_true(found);
  vi_cont_destroy(&c);
  vi_model_destroy(&m);
}

/* Fig. 2 beside 29 oscillators it does not touch (unforced, off the stop,
 * at rest): a 31-dof model whose P(1,1) orbit and period doubling are Fig.
 * 2's, found through bordered systems of 65 unknowns (the curves were
 * limited to 64).  The point located by following the orbit in Omega from
 * 1.6 is the closed-form one, OMEGA_PD; the curve goes on in r. */
static void test_large_model_pd(void **state)
{
  (void)state;
  enum { N = 31 };
  static double M[N * N], C[N * N], K[N * N];
  double a[N] = {0.5}, w[N] = {0, 1}, f0[N] = {0};
  memset(M, 0, sizeof M);
  memset(C, 0, sizeof C);
  memset(K, 0, sizeof K);
  const double E[4] = {2, -1, -1, 1};
  for (int i = 0; i < N; i++) M[i + i * N] = 1;
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2; j++) {
      K[i + j * N] = E[i + 2 * j];
      C[i + j * N] = 0.1 * E[i + 2 * j];
    }
  for (int i = 2; i < N; i++) { /* omega_i from 2.3 to 9.3, 2 % damping */
    K[i + i * N] = pow(2.3 + 0.25 * (i - 2), 2);
    C[i + i * N] = 0.04 * (2.3 + 0.25 * (i - 2));
  }
  vi_model *m = vi_test_model(N, M, C, K, 1.6, a, f0, w, 0.1, 0.7);
  double t = 0, x[N], v[N], p;
  int found = 0;
  assert_int_equal(vi_orbit_p1_scan(m, 1, 720, &t, x, v, N, 1, &found), VI_OK);
  assert_int_equal(found, 1);
  vi_cont_curve *c = NULL;
  assert_int_equal(vi_cont_curve_create(m, VI_CONT_CURVE_PD, 1, 1, "forcing.omega", "stop.r",
                                        &c), VI_OK);
  assert_int_equal(vi_cont_curve_set_orbit(c, t, x, v), VI_OK);
  assert_int_equal(vi_cont_curve_locate(c, 1.62, 2, &p), VI_OK);
  printf("  31 dofs: PD at Omega = %.15f (Fig. 2's closed form %.15f)\n", p, OMEGA_PD);
  assert_true(fabs(p - OMEGA_PD) < 1e-10);
  assert_int_equal(vi_cont_curve_set_range(c, 0.695, 0.705, 2), VI_OK);
  int n = 0;
  while (!vi_cont_curve_done(c) && n < 100) {
    assert_int_equal(vi_cont_curve_iterate(c), VI_OK);
    n++;
  }
  assert_true(n >= 2);
  vi_cont_curve_destroy(&c);
  vi_model_destroy(&m);
}

/* The 1:2 points of the chain with c = 0.02, r = 0.8 in (Omega, x_s):
 * codim2_check.py's closed form (24 digits, 16 kept). */
static const double R12[2][2] = {{0.4600125668111045, 1.123731014267325},
                                 {0.4837169950085476, 1.233367557722454}};

/* The admissible P(1,1) orbit of the chain (c = 0.02, r = 0.8) at Omega
 * and x_s with the smallest multipliers (as `curves` picks it). */
static vi_model *light_chain(double W, double xs, double *t, double *x, double *v)
{
  const double a[2] = {0.5, 0.0};
  vi_model *m = vi_test_chain(2, 1.0, 1.0, 0.02, xs, 0.8, W, a);
  double tt[4], xx[8], vv[8], re[4], im[4], best = HUGE_VAL, g;
  int found = 0, ok;
  assert_int_equal(vi_orbit_p1_scan(m, 1, 720, tt, xx, vv, 2, 4, &found), VI_OK);
  for (int k = 0; k < found && k < 4; k++) {
    const double *xk = xx + (size_t)2 * k, *vk = vv + (size_t)2 * k;
    assert_int_equal(vi_orbit_pnm_admissible(m, 1, 1, tt + k, xk, vk, 2, &g, &ok), VI_OK);
    assert_int_equal(vi_orbit_pnm_multipliers(m, 1, 1, tt + k, xk, vk, 2, re, im), VI_OK);
    double rho = 0;
    for (int i = 0; i < 4; i++) rho = fmax(rho, hypot(re[i], im[i]));
    if (ok && rho < best) {
      best = rho;
      *t = tt[k];
      memcpy(x, xk, sizeof(double) * 2);
      memcpy(v, vk, sizeof(double) * 2);
    }
  }
  assert_true(best < HUGE_VAL);
  return m;
}

static void test_resonance_12(void **state)
{
  (void)state;
  double t = 0, x[2] = {0}, v[2] = {0}, p, p2, q, q2, re[4], im[4], lt = 0, lx[2] = {0};
  double lv[2] = {0};
  int type, loc, n12 = 0;
  vi_model *m = light_chain(0.5, 1.233, &t, x, v);
  vi_cont_curve *c = NULL;
  assert_int_equal(vi_cont_curve_create(m, VI_CONT_CURVE_PD, 1, 1, "forcing.omega", "stop.xs",
                                        &c), VI_OK);
  assert_int_equal(vi_cont_curve_set_orbit(c, t, x, v), VI_OK);
  assert_int_equal(vi_cont_curve_locate(c, 0.3, 200, &p), VI_OK);
  assert_int_equal(vi_cont_curve_set_range(c, 1.1, 1.4, 200), VI_OK);
  while (!vi_cont_curve_done(c)) {
    assert_int_equal(vi_cont_curve_iterate(c), VI_OK);
    for (int i = 0; i < vi_cont_curve_num_special(c); i++) {
      assert_int_equal(vi_cont_curve_special(c, i, &type, &q, &q2, &loc), VI_OK);
      if (type != VI_CONT_SP_RESONANCE_12) continue;
      assert_true(n12 < 2 && loc);
      printf("  1:2 at Omega = %.16g, x_s = %.16g (closed form %.16g, %.16g)\n", q, q2,
             R12[n12][0], R12[n12][1]);
      assert_true(fabs(q - R12[n12][0]) < 1e-12 && fabs(q2 - R12[n12][1]) < 1e-12);
      /* the orbit there, from the last point before it */
      vi_model *mq = NULL;
      assert_int_equal(vi_model_copy(m, &mq), VI_OK);
      assert_int_equal(vi_model_set_param(mq, "forcing.omega", q), VI_OK);
      assert_int_equal(vi_model_set_param(mq, "stop.xs", q2), VI_OK);
      assert_int_equal(vi_orbit_pnm_solve(mq, 1, 1, &lt, lx, lv, 2, 0, NULL), VI_OK);
      assert_int_equal(vi_orbit_pnm_multipliers(mq, 1, 1, &lt, lx, lv, 2, re, im), VI_OK);
      double d[4];
      double complex pr = 1;
      for (int k = 0; k < 4; k++) {
        d[k] = hypot(re[k] + 1, im[k]);
        pr *= re[k] + I * im[k];
      }
      int near = 0;
      for (int k = 0; k < 4; k++) near += d[k] < 1e-6;
      double liou = 0.8 * 0.8 * exp(-0.06 * 2 * M_PI / q); /* tr(M^-1 C) = 0.02 (2 + 1) */
      printf("    multipliers' distances to -1: %.1e %.1e %.1e %.1e; product / Liouville - 1 = "
             "%.1e\n", d[0], d[1], d[2], d[3], cabs(pr - liou) / liou);
      assert_int_equal(near, 2);
      assert_true(cabs(pr - liou) < 1e-10 * liou);
      vi_model_destroy(&mq);
      n12++;
    }
    assert_int_equal(vi_cont_curve_point(c, &p, &p2, &lt, lx, lv, NULL), VI_OK);
  }
  assert_int_equal(n12, 2);
  vi_cont_curve_destroy(&c);
  vi_model_destroy(&m);
  /* the NS curve from x_s = 1.15 ends on the upper one: the pair turns real at -1 */
  m = light_chain(0.5, 1.15, &t, x, v);
  assert_int_equal(vi_cont_curve_create(m, VI_CONT_CURVE_NS, 1, 1, "forcing.omega", "stop.xs",
                                        &c), VI_OK);
  assert_int_equal(vi_cont_curve_set_orbit(c, t, x, v), VI_OK);
  assert_int_equal(vi_cont_curve_locate(c, 0.56, 200, &p), VI_OK);
  assert_int_equal(vi_cont_curve_set_range(c, 1.0, 1.4, 200), VI_OK);
  n12 = 0;
  while (!vi_cont_curve_done(c)) {
    assert_int_equal(vi_cont_curve_iterate(c), VI_OK);
    for (int i = 0; i < vi_cont_curve_num_special(c); i++) {
      assert_int_equal(vi_cont_curve_special(c, i, &type, &q, &q2, &loc), VI_OK);
      if (type != VI_CONT_SP_RESONANCE_12) continue;
      printf("  the ns curve ends at Omega = %.16g, x_s = %.16g\n", q, q2);
      assert_true(loc && fabs(q - R12[1][0]) < 1e-12 && fabs(q2 - R12[1][1]) < 1e-12);
      n12++;
    }
  }
  assert_int_equal(vi_cont_curve_done(c), VI_CONT_CURVE_RESONANCE);
  assert_int_equal(n12, 1);
  vi_cont_curve_destroy(&c);
  vi_model_destroy(&m);
}

/* The P(2,1) orbit of the same chain at Omega = 0.5, x_s = 1.3, followed
 * down in Omega, grazes the stop near 0.4976 before a pair of its
 * multipliers reaches the unit circle (0.4695): that Neimark-Sacker point
 * is of an orbit through the stop (its flight 0.38 above it by the closed
 * form), so locate stops at the grazing instead. */
static void test_locate_stops_at_grazing(void **state)
{
  (void)state;
  const double a[2] = {0.5, 0.0};
  vi_model *m = vi_test_chain(2, 1.0, 1.0, 0.02, 1.3, 0.8, 0.5, a);
  double tt[4], xx[8], vv[8], g, p;
  int found = 0, ok = 0, k = 0;
  assert_int_equal(vi_orbit_p1_scan(m, 2, 720, tt, xx, vv, 2, 4, &found), VI_OK);
  for (; k < found && k < 4 && !ok; k++)
    assert_int_equal(vi_orbit_pnm_admissible(m, 2, 1, tt + k, xx + (size_t)2 * k,
                                             vv + (size_t)2 * k, 2, &g, &ok), VI_OK);
  assert_true(ok);
  k--;
  vi_cont_curve *c = NULL;
  assert_int_equal(vi_cont_curve_create(m, VI_CONT_CURVE_NS, 2, 1, "forcing.omega", "stop.xs",
                                        &c), VI_OK);
  assert_int_equal(vi_cont_curve_set_orbit(c, tt[k], xx + (size_t)2 * k, vv + (size_t)2 * k),
                   VI_OK);
  assert_int_equal(vi_cont_curve_locate(c, 0.44, 200, &p), VI_STOPPED);
  printf("  %s\n", vi_cont_curve_errmsg(c));
  assert_non_null(strstr(vi_cont_curve_errmsg(c), "grazes"));
  vi_cont_curve_destroy(&c);
  vi_model_destroy(&m);
}

static void test_p10_grazing_curve(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  vi_cont_curve *c = NULL;
  double p, p2, last = 0, worst = 0, peak = 0;
  int n = 0;
  assert_int_equal(vi_cont_curve_create(m, VI_CONT_CURVE_GRAZING, 1, 0, "stop.xs",
                                        "forcing.omega", &c), VI_OK);
  assert_int_equal(vi_cont_curve_locate(c, 5, 100, &p), VI_OK);
  assert_true(fabs(p - free_amp(0.9)) < 1e-12 * p);
  assert_int_equal(vi_cont_curve_set_range(c, 0.5, 1.8, 200), VI_OK);
  while (!vi_cont_curve_done(c)) {
    assert_int_equal(vi_cont_curve_iterate(c), VI_OK);
    assert_int_equal(vi_cont_curve_point(c, &p, &p2, NULL, NULL, NULL, NULL), VI_OK);
    if (n == 0) assert_true(p2 == 0.5);
    else assert_true(p2 > last); /* ordered along the curve */
    last = p2;
    worst = fmax(worst, fabs(p - free_amp(p2)) / free_amp(p2));
    peak = fmax(peak, p);
    n++;
  }
  printf("  %d points, Omega to %.15g, peak x_s %.6g, worst relative error %.2e\n", n, last,
         peak, worst);
  assert_int_equal(vi_cont_curve_done(c), VI_CONT_CURVE_END);
  assert_true(last == 1.8);
  assert_true(worst < 1e-9);
  assert_true(peak > free_amp(0.618) * (1 - 1e-3)); /* through the resonance */
  vi_cont_curve_destroy(&c);
  vi_model_destroy(&m);
}

static void test_fold_curve_end(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  vi_cont_curve *c = NULL;
  double t, x[2], v[2], p, p2;
  int found;
  assert_int_equal(vi_model_set_param(m, "stop.xs", 0.5), VI_OK);
  assert_int_equal(vi_orbit_p1_scan(m, 1, 720, &t, x, v, 2, 1, &found), VI_OK);
  assert_int_equal(found, 1);
  assert_int_equal(vi_cont_curve_create(m, VI_CONT_CURVE_FOLD, 1, 1, "forcing.omega",
                                        "stop.xs", &c), VI_OK);
  assert_int_equal(vi_cont_curve_set_orbit(c, t, x, v), VI_OK);
  assert_int_equal(vi_cont_curve_locate(c, 2.5, 200, &p), VI_OK);
  printf("  fold of the branch from Omega = 0.9 at x_s = 0.5: Omega = %.12f\n", p);
  assert_true(p > 1.1 && p < 1.12);
  assert_int_equal(vi_cont_curve_set_range(c, 0.0, 1.5, 100), VI_OK);
  assert_int_equal(vi_cont_curve_iterate(c), VI_OK);
  int type, loc;
  assert_true(vi_cont_curve_num_special(c) >= 1);
  assert_int_equal(vi_cont_curve_special(c, 0, &type, &p, &p2, &loc), VI_OK);
  printf("  its end: type %d at Omega = %.12f, x_s = %.12f (closed-form grazing %.12f)\n", type,
         p, p2, free_amp(p));
  assert_int_equal(type, VI_CONT_SP_ADMISSIBILITY);
  assert_true(loc);
  assert_true(fabs(p2 - free_amp(p)) < 1e-9 * p2);
  vi_cont_curve_destroy(&c);
  vi_model_destroy(&m);
}

/* The stable P(2,2) orbit of Fig. 2 at Omega = 1.65 from the census (its
 * transients), its impacts in ascending time. */
static void p22_orbit(const vi_model *m, double *t, double *x, double *v)
{
  vi_census *cs = NULL;
  double tt[2], xx[4], vv[4];
  int stable = 0, i = 0;
  assert_int_equal(vi_census_create(m, 2, 2, &cs), VI_OK);
  assert_int_equal(vi_census_run(cs), VI_OK);
  for (; i < vi_census_count(cs) && !stable; i++)
    assert_int_equal(vi_census_stability(cs, i, NULL, NULL, &stable, NULL, NULL), VI_OK);
  assert_true(stable);
  assert_int_equal(vi_census_orbit(cs, i - 1, tt, xx, vv, 2, NULL, NULL), VI_OK);
  int j0 = tt[1] < tt[0];
  for (int j = 0; j < 2; j++) {
    int k = (j0 + j) % 2;
    t[j] = tt[k];
    memcpy(x + (size_t)2 * j, xx + (size_t)2 * k, sizeof(double) * 2);
    memcpy(v + (size_t)2 * j, vv + (size_t)2 * k, sizeof(double) * 2);
  }
  vi_census_destroy(&cs);
}

static void test_p22_pd_curve(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2(), *q = NULL;
  vi_cont_curve *c = NULL;
  double t[2], x[4], v[4], p, p2, re[4], im[4], F[10], worst = 0, wdet = 0, wres = 0;
  double rmin = HUGE_VAL, rmax = -HUGE_VAL;
  int n = 0;
  assert_int_equal(vi_model_set_param(m, "forcing.omega", 1.65), VI_OK);
  p22_orbit(m, t, x, v);
  assert_int_equal(vi_cont_curve_create(m, VI_CONT_CURVE_PD, 2, 2, "forcing.omega", "stop.r",
                                        &c), VI_OK);
  assert_int_equal(vi_cont_curve_set_orbit(c, t[0], x, v), VI_ERR_ARG); /* one impact only */
  assert_int_equal(vi_cont_curve_set_impacts(c, t, x, v, 2), VI_OK);
  assert_int_equal(vi_cont_curve_locate(c, 1.8, 200, &p), VI_OK);
  printf("  P(2,2) period doubling at r = 0.7: Omega = %.12f\n", p);
  assert_true(p > 1.66 && p < 1.70); /* between the sweep's P(2,2) and P(4,4) cells */
  assert_int_equal(vi_cont_curve_set_range(c, 0.5, 0.9, 100), VI_OK);
  assert_int_equal(vi_cont_curve_start(c), 0); /* not yet followed */
  assert_int_equal(vi_model_copy(m, &q), VI_OK);
  while (!vi_cont_curve_done(c)) {
    assert_int_equal(vi_cont_curve_iterate(c), VI_OK);
    assert_int_equal(vi_cont_curve_point(c, &p, &p2, NULL, NULL, NULL, NULL), VI_OK);
    assert_int_equal(vi_cont_curve_impacts(c, t, x, v, 2), VI_OK);
    assert_int_equal(vi_model_set_param(q, "forcing.omega", p), VI_OK);
    assert_int_equal(vi_model_set_param(q, "stop.r", p2), VI_OK);
    assert_int_equal(vi_orbit_pnm_residual(q, 2, 2, t, x, v, 2, F, NULL), VI_OK);
    for (int i = 0; i < 10; i++) wres = fmax(wres, fabs(F[i]));
    assert_int_equal(vi_orbit_pnm_multipliers(q, 2, 2, t, x, v, 2, re, im), VI_OK);
    double d = HUGE_VAL;
    double complex pr = 1;
    for (int i = 0; i < 4; i++) {
      d = fmin(d, hypot(re[i] + 1, im[i]));
      pr *= re[i] + I * im[i];
    }
    double liou = pow(p2, 4) * exp(-0.3 * 2 * (2 * M_PI / p)); /* tr(M^-1 C) = 0.1 (2 + 1) */
    worst = fmax(worst, d);
    wdet = fmax(wdet, cabs(pr - liou) / liou);
    rmin = fmin(rmin, p2);
    rmax = fmax(rmax, p2);
    assert_true(t[0] < t[1] && t[1] < t[0] + 2 * (2 * M_PI / p));
    assert_true(fabs(x[1] - 0.1) < 1e-12 && fabs(x[3] - 0.1) < 1e-12); /* on the stop */
    assert_true(v[1] > 0 && v[3] > 0);                                 /* approaching */
    n++;
  }
  printf("  %d points, r %.3g..%.3g: worst |mu + 1| %.2e, residual %.2e, relative error of the "
         "multipliers' product %.2e\n", n, rmin, rmax, worst, wres, wdet);
  /* both ends at the range's bounds, the first point at one of them */
  assert_int_equal(vi_cont_curve_start(c), VI_CONT_CURVE_END);
  assert_int_equal(vi_cont_curve_done(c), VI_CONT_CURVE_END);
  assert_true(rmin == 0.5 && rmax == 0.9 && n > 50);
  assert_true(worst < 1e-9);
  assert_true(wres < 1e-11);
  assert_true(wdet < 1e-10);
  vi_model_destroy(&q);
  vi_cont_curve_destroy(&c);
  vi_model_destroy(&m);
}

/* The fold of the P(2,2) branch at r = 0.7, from the closed-form P(2,2)
 * orbit of curves_check.py (p22_special(1.7294421, 0.7, 0.1, -1) at
 * mp.dps = 30): mp.findroot in (Omega, t_0, t_1) of w.x_0 = w.x_1 = x_s
 * and det(M - I) = 0, M the closed-form monodromy
 * e^{A(t_0 + 2T - t_1)} S_1 e^{A(t_1 - t_0)} S_0, seeded by p22_seeds
 * (a regular root: 1.7294421019139723719). */
#define OMEGA_FOLD22 1.72944210191397237

/* The fold of the P(2,2) orbit followed up from Omega = 1.65: the branch's
 * impact phases move about 40 times faster than Omega there, and the
 * search once ran out of points at 1.7255 (from above it was found);
 * now found for any step count, at the closed form's Omega, with a
 * multiplier at +1 (at a fold the two merging orbits' multipliers are
 * 1 +- c sqrt(p - p*): the point rounded to a double gives ~1e-8). */
static void test_p22_fold_upward(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2(), *q = NULL;
  double t0[2], x0[4], v0[4];
  assert_int_equal(vi_model_set_param(m, "forcing.omega", 1.65), VI_OK);
  p22_orbit(m, t0, x0, v0);
  static const int steps[] = {20, 200, 1000};
  for (int s = 0; s < 3; s++) {
    vi_cont_curve *c = NULL;
    double t[2], x[4], v[4], p, re[4], im[4], d = HUGE_VAL;
    assert_int_equal(vi_cont_curve_create(m, VI_CONT_CURVE_FOLD, 2, 2, "forcing.omega", "stop.r",
                                          &c), VI_OK);
    assert_int_equal(vi_cont_curve_set_impacts(c, t0, x0, v0, 2), VI_OK);
    assert_int_equal(vi_cont_curve_locate(c, 1.8, steps[s], &p), VI_OK);
    assert_int_equal(vi_cont_curve_impacts(c, t, x, v, 2), VI_OK);
    assert_int_equal(vi_model_copy(m, &q), VI_OK);
    assert_int_equal(vi_model_set_param(q, "forcing.omega", p), VI_OK);
    assert_int_equal(vi_orbit_pnm_multipliers(q, 2, 2, t, x, v, 2, re, im), VI_OK);
    for (int i = 0; i < 4; i++) d = fmin(d, hypot(re[i] - 1, im[i]));
    printf("  P(2,2) fold from 1.65 up, %d steps: Omega = %.17g (closed form %.17g), "
           "|mu - 1| %.2e\n", steps[s], p, OMEGA_FOLD22, d);
    assert_true(fabs(p - OMEGA_FOLD22) < 1e-11);
    assert_true(d < 1e-6);
    vi_model_destroy(&q);
    vi_cont_curve_destroy(&c);
  }
  vi_model_destroy(&m);
}

/* The period doubling of the P(2,2) branch at r = 0.7 from the same closed
 * form, det(M + I) = 0 (p22_special(1.6818211, 0.7, 0.1, 1)):
 * 1.6818211302390429108. */
#define OMEGA_PD22 1.68182113023904291

/* vi_cont_refine_pnm: P(2,2) points from orbits near them (the branch
 * followed from 1.65 by vi_orbit_pnm_solve), at the closed form's Omega,
 * the library's multiplier at -1 or +1 there; grazing refused (m > 1). */
static void test_refine_pnm(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  double t[2], x[4], v[4], tq[2], xq[4], vq[4], re[4], im[4];
  assert_int_equal(vi_model_set_param(m, "forcing.omega", 1.65), VI_OK);
  p22_orbit(m, t, x, v);
  static const double guess[2] = {1.675, 1.725}, want[2] = {OMEGA_PD22, OMEGA_FOLD22};
  static const int kind[2] = {VI_CONT_CURVE_PD, VI_CONT_CURVE_FOLD};
  double W = 1.65;
  for (int k = 0; k < 2; k++) {
    while (W < guess[k] - 1e-12) { /* the branch up to the guess */
      W += 0.0025;
      assert_int_equal(vi_model_set_param(m, "forcing.omega", W), VI_OK);
      assert_int_equal(vi_orbit_pnm_solve(m, 2, 2, t, x, v, 2, 0, NULL), VI_OK);
    }
    double p = W, d = HUGE_VAL, target = k ? 1 : -1;
    memcpy(tq, t, sizeof t);
    memcpy(xq, x, sizeof x);
    memcpy(vq, v, sizeof v);
    assert_int_equal(vi_cont_refine_pnm(m, "forcing.omega", 2, 2, kind[k], &p, tq, xq, vq, 2),
                     VI_OK);
    vi_model *q = NULL;
    assert_int_equal(vi_model_copy(m, &q), VI_OK);
    assert_int_equal(vi_model_set_param(q, "forcing.omega", p), VI_OK);
    assert_int_equal(vi_orbit_pnm_multipliers(q, 2, 2, tq, xq, vq, 2, re, im), VI_OK);
    for (int i = 0; i < 4; i++) d = fmin(d, hypot(re[i] - target, im[i]));
    printf("  P(2,2) %s refined from %.4g: Omega = %.17g (closed form %.17g), |mu %+g| %.2e\n",
           k ? "fold" : "pd", W, p, want[k], -target, d);
    assert_true(fabs(p - want[k]) < 1e-11);
    assert_true(d < 1e-9);
    assert_true(tq[0] < tq[1] && fabs(xq[1] - 0.1) < 1e-12 && fabs(xq[3] - 0.1) < 1e-12);
    vi_model_destroy(&q);
  }
  double p = W;
  assert_int_equal(vi_cont_refine_pnm(m, "forcing.omega", 2, 2, VI_CONT_CURVE_PD, &p, t, x, v, 1),
                   VI_ERR_ARG); /* ld < n_coords */
  vi_model_destroy(&m);
}

/* The grazing of the P(2,2) orbit at r = 0.7, x_s = 0.1 (its largest gap
 * over both flights reaching the stop), from the closed-form orbit of
 * curves_check.py: p22_grazing(1.6963, 0.7, 0.1) at mp.dps = 30,
 * mp.findroot in (Omega, t_0, t_1, s) of w.x_0 = w.x_1 = x_s and, at the
 * time s after the impact whose flight has the largest sampled gap,
 * w.x = x_s, w.v = 0 (1.69630397658454887354). */
#define OMEGA_GRAZE22 1.69630397658454887

/* The P(2,2) grazing point, refined and located, and its curve in
 * (Omega, r) from r = 0.6: at every point the orbit's equations hold, both
 * impacts are on the stop and approach it, and the largest gap between
 * impacts (vi_orbit_pnm_admissible, sampled independently of the curve's
 * tracked Newton) is 0; the curve ends where an impact's v_N reaches 0
 * (r = 0.734, a codimension-two point; curves_check.py's check 11 tests
 * the gap and that end against the closed form). */
static void test_p22_grazing_curve(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2(), *q = NULL;
  vi_cont_curve *c = NULL;
  double t[2], x[4], v[4], tq[2], xq[4], vq[4], p, p2, F[10], wres = 0, wgap = 0;
  double rmin = HUGE_VAL, rmax = -HUGE_VAL;
  int n = 0, ok;
  assert_int_equal(vi_model_set_param(m, "forcing.omega", 1.65), VI_OK);
  p22_orbit(m, t, x, v);
  /* located from 1.65 and followed */
  assert_int_equal(vi_cont_curve_create(m, VI_CONT_CURVE_GRAZING, 2, 2, "forcing.omega", "stop.r",
                                        &c), VI_OK);
  assert_int_equal(vi_cont_curve_set_impacts(c, t, x, v, 2), VI_OK);
  assert_int_equal(vi_cont_curve_locate(c, 1.8, 200, &p), VI_OK);
  printf("  P(2,2) grazing at r = 0.7: Omega = %.17g (closed form %.17g)\n", p, OMEGA_GRAZE22);
  assert_true(fabs(p - OMEGA_GRAZE22) < 1e-11);
  /* refined from that orbit moved to Omega - 0.001 (the branch that
   * grazes: the one walked up from 1.65 by vi_orbit_pnm_solve has no
   * interior maximum of the gap there) */
  assert_int_equal(vi_cont_curve_impacts(c, tq, xq, vq, 2), VI_OK);
  double pr = p - 1e-3;
  assert_int_equal(vi_model_set_param(m, "forcing.omega", pr), VI_OK);
  assert_int_equal(vi_orbit_pnm_solve(m, 2, 2, tq, xq, vq, 2, 0, NULL), VI_OK);
  assert_int_equal(vi_cont_refine_pnm(m, "forcing.omega", 2, 2, VI_CONT_CURVE_GRAZING, &pr, tq, xq,
                                      vq, 2), VI_OK);
  printf("  refined from Omega - 0.001: %.17g\n", pr);
  assert_true(fabs(pr - OMEGA_GRAZE22) < 1e-11);
  assert_int_equal(vi_cont_curve_set_range(c, 0.6, 0.8, 50), VI_OK);
  assert_int_equal(vi_model_copy(m, &q), VI_OK);
  while (!vi_cont_curve_done(c)) {
    assert_int_equal(vi_cont_curve_iterate(c), VI_OK);
    assert_int_equal(vi_cont_curve_point(c, &p, &p2, NULL, NULL, NULL, NULL), VI_OK);
    assert_int_equal(vi_cont_curve_impacts(c, t, x, v, 2), VI_OK);
    assert_int_equal(vi_model_set_param(q, "forcing.omega", p), VI_OK);
    assert_int_equal(vi_model_set_param(q, "stop.r", p2), VI_OK);
    assert_int_equal(vi_orbit_pnm_residual(q, 2, 2, t, x, v, 2, F, NULL), VI_OK);
    for (int i = 0; i < 10; i++) wres = fmax(wres, fabs(F[i]));
    double g;
    assert_int_equal(vi_orbit_pnm_admissible(q, 2, 2, t, x, v, 2, &g, &ok), VI_OK);
    wgap = fmax(wgap, fabs(g));
    rmin = fmin(rmin, p2);
    rmax = fmax(rmax, p2);
    assert_true(fabs(x[1] - 0.1) < 1e-12 && fabs(x[3] - 0.1) < 1e-12); /* on the stop */
    assert_true(v[1] > -1e-9 && v[3] > -1e-9);                         /* approaching */
    n++;
  }
  printf("  %d points, r %.3g..%.3g: residual %.2e, worst |largest gap| %.2e\n", n, rmin, rmax,
         wres, wgap);
  /* from the range's bound r = 0.6 to where the orbit stops being admissible */
  assert_int_equal(vi_cont_curve_start(c), VI_CONT_CURVE_END);
  assert_int_equal(vi_cont_curve_done(c), VI_CONT_CURVE_ENDS);
  assert_true(rmin == 0.6 && rmax > 0.73 && rmax < 0.74 && n > 20);
  assert_true(wres < 1e-11);
  assert_true(wgap < 1e-9 * 0.1); /* the sampled maximum, refined, against 0: 1e-8 of x_s */
  vi_model_destroy(&q);
  vi_cont_curve_destroy(&c);
  vi_model_destroy(&m);
}

/* x, x' of the single-degree-of-freedom oscillator x'' + c x' + x =
 * cos(W t), at time tau after (t0, x0, v0): particular solution plus the
 * damped free motion, written out. */
static void sdof_flow(double c, double W, double t0, double x0, double v0, double tau,
                      double *x, double *v)
{
  double complex P = 1 / (1 - W * W + I * c * W); /* x_p = Re P e^{iWt} */
  double complex e0 = cexp(I * W * t0), e1 = cexp(I * W * (t0 + tau));
  double h = x0 - creal(P * e0), hp = v0 - creal(I * W * P * e0);
  double wd = sqrt(1 - c * c / 4), d = exp(-c * tau / 2);
  double cs = cos(wd * tau), sn = sin(wd * tau), B = (hp + c / 2 * h) / wd;
  *x = creal(P * e1) + d * (h * cs + B * sn);
  *v = creal(I * W * P * e1) + d * ((-c / 2) * (h * cs + B * sn) + wd * (-h * sn + B * cs));
}

/* The lowest x of the P(1,1) flight from the impact (t0, x_s, v_-) at
 * the upper stop (restitution r): the smallest of 4096 samples, refined by
 * Newton on x' = 0 with x'' from the equation of motion. */
static double sdof_lowest(double c, double W, double r, double t0, double xs, double vm)
{
  double T = 2 * M_PI / W, best = HUGE_VAL, tb = 0, x, v;
  for (int k = 1; k < 4096; k++) {
    sdof_flow(c, W, t0, xs, -r * vm, k * T / 4096, &x, &v);
    if (x < best) {
      best = x;
      tb = k * T / 4096;
    }
  }
  for (int it = 0; it < 20; it++) {
    sdof_flow(c, W, t0, xs, -r * vm, tb, &x, &v);
    tb -= v / (cos(W * (t0 + tb)) - c * v - x);
  }
  sdof_flow(c, W, t0, xs, -r * vm, tb, &x, &v);
  return x;
}

/* A two-sided clearance: an oscillator between stops x <= 0.5 and
 * -x <= d.  Its P(1,1) orbit impacts the upper stop only; its grazing
 * curve in (d, Omega) is where the flight touches the lower stop, d = -min
 * x over the flight, whatever the clearance of the upper one: the curve
 * follows the other stop's gap, not the impacted one's. */
static vi_model *two_sided(double c, double r, double xs, double d)
{
  const double one = 1.0, up = 1.0, down = -1.0, zero = 0.0;
  vi_model *m = NULL;
  assert_int_equal(vi_model_create(1, &m), VI_OK);
  assert_int_equal(vi_model_set_mass(m, &one, 1), VI_OK);
  assert_int_equal(vi_model_set_damping(m, &c, 1), VI_OK);
  assert_int_equal(vi_model_set_stiffness(m, &one, 1), VI_OK);
  assert_int_equal(vi_model_set_forcing(m, 0.8, &one, NULL, &zero), VI_OK);
  assert_int_equal(vi_model_set_stop(m, &up, xs, r), VI_OK);
  if (d > 0) assert_int_equal(vi_model_add_stop(m, &down, d, r), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  return m;
}

static void test_two_sided_grazing_curve(void **state)
{
  (void)state;
  const double c = 0.1, r = 0.8, xs = 0.5;
  /* the orbit from the one-stop model's scan (the scan takes one stop) */
  vi_model *m = two_sided(c, r, xs, 0);
  double tt[4], xx[4], vv[4], g, p, p2, t, x, v, worst = 0, lo = HUGE_VAL, hi = -HUGE_VAL;
  int found = 0, ok = 0, k = 0, n = 0;
  assert_int_equal(vi_orbit_p1_scan(m, 1, 720, tt, xx, vv, 1, 4, &found), VI_OK);
  vi_model_destroy(&m);
  m = two_sided(c, r, xs, 5.0);
  for (; k < found && !ok; k++)
    assert_int_equal(vi_orbit_pnm_admissible(m, 1, 1, tt + k, xx + k, vv + k, 1, &g, &ok), VI_OK);
  assert_true(ok);
  k--;
  vi_cont_curve *cc = NULL;
  assert_int_equal(vi_cont_curve_create(m, VI_CONT_CURVE_GRAZING, 1, 1, "stops[2].xs",
                                        "forcing.omega", &cc), VI_OK);
  assert_int_equal(vi_cont_curve_set_orbit(cc, tt[k], xx + k, vv + k), VI_OK);
  int lst = vi_cont_curve_locate(cc, 0.0, 200, &p);
  assert_int_equal(lst, VI_OK);
  double ref = -sdof_lowest(c, 0.8, r, tt[k], xs, vv[k]);
  printf("  lower stop grazed at d = %.15g (closed form %.15g)\n", p, ref);
  assert_true(fabs(p - ref) < 1e-10 * ref);
  assert_int_equal(vi_cont_curve_set_range(cc, 0.7, 0.9, 40), VI_OK);
  while (!vi_cont_curve_done(cc)) {
    assert_int_equal(vi_cont_curve_iterate(cc), VI_OK);
    assert_int_equal(vi_cont_curve_point(cc, &p, &p2, &t, &x, &v, NULL), VI_OK);
    assert_true(fabs(x - xs) < 1e-12 && v > 0); /* the upper stop, approached */
    ref = -sdof_lowest(c, p2, r, t, xs, v);
    worst = fmax(worst, fabs(p - ref) / ref);
    lo = fmin(lo, p2);
    hi = fmax(hi, p2);
    n++;
  }
  printf("  %d points, Omega %.3g..%.3g: worst relative error %.2e\n", n, lo, hi, worst);
  assert_int_equal(vi_cont_curve_done(cc), VI_CONT_CURVE_END);
  assert_true(lo == 0.7 && hi == 0.9 && n > 10);
  assert_true(worst < 1e-10);
  vi_cont_curve_destroy(&cc);
  vi_model_destroy(&m);
}

/* cusp_check.py's 60-digit cusp of the P(2,2) fold curve, 16 kept */
#define CUSP_OMEGA 0.532300653891731
#define CUSP_XS 1.27878235550746

/* The point budget holds each way from the located point.  The 4-mode
 * cantilever's grazing curve in (Omega, x_s), x_s in [0.01, 0.2], located
 * at Omega = 0.855 (x_s = 0.05), runs a long way back (beyond the budget
 * at 10 steps) and, ahead, through two folds to Omega 1.59 where x_s
 * reaches 0.01.  With one budget for both ways, spent behind, the curve
 * stopped short of its located point (the pass from the start retraces
 * the way back), never going on. */
static void test_curve_budget(void **state)
{
  (void)state;
  double p, p2 = NAN, pmax = 0.0;
  vi_model *m = vi_test_beam(4, 0.05, 0.75);
  /* its stable P(1,1) orbit (the scan's with the smallest multipliers) */
  double tt[8], xx[32], vv[32], re[8], im[8], t = 0, x[4], v[4], rb = HUGE_VAL;
  int found = 0;
  assert_int_equal(vi_orbit_p1_scan(m, 1, 720, tt, xx, vv, 4, 8, &found), VI_OK);
  for (int i = 0; i < found && i < 8; i++) {
    double rho = 0.0;
    const double *xi = xx + (size_t)4 * i, *vi = vv + (size_t)4 * i;
    assert_int_equal(vi_orbit_pnm_multipliers(m, 1, 1, tt + i, xi, vi, 4, re, im), VI_OK);
    for (int j = 0; j < 8; j++) rho = fmax(rho, hypot(re[j], im[j]));
    if (rho < rb) {
      rb = rho;
      t = tt[i];
      memcpy(x, xi, sizeof x);
      memcpy(v, vi, sizeof v);
    }
  }
  assert_true(rb < 1.0);
  vi_cont_curve *c = NULL;
  assert_int_equal(vi_cont_curve_create(m, VI_CONT_CURVE_GRAZING, 1, 1, "forcing.omega",
                                        "stop.xs", &c), VI_OK);
  assert_int_equal(vi_cont_curve_set_orbit(c, t, x, v), VI_OK);
  assert_int_equal(vi_cont_curve_locate(c, 0.95, 10, &p), VI_OK);
  double located = p;
  assert_int_equal(vi_cont_curve_set_range(c, 0.01, 0.2, 10), VI_OK);
  int n = 0, folds = 0;
  while (!vi_cont_curve_done(c)) {
    assert_int_equal(vi_cont_curve_iterate(c), VI_OK);
    assert_int_equal(vi_cont_curve_point(c, &p, &p2, NULL, NULL, NULL, NULL), VI_OK);
    for (int i = 0; i < vi_cont_curve_num_special(c); i++) {
      int type;
      assert_int_equal(vi_cont_curve_special(c, i, &type, NULL, NULL, NULL), VI_OK);
      folds += type == VI_CONT_SP_FOLD;
    }
    pmax = fmax(pmax, p);
    n++;
  }
  printf("  %d points, located at Omega %.6f, on to %.6f (x_s %.6f), %d folds; first: %d, "
         "last: %d\n", n, located, pmax, p2, folds, vi_cont_curve_start(c),
         vi_cont_curve_done(c));
  assert_int_equal(vi_cont_curve_start(c), VI_CONT_CURVE_STALLED);
  assert_int_equal(vi_cont_curve_done(c), VI_CONT_CURVE_END);
  assert_true(n <= 2 * (20 * 10 + 100)); /* each way from the located point */
  assert_true(pmax > 1.5 && p2 == 0.01 && folds == 2);
  vi_cont_curve_destroy(&c);
  vi_model_destroy(&m);
}

/* A cusp of a fold curve: Fig. 2's chain with c = 0.05, its stable P(2,2)
 * orbit at (0.535, 1.285) followed down in Omega to its fold and the fold
 * in (Omega, x_s).  Two fold branches (two P(2,2) orbits merging) leave
 * the cusp towards smaller Omega; the curve passes it, its plane tangent
 * through zero, and the point is located where it vanishes: the closed
 * form's solution of the orbit, fold and cusp conditions (u^T D2g[v,v] =
 * 0) in 60-digit mpmath (tests/study/cusp_check.py). */
static void test_cusp(void **state)
{
  (void)state;
  const double a[2] = {0.5, 0.0};
  vi_model *m = vi_test_chain(2, 1.0, 1.0, 0.05, 1.285, 0.7, 0.535, a);
  double t[2], x[4], v[4], p, p2;
  int type, loc, ncusp = 0;
  p22_orbit(m, t, x, v);
  vi_cont_curve *c = NULL;
  assert_int_equal(vi_cont_curve_create(m, VI_CONT_CURVE_FOLD, 2, 2, "forcing.omega", "stop.xs",
                                        &c), VI_OK);
  assert_int_equal(vi_cont_curve_set_impacts(c, t, x, v, 2), VI_OK);
  assert_int_equal(vi_cont_curve_locate(c, 0.52, 200, &p), VI_OK);
  printf("  P(2,2) fold at x_s = 1.285: Omega = %.15g\n", p);
  assert_int_equal(vi_cont_curve_set_range(c, 1.27, 1.31, 200), VI_OK);
  while (!vi_cont_curve_done(c)) {
    assert_int_equal(vi_cont_curve_iterate(c), VI_OK);
    for (int i = 0; i < vi_cont_curve_num_special(c); i++) {
      assert_int_equal(vi_cont_curve_special(c, i, &type, &p, &p2, &loc), VI_OK);
      if (type != VI_CONT_SP_CUSP) continue;
      printf("  cusp at Omega = %.16g, x_s = %.16g, located %d (closed form %.15g, %.15g)\n", p,
             p2, loc, CUSP_OMEGA, CUSP_XS);
      assert_true(loc);
      assert_true(fabs(p - CUSP_OMEGA) < 1e-12 && fabs(p2 - CUSP_XS) < 1e-12);
      ncusp++;
    }
  }
  assert_int_equal(ncusp, 1);
  /* the upper branch's first point: where the corrector fails short of the
   * generalized period doubling of P(1,1) (doc/curves.md), said so */
  assert_int_equal(vi_cont_curve_start(c), VI_CONT_CURVE_CORRECTOR);
  assert_int_equal(vi_cont_curve_done(c), VI_CONT_CURVE_END);
  vi_cont_curve_destroy(&c);
  vi_model_destroy(&m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_pd_refined),
      cmocka_unit_test(test_p10_grazing_curve),
      cmocka_unit_test(test_fold_curve_end),
      cmocka_unit_test(test_p22_pd_curve),
      cmocka_unit_test(test_p22_fold_upward),
      cmocka_unit_test(test_refine_pnm),
      cmocka_unit_test(test_p22_grazing_curve),
      cmocka_unit_test(test_large_model_pd),
      cmocka_unit_test(test_resonance_12),
      cmocka_unit_test(test_locate_stops_at_grazing),
      cmocka_unit_test(test_two_sided_grazing_curve),
      cmocka_unit_test(test_cusp),
      cmocka_unit_test(test_curve_budget),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
