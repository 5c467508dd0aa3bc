/* vi_eigs.c - the k lowest modes of K psi = lambda M psi for sparse M, K
 * (vi_sparse.h): shift-invert Lanczos, ARPACK-ng dsaupd/dseupd in mode 3
 * (OP = (K - sigma M)^-1 M, B = M), on a CHOLMOD factorisation of
 * K - sigma M.  A reduction keeping (nearly) every mode takes LAPACK's dense
 * dsygvd instead, where Lanczos has no room.  MODEL.md section 5.
 *
 * M need only be semidefinite: FE codes write lumped masses with massless
 * dofs (zero rows and columns).  Their eigenvalues are infinite; shift-invert
 * maps them to 0, so Lanczos never meets them, and the dense path condenses
 * them statically first.  Whether a
 * mode is rigid is read off the mode itself: K psi at round-off, row by row
 * (a stiff and a soft layer side by side make K's norm useless for it). */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include <arpack.h>
#include <cblas.h>
#include <cholmod.h>
#include <lapacke.h>

#include "vi_fe_internal.h"
#include "vi_model_internal.h"

/* A pivot of K's factor below this fraction of its own diagonal entry
 * K_jj marks K as singular to working precision (a free structure, whose
 * rigid-body modes need a negative shift).  Relative to K_jj, not to the
 * largest pivot: stiff and soft parts of one structure differ by many
 * orders without K being any nearer to singular. */
#define VI_EIGS_SINGULAR 1e-13
/* The automatic negative shift, relative to the scale max_j K_jj / M_jj of
 * the spectrum (~lambda_max / 4 for linear elements): below the first
 * elastic eigenvalue of 1-D meshes up to ~5e4 elements and of any 2-D or
 * 3-D mesh of practical size, while cond(K - sigma M) <= scale / |sigma| =
 * 1e9 keeps the solves accurate. */
#define VI_EIGS_AUTO_SHIFT 1e-9
/* A mode is rigid when every row of K psi is below this multiple of the
 * round-off of its own products, |K| |psi| (Oettli-Prager).  A computed
 * rigid mode sits at 1e-16..1e-13; the first elastic mode of a 1-D mesh of
 * N elements at ~(pi / N)^2 / 4, 2.5e-10 for N = 1e5. */
#define VI_EIGS_RIGID 1e-11
/* Largest n for the dense path (dsygvd on n x n). */
#define VI_EIGS_DENSE_MAX 4000

/* ARPACK keeps its reverse-communication state in SAVE variables: two
 * Lanczos loops at once in one process corrupt each other (a heap overrun
 * in a CHOLMOD buffer, seen).  The one lock serialises them. */
static pthread_mutex_t arpack_lock = PTHREAD_MUTEX_INITIALIZER;

/* A stored matrix as CHOLMOD's symmetric (lower, stype -1) view: no copy. */
static void wrap(int n, const vi_csc *A, cholmod_sparse *S)
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

/* The diagonal entry of column j of a stored matrix (0 when not stored):
 * sorted lower storage puts it first. */
static double diag_of(const vi_csc *A, int j)
{
  int p = A->colptr[j];
  return p < A->colptr[j + 1] && A->rowind[p] == j ? A->val[p] : 0.0;
}

/* The principal submatrix of A on the dofs with map[i] >= 0 (their new
 * numbers, increasing with i, so that lower storage stays sorted). */
static int csc_sub(int n, const vi_csc *A, const int *map, int m, vi_csc *S)
{
  memset(S, 0, sizeof *S);
  int nnz = 0;
  for (int j = 0; j < n; j++)
    if (map[j] >= 0)
      for (int p = A->colptr[j]; p < A->colptr[j + 1]; p++)
        nnz += map[A->rowind[p]] >= 0;
  S->colptr = malloc(sizeof(int) * ((size_t)m + 1));
  S->rowind = malloc(sizeof(int) * (size_t)(nnz > 0 ? nnz : 1));
  S->val = malloc(sizeof(double) * (size_t)(nnz > 0 ? nnz : 1));
  if (!S->colptr || !S->rowind || !S->val) return -1;
  int q = 0;
  S->colptr[0] = 0;
  for (int j = 0; j < n; j++) {
    if (map[j] < 0) continue;
    for (int p = A->colptr[j]; p < A->colptr[j + 1]; p++)
      if (map[A->rowind[p]] >= 0) {
        S->rowind[q] = map[A->rowind[p]];
        S->val[q++] = A->val[p];
      }
    S->colptr[map[j] + 1] = q;
  }
  S->nnz = nnz;
  return 0;
}

static void csc_release(vi_csc *S)
{
  free(S->colptr);
  free(S->rowind);
  free(S->val);
  memset(S, 0, sizeof *S);
}

/* The smallest pivot of a factor of A relative to A's own diagonal entry
 * in that column: d_j / A_jj (LDL') or L_jj^2 / A_jj (LL'), in the factor's
 * permuted order. */
static double min_rel_pivot(const cholmod_factor *L, const vi_csc *A)
{
  const int *perm = L->Perm;
  const double *x = L->x;
  double r = HUGE_VAL;
  if (L->is_super) {
    const int *super = L->super, *pi = L->pi, *px = L->px;
    for (size_t s = 0; s < L->nsuper; s++) {
      int k1 = super[s], nrow = pi[s + 1] - pi[s];
      for (int j = k1; j < super[s + 1]; j++) {
        double l = x[px[s] + (j - k1) + (size_t)(j - k1) * nrow];
        double a = diag_of(A, perm ? perm[j] : j);
        if (a > 0.0) r = fmin(r, l * l / a);
      }
    }
  } else {
    const int *p = L->p;
    for (size_t j = 0; j < L->n; j++) {
      double d = x[p[j]], a = diag_of(A, perm ? perm[j] : (int)j);
      if (a > 0.0) r = fmin(r, L->is_ll ? d * d / a : d / a);
    }
  }
  return r;
}

/* Factorise A: 0 on success, 1 if A is not positive definite (*minor the
 * 1-based column), a (negative) vi status otherwise.  *relpiv receives the
 * smallest pivot relative to A's diagonal (min_rel_pivot). */
static int factor(vi_fe *fe, const char *what, cholmod_sparse *A,
                  const vi_csc *Acsc, cholmod_common *c, cholmod_factor **pL,
                  double *relpiv, int *minor)
{
  *pL = NULL;
  *minor = 0;
  *relpiv = 0.0;
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
  *relpiv = Acsc ? min_rel_pivot(L, Acsc) : cholmod_rcond(L, c);
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

/* v_s^T A^-1 v_s for every stop s, v_s = the stop vector gathered by map
 * (map NULL: w_s itself; else w_s at the dofs with map[i] >= 0, of which
 * there are m). */
static int compliances(vi_fe *fe, cholmod_factor *L, cholmod_common *c,
                       const int *map, int m, const double *V, double *out)
{
  int n = fe->n, st = VI_OK;
  double *x = malloc(sizeof(double) * 2 * (size_t)n);
  cholmod_dense *X = NULL, *Y = NULL, *E = NULL;
  if (!x) return vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory");
  double *b = x + n;
  for (int s = 0; s < fe->ns && !st; s++) {
    const double *w = (V ? V : fe->W) + (size_t)s * n;
    if (map)
      for (int i = 0; i < n; i++) {
        if (map[i] >= 0) b[map[i]] = w[i];
      }
    else
      memcpy(b, w, sizeof(double) * (size_t)n);
    if (solve(map ? m : n, L, b, x, &X, &Y, &E, c))
      st = vi_fail(fe->errmsg, VI_ERR_NOMEM, "CHOLMOD solve fails");
    else
      out[s] = cblas_ddot(map ? m : n, b, 1, x, 1);
  }
  cholmod_free_dense(&X, c);
  cholmod_free_dense(&Y, c);
  cholmod_free_dense(&E, c);
  free(x);
  return st;
}

int vi_fe_inspect(vi_fe *fe)
{
  int n = fe->n;
  const vi_csc *M = &fe->mat[VI_FE_MASS], *K = &fe->mat[VI_FE_STIFFNESS];
  int *touch = calloc((size_t)n, sizeof(int));
  if (!touch) return vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory");
  for (int j = 0; j < n; j++) /* off-diagonal entries touch both ends */
    for (int p = M->colptr[j]; p < M->colptr[j + 1]; p++)
      if (M->rowind[p] != j && M->val[p] != 0.0)
        touch[j] = touch[M->rowind[p]] = 1;
  double s = 0.0;
  fe->n0 = 0;
  fe->first_massless = -1;
  int st = VI_OK;
  for (int j = 0; j < n && !st; j++) {
    double mjj = diag_of(M, j), kjj = diag_of(K, j);
    if (mjj < 0.0 || (mjj == 0.0 && touch[j]))
      st = vi_fail(fe->errmsg, VI_ERR_NOT_PSD, "M is not positive "
                   "semidefinite: M(%d,%d) = %g%s", j + 1, j + 1, mjj,
                   mjj < 0.0 ? "" : " while its row has non-zero entries");
    else if (kjj < 0.0)
      st = vi_fail(fe->errmsg, VI_ERR_NOT_PSD, "K is not positive "
                   "semidefinite: K(%d,%d) = %g", j + 1, j + 1, kjj);
    else if (mjj == 0.0 && kjj == 0.0)
      st = vi_fail(fe->errmsg, VI_ERR_NOT_SPD, "dof %d has neither mass "
                   "nor stiffness (M and K are zero in its row): remove it",
                   j + 1);
    else if (mjj == 0.0) {
      if (fe->n0++ == 0) fe->first_massless = j;
    } else {
      s = fmax(s, kjj / mjj);
    }
  }
  free(touch);
  if (!st && fe->n0 == n)
    st = vi_fail(fe->errmsg, VI_ERR_NOT_SPD, "M is zero: no dof has mass");
  fe->scale = s > 0.0 ? s : 1.0;
  return st;
}

/* Every stop's compliance w^T M^-1 w (WB 10) over the finite modes.  With
 * massless dofs z, the massive ones m carry the motion and x_z = -K_zz^-1
 * K_zm x_m: the stop sees t = w_m - K_mz K_zz^-1 w_z through M_mm, so
 * w^T M^-1 w becomes t^T M_mm^-1 t (static condensation). */
static int mass_compliance(vi_fe *fe, cholmod_common *c)
{
  int n = fe->n, st = VI_OK, minor;
  double piv;
  cholmod_sparse S;
  cholmod_factor *L = NULL;
  if (fe->n0 == 0) {
    wrap(n, &fe->mat[VI_FE_MASS], &S);
    st = factor(fe, "M", &S, NULL, c, &L, &piv, &minor);
    if (st == 1)
      st = vi_fail(fe->errmsg, VI_ERR_NOT_SPD, "M is not positive definite "
                   "(the sparse Cholesky factorisation fails at column %d)",
                   minor);
    if (!st) st = compliances(fe, L, c, NULL, 0, NULL, fe->wMw);
    cholmod_free_factor(&L, c);
    return st;
  }
  int nz = fe->n0, nm = n - nz;
  int *mmap = calloc(2 * (size_t)n, sizeof(int));
  double *T = malloc(sizeof(double) * (2 * (size_t)n + (size_t)n * fe->ns));
  vi_csc Mmm = {0}, Kzz = {0};
  if (!mmap || !T) {
    st = vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory");
    goto done;
  }
  int *zmap = mmap + n;
  for (int j = 0, a = 0, b = 0; j < n; j++) {
    int massless = diag_of(&fe->mat[VI_FE_MASS], j) == 0.0;
    mmap[j] = massless ? -1 : a++;
    zmap[j] = massless ? b++ : -1;
  }
  if (csc_sub(n, &fe->mat[VI_FE_MASS], mmap, nm, &Mmm) ||
      csc_sub(n, &fe->mat[VI_FE_STIFFNESS], zmap, nz, &Kzz)) {
    st = vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory");
    goto done;
  }
  /* t_s = w_s - K [K_zz^-1 w_z; 0], kept on the massive rows below */
  double *u = T, *y = T + n, *V = T + 2 * (size_t)n;
  wrap(nz, &Kzz, &S);
  st = factor(fe, "K on the massless dofs", &S, &Kzz, c, &L, &piv, &minor);
  if (st == 1)
    st = vi_fail(fe->errmsg, VI_ERR_NOT_SPD, "the %d massless dofs cannot "
                 "be condensed: their own stiffness K_zz is singular (a "
                 "mechanism without mass), column %d of it", nz, minor);
  cholmod_dense *X = NULL, *Y = NULL, *E = NULL;
  for (int s = 0; s < fe->ns && !st; s++) {
    const double *w = fe->W + (size_t)s * n;
    double *t = V + (size_t)s * n;
    for (int i = 0; i < n; i++)
      if (zmap[i] >= 0) y[zmap[i]] = w[i];
    if (solve(nz, L, y, u, &X, &Y, &E, c)) {
      st = vi_fail(fe->errmsg, VI_ERR_NOMEM, "CHOLMOD solve fails");
      break;
    }
    for (int i = n - 1; i >= 0; i--) /* u back on the full numbering */
      y[i] = zmap[i] >= 0 ? u[zmap[i]] : 0.0;
    vi_csc_symv(n, &fe->mat[VI_FE_STIFFNESS], y, t);
    for (int i = 0; i < n; i++) t[i] = mmap[i] >= 0 ? w[i] - t[i] : 0.0;
  }
  cholmod_free_dense(&X, c);
  cholmod_free_dense(&Y, c);
  cholmod_free_dense(&E, c);
  cholmod_free_factor(&L, c);
  if (st) goto done;
  wrap(nm, &Mmm, &S);
  st = factor(fe, "M on the massive dofs", &S, NULL, c, &L, &piv, &minor);
  if (st == 1)
    st = vi_fail(fe->errmsg, VI_ERR_NOT_SPD, "M is singular beyond its %d "
                 "massless dofs (zero rows): on the others the Cholesky "
                 "factorisation fails at their %d-th", nz, minor);
  if (!st) st = compliances(fe, L, c, mmap, nm, V, fe->wMw);
  cholmod_free_factor(&L, c);
done:
  csc_release(&Mmm);
  csc_release(&Kzz);
  free(mmap);
  free(T);
  return st;
}

/* The infinity norm of a stored symmetric matrix (its largest absolute
 * column sum). */
static double norm_inf(int n, const vi_csc *A, double *t)
{
  memset(t, 0, sizeof(double) * (size_t)n);
  for (int j = 0; j < n; j++)
    for (int p = A->colptr[j]; p < A->colptr[j + 1]; p++) {
      t[j] += fabs(A->val[p]);
      if (A->rowind[p] != j) t[A->rowind[p]] += fabs(A->val[p]);
    }
  double r = 0.0;
  for (int i = 0; i < n; i++) r = fmax(r, t[i]);
  return r;
}

/* max_i |K z|_i / (|K| |z|)_i over the rows where |K| |z| is not zero:
 * K z at the round-off of its own products (0 for an exact null vector). */
static double rigidity(int n, const vi_csc *K, const double *z, double *t)
{
  double *y = t, *a = t + n;
  memset(t, 0, sizeof(double) * 2 * (size_t)n);
  for (int j = 0; j < n; j++)
    for (int p = K->colptr[j]; p < K->colptr[j + 1]; p++) {
      int i = K->rowind[p];
      double v = K->val[p];
      y[i] += v * z[j];
      a[i] += fabs(v * z[j]);
      if (i != j) {
        y[j] += v * z[i];
        a[j] += fabs(v * z[i]);
      }
    }
  double amax = 0.0, r = 0.0;
  for (int i = 0; i < n; i++) amax = fmax(amax, a[i]);
  for (int i = 0; i < n; i++) /* rows below round-off of the largest: 0 */
    if (a[i] > 1e-300 && a[i] > 1e-14 * amax) r = fmax(r, fabs(y[i]) / a[i]);
  return r;
}

/* Mass-normalise, sign (largest-magnitude entry positive, as vi_modal.c)
 * and sort ascending the k eigenpairs (lam, Z [n x k]); decide the rigid
 * modes from K psi, refuse a negative eigenvalue that is not one, and
 * measure each mode's residual and the set's M-orthonormality. */
static int finish(vi_fe *fe, const double *lam, const double *Z, double *Psi)
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
  for (int j = 1; j < k; j++) /* insertion sort: nearly sorted already */
    for (int i = j; i > 0 && lam[ord[i]] < lam[ord[i - 1]]; i--) {
      int tmp = ord[i];
      ord[i] = ord[i - 1];
      ord[i - 1] = tmp;
    }
  double nk = norm_inf(n, K, t), nm = norm_inf(n, M, t);
  int st = VI_OK;
  fe->resid = 0.0;
  fe->nrigid = 0;
  for (int jj = 0; jj < k && !st; jj++) {
    double *z = Psi + (size_t)jj * n, l;
    memcpy(z, Z + (size_t)ord[jj] * n, sizeof(double) * (size_t)n);
    vi_csc_symv(n, M, z, t);
    double zMz = cblas_ddot(n, z, 1, t, 1);
    if (!(zMz > 0.0)) {
      st = vi_fail(fe->errmsg, VI_ERR_NOT_CONVERGED, "mode %d: zero "
                   "eigenvector from the eigensolver", jj + 1);
      break;
    }
    int imax = 0;
    for (int i = 1; i < n; i++)
      if (fabs(z[i]) > fabs(z[imax]) * (1.0 + 1e-12)) imax = i;
    double s = (z[imax] < 0.0 ? -1.0 : 1.0) / sqrt(zMz);
    cblas_dscal(n, s, z, 1);
    /* backward error of the pair: ||K z - l M z|| / ((||K|| + |l| ||M||)
     * ||z||), before l is decided */
    vi_csc_symv(n, M, z, t);
    vi_csc_symv(n, K, z, t + n);
    /* the Rayleigh quotient: the best lambda for this psi (the Ritz value
     * carries the Lanczos tolerance once more) */
    l = cblas_ddot(n, z, 1, t + n, 1) / cblas_ddot(n, z, 1, t, 1);
    double r = 0.0, zn = 0.0;
    for (int i = 0; i < n; i++) {
      r = fmax(r, fabs(t[n + i] - l * t[i]));
      zn = fmax(zn, fabs(z[i]));
    }
    r /= (nk + fabs(l) * nm) * zn;
    fe->mresid[jj] = r;
    fe->resid = fmax(fe->resid, r);
    fe->mrigid[jj] = rigidity(n, K, z, t);
    /* only a singular K has rigid modes: an elastic mode of a fine mesh
     * can have K psi as small as 1e-12 of |K| |psi| (a sandwich beam) */
    int rigid = fe->k_singular && fe->mrigid[jj] <= VI_EIGS_RIGID;
    if (fe->rigid_in >= 0 && rigid != (jj < fe->rigid_in)) {
      st = vi_fail(fe->errmsg, VI_ERR_ARG, "%d rigid-body modes stated, "
                   "but mode %d (omega^2 = %.6g) is %s: its |K psi| is %.2g "
                   "of the round-off scale |K| |psi| (rigid below %.0e)",
                   fe->rigid_in, jj + 1, l, rigid ? "rigid" : "elastic",
                   fe->mrigid[jj], VI_EIGS_RIGID);
      break;
    }
    if (rigid) {
      l = 0.0;
      fe->nrigid++;
    } else if (!(l > 0.0)) {
      st = vi_fail(fe->errmsg, VI_ERR_NOT_PSD, "K is not positive "
                   "semidefinite: mode %d has omega^2 = %.6g (scale %.6g) "
                   "while K psi is not at round-off (%.2g of |K| |psi|)",
                   jj + 1, l, fe->scale, fe->mrigid[jj]);
      break;
    }
    fe->lambda[jj] = l;
    fe->omega[jj] = sqrt(l);
  }
  free(ord);
  free(t);
  if (st) return st;
  /* M-orthonormality: max |Psi^T M Psi - I| */
  double *MP = malloc(sizeof(double) * ((size_t)n * k + (size_t)k * k));
  if (!MP) return vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory");
  double *G = MP + (size_t)n * k;
  for (int j = 0; j < k; j++)
    vi_csc_symv(n, M, Psi + (size_t)j * n, MP + (size_t)j * n);
  cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, k, k, n, 1.0, Psi, n,
              MP, n, 0.0, G, k);
  fe->orth = 0.0;
  for (int j = 0; j < k; j++)
    for (int i = 0; i < k; i++)
      fe->orth = fmax(fe->orth, fabs(G[i + (size_t)j * k] - (i == j)));
  free(MP);
  for (int j = 0; j < k; j++)
    if (fe->mresid[j] > fe->accuracy)
      return vi_fail(fe->errmsg, VI_ERR_NOT_CONVERGED, "mode %d (omega = "
                     "%.6g): residual %.2g above the accuracy %.2g asked",
                     j + 1, fe->omega[j], fe->mresid[j], fe->accuracy);
  if (fe->orth > fe->accuracy)
    return vi_fail(fe->errmsg, VI_ERR_NOT_CONVERGED, "the %d modes are "
                   "M-orthonormal only to %.2g, above the accuracy %.2g "
                   "asked", k, fe->orth, fe->accuracy);
  return VI_OK;
}

/* Every finite mode from LAPACK's dense dsygvd (k >= nf - 1: no room for
 * Lanczos).  Massless dofs z are condensed first: K_r = K_mm - K_mz X with
 * X = K_zz^-1 K_zm, the pencil (K_r, M_mm) solved, and psi = [v; -X v]
 * (the static slaving the shapes must carry). */
static int eigs_dense(vi_fe *fe, double *Psi)
{
  int n = fe->n, k = fe->k, nz = fe->n0, nm = n - nz, st = VI_OK;
  if (n > VI_EIGS_DENSE_MAX)
    return vi_fail(fe->errmsg, VI_ERR_DIM, "%d modes of %d dofs with mass: "
                   "keep at most %d for the sparse solver", k, nm, nm - 2);
  size_t nn = (size_t)n * n;
  double *A = calloc(3 * nn + (size_t)n, sizeof(double));
  double *X = malloc(sizeof(double) * ((size_t)nz * nm + 1));
  int *map = malloc(sizeof(int) * (size_t)n);
  if (!A || !map || !X) {
    free(A);
    free(X);
    free(map);
    return vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory");
  }
  /* the dofs renumbered massive first: K = [Kmm Kmz; Kzm Kzz] in A */
  double *B = A + nn, *Z = B + nn, *lam = Z + nn;
  const vi_csc *K = &fe->mat[VI_FE_STIFFNESS], *M = &fe->mat[VI_FE_MASS];
  for (int j = 0, a = 0, b = nm; j < n; j++)
    map[j] = diag_of(M, j) == 0.0 ? b++ : a++;
  for (int j = 0; j < n; j++) {
    for (int p = K->colptr[j]; p < K->colptr[j + 1]; p++) {
      int r = map[K->rowind[p]], c = map[j];
      A[r + (size_t)c * n] = A[c + (size_t)r * n] = K->val[p];
    }
    for (int p = M->colptr[j]; p < M->colptr[j + 1]; p++) {
      int r = map[M->rowind[p]], c = map[j];
      if (r < nm && c < nm)
        B[r + (size_t)c * nm] = B[c + (size_t)r * nm] = M->val[p];
    }
  }
  lapack_int info = 0;
  double *Kzz = A + (size_t)nm * n + nm, *Kzm = A + nm, *Kmz = A + (size_t)nm * n;
  if (nz > 0) { /* X = Kzz^-1 Kzm into Kzm's place; Kmm -= Kmz X */
    info = LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'L', nz, Kzz, n);
    if (!info)
      info = LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'L', nz, nm, Kzz, n, Kzm, n);
    if (info) {
      st = vi_fail(fe->errmsg, VI_ERR_NOT_SPD, "the %d massless dofs cannot "
                   "be condensed: their own stiffness is singular (dpotrf "
                   "info %d)", nz, (int)info);
      goto cleanup;
    }
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, nm, nm, nz, -1.0,
                Kmz, n, Kzm, n, 1.0, A, n);
    LAPACKE_dlacpy(LAPACK_COL_MAJOR, 'A', nz, nm, Kzm, n, X, nz);
  }
  fe->shift = 0.0;
  /* lumped masses (what condensing the massless dofs often leaves): the
   * dense set-up's standard problem; Z is free until the modes are put
   * back in order */
  if (vi_mass_lumped(nm, B))
    info = vi_eig_lumped(nm, A, n, B, nm + 1, lam, Z);
  else
    info = LAPACKE_dsygvd(LAPACK_COL_MAJOR, 1, 'V', 'L', nm, A, n, B, nm, lam);
  if (info > nm) {
    st = vi_fail(fe->errmsg, VI_ERR_NOT_SPD, "M is not positive definite "
                 "on its %d dofs with mass (Cholesky fails at the %d-th)", nm,
                 (int)info - nm);
  } else if (info != 0) {
    st = vi_fail(fe->errmsg, VI_ERR_LAPACK, "dsygvd failed (info %d)",
                 (int)info);
  } else {
    /* the k lowest: v on the massive dofs, -X v on the massless ones,
     * back in the original numbering */
    for (int j = 0; j < k; j++) {
      double *v = A + (size_t)j * n, *z = Z + (size_t)j * n;
      if (nz > 0)
        cblas_dgemv(CblasColMajor, CblasNoTrans, nz, nm, -1.0, X, nz, v, 1,
                    0.0, v + nm, 1);
      for (int i = 0; i < n; i++) z[i] = v[map[i]];
    }
    st = finish(fe, lam, Z, Psi);
  }
cleanup:
  free(A);
  free(X);
  free(map);
  return st;
}

/* What ARPACK's info codes mean, as dsaupd's and dseupd's documentation
 * gives them (the two number some differently: -12, -13, -15, -17). */
const char *vi_arpack_words(int eupd, int info)
{
  switch (info) {
  case 0: return "normal exit";
  case 1: return "the maximum number of iterations was taken";
  case 3: return "no shifts could be applied during a restart cycle (raise "
                 "ncv)";
  case -1: return "n must be positive";
  case -2: return "the number of modes must be positive";
  case -3: return "ncv must exceed the modes and be at most n";
  case -4: return "the maximum number of iterations must be positive";
  case -5: return "which must be LM, SM, LA, SA or BE";
  case -6: return "bmat must be I or G";
  case -7: return "the private work array workl is too short";
  case -8: return "the tridiagonal eigensolve (LAPACK dsteqr) failed";
  case -9: return "the starting vector is zero";
  case -10: return "the mode iparam(7) must be 1 to 5";
  case -11: return "mode 1 and bmat = G are incompatible";
  case -12: return eupd ? "nev = 1 and which = BE are incompatible"
                        : "the shift strategy iparam(1) must be 0 or 1";
  case -13: return eupd ? "an unknown code"
                        : "nev = 1 and which = BE are incompatible";
  case -14: return eupd ? "dsaupd found no eigenvalue to sufficient accuracy"
                        : "an unknown code";
  case -15: return eupd ? "howmny must be A or S" : "an unknown code";
  case -16: return eupd ? "howmny = S is not implemented" : "an unknown code";
  case -17: return eupd ? "dseupd counted other converged Ritz values than "
                          "dsaupd (its data were changed between the two)"
                        : "an unknown code";
  case -9999: return eupd ? "an unknown code"
                          : "could not build a Lanczos (Arnoldi) "
                            "factorisation";
  default: return "an unknown code";
  }
}

/* ARPACK's reverse-communication loop on the factor L of K - sigma M and
 * the Ritz pairs: lam [k], Z [n x k].  Called under arpack_lock. */
static int arpack(vi_fe *fe, cholmod_factor *L, cholmod_common *c, int ncv,
                  double *V, a_int *sel, double *lam, double *Z)
{
  int n = fe->n, k = fe->k, st = VI_OK, lworkl = ncv * (ncv + 8);
  double *workd = V + (size_t)n * ncv, *resid = workd + 3 * (size_t)n;
  double *workl = resid + n, *tmp = workl + lworkl;
  cholmod_dense *X = NULL, *Y = NULL, *E = NULL;
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
                 "converged in %d restarts (ARPACK dsaupd info %d: %s; raise "
                 "maxit or ncv with vi_fe_set_eigensolver)", (int)iparam[4],
                 k, (int)iparam[2], (int)info, vi_arpack_words(0, (int)info));
    goto cleanup;
  }
  if (info != 0) {
    st = vi_fail(fe->errmsg, VI_ERR_LAPACK, "ARPACK dsaupd fails (info %d: "
                 "%s)", (int)info, vi_arpack_words(0, (int)info));
    goto cleanup;
  }
  dseupd_c(1, "A", sel, lam, Z, n, fe->shift, "G", n, "LM", k, tol, resid,
           ncv, V, n, iparam, ipntr, workd, workl, lworkl, &info);
  if (info != 0) {
    st = vi_fail(fe->errmsg, VI_ERR_LAPACK, "ARPACK dseupd fails (info %d: "
                 "%s)", (int)info, vi_arpack_words(1, (int)info));
    goto cleanup;
  }
  if (iparam[4] < k)
    st = vi_fail(fe->errmsg, VI_ERR_NOT_CONVERGED, "Lanczos: %d of %d modes "
                 "converged", (int)iparam[4], k);
cleanup:
  cholmod_free_dense(&X, c);
  cholmod_free_dense(&Y, c);
  cholmod_free_dense(&E, c);
  return st;
}

/* The k lowest modes by shift-invert Lanczos on the factor L. */
static int lanczos(vi_fe *fe, cholmod_factor *L, cholmod_common *c,
                   double *Psi)
{
  int n = fe->n, k = fe->k, st;
  int ncv = fe->ncv > 0 ? fe->ncv : vi_fe_default_ncv(k);
  if (ncv > n - fe->n0) ncv = n - fe->n0;
  if (ncv <= k)
    return vi_fail(fe->errmsg, VI_ERR_DIM, "Lanczos basis ncv = %d must "
                   "exceed the %d kept modes", ncv, k);
  size_t lworkl = (size_t)ncv * (ncv + 8);
  size_t need = (size_t)n * ncv + 5 * (size_t)n + lworkl + (size_t)n * k +
                (size_t)k;
  /* zeroed: ARPACK reads parts of its work arrays before writing them */
  double *V = calloc(need, sizeof(double));
  a_int *sel = calloc((size_t)ncv, sizeof(a_int));
  if (!V || !sel) {
    free(V);
    free(sel);
    return vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory for the Lanczos "
                   "basis (%d x %d)", n, ncv);
  }
  double *Z = V + (size_t)n * ncv + 5 * (size_t)n + lworkl;
  double *lam = Z + (size_t)n * k;
  pthread_mutex_lock(&arpack_lock);
  st = arpack(fe, L, c, ncv, V, sel, lam, Z);
  pthread_mutex_unlock(&arpack_lock);
  if (!st) st = finish(fe, lam, Z, Psi);
  free(V);
  free(sel);
  return st;
}

/* Factorise K - sigma M (sigma = fe->shift) and run Lanczos on it. */
static int shift_invert(vi_fe *fe, cholmod_sparse *Ks, cholmod_sparse *Ms,
                        cholmod_common *c, double *Psi)
{
  double alpha[2] = {1.0, 0.0}, beta[2] = {-fe->shift, 0.0}, piv;
  int minor, st;
  cholmod_factor *L = NULL;
  cholmod_sparse *A = cholmod_add(Ks, Ms, alpha, beta, 1, 1, c);
  if (!A)
    return vi_fail(fe->errmsg, VI_ERR_NOMEM, "K - sigma M: CHOLMOD fails "
                   "(status %d)", c->status);
  st = factor(fe, "K - sigma M", A, NULL, c, &L, &piv, &minor);
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
  if (!st) st = lanczos(fe, L, c, Psi);
  cholmod_free_factor(&L, c);
  cholmod_free_sparse(&A, c);
  return st;
}

int vi_fe_eigs(vi_fe *fe, double **pPsi)
{
  int n = fe->n, k = fe->k, st = VI_OK, minor;
  double piv = 0.0;
  *pPsi = NULL;
  double *Psi = malloc(sizeof(double) * (size_t)n * k);
  if (!Psi) return vi_fail(fe->errmsg, VI_ERR_NOMEM, "out of memory for "
                           "Psi (%d x %d)", n, k);
  cholmod_common cm, *c = &cm;
  cholmod_start(c);
  c->print = 0; /* the library never prints: statuses are read below */
  c->error_handler = NULL;
  cholmod_sparse Ms, Ks;
  cholmod_factor *L = NULL;
  wrap(n, &fe->mat[VI_FE_MASS], &Ms);
  wrap(n, &fe->mat[VI_FE_STIFFNESS], &Ks);

  /* M semidefinite, and the stops' compliance w^T M^-1 w (WB 10) */
  if ((st = mass_compliance(fe, c))) goto cleanup;

  /* K itself: a fixed structure factorises with sigma = 0, and its factor
   * gives the static compliance w^T K^-1 w too */
  st = factor(fe, "K", &Ks, &fe->mat[VI_FE_STIFFNESS], c, &L, &piv, &minor);
  if (st < 0) goto cleanup;
  fe->k_singular = st == 1 || piv <= VI_EIGS_SINGULAR;
  if (!fe->k_singular) {
    if ((st = compliances(fe, L, c, NULL, 0, NULL, fe->wKw))) goto cleanup;
  } else {
    for (int s = 0; s < fe->ns; s++) fe->wKw[s] = HUGE_VAL;
    cholmod_free_factor(&L, c);
  }
  if (fe->shift_set && fe->sigma_in == 0.0 && fe->k_singular) {
    st = vi_fail(fe->errmsg, VI_ERR_NOT_SPD, "K is singular or not "
                 "positive definite (column %d, smallest pivot %.3g of its "
                 "diagonal): the shift sigma = 0 must lie below the lowest "
                 "eigenvalue; a free structure needs sigma < 0", minor, piv);
    goto cleanup;
  }
  if (k >= n - fe->n0 - 1) {
    st = eigs_dense(fe, Psi);
    goto cleanup;
  }
  fe->shift = fe->shift_set ? fe->sigma_in
              : fe->k_singular ? -VI_EIGS_AUTO_SHIFT * fe->scale : 0.0;
  /* sigma = 0: K's own factor is the operator's */
  st = L && fe->shift == 0.0 ? lanczos(fe, L, c, Psi)
                             : shift_invert(fe, &Ks, &Ms, c, Psi);
  /* A free structure's first shift is a guess far below its first elastic
   * mode, and K - sigma M then as ill-conditioned as 1 / |sigma|: the
   * elastic modes come out with residuals near 1e-10.  Half the first
   * elastic eigenvalue, now known, makes them exact. */
  int e = 0;
  while (!st && e < k && fe->lambda[e] == 0.0) e++;
  if (!st && fe->k_singular && !fe->shift_set && e < k) {
    fe->shift = -0.5 * fe->lambda[e];
    st = shift_invert(fe, &Ks, &Ms, c, Psi);
  }
cleanup:
  cholmod_free_factor(&L, c);
  cholmod_finish(c);
  if (st) free(Psi);
  else *pPsi = Psi;
  return st;
}
