/* vi_bench_band.c - long chains in band storage: time per forcing period
 * and peak resident memory for n = 1000, 5000, 20000 masses (Adams and
 * BDF with the band solver; Adams also at 100000), against the dense model
 * at n = 1000, a consistent (banded, not diagonal) mass at n = 20000 (a
 * band Cholesky solve per right-hand side), and the memory estimate made
 * before allocating.  Each case runs in a child process so that its peak
 * RSS is its own.  Prints figures; asserts nothing.
 *   vi_bench_band [periods]   (default 5) */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <gsl/gsl_errno.h>

#include "vibroimpact.h"

static double now(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* A damped chain, m = k = 1, c = 0.01, forced on its last mass, which
 * meets a stop at 0.02 with r = 0.8; Omega = 1 lies inside the band of
 * the chain's frequencies (0, 2). */
static int run_case(int n, int band, int method, int periods)
{
  double *mass = malloc(sizeof(double) * 4 * (size_t)n);
  if (!mass) return 1;
  double *k = mass + n, *c = k + n, *a = c + n;
  for (int j = 0; j < n; j++) {
    mass[j] = k[j] = 1.0;
    c[j] = 0.01;
    a[j] = 0.0;
  }
  a[n - 1] = 0.5;
  double t0 = now();
  vi_model *m = NULL;
  int st;
  if (band == 1) {
    st = vi_model_create_chain(n, mass, k, c, &m);
  } else if (band == 2) { /* consistent mass m/6 tridiag(1, 4, 1): M^-1 by
                             band Cholesky solves */
    double *B = malloc(sizeof(double) * 6 * (size_t)n);
    st = B ? vi_model_create_band(n, 1, &m) : VI_ERR_NOMEM;
    if (!st) st = vi_build_chain_band(n, mass, k, c, B, B + 2 * (size_t)n,
                                      B + 4 * (size_t)n, 2);
    for (size_t j = 0; B && j < (size_t)n; j++) {
      B[2 * j] = j ? 1.0 / 6.0 : 0.0;
      B[2 * j + 1] = 4.0 / 6.0;
    }
    if (!st) st = vi_model_set_mass_band(m, 1, B, 2);
    if (!st) st = vi_model_set_damping_band(m, 1, B + 2 * (size_t)n, 2);
    if (!st) st = vi_model_set_stiffness_band(m, 1, B + 4 * (size_t)n, 2);
    free(B);
  } else {
    double *M = malloc(sizeof(double) * 3 * (size_t)n * n);
    st = M ? vi_model_create(n, &m) : VI_ERR_NOMEM;
    if (!st) st = vi_build_chain(n, mass, k, c, M, M + (size_t)n * n,
                                 M + 2 * (size_t)n * n, n);
    if (!st) st = vi_model_set_mass(m, M, n);
    if (!st) st = vi_model_set_damping(m, M + (size_t)n * n, n);
    if (!st) st = vi_model_set_stiffness(m, M + 2 * (size_t)n * n, n);
    free(M);
  }
  double *w = c; /* reuse: the stop vector */
  for (int j = 0; j < n; j++) w[j] = j == n - 1 ? 1.0 : 0.0;
  if (!st) st = vi_model_set_forcing(m, 1.0, a, NULL, NULL);
  if (!st) st = vi_model_set_stop(m, w, 0.02, 0.8);
  if (!st) st = vi_model_setup(m);
  double t_setup = now() - t0;
  vi_sim *s = NULL;
  if (!st) st = vi_sim_create(m, &s);
  if (!st) st = vi_sim_set_method(s, method);
  if (!st) st = vi_sim_set_tolerances(s, 1e-8, 1e-10);
  double t1 = now();
  if (!st) st = vi_sim_run(s, periods * 2.0 * M_PI);
  double t_run = now() - t1;
  if (st) {
    fprintf(stderr, "n = %d: %s: %s %s\n", n, vi_strerror(st),
            vi_model_errmsg(m), s ? vi_sim_errmsg(s) : "");
  } else {
    printf("%-5s %-5s n = %5d  setup %8.3f s  %9.4f s per period  "
           "%6lld steps  %4lld impacts  model %8.2f MB",
           band == 2 ? "bandM" : band ? "band" : "dense",
           vi_method_name(method), n, t_setup,
           t_run / periods, (long long)vi_sim_stat(s, VI_STAT_STEPS),
           (long long)vi_sim_stat(s, VI_STAT_IMPACTS),
           (double)vi_model_memory(m) / 1048576.0);
    fflush(stdout);
  }
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
  free(mass);
  return st != VI_OK;
}

/* Run one case in a child; print its peak RSS and the estimate. */
static void measure(int n, int band, int method, int periods)
{
  int64_t est = 0;
  vi_model_memory_estimate(n, band ? 1 : -1, 1, method, 0, &est);
  fflush(stdout);
  pid_t pid = fork();
  if (pid == 0) _exit(run_case(n, band, method, periods));
  struct rusage ru;
  int status = 0;
  if (pid < 0 || wait4(pid, &status, 0, &ru) < 0) {
    printf("  (fork failed)\n");
    return;
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0)
    printf("  peak RSS %8.1f MB  (estimate %8.1f MB)\n",
           (double)ru.ru_maxrss / 1024.0, (double)est / 1048576.0);
  else
    printf("  failed\n");
}

int main(int argc, char **argv)
{
  gsl_set_error_handler_off();
  long periods = argc > 1 ? strtol(argv[1], NULL, 10) : 5;
  if (periods < 1 || periods > 100000) periods = 5;
  printf("chain m = k = 1, c = 0.01, forced and stopped at its free end; "
         "%ld periods, rtol 1e-8\n", periods);
  measure(1000, 0, VI_METHOD_ADAMS, (int)periods);
  const int ns[4] = {1000, 5000, 20000, 100000};
  for (int i = 0; i < 4; i++) measure(ns[i], 1, VI_METHOD_ADAMS, (int)periods);
  for (int i = 0; i < 3; i++) measure(ns[i], 1, VI_METHOD_BDF, (int)periods);
  /* a banded (consistent) mass: a band solve per right-hand side */
  measure(20000, 2, VI_METHOD_ADAMS, (int)periods);
  return 0;
}
