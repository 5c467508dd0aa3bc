/* vi_bar.h - Siconos' impacting bar (examples/Mechanics/ImpactingBar): a free
 * elastic bar of ne linear elements with consistent mass (E, S, L, rho),
 * all nodes at x = 5e-5 moving at v = -0.1, node 1 on a rigid obstacle
 * x_1 >= 0 (the stop -x_1 <= 0) with r = 0.  Shared by the test
 * tests/sim/test_held.c and the benchmark bench/vi_bench_bar.c. */
#ifndef VI_BAR_H
#define VI_BAR_H

#include <stdlib.h>
#include <string.h>

#include <vibroimpact/vi_model.h>

#define BAR_E 210e9
#define BAR_S 3.14e-4
#define BAR_L 1.0
#define BAR_RHO 7800.0
#define BAR_X0 5e-5
#define BAR_V0 -0.1

/* The bar's model (dense M, K) with restitution r at the obstacle (the
 * example: 0), set up; NULL on failure. */
static inline vi_model *bar_model(int ne, double r)
{
  int n = ne + 1;
  double h = BAR_L / ne, mm = BAR_RHO * BAR_S * h, kk = BAR_E * BAR_S / h;
  double *M = calloc((size_t)n * n, sizeof(double));
  double *K = calloc((size_t)n * n, sizeof(double));
  double *w = calloc((size_t)n, sizeof(double));
  vi_model *m = NULL;
  if (!M || !K || !w || vi_model_create(n, &m)) goto out;
  for (int e = 0; e < ne; e++) { /* element e joins nodes e, e + 1 */
    int i = e, j = e + 1;
    M[i + (size_t)i * n] += mm / 3.0;
    M[j + (size_t)j * n] += mm / 3.0;
    M[i + (size_t)j * n] += mm / 6.0;
    M[j + (size_t)i * n] += mm / 6.0;
    K[i + (size_t)i * n] += kk;
    K[j + (size_t)j * n] += kk;
    K[i + (size_t)j * n] -= kk;
    K[j + (size_t)i * n] -= kk;
  }
  w[0] = -1.0;
  if (vi_model_set_mass(m, M, n) || vi_model_set_stiffness(m, K, n) ||
      vi_model_set_stop(m, w, 0.0, r) || vi_model_setup(m))
    vi_model_destroy(&m);
out:
  free(M);
  free(K);
  free(w);
  return m;
}

#endif
