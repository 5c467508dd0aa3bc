/* vi_siconos_plugin.c - the harmonic forcing a cos(Omega t) + b sin(Omega t)
 * + f0 as a Siconos external-force plugin (LagrangianDS FExt signature),
 * for bench/workprec.py.  z = (Omega, a[n], b[n], f0[n]). */
#include <math.h>

void vi_fext(double t, unsigned int n, double *f, unsigned int nz, double *z);

void vi_fext(double t, unsigned int n, double *f, unsigned int nz, double *z)
{
  (void)nz;
  double c = cos(z[0] * t), s = sin(z[0] * t);
  for (unsigned int i = 0; i < n; i++)
    f[i] = z[1 + i] * c + z[1 + n + i] * s + z[1 + 2 * n + i];
}
