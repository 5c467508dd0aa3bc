/** @file vi_sim.h
 * The event integrator.
 *
 * Integrates the physical-coordinate system between impacts, locates each
 * contact w.x = x_s (approached from below, and also at maxima of w.x so that
 * grazing contacts inside one step are not stepped over), applies the
 * restitution law and goes on.  Impact sequences that accumulate (chattering,
 * r < 1) end in a sticking phase g = x_s, g' = 0 that is released when the
 * contact force falls through zero.
 *
 * Several stops (vi_model_add_stop): every stop's gap and gap rate is
 * watched (2 root functions per stop on CVODE); stops within the gap
 * tolerance (10 (atol + rtol |x_k|) |w_k|) of a located contact, and the
 * stops held by sticking, touch together and take Newton's law for
 * simultaneous contacts (vi_impact.h), one IMPACT event per stop that takes
 * an impulse.  Sticking may hold any set of stops at once (the motion is
 * projected with their Delassus block G_SS; each is released when its
 * multiplier, of G_SS^-1 W_S^T a_free, falls through zero) while the
 * others are still watched.  A stop whose bounces die out (chatter
 * threshold, apex within 10 atol, floors, or r = 0) while other stops are
 * held or free has its chattering tail summed to its accumulation point
 * (Nordmark & Piiroinen), with the held stops' constraint forces in its
 * normal dynamics; it is held from the tail's first impact and its STICK
 * event comes at the accumulation point, each stop at its own.  Every
 * method takes several stops (exact and erk search every gap).
 *
 * Life cycle: vi_sim_create -> vi_sim_set_* -> vi_sim_run (repeatable; each
 * call continues from where the last stopped) -> queries ->
 * vi_sim_destroy.  Results leave only through callbacks: the library keeps no
 * storage that grows with the run.  One vi_sim per thread.
 *
 * Callbacks (event, sample, monitor, ledger, force, cancel) run inside
 * vi_sim_run and may call only these queries on their own sim:
 * vi_sim_state, vi_sim_n, vi_sim_is_sticking, vi_sim_stat,
 * vi_sim_stop_losses, vi_sim_errmsg, vi_sim_method_used,
 * vi_sim_method_note, vi_sim_ledger, vi_sim_ledger_force and
 * vi_sim_ledger_max_residual.  Every call that changes the sim (vi_sim_set_*,
 * vi_sim_add_spring, vi_sim_clear_springs, vi_sim_enable_ledger,
 * vi_sim_setup, a nested vi_sim_run or vi_sim_run_to_event) is refused
 * there with VI_ERR_STATE and a message, leaving the run undisturbed;
 * vi_sim_destroy there does not free the sim (the handle stays valid) but
 * ends the run, which returns VI_ERR_STATE: destroy it after vi_sim_run
 * returns.  Other sims may be used freely from a callback.
 *
 * Progress is guaranteed: a run whose time stops advancing (1000
 * consecutive steps within the resolution of t: a step size that
 * collapsed, a solution that blows up in finite time) fails with
 * VI_ERR_INTEGRATOR, a force that is not finite with VI_ERR_CALLBACK, and a
 * monitor or sampling interval that t cannot resolve is refused with
 * VI_ERR_LIMIT before the run; the message says which.
 */
#ifndef VI_SIM_H
#define VI_SIM_H

#include <stdint.h>

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_model.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Opaque simulation handle. */
typedef struct vi_sim vi_sim;

/** Integration methods (vi_sim_set_method). */
enum {
  VI_METHOD_ADAMS = 0, /**< CVODE Adams-Moulton, fixed-point iteration (the
                            fastest CVODE method on these scenes) */
  VI_METHOD_BDF = 1,   /**< CVODE BDF, Newton with the analytic Jacobian and a
                            dense or (banded models) band linear solver */
  VI_METHOD_EXACT = 2, /**< closed-form flow (vi_flow.h), contacts found by a
                            bounded grid search and polished to round-off:
                            any damping whose first-order system is
                            diagonalisable; sticking phases on the held
                            structure's modes in closed form too (damping
                            of Rayleigh form a M + b K), else on CVODE
                            Adams */
  VI_METHOD_AUTO = 3,  /**< (default) the exact method where it applies and is well
                            conditioned, CVODE Adams otherwise (and from any
                            point where the closed form loses accuracy);
                            vi_sim_method_note() says which ran and why */
  VI_METHOD_ERK = 4,   /**< ARKODE explicit Runge-Kutta of high order (no
                            restart ramp after an impact) */
  VI_METHOD_COUNT = 5  /**< number of methods */
};

/** Name of a method ("adams", "bdf", "exact", "auto", "erk"); NULL for an
 *  unknown value. */
VI_API const char *vi_method_name(int method);
/** Method of a name as vi_method_name() gives it; -1 for an unknown one. */
VI_API int vi_method_from_name(const char *name);

/** Kinds of event passed to the event callback. */
enum {
  VI_EVENT_IMPACT = 0,  /**< a Newton impact (WB 2) */
  VI_EVENT_STICK = 1,   /**< chattering accumulated (or r = 0): sticking begins */
  VI_EVENT_RELEASE = 2  /**< contact force fell through zero: sticking ends */
};

/** Statistics, read with vi_sim_stat(); totals over all vi_sim_run calls. */
enum {
  VI_STAT_STEPS = 0,      /**< integrator steps (exact method: scan steps) */
  VI_STAT_RHS_EVALS = 1,  /**< right-hand side evaluations */
  VI_STAT_JAC_EVALS = 2,  /**< Jacobian evaluations (BDF) */
  VI_STAT_ROOT_EVALS = 3, /**< root (event) function evaluations */
  VI_STAT_IMPACTS = 4,    /**< Newton impacts applied */
  VI_STAT_STICKS = 5,     /**< sticking phases entered */
  VI_STAT_GRAZE_CHECKS = 6, /**< maxima of w.x examined for a missed contact */
  VI_STAT_REINITS = 7,    /**< integrator restarts */
  VI_STAT_HANDOVERS = 8,  /**< exact method handed over to CVODE because the
                               closed form lost accuracy (vi_sim_method_note) */
  VI_STAT_CHATTER_SKIPPED = 9, /**< impacts of chattering tails not simulated
                               one by one: summed up by the jump to their
                               accumulation point */
  VI_STAT_FLOORS = 10,    /**< contacts where a floor (vi_sim_set_floors) acted */
  VI_STAT_POLISHES = 11,  /**< contacts re-located more accurately than the
                               integrator's step (root polishing) */
  VI_STAT_COUNT = 12      /**< number of statistics */
};

/** Name of a statistic ("steps", "rhs_evals", ...); NULL for an unknown one. */
VI_API const char *vi_stat_name(int which);

/** An event as the event callback sees it, valid only during the call. */
typedef struct vi_event {
  int kind;        /**< VI_EVENT_* */
  int n;           /**< number of coordinates */
  int64_t index;   /**< 0-based count of earlier events of this kind */
  double t;        /**< time of the event */
  double vn;       /**< approach velocity w.x'(t-) */
  double ie;       /**< kinetic energy lost (WB 10); 0 for a release */
  const double *x;       /**< positions [n] at the event */
  const double *v_minus; /**< velocities [n] just before */
  const double *v_plus;  /**< velocities [n] just after */
  int stop;        /**< the stop (0-based, vi_model_add_stop order): the one
                        hit, stuck on or released; simultaneous contacts give
                        one IMPACT event per stop that takes an impulse, in
                        stop order, all with the same x, v_minus, v_plus */
} vi_event;

/** Progress as the monitor sees it. */
typedef struct vi_progress {
  double t;        /**< current time */
  double t_start;  /**< time at the start of this vi_sim_run call */
  double t_end;    /**< end time of this vi_sim_run call */
  int64_t steps;   /**< integrator steps so far (VI_STAT_STEPS) */
  int64_t impacts; /**< impacts so far (VI_STAT_IMPACTS) */
} vi_progress;

/** Event callback: return 0 to go on, non-zero to stop the run. */
typedef int (*vi_event_fn)(const vi_event *ev, void *user);
/** Sample callback: state at time t, x and v [n] valid during the call;
 *  return 0 to go on, non-zero to stop. */
typedef int (*vi_sample_fn)(double t, int n, const double *x, const double *v,
                            void *user);
/** Monitor callback: return 0 to go on, non-zero to stop (e.g. on SIGINT). */
typedef int (*vi_monitor_fn)(const vi_progress *p, void *user);
/** Cancellation poll: return non-zero to cancel.  Called often (every
 *  integrator step and inside long scans), so it must be cheap, e.g. read a
 *  flag that a signal handler sets. */
typedef int (*vi_cancel_fn)(void *user);
/** Destroy function of a callback's user data: the library calls it with
 *  the user pointer when the callback is replaced by another user pointer
 *  or the handle is destroyed; NULL when the host keeps ownership. */
typedef void (*vi_destroy_fn)(void *user);

/** Create a simulation of a set-up model (borrowed: it must outlive the
 *  sim).  Defaults: auto, rtol 1e-8, atol 1e-10, rest at t = 0.
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE (model not set up), VI_ERR_NOMEM. */
VI_API int vi_sim_create(const vi_model *model, vi_sim **out);
/** Destroy a simulation and set *sim to NULL; NULL-safe. */
VI_API void vi_sim_destroy(vi_sim **sim);
/** Detail of the last error ("" if none), owned by the sim; CVODE's own
 *  messages end up here instead of on stderr. */
VI_API const char *vi_sim_errmsg(const vi_sim *sim);

/** Choose the integrator (VI_METHOD_*); takes effect at the next run.
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_UNSUPPORTED (exact method on a model
 *  without a usable closed form: an undamped mode forced at resonance, or a
 *  defective first-order system such as an undamped rigid-body mode beside
 *  non-proportional damping; nonlinear forces; a band-stored model, which
 *  has no modes; the message says which).  Exact and erk search every
 *  stop's gap; with several stops auto runs exact where the closed form
 *  applies. */
VI_API int vi_sim_set_method(vi_sim *sim, int method);
/** Relative and absolute tolerances, both > 0 and finite, rtol at least
 *  twice the machine epsilon; atol applies to positions and velocities
 *  alike (and to the ledger's energies).  @return VI_OK, VI_ERR_TOLERANCE. */
VI_API int vi_sim_set_tolerances(vi_sim *sim, double rtol, double atol);
/** Initial time and state; x0, v0 [n] (NULL = 0).  @return VI_OK,
 *  VI_ERR_NONFINITE, VI_ERR_INITIAL_STATE (w.x0 > x_s). */
VI_API int vi_sim_set_initial(vi_sim *sim, double t0, const double *x0,
                              const double *v0);
/** Approach velocity below which an impact of a chattering sequence ends it:
 *  the accumulation point is taken as reached and sticking begins, if the
 *  stop is pressed on.  A sequence also ends once the next bounce would rise
 *  less than 10 atol from the stop (no longer resolved).  Default 1e-7 V,
 *  V the run's velocity scale (vi_sim_velocity_scale), so that a model
 *  in other units (a micro-structure's 1e-6 m/s in SI) keeps its impacts;
 *  a value set here is absolute, in the model's velocity unit; 0 leaves
 *  only the tolerance criterion.
 *  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_sim_set_chatter_threshold(vi_sim *sim, double vmin);
/** Impacts a user can count on: every impact whose approach velocity v_n
 *  is at least ratio times the run's velocity scale V is located and
 *  reported individually, by every method alike, and only a chattering
 *  tail below that is summed by the chatter map (its impacts counted in
 *  VI_STAT_CHATTER_SKIPPED, its energy, the rebound's kinetic energy along
 *  the stop (r v_n)^2 / (2 w.M^-1.w), taken by the STICK event's ie and
 *  the ledger's impact loss).  V (vi_sim_velocity_scale) is the largest
 *  of the initial speeds |v0_i| and of the approach velocities of the run
 *  so far: a tail is measured against the run's own fastest impact, in
 *  any units and for any stiffness.  Default 1e-5 (scene key
 *  run.impact_resolution).  0 restores the accuracy-driven summing (a
 *  tail is summed as soon as resolving its next impact costs more
 *  accuracy than the closed-form tail: fewer impacts, and which depends on
 *  the method).  The chatter threshold (vi_sim_set_chatter_threshold)
 *  still ends a sequence below its velocity, and the exact method
 *  sums a sequence whose bounces stop decaying within its round-off of the
 *  gap (a load whose response dwarfs x_s).  Resolving a bounce
 *  of apex (r v_n)^2 / (2 w.a) needs atol below it: with loose tolerances
 *  the integrators may then fail on the penetration check
 *  (VI_ERR_INVARIANT) rather than sum it silently.
 *  @return VI_OK, VI_ERR_ARG (ratio outside [0, 1)), VI_ERR_STATE. */
VI_API int vi_sim_set_impact_resolution(vi_sim *sim, double ratio);
/** The run's velocity scale V of vi_sim_set_impact_resolution (0 before
 *  the first run): the largest initial speed or approach velocity so far. */
VI_API double vi_sim_velocity_scale(const vi_sim *sim);
/** First step CVODE takes after a restart: 0 (default) lets CVODE estimate
 *  it; h > 0 forces it.  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_sim_set_restart_step(vi_sim *sim, double h);
/** Largest CVODE step (0: unlimited, the default).  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_sim_set_max_step(vi_sim *sim, double hmax);
/** 1 (default): CVODE's vector operations are vibroimpact's own, compiled
 *  with optimisation (Debian's SUNDIALS is built without: 1.5-1.8x faster
 *  runs, see vi_bench); 0: SUNDIALS' serial ones.  Results agree within
 *  the integration error (round-off can change CVODE's step choices).
 *  Takes effect at the next run.  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_sim_set_native_vector_ops(vi_sim *sim, int on);

/** Call fn at every event (impact, stick, release); NULL turns it off. */
VI_API int vi_sim_set_event_callback(vi_sim *sim, vi_event_fn fn, void *user,
                                     vi_destroy_fn destroy);
/** 1 (default): events carry the state (x, v_minus, v_plus); 0: those are
 *  NULL, for a host that reads only t, vn and ie (a sweep).  The exact
 *  method then takes a bounce in modal coordinates, O(n), without building
 *  the physical state (O(n^2) on a dense model); the motion is bit for bit
 *  the same either way.  vi_sim_state is valid in callbacks in both cases.
 *  @return VI_OK, VI_ERR_ARG (on not 0 or 1), VI_ERR_STATE (in a run). */
VI_API int vi_sim_set_event_states(vi_sim *sim, int on);
/** Call fn at t0 + k dt (k = 0, 1, ...), states taken from the integrator's
 *  interpolant without forcing steps on it; a sample at an impact time sees
 *  the state before the impact.  dt <= 0 or fn NULL turns sampling off.
 *  @return VI_OK, VI_ERR_ARG (dt not finite). */
VI_API int vi_sim_set_sampling(vi_sim *sim, double dt, vi_sample_fn fn,
                               void *user, vi_destroy_fn destroy);
/** Call fn after the step that passes each multiple of `every` (> 0) units
 *  of simulated time (vi_sim_run refuses, with VI_ERR_LIMIT, an interval
 *  below 4 DBL_EPSILON |t| or more than 1e12 reports).  @return VI_OK,
 *  VI_ERR_ARG. */
VI_API int vi_sim_set_monitor(vi_sim *sim, double every, vi_monitor_fn fn,
                              void *user, vi_destroy_fn destroy);

/** Poll fn for cancellation during vi_sim_run; a cancelled run returns
 *  VI_CANCELLED with the state of the last completed step (consistent: a
 *  later run continues from it).  NULL turns it off.  @return VI_OK. */
VI_API int vi_sim_set_cancel(vi_sim *sim, vi_cancel_fn fn, void *user,
                             vi_destroy_fn destroy);
/** Floors that keep a run from stalling: an approach velocity below vn_min
 *  (> 0) or a contact less than dt_min (> 0) after the previous one, with
 *  the stop pressed on, ends the impact sequence in sticking.  0 leaves a
 *  floor off (default: both off; the chatter threshold still applies).
 *  Every time a floor acts it is counted (VI_STAT_FLOORS).
 *  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_sim_set_floors(vi_sim *sim, double vn_min, double dt_min);
/** The method that ran (VI_METHOD_*, never AUTO once a run started).  */
VI_API int vi_sim_method_used(const vi_sim *sim);
/** One line saying which method ran and why (auto's choice, hand-overs from
 *  the closed form to CVODE); owned by the sim. */
VI_API const char *vi_sim_method_note(const vi_sim *sim);

/** Integrate from the current time to t_end.  A callback's stop request
 *  takes effect once its step is complete (its impacts applied), so the
 *  state stays consistent and a later call continues seamlessly; samples of
 *  that step after the request are dropped.
 *  @return VI_OK on reaching t_end, VI_STOPPED, VI_CANCELLED, or
 *  VI_ERR_TIME (t_end not after the current time), VI_ERR_INTEGRATOR,
 *  VI_ERR_ROOT, VI_ERR_INVARIANT (a state beyond the stop or not finite: the
 *  message says where), VI_ERR_NOMEM, VI_ERR_CALLBACK (a force callback
 *  failed or a force is not finite), VI_ERR_LIMIT (a monitor or sampling
 *  interval t cannot resolve), VI_ERR_STATE (called from inside a callback
 *  of this sim's run, or vi_sim_destroy called there). */
VI_API int vi_sim_run(vi_sim *sim, double t_end);

/** Allocate the integrator now (it is otherwise built by the first run),
 *  so that a host sees allocation and solver set-up errors before it
 *  starts.  @return VI_OK, VI_ERR_ARG, VI_ERR_NOMEM, VI_ERR_INTEGRATOR. */
VI_API int vi_sim_setup(vi_sim *sim);
/** Integrate until the next event or t_end, whichever comes first, so that
 *  a host code can drive the simulation impact by impact.  The event
 *  callback still sees every event.  *kind receives the VI_EVENT_* of the
 *  last event of the step that ended on one (an impact may be followed by
 *  the start of sticking at the same instant), or -1 when t_end was
 *  reached.  @return VI_OK, or as vi_sim_run (VI_STOPPED when the event
 *  callback asked to stop). */
VI_API int vi_sim_run_to_event(vi_sim *sim, double t_end, int *kind);

/** Current time and state; t, x [n], v [n] may be NULL.  Valid from
 *  callbacks too.  The exact method may build the physical state from its
 *  modes here, so one sim is not for concurrent calls (as for every other
 *  call on it).  @return VI_OK. */
VI_API int vi_sim_state(const vi_sim *sim, double *t, double *x, double *v);
/** Number of coordinates n of the sim's model; 0 for NULL. */
VI_API int vi_sim_n(const vi_sim *sim);
/** 1 while in a sticking phase, else 0. */
VI_API int vi_sim_is_sticking(const vi_sim *sim);
/** Kinetic energy lost at each stop since the sim was created: ie [ns]
 *  (vi_model_num_stops) receives, per stop, the impacts' losses and those
 *  of the chattering tails summed into sticking; their sum is the ledger's
 *  total impact loss.  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_sim_stop_losses(const vi_sim *sim, double *ie);
/** Value of a statistic (VI_STAT_*); -1 for an unknown one. */
VI_API int64_t vi_sim_stat(const vi_sim *sim, int which);

/* Names before the 0.2 API revision (one query scheme, without "get"). */
/** @deprecated use vi_sim_stat */
VI_DEPRECATED static inline int64_t vi_sim_get_stat(const vi_sim *sim,
                                                    int which)
{
  return vi_sim_stat(sim, which);
}
/** @deprecated use vi_sim_state */
VI_DEPRECATED static inline int vi_sim_get_state(const vi_sim *sim, double *t,
                                                 double *x, double *v)
{
  return vi_sim_state(sim, t, x, v);
}

#ifdef __cplusplus
}
#endif
#endif
