/* vi_cont.c - a P(n,1) orbit followed in one parameter (vi_cont.h):
 * natural-parameter continuation with step halving and events located by
 * bisection, or pseudo-arclength around folds; the parameter changes on
 * the handle's own model (vi_param.h), nothing is rebuilt. */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <lapacke.h>

#include "vibroimpact/vi_cont.h"
#include "vibroimpact/vi_cont_curve.h"
#include "vibroimpact/vi_param.h"
#include "vi_model_internal.h"
#include "vi_orbit_internal.h"

#define MAXEV 16

/* One evaluated orbit on the branch. */
typedef struct cstate {
  double p, t, vn, rho, gmax;
  int kind; /* of the largest multiplier: 0 real < 0, 1 real > 0, 2 complex */
  double re, im;
  int ok;
} cstate;

typedef struct cevent {
  int type, adm;
  double p, vn, re, im;
} cevent;

struct vi_cont {
  vi_model *m;
  char key[64];
  int n, N, method, par;          /* par: vi_orbit_pnm_dparam's, or -1 */
  int pk;                         /* the stop of a stop parameter */
  int stop;                       /* the stop the orbit's impact hits */
  double p0, to, h;
  int steps, have_orbit, have_range, state;
  int64_t npts, iter;
  /* the current orbit and scratch: x, v, xp, vp, xs, vs [N] each */
  double t, *x, *v, *xp, *vp, *xs, *vs, *re, *im;
  cstate c, prev;
  double step;                    /* natural: the current step */
  /* arclength: U = (t, x, v, p) [K], tangent, history */
  double *U, *tau, *Un, *F, *dir, *Up, *U0, *A;
  double ds, dsmax, s, hs[3], hp[3];
  cevent ev[MAXEV];
  int nev;
  vi_cont_monitor_fn mon;
  void *mon_user;
  vi_destroy_fn mon_free;
  vi_cancel_fn cancel;
  void *cancel_user;
  vi_destroy_fn cancel_free;
  char errmsg[VI_MSG_LEN];
};

/* 1 if the caller asked to cancel (vi_cont_set_cancel). */
static int cancelled(const vi_cont *c)
{
  return c->cancel && c->cancel(c->cancel_user);
}

int vi_cont_create(const vi_model *m, const char *key, int n, int method,
                   vi_cont **out)
{
  if (!out) return VI_ERR_ARG;
  *out = NULL;
  if (!m || !key || n < 1 || (method != VI_CONT_NATURAL && method != VI_CONT_ARCLENGTH) ||
      vi_param_kind(key) != VI_PARAM_MODEL || strlen(key) >= 64)
    return VI_ERR_ARG;
  if (!m->frozen) return VI_ERR_STATE;
  vi_cont *c = calloc(1, sizeof *c);
  if (!c) return VI_ERR_NOMEM;
  int N = m->n, K = 2 * N + 2;
  size_t nd = 10 * (size_t)N + 7 * (size_t)K + (size_t)K * K;
  c->x = malloc(sizeof(double) * nd);
  if (!c->x || vi_model_copy(m, &c->m) ||
      vi_model_param(c->m, key, &c->p0)) {
    /* decided before the handle goes (destroy clears c: this said "out
     * of memory" for a key the model does not have, forcing.a[3] of 2) */
    int st = c->x && c->m ? VI_ERR_ARG : VI_ERR_NOMEM;
    vi_cont_destroy(&c);
    return st;
  }
  c->v = c->x + N;
  c->xp = c->v + N;
  c->vp = c->xp + N;
  c->xs = c->vp + N;
  c->vs = c->xs + N;
  c->re = c->vs + N; /* re, im: [2N] each */
  c->im = c->re + 2 * (size_t)N;
  c->U = c->x + 10 * (size_t)N;
  c->tau = c->U + K;
  c->Un = c->tau + K;
  c->F = c->Un + K;
  c->dir = c->F + K;
  c->Up = c->dir + K;
  c->U0 = c->Up + K;
  c->A = c->U0 + K;
  snprintf(c->key, sizeof c->key, "%s", key);
  c->n = n;
  c->N = N;
  c->method = method;
  c->par = vi_orbit_param_of_key(key, &c->pk);
  if (c->pk >= c->m->ns) c->par = -1; /* vi_model_param refused it above */
  *out = c;
  return VI_OK;
}

void vi_cont_destroy(vi_cont **cp)
{
  if (!cp || !*cp) return;
  vi_cont *c = *cp;
  vi_user_set(&c->mon_user, &c->mon_free, NULL, NULL);
  vi_user_set(&c->cancel_user, &c->cancel_free, NULL, NULL);
  vi_model_destroy(&c->m);
  free(c->x);
  free(c);
  *cp = NULL;
}

const char *vi_cont_errmsg(const vi_cont *c) { return c ? c->errmsg : ""; }

int vi_cont_set_range(vi_cont *c, double to, int steps)
{
  if (!c || steps < 1) return VI_ERR_ARG;
  if (!isfinite(to)) return VI_ERR_NONFINITE;
  c->to = to;
  c->steps = steps;
  c->have_range = 1;
  return VI_OK;
}

int vi_cont_set_orbit(vi_cont *c, double t, const double *x, const double *v)
{
  if (!c || !x || !v) return VI_ERR_ARG;
  if (!isfinite(t)) return VI_ERR_NONFINITE;
  for (int i = 0; i < c->N; i++)
    if (!isfinite(x[i]) || !isfinite(v[i])) return VI_ERR_NONFINITE;
  c->t = t;
  memcpy(c->x, x, sizeof(double) * c->N);
  memcpy(c->v, v, sizeof(double) * c->N);
  /* the impact's own stop: the one whose gap w_k.x - x_k is nearest 0 */
  const vi_model *m = c->m;
  double best = HUGE_VAL;
  c->stop = 0;
  for (int k = 0; k < m->ns; k++) {
    double g = fabs(vi_dot(c->N, vi_stop_w(m, k), x) - m->xsv[k]);
    if (g < best) {
      best = g;
      c->stop = k;
    }
  }
  c->have_orbit = 1;
  c->npts = c->iter = 0;
  c->state = VI_CONT_RUNNING;
  return VI_OK;
}

int vi_cont_set_monitor(vi_cont *c, vi_cont_monitor_fn fn, void *user,
                        vi_destroy_fn destroy)
{
  if (!c) return VI_ERR_ARG;
  c->mon = fn;
  vi_user_set(&c->mon_user, &c->mon_free, user, destroy);
  return VI_OK;
}

int vi_cont_set_cancel(vi_cont *c, vi_cancel_fn fn, void *user,
                       vi_destroy_fn destroy)
{
  if (!c) return VI_ERR_ARG;
  c->cancel = fn;
  vi_user_set(&c->cancel_user, &c->cancel_free, user, destroy);
  return VI_OK;
}

/* ---- one orbit at a parameter value --------------------------------------- */

/* Solve at p from the seed (t, x, v) (overwritten) and evaluate: 0, or
 * non-zero when the parameter is refused or Newton fails. */
static int solve_at(vi_cont *c, double p, double *t, double *x, double *v,
                    cstate *cs)
{
  int N = c->N, np = c->n, ok = 0;
  if (vi_model_set_param(c->m, c->key, p)) return -1;
  vi_model *m = c->m;
  const int *sk = &c->stop;
  int st = vi_orbit_pnm_solve_stops(m, np, 1, sk, t, x, v, N, 0.0, NULL);
  if (!st)
    st = vi_orbit_pnm_multipliers_stops(m, np, 1, sk, t, x, v, N, c->re, c->im);
  if (!st)
    st = vi_orbit_pnm_admissible_stops(m, np, 1, sk, t, x, v, N, &cs->gmax, &ok);
  if (!st) {
    const double *w = vi_stop_w(m, c->stop); /* v_n on the impact's stop */
    cs->p = p;
    cs->t = *t;
    cs->vn = 0;
    for (int i = 0; i < N; i++) cs->vn += w[i] * v[i];
    cs->rho = 0;
    for (int i = 0; i < 2 * N; i++) {
      double r = hypot(c->re[i], c->im[i]);
      if (r > cs->rho) {
        cs->rho = r;
        cs->re = c->re[i];
        cs->im = c->im[i];
      }
    }
    cs->kind = fabs(cs->im) > 1e-9 * cs->rho ? 2 : cs->re > 0;
    cs->ok = ok;
  }
  return st ? 1 : 0;
}

/* A point of a kind solved exactly (vi_cont_refine: the orbit's equations
 * plus the defining condition) from the bisected or interpolated guess p
 * and the nearby orbit (t, x, v); the event then carries the refined p,
 * v_N and critical multiplier.  Left as guessed when Newton fails. */
static void refine_event(vi_cont *c, int type, double *p, double t, const double *x,
                         const double *v, double *vn, double *re, double *im)
{
  int N = c->N, kind = type == VI_CONT_PERIOD_DOUBLING ? VI_CONT_CURVE_PD
                       : type == VI_CONT_NEIMARK_SACKER ? VI_CONT_CURVE_NS
                       : type == VI_CONT_GRAZING ? VI_CONT_CURVE_GRAZING : VI_CONT_CURVE_FOLD;
  double q = *p, *z = malloc(sizeof(double) * 6 * (size_t)N);
  if (!z) return;
  double *zv = z + N, *mr = z + 2 * (size_t)N, *mi = z + 4 * (size_t)N;
  memcpy(z, x, sizeof(double) * N);
  memcpy(zv, v, sizeof(double) * N);
  if (!vi_cont_refine(c->m, c->key, c->n, kind, &q, &t, z, zv) &&
      !vi_model_set_param(c->m, c->key, q) &&
      !vi_orbit_pnm_multipliers_stops(c->m, c->n, 1, &c->stop, &t, z, zv, N, mr, mi)) {
    *p = q;
    *vn = vi_dot(N, vi_stop_w(c->m, c->stop), zv);
    if (type != VI_CONT_GRAZING) { /* the multiplier the condition puts on the circle */
      int b = 0;
      double target = type == VI_CONT_PERIOD_DOUBLING ? -1 : 1;
      for (int i = 1; i < 2 * N; i++) {
        double di = type == VI_CONT_NEIMARK_SACKER ? fabs(hypot(mr[i], mi[i]) - 1)
                    : hypot(mr[i] - target, mi[i]);
        double db = type == VI_CONT_NEIMARK_SACKER ? fabs(hypot(mr[b], mi[b]) - 1)
                    : hypot(mr[b] - target, mi[b]);
        if (di < db) b = i;
      }
      *re = mr[b];
      *im = fabs(mi[b]);
    }
  }
  free(z);
}

static void add_event(vi_cont *c, int type, double p, double vn, double re,
                      double im, int adm)
{
  if (c->nev >= MAXEV) return;
  cevent e = {type, adm, p, vn, re, im};
  c->ev[c->nev++] = e;
}

/* ---- natural parameter ------------------------------------------------------ */

/* Crossings between prev and c, each bisected on p from the orbit at c:
 * stability (rho through 1), an interior gap maximum through the stop,
 * the impact velocity through 0. */
static void natural_events(vi_cont *c)
{
  int N = c->N;
  const cstate *pr = &c->prev, *cu = &c->c;
  int cross[3] = {(pr->rho < 1) != (cu->rho < 1), (pr->gmax < 0) != (cu->gmax < 0),
                  (pr->vn > 0) != (cu->vn > 0)};
  if (pr->vn <= 0 && cu->vn <= 0) cross[1] = 0; /* no impact: no contact */
  for (int e = 0; e < 3; e++) {
    if (!cross[e]) continue;
    double a = pr->p, b = cu->p, ts;
    double fa = e == 0 ? pr->rho - 1 : e == 1 ? pr->gmax : pr->vn;
    cstate mid = *cu;
    for (int it = 0; it < 60 && fabs(b - a) > 1e-13 * fmax(1.0, fabs(b)); it++) {
      double pm = 0.5 * (a + b);
      memcpy(c->xs, c->x, sizeof(double) * N);
      memcpy(c->vs, c->v, sizeof(double) * N);
      ts = c->t;
      if (solve_at(c, pm, &ts, c->xs, c->vs, &mid)) break;
      double fm = e == 0 ? mid.rho - 1 : e == 1 ? mid.gmax : mid.vn;
      if ((fm < 0) == (fa < 0)) {
        a = pm;
        fa = fm;
      } else {
        b = pm;
      }
    }
    int type = e == 0 ? mid.kind : e == 1 ? VI_CONT_GRAZING : VI_CONT_GRAZING_IMPACT;
    double re = e ? NAN : mid.re, im = e ? NAN : mid.im;
    if (type != VI_CONT_GRAZING_IMPACT)
      refine_event(c, type, &mid.p, c->t, c->x, c->v, &mid.vn, &re, &im);
    add_event(c, type, mid.p, mid.vn, re, im, mid.ok);
  }
}

/* Where Newton stops finding the orbit: bisection between the last
 * success and the smallest failed step, each try seeded from the latest
 * success (at a fold a multiplier approaches +1). */
static void natural_lost(vi_cont *c)
{
  int N = c->N;
  double a = c->prev.p, b = c->prev.p + 2 * c->step, ts;
  cstate ca = c->prev, cm;
  for (int it = 0; it < 50 && fabs(b - a) > 1e-12 * fmax(1.0, fabs(a)); it++) {
    double pm = 0.5 * (a + b);
    memcpy(c->xs, c->x, sizeof(double) * N);
    memcpy(c->vs, c->v, sizeof(double) * N);
    ts = c->t;
    if (!solve_at(c, pm, &ts, c->xs, c->vs, &cm)) {
      a = pm;
      ca = cm;
      c->t = ts;
      memcpy(c->x, c->xs, sizeof(double) * N);
      memcpy(c->v, c->vs, sizeof(double) * N);
    } else {
      b = pm;
    }
  }
  add_event(c, VI_CONT_LOST, a, ca.vn, ca.re, ca.im, ca.ok);
}

static int natural_step(vi_cont *c)
{
  int N = c->N;
  c->prev = c->c;
  memcpy(c->xp, c->x, sizeof(double) * N);
  memcpy(c->vp, c->v, sizeof(double) * N);
  double tp = c->t;
  int got = 0;
  while (!got && fabs(c->step) >= fabs(c->h) / 64) {
    if (cancelled(c)) { /* back to the last point: iterate again resumes */
      c->t = tp;
      memcpy(c->x, c->xp, sizeof(double) * N);
      memcpy(c->v, c->vp, sizeof(double) * N);
      c->c = c->prev;
      return VI_CANCELLED;
    }
    double pn = (c->to - (c->prev.p + c->step)) * c->h < 0 ? c->to : c->prev.p + c->step;
    c->t = tp;
    memcpy(c->x, c->xp, sizeof(double) * N);
    memcpy(c->v, c->vp, sizeof(double) * N);
    got = !solve_at(c, pn, &c->t, c->x, c->v, &c->c);
    if (!got) c->step /= 2;
  }
  if (!got) {
    c->t = tp;
    memcpy(c->x, c->xp, sizeof(double) * N);
    memcpy(c->v, c->vp, sizeof(double) * N);
    natural_lost(c);
    c->c = c->prev;
    c->state = VI_CONT_ENDS;
    return VI_STOPPED;
  }
  c->step = fabs(2 * c->step) < fabs(c->h) ? 2 * c->step : c->h;
  natural_events(c);
  return VI_OK;
}

/* ---- pseudo-arclength ---------------------------------------------------------- */

/* Dense solve A y = b (A [k x k] column-major, overwritten) by LAPACK's
 * LU with partial pivoting; 0, or 1 if singular (or out of memory). */
static int gauss(int k, double *A, double *b)
{
  lapack_int *ipiv = malloc(sizeof(lapack_int) * (size_t)k);
  if (!ipiv) return 1;
  lapack_int info = LAPACKE_dgesv(LAPACK_COL_MAJOR, k, 1, A, k, ipiv, b, k);
  free(ipiv);
  return info != 0;
}

/* F(u; p) [D] and, with Ja, the extended Jacobian's first D rows
 * [J_u | dF/dp] (Ja [(D+1) x (D+1)]): J_u exact; dF/dp exact for Omega,
 * x_s and r (vi_orbit_pnm_dparam), else central differences in p. */
static int ext_residual(vi_cont *c, const double *U, double *F, double *Ja)
{
  int N = c->N, np = c->n, D = 2 * N + 1, K = D + 1, st;
  double p = U[D];
  if (vi_model_set_param(c->m, c->key, p)) return -1;
  /* J [D x D] and two residuals (one spare: never a size of 0) */
  double *J = Ja ? malloc(sizeof(double) * ((size_t)D * D + 2 * (size_t)D + 1)) : NULL;
  if (Ja && !J) return VI_ERR_NOMEM;
  st = vi_orbit_pnm_residual_stops(c->m, np, 1, &c->stop, U, U + 1, U + 1 + N, N, F, J);
  if (!st && Ja && c->par >= 0) {
    double *dF = J + (size_t)D * D;
    st = vi_orbit_pnm_dparam(c->m, np, 1, &c->stop, U, U + 1, U + 1 + N, N,
                             c->par, c->pk, dF);
    for (int r = 0; r < D && !st; r++) Ja[r + (size_t)D * K] = dF[r];
  }
  if (st || !Ja) {
    free(J);
    return st;
  }
  for (int cc = 0; cc < D; cc++)
    for (int r = 0; r < D; r++) Ja[r + (size_t)cc * K] = J[r + (size_t)cc * D];
  if (c->par >= 0) {
    free(J);
    return VI_OK;
  }
  double dp = 1e-6 * fmax(1.0, fabs(p)), *Fp = J + (size_t)D * D, *Fm = Fp + D;
  st = vi_model_set_param(c->m, c->key, p + dp) ? -1
       : vi_orbit_pnm_residual_stops(c->m, np, 1, &c->stop, U, U + 1, U + 1 + N, N, Fp, NULL);
  if (!st) st = vi_model_set_param(c->m, c->key, p - dp) ? -1
                : vi_orbit_pnm_residual_stops(c->m, np, 1, &c->stop, U, U + 1, U + 1 + N, N, Fm, NULL);
  for (int r = 0; r < D && !st; r++) Ja[r + (size_t)D * K] = (Fp[r] - Fm[r]) / (2 * dp);
  free(J);
  return st;
}

/* Tangent of the branch at U: the null vector of [J_u | F_p], normalised,
 * oriented along dir (the previous tangent). */
static int tangent(vi_cont *c)
{
  int D = 2 * c->N + 1, K = D + 1;
  double *A = malloc(sizeof(double) * ((size_t)K * K + D)), *tau = c->tau;
  if (!A) return VI_ERR_NOMEM;
  int st = ext_residual(c, c->U, A + (size_t)K * K, A);
  if (!st) {
    for (int cc = 0; cc < K; cc++) A[D + (size_t)cc * K] = c->dir[cc];
    for (int r = 0; r < K; r++) tau[r] = r == D;
    st = gauss(K, A, tau) ? VI_ERR_NOT_CONVERGED : VI_OK;
  }
  if (!st) {
    double nrm = 0, dot = 0;
    for (int r = 0; r < K; r++) nrm += tau[r] * tau[r];
    nrm = sqrt(nrm);
    for (int r = 0; r < K; r++) {
      tau[r] /= nrm;
      dot += tau[r] * c->dir[r];
    }
    if (dot < 0)
      for (int r = 0; r < K; r++) tau[r] = -tau[r];
  }
  free(A);
  return st;
}

/* Predictor-corrector from U along tau: Newton on F = 0,
 * tau.(U - Up) = 0, halving ds on failure.  0, or 1 if it fails. */
static int corrector(vi_cont *c)  /* 0, 1 (no point) or VI_CANCELLED */
{
  int D = 2 * c->N + 1, K = D + 1, ok = 0;
  double *Un = c->Un, *F = c->F, *A = c->A, *tau = c->tau;
  while (!ok && c->ds > c->dsmax / 1024) {
    for (int r = 0; r < K; r++) c->Up[r] = c->U[r] + c->ds * tau[r];
    memcpy(Un, c->Up, sizeof(double) * K);
    for (int it = 0; it < 20; it++) {
      if (cancelled(c)) return VI_CANCELLED; /* c->U is still the last point */
      if (ext_residual(c, Un, F, A)) break;
      double fn = 0, sc = 1e-12;
      for (int r = 0; r < D; r++) fn = fmax(fn, fabs(F[r]));
      for (int r = 1; r < D; r++) sc = fmax(sc, fabs(Un[r]));
      F[D] = 0;
      for (int r = 0; r < K; r++) F[D] += tau[r] * (Un[r] - c->Up[r]);
      if (fn <= 1e-11 * sc && fabs(F[D]) <= 1e-11 * (1 + c->ds)) {
        ok = 1;
        break;
      }
      for (int c2 = 0; c2 < K; c2++) A[D + (size_t)c2 * K] = tau[c2];
      if (gauss(K, A, F)) break;
      for (int r = 0; r < K; r++) Un[r] -= F[r];
    }
    if (!ok) c->ds /= 2;
  }
  if (!ok) return 1;
  c->s += c->ds;
  memcpy(c->U, Un, sizeof(double) * K);
  c->ds = fmin(c->dsmax, 1.5 * c->ds);
  return 0;
}

/* The point at U: evaluated, its events against the previous point
 * (interpolated), the end and a closed branch checked, then the tangent
 * for the next step and a fold (dp/ds changing sign). */
static int arclength_point(vi_cont *c)
{
  int N = c->N, D = 2 * N + 1, K = D + 1;
  cstate cu;
  double tt = c->U[0];
  memcpy(c->Un, c->U + 1, sizeof(double) * 2 * N);
  if (solve_at(c, c->U[D], &tt, c->Un, c->Un + N, &cu)) {
    c->state = VI_CONT_STALLED;
    return VI_STOPPED;
  }
  const cstate *pr = &c->prev;
  if (c->npts && (pr->rho < 1) != (cu.rho < 1)) {
    double pe = pr->p + (cu.p - pr->p) * (1 - pr->rho) / (cu.rho - pr->rho), vn = NAN,
           re = NAN, im = NAN;
    refine_event(c, cu.kind, &pe, tt, c->Un, c->Un + N, &vn, &re, &im);
    add_event(c, cu.kind, pe, vn, re, im, cu.ok);
  }
  if (c->npts && ((pr->vn > 0) != (cu.vn > 0) ||
                  ((pr->gmax < 0) != (cu.gmax < 0) && (pr->vn > 0 || cu.vn > 0)))) {
    int imp = (pr->vn > 0) != (cu.vn > 0); /* v_N through 0, else the gap */
    double f0 = imp ? pr->vn : pr->gmax, f1 = imp ? cu.vn : cu.gmax, vn = NAN, re = NAN,
           im = NAN, pe = pr->p + (cu.p - pr->p) * f0 / (f0 - f1);
    if (!imp) refine_event(c, VI_CONT_GRAZING, &pe, tt, c->Un, c->Un + N, &vn, &re, &im);
    add_event(c, imp ? VI_CONT_GRAZING_IMPACT : VI_CONT_GRAZING, pe, vn, re, im, cu.ok);
  }
  c->c = cu;
  c->prev = cu;
  c->t = tt;
  memcpy(c->x, c->Un, sizeof(double) * 2 * N); /* x then v, contiguous */
  c->hs[0] = c->hs[1]; c->hs[1] = c->hs[2]; c->hs[2] = c->s;
  c->hp[0] = c->hp[1]; c->hp[1] = c->hp[2]; c->hp[2] = c->U[D];
  c->npts++;
  double *U = c->U;
  if (c->npts > 1 && (U[D] - c->to) * (c->p0 < c->to ? 1 : -1) >= 0) {
    c->state = VI_CONT_END;
    return VI_OK;
  }
  /* a closed branch (an isola) is done once it comes back to its start;
   * impact times compare modulo the forcing period */
  if (c->npts > 3 && fabs(U[D] - c->p0) < 0.5 * c->dsmax) {
    double T = vi_model_set_param(c->m, c->key, U[D]) ? HUGE_VAL
               : vi_model_forcing_period(c->m);
    double dt = fmod(fabs(U[0] - c->U0[0]), T), dist = fmin(dt, T - dt);
    for (int r = 1; r < K; r++) dist = fmax(dist, fabs(U[r] - c->U0[r]));
    if (dist < 0.5 * c->dsmax) {
      add_event(c, VI_CONT_CLOSED, U[D], NAN, NAN, NAN, cu.ok);
      c->state = VI_CONT_CLOSES;
      return VI_OK;
    }
  }
  if (tangent(c)) {
    c->state = VI_CONT_STALLED;
    return VI_OK;
  }
  if (c->npts >= 3 && c->tau[D] * c->dir[D] < 0) { /* the parabola's vertex */
    const double *hs = c->hs, *hp = c->hp;
    double a1 = (hp[1] - hp[0]) / (hs[1] - hs[0]), a2 = (hp[2] - hp[1]) / (hs[2] - hs[1]);
    double c2 = (a2 - a1) / (hs[2] - hs[0]), sv = 0.5 * (hs[0] + hs[1]) - a1 / (2 * c2);
    double pf = hp[0] + a1 * (sv - hs[0]) + c2 * (sv - hs[0]) * (sv - hs[1]);
    double vn = NAN, re = NAN, im = NAN;
    refine_event(c, VI_CONT_FOLD, &pf, tt, c->x, c->v, &vn, &re, &im);
    add_event(c, VI_CONT_FOLD, pf, vn, re, im, cu.ok);
  }
  memcpy(c->dir, c->tau, sizeof(double) * K);
  return VI_OK;
}

static void arclength_start(vi_cont *c)
{
  int N = c->N, D = 2 * N + 1, K = D + 1;
  c->U[0] = c->t;
  memcpy(c->U + 1, c->x, sizeof(double) * N);
  memcpy(c->U + 1 + N, c->v, sizeof(double) * N);
  c->U[D] = c->p0;
  memcpy(c->U0, c->U, sizeof(double) * K);
  for (int r = 0; r < K; r++) c->dir[r] = r == D ? (c->to > c->p0 ? 1 : -1) : 0;
  c->ds = c->dsmax = fabs(c->to - c->p0) / c->steps;
  c->s = 0;
  for (int i = 0; i < 3; i++) {
    c->hs[i] = 0;
    c->hp[i] = c->p0;
  }
}

/* ---- the loop's step ----------------------------------------------------------- */

static int first_point(vi_cont *c)
{
  if (c->method == VI_CONT_ARCLENGTH) {
    arclength_start(c);
    int st = arclength_point(c);
    if (st || !c->npts)
      return vi_fail(c->errmsg, VI_ERR_NOT_CONVERGED, "%s = %.17g: no P(%d,1) "
                     "orbit found from the orbit given", c->key, c->p0, c->n);
    return VI_OK;
  }
  c->h = (c->to - c->p0) / c->steps;
  c->step = c->h;
  if (solve_at(c, c->p0, &c->t, c->x, c->v, &c->c))
    return vi_fail(c->errmsg, VI_ERR_NOT_CONVERGED, "%s = %.17g: no P(%d,1) "
                   "orbit found from the orbit given", c->key, c->p0, c->n);
  c->npts = 1;
  return VI_OK;
}

int vi_cont_iterate(vi_cont *c)
{
  if (!c) return VI_ERR_ARG;
  if (!c->have_orbit || !c->have_range || c->state)
    return vi_fail(c->errmsg, VI_ERR_STATE, "%s", c->state ? "the continuation "
                   "is done" : "set the orbit and the range first");
  c->nev = 0;
  c->errmsg[0] = '\0';
  if (cancelled(c)) return VI_CANCELLED;
  int st;
  if (!c->iter++) {
    if ((st = first_point(c))) {
      c->state = VI_CONT_STALLED;
      return st;
    }
  } else if (c->method == VI_CONT_NATURAL) {
    if ((st = natural_step(c))) return st;
  } else {
    if (c->iter > 10 * (int64_t)c->steps) {
      c->state = VI_CONT_STALLED;
      return VI_STOPPED;
    }
    if ((st = corrector(c)) == VI_CANCELLED) return st;
    if (st) {
      c->state = VI_CONT_CORRECTOR;
      return VI_STOPPED;
    }
    if ((st = arclength_point(c))) return st;
  }
  if (c->method == VI_CONT_NATURAL) {
    if (c->iter > 1) c->npts++;
    if ((c->to - c->c.p) * c->h <= 1e-12 * fabs(c->h)) c->state = VI_CONT_END;
  }
  if (c->mon && c->mon(c, c->npts, c->mon_user)) return VI_STOPPED;
  return VI_OK;
}

/* ---- results --------------------------------------------------------------------- */

int vi_cont_done(const vi_cont *c) { return c ? c->state : 0; }

int vi_cont_point(const vi_cont *c, double *param, double *vn, double *t,
                  double *rho, int *admissible)
{
  if (!c) return VI_ERR_ARG;
  if (!c->npts) return VI_ERR_STATE;
  if (param) *param = c->c.p;
  if (vn) *vn = c->c.vn;
  if (t) *t = c->c.t;
  if (rho) *rho = c->c.rho;
  if (admissible) *admissible = c->c.ok;
  return VI_OK;
}

int vi_cont_orbit(const vi_cont *c, double *t, double *x, double *v)
{
  if (!c || !t || !x || !v) return VI_ERR_ARG;
  if (!c->npts) return VI_ERR_STATE;
  *t = c->t;
  memcpy(x, c->x, sizeof(double) * c->N);
  memcpy(v, c->v, sizeof(double) * c->N);
  return VI_OK;
}

int vi_cont_num_events(const vi_cont *c) { return c ? c->nev : 0; }

int vi_cont_event(const vi_cont *c, int i, int *type, double *param,
                  double *vn, double *re, double *im, int *admissible)
{
  if (!c || i < 0 || i >= c->nev) return VI_ERR_ARG;
  const cevent *e = &c->ev[i];
  if (type) *type = e->type;
  if (param) *param = e->p;
  if (vn) *vn = e->vn;
  if (re) *re = e->re;
  if (im) *im = e->im;
  if (admissible) *admissible = e->adm;
  return VI_OK;
}
