/* vi_sparse.c - the finite-element reduction (vi_sparse.h): CSC storage and
 * its checks, host-supplied modes, stops, forcing and outputs on physical
 * dofs, and the projections onto the kept modes (MODEL.md section 5) that
 * make a modal vi_model.  The eigensolve itself is vi_eigs.c. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cblas.h>
#include <lapacke.h>

#include "vi_fe_internal.h"

/* Symmetry tolerance of a full-storage matrix, relative to its largest
 * entry: as vi_model.c's for dense matrices read from text. */
#define VI_FE_SYM_TOL 1e-12
/* Relative tolerance of semidefiniteness of the modal damping. */
#define VI_FE_PSD_TOL 1e-12
/* Without vi_fe_set_modes, structures of up to this many dofs with mass
 * keep every mode (the dense solve takes ~0.5 s at 1000), larger ones
 * must say how many: a default cut would change the model silently. */
#define VI_FE_WHOLE_MAX 1000
/* Two frequencies squared this close (relative) are one, for a cut. */
#define VI_FE_SAME_FREQ 1e-8
/* The default accuracy asked of the modes (residual, orthonormality). */
#define VI_FE_ACCURACY 1e-8

static const char *const mat_name[3] = {"M", "C", "K"};

int vi_fe_create(int n, vi_fe **out)
{
  if (!out) return VI_ERR_ARG;
  *out = NULL;
  if (n < 1) return VI_ERR_DIM;
  vi_fe *fe = calloc(1, sizeof *fe);
  if (!fe) return VI_ERR_NOMEM;
  fe->n = n;
  fe->k = VI_FE_K_UNSET;
  fe->k_rule = VI_FE_MODES_WHOLE;
  fe->rigid_in = -1;
  fe->accuracy = VI_FE_ACCURACY;
  *out = fe;
  return VI_OK;
}

static void csc_free(vi_csc *A)
{
  free(A->colptr);
  free(A->rowind);
  free(A->val);
  memset(A, 0, sizeof *A);
}

/* The results of a setup (none before). */
static void free_results(vi_fe *fe)
{
  free(fe->omega);
  free(fe->Psi);
  fe->omega = fe->lambda = fe->D = fe->PsiW = fe->Fa = fe->Fb = fe->F0 =
      fe->Pout = fe->Psi = fe->wMw = fe->wKw = fe->mresid = fe->mrigid =
          NULL;
}

void vi_fe_destroy(vi_fe **pfe)
{
  if (!pfe || !*pfe) return;
  vi_fe *fe = *pfe;
  for (int i = 0; i < 3; i++) csc_free(&fe->mat[i]);
  free(fe->zeta_in);
  free(fe->Dhost);
  free(fe->omega_in);
  free(fe->rows);
  free(fe->rowpos);
  free(fe->Prow);
  free(fe->W);
  free(fe->fa);
  free(fe->fb);
  free(fe->f0);
  free(fe->outs);
  free_results(fe);
  free(fe);
  *pfe = NULL;
}

const char *vi_fe_errmsg(const vi_fe *fe) { return fe ? fe->errmsg : ""; }

static int check_open(vi_fe *fe)
{
  if (!fe) return VI_ERR_ARG;
  if (fe->frozen)
    return vi_fail(fe->errmsg, VI_ERR_STATE, "the reduction is frozen by "
                   "vi_fe_setup; create a new one");
  return VI_OK;
}

/* ---- CSC input ------------------------------------------------------------ */

/* Structure and values of one CSC array set: colptr from base and
 * non-decreasing, rows in range and strictly increasing, values finite;
 * with lower storage no entry above the diagonal. */
static int csc_check(vi_fe *fe, const char *name, int storage, int base,
                     const int *colptr, const int *rowind,
                     const double *values, double *amax)
{
  int n = fe->n;
  if (colptr[0] != base)
    return vi_fail(fe->errmsg, VI_ERR_DIM, "%s: colptr(1) = %d, expected "
                   "the base %d", name, colptr[0], base);
  for (int j = 0; j < n; j++)
    if (colptr[j + 1] < colptr[j])
      return vi_fail(fe->errmsg, VI_ERR_DIM, "%s: colptr decreases at "
                     "column %d (%d after %d)", name, j + 1, colptr[j + 1],
                     colptr[j]);
  *amax = 0.0;
  for (int j = 0; j < n; j++) {
    int prev = -1;
    for (int p = colptr[j] - base; p < colptr[j + 1] - base; p++) {
      int i = rowind[p] - base;
      if (i < 0 || i >= n)
        return vi_fail(fe->errmsg, VI_ERR_DIM, "%s: column %d, entry %d: "
                       "row index %d out of range %d..%d", name, j + 1,
                       p + 1, rowind[p], base, n - 1 + base);
      if (i <= prev)
        return vi_fail(fe->errmsg, VI_ERR_DIM, "%s: column %d: row %d "
                       "after row %d (rows must be sorted, without "
                       "duplicates)", name, j + 1, i + 1, prev + 1);
      if (storage == VI_CSC_LOWER && i < j)
        return vi_fail(fe->errmsg, VI_ERR_DIM, "%s(%d,%d) lies above the "
                       "diagonal in lower storage (VI_CSC_LOWER)", name,
                       i + 1, j + 1);
      if (!isfinite(values[p]))
        return vi_fail(fe->errmsg, VI_ERR_NONFINITE, "%s(%d,%d) = %g is "
                       "not finite", name, i + 1, j + 1, values[p]);
      *amax = fmax(*amax, fabs(values[p]));
      prev = i;
    }
  }
  return VI_OK;
}

/* The lower triangle of a full-storage matrix, checked symmetric: the
 * transpose T (A's rows as columns, built sorted) is walked with A column
 * by column; a missing mirror counts as 0.  dst receives the averages. */
static int csc_from_full(vi_fe *fe, const char *name, int base,
                         const int *colptr, const int *rowind,
                         const double *values, double amax, vi_csc *dst)
{
  int n = fe->n, nnz = colptr[n] - base, st = VI_OK;
  int *tp = calloc((size_t)n + 1, sizeof(int));
  int *ti = malloc(sizeof(int) * (size_t)(nnz > 0 ? nnz : 1));
  double *tv = malloc(sizeof(double) * (size_t)(nnz > 0 ? nnz : 1));
  int *next = malloc(sizeof(int) * (size_t)n);
  VI_CHECK(tp && ti && tv && next, fe->errmsg, VI_ERR_NOMEM, "out of memory");
  for (int p = 0; p < nnz; p++) tp[rowind[p] - base + 1]++;
  for (int i = 0; i < n; i++) tp[i + 1] += tp[i];
  memcpy(next, tp, sizeof(int) * (size_t)n);
  for (int j = 0; j < n; j++)
    for (int p = colptr[j] - base; p < colptr[j + 1] - base; p++) {
      int q = next[rowind[p] - base]++;
      ti[q] = j;
      tv[q] = values[p];
    }
  int lower = 0;
  for (int j = 0; j < n; j++) {
    int p = colptr[j] - base, pe = colptr[j + 1] - base;
    int q = tp[j], qe = tp[j + 1];
    while (p < pe || q < qe) {
      int ia = p < pe ? rowind[p] - base : n, it = q < qe ? ti[q] : n;
      int i = ia < it ? ia : it;
      double a = ia == i ? values[p++] : 0.0, t = it == i ? tv[q++] : 0.0;
      VI_CHECK(fabs(a - t) <= VI_FE_SYM_TOL * amax, fe->errmsg,
               VI_ERR_NOT_SYMMETRIC, "%s is not symmetric: %s(%d,%d) = "
               "%.17g but %s(%d,%d) = %.17g", name, name, i + 1, j + 1, a,
               name, j + 1, i + 1, t);
      if (i >= j) lower++;
    }
  }
  dst->colptr = malloc(sizeof(int) * ((size_t)n + 1));
  dst->rowind = malloc(sizeof(int) * (size_t)(lower > 0 ? lower : 1));
  dst->val = malloc(sizeof(double) * (size_t)(lower > 0 ? lower : 1));
  VI_CHECK(dst->colptr && dst->rowind && dst->val, fe->errmsg, VI_ERR_NOMEM,
           "out of memory");
  dst->nnz = lower;
  int c = 0;
  for (int j = 0; j < n; j++) {
    dst->colptr[j] = c;
    int p = colptr[j] - base, pe = colptr[j + 1] - base;
    int q = tp[j], qe = tp[j + 1];
    while (p < pe || q < qe) {
      int ia = p < pe ? rowind[p] - base : n, it = q < qe ? ti[q] : n;
      int i = ia < it ? ia : it;
      double a = ia == i ? values[p++] : 0.0, t = it == i ? tv[q++] : 0.0;
      if (i < j) continue;
      dst->rowind[c] = i;
      dst->val[c++] = 0.5 * (a + t);
    }
  }
  dst->colptr[n] = c;
cleanup:
  free(tp);
  free(ti);
  free(tv);
  free(next);
  if (st) csc_free(dst);
  return st;
}

static int csc_lower_copy(vi_fe *fe, int base, const int *colptr,
                          const int *rowind, const double *values, vi_csc *dst)
{
  int n = fe->n, nnz = colptr[n] - base;
  size_t sz = (size_t)(nnz > 0 ? nnz : 1);
  dst->colptr = malloc(sizeof(int) * ((size_t)n + 1));
  dst->rowind = malloc(sizeof(int) * sz);
  dst->val = malloc(sizeof(double) * sz);
  if (!dst->colptr || !dst->rowind || !dst->val) {
    csc_free(dst);
    return vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory");
  }
  for (int j = 0; j <= n; j++) dst->colptr[j] = colptr[j] - base;
  for (int p = 0; p < nnz; p++) dst->rowind[p] = rowind[p] - base;
  if (nnz > 0) memcpy(dst->val, values, sizeof(double) * (size_t)nnz);
  dst->nnz = nnz;
  return VI_OK;
}

static int set_csc(vi_fe *fe, int which, int storage, int base,
                   const int *colptr, const int *rowind, const double *values)
{
  int st = check_open(fe);
  if (st) return st;
  const char *name = mat_name[which];
  if (fe->source == VI_FE_SRC_HOST)
    return vi_fail(fe->errmsg, VI_ERR_STATE, "%s: host modes are set; a "
                   "reduction takes matrices or host modes, not both", name);
  if (!colptr || !rowind || !values)
    return vi_fail(fe->errmsg, VI_ERR_ARG, "%s: NULL array", name);
  if (base != 0 && base != 1)
    return vi_fail(fe->errmsg, VI_ERR_DIM, "%s: index base %d is neither 0 "
                   "nor 1", name, base);
  if (storage != VI_CSC_FULL && storage != VI_CSC_LOWER)
    return vi_fail(fe->errmsg, VI_ERR_ARG, "%s: storage %d is neither "
                   "VI_CSC_FULL nor VI_CSC_LOWER", name, storage);
  double amax = 0.0;
  if ((st = csc_check(fe, name, storage, base, colptr, rowind, values, &amax)))
    return st;
  vi_csc A = {0, NULL, NULL, NULL};
  st = storage == VI_CSC_FULL
           ? csc_from_full(fe, name, base, colptr, rowind, values, amax, &A)
           : csc_lower_copy(fe, base, colptr, rowind, values, &A);
  if (st) return st;
  csc_free(&fe->mat[which]);
  fe->mat[which] = A;
  return VI_OK;
}

int vi_fe_set_mass_csc(vi_fe *fe, int storage, int base, const int *colptr,
                       const int *rowind, const double *values)
{
  int st = set_csc(fe, VI_FE_MASS, storage, base, colptr, rowind, values);
  if (!st) fe->source = VI_FE_SRC_SPARSE;
  return st;
}

int vi_fe_set_stiffness_csc(vi_fe *fe, int storage, int base,
                            const int *colptr, const int *rowind,
                            const double *values)
{
  int st = set_csc(fe, VI_FE_STIFFNESS, storage, base, colptr, rowind,
                   values);
  if (!st) fe->source = VI_FE_SRC_SPARSE;
  return st;
}

int vi_fe_set_damping_csc(vi_fe *fe, int storage, int base,
                          const int *colptr, const int *rowind,
                          const double *values)
{
  int st = check_open(fe);
  if (st) return st;
  if (!colptr) {
    csc_free(&fe->mat[VI_FE_DAMPING]);
    if (fe->damping == VI_FE_DAMP_C) fe->damping = VI_FE_DAMP_NONE;
    return VI_OK;
  }
  st = set_csc(fe, VI_FE_DAMPING, storage, base, colptr, rowind, values);
  if (!st) {
    fe->damping = VI_FE_DAMP_C;
    fe->source = VI_FE_SRC_SPARSE;
  }
  return st;
}

/* ---- damping and settings ---------------------------------------------- */

int vi_fe_set_rayleigh(vi_fe *fe, double alpha, double beta)
{
  int st = check_open(fe);
  if (st) return st;
  if (!isfinite(alpha) || !isfinite(beta))
    return vi_fail(fe->errmsg, VI_ERR_NONFINITE, "Rayleigh alpha = %g, "
                   "beta = %g: not finite", alpha, beta);
  if (alpha < 0.0 || beta < 0.0)
    return vi_fail(fe->errmsg, VI_ERR_ARG, "Rayleigh alpha = %g, beta = %g: "
                   "both must be >= 0", alpha, beta);
  fe->alpha = alpha;
  fe->beta = beta;
  fe->damping = VI_FE_DAMP_RAYLEIGH;
  return VI_OK;
}

int vi_fe_set_modal_damping(vi_fe *fe, int nzeta, const double *zeta)
{
  int st = check_open(fe);
  if (st) return st;
  if (!zeta) return vi_fail(fe->errmsg, VI_ERR_ARG, "zeta: NULL array");
  if (nzeta < 1)
    return vi_fail(fe->errmsg, VI_ERR_DIM, "zeta: %d ratios; give 1 or one "
                   "per kept mode", nzeta);
  for (int j = 0; j < nzeta; j++) {
    if (!isfinite(zeta[j]))
      return vi_fail(fe->errmsg, VI_ERR_NONFINITE, "zeta(%d) = %g is not "
                     "finite", j + 1, zeta[j]);
    if (zeta[j] < 0.0)
      return vi_fail(fe->errmsg, VI_ERR_ARG, "zeta(%d) = %g is negative",
                     j + 1, zeta[j]);
  }
  double *z = malloc(sizeof(double) * (size_t)nzeta);
  if (!z) return vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory");
  memcpy(z, zeta, sizeof(double) * (size_t)nzeta);
  free(fe->zeta_in);
  fe->zeta_in = z;
  fe->nzeta = nzeta;
  fe->damping = VI_FE_DAMP_ZETA;
  return VI_OK;
}

int vi_fe_set_modes(vi_fe *fe, int k)
{
  int st = check_open(fe);
  if (st) return st;
  if (fe->source == VI_FE_SRC_HOST)
    return vi_fail(fe->errmsg, VI_ERR_STATE, "host modes fix the number of "
                   "modes (%d)", fe->k);
  if (k < 1 || k > fe->n)
    return vi_fail(fe->errmsg, VI_ERR_DIM, "%d modes: need 1 <= k <= n = %d",
                   k, fe->n);
  fe->k = k;
  fe->k_rule = VI_FE_MODES_GIVEN;
  return VI_OK;
}

int vi_fe_set_rigid_modes(vi_fe *fe, int count)
{
  int st = check_open(fe);
  if (st) return st;
  if (count < -1 || count > fe->n)
    return vi_fail(fe->errmsg, VI_ERR_ARG, "%d rigid-body modes: need -1 "
                   "(decide from K) or 0..%d", count, fe->n);
  fe->rigid_in = count;
  return VI_OK;
}

int vi_fe_set_accuracy(vi_fe *fe, double tol)
{
  int st = check_open(fe);
  if (st) return st;
  if (!(tol > 0.0 && tol < 1.0))
    return vi_fail(fe->errmsg, VI_ERR_TOLERANCE, "accuracy %g: need 0 < tol "
                   "< 1 (0 is not attainable in floating point)", tol);
  fe->accuracy = tol;
  return VI_OK;
}

int vi_fe_set_shift(vi_fe *fe, double sigma)
{
  int st = check_open(fe);
  if (st) return st;
  if (!isfinite(sigma))
    return vi_fail(fe->errmsg, VI_ERR_NONFINITE, "shift sigma = %g is not "
                   "finite", sigma);
  fe->sigma_in = sigma;
  fe->shift_set = 1;
  return VI_OK;
}

int vi_fe_set_eigensolver(vi_fe *fe, double tol, int ncv, int maxit)
{
  int st = check_open(fe);
  if (st) return st;
  if (!isfinite(tol) || tol < 0.0 || maxit < 0 || ncv < 0)
    return vi_fail(fe->errmsg, VI_ERR_ARG, "eigensolver tol = %g, ncv = %d, "
                   "maxit = %d: each must be >= 0 (0: default)", tol, ncv,
                   maxit);
  if (ncv > fe->n)
    return vi_fail(fe->errmsg, VI_ERR_DIM, "ncv = %d exceeds n = %d", ncv,
                   fe->n);
  fe->tol = tol;
  fe->ncv = ncv;
  fe->maxit = maxit;
  return VI_OK;
}

int vi_fe_set_memory_limit(vi_fe *fe, int64_t bytes)
{
  int st = check_open(fe);
  if (st) return st;
  if (bytes < 0)
    return vi_fail(fe->errmsg, VI_ERR_ARG, "memory limit %lld is negative",
                   (long long)bytes);
  fe->mem_limit = bytes;
  return VI_OK;
}

/* ---- host modes ---------------------------------------------------------- */

/* A dense symmetric k x k modal damping (checked symmetric and finite). */
static int check_modal_D(vi_fe *fe, int k, const double *D, int ldd)
{
  if (ldd < k)
    return vi_fail(fe->errmsg, VI_ERR_DIM, "D: leading dimension %d is less "
                   "than k = %d", ldd, k);
  double amax = 0.0;
  for (int j = 0; j < k; j++)
    for (int i = 0; i < k; i++) {
      double v = D[i + (size_t)j * ldd];
      if (!isfinite(v))
        return vi_fail(fe->errmsg, VI_ERR_NONFINITE, "D(%d,%d) = %g is not "
                       "finite", i + 1, j + 1, v);
      amax = fmax(amax, fabs(v));
    }
  for (int j = 0; j < k; j++)
    for (int i = j + 1; i < k; i++) {
      double lo = D[i + (size_t)j * ldd], up = D[j + (size_t)i * ldd];
      if (fabs(lo - up) > VI_FE_SYM_TOL * amax)
        return vi_fail(fe->errmsg, VI_ERR_NOT_SYMMETRIC, "D is not "
                       "symmetric: D(%d,%d) = %.17g but D(%d,%d) = %.17g",
                       i + 1, j + 1, lo, j + 1, i + 1, up);
    }
  return VI_OK;
}

int vi_fe_set_host_modes(vi_fe *fe, int k, const double *omega,
                         const double *zeta, const double *D, int ldd,
                         int nrows, const int *rows, const double *Psi,
                         int ldp)
{
  int st = check_open(fe);
  if (st) return st;
  int n = fe->n;
  if (fe->source == VI_FE_SRC_SPARSE)
    return vi_fail(fe->errmsg, VI_ERR_STATE, "sparse matrices are set; a "
                   "reduction takes matrices or host modes, not both");
  if (k < 1 || nrows < 1 || ldp < nrows)
    return vi_fail(fe->errmsg, VI_ERR_DIM, "host modes: k = %d, nrows = %d, "
                   "ldp = %d (need k >= 1, nrows >= 1, ldp >= nrows)", k,
                   nrows, ldp);
  if (!omega || !rows || !Psi)
    return vi_fail(fe->errmsg, VI_ERR_ARG, "host modes: NULL omega, rows or "
                   "Psi");
  if (zeta && D)
    return vi_fail(fe->errmsg, VI_ERR_ARG, "host modes: give zeta or D, not "
                   "both");
  for (int j = 0; j < k; j++) {
    if (!isfinite(omega[j]) || (zeta && !isfinite(zeta[j])))
      return vi_fail(fe->errmsg, VI_ERR_NONFINITE, "host mode %d: omega = %g"
                     "%s not finite", j + 1, omega[j], zeta ? " or zeta" : "");
    if (omega[j] < 0.0 || (zeta && zeta[j] < 0.0))
      return vi_fail(fe->errmsg, VI_ERR_ARG, "host mode %d: omega = %g, "
                     "zeta = %g: neither may be negative", j + 1, omega[j],
                     zeta ? zeta[j] : 0.0);
  }
  if (D && (st = check_modal_D(fe, k, D, ldd))) return st;
  int *pos = malloc(sizeof(int) * (size_t)n);
  if (!pos) return vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory");
  for (int i = 0; i < n; i++) pos[i] = -1;
  for (int r = 0; r < nrows; r++) {
    int i = rows[r];
    if (i < 0 || i >= n || pos[i] >= 0) {
      free(pos);
      return vi_fail(fe->errmsg, VI_ERR_ARG, "host modes: rows(%d) = %d is "
                     "%s", r + 1, i, i < 0 || i >= n ? "out of range" :
                     "repeated");
    }
    pos[i] = r;
    for (int j = 0; j < k; j++)
      if (!isfinite(Psi[r + (size_t)j * ldp])) {
        free(pos);
        return vi_fail(fe->errmsg, VI_ERR_NONFINITE, "host modes: Psi(%d,%d)"
                       " = %g is not finite", r + 1, j + 1,
                       Psi[r + (size_t)j * ldp]);
      }
  }
  double *om = malloc(sizeof(double) * (size_t)k);
  int *rw = malloc(sizeof(int) * (size_t)nrows);
  double *P = malloc(sizeof(double) * (size_t)nrows * k);
  double *z = zeta ? malloc(sizeof(double) * (size_t)k) : NULL;
  double *Dh = D ? malloc(sizeof(double) * (size_t)k * k) : NULL;
  if (!om || !rw || !P || (zeta && !z) || (D && !Dh)) {
    free(pos); free(om); free(rw); free(P); free(z); free(Dh);
    return vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory");
  }
  memcpy(om, omega, sizeof(double) * (size_t)k);
  memcpy(rw, rows, sizeof(int) * (size_t)nrows);
  for (int j = 0; j < k; j++)
    memcpy(P + (size_t)j * nrows, Psi + (size_t)j * ldp,
           sizeof(double) * (size_t)nrows);
  if (z) memcpy(z, zeta, sizeof(double) * (size_t)k);
  if (Dh)
    for (int j = 0; j < k; j++)
      for (int i = 0; i < k; i++)
        Dh[i + (size_t)j * k] =
            0.5 * (D[i + (size_t)j * ldd] + D[j + (size_t)i * ldd]);
  free(fe->omega_in); free(fe->rows); free(fe->rowpos); free(fe->Prow);
  free(fe->Dhost);
  fe->omega_in = om;
  fe->rows = rw;
  fe->rowpos = pos;
  fe->Prow = P;
  fe->nrows = nrows;
  fe->k = k;
  fe->k_rule = VI_FE_MODES_HOST;
  fe->Dhost = Dh;
  if (z) {
    free(fe->zeta_in);
    fe->zeta_in = z;
    fe->nzeta = k;
    fe->damping = VI_FE_DAMP_ZETA;
  } else if (Dh) {
    fe->damping = VI_FE_DAMP_HOST_D;
  } else if (fe->damping == VI_FE_DAMP_HOST_D) {
    fe->damping = VI_FE_DAMP_NONE;
  }
  fe->source = VI_FE_SRC_HOST;
  return VI_OK;
}

/* With host modes a physical vector may touch only the given rows. */
static int check_in_rows(vi_fe *fe, const char *what, const double *v)
{
  if (fe->source != VI_FE_SRC_HOST || !v) return VI_OK;
  for (int i = 0; i < fe->n; i++)
    if (v[i] != 0.0 && fe->rowpos[i] < 0)
      return vi_fail(fe->errmsg, VI_ERR_UNSUPPORTED, "%s: dof %d (1-based) "
                     "is not among the host's rows of Psi", what, i + 1);
  return VI_OK;
}

/* ---- stops, forcing, outputs ---------------------------------------------- */

int vi_fe_add_stop(vi_fe *fe, const double *w, double x_s, double r)
{
  int st = check_open(fe);
  if (st) return st;
  int n = fe->n, nz = 0;
  if (!w) return vi_fail(fe->errmsg, VI_ERR_ARG, "stop %d: w is NULL",
                         fe->ns + 1);
  for (int i = 0; i < n; i++) {
    if (!isfinite(w[i]))
      return vi_fail(fe->errmsg, VI_ERR_NONFINITE, "stop %d: w(%d) = %g is "
                     "not finite", fe->ns + 1, i + 1, w[i]);
    nz |= w[i] != 0.0;
  }
  if (!isfinite(x_s) || !isfinite(r))
    return vi_fail(fe->errmsg, VI_ERR_NONFINITE, "stop %d: x_s = %g, r = %g "
                   "not finite", fe->ns + 1, x_s, r);
  if (r < 0.0 || r > 1.0)
    return vi_fail(fe->errmsg, VI_ERR_RESTITUTION, "stop %d: restitution "
                   "r = %g is outside [0, 1]", fe->ns + 1, r);
  if (!nz)
    return vi_fail(fe->errmsg, VI_ERR_STOP_VECTOR, "stop %d: w is zero",
                   fe->ns + 1);
  char what[32];
  snprintf(what, sizeof what, "stop %d", fe->ns + 1);
  if ((st = check_in_rows(fe, what, w))) return st;
  if (fe->ns == fe->ns_cap) {
    int cap = fe->ns_cap ? 2 * fe->ns_cap : 2;
    if (cap > (1 << 20))
      return vi_fail(fe->errmsg, VI_ERR_LIMIT, "too many stops");
    /* layout [W | x_s | r], as vi_model's stops */
    double *p = realloc(fe->W, sizeof(double) * (size_t)cap * (size_t)(n + 2));
    if (!p) return vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory");
    memmove(p + (size_t)cap * n + cap, p + (size_t)fe->ns_cap * n + fe->ns_cap,
            sizeof(double) * (size_t)fe->ns_cap);
    memmove(p + (size_t)cap * n, p + (size_t)fe->ns_cap * n,
            sizeof(double) * (size_t)fe->ns_cap);
    fe->W = p;
    fe->xs = p + (size_t)cap * n;
    fe->r = fe->xs + cap;
    fe->ns_cap = cap;
  }
  memcpy(fe->W + (size_t)fe->ns * n, w, sizeof(double) * (size_t)n);
  fe->xs[fe->ns] = x_s;
  fe->r[fe->ns] = r;
  fe->ns++;
  return VI_OK;
}

int vi_fe_add_stop_dof(vi_fe *fe, int dof, int direction, double x_s,
                       double r)
{
  int st = check_open(fe);
  if (st) return st;
  if (dof < 0 || dof >= fe->n || (direction != 1 && direction != -1))
    return vi_fail(fe->errmsg, VI_ERR_ARG, "stop on dof %d (0-based), "
                   "direction %d: need 0 <= dof < %d and direction +1 or -1",
                   dof, direction, fe->n);
  double *w = calloc((size_t)fe->n, sizeof(double));
  if (!w) return vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory");
  w[dof] = direction;
  st = vi_fe_add_stop(fe, w, x_s, r);
  free(w);
  return st;
}

int vi_fe_num_stops(const vi_fe *fe) { return fe ? fe->ns : 0; }

/* Copy a forcing vector, NULL (or all zero) kept as NULL. */
static int copy_load(vi_fe *fe, const double *v, double **dst)
{
  *dst = NULL;
  if (!v) return VI_OK;
  int nz = 0;
  for (int i = 0; i < fe->n && !nz; i++) nz = v[i] != 0.0;
  if (!nz) return VI_OK;
  *dst = malloc(sizeof(double) * (size_t)fe->n);
  if (!*dst) return vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory");
  memcpy(*dst, v, sizeof(double) * (size_t)fe->n);
  return VI_OK;
}

int vi_fe_set_forcing(vi_fe *fe, double omega, const double *a,
                      const double *b, const double *f0)
{
  int st = check_open(fe);
  if (st) return st;
  const double *v[3] = {a, b, f0};
  const char *nm[3] = {"a", "b", "f0"};
  int harmonic = 0;
  for (int k = 0; k < 3; k++) {
    if (!v[k]) continue;
    for (int i = 0; i < fe->n; i++) {
      if (!isfinite(v[k][i]))
        return vi_fail(fe->errmsg, VI_ERR_NONFINITE, "%s(%d) = %g is not "
                       "finite", nm[k], i + 1, v[k][i]);
      if (k < 2) harmonic |= v[k][i] != 0.0;
    }
    if ((st = check_in_rows(fe, nm[k], v[k]))) return st;
  }
  if (!isfinite(omega))
    return vi_fail(fe->errmsg, VI_ERR_NONFINITE, "forcing frequency Omega = "
                   "%g is not finite", omega);
  if (omega < 0.0 || (harmonic && omega <= 0.0))
    return vi_fail(fe->errmsg, VI_ERR_FREQUENCY, "forcing frequency Omega = "
                   "%g must be %s", omega, harmonic ? "> 0 when a or b is "
                   "non-zero" : ">= 0");
  double *na, *nb, *nf;
  if ((st = copy_load(fe, a, &na))) return st;
  if ((st = copy_load(fe, b, &nb))) { free(na); return st; }
  if ((st = copy_load(fe, f0, &nf))) { free(na); free(nb); return st; }
  free(fe->fa); free(fe->fb); free(fe->f0);
  fe->fa = na;
  fe->fb = nb;
  fe->f0 = nf;
  fe->omega_f = omega;
  return VI_OK;
}

int vi_fe_set_outputs(vi_fe *fe, int nout, const int *dofs)
{
  int st = check_open(fe);
  if (st) return st;
  if (nout < 0)
    return vi_fail(fe->errmsg, VI_ERR_DIM, "%d outputs", nout);
  if (nout > 0 && !dofs)
    return vi_fail(fe->errmsg, VI_ERR_ARG, "outputs: NULL dofs");
  for (int r = 0; r < nout; r++) {
    if (dofs[r] < 0 || dofs[r] >= fe->n)
      return vi_fail(fe->errmsg, VI_ERR_ARG, "outputs(%d) = %d is out of "
                     "range 0..%d", r + 1, dofs[r], fe->n - 1);
    if (fe->source == VI_FE_SRC_HOST && fe->rowpos[dofs[r]] < 0)
      return vi_fail(fe->errmsg, VI_ERR_UNSUPPORTED, "outputs(%d): dof %d "
                     "(1-based) is not among the host's rows of Psi", r + 1,
                     dofs[r] + 1);
  }
  int *o = NULL;
  if (nout > 0) {
    o = malloc(sizeof(int) * (size_t)nout);
    if (!o) return vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory");
    memcpy(o, dofs, sizeof(int) * (size_t)nout);
  }
  free(fe->outs);
  fe->outs = o;
  fe->nout = nout;
  return VI_OK;
}

int vi_fe_set_keep_shapes(vi_fe *fe, int keep)
{
  int st = check_open(fe);
  if (st) return st;
  if (keep != 0 && keep != 1)
    return vi_fail(fe->errmsg, VI_ERR_ARG, "keep = %d: 0 or 1", keep);
  if (keep && fe->source == VI_FE_SRC_HOST)
    return vi_fail(fe->errmsg, VI_ERR_UNSUPPORTED, "host modes give only "
                   "rows of Psi, not the full shapes");
  fe->keep = keep;
  return VI_OK;
}

/* ---- setup ---------------------------------------------------------------- */

/* One block for the results: omega, lambda [k], D [k x k], PsiW [k x ns],
 * Fa, Fb, F0 [k], Pout [nout x k], wMw, wKw [ns], mresid, mrigid [k]. */
static int alloc_results(vi_fe *fe)
{
  size_t k = (size_t)fe->k, ns = (size_t)fe->ns;
  size_t count = 2 * k + k * k + k * ns + 3 * k + (size_t)fe->nout * k +
                 2 * ns + 2 * k;
  double *p = calloc(count, sizeof(double));
  if (!p) return vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory");
  fe->omega = p; p += k;
  fe->lambda = p; p += k;
  fe->D = p; p += k * k;
  fe->PsiW = p; p += k * ns;
  fe->Fa = p; p += k;
  fe->Fb = p; p += k;
  fe->F0 = p; p += k;
  fe->Pout = p; p += (size_t)fe->nout * k;
  fe->wMw = p; p += ns;
  fe->wKw = p; p += ns;
  fe->mresid = p; p += k;
  fe->mrigid = p;
  return VI_OK;
}

/* Psi^T v [k] for a physical vector v [n] (NULL: 0), from the full Psi or
 * from the host's rows. */
static void project(const vi_fe *fe, const double *Psi, const double *v,
                    double *out)
{
  int n = fe->n, k = fe->k;
  memset(out, 0, sizeof(double) * (size_t)k);
  if (!v) return;
  if (Psi) {
    cblas_dgemv(CblasColMajor, CblasTrans, n, k, 1.0, Psi, n, v, 1, 0.0, out,
                1);
    return;
  }
  for (int r = 0; r < fe->nrows; r++) {
    double vi = v[fe->rows[r]];
    if (vi != 0.0)
      cblas_daxpy(k, vi, fe->Prow + r, fe->nrows, out, 1);
  }
}

/* The modal damping D [k x k] of the chosen kind, checked semidefinite. */
static int modal_damping(vi_fe *fe, const double *Psi)
{
  int n = fe->n, k = fe->k, st = VI_OK;
  double *D = fe->D;
  memset(D, 0, sizeof(double) * (size_t)k * k);
  switch (fe->damping) {
  case VI_FE_DAMP_RAYLEIGH:
    for (int j = 0; j < k; j++)
      D[j + (size_t)j * k] = fe->alpha + fe->beta * fe->lambda[j];
    return VI_OK;
  case VI_FE_DAMP_ZETA:
    if (fe->nzeta != 1 && fe->nzeta != k)
      return vi_fail(fe->errmsg, VI_ERR_DIM, "%d modal damping ratios for "
                     "%d kept modes: give 1 or %d", fe->nzeta, k, k);
    for (int j = 0; j < k; j++)
      D[j + (size_t)j * k] =
          2.0 * fe->zeta_in[fe->nzeta == 1 ? 0 : j] * fe->omega[j];
    return VI_OK;
  case VI_FE_DAMP_HOST_D:
    memcpy(D, fe->Dhost, sizeof(double) * (size_t)k * k);
    break;
  case VI_FE_DAMP_C: {
    if (!Psi)
      return vi_fail(fe->errmsg, VI_ERR_UNSUPPORTED, "an explicit C needs "
                     "the sparse source");
    double *CP = malloc(sizeof(double) * (size_t)n * k);
    if (!CP) return vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory");
    for (int j = 0; j < k; j++)
      vi_csc_symv(n, &fe->mat[VI_FE_DAMPING], Psi + (size_t)j * n,
                  CP + (size_t)j * n);
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, k, k, n, 1.0, Psi, n,
                CP, n, 0.0, D, k);
    free(CP);
    for (int j = 0; j < k; j++)
      for (int i = j + 1; i < k; i++)
        D[i + (size_t)j * k] = D[j + (size_t)i * k] =
            0.5 * (D[i + (size_t)j * k] + D[j + (size_t)i * k]);
    break;
  }
  default:
    return VI_OK;
  }
  /* C (or the host's D) semidefinite: the eigenvalues of D (k x k) */
  double *work = malloc(sizeof(double) * ((size_t)k * k + k));
  if (!work) return vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory");
  memcpy(work, D, sizeof(double) * (size_t)k * k);
  double *ev = work + (size_t)k * k;
  lapack_int info = LAPACKE_dsyev(LAPACK_COL_MAJOR, 'N', 'L', k, work, k, ev);
  if (info != 0)
    st = vi_fail(fe->errmsg, VI_ERR_LAPACK, "dsyev on the modal damping "
                 "failed (info %d)", (int)info);
  else if (ev[0] < -VI_FE_PSD_TOL * fmax(fabs(ev[0]), fabs(ev[k - 1])))
    st = vi_fail(fe->errmsg, VI_ERR_NOT_PSD, "%s is not positive "
                 "semidefinite: the modal damping has eigenvalue %.6g "
                 "(largest magnitude %.6g)",
                 fe->damping == VI_FE_DAMP_C ? "C" : "D", ev[0],
                 fmax(fabs(ev[0]), fabs(ev[k - 1])));
  free(work);
  return st;
}

/* Stops, forcing, damping and outputs onto the modes (Psi full, or NULL
 * with host modes). */
static int projections(vi_fe *fe, const double *Psi)
{
  int n = fe->n, k = fe->k, st;
  for (int s = 0; s < fe->ns; s++) {
    double *ps = fe->PsiW + (size_t)s * k;
    project(fe, Psi, fe->W + (size_t)s * n, ps);
    double nrm = 0.0;
    for (int j = 0; j < k; j++) nrm = fmax(nrm, fabs(ps[j]));
    if (!(nrm > 0.0))
      return vi_fail(fe->errmsg, VI_ERR_STOP_VECTOR, "stop %d: the kept "
                     "modes do not move it (Psi^T w = 0)", s + 1);
  }
  project(fe, Psi, fe->fa, fe->Fa);
  project(fe, Psi, fe->fb, fe->Fb);
  project(fe, Psi, fe->f0, fe->F0);
  for (int r = 0; r < fe->nout; r++)
    for (int j = 0; j < k; j++)
      fe->Pout[r + (size_t)j * fe->nout] =
          Psi ? Psi[fe->outs[r] + (size_t)j * n]
              : fe->Prow[fe->rowpos[fe->outs[r]] + (size_t)j * fe->nrows];
  if ((st = modal_damping(fe, Psi))) return st;
  return VI_OK;
}

/* Host modes: every stop and load must touch only the given rows (they may
 * have been set before the modes). */
static int setup_host(vi_fe *fe)
{
  int st;
  for (int s = 0; s < fe->ns; s++) {
    char what[32];
    snprintf(what, sizeof what, "stop %d", s + 1);
    if ((st = check_in_rows(fe, what, fe->W + (size_t)s * fe->n))) return st;
  }
  if ((st = check_in_rows(fe, "a", fe->fa)) ||
      (st = check_in_rows(fe, "b", fe->fb)) ||
      (st = check_in_rows(fe, "f0", fe->f0)))
    return st;
  for (int r = 0; r < fe->nout; r++)
    if (fe->rowpos[fe->outs[r]] < 0)
      return vi_fail(fe->errmsg, VI_ERR_UNSUPPORTED, "outputs(%d): dof %d "
                     "(1-based) is not among the host's rows of Psi", r + 1,
                     fe->outs[r] + 1);
  for (int j = 0; j < fe->k; j++) {
    fe->omega[j] = fe->omega_in[j];
    fe->lambda[j] = fe->omega_in[j] * fe->omega_in[j];
  }
  for (int s = 0; s < fe->ns; s++) fe->wMw[s] = fe->wKw[s] = NAN;
  fe->shift = 0.0;
  fe->resid = fe->orth = 0.0;
  fe->n0 = fe->nrigid = 0;
  for (int j = 0; j < fe->k; j++) fe->nrigid += fe->omega_in[j] == 0.0;
  return projections(fe, NULL);
}

/* The number of kept modes of a sparse reduction: as set, or by default
 * the whole model where that is cheap; never more than the finite modes
 * (the massless dofs' eigenvalues are infinite). */
static int decide_modes(vi_fe *fe)
{
  int nf = fe->n - fe->n0;
  if (fe->k_rule == VI_FE_MODES_GIVEN && fe->k > nf)
    return vi_fail(fe->errmsg, VI_ERR_DIM, "%d modes asked, but the "
                   "structure has only %d finite ones (%d of its %d dofs are "
                   "massless: M's row %d is zero)", fe->k, nf, fe->n0, fe->n,
                   fe->first_massless + 1);
  if (fe->k_rule == VI_FE_MODES_GIVEN) return VI_OK;
  if (nf > VI_FE_WHOLE_MAX)
    return vi_fail(fe->errmsg, VI_ERR_STATE, "how many modes? The structure "
                   "has %d dofs with mass, more than the %d up to which the "
                   "whole model is kept by default: choose the lowest k "
                   "with vi_fe_set_modes (scene key model.modes; `vibroimpact"
                   " truncation` tells how many a stop needs)", nf,
                   VI_FE_WHOLE_MAX);
  fe->k = nf;
  fe->k_rule = VI_FE_MODES_WHOLE;
  return VI_OK;
}

/* A cut after mode kcut must not split modes of one frequency: which of
 * them the model keeps would be an accident of the eigensolver (a free
 * structure's rigid modes, a symmetric structure's pairs). */
static int check_cut(vi_fe *fe, int kcut)
{
  double a = fe->lambda[kcut - 1], b = fe->lambda[kcut];
  if (fabs(b - a) > VI_FE_SAME_FREQ * fmax(fabs(a), fabs(b)) ||
      (a != b && (a == 0.0 || b == 0.0)))
    return VI_OK;
  return vi_fail(fe->errmsg, VI_ERR_DIM, "keeping %d modes cuts through a "
                 "group of equal frequencies: modes %d and %d both have "
                 "omega = %.9g; keep all of the group or none of it (the "
                 "kept part would be arbitrary)", kcut, kcut, kcut + 1,
                 fe->omega[kcut - 1]);
}

int vi_fe_setup(vi_fe *fe)
{
  int st = check_open(fe);
  if (st) return st;
  if (fe->source == VI_FE_SRC_NONE ||
      (fe->source == VI_FE_SRC_SPARSE &&
       (!fe->mat[VI_FE_MASS].colptr || !fe->mat[VI_FE_STIFFNESS].colptr)))
    return vi_fail(fe->errmsg, VI_ERR_STATE, "no %s: set M and K "
                   "(vi_fe_set_mass_csc, vi_fe_set_stiffness_csc) or host "
                   "modes (vi_fe_set_host_modes)",
                   fe->source == VI_FE_SRC_NONE ? "structure"
                   : fe->mat[VI_FE_MASS].colptr ? "K" : "M");
  if (fe->ns < 1)
    return vi_fail(fe->errmsg, VI_ERR_STOP_VECTOR, "no stop: call "
                   "vi_fe_add_stop or vi_fe_add_stop_dof before setup");
  if (fe->source == VI_FE_SRC_SPARSE &&
      ((st = vi_fe_inspect(fe)) || (st = decide_modes(fe))))
    return st;
  if (fe->damping == VI_FE_DAMP_ZETA && fe->nzeta != 1 && fe->nzeta != fe->k)
    return vi_fail(fe->errmsg, VI_ERR_DIM, "%d modal damping ratios for %d "
                   "kept modes: give 1 or %d", fe->nzeta, fe->k, fe->k);
  /* the sparse source solves for one mode beyond the cut where there is
   * one, to see whether the cut splits a group of equal frequencies */
  int kcut = fe->k, nf = fe->n - fe->n0;
  if (fe->source == VI_FE_SRC_SPARSE && kcut < nf &&
      (kcut + 1 < nf - 1 || fe->n <= 4000))
    fe->k = kcut + 1;
  free_results(fe);
  st = alloc_results(fe);
  if (st) {
    fe->k = kcut;
    return st;
  }
  if (fe->source == VI_FE_SRC_HOST) {
    st = setup_host(fe);
  } else {
    double *Psi = NULL;
    st = vi_fe_eigs(fe, &Psi);
    if (!st && fe->k > kcut) st = check_cut(fe, kcut);
    fe->k = kcut;
    if (!st) st = projections(fe, Psi);
    if (!st && fe->keep) fe->Psi = Psi;
    else free(Psi);
  }
  if (st) {
    free_results(fe);
    return st;
  }
  fe->frozen = 1;
  fe->errmsg[0] = '\0';
  return VI_OK;
}

int vi_fe_create_model(const vi_fe *fe, vi_model **out)
{
  if (!out) return VI_ERR_ARG;
  *out = NULL;
  if (!fe) return VI_ERR_ARG;
  if (!fe->frozen) return VI_ERR_STATE;
  int k = fe->k, st;
  double *K = calloc((size_t)k * k, sizeof(double));
  if (!K) return VI_ERR_NOMEM;
  for (int j = 0; j < k; j++) K[j + (size_t)j * k] = fe->lambda[j];
  vi_model *m = NULL;
  st = vi_model_create(k, &m);
  if (!st) st = vi_model_set_stiffness(m, K, k);
  if (!st) st = vi_model_set_damping(m, fe->D, k);
  if (!st) st = vi_model_set_forcing(m, fe->omega_f, fe->Fa, fe->Fb, fe->F0);
  for (int s = 0; s < fe->ns && !st; s++)
    st = s == 0 ? vi_model_set_stop(m, fe->PsiW, fe->xs[0], fe->r[0])
                : vi_model_add_stop(m, fe->PsiW + (size_t)s * k, fe->xs[s],
                                    fe->r[s]);
  if (!st) st = vi_model_setup(m);
  free(K);
  if (st) vi_model_destroy(&m);
  *out = m;
  return st;
}

/* ---- getters -------------------------------------------------------------- */
#define FROZEN_OR(fe, v) (((fe) && (fe)->frozen) ? (v) : 0)

int vi_fe_n(const vi_fe *fe) { return fe ? fe->n : 0; }
int vi_fe_num_modes(const vi_fe *fe) { return fe ? fe->k : 0; }
const double *vi_fe_omega(const vi_fe *fe) { return FROZEN_OR(fe, fe->omega); }
double vi_fe_shift(const vi_fe *fe) { return FROZEN_OR(fe, fe->shift); }
double vi_fe_residual(const vi_fe *fe) { return FROZEN_OR(fe, fe->resid); }

const double *vi_fe_modal_damping(const vi_fe *fe, int *ld)
{
  if (ld) *ld = fe ? fe->k : 0;
  return FROZEN_OR(fe, fe->D);
}

const double *vi_fe_modal_stops(const vi_fe *fe, int *ld)
{
  if (ld) *ld = fe ? fe->k : 0;
  return FROZEN_OR(fe, fe->PsiW);
}

const double *vi_fe_output_shapes(const vi_fe *fe, int *ld)
{
  if (ld) *ld = fe ? fe->nout : 0;
  return fe && fe->frozen && fe->nout > 0 ? fe->Pout : NULL;
}

const double *vi_fe_shapes(const vi_fe *fe, int *ld)
{
  if (ld) *ld = fe ? fe->n : 0;
  return FROZEN_OR(fe, fe->Psi);
}

int vi_fe_summary(const vi_fe *fe, int *massless, int *rigid, int *rule,
                  double *orthogonality)
{
  if (massless) *massless = 0;
  if (rigid) *rigid = 0;
  if (rule) *rule = fe ? fe->k_rule : 0;
  if (orthogonality) *orthogonality = NAN;
  if (!fe) return VI_ERR_ARG;
  if (!fe->frozen) return VI_ERR_STATE;
  if (massless) *massless = fe->n0;
  if (rigid) *rigid = fe->nrigid;
  if (orthogonality) *orthogonality = fe->orth;
  return VI_OK;
}

const double *vi_fe_mode_residuals(const vi_fe *fe)
{
  return FROZEN_OR(fe, fe->mresid);
}

const double *vi_fe_mode_rigidity(const vi_fe *fe)
{
  return FROZEN_OR(fe, fe->mrigid);
}

int vi_fe_stop_compliance(const vi_fe *fe, int s, double *dynamic,
                          double *statik)
{
  if (!fe || s < 0 || s >= fe->ns) return VI_ERR_ARG;
  if (!fe->frozen) return VI_ERR_STATE;
  if (dynamic) *dynamic = fe->wMw[s];
  if (statik) *statik = fe->wKw[s];
  return VI_OK;
}

int vi_fe_matrix_csc(const vi_fe *fe, int which, int *nnz,
                     const int **colptr, const int **rowind,
                     const double **values)
{
  if (nnz) *nnz = 0;
  if (colptr) *colptr = NULL;
  if (rowind) *rowind = NULL;
  if (values) *values = NULL;
  if (!fe || which < VI_FE_MASS || which > VI_FE_STIFFNESS) return VI_ERR_ARG;
  const vi_csc *A = &fe->mat[which];
  if (!A->colptr) return VI_ERR_STATE;
  if (nnz) *nnz = A->nnz;
  if (colptr) *colptr = A->colptr;
  if (rowind) *rowind = A->rowind;
  if (values) *values = A->val;
  return VI_OK;
}

int vi_fe_to_outputs(const vi_fe *fe, int ncol, const double *Q, int ldq,
                     double *Y, int ldy)
{
  if (!fe || !Q || !Y) return VI_ERR_ARG;
  if (!fe->frozen || fe->nout < 1) return VI_ERR_STATE;
  if (ncol < 0 || ldq < fe->k || ldy < fe->nout) return VI_ERR_DIM;
  if (ncol == 0) return VI_OK;
  if (vi_overlap2(Q, (size_t)ldq * ncol, Y, (size_t)ldy * ncol))
    return VI_ERR_ARG;
  cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, fe->nout, ncol,
              fe->k, 1.0, fe->Pout, fe->nout, Q, ldq, 0.0, Y, ldy);
  return VI_OK;
}

int vi_fe_to_modal(const vi_fe *fe, const double *x, double *q)
{
  if (!fe || !x || !q) return VI_ERR_ARG;
  if (!fe->frozen) return VI_ERR_STATE;
  if (fe->source != VI_FE_SRC_SPARSE) return VI_ERR_UNSUPPORTED;
  if (!fe->Psi) return VI_ERR_STATE; /* vi_fe_set_keep_shapes(fe, 1) */
  if (vi_overlap2(x, (size_t)fe->n, q, (size_t)fe->k)) return VI_ERR_ARG;
  double *Mx = malloc(sizeof(double) * (size_t)fe->n);
  if (!Mx) return VI_ERR_NOMEM;
  vi_csc_symv(fe->n, &fe->mat[VI_FE_MASS], x, Mx);
  cblas_dgemv(CblasColMajor, CblasTrans, fe->n, fe->k, 1.0, fe->Psi, fe->n,
              Mx, 1, 0.0, q, 1);
  free(Mx);
  return VI_OK;
}

int vi_fe_memory_estimate(int n, int64_t nnz, int k, int keep,
                          int64_t *bytes)
{
  if (!bytes) return VI_ERR_ARG;
  *bytes = 0;
  if (n < 1 || k < 1 || k > n || nnz < 0) return VI_ERR_DIM;
  if (keep != 0 && keep != 1) return VI_ERR_ARG;
  double dn = n, dk = k, ncv = fmin(dn, vi_fe_default_ncv(k));
  /* three CSC copies (12 bytes an entry, colptr) and the caller's arrays
   * for K - sigma M; the Lanczos basis V [n x ncv], workd [3n], the
   * eigenvectors Z [n x k], the solver's vectors (4n) and the full Psi */
  double b = 3.0 * (12.0 * (double)nnz + 4.0 * dn) + 2.0 * 12.0 * (double)nnz +
             8.0 * (dn * ncv + 3.0 * dn + dn * dk + 4.0 * dn +
                    ncv * (ncv + 8.0)) +
             (keep ? 8.0 * dn * dk : 0.0) + 65536.0;
  if (!(b < 9.0e18)) return VI_ERR_LIMIT;
  *bytes = (int64_t)b;
  return VI_OK;
}

/* ---- a model straight from a host's modes --------------------------------- */

int vi_model_create_modal(int k, const double *omega, const double *zeta,
                          const double *D, int ldd, vi_model **out)
{
  if (!out) return VI_ERR_ARG;
  *out = NULL;
  if (k < 1 || (D && ldd < k)) return VI_ERR_DIM;
  if (!omega || (zeta && D)) return VI_ERR_ARG;
  for (int j = 0; j < k; j++) {
    if (!isfinite(omega[j]) || (zeta && !isfinite(zeta[j])))
      return VI_ERR_NONFINITE;
    if (omega[j] < 0.0 || (zeta && zeta[j] < 0.0)) return VI_ERR_ARG;
  }
  double *K = calloc(2 * (size_t)k * k, sizeof(double));
  if (!K) return VI_ERR_NOMEM;
  double *C = K + (size_t)k * k;
  for (int j = 0; j < k; j++) {
    K[j + (size_t)j * k] = omega[j] * omega[j];
    if (zeta) C[j + (size_t)j * k] = 2.0 * zeta[j] * omega[j];
  }
  vi_model *m = NULL;
  int st = vi_model_create(k, &m);
  if (!st) st = vi_model_set_stiffness(m, K, k);
  if (!st) st = D ? vi_model_set_damping(m, D, ldd)
                  : vi_model_set_damping(m, C, k);
  free(K);
  if (st) vi_model_destroy(&m);
  *out = m;
  return st;
}
