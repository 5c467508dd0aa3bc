/* vi_arkode.c - ARKODE backend: an explicit Runge-Kutta method of order 8
 * (Prince & Dormand 8(7), first-same-as-last, in ARKODE's ERKStep) with
 * ARKODE's root finding on the gap
 * and its rate.  A one-step method has no order ramp after an impact: it
 * restarts at full order with the step size it had.
 *
 * ARKODE has no quadratures, so the ledger integrals ride along as extra
 * state components under the same error control.  ARKODE locates roots on
 * its (cubic) Hermite interpolant, much less accurate than an 8th-order
 * step, so each contact is polished on the Runge-Kutta step itself: Newton
 * on the step length from the start of the step, which also gives the
 * state at the contact to the step's accuracy; gap maxima and samples are
 * taken on the step too. */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include <arkode/arkode_erkstep.h>
#include <nvector/nvector_serial.h>

#include "vi_forcing.h"
#include "vi_rhs.h"

/* Prince & Dormand's RK8(7)13M pair: P. J. Prince and J. R. Dormand, "High
 * order embedded Runge-Kutta formulae", J. Comput. Appl. Math. 7 (1981)
 * 67-75 (the paper's rational approximations, which satisfy the
 * order conditions to ~1e-18: bench/dp87_check.py checks them in exact
 * arithmetic).  Measured against ARKODE's own tables on Fig. 2 and the
 * 20-chain (rtol 1e-8 and 1e-9): Fehlberg 7(8) needs 2.1x and 2.3x the
 * right-hand sides for a larger error, Verner 8(5,6) 6x for 2000x the
 * error.  Row i of A holds stage i's coefficients; unlisted are zero. */
static ARKodeButcherTable dp87_table(void)
{
  enum { S = 13, S1 = S + 1 };
  static const double c[S] = {
      0.0, 1.0 / 18, 1.0 / 12, 1.0 / 8, 5.0 / 16, 3.0 / 8, 59.0 / 400,
      93.0 / 200, 5490023248.0 / 9719169821.0, 13.0 / 20,
      1201146811.0 / 1299019798.0, 1.0, 1.0};
  static const double b[S] = {
      14005451.0 / 335480064, 0, 0, 0, 0, -59238493.0 / 1068277825,
      181606767.0 / 758867731, 561292985.0 / 797845732,
      -1041891430.0 / 1371343529, 760417239.0 / 1151165299,
      118820643.0 / 751138087, -528747749.0 / 2220607170, 1.0 / 4};
  static const double d[S] = {
      13451932.0 / 455176623, 0, 0, 0, 0, -808719846.0 / 976000145,
      1757004468.0 / 5645159321.0, 656045339.0 / 265891186,
      -3867574721.0 / 1518517206, 465885868.0 / 322736535,
      53011238.0 / 667516719, 2.0 / 45, 0};
  /* stage, then (column, value) pairs of its nonzero coefficients */
  static const struct { int i, j; double a; } nz[] = {
      {1, 0, 1.0 / 18},
      {2, 0, 1.0 / 48}, {2, 1, 1.0 / 16},
      {3, 0, 1.0 / 32}, {3, 2, 3.0 / 32},
      {4, 0, 5.0 / 16}, {4, 2, -75.0 / 64}, {4, 3, 75.0 / 64},
      {5, 0, 3.0 / 80}, {5, 3, 3.0 / 16}, {5, 4, 3.0 / 20},
      {6, 0, 29443841.0 / 614563906}, {6, 3, 77736538.0 / 692538347},
      {6, 4, -28693883.0 / 1125000000}, {6, 5, 23124283.0 / 1800000000},
      {7, 0, 16016141.0 / 946692911}, {7, 3, 61564180.0 / 158732637},
      {7, 4, 22789713.0 / 633445777}, {7, 5, 545815736.0 / 2771057229.0},
      {7, 6, -180193667.0 / 1043307555},
      {8, 0, 39632708.0 / 573591083}, {8, 3, -433636366.0 / 683701615},
      {8, 4, -421739975.0 / 2616292301.0}, {8, 5, 100302831.0 / 723423059},
      {8, 6, 790204164.0 / 839813087}, {8, 7, 800635310.0 / 3783071287.0},
      {9, 0, 246121993.0 / 1340847787}, {9, 3, -37695042795.0 / 15268766246.0},
      {9, 4, -309121744.0 / 1061227803}, {9, 5, -12992083.0 / 490766935},
      {9, 6, 6005943493.0 / 2108947869}, {9, 7, 393006217.0 / 1396673457},
      {9, 8, 123872331.0 / 1001029789},
      {10, 0, -1028468189.0 / 846180014}, {10, 3, 8478235783.0 / 508512852},
      {10, 4, 1311729495.0 / 1432422823}, {10, 5, -10304129995.0 / 1701304382},
      {10, 6, -48777925059.0 / 3047939560.0},
      {10, 7, 15336726248.0 / 1032824649}, {10, 8, -45442868181.0 / 3398467696.0},
      {10, 9, 3065993473.0 / 597172653},
      {11, 0, 185892177.0 / 718116043}, {11, 3, -3185094517.0 / 667107341},
      {11, 4, -477755414.0 / 1098053517}, {11, 5, -703635378.0 / 230739211},
      {11, 6, 5731566787.0 / 1027545527}, {11, 7, 5232866602.0 / 850066563},
      {11, 8, -4093664535.0 / 808688257}, {11, 9, 3962137247.0 / 1805957418},
      {11, 10, 65686358.0 / 487910083},
      {12, 0, 403863854.0 / 491063109}, {12, 3, -5068492393.0 / 434740067},
      {12, 4, -411421997.0 / 543043805}, {12, 5, 652783627.0 / 914296604},
      {12, 6, 11173962825.0 / 925320556}, {12, 7, -13158990841.0 / 6184727034.0},
      {12, 8, 3936647629.0 / 1978049680}, {12, 9, -160528059.0 / 685178525},
      {12, 10, 248638103.0 / 1413531060}};
  /* A 14th stage f(t + h, y_n+1) (row = b, weight 0) makes the pair
   * first-same-as-last.  It costs nothing: ARKODE 6.4 takes the last stage
   * of any table whose last node is 1 as f(t_n+1, y_n+1), the next step's
   * first stage and the interpolant's end slope; for the 13-stage tables
   * (this one and Fehlberg's) that stage is not at y_n+1, and the error
   * it leaves doubles the steps for a given impact-time error. */
  double A[S1 * S1] = {0.0}, cc[S1] = {0.0}, bb[S1] = {0.0}, dd[S1] = {0.0};
  for (size_t k = 0; k < sizeof nz / sizeof nz[0]; k++)
    A[nz[k].i * S1 + nz[k].j] = nz[k].a;
  for (int j = 0; j < S; j++) A[S * S1 + j] = b[j];
  memcpy(cc, c, sizeof c);
  cc[S] = 1.0;
  memcpy(bb, b, sizeof b);
  memcpy(dd, d, sizeof d);
  return ARKodeButcherTable_Create(S1, 8, 7, cc, A, bb, dd);
}

typedef struct ark_data {
  SUNContext ctx;
  void *mem;
  vi_rhs *rhs;    /* the right-hand side's packed coefficients */
  ARKodeButcherTable B; /* our copy of the table, for polishing steps */
  int N;          /* 2n state, then nq ledger integrals */
  int nq;         /* 0 without the ledger, 4n, or 5n with nonlinear forces */
  double *ze;     /* extended state [N]: y wraps it */
  double *zd;     /* extended dense output [N]: yd wraps it */
  double *y0, *yt, *yo, *K; /* polishing: step start, stage input, output
                               [N each], stages [stages * N] */
  N_Vector y, yd;
  int nroots;     /* 2 per stop not held, 1 per held stop (the driver runs
                     sticking on CVODE today); 0 before a start */
  int *rinfo;     /* [2 ns]: root directions at a start, then root info */
  int k;          /* the stop whose gap the contact search looks at */
  long polish_rhs;
  double t_prev;  /* time of the previous return */
  int continued;  /* the last step ended on a root we integrated through */
  int fresh;      /* (re)started, no step since: no interpolant yet */
} ark_data;

/* The extended right-hand side: state rates, then (ledger) FE', DE', XE',
 * CE' (and NE') as vi_cvode.c's quadratures compute them. */
static void erk_f(vi_sim *s, ark_data *d, double t, const double *z,
                  double *zd)
{
  size_t n = (size_t)s->n;
  vi_rhs_rate(s, d->rhs, t, z, zd);
  if (s->led) {
    double lam[VI_CONTACT_MAX], *gq = NULL;
    vi_ledger_held h;
    vi_sim_held_reactions(s, t, z, lam, &h);
    if (s->nforces) {
      gq = s->fbuf + 3 * n;
      vi_force_modal(s, t, z, gq);
    }
    vi_ledger_rates_state(s->led, t, z, &h, gq, zd + 2 * n);
  }
}

static int rhs(double t, N_Vector y, N_Vector yd, void *user)
{
  vi_sim *s = user;
  erk_f(s, s->be_data, t, N_VGetArrayPointer(y), N_VGetArrayPointer(yd));
  return s->force_failed ? -1 : 0; /* the host's force failed: stop */
}

/* As vi_cvode.c: per stop k, contact (g_k rising) and gap maxima (g_k'
 * falling); while sticking, first the reaction of each held stop falling
 * through zero, then the pairs of the stops not held (vi_sim_gap_root). */
static int roots(double t, N_Vector y, double *g, void *user)
{
  vi_sim *s = user;
  vi_sim_roots_layout(s, t, N_VGetArrayPointer(y), g);
  return 0;
}

static void err_handler(int code, const char *module, const char *function,
                        char *msg, void *user)
{
  vi_sim *s = user;
  if (code < 0)
    vi_fail(s->errmsg, VI_ERR_INTEGRATOR, "%s %s (%d): %s", module, function,
            code, msg);
}

static void get_state(vi_sim *s, ark_data *d);

static void ark_destroy(vi_sim *s)
{
  ark_data *d = s->be_data;
  if (!d) return;
  ERKStepFree(&d->mem);
  ARKodeButcherTable_Free(d->B);
  vi_rhs_destroy(&d->rhs);
  N_VDestroy(d->y);
  N_VDestroy(d->yd);
  SUNContext_Free(&d->ctx);
  free(d->ze);
  free(d->rinfo);
  free(d);
  s->be_data = NULL;
}

#define ARK_TRY(call) VI_SUN_TRY(call)

static int ark_create(vi_sim *s)
{
  int st = VI_OK, n = s->n;
  ark_data *d = calloc(1, sizeof *d);
  if (!d) return vi_fail(s->errmsg, VI_ERR_NOMEM, "out of memory");
  s->be_data = d;
  s->errmsg[0] = '\0';
  d->nq = s->led ? (s->nforces ? 5 : 4) * n : 0;
  d->N = 2 * n + d->nq;
  VI_CHECK(vi_rhs_create(s, &d->rhs) == VI_OK, s->errmsg, VI_ERR_NOMEM,
           "out of memory");
  d->B = dp87_table();
  VI_CHECK(d->B, s->errmsg, VI_ERR_NOMEM, "ARKODE Butcher table unavailable");
  d->ze = calloc((size_t)d->N * (5 + (size_t)d->B->stages), sizeof(double));
  d->rinfo = calloc(2 * (size_t)s->ns, sizeof(int));
  VI_CHECK(d->ze && d->rinfo, s->errmsg, VI_ERR_NOMEM, "out of memory");
  d->zd = d->ze + d->N;
  d->y0 = d->zd + d->N;
  d->yt = d->y0 + d->N;
  d->yo = d->yt + d->N;
  d->K = d->yo + d->N;
  VI_CHECK(SUNContext_Create(NULL, &d->ctx) == 0, s->errmsg, VI_ERR_NOMEM,
           "SUNContext_Create failed");
  d->y = N_VMake_Serial(d->N, d->ze, d->ctx);
  d->yd = N_VMake_Serial(d->N, d->zd, d->ctx);
  VI_CHECK(d->y && d->yd, s->errmsg, VI_ERR_NOMEM, "N_VMake_Serial failed");
  if (s->fast_nvector) vi_nvector_fast_ops(d->y); /* before ARKODE clones it */
  get_state(s, d);
  d->mem = ERKStepCreate(rhs, s->t, d->y, d->ctx);
  VI_CHECK(d->mem, s->errmsg, VI_ERR_NOMEM, "ERKStepCreate failed");
  ARK_TRY(ERKStepSetErrHandlerFn(d->mem, err_handler, s));
  ARK_TRY(ERKStepSetUserData(d->mem, s));
  ARK_TRY(ERKStepSetTable(d->mem, d->B));
  /* The interpolant only brackets ARKODE's roots: contacts, grazes and
   * dense output are computed on the Runge-Kutta step.  The cubic needs no
   * right-hand side per evaluation, the quintic four (a fifth of all on
   * Fig. 2). */
  ARK_TRY(ERKStepSetInterpolantDegree(d->mem, 3));
  ARK_TRY(ERKStepSStolerances(d->mem, s->rtol, s->atol));
  ARK_TRY(ERKStepSetMaxNumSteps(d->mem, -1)); /* no limit: vi_sim_run owns it */
  if (s->h_restart > 0.0) ARK_TRY(ERKStepSetInitStep(d->mem, s->h_restart));
cleanup:
  if (st) ark_destroy(s);
  return st;
}

static int64_t ark_stat(const void *data, int which)
{
  const ark_data *d = data;
  long v = 0;
  switch (which) {
  case VI_STAT_STEPS: ERKStepGetNumSteps(d->mem, &v); break;
  case VI_STAT_RHS_EVALS:
    ERKStepGetNumRhsEvals(d->mem, &v);
    v += d->polish_rhs;
    break;
  case VI_STAT_ROOT_EVALS: ERKStepGetNumGEvals(d->mem, &v); break;
  default: break;
  }
  return v;
}

/* Copy the extended state out to the driver's s->z (and the ledger's
 * integrals), or in from them. */
static void put_state(vi_sim *s, const double *ze)
{
  ark_data *d = s->be_data;
  memcpy(s->z, ze, sizeof(double) * 2 * s->n);
  if (d->nq)
    memcpy(vi_ledger_integrals(s->led), ze + 2 * (size_t)s->n, sizeof(double) * d->nq);
}

static void get_state(vi_sim *s, ark_data *d)
{
  memcpy(d->ze, s->z, sizeof(double) * 2 * s->n);
  if (d->nq)
    memcpy(d->ze + 2 * (size_t)s->n, vi_ledger_integrals(s->led), sizeof(double) * d->nq);
}

/* A restart keeps ARKODE's counters and, unlike a multistep method's, its
 * step size: ERKStepReset goes on with the step it had planned, which
 * suits the post-impact flow as well as the pre-impact one (the error
 * test cuts it if not). */
static int ark_start(vi_sim *s)
{
  int st = VI_OK;
  if (!s->be_data) {
    if ((st = ark_create(s))) return st;
  } else {
    ark_data *d = s->be_data;
    get_state(s, d);
    ARK_TRY(ERKStepReset(d->mem, s->t, d->y));
  }
  ark_data *d = s->be_data;
  /* a rebound's low flight: tolerances tightened (vi_sim.c, on_contact_one) */
  ARK_TRY(ERKStepSStolerances(d->mem, s->rtol * s->tol_scale, s->atol * s->tol_scale));
  int nr = s->nstick + 2 * (s->ns - s->nstick);
  if (nr != d->nroots) { /* the directions depend on nstick alone */
    int *dir = d->rinfo;
    for (int i = 0; i < nr; i++)
      dir[i] = i < s->nstick ? -1 : (i - s->nstick) % 2 ? -1 : 1;
    ARK_TRY(ERKStepRootInit(d->mem, nr, roots));
    ARK_TRY(ERKStepSetRootDirection(d->mem, dir));
    ARK_TRY(ERKStepSetNoInactiveRootWarn(d->mem));
    d->nroots = nr;
  }
  /* sticking: resolve the forcing so that the release root is seen (see
   * vi_cvode.c) */
  double hmax = s->hmax;
  if (s->sticking && s->m->omega_f > 0.0) {
    double h = vi_forcing_period(s->m->omega_f) / 32.0;
    hmax = hmax > 0.0 ? fmin(hmax, h) : h;
  }
  /* ARKODE sees a root only as a sign change between step ends: a step
   * longer than half the fastest period could hold a gap maximum and the
   * following minimum, whose rate root pair cancels (a contact missed:
   * the 4-mode beam at rtol 5e-7).  A quarter period keeps one rate sign
   * change per step for every mode. */
  double wmax = vi_model_omega_bound(s->m);
  if (wmax > 0.0 && isfinite(wmax)) {
    double h = 0.5 * M_PI / wmax;
    hmax = hmax > 0.0 ? fmin(hmax, h) : h;
  }
  ARK_TRY(ERKStepSetMaxStep(d->mem, hmax));
  /* after an impact the first step stays inside the rebound's flight
   * (vi_sim.c, on_contact_one); 0: ARKODE's own estimate */
  double h0 = s->h_restart;
  if (s->h_flight > 0.0) h0 = h0 > 0.0 ? fmin(h0, s->h_flight) : s->h_flight;
  s->h_flight = 0.0;
  if (h0 > 0.0) ARK_TRY(ERKStepSetInitStep(d->mem, h0)); /* else as before */
  d->t_prev = s->t;
  d->fresh = 1;
cleanup:
  return st;
}

/* One step of the Runge-Kutta method from (t0, y0) of length h into d->yo. */
static void rk_step(vi_sim *s, ark_data *d, double t0, double h)
{
  const struct ARKodeButcherTableMem *B = d->B;
  int N = d->N, S = B->stages;
  while (S > 1 && B->b[S - 1] == 0.0) S--; /* the FSAL stage: not needed */
  for (int i = 0; i < S; i++) {
    memcpy(d->yt, d->y0, sizeof(double) * N);
    for (int j = 0; j < i; j++) {
      double a = h * B->A[i][j];
      if (a == 0.0) continue;
      const double *kj = d->K + (size_t)j * N;
      for (int k = 0; k < N; k++) d->yt[k] += a * kj[k];
    }
    erk_f(s, d, t0 + B->c[i] * h, d->yt, d->K + (size_t)i * N);
  }
  memcpy(d->yo, d->y0, sizeof(double) * N);
  for (int i = 0; i < S; i++) {
    double b = h * B->b[i];
    if (b == 0.0) continue;
    const double *ki = d->K + (size_t)i * N;
    for (int k = 0; k < N; k++) d->yo[k] += b * ki[k];
  }
  d->polish_rhs += S;
}

/* Polish a contact that the interpolant puts at tc in the last step [t0, tn]:
 * Newton on G(t) = gap of the Runge-Kutta step from t0 to t (G' ~ w.x').
 * On success the state at the contact is the step's, in d->ze and s->z. */
static int polish(vi_sim *s, ark_data *d, double tc, double lo, double hi)
{
  double tn, h;
  ERKStepGetCurrentTime(d->mem, &tn);
  ERKStepGetLastStep(d->mem, &h);
  double t0 = tn - h;
  /* the Hermite interpolant reproduces the step's end points */
  if (ERKStepGetDky(d->mem, t0, 0, d->yd) < 0) return 0;
  memcpy(d->y0, d->zd, sizeof(double) * d->N);
  double t = tc;
  for (int it = 0; it < 8; it++) {
    const double *w = vi_stop_w(s->m, d->k);
    double g, gd, scale = fabs(s->m->xsv[d->k]);
    rk_step(s, d, t0, t - t0);
    if (s->force_failed) return 0;
    vi_sim_gap_k(s, d->k, d->yo, &g, &gd);
    if (!(gd > 0.0)) return 0;
    for (size_t i = 0; i < (size_t)s->n; i++) scale += fabs(w[i] * d->yo[2 * i]);
    double dt = -g / gd;
    /* converged in t, or the gap is at its round-off (a grazing contact's
     * slow rate turns one ulp of g into many of t) */
    if (fabs(dt) <= 4.0 * DBL_EPSILON * fabs(t) ||
        fabs(g) <= 4.0 * DBL_EPSILON * scale) {
      memcpy(d->ze, d->yo, sizeof(double) * d->N);
      put_state(s, d->ze);
      s->t = t;
      s->stats[VI_STAT_POLISHES]++;
      return 1;
    }
    t += dt;
    if (!(t >= lo && t <= hi)) return 0;
  }
  return 0;
}

/* A failed interpolation or polishing step: the host's force callback (the
 * quintic interpolant evaluates the right-hand side), or ARKODE. */
static int step_failed(vi_sim *s, const char *what, double t)
{
  if (s->force_failed)
    return vi_force_failure(s);
  return vi_fail(s->errmsg, VI_ERR_INTEGRATOR, "%s failed at t = %.17g", what, t);
}

/* The start of the last step into d->y0 and its time into *t0. */
static int step_start(ark_data *d, double *t0)
{
  double tn, h;
  if (ERKStepGetCurrentTime(d->mem, &tn) < 0 ||
      ERKStepGetLastStep(d->mem, &h) < 0 ||
      ERKStepGetDky(d->mem, tn - h, 0, d->yd) < 0) /* Hermite: exact there */
    return -1;
  memcpy(d->y0, d->zd, sizeof(double) * d->N);
  *t0 = tn - h;
  return 0;
}

typedef struct gap_ctx { vi_sim *s; ark_data *d; double t0; } gap_ctx;

/* The gap of stop d->k at t on a Runge-Kutta step from the last step's
 * start (d->y0): a grazing contact is a matter of the gap's last digits,
 * which the interpolant does not have. */
static double gap_at(double t, void *p)
{
  gap_ctx *c = p;
  double g, gd;
  rk_step(c->s, c->d, c->t0, t - c->t0);
  vi_sim_gap_k(c->s, c->d->k, c->d->yo, &g, &gd);
  return g;
}

/* The gap's maximum near t in the last step [t0, tn], on the step itself:
 * Newton on the rate w.x' (its derivative w.x'' from one more right-hand
 * side), from the interpolant's root.  Returns the gap there; *tm is the
 * time and d->yo the state.  Where the quadratic model at the first point
 * puts the maximum below `below` even with twice its rise, g + g'^2/|g''|,
 * that bound is returned at once (most maxima: far from the stop). */
static double step_max(vi_sim *s, ark_data *d, gap_ctx *c, double lo, double hi,
                       double below, double *tm)
{
  double t = *tm, g = gap_at(t, c);
  for (int it = 0; it < 4; it++) {
    double gd, gdd, dummy;
    vi_sim_gap_k(s, d->k, d->yo, &dummy, &gd);
    vi_rhs_rate(s, d->rhs, t, d->yo, d->yt);
    vi_sim_gap_k(s, d->k, d->yt, &dummy, &gdd);
    d->polish_rhs++;
    if (!(gdd < 0.0)) break;
    if (it == 0 && g - gd * gd / gdd < below) {
      *tm = t;
      return g - gd * gd / gdd;
    }
    double tn = fmin(hi, fmax(lo, t - gd / gdd));
    if (fabs(tn - t) <= 4.0 * DBL_EPSILON * fabs(t)) break;
    double gn = gap_at(tn, c);
    if (!(gn >= g)) { /* no better: keep the last point (and its state) */
      gap_at(t, c);
      break;
    }
    t = tn;
    g = gn;
  }
  *tm = t;
  return g;
}

/* A contact root at s->t: polish it.  Newton can fail on a grazing
 * contact, where the interpolant's root lies beyond the gap's maximum on
 * the step; then the first point where the step's own gap is non-negative
 * (the root, the step's maximum near it, or the step's end) brackets the
 * crossing.  Only if the step shows none is the interpolant's kept. */
static int on_root_contact(vi_sim *s, ark_data *d, int k, double lo,
                           double hi, int *event)
{
  *event = VI_STEP_CONTACT;
  s->contact_stop = d->k = k;
  double tr = s->t;
  if (polish(s, d, tr, lo, hi)) return VI_OK;
  gap_ctx c = {s, d, 0.0};
  if (step_start(d, &c.t0) == 0 && gap_at(lo, &c) < 0.0) {
    double b = tr;
    if (!(gap_at(b, &c) >= 0.0) && !(step_max(s, d, &c, lo, hi, 0.0, &b) >= 0.0))
      b = hi;
    if (gap_at(b, &c) >= 0.0) {
      double tc = b;
      int st = vi_sim_bracket(s, gap_at, &c, lo, b, &tc);
      if (st) return st;
      gap_at(tc, &c);
      memcpy(d->ze, d->yo, sizeof(double) * d->N);
      s->t = tc;
      if (!polish(s, d, tc, lo, b)) put_state(s, d->ze);
      return VI_OK;
    }
  }
  put_state(s, d->ze);
  return VI_OK;
}

/* A maximum of the gap at s->t (as vi_cvode.c): a positive gap there means
 * the contact was stepped over; locate the first crossing.  The interpolant
 * over an 8th-order step is too coarse to see a graze of the integration
 * error's depth, so the maximum and the crossing are found on the step
 * itself. */
static int graze_check(vi_sim *s, ark_data *d, int k, int *event)
{
  s->stats[VI_STAT_GRAZE_CHECKS]++;
  d->k = k;
  gap_ctx c = {s, d, 0.0};
  if (step_start(d, &c.t0) < 0) return step_failed(s, "ERKStepGetDky", s->t);
  double tn, lo = fmax(d->t_prev, c.t0), tmax = s->t;
  ERKStepGetCurrentTime(d->mem, &tn);
  /* a maximum within 1 % of the gap's error tolerance only touches: a
   * plastic impact's rebound returns to the stop tangentially, and the
   * last digits of the step would report spurious contacts there */
  double touch = 0.01 * (s->atol + s->rtol * fabs(s->m->xsv[k])) * s->wnorms[k];
  double g = step_max(s, d, &c, lo, tn, touch, &tmax);
  if (s->force_failed) return step_failed(s, "", tmax);
  if (!(g > touch)) return VI_OK;
  double tc = lo;
  if (gap_at(lo, &c) < 0.0) {
    int st = vi_sim_bracket(s, gap_at, &c, lo, tmax, &tc);
    if (st) return st;
  }
  gap_at(tc, &c);
  memcpy(d->ze, d->yo, sizeof(double) * d->N);
  s->t = tc;
  if (!polish(s, d, tc, lo, tmax)) put_state(s, d->ze);
  s->contact_stop = k;
  *event = VI_STEP_CONTACT;
  return VI_OK;
}

static int ark_step(vi_sim *s, double t_end, int *event)
{
  ark_data *d = s->be_data;
  int st = VI_OK;
  *event = VI_STEP_NONE;
  ARK_TRY(ERKStepSetStopTime(d->mem, t_end));
  double t = s->t;
  int flag = ERKStepEvolve(d->mem, t_end, d->y, &t, ARK_ONE_STEP);
  if (flag == ARK_ILL_INPUT && d->continued) {
    /* as CVODE: a root function that stays zero at the root we go on from;
     * a restart from the same state clears the root history */
    s->errmsg[0] = '\0';
    if ((st = ark_start(s))) return st;
    s->stats[VI_STAT_REINITS]++;
    ARK_TRY(ERKStepSetStopTime(d->mem, t_end));
    flag = ERKStepEvolve(d->mem, t_end, d->y, &t, ARK_ONE_STEP);
  }
  d->continued = 0;
  d->fresh = 0;
  if (flag < 0 && s->force_failed)
    return vi_force_failure(s);
  if (flag < 0) {
    if (!s->errmsg[0])
      vi_fail(s->errmsg, VI_ERR_INTEGRATOR,
              "ERKStepEvolve failed (flag %d) at t = %g", flag, t);
    return VI_ERR_INTEGRATOR;
  }
  s->t = t;
  put_state(s, d->ze);
  if (flag == ARK_ROOT_RETURN) {
    int *info = d->rinfo, kc = -1;
    ERKStepGetRootInfo(d->mem, info);
    /* a contact first (the driver looks at the other stops at that
     * instant), then a held stop's release, else the gap maxima's grazing
     * checks in stop order (layout of vi_sim_gap_root) */
    int rel = -1;
    for (int i = 0; i < s->nstick; i++)
      if (info[i] && rel < 0) rel = s->stick_k[i];
    for (int k = 0; k < s->ns && kc < 0; k++) {
      int i = vi_sim_gap_root(s, k);
      if (i >= 0 && info[i]) kc = k;
    }
    if (kc >= 0) {
      double tn, hu;
      ERKStepGetCurrentTime(d->mem, &tn);
      ERKStepGetLastStep(d->mem, &hu);
      st = on_root_contact(s, d, kc, fmax(d->t_prev, tn - hu), tn, event);
    } else if (rel >= 0) {
      *event = VI_STEP_RELEASE;
      s->contact_stop = rel;
    }
    for (int k = 0; k < s->ns && kc < 0 && *event == VI_STEP_NONE && !st; k++) {
      int i = vi_sim_gap_root(s, k);
      if (i >= 0 && info[i + 1]) st = graze_check(s, d, k, event);
    }
    d->continued = *event == VI_STEP_NONE;
  }
  d->t_prev = s->t;
cleanup:
  return st;
}

/* The state at t inside the last step, from a Runge-Kutta step of the
 * method itself from the step's start: 8th order, where even ARKODE's
 * quintic Hermite interpolant loses digits over the long steps of an
 * 8th-order pair (2.5e-7 against a closed form at rtol 1e-10). */
static int ark_dense(vi_sim *s, double t)
{
  ark_data *d = s->be_data;
  if (d->fresh && t == s->t) { /* a sample at the start point itself */
    memcpy(s->zs, s->z, sizeof(double) * 2 * s->n);
    return VI_OK;
  }
  double t0;
  if (d->fresh || step_start(d, &t0) < 0) return step_failed(s, "ERKStepGetDky", t);
  rk_step(s, d, t0, t - t0);
  if (s->force_failed) return step_failed(s, "", t);
  memcpy(s->zs, d->yo, sizeof(double) * 2 * s->n);
  return VI_OK;
}

const vi_backend vi_backend_arkode = {"arkode", ark_start, ark_step, ark_dense,
                                      ark_stat, ark_destroy, NULL, NULL,
                                      NULL, NULL, NULL};
