/** @file vi_impact.h
 * the Newton restitution law as pure functions of velocities.
 *
 *   x'(t+) = x'(t-) - (1 + r) v_n M^-1 w / (w^T M^-1 w)               (WB 2)
 *   IE     = 1/2 v_n^2 (1 - r^2) / (w^T M^-1 w)                        (WB 10)
 *
 * They know nothing of the integrator.  They and the simulation's impacts
 * run one solver, Newton's law for simultaneous contacts below: the
 * single-stop functions are its case of one contact on stop 0.
 *
 * Several stops touching at once (Newton's law for multiple contacts,
 * Glocker & Pfeiffer): with W = [w_k] over the contacts, G = W^T M^-1 W
 * (the Delassus matrix) and u_k = w_k.x'(t-) the approach velocities,
 *
 *   x'(t+) = x'(t-) - M^-1 W P,   P >= 0,   y = G P - e >= 0,   P_k y_k = 0
 *   e_k = (1 + r_k) u_k for an approaching contact (u_k > 0), so that
 *         w_k.x'(t+) <= -r_k u_k, with equality where P_k > 0;
 *   e_k = u_k for a contact that is closed but not approaching (plastic:
 *         it must not start to approach through the others' impulses).
 *
 * The kinetic energy lost is P.u - P.G P / 2 = sum_k P_k (u_k - e_k / 2),
 * 1/2 sum_k P_k u_k (1 - r_k) when all approach: none for r = 1.  With G
 * positive definite (independent stop vectors) the solution is unique; it
 * is found by enumerating the active sets {k : P_k > 0} by increasing size,
 * 2^nc sets of an nc x nc solve, hence the limit of 12 contacts at one
 * instant (VI_ERR_LIMIT beyond).  One contact is exactly WB 2. */
#ifndef VI_IMPACT_H
#define VI_IMPACT_H

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_model.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Apply WB 2 with the model's r to v_minus [n], writing v_plus [n] (may be the
 * same array).  *vn receives the approach velocity w.v_minus and *ie the
 * kinetic energy lost (WB 10); either may be NULL.  The model must be set up.
 * An approach velocity vn <= 0 is not an impact: v_plus = v_minus, *ie = 0. */
VI_API int vi_impact_apply(const vi_model *m, const double *v_minus,
                           double *v_plus, double *vn, double *ie);

/** Same law with an explicit restitution r in [0, 1] (r = 0 gives the plastic
 * impact that starts a sticking phase). */
VI_API int vi_impact_apply_r(const vi_model *m, double r,
                             const double *v_minus, double *v_plus,
                             double *vn, double *ie);

/** Newton's law for nc simultaneous contacts with the stops stops [nc]
 *  (0-based, distinct) from v_minus [n] into v_plus [n] (may be the same
 *  array); P [nc] receives the impulses and ie [nc] the energy each contact
 *  takes (summing to the kinetic energy lost); either may be NULL.
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE (model not set up), VI_ERR_LIMIT
 *  (nc > 12), VI_ERR_NOT_CONVERGED (no solution: G singular on these
 *  stops, e.g. two stops with the same w). */
VI_API int vi_impact_apply_multi(const vi_model *m, int nc, const int *stops,
                                 const double *v_minus, double *v_plus,
                                 double *P, double *ie);

/** Evaluate WB 13: r = sqrt(1 - RE / KE_i) for 0 <= RE <= KE_i, KE_i > 0;
 * VI_ERR_ARG otherwise (an RE outside [0, KE_i] has no real r). */
VI_API int vi_restitution_from_energy(double re, double ke_i, double *r);

#ifdef __cplusplus
}
#endif
#endif
