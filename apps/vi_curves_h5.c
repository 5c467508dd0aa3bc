/* vi_curves_h5.c - the curve of `vibroimpact curves` in memory and in an
 * HDF5 file (layout in vi_curves.h and doc/curves.md). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hdf5.h>

#include "vibroimpact/vi_cont_curve.h"
#include "vi_curves.h"

int vi_curve_result_add(vi_curve_result *r, double p, double p2)
{
  if (r->npts == r->cap) {
    int cap = r->cap ? 2 * r->cap : 256;
    double *q = realloc(r->pts, sizeof(double) * 2 * (size_t)cap);
    if (!q) return 1;
    r->pts = q;
    r->cap = cap;
  }
  r->pts[2 * (size_t)r->npts] = p;
  r->pts[2 * (size_t)r->npts + 1] = p2;
  r->npts++;
  return 0;
}

int vi_curve_result_special(vi_curve_result *r, int type, double p, double p2, int located)
{
  if (r->nsp == r->spcap) {
    int cap = r->spcap ? 2 * r->spcap : 16;
    int *t = realloc(r->sp_type, sizeof(int) * (size_t)cap);
    if (t) r->sp_type = t;
    int *l = realloc(r->sp_loc, sizeof(int) * (size_t)cap);
    if (l) r->sp_loc = l;
    double *q = realloc(r->sp_pts, sizeof(double) * 2 * (size_t)cap);
    if (q) r->sp_pts = q;
    if (!t || !l || !q) return 1;
    r->spcap = cap;
  }
  r->sp_type[r->nsp] = type;
  r->sp_loc[r->nsp] = located;
  r->sp_pts[2 * (size_t)r->nsp] = p;
  r->sp_pts[2 * (size_t)r->nsp + 1] = p2;
  r->nsp++;
  return 0;
}

void vi_curve_result_free(vi_curve_result *r)
{
  free(r->pts);
  free(r->sp_type);
  free(r->sp_loc);
  free(r->sp_pts);
  memset(r, 0, sizeof *r);
}

const char *vi_curve_end_name(int state)
{
  static const char *const names[] = {"running", "end of range", "not admissible beyond",
                                      "closed", "corrector failed", "point limit",
                                      "resonance (beyond, a neutral saddle)"};
  return state >= 0 && state <= VI_CONT_CURVE_RESONANCE ? names[state] : "?";
}

static int attr_str(hid_t loc, const char *name, const char *s)
{
  hid_t ty = H5Tcopy(H5T_C_S1), sp = H5Screate(H5S_SCALAR);
  H5Tset_size(ty, strlen(s) + 1);
  hid_t at = H5Acreate2(loc, name, ty, sp, H5P_DEFAULT, H5P_DEFAULT);
  int bad = at < 0 || H5Awrite(at, ty, s) < 0;
  if (at >= 0) H5Aclose(at);
  H5Sclose(sp);
  H5Tclose(ty);
  return bad;
}

static int attr_num(hid_t loc, const char *name, hid_t ty, const void *v, hsize_t n)
{
  hid_t sp = H5Screate_simple(1, &n, NULL);
  hid_t at = H5Acreate2(loc, name, ty, sp, H5P_DEFAULT, H5P_DEFAULT);
  int bad = at < 0 || H5Awrite(at, ty, v) < 0;
  if (at >= 0) H5Aclose(at);
  H5Sclose(sp);
  return bad;
}

static int dset(hid_t g, const char *name, hid_t ty, const void *v, int rank, hsize_t n0)
{
  hsize_t dims[2] = {n0, 2};
  hid_t sp = H5Screate_simple(rank, dims, NULL);
  hid_t ds = H5Dcreate2(g, name, ty, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  int bad = ds < 0 || (n0 && H5Dwrite(ds, ty, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) < 0);
  if (ds >= 0) H5Dclose(ds);
  H5Sclose(sp);
  return bad;
}

int vi_curves_write_h5(const char *path, const char *kind, const char *key,
                       const char *key2, int n, int m, const vi_curve_result *r,
                       char *err, int errlen)
{
  char part[4200];
  snprintf(part, sizeof part, "%s.part", path);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  hid_t f = H5Fcreate(part, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (f < 0) {
    snprintf(err, (size_t)errlen, "%s: cannot create the HDF5 file", part);
    return 1;
  }
  hid_t g = H5Gcreate2(f, "curve", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  int orb[2] = {n, m}, bad = g < 0 || attr_str(f, "kind", "curves");
  double loc[2] = {r->located, r->located2};
  static const char types[] = "0 grazing, 1 fold, 2 period_doubling, 3 cusp, "
                              "4 resonance_1_1, 5 resonance_1_2, 6 admissibility";
  if (!bad) {
    bad |= attr_str(g, "kind", kind) | attr_str(g, "param", key) | attr_str(g, "param2", key2);
    bad |= attr_num(g, "orbit", H5T_NATIVE_INT, orb, 2);
    bad |= attr_num(g, "located", H5T_NATIVE_DOUBLE, loc, 2);
    bad |= attr_str(g, "start", vi_curve_end_name(r->start));
    bad |= attr_str(g, "end", vi_curve_end_name(r->state));
    bad |= attr_str(g, "special_types", types);
    bad |= dset(g, "points", H5T_NATIVE_DOUBLE, r->pts, 2, (hsize_t)r->npts);
    bad |= dset(g, "special_points", H5T_NATIVE_DOUBLE, r->sp_pts, 2, (hsize_t)r->nsp);
    bad |= dset(g, "special_type", H5T_NATIVE_INT, r->sp_type, 1, (hsize_t)r->nsp);
    bad |= dset(g, "special_located", H5T_NATIVE_INT, r->sp_loc, 1, (hsize_t)r->nsp);
    H5Gclose(g);
  }
  bad |= H5Fclose(f) < 0;
  if (bad || rename(part, path)) {
    remove(part);
    snprintf(err, (size_t)errlen, "%s: writing the HDF5 file failed", path);
    return 1;
  }
  return 0;
}
