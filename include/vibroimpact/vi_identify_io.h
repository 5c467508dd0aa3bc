/** @file vi_identify_io.h
 * HDF5 output of an identification (companion library vibroimpact_h5):
 * the recording, the fitted model's response at its times and the fit.
 *
 * Layout (one group /identify):
 *   t [ns], x [ns]          the recording (time, observed displacement)
 *   model [ns]              the fitted model's response at t (c.x)
 *   residual [ns]           x - model
 *   phase [ns]              (t + t0 - t_1) mod P / P in [0, 1): where each
 *                           sample falls in the fitted orbit's period P,
 *                           counted from its first impact t_1
 *   value, stderr, lo95, hi95 [np], flags [np] (VI_IDENTIFY_* bits)
 *                           the best fit: Jacobian intervals
 *   profile_lo95, profile_hi95, profile_flags [np]
 *                           its profile-likelihood intervals
 *                           (VI_IDENTIFY_PROFILE_* bits)
 *   correlation [np x np]
 *   solutions/              every fit the data admit, best first (row k
 *                           is vi_identify_solution k):
 *     value, stderr, lo95, hi95, profile_lo95, profile_hi95, flags,
 *     profile_flags [nsol x np]; orbit_n, orbit_m, rms_residual,
 *     residual_ratio, delta_chi2, separation, record_factor [nsol]
 *     (vi_identify_solution_separation); attributes unique (1: one
 *     solution), count (nsol)
 *   attributes: keys (comma-separated), shift, shift_stderr, period,
 *     orbit_n, orbit_m, converged, iterations, rms_residual, noise, rcond,
 *     r_energy_balance, vN_recorded
 * Written as TARGET.part and renamed: a failure leaves no file. */
#ifndef VI_IDENTIFY_IO_H
#define VI_IDENTIFY_IO_H

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_identify.h"
#include "vibroimpact/vi_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Write a completed identification and its recording t, x [ns] to the
 *  HDF5 file `path` (a regular file; see vi_output_resolve).  keys names
 *  the parameters for the file (comma-separated, may be NULL).
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE (no completed fit),
 *  VI_ERR_IO (message in diag), VI_ERR_NOMEM. */
VI_API int vi_identify_write_h5(const char *path, const vi_identify *id,
                                const char *keys, int ns, const double *t,
                                const double *x, vi_diag *diag);

#ifdef __cplusplus
}
#endif
#endif
