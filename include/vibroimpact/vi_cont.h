/** @file vi_cont.h
 * Continuation of a P(n,1) orbit in one parameter (vi_param.h key), one
 * branch point at a time, the loop in the caller's hands.
 *
 * Two methods: natural-parameter continuation (a secant-free predictor
 * from the last orbit, step halving where Newton fails, the loss of the
 * branch located by bisection), and pseudo-arclength continuation (around
 * folds: Newton on F(u; p) = 0 with tau.(U - U_pred) = 0, the tangent the
 * null vector of [J_u | F_p]; F_p exact for forcing.omega, stop.xs and
 * stop.r through vi_orbit_pnm_dparam, else by central differences in p).
 * Between two points the events are located: a multiplier leaving the unit
 * circle (period doubling at -1, fold or pitchfork at +1, Neimark-Sacker
 * for a complex pair), grazing (an interior maximum of the gap reaching
 * the stop) and grazing impacts (v_N through 0); natural continuation
 * bisects them, pseudo-arclength interpolates and also reports folds.
 *
 *   vi_cont_create(model, "forcing.omega", n, VI_CONT_NATURAL, &c)
 *   vi_cont_set_range(c, to, steps)
 *   vi_cont_set_orbit(c, t, x, v)     an impact of the orbit at the
 *                                     model's value of the key
 *   while (!vi_cont_done(c)) {
 *     int st = vi_cont_iterate(c);
 *     if (st == VI_CANCELLED) break;   with vi_cont_set_cancel
 *     if (st == VI_OK) vi_cont_point(c, ...);
 *     for (i < vi_cont_num_events(c)) vi_cont_event(c, i, ...);
 *   }
 *
 * The continuation works on its own copy of the model; the orbit is the
 * pre-impact state at an impact on the stop whose gap w_k.x - x_k at the
 * starting orbit is nearest zero: the impact's own stop, any of the model's
 * (vi_orbit_pnm_solve_stops).
 */
#ifndef VI_CONT_H
#define VI_CONT_H

#include <stdint.h>

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_model.h"
#include "vibroimpact/vi_sim.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Opaque continuation handle. */
typedef struct vi_cont vi_cont;

/** Continuation methods (vi_cont_create). */
typedef enum vi_cont_method {
  VI_CONT_NATURAL = 0,  /**< natural parameter, stops at a fold */
  VI_CONT_ARCLENGTH = 1 /**< pseudo-arclength, around folds */
} vi_cont_method;

/** Events between two branch points (vi_cont_event). */
typedef enum vi_cont_event_type {
  VI_CONT_PERIOD_DOUBLING = 0,   /**< a real multiplier through -1 */
  VI_CONT_FOLD_OR_PITCHFORK = 1, /**< a real multiplier through +1 */
  VI_CONT_NEIMARK_SACKER = 2,    /**< a complex pair through the circle */
  VI_CONT_GRAZING = 3,           /**< the gap between impacts touches */
  VI_CONT_GRAZING_IMPACT = 4,    /**< v_N through 0 */
  VI_CONT_FOLD = 5,              /**< dp/ds changes sign (arclength) */
  VI_CONT_LOST = 6,              /**< Newton loses the branch (natural) */
  VI_CONT_CLOSED = 7             /**< the branch closes on itself */
} vi_cont_event_type;

/** Why a continuation is done (vi_cont_done). */
typedef enum vi_cont_state {
  VI_CONT_RUNNING = 0,   /**< not done */
  VI_CONT_END = 1,       /**< the end of the range reached */
  VI_CONT_ENDS = 2,      /**< the branch was lost (VI_CONT_LOST event) */
  VI_CONT_CLOSES = 3,    /**< a closed branch came back to its start */
  VI_CONT_CORRECTOR = 4, /**< the arclength corrector failed */
  VI_CONT_STALLED = 5    /**< no tangent, or the step limit (10 steps) */
} vi_cont_state;

/** Monitor after each branch point (point numbered from 1); non-zero
 *  makes vi_cont_iterate return VI_STOPPED. */
typedef int (*vi_cont_monitor_fn)(const vi_cont *c, int64_t point,
                                  void *user);

/** Create a continuation of P(n, 1) orbits of (a copy of) the set-up model
 *  m in the parameter `key` (vi_param.h; its value in m is the start),
 *  with `method` a vi_cont_method.  @return VI_OK, VI_ERR_ARG (NULL, an
 *  unknown key or an initial-state key, n < 1, a bad method),
 *  VI_ERR_STATE (m not set up), VI_ERR_NOMEM. */
VI_API int vi_cont_create(const vi_model *m, const char *key, int n,
                          int method, vi_cont **out);
/** Destroy and set *c to NULL; NULL-safe. */
VI_API void vi_cont_destroy(vi_cont **c);
/** Detail of the last error ("" if none), owned by the handle. */
VI_API const char *vi_cont_errmsg(const vi_cont *c);
/** Follow the branch to the value `to` in `steps` >= 1 steps (natural:
 *  the step; arclength: the arclength step |to - p0| / steps).
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_NONFINITE. */
VI_API int vi_cont_set_range(vi_cont *c, double to, int steps);
/** The starting orbit: impact time t and the state x, v [n] just before
 *  it (a guess Newton refines at the first vi_cont_iterate).
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_NONFINITE. */
VI_API int vi_cont_set_orbit(vi_cont *c, double t, const double *x,
                             const double *v);
/** Monitor after each point (fn NULL: none).  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_cont_set_monitor(vi_cont *c, vi_cont_monitor_fn fn, void *user,
                               vi_destroy_fn destroy);
/** Cancellation (fn NULL: none): polled at the start of each
 *  vi_cont_iterate, before each trial step of the natural method and each
 *  Newton iteration of the pseudo-arclength corrector.  A cancelled step
 *  returns VI_CANCELLED and leaves the continuation at its last point
 *  (vi_cont_done stays 0: iterating again resumes).  user is handed over
 *  as vi_cont_set_monitor does.  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_cont_set_cancel(vi_cont *c, vi_cancel_fn fn, void *user,
                              vi_destroy_fn destroy);
/** One step along the branch.  @return VI_OK with a new point (and the
 *  events since the last one), VI_STOPPED when the step found no new
 *  point (vi_cont_done says why; events may say where) or the monitor
 *  asked, VI_CANCELLED (vi_cont_set_cancel), VI_ERR_STATE (no orbit or
 *  range set, or done), VI_ERR_NOT_CONVERGED (the first point: Newton
 *  failed from the orbit given), VI_ERR_NOMEM. */
VI_API int vi_cont_iterate(vi_cont *c);
/** A vi_cont_state: 0 while running (also for NULL). */
VI_API int vi_cont_done(const vi_cont *c);
/** The last point: parameter, approach velocity w.v, impact time, largest
 *  multiplier modulus (< 1: stable) and admissibility (each may be NULL).
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE (no point yet). */
VI_API int vi_cont_point(const vi_cont *c, double *param, double *vn,
                         double *t, double *rho, int *admissible);
/** The last point's orbit: impact time and x, v [n] before it.
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE (no point yet). */
VI_API int vi_cont_orbit(const vi_cont *c, double *t, double *x, double *v);
/** Number of events the last vi_cont_iterate found (0 for NULL). */
VI_API int vi_cont_num_events(const vi_cont *c);
/** Event i (0-based) of the last vi_cont_iterate: type (a
 *  vi_cont_event_type), parameter, v_N there, the critical multiplier
 *  re + i im, and admissibility of the orbit there (each may be NULL;
 *  NaN where an event does not define one).  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_cont_event(const vi_cont *c, int i, int *type, double *param,
                         double *vn, double *re, double *im, int *admissible);

#ifdef __cplusplus
}
#endif
#endif
