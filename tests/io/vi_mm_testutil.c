/* vi_mm_testutil.c - fixtures shared by the matrix readers' tests
 * (test_mmio.c, test_hbio.c): files written for one test, and the small
 * test matrix every format spells. */
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "vi_mm_testutil.h"

void vi_test_write_text(char *path, const char *tag, int k, const char *text)
{
  snprintf(path, 256, "%s_%ld_%d", tag, (long)getpid(), k);
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  assert_int_equal(fwrite(text, 1, strlen(text), f), strlen(text));
  assert_int_equal(fclose(f), 0);
}

/* A: its lower triangle and its full CSC. */
static const int lo_p[] = {0, 2, 4, 5}, lo_i[] = {0, 1, 1, 2, 2};
static const double lo_v[] = {4, -1, 4, -2, 5};
static const int fu_p[] = {0, 2, 5, 7}, fu_i[] = {0, 1, 0, 1, 2, 1, 2};
static const double fu_v[] = {4, -1, -1, 4, -2, -2, 5};

void vi_test_expect_a3(const vi_mm *m, int storage)
{
  const int *p = storage == VI_CSC_LOWER ? lo_p : fu_p,
            *ri = storage == VI_CSC_LOWER ? lo_i : fu_i;
  const double *v = storage == VI_CSC_LOWER ? lo_v : fu_v;
  int nnz = storage == VI_CSC_LOWER ? 5 : 7;
  assert_int_equal(vi_mm_rows(m), 3);
  assert_int_equal(vi_mm_cols(m), 3);
  assert_int_equal(vi_mm_nnz(m), nnz);
  assert_int_equal(vi_mm_storage_kind(m), storage);
  for (int j = 0; j <= 3; j++) assert_int_equal(vi_mm_colptr(m)[j], p[j]);
  for (int k = 0; k < nnz; k++) {
    assert_int_equal(vi_mm_rowind(m)[k], ri[k]);
    assert_true(vi_mm_values(m)[k] == v[k]); /* exact: read as written */
  }
}
