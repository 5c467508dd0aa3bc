/** @file vi_census.h
 * The census of P(n, m) periodic orbits of a model: every orbit found
 * directly, unstable and inadmissible ones included, each with its Floquet
 * multipliers and its admissibility (what `vibroimpact orbits` prints).
 *
 * Seeds (MODEL.md, periodic orbits):
 * - for m = 1 and one stop, the exhaustive scan of impact phases
 *   (vi_orbit_p1_scan: every P(n, 1) orbit);
 * - for any m, the motions transients settle on: from the initial state
 *   given by vi_census_set_initial (if any), then from rest at 8 forcing
 *   phases t0 = k T / 8, each run with the closed-form flow until its
 *   stroboscopic states repeat with period n three times (1e-9 relative)
 *   with m impacts per n T, for at most 2000 forcing periods.
 *
 * Each seed is refined by Newton (vi_orbit_pnm_solve_stops); impact times
 * are moved into [0, nT).  A refined orbit equal to one already found (the
 * same impacts on the same stops up to a cyclic shift, times to 1e-7 T
 * modulo T, velocities to 1e-6 relative) is dropped, and so is a
 * P(n/k, m/k) orbit traversed k times (its impacts recurring m/k impacts
 * and nT/k later: a transient that settles on P(1,1) repeats with period
 * 2T too, but it is not a P(2,2) orbit).  A new orbit gets its
 * multipliers (vi_orbit_pnm_multipliers_stops: monodromy with saltation
 * matrices), stability (all |mu| < 1) and admissibility
 * (vi_orbit_pnm_admissible_stops).  With several stops each impact keeps
 * the stop it hit (the seeds are transients only: the scan is for one
 * stop).  A seed whose run or Newton iteration fails is skipped.
 *
 *   vi_census_create(model, n, m, &c)    the model is borrowed
 *   vi_census_set_phases / _set_initial / _set_sim_hook / _set_monitor
 *   vi_census_run(c)                     the monitor sees each new orbit
 *   for i < vi_census_count(c):
 *     vi_census_orbit(c, i, ...), vi_census_stability(c, i, ...)
 *   vi_census_destroy(&c)
 *
 * A census is one thread's; censuses on other threads may share the
 * model, which no census changes.
 */
#ifndef VI_CENSUS_H
#define VI_CENSUS_H

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_model.h"
#include "vibroimpact/vi_sim.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Opaque orbit-census handle. */
typedef struct vi_census vi_census;

/** Monitor: called once per new orbit, index its 0-based place in the
 *  census (vi_census_orbit may read it).  Non-zero makes vi_census_run
 *  return VI_STOPPED with the orbits found so far kept. */
typedef int (*vi_census_monitor_fn)(const vi_census *c, int index,
                                    void *user);
/** Sim hook: called on every transient simulation after it is created and
 *  before the census sets its method (closed form) and initial state, to
 *  add a caller's run settings.  Non-zero skips that seed. */
typedef int (*vi_census_sim_fn)(vi_sim *sim, void *user);

/** Create a census of the P(n, m) orbits (1 <= n, m <= 64) of a set-up
 *  model with harmonic forcing and at least one stop; the model is
 *  borrowed and must outlive the census.  720 scan phases, no initial
 *  state of its own.
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE (model not set up, or no stop),
 *  VI_ERR_FREQUENCY (Omega = 0), VI_ERR_UNSUPPORTED (band storage: no
 *  modes), VI_ERR_NOMEM. */
VI_API int vi_census_create(const vi_model *model, int n, int m,
                            vi_census **out);
/** Destroy and set *c to NULL; NULL-safe. */
VI_API void vi_census_destroy(vi_census **c);
/** Detail of the last error ("" if none), owned by the census. */
VI_API const char *vi_census_errmsg(const vi_census *c);

/** Impact phases of the scan (vi_orbit_p1_scan), nphase >= 8 (default
 *  720).  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_census_set_phases(vi_census *c, int nphase);
/** One more transient seed, run first, from (t0, x, v) (x, v [n]; NULL =
 *  0): a scene's initial state.  @return VI_OK, VI_ERR_ARG,
 *  VI_ERR_NONFINITE. */
VI_API int vi_census_set_initial(vi_census *c, double t0, const double *x,
                                 const double *v);
/** Hook on each transient simulation (fn NULL: none); user is handed
 *  over as vi_sim_set_event_callback does.  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_census_set_sim_hook(vi_census *c, vi_census_sim_fn fn,
                                  void *user, vi_destroy_fn destroy);
/** Monitor of each new orbit (fn NULL: none).  @return VI_OK,
 *  VI_ERR_ARG. */
VI_API int vi_census_set_monitor(vi_census *c, vi_census_monitor_fn fn,
                                 void *user, vi_destroy_fn destroy);
/** Cancellation, polled by the phase scan (vi_orbit_p1_scan_polled) and
 *  by the transient simulations (vi_sim_set_cancel): vi_census_run then
 *  returns VI_CANCELLED.  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_census_set_cancel(vi_census *c, vi_cancel_fn fn, void *user,
                                vi_destroy_fn destroy);

/** Find the orbits (a previous census is forgotten).  @return VI_OK,
 *  VI_STOPPED (the monitor asked), VI_CANCELLED, VI_ERR_NOMEM, or the
 *  scan's error (vi_orbit_p1_scan; message in vi_census_errmsg). */
VI_API int vi_census_run(vi_census *c);
/** Number of orbits found (0 before vi_census_run or for NULL). */
VI_API int vi_census_count(const vi_census *c);
/** Orbit i (0-based, in order of discovery): its m impacts, t [m] (times
 *  in [0, nT)), the pre-impact states x, v [ld x m] (ld >= n), the stop
 *  of each, stop [m] (0-based), and the approach velocity w_k.v of each,
 *  vn [m].  Any pointer may be NULL.  @return VI_OK, VI_ERR_ARG (i out of
 *  range), VI_ERR_DIM (ld < n). */
VI_API int vi_census_orbit(const vi_census *c, int i, double *t, double *x,
                           double *v, int ld, int *stop, double *vn);
/** Stability of orbit i: Floquet multipliers re, im [2n]; *stable = 1 if
 *  every |mu| < 1; *admissible = 1 if every impact approaches its stop and
 *  no stop is crossed between impacts; *gmax the largest gap
 *  w.x - x_s between impacts (vi_orbit_pnm_admissible_stops).  Any
 *  pointer may be NULL.  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_census_stability(const vi_census *c, int i, double *re,
                               double *im, int *stable, int *admissible,
                               double *gmax);

#ifdef __cplusplus
}
#endif
#endif
