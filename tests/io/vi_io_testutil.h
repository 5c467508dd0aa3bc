/* vi_io_testutil.h - fixtures shared by the I/O tests (test_writer.c,
 * test_misuse_io.c): a fresh temporary file, and the writer's set-up
 * checks that both the writer's own test and the misuse test run. */
#ifndef VI_IO_TESTUTIL_H
#define VI_IO_TESTUTIL_H

#include "vi_testutil.h"

/* Create the file named by the mkstemp template `path` (ending XXXXXX,
 * rewritten in place) and close it; fails the test if it cannot. */
void vi_test_temp_file(char *path);

/* vi_writer_create refusing what it must (no path, no model, no handle:
 * VI_ERR_ARG; a model not set up: VI_ERR_STATE, no handle left), then
 * every writer function on a NULL handle: VI_ERR_ARG, -1 rows, "" as the
 * message, and abort/close of NULL harmless.  path: a writable file; m: a
 * set-up model. */
void vi_test_writer_refusals(const char *path, const vi_model *m);

#endif
