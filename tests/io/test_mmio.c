/* test_mmio.c - Matrix Market files: every form of the grammar gives the
 * same CSC arrays of one matrix, and every malformed file is refused with
 * its code, line and what is wrong.  (NULL and bad arguments:
 * test_misuse_io.c.) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "vi_mm_testutil.h"
#include "vibroimpact/vi_mmio.h"


/* Every form the grammar allows for A, each read into both storages. */
static void test_forms(void **state)
{
  (void)state;
  static const char *const forms[] = {
      /* symmetric coordinate, comments, a blank line, entries unsorted */
      "%%MatrixMarket matrix coordinate real symmetric\n% from a test\n%\n"
      "3 3 5\n3 3 5.0\n2 1 -1\n\n1 1 4\n3 2 -2e0\n2 2 4.000\n",
      /* general coordinate holding the whole matrix, CRLF line ends */
      "%%MatrixMarket matrix coordinate real general\r\n3 3 7\r\n1 1 4\r\n"
      "2 1 -1\r\n1 2 -1\r\n2 2 4\r\n3 2 -2\r\n2 3 -2\r\n3 3 5\r\n",
      /* integer field, header in capitals, trailing comments */
      "%%MatrixMarket MATRIX Coordinate INTEGER Symmetric\n3 3 5\n"
      "1 1 4\n2 1 -1\n2 2 4\n3 2 -2\n3 3 5\n% the end\n",
      /* dense, column by column (zeros are not entries) */
      "%%MatrixMarket matrix array real general\n3 3\n4\n-1\n0\n-1\n4\n-2\n"
      "0\n-2\n5\n",
      /* dense symmetric: the lower triangle column by column */
      "%%MatrixMarket matrix array double symmetric\n% lower\n3 3\n4\n-1\n0\n"
      "4\n-2\n5\n",
  };
  for (size_t k = 0; k < sizeof forms / sizeof forms[0]; k++) {
    char path[256];
    vi_test_write_text(path, "mmio", (int)k, forms[k]);
    int rows = 0, cols = 0, sym = -1;
    int64_t entries = -1;
    vi_diag d;
    assert_int_equal(vi_mm_read_header(path, &rows, &cols, &entries, &sym, &d),
                     VI_OK);
    assert_true(rows == 3 && cols == 3);
    assert_int_equal(sym, k == 0 || k == 2 || k == 4);
    static const int64_t want_entries[] = {5, 7, 5, 9, 6};
    assert_int_equal(entries, want_entries[k]);
    static const int storages[2] = {VI_CSC_LOWER, VI_CSC_FULL};
    for (int q = 0; q < 2; q++) {
      int s = storages[q];
      vi_mm *m = NULL;
      int st = vi_mm_load(path, s, &m, &d);
      if (st) print_error("form %zu: %s\n", k, d.message);
      assert_int_equal(st, VI_OK);
      vi_test_expect_a3(m, s);
      vi_mm_destroy(&m);
      assert_null(m);
    }
    remove(path);
  }
}

/* A general file whose mirror entries differ by round-off (1e-13 of the
 * largest entry, within the 1e-12 the model allows) is stored averaged,
 * exactly symmetric; a rectangular general file reads in full storage. */
static void test_general(void **state)
{
  (void)state;
  char path[256];
  vi_test_write_text(path, "mmio", 10, "%%MatrixMarket matrix coordinate real general\n2 2 4\n"
                   "1 1 10\n2 1 -1.000000000000001\n1 2 -1\n2 2 10\n");
  vi_mm *m = NULL;
  vi_diag d;
  assert_int_equal(vi_mm_load(path, VI_CSC_LOWER, &m, &d), VI_OK);
  assert_int_equal(vi_mm_nnz(m), 3);
  assert_true(vi_mm_values(m)[1] == 0.5 * (-1.000000000000001 - 1.0));
  vi_mm_destroy(&m);
  remove(path);
  vi_test_write_text(path, "mmio", 11, "%%MatrixMarket matrix coordinate real general\n2 3 2\n"
                   "2 3 7\n1 1 1\n");
  assert_int_equal(vi_mm_load(path, VI_CSC_FULL, &m, &d), VI_OK);
  assert_true(vi_mm_rows(m) == 2 && vi_mm_cols(m) == 3 && vi_mm_nnz(m) == 2);
  static const int p[] = {0, 1, 1, 2};
  for (int j = 0; j <= 3; j++) assert_int_equal(vi_mm_colptr(m)[j], p[j]);
  assert_true(vi_mm_rowind(m)[1] == 1 && vi_mm_values(m)[1] == 7);
  vi_mm_destroy(&m);
  assert_int_equal(vi_mm_load(path, VI_CSC_LOWER, &m, &d), VI_ERR_DIM);
  assert_null(m);
  remove(path);
}

/* Malformed files: the code, the line and a word of the message. */
typedef struct badmm {
  const char *what, *text;
  int code, line;
  const char *says;
} badmm;

#define HS "%%MatrixMarket matrix coordinate real symmetric\n"
#define HG "%%MatrixMarket matrix coordinate real general\n"
static const badmm bads[] = {
    {"empty file", "", VI_ERR_PARSE, 1, "empty"},
    {"no banner", "3 3 1\n1 1 1\n", VI_ERR_PARSE, 1, "%%MatrixMarket"},
    {"short header", "%%MatrixMarket matrix coordinate real\n", VI_ERR_PARSE, 1, "expected"},
    {"vector", "%%MatrixMarket vector coordinate real general\n", VI_ERR_UNSUPPORTED, 1, "vector"},
    {"unknown object", "%%MatrixMarket tensor coordinate real general\n", VI_ERR_PARSE, 1, "tensor"},
    {"unknown format", "%%MatrixMarket matrix sparse real general\n", VI_ERR_PARSE, 1, "sparse"},
    {"complex", "%%MatrixMarket matrix coordinate complex general\n", VI_ERR_UNSUPPORTED, 1, "complex"},
    {"pattern", "%%MatrixMarket matrix coordinate pattern symmetric\n", VI_ERR_UNSUPPORTED, 1, "pattern"},
    {"hermitian", "%%MatrixMarket matrix coordinate real hermitian\n", VI_ERR_UNSUPPORTED, 1, "hermitian"},
    {"skew", "%%MatrixMarket matrix coordinate real skew-symmetric\n", VI_ERR_UNSUPPORTED, 1, "skew"},
    {"unknown symmetry", "%%MatrixMarket matrix coordinate real upper\n", VI_ERR_PARSE, 1, "upper"},
    {"no size line", HS "% only a comment\n", VI_ERR_PARSE, 2, "size line"},
    {"size: two numbers", HS "3 3\n", VI_ERR_PARSE, 2, "rows cols entries"},
    {"size: text", HS "3 three 1\n", VI_ERR_PARSE, 2, "three"},
    {"size: zero rows", HS "0 0 0\n", VI_ERR_PARSE, 2, ">= 1"},
    {"size: not square", HS "3 2 1\n", VI_ERR_DIM, 2, "square"},
    {"size: too many entries", HS "2 2 4\n", VI_ERR_DIM, 2, "more than the 3"},
    {"size: huge", HS "3000000000 3000000000 1\n", VI_ERR_LIMIT, 2, "dimension"},
    {"row index 0", HS "3 3 1\n0 1 1\n", VI_ERR_DIM, 3, "outside"},
    {"column beyond", HG "3 3 2\n1 1 1\n2 4 1\n", VI_ERR_DIM, 4, "outside"},
    {"index not whole", HS "3 3 1\n1.5 1 1\n", VI_ERR_PARSE, 3, "whole"},
    {"value text", HS "3 3 1\n1 1 abc\n", VI_ERR_PARSE, 3, "abc"},
    {"value NaN", HS "3 3 2\n1 1 1\n2 2 nan\n", VI_ERR_NONFINITE, 4, "finite"},
    {"value Inf", HS "3 3 1\n1 1 -inf\n", VI_ERR_NONFINITE, 3, "finite"},
    {"value overflows", HS "3 3 1\n1 1 1e400\n", VI_ERR_NONFINITE, 3, "finite"},
    {"integer field, real value", "%%MatrixMarket matrix coordinate integer general\n1 1 1\n1 1 2.5\n", VI_ERR_PARSE, 3, "integer"},
    {"missing value", HS "3 3 1\n1 1      \n", VI_ERR_PARSE, 3, "2 words"},
    {"extra word", HS "3 3 1\n1 1 1 1\n", VI_ERR_PARSE, 3, "words"},
    {"truncated", HS "3 3 3\n1 1 1\n2 2 1\n", VI_ERR_PARSE, 2, "truncated"},
    {"truncated, long lines", HS "3 3 3\n1 1 1.0000000000000000\n2 2 1.0000000000000000\n", VI_ERR_PARSE, 4, "after 2 of its 3"},
    {"too many entries", HS "3 3 1\n1 1 1\n2 2 1\n", VI_ERR_PARSE, 4, "more entries"},
    {"above the diagonal", HS "3 3 2\n1 1 1\n1 2 1\n", VI_ERR_NOT_SYMMETRIC, 4, "above"},
    {"duplicate", HS "3 3 3\n1 1 1\n2 1 1\n1 1 2\n", VI_ERR_PARSE, 5, "lines 3 and 5"},
    {"not symmetric", HG "2 2 3\n1 1 1\n2 1 0.5\n1 2 0.4\n", VI_ERR_NOT_SYMMETRIC, 4, "not symmetric"},
    {"mirror absent", HG "2 2 2\n1 1 1\n1 2 0.5\n", VI_ERR_NOT_SYMMETRIC, 4, "absent"},
    {"array: too few", "%%MatrixMarket matrix array real symmetric\n2 2\n1\n2\n", VI_ERR_PARSE, 2, "truncated"},
    {"array: too few, long lines", "%%MatrixMarket matrix array real symmetric\n2 2\n1.000000\n2.000000\n", VI_ERR_PARSE, 4, "after 2 of its 3"},
    {"array: two per line", "%%MatrixMarket matrix array real general\n1 2\n1 2\n", VI_ERR_PARSE, 3, "one value"},
    {"array: size with entries", "%%MatrixMarket matrix array real general\n2 2 4\n", VI_ERR_PARSE, 2, "rows cols"},
    {"binary", HS "3 3 1\n1 1 1\0\n", VI_ERR_PARSE, 3, "NUL"},
};

static void test_malformed(void **state)
{
  (void)state;
  for (size_t k = 0; k < sizeof bads / sizeof bads[0]; k++) {
    const badmm *b = &bads[k];
    char path[256];
    /* the NUL case: its text goes on past the NUL */
    if (!strcmp(b->what, "binary")) {
      snprintf(path, sizeof path, "mmio_%ld_bin.mtx", (long)getpid());
      FILE *f = fopen(path, "wb");
      assert_non_null(f);
      size_t len = strlen(b->text) + 2;
      assert_int_equal(fwrite(b->text, 1, len, f), len);
      fclose(f);
    } else
      vi_test_write_text(path, "mmio", 100 + (int)k, b->text);
    vi_mm *m = NULL;
    vi_diag d;
    int st = vi_mm_load(path, VI_CSC_LOWER, &m, &d);
    char msg[1200];
    vi_diag_format(&d, msg, sizeof msg);
    print_message("%-26s -> %s\n", b->what, msg);
    assert_int_equal(st, b->code);
    assert_int_equal(d.code, b->code);
    assert_string_equal(d.file, path);
    assert_int_equal(d.line, b->line);
    assert_non_null(strstr(d.message, b->says));
    assert_null(m);
    remove(path);
  }
}

/* Limits: a file that would need more memory than allowed, or whose bytes
 * cannot hold the entries its size line promises, is refused at its size
 * line, before storage for its entries exists; a line beyond the length
 * limit is refused. */
static void test_limits(void **state)
{
  (void)state;
  char path[256];
  vi_test_write_text(path, "mmio", 200, HS "100000 100000 200000\n1 1 1\n");
  vi_mm *m = NULL;
  vi_diag d;
  assert_int_equal(vi_mm_load_limited(path, VI_CSC_LOWER, 1e6, &m, &d),
                   VI_ERR_LIMIT);
  assert_int_equal(d.line, 2);
  assert_non_null(strstr(d.message, "MB"));
  /* with room, the short file is refused at its size line: its bytes
   * cannot hold 200000 entries, so nothing is allocated for them */
  assert_int_equal(vi_mm_load_limited(path, VI_CSC_LOWER, 1e9, &m, &d),
                   VI_ERR_PARSE);
  assert_int_equal(d.line, 2);
  assert_non_null(strstr(d.message, "truncated"));
  remove(path);
  char *big = malloc(VI_MM_MAX_LINE + 200);
  assert_non_null(big);
  snprintf(big, 100, "%s3 3 1\n1 1 ", HS); /* HS as an argument: %% kept */
  size_t len = strlen(big);
  memset(big + len, '1', VI_MM_MAX_LINE);
  strcpy(big + len + VI_MM_MAX_LINE, "\n");
  vi_test_write_text(path, "mmio", 201, big);
  free(big);
  assert_int_equal(vi_mm_load(path, VI_CSC_LOWER, &m, &d), VI_ERR_PARSE);
  assert_int_equal(d.line, 3);
  assert_non_null(strstr(d.message, "longer"));
  remove(path);
}

/* A 1-D rod of N linear elements (stiffness tridiag(-1, 2, -1), clamped at
 * one end), written in random order: the CSC is sorted and complete. */
static void test_larger(void **state)
{
  (void)state;
  const int n = 2000;
  char path[256];
  snprintf(path, sizeof path, "mmio_%ld_rod.mtx", (long)getpid());
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  fputs(HS, f); /* not a format: %% is the banner's */
  fprintf(f, "%d %d %d\n", n, n, 2 * n - 1);
  for (int k = 0; k < 2 * n - 1; k++) {
    int e = (int)(((long long)k * 7919) % (2 * n - 1)); /* a permutation */
    if (e < n)
      fprintf(f, "%d %d %.17g\n", e + 1, e + 1, e == n - 1 ? 1.0 : 2.0);
    else
      fprintf(f, "%d %d -1\n", e - n + 2, e - n + 1);
  }
  fclose(f);
  vi_mm *m = NULL;
  vi_diag d;
  int st = vi_mm_load(path, VI_CSC_LOWER, &m, &d);
  if (st) print_error("%s\n", d.message);
  assert_int_equal(st, VI_OK);
  assert_int_equal(vi_mm_nnz(m), 2 * n - 1);
  const int *p = vi_mm_colptr(m), *ri = vi_mm_rowind(m);
  const double *v = vi_mm_values(m);
  for (int j = 0; j < n; j++) {
    assert_int_equal(p[j], 2 * j);
    assert_int_equal(ri[p[j]], j);
    assert_true(v[p[j]] == (j == n - 1 ? 1.0 : 2.0));
    if (j < n - 1) assert_true(ri[p[j] + 1] == j + 1 && v[p[j] + 1] == -1.0);
  }
  vi_mm_destroy(&m);
  remove(path);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_forms),     cmocka_unit_test(test_general),
      cmocka_unit_test(test_malformed), cmocka_unit_test(test_limits),
      cmocka_unit_test(test_larger),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
