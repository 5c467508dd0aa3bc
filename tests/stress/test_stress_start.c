/* test_stress_start.c - starts exactly on the stop (issue 9, case 5).
 *
 * Starts on the stop, with the ball x'' = f0, stop x <= 0:
 *  - moving into it (v0 = 2, f0 = g = 9.81, r = 0.8): an impact at t = 0 with
 *    v_n = 2 and rebound -r v0; the next at 2 r v0 / g; sticking at the
 *    accumulation point 2 r v0 / (g (1 - r)) (the ball of
 *    test_stress_chatter.c with V = r v0);
 *  - at rest and pressed (f0 = g): sticking from t = 0, no impact, x = 0;
 *  - at rest and pulled away (f0 = -g): it leaves, x = -g t^2 / 2, no event.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "stress_util.h"

#define G 9.81

/* One method's run of test_start_moving_into_stop: v0 and r the scene's,
 * t2 and tacc the closed-form second impact and stick times.  (Its own
 * function: the lint's path-sensitive analyser explored the loop over the
 * methods to its node budget.) */
static void into_stop_run(const vi_model *m, int meth, double v0, double r, double t2,
                          double tacc)
{
  st_log log = {0};
  st_guard guard = {0, 1000000};
  const double x0 = 0.0;
  vi_sim *s = st_sim(m, meth, 1e-12, 1e-14, 0.0, &x0, &v0, &log, &guard);
  int st = vi_sim_run(s, 2.0);
  if (st != VI_OK) print_error("%s\n", vi_sim_errmsg(s));
  st_check(st == VI_OK);
  st_check(log.count >= 3 && log.kind[0] == VI_EVENT_IMPACT && log.kind[1] == VI_EVENT_IMPACT);
  if (log.count >= 2) {
    st_check(log.t[0] == 0.0 && log.vn[0] == v0 && fabs(log.v1[0] + r * v0) <= 1e-15);
    st_check(fabs(log.t[1] - t2) <= 1e-12 && fabs(log.vn[1] - r * v0) <= 1e-11);
  }
  int is = st_log_find(&log, VI_EVENT_STICK, 0);
  st_check(is >= 0 && fabs(log.t[is] - tacc) <= 1e-10 * tacc);
  st_check(vi_sim_is_sticking(s) == 1);
  print_message("  into the stop %-5s: %d events, first at t = %g v_n = %g "
                "v+ = %g, second error %.3g, stick error %.3g\n",
                vi_method_name(meth), log.count, log.count ? log.t[0] : NAN,
                log.count ? log.vn[0] : NAN, log.count ? log.v1[0] : NAN,
                log.count > 1 ? log.t[1] - t2 : NAN,
                is >= 0 ? log.t[is] - tacc : NAN);
  st_log_free(&log);
  vi_sim_destroy(&s);
}

static void test_start_moving_into_stop(void **state)
{
  (void)state;
  const double v0 = 2.0, r = 0.8;
  vi_model *m = st_sdof(1.0, 0.0, 0.0, 0.0, 0.0, 0.0, G, 0.0, r);
  double t2 = 2.0 * r * v0 / G, tacc = t2 / (1.0 - r);
  for (int meth = 0; meth < VI_METHOD_COUNT; meth++)
    if (st_method_ok(m, meth)) into_stop_run(m, meth, v0, r, t2, tacc);
  vi_model_destroy(&m);
  st_end();
}

static void test_start_at_rest_on_stop(void **state)
{
  (void)state;
  for (int pressed = 1; pressed >= 0; pressed--) {
    double f0 = pressed ? G : -G;
    vi_model *m = st_sdof(1.0, 0.0, 0.0, 0.0, 0.0, 0.0, f0, 0.0, 0.8);
    for (int meth = 0; meth < VI_METHOD_COUNT; meth++) {
      if (!st_method_ok(m, meth)) continue;
      st_log log = {0};
      st_guard guard = {0, 1000000};
      const double x0 = 0.0, v0 = 0.0;
      vi_sim *s = st_sim(m, meth, 1e-12, 1e-14, 0.0, &x0, &v0, &log, &guard);
      int st = vi_sim_run(s, 1.0);
      if (st != VI_OK) print_error("%s\n", vi_sim_errmsg(s));
      st_check(st == VI_OK);
      double x = NAN, v = NAN;
      vi_sim_state(s, NULL, &x, &v);
      st_check(st_log_count(&log, VI_EVENT_IMPACT) == 0);
      st_check(st_log_count(&log, VI_EVENT_RELEASE) == 0);
      if (pressed) {
        st_check(vi_sim_is_sticking(s) == 1);
        st_check(st_log_count(&log, VI_EVENT_STICK) <= 1);
        st_check(fabs(x) <= 1e-14 && fabs(v) <= 1e-14);
      } else {
        st_check(log.count == 0 && vi_sim_is_sticking(s) == 0);
        st_check(fabs(x + 0.5 * G) <= 1e-10 && fabs(v + G) <= 1e-10);
      }
      print_message("  at rest, %s, %-5s: %d events, sticking %d, x(1) = %.15g "
                    "v(1) = %.15g\n", pressed ? "pressed" : "pulled off",
                    vi_method_name(meth), log.count, vi_sim_is_sticking(s), x, v);
      st_log_free(&log);
      vi_sim_destroy(&s);
    }
    vi_model_destroy(&m);
  }
  st_end();
}

/* A sim that was never given an initial state starts at rest at x = 0
 * (vi_sim_create); with the stop at x_s = -1 that state is beyond the stop,
 * which no run may accept: it must fail (VI_ERR_INITIAL_STATE or
 * VI_ERR_INVARIANT), not integrate a state beyond the stop. */
static void test_default_state_beyond_stop(void **state)
{
  (void)state;
  vi_model *m = st_sdof(1.0, 0.0, 1.0, 0.9, 0.5, 0.0, 0.0, -1.0, 0.8);
  for (int meth = 0; meth < VI_METHOD_COUNT; meth++) {
    if (!st_method_ok(m, meth)) continue;
    vi_sim *s = NULL;
    assert_int_equal(vi_sim_create(m, &s), VI_OK);
    assert_int_equal(vi_sim_set_method(s, meth), VI_OK);
    int st = vi_sim_run(s, 10.0);
    double x = NAN;
    vi_sim_state(s, NULL, &x, NULL);
    print_message("  default state, x_s = -1, %-5s: %s, x(end) = %.6g (%s)\n",
                  vi_method_name(meth), vi_status_name(st), x, vi_sim_errmsg(s));
    st_check(st == VI_ERR_INITIAL_STATE || st == VI_ERR_INVARIANT);
    vi_sim_destroy(&s);
  }
  vi_model_destroy(&m);
  st_end();
}

/* Defect 4 of the issue: the first sample of a run is the initial state
 * (it was NaN with CVODE).  The ball from x = -1, v = 2 (K = 0, f0 = g,
 * stop x <= 0): samples every 0.05 are x = -1 + 2 t + g t^2 / 2 until the
 * first contact at t = (-2 + sqrt(4 + 2 g)) / g. */
typedef struct first_samples { int n; double err; } first_samples;

static int sample_ball(double t, int n, const double *x, const double *v, void *u)
{
  (void)n;
  first_samples *f = u;
  double xe = -1.0 + 2.0 * t + 0.5 * G * t * t, ve = 2.0 + G * t;
  double e = fmax(fabs(x[0] - xe), fabs(v[0] - ve));
  if (!(e <= f->err)) f->err = e; /* a NaN sticks */
  f->n++;
  return 0;
}

static void test_first_sample_is_initial_state(void **state)
{
  (void)state;
  vi_model *m = st_sdof(1.0, 0.0, 0.0, 0.0, 0.0, 0.0, G, 0.0, 0.8);
  double t1 = (-2.0 + sqrt(4.0 + 2.0 * G)) / G;
  for (int meth = 0; meth < VI_METHOD_COUNT; meth++) {
    if (!st_method_ok(m, meth)) continue;
    first_samples f = {0, 0.0};
    const double x0 = -1.0, v0 = 2.0;
    vi_sim *s = st_sim(m, meth, 1e-10, 1e-12, 0.0, &x0, &v0, NULL, NULL);
    assert_int_equal(vi_sim_set_sampling(s, 0.05, sample_ball, &f, NULL), VI_OK);
    st_check(vi_sim_run(s, 0.05 * floor(t1 / 0.05)) == VI_OK);
    st_check(f.n == (int)floor(t1 / 0.05) + 1);
    st_check(f.err <= 1e-9); /* 10 (atol + rtol |x|), |x|, |v| <= 4 */
    print_message("  samples before the first contact, %-5s: %d, max error %.3g\n",
                  vi_method_name(meth), f.n, f.err);
    vi_sim_destroy(&s);
  }
  vi_model_destroy(&m);
  st_end();
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_start_moving_into_stop),
      cmocka_unit_test(test_start_at_rest_on_stop),
      cmocka_unit_test(test_default_state_beyond_stop),
      cmocka_unit_test(test_first_sample_is_initial_state),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
