/** @file vi_orbit.h
 * periodic impacting orbits and the coefficient-of-restitution
 * analysis of the paper (MODEL.md section 5; WB 11-13).
 *
 * vi_orbit_find runs past the transient, classifies the motion as P(n, m)
 * (period n forcing periods, m impacts in it) or not periodic, and for a
 * P(1,1) orbit refines it by Newton shooting on the stroboscopic map (GSL
 * hybridsj with the map's exact Jacobian: the closed-form variational flow
 * and the saltation matrix of each impact), computes its Floquet
 * multipliers and the energy balance over one period:
 *   IE = 1/2 v_N^2 (1 - r^2) / psi.psi = sum_j (FE_j - DE_j - XE_j) = RE (WB 11)
 *   r  = sqrt(1 - RE / KE_i),  KE_i = 1/2 v_N^2 / psi.psi            (WB 12, 13)
 * and the restitution r_S a reduced model keeping only the modes in S needs
 * to reproduce the orbit.
 *
 * P(1, m) orbits are analysed too, also when the impacts go to several
 * stops (a two-sided clearance: m = 2, one impact on each), with the
 * balance per stop (vi_orbit_stop_balance): the work fed in on the
 * approach to each stop's impacts against the energy they take. */
#ifndef VI_ORBIT_H
#define VI_ORBIT_H

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_builders.h" /* the reduced model, once declared here */
#include "vibroimpact/vi_model.h"
#include "vibroimpact/vi_sim.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Opaque periodic-orbit analysis handle. */
typedef struct vi_orbit vi_orbit;

/** Create an orbit analysis of a set-up model with harmonic forcing and at
 *  least one stop (the model is borrowed and must outlive the orbit).
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE (model not set up, or no stop),
 *  VI_ERR_FREQUENCY (Omega = 0), VI_ERR_NOMEM. */
VI_API int vi_orbit_create(const vi_model *model, vi_orbit **out);
/** Destroy and set *orbit to NULL; NULL-safe. */
VI_API void vi_orbit_destroy(vi_orbit **orbit);
/** Detail of the last error ("" if none), owned by the orbit. */
VI_API const char *vi_orbit_errmsg(const vi_orbit *orbit);

/** Integration method (VI_METHOD_*): default VI_METHOD_EXACT when the model
 *  allows it, else VI_METHOD_ADAMS.  @return VI_OK, VI_ERR_ARG,
 *  VI_ERR_UNSUPPORTED. */
VI_API int vi_orbit_set_method(vi_orbit *o, int method);
/** Tolerances of the integrations, as vi_sim_set_tolerances (defaults
 *  1e-11, 1e-13).  @return VI_OK, VI_ERR_TOLERANCE. */
VI_API int vi_orbit_set_tolerances(vi_orbit *o, double rtol, double atol);
/** Start of the transient run (default rest at t = 0); x0, v0 [n] or NULL. */
VI_API int vi_orbit_set_initial(vi_orbit *o, const double *x0,
                                const double *v0);
/** At most max_periods forcing periods of transient (default 3000); the
 * motion counts as periodic when impact states repeat to tol (relative,
 * default 1e-6) over 3 consecutive orbit periods. */
VI_API int vi_orbit_set_transient(vi_orbit *o, double max_periods, double tol);
/** Monitor of the transient run, called once per forcing period (see
 *  vi_sim_set_monitor); a non-zero return stops vi_orbit_find with
 *  VI_STOPPED.  fn NULL removes it.  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_orbit_set_monitor(vi_orbit *o, vi_monitor_fn fn, void *user,
                                vi_destroy_fn destroy);

/** Cancellation of the orbit's simulations (fn NULL: none), polled at
 *  every step as vi_sim_set_cancel: a long transient (a reference of
 *  many stiff modes) stops within a step; vi_orbit_find then fails
 *  (VI_CANCELLED from the transient) and the orbit is not to be used.  user is handed over as
 *  vi_orbit_set_monitor does.  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_orbit_set_cancel(vi_orbit *o, vi_cancel_fn fn, void *user,
                               vi_destroy_fn destroy);

/** Direct search (default on): when the transient does not settle on a
 *  P(1,1) orbit and the model has the closed-form flow, look for one with
 *  vi_orbit_p1_scan and analyse the most stable admissible one found, if
 *  it is stable (another attractor the transient missed).
 *  @return VI_OK, VI_ERR_ARG (on not 0 or 1). */
VI_API int vi_orbit_set_direct_search(vi_orbit *o, int on);
/** What vi_orbit_find did: *tn, *tm the classification of the transient
 *  (as vi_orbit_classify would give without the direct search), *by_scan
 *  1 if the analysed P(1,1) orbit came from the direct search.  Any
 *  pointer may be NULL. */
VI_API int vi_orbit_search_info(const vi_orbit *o, int *tn, int *tm,
                                int *by_scan);
/** Run, classify, and for P(1,1) refine and analyse; for P(1, m), m <= 8,
 * the same unless (one stop) the direct search finds a stable P(1,1)
 * orbit, which takes precedence.  VI_OK whatever the motion turns out to
 * be: ask vi_orbit_classify (and vi_orbit_impacts, VI_ERR_STATE if no orbit
 * was analysed: a P(1, m) orbit that shooting cannot hold stays only
 * classified).  VI_STOPPED if the monitor asked to stop; a negative code
 * means the computation itself failed.  The direct search is for models
 * with one stop. */
VI_API int vi_orbit_find(vi_orbit *o);
/** *n periods of forcing, *m impacts per orbit period; n = 0 when no period
 * up to 8 was found within the transient (m is then the mean number of
 * impacts per forcing period over the last 8 periods, rounded).  (1, 1)
 * also when the direct search found a stable P(1,1) orbit the transient
 * missed (vi_orbit_search_info tells the two apart).  @return VI_OK,
 * VI_ERR_ARG, VI_ERR_STATE (with n = m = 0) until vi_orbit_find has
 * classified a transient: an orbit never sought. */
VI_API int vi_orbit_classify(const vi_orbit *o, int *n, int *m);

/* ---- P(1,1) results: VI_ERR_STATE unless the analysed orbit is P(1,1) - */
/** period = 2 pi / Omega; phase = impact time modulo the period (time
 * units); vN = approach velocity w.x'(t-); KE_i, RE, IE as in WB 11-13;
 * r_rec from WB 12; closure = |RE - IE| / KE_i.  Any pointer may be NULL. */
VI_API int vi_orbit_balance(const vi_orbit *o, double *period, double *phase,
                            double *vN, double *KE_i, double *RE, double *IE,
                            double *r_rec, double *closure);
/** Per mode [n] over one period: FE, DE, XE and the effective restitution
 * r_eff_j = -q_j'(t+) / q_j'(t-).  Any pointer may be NULL. */
VI_API int vi_orbit_modal_balance(const vi_orbit *o, double *FE, double *DE,
                                  double *XE, double *r_eff);
/** The state just before the impact: t, x [n], v [n] (any may be NULL). */
VI_API int vi_orbit_impact_state(const vi_orbit *o, double *t, double *x,
                                 double *v);
/* ---- any analysed orbit (VI_ERR_STATE if none) ---------------------------- */
/** The analysed orbit's impacts in one period from the section: *count (at
 *  most 8), and per impact j the time t [count], the stop hit stop [count],
 *  the approach velocity vn [count], the state just before, x and v
 *  [n x count] with leading dimension ld.  Any pointer may be NULL.
 *  @return VI_OK, VI_ERR_ARG (ld < n with x or v), VI_ERR_STATE. */
VI_API int vi_orbit_impacts(const vi_orbit *o, int *count, double *t,
                            int *stop, double *vn, double *x, double *v,
                            int ld);
/** WB 11-13 for stop k's impacts (0-based): *count impacts per period,
 *  KE_i = sum 1/2 v_n^2 / (w_k^T M^-1 w_k), IE the energy they take (WB 10),
 *  RE the residual work sum_j (FE_j - DE_j - XE_j) fed in on the approach
 *  to each of them (from the impact before), r_rec = sqrt(1 - RE / KE_i)
 *  (WB 13), closure = |RE - IE| / KE_i.  The stops' RE - IE are the energy
 *  the motion carries from one stop to the next: they sum to zero, and each
 *  vanishes for one stop or a symmetric orbit.  NaN for a stop with no
 *  impact.  Any pointer may be NULL.  @return VI_OK, VI_ERR_ARG (k out of
 *  range), VI_ERR_STATE. */
VI_API int vi_orbit_stop_balance(const vi_orbit *o, int k, int *count,
                                 double *KE_i, double *RE, double *IE,
                                 double *r_rec, double *closure);
/** Per mode [n], the approach work to stop k's impacts: FE, DE, XE (their
 *  sums over the stops are vi_orbit_modal_balance's).  Any pointer may be
 *  NULL.  @return as vi_orbit_stop_balance. */
VI_API int vi_orbit_stop_modal_balance(const vi_orbit *o, int k, double *FE,
                                       double *DE, double *XE);
/** Floquet multipliers of the stroboscopic map, re and im [2n]: from the
 *  monodromy matrix of exact derivatives (vi_orbit_pnm_multipliers) at the
 *  refined orbit's impact.  With the exact method the orbit is exact to
 *  round-off; with CVODE the derivatives are still exact but the orbit
 *  carries the integration tolerance. */
VI_API int vi_orbit_multipliers(const vi_orbit *o, double *re, double *im);
/** Smallest value over the period of the gap to the nearest stop,
 * max_k (w_k.x - x_k) (the deepest excursion from the stops, <= 0). */
VI_API int vi_orbit_min_gap(const vi_orbit *o, double *gmin);
/** Equivalent restitution of a reduced model keeping the modes modes[0..k)
 * (0-based, ascending omega): r_S = sqrt(1 - RE_S / KE_S) with
 * KE_S = 1/2 (psi_S.q_S'(t-))^2 / psi_S.psi_S and RE_S the modes' residual
 * energy.  VI_ERR_ARG (and *r_S = NaN) if a mode index is outside 0..n-1
 * or RE_S is outside [0, KE_S] (no real r_S). */
VI_API int vi_orbit_reduced_restitution(const vi_orbit *o, const int *modes,
                                        int k, double *r_S);

/** The largest Lyapunov exponent of the motion from the initial state
 *  (vi_orbit_set_initial, rest by default; t = 0) of the orbit's model, with
 *  its method and tolerances: after `transient` forcing periods, a tangent
 *  vector is carried over the next `periods` (>= 2) by the exact
 *  state-transition matrix between impacts and the saltation matrix of each
 *  impact (MODEL.md section 13), renormalised after every factor.
 *  *lambda receives the mean growth rate (per unit time; multiply by
 *  2 pi / Omega for per forcing period), *spread (may be NULL) the
 *  difference between the rates of the first and second halves: a
 *  convergence indicator, not an error bound.  On a periodic orbit lambda
 *  tends to log|mu_max| / (nT).  A motion that sticks, sums a chattering
 *  tail or hits two stops at one instant is refused.  @return VI_OK,
 *  VI_ERR_ARG, VI_ERR_UNSUPPORTED, VI_ERR_NONFINITE (the tangent overflowed:
 *  a grazing impact), VI_ERR_NOMEM, or the simulation's code. */
VI_API int vi_orbit_lyapunov(vi_orbit *o, double transient, double periods,
                             double *lambda, double *spread);

/* ---- P(n, m) orbits found directly (vi_orbit_pnm.c) ------------------- */
/** An orbit is given by its m impacts in one orbit period n T (T = 2 pi /
 *  Omega): times t[m], ascending, and the states just before them, x and v
 *  [n x m] column-major with leading dimension ld (column j = impact j).
 *  The *_stops variants also take the stop each impact hits, stop[m]
 *  (0-based, vi_model_add_stop order; NULL = every impact on stop 0, which
 *  is what the functions without the suffix do).  Between impacts the
 *  motion is the closed-form free flow, so solve, residual and the scan
 *  need a model with the exact flow (VI_ERR_UNSUPPORTED otherwise); the
 *  multipliers and admissibility need only the linear model.  A model with
 *  several stops: admissibility watches every stop's gap. */

/** Newton's method on the impact conditions: for each impact j, the free
 *  flow from (t_j, x_j, v_j+) reaches (x_{j+1}, v_{j+1}) at t_{j+1} (the
 *  last one at t_0 + nT back to the first), and w.x_j = x_s; v+ from WB 2.
 *  Exact derivatives (the flow is affine in the state; time derivatives
 *  are the vector field).  t, x, v hold the seed and receive the orbit.
 *  Converged when every residual is <= tol times the state scale (tol <= 0:
 *  1e-12, what the closed-form flow delivers).  Admissibility is not
 *  checked (see vi_orbit_pnm_admissible).  @return VI_OK, VI_ERR_ARG,
 *  VI_ERR_STATE, VI_ERR_UNSUPPORTED, VI_ERR_FREQUENCY, VI_ERR_NOMEM,
 *  VI_ERR_NOT_CONVERGED (40 iterations, a singular Jacobian, or impacts
 *  out of order); *iters (may be NULL) the iterations. */
VI_API int vi_orbit_pnm_solve(const vi_model *m, int n, int mi, double *t,
                              double *x, double *v, int ld, double tol,
                              int *iters);
/** The conditions vi_orbit_pnm_solve zeroes, for a caller's own Newton
 *  (continuation): F [D], D = mi (2 n_coords + 1), ordered per impact j as
 *  (state mismatch [2 n_coords], w.x_j - x_s); with J non-NULL also their
 *  exact Jacobian J [D x D] (column-major, leading dimension D) with respect
 *  to (t_j, x_j, v_j) in the same order.  @return as vi_orbit_pnm_solve
 *  (VI_ERR_NOT_CONVERGED: impacts out of order). */
VI_API int vi_orbit_pnm_residual(const vi_model *m, int n, int mi,
                                 const double *t, const double *x,
                                 const double *v, int ld, double *F,
                                 double *J);
/** Floquet multipliers [2 n_coords] (re, im) of the orbit: eigenvalues of
 *  the monodromy matrix (vi_orbit_pnm_monodromy).  det = prod_j r_{s_j}^2
 *  exp(-tr(M^-1 C) nT).  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE,
 *  VI_ERR_NOMEM, VI_ERR_LAPACK. */
VI_API int vi_orbit_pnm_multipliers(const vi_model *m, int n, int mi,
                                    const double *t, const double *x,
                                    const double *v, int ld, double *re,
                                    double *im);
/** The monodromy matrix Mo [2n x 2n] (column-major, leading dimension 2n,
 *  state z = (x, v)) from just before impact 0 to one orbit period later:
 *  the product over the impacts of the saltation matrix
 *  S = R + (f+ - R f-) g^T / (g^T f-) (R = diag(I, Q) the impact law's
 *  Jacobian, f-+ the vector field before and after, g = (w, 0); the
 *  derivation is in vi_orbit_var.c) and the state-transition matrix to the
 *  next impact, e^{A tau}, in closed form (per mode for proportional
 *  damping, Pade scaling and squaring otherwise).  Exact derivatives: no
 *  differences, no integration; valid for any linear model, whatever
 *  computed the orbit.  @return VI_OK, VI_ERR_ARG (also an impact with no
 *  approach velocity: S is singular at grazing), VI_ERR_STATE,
 *  VI_ERR_FREQUENCY, VI_ERR_NOMEM, VI_ERR_LAPACK. */
VI_API int vi_orbit_pnm_monodromy(const vi_model *m, int n, int mi,
                                  const int *stop, const double *t,
                                  const double *x, const double *v, int ld,
                                  double *Mo);
/** Admissibility: *ok = 1 if every impact approaches the stop (w.v_j > 0)
 *  and the gap w.x - x_s stays below the stop between impacts (sampled at
 *  512 points per forcing period, maxima refined by golden section; 1e-10
 *  of the state scale allowed); *gmax (may be NULL) the largest gap found
 *  between impacts.  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE,
 *  VI_ERR_UNSUPPORTED, VI_ERR_NOMEM. */
VI_API int vi_orbit_pnm_admissible(const vi_model *m, int n, int mi,
                                   const double *t, const double *x,
                                   const double *v, int ld, double *gmax,
                                   int *ok);
/** vi_orbit_pnm_solve with the stop of each impact, stop [mi] (0-based;
 *  VI_ERR_ARG if one is out of range); each impact obeys its own stop's
 *  w_k, x_k and r_k. */
VI_API int vi_orbit_pnm_solve_stops(const vi_model *m, int n, int mi,
                                    const int *stop, double *t, double *x,
                                    double *v, int ld, double tol, int *iters);
/** vi_orbit_pnm_residual with the stop of each impact, stop [mi]. */
VI_API int vi_orbit_pnm_residual_stops(const vi_model *m, int n, int mi,
                                       const int *stop, const double *t,
                                       const double *x, const double *v,
                                       int ld, double *F, double *J);
/** vi_orbit_pnm_multipliers with the stop of each impact, stop [mi]. */
VI_API int vi_orbit_pnm_multipliers_stops(const vi_model *m, int n, int mi,
                                          const int *stop, const double *t,
                                          const double *x, const double *v,
                                          int ld, double *re, double *im);
/** vi_orbit_pnm_admissible with the stop of each impact, stop [mi]: the
 *  approach is to that stop; every stop's gap stays below between impacts. */
VI_API int vi_orbit_pnm_admissible_stops(const vi_model *m, int n, int mi,
                                         const int *stop, const double *t,
                                         const double *x, const double *v,
                                         int ld, double *gmax, int *ok);
/** Parameters of vi_orbit_pnm_dparam. */
enum {
  VI_ORBIT_PARAM_OMEGA = 0, /**< the forcing frequency Omega */
  VI_ORBIT_PARAM_XS = 1,    /**< stop k's position x_k */
  VI_ORBIT_PARAM_R = 2      /**< stop k's restitution r_k */
};
/** Exact derivative dF [D] of the conditions of vi_orbit_pnm_residual_stops
 *  with respect to a parameter (VI_ORBIT_PARAM_*; k the stop for XS and R,
 *  ignored for OMEGA), at fixed (t_j, x_j, v_j): what pseudo-arclength
 *  continuation needs beside the Jacobian.  Omega enters through the
 *  harmonic particular solution (its phasor's derivative in closed form)
 *  and the orbit period nT.  stop may be NULL.  @return as
 *  vi_orbit_pnm_residual, VI_ERR_ARG also for an unknown parameter or k. */
VI_API int vi_orbit_pnm_dparam(const vi_model *m, int n, int mi,
                               const int *stop, const double *t,
                               const double *x, const double *v, int ld,
                               int param, int k, double *dF);
/** Every P(n, 1) orbit: for each impact phase phi the periodic motion
 *  with one impact at phi per nT solves a linear system (the flow is
 *  affine); its gap w.x - x_s is scanned over nphase (>= 8) phases in
 *  [0, nT), sign changes refined by vi_orbit_pnm_solve, duplicates and
 *  non-approaching ones dropped.  Admissible or not, stable or not.  Up to
 *  cap orbits into t [cap] (impact time mod nT), x, v [n x cap]; *found
 *  receives how many there are (may exceed cap).  @return as
 *  vi_orbit_pnm_solve. */
VI_API int vi_orbit_p1_scan(const vi_model *m, int n, int nphase, double *t,
                            double *x, double *v, int ld, int cap, int *found);
/** vi_orbit_p1_scan with cancellation: cancel (NULL: never) is polled
 *  once per phase in each of the scan's two passes (the gaps, then the
 *  sign changes refined); when it
 *  returns non-zero the scan stops and returns VI_CANCELLED (t, x, v and
 *  *found then hold the orbits refined so far).  @return as
 *  vi_orbit_p1_scan, or VI_CANCELLED. */
VI_API int vi_orbit_p1_scan_polled(const vi_model *m, int n, int nphase,
                                   double *t, double *x, double *v, int ld,
                                   int cap, int *found, vi_cancel_fn cancel,
                                   void *user);

#ifdef __cplusplus
}
#endif
#endif
