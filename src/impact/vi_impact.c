/* vi_impact.c - the public face of Newton's law (WB 2, WB 10, WB 13) and
 * its linearisation for the orbit code (vi_impact_internal.h).  The law
 * itself is solved in one place, vi_contact_solve_r (vi_contact.c): one
 * contact is its case nc = 1. */
#include <math.h>
#include <string.h>

#include <cblas.h>

#include "vi_impact_internal.h"

int vi_impact_apply_r(const vi_model *m, double r, const double *v_minus,
                      double *v_plus, double *vn, double *ie)
{
  if (!m || !v_minus || !v_plus) return VI_ERR_ARG;
  if (!m->frozen) return VI_ERR_STATE;
  if (!(r >= 0.0 && r <= 1.0)) return VI_ERR_RESTITUTION;
  if (v_plus != v_minus && vi_overlap(v_minus, v_plus, m->n)) return VI_ERR_ARG;
  /* "the stop" of the single-stop API is stop 0 */
  const int k = 0;
  return vi_contact_solve_r(m, 1, &k, &r, v_minus, v_plus, NULL, vn, ie);
}

int vi_impact_apply(const vi_model *m, const double *v_minus, double *v_plus,
                    double *vn, double *ie)
{
  if (!m) return VI_ERR_ARG;
  if (!m->frozen) return VI_ERR_STATE;
  return vi_impact_apply_r(m, m->rv[0], v_minus, v_plus, vn, ie);
}

int vi_impact_apply_multi(const vi_model *m, int nc, const int *stops,
                          const double *v_minus, double *v_plus, double *P,
                          double *ie)
{
  if (!m || !stops || !v_minus || !v_plus || nc < 1) return VI_ERR_ARG;
  if (!m->frozen) return VI_ERR_STATE;
  if (nc > VI_CONTACT_MAX) return VI_ERR_LIMIT;
  for (int k = 0; k < nc; k++) {
    if (stops[k] < 0 || stops[k] >= m->ns) return VI_ERR_ARG;
    for (int j = 0; j < k; j++)
      if (stops[j] == stops[k]) return VI_ERR_ARG;
  }
  if (v_plus != v_minus && vi_overlap(v_minus, v_plus, m->n)) return VI_ERR_ARG;
  /* P and ie are written while v_minus is read and v_plus written */
  size_t n = (size_t)m->n, k = (size_t)nc;
  if (vi_overlap2(P, k, v_minus, n) || vi_overlap2(P, k, v_plus, n) ||
      vi_overlap2(ie, k, v_minus, n) || vi_overlap2(ie, k, v_plus, n) ||
      vi_overlap(P, ie, nc))
    return VI_ERR_ARG;
  return vi_contact_solve(m, nc, stops, v_minus, v_plus, P, NULL, ie);
}

int vi_restitution_from_energy(double re, double ke_i, double *r)
{
  if (!r) return VI_ERR_ARG;
  if (!(ke_i > 0.0) || !(re >= 0.0) || re > ke_i || !isfinite(ke_i))
    return VI_ERR_ARG;
  *r = sqrt(1.0 - re / ke_i); /* WB 13 */
  return VI_OK;
}

/* ---- the linearisation: Q_k = I - c_k M^-1 w_k w_k^T ------------------- */

/* c_k = (1 + r_k) / G_kk: the impulse per unit approach velocity (WB 2) */
static double q_coef(const vi_model *m, int k)
{
  return (1.0 + m->rv[k]) / m->G[k + (size_t)k * m->ns];
}

void vi_impact_q_left(const vi_model *m, int k, int nrhs, double *V, int ldv,
                      double *work)
{
  int n = m->n;
  /* work = V^T w_k, then V -= c_k (M^-1 w_k) work^T */
  cblas_dgemv(CblasColMajor, CblasTrans, n, nrhs, 1.0, V, ldv,
              vi_stop_w(m, k), 1, 0.0, work, 1);
  cblas_dger(CblasColMajor, n, nrhs, -q_coef(m, k), vi_stop_minvw(m, k), 1,
             work, 1, V, ldv);
}

void vi_impact_q_right(const vi_model *m, int k, int nr, double *A, int lda,
                       double *work)
{
  int n = m->n;
  /* work = A M^-1 w_k, then A -= c_k work w_k^T */
  cblas_dgemv(CblasColMajor, CblasNoTrans, nr, n, 1.0, A, lda,
              vi_stop_minvw(m, k), 1, 0.0, work, 1);
  cblas_dger(CblasColMajor, nr, n, -q_coef(m, k), work, 1, vi_stop_w(m, k),
             1, A, lda);
}

void vi_impact_q_dr(const vi_model *m, int k, const double *v, double *out)
{
  int n = m->n;
  double c = -vi_dot(n, vi_stop_w(m, k), v) / m->G[k + (size_t)k * m->ns];
  const double *Mw = vi_stop_minvw(m, k);
  for (int i = 0; i < n; i++) out[i] = c * Mw[i];
}

/* ---- the saltation matrix S = R + d g^T / v_n (MODEL.md section 13) ---- */

void vi_impact_salt_jump(const vi_model *m, int k, const double *fm,
                         const double *fp, double *d, double *work)
{
  int n = m->n, n2 = 2 * n;
  if (d != fm) memcpy(d, fm, sizeof(double) * (size_t)n2);
  vi_impact_q_left(m, k, 1, d + n, n, work); /* R f- */
  for (int i = 0; i < n2; i++) d[i] = fp[i] - d[i];
}

void vi_impact_salt_apply(const vi_model *m, int k, double vn,
                          const double *d, int nrhs, double *Z, int ldz,
                          double *work)
{
  int n = m->n;
  /* work = (g^T Z) / v_n from the positions before R acts on the
   * velocities, then Z <- R Z + d work^T */
  cblas_dgemv(CblasColMajor, CblasTrans, n, nrhs, 1.0 / vn, Z, ldz,
              vi_stop_w(m, k), 1, 0.0, work, 1);
  vi_impact_q_left(m, k, nrhs, Z + n, ldz, work + nrhs);
  cblas_dger(CblasColMajor, 2 * n, nrhs, 1.0, d, 1, work, 1, Z, ldz);
}

void vi_impact_salt_matrix(const vi_model *m, int k, double vn,
                           const double *d, double *S)
{
  int n = m->n, n2 = 2 * n;
  memset(S, 0, sizeof(double) * (size_t)n2 * (size_t)n2);
  for (int i = 0; i < n2; i++) S[i + (size_t)i * n2] = 1.0;
  /* R = diag(I, Q_k): the velocity block I - c_k M^-1 w_k w_k^T */
  cblas_dger(CblasColMajor, n, n, -q_coef(m, k), vi_stop_minvw(m, k), 1,
             vi_stop_w(m, k), 1, S + n + (size_t)n * n2, n2);
  /* + d g^T / v_n: g = (w_k, 0) touches the position columns only */
  cblas_dger(CblasColMajor, n2, n, 1.0 / vn, d, 1, vi_stop_w(m, k), 1, S,
             n2);
}
