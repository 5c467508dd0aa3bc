/* vi_eigs.c - the k lowest modes of K psi = lambda M psi for sparse M, K
 * (vi_sparse.h): shift-invert Lanczos, ARPACK-ng dsaupd/dseupd in mode 3
 * (OP = (K - sigma M)^-1 M, B = M), on a CHOLMOD factorisation of
 * K - sigma M.  A reduction keeping (nearly) every mode takes LAPACK's dense
 * dsygvd instead, where Lanczos has no room.  MODEL.md section 5. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <arpack.h>
#include <cblas.h>
#include <cholmod.h>
#include <lapacke.h>

#include "vi_fe_internal.h"

/* A factor's pivots below this ratio (cholmod_rcond: min/max of the
 * diagonal of D, or of L squared) mark K as singular to working precision:
 * a free structure, whose rigid-body modes need a negative shift. */
#define VI_EIGS_SINGULAR 1e-13
/* The automatic negative shift, relative to the scale max_j K_jj / M_jj of
 * the spectrum (~lambda_max / 4 for linear elements): below the first
 * elastic eigenvalue of 1-D meshes up to ~5e4 elements (lambda_1 / scale
 * ~ 3 / N^2) and of any 2-D or 3-D mesh of practical size, and within a few
 * lambda_1 up to 1e5 (a shift of a few lambda_1 hardly slows Lanczos),
 * while cond(K - sigma M) <= scale / |sigma| = 1e9 keeps the solves
 * accurate. */
#define VI_EIGS_AUTO_SHIFT 1e-9
/* Eigenvalues within this fraction of the scale are rigid-body modes
 * (round-off of zero: eps times cond of the factorised operator). */
#define VI_EIGS_ZERO 1e-13
/* Largest n for the dense fallback (dsygvd on n x n). */
#define VI_EIGS_DENSE_MAX 4000

/* A stored matrix as CHOLMOD's symmetric (lower, stype -1) view: no copy. */
static void wrap(int n, vi_csc *A, cholmod_sparse *S)
{
  memset(S, 0, sizeof *S);
  S->nrow = S->ncol = (size_t)n;
  S->nzmax = (size_t)(A->nnz > 0 ? A->nnz : 1);
  S->p = A->colptr;
  S->i = A->rowind;
  S->x = A->val;
  S->stype = -1;
  S->itype = CHOLMOD_INT;
  S->xtype = CHOLMOD_REAL;
  S->dtype = CHOLMOD_DOUBLE;
  S->sorted = 1;
  S->packed = 1;
}

static void wrap_dense(int n, double *x, cholmod_dense *B)
{
  memset(B, 0, sizeof *B);
  B->nrow = (size_t)n;
  B->ncol = 1;
  B->nzmax = (size_t)n;
  B->d = (size_t)n;
  B->x = x;
  B->xtype = CHOLMOD_REAL;
  B->dtype = CHOLMOD_DOUBLE;
}

/* Factorise A: 0 on success, 1 if A is not positive definite (*minor the
 * 1-based column), a (negative) vi status otherwise.  *rcond receives the pivot ratio. */
static int factor(vi_fe *fe, const char *what, cholmod_sparse *A,
                  cholmod_common *c, cholmod_factor **pL, double *rcond,
                  int *minor)
{
  *pL = NULL;
  *minor = 0;
  *rcond = 0.0;
  cholmod_factor *L = cholmod_analyze(A, c);
  if (!L)
    return vi_fail(fe->errmsg, c->status == CHOLMOD_OUT_OF_MEMORY
                                   ? VI_ERR_NOMEM : VI_ERR_LIMIT,
                   "%s: CHOLMOD's analysis fails (status %d)", what,
                   c->status);
  /* the factor's size is known now, before its numeric values exist */
  double bytes = c->lnz * 12.0 + 64.0 * (double)A->nrow;
  if (fe->mem_limit > 0 && bytes > (double)fe->mem_limit) {
    cholmod_free_factor(&L, c);
    return vi_fail(fe->errmsg, VI_ERR_LIMIT, "%s: the sparse factor needs "
                   "%.0f bytes (%.0f non-zeros), above the limit of %lld",
                   what, bytes, c->lnz, (long long)fe->mem_limit);
  }
  cholmod_factorize(A, L, c);
  if (c->status == CHOLMOD_NOT_POSDEF) {
    *minor = (int)L->minor + 1;
  } else if (c->status < CHOLMOD_OK) {
    int code = c->status == CHOLMOD_OUT_OF_MEMORY ? VI_ERR_NOMEM : VI_ERR_LIMIT;
    cholmod_free_factor(&L, c);
    return vi_fail(fe->errmsg, code, "%s: CHOLMOD's factorisation fails "
                   "(status %d)", what, c->status);
  } else if (!L->is_super && !L->is_ll) {
    /* a simplicial LDL' stops only at zero pivots: test D's signs here */
    const int *p = L->p;
    const double *x = L->x;
    for (size_t j = 0; j < L->n && !*minor; j++)
      if (!(x[p[j]] > 0.0)) *minor = (int)j + 1;
  }
  if (*minor) {
    cholmod_free_factor(&L, c);
    return 1;
  }
  *rcond = cholmod_rcond(L, c);
  *pL = L;
  return VI_OK;
}

/* x [n] = A^-1 b for a factor (X, Y, E: CHOLMOD's reusable workspace). */
static int solve(int n, cholmod_factor *L, double *b, double *x,
                 cholmod_dense **X, cholmod_dense **Y, cholmod_dense **E,
                 cholmod_common *c)
{
  cholmod_dense B;
  wrap_dense(n, b, &B);
  if (!cholmod_solve2(CHOLMOD_A, L, &B, NULL, X, NULL, Y, E, c)) return -1;
  memcpy(x, (*X)->x, sizeof(double) * (size_t)n);
  return 0;
}

/* w_s^T A^-1 w_s for every stop. */
static int compliances(vi_fe *fe, cholmod_factor *L, cholmod_common *c,
                       double *out)
{
  int n = fe->n, st = VI_OK;
  double *x = malloc(sizeof(double) * (size_t)n);
  cholmod_dense *X = NULL, *Y = NULL, *E = NULL;
  if (!x) return vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory");
  for (int s = 0; s < fe->ns && !st; s++) {
    double *w = fe->W + (size_t)s * n;
    if (solve(n, L, w, x, &X, &Y, &E, c))
      st = vi_fail(fe->errmsg, VI_ERR_NOMEM, "CHOLMOD solve fails");
    else
      out[s] = cblas_ddot(n, w, 1, x, 1);
  }
  cholmod_free_dense(&X, c);
  cholmod_free_dense(&Y, c);
  cholmod_free_dense(&E, c);
  free(x);
  return st;
}

/* Mass-normalise, sign (largest-magnitude entry positive, as vi_modal.c)
 * and sort ascending the k eigenpairs (lam, Z [n x k]); snap round-off of
 * rigid-body modes to 0, refuse a negative eigenvalue beyond it, and
 * measure the residuals. */
static int finish(vi_fe *fe, double scale, double *lam, double *Z,
                  double *Psi)
{
  int n = fe->n, k = fe->k;
  const vi_csc *M = &fe->mat[VI_FE_MASS], *K = &fe->mat[VI_FE_STIFFNESS];
  int *ord = malloc(sizeof(int) * (size_t)k);
  double *t = malloc(sizeof(double) * 2 * (size_t)n);
  if (!ord || !t) {
    free(ord);
    free(t);
    return vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory");
  }
  for (int j = 0; j < k; j++) ord[j] = j;
  for (int j = 1; j < k; j++) /* insertion sort: k is small */
    for (int i = j; i > 0 && lam[ord[i]] < lam[ord[i - 1]]; i--) {
      int tmp = ord[i];
      ord[i] = ord[i - 1];
      ord[i - 1] = tmp;
    }
  /* ||K||, ||M|| (infinity norms = column sums of the symmetric matrices) */
  double nk = 0.0, nm = 0.0;
  for (int i = 0; i < n; i++) t[i] = t[n + i] = 0.0;
  for (int j = 0; j < n; j++)
    for (int p = K->colptr[j]; p < K->colptr[j + 1]; p++) {
      t[j] += fabs(K->val[p]);
      if (K->rowind[p] != j) t[K->rowind[p]] += fabs(K->val[p]);
    }
  for (int j = 0; j < n; j++)
    for (int p = M->colptr[j]; p < M->colptr[j + 1]; p++) {
      t[n + j] += fabs(M->val[p]);
      if (M->rowind[p] != j) t[n + M->rowind[p]] += fabs(M->val[p]);
    }
  for (int i = 0; i < n; i++) {
    nk = fmax(nk, t[i]);
    nm = fmax(nm, t[n + i]);
  }
  int st = VI_OK;
  fe->resid = 0.0;
  for (int jj = 0; jj < k && !st; jj++) {
    double *z = Psi + (size_t)jj * n, l = lam[ord[jj]];
    memcpy(z, Z + (size_t)ord[jj] * n, sizeof(double) * (size_t)n);
    vi_csc_symv(n, M, z, t);
    double zMz = cblas_ddot(n, z, 1, t, 1);
    if (!(zMz > 0.0)) {
      st = vi_fail(fe->errmsg, VI_ERR_NOT_CONVERGED, "mode %d: zero "
                   "eigenvector from the Lanczos solver", jj + 1);
      break;
    }
    int imax = 0;
    for (int i = 1; i < n; i++)
      if (fabs(z[i]) > fabs(z[imax]) * (1.0 + 1e-12)) imax = i;
    double s = (z[imax] < 0.0 ? -1.0 : 1.0) / sqrt(zMz);
    cblas_dscal(n, s, z, 1);
    if (l < -1e-10 * scale) {
      st = vi_fail(fe->errmsg, VI_ERR_NOT_PSD, "K is not positive "
                   "semidefinite: eigenvalue %.6g of M^-1 K (scale %.6g)", l,
                   scale);
      break;
    }
    /* backward error of the pair: ||K z - l M z|| / ((||K|| + |l| ||M||)
     * ||z||), before l is snapped */
    vi_csc_symv(n, M, z, t);
    vi_csc_symv(n, K, z, t + n);
    double r = 0.0, zn = 0.0;
    for (int i = 0; i < n; i++) {
      r = fmax(r, fabs(t[n + i] - l * t[i]));
      zn = fmax(zn, fabs(z[i]));
    }
    r /= (nk + fabs(l) * nm) * zn;
    fe->resid = fmax(fe->resid, r);
    if (fabs(l) <= VI_EIGS_ZERO * scale) l = 0.0;
    fe->lambda[jj] = l;
    fe->omega[jj] = sqrt(l);
  }
  free(ord);
  free(t);
  return st;
}

/* Every mode from LAPACK's dense dsygvd (k >= n - 1: no room for Lanczos);
 * the compliances from all n modes: M^-1 = Psi Psi^T, K^-1 = Psi L^-1
 * Psi^T. */
static int eigs_dense(vi_fe *fe, double scale, double *Psi)
{
  int n = fe->n, k = fe->k, st = VI_OK;
  if (n > VI_EIGS_DENSE_MAX)
    return vi_fail(fe->errmsg, VI_ERR_DIM, "%d modes of %d dofs: keep at "
                   "most n - 2 for the sparse solver", k, n);
  size_t nn = (size_t)n * n;
  double *A = calloc(2 * nn + (size_t)n, sizeof(double));
  if (!A) return vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory");
  double *B = A + nn, *lam = B + nn;
  const vi_csc *K = &fe->mat[VI_FE_STIFFNESS], *M = &fe->mat[VI_FE_MASS];
  for (int j = 0; j < n; j++) {
    for (int p = K->colptr[j]; p < K->colptr[j + 1]; p++)
      A[K->rowind[p] + (size_t)j * n] = K->val[p];
    for (int p = M->colptr[j]; p < M->colptr[j + 1]; p++)
      B[M->rowind[p] + (size_t)j * n] = M->val[p];
  }
  lapack_int info = LAPACKE_dsygvd(LAPACK_COL_MAJOR, 1, 'V', 'L', n, A, n, B,
                                   n, lam);
  if (info > n) {
    st = vi_fail(fe->errmsg, VI_ERR_NOT_SPD, "M is not positive definite "
                 "(Cholesky fails at column %d)", (int)info - n);
    goto cleanup;
  }
  if (info != 0) {
    st = vi_fail(fe->errmsg, VI_ERR_LAPACK, "dsygvd failed (info %d)",
                 (int)info);
    goto cleanup;
  }
  /* compliances over all n modes, before the truncation to k */
  for (int s = 0; s < fe->ns; s++) {
    double dyn = 0.0, sta = 0.0;
    for (int j = 0; j < n; j++) {
      double ps = cblas_ddot(n, A + (size_t)j * n, 1, fe->W + (size_t)s * n, 1);
      dyn += ps * ps;
      if (lam[j] > VI_EIGS_ZERO * scale) sta += ps * ps / lam[j];
      else sta = HUGE_VAL;
    }
    fe->wMw[s] = dyn;
    fe->wKw[s] = sta;
  }
  fe->shift = 0.0;
  st = finish(fe, scale, lam, A, Psi);
cleanup:
  free(A);
  return st;
}

/* The ARPACK reverse-communication loop on the factor L of K - sigma M. */
static int lanczos(vi_fe *fe, cholmod_factor *L, cholmod_common *c,
                   double scale, double *Psi)
{
  int n = fe->n, k = fe->k, st = VI_OK;
  int ncv = fe->ncv > 0 ? fe->ncv : (2 * k + 1 > k + 20 ? 2 * k + 1 : k + 20);
  if (ncv > n) ncv = n;
  if (ncv <= k)
    return vi_fail(fe->errmsg, VI_ERR_DIM, "Lanczos basis ncv = %d must "
                   "exceed the %d kept modes", ncv, k);
  int lworkl = ncv * (ncv + 8);
  size_t need = (size_t)n * ncv + 4 * (size_t)n + (size_t)lworkl +
                (size_t)n * k + (size_t)k + (size_t)n;
  double *V = malloc(sizeof(double) * need);
  a_int *sel = malloc(sizeof(a_int) * (size_t)ncv);
  cholmod_dense *X = NULL, *Y = NULL, *E = NULL;
  if (!V || !sel) {
    free(V);
    free(sel);
    return vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory for the Lanczos "
                   "basis (%d x %d)", n, ncv);
  }
  double *workd = V + (size_t)n * ncv, *resid = workd + 3 * (size_t)n;
  double *workl = resid + n, *Z = workl + lworkl, *lam = Z + (size_t)n * k;
  double *tmp = lam + k;
  /* a fixed start vector, so that a setup is reproducible (ARPACK's own
   * random one depends on its saved seed) with components in every mode */
  unsigned long h = 12345u;
  for (int i = 0; i < n; i++) {
    h = h * 6364136223846793005ul + 1442695040888963407ul;
    resid[i] = 0.5 + (double)(h >> 33) / 8589934592.0;
  }
  a_int ido = 0, info = 1, iparam[11] = {0}, ipntr[14] = {0};
  iparam[0] = 1; /* exact shifts */
  iparam[2] = fe->maxit > 0 ? fe->maxit : 1000;
  iparam[6] = 3; /* shift-invert, generalised */
  double tol = fe->tol;
  for (;;) {
    dsaupd_c(&ido, "G", n, "LM", k, tol, resid, ncv, V, n, iparam, ipntr,
             workd, workl, lworkl, &info);
    if (ido == 99 || info < 0) break;
    double *x = workd + ipntr[0] - 1, *y = workd + ipntr[1] - 1;
    int bad = 0;
    if (ido == -1) { /* y = OP x = (K - sigma M)^-1 M x */
      vi_csc_symv(n, &fe->mat[VI_FE_MASS], x, tmp);
      bad = solve(n, L, tmp, y, &X, &Y, &E, c);
    } else if (ido == 1) { /* M x is given */
      bad = solve(n, L, workd + ipntr[2] - 1, y, &X, &Y, &E, c);
    } else if (ido == 2) {
      vi_csc_symv(n, &fe->mat[VI_FE_MASS], x, y);
    } else {
      st = vi_fail(fe->errmsg, VI_ERR_UNSUPPORTED, "ARPACK asks for "
                   "operation %d", (int)ido);
      goto cleanup;
    }
    if (bad) {
      st = vi_fail(fe->errmsg, VI_ERR_NOMEM, "CHOLMOD solve fails (status "
                   "%d)", c->status);
      goto cleanup;
    }
  }
  if (info == 1 || info == 3) {
    st = vi_fail(fe->errmsg, VI_ERR_NOT_CONVERGED, "Lanczos: %d of %d modes "
                 "converged in %d restarts (raise maxit or ncv with "
                 "vi_fe_set_eigensolver)", (int)iparam[4], k, (int)iparam[2]);
    goto cleanup;
  }
  if (info != 0) {
    st = vi_fail(fe->errmsg, VI_ERR_LAPACK, "ARPACK dsaupd fails (info %d)",
                 (int)info);
    goto cleanup;
  }
  dseupd_c(1, "A", sel, lam, Z, n, fe->shift, "G", n, "LM", k, tol, resid,
           ncv, V, n, iparam, ipntr, workd, workl, lworkl, &info);
  if (info != 0) {
    st = vi_fail(fe->errmsg, VI_ERR_LAPACK, "ARPACK dseupd fails (info %d)",
                 (int)info);
    goto cleanup;
  }
  if (iparam[4] < k) {
    st = vi_fail(fe->errmsg, VI_ERR_NOT_CONVERGED, "Lanczos: %d of %d modes "
                 "converged", (int)iparam[4], k);
    goto cleanup;
  }
  st = finish(fe, scale, lam, Z, Psi);
cleanup:
  cholmod_free_dense(&X, c);
  cholmod_free_dense(&Y, c);
  cholmod_free_dense(&E, c);
  free(V);
  free(sel);
  return st;
}

/* The scale max_j K_jj / M_jj of the spectrum; a non-positive M_jj is
 * refused (M cannot be positive definite). */
static int spectrum_scale(vi_fe *fe, double *scale)
{
  const vi_csc *M = &fe->mat[VI_FE_MASS], *K = &fe->mat[VI_FE_STIFFNESS];
  double s = 0.0;
  for (int j = 0; j < fe->n; j++) {
    /* sorted lower storage: the diagonal, if stored, comes first */
    int pm = M->colptr[j], pk = K->colptr[j];
    double mjj = pm < M->colptr[j + 1] && M->rowind[pm] == j ? M->val[pm] : 0;
    double kjj = pk < K->colptr[j + 1] && K->rowind[pk] == j ? K->val[pk] : 0;
    if (!(mjj > 0.0))
      return vi_fail(fe->errmsg, VI_ERR_NOT_SPD, "M is not positive "
                     "definite: M(%d,%d) = %g", j + 1, j + 1, mjj);
    s = fmax(s, kjj / mjj);
  }
  *scale = s > 0.0 ? s : 1.0;
  return VI_OK;
}

int vi_fe_eigs(vi_fe *fe, double **pPsi)
{
  int n = fe->n, k = fe->k, st = VI_OK, minor;
  double scale = 1.0, rcond = 0.0;
  *pPsi = NULL;
  if ((st = spectrum_scale(fe, &scale))) return st;
  double *Psi = malloc(sizeof(double) * (size_t)n * k);
  if (!Psi) return vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory for "
                           "Psi (%d x %d)", n, k);
  if (k >= n - 1) {
    st = eigs_dense(fe, scale, Psi);
    if (st) free(Psi);
    else *pPsi = Psi;
    return st;
  }
  cholmod_common cm, *c = &cm;
  cholmod_start(c);
  c->print = 0; /* the library never prints: statuses are read below */
  c->error_handler = NULL;
  cholmod_sparse Ms, Ks, *A = NULL;
  cholmod_factor *L = NULL;
  wrap(n, &fe->mat[VI_FE_MASS], &Ms);
  wrap(n, &fe->mat[VI_FE_STIFFNESS], &Ks);

  /* M positive definite, and the stops' compliance w^T M^-1 w (WB 10) */
  st = factor(fe, "M", &Ms, c, &L, &rcond, &minor);
  if (st == 1)
    st = vi_fail(fe->errmsg, VI_ERR_NOT_SPD, "M is not positive definite "
                 "(the sparse Cholesky factorisation fails at column %d)",
                 minor);
  if (!st) st = compliances(fe, L, c, fe->wMw);
  cholmod_free_factor(&L, c);
  if (st) goto cleanup;

  /* K itself first: a fixed structure factorises with sigma = 0, and its
   * factor gives the static compliance w^T K^-1 w too */
  int k_ok = 0;
  if (!fe->shift_set || fe->sigma_in == 0.0) {
    st = factor(fe, "K", &Ks, c, &L, &rcond, &minor);
    if (st < 0) goto cleanup;
    k_ok = st == 0 && rcond > VI_EIGS_SINGULAR;
    if (st == 0 && !k_ok) cholmod_free_factor(&L, c);
    if (fe->shift_set && !k_ok) {
      st = vi_fail(fe->errmsg, VI_ERR_NOT_SPD, "K is singular or not "
                   "positive definite (column %d, pivot ratio %.3g): the "
                   "shift sigma = 0 must lie below the lowest eigenvalue; "
                   "a free structure needs sigma < 0", minor, rcond);
      goto cleanup;
    }
  }
  if (k_ok) {
    if ((st = compliances(fe, L, c, fe->wKw))) goto cleanup;
    fe->shift = 0.0;
  } else {
    for (int s = 0; s < fe->ns; s++) fe->wKw[s] = HUGE_VAL;
    fe->shift = fe->shift_set ? fe->sigma_in : -VI_EIGS_AUTO_SHIFT * scale;
    if (fe->shift_set) { /* a user's shift: K may still be regular */
      st = factor(fe, "K", &Ks, c, &L, &rcond, &minor);
      if (st < 0) goto cleanup;
      if (st == 0 && rcond > VI_EIGS_SINGULAR &&
          (st = compliances(fe, L, c, fe->wKw)))
        goto cleanup;
      cholmod_free_factor(&L, c);
    }
    double alpha[2] = {1.0, 0.0}, beta[2] = {-fe->shift, 0.0};
    A = cholmod_add(&Ks, &Ms, alpha, beta, 1, 1, c);
    if (!A) {
      st = vi_fail(fe->errmsg, VI_ERR_NOMEM, "K - sigma M: CHOLMOD fails "
                   "(status %d)", c->status);
      goto cleanup;
    }
    st = factor(fe, "K - sigma M", A, c, &L, &rcond, &minor);
    if (st == 1) {
      st = fe->shift_set
               ? vi_fail(fe->errmsg, VI_ERR_NOT_SPD, "K - sigma M is not "
                         "positive definite (column %d) with sigma = %.6g: "
                         "the shift must lie below the lowest eigenvalue",
                         minor, fe->shift)
               : vi_fail(fe->errmsg, VI_ERR_NOT_PSD, "K is not positive "
                         "semidefinite: K - sigma M with sigma = %.6g fails "
                         "at column %d", fe->shift, minor);
    }
    if (st) goto cleanup;
  }
  st = lanczos(fe, L, c, scale, Psi);
cleanup:
  cholmod_free_factor(&L, c);
  if (A) cholmod_free_sparse(&A, c);
  cholmod_finish(c);
  if (st) free(Psi);
  else *pPsi = Psi;
  return st;
}
