/* stress_util.h - shared helpers of the stress suite (tests/stress): an
 * event log that keeps the energy of each event, a guard that cancels a run
 * which would otherwise hang, a sampler that records the largest excursion
 * beyond the stop, and the process's peak resident memory. */
#ifndef STRESS_UTIL_H
#define STRESS_UTIL_H

#include "vi_testutil.h"

/* Soft assertions: a failed check is printed with its line and counted, so
 * that one test function measures every method before it fails;
 * st_end() fails the test if any check failed since the last st_end().
 * The test is in a function of stress_util.c, out of the lint's
 * path-sensitive analyser's sight: a branch per check in the test files
 * made it explore each test with many checks to its node budget. */
extern int st_failures;
#define st_check(cond) st_check_(!!(cond), #cond, __FILE__, __LINE__)
void st_check_(int ok, const char *cond, const char *file, int line);
void st_end(void);

/* Every event with its kind, time, approach velocity and energy lost. */
typedef struct st_log {
  int count, cap;
  int *kind;
  double *t, *vn, *ie, *x1, *v1; /* x1, v1: w-weighted gap and w.v_plus */
  const double *w;
  double xs;
  int n;
} st_log;
int st_log_event(const vi_event *ev, void *user);
void st_log_free(st_log *l);
/* Number of events of a kind; index of the k-th (0-based) or -1. */
int st_log_count(const st_log *l, int kind);
int st_log_find(const st_log *l, int kind, int k);
/* Sum of ie over all events. */
double st_log_ie(const st_log *l);

/* Cancellation guard: cancels after `limit` polls (the library polls every
 * step), so a run that would stall ends with VI_CANCELLED instead of hanging
 * the test. */
typedef struct st_guard { int64_t polls, limit; } st_guard;
int st_guard_poll(void *user);

/* Sampler: the largest w.x - x_s over all samples. */
typedef struct st_gap { const double *w; double xs, gmax; int64_t count; } st_gap;
int st_gap_sample(double t, int n, const double *x, const double *v, void *user);

/* Methods to try: every VI_METHOD_* that vi_sim_set_method accepts for m
 * (VI_ERR_UNSUPPORTED ones are skipped with a message). */
int st_method_ok(const vi_model *m, int method);

/* A sim from (t0, x0, v0) with a method and tolerances, logging events into
 * log (may be NULL) and polling a guard of `limit` steps. */
vi_sim *st_sim(const vi_model *m, int method, double rtol, double atol,
               double t0, const double *x0, const double *v0, st_log *log,
               st_guard *guard);

/* SDOF m x'' + c x' + k x = a cos(W t) + b sin(W t) + f0, stop x <= xs. */
vi_model *st_sdof(double m, double c, double k, double W, double a, double b,
                  double f0, double xs, double r);

/* Peak resident set size (VmHWM) of this process in KiB; -1 if unknown. */
long st_vmhwm_kib(void);

#endif
