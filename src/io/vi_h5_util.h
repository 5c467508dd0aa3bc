/* vi_h5_util.h - the one set of small HDF5 helpers of every writer (a
 * run, a truncation study, an identification, the program's sweep and
 * basins); never installed.
 *
 * One source, vi_h5_util.c, compiled into each target that writes HDF5:
 * libvibroimpact_h5 (and its static twin for the program) and the
 * program's sweep library.  libvibroimpact_h5 hides its non-API symbols,
 * so the sweep cannot call its copy; the objects are built from the same
 * file, there is no second text.
 *
 * Every helper runs its HDF5 calls inside H5E_BEGIN_TRY (HDF5 prints
 * nothing) and returns nonzero on any failure, which the callers OR into
 * one flag.  Memory types are native; the file types are the little-endian
 * IEEE / two's-complement types of the same size, whatever the host. */
#ifndef VI_H5_UTIL_H
#define VI_H5_UTIL_H

#include <stdint.h>

#include <hdf5.h>

#include "vibroimpact/vi_scene.h"

/* vi_h5_str flags */
enum {
  VI_H5_DATASET = 1, /* a scalar dataset (no 64 KiB limit), not an attribute */
  VI_H5_UTF8 = 2     /* character set UTF-8 (default ASCII) */
};

/* Dataset `name` of rank 1..4 with dims, from data of native type mtype
 * (H5T_NATIVE_DOUBLE, _INT, _INT64) in C order; meaning != NULL adds the
 * string attribute "meaning".  Nothing is written for zero elements. */
int vi_h5_put(hid_t loc, const char *name, hid_t mtype, int rank,
              const hsize_t *dims, const void *data, const char *meaning);

/* Attribute `name` of len values (len 1: a scalar) of native type mtype. */
int vi_h5_attr(hid_t loc, const char *name, hid_t mtype, const void *v,
               hsize_t len);
int vi_h5_attr_double(hid_t loc, const char *name, double v);
int vi_h5_attr_int(hid_t loc, const char *name, int v);
int vi_h5_attr_i64(hid_t loc, const char *name, int64_t v);

/* A fixed-length string (its terminating NUL included) as an attribute,
 * or with VI_H5_DATASET a scalar dataset; VI_H5_UTF8 marks it UTF-8. */
int vi_h5_str(hid_t loc, const char *name, const char *val, int flags);
int vi_h5_attr_str(hid_t loc, const char *name, const char *val);

/* Group `name` in loc; < 0 on failure.  Closed by vi_h5_close. */
hid_t vi_h5_group(hid_t loc, const char *name);
/* Close an object id (group, dataset, ...) if >= 0; nonzero on failure. */
int vi_h5_close(hid_t id);

/* ---- small files built in memory -----------------------------------------
 * HDF5 1.10 writing to a disk that fills (or past a file size limit) fails
 * its flush, and the file it could not close then crashes its atexit
 * handler (exit 139).  A file built with the core driver and no backing
 * store never meets the disk: its image is written by vi_output_open /
 * vi_output_close, which check every write, the sync and the rename, and
 * leave no TARGET.part and the old TARGET on failure.  For files of some
 * MB at most (a study's tables): a run's trajectory streams (vi_writer.c). */

/* A new HDF5 file in memory named `name` (for HDF5's messages only),
 * growing in steps of `increment` bytes; < 0 on failure. */
hid_t vi_h5_image_create(const char *name, size_t increment);

/* Close f (every object in it closed) and write its image to target
 * through TARGET.part; bad != 0 (an earlier HDF5 failure) only closes.
 * @return VI_OK, VI_ERR_IO (the reason in diag), VI_ERR_NOMEM. */
int vi_h5_image_commit(hid_t f, int bad, const char *target, vi_diag *diag);

#endif
