/* vi_truncate.c - a model in modal coordinates truncated to its first k
 * coordinates, with or without the static residual vector at the stop
 * (vi_builders.h, vi_model_create_truncated; MODEL.md section 5): the
 * reduced models `vibroimpact truncation` measures. */
#include <math.h>
#include <stdlib.h>

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

/* X_n = T^T X T for X = I, K, C and the vectors T^T v.  Small dense
 * matrices (n <= a few hundred) whose T is mostly unit columns: plain
 * loops that skip T's zeros. */
static void project(const vi_model *R, int n, const double *T, double *Mn,
                    double *Kn, double *Cn, double *w, double *a, double *b,
                    double *f0)
{
  int nR = R->n;
  const double *K = R->K, *C = R->C;
  for (int p = 0; p < n; p++) {
    for (int q = 0; q < n; q++) {
      double sm = 0, sk = 0, sc = 0;
      for (int i = 0; i < nR; i++) {
        double ti = T[i + (size_t)p * nR];
        if (ti == 0) continue;
        sm += ti * T[i + (size_t)q * nR];
        for (int j = 0; j < nR; j++) {
          double tj = T[j + (size_t)q * nR];
          if (tj == 0) continue;
          sk += ti * K[i + (size_t)j * nR] * tj;
          sc += ti * C[i + (size_t)j * nR] * tj;
        }
      }
      Mn[p + (size_t)q * n] = sm;
      Kn[p + (size_t)q * n] = sk;
      Cn[p + (size_t)q * n] = sc;
    }
    double sw = 0, sa = 0, sb = 0, sf = 0;
    for (int i = 0; i < nR; i++) {
      double ti = T[i + (size_t)p * nR];
      sw += ti * vi_stop_w(R, 0)[i];
      sa += ti * R->a[i];
      sb += ti * R->b[i];
      sf += ti * R->f0[i];
    }
    w[p] = sw;
    a[p] = sa;
    b[p] = sb;
    f0[p] = sf;
  }
}

int vi_model_create_truncated(const vi_model *R, int k, int static_vector,
                              double r, const double *z, double *zt,
                              double *carried, vi_model **out)
{
  if (!out) return VI_ERR_ARG;
  *out = NULL;
  if (!R || (z && !zt)) return VI_ERR_ARG;
  if (!R->frozen) return VI_ERR_STATE;
  if (!R->ops->modal) return VI_ERR_UNSUPPORTED; /* band: no modes */
  int nR = R->n, corr = static_vector, n = k + corr, st;
  if (k < 1 || k > nR || (corr != 0 && corr != 1) || n > nR) return VI_ERR_ARG;
  double *T = calloc((size_t)nR * n + 3 * (size_t)n * n + 4 * (size_t)n,
                     sizeof(double));
  if (!T) return VI_ERR_NOMEM;
  double *Mn = T + (size_t)nR * n, *Kn = Mn + (size_t)n * n,
         *Cn = Kn + (size_t)n * n, *w = Cn + (size_t)n * n, *a = w + n,
         *b = a + n, *f0 = b + n;
  if ((st = columns(R, k, corr, T))) {
    free(T);
    return st;
  }
  project(R, n, T, Mn, Kn, Cn, w, a, b, f0);
  double g = 0;
  for (int p = 0; p < n; p++) g += w[p] * w[p]; /* w^T M^-1 w, M = I */
  /* the state [2 nR] projected: T^T q (T orthonormal) */
  for (int h = 0; z && h < 2; h++)
    for (int p = 0; p < n; p++) {
      double sum = 0;
      for (int i = 0; i < nR; i++) sum += T[i + (size_t)p * nR] * z[i + (size_t)h * nR];
      zt[p + (size_t)h * n] = sum;
    }
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
