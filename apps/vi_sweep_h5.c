/* vi_sweep_h5.c - a sweep to HDF5 (layout: share/doc/sweep-layout.md).
 * Whole arrays are known when the sweep ends, so each is one contiguous
 * dataset written at once; the file is FILE.part until it is complete. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <hdf5.h>

#include "vibroimpact.h"
#include "vi_sweep.h"
#include "vibroimpact/vi_output.h"

static int put(hid_t loc, const char *name, hid_t type, int rank,
               const hsize_t *dims, const void *data)
{
  int bad = 1;
  hid_t sp = -1, ds = -1;
  H5E_BEGIN_TRY {
    sp = H5Screate_simple(rank, dims, NULL);
    if (sp >= 0) ds = H5Dcreate2(loc, name, type, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    bad = ds < 0 || H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0;
    if (ds >= 0) H5Dclose(ds);
    if (sp >= 0) H5Sclose(sp);
  } H5E_END_TRY;
  return bad;
}

static int dset_str(hid_t loc, const char *name, const char *val)
{
  int bad = 1;
  hid_t t = -1, sp = -1, d = -1;
  H5E_BEGIN_TRY {
    t = H5Tcopy(H5T_C_S1);
    if (t >= 0 && H5Tset_size(t, strlen(val) + 1) >= 0 && H5Tset_cset(t, H5T_CSET_UTF8) >= 0)
      sp = H5Screate(H5S_SCALAR);
    if (sp >= 0) d = H5Dcreate2(loc, name, t, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    bad = d < 0 || H5Dwrite(d, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, val) < 0;
    if (d >= 0) H5Dclose(d);
    if (sp >= 0) H5Sclose(sp);
    if (t >= 0) H5Tclose(t);
  } H5E_END_TRY;
  return bad;
}

static int attr_str(hid_t loc, const char *name, const char *val)
{
  int bad = 1;
  hid_t t = -1, sp = -1, a = -1;
  H5E_BEGIN_TRY {
    t = H5Tcopy(H5T_C_S1);
    if (t >= 0 && H5Tset_size(t, strlen(val) + 1) >= 0 && H5Tset_cset(t, H5T_CSET_UTF8) >= 0)
      sp = H5Screate(H5S_SCALAR);
    if (sp >= 0) a = H5Acreate2(loc, name, t, sp, H5P_DEFAULT, H5P_DEFAULT);
    bad = a < 0 || H5Awrite(a, t, val) < 0;
    if (a >= 0) H5Aclose(a);
    if (sp >= 0) H5Sclose(sp);
    if (t >= 0) H5Tclose(t);
  } H5E_END_TRY;
  return bad;
}

static int attr_num(hid_t loc, const char *name, hid_t type, const void *val)
{
  int bad = 1;
  hid_t sp = -1, a = -1;
  H5E_BEGIN_TRY {
    sp = H5Screate(H5S_SCALAR);
    if (sp >= 0) a = H5Acreate2(loc, name, type, sp, H5P_DEFAULT, H5P_DEFAULT);
    bad = a < 0 || H5Awrite(a, type, val) < 0;
    if (a >= 0) H5Aclose(a);
    if (sp >= 0) H5Sclose(sp);
  } H5E_END_TRY;
  return bad;
}

/* /sweep/p11: every P(1,1) orbit at each value (sweep --orbits) */
static int put_p11(hid_t g, const vi_diagram *sw)
{
  int K = sw->spec.steps, L = sw->nlines, bad = 0;
  size_t LK = (size_t)L * K, J = 0;
  for (size_t i = 0; i < LK; i++) {
    int no = sw->lines[i / K].pt[i % K].norb;
    J += no > 0 ? (size_t)no : 0;
  }
  int *cnt = malloc(sizeof(int) * (LK + 2 * J + 1));
  int64_t *start = malloc(sizeof(int64_t) * LK);
  double *d = malloc(sizeof(double) * (2 * J + 1));
  if (!cnt || !start || !d) {
    bad = 1;
    goto done;
  }
  int *st = cnt + LK, *ad = st + J;
  size_t off = 0;
  for (size_t i = 0; i < LK; i++) {
    const vi_diagram_point *pt = &sw->lines[i / K].pt[i % K];
    cnt[i] = pt->norb;
    start[i] = (int64_t)off;
    for (int j = 0; j < pt->norb; j++, off++) {
      d[off] = pt->ovn[j];
      d[J + off] = pt->ophase[j];
      st[off] = pt->ostable[j];
      ad[off] = pt->oadm[j];
    }
  }
  hid_t h = -1;
  H5E_BEGIN_TRY { h = H5Gcreate2(g, "p11", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT); } H5E_END_TRY;
  if (h < 0) {
    bad = 1;
    goto done;
  }
  hsize_t dLK[2] = {(hsize_t)L, (hsize_t)K}, dJ[1] = {(hsize_t)J};
  bad |= attr_num(h, "phases", H5T_NATIVE_INT, &sw->spec.orbits);
  bad |= put(h, "count", H5T_NATIVE_INT, 2, dLK, cnt);
  bad |= put(h, "start", H5T_NATIVE_INT64, 2, dLK, start);
  bad |= put(h, "v_n", H5T_NATIVE_DOUBLE, 1, dJ, d);
  bad |= put(h, "phase", H5T_NATIVE_DOUBLE, 1, dJ, d + J);
  bad |= put(h, "stable", H5T_NATIVE_INT, 1, dJ, st);
  bad |= put(h, "admissible", H5T_NATIVE_INT, 1, dJ, ad);
  H5E_BEGIN_TRY { H5Gclose(h); } H5E_END_TRY;
done:
  free(cnt);
  free(start);
  free(d);
  return bad;
}

/* --lyapunov's exponents and basins' attractor ids, when asked for. */
static int put_extra(hid_t g, const vi_diagram *sw, const hsize_t *dLK)
{
  int K = sw->spec.steps, L = sw->nlines, bad = 0;
  if (sw->spec.lyapunov) { /* the largest Lyapunov exponent, NaN where refused */
    double *l = malloc(sizeof(double) * (size_t)L * K);
    for (int i = 0; l && i < L * K; i++) l[i] = sw->lines[i / K].pt[i % K].lyap;
    bad |= !l || put(g, "lyapunov", H5T_NATIVE_DOUBLE, 2, dLK, l);
    free(l);
  }
  if (sw->attractor) { /* basins: the attractor of each cell */
    bad |= put(g, "attractor", H5T_NATIVE_INT, 2, dLK, sw->attractor);
    bad |= attr_num(g, "n_attractors", H5T_NATIVE_INT, &sw->nattr);
  }
  /* which points were computed: all but those an interruption never reached */
  int *done = malloc(sizeof(int) * (size_t)L * K);
  for (int i = 0; done && i < L * K; i++) done[i] = sw->lines[i / K].pt[i % K].done;
  bad |= !done || put(g, "done", H5T_NATIVE_INT, 2, dLK, done);
  free(done);
  return bad;
}

/* The file's image through the output module (vi_output.h): PATH.part
 * in large write()s of the descriptor itself, synced, renamed; removed on
 * any failure.  0, or 1 with err. */
static int write_image(const char *path, const void *image, size_t size,
                       char *err, int errlen)
{
  FILE *fp = NULL;
  vi_diag od;
  memset(&od, 0, sizeof od);
  int wbad = vi_output_open(path, VI_OUTPUT_FILE, &fp, &od) != VI_OK;
  for (size_t at = 0; !wbad && at < size;) {
    ssize_t k = write(fileno(fp), (const char *)image + at, size - at);
    if (k <= 0) {
      snprintf(od.message, sizeof od.message, "cannot write %.300s.part: %s",
               path, strerror(k < 0 ? errno : EIO));
      wbad = 1;
    } else {
      at += (size_t)k;
    }
  }
  if (wbad || vi_output_close(&fp, path, VI_OUTPUT_FILE, &od)) {
    if (fp) vi_output_discard(&fp, path, VI_OUTPUT_FILE);
    snprintf(err, (size_t)errlen, "%s", od.message[0] ? od.message : "writing failed");
    return 1;
  }
  return 0;
}

/* The arrays of a diagram, flattened for HDF5. */
typedef struct flat_arrays {
  int *n, *m, *dir, *row;
  int64_t *cnt, *start, I;
  double *T, *flat, *strobe;
} flat_arrays;

/* The /sweep datasets and attributes; non-zero on any failure. */
static int put_sweep(hid_t g, hid_t gi, const vi_diagram *sw, const flat_arrays *a)
{
  const vi_sweep_spec *sp = &sw->spec;
  int K = sp->steps, L = sw->nlines, R = sp->record, n2 = 2 * sw->N, bad = 0;
  hsize_t dK[1] = {(hsize_t)K}, dR2[1] = {(hsize_t)sp->steps2},
          dL[1] = {(hsize_t)L}, dLK[2] = {(hsize_t)L, (hsize_t)K},
          dS[4] = {(hsize_t)L, (hsize_t)K, (hsize_t)R, (hsize_t)n2},
          dI[1] = {(hsize_t)a->I};
  bad |= attr_str(g, "key", sp->key);
  if (sp->key2) bad |= attr_str(g, "key2", sp->key2);
  bad |= attr_num(g, "transient", H5T_NATIVE_INT, &sp->transient);
  bad |= attr_num(g, "record", H5T_NATIVE_INT, &sp->record);
  bad |= attr_num(g, "chunks", H5T_NATIVE_INT, &sp->chunks);
  bad |= attr_num(g, "nmax", H5T_NATIVE_INT, &sp->nmax);
  bad |= attr_num(g, "tol", H5T_NATIVE_DOUBLE, &sp->tol);
  bad |= attr_num(g, "t0", H5T_NATIVE_DOUBLE, &sw->t0);
  bad |= attr_num(g, "n_coordinates", H5T_NATIVE_INT, &sw->N);
  bad |= put(g, "param", H5T_NATIVE_DOUBLE, 1, dK, sw->param);
  if (sp->key2) bad |= put(g, "param2", H5T_NATIVE_DOUBLE, 1, dR2, sw->param2);
  bad |= put(g, "direction", H5T_NATIVE_INT, 1, dL, a->dir);
  bad |= put(g, "row", H5T_NATIVE_INT, 1, dL, a->row);
  bad |= put(g, "n", H5T_NATIVE_INT, 2, dLK, a->n);
  bad |= put(g, "m", H5T_NATIVE_INT, 2, dLK, a->m);
  bad |= put(g, "period", H5T_NATIVE_DOUBLE, 2, dLK, a->T);
  bad |= put(g, "strobe", H5T_NATIVE_DOUBLE, 4, dS, a->strobe);
  bad |= put(g, "impact_count", H5T_NATIVE_INT64, 2, dLK, a->cnt);
  bad |= put(g, "impact_start", H5T_NATIVE_INT64, 2, dLK, a->start);
  bad |= put(gi, "time", H5T_NATIVE_DOUBLE, 1, dI, a->flat);
  bad |= put(gi, "phase", H5T_NATIVE_DOUBLE, 1, dI, a->flat + a->I);
  bad |= put(gi, "v_n", H5T_NATIVE_DOUBLE, 1, dI, a->flat + 2 * a->I);
  if (sp->orbits > 0) bad |= put_p11(g, sw);
  bad |= put_extra(g, sw, dLK);
  return bad;
}

/* The file's attributes: creator, kind, format, the scene (a dataset
 * when longer than an attribute may be) and its file name. */
static int put_file_attrs(hid_t f, const vi_diagram *sw)
{
  int bad = 0;
  char creator[64];
  snprintf(creator, sizeof creator, "vibroimpact %s", vi_version_string());
  int fmt = 1, complete = !sw->incomplete;
  int64_t total = (int64_t)sw->nlines * sw->spec.steps;
  bad |= attr_str(f, "creator", creator);
  /* an interrupted study is still a valid file, marked incomplete */
  bad |= attr_num(f, "complete", H5T_NATIVE_INT, &complete);
  bad |= attr_num(f, "points_done", H5T_NATIVE_INT64, &sw->points_done);
  bad |= attr_num(f, "points_total", H5T_NATIVE_INT64, &total);
  bad |= attr_str(f, "kind", sw->attractor ? "basins" : "sweep");
  bad |= attr_num(f, "format_version", H5T_NATIVE_INT, &fmt);
  /* an attribute holds at most 64 KiB: a longer scene goes to the
   * dataset /scene (a scalar string), as in a run's file */
  if (strlen(sw->text) < 60000) bad |= attr_str(f, "scene", sw->text);
  else bad |= dset_str(f, "scene", sw->text);
  bad |= attr_str(f, "scene_file", sw->name);
  return bad;
}

int vi_sweep_write_h5(const vi_diagram *sw, const char *path, char *err, int errlen)
{
  const vi_sweep_spec *sp = &sw->spec;
  int K = sp->steps, L = sw->nlines, R = sp->record, n2 = 2 * sw->N, bad = 0;
  char part[4096 + 8];
  if (vi_output_part(path, part, (int)sizeof part)) {
    snprintf(err, (size_t)errlen, "output path too long");
    return 1;
  }
  int64_t I = 0;
  for (int l = 0; l < L; l++)
    for (int k = 0; k < K; k++) I += sw->lines[l].pt[k].nimp;
  size_t LK = (size_t)L * K;
  int *ni = malloc(sizeof(int) * (LK * 2 + 2 * (size_t)L));
  int64_t *cnt = malloc(sizeof(int64_t) * LK * 2);
  double *T = malloc(sizeof(double) * LK);
  double *flat = malloc(sizeof(double) * (size_t)(3 * I + 1));
  double *strobe = malloc(sizeof(double) * LK * R * n2 + 1);
  if (!ni || !cnt || !T || !flat || !strobe) {
    snprintf(err, (size_t)errlen, "out of memory");
    bad = 1;
    goto done;
  }
  int *nn = ni, *mm = ni + LK, *lin = ni + 2 * LK;
  int64_t *start = cnt + LK, off = 0;
  for (int l = 0; l < L; l++) {
    const vi_diagram_line *ln = &sw->lines[l];
    memcpy(strobe + (size_t)l * K * R * n2, ln->strobe, sizeof(double) * K * R * n2);
    for (int k = 0; k < K; k++) {
      const vi_diagram_point *pt = &ln->pt[k];
      size_t i = (size_t)l * K + k;
      nn[i] = pt->failed ? -1 : pt->n;
      mm[i] = pt->n ? pt->m : 0;
      T[i] = pt->T;
      cnt[i] = pt->nimp;
      start[i] = off;
      for (int64_t j = 0; j < pt->nimp; j++, off++) {
        flat[off] = pt->t[j];
        flat[I + off] = pt->phase[j];
        flat[2 * I + off] = pt->vn[j];
      }
    }
  }
  int *dir = lin, *row = lin + L;
  for (int l = 0; l < L; l++) {
    dir[l] = sw->lines[l].dir;
    row[l] = sw->lines[l].row;
  }
  hid_t f = -1, g = -1, gi = -1;
  /* the file is built in memory (HDF5's core driver, no backing store) and
   * its image written through the output module: HDF5 never meets a full
   * disk (whose failed close crashed in its atexit handler), and every
   * write, the sync and the rename are checked */
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  if (fapl >= 0 && H5Pset_fapl_core(fapl, (size_t)1 << 20, 0) >= 0)
    H5E_BEGIN_TRY { f = H5Fcreate(part, H5F_ACC_TRUNC, H5P_DEFAULT, fapl); } H5E_END_TRY;
  if (fapl >= 0) H5Pclose(fapl);
  if (f < 0) {
    snprintf(err, (size_t)errlen, "cannot create '%s'", part);
    bad = 1;
    goto done;
  }
  bad |= put_file_attrs(f, sw);
  H5E_BEGIN_TRY {
    g = H5Gcreate2(f, "sweep", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (g >= 0) gi = H5Gcreate2(g, "impacts", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  } H5E_END_TRY;
  bad |= g < 0 || gi < 0;
  flat_arrays a = {nn, mm, dir, row, cnt, start, I, T, flat, strobe};
  if (!bad) bad = put_sweep(g, gi, sw, &a);
  void *image = NULL;
  ssize_t size = -1;
  H5E_BEGIN_TRY {
    if (gi >= 0) H5Gclose(gi);
    if (g >= 0) H5Gclose(g);
    if (!bad && H5Fflush(f, H5F_SCOPE_GLOBAL) >= 0 &&
        (size = H5Fget_file_image(f, NULL, 0)) > 0 &&
        (image = malloc((size_t)size)) != NULL &&
        H5Fget_file_image(f, image, (size_t)size) != size)
      size = -1;
    bad |= H5Fclose(f) < 0;
  } H5E_END_TRY;
  if (bad || size <= 0 || !image) {
    snprintf(err, (size_t)errlen, "building the file for '%s' failed", path);
    bad = 1;
  } else {
    bad = write_image(path, image, (size_t)size, err, errlen);
  }
  free(image);
done:
  free(ni);
  free(cnt);
  free(T);
  free(flat);
  free(strobe);
  return bad;
}
