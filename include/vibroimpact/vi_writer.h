/** @file vi_writer.h
 * HDF5 output of a run (companion library vibroimpact_h5).
 * The layout is documented in share/doc/hdf5-layout.md.
 *
 * Output goes to regular files only: a symbolic link is followed to its
 * target, devices, FIFOs, sockets and directories are refused
 * (vi_output_resolve of vi_output.h, which a program can call before
 * computing anything).
 * The file is written as TARGET.part and renamed to TARGET by
 * vi_writer_finish / vi_writer_close: complete = 1 for a finished run, 0
 * for an interrupted one (the file is valid and its root attribute
 * `complete` says 0).  On any failure (a full disk included) the partial
 * file is removed and TARGET keeps what it held before.  vi_writer_abort
 * removes the partial file: after an error no output file exists.  Rows are
 * buffered and appended to chunked, extendible datasets, so memory does not
 * grow with the run. */
#ifndef VI_WRITER_H
#define VI_WRITER_H

#include <stdint.h>

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_ledger.h"
#include "vibroimpact/vi_model.h"
#include "vibroimpact/vi_output.h"
#include "vibroimpact/vi_orbit.h"
#include "vibroimpact/vi_scene.h"
#include "vibroimpact/vi_sim.h"
#include "vibroimpact/vi_sparse.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Opaque HDF5 writer handle. */
typedef struct vi_writer vi_writer;

/** Create TARGET.part for the model's run (the model is borrowed and must
 *  be set up); path is resolved as by vi_output_resolve; compress != 0
 *  puts shuffle + deflate(4) on the trajectory.  @return VI_OK, VI_ERR_IO
 *  (with the reason in diag), VI_ERR_ARG, VI_ERR_STATE (model not set up),
 *  VI_ERR_NOMEM. */
VI_API int vi_writer_create(const char *path, const vi_model *model,
                            int compress, vi_writer **out, vi_diag *diag);
/** Write the root attributes (creator, tolerances, method), the scene text
 *  (dataset /scene), /model and, when the scene's output.modes is true or
 *  scene is NULL, /modal; for a model.matrix_market scene also /fe with
 *  its sparse M, K (and C) read from the scene's files (CSC, lower
 *  triangle; the run's /model is then the k-mode reduction).  @return VI_OK, VI_ERR_IO, VI_ERR_ARG (unknown
 *  method, tolerances not > 0), VI_ERR_DIM (a scene of another n). */
VI_API int vi_writer_write_header(vi_writer *w, const vi_scene *scene,
                                  double rtol, double atol, int method);
/** Write the kept mode shapes of a finite-element reduction to /fe: Psi
 *  [n][k] (row i = dof i, column j = mode j, x = Psi q) and omega [k].
 *  Only when asked (the scene's output.shapes; `vibroimpact run` calls
 *  it): a 1e5-dof, 20-mode Psi is 16 MB, the rest of such a file a few kB
 *  plus the sparse matrices (vi_writer_write_header writes those, M, K and
 *  C as CSC, for a model.matrix_market scene).  fe must have kept its
 *  shapes (vi_fe_set_keep_shapes, or vi_scene_create_fe with keep 1) and
 *  have as many modes as the writer's model has coordinates.
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE (no full Psi), VI_ERR_DIM,
 *  VI_ERR_IO. */
VI_API int vi_writer_fe_shapes(vi_writer *w, const vi_fe *fe);
/** Append one event to /impacts.  @return VI_OK, VI_ERR_IO (disk full...),
 *  VI_ERR_DIM (another n), VI_ERR_ARG (a kind or stop out of range),
 *  VI_ERR_NONFINITE (a value not finite; nothing written). */
VI_API int vi_writer_event(vi_writer *w, const vi_event *ev);
/** Append one sample at t (x, v [n]) to /trajectory, with its modal
 *  coordinates.  @return VI_OK, VI_ERR_IO, VI_ERR_NONFINITE (t, x or v not
 *  finite; nothing written). */
VI_API int vi_writer_sample(vi_writer *w, double t, const double *x,
                            const double *v);
/** Append one ledger interval to /ledger.  @return VI_OK, VI_ERR_IO. */
VI_API int vi_writer_ledger(vi_writer *w, const vi_ledger_interval *iv);
/** Write the analysis of a found orbit: group /orbits with its class
 *  (attributes period_n, impacts_m) and, for P(1,1), /orbits/P1_1 with the
 *  balance of WB 11-13 as attributes, the impact state, Floquet multipliers,
 *  per-mode FE, DE, XE, r_eff and the reduced-model r_S of the first 1..4
 *  modes (NaN where none exists).  @return VI_OK, VI_ERR_IO, VI_ERR_STATE
 *  (an orbit vi_orbit_find never sought). */
VI_API int vi_writer_orbit(vi_writer *w, const vi_orbit *orbit);
/** Write group /run: the method that ran and why (vi_sim_method_used,
 *  vi_sim_method_note) and every statistic (vi_stat_name: value) as
 *  attributes.  @return VI_OK, VI_ERR_ARG, VI_ERR_IO. */
VI_API int vi_writer_run_info(vi_writer *w, const vi_sim *sim);
/** Rows written so far to "impacts", "trajectory" or "ledger" (-1 for
 *  another name). */
VI_API int64_t vi_writer_rows(const vi_writer *w, const char *what);
/** Flush, mark the file complete (1) or interrupted (0), close it and
 *  rename TARGET.part to TARGET.  On failure (or after an earlier write
 *  error) the partial file is removed and TARGET is untouched; the handle
 *  stays valid for vi_writer_errmsg until vi_writer_abort frees it.
 *  @return VI_OK, VI_ERR_IO, VI_ERR_STATE (already finished). */
VI_API int vi_writer_finish(vi_writer *w, int complete);
/** vi_writer_finish, then free the handle: *w is NULL afterwards whatever
 *  the outcome (use vi_writer_finish to read the reason of a failure).
 *  @return VI_OK, VI_ERR_IO, VI_ERR_ARG. */
VI_API int vi_writer_close(vi_writer **w, int complete);
/** Close and free; deletes the partial file unless vi_writer_finish
 *  already renamed it (after an error: no output file at all); *w becomes
 *  NULL.  NULL-safe. */
VI_API void vi_writer_abort(vi_writer **w);
/** Detail of the last error ("" if none), owned by the writer. */
VI_API const char *vi_writer_errmsg(const vi_writer *w);

#ifdef __cplusplus
}
#endif
#endif
