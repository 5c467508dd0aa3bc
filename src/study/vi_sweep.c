/* vi_sweep.c - parameter studies one point at a time (vi_study.h): warm or
 * cold start, transient and recorded periods, stroboscopic sampling, the
 * impacts, the P(n, m) classification, and the P(1,1) orbit census. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vi_forcing.h"
#include "vibroimpact/vi_census.h"
#include "vibroimpact/vi_param.h"
#include "vibroimpact/vi_study.h"
#include "vi_held_internal.h"
#include "vi_orbit_internal.h"

struct vi_sweep {
  vi_model *m;                 /* the study's own copy */
  vi_held_cache *hc;           /* constrained modes of held sets, shared by
                                  the points' simulations */
  int n;
  int transient, record, nmax, method;
  double tol, rtol, atol;
  int warm, have_state;
  double t0, *x0, *v0;         /* the initial state [n] each */
  double *xw, *vw;             /* the warm state [n] each */
  /* the last point */
  int done, failed, pn, pm;
  double T, t_rec;
  int64_t nimp, cap, points;
  double *t, *phase, *vn;      /* [cap] */
  double *z;                   /* [2n x (record + 1)]: z_0 .. z_R */
  int oom;
  /* the largest Lyapunov exponent (vi_sweep_set_lyapunov) */
  int lyap;
  double lambda;
  /* the P(1,1) census (vi_sweep_set_orbits) */
  int nphase, norb;
  double *ovn, *ophase;
  int *ostable, *oadm;
  /* callbacks */
  vi_sweep_monitor_fn mon;
  void *mon_user;
  vi_destroy_fn mon_free;
  vi_sweep_sim_fn hook;
  void *hook_user;
  vi_destroy_fn hook_free;
  vi_cancel_fn cancel;
  void *cancel_user;
  vi_destroy_fn cancel_free;
  char errmsg[VI_MSG_LEN];
};

int vi_sweep_create(const vi_model *m, vi_sweep **out)
{
  if (!out) return VI_ERR_ARG;
  *out = NULL;
  if (!m) return VI_ERR_ARG;
  if (!m->frozen) return VI_ERR_STATE;
  vi_sweep *sw = calloc(1, sizeof *sw);
  if (!sw) return VI_ERR_NOMEM;
  int n = m->n, st = vi_model_copy(m, &sw->m);
  sw->x0 = calloc(4 * (size_t)n, sizeof(double));
  sw->hc = vi_held_cache_create();
  if (st || !sw->x0 || !sw->hc) {
    vi_sweep_destroy(&sw);
    return VI_ERR_NOMEM;
  }
  sw->v0 = sw->x0 + n;
  sw->xw = sw->v0 + n;
  sw->vw = sw->xw + n;
  sw->n = n;
  sw->transient = 100;
  sw->record = 10;
  sw->tol = 1e-6;
  sw->nmax = 32;
  sw->method = VI_METHOD_AUTO;
  sw->rtol = 1e-8;
  sw->atol = 1e-10;
  sw->warm = 1;
  *out = sw;
  return VI_OK;
}

static void free_orbits(vi_sweep *sw)
{
  free(sw->ovn);
  free(sw->ophase);
  free(sw->ostable);
  free(sw->oadm);
  sw->ovn = sw->ophase = NULL;
  sw->ostable = sw->oadm = NULL;
  sw->norb = 0;
}

void vi_sweep_destroy(vi_sweep **swp)
{
  if (!swp || !*swp) return;
  vi_sweep *sw = *swp;
  vi_user_set(&sw->mon_user, &sw->mon_free, NULL, NULL);
  vi_user_set(&sw->hook_user, &sw->hook_free, NULL, NULL);
  vi_user_set(&sw->cancel_user, &sw->cancel_free, NULL, NULL);
  vi_model_destroy(&sw->m);
  vi_held_cache_destroy(&sw->hc);
  free_orbits(sw);
  free(sw->x0);
  free(sw->t);
  free(sw->phase);
  free(sw->vn);
  free(sw->z);
  free(sw);
  *swp = NULL;
}

const char *vi_sweep_errmsg(const vi_sweep *sw) { return sw ? sw->errmsg : ""; }

int vi_sweep_set_periods(vi_sweep *sw, int transient, int record)
{
  if (!sw) return VI_ERR_ARG;
  if (transient < 0 || record < 2)
    return vi_fail(sw->errmsg, VI_ERR_ARG, "periods: transient %d must be "
                   ">= 0 and record %d >= 2", transient, record);
  if (record != sw->record) {
    free(sw->z);
    sw->z = NULL;
    sw->done = 0;
  }
  sw->transient = transient;
  sw->record = record;
  return VI_OK;
}

int vi_sweep_set_classify(vi_sweep *sw, double tol, int nmax)
{
  if (!sw) return VI_ERR_ARG;
  if (!(tol > 0.0) || !isfinite(tol) || nmax < 1)
    return vi_fail(sw->errmsg, VI_ERR_ARG, "classification: tol = %g must be "
                   "> 0 and nmax = %d >= 1", tol, nmax);
  sw->tol = tol;
  sw->nmax = nmax;
  return VI_OK;
}

int vi_sweep_set_run(vi_sweep *sw, int method, double rtol, double atol)
{
  if (!sw) return VI_ERR_ARG;
  if (method < 0 || method >= VI_METHOD_COUNT)
    return vi_fail(sw->errmsg, VI_ERR_ARG, "method %d is not a VI_METHOD_*",
                   method);
  if (!(rtol > 0.0) || !(atol > 0.0) || !isfinite(rtol) || !isfinite(atol))
    return vi_fail(sw->errmsg, VI_ERR_TOLERANCE, "rtol = %g and atol = %g "
                   "must be positive and finite", rtol, atol);
  sw->method = method;
  sw->rtol = rtol;
  sw->atol = atol;
  return VI_OK;
}

int vi_sweep_set_initial(vi_sweep *sw, double t0, const double *x,
                         const double *v)
{
  if (!sw) return VI_ERR_ARG;
  int n = sw->n;
  if (!isfinite(t0))
    return vi_fail(sw->errmsg, VI_ERR_NONFINITE, "t0 = %g is not finite", t0);
  for (int i = 0; i < n; i++)
    if ((x && !isfinite(x[i])) || (v && !isfinite(v[i])))
      return vi_fail(sw->errmsg, VI_ERR_NONFINITE, "the initial state of "
                     "coordinate %d is not finite", i + 1);
  for (int i = 0; i < n; i++) {
    sw->x0[i] = x ? x[i] : 0.0;
    sw->v0[i] = v ? v[i] : 0.0;
  }
  sw->t0 = t0;
  sw->have_state = 0;
  return VI_OK;
}

int vi_sweep_set_warm(vi_sweep *sw, int warm)
{
  if (!sw) return VI_ERR_ARG;
  if (warm != 0 && warm != 1)
    return vi_fail(sw->errmsg, VI_ERR_ARG, "warm = %d: 0 or 1", warm);
  sw->warm = warm;
  if (!warm) sw->have_state = 0;
  return VI_OK;
}

int vi_sweep_reset(vi_sweep *sw)
{
  if (!sw) return VI_ERR_ARG;
  sw->have_state = 0;
  return VI_OK;
}

int vi_sweep_warm_state(const vi_sweep *sw, double *x, double *v)
{
  if (!sw || !x || !v) return VI_ERR_ARG;
  if (!sw->have_state) {
    vi_fail(((vi_sweep *)sw)->errmsg, VI_ERR_STATE, "no warm state: the last "
            "point failed, or none was computed with warm start on");
    return VI_ERR_STATE;
  }
  memcpy(x, sw->xw, sizeof(double) * (size_t)sw->n);
  memcpy(v, sw->vw, sizeof(double) * (size_t)sw->n);
  return VI_OK;
}

int vi_sweep_set_warm_state(vi_sweep *sw, const double *x, const double *v)
{
  if (!sw || !x || !v) return VI_ERR_ARG;
  if (!sw->warm)
    return vi_fail(sw->errmsg, VI_ERR_STATE, "a warm state with warm start "
                   "off (vi_sweep_set_warm)");
  for (int i = 0; i < sw->n; i++)
    if (!isfinite(x[i]) || !isfinite(v[i]))
      return vi_fail(sw->errmsg, VI_ERR_NONFINITE, "the warm state of "
                     "coordinate %d is not finite", i + 1);
  memcpy(sw->xw, x, sizeof(double) * (size_t)sw->n);
  memcpy(sw->vw, v, sizeof(double) * (size_t)sw->n);
  sw->have_state = 1;
  return VI_OK;
}

int vi_sweep_set_param(vi_sweep *sw, const char *key, double value)
{
  if (!sw) return VI_ERR_ARG;
  if (vi_param_kind(key) == VI_PARAM_INITIAL_STATE) {
    int st = vi_param_set_initial(key, value, sw->n, &sw->t0, sw->x0, sw->v0);
    if (st)
      return vi_fail(sw->errmsg, st, "%s = %.17g: %s", key, value,
                     st == VI_ERR_DIM ? "index outside 1..n" : vi_strerror(st));
    sw->have_state = 0; /* a new initial state: a cold start */
    return VI_OK;
  }
  double om = sw->m->omega_f;
  int st = vi_model_set_param(sw->m, key, value);
  if (st) return vi_fail(sw->errmsg, st, "%s", vi_model_errmsg(sw->m));
  /* the shared constrained modes survive a new non-zero Omega (retuned)
   * and a new r; anything else rebuilds them (vi_held_internal.h) */
  const char *r = strstr(key, "].r");
  int keep = (!strcmp(key, "forcing.omega") &&
              (om == 0.0) == (sw->m->omega_f == 0.0)) ||
             (!strncmp(key, "stops[", 6) && r && !strcmp(r, "].r"));
  if (!keep) vi_held_cache_clear(sw->hc);
  return VI_OK;
}

int vi_sweep_param(const vi_sweep *sw, const char *key, double *value)
{
  if (!sw || !value) return VI_ERR_ARG;
  vi_sweep *s = (vi_sweep *)sw; /* only errmsg is written */
  int st = vi_param_kind(key) == VI_PARAM_INITIAL_STATE
               ? vi_param_initial(key, sw->n, sw->t0, sw->x0, sw->v0, value)
               : vi_model_param(sw->m, key, value);
  if (st)
    vi_fail(s->errmsg, st, "%s", vi_param_kind(key) == VI_PARAM_INITIAL_STATE
                                     ? vi_strerror(st)
                                     : vi_model_errmsg(sw->m));
  return st;
}

int vi_sweep_set_monitor(vi_sweep *sw, vi_sweep_monitor_fn fn, void *user,
                         vi_destroy_fn destroy)
{
  if (!sw) return VI_ERR_ARG;
  sw->mon = fn;
  vi_user_set(&sw->mon_user, &sw->mon_free, user, destroy);
  return VI_OK;
}

int vi_sweep_set_sim_hook(vi_sweep *sw, vi_sweep_sim_fn fn, void *user,
                          vi_destroy_fn destroy)
{
  if (!sw) return VI_ERR_ARG;
  sw->hook = fn;
  vi_user_set(&sw->hook_user, &sw->hook_free, user, destroy);
  return VI_OK;
}

int vi_sweep_set_cancel(vi_sweep *sw, vi_cancel_fn fn, void *user,
                        vi_destroy_fn destroy)
{
  if (!sw) return VI_ERR_ARG;
  sw->cancel = fn;
  vi_user_set(&sw->cancel_user, &sw->cancel_free, user, destroy);
  return VI_OK;
}

int vi_sweep_set_lyapunov(vi_sweep *sw, int on)
{
  if (!sw) return VI_ERR_ARG;
  if (on != 0 && on != 1)
    return vi_fail(sw->errmsg, VI_ERR_ARG, "lyapunov = %d: 0 or 1", on);
  sw->lyap = on;
  return VI_OK;
}

double vi_sweep_lyapunov(const vi_sweep *sw)
{
  return sw && sw->done && sw->lyap ? sw->lambda : NAN;
}

/* The largest Lyapunov exponent over the recorded periods, carried on from
 * the point's end state (vi_orbit_lyapunov: exact state-transition
 * matrices and saltation matrices); the forcing phase there is t0's, so t0
 * must be a whole number of periods.  NaN where it is refused (no
 * closed-form flow, sticking, a grazing impact). */
static int lyap_poll(const vi_progress *p, void *user) /* cancel, per period */
{
  const vi_sweep *sw = user;
  (void)p;
  return sw->cancel && sw->cancel(sw->cancel_user);
}

static double lyapunov(vi_sweep *sw)
{
  vi_orbit *o = NULL;
  double lambda = NAN, ph = fmod(sw->t0, sw->T);
  if (fmin(ph, sw->T - ph) > 1e-12 * sw->T) return NAN;
  if (!vi_orbit_create(sw->m, &o) &&
      !vi_orbit_set_monitor(o, lyap_poll, sw, NULL) &&
      !vi_orbit_set_tolerances(o, sw->rtol, sw->atol) &&
      !vi_orbit_set_initial(o, sw->xw, sw->vw) &&
      vi_orbit_lyapunov(o, 0.0, sw->record, &lambda, NULL))
    lambda = NAN;
  vi_orbit_destroy(&o);
  return lambda;
}

int vi_sweep_set_orbits(vi_sweep *sw, int nphase)
{
  if (!sw) return VI_ERR_ARG;
  if (nphase < 0 || (nphase > 0 && nphase < 8))
    return vi_fail(sw->errmsg, VI_ERR_ARG, "orbits: %d phases (0: none, "
                   "else at least 8)", nphase);
  sw->nphase = nphase;
  return VI_OK;
}

/* ---- one point ------------------------------------------------------------- */

/* Impacts of the recorded periods, kept in growing arrays. */
static int on_event(const vi_event *ev, void *user)
{
  vi_sweep *sw = user;
  if (ev->kind != VI_EVENT_IMPACT || ev->t < sw->t_rec) return 0;
  if (sw->nimp == sw->cap) {
    int64_t cap = sw->cap ? 2 * sw->cap : 16;
    double *t = realloc(sw->t, sizeof(double) * (size_t)cap);
    if (t) sw->t = t;
    double *ph = t ? realloc(sw->phase, sizeof(double) * (size_t)cap) : NULL;
    if (ph) sw->phase = ph;
    double *vn = ph ? realloc(sw->vn, sizeof(double) * (size_t)cap) : NULL;
    if (!vn) {
      sw->oom = 1;
      return 1;
    }
    sw->vn = vn;
    sw->cap = cap;
  }
  sw->t[sw->nimp] = ev->t;
  sw->phase[sw->nimp] = fmod(ev->t, sw->T);
  sw->vn[sw->nimp] = ev->vn;
  sw->nimp++;
  return 0;
}

/* Every P(1,1) orbit at this point, unstable ones included, for the
 * diagram's unstable branches: the orbit census (vi_census.h) seeded by the
 * phase scan alone; -1: no closed-form flow or not one stop. */
static int p11_orbits(vi_sweep *sw)
{
  vi_census *c = NULL;
  int st = vi_census_create(sw->m, 1, 1, &c);
  if (!st) {
    vi_census_scan_only(c);
    if (!(st = vi_census_set_phases(c, sw->nphase)) && sw->cancel)
      st = vi_census_set_cancel(c, sw->cancel, sw->cancel_user, NULL);
    if (!st) st = vi_census_run(c);
  }
  if (st == VI_ERR_UNSUPPORTED || st == VI_ERR_STATE) { /* band, or ns != 1 */
    sw->norb = -1;
    vi_census_destroy(&c);
    return VI_OK;
  }
  int found = st ? 0 : vi_census_count(c);
  if (found) {
    sw->ovn = malloc(sizeof(double) * found);
    sw->ophase = malloc(sizeof(double) * found);
    sw->ostable = malloc(sizeof(int) * found);
    sw->oadm = malloc(sizeof(int) * found);
    if (!sw->ovn || !sw->ophase || !sw->ostable || !sw->oadm) st = VI_ERR_NOMEM;
  }
  for (int i = 0; !st && i < found; i++) {
    double t = 0;
    vi_census_orbit(c, i, &t, NULL, NULL, 0, NULL, &sw->ovn[i]);
    vi_census_stability(c, i, NULL, NULL, &sw->ostable[i], &sw->oadm[i], NULL);
    sw->ophase[i] = fmod(t, sw->T);
    sw->norb++;
  }
  vi_census_destroy(&c);
  return st;
}

/* The warm state may lie past a stop that moved: put it back on each
 * violated stop along w_k (positions only), the smallest legal change. */
static void onto_stops(const vi_model *m, double *x)
{
  int n = m->n;
  for (int k = 0; k < m->ns; k++) {
    const double *w = vi_stop_w(m, k);
    double xs = m->xsv[k], gx = 0, ww = 0;
    for (int i = 0; i < n; i++) {
      gx += w[i] * x[i];
      ww += w[i] * w[i];
    }
    if (gx > xs) {
      double sft = (gx - xs + 1e-14 * fmax(1.0, fabs(xs))) / ww;
      for (int i = 0; i < n; i++) x[i] -= sft * w[i];
    }
  }
}

/* A simulation of the point, started warm or cold; NULL on error (st). */
static vi_sim *make_sim(vi_sweep *sw, int *st)
{
  vi_sim *s = NULL;
  if ((*st = vi_sim_create(sw->m, &s))) {
    vi_fail(sw->errmsg, *st, "creating the simulation: %s", vi_strerror(*st));
    return NULL;
  }
  if ((*st = vi_sim_set_method(s, sw->method)) ||
      (*st = vi_sim_set_tolerances(s, sw->rtol, sw->atol)) ||
      (sw->hook && (*st = sw->hook(s, sw->hook_user)))) {
    vi_fail(sw->errmsg, *st, "configuring the simulation: %s", vi_sim_errmsg(s));
    vi_sim_destroy(&s);
    return NULL;
  }
  int warm = sw->warm && sw->have_state;
  if (warm) onto_stops(sw->m, sw->xw);
  if ((*st = vi_sim_set_initial(s, sw->t0, warm ? sw->xw : sw->x0,
                                warm ? sw->vw : sw->v0))) {
    vi_fail(sw->errmsg, *st, "%s: %s", warm ? "warm start" : "initial state",
            vi_sim_errmsg(s));
    vi_sim_destroy(&s);
    return NULL;
  }
  if ((*st = vi_held_share_cache(s, sw->hc))) {
    vi_fail(sw->errmsg, *st, "out of memory");
    vi_sim_destroy(&s);
    return NULL;
  }
  vi_sim_set_event_callback(s, on_event, sw, NULL);
  vi_sim_set_event_states(s, 0); /* on_event reads t and vn only */
  if (sw->cancel) vi_sim_set_cancel(s, sw->cancel, sw->cancel_user, NULL);
  return s;
}

/* Transient, then the recorded periods with their stroboscopic states. */
static int simulate(vi_sweep *sw, vi_sim *s)
{
  int N = sw->n, R = sw->record, st;
  double T = sw->T;
  sw->t_rec = sw->t0 + sw->transient * T;
  st = sw->transient > 0 ? vi_sim_run(s, sw->t_rec) : VI_OK;
  if (!st) vi_sim_state(s, NULL, sw->z, sw->z + N);
  for (int j = 1; j <= R && !st; j++) {
    st = vi_sim_run(s, sw->t0 + (sw->transient + j) * T);
    if (!st) {
      double *zz = sw->z + (size_t)j * 2 * N;
      vi_sim_state(s, NULL, zz, zz + N);
    }
  }
  if (st) {
    if (sw->oom) st = VI_ERR_NOMEM;
    vi_fail(sw->errmsg, st, "%s: %s", vi_strerror(st),
            sw->oom ? "out of memory" : vi_sim_errmsg(s));
  }
  return st;
}

static int point(vi_sweep *sw)
{
  int N = sw->n, R = sw->record, st;
  size_t nz = (size_t)(R + 1) * 2 * N;
  if (!sw->z && !(sw->z = malloc(sizeof(double) * nz)))
    return vi_fail(sw->errmsg, VI_ERR_NOMEM, "out of memory");
  for (size_t i = 0; i < nz; i++) sw->z[i] = NAN;
  sw->nimp = 0;
  sw->oom = 0;
  sw->pn = sw->pm = 0;
  sw->lambda = NAN;
  free_orbits(sw);
  double omega = sw->m->omega_f;
  if (!(omega > 0))
    return vi_fail(sw->errmsg, VI_ERR_FREQUENCY, "no harmonic forcing, so "
                   "no forcing period to sample");
  sw->T = vi_forcing_period(omega);
  if (sw->cancel && sw->cancel(sw->cancel_user)) return VI_CANCELLED;
  if (sw->nphase > 0 && (st = p11_orbits(sw)))
    return vi_fail(sw->errmsg, st, "P(1,1) orbits: %s", vi_strerror(st));
  vi_sim *s = make_sim(sw, &st);
  if (!s) return st;
  st = simulate(sw, s);
  if (!st) {
    double t_end = sw->t0 + (sw->transient + R) * sw->T;
    sw->pn = vi_classify_strobes(R, 2 * N, sw->z, vi_orbit_xs_scale(sw->m), sw->tol,
                                 sw->nmax, sw->t, sw->nimp, sw->T, t_end,
                                 &sw->pm);
    vi_sim_state(s, NULL, sw->xw, sw->vw);
  }
  vi_sim_destroy(&s);
  if (!st && sw->lyap) sw->lambda = lyapunov(sw);
  if (!st && sw->cancel && sw->cancel(sw->cancel_user)) st = VI_CANCELLED;
  return st;
}

int vi_sweep_iterate(vi_sweep *sw)
{
  if (!sw) return VI_ERR_ARG;
  sw->errmsg[0] = '\0';
  int st = point(sw);
  sw->done = 1;
  sw->failed = st != VI_OK;
  sw->have_state = !st && sw->warm;
  if (st) sw->pn = sw->pm = 0; /* the impacts before the failure stay */
  sw->points++;
  if (sw->mon && sw->mon(sw, sw->points, st, sw->mon_user) && !st) {
    vi_fail(sw->errmsg, VI_STOPPED, "stopped by the monitor");
    return VI_STOPPED;
  }
  return st;
}

/* ---- results ------------------------------------------------------------------ */

int vi_sweep_period(const vi_sweep *sw, int *n, int *m)
{
  if (!sw || !n || !m) return VI_ERR_ARG;
  *n = *m = 0;
  if (!sw->done) return VI_ERR_STATE;
  *n = sw->pn;
  *m = sw->pm;
  return VI_OK;
}

int vi_sweep_failed(const vi_sweep *sw) { return sw ? sw->failed : 0; }

double vi_sweep_forcing_period(const vi_sweep *sw)
{
  return sw && sw->done ? sw->T : 0.0;
}

int vi_sweep_impacts(const vi_sweep *sw, int64_t *count, const double **t,
                     const double **phase, const double **vn)
{
  if (!sw || !count) return VI_ERR_ARG;
  *count = sw->done ? sw->nimp : 0;
  if (t) *t = sw->t;
  if (phase) *phase = sw->phase;
  if (vn) *vn = sw->vn;
  return VI_OK;
}

const double *vi_sweep_strobe(const vi_sweep *sw, int *ld, int *record)
{
  if (ld) *ld = sw ? 2 * sw->n : 0;
  if (record) *record = sw ? sw->record : 0;
  return sw && sw->done && sw->z ? sw->z + 2 * (size_t)sw->n : NULL;
}

const vi_model *vi_sweep_model(const vi_sweep *sw) { return sw ? sw->m : NULL; }

int vi_sweep_orbits(const vi_sweep *sw, int *count, const double **vn,
                    const double **phase, const int **stable,
                    const int **admissible)
{
  if (!sw || !count) return VI_ERR_ARG;
  *count = sw->done ? sw->norb : 0;
  if (vn) *vn = sw->ovn;
  if (phase) *phase = sw->ophase;
  if (stable) *stable = sw->ostable;
  if (admissible) *admissible = sw->oadm;
  return VI_OK;
}

/* ---- attractors across points ------------------------------------------------ */

/* 1 if the n states a and b [ld each, n2 used] agree up to a cyclic shift. */
static int same_cycle(int n, int n2, const double *a, const double *b, int ld,
                      double tol)
{
  double scale = 0.0;
  for (int k = 0; k < n; k++)
    for (int i = 0; i < n2; i++)
      scale = fmax(scale, fmax(fabs(a[(size_t)k * ld + i]),
                               fabs(b[(size_t)k * ld + i])));
  for (int s = 0; s < n; s++) {
    int ok = 1;
    for (int k = 0; ok && k < n; k++)
      for (int i = 0; ok && i < n2; i++)
        ok = fabs(a[(size_t)k * ld + i] - b[(size_t)((k + s) % n) * ld + i]) <=
             tol * scale;
    if (ok) return 1;
  }
  return 0;
}

int vi_sweep_attractors(int64_t count, int ncoord, int record, const int *n,
                        const double *strobe, int ld, double tol, int *id,
                        int *nattr)
{
  if (!n || !strobe || !id || !nattr || count < 0 || !(tol > 0.0))
    return VI_ERR_ARG;
  *nattr = 0;
  if (ncoord < 1 || record < 1 || ld < 2 * ncoord) return VI_ERR_DIM;
  int64_t *rep = malloc(sizeof(int64_t) * (size_t)(count ? count : 1));
  if (!rep) return VI_ERR_NOMEM;
  size_t blk = (size_t)ld * record;
  for (int64_t i = 0; i < count; i++) {
    id[i] = -1;
    if (n[i] < 1 || n[i] > record) continue;
    const double *a = strobe + (size_t)i * blk + (size_t)(record - n[i]) * ld;
    for (int k = 0; k < *nattr && id[i] < 0; k++) {
      int64_t r = rep[k];
      const double *b = strobe + (size_t)r * blk + (size_t)(record - n[r]) * ld;
      if (n[r] == n[i] && same_cycle(n[i], 2 * ncoord, a, b, ld, tol)) id[i] = k;
    }
    if (id[i] < 0) {
      rep[*nattr] = i;
      id[i] = (*nattr)++;
    }
  }
  free(rep);
  return VI_OK;
}
