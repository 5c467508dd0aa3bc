/* vi_contact.c - Newton's law for several simultaneous contacts: a small
 * linear complementarity problem solved by enumerating active sets. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "vi_impact_internal.h"

static int popcount(unsigned v)
{
  int c = 0;
  for (; v; v &= v - 1) c++;
  return c;
}

/* The one home of Newton's law (MODEL.md section 11; vi_impact.h): every
 * impact of the simulation, of the public wrappers (one contact: WB 2 and
 * WB 10) and, through its linearisation Q_k (vi_impact.c), of the orbit
 * code comes here. */
int vi_contact_law(const vi_model *m, int nc, const int *idx,
                   const double *r, const double *u, double *p, double *ie)
{
  int ns = m->ns;
  if (nc > VI_CONTACT_MAX) return VI_ERR_LIMIT;
  double e[VI_CONTACT_MAX];
  double A[VI_CONTACT_MAX * VI_CONTACT_MAX], ps[VI_CONTACT_MAX];
  int act[VI_CONTACT_MAX];
  double emax = 0.0;
  for (int k = 0; k < nc; k++) {
    /* Newton: w_k.v+ <= -r_k w_k.v- on an approaching contact; a closed
     * contact that is not approaching must not start to (plastic rule) */
    double rk = r ? r[k] : m->rv[idx[k]];
    e[k] = u[k] > 0.0 ? (1.0 + rk) * u[k] : u[k];
    emax = fmax(emax, fabs(e[k]));
    p[k] = 0.0;
  }
  /* Enumerate active sets S by increasing size: on S the impulses make
   * (G P)_S = e_S, and the set fits if P_S >= 0 and y_k = (G P)_k - e_k >= 0
   * off S.  G positive definite (independent stop vectors) makes the
   * solution unique, so the first set that fits is it; the empty set
   * (nothing approaching) comes first.  A single approaching contact is
   * the set {k}: P = (1 + r) v_n / G_kk, WB 2.  2^nc sets of at most
   * nc x nc solves: hence the limit VI_CONTACT_MAX. */
  double tol = 1e-11 * emax;
  int found = 0;
  if (nc == 1) { /* the enumeration below in closed form, every impact's case:
                    {} fits iff e <= tol, else {k} with P = e / G_kk (WB 2) */
    if (!(e[0] <= tol)) {
      double g = m->G[idx[0] + (size_t)idx[0] * ns];
      p[0] = e[0] / g;
      if (!(g > 0.0) || !(p[0] >= 0.0)) return VI_ERR_NOT_CONVERGED;
    }
    found = 1;
  }
  for (int size = 0; size <= nc && !found; size++) {
    for (unsigned mask = 0; mask < (1u << nc) && !found; mask++) {
      if (popcount(mask) != size) continue;
      int k = 0;
      for (int j = 0; j < nc; j++)
        if (mask & (1u << j)) act[k++] = j;
      for (int a = 0; a < k; a++) {
        for (int b = 0; b < k; b++)
          A[a + b * k] = m->G[idx[act[a]] + (size_t)idx[act[b]] * ns];
        ps[a] = e[act[a]];
      }
      if (k == 1) {
        if (!(A[0] > 0.0)) continue; /* a zero stop vector */
        ps[0] /= A[0];               /* exactly WB 2 */
      } else if (k) {
        if (vi_small_cholesky(k, A)) continue;
        vi_small_solve(k, A, ps);
      }
      int ok = 1;
      for (int a = 0; a < k && ok; a++)
        ok = ps[a] * m->G[idx[act[a]] + (size_t)idx[act[a]] * ns] >= -tol;
      for (int j = 0; j < nc && ok; j++) {
        if (mask & (1u << j)) continue;
        double y = -e[j];
        for (int a = 0; a < k; a++)
          y += m->G[idx[j] + (size_t)idx[act[a]] * ns] * ps[a];
        ok = y >= -tol;
      }
      if (!ok) continue;
      found = 1;
      for (int a = 0; a < k; a++) p[act[a]] = fmax(ps[a], 0.0);
    }
  }
  if (!found) return VI_ERR_NOT_CONVERGED;
  /* KE- - KE+ = P.u - P.G P / 2 and (G P)_k = e_k on the active set: each
   * contact takes P_k (u_k - e_k / 2), 1/2 P_k u_k (1 - r_k) for an
   * approaching one (WB 10 for one contact) */
  for (int k = 0; k < nc && ie; k++) ie[k] = p[k] * (u[k] - 0.5 * e[k]);
  return VI_OK;
}

int vi_contact_solve_r(const vi_model *m, int nc, const int *idx,
                       const double *r, const double *v, double *vp,
                       double *P, double *vn, double *ie)
{
  int n = m->n;
  if (nc > VI_CONTACT_MAX) return VI_ERR_LIMIT;
  double u[VI_CONTACT_MAX], p[VI_CONTACT_MAX];
  for (int k = 0; k < nc; k++) u[k] = vi_dot(n, vi_stop_w(m, idx[k]), v);
  int st = vi_contact_law(m, nc, idx, r, u, p, ie);
  if (st) return st;
  if (vp != v) memcpy(vp, v, sizeof(double) * (size_t)n);
  for (int k = 0; k < nc; k++) {
    if (p[k] == 0.0) continue;
    const double *mw = vi_stop_minvw(m, idx[k]);
    for (int i = 0; i < n; i++) vp[i] -= p[k] * mw[i];
  }
  for (int k = 0; k < nc; k++) {
    if (P) P[k] = p[k];
    if (vn) vn[k] = u[k];
  }
  return VI_OK;
}

int vi_contact_solve(const vi_model *m, int nc, const int *idx,
                     const double *v, double *vp, double *P, double *vn,
                     double *ie)
{
  return vi_contact_solve_r(m, nc, idx, NULL, v, vp, P, vn, ie);
}
