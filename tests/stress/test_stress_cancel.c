/* test_stress_cancel.c - cancellation polled in every loop (issue 20,
 * item 2): a host's cancel poll (vi_sim_set_cancel, vi_sweep_set_cancel)
 * must be answered within one step of every backend and study, never after
 * a loop of many.
 *
 * The poll counts its calls and asks to cancel at call P.  A backend that
 * polls before each of its steps (the driver's loop, the exact method's
 * and the held phases' batches of grid steps) has taken at most P steps
 * when the run returns VI_CANCELLED; one that ran an inner loop of many
 * steps unpolled would return later, with more.  Step counts are what is
 * asserted, not times.
 *
 * a. Every method on a forced impacting oscillator (m = k = 1, c = 0.05,
 *    0.6 cos 0.8 t, stop x <= 0.1, r = 0.7), cancelled at poll 40: at most
 *    40 steps, time past t0, and a later run continues from the state
 *    (VI_OK to the end, the invariants checked).
 * b. The exact method on a non-proportionally damped 2-DOF chain (the
 *    scanned closed form, vi_exact_scan.c).
 * c. A held phase: an oscillator under a preload (f = 0.8 + 0.6 cos 0.3 t,
 *    stop x <= 0.5, r = 0.5) chatters into sticking (the chatter map sums
 *    its tail) and is held; the poll cancels at the first call after the
 *    STICK event: no step is taken after it, the time is the stick's.
 * d. Cancelled from the monitor: the monitor sets the flag the poll reads;
 *    the run stops at the time the monitor saw, with that many steps.
 * e. The study (vi_sweep): a point of a 2-DOF chain with P(1,1) orbits
 *    takes C polls; with its Lyapunov exponent too, the same C and then
 *    one at least per period of the Lyapunov run: cancelled at poll C + 1
 *    the point returns VI_CANCELLED; cancelled at poll 1, before its orbit
 *    scan and any simulation.
 * f. The impact-phase scan (vi_orbit_p1_scan_polled) on that chain: a
 *    whole scan of 720 phases polls at least 721 times; cancelled at poll
 *    5 it returns VI_CANCELLED at that very poll.
 * g. Continuation (vi_cont_set_cancel), natural and pseudo-arclength, from
 *    the scan's orbit: a step cancelled at its K-th poll returns
 *    VI_CANCELLED at that poll, is not done, and iterating again (cancel
 *    off) gives the point an uncancelled run gives, to 1e-12.
 * i. Inside one grid step of the exact method (issue 29): two uncoupled
 *    masses, k = 1e12 and 1 (rates 1e6 and 1), the stop on the slow one.
 *    The fast mode is invisible to the stop, so the grid steps a quarter
 *    period of the slow one, while the ledger's quadrature takes panels of
 *    a quarter radian of the fast one, hq = (pi/4) / 1e6: 2e6 panels in one
 *    grid step.  Held (a preload 0.5 against x_s = 0.1, reaction 0.4, no
 *    release) and in free flight (the slow mass at rest, 0.1 from its
 *    stop) with the fast mode overdamped (d = 3e6, hq = (pi/4) / 3e6; a
 *    mode past damping ratio 1/2 has no closed-form ledger), cancelled at
 *    the second poll: the run returns VI_CANCELLED after the quadrature's
 *    64th panel, t in (63 hq, 64 hq] (a grid step later before: t = 1
 *    held, 1.57 in flight), and the ledger, taken to there, closes when
 *    the run goes on.  Undamped, the free flight's ledger is in closed
 *    form (vi_ledger_flight.h), with no panels to poll between: cancelled
 *    at the first poll between grid steps, t <= 1.57.
 * h. Identification (vi_identify_set_cancel) of r on that chain, from a
 *    recording of its settled motion: a whole fit takes C polls; cancelled
 *    at poll C / 2 (inside the least-squares iterations) it returns
 *    VI_CANCELLED at that very poll, and at poll 1 before any work.
 *    (The recording is the library's own: what is asserted is the
 *    cancellation, not the fitted value.) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stress_util.h"
#include <vibroimpact/vi_cont.h>
#include <vibroimpact/vi_identify.h>
#include <vibroimpact/vi_orbit.h>
#include <vibroimpact/vi_study.h>

typedef struct poll {
  int64_t calls, at; /* cancel at call `at` (0: never) */
  int flag;          /* or when set (by a callback) */
  int64_t calls_at_flag;
} poll;

static int poll_fn(void *user)
{
  poll *p = user;
  p->calls++;
  return p->flag || (p->at > 0 && p->calls >= p->at);
}

static int64_t steps(const vi_sim *s) { return vi_sim_stat(s, VI_STAT_STEPS); }

/* a. and b.: cancelled at poll 40, then continued to the end. */
static void cancel_at_poll(const vi_model *m, int method, double t_end,
                           const char *what)
{
  int n = vi_model_n(m);
  double x0[2] = {0, 0}, v0[2] = {0, 0};
  poll p = {0, 40, 0, 0};
  vi_sim *s = st_sim(m, method, 1e-10, 1e-12, 0.0, x0, v0, NULL, NULL);
  assert_int_equal(vi_sim_set_cancel(s, poll_fn, &p, NULL), VI_OK);
  int st = vi_sim_run(s, t_end);
  double t;
  double x[2], v[2];
  assert_int_equal(vi_sim_state(s, &t, x, v), VI_OK);
  print_message("  %-24s %-6s cancelled at poll %lld: %lld steps, t = %.6g\n",
                what, vi_method_name(method), (long long)p.calls,
                (long long)steps(s), t);
  st_check(st == VI_CANCELLED);
  st_check(steps(s) >= 1 && steps(s) <= p.at);
  st_check(t > 0.0 && t < t_end);
  /* consistent: the run goes on from there */
  p.at = 0;
  st = vi_sim_run(s, t_end);
  st_check(st == VI_OK);
  assert_int_equal(vi_sim_state(s, &t, x, v), VI_OK);
  st_check(t == t_end);
  (void)n;
  vi_sim_destroy(&s);
}

static void test_every_method(void **state)
{
  (void)state;
  vi_model *m = st_sdof(1.0, 0.05, 1.0, 0.8, 0.6, 0.0, 0.0, 0.1, 0.7);
  const int methods[] = {VI_METHOD_ADAMS, VI_METHOD_BDF, VI_METHOD_ERK,
                         VI_METHOD_EXACT, VI_METHOD_AUTO};
  for (int k = 0; k < 5; k++)
    if (st_method_ok(m, methods[k])) cancel_at_poll(m, methods[k], 2000.0, "oscillator");
  vi_model_destroy(&m);
  /* b. non-proportional damping: the exact method scans its closed form */
  vi_model *c = NULL;
  double M[4] = {1, 0, 0, 1}, K[4] = {2, -1, -1, 1}, C[4] = {0.3, 0, 0, 0.01};
  double w[2] = {0, 1}, a[2] = {0, 0.6}, b[2] = {0, 0}, f0[2] = {0, 0};
  assert_int_equal(vi_model_create(2, &c), VI_OK);
  assert_int_equal(vi_model_set_mass(c, M, 2), VI_OK);
  assert_int_equal(vi_model_set_damping(c, C, 2), VI_OK);
  assert_int_equal(vi_model_set_stiffness(c, K, 2), VI_OK);
  assert_int_equal(vi_model_set_forcing(c, 0.9, a, b, f0), VI_OK);
  assert_int_equal(vi_model_set_stop(c, w, 0.1, 0.7), VI_OK);
  assert_int_equal(vi_model_setup(c), VI_OK);
  cancel_at_poll(c, VI_METHOD_EXACT, 2000.0, "chain, non-proportional");
  cancel_at_poll(c, VI_METHOD_ADAMS, 2000.0, "chain, non-proportional");
  vi_model_destroy(&c);
  st_end();
}

/* c. The STICK event sets the flag: nothing is stepped after it. */
typedef struct stick_watch {
  poll *p;
  const vi_sim *s;
  double t_stick;
  int64_t steps_at, polls_at;
} stick_watch;

static int on_stick(const vi_event *ev, void *user)
{
  stick_watch *sw = user;
  if (ev->kind == VI_EVENT_STICK && sw->steps_at < 0) { /* the first */
    sw->p->flag = 1;
    sw->t_stick = ev->t;
    sw->steps_at = steps(sw->s);
    sw->polls_at = sw->p->calls;
  }
  return 0;
}

static void test_held_phase(void **state)
{
  (void)state;
  vi_model *m = st_sdof(1.0, 0.05, 1.0, 0.3, 0.6, 0.0, 0.8, 0.5, 0.5);
  const int methods[] = {VI_METHOD_EXACT, VI_METHOD_ADAMS, VI_METHOD_BDF};
  for (int k = 0; k < 3; k++) {
    double x0 = 0.0, v0 = 0.0;
    poll p = {0, 0, 0, 0};
    vi_sim *s = st_sim(m, methods[k], 1e-10, 1e-12, 0.0, &x0, &v0, NULL, NULL);
    assert_int_equal(vi_sim_set_impact_resolution(s, 1e-5), VI_OK);
    stick_watch sw = {&p, s, NAN, -1, -1};
    assert_int_equal(vi_sim_set_event_callback(s, on_stick, &sw, NULL), VI_OK);
    assert_int_equal(vi_sim_set_cancel(s, poll_fn, &p, NULL), VI_OK);
    int st = vi_sim_run(s, 500.0);
    double t, x, v;
    assert_int_equal(vi_sim_state(s, &t, &x, &v), VI_OK);
    print_message("  held phase %-6s STICK at t = %.9g (%lld steps), returned "
                  "%s at t = %.9g (%lld steps)\n", vi_method_name(methods[k]),
                  sw.t_stick, (long long)sw.steps_at, vi_strerror(st), t,
                  (long long)steps(s));
    st_check(st == VI_CANCELLED);
    st_check(sw.steps_at >= 0 && steps(s) == sw.steps_at);
    st_check(fabs(t - sw.t_stick) <= 1e-12 * fmax(1.0, t));
    /* and from there the held phase runs on to its release and beyond */
    p.flag = 0;
    st_check(vi_sim_run(s, 500.0) == VI_OK);
    st_check(vi_sim_stat(s, VI_STAT_STICKS) >= 2);
    vi_sim_destroy(&s);
    /* inside the held phase: cancelled 5 polls after the STICK, at most 5
     * held steps later, before the release */
    poll q = {0, sw.polls_at + 5, 0, 0};
    s = st_sim(m, methods[k], 1e-10, 1e-12, 0.0, &x0, &v0, NULL, NULL);
    assert_int_equal(vi_sim_set_impact_resolution(s, 1e-5), VI_OK);
    assert_int_equal(vi_sim_set_cancel(s, poll_fn, &q, NULL), VI_OK);
    st = vi_sim_run(s, 500.0);
    assert_int_equal(vi_sim_state(s, &t, &x, &v), VI_OK);
    print_message("  held phase %-6s cancelled at poll %lld: t = %.9g, %lld "
                  "steps\n", vi_method_name(methods[k]), (long long)q.at, t,
                  (long long)steps(s));
    st_check(st == VI_CANCELLED);
    st_check(steps(s) - sw.steps_at >= 1 && steps(s) - sw.steps_at <= 5);
    st_check(t > sw.t_stick && vi_sim_stat(s, VI_STAT_STICKS) == 1);
    vi_sim_destroy(&s);
  }
  vi_model_destroy(&m);
  st_end();
}

/* d. The monitor asks for the cancel. */
typedef struct mon_watch {
  poll *p;
  int calls;
  double t;
  int64_t steps;
} mon_watch;

static int on_monitor(const vi_progress *pr, void *user)
{
  mon_watch *mw = user;
  if (++mw->calls == 5) {
    mw->p->flag = 1;
    mw->t = pr->t;
    mw->steps = pr->steps;
  }
  return 0;
}

/* i.  Held, and a free flight whose ledger is integrated by quadrature
 * (an overdamped stiff mode, d = 3e6: no closed form), poll inside the
 * quadrature; a free flight whose ledger has its closed form (undamped)
 * has no quadrature and polls at the grid's first step. */
static void test_quadrature(void **state)
{
  (void)state;
  const double M[4] = {1, 0, 0, 1}, K[4] = {1e12, 0, 0, 1};
  const double w[2] = {0, 1};
  for (int kase = 0; kase < 3; kase++) {
    int held = kase == 0, closed = kase == 2;
    const double f0[2] = {0, held ? 0.5 : 0.0};
    const double C[4] = {kase == 1 ? 3e6 : 0.0, 0, 0, 0};
    /* a quarter radian of the fastest rate: sqrt(K), or the damping */
    double hq = 0.7853981633974483 / (kase == 1 ? 3e6 : 1e6);
    vi_model *m = NULL;
    assert_int_equal(vi_model_create(2, &m), VI_OK);
    assert_int_equal(vi_model_set_mass(m, M, 2), VI_OK);
    assert_int_equal(vi_model_set_damping(m, C, 2), VI_OK);
    assert_int_equal(vi_model_set_stiffness(m, K, 2), VI_OK);
    assert_int_equal(vi_model_set_forcing(m, 0.0, NULL, NULL, f0), VI_OK);
    assert_int_equal(vi_model_set_stop(m, w, 0.1, 0.5), VI_OK);
    assert_int_equal(vi_model_setup(m), VI_OK);
    const double x0[2] = {0, held ? 0.1 : 0.0}, v0[2] = {0, 0};
    poll p = {0, 2, 0, 0};
    vi_sim *s = st_sim(m, VI_METHOD_EXACT, 1e-10, 1e-12, 0.0, x0, v0, NULL,
                       NULL);
    assert_int_equal(vi_sim_enable_ledger(s, 1), VI_OK);
    assert_int_equal(vi_sim_set_cancel(s, poll_fn, &p, NULL), VI_OK);
    int st = vi_sim_run(s, 100.0);
    double t, x[2], v[2];
    assert_int_equal(vi_sim_state(s, &t, x, v), VI_OK);
    print_message("  %s: returned %s at t = %.9g = %.6g hq, poll %lld\n",
                  held ? "held" : closed ? "free flight, closed form"
                                         : "free flight, quadrature",
                  vi_strerror(st), t, t / hq, (long long)p.calls);
    st_check(st == VI_CANCELLED);
    if (closed) /* the grid's step: a quarter period of the slow mode */
      st_check(t > 0.0 && t <= 1.5707963267948966 * (1.0 + 1e-12));
    else
      st_check(t > 63.0 * hq && t <= 64.0 * hq * (1.0 + 1e-12));
    st_check(vi_sim_stat(s, VI_STAT_STICKS) == held);
    /* on from there: the integrals over the cut and the rest close */
    p.at = 0;
    st_check(vi_sim_run(s, closed ? t + 1.0 : 0.01) == VI_OK);
    st_check(vi_sim_ledger_max_residual(s) <= 1e-9);
    vi_sim_destroy(&s);
    vi_model_destroy(&m);
  }
}

static void test_from_monitor(void **state)
{
  (void)state;
  vi_model *m = st_sdof(1.0, 0.05, 1.0, 0.8, 0.6, 0.0, 0.0, 0.1, 0.7);
  const int methods[] = {VI_METHOD_ADAMS, VI_METHOD_BDF, VI_METHOD_ERK,
                         VI_METHOD_EXACT};
  for (int k = 0; k < 4; k++) {
    double x0 = 0.0, v0 = 0.0;
    poll p = {0, 0, 0, 0};
    mon_watch mw = {&p, 0, NAN, -1};
    vi_sim *s = st_sim(m, methods[k], 1e-10, 1e-12, 0.0, &x0, &v0, NULL, NULL);
    assert_int_equal(vi_sim_set_monitor(s, 10.0, on_monitor, &mw, NULL), VI_OK);
    assert_int_equal(vi_sim_set_cancel(s, poll_fn, &p, NULL), VI_OK);
    int st = vi_sim_run(s, 1e4);
    double t, x, v;
    assert_int_equal(vi_sim_state(s, &t, &x, &v), VI_OK);
    print_message("  monitor %-6s flag at t = %.9g (%lld steps), cancelled at "
                  "t = %.9g (%lld steps)\n", vi_method_name(methods[k]), mw.t,
                  (long long)mw.steps, t, (long long)steps(s));
    st_check(st == VI_CANCELLED);
    st_check(t == mw.t && steps(s) == mw.steps);
    st_check(t >= 40.0 && t < 60.0);
    vi_sim_destroy(&s);
  }
  vi_model_destroy(&m);
  st_end();
}

/* e. The study: the polls after the simulation (Lyapunov run, end of
 * point) and before the orbit scan. */
static vi_sweep *fig2_study(poll *p, int lyap)
{
  vi_model *m = vi_test_fig2();
  vi_sweep *sw = NULL;
  assert_int_equal(vi_sweep_create(m, &sw), VI_OK);
  vi_model_destroy(&m); /* the study keeps its own copy */
  assert_int_equal(vi_sweep_set_run(sw, VI_METHOD_EXACT, 1e-8, 1e-10), VI_OK);
  assert_int_equal(vi_sweep_set_periods(sw, 20, 20), VI_OK);
  assert_int_equal(vi_sweep_set_lyapunov(sw, lyap), VI_OK);
  assert_int_equal(vi_sweep_set_orbits(sw, 64), VI_OK);
  assert_int_equal(vi_sweep_set_cancel(sw, poll_fn, p, NULL), VI_OK);
  return sw;
}

static void test_study(void **state)
{
  (void)state;
  /* C polls in a point without the Lyapunov run; with it the same C come
   * first (the same simulation), then those of the Lyapunov run */
  poll p = {0, 0, 0, 0};
  vi_sweep *sw = fig2_study(&p, 0);
  assert_int_equal(vi_sweep_iterate(sw), VI_OK);
  int64_t C = p.calls;
  vi_sweep_destroy(&sw);
  poll q = {0, 0, 0, 0};
  sw = fig2_study(&q, 1);
  assert_int_equal(vi_sweep_iterate(sw), VI_OK);
  st_check(isfinite(vi_sweep_lyapunov(sw)));
  print_message("  study: %lld polls in a point, %lld with its Lyapunov run\n",
                (long long)C, (long long)q.calls);
  st_check(q.calls > C + 10); /* one at least per period of the 20 */
  vi_sweep_destroy(&sw);
  /* cancelled at the Lyapunov run's first poll: the point is cancelled */
  poll r = {0, C + 1, 0, 0};
  sw = fig2_study(&r, 1);
  int st = vi_sweep_iterate(sw);
  print_message("  study: cancelled at poll %lld: %s after %lld polls\n",
                (long long)C + 1, vi_strerror(st), (long long)r.calls);
  st_check(st == VI_CANCELLED);
  st_check(r.calls <= C + 2);
  vi_sweep_destroy(&sw);
  /* and at the first, before the orbit scan and any simulation */
  poll u = {0, 1, 0, 0};
  sw = fig2_study(&u, 1);
  st = vi_sweep_iterate(sw);
  st_check(st == VI_CANCELLED && u.calls == 1);
  vi_sweep_destroy(&sw);
  st_end();
}

/* Fig. 2's chain as in e., the model alone. */
/* f. The phase scan. */
static void test_scan(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  double t[8], x[16], v[16];
  int found = 0;
  poll p = {0, 0, 0, 0};
  assert_int_equal(vi_orbit_p1_scan_polled(m, 1, 720, t, x, v, 2, 8, &found,
                                           poll_fn, &p), VI_OK);
  print_message("  scan: %lld polls, %d orbit(s)\n", (long long)p.calls, found);
  st_check(p.calls >= 721 && found >= 1);
  poll q = {0, 5, 0, 0};
  int st = vi_orbit_p1_scan_polled(m, 1, 720, t, x, v, 2, 8, &found, poll_fn, &q);
  st_check(st == VI_CANCELLED && q.calls == 5);
  vi_model_destroy(&m);
  st_end();
}

/* g. One continuation, its step cancelled at poll `at` of the run, then
 * resumed; the point after the resumed step. */
static int cont_run(const vi_model *m, int method, int64_t at, double *pt)
{
  double t[8], x[16], v[16];
  int found = 0;
  assert_int_equal(vi_orbit_p1_scan(m, 1, 720, t, x, v, 2, 8, &found), VI_OK);
  assert_true(found >= 1);
  vi_cont *c = NULL;
  assert_int_equal(vi_cont_create(m, "forcing.omega", 1, method, &c), VI_OK);
  assert_int_equal(vi_cont_set_range(c, 1.0, 10), VI_OK);
  assert_int_equal(vi_cont_set_orbit(c, t[0], x, v), VI_OK);
  poll p = {0, at, 0, 0};
  assert_int_equal(vi_cont_set_cancel(c, poll_fn, &p, NULL), VI_OK);
  int cancelled = 0;
  for (int i = 0; i < 3; i++) {
    int st = vi_cont_iterate(c);
    if (st == VI_CANCELLED) {
      cancelled++;
      st_check(p.calls == at && vi_cont_done(c) == 0);
      p.at = 0; /* off: the same step again */
      st = vi_cont_iterate(c);
    }
    assert_int_equal(st, VI_OK);
  }
  assert_int_equal(vi_cont_point(c, &pt[0], &pt[1], &pt[2], NULL, NULL), VI_OK);
  vi_cont_destroy(&c);
  return cancelled;
}

static void test_cont(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  const int methods[2] = {VI_CONT_NATURAL, VI_CONT_ARCLENGTH};
  for (int k = 0; k < 2; k++) {
    double ref[3], got[3], got1[3];
    assert_int_equal(cont_run(m, methods[k], 0, ref), 0);
    /* poll 1: the first step, before anything; poll 3: inside the third
     * step of the natural method, the corrector of the second point */
    assert_int_equal(cont_run(m, methods[k], 1, got1), 1);
    assert_int_equal(cont_run(m, methods[k], 3, got), 1);
    print_message("  cont %d: omega %.12g, resumed %.12g, %.12g\n", k, ref[0],
                  got1[0], got[0]);
    for (int i = 0; i < 3; i++) {
      st_check(fabs(got[i] - ref[i]) <= 1e-12 * fmax(1.0, fabs(ref[i])));
      st_check(fabs(got1[i] - ref[i]) <= 1e-12 * fmax(1.0, fabs(ref[i])));
    }
  }
  vi_model_destroy(&m);
  st_end();
}

/* h. Identification. */
typedef struct recd {
  int ns;
  double t[512], y[512];
} recd;

static int on_sample(double t, int n, const double *x, const double *v, void *user)
{
  recd *r = user;
  (void)n;
  (void)v;
  if (r->ns < 512) {
    r->t[r->ns] = t;
    r->y[r->ns++] = x[1]; /* the gap coordinate w.x */
  }
  return 0;
}

static int identify_polls(const vi_model *m, const recd *r, int64_t at,
                          int64_t *calls)
{
  vi_identify *id = NULL;
  poll p = {0, at, 0, 0};
  assert_int_equal(vi_identify_create(m, 1, &id), VI_OK);
  assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_R, 0, 0.6, 0, 1), VI_OK);
  assert_int_equal(vi_identify_set_data(id, r->ns, r->t, r->y, NULL), VI_OK);
  assert_int_equal(vi_identify_set_cancel(id, poll_fn, &p, NULL), VI_OK);
  int st = vi_identify_run(id);
  if (st && st != VI_CANCELLED) print_message("  identify: %s\n", vi_identify_errmsg(id));
  *calls = p.calls;
  vi_identify_destroy(&id);
  return st;
}

static void test_identify(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  double T = 2 * M_PI / 0.9, x0[2] = {0, 0}, v0[2] = {0, 0};
  recd *r = calloc(1, sizeof *r);
  assert_non_null(r);
  vi_sim *s = st_sim(m, VI_METHOD_EXACT, 1e-12, 1e-14, 0.0, x0, v0, NULL, NULL);
  assert_int_equal(vi_sim_run(s, 300 * T), VI_OK);
  assert_int_equal(vi_sim_set_sampling(s, T / 64, on_sample, r, NULL), VI_OK);
  assert_int_equal(vi_sim_run(s, 304 * T), VI_OK);
  vi_sim_destroy(&s);
  int64_t C = 0, c2 = 0, c1 = 0;
  assert_int_equal(identify_polls(m, r, 0, &C), VI_OK);
  int st = identify_polls(m, r, C / 2, &c2);
  print_message("  identify: %lld polls in a fit (%d samples); cancelled at "
                "%lld: %s after %lld\n", (long long)C, r->ns, (long long)(C / 2),
                vi_strerror(st), (long long)c2);
  st_check(C >= 4);
  st_check(st == VI_CANCELLED && c2 == C / 2);
  st = identify_polls(m, r, 1, &c1);
  st_check(st == VI_CANCELLED && c1 == 1);
  free(r);
  vi_model_destroy(&m);
  st_end();
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_every_method),
      cmocka_unit_test(test_held_phase),
      cmocka_unit_test(test_quadrature),
      cmocka_unit_test(test_from_monitor),
      cmocka_unit_test(test_study),
      cmocka_unit_test(test_scan),
      cmocka_unit_test(test_cont),
      cmocka_unit_test(test_identify),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
