/* test_truncation.c - the truncation study (vi_truncation.h) against
 * closed forms and against what a truncation must leave unchanged:
 *
 *  - Fig. 2 (the paper's 2-mass chain): omega_1,2^2 = (3 -+ sqrt 5) / 2,
 *    w^T M^-1 w = 1, w^T K^-1 w = 2, the first mode carries (5 + sqrt 5) / 10
 *    of the dynamic compliance; with every mode kept the energy balance
 *    closes with the model's own r (r_S = r) and the k = n model is the
 *    reference itself (its orbit and first impacts);
 *  - a symmetric 3-mass structure whose antisymmetric mode (1, 0, -1) / sqrt 2
 *    does not move the stop (psi_2 = 0) and is not forced: keeping it
 *    changes nothing (rows k = 1 and 2 agree), the static vector of the
 *    1-mode model is mode 3, so the corrected 1-mode model is the whole
 *    structure; K = [[2,-1,0],[-1,3,-1],[0,-1,2]] has lambda = 1, 2, 4 with
 *    psi^2 = 1/3, 0, 2/3: dynamic fractions 1/3, 1/3, 1 and, with
 *    w^T K^-1 w = 1/2, static ones 2/3, 2/3, 1;
 *  - the same structure as an FE reduction (vi_truncation_create_fe) gives
 *    the same study; the reference's first impact equals that of the
 *    physical model simulated in its own coordinates;
 *  - a cancelled step, iterated again, gives the row an uninterrupted
 *    study gives.
 * Tolerances: 1e-12 for the closed forms (round-off of a 3x3 eigensolve),
 * 1e-8 between runs of one motion by different coordinates (the exact
 * method, or tolerances 1e-11 / 1e-14 of the first-impact runs). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vi_testutil.h"
#include "vibroimpact/vi_truncation.h"

enum { NC = VI_TRUNCATION_COLUMNS };
/* columns of a row (vi_truncation.h) */
enum { C_K = 0, C_OMEGA = 1, C_FD = 2, C_FS = 3, C_CLASS_N = 4, C_CLASS_M = 5,
       C_VN = 6, C_PHASE = 7, C_FIRST_N = 8, C_FIRST_T = 9, C_FIRST_VN = 12,
       C_FIRST_DT = 15, C_RS = 22, C_SC = 27, C_SC_FD = 28, C_SC_CLASS_N = 29,
       C_SC_VN = 31, C_SC_FIRST_N = 33, C_SC_FIRST_T = 34, C_SC_FIRST_DT = 40 };

/* The study's rows lo..hi into rows [(hi - lo + 1) x NC] (row-major here),
 * and the reference's into ref [NC]. */
static void run_study(vi_truncation *tr, int lo, int hi, double *ref,
                      double *rows)
{
  int k = lo;
  assert_int_equal(vi_truncation_iterate(tr), VI_OK); /* the reference */
  assert_int_equal(vi_truncation_row(tr, 0, ref), VI_OK);
  while (!vi_truncation_done(tr)) {
    assert_int_equal(vi_truncation_iterate(tr), VI_OK);
    assert_int_equal(vi_truncation_row(tr, k, rows + (size_t)(k - lo) * NC),
                     VI_OK);
    k++;
  }
  assert_int_equal(k, hi + 1);
}

static void test_fig2(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  vi_truncation *tr = NULL;
  double ref[NC], rows[2 * NC], info[VI_TRUNCATION_INFO];
  double x0[2] = {0, 0}, v0[2] = {0, 0};
  assert_int_equal(vi_truncation_create(m, &tr), VI_OK);
  assert_int_equal(vi_truncation_set_initial(tr, 0, 60, x0, v0), VI_OK);
  run_study(tr, 1, 2, ref, rows);
  assert_int_equal(vi_truncation_summary(tr, info), VI_OK);
  double s5 = sqrt(5.0), p1 = (5 + s5) / 10, l1 = (3 - s5) / 2, l2 = (3 + s5) / 2;
  assert_true(info[0] == 2 && info[1] == 1 && info[2] == 2 && info[3] == 2);
  assert_close(info[4], 0.7, 0.0);
  assert_close(info[5], 1.0, 1e-12); /* w^T M^-1 w */
  assert_close(info[6], 2.0, 1e-12); /* w^T K^-1 w */
  assert_true(info[7] == 1);
  const double *r1 = rows, *r2 = rows + NC;
  assert_close(r1[C_OMEGA], sqrt(l1), 1e-12);
  assert_close(r2[C_OMEGA], sqrt(l2), 1e-12);
  assert_close(r1[C_FD], p1, 1e-12);
  assert_close(r1[C_FS], p1 / l1 / 2, 1e-12);
  assert_close(r2[C_FD], 1.0, 1e-12);
  assert_close(r2[C_FS], 1.0, 1e-12);
  /* the reference orbit is Fig. 2's P(1,1) */
  assert_true(ref[C_K] == 2 && ref[C_CLASS_N] == 1 && ref[C_CLASS_M] == 1);
  /* every mode kept: the reference itself, r_S = r */
  assert_true(r2[C_CLASS_N] == 1 && r2[C_CLASS_M] == 1);
  assert_close(r2[C_VN], ref[C_VN], 1e-8 * fabs(ref[C_VN]));
  assert_close(r2[C_PHASE], ref[C_PHASE], 1e-8);
  assert_close(r2[C_RS], 0.7, 1e-9);
  assert_true(r2[C_FIRST_N] == ref[C_FIRST_N] && ref[C_FIRST_N] >= 1);
  assert_close(r2[C_FIRST_DT], 0.0, 1e-8);
  assert_true(r2[C_SC] == 0 && isnan(r2[C_SC_FD])); /* no mode beyond */
  /* one mode plus the static vector: mode 2 again, the whole model */
  assert_true(r1[C_SC] == 1);
  assert_close(r1[C_SC_FD], 1.0, 1e-12);
  assert_close(r1[C_SC_VN], ref[C_VN], 1e-8 * fabs(ref[C_VN]));
  assert_close(r1[C_SC_FIRST_DT], 0.0, 1e-8);
  vi_truncation_destroy(&tr);
  vi_model_destroy(&m);
}

/* The symmetric 3-mass structure (header comment). */
static const double M3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
static const double K3[9] = {2, -1, 0, -1, 3, -1, 0, -1, 2};
static const double C3[9] = {0.1, 0, 0, 0, 0.1, 0, 0, 0, 0.1};
static const double A3[3] = {0.6, 0.6, 0.6}, W3[3] = {0, 1, 0};
static const double X3[3] = {0.02, 0.05, 0.02}; /* symmetric: mode 2 rests */
enum { T_END = 80 };
#define OMEGA3 2.2 /* the reference orbit is P(1,1) there */
#define XS3 0.1
#define R3 0.7

static vi_model *sym3(void)
{
  return vi_test_model(3, M3, C3, K3, OMEGA3, A3, NULL, W3, XS3, R3);
}

/* The closed forms and the decoupled mode's rows. */
static void check_sym3(const double *info, const double *ref,
                       const double *rows)
{
  const double *r1 = rows, *r2 = rows + NC, *r3 = rows + (size_t)2 * NC;
  assert_close(info[5], 1.0, 1e-12);
  assert_close(info[6], 0.5, 1e-12);
  assert_close(r1[C_OMEGA], 1.0, 1e-12);
  assert_close(r2[C_OMEGA], sqrt(2.0), 1e-12);
  assert_close(r3[C_OMEGA], 2.0, 1e-12);
  assert_close(r1[C_FD], 1.0 / 3, 1e-12);
  assert_close(r2[C_FD], 1.0 / 3, 1e-12);
  assert_close(r3[C_FD], 1.0, 1e-12);
  assert_close(r1[C_FS], 2.0 / 3, 1e-12);
  assert_close(r2[C_FS], 2.0 / 3, 1e-12);
  assert_close(r3[C_FS], 1.0, 1e-12);
  /* the decoupled mode changes nothing: k = 1 and k = 2 agree */
  assert_true(r1[C_CLASS_N] == r2[C_CLASS_N] && r1[C_CLASS_M] == r2[C_CLASS_M]);
  assert_true(r1[C_CLASS_N] >= 0);
  if (r1[C_CLASS_N] == 1 && r1[C_CLASS_M] == 1)
    assert_close(r2[C_VN], r1[C_VN], 1e-8 * fabs(r1[C_VN]));
  assert_true(r1[C_FIRST_N] == r2[C_FIRST_N] && r1[C_FIRST_N] >= 1);
  for (int j = 0; j < r1[C_FIRST_N]; j++) {
    assert_close(r2[C_FIRST_T + j], r1[C_FIRST_T + j], 1e-8);
    assert_close(r2[C_FIRST_VN + j], r1[C_FIRST_VN + j], 1e-8);
  }
  assert_close(r2[C_RS], r1[C_RS], 1e-9);
  /* the 1- and 2-mode models with the static vector are the structure */
  for (int i = 0; i < 2; i++) {
    const double *r = rows + (size_t)i * NC;
    assert_true(r[C_SC] == 1);
    assert_close(r[C_SC_FD], 1.0, 1e-12);
    assert_true(r[C_SC_CLASS_N] == ref[C_CLASS_N]);
    assert_true(r[C_SC_FIRST_N] == ref[C_FIRST_N]);
    for (int j = 0; j < ref[C_FIRST_N]; j++)
      assert_close(r[C_SC_FIRST_DT + j], 0.0, 1e-8);
  }
  /* every mode: the reference, its balance closed by r */
  assert_true(r3[C_CLASS_N] == ref[C_CLASS_N] && r3[C_CLASS_M] == ref[C_CLASS_M]);
  assert_close(r3[C_FIRST_DT], 0.0, 1e-8);
  assert_true(ref[C_CLASS_N] == 1 && ref[C_CLASS_M] == 1);
  assert_close(r3[C_VN], ref[C_VN], 1e-8 * fabs(ref[C_VN]));
  assert_close(r3[C_RS], R3, 1e-9);
  assert_false(isnan(r1[C_RS])); /* the balance of the 1-mode model */
}

/* The first impact of the physical model from X3, in its own coordinates. */
static void physical_first(double *t, double *vn)
{
  vi_model *m = sym3();
  vi_test_events ev;
  memset(&ev, 0, sizeof ev);
  double v0[3] = {0, 0, 0};
  vi_sim *s = vi_test_sim(m, VI_METHOD_ADAMS, 1e-11, 1e-14, X3, v0, &ev);
  int st = vi_sim_run(s, T_END);
  assert_true(st == VI_OK || st == VI_STOPPED);
  assert_true(ev.count >= 1 && ev.kind[0] == VI_EVENT_IMPACT);
  *t = ev.t[0];
  *vn = ev.vn[0];
  vi_sim_destroy(&s);
  vi_test_events_free(&ev);
  vi_model_destroy(&m);
}

static void test_decoupled_mode(void **state)
{
  (void)state;
  vi_model *m = sym3();
  vi_truncation *tr = NULL;
  double ref[NC], rows[3 * NC], info[VI_TRUNCATION_INFO], v0[3] = {0, 0, 0};
  assert_int_equal(vi_truncation_create(m, &tr), VI_OK);
  assert_int_equal(vi_truncation_set_initial(tr, 0, T_END, X3, v0), VI_OK);
  run_study(tr, 1, 3, ref, rows);
  assert_int_equal(vi_truncation_summary(tr, info), VI_OK);
  check_sym3(info, ref, rows);
  double t, vn;
  physical_first(&t, &vn);
  print_message("  symmetric 3-mass: r_S of 1 and 2 modes %.6f %.6f, of 3 "
                "%.6f; first impact t = %.10g (physical %.10g)\n", rows[C_RS],
                rows[NC + C_RS], rows[2 * NC + C_RS], ref[C_FIRST_T], t);
  assert_close(ref[C_FIRST_T], t, 1e-8);
  assert_close(ref[C_FIRST_VN], vn, 1e-8);
  vi_truncation_destroy(&tr);
  vi_model_destroy(&m);
}

/* The same structure as an FE reduction keeping its 3 modes. */
static void test_fe(void **state)
{
  (void)state;
  static const int mcp[4] = {0, 1, 2, 3}, mri[3] = {0, 1, 2};
  static const double mv[3] = {1, 1, 1};
  static const int kcp[4] = {0, 2, 4, 5}, kri[5] = {0, 1, 1, 2, 2};
  static const double kv[5] = {2, -1, 3, -1, 2}; /* lower triangle */
  vi_fe *fe = NULL;
  vi_truncation *tr = NULL;
  double ref[NC], rows[3 * NC], info[VI_TRUNCATION_INFO], v0[3] = {0, 0, 0};
  assert_int_equal(vi_fe_create(3, &fe), VI_OK);
  assert_int_equal(vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 0, mcp, mri, mv), VI_OK);
  assert_int_equal(vi_fe_set_stiffness_csc(fe, VI_CSC_LOWER, 0, kcp, kri, kv),
                   VI_OK);
  assert_int_equal(vi_fe_set_rayleigh(fe, 0.1, 0), VI_OK); /* C = 0.1 M */
  assert_int_equal(vi_fe_set_modes(fe, 3), VI_OK);
  assert_int_equal(vi_fe_add_stop_dof(fe, 1, 1, XS3, R3), VI_OK);
  assert_int_equal(vi_fe_set_forcing(fe, OMEGA3, A3, NULL, NULL), VI_OK);
  assert_int_equal(vi_fe_set_keep_shapes(fe, 1), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_OK);
  assert_int_equal(vi_truncation_create_fe(fe, &tr), VI_OK);
  assert_int_equal(vi_truncation_set_initial(tr, 0, T_END, X3, v0), VI_OK);
  run_study(tr, 1, 3, ref, rows);
  assert_int_equal(vi_truncation_summary(tr, info), VI_OK);
  assert_true(info[0] == 3 && info[3] == 3);
  check_sym3(info, ref, rows);
  double t, vn;
  physical_first(&t, &vn);
  assert_close(ref[C_FIRST_T], t, 1e-8);
  assert_close(ref[C_FIRST_VN], vn, 1e-8);
  vi_truncation_destroy(&tr);
  vi_fe_destroy(&fe);
}

/* Cancels at the n-th poll (n counts down). */
static int cancel_at(void *user)
{
  int *n = user;
  return --*n == 0;
}

static void test_cancel_resumes(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  vi_truncation *tr = NULL, *whole = NULL;
  double ref[NC], rows[2 * NC] = {0}, row[NC] = {0}, x0[2] = {0, 0};
  assert_int_equal(vi_truncation_create(m, &whole), VI_OK);
  assert_int_equal(vi_truncation_set_initial(whole, 0, 60, x0, x0), VI_OK);
  run_study(whole, 1, 2, ref, rows);
  /* cancelled in the middle of row 1's runs (at the 50th poll), then
   * iterated again: the same row */
  int n = 50;
  assert_int_equal(vi_truncation_create(m, &tr), VI_OK);
  assert_int_equal(vi_truncation_set_initial(tr, 0, 60, x0, x0), VI_OK);
  assert_int_equal(vi_truncation_iterate(tr), VI_OK); /* the reference */
  assert_int_equal(vi_truncation_set_cancel(tr, cancel_at, &n, NULL), VI_OK);
  assert_int_equal(vi_truncation_iterate(tr), VI_CANCELLED);
  assert_true(n == 0);
  assert_int_equal(vi_truncation_row(tr, 1, row), VI_ERR_STATE);
  assert_int_equal(vi_truncation_iterate(tr), VI_OK); /* n < 0: never again */
  assert_int_equal(vi_truncation_row(tr, 1, row), VI_OK);
  for (int c = 0; c < NC; c++) /* the same numbers, NaN where NaN */
    assert_true(row[c] == rows[c] || (isnan(row[c]) && isnan(rows[c])));
  vi_truncation_destroy(&tr);
  vi_truncation_destroy(&whole);
  vi_model_destroy(&m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_fig2),
      cmocka_unit_test(test_decoupled_mode),
      cmocka_unit_test(test_fe),
      cmocka_unit_test(test_cancel_resumes),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
