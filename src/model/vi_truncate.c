/* vi_truncate.c - a model in modal coordinates truncated to its first k
 * coordinates, with or without the static residual vector at the stop
 * (vi_builders.h, vi_model_create_truncated; MODEL.md section 5): the
 * reduced models `vibroimpact truncation` measures. */
#include <math.h>
#include <stdlib.h>

#include <cblas.h>

#include "vibroimpact/vi_builders.h"
#include "vi_storage.h"

/* The columns T [nR x n]: unit vectors for the kept coordinates, then the
 * static vector c_j = psi_j / K_jj (j >= k), normalised; VI_ERR_ARG when
 * nothing lies beyond the kept modes. */
static int columns(const vi_model *R, int k, int corr, double *T)
{
  int nR = R->n;
  const double *K = R->K, *psi = vi_stop_w(R, 0);
  for (int j = 0; j < k; j++) T[j + (size_t)j * nR] = 1.0;
  if (!corr) return VI_OK;
  double nrm = 0;
  for (int j = k; j < nR; j++) {
    double lam = K[j + (size_t)j * nR];
    double c = lam > 0 ? psi[j] / lam : 0.0;
    T[j + (size_t)k * nR] = c;
    nrm += c * c;
  }
  nrm = sqrt(nrm);
  if (!(nrm > 0)) return VI_ERR_ARG; /* no residual beyond the kept modes */
  for (int j = k; j < nR; j++) T[j + (size_t)k * nR] /= nrm;
  return VI_OK;
}

/* X_n = T^T X T for X = I, K, C (BLAS: W = X T, then T^T W; K is
 * symmetric, C need not be) and the vectors T^T v.  W [nR x n] is scratch. */
static void project(const vi_model *R, int n, const double *T, double *W,
                    double *Mn, double *Kn, double *Cn, double *w, double *a,
                    double *b, double *f0)
{
  int nR = R->n;
  cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, n, n, nR, 1.0, T, nR,
              T, nR, 0.0, Mn, n);
  cblas_dsymm(CblasColMajor, CblasLeft, CblasUpper, nR, n, 1.0, R->K, nR, T,
              nR, 0.0, W, nR);
  cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, n, n, nR, 1.0, T, nR,
              W, nR, 0.0, Kn, n);
  cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, nR, n, nR, 1.0, R->C,
              nR, T, nR, 0.0, W, nR);
  cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, n, n, nR, 1.0, T, nR,
              W, nR, 0.0, Cn, n);
  const double *v[4] = {vi_stop_w(R, 0), R->a, R->b, R->f0};
  double *out[4] = {w, a, b, f0};
  for (int i = 0; i < 4; i++)
    cblas_dgemv(CblasColMajor, CblasTrans, nR, n, 1.0, T, nR, v[i], 1, 0.0,
                out[i], 1);
}

int vi_model_create_truncated(const vi_model *R, int k, int static_vector,
                              double r, const double *z, double *zt,
                              double *carried, vi_model **out)
{
  if (!out) return VI_ERR_ARG;
  *out = NULL;
  if (!R || (z && !zt)) return VI_ERR_ARG;
  if (!R->frozen) return VI_ERR_STATE;
  if (!vi_model_has_modes(R)) return VI_ERR_UNSUPPORTED; /* band: no modes */
  int nR = R->n, corr = static_vector, n = k + corr, st;
  if (k < 1 || k > nR || (corr != 0 && corr != 1) || n > nR) return VI_ERR_ARG;
  double *T = calloc(2 * (size_t)nR * n + 3 * (size_t)n * n + 4 * (size_t)n,
                     sizeof(double));
  if (!T) return VI_ERR_NOMEM;
  double *W = T + (size_t)nR * n, *Mn = W + (size_t)nR * n, *Kn = Mn + (size_t)n * n,
         *Cn = Kn + (size_t)n * n, *w = Cn + (size_t)n * n, *a = w + n,
         *b = a + n, *f0 = b + n;
  if ((st = columns(R, k, corr, T))) {
    free(T);
    return st;
  }
  project(R, n, T, W, Mn, Kn, Cn, w, a, b, f0);
  double g = cblas_ddot(n, w, 1, w, 1); /* w^T M^-1 w, M = I */
  /* the state [2 nR] projected: T^T q (T orthonormal) */
  if (z)
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, n, 2, nR, 1.0, T, nR,
                z, nR, 0.0, zt, n);
  if (carried) *carried = g;
  vi_model *m = NULL;
  if (!(st = vi_model_create(n, &m)) && !(st = vi_model_set_mass(m, Mn, n)) &&
      !(st = vi_model_set_stiffness(m, Kn, n)) &&
      !(st = vi_model_set_damping(m, Cn, n)) &&
      !(st = vi_model_set_forcing(m, R->omega_f, a, b, f0)) &&
      !(st = vi_model_set_stop(m, w, R->xsv[0], r)))
    st = vi_model_setup(m);
  free(T);
  if (st)
    vi_model_destroy(&m);
  else
    *out = m;
  return st;
}

int vi_model_modal_compliance(const vi_model *R, int stop, int k,
                              double *dynamic, double *static_part)
{
  if (!R || k < 1 || k > R->n || stop < 0 || stop >= R->ns)
    return VI_ERR_ARG;
  if (!R->frozen) return VI_ERR_STATE;
  if (!vi_model_has_modes(R)) return VI_ERR_UNSUPPORTED; /* band: no modes */
  int n = R->n;
  /* modal coordinates: M = I and K diagonal (to round-off of its scale) */
  double kmax = 0;
  for (int j = 0; j < n; j++) kmax = fmax(kmax, fabs(R->K[j + (size_t)j * n]));
  for (int q = 0; q < n; q++)
    for (int p = 0; p < n; p++) {
      double mi = R->M[p + (size_t)q * n] - (p == q);
      if (fabs(mi) > 1e-12 || (p != q && fabs(R->K[p + (size_t)q * n]) > 1e-12 * kmax))
        return VI_ERR_ARG;
    }
  const double *psi = vi_stop_w(R, stop);
  double cd = 0, cs = 0;
  for (int j = 0; j < k; j++) {
    /* MODEL.md section 5: mode j carries psi_j^2 of w^T M^-1 w and
     * psi_j^2 / omega_j^2 of w^T K^-1 w (a rigid mode with psi_j != 0
     * makes the static compliance infinite) */
    double lam = R->K[j + (size_t)j * n], p2 = psi[j] * psi[j];
    cd += p2;
    cs += lam > 0 ? p2 / lam : (p2 != 0 ? INFINITY : 0.0);
    if (dynamic) dynamic[j] = cd;
    if (static_part) static_part[j] = cs;
  }
  return VI_OK;
}
