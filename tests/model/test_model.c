/* test_model.c - every bad input gets its own code and a message naming the
 * culprit; none crashes. */
#include <math.h>
#include <string.h>

#include "vi_testutil.h"

static const double I2[4] = {1, 0, 0, 1};
static const double K2[4] = {2, -1, -1, 1};
static const double W2[2] = {0, 1};

static vi_model *fresh2(void)
{
  vi_model *m = NULL;
  assert_int_equal(vi_model_create(2, &m), VI_OK);
  return m;
}

#define assert_msg_has(m, s) assert_non_null(strstr(vi_model_errmsg(m), (s)))

static void test_dimensions(void **state)
{
  (void)state;
  vi_model *m = NULL;
  assert_int_equal(vi_model_create(0, &m), VI_ERR_DIM);
  assert_null(m);
  assert_int_equal(vi_model_create(-3, &m), VI_ERR_DIM);
  assert_int_equal(vi_model_create(2, NULL), VI_ERR_ARG);
  m = fresh2();
  assert_int_equal(vi_model_set_mass(m, I2, 1), VI_ERR_DIM);
  assert_msg_has(m, "leading dimension 1");
  assert_int_equal(vi_model_set_stiffness(m, NULL, 2), VI_ERR_ARG);
  /* a leading dimension larger than n is honoured, not an error */
  const double K3[6] = {2, -1, 99, -1, 1, 99};
  assert_int_equal(vi_model_set_stiffness(m, K3, 3), VI_OK);
  double b[4];
  assert_int_equal(vi_build_chain(2, I2, I2, NULL, b, b, b, 1), VI_ERR_DIM);
  vi_model_destroy(&m);
}

static void test_nonfinite(void **state)
{
  (void)state;
  vi_model *m = fresh2();
  double K[4] = {2, -1, -1, NAN};
  assert_int_equal(vi_model_set_stiffness(m, K, 2), VI_ERR_NONFINITE);
  assert_msg_has(m, "K(2,2)");
  double C[4] = {INFINITY, 0, 0, 1};
  assert_int_equal(vi_model_set_damping(m, C, 2), VI_ERR_NONFINITE);
  double a[2] = {0, NAN};
  assert_int_equal(vi_model_set_forcing(m, 1.0, a, NULL, NULL), VI_ERR_NONFINITE);
  assert_msg_has(m, "a(2)");
  assert_int_equal(vi_model_set_forcing(m, NAN, NULL, NULL, NULL), VI_ERR_NONFINITE);
  double w[2] = {INFINITY, 1};
  assert_int_equal(vi_model_set_stop(m, w, 0.1, 0.5), VI_ERR_NONFINITE);
  assert_int_equal(vi_model_set_stop(m, W2, NAN, 0.5), VI_ERR_NONFINITE);
  assert_int_equal(vi_model_set_stop(m, W2, 0.1, NAN), VI_ERR_NONFINITE);
  vi_model_destroy(&m);
}

static void test_symmetry_and_definiteness(void **state)
{
  (void)state;
  vi_model *m = fresh2();
  const double Kns[4] = {2, -1, -0.9, 1}; /* K(2,1) = -1, K(1,2) = -0.9 */
  assert_int_equal(vi_model_set_stiffness(m, Kns, 2), VI_ERR_NOT_SYMMETRIC);
  assert_msg_has(m, "K(2,1)");
  assert_int_equal(vi_model_set_damping(m, Kns, 2), VI_ERR_NOT_SYMMETRIC);
  assert_int_equal(vi_model_set_mass(m, Kns, 2), VI_ERR_NOT_SYMMETRIC);

  const double Mbad[4] = {1, 2, 2, 1}; /* eigenvalues 3, -1 */
  assert_int_equal(vi_model_set_mass(m, Mbad, 2), VI_OK);
  assert_int_equal(vi_model_set_stiffness(m, K2, 2), VI_OK);
  assert_int_equal(vi_model_set_stop(m, W2, 0.1, 0.7), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_ERR_NOT_SPD);
  assert_msg_has(m, "M is not positive definite");
  const double Msing[4] = {1, 1, 1, 1}; /* semidefinite is not enough for M */
  assert_int_equal(vi_model_set_mass(m, Msing, 2), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_ERR_NOT_SPD);
  assert_msg_has(m, "Cholesky fails at column 2");
  /* a massless dof (a lumped FE mass): named, and where to take it */
  const double Mzero[4] = {1, 0, 0, 0};
  assert_int_equal(vi_model_set_mass(m, Mzero, 2), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_ERR_NOT_SPD);
  assert_msg_has(m, "dof 2 has no mass");
  assert_msg_has(m, "vi_fe_setup");

  assert_int_equal(vi_model_set_mass(m, I2, 2), VI_OK);
  const double Kind[4] = {1, 0, 0, -0.5};
  assert_int_equal(vi_model_set_stiffness(m, Kind, 2), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_ERR_NOT_PSD);
  assert_msg_has(m, "K is not positive semidefinite");
  assert_int_equal(vi_model_set_stiffness(m, K2, 2), VI_OK);
  assert_int_equal(vi_model_set_damping(m, Kind, 2), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_ERR_NOT_PSD);
  assert_msg_has(m, "C is not positive semidefinite");
  /* a rigid-body mode (K singular, semidefinite) is allowed */
  const double Kfree[4] = {1, -1, -1, 1};
  assert_int_equal(vi_model_set_damping(m, NULL, 2), VI_OK);
  assert_int_equal(vi_model_set_stiffness(m, Kfree, 2), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  assert_close(vi_model_omega(m)[0], 0.0, 1e-7);
  vi_model_destroy(&m);
}

static void test_stop_and_forcing(void **state)
{
  (void)state;
  vi_model *m = fresh2();
  assert_int_equal(vi_model_set_stop(m, W2, 0.1, 1.5), VI_ERR_RESTITUTION);
  assert_msg_has(m, "1.5");
  assert_int_equal(vi_model_set_stop(m, W2, 0.1, -0.01), VI_ERR_RESTITUTION);
  const double z[2] = {0, 0};
  assert_int_equal(vi_model_set_stop(m, z, 0.1, 0.5), VI_ERR_STOP_VECTOR);
  assert_int_equal(vi_model_set_stop(m, NULL, 0.1, 0.5), VI_ERR_ARG);
  const double a[2] = {0.5, 0};
  assert_int_equal(vi_model_set_forcing(m, 0.0, a, NULL, NULL), VI_ERR_FREQUENCY);
  assert_int_equal(vi_model_set_forcing(m, -0.9, NULL, a, NULL), VI_ERR_FREQUENCY);
  /* a constant load alone needs no frequency */
  assert_int_equal(vi_model_set_forcing(m, 0.0, NULL, NULL, a), VI_OK);
  /* no stop at setup */
  assert_int_equal(vi_model_setup(m), VI_ERR_STOP_VECTOR);
  assert_int_equal(vi_model_set_stop(m, W2, 0.1, 0.5), VI_OK);
  assert_int_equal(vi_model_set_stiffness(m, K2, 2), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  /* frozen */
  assert_int_equal(vi_model_set_mass(m, I2, 2), VI_ERR_STATE);
  assert_int_equal(vi_model_setup(m), VI_ERR_STATE);
  vi_model_destroy(&m);
}

static void test_sim_inputs(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  vi_sim *s = NULL;
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  const double x0bad[2] = {0.0, 0.2}; /* w.x0 = 0.2 > x_s = 0.1 */
  assert_int_equal(vi_sim_set_initial(s, 0.0, x0bad, NULL), VI_ERR_INITIAL_STATE);
  assert_non_null(strstr(vi_sim_errmsg(s), "violates the stop"));
  const double xnan[2] = {NAN, 0.0};
  assert_int_equal(vi_sim_set_initial(s, 0.0, xnan, NULL), VI_ERR_NONFINITE);
  assert_int_equal(vi_sim_set_initial(s, 5.0, NULL, NULL), VI_OK);
  assert_int_equal(vi_sim_run(s, 5.0), VI_ERR_TIME);
  assert_int_equal(vi_sim_run(s, 1.0), VI_ERR_TIME);
  assert_int_equal(vi_sim_run(s, NAN), VI_ERR_TIME);
  assert_int_equal(vi_sim_set_tolerances(s, -1e-8, 1e-10), VI_ERR_TOLERANCE);
  assert_int_equal(vi_sim_set_tolerances(s, 1e-8, 0.0), VI_ERR_TOLERANCE);
  assert_int_equal(vi_sim_set_tolerances(s, 1e-20, 1e-10), VI_ERR_TOLERANCE);
  assert_int_equal(vi_sim_set_method(s, 42), VI_ERR_ARG);
  assert_int_equal(vi_sim_set_chatter_threshold(s, -1.0), VI_ERR_ARG);
  assert_int_equal(vi_sim_set_monitor(s, 0.0, (vi_monitor_fn)1, NULL, NULL), VI_ERR_ARG);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);

  /* the exact method refuses a defective first-order system, saying why:
   * an undamped rigid-body mode (x = a + b t, a Jordan block) next to a
   * damper that is not proportional (free-free chain, one relative damper) */
  const double K3[9] = {1, -1, 0, -1, 2, -1, 0, -1, 1};
  const double C3[9] = {0.3, -0.3, 0, -0.3, 0.3, 0, 0, 0, 0};
  const double I3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, w3[3] = {0, 0, 1};
  vi_model *np = vi_test_model(3, I3, C3, K3, 0.0, NULL, NULL, w3, 0.1, 0.7);
  assert_int_equal(vi_model_is_proportional(np), 0);
  assert_int_equal(vi_sim_create(np, &s), VI_OK);
  assert_int_equal(vi_sim_set_method(s, VI_METHOD_EXACT), VI_ERR_UNSUPPORTED);
  assert_non_null(strstr(vi_sim_errmsg(s), "not safely diagonalisable"));
  double x[3] = {0}, v[3] = {0}, x1[3], v1[3];
  assert_int_equal(vi_flow_physical(np, 0, x, v, 1, x1, v1), VI_ERR_UNSUPPORTED);
  vi_sim_destroy(&s);
  vi_model_destroy(&np);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_dimensions),
      cmocka_unit_test(test_nonfinite),
      cmocka_unit_test(test_symmetry_and_definiteness),
      cmocka_unit_test(test_stop_and_forcing),
      cmocka_unit_test(test_sim_inputs),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
