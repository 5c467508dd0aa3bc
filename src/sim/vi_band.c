/* vi_band.c - the integrator's Jacobian of a band-storage model (the
 * model side, its set-up and acceleration, is src/model/vi_band_model.c):
 * band or dense SUNMatrix, projected while stops are held. */
#include <string.h>

#include <sunmatrix/sunmatrix_band.h>
#include <sunmatrix/sunmatrix_dense.h>

#include "vi_band_internal.h"
#include "vi_sim_state.h"

/* Column jz of the Jacobian [[0, I], [-M^-1 K, -M^-1 C]] (interleaved)
 * on the band [j - bw, j + bw] of rows, projected while sticking.  With a
 * band matrix the model has a diagonal M and every stop acts on one
 * coordinate p_k (cvode's use_band), so the projection
 * a -= M^-1 W_S G_SS^-1 W_S^T a touches the rows p_k only. */
int vi_band_jac(vi_sim *s, SUNMatrix J)
{
  const vi_model *m = s->m;
  int n = s->n, kd = m->kd, w = 2 * kd + 1, ns = s->nstick;
  if (SUNMatGetID(J) != SUNMATRIX_BAND) {
    /* small models: full columns by band products, O(n^2 kd) */
    double *e = s->zs, *col = s->zs + n, zero = 0.0;
    memset(e, 0, sizeof(double) * (size_t)n);
    for (int jz = 0; jz < 2 * n; jz++) {
      int j = jz / 2;
      e[j] = 1.0;
      if (jz % 2) m->ops->apply(m, &zero, 0, e, 1, col);
      else m->ops->apply(m, e, 1, &zero, 0, col);
      e[j] = 0.0;
      for (int i = 0; i < n; i++) col[i] = -col[i];
      if (s->sticking) vi_sim_constrain(s, col, NULL);
      for (int i = 0; i < n; i++) SM_ELEMENT_D(J, 2 * i + 1, jz) = col[i];
      if (jz % 2) SM_ELEMENT_D(J, jz - 1, jz) = 1.0;
    }
    return 0;
  }
  int bw = m->bw, p[VI_CONTACT_MAX];
  double wp[VI_CONTACT_MAX], mwp[VI_CONTACT_MAX];
  for (int q = 0; q < ns; q++) {
    const double *wk = vi_stop_w(m, s->stick_k[q]);
    int i = 0;
    while (i < n - 1 && wk[i] == 0.0) i++;
    p[q] = i;
    wp[q] = wk[i];
    mwp[q] = vi_stop_minvw(m, s->stick_k[q])[i];
  }
  for (int jz = 0; jz < 2 * n; jz++) {
    int j = jz / 2;
    const double *R = jz % 2 ? m->CR : m->KR;
    int i0 = j - bw < 0 ? 0 : j - bw, i1 = j + bw >= n ? n - 1 : j + bw;
    for (int i = i0; i <= i1; i++)
      SM_ELEMENT_B(J, 2 * i + 1, jz) = -R[(size_t)i * w + (j - i + kd)];
    if (jz % 2) SM_ELEMENT_B(J, jz - 1, jz) = 1.0;
    if (!ns) continue;
    double b[VI_CONTACT_MAX];
    int any = 0;
    for (int q = 0; q < ns; q++) {
      int in = p[q] >= i0 && p[q] <= i1;
      b[q] = in ? wp[q] * SM_ELEMENT_B(J, 2 * p[q] + 1, jz) : 0.0;
      any |= b[q] != 0.0;
    }
    if (!any) continue;
    if (ns == 1) b[0] /= m->G[s->stick_k[0] * (size_t)(m->ns + 1)];
    else vi_small_solve(ns, s->stick_L, b);
    for (int q = 0; q < ns; q++)
      if (p[q] >= i0 && p[q] <= i1)
        SM_ELEMENT_B(J, 2 * p[q] + 1, jz) -= b[q] * mwp[q];
  }
  return 0;
}
