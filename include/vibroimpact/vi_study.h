/** @file vi_study.h
 * Parameter studies: bifurcation diagrams, two-parameter maps and basins
 * of attraction, one point at a time, the loop in the caller's hands (as
 * GSL's ode driver over step/evolve, or gsl_multiroot_fsolver_iterate).
 *
 * A point is the study's model at its current parameters (vi_param.h
 * keys, set by vi_sweep_set_param), simulated for `transient` forcing
 * periods and `record` more, whose impacts (time, time mod T, approach
 * velocity) and stroboscopic states (at t0 + (transient + k) T,
 * k = 1..record) are kept; the motion is then classified P(n, m): the
 * smallest n <= nmax with z_{k+n} = z_k for every recorded k (to tol
 * relative to the largest state entry or |x_s|), m the impacts in the last
 * n periods (vi_classify_record).
 *
 *   vi_sweep_create(model, &sw)          the study works on its own copy
 *   vi_sweep_set_periods / _set_run / _set_initial / _set_warm / ...
 *   for each value:
 *     vi_sweep_set_param(sw, "forcing.omega", value)
 *     vi_sweep_iterate(sw)               one point
 *     vi_sweep_period(sw, &n, &m), vi_sweep_impacts(...), ...
 *   vi_sweep_destroy(&sw)
 *
 * Warm start (the default, a bifurcation diagram): a point starts from the
 * state the previous one ended in, at the same forcing phase (time t0),
 * so sweeps up and down show hysteresis; a state the stops have moved
 * past is put back on them along w_k (positions only).  Without warm
 * start (a basin of attraction), every point starts from the study's
 * initial state, which the keys initial.t0, initial.x[i], initial.v[i]
 * change.  After a failed point the next one starts cold.
 *
 * A monitor (as PETSc's TSMonitorSet) is called after each point.  A
 * study is one thread's: studies on other threads are made from the same
 * model, each copying it (the model is not changed by a study).
 */
#ifndef VI_STUDY_H
#define VI_STUDY_H

#include <stdint.h>

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_model.h"
#include "vibroimpact/vi_sim.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Opaque study handle. */
typedef struct vi_sweep vi_sweep;

/** Monitor: called after each point (also a failed one, status its
 *  error) with the number of points done so far (1-based).  Return
 *  non-zero to make vi_sweep_iterate return VI_STOPPED. */
typedef int (*vi_sweep_monitor_fn)(const vi_sweep *sw, int64_t point,
                                   int status, void *user);
/** Sim hook: called on every simulation the study makes, before the
 *  study sets its initial state, to add what a model does not hold
 *  (nonlinear springs, a scene's run settings).  Non-zero fails the point
 *  with that status. */
typedef int (*vi_sweep_sim_fn)(vi_sim *sim, void *user);

/** Create a study of (a copy of) the set-up model m: transient 100 and
 *  record 10 periods, tolerance 1e-6, nmax 32, warm start, method auto
 *  with rtol 1e-8 and atol 1e-10, starting at rest at t0 = 0.
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE (m not set up), VI_ERR_NOMEM. */
VI_API int vi_sweep_create(const vi_model *m, vi_sweep **out);
/** Destroy and set *sw to NULL; NULL-safe. */
VI_API void vi_sweep_destroy(vi_sweep **sw);
/** Detail of the last error ("" if none), owned by the study. */
VI_API const char *vi_sweep_errmsg(const vi_sweep *sw);

/** Transient and recorded forcing periods per point (transient >= 0,
 *  record >= 2).  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_sweep_set_periods(vi_sweep *sw, int transient, int record);
/** Classification tolerance (relative, > 0) and longest period looked
 *  for, nmax >= 1 forcing periods.  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_sweep_set_classify(vi_sweep *sw, double tol, int nmax);
/** Method (VI_METHOD_*) and tolerances of the simulations.
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_TOLERANCE. */
VI_API int vi_sweep_set_run(vi_sweep *sw, int method, double rtol,
                            double atol);
/** The initial state (t0; x, v [n]; NULL = 0) of a cold start; the warm
 *  state is forgotten.  @return VI_OK, VI_ERR_ARG, VI_ERR_NONFINITE. */
VI_API int vi_sweep_set_initial(vi_sweep *sw, double t0, const double *x,
                                const double *v);
/** 1: warm start (default); 0: every point from the initial state.
 *  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_sweep_set_warm(vi_sweep *sw, int warm);
/** The warm state the next point starts from (x, v [n], at the forcing
 *  phase of t0): the state the last point ended in.  With
 *  vi_sweep_set_warm_state it hands a branch from one study to another
 *  (the program's chunked sweep seeds each chunk so).  @return VI_OK,
 *  VI_ERR_ARG, VI_ERR_STATE (none: the last point failed or warm start
 *  is off). */
VI_API int vi_sweep_warm_state(const vi_sweep *sw, double *x, double *v);
/** Start the next point from (x, v [n]) at t0 instead of the initial
 *  state; warm start must be on.  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE
 *  (warm start off), VI_ERR_NONFINITE. */
VI_API int vi_sweep_set_warm_state(vi_sweep *sw, const double *x,
                                   const double *v);
/** Set a parameter (vi_param.h): a model key changes the study's model,
 *  an initial-state key its initial state.  @return as
 *  vi_model_set_param / vi_param_set_initial (message in
 *  vi_sweep_errmsg). */
VI_API int vi_sweep_set_param(vi_sweep *sw, const char *key, double value);
/** Read a parameter of the study (model or initial state).
 *  @return as vi_sweep_set_param. */
VI_API int vi_sweep_param(const vi_sweep *sw, const char *key,
                          double *value);
/** Forget the warm state: the next point starts from the initial state.
 *  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_sweep_reset(vi_sweep *sw);
/** Monitor after each point (fn NULL: none); user is handed over as
 *  vi_sim_set_event_callback does.  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_sweep_set_monitor(vi_sweep *sw, vi_sweep_monitor_fn fn,
                                void *user, vi_destroy_fn destroy);
/** Hook on each simulation (fn NULL: none).  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_sweep_set_sim_hook(vi_sweep *sw, vi_sweep_sim_fn fn,
                                 void *user, vi_destroy_fn destroy);
/** Cancellation (fn NULL: none).  vi_sweep_iterate polls it before the
 *  point starts; then the P(1,1) census polls it once per scan phase
 *  (vi_census_set_cancel, vi_orbit_p1_scan_polled), the point's
 *  simulation at every step (vi_sim_set_cancel), the Lyapunov run once
 *  per forcing period (a cancelled one leaves NaN), and vi_sweep_iterate
 *  once more after the point.  A cancelled point returns VI_CANCELLED and
 *  its results are not to be used.  user is handed over as vi_sweep_set_monitor does.
 *  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_sweep_set_cancel(vi_sweep *sw, vi_cancel_fn fn, void *user,
                               vi_destroy_fn destroy);

/** Also find every P(1,1) orbit at each point, unstable ones included
 *  (the orbit census, vi_census.h, seeded by its phase scan alone,
 *  vi_orbit_p1_scan with nphase impact phases; 0: off, the default):
 *  the branches a diagram cannot reach by simulation.
 *  @return VI_OK, VI_ERR_ARG (nphase < 0 or 1 .. 7). */
VI_API int vi_sweep_set_orbits(vi_sweep *sw, int nphase);

/** Also the largest Lyapunov exponent of each point (on = 1; default 0):
 *  carried on from the point's end state over `record` more periods by
 *  vi_orbit_lyapunov (exact state-transition and saltation matrices), to
 *  tell chaos (> 0) from a long period (< 0).  Needs a model with the
 *  closed-form flow and t0 a whole number of forcing periods; NaN where
 *  refused (vi_orbit_lyapunov's cases).  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_sweep_set_lyapunov(vi_sweep *sw, int on);
/** The last point's largest Lyapunov exponent (per unit time); NaN when
 *  not asked for (vi_sweep_set_lyapunov), refused or before a point. */
VI_API double vi_sweep_lyapunov(const vi_sweep *sw);

/** Compute one point at the current parameters.  On an error the point
 *  is marked failed (vi_sweep_failed), its results are empty and the next
 *  point starts cold.  @return VI_OK, VI_STOPPED (the monitor asked),
 *  VI_CANCELLED, VI_ERR_FREQUENCY (no harmonic forcing: no period), or
 *  the simulation's error; VI_ERR_NOMEM. */
VI_API int vi_sweep_iterate(vi_sweep *sw);

/** @name Results of the last point
 *  Views owned by the study, valid until its next vi_sweep_iterate.
 *  @{ */
/** P(n, m) of the last point; n = 0 when no period <= nmax was found (or
 *  the point failed).  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE (no point
 *  yet). */
VI_API int vi_sweep_period(const vi_sweep *sw, int *n, int *m);
/** 1 if the last point failed, else 0 (also for NULL). */
VI_API int vi_sweep_failed(const vi_sweep *sw);
/** Forcing period T = 2 pi / Omega of the last point (0 before one). */
VI_API double vi_sweep_forcing_period(const vi_sweep *sw);
/** The recorded impacts of the last point: *count receives their number;
 *  t, phase (t mod T) and vn (approach velocity) point to [count] arrays
 *  (each may be NULL).  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_sweep_impacts(const vi_sweep *sw, int64_t *count,
                            const double **t, const double **phase,
                            const double **vn);
/** The stroboscopic states of the last point: [2n x record], column k
 *  = (x, v) at t0 + (transient + k + 1) T; *ld receives 2n, *record the
 *  number of columns.  NaN where a failed point did not reach them; NULL
 *  before a point. */
VI_API const double *vi_sweep_strobe(const vi_sweep *sw, int *ld,
                                     int *record);
/** The P(1,1) orbits of the last point (vi_sweep_set_orbits): *count
 *  receives their number (-1: the model has no closed-form flow or not
 *  one stop, 0 without
 *  the census), and vn (approach velocity w.v), phase (impact time mod T),
 *  stable (all |mu| < 1) and admissible point to [count] arrays (each may
 *  be NULL).  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_sweep_orbits(const vi_sweep *sw, int *count, const double **vn,
                           const double **phase, const int **stable,
                           const int **admissible);
/** The study's model (read-only view, at the current parameters). */
VI_API const vi_model *vi_sweep_model(const vi_sweep *sw);
/** @} */

/** Attractors across points (basins of attraction): the periodic points
 *  among count, each with its period n[i] (0: none, not an attractor)
 *  and its last n[i] stroboscopic states, the last n[i] columns of its
 *  [ld x record] block at strobe + i * ld * record (ld >= 2 ncoord), are
 *  grouped: two points share an attractor when their periods agree and
 *  their states agree to tol relative (to the larger state entry), up to
 *  a cyclic shift.  id [count] receives 0, 1, ... in order of first
 *  appearance, -1 for n[i] = 0; *nattr the number of attractors.
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_DIM, VI_ERR_NOMEM. */
VI_API int vi_sweep_attractors(int64_t count, int ncoord, int record,
                               const int *n, const double *strobe, int ld,
                               double tol, int *id, int *nattr);

#ifdef __cplusplus
}
#endif
#endif
