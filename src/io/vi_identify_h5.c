/* vi_identify_h5.c - an identification to HDF5 (vi_identify_io.h): the
 * recording, the fitted response, residuals and phases for the plot
 * (share/plot_identify.py), and the fit with its uncertainty. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hdf5.h>

#include "vi_h5_image.h"
#include "vi_io_internal.h"
#include "vibroimpact.h"
#include "vibroimpact/vi_identify_io.h"
#include "vibroimpact/vi_output.h"
#include "vibroimpact/vi_writer.h"

static int put(hid_t g, const char *name, const double *a, hsize_t n0,
               hsize_t n1)
{
  hsize_t dims[2] = {n0, n1};
  hid_t sp = H5Screate_simple(n1 ? 2 : 1, dims, NULL);
  hid_t ds = sp < 0 ? -1 : H5Dcreate2(g, name, H5T_IEEE_F64LE, sp, H5P_DEFAULT,
                                      H5P_DEFAULT, H5P_DEFAULT);
  int bad = ds < 0 || H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL,
                               H5P_DEFAULT, a) < 0;
  if (ds >= 0) H5Dclose(ds);
  if (sp >= 0) H5Sclose(sp);
  return bad;
}

static int attr(hid_t g, const char *name, double v)
{
  hid_t sp = H5Screate(H5S_SCALAR);
  hid_t a = H5Acreate2(g, name, H5T_IEEE_F64LE, sp, H5P_DEFAULT, H5P_DEFAULT);
  int bad = a < 0 || H5Awrite(a, H5T_NATIVE_DOUBLE, &v) < 0;
  if (a >= 0) H5Aclose(a);
  H5Sclose(sp);
  return bad;
}

static int attr_str(hid_t g, const char *name, const char *s)
{
  hid_t ty = H5Tcopy(H5T_C_S1);
  H5Tset_size(ty, strlen(s) + 1);
  hid_t sp = H5Screate(H5S_SCALAR);
  hid_t a = H5Acreate2(g, name, ty, sp, H5P_DEFAULT, H5P_DEFAULT);
  int bad = a < 0 || H5Awrite(a, ty, s) < 0;
  if (a >= 0) H5Aclose(a);
  H5Sclose(sp);
  H5Tclose(ty);
  return bad;
}

int vi_identify_write_h5(const char *path, const vi_identify *id,
                         const char *keys, int ns, const double *t,
                         const double *x, vi_diag *diag)
{
  if (diag) memset(diag, 0, sizeof *diag);
  if (!path || !id || !t || !x || ns < 1) return VI_ERR_ARG;
  int conv, it, n, m, np;
  double rms, noise, rcond, t0, t0se, r12, vN;
  int st = vi_identify_summary(id, &conv, &it, &rms, &noise, &rcond, &n, &m);
  if (st) return st;
  vi_identify_shift(id, &t0, &t0se);
  vi_identify_energy_restitution(id, &r12, &vN, NULL, NULL);
  np = vi_identify_nparams(id);
  char target[4096];
  if ((st = vi_output_resolve(path, target, sizeof target, diag))) return st;
  size_t nsz = (size_t)ns;
  double *buf = malloc(sizeof(double) * (4 * nsz + 5 * (size_t)np + (size_t)np * np + 8));
  if (!buf) return VI_ERR_NOMEM;
  double *mo = buf, *res = mo + nsz, *ph = res + nsz, *tt = ph + nsz;
  double *val = tt + nsz, *se = val + np, *lo = se + np, *hi = lo + np,
         *fl = hi + np, *R = fl + np, *t1 = R + (size_t)np * np;
  int *ifl = malloc(sizeof(int) * (size_t)np);
  double period = NAN;
  st = ifl ? vi_identify_response(id, ns, t, mo, NULL) : VI_ERR_NOMEM;
  if (!st) st = vi_identify_params(id, val, se, lo, hi, ifl);
  if (!st) st = vi_identify_correlation(id, R, np);
  if (!st) st = vi_identify_orbit_period(id, &period, t1);
  if (st) {
    free(buf);
    free(ifl);
    return st;
  }
  for (int j = 0; j < np; j++) fl[j] = ifl[j];
  free(ifl);
  for (int i = 0; i < ns; i++) {
    res[i] = x[i] - mo[i];
    double p = fmod(t[i] + t0 - t1[0], period) / period;
    ph[i] = p < 0 ? p + 1.0 : p;
  }
  char part[4200];
  if (vi_output_part(target, part, (int)sizeof part)) {
    free(buf);
    return VI_ERR_LIMIT;
  }
  hid_t f = vi_h5_image_create(part); /* in memory: vi_h5_image.h */
  hid_t g = f < 0 ? -1 : H5Gcreate2(f, "identify", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  int bad = g < 0;
  if (!bad) {
    bad |= put(g, "t", t, nsz, 0) | put(g, "x", x, nsz, 0) |
           put(g, "model", mo, nsz, 0) | put(g, "residual", res, nsz, 0) |
           put(g, "phase", ph, nsz, 0);
    bad |= put(g, "value", val, np, 0) | put(g, "stderr", se, np, 0) |
           put(g, "lo95", lo, np, 0) | put(g, "hi95", hi, np, 0) |
           put(g, "flags", fl, np, 0) | put(g, "correlation", R, np, np);
    bad |= attr_str(g, "keys", keys ? keys : "");
    bad |= attr(g, "shift", t0) | attr(g, "shift_stderr", t0se) |
           attr(g, "period", period) | attr(g, "orbit_n", n) |
           attr(g, "orbit_m", m) | attr(g, "converged", conv) |
           attr(g, "iterations", it) | attr(g, "rms_residual", rms) |
           attr(g, "noise", noise) | attr(g, "rcond", rcond) |
           attr(g, "r_energy_balance", r12) | attr(g, "vN_recorded", vN);
  }
  if (g >= 0) H5Gclose(g);
  free(buf);
  if (f < 0)
    return vi_diag_set(diag, target, VI_ERR_IO, 0, 0, "", "",
                       "cannot create %s", part);
  return vi_h5_image_commit(f, bad, target, diag); /* through TARGET.part */
}
