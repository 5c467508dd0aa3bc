/* vi_identify.c - model parameters from a recorded periodic response
 * (MODEL.md sections 5, 6; the paper's section 4): the handle, its
 * set-up, the order of vi_identify_run and the result getters.  The steps
 * live by concern in the files vi_identify_internal.h lists. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vi_forcing.h"
#include "vi_identify_internal.h"
#include "vibroimpact/vi_param.h"

/* The cancel poll, sticky within a run (GSL and the scans stop on it). */
int vi_id_poll_cancel(vi_identify *id)
{
  if (id->cancel && !id->cancel_hit && id->cancel(id->cancel_user))
    id->cancel_hit = 1;
  return id->cancel_hit;
}
int vi_id_poll_fn(void *user) { return vi_id_poll_cancel(user); }
int vi_id_poll_mon(const vi_progress *p, void *user)
{
  (void)p;
  return vi_id_poll_cancel(user);
}

int vi_id_orb_alloc(orb *o, int N)
{
  o->x = calloc((size_t)N * MAX_M, sizeof(double));
  o->v = calloc((size_t)N * MAX_M, sizeof(double));
  return o->x && o->v ? VI_OK : VI_ERR_NOMEM;
}

void vi_id_orb_copy(orb *d, const orb *s, int N)
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
  if (!vi_model_has_modes(base) || !vi_xflow_available(base))
    return VI_ERR_UNSUPPORTED;
  if (!(base->omega_f > 0.0)) return VI_ERR_FREQUENCY;
  vi_identify *id = calloc(1, sizeof *id);
  if (!id) return VI_ERR_NOMEM;
  id->base = base;
  vi_model_hold(base, 1); /* a fit changes copies of it, never it */
  id->N = base->n;
  id->np = np;
  id->fit_shift = 1;
  id->stable_only = 1;
  id->shift0 = NAN;
  id->global = 1;
  vi_id_hold(id, -1, NAN);
  id->c = malloc(sizeof(double) * id->N);
  id->dudp = malloc(sizeof(double) * (size_t)MAX_M * (2 * id->N + 1) * np);
  id->mre = malloc(sizeof(double) * 4 * (size_t)id->N);
  id->mim = id->mre ? id->mre + (size_t)2 * id->N : NULL;
  if (!id->c || !id->dudp || !id->mre || vi_id_orb_alloc(&id->o, id->N) ||
      vi_id_orb_alloc(&id->trial, id->N) || vi_id_orb_alloc(&id->acc, id->N)) {
    vi_identify_destroy(&id);
    return VI_ERR_NOMEM;
  }
  memcpy(id->c, vi_stop_w(base, 0), sizeof(double) * id->N);
  *out = id;
  return VI_OK;
}

void vi_id_drop_cur(vi_identify *id)
{
  vi_xflow_destroy(&id->xf);
  vi_model_destroy(&id->cur);
  id->have_cur = 0;
}

void vi_identify_destroy(vi_identify **idp)
{
  if (!idp || !*idp) return;
  vi_identify *id = *idp;
  vi_id_drop_cur(id);
  if (id->destroy) id->destroy(id->user);
  vi_user_set(&id->cancel_user, &id->cancel_free, NULL, NULL);
  free(id->c);
  free(id->t);
  free(id->y);
  free(id->vy);
  free(id->ay);
  vi_id_free_channels(id);
  vi_id_free_solutions(id);
  free(id->o.x);
  free(id->o.v);
  free(id->trial.x);
  free(id->trial.v);
  free(id->acc.x);
  free(id->acc.v);
  free(id->dudp);
  free(id->mre);
  vi_model_hold(id->base, -1);
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
  /* the same number twice is two columns of one: no fit tells them apart
   * (each came out "not determined", at two different values) */
  for (int q = 0; q < id->np; q++)
    if (q != j && id->pset[q] && kind != VI_IDENTIFY_OTHER && id->kind[q] == kind &&
        (kind == VI_IDENTIFY_OMEGA || id->kst[q] == k))
      return vi_fail(id->errmsg, VI_ERR_ARG, "parameter %d: %s is parameter %d already",
                     j + 1, id->key[q], q + 1);
  id->kind[j] = kind;
  id->kst[j] = kind == VI_IDENTIFY_XS || kind == VI_IDENTIFY_R ? k : 0;
  if (kind == VI_IDENTIFY_OMEGA) snprintf(id->key[j], sizeof id->key[j], "forcing.omega");
  else if (kind == VI_IDENTIFY_XS) snprintf(id->key[j], sizeof id->key[j], "stops[%d].xs", k + 1);
  else if (kind == VI_IDENTIFY_R) snprintf(id->key[j], sizeof id->key[j], "stops[%d].r", k + 1);
  id->p0[j] = id->pgiven[j] = p0;
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
  for (int q = 0; q < id->np; q++)
    if (q != j && id->pset[q] && !strcmp(id->key[q], key))
      return vi_fail(id->errmsg, VI_ERR_ARG, "parameter %d: %s is parameter %d already",
                     j + 1, key, q + 1);
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
  if (id && !x) return vi_fail(id->errmsg, VI_ERR_ARG, "no times or values");
  return vi_identify_set_sensors(id, ns, t, x, v, NULL);
}

int vi_identify_set_sensors(vi_identify *id, int ns, const double *t,
                            const double *x, const double *v, const double *a)
{
  if (!id) return VI_ERR_ARG;
  if (!t || (!x && !v && !a))
    return vi_fail(id->errmsg, VI_ERR_ARG, "no times or values");
  if (ns < 16)
    return vi_fail(id->errmsg, VI_ERR_ARG,
                   "too few samples: %d (at least 16)", ns);
  const double *ch[3] = {x, v, a};
  static const char *const nm[3] = {"x", "v", "a"};
  for (int i = 0; i < ns; i++) {
    if (!isfinite(t[i]))
      return vi_fail(id->errmsg, VI_ERR_NONFINITE,
                     "sample %d is not finite (t = %g)", i + 1, t[i]);
    for (int c = 0; c < 3; c++)
      if (ch[c] && !isfinite(ch[c][i]))
        return vi_fail(id->errmsg, VI_ERR_NONFINITE,
                       "sample %d is not finite (t = %g, %s = %g)", i + 1,
                       t[i], nm[c], ch[c][i]);
    if (i > 0 && !(t[i] > t[i - 1]))
      return vi_fail(id->errmsg, VI_ERR_ARG,
                     "times not increasing at sample %d: %.17g after %.17g",
                     i + 1, t[i], t[i - 1]);
  }
  /* the first channel recorded is y (its order ych), the others follow */
  int ych = x ? 0 : v ? 1 : 2;
  const double *yy = ch[ych], *vv = ych < 1 ? v : NULL, *aa = ych < 2 ? a : NULL;
  size_t sz = sizeof(double) * ns;
  double *nt = malloc(sz), *ny = malloc(sz);
  double *nv = vv ? malloc(sz) : NULL, *na = aa ? malloc(sz) : NULL;
  if (!nt || !ny || (vv && !nv) || (aa && !na)) {
    free(nt);
    free(ny);
    free(nv);
    free(na);
    return vi_fail(id->errmsg, VI_ERR_NOMEM, "out of memory");
  }
  for (int i = 0; i < ns; i++) nt[i] = t[i] - t[0]; /* exact (Sterbenz) */
  memcpy(ny, yy, sz);
  if (vv) memcpy(nv, vv, sz);
  if (aa) memcpy(na, aa, sz);
  free(id->t);
  free(id->y);
  free(id->vy);
  free(id->ay);
  id->t = nt;
  id->tref = t[0];
  id->y = ny;
  id->vy = nv;
  id->ay = na;
  id->ych = ych;
  id->ns = ns;
  vi_id_free_channels(id);
  id->done = 0;
  return VI_OK;
}

void vi_id_free_channels(vi_identify *id)
{
  for (int k = 0; k < id->nch; k++) {
    free(id->chc[k]);
    free(id->chy[k]);
  }
  id->nch = 0;
}

int vi_identify_add_channel(vi_identify *id, const double *c, int order,
                            const double *y)
{
  if (!id) return VI_ERR_ARG;
  if (!id->ns)
    return vi_fail(id->errmsg, VI_ERR_STATE, "a channel before the recording");
  if (!c || !y || order < 0 || order > 2)
    return vi_fail(id->errmsg, VI_ERR_ARG, "a channel needs an observation, "
                   "order 0, 1 or 2, and samples");
  if (id->nch == MAXCH)
    return vi_fail(id->errmsg, VI_ERR_DIM, "more than %d added channels", MAXCH);
  double s = 0.0;
  for (int i = 0; i < id->N; i++) {
    if (!isfinite(c[i]))
      return vi_fail(id->errmsg, VI_ERR_NONFINITE, "channel %d: observation %d: %g",
                     id->nch + 1, i + 1, c[i]);
    s += fabs(c[i]);
  }
  if (!(s > 0.0))
    return vi_fail(id->errmsg, VI_ERR_ARG, "channel %d: the observation vector is zero",
                   id->nch + 1);
  for (int i = 0; i < id->ns; i++)
    if (!isfinite(y[i]))
      return vi_fail(id->errmsg, VI_ERR_NONFINITE, "channel %d: sample %d is not "
                     "finite (t = %g, %g)", id->nch + 1, i + 1, id->t[i] + id->tref, y[i]);
  double *nc = malloc(sizeof(double) * id->N), *ny = malloc(sizeof(double) * id->ns);
  if (!nc || !ny) {
    free(nc);
    free(ny);
    return vi_fail(id->errmsg, VI_ERR_NOMEM, "out of memory");
  }
  memcpy(nc, c, sizeof(double) * id->N);
  memcpy(ny, y, sizeof(double) * id->ns);
  id->chc[id->nch] = nc;
  id->chy[id->nch] = ny;
  id->chord[id->nch++] = order;
  id->done = 0;
  return VI_OK;
}

int vi_identify_set_global(vi_identify *id, int on)
{
  if (!id) return VI_ERR_ARG;
  if (on != 0 && on != 1)
    return vi_fail(id->errmsg, VI_ERR_ARG, "global must be 0 or 1");
  id->global = on;
  id->done = 0;
  return VI_OK;
}

/* The minima s [n] and their orbits' buffers. */
static void free_sols(vi_id_sol *s, int n)
{
  for (int k = 0; k < n; k++) {
    free(s[k].o.x);
    free(s[k].o.v);
  }
  free(s);
}

void vi_id_free_solutions(vi_identify *id)
{
  free_sols(id->sol, id->nsol);
  id->sol = NULL;
  id->nsol = id->nfound = 0;
}

/* The fit from the starting values alone (vi_identify_set_global 0): the
 * orbit the model shows there, the one minimum the fit reaches. */
static int local_only(vi_identify *id, int nd)
{
  int st = vi_id_choose_orbit(id, nd, NULL);
  if (st) return st;
  memcpy(id->pcur, id->p0, sizeof(double) * id->np);
  id->have_cur = 1;
  for (int j = 0; j < id->np; j++) id->glo[j] = id->ghi[j] = id->p0[j];
  double t0 = id->fit_shift && isnan(id->shift0) ? vi_id_scan_shift(id, NULL) : vi_id_shift0(id);
  id->sol = calloc(1, sizeof *id->sol);
  if (!id->sol || vi_id_orb_alloc(&id->sol->o, id->N)) {
    if (id->sol) {
      free(id->sol->o.x);
      free(id->sol->o.v);
    }
    free(id->sol);
    id->sol = NULL;
    return vi_fail(id->errmsg, VI_ERR_NOMEM, "out of memory");
  }
  id->nsol = id->nfound = 1;
  id->unique = 1;
  return vi_id_local(id, id->p0, t0, id->sol);
}

/* The best minimum's results into the handle, its model and orbit
 * current (the getters read them). */
static int take_best(vi_identify *id)
{
  const vi_id_sol *s = &id->sol[0];
  int np = id->np;
  size_t b = sizeof(double) * np;
  vi_id_hold(id, -1, NAN);
  vi_id_drop_cur(id);
  id->have_pred = 0;
  vi_id_orb_copy(&id->o, &s->o, id->N);
  if (vi_id_ensure(id, s->p))
    return vi_fail(id->errmsg, VI_ERR_NOT_CONVERGED, "the best fit's orbit "
                   "cannot be held again");
  memcpy(id->p, s->p, b);
  memcpy(id->se, s->se, b);
  memcpy(id->l95, s->l95, b);
  memcpy(id->h95, s->h95, b);
  memcpy(id->flags, s->flags, sizeof(int) * np);
  memcpy(id->corr, s->corr, b * np);
  id->t0 = s->t0;
  id->t0se = s->t0se;
  id->rms = s->rms;
  id->rcond = s->rcond;
  id->conv = s->conv;
  id->iters = s->iters;
  return VI_OK;
}

/* 1 when the best minimum's residual is within 1.5 noise levels.  Not
 * the chi-square bound: the noise estimated from the recording runs up
 * to 13 % below the true fit's residual (Fig. 2's SciPy recording), and
 * the wider searches that a failed test brings took a right fit 4 times
 * as long; a wrong orbit that comes near the noise is found by the
 * search about the best minimum instead (widen_retry). */
static int explained(const vi_identify *id)
{
  return id->nsol > 0 && !(id->sol[0].rms > 1.5 * id->noise);
}

/* The global stage once more: its starts spread a factor `widen` either
 * way of the given start in log over the keys with no natural range, or
 * (widen < 0) |widen| either way of the best minimum's values over those
 * keys whose bounds are open or decades apart; its minima ranked with
 * those found before (vi_identify_search_range: what every stage
 * searched). */
static int global_again(vi_identify *id, int nd, double widen)
{
  vi_id_sol *keep = id->sol;
  int kn = id->nsol, kf = id->nfound, ku = id->unique, klog[MAXP];
  double klo[MAXP], khi[MAXP], p0[MAXP];
  memcpy(klo, id->glo, sizeof klo);
  memcpy(khi, id->ghi, sizeof khi);
  memcpy(klog, id->glog, sizeof klog);
  memcpy(p0, id->p0, sizeof p0);
  if (widen < 0.0) memcpy(id->p0, keep[0].p, sizeof(double) * id->np);
  id->sol = NULL;
  id->nsol = id->nfound = 0;
  id->widen = widen;
  int st = vi_id_global(id, nd);
  id->widen = 0.0;
  memcpy(id->p0, p0, sizeof p0);
  vi_id_sol *all = st || !id->nsol ? NULL
                   : realloc(keep, sizeof *all * (size_t)(kn + id->nsol));
  if (!all) { /* nothing new (or no room for it): as before */
    free_sols(id->sol, id->nsol);
    id->sol = keep;
    id->nsol = kn;
    id->nfound = kf;
    id->unique = ku;
    memcpy(id->glo, klo, sizeof klo);
    memcpy(id->ghi, khi, sizeof khi);
    memcpy(id->glog, klog, sizeof klog);
    return st == VI_ERR_NOMEM || st == VI_CANCELLED ? st : VI_OK;
  }
  memcpy(all + kn, id->sol, sizeof *all * (size_t)id->nsol);
  free(id->sol);
  id->sol = all;
  id->nsol += kn;
  for (int j = 0; kn && j < id->np; j++) {
    id->glog[j] = id->glog[j] && klog[j];
    id->glo[j] = fmin(id->glo[j], klo[j]);
    id->ghi[j] = fmax(id->ghi[j], khi[j]);
  }
  vi_id_rank(id, id->sol, &id->nsol);
  return VI_OK;
}

/* A naive guess of an amplitude or a damping (3 to 16 times off) may
 * give the local fits no start in the recording's orbit's basin, or one
 * only in another orbit's that explains the data nearly as well; so may
 * bounds decades apart.  So the global stage runs again:
 *  - about the best minimum, +-50 % of its values (they may hold the
 *    right amplitude with the wrong orbit: the cantilever's base 0.0100
 *    with a P(1,2) at r = 0.32 and 1.03 noise levels, where the
 *    recording's P(1,1) at r = 0.75 exists only within 5 % of 0.01), and
 *    again about each new best;
 *  - closer, +-25 % then +-12.5 %, about a best that does not explain the
 *    data (starts 20 % apart missed a window of a few per cent);
 *  - where the best still does not, with the open keys spread a factor
 *    4, 8, then 16 either way of the start in log.
 * All the minima are ranked together.  (No one grid served: of 14 fits
 * from such guesses, doc/identify.md's, 10 ended right without the
 * searches about the best, 14 with them.) */
static int widen_retry(vi_identify *id, int nd)
{
  static const double factor[3] = {4.0, 8.0, 16.0};
  int open = 0, other = 0, st = VI_OK;
  /* the sum of squares of the best searched about: searched again where
   * a new best lowers it by more than a noise variance (not the same
   * minimum re-found to a few digits more) */
  double centred = HUGE_VAL, s2 = id->noise > 0.0 ? id->noise * id->noise : 0.0;
  for (int j = 0; j < id->np; j++) {
    open |= vi_id_open_key(id, j);
    other |= id->kind[j] == VI_IDENTIFY_OTHER;
  }
  for (int k = 0, nre = 0; k <= 3 && other && !st; k++) {
    double zoom = 0.5;
    while (!st && id->nsol > 0 && nre < 6) {
      if (id->sol[0].ssr < centred - s2) zoom = 0.5; /* a new best */
      else if (!explained(id) && zoom > 0.2) zoom *= 0.5; /* the same: closer */
      else break;
      centred = id->sol[0].ssr;
      nre++;
      st = global_again(id, nd, -zoom);
    }
    if (st || k == 3 || !open || explained(id)) break;
    st = global_again(id, nd, factor[k]);
  }
  return st;
}

/* The message of a global search that found nothing: why the last start
 * failed, and the ranges the starts covered, which the value lies outside
 * or between (the 4-mode beam's damping ratio 0.05 from 1.0: 0.0625 to
 * 16 at the widest). */
static void searched(vi_identify *id, const char *why)
{
  char r[160] = ""; /* with why's first 250: the message fits */
  size_t n = 0;
  for (int j = 0; j < id->np && n < sizeof r; j++) {
    if (j == id->jom) continue; /* its starts are the recording's multiples */
    char name[80];
    if (id->key[j][0]) snprintf(name, sizeof name, "%s", id->key[j]);
    else snprintf(name, sizeof name, "parameter %d", j + 1);
    int w = snprintf(r + n, sizeof r - n, "%s%s %.3g to %.3g", n ? ", " : "", name,
                     id->slo[j], id->shi[j]);
    n += w > 0 ? (size_t)w : 0;
  }
  snprintf(id->errmsg, sizeof id->errmsg, "%.250s; the starts covered %s: a start "
           "nearer the value, or bounds that hold it, let the search reach it", why, r);
}

/* A fitted forcing frequency: the model's period at the given start
 * proves nothing about the recording's, so the recording's own period
 * (vi_id_data_lag) sets the start, the multiple 2 pi n / lag nearest the
 * given one (n <= MAX_N, within the bounds), and *nd, the recording's
 * period in the forcing periods of that start (n, unless the lag is a
 * multiple of the recording's period); the global stage starts from each
 * multiple within its range (vi_id_global). */
static int omega_start(vi_identify *id, int *nd)
{
  int j = id->jom, best = 0;
  double lo = id->lo[j] > 0.0 ? id->lo[j] : 0.1 * id->p0[j], bd = HUGE_VAL;
  double lag = vi_id_data_lag(id, MAX_N * 2.0 * M_PI / lo);
  if (!(lag > 0.0)) return VI_ERR_ARG;
  for (int n = 1; n <= MAX_N; n++) {
    double om = 2.0 * M_PI * n / lag, d = fabs(log(om / id->p0[j]));
    if (om >= id->lo[j] && om <= id->hi[j] && (!best || d < bd)) {
      best = n;
      bd = d;
    }
  }
  if (!best)
    return vi_fail(id->errmsg, VI_ERR_ARG, "the recording repeats every %g time units, so "
                   "the forcing frequency is 2 pi n / %g for n = 1..%d: none lies in "
                   "forcing.omega's range [%g, %g]", lag, lag, MAX_N, id->lo[j], id->hi[j]);
  /* where no multiple comes within a factor 10 of the start and no bounds
   * say otherwise, the recording's clock is likely in other units than
   * the model's (milliseconds against seconds) */
  double near = 2.0 * M_PI * best / lag;
  if (bd > log(10.0) && !(id->lo[j] > 0.0 && isfinite(id->hi[j])))
    return vi_fail(id->errmsg, VI_ERR_ARG, "the recording repeats every %g time units, so "
                   "the forcing frequency is 2 pi n / %g for n = 1..%d, at best %g: %.3g "
                   "times the start %g (is the recording's time in the model's unit? "
                   "Bounds on forcing.omega that hold %g allow it)", lag, lag, MAX_N, near,
                   near / id->p0[j], id->p0[j], near);
  id->lag = lag;
  id->p0[j] = 2.0 * M_PI * best / lag;
  *nd = vi_id_data_period(id, lag / best); /* the recording's period in the new T */
  if (!*nd) *nd = best;
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
  int np = id->np, P = np + id->fit_shift, st;
  id->errmsg[0] = 0;
  id->nsearch = 0;
  id->cancel_hit = 0;
  vi_id_free_solutions(id);
  vi_id_hold(id, -1, NAN);
  if (vi_id_poll_cancel(id)) return vi_fail(id->errmsg, VI_CANCELLED, "cancelled");
  id->jom = -1;
  for (int j = 0; j < np; j++) {
    id->p0[j] = id->pgiven[j]; /* a second run starts where the caller said */
    if (id->kind[j] == VI_IDENTIFY_OMEGA) id->jom = j;
  }
  int nom = 0;
  if (id->jom >= 0 && id->ns >= 4 * P + 8 && (st = omega_start(id, &nom))) return st;
  /* the model at the starting values: the recording's period */
  vi_id_drop_cur(id);
  id->have_pred = 0;
  vi_model *m0 = NULL;
  if ((st = vi_id_make_model(id, id->p0, &m0)))
    return id->errmsg[0] ? st
                         : vi_fail(id->errmsg, st, "no model at the starting "
                                   "values (%s)", vi_strerror(st));
  id->cur = m0;
  if ((st = vi_xflow_create(m0, &id->xf))) return vi_fail(id->errmsg, st, "out of memory");
  id->Om0 = m0->omega_f;
  id->scale = 0.0;
  for (int i = 0; i < id->ns; i++) id->scale = fmax(id->scale, fabs(id->y[i]));
  if (!(id->scale > 0.0)) id->scale = 1.0;
  double T = vi_id_period_of(m0, 1), span = id->t[id->ns - 1] - id->t[0];
  if (id->ns < 4 * P + 8)
    return vi_fail(id->errmsg, VI_ERR_ARG,
                   "too few samples: %d for %d fitted values", id->ns, P);
  int nd = nom ? nom : vi_id_data_period(id, T);
  if (!nd) return VI_ERR_ARG;
  if (span < nd * T)
    return vi_fail(id->errmsg, VI_ERR_ARG,
                   "the recording spans %g time units, less than one period "
                   "%g of its motion", span, nd * T);
  id->noise = id->sigma > 0.0 ? id->sigma : vi_id_noise_estimate(id, nd * T);
  st = id->global ? vi_id_global(id, nd) : local_only(id, nd);
  if (id->global && (!st || st == VI_ERR_NOT_CONVERGED)) {
    /* not explained, or no start showed the recording's orbit: wider */
    char why[VI_MSG_LEN];
    snprintf(why, sizeof why, "%s", id->errmsg);
    int sw = widen_retry(id, nd);
    if (sw) st = sw;
    else if (st && id->nsol > 0) st = VI_OK;
    else if (st) searched(id, why);
  }
  /* profile intervals of every minimum reported */
  for (int k = 0; !st && k < id->nfound; k++) st = vi_id_profile(id, &id->sol[k]);
  if (!st) st = take_best(id);
  if (id->cancel_hit) return vi_fail(id->errmsg, VI_CANCELLED, "cancelled");
  if (st) return st;
  if (!(id->sigma > 0.0)) {
    /* the folded estimate again at the fitted orbit's period: the start's
     * may be off by part of a sample over a short record, which the fold
     * of a signal as rich as an accelerometer's reads as noise (6 periods
     * of the beam's tip acceleration: 50 times the noise).  Both are upper
     * bounds; the smaller holds */
    double nf = vi_id_noise_estimate(id, vi_id_period_of(id->cur, id->o.n));
    if (nf < id->noise) id->noise = nf;
  }
  vi_id_energy_route(id);
  id->mumax = NAN;
  const orb *o = &id->o;
  if (!vi_orbit_pnm_multipliers_stops(id->cur, o->n, o->m, o->stop, o->t, o->x,
                                      o->v, id->N, id->mre, id->mim)) {
    id->mumax = 0.0;
    for (int i = 0; i < 2 * id->N; i++)
      id->mumax = fmax(id->mumax, hypot(id->mre[i], id->mim[i]));
  }
  id->errmsg[0] = 0; /* what failed at some starts is no error of the run */
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

int vi_identify_profile(const vi_identify *id, double *plo95, double *phi95,
                        int *flags)
{
  return vi_identify_solution_profile(id, 0, plo95, phi95, flags);
}

int vi_identify_nsolutions(const vi_identify *id, int *unique)
{
  if (!id || !id->done) return 0;
  if (unique) *unique = id->unique;
  return id->nfound;
}

#define NEED_SOL(id, k) \
  do { NEED_DONE(id); if ((k) < 0 || (k) >= (id)->nfound) return VI_ERR_ARG; } while (0)

int vi_identify_solution(const vi_identify *id, int k, double *p, double *se,
                         double *lo95, double *hi95, int *flags)
{
  NEED_SOL(id, k);
  const vi_id_sol *s = &id->sol[k];
  size_t b = sizeof(double) * id->np;
  if (p) memcpy(p, s->p, b);
  if (se) memcpy(se, s->se, b);
  if (lo95) memcpy(lo95, s->l95, b);
  if (hi95) memcpy(hi95, s->h95, b);
  if (flags) memcpy(flags, s->flags, sizeof(int) * id->np);
  return VI_OK;
}

int vi_identify_solution_profile(const vi_identify *id, int k, double *plo95,
                                 double *phi95, int *flags)
{
  NEED_SOL(id, k);
  const vi_id_sol *s = &id->sol[k];
  size_t b = sizeof(double) * id->np;
  if (plo95) memcpy(plo95, s->pl95, b);
  if (phi95) memcpy(phi95, s->ph95, b);
  if (flags) memcpy(flags, s->pflags, sizeof(int) * id->np);
  return VI_OK;
}

int vi_identify_solution_summary(const vi_identify *id, int k, int *n, int *m,
                                 double *rms, double *ratio, double *dchi2,
                                 double *t0)
{
  NEED_SOL(id, k);
  const vi_id_sol *s = &id->sol[k];
  if (n) *n = s->n;
  if (m) *m = s->m;
  if (rms) *rms = s->rms;
  if (ratio) *ratio = s->rms / id->noise;
  if (dchi2) *dchi2 = id->global ? s->dchi2 : 0.0;
  if (t0) *t0 = s->t0 - id->tref; /* on the caller's clock (vi_identify_shift) */
  return VI_OK;
}

int vi_identify_solution_separation(const vi_identify *id, int k, double *d,
                                    double *length)
{
  NEED_SOL(id, k);
  const vi_id_sol *s = &id->sol[k];
  if (d) *d = k == 0 ? 0.0 : s->dsep;
  if (length) *length = k == 0 ? NAN : s->lsep;
  return VI_OK;
}

int vi_identify_search_range(const vi_identify *id, double *lo, double *hi)
{
  NEED_DONE(id);
  /* every stage's (a stage that found nothing new covered them too) */
  if (lo) memcpy(lo, id->nsearch ? id->slo : id->glo, sizeof(double) * id->np);
  if (hi) memcpy(hi, id->nsearch ? id->shi : id->ghi, sizeof(double) * id->np);
  return VI_OK;
}

int vi_identify_shift(const vi_identify *id, double *t0, double *se)
{
  NEED_DONE(id);
  if (t0) *t0 = id->t0 - id->tref; /* on the caller's clock */
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
  if (period) *period = vi_id_period_of(id->cur, id->o.n);
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
    vi_id_orbit_state(id->cur, id->xf, &id->o, t[i] - id->tref + id->t0, z,
                      z + (size_t)2 * N, NULL, NULL, NULL);
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
  double T = vi_forcing_period(omega), s0 = fmod(atan2(-be, al) / omega, T);
  *t0 = s0 < 0 ? s0 + T : s0;
  return VI_OK;
}
