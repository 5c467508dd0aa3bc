/* vibroimpact - command-line front end: scene in, summary / CSV / HDF5 out.
 *
 *   vibroimpact [run] [SCENE.yaml] [-o OUT.h5] [--impacts-csv FILE] ...
 *   vibroimpact energy [SCENE.yaml] [--json]
 *   vibroimpact restitution --re RE --ke KE_i
 *
 * With no scene it runs the embedded default: the paper's Fig. 2.
 * Exit status: 0 success, 1 run-time error (or interrupted), 2 usage or
 * input error. */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <gsl/gsl_errno.h>

#include "vi_app.h"
#include "vi_sweep.h"

volatile sig_atomic_t vi_app_interrupted;
static void on_signal(int sig) { (void)sig; vi_app_interrupted = 1; }

static void usage(FILE *f)
{
  fprintf(f,
    "usage: vibroimpact [run] [SCENE.yaml] [options]   simulate a scene\n"
    "       vibroimpact energy [SCENE.yaml] [options]  P(1,1) energy balance (WB 11-13)\n"
    "       vibroimpact restitution --re RE --ke KE_I  r = sqrt(1 - RE/KE_i) (WB 13)\n"
    "       vibroimpact sweep [SCENE.yaml] --param KEY --from A --to B --steps K ...\n"
    "                                                  bifurcation diagram (sweep --help)\n"
    "       vibroimpact orbits [SCENE.yaml] [--n N] [--m M] [--json]  P(n,m) orbits by Newton\n"
    "With no scene: the embedded default, Wagg & Bishop (2000) Fig. 2.\n\n"
    "  -o, --output FILE   write the run to an HDF5 file (FILE.part until done)\n"
    "  --impacts-csv FILE  one line per impact, pre-impact state; '-' = stdout\n"
    "  --periods P         forcing periods to simulate (overrides the scene)\n"
    "  --rtol R, --atol A  tolerances (override the scene)\n"
    "  --method M          adams, bdf or exact (closed-form flow)\n"
    "  --json              (energy) print one JSON object\n"
    "  --set KEY=VALUE     override a scene key, e.g. --set forcing.omega=0.95\n"
    "  --quiet             no summary and no progress bar\n"
    "  --version, --help\n\n"
    "Exit status: 0 success, 1 run-time error or interrupted, 2 usage or input error.\n");
}

static int num(const char *opt, const char *s, double *out)
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

static int restitution(double re, double ke)
{
  double r;
  if (vi_restitution_from_energy(re, ke, &r) != VI_OK) {
    fprintf(stderr, "vibroimpact: restitution: need KE_i > 0 and 0 <= RE <= "
            "KE_i (got RE = %g, KE_i = %g)\n", re, ke);
    return 2;
  }
  printf("%.17g\n", r);
  return 0;
}

int main(int argc, char **argv)
{
  gsl_set_error_handler_off();
  if (vi_version_number() != VI_VERSION_NUMBER) {
    fprintf(stderr, "vibroimpact: header %s and library %s differ\n",
            VI_VERSION_STRING, vi_version_string());
    return 1;
  }
  if (argc > 1 && !strcmp(argv[1], "sweep")) return vi_sweep_exec(argc - 1, argv + 1);
  if (argc > 1 && !strcmp(argv[1], "orbits")) return vi_cmd_orbits_main(argc - 1, argv + 1);
  if ((argc = vi_sets_take(argc, argv)) < 0) { fprintf(stderr, "vibroimpact: --set needs KEY=VALUE\n"); return 2; }
  app_opts o = {NULL, NULL, NULL, 0, 0, 0, -1, 0, 0, 0};
  const char *cmd = "run";
  int first = 1;
  if (argc > 1 && (!strcmp(argv[1], "run") || !strcmp(argv[1], "energy") ||
                   !strcmp(argv[1], "restitution"))) {
    cmd = argv[1];
    first = 2;
  }
  static const struct option lo[] = {
      {"output", required_argument, 0, 'o'}, {"impacts-csv", required_argument, 0, 'c'},
      {"periods", required_argument, 0, 'p'}, {"rtol", required_argument, 0, 'r'},
      {"atol", required_argument, 0, 'a'},   {"method", required_argument, 0, 'm'},
      {"json", no_argument, 0, 'j'},         {"quiet", no_argument, 0, 'q'},
      {"re", required_argument, 0, 'R'},     {"ke", required_argument, 0, 'K'},
      {"version", no_argument, 0, 'V'},      {"help", no_argument, 0, 'h'},
      {0, 0, 0, 0}};
  double re = NAN, ke = NAN;
  int c;
  optind = first;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "o:", lo, NULL)) != -1) {
    switch (c) {
    case 'o': o.out = optarg; break;
    case 'c': o.csv = optarg; break;
    case 'p':
      if (!num("--periods", optarg, &o.periods)) return 2;
      if (!(o.periods > 0)) { fprintf(stderr, "vibroimpact: --periods must be > 0\n"); return 2; }
      break;
    case 'r':
      if (!num("--rtol", optarg, &o.rtol)) return 2;
      if (!(o.rtol > 0)) { fprintf(stderr, "vibroimpact: --rtol must be > 0\n"); return 2; }
      break;
    case 'a':
      if (!num("--atol", optarg, &o.atol)) return 2;
      if (!(o.atol > 0)) { fprintf(stderr, "vibroimpact: --atol must be > 0\n"); return 2; }
      break;
    case 'm':
      if (!strcmp(optarg, "adams")) o.method = VI_METHOD_ADAMS;
      else if (!strcmp(optarg, "bdf")) o.method = VI_METHOD_BDF;
      else if (!strcmp(optarg, "exact")) o.method = VI_METHOD_EXACT;
      else {
        fprintf(stderr, "vibroimpact: --method: '%s' is not adams, bdf or exact\n", optarg);
        return 2;
      }
      break;
    case 'j': o.json = 1; break;
    case 'q': o.quiet = 1; break;
    case 'R': if (!num("--re", optarg, &re)) return 2; break;
    case 'K': if (!num("--ke", optarg, &ke)) return 2; break;
    case 'V':
      printf("vibroimpact %s (SUNDIALS %s)\n", vi_version_string(), vi_sundials_version());
      return 0;
    case 'h': usage(stdout); return 0;
    default:
      fprintf(stderr, "vibroimpact: unknown or incomplete option '%s'\n", argv[optind - 1]);
      usage(stderr);
      return 2;
    }
  }
  if (optind < argc) o.scene = argv[optind++];
  if (optind < argc) {
    fprintf(stderr, "vibroimpact: unexpected argument '%s'\n", argv[optind]);
    return 2;
  }
  if (!strcmp(cmd, "restitution")) {
    if (isnan(re) || isnan(ke)) {
      fprintf(stderr, "vibroimpact: restitution needs --re and --ke\n");
      return 2;
    }
    return restitution(re, ke);
  }
  o.progress = !o.quiet && isatty(STDERR_FILENO);
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sigaction(SIGINT, &sa, NULL);
  sigaction(SIGTERM, &sa, NULL);
  return !strcmp(cmd, "energy") ? vi_cmd_energy(&o) : vi_cmd_run(&o);
}
