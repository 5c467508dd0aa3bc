/* vi_testutil.h - shared fixtures for the cmocka tests. */
#ifndef VI_TESTUTIL_H
#define VI_TESTUTIL_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "vibroimpact.h"

/* assert |a - b| <= tol, printing both on failure */
#define assert_close(a, b, tol)                                            \
  vi_assert_close_((a), (b), (tol), #a, #b, __FILE__, __LINE__)
void vi_assert_close_(double a, double b, double tol, const char *sa,
                      const char *sb, const char *file, int line);

/* The paper's Fig. 2 scene (MODEL.md section 6): N = 2 chain, m = k = 1,
 * c = 0.1, x_s = 0.1, a = (0.5, 0), Omega = 0.9, r = 0.7, stop on mass 2.
 * Returns a set-up model; fails the test on error. */
vi_model *vi_test_fig2(void);
/* Uniform fixed-free chain of n masses; stop on the last mass. */
vi_model *vi_test_chain(int n, double m, double k, double c, double xs,
                        double r, double omega, const double *a);
/* Single degree of freedom m x'' + c x' + k x = f, stop at xs. */
vi_model *vi_test_sdof(double m, double c, double k, double a, double f0,
                       double omega, double xs, double r);

/* A set-up model from explicit column-major n x n matrices (C may be NULL),
 * forcing a cos(omega t) (a may be NULL) and the stop w.x <= xs, r. */
vi_model *vi_test_model(int n, const double *M, const double *C,
                        const double *K, double omega, const double *a,
                        const double *f0, const double *w, double xs, double r);

/* The paper's beam (WB 2000 section 4): the clamped-free cantilever's
 * first `modes` modes (vi_build_cantilever, omega_1 = 1, zeta = 0.05, the
 * stop at the tip), a base acceleration 0.01 cos(0.85 t) and the stop at
 * xs with r; modes <= 8. */
vi_model *vi_test_beam(int modes, double xs, double r);

/* The non-proportional 3-DOF fixture (also share/scenes/nonproportional.yaml):
 * non-diagonal M, a damper that is not proportional, stop w = (0.2, -0.5, 1)
 * at xs with r = 0.6, forcing a = (0.6, 0, 0.3) cos(0.8 t) + f0 (f0 may be
 * NULL).  The arrays are exported for tests that check the ODE itself. */
extern const double vi_test_np3_M[9], vi_test_np3_C[9], vi_test_np3_K[9],
    vi_test_np3_a[3];
vi_model *vi_test_nonprop3(double xs, const double *f0);

/* Impact records collected by vi_test_collect (an event callback). */
typedef struct vi_test_events {
  int count, cap, n;
  int *kind;
  double *t, *vn, *x, *vm, *vp; /* vm, vp, x: count x n */
} vi_test_events;
int vi_test_collect(const vi_event *ev, void *user);
void vi_test_events_free(vi_test_events *e);

/* A sim with method and tolerances from (0, x0, v0), collecting events into
 * ev when it is not NULL. */
vi_sim *vi_test_sim(const vi_model *m, int method, double rtol, double atol,
                    const double *x0, const double *v0, vi_test_events *ev);

/* Run a model with a method and tolerances from rest (or x0, v0) over
 * [0, t_end], collecting events; returns the status of vi_sim_run. */
int vi_test_run(const vi_model *m, int method, double rtol, double atol,
                const double *x0, const double *v0, double t_end,
                vi_test_events *ev);

/* Events with their stop: kind, stop, t, vn, ie [count]; x, v_minus (vm),
 * v_plus (vp) [count x n], NaN for events without states.  vi_test_record
 * is the event callback. */
typedef struct vi_test_rec {
  int count, cap, n;
  int *kind, *stop;
  double *t, *vn, *ie, *x, *vm, *vp;
} vi_test_rec;
int vi_test_record(const vi_event *ev, void *user);
void vi_test_rec_free(vi_test_rec *e);
/* A set-up model: n x n M, C (NULL = 0), K; forcing a cos(omega t) + f0
 * (either NULL); ns stops, W [n x ns] column-major, xs [ns], r [ns]. */
vi_model *vi_test_model_stops(int n, const double *M, const double *C,
                              const double *K, double omega, const double *a,
                              const double *f0, int ns, const double *W,
                              const double *xs, const double *r);
/* A sim of m with the method and tolerances, starting at (t0, x0, v0),
 * recording its events into ev (may be NULL). */
vi_sim *vi_test_sim_stops(const vi_model *m, int method, double rtol,
                          double atol, double t0, const double *x0,
                          const double *v0, vi_test_rec *ev);

/* Chattering (Budd & Dux): a free mass pressed on the stop x <= 0 by a
 * load g = 2, leaving it at V = 1 with r = 0.5, bounces at 2V/g (1 + r +
 * ... + r^(k-1)) with speed V r^(k-1); the impacts accumulate at
 * T = 2V / (g (1 - r)) = 2.  Runs it to t = 5 with the method at rtol
 * 1e-12, atol 1e-14 and the accuracy-driven summing, and asserts what
 * every method must give: more than 4 resolved impacts (those with v_n >
 * 10 atol / rtol = 0.1 at least) at those times and speeds (1e-9; 1e-6 for
 * the late, grazing bounces, where a position error dx is a velocity error
 * g dx / v), a last STICK event at T (1e-10), and the mass at rest on the
 * stop.  Returns the sim for further checks (the caller destroys it, ev and
 * *m); *last is the index of the STICK event. */
vi_sim *vi_test_chatter_sticks(int method, vi_model **m, vi_test_events *ev,
                               int *last);

#endif
