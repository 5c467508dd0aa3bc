/* vi_diagram_h5.c - a sweep or basins diagram to HDF5 (vi_diagram_h5.h,
 * doc/sweep-layout.md), beside the truncation study's writer.  Whole
 * arrays are known when the study ends, so each is one contiguous dataset
 * written at once; the file is FILE.part until it is complete. */
#include <stdio.h>
#include <string.h>

#include <hdf5.h>

#include "vi_diagram_h5.h"
#include "vi_h5_util.h"
#include "vibroimpact.h"
#include "vibroimpact/vi_output.h"

/* /sweep/p11: every P(1,1) orbit at each value (sweep --orbits) */
static int put_p11(hid_t g, const vi_diagram_file *d)
{
  int bad = 0;
  hid_t h = vi_h5_group(g, "p11");
  if (h < 0) return 1;
  hsize_t dLK[2] = {(hsize_t)d->nlines, (hsize_t)d->steps},
          dJ[1] = {(hsize_t)d->np11};
  bad |= vi_h5_attr(h, "phases", H5T_NATIVE_INT, &d->orbits, 1);
  bad |= vi_h5_put(h, "count", H5T_NATIVE_INT, 2, dLK, d->p11_count, NULL);
  bad |= vi_h5_put(h, "start", H5T_NATIVE_INT64, 2, dLK, d->p11_start, NULL);
  bad |= vi_h5_put(h, "v_n", H5T_NATIVE_DOUBLE, 1, dJ, d->p11_vn, NULL);
  bad |= vi_h5_put(h, "phase", H5T_NATIVE_DOUBLE, 1, dJ, d->p11_phase, NULL);
  bad |= vi_h5_put(h, "stable", H5T_NATIVE_INT, 1, dJ, d->p11_stable, NULL);
  bad |= vi_h5_put(h, "admissible", H5T_NATIVE_INT, 1, dJ, d->p11_admissible,
                   NULL);
  return bad | vi_h5_close(h);
}

/* --lyapunov's exponents, basins' attractor ids, the points done. */
static int put_extra(hid_t g, const vi_diagram_file *d, const hsize_t *dLK)
{
  int bad = 0;
  if (d->lyapunov) /* the largest Lyapunov exponent, NaN where refused */
    bad |= vi_h5_put(g, "lyapunov", H5T_NATIVE_DOUBLE, 2, dLK, d->lyapunov, NULL);
  if (d->attractor) { /* basins: the attractor of each cell */
    bad |= vi_h5_put(g, "attractor", H5T_NATIVE_INT, 2, dLK, d->attractor, NULL);
    bad |= vi_h5_attr(g, "n_attractors", H5T_NATIVE_INT, &d->nattr, 1);
  }
  /* which points were computed: all but those an interruption never reached */
  return bad | vi_h5_put(g, "done", H5T_NATIVE_INT, 2, dLK, d->done, NULL);
}

/* The /sweep datasets and attributes; non-zero on any failure. */
static int put_sweep(hid_t g, hid_t gi, const vi_diagram_file *d)
{
  int bad = 0;
  hsize_t dK[1] = {(hsize_t)d->steps}, dR2[1] = {(hsize_t)d->steps2},
          dL[1] = {(hsize_t)d->nlines},
          dLK[2] = {(hsize_t)d->nlines, (hsize_t)d->steps},
          dS[4] = {(hsize_t)d->nlines, (hsize_t)d->steps, (hsize_t)d->record,
                   2 * (hsize_t)d->ncoord},
          dI[1] = {(hsize_t)d->nimpacts};
  bad |= vi_h5_str(g, "key", d->key, VI_H5_UTF8);
  if (d->key2) bad |= vi_h5_str(g, "key2", d->key2, VI_H5_UTF8);
  bad |= vi_h5_attr(g, "transient", H5T_NATIVE_INT, &d->transient, 1);
  bad |= vi_h5_attr(g, "record", H5T_NATIVE_INT, &d->record, 1);
  bad |= vi_h5_attr(g, "chunks", H5T_NATIVE_INT, &d->chunks, 1);
  bad |= vi_h5_attr(g, "seeded", H5T_NATIVE_INT, &d->seeded, 1);
  bad |= vi_h5_attr(g, "nmax", H5T_NATIVE_INT, &d->nmax, 1);
  bad |= vi_h5_attr(g, "tol", H5T_NATIVE_DOUBLE, &d->tol, 1);
  bad |= vi_h5_attr(g, "t0", H5T_NATIVE_DOUBLE, &d->t0, 1);
  bad |= vi_h5_attr(g, "n_coordinates", H5T_NATIVE_INT, &d->ncoord, 1);
  bad |= vi_h5_put(g, "param", H5T_NATIVE_DOUBLE, 1, dK, d->param, NULL);
  if (d->key2) bad |= vi_h5_put(g, "param2", H5T_NATIVE_DOUBLE, 1, dR2, d->param2, NULL);
  bad |= vi_h5_put(g, "direction", H5T_NATIVE_INT, 1, dL, d->dir, NULL);
  bad |= vi_h5_put(g, "row", H5T_NATIVE_INT, 1, dL, d->row, NULL);
  bad |= vi_h5_put(g, "n", H5T_NATIVE_INT, 2, dLK, d->n, NULL);
  bad |= vi_h5_put(g, "m", H5T_NATIVE_INT, 2, dLK, d->m, NULL);
  bad |= vi_h5_put(g, "period", H5T_NATIVE_DOUBLE, 2, dLK, d->period, NULL);
  bad |= vi_h5_put(g, "strobe", H5T_NATIVE_DOUBLE, 4, dS, d->strobe, NULL);
  bad |= vi_h5_put(g, "impact_count", H5T_NATIVE_INT64, 2, dLK, d->impact_count, NULL);
  bad |= vi_h5_put(g, "impact_start", H5T_NATIVE_INT64, 2, dLK, d->impact_start, NULL);
  bad |= vi_h5_put(gi, "time", H5T_NATIVE_DOUBLE, 1, dI, d->impact_time, NULL);
  bad |= vi_h5_put(gi, "phase", H5T_NATIVE_DOUBLE, 1, dI, d->impact_phase, NULL);
  bad |= vi_h5_put(gi, "v_n", H5T_NATIVE_DOUBLE, 1, dI, d->impact_vn, NULL);
  if (d->orbits > 0) bad |= put_p11(g, d);
  bad |= put_extra(g, d, dLK);
  return bad;
}

/* The file's attributes: creator, kind, format, the scene (a dataset
 * when longer than an attribute may be) and its file name. */
static int put_file_attrs(hid_t f, const vi_diagram_file *d)
{
  int bad = 0;
  char creator[64];
  snprintf(creator, sizeof creator, "vibroimpact %s", vi_version_string());
  int fmt = 1;
  int64_t total = (int64_t)d->nlines * d->steps;
  bad |= vi_h5_str(f, "creator", creator, VI_H5_UTF8);
  /* an interrupted study is still a valid file, marked incomplete */
  bad |= vi_h5_attr(f, "complete", H5T_NATIVE_INT, &d->complete, 1);
  bad |= vi_h5_attr(f, "points_done", H5T_NATIVE_INT64, &d->points_done, 1);
  bad |= vi_h5_attr(f, "points_total", H5T_NATIVE_INT64, &total, 1);
  bad |= vi_h5_str(f, "kind", d->basins ? "basins" : "sweep", VI_H5_UTF8);
  bad |= vi_h5_attr(f, "format_version", H5T_NATIVE_INT, &fmt, 1);
  /* an attribute holds at most 64 KiB: a longer scene goes to the
   * dataset /scene (a scalar string), as in a run's file */
  if (strlen(d->text) < 60000) bad |= vi_h5_str(f, "scene", d->text, VI_H5_UTF8);
  else bad |= vi_h5_str(f, "scene", d->text, VI_H5_DATASET | VI_H5_UTF8);
  bad |= vi_h5_str(f, "scene_file", d->name, VI_H5_UTF8);
  return bad;
}

int vi_diagram_file_write(const vi_diagram_file *d, const char *path,
                          char *err, int errlen)
{
  char part[4096 + 8];
  if (vi_output_part(path, part, (int)sizeof part)) {
    snprintf(err, (size_t)errlen, "output path too long");
    return 1;
  }
  /* built in memory and committed through the output module (vi_h5_util.h):
   * HDF5 never meets a full disk; every write, the sync and the rename are
   * checked; 1 MiB steps for files of some MB */
  hid_t f = vi_h5_image_create(part, (size_t)1 << 20);
  if (f < 0) {
    snprintf(err, (size_t)errlen, "cannot create '%s'", part);
    return 1;
  }
  int bad = put_file_attrs(f, d);
  hid_t g = vi_h5_group(f, "sweep"), gi = g < 0 ? -1 : vi_h5_group(g, "impacts");
  bad |= g < 0 || gi < 0;
  if (!bad) bad = put_sweep(g, gi, d);
  bad |= vi_h5_close(gi) | vi_h5_close(g);
  vi_diag od;
  memset(&od, 0, sizeof od);
  if (vi_h5_image_commit(f, bad, path, &od)) {
    snprintf(err, (size_t)errlen, "%s", od.message);
    bad = 1;
  }
  return bad;
}
