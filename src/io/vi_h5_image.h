/* vi_h5_image.h - small HDF5 files built in memory and written through the
 * output module (vi_output.h); never installed.
 *
 * HDF5 1.10 writing to a disk that fills (or past a file size limit) fails
 * its flush, and the file it could not close then crashes its atexit
 * handler (exit 139).  A file built with the core driver and no backing
 * store never meets the disk: its image is written by vi_output_open /
 * vi_output_close, which check every write, the sync and the rename, and
 * leave no TARGET.part and the old TARGET on failure.  For files of a few
 * MB at most (a study's tables): a run's trajectory streams (vi_writer.c). */
#ifndef VI_H5_IMAGE_H
#define VI_H5_IMAGE_H

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <hdf5.h>

#include "vi_io_internal.h"
#include "vibroimpact/vi_output.h"

/* A new HDF5 file in memory named `name` (for HDF5's messages only); < 0
 * on failure. */
static inline hid_t vi_h5_image_create(const char *name)
{
  hid_t f = -1, fapl = H5Pcreate(H5P_FILE_ACCESS);
  if (fapl >= 0 && H5Pset_fapl_core(fapl, (size_t)1 << 16, 0) >= 0)
    H5E_BEGIN_TRY { f = H5Fcreate(name, H5F_ACC_TRUNC, H5P_DEFAULT, fapl); }
    H5E_END_TRY;
  if (fapl >= 0) H5Pclose(fapl);
  return f;
}

/* Close f (every object in it closed) and write its image to target
 * through TARGET.part; bad != 0 (an earlier HDF5 failure) only closes.
 * @return VI_OK, VI_ERR_IO (the reason in diag), VI_ERR_NOMEM. */
static inline int vi_h5_image_commit(hid_t f, int bad, const char *target,
                                     vi_diag *diag)
{
  void *image = NULL;
  ssize_t size = -1;
  H5E_BEGIN_TRY {
    if (!bad && H5Fflush(f, H5F_SCOPE_GLOBAL) >= 0 &&
        (size = H5Fget_file_image(f, NULL, 0)) > 0 &&
        (image = malloc((size_t)size)) != NULL &&
        H5Fget_file_image(f, image, (size_t)size) != size)
      size = -1;
    if (H5Fclose(f) < 0) size = -1;
  } H5E_END_TRY;
  if (bad || size <= 0 || !image) {
    free(image);
    return vi_diag_set(diag, target, image || bad ? VI_ERR_IO : VI_ERR_NOMEM,
                       0, 0, "", "", "building the HDF5 file for %s failed",
                       target);
  }
  FILE *fp = NULL;
  int st = vi_output_open(target, VI_OUTPUT_FILE, &fp, diag), e = 0;
  /* write(2) on the descriptor: its errno (ENOSPC, EFBIG) is the message */
  for (size_t at = 0; !st && !e && at < (size_t)size;) {
    ssize_t k = write(fileno(fp), (const char *)image + at, (size_t)size - at);
    if (k > 0) at += (size_t)k;
    else e = k < 0 && errno ? errno : EIO;
  }
  free(image);
  if (st) return st;
  if (!e) return vi_output_close(&fp, target, VI_OUTPUT_FILE, diag);
  vi_output_discard(&fp, target, VI_OUTPUT_FILE);
  return vi_diag_set(diag, target, VI_ERR_IO, 0, 0, "", "",
                     "cannot write %s.part: %s", target, strerror(e));
}

#endif
