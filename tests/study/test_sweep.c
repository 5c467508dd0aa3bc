/* test_sweep.c - the study API (vi_study.h, src/study/vi_sweep.c) on its
 * own, linked to the library only, against physics: the Fig. 2 P(1,1)
 * orbit from an independent 40-digit shooting (tests/orbit/ref_fig2_p11.py),
 * the closed-form harmonic response when the stop is out of reach, up and
 * down sweeps agreeing where the motion is unique, warm start continuing
 * one trajectory, the P(1,1) census of the stable orbit, and the monitor. */
#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vi_testutil.h"

/* tests/orbit/ref_fig2_p11.py (mpmath, 40 digits) */
#define FIG2_VN 0.78766085255479729134
#define FIG2_PHASE 0.67857113423124466619

static vi_sweep *study(vi_model *m, int transient, int record)
{
  vi_sweep *sw = NULL;
  assert_int_equal(vi_sweep_create(m, &sw), VI_OK);
  assert_int_equal(vi_sweep_set_run(sw, VI_METHOD_EXACT, 1e-8, 1e-10), VI_OK);
  assert_int_equal(vi_sweep_set_periods(sw, transient, record), VI_OK);
  assert_int_equal(vi_sweep_set_classify(sw, 1e-6, 32), VI_OK);
  return sw;
}

/* The last recorded impact's v_n and phase of the last point. */
static void last_impact(const vi_sweep *sw, double *vn, double *phase)
{
  int64_t n;
  const double *v, *p;
  assert_int_equal(vi_sweep_impacts(sw, &n, NULL, &p, &v), VI_OK);
  assert_true(n > 0);
  *vn = v[n - 1];
  *phase = p[n - 1];
}

/* Fig. 2 at Omega = 0.9: P(1,1), v_N and impact phase of the exact orbit.
 * The exact flow's error is round-off and the transient (500 periods,
 * Floquet multipliers well inside the unit circle) has decayed: 1e-9. */
static void fig2_p11(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  vi_sweep *sw = study(m, 500, 100);
  int n, mm;
  int64_t ni;
  double vn, ph;
  assert_int_equal(vi_sweep_iterate(sw), VI_OK);
  assert_int_equal(vi_sweep_period(sw, &n, &mm), VI_OK);
  assert_int_equal(n, 1);
  assert_int_equal(mm, 1);
  assert_int_equal(vi_sweep_impacts(sw, &ni, NULL, NULL, NULL), VI_OK);
  assert_int_equal(ni, 100); /* one per recorded period */
  last_impact(sw, &vn, &ph);
  assert_close(vn, FIG2_VN, 1e-9);
  assert_close(ph, FIG2_PHASE, 1e-9);
  assert_close(vi_sweep_forcing_period(sw), 2 * M_PI / 0.9, 1e-15);
  assert_int_equal(vi_sweep_failed(sw), 0);
  vi_sweep_destroy(&sw);
  vi_model_destroy(&m);
}

/* Stop out of reach (x_s = 100): no impacts, P(1,0), and the stroboscopic
 * states are the harmonic response x = Re(H a), v = Re(i Omega H a) with
 * H = (K - Omega^2 M + i Omega C)^-1 at t = kT (phase 0), K = [2 -1; -1 1],
 * C = 0.1 K; relative 1e-8 (the transient of 400 periods has decayed). */
static void harmonic_response(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  vi_sweep *sw = study(m, 400, 4);
  assert_int_equal(vi_sweep_set_param(sw, "stop.xs", 100.0), VI_OK);
  for (int k = 0; k < 15; k++) {
    double Om = 0.2 + 0.2 * k, got;
    int n, mm, ld, R;
    assert_int_equal(vi_sweep_set_param(sw, "forcing.omega", Om), VI_OK);
    assert_int_equal(vi_sweep_param(sw, "forcing.omega", &got), VI_OK);
    assert_true(got == Om);
    assert_int_equal(vi_sweep_iterate(sw), VI_OK);
    assert_int_equal(vi_sweep_period(sw, &n, &mm), VI_OK);
    assert_int_equal(n, 1);
    assert_int_equal(mm, 0);
    double complex h11 = 2 - Om * Om + I * Om * 0.2, h12 = -1 - I * Om * 0.1,
                   h22 = 1 - Om * Om + I * Om * 0.1, det = h11 * h22 - h12 * h12;
    double complex X1 = h22 * 0.5 / det, X2 = -h12 * 0.5 / det;
    double want[4] = {creal(X1), creal(X2), creal(I * Om * X1), creal(I * Om * X2)};
    double amp = cabs(X1) + cabs(X2);
    const double *z = vi_sweep_strobe(sw, &ld, &R);
    assert_int_equal(ld, 4);
    assert_int_equal(R, 4);
    for (int j = 0; j < R; j++)
      for (int i = 0; i < 4; i++)
        assert_close(z[j * ld + i], want[i], 1e-8 * amp * (1 + Om));
  }
  vi_sweep_destroy(&sw);
  vi_model_destroy(&m);
}

/* A damped linear motion out of reach of the stop settles to P(1,0) only:
 * the lightly damped oscillator of test_orbit (zeta = 0.002, omega = 1.25
 * Omega, x(0) = 0.5), whose free vibration makes 5 cycles in 4 periods,
 * repeats over 4 periods within the tolerance long before it does over
 * 1: recorded over 100 periods after a transient of 500 to 660 it read
 * P(4,0), from 680 on P(1,0).  Its change over one period still shrinks
 * over the record, so it is not periodic yet; after 800, P(1,0). */
static void lingering_not_p4(void **state)
{
  (void)state;
  double W = 1.0, w = 1.25 * W, zeta = 0.002;
  vi_model *m = vi_test_sdof(1.0, 2.0 * zeta * w, w * w, 0.1, 0.0, W, 10.0, 0.7);
  const int transient[2] = {500, 800}, want[2] = {0, 1};
  for (int c = 0; c < 2; c++) {
    vi_sweep *sw = study(m, transient[c], 100);
    int n, mm;
    assert_int_equal(vi_sweep_set_warm(sw, 0), VI_OK);
    assert_int_equal(vi_sweep_set_param(sw, "initial.x[1]", 0.5), VI_OK);
    assert_int_equal(vi_sweep_iterate(sw), VI_OK);
    assert_int_equal(vi_sweep_period(sw, &n, &mm), VI_OK);
    print_message("transient %d: P(%d,%d)\n", transient[c], n, mm);
    assert_int_equal(n, want[c]);
    assert_int_equal(mm, 0);
    vi_sweep_destroy(&sw);
  }
  vi_model_destroy(&m);
}

/* Up and down over 0.88..0.95, where the P(1,1) orbit is the only
 * attractor, agree value by value (warm start both ways). */
static void up_down_agree(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  vi_sweep *up = study(m, 500, 100), *down = study(m, 500, 100);
  double vu[8], pu[8], vd, pd;
  for (int k = 0; k < 8; k++) {
    assert_int_equal(vi_sweep_set_param(up, "forcing.omega", 0.88 + 0.01 * k), VI_OK);
    assert_int_equal(vi_sweep_iterate(up), VI_OK);
    last_impact(up, &vu[k], &pu[k]);
  }
  for (int k = 7; k >= 0; k--) {
    int n, mm;
    assert_int_equal(vi_sweep_set_param(down, "forcing.omega", 0.88 + 0.01 * k), VI_OK);
    assert_int_equal(vi_sweep_iterate(down), VI_OK);
    assert_int_equal(vi_sweep_period(down, &n, &mm), VI_OK);
    assert_int_equal(n, 1);
    assert_int_equal(mm, 1);
    last_impact(down, &vd, &pd);
    assert_close(vd, vu[k], 1e-9);
    assert_close(pd, pu[k], 1e-9);
  }
  vi_sweep_destroy(&up);
  vi_sweep_destroy(&down);
  vi_model_destroy(&m);
}

/* Warm start: point 2 starts where point 1 ended (same forcing phase), so
 * with Omega unchanged it continues the same trajectory: its states equal
 * one point with transient P + R + P, while a cold start (from rest) is
 * elsewhere.  Short runs, so the transient has not yet died out. */
static void warm_start(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  vi_sweep *warm = study(m, 5, 5), *longer = study(m, 15, 5);
  int ld, R;
  assert_int_equal(vi_sweep_iterate(warm), VI_OK);
  assert_int_equal(vi_sweep_iterate(warm), VI_OK);
  assert_int_equal(vi_sweep_iterate(longer), VI_OK);
  const double *w = vi_sweep_strobe(warm, &ld, &R), *l = vi_sweep_strobe(longer, &ld, &R);
  for (int i = 0; i < 5 * 4; i++) assert_close(w[i], l[i], 1e-10);
  double keep[20], far = 0;
  memcpy(keep, w, sizeof keep);
  assert_int_equal(vi_sweep_reset(warm), VI_OK); /* cold again */
  assert_int_equal(vi_sweep_iterate(warm), VI_OK);
  double cold[20];
  memcpy(cold, vi_sweep_strobe(warm, &ld, &R), sizeof cold);
  for (int i = 0; i < 5 * 4; i++) far = fmax(far, fabs(keep[i] - cold[i]));
  assert_true(far > 1e-3);
  /* without warm start every point is the cold one, bit for bit */
  assert_int_equal(vi_sweep_set_warm(warm, 0), VI_OK);
  assert_int_equal(vi_sweep_iterate(warm), VI_OK);
  assert_int_equal(vi_sweep_iterate(warm), VI_OK);
  assert_memory_equal(vi_sweep_strobe(warm, &ld, &R), cold, sizeof cold);
  vi_sweep_destroy(&warm);
  vi_sweep_destroy(&longer);
  vi_model_destroy(&m);
}

/* A warm sweep of the clearance of the stop the motion hits, on Fig. 2
 * with a stop it never reaches put first (stop 0 holds mass 1 above
 * x_1 = -5): stops[2].xs from 0.1 to 0.02, each point started from the
 * last, is the one-stop model's sweep of stops[1].xs to the integrator's
 * tolerance (rtol 1e-8: v_n to 1e-7): the same P(n, m) and impact
 * velocities, with the classification's scale taken over every stop. */
static void warm_second_stop(void **state)
{
  (void)state;
  vi_model *one = vi_test_fig2(), *f = vi_test_fig2();
  const double a[2] = {0.5, 0.0}, W[4] = {-1.0, 0.0, 0.0, 1.0},
               xs[2] = {5.0, 0.1}, r[2] = {0.5, 0.7};
  vi_model *two = vi_test_model_stops(2, vi_model_mass(f), vi_model_damping(f),
                                      vi_model_stiffness(f), 0.9, a, NULL, 2,
                                      W, xs, r);
  vi_model_destroy(&f);
  vi_sweep *s1 = study(one, 200, 8), *s2 = study(two, 200, 8);
  const double vals[3] = {0.1, 0.05, 0.02};
  for (int k = 0; k < 3; k++) {
    assert_int_equal(vi_sweep_set_param(s1, "stops[1].xs", vals[k]), VI_OK);
    assert_int_equal(vi_sweep_set_param(s2, "stops[2].xs", vals[k]), VI_OK);
    assert_int_equal(vi_sweep_iterate(s1), VI_OK);
    assert_int_equal(vi_sweep_iterate(s2), VI_OK);
    int n1, m1, n2, m2;
    assert_int_equal(vi_sweep_period(s1, &n1, &m1), VI_OK);
    assert_int_equal(vi_sweep_period(s2, &n2, &m2), VI_OK);
    assert_true(n1 >= 1 && m1 >= 1);
    assert_int_equal(n2, n1);
    assert_int_equal(m2, m1);
    int64_t c1, c2;
    const double *v1, *v2;
    assert_int_equal(vi_sweep_impacts(s1, &c1, NULL, NULL, &v1), VI_OK);
    assert_int_equal(vi_sweep_impacts(s2, &c2, NULL, NULL, &v2), VI_OK);
    assert_true(c1 == c2 && c1 > 0);
    for (int64_t i = 0; i < c1; i++) assert_close(v2[i], v1[i], 1e-7);
  }
  vi_sweep_destroy(&s1);
  vi_sweep_destroy(&s2);
  vi_model_destroy(&one);
  vi_model_destroy(&two);
}

/* The P(1,1) census at Omega = 0.9: one admissible orbit, stable, the one
 * the simulation settles on (v_N of the 40-digit reference). */
static void p11_census(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  vi_sweep *sw = study(m, 300, 10);
  const double *vn, *ph;
  const int *stable, *adm;
  int count, found = 0;
  double v, p;
  assert_int_equal(vi_sweep_set_orbits(sw, 360), VI_OK);
  assert_int_equal(vi_sweep_iterate(sw), VI_OK);
  assert_int_equal(vi_sweep_orbits(sw, &count, &vn, &ph, &stable, &adm), VI_OK);
  last_impact(sw, &v, &p);
  for (int i = 0; i < count; i++)
    if (adm[i]) {
      found++;
      assert_true(stable[i]);
      assert_close(vn[i], FIG2_VN, 1e-12);
      assert_close(vn[i], v, 1e-9);
      assert_close(ph[i], FIG2_PHASE, 1e-9);
    }
  assert_int_equal(found, 1);
  vi_sweep_destroy(&sw);
  vi_model_destroy(&m);
}

/* --lyapunov: the study's exponent is vi_orbit_lyapunov's from the
 * point's end state, bit for bit; on the stable P(1,1) orbit of Fig. 2 it
 * is log|mu_max| / T (Floquet multipliers of the orbit API), to 2e-3
 * relative over 400 periods (the tangent's initial alignment, a term
 * O(1) / (400 T), is what is left); without the option it is NaN. */
static void lyapunov_exponent(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  vi_sweep *sw = study(m, 300, 400);
  assert_true(isnan(vi_sweep_lyapunov(sw)));
  assert_int_equal(vi_sweep_set_lyapunov(sw, 1), VI_OK);
  assert_int_equal(vi_sweep_iterate(sw), VI_OK);
  double lam = vi_sweep_lyapunov(sw), T = 2 * M_PI / 0.9;
  /* the same from the end state by the orbit API */
  int ld, R;
  const double *z = vi_sweep_strobe(sw, &ld, &R);
  vi_orbit *o = NULL;
  double ref;
  assert_int_equal(vi_orbit_create(m, &o), VI_OK);
  assert_int_equal(vi_orbit_set_tolerances(o, 1e-8, 1e-10), VI_OK);
  assert_int_equal(vi_orbit_set_initial(o, z + (size_t)(R - 1) * ld, z + (size_t)(R - 1) * ld + 2), VI_OK);
  assert_int_equal(vi_orbit_lyapunov(o, 0.0, R, &ref, NULL), VI_OK);
  assert_true(lam == ref);
  vi_orbit_destroy(&o);
  /* Floquet: the multipliers of the orbit the orbit API finds */
  double re[4], im[4], mu = 0;
  assert_int_equal(vi_orbit_create(m, &o), VI_OK);
  assert_int_equal(vi_orbit_find(o), VI_OK);
  assert_int_equal(vi_orbit_multipliers(o, re, im), VI_OK);
  vi_orbit_destroy(&o);
  for (int i = 0; i < 4; i++) mu = fmax(mu, hypot(re[i], im[i]));
  assert_close(lam, log(mu) / T, 2e-3 * fabs(log(mu) / T));
  assert_true(lam < 0);
  vi_sweep_destroy(&sw);
  vi_model_destroy(&m);
}

typedef struct seen {
  int64_t calls, last;
  int stop_at;
} seen;

static int count_sticks(const vi_event *ev, void *user)
{
  if (ev->kind == VI_EVENT_STICK) (*(int *)user)++;
  return 0;
}

/* The constrained modes of a held set are shared by the points of a sweep
 * over Omega (built once, retuned per Omega): every point equals, bit for
 * bit, a study of its own value alone.  A 3-mass chain (Rayleigh damping,
 * the closed form of held phases) pressed onto the stop on mass 3 by a
 * preload sticks at every value, checked on a plain simulation. */
static void held_modes_shared(void **state)
{
  (void)state;
  const double M[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  const double K[9] = {2, -1, 0, -1, 2, -1, 0, -1, 1};
  double C[9];
  for (int i = 0; i < 9; i++) C[i] = 0.05 * K[i];
  const double a[3] = {0.6, 0, 0}, f0[3] = {0, 0, 0.3}, w[3] = {0, 0, 1};
  const double om[3] = {0.3, 0.45, 0.6};
  vi_model *m = vi_test_model(3, M, C, K, om[0], a, f0, w, 0.0, 0.5);
  for (int j = 0; j < 3; j++) { /* it sticks at each value */
    vi_model *mj = NULL;
    vi_sim *s = NULL;
    int sticks = 0;
    assert_int_equal(vi_model_copy(m, &mj), VI_OK);
    assert_int_equal(vi_model_set_param(mj, "forcing.omega", om[j]), VI_OK);
    assert_int_equal(vi_sim_create(mj, &s), VI_OK);
    assert_int_equal(vi_sim_set_method(s, VI_METHOD_EXACT), VI_OK);
    assert_int_equal(vi_sim_set_event_callback(s, count_sticks, &sticks, NULL), VI_OK);
    assert_int_equal(vi_sim_run(s, 8 * 2 * M_PI / om[j]), VI_OK);
    assert_true(sticks >= 1);
    vi_sim_destroy(&s);
    vi_model_destroy(&mj);
  }
  vi_sweep *all = study(m, 0, 8);
  assert_int_equal(vi_sweep_set_warm(all, 0), VI_OK);
  for (int j = 0; j < 3; j++) {
    vi_sweep *one = study(m, 0, 8);
    assert_int_equal(vi_sweep_set_param(all, "forcing.omega", om[j]), VI_OK);
    assert_int_equal(vi_sweep_set_param(one, "forcing.omega", om[j]), VI_OK);
    assert_int_equal(vi_sweep_iterate(all), VI_OK);
    assert_int_equal(vi_sweep_iterate(one), VI_OK);
    int64_t na, no;
    const double *ta, *va, *to, *vo;
    assert_int_equal(vi_sweep_impacts(all, &na, &ta, NULL, &va), VI_OK);
    assert_int_equal(vi_sweep_impacts(one, &no, &to, NULL, &vo), VI_OK);
    assert_true(na > 0);
    assert_int_equal(na, no);
    assert_memory_equal(ta, to, sizeof(double) * (size_t)na);
    assert_memory_equal(va, vo, sizeof(double) * (size_t)na);
    vi_sweep_destroy(&one);
  }
  vi_sweep_destroy(&all);
  vi_model_destroy(&m);
}

static int monitor(const vi_sweep *sw, int64_t point, int status, void *user)
{
  seen *s = user;
  int n, m;
  assert_int_equal(status, VI_OK);
  assert_int_equal(vi_sweep_period(sw, &n, &m), VI_OK);
  s->calls++;
  s->last = point;
  return point == s->stop_at;
}

/* The monitor sees every point, numbered from 1, and can stop the loop;
 * the study's model is a copy: the caller's is unchanged. */
static void monitor_and_copy(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  vi_sweep *sw = study(m, 2, 2);
  seen s = {0, 0, 3};
  assert_int_equal(vi_sweep_set_monitor(sw, monitor, &s, NULL), VI_OK);
  for (int k = 0; k < 2; k++) {
    assert_int_equal(vi_sweep_set_param(sw, "forcing.omega", 1.0 + 0.1 * k), VI_OK);
    assert_int_equal(vi_sweep_iterate(sw), VI_OK);
  }
  assert_int_equal(vi_sweep_iterate(sw), VI_STOPPED);
  assert_int_equal(s.calls, 3);
  assert_int_equal(s.last, 3);
  assert_true(vi_model_omega_forcing(m) == 0.9);
  assert_true(vi_model_omega_forcing(vi_sweep_model(sw)) == 1.1);
  vi_sweep_destroy(&sw);
  vi_model_destroy(&m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(fig2_p11),      cmocka_unit_test(harmonic_response),
      cmocka_unit_test(up_down_agree), cmocka_unit_test(warm_start),
      cmocka_unit_test(p11_census),    cmocka_unit_test(monitor_and_copy),
      cmocka_unit_test(lyapunov_exponent), cmocka_unit_test(warm_second_stop),
      cmocka_unit_test(held_modes_shared), cmocka_unit_test(lingering_not_p4),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
