/* fuzz_mm.c - libFuzzer target: a matrix file (Matrix Market,
 * Harwell-Boeing or coordinate, told by content) through the readers
 * (vi_mmio.h) into both storages.  Any crash, leak or sanitizer report is a
 * bug; every rejection must come with a reason, and an accepted matrix must
 * be well-formed CSC: column pointers from 0 non-decreasing to nnz, rows in
 * range and strictly increasing within a column, the lower storage below
 * the diagonal, values finite.  The reader takes a path, so each input is
 * written to one scratch file: a memory file (memfd) read through
 * /proc/self/fd, since a file on disk truncated and rewritten 20 000 times
 * waits on ext4's flush at each close (36 s of a 6 CPU-s run). */
#ifndef _GNU_SOURCE
#define _GNU_SOURCE /* memfd_create */
#endif
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <unistd.h>

#include "vibroimpact/vi_mmio.h"

static void check(const vi_mm *m, int storage)
{
  int rows = vi_mm_rows(m), cols = vi_mm_cols(m), nnz = vi_mm_nnz(m);
  const int *p = vi_mm_colptr(m), *ri = vi_mm_rowind(m);
  const double *v = vi_mm_values(m);
  if (p[0] != 0 || p[cols] != nnz) abort();
  for (int j = 0; j < cols; j++) {
    if (p[j + 1] < p[j]) abort();
    for (int k = p[j]; k < p[j + 1]; k++) {
      if (ri[k] < 0 || ri[k] >= rows || !isfinite(v[k])) abort();
      if (k > p[j] && ri[k] <= ri[k - 1]) abort();
      if (storage == VI_CSC_LOWER && ri[k] < j) abort();
    }
  }
}

static char path[64];

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  static int fd = -1;
  if (fd < 0) {
    fd = memfd_create("fuzz_mm", 0);
    if (fd < 0) abort();
    snprintf(path, sizeof path, "/proc/self/fd/%d", fd);
  }
  if (ftruncate(fd, 0) || (size && pwrite(fd, data, size, 0) != (ssize_t)size))
    abort();
  static const int storages[2] = {VI_CSC_LOWER, VI_CSC_FULL};
  for (int q = 0; q < 2; q++) {
    vi_mm *m = NULL;
    vi_diag d;
    /* the limit keeps a size line's promise from costing the fuzzer */
    int st = vi_matrix_load(path, VI_MATRIX_AUTO, NULL, storages[q], 64e6,
                            &m, &d);
    if (st) {
      if (!d.message[0] || m) abort(); /* a rejection without a reason */
      continue;
    }
    check(m, storages[q]);
    vi_mm_destroy(&m);
  }
  return 0;
}
