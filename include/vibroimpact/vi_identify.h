/** @file vi_identify.h
 * Model parameters from a recorded response (MODEL.md sections 5, 6; the
 * paper's section 4): the restitution, clearance, forcing frequency or any
 * other parameter a model needs to reproduce a measured periodic impacting
 * motion, with honest uncertainties.
 *
 * The recording is samples y_i = c.x(t_i) (c the observation vector: the
 * stop's w by default, so y is the gap coordinate w.x, or a unit vector for
 * one coordinate), optionally with the velocity c.x'(t_i).  The model's
 * response is its steady periodic impacting orbit P(n, m) at the trial
 * parameters p: found once by a transient (vi_orbit_find) at the starting
 * values, then continued from trial to trial by Newton's method on the
 * impact conditions (vi_orbit_pnm_solve_stops); between impacts the
 * response at the sample times is the exact flow (vi_flow.h).  The
 * recording's forcing phase is unknown: model time s = t + t0, and the
 * shift t0 is a nuisance parameter, fitted.
 *
 * Nonlinear least squares (GSL gsl_multifit_nlinear, Levenberg-Marquardt
 * trust region) minimises sum_i (y_i - c.x(t_i + t0; p))^2 (plus the
 * velocity residuals divided by Omega when velocities are given).  The
 * Jacobian: the orbit's sensitivity du/dp = -F_u^-1 F_p from the exact
 * Jacobian F_u of the impact conditions and their exact parameter
 * derivative F_p (vi_orbit_pnm_dparam: Omega, x_s, r; a central
 * difference of the conditions for any other parameter), carried to every
 * sample by the exact state-transition matrix; d/dt0 is the model's
 * velocity.
 *
 * Uncertainty: cov = s^2 (J^T J)^-1 at the optimum with the residual
 * variance s^2 = SSR / (N - P) (N residuals, P fitted values with the
 * shift), 95 % intervals p +- t_{0.975, N-P} stderr.  Valid when the noise
 * is independent and the model is right: compare the residual RMS with the
 * noise level (given, or estimated from the recording: its periods folded
 * onto one, or its 4th differences).
 *
 * Life cycle: vi_identify_create -> vi_identify_set_param (each one) ->
 * [vi_identify_set_builder, _set_observation, _set_shift, _set_noise] ->
 * vi_identify_set_data -> vi_identify_run -> the result getters ->
 * vi_identify_destroy.
 */
#ifndef VI_IDENTIFY_H
#define VI_IDENTIFY_H

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_model.h"
#include "vibroimpact/vi_sim.h" /* vi_destroy_fn */

#ifdef __cplusplus
extern "C" {
#endif

/** Opaque identification handle. */
typedef struct vi_identify vi_identify;

/** Builds the set-up model at parameter values p [np] into *out (a new
 *  handle the identification destroys).  Return VI_OK, or a non-zero code
 *  for values that make no model (the step is then rejected). */
typedef int (*vi_identify_model_fn)(const double *p, void *user,
                                    vi_model **out);

/** Parameter kinds of vi_identify_set_param: the vi_orbit_pnm_dparam
 *  parameters, whose derivatives are exact and whose models the
 *  identification can build itself from the base model, or any other
 *  (VI_IDENTIFY_OTHER: set by its key, vi_identify_set_param_key, or by the
 *  builder; derivative differenced). */
enum {
  VI_IDENTIFY_OMEGA = 0, /**< forcing frequency Omega (VI_ORBIT_PARAM_OMEGA) */
  VI_IDENTIFY_XS = 1,    /**< a stop's position x_k (VI_ORBIT_PARAM_XS) */
  VI_IDENTIFY_R = 2,     /**< a stop's restitution r_k (VI_ORBIT_PARAM_R) */
  VI_IDENTIFY_OTHER = 3  /**< anything the builder sets */
};

/** Warnings about a fitted parameter (vi_identify_params flags). */
enum {
  VI_IDENTIFY_ON_BOUND = 1,     /**< the optimum lies on (within 1e-6 of the
                                     range of) a bound: stderr and interval
                                     do not apply */
  VI_IDENTIFY_UNDETERMINED = 2, /**< the data do not determine it: the
                                     Jacobian is singular or ill-conditioned
                                     (reciprocal condition < 1e-10) in its
                                     direction, or its interval is wider
                                     than its range */
  VI_IDENTIFY_CORRELATED = 4,   /**< |correlation| > 0.99 with another */
  /* the profile interval's (vi_identify_profile) */
  VI_IDENTIFY_PROFILE_DIFFERS = 8, /**< a side differs from the Jacobian
                                        interval's by more than 20 % */
  VI_IDENTIFY_PROFILE_BOUND = 16,  /**< it reaches the parameter's bound */
  VI_IDENTIFY_PROFILE_ORBIT = 32   /**< it ends where the orbit changes
                                        type or stops being admissible and
                                        stable (the data's 95 % level lies
                                        beyond) */
};

/** Create an identification of np >= 1 parameters of the set-up model
 *  `base` (borrowed; it must outlive the handle): its values are the
 *  starting point unless vi_identify_set_param gives others.  The model
 *  needs the closed-form flow (vi_flow.h), harmonic forcing and a stop.
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_DIM (np < 1 or > 32), VI_ERR_STATE
 *  (model not set up or without a stop), VI_ERR_UNSUPPORTED (no
 *  closed-form flow, a band model), VI_ERR_FREQUENCY (no forcing),
 *  VI_ERR_NOMEM. */
VI_API int vi_identify_create(const vi_model *base, int np, vi_identify **out);
/** Destroy and set *id to NULL; NULL-safe (the builder's user data is
 *  released with its destroy function). */
VI_API void vi_identify_destroy(vi_identify **id);
/** Detail of the last error ("" if none), owned by the handle. */
VI_API const char *vi_identify_errmsg(const vi_identify *id);

/** Parameter j (0-based): its kind (VI_IDENTIFY_*), the stop k (0-based)
 *  for VI_IDENTIFY_XS and VI_IDENTIFY_R (ignored otherwise), its starting
 *  value p0 and its admissible range [lo, hi] (lo < hi; infinite bounds
 *  allowed; r is also confined to [0, 1]).  A VI_IDENTIFY_OTHER parameter
 *  keeps the key vi_identify_set_param_key gave it (a new start or range).
 *  Every parameter must be set
 *  before vi_identify_run.  @return VI_OK, VI_ERR_ARG (j, kind or k out of
 *  range, p0 outside [lo, hi], lo >= hi), VI_ERR_NONFINITE (p0 NaN or
 *  infinite). */
VI_API int vi_identify_set_param(vi_identify *id, int j, int kind, int k,
                                 double p0, double lo, double hi);
/** Parameter j by its vi_param.h key (forcing.omega, stop.xs, stops[k].r,
 *  forcing.a[i], damping.zeta, ...): the starting value is the base
 *  model's (vi_model_param), the range [lo, hi] (NaN: unbounded on that
 *  side; r also within [0, 1]).  Without a builder the model at trial
 *  values is a copy of the base model (vi_model_copy) with every keyed
 *  parameter set by vi_model_set_param.  Omega, x_k and r_k keep exact
 *  derivatives; any other key is differenced.  @return VI_OK, VI_ERR_ARG
 *  (NULL or unknown key, j out of range, the start outside [lo, hi]),
 *  VI_ERR_DIM (an index out of range), VI_ERR_UNSUPPORTED, as
 *  vi_model_param. */
VI_API int vi_identify_set_param_key(vi_identify *id, int j, const char *key,
                                     double lo, double hi);
/** The model at trial values: fn builds it from all np values (needed
 *  for a VI_IDENTIFY_OTHER parameter without a key; without a builder the
 *  identification sets each parameter by its key on a copy of the base
 *  model, vi_model_copy and vi_model_set_param).  The models must keep the base
 *  model's size and stops.  fn NULL removes it.  @return VI_OK,
 *  VI_ERR_ARG. */
VI_API int vi_identify_set_builder(vi_identify *id, vi_identify_model_fn fn,
                                   void *user, vi_destroy_fn destroy);
/** Cancellation (fn NULL: none), polled by vi_identify_run before it
 *  starts, once per forcing period of the transient that seeks the
 *  orbit, once per phase of the impact-phase scan
 *  (vi_orbit_p1_scan_polled) and at every residual and Jacobian
 *  evaluation of the least-squares (GSL) iterations: vi_identify_run
 *  then returns VI_CANCELLED with no result.  user is handed over as
 *  vi_identify_set_builder does.  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_identify_set_cancel(vi_identify *id, vi_cancel_fn fn,
                                  void *user, vi_destroy_fn destroy);
/** Observation vector c [n]: the recording is c.x (default, c NULL: stop
 *  0's w, the gap coordinate; e_i for coordinate i).  @return VI_OK,
 *  VI_ERR_ARG (c zero), VI_ERR_NONFINITE. */
VI_API int vi_identify_set_observation(vi_identify *id, const double *c);
/** The time shift t0 (model time = recording time + t0): fit = 1 fits it
 *  starting from t0, or from a scan of one orbit period when t0 is NaN (the
 *  default); fit = 0 holds it at t0 (finite).  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_identify_set_shift(vi_identify *id, int fit, double t0);
/** on = 1 (default): the model's orbit must be stable (|Floquet
 *  multipliers| < 1): an unstable orbit is not a motion a recording can
 *  show.  on = 0 also fits unstable orbits: the shape a model's orbit
 *  would need, e.g. to compare a reduced model that cannot hold the motion
 *  (vi_identify_stability then tells).  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_identify_set_stable_only(vi_identify *id, int on);
/** The recording's noise standard deviation, if known (sigma <= 0: estimate
 *  it from the recording: the smaller of its periods folded onto one, each
 *  sample against its neighbours in phase, and the 4th differences of
 *  near-uniform samples), for
 *  the comparison with the residual RMS.  @return VI_OK, VI_ERR_NONFINITE. */
VI_API int vi_identify_set_noise(vi_identify *id, double sigma);
/** The recording (copied): ns samples at times t [ns] (strictly
 *  increasing, uniform or not), displacements x [ns] (c.x), velocities v
 *  [ns] (c.x') or NULL.  @return VI_OK, VI_ERR_ARG (ns < 16 or t not
 *  strictly increasing, the message giving the sample), VI_ERR_NONFINITE
 *  (a NaN or infinite value, 1-based sample in the message),
 *  VI_ERR_NOMEM. */
VI_API int vi_identify_set_data(vi_identify *id, int ns, const double *t,
                                const double *x, const double *v);
/** The recording from any of the sensors: ns samples at times t [ns]
 *  (as vi_identify_set_data) of c.x (x), c.x' (v), c.x'' (a, an
 *  accelerometer), each NULL when not recorded, at least one given.
 *  Each channel is a block of residuals, weighted by Omega^(k0 - k) (k
 *  its order, k0 the first recorded's) so that all are on the first's
 *  scale; the noise estimate, the period and the shift scan use the first.
 *  @return as vi_identify_set_data. */
VI_API int vi_identify_set_sensors(vi_identify *id, int ns, const double *t,
                                   const double *x, const double *v,
                                   const double *a);
/** One more recorded channel (several sensors, several dofs at once):
 *  samples y [ns] of c.x, c.x' or c.x'' (order 0, 1, 2; c [N], copied) at
 *  the recording's times, a block of residuals weighted as
 *  vi_identify_set_sensors's.  After vi_identify_set_data or _set_sensors
 *  (which remove the channels added before).  @return VI_OK, VI_ERR_ARG
 *  (NULL, order out of range, c zero), VI_ERR_STATE (no recording yet),
 *  VI_ERR_DIM (more than 8), VI_ERR_NONFINITE, VI_ERR_NOMEM. */
VI_API int vi_identify_add_channel(vi_identify *id, const double *c, int order,
                                   const double *y);
/** on = 1 (default): the global stage.  vi_identify_run then needs no
 *  good start: starts spread over each parameter's range (a grid of 8
 *  for one parameter, 5 x 5 for two, a Halton design of 8 np points for
 *  more; over r in [0, 1], a stop observed through its own gap
 *  coordinate within 5 % of the recording's span of its top, the given
 *  bounds (in log where positive and a decade or more apart), or +-50 %
 *  of the start where there are none: vi_identify_search_range), at each
 *  the model's orbits with the recording's period (its transient and the
 *  impact-phase scan) scored against the recording, and the least squares
 *  from the best of each orbit type and the next best distinct ones (2 +
 *  np fits in all).  With VI_IDENTIFY_OTHER parameters the stage runs
 *  again about the best minimum (+-50 % of those whose bounds are open or
 *  decades apart; +-25 % and +-12.5 % about a best whose residual exceeds
 *  1.5 noise levels), and where the best still exceeds it, with the
 *  parameters that have a positive start and an open side spread a factor
 *  4, 8, then 16 either way of it; the minima of every stage are ranked
 *  together.
 *  Every distinct minimum whose displacement residual the noise explains
 *  (SSR <= s^2 chi2_0.95(ns - P), s the noise or the best's residual
 *  level if larger) is a solution (vi_identify_nsolutions), best first.
 *  on = 0: one fit from the starting values (the orbit the model shows
 *  there).  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_identify_set_global(vi_identify *id, int on);
/** Fit.  Checks that the recording repeats with a multiple of the forcing
 *  period (with Omega fitted, VI_IDENTIFY_OMEGA: finds the recording's own
 *  period P without the model, moves Omega's start to the 2 pi n / P
 *  nearest it within its bounds, and starts the global stage from each
 *  such multiple in its range instead of spreading Omega), finds the
 *  model's orbits with that period (over the ranges, or
 *  at the starting values: vi_identify_set_global), scans the shift,
 *  runs the least squares (at most 200 iterations each) and the profile
 *  intervals of each solution.  VI_OK when the fit completed, converged
 *  or not (vi_identify_summary tells).
 *  @return VI_OK, VI_ERR_STATE (no data, a parameter not set),
 *  VI_ERR_ARG (too few samples per fitted value, a recording shorter than
 *  one orbit period, or one that does not repeat with the model's orbit
 *  period, or, Omega fitted, with any period below 1 / 1.5 of its span,
 *  or none of whose multiples lies in Omega's bounds: message), VI_ERR_NOT_CONVERGED (the model's motion at the
 *  starting values is not periodic, or its orbit cannot be held), the
 *  builder's code, VI_CANCELLED (vi_identify_set_cancel), VI_ERR_NOMEM. */
VI_API int vi_identify_run(vi_identify *id);

/* ---- results: VI_ERR_STATE before a completed vi_identify_run -------- */
/** Fitted values p [np], standard errors se [np], 95 % intervals
 *  [lo95, hi95] [np], warning flags (VI_IDENTIFY_* bits) [np].  Any
 *  pointer may be NULL.  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE. */
VI_API int vi_identify_params(const vi_identify *id, double *p, double *se,
                              double *lo95, double *hi95, int *flags);
/** Profile-likelihood 95 % intervals [plo95, phi95] [np] of the best
 *  fit: the values of each parameter where the least cost with the
 *  others and the shift re-fitted has risen by t^2 s^2 (t = t_{0.975,
 *  N-P}, s^2 = SSR / (N - P): the Jacobian interval's level, so that the
 *  two agree where the model is linear over the interval), flags [np]
 *  (VI_IDENTIFY_PROFILE_*).  NaN for an undetermined parameter.  Any
 *  pointer may be NULL.  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE. */
VI_API int vi_identify_profile(const vi_identify *id, double *plo95,
                               double *phi95, int *flags);
/** Number of solutions the data admit (>= 1 after a completed run, 0
 *  before or for NULL): the distinct minima whose residual the noise
 *  explains, best (least residual) first; solution 0 is what
 *  vi_identify_params and the other getters report.  *unique (may be
 *  NULL) = 1 when there is one. */
VI_API int vi_identify_nsolutions(const vi_identify *id, int *unique);
/** Solution k (0-based, < vi_identify_nsolutions) as vi_identify_params.
 *  @return VI_OK, VI_ERR_ARG (k out of range), VI_ERR_STATE. */
VI_API int vi_identify_solution(const vi_identify *id, int k, double *p,
                                double *se, double *lo95, double *hi95,
                                int *flags);
/** Solution k's profile intervals, as vi_identify_profile. */
VI_API int vi_identify_solution_profile(const vi_identify *id, int k,
                                        double *plo95, double *phi95,
                                        int *flags);
/** Solution k's orbit P(n, m), residual RMS (of the first recorded
 *  channel), its ratio to the noise (NaN without one), *dchi2 = (SSR_k -
 *  SSR_0) / s^2 its excess over the best in units of the noise variance
 *  the test used (a likelihood-ratio statistic: large values mean the
 *  best is preferred although both residuals are at the noise level) and
 *  its shift.  Any pointer may be NULL.  @return VI_OK, VI_ERR_ARG,
 *  VI_ERR_STATE. */
VI_API int vi_identify_solution_summary(const vi_identify *id, int k, int *n,
                                        int *m, double *rms, double *ratio,
                                        double *dchi2, double *t0);
/** What would separate solution k from the best: *d = sum_i (y_0(t_i) -
 *  y_k(t_i))^2 / s^2, their responses' difference over the recording in
 *  noise variances (the likelihood-ratio statistic's mean were either
 *  true; 0 for k = 0), and *length, the multiple of the record's length
 *  at this noise for which the test at 95 % rejects the wrong one with
 *  95 % power: y^2 / d, y = (3.29 + sqrt(3.29^2 + 4 chi2_0.95(P))) / 2
 *  (NaN for k = 0, or where a model could not be rebuilt).  Either
 *  pointer may be NULL.  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE. */
VI_API int vi_identify_solution_separation(const vi_identify *id, int k,
                                           double *d, double *length);
/** The ranges [lo, hi] [np] the global stage's starts covered, every
 *  stage of the last run together (the starting values themselves
 *  without it). */
VI_API int vi_identify_search_range(const vi_identify *id, double *lo,
                                    double *hi);
/** The fitted (or held) shift *t0 and its standard error *se (0 if held).
 *  Either pointer may be NULL. */
VI_API int vi_identify_shift(const vi_identify *id, double *t0, double *se);
/** Correlation matrix R [np x np] of the fitted parameters (leading
 *  dimension ld >= np).  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE. */
VI_API int vi_identify_correlation(const vi_identify *id, double *R, int ld);
/** Summary: converged (1/0), least-squares iterations, residual RMS (over
 *  the displacement samples), the noise level (given or estimated; NaN
 *  if neither), the Jacobian's reciprocal condition number, the fitted
 *  orbit P(n, m).  Any pointer may be NULL. */
VI_API int vi_identify_summary(const vi_identify *id, int *converged,
                               int *iterations, double *rms, double *noise,
                               double *rcond, int *n, int *m);
/** The fitted orbit's largest Floquet multiplier modulus *mu (< 1:
 *  stable; NaN if it could not be computed).  @return VI_OK, VI_ERR_ARG,
 *  VI_ERR_STATE. */
VI_API int vi_identify_stability(const vi_identify *id, double *mu);
/** Number of parameters np of the identification (0 for NULL). */
VI_API int vi_identify_nparams(const vi_identify *id);
/** The fitted orbit: its period *period = n 2 pi / Omega and the model
 *  times t [m] (m <= 8, vi_identify_summary) of its impacts in the period
 *  [0, *period) (the shift maps recording time t to model time t + t0).
 *  Either pointer may be NULL.  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE. */
VI_API int vi_identify_orbit_period(const vi_identify *id, double *period,
                                    double *t);
/** The fitted model's response c.x at recording times t [nt] (the shift
 *  applied) into x [nt]; v [nt] (may be NULL) receives c.x'.
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE, VI_ERR_NONFINITE. */
VI_API int vi_identify_response(const vi_identify *id, int nt,
                                const double *t, double *x, double *v);
/** The samples of the recording's first channel (vi_identify_set_data's
 *  x, or v without it; vi_identify_set_sensors' first) that lie more than
 *  `level` noise levels (vi_identify_summary's noise) from the fitted
 *  motion: their number *count; the min(cap, *count) worst, farthest
 *  first, into idx [cap] (0-based sample numbers) and z [cap] (their
 *  distances in noise levels); *rest the other samples' residual RMS over
 *  the noise (NaN where none is left).  A Gaussian sample lies beyond 6
 *  noise levels once in 5e8: a few such samples are glitches the least
 *  squares moved with (remove them and fit again), many a model that does
 *  not explain the data.  Pointers may be NULL (idx and z with cap 0).
 *  @return VI_OK, VI_ERR_ARG (NULL id, level not > 0, cap < 0, or cap > 0
 *  with idx or z NULL), VI_ERR_STATE (no completed run). */
VI_API int vi_identify_outliers(const vi_identify *id, double level, int cap,
                                int *idx, double *z, int *count, double *rest);
/** The WB 12 route (MODEL.md section 5) at the fitted orbit, for a P(1,1)
 *  orbit observed at the stop (c = w): the model's residual energy RE =
 *  sum_j (FE_j - DE_j - XE_j) over one period (the modal ledger of the
 *  fitted orbit), the recorded approach velocity vN just before each
 *  recorded impact, averaged (when the residual is within 1.5 times the
 *  noise: the fitted model's vN corrected by a low-order fit of the
 *  residuals just before the impact, the model interpolating between the
 *  samples; otherwise NaN: at 64 samples per period a local polynomial of
 *  the recording alone is off by about 2 % of vN on the 4-mode beam), KE = 1/2 vN^2 / (w^T M^-1 w), and
 *  r12 = sqrt(1 - RE / KE) (WB 13).  NaN where they do not apply (not
 *  P(1,1), another observation, RE outside [0, KE]).  Any pointer may be
 *  NULL.  @return VI_OK, VI_ERR_STATE. */
VI_API int vi_identify_energy_restitution(const vi_identify *id, double *r12,
                                          double *vN, double *KE, double *RE);
/** The forcing phase a recorded forcing signal implies: f [ns] at times
 *  t [ns] fitted by least squares as alpha cos(Omega t) + beta sin(Omega t)
 *  = A cos(Omega (t + t0)), *t0 in [0, 2 pi / Omega): the shift that maps
 *  the recording's time onto a model forced by a cos(Omega t) (compare
 *  vi_identify_shift).  *t0 is NaN on an error.  @return VI_OK, VI_ERR_ARG
 *  (NULL, ns < 2, or samples that do not determine a phase: all at one
 *  phase modulo pi), VI_ERR_FREQUENCY (omega <= 0), VI_ERR_NONFINITE. */
VI_API int vi_identify_forcing_phase(int ns, const double *t, const double *f,
                                     double omega, double *t0);

#ifdef __cplusplus
}
#endif
#endif
