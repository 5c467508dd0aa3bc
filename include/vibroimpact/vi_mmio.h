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


/* ---- other formats FE codes write, and choosing by content --------------
 * vi_matrix_load reads the same CSC (the same rules: duplicates refused,
 * general files checked symmetric for VI_CSC_LOWER, every malformed field
 * named by line and column) from three formats:
 *
 * VI_MATRIX_MARKET: the grammar above.
 *
 * VI_MATRIX_HARWELL_BOEING: Harwell-Boeing (Duff, Grimes, Lewis 1989) and
 *   Rutherford-Boeing (Duff, Grimes, Lewis 1997) files, .rsa .rua .rb:
 *     line 1  title (A72) and key (A8): free text
 *     line 2  TOTCRD PTRCRD INDCRD VALCRD [RHSCRD]   (I14 each; RB has
 *             no RHSCRD)
 *     line 3  MXTYPE (A3), 11 blanks, NROW NCOL NNZERO [NELTVL] (I14 each)
 *     line 4  PTRFMT (A16) INDFMT (A16) VALFMT (A20) [RHSFMT (A20)]
 *     line 5  (HB with RHSCRD > 0 only) RHSTYP NRHS NRHSIX: skipped
 *     then PTRCRD lines of NCOL + 1 column pointers, INDCRD lines of
 *     NNZERO row indices, VALCRD lines of NNZERO values, each in its
 *     Fortran format; right-hand sides after them are not read.
 *   MXTYPE (either case): R (real) or I (integer) values, S (symmetric:
 *   the lower triangle stored, an entry above the diagonal refused) or U
 *   (unsymmetric: checked symmetric for VI_CSC_LOWER, as a general Matrix
 *   Market file) or R (rectangular, VI_CSC_FULL only), A (assembled).
 *   Refused, saying why: C (complex), P (pattern: no values), H, Z, E
 *   (elemental: unassembled element matrices).
 *   Formats: (rIw) for the integers, (rEw.d), (rDw.d), (rFw.d), (rGw.d),
 *   (rESw.d), (rENw.d) (an optional Ee exponent width) for the values, with
 *   an optional scale factor kP ((1P5D16.9), (1P,4E20.12)).  Each line
 *   holds r fields of w columns (the last line of a section fewer;
 *   trailing blanks of a line may be left out).  A value is read as
 *   Fortran reads it: an optional sign, digits with an optional point (no
 *   point: the last d digits are the fraction), an optional exponent
 *   written E, D, e, d with an optional sign, or a bare sign (1.0-3 is
 *   1.0e-3); without an exponent the scale factor divides by 10^k.
 *   Refused: a blank field, blanks inside a number (a sign that the
 *   format's widths do not match the file), anything after a line's r
 *   fields, counts that do not match the formats (PTRCRD, INDCRD, VALCRD,
 *   TOTCRD), pointers that do not start at 1, decrease or do not end at
 *   NNZERO + 1, indices out of range, values that are not finite.
 *
 * VI_MATRIX_COORDINATE: the element-free text exports of FE codes
 *   (Abaqus' *MATRIX GENERATE with *MATRIX OUTPUT), one entry a line,
 *   fields separated by commas (or, in a line without one, by blanks):
 *     row node, row dof, column node, column dof, value   (FORMAT=MATRIX
 *                                                           INPUT)
 *     row column value            (FORMAT=COORDINATE: global equations)
 *   node labels any int (Abaqus writes internal nodes negative), dofs and
 *   equations >= 1; blank lines and comment lines (starting **, # or %)
 *   skipped; every line of a file, and every file of a model, of one kind.
 *   Equation-numbered files: global dof i is equation i, n the largest
 *   equation any of the model's files names (vi_dofmap_label gives (i, 0),
 *   vi_dofmap_index(map, i, 0) gives i).
 *   The matrix's rows are the global dofs of a vi_dofmap: the (node, dof)
 *   pairs sorted by node, then dof, numbered from 1 (0-based in the CSC).
 *   M, K and C of one model must share one map, built over all of their
 *   files (vi_dofmap_scan): a pair that only K names is still a dof of M
 *   (a massless one).  Symmetry: a file that writes some pair (i, j) both
 *   ways holds the whole matrix (every entry's mirror must be there and
 *   equal to 1e-12); a file that writes each pair once holds one triangle,
 *   in whatever order its code numbered the equations, and is mirrored.
 *
 * VI_MATRIX_AUTO chooses by content (vi_matrix_detect): a first line
 * starting %%MatrixMarket; else a Harwell-Boeing header (line 2 starting
 * with a number, line 3 with a three-letter type such as RSA); else a
 * first data line of five comma-separated fields. */
/** A matrix file's format (the grammar of each: the comment above). */
enum vi_matrix_format {
  VI_MATRIX_AUTO = 0,           /**< told by the file's content */
  VI_MATRIX_MARKET = 1,         /**< Matrix Market */
  VI_MATRIX_HARWELL_BOEING = 2, /**< Harwell-Boeing, Rutherford-Boeing */
  VI_MATRIX_COORDINATE = 3      /**< node, dof, node, dof, value lines */
};

/** The (node, dof) -> global dof numbering of coordinate files. */
typedef struct vi_dofmap vi_dofmap;

/** The format of a matrix file by its content: *format receives
 *  VI_MATRIX_MARKET, VI_MATRIX_HARWELL_BOEING or VI_MATRIX_COORDINATE.
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_IO, VI_ERR_PARSE (none of them, the
 *  message saying what each would start with). */
VI_API int vi_matrix_detect(const char *path, int *format, vi_diag *diag);
/** Read the header of a matrix file of the given format (VI_MATRIX_AUTO:
 *  detected): as vi_mm_read_header.  A coordinate file has no header: it
 *  is read whole, *rows = *cols = its own (node, dof) pairs, *entries its
 *  lines, *symmetric 1 when it holds one triangle. */
VI_API int vi_matrix_read_header(const char *path, int format, int *rows,
                                 int *cols, int64_t *entries,
                                 int *symmetric, vi_diag *diag);
/** Read a matrix file of the given format (VI_MATRIX_AUTO: detected) into
 *  CSC storage, refusing (VI_ERR_LIMIT) a file that would need more than
 *  max_bytes (<= 0: no limit).  map: the dof numbering of a coordinate
 *  file (NULL: the file's own pairs); ignored by the other formats.
 *  @return as vi_mm_load; VI_ERR_DIM also for a (node, dof) the map does
 *  not hold. */
VI_API int vi_matrix_load(const char *path, int format, const vi_dofmap *map,
                          int storage, double max_bytes, vi_mm **out,
                          vi_diag *diag);
/** The global dofs of nfiles coordinate files (M, K, C of one model): the
 *  (node, dof) pairs any of them names, sorted by node then dof.  The
 *  files are read whole (max_bytes: a limit on the pairs' memory, <= 0
 *  none).  @return VI_OK, VI_ERR_ARG, VI_ERR_IO, VI_ERR_PARSE,
 *  VI_ERR_LIMIT, VI_ERR_NOMEM with diag naming file, line and column. */
VI_API int vi_dofmap_scan(int nfiles, const char *const *paths,
                          double max_bytes, vi_dofmap **out, vi_diag *diag);
/** Destroy and set *map to NULL; NULL-safe. */
VI_API void vi_dofmap_destroy(vi_dofmap **map);
/** Global dofs (0 for NULL). */
VI_API int vi_dofmap_n(const vi_dofmap *map);
/** The node and dof of global dof `index` (1-based, as a scene's dof:
 *  keys).  @return VI_OK, VI_ERR_ARG (NULL), VI_ERR_DIM (out of range). */
VI_API int vi_dofmap_label(const vi_dofmap *map, int index, int *node,
                           int *dof);
/** The 1-based global dof of (node, dof) (equation-numbered files: (i, 0)
 *  is i); 0 when the map does not hold it (or map is NULL). */
VI_API int vi_dofmap_index(const vi_dofmap *map, int node, int dof);
/** The dof numbering of a finite-element scene read from coordinate files
 *  (a view owned by the scene); NULL for any other scene. */
VI_API const vi_dofmap *vi_scene_dofmap(const vi_scene *scene);
/** The format of an FE scene's matrix file: which 0 M, 1 K, 2 C; the
 *  VI_MATRIX_* value detected or named, -1 when the scene has no such
 *  file. */
VI_API int vi_scene_matrix_format(const vi_scene *scene, int which);

#ifdef __cplusplus
}
#endif
#endif
