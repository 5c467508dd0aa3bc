/* test_stress_scale.c - a run is scale-consistent (issue 29: no input
 * gives a hang or a silent wrong answer).
 *
 * The 2-mass chain (m = k = 1, c = 0.1), stop on mass 2 at x_s with
 * r = 0.7, forcing a = (A, 0) at Omega = 0.9, three forcing periods from
 * rest.  Between impacts the system is linear and Newton's law is
 * homogeneous of degree one, so the motion for (lambda A, lambda x_s) is
 * exactly lambda times that for (A, x_s): with the absolute tolerances in
 * the model's units scaled alike (atol and the chatter threshold times
 * lambda), every method must give the same impacts and sticks, at the
 * same times, with approach velocities lambda times as large.
 *  a. x_s = 0.1 A (five impacts, no stick) and x_s = 0 (a stick from the
 *     start, released, two impacts), lambda = 1e-6 .. 1e90, every method:
 *     counts equal, times within 1e-9 and v_n / lambda within 1e-9 of
 *     lambda = 1 (the same arithmetic up to the rounding of lambda's
 *     products).
 *  b. A stop that the load's scale cannot resolve: x_s = 0.1 fixed and
 *     A = 1e20 or 1e90 with atol 1e-10 (or 1e-10 A): x_s / A is below the
 *     round-off of every position (1e-16 A), so the motion is that of
 *     x_s = 0 to every digit: two impacts and one stick, the last impact's
 *     time and v_n / A those of x_s = 0 (the exact method; a run that took
 *     millions of impacts of round-off's size or never ended before).
 *  c. x_s / A = 1e-9 (A = 1e8, default tolerances, the exact method):
 *     the chatter of the first contact is resolved until its bounces stop
 *     decaying in the closed form's round-off and summed there (17
 *     impacts, not millions); the last impact is that of x_s = 0 to 1e-6
 *     (x_s moves it by about 1e-9 of its size).
 *  d. The integrators with atol 1e-10 under A = 1e20 and 1e90: the x_s = 0
 *     motion, or VI_ERR_INTEGRATOR with a message that says to raise atol
 *     (near a release the motion grows from rest like a power of the time
 *     since, and no step within atol + rtol |x| is longer than an ulp of
 *     t); never a hang (a guard of 100 000 steps).
 *  e. (test_default_threshold) as a., lambda = 1e-9 .. 1e20, with the
 *     default chatter threshold, only atol scaled: the same motion.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "stress_util.h"

enum { MAXEV = 256 };

typedef struct run_out {
  int impacts, sticks, count, st;
  char msg[1024];
  double t[MAXEV], vn[MAXEV];
  int kind[MAXEV];
} run_out;

static int on_event(const vi_event *ev, void *user)
{
  run_out *o = user;
  if (ev->kind == VI_EVENT_IMPACT) o->impacts++;
  if (ev->kind == VI_EVENT_STICK) o->sticks++;
  if (o->count < MAXEV) {
    o->kind[o->count] = ev->kind;
    o->t[o->count] = ev->t;
    o->vn[o->count] = ev->vn;
    o->count++;
  }
  return 0;
}

static vi_model *chain(double A, double xs)
{
  const double mass[2] = {1.0, 1.0}, k[2] = {1.0, 1.0}, c[2] = {0.1, 0.1};
  double M[4], C[4], K[4], a[2] = {A, 0.0}, b[2] = {0.0, 0.0},
         f0[2] = {0.0, 0.0}, w[2] = {0.0, 1.0};
  vi_model *m = NULL;
  assert_int_equal(vi_build_chain(2, mass, k, c, M, C, K, 2), VI_OK);
  assert_int_equal(vi_model_create(2, &m), VI_OK);
  assert_int_equal(vi_model_set_mass(m, M, 2), VI_OK);
  assert_int_equal(vi_model_set_damping(m, C, 2), VI_OK);
  assert_int_equal(vi_model_set_stiffness(m, K, 2), VI_OK);
  assert_int_equal(vi_model_set_forcing(m, 0.9, a, b, f0), VI_OK);
  assert_int_equal(vi_model_set_stop(m, w, xs, 0.7), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  return m;
}

/* Three forcing periods from rest (vchat < 0: the default chatter
 * threshold); VI_ERR_UNSUPPORTED in o->st if the
 * method does not apply.  A guard of 100 000 steps turns a hang into a
 * failure. */
static void run(double A, double xs, double atol, double vchat, int meth,
                run_out *o)
{
  memset(o, 0, sizeof *o);
  vi_model *m = chain(A, xs);
  vi_sim *s = NULL;
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  o->st = vi_sim_set_method(s, meth);
  if (o->st == VI_OK) {
    st_guard guard = {0, 100000};
    assert_int_equal(vi_sim_set_tolerances(s, 1e-8, atol), VI_OK);
    if (vchat >= 0.0) assert_int_equal(vi_sim_set_chatter_threshold(s, vchat), VI_OK);
    assert_int_equal(vi_sim_set_event_callback(s, on_event, o, NULL), VI_OK);
    assert_int_equal(vi_sim_set_cancel(s, st_guard_poll, &guard, NULL), VI_OK);
    o->st = vi_sim_run(s, 3.0 * 2.0 * M_PI / 0.9);
    snprintf(o->msg, sizeof o->msg, "%s", vi_sim_errmsg(s));
  }
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
}

/* o (scale lambda) against ref (scale 1): the same events, times within
 * ttol, v_n / lambda within vtol relative */
static void same_motion(const run_out *ref, const run_out *o, double lambda,
                        double ttol, double vtol)
{
  if (o->st) print_error("%s\n", o->msg);
  st_check(o->st == VI_OK);
  st_check(o->impacts == ref->impacts && o->sticks == ref->sticks);
  st_check(o->count == ref->count);
  double et = 0.0, ev = 0.0;
  for (int i = 0; i < o->count && i < ref->count; i++) {
    st_check(o->kind[i] == ref->kind[i]);
    et = fmax(et, fabs(o->t[i] - ref->t[i]));
    if (ref->kind[i] == VI_EVENT_IMPACT)
      ev = fmax(ev, fabs(o->vn[i] / lambda - ref->vn[i]) / ref->vn[i]);
  }
  st_check(et <= ttol && ev <= vtol);
  print_message("    lambda %-6g: %d impacts %d sticks, times %.2g, v_n %.2g\n",
                lambda, o->impacts, o->sticks, et, ev);
}

static void test_scaled_scene(void **state)
{
  (void)state;
  static const double lambdas[] = {1e-6, 1e-3, 1e3, 1e8, 1e20, 1e90};
  static const double xs0[] = {0.1, 0.0};
  for (int meth = 0; meth < VI_METHOD_COUNT; meth++) {
    for (int c = 0; c < 2; c++) {
      run_out ref, o;
      run(1.0, xs0[c], 1e-10, 1e-7, meth, &ref);
      if (ref.st == VI_ERR_UNSUPPORTED) break;
      st_check(ref.st == VI_OK);
      /* physics: x_s = 0.1 gives five impacts, none chattering; x_s = 0
       * sticks from the start, is released, and hits twice */
      st_check(c == 0 ? ref.impacts == 5 && ref.sticks == 0
                      : ref.impacts == 2 && ref.sticks == 1);
      print_message("  %s x_s = %g A: %d impacts, %d sticks\n",
                    vi_method_name(meth), xs0[c], ref.impacts, ref.sticks);
      for (size_t i = 0; i < sizeof lambdas / sizeof lambdas[0]; i++) {
        double L = lambdas[i];
        run(L, L * xs0[c], L * 1e-10, L * 1e-7, meth, &o);
        same_motion(&ref, &o, L, 1e-9, 1e-9);
      }
    }
  }
  st_end();
}

/* The defaults alone (only atol scaled, as a user gives it in the model's
 * units): the default chatter threshold is relative to the run's
 * velocity scale, so a nano-scale model keeps its impacts.  Before, an
 * absolute 1e-7 summed them as chatter: at lambda = 1e-9 (approach
 * velocities about 1e-9) 3 impacts and a stick for 5 impacts, and at
 * x_s = 0 three sticks for one. */
static void test_default_threshold(void **state)
{
  (void)state;
  static const double lambdas[] = {1e-9, 1e-6, 1e-3, 1e3, 1e20};
  static const double xs0[] = {0.1, 0.0};
  for (int meth = 0; meth < VI_METHOD_COUNT; meth++) {
    for (int c = 0; c < 2; c++) {
      run_out ref, o;
      run(1.0, xs0[c], 1e-10, -1.0, meth, &ref);
      if (ref.st == VI_ERR_UNSUPPORTED) break;
      st_check(c == 0 ? ref.st == VI_OK && ref.impacts == 5 && ref.sticks == 0
                      : ref.st == VI_OK && ref.impacts == 2 && ref.sticks == 1);
      print_message("  %s x_s = %g A, default threshold:\n", vi_method_name(meth), xs0[c]);
      for (size_t i = 0; i < sizeof lambdas / sizeof lambdas[0]; i++) {
        double L = lambdas[i];
        run(L, L * xs0[c], L * 1e-10, -1.0, meth, &o);
        same_motion(&ref, &o, L, 1e-9, 1e-9);
      }
    }
  }
  st_end();
}

/* o's last impact is ref's (x_s = 0) scaled by A, after a stick and at
 * most nmax impacts */
static void last_impact_as_ref(const run_out *ref, const run_out *o, double A,
                               int nmax)
{
  int last = o->count - 1;
  while (last >= 0 && o->kind[last] != VI_EVENT_IMPACT) last--;
  st_check(o->st == VI_OK && o->sticks >= 1 && o->impacts >= 2 &&
           o->impacts <= nmax && last >= 0);
  if (last < 0) return;
  double tl = ref->t[ref->count - 1], vl = ref->vn[ref->count - 1];
  st_check(fabs(o->t[last] - tl) <= 1e-6 * tl &&
           fabs(o->vn[last] / A - vl) <= 1e-6 * vl);
  print_message("    %d impacts %d sticks, last at %.10g v_n / A %.10g "
                "(x_s = 0: %.10g, %.10g)\n", o->impacts, o->sticks,
                o->t[last], o->vn[last] / A, tl, vl);
}

static void test_unresolved_stop(void **state)
{
  (void)state;
  run_out ref, o;
  run(1.0, 0.0, 1e-10, 1e-7, VI_METHOD_EXACT, &ref);
  st_check(ref.st == VI_OK && ref.impacts == 2 && ref.sticks == 1);
  static const double amps[] = {1e20, 1e90};
  for (size_t i = 0; i < sizeof amps / sizeof amps[0]; i++)
    for (int loose = 0; loose < 2; loose++) {
      double A = amps[i], atol = loose ? 1e-10 * A : 1e-10;
      run(A, 0.1, atol, 1e-7, VI_METHOD_EXACT, &o);
      print_message("  A = %g x_s = 0.1 atol = %g:\n", A, atol);
      same_motion(&ref, &o, A, 1e-9, 1e-9);
    }
  /* c: resolved down to the round-off, then summed */
  run(1e8, 0.1, 1e-10, 1e-7, VI_METHOD_EXACT, &o);
  last_impact_as_ref(&ref, &o, 1e8, 40);
  /* d: the integrators, whose atol 1e-10 resolves the stop at 0.1 but not
   * the motion near a release (it grows from rest like a power of the time
   * since, 1e90 times, and a step within atol + rtol |x| falls below an
   * ulp of t): the x_s = 0 motion, or a message that says to raise atol */
  static const int integ[] = {VI_METHOD_ADAMS, VI_METHOD_BDF, VI_METHOD_ERK};
  for (int i = 0; i < 3; i++)
    for (int a = 0; a < 2; a++) {
      double A = a ? 1e90 : 1e20;
      run(A, 0.1, 1e-10, 1e-7, integ[i], &o);
      print_message("  %s A = %g x_s = 0.1 atol = 1e-10: status %d\n",
                    vi_method_name(integ[i]), A, o.st);
      if (o.st == VI_OK) last_impact_as_ref(&ref, &o, A, 200);
      else
        st_check(o.st == VI_ERR_INTEGRATOR && strstr(o.msg, "raise atol"));
    }
  st_end();
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_scaled_scene),
      cmocka_unit_test(test_unresolved_stop),
      cmocka_unit_test(test_default_threshold),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
