/* vi_beam.c - clamped-free Euler-Bernoulli cantilever modes and the Galerkin
 * model of the paper's beam example (MODEL.md section 6, WB section 4). */
#include <float.h>
#include <math.h>

#include "vi_internal.h"

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
  return VI_OK;
}
