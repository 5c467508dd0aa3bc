/* vi_sim.h - the event integrator.
 *
 * Integrates the physical-coordinate system between impacts, locates each
 * contact w.x = x_s (approached from below, and also at maxima of w.x so that
 * grazing contacts inside one step are not stepped over), applies the
 * restitution law and goes on.  Impact sequences that accumulate (chattering,
 * r < 1) end in a sticking phase g = x_s, g' = 0 that is released when the
 * contact force falls through zero.
 *
 * Life cycle: vi_sim_create -> vi_sim_set_* -> vi_sim_run (repeatable; each
 * call continues from where the last stopped) -> vi_sim_get_* ->
 * vi_sim_destroy.  Results leave only through callbacks: the library keeps no
 * storage that grows with the run. */
#ifndef VI_SIM_H
#define VI_SIM_H

#include <stdint.h>

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vi_sim vi_sim;

/* Integration methods. */
enum {
  VI_METHOD_ADAMS = 0, /* CVODE Adams-Moulton, fixed-point iteration (default) */
  VI_METHOD_BDF = 1,   /* CVODE BDF, Newton with analytic Jacobian, dense or
                          band linear solver chosen from the model's bandwidth */
  VI_METHOD_EXACT = 2  /* closed-form flow (vi_flow.h) with root bracketing;
                          proportional damping only */
};

/* Kinds of event passed to the impact callback. */
enum {
  VI_EVENT_IMPACT = 0,  /* a Newton impact (WB 2) */
  VI_EVENT_STICK = 1,   /* chattering accumulated: sticking begins */
  VI_EVENT_RELEASE = 2  /* contact force fell through zero: sticking ends */
};

/* Statistics, read with vi_sim_get_stat(); totals over all vi_sim_run calls. */
enum {
  VI_STAT_STEPS = 0,      /* integrator steps (exact method: bracketing steps) */
  VI_STAT_RHS_EVALS = 1,  /* right-hand side evaluations */
  VI_STAT_JAC_EVALS = 2,  /* Jacobian evaluations (BDF) */
  VI_STAT_ROOT_EVALS = 3, /* root (event) function evaluations */
  VI_STAT_IMPACTS = 4,    /* Newton impacts applied */
  VI_STAT_STICKS = 5,     /* sticking phases entered */
  VI_STAT_GRAZE_CHECKS = 6, /* maxima of w.x examined for a missed contact */
  VI_STAT_REINITS = 7,    /* integrator restarts */
  VI_STAT_COUNT = 8
};

/* An event, valid only during the callback.  x, v_minus and v_plus are [n]
 * physical positions and velocities just before and after the event. */
typedef struct vi_event {
  int kind;        /* VI_EVENT_* */
  int n;
  int64_t index;   /* 0-based count of events of this kind so far */
  double t;
  double vn;       /* approach velocity w.x'(t-) */
  double ie;       /* kinetic energy lost (WB 10); 0 for stick/release */
  const double *x;
  const double *v_minus;
  const double *v_plus;
} vi_event;

typedef struct vi_progress {
  double t, t_start, t_end;
  int64_t steps, impacts;
} vi_progress;

/* Callbacks return 0 to go on, non-zero to stop: vi_sim_run then returns
 * VI_STOPPED with the state at the moment of the callback. */
typedef int (*vi_event_fn)(const vi_event *ev, void *user);
typedef int (*vi_sample_fn)(double t, int n, const double *x, const double *v,
                            void *user);
typedef int (*vi_monitor_fn)(const vi_progress *p, void *user);

/* The model must be set up; it is borrowed and must outlive the sim. */
VI_API int vi_sim_create(const vi_model *model, vi_sim **out);
VI_API void vi_sim_destroy(vi_sim **sim);
VI_API const char *vi_sim_errmsg(const vi_sim *sim);

VI_API int vi_sim_set_method(vi_sim *sim, int method);
/* rtol > 0, atol > 0 (absolute, on positions and velocities alike);
 * defaults 1e-8 and 1e-10. */
VI_API int vi_sim_set_tolerances(vi_sim *sim, double rtol, double atol);
/* Initial time and state; x0, v0 [n] (NULL = 0).  Default: rest at t = 0.
 * VI_ERR_INITIAL_STATE if w.x0 > x_s. */
VI_API int vi_sim_set_initial(vi_sim *sim, double t0, const double *x0,
                              const double *v0);
/* Approach velocity below which an impact ends chattering: the accumulation
 * point is taken as reached and sticking begins (if the contact force pushes
 * into the stop).  Default 1e-7 (in the model's velocity unit); 0 disables
 * it (then only r = 0 sticks). */
VI_API int vi_sim_set_chatter_threshold(vi_sim *sim, double vmin);
/* Step chosen by CVODE just after a restart: 0 (default) lets CVODE estimate
 * it; h > 0 forces it. */
VI_API int vi_sim_set_restart_step(vi_sim *sim, double h);
/* Maximum step size (0: unlimited, the default). */
VI_API int vi_sim_set_max_step(vi_sim *sim, double hmax);

VI_API int vi_sim_set_event_callback(vi_sim *sim, vi_event_fn fn, void *user);
/* Samples at t0 + k dt taken from the integrator's interpolant, without
 * forcing steps on it.  dt <= 0 or fn NULL turns sampling off. */
VI_API int vi_sim_set_sampling(vi_sim *sim, double dt, vi_sample_fn fn,
                               void *user);
/* Monitor called at least every `every` units of simulated time. */
VI_API int vi_sim_set_monitor(vi_sim *sim, vi_monitor_fn fn, void *user,
                              double every);

/* Integrate to t_end (> current time).  VI_OK on reaching t_end, VI_STOPPED
 * if a callback asked to stop, a negative code on failure. */
VI_API int vi_sim_run(vi_sim *sim, double t_end);

/* Current time and state; x, v [n] may be NULL. */
VI_API int vi_sim_get_state(const vi_sim *sim, double *t, double *x,
                            double *v);
/* 1 while in a sticking phase. */
VI_API int vi_sim_is_sticking(const vi_sim *sim);
/* A statistic (VI_STAT_*); -1 for an unknown one. */
VI_API int64_t vi_sim_get_stat(const vi_sim *sim, int which);

#ifdef __cplusplus
}
#endif
#endif
