/** @file vi_model.h
 * The linear structure, its forcing and the stop.
 *
 *   M x'' + C x' + K x = a cos(Omega t) + b sin(Omega t) + f0      (WB 1)
 *   w.x <= x_s, Newton impact with restitution r                     (WB 2)
 *
 * Several stops w_k.x <= x_k (restitution r_k, k = 0, 1, ...) are allowed:
 * two-sided clearances (a pair with opposite normals), stops on different
 * coordinates.  Simultaneous contacts follow Newton's law for multiple
 * contacts (vi_impact.h).  Stop 0 is "the stop" of the single-stop getters
 * (vi_model_stop_vector, vi_model_clearance, ...) and of orbits, which
 * need a model with one stop; the exact method searches every stop.
 *
 * Life cycle: vi_model_create -> vi_model_set_* -> vi_model_setup ->
 * (getters, vi_sim_create) -> vi_model_destroy.  Every array is copied when
 * it is set; matrices are column-major with a leading dimension (LAPACK),
 * so a Fortran caller passes its arrays unchanged.  After vi_model_setup the
 * model is frozen (setters return VI_ERR_STATE) and may be shared by threads.
 * Units are the caller's, consistent throughout (any length, mass, time).
 * Indices in messages are 1-based, as a Fortran or MATLAB user reads them.
 */
#ifndef VI_MODEL_H
#define VI_MODEL_H

#include <stdint.h>

#include "vibroimpact/vi_export.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Opaque model handle. */
typedef struct vi_model vi_model;

/** Create a model with n >= 1 coordinates: M = I, C = K = 0, no forcing and
 *  no stop (w must be set before setup).  *out receives the handle, NULL on
 *  failure.  @return VI_OK, VI_ERR_DIM (n < 1), VI_ERR_ARG, VI_ERR_NOMEM. */
VI_API int vi_model_create(int n, vi_model **out);
/** Destroy a model and set *model to NULL; NULL-safe.  Sims, orbits,
 *  censuses and identifications made from it must be destroyed first
 *  (they hold it: vi_model_set_param refuses while they exist). */
VI_API void vi_model_destroy(vi_model **model);

/** Create a model in band storage: n >= 1 coordinates, M, C and K
 *  symmetric with half-bandwidth kd >= 0 (clamped to n - 1), stored in
 *  LAPACK's symmetric band 'U' form, (kd + 1) n doubles each, so that a long
 *  chain needs memory and time per step O(n kd) instead of O(n^2).  M = I,
 *  C = K = 0 as with vi_model_create; every setter works (a dense matrix
 *  given to vi_model_set_mass etc. must be zero outside the band).
 *
 *  A band model has no modes: vi_model_setup does no modal analysis, the
 *  modal getters (vi_model_omega, vi_model_modal_shapes, ...) and the dense
 *  ones (vi_model_mass, vi_model_damping, vi_model_stiffness) return NULL
 *  (read vi_model_mass_band etc.), vi_model_to_modal / from_modal return
 *  VI_ERR_UNSUPPORTED, and so do the energy ledger, the exact method, the
 *  orbits and nonlinear forces; the method "auto" runs Adams.  Adams and
 *  ERK run on any band model; BDF uses SUNDIALS' band solver when M is
 *  diagonal and every stop acts on one coordinate (a chain with its stop
 *  on a mass), else a dense Jacobian, refused above 2000 coordinates.  A
 *  diagonal M is inverted (M^-1 K is then banded); a banded M is factored
 *  by band Cholesky (dpbtrf) and applied by a band solve per evaluation.
 *  @return VI_OK, VI_ERR_DIM (n < 1 or kd < 0), VI_ERR_ARG, VI_ERR_NOMEM. */
VI_API int vi_model_create_band(int n, int kd, vi_model **out);
/** Set M from its symmetric band form AB [ldab x n], LAPACK 'U' storage
 *  (as dsbev and dpbtrf take it): entry (i, j), i <= j <= i + kd, at
 *  AB[kd + i - j + j ldab] (0-based; Fortran AB(kd+1+i-j, j)).  Rows above
 *  the band's first column are not read.  Any model: a dense one receives
 *  the expanded matrix; a band model needs kd at most its own half-bandwidth
 *  or zeros beyond it.  @return VI_OK, VI_ERR_DIM (kd < 0, ldab < kd + 1, a
 *  non-zero outside the model's band), VI_ERR_NONFINITE, VI_ERR_ARG,
 *  VI_ERR_STATE. */
VI_API int vi_model_set_mass_band(vi_model *m, int kd, const double *AB,
                                  int ldab);
/** Set C in band form as vi_model_set_mass_band; AB NULL means C = 0. */
VI_API int vi_model_set_damping_band(vi_model *m, int kd, const double *AB,
                                     int ldab);
/** Set K in band form as vi_model_set_mass_band. */
VI_API int vi_model_set_stiffness_band(vi_model *m, int kd, const double *AB,
                                       int ldab);
/** The paper's fixed-free chain (vi_build_chain) as a band model (kd = 1)
 *  with M, C, K set: the forcing and the stop remain to be set before
 *  vi_model_setup.  mass, k [n], c [n] or NULL.  *out is NULL on failure.
 *  @return VI_OK, VI_ERR_DIM, VI_ERR_ARG (a mass not positive, a spring or
 *  damper negative), VI_ERR_NONFINITE, VI_ERR_NOMEM. */
VI_API int vi_model_create_chain(int n, const double *mass, const double *k,
                                 const double *c, vi_model **out);
/** Bytes a model of n coordinates with ns stops and a simulation of it
 *  will need, estimated before anything is allocated: kd >= 0 for band
 *  storage of that half-bandwidth (vi_model_create_band), kd < 0 for dense
 *  storage (vi_model_create, including the modal analysis' workspace);
 *  method a VI_METHOD_* (vi_sim.h; the integrator's vectors, BDF's
 *  Jacobian), ledger 0 or 1.  Output buffers are not counted.
 *  @return VI_OK, VI_ERR_DIM (n < 1, ns < 0), VI_ERR_ARG,
 *  VI_ERR_UNSUPPORTED (band storage with the exact method or the ledger,
 *  which need the modes), VI_ERR_LIMIT (beyond int64). */
VI_API int vi_model_memory_estimate(int n, int kd, int ns, int method,
                                    int ledger, int64_t *bytes);
/** An upper bound of the highest natural frequency, for checks of the
 *  forcing frequency against the model: omega_n itself for a dense model,
 *  a Gershgorin bound for a band model (sqrt of the largest row sum of
 *  |M^-1 K| for a diagonal M; HUGE_VAL if M's rows are not diagonally
 *  dominant); 0 before setup. */
VI_API double vi_model_omega_bound(const vi_model *m);
/** @name Ranges of a run
 *  The one validation of a run's values, shared by the scene reader and
 *  vi_sim_run (vi_model_check_run).
 *  @{ */
#define VI_RUN_RTOL_MIN 4.4408920985006262e-16 /**< 2 DBL_EPSILON */
#define VI_RUN_RTOL_MAX 0.1          /**< loosest relative tolerance */
#define VI_RUN_ATOL_RATIO 0.01       /**< atol / length scale, at most */
#define VI_RUN_FREQ_RATIO_MIN 1e-8   /**< Omega / highest omega, at least */
#define VI_RUN_FREQ_RATIO_MAX 1e8    /**< Omega / highest omega, at most */
#define VI_RUN_ZETA_MAX 1e6          /**< largest modal damping ratio */
#define VI_RUN_STATE_RATIO 1e8       /**< initial state / length scale */
/** Check that a run of the set-up model m from (t0, x0, v0) to t_end with
 *  tolerances rtol, atol lies in the ranges double precision and the
 *  problem's own scales support; W is the fastest of the natural
 *  frequencies and the forcing, L the clearance or the static response to
 *  the loads: Omega within [1e-8, 1e8] times the highest natural
 *  frequency; modal damping ratios up to 1e6; |t| eps W <= 1e-3 and a span
 *  of at least 1e-9 / W (|t| <= 1e-3 / eps without any frequency); |x0| <=
 *  1e8 L, |v0| <= 1e8 L W; DBL_MIN <= atol <= 0.01 max(L, |x0|, |v0| / W);
 *  rtol in [VI_RUN_RTOL_MIN, VI_RUN_RTOL_MAX].  vi_sim_run applies it at
 *  its first start (and the time span on every call); the scene reader
 *  applies it to a scene, naming the line.  x0, v0 [n] may be NULL (0).
 *  On failure *key receives the scene key of the value ("forcing.omega",
 *  "model", "run.t_end", "initial.x", "initial.v", "run.atol",
 *  "run.rtol"; a static string), *value the value and msg[len] the reason
 *  (key, value, msg may be NULL).  @return VI_OK, VI_ERR_ARG (model not set
 *  up), VI_ERR_NONFINITE, VI_ERR_LIMIT. */
VI_API int vi_model_check_run(const vi_model *m, double t0, double t_end,
                              const double *x0, const double *v0, double rtol,
                              double atol, const char **key, double *value,
                              char *msg, int len);
/** @} */
/** Bytes the model holds now (its arrays and stops; 0 for NULL). */
VI_API int64_t vi_model_memory(const vi_model *m);
/** Half-bandwidth kd of a band model, -1 for dense storage (also before
 *  setup). */
VI_API int vi_model_bandwidth(const vi_model *m);

/** Set the mass matrix M [ldm x n] (copied; symmetric to 1e-12 relative,
 *  positive definite, checked at setup).  @return VI_OK, VI_ERR_DIM
 *  (ldm < n), VI_ERR_NONFINITE, VI_ERR_NOT_SYMMETRIC, VI_ERR_STATE. */
VI_API int vi_model_set_mass(vi_model *m, const double *M, int ldm);
/** Set the damping matrix C [ldc x n], symmetric positive semidefinite;
 *  NULL means C = 0.  Errors as vi_model_set_mass. */
VI_API int vi_model_set_damping(vi_model *m, const double *C, int ldc);
/** Set the stiffness matrix K [ldk x n], symmetric positive semidefinite
 *  (rigid-body modes allowed).  Errors as vi_model_set_mass. */
VI_API int vi_model_set_stiffness(vi_model *m, const double *K, int ldk);
/** Set the forcing f(t) = a cos(omega t) + b sin(omega t) + f0 (rad per time
 *  unit; vectors [n], each may be NULL = 0).  @return VI_OK,
 *  VI_ERR_FREQUENCY (omega <= 0 with a or b non-zero), VI_ERR_NONFINITE,
 *  VI_ERR_LIMIT (an entry above 1e100 in magnitude). */
VI_API int vi_model_set_forcing(vi_model *m, double omega, const double *a,
                                const double *b, const double *f0);
/** Set the stop w.x <= x_s (w [n], not zero) and the restitution r in
 *  [0, 1].  @return VI_OK, VI_ERR_STOP_VECTOR, VI_ERR_RESTITUTION,
 *  VI_ERR_NONFINITE, VI_ERR_ARG (w NULL). */
VI_API int vi_model_set_stop(vi_model *m, const double *w, double x_s,
                             double r);
/** Add a further stop w.x <= x_s with restitution r (appended: the first
 *  stop added to a model without one is stop 0, as vi_model_set_stop
 *  makes it; vi_model_set_stop later replaces stop 0 only).  Validation
 *  and errors as vi_model_set_stop, the message naming the stop (1-based).
 *  Stops should be independent where they can touch at once (the Delassus
 *  matrix G of the touching stops positive definite); a stop whose
 *  constraint cannot hold together with the others is not detected here,
 *  but by vi_sim_set_initial.  @return as vi_model_set_stop, and
 *  VI_ERR_NOMEM, VI_ERR_LIMIT. */
VI_API int vi_model_add_stop(vi_model *m, const double *w, double x_s,
                             double r);
/** Number of stops set so far (also before setup). */
VI_API int vi_model_num_stops(const vi_model *m);
/** Stop k (0-based, below vi_model_num_stops): w [n], *x_s, *r receive it
 *  (each may be NULL).  Also before setup.  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_model_stop(const vi_model *m, int k, double *w,
                             double *x_s, double *r);
/** Delassus matrix G = W^T M^-1 W [ns x ns] of the stops (W = [w_0 ...]),
 *  column-major, *ld receives ns; G_kk is stop k's compliance w_k^T M^-1
 *  w_k.  NULL before setup. */
VI_API const double *vi_model_delassus(const vi_model *m, int *ld);
/** Validate everything, factor M, solve the modal problem, freeze.
 *  @return VI_OK, VI_ERR_STOP_VECTOR (no stop set), VI_ERR_NOT_SPD (M),
 *  VI_ERR_NOT_PSD (C or K), VI_ERR_LAPACK, VI_ERR_NOMEM, VI_ERR_STATE. */
VI_API int vi_model_setup(vi_model *m);
/** Detail of the last error on this model, naming the culprit ("" if none);
 *  owned by the model, valid until its next call. */
VI_API const char *vi_model_errmsg(const vi_model *m);

/** @name Getters
 *  Valid after vi_model_setup: before it they return 0 or NULL.  The modal
 *  ones return NULL (or 0) for a band model, which has no modes.  Returned
 *  pointers are read-only views owned by the model, valid until it is
 *  destroyed.
 *  @{ */
/** Number of coordinates n (also before setup). */
VI_API int vi_model_n(const vi_model *m);
/** Forcing frequency Omega (rad per time unit; 0 without harmonic forcing). */
VI_API double vi_model_omega_forcing(const vi_model *m);
/** The forcing period T = 2 pi / Omega, the one place it is written out
 *  (0 without harmonic forcing, or before setup). */
VI_API double vi_model_forcing_period(const vi_model *m);
/** Clearance x_s of the stop (stop 0 with several). */
VI_API double vi_model_clearance(const vi_model *m);
/** Coefficient of restitution r (of stop 0 with several). */
VI_API double vi_model_restitution(const vi_model *m);
/** Mass matrix as set (exactly symmetric), column-major, leading dimension
 *  n; NULL for a band model (vi_model_mass_band), as the two below. */
VI_API const double *vi_model_mass(const vi_model *m);
/** Damping matrix as set, column-major, leading dimension n. */
VI_API const double *vi_model_damping(const vi_model *m);
/** Stiffness matrix as set, column-major, leading dimension n. */
VI_API const double *vi_model_stiffness(const vi_model *m);
/** M of a band model in LAPACK 'U' band form [*ldab x n] with
 *  half-bandwidth *kd (see vi_model_set_mass_band); NULL (and 0) for a
 *  dense model or before setup. */
VI_API const double *vi_model_mass_band(const vi_model *m, int *kd,
                                        int *ldab);
/** C of a band model in 'U' band form, as vi_model_mass_band. */
VI_API const double *vi_model_damping_band(const vi_model *m, int *kd,
                                           int *ldab);
/** K of a band model in 'U' band form, as vi_model_mass_band. */
VI_API const double *vi_model_stiffness_band(const vi_model *m, int *kd,
                                             int *ldab);
/** Stop vector w [n] (stop 0's with several: vi_model_stop). */
VI_API const double *vi_model_stop_vector(const vi_model *m);
/** Forcing amplitude a [n] of a cos(Omega t). */
VI_API const double *vi_model_forcing_cos(const vi_model *m);
/** Forcing amplitude b [n] of b sin(Omega t). */
VI_API const double *vi_model_forcing_sin(const vi_model *m);
/** Constant load f0 [n]. */
VI_API const double *vi_model_forcing_const(const vi_model *m);
/** Natural frequencies omega_j [n], ascending (rad per time unit), from
 *  K psi_j = omega_j^2 M psi_j (LAPACK dsygvd). */
VI_API const double *vi_model_omega(const vi_model *m);
/** Mode shapes Psi [n x n], column j = mode j, mass-normalised
 *  (Psi^T M Psi = I), largest-magnitude entry positive; *ld receives the
 *  leading dimension (n). */
VI_API const double *vi_model_modal_shapes(const vi_model *m, int *ld);
/** Modal damping D = Psi^T C Psi [n x n]; *ld receives n. */
VI_API const double *vi_model_modal_damping(const vi_model *m, int *ld);
/** Damping ratios zeta_j = D_jj / (2 omega_j) [n]; 0 for a rigid-body mode. */
VI_API const double *vi_model_zeta(const vi_model *m);
/** 1 if D is diagonal to 1e-10 relative (proportional damping: the modes
 *  decouple between impacts, WB 4, and XE = 0), else 0. */
VI_API int vi_model_is_proportional(const vi_model *m);
/** Modal impact vector psi = Psi^T w [n] (stop 0); psi.psi = w^T M^-1 w. */
VI_API const double *vi_model_modal_stop(const vi_model *m);
/** Modal forcing Psi^T a [n]. */
VI_API const double *vi_model_modal_forcing_cos(const vi_model *m);
/** Modal forcing Psi^T b [n]. */
VI_API const double *vi_model_modal_forcing_sin(const vi_model *m);
/** Modal constant load Psi^T f0 [n]. */
VI_API const double *vi_model_modal_forcing_const(const vi_model *m);
/** w^T M^-1 w: the inverse of the stop's effective mass (WB 10; stop 0,
 *  the others' are the diagonal of vi_model_delassus). */
VI_API double vi_model_stop_compliance(const vi_model *m);
/** @} */

/** Modal coordinates q = Psi^T M x of x [n] into q [n] (also velocities);
 *  the arrays must not overlap.  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE. */
VI_API int vi_model_to_modal(const vi_model *m, const double *x, double *q);
/** Physical coordinates x = Psi q of q [n] into x [n]; no overlap.
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE. */
VI_API int vi_model_from_modal(const vi_model *m, const double *q, double *x);
/** Total mechanical energy 1/2 v^T M v + 1/2 x^T K x of x, v [n]
 *  (NaN for NULL arguments). */
VI_API double vi_model_energy(const vi_model *m, const double *x,
                              const double *v);

/** The paper's fixed-free chain (MODEL.md section 1), into caller arrays:
 *  element j joins mass j-1 (mass 0 to the ground) to mass j with spring k_j
 *  and dashpot c_j.  mass, k, c [n] (c may be NULL: no damping); M, C, K are
 *  written n x n column-major with leading dimension ld >= n.
 *  @return VI_OK, VI_ERR_DIM, VI_ERR_ARG. */
VI_API int vi_build_chain(int n, const double *mass, const double *k,
                          const double *c, double *M, double *C, double *K,
                          int ld);
/** The same chain in LAPACK 'U' band form with kd = 1 (n >= 1): MB, CB, KB
 *  [ldab x n], ldab >= 2, row 1 (0-based) the diagonal, row 0 the
 *  superdiagonal, for vi_model_set_*_band.  @return as vi_build_chain. */
VI_API int vi_build_chain_band(int n, const double *mass, const double *k,
                               const double *c, double *MB, double *CB,
                               double *KB, int ldab);

#ifdef __cplusplus
}
#endif
#endif
