/* vi_modal.c - generalised eigenproblem K psi = lambda M psi (LAPACK dsygvd),
 * modal damping, forcing and impact vector (MODEL.md section 3): the modes,
 * on which the exact flow (vi_flow.c) is built. */
#include <math.h>
#include <string.h>

#include <lapacke.h>

#include "vi_internal.h"

/* Off-diagonal modal damping below this fraction of the largest entry is
 * round-off: the damping is proportional and modes decouple (WB 4). */
#define VI_PROP_TOL 1e-10

int vi_modal_setup(vi_model *m)
{
  int n = m->n;
  size_t nn = (size_t)n * n;
  double *Kw = m->D + nn, *Mw = Kw + nn; /* setup workspace blocks */
  memcpy(Kw, m->K, sizeof(double) * nn);
  memcpy(Mw, m->M, sizeof(double) * nn);
  /* itype 1: K z = lambda M z with Z^T M Z = I, eigenvalues ascending */
  lapack_int info = LAPACKE_dsygvd(LAPACK_COL_MAJOR, 1, 'V', 'L', n, Kw, n, Mw,
                                   n, m->lambda);
  if (info != 0)
    return vi_fail(m->errmsg, VI_ERR_LAPACK, "dsygvd failed (info %d)",
                   (int)info);
  for (int j = 0; j < n; j++) {
    double *col = Kw + (size_t)j * n;
    /* deterministic sign: the largest-magnitude entry positive */
    int imax = 0;
    for (int i = 1; i < n; i++)
      if (fabs(col[i]) > fabs(col[imax]) * (1.0 + 1e-12)) imax = i;
    double s = col[imax] < 0.0 ? -1.0 : 1.0;
    for (int i = 0; i < n; i++) m->Psi[i + (size_t)j * n] = s * col[i];
    /* K is PSD, so a negative eigenvalue is round-off of a rigid mode */
    if (m->lambda[j] < 0.0) m->lambda[j] = 0.0;
    m->omega[j] = sqrt(m->lambda[j]);
  }
  /* PsiTM = Psi^T M (x -> q), D = Psi^T C Psi; Mw holds C Psi, M Psi */
  for (int j = 0; j < n; j++) {
    vi_matvec(n, m->C, m->Psi + (size_t)j * n, Mw + (size_t)j * n);
    vi_matvec(n, m->M, m->Psi + (size_t)j * n, Kw + (size_t)j * n);
  }
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      m->D[i + (size_t)j * n] =
          vi_dot(n, m->Psi + (size_t)i * n, Mw + (size_t)j * n);
      /* (Psi^T M)_{ij} = (M Psi)_{ji} since M is symmetric */
      m->PsiTM[i + (size_t)j * n] = Kw[j + (size_t)i * n];
    }
  double dmax = 0.0, offmax = 0.0;
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      double v = fabs(m->D[i + (size_t)j * n]);
      dmax = fmax(dmax, v);
      if (i != j) offmax = fmax(offmax, v);
    }
  m->proportional = offmax <= VI_PROP_TOL * dmax;
  vi_matvec_t(n, m->Psi, m->w, m->psi);
  vi_matvec_t(n, m->Psi, m->a, m->Fa);
  vi_matvec_t(n, m->Psi, m->b, m->Fb);
  vi_matvec_t(n, m->Psi, m->f0, m->F0);

  /* the exact flow built on these modes is a layer of its own
   * (vi_flow_internal.h) */
  for (int j = 0; j < n; j++) {
    double d = m->D[j + (size_t)j * n];
    m->zeta[j] = m->omega[j] > 0.0 ? d / (2.0 * m->omega[j]) : 0.0;
  }
  return VI_OK;
}
