/* test_stress_floors.c - nothing hangs (issue 9, case 6).
 *
 * With r = 1 there is no chatter: a mass pressed onto the stop with a tiny
 * normal speed bounces for ever with flights 2 v / g, so a run to t = 1
 * would take ~ g / (2 v) impacts (5e9 for v = 1e-9) or stall on zero-length
 * flights when v = 0.  The floors of vi_sim_set_floors (vn_min, dt_min) end
 * such a sequence in sticking: the run must terminate with VI_OK, count
 * the interventions (VI_STAT_FLOORS > 0), and leave the mass at rest on the
 * stop (x = 0, v = 0: while pressed by g it can only stick).  Every run here
 * polls a guard that cancels it after 1e5 steps, so a run that would stall
 * fails its assertions instead of hanging the test.  The same scenes
 * without floors are run too, over t = 0.05 and 1e4 steps: a run that
 * neither sticks nor stalls must then bounce as the closed form says (r = 1:
 * an impact every 2 v0 / g, each at speed v0). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "stress_util.h"

#define G 9.81

typedef struct scene { const char *what; double v0, vn_min, dt_min; } scene;

static void test_floors_terminate(void **state)
{
  (void)state;
  const scene sc[3] = {
      {"at rest, pressed, r = 1", 0.0, 1e-6, 0.0},
      {"v0 = 1e-9 into the stop, r = 1 (vn floor)", 1e-9, 1e-6, 0.0},
      {"v0 = 1e-4 into the stop, r = 1 (dt floor: flights 2e-5)", 1e-4, 0.0, 1e-3},
  };
  vi_model *m = st_sdof(1.0, 0.0, 0.0, 0.0, 0.0, 0.0, G, 0.0, 1.0);
  for (int k = 0; k < 3; k++)
    for (int meth = 0; meth < VI_METHOD_COUNT; meth++) {
      if (!st_method_ok(m, meth)) continue;
      for (int floors = 0; floors <= 1; floors++) {
        st_log log = {0};
        /* without floors the v0 = 1e-9 run stalls: a short span shows it */
        st_guard guard = {0, floors ? 100000 : 10000};
        const double x0 = 0.0, tend = floors ? 1.0 : 0.05;
        vi_sim *s = st_sim(m, meth, 1e-10, 1e-12, 0.0, &x0, &sc[k].v0, &log,
                           &guard);
        if (floors)
          assert_int_equal(vi_sim_set_floors(s, sc[k].vn_min, sc[k].dt_min), VI_OK);
        int st = vi_sim_run(s, tend);
        double t = NAN, x = NAN, v = NAN;
        vi_sim_state(s, &t, &x, &v);
        int64_t nf = vi_sim_stat(s, VI_STAT_FLOORS);
        int f0 = st_failures;
        if (floors) {
          st_check(st == VI_OK);
          /* at rest and pressed the mass sticks at once, floor or not */
          st_check(nf > 0 || sc[k].v0 == 0.0);
          st_check(vi_sim_is_sticking(s) == 1);
          st_check(fabs(x) <= 1e-12 && fabs(v) <= 1e-9);
          /* energy: at most the initial 1/2 v0^2 can have been taken */
          st_check(st_log_ie(&log) <= 0.5 * sc[k].v0 * sc[k].v0 * (1 + 1e-9));
        } else if (st == VI_OK && !vi_sim_is_sticking(s) && sc[k].v0 > 0.0) {
          /* impacts at t = j 2 v0 / g, j = 0, 1, ...: one more than the
           * flights that fit (the last may land either side of tend) */
          int ni = st_log_count(&log, VI_EVENT_IMPACT);
          double nf_exact = floor(tend * G / (2.0 * sc[k].v0)) + 1.0;
          st_check(fabs(ni - nf_exact) <= 1.0);
          for (int e = 0; e < log.count; e++)
            if (log.kind[e] == VI_EVENT_IMPACT)
              st_check(fabs(fabs(log.vn[e]) - sc[k].v0) <= 1e-6 * sc[k].v0);
        }
        print_message("  %-55s %-5s floors %s: %s at t = %.6g, %d events, "
                      "%lld steps, floors %lld, sticking %d%s\n", sc[k].what,
                      vi_method_name(meth), floors ? "on " : "off",
                      vi_status_name(st), t, log.count,
                      (long long)vi_sim_stat(s, VI_STAT_STEPS), (long long)nf,
                      vi_sim_is_sticking(s), st_failures > f0 ? "  <-- FAIL" : "");
        st_log_free(&log);
        vi_sim_destroy(&s);
      }
    }
  vi_model_destroy(&m);
  st_end();
}

/* With r < 1 a floor may end a sequence before the chatter criterion does:
 * the ball (V = 5, r = 0.5) with vn_min = 1 has impacts at v_n = 5, 2.5,
 * 1.25 and then 0.625 < 1, where the floor acts.  Whatever the sticking
 * time chosen by the intervention, it lies between that impact, at
 * t_4 = (2V/g)(1 + r + r^2) = 1.7839..., and the accumulation point
 * 2V/(g(1 - r)) = 2.0387...; the mass ends at rest on the stop, all of
 * 1/2 V^2 is lost, and the intervention is counted. */
static void test_floor_before_chatter(void **state)
{
  (void)state;
  const double V = 5.0, r = 0.5;
  vi_model *m = st_sdof(1.0, 0.0, 0.0, 0.0, 0.0, 0.0, G, 0.0, r);
  double t4 = 2.0 * V / G * (1.0 + r + r * r), tacc = 2.0 * V / (G * (1.0 - r));
  for (int meth = 0; meth < VI_METHOD_COUNT; meth++) {
    if (!st_method_ok(m, meth)) continue;
    st_log log = {0};
    st_guard guard = {0, 100000};
    const double x0 = 0.0, v0 = -V;
    vi_sim *s = st_sim(m, meth, 1e-10, 1e-12, 0.0, &x0, &v0, &log, &guard);
    assert_int_equal(vi_sim_set_floors(s, 1.0, 0.0), VI_OK);
    int st = vi_sim_run(s, 3.0);
    int is = st_log_find(&log, VI_EVENT_STICK, 0);
    int nimp = st_log_count(&log, VI_EVENT_IMPACT);
    int64_t nf = vi_sim_stat(s, VI_STAT_FLOORS);
    double x = NAN, v = NAN;
    vi_sim_state(s, NULL, &x, &v);
    int f0 = st_failures;
    st_check(st == VI_OK);
    st_check(nf > 0);
    st_check(nimp >= 3 && nimp <= 4); /* 5, 2.5, 1.25 (and 0.625) */
    st_check(is >= 0 && log.t[is] >= t4 - 1e-9 && log.t[is] <= tacc + 1e-9);
    st_check(vi_sim_is_sticking(s) == 1 && fabs(x) <= 1e-10 && fabs(v) <= 1e-10);
    st_check(fabs(st_log_ie(&log) - 0.5 * V * V) <= 1e-8 * 0.5 * V * V);
    print_message("  r = 0.5, vn_min = 1, %-5s: %s, %d impacts, stick at %.10g "
                  "(in [%.10g, %.10g]), floors %lld, sum ie %.12g%s\n",
                  vi_method_name(meth), vi_status_name(st), nimp,
                  is >= 0 ? log.t[is] : NAN, t4, tacc, (long long)nf,
                  st_log_ie(&log), st_failures > f0 ? "  <-- FAIL" : "");
    st_log_free(&log);
    vi_sim_destroy(&s);
  }
  vi_model_destroy(&m);
  st_end();
}

/* Bad floors are rejected. */
static void test_floors_arguments(void **state)
{
  (void)state;
  vi_model *m = st_sdof(1.0, 0.0, 0.0, 0.0, 0.0, 0.0, G, 0.0, 1.0);
  vi_sim *s = NULL;
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_sim_set_floors(s, -1.0, 0.0), VI_ERR_ARG);
  assert_int_equal(vi_sim_set_floors(s, 0.0, NAN), VI_ERR_ARG);
  assert_int_equal(vi_sim_set_floors(s, INFINITY, 0.0), VI_ERR_ARG);
  assert_int_equal(vi_sim_set_floors(s, 0.0, 0.0), VI_OK);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_floors_arguments),
      cmocka_unit_test(test_floors_terminate),
      cmocka_unit_test(test_floor_before_chatter),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
