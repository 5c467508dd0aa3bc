/* vi_cmd_sweep.c - `vibroimpact sweep`: brute-force bifurcation diagrams,
 * and `vibroimpact basins`: basins of attraction (the same program with
 * --basins first: every cell from its own initial state).
 *
 *   vibroimpact sweep [SCENE.yaml] --param KEY --from A --to B --steps K
 *       [--down | --both] [--transient P] [--record P] [--json] [-o OUT.h5]
 *       [--param2 KEY --from2 A --to2 B --steps2 K2] [--threads T]
 *       [--chunks C] [--tol TOL] [--nmax N] [--method M] [--set KEY=VALUE]...
 *   vibroimpact basins [SCENE.yaml] --param KEY --from A --to B --steps K
 *       --param2 KEY2 --from2 C --to2 D --steps2 K2 [--transient P]
 *       [--record R] [--json] [-o OUT.h5] [--threads T] ...
 */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vibroimpact.h"
#include "vibroimpact/vi_output.h"
#include "vi_diagram.h"
#ifdef VI_HAVE_MPI
#include <mpi.h>
#endif
#ifdef _OPENMP
#include <omp.h>
#endif

static volatile sig_atomic_t interrupted;
static void on_signal(int sig) { interrupted = sig; } /* 128 + sig on exit */

static void usage(FILE *f, int basins)
{
  if (basins) {
    fprintf(f,
      "usage: vibroimpact basins [SCENE.yaml] --param KEY --from A --to B --steps K\n"
      "         --param2 KEY2 --from2 C --to2 D --steps2 K2 [options]\n"
      "Basins of attraction: every cell of the K x K2 grid of the two keys (initial\n"
      "conditions such as initial.x[2] and initial.v[2], or any two parameters) is\n"
      "simulated from its own initial state (no warm start) for P transient and R\n"
      "recorded forcing periods, classified P(n,m), and its attractor identified\n"
      "across cells (same orbit, same id; -1: none found).\n\n"
      "  --transient P, --record R, --threads T, --tol TOL, --nmax N, --method M,\n"
      "  --set KEY=VALUE, --json, -o FILE, --max-memory B, --max-depth D, --quiet\n"
      "                        as for sweep (--help there)\n"
      "Plot: /usr/bin/python3 share/plot_basins.py OUT.h5\n");
    return;
  }
  fprintf(f,
    "usage: vibroimpact sweep [SCENE.yaml] --param KEY --from A --to B --steps K [options]\n"
    "Brute-force bifurcation diagram: KEY (a parameter: forcing.omega, forcing.a[i],\n"
    "stop.xs, stop.r, stops[k].xs, model.rayleigh.alpha, initial.x[i], ...) takes K\n"
    "values from A to B, changed on the model built once; each value starts from\n"
    "the state the previous one ended in (warm start), runs P transient and R recorded\n"
    "forcing periods, and is classified P(n,m).  Structural keys of a chain scene:\n"
    "model.chain.m, model.chain.k, model.chain.c scale its mass, stiffness and damping\n"
    "matrices (the model's mass.scale, stiffness.scale, damping.scale; modes redone).\n\n"
    "  --down | --both       sweep B -> A, or both ways (hysteresis)\n"
    "  --transient P         transient forcing periods per value (default 500)\n"
    "  --record R            recorded forcing periods per value (default 100)\n"
    "  --param2 KEY --from2 A --to2 B --steps2 K2   a two-parameter map: one sweep\n"
    "                        of KEY per value of the second key\n"
    "  --threads T           OpenMP threads (default: all cores)\n"
    "  --chunks C            split each line into C chunks run in parallel; a serial\n"
    "                        chain through the chunks' first values seeds each with\n"
    "                        its warm state.  Default: a chunk per 16 values (per\n"
    "                        sqrt(K) when fewer than 256), the same for any thread\n"
    "                        count; 1 (each line in order, warm start exact) with\n"
    "                        --both or 16 lines or more\n"
    "  --tol TOL             classification tolerance, relative (default 1e-6)\n"
    "  --nmax N              longest period looked for (default 32)\n"
    "  --method M            adams, bdf, exact, auto, erk (sets run.method)\n"
    "  --orbits[=K]          also every P(1,1) orbit at each value, stable or not,\n"
    "                        by a scan of K impact phases (default 360; closed-form\n"
    "                        flow needed): the diagram's unstable branches\n"
    "  --lyapunov            also the largest Lyapunov exponent of each value (over\n"
    "                        R more periods from its end state; > 0: chaos)\n"
    "  --set KEY=VALUE       override a scene key (repeatable)\n"
    "  --json                print the diagram as one JSON object\n"
    "  -o, --output FILE     write the diagram to HDF5 (share/doc/sweep-layout.md)\n"
    "  --max-memory B        memory the sweep may plan (default: the machine's\n"
    "                        MemAvailable); B may end in K, M or G\n"
    "  --max-depth D         deepest YAML nesting of the scene and the --set\n"
    "                        values (default 32)\n"
    "  --quiet               no table\n");
}

/* cmd: the command the user typed (sweep or basins), for the messages. */
static int num(const char *cmd, const char *opt, const char *s, double *out)
{
  char *end;
  if (!s) return 0;
  errno = 0;
  double v = strtod(s, &end);
  if (errno || end == s || *end || !isfinite(v)) {
    fprintf(stderr, "vibroimpact: %s: %s: '%s' is %s\n", cmd, opt, s,
            errno == ERANGE && end != s && !*end
                ? "beyond double precision's range (it under- or overflows)"
                : "not a finite number");
    return 0;
  }
  *out = v;
  return 1;
}

static int inum(const char *cmd, const char *opt, const char *s, int lo, int *out)
{
  double v;
  if (!num(cmd, opt, s, &v)) return 0;
  if (v != floor(v) || v < lo || v > 1e8) {
    fprintf(stderr, "vibroimpact: %s: %s must be an integer in [%d, "
            "100000000] (got '%s')\n", cmd, opt, lo, s);
    return 0;
  }
  *out = (int)v;
  return 1;
}

/* --max-memory B: bytes, or with K, M, G. */
static int bytes(const char *cmd, const char *s, double *out)
{
  char *end;
  if (!s) return 0;
  errno = 0;
  double v = strtod(s, &end), mul = 1;
  if (end != s && *end && !end[1] && strchr("kKmMgG", *end)) {
    mul = *end == 'k' || *end == 'K' ? 1024.0 : *end == 'm' || *end == 'M'
          ? 1048576.0 : 1073741824.0;
    end++;
  }
  if (errno || end == s || *end || !isfinite(v) || !(v > 0)) {
    fprintf(stderr, "vibroimpact: %s: --max-memory: '%s' is not a size > 0 "
            "(bytes, or with K, M, G)\n", cmd, s);
    return 0;
  }
  *out = v * mul;
  return 1;
}

static void table(const vi_diagram *sw)
{
  const vi_diagram_spec *sp = &sw->spec;
  int K = sp->steps;
  char split[160];
  vi_diagram_split(sw, split, sizeof split);
  printf("sweep of %s over %d values, %d transient + %d recorded periods per "
         "value, %d line%s (%s), %.3f s\n", sp->key, K, sp->transient, sp->record,
         sw->nlines, sw->nlines > 1 ? "s" : "", split, sw->wall);
  for (int l = 0; l < sw->nlines; l++) {
    const vi_diagram_line *ln = &sw->lines[l];
    printf("%s%s", ln->dir > 0 ? "up" : "down", sp->key2 ? "" : "\n");
    if (sp->key2) printf(", %s = %.10g\n", sp->key2, sw->param2[ln->row]);
    printf("  %14s  %-9s  %s\n", sp->key, "motion", "v_n of one period (or the last recorded)");
    for (int p = 0; p < K; p++) {
      int k = ln->dir > 0 ? p : K - 1 - p;
      const vi_diagram_point *pt = &ln->pt[k];
      char cls[32];
      if (pt->failed) snprintf(cls, sizeof cls, "failed");
      else if (pt->n) snprintf(cls, sizeof cls, "P(%d,%d)", pt->n, pt->m);
      else snprintf(cls, sizeof cls, "-");
      printf("  %14.8g  %-9s ", sw->param[k], cls);
      int64_t a = pt->n ? pt->nimp - pt->m : (pt->nimp > 4 ? pt->nimp - 4 : 0);
      for (int64_t j = a; j < pt->nimp && j < a + 6; j++) printf(" %.6g", pt->vn[j]);
      if (pt->nimp - a > 6) printf(" ...");
      printf("\n");
    }
  }
}

/* The command line, into sp and the rest; 0 to go on, else the exit
 * status (2: usage, 0: --help). */
typedef struct args {
  vi_diagram_spec sp;
  const char *out, *scene, **sets;
  int nsets, json, quiet, basins, chunks_set;
  double max_memory; /* --max-memory bytes; 0: what the machine has */
  char method_set[64];
  char target[4096]; /* the output's final path (vi_output_check) */
} args;

static int parse(int argc, char **argv, args *a)
{
  static const struct option lo[] = {
      {"param", required_argument, 0, 'k'},   {"from", required_argument, 0, 'f'},
      {"to", required_argument, 0, 't'},      {"steps", required_argument, 0, 's'},
      {"param2", required_argument, 0, 'K'},  {"from2", required_argument, 0, 'F'},
      {"to2", required_argument, 0, 'T'},     {"steps2", required_argument, 0, 'S'},
      {"down", no_argument, 0, 'd'},          {"both", no_argument, 0, 'b'},
      {"transient", required_argument, 0, 'p'}, {"record", required_argument, 0, 'r'},
      {"threads", required_argument, 0, 'j'}, {"chunks", required_argument, 0, 'c'},
      {"tol", required_argument, 0, 'e'},     {"nmax", required_argument, 0, 'n'},
      {"method", required_argument, 0, 'm'},  {"set", required_argument, 0, 'x'},
      {"json", no_argument, 0, 'J'},          {"output", required_argument, 0, 'o'},
      {"quiet", no_argument, 0, 'q'},         {"help", no_argument, 0, 'h'},
      {"orbits", optional_argument, 0, 'O'},  {"basins", no_argument, 0, 'B'},
      {"lyapunov", no_argument, 0, 'L'},     {"max-memory", required_argument, 0, 'M'},
      {"max-depth", required_argument, 0, 'D'}, {0, 0, 0, 0}};
  vi_diagram_spec *sp = &a->sp;
  int c;
  optind = 1;
  opterr = 0;
  /* the program runs basins as sweep with --basins first */
  const char *cmd = argc > 1 && !strcmp(argv[1], "--basins") ? "basins" : "sweep";
  while ((c = getopt_long(argc, argv, "o:", lo, NULL)) != -1) {
    int ok = 1;
    switch (c) {
    case 'k': sp->key = optarg; break;
    case 'f': ok = num(cmd, "--from", optarg, &sp->from); break;
    case 't': ok = num(cmd, "--to", optarg, &sp->to); break;
    case 's': ok = inum(cmd, "--steps", optarg, 1, &sp->steps); break;
    case 'K': sp->key2 = optarg; break;
    case 'F': ok = num(cmd, "--from2", optarg, &sp->from2); break;
    case 'T': ok = num(cmd, "--to2", optarg, &sp->to2); break;
    case 'S': ok = inum(cmd, "--steps2", optarg, 1, &sp->steps2); break;
    case 'd': sp->dirs = 2; break;
    case 'b': sp->dirs = 3; break;
    case 'p': ok = inum(cmd, "--transient", optarg, 0, &sp->transient); break;
    case 'r': ok = inum(cmd, "--record", optarg, 2, &sp->record); break;
    case 'j': ok = inum(cmd, "--threads", optarg, 1, &sp->threads); break;
    case 'c': ok = inum(cmd, "--chunks", optarg, 1, &sp->chunks); a->chunks_set = 1; break;
    case 'e': ok = num(cmd, "--tol", optarg, &sp->tol) && sp->tol > 0; break;
    case 'n': ok = inum(cmd, "--nmax", optarg, 1, &sp->nmax); break;
    case 'm':
      ok = vi_method_from_name(optarg) >= 0;
      if (!ok) fprintf(stderr, "vibroimpact: %s: --method: '%s' is not adams, "
                       "bdf, exact, auto or erk\n", cmd, optarg);
      snprintf(a->method_set, sizeof a->method_set, "run.method=%s", optarg);
      a->sets[a->nsets++] = a->method_set;
      break;
    case 'x': a->sets[a->nsets++] = optarg; break;
    case 'J': a->json = 1; break;
    case 'o': a->out = optarg; break;
    case 'q': a->quiet = 1; break;
    case 'O':
      sp->orbits = 360;
      if (optarg) ok = inum(cmd, "--orbits", optarg, 8, &sp->orbits);
      break;
    case 'B': a->basins = 1; break;
    case 'L': sp->lyapunov = 1; break;
    case 'M': ok = bytes(cmd, optarg, &a->max_memory); break;
    case 'D': ok = inum(cmd, "--max-depth", optarg, 1, &sp->max_depth); break;
    case 'h': usage(stdout, a->basins); return -1;
    default:
      fprintf(stderr, "vibroimpact: %s: unknown or incomplete option '%s'\n", cmd,
              argv[optind - 1]);
      usage(stderr, a->basins);
      return 2;
    }
    if (!ok) {
      if (c == 'e') fprintf(stderr, "vibroimpact: %s: --tol must be > 0\n", cmd);
      return 2;
    }
  }
  if (optind < argc) a->scene = argv[optind++];
  if (optind < argc) {
    fprintf(stderr, "vibroimpact: %s: unexpected argument '%s'\n", cmd, argv[optind]);
    return 2;
  }
  return 0;
}

/* What the arguments must hold together; 0 or the exit status 2. */
static int check(args *a)
{
  vi_diagram_spec *sp = &a->sp;
  const char *cmd = a->basins ? "basins" : "sweep";
  if (!sp->key || isnan(sp->from) || isnan(sp->to) || !sp->steps) {
    fprintf(stderr, "vibroimpact: %s needs --param KEY --from A --to B --steps K\n", cmd);
    return 2;
  }
  if ((sp->key2 || a->basins) && (!sp->key2 || isnan(sp->from2) || isnan(sp->to2) ||
                                  !sp->steps2)) {
    fprintf(stderr, "vibroimpact: %s: --param2 needs --from2, --to2 and --steps2\n", cmd);
    return 2;
  }
  if (sp->key2 && vi_app_same_key(sp->key, sp->key2)) { /* one axis was ignored */
    fprintf(stderr, "vibroimpact: %s: --param and --param2 both name %s: a "
            "map needs two different parameters\n", cmd, sp->key2);
    return 2;
  }
  if (a->basins && (sp->dirs != 1 || sp->orbits)) {
    fprintf(stderr, "vibroimpact: basins: --down, --both and --orbits are for sweep\n");
    return 2;
  }
  if (!sp->key2) sp->steps2 = 1;
  if (a->basins) {
    /* cells are independent, so any split gives the same map: pieces of
     * about 8 cells, one study set up for them (a study per cell was 2 to
     * 3 % of a 2-dof map's CPU on one thread), still thousands of pieces
     * for the threads on a 200 x 200 map */
    sp->cold = 1;
    if (!a->chunks_set) sp->chunks = (sp->steps + 7) / 8;
  } else if (!a->chunks_set) {
    sp->chunks = vi_diagram_default_chunks(sp);
  }
  /* the one output path (vi_output.h): checked before the sweep, the
   * links followed, devices, FIFOs, directories, a planted .part link and
   * the scene itself refused */
  if (a->out) {
    vi_diag od;
    int ost = vi_output_check(a->out, VI_OUTPUT_REGULAR, a->scene, a->target,
                              (int)sizeof a->target, NULL, &od);
    if (ost) {
      fprintf(stderr, "vibroimpact: %s: %s\n", cmd, od.message);
      return ost == VI_ERR_ARG ? 2 : 1;
    }
    a->out = a->target;
  }
  return 0;
}

/* MPI when started by mpirun (a plain run never touches MPI): ranks on one
 * machine share its cores, so without --threads each takes its share. */
static int mpi_start(vi_diagram_spec *sp)
{
  int mpi = 0;
#ifdef VI_HAVE_MPI
  mpi = getenv("OMPI_COMM_WORLD_SIZE") != NULL;
  if (mpi) MPI_Init(NULL, NULL);
  const char *local = getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
  int nlocal = local ? (int)strtol(local, NULL, 10) : 0;
  if (mpi && sp->threads <= 0 && nlocal > 1) {
#ifdef _OPENMP
    sp->threads = omp_get_num_procs() / nlocal;
#endif
    if (sp->threads < 1) sp->threads = 1;
  }
#else
  (void)sp;
#endif
  return mpi;
}

static int mpi_rank(int mpi)
{
  int rank = 0;
#ifdef VI_HAVE_MPI
  if (mpi) MPI_Comm_rank(MPI_COMM_WORLD, &rank);
#else
  (void)mpi;
#endif
  return rank;
}

/* Every rank leaves with rank 0's status. */
static int mpi_finish(int mpi, int rc)
{
#ifdef VI_HAVE_MPI
  if (mpi) {
    MPI_Bcast(&rc, 1, MPI_INT, 0, MPI_COMM_WORLD);
    MPI_Finalize();
  }
#else
  (void)mpi;
#endif
  return rc;
}

/* The values (cells) that failed: one line, however many (a 40 x 40 map
 * half beyond the stop printed 680): the count, the first message, what
 * follows a failure and where every message is. */
static void warn_failed(const args *a, const vi_diagram *sw)
{
  const char *cmd = a->basins ? "basins" : "sweep", *first = NULL;
  long long nfail = 0, total = (long long)sw->nlines * a->sp.steps;
  for (int l = 0; l < sw->nlines; l++)
    for (int k = 0; k < a->sp.steps; k++)
      if (sw->lines[l].pt[k].failed && !nfail++)
        first = sw->lines[l].pt[k].error ? sw->lines[l].pt[k].error : "";
  if (!nfail) return;
  /* a basin's cells never warm-start; a diagram's value after a failed
   * one starts from the scene's initial state */
  const char *unit = a->basins ? "cell" : "value",
             *then = a->basins ? "" : "; the next value starts from the scene's "
                                      "initial state";
  if (nfail == 1) {
    fprintf(stderr, "vibroimpact: %s: warning: %s (marked failed%s)\n", cmd,
            first, then);
    return;
  }
  char where[4200];
  if (a->json)
    snprintf(where, sizeof where, "every message in the JSON's \"failed\"");
  else if (a->out)
    snprintf(where, sizeof where, "each marked n = -1 in %s; --json lists "
             "every message", a->out);
  else
    snprintf(where, sizeof where, "--json lists every message");
  fprintf(stderr, "vibroimpact: %s: warning: %lld of %lld %ss failed and are "
          "marked so%s (%s); the first: %s\n", cmd, nfail, total, unit,
          a->basins ? "" : "; the value after each starts from the scene's "
                           "initial state", where, first);
}

/* Rank 0: warnings, then the file, JSON or table.  The exit status. */
static int report(const args *a, vi_diagram *sw)
{
  char err[2048];
  const char *cmd = a->basins ? "basins" : "sweep";
  warn_failed(a, sw);
  if (a->basins && vi_basins_identify(sw)) {
    fprintf(stderr, "vibroimpact: basins: out of memory\n");
    return 1;
  }
  if (a->out && vi_diagram_write_h5(sw, a->out, err, sizeof err)) {
    fprintf(stderr, "vibroimpact: %s: %s\n", cmd, err);
    return 1;
  }
  if (sw->incomplete)
    fprintf(stderr, "vibroimpact: %s: interrupted (%s) after %lld of %lld points%s\n",
            cmd, interrupted == SIGTERM ? "SIGTERM" : "SIGINT",
            (long long)sw->points_done, (long long)sw->nlines * a->sp.steps,
            a->out ? "; the file is marked incomplete" : "");
  if (a->json && a->basins) vi_basins_print_json(sw, stdout);
  else if (a->json) vi_diagram_print_json(sw, stdout);
  else if (!a->quiet) {
    if (a->basins) vi_basins_table(sw, stdout);
    else table(sw);
    if (a->out) printf("%s written to %s\n", a->basins ? "basins" : "diagram", a->out);
  }
  vi_diag od; /* a lost table or JSON is an error (> /dev/full) */
  FILE *so = stdout;
  if (vi_output_close(&so, "-", VI_OUTPUT_STDOUT, &od)) {
    fprintf(stderr, "vibroimpact: %s: %s\n", cmd, od.message);
    return 1;
  }
  return 0;
}

int vi_cmd_sweep_main(int argc, char **argv)
{
  args a;
  memset(&a, 0, sizeof a);
  vi_diagram_spec sp0 = {NULL, NAN, NAN, 0, NULL, NAN, NAN, 1, 1, 500, 100, 1, 0,
                       1e-6, 32, 0, 0, 0, 0};
  a.sp = sp0;
  a.sets = calloc((size_t)argc + 2, sizeof *a.sets);
  if (!a.sets) return 1;
  /* the handler first: check() creates and removes OUT.part (the output
   * check), and a signal then must not leave it behind */
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sigaction(SIGINT, &sa, NULL);
  sigaction(SIGTERM, &sa, NULL);
  int rc = parse(argc, argv, &a);
  if (!rc) rc = check(&a);
  char err[2048];
  char *text = rc ? NULL : vi_app_read_text(a.scene, err, sizeof err);
  if (!rc && !text) {
    fprintf(stderr, "vibroimpact: %s\n", err);
    rc = 1;
  }
  if (rc || interrupted) {
    free(a.sets);
    free(text);
    if (interrupted) { /* nothing written yet: said so */
      fprintf(stderr, "vibroimpact: %s: interrupted (%s) before the first point; no file "
              "written\n", a.basins ? "basins" : "sweep",
              interrupted == SIGTERM ? "SIGTERM" : "SIGINT");
      return 128 + (int)interrupted;
    }
    if (rc < 0 && (fflush(stdout) != 0 || ferror(stdout))) { /* --help lost */
      fprintf(stderr, "vibroimpact: %s: cannot write the standard output: "
              "%s\n", a.basins ? "basins" : "sweep", strerror(errno));
      return 1;
    }
    return rc < 0 ? 0 : rc;
  }
  vi_diagram *sw = NULL;
  int mpi = mpi_start(&a.sp);
  rc = vi_diagram_run_limited(text, a.scene ? a.scene : "<default scene: fig2>",
                              a.sets, a.nsets, &a.sp, a.max_memory, a.out != NULL,
                              &interrupted, &sw, err, sizeof err);
  free(text);
  if (rc && rc != 3 && !mpi_rank(mpi)) /* once */
    fprintf(stderr, "vibroimpact: %s: %s\n", a.basins ? "basins" : "sweep", err);
  /* rank 0 reports and writes, an interrupted sweep's points too */
  if ((!rc || rc == 3) && !sw->rank) rc = report(&a, sw);
  vi_diagram_free(&sw);
  free(a.sets);
  if (interrupted) rc = 128 + (int)interrupted; /* 130 SIGINT, 143 SIGTERM */
  return mpi_finish(mpi, rc);
}
