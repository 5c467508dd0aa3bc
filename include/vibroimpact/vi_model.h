/* vi_model.h - the linear structure, its forcing and the stop.
 *
 *   M x'' + C x' + K x = a cos(Omega t) + b sin(Omega t) + f0      (WB 1)
 *   w.x <= x_s, Newton impact with restitution r                     (WB 2)
 *
 * Life cycle: vi_model_create -> vi_model_set_* -> vi_model_setup ->
 * (getters, vi_sim_create) -> vi_model_destroy.  Every array is copied when
 * it is set; matrices are column-major with a leading dimension (LAPACK),
 * so a Fortran caller passes its arrays unchanged.  After vi_model_setup the
 * model is frozen (setters return VI_ERR_STATE) and may be shared by threads.
 * Indices in messages are 1-based, as a Fortran or MATLAB user reads them. */
#ifndef VI_MODEL_H
#define VI_MODEL_H

#include "vibroimpact/vi_export.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vi_model vi_model;

/* A model with n >= 1 coordinates: M = I, C = K = 0, no forcing, no stop
 * (w must be set before setup). */
VI_API int vi_model_create(int n, vi_model **out);
/* NULL-safe; clears the caller's pointer. */
VI_API void vi_model_destroy(vi_model **model);

/* M symmetric positive definite (checked at setup by Cholesky). */
VI_API int vi_model_set_mass(vi_model *m, const double *M, int ldm);
/* C symmetric positive semidefinite; NULL means C = 0. */
VI_API int vi_model_set_damping(vi_model *m, const double *C, int ldc);
/* K symmetric positive semidefinite (rigid-body modes allowed). */
VI_API int vi_model_set_stiffness(vi_model *m, const double *K, int ldk);
/* Forcing f(t) = a cos(omega t) + b sin(omega t) + f0; any of a, b, f0 may be
 * NULL (zero).  omega must be > 0 when a or b is non-zero. */
VI_API int vi_model_set_forcing(vi_model *m, double omega, const double *a,
                                const double *b, const double *f0);
/* The stop w.x <= x_s with restitution r in [0, 1]; w != 0. */
VI_API int vi_model_set_stop(vi_model *m, const double *w, double x_s,
                             double r);
/* Validate everything, factor M, solve the modal problem; freezes the model. */
VI_API int vi_model_setup(vi_model *m);
/* Detail of the last error on this model ("" if none); owned by the model. */
VI_API const char *vi_model_errmsg(const vi_model *m);

/* ---- getters: valid after vi_model_setup (NULL / 0 before) ----------------
 * Returned pointers are read-only views owned by the model, valid until it
 * is destroyed. */
VI_API int vi_model_n(const vi_model *m);
VI_API double vi_model_omega_forcing(const vi_model *m);
VI_API double vi_model_clearance(const vi_model *m);  /* x_s */
VI_API double vi_model_restitution(const vi_model *m); /* r */
/* Physical matrices as set (column-major, leading dimension n). */
VI_API const double *vi_model_mass(const vi_model *m);
VI_API const double *vi_model_damping(const vi_model *m);
VI_API const double *vi_model_stiffness(const vi_model *m);
VI_API const double *vi_model_stop_vector(const vi_model *m);     /* w [n] */
/* a, b, f0 [n] each. */
VI_API const double *vi_model_forcing_cos(const vi_model *m);
VI_API const double *vi_model_forcing_sin(const vi_model *m);
VI_API const double *vi_model_forcing_const(const vi_model *m);

/* Modal analysis: K psi_j = omega_j^2 M psi_j, Psi^T M Psi = I.
 * omega [n] ascending (rad per time unit); Psi column j is mode j, with its
 * largest-magnitude entry positive; *ld receives the leading dimension. */
VI_API const double *vi_model_omega(const vi_model *m);
VI_API const double *vi_model_modal_shapes(const vi_model *m, int *ld);
/* D = Psi^T C Psi [n x n], column-major, leading dimension n. */
VI_API const double *vi_model_modal_damping(const vi_model *m, int *ld);
/* zeta_j = D_jj / (2 omega_j); 0 for a rigid-body mode (omega_j = 0). */
VI_API const double *vi_model_zeta(const vi_model *m);
/* 1 if D is diagonal to 1e-12 relative (modes decouple between impacts). */
VI_API int vi_model_is_proportional(const vi_model *m);
/* Modal impact vector psi = Psi^T w [n]; psi.psi = w^T M^-1 w. */
VI_API const double *vi_model_modal_stop(const vi_model *m);
/* Modal forces Psi^T a, Psi^T b, Psi^T f0 [n] each. */
VI_API const double *vi_model_modal_forcing_cos(const vi_model *m);
VI_API const double *vi_model_modal_forcing_sin(const vi_model *m);
VI_API const double *vi_model_modal_forcing_const(const vi_model *m);
/* w^T M^-1 w: the inverse of the stop's effective mass. */
VI_API double vi_model_stop_compliance(const vi_model *m);

/* Coordinate changes: q = Psi^T M x and x = Psi q (also for velocities).
 * x and q [n], caller-owned; they must not overlap. */
VI_API int vi_model_to_modal(const vi_model *m, const double *x, double *q);
VI_API int vi_model_from_modal(const vi_model *m, const double *q, double *x);
/* Total mechanical energy 1/2 v^T M v + 1/2 x^T K x. */
VI_API double vi_model_energy(const vi_model *m, const double *x,
                              const double *v);

/* ---- model builders: fill caller arrays, no handle needed ----------------
 * The paper's fixed-free chain (MODEL.md section 1): mass j is tied to mass
 * j-1 (mass 0 to the ground) by spring k_j and dashpot c_j.  mass, k, c are
 * arrays of length n (c may be NULL for no damping); M, C, K are written
 * n x n column-major with leading dimension ld >= n. */
VI_API int vi_build_chain(int n, const double *mass, const double *k,
                          const double *c, double *M, double *C, double *K,
                          int ld);

#ifdef __cplusplus
}
#endif
#endif
