/* vi_builders.c - model builders (vi_builders.h): the clamped-free
 * Euler-Bernoulli cantilever's modes and the Galerkin model of the paper's
 * beam example (MODEL.md section 6, WB section 4), and the reduced model
 * that keeps a subset of a model's modes (MODEL.md section 5).  The chain
 * builders (dense, band, vi_model_create_chain) live in vi_model.c: the
 * band chain is built into the model's own storage. */
#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "vi_storage.h"

double vi_cantilever_beta(int j)
{
  if (j < 0 || j > 200) return NAN;
  /* cos b cosh b = -1 divided by cosh b: f(b) = cos b + sech b, whose root
   * lies within 0.3 of (j + 1/2) pi, where f' = -sin b - sech b tanh b is
   * far from zero.  Newton converges in a few steps; no allocation, since
   * every shape evaluation needs beta. */
  double b = (j + 0.5) * M_PI;
  for (int it = 0; it < 50; it++) {
    double sech = 1.0 / cosh(b);
    double f = cos(b) + sech, fp = -sin(b) - sech * tanh(b);
    double step = f / fp;
    b -= step;
    if (fabs(step) <= 4.0 * DBL_EPSILON * b) break;
  }
  return b;
}

/* s_j = (cosh b + cos b) / (sinh b + sin b), and 1 - s_j without the
 * cancellation of sinh b - cosh b = -e^{-b}. */
static void sigma(double b, double *s, double *one_minus_s)
{
  double den = sinh(b) + sin(b);
  *s = (cosh(b) + cos(b)) / den;
  *one_minus_s = (-exp(-b) + sin(b) - cos(b)) / den;
}

double vi_cantilever_shape(int j, double xi)
{
  double b = vi_cantilever_beta(j), s, oms;
  if (!isfinite(b)) return NAN;
  sigma(b, &s, &oms);
  double y = b * xi;
  /* cosh y - s sinh y = ((1 - s) e^y + (1 + s) e^-y) / 2: stable for large b */
  return 0.5 * (oms * exp(y) + (1.0 + s) * exp(-y)) - cos(y) + s * sin(y);
}

double vi_cantilever_participation(int j)
{
  double b = vi_cantilever_beta(j), s, oms;
  if (!isfinite(b)) return NAN;
  sigma(b, &s, &oms);
  return 2.0 * s / b;
}

int vi_build_cantilever(int modes, double omega1, double zeta, double xi_stop,
                        double *M, double *C, double *K, int ld, double *w,
                        double *gamma)
{
  if (modes < 1 || ld < modes) return VI_ERR_DIM;
  if (modes > 201) return VI_ERR_LIMIT; /* beta_j is tabulated for j <= 200 */
  if (!M || !C || !K || !w) return VI_ERR_ARG;
  if (!(omega1 > 0.0) || !(zeta >= 0.0) || !(xi_stop >= 0.0 && xi_stop <= 1.0))
    return VI_ERR_ARG;
  double b1 = vi_cantilever_beta(0);
  for (int j = 0; j < modes; j++) {
    for (int i = 0; i < modes; i++)
      M[i + (size_t)j * ld] = C[i + (size_t)j * ld] = K[i + (size_t)j * ld] = 0;
    double bj = vi_cantilever_beta(j), om = omega1 * (bj / b1) * (bj / b1);
    M[j + (size_t)j * ld] = 1.0;
    K[j + (size_t)j * ld] = om * om;
    C[j + (size_t)j * ld] = 2.0 * zeta * om;
    w[j] = vi_cantilever_shape(j, xi_stop);
    if (gamma) gamma[j] = vi_cantilever_participation(j);
  }
  /* at the clamp every shape is 0 (round-off of cosh - cos): a stop there
   * could never be reached.  Near it phi_j ~ beta_j^2 xi^2: refuse a w
   * whose largest entry is round-off against the tip's |phi_j(1)| = 2 */
  double wmax = 0.0;
  for (int j = 0; j < modes; j++) wmax = fmax(wmax, fabs(w[j]));
  if (!(xi_stop > 0.0) || !(wmax > 1e-10)) return VI_ERR_STOP_VECTOR;
  return VI_OK;
}

/* ---- the reduced model --------------------------------------------------- */
int vi_model_create_reduced(const vi_model *full, const int *modes, int k,
                            double r, vi_model **out)
{
  if (!out) return VI_ERR_ARG;
  *out = NULL;
  if (!full || !modes || k < 1 || k > full->n) return VI_ERR_ARG;
  if (!full->frozen) return VI_ERR_STATE;
  if (full->ns > 1) return VI_ERR_UNSUPPORTED; /* one stop is reduced */
  if (!vi_model_has_modes(full)) return VI_ERR_UNSUPPORTED; /* band: no modes */
  int n = full->n, st;
  double *buf = calloc(4 * (size_t)k * k + 5 * (size_t)k, sizeof(double));
  if (!buf) return VI_ERR_NOMEM;
  size_t kk = (size_t)k * k;
  double *M = buf, *K = M + kk, *C = K + kk, *w = C + kk;
  double *a = w + k, *b = a + k, *f0 = b + k;
  for (int p = 0; p < k; p++) {
    int j = modes[p];
    int seen = 0; /* a subset: a mode kept twice would count it twice */
    for (int q = 0; q < p; q++) seen |= modes[q] == j;
    if (j < 0 || j >= n || seen) { free(buf); return VI_ERR_ARG; }
    M[p + p * k] = 1.0;
    K[p + p * k] = full->lambda[j];
    for (int q = 0; q < k; q++) C[p + q * k] = full->D[j + (size_t)modes[q] * n];
    w[p] = full->PsiW[j];
    a[p] = full->Fa[j];
    b[p] = full->Fb[j];
    f0[p] = full->F0[j];
  }
  vi_model *m = NULL;
  st = vi_model_create(k, &m);
  if (!st) st = vi_model_set_mass(m, M, k);
  if (!st) st = vi_model_set_stiffness(m, K, k);
  if (!st) st = vi_model_set_damping(m, C, k);
  if (!st) st = vi_model_set_forcing(m, full->omega_f, a, b, f0);
  if (!st) st = vi_model_set_stop(m, w, full->xsv[0], r);
  if (!st) st = vi_model_setup(m);
  free(buf);
  if (st) vi_model_destroy(&m);
  *out = m;
  return st;
}
