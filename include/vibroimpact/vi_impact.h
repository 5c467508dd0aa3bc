/** @file vi_impact.h
 * the Newton restitution law as pure functions of velocities.
 *
 *   x'(t+) = x'(t-) - (1 + r) v_n M^-1 w / (w^T M^-1 w)               (WB 2)
 *   IE     = 1/2 v_n^2 (1 - r^2) / (w^T M^-1 w)                        (WB 10)
 *
 * They know nothing of the integrator; vi_sim calls them at each contact. */
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

/** Evaluate WB 13: r = sqrt(1 - RE / KE_i) for 0 <= RE <= KE_i, KE_i > 0;
 * VI_ERR_ARG otherwise (an RE outside [0, KE_i] has no real r). */
VI_API int vi_restitution_from_energy(double re, double ke_i, double *r);

#ifdef __cplusplus
}
#endif
#endif
