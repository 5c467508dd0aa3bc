/* test_stress_chatref.c - impacts a user can count on (issue 20, item 5)
 * against an independent reference.
 *
 * By default every impact with v_n >= 1e-5 V (V = vi_sim_velocity_scale:
 * the largest initial speed or approach velocity) is reported
 * individually, by every method alike.  ref/chatter_ref.py follows two
 * chattering models to their first accumulation point without the library
 * (30-digit mpmath: closed-form modal flights, contacts by dense sampling
 * of the gap and of its local maxima, bisection) and writes the impacts
 * above 1e-5 V as ref/chatter_ref_{chain,rod}.csv (index, t, v_n):
 *  - the 2-DOF chain of test_stress_mdof.c (unit masses, K = [2 -1; -1 1],
 *    load 1 on mass 2 into the stop x_2 <= 0, r 0.8, v0 = (2, -0.3),
 *    V = 2): 44 impacts, the last at 1.2e-5 V, the next at 9.6e-6 V;
 *  - the 20-mode rod of issue 20 as test_sim.c builds it: 52 impacts, the
 *    last at 1.06e-5 V, the next at 8.4e-6 V, accumulating at 0.921040.
 * The threshold falls between two impacts a factor r apart, so the count
 * is exact: every method must report exactly these impacts above 1e-5 V
 * before its first stick.
 *
 * Tolerances (rtol 1e-12, atol 1e-14): the gap's position error is
 * dx = 10 sum |w_i| (atol + rtol |x_i|) (|w|_1 = 1, x ~ 1 for the chain;
 * |w|_1 = 20 sqrt 2, modal amplitudes <= 0.05 for the rod).  It shifts a
 * landing of approach velocity v_n by dx / v_n, and in a chattering
 * sequence the shifts add up geometrically, to dx / (v_n (1 - r)) (plus
 * 10 rtol t for the clock).  A timing error dt changes v_n by the contact
 * acceleration a = g'' (written by the reference for each impact) times
 * dt, plus the velocity error 10 (atol + rtol V).
 *
 * Whether the count at the threshold is decided by the tolerances at all is
 * printed: the v_n bound of the last impact above 1e-5 V against its
 * distance to the threshold.  For the chain it is 0.88 (decided); for the
 * rod it is 3e3: the flight before its last impact above (1.056e-5 V,
 * 7.7e-7) rises (r v_n)^2 / (2 a) = 2.6e-13 (a = 1.12), below dx, so at
 * the run's tolerances an integrator's v_n there would only be good to
 * some 10 % (BDF reported 9.48e-6 V, one impact short).  The simulator
 * tightens the integrators' tolerances for such a low flight when the next
 * impact is one to report, until dx is 1/50 of the apex (vi_sim.c,
 * on_contact_one): every method must then report all 52, with v_n within
 * the bounds above. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stress_util.h"

#ifndef VI_CHATREF_DIR
#error "VI_CHATREF_DIR: the folder of chatter_ref_*.csv"
#endif

#define RTOL 1e-12
#define ATOL 1e-14
#define RR 0.8

typedef struct ref_seq {
  int n;
  double V, below, t[256], vn[256], a[256];
} ref_seq;

static void ref_read(const char *name, ref_seq *r)
{
  char path[1024], line[512];
  snprintf(path, sizeof path, "%s/%s", VI_CHATREF_DIR, name);
  FILE *f = fopen(path, "r");
  assert_non_null(f);
  r->n = 0;
  r->V = r->below = NAN;
  static const char below[] = "# first v_n below 1e-5 V: ";
  while (fgets(line, sizeof line, f)) {
    if (strncmp(line, "# V ", 4) == 0) r->V = strtod(line + 4, NULL);
    if (strncmp(line, below, sizeof below - 1) == 0)
      r->below = strtod(line + sizeof below - 1, NULL);
    if (line[0] < '0' || line[0] > '9') continue; /* comments, the header */
    /* index,t,vn,a */
    char *p = line, *e;
    long i = strtol(p, &e, 10);
    double v[3];
    for (int c = 0; c < 3; c++) {
      assert_true(*e == ',');
      p = e + 1;
      v[c] = strtod(p, &e);
      assert_true(e != p);
    }
    double t = v[0], vn = v[1], a = v[2];
    assert_int_equal(i, r->n);
    assert_true(r->n < 256);
    r->t[r->n] = t;
    r->vn[r->n] = vn;
    r->a[r->n++] = fabs(a);
  }
  fclose(f);
  assert_true(r->n > 1 && r->V > 0 && r->below > 0);
}

/* Every method with the default impact resolution against the reference:
 * the impacts above 1e-5 V before the first stick, their count, times and
 * approach velocities.  W1 = |w|_1 and X the largest |x_i|: the gap's
 * position error is sum |w_i| (atol + rtol |x_i|) <= W1 (atol + rtol X),
 * times 10 as in test_stress_mdof.c.  known: a method whose count is
 * known to miss by one (reported, and held to that). */
static void check_all(const vi_model *m, const char *csv, const double *x0,
                      const double *v0, double t_end, double W1, double X,
                      int known)
{
  static ref_seq ref;
  memset(&ref, 0, sizeof ref);
  ref_read(csv, &ref);
  const double dx = 10.0 * W1 * (ATOL + RTOL * X), dv = 10.0 * (ATOL + RTOL * ref.V);
  /* bounds of impact k: time, and v_n through the contact acceleration */
#define BT(k) (dx / ((1.0 - RR) * ref.vn[k]) + 10.0 * RTOL * ref.t[k])
#define BV(k) (ref.a[k] * BT(k) + dv)
  /* is the count at the threshold decided by the tolerances?  The v_n
   * bound of the last impact above it against its distance to it */
  double thr = 1e-5 * ref.V, last = ref.vn[ref.n - 1];
  print_message("  %s: %d impacts >= 1e-5 V, the last %.4g V with v_n bound "
                "%.3g of its distance to the threshold, the next %.4g V\n",
                csv, ref.n, last / ref.V, BV(ref.n - 1) / (last - thr),
                ref.below / ref.V);
  int kV = 0;
  for (int k = 1; k < ref.n; k++) kV = ref.vn[k] > ref.vn[kV] ? k : kV;
  for (int meth = 0; meth < VI_METHOD_COUNT; meth++) {
    if (!st_method_ok(m, meth)) continue;
    vi_test_events ev = {0};
    vi_sim *s = vi_test_sim(m, meth, RTOL, ATOL, x0, v0, &ev);
    int st = vi_sim_run(s, t_end);
    if (st != VI_OK) print_error("%s: %s\n", vi_method_name(meth), vi_sim_errmsg(s));
    st_check(st == VI_OK);
    double V = vi_sim_velocity_scale(s);
    st_check(fabs(V - ref.V) <= BV(kV));
    int above = 0, stuck = 0;
    double et = 0, ev_ = 0, rt = 0, rv = 0, vlast = NAN;
    for (int i = 0; i < ev.count && !stuck; i++) {
      if (ev.kind[i] == VI_EVENT_STICK) stuck = 1;
      if (ev.kind[i] != VI_EVENT_IMPACT || ev.vn[i] < 1e-5 * V) continue;
      if (above < ref.n) {
        double dt = fabs(ev.t[i] - ref.t[above]), dvn = fabs(ev.vn[i] - ref.vn[above]);
        et = fmax(et, dt);
        ev_ = fmax(ev_, dvn);
        rt = fmax(rt, dt / BT(above));
        rv = fmax(rv, dvn / BV(above));
      }
      vlast = ev.vn[i] / V;
      above++;
    }
    print_message("  %s %-5s: %d impacts >= 1e-5 V (reference %d, the last "
                  "%.4g V), V %.12g (reference %.12g); |dt| <= %.3g (%.3g of "
                  "its bound), |dv_n| <= %.3g (%.3g of its bound)\n", csv,
                  vi_method_name(meth), above, ref.n, vlast, V, ref.V, et, rt,
                  ev_, rv);
    st_check(stuck);
    if (meth == known) {
      print_message("  KNOWN FAILURE (issue 20, item 5): %s reports %d of the "
                    "%d impacts above 1e-5 V\n", vi_method_name(meth), above,
                    ref.n);
      st_check(above == ref.n - 1);
    } else {
      st_check(above == ref.n);
    }
    st_check(rt <= 1.0);
    st_check(rv <= 1.0);
    vi_test_events_free(&ev);
    vi_sim_destroy(&s);
  }
#undef BT
#undef BV
}

static void test_chain_impacts(void **state)
{
  (void)state;
  const double M[4] = {1, 0, 0, 1}, K[4] = {2, -1, -1, 1}, f0[2] = {0, 1};
  const double w[2] = {0, 1}, x0[2] = {0, 0}, v0[2] = {2, -0.3};
  vi_model *m = vi_test_model(2, M, NULL, K, 0.0, NULL, f0, w, 0.0, RR);
  check_all(m, "chatter_ref_chain.csv", x0, v0, 2.5, 1.0, 1.0, -1);
  vi_model_destroy(&m);
  st_end();
}

static void test_rod_impacts(void **state)
{
  (void)state;
  enum { N = 20 };
  static double M[N * N], C[N * N], K[N * N];
  double w[N], a[N];
  memset(M, 0, sizeof M);
  memset(C, 0, sizeof C);
  memset(K, 0, sizeof K);
  for (int j = 0; j < N; j++) {
    double om = (2 * j + 1) * M_PI / 2;
    size_t jj = (size_t)j * (N + 1);
    M[jj] = 1.0;
    K[jj] = om * om;
    C[jj] = 2 * 0.02 * om;
    w[j] = (j % 2 ? -1.0 : 1.0) * sqrt(2.0);
    a[j] = 0.1 * w[j];
  }
  vi_model *m = vi_test_model(N, M, C, K, 1.4, a, NULL, w, 0.05, RR);
  check_all(m, "chatter_ref_rod.csv", NULL, NULL, 1.0, N * sqrt(2.0), 0.05, -1);
  vi_model_destroy(&m);
  st_end();
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_chain_impacts),
      cmocka_unit_test(test_rod_impacts),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
