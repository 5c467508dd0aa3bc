/* vi_modal.c - generalised eigenproblem K psi = lambda M psi (LAPACK dsygvd,
 * dsyevd where M is diagonal), modal damping, forcing and impact vector
 * (MODEL.md section 3): the modes, on which the exact flow (vi_flow.c) is
 * built.  The products are BLAS-3
 * (issue 21 item 5): the set-up costs a few dsygvd's, not n^3 dot products. */
#include <float.h>
#include <math.h>
#include <string.h>

#include <cblas.h>
#include <lapacke.h>

#include "vi_model_internal.h"

/* Off-diagonal modal damping below this fraction of the largest entry is
 * round-off: the damping is proportional and modes decouple (WB 4). */
#define VI_PROP_TOL 1e-10
/* Relative tolerance of semidefiniteness, as vi_model.c's VI_PSD_TOL. */
#define VI_MODAL_PSD_TOL 1e-12

/* C is PSD iff D = Psi^T C Psi is (a congruence, Psi non-singular), so the
 * test runs on D: its diagonal when the damping is proportional, else its
 * eigenvalues (dsyev on a copy in work). */
static int check_damping(vi_model *m, double *work)
{
  int n = m->n;
  double dmin = HUGE_VAL, big = 0.0;
  if (m->proportional) {
    for (int j = 0; j < n; j++) {
      double d = m->D[j + (size_t)j * n];
      dmin = fmin(dmin, d);
      big = fmax(big, fabs(d));
    }
  } else {
    memcpy(work, m->D, sizeof(double) * (size_t)n * n);
    lapack_int info = LAPACKE_dsyev(LAPACK_COL_MAJOR, 'N', 'L', n, work, n,
                                    m->zeta);
    if (info != 0)
      return vi_fail(m->errmsg, VI_ERR_LAPACK, "dsyev on the modal damping "
                     "failed (info %d)", (int)info);
    dmin = m->zeta[0];
    big = fmax(fabs(m->zeta[0]), fabs(m->zeta[n - 1]));
  }
  if (dmin < -VI_MODAL_PSD_TOL * big)
    return vi_fail(m->errmsg, VI_ERR_NOT_PSD,
                   "C is not positive semidefinite: the modal damping "
                   "Psi^T C Psi has eigenvalue %.6g (largest magnitude %.6g)",
                   dmin, big);
  return VI_OK;
}

/* A rigid-body mode has K psi at round-off row by row: max_i |K psi|_i /
 * (|K| |psi|)_i at a few eps (see vi_eigs.c).  Asked only of the modes
 * whose eigenvalue is within dsygvd's absolute error of zero. */
#define VI_MODAL_RIGID 1e-11
static double rigidity(int n, const double *K, const double *z)
{
  double r = 0.0, amax = 0.0;
  for (int i = 0; i < n; i++) {
    double y = 0.0, a = 0.0;
    for (int j = 0; j < n; j++) { /* row i of the symmetric K = column i */
      double v = K[j + (size_t)i * n] * z[j];
      y += v;
      a += fabs(v);
    }
    amax = fmax(amax, a);
    if (a > 0.0) r = fmax(r, fabs(y) / a);
  }
  return amax > 0.0 ? r : 0.0;
}

int vi_mass_lumped(int n, const double *M)
{
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++)
      if (i == j ? !(M[i + (size_t)j * n] > 0.0) : M[i + (size_t)j * n] != 0.0)
        return 0;
  return 1;
}

/* K z = lambda M z, itype 1 (Z^T M Z = I), eigenvalues ascending, Z into Kw
 * (n x n); diag: M is lumped (then vi_eig_lumped); Mw: n x n workspace. */
static lapack_int eigen(const vi_model *m, int diag, double *Kw, double *Mw)
{
  int n = m->n;
  size_t nn = (size_t)n * n;
  memcpy(Kw, m->K, sizeof(double) * nn);
  if (!diag) {
    memcpy(Mw, m->M, sizeof(double) * nn);
    return LAPACKE_dsygvd(LAPACK_COL_MAJOR, 1, 'V', 'L', n, Kw, n, Mw, n,
                          m->lambda);
  }
  return vi_eig_lumped(n, Kw, n, m->M, n + 1, m->lambda, Mw);
}

int vi_eig_lumped(int n, double *A, int lda, const double *mass, int inc,
                  double *lam, double *s)
{
  for (int i = 0; i < n; i++) s[i] = 1.0 / sqrt(mass[(size_t)i * inc]);
  for (int i = 0; i < n; i++) { /* S K S: column i, then row i, by S_ii */
    cblas_dscal(n, s[i], A + (size_t)i * lda, 1);
    cblas_dscal(n, s[i], A + i, lda);
  }
  lapack_int info = LAPACKE_dsyevd(LAPACK_COL_MAJOR, 'V', 'L', n, A, lda, lam);
  for (int i = 0; i < n && info == 0; i++) cblas_dscal(n, s[i], A + i, lda); /* Z = S Y */
  return (int)info;
}

int vi_modal_setup(vi_model *m, int c_zero, int diag)
{
  int n = m->n;
  size_t nn = (size_t)n * n;
  double *Kw = m->D + nn, *Mw = Kw + nn; /* setup workspace blocks */
  lapack_int info = eigen(m, diag, Kw, Mw);
  if (info != 0)
    return vi_fail(m->errmsg, VI_ERR_LAPACK, "%s failed (info %d)",
                   diag ? "dsyevd" : "dsygvd", (int)info);
  for (int j = 0; j < n; j++)
    if (!isfinite(m->lambda[j]))
      return vi_fail(m->errmsg, VI_ERR_NONFINITE, "the modal analysis gives "
                     "omega^2 = %g for mode %d: M and K are beyond what "
                     "double precision resolves (rescale their units)",
                     m->lambda[j], j + 1);
  /* K is PSD iff M^-1 K's eigenvalues are >= 0 (Sylvester's inertia): the
   * check costs nothing beyond the eigenproblem */
  double big = fmax(fabs(m->lambda[0]), fabs(m->lambda[n - 1]));
  if (m->lambda[0] < -VI_MODAL_PSD_TOL * big)
    return vi_fail(m->errmsg, VI_ERR_NOT_PSD,
                   "K is not positive semidefinite: smallest eigenvalue %.6g "
                   "of M^-1 K (largest magnitude %.6g)", m->lambda[0], big);
  for (int j = 0; j < n; j++) {
    double *col = Kw + (size_t)j * n;
    /* deterministic sign: the largest-magnitude entry positive */
    int imax = 0;
    for (int i = 1; i < n; i++)
      if (fabs(col[i]) > fabs(col[imax]) * (1.0 + 1e-12)) imax = i;
    double s = col[imax] < 0.0 ? -1.0 : 1.0;
    for (int i = 0; i < n; i++) m->Psi[i + (size_t)j * n] = s * col[i];
    /* an eigenvalue within dsygvd's absolute error of zero, a few n eps
     * lambda_max, is a rigid mode's round-off (a free FE bar's came out at
     * omega ~ 0.5 with lambda_max 1e15, bending its rigid translation by
     * omega^2 t^2 / 2) if K psi is at round-off too; otherwise it is an
     * elastic mode the solver cannot resolve, which must not become 0 */
    if (m->lambda[j] < 4.0 * n * DBL_EPSILON * m->lambda[n - 1]) {
      if (rigidity(n, m->K, m->Psi + (size_t)j * n) <= VI_MODAL_RIGID)
        m->lambda[j] = 0.0;
      else if (!(m->lambda[j] > 0.0))
        return vi_fail(m->errmsg, VI_ERR_NOT_PSD, "mode %d: omega^2 = %.3g "
                       "is within round-off of 0 (largest %.3g) but K psi "
                       "is not: M and K span more orders than double "
                       "precision resolves (rescale the model)", j + 1,
                       m->lambda[j], m->lambda[n - 1]);
    }
    m->omega[j] = sqrt(m->lambda[j]);
  }
  /* PsiTM = Psi^T M (x -> q); a diagonal M scales Psi^T's columns */
  if (diag) {
    for (int i = 0; i < n; i++) {
      cblas_dcopy(n, m->Psi + i, n, m->PsiTM + (size_t)i * n, 1);
      cblas_dscal(n, m->M[i + (size_t)i * n], m->PsiTM + (size_t)i * n, 1);
    }
  } else {
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, n, n, n, 1.0, m->Psi,
                n, m->M, n, 0.0, m->PsiTM, n);
  }
  /* D = Psi^T (C Psi), made exactly symmetric */
  if (c_zero) {
    memset(m->D, 0, sizeof(double) * nn);
  } else {
    cblas_dsymm(CblasColMajor, CblasLeft, CblasLower, n, n, 1.0, m->C, n,
                m->Psi, n, 0.0, Mw, n);
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, n, n, n, 1.0, m->Psi,
                n, Mw, n, 0.0, m->D, n);
    for (int j = 0; j < n; j++)
      for (int i = j + 1; i < n; i++)
        m->D[i + (size_t)j * n] = m->D[j + (size_t)i * n] =
            0.5 * (m->D[i + (size_t)j * n] + m->D[j + (size_t)i * n]);
  }
  double dmax = 0.0, offmax = 0.0;
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      double v = fabs(m->D[i + (size_t)j * n]);
      dmax = fmax(dmax, v);
      if (i != j) offmax = fmax(offmax, v);
    }
  m->proportional = offmax <= VI_PROP_TOL * dmax;
  if (!c_zero) {
    int st = check_damping(m, Kw);
    if (st) return st;
  }
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

void vi_modal_project(const vi_model *m, const double *z, double *q,
                      double *qd)
{
  /* z interleaves (x_i, v_i): stride 2 picks either */
  int n = m->n;
  if (q)
    cblas_dgemv(CblasColMajor, CblasNoTrans, n, n, 1.0, m->PsiTM, n, z, 2,
                0.0, q, 1);
  if (qd)
    cblas_dgemv(CblasColMajor, CblasNoTrans, n, n, 1.0, m->PsiTM, n, z + 1,
                2, 0.0, qd, 1);
}
