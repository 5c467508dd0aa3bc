/* vi_bench_curves.c - what a two-parameter curve costs (vi_cont_curve.h):
 * the Fig. 2 chain's curves of `vibroimpact curves` (doc/curves.md),
 * each located from the scene's orbit and followed over its range with
 * the command's default largest step (1/200 of the range), timed R times
 * and the least CPU time kept (the machine may be shared).  Prints the
 * points, the codimension-two points and the seconds per curve, and the
 * microseconds per point; then the pd curve of a model of N coordinates
 * (Fig. 2 beside N - 2 oscillators it does not touch), 20 points.
 *
 * Usage: vi_bench_curves [R]   (default 5) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <vibroimpact.h>

static double cpu(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The Fig. 2 chain (c the dashpots, x_s and r the stop's). */
static vi_model *fig2(double c1, double xs, double r)
{
  const double mass[2] = {1, 1}, k[2] = {1, 1}, c[2] = {c1, c1};
  const double a[2] = {0.5, 0}, w[2] = {0, 1};
  double M[4], C[4], K[4];
  vi_model *m = NULL;
  vi_build_chain(2, mass, k, c, M, C, K, 2);
  if (vi_model_create(2, &m)) return NULL;
  vi_model_set_mass(m, M, 2);
  vi_model_set_damping(m, C, 2);
  vi_model_set_stiffness(m, K, 2);
  vi_model_set_forcing(m, 0.9, a, NULL, NULL);
  vi_model_set_stop(m, w, xs, r);
  if (vi_model_setup(m)) vi_model_destroy(&m);
  return m;
}

/* Fig. 2 beside N - 2 oscillators it does not touch (unforced, off the
 * stop, omega_i from 2.3 up by 0.25, 2 % damping): its orbits and curves
 * are Fig. 2's, in a model of N coordinates. */
static vi_model *fig2_beside(int N)
{
  double *M = calloc(3 * (size_t)N * N + 3 * (size_t)N, sizeof(double));
  if (!M) return NULL;
  double *C = M + (size_t)N * N, *K = C + (size_t)N * N, *a = K + (size_t)N * N, *w = a + N,
         *f0 = w + N;
  const double E[4] = {2, -1, -1, 1};
  vi_model *m = NULL;
  a[0] = 0.5;
  w[1] = 1;
  for (int i = 0; i < N; i++) M[i + (size_t)i * N] = 1;
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2; j++) {
      K[i + (size_t)j * N] = E[i + 2 * j];
      C[i + (size_t)j * N] = 0.1 * E[i + 2 * j];
    }
  for (int i = 2; i < N; i++) {
    K[i + (size_t)i * N] = pow(2.3 + 0.25 * (i - 2), 2);
    C[i + (size_t)i * N] = 0.04 * (2.3 + 0.25 * (i - 2));
  }
  if (!vi_model_create(N, &m) && (vi_model_set_mass(m, M, N) || vi_model_set_damping(m, C, N) ||
                                  vi_model_set_stiffness(m, K, N) ||
                                  vi_model_set_forcing(m, 1.6, a, NULL, f0) ||
                                  vi_model_set_stop(m, w, 0.1, 0.7) || vi_model_setup(m)))
    vi_model_destroy(&m);
  free(M);
  return m;
}

/* Its pd curve in (Omega, r) from the P(1,1) orbit at Omega = 1.6: the
 * CPU seconds of 20 points (-1: failed). */
static double beside(int N)
{
  vi_model *m = fig2_beside(N);
  vi_cont_curve *c = NULL;
  double *x = malloc(sizeof(double) * 2 * (size_t)N), *v = x ? x + N : NULL, t = 0, t0 = cpu();
  int found = 0, st = m && x ? VI_OK : VI_ERR_NOMEM, n = 0;
  if (!st) st = vi_orbit_p1_scan(m, 1, 720, &t, x, v, N, 1, &found);
  if (!st && !found) st = VI_ERR_NOT_CONVERGED;
  if (!st) st = vi_cont_curve_create(m, VI_CONT_CURVE_PD, 1, 1, "forcing.omega", "stop.r", &c);
  if (!st) st = vi_cont_curve_set_orbit(c, t, x, v);
  if (!st) st = vi_cont_curve_locate(c, 1.62, 2, NULL);
  if (!st) st = vi_cont_curve_set_range(c, 0.6, 0.8, 20);
  for (; !st && n < 20 && !vi_cont_curve_done(c); n++) st = vi_cont_curve_iterate(c);
  double dt = cpu() - t0;
  vi_cont_curve_destroy(&c);
  vi_model_destroy(&m);
  free(x);
  return st || n < 20 ? -1 : dt;
}

typedef struct bcurve {
  const char *name;
  double c, xs, r;
  int kind, mi;
  const char *key, *key2;
  double to, from2, to2;
} bcurve;

/* One curve from scratch; its CPU seconds, points and specials (-1: failed). */
static double one(const bcurve *b, int *npts, int *nsp)
{
  vi_model *m = fig2(b->c, b->xs, b->r);
  vi_cont_curve *c = NULL;
  double t[8], x[16], v[16], t0 = cpu();
  int found = 0, st = m ? VI_OK : VI_ERR_ARG;
  *npts = *nsp = 0;
  if (!st && b->mi) st = vi_orbit_p1_scan(m, 1, 720, t, x, v, 2, 8, &found);
  if (!st && b->mi && !found) st = VI_ERR_NOT_CONVERGED;
  if (!st) st = vi_cont_curve_create(m, b->kind, 1, b->mi, b->key, b->key2, &c);
  if (!st && b->mi) st = vi_cont_curve_set_orbit(c, t[0], x, v);
  if (!st) st = vi_cont_curve_locate(c, b->to, 200, NULL);
  if (!st) st = vi_cont_curve_set_range(c, b->from2, b->to2, 200);
  while (!st && !vi_cont_curve_done(c)) {
    if ((st = vi_cont_curve_iterate(c)) > 0) st = 0;
    else if (!st) (*npts)++;
    *nsp += vi_cont_curve_num_special(c);
  }
  double dt = cpu() - t0;
  vi_cont_curve_destroy(&c);
  vi_model_destroy(&m);
  return st ? -1 : dt;
}

int main(int argc, char **argv)
{
  int R = argc > 1 ? (int)strtol(argv[1], NULL, 10) : 5;
  static const bcurve cs[] = {
      {"pd (Omega, r), r 0.5..0.9", 0.1, 0.1, 0.7, VI_CONT_CURVE_PD, 1, "forcing.omega",
       "stop.r", 1.8, 0.5, 0.9},
      {"grazing P(1,0) (x_s, Omega), Omega 0.5..1.8", 0.1, 0.1, 0.7, VI_CONT_CURVE_GRAZING, 0,
       "stop.xs", "forcing.omega", 5, 0.5, 1.8},
      {"grazing P(1,1) (Omega, x_s), x_s 0..0.5", 0.1, 0.1, 0.7, VI_CONT_CURVE_GRAZING, 1,
       "forcing.omega", "stop.xs", 0.3, 0.0, 0.5},
      {"fold (Omega, x_s) from x_s 0.5, x_s 0..1.5", 0.1, 0.5, 0.7, VI_CONT_CURVE_FOLD, 1,
       "forcing.omega", "stop.xs", 2.5, 0.0, 1.5},
      {"ns (Omega, r), c 0.02, x_s 0.2, r 0.3..0.9", 0.02, 0.2, 0.6, VI_CONT_CURVE_NS, 1,
       "forcing.omega", "stop.r", 3, 0.3, 0.9}};
  if (R < 1) R = 1;
  printf("Two-parameter curves of the Fig. 2 chain, least CPU time of %d runs\n", R);
  printf("  %-46s %7s %8s %9s %10s\n", "curve", "points", "special", "seconds", "us/point");
  int bad = 0;
  for (size_t i = 0; i < sizeof cs / sizeof cs[0]; i++) {
    double best = HUGE_VAL;
    int np = 0, ns = 0;
    for (int k = 0; k < R; k++) {
      double s = one(&cs[i], &np, &ns);
      if (s < 0) {
        best = NAN;
        break;
      }
      best = fmin(best, s);
    }
    bad |= isnan(best);
    printf("  %-46s %7d %8d %9.3f %10.0f\n", cs[i].name, np, ns, best, 1e6 * best / np);
  }
  /* the cost in the model's size: a step grows as N^4 (the condition's
   * Jacobian row, 2 (2N + 3) monodromies of dense 2N x 2N products) */
  printf("Fig. 2 beside N - 2 untouched oscillators: its pd curve in (Omega, r), 20 points\n");
  printf("  %4s %9s %10s\n", "N", "seconds", "ms/point");
  static const int Ns[] = {11, 21, 31};
  for (size_t i = 0; i < sizeof Ns / sizeof Ns[0]; i++) {
    double s = beside(Ns[i]);
    bad |= s < 0;
    printf("  %4d %9.3f %10.1f\n", Ns[i], s, 1e3 * s / 20);
  }
  return bad;
}
