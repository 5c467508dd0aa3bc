/** @file vi_truncation_io.h
 * HDF5 output of a truncation study (companion library vibroimpact_h5),
 * the content of `vibroimpact truncation --json` (doc/truncation-layout.md).
 *
 * The study is passed as caller-owned column-major tables: one row per
 * kept-mode count k, VI_TRUNCATION_COLUMNS columns in the layout of
 * vi_truncation.h (vi_truncation_row, vi_truncation_table give them);
 * info[VI_TRUNCATION_INFO] as vi_truncation_summary gives it.  Missing values
 * are NaN. */
#ifndef VI_TRUNCATION_IO_H
#define VI_TRUNCATION_IO_H

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_scene.h"
#include "vibroimpact/vi_truncation.h" /* the row layout and sizes */

#ifdef __cplusplus
extern "C" {
#endif

/** Write a truncation study to the HDF5 file `path` (a regular file; see
 *  vi_output_resolve), as TARGET.part renamed on success: a failure
 *  leaves no file.  scene_name and scene_text (the scene as read) are
 *  stored as given (NULL: empty); info [VI_TRUNCATION_INFO]; reference
 *  [VI_TRUNCATION_COLUMNS], the reference model's row; rows
 *  [ldrows x VI_TRUNCATION_COLUMNS], column-major, nrows >= 0 of them.
 *  @return VI_OK, VI_ERR_ARG (NULL path, info, reference or rows, nrows
 *  < 0, ldrows < max(1, nrows)), VI_ERR_IO (message in diag),
 *  VI_ERR_NOMEM, VI_ERR_LIMIT (path too long). */
VI_API int vi_truncation_write_h5(const char *path, const char *scene_name,
                                  const char *scene_text, const double *info,
                                  const double *reference, int nrows,
                                  const double *rows, int ldrows,
                                  vi_diag *diag);

#ifdef __cplusplus
}
#endif
#endif
