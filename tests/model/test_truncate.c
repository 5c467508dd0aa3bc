/* test_truncate.c - truncated models (vi_model_create_truncated, MODEL.md
 * section 5) against what truncation means:
 * - all the modes of Fig. 2's chain, or one mode plus the static vector
 *   (which then spans the rest), give back its frequencies
 *   omega^2 = (3 -+ sqrt 5) / 2 and its whole stop compliance
 *   w^T M^-1 w = 1;
 * - one mode alone carries psi_1^2 of it and has omega_1;
 * - on a 12-mass chain, k modes plus the static vector reproduce the
 *   static compliance w^T K^-1 w = sum_j psi_j^2 / omega_j^2 exactly (the
 *   static response K^-1 w lies in their span), which k modes alone do not;
 * - a state is projected onto the kept coordinates;
 * - vi_model_modal_compliance: on a fixed-free chain of n masses m and
 *   springs k with the stop at its tip, the static compliance of all the
 *   modes is n / k (springs in series) and the dynamic one 1 / m (w = e_n,
 *   w^T M^-1 w), both rising with each mode added; fig2's first mode
 *   carries psi_1^2 = (5 + sqrt 5) / 10 of its unit dynamic compliance
 *   (the tip's share of the normalised mode (1, phi) / sqrt(1 + phi^2),
 *   phi the golden ratio). */
#include <math.h>
#include <stdlib.h>

#include "vi_testutil.h"

/* w^T K^-1 w from a model's modes */
static double static_compliance(const vi_model *m)
{
  const double *om = vi_model_omega(m), *ps = vi_model_modal_stop(m);
  double s = 0;
  for (int j = 0; j < vi_model_n(m); j++) s += ps[j] * ps[j] / (om[j] * om[j]);
  return s;
}

static void fig2_truncations(void **state)
{
  (void)state;
  vi_model *f = vi_test_fig2(), *R = NULL, *t = NULL;
  const int all[2] = {0, 1};
  const double w1 = sqrt((3 - sqrt(5)) / 2), w2 = sqrt((3 + sqrt(5)) / 2);
  assert_int_equal(vi_model_create_reduced(f, all, 2, 0.7, &R), VI_OK);
  for (int q = 0; q < 2; q++) { /* 2 modes; 1 mode + the static vector */
    double g = 0;
    assert_int_equal(vi_model_create_truncated(R, 2 - q, q, 0.7, NULL, NULL, &g, &t), VI_OK);
    assert_int_equal(vi_model_n(t), 2);
    assert_close(vi_model_omega(t)[0], w1, 1e-14);
    assert_close(vi_model_omega(t)[1], w2, 1e-14);
    assert_close(g, 1.0, 1e-14); /* w = e_2, M = I */
    assert_close(vi_model_stop_compliance(t), 1.0, 1e-14);
    assert_true(vi_model_restitution(t) == 0.7 && vi_model_clearance(t) == 0.1);
    vi_model_destroy(&t);
  }
  double g = 0, z[4] = {0.3, -0.2, 0.05, 0.7}, zt[2];
  assert_int_equal(vi_model_create_truncated(R, 1, 0, 0.5, z, zt, &g, &t), VI_OK);
  assert_close(vi_model_omega(t)[0], w1, 1e-14);
  double p1 = vi_model_modal_stop(f)[0];
  assert_close(g, p1 * p1, 1e-15);
  assert_true(g < 0.95); /* one mode carries part of the compliance */
  assert_close(zt[0], 0.3, 0.0); /* T = e_1: the first coordinate */
  assert_close(zt[1], 0.05, 0.0);
  assert_true(vi_model_restitution(t) == 0.5);
  vi_model_destroy(&t);
  vi_model_destroy(&R);
  vi_model_destroy(&f);
}

static void chain_static_correction(void **state)
{
  (void)state;
  const int n = 12;
  double a[12] = {0}, z[24] = {0};
  a[n - 1] = 0.3;
  vi_model *f = vi_test_chain(n, 1.0, 1.0, 0.02, 0.1, 0.7, 0.9, a), *R = NULL;
  int all[12];
  for (int j = 0; j < n; j++) all[j] = j;
  assert_int_equal(vi_model_create_reduced(f, all, n, 0.7, &R), VI_OK);
  double full = static_compliance(R);
  /* the fixed-free chain's tip: w^T K^-1 w = n / k */
  assert_close(full, (double)n, 1e-11 * n);
  for (int k = 1; k < n; k += 3) {
    vi_model *t = NULL, *s = NULL;
    double zt[26];
    z[k] = 1.0; /* a state along coordinate k + 1: beyond the kept ones */
    assert_int_equal(vi_model_create_truncated(R, k, 0, 0.7, NULL, NULL, NULL, &t), VI_OK);
    assert_int_equal(vi_model_create_truncated(R, k, 1, 0.7, z, zt, NULL, &s), VI_OK);
    double ct = static_compliance(t), cs = static_compliance(s), miss = 0;
    const double *om = vi_model_omega(R), *ps = vi_model_modal_stop(R);
    for (int j = k; j < n; j++) miss += ps[j] * ps[j] / (om[j] * om[j]);
    /* the kept modes alone miss the others' part, and only that */
    assert_true(miss > 1e-4 * full);
    assert_close(ct, full - miss, 1e-11 * full);
    assert_close(cs, full, 1e-11 * full);  /* the static vector restores it */
    for (int j = 0; j < k; j++) assert_close(zt[j], 0.0, 0.0);
    assert_true(fabs(zt[k]) > 0); /* the state's part along the static vector */
    z[k] = 0.0;
    vi_model_destroy(&t);
    vi_model_destroy(&s);
  }
  vi_model_destroy(&R);
  vi_model_destroy(&f);
}

static void modal_compliance(void **state)
{
  (void)state;
  const int n = 7;
  const double m = 2.5, k = 4.0;
  double a[7] = {0}, cd[7], cs[7];
  a[n - 1] = 0.3;
  vi_model *f = vi_test_chain(n, m, k, 0.02, 0.1, 0.7, 0.9, a), *R = NULL;
  int all[7];
  for (int j = 0; j < n; j++) all[j] = j;
  assert_int_equal(vi_model_create_reduced(f, all, n, 0.7, &R), VI_OK);
  assert_int_equal(vi_model_modal_compliance(R, 0, n, cd, cs), VI_OK);
  assert_close(cs[n - 1], n / k, 1e-13 * n / k);
  assert_close(cd[n - 1], 1.0 / m, 1e-13 / m);
  for (int j = 1; j < n; j++) assert_true(cd[j] > cd[j - 1] && cs[j] > cs[j - 1]);
  assert_true(cs[0] < n / k && cd[0] < 1.0 / m);
  double one = 0;
  assert_int_equal(vi_model_modal_compliance(R, 0, 1, NULL, &one), VI_OK);
  assert_true(one == cs[0]);
  vi_model_destroy(&R);
  vi_model_destroy(&f);
  /* fig2 (unit masses and springs, stop on mass 2) */
  vi_model *g = vi_test_fig2();
  const int two[2] = {0, 1};
  assert_int_equal(vi_model_create_reduced(g, two, 2, 0.7, &R), VI_OK);
  assert_int_equal(vi_model_modal_compliance(R, 0, 2, cd, cs), VI_OK);
  assert_close(cd[0], (5 + sqrt(5)) / 10, 1e-14);
  assert_close(cd[1], 1.0, 1e-14);
  assert_close(cs[1], 2.0, 1e-14); /* two unit springs in series */
  vi_model_destroy(&R);
  vi_model_destroy(&g);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(fig2_truncations),
      cmocka_unit_test(chain_static_correction),
      cmocka_unit_test(modal_compliance),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
