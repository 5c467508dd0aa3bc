/* test_writer.c - the HDF5 file of the Fig. 2 scene read back through the
 * HDF5 API; no partial file after an error; no HDF5 object left open. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gsl/gsl_errno.h>
#include <hdf5.h>

#include "vi_io_testutil.h"
#include "vi_testutil.h"
#include "vibroimpact/vi_scene.h"
#include "vibroimpact/vi_output.h"
#include "vibroimpact/vi_writer.h"

typedef struct both { vi_writer *w; vi_test_events ev; int nled; } both;

static int on_ev(const vi_event *e, void *u)
{
  both *b = u;
  vi_test_collect(e, &b->ev);
  return vi_writer_event(b->w, e);
}
static int on_smp(double t, int n, const double *x, const double *v, void *u)
{
  (void)n;
  return vi_writer_sample(((both *)u)->w, t, x, v);
}
static int on_led(const vi_ledger_interval *iv, void *u)
{
  ((both *)u)->nled++;
  return vi_writer_ledger(((both *)u)->w, iv);
}

static hsize_t rows(hid_t f, const char *name, int *rank, hsize_t *cols)
{
  hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
  assert_true(d >= 0);
  hid_t sp = H5Dget_space(d);
  hsize_t dims[2] = {0, 1};
  *rank = H5Sget_simple_extent_dims(sp, dims, NULL);
  H5Sclose(sp);
  H5Dclose(d);
  *cols = dims[1];
  return dims[0];
}

/* The whole dataset `name` as `type` (count values of size bytes). */
static void *read_as(hid_t f, const char *name, hid_t type, size_t size,
                     size_t count)
{
  void *buf = malloc(size * (count ? count : 1));
  hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
  assert_true(d >= 0);
  assert_true(H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf) >= 0);
  H5Dclose(d);
  return buf;
}

static double *read_all(hid_t f, const char *name, size_t count)
{
  return read_as(f, name, H5T_NATIVE_DOUBLE, sizeof(double), count);
}

static void test_fig2_round_trip(void **state)
{
  (void)state;
  char path[] = "/tmp/vi_test_writer_XXXXXX";
  vi_test_temp_file(path);
  vi_scene *sc = NULL;
  vi_model *m = NULL;
  vi_sim *s = NULL;
  vi_diag d;
  assert_int_equal(vi_scene_parse(vi_scene_default_text(), -1, "fig2", &sc, &d), VI_OK);
  assert_int_equal(vi_scene_set_run(sc, 0, 0, 20, -1), VI_OK);
  assert_int_equal(vi_scene_create_model(sc, &m, &d), VI_OK);
  both b = {NULL, {0}, 0};
  assert_int_equal(vi_writer_create(path, m, 1, &b.w, &d), VI_OK);
  assert_int_equal(vi_writer_write_header(b.w, sc, 1e-8, 1e-10, 0), VI_OK);
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_scene_configure_sim(sc, s, &d), VI_OK);
  double T = 2 * M_PI / 0.9;
  int spp = vi_scene_samples_per_period(sc);
  assert_int_equal(spp, 64);
  vi_sim_set_event_callback(s, on_ev, &b, NULL);
  vi_sim_set_sampling(s, T / spp, on_smp, &b, NULL);
  vi_sim_enable_ledger(s, 1);
  vi_sim_set_ledger_callback(s, on_led, &b, NULL);
  assert_int_equal(vi_sim_run(s, vi_scene_t_end(sc)), VI_OK);
  assert_int_equal(vi_writer_close(&b.w, 1), VI_OK);
  assert_null(b.w);

  char part[64];
  snprintf(part, sizeof part, "%s.part", path);
  assert_int_not_equal(access(part, F_OK), 0); /* renamed */
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  int rank;
  hsize_t cols, ni = rows(f, "impacts/time", &rank, &cols);
  assert_int_equal((int)ni, b.ev.count);
  assert_true(ni >= 19);
  double *t = read_all(f, "impacts/time", ni), *vn = read_all(f, "impacts/vn", ni);
  double *x = read_all(f, "impacts/x", 2 * ni);
  assert_int_equal((int)rows(f, "impacts/x", &rank, &cols), b.ev.count);
  assert_int_equal(rank, 2);
  assert_int_equal((int)cols, 2);
  for (hsize_t i = 0; i < ni; i++) {
    assert_close(t[i], b.ev.t[i], 0);       /* bit for bit */
    assert_close(vn[i], b.ev.vn[i], 0);
    assert_close(x[2 * i + 1], b.ev.x[2 * i + 1], 0); /* row i = (x_1, x_2) */
  }
  /* samples at t0 + k T/64 for k = 0 .. 20*64 */
  hsize_t ns = rows(f, "trajectory/time", &rank, &cols);
  assert_int_equal((int)ns, 20 * spp + 1);
  double *ts = read_all(f, "trajectory/time", ns), *q = read_all(f, "trajectory/q", 2 * ns),
         *xs = read_all(f, "trajectory/x", 2 * ns);
  assert_close(ts[ns - 1], 20 * T, 1e-9);
  /* the modal columns are Psi^T M x of the physical ones */
  double qq[2];
  vi_model_to_modal(m, xs + 2 * (ns / 2), qq);
  assert_close(q[2 * (ns / 2)], qq[0], 1e-15);
  assert_int_equal((int)rows(f, "ledger/FE", &rank, &cols), b.nled);
  /* the scene text (a dataset: any length) and the state of the file */
  hid_t sd = H5Dopen2(f, "scene", H5P_DEFAULT);
  hid_t ty = H5Dget_type(sd);
  size_t len = H5Tget_size(ty);
  char *text = malloc(len);
  assert_true(H5Dread(sd, ty, H5S_ALL, H5S_ALL, H5P_DEFAULT, text) >= 0);
  assert_string_equal(text, vi_scene_default_text());
  H5Tclose(ty);
  H5Dclose(sd);
  int complete = -1;
  hid_t a = H5Aopen(f, "complete", H5P_DEFAULT);
  H5Aread(a, H5T_NATIVE_INT, &complete);
  H5Aclose(a);
  assert_int_equal(complete, 1);
  double Psi[4];
  hid_t ds = H5Dopen2(f, "modal/Psi", H5P_DEFAULT);
  H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, Psi);
  H5Dclose(ds);
  int ld;
  const double *P = vi_model_modal_shapes(m, &ld);
  assert_close(Psi[0 * 2 + 1], P[0 + 1 * ld], 0); /* [i][j] = Psi(i, j) */
  H5Fclose(f);
  /* nothing left open by the writer or by us */
  assert_int_equal((int)H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0);
  free(text); free(t); free(vn); free(x); free(ts); free(q); free(xs);
  remove(path);
  vi_test_events_free(&b.ev);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
  vi_scene_destroy(&sc);
}

static void test_unwritable_and_abort(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  vi_writer *w = NULL;
  vi_diag d;
  assert_int_equal(vi_writer_create("/nonexistent-dir/x.h5", m, 0, &w, &d), VI_ERR_IO);
  assert_null(w);
  assert_non_null(strstr(d.message, "cannot write /nonexistent-dir/x.h5"));
  char path[] = "/tmp/vi_test_abort_XXXXXX", part[64];
  vi_test_temp_file(path);
  remove(path);
  snprintf(part, sizeof part, "%s.part", path);
  assert_int_equal(vi_writer_create(path, m, 0, &w, &d), VI_OK);
  assert_int_equal(access(part, F_OK), 0);
  vi_writer_abort(&w); /* an error in the run: no file at all */
  assert_null(w);
  assert_int_not_equal(access(part, F_OK), 0);
  assert_int_not_equal(access(path, F_OK), 0);
  assert_int_equal((int)H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0);
  vi_model_destroy(&m);
}

/* Every writer function with NULL, zero, mismatched and out-of-order
 * arguments: a code, never a crash (run under ASan/UBSan in the sanitizer
 * build); the handle is freed by close whatever happens. */
static void test_misuse(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  vi_writer *w = NULL;
  vi_diag d;
  char path[] = "/tmp/vi_test_misuse_XXXXXX", target[16];
  vi_test_temp_file(path);
  assert_int_equal(vi_output_resolve(NULL, target, sizeof target, &d), VI_ERR_ARG);
  assert_int_equal(vi_output_resolve("", target, sizeof target, &d), VI_ERR_ARG);
  assert_int_equal(vi_output_resolve(path, NULL, 100, &d), VI_ERR_ARG);
  assert_int_equal(vi_output_resolve(path, target, 0, NULL), VI_ERR_ARG);
  assert_int_equal(vi_output_resolve(path, target, sizeof target, &d), VI_ERR_LIMIT);
  vi_test_writer_refusals(path, m);
  vi_ledger_interval iv = {0};
  /* a live writer given wrong things */
  assert_int_equal(vi_writer_create(path, m, 0, &w, &d), VI_OK);
  vi_scene *sc3 = NULL;
  assert_int_equal(vi_scene_parse("model:\n  chain: {n: 3, m: 1, k: 1}\n"
                                  "stop: {mass: 3, xs: 0.1, r: 0.5}\n"
                                  "run: {t_end: 10}\n", -1, "three", &sc3, &d), VI_OK);
  assert_int_equal(vi_writer_write_header(w, sc3, 1e-8, 1e-10, 0), VI_ERR_DIM);
  assert_int_equal(vi_writer_write_header(w, NULL, 1e-8, 1e-10, 99), VI_ERR_ARG);
  assert_int_equal(vi_writer_write_header(w, NULL, -1, 1e-10, 0), VI_ERR_ARG);
  assert_int_equal(vi_writer_write_header(w, NULL, NAN, 1e-10, 0), VI_ERR_ARG);
  double x[3] = {0, 0, 0};
  vi_event bad = {VI_EVENT_IMPACT, 3, 0, 1.0, -1.0, 0.1, x, x, x, 0};
  assert_int_equal(vi_writer_event(w, &bad), VI_ERR_DIM);
  bad.n = 2;
  bad.v_plus = NULL;
  assert_int_equal(vi_writer_event(w, &bad), VI_ERR_ARG);
  assert_int_equal(vi_writer_event(w, NULL), VI_ERR_ARG);
  assert_int_equal(vi_writer_sample(w, 0, x, NULL), VI_ERR_ARG);
  assert_int_equal(vi_writer_ledger(w, &iv), VI_ERR_ARG); /* NULL arrays */
  iv.n = 3;
  iv.Ea = iv.Eb = iv.FE = iv.DE = iv.XE = iv.CE = x;
  assert_int_equal(vi_writer_ledger(w, &iv), VI_ERR_DIM);
  assert_int_equal(vi_writer_run_info(w, NULL), VI_ERR_ARG);
  assert_int_equal((int)vi_writer_rows(w, NULL), -1);
  assert_int_equal((int)vi_writer_rows(w, "nonsense"), -1);
  /* finish twice: the second is out of order; close frees either way */
  assert_int_equal(vi_writer_write_header(w, NULL, 1e-8, 1e-10, 0), VI_OK);
  assert_int_equal(vi_writer_finish(w, 1), VI_OK);
  assert_int_equal(vi_writer_finish(w, 1), VI_ERR_STATE);
  assert_int_equal(vi_writer_close(&w, 1), VI_ERR_STATE);
  assert_null(w);
  assert_int_equal(access(path, F_OK), 0); /* the finished file stays */
  /* a failed close frees the handle too, and leaves no file */
  remove(path);
  assert_int_equal(vi_writer_create(path, m, 0, &w, &d), VI_OK);
  assert_int_equal(vi_writer_close(&w, 1), VI_ERR_IO); /* no header */
  assert_null(w);
  assert_int_not_equal(access(path, F_OK), 0);
  assert_int_equal((int)H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0);
  vi_scene_destroy(&sc3);
  vi_model_destroy(&m);
}

/* Fitted chunks and fixed ranks: a one-mass scene writes [rows][1]; a
 * short run's file holds about its data, not 64 KiB chunks per dataset. */
static void test_rank_and_size(void **state)
{
  (void)state;
  char path[] = "/tmp/vi_test_rank_XXXXXX";
  vi_test_temp_file(path);
  vi_model *m = vi_test_sdof(1, 0.05, 1, 0.5, 0, 0.9, 0.1, 0.7);
  vi_writer *w = NULL;
  vi_sim *s = NULL;
  vi_diag d;
  both b = {NULL, {0}, 0};
  assert_int_equal(vi_writer_create(path, m, 1, &w, &d), VI_OK);
  b.w = w;
  assert_int_equal(vi_writer_write_header(w, NULL, 1e-8, 1e-10, 0), VI_OK);
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  vi_sim_set_event_callback(s, on_ev, &b, NULL);
  vi_sim_set_sampling(s, 0.1, on_smp, &b, NULL);
  assert_int_equal(vi_sim_run(s, 50.0), VI_OK);
  assert_int_equal(vi_writer_run_info(w, s), VI_OK);
  assert_int_equal(vi_writer_close(&w, 1), VI_OK);
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  int rank;
  hsize_t cols;
  const char *vec[] = {"impacts/x", "impacts/v_minus", "impacts/v_plus",
                       "trajectory/x", "trajectory/v", "trajectory/q",
                       "trajectory/qd"};
  for (int k = 0; k < 7; k++) {
    rows(f, vec[k], &rank, &cols);
    assert_int_equal(rank, 2);
    assert_int_equal((int)cols, 1);
  }
  hsize_t ni = rows(f, "impacts/time", &rank, &cols);
  assert_int_equal(rank, 1);
  assert_int_equal((int)ni, b.ev.count);
  /* /run: the method that ran and every statistic by name */
  int64_t steps = -1;
  hid_t a = H5Aopen_by_name(f, "run", vi_stat_name(VI_STAT_STEPS), H5P_DEFAULT, H5P_DEFAULT);
  assert_true(a >= 0);
  H5Aread(a, H5T_NATIVE_INT64, &steps);
  H5Aclose(a);
  assert_int_equal(steps, vi_sim_stat(s, VI_STAT_STEPS));
  for (int k = 0; k < VI_STAT_COUNT; k++)
    assert_true(H5Aexists_by_name(f, "run", vi_stat_name(k), H5P_DEFAULT) > 0);
  assert_true(H5Aexists_by_name(f, "run", "method_note", H5P_DEFAULT) > 0);
  assert_int_equal(H5Lexists(f, "ledger", H5P_DEFAULT), 0); /* not asked */
  H5Fclose(f);
  /* 501 samples of 5 one-wide columns (20 kB raw) and the events: the
   * file stays well under what 64 KiB chunks per dataset would take */
  struct stat st;
  assert_int_equal(stat(path, &st), 0);
  print_message("one-mass file: %lld bytes, %d events\n", (long long)st.st_size, b.ev.count);
  assert_true(st.st_size < 200000);
  remove(path);
  vi_test_events_free(&b.ev);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
}

/* A scene text of any size is stored (an attribute stops at 64 KiB). */
static void test_large_scene_text(void **state)
{
  (void)state;
  size_t big = 200000;
  char *text = malloc(big + 512);
  int k = (int)strlen(vi_scene_default_text());
  memcpy(text, vi_scene_default_text(), (size_t)k + 1);
  while ((size_t)k < big) k += snprintf(text + k, 512, "# padding comment line\n");
  vi_scene *sc = NULL;
  vi_model *m = NULL;
  vi_writer *w = NULL;
  vi_diag d;
  assert_int_equal(vi_scene_parse(text, -1, "big", &sc, &d), VI_OK);
  assert_int_equal(vi_scene_create_model(sc, &m, &d), VI_OK);
  char path[] = "/tmp/vi_test_big_XXXXXX";
  vi_test_temp_file(path);
  assert_int_equal(vi_writer_create(path, m, 0, &w, &d), VI_OK);
  assert_int_equal(vi_writer_write_header(w, sc, 1e-8, 1e-10, 0), VI_OK);
  assert_int_equal(vi_writer_close(&w, 1), VI_OK);
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  hid_t ds = H5Dopen2(f, "scene", H5P_DEFAULT), ty = H5Dget_type(ds);
  size_t len = H5Tget_size(ty);
  char *back = malloc(len);
  assert_true(H5Dread(ds, ty, H5S_ALL, H5S_ALL, H5P_DEFAULT, back) >= 0);
  assert_string_equal(back, text);
  H5Tclose(ty);
  H5Dclose(ds);
  H5Fclose(f);
  free(back);
  free(text);
  remove(path);
  vi_model_destroy(&m);
  vi_scene_destroy(&sc);
}

/* A two-sided clearance (as share/scenes/clearance.yaml): /impacts/stop holds
 * each event's stop, bit for bit, and /model the stops as rows. */
typedef struct stops_rec { vi_writer *w; int count, stop[4096]; } stops_rec;

static int on_stop_ev(const vi_event *e, void *u)
{
  stops_rec *r = u;
  if (r->count < 4096) r->stop[r->count] = e->stop;
  r->count++;
  return vi_writer_event(r->w, e);
}

static void test_stops_round_trip(void **state)
{
  (void)state;
  char path[] = "/tmp/vi_test_writer_XXXXXX";
  vi_test_temp_file(path);
  vi_scene *sc = NULL;
  vi_model *m = NULL;
  vi_sim *s = NULL;
  vi_diag d;
  const char *text = "model:\n  chain: {n: 2, m: 1.0, k: 1.0, c: 0.05}\n"
                     "forcing: {omega: 0.9, a: [0.5, 0.0]}\n"
                     "stops:\n  - {mass: 2, xs: 0.1, r: 0.8}\n"
                     "  - {w: [0.0, -1.0], xs: 0.1, r: 0.8}\n";
  assert_int_equal(vi_scene_parse(text, -1, "clearance", &sc, &d), VI_OK);
  assert_int_equal(vi_scene_set_run(sc, 0, 0, 20, -1), VI_OK);
  assert_int_equal(vi_scene_create_model(sc, &m, &d), VI_OK);
  stops_rec *r = calloc(1, sizeof *r);
  assert_non_null(r);
  assert_int_equal(vi_writer_create(path, m, 1, &r->w, &d), VI_OK);
  assert_int_equal(vi_writer_write_header(r->w, sc, 1e-8, 1e-10, 0), VI_OK);
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_scene_configure_sim(sc, s, &d), VI_OK);
  vi_sim_set_event_callback(s, on_stop_ev, r, NULL);
  assert_int_equal(vi_sim_run(s, vi_scene_t_end(sc)), VI_OK);
  assert_int_equal(vi_writer_close(&r->w, 1), VI_OK);
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  int rank;
  hsize_t cols, ni = rows(f, "impacts/stop", &rank, &cols);
  assert_int_equal((int)ni, r->count);
  assert_true(r->count <= 4096);
  double *st = read_all(f, "impacts/stop", ni);
  int hits[2] = {0, 0};
  for (hsize_t i = 0; i < ni; i++) {
    assert_close(st[i], r->stop[i], 0);
    hits[r->stop[i]]++;
  }
  print_message("clearance: %d events, %d on the upper stop, %d on the "
                "lower\n", r->count, hits[0], hits[1]);
  assert_true(hits[0] > 0 && hits[1] > 0);
  assert_int_equal((int)rows(f, "model/stops_w", &rank, &cols), 2);
  assert_int_equal((int)cols, 2);
  double *sw = read_all(f, "model/stops_w", 4), *sx = read_all(f, "model/stops_x_s", 2);
  /* row k = w_k: (0, 1) then (0, -1) */
  assert_true(sw[0] == 0.0 && sw[1] == 1.0 && sw[2] == 0.0 && sw[3] == -1.0);
  assert_true(sx[0] == 0.1 && sx[1] == 0.1);
  H5Fclose(f);
  free(st);
  free(sw);
  free(sx);
  free(r);
  unlink(path);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
  vi_scene_destroy(&sc);
}

/* The output module (vi_output.h): the same file by device and inode, a
 * character device written directly by streams, a planted link at
 * TARGET.part and the scene refused, a commit that renames and a discard
 * that leaves the old file. */
static void test_output_module(void **state)
{
  (void)state;
  char dir[] = "/tmp/vi_outXXXXXX", a[256], b[256], t[4096], part[4200];
  assert_non_null(mkdtemp(dir));
  vi_diag d;
  int kind = -1;
  snprintf(a, sizeof a, "%s/x.h5", dir);
  /* two names of one file still to be written, then of an existing one */
  snprintf(b, sizeof b, "%s/./x.h5", dir);
  assert_int_equal(vi_output_same(a, b), 1);
  snprintf(b, sizeof b, "%s/y.h5", dir);
  assert_int_equal(vi_output_same(a, b), 0);
  FILE *f = fopen(a, "w");
  assert_non_null(f);
  fputs("old", f);
  fclose(f);
  snprintf(b, sizeof b, "%s/link.h5", dir);
  assert_int_equal(symlink(a, b), 0);
  assert_int_equal(vi_output_same(a, b), 1);
  /* a stream to /dev/null is written directly; a regular output refuses it */
  assert_int_equal(vi_output_check("/dev/null", VI_OUTPUT_STREAM, NULL, t,
                                   (int)sizeof t, &kind, &d), VI_OK);
  assert_int_equal(kind, VI_OUTPUT_DEVICE);
  assert_int_equal(vi_output_open(t, kind, &f, &d), VI_OK);
  assert_true(fputs("k,t\n", f) >= 0);
  assert_int_equal(vi_output_close(&f, t, kind, &d), VI_OK);
  assert_null(f);
  struct stat st;
  assert_int_equal(stat("/dev/null", &st), 0);
  assert_true(S_ISCHR(st.st_mode));
  assert_int_equal(vi_output_check("/dev/null", VI_OUTPUT_REGULAR, NULL, t,
                                   (int)sizeof t, &kind, &d), VI_ERR_IO);
  assert_non_null(strstr(d.message, "character device"));
  /* "-" is stdout for streams only */
  assert_int_equal(vi_output_check("-", VI_OUTPUT_STREAM, NULL, t, (int)sizeof t,
                                   &kind, &d), VI_OK);
  assert_int_equal(kind, VI_OUTPUT_STDOUT);
  /* the scene, named through the link, is refused */
  assert_int_equal(vi_output_check(b, VI_OUTPUT_STREAM, a, t, (int)sizeof t,
                                   &kind, &d), VI_ERR_ARG);
  assert_non_null(strstr(d.message, "scene"));
  /* a link planted at TARGET.part */
  assert_int_equal(vi_output_part(a, part, (int)sizeof part), VI_OK);
  assert_int_equal(symlink("/tmp/vi_out_victim", part), 0);
  assert_int_equal(vi_output_check(a, 0, NULL, t, (int)sizeof t, &kind, &d), VI_ERR_IO);
  assert_non_null(strstr(d.message, "symbolic link"));
  assert_int_equal(vi_output_open(a, VI_OUTPUT_FILE, &f, &d), VI_ERR_IO);
  assert_int_equal(access("/tmp/vi_out_victim", F_OK), -1);
  unlink(part);
  /* through the link: the target is replaced on close, kept on discard */
  assert_int_equal(vi_output_check(b, 0, NULL, t, (int)sizeof t, &kind, &d), VI_OK);
  assert_int_equal(kind, VI_OUTPUT_FILE);
  assert_int_equal(vi_output_open(t, kind, &f, &d), VI_OK);
  fputs("partial", f);
  vi_output_discard(&f, t, kind);
  assert_int_equal(access(part, F_OK), -1);
  char buf[16] = "";
  f = fopen(a, "r");
  assert_non_null(fgets(buf, sizeof buf, f));
  fclose(f);
  assert_string_equal(buf, "old");
  assert_int_equal(vi_output_open(t, kind, &f, &d), VI_OK);
  fputs("new", f);
  assert_int_equal(vi_output_close(&f, t, kind, &d), VI_OK);
  f = fopen(a, "r");
  assert_non_null(fgets(buf, sizeof buf, f));
  fclose(f);
  assert_string_equal(buf, "new");
  assert_int_equal(lstat(b, &st), 0);
  assert_true(S_ISLNK(st.st_mode));
  /* a directory and a FIFO are refused even as streams */
  assert_int_equal(vi_output_check(dir, VI_OUTPUT_STREAM, NULL, t, (int)sizeof t,
                                   &kind, &d), VI_ERR_IO);
  snprintf(part, sizeof part, "%s/fifo", dir);
  assert_int_equal(mkfifo(part, 0600), 0);
  assert_int_equal(vi_output_check(part, VI_OUTPUT_STREAM, NULL, t, (int)sizeof t,
                                   &kind, &d), VI_ERR_IO);
  assert_non_null(strstr(d.message, "FIFO"));
  unlink(part);
  /* /dev/full: the loss is reported at close */
  assert_int_equal(vi_output_check("/dev/full", VI_OUTPUT_STREAM, NULL, t,
                                   (int)sizeof t, &kind, &d), VI_OK);
  assert_int_equal(vi_output_open(t, kind, &f, &d), VI_OK);
  fputs("lost", f);
  assert_int_equal(vi_output_close(&f, t, kind, &d), VI_ERR_IO);
  assert_null(f);
  unlink(b);
  unlink(a);
  assert_int_equal(rmdir(dir), 0);
}

/* A free body (K = 0, a rigid-body mode, omega_1 = 0: the bouncing ball)
 * is set up like any model and written like any other. */
static void test_free_body(void **state)
{
  (void)state;
  vi_model *m = NULL;
  double M = 1.0, K = 0.0, w = 1.0;
  assert_int_equal(vi_model_create(1, &m), VI_OK);
  assert_int_equal(vi_model_set_mass(m, &M, 1), VI_OK);
  assert_int_equal(vi_model_set_stiffness(m, &K, 1), VI_OK);
  assert_int_equal(vi_model_set_stop(m, &w, 0.0, 0.8), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  assert_true(vi_model_omega_bound(m) == 0.0); /* the old "set up" test */
  char path[] = "/tmp/vi_free_XXXXXX";
  vi_test_temp_file(path);
  vi_writer *wr = NULL;
  vi_diag d;
  assert_int_equal(vi_writer_create(path, m, 0, &wr, &d), VI_OK);
  assert_int_equal(vi_writer_write_header(wr, NULL, 1e-8, 1e-10, 0), VI_OK);
  double x = 0.5, v = 0.0;
  assert_int_equal(vi_writer_sample(wr, 0.0, &x, &v), VI_OK);
  assert_int_equal(vi_writer_close(&wr, 1), VI_OK);
  struct stat st;
  assert_int_equal(stat(path, &st), 0);
  assert_true(st.st_size > 0);
  remove(path);
  vi_model_destroy(&m);
}

/* What a file must never hold: NaN samples and events, kinds and stops out
 * of range, an orbit that was never sought; each refused with nothing
 * written, and the file still finishes. */
static void test_refused_rows(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  char path[] = "/tmp/vi_rows_XXXXXX";
  vi_test_temp_file(path);
  vi_writer *w = NULL;
  vi_diag d;
  assert_int_equal(vi_writer_create(path, m, 0, &w, &d), VI_OK);
  assert_int_equal(vi_writer_write_header(w, NULL, 1e-8, 1e-10, 0), VI_OK);
  double x[2] = {0.0, 0.1}, v[2] = {0.2, 0.3}, xn[2] = {NAN, 0.0};
  assert_int_equal(vi_writer_sample(w, 1.0, xn, v), VI_ERR_NONFINITE);
  assert_int_equal(vi_writer_sample(w, INFINITY, x, v), VI_ERR_NONFINITE);
  assert_non_null(strstr(vi_writer_errmsg(w), "not finite"));
  vi_event ev = {0};
  ev.n = 2;
  ev.t = 1.0;
  ev.vn = 0.3;
  ev.x = x;
  ev.v_minus = v;
  ev.v_plus = v;
  ev.kind = 7;
  assert_int_equal(vi_writer_event(w, &ev), VI_ERR_ARG);
  ev.kind = VI_EVENT_IMPACT;
  ev.stop = 1; /* Fig. 2 has one stop */
  assert_int_equal(vi_writer_event(w, &ev), VI_ERR_ARG);
  ev.stop = 0;
  ev.vn = NAN;
  assert_int_equal(vi_writer_event(w, &ev), VI_ERR_NONFINITE);
  ev.vn = 0.3;
  assert_int_equal(vi_writer_event(w, &ev), VI_OK);
  assert_int_equal(vi_writer_sample(w, 1.0, x, v), VI_OK);
  vi_orbit *o = NULL;
  assert_int_equal(vi_orbit_create(m, &o), VI_OK);
  int pn = -1, pm = -1;
  assert_int_equal(vi_orbit_classify(o, &pn, &pm), VI_ERR_STATE);
  assert_int_equal(vi_writer_orbit(w, o), VI_ERR_STATE);
  assert_non_null(strstr(vi_writer_errmsg(w), "never"));
  vi_orbit_destroy(&o);
  assert_int_equal(vi_writer_rows(w, "impacts"), 1);
  assert_int_equal(vi_writer_rows(w, "trajectory"), 1);
  assert_int_equal(vi_writer_close(&w, 1), VI_OK);
  remove(path);
  vi_model_destroy(&m);
}

static int attr_int_of(hid_t obj, const char *name)
{
  int v = -1;
  hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
  assert_true(a >= 0);
  assert_true(H5Aread(a, H5T_NATIVE_INT, &v) >= 0);
  H5Aclose(a);
  return v;
}

static int *read_ints(hid_t f, const char *name, size_t count)
{
  return read_as(f, name, H5T_NATIVE_INT, sizeof(int), count);
}

/* A finite-element scene (the shipped 100-element beam, 200 dofs, 4
 * modes): /fe holds its M and K as CSC arrays equal to the reduction's own
 * (read from the same files), /fe/Psi [200][4] only because it is asked
 * for, and the shapes read back are mass-normalised against the M read
 * back: Psi^T M Psi = I to 1e-12.  The file stays small (the dense M, K
 * and Psi would be 640 kB; the whole file is asserted below 150 kB). */
static void test_fe_round_trip(void **state)
{
  (void)state;
  char path[] = "/tmp/vi_test_writer_fe_XXXXXX";
  vi_test_temp_file(path);
  vi_scene *sc = NULL;
  vi_model *m = NULL;
  vi_writer *w = NULL;
  vi_fe *fe = NULL;
  vi_diag d;
  assert_int_equal(vi_scene_load(VI_SCENE_DIR "/beam_fe.yaml", &sc, &d), VI_OK);
  assert_int_equal(vi_scene_create_model(sc, &m, &d), VI_OK);
  assert_int_equal(vi_writer_create(path, m, 1, &w, &d), VI_OK);
  assert_int_equal(vi_writer_write_header(w, sc, 1e-8, 1e-10, VI_METHOD_EXACT), VI_OK);
  assert_int_equal(vi_scene_create_fe(sc, 0, 1, &fe, &d), VI_OK);
  assert_int_equal(vi_writer_fe_shapes(w, fe), VI_OK);
  assert_int_equal(vi_writer_close(&w, 1), VI_OK);
  struct stat stt;
  assert_int_equal(stat(path, &stt), 0);
  print_message("FE beam file: %lld bytes\n", (long long)stt.st_size);
  assert_true(stt.st_size < 150000);
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  hid_t g = H5Gopen2(f, "fe", H5P_DEFAULT);
  assert_int_equal(attr_int_of(g, "dofs"), 200);
  assert_int_equal(attr_int_of(g, "modes"), 4);
  H5Gclose(g);
  const char *names[2] = {"fe/M", "fe/K"};
  const int which[2] = {VI_FE_MASS, VI_FE_STIFFNESS};
  int n = 200, *cpM = NULL, *riM = NULL;
  double *vM = NULL;
  for (int q = 0; q < 2; q++) {
    char key[64];
    g = H5Gopen2(f, names[q], H5P_DEFAULT);
    assert_int_equal(attr_int_of(g, "rows"), n);
    int nnz = attr_int_of(g, "nnz"), fnnz;
    assert_int_equal(attr_int_of(g, "index_base"), 0);
    H5Gclose(g);
    const int *cp, *ri;
    const double *v;
    assert_int_equal(vi_fe_matrix_csc(fe, which[q], &fnnz, &cp, &ri, &v), VI_OK);
    assert_int_equal(nnz, fnnz);
    snprintf(key, sizeof key, "%s/colptr", names[q]);
    int *rcp = read_ints(f, key, (size_t)n + 1);
    snprintf(key, sizeof key, "%s/rowind", names[q]);
    int *rri = read_ints(f, key, (size_t)nnz);
    snprintf(key, sizeof key, "%s/values", names[q]);
    double *rv = read_all(f, key, (size_t)nnz);
    assert_memory_equal(rcp, cp, sizeof(int) * ((size_t)n + 1));
    assert_memory_equal(rri, ri, sizeof(int) * (size_t)nnz);
    assert_memory_equal(rv, v, sizeof(double) * (size_t)nnz);
    if (q == 0) {
      cpM = rcp;
      riM = rri;
      vM = rv;
    } else {
      free(rcp);
      free(rri);
      free(rv);
    }
  }
  int rank;
  hsize_t cols;
  assert_int_equal(rows(f, "fe/Psi", &rank, &cols), (hsize_t)n);
  assert_int_equal(cols, 4);
  double *P = read_all(f, "fe/Psi", (size_t)n * 4); /* [i][j]: C order */
  double emax = 0;
  for (int a = 0; a < 4; a++)
    for (int b = 0; b < 4; b++) {
      double sum = 0; /* psi_a^T M psi_b, M from its lower triangle */
      for (int j = 0; j < n; j++)
        for (int k = cpM[j]; k < cpM[j + 1]; k++) {
          int i = riM[k];
          sum += P[i * 4 + a] * vM[k] * P[j * 4 + b];
          if (i != j) sum += P[j * 4 + a] * vM[k] * P[i * 4 + b];
        }
      emax = fmax(emax, fabs(sum - (a == b)));
    }
  print_message("Psi^T M Psi - I read back: %.2g\n", emax);
  assert_true(emax < 1e-12);
  double *om = read_all(f, "fe/omega", 4);
  for (int j = 0; j < 4; j++) assert_true(om[j] == vi_fe_omega(fe)[j]);
  free(om);
  free(P);
  free(cpM);
  free(riM);
  free(vM);
  H5Fclose(f);
  assert_int_equal(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0);
  remove(path);
  vi_fe_destroy(&fe);
  vi_model_destroy(&m);
  vi_scene_destroy(&sc);
}

/* An FE scene from coordinate files (node, dof, node, dof, value): /fe
 * names each file's format and holds the dof numbering, dof_node and
 * dof_component [n], the pairs sorted by node then dof. */
static void test_fe_coordinate(void **state)
{
  (void)state;
  char dir[] = "/tmp/vi_test_writer_co_XXXXXX", path[] =
      "/tmp/vi_test_writer_coh5_XXXXXX", pm[96], pk[96], text[512];
  assert_non_null(mkdtemp(dir));
  vi_test_temp_file(path);
  snprintf(pm, sizeof pm, "%s/M.txt", dir);
  snprintf(pk, sizeof pk, "%s/K.txt", dir);
  FILE *f = fopen(pm, "w");
  assert_non_null(f);
  fputs("12, 3, 12, 3, 2.0\n-1, 1, -1, 1, 1.0\n", f);
  fclose(f);
  assert_non_null(f = fopen(pk, "w"));
  fputs("12, 3, 12, 3, 5.0\n-1, 1, 12, 3, -1.0\n-1, 1, -1, 1, 3.0\n", f);
  fclose(f);
  snprintf(text, sizeof text, "model:\n  matrices: {M: %s, K: %s}\n  "
           "modes: 2\nstop: {dof: 2, xs: 0.1, r: 0.8}\nrun: {t_end: 1}\n",
           pm, pk);
  vi_scene *sc = NULL;
  vi_model *m = NULL;
  vi_writer *w = NULL;
  vi_diag d;
  assert_int_equal(vi_scene_parse(text, -1, "co.yaml", &sc, &d), VI_OK);
  assert_int_equal(vi_scene_create_model(sc, &m, &d), VI_OK);
  assert_int_equal(vi_writer_create(path, m, 1, &w, &d), VI_OK);
  assert_int_equal(vi_writer_write_header(w, sc, 1e-8, 1e-10,
                                          VI_METHOD_EXACT), VI_OK);
  assert_int_equal(vi_writer_close(&w, 1), VI_OK);
  hid_t h = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(h >= 0);
  int *node = read_ints(h, "fe/dof_node", 2),
      *dof = read_ints(h, "fe/dof_component", 2);
  assert_true(node[0] == -1 && dof[0] == 1 && node[1] == 12 && dof[1] == 3);
  hid_t g = H5Gopen2(h, "fe", H5P_DEFAULT);
  char fmt[32] = "";
  hid_t a = H5Aopen(g, "K_format", H5P_DEFAULT), t = H5Aget_type(a);
  assert_true(H5Tget_size(t) < sizeof fmt);
  assert_true(H5Aread(a, t, fmt) >= 0);
  assert_string_equal(fmt, "coordinate");
  H5Tclose(t);
  H5Aclose(a);
  H5Gclose(g);
  /* K's lower triangle in that numbering: (1,1) 3, (2,1) -1, (2,2) 5 */
  double *v = read_all(h, "fe/K/values", 3);
  assert_true(v[0] == 3.0 && v[1] == -1.0 && v[2] == 5.0);
  free(v);
  free(node);
  free(dof);
  H5Fclose(h);
  remove(path);
  remove(pm);
  remove(pk);
  rmdir(dir);
  vi_model_destroy(&m);
  vi_scene_destroy(&sc);
}

int main(void)
{
  gsl_set_error_handler_off();
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_fig2_round_trip),
      cmocka_unit_test(test_stops_round_trip),
      cmocka_unit_test(test_unwritable_and_abort),
      cmocka_unit_test(test_misuse),
      cmocka_unit_test(test_free_body),
      cmocka_unit_test(test_refused_rows),
      cmocka_unit_test(test_output_module),
      cmocka_unit_test(test_rank_and_size),
      cmocka_unit_test(test_large_scene_text),
      cmocka_unit_test(test_fe_round_trip),
      cmocka_unit_test(test_fe_coordinate),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
