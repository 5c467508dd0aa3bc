/* vi_arkode.c - ARKODE backend: the explicit Runge-Kutta method of order 8
 * (Fehlberg 13-7-8, ARKODE's ERKStep) with ARKODE's root finding on the gap
 * and its rate.  A one-step method has no order ramp after an impact: it
 * restarts at full order with the step size it had.
 *
 * ARKODE has no quadratures, so the ledger integrals ride along as extra
 * state components under the same error control.  ARKODE locates roots on
 * its Hermite interpolant (degree <= 5), much less accurate than an
 * 8th-order step, so each contact is polished on the Runge-Kutta step
 * itself: Newton on the step length from the start of the step, which also
 * gives the state at the contact to the step's accuracy. */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include <arkode/arkode_erkstep.h>
#include <nvector/nvector_serial.h>

#include "vi_rhs.h"

/* of ARKODE's explicit tables the cheapest per accuracy on Fig. 2 (Verner
 * 8-5-6 and Dormand-Prince 7-4-5 need 3x and 1.2-1.4x the evaluations) */
#define VI_ERK_TABLE ARKODE_FEHLBERG_13_7_8

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
  int nroots;     /* 2 in free flight, 1 while sticking; 0 before a start */
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
    double Lambda = 0.0, *gq = NULL;
    if (s->sticking) {
      vi_sim_accel(s, t, z, 0, d->rhs->acc);
      Lambda = vi_dot(s->n, s->m->w, d->rhs->acc) / s->m->wMw;
    }
    if (s->nforces) {
      gq = s->fbuf + 3 * n;
      vi_force_modal(s, t, z, gq);
    }
    vi_ledger_rates_state(s->led, t, z, Lambda, gq, zd + 2 * n);
  }
}

static int rhs(double t, N_Vector y, N_Vector yd, void *user)
{
  vi_sim *s = user;
  erk_f(s, s->be_data, t, N_VGetArrayPointer(y), N_VGetArrayPointer(yd));
  return s->force_failed ? -1 : 0; /* the host's force failed: stop */
}

/* As vi_cvode.c: contact (g rising), gap maxima (g' falling), and while
 * sticking the free normal acceleration falling through zero. */
static int roots(double t, N_Vector y, double *g, void *user)
{
  vi_sim *s = user;
  const double *z = N_VGetArrayPointer(y);
  if (s->sticking) {
    vi_sim_accel(s, t, z, 0, s->vp);
    g[0] = vi_dot(s->n, s->m->w, s->vp);
  } else {
    vi_sim_gap(s, z, &g[0], &g[1]);
  }
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
  d->B = ARKodeButcherTable_LoadERK(VI_ERK_TABLE);
  VI_CHECK(d->B, s->errmsg, VI_ERR_NOMEM, "ARKODE Butcher table unavailable");
  d->ze = calloc((size_t)d->N * (5 + (size_t)d->B->stages), sizeof(double));
  VI_CHECK(d->ze, s->errmsg, VI_ERR_NOMEM, "out of memory");
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
  int nr = s->sticking ? 1 : 2;
  if (nr != d->nroots) {
    int dir[2] = {s->sticking ? -1 : 1, -1};
    ARK_TRY(ERKStepRootInit(d->mem, nr, roots));
    ARK_TRY(ERKStepSetRootDirection(d->mem, dir));
    ARK_TRY(ERKStepSetNoInactiveRootWarn(d->mem));
    d->nroots = nr;
  }
  /* sticking: resolve the forcing so that the release root is seen (see
   * vi_cvode.c) */
  double hmax = s->hmax;
  if (s->sticking && s->m->omega_f > 0.0) {
    double h = 2.0 * M_PI / s->m->omega_f / 32.0;
    hmax = hmax > 0.0 ? fmin(hmax, h) : h;
  }
  ARK_TRY(ERKStepSetMaxStep(d->mem, hmax));
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
    double g, gd;
    rk_step(s, d, t0, t - t0);
    if (s->force_failed) return 0;
    vi_sim_gap(s, d->yo, &g, &gd);
    if (!(gd > 0.0)) return 0;
    double dt = -g / gd;
    if (fabs(dt) <= 4.0 * DBL_EPSILON * fabs(t) || g == 0.0) {
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

/* The gap at t on a Runge-Kutta step from the last step's start (d->y0):
 * a grazing contact is a matter of the gap's last digits, which the cubic
 * interpolant does not have. */
static double gap_at(double t, void *p)
{
  gap_ctx *c = p;
  double g, gd;
  rk_step(c->s, c->d, c->t0, t - c->t0);
  vi_sim_gap(c->s, c->d->yo, &g, &gd);
  return g;
}

/* A contact root at s->t: polish it.  Newton can fail on a grazing
 * contact, where the interpolant's root lies beyond the gap's maximum on
 * the step; then the first point of [lo, hi] where the step's own gap is
 * non-negative (the root, the step's end, or a scan between) brackets the
 * crossing.  Only if the step shows none is the interpolant's kept. */
static int on_root_contact(vi_sim *s, ark_data *d, double lo, double hi,
                           int *event)
{
  *event = VI_STEP_CONTACT;
  double tr = s->t;
  if (polish(s, d, tr, lo, hi)) return VI_OK;
  gap_ctx c = {s, d, 0.0};
  if (step_start(d, &c.t0) == 0 && gap_at(lo, &c) < 0.0) {
    double b = tr;
    if (!(gap_at(b, &c) >= 0.0)) b = hi;
    for (int k = 1; k < 16 && !(gap_at(b, &c) >= 0.0); k++)
      b = lo + (hi - lo) * k / 16.0;
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

/* The gap at t on ARKODE's interpolant. */
static double gap_interp(double t, void *p)
{
  gap_ctx *c = p;
  double g, gd;
  ERKStepGetDky(c->d->mem, t, 0, c->d->yd);
  vi_sim_gap(c->s, c->d->zd, &g, &gd);
  return g;
}

/* A maximum of the gap at s->t (as vi_cvode.c): a positive gap there means
 * the contact was stepped over; locate the first crossing, on the step
 * itself where the step shows it, else on the interpolant.  Whether the
 * maximum crosses is read on the interpolant, as CVODE does: where the
 * true maximum just touches the stop (a plastic impact's rebound) either
 * answer is within the error. */
static int graze_check(vi_sim *s, ark_data *d, int *event)
{
  double g, gd;
  vi_sim_gap(s, s->z, &g, &gd);
  s->stats[VI_STAT_GRAZE_CHECKS]++;
  if (g <= 0.0) return VI_OK;
  gap_ctx c = {s, d, 0.0};
  if (step_start(d, &c.t0) < 0)
    return vi_fail(s->errmsg, VI_ERR_INTEGRATOR, "ERKStepGetDky failed");
  double tmax = s->t, lo = fmax(d->t_prev, c.t0), tc = lo;
  double (*gap)(double, void *) = gap_at(tmax, &c) > 0.0 ? gap_at : gap_interp;
  if (gap(lo, &c) < 0.0) {
    int st = vi_sim_bracket(s, gap, &c, lo, tmax, &tc);
    if (st) return st;
  }
  gap_at(tc, &c);
  memcpy(d->ze, d->yo, sizeof(double) * d->N);
  s->t = tc;
  if (!polish(s, d, tc, lo, tmax)) put_state(s, d->ze);
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
    return vi_fail(s->errmsg, VI_ERR_CALLBACK, "the host's force callback "
                   "failed at t = %.17g", s->force_fail_t);
  if (flag < 0) {
    if (!s->errmsg[0])
      vi_fail(s->errmsg, VI_ERR_INTEGRATOR,
              "ERKStepEvolve failed (flag %d) at t = %g", flag, t);
    return VI_ERR_INTEGRATOR;
  }
  s->t = t;
  put_state(s, d->ze);
  if (flag == ARK_ROOT_RETURN) {
    int info[2] = {0, 0};
    ERKStepGetRootInfo(d->mem, info);
    if (s->sticking) *event = info[0] ? VI_STEP_RELEASE : VI_STEP_NONE;
    else if (info[0]) {
      double tn, hu;
      ERKStepGetCurrentTime(d->mem, &tn);
      ERKStepGetLastStep(d->mem, &hu);
      st = on_root_contact(s, d, fmax(d->t_prev, tn - hu), tn, event);
    } else if (info[1]) st = graze_check(s, d, event);
    d->continued = *event == VI_STEP_NONE;
  }
  d->t_prev = s->t;
cleanup:
  return st;
}

static int ark_dense(vi_sim *s, double t)
{
  ark_data *d = s->be_data;
  if (d->fresh && t == s->t) { /* a sample at the start point itself */
    memcpy(s->zs, s->z, sizeof(double) * 2 * s->n);
    return VI_OK;
  }
  if (d->fresh || ERKStepGetDky(d->mem, t, 0, d->yd) < 0)
    return vi_fail(s->errmsg, VI_ERR_INTEGRATOR,
                   "ERKStepGetDky failed at t = %.17g", t);
  memcpy(s->zs, d->zd, sizeof(double) * 2 * s->n);
  return VI_OK;
}

const vi_backend vi_backend_arkode = {"arkode", ark_start, ark_step, ark_dense,
                                      ark_stat, ark_destroy, NULL, NULL};
