/* vi_mm_testutil.h - fixtures shared by the matrix readers' tests
 * (test_mmio.c, test_hbio.c). */
#ifndef VI_MM_TESTUTIL_H
#define VI_MM_TESTUTIL_H

#include "vi_testutil.h"
#include "vibroimpact/vi_mmio.h"

/* Write text to a file of this process named tag_PID_k (path[256]). */
void vi_test_write_text(char *path, const char *tag, int k, const char *text);

/* The readers' test matrix A = [4 -1 0; -1 4 -2; 0 -2 5], as a reader
 * returned it in `storage` (VI_CSC_LOWER or VI_CSC_FULL): every index and
 * value exact. */
void vi_test_expect_a3(const vi_mm *m, int storage);

#endif
