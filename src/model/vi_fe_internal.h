/* vi_fe_internal.h - the finite-element reduction's private structure
 * (vi_sparse.h), shared by vi_sparse.c (storage, checks, projections) and
 * vi_eigs.c (the sparse partial eigensolve); never installed. */
#ifndef VI_FE_INTERNAL_H
#define VI_FE_INTERNAL_H

#include <limits.h>
#include <string.h>

#include "vi_internal.h"
#include "vibroimpact/vi_sparse.h"

/* A symmetric matrix as stored: lower triangle with the diagonal, 0-based,
 * rows strictly increasing in each column (CHOLMOD's stype -1 form). */
typedef struct vi_csc {
  int nnz;
  int *colptr, *rowind; /* [n + 1], [nnz]; NULL: not set */
  double *val;          /* [nnz] */
} vi_csc;

enum { VI_FE_SRC_NONE = 0, VI_FE_SRC_SPARSE = 1, VI_FE_SRC_HOST = 2 };
enum { VI_FE_DAMP_NONE = 0, VI_FE_DAMP_C = 1, VI_FE_DAMP_RAYLEIGH = 2,
       VI_FE_DAMP_ZETA = 3, VI_FE_DAMP_HOST_D = 4 };

enum { VI_FE_K_UNSET = 0 }; /* k before vi_fe_set_modes: decided at setup */

struct vi_fe {
  int n, k, frozen, source;
  int k_rule;               /* vi_fe_modes_rule: how k was chosen */
  int rigid_in;             /* the user's count of rigid-body modes, -1 */
  double accuracy;          /* largest residual / orthogonality accepted */
  vi_csc mat[3];            /* VI_FE_MASS, VI_FE_DAMPING, VI_FE_STIFFNESS */
  int damping;              /* VI_FE_DAMP_* */
  double alpha, beta;       /* Rayleigh */
  int nzeta;                /* 1 or k ratios in zeta */
  double *zeta_in;
  double *Dhost;            /* host's modal D [k x k] */
  int shift_set;
  double sigma_in, tol;
  int ncv, maxit, keep;
  int64_t mem_limit;
  /* host modes: omega_in [k], rows [nrows], Prow [nrows x k] */
  double *omega_in;
  int nrows;
  int *rows, *rowpos;       /* rowpos [n]: dof -> row in Prow, -1 absent */
  double *Prow;
  /* stops: W [n x ns_cap], x_s, r [ns_cap] */
  int ns, ns_cap;
  double *W, *xs, *r;
  /* forcing: a, b, f0 [n] each, NULL when zero */
  double omega_f;
  double *fa, *fb, *f0;
  int nout;
  int *outs;
  /* results of setup */
  double *omega, *lambda;   /* [k] */
  double *D;                /* [k x k] */
  double *PsiW;             /* [k x ns] */
  double *Fa, *Fb, *F0;     /* [k] */
  double *Pout;             /* [nout x k] */
  double *Psi;              /* [n x k] when kept */
  double *wMw, *wKw;        /* [ns] */
  double *mresid, *mrigid;  /* [k]: backward error, componentwise |K psi| */
  double shift, resid, orth;
  /* the structure as inspected at setup (vi_fe_inspect) */
  int n0, first_massless;   /* massless dofs (zero rows of M), the first */
  int nrigid;               /* modes found rigid (|K psi| at round-off) */
  int k_singular;           /* K singular to working precision */
  double scale;             /* max K_jj / M_jj over the massive dofs */
  char errmsg[VI_MSG_LEN];
};

/* y = A x for a stored symmetric matrix (lower triangle).  Here, below
 * both vi_sparse.c (projections) and vi_eigs.c (the Lanczos operator), so
 * that the two call one way: vi_sparse.c -> vi_eigs.c. */
static inline void vi_csc_symv(int n, const vi_csc *A, const double *x,
                               double *y)
{
  memset(y, 0, sizeof(double) * (size_t)n);
  for (int j = 0; j < n; j++) {
    double xj = x[j], acc = 0.0;
    for (int p = A->colptr[j]; p < A->colptr[j + 1]; p++) {
      int i = A->rowind[p];
      double v = A->val[p];
      y[i] += v * xj;
      if (i != j) acc += v * x[i]; /* the mirrored upper entry (j, i) */
    }
    y[j] += acc;
  }
}

/* Inspect M and K before any solve (vi_eigs.c): the massless dofs (zero
 * rows and columns of M), the diagonal signs, the spectrum's scale. */
int vi_fe_inspect(vi_fe *fe);

/* The sparse path of vi_fe_setup (vi_eigs.c): factorise, solve for the k
 * lowest modes, and fill fe->omega, fe->lambda, the stops' compliances and
 * *Psi [n x k] (allocated, mass-normalised, ascending, signed: the caller
 * frees it), fe->shift, fe->resid. */
int vi_fe_eigs(vi_fe *fe, double **Psi);

/* The default Lanczos basis for k modes (before the cap at the finite
 * modes' count): k + max(20, 3k/2).  The implicit restarts converge at the
 * rate of the gap between the k-th and the first unwanted Ritz value,
 * which a larger basis widens; ARPACK's 2k + 1 took twice as long on the
 * 100 000-dof rod's 20 modes (5.5 s against 3.0 at 50; 12.1 against 8.7 s
 * at k = 40 and 100; bench/vi_bench_sparse), and the small k keep k + 20.
 * One formula for the eigensolver and the memory estimate (vi_sparse.c). */
static inline int vi_fe_default_ncv(int k)
{
  long long extra = k + (k + 1LL) / 2, ncv = k + (extra > 20 ? extra : 20);
  return ncv < INT_MAX ? (int)ncv : INT_MAX;
}

/* ARPACK's info code in words (vi_eigs.c): of dseupd when eupd is nonzero,
 * else of dsaupd; "an unknown code" for one neither documents. */
const char *vi_arpack_words(int eupd, int info);

#endif
