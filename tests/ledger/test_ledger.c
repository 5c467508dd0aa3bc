/* test_ledger.c - the per-mode energy ledger closes (MODEL.md section 4). */
#include <math.h>
#include <stdlib.h>

#include "vi_testutil.h"

typedef struct led_stats {
  int intervals, impacts;
  double maxres, max_jump_err, max_xe, sum_ce_err;
} led_stats;

static int on_interval(const vi_ledger_interval *iv, void *u)
{
  led_stats *st = u;
  st->intervals++;
  st->maxres = fmax(st->maxres, iv->residual);
  double xe = 0.0, ce = 0.0, cabs = 0.0;
  for (int j = 0; j < iv->n; j++) {
    xe = fmax(xe, fabs(iv->XE[j]));
    ce += iv->CE[j];
    cabs += fabs(iv->CE[j]);
  }
  st->max_xe = fmax(st->max_xe, xe);
  st->sum_ce_err = fmax(st->sum_ce_err, fabs(ce));
  (void)cabs;
  if (iv->dE) {
    /* the jumps sum to -IE (WB 10) */
    double sum = 0.0;
    for (int j = 0; j < iv->n; j++) sum += iv->dE[j];
    st->max_jump_err = fmax(st->max_jump_err, fabs(sum + iv->ie) / fmax(iv->ie, 1e-300));
    st->impacts++;
  }
  return 0;
}

static led_stats run_ledger(const vi_model *m, int method, double rtol,
                            const double *x0, const double *v0, double t_end)
{
  led_stats st = {0};
  vi_sim *s = vi_test_sim(m, method, rtol, rtol * 1e-2, x0, v0, NULL);
  assert_int_equal(vi_sim_enable_ledger(s, 1), VI_OK);
  assert_int_equal(vi_sim_set_ledger_callback(s, on_interval, &st, NULL), VI_OK);
  assert_int_equal(vi_sim_run(s, t_end), VI_OK);
  assert_close(vi_sim_ledger_max_residual(s), st.maxres, 0);
  vi_sim_destroy(&s);
  return st;
}

/* Fig. 2 at rtol 1e-10: every interval closes to 1e-8 relative (CVODE, the
 * quadratures under the state's error control) or round-off (exact). */
static void test_fig2_closure(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  double t_end = 100 * 2 * M_PI / 0.9;
  /* BDF is the least accurate per tolerance (see vi_bench): it meets the
   * bound one decade tighter */
  const int meth[3] = {VI_METHOD_ADAMS, VI_METHOD_BDF, VI_METHOD_EXACT};
  const double rtol[3] = {1e-10, 1e-11, 1e-10}, bound[3] = {1e-8, 1e-8, 1e-12};
  for (int k = 0; k < 3; k++) {
    led_stats st = run_ledger(m, meth[k], rtol[k], NULL, NULL, t_end);
    print_message("fig2 method %d: %d intervals, %d impacts, max residual "
                  "%.3g, jump error %.3g\n", meth[k], st.intervals, st.impacts,
                  st.maxres, st.max_jump_err);
    assert_true(st.impacts >= 99);
    assert_true(st.maxres <= bound[k]);
    assert_true(st.max_jump_err < 1e-12);
    assert_true(st.max_xe == 0.0); /* proportional: XE not computed */
  }
  vi_model_destroy(&m);
}

/* Non-proportional damping, non-diagonal M, non-unit w: XE is non-zero and
 * the ledger still closes. */
static void test_nonproportional_closure(void **state)
{
  (void)state;
  vi_model *m = vi_test_nonprop3(0.05, NULL);
  for (int k = 0; k < 3; k++) { /* Adams, BDF, exact */
    led_stats st = run_ledger(m, k, 1e-10, NULL, NULL, 400.0);
    print_message("3-dof method %d: %d impacts, max residual %.3g, max |XE| "
                  "%.3g\n", k, st.impacts, st.maxres, st.max_xe);
    assert_true(st.impacts > 20);
    assert_true(st.maxres <= (k == VI_METHOD_EXACT ? 1e-12 : 1e-8));
    assert_true(st.max_xe > 1e-4);
    assert_true(st.max_jump_err < 1e-12);
  }
  vi_model_destroy(&m);
}

/* r = 1, C = 0: no loss anywhere, so over a long run the summed forcing
 * work equals the change of total mechanical energy. */
static void test_conservative_run(void **state)
{
  (void)state;
  const double a[2] = {0.3, 0.0};
  vi_model *m = vi_test_chain(2, 1.0, 1.0, 0.0, 0.4, 1.0, 0.9, a);
  for (int k = 0; k < 3; k++) {
    int meth = k == 2 ? VI_METHOD_EXACT : k;
    vi_sim *s = vi_test_sim(m, meth, 1e-10, 1e-12, NULL, NULL, NULL);
    assert_int_equal(vi_sim_enable_ledger(s, 1), VI_OK);
    assert_int_equal(vi_sim_run(s, 2000.0), VI_OK);
    double E[2], FE[2], DE[2], dE[2], ie, x[2], v[2];
    assert_int_equal(vi_sim_ledger(s, E, FE, DE, NULL, NULL, dE, &ie), VI_OK);
    vi_sim_state(s, NULL, x, v);
    double etot = vi_model_energy(m, x, v);
    assert_close(E[0] + E[1], etot, 1e-13);
    assert_close(ie, 0.0, 0.0);
    assert_close(DE[0] + DE[1], 0.0, 0.0);
    assert_close(dE[0] + dE[1], 0.0, 1e-12);    /* r = 1: jumps only move energy */
    double scale = fabs(FE[0]) + fabs(FE[1]);
    print_message("conservative method %d: %lld impacts, E = %.12g, sum FE = "
                  "%.12g, |FE| scale %.3g\n", meth,
                  (long long)vi_sim_stat(s, VI_STAT_IMPACTS), etot,
                  FE[0] + FE[1], scale);
    assert_true(vi_sim_stat(s, VI_STAT_IMPACTS) > 100);
    /* the drift is integration error: round-off for the exact flow; at
     * rtol 1e-10 over 2000 time units measured 4e-9 (Adams), 1.1e-6 (BDF) */
    double tol = meth == VI_METHOD_EXACT ? 1e-11 : meth == VI_METHOD_ADAMS ? 1e-8 : 1e-5;
    assert_close(FE[0] + FE[1], etot, tol * scale);
    vi_sim_destroy(&s);
  }
  vi_model_destroy(&m);
}

/* Sticking: the contact force does no net work (w.v = 0), but it moves
 * energy between modes; the ledger with CE closes through the phase. */
static void test_sticking_ledger(void **state)
{
  (void)state;
  const double f0[2] = {0.0, 0.3}, a[2] = {0.5, 0.0};
  const double mass[2] = {1, 1}, k[2] = {1, 1}, c[2] = {0.05, 0.05}, w[2] = {0, 1};
  double M[4], C[4], K[4];
  vi_build_chain(2, mass, k, c, M, C, K, 2);
  vi_model *m = vi_test_model(2, M, C, K, 0.5, a, f0, w, 0.2, 0.0); /* plastic */
  led_stats st = {0};
  vi_sim *s = vi_test_sim(m, VI_METHOD_ADAMS, 1e-10, 1e-12, NULL, NULL, NULL);
  assert_int_equal(vi_sim_enable_ledger(s, 1), VI_OK);
  assert_int_equal(vi_sim_set_ledger_callback(s, on_interval, &st, NULL), VI_OK);
  assert_int_equal(vi_sim_run(s, 300.0), VI_OK);
  double CE[2];
  vi_sim_ledger(s, NULL, NULL, NULL, NULL, CE, NULL, NULL);
  print_message("sticking: %lld sticks, %d intervals, residual %.3g, CE = "
                "(%.6g, %.6g)\n", (long long)vi_sim_stat(s, VI_STAT_STICKS),
                st.intervals, st.maxres, CE[0], CE[1]);
  assert_true(vi_sim_stat(s, VI_STAT_STICKS) > 5);
  assert_true(fabs(CE[0]) > 1e-4);               /* work moved between modes */
  assert_close(CE[0] + CE[1], 0.0, 1e-8 * fabs(CE[0]));
  assert_true(st.maxres <= 1e-8);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
}

/* Windowed totals: the difference of two cumulative snapshots is the
 * ledger of the window, and it closes like any interval. */
static void test_window_totals(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  vi_sim *s = vi_test_sim(m, VI_METHOD_EXACT, 1e-12, 1e-14, NULL, NULL, NULL);
  assert_int_equal(vi_sim_enable_ledger(s, 1), VI_OK);
  double T = 2 * M_PI / 0.9, E1[2], F1[2], D1[2], J1[2], ie1, E2[2], F2[2], D2[2], J2[2], ie2;
  assert_int_equal(vi_sim_run(s, 50.3 * T), VI_OK);
  assert_int_equal(vi_sim_ledger(s, E1, F1, D1, NULL, NULL, J1, &ie1), VI_OK);
  int64_t i1 = vi_sim_stat(s, VI_STAT_IMPACTS);
  assert_int_equal(vi_sim_run(s, 57.3 * T), VI_OK); /* seven periods */
  assert_int_equal(vi_sim_ledger(s, E2, F2, D2, NULL, NULL, J2, &ie2), VI_OK);
  assert_int_equal(vi_sim_stat(s, VI_STAT_IMPACTS) - i1, 7);
  double lhs = E2[0] + E2[1] - E1[0] - E1[1], rhs = 0.0, jumps = 0.0;
  for (int j = 0; j < 2; j++) {
    rhs += (F2[j] - F1[j]) - (D2[j] - D1[j]) + (J2[j] - J1[j]);
    jumps += J2[j] - J1[j];
  }
  assert_close(lhs, rhs, 1e-11);
  assert_close(jumps, -(ie2 - ie1), 1e-12);  /* the window's jumps sum to -IE */
  assert_true(ie2 - ie1 > 1.0);             /* seven impacts of ~0.158 */
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
}

/* The exact method's closed-form ledger is computed when read: reading
 * the totals mid-flight (between runs) changes nothing, a run in two
 * pieces gives one run's totals, and a new initial state mid-run keeps
 * the integrals owed up to the old time and closes from the new one. */
static void test_deferred_reads(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  double T = 2 * M_PI / 0.9, F1[2], D1[2], F2[2], D2[2], Fa[2], Da[2];
  vi_sim *a = vi_test_sim(m, VI_METHOD_EXACT, 1e-10, 1e-12, NULL, NULL, NULL);
  vi_sim *b = vi_test_sim(m, VI_METHOD_EXACT, 1e-10, 1e-12, NULL, NULL, NULL);
  assert_int_equal(vi_sim_enable_ledger(a, 1), VI_OK);
  assert_int_equal(vi_sim_enable_ledger(b, 1), VI_OK);
  assert_int_equal(vi_sim_run(a, 20.3 * T), VI_OK);
  assert_int_equal(vi_sim_run(b, 10.3 * T), VI_OK); /* mid-flight */
  for (int k = 0; k < 3; k++) /* read, and read again */
    assert_int_equal(vi_sim_ledger(b, NULL, F1, D1, NULL, NULL, NULL, NULL),
                     VI_OK);
  assert_int_equal(vi_sim_run(b, 20.3 * T), VI_OK);
  assert_int_equal(vi_sim_ledger(a, NULL, Fa, Da, NULL, NULL, NULL, NULL),
                   VI_OK);
  assert_int_equal(vi_sim_ledger(b, NULL, F2, D2, NULL, NULL, NULL, NULL),
                   VI_OK);
  for (int j = 0; j < 2; j++) {
    /* the same motion (the grid restarts at 10.3 T: impact times agree to
     * the root's tolerance), the same integrals */
    assert_close(F2[j], Fa[j], 1e-9 * fabs(Fa[j]));
    assert_close(D2[j], Da[j], 1e-9 * fabs(Da[j]));
    assert_true(F2[j] != F1[j] && D2[j] > D1[j]);
  }
  assert_true(vi_sim_ledger_max_residual(b) <= 1e-12);
  /* a new state at 20.3 T: FE, DE so far are kept, and go on from there */
  const double x0[2] = {0.05, -0.02}, v0[2] = {0.3, 0.1};
  assert_int_equal(vi_sim_set_initial(b, 20.3 * T, x0, v0), VI_OK);
  assert_int_equal(vi_sim_ledger(b, NULL, F1, D1, NULL, NULL, NULL, NULL),
                   VI_OK);
  for (int j = 0; j < 2; j++) {
    assert_true(F1[j] == F2[j]);
    assert_true(D1[j] == D2[j]);
  }
  assert_int_equal(vi_sim_run(b, 30.3 * T), VI_OK);
  assert_true(vi_sim_ledger_max_residual(b) <= 1e-12);
  vi_sim_destroy(&a);
  vi_sim_destroy(&b);
  vi_model_destroy(&m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_fig2_closure),
      cmocka_unit_test(test_deferred_reads),
      cmocka_unit_test(test_nonproportional_closure),
      cmocka_unit_test(test_conservative_run),
      cmocka_unit_test(test_sticking_ledger),
      cmocka_unit_test(test_window_totals),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
