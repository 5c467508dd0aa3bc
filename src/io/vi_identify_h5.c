/* vi_identify_h5.c - an identification to HDF5 (vi_identify_io.h): the
 * recording, the fitted response, residuals and phases for the plot
 * (share/plot_identify.py), the fit with its uncertainty, and every
 * fit the data admit (group solutions). */
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

/* Group `solutions`: every fit the data admit, best first (row k of each
 * [nsol x np] table is solution k), and the best's profile intervals in g
 * beside its Jacobian ones.  0, or nonzero on failure. */
static int solutions(hid_t g, const vi_identify *id, int np)
{
  int unique = 1, nsol = vi_identify_nsolutions(id, &unique), bad = 0;
  if (nsol < 1) return 1;
  size_t nt = (size_t)nsol * np;
  double *b = malloc(sizeof(double) * (8 * nt + 7 * (size_t)nsol));
  int *fi = malloc(sizeof(int) * 2 * (size_t)np);
  if (!b || !fi) {
    free(b);
    free(fi);
    return 1;
  }
  double *val = b, *se = val + nt, *lo = se + nt, *hi = lo + nt, *pl = hi + nt,
         *ph = pl + nt, *fl = ph + nt, *pfl = fl + nt, *on = pfl + nt,
         *om = on + nsol, *rms = om + nsol, *rat = rms + nsol, *dc = rat + nsol,
         *sd = dc + nsol, *sl = sd + nsol;
  for (int k = 0; k < nsol && !bad; k++) {
    size_t o = (size_t)k * np;
    int n = 0, m = 0;
    bad |= vi_identify_solution(id, k, val + o, se + o, lo + o, hi + o, fi) != VI_OK;
    bad |= vi_identify_solution_profile(id, k, pl + o, ph + o, fi + np) != VI_OK;
    bad |= vi_identify_solution_summary(id, k, &n, &m, rms + k, rat + k, dc + k, NULL) != VI_OK;
    bad |= vi_identify_solution_separation(id, k, sd + k, sl + k) != VI_OK;
    for (int j = 0; j < np; j++) {
      fl[o + j] = fi[j];
      pfl[o + j] = fi[np + j];
    }
    on[k] = n;
    om[k] = m;
  }
  /* the best's profile intervals beside its Jacobian ones */
  if (!bad)
    bad |= vec(g, "profile_lo95", pl, np) | vec(g, "profile_hi95", ph, np) |
           vec(g, "profile_flags", pfl, np);
  hid_t s = bad ? -1 : vi_h5_group(g, "solutions");
  bad |= s < 0;
  if (!bad) {
    hsize_t d2[2] = {(hsize_t)nsol, (hsize_t)np}, d1 = (hsize_t)nsol;
    static const char *const tn[8] = {"value", "stderr", "lo95", "hi95",
                                      "profile_lo95", "profile_hi95", "flags",
                                      "profile_flags"};
    const double *tv[8] = {val, se, lo, hi, pl, ph, fl, pfl};
    for (int q = 0; q < 8; q++)
      bad |= vi_h5_put(s, tn[q], H5T_NATIVE_DOUBLE, 2, d2, tv[q], NULL);
    static const char *const cn[7] = {"orbit_n", "orbit_m", "rms_residual",
                                      "residual_ratio", "delta_chi2",
                                      "separation", "record_factor"};
    const double *cv[7] = {on, om, rms, rat, dc, sd, sl};
    for (int q = 0; q < 7; q++)
      bad |= vi_h5_put(s, cn[q], H5T_NATIVE_DOUBLE, 1, &d1, cv[q], NULL);
    bad |= vi_h5_attr_int(s, "unique", unique) | vi_h5_attr_int(s, "count", nsol);
  }
  bad |= vi_h5_close(s);
  free(b);
  free(fi);
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
    bad |= solutions(g, id, np);
  }
  bad |= vi_h5_close(g);
  free(buf);
  if (f < 0)
    return vi_diag_set(diag, target, VI_ERR_IO, 0, 0, "", "",
                       "cannot create %s", part);
  return vi_h5_image_commit(f, bad, target, diag); /* through TARGET.part */
}
