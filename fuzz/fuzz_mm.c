/* fuzz_mm.c - libFuzzer target: a matrix file (Matrix Market,
 * Harwell-Boeing or coordinate, told by content) through the readers
 * (vi_mmio.h) into both storages.  Any crash, leak or sanitizer report is a
 * bug; every rejection must come with a reason, and an accepted matrix must
 * be well-formed CSC: column pointers from 0 non-decreasing to nnz, rows in
 * range and strictly increasing within a column, the lower storage below
 * the diagonal, values finite.  The reader takes a path, so each input is
 * written to one scratch file. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
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
static void remove_scratch(void) { remove(path); }

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  if (!path[0]) {
    snprintf(path, sizeof path, "fuzz_mm_%ld.mtx", (long)getpid());
    atexit(remove_scratch);
  }
  FILE *f = fopen(path, "wb");
  if (!f) return 0;
  if (size && fwrite(data, 1, size, f) != size) {
    fclose(f);
    return 0;
  }
  fclose(f);
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
