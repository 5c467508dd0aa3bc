/* vi_bench_bar.c - Siconos' impacting bar (tests/stress/vi_bar.h) with our
 * default method, for bench/bar_bench.py, which times this whole process
 * against Siconos' Moreau-Jean in the same run.
 *
 * Usage: vi_bench_bar NE [METHOD [T_END]]
 * Prints one line: elements, release time, rebound speed (momentum / mass),
 * the method that ran, the model set-up and run times (s), and statistics. */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include <vibroimpact/vi_sim.h>

#include "vi_bar.h"

static double now(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int on_event(const vi_event *ev, void *user)
{
  double *t_rel = user;
  if (ev->kind == VI_EVENT_RELEASE && *t_rel < 0.0) *t_rel = ev->t;
  return 0;
}

int main(int argc, char **argv)
{
  int ne = argc > 1 ? (int)strtol(argv[1], NULL, 10) : 500;
  int method = argc > 2 ? vi_method_from_name(argv[2]) : VI_METHOD_AUTO;
  double t_end = argc > 3 ? strtod(argv[3], NULL) : 1.5e-3;
  if (ne < 1 || method < 0 || !(t_end > 5e-4)) {
    fprintf(stderr, "usage: vi_bench_bar NE [auto|exact|adams|bdf|erk [T_END > 5e-4]]\n");
    return 2;
  }
  double t0 = now();
  vi_model *m = bar_model(ne, 0.0);
  int n = ne + 1;
  double *x = malloc(sizeof(double) * (size_t)n), *v = malloc(sizeof(double) * (size_t)n);
  vi_sim *s = NULL;
  if (!m || !x || !v || vi_sim_create(m, &s)) {
    fprintf(stderr, "vi_bench_bar: set-up failed\n");
    free(x);
    free(v);
    vi_model_destroy(&m);
    return 1;
  }
  for (int i = 0; i < n; i++) {
    x[i] = BAR_X0;
    v[i] = BAR_V0;
  }
  double t_rel = -1.0;
  vi_sim_set_method(s, method);
  vi_sim_set_initial(s, 0.0, x, v);
  vi_sim_set_event_callback(s, on_event, &t_rel, NULL);
  double t1 = now();
  int st = vi_sim_run(s, t_end);
  double t2 = now();
  if (st) {
    fprintf(stderr, "vi_bench_bar: %s\n", vi_sim_errmsg(s));
    vi_sim_destroy(&s);
    vi_model_destroy(&m);
    free(x);
    free(v);
    return 1;
  }
  double t;
  vi_sim_state(s, &t, x, v);
  const double *M = vi_model_mass(m);
  double P = 0.0;
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) P += M[i + (size_t)j * n] * v[j];
  printf("%d %.17g %.17g %s %.3f %.3f rhs_evals %lld steps %lld sticks %lld\n",
         ne, t_rel, P / (BAR_RHO * BAR_S * BAR_L),
         vi_method_name(vi_sim_method_used(s)), t1 - t0, t2 - t1,
         (long long)vi_sim_stat(s, VI_STAT_RHS_EVALS),
         (long long)vi_sim_stat(s, VI_STAT_STEPS),
         (long long)vi_sim_stat(s, VI_STAT_STICKS));
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
  free(x);
  free(v);
  return 0;
}
