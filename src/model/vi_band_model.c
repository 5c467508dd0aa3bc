/* vi_band_model.c - models in band storage (vi_model_create_band): setup,
 * the acceleration M^-1 (f - C v - K x), its rates and the energy in O(n kd)
 * per evaluation, so that a long chain runs in memory and time linear in
 * n (the integrator's Jacobian is src/sim/vi_band.c).  There are no modes: the
 * ledger, the closed form and the orbits need them and refuse such models.
 *
 * Storage is LAPACK's symmetric band 'U' form [(kd+1) x n] as set; for the
 * hot loops the rows of K and C (of M^-1 K and M^-1 C when M is diagonal,
 * a row scaling) are kept contiguous, [n x (2kd+1)].  A banded M that is
 * not diagonal is applied by a band Cholesky solve per evaluation
 * (dpbtrs, O(n kdm)): M^-1 K would be dense.
 *
 * The operations are the model's storage table vi_storage_band
 * (vi_storage.h), set by vi_model_create_band. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <lapacke.h>

#include "vi_storage.h"

/* A PSD matrix plus this fraction of its infinity norm (a bound of its
 * largest eigenvalue) has a band Cholesky factor; an indefinite one with a
 * negative eigenvalue beyond it has none.  The backward error of band
 * Cholesky grows with kd, not n, so the shift stays far above round-off. */
#define VI_BAND_PSD_SHIFT 1e-11

/* Entry (i, j), |i - j| <= kd, of a symmetric matrix in 'U' band form. */
static inline double sb_get(const double *AB, int kd, int ldb, int i, int j)
{
  return i <= j ? AB[kd + i - j + (size_t)j * ldb]
                : AB[kd + j - i + (size_t)i * ldb];
}

/* Largest |i - j| with a non-zero entry of a 'U' band matrix. */
static int band_width(const double *AB, int n, int kd, int ldb)
{
  for (int d = kd; d > 0; d--)
    for (int j = d; j < n; j++)
      if (AB[kd - d + (size_t)j * ldb] != 0.0) return d;
  return 0;
}

/* Infinity norm of a symmetric 'U' band matrix. */
static double band_norm(const double *AB, int n, int kd, int ldb)
{
  double nm = 0.0;
  for (int i = 0; i < n; i++) {
    double r = 0.0;
    int j0 = i - kd < 0 ? 0 : i - kd, j1 = i + kd >= n ? n - 1 : i + kd;
    for (int j = j0; j <= j1; j++) r += fabs(sb_get(AB, kd, ldb, i, j));
    nm = fmax(nm, r);
  }
  return nm;
}

/* K (or C) positive semidefinite: K + shift |K| I has a Cholesky factor. */
static int check_psd_band(vi_model *m, const char *name, const double *AB,
                          double *work)
{
  int n = m->n, kd = m->kd, ldb = m->ldb;
  double nm = band_norm(AB, n, kd, ldb);
  if (nm == 0.0) return VI_OK;
  memcpy(work, AB, sizeof(double) * (size_t)ldb * n);
  for (int j = 0; j < n; j++) work[kd + (size_t)j * ldb] += VI_BAND_PSD_SHIFT * nm;
  lapack_int info = LAPACKE_dpbtrf(LAPACK_COL_MAJOR, 'U', n, kd, work, ldb);
  if (info < 0)
    return vi_fail(m->errmsg, VI_ERR_LAPACK, "dpbtrf on %s failed (info %d)",
                   name, (int)info);
  if (info > 0)
    return vi_fail(m->errmsg, VI_ERR_NOT_PSD,
                   "%s is not positive semidefinite: %s + %g |%s| I has no "
                   "Cholesky factor (column %d)", name, name,
                   VI_BAND_PSD_SHIFT, name, (int)info);
  return VI_OK;
}

/* x := M^-1 x for nrhs columns [n x nrhs] (leading dimension n). */
static int minv(const vi_model *m, int nrhs, double *x)
{
  int n = m->n;
  if (m->kdm == 0) {
    for (int k = 0; k < nrhs; k++)
      for (int i = 0; i < n; i++) x[i + (size_t)k * n] *= m->LB[i];
    return 0;
  }
  return (int)LAPACKE_dpbtrs_work(LAPACK_COL_MAJOR, 'U', n, m->kdm, nrhs,
                                  m->LB, m->kdm + 1, x, n);
}

/* The band setup: band Cholesky of M, positive semidefiniteness of K and
 * C by shifted band Cholesky, M^-1 of the forcing and the stops, the row
 * form KR, CR. */
static int band_setup(vi_model *m)
{
  int n = m->n, kd = m->kd, ldb = m->ldb, ns = m->ns, st;
  double *work = malloc(sizeof(double) * (size_t)ldb * n);
  if (!work) return vi_fail(m->errmsg, VI_ERR_NOMEM, "out of memory");
  if ((st = check_psd_band(m, "K", m->KB, work)) ||
      (st = check_psd_band(m, "C", m->CB, work))) {
    free(work);
    return st;
  }
  free(work);

  /* M: a diagonal one is inverted, a banded one factored */
  m->kdm = band_width(m->MB, n, kd, ldb);
  if (m->kdm == 0) {
    for (int i = 0; i < n; i++) {
      double mi = m->MB[kd + (size_t)i * ldb];
      if (!(mi > 0.0))
        return vi_fail(m->errmsg, VI_ERR_NOT_SPD, "M is not positive "
                       "definite: M(%d,%d) = %g", i + 1, i + 1, mi);
      m->LB[i] = 1.0 / mi;
    }
  } else {
    int lm = m->kdm + 1;
    for (int j = 0; j < n; j++)
      memcpy(m->LB + (size_t)j * lm, m->MB + (kd - m->kdm) + (size_t)j * ldb,
             sizeof(double) * lm);
    lapack_int info = LAPACKE_dpbtrf(LAPACK_COL_MAJOR, 'U', n, m->kdm, m->LB,
                                     lm);
    if (info != 0)
      return vi_fail(m->errmsg, info > 0 ? VI_ERR_NOT_SPD : VI_ERR_LAPACK,
                     "M is not positive definite (band Cholesky fails at "
                     "column %d)", (int)info);
  }

  /* M^-1 [a b f0]: the three vectors are contiguous, as their images */
  memcpy(m->Minv_a, m->a, sizeof(double) * 3 * (size_t)n);
  if (minv(m, 3, m->Minv_a))
    return vi_fail(m->errmsg, VI_ERR_LAPACK, "dpbtrs failed");

  /* the stops: M^-1 W and the Delassus matrix G = W^T M^-1 W */
  size_t nS = (size_t)n * ns;
  free(m->MinvW);
  m->MinvW = malloc(sizeof(double) * (nS + (size_t)ns * ns));
  if (!m->MinvW) return vi_fail(m->errmsg, VI_ERR_NOMEM, "out of memory");
  m->PsiW = NULL; /* no modes */
  m->G = m->MinvW + nS;
  memcpy(m->MinvW, m->Ws, sizeof(double) * nS);
  if (minv(m, ns, m->MinvW))
    return vi_fail(m->errmsg, VI_ERR_LAPACK, "dpbtrs failed on the stops");
  for (int k = 0; k < ns; k++)
    for (int j = 0; j < ns; j++)
      m->G[j + (size_t)k * ns] =
          vi_dot(n, m->Ws + (size_t)j * n, m->MinvW + (size_t)k * n);
  for (int k = 0; k < ns; k++)
    for (int j = k + 1; j < ns; j++)
      m->G[j + (size_t)k * ns] = m->G[k + (size_t)j * ns] =
          0.5 * (m->G[j + (size_t)k * ns] + m->G[k + (size_t)j * ns]);

  /* rows of K and C (of M^-1 K, M^-1 C for a diagonal M) */
  int w = 2 * kd + 1;
  for (int i = 0; i < n; i++) {
    double s = m->kdm == 0 ? m->LB[i] : 1.0;
    double *kr = m->KR + (size_t)i * w, *cr = m->CR + (size_t)i * w;
    for (int d = -kd; d <= kd; d++) {
      int j = i + d, in = j >= 0 && j < n;
      kr[d + kd] = in ? s * sb_get(m->KB, kd, ldb, i, j) : 0.0;
      cr[d + kd] = in ? s * sb_get(m->CB, kd, ldb, i, j) : 0.0;
    }
  }
  /* half-bandwidth of M^-1 K, M^-1 C (the band Jacobian's): that of K and
   * C for a diagonal M; a banded M makes them dense */
  int bk = band_width(m->KB, n, kd, ldb), bc = band_width(m->CB, n, kd, ldb);
  m->bw = m->kdm == 0 ? (bk > bc ? bk : bc) : n - 1;
  m->proportional = 0;
  return VI_OK;
}

/* y = R x + S v for the row-stored R, S: the O(n kd) kernel. */
static void rows_apply(const vi_model *m, const double *x, int incx,
                       const double *v, int incv, double *y)
{
  int n = m->n, kd = m->kd, w = 2 * kd + 1;
  for (int i = 0; i < n; i++) {
    const double *kr = m->KR + (size_t)i * w, *cr = m->CR + (size_t)i * w;
    int d0 = i - kd < 0 ? -i : -kd, d1 = i + kd >= n ? n - 1 - i : kd;
    double a = 0.0;
    for (int d = d0; d <= d1; d++) {
      int j = i + d;
      a += kr[d + kd] * x[(size_t)j * (size_t)incx] +
           cr[d + kd] * v[(size_t)j * (size_t)incv];
    }
    y[i] = a;
  }
}

static void band_apply(const vi_model *m, const double *x, int incx,
                       const double *v, int incv, double *y)
{
  rows_apply(m, x, incx, v, incv, y);
  if (m->kdm > 0) minv(m, 1, y);
}

static void band_accel(const vi_model *m, const vi_phase *p, const double *z,
                       double *acc)
{
  int n = m->n;
  const double *fa, *fb, *f0;
  rows_apply(m, z, 2, z + 1, 2, acc);
  /* diagonal M: the rows are M^-1's already; else the physical forcing
   * and one band solve */
  vi_forcing_vectors(m, m->kdm == 0 ? VI_FORCING_MINV : VI_FORCING_PHYS,
                     &fa, &fb, &f0);
  for (int i = 0; i < n; i++)
    acc[i] = vi_harm(p, 0, fa[i], fb[i], f0[i]) - acc[i];
  if (m->kdm > 0) minv(m, 1, acc);
}

static void band_accel_rate(const vi_model *m, const vi_phase *p, int k,
                            const double *u, const double *ud, double *out)
{
  int n = m->n;
  const double *fa, *fb, *f0;
  vi_forcing_vectors(m, VI_FORCING_MINV, &fa, &fb, &f0);
  band_apply(m, u, 1, ud, 1, out);
  for (int i = 0; i < n; i++)
    out[i] = vi_harm(p, k, fa[i], fb[i], 0.0) - out[i];
}

static double band_energy(const vi_model *m, const double *x, const double *v)
{
  int n = m->n, kd = m->kd, ldb = m->ldb;
  double e = 0.0;
  for (int j = 0; j < n; j++) {
    int i0 = j - kd < 0 ? 0 : j - kd;
    for (int i = i0; i <= j; i++) {
      double f = i == j ? 0.5 : 1.0; /* the lower half mirrors the upper */
      size_t ij = (size_t)(kd + i - j) + (size_t)j * ldb;
      e += f * (v[i] * m->MB[ij] * v[j] + x[i] * m->KB[ij] * x[j]);
    }
  }
  return e;
}


static double *band_matrix(const vi_model *m, int which, size_t *len)
{
  if (len) *len = (size_t)m->ldb * (size_t)m->n;
  return which == 0 ? m->MB : which == 1 ? m->CB : m->KB;
}

/* Gershgorin: lambda_max(M^-1 K) <= max row sum of |K| / lambda_min(M),
 * with lambda_min(M) >= min_i (M_ii - sum_j!=i |M_ij|) */
static double band_omega_bound(const vi_model *m)
{
  int n = m->n, kd = m->kd, w = 2 * kd + 1;
  double kmax = 0.0, mmin = HUGE_VAL;
  for (int i = 0; i < n; i++) {
    const double *kr = m->KR + (size_t)i * w;
    double r = 0.0;
    for (int d = 0; d < w; d++) r += fabs(kr[d]);
    if (m->kdm == 0) { /* KR holds M^-1 K: its rows bound the spectrum */
      kmax = fmax(kmax, r);
      continue;
    }
    kmax = fmax(kmax, r);
    double mi = m->MB[kd + (size_t)i * m->ldb], off = 0.0;
    for (int j = i - kd < 0 ? 0 : i - kd; j <= (i + kd < n ? i + kd : n - 1); j++)
      if (j != i)
        off += fabs(j > i ? m->MB[kd + i - j + (size_t)j * m->ldb]
                          : m->MB[kd + j - i + (size_t)i * m->ldb]);
    mmin = fmin(mmin, mi - off);
  }
  if (m->kdm == 0) return sqrt(kmax);
  return mmin > 0.0 ? sqrt(kmax / mmin) : HUGE_VAL;
}

const vi_storage_ops vi_storage_band = {
    .name = "band",
    .modal = 0,
    .stop_vectors = 1,
    .dense_jac_max = 2000,
    .setup = band_setup,
    .accel = band_accel,
    .accel_rate = band_accel_rate,
    .apply = band_apply,
    .energy = band_energy,
    .solve_mass = minv,
    .matrix = band_matrix,
    .omega_bound = band_omega_bound,
    .minv_col = NULL,  /* M^-1 K: the row form, or dense for a banded M */
    .pack_rows = NULL, /* band_accel is the O(n kd) kernel already */
};
