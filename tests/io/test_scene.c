/* test_scene.c - scene files: every scene in share/scenes runs; malformed
 * scenes are reported with their code, line and key. */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include <gsl/gsl_sf_ellint.h>

#include "vi_testutil.h"
#include "vibroimpact/vi_scene.h"

static void test_shipped_scenes_run(void **state)
{
  (void)state;
  DIR *dir = opendir(VI_SCENE_DIR);
  assert_non_null(dir);
  struct dirent *e;
  int count = 0;
  while ((e = readdir(dir))) {
    size_t len = strlen(e->d_name);
    if (len < 6 || strcmp(e->d_name + len - 5, ".yaml") != 0) continue;
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", VI_SCENE_DIR, e->d_name);
    vi_scene *sc = NULL;
    vi_model *m = NULL;
    vi_sim *s = NULL;
    vi_diag d;
    int st = vi_scene_load(path, &sc, &d);
    if (st) print_error("%s: %s\n", path, d.message);
    assert_int_equal(st, VI_OK);
    /* short: 5 forcing periods; a free-motion scene keeps its t_end */
    st = vi_scene_set_run(sc, 0, 0, 5, -1);
    assert_true(st == VI_OK || st == VI_ERR_FREQUENCY);
    assert_int_equal(vi_scene_create_model(sc, &m, &d), VI_OK);
    assert_int_equal(vi_model_n(m), vi_scene_n(sc));
    assert_int_equal(vi_sim_create(m, &s), VI_OK);
    assert_int_equal(vi_scene_configure_sim(sc, s, &d), VI_OK);
    if (vi_scene_outputs(sc) & VI_SCENE_OUT_LEDGER) assert_int_equal(vi_sim_enable_ledger(s, 1), VI_OK);
    st = vi_sim_run(s, vi_scene_t_end(sc));
    if (st) print_error("%s: %s\n", path, vi_sim_errmsg(s));
    assert_int_equal(st, VI_OK);
    if (vi_scene_outputs(sc) & VI_SCENE_OUT_LEDGER) assert_true(vi_sim_ledger_max_residual(s) < 1e-6);
    print_message("%-22s n = %d, %lld impacts in 5 periods\n", e->d_name,
                  vi_model_n(m), (long long)vi_sim_stat(s, VI_STAT_IMPACTS));
    vi_sim_destroy(&s);
    vi_model_destroy(&m);
    vi_scene_destroy(&sc);
    count++;
  }
  closedir(dir);
  assert_true(count >= 6);
}

/* The embedded default is share/scenes/fig2.yaml, byte for byte. */
static void test_default_is_fig2(void **state)
{
  (void)state;
  vi_scene *sc = NULL;
  vi_diag d;
  assert_int_equal(vi_scene_load(VI_SCENE_DIR "/fig2.yaml", &sc, &d), VI_OK);
  assert_string_equal(vi_scene_text(sc), vi_scene_default_text());
  assert_close(vi_scene_t_end(sc), 100 * 2 * M_PI / 0.9, 1e-12);
  vi_scene_destroy(&sc);
}

#include "vi_bad_scenes.h"

static void test_malformed_scenes(void **state)
{
  (void)state;
  size_t nc = sizeof cases / sizeof cases[0];
  assert_true(nc >= 15);
  for (size_t i = 0; i < nc; i++) {
    const bad *b = &cases[i];
    vi_scene *sc = NULL;
    vi_model *m = NULL;
    vi_sim *s = NULL;
    vi_diag d;
    int st = vi_scene_parse(b->text, -1, "bad.yaml", &sc, &d);
    if (!st) st = vi_scene_create_model(sc, &m, &d);
    if (!st) {
      assert_int_equal(vi_sim_create(m, &s), VI_OK);
      st = vi_scene_configure_sim(sc, s, &d);
    }
    char msg[1200];
    vi_diag_format(&d, msg, sizeof msg);
    print_message("%-30s -> %s\n", b->what, msg);
    assert_int_equal(st, b->code);
    assert_int_equal(d.code, b->code);
    assert_string_equal(d.file, "bad.yaml");
    assert_int_equal(d.line, b->line);
    assert_string_equal(d.key, b->key);
    assert_true(strlen(d.message) > 5);
    vi_sim_destroy(&s);
    vi_model_destroy(&m);
    vi_scene_destroy(&sc);
    assert_null(sc);
  }
  /* a lumped M with a massless dof: the dof named, and where such a
   * model is taken (its files, condensed by the FE reduction) */
  vi_scene *sc = NULL;
  vi_model *m = NULL;
  vi_diag d;
  assert_int_equal(vi_scene_parse("model:\n  M: [[1, 0], [0, 0]]\n  K: [[2, -1], [-1, 1]]\n"
                                  "stop: {w: [0, 1], xs: 0.1, r: 0.7}\nrun: {t_end: 10}\n", -1,
                                  "lumped.yaml", &sc, &d), VI_OK);
  assert_int_equal(vi_scene_create_model(sc, &m, &d), VI_ERR_NOT_SPD);
  assert_null(m);
  assert_int_equal(d.line, 2);
  assert_non_null(strstr(d.message, "dof 2 has no mass"));
  assert_non_null(strstr(d.message, "model.matrices"));
  vi_scene_destroy(&sc);
}

/* A scene's built-in springs reach the simulation: the free Duffing
 * oscillator x'' + x + eps x^3 = 0 from rest at A returns to A after the
 * period 4 K(m) / sqrt(1 + eps A^2), m = eps A^2 / (2 (1 + eps A^2)). */
static void test_scene_springs(void **state)
{
  (void)state;
  const char *t = "model: {M: [[1.0]], K: [[1.0]]}\n"
                  "stop: {mass: 1, xs: 10.0, r: 0.8}\n"
                  "springs:\n  - {type: cubic, i: 1, k3: 0.8}\n"
                  "initial: {x: [1.3]}\n"
                  "run: {t_end: 100, rtol: 1.0e-11, atol: 1.0e-13}\n";
  double eps = 0.8, A = 1.3, w2 = 1 + eps * A * A, mm = eps * A * A / (2 * w2);
  double T = 4 * gsl_sf_ellint_Kcomp(sqrt(mm), GSL_PREC_DOUBLE) / sqrt(w2);
  vi_scene *sc = NULL;
  vi_model *m = NULL;
  vi_sim *s = NULL;
  vi_diag d;
  assert_int_equal(vi_scene_parse(t, -1, "duffing.yaml", &sc, &d), VI_OK);
  assert_int_equal(vi_scene_create_model(sc, &m, &d), VI_OK);
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_scene_configure_sim(sc, s, &d), VI_OK);
  assert_int_equal(vi_scene_configure_sim(sc, s, &d), VI_OK); /* idempotent */
  assert_int_equal(vi_sim_run(s, 3 * T), VI_OK);
  double x, v;
  vi_sim_state(s, NULL, &x, &v);
  assert_close(x, A, 1e-8);
  assert_close(v, 0.0, 1e-8);
  assert_int_equal(vi_sim_method_used(s), VI_METHOD_ADAMS);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
  vi_scene_destroy(&sc);
}

/* stops: a two-sided clearance from a scene: a free particle between walls
 * at +-0.5 (w = 1 at 0.5, w = -1 at 0.5, r = 1) from x = 0 at speed 1.3
 * hits them alternately every 2 x_s / v = 1 / 1.3, the first at 0.5 / 1.3;
 * the events name the stop, in list order. */
typedef struct wall_hits {
  int count, bad_stop;
  double et;
} wall_hits;

static int on_wall(const vi_event *ev, void *user)
{
  wall_hits *h = user;
  double t = (0.5 + h->count) / 1.3;
  h->et = fmax(h->et, fabs(ev->t - t));
  h->bad_stop += ev->stop != h->count % 2;
  h->count++;
  return 0;
}

static void test_scene_stops(void **state)
{
  (void)state;
  const char *t = "model: {M: [[1.0]], K: [[0.0]]}\n"
                  "stops:\n"
                  "  - {mass: 1, xs: 0.5, r: 1.0}\n"
                  "  - {w: [-1.0], xs: 0.5, r: 1.0}\n"
                  "initial: {v: [1.3]}\n"
                  "run: {t_end: 20, rtol: 1.0e-10, atol: 1.0e-12}\n";
  vi_scene *sc = NULL;
  vi_model *m = NULL;
  vi_sim *s = NULL;
  vi_diag d;
  assert_int_equal(vi_scene_parse(t, -1, "walls.yaml", &sc, &d), VI_OK);
  assert_int_equal(vi_scene_create_model(sc, &m, &d), VI_OK);
  assert_int_equal(vi_model_num_stops(m), 2);
  double w, xs, r;
  assert_int_equal(vi_model_stop(m, 1, &w, &xs, &r), VI_OK);
  assert_true(w == -1.0 && xs == 0.5 && r == 1.0);
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_scene_configure_sim(sc, s, &d), VI_OK);
  wall_hits h = {0, 0, 0.0};
  assert_int_equal(vi_sim_set_event_callback(s, on_wall, &h, NULL), VI_OK);
  assert_int_equal(vi_sim_run(s, vi_scene_t_end(sc)), VI_OK);
  print_message("walls from a scene: %d impacts, times within %.3g\n",
                h.count, h.et);
  assert_int_equal(h.count, 26); /* (0.5 + j) / 1.3 < 20: j = 0 .. 25 */
  assert_int_equal(h.bad_stop, 0);
  assert_true(h.et < 1e-10);
  /* method auto runs the closed form on several stops, and exact is
   * accepted */
  assert_int_equal(vi_sim_method_used(s), VI_METHOD_EXACT);
  vi_sim_destroy(&s);
  vi_scene_destroy(&sc);
  const char *te = "model: {M: [[1.0]], K: [[0.0]]}\n"
                   "stops:\n"
                   "  - {mass: 1, xs: 0.5, r: 1.0}\n"
                   "  - {w: [-1.0], xs: 0.5, r: 1.0}\n"
                   "run: {t_end: 20, method: exact}\n";
  assert_int_equal(vi_scene_parse(te, -1, "walls.yaml", &sc, &d), VI_OK);
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_scene_configure_sim(sc, s, &d), VI_OK);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
  vi_scene_destroy(&sc);
}

/* Conveniences for big models: a stop named by its coordinate and
 * direction, a scalar initial state for every coordinate, no forcing.
 * A free oscillator x'' + x = 0 from x = 0 at v = -1 moves as x = -sin t;
 * the stop {dof: 1, direction: -1, xs: 0.5} is -x <= 0.5, reached first at
 * t = pi/6 with approach velocity -x' = cos(pi/6) (r = 1: the rebound is
 * the mirror image, next contact 2 pi later). */
typedef struct first_hit {
  int count;
  double t, vn;
} first_hit;

static int on_first(const vi_event *ev, void *user)
{
  first_hit *h = user;
  if (ev->kind == VI_EVENT_IMPACT && h->count++ == 0) {
    h->t = ev->t;
    h->vn = ev->vn;
  }
  return 0;
}

static void test_scene_conveniences(void **state)
{
  (void)state;
  const char *t = "model: {M: [[1.0]], K: [[1.0]]}\n"
                  "stop: {dof: 1, direction: -1, xs: 0.5, r: 1.0}\n"
                  "initial: {v: -1.0}\n"
                  "run: {t_end: 3, rtol: 1.0e-11, atol: 1.0e-13}\n";
  vi_scene *sc = NULL;
  vi_model *m = NULL;
  vi_sim *s = NULL;
  vi_diag d;
  assert_int_equal(vi_scene_parse(t, -1, "free.yaml", &sc, &d), VI_OK);
  assert_int_equal(vi_scene_create_model(sc, &m, &d), VI_OK);
  assert_close(vi_model_stop_vector(m)[0], -1.0, 0);
  assert_close(vi_model_omega_forcing(m), 0.0, 0);
  assert_close(vi_model_forcing_cos(m)[0], 0.0, 0);
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_scene_configure_sim(sc, s, &d), VI_OK);
  first_hit h = {0, 0, 0};
  assert_int_equal(vi_sim_set_event_callback(s, on_first, &h, NULL), VI_OK);
  assert_int_equal(vi_sim_run(s, vi_scene_t_end(sc)), VI_OK);
  print_message("stop {dof: 1, direction: -1}: first contact t = %.15g "
                "(pi/6 = %.15g), v_n = %.15g\n", h.t, M_PI / 6, h.vn);
  assert_int_equal(h.count, 1);
  assert_close(h.t, M_PI / 6, 1e-9);
  assert_close(h.vn, cos(M_PI / 6), 1e-9);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
  vi_scene_destroy(&sc);
  /* a 3-mass chain: scalars broadcast to every coordinate, `mass` is a
   * synonym of `dof` (direction +1 by default), stops: takes the form */
  t = "model:\n  chain: {n: 3, m: 1, k: 1}\n"
      "stops:\n  - {dof: 3, xs: 0.2, r: 0.8}\n"
      "  - {mass: 1, direction: -1, xs: 0.3, r: 0.7}\n"
      "  - {dof: 2, direction: +1, xs: 0.4, r: 0.6}\n"
      "initial: {x: 0.01, v: [0.1, 0.2, 0.3]}\n"
      "run: {t_end: 1}\n";
  assert_int_equal(vi_scene_parse(t, -1, "chain.yaml", &sc, &d), VI_OK);
  assert_int_equal(vi_scene_create_model(sc, &m, &d), VI_OK);
  assert_int_equal(vi_model_num_stops(m), 3);
  const double want[3][3] = {{0, 0, 1}, {-1, 0, 0}, {0, 1, 0}};
  const double wxs[3] = {0.2, 0.3, 0.4}, wr[3] = {0.8, 0.7, 0.6};
  for (int k = 0; k < 3; k++) {
    double w[3], xs, r;
    assert_int_equal(vi_model_stop(m, k, w, &xs, &r), VI_OK);
    for (int i = 0; i < 3; i++) assert_close(w[i], want[k][i], 0);
    assert_close(xs, wxs[k], 0);
    assert_close(r, wr[k], 0);
  }
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_scene_configure_sim(sc, s, &d), VI_OK);
  double x[3], v[3];
  assert_int_equal(vi_sim_state(s, NULL, x, v), VI_OK);
  const double v0[3] = {0.1, 0.2, 0.3}; /* as read: exact */
  for (int i = 0; i < 3; i++) {
    assert_close(x[i], 0.01, 0);
    assert_close(v[i], v0[i], 0);
  }
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
  vi_scene_destroy(&sc);
  /* forcing on coordinates of any model: a cantilever's modal coordinate */
  t = "model:\n  cantilever: {modes: 3, omega1: 2}\n"
      "forcing: {omega: 1.5, on: [2], amplitude: 0.25}\n"
      "stop: {xs: 0.01, r: 0.75}\n";
  assert_int_equal(vi_scene_parse(t, -1, "beam.yaml", &sc, &d), VI_OK);
  assert_int_equal(vi_scene_create_model(sc, &m, &d), VI_OK);
  const double *a = vi_model_forcing_cos(m);
  assert_true(a[0] == 0 && a[1] == 0.25 && a[2] == 0);
  vi_model_destroy(&m);
  vi_scene_destroy(&sc);
}

static void test_overrides_and_builders(void **state)
{
  (void)state;
  /* Rayleigh damping on a chain, forcing by index and amplitude */
  const char *t = "model:\n  chain: {n: 3, m: [1, 2, 3], k: 4}\n"
                  "  rayleigh: {alpha: 0.01, beta: 0.02}\n"
                  "forcing: {omega: 2, on: [1, 3], amplitude: 0.5}\n"
                  "stop: {mass: 3, xs: 0.2, r: 0.9}\n";
  vi_scene *sc = NULL;
  vi_model *m = NULL;
  vi_diag d;
  assert_int_equal(vi_scene_parse(t, -1, "x", &sc, &d), VI_OK);
  assert_int_equal(vi_scene_create_model(sc, &m, &d), VI_OK);
  const double *M = vi_model_mass(m), *C = vi_model_damping(m), *K = vi_model_stiffness(m);
  assert_close(M[4], 2.0, 0);
  assert_close(K[0], 8.0, 0);  /* k1 + k2 */
  assert_close(C[0], 0.01 * 1 + 0.02 * 8, 1e-15);
  assert_int_equal(vi_model_is_proportional(m), 1);
  assert_close(vi_model_forcing_cos(m)[0], 0.5, 0);
  assert_close(vi_model_forcing_cos(m)[1], 0.0, 0);
  assert_close(vi_model_forcing_cos(m)[2], 0.5, 0);
  assert_close(vi_scene_t_end(sc), 100 * M_PI, 1e-12); /* default 100 periods */
  assert_int_equal(vi_scene_set_run(sc, 1e-9, 1e-11, 7, VI_METHOD_EXACT), VI_OK);
  assert_close(vi_scene_t_end(sc), 7 * M_PI, 1e-12);
  assert_int_equal(vi_scene_method(sc), VI_METHOD_EXACT);
  vi_model_destroy(&m);
  vi_scene_destroy(&sc);
  /* the cantilever's base excitation is -A gamma; its stop the tip shapes */
  t = "model:\n  cantilever: {modes: 2, omega1: 3}\nforcing: {omega: 2.5, base: 0.1}\n"
      "stop: {xs: 0.01, r: 0.75}\n";
  assert_int_equal(vi_scene_parse(t, -1, "x", &sc, &d), VI_OK);
  assert_int_equal(vi_scene_create_model(sc, &m, &d), VI_OK);
  assert_close(vi_model_forcing_cos(m)[0], -0.1 * vi_cantilever_participation(0), 1e-15);
  assert_close(fabs(vi_model_stop_vector(m)[1]), 2.0, 1e-10);
  assert_close(vi_model_omega(m)[0], 3.0, 1e-12);
  vi_model_destroy(&m);
  vi_scene_destroy(&sc);
}

/* Every io function of the scene reader with NULL, zero, negative and
 * mismatched arguments: a code, never a crash or a read out of bounds
 * (run under ASan/UBSan in the sanitizer build). */
static void test_misuse(void **state)
{
  (void)state;
  vi_scene *sc = NULL, *sc3 = NULL;
  vi_model *m = NULL;
  vi_sim *s = NULL;
  vi_diag d;
  char buf[64];
  assert_int_equal(vi_scene_parse(NULL, -1, "x", &sc, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_parse("a: 1", -1, "x", NULL, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_parse("", 0, NULL, &sc, NULL), VI_ERR_PARSE);
  assert_null(sc);
  assert_int_equal(vi_scene_parse_limited("a: [[1]]", -1, "x", 2, &sc, &d), VI_ERR_LIMIT);
  assert_int_equal(vi_scene_load(NULL, &sc, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_load("x.yaml", NULL, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_load("/nonexistent/x.yaml", &sc, NULL), VI_ERR_IO);
  assert_int_equal(vi_scene_load_limited(VI_SCENE_DIR "/fig2.yaml", 10, 0, &sc, &d),
                   VI_ERR_LIMIT);
  assert_non_null(strstr(d.message, "larger than 10 bytes"));
  assert_int_equal(vi_scene_load_limited(VI_SCENE_DIR "/fig2.yaml", -5, -5, &sc, &d),
                   VI_OK); /* <= 0: the defaults */
  vi_scene_destroy(&sc);
  vi_scene_destroy(&sc);
  vi_scene_destroy(NULL);
  /* getters on NULL */
  assert_string_equal(vi_scene_name(NULL), "");
  assert_string_equal(vi_scene_text(NULL), "");
  assert_int_equal(vi_scene_n(NULL), 0);
  assert_true(vi_scene_t0(NULL) == 0 && vi_scene_t_end(NULL) == 0);
  assert_true(vi_scene_rtol(NULL) == 0 && vi_scene_atol(NULL) == 0);
  assert_int_equal(vi_scene_method(NULL), 0);
  assert_int_equal(vi_scene_samples_per_period(NULL), 0);
  assert_int_equal(vi_scene_outputs(NULL), 0);
  assert_true(vi_scene_memory_estimate(NULL) == 0);
  assert_int_equal(vi_scene_check_memory(NULL, 0, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_set_run(NULL, 0, 0, 0, -1), VI_ERR_ARG);
  assert_int_equal(vi_scene_create_model(NULL, &m, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_configure_sim(NULL, NULL, &d), VI_ERR_ARG);
  vi_diag_format(NULL, buf, sizeof buf);
  assert_string_equal(buf, "");
  vi_diag_format(&d, NULL, 10);
  vi_diag_format(&d, buf, 0);
  vi_diag_format(&d, buf, -3);
  /* a valid scene with bad overrides */
  assert_int_equal(vi_scene_parse(vi_scene_default_text(), -1, "fig2", &sc, &d), VI_OK);
  assert_int_equal(vi_scene_set_run(sc, NAN, 0, 0, -1), VI_ERR_ARG);
  assert_int_equal(vi_scene_set_run(sc, 0, 0, INFINITY, -1), VI_ERR_ARG);
  assert_int_equal(vi_scene_set_run(sc, 0, 0, 0, 99), VI_ERR_ARG);
  assert_int_equal(vi_scene_set_run(sc, 10, 0, 0, -1), VI_ERR_TOLERANCE);
  assert_int_equal(vi_scene_set_run(sc, 1e-17, 0, 0, -1), VI_ERR_TOLERANCE);
  assert_int_equal(vi_scene_set_run(sc, 0, INFINITY, 0, -1), VI_ERR_TOLERANCE);
  assert_int_equal(vi_scene_set_run(sc, -1, -1, -1, -1), VI_OK); /* keep all */
  assert_close(vi_scene_rtol(sc), 1e-8, 0);
  assert_int_equal(vi_scene_create_model(sc, NULL, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_check_memory(sc, 1.0, &d), VI_ERR_LIMIT);
  assert_string_equal(d.key, "model.chain.n");
  assert_int_equal(vi_scene_check_memory(sc, 1e12, NULL), VI_OK);
  /* a budget while loading: Fig. 2's 7 vectors of n = 2 doubles are 112
   * bytes, refused by a budget of 111 before they are allocated, at the
   * key that gives n, and allowed by 112 */
  vi_scene *sw = NULL;
  assert_int_equal(vi_scene_load_within(VI_SCENE_DIR "/fig2.yaml", 0, 0, 111.0,
                                        &sw, &d), VI_ERR_LIMIT);
  assert_null(sw);
  assert_int_equal(d.line, 8);
  assert_string_equal(d.key, "model.chain.n");
  assert_string_equal(d.value, "2");
  assert_non_null(strstr(d.message, "vectors of 2 dofs alone would need 0.000107 MB"));
  assert_non_null(strstr(d.message, "than the 0.000106 MB allowed"));
  assert_int_equal(vi_scene_load_within(VI_SCENE_DIR "/fig2.yaml", 0, 0, 112.0,
                                        &sw, &d), VI_OK);
  assert_int_equal(vi_scene_n(sw), 2);
  vi_scene_destroy(&sw);
  /* a sim of another size: refused, no read past the scene's arrays */
  assert_int_equal(vi_scene_parse("model:\n  chain: {n: 3, m: 1, k: 1}\n"
                                  "stop: {mass: 3, xs: 0.1, r: 0.5}\n"
                                  "run: {t_end: 10}\n", -1, "three", &sc3, &d), VI_OK);
  vi_model *m5 = vi_test_chain(5, 1, 1, 0.1, 0.1, 0.7, 0.9, NULL);
  assert_int_equal(vi_sim_create(m5, &s), VI_OK);
  assert_int_equal(vi_scene_configure_sim(sc3, s, &d), VI_ERR_DIM);
  assert_non_null(strstr(d.message, "n = 3"));
  assert_int_equal(vi_scene_configure_sim(sc3, NULL, &d), VI_ERR_ARG);
  assert_int_equal(vi_scene_configure_sim(sc3, s, NULL), VI_ERR_DIM);
  vi_sim_destroy(&s);
  vi_model_destroy(&m5);
  vi_scene_destroy(&sc3);
  vi_scene_destroy(&sc);
}

/* A long chain that asks for nothing modal is stored in band form: O(n)
 * memory (estimated before, held after), its top frequency bounded by
 * Gershgorin: m = k = 1 gives omega_max = 2 sin(n pi / (2n + 1)) < 2 and the
 * bound sqrt(max row sum |M^-1 K|) = 2.  Asking for the ledger needs the
 * modes: dense storage, and the estimate says 16 n^2 doubles. */
static void test_band_chain_scene(void **state)
{
  (void)state;
  const int n = 4000;
  char text[512];
  const char *tail[2] = {"", ", ledger: true"};
  double est[2];
  vi_scene *sc = NULL;
  vi_diag d;
  for (int k = 0; k < 2; k++) {
    snprintf(text, sizeof text,
             "model:\n  chain: {n: %d, m: 1.0, k: 1.0, c: 0.01}\n"
             "forcing: {omega: 0.5, on: [1], amplitude: 0.3}\n"
             "stop: {mass: %d, xs: 0.05, r: 0.8}\n"
             "run: {periods: 1}\noutput: {impacts: true%s}\n", n, n, tail[k]);
    assert_int_equal(vi_scene_parse(text, -1, "long.yaml", &sc, &d), VI_OK);
    est[k] = vi_scene_memory_estimate(sc);
    if (k == 0) {
      vi_model *m = NULL;
      assert_int_equal(vi_scene_create_model(sc, &m, &d), VI_OK);
      assert_int_equal(vi_model_bandwidth(m), 1);
      assert_null(vi_model_omega(m));
      assert_true((double)vi_model_memory(m) <= 8.0 * 64 * n);
      assert_true((double)vi_model_memory(m) <= est[0]);
      double wmax = 2.0 * sin(n * M_PI / (2.0 * n + 1.0));
      assert_true(vi_model_omega_bound(m) >= wmax);
      assert_true(vi_model_omega_bound(m) <= 2.0 * (1 + 1e-12));
      vi_model_destroy(&m);
      assert_int_equal(vi_scene_check_memory(sc, 100e6, &d), VI_OK);
    } else {
      assert_int_equal(vi_scene_check_memory(sc, 100e6, &d), VI_ERR_LIMIT);
      assert_string_equal(d.key, "model.chain.n");
    }
    vi_scene_destroy(&sc);
  }
  assert_true(est[0] < 8.0 * 1000 * n);      /* O(n) */
  assert_true(est[1] > 8.0 * 14 * n * n);    /* dense, with its modes */
}

/* Text is not a number: quoted or !!str-tagged scalars; aliases resolve
 * only to complete nodes; a second document is refused. */
static void test_yaml_strictness(void **state)
{
  (void)state;
  static const struct { const char *text, *key; int code; } c[] = {
    {CHAIN GOOD_STOP "forcing: {omega: \"0.9\"}\n", "forcing.omega", VI_ERR_PARSE},
    {CHAIN GOOD_STOP "forcing: {omega: !!str 0.9}\n", "forcing.omega", VI_ERR_PARSE},
    {CHAIN GOOD_STOP "forcing: {omega: !!float 0.9}\nrun: {periods: 1}\n", "", VI_OK},
    {CHAIN GOOD_STOP "forcing: {omega: 0.9}\n---\n", "", VI_ERR_PARSE},
    {CHAIN GOOD_STOP "forcing: &f {omega: 0.9, a: *f}\n", "", VI_ERR_PARSE},
    {CHAIN GOOD_STOP "forcing: {omega: 0.9, a: &v [0.5, 0], b: *v}\nrun: {periods: 1}\n", "", VI_OK},
    {"name: {a: 1}\n" CHAIN GOOD_STOP, "name", VI_ERR_PARSE},
  };
  for (size_t k = 0; k < sizeof c / sizeof c[0]; k++) {
    vi_scene *sc = NULL;
    vi_diag d;
    int st = vi_scene_parse(c[k].text, -1, "strict", &sc, &d);
    if (st != c[k].code) print_error("case %zu: %s\n", k, d.message);
    assert_int_equal(st, c[k].code);
    if (st) assert_string_equal(d.key, c[k].key);
    vi_scene_destroy(&sc);
  }
}

/* output: one typed bit per key, defaults impacts and compress on; a key
 * set to false clears its bit, and a non-boolean is refused at its line. */
static void test_outputs(void **state)
{
  (void)state;
  static const struct { const char *output; int bits; } c[] = {
    {"", VI_SCENE_OUT_IMPACTS | VI_SCENE_OUT_COMPRESS},
    {"output: {ledger: true}\n",
     VI_SCENE_OUT_IMPACTS | VI_SCENE_OUT_LEDGER | VI_SCENE_OUT_COMPRESS},
    {"output: {impacts: false, compress: false, modes: true}\n",
     VI_SCENE_OUT_MODES},
    {"output: {ledger: true, modes: true, impacts: true, compress: true}\n",
     VI_SCENE_OUT_IMPACTS | VI_SCENE_OUT_LEDGER | VI_SCENE_OUT_MODES |
         VI_SCENE_OUT_COMPRESS},
  };
  for (size_t k = 0; k < sizeof c / sizeof c[0]; k++) {
    char text[512];
    snprintf(text, sizeof text, "%s%s%s", CHAIN GOOD_STOP, "run: {t_end: 1}\n",
             c[k].output);
    vi_scene *sc = NULL;
    vi_diag d;
    assert_int_equal(vi_scene_parse(text, -1, "outputs", &sc, &d), VI_OK);
    assert_int_equal(vi_scene_outputs(sc), c[k].bits);
    vi_scene_destroy(&sc);
  }
  vi_scene *sc = NULL;
  vi_diag d;
  assert_int_equal(vi_scene_parse(CHAIN GOOD_STOP "run: {t_end: 1}\n"
                                  "output: {ledger: yes}\n", -1, "outputs",
                                  &sc, &d), VI_ERR_PARSE);
  assert_string_equal(d.key, "output.ledger");
  assert_int_equal(d.line, 5); /* CHAIN 1-2, stop 3, run 4, output 5 */
  assert_null(sc);
}

int main(void)
{
  gsl_set_error_handler_off();
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_shipped_scenes_run),
      cmocka_unit_test(test_default_is_fig2),
      cmocka_unit_test(test_malformed_scenes),
      cmocka_unit_test(test_scene_springs),
      cmocka_unit_test(test_scene_stops),
      cmocka_unit_test(test_scene_conveniences),
      cmocka_unit_test(test_overrides_and_builders),
      cmocka_unit_test(test_misuse),
      cmocka_unit_test(test_yaml_strictness),
      cmocka_unit_test(test_outputs),
      cmocka_unit_test(test_band_chain_scene),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
