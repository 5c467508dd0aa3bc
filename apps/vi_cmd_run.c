/* vi_cmd_run.c - `vibroimpact run`: simulate a scene, write CSV / HDF5. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "vi_app.h"
#include "vi_diagram.h"

void vi_app_print_diag(const vi_diag *d, int st)
{
  vi_diag dd = *d;
  char msg[1200];
  if (!dd.code) {
    dd.code = st;
    if (!dd.message[0])
      snprintf(dd.message, sizeof dd.message, "%s", vi_strerror(st));
  }
  vi_diag_format(&dd, msg, sizeof msg);
  fprintf(stderr, "vibroimpact: %s\n", msg);
}

int vi_app_load(const app_opts *o, vi_scene **scene, vi_model **model)
{
  vi_diag d;
  memset(&d, 0, sizeof d);
  /* the scene's own vectors within --max-memory too, before they are
   * allocated (a matrix file's header may claim any n) */
  int st = vi_sets_active()
               ? vi_sets_load(o->scene, o->max_scene_bytes, o->max_depth, o->max_memory, scene,
                              &d) /* --set */
           : o->scene ? vi_scene_load_within(o->scene, o->max_scene_bytes,
                                             o->max_depth, o->max_memory,
                                             scene, &d)
                      : vi_scene_parse(vi_scene_default_text(), -1,
                                       "<default scene: fig2>", scene, &d);
  if (!st && (st = vi_scene_set_run(*scene, o->rtol, o->atol, o->periods,
                                    o->method)))
    snprintf(d.message, sizeof d.message, "%s",
             st == VI_ERR_FREQUENCY
                 ? "--periods needs a forcing frequency (forcing.omega)"
             : st == VI_ERR_TOLERANCE
                 ? "--rtol must lie in [4.4e-16, 0.1] (run.rtol's range)"
                 : "cannot apply the command-line overrides");
  /* the memory the model will need, before any of it is allocated */
  if (!st) st = vi_scene_check_memory(*scene, o->max_memory, &d);
  if (!st) st = vi_scene_create_model(*scene, model, &d);
  if (st) {
    vi_app_print_diag(&d, st);
    vi_scene_destroy(scene);
    /* a scene that cannot be read is an input error too; only running out
     * of memory is the machine's */
    return st == VI_ERR_NOMEM ? 1 : 2;
  }
  return 0;
}

typedef struct run_ctx {
  const app_opts *o;
  FILE *csv;
  vi_writer *w;
  const app_writer_api *wa; /* loaded with -o only */
  int n, io_err, store_events;
  int64_t impacts;
  double t_last, vn_last, t0, t_end, wall0;
} run_ctx;

static double now(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int on_event(const vi_event *ev, void *user)
{
  run_ctx *c = user;
  if (c->w && c->store_events && c->wa->event(c->w, ev)) c->io_err = 1;
  if (ev->kind != VI_EVENT_IMPACT) return c->io_err;
  c->t_last = ev->t;
  c->vn_last = ev->vn;
  if (c->csv) {
    fprintf(c->csv, "%lld,%.17g,%.17g", (long long)c->impacts, ev->t, ev->vn);
    for (int i = 0; i < ev->n; i++) fprintf(c->csv, ",%.17g", ev->x[i]);
    for (int i = 0; i < ev->n; i++) fprintf(c->csv, ",%.17g", ev->v_minus[i]);
    if (fputc('\n', c->csv) == EOF || ferror(c->csv)) c->io_err = 2;
  }
  c->impacts++;
  return c->io_err;
}

static int on_sample(double t, int n, const double *x, const double *v, void *user)
{
  (void)n;
  run_ctx *c = user;
  if (c->wa->sample(c->w, t, x, v)) c->io_err = 1;
  return c->io_err;
}

static int on_ledger(const vi_ledger_interval *iv, void *user)
{
  run_ctx *c = user;
  if (c->w && c->wa->ledger(c->w, iv)) c->io_err = 1;
  return c->io_err;
}

static int on_monitor(const vi_progress *p, void *user)
{
  run_ctx *c = user;
  if (c->o->progress) {
    double frac = (p->t - c->t0) / (c->t_end - c->t0), el = now() - c->wall0;
    int bar = (int)(30 * frac);
    bar = bar < 0 ? 0 : bar > 30 ? 30 : bar;
    fprintf(stderr, "\r[%.*s%*s] %5.1f%%  %lld impacts  %.3g time units/s ",
            bar, "##############################", 30 - bar, "", 100 * frac,
            (long long)p->impacts, el > 0 ? (p->t - c->t0) / el : 0.0);
  }
  return 0;
}

static void summary(FILE *f, const app_opts *o, const vi_scene *sc,
                    const vi_model *m, const vi_sim *s, const run_ctx *c,
                    double period, int ledger, double setup, double wall,
                    const long *rows)
{
  int n = c->n;
  const double *om = vi_model_omega(m);
  const char *used = vi_method_name(vi_sim_method_used(s)),
             *note = vi_sim_method_note(s);
  fprintf(f, "vibroimpact %s: scene %s (n = %d)\n", vi_version_string(),
          vi_scene_name(sc), n);
  vi_app_fe_report(f, sc);
  if (om) {
    fprintf(f, "  modes     omega =");
    for (int j = 0; j < n && j < 8; j++) fprintf(f, " %.6g", om[j]);
    fprintf(f, "%s\n", n > 8 ? " ..." : "");
  } else {
    fprintf(f, "  model     band storage (half-bandwidth %d), no modal "
            "analysis; highest frequency <= %.6g\n", vi_model_bandwidth(m),
            vi_model_omega_bound(m));
  }
  int forced = vi_model_omega_forcing(m) > 0; /* else: free motion */
  char span[64] = "free motion";
  if (forced)
    snprintf(span, sizeof span, "%.6g forcing periods",
             (c->t_end - c->t0) / period);
  fprintf(f, "  run       t = %g .. %g (%s), method %s, rtol %g, atol %g\n",
          c->t0, c->t_end, span, used ? used : "?", vi_scene_rtol(sc),
          vi_scene_atol(sc));
  if (note && note[0]) fprintf(f, "  method    %s\n", note);
  fprintf(f, "  impacts   %lld", (long long)c->impacts);
  if (forced)
    fprintf(f, " (%.4f per forcing period)",
            c->impacts / ((c->t_end - c->t0) / period));
  if (c->impacts)
    fprintf(f, "; last at t = %.10g, v_n = %.10g", c->t_last, c->vn_last);
  fputc('\n', f);
  if (ledger) {
    double ie;
    vi_sim_ledger(s, NULL, NULL, NULL, NULL, NULL, NULL, &ie);
    fprintf(f, "  ledger    energy lost at impacts %.10g; largest closure "
            "residual %.3g\n", ie, vi_sim_ledger_max_residual(s));
  }
  /* every statistic the library keeps, by its own name */
  fprintf(f, "  stats    ");
  for (int k = 0, col = 11; k < VI_STAT_COUNT; k++) {
    const char *name = vi_stat_name(k);
    if (!name) continue;
    char item[96];
    int len = snprintf(item, sizeof item, " %s %lld", name,
                       (long long)vi_sim_stat(s, k));
    if (col + len > 78) {
      fprintf(f, "\n           ");
      col = 11;
    }
    fputs(item, f);
    col += len;
  }
  fprintf(f, "\n  set-up    %.3f ms (the integrator, before the run)\n", 1e3 * setup);
  fprintf(f, "  cost      %.3f ms\n", 1e3 * wall);
  if (o->out)
    fprintf(f, "  output    %s: %ld events, %ld samples, %ld ledger rows\n",
            o->out, rows[0], rows[1], rows[2]);
}

/* The sim of the scene's model with the scene's settings; 0 or the exit
 * status with the message printed. */
static int create_sim(const vi_scene *sc, const vi_model *m, vi_sim **s)
{
  vi_diag d;
  memset(&d, 0, sizeof d);
  int st = vi_sim_create(m, s);
  if (!st) st = vi_scene_configure_sim(sc, *s, &d);
  if (!st) return 0;
  if (!d.message[0]) snprintf(d.message, sizeof d.message, "%s", vi_sim_errmsg(*s));
  vi_app_print_diag(&d, st);
  return st == VI_ERR_NOMEM ? 1 : 2;
}

/* The full Psi into the HDF5 file, only when asked: the reduction is
 * solved again with its shapes kept (the model made for the run kept
 * none).  0 or the exit status with the message printed. */
static int write_shapes(run_ctx *c, const vi_scene *sc)
{
  vi_diag d;
  memset(&d, 0, sizeof d);
  vi_fe *fe = NULL;
  int fst = vi_scene_create_fe(sc, 0, 1, &fe, &d), wst = VI_OK;
  if (fst)
    vi_app_print_diag(&d, fst);
  else if ((wst = c->wa->fe_shapes(c->w, fe)))
    fprintf(stderr, "vibroimpact: %s\n", c->wa->errmsg(c->w));
  vi_fe_destroy(&fe);
  if (fst || wst) return fst && fst != VI_ERR_NOMEM ? 2 : 1;
  return 0;
}

/* -o: the HDF5 writer, its header and the shapes if asked; 0 or the exit
 * status with the message printed. */
static int open_writer(run_ctx *c, const vi_scene *sc, const vi_model *m, int outs)
{
  const app_opts *o = c->o;
  vi_diag d;
  memset(&d, 0, sizeof d);
  if (!(c->wa = vi_app_writer())) return 1;
  if (c->wa->create(o->out_target, m, (outs & VI_SCENE_OUT_COMPRESS) != 0, &c->w, &d)) {
    fprintf(stderr, "vibroimpact: %s\n", d.message);
    return 1;
  }
  if (c->wa->write_header(c->w, sc, vi_scene_rtol(sc), vi_scene_atol(sc),
                          vi_scene_method(sc))) {
    fprintf(stderr, "vibroimpact: %s\n", c->wa->errmsg(c->w));
    return 1;
  }
  return outs & VI_SCENE_OUT_SHAPES ? write_shapes(c, sc) : 0;
}

/* --csv: the impacts table opened and its header written; 0, or 1 with
 * the message printed (and part cleared: nothing of ours to remove). */
static int open_csv(run_ctx *c, char *part)
{
  const app_opts *o = c->o;
  vi_diag d;
  memset(&d, 0, sizeof d);
  if (vi_output_open(o->csv_target, o->csv_kind, &c->csv, &d)) {
    fprintf(stderr, "vibroimpact: %s\n", d.message);
    part[0] = '\0';
    return 1;
  }
  fprintf(c->csv, "k,t,vn");
  for (int i = 1; i <= c->n; i++) fprintf(c->csv, ",x_%d", i);
  for (int i = 1; i <= c->n; i++) fprintf(c->csv, ",v_%d", i);
  fputc('\n', c->csv);
  return 0;
}

/* The callbacks on the sim (events, progress, cancel, samples, ledger),
 * the integrator built (vi_sim_setup: its allocations and first use of
 * the code and tables it needs, timed apart in *setup), then the run; the
 * status of the first that fails, *wall the run's seconds. */
static int simulate(run_ctx *c, vi_sim *s, double period, int spp, int ledger,
                    double *setup, double *wall)
{
  vi_sim_set_event_callback(s, on_event, c, NULL);
  /* states only for the files that store them: else the exact method
   * keeps each bounce in modes */
  vi_sim_set_event_states(s, c->csv || (c->w && c->store_events));
  if (c->o->progress) vi_sim_set_monitor(s, period, on_monitor, c, NULL);
  vi_sim_set_cancel(s, vi_app_cancel, NULL, NULL);
  if (spp > 0) vi_sim_set_sampling(s, period / spp, on_sample, c, NULL);
  if (ledger) {
    vi_sim_enable_ledger(s, 1);
    vi_sim_set_ledger_callback(s, on_ledger, c, NULL);
  }
  *wall = 0.0;
  double t0 = now();
  int st = vi_sim_setup(s);
  *setup = now() - t0;
  if (st) return st;
  c->wall0 = now();
  vi_app_set_polling(1);
  st = vi_sim_run(s, c->t_end);
  *wall = now() - c->wall0;
  if (c->o->progress) fputc('\n', stderr);
  return st;
}

/* After the run: write errors reported, the HDF5 file's row counts and
 * its completion, the CSV closed (renamed into place; part cleared).  0
 * or 1 with the message printed. */
static int close_outputs(run_ctx *c, const vi_sim *s, int complete, long *rows,
                         char *part)
{
  const app_opts *o = c->o;
  vi_diag d;
  memset(&d, 0, sizeof d);
  if (c->io_err) {
    fprintf(stderr, "vibroimpact: writing output failed: %s\n",
            c->io_err == 1 && c->w ? c->wa->errmsg(c->w)
            : c->csv == stdout     ? "cannot write the standard output"
                                   : "cannot write the impacts CSV (disk full?)");
    return 1;
  }
  static const char *tables[3] = {"impacts", "trajectory", "ledger"};
  for (int k = 0; k < 3 && c->w; k++) rows[k] = c->wa->rows(c->w, tables[k]);
  if (c->w && (c->wa->run_info(c->w, s) || c->wa->finish(c->w, complete))) {
    fprintf(stderr, "vibroimpact: %s\n", c->wa->errmsg(c->w));
    return 1;
  }
  if (c->csv) {
    /* every write, the flush, the sync and the close checked; renamed */
    int to_stdout = c->csv == stdout;
    if (vi_output_close(&c->csv, o->csv_target, o->csv_kind, &d)) {
      fprintf(stderr, "vibroimpact: %s\n", d.message);
      return 1;
    }
    if (to_stdout) c->csv = stdout; /* the summary then goes to stderr */
    part[0] = '\0';
  }
  return 0;
}

/* A run cut short by a signal, or a signal after it finished: the exit
 * status (the message printed); 0 for none. */
static int interrupted(const run_ctx *c, const vi_sim *s, int complete)
{
  if (!complete) {
    double t;
    vi_sim_state(s, &t, NULL, NULL);
    fprintf(stderr, "vibroimpact: interrupted (%s) at t = %g%s\n",
            vi_app_signal == SIGTERM ? "SIGTERM" : "SIGINT", t,
            c->o->out ? "; the output file is valid and marked incomplete" : "");
    return vi_app_interrupt_status();
  }
  /* after the run had finished: the file is whole */
  return vi_app_signal ? vi_app_interrupt_status() : 0;
}

int vi_cmd_run(const app_opts *o)
{
  vi_scene *sc = NULL;
  vi_model *m = NULL;
  vi_sim *s = NULL;
  run_ctx c;
  memset(&c, 0, sizeof c);
  c.o = o;
  char part[VI_APP_PATH + 8] = "", h5part[VI_APP_PATH + 8] = "";
  int rc = vi_app_load(o, &sc, &m), st;
  if (rc) return rc;
  c.n = vi_model_n(m);
  c.t0 = vi_scene_t0(sc);
  c.t_end = vi_scene_t_end(sc);
  /* only what something consumes: the ledger feeds the file and the
   * summary; samples go only into a file */
  int outs = vi_scene_outputs(sc);
  int ledger = (outs & VI_SCENE_OUT_LEDGER) && (o->out || !o->quiet);
  c.store_events = (outs & VI_SCENE_OUT_IMPACTS) != 0;
  int spp = o->out ? vi_scene_samples_per_period(sc) : 0;
  if ((rc = create_sim(sc, m, &s))) goto done;
  /* from here files exist: a signal before the run polls removes them */
  if (o->out) vi_output_part(o->out_target, h5part, (int)sizeof h5part);
  if (o->csv && o->csv_kind == VI_OUTPUT_FILE)
    vi_output_part(o->csv_target, part, (int)sizeof part);
  vi_app_arm_parts(h5part, part);
  if ((o->out && (rc = open_writer(&c, sc, m, outs))) || (o->csv && (rc = open_csv(&c, part))))
    goto done;
  double period = vi_model_forcing_period(m), setup, wall; /* 0: no forcing */
  if (!(period > 0)) period = (c.t_end - c.t0) / 100;
  st = simulate(&c, s, period, spp, ledger, &setup, &wall);
  rc = 1;
  if (st < 0) {
    /* VI_ERR_INVARIANT: a non-finite or penetrating state, said where */
    fprintf(stderr, "vibroimpact: %s: %s\n", vi_strerror(st), vi_sim_errmsg(s));
    goto done;
  }
  long rows[3] = {0, 0, 0};
  if (close_outputs(&c, s, st == VI_OK, rows, part)) goto done;
  if ((rc = interrupted(&c, s, st == VI_OK))) goto done;
  if (!o->quiet)
    summary(c.csv == stdout ? stderr : stdout, o, sc, m, s, &c, period, ledger,
            setup, wall, rows);
  rc = 0;
done:
  if (c.csv && c.csv != stdout) vi_output_discard(&c.csv, o->csv_target, o->csv_kind);
  if (part[0]) remove(part);
  if (c.w) c.wa->abort(&c.w);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
  vi_scene_destroy(&sc);
  return rc;
}
