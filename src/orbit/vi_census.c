/* vi_census.c - the census of P(n, m) orbits (vi_census.h): seeds from the
 * impact-phase scan and from transients, Newton refinement, duplicates
 * dropped, multipliers and admissibility of each orbit found. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "vi_forcing.h"
#include "vibroimpact/vi_census.h"
#include "vi_held_internal.h"
#include "vi_orbit_internal.h"

#define SCAN_CAP 64      /* orbits the phase scan hands over */
#define RINGN 4096       /* impacts remembered during a transient */
#define MAX_PERIODS 2000 /* forcing periods of a transient seed */
#define MAX_NM 64

typedef struct census_orbit {
  int *stop;                         /* [m] */
  double *t, *x, *v, *vn, *re, *im;  /* [m], [n x m] x2, [m], [2n] x2 */
  int stable, admissible;
  double gmax;
} census_orbit;

struct vi_census {
  const vi_model *m;
  int N, n, mi, nphase;
  double T;                          /* forcing period */
  int has_init, scan_only;          /* scan_only: vi_census_scan_only */
  double t0, *x0;                    /* [2N]: the caller's seed (x, v) */
  int count, cap;
  census_orbit *o;
  vi_census_monitor_fn mon;
  void *mon_user;
  vi_destroy_fn mon_free;
  vi_census_sim_fn hook;
  void *hook_user;
  vi_destroy_fn hook_free;
  vi_cancel_fn cancel;
  void *cancel_user;
  vi_destroy_fn cancel_free;
  vi_held_cache *hc;                 /* held sets' modes, shared by seeds */
  char errmsg[VI_MSG_LEN];
};

int vi_census_create(const vi_model *model, int n, int m, vi_census **out)
{
  if (!out) return VI_ERR_ARG;
  *out = NULL;
  if (!model || n < 1 || n > MAX_NM || m < 1 || m > MAX_NM) return VI_ERR_ARG;
  if (!model->frozen || model->ns < 1) return VI_ERR_STATE;
  if (!(model->omega_f > 0.0)) return VI_ERR_FREQUENCY;
  if (!vi_model_has_modes(model)) return VI_ERR_UNSUPPORTED; /* band: no closed form */
  vi_census *c = calloc(1, sizeof *c);
  if (!c) return VI_ERR_NOMEM;
  c->x0 = calloc(2 * (size_t)model->n, sizeof(double));
  c->hc = vi_held_cache_create();
  if (!c->x0 || !c->hc) {
    free(c->x0);
    vi_held_cache_destroy(&c->hc);
    free(c);
    return VI_ERR_NOMEM;
  }
  c->m = model;
  vi_model_hold(model, 1);
  c->N = model->n;
  c->n = n;
  c->mi = m;
  c->nphase = 720;
  c->T = vi_forcing_period(model->omega_f);
  *out = c;
  return VI_OK;
}

static void orbit_free(census_orbit *o)
{
  free(o->stop);
  free(o->t);
  free(o->x);
  free(o->v);
  free(o->vn);
  free(o->re);
  free(o->im);
  memset(o, 0, sizeof *o);
}

static void forget(vi_census *c)
{
  for (int i = 0; i < c->count; i++) orbit_free(&c->o[i]);
  c->count = 0;
}

void vi_census_destroy(vi_census **cp)
{
  if (!cp || !*cp) return;
  vi_census *c = *cp;
  vi_user_set(&c->mon_user, &c->mon_free, NULL, NULL);
  vi_user_set(&c->hook_user, &c->hook_free, NULL, NULL);
  vi_user_set(&c->cancel_user, &c->cancel_free, NULL, NULL);
  forget(c);
  free(c->o);
  free(c->x0);
  vi_held_cache_destroy(&c->hc);
  vi_model_hold(c->m, -1);
  free(c);
  *cp = NULL;
}

const char *vi_census_errmsg(const vi_census *c) { return c ? c->errmsg : ""; }

int vi_census_set_phases(vi_census *c, int nphase)
{
  if (!c) return VI_ERR_ARG;
  if (nphase < 8)
    return vi_fail(c->errmsg, VI_ERR_ARG, "phases = %d: at least 8", nphase);
  c->nphase = nphase;
  return VI_OK;
}

int vi_census_set_initial(vi_census *c, double t0, const double *x,
                          const double *v)
{
  if (!c) return VI_ERR_ARG;
  int N = c->N;
  if (!isfinite(t0))
    return vi_fail(c->errmsg, VI_ERR_NONFINITE, "initial t0 = %g", t0);
  for (int i = 0; i < N; i++)
    if ((x && !isfinite(x[i])) || (v && !isfinite(v[i])))
      return vi_fail(c->errmsg, VI_ERR_NONFINITE,
                     "initial state: coordinate %d is not finite", i);
  for (int i = 0; i < N; i++) {
    c->x0[i] = x ? x[i] : 0.0;
    c->x0[N + i] = v ? v[i] : 0.0;
  }
  c->t0 = t0;
  c->has_init = 1;
  return VI_OK;
}

int vi_census_set_sim_hook(vi_census *c, vi_census_sim_fn fn, void *user,
                           vi_destroy_fn destroy)
{
  if (!c) return VI_ERR_ARG;
  c->hook = fn;
  vi_user_set(&c->hook_user, &c->hook_free, user, destroy);
  return VI_OK;
}

int vi_census_set_monitor(vi_census *c, vi_census_monitor_fn fn, void *user,
                          vi_destroy_fn destroy)
{
  if (!c) return VI_ERR_ARG;
  c->mon = fn;
  vi_user_set(&c->mon_user, &c->mon_free, user, destroy);
  return VI_OK;
}

int vi_census_set_cancel(vi_census *c, vi_cancel_fn fn, void *user,
                         vi_destroy_fn destroy)
{
  if (!c) return VI_ERR_ARG;
  c->cancel = fn;
  vi_user_set(&c->cancel_user, &c->cancel_free, user, destroy);
  return VI_OK;
}

/* Same orbit: the same impacts up to a cyclic shift of their order and a
 * shift of time by whole forcing periods (the forcing is T-periodic, so a
 * P(n, m) orbit and its copy started T later are one orbit). */
static int same(const vi_census *c, const census_orbit *a, const double *t,
                const double *v, const int *stop)
{
  double T = c->T;
  int N = c->N, m = c->mi;
  for (int s = 0; s < m; s++) {
    int ok = 1;
    for (int j = 0; j < m && ok; j++) {
      int k = (j + s) % m;
      if (a->stop[j] != stop[k]) {
        ok = 0;
        break;
      }
      double d = fmod(fabs(a->t[j] - t[k]), T), dv = 0, sv = 1;
      for (int q = 0; q < N; q++) {
        dv = fmax(dv, fabs(a->v[(size_t)j * N + q] - v[(size_t)k * N + q]));
        sv = fmax(sv, fabs(v[(size_t)k * N + q]));
      }
      ok = fmin(d, T - d) < 1e-7 * T && dv < 1e-6 * sv;
    }
    if (ok) return 1;
  }
  return 0;
}

/* 1 if the P(n, m) orbit (t, v, stop) is a P(n/k, m/k) orbit traversed k
 * > 1 times: every impact recurs m/k impacts later, n T/k later (1e-7 T),
 * with the same velocities (1e-6 relative) on the same stop.  A transient
 * that settled on a P(1,1) orbit repeats with period 2 as well, and
 * Newton keeps it: it is not a P(2,2) orbit, and the curves and
 * continuations that start from the census would follow the wrong one. */
static int repeats(const vi_census *c, const double *t, const double *v,
                   const int *stop)
{
  int N = c->N, m = c->mi, n = c->n;
  for (int k = 2; k <= m; k++) {
    if (m % k || n % k) continue;
    int s = m / k, ok = 1;
    double P = n * c->T, lag = P / k;
    for (int j = 0; j < m && ok; j++) {
      int i = (j + s) % m;
      double d = fmod(fabs(t[i] - t[j] - lag), P), dv = 0, sv = 1;
      for (int q = 0; q < N; q++) {
        dv = fmax(dv, fabs(v[(size_t)i * N + q] - v[(size_t)j * N + q]));
        sv = fmax(sv, fabs(v[(size_t)j * N + q]));
      }
      ok = stop[i] == stop[j] && fmin(d, P - d) < 1e-7 * c->T && dv < 1e-6 * sv;
    }
    if (ok) return 1;
  }
  return 0;
}

/* A new slot with its arrays, or NULL out of memory. */
static census_orbit *new_slot(vi_census *c)
{
  int N = c->N, m = c->mi;
  if (c->count == c->cap) {
    int cap = c->cap ? 2 * c->cap : 16;
    census_orbit *o = realloc(c->o, sizeof *o * (size_t)cap);
    if (!o) return NULL;
    c->o = o;
    c->cap = cap;
  }
  census_orbit *o = &c->o[c->count];
  memset(o, 0, sizeof *o);
  o->stop = malloc(sizeof(int) * (size_t)m);
  o->t = malloc(sizeof(double) * (size_t)m);
  o->x = malloc(sizeof(double) * (size_t)N * m);
  o->v = malloc(sizeof(double) * (size_t)N * m);
  o->vn = malloc(sizeof(double) * (size_t)m);
  o->re = malloc(sizeof(double) * 2 * (size_t)N);
  o->im = malloc(sizeof(double) * 2 * (size_t)N);
  if (!o->stop || !o->t || !o->x || !o->v || !o->vn || !o->re || !o->im) {
    orbit_free(o);
    return NULL;
  }
  return o;
}

/* The approach velocity w_k.v of each impact on its stop k (MODEL.md:
 * v_N = w.v before the impact). */
static int approach(const vi_census *c, census_orbit *o)
{
  int N = c->N;
  double *w = malloc(sizeof(double) * (size_t)N);
  if (!w) return VI_ERR_NOMEM;
  for (int j = 0; j < c->mi; j++) {
    o->vn[j] = NAN;
    if (vi_model_stop(c->m, o->stop[j], w, NULL, NULL)) continue;
    double vn = 0;
    for (int q = 0; q < N; q++) vn += w[q] * o->v[(size_t)j * N + q];
    o->vn[j] = vn;
  }
  free(w);
  return VI_OK;
}

/* Refine a seed (stop: the stop of each impact, NULL for stop 0) and keep
 * it if new.  VI_OK also for a seed dropped; VI_STOPPED, VI_ERR_NOMEM. */
static int add(vi_census *c, double *t, double *x, double *v, const int *stop)
{
  int N = c->N, m = c->mi;
  int *sp = calloc((size_t)m, sizeof(int));
  if (!sp) return VI_ERR_NOMEM;
  for (int j = 0; stop && j < m; j++) sp[j] = stop[j];
  int st = vi_orbit_pnm_solve_stops(c->m, c->n, m, sp, t, x, v, N, 0.0, NULL);
  double P = c->n * c->T;
  /* impact times into [0, nT), order kept cyclically */
  double sh = st ? 0 : floor(t[0] / P) * P;
  for (int j = 0; !st && j < m; j++) t[j] -= sh;
  for (int i = 0; !st && i < c->count; i++)
    if (same(c, &c->o[i], t, v, sp)) st = 1;
  if (!st && repeats(c, t, v, sp)) st = 1;
  if (st) { /* not converged, known, or a shorter orbit repeated */
    free(sp);
    return VI_OK;
  }
  census_orbit *o = new_slot(c);
  if (!o) {
    free(sp);
    return VI_ERR_NOMEM;
  }
  memcpy(o->stop, sp, sizeof(int) * (size_t)m);
  free(sp);
  memcpy(o->t, t, sizeof(double) * (size_t)m);
  memcpy(o->x, x, sizeof(double) * (size_t)N * m);
  memcpy(o->v, v, sizeof(double) * (size_t)N * m);
  if (vi_orbit_pnm_multipliers_stops(c->m, c->n, m, o->stop, t, x, v, N, o->re, o->im) ||
      vi_orbit_pnm_admissible_stops(c->m, c->n, m, o->stop, t, x, v, N, &o->gmax,
                                    &o->admissible)) {
    orbit_free(o);
    return VI_OK;
  }
  if (approach(c, o)) {
    orbit_free(o);
    return VI_ERR_NOMEM;
  }
  double mx = 0;
  for (int i = 0; i < 2 * N; i++) mx = fmax(mx, hypot(o->re[i], o->im[i]));
  o->stable = mx < 1.0;
  c->count++;
  if (c->mon && c->mon(c, c->count - 1, c->mon_user)) return VI_STOPPED;
  return VI_OK;
}

/* ---- seeds from transients ---------------------------------------------- */
typedef struct ring {
  int N;
  int64_t k;
  double t[RINGN], *z; /* z: RINGN x 2N, pre-impact (x, v) */
  int stop[RINGN];
} ring;

static int on_impact(const vi_event *ev, void *user)
{
  ring *r = user;
  if (ev->kind != VI_EVENT_IMPACT) return 0;
  int i = (int)(r->k % RINGN);
  r->t[i] = ev->t;
  r->stop[i] = ev->stop;
  memcpy(r->z + (size_t)i * 2 * r->N, ev->x, sizeof(double) * r->N);
  memcpy(r->z + (size_t)i * 2 * r->N + r->N, ev->v_minus, sizeof(double) * r->N);
  r->k++;
  return 0;
}

/* The last m impacts of the ring as a seed. */
static int seed_from_ring(vi_census *c, const ring *r, double *st)
{
  int N = c->N, m = c->mi;
  double *tt = st, *xx = tt + m, *vv = xx + (size_t)N * m;
  int sp[MAX_NM]; /* m <= MAX_NM (vi_census_create) */
  for (int j = 0; j < m; j++) {
    int64_t q = r->k - m + j;
    tt[j] = r->t[q % RINGN];
    sp[j] = r->stop[q % RINGN];
    memcpy(xx + (size_t)j * N, r->z + (size_t)(q % RINGN) * 2 * N, sizeof(double) * N);
    memcpy(vv + (size_t)j * N, r->z + (size_t)(q % RINGN) * 2 * N + N, sizeof(double) * N);
  }
  return add(c, tt, xx, vv, sp);
}

/* A simulation from (t0, x0, v0) with the closed-form flow, recording
 * impacts into r; NULL if it cannot be set up (the seed is skipped). */
static vi_sim *seed_sim(vi_census *c, ring *r, double t0, const double *x0,
                        const double *v0)
{
  vi_sim *s = NULL;
  if (vi_sim_create(c->m, &s) || (c->hook && c->hook(s, c->hook_user)) ||
      vi_sim_set_method(s, VI_METHOD_EXACT) || vi_sim_set_initial(s, t0, x0, v0) ||
      vi_held_share_cache(s, c->hc)) {
    vi_sim_destroy(&s);
    return NULL;
  }
  vi_sim_set_event_callback(s, on_impact, r, NULL);
  if (c->cancel) vi_sim_set_cancel(s, c->cancel, c->cancel_user, NULL);
  return s;
}

/* 1 if the stroboscopic state zk (period k) repeats with period n three
 * times, 1e-9 relative, in the window z of W states. */
static int strobe_periodic(const double *z, const double *zk, int N, int k,
                           int n, int W)
{
  double scl = 1e-9;
  for (int i = 0; i < 2 * N; i++) scl = fmax(scl, fabs(zk[i]));
  for (int j = 1; j <= 3; j++)
    for (int i = 0; i < 2 * N; i++)
      if (!(fabs(z[(size_t)((k - j * n) % W) * 2 * N + i] - zk[i]) <= 1e-9 * scl))
        return 0;
  return 1;
}

/* Run from (t0, x0, v0) until the stroboscopic states repeat with period n
 * with m impacts per n periods; seed from them.  VI_OK also when the run
 * settles elsewhere or fails; VI_CANCELLED, VI_STOPPED, VI_ERR_NOMEM. */
static int transient_seed(vi_census *c, double t0, const double *x0,
                          const double *v0)
{
  int N = c->N, n = c->n, m = c->mi, W = 3 * n + 1, rc = VI_OK;
  vi_sim *s = NULL;
  ring *r = calloc(1, sizeof *r);
  double *z = malloc(sizeof(double) * 2 * N * W);
  double *st = malloc(sizeof(double) * (2 * N + 1) * m + 1);
  if (r) r->z = malloc(sizeof(double) * RINGN * 2 * N);
  if (!r || !z || !st || !r->z) {
    rc = VI_ERR_NOMEM;
    goto done;
  }
  r->N = N;
  if (!(s = seed_sim(c, r, t0, x0, v0))) goto done;
  for (int k = 1; k <= MAX_PERIODS; k++) {
    int e = vi_sim_run(s, t0 + k * c->T);
    if (e) {
      if (e == VI_CANCELLED || e == VI_ERR_NOMEM) rc = e;
      goto done;
    }
    double *zk = z + (size_t)(k % W) * 2 * N;
    vi_sim_state(s, NULL, zk, zk + N);
    if (k < W || r->k < m || !strobe_periodic(z, zk, N, k, n, W)) continue;
    int cnt = 0;
    double tn = t0 + (k - n) * c->T;
    for (int64_t q = r->k - 1; q >= 0 && q > r->k - RINGN && r->t[q % RINGN] >= tn; q--) cnt++;
    if (cnt == m) rc = seed_from_ring(c, r, st); /* else another P(n, m') */
    goto done;
  }
done:
  vi_sim_destroy(&s);
  if (r) free(r->z);
  free(r);
  free(z);
  free(st);
  return rc;
}

/* The phase scan (m = 1, one stop): every P(n, 1) orbit. */
static int scan_seeds(vi_census *c)
{
  int N = c->N, found = 0, rc = VI_OK;
  double *t = malloc(sizeof(double) * SCAN_CAP * (2 * N + 1));
  if (!t) return VI_ERR_NOMEM;
  double *x = t + SCAN_CAP, *v = x + (size_t)SCAN_CAP * N;
  int st = vi_orbit_p1_scan_polled(c->m, c->n, c->nphase, t, x, v, N, SCAN_CAP,
                                   &found, c->cancel, c->cancel_user);
  if (st) {
    free(t);
    if (st == VI_CANCELLED) return st;
    return vi_fail(c->errmsg, st, "the phase scan: %s", vi_strerror(st));
  }
  for (int i = 0; i < found && i < SCAN_CAP && !rc; i++)
    rc = add(c, &t[i], x + (size_t)i * N, v + (size_t)i * N, NULL);
  free(t);
  return rc;
}

void vi_census_scan_only(vi_census *c) { c->scan_only = 1; }

int vi_census_run(vi_census *c)
{
  if (!c) return VI_ERR_ARG;
  int N = c->N, rc = VI_OK;
  forget(c);
  vi_held_cache_clear(c->hc); /* the model may have changed since */
  c->errmsg[0] = '\0';
  if (c->scan_only && !(c->mi == 1 && c->m->ns == 1))
    return vi_fail(c->errmsg, VI_ERR_UNSUPPORTED, "the phase scan is for "
                   "P(n, 1) orbits on one stop");
  if (c->mi == 1 && c->m->ns == 1) rc = scan_seeds(c);
  if (c->scan_only) {
    if (rc && !c->errmsg[0]) vi_fail(c->errmsg, rc, "%s", vi_strerror(rc));
    return rc;
  }
  if (!rc && c->has_init) rc = transient_seed(c, c->t0, c->x0, c->x0 + N);
  double *rest = calloc(2 * (size_t)N, sizeof(double));
  if (!rest && !rc) rc = VI_ERR_NOMEM;
  for (int k = 0; k < 8 && !rc; k++)
    rc = transient_seed(c, k * c->T / 8, rest, rest + N);
  free(rest);
  if (rc && !c->errmsg[0]) vi_fail(c->errmsg, rc, "%s", vi_strerror(rc));
  return rc;
}

int vi_census_count(const vi_census *c) { return c ? c->count : 0; }

int vi_census_orbit(const vi_census *c, int i, double *t, double *x,
                    double *v, int ld, int *stop, double *vn)
{
  if (!c || i < 0 || i >= c->count) return VI_ERR_ARG;
  int N = c->N, m = c->mi;
  if ((x || v) && ld < N) return VI_ERR_DIM;
  const census_orbit *o = &c->o[i];
  for (int j = 0; j < m; j++) {
    if (t) t[j] = o->t[j];
    if (stop) stop[j] = o->stop[j];
    if (vn) vn[j] = o->vn[j];
    if (x) memcpy(x + (size_t)j * ld, o->x + (size_t)j * N, sizeof(double) * N);
    if (v) memcpy(v + (size_t)j * ld, o->v + (size_t)j * N, sizeof(double) * N);
  }
  return VI_OK;
}

int vi_census_stability(const vi_census *c, int i, double *re, double *im,
                        int *stable, int *admissible, double *gmax)
{
  if (!c || i < 0 || i >= c->count) return VI_ERR_ARG;
  const census_orbit *o = &c->o[i];
  if (re) memcpy(re, o->re, sizeof(double) * 2 * (size_t)c->N);
  if (im) memcpy(im, o->im, sizeof(double) * 2 * (size_t)c->N);
  if (stable) *stable = o->stable;
  if (admissible) *admissible = o->admissible;
  if (gmax) *gmax = o->gmax;
  return VI_OK;
}
