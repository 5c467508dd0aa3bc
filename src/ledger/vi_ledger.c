/* vi_ledger.c - the per-mode energy ledger (MODEL.md section 4): intervals,
 * impact jumps and closure residuals.  The integrals themselves are the
 * backends' (CVODES quadratures, Gauss-Legendre on the closed form); they
 * reach this file only through the rates below. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vi_forcing.h"
#include "vi_ledger_internal.h"

struct vi_ledger {
  const vi_model *m;
  int n, harmonic;
  double *Q;            /* cumulative FE, DE, XE, CE, NE [5n] */
  double *QA;           /* Q at the interval's start; then its integrals [5n] */
  double *EA, *KA;      /* modal energy and its kinetic part at t_a [n] */
  double *EB, *KB, *qd; /* the same and q' before the jump [n] */
  double *dE, *dEtot;   /* this jump, all jumps [n] */
  double *R, *qs, *qds; /* scratch: rates [5n], q and q' [n] */
  double ta, ie, maxres, emax;
  vi_ledger_fn fn;
  void *user;
  vi_ledger_pending_fn pend; /* a backend's integrals owed (vi_ledger_defer) */
  vi_ledger_since_fn since;
  void *pend_data;
};

/* Bring Q to the owing backend's present time. */
static void flush(vi_ledger *L)
{
  if (L->pend) L->pend(L->pend_data, L->Q);
}

void vi_ledger_defer(vi_ledger *L, vi_ledger_pending_fn fn,
                     vi_ledger_since_fn since, void *data)
{
  L->pend = fn;
  L->since = since;
  L->pend_data = data;
}

void vi_ledger_settle(vi_ledger *L)
{
  if (!L) return;
  flush(L);
  L->pend = NULL;
  L->since = NULL;
  L->pend_data = NULL;
}

vi_ledger *vi_ledger_create(const vi_model *m)
{
  int n = m->n;
  vi_ledger *L = calloc(1, sizeof *L + 25 * (size_t)n * sizeof(double));
  if (!L) return NULL;
  double *p = (double *)(L + 1);
  L->Q = p; p += VI_LEDGER_BLOCKS * (size_t)n;
  L->QA = p; p += VI_LEDGER_BLOCKS * (size_t)n;
  L->EA = p; p += n;
  L->KA = p; p += n;
  L->EB = p; p += n;
  L->KB = p; p += n;
  L->qd = p; p += n;
  L->dE = p; p += n;
  L->dEtot = p; p += n;
  L->R = p; p += VI_LEDGER_BLOCKS * (size_t)n;
  L->qs = p; p += n;
  L->qds = p;
  L->m = m;
  L->n = n;
  L->harmonic = vi_forcing_harmonic(m);
  return L;
}

void vi_ledger_destroy(vi_ledger *L) { free(L); }

void vi_ledger_set_callback(vi_ledger *L, vi_ledger_fn fn, void *user)
{
  L->fn = fn;
  L->user = user;
}

double *vi_ledger_integrals(vi_ledger *L)
{
  vi_ledger_settle(L); /* the caller integrates into Q from here */
  return L->Q;
}

double vi_ledger_open_since(const vi_ledger *L) { return L->ta; }

double vi_ledger_max_residual(const vi_ledger *L) { return L->maxres; }

void vi_ledger_rates(vi_ledger *L, double t, const double *qd,
                     const vi_ledger_held *h, const double *gq, double *rates)
{
  const vi_model *m = L->m;
  vi_phase p = L->harmonic ? vi_phase_at(m->omega_f, t)
                           : vi_phase_none(m->omega_f);
  vi_ledger_rates_phase(L, &p, qd, h, gq, rates);
}

void vi_ledger_rates_phase(vi_ledger *L, const vi_phase *p, const double *qd,
                           const vi_ledger_held *h, const double *gq,
                           double *rates)
{
  const vi_model *m = L->m;
  int n = L->n;
  const double *Fa, *Fb, *F0;
  vi_forcing_vectors(m, VI_FORCING_MODAL, &Fa, &Fb, &F0);
  double *FE = rates, *DE = rates + n, *XE = rates + 2 * (size_t)n;
  double *CE = rates + 3 * (size_t)n, *NE = gq ? rates + 4 * (size_t)n : NULL;
  for (int j = 0; j < n; j++) {
    double F = vi_harm(p, 0, Fa[j], Fb[j], F0[j]);
    FE[j] = qd[j] * F;                                           /* WB 7 */
    DE[j] = m->D[j + (size_t)j * (size_t)n] * qd[j] * qd[j];     /* WB 8 */
    /* the held stops' reactions on mode j, each along its own psi_k
     * (MODEL.md section 9): CE_j = -sum_k lambda_k psi_kj q_j' */
    double c = 0.0;
    for (int i = 0; h && i < h->cnt; i++)
      c += h->lam[i] * vi_stop_psi(m, h->set[i])[j];
    CE[j] = -c * qd[j];
    if (NE) NE[j] = qd[j] * gq[j];
    XE[j] = 0.0;
    if (!m->proportional) {
      double x = 0.0;
      for (int k = 0; k < n; k++)
        if (k != j) x += m->D[j + (size_t)k * (size_t)n] * qd[k];
      XE[j] = qd[j] * x;
    }
  }
}

void vi_ledger_rates_state(vi_ledger *L, double t, const double *z,
                           const vi_ledger_held *h, const double *gq,
                           double *rates)
{
  vi_modal_project(L->m, z, NULL, L->qds);
  vi_ledger_rates(L, t, L->qds, h, gq, rates);
}

void vi_ledger_accumulate(vi_ledger *L, double t, const double *qd,
                          const vi_ledger_held *h, double weight)
{
  vi_ledger_settle(L);
  vi_ledger_rates(L, t, qd, h, NULL, L->R);
  for (int k = 0; k < 4 * L->n; k++) L->Q[k] += weight * L->R[k];
}

void vi_ledger_accumulate_phase(vi_ledger *L, const vi_phase *p,
                                const double *qd, const vi_ledger_held *h,
                                double weight)
{
  const vi_model *m = L->m;
  vi_ledger_settle(L);
  if (!h && m->proportional) {
    /* free flight, modal damping: XE and CE vanish, so only FE and DE
     * move (the same products as vi_ledger_rates_phase's); the exact
     * method's quadrature comes here at every node */
    int n = L->n;
    const double *Fa, *Fb, *F0;
    vi_forcing_vectors(m, VI_FORCING_MODAL, &Fa, &Fb, &F0);
    double *restrict FE = L->Q, *restrict DE = L->Q + n;
    for (int j = 0; j < n; j++) {
      double v = qd[j], F = vi_harm(p, 0, Fa[j], Fb[j], F0[j]);
      FE[j] += weight * (v * F);
      DE[j] += weight * (m->D[j + (size_t)j * (size_t)n] * v * v);
    }
    return;
  }
  vi_ledger_rates_phase(L, p, qd, h, NULL, L->R);
  for (int k = 0; k < 4 * L->n; k++) L->Q[k] += weight * L->R[k];
}

/* Modal energies (and, K != NULL, their kinetic parts) of a modal state. */
static void energies(const vi_model *m, const double *q, const double *qd,
                     double *E, double *K)
{
  for (int j = 0; j < m->n; j++) {
    if (K) K[j] = 0.5 * qd[j] * qd[j];
    E[j] = 0.5 * qd[j] * qd[j] + 0.5 * m->lambda[j] * q[j] * q[j];
  }
}

/* ... of a physical state z (q, qd: where its modes go). */
static void modal_energy(const vi_model *m, const double *z, double *q,
                         double *qd, double *E, double *K)
{
  vi_modal_project(m, z, q, qd);
  energies(m, q, qd, E, K);
}

/* An interval starts at t, Q being up to date. */
static void begin_now(vi_ledger *L, double t, const double *q,
                      const double *qd)
{
  memcpy(L->QA, L->Q, sizeof(double) * VI_LEDGER_BLOCKS * (size_t)L->n);
  energies(L->m, q, qd, L->EA, L->KA);
  L->ta = t;
}

void vi_ledger_begin_modal(vi_ledger *L, double t, const double *q,
                           const double *qd)
{
  flush(L);
  begin_now(L, t, q, qd);
}

void vi_ledger_begin(vi_ledger *L, double t, const double *z)
{
  vi_modal_project(L->m, z, L->qs, L->qds);
  vi_ledger_begin_modal(L, t, L->qs, L->qds);
}

void vi_ledger_pre_jump_modal(vi_ledger *L, const double *q, const double *qd)
{
  memcpy(L->qd, qd, sizeof(double) * (size_t)L->n); /* q'(t-) */
  energies(L->m, q, qd, L->EB, L->KB);
}

void vi_ledger_pre_jump(vi_ledger *L, const double *z)
{
  modal_energy(L->m, z, L->qs, L->qd, L->EB, L->KB); /* and q'(t-) */
}

int vi_ledger_close(vi_ledger *L, double t, const double *z, int jump,
                    double ie, int quiet)
{
  vi_modal_project(L->m, z, L->qs, L->qds);
  return vi_ledger_close_modal(L, t, L->qs, L->qds, jump, ie, quiet);
}

/* fmax (a NaN loses to a number), inline: five calls at every interval */
static inline double max_num(double a, double b)
{
  if (isnan(a)) return b;
  return a >= b || isnan(b) ? a : b;
}

int vi_ledger_close_modal(vi_ledger *L, double t, const double *q,
                          const double *qd, int jump, double ie, int quiet)
{
  int n = L->n, stop = 0;
  flush(L);
  double *I = L->QA; /* becomes the interval's integrals, FE DE XE CE NE */
  /* FE, DE: the backend's own integrals over the interval where it has
   * them, else (and the other blocks) the difference of the totals */
  int own = L->since && L->since(L->pend_data, L->ta, L->QA, L->R);
  for (int k = own ? 2 * n : 0; k < VI_LEDGER_BLOCKS * n; k++)
    I[k] = L->Q[k] - I[k];
  if (own) memcpy(I, L->R, sizeof(double) * 2 * (size_t)n);
  double scale = DBL_MIN, sum = 0.0, ea = 0.0, eb = 0.0;
  for (int j = 0; j < n; j++) {
    double FE = I[j], DE = I[n + j], XE = I[2 * n + j], CE = I[3 * n + j];
    double NE = I[4 * n + j];
    sum += L->EB[j] - L->EA[j] - FE + DE + XE - CE - NE;
    ea += L->EA[j];
    eb += L->EB[j];
    scale = max_num(scale, fabs(FE) + fabs(DE) + fabs(XE) + fabs(CE) + fabs(NE));
  }
  /* relative to the energy scale of the run so far: the micro-bounces at
   * the end of a chattering sequence carry 1e-11 of it, and their own
   * energy would turn the quadrature's absolute error into a large ratio */
  L->emax = max_num(L->emax, max_num(ea, eb));
  scale = max_num(scale, L->emax);
  double res = fabs(sum) / scale;
  /* a NaN residual must show, not vanish in a comparison */
  if (res > L->maxres || isnan(res)) L->maxres = res;
  if (jump) {
    for (int j = 0; j < n; j++) { /* qd: q'(t+) */
      L->dE[j] = 0.5 * (qd[j] * qd[j] - L->qd[j] * L->qd[j]);
      L->dEtot[j] += L->dE[j];
    }
    L->ie += ie;
  }
  if (L->fn && !quiet) {
    vi_ledger_interval iv = {n, L->ta, t, L->EA, L->EB, L->KA, L->KB,
                             I, I + n, I + 2 * (size_t)n, I + 3 * (size_t)n,
                             jump ? L->dE : NULL, jump ? ie : 0.0, res,
                             I + 4 * (size_t)n};
    stop = L->fn(&iv, L->user) != 0;
  }
  begin_now(L, t, q, qd); /* Q flushed above */
  return stop;
}

void vi_ledger_totals(vi_ledger *L, const double *z, double *E, double *FE,
                      double *DE, double *XE, double *CE, double *dE,
                      double *ie)
{
  int n = L->n;
  size_t b = sizeof(double) * (size_t)n;
  flush(L);
  if (E) modal_energy(L->m, z, L->qs, L->qds, E, NULL);
  if (FE) memcpy(FE, L->Q, b);
  if (DE) memcpy(DE, L->Q + n, b);
  if (XE) memcpy(XE, L->Q + 2 * (size_t)n, b);
  if (CE) memcpy(CE, L->Q + 3 * (size_t)n, b);
  if (dE) memcpy(dE, L->dEtot, b);
  if (ie) *ie = L->ie;
}

void vi_ledger_force_totals(vi_ledger *L, double *NE)
{
  flush(L);
  memcpy(NE, L->Q + 4 * (size_t)L->n, sizeof(double) * (size_t)L->n);
}
