/* vi_identify_h5.c - an identification to HDF5 (vi_identify_io.h): the
 * recording, the fitted response, residuals and phases for the plot
 * (share/plot_identify.py), and the fit with its uncertainty. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hdf5.h>

#include "vi_h5_util.h"
#include "vi_io_internal.h"
#include "vibroimpact.h"
#include "vibroimpact/vi_identify_io.h"
#include "vibroimpact/vi_output.h"
#include "vibroimpact/vi_writer.h"

/* A vector [n] of doubles. */
static int vec(hid_t g, const char *name, const double *a, hsize_t n)
{
  return vi_h5_put(g, name, H5T_NATIVE_DOUBLE, 1, &n, a, NULL);
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
  hid_t f = vi_h5_image_create(part, (size_t)1 << 16); /* in memory */
  hid_t g = f < 0 ? -1 : vi_h5_group(f, "identify");
  int bad = g < 0;
  if (!bad) {
    hsize_t dR[2] = {(hsize_t)np, (hsize_t)np};
    bad |= vec(g, "t", t, nsz) | vec(g, "x", x, nsz) |
           vec(g, "model", mo, nsz) | vec(g, "residual", res, nsz) |
           vec(g, "phase", ph, nsz);
    bad |= vec(g, "value", val, np) | vec(g, "stderr", se, np) |
           vec(g, "lo95", lo, np) | vec(g, "hi95", hi, np) |
           vec(g, "flags", fl, np) |
           vi_h5_put(g, "correlation", H5T_NATIVE_DOUBLE, 2, dR, R, NULL);
    bad |= vi_h5_attr_str(g, "keys", keys ? keys : "");
    static const char *const names[12] = {
        "shift", "shift_stderr", "period", "orbit_n", "orbit_m", "converged",
        "iterations", "rms_residual", "noise", "rcond", "r_energy_balance",
        "vN_recorded"};
    const double v[12] = {t0, t0se, period, n, m, conv, it, rms, noise, rcond,
                          r12, vN};
    for (int k = 0; k < 12; k++) bad |= vi_h5_attr_double(g, names[k], v[k]);
  }
  bad |= vi_h5_close(g);
  free(buf);
  if (f < 0)
    return vi_diag_set(diag, target, VI_ERR_IO, 0, 0, "", "",
                       "cannot create %s", part);
  return vi_h5_image_commit(f, bad, target, diag); /* through TARGET.part */
}
