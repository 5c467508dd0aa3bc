/* vi_minimize.c - the least value of a function of one variable on an
 * interval, by golden section (vi_internal.h). */
#include <math.h>

#include "vi_internal.h"

double vi_golden_min(double (*f)(void *ctx, double x), void *ctx, double a, double b,
                     double tol, int maxit, double *fx)
{
  const double g = 0.5 * (sqrt(5.0) - 1.0);
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = f(ctx, c), fd = f(ctx, d);
  for (int it = 0; it < maxit && fabs(b - a) > tol; it++) {
    /* a NaN on the right (beyond where f is defined) moves left */
    if (fc <= fd || isnan(fd)) {
      b = d;
      d = c;
      fd = fc;
      c = b - g * (b - a);
      fc = f(ctx, c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + g * (b - a);
      fd = f(ctx, d);
    }
  }
  int left = fc <= fd || isnan(fd);
  if (fx) *fx = left ? fc : fd;
  return left ? c : d;
}
