/* test_misuse_io.c - every exported function of the companion library
 * vibroimpact_scene and vibroimpact_h5 (scenes, scene edits, the HDF5 writer) called as a careless
 * or hostile host would: NULL handles, arrays and strings, zero and negative
 * lengths, non-finite values, calls out of order and after finishing.  Each
 * must return an error code (never VI_OK) and the documented sentinel, and
 * fill the diag or the handle's message; nothing may read or write out of
 * bounds (ASan and UBSan in the sanitizer build).  A separate program from
 * test_misuse.c because the numerical core links no HDF5 and no YAML. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "vi_io_testutil.h"
#include "vi_testutil.h"
#include "vibroimpact/vi_mmio.h"
#include "vibroimpact/vi_orbit.h"
#include "vibroimpact/vi_scene.h"
#include "vibroimpact/vi_scene_edit.h"
#include "vibroimpact/vi_scene_param.h"
#include "vibroimpact/vi_output.h"
#include "vibroimpact/vi_writer.h"
#include "vibroimpact/vi_identify_io.h"
#include "vibroimpact/vi_truncation_io.h"

/* an error code, and the diag's message says something */
#define assert_err_diag(call, d)         \
  do {                                   \
    memset(&(d), 0, sizeof(d));          \
    assert_true((call) < 0);             \
    assert_true(strlen((d).message) > 0); \
  } while (0)

static const char *chain3 = "model:\n  chain: {n: 3, m: 1, k: 1}\n"
                            "stop: {mass: 3, xs: 0.1, r: 0.5}\n"
                            "run: {t_end: 10}\n";

static void test_scene_misuse(void **state)
{
  (void)state;
  vi_scene *sc = NULL;
  vi_model *m = NULL;
  vi_diag d;
  const char *text = vi_scene_default_text();
  assert_non_null(text);
  assert_true(strlen(text) > 0);
  /* NULL text, NULL out, unreadable and empty files, limits */
  assert_int_equal(vi_scene_parse(NULL, -1, "x", &sc, &d), VI_ERR_ARG);
  assert_null(sc);
  assert_int_equal(vi_scene_parse(text, -1, "x", NULL, &d), VI_ERR_ARG);
  assert_err_diag(vi_scene_parse("model: [", -1, "x", &sc, &d), d);
  assert_null(sc);
  /* a length shorter than the text: only that much is read (cut mid-key) */
  assert_err_diag(vi_scene_parse(text, 3, "x", &sc, &d), d);
  assert_null(sc);
  assert_int_equal(vi_scene_parse_limited(NULL, -1, "x", 4, &sc, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_parse_limited(text, -1, "x", 4, NULL, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_parse_limited("a: [[[1]]]", -1, "x", 2, &sc, &d),
                   VI_ERR_LIMIT);
  assert_null(sc);
  assert_int_equal(vi_scene_load(NULL, &sc, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_load("x.yaml", NULL, &d), VI_ERR_ARG);
  assert_err_diag(vi_scene_load("/nonexistent/x.yaml", &sc, &d), d);
  assert_int_equal(d.code, VI_ERR_IO);
  assert_err_diag(vi_scene_load("/", &sc, &d), d); /* a directory */
  assert_null(sc);
  assert_int_equal(vi_scene_load_limited(NULL, 0, 0, &sc, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_load_limited("x.yaml", 0, 0, NULL, &d), VI_ERR_ARG);
  assert_err_diag(vi_scene_load_limited("/nonexistent/x.yaml", 0, 0, &sc, &d), d);
  assert_null(sc);
  assert_int_equal(vi_scene_load_within(NULL, 0, 0, 1e9, &sc, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_load_within("x.yaml", 0, 0, 1e9, NULL, &d), VI_ERR_ARG);
  assert_err_diag(vi_scene_load_within("x.yaml", 0, 0, NAN, &sc, &d), d);
  assert_int_equal(d.code, VI_ERR_ARG);
  assert_err_diag(vi_scene_load_within("/nonexistent/x.yaml", 0, 0, 1e9, &sc, &d), d);
  assert_int_equal(d.code, VI_ERR_IO);
  assert_null(sc);
  vi_scene_destroy(NULL);
  vi_scene_destroy(&sc); /* *sc == NULL */

  /* getters on NULL: "" and 0 */
  assert_string_equal(vi_scene_name(NULL), "");
  assert_string_equal(vi_scene_text(NULL), "");
  assert_int_equal(vi_scene_n(NULL), 0);
  assert_true(vi_scene_t0(NULL) == 0.0);
  assert_true(vi_scene_t_end(NULL) == 0.0);
  assert_true(vi_scene_rtol(NULL) == 0.0);
  assert_true(vi_scene_atol(NULL) == 0.0);
  assert_int_equal(vi_scene_method(NULL), 0);
  assert_int_equal(vi_scene_samples_per_period(NULL), 0);
  assert_int_equal(vi_scene_outputs(NULL), 0);
  assert_true(vi_scene_memory_estimate(NULL) == 0.0);
  assert_true(vi_scene_memory_available() >= 0.0); /* no handle: never fails */
  assert_int_equal(vi_scene_check_memory(NULL, 1e12, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_set_run(NULL, 1e-8, 1e-10, 10, 0), VI_ERR_ARG);
  assert_int_equal(vi_scene_create_model(NULL, &m, &d), VI_ERR_ARG);
  assert_null(m);
  assert_int_equal(vi_scene_configure_sim(NULL, NULL, &d), VI_ERR_ARG);

  /* a valid scene given bad overrides and mismatched handles */
  assert_int_equal(vi_scene_parse(text, -1, "fig2", &sc, &d), VI_OK);
  assert_int_equal(vi_scene_set_run(sc, NAN, 0, 0, -1), VI_ERR_ARG);
  assert_int_equal(vi_scene_set_run(sc, 0, NAN, 0, -1), VI_ERR_ARG);
  assert_int_equal(vi_scene_set_run(sc, 0, 0, NAN, -1), VI_ERR_ARG);
  assert_int_equal(vi_scene_set_run(sc, 0, 0, 0, VI_METHOD_COUNT), VI_ERR_ARG);
  assert_int_equal(vi_scene_set_run(sc, 0.5, 0, 0, -1), VI_ERR_TOLERANCE);
  assert_int_equal(vi_scene_create_model(sc, NULL, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_check_memory(sc, 1.0, &d), VI_ERR_LIMIT);
  assert_true(strlen(d.message) > 0);
  assert_err_diag(vi_scene_check_memory(sc, NAN, &d), d);
  assert_int_equal(d.code, VI_ERR_ARG);
  vi_scene *sc3 = NULL;
  assert_int_equal(vi_scene_parse(chain3, -1, "three", &sc3, &d), VI_OK);
  vi_model *m2 = vi_test_fig2();
  vi_sim *s = NULL;
  assert_int_equal(vi_sim_create(m2, &s), VI_OK);
  assert_err_diag(vi_scene_configure_sim(sc3, s, &d), d);
  assert_int_equal(d.code, VI_ERR_DIM);
  assert_int_equal(vi_scene_configure_sim(sc, NULL, &d), VI_ERR_ARG);
  vi_sim_destroy(&s);
  vi_model_destroy(&m2);
  vi_scene_destroy(&sc3);
  assert_null(sc3);
  vi_scene_destroy(&sc);

  /* diag formatting: NULL diag, NULL or short buffers, never past len */
  char buf[8];
  memset(buf, 'x', sizeof buf);
  vi_diag_format(NULL, buf, (int)sizeof buf);
  assert_string_equal(buf, "");
  memset(&d, 0, sizeof d);
  strcpy(d.file, "a-rather-long-file-name.yaml");
  strcpy(d.message, "a message longer than the buffer");
  d.line = 3;
  memset(buf, 'x', sizeof buf);
  vi_diag_format(&d, buf, 4);
  assert_true(strlen(buf) <= 3);
  assert_int_equal(buf[5], 'x'); /* nothing written past len */
  vi_diag_format(&d, NULL, 10);
  vi_diag_format(&d, buf, 0);
  vi_diag_format(&d, buf, -1);
}

static void test_scene_edit_misuse(void **state)
{
  (void)state;
  vi_scene_edit *e = NULL;
  vi_diag d;
  char buf[16];
  const char *text = vi_scene_default_text();
  assert_int_equal(vi_scene_edit_create(NULL, -1, "x", &e, &d), VI_ERR_ARG);
  assert_null(e);
  assert_int_equal(vi_scene_edit_create(text, -1, "x", NULL, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_edit_create_limited(NULL, -1, "x", 4, &e, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_edit_create_limited(text, -1, "x", 4, NULL, &d), VI_ERR_ARG);
  assert_err_diag(vi_scene_edit_create_limited("a: [[[[[1]]]]]", -1, "x", 3, &e, &d), d);
  assert_int_equal(d.code, VI_ERR_LIMIT);
  assert_null(e);
  assert_err_diag(vi_scene_edit_create("a: [", -1, "x", &e, &d), d);
  assert_int_equal(d.code, VI_ERR_PARSE);
  assert_null(e);
  vi_scene_edit_destroy(NULL);
  vi_scene_edit_destroy(&e);
  /* every call on a NULL edit */
  assert_int_equal(vi_scene_edit_set(NULL, "stop.r", "0.5", &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_edit_assign(NULL, "stop.r=0.5", &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_edit_set_number(NULL, "stop.r", 0.5, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_edit_get(NULL, "stop.r", buf, (int)sizeof buf, &d),
                   VI_ERR_ARG);
  assert_string_equal(vi_scene_edit_text(NULL), "");
  vi_scene *sc = NULL;
  assert_int_equal(vi_scene_edit_parse(NULL, &sc, &d), VI_ERR_ARG);
  assert_null(sc);
  assert_int_equal(vi_scene_edit_parse_within(NULL, 1e9, &sc, &d), VI_ERR_ARG);
  assert_null(sc);

  /* a live edit: NULL and malformed keys and values, short buffers */
  assert_int_equal(vi_scene_edit_create(text, -1, "fig2", &e, &d), VI_OK);
  assert_int_equal(vi_scene_edit_set(e, NULL, "1", &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_edit_set(e, "stop.r", NULL, &d), VI_ERR_ARG);
  assert_err_diag(vi_scene_edit_set(e, "", "1", &d), d);
  assert_err_diag(vi_scene_edit_set(e, "stop..r", "1", &d), d);
  assert_err_diag(vi_scene_edit_set(e, "forcing.a[0]", "1", &d), d); /* 1-based */
  assert_err_diag(vi_scene_edit_set(e, "forcing.a[-1]", "1", &d), d);
  assert_err_diag(vi_scene_edit_set(e, "forcing.a[99]", "1", &d), d);
  assert_err_diag(vi_scene_edit_set(e, "stop.r.x", "1", &d), d); /* through a scalar */
  assert_err_diag(vi_scene_edit_set(e, "stop.r", "[1, ", &d), d);
  assert_err_diag(vi_scene_edit_set(e, "stop.r", "1\n2", &d), d);
  assert_int_equal(vi_scene_edit_assign(e, NULL, &d), VI_ERR_ARG);
  assert_err_diag(vi_scene_edit_assign(e, "stop.r", &d), d); /* no '=' */
  assert_err_diag(vi_scene_edit_assign(e, "=0.5", &d), d);
  assert_int_equal(vi_scene_edit_set_number(e, NULL, 0.5, &d), VI_ERR_ARG);
  /* a non-finite number is written as the text says; the parse refuses it */
  assert_int_equal(vi_scene_edit_set_number(e, "stop.r", NAN, &d), VI_OK);
  assert_err_diag(vi_scene_edit_parse(e, &sc, &d), d);
  assert_null(sc);
  assert_int_equal(vi_scene_edit_get(e, NULL, buf, (int)sizeof buf, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_edit_get(e, "stop.r", NULL, 16, &d), VI_ERR_ARG);
  assert_true(vi_scene_edit_get(e, "stop.r", buf, 0, &d) < 0);
  assert_true(vi_scene_edit_get(e, "stop.r", buf, -4, &d) < 0);
  assert_err_diag(vi_scene_edit_get(e, "stop.nothing", buf, (int)sizeof buf, &d), d);
  assert_err_diag(vi_scene_edit_get(e, "stop", buf, (int)sizeof buf, &d), d); /* a mapping */
  char one[2];
  memset(one, 'x', sizeof one);
  assert_err_diag(vi_scene_edit_get(e, "stop.r", one, 1, &d), d); /* no room */
  assert_int_equal(d.code, VI_ERR_LIMIT);
  assert_int_equal(vi_scene_edit_parse(e, NULL, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_edit_parse_within(e, 1e9, NULL, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_edit_parse_within(e, NAN, &sc, &d), VI_ERR_ARG);
  assert_null(sc);
  /* a value the scene refuses: the parse names it */
  assert_int_equal(vi_scene_edit_set(e, "stop.r", "1.5", &d), VI_OK);
  assert_err_diag(vi_scene_edit_parse(e, &sc, &d), d);
  assert_null(sc);
  assert_non_null(vi_scene_edit_text(e));
  vi_scene_edit_destroy(&e);
  assert_null(e);
}

static void test_writer_misuse(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  vi_writer *w = NULL;
  vi_diag d;
  char path[] = "/tmp/vi_misuse_io_XXXXXX", target[512];
  vi_test_temp_file(path);
  assert_int_equal(vi_output_resolve(NULL, target, (int)sizeof target, &d), VI_ERR_ARG);
  assert_int_equal(vi_output_resolve(path, NULL, (int)sizeof target, &d), VI_ERR_ARG);
  assert_int_equal(vi_output_resolve(path, target, 0, &d), VI_ERR_ARG);
  assert_int_equal(vi_output_resolve(path, target, -1, &d), VI_ERR_ARG);
  assert_int_equal(vi_output_resolve(path, target, 4, &d), VI_ERR_LIMIT);
  assert_err_diag(vi_output_resolve("/", target, (int)sizeof target, &d), d);
  assert_int_equal(d.code, VI_ERR_IO);
  assert_err_diag(vi_output_resolve("/dev/null", target, (int)sizeof target, &d), d);
  assert_err_diag(vi_output_resolve("/nonexistent/dir/x.h5", target,
                                    (int)sizeof target, &d), d);
  /* the rest of the output module (vi_output.h) */
  int kind = -1;
  FILE *f = NULL;
  assert_int_equal(vi_output_check(NULL, 0, NULL, target, (int)sizeof target, &kind, &d), VI_ERR_ARG);
  assert_int_equal(vi_output_check(path, 7, NULL, target, (int)sizeof target, &kind, &d), VI_ERR_ARG);
  assert_int_equal(vi_output_check(path, 0, NULL, NULL, 10, &kind, &d), VI_ERR_ARG);
  assert_int_equal(vi_output_check("/dev/null", VI_OUTPUT_REGULAR, NULL, target,
                                   (int)sizeof target, &kind, &d), VI_ERR_IO);
  assert_int_equal(vi_output_part(NULL, target, (int)sizeof target), VI_ERR_ARG);
  assert_int_equal(vi_output_part(path, NULL, 10), VI_ERR_ARG);
  assert_int_equal(vi_output_part(path, target, 0), VI_ERR_ARG);
  assert_int_equal(vi_output_part(path, target, 4), VI_ERR_LIMIT);
  assert_int_equal(vi_output_same(NULL, path), 0);
  assert_int_equal(vi_output_same(path, "-"), 0);
  assert_int_equal(vi_output_open(NULL, VI_OUTPUT_FILE, &f, &d), VI_ERR_ARG);
  assert_int_equal(vi_output_open(path, 9, &f, &d), VI_ERR_ARG);
  assert_int_equal(vi_output_open(path, VI_OUTPUT_FILE, NULL, &d), VI_ERR_ARG);
  assert_null(f);
  assert_int_equal(vi_output_close(NULL, path, VI_OUTPUT_FILE, &d), VI_ERR_ARG);
  assert_int_equal(vi_output_close(&f, path, VI_OUTPUT_FILE, &d), VI_ERR_ARG);
  vi_output_discard(NULL, NULL, VI_OUTPUT_FILE);
  vi_output_discard(&f, path, 9);
  assert_int_equal(vi_output_commit(NULL, &d), VI_ERR_ARG);
  assert_int_equal(vi_output_commit("/nonexistent/dir/x.h5", &d), VI_ERR_IO);
  /* the bad arguments of vi_writer_create, every call on a NULL writer */
  vi_test_writer_refusals(path, m);
  assert_err_diag(vi_writer_create("/", m, 0, &w, &d), d);
  assert_null(w);

  vi_event ev = {0};
  vi_ledger_interval iv = {0};
  double x[2] = {0, 0};

  /* a live writer given wrong things, each with a message */
  assert_int_equal(vi_writer_create(path, m, 0, &w, &d), VI_OK);
  const char *msg = vi_writer_errmsg(w);
  assert_true(vi_writer_write_header(w, NULL, 1e-8, -1e-10, 0) < 0);
  assert_true(strlen(msg) > 0);
  assert_true(vi_writer_write_header(w, NULL, 1e-8, 1e-10, -1) < 0);
  assert_true(vi_writer_write_header(w, NULL, NAN, 1e-10, 0) < 0);
  assert_int_equal(vi_writer_write_header(w, NULL, 1e-8, 1e-10, 0), VI_OK);
  assert_int_equal(vi_writer_event(w, NULL), VI_ERR_ARG);
  assert_int_equal(vi_writer_sample(w, 0, NULL, x), VI_ERR_ARG);
  assert_int_equal(vi_writer_ledger(w, NULL), VI_ERR_ARG);
  assert_int_equal(vi_writer_ledger(w, &iv), VI_ERR_ARG); /* NULL arrays */
  assert_int_equal(vi_writer_orbit(w, NULL), VI_ERR_ARG);
  assert_int_equal(vi_writer_run_info(w, NULL), VI_ERR_ARG);
  assert_int_equal((int)vi_writer_rows(w, NULL), -1);
  assert_int_equal((int)vi_writer_rows(w, ""), -1);
  assert_int_equal(vi_writer_finish(w, 1), VI_OK);
  /* after finishing: out of order */
  assert_int_equal(vi_writer_sample(w, 0, x, x), VI_ERR_STATE);
  assert_int_equal(vi_writer_event(w, &ev), VI_ERR_ARG); /* NULL arrays */
  vi_event ev2 = {VI_EVENT_IMPACT, 2, 0, 1.0, 0.1, 0.0, x, x, x, 0};
  assert_int_equal(vi_writer_event(w, &ev2), VI_ERR_STATE);
  assert_true(vi_writer_write_header(w, NULL, 1e-8, 1e-10, 0) < 0);
  assert_int_equal(vi_writer_finish(w, 1), VI_ERR_STATE);
  assert_true(strlen(vi_writer_errmsg(w)) > 0);
  assert_int_equal(vi_writer_close(&w, 1), VI_ERR_STATE);
  assert_null(w);
  remove(path);
  /* the analysed Fig. 2 orbit (n = 2) given to a writer of a one-mass
   * model: refused, nothing written past the writer's n-sized buffers */
  vi_model *sdof = vi_test_sdof(1, 0.1, 1, 0.5, 0, 0.9, 0.1, 0.7);
  vi_orbit *o = NULL;
  assert_int_equal(vi_orbit_create(m, &o), VI_OK);
  assert_int_equal(vi_orbit_find(o), VI_OK);
  assert_int_equal(vi_writer_create(path, sdof, 0, &w, &d), VI_OK);
  assert_int_equal(vi_writer_write_header(w, NULL, 1e-8, 1e-10, 0), VI_OK);
  assert_int_equal(vi_writer_orbit(w, o), VI_ERR_DIM);
  assert_true(strlen(vi_writer_errmsg(w)) > 0);
  vi_writer_abort(&w);
  assert_null(w);
  assert_int_not_equal(access(path, F_OK), 0); /* aborted: no file */
  vi_orbit_destroy(&o);
  vi_model_destroy(&sdof);
  vi_model_destroy(&m);
}

/* Scene keys as parameters: NULL arguments, keys that are no parameter
 * (named in the diag), a buffer too small. */
static void test_scene_param_misuse(void **state)
{
  (void)state;
  vi_scene *sc = NULL;
  vi_diag d;
  char out[64];
  assert_int_equal(vi_scene_parse(vi_scene_default_text(), -1, "fig2.yaml",
                                  &sc, &d), VI_OK);
  assert_int_equal(vi_scene_param_key(NULL, "stop.xs", out, 64, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_param_key(sc, NULL, out, 64, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_param_key(sc, "stop.xs", NULL, 64, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_param_key(sc, "stop.xs", out, 0, NULL), VI_ERR_ARG);
  assert_int_equal(vi_scene_param_key(sc, "model.chain.n", out, 64, &d),
                   VI_ERR_PARSE); /* the size: not a parameter */
  assert_string_equal(d.key, "model.chain.n");
  assert_non_null(strstr(d.message, "forcing.omega"));
  assert_int_equal(vi_scene_param_key(sc, "run.method", out, 64, &d), VI_ERR_PARSE);
  assert_int_equal(vi_scene_param_key(sc, "model.rayleigh.alpha", out, 5, &d),
                   VI_ERR_LIMIT);
  assert_int_equal(vi_scene_param_key(sc, "model.rayleigh.alpha", out, 64, &d),
                   VI_OK);
  assert_string_equal(out, "damping.alpha");
  assert_int_equal(vi_scene_param_key(sc, "model.chain.k", out, 64, &d), VI_OK);
  assert_string_equal(out, "stiffness.scale"); /* a structural key */
  vi_scene_destroy(&sc);
}

/* Matrix Market reader: NULL paths, handles and outputs, an unknown
 * storage, a NaN limit, a directory and a missing file for a path; the
 * getters of a NULL handle return their sentinels. */
static void test_mm_misuse(void **state)
{
  (void)state;
  vi_mm *m = NULL;
  vi_diag d;
  assert_err_diag(vi_mm_load(NULL, VI_CSC_LOWER, &m, &d), d);
  assert_err_diag(vi_mm_load("x.mtx", VI_CSC_LOWER, NULL, &d), d);
  assert_err_diag(vi_mm_load("x.mtx", 7, &m, &d), d);
  assert_err_diag(vi_mm_load("x.mtx", -1, &m, &d), d);
  assert_int_equal(vi_mm_load("x.mtx", 7, &m, NULL), VI_ERR_ARG);
  assert_err_diag(vi_mm_load_limited("x.mtx", VI_CSC_FULL, NAN, &m, &d), d);
  assert_err_diag(vi_mm_load_limited(NULL, VI_CSC_FULL, 1e9, &m, &d), d);
  assert_err_diag(vi_mm_load("/nonexistent/x.mtx", VI_CSC_FULL, &m, &d), d);
  assert_int_equal(d.code, VI_ERR_IO);
  assert_err_diag(vi_mm_load("/", VI_CSC_FULL, &m, &d), d); /* a directory */
  assert_null(m);
  assert_err_diag(vi_mm_read_header(NULL, NULL, NULL, NULL, NULL, &d), d);
  assert_int_equal(vi_mm_read_header("/nonexistent", NULL, NULL, NULL, NULL,
                                     NULL), VI_ERR_IO);
  assert_err_diag(vi_mm_read_header("/dev/null", NULL, NULL, NULL, NULL, &d),
                  d);
  vi_mm_destroy(&m);
  vi_mm_destroy(NULL);
  assert_int_equal(vi_mm_rows(NULL), 0);
  assert_int_equal(vi_mm_cols(NULL), 0);
  assert_int_equal(vi_mm_nnz(NULL), 0);
  assert_int_equal(vi_mm_storage_kind(NULL), -1);
  assert_null(vi_mm_colptr(NULL));
  assert_null(vi_mm_rowind(NULL));
  assert_null(vi_mm_values(NULL));
  /* the other formats, the dof map and the scene's view of them */
  int fmt = 0, node = 0, dof = 0;
  assert_err_diag(vi_matrix_detect(NULL, &fmt, &d), d);
  assert_err_diag(vi_matrix_detect("/dev/null", NULL, &d), d);
  assert_err_diag(vi_matrix_detect("/dev/null", &fmt, &d), d); /* a device */
  assert_err_diag(vi_matrix_read_header(NULL, VI_MATRIX_AUTO, NULL, NULL,
                                        NULL, NULL, &d), d);
  assert_err_diag(vi_matrix_read_header("/", 9, NULL, NULL, NULL, NULL, &d),
                  d);
  assert_err_diag(vi_matrix_load(NULL, VI_MATRIX_AUTO, NULL, VI_CSC_LOWER, 0,
                                 &m, &d), d);
  assert_err_diag(vi_matrix_load("x", VI_MATRIX_AUTO, NULL, VI_CSC_LOWER, 0,
                                 NULL, &d), d);
  assert_err_diag(vi_matrix_load("x", VI_MATRIX_AUTO, NULL, 7, 0, &m, &d), d);
  assert_err_diag(vi_matrix_load("x", VI_MATRIX_AUTO, NULL, VI_CSC_LOWER,
                                 NAN, &m, &d), d);
  assert_err_diag(vi_matrix_load("/nonexistent", -4, NULL, VI_CSC_LOWER, 0,
                                 &m, &d), d);
  assert_null(m);
  vi_dofmap *map = NULL;
  const char *paths[2] = {"/nonexistent", NULL};
  assert_err_diag(vi_dofmap_scan(0, paths, 0, &map, &d), d);
  assert_err_diag(vi_dofmap_scan(1, NULL, 0, &map, &d), d);
  assert_err_diag(vi_dofmap_scan(1, paths, 0, NULL, &d), d);
  assert_err_diag(vi_dofmap_scan(1, paths, NAN, &map, &d), d);
  assert_err_diag(vi_dofmap_scan(2, paths, 0, &map, &d), d); /* a NULL path */
  assert_err_diag(vi_dofmap_scan(1, paths, 0, &map, &d), d); /* missing */
  assert_null(map);
  vi_dofmap_destroy(&map);
  vi_dofmap_destroy(NULL);
  assert_int_equal(vi_dofmap_n(NULL), 0);
  assert_int_equal(vi_dofmap_label(NULL, 1, &node, &dof), VI_ERR_ARG);
  assert_int_equal(vi_dofmap_index(NULL, 1, 1), 0);
  assert_null(vi_scene_dofmap(NULL));
  assert_int_equal(vi_scene_matrix_format(NULL, 0), -1);
  vi_scene *sc = NULL;
  assert_int_equal(vi_scene_parse(vi_scene_default_text(), -1, "x", &sc, &d),
                   VI_OK);
  assert_null(vi_scene_dofmap(sc)); /* not an FE scene */
  assert_int_equal(vi_scene_matrix_format(sc, 0), -1);
  vi_scene_destroy(&sc);
}

/* FE scenes: vi_scene_create_fe on NULL, another kind of model, bad
 * modes and keep; vi_scene_dofs of NULL. */
static void test_fe_scene_misuse(void **state)
{
  (void)state;
  vi_scene *sc = NULL;
  vi_fe *fe = NULL;
  vi_diag d;
  assert_int_equal(vi_scene_dofs(NULL), 0);
  assert_int_equal(vi_scene_fe_summary(NULL, NULL, NULL, NULL, NULL, NULL, NULL), VI_ERR_ARG);
  assert_err_diag(vi_scene_create_fe(NULL, 0, 0, &fe, &d), d);
  assert_int_equal(vi_scene_parse(chain3, -1, "chain3", &sc, &d), VI_OK);
  assert_int_equal(vi_scene_dofs(sc), 3);
  assert_int_equal(vi_scene_initial(NULL, NULL, NULL), VI_ERR_ARG);
  assert_int_equal(vi_scene_initial(sc, NULL, NULL), VI_OK);
  assert_err_diag(vi_scene_create_fe(sc, 0, 0, NULL, &d), d);
  assert_err_diag(vi_scene_create_fe(sc, 0, 2, &fe, &d), d);
  assert_err_diag(vi_scene_create_fe(sc, 0, -1, &fe, &d), d);
  assert_err_diag(vi_scene_create_fe(sc, 0, 0, &fe, &d), d); /* a chain */
  assert_int_equal(d.code, VI_ERR_UNSUPPORTED);
  assert_int_equal(vi_scene_create_fe(sc, -3, 0, &fe, NULL), VI_ERR_UNSUPPORTED);
  assert_null(fe);
  vi_scene_destroy(&sc);
}

/* vi_writer_fe_shapes: NULL writer or reduction; a reduction without its
 * full Psi; one of another size than the writer's model. */
static void test_fe_shapes_misuse(void **state)
{
  (void)state;
  char path[] = "/tmp/vi_misuse_fe_XXXXXX";
  vi_test_temp_file(path);
  static const int cp[4] = {0, 1, 2, 3}, ri[3] = {0, 1, 2};
  static const double mv[3] = {1, 2, 3}, kv[3] = {4, 5, 6};
  double w[3] = {0, 0, 1};
  vi_fe *fe = NULL;
  vi_model *m = NULL;
  vi_writer *wr = NULL;
  vi_diag d;
  assert_int_equal(vi_fe_create(3, &fe), VI_OK);
  assert_int_equal(vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 0, cp, ri, mv), VI_OK);
  assert_int_equal(vi_fe_set_stiffness_csc(fe, VI_CSC_LOWER, 0, cp, ri, kv), VI_OK);
  assert_int_equal(vi_fe_set_modes(fe, 2), VI_OK);
  assert_int_equal(vi_fe_add_stop(fe, w, 0.1, 0.5), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_OK); /* no shapes kept */
  assert_int_equal(vi_fe_create_model(fe, &m), VI_OK);
  assert_int_equal(vi_writer_create(path, m, 0, &wr, &d), VI_OK);
  assert_int_equal(vi_writer_fe_shapes(NULL, fe), VI_ERR_ARG);
  assert_int_equal(vi_writer_fe_shapes(wr, NULL), VI_ERR_ARG);
  assert_int_equal(vi_writer_fe_shapes(wr, fe), VI_ERR_STATE);
  assert_true(strlen(vi_writer_errmsg(wr)) > 0);
  vi_writer_abort(&wr);
  vi_model_destroy(&m);
  /* a writer of another n */
  vi_model *m5 = vi_test_chain(5, 1, 1, 0.1, 0.1, 0.7, 0.9, NULL);
  vi_fe *fk = NULL;
  assert_int_equal(vi_fe_create(3, &fk), VI_OK);
  assert_int_equal(vi_fe_set_mass_csc(fk, VI_CSC_LOWER, 0, cp, ri, mv), VI_OK);
  assert_int_equal(vi_fe_set_stiffness_csc(fk, VI_CSC_LOWER, 0, cp, ri, kv), VI_OK);
  assert_int_equal(vi_fe_set_modes(fk, 2), VI_OK);
  assert_int_equal(vi_fe_add_stop(fk, w, 0.1, 0.5), VI_OK);
  assert_int_equal(vi_fe_set_keep_shapes(fk, 1), VI_OK);
  assert_int_equal(vi_fe_setup(fk), VI_OK);
  assert_int_equal(vi_writer_create(path, m5, 0, &wr, &d), VI_OK);
  assert_int_equal(vi_writer_fe_shapes(wr, fk), VI_ERR_DIM);
  vi_writer_abort(&wr);
  char part[64];
  snprintf(part, sizeof part, "%s.part", path);
  assert_int_equal(access(part, F_OK), -1); /* aborted: no partial file */
  remove(path);
  vi_fe_destroy(&fk);
  vi_fe_destroy(&fe);
  vi_model_destroy(&m5);
}

/* vi_identify_write_h5: NULL arguments, an identification without a fit. */
static void test_identify_h5_misuse(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  vi_identify *id = NULL;
  vi_diag d;
  double t[2] = {0, 1}, x[2] = {0, 0};
  assert_int_equal(vi_identify_create(m, 1, &id), VI_OK);
  assert_int_equal(vi_identify_write_h5(NULL, id, NULL, 2, t, x, &d), VI_ERR_ARG);
  assert_int_equal(vi_identify_write_h5("x.h5", NULL, NULL, 2, t, x, &d), VI_ERR_ARG);
  assert_int_equal(vi_identify_write_h5("x.h5", id, NULL, 0, t, x, &d), VI_ERR_ARG);
  assert_int_equal(vi_identify_write_h5("x.h5", id, NULL, 2, NULL, x, NULL), VI_ERR_ARG);
  assert_int_equal(vi_identify_write_h5("x.h5", id, "stop.r", 2, t, x, &d), VI_ERR_STATE);
  vi_identify_destroy(&id);
  vi_model_destroy(&m);
}

/* vi_truncation_write_h5: NULL tables, bad sizes, a directory as target:
 * refused, no file or .part left. */
static void test_truncation_h5_misuse(void **state)
{
  (void)state;
  vi_diag d;
  double info[VI_TRUNCATION_INFO] = {0}, ref[VI_TRUNCATION_COLUMNS] = {0},
         rows[2 * VI_TRUNCATION_COLUMNS] = {0};
  assert_int_equal(vi_truncation_write_h5(NULL, "s", "", info, ref, 2, rows, 2, &d), VI_ERR_ARG);
  assert_int_equal(vi_truncation_write_h5("x.h5", "s", "", NULL, ref, 2, rows, 2, &d), VI_ERR_ARG);
  assert_int_equal(vi_truncation_write_h5("x.h5", "s", "", info, NULL, 2, rows, 2, &d), VI_ERR_ARG);
  assert_int_equal(vi_truncation_write_h5("x.h5", "s", "", info, ref, 2, NULL, 2, NULL), VI_ERR_ARG);
  assert_int_equal(vi_truncation_write_h5("x.h5", "s", "", info, ref, -1, rows, 2, &d), VI_ERR_ARG);
  assert_int_equal(vi_truncation_write_h5("x.h5", "s", "", info, ref, 2, rows, 1, &d), VI_ERR_ARG);
  assert_int_equal(vi_truncation_write_h5("x.h5", "s", "", info, ref, 0, rows, 0, &d), VI_ERR_ARG);
  assert_int_equal(access("x.h5", F_OK), -1);
  assert_int_equal(vi_truncation_write_h5(".", NULL, NULL, info, ref, 2, rows, 2, &d), VI_ERR_IO);
  assert_int_equal(access("./.part", F_OK), -1);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_scene_misuse),
      cmocka_unit_test(test_scene_edit_misuse),
      cmocka_unit_test(test_writer_misuse),
      cmocka_unit_test(test_scene_param_misuse),
      cmocka_unit_test(test_mm_misuse),
      cmocka_unit_test(test_fe_scene_misuse),
      cmocka_unit_test(test_fe_shapes_misuse),
      cmocka_unit_test(test_identify_h5_misuse),
      cmocka_unit_test(test_truncation_h5_misuse),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
