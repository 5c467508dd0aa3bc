/* vi_bench_chatter.c - what resolving chattering impacts costs: the impact
 * resolution's default (every impact above 1e-5 of the run's velocity
 * scale reported individually, vi_sim_set_impact_resolution) against 0
 * (the older rule: a tail summed by the chatter map as soon as resolving
 * the next impact looks costlier), per method, on
 *  - share/scenes/chatter.yaml (SDOF, preload, r = 0.5; 50 forcing periods
 *    at the scene's rtol 1e-10, atol 1e-12), and
 *  - the 20-mode modal rod of issue 20 (omega_j = (2j - 1) pi / 2, zeta
 *    0.02, tip stop x_s 0.05, r 0.8, tip force 0.1 cos 1.4 t; 10 forcing
 *    periods at rtol 1e-10, atol 1e-12).
 * Each case is run R times for each setting, interleaved, and the least
 * CPU time of each kept; the ratio is taken within this one run (the
 * machine is shared), with the impacts reported and the ones summed.
 *
 * Usage: vi_bench_chatter [SCENE_DIR [R]]   (default share/scenes, 5) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <vibroimpact.h>
#include <vibroimpact/vi_scene.h>

static double cpu(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* One case: a model, its initial state and run. */
typedef struct bcase {
  const char *name;
  vi_model *m;
  const vi_scene *sc; /* NULL: rest at t = 0 */
  double t_end, rtol, atol;
} bcase;

/* One run; its CPU seconds, impacts reported and summed; -1 on failure. */
static double one(const bcase *c, int method, double res, long long *imp,
                  long long *skipped)
{
  vi_sim *s = NULL;
  vi_diag d;
  if (vi_sim_create(c->m, &s)) return -1;
  int st = c->sc ? vi_scene_configure_sim(c->sc, s, &d) : VI_OK;
  if (!st) st = vi_sim_set_method(s, method);
  if (!st) st = vi_sim_set_tolerances(s, c->rtol, c->atol);
  if (!st) st = vi_sim_set_impact_resolution(s, res);
  double t0 = cpu();
  if (!st) st = vi_sim_run(s, c->t_end);
  double t = cpu() - t0;
  *imp = (long long)vi_sim_stat(s, VI_STAT_IMPACTS);
  *skipped = (long long)vi_sim_stat(s, VI_STAT_CHATTER_SKIPPED);
  if (st) fprintf(stderr, "%s %s: %s\n", c->name, vi_method_name(method), vi_sim_errmsg(s));
  vi_sim_destroy(&s);
  return st ? -1 : t;
}

static void bench(const bcase *c, int reps)
{
  static const int methods[] = {VI_METHOD_EXACT, VI_METHOD_ADAMS, VI_METHOD_BDF,
                                VI_METHOD_ERK};
  printf("%s (t_end %.4g, rtol %g, atol %g): least CPU time of %d runs\n", c->name,
         c->t_end, c->rtol, c->atol, reps);
  printf("  %-6s %12s %10s %10s %12s %10s %10s %8s\n", "method", "1e-5 (ms)",
         "impacts", "summed", "0 (ms)", "impacts", "summed", "ratio");
  for (size_t k = 0; k < sizeof methods / sizeof methods[0]; k++) {
    double best[2] = {HUGE_VAL, HUGE_VAL};
    long long imp[2] = {0, 0}, skip[2] = {0, 0};
    int bad = 0;
    for (int r = 0; r < reps && !bad; r++)
      for (int j = 0; j < 2; j++) { /* interleaved: drift hits both alike */
        double t = one(c, methods[k], j ? 0.0 : 1e-5, &imp[j], &skip[j]);
        if (t < 0) bad = 1;
        else best[j] = fmin(best[j], t);
      }
    if (bad) {
      printf("  %-6s failed (message above)\n", vi_method_name(methods[k]));
      continue;
    }
    printf("  %-6s %12.3f %10lld %10lld %12.3f %10lld %10lld %8.2f\n",
           vi_method_name(methods[k]), 1e3 * best[0], imp[0], skip[0],
           1e3 * best[1], imp[1], skip[1], best[0] / best[1]);
  }
}

/* The 20-mode rod of issue 20 (tests/stress/test_stress_chatref.c). */
static vi_model *rod(void)
{
  enum { N = 20 };
  static double M[N * N], C[N * N], K[N * N];
  double w[N], a[N], b[N], f0[N];
  for (int j = 0; j < N; j++) {
    double om = (2 * j + 1) * M_PI / 2;
    size_t jj = (size_t)j * (N + 1);
    M[jj] = 1.0;
    K[jj] = om * om;
    C[jj] = 2 * 0.02 * om;
    w[j] = (j % 2 ? -1.0 : 1.0) * sqrt(2.0);
    a[j] = 0.1 * w[j];
    b[j] = f0[j] = 0.0;
  }
  vi_model *m = NULL;
  if (vi_model_create(N, &m) || vi_model_set_mass(m, M, N) ||
      vi_model_set_damping(m, C, N) || vi_model_set_stiffness(m, K, N) ||
      vi_model_set_forcing(m, 1.4, a, b, f0) || vi_model_set_stop(m, w, 0.05, 0.8) ||
      vi_model_setup(m))
    vi_model_destroy(&m);
  return m;
}

int main(int argc, char **argv)
{
  const char *dir = argc > 1 ? argv[1] : "share/scenes";
  int reps = argc > 2 ? (int)strtol(argv[2], NULL, 10) : 5;
  if (reps < 1) reps = 1;
  char path[4096];
  snprintf(path, sizeof path, "%s/chatter.yaml", dir);
  vi_scene *sc = NULL;
  vi_diag d;
  vi_model *m = NULL;
  if (vi_scene_load(path, &sc, &d) || vi_scene_create_model(sc, &m, &d)) {
    char msg[2048];
    vi_diag_format(&d, msg, sizeof msg);
    fprintf(stderr, "vi_bench_chatter: %s\n", msg);
    vi_scene_destroy(&sc);
    return 1;
  }
  bcase ch = {"share/scenes/chatter.yaml", m, sc, vi_scene_t_end(sc),
              vi_scene_rtol(sc), vi_scene_atol(sc)};
  bench(&ch, reps);
  vi_model *r = rod();
  if (!r) {
    fprintf(stderr, "vi_bench_chatter: the rod model failed\n");
    return 1;
  }
  bcase rc = {"20-mode rod (issue 20)", r, NULL, 10 * 2 * M_PI / 1.4, 1e-10, 1e-12};
  bench(&rc, reps);
  vi_model_destroy(&r);
  vi_model_destroy(&m);
  vi_scene_destroy(&sc);
  return 0;
}
