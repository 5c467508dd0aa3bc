/* test_api.c - handle life cycle, status table, versions. */
#include <string.h>

#include "vi_testutil.h"

static void test_destroy_null_and_twice(void **state)
{
  (void)state;
  vi_model *m = NULL;
  vi_model_destroy(NULL);
  vi_model_destroy(&m);
  m = vi_test_fig2();
  vi_sim *s = NULL;
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  vi_sim_destroy(&s);
  assert_null(s);
  vi_sim_destroy(&s);
  vi_sim_destroy(NULL);
  vi_model_destroy(&m);
  assert_null(m);
  vi_model_destroy(&m);
}

/* User data handed over with a destroy function is destroyed exactly once:
 * when another pointer replaces it or the handle goes, never while in use. */
static int n_destroyed;
static void count_destroy(void *user)
{
  n_destroyed++;
  *(int *)user = -1;
}
static int never(const vi_event *ev, void *user)
{
  (void)ev;
  (void)user;
  return 0;
}
static int never_mon(const vi_progress *p, void *user)
{
  (void)p;
  (void)user;
  return 0;
}

static void test_user_data_destroy(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  vi_sim *s = NULL;
  int a = 1, b = 2, c = 3;
  n_destroyed = 0;
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_sim_set_event_callback(s, never, &a, count_destroy), VI_OK);
  /* the same pointer again: still in use, not destroyed */
  assert_int_equal(vi_sim_set_event_callback(s, never, &a, count_destroy), VI_OK);
  assert_int_equal(n_destroyed, 0);
  assert_int_equal(vi_sim_set_event_callback(s, never, &b, count_destroy), VI_OK);
  assert_int_equal(n_destroyed, 1);
  assert_int_equal(a, -1);
  /* a refused setting takes nothing over */
  assert_int_equal(vi_sim_set_sampling(s, -1.0, NULL, &c, count_destroy), VI_OK);
  assert_int_equal(vi_sim_set_monitor(s, -1.0, never_mon, &c,
                                      count_destroy), VI_ERR_ARG);
  assert_int_equal(c, 3);
  vi_sim_destroy(&s);
  /* b at destroy, c once (sampling, set with fn NULL, kept until destroy) */
  assert_int_equal(n_destroyed, 3);
  assert_int_equal(b, -1);
  assert_int_equal(c, -1);
  vi_model_destroy(&m);
}

static void test_status_table(void **state)
{
  (void)state;
  static const int codes[] = {
#define X_(name, value, msg) value,
      VI_STATUS_LIST(X_)
#undef X_
  };
  size_t nc = sizeof codes / sizeof codes[0];
  for (size_t i = 0; i < nc; i++) {
    assert_string_not_equal(vi_status_name(codes[i]), "VI_UNKNOWN");
    assert_true(strlen(vi_strerror(codes[i])) > 3);
    for (size_t j = 0; j < i; j++) {
      assert_int_not_equal(codes[i], codes[j]);
      assert_string_not_equal(vi_status_name(codes[i]),
                              vi_status_name(codes[j]));
    }
  }
  assert_string_equal(vi_status_name(VI_ERR_NOT_SPD), "VI_ERR_NOT_SPD");
  assert_string_equal(vi_status_name(12345), "VI_UNKNOWN");
  assert_non_null(vi_strerror(12345));
}

static void test_versions_agree(void **state)
{
  (void)state;
  assert_int_equal(vi_version_number(), VI_VERSION_NUMBER);
  assert_string_equal(vi_version_string(), VI_VERSION_STRING);
  assert_string_equal(vi_sundials_version(), "6.4.1");
}

static void test_stats_and_getters_before_setup(void **state)
{
  (void)state;
  vi_model *m = NULL;
  assert_int_equal(vi_model_create(3, &m), VI_OK);
  assert_null(vi_model_omega(m)); /* views only after setup */
  vi_sim *s = NULL;
  assert_int_equal(vi_sim_create(m, &s), VI_ERR_STATE);
  assert_null(s);
  vi_model_destroy(&m);
  m = vi_test_fig2();
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_sim_stat(s, VI_STAT_COUNT), -1);
  assert_int_equal(vi_sim_stat(s, VI_STAT_IMPACTS), 0);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_destroy_null_and_twice),
      cmocka_unit_test(test_user_data_destroy),
      cmocka_unit_test(test_status_table),
      cmocka_unit_test(test_versions_agree),
      cmocka_unit_test(test_stats_and_getters_before_setup),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
