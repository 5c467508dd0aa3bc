/* vi_io_testutil.c - fixtures shared by the I/O tests (vi_io_testutil.h). */
#include "vi_io_testutil.h"

#include <stdlib.h>
#include <unistd.h>

#include "vibroimpact/vi_writer.h"

void vi_test_temp_file(char *path)
{
  int fd = mkstemp(path);
  assert_true(fd >= 0);
  close(fd);
}

void vi_test_writer_refusals(const char *path, const vi_model *m)
{
  vi_writer *w = NULL;
  vi_model *unset = NULL;
  vi_diag d;
  assert_int_equal(vi_writer_create(NULL, m, 0, &w, &d), VI_ERR_ARG);
  assert_int_equal(vi_writer_create(path, NULL, 0, &w, &d), VI_ERR_ARG);
  assert_int_equal(vi_writer_create(path, m, 0, NULL, &d), VI_ERR_ARG);
  assert_int_equal(vi_model_create(2, &unset), VI_OK);
  assert_int_equal(vi_writer_create(path, unset, 0, &w, &d), VI_ERR_STATE);
  assert_null(w);
  vi_model_destroy(&unset);
  /* every call on a NULL writer */
  vi_event ev = {0};
  vi_ledger_interval iv = {0};
  double x[2] = {0, 0};
  assert_int_equal(vi_writer_write_header(NULL, NULL, 1e-8, 1e-10, 0), VI_ERR_ARG);
  assert_int_equal(vi_writer_event(NULL, &ev), VI_ERR_ARG);
  assert_int_equal(vi_writer_sample(NULL, 0, x, x), VI_ERR_ARG);
  assert_int_equal(vi_writer_sample(NULL, 0, NULL, NULL), VI_ERR_ARG);
  assert_int_equal(vi_writer_ledger(NULL, &iv), VI_ERR_ARG);
  assert_int_equal(vi_writer_orbit(NULL, NULL), VI_ERR_ARG);
  assert_int_equal(vi_writer_run_info(NULL, NULL), VI_ERR_ARG);
  assert_int_equal(vi_writer_fe_shapes(NULL, NULL), VI_ERR_ARG);
  assert_int_equal((int)vi_writer_rows(NULL, "impacts"), -1);
  assert_int_equal(vi_writer_finish(NULL, 1), VI_ERR_ARG);
  assert_int_equal(vi_writer_close(NULL, 1), VI_ERR_ARG);
  assert_int_equal(vi_writer_close(&w, 1), VI_ERR_ARG);
  vi_writer_abort(NULL);
  vi_writer_abort(&w);
  assert_string_equal(vi_writer_errmsg(NULL), "");
}
