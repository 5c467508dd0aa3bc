/* test_flow.c - the closed-form flow against textbook solutions, the ODE
 * itself (finite differences) and the semigroup property. */
#include <math.h>

#include "vi_testutil.h"

/* undamped, unforced: x = x0 cos wt + v0/w sin wt */
static void test_sdof_free(void **state)
{
  (void)state;
  vi_model *m = vi_test_sdof(2.0, 0.0, 8.0, 0.0, 0.0, 0.0, 1.0, 0.5);
  double w = 2.0, x0 = 0.3, v0 = -0.7, x, v;
  for (int i = 0; i * 3.7 < 50.0; i++) {
    double t = i * 3.7;
    assert_int_equal(vi_flow_physical(m, 0.0, &x0, &v0, t, &x, &v), VI_OK);
    assert_close(x, x0 * cos(w * t) + v0 / w * sin(w * t), 1e-13);
    assert_close(v, -x0 * w * sin(w * t) + v0 * cos(w * t), 1e-13);
  }
  vi_model_destroy(&m);
}

/* steady state of m x'' + c x' + k x = a cos Wt: amplitude
 * a / sqrt((k - m W^2)^2 + (c W)^2), reached once transients decay */
static void test_sdof_steady_state(void **state)
{
  (void)state;
  double m_ = 1.0, c = 0.4, k = 2.0, a = 0.8, W = 1.3;
  vi_model *m = vi_test_sdof(m_, c, k, a, 0.0, W, 100.0, 0.5);
  double amp = a / sqrt(pow(k - m_ * W * W, 2) + pow(c * W, 2));
  double phase = atan2(c * W, k - m_ * W * W);
  double x0 = 0.2, v0 = 0.0, x, v;
  double t = 200.0; /* e^{-0.2 t} ~ 1e-17 */
  assert_int_equal(vi_flow_physical(m, 0.0, &x0, &v0, t, &x, &v), VI_OK);
  assert_close(x, amp * cos(W * t - phase), 1e-13);
  assert_close(v, -amp * W * sin(W * t - phase), 1e-13);
  vi_model_destroy(&m);
}

/* Residual of the ODE by central differences, for under-, critically and
 * over-damped modes, a rigid-body mode and a constant load. */
static void check_ode(double m_, double c, double k, double a, double f0,
                      double W)
{
  vi_model *m = vi_test_sdof(m_, c, k, a, f0, W, 100.0, 0.5);
  double x0 = 0.3, v0 = -0.4, h = 1e-3;
  for (int i = 0; 0.5 + i * 1.1 < 10.0; i++) {
    double t = 0.5 + i * 1.1;
    double xm, xc, xp, vm, vc, vp;
    vi_flow_physical(m, 0.2, &x0, &v0, t - h, &xm, &vm);
    vi_flow_physical(m, 0.2, &x0, &v0, t, &xc, &vc);
    vi_flow_physical(m, 0.2, &x0, &v0, t + h, &xp, &vp);
    double acc = (xp - 2 * xc + xm) / (h * h);
    double f = a * cos(W * t) + f0;
    assert_close(m_ * acc + c * vc + k * xc, f, 1e-5);
    assert_close((xp - xm) / (2 * h), vc, 1e-6);
  }
  vi_model_destroy(&m);
}

static void test_ode_residual(void **state)
{
  (void)state;
  check_ode(1.0, 0.3, 4.0, 0.5, 0.1, 1.7);  /* underdamped */
  check_ode(1.0, 4.0, 4.0, 0.5, 0.1, 1.7);  /* critical: c = 2 sqrt(km) */
  check_ode(1.0, 9.0, 4.0, 0.5, 0.1, 1.7);  /* overdamped */
  check_ode(1.0, 0.5, 0.0, 0.5, 0.2, 1.7);  /* rigid, damped */
  check_ode(1.0, 0.0, 0.0, 0.5, 0.2, 1.7);  /* rigid, free */
}

/* rigid body, constant load: x = x0 + v0 t + f0 t^2 / (2m) */
static void test_uniform_acceleration(void **state)
{
  (void)state;
  vi_model *m = vi_test_sdof(2.0, 0.0, 0.0, 0.0, 3.0, 0.0, 100.0, 0.5);
  double x0 = 0.1, v0 = -2.0, x, v, t = 4.0;
  assert_int_equal(vi_flow_physical(m, 1.0, &x0, &v0, 1.0 + t, &x, &v), VI_OK);
  assert_close(x, x0 + v0 * t + 0.75 * t * t, 1e-13);
  assert_close(v, v0 + 1.5 * t, 1e-13);
  vi_model_destroy(&m);
}

/* flow(t0 -> t2) = flow(t1 -> t2) o flow(t0 -> t1) on the Fig. 2 chain */
static void test_semigroup(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  double x0[2] = {0.05, -0.02}, v0[2] = {0.1, 0.3}, x1[2], v1[2], x2[2],
         v2[2], y2[2], w2[2];
  vi_flow_physical(m, 0.3, x0, v0, 7.9, x1, v1);
  vi_flow_physical(m, 7.9, x1, v1, 23.4, x2, v2);
  vi_flow_physical(m, 0.3, x0, v0, 23.4, y2, w2);
  for (int i = 0; i < 2; i++) {
    assert_close(x2[i], y2[i], 1e-14);
    assert_close(v2[i], w2[i], 1e-14);
  }
  assert_int_equal(vi_flow_physical(m, 1.0, x0, v0, 0.5, x1, v1), VI_ERR_TIME);
  vi_model_destroy(&m);
}

/* Non-proportional damping (first-order eigen-solution): the ODE residual
 * M x'' + C x' + K x - f by central differences, and the semigroup. */
static void test_nonproportional_flow(void **state)
{
  (void)state;
  const double *M = vi_test_np3_M, *C = vi_test_np3_C, *K = vi_test_np3_K,
               *a = vi_test_np3_a, f0[3] = {0.1, 0, -0.2};
  vi_model *m = vi_test_nonprop3(10.0, f0); /* stop out of reach */
  double x0[3] = {0.1, -0.2, 0.05}, v0[3] = {0.3, 0.0, -0.1}, h = 1e-3;
  for (int k = 0; 1.0 + k * 3.3 < 30.0; k++) {
    double t = 1.0 + k * 3.3;
    double xm[3], xc[3], xp[3], vm[3], vc[3], vp[3];
    vi_flow_physical(m, 0.5, x0, v0, t - h, xm, vm);
    vi_flow_physical(m, 0.5, x0, v0, t, xc, vc);
    vi_flow_physical(m, 0.5, x0, v0, t + h, xp, vp);
    for (int i = 0; i < 3; i++) {
      double r = -(a[i] * cos(0.8 * t) + f0[i]);
      for (int j = 0; j < 3; j++)
        r += M[i + 3 * j] * (xp[j] - 2 * xc[j] + xm[j]) / (h * h) +
             C[i + 3 * j] * vc[j] + K[i + 3 * j] * xc[j];
      assert_close(r, 0.0, 2e-6);
      assert_close((xp[i] - xm[i]) / (2 * h), vc[i], 1e-6);
    }
  }
  double x1[3], v1[3], x2[3], v2[3], y2[3], u2[3];
  vi_flow_physical(m, 0.0, x0, v0, 7.7, x1, v1);
  vi_flow_physical(m, 7.7, x1, v1, 31.0, x2, v2);
  vi_flow_physical(m, 0.0, x0, v0, 31.0, y2, u2);
  for (int i = 0; i < 3; i++) {
    assert_close(x2[i], y2[i], 1e-13);
    assert_close(v2[i], u2[i], 1e-13);
  }
  vi_model_destroy(&m);
}

static void test_unsupported(void **state)
{
  (void)state;
  /* undamped SDOF forced at resonance has no bounded particular solution */
  vi_model *m = vi_test_sdof(1.0, 0.0, 4.0, 1.0, 0.0, 2.0, 1.0, 0.5);
  double x0 = 0, v0 = 0, x, v;
  assert_int_equal(vi_flow_physical(m, 0, &x0, &v0, 1, &x, &v), VI_ERR_UNSUPPORTED);
  vi_model_destroy(&m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_sdof_free),
      cmocka_unit_test(test_sdof_steady_state),
      cmocka_unit_test(test_ode_residual),
      cmocka_unit_test(test_uniform_acceleration),
      cmocka_unit_test(test_semigroup),
      cmocka_unit_test(test_nonproportional_flow),
      cmocka_unit_test(test_unsupported),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
