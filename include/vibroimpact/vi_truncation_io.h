/** @file vi_truncation_io.h
 * HDF5 output of a truncation study (companion library vibroimpact_h5),
 * the content of `vibroimpact truncation --json` (doc/truncation-layout.md).
 *
 * The study is passed as caller-owned column-major tables: one row per
 * kept-mode count k, VI_TRUNCATION_COLUMNS columns in this order (0-based
 * column: the dataset it becomes; [3]: three columns, the first impacts):
 *
 *   0 k, 1 omega, 2 dynamic_fraction, 3 static_fraction,
 *   4 class_n, 5 class_m, 6 vN, 7 phase   (the k-mode response with r:
 *        class_n -1 no orbit search ran, 0 not periodic with class_m
 *        impacts per period, else P(class_n, class_m); vN, phase of P(1,1))
 *   8 first_n (impacts found, -1 the run failed), 9 first_t [3],
 *   12 first_vn [3], 15 first_dt [3], 18 first_dvn_rel [3] (against the
 *        reference's, NaN where either has no such impact), 21 release,
 *   22 r_S, 23 r_S_class_n, 24 r_S_class_m, 25 r_S_vN, 26 r_S_phase,
 *   27 static_corrected (1: the variant exists, 0: no mode beyond k),
 *   28 sc_dynamic_fraction, 29 sc_class_n, 30 sc_class_m, 31 sc_vN,
 *   32 sc_phase, 33 sc_first_n, 34 sc_first_t [3], 37 sc_first_vn [3],
 *   40 sc_first_dt [3], 43 sc_first_dvn_rel [3], 46 sc_release.
 *
 * Missing values are NaN.  The reference is one row of the same layout.
 * info[VI_TRUNCATION_INFO] holds, in order: dofs, modes_lo, modes_hi,
 * reference_modes, restitution, compliance_dynamic, compliance_static. */
#ifndef VI_TRUNCATION_IO_H
#define VI_TRUNCATION_IO_H

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Sizes of the tables of vi_truncation_write_h5. */
enum vi_truncation_size {
  VI_TRUNCATION_COLUMNS = 47, /**< columns of a row (the layout above) */
  VI_TRUNCATION_INFO = 8      /**< entries of info (the last: 1 for a
                                   complete study, 0 for one interrupted) */
};

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
