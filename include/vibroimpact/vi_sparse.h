/** @file vi_sparse.h
 * Finite-element structures in: sparse M, K (and C) in compressed sparse
 * column form, a partial eigensolve keeping the lowest modes, or a host's
 * own modes, reduced to a modal vi_model (MODEL.md section 5).
 *
 * The reduction object vi_fe holds one structure of n physical degrees of
 * freedom (dofs) and produces a model in k modal coordinates q, x ~ Psi q:
 *
 *   M = I,  K = diag(omega_j^2),  C = D (k x k modal damping),
 *   stop s:   w_s -> Psi^T w_s  (the rows of Psi at the stop's dofs),
 *   forcing:  a, b, f0 -> Psi^T a, Psi^T b, Psi^T f0,
 *
 * with Psi [n x k] mass-normalised (Psi^T M Psi = I), each column's
 * largest-magnitude entry positive, modes ascending (rigid-body modes, at
 * omega = 0, first).  The model is an ordinary dense vi_model of k
 * coordinates (as vi_model_create_reduced and vi_build_cantilever make):
 * every method, the ledger, orbits and vi_model_create_reduced apply.
 *
 * Two sources of modes:
 * - sparse matrices (vi_fe_set_mass_csc, vi_fe_set_stiffness_csc): the k
 *   lowest modes of K psi = lambda M psi by shift-invert Lanczos (ARPACK-ng
 *   dsaupd/dseupd, mode 3) on a sparse Cholesky factorisation of
 *   K - sigma M (CHOLMOD, supernodal).  sigma lies below the lowest
 *   eigenvalue; by default it is 0 when K factorises (a fixed structure)
 *   and negative when K is singular (a free structure: rigid-body modes).
 * - a host's eigensolver output (vi_fe_set_host_modes): omega_j, modal
 *   damping and the rows of Psi at the dofs that matter; no M, no K.
 *
 * Only the rows of Psi at the dofs that matter are kept: the stops', the
 * forcing's (folded into Psi^T f at setup) and the outputs'
 * (vi_fe_set_outputs).  The full Psi [n x k] is kept only when asked
 * (vi_fe_set_keep_shapes), e.g. to project a physical initial state
 * (vi_fe_to_modal).
 *
 * Life cycle: vi_fe_create -> vi_fe_set_* / vi_fe_add_stop* -> vi_fe_setup
 * -> vi_fe_create_model, getters, vi_fe_to_outputs -> vi_fe_destroy.
 * After vi_fe_setup the object is frozen (setters return VI_ERR_STATE);
 * models made from it are independent (vi_fe_destroy may come first).
 *
 * Conventions: dof indices in C are 0-based (a Fortran caller subtracts 1),
 * except CSC arrays, whose base (0 or 1) is an argument so that Fortran and
 * Harwell-Boeing arrays pass unchanged.  Every array is copied when set.
 * Messages (vi_fe_errmsg) name matrices, columns and rows 1-based.
 *
 * Threads: a vi_fe is used by one thread at a time.  ARPACK keeps state in
 * SAVE variables between its reverse-communication calls, so two
 * vi_fe_setup calls of the sparse path must not run at the same time in
 * one process; everything else (and the models made) is thread-safe as
 * vi_model. */
#ifndef VI_SPARSE_H
#define VI_SPARSE_H

#include <stdint.h>

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_model.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Storage of a symmetric matrix in CSC form (vi_fe_set_mass_csc). */
typedef enum vi_csc_storage {
  /** Both triangles stored; the matrix must be symmetric (pattern and
   *  values, to 1e-12 of its largest entry). */
  VI_CSC_FULL = 0,
  /** The lower triangle with the diagonal (row >= column), as
   *  Harwell-Boeing "RSA" files and CHOLMOD's stype -1 hold it. */
  VI_CSC_LOWER = 1
} vi_csc_storage;

/** Which matrix a CSC getter returns (vi_fe_matrix_csc). */
typedef enum vi_fe_matrix {
  VI_FE_MASS = 0,      /**< M */
  VI_FE_DAMPING = 1,   /**< C (explicit damping only) */
  VI_FE_STIFFNESS = 2  /**< K */
} vi_fe_matrix;

/** How the number of kept modes was chosen (vi_fe_summary). */
typedef enum vi_fe_modes_rule {
  /** Every finite mode: no vi_fe_set_modes, and at most 1000 dofs with
   *  mass (beyond, setup refuses with VI_ERR_STATE rather than cut). */
  VI_FE_MODES_WHOLE = 0,
  /** As set by vi_fe_set_modes. */
  VI_FE_MODES_GIVEN = 1,
  /** As many as the host's modes (vi_fe_set_host_modes). */
  VI_FE_MODES_HOST = 2
} vi_fe_modes_rule;

/** Opaque finite-element reduction handle. */
typedef struct vi_fe vi_fe;

/** Create a reduction for a structure of n >= 1 dofs: no matrices, no modes,
 *  no stop, no forcing, undamped; the number of kept modes undecided
 *  (vi_fe_set_modes; without it every finite mode is kept where there are
 *  at most 1000, and setup refuses beyond), the rigid-body modes decided
 *  from K, an accuracy of 1e-8 asked of the modes (vi_fe_set_accuracy).
 *  *out is NULL on failure.
 *  @return VI_OK, VI_ERR_DIM (n < 1), VI_ERR_ARG, VI_ERR_NOMEM. */
VI_API int vi_fe_create(int n, vi_fe **out);
/** Destroy and set *fe to NULL; NULL-safe.  Models made by
 *  vi_fe_create_model stay valid. */
VI_API void vi_fe_destroy(vi_fe **fe);
/** Detail of the last error, naming the culprit ("" if none); owned by the
 *  handle, valid until its next call.  "" for NULL. */
VI_API const char *vi_fe_errmsg(const vi_fe *fe);

/** @name Sparse matrices (the eigensolve source)
 *  An n x n symmetric matrix in compressed sparse column form, the
 *  Harwell-Boeing / Fortran convention: colptr [n + 1], rowind [nnz],
 *  values [nnz], nnz = colptr[n] - base; column j holds the entries
 *  rowind[p], values[p] for p = colptr[j] - base .. colptr[j+1] - base - 1.
 *  base is 0 (C) or 1 (Fortran, Matlab, Harwell-Boeing files): it applies to
 *  colptr and rowind alike.  Row indices must be strictly increasing within
 *  each column (sorted, no duplicates: sum duplicates before) and in range;
 *  values finite; storage a vi_csc_storage.  A bad array is refused with
 *  the column and row (1-based) in the message: VI_ERR_ARG (NULL array),
 *  VI_ERR_DIM (base not 0 or 1, colptr not starting at base or decreasing,
 *  nnz negative, a row index out of range, unsorted or repeated, an
 *  entry above the diagonal with VI_CSC_LOWER), VI_ERR_NONFINITE,
 *  VI_ERR_NOT_SYMMETRIC (VI_CSC_FULL storage of a non-symmetric matrix),
 *  VI_ERR_STATE (frozen, or host modes set), VI_ERR_NOMEM.  Positive
 *  definiteness of M and semidefiniteness of K are checked at setup.
 *  @{ */
/** Set the mass matrix M (symmetric positive semidefinite).  A lumped
 *  mass may leave dofs massless (a zero row and column, e.g. rotations
 *  without rotary inertia): their eigenvalues are infinite and never among
 *  the kept modes, whose shapes carry them statically (x_z = -K_zz^-1 K_zm
 *  x_m).  A stop on a massless dof therefore acts through the massive dofs
 *  it is tied to, with the effective mass 1 / (t^T M_mm^-1 t), t = w_m -
 *  K_mz K_zz^-1 w_z (vi_fe_stop_compliance); a load on one reaches the
 *  modes through Psi^T f, and its local static deflection K_zz^-1 f_z,
 *  which no mode spans, is dropped as every truncation drops the static
 *  residual.  Setup refuses a dof with neither mass nor stiffness, massless
 *  dofs whose own stiffness K_zz is singular, and an M singular beyond its
 *  zero rows. */
VI_API int vi_fe_set_mass_csc(vi_fe *fe, int storage, int base,
                              const int *colptr, const int *rowind,
                              const double *values);
/** Set the stiffness matrix K (symmetric positive semidefinite; singular for
 *  a free structure). */
VI_API int vi_fe_set_stiffness_csc(vi_fe *fe, int storage, int base,
                                   const int *colptr, const int *rowind,
                                   const double *values);
/** Set an explicit damping matrix C (symmetric positive semidefinite),
 *  projected at setup to D = Psi^T C Psi [k x k] (not diagonal in general:
 *  non-proportional damping).  colptr NULL removes it (undamped).  Replaces
 *  any damping set before (vi_fe_set_rayleigh, vi_fe_set_modal_damping). */
VI_API int vi_fe_set_damping_csc(vi_fe *fe, int storage, int base,
                                 const int *colptr, const int *rowind,
                                 const double *values);
/** @} */

/** Rayleigh damping C = alpha M + beta K, i.e. D = diag(alpha + beta
 *  omega_j^2) (zeta_j = alpha / (2 omega_j) + beta omega_j / 2).  alpha,
 *  beta >= 0 and finite.  Replaces any damping set before.  Works with host
 *  modes too.  @return VI_OK, VI_ERR_ARG, VI_ERR_NONFINITE, VI_ERR_STATE. */
VI_API int vi_fe_set_rayleigh(vi_fe *fe, double alpha, double beta);
/** Modal damping ratios: D = diag(2 zeta_j omega_j).  nzeta = 1: one ratio
 *  for every mode; nzeta = k (the kept modes, vi_fe_set_modes): one per
 *  mode, ascending order.  zeta_j >= 0, finite.  Replaces any damping set
 *  before.  @return VI_OK, VI_ERR_ARG (NULL, a negative ratio),
 *  VI_ERR_DIM (nzeta not 1 or k), VI_ERR_NONFINITE, VI_ERR_STATE. */
VI_API int vi_fe_set_modal_damping(vi_fe *fe, int nzeta, const double *zeta);

/** @name Eigensolver settings (sparse source)
 *  @{ */
/** Keep the k lowest modes, 1 <= k <= n (and, at setup, at most the
 *  number of finite modes: dofs with mass).  Lanczos needs k <= nf - 2;
 *  for k >= nf - 1 the modes come from LAPACK's dense dsygvd instead (n <=
 *  4000), after the massless dofs are condensed statically.  A per-mode zeta set before must have k
 *  entries at setup.  @return VI_OK, VI_ERR_DIM, VI_ERR_STATE (frozen, or
 *  host modes set: they fix k). */
VI_API int vi_fe_set_modes(vi_fe *fe, int k);
/** The number of rigid-body modes the structure has, if the user knows it:
 *  count >= 0 makes setup check that exactly the lowest `count` kept modes
 *  are rigid (VI_ERR_ARG naming the first that disagrees); -1 (default)
 *  decides from K alone.  A mode is rigid when K psi is at round-off row by
 *  row: max_i |K psi|_i / (|K| |psi|)_i <= 1e-11 (vi_fe_mode_rigidity), a
 *  property of K's null space, never of the spectrum's scale; only such a
 *  mode is given omega = 0.  @return VI_OK, VI_ERR_ARG (count < -1 or >
 *  n), VI_ERR_STATE. */
VI_API int vi_fe_set_rigid_modes(vi_fe *fe, int count);
/** The accuracy asked of the modes, 0 < tol < 1 (default 1e-8): setup fails
 *  with VI_ERR_NOT_CONVERGED, naming the mode, when a kept mode's residual
 *  (vi_fe_mode_residuals) or the modes' M-orthonormality error exceeds it.
 *  @return VI_OK, VI_ERR_TOLERANCE, VI_ERR_STATE. */
VI_API int vi_fe_set_accuracy(vi_fe *fe, double tol);
/** The shift sigma of the shift-invert (K - sigma M)^-1 M, finite and
 *  below the lowest eigenvalue (lambda = omega^2); a shift at or above it
 *  makes the factorisation indefinite, refused at setup (VI_ERR_NOT_SPD).
 *  Default: automatic (0, or negative for a singular K).
 *  @return VI_OK, VI_ERR_NONFINITE, VI_ERR_STATE. */
VI_API int vi_fe_set_shift(vi_fe *fe, double sigma);
/** Lanczos settings: tol, ARPACK's relative accuracy of the Ritz values
 *  (0: the default, machine precision); ncv, the Lanczos basis size (0: the
 *  default min(n, k + max(20, 3k/2)); else k < ncv <= n, checked at
 *  setup); maxit, restart iterations (0: default 1000).  The start vector
 *  is fixed, so a setup is reproducible.  @return VI_OK, VI_ERR_ARG (negative or
 *  non-finite), VI_ERR_DIM (ncv), VI_ERR_STATE. */
VI_API int vi_fe_set_eigensolver(vi_fe *fe, double tol, int ncv, int maxit);
/** Refuse a setup that would hold more than `bytes` (the CSC copies, the
 *  sparse factor, counted after CHOLMOD's symbolic analysis and before
 *  the numeric factorisation, and the Lanczos basis): VI_ERR_LIMIT with
 *  the figures.  0 (default): no limit.
 *  @return VI_OK, VI_ERR_ARG (negative), VI_ERR_STATE. */
VI_API int vi_fe_set_memory_limit(vi_fe *fe, int64_t bytes);
/** @} */

/** @name Host-supplied modes (instead of the sparse matrices)
 *  @{ */
/** A host's own modes: k >= 1 natural frequencies omega [k] (>= 0,
 *  ascending not required, kept in the given order), mass-normalised shapes
 *  given only by their rows at nrows dofs: rows [nrows] (0-based, distinct,
 *  < n), Psi [ldp x k] with row r = dof rows[r] (ldp >= nrows), and the
 *  modal damping: zeta [k] (D = diag(2 zeta_j omega_j)), or a dense modal
 *  D [ldd x k] (symmetric positive semidefinite), or both NULL (undamped;
 *  vi_fe_set_rayleigh may follow).  Stops, forcing and outputs may then
 *  touch only these dofs.  Sets the number of kept modes to k; the sparse
 *  setters are then refused, and the reverse.  No eigensolve at setup.
 *  @return VI_OK, VI_ERR_ARG (NULL omega, rows or Psi, zeta and D both
 *  given, a repeated or out-of-range row, a negative omega or zeta),
 *  VI_ERR_DIM (k, nrows, ldp, ldd), VI_ERR_NONFINITE, VI_ERR_NOT_SYMMETRIC,
 *  VI_ERR_STATE, VI_ERR_NOMEM. */
VI_API int vi_fe_set_host_modes(vi_fe *fe, int k, const double *omega,
                                const double *zeta, const double *D, int ldd,
                                int nrows, const int *rows, const double *Psi,
                                int ldp);
/** @} */

/** @name Stops, forcing, outputs (physical dofs)
 *  @{ */
/** Add a stop w.x <= x_s with restitution r in [0, 1], w [n] a physical
 *  vector (e.g. e_i, or e_i - e_j for a gap between two dofs).  Stops are
 *  numbered in the order added (stop 0 first).  With host modes w must be
 *  zero outside the given rows.  @return VI_OK, VI_ERR_ARG,
 *  VI_ERR_STOP_VECTOR (w zero), VI_ERR_RESTITUTION, VI_ERR_NONFINITE,
 *  VI_ERR_UNSUPPORTED (w outside the host's rows), VI_ERR_STATE,
 *  VI_ERR_NOMEM. */
VI_API int vi_fe_add_stop(vi_fe *fe, const double *w, double x_s, double r);
/** Add a stop on one dof: direction x_dof <= x_s (direction +1) or
 *  -x_dof <= x_s (direction -1, a stop pushing the other way).  dof
 *  0-based.  @return as vi_fe_add_stop, VI_ERR_ARG (dof out of range,
 *  direction not +-1). */
VI_API int vi_fe_add_stop_dof(vi_fe *fe, int dof, int direction, double x_s,
                              double r);
/** Physical forcing a cos(omega t) + b sin(omega t) + f0, vectors [n] (each
 *  may be NULL = 0), projected at setup to Psi^T a, ...  Errors as
 *  vi_model_set_forcing, and VI_ERR_UNSUPPORTED (host modes: a load
 *  outside the given rows). */
VI_API int vi_fe_set_forcing(vi_fe *fe, double omega, const double *a,
                             const double *b, const double *f0);
/** Output dofs: the rows of Psi kept for vi_fe_to_outputs, dofs [nout]
 *  (0-based, < n; repeats allowed); nout = 0 removes them.  With host
 *  modes each must be one of the given rows.  @return VI_OK, VI_ERR_ARG,
 *  VI_ERR_DIM, VI_ERR_UNSUPPORTED, VI_ERR_STATE, VI_ERR_NOMEM. */
VI_API int vi_fe_set_outputs(vi_fe *fe, int nout, const int *dofs);
/** Keep the full Psi [n x k] after setup (vi_fe_shapes, vi_fe_to_modal):
 *  keep 1 or 0 (default 0: only the rows that matter).  Sparse source only
 *  (VI_ERR_UNSUPPORTED with host modes).  @return VI_OK, VI_ERR_ARG,
 *  VI_ERR_UNSUPPORTED, VI_ERR_STATE. */
VI_API int vi_fe_set_keep_shapes(vi_fe *fe, int keep);
/** @} */

/** Validate, factorise, solve for the kept modes and project the stops,
 *  forcing, damping and outputs; freeze.  Sparse source: M is checked
 *  semidefinite and its massless dofs counted (its Cholesky factorisation
 *  on the massive dofs also gives the stops' compliance w^T M^-1 w), K
 *  factorised (a pivot below 1e-13 of its own diagonal entry marks K
 *  singular: a negative shift), the k lowest modes found, the rigid ones
 *  decided from K psi, and every mode checked (residual, orthonormality,
 *  K semidefinite).  @return VI_OK, VI_ERR_STOP_VECTOR (no stop),
 *  VI_ERR_STATE (no matrices or modes; no vi_fe_set_modes beyond 1000 dofs
 *  with mass), VI_ERR_NOT_SPD (M singular beyond its zero rows, massless
 *  dofs that cannot be condensed, K - sigma M for a shift at or above the
 *  lowest eigenvalue), VI_ERR_NOT_PSD (M, K or C indefinite), VI_ERR_DIM
 *  (more modes than finite ones), VI_ERR_ARG (a stated rigid-mode count K
 *  contradicts), VI_ERR_NOT_CONVERGED (Lanczos; a mode less accurate than
 *  vi_fe_set_accuracy asks), VI_ERR_LAPACK, VI_ERR_LIMIT, VI_ERR_NOMEM. */
VI_API int vi_fe_setup(vi_fe *fe);

/** The reduced modal model of a set-up reduction: k coordinates, M = I,
 *  K = diag(omega_j^2), C = D, every stop (Psi^T w_s, x_s, r_s), the
 *  projected forcing; a new, set-up vi_model (*out NULL on failure).
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE (not set up), VI_ERR_NOMEM and
 *  the codes of vi_model_setup. */
VI_API int vi_fe_create_model(const vi_fe *fe, vi_model **out);

/** @name Getters
 *  After vi_fe_setup (before it: 0, NaN or NULL).  Views are owned by the
 *  handle, valid until it is destroyed.
 *  @{ */
/** Number of physical dofs n (also before setup). */
VI_API int vi_fe_n(const vi_fe *fe);
/** Number of kept modes k (before setup: as set, 0 while undecided). */
VI_API int vi_fe_num_modes(const vi_fe *fe);
/** Natural frequencies omega_j [k], ascending for the sparse source. */
VI_API const double *vi_fe_omega(const vi_fe *fe);
/** Modal damping D [k x k] with *ld = k. */
VI_API const double *vi_fe_modal_damping(const vi_fe *fe, int *ld);
/** Modal stop vectors Psi^T w_s [k x ns], column s = stop s, *ld = k. */
VI_API const double *vi_fe_modal_stops(const vi_fe *fe, int *ld);
/** Number of stops added (also before setup). */
VI_API int vi_fe_num_stops(const vi_fe *fe);
/** Rows of Psi at the output dofs [nout x k], row r = dofs[r] of
 *  vi_fe_set_outputs, *ld = nout (NULL without outputs). */
VI_API const double *vi_fe_output_shapes(const vi_fe *fe, int *ld);
/** The full Psi [n x k], *ld = n; NULL unless vi_fe_set_keep_shapes(fe, 1). */
VI_API const double *vi_fe_shapes(const vi_fe *fe, int *ld);
/** The shift sigma used (0 with host modes). */
VI_API double vi_fe_shift(const vi_fe *fe);
/** Largest backward error of the kept eigenpairs,
 *  max_j ||K psi_j - lambda_j M psi_j|| / ((||K|| + |lambda_j| ||M||)
 *  ||psi_j||) (infinity norms); 0 with host modes. */
VI_API double vi_fe_residual(const vi_fe *fe);
/** What the reduction did to the model, for its report: *massless, the
 *  dofs with no mass (zero rows of M); *rigid, the kept modes found rigid
 *  (omega = 0); *rule, a vi_fe_modes_rule; *orthogonality, max |Psi^T M
 *  Psi - I| over the kept modes (0 with host modes).  Any pointer may be
 *  NULL.  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE (not set up). */
VI_API int vi_fe_summary(const vi_fe *fe, int *massless, int *rigid,
                         int *rule, double *orthogonality);
/** Each kept mode's backward error [k], ||K psi - lambda M psi|| / ((||K||
 *  + |lambda| ||M||) ||psi||) (infinity norms), computed before a rigid
 *  mode's lambda is set to 0; zeros with host modes. */
VI_API const double *vi_fe_mode_residuals(const vi_fe *fe);
/** Each kept mode's rigidity [k], max_i |K psi|_i / (|K| |psi|)_i: round-off
 *  (<= 1e-11) for a rigid-body mode, the mode's own lambda M psi against
 *  K's entries otherwise; zeros with host modes. */
VI_API const double *vi_fe_mode_rigidity(const vi_fe *fe);
/** Stop s's compliance (WB 10): *dynamic = w^T M^-1 w, the inverse of its
 *  effective mass, against which sum_j psi_sj^2 over the kept modes is the
 *  fraction the modes carry; *statik = w^T K^-1 w (static flexibility,
 *  against sum_j psi_sj^2 / omega_j^2; +Inf for a singular K).  Sparse
 *  source only: NaN with host modes.  Either pointer may be NULL.
 *  @return VI_OK, VI_ERR_ARG (s out of range), VI_ERR_STATE. */
VI_API int vi_fe_stop_compliance(const vi_fe *fe, int s, double *dynamic,
                                 double *statik);
/** The stored matrix `which` (a vi_fe_matrix) in CSC form, lower triangle
 *  with the diagonal, 0-based, rows sorted: *nnz entries, *colptr [n + 1],
 *  *rowind [nnz], *values [nnz], views owned by the handle (each output may
 *  be NULL).  Also before setup.  For storage of the model (e.g. HDF5).
 *  @return VI_OK, VI_ERR_ARG (which, NULL fe), VI_ERR_STATE (matrix not
 *  set). */
VI_API int vi_fe_matrix_csc(const vi_fe *fe, int which, int *nnz,
                            const int **colptr, const int **rowind,
                            const double **values);
/** @} */

/** Physical displacements (or velocities) at the output dofs from modal
 *  ones: Y = Psi_out Q, Q [ldq x ncol] with k rows (e.g. a model state's
 *  positions or velocities, one column per sample), Y [ldy x ncol] with
 *  nout rows.  @return VI_OK, VI_ERR_ARG (NULL, overlap), VI_ERR_DIM
 *  (ncol < 0, ldq < k, ldy < nout), VI_ERR_STATE (not set up, no
 *  outputs). */
VI_API int vi_fe_to_outputs(const vi_fe *fe, int ncol, const double *Q,
                            int ldq, double *Y, int ldy);
/** Modal coordinates q = Psi^T M x [k] of a physical x [n] (positions or
 *  velocities: an initial state), exact for x in the span of the kept modes
 *  and the M-orthogonal projection otherwise.  Needs the full Psi
 *  (vi_fe_set_keep_shapes) and the sparse source.  @return VI_OK,
 *  VI_ERR_ARG, VI_ERR_STATE, VI_ERR_UNSUPPORTED. */
VI_API int vi_fe_to_modal(const vi_fe *fe, const double *x, double *q);

/** Bytes a sparse reduction of n dofs with nnz stored entries per matrix
 *  (the largest of M and K, as passed) and k modes will need before the
 *  sparse factor, whose fill only CHOLMOD's analysis knows (setup checks it
 *  against vi_fe_set_memory_limit): CSC copies, the Lanczos basis and work
 *  arrays, a full Psi when keep is 1.  @return VI_OK, VI_ERR_ARG,
 *  VI_ERR_DIM, VI_ERR_LIMIT. */
VI_API int vi_fe_memory_estimate(int n, int64_t nnz, int k, int keep,
                                 int64_t *bytes);

/** A modal model straight from a host's modes, without M and K: k
 *  coordinates, M = I, K = diag(omega_j^2), C = diag(2 zeta_j omega_j)
 *  (zeta [k]) or the dense modal D [ldd x k], or 0 (both NULL).  The model is
 *  open: the host adds its stops with w = the rows of its Psi at the stop
 *  (times the stop's direction) through vi_model_set_stop / add_stop, the
 *  forcing as Psi^T f through vi_model_set_forcing, then vi_model_setup.
 *  (vi_fe_set_host_modes does the same from the rows at given dofs.)
 *  @return VI_OK, VI_ERR_DIM (k < 1, ldd < k), VI_ERR_ARG (a negative omega
 *  or zeta, zeta and D both given), VI_ERR_NONFINITE, VI_ERR_NOT_SYMMETRIC,
 *  VI_ERR_NOMEM. */
VI_API int vi_model_create_modal(int k, const double *omega,
                                 const double *zeta, const double *D, int ldd,
                                 vi_model **out);

#ifdef __cplusplus
}
#endif
#endif
