/* vi_app.h - shared pieces of the vibroimpact program. */
#ifndef VI_APP_H
#define VI_APP_H

#include <signal.h>
#include <stdint.h>

#include "vibroimpact.h"
#include "vibroimpact/vi_scene.h"
#include "vibroimpact/vi_writer.h"

#define VI_APP_PATH 4096

typedef struct app_opts {
  const char *scene;  /* NULL: the embedded default (Fig. 2) */
  const char *out;    /* -o FILE.h5 as given */
  const char *csv;    /* --impacts-csv FILE or - */
  char out_target[VI_APP_PATH], csv_target[VI_APP_PATH]; /* links followed */
  int csv_kind;       /* vi_output_kind of the CSV */
  double rtol, atol, periods; /* <= 0: from the scene */
  double re, ke;      /* restitution */
  int method;         /* -1: from the scene */
  int quiet, json, progress;
  int64_t max_scene_bytes; /* limits (0: the library's defaults) */
  int max_depth;
  double max_memory;  /* bytes; 0: what the machine has available */
  int modes_lo, modes_hi; /* truncation --modes A..B (0: the defaults) */
  int modes_ref;          /* truncation --reference N (0: the default) */
} app_opts;

/* One subcommand: `vibroimpact NAME ...`.  The table in vibroimpact.c is
 * the only list (usage text and the suggestion for a mistyped name come
 * from it). */
typedef struct app_cmd {
  const char *name;
  int (*fn)(const app_opts *o);
  const char *synopsis; /* after "vibroimpact NAME " in the usage */
  const char *what;     /* one line */
} app_cmd;

/* ---- the HDF5 writer (vi_app_h5.c) -------------------------------------
 * The vi_writer_* functions of libvibroimpact_h5, as a table. */
typedef struct app_writer_api {
  int (*create)(const char *, const vi_model *, int, vi_writer **, vi_diag *);
  int (*write_header)(vi_writer *, const vi_scene *, double, double, int);
  int (*event)(vi_writer *, const vi_event *);
  int (*sample)(vi_writer *, double, const double *, const double *);
  int (*ledger)(vi_writer *, const vi_ledger_interval *);
  int (*orbit)(vi_writer *, const vi_orbit *);
  int (*run_info)(vi_writer *, const vi_sim *);
  long (*rows)(const vi_writer *, const char *);
  int (*finish)(vi_writer *, int);
  void (*abort)(vi_writer **);
  const char *(*errmsg)(const vi_writer *);
  int (*fe_shapes)(vi_writer *, const vi_fe *);
} app_writer_api;
/* The writer's functions (never NULL since the program links the library;
 * the callers' NULL checks stay harmless). */
const app_writer_api *vi_app_writer(void);
/* The study writer `name` of libvibroimpact_h5 (vi_truncation_write_h5),
 * or NULL after a message on stderr. */
void *vi_app_io_symbol(const char *name);

/* ---- signals (vibroimpact.c) ---------------------------------------------
 * Until a run polls for cancellation, SIGINT/SIGTERM end the process at
 * once: the handler removes the armed partial files and _exits with
 * 128 + signal, so parsing, model building and eigen-solves answer at once
 * and nothing is left on disk.  While a run polls, the handler only sets
 * vi_app_signal; the run stops within a step and closes its file marked
 * incomplete. */
extern volatile sig_atomic_t vi_app_signal;
/* Partial files (PATH.part, NULL for none) the handler removes. */
void vi_app_arm_parts(const char *part1, const char *part2);
/* 1: the run polls vi_app_signal (vi_app_cancel); 0: exit at once. */
void vi_app_set_polling(int on);
/* Cancellation poll for vi_sim_set_cancel. */
int vi_app_cancel(void *user);
/* Exit status for an interrupted command: 128 + signal (130, 143). */
int vi_app_interrupt_status(void);

/* Load the scene (or the default) with the command-line overrides and
 * limits and build its model; prints the diagnostic and returns an exit
 * status on failure (2 for input errors, 1 for run-time ones). */
int vi_app_load(const app_opts *o, vi_scene **scene, vi_model **model);
/* Print "vibroimpact: file:line:col: key = value: message". */
void vi_app_print_diag(const vi_diag *d, int st);
/* What the reduction of a finite-element scene did (nothing for others):
 * a summary line "  reduction ...", or a JSON member "fe": {...} followed
 * by ", ". */
void vi_app_fe_report(FILE *f, const vi_scene *sc);
void vi_app_fe_json(FILE *f, const vi_scene *sc);

/* Parse the command line into *o and the command; -1 to go on, else the
 * exit status (after --help, --version or a usage error).  No files are
 * touched (the output checks come after, in main). */
int vi_app_parse(int argc, char **argv, app_opts *o, const app_cmd **cmd);

int vi_cmd_run(const app_opts *o);
int vi_cmd_energy(const app_opts *o);
int vi_cmd_truncation(const app_opts *o);
/* `vibroimpact identify` parses its own arguments (vi_cmd_identify.c). */
int vi_cmd_identify_main(int argc, char **argv);
int vi_cmd_curves_main(int argc, char **argv);

#endif
