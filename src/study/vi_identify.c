/* vi_identify.c - model parameters from a recorded periodic response
 * (MODEL.md sections 5, 6; the paper's section 4): nonlinear least squares
 * on the model's steady P(n, m) orbit, continued from trial to trial, with
 * the orbit's exact parameter sensitivities carried to every sample by the
 * state-transition matrix, and the uncertainty the data actually hold. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <lapacke.h>

#include "vi_forcing.h"
#include "vi_orbit_internal.h"
#include "vibroimpact/vi_identify.h"
#include "vibroimpact/vi_param.h"

#define MAXP 32

/* A P(n, m) orbit: impact times, stops, pre-impact states [N x MAX_M]. */
typedef struct orb {
  int n, m;
  int stop[MAX_M];
  double t[MAX_M];
  double *x, *v;
} orb;

struct vi_identify {
  const vi_model *base;
  int N, np;
  int kind[MAXP], kst[MAXP], pset[MAXP];
  double p0[MAXP], lo[MAXP], hi[MAXP];
  char key[MAXP][64]; /* the vi_param.h key of each parameter */
  vi_identify_model_fn fn;
  void *user;
  vi_destroy_fn destroy;
  double *c; /* observation [N] */
  int fit_shift, stable_only;
  double shift0, sigma, mumax; /* mumax: the fitted orbit's largest |multiplier| */
  int ns;
  double *t, *y, *vy; /* recording */
  /* the model and orbit at pcur (continuation: each trial starts here) */
  vi_model *cur;
  vi_xflow *xf;
  double pcur[MAXP];
  int have_cur;
  orb o, trial;
  /* the last Jacobian's point: its orbit and du/dp [D x np], the
   * predictor of the next trials' orbits */
  orb acc;
  double pacc[MAXP], *dudp, *mre, *mim;
  int have_pred;
  double Om0, scale; /* velocity scaling; largest |y| (penalty) */
  /* results */
  int done, conv, iters;
  double p[MAXP], se[MAXP], l95[MAXP], h95[MAXP], t0, t0se, rms, noise, rcond;
  int flags[MAXP];
  double corr[MAXP * MAXP], r12, vN, KE, RE;
  vi_cancel_fn cancel;          /* vi_identify_set_cancel */
  void *cancel_user;
  vi_destroy_fn cancel_free;
  int cancel_hit;               /* the poll said cancel during this run */
  char errmsg[VI_MSG_LEN];
};

/* The cancel poll, sticky within a run (GSL and the scans stop on it). */
static int poll_cancel(vi_identify *id)
{
  if (id->cancel && !id->cancel_hit && id->cancel(id->cancel_user))
    id->cancel_hit = 1;
  return id->cancel_hit;
}
static int poll_fn(void *user) { return poll_cancel(user); }
static int poll_mon(const vi_progress *p, void *user)
{
  (void)p;
  return poll_cancel(user);
}

static int orb_alloc(orb *o, int N)
{
  o->x = calloc((size_t)N * MAX_M, sizeof(double));
  o->v = calloc((size_t)N * MAX_M, sizeof(double));
  return o->x && o->v ? VI_OK : VI_ERR_NOMEM;
}

static void orb_copy(orb *d, const orb *s, int N)
{
  d->n = s->n;
  d->m = s->m;
  memcpy(d->stop, s->stop, sizeof d->stop);
  memcpy(d->t, s->t, sizeof d->t);
  memcpy(d->x, s->x, sizeof(double) * N * MAX_M);
  memcpy(d->v, s->v, sizeof(double) * N * MAX_M);
}

int vi_identify_create(const vi_model *base, int np, vi_identify **out)
{
  if (!out) return VI_ERR_ARG;
  *out = NULL;
  if (!base) return VI_ERR_ARG;
  if (np < 1 || np > MAXP) return VI_ERR_DIM;
  if (!base->frozen || base->ns < 1) return VI_ERR_STATE;
  if (!base->ops->modal || !vi_xflow_available(base))
    return VI_ERR_UNSUPPORTED;
  if (!(base->omega_f > 0.0)) return VI_ERR_FREQUENCY;
  vi_identify *id = calloc(1, sizeof *id);
  if (!id) return VI_ERR_NOMEM;
  id->base = base;
  id->N = base->n;
  id->np = np;
  id->fit_shift = 1;
  id->stable_only = 1;
  id->shift0 = NAN;
  id->c = malloc(sizeof(double) * id->N);
  id->dudp = malloc(sizeof(double) * (size_t)MAX_M * (2 * id->N + 1) * np);
  id->mre = malloc(sizeof(double) * 4 * (size_t)id->N);
  id->mim = id->mre ? id->mre + (size_t)2 * id->N : NULL;
  if (!id->c || !id->dudp || !id->mre || orb_alloc(&id->o, id->N) ||
      orb_alloc(&id->trial, id->N) || orb_alloc(&id->acc, id->N)) {
    vi_identify_destroy(&id);
    return VI_ERR_NOMEM;
  }
  memcpy(id->c, vi_stop_w(base, 0), sizeof(double) * id->N);
  *out = id;
  return VI_OK;
}

static void drop_cur(vi_identify *id)
{
  vi_xflow_destroy(&id->xf);
  vi_model_destroy(&id->cur);
  id->have_cur = 0;
}

void vi_identify_destroy(vi_identify **idp)
{
  if (!idp || !*idp) return;
  vi_identify *id = *idp;
  drop_cur(id);
  if (id->destroy) id->destroy(id->user);
  vi_user_set(&id->cancel_user, &id->cancel_free, NULL, NULL);
  free(id->c);
  free(id->t);
  free(id->y);
  free(id->vy);
  free(id->o.x);
  free(id->o.v);
  free(id->trial.x);
  free(id->trial.v);
  free(id->acc.x);
  free(id->acc.v);
  free(id->dudp);
  free(id->mre);
  free(id);
  *idp = NULL;
}

const char *vi_identify_errmsg(const vi_identify *id)
{
  return id ? id->errmsg : "";
}

int vi_identify_set_param(vi_identify *id, int j, int kind, int k, double p0,
                          double lo, double hi)
{
  if (!id) return VI_ERR_ARG;
  if (j < 0 || j >= id->np)
    return vi_fail(id->errmsg, VI_ERR_ARG, "parameter %d of %d", j + 1, id->np);
  if (kind < VI_IDENTIFY_OMEGA || kind > VI_IDENTIFY_OTHER)
    return vi_fail(id->errmsg, VI_ERR_ARG, "parameter %d: unknown kind %d",
                   j + 1, kind);
  if ((kind == VI_IDENTIFY_XS || kind == VI_IDENTIFY_R) &&
      (k < 0 || k >= id->base->ns))
    return vi_fail(id->errmsg, VI_ERR_ARG, "parameter %d: stop %d of %d",
                   j + 1, k + 1, id->base->ns);
  if (!isfinite(p0))
    return vi_fail(id->errmsg, VI_ERR_NONFINITE, "parameter %d: start %g",
                   j + 1, p0);
  if (kind == VI_IDENTIFY_R) {
    lo = fmax(lo, 0.0);
    hi = fmin(hi, 1.0);
  }
  if (kind == VI_IDENTIFY_OMEGA) lo = fmax(lo, 0.0);
  if (isnan(lo) || isnan(hi) || !(lo < hi) || p0 < lo || p0 > hi)
    return vi_fail(id->errmsg, VI_ERR_ARG,
                   "parameter %d: start %g outside the range [%g, %g]", j + 1,
                   p0, lo, hi);
  id->kind[j] = kind;
  id->kst[j] = kind == VI_IDENTIFY_XS || kind == VI_IDENTIFY_R ? k : 0;
  if (kind == VI_IDENTIFY_OMEGA) snprintf(id->key[j], sizeof id->key[j], "forcing.omega");
  else if (kind == VI_IDENTIFY_XS) snprintf(id->key[j], sizeof id->key[j], "stops[%d].xs", k + 1);
  else if (kind == VI_IDENTIFY_R) snprintf(id->key[j], sizeof id->key[j], "stops[%d].r", k + 1);
  id->p0[j] = p0;
  id->lo[j] = lo;
  id->hi[j] = hi;
  id->pset[j] = 1;
  id->done = 0;
  return VI_OK;
}

/* "stop.xs", "stops[k].r", ...: the stop (0-based) and the field, or -1. */
static int stop_key(const char *key, const char *field)
{
  char tail[16];
  snprintf(tail, sizeof tail, ".%s", field);
  if (!strncmp(key, "stop.", 5)) return strcmp(key + 4, tail) == 0 ? 0 : -1;
  if (strncmp(key, "stops[", 6) != 0) return -1;
  char *end;
  long k = strtol(key + 6, &end, 10);
  if (end == key + 6 || *end != ']' || strcmp(end + 1, tail) != 0 || k < 1 ||
      k > 1000000)
    return -1;
  return (int)k - 1;
}

int vi_identify_set_param_key(vi_identify *id, int j, const char *key,
                              double lo, double hi)
{
  if (!id) return VI_ERR_ARG;
  if (!key || strlen(key) >= sizeof id->key[0])
    return vi_fail(id->errmsg, VI_ERR_ARG, "parameter %d: no key or too long",
                   j + 1);
  double p0;
  int st = vi_model_param(id->base, key, &p0);
  if (st)
    return vi_fail(id->errmsg, st, "parameter %d: %s", j + 1,
                   vi_model_errmsg(id->base));
  int kind = VI_IDENTIFY_OTHER, k = 0;
  if (!strcmp(key, "forcing.omega")) kind = VI_IDENTIFY_OMEGA;
  else if ((k = stop_key(key, "xs")) >= 0) kind = VI_IDENTIFY_XS;
  else if ((k = stop_key(key, "r")) >= 0) kind = VI_IDENTIFY_R;
  if (k < 0) k = 0;
  if (isnan(lo)) lo = -HUGE_VAL;
  if (isnan(hi)) hi = HUGE_VAL;
  if ((st = vi_identify_set_param(id, j, kind, k, p0, lo, hi))) return st;
  snprintf(id->key[j], sizeof id->key[j], "%s", key);
  return VI_OK;
}

int vi_identify_set_builder(vi_identify *id, vi_identify_model_fn fn,
                            void *user, vi_destroy_fn destroy)
{
  if (!id) return VI_ERR_ARG;
  vi_user_set(&id->user, &id->destroy, fn ? user : NULL, fn ? destroy : NULL);
  id->fn = fn;
  id->done = 0;
  return VI_OK;
}

int vi_identify_set_cancel(vi_identify *id, vi_cancel_fn fn, void *user,
                           vi_destroy_fn destroy)
{
  if (!id) return VI_ERR_ARG;
  id->cancel = fn;
  vi_user_set(&id->cancel_user, &id->cancel_free, user, destroy);
  return VI_OK;
}

int vi_identify_set_observation(vi_identify *id, const double *c)
{
  if (!id) return VI_ERR_ARG;
  const double *w = c ? c : vi_stop_w(id->base, 0);
  double s = 0.0;
  for (int i = 0; i < id->N; i++) {
    if (!isfinite(w[i]))
      return vi_fail(id->errmsg, VI_ERR_NONFINITE, "observation %d: %g",
                     i + 1, w[i]);
    s += fabs(w[i]);
  }
  if (!(s > 0.0))
    return vi_fail(id->errmsg, VI_ERR_ARG, "the observation vector is zero");
  memcpy(id->c, w, sizeof(double) * id->N);
  id->done = 0;
  return VI_OK;
}

int vi_identify_set_shift(vi_identify *id, int fit, double t0)
{
  if (!id) return VI_ERR_ARG;
  if ((fit != 0 && fit != 1) || (!fit && !isfinite(t0)) || isinf(t0))
    return vi_fail(id->errmsg, VI_ERR_ARG,
                   "shift: fit must be 0 or 1, a held shift finite");
  id->fit_shift = fit;
  id->shift0 = t0;
  id->done = 0;
  return VI_OK;
}

int vi_identify_set_stable_only(vi_identify *id, int on)
{
  if (!id) return VI_ERR_ARG;
  if (on != 0 && on != 1)
    return vi_fail(id->errmsg, VI_ERR_ARG, "stable_only must be 0 or 1");
  id->stable_only = on;
  id->done = 0;
  return VI_OK;
}

int vi_identify_set_noise(vi_identify *id, double sigma)
{
  if (!id) return VI_ERR_ARG;
  if (!isfinite(sigma))
    return vi_fail(id->errmsg, VI_ERR_NONFINITE, "noise level %g", sigma);
  id->sigma = sigma > 0.0 ? sigma : 0.0;
  return VI_OK;
}

int vi_identify_set_data(vi_identify *id, int ns, const double *t,
                         const double *x, const double *v)
{
  if (!id) return VI_ERR_ARG;
  if (!t || !x) return vi_fail(id->errmsg, VI_ERR_ARG, "no times or values");
  if (ns < 16)
    return vi_fail(id->errmsg, VI_ERR_ARG,
                   "too few samples: %d (at least 16)", ns);
  for (int i = 0; i < ns; i++) {
    if (!isfinite(t[i]) || !isfinite(x[i]) || (v && !isfinite(v[i])))
      return vi_fail(id->errmsg, VI_ERR_NONFINITE,
                     "sample %d is not finite (t = %g, x = %g%s)", i + 1,
                     t[i], x[i], v && !isfinite(v[i]) ? ", v" : "");
    if (i > 0 && !(t[i] > t[i - 1]))
      return vi_fail(id->errmsg, VI_ERR_ARG,
                     "times not increasing at sample %d: %.17g after %.17g",
                     i + 1, t[i], t[i - 1]);
  }
  double *nt = malloc(sizeof(double) * ns), *ny = malloc(sizeof(double) * ns);
  double *nv = v ? malloc(sizeof(double) * ns) : NULL;
  if (!nt || !ny || (v && !nv)) {
    free(nt);
    free(ny);
    free(nv);
    return vi_fail(id->errmsg, VI_ERR_NOMEM, "out of memory");
  }
  memcpy(nt, t, sizeof(double) * ns);
  memcpy(ny, x, sizeof(double) * ns);
  if (v) memcpy(nv, v, sizeof(double) * ns);
  free(id->t);
  free(id->y);
  free(id->vy);
  id->t = nt;
  id->y = ny;
  id->vy = nv;
  id->ns = ns;
  id->done = 0;
  return VI_OK;
}

/* ---- models at trial values ------------------------------------------- */

/* A copy of the base model with the parameters set by key (vi_param.h:
 * only what each touches is redone). */
static int copy_model(vi_identify *id, const double *p, vi_model **out)
{
  vi_model *m = NULL;
  int st = vi_model_copy(id->base, &m);
  for (int j = 0; !st && j < id->np; j++)
    if ((st = vi_model_set_param(m, id->key[j], p[j])))
      vi_fail(id->errmsg, st, "%s", vi_model_errmsg(m));
  if (st) vi_model_destroy(&m);
  *out = m;
  return st;
}

static int make_model(vi_identify *id, const double *p, vi_model **out)
{
  *out = NULL;
  for (int j = 0; j < id->np; j++)
    if (!(p[j] >= id->lo[j] && p[j] <= id->hi[j])) return VI_ERR_ARG;
  if (!id->fn) return copy_model(id, p, out);
  int st = id->fn(p, id->user, out);
  if (st || !*out) {
    vi_model_destroy(out);
    return st ? st : VI_ERR_CALLBACK;
  }
  const vi_model *m = *out;
  if (!m->frozen || m->n != id->N || m->ns != id->base->ns || !m->ops->modal ||
      !(m->omega_f > 0.0)) {
    vi_model_destroy(out);
    return vi_fail(id->errmsg, VI_ERR_CALLBACK,
                   "the builder's model is not set up like the base model "
                   "(%d coordinates, %d stops, harmonic forcing)",
                   id->N, id->base->ns);
  }
  return VI_OK;
}

static double period_of(const vi_model *m, int n) { return n * 2.0 * M_PI / m->omega_f; }

/* Bring the orbit's first impact into [0, P): the same periodic orbit. */
static void orb_normalise(orb *o, double P)
{
  double k = floor(o->t[0] / P);
  for (int j = 0; j < o->m; j++) o->t[j] -= k * P;
}

/* The model and its orbit at p: continued by Newton on the impact
 * conditions from the linear predictor u + du/dp (p - p_J) of the last
 * Jacobian's point (else from the current orbit).  The orbit must stay
 * admissible (one that hits a stop between impacts is not this motion)
 * and stable (an unstable orbit is not what a recording shows; Newton
 * may land on one from a far trial). */
static int ensure(vi_identify *id, const double *p)
{
  if (id->have_cur && !memcmp(p, id->pcur, sizeof(double) * id->np))
    return VI_OK;
  vi_model *m = NULL;
  vi_xflow *xf = NULL;
  int st = make_model(id, p, &m), ok = 0, N = id->N;
  if (st) return st;
  orb *tr = &id->trial;
  if (id->have_pred) {
    int B = 2 * N + 1, D = id->acc.m * B;
    orb_copy(tr, &id->acc, N);
    for (int q = 0; q < id->np; q++) {
      double dp = p[q] - id->pacc[q];
      const double *du = id->dudp + (size_t)q * D;
      for (int j = 0; j < tr->m; j++) {
        tr->t[j] += du[(size_t)j * B] * dp;
        for (int i = 0; i < N; i++) {
          tr->x[i + (size_t)j * N] += du[(size_t)j * B + 1 + i] * dp;
          tr->v[i + (size_t)j * N] += du[(size_t)j * B + 1 + N + i] * dp;
        }
      }
    }
  } else {
    orb_copy(tr, &id->o, N);
  }
  st = vi_orbit_pnm_solve_stops(m, tr->n, tr->m, tr->stop, tr->t, tr->x,
                                tr->v, N, 0.0, NULL);
  if (!st)
    st = vi_orbit_pnm_admissible_stops(m, tr->n, tr->m, tr->stop, tr->t,
                                       tr->x, tr->v, N, NULL, &ok);
  if (!st && !ok) st = VI_ERR_NOT_CONVERGED;
  if (!st)
    st = vi_orbit_pnm_multipliers_stops(m, tr->n, tr->m, tr->stop, tr->t,
                                        tr->x, tr->v, N, id->mre, id->mim);
  for (int i = 0; !st && id->stable_only && i < 2 * N; i++)
    if (!(hypot(id->mre[i], id->mim[i]) < 1.0)) st = VI_ERR_NOT_CONVERGED;
  if (!st) st = vi_xflow_create(m, &xf);
  if (st) {
    vi_model_destroy(&m);
    return st;
  }
  drop_cur(id);
  id->cur = m;
  id->xf = xf;
  orb_normalise(tr, period_of(m, tr->n));
  orb_copy(&id->o, tr, N);
  memcpy(id->pcur, p, sizeof(double) * id->np);
  id->have_cur = 1;
  return VI_OK;
}

/* Where model time s falls on the orbit: after impact *j, *tau later, in
 * the *k-th orbit period from the first impact. */
static void locate(const orb *o, double P, double s, int *j, double *tau,
                   double *k)
{
  double ph = s - o->t[0], kk = floor(ph / P);
  ph -= kk * P;
  if (ph >= P) {
    ph -= P;
    kk += 1.0;
  }
  if (ph < 0.0) ph = 0.0;
  int jj = o->m - 1;
  while (jj > 0 && o->t[jj] - o->t[0] > ph) jj--;
  *j = jj;
  *tau = ph - (o->t[jj] - o->t[0]);
  *k = kk;
}

/* State z = (x, v) [2N] of the orbit of m at model time s; zp [2N] the
 * post-impact state of the segment. */
static void orbit_state(const vi_model *m, const vi_xflow *xf, const orb *o,
                        double s, double *z, double *zp, int *jo,
                        double *tauo, double *ko)
{
  int N = m->n, j;
  double tau, k;
  locate(o, period_of(m, o->n), s, &j, &tau, &k);
  memcpy(z, o->x + (size_t)j * N, sizeof(double) * N);
  memcpy(z + N, o->v + (size_t)j * N, sizeof(double) * N);
  vi_var_impact(m, o->stop[j], z, zp);
  vi_xflow_physical(xf, m, o->t[j], zp, zp + N, o->t[j] + tau, z, z + N);
  if (jo) *jo = j;
  if (tauo) *tauo = tau;
  if (ko) *ko = k;
}

/* ---- the least-squares problem ------------------------------------------- */

static int nres(const vi_identify *id) { return id->vy ? 2 * id->ns : id->ns; }

static void split(const vi_identify *id, const gsl_vector *th, double *p,
                  double *t0)
{
  for (int j = 0; j < id->np; j++) p[j] = gsl_vector_get(th, j);
  *t0 = id->fit_shift ? gsl_vector_get(th, id->np) : id->shift0;
}

static int res_f(const gsl_vector *th, void *ctx, gsl_vector *f)
{
  vi_identify *id = ctx;
  int N = id->N, ns = id->ns;
  double p[MAXP], t0, z[64], zp[64];
  double *zz = N <= 32 ? z : malloc(sizeof(double) * 4 * N);
  if (!zz) return GSL_ENOMEM;
  double *zzp = N <= 32 ? zp : zz + (size_t)2 * N;
  if (poll_cancel(id)) { /* stops the GSL iteration */
    if (zz != z) free(zz);
    return GSL_EBADFUNC;
  }
  split(id, th, p, &t0);
  if (ensure(id, p)) {
    /* no admissible orbit there: a cost no step can accept */
    gsl_vector_set_all(f, 1e3 * id->scale);
    if (zz != z) free(zz);
    return GSL_SUCCESS;
  }
  for (int i = 0; i < ns; i++) {
    orbit_state(id->cur, id->xf, &id->o, id->t[i] + t0, zz, zzp, NULL, NULL,
                NULL);
    gsl_vector_set(f, i, id->y[i] - vi_dot(N, id->c, zz));
    if (id->vy)
      gsl_vector_set(f, ns + i, (id->vy[i] - vi_dot(N, id->c, zz + N)) / id->Om0);
  }
  if (zz != z) free(zz);
  return GSL_SUCCESS;
}

/* Difference step of parameter j at p, kept inside its range. */
static void dstep(const vi_identify *id, const double *p, int j, double *hp,
                  double *hm)
{
  double h = 1e-6 * fmax(fabs(p[j]), 1e-3);
  *hp = p[j] + h <= id->hi[j] ? h : 0.0;
  *hm = p[j] - h >= id->lo[j] ? h : 0.0;
}

typedef struct jac_ws {
  double *Fu, *Fp, *F, *Fa, *Fb, *Phi, *zeta, *dz, *z, *zp, *f, *za, *zb, *zt;
  int *ipiv;
  vi_model *mp[MAXP], *mm[MAXP];
  vi_xflow *xp[MAXP], *xm[MAXP];
  double hp[MAXP], hm[MAXP];
} jac_ws;

static void jac_free(jac_ws *w, int np)
{
  free(w->Fu);
  free(w->ipiv);
  for (int j = 0; j < np; j++) {
    vi_xflow_destroy(&w->xp[j]);
    vi_xflow_destroy(&w->xm[j]);
    vi_model_destroy(&w->mp[j]);
    vi_model_destroy(&w->mm[j]);
  }
}

/* Models at p +- h e_j for the differenced parts (VI_IDENTIFY_OTHER: the
 * conditions and the response; Omega: the response at a fixed orbit). */
static int jac_models(vi_identify *id, const double *p, jac_ws *w, int j)
{
  double q[MAXP];
  int st;
  dstep(id, p, j, &w->hp[j], &w->hm[j]);
  memcpy(q, p, sizeof(double) * id->np);
  q[j] = p[j] + w->hp[j];
  if ((st = make_model(id, q, &w->mp[j]))) return st;
  q[j] = p[j] - w->hm[j];
  if ((st = make_model(id, q, &w->mm[j]))) return st;
  if ((st = vi_xflow_create(w->mp[j], &w->xp[j]))) return st;
  return vi_xflow_create(w->mm[j], &w->xm[j]);
}

static int res_df(const gsl_vector *th, void *ctx, gsl_matrix *J)
{
  vi_identify *id = ctx;
  int N = id->N, N2 = 2 * N, ns = id->ns, np = id->np, st;
  double p[MAXP], t0;
  if (poll_cancel(id)) return GSL_EBADFUNC;
  split(id, th, p, &t0);
  if (ensure(id, p)) return GSL_EBADFUNC;
  const vi_model *m = id->cur;
  const orb *o = &id->o;
  int B = N2 + 1, D = o->m * B;
  jac_ws w;
  memset(&w, 0, sizeof w);
  size_t nd = (size_t)D * D + (size_t)D * np + 3 * (size_t)D +
              (size_t)N2 * N2 + 9 * (size_t)N2;
  w.Fu = malloc(sizeof(double) * nd);
  w.ipiv = malloc(sizeof(int) * D);
  if (!w.Fu || !w.ipiv) {
    jac_free(&w, np);
    return GSL_ENOMEM;
  }
  w.Fp = w.Fu + (size_t)D * D;
  w.F = w.Fp + (size_t)D * np;
  w.Fa = w.F + D;
  w.Fb = w.Fa + D;
  w.Phi = w.Fb + D;
  w.zeta = w.Phi + (size_t)N2 * N2;
  w.dz = w.zeta + N2;
  w.z = w.dz + N2;
  w.zp = w.z + N2;
  w.f = w.zp + N2;
  w.za = w.f + N2;
  w.zb = w.za + N2;
  w.zt = w.zb + N2;
  /* the orbit's sensitivity du/dp = -F_u^-1 F_p (exact F_u) */
  st = vi_orbit_pnm_residual_stops(m, o->n, o->m, o->stop, o->t, o->x, o->v,
                                   N, w.F, w.Fu);
  for (int j = 0; !st && j < np; j++) {
    double *Fpj = w.Fp + (size_t)j * D;
    int k = id->kind[j];
    if (k == VI_IDENTIFY_OMEGA || k == VI_IDENTIFY_OTHER)
      st = jac_models(id, p, &w, j);
    if (st) break;
    if (k != VI_IDENTIFY_OTHER) {
      st = vi_orbit_pnm_dparam(m, o->n, o->m, o->stop, o->t, o->x, o->v, N,
                               k, id->kst[j], Fpj);
      continue;
    }
    st = vi_orbit_pnm_residual_stops(w.mp[j], o->n, o->m, o->stop, o->t,
                                     o->x, o->v, N, w.Fa, NULL);
    if (!st)
      st = vi_orbit_pnm_residual_stops(w.mm[j], o->n, o->m, o->stop, o->t,
                                       o->x, o->v, N, w.Fb, NULL);
    for (int i = 0; !st && i < D; i++)
      Fpj[i] = (w.Fa[i] - w.Fb[i]) / (w.hp[j] + w.hm[j]);
  }
  if (!st && LAPACKE_dgesv(LAPACK_COL_MAJOR, D, np, w.Fu, D, w.ipiv, w.Fp, D))
    st = VI_ERR_LAPACK;
  if (st) {
    jac_free(&w, np);
    return GSL_EBADFUNC;
  }
  /* the predictor for the next trials */
  orb_copy(&id->acc, o, N);
  memcpy(id->pacc, p, sizeof(double) * np);
  for (size_t i = 0; i < (size_t)D * np; i++) id->dudp[i] = -w.Fp[i];
  id->have_pred = 1;
  double P = period_of(m, o->n);
  for (int i = 0; i < ns; i++) {
    int j;
    double tau, kper;
    orbit_state(m, id->xf, o, id->t[i] + t0, w.z, w.zp, &j, &tau, &kper);
    double tj = o->t[j];
    int sj = o->stop[j];
    vi_var_field(m, tj, w.zp, w.f);
    if (vi_var_stm(m, tau, w.Phi)) {
      jac_free(&w, np);
      return GSL_EBADFUNC;
    }
    for (int q = 0; q < np; q++) {
      /* du/dp of impact j, through the impact law, moved to the sample:
       * dz(s) = Phi(tau) [R (dx_j, dv_j) - dt_j f+] */
      const double *du = w.Fp + (size_t)q * D + (size_t)j * B;
      double dt = -du[0], dy, dv;
      for (int r = 0; r < N2; r++) w.dz[r] = -du[1 + r];
      vi_var_impact(m, sj, w.dz, w.zeta);
      for (int r = 0; r < N2; r++) w.zeta[r] -= dt * w.f[r];
      if (id->kind[q] == VI_IDENTIFY_R && id->kst[q] == sj) {
        /* d v+/dr = -(w.v-) M^-1 w / (w^T M^-1 w) (WB 2) */
        const double *vj = o->v + (size_t)j * N, *Mw = vi_stop_minvw(m, sj);
        double g = vi_dot(N, vi_stop_w(m, sj), vj) / m->G[sj + (size_t)sj * m->ns];
        for (int r = 0; r < N; r++) w.zeta[N + r] -= g * Mw[r];
      }
      cblas_dgemv(CblasColMajor, CblasNoTrans, N2, N2, 1.0, w.Phi, N2,
                  w.zeta, 1, 0.0, w.dz, 1);
      dy = vi_dot(N, id->c, w.dz);
      dv = vi_dot(N, id->c, w.dz + N);
      if (w.mp[q]) {
        /* the response's own dependence at a fixed orbit (Omega: the
         * forcing and the period, k periods on), differenced */
        double *zt = w.zt;
        double ta = tau + kper * (P - period_of(w.mp[q], o->n));
        double tb = tau + kper * (P - period_of(w.mm[q], o->n));
        memcpy(zt, o->x + (size_t)j * N, sizeof(double) * N);
        memcpy(zt + N, o->v + (size_t)j * N, sizeof(double) * N);
        vi_var_impact(w.mp[q], sj, zt, w.zeta);
        vi_xflow_physical(w.xp[q], w.mp[q], tj, w.zeta, w.zeta + N, tj + ta,
                          w.za, w.za + N);
        memcpy(zt, o->x + (size_t)j * N, sizeof(double) * N);
        memcpy(zt + N, o->v + (size_t)j * N, sizeof(double) * N);
        vi_var_impact(w.mm[q], sj, zt, w.zeta);
        vi_xflow_physical(w.xm[q], w.mm[q], tj, w.zeta, w.zeta + N, tj + tb,
                          w.zb, w.zb + N);
        double h = w.hp[q] + w.hm[q];
        dy += (vi_dot(N, id->c, w.za) - vi_dot(N, id->c, w.zb)) / h;
        dv += (vi_dot(N, id->c, w.za + N) - vi_dot(N, id->c, w.zb + N)) / h;
      }
      gsl_matrix_set(J, i, q, -dy);
      if (id->vy) gsl_matrix_set(J, ns + i, q, -dv / id->Om0);
    }
    if (id->fit_shift) {
      vi_var_field(m, tj + tau, w.z, w.f);
      gsl_matrix_set(J, i, np, -vi_dot(N, id->c, w.f));
      if (id->vy) gsl_matrix_set(J, ns + i, np, -vi_dot(N, id->c, w.f + N) / id->Om0);
    }
  }
  jac_free(&w, np);
  return GSL_SUCCESS;
}

/* ---- the steps of vi_identify_run ---------------------------------------- */

/* The model's steady motion at the starting values: a transient classified
 * P(n, m), its last m impacts refined by Newton. */
static int seed_orbit(vi_identify *id, orb *o)
{
  vi_orbit *ob = NULL;
  const vi_model *m = id->cur;
  int st = vi_orbit_create(m, &ob), pn = 0, pm = 0, N = id->N, cnt = 0;
  if (!st && id->cancel) st = vi_orbit_set_monitor(ob, poll_mon, id, NULL);
  if (!st) st = vi_orbit_find(ob);
  if (!st) st = vi_orbit_classify(ob, &pn, &pm);
  if (st) {
    vi_fail(id->errmsg, st, "the transient at the starting values failed: %s",
            vi_orbit_errmsg(ob));
    vi_orbit_destroy(&ob);
    return st;
  }
  if (pn < 1 || pm < 1 || pm > MAX_M) {
    vi_orbit_destroy(&ob);
    return vi_fail(id->errmsg, VI_ERR_NOT_CONVERGED,
                   pn < 1 ? "the model's motion at the starting values is not "
                            "periodic (no period up to %d forcing periods)"
                          : "the model's motion at the starting values has "
                            "%d impacts per period (1 to %d identifiable)",
                   pn < 1 ? MAX_N : pm, MAX_M);
  }
  o->n = pn;
  o->m = pm;
  if (!vi_orbit_impacts(ob, &cnt, o->t, o->stop, NULL, o->x, o->v, N) &&
      cnt == pm) {
    /* the analysed P(1, m) orbit */
  } else {
    /* its last pm impacts in the transient's record */
    for (int j = 0; j < pm; j++) {
      size_t r = (size_t)((ob->nimp - pm + j) % RING);
      o->t[j] = ob->rt[r];
      o->stop[j] = ob->rs[r];
      memcpy(o->x + (size_t)j * N, ob->rz + r * 2 * N, sizeof(double) * N);
      memcpy(o->v + (size_t)j * N, ob->rz + r * 2 * N + N, sizeof(double) * N);
    }
  }
  vi_orbit_destroy(&ob);
  int ok = 0;
  st = vi_orbit_pnm_solve_stops(m, o->n, o->m, o->stop, o->t, o->x, o->v, N,
                                0.0, NULL);
  if (!st)
    st = vi_orbit_pnm_admissible_stops(m, o->n, o->m, o->stop, o->t, o->x,
                                       o->v, N, NULL, &ok);
  if (st || !ok)
    return vi_fail(id->errmsg, VI_ERR_NOT_CONVERGED,
                   "the model's P(%d,%d) motion at the starting values cannot "
                   "be refined to a periodic orbit (%s)", pn, pm,
                   st ? vi_strerror(st) : "not admissible");
  orb_normalise(o, period_of(m, o->n));
  return VI_OK;
}

/* Linear interpolation of the recording at time s (inside its span). */
static double interp(const vi_identify *id, double s)
{
  int a = 0, b = id->ns - 1;
  while (b - a > 1) {
    int c = (a + b) / 2;
    if (id->t[c] <= s) a = c;
    else b = c;
  }
  double u = (s - id->t[a]) / (id->t[b] - id->t[a]);
  return id->y[a] + u * (id->y[b] - id->y[a]);
}

/* RMS change of the recording over a time lag P against its RMS
 * variation, over the samples that have a partner; NaN if fewer than 8. */
static double repeat_ratio(const vi_identify *id, double P)
{
  int ns = id->ns, cnt = 0;
  double mean = 0.0, var = 0.0, d = 0.0;
  for (int i = 0; i < ns; i++) mean += id->y[i] / ns;
  for (int i = 0; i < ns; i++) var += (id->y[i] - mean) * (id->y[i] - mean);
  for (int i = 0; i < ns && id->t[i] + P <= id->t[ns - 1]; i++, cnt++) {
    double e = interp(id, id->t[i] + P) - id->y[i];
    d += e * e;
  }
  if (cnt < 8 || !(var > 0.0)) return NAN;
  return sqrt(d / cnt) / sqrt(var / ns);
}

/* The recording's period in forcing periods T: the smallest n <= MAX_N it
 * repeats with, as well as with the best one up to the noise (0 if none;
 * 1 when it is too short to tell). */
static int data_period(vi_identify *id, double T)
{
  double rat[MAX_N + 1], best = HUGE_VAL;
  int known = 0;
  for (int n = 1; n <= MAX_N; n++) {
    rat[n] = repeat_ratio(id, n * T);
    if (isfinite(rat[n])) {
      best = fmin(best, rat[n]);
      known = n;
    }
  }
  if (!known) return 1;
  for (int n = 1; n <= known; n++)
    if (rat[n] < 0.3 && rat[n] <= fmax(1.5 * best, best + 0.05)) return n;
  vi_fail(id->errmsg, VI_ERR_ARG,
          "the recording does not repeat with any period up to %d forcing "
          "periods (2 pi / Omega = %g): its change over one period is %.2g "
          "of its RMS variation (a motion that is not periodic)", known, T,
          rat[1]);
  return 0;
}

/* Starting shift: the best of 128 over one orbit period, on the first two
 * periods of the recording. */
static double scan_shift(vi_identify *id, double *cost_out)
{
  if (cost_out) *cost_out = HUGE_VAL;
  double P = period_of(id->cur, id->o.n), best = 0.0, bc = HUGE_VAL;
  int N = id->N, use = 0;
  double z[64], zp[64];
  double *zz = N <= 32 ? z : malloc(sizeof(double) * 4 * N);
  if (!zz) return 0.0;
  double *zzp = N <= 32 ? zp : zz + (size_t)2 * N;
  while (use < id->ns && id->t[use] - id->t[0] < 2.0 * P && use < 1024) use++;
  for (int k = 0; k < 128; k++) {
    double t0 = k * P / 128.0, cost = 0.0;
    for (int i = 0; i < use; i++) {
      orbit_state(id->cur, id->xf, &id->o, id->t[i] + t0, zz, zzp, NULL, NULL,
                  NULL);
      double e = id->y[i] - vi_dot(N, id->c, zz);
      cost += e * e;
    }
    if (cost < bc) {
      bc = cost;
      best = t0;
    }
  }
  if (zz != z) free(zz);
  if (cost_out) *cost_out = bc;
  return best;
}

static int cmp_double(const void *a, const void *b)
{
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* Noise of a near-uniform recording from its 4th differences (a smooth
 * signal's are ~ A (Omega dt)^4; noise's have variance 70 sigma^2), their
 * median absolute value robust to the impacts' kinks. */
static double noise_estimate(const vi_identify *id)
{
  int ns = id->ns;
  double dmin = HUGE_VAL, dmax = 0.0;
  for (int i = 1; i < ns; i++) {
    dmin = fmin(dmin, id->t[i] - id->t[i - 1]);
    dmax = fmax(dmax, id->t[i] - id->t[i - 1]);
  }
  if (dmax > 1.01 * dmin || ns < 16) return NAN;
  double *d = malloc(sizeof(double) * ns);
  if (!d) return NAN;
  int k = 0;
  for (int i = 0; i + 4 < ns; i++)
    d[k++] = fabs(id->y[i] - 4 * id->y[i + 1] + 6 * id->y[i + 2] -
                  4 * id->y[i + 3] + id->y[i + 4]);
  qsort(d, k, sizeof(double), cmp_double);
  double med = k % 2 ? d[k / 2] : 0.5 * (d[k / 2 - 1] + d[k / 2]);
  free(d);
  return 1.4826 * med / sqrt(70.0);
}

/* Standard errors, intervals, correlations and flags from the Jacobian at
 * the optimum, columns scaled to unit norm, by its SVD: cov = s^2 V S^-2 V^T
 * (scaled back); directions with no singular value are infinitely
 * uncertain, not zero. */
static int uncertainty(vi_identify *id, const gsl_matrix *J, double ssr)
{
  int nr = (int)J->size1, P = (int)J->size2, np = id->np, st = VI_OK;
  gsl_matrix *A = gsl_matrix_alloc(nr, P), *V = gsl_matrix_alloc(P, P);
  gsl_vector *S = gsl_vector_alloc(P), *wk = gsl_vector_alloc(P),
             *D = gsl_vector_alloc(P);
  gsl_matrix *C = gsl_matrix_calloc(P, P);
  if (!A || !V || !S || !wk || !D || !C) {
    st = VI_ERR_NOMEM;
    goto done;
  }
  gsl_matrix_memcpy(A, J);
  for (int q = 0; q < P; q++) {
    gsl_vector_view col = gsl_matrix_column(A, q);
    double nrm = gsl_blas_dnrm2(&col.vector);
    gsl_vector_set(D, q, nrm > 0.0 ? nrm : 1.0);
    gsl_vector_scale(&col.vector, 1.0 / gsl_vector_get(D, q));
  }
  if (gsl_linalg_SV_decomp(A, V, S, wk)) {
    st = VI_ERR_NOT_CONVERGED;
    goto done;
  }
  double smax = gsl_vector_get(S, 0), smin = gsl_vector_get(S, P - 1);
  id->rcond = smax > 0.0 ? smin / smax : 0.0;
  int dof = nr - P;
  double s2 = dof > 0 ? ssr / dof : NAN;
  double tq = dof > 0 ? gsl_cdf_tdist_Pinv(0.975, dof) : NAN;
  int sing[MAXP + 1] = {0};
  for (int k = 0; k < P; k++) {
    double sk = gsl_vector_get(S, k);
    int null = !(sk > 1e-13 * smax), ill = !(sk > 1e-10 * smax) || null;
    for (int a = 0; a < P; a++) {
      double va = gsl_matrix_get(V, a, k);
      if (ill && fabs(va) > (null ? 1e-3 : 0.1)) sing[a] = null ? 2 : 1;
      if (null) continue;
      for (int b = 0; b < P; b++)
        *gsl_matrix_ptr(C, a, b) += va * gsl_matrix_get(V, b, k) / (sk * sk);
    }
  }
  for (int a = 0; a < P; a++)
    for (int b = 0; b < P; b++)
      *gsl_matrix_ptr(C, a, b) *= s2 / (gsl_vector_get(D, a) * gsl_vector_get(D, b));
  for (int j = 0; j < np; j++) {
    double se = sing[j] == 2 ? INFINITY : sqrt(gsl_matrix_get(C, j, j));
    id->se[j] = se;
    id->l95[j] = id->p[j] - tq * se;
    id->h95[j] = id->p[j] + tq * se;
    int fl = 0;
    double range = id->hi[j] - id->lo[j], eps = 1e-6 * (isfinite(range) ? range : fmax(fabs(id->p[j]), 1.0));
    if (id->p[j] - id->lo[j] <= eps || id->hi[j] - id->p[j] <= eps) fl |= VI_IDENTIFY_ON_BOUND;
    if (sing[j] || !isfinite(se) || 2.0 * tq * se > range) fl |= VI_IDENTIFY_UNDETERMINED;
    for (int q = 0; q < np; q++) {
      double cc = gsl_matrix_get(C, j, q) /
                  sqrt(gsl_matrix_get(C, j, j) * gsl_matrix_get(C, q, q));
      if (sing[j] || sing[q]) cc = j == q ? 1.0 : NAN;
      id->corr[j + (size_t)q * np] = cc;
      if (q != j && fabs(cc) > 0.99) fl |= VI_IDENTIFY_CORRELATED;
    }
    id->flags[j] = fl;
  }
  id->t0se = id->fit_shift ? (sing[np] == 2 ? INFINITY : sqrt(gsl_matrix_get(C, np, np))) : 0.0;
done:
  gsl_matrix_free(A);
  gsl_matrix_free(V);
  gsl_vector_free(S);
  gsl_vector_free(wk);
  gsl_vector_free(D);
  gsl_matrix_free(C);
  return st;
}

/* Value (der = 0) or slope (der = 1) at time s of a least-squares
 * polynomial of degree deg through the k samples of f before s. */
static double local_poly(const vi_identify *id, const double *f, int last,
                         int k, int deg, double s, int der)
{
  double A[25] = {0}, r[5] = {0}, h = id->t[last] - id->t[last - k + 1];
  int d1 = deg + 1, ipiv[5];
  for (int i = last - k + 1; i <= last; i++) {
    double u = (id->t[i] - s) / h, pw[5] = {1.0, u, u * u, u * u * u, u * u * u * u};
    for (int a = 0; a < d1; a++) {
      r[a] += pw[a] * f[i];
      for (int c = 0; c < d1; c++) A[a + d1 * c] += pw[a] * pw[c];
    }
  }
  if (LAPACKE_dgesv(LAPACK_COL_MAJOR, d1, 1, A, d1, ipiv, r, d1)) return NAN;
  return der ? r[1] / h : r[0];
}

/* The recorded approach velocity at time s.  When the model explains
 * the recording (residual RMS within 1.5 times the noise): the fitted
 * model's vN plus the recording's departure from it just before s (the
 * slope of a line through the last 8 displacement residuals, or the mean
 * of the last 3 velocity residuals: low-order, so that noise is averaged,
 * not amplified); the model interpolates what 64 samples per period
 * cannot, the higher modes ringing between impacts.  Otherwise NaN:
 * 64 samples per period do not resolve the approach by themselves (a
 * local polynomial of the 4-mode beam's samples is off by 2 % of vN, and
 * a model that misses the motion puts its impacts elsewhere). */
static double recorded_slope(const vi_identify *id, const double *e,
                             const double *ev, double vNm, int assisted,
                             double s)
{
  int b = 0, en = id->ns;
  while (en - b > 1) {
    int c = (b + en) / 2;
    if (id->t[c] < s) b = c;
    else en = c;
  }
  int last = b; /* last sample before s */
  if (!(id->t[last] < s) || last < 8) return NAN;
  if (!assisted) return NAN;
  return vNm + (ev ? local_poly(id, ev, last, 3, 0, s, 0)
                   : local_poly(id, e, last, 8, 1, s, 1));
}

/* WB 12 at the fitted orbit: the model's residual energy from its modal
 * ledger over one period (vi_orbit_balance, started on the orbit), the
 * recorded approach velocity averaged over the recorded impacts. */
static void energy_route(vi_identify *id)
{
  id->r12 = id->vN = id->KE = id->RE = NAN;
  const vi_model *m = id->cur;
  const orb *o = &id->o;
  int N = id->N;
  if (o->n != 1 || o->m != 1 || o->stop[0] != 0) return;
  const double *w = vi_stop_w(m, 0);
  for (int i = 0; i < N; i++)
    if (fabs(id->c[i] - w[i]) > 1e-12 * (fabs(w[i]) + 1e-300)) return;
  double P = period_of(m, 1), sum = 0.0;
  int cnt = 0, ns = id->ns;
  double *e = malloc(sizeof(double) * (2 * (size_t)ns + 4 * (size_t)N));
  if (!e) return;
  double *ev = e + ns, *zz = ev + ns;
  for (int i = 0; i < ns; i++) {
    orbit_state(m, id->xf, o, id->t[i] + id->t0, zz, zz + (size_t)2 * N, NULL, NULL,
                NULL);
    e[i] = id->y[i] - vi_dot(N, id->c, zz);
    ev[i] = id->vy ? id->vy[i] - vi_dot(N, id->c, zz + N) : 0.0;
  }
  double vNm = vi_dot(N, w, o->v);
  double nz = id->sigma > 0.0 ? id->sigma : noise_estimate(id);
  int assisted = !(id->rms > 1.5 * nz);
  for (long k = (long)ceil((id->t[0] + id->t0 - o->t[0]) / P);; k++) {
    double s = o->t[0] + (double)k * P - id->t0; /* recording time of impact k */
    if (s > id->t[ns - 1]) break;
    double v = recorded_slope(id, e, id->vy ? ev : NULL, vNm, assisted, s);
    if (isfinite(v)) {
      sum += v;
      cnt++;
    }
  }
  free(e);
  if (cnt == 0) return;
  id->vN = sum / cnt;
  id->KE = 0.5 * id->vN * id->vN / m->G[0];
  /* the modal ledger of one period, from the orbit's state at t = 0 */
  double *z = malloc(sizeof(double) * 4 * N);
  vi_orbit *ob = NULL;
  double RE = NAN;
  int pn = 0, pm = 0;
  if (z) {
    orbit_state(m, id->xf, o, 0.0, z, z + (size_t)2 * N, NULL, NULL, NULL);
    if (!vi_orbit_create(m, &ob) && !vi_orbit_set_initial(ob, z, z + N) &&
        !vi_orbit_set_direct_search(ob, 0) && !vi_orbit_find(ob) &&
        !vi_orbit_classify(ob, &pn, &pm) && pn == 1 && pm == 1)
      vi_orbit_balance(ob, NULL, NULL, NULL, NULL, &RE, NULL, NULL, NULL);
  }
  vi_orbit_destroy(&ob);
  free(z);
  if (isnan(RE)) {
    /* an orbit the transient cannot hold (unstable): its ledger over one
     * period still closes, RE = IE = 1/2 vN^2 (1 - r^2) / G (WB 10, 11) */
    double r = m->rv[0];
    RE = 0.5 * vNm * vNm * (1.0 - r * r) / m->G[0];
  }
  id->RE = RE;
  if (RE >= 0.0 && RE <= id->KE) id->r12 = sqrt(1.0 - RE / id->KE);
}

/* The model's orbit the recording shows, period nd forcing periods: the
 * transient's motion and every stable admissible P(nd, 1) orbit of the
 * impact-phase scan (the start may lie where several coexist, or where the
 * transient settles on another), the one closest to the recording. */
static int choose_orbit(vi_identify *id, int nd)
{
  const vi_model *m = id->cur;
  int N = id->N, found = 0, best = -1, cap = 16, ok = 0, st;
  double bc = HUGE_VAL, cost = HUGE_VAL;
  orb cand;
  memset(&cand, 0, sizeof cand);
  cand.x = malloc(sizeof(double) * (size_t)N * (MAX_M + 2 * cap));
  cand.v = malloc(sizeof(double) * (size_t)N * (MAX_M + 2 * cap));
  double *st_ = malloc(sizeof(double) * cap);
  orb keep = id->o; /* buffers of the chosen one */
  if (!cand.x || !cand.v || !st_) {
    free(cand.x);
    free(cand.v);
    free(st_);
    return vi_fail(id->errmsg, VI_ERR_NOMEM, "out of memory");
  }
  double *sx = cand.x + (size_t)N * MAX_M, *sv = cand.v + (size_t)N * MAX_M;
  char why[VI_MSG_LEN] = "";
  int tn = 0, tm = 0;
  if (!seed_orbit(id, &cand)) {
    tn = cand.n;
    tm = cand.m;
    if (cand.n == nd) {
      id->o = cand; /* borrow the buffers for the cost */
      scan_shift(id, &cost);
      id->o = keep;
      bc = cost;
      best = cap;
      orb_copy(&keep, &cand, N);
    }
  } else {
    snprintf(why, sizeof why, "%s", id->errmsg);
  }
  st = vi_orbit_p1_scan_polled(m, nd, 256, st_, sx, sv, N, cap, &found,
                               poll_fn, id);
  for (int k = 0; !st && k < found && k < cap; k++) {
    orb c1;
    c1.n = nd;
    c1.m = 1;
    c1.stop[0] = 0;
    c1.t[0] = st_[k];
    c1.x = sx + (size_t)k * N;
    c1.v = sv + (size_t)k * N;
    if (vi_orbit_pnm_admissible(m, nd, 1, c1.t, c1.x, c1.v, N, NULL, &ok) || !ok ||
        vi_orbit_pnm_multipliers(m, nd, 1, c1.t, c1.x, c1.v, N, id->mre, id->mim))
      continue;
    int stable = 1;
    for (int i = 0; i < 2 * N; i++)
      if (!(hypot(id->mre[i], id->mim[i]) < 1.0)) stable = 0;
    if (!stable && id->stable_only) continue;
    orb_normalise(&c1, period_of(m, nd));
    orb save = id->o;
    id->o.n = c1.n;
    id->o.m = 1;
    id->o.stop[0] = 0;
    id->o.t[0] = c1.t[0];
    id->o.x = c1.x;
    id->o.v = c1.v;
    scan_shift(id, &cost);
    id->o = save;
    if (cost < bc) {
      bc = cost;
      best = k;
      keep.n = nd;
      keep.m = 1;
      keep.stop[0] = 0;
      keep.t[0] = c1.t[0];
      memcpy(keep.x, c1.x, sizeof(double) * N);
      memcpy(keep.v, c1.v, sizeof(double) * N);
    }
  }
  free(cand.x);
  free(cand.v);
  free(st_);
  if (best < 0) {
    if (tn)
      return vi_fail(id->errmsg, VI_ERR_NOT_CONVERGED,
                     "the recording repeats every %d forcing period(s), but "
                     "the model at the starting values settles on P(%d,%d) "
                     "and the impact-phase scan finds no %sP(%d,1) orbit: "
                     "start nearer", nd, tn, tm,
                     id->stable_only ? "stable " : "", nd);
    return vi_fail(id->errmsg, VI_ERR_NOT_CONVERGED, "%s",
                   why[0] ? why : "no periodic orbit at the starting values");
  }
  id->o = keep;
  return VI_OK;
}

int vi_identify_run(vi_identify *id)
{
  if (!id) return VI_ERR_ARG;
  id->done = 0;
  if (!id->ns) return vi_fail(id->errmsg, VI_ERR_STATE, "no recording set");
  for (int j = 0; j < id->np; j++) {
    if (!id->pset[j])
      return vi_fail(id->errmsg, VI_ERR_STATE, "parameter %d not set", j + 1);
    if (id->kind[j] == VI_IDENTIFY_OTHER && !id->fn && !id->key[j][0])
      return vi_fail(id->errmsg, VI_ERR_STATE,
                     "parameter %d needs a key or a model builder", j + 1);
  }
  int np = id->np, P = np + id->fit_shift, nr = nres(id), st;
  id->errmsg[0] = 0;
  id->cancel_hit = 0;
  if (poll_cancel(id)) return vi_fail(id->errmsg, VI_CANCELLED, "cancelled");
  /* the model and its orbit at the starting values */
  drop_cur(id);
  id->have_pred = 0;
  vi_model *m0 = NULL;
  if ((st = make_model(id, id->p0, &m0)))
    return id->errmsg[0] ? st
                         : vi_fail(id->errmsg, st, "no model at the starting "
                                   "values (%s)", vi_strerror(st));
  id->cur = m0;
  if ((st = vi_xflow_create(m0, &id->xf))) return vi_fail(id->errmsg, st, "out of memory");
  id->Om0 = m0->omega_f;
  id->scale = 0.0;
  for (int i = 0; i < id->ns; i++) id->scale = fmax(id->scale, fabs(id->y[i]));
  if (!(id->scale > 0.0)) id->scale = 1.0;
  double T = period_of(m0, 1), span = id->t[id->ns - 1] - id->t[0];
  if (id->ns < 4 * P + 8)
    return vi_fail(id->errmsg, VI_ERR_ARG,
                   "too few samples: %d for %d fitted values", id->ns, P);
  int nd = data_period(id, T);
  if (!nd) return VI_ERR_ARG;
  if (span < nd * T)
    return vi_fail(id->errmsg, VI_ERR_ARG,
                   "the recording spans %g time units, less than one period "
                   "%g of its motion", span, nd * T);
  if ((st = choose_orbit(id, nd)))
    return id->cancel_hit ? vi_fail(id->errmsg, VI_CANCELLED, "cancelled "
                                    "while seeking the orbit") : st;
  memcpy(id->pcur, id->p0, sizeof(double) * np);
  id->have_cur = 1;
  double t0 = id->fit_shift && isnan(id->shift0) ? scan_shift(id, NULL) : id->shift0;

  gsl_multifit_nlinear_fdf fdf;
  gsl_multifit_nlinear_parameters par = gsl_multifit_nlinear_default_parameters();
  par.trs = gsl_multifit_nlinear_trs_lm;
  fdf.f = res_f;
  fdf.df = res_df;
  fdf.fvv = NULL;
  fdf.n = (size_t)nr;
  fdf.p = (size_t)P;
  fdf.params = id;
  gsl_multifit_nlinear_workspace *w =
      gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &par, nr, P);
  gsl_vector *x0 = gsl_vector_alloc(P);
  if (!w || !x0) {
    gsl_multifit_nlinear_free(w);
    gsl_vector_free(x0);
    return vi_fail(id->errmsg, VI_ERR_NOMEM, "out of memory");
  }
  for (int j = 0; j < np; j++) gsl_vector_set(x0, j, id->p0[j]);
  if (id->fit_shift) gsl_vector_set(x0, np, t0);
  int info = 0;
  st = gsl_multifit_nlinear_init(x0, &fdf, w);
  if (!st) st = gsl_multifit_nlinear_driver(200, 1e-10, 1e-10, 0.0, NULL, NULL,
                                            &info, w);
  id->iters = (int)gsl_multifit_nlinear_niter(w);
  if (id->cancel_hit) {
    gsl_multifit_nlinear_free(w);
    gsl_vector_free(x0);
    return vi_fail(id->errmsg, VI_CANCELLED, "cancelled after %d least-squares "
                   "iterations", id->iters);
  }
  /* GSL_ENOPROG: no step lowers the cost any more (the optimum to round-off) */
  id->conv = st == GSL_SUCCESS || st == GSL_ENOPROG;
  if (st && st != GSL_ENOPROG && st != GSL_EMAXITER) {
    int code = st == GSL_ENOMEM ? VI_ERR_NOMEM : VI_ERR_NOT_CONVERGED;
    vi_fail(id->errmsg, code, "least squares failed: %s", gsl_strerror(st));
    gsl_multifit_nlinear_free(w);
    gsl_vector_free(x0);
    return code;
  }
  const gsl_vector *xs = gsl_multifit_nlinear_position(w);
  double p[MAXP];
  split(id, xs, p, &id->t0);
  memcpy(id->p, p, sizeof(double) * np);
  /* the residual and Jacobian at the optimum, evaluated afresh */
  gsl_vector *f = gsl_vector_alloc(nr);
  gsl_matrix *J = gsl_matrix_alloc(nr, P);
  st = f && J ? VI_OK : VI_ERR_NOMEM;
  if (!st && ensure(id, p)) st = VI_ERR_NOT_CONVERGED;
  if (!st) res_f(xs, id, f);
  if (!st && res_df(xs, id, J)) st = VI_ERR_NOT_CONVERGED;
  if (!st) {
    double ssr = 0.0, ssx = 0.0;
    for (int i = 0; i < nr; i++) ssr += gsl_vector_get(f, i) * gsl_vector_get(f, i);
    for (int i = 0; i < id->ns; i++) ssx += gsl_vector_get(f, i) * gsl_vector_get(f, i);
    id->rms = sqrt(ssx / id->ns);
    st = uncertainty(id, J, ssr);
  }
  gsl_vector_free(f);
  gsl_matrix_free(J);
  gsl_multifit_nlinear_free(w);
  gsl_vector_free(x0);
  if (st)
    return vi_fail(id->errmsg, st, "no uncertainty at the optimum: %s",
                   vi_strerror(st));
  id->noise = id->sigma > 0.0 ? id->sigma : noise_estimate(id);
  energy_route(id);
  id->mumax = NAN;
  const orb *o = &id->o;
  if (!vi_orbit_pnm_multipliers_stops(id->cur, o->n, o->m, o->stop, o->t, o->x,
                                      o->v, id->N, id->mre, id->mim)) {
    id->mumax = 0.0;
    for (int i = 0; i < 2 * id->N; i++)
      id->mumax = fmax(id->mumax, hypot(id->mre[i], id->mim[i]));
  }
  id->done = 1;
  return VI_OK;
}

/* ---- results ------------------------------------------------------------- */

#define NEED_DONE(id) \
  do { if (!(id)) return VI_ERR_ARG; if (!(id)->done) return VI_ERR_STATE; } while (0)

int vi_identify_params(const vi_identify *id, double *p, double *se,
                       double *lo95, double *hi95, int *flags)
{
  NEED_DONE(id);
  size_t b = sizeof(double) * id->np;
  if (p) memcpy(p, id->p, b);
  if (se) memcpy(se, id->se, b);
  if (lo95) memcpy(lo95, id->l95, b);
  if (hi95) memcpy(hi95, id->h95, b);
  if (flags) memcpy(flags, id->flags, sizeof(int) * id->np);
  return VI_OK;
}

int vi_identify_shift(const vi_identify *id, double *t0, double *se)
{
  NEED_DONE(id);
  if (t0) *t0 = id->t0;
  if (se) *se = id->t0se;
  return VI_OK;
}

int vi_identify_correlation(const vi_identify *id, double *R, int ld)
{
  NEED_DONE(id);
  if (!R || ld < id->np) return VI_ERR_ARG;
  for (int q = 0; q < id->np; q++)
    for (int j = 0; j < id->np; j++)
      R[j + (size_t)q * ld] = id->corr[j + (size_t)q * id->np];
  return VI_OK;
}

int vi_identify_summary(const vi_identify *id, int *converged, int *iterations,
                        double *rms, double *noise, double *rcond, int *n,
                        int *m)
{
  NEED_DONE(id);
  if (converged) *converged = id->conv;
  if (iterations) *iterations = id->iters;
  if (rms) *rms = id->rms;
  if (noise) *noise = id->noise;
  if (rcond) *rcond = id->rcond;
  if (n) *n = id->o.n;
  if (m) *m = id->o.m;
  return VI_OK;
}

int vi_identify_nparams(const vi_identify *id) { return id ? id->np : 0; }

int vi_identify_stability(const vi_identify *id, double *mu)
{
  NEED_DONE(id);
  if (!mu) return VI_ERR_ARG;
  *mu = id->mumax;
  return VI_OK;
}

int vi_identify_orbit_period(const vi_identify *id, double *period, double *t)
{
  NEED_DONE(id);
  if (period) *period = period_of(id->cur, id->o.n);
  if (t) memcpy(t, id->o.t, sizeof(double) * id->o.m);
  return VI_OK;
}

int vi_identify_response(const vi_identify *id, int nt, const double *t,
                         double *x, double *v)
{
  NEED_DONE(id);
  if (nt < 0 || (nt > 0 && (!t || !x))) return VI_ERR_ARG;
  int N = id->N;
  double *z = malloc(sizeof(double) * 4 * N);
  if (!z) return VI_ERR_NOMEM;
  for (int i = 0; i < nt; i++) {
    if (!isfinite(t[i])) {
      free(z);
      return VI_ERR_NONFINITE;
    }
    orbit_state(id->cur, id->xf, &id->o, t[i] + id->t0, z, z + (size_t)2 * N, NULL,
                NULL, NULL);
    x[i] = vi_dot(N, id->c, z);
    if (v) v[i] = vi_dot(N, id->c, z + N);
  }
  free(z);
  return VI_OK;
}

int vi_identify_energy_restitution(const vi_identify *id, double *r12,
                                   double *vN, double *KE, double *RE)
{
  NEED_DONE(id);
  if (r12) *r12 = id->r12;
  if (vN) *vN = id->vN;
  if (KE) *KE = id->KE;
  if (RE) *RE = id->RE;
  return VI_OK;
}

/* Least squares on the two columns cos, sin (normal equations: a 2 x 2
 * system, solved by Cramer's rule). */
int vi_identify_forcing_phase(int ns, const double *t, const double *f,
                              double omega, double *t0)
{
  if (!t0) return VI_ERR_ARG;
  *t0 = NAN;
  if (!t || !f || ns < 2) return VI_ERR_ARG;
  if (!(omega > 0.0)) return isfinite(omega) ? VI_ERR_FREQUENCY : VI_ERR_NONFINITE;
  double cc = 0, cs = 0, ss = 0, fc = 0, fs = 0;
  for (int i = 0; i < ns; i++) {
    if (!isfinite(t[i]) || !isfinite(f[i])) return VI_ERR_NONFINITE;
    vi_phase p = vi_phase_at(omega, t[i]); /* the forcing phase */
    double c = p.c, s = p.s;
    cc += c * c;
    cs += c * s;
    ss += s * s;
    fc += f[i] * c;
    fs += f[i] * s;
  }
  double det = cc * ss - cs * cs;
  if (!(fabs(det) > 0)) return VI_ERR_ARG;
  double al = (fc * ss - fs * cs) / det, be = (fs * cc - fc * cs) / det;
  /* alpha cos + beta sin = A cos(Omega t - phi), phi = atan2(beta, alpha):
   * t0 = -phi / Omega, into [0, T) */
  double T = 2 * M_PI / omega, s0 = fmod(atan2(-be, al) / omega, T);
  *t0 = s0 < 0 ? s0 + T : s0;
  return VI_OK;
}
