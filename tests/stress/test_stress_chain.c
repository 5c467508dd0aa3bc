/* test_stress_chain.c - a 1000-mass chain against its modal closed form
 * (issue 9, case 5).  `test_stress_chain free` and `test_stress_chain
 * impacts` are separate ctest entries: each sets up one 1000-mass model
 * (the dense modal analysis of the library takes ~3 s of the run).
 *
 * The paper's fixed-free chain (MODEL.md section 1) of N = 1000 unit masses
 * and springs, undamped, driven by a cos(W t) on the last mass (a = 2,
 * W = 0.9), stop on the last mass.  Its modes are known in closed form:
 *   th_j = (2j - 1) pi / (2N + 1),  w_j = 2 sin(th_j / 2),
 *   psi_j(i) = 2 sin(i th_j) / sqrt(2N + 1)   (mass-normalised: the sum of
 *   sin^2(i th_j) over i = 1..N is (2N + 1)/4),
 * and mode j obeys q_j'' + w_j^2 q_j = F_j cos(W t), F_j = a psi_j(N), so
 * from (t0, q0, q0') with P_j = F_j / (w_j^2 - W^2), tau = t - t0:
 *   q_j(t) = P_j cos W t + (q0 - P_j cos W t0) cos w_j tau
 *            + (q0' + P_j W sin W t0) / w_j sin w_j tau,
 * and x_N = sum_j psi_j(N) q_j.  An impact (M = I, w = e_N) changes only
 * v_N, by -(1 + r) v_N, i.e. q_j' by -(1 + r) v_N psi_j(N).  This event-
 * driven reference is written here independently of the library (no
 * LAPACK, no vi_flow): contacts by a scan of x_N - x_s in steps of 2e-3
 * (a quarter of a percent of the fastest period 2 pi / 2) and bisection to
 * round-off. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stress_util.h"

#define NCH 1000
#define WF 0.9
#define AF 2.0

typedef struct chain_ref {
  double w[NCH], psiN[NCH], P[NCH], q[NCH], qd[NCH], t0;
} chain_ref;

static void chain_ref_init(chain_ref *c)
{
  for (int j = 0; j < NCH; j++) {
    double th = (2.0 * (j + 1) - 1.0) * M_PI / (2.0 * NCH + 1.0);
    c->w[j] = 2.0 * sin(0.5 * th);
    c->psiN[j] = 2.0 * sin(NCH * th) / sqrt(2.0 * NCH + 1.0);
    c->P[j] = AF * c->psiN[j] / (c->w[j] * c->w[j] - WF * WF);
    c->q[j] = c->qd[j] = 0.0;
  }
  c->t0 = 0.0;
}

/* x_N and v_N at t from the current piece. */
static void chain_eval(const chain_ref *c, double t, double *x, double *v)
{
  double sx = 0.0, sv = 0.0, cW = cos(WF * t), sW = sin(WF * t);
  double c0 = cos(WF * c->t0), s0 = sin(WF * c->t0), tau = t - c->t0;
  for (int j = 0; j < NCH; j++) {
    double wj = c->w[j], A = c->q[j] - c->P[j] * c0;
    double B = (c->qd[j] + c->P[j] * WF * s0) / wj;
    double cj = cos(wj * tau), sj = sin(wj * tau);
    sx += c->psiN[j] * (c->P[j] * cW + A * cj + B * sj);
    sv += c->psiN[j] * (-c->P[j] * WF * sW - A * wj * sj + B * wj * cj);
  }
  *x = sx;
  if (v) *v = sv;
}

/* Move the piece's start to t (modal state at t). */
static void chain_advance(chain_ref *c, double t)
{
  double c0 = cos(WF * c->t0), s0 = sin(WF * c->t0), tau = t - c->t0;
  for (int j = 0; j < NCH; j++) {
    double wj = c->w[j], A = c->q[j] - c->P[j] * c0;
    double B = (c->qd[j] + c->P[j] * WF * s0) / wj;
    double cj = cos(wj * tau), sj = sin(wj * tau);
    c->q[j] = c->P[j] * cos(WF * t) + A * cj + B * sj;
    c->qd[j] = -c->P[j] * WF * sin(WF * t) - A * wj * sj + B * wj * cj;
  }
  c->t0 = t;
}

/* Impacts of the reference up to t_end: times and approach speeds. */
static int chain_ref_impacts(double xs, double r, double t_end, double *ti,
                             double *vi, int cap)
{
  static chain_ref c;
  chain_ref_init(&c);
  int n = 0;
  double t = c.t0, h = 2e-3, x, v;
  chain_eval(&c, t, &x, NULL);
  while (t < t_end && n < cap) {
    double x1;
    chain_eval(&c, t + h, &x1, NULL);
    if (x1 - xs > 0.0) {
      double lo = t, hi = t + h;
      for (int it = 0; it < 60; it++) {
        double mid = 0.5 * (lo + hi), xm;
        chain_eval(&c, mid, &xm, NULL);
        if (xm - xs > 0.0) hi = mid; else lo = mid;
      }
      chain_advance(&c, lo);
      chain_eval(&c, lo, &x, &v);
      ti[n] = lo;
      vi[n++] = v;
      for (int j = 0; j < NCH; j++) c.qd[j] -= (1.0 + r) * v * c.psiN[j];
      t = lo;
      continue;
    }
    t += h;
  }
  return n;
}

static vi_model *chain_model(double xs, double r)
{
  double *a = calloc(NCH, sizeof(double));
  assert_non_null(a);
  a[NCH - 1] = AF;
  vi_model *m = vi_test_chain(NCH, 1.0, 1.0, 0.0, xs, r, WF, a);
  free(a);
  return m;
}

typedef struct chain_check { chain_ref *ref; double err, xmax; int n; } chain_check;

static int chain_sample(double t, int n, const double *x, const double *v, void *u)
{
  (void)v;
  chain_check *c = u;
  double xe;
  chain_eval(c->ref, t, &xe, NULL);
  c->err = fmax(c->err, fabs(x[n - 1] - xe));
  c->xmax = fmax(c->xmax, fabs(xe));
  c->n++;
  return 0;
}

/* Stop out of reach: the last mass follows the modal closed form.  Bound:
 * position error dx = atol + rtol X (X = 3, above the largest |x_N| of 2.23), grown
 * by the number of periods of the fastest mode over the run (phase error),
 * times 10. */
static void test_chain_free_closed_form(void **state)
{
  (void)state;
  static chain_ref ref;
  chain_ref_init(&ref);
  vi_model *m = chain_model(1e3, 0.8);
  const double t_end = 5.0, rtol = 1e-10, atol = 1e-12;
  double bound = 10.0 * (atol + rtol * 3.0) * (1.0 + 2.0 * t_end / (2.0 * M_PI));
  for (int meth = 0; meth < VI_METHOD_COUNT; meth++) {
    if (meth == VI_METHOD_AUTO || !st_method_ok(m, meth)) continue;
    chain_check c = {&ref, 0.0, 0.0, 0};
    vi_sim *s = st_sim(m, meth, rtol, atol, 0.0, NULL, NULL, NULL, NULL);
    assert_int_equal(vi_sim_set_sampling(s, 0.25, chain_sample, &c), VI_OK);
    int st = vi_sim_run(s, t_end);
    st_check(st == VI_OK);
    st_check(c.n == 21);
    st_check(c.err <= bound);
    print_message("  chain of %d, stop out of reach, %-5s: max |x_N - closed "
                  "form| %.3g over %d samples (bound %.3g; max |x_N| %.3g)\n",
                  NCH, vi_method_name(meth), c.err, c.n, bound, c.xmax);
    vi_sim_destroy(&s);
  }
  vi_model_destroy(&m);
  st_end();
}

/* Stop in reach (x_s = 0.1, r = 0.8) over 10 time units: 3 impacts, all
 * before t = 1.6 (the long chain carries the driven end's energy away), and
 * none after: every impact of every method against the event-driven closed
 * form. */
static void test_chain_impacts(void **state)
{
  (void)state;
  const double xs = 0.1, r = 0.8, t_end = 10.0, rtol = 1e-10, atol = 1e-12;
  double tr[64] = {0}, vr[64] = {0};
  int nr = chain_ref_impacts(xs, r, t_end, tr, vr, 64);
  assert_true(nr >= 3);
  print_message("  reference: %d impacts in [0, %g], at %.10g %.10g %.10g\n", nr,
                t_end, tr[0], tr[1], tr[2]);
  vi_model *m = chain_model(xs, r);
  for (int meth = 0; meth < VI_METHOD_COUNT; meth++) {
    if (!st_method_ok(m, meth)) continue;
    st_log log = {0};
    st_guard guard = {0, 1000000};
    vi_sim *s = st_sim(m, meth, rtol, atol, 0.0, NULL, NULL, &log, &guard);
    int st = vi_sim_run(s, t_end);
    if (st != VI_OK) print_error("%s\n", vi_sim_errmsg(s));
    st_check(st == VI_OK);
    int ni = st_log_count(&log, VI_EVENT_IMPACT);
    st_check(ni == nr);
    double et = 0.0, ev = 0.0, worst = 0.0;
    for (int k = 0; k < ni && k < nr; k++) {
      int i = st_log_find(&log, VI_EVENT_IMPACT, k);
      /* dx / v_n in time and the error of earlier impacts carried on:
       * dx grown with the fastest mode's periods, summed over impacts */
      double dx = (atol + rtol * 3.0) * (1.0 + 2.0 * tr[k] / (2.0 * M_PI));
      double b = 0.0;
      for (int q = 0; q <= k; q++) b += 10.0 * dx / vr[q];
      et = fmax(et, fabs(log.t[i] - tr[k]));
      ev = fmax(ev, fabs(log.vn[i] - vr[k]));
      worst = fmax(worst, fabs(log.t[i] - tr[k]) / b);
      st_check(fabs(log.t[i] - tr[k]) <= b);
    }
    print_message("  chain of %d, x_s = %g, %-5s: %d impacts (reference %d), "
                  "max |dt| %.3g, max |dv_n| %.3g, worst error/bound %.3g\n",
                  NCH, xs, vi_method_name(meth), ni, nr, et, ev, worst);
    st_log_free(&log);
    vi_sim_destroy(&s);
  }
  vi_model_destroy(&m);
  st_end();
}

int main(int argc, char **argv)
{
  const struct CMUnitTest free_tests[] = {
      cmocka_unit_test(test_chain_free_closed_form),
  };
  const struct CMUnitTest impact_tests[] = {
      cmocka_unit_test(test_chain_impacts),
  };
  if (argc > 1 && !strcmp(argv[1], "impacts"))
    return cmocka_run_group_tests(impact_tests, NULL, NULL);
  return cmocka_run_group_tests(free_tests, NULL, NULL);
}
