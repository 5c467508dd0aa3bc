/* vi_balance.c - the energy balance of a periodic impacting orbit
 * (MODEL.md section 5; WB 11-13): one period with the ledger, the work fed
 * in on the approach to each impact, totals and per stop, the restitution
 * they imply, and the reduced model's equivalent restitution. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vi_impact_internal.h"
#include "vi_orbit_handle.h"

typedef struct bal_ctx {
  vi_orbit *o;
  int seen, closed, bad; /* impacts, ledger intervals ended by one */
  double *pFE, *pDE, *pXE; /* work since the last impact [n] */
} bal_ctx;

static int bal_event(const vi_event *ev, void *user)
{
  bal_ctx *c = user;
  vi_orbit *o = c->o;
  if (ev->kind != VI_EVENT_IMPACT) return 0;
  int j = c->seen++, n = o->n;
  if (j >= MAX_M) return 0;
  if (j > 0 && ev->t == o->it[j - 1]) c->bad = 1; /* simultaneous contacts */
  o->it[j] = ev->t;
  o->istop[j] = ev->stop;
  o->ivn[j] = ev->vn;
  o->iie[j] = ev->ie;
  memcpy(o->ix + (size_t)j * n, ev->x, sizeof(double) * n);
  memcpy(o->iv + (size_t)j * n, ev->v_minus, sizeof(double) * n);
  memcpy(o->ivp + (size_t)j * n, ev->v_plus, sizeof(double) * n);
  return 0;
}

/* the work of each interval goes to the impact that ends it (its
 * approach); what follows the last impact of the period is the approach of
 * the first one, one period later */
static int bal_ledger(const vi_ledger_interval *iv, void *user)
{
  bal_ctx *c = user;
  vi_orbit *o = c->o;
  int n = o->n;
  for (int i = 0; i < n; i++) {
    c->pFE[i] += iv->FE[i];
    c->pDE[i] += iv->DE[i];
    c->pXE[i] += iv->XE[i];
  }
  if (!iv->dE) return 0;
  int j = c->closed++;
  if (j >= MAX_M) return 0;
  memcpy(o->aFE + (size_t)j * n, c->pFE, sizeof(double) * n);
  memcpy(o->aDE + (size_t)j * n, c->pDE, sizeof(double) * n);
  memcpy(o->aXE + (size_t)j * n, c->pXE, sizeof(double) * n);
  memset(c->pFE, 0, sizeof(double) * 3 * n);
  return 0;
}

static int bal_sample(double t, int n, const double *x, const double *v, void *u)
{
  (void)t; (void)v;
  vi_orbit *o = u;
  double g = -HUGE_VAL; /* the nearest stop */
  for (int k = 0; k < o->ns; k++)
    g = fmax(g, vi_dot(n, vi_stop_w(o->m, k), x) - o->m->xsv[k]);
  o->gmin = fmin(o->gmin, g);
  return 0;
}

/* One period from the fixed point with the ledger: WB 11-13, in total and
 * per stop. */
int vi_balance_run(vi_orbit *o)
{
  const vi_model *m = o->m;
  int n = o->n, ns = o->ns, st;
  double *pw = calloc(3 * (size_t)n, sizeof(double));
  if (!pw) return vi_fail(o->errmsg, VI_ERR_NOMEM, "out of memory");
  bal_ctx c = {o, 0, 0, 0, pw, pw + n, pw + (size_t)2 * n};
  o->gmin = HUGE_VAL;
  if ((st = vi_sim_enable_ledger(o->sim, 1)) ||
      (st = vi_sim_set_event_callback(o->sim, bal_event, &c, NULL)) ||
      (st = vi_sim_set_ledger_callback(o->sim, bal_ledger, &c, NULL)) ||
      (st = vi_sim_set_initial(o->sim, o->t_s, o->zfix, o->zfix + n)) ||
      (st = vi_sim_set_sampling(o->sim, o->T / 4096, bal_sample, o, NULL)) ||
      (st = vi_sim_run(o->sim, o->t_s + o->T)))
    vi_fail(o->errmsg, st < 0 ? st : VI_ERR_STATE, "balance run: %s",
            vi_sim_errmsg(o->sim));
  /* whatever happened, the sim keeps no pointer to this frame's context
   * and no ledger or sampling it did not have before */
  vi_sim_set_event_callback(o->sim, NULL, NULL, NULL);
  vi_sim_set_ledger_callback(o->sim, NULL, NULL, NULL);
  vi_sim_set_sampling(o->sim, 0.0, NULL, NULL, NULL);
  vi_sim_enable_ledger(o->sim, 0);
  if (!st && c.closed >= 1 && c.closed <= MAX_M)
    for (int i = 0; i < n; i++) { /* the tail: the first impact's approach */
      o->aFE[i] += pw[i];
      o->aDE[i] += pw[n + i];
      o->aXE[i] += pw[2 * n + i];
    }
  free(pw);
  if (st) return st < 0 ? st : VI_ERR_STATE;
  if (c.seen != o->pm || c.closed != o->pm || c.bad)
    return vi_fail(o->errmsg, VI_ERR_NOT_CONVERGED,
                   "balance run: %d impacts in the period of a P(1,%d) orbit%s",
                   c.seen, o->pm, c.bad ? " (simultaneous contacts)" : "");
  o->mi = o->pm;
  /* totals over the period (WB 11) and per stop (the approaches to its
   * impacts): RE_k = sum of the approach work, KE_k = sum 1/2 v_n^2 / G_kk
   * (WB 12), r_k = sqrt(1 - RE_k / KE_k) (WB 13); the stops' RE_k - IE_k
   * are the energy the motion carries from one stop to the next and sum to
   * zero: one stop, or a symmetric orbit, closes each */
  memset(o->FE, 0, sizeof(double) * 3 * (size_t)n); /* FE, DE, XE */
  memset(o->kFE, 0, sizeof(double) * 3 * (size_t)n * ns);
  memset(o->kKE, 0, sizeof(double) * 3 * (size_t)ns); /* kKE, kRE, kIE */
  memset(o->kcnt, 0, sizeof(int) * (size_t)ns);
  o->RE = o->IE = o->KEi = 0.0;
  for (int j = 0; j < o->mi; j++) {
    int k = o->istop[j];
    double ke = vi_impact_ke(o->ivn[j], m->G[k + (size_t)k * ns]);
    o->kcnt[k]++;
    o->kKE[k] += ke;
    o->kIE[k] += o->iie[j];
    o->KEi += ke;
    o->IE += o->iie[j];
    for (int i = 0; i < n; i++) {
      size_t a = (size_t)j * n + i, b = (size_t)k * n + i;
      o->FE[i] += o->aFE[a];
      o->DE[i] += o->aDE[a];
      o->XE[i] += o->aXE[a];
      o->kFE[b] += o->aFE[a];
      o->kDE[b] += o->aDE[a];
      o->kXE[b] += o->aXE[a];
      double w = o->aFE[a] - o->aDE[a] - o->aXE[a];
      o->kRE[k] += w;
      o->RE += w;
    }
  }
  for (int k = 0; k < ns; k++) {
    double x = o->kKE[k] > 0.0 ? 1.0 - o->kRE[k] / o->kKE[k] : NAN;
    o->kr[k] = x >= 0.0 ? sqrt(x) : NAN;
    o->kcl[k] = o->kKE[k] > 0.0 ? fabs(o->kRE[k] - o->kIE[k]) / o->kKE[k] : NAN;
  }
  double x = 1.0 - o->RE / o->KEi;                      /* WB 12, 13 */
  o->r_rec = x >= 0.0 ? sqrt(x) : NAN;
  o->closure = fabs(o->RE - o->IE) / o->KEi;             /* WB 11 */
  for (int j = 0; j < n; j++) { /* r_eff of the first impact */
    double qm = 0.0, qp = 0.0;
    for (int i = 0; i < n; i++) {
      qm += m->PsiTM[j + (size_t)i * n] * o->iv[i];
      qp += m->PsiTM[j + (size_t)i * n] * o->ivp[i];
    }
    o->reff[j] = qm != 0.0 ? -qp / qm : NAN;
  }
  return VI_OK;
}

/* ---- getters ------------------------------------------------------------ */
int vi_orbit_balance(const vi_orbit *o, double *period, double *phase,
                     double *vN, double *KE_i, double *RE, double *IE,
                     double *r_rec, double *closure)
{
  NEED_P11(o);
  if (period) *period = o->T;
  if (phase) *phase = fmod(o->it[0], o->T);
  if (vN) *vN = o->ivn[0];
  if (KE_i) *KE_i = o->KEi;
  if (RE) *RE = o->RE;
  if (IE) *IE = o->IE;
  if (r_rec) *r_rec = o->r_rec;
  if (closure) *closure = o->closure;
  return VI_OK;
}

int vi_orbit_modal_balance(const vi_orbit *o, double *FE, double *DE,
                           double *XE, double *r_eff)
{
  NEED_P11(o);
  size_t b = sizeof(double) * o->n;
  if (FE) memcpy(FE, o->FE, b);
  if (DE) memcpy(DE, o->DE, b);
  if (XE) memcpy(XE, o->XE, b);
  if (r_eff) memcpy(r_eff, o->reff, b);
  return VI_OK;
}

int vi_orbit_impact_state(const vi_orbit *o, double *t, double *x, double *v)
{
  NEED_P11(o);
  if (t) *t = o->it[0];
  if (x) memcpy(x, o->ix, sizeof(double) * o->n);
  if (v) memcpy(v, o->iv, sizeof(double) * o->n);
  return VI_OK;
}

int vi_orbit_impacts(const vi_orbit *o, int *count, double *t, int *stop,
                     double *vn, double *x, double *v, int ld)
{
  NEED_ORBIT(o);
  if ((x || v) && ld < o->n) return VI_ERR_ARG;
  if (count) *count = o->mi;
  for (int j = 0; j < o->mi; j++) {
    if (t) t[j] = o->it[j];
    if (stop) stop[j] = o->istop[j];
    if (vn) vn[j] = o->ivn[j];
    if (x) memcpy(x + (size_t)j * ld, o->ix + (size_t)j * o->n, sizeof(double) * o->n);
    if (v) memcpy(v + (size_t)j * ld, o->iv + (size_t)j * o->n, sizeof(double) * o->n);
  }
  return VI_OK;
}

int vi_orbit_stop_balance(const vi_orbit *o, int k, int *count, double *KE_i,
                          double *RE, double *IE, double *r_rec,
                          double *closure)
{
  NEED_ORBIT(o);
  if (k < 0 || k >= o->ns) return VI_ERR_ARG;
  if (count) *count = o->kcnt[k];
  if (KE_i) *KE_i = o->kKE[k];
  if (RE) *RE = o->kRE[k];
  if (IE) *IE = o->kIE[k];
  if (r_rec) *r_rec = o->kr[k];
  if (closure) *closure = o->kcl[k];
  return VI_OK;
}

int vi_orbit_stop_modal_balance(const vi_orbit *o, int k, double *FE,
                                double *DE, double *XE)
{
  NEED_ORBIT(o);
  if (k < 0 || k >= o->ns) return VI_ERR_ARG;
  size_t b = sizeof(double) * o->n, off = (size_t)k * o->n;
  if (FE) memcpy(FE, o->kFE + off, b);
  if (DE) memcpy(DE, o->kDE + off, b);
  if (XE) memcpy(XE, o->kXE + off, b);
  return VI_OK;
}

int vi_orbit_min_gap(const vi_orbit *o, double *gmin)
{
  NEED_ORBIT(o);
  if (gmin) *gmin = o->gmin;
  return VI_OK;
}

int vi_orbit_reduced_restitution(const vi_orbit *o, const int *modes, int k,
                                 double *r_S)
{
  NEED_P11(o);
  if (!modes || !r_S || k < 1 || k > o->n) return VI_ERR_ARG;
  const vi_model *m = o->m;
  int n = o->n;
  const double *psi = vi_stop_psi(m, o->istop[0]);
  double pq = 0.0, pp = 0.0, re = 0.0;
  *r_S = NAN;
  for (int a = 0; a < k; a++) {
    int j = modes[a];
    if (j < 0 || j >= n) return VI_ERR_ARG; /* a getter: o stays const */
    double qd = 0.0;
    for (int i = 0; i < n; i++) qd += m->PsiTM[j + (size_t)i * n] * o->iv[i];
    pq += psi[j] * qd;
    pp += psi[j] * psi[j];
    re += o->FE[j] - o->DE[j] - o->XE[j];
  }
  double ke = 0.5 * pq * pq / pp; /* KE_S */
  if (!(pp > 0.0) || !(re >= 0.0) || re > ke) return VI_ERR_ARG;
  *r_S = sqrt(1.0 - re / ke);
  return VI_OK;
}
