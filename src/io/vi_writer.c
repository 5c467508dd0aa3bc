/* vi_writer.c - the HDF5 file of a run (layout: share/doc/hdf5-layout.md).
 * Every HDF5 call runs inside H5E_BEGIN_TRY so that HDF5 prints nothing;
 * failures become our status codes and messages. */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <fcntl.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <hdf5.h>

#include "vi_h5_util.h"
#include "vi_scene_internal.h"
#include "vibroimpact.h"
#include "vibroimpact/vi_mmio.h"
#include "vibroimpact/vi_writer.h"

#define MAXCOL 13
#define FORMAT_VERSION 2

typedef struct col {
  const char *name, *units, *meaning;
  int width;   /* values per row */
  int rank;    /* 1: dataset [rows]; 2: [rows][width], also when width = 1 */
  hid_t ftype; /* file type */
  hid_t dset;
  double *buf; /* cap x width */
} col;

typedef struct table {
  const char *gname;
  hid_t group;
  int ncol, cap, used, compress, made; /* made: datasets exist */
  hsize_t rows;
  col c[MAXCOL];
} table;

struct vi_writer {
  hid_t file;
  int fd;           /* our own descriptor of PATH.part, for the reserve */
  int no_reserve;   /* the file system cannot preallocate */
  int zero_fill;    /* preallocate by writing zeros (no fallocate) */
  int64_t reserved; /* blocks allocated up to this offset */
  char *path, *part;
  const vi_model *m;
  int n, compress, failed;
  table imp, traj, led;
  double *q, *qd; /* modal scratch [n] */
  char errmsg[512];
};

static int werr(vi_writer *w, int code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static int werr(vi_writer *w, int code, const char *fmt, ...)
{
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(w->errmsg, sizeof w->errmsg, fmt, ap);
  va_end(ap);
  w->failed = 1;
  return code;
}

/* A misuse: the message, but the file is not broken. */
static int warg(vi_writer *w, int code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static int warg(vi_writer *w, int code, const char *fmt, ...)
{
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(w->errmsg, sizeof w->errmsg, fmt, ap);
  va_end(ap);
  return code;
}

const char *vi_writer_errmsg(const vi_writer *w) { return w ? w->errmsg : ""; }

/* ---- space before HDF5 needs it ------------------------------------------
 * HDF5 1.10 does not survive a failed write: after ENOSPC the file stays
 * half-closed in its tables and H5Fclose, H5close or the exit-time clean-up
 * crash on it.  So HDF5 must never meet a full disk: before each batch of
 * writes the blocks past the end of PATH.part are allocated (fallocate,
 * keeping the size) for the batch plus a margin for metadata, and a full
 * disk is found here, while HDF5 is still healthy and can close cleanly. */
#define RESERVE_MARGIN (32 * 1024)

static int zero_fill(int fd, off_t from, off_t to)
{
  static const char zeros[16384];
  while (from < to) {
    size_t n = to - from < (off_t)sizeof zeros ? (size_t)(to - from)
                                                 : sizeof zeros;
    ssize_t k = pwrite(fd, zeros, n, from);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return k < 0 ? errno : EIO;
    from += k;
  }
  return 0;
}

static int reserve(vi_writer *w, double bytes)
{
  if (w->no_reserve || w->fd < 0) return VI_OK;
  struct stat st;
  hsize_t eoa = 0;
  if (fstat(w->fd, &st) != 0) return VI_OK;
  /* from HDF5's end of allocation, which runs ahead of what is on disk
   * (metadata is allocated at once and written at the flush) */
  H5E_BEGIN_TRY { if (H5Fget_filesize(w->file, &eoa) < 0) eoa = 0; }
  H5E_END_TRY;
  double end = (double)eoa > (double)st.st_size ? (double)eoa
                                                : (double)st.st_size;
  double need = end + bytes + RESERVE_MARGIN;
  /* a file size limit (ulimit -f) fails writes as a full disk does */
  struct rlimit fl;
  if (getrlimit(RLIMIT_FSIZE, &fl) == 0 && fl.rlim_cur != RLIM_INFINITY &&
      need > (double)fl.rlim_cur)
    return werr(w, VI_ERR_IO, "cannot write %s: %s (%.0f more bytes needed)",
                w->part, strerror(EFBIG), bytes);
  if (need <= (double)w->reserved) return VI_OK;
  /* grow in steps of at least 1/8 of the file, not one batch at a time */
  double more = need - (double)st.st_size;
  if (more < (double)st.st_size / 8) more = (double)st.st_size / 8;
  if (more > 9e18) return werr(w, VI_ERR_IO, "output too large");
  int e = w->zero_fill ? -1
                       : fallocate(w->fd, FALLOC_FL_KEEP_SIZE, st.st_size,
                                   (off_t)more);
  if (e != 0) {
    e = w->zero_fill ? EOPNOTSUPP : errno;
    if (e == EOPNOTSUPP || e == ENOSYS) {
      /* no preallocation on this file system: write zeros past the end
       * instead (HDF5 overwrites them, or they stay as harmless padding
       * past its end of allocation) */
      w->zero_fill = 1;
      e = zero_fill(w->fd, st.st_size, st.st_size + (off_t)more);
    }
    if (e) {
      if (e == EINVAL) {
        w->no_reserve = 1; /* best effort where it cannot be done */
        return VI_OK;
      }
      return werr(w, VI_ERR_IO, "cannot write %s: %s (%.0f more bytes "
                  "needed)", w->part, strerror(e), bytes);
    }
  }
  w->reserved = (int64_t)((double)st.st_size + more);
  return VI_OK;
}

static double row_bytes(const table *t)
{
  double b = 0;
  for (int k = 0; k < t->ncol; k++) b += 8.0 * t->c[k].width;
  return b;
}

/* ---- fixed datasets (the helpers: vi_h5_util.h) ---------------------------- */
/* A fixed array: a vector [rows] (cols = 0) or a column-major matrix written
 * in C order, so that element [i][j] of the dataset is A(i, j). */
static int put(hid_t g, const char *name, const double *A, int rows, int cols,
               const char *meaning)
{
  hsize_t dims[2] = {(hsize_t)rows, (hsize_t)cols};
  double *buf = NULL;
  if (cols > 0) {
    buf = malloc(sizeof(double) * rows * cols);
    if (!buf) return 1;
    for (int i = 0; i < rows; i++)
      for (int j = 0; j < cols; j++)
        buf[(size_t)i * cols + j] = A[i + (size_t)j * rows];
  }
  int bad = vi_h5_put(g, name, H5T_NATIVE_DOUBLE, cols > 0 ? 2 : 1, dims,
                      buf ? buf : A, meaning);
  free(buf);
  return bad;
}

/* A sparse symmetric matrix as group `name`: colptr [n + 1], rowind [nnz],
 * values [nnz] (0-based CSC, lower triangle with the diagonal: the
 * Harwell-Boeing / vi_fe_set_mass_csc form) with attributes rows, cols,
 * nnz, storage "lower", index_base 0. */
static int put_csc(hid_t parent, const char *name, int n, int nnz,
                   const int *colptr, const int *rowind, const double *val)
{
  hid_t g = vi_h5_group(parent, name);
  if (g < 0) return 1;
  int bad = vi_h5_attr_int(g, "rows", n) | vi_h5_attr_int(g, "cols", n) |
            vi_h5_attr_int(g, "nnz", nnz) |
            vi_h5_attr_str(g, "storage", "lower") |
            vi_h5_attr_int(g, "index_base", 0);
  hsize_t dp = (hsize_t)n + 1, dn = (hsize_t)nnz;
  bad |= vi_h5_put(g, "colptr", H5T_NATIVE_INT, 1, &dp, colptr, "column j: "
                   "entries colptr[j] .. colptr[j+1]-1");
  bad |= vi_h5_put(g, "rowind", H5T_NATIVE_INT, 1, &dn, rowind, "row of each "
                   "entry, ascending within a column");
  bad |= put(g, "values", val, nnz, 0, "value of each entry");
  return vi_h5_close(g) | bad;
}

/* /fe of an FE scene (model.matrices): the physical model as it came in,
 * sparse: M, K (and C) from the scene's files, their formats, the dofs and
 * kept modes, and for coordinate files the numbering of the dofs (node,
 * dof of each).  The rows are the files' own (read again: O(nnz), no
 * eigensolve). */
static int write_dofmap(hid_t g, const vi_dofmap *map)
{
  int n = vi_dofmap_n(map), bad = 0;
  int *nd = malloc(2 * sizeof(int) * ((size_t)n + 1));
  if (!nd) return 1;
  for (int i = 0; i < n; i++)
    bad |= vi_dofmap_label(map, i + 1, nd + i, nd + n + i) != VI_OK;
  hsize_t dn = (hsize_t)n;
  bad |= vi_h5_put(g, "dof_node", H5T_NATIVE_INT, 1, &dn, nd, "node label "
                   "of global dof i (row i of M, K, C): the (node, dof) "
                   "pairs of the coordinate files, sorted by node then dof");
  bad |= vi_h5_put(g, "dof_component", H5T_NATIVE_INT, 1, &dn, nd + n,
                   "dof (component) at that node of global dof i");
  free(nd);
  return bad;
}

/* What the reduction did (vi_scene_fe_summary), once the model is made. */
static int write_reduction(hid_t g, const struct vi_scene_fe_report *r)
{
  static const char *const rules[3] = {"whole", "given", "host"};
  if (!r || !r->done) return 0;
  int bad = vi_h5_attr_str(g, "modes_rule",
                           rules[r->rule >= 0 && r->rule < 3 ? r->rule : 0]);
  bad |= vi_h5_attr_int(g, "massless_dofs", r->massless);
  bad |= vi_h5_attr_int(g, "rigid_modes", r->rigid);
  bad |= vi_h5_attr_double(g, "orthogonality", r->orth);
  bad |= vi_h5_attr_double(g, "max_residual", r->resid);
  if (r->mresid) {
    hsize_t k = (hsize_t)r->modes;
    bad |= vi_h5_put(g, "mode_residual", H5T_NATIVE_DOUBLE, 1, &k, r->mresid,
                     "backward error of each kept mode, ||K psi - lambda M "
                     "psi|| / ((||K|| + |lambda| ||M||) ||psi||)");
  }
  return bad;
}

static int write_fe(vi_writer *w, const vi_scene *s)
{
  static const char *const names[3] = {"M", "C", "K"};
  static const char *const fmts[4] = {"auto", "matrix_market",
                                      "harwell_boeing", "coordinate"};
  hid_t g = vi_h5_group(w->file, "fe");
  if (g < 0) return 1;
  int bad = vi_h5_attr_int(g, "dofs", s->n) |
            vi_h5_attr_int(g, "modes", s->fe.modes);
  bad |= vi_h5_attr_str(g, "meaning", "the finite-element model (physical dofs, "
                  "sparse); the run's model is its reduction to the lowest "
                  "modes (/model)");
  if (s->fe.map) bad |= write_dofmap(g, s->fe.map);
  bad |= write_reduction(g, s->fe.report);
  for (int k = 0; k < 3 && !bad; k++) {
    if (!s->fe.path[k]) continue;
    vi_mm *mm = NULL;
    vi_diag d;
    if (vi_matrix_load(s->fe.path[k], s->fe.format[k], s->fe.map,
                       VI_CSC_LOWER, 0, &mm, &d)) {
      bad = 1;
      snprintf(w->errmsg, sizeof w->errmsg, "%s", d.message);
      break;
    }
    bad |= put_csc(g, names[k], vi_mm_rows(mm), vi_mm_nnz(mm),
                   vi_mm_colptr(mm), vi_mm_rowind(mm), vi_mm_values(mm));
    char an[16];
    snprintf(an, sizeof an, "%s_file", names[k]);
    bad |= vi_h5_attr_str(g, an, s->fe.path[k]);
    snprintf(an, sizeof an, "%s_format", names[k]);
    int f = s->fe.format[k];
    bad |= vi_h5_attr_str(g, an, fmts[f >= 0 && f < 4 ? f : 0]);
    vi_mm_destroy(&mm);
  }
  H5Gclose(g);
  return bad;
}

int vi_writer_fe_shapes(vi_writer *w, const vi_fe *fe)
{
  if (!w || !fe) return VI_ERR_ARG;
  if (w->failed) return VI_ERR_IO;
  int n = vi_fe_n(fe), k = vi_fe_num_modes(fe), ld = 0;
  const double *Psi = vi_fe_shapes(fe, &ld), *om = vi_fe_omega(fe);
  if (!Psi || !om)
    return warg(w, VI_ERR_STATE, "vi_writer_fe_shapes: the reduction holds "
                "no full Psi (vi_fe_set_keep_shapes(fe, 1) before its setup)");
  if (k != w->n)
    return warg(w, VI_ERR_DIM, "vi_writer_fe_shapes: %d modes, the writer's "
                "model has n = %d", k, w->n);
  int st = reserve(w, 8.0 * ((double)n * k + k));
  if (st) return st;
  int bad = 0;
  H5E_BEGIN_TRY
  {
    hid_t g = H5Lexists(w->file, "fe", H5P_DEFAULT) > 0
                  ? H5Gopen2(w->file, "fe", H5P_DEFAULT)
                  : vi_h5_group(w->file, "fe");
    bad = g < 0;
    if (g >= 0) {
      /* [n][k] in C order: row i = dof i, as Psi(i, j) */
      bad |= ld != n ||
             put(g, "Psi", Psi, n, k, "mass-normalised modes kept, column j "
                 "= mode j (x = Psi q)");
      bad |= put(g, "omega", om, k, 0, "natural frequencies of the kept modes");
      H5Gclose(g);
    }
  }
  H5E_END_TRY;
  return bad ? werr(w, VI_ERR_IO, "cannot write the mode shapes to %s",
                    w->part)
             : VI_OK;
}

/* ---- growing tables -----------------------------------------------------
 * Rows are buffered (cap rows, ~64 KiB for the widest column) and the
 * datasets are made at the first flush: a table that never fills its buffer
 * gets chunks of exactly its rows, so short runs give small files; a long
 * one gets chunks of cap whole rows along time. */
static int table_init(vi_writer *w, table *t, const char *group, int compress)
{
  t->gname = group;
  t->compress = compress;
  int widest = 1;
  for (int k = 0; k < t->ncol; k++)
    widest = t->c[k].width > widest ? t->c[k].width : widest;
  t->cap = 8192 / widest > 16 ? 8192 / widest : 16;
  for (int k = 0; k < t->ncol; k++) {
    t->c[k].buf = malloc(sizeof(double) * (size_t)t->cap * t->c[k].width);
    if (!t->c[k].buf) return werr(w, VI_ERR_NOMEM, "out of memory");
  }
  return VI_OK;
}

static int table_make(vi_writer *w, table *t, hsize_t chunk_rows)
{
  if (t->group <= 0) {
    t->group = vi_h5_group(w->file, t->gname);
    if (t->group < 0) {
      t->group = 0;
      return werr(w, VI_ERR_IO, "cannot create group /%s in %s (disk full?)",
                  t->gname, w->part);
    }
  }
  if (chunk_rows < 1) chunk_rows = 1;
  for (int k = 0; k < t->ncol; k++) {
    col *c = &t->c[k];
    hsize_t dims[2] = {0, (hsize_t)c->width},
            maxd[2] = {H5S_UNLIMITED, (hsize_t)c->width};
    hsize_t chunk[2] = {chunk_rows, (hsize_t)c->width};
    hid_t sp = H5Screate_simple(c->rank, dims, maxd),
          pl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(pl, c->rank, chunk);
    if (t->compress) {
      H5Pset_shuffle(pl);
      H5Pset_deflate(pl, 4);
    }
    /* rows are flushed a whole chunk at a time, so HDF5's default 1 MiB
     * chunk cache per dataset would only grow the footprint */
    hid_t ap = H5Pcreate(H5P_DATASET_ACCESS);
    H5Pset_chunk_cache(ap, 11, 2 * sizeof(double) * chunk_rows * c->width,
                       1.0);
    c->dset = H5Dcreate2(t->group, c->name, c->ftype, sp, H5P_DEFAULT, pl, ap);
    H5Pclose(ap);
    H5Pclose(pl);
    H5Sclose(sp);
    if (c->dset < 0) {
      c->dset = 0;
      return werr(w, VI_ERR_IO, "cannot create dataset /%s/%s in %s "
                  "(disk full?)", t->gname, c->name, w->part);
    }
    if (vi_h5_attr_str(c->dset, "units", c->units) ||
        vi_h5_attr_str(c->dset, "meaning", c->meaning))
      return werr(w, VI_ERR_IO, "cannot write attributes of /%s/%s in %s "
                  "(disk full?)", t->gname, c->name, w->part);
  }
  t->made = 1;
  return VI_OK;
}

static int table_flush(vi_writer *w, table *t)
{
  int st;
  /* compressed chunks can be a little larger than the raw data */
  if ((st = reserve(w, 1.1 * row_bytes(t) * t->used + 4096.0 * t->ncol)))
    return st;
  if (!t->made &&
      (st = table_make(w, t, t->used < t->cap ? (hsize_t)t->used
                                              : (hsize_t)t->cap)))
    return st;
  if (t->used == 0) return VI_OK;
  for (int k = 0; k < t->ncol; k++) {
    col *c = &t->c[k];
    hsize_t size[2] = {t->rows + t->used, (hsize_t)c->width};
    hsize_t start[2] = {t->rows, 0},
            count[2] = {(hsize_t)t->used, (hsize_t)c->width};
    if (H5Dset_extent(c->dset, size) < 0)
      return werr(w, VI_ERR_IO, "cannot extend /%s/%s in %s (disk full?)",
                  t->gname, c->name, w->part);
    hid_t fs = H5Dget_space(c->dset),
          ms = H5Screate_simple(c->rank, count, NULL);
    herr_t e = H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count,
                                   NULL);
    if (e >= 0)
      e = H5Dwrite(c->dset, H5T_NATIVE_DOUBLE, ms, fs, H5P_DEFAULT, c->buf);
    H5Sclose(ms);
    H5Sclose(fs);
    if (e < 0)
      return werr(w, VI_ERR_IO, "cannot write /%s/%s in %s (disk full?)",
                  t->gname, c->name, w->part);
  }
  t->rows += t->used;
  t->used = 0;
  return VI_OK;
}

/* Append one row: vals[k] points at column k's width values. */
static int table_row(vi_writer *w, table *t, const double *const *vals)
{
  if (w->failed) return VI_ERR_IO; /* the file is already broken */
  /* after vi_writer_finish the tables' buffers are gone */
  if (!w->file) return warg(w, VI_ERR_STATE, "the writer is already closed");
  for (int k = 0; k < t->ncol; k++)
    memcpy(t->c[k].buf + (size_t)t->used * t->c[k].width, vals[k],
           sizeof(double) * t->c[k].width);
  if (++t->used == t->cap) return table_flush(w, t);
  return VI_OK;
}

static void table_close(table *t)
{
  for (int k = 0; k < t->ncol; k++) {
    if (t->c[k].dset > 0) H5Dclose(t->c[k].dset);
    free(t->c[k].buf);
    t->c[k].dset = 0;
    t->c[k].buf = NULL;
  }
  if (t->group > 0) H5Gclose(t->group);
  t->group = 0;
}

/* per-row scalars are [rows]; per-coordinate columns are [rows][n], for
 * n = 1 too, so a reader never sees the rank change with the model */
#define COL(nm, wd, ft, un, mn) ((col){nm, un, mn, wd, 1, ft, 0, NULL})
#define VEC(nm, wd, ft, un, mn) ((col){nm, un, mn, wd, 2, ft, 0, NULL})

/* ---- public ------------------------------------------------------------- */
static int create_fail(vi_diag *diag, const char *path, int code,
                       const char *msg)
{
  if (diag) {
    memset(diag, 0, sizeof *diag);
    diag->code = code;
    snprintf(diag->file, sizeof diag->file, "%s", path ? path : "");
    snprintf(diag->message, sizeof diag->message, "%.500s", msg);
  }
  return code;
}

int vi_writer_create(const char *path, const vi_model *model, int compress,
                     vi_writer **out, vi_diag *diag)
{
  if (diag) memset(diag, 0, sizeof *diag);
  if (out) *out = NULL;
  if (!path || !model || !out)
    return create_fail(diag, path, VI_ERR_ARG,
                       "vi_writer_create: path, model and out are required");
  int n = vi_model_n(model), st = VI_OK;
  /* set up means frozen: the stop's compliance w.M^-1.w is > 0 then, also
   * for a free body whose omega_1 = 0 (omega_bound is 0 for K = 0) */
  if (n < 1 || !(vi_model_stop_compliance(model) > 0))
    return create_fail(diag, path, VI_ERR_STATE,
                       "vi_writer_create: the model is not set up "
                       "(vi_model_setup)");
  char target[4096];
  if ((st = vi_output_resolve(path, target, (int)sizeof target, diag)))
    return st;
  vi_writer *w = calloc(1, sizeof *w);
  if (!w) return create_fail(diag, path, VI_ERR_NOMEM, "out of memory");
  w->m = model;
  w->n = n;
  w->fd = -1;
  w->compress = compress;
  w->path = strdup(target);
  w->part = malloc(strlen(target) + 6);
  w->q = malloc(sizeof(double) * 2 * (size_t)n);
  if (!w->path || !w->part || !w->q) {
    vi_writer_abort(&w);
    return create_fail(diag, path, VI_ERR_NOMEM, "out of memory");
  }
  w->qd = w->q + n;
  vi_output_part(target, w->part, (int)strlen(target) + 6);
  /* a stale PATH.part of an earlier crash is ours (vi_output_resolve made
   * sure it is a plain file); EXCL then creates a fresh one and never
   * follows a link planted in between */
  remove(w->part);
  errno = 0;
  H5E_BEGIN_TRY
  {
    w->file = H5Fcreate(w->part, H5F_ACC_EXCL, H5P_DEFAULT, H5P_DEFAULT);
  }
  H5E_END_TRY;
  if (w->file < 0) {
    int e = errno;
    char msg[600];
    snprintf(msg, sizeof msg, "cannot create %s: %s", w->part,
             e ? strerror(e) : "HDF5 refused");
    w->file = 0;
    vi_writer_abort(&w);
    return create_fail(diag, path, VI_ERR_IO, msg);
  }
  w->fd = open(w->part, O_WRONLY | O_CLOEXEC);
  if (w->fd < 0 || reserve(w, 0) != VI_OK) {
    char msg[600];
    snprintf(msg, sizeof msg, "%.500s", w->fd < 0 ? "cannot open the new "
             "file again" : w->errmsg);
    vi_writer_abort(&w);
    return create_fail(diag, path, VI_ERR_IO, msg);
  }
  hid_t F64 = H5T_IEEE_F64LE, I32 = H5T_STD_I32LE;
  w->imp.ncol = 8;
  w->imp.c[0] = COL("time", 1, F64, "time", "instant of the event");
  w->imp.c[1] = COL("kind", 1, I32, "1", "0 impact, 1 stick, 2 release");
  w->imp.c[2] = COL("vn", 1, F64, "length/time", "approach velocity w.x'(t-)");
  w->imp.c[3] = COL("ie", 1, F64, "energy", "kinetic energy lost (WB 10)");
  w->imp.c[4] = VEC("x", n, F64, "length", "positions at the event");
  w->imp.c[5] = VEC("v_minus", n, F64, "length/time", "velocities before");
  w->imp.c[6] = VEC("v_plus", n, F64, "length/time", "velocities after");
  w->imp.c[7] = COL("stop", 1, I32, "1",
                    "the stop hit, stuck on or released (0-based)");
  w->traj.ncol = 5;
  w->traj.c[0] = COL("time", 1, F64, "time", "uniform sample times");
  w->traj.c[1] = VEC("x", n, F64, "length", "physical positions");
  w->traj.c[2] = VEC("v", n, F64, "length/time", "physical velocities");
  w->traj.c[3] = VEC("q", n, F64, "modal", "modal coordinates q = Psi^T M x "
                     "(NaN for a band-stored model, which has no modes)");
  w->traj.c[4] = VEC("qd", n, F64, "modal/time", "modal velocities (NaN as q)");
  w->led.ncol = 13;
  w->led.c[0] = COL("t_a", 1, F64, "time", "interval start");
  w->led.c[1] = COL("t_b", 1, F64, "time", "interval end (before the event)");
  w->led.c[2] = VEC("E_a", n, F64, "energy", "modal energy at t_a");
  w->led.c[3] = VEC("E_b", n, F64, "energy", "modal energy at t_b");
  w->led.c[4] =
      VEC("FE", n, F64, "energy", "forcing work into each mode (WB 7)");
  w->led.c[5] = VEC("DE", n, F64, "energy", "damping loss of each mode (WB 8)");
  w->led.c[6] = VEC("XE", n, F64, "energy", "damping coupling work");
  w->led.c[7] =
      VEC("CE", n, F64, "energy", "contact-force work while sticking");
  w->led.c[8] = VEC("dE", n, F64, "energy", "impact jump of each mode at t_b");
  w->led.c[9] = COL("ie", 1, F64, "energy", "energy lost at t_b (WB 10)");
  w->led.c[10] =
      COL("residual", 1, F64, "1", "closure residual / energy scale");
  w->led.c[11] =
      COL("impact", 1, I32, "1", "1 when the interval ends in a jump");
  w->led.c[12] = VEC("NE", n, F64, "energy",
                     "work of the nonlinear forces on each mode (0 without)");
  if ((st = table_init(w, &w->imp, "impacts", 0)) == VI_OK &&
      (st = table_init(w, &w->traj, "trajectory", compress)) == VI_OK)
    st = table_init(w, &w->led, "ledger", 0);
  if (st) {
    create_fail(diag, path, st, w->errmsg);
    vi_writer_abort(&w);
    return st;
  }
  *out = w;
  return VI_OK;
}

int vi_writer_write_header(vi_writer *w, const vi_scene *scene, double rtol,
                           double atol, int method)
{
  if (!w) return VI_ERR_ARG;
  if (w->failed) return VI_ERR_IO;
  if (scene && vi_scene_n(scene) != w->n)
    return warg(w, VI_ERR_DIM, "the scene has n = %d, the writer's model "
                "n = %d", vi_scene_n(scene), w->n);
  const char *mname = vi_method_name(method);
  if (!mname || !(rtol > 0) || !(atol > 0))
    return warg(w, VI_ERR_ARG, "vi_writer_write_header: method %d, rtol %g, "
                "atol %g", method, rtol, atol);
  const vi_model *m = w->m;
  int n = w->n, bad = 0, ld;
  char creator[64];
  int kd = vi_model_bandwidth(m); /* >= 0: band storage, no modes */
  double nn = kd < 0 ? (double)n * n : (kd + 1.0) * n;
  int fe = scene && scene->kind == VI_SCENE_FE;
  int st = reserve(w, 8.0 * (5 * nn + 10.0 * n) +
                          (scene ? (double)strlen(vi_scene_text(scene)) : 0) +
                          (fe ? 36.0 * (double)scene->fe.entries +
                                    12.0 * scene->n
                              : 0));
  if (st) return st;
  snprintf(creator, sizeof creator, "vibroimpact %s", vi_version_string());
  H5E_BEGIN_TRY
  {
    bad |= vi_h5_attr_str(w->file, "creator", creator);
    bad |= vi_h5_attr_int(w->file, "format_version", FORMAT_VERSION);
    bad |= vi_h5_attr_str(w->file, "sundials", vi_sundials_version());
    if (scene) {
      /* a dataset, not an attribute: attributes stop at 64 KiB */
      bad |= vi_h5_str(w->file, "scene", vi_scene_text(scene),
                       VI_H5_DATASET);
      bad |= vi_h5_attr_str(w->file, "scene_name", vi_scene_name(scene));
    }
    bad |= vi_h5_attr_double(w->file, "rtol", rtol);
    bad |= vi_h5_attr_double(w->file, "atol", atol);
    bad |= vi_h5_attr_str(w->file, "method", mname);
    bad |= vi_h5_attr_int(w->file, "complete", 0);
    bad |= vi_h5_attr_str(w->file, "units",
                    "consistent model units: any length, mass and time");
    hid_t g =
        vi_h5_group(w->file, "model");
    bad |= g < 0;
    if (g >= 0) {
      double v;
      if (kd < 0) {
        bad |= put(g, "M", vi_model_mass(m), n, n, "mass matrix");
        bad |= put(g, "C", vi_model_damping(m), n, n, "damping matrix");
        bad |= put(g, "K", vi_model_stiffness(m), n, n, "stiffness matrix");
      } else { /* LAPACK 'U' band rows [ldab x n], as vi_model_mass_band */
        int bk, ldab;
        const double *B = vi_model_mass_band(m, &bk, &ldab);
        bad |= put(g, "M_band", B, ldab, n, "mass matrix, symmetric band "
                   "'U' storage: (i, j) at row kd + i - j, column j");
        B = vi_model_damping_band(m, &bk, &ldab);
        bad |= put(g, "C_band", B, ldab, n, "damping matrix, band as M_band");
        B = vi_model_stiffness_band(m, &bk, &ldab);
        bad |= put(g, "K_band", B, ldab, n, "stiffness matrix, band as M_band");
        bad |= vi_h5_attr_int(g, "kd", kd);
      }
      bad |=
          put(g, "w", vi_model_stop_vector(m), n, 0, "stop vector: w.x <= x_s");
      bad |=
          put(g, "a", vi_model_forcing_cos(m), n, 0, "forcing a cos(Omega t)");
      bad |=
          put(g, "b", vi_model_forcing_sin(m), n, 0, "forcing b sin(Omega t)");
      bad |= put(g, "f0", vi_model_forcing_const(m), n, 0, "constant load");
      v = vi_model_clearance(m);
      bad |= vi_h5_attr_double(g, "x_s", v);
      v = vi_model_restitution(m);
      bad |= vi_h5_attr_double(g, "r", v);
      v = vi_model_omega_forcing(m);
      bad |= vi_h5_attr_double(g, "Omega", v);
      int ns = vi_model_num_stops(m);
      if (ns > 1) { /* several stops: all of them, row k = stop k */
        double *sw = malloc(sizeof(double) * ((size_t)ns * (n + 2) + n));
        bad |= !sw;
        if (sw) {
          /* column-major ns x n for put(): element (k, j) = w_k(j) */
          double *sx = sw + (size_t)ns * n, *sr = sx + ns, *wk = sr + ns;
          for (int k = 0; k < ns; k++) {
            vi_model_stop(m, k, wk, sx + k, sr + k);
            for (int j = 0; j < n; j++) sw[k + (size_t)j * ns] = wk[j];
          }
          bad |= put(g, "stops_w", sw, ns, n, "stop vectors, row k: w_k.x <= "
                     "x_s_k");
          bad |= put(g, "stops_x_s", sx, ns, 0, "clearance of each stop");
          bad |= put(g, "stops_r", sr, ns, 0, "restitution of each stop");
          free(sw);
        }
      }
      H5Gclose(g);
    }
    /* the modes only when the scene asks for them (always without a scene)
     * and the model has them (a band model has none) */
    g = kd >= 0 || (scene && !(vi_scene_outputs(scene) & VI_SCENE_OUT_MODES))
            ? 0
            : vi_h5_group(w->file, "modal");
    bad |= g < 0;
    if (g > 0) {
      bad |= put(g, "omega", vi_model_omega(m), n, 0,
                 "natural frequencies, ascending");
      bad |= put(g, "zeta", vi_model_zeta(m), n, 0,
                 "modal damping ratios D_jj/(2 omega_j)");
      bad |= put(g, "Psi", vi_model_modal_shapes(m, &ld), n, n,
                 "mass-normalised modes, column j = mode j");
      bad |= put(g, "D", vi_model_modal_damping(m, &ld), n, n, "Psi^T C Psi");
      bad |= put(g, "psi", vi_model_modal_stop(m), n, 0,
                 "modal impact vector Psi^T w");
      bad |= vi_h5_attr_int(g, "proportional", vi_model_is_proportional(m));
      H5Gclose(g);
    }
    if (fe) bad |= write_fe(w, scene);
  }
  H5E_END_TRY;
  return bad ? werr(w, VI_ERR_IO, "cannot write the header of %s", w->part)
             : VI_OK;
}

int vi_writer_event(vi_writer *w, const vi_event *ev)
{
  if (!w || !ev || !ev->x || !ev->v_minus || !ev->v_plus) return VI_ERR_ARG;
  if (ev->n != w->n)
    return warg(w, VI_ERR_DIM, "event of n = %d for a writer of n = %d",
                ev->n, w->n);
  if (ev->kind < VI_EVENT_IMPACT || ev->kind > VI_EVENT_RELEASE ||
      ev->stop < 0 || ev->stop >= vi_model_num_stops(w->m))
    return warg(w, VI_ERR_ARG, "event of kind %d on stop %d: out of range "
                "(kinds 0..2, stops 0..%d)", ev->kind, ev->stop,
                vi_model_num_stops(w->m) - 1);
  int finite = isfinite(ev->t) && isfinite(ev->vn) && isfinite(ev->ie);
  for (int i = 0; i < w->n && finite; i++)
    finite = isfinite(ev->x[i]) && isfinite(ev->v_minus[i]) &&
             isfinite(ev->v_plus[i]);
  if (!finite)
    return warg(w, VI_ERR_NONFINITE, "event at t = %g holds a value that is "
                "not finite", ev->t);
  double kind = ev->kind, stop = ev->stop;
  const double *vals[8] = {&ev->t, &kind,       &ev->vn,   &ev->ie,
                           ev->x,  ev->v_minus, ev->v_plus, &stop};
  int st;
  H5E_BEGIN_TRY { st = table_row(w, &w->imp, vals); }
  H5E_END_TRY;
  return st;
}

int vi_writer_sample(vi_writer *w, double t, const double *x, const double *v)
{
  if (!w || !x || !v) return VI_ERR_ARG;
  int finite = isfinite(t);
  for (int i = 0; i < w->n && finite; i++) finite = isfinite(x[i]) && isfinite(v[i]);
  if (!finite)
    return warg(w, VI_ERR_NONFINITE, "sample at t = %g holds a value that is "
                "not finite", t);
  if (vi_model_to_modal(w->m, x, w->q) != VI_OK ||
      vi_model_to_modal(w->m, v, w->qd) != VI_OK)
    for (int j = 0; j < 2 * w->n; j++) w->q[j] = NAN; /* a band model: no modes */
  const double *vals[5] = {&t, x, v, w->q, w->qd};
  int st;
  H5E_BEGIN_TRY { st = table_row(w, &w->traj, vals); }
  H5E_END_TRY;
  return st;
}

int vi_writer_ledger(vi_writer *w, const vi_ledger_interval *iv)
{
  if (!w || !iv || !iv->Ea || !iv->Eb || !iv->FE || !iv->DE || !iv->XE ||
      !iv->CE)
    return VI_ERR_ARG;
  if (iv->n != w->n)
    return warg(w, VI_ERR_DIM, "ledger interval of n = %d for a writer of "
                "n = %d", iv->n, w->n);
  double imp = iv->dE ? 1.0 : 0.0;
  const double *dE = iv->dE ? iv->dE : w->q; /* zeros when no jump */
  if (!iv->dE) memset(w->q, 0, sizeof(double) * w->n);
  const double *NE = iv->NE ? iv->NE : w->q; /* zeros without forces */
  if (!iv->NE) memset(w->q, 0, sizeof(double) * w->n);
  const double *vals[13] = {&iv->t_a, &iv->t_b, iv->Ea,        iv->Eb,
                            iv->FE,   iv->DE,   iv->XE,        iv->CE,
                            dE,       &iv->ie,  &iv->residual, &imp, NE};
  int st;
  H5E_BEGIN_TRY { st = table_row(w, &w->led, vals); }
  H5E_END_TRY;
  return st;
}

int vi_writer_orbit(vi_writer *w, const vi_orbit *o)
{
  if (!w || !o) return VI_ERR_ARG;
  if (w->failed) return VI_ERR_IO;
  int n = w->n, pn, pm, bad = 0;
  if (vi_orbit_classify(o, &pn, &pm) != VI_OK)
    return warg(w, VI_ERR_STATE, "%s", "vi_writer_orbit: the orbit was never "
                "sought (vi_orbit_find)");
  if (reserve(w, 8.0 * (12.0 * n + 64))) return VI_ERR_IO;
  double *buf = calloc(10 * (size_t)n + 8, sizeof(double));
  if (!buf) return werr(w, VI_ERR_NOMEM, "out of memory");
  /* the getters below fill [n] arrays of the orbit's own n: an orbit of a
   * larger model would write past buf (vi_orbit_impacts refuses ld < n;
   * buf holds its at most 8 columns) */
  int cnt;
  if (vi_orbit_impacts(o, &cnt, NULL, NULL, NULL, buf, NULL, n) == VI_ERR_ARG) {
    free(buf);
    return warg(w, VI_ERR_DIM, "vi_writer_orbit: the orbit's model has more "
                "coordinates than the writer's (%d)", n);
  }
  H5E_BEGIN_TRY {
    hid_t g = vi_h5_group(w->file, "orbits");
    bad |= g < 0 || vi_h5_attr_int(g, "period_n", pn) || vi_h5_attr_int(g, "impacts_m", pm);
    double v[9];
    if (g >= 0 && !vi_orbit_balance(o, &v[0], &v[1], &v[2], &v[3], &v[4],
                                    &v[5], &v[6], &v[7])) {
      static const char *names[8] = {"period", "impact_phase", "vN", "KE_i",
                                     "RE", "IE", "r_recovered", "closure"};
      hid_t p = vi_h5_group(g, "P1_1");
      bad |= p < 0;
      for (int k = 0; k < 8 && p >= 0; k++) bad |= vi_h5_attr_double(p, names[k], v[k]);
      double *x = buf, *vel = x + n, *re = vel + n, *im = re + (size_t)2 * n;
      double *FE = im + (size_t)2 * n, *DE = FE + n, *XE = DE + n, *reff = XE + n;
      double *rS = reff + n, gmin, t;
      const int modes[4] = {0, 1, 2, 3};
      vi_orbit_impact_state(o, &t, x, vel);
      vi_orbit_multipliers(o, re, im);
      vi_orbit_modal_balance(o, FE, DE, XE, reff);
      vi_orbit_min_gap(o, &gmin);
      int kmax = n < 4 ? n : 4;
      for (int k = 1; k <= kmax; k++)
        if (vi_orbit_reduced_restitution(o, modes, k, &rS[k - 1])) rS[k - 1] = NAN;
      if (p >= 0) {
        bad |= vi_h5_attr_double(p, "t_impact", t) || vi_h5_attr_double(p, "min_gap", gmin);
        bad |= put(p, "x_impact", x, n, 0, "positions at the impact");
        bad |= put(p, "v_impact", vel, n, 0, "velocities just before it");
        bad |= put(p, "multipliers_re", re, 2 * n, 0, "Floquet multipliers, real parts");
        bad |= put(p, "multipliers_im", im, 2 * n, 0, "Floquet multipliers, imaginary parts");
        bad |= put(p, "FE", FE, n, 0, "forcing work per mode over one period");
        bad |= put(p, "DE", DE, n, 0, "damping loss per mode over one period");
        bad |= put(p, "XE", XE, n, 0, "damping coupling per mode over one period");
        bad |= put(p, "r_eff", reff, n, 0, "-q_j'(+) / q_j'(-) at the impact");
        bad |= put(p, "r_S", rS, kmax, 0, "restitution of the reduced model with the first 1, 2, ... modes");
        H5Gclose(p);
      }
    }
    if (g >= 0) H5Gclose(g);
  } H5E_END_TRY;
  free(buf);
  return bad ? werr(w, VI_ERR_IO, "cannot write /orbits to %s", w->part) : VI_OK;
}

int64_t vi_writer_rows(const vi_writer *w, const char *what)
{
  if (!w || !what) return -1;
  const table *t = !strcmp(what, "impacts")      ? &w->imp
                   : !strcmp(what, "trajectory") ? &w->traj
                   : !strcmp(what, "ledger")     ? &w->led
                                                 : NULL;
  return t ? (long)(t->rows + t->used) : -1;
}

int vi_writer_run_info(vi_writer *w, const vi_sim *sim)
{
  if (!w || !sim) return VI_ERR_ARG;
  if (w->failed) return VI_ERR_IO;
  int bad = 0;
  if (reserve(w, 4096.0 + 256.0 * VI_STAT_COUNT)) return VI_ERR_IO;
  const char *used = vi_method_name(vi_sim_method_used(sim)),
             *note = vi_sim_method_note(sim);
  H5E_BEGIN_TRY
  {
    hid_t g = vi_h5_group(w->file, "run");
    bad |= g < 0;
    if (g >= 0) {
      bad |= vi_h5_attr_str(g, "method_used", used ? used : "none");
      bad |= vi_h5_attr_str(g, "method_note", note ? note : "");
      for (int k = 0; k < VI_STAT_COUNT; k++) {
        const char *name = vi_stat_name(k);
        if (name) bad |= vi_h5_attr_i64(g, name, vi_sim_stat(sim, k));
      }
      bad |= H5Gclose(g) < 0;
    }
  }
  H5E_END_TRY;
  return bad ? werr(w, VI_ERR_IO, "cannot write /run to %s (disk full?)",
                    w->part)
             : VI_OK;
}

/* Close every HDF5 object and our descriptor; 0 when the file closed
 * cleanly (reserve() keeps HDF5 from meeting a full disk, so its close
 * succeeds even after our own write error). */
static int close_all(vi_writer *w)
{
  int bad = 0;
  haddr_t eoa = 0;
  H5E_BEGIN_TRY
  {
    table_close(&w->imp);
    table_close(&w->traj);
    table_close(&w->led);
    /* zero padding ends where HDF5's allocation ends */
    if (w->file > 0 && w->zero_fill &&
        (H5Fflush(w->file, H5F_SCOPE_LOCAL) < 0 ||
         H5Fget_eoa(w->file, &eoa) < 0))
      eoa = 0;
    if (w->file > 0) bad = H5Fclose(w->file) < 0;
  }
  H5E_END_TRY;
  if (!bad && w->fd >= 0 && eoa > 0 && ftruncate(w->fd, (off_t)eoa) != 0)
    bad = 1;
  w->file = 0;
  if (w->fd >= 0) {
    /* give back the blocks reserved past the end */
    struct stat st;
    if (!bad && !w->zero_fill && w->reserved > 0 &&
        fstat(w->fd, &st) == 0 && ftruncate(w->fd, st.st_size) != 0)
      bad = 1;
    if (close(w->fd) != 0) bad = 1;
    w->fd = -1;
  }
  return bad;
}

static void free_writer(vi_writer *w)
{
  free(w->path);
  free(w->part);
  free(w->q);
  free(w);
}

int vi_writer_finish(vi_writer *w, int complete)
{
  if (!w) return VI_ERR_ARG;
  if (!w->file) return warg(w, VI_ERR_STATE, "the writer is already closed");
  int st = w->failed ? VI_ERR_IO : VI_OK;
  if (!st)
    st = reserve(w, 1.1 * (row_bytes(&w->imp) * w->imp.used +
                           row_bytes(&w->traj) * w->traj.used +
                           row_bytes(&w->led) * w->led.used) + 65536.0);
  if (st) {
    /* keep the first error's message */
  } else {
    H5E_BEGIN_TRY
    {
      if ((st = table_flush(w, &w->imp)) == VI_OK &&
          (st = table_flush(w, &w->traj)) == VI_OK &&
          (w->led.rows + w->led.used > 0)) /* no empty /ledger */
        st = table_flush(w, &w->led);
      if (st == VI_OK) {
        hid_t a = H5Aopen(w->file, "complete", H5P_DEFAULT);
        int c = complete ? 1 : 0;
        if (a < 0 || H5Awrite(a, H5T_NATIVE_INT, &c) < 0)
          st = werr(w, VI_ERR_IO, "cannot mark %s complete (no header "
                    "written?)", w->part);
        if (a >= 0) H5Aclose(a);
        if (st == VI_OK && H5Fflush(w->file, H5F_SCOPE_GLOBAL) < 0)
          st = werr(w, VI_ERR_IO, "cannot flush %s (disk full?)", w->part);
      }
    }
    H5E_END_TRY;
  }
  if (close_all(w) && st == VI_OK)
    st = werr(w, VI_ERR_IO, "cannot close %s (disk full?)", w->part);
  if (st == VI_OK && rename(w->part, w->path) != 0)
    st = werr(w, VI_ERR_IO, "cannot rename %s to %s: %s", w->part, w->path,
              strerror(errno));
  if (st) remove(w->part);
  return st;
}

int vi_writer_close(vi_writer **wp, int complete)
{
  if (!wp || !*wp) return VI_ERR_ARG;
  int st = vi_writer_finish(*wp, complete);
  vi_writer_abort(wp);
  return st;
}

void vi_writer_abort(vi_writer **wp)
{
  if (!wp || !*wp) return;
  vi_writer *w = *wp;
  int open = w->file > 0;
  close_all(w);
  if (open && w->part) remove(w->part);
  free_writer(w);
  *wp = NULL;
}
