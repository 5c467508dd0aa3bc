/* vibroimpact - command-line front end: scene in, summary / CSV / HDF5 out.
 *
 *   vibroimpact [run] [SCENE.yaml] [-o OUT.h5] [--impacts-csv FILE] ...
 *   vibroimpact energy [SCENE.yaml] [--json]
 *   vibroimpact restitution --re RE --ke KE_i
 *
 * With no scene it runs the embedded default: the paper's Fig. 2.
 * Exit status: 0 success, 1 run-time error, 2 usage or input error,
 * 128 + signal when interrupted (130 SIGINT, 143 SIGTERM). */
#include <errno.h>
#include <fcntl.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gsl/gsl_errno.h>

#include "vi_app.h"
#include "vi_app_blas.h"
#include "vi_diagram.h" /* sweep, orbits, --set */

static int cmd_restitution(const app_opts *o);

/* The subcommands; the first is the default.  Add a row to add one. */
static const app_cmd cmds[] = {
    {"run", vi_cmd_run, "[SCENE.yaml] [options]", "simulate a scene"},
    {"energy", vi_cmd_energy, "[SCENE.yaml] [options]",
     "P(1,1) energy balance (WB 11-13)"},
    {"restitution", cmd_restitution, "--re RE --ke KE_I",
     "r = sqrt(1 - RE/KE_i) (WB 13)"},
    {"truncation", vi_cmd_truncation,
     "[SCENE.yaml] [--modes A..B] [--reference N] [--json] [-o OUT.h5]",
     "how many modes: compliance carried, response and r_S per k"},
};
enum { NCMD = sizeof cmds / sizeof cmds[0] };

/* ---- signals ------------------------------------------------------------- */
volatile sig_atomic_t vi_app_signal;
static volatile sig_atomic_t polling, armed;
static char part_a[VI_APP_PATH + 8], part_b[VI_APP_PATH + 8];

static void on_signal(int sig)
{
  vi_app_signal = sig;
  if (polling) return; /* the run sees the flag within a step */
  /* nothing polls: parsing, model building, eigen-solves, writing a
   * header.  Leave nothing on disk and go (async-signal-safe calls only). */
  if (armed) {
    if (part_a[0]) unlink(part_a);
    if (part_b[0]) unlink(part_b);
  }
  /* said, not silent: write(2) is async-signal-safe, printf is not */
  static const char m_int[] = "vibroimpact: interrupted (SIGINT): "
                              "stopped, no file left behind\n";
  static const char m_term[] = "vibroimpact: interrupted (SIGTERM): "
                               "stopped, no file left behind\n";
  ssize_t w = sig == SIGTERM ? write(STDERR_FILENO, m_term, sizeof m_term - 1)
                             : write(STDERR_FILENO, m_int, sizeof m_int - 1);
  (void)w;
  _exit(128 + sig);
}

void vi_app_arm_parts(const char *p1, const char *p2)
{
  armed = 0;
  snprintf(part_a, sizeof part_a, "%s", p1 ? p1 : "");
  snprintf(part_b, sizeof part_b, "%s", p2 ? p2 : "");
  armed = 1;
}

void vi_app_set_polling(int on) { polling = on; }

int vi_app_cancel(void *user)
{
  (void)user;
  return vi_app_signal != 0;
}

int vi_app_interrupt_status(void)
{
  return vi_app_signal ? 128 + vi_app_signal : 130;
}

/* ---- usage and arguments ------------------------------------------------- */
static void usage(FILE *f)
{
  for (int k = 0; k < NCMD; k++)
    fprintf(f, "%s vibroimpact %s %s\n%*s%s\n", k ? "      " : "usage:",
            cmds[k].name, cmds[k].synopsis, 9, "", cmds[k].what);
  fprintf(f, "       vibroimpact sweep [SCENE.yaml] --param KEY --from A --to B --steps K ...\n"
             "         bifurcation diagram (vibroimpact sweep --help)\n"
             "       vibroimpact basins [SCENE.yaml] --param KEY ... --param2 KEY2 ...\n"
             "         basins of attraction (vibroimpact basins --help)\n"
             "       vibroimpact orbits [SCENE.yaml] [--n N] [--m M] [--json]\n"
             "         P(n,m) orbits by Newton, stable or not (--help)\n"
             "       vibroimpact curves [SCENE.yaml] --kind grazing|fold|pd|ns --param KEY ...\n"
             "         two-parameter bifurcation curves (--help)\n"
             "       vibroimpact identify SCENE.yaml --data REC.csv --fit KEY[,KEY...]\n"
             "         parameters from a recorded response (--help)\n");
  fprintf(f,
    "With no scene: the embedded default, Wagg & Bishop (2000) Fig. 2.\n\n"
    "  -o, --output FILE   write the run to an HDF5 file (FILE.part until "
    "done;\n"
    "                      regular files only, symbolic links followed)\n"
    "  --impacts-csv FILE  one line per impact, pre-impact state; '-' = stdout\n"
    "  --periods P         forcing periods to simulate (overrides the scene)\n"
    "  --rtol R, --atol A  tolerances (override the scene)\n"
    "  --method M          ");
  for (int m = 0; vi_method_name(m); m++)
    fprintf(f, "%s%s", m ? ", " : "", vi_method_name(m));
  fprintf(f, "\n"
    "  --json              (energy, truncation) print one JSON object\n"
    "  --modes A..B        (truncation) kept modes studied, or K for 1..K\n"
    "  --reference N       (truncation) modes of the reference model (FE\n"
    "                      scenes; default max(2B, B + 20))\n"
    "  --set KEY=VALUE     override a scene key, e.g. --set forcing.omega=0.95\n"
    "  --quiet             no summary and no progress bar\n"
    "  --max-scene-size B  largest scene file read (default %lld bytes)\n"
    "  --max-depth D       deepest YAML nesting (default %d)\n"
    "  --max-memory B      memory a model may need (default: the machine's\n"
    "                      MemAvailable); B may end in K, M or G\n"
    "  --version, --help\n\n"
    "Exit status: 0 success, 1 run-time error, 2 usage or input error,\n"
    "128 + signal when interrupted (130 SIGINT, 143 SIGTERM).\n",
    (long long)VI_SCENE_MAX_BYTES, VI_SCENE_MAX_DEPTH);
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

/* A number > 0 (periods, tolerances). */
static int positive(const char *opt, const char *s, double *out)
{
  if (!num(opt, s, out)) return 0;
  if (*out > 0) return 1;
  fprintf(stderr, "vibroimpact: %s must be > 0\n", opt);
  return 0;
}

/* A size in bytes with an optional K, M or G suffix (powers of 1024). */
static int bytes(const char *opt, const char *s, double *out)
{
  char *end;
  errno = 0;
  double v = strtod(s, &end);
  double mul = 1;
  if (end != s && *end && !end[1]) {
    mul = *end == 'K' || *end == 'k'   ? 1024.0
          : *end == 'M' || *end == 'm' ? 1048576.0
          : *end == 'G' || *end == 'g' ? 1073741824.0
                                       : 0;
    if (mul > 0) end++;
  }
  if (errno || end == s || *end || !isfinite(v) || !(v > 0) || !(mul > 0)) {
    fprintf(stderr, "vibroimpact: %s: '%s' is not a size > 0 (bytes, or "
            "with K, M, G)\n", opt, s);
    return 0;
  }
  *out = v * mul;
  return 1;
}

static int cmd_restitution(const app_opts *o)
{
  double r;
  if (isnan(o->re) || isnan(o->ke)) {
    fprintf(stderr, "vibroimpact: restitution needs --re and --ke\n");
    return 2;
  }
  if (vi_restitution_from_energy(o->re, o->ke, &r) != VI_OK) {
    fprintf(stderr, "vibroimpact: restitution: need KE_i > 0 and 0 <= RE <= "
            "KE_i (got RE = %g, KE_i = %g)\n", o->re, o->ke);
    return 2;
  }
  printf("%.17g\n", r);
  return 0;
}

/* Edit distance (insertions, deletions, substitutions), capped at 9. */
static int distance(const char *a, const char *b)
{
  size_t la = strlen(a), lb = strlen(b);
  if (la > 30 || lb > 30) return 9;
  int row[32];
  for (size_t j = 0; j <= lb; j++) row[j] = (int)j;
  for (size_t i = 1; i <= la; i++) {
    int diag = row[0];
    row[0] = (int)i;
    for (size_t j = 1; j <= lb; j++) {
      int up = row[j], best = diag + (a[i - 1] != b[j - 1]);
      if (up + 1 < best) best = up + 1;
      if (row[j - 1] + 1 < best) best = row[j - 1] + 1;
      diag = up;
      row[j] = best;
    }
  }
  return row[lb] < 9 ? row[lb] : 9;
}

/* A first argument that is neither a command nor an existing file but
 * looks like a command: the command meant, else NULL. */
static const char *suggest(const char *arg)
{
  if (!arg[0] || arg[0] == '-' || strchr(arg, '/') || strchr(arg, '.') ||
      access(arg, F_OK) == 0)
    return NULL;
  const char *best = NULL;
  int bd = 3;
  for (int k = 0; k < NCMD; k++) {
    const char *nm = cmds[k].name;
    int d = strncmp(nm, arg, strlen(arg)) == 0 ? 0 : distance(arg, nm);
    if (d < bd) {
      bd = d;
      best = nm;
    }
  }
  return best;
}

/* Output paths are checked before anything is computed (vi_output.h):
 * the scene itself is refused, a stream may go to a character device. */
static int check_output(const char *path, int flags, const char *scene,
                        char *target, int *kind)
{
  vi_diag d;
  int st = vi_output_check(path, flags, scene, target, VI_APP_PATH, kind, &d);
  if (st) fprintf(stderr, "vibroimpact: %s\n", d.message);
  /* the scene named as the output is a usage error (2), the rest the
   * machine's (1) */
  return !st ? 0 : st == VI_ERR_ARG ? 2 : 1;
}

/* Standard output is checked like a file: a lost summary is an error. */
static int close_stdout(int rc)
{
  int bad = fflush(stdout) != 0 || ferror(stdout);
  int e = errno;
  if (fclose(stdout) != 0 && !bad) {
    bad = 1;
    e = errno;
  }
  if (bad) {
    fprintf(stderr, "vibroimpact: cannot write the standard output: %s\n",
            strerror(e ? e : EIO));
    return rc ? rc : 1;
  }
  return rc;
}

/* The command named by argv[1] (run if none); *first = 2 when argv[1]
 * named one.  0, or 2 when argv[1] looks like a misspelt command. */
static int pick_command(int argc, char **argv, const app_cmd **cmd, int *first)
{
  *cmd = &cmds[0];
  *first = 1;
  if (argc <= 1) return 0;
  for (int k = 0; k < NCMD; k++)
    if (!strcmp(argv[1], cmds[k].name)) {
      *cmd = &cmds[k];
      *first = 2;
    }
  const char *s = *first == 1 ? suggest(argv[1]) : NULL;
  if (s) {
    fprintf(stderr, "vibroimpact: '%s' is neither a command nor a file; "
            "did you mean 'vibroimpact %s'?\n", argv[1], s);
    return 2;
  }
  return 0;
}

enum { O_MAXSIZE = 256, O_MAXDEPTH, O_MAXMEM, O_MODES, O_REF };
static const struct option long_opts[] = {
    {"output", required_argument, 0, 'o'}, {"impacts-csv", required_argument, 0, 'c'},
    {"periods", required_argument, 0, 'p'}, {"rtol", required_argument, 0, 'r'},
    {"atol", required_argument, 0, 'a'},   {"method", required_argument, 0, 'm'},
    {"json", no_argument, 0, 'j'},         {"quiet", no_argument, 0, 'q'},
    {"re", required_argument, 0, 'R'},     {"ke", required_argument, 0, 'K'},
    {"max-scene-size", required_argument, 0, O_MAXSIZE},
    {"max-depth", required_argument, 0, O_MAXDEPTH},
    {"max-memory", required_argument, 0, O_MAXMEM},
    {"modes", required_argument, 0, O_MODES},
    {"reference", required_argument, 0, O_REF},
    {"version", no_argument, 0, 'V'},      {"help", no_argument, 0, 'h'},
    {0, 0, 0, 0}};

/* --method NAME: 1, or 0 with the known names printed. */
static int method_arg(const char *arg, int *method)
{
  if ((*method = vi_method_from_name(arg)) >= 0) return 1;
  fprintf(stderr, "vibroimpact: --method: '%s' is not one of", arg);
  for (int m = 0; vi_method_name(m); m++)
    fprintf(stderr, "%s %s", m ? "," : "", vi_method_name(m));
  fputc('\n', stderr);
  return 0;
}

/* A whole number in [1, hi] for option name: 1, or 0 with a message. */
static int whole_arg(const char *name, const char *arg, double hi, int *out)
{
  double v;
  if (!num(name, arg, &v)) return 0;
  if (!(v >= 1 && v <= hi) || v != floor(v)) {
    fprintf(stderr, "vibroimpact: %s must be a whole number in [1, %.0f]\n", name, hi);
    return 0;
  }
  *out = (int)v;
  return 1;
}

/* --modes K (= 1..K) or A..B: 1, or 0 with a message. */
static int modes_arg(const char *arg, app_opts *o)
{
  char *end;
  const char *dots = strstr(arg, "..");
  long a = strtol(arg, &end, 10), b = a;
  if (dots && end == dots) b = strtol(dots + 2, &end, 10);
  if (end == arg || *end || a < 1 || b < a || b > 100000) {
    fprintf(stderr, "vibroimpact: --modes: '%s' is not K or A..B with "
            "1 <= A <= B <= 100000\n", arg);
    return 0;
  }
  o->modes_lo = dots ? (int)a : 1;
  o->modes_hi = (int)b;
  return 1;
}

/* One option c (getopt_long's) into o: -1 to go on, else the exit status
 * (0 after --version or --help, 2 for a bad value, with the message). */
static int parse_option(int c, int argc, char **argv, app_opts *o)
{
  double v;
  int ok = 1;
  switch (c) {
  case 'o': o->out = optarg; break;
  case 'c': o->csv = optarg; break;
  case 'p': ok = positive("--periods", optarg, &o->periods); break;
  case 'r': ok = positive("--rtol", optarg, &o->rtol); break;
  case 'a': ok = positive("--atol", optarg, &o->atol); break;
  case 'm': ok = method_arg(optarg, &o->method); break;
  case 'j': o->json = 1; break;
  case 'q': o->quiet = 1; break;
  case 'R': ok = num("--re", optarg, &o->re); break;
  case 'K': ok = num("--ke", optarg, &o->ke); break;
  case O_MAXSIZE:
    if ((ok = bytes("--max-scene-size", optarg, &v)))
      o->max_scene_bytes = v > 9e18 ? INT64_MAX : (int64_t)v;
    break;
  case O_MAXDEPTH: ok = whole_arg("--max-depth", optarg, 1e6, &o->max_depth); break;
  case O_MAXMEM: ok = bytes("--max-memory", optarg, &o->max_memory); break;
  case O_MODES: ok = modes_arg(optarg, o); break;
  case O_REF: ok = whole_arg("--reference", optarg, 1e5, &o->modes_ref); break;
  case 'V':
    printf("vibroimpact %s (SUNDIALS %s)\n", vi_version_string(), vi_sundials_version());
    return 0;
  case 'h': usage(stdout); return 0;
  default:
    fprintf(stderr, "vibroimpact: unknown or incomplete option '%s'\n",
            optind > 0 && optind <= argc ? argv[optind - 1] : "?");
    usage(stderr);
    return 2;
  }
  return ok ? -1 : 2;
}

int vi_app_parse(int argc, char **argv, app_opts *op, const app_cmd **cmdp)
{
  app_opts o;
  memset(&o, 0, sizeof o);
  o.method = -1;
  o.re = o.ke = NAN;
  const app_cmd *cmd = &cmds[0];
  *cmdp = cmd; /* never left unset, whatever is returned */
  int first, c, rc = pick_command(argc, argv, &cmd, &first);
  if (rc) return rc;
  optind = 0; /* 0: glibc starts afresh (a second call, the fuzz target) */
  opterr = 0;
  /* "+": stop at the first non-option, as POSIX; then skip the command */
  if (first == 2) {
    argv++;
    argc--;
  }
  while ((c = getopt_long(argc, argv, "o:", long_opts, NULL)) != -1)
    if ((rc = parse_option(c, argc, argv, &o)) >= 0) return rc;
  if (optind < argc) o.scene = argv[optind++];
  if (optind < argc) {
    fprintf(stderr, "vibroimpact: unexpected argument '%s'\n", argv[optind]);
    return 2;
  }
  *op = o;
  *cmdp = cmd;
  return -1;
}

int main(int argc, char **argv)
{
  /* a closed standard descriptor would be reused by the first file we
   * open (the HDF5 output), and the summary would be written into it:
   * hold 0, 1, 2 with /dev/null opened read-only, so that writes to a
   * closed stdout fail and are reported instead */
  for (int fd = 0; fd <= 2; fd++)
    if (fcntl(fd, F_GETFD) == -1 && errno == EBADF) {
      int k = open("/dev/null", O_RDONLY);
      if (k >= 0 && k != fd) {
        dup2(k, fd);
        close(k);
      }
    }
  vi_app_blas_rest();
  gsl_set_error_handler_off();
  if (vi_version_number() != VI_VERSION_NUMBER) {
    fprintf(stderr, "vibroimpact: header %s and library %s differ\n",
            VI_VERSION_STRING, vi_version_string());
    return 1;
  }
  /* sweep and orbits parse their own arguments (apps/vi_diagram.h) */
  if (argc > 1 && (!strcmp(argv[1], "sweep") || !strcmp(argv[1], "basins")))
    return vi_app_sweep_exec(argc - 1, argv + 1);
  if (argc > 1 && (!strcmp(argv[1], "orbits") || !strcmp(argv[1], "identify") ||
                   !strcmp(argv[1], "curves"))) {
    /* the common handler: 130/143, nothing left on disk */
    struct sigaction so;
    memset(&so, 0, sizeof so);
    so.sa_handler = on_signal;
    sigaction(SIGINT, &so, NULL);
    sigaction(SIGTERM, &so, NULL);
    if (argv[1][0] == 'o') return vi_cmd_orbits_main(argc - 1, argv + 1);
    if (argv[1][0] == 'c') return vi_cmd_curves_main(argc - 1, argv + 1);
    return close_stdout(vi_cmd_identify_main(argc - 1, argv + 1));
  }
  if ((argc = vi_sets_take(argc, argv)) < 0) {
    fprintf(stderr, "vibroimpact: --set needs KEY=VALUE\n");
    return 2;
  }
  /* signals first: from here on every phase answers them */
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sigaction(SIGINT, &sa, NULL);
  sigaction(SIGTERM, &sa, NULL);

  static app_opts o;
  const app_cmd *cmd = NULL;
  int rc = vi_app_parse(argc, argv, &o, &cmd);
  if (rc >= 0) return close_stdout(rc);
  /* the check creates and removes PATH.part: no signal in between */
  sigset_t block, old;
  sigemptyset(&block);
  sigaddset(&block, SIGINT);
  sigaddset(&block, SIGTERM);
  sigprocmask(SIG_BLOCK, &block, &old);
  int bad = o.out ? check_output(o.out, VI_OUTPUT_REGULAR, o.scene,
                                 o.out_target, NULL) : 0;
  if (!bad && o.csv)
    bad = check_output(o.csv, VI_OUTPUT_STREAM, o.scene, o.csv_target,
                       &o.csv_kind);
  sigprocmask(SIG_SETMASK, &old, NULL);
  if (bad) return bad;
  /* one file named two ways is the same file: by device and inode */
  if (o.out && o.csv && vi_output_same(o.out_target, o.csv_target)) {
    fprintf(stderr, "vibroimpact: -o and --impacts-csv name the same file "
            "%s\n", o.out_target);
    return 2;
  }
  o.progress = !o.quiet && isatty(STDERR_FILENO);
  return close_stdout(cmd->fn(&o));
}
