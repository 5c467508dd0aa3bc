/** @file vi_flow.h
 * The exact flow between impacts (MODEL.md section 8).
 *
 * Between impacts the structure is linear with harmonic forcing.  For
 * proportional damping every mode is a forced damped oscillator with a
 * closed-form solution (under-, critically and over-damped, rigid-body
 * modes included).  For any other damping the first-order system
 * z' = A z + b(t) is diagonalised (LAPACK dgeev) and each complex mode has
 * a closed form.  This is both the integrator of the VI_METHOD_EXACT
 * simulation and the reference against which the CVODE path's error is
 * measured. */
#ifndef VI_FLOW_H
#define VI_FLOW_H

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_model.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Advance the free (stop-ignoring) motion from (t0, x0, v0) to t >= t0:
 * x, v [n] receive the state at t.  Arrays may not overlap.
 * @return VI_OK, VI_ERR_ARG, VI_ERR_STATE (model not set up), VI_ERR_TIME
 * (t < t0), VI_ERR_NONFINITE (a time not finite), VI_ERR_LIMIT (|t| eps W
 * above 1e-3, W the highest of the natural and forcing frequencies:
 * double precision no longer resolves the phase, e.g. t = 1e300),
 * VI_ERR_NOMEM, VI_ERR_UNSUPPORTED for an undamped mode forced
 * exactly at its natural frequency (secular growth) and for a defective
 * first-order system (an undamped rigid-body mode beside non-proportional
 * damping). */
VI_API int vi_flow_physical(const vi_model *m, double t0, const double *x0,
                            const double *v0, double t, double *x, double *v);
/** The same in modal coordinates q, q' [n] (q = Psi^T M x). */
VI_API int vi_flow_modal(const vi_model *m, double t0, const double *q0,
                         const double *qd0, double t, double *q, double *qd);

#ifdef __cplusplus
}
#endif
#endif
