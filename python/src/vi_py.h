/* vi_py.h - the C side of the Python package: a run's events, samples and
 * ledger collected into growing arrays (no Python call per impact), and
 * Ctrl-C turned into the library's cancel hook.  Compiled into the cffi
 * extension vibroimpact._vi; the Python side reads the arrays once the
 * run returns. */
#ifndef VI_PY_H
#define VI_PY_H
#include <stdint.h>
#include <vibroimpact.h>
#include <vibroimpact/vi_writer.h>

/* One growing array of doubles (or ints stored as doubles' neighbours). */
typedef struct vi_py_buf {
  double *d;
  int64_t len, cap;
} vi_py_buf;

/* What a run keeps: per event t, vn, ie, kind, stop and (states) x,
 * v_minus, v_plus [n]; per sample t, x, v [n]; per ledger interval t_a,
 * t_b, ie, residual, impact and the [n] rows E_a, E_b, K_a, K_b, FE, DE,
 * XE, CE, NE, dE. */
typedef struct vi_py_run {
  int n, states, nomem;
  int64_t events, samples, intervals;
  vi_py_buf ev[8];   /* t, vn, ie, kind, stop, x, v_minus, v_plus */
  vi_py_buf smp[3];  /* t, x, v */
  vi_py_buf led[15]; /* t_a, t_b, ie, residual, impact, E_a, E_b, K_a, K_b,
                        FE, DE, XE, CE, NE, dE */
  unsigned sig0;     /* the SIGINT count when the run started */
} vi_py_run;

vi_py_run *vi_py_run_new(int n, int states);
void vi_py_run_free(vi_py_run *r);
/* 1 when a collector ran out of memory (the run was stopped). */
int vi_py_nomem(const vi_py_run *r);
/* Attach the collectors (events; samples every dt > 0; the ledger when
 * ledger is 1) and the cancel hook to sim. */
int vi_py_attach(vi_py_run *r, vi_sim *sim, double dt, int ledger);
/* Length of collected array `which` of a group (0 events, 1 samples,
 * 2 ledger) and a pointer to it. */
const double *vi_py_data(const vi_py_run *r, int group, int which,
                         int64_t *len);
/* Replay the collected rows into an HDF5 writer (as the program writes
 * them during its run).  0 or the writer's status. */
int vi_py_replay(const vi_py_run *r, vi_writer *w);

/* Ctrl-C: while any run is in progress a SIGINT handler counts the
 * signals (and passes them on to the handler it replaced, Python's, so
 * that KeyboardInterrupt is raised when the interpreter resumes).  The
 * cancel hook of a run reports a signal since its start. */
int vi_py_sigint_arm(void);
void vi_py_sigint_disarm(void);
unsigned vi_py_sigint_count(void);
int vi_py_cancel(void *user);
/* A run's study hooks: cancel polls for a vi_sweep, vi_cont, ... with
 * user = a pointer to the unsigned SIGINT count at its start. */
int vi_py_cancel_since(void *user);

/* Run sim to t_end with the GIL released by cffi: arm, run, disarm.  The
 * status of vi_sim_run; *interrupted is 1 when SIGINT cancelled it. */
int vi_py_sim_run(vi_sim *sim, vi_py_run *r, double t_end, int *interrupted);
#endif
