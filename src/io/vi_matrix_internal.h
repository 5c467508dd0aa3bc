/* vi_matrix_internal.h - what the matrix readers of libvibroimpact_scene
 * share (vi_mmio.c: Matrix Market and the shared parts; vi_hbio.c:
 * Harwell-Boeing / Rutherford-Boeing; vi_coordio.c: FE codes'
 * (node, dof, node, dof, value) exports); never installed.  The functions
 * are hidden by the library's visibility, as every non-API symbol. */
#ifndef VI_MATRIX_INTERNAL_H
#define VI_MATRIX_INTERNAL_H

#include <stdint.h>
#include <stdio.h>

#include "vi_io_internal.h"
#include "vibroimpact/vi_mmio.h"

struct vi_mm {
  int rows, cols, nnz, storage;
  int *colptr, *rowind;
  double *val;
};

/* A text file read line by line: regular files only (a FIFO or a device
 * such as /dev/zero is refused at the open, never read). */
typedef struct vi_mx_reader {
  FILE *f;
  const char *path;
  vi_diag *d;
  int line;                     /* 1-based number of the line in buf */
  char buf[VI_MM_MAX_LINE + 2]; /* the line, NUL-terminated, no line end */
} vi_mx_reader;

int vi_mx_open(vi_mx_reader *r, const char *path, vi_diag *d);
/* The next line into r->buf: 1, or 0 at the end (or an error: *st). */
int vi_mx_next_line(vi_mx_reader *r, int *st);
/* An error at the current line and column col (0: the line as a whole). */
int vi_mx_fail_at(vi_mx_reader *r, int code, int col, const char *key,
                  const char *fmt, ...) __attribute__((format(printf, 5, 6)));
#define vi_mx_fail(r, code, key, ...) vi_mx_fail_at(r, code, 0, key, __VA_ARGS__)
/* Refuse (VI_ERR_PARSE, at the current line) a regular file whose bytes
 * after the current position are fewer than `least`: a short file cannot
 * make the reader allocate for what its header promises. */
int vi_mx_check_room(vi_mx_reader *r, double least, int64_t entries,
                     const char *key);

/* Entries as read: 0-based indices, the line of each. */
typedef struct vi_mx_triplets {
  int *i, *j, *line;
  double *v;
  int64_t count, cap;
} vi_mx_triplets;

int vi_mx_trip_alloc(vi_mx_triplets *t, int64_t cap);
void vi_mx_trip_free(vi_mx_triplets *t);

/* The triplets into CSC (vi_mmio.h's rules): symmetric 1 when they hold
 * the lower triangle of a symmetric matrix (mirrored for VI_CSC_FULL: t
 * must have room for twice its count), 0 for a general matrix (checked
 * symmetric and averaged for VI_CSC_LOWER); duplicates refused with both
 * lines named. */
int vi_mx_build(vi_mx_reader *r, int rows, int cols, int symmetric,
                vi_mx_triplets *t, int storage, vi_mm **out);

/* The formats' own readers (vi_hbio.c, vi_coordio.c), behind
 * vi_matrix_read_header and vi_matrix_load. */
int vi_hb_header(const char *path, int *rows, int *cols, int64_t *entries,
                 int *symmetric, vi_diag *d);
int vi_hb_load(const char *path, int storage, double max_bytes, vi_mm **out,
               vi_diag *d);
int vi_coord_load(const char *path, const vi_dofmap *map, int storage,
                  double max_bytes, vi_mm **out, vi_diag *d);
/* Entries (lines) of the largest file the map was scanned over. */
int64_t vi_dofmap_entries(const vi_dofmap *map);

#endif
