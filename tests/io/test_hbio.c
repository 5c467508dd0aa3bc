/* test_hbio.c - the formats FE codes write besides Matrix Market
 * (vi_mmio.h): Harwell-Boeing / Rutherford-Boeing files and the
 * (node, dof, node, dof, value) coordinate export, the format told by
 * content, and every malformed file refused with its code, line, column
 * and what is wrong.  A real file: bcsstk01 of the Harwell-Boeing
 * collection (tests/data/hb, from SuiteSparse), as .rsa and as .rb,
 * compared entry by entry with the same matrix written independently as
 * triplets (bcsstk01.tri, read here with strtod).
 *   test_hbio DATA_DIR */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "vi_mm_testutil.h"

extern char **environ;
#include "vibroimpact/vi_mmio.h"

static const char *data_dir = ".";


/* Headers: line 2 of I14 counts, line 3 the type and sizes (14 columns
 * each after the type's A3 and 11 blanks), line 4 the formats. */
#define T1 "test matrix A                                                           KEY\n"
#define RSA(tot, p, i, v) T1 tot p i v "\nRSA                        3             3             5\n"

static const struct form {
  const char *what, *text;
  int format;
} forms[] = {
    {"RSA, (4I5) (5I3) (5E16.8)",
     T1 "             3             1             1             1\n"
        "RSA                        3             3             5             0\n"
        "(4I5)           (5I3)           (5E16.8)            \n"
        "    1    3    5    6\n"
        "  1  2  2  3  3\n"
        "  4.00000000E+00 -1.00000000E+00  4.00000000E+00 -2.00000000E+00  5.00000000E+00\n",
     VI_MATRIX_HARWELL_BOEING},
    {"rsa lower case, D exponents, scale factor, bare-sign exponent, no point",
     T1 "             6             2             2             2             0\n"
        "rsa                        3             3             5\n"
        "(3I2)           (3I3)           (1P3D16.8)          (3E10.2)\n"
        " 1 3 5\n 6\n  1  2  2\n  3  3\n"
        /* no point: the last d = 8 digits are the fraction; no exponent:
         * 1P divides by 10 */
        " 4.00000000D+00 -1.0000000000-00      4000000000\n"
        "-2.0000000000+00            50.0\n",
     VI_MATRIX_HARWELL_BOEING},
    {"RUA holding the whole matrix, HB right-hand side header skipped",
     T1 "             5             1             1             2             1\n"
        "RUA                        3             3             7             0\n"
        "(4I3)           (7I2)           (4F10.3)            (4F10.3)\n"
        "RHS                        1             0\n"
        "  1  3  6  8\n 1 2 1 2 3 2 3\n"
        "     4.000    -1.000    -1.000     4.000\n"
        "    -2.000    -2.000     5.000\n"
        "     1.000     2.000     3.000\n",
     VI_MATRIX_HARWELL_BOEING},
    {"ISA: integer values, CRLF line ends",
     T1 "             3             1             1             1\r\n"
        "ISA                        3             3             5\r\n"
        "(4I5)           (5I3)           (5I4)\r\n"
        "    1    3    5    6\r\n  1  2  2  3  3\r\n   4  -1   4  -2   5\r\n",
     VI_MATRIX_HARWELL_BOEING},
    {"coordinate, one triangle, unsorted, comments",
     "** K of a test model\n1, 1, 1, 1, 4.0\n\n2,1, 1,1, -1\n"
     "# node 2\n2, 1, 2, 1, 4\n2, 1, 3, 2, -2.0e0\n3, 2, 3, 2, 5\n",
     VI_MATRIX_COORDINATE},
    {"coordinate, whole matrix",
     "1,1,1,1,4\n2,1,1,1,-1\n1,1,2,1,-1\n2,1,2,1,4\n3,2,2,1,-2\n"
     "2,1,3,2,-2\n3,2,3,2,5\n",
     VI_MATRIX_COORDINATE},
    {"equations, whole matrix (Abaqus FORMAT=COORDINATE)",
     "1 1  4.000000000000000e+00\n1 2 -1.0\n2 1 -1.0\n2 2 4\n2 3 -2\n"
     "3 2 -2\n3 3 5\n",
     VI_MATRIX_COORDINATE},
    {"equations, one triangle, commas, a comment",
     "** K\n3, 3, 5\n1, 1, 4\n1, 2, -1\n2, 2, 4\n3, 2, -2\n",
     VI_MATRIX_COORDINATE},
};

static void test_forms(void **state)
{
  (void)state;
  for (size_t k = 0; k < sizeof forms / sizeof forms[0]; k++) {
    char path[256];
    vi_test_write_text(path, "hbio_form", (int)k, forms[k].text);
    vi_diag d;
    int f = -1, rows = 0, cols = 0, sym = -1;
    int64_t entries = 0;
    assert_int_equal(vi_matrix_detect(path, &f, &d), VI_OK);
    assert_int_equal(f, forms[k].format);
    int st = vi_matrix_read_header(path, VI_MATRIX_AUTO, &rows, &cols,
                                   &entries, &sym, &d);
    if (st) print_error("%s: %s\n", forms[k].what, d.message);
    assert_int_equal(st, VI_OK);
    assert_true(rows == 3 && cols == 3);
    assert_int_equal(sym, k != 2 && k != 5 && k != 6);
    static const int storages[2] = {VI_CSC_LOWER, VI_CSC_FULL};
    for (int q = 0; q < 2; q++) {
      vi_mm *m = NULL;
      st = vi_matrix_load(path, VI_MATRIX_AUTO, NULL, storages[q], 0, &m, &d);
      if (st) print_error("%s: line %d: %s\n", forms[k].what, d.line,
                          d.message);
      assert_int_equal(st, VI_OK);
      vi_test_expect_a3(m, storages[q]);
      vi_mm_destroy(&m);
    }
    /* named formats: the right one reads, a wrong one is refused */
    vi_mm *m = NULL;
    assert_int_equal(vi_matrix_load(path, forms[k].format, NULL,
                                    VI_CSC_LOWER, 0, &m, &d), VI_OK);
    vi_mm_destroy(&m);
    assert_true(vi_matrix_load(path, VI_MATRIX_MARKET, NULL, VI_CSC_LOWER, 0,
                               &m, &d) != VI_OK);
    assert_null(m);
    remove(path);
  }
}

/* The dof map of coordinate files: the (node, dof) pairs of M and K
 * together, sorted by node then dof (negative labels first: Abaqus'
 * internal nodes); a dof only K names is a row of M too (massless). */
static void test_dofmap(void **state)
{
  (void)state;
  char pm[256], pk[256];
  vi_test_write_text(pm, "hbio_map", 0, "30,1,30,1,2.0\n-4,3,-4,3,1.5\n");
  vi_test_write_text(pk, "hbio_map", 1,
                     "30, 1, 30, 1, 6\n7, 2, 7, 2, 9\n7, 2, 30, 1, -3\n"
                     "-4, 3, -4, 3, 5\n");
  const char *paths[2] = {pm, pk};
  vi_dofmap *map = NULL;
  vi_diag d;
  assert_int_equal(vi_dofmap_scan(2, paths, 0, &map, &d), VI_OK);
  assert_int_equal(vi_dofmap_n(map), 3);
  static const int want[3][2] = {{-4, 3}, {7, 2}, {30, 1}};
  for (int i = 0; i < 3; i++) {
    int node = 0, dof = 0;
    assert_int_equal(vi_dofmap_label(map, i + 1, &node, &dof), VI_OK);
    assert_int_equal(node, want[i][0]);
    assert_int_equal(dof, want[i][1]);
    assert_int_equal(vi_dofmap_index(map, node, dof), i + 1);
  }
  assert_int_equal(vi_dofmap_index(map, 7, 1), 0);
  int node, dof;
  assert_int_equal(vi_dofmap_label(map, 4, &node, &dof), VI_ERR_DIM);
  /* M through the shared map: 3 x 3 with an empty row 2 (node 7) */
  vi_mm *m = NULL;
  assert_int_equal(vi_matrix_load(pm, VI_MATRIX_AUTO, map, VI_CSC_LOWER, 0,
                                  &m, &d), VI_OK);
  assert_int_equal(vi_mm_rows(m), 3);
  assert_int_equal(vi_mm_nnz(m), 2);
  static const int mp[] = {0, 1, 1, 2};
  for (int j = 0; j <= 3; j++) assert_int_equal(vi_mm_colptr(m)[j], mp[j]);
  assert_true(vi_mm_values(m)[0] == 1.5 && vi_mm_values(m)[1] == 2.0);
  vi_mm_destroy(&m);
  /* K: the entry (7,2)-(30,1) lands at (3, 2) of the lower triangle */
  assert_int_equal(vi_matrix_load(pk, VI_MATRIX_COORDINATE, map,
                                  VI_CSC_LOWER, 0, &m, &d), VI_OK);
  assert_int_equal(vi_mm_nnz(m), 4);
  assert_int_equal(vi_mm_rowind(m)[2], 2);
  assert_true(vi_mm_values(m)[2] == -3.0);
  vi_mm_destroy(&m);
  /* M alone (its own map): 2 x 2 */
  assert_int_equal(vi_matrix_load(pm, VI_MATRIX_AUTO, NULL, VI_CSC_LOWER, 0,
                                  &m, &d), VI_OK);
  assert_int_equal(vi_mm_rows(m), 2);
  vi_mm_destroy(&m);
  /* a map of M alone does not hold K's node 7 */
  vi_dofmap *mm = NULL;
  assert_int_equal(vi_dofmap_scan(1, paths, 0, &mm, &d), VI_OK);
  assert_int_equal(vi_matrix_load(pk, VI_MATRIX_AUTO, mm, VI_CSC_LOWER, 0,
                                  &m, &d), VI_ERR_DIM);
  assert_int_equal(d.line, 2);
  assert_non_null(strstr(d.message, "node 7, dof 2"));
  vi_dofmap_destroy(&mm);
  vi_dofmap_destroy(&map);
  assert_null(map);
  remove(pm);
  remove(pk);
  /* equation numbers: dof i is equation i, n the largest of all files
   * (M here names 1..3, K 1..4: M's row 4 is empty, a massless dof) */
  vi_test_write_text(pm, "hbio_map", 2, "1 1 1.0\n2 2 2.0\n3 3 3.0\n");
  vi_test_write_text(pk, "hbio_map", 3, "1 1 4\n4 4 6\n4 1 -1\n1 4 -1\n2 2 5\n3 3 5\n");
  assert_int_equal(vi_dofmap_scan(2, paths, 0, &map, &d), VI_OK);
  assert_int_equal(vi_dofmap_n(map), 4);
  assert_int_equal(vi_dofmap_label(map, 4, &node, &dof), VI_OK);
  assert_true(node == 4 && dof == 0);
  assert_int_equal(vi_dofmap_index(map, 3, 0), 3);
  assert_int_equal(vi_dofmap_index(map, 3, 1), 0);
  assert_int_equal(vi_dofmap_index(map, 5, 0), 0);
  assert_int_equal(vi_matrix_load(pm, VI_MATRIX_AUTO, map, VI_CSC_LOWER, 0,
                                  &m, &d), VI_OK);
  assert_true(vi_mm_rows(m) == 4 && vi_mm_nnz(m) == 3);
  assert_int_equal(vi_mm_colptr(m)[4], 3); /* column 4 empty */
  vi_mm_destroy(&m);
  vi_dofmap_destroy(&map);
  /* one model's files number their dofs alike: pairs beside equations */
  remove(pk);
  vi_test_write_text(pk, "hbio_map", 4, "1, 1, 1, 1, 4\n");
  assert_int_equal(vi_dofmap_scan(2, paths, 0, &map, &d), VI_ERR_PARSE);
  assert_non_null(strstr(d.message, "number their dofs alike"));
  assert_null(map);
  remove(pm);
  remove(pk);
}

/* Malformed files: code, line, column (0: not checked) and a word of the
 * message. */
typedef struct bad {
  const char *what, *text;
  int code, line, col;
  const char *says;
} bad;

#define L2 "             3             1             1             1\n"
#define L3 "RSA                        3             3             5\n"
#define L4 "(4I5)           (5I3)           (5E16.8)\n"
#define PTR "    1    3    5    6\n"
#define IND "  1  2  2  3  3\n"
#define VAL "  4.00000000E+00 -1.00000000E+00  4.00000000E+00 -2.00000000E+00  5.00000000E+00\n"
static const bad hb_bads[] = {
    {"truncated header", T1 L2, VI_ERR_PARSE, 2, 0, "truncated header"},
    {"TOTCRD not a number", T1 "             x             1             1             1\n" L3 L4 PTR IND VAL, VI_ERR_PARSE, 2, 14, "TOTCRD"},
    {"VALCRD missing", T1 "             3             1             1\n" L3 L4 PTR IND VAL, VI_ERR_PARSE, 2, 43, "VALCRD missing"},
    {"text after the counts", T1 "             3             1             1             1             0 x\n" L3 L4 PTR IND VAL, VI_ERR_PARSE, 2, 72, "text after"},
    {"complex", T1 L2 "CSA                        3             3             5\n" L4, VI_ERR_UNSUPPORTED, 3, 1, "complex"},
    {"pattern", T1 L2 "PSA                        3             3             5\n" L4, VI_ERR_UNSUPPORTED, 3, 1, "pattern"},
    {"elemental", T1 L2 "RSE                        3             3             5\n" L4, VI_ERR_UNSUPPORTED, 3, 1, "elemental"},
    {"hermitian", T1 L2 "CHA                        3             3             5\n" L4, VI_ERR_UNSUPPORTED, 3, 1, "complex"},
    {"skew", T1 L2 "RZA                        3             3             5\n" L4, VI_ERR_UNSUPPORTED, 3, 1, "skew"},
    {"unknown type", T1 L2 "XYZ                        3             3             5\n" L4, VI_ERR_PARSE, 3, 1, "three letters"},
    {"text in columns 4-14", T1 L2 "RSA  x                     3             3             5\n" L4, VI_ERR_PARSE, 3, 6, "blank"},
    {"symmetric not square", T1 L2 "RSA                        3             2             5\n" L4, VI_ERR_DIM, 3, 15, "square"},
    {"NNZERO too large", T1 L2 "RSA                        3             3             7\n" L4, VI_ERR_DIM, 3, 43, "more than the 6"},
    {"NROW zero", T1 L2 "RSA                        0             0             0\n" L4, VI_ERR_PARSE, 3, 28, ">= 1"},
    {"bad pointer format", T1 L2 L3 "(4X5)           (5I3)           (5E16.8)\n", VI_ERR_PARSE, 4, 1, "edit descriptor"},
    {"pointer format real", T1 L2 L3 "(4E5.1)         (5I3)           (5E16.8)\n", VI_ERR_PARSE, 4, 1, "integers"},
    {"value format integer", T1 L2 L3 "(4I5)           (5I3)           (5I16)\n", VI_ERR_PARSE, 4, 33, "E, D, F or G"},
    {"value format without d", T1 L2 L3 "(4I5)           (5I3)           (5E16)\n", VI_ERR_PARSE, 4, 33, "w.d"},
    {"format without parentheses", T1 L2 L3 "4I5             (5I3)           (5E16.8)\n", VI_ERR_PARSE, 4, 1, "such as"},
    {"nested format", T1 L2 L3 "(4I5)           (5I3)           (5(E16.8))\n", VI_ERR_PARSE, 4, 33, "edit descriptor"},
    {"more digits than width", T1 L2 L3 "(4I5)           (5I3)           (5E16.999)\n", VI_ERR_PARSE, 4, 33, "width"},
    {"format line too long", T1 L2 L3 "(4I5)           (5I3)           (99E16.8)\n", VI_ERR_PARSE, 4, 33, "1024"},
    {"PTRCRD against the format", T1 "             4             2             1             1\n" L3 L4 PTR IND VAL, VI_ERR_PARSE, 2, 15, "take 1 line"},
    {"TOTCRD against the sum", T1 "             9             1             1             1\n" L3 L4 PTR IND VAL, VI_ERR_PARSE, 2, 1, "TOTCRD = 9"},
    {"truncated pointers", T1 L2 L3 L4, VI_ERR_PARSE, 4, 0, "truncated"},
    {"pointer not from 1", T1 L2 L3 L4 "    2    3    5    6\n" IND VAL, VI_ERR_PARSE, 5, 1, "start at 1"},
    {"pointer decreasing", T1 L2 L3 L4 "    1    3    2    6\n" IND VAL, VI_ERR_PARSE, 5, 11, "decrease"},
    {"last pointer wrong", T1 L2 L3 L4 "    1    3    5    5\n" IND VAL, VI_ERR_PARSE, 5, 16, "NNZERO + 1"},
    {"pointer field blank", T1 L2 L3 L4 "    1    3    5\n" IND VAL, VI_ERR_PARSE, 5, 16, "blank"},
    {"pointer with a blank inside", T1 L2 L3 L4 "    1    3  5 5    6\n" IND VAL, VI_ERR_PARSE, 5, 13, "blank inside"},
    {"text after the fields", T1 L2 L3 L4 "    1    3    5    6 7\n" IND VAL, VI_ERR_PARSE, 5, 22, "text after"},
    {"row index out of range", T1 L2 L3 L4 PTR "  1  2  2  4  3\n" VAL, VI_ERR_DIM, 6, 10, "outside"},
    {"row index zero", T1 L2 L3 L4 PTR "  1  2  2  0  3\n" VAL, VI_ERR_DIM, 6, 10, "outside"},
    {"above the diagonal", T1 L2 L3 L4 PTR "  1  2  1  3  3\n" VAL, VI_ERR_NOT_SYMMETRIC, 6, 7, "above"},
    {"duplicate entry", T1 L2 L3 L4 PTR "  1  2  2  2  3\n" VAL, VI_ERR_PARSE, 6, 0, "both on line 6"},
    {"index not a number", T1 L2 L3 L4 PTR "  1  2  a  3  3\n" VAL, VI_ERR_PARSE, 6, 7, "whole number"},
    {"value not a number", T1 L2 L3 L4 PTR IND "  4.00000000E+00 -1.00000000E+00  4.0000000xE+00 -2.00000000E+00  5.00000000E+00\n", VI_ERR_PARSE, 7, 33, "not a number"},
    {"value overflows", T1 L2 L3 L4 PTR IND "  4.00000000E+00 -1.00000000E+00  4.00000000E+99 -2.0000000E+999  5.00000000E+00\n", VI_ERR_NONFINITE, 7, 49, "finite"},
    {"value NaN", T1 L2 L3 L4 PTR IND "             NaN -1.00000000E+00  4.00000000E+00 -2.00000000E+00  5.00000000E+00\n", VI_ERR_NONFINITE, 7, 1, "finite"},
    {"value exponent without digits", T1 L2 L3 L4 PTR IND "  4.00000000E+00 -1.00000000E+00  4.00000000E+00 -2.00000000E+  5.00000000E+00\n", VI_ERR_PARSE, 7, 49, "not a number"},
    {"value field blank", T1 L2 L3 L4 PTR IND "  4.00000000E+00 -1.00000000E+00                                                \n", VI_ERR_PARSE, 7, 33, "missing"},
    {"values truncated", T1 L2 L3 L4 PTR IND "  4.00000000E+00 -1.00000000E+00\n", VI_ERR_PARSE, 4, 0, "truncated"},
    {"values missing", T1 L2 L3 L4 PTR IND, VI_ERR_PARSE, 4, 0, "truncated"},
    {"RUA not symmetric", T1 "             4             1             1             2\n"
        "RUA                        3             3             7\n"
        "(4I3)           (7I2)           (4F10.3)\n"
        "  1  3  6  8\n 1 2 1 2 3 2 3\n"
        "     4.000    -1.000    -1.100     4.000\n"
        "    -2.000    -2.000     5.000\n", VI_ERR_NOT_SYMMETRIC, 6, 0, "not symmetric"},
    {"empty", "", VI_ERR_PARSE, 1, 0, "empty"},
};

static const bad coord_bads[] = {
    {"four fields", "1,1,1,1,4\n2,1,1,1\n", VI_ERR_PARSE, 2, 0, "got 4"},
    {"six fields", "1,1,1,1,4\n2,1,1,1,3,7\n", VI_ERR_PARSE, 2, 0, "got 6"},
    {"node not a number", "1,1,1,1,4\n2.5,1,1,1,-1\n", VI_ERR_PARSE, 2, 1, "row node"},
    {"dof zero", "1,1,1,1,4\n2,0,1,1,-1\n", VI_ERR_PARSE, 2, 3, "from 1"},
    {"column dof text", "1,1,1,1,4\n2,1,1,x,-1\n", VI_ERR_PARSE, 2, 7, "column dof"},
    {"value text", "1,1,1,1,4\n2,1,1,1, abc\n", VI_ERR_PARSE, 2, 10, "not a number"},
    {"value empty", "1,1,1,1,4\n2,1,1,1,\n", VI_ERR_PARSE, 2, 9, "not a number"},
    {"value overflows", "1,1,1,1,4\n2,1,1,1,1e999\n", VI_ERR_NONFINITE, 2, 9, "finite"},
    {"value NaN", "1,1,1,1,nan\n", VI_ERR_NONFINITE, 1, 9, "finite"},
    {"node beyond int", "1,1,1,1,4\n9999999999,1,1,1,1\n", VI_ERR_PARSE, 2, 1, "whole"},
    {"duplicate", "1,1,1,1,4\n2,1,1,1,-1\n1,1,1,1,4\n", VI_ERR_PARSE, 3, 0, "lines 1 and 3"},
    {"not symmetric", "1,1,1,1,4\n2,1,1,1,-1\n1,1,2,1,-1.5\n2,1,2,1,4\n", VI_ERR_NOT_SYMMETRIC, 0, 0, "not symmetric"},
    {"mirror missing in a whole matrix", "1,1,1,1,4\n2,1,1,1,-1\n1,1,2,1,-1\n3,1,2,1,-1\n2,1,2,1,4\n", VI_ERR_NOT_SYMMETRIC, 4, 0, "absent"},
    {"only comments", "** nothing\n\n", VI_ERR_PARSE, 0, 0, "no entries"},
    {"equation zero", "1 1 4\n0 1 4\n", VI_ERR_PARSE, 2, 1, "numbered from 1"},
    {"equation text", "1 1 4\n2 b 4\n", VI_ERR_PARSE, 2, 3, "column 'b'"},
    {"equations then pairs", "1 1 4\n2,1,2,1,4\n", VI_ERR_PARSE, 2, 0, "'row column value' (3 fields"},
    {"four blank-separated fields", "1 1 4\n2 2 1 4\n", VI_ERR_PARSE, 2, 0, "got 4"},
    {"equations not symmetric", "1 1 4\n1 2 -1\n2 1 -2\n2 2 4\n", VI_ERR_NOT_SYMMETRIC, 0, 0, "not symmetric"},
};

static void run_bads(const bad *b, size_t nb, int format, const char *tag)
{
  for (size_t k = 0; k < nb; k++) {
    char path[256];
    vi_test_write_text(path, tag, (int)k, b[k].text);
    vi_mm *m = NULL;
    vi_diag d;
    int st = vi_matrix_load(path, format, NULL, VI_CSC_LOWER, 0, &m, &d);
    char msg[1200];
    vi_diag_format(&d, msg, sizeof msg);
    print_message("%-32s -> %s\n", b[k].what, msg);
    assert_int_equal(st, b[k].code);
    assert_int_equal(d.code, b[k].code);
    assert_string_equal(d.file, path);
    if (b[k].line) assert_int_equal(d.line, b[k].line);
    if (b[k].col) assert_int_equal(d.column, b[k].col);
    assert_non_null(strstr(d.message, b[k].says));
    assert_null(m);
    remove(path);
  }
}

static void test_malformed_hb(void **state)
{
  (void)state;
  run_bads(hb_bads, sizeof hb_bads / sizeof hb_bads[0],
           VI_MATRIX_HARWELL_BOEING, "hb");
}

static void test_malformed_coordinate(void **state)
{
  (void)state;
  run_bads(coord_bads, sizeof coord_bads / sizeof coord_bads[0],
           VI_MATRIX_COORDINATE, "co");
}

/* Limits and files that are not files: a header promising a huge matrix
 * is refused under a memory limit, and (without one) because the file's
 * bytes cannot hold it, before anything is allocated; /dev/zero, a FIFO
 * and a directory are refused at once, never read; unknown content says
 * what each format starts with. */
static void test_limits(void **state)
{
  (void)state;
  char path[256];
  vi_test_write_text(path, "hbio_lim", 0, T1 "             3             1        200000        200000\n"
                      "RSA                  1000000       1000000       1000000\n"
                      "(4I5)           (5I8)           (5E16.8)\n");
  vi_mm *m = NULL;
  vi_diag d;
  assert_int_equal(vi_matrix_load(path, VI_MATRIX_AUTO, NULL, VI_CSC_LOWER,
                                  1e6, &m, &d), VI_ERR_PARSE); /* PTRCRD */
  remove(path);
  vi_test_write_text(path, "hbio_lim", 1, T1 "        600000        200000        200000        200000\n"
                      "RSA                   999999        999999       1000000\n"
                      "(5I8)           (5I8)           (5E16.8)\n");
  assert_int_equal(vi_matrix_load(path, VI_MATRIX_AUTO, NULL, VI_CSC_LOWER,
                                  1e6, &m, &d), VI_ERR_LIMIT);
  assert_non_null(strstr(d.message, "MB"));
  assert_int_equal(vi_matrix_load(path, VI_MATRIX_AUTO, NULL, VI_CSC_LOWER,
                                  0, &m, &d), VI_ERR_PARSE);
  assert_non_null(strstr(d.message, "truncated"));
  assert_null(m);
  remove(path);
  /* a coordinate file under a limit its entries exceed */
  FILE *f = fopen("hbio_big.txt", "w");
  assert_non_null(f);
  for (int i = 1; i <= 20000; i++) fprintf(f, "%d,1,%d,1,1.0\n", i, i);
  fclose(f);
  assert_int_equal(vi_matrix_load("hbio_big.txt", VI_MATRIX_AUTO, NULL,
                                  VI_CSC_LOWER, 1e5, &m, &d), VI_ERR_LIMIT);
  assert_int_equal(vi_matrix_load("hbio_big.txt", VI_MATRIX_AUTO, NULL,
                                  VI_CSC_LOWER, 0, &m, &d), VI_OK);
  assert_int_equal(vi_mm_rows(m), 20000);
  vi_mm_destroy(&m);
  remove("hbio_big.txt");
  /* not regular files */
  int fmt = -1;
  assert_int_equal(vi_matrix_detect("/dev/zero", &fmt, &d), VI_ERR_IO);
  assert_non_null(strstr(d.message, "character device"));
  assert_int_equal(vi_matrix_load("/dev/zero", VI_MATRIX_HARWELL_BOEING, NULL,
                                  VI_CSC_LOWER, 0, &m, &d), VI_ERR_IO);
  assert_int_equal(vi_mm_load("/dev/zero", VI_CSC_LOWER, &m, &d), VI_ERR_IO);
  char fifo[64];
  snprintf(fifo, sizeof fifo, "hbio_%ld.fifo", (long)getpid());
  assert_int_equal(mkfifo(fifo, 0600), 0);
  assert_int_equal(vi_matrix_load(fifo, VI_MATRIX_AUTO, NULL, VI_CSC_LOWER, 0,
                                  &m, &d), VI_ERR_IO);
  assert_non_null(strstr(d.message, "FIFO"));
  assert_int_equal(vi_mm_read_header(fifo, NULL, NULL, NULL, NULL, &d),
                   VI_ERR_IO);
  remove(fifo);
  assert_int_equal(vi_matrix_detect(".", &fmt, &d), VI_ERR_IO);
  assert_non_null(strstr(d.message, "directory"));
  vi_test_write_text(path, "hbio_lim", 2, "hello\nworld\n");
  assert_int_equal(vi_matrix_detect(path, &fmt, &d), VI_ERR_PARSE);
  assert_non_null(strstr(d.message, "RSA"));
  assert_int_equal(d.line, 1);
  remove(path);
}

/* bcsstk01 (Harwell-Boeing collection, BCSSTRUC1: 48 dofs, 224 stored
 * entries of the lower triangle) as SuiteSparse ships it in two writers'
 * hands: the original .rsa ((16I5), (4E20.12), values like
 * .283226851852E+07) and RBio's .rb ((20I4), (26I3), 0.2832...E+07), each
 * against the triplets of bcsstk01.tri (i j value, 1-based, 18 digits:
 * the same doubles, so equal exactly), read here with strtol and strtod. */
static void test_bcsstk01(void **state)
{
  (void)state;
  char path[512];
  snprintf(path, sizeof path, "%s/hb/bcsstk01.tri", data_dir);
  FILE *f = fopen(path, "r");
  assert_non_null(f);
  char line[256];
  int n = 0, nc = 0, nz = 0, stype = 0, got = 0;
  while (fgets(line, sizeof line, f) && line[0] == '%') {
  }
  char *end = line;
  n = (int)strtol(end, &end, 10);
  nc = (int)strtol(end, &end, 10);
  nz = (int)strtol(end, &end, 10);
  stype = (int)strtol(end, &end, 10);
  assert_int_equal(stype, -1); /* lower triangle stored */
  assert_true(n == 48 && nc == 48 && nz == 224);
  double *A = calloc((size_t)n * n, sizeof *A);
  assert_non_null(A);
  for (int k = 0; k < nz; k++) {
    int i, j;
    double v;
    assert_non_null(fgets(line, sizeof line, f));
    char *e1, *e2, *e3;
    i = (int)strtol(line, &e1, 10);
    j = (int)strtol(e1, &e2, 10);
    v = strtod(e2, &e3);
    assert_true(e1 != line && e2 != e1 && e3 != e2);
    assert_true(i >= 1 && i <= n && j >= 1 && j <= n);
    A[(size_t)(i - 1) + (size_t)(j - 1) * n] = v;
    A[(size_t)(j - 1) + (size_t)(i - 1) * n] = v;
    got++;
  }
  fclose(f);
  static const char *const files[2] = {"bcsstk01.rsa", "bcsstk01.rb"};
  for (int q = 0; q < 2; q++) {
    snprintf(path, sizeof path, "%s/hb/%s", data_dir, files[q]);
    vi_mm *m = NULL;
    vi_diag d;
    int fmt = -1;
    assert_int_equal(vi_matrix_detect(path, &fmt, &d), VI_OK);
    assert_int_equal(fmt, VI_MATRIX_HARWELL_BOEING);
    int st = vi_matrix_load(path, VI_MATRIX_AUTO, NULL, VI_CSC_FULL, 0, &m, &d);
    if (st) print_error("%s line %d col %d: %s\n", files[q], d.line,
                        d.column, d.message);
    assert_int_equal(st, VI_OK);
    assert_int_equal(vi_mm_rows(m), 48);
    assert_int_equal(vi_mm_nnz(m), 2 * 224 - 48);
    /* every stored entry equals the triplets', and every triplet is stored */
    const int *p = vi_mm_colptr(m), *ri = vi_mm_rowind(m);
    const double *v = vi_mm_values(m);
    int seen = 0, differ = 0;
    for (int j = 0; j < n; j++)
      for (int k = p[j]; k < p[j + 1]; k++) {
        differ += v[k] != A[(size_t)ri[k] + (size_t)j * n];
        seen += ri[k] >= j;
      }
    int nonzero = 0;
    for (size_t k = 0; k < (size_t)n * n; k++) nonzero += A[k] != 0;
    print_message("%s: %d of %d entries against bcsstk01.tri, %d differ\n",
                  files[q], seen, got, differ);
    assert_int_equal(differ, 0);
    assert_int_equal(seen, got);
    assert_int_equal(vi_mm_nnz(m), nonzero);
    vi_mm_destroy(&m);
  }
  free(A);
}

/* A real Abaqus export (tests/data/abaqus: EXUDYN's free rotor with a
 * disc, *MATRIX OUTPUT, FORMAT=COORDINATE, 345 equations): K (both
 * triangles, xz-compressed in the tree) and the lumped M, detected as
 * coordinate files and read through one map, against their lines read
 * independently: every entry equal bit for bit, K stored as its lower
 * triangle with every mirror equal. */
static int read_lines(const char *path, int n, double *A)
{
  FILE *f = fopen(path, "r");
  assert_non_null(f);
  char line[256];
  int count = 0;
  while (fgets(line, sizeof line, f)) {
    char *e1, *e2, *e3;
    long i = strtol(line, &e1, 10), j = strtol(e1, &e2, 10);
    double v = strtod(e2, &e3);
    assert_true(e1 != line && e2 != e1 && e3 != e2);
    assert_true(i >= 1 && i <= n && j >= 1 && j <= n);
    A[(size_t)(i - 1) + (size_t)(j - 1) * n] = v;
    count++;
  }
  fclose(f);
  return count;
}

static void test_abaqus(void **state)
{
  (void)state;
  char src[512], pk[64], pm[512];
  snprintf(src, sizeof src, "%s/abaqus/rotorDiscTestSTIF1.mtx.xz", data_dir);
  snprintf(pk, sizeof pk, "hbio_%ld_rotorK.mtx", (long)getpid());
  snprintf(pm, sizeof pm, "%s/abaqus/rotorDiscTestMASS1.mtx", data_dir);
  /* xz -dc SRC > PK, without a shell */
  posix_spawn_file_actions_t fa;
  pid_t pid;
  int status = -1;
  char *argv[] = {"xz", "-dc", src, NULL};
  assert_int_equal(posix_spawn_file_actions_init(&fa), 0);
  assert_int_equal(posix_spawn_file_actions_addopen(
                       &fa, 1, pk, O_WRONLY | O_CREAT | O_TRUNC, 0600), 0);
  if (posix_spawnp(&pid, "xz", &fa, NULL, argv, environ) != 0 ||
      waitpid(pid, &status, 0) != pid)
    status = -1;
  posix_spawn_file_actions_destroy(&fa);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    print_message("test_abaqus: skipped (xz -dc failed: is xz installed?)\n");
    remove(pk);
    return;
  }
  const int n = 345;
  double *A = calloc(2 * (size_t)n * n, sizeof *A), *B = A + (size_t)n * n;
  assert_non_null(A);
  int lk = read_lines(pk, n, A), lm = read_lines(pm, n, B);
  const char *paths[2] = {pm, pk};
  vi_dofmap *map = NULL;
  vi_diag d;
  int fmt = -1;
  assert_int_equal(vi_matrix_detect(pk, &fmt, &d), VI_OK);
  assert_int_equal(fmt, VI_MATRIX_COORDINATE);
  assert_int_equal(vi_dofmap_scan(2, paths, 0, &map, &d), VI_OK);
  assert_int_equal(vi_dofmap_n(map), n);
  const char *files[2] = {pk, pm};
  double *ref[2] = {A, B};
  for (int q = 0; q < 2; q++) {
    vi_mm *m = NULL;
    int st = vi_matrix_load(files[q], VI_MATRIX_AUTO, map, VI_CSC_LOWER, 0,
                            &m, &d);
    if (st) print_error("%s line %d: %s\n", files[q], d.line, d.message);
    assert_int_equal(st, VI_OK);
    const int *p = vi_mm_colptr(m), *ri = vi_mm_rowind(m);
    const double *v = vi_mm_values(m);
    int differ = 0, stored = 0;
    for (int j = 0; j < n; j++)
      for (int k = p[j]; k < p[j + 1]; k++) {
        size_t at = (size_t)ri[k] + (size_t)j * n, mir = (size_t)j + (size_t)ri[k] * n;
        differ += v[k] != ref[q][at] || v[k] != ref[q][mir];
        stored++;
      }
    int lower = 0;
    for (int j = 0; j < n; j++)
      for (int i = j; i < n; i++) lower += ref[q][(size_t)i + (size_t)j * n] != 0;
    print_message("Abaqus %s: %d lines, %d lower entries stored, %d differ "
                  "from the lines\n", q ? "M" : "K", q ? lm : lk, stored,
                  differ);
    assert_int_equal(differ, 0);
    assert_int_equal(stored, lower);
    vi_mm_destroy(&m);
  }
  vi_dofmap_destroy(&map);
  free(A);
  remove(pk);
}

int main(int argc, char **argv)
{
  if (argc > 1) data_dir = argv[1];
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_forms),       cmocka_unit_test(test_dofmap),
      cmocka_unit_test(test_malformed_hb), cmocka_unit_test(test_malformed_coordinate),
      cmocka_unit_test(test_limits),      cmocka_unit_test(test_bcsstk01),
      cmocka_unit_test(test_abaqus),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
