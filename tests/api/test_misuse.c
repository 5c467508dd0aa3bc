/* test_misuse.c - every exported function of the numerical core called as a
 * careless or hostile host would: NULL handles and arrays, zero, negative and
 * non-finite sizes and values, calls out of order, overlapping arrays.  Each
 * must return an error code (never VI_OK) and, where a handle exists, leave
 * a message; nothing may read or write out of bounds (this file runs under
 * ASan and UBSan in the sanitizer build). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vi_testutil.h"
#include "vibroimpact/vi_builders.h"
#include "vibroimpact/vi_census.h"
#include "vibroimpact/vi_orbit.h"
#include "vibroimpact/vi_truncation.h"
#include "vibroimpact/vi_version.h"

/* an error code, and the handle's message says something */
#define assert_err(call) assert_true((call) < 0)
#define assert_err_msg(call, msg)       \
  do {                                  \
    assert_true((call) < 0);            \
    assert_true(strlen(msg) > 0);       \
  } while (0)

/* vi_sparse.h: the finite-element reduction, its CSC input and host modes. */
static void test_fe_misuse(void **state)
{
  (void)state;
  vi_fe *fe = NULL;
  assert_err(vi_fe_create(0, &fe));
  assert_null(fe);
  assert_err(vi_fe_create(-3, &fe));
  assert_err(vi_fe_create(3, NULL));
  vi_fe_destroy(NULL);
  vi_fe_destroy(&fe); /* NULL handle: no-op */
  assert_string_equal(vi_fe_errmsg(NULL), "");
  /* NULL handle everywhere */
  int p[4] = {0, 2, 4, 5}, i[5] = {0, 1, 1, 2, 2}, dofs[1] = {2};
  double v[5] = {2, -1, 2, -1, 1}, w[3] = {0, 0, 1}, q[3] = {0}, y[3];
  assert_err(vi_fe_set_mass_csc(NULL, VI_CSC_LOWER, 0, p, i, v));
  assert_err(vi_fe_set_stiffness_csc(NULL, VI_CSC_LOWER, 0, p, i, v));
  assert_err(vi_fe_set_damping_csc(NULL, VI_CSC_LOWER, 0, p, i, v));
  assert_err(vi_fe_set_rayleigh(NULL, 0.1, 0.1));
  assert_err(vi_fe_set_modal_damping(NULL, 1, v));
  assert_err(vi_fe_set_modes(NULL, 1));
  assert_err(vi_fe_set_shift(NULL, 0.0));
  assert_err(vi_fe_set_eigensolver(NULL, 0.0, 0, 0));
  assert_err(vi_fe_set_memory_limit(NULL, 0));
  assert_err(vi_fe_set_host_modes(NULL, 1, v, NULL, NULL, 0, 1, dofs, v, 1));
  assert_err(vi_fe_add_stop(NULL, w, 0.0, 0.5));
  assert_err(vi_fe_add_stop_dof(NULL, 0, 1, 0.0, 0.5));
  assert_err(vi_fe_set_forcing(NULL, 1.0, w, NULL, NULL));
  assert_err(vi_fe_set_outputs(NULL, 1, dofs));
  assert_err(vi_fe_set_keep_shapes(NULL, 1));
  assert_err(vi_fe_setup(NULL));
  vi_model *m = NULL;
  assert_err(vi_fe_create_model(NULL, &m));
  assert_null(m);
  assert_int_equal(vi_fe_n(NULL), 0);
  assert_int_equal(vi_fe_num_modes(NULL), 0);
  assert_int_equal(vi_fe_num_stops(NULL), 0);
  assert_null(vi_fe_omega(NULL));
  int ld = 7;
  assert_null(vi_fe_modal_damping(NULL, &ld));
  assert_int_equal(ld, 0);
  assert_null(vi_fe_modal_stops(NULL, &ld));
  assert_null(vi_fe_output_shapes(NULL, &ld));
  assert_null(vi_fe_shapes(NULL, &ld));
  assert_true(vi_fe_shift(NULL) == 0.0);
  assert_true(vi_fe_residual(NULL) == 0.0);
  assert_null(vi_fe_mode_residuals(NULL));
  assert_null(vi_fe_mode_rigidity(NULL));
  int nml = 7, nrg = 7, rule = 7;
  double orth = 0.0;
  assert_err(vi_fe_summary(NULL, &nml, &nrg, &rule, &orth));
  assert_true(nml == 0 && nrg == 0 && isnan(orth));
  assert_err(vi_fe_set_rigid_modes(NULL, 1));
  assert_err(vi_fe_set_accuracy(NULL, 1e-8));
  double dyn, sta;
  assert_err(vi_fe_stop_compliance(NULL, 0, &dyn, &sta));
  int nnz;
  const int *cp, *ri;
  const double *vv;
  assert_err(vi_fe_matrix_csc(NULL, VI_FE_MASS, &nnz, &cp, &ri, &vv));
  assert_err(vi_fe_to_outputs(NULL, 1, q, 3, y, 3));
  assert_err(vi_fe_to_modal(NULL, w, q));
  int64_t bytes = 1;
  assert_err(vi_fe_memory_estimate(0, 5, 1, 0, &bytes));
  assert_int_equal(bytes, 0);
  assert_err(vi_fe_memory_estimate(3, -1, 1, 0, &bytes));
  assert_err(vi_fe_memory_estimate(3, 5, 4, 0, &bytes)); /* k > n */
  assert_err(vi_fe_memory_estimate(3, 5, 1, 2, &bytes));
  assert_err(vi_fe_memory_estimate(3, 5, 1, 0, NULL));
  assert_int_equal(vi_fe_memory_estimate(3, 5, 1, 0, &bytes), VI_OK);
  assert_true(bytes > 0);
  /* vi_model_create_modal */
  double om[2] = {1, 2}, zz[2] = {0.1, 0.1}, neg[2] = {-1, 2}, D[4] = {1, 0, 0, 1};
  assert_err(vi_model_create_modal(0, om, NULL, NULL, 0, &m));
  assert_err(vi_model_create_modal(2, NULL, NULL, NULL, 0, &m));
  assert_err(vi_model_create_modal(2, neg, NULL, NULL, 0, &m));
  assert_err(vi_model_create_modal(2, om, zz, D, 2, &m)); /* both */
  assert_err(vi_model_create_modal(2, om, NULL, D, 1, &m)); /* ldd */
  assert_err(vi_model_create_modal(2, om, neg, NULL, 0, &m));
  double nan2[2] = {NAN, 1};
  assert_err(vi_model_create_modal(2, nan2, NULL, NULL, 0, &m));
  assert_err(vi_model_create_modal(2, om, NULL, NULL, 0, NULL));
  assert_null(m);

  /* a real handle: bad arguments, each with a message */
  assert_int_equal(vi_fe_create(3, &fe), VI_OK);
  assert_err_msg(vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 0, NULL, i, v), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 0, p, NULL, v), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 0, p, i, NULL), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_mass_csc(fe, 7, 0, p, i, v), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_mass_csc(fe, VI_CSC_LOWER, -1, p, i, v), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_stiffness_csc(fe, VI_CSC_FULL, 1, p, i, v), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_damping_csc(fe, VI_CSC_LOWER, 0, p, NULL, v), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_rayleigh(fe, -1.0, 0.0), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_rayleigh(fe, NAN, 0.0), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_modal_damping(fe, 0, v), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_modal_damping(fe, 1, NULL), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_modal_damping(fe, 2, neg), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_modes(fe, 0), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_modes(fe, 4), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_shift(fe, INFINITY), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_rigid_modes(fe, -2), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_rigid_modes(fe, 4), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_accuracy(fe, 0.0), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_accuracy(fe, NAN), vi_fe_errmsg(fe));
  assert_int_equal(vi_fe_summary(fe, NULL, NULL, NULL, NULL), VI_ERR_STATE);
  assert_err_msg(vi_fe_set_eigensolver(fe, -1.0, 0, 0), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_eigensolver(fe, 0.0, 4, 0), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_eigensolver(fe, 0.0, 0, -1), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_memory_limit(fe, -1), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_host_modes(fe, 0, v, NULL, NULL, 0, 1, dofs, v, 1), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_host_modes(fe, 1, NULL, NULL, NULL, 0, 1, dofs, v, 1), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_host_modes(fe, 1, v, NULL, NULL, 0, 2, dofs, v, 1), vi_fe_errmsg(fe));
  int oor[1] = {3};
  assert_err_msg(vi_fe_set_host_modes(fe, 1, v, NULL, NULL, 0, 1, oor, v, 1), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_host_modes(fe, 2, om, zz, D, 2, 1, dofs, v, 1), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_add_stop(fe, NULL, 0.0, 0.5), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_add_stop(fe, q, 0.0, 0.5), vi_fe_errmsg(fe)); /* zero */
  assert_err_msg(vi_fe_add_stop(fe, w, 0.0, 1.5), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_add_stop(fe, w, NAN, 0.5), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_add_stop_dof(fe, 3, 1, 0.0, 0.5), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_add_stop_dof(fe, 0, 0, 0.0, 0.5), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_forcing(fe, 0.0, w, NULL, NULL), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_forcing(fe, -1.0, NULL, NULL, NULL), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_forcing(fe, NAN, NULL, NULL, w), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_outputs(fe, -1, dofs), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_outputs(fe, 1, NULL), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_outputs(fe, 1, oor), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_set_keep_shapes(fe, 2), vi_fe_errmsg(fe));
  /* out of order: before setup */
  assert_err_msg(vi_fe_setup(fe), vi_fe_errmsg(fe)); /* no matrices */
  assert_int_equal(vi_fe_create_model(fe, &m), VI_ERR_STATE);
  assert_err(vi_fe_create_model(fe, NULL));
  assert_null(vi_fe_omega(fe));
  assert_err(vi_fe_stop_compliance(fe, 0, &dyn, &sta));
  assert_int_equal(vi_fe_matrix_csc(fe, VI_FE_MASS, &nnz, &cp, &ri, &vv), VI_ERR_STATE);
  assert_null(cp);
  assert_err(vi_fe_matrix_csc(fe, 5, &nnz, &cp, &ri, &vv));
  assert_err(vi_fe_to_outputs(fe, 1, q, 3, y, 3));
  assert_err(vi_fe_to_modal(fe, w, q));
  /* set up a 3-dof chain, then misuse the frozen reduction */
  assert_int_equal(vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 0, p, i, (double[]){1, 0, 1, 0, 1}), VI_OK);
  assert_int_equal(vi_fe_set_stiffness_csc(fe, VI_CSC_LOWER, 0, p, i, v), VI_OK);
  assert_int_equal(vi_fe_set_modes(fe, 3), VI_OK);
  assert_int_equal(vi_fe_add_stop_dof(fe, 2, 1, 0.1, 0.5), VI_OK);
  assert_int_equal(vi_fe_set_outputs(fe, 1, dofs), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_ERR_STATE);
  assert_err_msg(vi_fe_set_modes(fe, 1), vi_fe_errmsg(fe));
  assert_err_msg(vi_fe_add_stop(fe, w, 0.0, 0.5), vi_fe_errmsg(fe));
  assert_err(vi_fe_stop_compliance(fe, 1, &dyn, &sta));
  assert_err(vi_fe_stop_compliance(fe, -1, &dyn, &sta));
  assert_err(vi_fe_to_outputs(fe, -1, q, 3, y, 3));
  assert_err(vi_fe_to_outputs(fe, 1, q, 2, y, 3)); /* ldq < k */
  assert_err(vi_fe_to_outputs(fe, 1, q, 3, y, 0)); /* ldy < nout */
  assert_err(vi_fe_to_outputs(fe, 1, q, 3, q, 3)); /* overlap */
  assert_err(vi_fe_to_outputs(fe, 1, NULL, 3, y, 3));
  assert_int_equal(vi_fe_to_modal(fe, w, q), VI_ERR_STATE); /* no shapes kept */
  assert_err(vi_fe_to_modal(fe, w, NULL));
  assert_int_equal(vi_fe_create_model(fe, &m), VI_OK);
  vi_model_destroy(&m);
  vi_fe_destroy(&fe);
  assert_null(fe);
}

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
  assert_err(vi_sim_set_impact_resolution(NULL, 1e-5));
  assert_true(vi_sim_velocity_scale(NULL) == 0.0);
  assert_err(vi_sim_set_restart_step(NULL, 0));
  assert_err(vi_sim_set_max_step(NULL, 0));
  assert_err(vi_sim_set_native_vector_ops(NULL, 1));
  assert_err(vi_sim_set_event_callback(NULL, never, NULL, NULL));
  assert_err(vi_sim_set_event_states(NULL, 0));
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
  assert_err_msg(vi_sim_set_impact_resolution(s, -1e-5), msg);
  assert_err_msg(vi_sim_set_impact_resolution(s, 1.0), msg);
  assert_err_msg(vi_sim_set_impact_resolution(s, NAN), msg);
  assert_err_msg(vi_sim_set_restart_step(s, NAN), msg);
  assert_err_msg(vi_sim_set_max_step(s, -1), msg);
  assert_err_msg(vi_sim_set_native_vector_ops(s, 2), msg);
  assert_err_msg(vi_sim_set_event_states(s, 2), msg);
  assert_err_msg(vi_sim_set_event_states(s, -1), msg);
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

  /* the API refuses what a scene refuses (one check, vi_model_check_run),
   * at once instead of running endlessly */
  const char *key = "x";
  double val = 0;
  char why[200];
  assert_int_equal(vi_model_check_run(NULL, 0, 1, NULL, NULL, 1e-8, 1e-10,
                                      &key, &val, why, (int)sizeof why), VI_ERR_ARG);
  assert_int_equal(vi_model_check_run(m, 0, NAN, NULL, NULL, 1e-8, 1e-10,
                                      &key, &val, why, (int)sizeof why), VI_ERR_NONFINITE);
  assert_int_equal(vi_model_check_run(m, 0, 10, NULL, NULL, 1e-8, 1e-10,
                                      NULL, NULL, NULL, 0), VI_OK);
  assert_int_equal(vi_model_check_run(m, 1e300, 2e300, NULL, NULL, 1e-8, 1e-10,
                                      &key, &val, why, (int)sizeof why), VI_ERR_LIMIT);
  assert_string_equal(key, "run.t_end");
  assert_int_equal(vi_model_check_run(m, 0, 10, NULL, NULL, 1e-8, 1e300,
                                      &key, &val, why, (int)sizeof why), VI_ERR_LIMIT);
  assert_string_equal(key, "run.atol");
  assert_true(val == 1e300);
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_sim_set_initial(s, 1e300, NULL, NULL), VI_OK);
  assert_err_msg(vi_sim_run(s, 1.1e300), msg = vi_sim_errmsg(s));
  assert_non_null(strstr(msg, "resolves"));
  assert_int_equal(vi_sim_set_initial(s, 0, NULL, NULL), VI_OK);
  assert_int_equal(vi_sim_set_tolerances(s, 1e-8, 1e300), VI_OK);
  assert_int_equal(vi_sim_run(s, 10.0), VI_ERR_LIMIT);
  assert_non_null(strstr(msg, "atol"));
  assert_int_equal(vi_sim_set_tolerances(s, 0.5, 1e-10), VI_OK);
  assert_int_equal(vi_sim_run(s, 10.0), VI_ERR_LIMIT); /* rtol above 0.1 */
  assert_int_equal(vi_sim_set_tolerances(s, 1e-8, 1e-10), VI_OK);
  assert_int_equal(vi_sim_set_max_step(s, 1e-300), VI_OK);
  assert_int_equal(vi_sim_run(s, 10.0), VI_ERR_LIMIT);
  assert_non_null(strstr(msg, "max step"));
  assert_int_equal(vi_sim_set_max_step(s, 0), VI_OK);
  assert_int_equal(vi_sim_run(s, 10.0), VI_OK);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
  /* a forcing frequency 1e300 times the structure's */
  double a[2] = {0.5, 0};
  m = vi_test_chain(2, 1.0, 1.0, 0.1, 0.1, 0.7, 1e300, a);
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_sim_run(s, 1.0), VI_ERR_LIMIT);
  assert_non_null(strstr(vi_sim_errmsg(s), "forcing frequency"));
  vi_sim_destroy(&s);
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
  double xo[2], vo[2];
  assert_err(vi_flow_physical(NULL, 0, x, v, 1, x, v));
  assert_err(vi_flow_physical(m, 0, x, v, -1, vp, vp)); /* backwards */
  assert_err(vi_flow_physical(m, 0, x, v, NAN, vp, vp));
  /* a time whose phase double precision cannot resolve */
  assert_int_equal(vi_flow_physical(m, 0, x, v, 1e300, vp, vo), VI_ERR_LIMIT);
  assert_int_equal(vi_flow_modal(m, 1e300, x, v, 1e300, vp, vo), VI_ERR_LIMIT);
  assert_int_equal(vi_flow_physical(m, 0, x, v, 1e6, vp, vo), VI_OK);

  assert_err(vi_flow_physical(m, 0, x, v, 1, x, vo)); /* x0 and x overlap */
  assert_err(vi_flow_modal(m, 0, x, v, 1, xo, xo));   /* q and qd overlap */
  assert_string_equal(vi_status_name(-1000), "VI_UNKNOWN");
  assert_true(strlen(vi_strerror(-1000)) > 0);
  vi_model_destroy(&m);
}

/* band storage, chain and memory estimate, and the getters of a model that
 * is not set up, of NULL and of the wrong storage */
static void test_model_band_getters_misuse(void **state)
{
  (void)state;
  vi_model *m = NULL;
  assert_int_equal(vi_model_create_band(0, 1, &m), VI_ERR_DIM);
  assert_null(m);
  assert_int_equal(vi_model_create_band(3, -1, &m), VI_ERR_DIM);
  assert_null(m);
  assert_err(vi_model_create_band(3, 1, NULL));
  /* n = 1.5e9: the size in 64 bits (a 32-bit product would wrap to a small
   * block and the first write would corrupt the heap) */
#ifndef __SANITIZE_ADDRESS__ /* ASan aborts on a failed 264 GB calloc */
  {
    int big = vi_model_create_band(1500000000, 1, &m);
    assert_true(big == VI_ERR_NOMEM || big == VI_OK);
    if (big == VI_OK) assert_true(vi_model_memory(m) > (int64_t)1500000000 * 20 * 8);
    vi_model_destroy(&m);
  }
#endif
  double AB[6] = {0, 1, 0, 1, 0, 1}, ABn[6] = {0, 1, 0, NAN, 0, 1};
  assert_err(vi_model_set_mass_band(NULL, 1, AB, 2));
  assert_err(vi_model_set_damping_band(NULL, 1, AB, 2));
  assert_err(vi_model_set_stiffness_band(NULL, 1, AB, 2));
  assert_int_equal(vi_model_create_band(3, 1, &m), VI_OK);
  const char *msg = vi_model_errmsg(m);
  assert_int_equal(vi_model_set_mass_band(m, -1, AB, 2), VI_ERR_DIM);
  assert_true(strlen(msg) > 0);
  assert_int_equal(vi_model_set_mass_band(m, 1, AB, 1), VI_ERR_DIM); /* ldab < kd + 1 */
  assert_int_equal(vi_model_set_damping_band(m, 1, AB, 0), VI_ERR_DIM);
  assert_int_equal(vi_model_set_stiffness_band(m, 1, AB, -3), VI_ERR_DIM);
  assert_err_msg(vi_model_set_mass_band(m, 1, NULL, 2), msg);
  assert_err_msg(vi_model_set_stiffness_band(m, 1, NULL, 2), msg);
  assert_err_msg(vi_model_set_mass_band(m, 1, ABn, 2), msg);
  assert_err_msg(vi_model_set_stiffness_band(m, 1, ABn, 2), msg);
  assert_err_msg(vi_model_set_damping_band(m, 1, ABn, 2), msg);
  /* kd beyond the model's own half-bandwidth with non-zeros there */
  double AB2[9] = {5, 0, 1, 5, 0, 1, 5, 0, 1};
  assert_int_equal(vi_model_set_stiffness_band(m, 2, AB2, 3), VI_ERR_DIM);
  assert_true(strlen(msg) > 0);
  /* a band model has no dense matrices and no modes, even before setup */
  assert_null(vi_model_mass(m));
  assert_int_equal(vi_model_bandwidth(m), 1); /* known before setup */
  int kd = 7, ld = 7;
  assert_null(vi_model_mass_band(m, &kd, &ld)); /* before setup */
  vi_model_destroy(&m);

  double mass[3] = {1, 1, 1}, k[3] = {1, 1, 1}, negk[3] = {1, -1, 1};
  double nank[3] = {1, NAN, 1};
  assert_int_equal(vi_model_create_chain(0, mass, k, NULL, &m), VI_ERR_DIM);
  assert_null(m);
  assert_int_equal(vi_model_create_chain(-3, mass, k, NULL, &m), VI_ERR_DIM);
  assert_err(vi_model_create_chain(3, NULL, k, NULL, &m));
  assert_null(m);
  assert_err(vi_model_create_chain(3, mass, NULL, NULL, &m));
  assert_null(m);
  assert_err(vi_model_create_chain(3, mass, negk, NULL, &m));
  assert_null(m);
  assert_err(vi_model_create_chain(3, mass, nank, NULL, &m));
  assert_null(m);
  assert_err(vi_model_create_chain(3, mass, k, NULL, NULL));

  int64_t bytes = 0;
  assert_int_equal(vi_model_memory_estimate(0, -1, 1, VI_METHOD_ADAMS, 0, &bytes),
                   VI_ERR_DIM);
  assert_int_equal(vi_model_memory_estimate(3, -1, -1, VI_METHOD_ADAMS, 0, &bytes),
                   VI_ERR_DIM);
  assert_err(vi_model_memory_estimate(3, -1, 1, -1, 0, &bytes));
  assert_err(vi_model_memory_estimate(3, -1, 1, VI_METHOD_COUNT, 0, &bytes));
  assert_err(vi_model_memory_estimate(3, -1, 1, VI_METHOD_ADAMS, 2, &bytes));
  assert_err(vi_model_memory_estimate(3, -1, 1, VI_METHOD_ADAMS, 0, NULL));
  assert_int_equal(vi_model_memory_estimate(3, 1, 1, VI_METHOD_EXACT, 0, &bytes),
                   VI_ERR_UNSUPPORTED);
  assert_int_equal(vi_model_memory_estimate(3, 1, 1, VI_METHOD_ADAMS, 1, &bytes),
                   VI_ERR_UNSUPPORTED);
  assert_int_equal(vi_model_memory_estimate(2000000000, -1, 1, VI_METHOD_BDF,
                                            0, &bytes), VI_ERR_LIMIT);

  /* NULL model: the documented 0 / NULL / -1 */
  assert_true(vi_model_omega_bound(NULL) == 0.0);
  assert_int_equal(vi_model_memory(NULL), 0);
  assert_int_equal(vi_model_bandwidth(NULL), -1);
  assert_int_equal(vi_model_num_stops(NULL), 0);
  double w[2], xs, r;
  assert_err(vi_model_stop(NULL, 0, w, &xs, &r));
  assert_err(vi_model_set_damping(NULL, NULL, 2));
  assert_err(vi_model_set_forcing(NULL, 1, NULL, NULL, NULL));
  assert_err(vi_model_set_stop(NULL, w, 0.1, 0.5));
  assert_err(vi_model_add_stop(NULL, w, 0.1, 0.5));
  int ldg = 5;
  assert_null(vi_model_delassus(NULL, &ldg));
  assert_true(vi_model_omega_forcing(NULL) == 0.0);
  assert_true(vi_model_forcing_period(NULL) == 0.0);
  assert_true(vi_model_restitution(NULL) == 0.0);
  assert_true(vi_model_stop_compliance(NULL) == 0.0);
  assert_null(vi_model_mass(NULL));
  assert_null(vi_model_damping(NULL));
  assert_null(vi_model_stiffness(NULL));
  assert_null(vi_model_mass_band(NULL, &kd, &ld));
  assert_null(vi_model_damping_band(NULL, &kd, &ld));
  assert_null(vi_model_stiffness_band(NULL, &kd, &ld));
  assert_null(vi_model_stop_vector(NULL));
  assert_null(vi_model_forcing_cos(NULL));
  assert_null(vi_model_forcing_sin(NULL));
  assert_null(vi_model_forcing_const(NULL));
  assert_null(vi_model_omega(NULL));
  assert_null(vi_model_modal_shapes(NULL, &ld));
  assert_null(vi_model_modal_damping(NULL, &ld));
  assert_null(vi_model_zeta(NULL));
  assert_int_equal(vi_model_is_proportional(NULL), 0);
  assert_null(vi_model_modal_stop(NULL));
  assert_null(vi_model_modal_forcing_cos(NULL));
  assert_null(vi_model_modal_forcing_sin(NULL));
  assert_null(vi_model_modal_forcing_const(NULL));
  double x[2] = {0, 0}, q[2];
  assert_err(vi_model_from_modal(NULL, x, q));

  /* a dense model before setup: getters 0 / NULL; stop k out of range */
  assert_int_equal(vi_model_create(2, &m), VI_OK);
  msg = vi_model_errmsg(m);
  double w0[2] = {0, 0}, wn[2] = {NAN, 1}, w1[2] = {0, 1};
  assert_int_equal(vi_model_add_stop(m, NULL, 0.1, 0.5), VI_ERR_ARG);
  assert_int_equal(vi_model_add_stop(m, w0, 0.1, 0.5), VI_ERR_STOP_VECTOR);
  assert_true(strlen(msg) > 0);
  assert_int_equal(vi_model_add_stop(m, wn, 0.1, 0.5), VI_ERR_NONFINITE);
  assert_int_equal(vi_model_add_stop(m, w1, 0.1, -0.5), VI_ERR_RESTITUTION);
  assert_int_equal(vi_model_add_stop(m, w1, INFINITY, 0.5), VI_ERR_NONFINITE);
  assert_int_equal(vi_model_num_stops(m), 0); /* the refusals added none */
  assert_int_equal(vi_model_stop(m, 0, w, &xs, &r), VI_ERR_ARG); /* none yet */
  assert_err_msg(vi_model_set_damping(m, x, 1), msg); /* ld < n */
  double Cn[4] = {0, NAN, NAN, 0};
  assert_err_msg(vi_model_set_damping(m, Cn, 2), msg);
  double Cs[4] = {0, 1, 0, 0};
  assert_err_msg(vi_model_set_damping(m, Cs, 2), msg); /* not symmetric */
  double an[2] = {NAN, 0};
  assert_err_msg(vi_model_set_forcing(m, 1.0, an, NULL, NULL), msg);
  assert_err_msg(vi_model_set_forcing(m, 1.0, NULL, NULL, an), msg);
  assert_err_msg(vi_model_set_forcing(m, 0.0, x, w1, NULL), msg);
  assert_null(vi_model_delassus(m, &ldg));
  assert_true(vi_model_omega_bound(m) == 0.0);
  assert_null(vi_model_stop_vector(m));
  assert_null(vi_model_zeta(m));
  assert_null(vi_model_modal_damping(m, &ld));
  assert_null(vi_model_modal_stop(m));
  assert_true(vi_model_stop_compliance(m) == 0.0);
  assert_int_equal(vi_model_from_modal(m, x, q), VI_ERR_STATE);
  vi_model_destroy(&m);

  /* a set-up dense model: stop k = -1 and k = ns, overlapping and NULL
   * arrays, and the band getters of dense storage */
  m = vi_test_fig2();
  assert_int_equal(vi_model_stop(m, -1, w, &xs, &r), VI_ERR_ARG);
  assert_int_equal(vi_model_stop(m, 1, w, &xs, &r), VI_ERR_ARG); /* k = ns */
  assert_err_msg(vi_model_add_stop(m, w1, 0.2, 0.5), msg = vi_model_errmsg(m)); /* frozen */
  assert_int_equal(vi_model_num_stops(m), 1);
  assert_err_msg(vi_model_set_damping_band(m, 1, AB, 2), msg); /* frozen */
  kd = 7;
  ld = 7;
  assert_null(vi_model_mass_band(m, &kd, &ld));
  assert_int_equal(kd, 0);
  assert_int_equal(ld, 0);
  assert_null(vi_model_damping_band(m, &kd, &ld));
  assert_null(vi_model_stiffness_band(m, NULL, NULL));
  assert_int_equal(vi_model_bandwidth(m), -1);
  assert_int_equal(vi_model_from_modal(m, NULL, q), VI_ERR_ARG);
  assert_int_equal(vi_model_from_modal(m, x, NULL), VI_ERR_ARG);
  assert_int_equal(vi_model_to_modal(m, x, NULL), VI_ERR_ARG);
  assert_true(isnan(vi_model_energy(m, x, NULL)));
  vi_model_destroy(&m);

  /* a set-up band model: no dense matrices, no modes */
  double chm[3] = {1, 1, 1}, wb[3] = {0, 0, 1};
  assert_int_equal(vi_model_create_chain(3, chm, k, NULL, &m), VI_OK);
  assert_int_equal(vi_model_set_stop(m, wb, 0.1, 0.7), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  assert_null(vi_model_mass(m));
  assert_null(vi_model_damping(m));
  assert_null(vi_model_stiffness(m));
  assert_null(vi_model_omega(m));
  assert_null(vi_model_modal_shapes(m, &ld));
  assert_null(vi_model_modal_forcing_cos(m));
  double x3[3] = {0, 0, 0}, q3[3];
  assert_int_equal(vi_model_to_modal(m, x3, q3), VI_ERR_UNSUPPORTED);
  assert_int_equal(vi_model_from_modal(m, x3, q3), VI_ERR_UNSUPPORTED);
  vi_model_destroy(&m);
}

static void test_builders_misuse(void **state)
{
  (void)state;
  double mass[2] = {1, 1}, k[2] = {1, 1}, c[2] = {0.1, 0.1}, out[4], o2[4],
         o3[4], negc[2] = {0.1, -0.1}, nanm[2] = {1, NAN};
  assert_err(vi_build_chain(-2, mass, k, c, out, o2, o3, 2));
  assert_err(vi_build_chain(2, mass, NULL, c, out, o2, o3, 2));
  assert_err(vi_build_chain(2, mass, k, negc, out, o2, o3, 2));
  assert_err(vi_build_chain(2, nanm, k, c, out, o2, o3, 2));
  assert_err(vi_build_chain(2, mass, k, c, NULL, o2, o3, 2));
  assert_err(vi_build_chain_band(0, mass, k, c, out, o2, o3, 2));
  assert_err(vi_build_chain_band(2, NULL, k, c, out, o2, o3, 2));
  assert_err(vi_build_chain_band(2, mass, k, c, out, o2, o3, 1)); /* ldab < 2 */
  assert_err(vi_build_chain_band(2, mass, k, c, out, o2, NULL, 2));

  assert_true(isnan(vi_cantilever_beta(-1)));
  assert_true(isnan(vi_cantilever_beta(201)));
  assert_true(isnan(vi_cantilever_shape(-1, 0.5)));
  assert_true(isnan(vi_cantilever_shape(201, 0.5)));
  assert_true(isnan(vi_cantilever_shape(0, NAN)));
  assert_true(isnan(vi_cantilever_participation(-1)));
  assert_true(isnan(vi_cantilever_participation(201)));
  double M[4], C[4], K[4], w[2], g[2];
  assert_err(vi_build_cantilever(0, 1, 0.01, 1, M, C, K, 2, w, g));
  assert_err(vi_build_cantilever(-2, 1, 0.01, 1, M, C, K, 2, w, g));
  assert_err(vi_build_cantilever(2, 1, 0.01, 1, M, C, K, 1, w, g)); /* ld < modes */
  assert_err(vi_build_cantilever(2, -1, 0.01, 1, M, C, K, 2, w, g));
  /* the stop at the clamp (or within round-off of it) can never be hit */
  assert_int_equal(vi_build_cantilever(2, 1, 0.01, 0.0, M, C, K, 2, w, g), VI_ERR_STOP_VECTOR);
  assert_int_equal(vi_build_cantilever(2, 1, 0.01, 1e-7, M, C, K, 2, w, g), VI_ERR_STOP_VECTOR);
  assert_int_equal(vi_build_cantilever(2, 1, 0.01, 0.01, M, C, K, 2, w, g), VI_OK);
  assert_err(vi_build_cantilever(2, NAN, 0.01, 1, M, C, K, 2, w, g));
  assert_err(vi_build_cantilever(2, 1, -0.01, 1, M, C, K, 2, w, g));
  assert_err(vi_build_cantilever(2, 1, 0.01, 1.5, M, C, K, 2, w, g));
  assert_err(vi_build_cantilever(2, 1, 0.01, 1, NULL, C, K, 2, w, g));
  assert_err(vi_build_cantilever(2, 1, 0.01, 1, M, C, K, 2, NULL, g));
  /* beyond the 201 tabulated modes beta is NaN: refused, not written */
  size_t big = 202;
  double *BM = calloc(big * big, sizeof(double)), *BC = calloc(big * big, sizeof(double)),
         *BK = calloc(big * big, sizeof(double)), *bw = calloc(big, sizeof(double));
  assert_non_null(BM);
  assert_non_null(BC);
  assert_non_null(BK);
  assert_non_null(bw);
  assert_err(vi_build_cantilever(202, 1, 0.01, 1, BM, BC, BK, 202, bw, NULL));
  free(BM);
  free(BC);
  free(BK);
  free(bw);

  vi_model *full = vi_test_fig2(), *red = NULL;
  int modes[2] = {0, 1}, bad[2] = {0, 2}, neg[1] = {-1}, dup[2] = {0, 0};
  assert_err(vi_model_create_reduced(NULL, modes, 1, 0.7, &red));
  assert_null(red);
  assert_err(vi_model_create_reduced(full, NULL, 1, 0.7, &red));
  assert_err(vi_model_create_reduced(full, modes, 0, 0.7, &red));
  assert_err(vi_model_create_reduced(full, modes, -1, 0.7, &red));
  assert_err(vi_model_create_reduced(full, modes, 3, 0.7, &red)); /* k > n */
  assert_err(vi_model_create_reduced(full, bad, 2, 0.7, &red));
  assert_err(vi_model_create_reduced(full, neg, 1, 0.7, &red));
  assert_err(vi_model_create_reduced(full, dup, 2, 0.7, &red));
  assert_err(vi_model_create_reduced(full, modes, 1, 1.5, &red));
  assert_err(vi_model_create_reduced(full, modes, 1, NAN, &red));
  assert_err(vi_model_create_reduced(full, modes, 1, 0.7, NULL));
  assert_null(red);
  vi_model *raw = NULL;
  assert_int_equal(vi_model_create(2, &raw), VI_OK);
  assert_int_equal(vi_model_create_reduced(raw, modes, 1, 0.7, &red), VI_ERR_STATE);
  assert_null(red);
  vi_model_destroy(&raw);
  vi_model_destroy(&full);

  /* the versions: well-formed, never NULL */
  assert_true(vi_version_number() > 0);
  assert_non_null(vi_version_string());
  assert_true(strlen(vi_version_string()) >= 5);
  assert_non_null(vi_sundials_version());
  assert_true(strlen(vi_sundials_version()) > 0);
}

static void test_impact_multi_misuse(void **state)
{
  (void)state;
  /* two independent stops on a 2-DOF chain: x_1 <= 0.1 and x_2 <= 0.1 */
  double M[4] = {1, 0, 0, 1}, K[4] = {2, -1, -1, 1}, W[4] = {1, 0, 0, 1},
         xs[2] = {0.1, 0.1}, r[2] = {0.7, 0.7};
  vi_model *m = vi_test_model_stops(2, M, NULL, K, 0.9, NULL, NULL, 2, W, xs, r);
  int st[2] = {0, 1}, bad[1] = {2}, neg[1] = {-1}, dup[2] = {0, 0};
  double v[2] = {0, 1}, vp[2], P[2], ie[2];
  assert_err(vi_impact_apply_multi(NULL, 1, st, v, vp, P, ie));
  assert_err(vi_impact_apply_multi(m, 0, st, v, vp, P, ie));
  assert_err(vi_impact_apply_multi(m, -1, st, v, vp, P, ie));
  assert_err(vi_impact_apply_multi(m, 13, st, v, vp, P, ie));
  assert_err(vi_impact_apply_multi(m, 1, NULL, v, vp, P, ie));
  assert_err(vi_impact_apply_multi(m, 1, st, NULL, vp, P, ie));
  assert_err(vi_impact_apply_multi(m, 1, st, v, NULL, P, ie));
  assert_int_equal(vi_impact_apply_multi(m, 1, bad, v, vp, P, ie), VI_ERR_ARG);
  assert_int_equal(vi_impact_apply_multi(m, 1, neg, v, vp, P, ie), VI_ERR_ARG);
  assert_err(vi_impact_apply_multi(m, 2, dup, v, vp, P, ie)); /* G singular */
  assert_int_equal(vi_impact_apply_multi(m, 2, st, v, vp, P, P), VI_ERR_ARG); /* P, ie overlap */
  assert_int_equal(vi_impact_apply_multi(m, 2, st, v, vp, v, ie), VI_ERR_ARG); /* P over v_minus */
  assert_int_equal(vi_impact_apply_multi(m, 2, st, v, vp, P, vp), VI_ERR_ARG); /* ie over v_plus */
  double vnan[2] = {0, NAN};
  assert_err(vi_impact_apply_multi(m, 1, st, vnan, vp, P, ie));
  vi_model *raw = NULL;
  assert_int_equal(vi_model_create(2, &raw), VI_OK);
  assert_int_equal(vi_impact_apply_multi(raw, 1, st, v, vp, P, ie), VI_ERR_STATE);
  vi_model_destroy(&raw);

  /* vi_sim_stop_losses: NULL sim, NULL array */
  assert_err(vi_sim_stop_losses(NULL, ie));
  vi_sim *s = NULL;
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_sim_stop_losses(s, NULL), VI_ERR_ARG); /* const: code only */
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
}

static int stop_mon(const vi_progress *p, void *u)
{
  (void)p;
  (void)u;
  return 1;
}

static void test_orbit_misuse(void **state)
{
  (void)state;
  vi_orbit *o = NULL;
  assert_err(vi_orbit_create(NULL, &o));
  assert_null(o);
  vi_model *raw = NULL;
  assert_int_equal(vi_model_create(2, &raw), VI_OK);
  assert_int_equal(vi_orbit_create(raw, &o), VI_ERR_STATE);
  assert_null(o);
  vi_model *m = vi_test_fig2();
  assert_err(vi_orbit_create(m, NULL));
  vi_model *unforced = vi_test_sdof(1, 0.1, 1, 0, 0, 0, 0.1, 0.7);
  assert_int_equal(vi_orbit_create(unforced, &o), VI_ERR_FREQUENCY);
  assert_null(o);
  vi_orbit_destroy(NULL);
  vi_orbit_destroy(&o);

  /* every call on a NULL orbit */
  int n = 0, mm = 0, sc = 0, cnt = 0, stp[8];
  double d[8], x[16], v[16], re[4], im[4], rS = 0;
  int modes[2] = {0, 1};
  assert_string_equal(vi_orbit_errmsg(NULL), "");
  assert_err(vi_orbit_set_method(NULL, VI_METHOD_ADAMS));
  assert_err(vi_orbit_set_tolerances(NULL, 1e-8, 1e-10));
  assert_err(vi_orbit_set_initial(NULL, NULL, NULL));
  assert_err(vi_orbit_set_transient(NULL, 100, 1e-6));
  assert_err(vi_orbit_set_monitor(NULL, NULL, NULL, NULL));
  assert_err(vi_orbit_set_direct_search(NULL, 1));
  assert_err(vi_orbit_search_info(NULL, &n, &mm, &sc));
  assert_err(vi_orbit_find(NULL));
  assert_err(vi_orbit_classify(NULL, &n, &mm));
  assert_err(vi_orbit_balance(NULL, d, d, d, d, d, d, d, d));
  assert_err(vi_orbit_modal_balance(NULL, d, d, d, d));
  assert_err(vi_orbit_impact_state(NULL, d, x, v));
  assert_err(vi_orbit_impacts(NULL, &cnt, d, stp, d, x, v, 2));
  assert_err(vi_orbit_stop_balance(NULL, 0, &cnt, d, d, d, d, d));
  assert_err(vi_orbit_stop_modal_balance(NULL, 0, d, d, d));
  assert_err(vi_orbit_multipliers(NULL, re, im));
  assert_err(vi_orbit_min_gap(NULL, d));
  assert_err(vi_orbit_reduced_restitution(NULL, modes, 1, &rS));
  assert_err(vi_orbit_lyapunov(NULL, 10, 10, d, d));

  /* bad values on a live orbit, each with a message */
  assert_int_equal(vi_orbit_create(m, &o), VI_OK);
  const char *msg = vi_orbit_errmsg(o);
  assert_err_msg(vi_orbit_set_method(o, -1), msg);
  assert_err_msg(vi_orbit_set_method(o, VI_METHOD_COUNT), msg);
  assert_err_msg(vi_orbit_set_tolerances(o, 0, 1e-10), msg);
  assert_err_msg(vi_orbit_set_tolerances(o, 1e-8, NAN), msg);
  assert_err_msg(vi_orbit_set_tolerances(o, -1, 1e-10), msg);
  double xnan[2] = {NAN, 0}, xbeyond[2] = {0, 0.5};
  assert_err_msg(vi_orbit_set_initial(o, xnan, NULL), msg);
  assert_err_msg(vi_orbit_set_initial(o, NULL, xnan), msg);
  assert_err_msg(vi_orbit_set_initial(o, xbeyond, NULL), msg);
  assert_err_msg(vi_orbit_set_transient(o, 0, 1e-6), msg);
  assert_err_msg(vi_orbit_set_transient(o, -5, 1e-6), msg);
  assert_err_msg(vi_orbit_set_transient(o, NAN, 1e-6), msg);
  assert_err_msg(vi_orbit_set_transient(o, 100, -1e-6), msg);
  assert_err_msg(vi_orbit_set_transient(o, 100, NAN), msg);
  assert_err_msg(vi_orbit_set_direct_search(o, 2), msg);
  assert_err_msg(vi_orbit_set_direct_search(o, -1), msg);
  assert_err_msg(vi_orbit_lyapunov(o, 10, 10, NULL, d), msg);
  assert_err_msg(vi_orbit_lyapunov(o, -1, 10, d, d), msg);
  assert_err_msg(vi_orbit_lyapunov(o, NAN, 10, d, d), msg);
  assert_err_msg(vi_orbit_lyapunov(o, 10, 1, d, d), msg);
  assert_err_msg(vi_orbit_lyapunov(o, 10, INFINITY, d, d), msg);
  assert_err_msg(vi_orbit_lyapunov(o, 1e9, 10, d, d), msg);
  /* results before vi_orbit_find: VI_ERR_STATE */
  assert_int_equal(vi_orbit_balance(o, d, d, d, d, d, d, d, d), VI_ERR_STATE);
  assert_int_equal(vi_orbit_modal_balance(o, d, d, d, d), VI_ERR_STATE);
  assert_int_equal(vi_orbit_impact_state(o, d, x, v), VI_ERR_STATE);
  assert_int_equal(vi_orbit_impacts(o, &cnt, d, stp, d, x, v, 2), VI_ERR_STATE);
  assert_int_equal(vi_orbit_stop_balance(o, 0, &cnt, d, d, d, d, d), VI_ERR_STATE);
  assert_int_equal(vi_orbit_stop_modal_balance(o, 0, d, d, d), VI_ERR_STATE);
  assert_int_equal(vi_orbit_multipliers(o, re, im), VI_ERR_STATE);
  assert_int_equal(vi_orbit_min_gap(o, d), VI_ERR_STATE);
  assert_err(vi_orbit_reduced_restitution(o, modes, 1, &rS));
  /* a monitor that stops at once: VI_STOPPED, not an analysis */
  assert_int_equal(vi_orbit_set_monitor(o, stop_mon, NULL, NULL), VI_OK);
  assert_int_equal(vi_orbit_find(o), VI_STOPPED);
  assert_int_equal(vi_orbit_balance(o, d, d, d, d, d, d, d, d), VI_ERR_STATE);
  assert_int_equal(vi_orbit_set_monitor(o, NULL, NULL, NULL), VI_OK);
  /* the analysed Fig. 2 orbit (P(1,1)): out-of-range indices, ld < n */
  assert_int_equal(vi_orbit_find(o), VI_OK);
  assert_int_equal(vi_orbit_classify(o, &n, &mm), VI_OK);
  assert_int_equal(n, 1);
  assert_int_equal(mm, 1);
  assert_int_equal(vi_orbit_impacts(o, &cnt, d, stp, d, x, v, 1), VI_ERR_ARG);
  assert_int_equal(vi_orbit_impacts(o, &cnt, d, stp, d, x, NULL, 0), VI_ERR_ARG);
  assert_int_equal(vi_orbit_stop_balance(o, -1, &cnt, d, d, d, d, d), VI_ERR_ARG);
  assert_int_equal(vi_orbit_stop_balance(o, 1, &cnt, d, d, d, d, d), VI_ERR_ARG); /* k = ns */
  assert_int_equal(vi_orbit_stop_modal_balance(o, -1, d, d, d), VI_ERR_ARG);
  assert_int_equal(vi_orbit_stop_modal_balance(o, 1, d, d, d), VI_ERR_ARG);
  int badm[1] = {2}, negm[1] = {-1};
  rS = 0;
  assert_int_equal(vi_orbit_reduced_restitution(o, badm, 1, &rS), VI_ERR_ARG);
  assert_true(isnan(rS));
  assert_int_equal(vi_orbit_reduced_restitution(o, negm, 1, &rS), VI_ERR_ARG);
  assert_err(vi_orbit_reduced_restitution(o, NULL, 1, &rS));
  assert_err(vi_orbit_reduced_restitution(o, modes, 0, &rS));
  assert_err(vi_orbit_reduced_restitution(o, modes, -1, &rS));
  assert_err(vi_orbit_reduced_restitution(o, modes, 3, &rS));
  assert_err(vi_orbit_reduced_restitution(o, modes, 1, NULL));
  /* the orbit still answers after the refusals */
  assert_int_equal(vi_orbit_search_info(o, NULL, NULL, NULL), VI_OK);
  assert_int_equal(vi_orbit_min_gap(o, d), VI_OK);
  vi_orbit_destroy(&o);
  assert_null(o);

  /* P(n, m) functions: one impact per period of Fig. 2 */
  double t[1] = {0}, x1[2] = {0, 0.1}, v1[2] = {0, 0.1}, F[5], J[25], Mo[16];
  double dF[5], g = 0;
  int st0[1] = {0}, st1[1] = {1}, stn[1] = {-1}, it = 0, ok = 0, found = 0;
  assert_err(vi_orbit_pnm_solve(NULL, 1, 1, t, x1, v1, 2, 0, &it));
  assert_err(vi_orbit_pnm_solve(m, 0, 1, t, x1, v1, 2, 0, &it));
  assert_err(vi_orbit_pnm_solve(m, 1, 0, t, x1, v1, 2, 0, &it));
  assert_err(vi_orbit_pnm_solve(m, 1, -1, t, x1, v1, 2, 0, &it));
  assert_err(vi_orbit_pnm_solve(m, -1, 1, t, x1, v1, 2, 0, &it));
  assert_err(vi_orbit_pnm_solve(m, 1, 1, NULL, x1, v1, 2, 0, &it));
  assert_err(vi_orbit_pnm_solve(m, 1, 1, t, x1, v1, 1, 0, &it)); /* ld < n */
  assert_int_equal(vi_orbit_pnm_solve(m, 1, 1, t, x1, x1, 2, 0, &it), VI_ERR_ARG); /* x, v overlap */
  assert_int_equal(vi_orbit_pnm_solve(m, 1, 1, x1, x1, v1, 2, 0, &it), VI_ERR_ARG); /* t, x overlap */
  assert_err(vi_orbit_pnm_solve_stops(m, 1, 1, st1, t, x1, v1, 2, 0, &it));
  assert_err(vi_orbit_pnm_solve_stops(m, 1, 1, stn, t, x1, v1, 2, 0, &it));
  assert_err(vi_orbit_pnm_solve_stops(NULL, 1, 1, st0, t, x1, v1, 2, 0, &it));
  assert_err(vi_orbit_pnm_residual(NULL, 1, 1, t, x1, v1, 2, F, J));
  assert_err(vi_orbit_pnm_residual(m, 1, 0, t, x1, v1, 2, F, J));
  assert_err(vi_orbit_pnm_residual(m, 1, 1, t, x1, v1, 1, F, J));
  assert_err(vi_orbit_pnm_residual(m, 1, 1, t, x1, v1, 2, NULL, J));
  assert_err(vi_orbit_pnm_residual_stops(m, 1, 1, st1, t, x1, v1, 2, F, J));
  assert_err(vi_orbit_pnm_residual_stops(m, 1, 1, stn, t, x1, v1, 2, F, J));
  assert_err(vi_orbit_pnm_residual_stops(NULL, 1, 1, st0, t, x1, v1, 2, F, J));
  assert_err(vi_orbit_pnm_multipliers(NULL, 1, 1, t, x1, v1, 2, re, im));
  assert_err(vi_orbit_pnm_multipliers(m, 0, 1, t, x1, v1, 2, re, im));
  assert_err(vi_orbit_pnm_multipliers(m, 1, 1, t, x1, v1, 1, re, im));
  assert_err(vi_orbit_pnm_multipliers(m, 1, 1, t, x1, v1, 2, NULL, im));
  assert_err(vi_orbit_pnm_multipliers_stops(m, 1, 1, st1, t, x1, v1, 2, re, im));
  assert_err(vi_orbit_pnm_multipliers_stops(m, 1, 1, stn, t, x1, v1, 2, re, im));
  assert_err(vi_orbit_pnm_multipliers_stops(NULL, 1, 1, st0, t, x1, v1, 2, re, im));
  assert_err(vi_orbit_pnm_monodromy(NULL, 1, 1, NULL, t, x1, v1, 2, Mo));
  assert_err(vi_orbit_pnm_monodromy(m, 1, 0, NULL, t, x1, v1, 2, Mo));
  assert_err(vi_orbit_pnm_monodromy(m, 1, 1, st1, t, x1, v1, 2, Mo));
  assert_err(vi_orbit_pnm_monodromy(m, 1, 1, NULL, t, x1, v1, 1, Mo));
  assert_err(vi_orbit_pnm_monodromy(m, 1, 1, NULL, t, x1, v1, 2, NULL));
  double v0[2] = {0, 0};
  assert_err(vi_orbit_pnm_monodromy(m, 1, 1, NULL, t, x1, v0, 2, Mo)); /* grazing */
  assert_err(vi_orbit_pnm_admissible(NULL, 1, 1, t, x1, v1, 2, &g, &ok));
  assert_err(vi_orbit_pnm_admissible(m, 1, 0, t, x1, v1, 2, &g, &ok));
  assert_err(vi_orbit_pnm_admissible(m, 1, 1, t, x1, v1, 1, &g, &ok));
  assert_err(vi_orbit_pnm_admissible(m, 1, 1, t, x1, v1, 2, &g, NULL));
  assert_err(vi_orbit_pnm_admissible_stops(m, 1, 1, st1, t, x1, v1, 2, &g, &ok));
  assert_err(vi_orbit_pnm_admissible_stops(m, 1, 1, stn, t, x1, v1, 2, &g, &ok));
  assert_err(vi_orbit_pnm_admissible_stops(NULL, 1, 1, st0, t, x1, v1, 2, &g, &ok));
  assert_err(vi_orbit_pnm_dparam(NULL, 1, 1, NULL, t, x1, v1, 2,
                                 VI_ORBIT_PARAM_OMEGA, 0, dF));
  assert_err(vi_orbit_pnm_dparam(m, 1, 1, NULL, t, x1, v1, 2, -1, 0, dF));
  assert_err(vi_orbit_pnm_dparam(m, 1, 1, NULL, t, x1, v1, 2, 3, 0, dF));
  assert_err(vi_orbit_pnm_dparam(m, 1, 1, NULL, t, x1, v1, 2,
                                 VI_ORBIT_PARAM_XS, 1, dF)); /* k = ns */
  assert_err(vi_orbit_pnm_dparam(m, 1, 1, NULL, t, x1, v1, 2,
                                 VI_ORBIT_PARAM_R, -1, dF));
  assert_err(vi_orbit_pnm_dparam(m, 1, 1, st1, t, x1, v1, 2,
                                 VI_ORBIT_PARAM_OMEGA, 0, dF));
  assert_err(vi_orbit_pnm_dparam(m, 1, 1, NULL, t, x1, v1, 1,
                                 VI_ORBIT_PARAM_OMEGA, 0, dF));
  assert_err(vi_orbit_pnm_dparam(m, 1, 1, NULL, t, x1, v1, 2,
                                 VI_ORBIT_PARAM_OMEGA, 0, NULL));
  double ts[4], xs4[8], vs4[8];
  assert_err(vi_orbit_p1_scan(NULL, 1, 64, ts, xs4, vs4, 2, 4, &found));
  assert_err(vi_orbit_p1_scan(m, 0, 64, ts, xs4, vs4, 2, 4, &found));
  assert_err(vi_orbit_p1_scan(m, 1, 7, ts, xs4, vs4, 2, 4, &found)); /* nphase < 8 */
  assert_err(vi_orbit_p1_scan(m, 1, 64, ts, xs4, vs4, 1, 4, &found));
  assert_err(vi_orbit_p1_scan(m, 1, 64, ts, xs4, vs4, 2, -1, &found));
  assert_err(vi_orbit_p1_scan(m, 1, 64, ts, xs4, vs4, 2, 4, NULL));
  assert_err(vi_orbit_p1_scan(m, 1, 64, ts, xs4, xs4, 2, 4, &found)); /* overlap */
  assert_err(vi_orbit_p1_scan_polled(NULL, 1, 64, ts, xs4, vs4, 2, 4, &found, NULL, NULL));
  assert_err(vi_orbit_p1_scan_polled(m, 1, 7, ts, xs4, vs4, 2, 4, &found, NULL, NULL));
  assert_err(vi_orbit_p1_scan_polled(m, 1, 64, ts, xs4, vs4, 2, 4, NULL, NULL, NULL));
  /* a model that is not set up */
  assert_int_equal(vi_orbit_pnm_residual(raw, 1, 1, t, x1, v1, 2, F, J),
                   VI_ERR_STATE);
  assert_int_equal(vi_orbit_pnm_multipliers(raw, 1, 1, t, x1, v1, 2, re, im),
                   VI_ERR_STATE);
  vi_model_destroy(&raw);
  vi_model_destroy(&unforced);
  vi_model_destroy(&m);
}

/* Parameters by key: NULL handles, keys and outputs, unknown keys,
 * indices out of range, values out of their domain; a model before setup
 * takes the model keys but not the modal ratios. */
/* Issue 29: a model held by a simulation (or orbit, census, fit) made from
 * it is immutable, also from the simulation's own event callback during a
 * run; the run then goes on exactly as with an untouched model. */
typedef struct held_ctx {
  vi_model *m;
  int calls, refused;
  vi_test_events ev;
} held_ctx;

static int change_in_run(const vi_event *e, void *user)
{
  static const char *const keys[] = {"stiffness.scale", "mass.scale",
                                     "forcing.omega", "forcing.a[1]",
                                     "stops[1].xs", "damping.alpha"};
  static const double vals[] = {0.0, 2.0, 1.3, 0.7, 0.2, 0.1};
  held_ctx *c = user;
  for (int k = 0; k < 6; k++) {
    c->calls++;
    if (vi_model_set_param(c->m, keys[k], vals[k]) == VI_ERR_STATE &&
        strstr(vi_model_errmsg(c->m), "in use") &&
        strstr(vi_model_errmsg(c->m), keys[k]))
      c->refused++;
  }
  return vi_test_collect(e, &c->ev);
}

static int cancel_after(void *user)
{
  return ++*(int *)user > 20000;
}

/* A load at the range's end (1e99 on a unit oscillator 0.13 from its
 * stop): the host's cancel is polled in every search, and where the run
 * ends it is right.  The stop lies below the round-off of every position
 * (1e-16 of 1e99), so the motion is that of x_s = 0, 1e99 times the unit
 * load's (linear between impacts, Newton's law homogeneous): the exact
 * method gives it (it pinned the mass in ever shorter chatter before);
 * an integrator under atol 1e-12 may fail, with a message, or be
 * cancelled. */
static void test_load_at_range_end(void **state)
{
  (void)state;
  vi_model *m = vi_test_sdof(1.0, 0.02, 1.0, 1e99, 0.0, 0.5, 0.13332, 0.8);
  vi_model *unit = vi_test_sdof(1.0, 0.02, 1.0, 1.0, 0.0, 0.5, 0.0, 0.8);
  vi_test_events ref = {0};
  assert_int_equal(vi_test_run(unit, VI_METHOD_EXACT, 1e-10, 1e-12, NULL,
                               NULL, 100.0, &ref), VI_OK);
  assert_true(ref.count > 10);
  for (int meth = 0; meth < 2; meth++) {
    int polls = 0;
    vi_test_events ev = {0};
    vi_sim *s = vi_test_sim(m, meth ? VI_METHOD_ADAMS : VI_METHOD_EXACT,
                            1e-10, 1e-12, NULL, NULL, &ev);
    vi_sim_set_cancel(s, cancel_after, &polls, NULL);
    int st = vi_sim_run(s, 100.0);
    assert_true(st == VI_OK || st == VI_CANCELLED || st < 0);
    assert_true(polls <= 20001);
    if (!meth) {
      assert_int_equal(st, VI_OK);
      assert_int_equal(ev.count, ref.count);
      for (int i = 0; i < ev.count; i++) {
        assert_int_equal(ev.kind[i], ref.kind[i]);
        assert_true(fabs(ev.t[i] - ref.t[i]) <= 1e-9 * fmax(1.0, ref.t[i]));
        assert_true(fabs(ev.vn[i] / 1e99 - ref.vn[i]) <=
                    1e-9 * fmax(1.0, fabs(ref.vn[i])));
      }
    }
    vi_test_events_free(&ev);
    vi_sim_destroy(&s);
  }
  vi_test_events_free(&ref);
  vi_model_destroy(&unit);
  vi_model_destroy(&m);
}

static void test_param_in_use(void **state)
{
  (void)state;
  static const int methods[] = {VI_METHOD_EXACT, VI_METHOD_ADAMS};
  for (int im = 0; im < 2; im++) {
    vi_model *m = vi_test_fig2(), *ref = vi_test_fig2();
    held_ctx c = {m, 0, 0, {0}};
    vi_test_events er = {0};
    vi_sim *s = vi_test_sim(m, methods[im], 1e-9, 1e-11, NULL, NULL, NULL);
    assert_int_equal(vi_sim_set_event_callback(s, change_in_run, &c, NULL), VI_OK);
    assert_int_equal(vi_sim_run(s, 150.0), VI_OK);
    assert_int_equal(vi_test_run(ref, methods[im], 1e-9, 1e-11, NULL, NULL,
                                 150.0, &er), VI_OK);
    /* every change refused, the motion that of the untouched model */
    assert_true(c.ev.count > 10);
    assert_int_equal(c.refused, c.calls);
    assert_int_equal(c.ev.count, er.count);
    for (int i = 0; i < er.count; i++) {
      assert_true(c.ev.t[i] == er.t[i]);
      assert_true(c.ev.vn[i] == er.vn[i]);
    }
    /* the check says the same; reading is allowed */
    double val;
    assert_int_equal(vi_model_check_param(m, "forcing.omega", 1.0), VI_ERR_STATE);
    assert_int_equal(vi_model_param(m, "forcing.omega", &val), VI_OK);
    assert_true(val == 0.9);
    vi_sim_destroy(&s);
    /* released with the last holder */
    assert_int_equal(vi_model_set_param(m, "mass.scale", 2.0), VI_OK);
    vi_test_events_free(&c.ev);
    vi_test_events_free(&er);
    vi_model_destroy(&ref);
    vi_model_destroy(&m);
  }
  /* the other handles holding a model: orbit, census, identification; a
   * sweep and a continuation change their own copies */
  vi_model *m = vi_test_fig2();
  vi_orbit *o = NULL;
  vi_census *ce = NULL;
  vi_identify *id = NULL;
  vi_sweep *sw = NULL;
  assert_int_equal(vi_orbit_create(m, &o), VI_OK);
  assert_int_equal(vi_census_create(m, 1, 1, &ce), VI_OK);
  assert_int_equal(vi_identify_create(m, 1, &id), VI_OK);
  assert_int_equal(vi_sweep_create(m, &sw), VI_OK);
  vi_orbit_destroy(&o);
  vi_census_destroy(&ce);
  assert_int_equal(vi_model_set_param(m, "forcing.omega", 1.0), VI_ERR_STATE);
  assert_non_null(strstr(vi_model_errmsg(m), "1 handle "));
  vi_identify_destroy(&id);
  assert_int_equal(vi_model_set_param(m, "forcing.omega", 1.0), VI_OK);
  double om;
  assert_int_equal(vi_sweep_param(sw, "forcing.omega", &om), VI_OK);
  assert_true(om == 0.9); /* the sweep's copy kept its value */
  vi_sweep_destroy(&sw);
  vi_model_destroy(&m);
}

static void test_param_misuse(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2(), *c = NULL, *raw = NULL;
  double val, t0 = 0, x[2] = {0, 0}, v[2] = {0, 0};
  assert_err(vi_model_set_param(NULL, "forcing.omega", 1.0));
  assert_err_msg(vi_model_set_param(m, NULL, 1.0), vi_model_errmsg(m));
  assert_err_msg(vi_model_set_param(m, "", 1.0), vi_model_errmsg(m));
  assert_err_msg(vi_model_set_param(m, "forcing.a[]", 1.0), vi_model_errmsg(m));
  assert_err_msg(vi_model_set_param(m, "forcing.a[1][1]", 1.0), vi_model_errmsg(m));
  assert_err_msg(vi_model_set_param(m, "forcing.a[99999999999]", 1.0),
                 vi_model_errmsg(m));
  assert_err_msg(vi_model_set_param(m, "stops[-1].xs", 1.0), vi_model_errmsg(m));
  assert_err_msg(vi_model_set_param(m, "forcing.omega", INFINITY), vi_model_errmsg(m));
  assert_err_msg(vi_model_set_param(m, "damping.zeta[3]", 0.1), vi_model_errmsg(m));
  assert_err_msg(vi_model_set_param(m, "damping.zeta", -0.1), vi_model_errmsg(m));
  /* issue 29: a load beyond the scene's 1e100 (the run never ended), a
   * mass so small that omega^2 overflows (NaN frequencies) */
  assert_int_equal(vi_model_set_param(m, "forcing.a[1]", 1e200), VI_ERR_LIMIT);
  assert_non_null(strstr(vi_model_errmsg(m), "1e100"));
  assert_int_equal(vi_model_check_param(m, "forcing.f0[2]", -1e101), VI_ERR_LIMIT);
  assert_int_equal(vi_model_set_param(m, "mass.scale", 1e-308), VI_ERR_NONFINITE);
  assert_non_null(strstr(vi_model_errmsg(m), "mass.scale"));
  assert_true(vi_model_omega(m)[0] > 0.6 && vi_model_omega(m)[0] < 0.62);
  /* the check says what the setter would, and changes nothing */
  assert_err(vi_model_check_param(NULL, "forcing.omega", 1.0));
  assert_err_msg(vi_model_check_param(m, "forcing.omgea", 1.0), vi_model_errmsg(m));
  assert_int_equal(vi_model_check_param(m, "forcing.omega", -1.0), VI_ERR_FREQUENCY);
  assert_int_equal(vi_model_check_param(m, "stops[1].r", 1.5), VI_ERR_RESTITUTION);
  assert_int_equal(vi_model_check_param(m, "mass.scale", 0.0), VI_ERR_NOT_SPD);
  assert_int_equal(vi_model_check_param(m, "damping.beta", -0.1), VI_ERR_NOT_PSD);
  assert_int_equal(vi_model_check_param(m, "forcing.omega", 2.0), VI_OK);
  assert_int_equal(vi_model_check_param(m, "stiffness.scale", 2.0), VI_OK);
  assert_int_equal(vi_model_param(m, "forcing.omega", &val), VI_OK);
  assert_true(val == 0.9);
  assert_int_equal(vi_model_param(m, "stiffness.scale", &val), VI_OK);
  assert_true(val == 1.0);
  assert_err(vi_model_param(NULL, "forcing.omega", &val));
  assert_err(vi_model_param(m, "forcing.omega", NULL));
  assert_err_msg(vi_model_param(m, "forcing.omgea", &val), vi_model_errmsg(m));
  assert_err_msg(vi_model_param(m, "stops[2].r", &val), vi_model_errmsg(m));
  assert_err_msg(vi_model_param(m, "initial.x[1]", &val), vi_model_errmsg(m));
  assert_err(vi_model_copy(NULL, &c));
  assert_null(c);
  assert_err(vi_model_copy(m, NULL));
  assert_int_equal(vi_param_kind(NULL), VI_PARAM_UNKNOWN);
  assert_int_equal(vi_param_kind("initial.x[1]x"), VI_PARAM_UNKNOWN);
  assert_err(vi_param_set_initial(NULL, 1.0, 2, &t0, x, v));
  assert_err(vi_param_set_initial("initial.x[1]", NAN, 2, &t0, x, v));
  assert_err(vi_param_set_initial("initial.x[1]", 1.0, 2, &t0, NULL, v));
  assert_err(vi_param_set_initial("initial.t0", 1.0, 2, NULL, x, v));
  assert_err(vi_param_set_initial("initial.v[0]", 1.0, 2, &t0, x, v));
  assert_err(vi_param_initial("initial.v[1]", 2, t0, x, NULL, &val));
  assert_err(vi_param_initial("initial.v[1]", 2, t0, x, v, NULL));
  assert_err(vi_param_initial("initial.v[3]", 2, t0, x, v, &val));
  assert_err(vi_param_initial("stop.xs", 2, t0, x, v, &val));
  assert_null(vi_param_key_name(-1));
  assert_true(vi_param_key_count() > 0);
  /* before setup: model keys yes, modal ratios no */
  assert_int_equal(vi_model_create(2, &raw), VI_OK);
  assert_int_equal(vi_model_set_param(raw, "forcing.omega", 1.0), VI_OK);
  assert_err_msg(vi_model_set_param(raw, "stop.xs", 1.0), vi_model_errmsg(raw));
  assert_int_equal(vi_model_set_param(raw, "damping.zeta", 0.1), VI_ERR_STATE);
  assert_int_equal(vi_model_set_param(raw, "forcing.a[1]", 1.0), VI_OK);
  const double big[2] = {0.0, 1e200};
  assert_int_equal(vi_model_set_forcing(raw, 1.0, NULL, big, NULL), VI_ERR_LIMIT);
  assert_int_equal(vi_model_set_param(raw, "forcing.omega", 0.0),
                   VI_ERR_FREQUENCY); /* harmonic forcing needs Omega */
  vi_model_destroy(&raw);
  vi_model_destroy(&m);
}

static int stop_at_once(const vi_sweep *sw, int64_t point, int status,
                        void *user)
{
  (void)sw, (void)status, (void)user;
  return point >= 1;
}

static int hook_fails(vi_sim *sim, void *user)
{
  (void)sim, (void)user;
  return VI_ERR_CALLBACK;
}

static int never_cancel(void *user)
{
  (void)user;
  return 0;
}

/* Studies: NULL handles and outputs, out-of-range settings, results
 * before a point, a model not set up, a failing hook, a stopping monitor,
 * and the attractor grouping's bad sizes. */
static void test_sweep_misuse(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2(), *raw = NULL;
  vi_sweep *sw = NULL;
  int n, mm, ld, R, cnt, id[2], na, per[2] = {1, 1};
  int64_t ni;
  double val, x[2] = {0, 0}, z[8] = {0};
  assert_err(vi_sweep_create(NULL, &sw));
  assert_err(vi_sweep_create(m, NULL));
  assert_int_equal(vi_model_create(2, &raw), VI_OK);
  assert_int_equal(vi_sweep_create(raw, &sw), VI_ERR_STATE);
  assert_null(sw);
  vi_model_destroy(&raw);
  assert_int_equal(vi_sweep_create(m, &sw), VI_OK);
  assert_err(vi_sweep_set_periods(NULL, 1, 2));
  assert_err_msg(vi_sweep_set_periods(sw, -1, 2), vi_sweep_errmsg(sw));
  assert_err_msg(vi_sweep_set_periods(sw, 1, 1), vi_sweep_errmsg(sw));
  assert_err(vi_sweep_set_classify(NULL, 1e-6, 4));
  assert_err_msg(vi_sweep_set_classify(sw, 0, 4), vi_sweep_errmsg(sw));
  assert_err_msg(vi_sweep_set_classify(sw, NAN, 4), vi_sweep_errmsg(sw));
  assert_err_msg(vi_sweep_set_classify(sw, 1e-6, 0), vi_sweep_errmsg(sw));
  assert_err(vi_sweep_set_run(NULL, VI_METHOD_EXACT, 1e-8, 1e-10));
  assert_err_msg(vi_sweep_set_run(sw, -1, 1e-8, 1e-10), vi_sweep_errmsg(sw));
  assert_err_msg(vi_sweep_set_run(sw, VI_METHOD_COUNT, 1e-8, 1e-10), vi_sweep_errmsg(sw));
  assert_err_msg(vi_sweep_set_run(sw, VI_METHOD_EXACT, 0, 1e-10), vi_sweep_errmsg(sw));
  assert_err_msg(vi_sweep_set_run(sw, VI_METHOD_EXACT, 1e-8, INFINITY), vi_sweep_errmsg(sw));
  assert_err(vi_sweep_set_initial(NULL, 0, x, x));
  assert_err_msg(vi_sweep_set_initial(sw, NAN, x, x), vi_sweep_errmsg(sw));
  x[1] = INFINITY;
  assert_err_msg(vi_sweep_set_initial(sw, 0, x, NULL), vi_sweep_errmsg(sw));
  assert_err(vi_sweep_set_warm(NULL, 1));
  assert_err_msg(vi_sweep_set_warm(sw, 2), vi_sweep_errmsg(sw));
  assert_err(vi_sweep_set_param(NULL, "forcing.omega", 1.0));
  assert_err_msg(vi_sweep_set_param(sw, "forcing.omgea", 1.0), vi_sweep_errmsg(sw));
  assert_err_msg(vi_sweep_set_param(sw, "initial.x[3]", 1.0), vi_sweep_errmsg(sw));
  assert_err_msg(vi_sweep_set_param(sw, NULL, 1.0), vi_sweep_errmsg(sw));
  assert_err(vi_sweep_param(NULL, "forcing.omega", &val));
  assert_err(vi_sweep_param(sw, "forcing.omega", NULL));
  assert_err_msg(vi_sweep_param(sw, "initial.v[0]", &val), vi_sweep_errmsg(sw));
  assert_err(vi_sweep_reset(NULL));
  assert_err(vi_sweep_warm_state(NULL, x, x));
  assert_err(vi_sweep_warm_state(sw, x, NULL));
  assert_err_msg(vi_sweep_warm_state(sw, x, x), vi_sweep_errmsg(sw)); /* none yet */
  assert_err(vi_sweep_set_warm_state(NULL, x, x));
  assert_err_msg(vi_sweep_set_warm_state(sw, x, x), vi_sweep_errmsg(sw)); /* x[1] inf */
  assert_err(vi_sweep_set_monitor(NULL, NULL, NULL, NULL));
  assert_err(vi_sweep_set_sim_hook(NULL, NULL, NULL, NULL));
  assert_err(vi_sweep_set_cancel(NULL, never_cancel, NULL, NULL));
  assert_err(vi_sweep_set_orbits(NULL, 8));
  assert_err(vi_sweep_set_lyapunov(NULL, 1));
  assert_err_msg(vi_sweep_set_lyapunov(sw, 2), vi_sweep_errmsg(sw));
  assert_true(isnan(vi_sweep_lyapunov(NULL)));
  assert_true(isnan(vi_sweep_lyapunov(sw))); /* before a point */
  assert_err_msg(vi_sweep_set_orbits(sw, -1), vi_sweep_errmsg(sw));
  assert_err(vi_sweep_iterate(NULL));
  /* results before any point */
  assert_int_equal(vi_sweep_period(sw, &n, &mm), VI_ERR_STATE);
  assert_err(vi_sweep_period(NULL, &n, &mm));
  assert_err(vi_sweep_period(sw, NULL, &mm));
  assert_int_equal(vi_sweep_failed(NULL), 0);
  assert_true(vi_sweep_forcing_period(NULL) == 0.0);
  assert_err(vi_sweep_impacts(NULL, &ni, NULL, NULL, NULL));
  assert_err(vi_sweep_impacts(sw, NULL, NULL, NULL, NULL));
  assert_null(vi_sweep_strobe(NULL, &ld, &R));
  assert_null(vi_sweep_strobe(sw, &ld, &R));
  assert_err(vi_sweep_orbits(NULL, &cnt, NULL, NULL, NULL, NULL));
  assert_err(vi_sweep_orbits(sw, NULL, NULL, NULL, NULL, NULL));
  assert_null(vi_sweep_model(NULL));
  assert_string_equal(vi_sweep_errmsg(NULL), "");
  /* a hook that fails fails the point, named; a monitor stops */
  assert_int_equal(vi_sweep_set_periods(sw, 2, 2), VI_OK);
  assert_int_equal(vi_sweep_set_sim_hook(sw, hook_fails, NULL, NULL), VI_OK);
  assert_int_equal(vi_sweep_iterate(sw), VI_ERR_CALLBACK);
  assert_int_equal(vi_sweep_failed(sw), 1);
  assert_true(strlen(vi_sweep_errmsg(sw)) > 0);
  assert_int_equal(vi_sweep_set_sim_hook(sw, NULL, NULL, NULL), VI_OK);
  assert_int_equal(vi_sweep_set_monitor(sw, stop_at_once, NULL, NULL), VI_OK);
  assert_int_equal(vi_sweep_iterate(sw), VI_STOPPED);
  assert_int_equal(vi_sweep_set_param(sw, "stop.r", 1.5), VI_ERR_RESTITUTION);
  vi_sweep_destroy(&sw);
  vi_sweep_destroy(&sw); /* NULL-safe */
  /* attractors */
  assert_err(vi_sweep_attractors(1, 1, 2, NULL, z, 2, 1e-6, id, &na));
  assert_err(vi_sweep_attractors(1, 1, 2, per, z, 2, 0, id, &na));
  assert_err(vi_sweep_attractors(-1, 1, 2, per, z, 2, 1e-6, id, &na));
  assert_int_equal(vi_sweep_attractors(1, 1, 2, per, z, 1, 1e-6, id, &na), VI_ERR_DIM);
  assert_int_equal(vi_sweep_attractors(1, 0, 2, per, z, 2, 1e-6, id, &na), VI_ERR_DIM);
  assert_int_equal(vi_sweep_attractors(2, 1, 2, per, z, 2, 1e-6, id, &na), VI_OK);
  assert_int_equal(na, 1); /* two equal points: one attractor */
  vi_model_destroy(&m);
}

/* The truncated model: NULL, k out of range, a model not set up, a band
 * model, no residual beyond the kept modes, a state without its output. */
static void test_truncated_misuse(void **state)
{
  (void)state;
  vi_model *f = vi_test_fig2(), *R = NULL, *t = NULL, *raw = NULL;
  const int all[2] = {0, 1};
  double z[4] = {0}, zt[4], g;
  assert_int_equal(vi_model_create_reduced(f, all, 2, 0.7, &R), VI_OK);
  assert_err(vi_model_create_truncated(NULL, 1, 0, 0.7, NULL, NULL, NULL, &t));
  assert_err(vi_model_create_truncated(R, 1, 0, 0.7, NULL, NULL, NULL, NULL));
  assert_err(vi_model_create_truncated(R, 0, 0, 0.7, NULL, NULL, NULL, &t));
  assert_err(vi_model_create_truncated(R, 3, 0, 0.7, NULL, NULL, NULL, &t));
  assert_err(vi_model_create_truncated(R, 1, 2, 0.7, NULL, NULL, NULL, &t));
  assert_err(vi_model_create_truncated(R, 2, 1, 0.7, NULL, NULL, NULL, &t)); /* nothing beyond */
  assert_err(vi_model_create_truncated(R, 1, 0, 0.7, z, NULL, NULL, &t));
  double cd[2], cs[2];
  assert_err(vi_model_modal_compliance(NULL, 0, 1, cd, cs));
  assert_err(vi_model_modal_compliance(R, 0, 0, cd, cs));
  assert_err(vi_model_modal_compliance(R, 0, 3, cd, cs));
  assert_err(vi_model_modal_compliance(R, 1, 1, cd, cs)); /* one stop */
  assert_err(vi_model_modal_compliance(f, 0, 2, cd, cs)); /* not modal: M != I */
  assert_int_equal(vi_model_create_truncated(R, 1, 0, 1.5, z, zt, &g, &t), VI_ERR_RESTITUTION);
  assert_null(t);
  assert_int_equal(vi_model_create(2, &raw), VI_OK);
  assert_int_equal(vi_model_create_truncated(raw, 1, 0, 0.7, NULL, NULL, NULL, &t), VI_ERR_STATE);
  vi_model_destroy(&raw);
  double mass[2] = {1, 1}, k[2] = {1, 1}, w[2] = {0, 1}, a[2] = {0.5, 0};
  assert_int_equal(vi_model_create_chain(2, mass, k, NULL, &raw), VI_OK);
  assert_int_equal(vi_model_set_forcing(raw, 0.9, a, NULL, NULL), VI_OK);
  assert_int_equal(vi_model_set_stop(raw, w, 0.1, 0.7), VI_OK);
  assert_int_equal(vi_model_setup(raw), VI_OK);
  assert_int_equal(vi_model_create_truncated(raw, 1, 0, 0.7, NULL, NULL, NULL, &t),
                   VI_ERR_UNSUPPORTED); /* band: no modal coordinates */
  vi_model_destroy(&raw);
  vi_model_destroy(&R);
  vi_model_destroy(&f);
}

static int trunc_yes(void *user)
{
  (void)user;
  return 1;
}

static int trunc_stop_mon(const vi_progress *p, void *user)
{
  (void)p, (void)user;
  return 1;
}

/* The truncation study (vi_truncation.h): NULL handles and outputs, bad
 * ranges and states, calls out of order, a model not set up or in band
 * storage, an FE reduction not set up, a cancel and a monitor that stop. */
static void test_truncation_misuse(void **state)
{
  (void)state;
  vi_model *f = vi_test_fig2(), *raw = NULL;
  vi_truncation *tr = NULL;
  vi_fe *fe = NULL;
  double row[VI_TRUNCATION_COLUMNS], info[VI_TRUNCATION_INFO], x[2] = {0, 0};
  double tab[2 * VI_TRUNCATION_COLUMNS];
  int n = -1;
  assert_err(vi_truncation_create(NULL, &tr));
  assert_err(vi_truncation_create(f, NULL));
  assert_err(vi_truncation_create_fe(NULL, &tr));
  assert_err(vi_truncation_create_fe((const vi_fe *)NULL, NULL));
  assert_int_equal(vi_model_create(2, &raw), VI_OK);
  assert_int_equal(vi_truncation_create(raw, &tr), VI_ERR_STATE);
  vi_model_destroy(&raw);
  double mass[2] = {1, 1}, k[2] = {1, 1}, w[2] = {0, 1}, a[2] = {0.5, 0};
  assert_int_equal(vi_model_create_chain(2, mass, k, NULL, &raw), VI_OK);
  assert_int_equal(vi_model_set_forcing(raw, 0.9, a, NULL, NULL), VI_OK);
  assert_int_equal(vi_model_set_stop(raw, w, 0.1, 0.7), VI_OK);
  assert_int_equal(vi_model_setup(raw), VI_OK);
  assert_int_equal(vi_truncation_create(raw, &tr), VI_ERR_UNSUPPORTED); /* band */
  assert_null(tr);
  vi_model_destroy(&raw);
  assert_int_equal(vi_fe_create(4, &fe), VI_OK);
  assert_err(vi_truncation_create_fe(fe, &tr)); /* not set up */
  assert_null(tr);
  vi_fe_destroy(&fe);
  /* NULL handles */
  assert_string_equal(vi_truncation_errmsg(NULL), "");
  assert_err(vi_truncation_set_modes(NULL, 1, 1));
  assert_err(vi_truncation_set_initial(NULL, 0, 1, NULL, NULL));
  assert_err(vi_truncation_set_monitor(NULL, NULL, NULL, NULL));
  assert_err(vi_truncation_set_cancel(NULL, NULL, NULL, NULL));
  assert_err(vi_truncation_iterate(NULL));
  assert_int_equal(vi_truncation_done(NULL), 0);
  assert_err(vi_truncation_row(NULL, 0, row));
  assert_err(vi_truncation_table(NULL, NULL, 0, &n));
  assert_err(vi_truncation_summary(NULL, info));
  assert_null(vi_truncation_model(NULL));
  vi_truncation_destroy(NULL);
  /* bad values on a study of Fig. 2 */
  assert_int_equal(vi_truncation_create(f, &tr), VI_OK);
  assert_non_null(vi_truncation_model(tr));
  assert_err_msg(vi_truncation_set_modes(tr, 0, 1), vi_truncation_errmsg(tr));
  assert_err(vi_truncation_set_modes(tr, 2, 1));
  assert_err(vi_truncation_set_modes(tr, 1, 3)); /* two modes */
  assert_int_equal(vi_truncation_set_initial(tr, NAN, 1, NULL, NULL), VI_ERR_NONFINITE);
  assert_int_equal(vi_truncation_set_initial(tr, 1, 1, NULL, NULL), VI_ERR_TIME);
  x[1] = INFINITY;
  assert_int_equal(vi_truncation_set_initial(tr, 0, 1, x, NULL), VI_ERR_NONFINITE);
  x[1] = 0;
  assert_err(vi_truncation_row(tr, 0, NULL));
  assert_err(vi_truncation_row(tr, 3, row));
  assert_int_equal(vi_truncation_row(tr, 0, row), VI_ERR_STATE); /* no reference yet */
  assert_int_equal(vi_truncation_row(tr, 1, row), VI_ERR_STATE);
  assert_err(vi_truncation_table(tr, NULL, 0, NULL));
  assert_err(vi_truncation_summary(tr, NULL));
  /* a cancel before anything: nothing done, the study not begun */
  assert_int_equal(vi_truncation_set_cancel(tr, trunc_yes, NULL, NULL), VI_OK);
  assert_int_equal(vi_truncation_iterate(tr), VI_CANCELLED);
  assert_int_equal(vi_truncation_set_cancel(tr, NULL, NULL, NULL), VI_OK);
  /* a monitor that stops the reference's orbit search */
  assert_int_equal(vi_truncation_set_monitor(tr, trunc_stop_mon, NULL, NULL), VI_OK);
  assert_int_equal(vi_truncation_iterate(tr), VI_STOPPED);
  assert_int_equal(vi_truncation_row(tr, 0, row), VI_ERR_STATE);
  assert_int_equal(vi_truncation_set_monitor(tr, NULL, NULL, NULL), VI_OK);
  /* begun: the settings are refused */
  assert_int_equal(vi_truncation_set_modes(tr, 1, 1), VI_ERR_STATE);
  assert_int_equal(vi_truncation_set_initial(tr, 0, 1, x, x), VI_ERR_STATE);
  /* the whole study, then one step too many */
  while (!vi_truncation_done(tr)) assert_int_equal(vi_truncation_iterate(tr), VI_OK);
  assert_err_msg(vi_truncation_iterate(tr), vi_truncation_errmsg(tr));
  assert_int_equal(vi_truncation_table(tr, NULL, 0, &n), VI_OK);
  assert_int_equal(n, 2);
  assert_err(vi_truncation_table(tr, tab, 1, &n)); /* ldrows < nrows */
  assert_int_equal(vi_truncation_table(tr, tab, 2, &n), VI_OK);
  assert_int_equal(vi_truncation_row(tr, 2, row), VI_OK);
  assert_true(row[0] == 2 && tab[1] == 2);
  assert_int_equal(vi_truncation_summary(tr, info), VI_OK);
  assert_true(info[VI_TRUNCATION_INFO - 1] == 1);
  vi_truncation_destroy(&tr);
  vi_truncation_destroy(&tr); /* NULL-safe */
  /* an orbit search cancelled within its transient */
  vi_orbit *o = NULL;
  assert_err(vi_orbit_set_cancel(NULL, NULL, NULL, NULL));
  assert_int_equal(vi_orbit_create(f, &o), VI_OK);
  assert_int_equal(vi_orbit_set_cancel(o, trunc_yes, NULL, NULL), VI_OK);
  assert_int_equal(vi_orbit_find(o), VI_CANCELLED);
  vi_orbit_destroy(&o);
  vi_model_destroy(&f);
}

static int census_stop(const vi_census *c, int index, void *user)
{
  (void)c, (void)index, (void)user;
  return 1;
}

/* The orbit census: NULL handles, out-of-range n, m, phases and indices,
 * non-finite seeds, a model without forcing or stop, a stopping monitor. */
static void test_census_misuse(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2(), *raw = NULL;
  vi_census *c = NULL;
  double t, x[4], v[4], re[4], im[4], gmax, nanx[2] = {NAN, 0};
  int stop, st, ad;
  assert_err(vi_census_create(NULL, 1, 1, &c));
  assert_err(vi_census_create(m, 1, 1, NULL));
  assert_err(vi_census_create(m, 0, 1, &c));
  assert_err(vi_census_create(m, 1, 65, &c));
  assert_null(c);
  assert_int_equal(vi_model_create(2, &raw), VI_OK);
  assert_int_equal(vi_census_create(raw, 1, 1, &c), VI_ERR_STATE);
  vi_model_destroy(&raw);
  raw = vi_test_sdof(1, 0.1, 1, 0, 0.5, 0, 0.1, 0.7); /* no harmonic forcing */
  assert_int_equal(vi_census_create(raw, 1, 1, &c), VI_ERR_FREQUENCY);
  assert_null(c);
  vi_model_destroy(&raw);
  assert_int_equal(vi_census_create(m, 1, 1, &c), VI_OK);
  assert_err(vi_census_set_phases(NULL, 720));
  assert_err_msg(vi_census_set_phases(c, 7), vi_census_errmsg(c));
  assert_err(vi_census_set_initial(NULL, 0, NULL, NULL));
  assert_err_msg(vi_census_set_initial(c, INFINITY, NULL, NULL), vi_census_errmsg(c));
  assert_err_msg(vi_census_set_initial(c, 0, nanx, NULL), vi_census_errmsg(c));
  assert_err_msg(vi_census_set_initial(c, 0, NULL, nanx), vi_census_errmsg(c));
  assert_err(vi_census_set_sim_hook(NULL, hook_fails, NULL, NULL));
  assert_err(vi_census_set_monitor(NULL, census_stop, NULL, NULL));
  assert_err(vi_census_set_cancel(NULL, never_cancel, NULL, NULL));
  assert_err(vi_census_run(NULL));
  assert_int_equal(vi_census_count(NULL), 0);
  assert_int_equal(vi_census_count(c), 0);
  assert_string_equal(vi_census_errmsg(NULL), "");
  /* no orbit before a run */
  assert_err(vi_census_orbit(c, 0, &t, x, v, 2, &stop, NULL));
  assert_err(vi_census_stability(c, 0, re, im, &st, &ad, &gmax));
  assert_err(vi_census_orbit(NULL, 0, &t, x, v, 2, &stop, NULL));
  assert_err(vi_census_stability(NULL, 0, re, im, &st, &ad, &gmax));
  /* a failing hook skips the transient seeds; a monitor stops at the
   * first orbit (the phase scan's), which is kept */
  assert_int_equal(vi_census_set_sim_hook(c, hook_fails, NULL, NULL), VI_OK);
  assert_int_equal(vi_census_set_monitor(c, census_stop, NULL, NULL), VI_OK);
  assert_int_equal(vi_census_run(c), VI_STOPPED);
  assert_int_equal(vi_census_count(c), 1);
  assert_int_equal(vi_census_orbit(c, 0, &t, x, v, 1, &stop, NULL), VI_ERR_DIM);
  assert_err(vi_census_orbit(c, 1, &t, x, v, 2, &stop, NULL));
  assert_err(vi_census_orbit(c, -1, &t, NULL, NULL, 0, NULL, NULL));
  assert_err(vi_census_stability(c, 1, re, im, &st, &ad, &gmax));
  assert_int_equal(vi_census_orbit(c, 0, &t, NULL, NULL, 0, NULL, NULL), VI_OK);
  vi_census_destroy(&c);
  vi_census_destroy(&c); /* NULL-safe */
  vi_census_destroy(NULL);
  vi_model_destroy(&m);
}

static int stop_cont(const vi_cont *c, int64_t point, void *user)
{
  (void)c, (void)user;
  return point >= 1;
}

/* Continuation: NULL handles and outputs, bad keys and methods, calls out
 * of order, a model not set up, a monitor that stops. */
static void test_cont_misuse(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2(), *raw = NULL;
  vi_cont *c = NULL;
  double x[2] = {0, 0}, p, t;
  int type;
  assert_err(vi_cont_create(NULL, "forcing.omega", 1, VI_CONT_NATURAL, &c));
  assert_err(vi_cont_create(m, "forcing.omega", 1, VI_CONT_NATURAL, NULL));
  assert_err(vi_cont_create(m, NULL, 1, VI_CONT_NATURAL, &c));
  assert_err(vi_cont_create(m, "forcing.omgea", 1, VI_CONT_NATURAL, &c));
  assert_err(vi_cont_create(m, "initial.x[1]", 1, VI_CONT_NATURAL, &c));
  assert_err(vi_cont_create(m, "forcing.omega", 0, VI_CONT_NATURAL, &c));
  assert_err(vi_cont_create(m, "forcing.omega", 1, 7, &c));
  /* a key the model lacks is a bad argument, not a lack of memory */
  assert_int_equal(vi_cont_create(m, "forcing.a[3]", 1, VI_CONT_NATURAL, &c), VI_ERR_ARG);
  assert_null(c);
  assert_int_equal(vi_model_create(2, &raw), VI_OK);
  assert_int_equal(vi_cont_create(raw, "forcing.omega", 1, VI_CONT_NATURAL, &c),
                   VI_ERR_STATE);
  vi_model_destroy(&raw);
  assert_int_equal(vi_cont_create(m, "forcing.omega", 1, VI_CONT_NATURAL, &c), VI_OK);
  assert_err(vi_cont_set_range(NULL, 1.0, 2));
  assert_err(vi_cont_set_range(c, 1.0, 0));
  assert_err(vi_cont_set_range(c, NAN, 2));
  assert_err(vi_cont_set_orbit(NULL, 0, x, x));
  assert_err(vi_cont_set_orbit(c, 0, NULL, x));
  assert_err(vi_cont_set_orbit(c, INFINITY, x, x));
  x[0] = NAN;
  assert_err(vi_cont_set_orbit(c, 0, x, x));
  x[0] = 0;
  assert_err(vi_cont_set_monitor(NULL, NULL, NULL, NULL));
  assert_err(vi_cont_set_cancel(NULL, NULL, NULL, NULL));
  assert_err(vi_cont_iterate(NULL));
  assert_err_msg(vi_cont_iterate(c), vi_cont_errmsg(c)); /* nothing set */
  assert_err(vi_cont_point(NULL, &p, NULL, NULL, NULL, NULL));
  assert_int_equal(vi_cont_point(c, &p, NULL, NULL, NULL, NULL), VI_ERR_STATE);
  assert_err(vi_cont_orbit(c, &t, x, NULL));
  assert_int_equal(vi_cont_orbit(c, &t, x, x), VI_ERR_STATE);
  assert_int_equal(vi_cont_num_events(NULL), 0);
  assert_err(vi_cont_event(c, 0, &type, NULL, NULL, NULL, NULL, NULL));
  assert_err(vi_cont_event(NULL, 0, &type, NULL, NULL, NULL, NULL, NULL));
  assert_int_equal(vi_cont_done(NULL), 0);
  assert_string_equal(vi_cont_errmsg(NULL), "");
  /* a range that ends where it starts: one point, then done */
  double xo[2] = {-0.0563, 0.1}, vo[2] = {0.11, 0.79};
  assert_int_equal(vi_cont_set_range(c, 0.9, 1), VI_OK);
  assert_int_equal(vi_cont_set_orbit(c, 0.68, xo, vo), VI_OK);
  assert_int_equal(vi_cont_iterate(c), VI_OK);
  assert_int_equal(vi_cont_done(c), VI_CONT_END);
  assert_err_msg(vi_cont_iterate(c), vi_cont_errmsg(c));
  vi_cont_destroy(&c);
  vi_cont_destroy(&c); /* NULL-safe */
  /* a monitor that stops after the first point (the Fig. 2 orbit) */
  assert_int_equal(vi_cont_create(m, "forcing.omega", 1, VI_CONT_NATURAL, &c), VI_OK);
  assert_int_equal(vi_cont_set_range(c, 1.0, 2), VI_OK);
  assert_int_equal(vi_cont_set_orbit(c, 0.68, xo, vo), VI_OK);
  assert_int_equal(vi_cont_set_monitor(c, stop_cont, NULL, NULL), VI_OK);
  assert_int_equal(vi_cont_iterate(c), VI_STOPPED);
  vi_cont_destroy(&c);
  vi_model_destroy(&m);
}

/* Two-parameter curves (vi_cont_curve.h): NULL handles and outputs, bad
 * kinds, orbits and keys, calls out of order, a point that is not there. */
static void test_curve_misuse(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  vi_cont_curve *c = NULL;
  double x[2] = {-0.0563, 0.1}, v[2] = {0.11, 0.79}, p = 0.9, t = 0.68;
  int type;
  assert_err(vi_cont_curve_create(NULL, VI_CONT_CURVE_PD, 1, 1, "forcing.omega", "stop.r", &c));
  assert_err(vi_cont_curve_create(m, VI_CONT_CURVE_PD, 1, 1, "forcing.omega", "stop.r", NULL));
  assert_err(vi_cont_curve_create(m, 9, 1, 1, "forcing.omega", "stop.r", &c));
  assert_err(vi_cont_curve_create(m, VI_CONT_CURVE_PD, 0, 1, "forcing.omega", "stop.r", &c));
  assert_err(vi_cont_curve_create(m, VI_CONT_CURVE_PD, 1, 0, "forcing.omega", "stop.r", &c));
  /* one number under two names */
  assert_int_equal(vi_cont_curve_create(m, VI_CONT_CURVE_PD, 1, 1, "stop.r", "stops[1].r", &c),
                   VI_ERR_ARG);
  assert_err(vi_cont_curve_create(m, VI_CONT_CURVE_PD, 1, 1, "forcing.omgea", "stop.r", &c));
  assert_err(vi_cont_curve_create(m, VI_CONT_CURVE_PD, 1, 1, "stop.r", "stop.r", &c));
  assert_err(vi_cont_curve_create(m, VI_CONT_CURVE_PD, 1, 1, "initial.x[1]", "stop.r", &c));
  assert_err(vi_cont_refine(NULL, "forcing.omega", 1, VI_CONT_CURVE_PD, &p, &t, x, v));
  assert_err(vi_cont_refine(m, "forcing.omega", 1, VI_CONT_CURVE_PD, NULL, &t, x, v));
  assert_err(vi_cont_refine_pnm(NULL, "forcing.omega", 1, 1, VI_CONT_CURVE_PD, &p, &t, x, v, 2));
  assert_err(vi_cont_refine_pnm(m, "forcing.omega", 1, 0, VI_CONT_CURVE_PD, &p, &t, x, v, 2));
  assert_err(vi_cont_refine_pnm(m, "forcing.omega", 1, 1, VI_CONT_CURVE_PD, &p, &t, x, v, 1));
  /* no period doubling near Omega = 0.9 */
  assert_err(vi_cont_refine(m, "forcing.omega", 1, VI_CONT_CURVE_PD, &p, &t, x, v));
  assert_err(vi_cont_curve_iterate(NULL));
  assert_err(vi_cont_curve_locate(NULL, 1.8, 10, NULL));
  assert_err(vi_cont_curve_set_orbit(NULL, 0, x, v));
  assert_err(vi_cont_curve_set_range(NULL, 0.5, 0.9, 10));
  assert_err(vi_cont_curve_point(NULL, &p, NULL, NULL, NULL, NULL, NULL));
  assert_err(vi_cont_curve_special(NULL, 0, &type, NULL, NULL, NULL));
  assert_int_equal(vi_cont_curve_num_special(NULL), 0);
  assert_int_equal(vi_cont_curve_done(NULL), 0);
  assert_int_equal(vi_cont_curve_start(NULL), 0);
  assert_string_equal(vi_cont_curve_errmsg(NULL), "");
  assert_int_equal(vi_cont_curve_create(m, VI_CONT_CURVE_PD, 1, 1, "forcing.omega", "stop.r",
                                        &c), VI_OK);
  assert_err_msg(vi_cont_curve_locate(c, 1.8, 10, NULL), vi_cont_curve_errmsg(c)); /* no orbit */
  assert_err_msg(vi_cont_curve_iterate(c), vi_cont_curve_errmsg(c)); /* not located */
  assert_int_equal(vi_cont_curve_point(c, &p, NULL, NULL, NULL, NULL, NULL), VI_ERR_STATE);
  assert_err(vi_cont_curve_set_orbit(c, 0, NULL, v));
  assert_err(vi_cont_curve_set_orbit(c, INFINITY, x, v));
  assert_err(vi_cont_curve_locate(c, NAN, 10, NULL));
  assert_err(vi_cont_curve_locate(c, 1.8, 0, NULL));
  assert_err(vi_cont_curve_set_range(c, 0.5, 0.5, 10));
  assert_err(vi_cont_curve_set_range(c, 0.5, NAN, 10));
  assert_err(vi_cont_curve_set_range(c, 0.5, 0.9, 0));
  assert_err(vi_cont_curve_special(c, 0, &type, NULL, NULL, NULL));
  /* the range of r must hold the located point's r = 0.7 */
  assert_int_equal(vi_cont_curve_set_orbit(c, 0.68, x, v), VI_OK);
  /* a search that ends where it begins (its step of no length spun) */
  double om = 0;
  assert_int_equal(vi_model_param(m, "forcing.omega", &om), VI_OK);
  assert_int_equal(vi_cont_curve_locate(c, om, 100, &p), VI_ERR_ARG);
  assert_non_null(strstr(vi_cont_curve_errmsg(c), "nothing to search"));
  assert_int_equal(vi_cont_curve_locate(c, 1.8, 100, &p), VI_OK);
  assert_err(vi_cont_curve_set_orbit(c, 0.68, x, v)); /* already located */
  assert_int_equal(vi_cont_curve_set_range(c, 0.8, 0.9, 10), VI_OK);
  assert_err_msg(vi_cont_curve_iterate(c), vi_cont_curve_errmsg(c));
  assert_err_msg(vi_cont_curve_iterate(c), vi_cont_curve_errmsg(c)); /* done */
  vi_cont_curve_destroy(&c);
  vi_cont_curve_destroy(&c); /* NULL-safe */
  /* P(1,0) takes no orbit and only the grazing kind */
  assert_err(vi_cont_curve_create(m, VI_CONT_CURVE_FOLD, 1, 0, "stop.xs", "forcing.omega", &c));
  assert_int_equal(vi_cont_curve_create(m, VI_CONT_CURVE_GRAZING, 1, 0, "stop.xs",
                                        "forcing.omega", &c), VI_OK);
  assert_err(vi_cont_curve_set_orbit(c, 0, x, v));
  assert_err(vi_cont_curve_set_impacts(c, &t, x, v, 2));
  assert_err(vi_cont_curve_impacts(c, &t, x, v, 2));
  assert_int_equal(vi_cont_curve_locate(c, 0.2, 4, NULL), VI_STOPPED); /* grazes at 0.64 */
  vi_cont_curve_destroy(&c);
  /* P(n,m), m > 1: every kind, up to 32 impacts; impacts as arrays */
  assert_err(vi_cont_curve_create(m, VI_CONT_CURVE_GRAZING, 2, 33, "forcing.omega", "stop.r", &c));
  assert_int_equal(vi_cont_curve_create(m, VI_CONT_CURVE_GRAZING, 2, 2, "forcing.omega", "stop.r",
                                        &c), VI_OK);
  vi_cont_curve_destroy(&c);
  assert_err(vi_cont_curve_create(m, VI_CONT_CURVE_PD, 2, 33, "forcing.omega", "stop.r", &c));
  assert_int_equal(vi_cont_curve_create(m, VI_CONT_CURVE_PD, 2, 20, "forcing.omega", "stop.r",
                                        &c), VI_OK); /* 102 unknowns: no size limit */
  vi_cont_curve_destroy(&c);
  double t2[2] = {1, 4}, x2[4] = {0, 0.1, 0, 0.1}, v2[4] = {0, 1, 0, 1};
  assert_err(vi_cont_curve_set_impacts(NULL, t2, x2, v2, 2));
  assert_err(vi_cont_curve_impacts(NULL, t2, x2, v2, 2));
  assert_int_equal(vi_cont_curve_create(m, VI_CONT_CURVE_PD, 2, 2, "forcing.omega", "stop.r",
                                        &c), VI_OK);
  assert_err(vi_cont_curve_set_orbit(c, 1, x2, v2)); /* two impacts: set_impacts */
  assert_err(vi_cont_curve_set_impacts(c, NULL, x2, v2, 2));
  assert_err(vi_cont_curve_set_impacts(c, t2, x2, v2, 1)); /* ld < n */
  t2[1] = NAN;
  assert_err(vi_cont_curve_set_impacts(c, t2, x2, v2, 2));
  assert_int_equal(vi_cont_curve_impacts(c, t2, x2, v2, 2), VI_ERR_STATE); /* no point yet */
  assert_err(vi_cont_curve_impacts(c, t2, x2, v2, 1));
  vi_cont_curve_destroy(&c);
  vi_model_destroy(&m);
}

/* vi_identify_*: NULL handles, out-of-range parameters, bad data, results
 * before a fit. */
static int ident_builder(const double *p, void *user, vi_model **out)
{
  (void)p;
  (void)user;
  *out = NULL;
  return VI_ERR_ARG;
}

static void test_identify_misuse(void **state)
{
  (void)state;
  vi_identify *id = NULL;
  vi_model *m = vi_test_fig2();
  double t[20], x[20], R[4], c[2] = {0, 0};
  int fl[1];
  for (int i = 0; i < 20; i++) {
    t[i] = i;
    x[i] = 0.0;
  }
  assert_err(vi_identify_create(NULL, 1, &id));
  assert_err(vi_identify_create(m, 1, NULL));
  assert_int_equal(vi_identify_create(m, 0, &id), VI_ERR_DIM);
  assert_null(id);
  vi_identify_destroy(NULL);
  vi_identify_destroy(&id);
  assert_string_equal(vi_identify_errmsg(NULL), "");
  assert_int_equal(vi_identify_nparams(NULL), 0);
  assert_int_equal(vi_identify_create(m, 1, &id), VI_OK);
  assert_int_equal(vi_identify_nparams(id), 1);
  assert_err(vi_identify_set_param(NULL, 0, VI_IDENTIFY_R, 0, 0.5, 0, 1));
  assert_err(vi_identify_set_param(id, 1, VI_IDENTIFY_R, 0, 0.5, 0, 1));
  assert_err(vi_identify_set_param(id, 0, 7, 0, 0.5, 0, 1));
  assert_err(vi_identify_set_param(id, 0, VI_IDENTIFY_R, 3, 0.5, 0, 1));
  assert_err(vi_identify_set_param(id, 0, VI_IDENTIFY_R, 0, NAN, 0, 1));
  assert_err_msg(vi_identify_set_param(id, 0, VI_IDENTIFY_XS, 0, 2.0, 0, 1), "outside");
  assert_err(vi_identify_set_param_key(NULL, 0, "stop.r", NAN, NAN));
  assert_err(vi_identify_set_param_key(id, 0, NULL, NAN, NAN));
  assert_err(vi_identify_set_param_key(id, 0, "no.such.key", NAN, NAN));
  assert_err(vi_identify_set_param_key(id, 0, "stop.r", 0.8, 0.9));
  assert_err(vi_identify_set_builder(NULL, ident_builder, NULL, NULL));
  assert_err(vi_identify_set_cancel(NULL, NULL, NULL, NULL));
  assert_err(vi_identify_set_observation(NULL, NULL));
  assert_err(vi_identify_set_observation(id, c));
  c[0] = NAN;
  assert_int_equal(vi_identify_set_observation(id, c), VI_ERR_NONFINITE);
  assert_err(vi_identify_set_shift(NULL, 1, NAN));
  assert_err(vi_identify_set_shift(id, 2, 0.0));
  assert_err(vi_identify_set_shift(id, 0, NAN));
  assert_err(vi_identify_set_noise(NULL, 0.1));
  assert_err(vi_identify_set_stable_only(NULL, 1));
  assert_err(vi_identify_set_stable_only(id, 2));
  assert_int_equal(vi_identify_stability(id, R), VI_ERR_STATE);
  assert_int_equal(vi_identify_stability(NULL, R), VI_ERR_ARG);
  assert_int_equal(vi_identify_set_noise(id, INFINITY), VI_ERR_NONFINITE);
  assert_err(vi_identify_set_data(NULL, 20, t, x, NULL));
  assert_err(vi_identify_set_data(id, 20, NULL, x, NULL));
  assert_err_msg(vi_identify_set_data(id, 15, t, x, NULL), "too few");
  t[3] = t[2];
  assert_err_msg(vi_identify_set_data(id, 20, t, x, NULL), "sample 4");
  t[3] = 3.0;
  x[5] = INFINITY;
  assert_int_equal(vi_identify_set_data(id, 20, t, x, NULL), VI_ERR_NONFINITE);
  x[5] = 0.0;
  /* out of order: no data, a parameter not set */
  assert_int_equal(vi_identify_run(NULL), VI_ERR_ARG);
  assert_int_equal(vi_identify_run(id), VI_ERR_STATE);
  assert_int_equal(vi_identify_set_data(id, 20, t, x, NULL), VI_OK);
  assert_int_equal(vi_identify_run(id), VI_ERR_STATE);
  /* the builder fails at the start */
  assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_OTHER, 0, 0.5, 0, 1), VI_OK);
  assert_int_equal(vi_identify_run(id), VI_ERR_STATE); /* no key, no builder */
  assert_int_equal(vi_identify_set_builder(id, ident_builder, NULL, NULL), VI_OK);
  assert_err(vi_identify_run(id));
  assert_int_equal(vi_identify_set_builder(id, NULL, NULL, NULL), VI_OK);
  /* results before a completed fit */
  assert_int_equal(vi_identify_params(id, NULL, NULL, NULL, NULL, fl), VI_ERR_STATE);
  assert_int_equal(vi_identify_params(NULL, NULL, NULL, NULL, NULL, fl), VI_ERR_ARG);
  assert_int_equal(vi_identify_shift(id, NULL, NULL), VI_ERR_STATE);
  assert_int_equal(vi_identify_shift(NULL, NULL, NULL), VI_ERR_ARG);
  assert_int_equal(vi_identify_correlation(id, R, 1), VI_ERR_STATE);
  assert_int_equal(vi_identify_correlation(NULL, R, 1), VI_ERR_ARG);
  assert_int_equal(vi_identify_summary(id, NULL, NULL, NULL, NULL, NULL, NULL, NULL), VI_ERR_STATE);
  assert_int_equal(vi_identify_summary(NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL), VI_ERR_ARG);
  assert_int_equal(vi_identify_orbit_period(id, R, NULL), VI_ERR_STATE);
  assert_int_equal(vi_identify_orbit_period(NULL, R, NULL), VI_ERR_ARG);
  assert_int_equal(vi_identify_response(id, 1, t, x, NULL), VI_ERR_STATE);
  assert_int_equal(vi_identify_response(NULL, 1, t, x, NULL), VI_ERR_ARG);
  {
    int oi[2], oc = -1;
    double oz[2];
    assert_int_equal(vi_identify_outliers(id, 6.0, 2, oi, oz, &oc, NULL), VI_ERR_STATE);
    assert_int_equal(vi_identify_outliers(NULL, 6.0, 2, oi, oz, &oc, NULL), VI_ERR_ARG);
    assert_int_equal(vi_identify_outliers(id, 0.0, 2, oi, oz, &oc, NULL), VI_ERR_ARG);
    assert_int_equal(vi_identify_outliers(id, NAN, 2, oi, oz, &oc, NULL), VI_ERR_ARG);
    assert_int_equal(vi_identify_outliers(id, 6.0, -1, oi, oz, &oc, NULL), VI_ERR_ARG);
    assert_int_equal(vi_identify_outliers(id, 6.0, 2, NULL, oz, &oc, NULL), VI_ERR_ARG);
    assert_int_equal(vi_identify_outliers(id, 6.0, 2, oi, NULL, &oc, NULL), VI_ERR_ARG);
    assert_int_equal(oc, -1); /* nothing written on an error */
  }
  assert_int_equal(vi_identify_energy_restitution(id, NULL, NULL, NULL, NULL), VI_ERR_STATE);
  assert_int_equal(vi_identify_energy_restitution(NULL, NULL, NULL, NULL, NULL), VI_ERR_ARG);
  /* issue 28: the solutions, profile and sensors API */
  assert_int_equal(vi_identify_profile(id, NULL, NULL, NULL), VI_ERR_STATE);
  assert_int_equal(vi_identify_profile(NULL, NULL, NULL, NULL), VI_ERR_ARG);
  assert_int_equal(vi_identify_nsolutions(id, NULL), 0);
  assert_int_equal(vi_identify_nsolutions(NULL, NULL), 0);
  assert_int_equal(vi_identify_solution(id, 0, NULL, NULL, NULL, NULL, NULL), VI_ERR_STATE);
  assert_int_equal(vi_identify_solution(NULL, 0, NULL, NULL, NULL, NULL, NULL), VI_ERR_ARG);
  assert_int_equal(vi_identify_solution_profile(id, 0, NULL, NULL, NULL), VI_ERR_STATE);
  assert_int_equal(vi_identify_solution_profile(NULL, 0, NULL, NULL, NULL), VI_ERR_ARG);
  assert_int_equal(vi_identify_solution_summary(id, 0, NULL, NULL, NULL, NULL, NULL, NULL), VI_ERR_STATE);
  assert_int_equal(vi_identify_solution_summary(NULL, 0, NULL, NULL, NULL, NULL, NULL, NULL), VI_ERR_ARG);
  assert_int_equal(vi_identify_search_range(id, NULL, NULL), VI_ERR_STATE);
  assert_int_equal(vi_identify_search_range(NULL, NULL, NULL), VI_ERR_ARG);
  assert_int_equal(vi_identify_solution_separation(id, 0, NULL, NULL), VI_ERR_STATE);
  assert_int_equal(vi_identify_solution_separation(NULL, 0, NULL, NULL), VI_ERR_ARG);
  assert_err(vi_identify_set_global(NULL, 1));
  assert_err(vi_identify_add_channel(NULL, c, 0, x));
  assert_err(vi_identify_add_channel(id, c, 3, x));
  assert_err(vi_identify_add_channel(id, NULL, 0, x));
  assert_err(vi_identify_set_global(id, 2));
  assert_err(vi_identify_set_sensors(NULL, 20, t, x, NULL, NULL));
  assert_err_msg(vi_identify_set_sensors(id, 20, t, NULL, NULL, NULL), "no times or values");
  assert_err_msg(vi_identify_set_sensors(id, 15, t, NULL, x, NULL), "too few");
  x[3] = NAN;
  assert_int_equal(vi_identify_set_sensors(id, 20, t, NULL, NULL, x), VI_ERR_NONFINITE);
  assert_non_null(strstr(vi_identify_errmsg(id), "a = nan"));
  x[3] = 0.0;
  { /* the forcing phase of a recorded signal */
    double tt[3] = {0, 1, 2}, ff[3] = {1, 0, -1}, same[3] = {0, 0, 0}, ph;
    assert_err(vi_identify_forcing_phase(3, tt, ff, 1.0, NULL));
    assert_err(vi_identify_forcing_phase(3, NULL, ff, 1.0, &ph));
    assert_true(isnan(ph));
    assert_err(vi_identify_forcing_phase(3, tt, NULL, 1.0, &ph));
    assert_err(vi_identify_forcing_phase(1, tt, ff, 1.0, &ph));
    assert_int_equal(vi_identify_forcing_phase(3, tt, ff, 0.0, &ph), VI_ERR_FREQUENCY);
    assert_int_equal(vi_identify_forcing_phase(3, tt, ff, NAN, &ph), VI_ERR_NONFINITE);
    ff[1] = INFINITY;
    assert_int_equal(vi_identify_forcing_phase(3, tt, ff, 1.0, &ph), VI_ERR_NONFINITE);
    /* every sample at t = 0: sin is 0 throughout, no phase */
    assert_int_equal(vi_identify_forcing_phase(3, same, tt, 1.0, &ph), VI_ERR_ARG);
    assert_true(isnan(ph));
  }
  vi_identify_destroy(&id);
  assert_null(id);
  vi_model_destroy(&m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_model_misuse),
      cmocka_unit_test(test_fe_misuse),
      cmocka_unit_test(test_sim_misuse),
      cmocka_unit_test(test_impact_flow_misuse),
      cmocka_unit_test(test_model_band_getters_misuse),
      cmocka_unit_test(test_builders_misuse),
      cmocka_unit_test(test_impact_multi_misuse),
      cmocka_unit_test(test_orbit_misuse),
      cmocka_unit_test(test_param_misuse),
      cmocka_unit_test(test_param_in_use),
      cmocka_unit_test(test_load_at_range_end),
      cmocka_unit_test(test_sweep_misuse),
      cmocka_unit_test(test_census_misuse),
      cmocka_unit_test(test_truncated_misuse),
      cmocka_unit_test(test_truncation_misuse),
      cmocka_unit_test(test_cont_misuse),
      cmocka_unit_test(test_curve_misuse),
      cmocka_unit_test(test_identify_misuse),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
