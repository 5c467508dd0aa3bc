/* vi_ledger.c - per-mode energy ledger bookkeeping (MODEL.md section 4).
 * The integrals themselves are the backends' quadratures; this file turns
 * them into intervals, impact jumps and closure residuals. */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "vi_sim_internal.h"

void vi_ledger_modal_velocity(const vi_sim *s, const double *z, double *qd)
{
  const vi_model *m = s->m;
  int n = s->n;
  for (int j = 0; j < n; j++) {
    double a = 0.0;
    for (int i = 0; i < n; i++) a += m->PsiTM[j + (size_t)i * n] * z[2 * i + 1];
    qd[j] = a;
  }
}

void vi_ledger_rates(const vi_sim *s, double t, const double *qd,
                     double Lambda, double *rates)
{
  const vi_model *m = s->m;
  int n = s->n;
  double c = 1.0, sn = 0.0;
  if (s->harmonic) {
    c = cos(m->omega_f * t);
    sn = sin(m->omega_f * t);
  }
  double *FE = rates, *DE = rates + n, *XE = rates + 2 * n, *CE = rates + 3 * n;
  for (int j = 0; j < n; j++) {
    double F = m->Fa[j] * c + m->Fb[j] * sn + m->F0[j];
    FE[j] = qd[j] * F;                                /* WB 7 */
    DE[j] = m->D[j + (size_t)j * n] * qd[j] * qd[j]; /* WB 8 */
    CE[j] = -Lambda * m->psi[j] * qd[j];
    XE[j] = 0.0;
    if (!m->proportional) {
      double x = 0.0;
      for (int k = 0; k < n; k++)
        if (k != j) x += m->D[j + (size_t)k * n] * qd[k];
      XE[j] = qd[j] * x;
    }
  }
}

/* Modal energies and (K != NULL) their kinetic parts of a state. */
static void modal_energy(const vi_sim *s, const double *z, double *E, double *K)
{
  const vi_model *m = s->m;
  int n = s->n;
  for (int j = 0; j < n; j++) {
    double q = 0.0, qd = 0.0;
    for (int i = 0; i < n; i++) {
      double p = m->PsiTM[j + (size_t)i * n];
      q += p * z[2 * i];
      qd += p * z[2 * i + 1];
    }
    if (K) K[j] = 0.5 * qd * qd;
    E[j] = 0.5 * qd * qd + 0.5 * m->lambda[j] * q * q;
  }
}

int vi_sim_enable_ledger(vi_sim *s, int on)
{
  if (!s) return VI_ERR_ARG;
  if (on != 0 && on != 1)
    return vi_fail(s->errmsg, VI_ERR_ARG, "ledger switch %d is not 0 or 1", on);
  int n = s->n;
  vi_ledger_free(s);
  if (on) {
    s->led_block = calloc(16 * (size_t)n, sizeof(double));
    if (!s->led_block)
      return vi_fail(s->errmsg, VI_ERR_NOMEM, "out of memory for the ledger");
    double *p = s->led_block;
    s->Q = p; p += 4 * n;
    s->QA = p; p += 4 * n;
    s->EA = p; p += n;
    s->KA = p; p += n;
    s->EB = p; p += n;
    s->KB = p; p += n;
    s->dE = p; p += n;
    s->dEtot = p; p += n;
    s->qd = p; p += n;
    s->qdw = p;
    s->ledger_on = 1;
    s->led_ie = 0.0;
    s->led_maxres = 0.0;
    s->led_emax = 0.0;
    vi_ledger_begin(s);
  }
  /* the integrator must be rebuilt with (or without) the quadratures */
  if (s->be_data) s->be->destroy(s);
  s->started = 0;
  return VI_OK;
}

void vi_ledger_free(vi_sim *s)
{
  free(s->led_block);
  s->led_block = s->Q = s->QA = s->EA = s->KA = s->EB = s->KB = s->dE =
      s->dEtot = s->qd = s->qdw = NULL;
  s->ledger_on = 0;
}

int vi_sim_set_ledger_callback(vi_sim *s, vi_ledger_fn fn, void *user)
{
  if (!s) return VI_ERR_ARG;
  s->led_fn = fn;
  s->led_user = user;
  return VI_OK;
}

void vi_ledger_begin(vi_sim *s)
{
  if (!s->ledger_on) return;
  memcpy(s->QA, s->Q, sizeof(double) * 4 * s->n);
  modal_energy(s, s->z, s->EA, s->KA);
  s->led_ta = s->t;
}

void vi_ledger_pre_jump(vi_sim *s)
{
  if (!s->ledger_on) return;
  modal_energy(s, s->z, s->EB, s->KB);
  vi_ledger_modal_velocity(s, s->z, s->qd); /* q'(t-) */
}

/* Close the interval [t_a, s->t]: s->EB/KB and s->qd hold the state before
 * the jump (vi_ledger_pre_jump), s->z the state after it. */
void vi_ledger_close(vi_sim *s, int jump, double ie)
{
  if (!s->ledger_on) return;
  int n = s->n;
  double *I = s->QA; /* becomes the interval's integrals, FE DE XE CE */
  for (int k = 0; k < 4 * n; k++) I[k] = s->Q[k] - I[k];
  double scale = DBL_MIN, sum = 0.0, ea = 0.0, eb = 0.0;
  for (int j = 0; j < n; j++) {
    double FE = I[j], DE = I[n + j], XE = I[2 * n + j], CE = I[3 * n + j];
    sum += s->EB[j] - s->EA[j] - FE + DE + XE - CE;
    ea += s->EA[j];
    eb += s->EB[j];
    scale = fmax(scale, fabs(FE) + fabs(DE) + fabs(XE) + fabs(CE));
  }
  /* relative to the energy scale of the run so far: the micro-bounces at
   * the end of a chattering sequence carry 1e-11 of it, and their own
   * energy would turn the quadrature's absolute error into a large ratio */
  s->led_emax = fmax(s->led_emax, fmax(ea, eb));
  scale = fmax(scale, s->led_emax);
  double res = fabs(sum) / scale;
  if (res > s->led_maxres) s->led_maxres = res;
  if (jump) {
    vi_ledger_modal_velocity(s, s->z, s->qdw); /* q'(t+) */
    for (int j = 0; j < n; j++) {
      s->dE[j] = 0.5 * (s->qdw[j] * s->qdw[j] - s->qd[j] * s->qd[j]);
      s->dEtot[j] += s->dE[j];
    }
    s->led_ie += ie;
  }
  if (s->led_fn && !vi_sim_user_stopped(s)) {
    vi_ledger_interval iv = {n, s->led_ta, s->t, s->EA, s->EB, s->KA, s->KB,
                             I, I + n, I + 2 * n, I + 3 * n,
                             jump ? s->dE : NULL, jump ? ie : 0.0, res};
    if (s->led_fn(&iv, s->led_user)) s->stop = 1;
  }
  vi_ledger_begin(s);
}

int vi_sim_get_ledger(const vi_sim *s, double *E, double *FE, double *DE,
                      double *XE, double *CE, double *dE, double *ie)
{
  if (!s) return VI_ERR_ARG;
  if (!s->ledger_on)
    return VI_ERR_STATE;
  int n = s->n;
  size_t b = sizeof(double) * n;
  if (E) modal_energy(s, s->z, E, NULL);
  if (FE) memcpy(FE, s->Q, b);
  if (DE) memcpy(DE, s->Q + n, b);
  if (XE) memcpy(XE, s->Q + 2 * n, b);
  if (CE) memcpy(CE, s->Q + 3 * n, b);
  if (dE) memcpy(dE, s->dEtot, b);
  if (ie) *ie = s->led_ie;
  return VI_OK;
}

double vi_sim_ledger_max_residual(const vi_sim *s)
{
  return s && s->ledger_on ? s->led_maxres : 0.0;
}
