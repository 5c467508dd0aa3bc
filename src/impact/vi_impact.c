/* vi_impact.c - Newton restitution law (WB 2), energy loss (WB 10), WB 13. */
#include <math.h>

#include "vi_internal.h"

int vi_impact_apply_r(const vi_model *m, double r, const double *v_minus,
                      double *v_plus, double *vn, double *ie)
{
  if (!m || !v_minus || !v_plus) return VI_ERR_ARG;
  if (!m->frozen) return VI_ERR_STATE;
  if (!(r >= 0.0 && r <= 1.0)) return VI_ERR_RESTITUTION;
  int n = m->n;
  double u = vi_dot(n, m->w, v_minus);
  if (vn) *vn = u;
  if (u <= 0.0) { /* separating or tangent: no impulse */
    for (int i = 0; i < n; i++) v_plus[i] = v_minus[i];
    if (ie) *ie = 0.0;
    return VI_OK;
  }
  /* WB 2: rank-one M^-1 w update, so that w.v+ = -r u */
  double s = (1.0 + r) * u / m->wMw;
  for (int i = 0; i < n; i++) v_plus[i] = v_minus[i] - s * m->Minv_w[i];
  if (ie) *ie = 0.5 * u * u * (1.0 - r * r) / m->wMw; /* WB 10 */
  return VI_OK;
}

int vi_impact_apply(const vi_model *m, const double *v_minus, double *v_plus,
                    double *vn, double *ie)
{
  if (!m) return VI_ERR_ARG;
  return vi_impact_apply_r(m, m->r, v_minus, v_plus, vn, ie);
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
