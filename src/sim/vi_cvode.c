/* vi_cvode.c - CVODE(S) backend: Adams/fixed-point or BDF/Newton with the
 * analytic (constant) Jacobian, root functions for contact, maxima of the
 * gap (grazing) and release from sticking. */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include <cvodes/cvodes.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_band.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_band.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include "vi_forcing.h"
#include "vi_band_internal.h"
#include "vi_rhs.h"

typedef struct cv_data {
  SUNContext ctx;
  void *mem;
  vi_rhs *rhs;    /* the right-hand side's packed coefficients */
  N_Vector y;     /* wraps s->z: CVODE writes the state in place */
  N_Vector ys;    /* wraps s->zs: interpolant output */
  N_Vector yQ;    /* wraps s->Q: ledger quadratures, NULL without a ledger */
  SUNMatrix A;
  SUNLinearSolver LS;
  SUNNonlinearSolver NLS;
  int nroots;     /* 2 in free flight, 1 while sticking (one stop) */
  int rstick[VI_CONTACT_MAX + 1]; /* the sticking set the roots were set
                                     for: count, then the stops */
  int *info;      /* root info [2 ns] */
  long base[4];   /* steps, rhs, jac, root evals before the last ReInit */
  double t_prev;  /* time of the previous return */
  double *zprev;  /* state [2n] and ledger integrals [5n] at t_prev */
  int continued;  /* the last step ended on a root we integrated through */
} cv_data;

static int rhs(double t, N_Vector y, N_Vector yd, void *user)
{
  vi_sim *s = user;
  cv_data *d = s->be_data;
  vi_rhs_rate(s, d->rhs, t, N_VGetArrayPointer(y), N_VGetArrayPointer(yd));
  return s->force_failed ? -1 : 0; /* the host's force failed: stop */
}

/* Free flight: g0 = w.x - x_s rising (contact), g1 = w.x' falling (a maximum
 * of the gap, where a grazing contact inside one step is looked for).
 * Sticking: g0 = w.a_free falling (the contact force lambda through zero).
 * Several stops: first the contact force of each sticking stop (its
 * multiplier lambda_k of G_SS^-1 W_S^T a_free, falling), then the pair
 * (gap rising, rate falling) of every other stop in order. */
static int roots(double t, N_Vector y, double *g, void *user)
{
  vi_sim *s = user;
  const double *z = N_VGetArrayPointer(y);
  if (s->ns == 1) {
    if (s->sticking) {
      vi_sim_accel(s, t, z, 0, s->vp);
      g[0] = vi_dot(s->n, s->m->Ws, s->vp);
    } else {
      vi_sim_gap(s, z, &g[0], &g[1]);
    }
    return 0;
  }
  vi_sim_roots_layout(s, t, z, g);
  return 0;
}

/* J = [[0, I], [-M^-1 K, -M^-1 C]] in interleaved order; while sticking the
 * rows of the acceleration are projected like the RHS. */
static void jac_entries(vi_sim *s, SUNMatrix J, int band)
{
  const vi_model *m = s->m;
  int n = s->n, bw = band ? m->bw : n;
  double *col = s->zs; /* 2n scratch: one column of d(acc)/dz */
  for (int jz = 0; jz < 2 * n; jz++) {
    int j = jz / 2;
    const double *src = m->ops->minv_col(m, jz % 2, j);
    for (int i = 0; i < n; i++) col[i] = -src[i];
    if (s->sticking) vi_sim_constrain(s, col, NULL);
    int i0 = j - bw < 0 ? 0 : j - bw, i1 = j + bw >= n ? n - 1 : j + bw;
    for (int i = i0; i <= i1; i++) {
      if (band) SM_ELEMENT_B(J, 2 * i + 1, jz) = col[i];
      else SM_ELEMENT_D(J, 2 * i + 1, jz) = col[i];
    }
    if (jz % 2) { /* d(x_j')/d(v_j) = 1 */
      if (band) SM_ELEMENT_B(J, jz - 1, jz) = 1.0;
      else SM_ELEMENT_D(J, jz - 1, jz) = 1.0;
    }
  }
}

/* With nonlinear forces the Jacobian depends on the state: the linear part
 * plus d(M^-1 g)/dx, d(M^-1 g)/dv (vi_force.c), dense, projected while
 * sticking like the right-hand side. */
static int jac_forced(vi_sim *s, double t, const double *z, SUNMatrix J)
{
  const vi_model *m = s->m;
  int n = s->n;
  double *Ax, *Av;
  if (vi_force_jacobian(s, t, z, &Ax, &Av)) return -1;
  double *col = s->zs;
  for (int jz = 0; jz < 2 * n; jz++) {
    int j = jz / 2;
    const double *lin = m->ops->minv_col(m, jz % 2, j);
    const double *nl = (jz % 2 ? Av : Ax) + (size_t)j * n;
    for (int i = 0; i < n; i++) col[i] = nl[i] - lin[i];
    if (s->sticking) vi_sim_constrain(s, col, NULL);
    for (int i = 0; i < n; i++) SM_ELEMENT_D(J, 2 * i + 1, jz) = col[i];
    if (jz % 2) SM_ELEMENT_D(J, jz - 1, jz) = 1.0;
  }
  return 0;
}

static int jac(double t, N_Vector y, N_Vector fy, SUNMatrix J, void *user,
               N_Vector t1, N_Vector t2, N_Vector t3)
{
  (void)fy; (void)t1; (void)t2; (void)t3;
  vi_sim *s = user;
  SUNMatZero(J);
  /* no dense M^-1 K (band storage): assembled by vi_band.c */
  if (!s->m->ops->minv_col) return vi_band_jac(s, J);
  if (s->nforces) return jac_forced(s, t, N_VGetArrayPointer(y), J);
  jac_entries(s, J, SUNMatGetID(J) == SUNMATRIX_BAND);
  return 0;
}

/* Ledger integrands FE', DE', XE', CE', NE' (vi_ledger.c); CE from the
 * reactions of whichever stops are held. */
static int qrhs(double t, N_Vector y, N_Vector yQd, void *user)
{
  vi_sim *s = user;
  const double *z = N_VGetArrayPointer(y);
  double lam[VI_CONTACT_MAX];
  vi_ledger_held h;
  vi_sim_held_reactions(s, t, z, lam, &h);
  double *gq = NULL;
  if (s->nforces) { /* the modal force, for the NE column */
    gq = s->fbuf + 3 * (size_t)s->n;
    vi_force_modal(s, t, z, gq);
  }
  vi_ledger_rates_state(s->led, t, z, &h, gq, N_VGetArrayPointer(yQd));
  return 0;
}

/* CVODE would print to stderr; keep the message for vi_sim_errmsg. */
static void err_handler(int code, const char *module, const char *function,
                        char *msg, void *user)
{
  vi_sim *s = user;
  if (code < 0)
    vi_fail(s->errmsg, VI_ERR_INTEGRATOR, "%s %s (%d): %s", module, function,
            code, msg);
}

static void cv_destroy(vi_sim *s)
{
  cv_data *d = s->be_data;
  if (!d) return;
  CVodeFree(&d->mem);
  SUNNonlinSolFree(d->NLS);
  SUNLinSolFree(d->LS);
  SUNMatDestroy(d->A);
  N_VDestroy(d->y);
  N_VDestroy(d->ys);
  N_VDestroy(d->yQ);
  SUNContext_Free(&d->ctx);
  free(d->zprev);
  free(d->info);
  vi_rhs_destroy(&d->rhs);
  free(d);
  s->be_data = NULL;
}

/* The band solver pays when the interleaved bandwidth is well below 2n and
 * the sticking projection keeps the band (stop on one coordinate of a
 * diagonal-mass chain). */
static int use_band(const vi_sim *s)
{
  const vi_model *m = s->m;
  int n = s->n;
  if (s->nforces) return 0; /* a force may couple any coordinates */
  /* each stop on one coordinate: the projection touches only its rows */
  for (int k = 0; k < m->ns; k++) {
    const double *w = vi_stop_w(m, k), *mw = vi_stop_minvw(m, k);
    int nz = 0;
    for (int i = 0; i < n; i++) {
      if (mw[i] != 0.0) nz++;
      if ((mw[i] != 0.0) != (w[i] != 0.0)) return 0;
    }
    if (nz != 1) return 0;
  }
  return 4 * m->bw + 2 < n;
}

#define CV_TRY(call) VI_SUN_TRY(call)

static int cv_create(vi_sim *s)
{
  int st = VI_OK, N = 2 * s->n;
  cv_data *d = calloc(1, sizeof *d);
  if (!d) return vi_fail(s->errmsg, VI_ERR_NOMEM, "out of memory");
  s->be_data = d;
  s->errmsg[0] = '\0';
  d->zprev = malloc(sizeof(double) * (2 + VI_LEDGER_BLOCKS) * (size_t)s->n);
  d->info = calloc(2 * (size_t)s->ns, sizeof(int));
  VI_CHECK(d->zprev && d->info && vi_rhs_create(s, &d->rhs) == VI_OK,
           s->errmsg, VI_ERR_NOMEM, "out of memory");
  VI_CHECK(SUNContext_Create(NULL, &d->ctx) == 0, s->errmsg, VI_ERR_NOMEM,
           "SUNContext_Create failed");
  d->y = N_VMake_Serial(N, s->z, d->ctx);
  d->ys = N_VMake_Serial(N, s->zs, d->ctx);
  VI_CHECK(d->y && d->ys, s->errmsg, VI_ERR_NOMEM, "N_VMake_Serial failed");
  if (s->fast_nvector) vi_nvector_fast_ops(d->y); /* before CVODE clones it */
  d->mem = CVodeCreate(s->method == VI_METHOD_BDF ? CV_BDF : CV_ADAMS, d->ctx);
  VI_CHECK(d->mem, s->errmsg, VI_ERR_NOMEM, "CVodeCreate failed");
  CV_TRY(CVodeSetErrHandlerFn(d->mem, err_handler, s));
  CV_TRY(CVodeInit(d->mem, rhs, s->t, d->y));
  CV_TRY(CVodeSetUserData(d->mem, s));
  CV_TRY(CVodeSStolerances(d->mem, s->rtol, s->atol));
  CV_TRY(CVodeSetNoInactiveRootWarn(d->mem));
  if (s->method == VI_METHOD_BDF) {
    int bw = s->m->bw;
    VI_CHECK(use_band(s) || s->n <= s->m->ops->dense_jac_max, s->errmsg,
             VI_ERR_UNSUPPORTED, "BDF on this band model needs a dense "
             "Jacobian (M not diagonal, or a stop on several coordinates): "
             "use adams or erk");
    d->A = use_band(s) ? SUNBandMatrix(N, bw > 0 ? 2 * bw : 1, 2 * bw + 1, d->ctx)
                       : SUNDenseMatrix(N, N, d->ctx);
    VI_CHECK(d->A, s->errmsg, VI_ERR_NOMEM, "matrix allocation failed");
    d->LS = SUNMatGetID(d->A) == SUNMATRIX_BAND
                ? SUNLinSol_Band(d->y, d->A, d->ctx)
                : SUNLinSol_Dense(d->y, d->A, d->ctx);
    VI_CHECK(d->LS, s->errmsg, VI_ERR_NOMEM, "linear solver allocation failed");
    CV_TRY(CVodeSetLinearSolver(d->mem, d->LS, d->A));
    CV_TRY(CVodeSetJacFn(d->mem, jac));
  } else {
    /* non-stiff: fixed-point iteration needs no Jacobian at all */
    d->NLS = SUNNonlinSol_FixedPoint(d->y, 0, d->ctx);
    VI_CHECK(d->NLS, s->errmsg, VI_ERR_NOMEM, "fixed-point solver failed");
    CV_TRY(CVodeSetNonlinearSolver(d->mem, d->NLS));
  }
  if (s->led) {
    /* under the state's error control, so the ledger closes to tolerance */
    d->yQ = N_VMake_Serial((sunindextype)(s->nforces ? 5 : 4) * s->n,
                           vi_ledger_integrals(s->led), d->ctx);
    VI_CHECK(d->yQ, s->errmsg, VI_ERR_NOMEM, "N_VMake_Serial failed");
    if (s->fast_nvector) vi_nvector_fast_ops(d->yQ);
    CV_TRY(CVodeQuadInit(d->mem, qrhs, d->yQ));
    CV_TRY(CVodeQuadSStolerances(d->mem, s->rtol, s->atol));
    CV_TRY(CVodeSetQuadErrCon(d->mem, 1));
  }
  d->nroots = 0;
cleanup:
  if (st) cv_destroy(s);
  return st;
}

static int64_t cv_live(const cv_data *d, int which)
{
  long v = 0;
  switch (which) {
  case VI_STAT_STEPS: CVodeGetNumSteps(d->mem, &v); break;
  case VI_STAT_RHS_EVALS: CVodeGetNumRhsEvals(d->mem, &v); break;
  case VI_STAT_JAC_EVALS: if (d->LS) CVodeGetNumJacEvals(d->mem, &v); break;
  case VI_STAT_ROOT_EVALS: CVodeGetNumGEvals(d->mem, &v); break;
  default: break;
  }
  return v;
}

static int64_t cv_stat(const void *data, int which)
{
  const cv_data *d = data;
  if (which < 0 || which > VI_STAT_ROOT_EVALS) return 0;
  return d->base[which] + cv_live(d, which);
}

static void save_prev(vi_sim *s, cv_data *d);

static int cv_start(vi_sim *s)
{
  int st = VI_OK;
  if (!s->be_data && (st = cv_create(s))) return st;
  cv_data *d = s->be_data;
  /* ReInit zeroes CVODE's counters: bank them first */
  for (int k = 0; k <= VI_STAT_ROOT_EVALS; k++) d->base[k] += cv_live(d, k);
  CV_TRY(CVodeReInit(d->mem, s->t, d->y));
  if (d->yQ) CV_TRY(CVodeQuadReInit(d->mem, d->yQ));
  /* a rebound's low flight: tolerances tightened (vi_sim.c, on_contact_one) */
  CV_TRY(CVodeSStolerances(d->mem, s->rtol * s->tol_scale, s->atol * s->tol_scale));
  if (s->ns == 1) {
    int nr = s->sticking ? 1 : 2;
    if (nr != d->nroots) {
      int dir[2] = {s->sticking ? -1 : 1, -1};
      CV_TRY(CVodeRootInit(d->mem, nr, roots));
      CV_TRY(CVodeSetRootDirection(d->mem, dir));
      d->nroots = nr;
    }
  } else if (d->nroots == 0 || d->rstick[0] != s->nstick ||
             memcmp(d->rstick + 1, s->stick_k, sizeof(int) * s->nstick) != 0) {
    /* the layout of roots() follows the sticking set */
    int nr = s->nstick + 2 * (s->ns - s->nstick), *dir = d->info;
    for (int i = 0; i < nr; i++)
      dir[i] = i < s->nstick ? -1 : (i - s->nstick) % 2 ? -1 : 1;
    CV_TRY(CVodeRootInit(d->mem, nr, roots));
    CV_TRY(CVodeSetRootDirection(d->mem, dir));
    d->nroots = nr;
    d->rstick[0] = s->nstick;
    memcpy(d->rstick + 1, s->stick_k, sizeof(int) * s->nstick);
  }
  if (s->h_restart > 0.0) CV_TRY(CVodeSetInitStep(d->mem, s->h_restart));
  s->h_flight = 0.0; /* ERK's hint (vi_arkode.c); CVODE's own first step
                        after a restart is small enough */
  /* While sticking the state barely moves, so CVODE's error control lets
   * the step grow past oscillations of the contact force that the release
   * root must see: resolve the forcing instead. */
  double hmax = s->hmax;
  if (s->sticking && s->m->omega_f > 0.0) {
    double h = vi_forcing_period(s->m->omega_f) / 32.0;
    hmax = hmax > 0.0 ? fmin(hmax, h) : h;
  }
  CV_TRY(CVodeSetMaxStep(d->mem, hmax));
  save_prev(s, d);
cleanup:
  return st;
}

/* Keep the state of the last return: a contact located on the interpolant
 * can be re-integrated from it (cv_polish). */
static void save_prev(vi_sim *s, cv_data *d)
{
  d->t_prev = s->t;
  memcpy(d->zprev, s->z, sizeof(double) * 2 * (size_t)s->n);
  if (d->yQ)
    memcpy(d->zprev + 2 * (size_t)s->n, vi_ledger_integrals(s->led),
           sizeof(double) * VI_LEDGER_BLOCKS * (size_t)s->n);
}

/* Near grazing the approach speed v_n is small and a position error dx of
 * the located contact becomes a speed error g'' dx / v_n.  CVODE's root
 * lies on the interpolant of its last (large) step, whose error exceeds
 * that of the step ends, so when the amplification matters the piece from
 * the previous return is integrated again with the root found on its own,
 * short steps, and a contact time still short of the stop is polished by
 * Newton steps on the gap, landing each on a step end (CVODE's stop time). */
static int cv_polish(vi_sim *s)
{
  cv_data *d = s->be_data;
  int st = VI_OK, n = s->n, k = s->contact_stop, groot = vi_sim_gap_root(s, k);
  double tc = s->t, t = d->t_prev, g, gd, xs = s->m->xsv[k];
  if (groot < 0) return VI_OK;
  vi_sim_gap_k(s, k, s->z, &g, &gd);
  vi_sim_accel(s, s->t, s->z, s->sticking, s->vp);
  double p = fabs(vi_dot(n, vi_stop_w(s->m, k), s->vp));
  double dx = s->atol * s->wnorms[k] + s->rtol * fabs(xs);
  if (!(gd > 0.0) || p * dx <= 100.0 * s->rtol * gd * gd || !(tc > t))
    return VI_OK;
  memcpy(s->z, d->zprev, sizeof(double) * 2 * (size_t)n);
  if (d->yQ)
    memcpy(vi_ledger_integrals(s->led), d->zprev + 2 * (size_t)n,
           sizeof(double) * VI_LEDGER_BLOCKS * (size_t)n);
  CV_TRY(CVodeReInit(d->mem, t, d->y));
  if (d->yQ) CV_TRY(CVodeQuadReInit(d->mem, d->yQ));
  s->stats[VI_STAT_POLISHES]++;
  double tstop = tc;
  for (int it = 0; it < 8; it++) {
    CV_TRY(CVodeSetStopTime(d->mem, tstop));
    int flag = CVode(d->mem, tstop, d->y, &t, CV_NORMAL);
    if (flag < 0) {
      st = VI_ERR_INTEGRATOR;
      goto cleanup;
    }
    if (d->yQ) CV_TRY(CVodeGetQuad(d->mem, &t, d->yQ));
    vi_sim_gap_k(s, k, s->z, &g, &gd);
    if (flag == CV_ROOT_RETURN) {
      CVodeGetRootInfo(d->mem, d->info);
      if (d->info[groot]) break; /* the contact, on the short steps'
                                    interpolant */
      continue;
    }
    /* at the stop time, a step end: done once on the stop to round-off */
    if (g >= -4.0 * DBL_EPSILON * fabs(xs) || !(gd > 0.0)) break;
    tstop = t - g / gd;
  }
  s->t = t;
cleanup:
  return st;
}

typedef struct gap_ctx { vi_sim *s; cv_data *d; int k; } gap_ctx;

static double gap_at(double t, void *p)
{
  gap_ctx *c = p;
  double g, gd;
  CVodeGetDky(c->d->mem, t, 0, c->d->ys);
  vi_sim_gap_k(c->s, c->k, c->s->zs, &g, &gd);
  return g;
}

/* A maximum of the gap was found at s->t.  If the gap is positive there, the
 * contact was stepped over (two crossings inside one step: grazing); locate
 * the first crossing on the interpolant and report it as the contact. */
static int graze_check(vi_sim *s, cv_data *d, int k, int *event)
{
  double g, gd;
  vi_sim_gap_k(s, k, s->z, &g, &gd);
  s->stats[VI_STAT_GRAZE_CHECKS]++;
  if (g <= 0.0) return VI_OK;
  double tn, hu, lo;
  CVodeGetCurrentTime(d->mem, &tn);
  CVodeGetLastStep(d->mem, &hu);
  lo = fmax(d->t_prev, tn - hu);
  gap_ctx c = {s, d, k};
  double tc = lo;
  if (gap_at(lo, &c) < 0.0) {
    int st = vi_sim_bracket(s, gap_at, &c, lo, s->t, &tc);
    if (st) return st;
  }
  if (CVodeGetDky(d->mem, tc, 0, d->y) < 0 ||
      (d->yQ && CVodeGetQuadDky(d->mem, tc, 0, d->yQ) < 0))
    return vi_fail(s->errmsg, VI_ERR_INTEGRATOR, "CVodeGetDky failed");
  s->t = tc;
  s->contact_stop = k;
  *event = VI_STEP_CONTACT;
  return VI_OK;
}

/* While sticking the held gaps are kept by the projected acceleration
 * alone, so the integration error makes them drift (random-walk-like: no
 * local error test bounds it).  Once a held gap is off by a tenth of what
 * the invariant check allows, put the state back on the held stops - the
 * M-orthogonal projection of positions, and of velocities so that w_k.v =
 * 0 - and restart from it: the penetration a projection leaves is
 * round-off, and a stop not held is still checked at its own tolerance. */
static int hold_drift(vi_sim *s)
{
  const vi_model *m = s->m;
  int n = s->n, over = 0;
  double g[VI_CONTACT_MAX];
  for (int i = 0; i < s->nstick; i++) {
    int k = s->stick_k[i];
    double gd;
    vi_sim_gap_k(s, k, s->z, &g[i], &gd);
    over |= !(fabs(g[i]) <= 0.1 * vi_sim_gap_tol(s, k));
  }
  if (!over) return VI_OK;
  double *x = s->w2, *v = s->w1;
  for (int i = 0; i < n; i++) {
    x[i] = s->z[2 * (size_t)i];
    v[i] = s->z[2 * (size_t)i + 1];
  }
  vi_small_solve(s->nstick, s->stick_L, g); /* G_SS^-1 (W^T x - x_S) */
  for (int i = 0; i < s->nstick; i++) {
    const double *mw = vi_stop_minvw(m, s->stick_k[i]);
    for (int j = 0; j < n; j++) x[j] -= g[i] * mw[j];
  }
  vi_sim_constrain(s, v, NULL);
  for (int i = 0; i < n; i++) {
    s->z[2 * (size_t)i] = x[i];
    s->z[2 * (size_t)i + 1] = v[i];
  }
  s->stats[VI_STAT_REINITS]++;
  return cv_start(s);
}

static int cv_step(vi_sim *s, double t_end, int *event)
{
  cv_data *d = s->be_data;
  int st = VI_OK;
  *event = VI_STEP_NONE;
  save_prev(s, d);
  CV_TRY(CVodeSetStopTime(d->mem, t_end));
  double t;
  int flag = CVode(d->mem, t_end, d->y, &t, CV_ONE_STEP);
  if (flag == CV_ILL_INPUT && d->continued) {
    /* CVODE refuses to go on from a root at which a root function stays
     * exactly zero (a gap maximum on a resting contact); a restart from the
     * same state clears its root history */
    s->errmsg[0] = '\0';
    if ((st = cv_start(s))) return st;
    s->stats[VI_STAT_REINITS]++;
    flag = CVode(d->mem, t_end, d->y, &t, CV_ONE_STEP);
  }
  d->continued = 0;
  if (flag < 0 && s->force_failed)
    return vi_force_failure(s);
  if (flag < 0) {
    if (!s->errmsg[0])
      vi_fail(s->errmsg, VI_ERR_INTEGRATOR, "CVode failed (flag %d) at t = %g",
              flag, t);
    return VI_ERR_INTEGRATOR;
  }
  s->t = t;
  if (d->yQ) CV_TRY(CVodeGetQuad(d->mem, &t, d->yQ));
  if (s->sticking && flag != CV_ROOT_RETURN && (st = hold_drift(s)))
    return st;
  if (flag == CV_ROOT_RETURN && s->ns == 1) {
    int info[2] = {0, 0};
    CVodeGetRootInfo(d->mem, info);
    if (s->sticking) *event = info[0] ? VI_STEP_RELEASE : VI_STEP_NONE;
    else if (info[0]) *event = VI_STEP_CONTACT;
    else if (info[1]) st = graze_check(s, d, 0, event);
    d->continued = *event == VI_STEP_NONE;
  } else if (flag == CV_ROOT_RETURN) {
    /* several stops (layout of roots()): a contact first, then a release,
     * then the gap maxima's grazing checks */
    int *info = d->info, nst = s->nstick, rel = -1;
    CVodeGetRootInfo(d->mem, info);
    for (int i = 0; i < nst; i++)
      if (info[i] && rel < 0) rel = s->stick_k[i];
    for (int k = 0; k < s->ns && *event == VI_STEP_NONE; k++) {
      int i = vi_sim_gap_root(s, k);
      if (i >= 0 && info[i]) {
        *event = VI_STEP_CONTACT;
        s->contact_stop = k;
      }
    }
    if (*event == VI_STEP_NONE && rel >= 0) {
      *event = VI_STEP_RELEASE;
      s->contact_stop = rel;
    }
    for (int k = 0; k < s->ns && *event == VI_STEP_NONE && !st; k++) {
      int i = vi_sim_gap_root(s, k);
      if (i >= 0 && info[i + 1]) st = graze_check(s, d, k, event);
    }
    d->continued = *event == VI_STEP_NONE;
  }
cleanup:
  return st;
}

static int cv_dense(vi_sim *s, double t)
{
  cv_data *d = s->be_data; /* ys wraps s->zs */
  if (CVodeGetDky(d->mem, t, 0, d->ys) < 0)
    return vi_fail(s->errmsg, VI_ERR_INTEGRATOR,
                   "CVodeGetDky failed at t = %.17g", t);
  return VI_OK;
}

const vi_backend vi_backend_cvode = {"cvode", cv_start, cv_step, cv_dense,
                                     cv_stat, cv_destroy, NULL, cv_polish,
                                     NULL, NULL, NULL};
