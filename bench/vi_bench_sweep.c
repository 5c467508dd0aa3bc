/* vi_bench_sweep.c - the speed target of the parameter-space issue: the
 * Fig. 2 scene swept over 1000 values of Omega with 500 transient + 100
 * recorded periods each (6e5 forcing periods) on the exact method, and the
 * speed-up with threads, measured as ratios within this one run.
 *
 *   vi_bench_sweep [--values K] [--transient P] [--record R] [--threads T]
 *   vi_bench_sweep --chain N [--values K]
 *
 * --chain N: issue 19's target, a K-value sweep (default 40) of
 * forcing.omega on an N-mass chain (m = k = 1, C = 0.02 K, forced on mass
 * 1, a stop on mass N; dense, exact method) with 5 + 2 periods per value,
 * against one run of the scene for 7 periods (parse, model, simulation),
 * and against the former way of sweeping (the value printed into the
 * scene text, re-parsed, the model rebuilt with its modal analysis),
 * timed here by doing it; ratios of wall times within this one run.
 *
 * Runs: (1) one warm-started sweep, unsplit, serial; (2) the program's
 * default split (vi_diagram_default_chunks: seeded chunks of 16 values),
 * serial; (3) the same split on 2, 4, .. T threads, each checked
 * bit-identical to (2); (1)/(3) is what the user gains by default. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "vibroimpact.h"
#include "vibroimpact/vi_scene.h"
#include "vibroimpact/vi_scene_edit.h"
#include "vi_diagram.h"

static double now(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static double cpu(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static double cpu_used; /* CPU seconds of the last sweep, all threads */

static vi_diagram *sweep(vi_diagram_spec *sp, double *wall)
{
  double c0 = cpu();
  static const char *sets[] = {"run.method=exact"};
  vi_diagram *sw = NULL;
  char err[2048];
  double t = now();
  if (vi_diagram_run(vi_scene_default_text(), "fig2.yaml", sets, 1, sp, NULL,
                     &sw, err, sizeof err)) {
    fprintf(stderr, "vi_bench_sweep: %s\n", err);
    exit(1);
  }
  *wall = now() - t;
  cpu_used = cpu() - c0;
  return sw;
}

static int identical(const vi_diagram *a, const vi_diagram *b)
{
  int K = a->spec.steps, R = a->spec.record;
  if (memcmp(a->lines[0].strobe, b->lines[0].strobe, sizeof(double) * K * R * 2 * a->N) != 0)
    return 0;
  for (int k = 0; k < K; k++) {
    const vi_diagram_point *p = &a->lines[0].pt[k], *q = &b->lines[0].pt[k];
    if (p->n != q->n || p->m != q->m || p->nimp != q->nimp ||
        (p->nimp && memcmp(p->vn, q->vn, sizeof(double) * p->nimp) != 0))
      return 0;
  }
  return 1;
}

static void census(const vi_diagram *sw)
{
  int K = sw->spec.steps, p11 = 0, per = 0, failed = 0;
  int64_t imp = 0;
  for (int k = 0; k < K; k++) {
    const vi_diagram_point *p = &sw->lines[0].pt[k];
    p11 += p->n == 1 && p->m == 1;
    per += p->n > 0;
    failed += p->failed;
    imp += p->nimp;
  }
  printf("  diagram: %d values periodic (%d P(1,1)), %d unclassified, %d "
         "failed; %lld recorded impacts\n", per, p11, K - per - failed, failed,
         (long long)imp);
}

/* One run of the scene text (after setting `key` to val when key is
 * not NULL, the former sweep's way): parse, model, simulate to t_end. */
static double one_run(const char *text, const char *key, double val,
                      double periods)
{
  vi_scene_edit *ed = NULL;
  vi_scene *sc = NULL;
  vi_model *m = NULL;
  vi_sim *s = NULL;
  double t = now();
  int st = vi_scene_edit_create(text, -1, "chain", &ed, NULL);
  if (!st && key) st = vi_scene_edit_set_number(ed, key, val, NULL);
  if (!st) st = vi_scene_edit_parse(ed, &sc, NULL);
  if (!st) st = vi_scene_create_model(sc, &m, NULL);
  if (!st) st = vi_sim_create(m, &s);
  if (!st) st = vi_scene_configure_sim(sc, s, NULL);
  if (!st) st = vi_sim_run(s, periods * 2 * M_PI / vi_model_omega_forcing(m));
  if (st) {
    fprintf(stderr, "vi_bench_sweep: one run: %s\n", vi_strerror(st));
    exit(1);
  }
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
  vi_scene_destroy(&sc);
  vi_scene_edit_destroy(&ed);
  return now() - t;
}

static int cmp_double(const void *a, const void *b)
{
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* REPS alternating pairs (one run, then the sweep): the machine's load
 * drifts, so each sweep is set against the run just before it, and the
 * median of those ratios is the figure. */
#define REPS 5

static int chain_bench(int n, int K)
{
  char text[1024];
  snprintf(text, sizeof text,
           "name: chain%d\nmodel:\n  chain: {n: %d, m: 1.0, k: 1.0}\n"
           "  rayleigh: {alpha: 0.0, beta: 0.02}\n"
           "forcing: {omega: 0.04, on: [1], amplitude: 0.05}\n"
           "stop: {mass: %d, xs: 0.1, r: 0.95}\n"
           "run: {periods: 7, rtol: 1.0e-8, atol: 1.0e-10, method: exact}\n",
           n, n, n);
  printf("vi_bench_sweep --chain %d: %d values of forcing.omega 0.03..0.05, "
         "5 + 2 periods each, exact method, 1 thread; %d alternating pairs\n",
         n, K, REPS);
  vi_diagram_spec sp = {"forcing.omega", 0.03, 0.05, K, NULL, NAN, NAN, 1, 1,
                      5, 2, 1, 1, 1e-6, 32, 0, 0, 0, 0};
  double ratio[REPS], w_one = 0.0, w_sweep = 0.0;
  char err[2048];
  for (int r = 0; r < REPS; r++) {
    double w1 = one_run(text, NULL, 0, 7);
    vi_diagram *sw = NULL;
    double t = now();
    if (vi_diagram_run(text, "chain", NULL, 0, &sp, NULL, &sw, err, sizeof err)) {
      fprintf(stderr, "vi_bench_sweep: %s\n", err);
      return 1;
    }
    double ws = now() - t;
    vi_diagram_free(&sw);
    ratio[r] = ws / w1;
    printf("  pair %d: one run (parse, model, 7 periods) %7.3f s, sweep "
           "(parameters, vi_param.h) %7.3f s: %.2f x\n", r + 1, w1, ws,
           ratio[r]);
    w_one = r ? fmin(w_one, w1) : w1;
    w_sweep = r ? fmin(w_sweep, ws) : ws;
  }
  qsort(ratio, REPS, sizeof *ratio, cmp_double);
  printf("  sweep / one run: median %.2f x (range %.2f .. %.2f; target <= 3); "
         "fastest sweep / fastest run %.2f x\n", ratio[REPS / 2], ratio[0],
         ratio[REPS - 1], w_sweep / w_one);
  double t = now();
  for (int k = 0; k < K; k++)
    one_run(text, "forcing.omega", 0.03 + 0.02 * k / (K - 1), 7);
  double w_text = now() - t;
  printf("  the former way (text per value):     %8.3f s  = %.2f x the "
         "fastest one run; the fastest sweep is %.1f x faster\n", w_text,
         w_text / w_one, w_text / w_sweep);
  return 0;
}

int main(int argc, char **argv)
{
  if (argc >= 3 && !strcmp(argv[1], "--chain")) {
    int n = (int)strtol(argv[2], NULL, 10), K = 40;
    if (argc >= 5 && !strcmp(argv[3], "--values"))
      K = (int)strtol(argv[4], NULL, 10);
    if (n < 2 || K < 2) return 2;
    return chain_bench(n, K);
  }
  int K = 1000, P = 500, R = 100, T = 0; /* T 0: every core */
  for (int i = 1; i + 1 < argc; i += 2) {
    int v = (int)strtol(argv[i + 1], NULL, 10);
    if (!strcmp(argv[i], "--values")) K = v;
    else if (!strcmp(argv[i], "--transient")) P = v;
    else if (!strcmp(argv[i], "--record")) R = v;
    else if (!strcmp(argv[i], "--threads")) T = v;
    else {
      fprintf(stderr, "usage: vi_bench_sweep [--values K] [--transient P] "
              "[--record R] [--threads T]\n");
      return 2;
    }
  }
  if (K < 2 || P < 0 || R < 2 || T < 0) return 2;
#ifdef _OPENMP
  int cores = omp_get_num_procs();
  if (T == 0) T = cores;
#else
  int cores = 1;
  T = 1;
#endif
  vi_diagram_spec sp = {"forcing.omega", 0.5, 1.8, K, NULL, NAN, NAN, 1, 1, P, R,
                      1, 1, 1e-6, 32, 0, 0, 0, 0};
  double periods = (double)K * (P + R), w1, w2, w3 = INFINITY;
  printf("vi_bench_sweep: Fig. 2, Omega 0.5..1.8 in %d values, %d transient + "
         "%d recorded periods each (%.3g forcing periods), exact method; %d "
         "cores\n", K, P, R, periods, cores);
  vi_diagram *a = sweep(&sp, &w1);
  printf("  (1) 1 sweep, 1 thread:         %8.3f s wall, %8.3f s CPU  (%.2f us "
         "CPU per forcing period)\n", w1, cpu_used, 1e6 * cpu_used / periods);
  census(a);
  vi_diagram_free(&a);
  /* the program's default split, on 1, 2, 4, .. T threads: each must give
   * the same diagram bit for bit (the split depends on K alone) */
  sp.chunks = vi_diagram_default_chunks(&sp);
  sp.threads = 1;
  vi_diagram *b = sweep(&sp, &w2);
  printf("  (2) default split (%d chunks, seeded), 1 thread: %8.3f s wall, "
         "%8.3f s CPU  (%.3f x the unsplit sweep's wall)\n", sp.chunks, w2,
         cpu_used, w2 / w1);
  for (int t = 2; t <= T; t = t < T && 2 * t > T ? T : 2 * t) {
    sp.threads = t;
    vi_diagram *c = sweep(&sp, &w3);
    printf("  (3) default split, %2d threads: %8.3f s wall, %8.3f s CPU  "
           "speed-up %.2f over (1), %.2f over (2); bit-identical to (2): %s\n",
           t, w3, cpu_used, w1 / w3, w2 / w3, identical(b, c) ? "yes" : "NO");
    vi_diagram_free(&c);
  }
  printf("  target: a 1000-value sweep >= 8 x faster on 16 cores than on one "
         "by default; <= 1.5 s wall for the 1000 x 600-period diagram; best "
         "here %.3f s\n", fmin(w1, fmin(w2, w3)) * 6e5 / periods);
  vi_diagram_free(&b);
  return 0;
}
