/** @file vi_cont_curve.h
 * Codimension-one points of an orbit located exactly, and followed in two
 * parameters (vi_param.h keys), the loop in the caller's hands.
 *
 * The orbit is a P(n,m) orbit (m >= 1 impacts per n forcing periods, the
 * equations of vi_orbit_pnm_residual_stops in u = (t_j, x_j, v_j), j < m;
 * every kind for every m) or the
 * non-impacting orbit P(1,0), the harmonic steady state of the free
 * structure.  A point of a kind is where the orbit's defining condition
 * holds:
 *   fold     prod_i (mu_i - 1) = 0        a multiplier at +1
 *   pd       prod_i (mu_i + 1) = 0        a multiplier at -1
 *   ns       prod_{i<j} (mu_i mu_j - 1) = 0, the pair complex: a pair on
 *            the unit circle
 *   grazing  the largest gap w.x(t) - x_s between impacts = 0, over all m
 *            flights (flight j from impact j to j + 1, the last to the
 *            first + nT; the stop of the first impact; an interior maximum
 *            followed by Newton on w.v = 0 in its flight, all flights
 *            scanned where it is lost) (P(1,0):
 *            w.K^-1 f0 + |w.(K - Omega^2 M + i Omega C)^-1 (a - i b)| = x_s)
 * with mu_i the Floquet multipliers (vi_orbit_pnm_multipliers_stops: the
 * product forms are polynomials in the monodromy's entries, smooth where
 * eigenvalues collide).  A point is solved by Newton on the orbit's
 * equations F(u; p) = 0 plus the condition g(u; p) = 0 in (u, p): the
 * exact Jacobian of F (and dF/dp exact for forcing.omega, stop.xs, stop.r),
 * g's row by central differences; to the accuracy of the orbit itself.
 * A curve is the solution set of the same system in (u, p, p2), followed
 * by pseudo-arclength in scaled coordinates, around turning points, over
 * the whole range of p2; along it the codimension-two points (where a
 * second condition holds, vi_cont_special_type) are located by regula
 * falsi on the curve.
 *
 *   vi_cont_curve_create(model, VI_CONT_CURVE_PD, 1, 1, "forcing.omega",
 *                        "stop.r", &c)
 *   vi_cont_curve_set_orbit(c, t, x, v)          an impact of the orbit
 *   vi_cont_curve_locate(c, 1.8, 200, &p)        the first PD towards 1.8
 *   vi_cont_curve_set_range(c, 0.5, 0.9, 200)    over r in [0.5, 0.9]
 *   while (!vi_cont_curve_done(c))
 *     if (vi_cont_curve_iterate(c) == VI_OK) {
 *       vi_cont_curve_point(c, &p, &p2, ...);    in order along the curve
 *       for (i < vi_cont_curve_num_special(c)) vi_cont_curve_special(c, i, ...);
 *     }
 *
 * The points come in order along the curve from one end of the range (or
 * of the admissible part) to the other: the first iterate follows the
 * curve backwards from the located point to its end, unreported. */
#ifndef VI_CONT_CURVE_H
#define VI_CONT_CURVE_H

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_model.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Opaque handle of a two-parameter curve. */
typedef struct vi_cont_curve vi_cont_curve;

/** Kinds of point (vi_cont_curve_create, vi_cont_refine, vi_cont_refine_pnm). */
typedef enum vi_cont_curve_kind {
  VI_CONT_CURVE_GRAZING = 0, /**< the gap between impacts touches the stop */
  VI_CONT_CURVE_FOLD = 1,    /**< a multiplier at +1 */
  VI_CONT_CURVE_PD = 2,      /**< a multiplier at -1 (period doubling) */
  VI_CONT_CURVE_NS = 3       /**< a complex pair on the unit circle */
} vi_cont_curve_kind;

/** Codimension-two points on a curve (vi_cont_curve_special). */
typedef enum vi_cont_special_type {
  VI_CONT_SP_GRAZING = 0,       /**< meets the grazing curve: beyond, the
                                     orbit is not admissible (the curve ends) */
  VI_CONT_SP_FOLD = 1,          /**< meets a fold curve (another multiplier +1) */
  VI_CONT_SP_PD = 2,            /**< meets a period-doubling curve (a multiplier -1) */
  VI_CONT_SP_CUSP = 3,          /**< a cusp of a fold curve: its tangent in
                                     the plane vanishes (two fold branches
                                     meet; P(n,m), m >= 2, only) */
  VI_CONT_SP_RESONANCE_11 = 4,  /**< two multipliers at +1 */
  VI_CONT_SP_RESONANCE_12 = 5,  /**< two multipliers at -1: a period doubling
                                     turning into a Neimark-Sacker */
  VI_CONT_SP_ADMISSIBILITY = 6  /**< v_N through 0: the curve ends on the loss
                                     of admissibility */
} vi_cont_special_type;

/** Why a curve is done (vi_cont_curve_done). */
typedef enum vi_cont_curve_state {
  VI_CONT_CURVE_RUNNING = 0,   /**< not done */
  VI_CONT_CURVE_END = 1,       /**< the end of the range of p2 reached */
  VI_CONT_CURVE_ENDS = 2,      /**< the orbit stops being admissible */
  VI_CONT_CURVE_CLOSES = 3,    /**< a closed curve came back to its start */
  VI_CONT_CURVE_CORRECTOR = 4, /**< the corrector failed (step 1/4096 of the
                                    largest) */
  VI_CONT_CURVE_STALLED = 5,   /**< the point limit: 20 steps + 100, each way
                                    from the located point */
  VI_CONT_CURVE_RESONANCE = 6  /**< an NS curve's pair turns real (1:1 or
                                    1:2 resonance): beyond, a neutral saddle */
} vi_cont_curve_state;

/** Refine a point of `kind` (vi_cont_curve_kind) of a P(n,1) orbit of the
 *  set-up model m in the parameter `key` (vi_param.h): *p (the parameter)
 *  and the orbit's impact time *t and state x, v [n_coords] before it are
 *  the guess and receive the point.  The impact is on the stop whose gap
 *  is nearest 0.  @return VI_OK, VI_ERR_ARG, VI_ERR_NONFINITE,
 *  VI_ERR_STATE (m not set up), VI_ERR_UNSUPPORTED (no closed-form flow),
 *  VI_ERR_NOT_CONVERGED (Newton failed: no such point near the guess),
 *  VI_ERR_NOMEM. */
VI_API int vi_cont_refine(const vi_model *m, const char *key, int n, int kind,
                          double *p, double *t, double *x, double *v);
/** vi_cont_refine for a P(n, mi) orbit, mi >= 1 (every kind): *p and the
 *  impacts' times t [mi] (ascending within n T) and the states before
 *  them x, v [ld x mi] (column-major, ld >= n_coords; each impact on the
 *  stop whose gap is nearest 0) are the guess and receive the point, by
 *  the Newton vi_cont_curve_locate uses.  @return as vi_cont_refine
 *  (VI_ERR_ARG also for mi < 1, mi > 32 or ld < n_coords). */
VI_API int vi_cont_refine_pnm(const vi_model *m, const char *key, int n, int mi,
                              int kind, double *p, double *t, double *x,
                              double *v, int ld);

/** Create a curve of points of `kind` of P(n, mi) orbits, mi 1 (n >= 1),
 *  2 to 32 (every kind; the bordered systems of mi (2 n_coords +
 *  1) + 2 unknowns are dense) or 0 (n = 1: the non-impacting
 *  orbit, kind grazing only), of a copy of the
 *  set-up model m, in the keys key and key2 (distinct; their values in m
 *  are the start).  @return VI_OK, VI_ERR_ARG (NULL, an unknown or
 *  initial-state key, a bad kind, n or mi), VI_ERR_STATE (m not set up),
 *  VI_ERR_UNSUPPORTED (P(1,0): a band model or one without a damping
 *  matrix), VI_ERR_NOMEM. */
VI_API int vi_cont_curve_create(const vi_model *m, int kind, int n, int mi,
                                const char *key, const char *key2,
                                vi_cont_curve **out);
/** Destroy and set *c to NULL; NULL-safe. */
VI_API void vi_cont_curve_destroy(vi_cont_curve **c);
/** Detail of the last error ("" if none), owned by the handle. */
VI_API const char *vi_cont_curve_errmsg(const vi_cont_curve *c);
/** The starting orbit (P(n,1)): impact time t and x, v [n_coords] just
 *  before it, a guess Newton refines.  @return VI_OK, VI_ERR_ARG (also for
 *  P(1,0) and for mi > 1: vi_cont_curve_set_impacts), VI_ERR_NONFINITE. */
VI_API int vi_cont_curve_set_orbit(vi_cont_curve *c, double t, const double *x,
                                   const double *v);
/** The starting orbit P(n, mi), mi >= 1: its impacts' times t [mi]
 *  (ascending, within one orbit period n T) and the states just before
 *  them, x, v [ld x mi] column-major (ld >= n_coords), a guess Newton
 *  refines (vi_orbit_pnm_solve_stops's layout; each impact on the stop
 *  whose gap is nearest 0).  @return VI_OK, VI_ERR_ARG (also for P(1,0)),
 *  VI_ERR_NONFINITE, VI_ERR_STATE (already located). */
VI_API int vi_cont_curve_set_impacts(vi_cont_curve *c, const double *t,
                                     const double *x, const double *v, int ld);
/** Follow the orbit in key from its value in the model towards `to` in
 *  `steps` >= 1 steps (P(n,m): pseudo-arclength, around folds, the step
 *  in arclength up to 16 times longer where the orbit moves faster than
 *  key, at most 20 steps + 100 points; P(1,0): the gap on a grid) and stop at the first point of the curve's kind, refined
 *  (vi_cont_refine's Newton); *param (may be NULL) receives key's value
 *  there.  @return VI_OK, VI_STOPPED (none before `to`, the branch is
 *  lost, or the orbit stops being admissible first: v_N through 0, or,
 *  for fold, pd and ns, its gap between impacts reaching the stop),
 *  VI_ERR_ARG (also `to` equal to key's value), VI_ERR_NONFINITE,
 *  VI_ERR_STATE (no orbit set, or already located), VI_ERR_NOT_CONVERGED
 *  (no orbit from the one given), VI_ERR_NOMEM. */
VI_API int vi_cont_curve_locate(vi_cont_curve *c, double to, int steps,
                                double *param);
/** The range of key2, from2 to to2 (distinct; the located point's key2
 *  value inside), and the largest step, 1/steps of it (in coordinates
 *  scaled by the range of key2, the located point's |key| and the orbit's
 *  size).  @return VI_OK, VI_ERR_ARG, VI_ERR_NONFINITE. */
VI_API int vi_cont_curve_set_range(vi_cont_curve *c, double from2, double to2,
                                   int steps);
/** One point along the curve.  @return VI_OK with a new point (and the
 *  codimension-two points since the last one), VI_STOPPED when no new point
 *  came (vi_cont_curve_done says why), VI_ERR_STATE (not located, no range,
 *  or done), VI_ERR_ARG (the located point outside the range of key2),
 *  VI_ERR_NOMEM. */
VI_API int vi_cont_curve_iterate(vi_cont_curve *c);
/** A vi_cont_curve_state: 0 while running (also for NULL). */
VI_API int vi_cont_curve_done(const vi_cont_curve *c);
/** Why the curve begins where it does: the vi_cont_curve_state at which
 *  the first iterate's backward pass from the located point ended (its
 *  first point): VI_CONT_CURVE_END at the range's bound, _ENDS or
 *  _RESONANCE at the codimension-two point reported with it, _CORRECTOR,
 *  _CLOSES (a closed curve: the located point) or _STALLED.  0 before the
 *  first iterate (also for NULL). */
VI_API int vi_cont_curve_start(const vi_cont_curve *c);
/** The last point: key's and key2's values, and for P(n,m) impact 0's
 *  time, x, v [n_coords] (all impacts: vi_cont_curve_impacts) and the
 *  largest multiplier modulus (NaN for P(1,0); t,
 *  x, v untouched); each may be NULL.  After vi_cont_curve_locate and
 *  before the first iterate: the located point.  @return VI_OK,
 *  VI_ERR_ARG, VI_ERR_STATE (no point yet). */
VI_API int vi_cont_curve_point(const vi_cont_curve *c, double *p, double *p2,
                               double *t, double *x, double *v, double *rho);
/** The last point's orbit, P(n, mi) with mi >= 1: the impact times t
 *  [mi] and the states before them, x, v [ld x mi] (ld >= n_coords); each
 *  may be NULL.  vi_cont_curve_point gives impact 0's.  @return VI_OK,
 *  VI_ERR_ARG (also for P(1,0)), VI_ERR_STATE (no point yet). */
VI_API int vi_cont_curve_impacts(const vi_cont_curve *c, double *t, double *x,
                                 double *v, int ld);
/** Number of codimension-two points the last iterate found (0 for NULL). */
VI_API int vi_cont_curve_num_special(const vi_cont_curve *c);
/** Codimension-two point i (0-based) of the last iterate: its type (a
 *  vi_cont_special_type), key's and key2's values, *located 1 when solved
 *  on the curve to round-off (0: interpolated between two points); each
 *  may be NULL.  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_cont_curve_special(const vi_cont_curve *c, int i, int *type,
                                 double *p, double *p2, int *located);

#ifdef __cplusplus
}
#endif
#endif
