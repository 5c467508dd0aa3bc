/* vi_dense.c - dense column-major helpers (leading dimension n) and the
 * modal projection of an interleaved state: shared by the model, the modal
 * analysis, the ledger, the orbits and the closed-form backend. */
#include "vi_internal.h"

void vi_matvec(int n, const double *A, const double *x, double *y)
{
  for (int i = 0; i < n; i++) y[i] = 0.0;
  for (int j = 0; j < n; j++) {
    double xj = x[j];
    const double *col = A + (size_t)j * (size_t)n;
    for (int i = 0; i < n; i++) y[i] += col[i] * xj;
  }
}

void vi_matvec_t(int n, const double *A, const double *x, double *y)
{
  for (int j = 0; j < n; j++) y[j] = vi_dot(n, A + (size_t)j * (size_t)n, x);
}

double vi_dot(int n, const double *x, const double *y)
{
  double s = 0.0;
  for (int i = 0; i < n; i++) s += x[i] * y[i];
  return s;
}

void vi_modal_project(const vi_model *m, const double *z, double *q,
                      double *qd)
{
  int n = m->n;
  for (int j = 0; j < n; j++) {
    const double *row = m->PsiTM + j; /* row j of Psi^T M, stride n */
    double a = 0.0, b = 0.0;
    for (int i = 0; i < n; i++) {
      double p = row[(size_t)i * (size_t)n];
      a += p * z[2 * (size_t)i];
      b += p * z[2 * (size_t)i + 1];
    }
    if (q) q[j] = a;
    if (qd) qd[j] = b;
  }
}
