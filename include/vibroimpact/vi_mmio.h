/** @file vi_mmio.h
 * Matrix Market files (NIST's exchange format, math.nist.gov/MatrixMarket)
 * read into compressed sparse columns: part of the companion library
 * vibroimpact_scene, so that a finite-element model's M, C and K can come from
 * the host's own code as files.
 *
 * The grammar read, in full:
 *
 *   %%MatrixMarket matrix coordinate|array real|double|integer|pattern
 *                                          general|symmetric|skew-symmetric|hermitian
 *   % comment lines (and blank lines) anywhere after the header
 *   rows cols entries        (coordinate)  |  rows cols  (array)
 *   i j value                (coordinate: 1-based indices, one entry a line)
 *   value                    (array: column by column, one value a line;
 *                             symmetric: the lower triangle only)
 *
 * The header's words are case-insensitive.  Refused with a message saying
 * why: `vector` objects, `complex` and `hermitian` (M, C, K are real),
 * `skew-symmetric` (M, C, K are symmetric), `pattern` (a structure without
 * values cannot be a mass or stiffness matrix).  Every malformed file is an
 * error naming the file and line (vi_diag: key "header", "size" or
 * "entry k", value the line as written): a missing or wrong header, a size
 * line that is not two or three positive whole numbers, more entries than
 * the matrix holds, an index out of range, a value that is not a number,
 * not finite or (field integer) not whole, extra or missing words on a line,
 * too few entries (a truncated file: refused at the size line when the
 * file's bytes cannot hold them, so nothing is allocated for them) or too
 * many, an entry above the
 * diagonal in a symmetric file (the format stores the lower triangle), and
 * a **duplicate entry, which is refused** with both lines named (the format
 * does not define duplicates; an assembled matrix has none, so a duplicate
 * is a writer's error, not something to sum).  Coordinate entries may come
 * in any order and explicit zeros are kept; the exact zeros of an array file
 * are dropped.  Line endings LF or CRLF; lines up to 1024 characters.
 *
 * Output: CSC arrays (the Harwell-Boeing convention), 0-based, rows sorted
 * within each column: colptr [cols + 1], rowind and values [nnz], as
 * vi_fe_set_mass_csc (vi_sparse.h) takes them with base 0.  Storage
 * (vi_csc_storage) VI_CSC_LOWER keeps the lower triangle (i >= j) of a square symmetric
 * matrix: a symmetric file as it is, a general file after checking that
 * A(i,j) = A(j,i) to 1e-12 of the largest |A| (as vi_model_set_mass does;
 * VI_ERR_NOT_SYMMETRIC names both lines otherwise) and storing the average.
 * VI_CSC_FULL keeps every entry, a symmetric file's mirrored.
 *
 * Memory: a file of E entries (vi_mm_read_header) takes about 40 E bytes
 * while it is read and 12 E (24 E for VI_CSC_FULL of a symmetric file) once
 * stored; vi_mm_load_limited refuses, before reading the entries, a file
 * that would need more than its limit.
 */
#ifndef VI_MMIO_H
#define VI_MMIO_H

#include <stdint.h>

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_scene.h"
#include "vibroimpact/vi_sparse.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Longest line of a Matrix Market file read (characters, without the
 *  line end). */
#define VI_MM_MAX_LINE 1024

/** Opaque loaded matrix: CSC arrays and their dimensions. */
typedef struct vi_mm vi_mm;

/** Read only the header and size line of a Matrix Market file: *rows,
 *  *cols, *entries (the values stored in the file: the size line's count
 *  for coordinate, rows cols or the lower triangle's n (n + 1) / 2 for
 *  array) and *symmetric (1 for a symmetric file); each may be NULL.  For
 *  an estimate of memory before anything is read.
 *  @return VI_OK, VI_ERR_ARG (path NULL), VI_ERR_IO, VI_ERR_PARSE,
 *  VI_ERR_UNSUPPORTED (complex, hermitian, skew-symmetric, pattern, vector),
 *  VI_ERR_LIMIT (a dimension beyond int) with diag (may be NULL) naming the
 *  file and line. */
VI_API int vi_mm_read_header(const char *path, int *rows, int *cols,
                             int64_t *entries, int *symmetric, vi_diag *diag);
/** Read a Matrix Market file into CSC storage (see the file comment);
 *  *out receives the matrix, NULL on failure.  storage: VI_CSC_LOWER
 *  (square and symmetric) or VI_CSC_FULL (any matrix).
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_IO, VI_ERR_PARSE, VI_ERR_DIM (an index
 *  out of range; a matrix that is not square for VI_MM_LOWER),
 *  VI_ERR_NONFINITE, VI_ERR_NOT_SYMMETRIC, VI_ERR_UNSUPPORTED, VI_ERR_LIMIT,
 *  VI_ERR_NOMEM, with diag (may be NULL) naming file, line and entry. */
VI_API int vi_mm_load(const char *path, int storage, vi_mm **out,
                      vi_diag *diag);
/** vi_mm_load refusing (VI_ERR_LIMIT, before the entries are read) a file
 *  whose reading would take more than max_bytes (<= 0: no limit; the
 *  estimate of the file comment). */
VI_API int vi_mm_load_limited(const char *path, int storage, double max_bytes,
                              vi_mm **out, vi_diag *diag);
/** Destroy and set *mm to NULL; NULL-safe. */
VI_API void vi_mm_destroy(vi_mm **mm);

/** Rows of the matrix (0 for NULL). */
VI_API int vi_mm_rows(const vi_mm *mm);
/** Columns of the matrix (0 for NULL). */
VI_API int vi_mm_cols(const vi_mm *mm);
/** Entries stored (the length of rowind and values; 0 for NULL). */
VI_API int vi_mm_nnz(const vi_mm *mm);
/** The storage held, VI_CSC_LOWER or VI_CSC_FULL (-1 for NULL). */
VI_API int vi_mm_storage_kind(const vi_mm *mm);
/** Column pointers [cols + 1], 0-based (column j's entries are
 *  colptr[j] .. colptr[j+1] - 1; Fortran adds 1); a view owned by mm,
 *  NULL for NULL. */
VI_API const int *vi_mm_colptr(const vi_mm *mm);
/** Row indices [nnz], 0-based, ascending within each column; a view. */
VI_API const int *vi_mm_rowind(const vi_mm *mm);
/** Values [nnz]; a view. */
VI_API const double *vi_mm_values(const vi_mm *mm);

#ifdef __cplusplus
}
#endif
#endif
