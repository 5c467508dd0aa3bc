/* vi_bench - run time against error on the paper's Fig. 2 scene, the
 * exact method's loop time against Adams (Fig. 2, a 20-mass chain) and its
 * cost per forcing period against chain length N.
 *
 * 1000 forcing periods for each method and tolerance; the impact times are
 * compared with the closed-form event-driven run (VI_METHOD_EXACT, whose
 * contacts are located to round-off).  Wall times are the best of several
 * repeats (CPU time of the thread: the machine is shared) and are also printed as ratios to the exact method measured in
 * the same process, because absolute times on a shared machine are noise. */
#include <link.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gsl/gsl_errno.h>

#include "vibroimpact.h"
#include "vibroimpact/vi_scene.h"
#include "vibroimpact/vi_writer.h"

typedef struct rec { int n, cap; double *t, *vn; } rec;

static int collect(const vi_event *ev, void *u)
{
  rec *r = u;
  if (ev->kind != VI_EVENT_IMPACT) return 0;
  if (r->n == r->cap) {
    r->cap = r->cap ? 2 * r->cap : 1024;
    r->t = realloc(r->t, sizeof(double) * r->cap);
    r->vn = realloc(r->vn, sizeof(double) * r->cap);
    if (!r->t || !r->vn) return 1;
  }
  r->t[r->n] = ev->t;
  r->vn[r->n++] = ev->vn;
  return 0;
}

static double now(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts); /* CPU: the machine is shared */
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* The loaded SUNDIALS libraries (CVODES for adams/bdf, ARKODE for erk):
 * which build ran, e.g. the optimised one of share/scripts/deps.sh. */
typedef struct libs { char cvodes[512], arkode[512]; } libs;

static int find_lib(struct dl_phdr_info *info, size_t size, void *out)
{
  (void)size;
  libs *l = out;
  if (strstr(info->dlpi_name, "sundials_cvodes"))
    snprintf(l->cvodes, sizeof l->cvodes, "%s", info->dlpi_name);
  if (strstr(info->dlpi_name, "sundials_arkode"))
    snprintf(l->arkode, sizeof l->arkode, "%s", info->dlpi_name);
  return 0;
}

static vi_model *fig2(void)
{
  const double mass[2] = {1, 1}, k[2] = {1, 1}, c[2] = {0.1, 0.1};
  const double a[2] = {0.5, 0.0}, w[2] = {0.0, 1.0};
  double M[4], C[4], K[4];
  vi_model *m = NULL;
  vi_build_chain(2, mass, k, c, M, C, K, 2);
  if (vi_model_create(2, &m) || vi_model_set_mass(m, M, 2) ||
      vi_model_set_damping(m, C, 2) || vi_model_set_stiffness(m, K, 2) ||
      vi_model_set_forcing(m, 0.9, a, NULL, NULL) ||
      vi_model_set_stop(m, w, 0.1, 0.7) || vi_model_setup(m)) {
    fprintf(stderr, "vi_bench: model: %s\n", vi_model_errmsg(m));
    exit(1);
  }
  return m;
}

typedef struct result { double wall; int64_t rhs, steps; rec r; } result;

static int ledger_none(const vi_ledger_interval *iv, void *u)
{
  (void)iv;
  (void)u;
  return 0;
}

/* One exact-method run of m to t_end with the energy ledger on, as the
 * program runs the default scene (a ledger callback, its closure printed):
 * the thread's CPU seconds in vi_sim_run, after vi_sim_setup (the program
 * times its set-up apart); *res its largest closure residual. */
static double run_ledger(const vi_model *m, double t_end, double *res)
{
  vi_sim *s = NULL;
  if (vi_sim_create(m, &s) || vi_sim_set_method(s, VI_METHOD_EXACT) ||
      vi_sim_set_tolerances(s, 1e-10, 1e-12) || vi_sim_enable_ledger(s, 1) ||
      vi_sim_set_ledger_callback(s, ledger_none, NULL, NULL) || vi_sim_setup(s)) {
    fprintf(stderr, "vi_bench: ledger set-up: %s\n", vi_sim_errmsg(s));
    exit(1);
  }
  double t0 = now();
  int st = vi_sim_run(s, t_end);
  double wall = now() - t0;
  if (st) {
    fprintf(stderr, "vi_bench: ledger run: %s\n", vi_sim_errmsg(s));
    exit(1);
  }
  *res = vi_sim_ledger_max_residual(s);
  vi_sim_destroy(&s);
  return wall;
}

static result run(const vi_model *m, int method, double rtol, double hrestart,
                  int native_ops, double t_end, int repeats)
{
  result best = {HUGE_VAL, 0, 0, {0, 0, NULL, NULL}};
  for (int k = 0; k < repeats; k++) {
    vi_sim *s = NULL;
    rec r = {0, 0, NULL, NULL};
    if (vi_sim_create(m, &s) || vi_sim_set_method(s, method) ||
        vi_sim_set_tolerances(s, rtol, rtol * 1e-2) ||
        vi_sim_set_restart_step(s, hrestart) ||
        vi_sim_set_native_vector_ops(s, native_ops) ||
        vi_sim_set_event_callback(s, collect, &r, NULL)) {
      fprintf(stderr, "vi_bench: set-up: %s\n", vi_sim_errmsg(s));
      exit(1);
    }
    double t0 = now();
    int st = vi_sim_run(s, t_end);
    double wall = now() - t0;
    if (st) {
      fprintf(stderr, "vi_bench: run: %s\n", vi_sim_errmsg(s));
      exit(1);
    }
    if (wall < best.wall) {
      free(best.r.t);
      free(best.r.vn);
      best.wall = wall;
      best.rhs = vi_sim_stat(s, VI_STAT_RHS_EVALS);
      best.steps = vi_sim_stat(s, VI_STAT_STEPS);
      best.r = r;
    } else {
      free(r.t);
      free(r.vn);
    }
    vi_sim_destroy(&s);
  }
  return best;
}

/* ---- memory: peak RSS of a run writing samples, in a fresh child ------- */
static int wr_event(const vi_event *ev, void *u) { return vi_writer_event(u, ev); }
static int wr_sample(double t, int n, const double *x, const double *v, void *u)
{
  (void)n;
  return vi_writer_sample(u, t, x, v);
}

/* Child: Fig. 2 for `periods` periods, exact method, 16 samples per period
 * and every impact into a compressed HDF5 file; reports ru_maxrss (KiB). */
static long child_rss(double periods, const char *path)
{
  int fd[2];
  if (pipe(fd)) return -1;
  pid_t pid = fork();
  if (pid == 0) {
    close(fd[0]);
    vi_scene *sc = NULL;
    vi_model *m = NULL;
    vi_sim *s = NULL;
    vi_writer *w = NULL;
    vi_diag d;
    long rss = -1;
    double T = 2 * M_PI / 0.9;
    if (!vi_scene_parse(vi_scene_default_text(), -1, "fig2", &sc, &d) &&
        !vi_scene_set_run(sc, 0, 0, periods, VI_METHOD_EXACT) &&
        !vi_scene_create_model(sc, &m, &d) && !vi_sim_create(m, &s) &&
        !vi_scene_configure_sim(sc, s, &d) && !vi_writer_create(path, m, 1, &w, &d) &&
        !vi_writer_write_header(w, sc, 1e-8, 1e-10, VI_METHOD_EXACT) &&
        !vi_sim_set_event_callback(s, wr_event, w, NULL) &&
        !vi_sim_set_sampling(s, T / 16, wr_sample, w, NULL) &&
        !vi_sim_run(s, vi_scene_t_end(sc)) && !vi_writer_close(&w, 1)) {
      struct rusage ru;
      getrusage(RUSAGE_SELF, &ru);
      rss = ru.ru_maxrss;
    }
    if (write(fd[1], &rss, sizeof rss) != sizeof rss) _exit(1);
    _exit(0);
  }
  close(fd[1]);
  long rss = -1;
  if (read(fd[0], &rss, sizeof rss) != sizeof rss) rss = -1;
  close(fd[0]);
  waitpid(pid, NULL, 0);
  return rss;
}

static void memory_section(void)
{
  const double periods[2] = {1e3, 1e5};
  long rss[2];
  char path[] = "/tmp/vi_bench_XXXXXX";
  int fd = mkstemp(path);
  if (fd < 0) return;
  close(fd);
  printf("\nmemory: Fig. 2, exact method, 16 samples per period and every impact "
         "written to HDF5 (deflate), peak RSS of a fresh process\n");
  for (int k = 0; k < 2; k++) {
    double t0 = now();
    rss[k] = child_rss(periods[k], path);
    printf("  %8.0f periods: peak RSS %6.1f MiB (%.2f s)\n", periods[k],
           rss[k] / 1024.0, now() - t0);
  }
  printf("  growth for 100x the run: %+.2f MiB\n", (rss[1] - rss[0]) / 1024.0);
  remove(path);
}

/* ---- the exact method at the limit: loop time and N-scaling ------------ */
/* Uniform fixed-free chain of n unit masses and springs, C = c E (so
 * proportional), forced 0.5 cos(0.9 t) on the last mass, stop at 0.1 on
 * the last mass with r = 0.7: Fig. 2's numbers on a chain of any length. */
static vi_model *chain(int n, double c)
{
  double *mass = malloc(sizeof(double) * 3 * (size_t)n);
  double *M = calloc(3 * (size_t)n * n, sizeof(double));
  double *a = calloc((size_t)n, sizeof(double)), *w = calloc((size_t)n, sizeof(double));
  vi_model *m = NULL;
  if (!mass || !M || !a || !w) exit(1);
  double *k = mass + n, *cv = k + n, *C = M + (size_t)n * n, *K = C + (size_t)n * n;
  for (int i = 0; i < n; i++) {
    mass[i] = 1.0;
    k[i] = 1.0;
    cv[i] = c;
  }
  a[n - 1] = 0.5;
  w[n - 1] = 1.0;
  vi_build_chain(n, mass, k, cv, M, C, K, n);
  if (vi_model_create(n, &m) || vi_model_set_mass(m, M, n) ||
      vi_model_set_damping(m, C, n) || vi_model_set_stiffness(m, K, n) ||
      vi_model_set_forcing(m, 0.9, a, NULL, NULL) ||
      vi_model_set_stop(m, w, 0.1, 0.7) || vi_model_setup(m)) {
    fprintf(stderr, "vi_bench: chain model: %s\n", vi_model_errmsg(m));
    exit(1);
  }
  free(mass);
  free(M);
  free(a);
  free(w);
  return m;
}

static double max_dt(const rec *a, const rec *b)
{
  double err = 0.0;
  int nc = a->n < b->n ? a->n : b->n;
  for (int k = 0; k < nc; k++) err = fmax(err, fabs(a->t[k] - b->t[k]));
  return err;
}

/* Loop time of the exact method (rtol 1e-10) and of Adams at rtol 1e-10 on
 * Fig. 2 and a 20-mass chain, 100 periods, best of `repeats`, interleaved. */
static void limit_section(int repeats)
{
  printf("\nlimit: exact vs adams, 100 forcing periods, loop time only, best of %d\n",
         repeats);
  printf("%-10s %12s %8s %12s %8s %10s %12s\n", "scene", "exact_ms", "impacts",
         "adams_ms", "impacts", "adams/exact", "max|dt_imp|");
  for (int sc = 0; sc < 2; sc++) {
    vi_model *m = sc == 0 ? fig2() : chain(20, 0.1);
    double t_end = 100 * 2.0 * M_PI / 0.9;
    result e = {HUGE_VAL, 0, 0, {0, 0, NULL, NULL}}, a = e;
    for (int k = 0; k < repeats; k++) { /* interleave: fair under load */
      result r1 = run(m, VI_METHOD_EXACT, 1e-10, 0.0, 1, t_end, 1);
      result r2 = run(m, VI_METHOD_ADAMS, 1e-10, 0.0, 1, t_end, 1);
      if (r1.wall < e.wall) { free(e.r.t); free(e.r.vn); e = r1; }
      else { free(r1.r.t); free(r1.r.vn); }
      if (r2.wall < a.wall) { free(a.r.t); free(a.r.vn); a = r2; }
      else { free(r2.r.t); free(r2.r.vn); }
    }
    printf("%-10s %12.4f %8d %12.3f %8d %10.1f %12.3e%s\n",
           sc == 0 ? "fig2" : "chain20", 1e3 * e.wall, e.r.n, 1e3 * a.wall,
           a.r.n, a.wall / e.wall, max_dt(&e.r, &a.r),
           e.r.n != a.r.n ? "  COUNT MISMATCH" : "");
    if (sc == 0) {
      /* the ledger's price per run, beside the same loop: the program's
       * default scene has the ledger on (issue 29) */
      double led = HUGE_VAL, loop = HUGE_VAL, res = 0.0;
      for (int k = 0; k < repeats; k++) {
        result lo = run(m, VI_METHOD_EXACT, 1e-10, 0.0, 1, t_end, 1);
        led = fmin(led, run_ledger(m, t_end, &res));
        loop = fmin(loop, lo.wall); /* interleaved: the same load */
        free(lo.r.t);
        free(lo.r.vn);
      }
      printf("%-10s %12.4f   the energy ledger on (set up before): %.2fx "
             "the loop beside it (%.4f ms), closure residual %.2g\n",
             "fig2+led", 1e3 * led, led / loop, 1e3 * loop, res);
    }
    free(e.r.t); free(e.r.vn); free(a.r.t); free(a.r.vn);
    vi_model_destroy(&m);
  }
  printf("(issue 10: the closed form's limit measured on this machine was "
         "0.106 ms for Fig. 2, 0.29 ms for a 20-chain)\n");
}

/* Issue 29's "a run starts at once": vi_sim_setup timed in a process
 * that has run no sim yet and then again, each sim as the program sets
 * up the default scene (exact, the ledger on), with the minor page
 * faults of each.  The first pays the first touch of the integrator's
 * code and data pages; the later ones are what a set-up itself costs a
 * caller that runs many (a study, a script).  Must run first in its
 * process: `vi_bench PERIODS REPEATS setup`. */
static long minor_faults(void)
{
  struct rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_minflt;
}

static void setup_section(int repeats)
{
  vi_model *m = fig2();
  double t_end = 100 * 2.0 * M_PI / 0.9, later = HUGE_VAL, loop = HUGE_VAL;
  double first = 0.0, first_run = 0.0;
  long first_flt = 0, later_flt = 0;
  for (int k = 0; k <= repeats; k++) {
    vi_sim *s = NULL;
    if (vi_sim_create(m, &s) || vi_sim_set_method(s, VI_METHOD_EXACT) ||
        vi_sim_set_tolerances(s, 1e-10, 1e-12) || vi_sim_enable_ledger(s, 1) ||
        vi_sim_set_ledger_callback(s, ledger_none, NULL, NULL)) {
      fprintf(stderr, "vi_bench: set-up: %s\n", vi_sim_errmsg(s));
      exit(1);
    }
    long f0 = minor_faults();
    double t0 = now();
    int st = vi_sim_setup(s);
    double t1 = now();
    long f1 = minor_faults();
    if (!st) st = vi_sim_run(s, t_end);
    double t2 = now();
    if (st) {
      fprintf(stderr, "vi_bench: setup run: %s\n", vi_sim_errmsg(s));
      exit(1);
    }
    if (k == 0) {
      first = t1 - t0;
      first_flt = f1 - f0;
      first_run = t2 - t1;
    } else {
      later = fmin(later, t1 - t0);
      later_flt += f1 - f0;
      loop = fmin(loop, t2 - t1);
    }
    vi_sim_destroy(&s);
  }
  printf("\nset-up: Fig. 2, exact, the ledger on, 100 periods; vi_sim_setup's CPU time\n");
  printf("first in the process %8.1f us (%ld minor page faults), its run %.4f ms\n",
         1e6 * first, first_flt, 1e3 * first_run);
  printf("later, best of %-5d %8.1f us (%ld page faults in all), run best %.4f ms "
         "(set-up + run: %.3fx the run)\n", repeats, 1e6 * later, later_flt,
         1e3 * loop, (later + loop) / loop);
  vi_model_destroy(&m);
}

/* Cost per forcing period against chain length, exact and Adams. */
static void scaling_section(int repeats)
{
  const int ns[] = {2, 10, 50, 200, 1000};
  printf("\nN-scaling: chain of N masses (c = 0.1, forced and stopped at the free "
         "end), rtol 1e-10, best of %d (N = 1000: once)\n", repeats);
  printf("%6s %8s %14s %14s %10s %9s %9s %12s\n", "N", "periods", "exact_us/per",
         "adams_us/per", "adams/ex", "imp_ex", "imp_ad", "ex_ns/per/N");
  for (int i = 0; i < 5; i++) {
    int n = ns[i];
    double periods = n >= 1000 ? 100 : 50;
    vi_model *m = chain(n, 0.1);
    double t_end = periods * 2.0 * M_PI / 0.9;
    int rep = n >= 1000 ? 1 : repeats;
    result e = run(m, VI_METHOD_EXACT, 1e-10, 0.0, 1, t_end, rep);
    result a = run(m, VI_METHOD_ADAMS, 1e-10, 0.0, 1, t_end, rep);
    printf("%6d %8.0f %14.2f %14.2f %10.1f %9d %9d %12.1f\n", n, periods,
           1e6 * e.wall / periods, 1e6 * a.wall / periods, a.wall / e.wall,
           e.r.n, a.r.n, 1e9 * e.wall / periods / n);
    fflush(stdout);
    free(e.r.t); free(e.r.vn); free(a.r.t); free(a.r.vn);
    vi_model_destroy(&m);
  }
}

int main(int argc, char **argv)
{
  gsl_set_error_handler_off();
  double periods = argc > 1 ? strtod(argv[1], NULL) : 1000.0;
  int repeats = argc > 2 ? (int)strtol(argv[2], NULL, 10) : 3;
  const char *only = argc > 3 ? argv[3] : "all";
  if (!(periods > 0) || repeats < 1) {
    fprintf(stderr, "usage: vi_bench [PERIODS [REPEATS [all|table|limit|scaling|memory|setup]]]\n");
    return 2;
  }
  libs lib = {"(not found)", "(not found)"};
  dl_iterate_phdr(find_lib, &lib);
  printf("vi_bench: vibroimpact %s, SUNDIALS %s from %s and %s\n",
         vi_version_string(), vi_sundials_version(), lib.cvodes, lib.arkode);
  printf("scene: Wagg & Bishop Fig. 2, %g forcing periods, best of %d; "
         "atol = rtol / 100\n\n", periods, repeats);
  if (!strcmp(only, "setup")) { /* first: it times the process's first sim */
    setup_section(repeats);
    return 0;
  }
  if (!strcmp(only, "limit") || !strcmp(only, "all")) limit_section(5);
  if (!strcmp(only, "scaling") || !strcmp(only, "all")) scaling_section(repeats);
  if (!strcmp(only, "memory")) {
    memory_section();
    return 0;
  }
  if (strcmp(only, "table") != 0 && strcmp(only, "all") != 0) return 0;
  vi_model *m = fig2();
  double t_end = periods * 2.0 * M_PI / 0.9;
  result ref = run(m, VI_METHOD_EXACT, 1e-12, 0.0, 1, t_end, repeats);
  printf("variant: cvode = CVODE's own first step after a restart and our vector\n"
         "ops; 1e-x = that first step forced; sun-ops = SUNDIALS' vector ops\n\n");
  printf("%-7s %-9s %-9s %10s %8s %12s %10s %10s %12s %9s\n", "method", "rtol",
         "variant", "wall_ms", "impacts", "rhs/period", "steps/imp",
         "us/impact", "max|dt_imp|", "x_exact");
  const struct { int m; const char *name; } meth[] = {
      {VI_METHOD_EXACT, "exact"}, {VI_METHOD_ADAMS, "adams"},
      {VI_METHOD_BDF, "bdf"}, {VI_METHOD_ERK, "erk"}};
  const double tols[] = {1e-6, 1e-8, 1e-10};
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 3; j++)
      for (int h = 0; h < (meth[i].m == VI_METHOD_EXACT ? 1 : 3); h++) {
        /* variant 1 forces the first step after a restart; variant 2 runs
         * on SUNDIALS' own (Debian, -O0) vector operations */
        double hr = h == 1 ? 1e-3 * pow(tols[j], 0.25) : 0.0;
        result r = run(m, meth[i].m, tols[j], hr, h != 2, t_end, repeats);
        double err = 0.0;
        int nc = r.r.n < ref.r.n ? r.r.n : ref.r.n;
        for (int k = 0; k < nc; k++) err = fmax(err, fabs(r.r.t[k] - ref.r.t[k]));
        char hs[16];
        snprintf(hs, sizeof hs, h == 1 ? "%.1e" : h == 2 ? "sun-ops" : "cvode", hr);
        printf("%-7s %-9.0e %-9s %10.3f %8d %12.1f %10.1f %10.2f %12.3e %9.1f%s\n",
               meth[i].name, tols[j], meth[i].m == VI_METHOD_EXACT ? "-" : hs,
               1e3 * r.wall, r.r.n, (double)r.rhs / periods,
               r.r.n ? (double)r.steps / r.r.n : 0.0,
               r.r.n ? 1e6 * r.wall / r.r.n : 0.0, err, r.wall / ref.wall,
               r.r.n != ref.r.n ? "  COUNT MISMATCH" : "");
        free(r.r.t);
        free(r.r.vn);
      }
  free(ref.r.t);
  free(ref.r.vn);
  vi_model_destroy(&m);
  if (!strcmp(only, "memory") || !strcmp(only, "all")) memory_section();
  return 0;
}
