/* vi_writer.h - HDF5 output of a run (companion library vibroimpact_io).
 * The layout is documented in share/doc/hdf5-layout.md.
 *
 * The file is written as PATH.part and renamed to PATH by vi_writer_close:
 * complete = 1 for a finished run, 0 for an interrupted one (the file is
 * valid and its root attribute `complete` says 0).  vi_writer_abort removes
 * the partial file: after an error no output file exists.  Rows are
 * buffered and appended to chunked, extendible datasets, so memory does not
 * grow with the run. */
#ifndef VI_WRITER_H
#define VI_WRITER_H

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_ledger.h"
#include "vibroimpact/vi_model.h"
#include "vibroimpact/vi_scene.h"
#include "vibroimpact/vi_sim.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vi_writer vi_writer;

/* Create PATH.part for a model of n coordinates.  compress: shuffle +
 * deflate(4) on the trajectory. */
VI_API int vi_writer_create(const char *path, const vi_model *model,
                            int compress, vi_writer **out, vi_diag *diag);
/* Scene text and run parameters as attributes, /model and /modal. */
VI_API int vi_writer_write_header(vi_writer *w, const vi_scene *scene,
                                  double rtol, double atol, int method);
/* Append one event, one sample (physical and modal), one ledger interval. */
VI_API int vi_writer_event(vi_writer *w, const vi_event *ev);
VI_API int vi_writer_sample(vi_writer *w, double t, const double *x,
                            const double *v);
VI_API int vi_writer_ledger(vi_writer *w, const vi_ledger_interval *iv);
/* Counters for the summary. */
VI_API long vi_writer_rows(const vi_writer *w, const char *what);
/* Flush, mark complete (1) or interrupted (0), close and rename. */
VI_API int vi_writer_close(vi_writer **w, int complete);
/* Close and delete the partial file. */
VI_API void vi_writer_abort(vi_writer **w);
VI_API const char *vi_writer_errmsg(const vi_writer *w);

#ifdef __cplusplus
}
#endif
#endif
