/* test_stress_held.c - sticking phases in closed form (issue 18): the exact
 * method holds stops on the constrained structure's modes (vi_held.c), with
 * no right-hand side, and finds releases and contacts as rigorous roots.
 *
 * a. SDOF under a preload: m = k = 1, c = 0.05, f = 0.8 + 0.6 cos(0.3 t),
 *    stop x <= 0.5 (r = 0.5), from rest on the stop.  On the stop the
 *    contact force is lambda = 0.8 + 0.6 cos(0.3 t) - 0.5, so every
 *    release, the first and those after each later chattering sequence
 *    into sticking (one per forcing period), comes at 0.3 t = 2 pi / 3
 *    (mod 2 pi).
 * b. Mass 2 of a 2-DOF chain held: M = I, K = [[2, -1], [-1, 1]],
 *    C = 0.02 K, f = (0, 0.2 + 0.3 cos(0.7 t)), stop x2 <= 0.1, from
 *    x = (0, 0.1) at rest.  Held, mass 1 is the damped oscillator
 *    x1'' + 0.04 x1' + 2 x1 = 0.1 and lambda = f2 + x1 + 0.02 x1' - 0.1:
 *    the release is its first root, bracketed here on that closed form.
 * c. One stop held while the other is hit: the same chain, C = 0,
 *    f = (0, 1), stops x2 <= 0 (r = 0) and x1 <= 0.3 (r = 0.5), from
 *    x = 0, v = (1, 0).  Mass 2 holds (lambda = 1 + x1 > 0) and mass 1
 *    oscillates as x1 = sin(sqrt2 t) / sqrt2, hitting x1 = 0.3 with speed
 *    u1 = cos(sqrt2 t1); each rebound -r u returns to the stop after
 *    (2 pi + 2 atan(-r u / (0.3 sqrt2))) / sqrt2 at the same speed r u.
 * d. Siconos' impacting bar (vi_bar.h, 20 to 500 elements) against the independent clamped-bar
 *    reference ref/bar_ref.py: release to 1e-11 s; and the continuum limit
 *    5e-4 + 2 L / c, rebound 0.1 m/s, approached as the mesh is refined.
 *
 * e. The stiff methods on the bar (20 and 50 elements, rtol 1e-10, atol
 *    1e-14): the plastic impact leaves the contact force at zero, growing;
 *    a restart in free flight there let BDF tunnel (1.1e-12 beyond the
 *    stop, VI_ERR_INVARIANT).  Both CVODE methods must finish, releasing
 *    within 1e-10 s of the reference (measured: 2e-13 s or better).
 *
 * f. Chatter into sticking on a structure of a hundred modes: the
 *    100-element bar with r = 0.5 bounces (its high modes ringing against
 *    node 1), its impacts accumulate, node 1 sticks and is released.  No
 *    closed form: the exact method against CVODE Adams at rtol 1e-10 -
 *    releases within 1e-11 s of each other (measured 3e-14 s), the STICK
 *    events (summed tails) within 1e-9 s.
 *
 * g. Case b with the held stop second or third (the stops before it never
 *    reached), under every method: release, no penetration, the ledger
 *    closed mode by mode.
 * h. Two stops held at once, in either order: the one whose reaction falls
 *    through zero first lets go at its closed form, the other holds.
 *
 * Every case but e and g: rhs_evals 0 under the exact method. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stress_util.h"
#include <vibroimpact/vi_ledger.h>
#include "vi_bar.h"

typedef struct hlog {
  int count;
  int kind[4096], stop[4096];
  double t[4096], vn[4096];
} hlog;

static int hlog_event(const vi_event *ev, void *user)
{
  hlog *l = user;
  if (l->count < 4096) {
    l->kind[l->count] = ev->kind;
    l->stop[l->count] = ev->stop;
    l->t[l->count] = ev->t;
    l->vn[l->count] = ev->vn;
    l->count++;
  }
  return 0;
}

static vi_sim *held_sim(const vi_model *m, int method, double rtol,
                        double atol, const double *x0, const double *v0,
                        hlog *log)
{
  vi_sim *s = NULL;
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_sim_set_method(s, method), VI_OK);
  assert_int_equal(vi_sim_set_tolerances(s, rtol, atol), VI_OK);
  assert_int_equal(vi_sim_set_initial(s, 0.0, x0, v0), VI_OK);
  assert_int_equal(vi_sim_set_event_callback(s, hlog_event, log, NULL), VI_OK);
  return s;
}

static void test_sdof_preload(void **state)
{
  (void)state;
  vi_model *m = st_sdof(1.0, 0.05, 1.0, 0.3, 0.6, 0.0, 0.8, 0.5, 0.5);
  double x0 = 0.5, v0 = 0.0;
  hlog *log = calloc(1, sizeof *log);
  assert_non_null(log);
  vi_sim *s = held_sim(m, VI_METHOD_EXACT, 1e-10, 1e-12, &x0, &v0, log);
  assert_int_equal(vi_sim_run(s, 40.0 * 2.0 * M_PI / 0.3), VI_OK);
  int nrel = 0, nstick = 0;
  double worst = 0.0;
  for (int i = 0; i < log->count; i++) {
    if (log->kind[i] == VI_EVENT_STICK) nstick++;
    if (log->kind[i] != VI_EVENT_RELEASE) continue;
    /* the phase 0.3 t mod 2 pi of the root of 0.3 + 0.6 cos */
    double ph = fmod(0.3 * log->t[i], 2.0 * M_PI);
    worst = fmax(worst, fabs(ph - 2.0 * M_PI / 3.0) / 0.3);
    nrel++;
  }
  printf("sdof preload: %d sticks, %d releases, worst release %.3g from "
         "the closed form, rhs_evals %lld\n", nstick, nrel, worst,
         (long long)vi_sim_stat(s, VI_STAT_RHS_EVALS));
  /* one stick and release per forcing period */
  assert_true(nrel >= 39 && nstick >= nrel);
  /* to the round-off of t (up to 838) and of the phase */
  assert_true(worst <= 8.0 * DBL_EPSILON * 40.0 * 2.0 * M_PI / 0.3);
  assert_int_equal(vi_sim_stat(s, VI_STAT_RHS_EVALS), 0);
  assert_string_equal(vi_method_name(vi_sim_method_used(s)), "exact");
  vi_sim_destroy(&s);
  free(log);
  vi_model_destroy(&m);
}

static vi_model *chain2(double cdamp, const double *f0, double W,
                        const double *a)
{
  const double M[4] = {1, 0, 0, 1}, K[4] = {2, -1, -1, 1};
  double C[4];
  for (int i = 0; i < 4; i++) C[i] = cdamp * K[i];
  vi_model *m = NULL;
  assert_int_equal(vi_model_create(2, &m), VI_OK);
  assert_int_equal(vi_model_set_mass(m, M, 2), VI_OK);
  assert_int_equal(vi_model_set_damping(m, C, 2), VI_OK);
  assert_int_equal(vi_model_set_stiffness(m, K, 2), VI_OK);
  assert_int_equal(vi_model_set_forcing(m, W, a, NULL, f0), VI_OK);
  return m;
}

/* case b's contact force on the closed form of the held motion */
static double chain_lambda(double t)
{
  double mu = sqrt(2.0 - 0.0004), A = -0.05, B = 0.02 * A / mu;
  double e = exp(-0.02 * t), c = cos(mu * t), sn = sin(mu * t);
  double x1 = 0.05 + e * (A * c + B * sn);
  double v1 = e * (-0.02 * (A * c + B * sn) + mu * (-A * sn + B * c));
  return 0.2 + 0.3 * cos(0.7 * t) + x1 + 0.02 * v1 - 0.1;
}

/* The reference release: the first root of chain_lambda, scanned in steps
 * of 1e-3 then bisected to round-off. */
static double chain_release(void)
{
  double lo = 0.0, hi = 0.0;
  for (int i = 0; i < 20000; i++)
    if (chain_lambda(1e-3 * (i + 1)) < 0.0) {
      lo = 1e-3 * i;
      hi = 1e-3 * (i + 1);
      break;
    }
  assert_true(hi > 0.0);
  for (int it = 0; it < 200 && hi - lo > 4e-16 * hi; it++) {
    double mid = 0.5 * (lo + hi);
    if (chain_lambda(mid) < 0.0) hi = mid;
    else lo = mid;
  }
  return hi;
}

static void test_chain_mass2(void **state)
{
  (void)state;
  const double f0[2] = {0.0, 0.2}, a[2] = {0.0, 0.3}, w[2] = {0.0, 1.0};
  vi_model *m = chain2(0.02, f0, 0.7, a);
  assert_int_equal(vi_model_set_stop(m, w, 0.1, 0.5), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  const double hi = chain_release(); /* the reference */
  const double x0[2] = {0.0, 0.1}, v0[2] = {0.0, 0.0};
  const int methods[2] = {VI_METHOD_EXACT, VI_METHOD_ADAMS};
  double ce_exact = 0.0;
  for (int q = 0; q < 2; q++) {
    hlog *log = calloc(1, sizeof *log);
    assert_non_null(log);
    vi_sim *s = held_sim(m, methods[q], 1e-11, 1e-13, x0, v0, log);
    assert_int_equal(vi_sim_enable_ledger(s, 1), VI_OK);
    assert_int_equal(vi_sim_run(s, hi + 1e-3), VI_OK);
    /* the ledger closes through the held phase, the stop's exchange CE
     * between the modes summing to its work: zero for a fixed stop */
    double CE[2], FE[2], DE[2];
    assert_int_equal(vi_sim_ledger(s, NULL, FE, DE, NULL, CE, NULL, NULL), VI_OK);
    double ce = fabs(CE[0]) + fabs(CE[1]), scale = fabs(FE[0]) + fabs(FE[1]);
    printf("  ledger: CE = (%.6g, %.6g), sum %.3g; largest closure residual "
           "%.3g\n", CE[0], CE[1], CE[0] + CE[1], vi_sim_ledger_max_residual(s));
    assert_true(ce > 1e-3 * scale); /* the stop moves energy between modes */
    assert_true(fabs(CE[0] + CE[1]) <= 1e-9 * ce);
    assert_true(vi_sim_ledger_max_residual(s) <= 1e-9);
    /* the closed form's quadrature and CVODE's agree on the exchange */
    if (q == 0) ce_exact = CE[1];
    else assert_true(fabs(CE[1] - ce_exact) <= 1e-8 * fabs(ce_exact));
    int ir = -1;
    for (int i = 0; i < log->count && ir < 0; i++)
      if (log->kind[i] == VI_EVENT_RELEASE) ir = i;
    assert_true(ir >= 0);
    if (ir < 0) ir = 0; /* (failed above) */
    double err = fabs(log->t[ir] - hi);
    printf("chain, mass 2 held (%s): release %.17g, closed form %.17g, "
           "error %.3g, rhs_evals %lld\n", vi_method_name(methods[q]),
           log->t[ir], hi, err, (long long)vi_sim_stat(s, VI_STAT_RHS_EVALS));
    if (methods[q] == VI_METHOD_EXACT) {
      assert_true(err <= 1e-12);
      assert_int_equal(vi_sim_stat(s, VI_STAT_RHS_EVALS), 0);
    } else {
      assert_true(err <= 1e-7); /* CVODE at rtol 1e-11: its own error */
    }
    vi_sim_destroy(&s);
    free(log);
  }
  vi_model_destroy(&m);
}

static void test_held_while_other_hit(void **state)
{
  (void)state;
  const double f0[2] = {0.0, 1.0}, w2[2] = {0.0, 1.0}, w1[2] = {1.0, 0.0};
  vi_model *m = chain2(0.0, f0, 1.0, NULL);
  assert_int_equal(vi_model_set_stop(m, w2, 0.0, 0.0), VI_OK);
  assert_int_equal(vi_model_add_stop(m, w1, 0.3, 0.5), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  const double x0[2] = {0.0, 0.0}, v0[2] = {1.0, 0.0}, r2 = sqrt(2.0);
  hlog *log = calloc(1, sizeof *log);
  assert_non_null(log);
  vi_sim *s = held_sim(m, VI_METHOD_EXACT, 1e-11, 1e-13, x0, v0, log);
  assert_int_equal(vi_sim_run(s, 20.0), VI_OK);
  double t = asin(0.3 * r2) / r2, u = cos(r2 * t), et = 0.0, ev = 0.0;
  int k = 0, rel = 0;
  for (int i = 0; i < log->count; i++) {
    if (log->kind[i] == VI_EVENT_RELEASE) rel++;
    if (log->kind[i] != VI_EVENT_IMPACT || log->stop[i] != 1) continue;
    et = fmax(et, fabs(log->t[i] - t));
    ev = fmax(ev, fabs(log->vn[i] - u));
    t += (2.0 * M_PI + 2.0 * atan(-0.5 * u / (0.3 * r2))) / r2;
    u *= 0.5;
    k++;
  }
  printf("stop 2 held, stop 1 hit: %d impacts, time error %.3g, speed "
         "error %.3g, releases %d, rhs_evals %lld\n", k, et, ev, rel,
         (long long)vi_sim_stat(s, VI_STAT_RHS_EVALS));
  assert_true(k >= 4);
  assert_true(et <= 1e-12 * 20.0);
  assert_true(ev <= 1e-12);
  assert_int_equal(rel, 0);
  assert_true(vi_sim_is_sticking(s));
  assert_int_equal(vi_sim_stat(s, VI_STAT_RHS_EVALS), 0);
  vi_sim_destroy(&s);
  free(log);
  vi_model_destroy(&m);
}

/* ref/bar_ref.py: release time and rebound speed (momentum / mass) */
static const struct { int ne; double t, v; } bar_ref[] = {
    {20, 0.00087896085962067588, 0.096214567393333603},
    {50, 0.00088190517159937262, 0.097932658841603834},
    {100, 0.00088310604066142826, 0.098698152326737121},
    {200, 0.00088402089810526855, 0.099177994429015995},
    {500, 0.00088466116610149445, 0.099553874153702135},
};

/* The bar of ne elements held on its stop from rest (x = BAR_X0, v =
 * BAR_V0), run with a method and tolerances to t_end: the model, the
 * initial state (x, v, of ne + 1 entries, to be freed) and the event log.
 * (The set-up and each case of the bar tests in their own functions: the
 * lint's path-sensitive analyser explored the loops over the cases to its
 * node budget.) */
static vi_sim *bar_run(int ne, int method, double rtol, double atol, double t_end,
                       vi_model **m, double **x, double **v, hlog **log, int *st)
{
  int n = ne + 1;
  *m = bar_model(ne, 0.0);
  assert_non_null(*m);
  double *x0 = malloc(sizeof(double) * n), *v0 = malloc(sizeof(double) * n);
  assert_true(x0 && v0);
  for (int i = 0; i < n; i++) {
    x0[i] = BAR_X0;
    v0[i] = BAR_V0;
  }
  *x = x0;
  *v = v0;
  *log = calloc(1, sizeof **log);
  assert_non_null(*log);
  vi_sim *s = held_sim(*m, method, rtol, atol, x0, v0, *log);
  *st = vi_sim_run(s, t_end);
  return s;
}

/* The index of the first release in l (-1: none), their number in *count. */
static int hlog_release(const hlog *l, int *count)
{
  int ir = -1;
  *count = 0;
  for (int i = 0; i < l->count; i++)
    if (l->kind[i] == VI_EVENT_RELEASE) {
      ++*count;
      if (ir < 0) ir = i;
    }
  return ir;
}

/* Case q of bar_ref with the automatic method; prev_t, prev_v: the
 * distances to the continuum limit of the previous (coarser) case. */
static void impacting_bar_case(size_t q, double tc, double *prev_t, double *prev_v)
{
  int ne = bar_ref[q].ne, n = ne + 1, st;
  vi_model *m;
  double *x, *v;
  hlog *log;
  vi_sim *s = bar_run(ne, VI_METHOD_AUTO, 1e-8, 1e-10, 1.5e-3, &m, &x, &v, &log, &st);
  assert_int_equal(st, VI_OK);
  int nrel, ir = hlog_release(log, &nrel);
  assert_int_equal(nrel, 1);
  if (ir < 0) ir = 0; /* (failed above) */
  /* momentum of the free bar after release: 1^T M v / (rho S L) */
  double t;
  assert_int_equal(vi_sim_state(s, &t, x, v), VI_OK);
  const double *M = vi_model_mass(m);
  double P = 0.0;
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) P += M[i + (size_t)j * n] * v[j];
  double vr = P / (BAR_RHO * BAR_S * BAR_L);
  double et = fabs(log->t[ir] - bar_ref[q].t), ev = fabs(vr - bar_ref[q].v);
  printf("bar, %4d elements: release %.17g (ref %.17g, error %.3g s), "
         "rebound %.12f (ref error %.3g), continuum gap %.3g s, %.3g m/s, "
         "rhs_evals %lld\n", ne, log->t[ir], bar_ref[q].t, et, vr, ev,
         log->t[ir] - tc, 0.1 - vr,
         (long long)vi_sim_stat(s, VI_STAT_RHS_EVALS));
  /* the target is 1e-11 s; the modal sums reach 1e-13 s (a rigid
   * mode left at dsygvd's round-off eigenvalue cost 2e-13 s here).  From
   * 100 elements on (n >= 64) the held bar's modes come from the secular
   * equation, below from the dense eigen-solve (vi_constrained.c): both
   * against the same reference */
  assert_true(et <= 1e-13);
  /* momentum after release: round-off of the modal sums */
  assert_true(ev <= 1e-12);
  assert_int_equal(vi_sim_stat(s, VI_STAT_RHS_EVALS), 0);
  /* the continuum limit is approached from below, monotonically */
  assert_true(log->t[ir] < tc && tc - log->t[ir] < *prev_t);
  assert_true(vr < 0.1 && 0.1 - vr < *prev_v);
  *prev_t = tc - log->t[ir];
  *prev_v = 0.1 - vr;
  vi_sim_destroy(&s);
  free(log);
  free(x);
  free(v);
  vi_model_destroy(&m);
}

static void test_impacting_bar(void **state)
{
  (void)state;
  const double tc = 5e-4 + 2.0 * BAR_L / sqrt(BAR_E / BAR_RHO);
  double prev_t = HUGE_VAL, prev_v = HUGE_VAL;
  for (size_t q = 0; q < sizeof bar_ref / sizeof bar_ref[0]; q++)
    impacting_bar_case(q, tc, &prev_t, &prev_v);
}

/* Case b of bar_ref with a stiff method at tight tolerances. */
static void bar_stiff_case(int method, int b)
{
  int ne = bar_ref[b].ne, st;
  vi_model *m;
  double *x, *v;
  hlog *log;
  vi_sim *s = bar_run(ne, method, 1e-10, 1e-14, 1.2e-3, &m, &x, &v, &log, &st);
  int nrel, ir = hlog_release(log, &nrel);
  printf("bar, %d elements, %s: %s, release error %.3g s\n", ne,
         vi_method_name(method), st ? vi_sim_errmsg(s) : "ok",
         ir >= 0 ? log->t[ir] - bar_ref[b].t : HUGE_VAL);
  assert_int_equal(st, VI_OK);
  assert_true(ir >= 0);
  if (ir < 0) ir = 0; /* (failed above) */
  assert_true(fabs(log->t[ir] - bar_ref[b].t) <= 1e-10);
  vi_sim_destroy(&s);
  free(log);
  free(x);
  free(v);
  vi_model_destroy(&m);
}

static void test_bar_stiff_methods(void **state)
{
  (void)state;
  const int methods[2] = {VI_METHOD_BDF, VI_METHOD_ADAMS};
  for (size_t q = 0; q < 2; q++)
    for (int b = 0; b < 2; b++) bar_stiff_case(methods[q], b);
}

static void test_bar_chatter(void **state)
{
  (void)state;
  int ne = 100, n = ne + 1;
  vi_model *m = bar_model(ne, 0.5);
  assert_non_null(m);
  double *x = malloc(sizeof(double) * n), *v = malloc(sizeof(double) * n);
  assert_true(x && v);
  const int methods[2] = {VI_METHOD_EXACT, VI_METHOD_ADAMS};
  double ts[2][2] = {{0.0, 0.0}, {0.0, 0.0}};
  for (int q = 0; q < 2; q++) {
    for (int i = 0; i < n; i++) {
      x[i] = BAR_X0;
      v[i] = BAR_V0;
    }
    hlog *log = calloc(1, sizeof *log);
    assert_non_null(log);
    vi_sim *s = held_sim(m, methods[q], 1e-10, 1e-13, x, v, log);
    assert_int_equal(vi_sim_run(s, 1.2e-3), VI_OK);
    int nimp = 0, nst = 0, nrel = 0;
    for (int i = 0; i < log->count; i++) {
      if (log->kind[i] == VI_EVENT_IMPACT) nimp++;
      if (log->kind[i] == VI_EVENT_STICK && nst++ == 0) ts[q][0] = log->t[i];
      if (log->kind[i] == VI_EVENT_RELEASE && nrel++ == 0) ts[q][1] = log->t[i];
    }
    printf("bar, r = 0.5 (%s): %d impacts, stick %.17g, release %.17g, "
           "rhs_evals %lld\n", vi_method_name(methods[q]), nimp, ts[q][0],
           ts[q][1], (long long)vi_sim_stat(s, VI_STAT_RHS_EVALS));
    assert_true(nimp >= 5);
    assert_int_equal(nst, 1);
    assert_int_equal(nrel, 1);
    if (q == 0) assert_int_equal(vi_sim_stat(s, VI_STAT_RHS_EVALS), 0);
    vi_sim_destroy(&s);
    free(log);
  }
  /* the STICK event is the accumulation point the driver sums from the
   * tail model at the impact where it decides to hold, which the methods
   * reach after different impacts (measured 8e-11 s apart); the release
   * is a root of the held flow from there */
  assert_true(fabs(ts[0][0] - ts[1][0]) <= 1e-9);
  assert_true(fabs(ts[0][1] - ts[1][1]) <= 1e-11);
  free(x);
  free(v);
  vi_model_destroy(&m);
}

/* case g: case b's hold on a stop that is not stop 0.  Stops x1 <= 5 (and,
 * with three, -x2 <= 5) come first and are never reached; the held stop
 * x2 <= 0.1 is stop 1 or 2.  Every method must release at case b's closed
 * form, keep the state behind every stop, close the ledger mode by mode
 * (E_j(t_b) - E_j(t_a) = FE_j - DE_j - XE_j + CE_j on every interval: a CE
 * column computed with another stop's psi breaks it) and book CE summing
 * to zero (a fixed stop does no work) while moving energy between modes. */
typedef struct g_led {
  double worst, emax;
  int count;
} g_led;

static int g_ledger(const vi_ledger_interval *iv, void *user)
{
  g_led *l = user;
  for (int j = 0; j < iv->n; j++) {
    double r = iv->Eb[j] - iv->Ea[j] - iv->FE[j] + iv->DE[j] + iv->XE[j] -
               iv->CE[j];
    l->worst = fmax(l->worst, fabs(r));
    l->emax = fmax(l->emax, fmax(iv->Ea[j], iv->Eb[j]));
  }
  l->count++;
  return 0;
}

typedef struct g_pen {
  double worst; /* largest w_k.x - x_k over the samples */
  int nst;
} g_pen;

static int g_sample(double t, int n, const double *x, const double *v,
                    void *user)
{
  (void)t;
  (void)n;
  (void)v;
  g_pen *p = user;
  p->worst = fmax(p->worst, fmax(x[0] - 5.0, x[1] - 0.1));
  if (p->nst == 3) p->worst = fmax(p->worst, -x[1] - 5.0);
  return 0;
}

static void test_held_not_stop0(void **state)
{
  (void)state;
  const double hi = chain_release(); /* the reference */
  const double f0[2] = {0.0, 0.2}, a[2] = {0.0, 0.3};
  const double w0[2] = {1.0, 0.0}, wl[2] = {0.0, -1.0}, wh[2] = {0.0, 1.0};
  const double x0[2] = {0.0, 0.1}, v0[2] = {0.0, 0.0};
  const int methods[4] = {VI_METHOD_EXACT, VI_METHOD_ADAMS, VI_METHOD_BDF,
                          VI_METHOD_ERK};
  for (int nst = 2; nst <= 3; nst++) {
    vi_model *m = chain2(0.02, f0, 0.7, a);
    assert_int_equal(vi_model_set_stop(m, w0, 5.0, 0.5), VI_OK);
    if (nst == 3) assert_int_equal(vi_model_add_stop(m, wl, 5.0, 0.5), VI_OK);
    assert_int_equal(vi_model_add_stop(m, wh, 0.1, 0.5), VI_OK);
    assert_int_equal(vi_model_setup(m), VI_OK);
    for (int q = 0; q < 4; q++) {
      hlog *log = calloc(1, sizeof *log);
      assert_non_null(log);
      vi_sim *s = held_sim(m, methods[q], 1e-11, 1e-13, x0, v0, log);
      g_led led = {0.0, 0.0, 0};
      g_pen pen = {-HUGE_VAL, nst};
      assert_int_equal(vi_sim_enable_ledger(s, 1), VI_OK);
      assert_int_equal(vi_sim_set_ledger_callback(s, g_ledger, &led, NULL),
                       VI_OK);
      assert_int_equal(vi_sim_set_sampling(s, 1e-2, g_sample, &pen, NULL),
                       VI_OK);
      assert_int_equal(vi_sim_run(s, hi + 1e-3), VI_OK);
      double CE[2], FE[2];
      assert_int_equal(vi_sim_ledger(s, NULL, FE, NULL, NULL, CE, NULL, NULL),
                       VI_OK);
      double ce = fabs(CE[0]) + fabs(CE[1]), scale = fabs(FE[0]) + fabs(FE[1]);
      int ir = -1;
      for (int i = 0; i < log->count && ir < 0; i++)
        if (log->kind[i] == VI_EVENT_RELEASE) ir = i;
      assert_true(ir >= 0);
      if (ir < 0) ir = 0; /* (failed above) */
      double err = fabs(log->t[ir] - hi);
      printf("held stop %d of %d (%s): release error %.3g (stop %d), "
             "penetration %.3g, CE = (%.6g, %.6g) sum %.3g, per-mode "
             "closure %.3g of %.3g, residual %.3g\n", nst - 1, nst,
             vi_method_name(methods[q]), err, log->stop[ir], pen.worst,
             CE[0], CE[1], CE[0] + CE[1], led.worst, led.emax,
             vi_sim_ledger_max_residual(s));
      assert_int_equal(log->stop[ir], nst - 1);
      /* the exact method to round-off; CVODE/ARKODE at rtol 1e-11: their
       * own error (measured below 1e-9) */
      assert_true(err <= (methods[q] == VI_METHOD_EXACT ? 1e-12 : 1e-7));
      assert_true(pen.worst <= 1e-10);
      assert_true(ce > 1e-3 * scale); /* the stop moves energy between modes */
      assert_true(fabs(CE[0] + CE[1]) <= 1e-9 * ce);
      assert_true(led.count >= 2);
      assert_true(led.worst <= 1e-9 * led.emax);
      assert_true(vi_sim_ledger_max_residual(s) <= 1e-9);
      vi_sim_destroy(&s);
      free(log);
    }
    vi_model_destroy(&m);
  }
}

/* case h: two stops held at once.  The same chain, C = 0.02 K, f = (0.3,
 * 0.2 + 0.3 cos(0.7 t)), stops x1 <= 0 and x2 <= 0.1 (in either order),
 * from x = (0, 0.1) at rest.  Both held, nothing moves and the reactions
 * are f - K x: lambda_1 = 0.4, lambda_2 = 0.1 + 0.3 cos(0.7 t), so the x2
 * stop lets go first at t = acos(-1/3) / 0.7 while x1's stays held
 * (lambda_1 = 0.3 + x2 > 0 over the next time unit). */
typedef struct h_pen {
  double worst;
} h_pen;

static int h_sample(double t, int n, const double *x, const double *v,
                    void *user)
{
  (void)t;
  (void)n;
  (void)v;
  h_pen *p = user;
  p->worst = fmax(p->worst, fmax(x[0], x[1] - 0.1));
  return 0;
}

static void test_two_held(void **state)
{
  (void)state;
  const double f0[2] = {0.3, 0.2}, a[2] = {0.0, 0.3};
  const double w1[2] = {1.0, 0.0}, w2[2] = {0.0, 1.0};
  const double x0[2] = {0.0, 0.1}, v0[2] = {0.0, 0.0};
  const double tr = acos(-1.0 / 3.0) / 0.7;
  const int methods[4] = {VI_METHOD_EXACT, VI_METHOD_ADAMS, VI_METHOD_BDF,
                          VI_METHOD_ERK};
  for (int order = 0; order < 2; order++) {
    vi_model *m = chain2(0.02, f0, 0.7, a);
    assert_int_equal(vi_model_set_stop(m, order ? w2 : w1, order ? 0.1 : 0.0,
                                       0.5), VI_OK);
    assert_int_equal(vi_model_add_stop(m, order ? w1 : w2, order ? 0.0 : 0.1,
                                       0.5), VI_OK);
    assert_int_equal(vi_model_setup(m), VI_OK);
    int k2 = order ? 0 : 1; /* the x2 stop's index */
    for (int q = 0; q < 4; q++) {
      hlog *log = calloc(1, sizeof *log);
      assert_non_null(log);
      vi_sim *s = held_sim(m, methods[q], 1e-11, 1e-13, x0, v0, log);
      g_led led = {0.0, 0.0, 0};
      h_pen pen = {-HUGE_VAL};
      assert_int_equal(vi_sim_enable_ledger(s, 1), VI_OK);
      assert_int_equal(vi_sim_set_ledger_callback(s, g_ledger, &led, NULL),
                       VI_OK);
      assert_int_equal(vi_sim_set_sampling(s, 1e-2, h_sample, &pen, NULL),
                       VI_OK);
      assert_int_equal(vi_sim_run(s, tr + 1.0), VI_OK);
      int ir = -1, nrel = 0;
      for (int i = 0; i < log->count; i++)
        if (log->kind[i] == VI_EVENT_RELEASE) {
          if (ir < 0) ir = i;
          nrel++;
        }
      assert_true(ir >= 0);
      if (ir < 0) ir = 0; /* (failed above) */
      double CE[2];
      assert_int_equal(vi_sim_ledger(s, NULL, NULL, NULL, NULL, CE, NULL,
                                     NULL), VI_OK);
      double err = fabs(log->t[ir] - tr), ce = fabs(CE[0]) + fabs(CE[1]);
      printf("two held, x2 stop is stop %d (%s): release error %.3g (stop "
             "%d), releases %d, still held %d, penetration %.3g, CE = (%.6g, "
             "%.6g), per-mode closure %.3g of %.3g, residual %.3g\n", k2,
             vi_method_name(methods[q]), err, log->stop[ir], nrel,
             vi_sim_is_sticking(s), pen.worst, CE[0], CE[1], led.worst,
             led.emax, vi_sim_ledger_max_residual(s));
      assert_int_equal(log->stop[ir], k2);
      assert_int_equal(nrel, 1);
      assert_int_equal(vi_sim_is_sticking(s), 1); /* x1's stop still held */
      assert_true(err <= (methods[q] == VI_METHOD_EXACT ? 1e-12 : 1e-7));
      assert_true(pen.worst <= 1e-10);
      assert_true(fabs(CE[0] + CE[1]) <= 1e-9 * fmax(ce, 1e-300) + 1e-15);
      assert_true(led.worst <= 1e-9 * led.emax);
      assert_true(vi_sim_ledger_max_residual(s) <= 1e-9);
      vi_sim_destroy(&s);
      free(log);
    }
    vi_model_destroy(&m);
  }
}

/* The held modes two ways.  One held stop on a 70-mass chain takes them
 * from the secular equation (64 modes or more, simple eigenvalues); the
 * same chain beside an identical, uncoupled copy at rest (140 modes, every
 * eigenvalue double) from the dense eigen-solve (vi_constrained.c).  The
 * copy takes no part in the motion, so the first chain's stick, release
 * and later impacts must agree: pressed on the stop at rest by f0 = 0.5
 * with a cos(0.5 t), a = 1, on its last mass, r = 0. */
static vi_model *twin_chains(int n, int copies)
{
  int N = n * copies;
  double *M = calloc((size_t)N * N, sizeof(double));
  double *K = calloc((size_t)N * N, sizeof(double));
  double *C = calloc((size_t)N * N, sizeof(double));
  double *a = calloc((size_t)N, sizeof(double));
  double *f0 = calloc((size_t)N, sizeof(double));
  double *W = calloc((size_t)N, sizeof(double));
  assert_true(M && K && C && a && f0 && W);
  for (int c = 0; c < copies; c++)
    for (int i = 0; i < n; i++) {
      size_t j = (size_t)c * n + i;
      M[j + j * N] = 1.0;
      K[j + j * N] = i + 1 < n ? 2.0 : 1.0;
      if (i + 1 < n) K[j + 1 + j * N] = K[j + (j + 1) * N] = -1.0;
    }
  for (size_t i = 0; i < (size_t)N * N; i++) C[i] = 0.02 * K[i];
  a[n - 1] = 1.0;
  f0[n - 1] = 0.5;
  W[n - 1] = 1.0;
  double xs = 0.0, r = 0.0;
  vi_model *m = vi_test_model_stops(N, M, C, K, 0.5, a, f0, 1, W, &xs, &r);
  free(M);
  free(K);
  free(C);
  free(a);
  free(f0);
  free(W);
  return m;
}

static void test_secular_vs_dense(void **state)
{
  (void)state;
  hlog *lg[2];
  vi_sim *s[2];
  vi_model *m[2];
  for (int c = 0; c < 2; c++) {
    m[c] = twin_chains(70, c + 1);
    lg[c] = calloc(1, sizeof *lg[c]);
    assert_non_null(lg[c]);
    s[c] = held_sim(m[c], VI_METHOD_EXACT, 1e-10, 1e-12, NULL, NULL, lg[c]);
    assert_int_equal(vi_sim_run(s[c], 60.0), VI_OK);
    assert_int_equal(vi_sim_stat(s[c], VI_STAT_RHS_EVALS), 0);
  }
  int rel = 0, imp = 0;
  double et = 0.0, ev = 0.0;
  assert_int_equal(lg[1]->count, lg[0]->count);
  for (int i = 0; i < lg[0]->count; i++) {
    assert_int_equal(lg[1]->kind[i], lg[0]->kind[i]);
    rel += lg[0]->kind[i] == VI_EVENT_RELEASE;
    imp += lg[0]->kind[i] == VI_EVENT_IMPACT;
    et = fmax(et, fabs(lg[1]->t[i] - lg[0]->t[i]));
    ev = fmax(ev, fabs(lg[1]->vn[i] - lg[0]->vn[i]));
  }
  printf("held chain of 70, secular (alone) against dense (beside its twin): "
         "%d events (%d releases, %d impacts), times agree to %.3g, speeds "
         "to %.3g\n", lg[0]->count, rel, imp, et, ev);
  assert_true(rel >= 2 && imp >= 1);
  assert_true(et <= 1e-11 * 60.0);
  assert_true(ev <= 1e-10);
  for (int c = 0; c < 2; c++) {
    vi_sim_destroy(&s[c]);
    vi_model_destroy(&m[c]);
    free(lg[c]);
  }
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_sdof_preload),
      cmocka_unit_test(test_chain_mass2),
      cmocka_unit_test(test_held_not_stop0),
      cmocka_unit_test(test_two_held),
      cmocka_unit_test(test_held_while_other_hit),
      cmocka_unit_test(test_impacting_bar),
      cmocka_unit_test(test_bar_stiff_methods),
      cmocka_unit_test(test_bar_chatter),
      cmocka_unit_test(test_secular_vs_dense),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
