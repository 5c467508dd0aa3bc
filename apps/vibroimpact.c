/* vibroimpact - command-line front end.
 *
 * With no arguments it runs the embedded default scene, the paper's Fig. 2
 * (Wagg & Bishop 2000): N = 2 chain, m = k = 1, c = 0.1, x_s = 0.1,
 * a = (0.5, 0), Omega = 0.9, r = 0.7, stop on mass 2, from rest, 100 forcing
 * periods.  Exit status: 0 success, 1 run-time error, 2 usage error. */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <gsl/gsl_errno.h>

#include "vibroimpact.h"

static volatile sig_atomic_t interrupted;
static void on_signal(int sig) { (void)sig; interrupted = 1; }

typedef struct opts {
  double rtol, atol, periods;
  int method;
  const char *csv;
  int quiet;
} opts;

static void usage(FILE *f)
{
  fprintf(f,
    "usage: vibroimpact [options]\n"
    "Simulate a vibro-impact system; with no scene, the paper's Fig. 2.\n\n"
    "  --periods P         forcing periods to simulate (default 100)\n"
    "  --rtol R            relative tolerance (default 1e-8)\n"
    "  --atol A            absolute tolerance (default 1e-10)\n"
    "  --method M          adams (default), bdf or exact (closed-form flow)\n"
    "  --impacts-csv FILE  one line per impact, pre-impact state; '-' = stdout\n"
    "  --quiet             no summary\n"
    "  --version           print the version\n"
    "  --help              this text\n\n"
    "Exit status: 0 success, 1 run-time error, 2 usage error.\n");
}

static int parse_double(const char *opt, const char *s, double *out)
{
  char *end;
  errno = 0;
  double v = strtod(s, &end);
  if (errno || end == s || *end || !isfinite(v)) {
    fprintf(stderr, "vibroimpact: %s: '%s' is not a finite number\n", opt, s);
    return 0;
  }
  *out = v;
  return 1;
}

static int parse_args(int argc, char **argv, opts *o)
{
  static const struct option lo[] = {
      {"periods", required_argument, 0, 'p'}, {"rtol", required_argument, 0, 'r'},
      {"atol", required_argument, 0, 'a'},    {"method", required_argument, 0, 'm'},
      {"impacts-csv", required_argument, 0, 'c'}, {"quiet", no_argument, 0, 'q'},
      {"version", no_argument, 0, 'V'},       {"help", no_argument, 0, 'h'},
      {0, 0, 0, 0}};
  int c;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "", lo, NULL)) != -1) {
    switch (c) {
    case 'p':
      if (!parse_double("--periods", optarg, &o->periods)) return 2;
      if (!(o->periods > 0)) {
        fprintf(stderr, "vibroimpact: --periods: %g must be > 0\n", o->periods);
        return 2;
      }
      break;
    case 'r': if (!parse_double("--rtol", optarg, &o->rtol)) return 2; break;
    case 'a': if (!parse_double("--atol", optarg, &o->atol)) return 2; break;
    case 'm':
      if (!strcmp(optarg, "adams")) o->method = VI_METHOD_ADAMS;
      else if (!strcmp(optarg, "bdf")) o->method = VI_METHOD_BDF;
      else if (!strcmp(optarg, "exact")) o->method = VI_METHOD_EXACT;
      else {
        fprintf(stderr, "vibroimpact: --method: '%s' is not adams, bdf or "
                "exact\n", optarg);
        return 2;
      }
      break;
    case 'c': o->csv = optarg; break;
    case 'q': o->quiet = 1; break;
    case 'V': printf("vibroimpact %s (SUNDIALS %s)\n", vi_version_string(),
                     vi_sundials_version()); return -1;
    case 'h': usage(stdout); return -1;
    default:
      fprintf(stderr, "vibroimpact: unknown or incomplete option '%s'\n",
              argv[optind - 1]);
      usage(stderr);
      return 2;
    }
  }
  if (optind < argc) {
    fprintf(stderr, "vibroimpact: unexpected argument '%s' (scene files are "
            "not supported yet)\n", argv[optind]);
    return 2;
  }
  return 0;
}

/* ---- the run -------------------------------------------------------------- */
typedef struct run_ctx {
  FILE *csv;
  int n, csv_err;
  int64_t impacts;
  double t_first, t_last, vn_last;
} run_ctx;

static int on_event(const vi_event *ev, void *user)
{
  run_ctx *c = user;
  if (ev->kind != VI_EVENT_IMPACT) return 0;
  if (c->impacts == 0) c->t_first = ev->t;
  c->t_last = ev->t;
  c->vn_last = ev->vn;
  if (c->csv) {
    if (fprintf(c->csv, "%lld,%.17g,%.17g", (long long)c->impacts, ev->t,
                ev->vn) < 0)
      c->csv_err = 1;
    for (int i = 0; i < ev->n; i++) fprintf(c->csv, ",%.17g", ev->x[i]);
    for (int i = 0; i < ev->n; i++) fprintf(c->csv, ",%.17g", ev->v_minus[i]);
    if (fputc('\n', c->csv) == EOF) c->csv_err = 1;
  }
  c->impacts++;
  return c->csv_err;
}

static int on_monitor(const vi_progress *p, void *user)
{
  (void)p;
  (void)user;
  return interrupted;
}

static vi_model *fig2_model(char *err, size_t len)
{
  const double mass[2] = {1, 1}, k[2] = {1, 1}, c[2] = {0.1, 0.1};
  const double a[2] = {0.5, 0.0}, w[2] = {0.0, 1.0};
  double M[4], C[4], K[4];
  vi_model *m = NULL;
  int st = vi_build_chain(2, mass, k, c, M, C, K, 2);
  if (!st) st = vi_model_create(2, &m);
  if (!st) st = vi_model_set_mass(m, M, 2);
  if (!st) st = vi_model_set_damping(m, C, 2);
  if (!st) st = vi_model_set_stiffness(m, K, 2);
  if (!st) st = vi_model_set_forcing(m, 0.9, a, NULL, NULL);
  if (!st) st = vi_model_set_stop(m, w, 0.1, 0.7);
  if (!st) st = vi_model_setup(m);
  if (st) {
    snprintf(err, len, "%s: %s", vi_strerror(st), m ? vi_model_errmsg(m) : "");
    vi_model_destroy(&m);
  }
  return m;
}

static double now(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

int main(int argc, char **argv)
{
  gsl_set_error_handler_off();
  if (vi_version_number() != VI_VERSION_NUMBER) {
    fprintf(stderr, "vibroimpact: header %s and library %s differ\n",
            VI_VERSION_STRING, vi_version_string());
    return 1;
  }
  opts o = {1e-8, 1e-10, 100.0, VI_METHOD_ADAMS, NULL, 0};
  int pa = parse_args(argc, argv, &o);
  if (pa) return pa < 0 ? 0 : pa;

  char err[600] = "";
  char part[4096] = "";
  run_ctx ctx = {0};
  vi_sim *s = NULL;
  int rc = 1, st;
  vi_model *m = fig2_model(err, sizeof err);
  if (!m) {
    fprintf(stderr, "vibroimpact: default scene: %s\n", err);
    return 1;
  }
  if ((st = vi_sim_create(m, &s)) || (st = vi_sim_set_method(s, o.method)) ||
      (st = vi_sim_set_tolerances(s, o.rtol, o.atol))) {
    int usage_err = st == VI_ERR_TOLERANCE;
    fprintf(stderr, "vibroimpact: %s: %s\n", vi_strerror(st),
            s ? vi_sim_errmsg(s) : "");
    vi_sim_destroy(&s);
    vi_model_destroy(&m);
    return usage_err ? 2 : 1;
  }
  if (o.csv) {
    if (!strcmp(o.csv, "-")) {
      ctx.csv = stdout;
    } else {
      /* write beside the target and rename on success: never a partial file */
      snprintf(part, sizeof part, "%s.part", o.csv);
      ctx.csv = fopen(part, "w");
      if (!ctx.csv) {
        fprintf(stderr, "vibroimpact: cannot write '%s': %s\n", part,
                strerror(errno));
        goto done;
      }
    }
    fprintf(ctx.csv, "k,t,vn");
    for (int i = 1; i <= 2; i++) fprintf(ctx.csv, ",x_%d", i);
    for (int i = 1; i <= 2; i++) fprintf(ctx.csv, ",v_%d", i);
    fputc('\n', ctx.csv);
  }
  signal(SIGINT, on_signal);
  signal(SIGTERM, on_signal);
  vi_sim_set_event_callback(s, on_event, &ctx);
  vi_sim_set_monitor(s, on_monitor, NULL, 2.0 * M_PI / 0.9);
  double t_end = o.periods * 2.0 * M_PI / 0.9, t0 = now();
  st = vi_sim_run(s, t_end);
  double wall = now() - t0;
  if (st < 0) {
    fprintf(stderr, "vibroimpact: %s: %s\n", vi_strerror(st), vi_sim_errmsg(s));
    goto done;
  }
  if (ctx.csv_err) {
    fprintf(stderr, "vibroimpact: writing '%s' failed\n", o.csv);
    goto done;
  }
  if (st == VI_STOPPED) {
    fprintf(stderr, "vibroimpact: interrupted\n");
    goto done;
  }
  if (ctx.csv && ctx.csv != stdout) {
    int bad = ferror(ctx.csv) | fclose(ctx.csv);
    ctx.csv = NULL;
    if (bad || rename(part, o.csv)) {
      fprintf(stderr, "vibroimpact: cannot write '%s': %s\n", o.csv,
              strerror(errno));
      goto done;
    }
    part[0] = '\0';
  }
  if (!o.quiet) {
    FILE *f = (ctx.csv == stdout) ? stderr : stdout;
    const char *mn[] = {"adams", "bdf", "exact"};
    fprintf(f, "vibroimpact %s: Wagg & Bishop (2000) Fig. 2 scene\n",
            vi_version_string());
    fprintf(f, "  model     N = 2 chain, m = k = 1, c = 0.1, x_s = 0.1, r = 0.7, "
            "Omega = 0.9\n");
    fprintf(f, "  modes     omega = %.6f, %.6f\n", vi_model_omega(m)[0],
            vi_model_omega(m)[1]);
    fprintf(f, "  run       %g periods (t = %.6g), method %s, rtol %g, atol %g\n",
            o.periods, t_end, mn[o.method], o.rtol, o.atol);
    fprintf(f, "  impacts   %lld (%.4f per period)", (long long)ctx.impacts,
            ctx.impacts / o.periods);
    if (ctx.impacts)
      fprintf(f, "; last at t = %.10g with v_n = %.10g, phase %.6f rad",
              ctx.t_last, ctx.vn_last, fmod(0.9 * ctx.t_last, 2.0 * M_PI));
    fprintf(f, "\n  cost      %lld steps, %lld RHS evaluations, %.3f ms\n",
            (long long)vi_sim_get_stat(s, VI_STAT_STEPS),
            (long long)vi_sim_get_stat(s, VI_STAT_RHS_EVALS), 1e3 * wall);
  }
  rc = 0;
done:
  if (ctx.csv && ctx.csv != stdout) fclose(ctx.csv);
  if (part[0]) remove(part);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
  return rc;
}
