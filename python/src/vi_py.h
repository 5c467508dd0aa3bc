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

/* What a run keeps, one row of doubles per item so that Python reads each
 * table with one copy: events [t, vn, ie, (kind, stop as two int32 in one
 * double's bytes), (states) x, v_minus, v_plus [n each]]; samples [t, x, v]; ledger intervals [t_a, t_b, ie,
 * residual, impact, E_a, E_b, K_a, K_b, FE, DE, XE, CE, NE, dE]. */
typedef struct vi_py_run {
  int n, states, nomem;
  int width[3];        /* doubles per row of each table */
  vi_py_buf tab[3];    /* 0 events, 1 samples, 2 ledger */
  unsigned sig0;       /* the SIGINT count when the run started */
} vi_py_run;

vi_py_run *vi_py_run_new(int n, int states);
void vi_py_run_free(vi_py_run *r);
/* 1 when a collector ran out of memory (the run was stopped). */
int vi_py_nomem(const vi_py_run *r);
/* vi_sim_destroy for a finaliser that holds the pointer itself. */
void vi_py_sim_free(vi_sim *sim);
/* Method, tolerances, the collectors (events; samples every dt > 0; the
 * ledger when ledger is 1) and the cancel hook on sim, in one call.
 * 0 or the first setter's status (its message in vi_sim_errmsg). */
int vi_py_prepare(vi_py_run *r, vi_sim *sim, int method, double rtol,
                  double atol, double dt, int ledger);
/* Table `which` (0 events, 1 samples, 2 ledger): *rows rows of *width
 * doubles, row-major. */
const double *vi_py_table(const vi_py_run *r, int which, int64_t *rows,
                          int *width);
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

/* The C loops of bench/python_bench.py (vi_py_bench.c): seconds per run,
 * and of a whole sweep; negative on an error. */
double vi_py_bench_simulate(const vi_model *model, int reps, double t_end,
                            int method, double rtol, double atol);
double vi_py_bench_sweep(const vi_model *model, const char *key,
                         const double *values, int nv, int transient,
                         int record, int method, double *sink);
#endif
