/* vi_dense.c - dense column-major helpers (leading dimension n) and the
 * small Cholesky solves of the contact and constraint sets: shared by the
 * model, the modal analysis, the ledger, the orbits and the closed-form
 * backend. */
#include <math.h>

#include <cblas.h>

#include "vi_internal.h"

void vi_matvec(int n, const double *A, const double *x, double *y)
{
  cblas_dgemv(CblasColMajor, CblasNoTrans, n, n, 1.0, A, n, x, 1, 0.0, y, 1);
}

void vi_matvec_t(int n, const double *A, const double *x, double *y)
{
  cblas_dgemv(CblasColMajor, CblasTrans, n, n, 1.0, A, n, x, 1, 0.0, y, 1);
}

double vi_dot(int n, const double *x, const double *y)
{
  double s = 0.0;
  for (int i = 0; i < n; i++) s += x[i] * y[i];
  return s;
}

/* In-place Cholesky of the k x k matrix A (column-major, leading dimension
 * k); 0 if positive definite to round-off relative to its diagonal. */
int vi_small_cholesky(int k, double *A)
{
  double dmax = 0.0;
  for (int i = 0; i < k; i++) dmax = fmax(dmax, A[i + i * k]);
  for (int j = 0; j < k; j++) {
    double d = A[j + j * k];
    for (int p = 0; p < j; p++) d -= A[j + p * k] * A[j + p * k];
    /* a pivot lost to cancellation: G singular on this set (dependent
     * stop vectors), no unique impulses */
    if (!(d > 1e-12 * dmax)) return -1;
    d = sqrt(d);
    A[j + j * k] = d;
    for (int i = j + 1; i < k; i++) {
      double a = A[i + j * k];
      for (int p = 0; p < j; p++) a -= A[i + p * k] * A[j + p * k];
      A[i + j * k] = a / d;
    }
  }
  return 0;
}

void vi_small_solve(int k, const double *L, double *b)
{
  for (int i = 0; i < k; i++) {
    double a = b[i];
    for (int p = 0; p < i; p++) a -= L[i + p * k] * b[p];
    b[i] = a / L[i + i * k];
  }
  for (int i = k - 1; i >= 0; i--) {
    double a = b[i];
    for (int p = i + 1; p < k; p++) a -= L[p + i * k] * b[p];
    b[i] = a / L[i + i * k];
  }
}
