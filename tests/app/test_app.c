/* test_app.c - the program as a user runs it: exit statuses, messages with
 * the line, no output file after an error, SIGINT leaves a valid file
 * marked incomplete. */
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <hdf5.h>

#include "vi_testutil.h"
#include "vi_bad_scenes.h"

static const char *app;
static char dir[] = "/tmp/vi_test_app_XXXXXX";

/* Run the app with argv, stdout and stderr to files; returns the exit
 * status, or 128 + signal. */
static int run_app(char *const argv[], const char *out, const char *err)
{
  pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    int o = open(out, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    int e = open(err, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(o, 1);
    dup2(e, 2);
    execv(app, argv);
    _exit(127);
  }
  int st;
  waitpid(pid, &st, 0);
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
}

static char *slurp(const char *path)
{
  FILE *f = fopen(path, "rb");
  assert_non_null(f);
  static char buf[65536];
  size_t n = fread(buf, 1, sizeof buf - 1, f);
  buf[n] = '\0';
  fclose(f);
  return buf;
}

static int exists(const char *p) { return access(p, F_OK) == 0; }

static void test_malformed_scene_files(void **state)
{
  (void)state;
  char scene[256], h5[256], part[256], out[256], err[256];
  snprintf(h5, sizeof h5, "%s/out.h5", dir);
  snprintf(part, sizeof part, "%s/out.h5.part", dir);
  snprintf(out, sizeof out, "%s/stdout", dir);
  snprintf(err, sizeof err, "%s/stderr", dir);
  size_t nc = sizeof cases / sizeof cases[0];
  for (size_t i = 0; i < nc; i++) {
    snprintf(scene, sizeof scene, "%s/bad%02zu.yaml", dir, i);
    FILE *f = fopen(scene, "w");
    fputs(cases[i].text, f);
    fclose(f);
    char *argv[] = {(char *)app, "run", scene, "-o", h5, "--quiet", NULL};
    int rc = run_app(argv, out, err);
    char *msg = slurp(err);
    print_message("%-30s exit %d: %s", cases[i].what, rc, msg);
    assert_true(rc == 2 || rc == 1);
    assert_non_null(strstr(msg, scene)); /* names the file */
    if (cases[i].line > 0) {
      char at[300];
      snprintf(at, sizeof at, "%s:%d:", scene, cases[i].line);
      assert_non_null(strstr(msg, at));  /* and the line */
    }
    assert_false(exists(h5));
    assert_false(exists(part));
    remove(scene);
  }
  /* a missing scene is an input error (2), an unwritable output a
   * run-time one (1) */
  char *argv2[] = {(char *)app, "/nonexistent/scene.yaml", NULL};
  assert_int_equal(run_app(argv2, out, err), 2);
  assert_non_null(strstr(slurp(err), "cannot open"));
  char *argv3[] = {(char *)app, "-o", "/nonexistent-dir/x.h5", "--periods", "2", NULL};
  assert_int_equal(run_app(argv3, out, err), 1);
  assert_non_null(strstr(slurp(err), "cannot write /nonexistent-dir/x.h5"));
  char *argv4[] = {(char *)app, "--rtol", "-3", NULL};
  assert_int_equal(run_app(argv4, out, err), 2);
  char *argv5[] = {(char *)app, "--bogus", NULL};
  assert_int_equal(run_app(argv5, out, err), 2);
  remove(out);
  remove(err);
}

static void test_outputs(void **state)
{
  (void)state;
  char out[256], err[256];
  snprintf(out, sizeof out, "%s/stdout", dir);
  snprintf(err, sizeof err, "%s/stderr", dir);
  char *a1[] = {(char *)app, "--impacts-csv", "-", "--periods", "3", "--quiet", NULL};
  assert_int_equal(run_app(a1, out, err), 0);
  char *csv = slurp(out);
  assert_int_equal(strncmp(csv, "k,t,vn,x_1,x_2,v_1,v_2\n0,", 25), 0);
  char *a2[] = {(char *)app, "restitution", "--re", "0.51", "--ke", "1", NULL};
  assert_int_equal(run_app(a2, out, err), 0);
  assert_close(strtod(slurp(out), NULL), 0.7, 1e-15);
  char *a3[] = {(char *)app, "restitution", "--re", "2", "--ke", "1", NULL};
  assert_int_equal(run_app(a3, out, err), 2);
  char *a4[] = {(char *)app, "energy", "--json", NULL};
  assert_int_equal(run_app(a4, out, err), 0);
  char *js = slurp(out), *p = strstr(js, "\"r_recovered\": ");
  assert_non_null(p);
  assert_close(strtod(p + 15, NULL), 0.7, 1e-10);
  assert_non_null(strstr(js, "\"modes\": [{\"omega\": "));
  assert_non_null(strstr(js, "\"reduced\": [{\"modes\": 1, \"r_S\": "));
  /* the same analysis into HDF5: /orbits/P1_1 */
  char h5[256];
  snprintf(h5, sizeof h5, "%s/energy.h5", dir);
  char *a5[] = {(char *)app, "energy", "-o", h5, NULL};
  assert_int_equal(run_app(a5, out, err), 0);
  hid_t f = H5Fopen(h5, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  hid_t g = H5Gopen2(f, "orbits/P1_1", H5P_DEFAULT);
  assert_true(g >= 0);
  double r = 0, rS[2] = {0, 0};
  hid_t at = H5Aopen(g, "r_recovered", H5P_DEFAULT);
  H5Aread(at, H5T_NATIVE_DOUBLE, &r);
  H5Aclose(at);
  hid_t d = H5Dopen2(g, "r_S", H5P_DEFAULT);
  H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, rS);
  H5Dclose(d);
  H5Gclose(g);
  H5Fclose(f);
  assert_close(r, 0.7, 1e-10);
  assert_close(rS[1], 0.7, 1e-10); /* both modes kept: r itself */
  assert_true(rS[0] > 0.2 && rS[0] < 0.5);
  remove(h5);
  remove(out);
  remove(err);
}

/* What the scene does not ask for is not in the file: no events without
 * output.impacts, no /modal without output.modes, no /ledger without
 * output.ledger, no samples without samples_per_period. */
static void test_output_flags(void **state)
{
  (void)state;
  char scene[256], h5[256], out[256], err[256];
  snprintf(scene, sizeof scene, "%s/flags.yaml", dir);
  snprintf(h5, sizeof h5, "%s/flags.h5", dir);
  snprintf(out, sizeof out, "%s/stdout", dir);
  snprintf(err, sizeof err, "%s/stderr", dir);
  FILE *f = fopen(scene, "w");
  fputs("model:\n  chain: {n: 2, m: 1, k: 1, c: 0.1}\n"
        "forcing: {omega: 0.9, a: [0.5, 0]}\nstop: {mass: 2, xs: 0.1, r: 0.7}\n"
        "run: {periods: 5}\noutput: {impacts: false, modes: false}\n", f);
  fclose(f);
  char *argv[] = {(char *)app, scene, "-o", h5, "--quiet", NULL};
  assert_int_equal(run_app(argv, out, err), 0);
  hid_t file = H5Fopen(h5, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(file >= 0);
  assert_int_equal(H5Lexists(file, "modal", H5P_DEFAULT), 0);
  assert_int_equal(H5Lexists(file, "ledger", H5P_DEFAULT), 0);
  assert_true(H5Lexists(file, "model", H5P_DEFAULT) > 0);
  const char *empty[2] = {"impacts/time", "trajectory/time"};
  for (int k = 0; k < 2; k++) {
    hid_t d = H5Dopen2(file, empty[k], H5P_DEFAULT), sp = H5Dget_space(d);
    hsize_t rows;
    H5Sget_simple_extent_dims(sp, &rows, NULL);
    assert_int_equal((int)rows, 0);
    H5Sclose(sp);
    H5Dclose(d);
  }
  H5Fclose(file);
  remove(h5);
  remove(scene);
  remove(out);
  remove(err);
}

/* SIGINT during a long run: exit 130, the file exists, is valid HDF5, holds
 * what was computed and says complete = 0. */
static void test_sigint_leaves_valid_file(void **state)
{
  (void)state;
  char h5[256], part[256], err[256];
  snprintf(h5, sizeof h5, "%s/long.h5", dir);
  snprintf(part, sizeof part, "%s/long.h5.part", dir);
  snprintf(err, sizeof err, "%s/stderr", dir);
  pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    int e = open(err, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(e, 2);
    execl(app, app, "--periods", "1e7", "--method", "exact", "-o", h5, "--quiet", (char *)NULL);
    _exit(127);
  }
  /* wait until the run is writing, then interrupt it */
  for (int i = 0; i < 1000 && !exists(part); i++) usleep(10000); /* up to 10 s */
  usleep(300000);
  assert_true(exists(part));
  kill(pid, SIGINT);
  int st;
  waitpid(pid, &st, 0);
  assert_true(WIFEXITED(st));
  assert_int_equal(WEXITSTATUS(st), 130);
  assert_non_null(strstr(slurp(err), "interrupted"));
  assert_true(exists(h5));
  assert_false(exists(part));
  hid_t f = H5Fopen(h5, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  int complete = -1;
  hid_t a = H5Aopen(f, "complete", H5P_DEFAULT);
  H5Aread(a, H5T_NATIVE_INT, &complete);
  H5Aclose(a);
  assert_int_equal(complete, 0);
  hid_t d = H5Dopen2(f, "impacts/time", H5P_DEFAULT), sp = H5Dget_space(d);
  hsize_t n;
  H5Sget_simple_extent_dims(sp, &n, NULL);
  H5Sclose(sp);
  H5Dclose(d);
  print_message("interrupted run kept %llu impacts\n", (unsigned long long)n);
  assert_true(n > 10);
  H5Fclose(f);
  remove(h5);
  remove(err);
}

/* A free body (the bouncing ball: K = 0, a constant load, no forcing
 * frequency) runs, is written to HDF5 like any model, and its summary is
 * in time units, not "forcing periods" it does not have. */
static void test_free_body_run(void **state)
{
  (void)state;
  char scene[256], h5[256], out[256], err[256];
  snprintf(scene, sizeof scene, "%s/ball.yaml", dir);
  snprintf(h5, sizeof h5, "%s/ball.h5", dir);
  snprintf(out, sizeof out, "%s/stdout", dir);
  snprintf(err, sizeof err, "%s/stderr", dir);
  FILE *f = fopen(scene, "w");
  fputs("name: ball\nmodel: {M: [[1.0]], K: [[0.0]]}\nforcing: {f0: [1.0]}\n"
        "stop: {mass: 1, xs: 0.0, r: 0.8}\ninitial: {x: [0.0], v: [-1.0]}\n"
        "run: {t_end: 20, rtol: 1.0e-10, atol: 1.0e-12}\n"
        "output: {ledger: true}\n", f);
  fclose(f);
  char *argv[] = {(char *)app, scene, "-o", h5, NULL};
  int rc = run_app(argv, out, err);
  if (rc) printf("%s", slurp(err));
  assert_int_equal(rc, 0);
  const char *s = slurp(out);
  printf("%s", s);
  assert_null(strstr(s, "forcing period"));
  assert_non_null(strstr(s, "free motion"));
  hid_t file = H5Fopen(h5, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(file >= 0);
  assert_true(H5Lexists(file, "impacts", H5P_DEFAULT) > 0);
  H5Fclose(file);
  remove(h5);
  remove(scene);
  remove(out);
  remove(err);
}

/* An FE run says what its reduction did: on the summary line, and in /fe
 * (the beam of share/scenes/beam_fe.yaml: 4 of its 200 modes, as
 * model.modes asks, no rigid mode, no massless dof, residuals at
 * round-off). */
static void test_fe_report(void **state)
{
  (void)state;
  char h5[256], out[256], err[256];
  snprintf(h5, sizeof h5, "%s/beam.h5", dir);
  snprintf(out, sizeof out, "%s/stdout", dir);
  snprintf(err, sizeof err, "%s/stderr", dir);
  static char beam[] = VI_SCENE_DIR "/beam_fe.yaml";
  char *argv[] = {(char *)app, beam, "-o", h5, NULL};
  int rc = run_app(argv, out, err);
  if (rc) printf("%s", slurp(err));
  assert_int_equal(rc, 0);
  const char *s = slurp(out);
  assert_non_null(strstr(s, "reduction 4 of 200 modes (as model.modes asks); "
                            "0 rigid (K psi at round-off), 0 massless dofs"));
  hid_t file = H5Fopen(h5, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(file >= 0);
  hid_t g = H5Gopen2(file, "fe", H5P_DEFAULT);
  assert_true(g >= 0);
  int rigid = -1, massless = -1;
  double res = 1.0, mres[4] = {1, 1, 1, 1};
  hid_t a = H5Aopen(g, "rigid_modes", H5P_DEFAULT);
  assert_true(H5Aread(a, H5T_NATIVE_INT, &rigid) >= 0);
  H5Aclose(a);
  a = H5Aopen(g, "massless_dofs", H5P_DEFAULT);
  assert_true(H5Aread(a, H5T_NATIVE_INT, &massless) >= 0);
  H5Aclose(a);
  a = H5Aopen(g, "max_residual", H5P_DEFAULT);
  assert_true(H5Aread(a, H5T_NATIVE_DOUBLE, &res) >= 0);
  H5Aclose(a);
  hid_t ds = H5Dopen2(g, "mode_residual", H5P_DEFAULT);
  assert_true(ds >= 0);
  assert_true(H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT,
                      mres) >= 0);
  H5Dclose(ds);
  H5Gclose(g);
  H5Fclose(file);
  assert_int_equal(rigid, 0);
  assert_int_equal(massless, 0);
  assert_true(res < 1e-12);
  for (int j = 0; j < 4; j++) assert_true(mres[j] <= res && mres[j] > 0.0);
  remove(h5);
  remove(out);
  remove(err);
}

int main(int argc, char **argv)
{
  if (argc < 2) {
    fprintf(stderr, "usage: test_app PATH-TO-vibroimpact\n");
    return 2;
  }
  app = argv[1];
  if (!mkdtemp(dir)) return 2;
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_malformed_scene_files),
      cmocka_unit_test(test_outputs),
      cmocka_unit_test(test_output_flags),
      cmocka_unit_test(test_free_body_run),
      cmocka_unit_test(test_fe_report),
      cmocka_unit_test(test_sigint_leaves_valid_file),
  };
  int rc = cmocka_run_group_tests(tests, NULL, NULL);
  rmdir(dir);
  return rc;
}
