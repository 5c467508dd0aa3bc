/* test_misuse.c - every exported function of the numerical core called as a
 * careless or hostile host would: NULL handles and arrays, zero, negative and
 * non-finite sizes and values, calls out of order, overlapping arrays.  Each
 * must return an error code (never VI_OK) and, where a handle exists, leave
 * a message; nothing may read or write out of bounds (this file runs under
 * ASan and UBSan in the sanitizer build). */
#include <math.h>
#include <string.h>

#include "vi_testutil.h"

/* an error code, and the handle's message says something */
#define assert_err(call) assert_true((call) < 0)
#define assert_err_msg(call, msg)       \
  do {                                  \
    assert_true((call) < 0);            \
    assert_true(strlen(msg) > 0);       \
  } while (0)

static void test_model_misuse(void **state)
{
  (void)state;
  vi_model *m = NULL;
  assert_err(vi_model_create(0, &m));
  assert_null(m);
  assert_err(vi_model_create(-5, &m));
  assert_err(vi_model_create(2, NULL));
  vi_model_destroy(NULL);
  vi_model_destroy(&m); /* *m == NULL */
  assert_err(vi_model_set_mass(NULL, NULL, 2));
  assert_err(vi_model_setup(NULL));
  assert_string_equal(vi_model_errmsg(NULL), "");

  assert_int_equal(vi_model_create(2, &m), VI_OK);
  double M[4] = {1, 0, 0, 1}, bad[4] = {1, NAN, NAN, 1}, w[2] = {0, 1};
  assert_err_msg(vi_model_set_mass(m, NULL, 2), vi_model_errmsg(m));
  assert_err_msg(vi_model_set_mass(m, M, 1), vi_model_errmsg(m)); /* ld < n */
  assert_err_msg(vi_model_set_mass(m, M, 0), vi_model_errmsg(m));
  assert_err_msg(vi_model_set_mass(m, bad, 2), vi_model_errmsg(m));
  assert_err_msg(vi_model_set_stiffness(m, M, -2), vi_model_errmsg(m));
  assert_err_msg(vi_model_set_forcing(m, -0.9, NULL, NULL, NULL),
                 vi_model_errmsg(m)); /* a negative frequency means nothing */
  assert_err_msg(vi_model_set_forcing(m, INFINITY, NULL, NULL, NULL),
                 vi_model_errmsg(m));
  assert_err_msg(vi_model_set_stop(m, NULL, 0.1, 0.7), vi_model_errmsg(m));
  assert_err_msg(vi_model_set_stop(m, w, NAN, 0.7), vi_model_errmsg(m));
  assert_err_msg(vi_model_set_stop(m, w, 0.1, 1.5), vi_model_errmsg(m));
  assert_err_msg(vi_model_set_stop(m, w, 0.1, NAN), vi_model_errmsg(m));
  /* setup before the matrices and the stop */
  assert_err_msg(vi_model_setup(m), vi_model_errmsg(m));
  /* getters of a model that is not set up: NULL / NaN, never garbage */
  assert_null(vi_model_omega(m));
  assert_null(vi_model_modal_shapes(m, NULL));
  double x[2] = {0, 0}, q[2];
  assert_int_equal(vi_model_to_modal(m, x, q), VI_ERR_STATE);
  vi_model_destroy(&m);
  assert_null(m);

  /* a set-up model: frozen, and arrays that overlap are refused */
  m = vi_test_fig2();
  assert_err_msg(vi_model_set_mass(m, M, 2), vi_model_errmsg(m));
  /* (const handles cannot keep a message: the code says it) */
  assert_int_equal(vi_model_to_modal(m, x, x), VI_ERR_ARG);
  assert_int_equal(vi_model_from_modal(m, x, x), VI_ERR_ARG);
  assert_int_equal(vi_model_to_modal(m, NULL, q), VI_ERR_ARG);
  assert_true(isnan(vi_model_energy(m, NULL, x)));
  assert_true(isnan(vi_model_energy(NULL, x, x)));
  assert_int_equal(vi_model_n(NULL), 0);
  assert_true(vi_model_clearance(NULL) == 0.0); /* documented: 0 or NULL */
  vi_model_destroy(&m);

  /* builders */
  double mass[2] = {1, 1}, k[2] = {1, 1}, c[2] = {0.1, 0.1}, out[4];
  assert_err(vi_build_chain(0, mass, k, c, out, out, out, 2));
  assert_err(vi_build_chain(2, NULL, k, c, out, out, out, 2));
  assert_err(vi_build_chain(2, mass, k, c, out, out, out, 1));
  double negm[2] = {1, -1};
  assert_err(vi_build_chain(2, negm, k, c, out, out, out, 2));
}

static int never(const vi_event *ev, void *u)
{
  (void)ev;
  (void)u;
  return 0;
}

static int never_mon(const vi_progress *p, void *u)
{
  (void)p;
  (void)u;
  return 0;
}

static int sample_count(double t, int n, const double *x, const double *v,
                        void *u)
{
  (void)t;
  (void)n;
  (void)x;
  (void)v;
  ++*(int *)u;
  return 0;
}

static void test_sim_misuse(void **state)
{
  (void)state;
  vi_sim *s = NULL;
  vi_model *m = NULL;
  assert_err(vi_sim_create(NULL, &s));
  assert_null(s);
  assert_int_equal(vi_model_create(2, &m), VI_OK);
  assert_err(vi_sim_create(m, &s)); /* not set up */
  assert_null(s);
  vi_model_destroy(&m);
  m = vi_test_fig2();
  assert_err(vi_sim_create(m, NULL));
  vi_sim_destroy(NULL);
  vi_sim_destroy(&s);

  /* every call on a NULL handle */
  assert_err(vi_sim_set_method(NULL, VI_METHOD_ADAMS));
  assert_err(vi_sim_set_tolerances(NULL, 1e-8, 1e-10));
  assert_err(vi_sim_set_initial(NULL, 0, NULL, NULL));
  assert_err(vi_sim_set_chatter_threshold(NULL, 0));
  assert_err(vi_sim_set_restart_step(NULL, 0));
  assert_err(vi_sim_set_max_step(NULL, 0));
  assert_err(vi_sim_set_native_vector_ops(NULL, 1));
  assert_err(vi_sim_set_event_callback(NULL, never, NULL, NULL));
  assert_err(vi_sim_set_sampling(NULL, 1.0, sample_count, NULL, NULL));
  assert_err(vi_sim_set_monitor(NULL, 1.0, NULL, NULL, NULL));
  assert_err(vi_sim_set_cancel(NULL, NULL, NULL, NULL));
  assert_err(vi_sim_set_floors(NULL, 0, 0));
  assert_err(vi_sim_set_force(NULL, NULL, NULL, NULL, NULL));
  assert_err(vi_sim_add_spring(NULL, VI_SPRING_CUBIC, 1, 0, 1, 0));
  assert_err(vi_sim_clear_springs(NULL));
  assert_err(vi_sim_ledger_force(NULL, NULL));
  assert_err(vi_sim_setup(NULL));
  int kind;
  assert_err(vi_sim_run_to_event(NULL, 1.0, &kind));
  assert_err(vi_sim_run(NULL, 1.0));
  assert_err(vi_sim_state(NULL, NULL, NULL, NULL));
  assert_err(vi_sim_enable_ledger(NULL, 1));
  assert_err(vi_sim_set_ledger_callback(NULL, NULL, NULL, NULL));
  assert_err(vi_sim_ledger(NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL));
  assert_int_equal(vi_sim_stat(NULL, VI_STAT_STEPS), -1);
  assert_int_equal(vi_sim_is_sticking(NULL), 0);
  assert_int_equal(vi_sim_method_used(NULL), -1);
  assert_int_equal(vi_sim_n(NULL), 0);
  assert_string_equal(vi_sim_errmsg(NULL), "");
  assert_string_equal(vi_sim_method_note(NULL), "");
  assert_true(vi_sim_ledger_max_residual(NULL) == 0.0);

  /* out-of-range values on a live sim, each with a message */
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  const char *msg = vi_sim_errmsg(s);
  assert_err_msg(vi_sim_set_method(s, -1), msg);
  assert_err_msg(vi_sim_set_method(s, VI_METHOD_COUNT), msg);
  assert_err_msg(vi_sim_set_tolerances(s, 0, 1e-10), msg);
  assert_err_msg(vi_sim_set_tolerances(s, 1e-8, -1), msg);
  assert_err_msg(vi_sim_set_tolerances(s, NAN, 1e-10), msg);
  assert_err_msg(vi_sim_set_tolerances(s, 1e-20, 1e-10), msg); /* < 2 eps */
  assert_err_msg(vi_sim_set_tolerances(s, 10.0, 1e-10), msg); /* >= 1 */
  double xbad[2] = {0, 0.5}, xnan[2] = {NAN, 0};
  assert_err_msg(vi_sim_set_initial(s, 0, xbad, NULL), msg); /* beyond stop */
  assert_err_msg(vi_sim_set_initial(s, 0, xnan, NULL), msg);
  assert_err_msg(vi_sim_set_initial(s, INFINITY, NULL, NULL), msg);
  assert_err_msg(vi_sim_set_chatter_threshold(s, -1), msg);
  assert_err_msg(vi_sim_set_restart_step(s, NAN), msg);
  assert_err_msg(vi_sim_set_max_step(s, -1), msg);
  assert_err_msg(vi_sim_set_native_vector_ops(s, 2), msg);
  int count = 0;
  assert_err_msg(vi_sim_set_sampling(s, 0.0, sample_count, &count, NULL), msg);
  assert_err_msg(vi_sim_set_sampling(s, -1.0, sample_count, &count, NULL), msg);
  assert_err_msg(vi_sim_set_sampling(s, NAN, sample_count, &count, NULL), msg);
  assert_err_msg(vi_sim_set_monitor(s, -1.0, never_mon, NULL, NULL), msg);
  assert_err_msg(vi_sim_set_floors(s, -1, 0), msg);
  assert_err_msg(vi_sim_set_floors(s, 0, NAN), msg);
  assert_err_msg(vi_sim_enable_ledger(s, 2), msg);
  assert_err_msg(vi_sim_ledger(s, NULL, NULL, NULL, NULL, NULL, NULL,
                                   NULL), msg); /* ledger not enabled */
  assert_err_msg(vi_sim_run(s, -1.0), msg);
  assert_err_msg(vi_sim_run(s, NAN), msg);
  assert_int_equal(vi_sim_stat(s, -1), -1);
  assert_int_equal(vi_sim_stat(s, VI_STAT_COUNT), -1);
  assert_null(vi_method_name(-1));
  assert_null(vi_method_name(VI_METHOD_COUNT));
  assert_int_equal(vi_method_from_name(NULL), -1);
  assert_int_equal(vi_method_from_name("rk4"), -1);
  assert_null(vi_stat_name(VI_STAT_COUNT));
  /* a sampling interval so small that the run would never end */
  assert_int_equal(vi_sim_set_sampling(s, 1e-300, sample_count, &count, NULL), VI_OK);
  assert_err_msg(vi_sim_run(s, 10.0), msg);
  assert_int_equal(count, 0);
  /* the refusals left the sim usable */
  assert_int_equal(vi_sim_set_sampling(s, 1.0, sample_count, &count, NULL), VI_OK);
  assert_int_equal(vi_sim_run(s, 10.0), VI_OK);
  assert_int_equal(count, 11);
  vi_sim_destroy(&s);
  assert_null(s);
  vi_model_destroy(&m);
}

static void test_impact_flow_misuse(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  double v[2] = {0, 1}, vp[2], vn, ie, x[2] = {0, 0}, r;
  assert_err(vi_impact_apply(NULL, v, vp, &vn, &ie));
  assert_err(vi_impact_apply(m, NULL, vp, &vn, &ie));
  assert_err(vi_impact_apply_r(m, 1.5, v, vp, &vn, &ie));
  assert_err(vi_impact_apply_r(m, NAN, v, vp, &vn, &ie));
  assert_err(vi_restitution_from_energy(-1, 1, &r));
  assert_err(vi_restitution_from_energy(2, 1, &r)); /* RE > KE_i */
  assert_err(vi_restitution_from_energy(0.5, 1, NULL));
  assert_err(vi_flow_physical(NULL, 0, x, v, 1, x, v));
  assert_err(vi_flow_physical(m, 0, x, v, -1, vp, vp)); /* backwards */
  assert_err(vi_flow_physical(m, 0, x, v, NAN, vp, vp));
  double xo[2], vo[2];
  assert_err(vi_flow_physical(m, 0, x, v, 1, x, vo)); /* x0 and x overlap */
  assert_err(vi_flow_modal(m, 0, x, v, 1, xo, xo));   /* q and qd overlap */
  assert_string_equal(vi_status_name(-1000), "VI_UNKNOWN");
  assert_true(strlen(vi_strerror(-1000)) > 0);
  vi_model_destroy(&m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_model_misuse),
      cmocka_unit_test(test_sim_misuse),
      cmocka_unit_test(test_impact_flow_misuse),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
