/* test_fe_whole.c - an FE scene without model.modes (vi_scene.h): no
 * silent cut.  Siconos' impacting bar (share/scenes/impacting_bar.yaml,
 * 500 dofs) written without `modes` keeps all 500 modes, says so through
 * vi_scene_fe_summary, and releases from the obstacle when the independent
 * reference of the scene's bar does: tests/stress/ref/bar_ref.py (clamped
 * modes from scipy's eigh, the force's zero by brentq) for its geometry,
 * 499 elements of 1/500 m (`import bar_ref; bar_ref.L = 0.998;
 * bar_ref.release(499)`): 0.0008838979363549439 s.  A 6-mode cut, the
 * former default, released 1.4e-5 s early.  A structure above 1000 dofs without model.modes is
 * refused with the key named. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "vi_testutil.h"
#include "vibroimpact/vi_scene.h"

static const double BAR_RELEASE = 0.0008838979363549439;

typedef struct bar_log {
  int releases;
  double t_rel;
} bar_log;

static int on_bar(const vi_event *ev, void *user)
{
  bar_log *b = user;
  if (ev->kind == VI_EVENT_RELEASE && b->releases++ == 0) b->t_rel = ev->t;
  return 0;
}

static void test_bar_whole(void **state)
{
  (void)state;
  char text[1024];
  snprintf(text, sizeof text,
           "name: bar-whole\n"
           "model:\n"
           "  matrix_market: {M: %s/bar_M.mtx, K: %s/bar_K.mtx}\n"
           "stop: {dof: 1, direction: -1, xs: 0.0, r: 0.0}\n"
           "initial: {x: 5.0e-5, v: -0.1}\n"
           "run: {t_end: 0.0015, rtol: 1.0e-9, atol: 1.0e-14}\n",
           VI_SCENE_DIR, VI_SCENE_DIR);
  vi_scene *sc = NULL;
  vi_model *m = NULL;
  vi_diag d;
  assert_int_equal(vi_scene_parse(text, -1, "bar-whole", &sc, &d), VI_OK);
  assert_int_equal(vi_scene_fe_summary(sc, NULL, NULL, NULL, NULL, NULL,
                                       NULL), VI_ERR_STATE);
  assert_int_equal(vi_scene_create_model(sc, &m, &d), VI_OK);
  int k, rule, nz, nr;
  double res, orth;
  assert_int_equal(vi_scene_fe_summary(sc, &k, &rule, &nz, &nr, &res, &orth),
                   VI_OK);
  print_message("bar without model.modes: %d of %d modes, rule %d, %d rigid, "
                "%d massless, residuals <= %.2g, orthonormal to %.2g\n", k,
                vi_scene_dofs(sc), rule, nr, nz, res, orth);
  assert_int_equal(k, 500);
  assert_int_equal(vi_model_n(m), 500);
  assert_int_equal(rule, VI_FE_MODES_WHOLE);
  assert_int_equal(nr, 1); /* the free bar's translation */
  assert_int_equal(nz, 0);
  assert_true(res < 1e-12 && orth < 1e-12);
  vi_sim *s = NULL;
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_scene_configure_sim(sc, s, &d), VI_OK);
  bar_log b = {0, 0.0};
  assert_int_equal(vi_sim_set_event_callback(s, on_bar, &b, NULL), VI_OK);
  assert_int_equal(vi_sim_run(s, vi_scene_t_end(sc)), VI_OK);
  print_message("release %.17g s, reference %.17g s (error %.2g s)\n",
                b.t_rel, BAR_RELEASE, fabs(b.t_rel - BAR_RELEASE));
  assert_true(b.releases >= 1);
  assert_true(fabs(b.t_rel - BAR_RELEASE) < 1e-12);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
  vi_scene_destroy(&sc);
}

/* model.rigid_modes: the free bar has one; a scene that says none is
 * refused, naming the mode K finds rigid. */
static void test_rigid_modes_key(void **state)
{
  (void)state;
  for (int said = 0; said <= 1; said++) {
    char text[1024];
    snprintf(text, sizeof text,
             "model:\n"
             "  matrix_market: {M: %s/bar_M.mtx, K: %s/bar_K.mtx}\n"
             "  modes: 10\n"
             "  rigid_modes: %d\n"
             "stop: {dof: 1, direction: -1, xs: 0.0, r: 0.0}\n"
             "run: {t_end: 0.0015}\n",
             VI_SCENE_DIR, VI_SCENE_DIR, said);
    vi_scene *sc = NULL;
    vi_model *m = NULL;
    vi_diag d;
    assert_int_equal(vi_scene_parse(text, -1, "bar-rigid", &sc, &d), VI_OK);
    int st = vi_scene_create_model(sc, &m, &d);
    if (said == 1) {
      assert_int_equal(st, VI_OK);
    } else {
      char msg[1200];
      vi_diag_format(&d, msg, sizeof msg);
      print_message("rigid_modes: 0 on the free bar: %s\n", msg);
      assert_int_equal(st, VI_ERR_ARG);
      assert_non_null(strstr(d.message, "mode 1"));
    }
    vi_model_destroy(&m);
    vi_scene_destroy(&sc);
  }
}

/* A 1001-dof chain in Matrix Market files without model.modes: refused at
 * the scene, naming the key and the way out. */
static void test_large_without_modes(void **state)
{
  (void)state;
  char dir[64], path[160];
  snprintf(dir, sizeof dir, "fe_whole_%ld", (long)getpid());
  assert_int_equal(mkdir(dir, 0700), 0);
  const int n = 1001;
  for (int w = 0; w < 2; w++) {
    snprintf(path, sizeof path, "%s/%s.mtx", dir, w ? "K" : "M");
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fprintf(f, "%%%%MatrixMarket matrix coordinate real symmetric\n%d %d %d\n",
            n, n, w ? 2 * n - 1 : n);
    for (int j = 1; j <= n; j++) {
      fprintf(f, "%d %d %g\n", j, j, w ? (j < n ? 2.0 : 1.0) : 1.0);
      if (w && j < n) fprintf(f, "%d %d -1\n", j + 1, j);
    }
    assert_int_equal(fclose(f), 0);
  }
  char text[512];
  snprintf(text, sizeof text,
           "model:\n  matrix_market: {M: %s/M.mtx, K: %s/K.mtx}\n"
           "stop: {dof: %d, xs: 0.1, r: 0.7}\n", dir, dir, n);
  vi_scene *sc = NULL;
  vi_diag d;
  int st = vi_scene_parse(text, -1, "big", &sc, &d);
  char msg[1200];
  vi_diag_format(&d, msg, sizeof msg);
  print_message("%s\n", msg);
  assert_int_equal(st, VI_ERR_PARSE);
  assert_string_equal(d.key, "model.modes");
  assert_non_null(strstr(d.message, "vibroimpact truncation"));
  assert_null(sc);
  for (int w = 0; w < 2; w++) {
    snprintf(path, sizeof path, "%s/%s.mtx", dir, w ? "K" : "M");
    unlink(path);
  }
  rmdir(dir);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_bar_whole),
      cmocka_unit_test(test_rigid_modes_key),
      cmocka_unit_test(test_large_without_modes),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
