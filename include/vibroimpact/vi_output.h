/** @file vi_output.h
 * Where a program's output may go (companion library vibroimpact_scene): the
 * one output path of every command.
 *
 * A regular file is written as TARGET.part and renamed to TARGET once
 * every write, flush, sync and close has succeeded, so a failed or
 * interrupted program (a full disk included) leaves no partial file and
 * TARGET keeps what it held before.  Symbolic links are followed to their
 * final target (which is replaced, the link stays); directories, FIFOs,
 * sockets, block devices and a TARGET.part that is not a plain file are
 * refused, and so is the scene the output would overwrite (compared by
 * device and inode, not by name).  A stream output (a CSV, a JSON summary)
 * may also go to a character device (/dev/null, a terminal), which is then
 * written directly and never replaced, or to the standard output ("-").
 *
 * Typical use, before anything is computed:
 * @code
 *   char target[4096];
 *   int kind;
 *   if (vi_output_check(path, VI_OUTPUT_STREAM, scene_path, target,
 *                       sizeof target, &kind, &diag)) fail(&diag);
 *   FILE *f;
 *   vi_output_open(target, kind, &f, &diag);
 *   ... fprintf(f, ...) ...
 *   if (vi_output_close(&f, target, kind, &diag)) fail(&diag);  // renamed
 *   // or, on any error: vi_output_discard(&f, target, kind);
 * @endcode */
#ifndef VI_OUTPUT_H
#define VI_OUTPUT_H

#include <stdio.h>

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Flags of vi_output_check. */
typedef enum vi_output_flag {
  VI_OUTPUT_REGULAR = 0, /**< regular files only (HDF5 files) */
  VI_OUTPUT_STREAM = 1   /**< also a character device, or "-" for stdout */
} vi_output_flag;

/** What kind of target vi_output_check found. */
typedef enum vi_output_kind {
  VI_OUTPUT_FILE = 0,   /**< a regular file: written through TARGET.part */
  VI_OUTPUT_DEVICE = 1, /**< a character device, written directly */
  VI_OUTPUT_STDOUT = 2  /**< the standard output ("-") */
} vi_output_kind;

/** Check, before anything is computed, where output for `path` will go:
 *  symbolic links followed to the final target (written into target[len]),
 *  the folder tried by creating and removing TARGET.part.  Refuses
 *  (VI_ERR_IO, the reason in diag) directories, FIFOs, sockets, block
 *  devices, character devices unless flags has VI_OUTPUT_STREAM, a target
 *  or folder that is not writable, a TARGET.part that exists and is not a
 *  regular file (a planted link), and (VI_ERR_ARG, a usage error) the
 *  file `scene` (NULL: none) itself.  kind (NULL: not wanted) receives a
 *  vi_output_kind.  @return VI_OK, VI_ERR_ARG, VI_ERR_IO, VI_ERR_LIMIT
 *  (path longer than len). */
VI_API int vi_output_check(const char *path, int flags, const char *scene,
                           char *target, int len, int *kind, vi_diag *diag);

/** vi_output_check(path, VI_OUTPUT_REGULAR, NULL, target, len, NULL,
 *  diag): the check of an HDF5 output.  @return as vi_output_check. */
VI_API int vi_output_resolve(const char *path, char *target, int len,
                             vi_diag *diag);

/** The partial file of target, "TARGET.part", into part[len] (the one
 *  place that name is made).  @return VI_OK, VI_ERR_ARG, VI_ERR_LIMIT. */
VI_API int vi_output_part(const char *target, char *part, int len);

/** 1 if paths a and b name the same file, compared by device and inode:
 *  of the files where both exist, else of their folders plus the last
 *  name (two names of a file still to be written); 0 if not or when
 *  either is NULL or "-". */
VI_API int vi_output_same(const char *a, const char *b);

/** Open the output checked by vi_output_check: TARGET.part created anew
 *  for a file (a stale one of ours is removed), the device itself, or
 *  stdout.  @return VI_OK, VI_ERR_ARG, VI_ERR_IO (reason in diag). */
VI_API int vi_output_open(const char *target, int kind, FILE **out,
                          vi_diag *diag);

/** Finish an output opened by vi_output_open and set *f to NULL: every
 *  error of the stream, the flush, the sync and the close is checked; a
 *  file's TARGET.part is then renamed to TARGET, and removed on any
 *  failure.  stdout is flushed and checked, not closed.
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_IO (reason in diag). */
VI_API int vi_output_close(FILE **f, const char *target, int kind,
                           vi_diag *diag);

/** Give up an output: close *f (NULL-safe; stdout is left open) and
 *  remove a file's TARGET.part; TARGET is untouched.  Safe after an
 *  error or a failed vi_output_close. */
VI_API void vi_output_discard(FILE **f, const char *target, int kind);

/** Sync TARGET.part (already written and closed by its writer) and rename
 *  it to TARGET; on failure it is removed.  @return VI_OK, VI_ERR_ARG,
 *  VI_ERR_IO (reason in diag). */
VI_API int vi_output_commit(const char *target, vi_diag *diag);

#ifdef __cplusplus
}
#endif

#endif
