/* vi_nvector.c - the hot N_Vector operations compiled with our flags.
 *
 * Debian's SUNDIALS 6.4 is built without optimisation, and its serial vector
 * operations take a third of an Adams run (perf).  The op table is SUNDIALS'
 * documented extension point: we keep the serial vector's layout and
 * replace the operations CVODE calls on every step.  Clones copy the table,
 * so patching the template vector before CVodeInit covers all of CVODE's
 * vectors. */
#include <math.h>

#include <nvector/nvector_serial.h>

#include "vi_sim_state.h"

#define LEN(v) NV_LENGTH_S(v)
#define DAT(v) NV_DATA_S(v)

static void linearsum(double a, N_Vector x, double b, N_Vector y, N_Vector z)
{
  const double *xd = DAT(x), *yd = DAT(y);
  double *zd = DAT(z);
  for (sunindextype i = 0, n = LEN(x); i < n; i++) zd[i] = a * xd[i] + b * yd[i];
}

static void scale(double c, N_Vector x, N_Vector z)
{
  const double *xd = DAT(x);
  double *zd = DAT(z);
  for (sunindextype i = 0, n = LEN(x); i < n; i++) zd[i] = c * xd[i];
}

static void constant(double c, N_Vector z)
{
  double *zd = DAT(z);
  for (sunindextype i = 0, n = LEN(z); i < n; i++) zd[i] = c;
}

static void prod(N_Vector x, N_Vector y, N_Vector z)
{
  const double *xd = DAT(x), *yd = DAT(y);
  double *zd = DAT(z);
  for (sunindextype i = 0, n = LEN(x); i < n; i++) zd[i] = xd[i] * yd[i];
}

static void vabs(N_Vector x, N_Vector z)
{
  const double *xd = DAT(x);
  double *zd = DAT(z);
  for (sunindextype i = 0, n = LEN(x); i < n; i++) zd[i] = fabs(xd[i]);
}

static void inv(N_Vector x, N_Vector z)
{
  const double *xd = DAT(x);
  double *zd = DAT(z);
  for (sunindextype i = 0, n = LEN(x); i < n; i++) zd[i] = 1.0 / xd[i];
}

static void addconst(N_Vector x, double b, N_Vector z)
{
  const double *xd = DAT(x);
  double *zd = DAT(z);
  for (sunindextype i = 0, n = LEN(x); i < n; i++) zd[i] = xd[i] + b;
}

static double maxnorm(N_Vector x)
{
  const double *xd = DAT(x);
  double m = 0.0;
  for (sunindextype i = 0, n = LEN(x); i < n; i++) m = fmax(m, fabs(xd[i]));
  return m;
}

static double wrmsnorm(N_Vector x, N_Vector w)
{
  const double *xd = DAT(x), *wd = DAT(w);
  double s = 0.0;
  sunindextype n = LEN(x);
  for (sunindextype i = 0; i < n; i++) s += (xd[i] * wd[i]) * (xd[i] * wd[i]);
  return sqrt(s / (double)n);
}

/* z = sum_k c_k X_k: Nordsieck-array work (prediction, interpolation) and
 * every Runge-Kutta stage.  Zero coefficients after the first are skipped
 * (a third of a Fehlberg 7(8) tableau, and all but three terms of its error
 * estimate) and the rest are taken four at a time, so z is read and written
 * once per four vectors. */
static int linearcombination(int nv, double *c, N_Vector *X, N_Vector z)
{
  double *zd = DAT(z);
  sunindextype n = LEN(z);
  int k = 1;
  if (X[0] == z) { /* as SUNDIALS' own: only X[0] may be z */
    if (c[0] != 1.0)
      for (sunindextype i = 0; i < n; i++) zd[i] *= c[0];
  } else {
    const double *x0 = DAT(X[0]);
    double c0 = c[0];
    for (sunindextype i = 0; i < n; i++) zd[i] = c0 * x0[i];
  }
  const double *xs[4] = {NULL, NULL, NULL, NULL};
  double cs[4] = {0.0, 0.0, 0.0, 0.0};
  int m = 0;
  for (; k <= nv; k++) {
    if (k < nv) {
      if (c[k] == 0.0) continue;
      xs[m] = DAT(X[k]);
      cs[m++] = c[k];
      if (m < 4) continue;
    }
    const double *x0 = xs[0], *x1 = xs[1], *x2 = xs[2], *x3 = xs[3];
    switch (m) {
    case 4:
      for (sunindextype i = 0; i < n; i++)
        zd[i] += cs[0] * x0[i] + cs[1] * x1[i] + cs[2] * x2[i] + cs[3] * x3[i];
      break;
    case 3:
      for (sunindextype i = 0; i < n; i++)
        zd[i] += cs[0] * x0[i] + cs[1] * x1[i] + cs[2] * x2[i];
      break;
    case 2:
      for (sunindextype i = 0; i < n; i++) zd[i] += cs[0] * x0[i] + cs[1] * x1[i];
      break;
    case 1:
      for (sunindextype i = 0; i < n; i++) zd[i] += cs[0] * x0[i];
      break;
    default: break;
    }
    m = 0;
  }
  return 0;
}

/* Z_k = a_k x + Y_k */
static int scaleaddmulti(int nv, double *a, N_Vector x, N_Vector *Y, N_Vector *Z)
{
  const double *xd = DAT(x);
  sunindextype n = LEN(x);
  for (int k = 0; k < nv; k++) {
    const double *yd = DAT(Y[k]);
    double *zd = DAT(Z[k]);
    for (sunindextype i = 0; i < n; i++) zd[i] = a[k] * xd[i] + yd[i];
  }
  return 0;
}

void vi_nvector_fast_ops(N_Vector v)
{
  v->ops->nvlinearsum = linearsum;
  v->ops->nvscale = scale;
  v->ops->nvconst = constant;
  v->ops->nvprod = prod;
  v->ops->nvabs = vabs;
  v->ops->nvinv = inv;
  v->ops->nvaddconst = addconst;
  v->ops->nvmaxnorm = maxnorm;
  v->ops->nvwrmsnorm = wrmsnorm;
  v->ops->nvlinearcombination = linearcombination;
  v->ops->nvscaleaddmulti = scaleaddmulti;
}
