/* vi_truncation.c - the truncation study (vi_truncation.h): per kept-mode
 * count k, the compliance the k modes carry, the k-mode model's response
 * with r and with the r_S that carries the reference orbit's balance, its
 * first impacts, and the same with the static vector added.  Everything
 * is in the reference's modal coordinates, where M = I: reduced models
 * keep its first k coordinates (vi_model_create_truncated). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vibroimpact/vi_truncation.h"
#include "vi_internal.h"

enum { NHIT = 3 }; /* first impacts kept per run */

/* The outcome of an orbit search on one model. */
typedef struct response {
  int pn, pm;       /* class: (1, 1) P(1,1); (0, m) not periodic */
  double vN, phase; /* P(1,1): approach velocity, impact time mod T / T */
  int ok;           /* the search ran */
} response;

/* The first impacts of a run from the initial state. */
typedef struct first {
  int n; /* impacts found, -1 the run failed */
  double t[NHIT], vn[NHIT];
  double release; /* the first end of sticking (r = 0, chatter), or NaN */
} first;

struct vi_truncation {
  vi_model *R;        /* the reference, in its modal coordinates */
  const vi_model *full; /* borrowed: the projection of the initial state */
  const vi_fe *fe;
  int nR, dofs, lo, hi;
  double Gd, Gs, r;   /* the full model's w^T M^-1 w, w^T K^-1 w; R's r */
  double t0, tend;
  int have_initial, begun, forced, p11;
  int next;           /* 0: the reference is next; else the next row's k */
  int nrows, ldt;
  double *q0R, *qk;   /* [2 nR] each: the initial state in R, in a model */
  int *idx;           /* [nR] 0, 1, ...: the modes of a k-mode model */
  double *cd, *cs;    /* [hi] each: compliance carried by k = 1..hi modes */
  double *tab;        /* [ldt x VI_TRUNCATION_COLUMNS] the rows done */
  double ref[VI_TRUNCATION_COLUMNS];
  response rref;
  first fref;
  vi_orbit *oref;     /* the reference orbit (P(1,1): r_S) */
  vi_monitor_fn mon;
  void *mon_user;
  vi_destroy_fn mon_free;
  vi_cancel_fn cancel;
  void *cancel_user;
  vi_destroy_fn cancel_free;
  int stopped, cancelled; /* what interrupted the last step */
  char errmsg[VI_MSG_LEN];
};

/* ---- creation --------------------------------------------------------- */

/* The parts every study has, once R is made; frees R on failure. */
static int finish_create(vi_truncation *tr, vi_truncation **out)
{
  int nR = tr->nR = vi_model_n(tr->R);
  tr->lo = 1;
  tr->hi = nR;
  tr->r = vi_model_restitution(tr->R);
  tr->q0R = calloc(4 * (size_t)nR, sizeof(double));
  tr->idx = malloc(sizeof(int) * (size_t)nR);
  if (!tr->q0R || !tr->idx) {
    vi_truncation_destroy(&tr);
    return VI_ERR_NOMEM;
  }
  tr->qk = tr->q0R + 2 * (size_t)nR;
  for (int j = 0; j < nR; j++) tr->idx[j] = j;
  for (int c = 0; c < VI_TRUNCATION_COLUMNS; c++) tr->ref[c] = NAN;
  *out = tr;
  return VI_OK;
}

int vi_truncation_create(const vi_model *m, vi_truncation **out)
{
  if (!out) return VI_ERR_ARG;
  *out = NULL;
  if (!m) return VI_ERR_ARG;
  int n = vi_model_n(m);
  if (n < 1) return VI_ERR_ARG;
  vi_truncation *tr = calloc(1, sizeof *tr);
  int *all = malloc(sizeof(int) * (size_t)n);
  double *cs = malloc(sizeof(double) * (size_t)n);
  int st = tr && all && cs ? VI_OK : VI_ERR_NOMEM;
  for (int j = 0; !st && j < n; j++) all[j] = j;
  if (!st)
    st = vi_model_create_reduced(m, all, n, vi_model_restitution(m), &tr->R);
  /* w^T K^-1 w: the sum over all the modes */
  if (!st) st = vi_model_modal_compliance(tr->R, 0, n, NULL, cs);
  if (!st) {
    tr->full = m;
    tr->dofs = n;
    tr->Gd = vi_model_stop_compliance(m);
    tr->Gs = cs[n - 1];
  }
  free(all);
  free(cs);
  if (st) {
    vi_truncation_destroy(&tr);
    return st;
  }
  return finish_create(tr, out);
}

int vi_truncation_create_fe(const vi_fe *fe, vi_truncation **out)
{
  if (!out) return VI_ERR_ARG;
  *out = NULL;
  if (!fe) return VI_ERR_ARG;
  vi_truncation *tr = calloc(1, sizeof *tr);
  if (!tr) return VI_ERR_NOMEM;
  int st = vi_fe_create_model(fe, &tr->R);
  if (st) {
    vi_truncation_destroy(&tr);
    return st;
  }
  tr->fe = fe;
  tr->dofs = vi_fe_n(fe);
  tr->Gd = tr->Gs = NAN;
  vi_fe_stop_compliance(fe, 0, &tr->Gd, &tr->Gs);
  return finish_create(tr, out);
}

void vi_truncation_destroy(vi_truncation **trp)
{
  if (!trp || !*trp) return;
  vi_truncation *tr = *trp;
  vi_user_set(&tr->mon_user, &tr->mon_free, NULL, NULL);
  vi_user_set(&tr->cancel_user, &tr->cancel_free, NULL, NULL);
  vi_orbit_destroy(&tr->oref);
  vi_model_destroy(&tr->R);
  free(tr->q0R);
  free(tr->idx);
  free(tr->cd);
  free(tr->tab);
  free(tr);
  *trp = NULL;
}

const char *vi_truncation_errmsg(const vi_truncation *tr)
{
  return tr ? tr->errmsg : "";
}

/* ---- settings --------------------------------------------------------- */

int vi_truncation_set_modes(vi_truncation *tr, int lo, int hi)
{
  if (!tr) return VI_ERR_ARG;
  if (tr->begun)
    return vi_fail(tr->errmsg, VI_ERR_STATE, "the study has begun");
  if (lo < 1 || lo > hi || hi > tr->nR)
    return vi_fail(tr->errmsg, VI_ERR_ARG, "modes %d..%d: need 1 <= lo <= "
                   "hi <= %d (the reference's modes)", lo, hi, tr->nR);
  tr->lo = lo;
  tr->hi = hi;
  return VI_OK;
}

/* x [dofs] into q [nR]: the FE reduction's kept shapes or the modes. */
static int to_modal(const vi_truncation *tr, const double *x, double *q)
{
  if (!x) {
    memset(q, 0, sizeof(double) * (size_t)tr->nR);
    return VI_OK;
  }
  return tr->fe ? vi_fe_to_modal(tr->fe, x, q) : vi_model_to_modal(tr->full, x, q);
}

int vi_truncation_set_initial(vi_truncation *tr, double t0, double t_end,
                              const double *x, const double *v)
{
  if (!tr) return VI_ERR_ARG;
  if (tr->begun)
    return vi_fail(tr->errmsg, VI_ERR_STATE, "the study has begun");
  if (!isfinite(t0) || !isfinite(t_end))
    return vi_fail(tr->errmsg, VI_ERR_NONFINITE, "t0 = %g, t_end = %g", t0,
                   t_end);
  if (!(t_end > t0))
    return vi_fail(tr->errmsg, VI_ERR_TIME, "t_end = %g must exceed t0 = %g",
                   t_end, t0);
  for (int i = 0; i < tr->dofs; i++)
    if ((x && !isfinite(x[i])) || (v && !isfinite(v[i])))
      return vi_fail(tr->errmsg, VI_ERR_NONFINITE, "initial state entry %d "
                     "is not finite", i);
  double *q = tr->q0R, *qd = tr->q0R + tr->nR;
  if (to_modal(tr, x, q) || to_modal(tr, v, qd)) {
    memset(tr->q0R, 0, sizeof(double) * 2 * (size_t)tr->nR);
    tr->have_initial = 0;
    return vi_fail(tr->errmsg, VI_ERR_STATE, "cannot project the initial "
                   "state onto the modes%s", tr->fe ? " (the FE reduction "
                   "keeps no shapes: vi_fe_set_keep_shapes)" : "");
  }
  tr->t0 = t0;
  tr->tend = t_end;
  tr->have_initial = 1;
  return VI_OK;
}

int vi_truncation_set_monitor(vi_truncation *tr, vi_monitor_fn fn, void *user,
                              vi_destroy_fn destroy)
{
  if (!tr) return VI_ERR_ARG;
  tr->mon = fn;
  vi_user_set(&tr->mon_user, &tr->mon_free, user, destroy);
  return VI_OK;
}

int vi_truncation_set_cancel(vi_truncation *tr, vi_cancel_fn fn, void *user,
                             vi_destroy_fn destroy)
{
  if (!tr) return VI_ERR_ARG;
  tr->cancel = fn;
  vi_user_set(&tr->cancel_user, &tr->cancel_free, user, destroy);
  return VI_OK;
}

/* ---- the runs --------------------------------------------------------- */

/* 1 (and the flag set) if the caller asked to cancel. */
static int poll_cancel(vi_truncation *tr)
{
  if (tr->cancel && tr->cancel(tr->cancel_user)) tr->cancelled = 1;
  return tr->cancelled;
}

static int interrupted(const vi_truncation *tr)
{
  return tr->cancelled || tr->stopped;
}

static int on_period(const vi_progress *p, void *user)
{
  vi_truncation *tr = user;
  if (tr->mon(p, tr->mon_user)) tr->stopped = 1;
  return tr->stopped;
}

static int sim_cancel(void *user) { return poll_cancel(user); }

/* The orbit search on m; the caller's monitor watches the reference's
 * (user_monitor), the cancellation every one at every step. */
static void find_orbit(vi_truncation *tr, const vi_model *m, response *r,
                       vi_orbit **keep, int user_monitor)
{
  vi_orbit *o = NULL;
  int watched = user_monitor && tr->mon;
  memset(r, 0, sizeof *r);
  r->vN = r->phase = NAN;
  if (!vi_orbit_create(m, &o) && !vi_orbit_set_initial(o, NULL, NULL) &&
      (!watched || !vi_orbit_set_monitor(o, on_period, tr, NULL)) &&
      (!tr->cancel || !vi_orbit_set_cancel(o, sim_cancel, tr, NULL)) &&
      !vi_orbit_find(o) && !interrupted(tr)) {
    r->ok = 1;
    vi_orbit_classify(o, &r->pn, &r->pm);
    double T = 0, ph = 0;
    if (r->pn == 1 && r->pm == 1 &&
        !vi_orbit_balance(o, &T, &ph, &r->vN, NULL, NULL, NULL, NULL, NULL))
      r->phase = ph / T;
  }
  if (keep && r->ok)
    *keep = o;
  else
    vi_orbit_destroy(&o);
}

static int on_first(const vi_event *ev, void *user)
{
  first *f = user;
  if (ev->kind == VI_EVENT_RELEASE && isnan(f->release)) f->release = ev->t;
  if (ev->kind != VI_EVENT_IMPACT) return 0;
  f->t[f->n] = ev->t;
  f->vn[f->n++] = ev->vn;
  return f->n >= NHIT; /* nonzero: stop */
}

/* The first impacts of m from z [2 n] at t0 (the exact method where it
 * applies): before the first contact the structure answers the forcing,
 * quasi-statically in its high modes (the static flexibility's domain);
 * after it, Newton's law acts through the dynamic compliance. */
static void first_impacts(vi_truncation *tr, const vi_model *m,
                          const double *z, first *f)
{
  vi_sim *s = NULL;
  int n = vi_model_n(m);
  memset(f, 0, sizeof *f);
  f->release = NAN;
  if (!tr->have_initial) return;
  if (!vi_sim_create(m, &s) &&
      !vi_sim_set_initial(s, tr->t0, z, z + n) &&
      !vi_sim_set_tolerances(s, 1e-11, 1e-14) &&
      !vi_sim_set_event_callback(s, on_first, f, NULL) &&
      !vi_sim_set_event_states(s, 0) && /* on_first reads t and vn */
      (!tr->cancel || !vi_sim_set_cancel(s, sim_cancel, tr, NULL))) {
    int st = vi_sim_run(s, tr->tend);
    if (st != VI_OK && st != VI_STOPPED) f->n = -1;
  }
  vi_sim_destroy(&s);
}

/* ---- rows ------------------------------------------------------------- */

/* A response into columns c..c+3 of a row (stride ld). */
static void put_response(double *t, int ld, int c, const response *r)
{
  t[(size_t)c * ld] = r->ok ? r->pn : -1;
  t[(size_t)(c + 1) * ld] = r->ok ? r->pm : NAN;
  t[(size_t)(c + 2) * ld] = r->vN;
  t[(size_t)(c + 3) * ld] = r->phase;
}

/* First impacts into columns c..c+13, against ref's (NULL: none). */
static void put_first(double *t, int ld, int c, const first *f,
                      const first *ref)
{
  t[(size_t)c * ld] = f->n;
  for (int j = 0; j < NHIT; j++) {
    int have = j < f->n;
    double dt = NAN, dv = NAN;
    if (have && ref && j < ref->n) {
      dt = f->t[j] - ref->t[j];
      dv = (f->vn[j] - ref->vn[j]) / ref->vn[j];
    }
    t[(size_t)(c + 1 + j) * ld] = have ? f->t[j] : NAN;
    t[(size_t)(c + 4 + j) * ld] = have ? f->vn[j] : NAN;
    t[(size_t)(c + 7 + j) * ld] = dt;
    t[(size_t)(c + 10 + j) * ld] = dv;
  }
  t[(size_t)(c + 13) * ld] = f->release;
}

/* The reference orbit (the balance every reduced model is measured by)
 * and the reference's first impacts. */
static int run_reference(vi_truncation *tr)
{
  tr->forced = vi_model_omega_forcing(tr->R) > 0;
  vi_orbit_destroy(&tr->oref);
  memset(&tr->rref, 0, sizeof tr->rref);
  tr->rref.vN = tr->rref.phase = NAN;
  if (tr->forced) find_orbit(tr, tr->R, &tr->rref, &tr->oref, 1);
  if (!interrupted(tr)) first_impacts(tr, tr->R, tr->q0R, &tr->fref);
  if (interrupted(tr)) {
    vi_orbit_destroy(&tr->oref);
    return tr->cancelled ? VI_CANCELLED : VI_STOPPED;
  }
  tr->p11 = tr->oref && tr->rref.pn == 1 && tr->rref.pm == 1;
  tr->ref[0] = tr->nR;
  put_response(tr->ref, 1, 4, &tr->rref);
  put_first(tr->ref, 1, 8, &tr->fref, NULL);
  tr->next = tr->lo;
  return VI_OK;
}

/* The buffers of the rows and the compliances the first k modes carry,
 * k = 1..hi (vi_model_modal_compliance), before the first row. */
static int prepare_rows(vi_truncation *tr)
{
  tr->ldt = tr->hi - tr->lo + 1;
  tr->cd = malloc(sizeof(double) * 2 * (size_t)tr->hi);
  tr->tab = malloc(sizeof(double) * (size_t)tr->ldt * VI_TRUNCATION_COLUMNS);
  if (!tr->cd || !tr->tab) {
    free(tr->cd);
    free(tr->tab);
    tr->cd = tr->tab = NULL;
    return vi_fail(tr->errmsg, VI_ERR_NOMEM, "no memory for the rows");
  }
  tr->cs = tr->cd + tr->hi;
  int st = vi_model_modal_compliance(tr->R, 0, tr->hi, tr->cd, tr->cs);
  if (st) {
    free(tr->cd);
    tr->cd = NULL;
    return vi_fail(tr->errmsg, st, "the compliances the modes carry: %s",
                   vi_strerror(st));
  }
  return VI_OK;
}

/* Row k's models run into t (stride ld): k modes with r and with r_S,
 * and k modes plus the static vector (k < nR). */
static void compute_row(vi_truncation *tr, int k, double *t, int ld)
{
  double carried = NAN, rS = NAN;
  response rk, rs, rc;
  first fk, fc;
  vi_model *mk = NULL, *ms = NULL, *mc = NULL;
  /* a model not made runs nothing: no impacts, release 0 */
  memset(&fk, 0, sizeof fk);
  memset(&fc, 0, sizeof fc);
  memset(&rk, 0, sizeof rk);
  rk.vN = rk.phase = NAN;
  rs = rc = rk;
  if (!vi_model_create_truncated(tr->R, k, 0, tr->r, tr->q0R, tr->qk, NULL, &mk))
    first_impacts(tr, mk, tr->qk, &fk);
  if (tr->forced && !interrupted(tr)) {
    if (mk) find_orbit(tr, mk, &rk, NULL, 0);
    if (tr->p11 && !interrupted(tr) &&
        !vi_orbit_reduced_restitution(tr->oref, tr->idx, k, &rS) &&
        !vi_model_create_truncated(tr->R, k, 0, rS, NULL, NULL, NULL, &ms))
      find_orbit(tr, ms, &rs, NULL, 0);
  }
  if (k < tr->nR && !interrupted(tr) &&
      !vi_model_create_truncated(tr->R, k, 1, tr->r, tr->q0R, tr->qk,
                                 &carried, &mc)) {
    first_impacts(tr, mc, tr->qk, &fc);
    if (tr->forced && !interrupted(tr)) find_orbit(tr, mc, &rc, NULL, 0);
  }
  vi_model_destroy(&mk);
  vi_model_destroy(&ms);
  vi_model_destroy(&mc);
  t[(size_t)22 * ld] = rS;
  put_response(t, ld, 4, &rk);
  put_first(t, ld, 8, &fk, &tr->fref);
  put_response(t, ld, 23, &rs);
  t[(size_t)27 * ld] = k < tr->nR;
  t[(size_t)28 * ld] = k < tr->nR ? carried / tr->Gd : NAN;
  put_response(t, ld, 29, &rc);
  put_first(t, ld, 33, &fc, &tr->fref);
  if (k >= tr->nR) /* no mode beyond k: no variant */
    for (int c = 29; c < VI_TRUNCATION_COLUMNS; c++) t[(size_t)c * ld] = NAN;
}

static int run_row(vi_truncation *tr)
{
  int st, k = tr->next;
  if (!tr->cd && (st = prepare_rows(tr))) return st;
  const double *K = vi_model_stiffness(tr->R);
  double lam = K[(k - 1) + (size_t)(k - 1) * tr->nR];
  double *t = tr->tab + tr->nrows;
  int ld = tr->ldt;
  t[0] = k;
  t[ld] = sqrt(lam > 0 ? lam : 0);
  t[2 * (size_t)ld] = tr->cd[k - 1] / tr->Gd;
  t[3 * (size_t)ld] = isfinite(tr->Gs) && isfinite(tr->cs[k - 1])
                          ? tr->cs[k - 1] / tr->Gs : NAN;
  compute_row(tr, k, t, ld);
  if (interrupted(tr)) return tr->cancelled ? VI_CANCELLED : VI_STOPPED;
  tr->nrows++;
  tr->next++;
  return VI_OK;
}

int vi_truncation_iterate(vi_truncation *tr)
{
  if (!tr) return VI_ERR_ARG;
  if (vi_truncation_done(tr))
    return vi_fail(tr->errmsg, VI_ERR_STATE, "the study is done: rows "
                   "%d..%d", tr->lo, tr->hi);
  tr->begun = 1;
  tr->cancelled = tr->stopped = 0;
  if (poll_cancel(tr)) return VI_CANCELLED;
  int st = tr->next ? run_row(tr) : run_reference(tr);
  if (st == VI_CANCELLED)
    vi_fail(tr->errmsg, st, "cancelled in %s", tr->next ? "a row" : "the reference");
  else if (st == VI_STOPPED)
    vi_fail(tr->errmsg, st, "stopped by the monitor in the reference");
  return st;
}

/* ---- results ---------------------------------------------------------- */

int vi_truncation_done(const vi_truncation *tr)
{
  return tr && tr->next > tr->hi;
}

int vi_truncation_row(const vi_truncation *tr, int k, double *row)
{
  if (!tr || !row || (k != 0 && (k < tr->lo || k > tr->hi))) return VI_ERR_ARG;
  if (k == 0 ? !tr->next : k - tr->lo >= tr->nrows) return VI_ERR_STATE;
  for (int c = 0; c < VI_TRUNCATION_COLUMNS; c++)
    row[c] = k == 0 ? tr->ref[c]
                    : tr->tab[(k - tr->lo) + (size_t)c * tr->ldt];
  return VI_OK;
}

int vi_truncation_table(const vi_truncation *tr, double *rows, int ldrows,
                        int *nrows)
{
  if (!tr || !nrows) return VI_ERR_ARG;
  if (rows && ldrows < (tr->nrows > 1 ? tr->nrows : 1)) return VI_ERR_ARG;
  *nrows = tr->nrows;
  for (int c = 0; rows && c < VI_TRUNCATION_COLUMNS; c++)
    for (int i = 0; i < tr->nrows; i++)
      rows[i + (size_t)c * ldrows] = tr->tab[i + (size_t)c * tr->ldt];
  return VI_OK;
}

int vi_truncation_summary(const vi_truncation *tr, double *info)
{
  if (!tr || !info) return VI_ERR_ARG;
  info[0] = tr->dofs;
  info[1] = tr->lo;
  info[2] = tr->hi;
  info[3] = tr->nR;
  info[4] = tr->r;
  info[5] = tr->Gd;
  info[6] = tr->Gs;
  info[7] = vi_truncation_done(tr);
  return VI_OK;
}

const vi_model *vi_truncation_model(const vi_truncation *tr)
{
  return tr ? tr->R : NULL;
}
