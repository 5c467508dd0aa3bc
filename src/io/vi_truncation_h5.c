/* vi_truncation_h5.c - a truncation study to HDF5 (vi_truncation_io.h,
 * doc/truncation-layout.md): each column of the caller's table becomes a
 * named dataset, so a reader needs no column numbers. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hdf5.h>

#include "vi_h5_util.h"
#include "vi_io_internal.h"
#include "vibroimpact.h"
#include "vibroimpact/vi_output.h"
#include "vibroimpact/vi_truncation_io.h"

/* The row layout of vi_truncation_io.h: name, first column, width. */
typedef struct column {
  const char *name;
  int col, width;
} column;

static const column cols[] = {
    {"k", 0, 1},              {"omega", 1, 1},
    {"dynamic_fraction", 2, 1}, {"static_fraction", 3, 1},
    {"class_n", 4, 1},        {"class_m", 5, 1},
    {"vN", 6, 1},             {"phase", 7, 1},
    {"first_n", 8, 1},        {"first_t", 9, 3},
    {"first_vn", 12, 3},      {"first_dt", 15, 3},
    {"first_dvn_rel", 18, 3}, {"release", 21, 1},
    {"r_S", 22, 1},           {"r_S_class_n", 23, 1},
    {"r_S_class_m", 24, 1},   {"r_S_vN", 25, 1},
    {"r_S_phase", 26, 1},     {"static_corrected", 27, 1},
    {"sc_dynamic_fraction", 28, 1}, {"sc_class_n", 29, 1},
    {"sc_class_m", 30, 1},    {"sc_vN", 31, 1},
    {"sc_phase", 32, 1},      {"sc_first_n", 33, 1},
    {"sc_first_t", 34, 3},    {"sc_first_vn", 37, 3},
    {"sc_first_dt", 40, 3},   {"sc_first_dvn_rel", 43, 3},
    {"sc_release", 46, 1},
};

static const char *const info_names[VI_TRUNCATION_INFO] = {
    "dofs", "modes_lo", "modes_hi", "reference_modes", "restitution",
    "compliance_dynamic", "compliance_static", "complete"};

/* One column group of the table as a [n] or [n x width] dataset (row-major
 * in the file: row i of the study is row i of the dataset). */
static int put_column(hid_t g, const column *c, const double *t, int n,
                      int ld, double *buf)
{
  for (int i = 0; i < n; i++)
    for (int w = 0; w < c->width; w++)
      buf[(size_t)i * c->width + w] = t[i + (size_t)(c->col + w) * ld];
  hsize_t dims[2] = {(hsize_t)n, (hsize_t)c->width};
  return vi_h5_put(g, c->name, H5T_NATIVE_DOUBLE, c->width > 1 ? 2 : 1, dims,
                   buf, NULL);
}

static int put_table(hid_t parent, const char *name, const double *t, int n,
                     int ld, double *buf)
{
  hid_t g = vi_h5_group(parent, name);
  int bad = g < 0;
  for (size_t j = 0; !bad && j < sizeof cols / sizeof cols[0]; j++)
    bad |= put_column(g, &cols[j], t, n, ld, buf);
  return vi_h5_close(g) | bad;
}

int vi_truncation_write_h5(const char *path, const char *scene_name,
                           const char *scene_text, const double *info,
                           const double *reference, int nrows,
                           const double *rows, int ldrows, vi_diag *diag)
{
  if (diag) memset(diag, 0, sizeof *diag);
  if (!path || !info || !reference || !rows || nrows < 0 ||
      ldrows < (nrows > 1 ? nrows : 1))
    return VI_ERR_ARG;
  char target[4096], part[4200];
  int st = vi_output_resolve(path, target, sizeof target, diag);
  if (!st) st = vi_output_part(target, part, sizeof part);
  if (st) return st;
  double *buf = malloc(sizeof(double) * 3 * ((size_t)nrows + 1));
  if (!buf) return VI_ERR_NOMEM;
  hid_t f = vi_h5_image_create(part, (size_t)1 << 16); /* in memory */
  hid_t g = f < 0 ? -1 : vi_h5_group(f, "truncation");
  int bad = g < 0;
  if (!bad) {
    bad |= vi_h5_attr_str(g, "scene", scene_name ? scene_name : "");
    /* a dataset: a scene may exceed an attribute's 64 KiB */
    bad |= vi_h5_str(g, "scene_text", scene_text ? scene_text : "",
                     VI_H5_DATASET);
    for (int j = 0; j < VI_TRUNCATION_INFO - 1; j++)
      bad |= vi_h5_attr_double(g, info_names[j], info[j]);
    /* complete: an int, as the sweep's (an interrupted study holds the
     * rows done) */
    bad |= vi_h5_attr_int(g, info_names[VI_TRUNCATION_INFO - 1],
                          info[VI_TRUNCATION_INFO - 1] != 0.0);
    bad |= put_table(g, "rows", rows, nrows, ldrows, buf);
    bad |= put_table(g, "reference", reference, 1, 1, buf);
  }
  bad |= vi_h5_close(g);
  free(buf);
  if (f < 0)
    return vi_diag_set(diag, target, VI_ERR_IO, 0, 0, "", "",
                       "cannot create %s", part);
  return vi_h5_image_commit(f, bad, target, diag); /* through TARGET.part */
}
