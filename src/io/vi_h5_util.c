/* vi_h5_util.c - the small HDF5 helpers of every writer (vi_h5_util.h).
 * Compiled into libvibroimpact_h5 and into the program's sweep library
 * (CMakeLists.txt): one source, one home, two hidden copies. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "vi_h5_util.h"
#include "vi_io_internal.h"
#include "vibroimpact/vi_output.h"

/* The file type of a native memory type: little-endian of the same size,
 * so a file reads the same on any host. */
static hid_t file_type(hid_t mtype)
{
  if (H5Tequal(mtype, H5T_NATIVE_DOUBLE) > 0) return H5T_IEEE_F64LE;
  if (H5Tequal(mtype, H5T_NATIVE_INT) > 0) return H5T_STD_I32LE;
  if (H5Tequal(mtype, H5T_NATIVE_INT64) > 0) return H5T_STD_I64LE;
  return mtype;
}

int vi_h5_put(hid_t loc, const char *name, hid_t mtype, int rank,
              const hsize_t *dims, const void *data, const char *meaning)
{
  int bad = 1;
  hsize_t count = 1;
  for (int i = 0; i < rank; i++) count *= dims[i];
  H5E_BEGIN_TRY {
    hid_t sp = H5Screate_simple(rank, dims, NULL), ds = -1;
    if (sp >= 0)
      ds = H5Dcreate2(loc, name, file_type(mtype), sp, H5P_DEFAULT,
                      H5P_DEFAULT, H5P_DEFAULT);
    bad = ds < 0 || (count > 0 && H5Dwrite(ds, mtype, H5S_ALL, H5S_ALL,
                                           H5P_DEFAULT, data) < 0);
    if (ds >= 0 && meaning) bad |= vi_h5_attr_str(ds, "meaning", meaning);
    if (ds >= 0 && H5Dclose(ds) < 0) bad = 1;
    if (sp >= 0) H5Sclose(sp);
  } H5E_END_TRY;
  return bad;
}

int vi_h5_attr(hid_t loc, const char *name, hid_t mtype, const void *v,
               hsize_t len)
{
  int bad = 1;
  H5E_BEGIN_TRY {
    hid_t sp = len == 1 ? H5Screate(H5S_SCALAR)
                        : H5Screate_simple(1, &len, NULL),
          a = -1;
    if (sp >= 0)
      a = H5Acreate2(loc, name, file_type(mtype), sp, H5P_DEFAULT,
                     H5P_DEFAULT);
    bad = a < 0 || H5Awrite(a, mtype, v) < 0;
    if (a >= 0 && H5Aclose(a) < 0) bad = 1;
    if (sp >= 0) H5Sclose(sp);
  } H5E_END_TRY;
  return bad;
}

int vi_h5_attr_double(hid_t loc, const char *name, double v)
{
  return vi_h5_attr(loc, name, H5T_NATIVE_DOUBLE, &v, 1);
}

int vi_h5_attr_int(hid_t loc, const char *name, int v)
{
  return vi_h5_attr(loc, name, H5T_NATIVE_INT, &v, 1);
}

int vi_h5_attr_i64(hid_t loc, const char *name, int64_t v)
{
  return vi_h5_attr(loc, name, H5T_NATIVE_INT64, &v, 1);
}

int vi_h5_str(hid_t loc, const char *name, const char *val, int flags)
{
  int bad = 1;
  H5E_BEGIN_TRY {
    hid_t t = H5Tcopy(H5T_C_S1), sp = -1, o = -1;
    if (t >= 0 && H5Tset_size(t, strlen(val) + 1) >= 0 &&
        (!(flags & VI_H5_UTF8) || H5Tset_cset(t, H5T_CSET_UTF8) >= 0))
      sp = H5Screate(H5S_SCALAR);
    if (sp >= 0 && (flags & VI_H5_DATASET)) {
      o = H5Dcreate2(loc, name, t, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      bad = o < 0 || H5Dwrite(o, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, val) < 0;
      if (o >= 0 && H5Dclose(o) < 0) bad = 1;
    } else if (sp >= 0) {
      o = H5Acreate2(loc, name, t, sp, H5P_DEFAULT, H5P_DEFAULT);
      bad = o < 0 || H5Awrite(o, t, val) < 0;
      if (o >= 0 && H5Aclose(o) < 0) bad = 1;
    }
    if (sp >= 0) H5Sclose(sp);
    if (t >= 0) H5Tclose(t);
  } H5E_END_TRY;
  return bad;
}

int vi_h5_attr_str(hid_t loc, const char *name, const char *val)
{
  return vi_h5_str(loc, name, val, 0);
}

hid_t vi_h5_group(hid_t loc, const char *name)
{
  hid_t g = -1;
  H5E_BEGIN_TRY {
    g = H5Gcreate2(loc, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  } H5E_END_TRY;
  return g;
}

int vi_h5_close(hid_t id)
{
  herr_t e = 0;
  if (id >= 0) H5E_BEGIN_TRY { e = H5Oclose(id); } H5E_END_TRY;
  return e < 0;
}

hid_t vi_h5_image_create(const char *name, size_t increment)
{
  hid_t f = -1;
  H5E_BEGIN_TRY {
    hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
    if (fapl >= 0 && H5Pset_fapl_core(fapl, increment, 0) >= 0)
      f = H5Fcreate(name, H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
    if (fapl >= 0) H5Pclose(fapl);
  } H5E_END_TRY;
  return f;
}

int vi_h5_image_commit(hid_t f, int bad, const char *target, vi_diag *diag)
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
