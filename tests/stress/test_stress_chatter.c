/* test_stress_chatter.c - chatter that ends at its accumulation point, and
 * release from sticking, against closed forms (issue 9, case 1).
 *
 * The bouncing ball as an SDOF model: x = -height, M = 1, K = C = 0,
 * f0 = +g = 9.81 presses the mass into the stop x <= 0, r = 0.8, and it
 * leaves the stop at t = 0 with speed V = 5.  Flight j (j = 0, 1, ...) starts
 * with speed r^j V and lasts 2 r^j V / g, so impact k (1-based) is at
 *   t_k = (2V/g) (1 - r^k) / (1 - r),  approach speed v_k = r^(k-1) V,
 * and the impacts accumulate at T = 2V / (g (1 - r)) = 5.0968399592252803...
 * (ref/stress_ref.py, 30 digits).  There the ball sticks (the stop stays
 * pressed by g) for ever.
 *
 * Energy: the ball starts and ends at x = 0, so f0 does no net work and the
 * kinetic energy 1/2 V^2 = 12.5 is all lost in impacts.  The impacts after
 * the last resolved one (approach v_N, rebound r v_N) lose
 *   sum_{j>=1} 1/2 (1 - r^2) (r^j v_N)^2 = 1/2 (r v_N)^2,
 * the kinetic energy of that rebound: this is what the stick event's ie must
 * hold, and the ledger must close over the whole run. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "stress_util.h"

#define G 9.81
#define V0 5.0
#define R 0.8
/* ref/stress_ref.py */
#define T_ACC 5.09683995922528032619775739042
#define T_1 1.01936799184505606523955147808
#define T_30 5.09053037696592568667227765431

static double t_impact(int k) { return 2.0 * V0 / G * (1.0 - pow(R, k)) / (1.0 - R); }

typedef struct ball_result {
  double et, evn, estick, eie, stick_ie, stick_ie_ref, ledger_res, ledger_gap;
  int impacts;
  int64_t skipped;
} ball_result;

/* One run of the ball to t = 6 with a method and tolerances.  The first
 * check_n impact times are checked against the closed form to
 * max(tol_rel_t t_k, 10 dx / (v_k (1 - r))): a position error dx turns
 * into a time error dx / v per flight, and the flights' errors sum
 * geometrically to dx / (v_k (1 - r)).  The stick time to tol_stick. */
static ball_result run_ball(const vi_model *m, int method, double rtol,
                            double atol, int check_n, double tol_rel_t,
                            double tol_stick, double dx)
{
  ball_result res;
  memset(&res, 0, sizeof res);
  st_log log = {0};
  st_guard guard = {0, 200000};
  const double x0 = 0.0, v0 = -V0;
  vi_sim *s = st_sim(m, method, rtol, atol, 0.0, &x0, &v0, &log, &guard);
  assert_int_equal(vi_sim_enable_ledger(s, 1), VI_OK);
  st_gap gap = {NULL, 0.0, -HUGE_VAL, 0};
  assert_int_equal(vi_sim_set_sampling(s, 6.0 / 6000.0, st_gap_sample, &gap, NULL), VI_OK);
  int st = vi_sim_run(s, 6.0);
  /* no sample beyond the stop by more than the position error */
  st_check(gap.gmax <= 10.0 * dx);
  st_check(st == VI_OK);
  if (st != VI_OK) {
    print_error("%s: %s\n", vi_method_name(method), vi_sim_errmsg(s));
    res.estick = HUGE_VAL;
    st_log_free(&log);
    vi_sim_destroy(&s);
    return res;
  }

  int nimp = st_log_count(&log, VI_EVENT_IMPACT);
  res.impacts = nimp;
  /* the first impacts are resolved one by one (at least five from 5 m/s:
   * down to 10 dx / (r rtol t), or 0.3 m/s at the default tolerances);
   * the rest of the sequence is summed by the chatter map, which the
   * stick time checks */
  st_check(nimp >= 5);
  if (check_n > nimp) check_n = nimp;
  st_check(vi_sim_stat(s, VI_STAT_IMPACTS) == nimp);
  for (int k = 1; k <= nimp; k++) {
    int i = st_log_find(&log, VI_EVENT_IMPACT, k - 1);
    double vk = V0 * pow(R, k - 1);
    double bound = fmax(tol_rel_t * t_impact(k), 10.0 * dx / (vk * (1.0 - R)));
    if (k <= check_n) {
      res.et = fmax(res.et, fabs(log.t[i] - t_impact(k)) / t_impact(k));
      res.evn = fmax(res.evn, fabs(log.vn[i] - vk) / V0);
      st_check(fabs(log.t[i] - t_impact(k)) <= bound);
      st_check(fabs(log.vn[i] - vk) <= G * bound + 10.0 * dx);
    }
    st_check(log.t[i] < T_ACC);
  }
  /* one stick, at the accumulation point, after every impact */
  int is = st_log_find(&log, VI_EVENT_STICK, 0);
  st_check(st_log_count(&log, VI_EVENT_STICK) == 1);
  st_check(st_log_count(&log, VI_EVENT_RELEASE) == 0);
  st_check(is == log.count - 1);
  res.estick = is >= 0 ? fabs(log.t[is] - T_ACC) : HUGE_VAL;
  print_message("  %-5s rtol %.0e: %d impacts (first %d within %.2e rel of "
                "t_k, v_n within %.2e V), stick at %.15g: error %.3g "
                "(bound %.3g)\n", vi_method_name(method), rtol, nimp, check_n,
                res.et, res.evn, is >= 0 ? log.t[is] : NAN, res.estick, tol_stick);
  st_check(res.estick <= tol_stick);
  st_check(vi_sim_stat(s, VI_STAT_STICKS) == 1);
  st_check(vi_sim_is_sticking(s) == 1);
  double x, v;
  assert_int_equal(vi_sim_state(s, NULL, &x, &v), VI_OK);
  st_check(fabs(x) <= 10.0 * dx);
  st_check(fabs(v) <= 10.0 * dx);

  /* energy: all of 1/2 V^2 is lost in impacts; the stick event holds the
   * tail's share, the rebound energy of the last resolved impact */
  res.eie = fabs(st_log_ie(&log) - 0.5 * V0 * V0) / (0.5 * V0 * V0);
  int il = st_log_find(&log, VI_EVENT_IMPACT, nimp - 1);
  res.stick_ie = is >= 0 ? log.ie[is] : NAN;
  res.stick_ie_ref = il >= 0 ? 0.5 * R * R * log.vn[il] * log.vn[il] : NAN;
  res.skipped = vi_sim_stat(s, VI_STAT_CHATTER_SKIPPED);
  double E[1], FE[1], DE[1], XE[1], CE[1], dE[1], ie;
  assert_int_equal(vi_sim_ledger(s, E, FE, DE, XE, CE, dE, &ie), VI_OK);
  res.ledger_res = vi_sim_ledger_max_residual(s);
  /* the ledger's own totals against the energies known in closed form:
   * nothing left (E = 0), all of 1/2 V^2 lost, the jumps summing to -ie */
  res.ledger_gap = fmax(fabs(ie - 0.5 * V0 * V0), fabs(E[0]));
  res.ledger_gap = fmax(res.ledger_gap, fabs(dE[0] + ie));
  print_message("        sum ie %.3g rel; stick ie %.6g vs 1/2 (r v_N)^2 = "
                "%.6g; chatter_skipped %lld; ledger residual %.3g, |ledger - "
                "closed form| %.3g\n", res.eie, res.stick_ie, res.stick_ie_ref,
                (long long)res.skipped, res.ledger_res, res.ledger_gap);
  st_log_free(&log);
  vi_sim_destroy(&s);
  return res;
}

static vi_model *ball(void)
{
  return st_sdof(1.0, 0.0, 0.0, 0.0, 0.0, 0.0, G, 0.0, R);
}

/* The references themselves: the closed form in double against mpmath. */
static void test_ball_reference(void **state)
{
  (void)state;
  assert_close(2.0 * V0 / (G * (1.0 - R)), T_ACC, 1e-15 * T_ACC);
  assert_close(t_impact(1), T_1, 1e-15);
  assert_close(t_impact(30), T_30, 1e-14);
}

/* Tight tolerances (rtol 1e-12, atol 1e-14): the first 30 impact times to
 * 1e-10 relative, the accumulation time to 1e-10 (relative to T), with
 * every method.  The free flight is a parabola, which Adams and BDF
 * integrate exactly up to round-off, and the closed form is exact: what is
 * left is where the event is located and where the tail is summed. */
static void test_ball_tight(void **state)
{
  (void)state;
  vi_model *m = ball();
  for (int meth = 0; meth < VI_METHOD_COUNT; meth++)
    if (st_method_ok(m, meth))
      run_ball(m, meth, 1e-12, 1e-14, 30, 1e-10, 1e-10 * T_ACC,
               1e-14 + 1e-12 * V0 * V0 / (2 * G));
  vi_model_destroy(&m);
  st_end();
}

/* Default tolerances (rtol 1e-8, atol 1e-10): position error
 * dx = atol + rtol H, H = V^2 / 2g the highest point.  Impact k then carries
 * a time error of at most dx / (v_k (1 - r)) (above) times a safety factor
 * 10.  The sequence is cut where the next apex is within ~10 atol of the
 * stop, i.e. at v_c ~ sqrt(2 g 10 dx); the jump to the accumulation point
 * from there inherits the time error dx / (v_c (1 - r)) and the speed error
 * g of that, spread over the tail's remaining flight 2 r v_c / (g (1 - r)):
 * a bound 10 (1 + 2r/(1 - r)) dx / (v_c (1 - r)), of order sqrt(dx / g). */
static void test_ball_default_tolerances(void **state)
{
  (void)state;
  vi_model *m = ball();
  double dx = 1e-10 + 1e-8 * V0 * V0 / (2 * G);
  double vc = sqrt(2.0 * G * 10.0 * dx);
  double tol_stick = 10.0 * (1.0 + 2.0 * R / (1.0 - R)) * dx / (vc * (1.0 - R));
  for (int meth = 0; meth < VI_METHOD_COUNT; meth++) {
    if (!st_method_ok(m, meth)) continue;
    run_ball(m, meth, 1e-8, 1e-10, 30, 0.0, tol_stick, dx);
  }
  vi_model_destroy(&m);
  st_end();
}

/* One method's run of test_ball_energy_bookkeeping.  (Its own function:
 * the lint's path-sensitive analyser explored the loop over the methods to
 * its node budget.) */
static void ball_energy(const vi_model *m, int meth)
{
  double dx = 1e-14 + 1e-12 * V0 * V0 / (2 * G);
  ball_result r = run_ball(m, meth, 1e-12, 1e-14, 30, 1e-10, 1.0, dx);
  /* v_N is located where the position error is atol: relative error
   * g atol / v_N^2 in v_N, twice that in its energy, times 10 */
  double vN = sqrt(2.0 * r.stick_ie_ref) / R;
  double rel = 20.0 * G * 1e-14 / (vN * vN);
  st_check(r.eie <= 1e-10);
  st_check(fabs(r.stick_ie - r.stick_ie_ref) <= rel * r.stick_ie_ref);
  st_check(r.ledger_res <= 1e-8);
  st_check(r.ledger_gap <= 1e-9 * 0.5 * V0 * V0);
  st_check(r.skipped > 0);
}

/* The impacts skipped in the jump and the energy they absorb are recorded:
 * VI_STAT_CHATTER_SKIPPED > 0, the stick event's ie is the rebound energy of
 * the last resolved impact 1/2 (r v_N)^2 (to the resolution of v_N: its
 * relative error is g dx / v_N^2, dx the position error), the events' ie sum
 * to 1/2 V^2, and the ledger (vi_ledger.h) closes with totals E_end = 0,
 * sum ie = 1/2 V^2, sum dE = -sum ie. */
static void test_ball_energy_bookkeeping(void **state)
{
  (void)state;
  vi_model *m = ball();
  for (int meth = 0; meth < VI_METHOD_COUNT; meth++)
    if (st_method_ok(m, meth)) ball_energy(m, meth);
  vi_model_destroy(&m);
  st_end();
}

/* One run of test_release_instant with a method at rtol, atol (tight: the
 * tight ones, whose impact bound is 1e-8), against the release time tr and
 * the impact's time ti and speed vi.  (Its own function: the lint's
 * path-sensitive analyser explored the loops over the methods and
 * tolerances to its node budget.) */
static void release_run(const vi_model *m, int meth, int tight, double rtol, double atol,
                        double tr, double ti, double vi)
{
  st_log log = {0};
  st_guard guard = {0, 200000};
  const double x0 = 0.2, v0 = 0.0;
  vi_sim *s = st_sim(m, meth, rtol, atol, 0.0, &x0, &v0, &log, &guard);
  int st = vi_sim_run(s, 3.5);
  if (st != VI_OK) print_error("%s\n", vi_sim_errmsg(s));
  st_check(st == VI_OK);
  int ir = st_log_find(&log, VI_EVENT_RELEASE, 0);
  int ii = st_log_find(&log, VI_EVENT_IMPACT, 0);
  st_check(ir >= 0);
  st_check(ii > ir);
  if (ir < 0 || ii < 0) ir = ii = 0; /* already failed: read safe slots */
  if (log.count == 0) { st_log_free(&log); vi_sim_destroy(&s); return; }
  double tol_i = tight ? 1e-8 : 10.0 * (atol + rtol) / vi * 2.0 * ti;
  print_message("  %-5s rtol %.0e: release %.15g (error %.3g), impact %.15g "
                "(error %.3g), v_n error %.3g\n", vi_method_name(meth),
                rtol, log.t[ir], log.t[ir] - tr, log.t[ii],
                log.t[ii] - ti, log.vn[ii] - vi);
  st_check(fabs(log.t[ir] - tr) <= 1e-8);
  st_check(fabs(log.t[ii] - ti) <= tol_i);
  st_check(fabs(log.vn[ii] - vi) <= tol_i);
  /* before the release the mass sat on the stop: no impact before it */
  st_check(st_log_count(&log, VI_EVENT_RELEASE) == 1);
  for (int i = 0; i < ir; i++) st_check(log.kind[i] != VI_EVENT_IMPACT);
  st_log_free(&log);
  vi_sim_destroy(&s);
}

/* Release from sticking.  x'' + x = f0 + A cos(W t), stop x <= xs = 0.2,
 * f0 = 0.7, A = 1, W = 2, r = 0.5, starting stuck (x = xs, v = 0; contact
 * force lambda = f0 - K xs + A cos(W t) = 0.5 + cos 2t > 0, pressed).
 * lambda falls through zero at t_r = acos(-(f0 - K xs)/A)/W = pi/3; the free
 * motion from (xs, 0) at t_r returns to the stop at t_i = pi with
 * v_n = sqrt(3)/2 (ref/stress_ref.py: 3.14159265358979323846...,
 * 0.866025403784438646763...).  Release to 1e-8 with every method at both
 * tolerances; the impact to 1e-8 at tight tolerances and to
 * 10 (atol + rtol) / v_n times the elapsed phase W t_i at the default ones. */
static void test_release_instant(void **state)
{
  (void)state;
  const double tr = 1.04719755119659774615421446109;
  const double ti = 3.14159265358979323846264338328;
  const double vi = 0.866025403784438646763723170753;
  assert_close(acos(-0.5) / 2.0, tr, 1e-15);
  vi_model *m = st_sdof(1.0, 0.0, 1.0, 2.0, 1.0, 0.0, 0.7, 0.2, 0.5);
  const double tols[2][2] = {{1e-12, 1e-14}, {1e-8, 1e-10}};
  for (int meth = 0; meth < VI_METHOD_COUNT; meth++) {
    if (!st_method_ok(m, meth)) continue;
    for (int it = 0; it < 2; it++)
      release_run(m, meth, it == 0, tols[it][0], tols[it][1], tr, ti, vi);
  }
  vi_model_destroy(&m);
  st_end();
}

/* Chatter under a time-varying load: x'' + x = 1 + 0.5 cos 3t, stop x <= 0,
 * r = 0.8, leaving the stop at speed 1 at t = 0.  The contact force
 * 1 + 0.5 cos 3t stays positive, so the impacts accumulate and the mass
 * sticks for good; the flights are not the ball's (the load changes by ~1.5
 * per unit time).  Reference, independent of the library: the closed-form
 * free motion x = 1 + P cos 3t + c1 cos t + c2 sin t (P = 0.5/(1 - 9)),
 * contacts by a scan in steps of 1/20 of the expected flight and bisection
 * to round-off, down to v_n = 5e-6, then the tail 2 r v_n / (a (1 - r))
 * with the contact acceleration a at that impact.  The tail's model error
 * (the load's rate over its 4e-5 time units) shrinks like v_n^2 and the
 * brute force's round-off (1e-16 in position, amplified by a / v_n into the
 * speeds) grows like 1/v_n: halving the cut from 1e-5 to 5e-6 moves the
 * result by 1.9e-9, from 5e-6 to 2.5e-6 by 3e-10, so the reference is good
 * to ~1e-9.  Stick time to 1e-8 with every method (tight tolerances), first
 * impacts within 10 dx / (v_k (1 - r)). */
#define HW 3.0
#define HA 0.5
static void harm_free(double t0, double x0, double v0, double t, double *x,
                      double *v)
{
  double P = HA / (1.0 - HW * HW);
  double c1 = x0 - 1.0 - P * cos(HW * t0), c2 = v0 + P * HW * sin(HW * t0);
  double tau = t - t0;
  *x = 1.0 + P * cos(HW * t) + c1 * cos(tau) + c2 * sin(tau);
  *v = -P * HW * sin(HW * t) - c1 * sin(tau) + c2 * cos(tau);
}

/* test_chatter_harmonic_load's reference (see above): the impacts' times
 * tr and speeds vr (400 at most), their number returned, and the
 * accumulation time *t_acc. */
static int harm_reference(double *tr, double *vr, double *t_acc)
{
  int nr = 0;
  double t = 0.0, x = 0.0, v = -1.0;
  for (;;) {
    double a0 = 1.0 - x + HA * cos(HW * t), u = fabs(v);
    double h = fmin(1e-3, 0.05 * 2.0 * u / a0), lo = 0.0, hi = h, xe, ve;
    for (;;) {
      harm_free(t, x, v, t + hi, &xe, &ve);
      if (xe > 0.0) break;
      lo = hi;
      hi += h;
      assert_true(hi < 50.0);
    }
    for (int it = 0; it < 200 && hi - lo > 4e-16 * (t + hi); it++) {
      double mid = 0.5 * (lo + hi);
      harm_free(t, x, v, t + mid, &xe, &ve);
      if (xe > 0.0) hi = mid; else lo = mid;
    }
    harm_free(t, x, v, t + lo, &xe, &ve);
    t += lo;
    assert_true(nr < 400);
    tr[nr] = t;
    vr[nr++] = ve;
    double a = 1.0 + HA * cos(HW * t);
    assert_true(a > 0.0);
    if (ve < 5e-6) {
      *t_acc = t + 2.0 * R * ve / (a * (1.0 - R));
      break;
    }
    x = 0.0;
    v = -R * ve;
  }
  return nr;
}

/* One method's run of test_chatter_harmonic_load against the reference:
 * nr impacts at tr with speeds vr, accumulating at t_acc.  (Its own
 * function, as is the reference: the lint's path-sensitive analyser
 * explored the test, reference and method loop in one, to its node
 * budget.) */
static void harm_run(const vi_model *m, int meth, const double *tr, const double *vr, int nr,
                     double t_acc)
{
  st_log log = {0};
  st_guard guard = {0, 200000};
  const double x0 = 0.0, v0 = -1.0;
  vi_sim *s = st_sim(m, meth, 1e-12, 1e-14, 0.0, &x0, &v0, &log, &guard);
  int st = vi_sim_run(s, t_acc + 2.0);
  if (st != VI_OK) print_error("%s\n", vi_sim_errmsg(s));
  st_check(st == VI_OK);
  int is = st_log_find(&log, VI_EVENT_STICK, 0);
  double et = 0.0;
  int nimp = st_log_count(&log, VI_EVENT_IMPACT);
  for (int k = 0; k < nimp && k < nr; k++) {
    int i = st_log_find(&log, VI_EVENT_IMPACT, k);
    double b = 10.0 * (1e-14 + 1e-12 * 1.0) / (vr[k] * (1.0 - R));
    st_check(fabs(log.t[i] - tr[k]) <= fmax(b, 1e-12));
    et = fmax(et, fabs(log.t[i] - tr[k]));
  }
  double es = is >= 0 ? log.t[is] - t_acc : NAN;
  st_check(is >= 0 && fabs(es) <= 1e-8);
  st_check(st_log_count(&log, VI_EVENT_RELEASE) == 0 && vi_sim_is_sticking(s));
  print_message("  %-5s: %d impacts within %.3g of the reference, stick "
                "error %.3g\n", vi_method_name(meth), nimp, et, es);
  st_log_free(&log);
  vi_sim_destroy(&s);
}

static void test_chatter_harmonic_load(void **state)
{
  (void)state;
  /* the reference */
  static double tr[400], vr[400];
  double t_acc = NAN;
  int nr = harm_reference(tr, vr, &t_acc);
  print_message("  reference: %d impacts to v_n = 5e-6, accumulation at %.15g\n",
                nr, t_acc);
  vi_model *m = st_sdof(1.0, 0.0, 1.0, HW, HA, 0.0, 1.0, 0.0, R);
  for (int meth = 0; meth < VI_METHOD_COUNT; meth++)
    if (st_method_ok(m, meth)) harm_run(m, meth, tr, vr, nr, t_acc);
  vi_model_destroy(&m);
  st_end();
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_ball_reference),
      cmocka_unit_test(test_ball_tight),
      cmocka_unit_test(test_ball_default_tolerances),
      cmocka_unit_test(test_ball_energy_bookkeeping),
      cmocka_unit_test(test_release_instant),
      cmocka_unit_test(test_chatter_harmonic_load),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
