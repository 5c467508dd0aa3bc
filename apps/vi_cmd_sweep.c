/* vi_cmd_sweep.c - `vibroimpact sweep`: brute-force bifurcation diagrams.
 *
 *   vibroimpact sweep [SCENE.yaml] --param KEY --from A --to B --steps K
 *       [--down | --both] [--transient P] [--record P] [--json] [-o OUT.h5]
 *       [--param2 KEY --from2 A --to2 B --steps2 K2] [--threads T]
 *       [--chunks C] [--tol TOL] [--nmax N] [--method M] [--set KEY=VALUE]...
 */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vibroimpact.h"
#include "vi_sweep.h"
#ifdef VI_HAVE_MPI
#include <mpi.h>
#endif
#ifdef _OPENMP
#include <omp.h>
#endif

static volatile sig_atomic_t interrupted;
static void on_signal(int sig) { (void)sig; interrupted = 1; }

static void usage(FILE *f)
{
  fprintf(f,
    "usage: vibroimpact sweep [SCENE.yaml] --param KEY --from A --to B --steps K [options]\n"
    "Brute-force bifurcation diagram: KEY (any numeric scene key, e.g. forcing.omega,\n"
    "stop.xs, stop.r, forcing.a[1]) takes K values from A to B; each value starts from\n"
    "the state the previous one ended in (warm start), runs P transient and R recorded\n"
    "forcing periods, and is classified P(n,m).\n\n"
    "  --down | --both       sweep B -> A, or both ways (hysteresis)\n"
    "  --transient P         transient forcing periods per value (default 500)\n"
    "  --record R            recorded forcing periods per value (default 100)\n"
    "  --param2 KEY --from2 A --to2 B --steps2 K2   a two-parameter map: one sweep\n"
    "                        of KEY per value of the second key\n"
    "  --threads T           OpenMP threads (default: all cores)\n"
    "  --chunks C            split each sweep into C pieces run in parallel, each\n"
    "                        starting from the scene's initial state (default 1)\n"
    "  --tol TOL             classification tolerance, relative (default 1e-6)\n"
    "  --nmax N              longest period looked for (default 32)\n"
    "  --method M            adams, bdf, exact, auto, erk (sets run.method)\n"
    "  --orbits[=K]          also every P(1,1) orbit at each value, stable or not,\n"
    "                        by a scan of K impact phases (default 360; closed-form\n"
    "                        flow needed): the diagram's unstable branches\n"
    "  --set KEY=VALUE       override a scene key (repeatable)\n"
    "  --json                print the diagram as one JSON object\n"
    "  -o, --output FILE     write the diagram to HDF5 (share/doc/sweep-layout.md)\n"
    "  --quiet               no table\n");
}

static int num(const char *opt, const char *s, double *out)
{
  char *end;
  if (!s) return 0;
  errno = 0;
  double v = strtod(s, &end);
  if (errno || end == s || *end || !isfinite(v)) {
    fprintf(stderr, "vibroimpact: sweep: %s: '%s' is not a finite number\n", opt, s);
    return 0;
  }
  *out = v;
  return 1;
}

static int inum(const char *opt, const char *s, int lo, int *out)
{
  double v;
  if (!num(opt, s, &v)) return 0;
  if (v != floor(v) || v < lo || v > 1e8) {
    fprintf(stderr, "vibroimpact: sweep: %s must be an integer >= %d (got '%s')\n",
            opt, lo, s);
    return 0;
  }
  *out = (int)v;
  return 1;
}

static void table(const vi_diagram *sw)
{
  const vi_sweep_spec *sp = &sw->spec;
  int K = sp->steps;
  printf("sweep of %s over %d values, %d transient + %d recorded periods per "
         "value, %d line%s, %.3f s\n", sp->key, K, sp->transient, sp->record,
         sw->nlines, sw->nlines > 1 ? "s" : "", sw->wall);
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

int vi_cmd_sweep_main(int argc, char **argv)
{
  vi_sweep_spec sp = {NULL, NAN, NAN, 0, NULL, NAN, NAN, 1, 1, 500, 100, 1, 0, 1e-6, 32, 0, 0};
  const char *out = NULL, *scene = NULL;
  const char **sets = calloc((size_t)argc + 2, sizeof *sets);
  char method_set[64];
  int nsets = 0, json = 0, quiet = 0, c, rc = 2;
  if (!sets) return 1;
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
      {"orbits", optional_argument, 0, 'O'},
      {0, 0, 0, 0}};
  optind = 1;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "o:", lo, NULL)) != -1) {
    switch (c) {
    case 'k': sp.key = optarg; break;
    case 'f': if (!num("--from", optarg, &sp.from)) goto done; break;
    case 't': if (!num("--to", optarg, &sp.to)) goto done; break;
    case 's': if (!inum("--steps", optarg, 1, &sp.steps)) goto done; break;
    case 'K': sp.key2 = optarg; break;
    case 'F': if (!num("--from2", optarg, &sp.from2)) goto done; break;
    case 'T': if (!num("--to2", optarg, &sp.to2)) goto done; break;
    case 'S': if (!inum("--steps2", optarg, 1, &sp.steps2)) goto done; break;
    case 'd': sp.dirs = 2; break;
    case 'b': sp.dirs = 3; break;
    case 'p': if (!inum("--transient", optarg, 0, &sp.transient)) goto done; break;
    case 'r': if (!inum("--record", optarg, 2, &sp.record)) goto done; break;
    case 'j': if (!inum("--threads", optarg, 1, &sp.threads)) goto done; break;
    case 'c': if (!inum("--chunks", optarg, 1, &sp.chunks)) goto done; break;
    case 'e':
      if (!num("--tol", optarg, &sp.tol)) goto done;
      if (!(sp.tol > 0)) { fprintf(stderr, "vibroimpact: sweep: --tol must be > 0\n"); goto done; }
      break;
    case 'n': if (!inum("--nmax", optarg, 1, &sp.nmax)) goto done; break;
    case 'm':
      if (vi_method_from_name(optarg) < 0) {
        fprintf(stderr, "vibroimpact: sweep: --method: '%s' is not adams, bdf, "
                "exact, auto or erk\n", optarg);
        goto done;
      }
      snprintf(method_set, sizeof method_set, "run.method=%s", optarg);
      sets[nsets++] = method_set;
      break;
    case 'x': sets[nsets++] = optarg; break;
    case 'J': json = 1; break;
    case 'o': out = optarg; break;
    case 'q': quiet = 1; break;
    case 'O':
      sp.orbits = 360;
      if (optarg && !inum("--orbits", optarg, 8, &sp.orbits)) goto done;
      break;
    case 'h': usage(stdout); rc = 0; goto done;
    default:
      fprintf(stderr, "vibroimpact: sweep: unknown or incomplete option '%s'\n",
              argv[optind - 1]);
      usage(stderr);
      goto done;
    }
  }
  if (optind < argc) scene = argv[optind++];
  if (optind < argc) {
    fprintf(stderr, "vibroimpact: sweep: unexpected argument '%s'\n", argv[optind]);
    goto done;
  }
  if (!sp.key || isnan(sp.from) || isnan(sp.to) || !sp.steps) {
    fprintf(stderr, "vibroimpact: sweep needs --param KEY --from A --to B --steps K\n");
    goto done;
  }
  if (sp.key2 && (isnan(sp.from2) || isnan(sp.to2))) {
    fprintf(stderr, "vibroimpact: sweep: --param2 needs --from2, --to2 and --steps2\n");
    goto done;
  }
  if (!sp.key2) sp.steps2 = 1;
  char err[2048];
  if (out) { /* a path we cannot write fails now, not after the sweep */
    char part[4096];
    snprintf(part, sizeof part, "%s.part", out);
    FILE *f = fopen(part, "wb");
    if (!f) {
      fprintf(stderr, "vibroimpact: sweep: cannot write '%s': %s\n", part, strerror(errno));
      rc = 1;
      goto done;
    }
    fclose(f);
    remove(part);
  }
  char *text = vi_sweep_read_text(scene, err, sizeof err);
  if (!text) {
    fprintf(stderr, "vibroimpact: %s\n", err);
    rc = 1;
    goto done;
  }
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sigaction(SIGINT, &sa, NULL);
  sigaction(SIGTERM, &sa, NULL);
  vi_diagram *sw = NULL;
#ifdef VI_HAVE_MPI
  /* only when started by mpirun: a plain run never touches MPI */
  int mpi = getenv("OMPI_COMM_WORLD_SIZE") != NULL;
  if (mpi) MPI_Init(NULL, NULL);
  /* ranks on one machine share its cores: without --threads, each takes
   * its share rather than all of them */
  const char *local = getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
  int nlocal = local ? (int)strtol(local, NULL, 10) : 0;
  if (mpi && sp.threads <= 0 && nlocal > 1) {
#ifdef _OPENMP
    sp.threads = omp_get_num_procs() / nlocal;
#endif
    if (sp.threads < 1) sp.threads = 1;
  }
#endif
  rc = vi_sweep_run(text, scene ? scene : "<default scene: fig2>", sets, nsets,
                    &sp, &interrupted, &sw, err, sizeof err);
  free(text);
  if (rc) {
    int rank = 0;
#ifdef VI_HAVE_MPI
    if (mpi) MPI_Comm_rank(MPI_COMM_WORLD, &rank);
#endif
    if (!rank) fprintf(stderr, "vibroimpact: sweep: %s\n", err); /* once */
    goto finish;
  }
  if (sw->rank) { /* rank 0 reports and writes */
    vi_sweep_free(&sw);
    goto finish;
  }
  for (int l = 0; l < sw->nlines; l++)
    for (int k = 0; k < sp.steps; k++)
      if (sw->lines[l].pt[k].failed)
        fprintf(stderr, "vibroimpact: sweep: warning: %s (marked failed; the "
                "next value starts from the scene's initial state)\n",
                sw->lines[l].pt[k].error ? sw->lines[l].pt[k].error : "");
  if (out && vi_sweep_write_h5(sw, out, err, sizeof err)) {
    fprintf(stderr, "vibroimpact: sweep: %s\n", err);
    rc = 1;
  } else if (json) {
    vi_sweep_print_json(sw, stdout);
  } else if (!quiet) {
    table(sw);
    if (out) printf("diagram written to %s\n", out);
  }
  vi_sweep_free(&sw);
finish:
#ifdef VI_HAVE_MPI
  if (mpi) {
    /* every rank leaves with rank 0's status */
    MPI_Bcast(&rc, 1, MPI_INT, 0, MPI_COMM_WORLD);
    MPI_Finalize();
  }
#endif
done:
  free(sets);
  return rc;
}
