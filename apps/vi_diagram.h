/* vi_diagram.h - brute-force bifurcation diagrams (`vibroimpact sweep`).
 *
 * One scene key (any numeric one, e.g. forcing.omega, stop.xs, forcing.a[1])
 * takes K values from..to; at each value the key is set on the model built
 * once (vi_sweep_set_param, a copy per piece), simulated for `transient` forcing periods and
 * then `record` more, whose impacts (time mod T, v_n) and stroboscopic
 * states (at t0 + k T) are kept, and the motion is classified P(n, m).
 *
 * Warm start: each value starts from the state the previous value ended in
 * (at the same forcing phase, t0 mod T), so sweeps up and down show
 * hysteresis.  The first value of a line starts from the scene's
 * `initial:`.  A piece is a whole line (one direction at one value of the
 * second parameter) or, with `chunks` C > 1, one of C contiguous runs of
 * values of the line in its direction, seeded with the state a serial
 * chain through the chunks' first values ends in; each value's start
 * depends on C alone, so any number of threads (or a serial run) gives
 * bit-identical results for the same C.  Under MPI (`mpirun -np K vibroimpact sweep ...`, built with
 * OpenMPI) the pieces are dealt round-robin to the ranks, each runs its
 * own on its OpenMP threads, and rank 0 gathers the diagram: identical
 * for any K.
 */
#ifndef VI_DIAGRAM_H
#define VI_DIAGRAM_H

#include <signal.h>
#include <stdint.h>
#include <stdio.h>

#include "vibroimpact.h"

typedef struct vi_diagram_spec {
  const char *key;      /* swept scene key */
  double from, to;
  int steps;            /* K >= 1 */
  const char *key2;     /* second parameter (two-parameter map) or NULL */
  double from2, to2;
  int steps2;           /* rows of the map (1 without key2) */
  int dirs;             /* 1 up (from -> to), 2 down, 3 both */
  int transient, record;/* forcing periods per value */
  int chunks;           /* pieces per line (warm start inside a piece) */
  int threads;          /* <= 0: the OpenMP default */
  double tol;           /* classification tolerance, relative */
  int nmax;             /* longest orbit period looked for (forcing periods) */
  int orbits;           /* > 0: also every P(1,1) orbit at each value, by a
                           scan of this many impact phases (vi_orbit_p1_scan),
                           unstable ones included; 0: off */
  int cold;             /* 1: every value from the scene's initial state (a
                           basin of attraction), no warm start */
  int lyapunov;         /* 1: the largest Lyapunov exponent of each value
                           (vi_sweep_set_lyapunov) */
  int max_depth;        /* deepest YAML nesting of the scene and the --set
                           values (<= 0: VI_SCENE_MAX_DEPTH) */
} vi_diagram_spec;

/* One parameter value of one line. */
typedef struct vi_diagram_point {
  int n, m;             /* P(n, m); n = 0: none within the recorded periods */
  int64_t nimp;         /* impacts in the recorded periods */
  double *t, *phase, *vn; /* their times, times mod T, approach velocities */
  double T;             /* forcing period */
  int failed;           /* 1: the simulation of this value failed (why:
                           `error`); the next value starts cold */
  char *error;
  /* spec.orbits: the P(1,1) orbits at this value (-1: no closed-form flow) */
  double lyap;          /* spec.lyapunov: the largest Lyapunov exponent
                           (per unit time), NaN where refused */
  int norb;
  double *ovn, *ophase;  /* [norb] approach velocity w.v, impact time mod T */
  int *ostable, *oadm;   /* [norb] stable (all |mu| < 1), admissible */
  int done;             /* 1: computed (failed or not); 0: an interrupted
                           sweep never reached it */
} vi_diagram_point;

typedef struct vi_diagram_line {
  int dir;              /* +1 up, -1 down */
  int row;              /* index of the second parameter's value */
  vi_diagram_point *pt;   /* [K], by value index (ascending from..to) */
  double *strobe;       /* [K][record][2N]: x then v at t0 + (P + k) T */
} vi_diagram_line;

typedef struct vi_diagram {
  vi_diagram_spec spec;
  int N;                /* coordinates */
  double t0;
  double *z0;             /* [2N]: the scene's initial x then v, read once
                             (projected onto the modes of an FE scene) */
  double *param, *param2; /* [K], [steps2] */
  int nlines;
  vi_diagram_line *lines;   /* row-major: row r, then up before down */
  char *text, *name;      /* the base scene (after --set) and its file name */
  double wall;            /* seconds spent in vi_diagram_run */
  int rank;               /* MPI rank (0 without MPI): only rank 0 holds
                             the whole diagram */
  struct vi_scene *sc;    /* the base scene */
  vi_model *model;        /* its model, built once: values are parameters */
  char pkey[64], pkey2[64]; /* the keys as parameters (vi_param.h) */
  int warm;               /* warm start along a line (not spec.cold) */
  int *attractor;         /* spec.cold: [nlines x K] attractor ids (-1:
                             none), vi_sweep_attractors; rank 0 only */
  int nattr;
  double max_memory;      /* the memory check's limit (vi_diagram_run_limited) */
  int writes;             /* 1: the file will be built in memory too */
  int incomplete;         /* 1: interrupted, only the points marked done */
  int64_t points_done;    /* points computed (of nlines x K) */
} vi_diagram;

/* Run the sweep on the scene text (name: its file, for messages) after
 * the KEY=VALUE assignments sets[nsets].  Returns 0, or 2 for bad input
 * (message in err, naming file:line:key where known), 1 for a run-time
 * failure, 3 when cancelled (*cancel set non-zero by a signal handler):
 * then *out holds the points done so far (incomplete = 1; the point in
 * progress in each piece is dropped). */
int vi_diagram_run(const char *text, const char *name, const char *const *sets,
                   int nsets, const vi_diagram_spec *spec,
                   volatile sig_atomic_t *cancel, vi_diagram **out, char *err,
                   int errlen);
/* vi_diagram_run with the memory check's limit: before the model and the
 * diagram are allocated, their size (the model and a simulation per
 * thread, the stroboscopic states, one impact per recorded period, and
 * with `writes` the file built in memory) is compared with max_memory
 * bytes (<= 0: MemAvailable of /proc/meminfo); more is refused (2, the
 * flags and the figures in err).  vi_diagram_run: max_memory 0, writes 0. */
int vi_diagram_run_limited(const char *text, const char *name,
                           const char *const *sets, int nsets,
                           const vi_diagram_spec *spec, double max_memory,
                           int writes, volatile sig_atomic_t *cancel,
                           vi_diagram **out, char *err, int errlen);
/* The bytes a diagram of spec with N coordinates holds (the estimate
 * vi_diagram_run_limited checks), scene_bytes the model's and one
 * simulation's (vi_scene_memory_estimate). */
double vi_diagram_memory_estimate(const vi_diagram_spec *spec, int N,
                                  double scene_bytes, int writes);
void vi_diagram_free(vi_diagram **sw);
/* The chunks per line a warm sweep of spec gets without --chunks, fixed by
 * its size alone (never by the threads, so the diagram is the same on any
 * machine): one per min(16, ceil(sqrt(K))) values; 1 (each line exact, in
 * order) for --both (hysteresis asked for) and for 16 lines or more (the
 * lines are parallel enough). */
int vi_diagram_default_chunks(const vi_diagram_spec *spec);
/* How the sweep was split, in words, into s[len]. */
void vi_diagram_split(const vi_diagram *sw, char *s, int len);

/* Basins (spec.cold): the attractor of every cell, sw->attractor and
 * sw->nattr (vi_sweep_attractors); 0, or 1 out of memory.  Then JSON (flat
 * param, param2, n, m, attractor per cell) or a text grid. */
int vi_basins_identify(vi_diagram *sw);
void vi_basins_print_json(const vi_diagram *sw, FILE *f);
void vi_basins_table(const vi_diagram *sw, FILE *f);

/* The diagram as one JSON object (see share/doc/sweep-layout.md). */
void vi_diagram_print_json(const vi_diagram *sw, FILE *f);
/* The diagram to HDF5 (share/doc/sweep-layout.md): written to path.part,
 * renamed on success.  Returns 0, or 1 with a message in err. */
int vi_diagram_write_h5(const vi_diagram *sw, const char *path, char *err,
                        int errlen);


/* The scene file's text (path NULL: the embedded default), malloc'ed; NULL
 * with a message in err. */
char *vi_app_read_text(const char *path, char *err, int errlen);
/* Read a scene file (NULL: the default) with KEY=VALUE overrides applied
 * (vi_scene_edit, at most max_depth levels of nesting, <= 0: the default)
 * and parse it, the scene's vectors within max_memory bytes (<= 0: what
 * the machine has; vi_scene_edit_parse_within).  Returns 0, 2 for bad
 * input, 1 for I/O;
 * err names file:line:key. */
struct vi_scene;
int vi_app_load_scene(const char *path, const char *const *sets, int nsets,
                      int max_depth, double max_memory,
                      struct vi_scene **out, char *err, int errlen);

/* --set KEY=VALUE for run and energy: vi_sets_take removes every
 * `--set KEY=VALUE` (or `--set=KEY=VALUE`) from argv and keeps them;
 * returns the new argc, -1 for a --set without its value.  vi_sets_load
 * then loads a scene (NULL: the default) as vi_scene_load does, with them
 * applied (vi_scene_edit: errors keep the file:line of the key) and at most
 * max_depth levels of nesting (<= 0: the default, --max-depth), the file
 * at most max_bytes (--max-scene-size; <= 0: the reader's limit), the
 * scene's vectors within max_memory (as vi_app_load_scene). */
int vi_sets_take(int argc, char **argv);
/* Number of --set assignments taken (0: load scenes as usual). */
int vi_sets_active(void);
struct vi_diag;
int vi_sets_load(const char *path, int64_t max_bytes, int max_depth, double max_memory,
                 struct vi_scene **out, struct vi_diag *d);

/* Two keys of one parameter (stop.xs is stops[1].xs): 1 or 0. */
int vi_app_same_key(const char *k1, const char *k2);

/* 1 if the scene text has nonlinear springs (`springs:`): the closed-form
 * orbit machinery (orbits, sweep --orbits) covers linear scenes only. */
int vi_app_text_nonlinear(const char *text);

/* `vibroimpact sweep ARGS`: replace this process by vibroimpact-sweep
 * (beside the program) with argv = the subcommand's; returns only on
 * failure (exit status 1, message printed). */
int vi_app_sweep_exec(int argc, char **argv);

/* Follow the P(n,1) orbit (t0, x0, v0 [N]: an impact and the state before
 * it) of the scene's model m in the scene key `key` from its value to `to`
 * in `steps` steps, naturally or (arclength) by pseudo-arclength around
 * folds (vi_cont.h), printing the branch and the points where it loses
 * stability, folds or grazes (text, or JSON {key, n, m, branch, events}).
 * Returns 0, 2 for bad input (err), 1 otherwise (vi_cmd_orbits_cont.c). */
int vi_orbits_follow(const vi_model *m, const struct vi_scene *sc,
                     const char *key, int arclength, double to, int steps,
                     int np, double t0, const double *x0, const double *v0,
                     int json, char *err, int errlen);

/* `vibroimpact sweep ...` and `vibroimpact orbits ...`: argv[0] is the
 * subcommand; returns the exit status. */
int vi_cmd_sweep_main(int argc, char **argv);
int vi_cmd_orbits_main(int argc, char **argv);

#endif
