/* test_exact.c - the exact method against closed forms: a ball on springs
 * from very soft (K -> 0, static offset 1e9 beyond the stop) to very stiff
 * (K = 1e8); its first contact against a brute-force scan of an
 * independently written closed form, on random states, with maxima that
 * overshoot the stop by 1e-12 between grid points; long free flights; the
 * hand-over to CVODE; cancellation. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vi_testutil.h"

/* ---- the bouncing ball on a spring ------------------------------------- */
/* x'' = -g - K x, floor x >= 0 (w = -1, x_s = 0), r = 0.8, leaving the
 * floor at V0 = 5.  A flight from the floor at speed V returns at speed V
 * after T(V) = (2 / om) atan(V om / g), om = sqrt(K) (2 V / g for K = 0):
 * x = c (1 - cos om t) + (V / om) sin om t with c = -g / K, zero again where
 * tan(om t / 2) = V om / g.  So impact k (k = 1, 2, ...) is at
 * t_k = sum_{i < k} T(V0 r^i) with approach speed V0 r^(k-1). */
static const double G = 9.81, V0 = 5.0, R = 0.8;

static vi_model *ball(double K)
{
  const double M = 1.0, C = 0.0, f0 = -G, w = -1.0;
  return vi_test_model(1, &M, &C, &K, 0.0, NULL, &f0, &w, 0.0, R);
}

static long double flight(double K, long double V)
{
  if (K == 0.0) return 2.0L * V / (long double)G;
  long double om = sqrtl((long double)K);
  return 2.0L / om * atanl(V * om / (long double)G);
}

static void check_ball(double K)
{
  vi_model *m = ball(K);
  vi_test_events ev = {0};
  const double x0 = 0.0, v0 = V0;
  vi_sim *s = vi_test_sim(m, VI_METHOD_EXACT, 1e-10, 1e-12, &x0, &v0, &ev);
  /* past the accumulation point of the rigid ball, 10 / (9.81 * 0.2) */
  double t_acc = 2.0 * V0 / (G * (1.0 - R)), t_end = 1.5 * t_acc;
  assert_int_equal(vi_sim_run(s, t_end), VI_OK);
  long double t = 0.0L, V = V0;
  double et = 0.0, ev_n = 0.0;
  int k = 0;
  /* the impacts resolved one by one, up to 40: the driver may sum the
   * rest of a chattering tail (its own business, tested elsewhere) */
  for (int i = 0; i < ev.count && k < 40; i++) {
    if (ev.kind[i] != VI_EVENT_IMPACT) break;
    t += flight(K, V);
    et = fmax(et, fabs(ev.t[i] - (double)t) / (double)t);
    /* speeds: an absolute error against the launch speed's round-off */
    ev_n = fmax(ev_n, fabs(ev.vn[i] - (double)V) / V0);
    V *= R;
    k++;
  }
  double tx, x, v;
  vi_sim_state(s, &tx, &x, &v);
  print_message("ball K = %g: %d events, first 40 impact times max rel err "
                "%.3g, speeds %.3g (%d checked); end x = %.3g, %s; %s\n", K, ev.count, et,
                ev_n, k, x, vi_sim_is_sticking(s) ? "sticking" : "free",
                vi_sim_method_note(s));
  assert_true(k >= 30);
  /* the closed form is exact: what is left is round-off, carried through
   * 40 impacts (each multiplies a speed error by r and adds eps) */
  assert_true(et <= 1e-12);
  assert_true(ev_n <= 1e-12);
  /* pressed on the floor by gravity after the accumulation: at rest on
   * it, never through it (issue 9: the mass ended at x = 40) */
  assert_true(x >= -1e-10);
  assert_true(x <= 1e-6);
  assert_true(vi_sim_is_sticking(s));
  assert_int_equal(vi_sim_stat(s, VI_STAT_HANDOVERS), 0);
  vi_sim_destroy(&s);
  vi_test_events_free(&ev);
  vi_model_destroy(&m);
}

static void test_ball_rigid(void **state) { (void)state; check_ball(0.0); }
static void test_ball_soft_1e8(void **state) { (void)state; check_ball(1e-8); }
static void test_ball_soft_1e7(void **state) { (void)state; check_ball(1e-7); }
static void test_ball_soft_1e6(void **state) { (void)state; check_ball(1e-6); }
static void test_ball_unit(void **state) { (void)state; check_ball(1.0); }
static void test_ball_stiff_1e8(void **state) { (void)state; check_ball(1e8); }

/* ---- an independent closed form ---------------------------------------- */
/* Proportionally damped, underdamped modes only, in long double and the
 * textbook form: q = P(t) + e^{-z w t} (A cos w_d t + B sin w_d t), P the
 * harmonic plus static particular solution.  (Fine for the moderate random
 * models below; it is not the library's relative formulation.) */
typedef struct ref {
  int n;
  long double xs, Om, amp, wmax, w[4], zw[4], wd[4], pa[4], pb[4], ps[4], A[4], B[4], psi[4];
} ref;

static void ref_init(ref *r, const vi_model *m, const double *x0, const double *v0)
{
  int n = vi_model_n(m);
  const double *om = vi_model_omega(m), *z = vi_model_zeta(m);
  const double *Fa = vi_model_modal_forcing_cos(m), *Fb = vi_model_modal_forcing_sin(m);
  const double *F0 = vi_model_modal_forcing_const(m), *psi = vi_model_modal_stop(m);
  double q0[4], qd0[4];
  assert_int_equal(vi_model_to_modal(m, x0, q0), VI_OK);
  assert_int_equal(vi_model_to_modal(m, v0, qd0), VI_OK);
  r->n = n;
  r->amp = r->wmax = 0.0L;
  r->xs = vi_model_clearance(m);
  r->Om = vi_model_omega_forcing(m);
  for (int j = 0; j < n; j++) {
    long double w = om[j], lam = w * w, d = 2.0L * z[j] * w, O = r->Om;
    assert_true(z[j] < 1.0 && w > 0.0);
    long double p = lam - O * O, sd = d * O, det = p * p + sd * sd;
    r->pa[j] = (p * Fa[j] - sd * Fb[j]) / det;
    r->pb[j] = (sd * Fa[j] + p * Fb[j]) / det;
    r->ps[j] = F0[j] / lam;
    r->w[j] = w;
    r->zw[j] = z[j] * w;
    r->wd[j] = w * sqrtl(1.0L - (long double)z[j] * z[j]);
    r->A[j] = q0[j] - (r->pa[j] + r->ps[j]);
    r->B[j] = (qd0[j] - O * r->pb[j] + r->zw[j] * r->A[j]) / r->wd[j];
    r->psi[j] = psi[j];
    r->amp += fabsl(r->psi[j]) * (fabsl(r->pa[j]) + fabsl(r->pb[j]) + fabsl(r->ps[j]) +
                                  fabsl(r->A[j]) + fabsl(r->B[j]));
    r->wmax = fmaxl(r->wmax, fmaxl(w, O));
  }
}

/* Round-off of g at time t in double: phases Omega t carry eps Omega t. */
static double gap_roundoff(const ref *r, double t)
{
  return 16.0 * 2.2e-16 * (double)(r->amp * (1.0L + r->wmax * t) + fabsl(r->xs));
}

/* g - x_s, g' and g'' at t */
static void ref_gap(const ref *r, long double t, long double *g, long double *gd,
                    long double *gdd)
{
  long double a = -r->xs, b = 0.0L, c2 = 0.0L, O = r->Om;
  long double c = cosl(O * t), s = sinl(O * t);
  for (int j = 0; j < r->n; j++) {
    long double e = expl(-r->zw[j] * t), cw = cosl(r->wd[j] * t), sw = sinl(r->wd[j] * t);
    long double u = e * (r->A[j] * cw + r->B[j] * sw);
    long double up = -r->zw[j] * u + e * r->wd[j] * (r->B[j] * cw - r->A[j] * sw);
    /* u'' = -2 z w u' - w^2 u */
    long double upp = -2.0L * r->zw[j] * up - r->w[j] * r->w[j] * u;
    a += r->psi[j] * (r->pa[j] * c + r->pb[j] * s + r->ps[j] + u);
    b += r->psi[j] * (O * (r->pb[j] * c - r->pa[j] * s) + up);
    c2 += r->psi[j] * (-O * O * (r->pa[j] * c + r->pb[j] * s) + upp);
  }
  *g = a;
  *gd = b;
  if (gdd) *gdd = c2;
}

/* g - x_s at t = i dt, i = 0..count, into gs: the scans that bracket the
 * roots and maxima the bisections then solve with ref_gap.  cos, sin and
 * e^{-z w t} advance by one step's rotation and decay (sinl of large
 * arguments cost 3 s of this file's 4), evaluated afresh every 64 samples:
 * 64 steps drift a few 1e-18, against brackets of 1e-12 at the finest. */
static void ref_scan(const ref *r, double dt, int count, long double *gs)
{
  long double st[5][4], stp[5][4]; /* cos, sin, e: forcing [0], modes [1..n] */
  long double h = dt;
  for (int i = 0; i <= count; i++) {
    if (i % 64 == 0) {
      long double t = i * h;
      st[0][0] = cosl(r->Om * t), st[0][1] = sinl(r->Om * t), st[0][2] = 1.0L;
      stp[0][0] = cosl(r->Om * h), stp[0][1] = sinl(r->Om * h), stp[0][2] = 1.0L;
      for (int j = 0; j < r->n; j++) {
        st[j + 1][0] = cosl(r->wd[j] * t), st[j + 1][1] = sinl(r->wd[j] * t);
        st[j + 1][2] = expl(-r->zw[j] * t);
        stp[j + 1][0] = cosl(r->wd[j] * h), stp[j + 1][1] = sinl(r->wd[j] * h);
        stp[j + 1][2] = expl(-r->zw[j] * h);
      }
    }
    long double a = -r->xs, c = st[0][0], s = st[0][1];
    for (int j = 0; j < r->n; j++) {
      const long double *q = st[j + 1];
      long double u = q[2] * (r->A[j] * q[0] + r->B[j] * q[1]);
      a += r->psi[j] * (r->pa[j] * c + r->pb[j] * s + r->ps[j] + u);
    }
    gs[i] = a;
    for (int k = 0; k <= r->n; k++) { /* to t + dt */
      long double c0 = st[k][0], s0 = st[k][1];
      st[k][0] = c0 * stp[k][0] - s0 * stp[k][1];
      st[k][1] = s0 * stp[k][0] + c0 * stp[k][1];
      st[k][2] *= stp[k][2];
    }
  }
}

static long double ref_root(const ref *r, long double lo, long double hi)
{
  long double g, gd;
  for (int it = 0; it < 200 && hi - lo > 1e-18L * (1.0L + hi); it++) {
    long double mid = 0.5L * (lo + hi);
    ref_gap(r, mid, &g, &gd, NULL);
    if (g < 0.0L) lo = mid; else hi = mid;
  }
  return 0.5L * (lo + hi);
}

static unsigned long long rng_state = 88172645463325252ULL;
static double urand(double a, double b)
{
  rng_state ^= rng_state << 13;
  rng_state ^= rng_state >> 7;
  rng_state ^= rng_state << 17;
  return a + (b - a) * (double)(rng_state >> 11) / 9007199254740992.0;
}

/* A random proportionally damped chain of n <= 3 masses, a random stop
 * direction, forcing a cos + b sin + f0; x_s is set by the caller. */
typedef struct rcase {
  int n;
  double M[9], C[9], K[9], a[3], b[3], f0[3], w[3], Om, x0[3], v0[3];
} rcase;

static void random_case(rcase *c)
{
  int n = c->n = 1 + (int)urand(0.0, 2.999);
  double mv[3] = {0}, kv[3] = {0}, cv[3] = {0}, al = urand(0.0, 0.05), be = urand(0.0, 0.03);
  for (int i = 0; i < n; i++) {
    mv[i] = urand(0.5, 2.0);
    kv[i] = urand(0.5, 2.0);
    cv[i] = be * kv[i];
  }
  assert_int_equal(vi_build_chain(n, mv, kv, cv, c->M, c->C, c->K, n), VI_OK);
  for (int i = 0; i < n; i++) c->C[i + i * n] += al * c->M[i + i * n];
  for (int i = 0; i < n; i++) {
    c->a[i] = urand(-0.5, 0.5);
    c->b[i] = urand(-0.5, 0.5);
    c->f0[i] = urand(-0.1, 0.1);
    c->w[i] = n > 1 && urand(0, 1) < 0.5 ? urand(-1.0, 1.0) : (i == n - 1);
    c->x0[i] = urand(-0.5, 0.5);
    c->v0[i] = urand(-0.5, 0.5);
  }
  c->Om = urand(0.3, 2.0);
}

static vi_model *case_model(const rcase *c, double xs)
{
  vi_model *m = NULL;
  int n = c->n;
  assert_int_equal(vi_model_create(n, &m), VI_OK);
  assert_int_equal(vi_model_set_mass(m, c->M, n), VI_OK);
  assert_int_equal(vi_model_set_damping(m, c->C, n), VI_OK);
  assert_int_equal(vi_model_set_stiffness(m, c->K, n), VI_OK);
  assert_int_equal(vi_model_set_forcing(m, c->Om, c->a, c->b, c->f0), VI_OK);
  assert_int_equal(vi_model_set_stop(m, c->w, xs, 0.7), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  return m;
}

static int first_event(const vi_event *ev, void *u)
{
  double *t = u;
  if (ev->kind == VI_EVENT_IMPACT || ev->kind == VI_EVENT_STICK) {
    *t = ev->t;
    return 1;
  }
  return 0;
}

/* First contact of the exact method from (x0, v0) over [0, t_end]. */
static double exact_first(const vi_model *m, const rcase *c, double t_end)
{
  vi_sim *s = NULL;
  double tc = HUGE_VAL;
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_sim_set_method(s, VI_METHOD_EXACT), VI_OK);
  assert_int_equal(vi_sim_set_tolerances(s, 1e-12, 1e-14), VI_OK);
  assert_int_equal(vi_sim_set_initial(s, 0.0, c->x0, c->v0), VI_OK);
  assert_int_equal(vi_sim_set_event_callback(s, first_event, &tc, NULL), VI_OK);
  int st = vi_sim_run(s, t_end);
  assert_true(st == VI_OK || st == VI_STOPPED);
  vi_sim_destroy(&s);
  return tc;
}

#define NSAMP 6000
/* Random states, stop at a random level below the reach of the motion:
 * the exact method's first contact is a root of the independent closed
 * form, and no sample of a fine brute-force scan before it reaches the
 * stop. */
static void test_first_contact_random(void **state)
{
  (void)state;
  int cases = 0, earlier = 0;
  double worst = 0.0;
  long double *gs = malloc(sizeof(long double) * (NSAMP + 1));
  assert_non_null(gs);
  while (cases < 150) {
    rcase c;
    random_case(&c);
    vi_model *m = case_model(&c, 1e3);
    ref r;
    ref_init(&r, m, c.x0, c.v0);
    double T = 40.0, dt = T / NSAMP;
    long double g0 = 0.0L, gmax = -1e30L, gd, xs0 = r.xs;
    ref_scan(&r, dt, NSAMP, gs);
    for (int i = 0; i <= NSAMP; i++) gmax = fmaxl(gmax, gs[i]);
    g0 = gs[0];
    vi_model_destroy(&m);
    if (gmax - g0 < 1e-2L) continue;
    /* the stop between the start and the highest point */
    double xs = (double)(r.xs + g0 + urand(0.05, 0.95) * (gmax - g0));
    m = case_model(&c, xs);
    ref_init(&r, m, c.x0, c.v0);
    int ib = -1; /* the same samples, the stop moved from xs0 to r.xs */
    for (int i = 0; i <= NSAMP && ib < 0; i++)
      if (gs[i] + (xs0 - r.xs) >= 0.0L) ib = i;
    assert_true(ib > 0);
    long double tref = ref_root(&r, (ib - 1) * dt, ib * dt), g, gdd;
    double tc = exact_first(m, &c, T);
    ref_gap(&r, tc, &g, &gd, &gdd);
    /* on the stop, to the round-off of g (terms of order 1) */
    assert_true(tc < T);
    assert_true(fabsl(g) <= gap_roundoff(&r, tc));
    if (tc < (double)tref - 1e-9) {
      /* a grazing contact between the scan's samples: only if genuine */
      earlier++;
      assert_true(tc > (ib - 1) * dt - dt);
    } else {
      ref_gap(&r, tref, &g, &gd, NULL);
      double err = fabs(tc - (double)tref);
      double tol = gap_roundoff(&r, (double)tref) / fabsl(gd) + 4e-16 * T;
      worst = fmax(worst, err / tol);
      assert_true(err <= tol);
    }
    vi_model_destroy(&m);
    cases++;
  }
  print_message("random first contacts: %d cases, %d grazing contacts between "
                "scan samples, worst error / tolerance %.3g\n", cases, earlier, worst);
  free(gs);
}

/* A maximum of the gap exceeding the stop by eps = 1e-12 ... 1e-4 between
 * grid points: the exact method must stop at its rising crossing,
 * t_m - sqrt(2 eps / |g''|) to leading order, computed here by bisection of
 * the independent closed form. */
static void test_first_contact_grazing(void **state)
{
  (void)state;
  int cases = 0;
  double worst = 0.0;
  long double *gs = malloc(sizeof(long double) * (NSAMP + 1));
  assert_non_null(gs);
  while (cases < 150) {
    rcase c;
    random_case(&c);
    vi_model *m = case_model(&c, 1e3);
    ref r;
    ref_init(&r, m, c.x0, c.v0);
    double T = 40.0, dt = T / NSAMP;
    long double gd, gdd;
    int im = 0;
    ref_scan(&r, dt, NSAMP, gs);
    for (int i = 0; i <= NSAMP; i++)
      if (gs[i] > gs[im]) im = i;
    vi_model_destroy(&m);
    if (im < 2 || im > NSAMP - 2 || gs[im] - gs[0] < 1e-2L) continue;
    /* the maximum to round-off: bisection on g' */
    long double lo = (im - 1) * dt, hi = (im + 1) * dt, gm;
    for (int it = 0; it < 200; it++) {
      long double mid = 0.5L * (lo + hi), g;
      ref_gap(&r, mid, &g, &gd, NULL);
      if (gd > 0.0L) lo = mid; else hi = mid;
    }
    long double tm = 0.5L * (lo + hi);
    ref_gap(&r, tm, &gm, &gd, &gdd);
    double eps = pow(10.0, -12.0 + 2.0 * (cases % 5));
    /* no other point of the scan within eps of the maximum before it */
    int clash = 0;
    for (int i = 0; i < im - 1; i++) clash |= gs[i] >= gm - 2.0L * eps;
    if (clash || gdd >= 0.0L) continue;
    double xs = (double)(r.xs + gm) - eps;
    m = case_model(&c, xs);
    ref_init(&r, m, c.x0, c.v0);
    ref_gap(&r, tm, &gm, &gd, &gdd);
    if (!(gm > 0.25L * eps)) { /* x_s rounded away the overshoot */
      vi_model_destroy(&m);
      continue;
    }
    /* rising crossing: in [tm - 4 sqrt(2 eps / |g''|) - dt, tm] */
    long double half = sqrtl(2.0L * gm / fabsl(gdd));
    long double a = tm - 4.0L * half - dt, g;
    ref_gap(&r, a, &g, &gd, NULL);
    assert_true(g < 0.0L);
    long double tref = ref_root(&r, a, tm);
    double tc = exact_first(m, &c, T);
    ref_gap(&r, tref, &g, &gd, NULL);
    /* a crossing time carries the gap's round-off divided by g' */
    double err = fabs(tc - (double)tref);
    double tol = gap_roundoff(&r, (double)tref) / fabsl(gd) + 4e-16 * T;
    if (!(err <= tol))
      print_error("eps %g: t_m %.17Lg, contact %.17g, expected %.17Lg (g' = %.3Lg)\n",
                  eps, tm, tc, tref, gd);
    assert_true(err <= tol);
    worst = fmax(worst, err / tol);
    if (getenv("VI_TEST_VERBOSE")) {
      long double g2, gd2;
      ref_gap(&r, tc, &g2, &gd2, NULL);
      print_message("eps %g n %d err*g' %.3g g' %.3Lg g(tc) %.3Lg tc %.17g tm %.17Lg\n", eps, c.n, (double)(err * fabsl(gd)), gd, g2, tc, tm);
    }
    vi_model_destroy(&m);
    cases++;
  }
  print_message("grazing maxima (overshoot 1e-12 .. 1e-4): %d cases found, "
                "worst error / tolerance %.3g\n", cases, worst);
  free(gs);
}

/* ---- long free flight: the recurrence stays on the closed form ---------- */
typedef struct flight_chk { ref *r; double err; int n; } flight_chk;

static int flight_sample(double t, int n, const double *x, const double *v, void *u)
{
  (void)n;
  (void)v;
  flight_chk *c = u;
  /* stop far away: g here is the position along w, minus x_s */
  long double g, gd;
  ref_gap(c->r, t, &g, &gd, NULL);
  c->err = fmax(c->err, fabs((double)(g + c->r->xs) - x[1]));
  c->n++;
  return 0;
}

static void test_long_free_flight(void **state)
{
  (void)state;
  const double M[4] = {1, 0, 0, 1}, K[4] = {2, -1, -1, 1};
  const double C[4] = {0.002, -0.001, -0.001, 0.001}; /* 0.001 K */
  const double a[2] = {0.5, 0.0}, w[2] = {0.0, 1.0}, x0[2] = {0.2, -0.1},
               v0[2] = {0.0, 0.3};
  vi_model *m = vi_test_model(2, M, C, K, 0.9, a, NULL, w, 100.0, 0.7);
  ref r;
  ref_init(&r, m, x0, v0);
  flight_chk c = {&r, 0.0, 0};
  vi_sim *s = vi_test_sim(m, VI_METHOD_EXACT, 1e-12, 1e-14, x0, v0, NULL);
  assert_int_equal(vi_sim_set_sampling(s, 7.0, flight_sample, &c, NULL), VI_OK);
  assert_int_equal(vi_sim_run(s, 7e4), VI_OK);
  double t, x[2], v[2];
  vi_sim_state(s, &t, x, v);
  long double g, gd;
  ref_gap(&r, t, &g, &gd, NULL);
  print_message("free flight to t = 7e4 (%lld steps): samples max err %.3g, "
                "end %.3g\n", (long long)vi_sim_stat(s, VI_STAT_STEPS),
                c.err, fabs((double)(g + r.xs) - x[1]));
  /* ~1e4 periods: phase round-off eps * Omega t ~ 1e-11 is the floor */
  assert_true(c.err <= 1e-10);
  assert_true(fabs((double)(g + r.xs) - x[1]) <= 1e-10);
  assert_int_equal(c.n, 10001);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
}

/* ---- a particular solution that the closed form cannot cancel ---------- */
/* Undamped but for 2e-11, forced at resonance from rest: the harmonic
 * particular solution is 0.1 / 2e-11 = 5e9 against a motion of order one. */
static void test_handover_near_resonance(void **state)
{
  (void)state;
  vi_model *m = vi_test_sdof(1.0, 2e-11, 1.0, 0.1, 0.0, 1.0, 1.0, 0.8);
  vi_test_events ev = {0};
  vi_sim *s = vi_test_sim(m, VI_METHOD_EXACT, 1e-10, 1e-12, NULL, NULL, &ev);
  assert_int_equal(vi_sim_run(s, 100.0), VI_OK);
  print_message("near resonance: %s; %d impacts\n", vi_sim_method_note(s), ev.count);
  assert_int_equal(vi_sim_stat(s, VI_STAT_HANDOVERS), 1);
  assert_non_null(strstr(vi_sim_method_note(s), "adams"));
  /* x = (0.1 / 2) t sin t reaches 1 first near t = 20.1 */
  assert_true(ev.count > 0);
  assert_true(ev.t[0] > 19.0 && ev.t[0] < 21.5);
  vi_sim_destroy(&s);
  vi_test_events_free(&ev);
  vi_model_destroy(&m);
  /* but an ordinary forced response from rest, on a stop at the origin
   * and at the tightest tolerance, stays on the closed form */
  const double a[2] = {0.5, 0.0};
  m = vi_test_chain(2, 1.0, 1.0, 0.1, 0.0, 0.7, 0.9, a);
  s = vi_test_sim(m, VI_METHOD_EXACT, 1e-14, 1e-16, NULL, NULL, NULL);
  assert_int_equal(vi_sim_run(s, 100.0), VI_OK);
  assert_int_equal(vi_sim_stat(s, VI_STAT_HANDOVERS), 0);
  assert_true(vi_sim_stat(s, VI_STAT_IMPACTS) > 5);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
}

/* ---- cancellation inside a long step ----------------------------------- */
static int cancel_after(void *u)
{
  int *k = u;
  return ++*k > 5;
}

static void test_cancel(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  vi_sim *s = vi_test_sim(m, VI_METHOD_EXACT, 1e-10, 1e-12, NULL, NULL, NULL);
  int k = 0;
  assert_int_equal(vi_sim_set_cancel(s, cancel_after, &k, NULL), VI_OK);
  assert_int_equal(vi_sim_run(s, 1e6), VI_CANCELLED);
  double t, x[2], v[2];
  vi_sim_state(s, &t, x, v);
  assert_true(t > 0.0 && t < 1e6);
  assert_true(isfinite(x[0]) && isfinite(v[1]) && x[1] <= 0.1 + 1e-12);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
}

/* ---- a bounce in modes ------------------------------------------------- */
/* A 6-mass chain, M = diag(1..6), C = 0.02 K, forced on mass 1, against an
 * oblique stop w = (0, 0, 0.3, 0, 0, 1): the exact method takes a bounce in
 * modal coordinates (q' -= P psi, q -= g psi / G), and builds the physical
 * state only for whoever reads it.  (i) The motion is bit for bit the same
 * with and without the event's states and with the ledger on; (ii) the
 * state just after the first impact, read back from the modes, obeys
 * Newton's law (w.v+ = -r w.v-, v+ - v- along M^-1 w) and lies on the
 * stop, to round-off; (iii) each impact takes the kinetic energy it
 * reports, 1/2 (v-.M v- - v+.M v+) = IE, to 1e-12. */
enum { MB_N = 6 };
static vi_model *mb_model(void)
{
  double M[MB_N * MB_N] = {0}, K[MB_N * MB_N] = {0}, C[MB_N * MB_N];
  double a[MB_N] = {1.0}, W[MB_N] = {0, 0, 0.3, 0, 0, 1};
  double xs = 0.02, r = 0.8;
  for (int i = 0; i < MB_N; i++) {
    M[i + i * MB_N] = 1.0 + i;
    K[i + i * MB_N] = i + 1 < MB_N ? 2.0 : 1.0;
    if (i + 1 < MB_N) K[i + 1 + i * MB_N] = K[i + (i + 1) * MB_N] = -1.0;
  }
  for (int i = 0; i < MB_N * MB_N; i++) C[i] = 0.02 * K[i];
  return vi_test_model_stops(MB_N, M, C, K, 0.4, a, NULL, 1, W, &xs, &r);
}

static vi_sim *mb_run(const vi_model *m, int states, int ledger,
                      vi_test_rec *ev, double t_end, double *z)
{
  vi_sim *s = vi_test_sim_stops(m, VI_METHOD_EXACT, 1e-10, 1e-12, 0.0, NULL,
                                NULL, ev);
  assert_int_equal(vi_sim_set_event_states(s, states), VI_OK);
  assert_int_equal(vi_sim_enable_ledger(s, ledger), VI_OK);
  assert_int_equal(vi_sim_run(s, t_end), VI_OK);
  double t;
  assert_int_equal(vi_sim_state(s, &t, z, z + MB_N), VI_OK);
  return s;
}

static void test_modal_bounce(void **state)
{
  (void)state;
  vi_model *m = mb_model();
  const double W[MB_N] = {0, 0, 0.3, 0, 0, 1}, r = 0.8;
  double za[2 * MB_N], zb[2 * MB_N], zc[2 * MB_N], t_end = 40.0 * 2.0 * M_PI / 0.4;
  vi_test_rec a = {0}, b = {0}, c = {0};
  vi_sim *sa = mb_run(m, 1, 0, &a, t_end, za);
  vi_sim *sb = mb_run(m, 0, 0, &b, t_end, zb);
  vi_sim *sc = mb_run(m, 0, 1, &c, t_end, zc);
  /* (i) */
  print_message("modal bounce: %d impacts\n", a.count);
  assert_true(a.count > 25);
  assert_true(vi_sim_stat(sa, VI_STAT_IMPACTS) == a.count);
  assert_int_equal(b.count, a.count);
  assert_int_equal(c.count, a.count);
  assert_memory_equal(b.t, a.t, sizeof(double) * a.count);
  assert_memory_equal(b.vn, a.vn, sizeof(double) * a.count);
  assert_memory_equal(c.t, a.t, sizeof(double) * a.count);
  assert_memory_equal(zb, za, sizeof za);
  assert_memory_equal(zc, za, sizeof za);
  assert_true(isnan(b.x[0]) && isnan(b.vm[0]) && isnan(b.vp[0]));
  /* (iii) */
  for (int i = 0; i < a.count; i++) {
    const double *vm = a.vm + (size_t)i * MB_N, *vp = a.vp + (size_t)i * MB_N;
    double ke = 0.0;
    for (int j = 0; j < MB_N; j++) ke += 0.5 * (1.0 + j) * (vm[j] * vm[j] - vp[j] * vp[j]);
    assert_close(ke, a.ie[i], 1e-12 * fmax(a.ie[i], 1e-3));
  }
  /* (ii): stopped after the step of the first impact, the state is the
   * modes' own, read back through Psi */
  vi_sim_destroy(&sb);
  sb = vi_test_sim_stops(m, VI_METHOD_EXACT, 1e-10, 1e-12, 0.0, NULL, NULL,
                         NULL);
  assert_int_equal(vi_sim_set_event_states(sb, 0), VI_OK);
  int kind;
  assert_int_equal(vi_sim_run_to_event(sb, t_end, &kind), VI_OK);
  assert_int_equal(kind, VI_EVENT_IMPACT);
  double t, x[MB_N], v[MB_N], wx = 0.0, wv = 0.0, vn = a.vn[0];
  assert_int_equal(vi_sim_state(sb, &t, x, v), VI_OK);
  assert_true(t == a.t[0]);
  for (int j = 0; j < MB_N; j++) {
    wx += W[j] * x[j];
    wv += W[j] * v[j];
    /* v+ - v- = -P M^-1 w: zero off the stop's coordinates */
    if (W[j] == 0.0) assert_close(v[j], a.vm[j], 1e-14 * vn);
    assert_close(v[j], a.vp[j], 1e-14 * vn);
    assert_close(x[j], a.x[j], 1e-14);
  }
  assert_close(wv, -r * vn, 1e-14 * vn);
  assert_close(wx, 0.02, 1e-15);
  vi_test_rec_free(&a);
  vi_test_rec_free(&b);
  vi_test_rec_free(&c);
  vi_sim_destroy(&sa);
  vi_sim_destroy(&sb);
  vi_sim_destroy(&sc);
  vi_model_destroy(&m);
}

/* ---- non-proportional damping on a very soft structure ----------------- */
/* The 3-DOF non-proportional fixture with K scaled by 1e-6 and a constant
 * push of 0.5 on mass 3 towards the stop: the static offset f0 / K is ~1e6
 * beyond the stop.  The impacts must agree with Adams (the first-order
 * closed form hands over to CVODE where it would cancel that offset). */
static void test_nonproportional_soft(void **state)
{
  (void)state;
  double K[9];
  const double f0[3] = {0.0, 0.0, 0.5}, w[3] = {0.2, -0.5, 1.0};
  for (int i = 0; i < 9; i++) K[i] = 1e-6 * vi_test_np3_K[i];
  vi_model *m = vi_test_model(3, vi_test_np3_M, vi_test_np3_C, K, 0.8,
                              vi_test_np3_a, f0, w, 0.05, 0.6);
  vi_test_events ex = {0}, ad = {0};
  int st = vi_test_run(m, VI_METHOD_EXACT, 1e-12, 1e-14, NULL, NULL, 60.0, &ex);
  assert_int_equal(vi_test_run(m, VI_METHOD_ADAMS, 1e-12, 1e-14, NULL, NULL, 60.0, &ad), VI_OK);
  print_message("non-proportional soft: exact status %d, %d events; adams %d events\n",
                st, ex.count, ad.count);
  assert_int_equal(st, VI_OK);
  assert_true(ad.count > 5);
  assert_int_equal(ex.count, ad.count);
  for (int i = 0; i < ad.count; i++) assert_close(ex.t[i], ad.t[i], 1e-8);
  vi_test_events_free(&ex);
  vi_test_events_free(&ad);
  vi_model_destroy(&m);
}

/* The same soft structure with the stop it hits second: stop 0, -x1 <=
 * 1e8, is never reached and its gap sees the offset as small against its
 * clearance, so only stop 1's gap would cancel it.  Every stop's scale is
 * looked at: the exact method still hands over and agrees with Adams. */
static void test_nonproportional_soft_stop1(void **state)
{
  (void)state;
  double K[9];
  const double f0[3] = {0.0, 0.0, 0.5}, w[3] = {0.2, -0.5, 1.0};
  const double w0[3] = {-1.0, 0.0, 0.0};
  for (int i = 0; i < 9; i++) K[i] = 1e-6 * vi_test_np3_K[i];
  vi_model *m = NULL;
  assert_int_equal(vi_model_create(3, &m), VI_OK);
  assert_int_equal(vi_model_set_mass(m, vi_test_np3_M, 3), VI_OK);
  assert_int_equal(vi_model_set_damping(m, vi_test_np3_C, 3), VI_OK);
  assert_int_equal(vi_model_set_stiffness(m, K, 3), VI_OK);
  assert_int_equal(vi_model_set_forcing(m, 0.8, vi_test_np3_a, NULL, f0), VI_OK);
  assert_int_equal(vi_model_set_stop(m, w0, 1e8, 0.6), VI_OK);
  assert_int_equal(vi_model_add_stop(m, w, 0.05, 0.6), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  vi_test_events ex = {0}, ad = {0};
  vi_sim *s = vi_test_sim(m, VI_METHOD_EXACT, 1e-12, 1e-14, NULL, NULL, &ex);
  int st = vi_sim_run(s, 60.0);
  print_message("non-proportional soft, stop 1: exact status %d (%s), %d "
                "events\n", st, vi_sim_method_note(s), ex.count);
  assert_int_equal(st, VI_OK);
  assert_non_null(strstr(vi_sim_method_note(s), "stop 2's gap"));
  vi_sim_destroy(&s);
  assert_int_equal(vi_test_run(m, VI_METHOD_ADAMS, 1e-12, 1e-14, NULL, NULL, 60.0, &ad), VI_OK);
  assert_true(ad.count > 5);
  assert_int_equal(ex.count, ad.count);
  for (int i = 0; i < ad.count; i++) assert_close(ex.t[i], ad.t[i], 1e-8);
  vi_test_events_free(&ex);
  vi_test_events_free(&ad);
  vi_model_destroy(&m);
}

/* A free-free chain of three masses (a rigid-body mode, K singular) falling
 * under gravity on a floor under mass 1, C = 0.01 K: the exact method
 * against Adams at tight tolerances, impact for impact. */
static void test_free_free_chain_gravity(void **state)
{
  (void)state;
  const double M[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  const double K[9] = {1, -1, 0, -1, 2, -1, 0, -1, 1};
  double C[9];
  for (int i = 0; i < 9; i++) C[i] = 0.01 * K[i];
  const double f0[3] = {-G, -G, -G}, w[3] = {-1, 0, 0};
  const double x0[3] = {0.0, 1.0, 2.0}, v0[3] = {5.0, 5.5, 4.0};
  vi_model *m = vi_test_model(3, M, C, K, 1.0, NULL, f0, w, 0.0, 0.8);
  assert_true(vi_model_is_proportional(m));
  vi_test_events ex = {0}, ad = {0};
  assert_int_equal(vi_test_run(m, VI_METHOD_EXACT, 1e-12, 1e-14, x0, v0, 6.0, &ex), VI_OK);
  assert_int_equal(vi_test_run(m, VI_METHOD_ADAMS, 1e-12, 1e-14, x0, v0, 6.0, &ad), VI_OK);
  /* the impacts both resolved one by one (the driver may sum a chattering
   * tail earlier for one method than for the other) */
  int nc = 0;
  while (nc < 20 && nc < ex.count && nc < ad.count && ex.kind[nc] == VI_EVENT_IMPACT &&
         ad.kind[nc] == VI_EVENT_IMPACT)
    nc++;
  double et = 0.0;
  if (getenv("VI_TEST_VERBOSE"))
    for (int i = 0; i < ex.count || i < ad.count; i++)
      print_message("%d: exact %d %.12g %.3g | adams %d %.12g %.3g\n", i,
                    i < ex.count ? ex.kind[i] : -1, i < ex.count ? ex.t[i] : 0.0,
                    i < ex.count ? ex.vn[i] : 0.0, i < ad.count ? ad.kind[i] : -1,
                    i < ad.count ? ad.t[i] : 0.0, i < ad.count ? ad.vn[i] : 0.0);
  for (int i = 0; i < nc && i < ad.count; i++) et = fmax(et, fabs(ex.t[i] - ad.t[i]));
  print_message("free-free chain under gravity: %d / %d events, first %d times "
                "agree to %.3g\n", ex.count, ad.count, nc, et);
  assert_true(nc >= 10);
  /* Adams at rtol 1e-12 locates impacts to ~1e-10 here */
  assert_true(et <= 1e-8);
  vi_test_events_free(&ex);
  vi_test_events_free(&ad);
  vi_model_destroy(&m);
}

/* Two unit masses, springs 1 (ground-mass 1) and 1 (between), a load 1
 * pressing mass 2 on a stop at x_2 = 0 (so the stop coordinate itself is 0
 * at every contact while mass 1 swings): each rebound must start a new
 * flight, never a second contact at the same instant (a round-off of g
 * measured against x_2 alone once read as one). */
static void test_two_mass_stop_at_origin(void **state)
{
  (void)state;
  const double M[4] = {1, 0, 0, 1}, K[4] = {2, -1, -1, 1}, C[4] = {0, 0, 0, 0};
  const double f0[2] = {0, 1.0}, w[2] = {0, 1}, x0[2] = {0, 0}, v0[2] = {2.0, -0.3};
  vi_model *m = vi_test_model(2, M, C, K, 0.0, NULL, f0, w, 0.0, 0.8);
  vi_test_events ex = {0}, ad = {0};
  assert_int_equal(vi_test_run(m, VI_METHOD_EXACT, 1e-12, 1e-14, x0, v0, 1.85, &ex), VI_OK);
  assert_int_equal(vi_test_run(m, VI_METHOD_ADAMS, 1e-12, 1e-14, x0, v0, 1.85, &ad), VI_OK);
  double et = 0.0;
  for (int i = 0; i < ex.count && i < ad.count; i++) {
    assert_int_equal(ex.kind[i], VI_EVENT_IMPACT);
    assert_true(ex.vn[i] > 0.0);
    et = fmax(et, fabs(ex.t[i] - ad.t[i]));
  }
  print_message("two masses, stop at the origin: %d / %d impacts to t = 1.85, "
                "times agree to %.3g\n", ex.count, ad.count, et);
  assert_int_equal(ex.count, ad.count);
  assert_true(ex.count >= 15);
  assert_true(et <= 1e-9);
  vi_test_events_free(&ex);
  vi_test_events_free(&ad);
  vi_model_destroy(&m);
}

/* A free mass at rest on the stop (no force at all): g = 0 for ever.  No
 * contact, no hang: the search must not bisect a motion that lies on the
 * stop within round-off. */
static void test_resting_on_stop(void **state)
{
  (void)state;
  vi_model *m = vi_test_sdof(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.8);
  vi_test_events ev = {0};
  assert_int_equal(vi_test_run(m, VI_METHOD_EXACT, 1e-10, 1e-12, NULL, NULL, 100.0, &ev),
                   VI_OK);
  assert_int_equal(ev.count, 0);
  vi_test_events_free(&ev);
  vi_model_destroy(&m);
}

/* ---- the relative closed form of one mode, in every regime ------------- */
/* x'' + d x' + lambda x = F from (x0, v0) after tau, by the exponential of
 * the augmented matrix [[0, 1, 0], [-lambda, -d, F], [0, 0, 0]] tau: Taylor
 * series in long double after scaling by 2^-s, then s squarings.  An
 * independent way to the same numbers. */
static void expm_ref(double lam, double d, double F, double x0, double v0,
                     double tau, long double *x, long double *v)
{
  /* balanced: (x, y = v / sg), sg = sqrt(lambda) for a stiff mode */
  long double sg = lam > 1.0 ? sqrtl((long double)lam) : 1.0L, T0 = tau;
  long double A[9] = {0, -lam / sg * T0, 0, sg * T0, -d * T0, 0,
                      0, F / sg * T0, 0}; /* column-major */
  long double nrm = fabsl(A[1]) + fabsl(A[3]) + fabsl(A[4]) + fabsl(A[7]);
  int sq = 0;
  while (nrm > 0.5L) {
    nrm *= 0.5L;
    sq++;
  }
  for (int i = 0; i < 9; i++) A[i] = ldexpl(A[i], -sq);
  long double E[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, T[9], P[9];
  memcpy(T, E, sizeof T);
  for (int k = 1; k < 30; k++) { /* T = T A / k; E += T */
    for (int c = 0; c < 3; c++)
      for (int r = 0; r < 3; r++) {
        long double acc = 0.0L;
        for (int j = 0; j < 3; j++) acc += T[r + 3 * j] * A[j + 3 * c];
        P[r + 3 * c] = acc / k;
      }
    memcpy(T, P, sizeof T);
    for (int i = 0; i < 9; i++) E[i] += T[i];
  }
  for (int q = 0; q < sq; q++) {
    for (int c = 0; c < 3; c++)
      for (int r = 0; r < 3; r++) {
        long double acc = 0.0L;
        for (int j = 0; j < 3; j++) acc += E[r + 3 * j] * E[j + 3 * c];
        P[r + 3 * c] = acc;
      }
    memcpy(E, P, sizeof E);
  }
  *x = E[0] * x0 + E[3] * (v0 / sg) + E[6];
  *v = sg * (E[1] * x0 + E[4] * (v0 / sg) + E[7]);
}

static void test_mode_regimes(void **state)
{
  (void)state;
  /* lambda, d, tau: Taylor branch; underdamped; soft (static offset 1e6)
   * short and long; critical, just over and just under; overdamped with
   * small and large lambda tau^2; rigid damped and free; stiff */
  const double cs[][3] = {{1, 0.1, 0.5},   {1, 0.1, 3},      {1e-6, 0, 1},
                          {1e-6, 0, 3000}, {1e-8, 0.01, 50}, {1, 2, 3},
                          {1, 2.0000001, 3}, {1, 1.9999999, 3}, {1e-4, 5, 2},
                          {1, 5, 2},       {0, 0.5, 10},     {0, 0, 10},
                          {1e8, 0, 1e-3},  {1e8, 1e3, 1e-3}, {4, 4, 0.7},
                          {0.3, 1.1, 1.2}};
  double worst = 0.0;
  for (size_t i = 0; i < sizeof cs / sizeof cs[0]; i++) {
    /* the time step as the flow sees it: (2 + tau) - 2, exact in double */
    double lam = cs[i][0], d = cs[i][1], t1 = 2.0 + cs[i][2], tau = t1 - 2.0, F = -9.81;
    const double M = 1.0, w = 1.0, x0 = 0.3, v0 = -0.7;
    vi_model *m = vi_test_model(1, &M, &d, &lam, 1.0, NULL, &F, &w, 1e12, 0.5);
    double q, qd;
    assert_int_equal(vi_flow_modal(m, 2.0, &x0, &v0, t1, &q, &qd), VI_OK);
    long double xr, vr;
    expm_ref(lam, d, F, x0, v0, tau, &xr, &vr);
    /* relative to the size of the motion: position, and speed times tau */
    long double sc = fabsl(xr) + fabsl(x0) + tau * (fabsl(vr) + fabsl(v0)) + fabsl(F) * tau * tau;
    double ex = (double)(fabsl(q - xr) / sc), ev = (double)(fabsl(qd - vr) * tau / sc);
    if (!(ex <= 1e-14 && ev <= 1e-14))
      print_error("lambda %g d %g tau %g: x %.17g vs %.17Lg, v %.17g vs %.17Lg\n",
                  lam, d, tau, q, xr, qd, vr);
    assert_true(ex <= 1e-14 && ev <= 1e-14);
    worst = fmax(worst, fmax(ex, ev));
    vi_model_destroy(&m);
  }
  print_message("one mode in every regime: worst relative error %.3g\n", worst);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_mode_regimes),
      cmocka_unit_test(test_ball_rigid),
      cmocka_unit_test(test_ball_soft_1e8),
      cmocka_unit_test(test_ball_soft_1e7),
      cmocka_unit_test(test_ball_soft_1e6),
      cmocka_unit_test(test_ball_unit),
      cmocka_unit_test(test_ball_stiff_1e8),
      cmocka_unit_test(test_first_contact_random),
      cmocka_unit_test(test_first_contact_grazing),
      cmocka_unit_test(test_long_free_flight),
      cmocka_unit_test(test_handover_near_resonance),
      cmocka_unit_test(test_cancel),
      cmocka_unit_test(test_modal_bounce),
      cmocka_unit_test(test_nonproportional_soft),
      cmocka_unit_test(test_nonproportional_soft_stop1),
      cmocka_unit_test(test_resting_on_stop),
      cmocka_unit_test(test_two_mass_stop_at_origin),
      cmocka_unit_test(test_free_free_chain_gravity),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
