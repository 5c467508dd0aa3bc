/** @file vi_builders.h
 * model builders: the paper's clamped-free cantilever (MODEL.md section 6)
 * into caller arrays, and the reduced model that keeps a subset of a
 * set-up model's modes (MODEL.md section 5).  The chain builders are in
 * vi_model.h (vi_build_chain, vi_build_chain_band, vi_model_create_chain). */
#ifndef VI_BUILDERS_H
#define VI_BUILDERS_H

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_model.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The reduced model itself, in the modal coordinates of `full`: M = I,
 * K = diag(omega_S^2), C = D_SS, forcing Psi_S^T (a, b, f0), stop psi_S
 * with the same x_s and restitution r.  A new, set-up model; a model with
 * several stops is refused (VI_ERR_UNSUPPORTED). */
VI_API int vi_model_create_reduced(const vi_model *full, const int *modes,
                                   int k, double r, vi_model **out);

/** A truncated model of a model R in modal coordinates (M = I, K
 * diagonal: vi_model_create_reduced with every mode, vi_fe_create_model),
 * as `vibroimpact truncation` studies it (MODEL.md section 5): R's first k
 * coordinates and, with static_vector = 1, the static residual vector at
 * the stop, c_j = psi_j / K_jj for j >= k (K^-1 w less its part in the
 * kept modes), normalised.  With T [n_R x (k + static_vector)] those
 * columns: M = T^T T (= I), K = T^T K T, C = T^T C T, stop T^T psi with
 * R's x_s and restitution r, forcing T^T (a, b, f0).  z [2 n_R] (x then v
 * of R; may be NULL) is projected into zt [2 (k + static_vector)] (T^T,
 * T orthonormal); *carried (may be NULL) receives the stop's compliance
 * the truncated coordinates carry, |T^T psi|^2.  A new, set-up model.
 * @return VI_OK, VI_ERR_ARG (NULL, k outside 1..n_R, static_vector not 0
 * or 1, or no residual: k = n_R or psi zero beyond k), VI_ERR_STATE (R not
 * set up), VI_ERR_UNSUPPORTED (band storage), VI_ERR_NOMEM, or the
 * model's own error (r outside [0, 1]: VI_ERR_RESTITUTION). */
VI_API int vi_model_create_truncated(const vi_model *R, int k,
                                     int static_vector, double r,
                                     const double *z, double *zt,
                                     double *carried, vi_model **out);

/** The stop's compliance carried by the first modes of a model R in modal
 * coordinates (M = I, K diagonal: vi_model_create_reduced with every
 * mode, vi_fe_create_model), as `vibroimpact truncation` reports it
 * (MODEL.md section 5): with psi the stop's vector in R, for j = 1..k
 * dynamic[j-1] = sum_{i<=j} psi_i^2 (of w^T M^-1 w, the Delassus number
 * of Newton's law, WB 2, 10) and static_part[j-1] = sum_{i<=j}
 * psi_i^2 / K_ii (of w^T K^-1 w; INFINITY once a mode with K_ii <= 0 and
 * psi_i != 0 is included).  With k = n the sums are R's whole
 * compliances.  dynamic, static_part [k] (either may be NULL).
 * @return VI_OK, VI_ERR_ARG (NULL R, k outside 1..n, stop outside
 * 0..stops-1, or R not in modal coordinates: M != I or K not diagonal, to
 * 1e-12), VI_ERR_STATE (R not set up), VI_ERR_UNSUPPORTED (band
 * storage). */
VI_API int vi_model_modal_compliance(const vi_model *R, int stop, int k,
                                     double *dynamic, double *static_part);

/** The paper's beam: a clamped-free Euler-Bernoulli cantilever.
 * Mode j (0-based) of a unit-length, unit-mass-per-length cantilever: beta_j
 * solves cos(beta) cosh(beta) = -1 and the mass-normalised shape is
 *   phi_j(xi) = cosh(b xi) - cos(b xi) - s_j (sinh(b xi) - sin(b xi)).
 * vi_cantilever_shape evaluates phi_j(xi), xi in [0, 1], stably for large
 * beta.  vi_cantilever_beta returns beta_j (j = 0: 1.8751041), NaN for j
 * outside 0..200. */
VI_API double vi_cantilever_beta(int j);
/** phi_j(xi) of the cantilever, xi in [0, 1] (0 the clamp, 1 the tip);
 *  |phi_j(1)| = 2; NaN for j outside 0..200. */
VI_API double vi_cantilever_shape(int j, double xi);
/** Integral of phi_j over the span (the participation of a uniform base
 * acceleration): 2 s_j / beta_j. */
VI_API double vi_cantilever_participation(int j);
/** Galerkin model with `modes` modes in modal coordinates: M = I,
 * K = diag(omega_j^2) with omega_j = omega1 (beta_j / beta_1)^2,
 * C = diag(2 zeta omega_j); w_j = phi_j(xi_stop) (the stop acts at
 * xi_stop, 1 = the free end); gamma_j = participation.  A base acceleration
 * A cos(Omega t) is the forcing a = -A gamma.  M, C, K [ld x modes].
 * @return VI_OK, VI_ERR_DIM, VI_ERR_LIMIT (more than 201 modes), VI_ERR_ARG,
 * VI_ERR_STOP_VECTOR (xi_stop = 0, the clamp, or so near it that w is
 * round-off: a stop no motion can reach). */
VI_API int vi_build_cantilever(int modes, double omega1, double zeta,
                               double xi_stop, double *M, double *C,
                               double *K, int ld, double *w, double *gamma);

#ifdef __cplusplus
}
#endif
#endif
