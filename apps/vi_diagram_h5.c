/* vi_diagram_h5.c - a sweep to HDF5 (layout: share/doc/sweep-layout.md).
 * Whole arrays are known when the sweep ends, so each is one contiguous
 * dataset written at once; the file is FILE.part until it is complete. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hdf5.h>

#include "vibroimpact.h"
#include "vi_h5_util.h"
#include "vi_diagram.h"
#include "vibroimpact/vi_output.h"

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
  hid_t h = vi_h5_group(g, "p11");
  if (h < 0) {
    bad = 1;
    goto done;
  }
  hsize_t dLK[2] = {(hsize_t)L, (hsize_t)K}, dJ[1] = {(hsize_t)J};
  bad |= vi_h5_attr(h, "phases", H5T_NATIVE_INT, &sw->spec.orbits, 1);
  bad |= vi_h5_put(h, "count", H5T_NATIVE_INT, 2, dLK, cnt, NULL);
  bad |= vi_h5_put(h, "start", H5T_NATIVE_INT64, 2, dLK, start, NULL);
  bad |= vi_h5_put(h, "v_n", H5T_NATIVE_DOUBLE, 1, dJ, d, NULL);
  bad |= vi_h5_put(h, "phase", H5T_NATIVE_DOUBLE, 1, dJ, d + J, NULL);
  bad |= vi_h5_put(h, "stable", H5T_NATIVE_INT, 1, dJ, st, NULL);
  bad |= vi_h5_put(h, "admissible", H5T_NATIVE_INT, 1, dJ, ad, NULL);
  bad |= vi_h5_close(h);
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
    bad |= !l || vi_h5_put(g, "lyapunov", H5T_NATIVE_DOUBLE, 2, dLK, l, NULL);
    free(l);
  }
  if (sw->attractor) { /* basins: the attractor of each cell */
    bad |= vi_h5_put(g, "attractor", H5T_NATIVE_INT, 2, dLK, sw->attractor, NULL);
    bad |= vi_h5_attr(g, "n_attractors", H5T_NATIVE_INT, &sw->nattr, 1);
  }
  /* which points were computed: all but those an interruption never reached */
  int *done = malloc(sizeof(int) * (size_t)L * K);
  for (int i = 0; done && i < L * K; i++) done[i] = sw->lines[i / K].pt[i % K].done;
  bad |= !done || vi_h5_put(g, "done", H5T_NATIVE_INT, 2, dLK, done, NULL);
  free(done);
  return bad;
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
  const vi_diagram_spec *sp = &sw->spec;
  int K = sp->steps, L = sw->nlines, R = sp->record, n2 = 2 * sw->N, bad = 0;
  hsize_t dK[1] = {(hsize_t)K}, dR2[1] = {(hsize_t)sp->steps2},
          dL[1] = {(hsize_t)L}, dLK[2] = {(hsize_t)L, (hsize_t)K},
          dS[4] = {(hsize_t)L, (hsize_t)K, (hsize_t)R, (hsize_t)n2},
          dI[1] = {(hsize_t)a->I};
  bad |= vi_h5_str(g, "key", sp->key, VI_H5_UTF8);
  if (sp->key2) bad |= vi_h5_str(g, "key2", sp->key2, VI_H5_UTF8);
  bad |= vi_h5_attr(g, "transient", H5T_NATIVE_INT, &sp->transient, 1);
  bad |= vi_h5_attr(g, "record", H5T_NATIVE_INT, &sp->record, 1);
  bad |= vi_h5_attr(g, "chunks", H5T_NATIVE_INT, &sp->chunks, 1);
  int seeded = sp->chunks > 1 && sw->warm;
  bad |= vi_h5_attr(g, "seeded", H5T_NATIVE_INT, &seeded, 1);
  bad |= vi_h5_attr(g, "nmax", H5T_NATIVE_INT, &sp->nmax, 1);
  bad |= vi_h5_attr(g, "tol", H5T_NATIVE_DOUBLE, &sp->tol, 1);
  bad |= vi_h5_attr(g, "t0", H5T_NATIVE_DOUBLE, &sw->t0, 1);
  bad |= vi_h5_attr(g, "n_coordinates", H5T_NATIVE_INT, &sw->N, 1);
  bad |= vi_h5_put(g, "param", H5T_NATIVE_DOUBLE, 1, dK, sw->param, NULL);
  if (sp->key2) bad |= vi_h5_put(g, "param2", H5T_NATIVE_DOUBLE, 1, dR2, sw->param2, NULL);
  bad |= vi_h5_put(g, "direction", H5T_NATIVE_INT, 1, dL, a->dir, NULL);
  bad |= vi_h5_put(g, "row", H5T_NATIVE_INT, 1, dL, a->row, NULL);
  bad |= vi_h5_put(g, "n", H5T_NATIVE_INT, 2, dLK, a->n, NULL);
  bad |= vi_h5_put(g, "m", H5T_NATIVE_INT, 2, dLK, a->m, NULL);
  bad |= vi_h5_put(g, "period", H5T_NATIVE_DOUBLE, 2, dLK, a->T, NULL);
  bad |= vi_h5_put(g, "strobe", H5T_NATIVE_DOUBLE, 4, dS, a->strobe, NULL);
  bad |= vi_h5_put(g, "impact_count", H5T_NATIVE_INT64, 2, dLK, a->cnt, NULL);
  bad |= vi_h5_put(g, "impact_start", H5T_NATIVE_INT64, 2, dLK, a->start, NULL);
  bad |= vi_h5_put(gi, "time", H5T_NATIVE_DOUBLE, 1, dI, a->flat, NULL);
  bad |= vi_h5_put(gi, "phase", H5T_NATIVE_DOUBLE, 1, dI, a->flat + a->I, NULL);
  bad |= vi_h5_put(gi, "v_n", H5T_NATIVE_DOUBLE, 1, dI, a->flat + 2 * a->I, NULL);
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
  bad |= vi_h5_str(f, "creator", creator, VI_H5_UTF8);
  /* an interrupted study is still a valid file, marked incomplete */
  bad |= vi_h5_attr(f, "complete", H5T_NATIVE_INT, &complete, 1);
  bad |= vi_h5_attr(f, "points_done", H5T_NATIVE_INT64, &sw->points_done, 1);
  bad |= vi_h5_attr(f, "points_total", H5T_NATIVE_INT64, &total, 1);
  bad |= vi_h5_str(f, "kind", sw->attractor ? "basins" : "sweep", VI_H5_UTF8);
  bad |= vi_h5_attr(f, "format_version", H5T_NATIVE_INT, &fmt, 1);
  /* an attribute holds at most 64 KiB: a longer scene goes to the
   * dataset /scene (a scalar string), as in a run's file */
  if (strlen(sw->text) < 60000) bad |= vi_h5_str(f, "scene", sw->text, VI_H5_UTF8);
  else bad |= vi_h5_str(f, "scene", sw->text, VI_H5_DATASET | VI_H5_UTF8);
  bad |= vi_h5_str(f, "scene_file", sw->name, VI_H5_UTF8);
  return bad;
}

int vi_diagram_write_h5(const vi_diagram *sw, const char *path, char *err, int errlen)
{
  const vi_diagram_spec *sp = &sw->spec;
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
  /* built in memory and committed through the output module (vi_h5_util.h):
   * HDF5 never meets a full disk; every write, the sync and the rename are
   * checked; 1 MiB steps for files of some MB */
  hid_t f = vi_h5_image_create(part, (size_t)1 << 20);
  if (f < 0) {
    snprintf(err, (size_t)errlen, "cannot create '%s'", part);
    bad = 1;
    goto done;
  }
  bad |= put_file_attrs(f, sw);
  hid_t g = vi_h5_group(f, "sweep"), gi = g < 0 ? -1 : vi_h5_group(g, "impacts");
  bad |= g < 0 || gi < 0;
  flat_arrays a = {nn, mm, dir, row, cnt, start, I, T, flat, strobe};
  if (!bad) bad = put_sweep(g, gi, sw, &a);
  bad |= vi_h5_close(gi) | vi_h5_close(g);
  vi_diag od;
  memset(&od, 0, sizeof od);
  if (vi_h5_image_commit(f, bad, path, &od)) {
    snprintf(err, (size_t)errlen, "%s", od.message);
    bad = 1;
  }
done:
  free(ni);
  free(cnt);
  free(T);
  free(flat);
  free(strobe);
  return bad;
}
