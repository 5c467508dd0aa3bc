/* vi_dense_model.c - the operations of models in dense storage
 * (vi_model_create): M, C, K, M^-1 K and M^-1 C as n x n column-major
 * arrays, the modes beside them (set up by vi_dense_setup, vi_model.c).
 * The loops run over the band of M^-1 K and M^-1 C, half-bandwidth m->bw:
 * a chain with a diagonal M is tridiagonal. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <lapacke.h>

#include "vi_storage.h"

/* out [n] = M^-1 (f^(k)(t) - K x - C v), x and v read with strides incx,
 * incv: the one kernel of the model's acceleration (k = 0, the run's
 * interleaved state or the variational field's blocked one) and of its
 * rates (k = 1, 2, where the constant f0 drops: vi_harm ignores it), over
 * the band of M^-1 K and M^-1 C. */
static void dense_accel_k(const vi_model *m, const vi_phase *p, int k,
                          const double *x, size_t incx, const double *v,
                          size_t incv, double *out)
{
  int n = m->n, bw = m->bw;
  const double *fa, *fb, *f0;
  vi_forcing_vectors(m, VI_FORCING_MINV, &fa, &fb, &f0);
  for (int i = 0; i < n; i++) {
    double a = vi_harm(p, k, fa[i], fb[i], f0[i]);
    int j0 = i - bw < 0 ? 0 : i - bw, j1 = i + bw >= n ? n - 1 : i + bw;
    for (int j = j0; j <= j1; j++) {
      size_t ij = (size_t)i + (size_t)j * (size_t)n;
      a -= m->MinvK[ij] * x[(size_t)j * incx] +
           m->MinvC[ij] * v[(size_t)j * incv];
    }
    out[i] = a;
  }
}

static void dense_accel(const vi_model *m, const vi_phase *p, const double *z,
                        double *acc)
{
  dense_accel_k(m, p, 0, z, 2, z + 1, 2, acc);
}

static void dense_accel_rate(const vi_model *m, const vi_phase *p, int k,
                             const double *u, const double *ud, double *out)
{
  dense_accel_k(m, p, k, u, 1, ud, 1, out);
}

static void dense_apply(const vi_model *m, const double *x, int incx,
                        const double *v, int incv, double *y)
{
  int n = m->n, bw = m->bw;
  for (int i = 0; i < n; i++) {
    double a = 0.0;
    int j0 = i - bw < 0 ? 0 : i - bw, j1 = i + bw >= n ? n - 1 : i + bw;
    for (int j = j0; j <= j1; j++) {
      size_t ij = (size_t)i + (size_t)j * n;
      a += m->MinvK[ij] * x[(size_t)j * (size_t)incx] +
           m->MinvC[ij] * v[(size_t)j * (size_t)incv];
    }
    y[i] = a;
  }
}

static double dense_energy(const vi_model *m, const double *x, const double *v)
{
  int n = m->n;
  double e = 0.0;
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++)
      e += 0.5 * (v[i] * m->M[i + (size_t)j * n] * v[j] +
                  x[i] * m->K[i + (size_t)j * n] * x[j]);
  return e;
}

/* By the Cholesky factor of M, solved as vi_dense_setup solves it (so
 * that a vector changed later and one given before setup agree to the last
 * bit); the factor is not kept: the spare blocks are the modal setup's. */
static int dense_solve_mass(const vi_model *m, int nrhs, double *x)
{
  int n = m->n;
  double *L = malloc(sizeof(double) * (size_t)n * n);
  if (!L) return -1;
  memcpy(L, m->M, sizeof(double) * (size_t)n * n);
  lapack_int info = LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'L', n, L, n);
  if (!info)
    info = LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'L', n, nrhs, L, n, x, n);
  free(L);
  return (int)info;
}

static double *dense_matrix(const vi_model *m, int which, size_t *len)
{
  if (len) *len = (size_t)m->n * (size_t)m->n;
  return which == 0 ? m->M : which == 1 ? m->C : m->K;
}

static double dense_omega_bound(const vi_model *m)
{
  return m->omega[m->n - 1];
}

static const double *dense_minv_col(const vi_model *m, int which, int j)
{
  return (which ? m->MinvC : m->MinvK) + (size_t)j * (size_t)m->n;
}

/* Row i of the band reads z [lo_i .. lo_i + width), shifted inwards at the
 * edges, with zero coefficients where the band ends. */
static void dense_pack_rows(const vi_model *m, int width, int *lo, double *R)
{
  int n = m->n, bw = m->bw;
  for (int i = 0; i < n; i++) {
    int l = 2 * (i - bw);
    if (l > 2 * n - width) l = 2 * n - width;
    if (l < 0) l = 0;
    lo[i] = l;
    double *row = R + (size_t)i * (size_t)width;
    for (int j = 0; j < n; j++) {
      int q = 2 * j - l;
      if (q < 0 || q >= width || j < i - bw || j > i + bw) continue;
      size_t ij = (size_t)i + (size_t)j * (size_t)n;
      row[q] = -m->MinvK[ij];
      row[q + 1] = -m->MinvC[ij];
    }
  }
}

const vi_storage_ops vi_storage_dense = {
    .name = "dense",
    .modal = 1,
    .stop_vectors = 2,
    .dense_jac_max = 0x7fffffff,
    .setup = vi_dense_setup,
    .accel = dense_accel,
    .accel_rate = dense_accel_rate,
    .apply = dense_apply,
    .energy = dense_energy,
    .solve_mass = dense_solve_mass,
    .matrix = dense_matrix,
    .omega_bound = dense_omega_bound,
    .minv_col = dense_minv_col,
    .pack_rows = dense_pack_rows,
};
