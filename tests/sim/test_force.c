/* test_force.c - nonlinear forces (vi_force.h) against closed forms: the
 * free Duffing oscillator's period (a complete elliptic integral) and its
 * conserved energy, the bilinear (piecewise-linear) oscillator's period,
 * the host callback against the built-in spring, the ledger's NE column
 * against the nonlinear potential, and the refusals. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <gsl/gsl_sf_ellint.h>

#include "vi_testutil.h"

static const int cv_methods[2] = {VI_METHOD_ADAMS, VI_METHOD_BDF};

/* x'' + x + eps x^3 = 0, x(0) = A, x'(0) = 0 (hardening, eps > 0): with
 * w2 = 1 + eps A^2 and m = eps A^2 / (2 w2), the period is
 * T = 4 K(m) / sqrt(w2) (K the complete elliptic integral of the first kind,
 * parameter m; GSL takes the modulus sqrt(m)). */
static double duffing_period(double eps, double A)
{
  double w2 = 1.0 + eps * A * A, m = eps * A * A / (2.0 * w2);
  return 4.0 * gsl_sf_ellint_Kcomp(sqrt(m), GSL_PREC_DOUBLE) / sqrt(w2);
}

typedef struct energy_check {
  double eps, H0, err;
} energy_check;

static int check_energy(double t, int n, const double *x, const double *v,
                        void *u)
{
  (void)t;
  (void)n;
  energy_check *c = u;
  double H = 0.5 * v[0] * v[0] + 0.5 * x[0] * x[0] +
             0.25 * c->eps * x[0] * x[0] * x[0] * x[0];
  c->err = fmax(c->err, fabs(H - c->H0));
  return 0;
}

/* the cubic spring through the host callback, with its Jacobian */
static int cubic_force(double t, int n, const double *x, const double *v,
                       double *g, void *user)
{
  (void)t;
  (void)n;
  (void)v;
  double eps = *(double *)user;
  g[0] = -eps * x[0] * x[0] * x[0];
  return 0;
}

static int cubic_jac(double t, int n, const double *x, const double *v,
                     double *gx, double *gv, int ld, void *user)
{
  (void)t;
  (void)n;
  (void)v;
  (void)gv;
  (void)ld;
  gx[0] = -3.0 * *(double *)user * x[0] * x[0];
  return 0;
}

static void test_duffing_period_and_energy(void **state)
{
  (void)state;
  double eps = 0.8, A = 1.3, T = duffing_period(eps, A);
  /* the stop far out of reach: no impacts */
  vi_model *m = vi_test_sdof(1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 10.0, 0.8);
  for (int variant = 0; variant < 4; variant++) {
    int meth = cv_methods[variant % 2];
    double x0 = A, v0 = 0.0, x, v, t;
    vi_sim *s = vi_test_sim(m, meth, 1e-11, 1e-13, &x0, &v0, NULL);
    if (variant < 2)
      assert_int_equal(vi_sim_add_spring(s, VI_SPRING_CUBIC, 1, 0, eps, 0.0),
                       VI_OK);
    else /* the host callback: with its Jacobian for BDF, without for Adams */
      assert_int_equal(vi_sim_set_force(s, cubic_force, meth == VI_METHOD_BDF ? cubic_jac : NULL, &eps, NULL), VI_OK);
    energy_check c = {eps, 0.5 * A * A + 0.25 * eps * A * A * A * A, 0.0};
    assert_int_equal(vi_sim_set_sampling(s, T / 64, check_energy, &c, NULL), VI_OK);
    /* half a period: the other turning point; ten periods: back at A */
    assert_int_equal(vi_sim_run(s, 0.5 * T), VI_OK);
    vi_sim_state(s, &t, &x, &v);
    assert_close(x, -A, 1e-8);
    assert_close(v, 0.0, 1e-8);
    assert_int_equal(vi_sim_run(s, 10.0 * T), VI_OK);
    vi_sim_state(s, &t, &x, &v);
    print_message("duffing variant %d: T = %.12f, x(10 T) - A = %.2g, "
                  "v = %.2g, energy drift %.2g\n", variant, T, x - A, v, c.err);
    assert_close(x, A, 1e-7);
    assert_close(v, 0.0, 1e-7);
    assert_true(c.err < 1e-8);
    assert_int_equal(vi_sim_stat(s, VI_STAT_IMPACTS), 0);
    vi_sim_destroy(&s);
  }
  /* auto picks CVODE: the closed form has no nonlinear springs */
  vi_sim *s = NULL;
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_sim_add_spring(s, VI_SPRING_CUBIC, 1, 0, eps, 0.0), VI_OK);
  assert_int_equal(vi_sim_run(s, 1.0), VI_OK);
  assert_int_equal(vi_sim_method_used(s), VI_METHOD_ADAMS);
  assert_non_null(strstr(vi_sim_method_note(s), "nonlinear"));
  assert_int_equal(vi_sim_set_method(s, VI_METHOD_EXACT), VI_ERR_UNSUPPORTED);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
}

/* Piecewise-linear oscillator: x'' + x = 0 for x <= d, plus a spring k past
 * the gap d.  From rest at -X the mass reaches d after t1 = acos(-d / X)
 * at speed v1 = X sin t1; beyond d it oscillates at w2 = sqrt(1 + k) about
 * x* = k d / (1 + k) and comes back to d after t2 = 2 phi / w2, phi =
 * atan2(v1 / w2, d - x*); the period is 2 t1 + t2. */
static void test_bilinear_period(void **state)
{
  (void)state;
  double X = 1.0, d = 0.4, k = 3.0;
  double t1 = acos(-d / X), v1 = X * sin(t1), w2 = sqrt(1.0 + k);
  double xs = k * d / (1.0 + k), phi = atan2(v1 / w2, d - xs);
  double T = 2.0 * t1 + 2.0 * phi / w2;
  vi_model *m = vi_test_sdof(1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 10.0, 0.8);
  for (int k2 = 0; k2 < 2; k2++) {
    double x0 = -X, v0 = 0.0, x, v, t;
    vi_sim *s = vi_test_sim(m, cv_methods[k2], 1e-11, 1e-13, &x0, &v0, NULL);
    assert_int_equal(vi_sim_add_spring(s, VI_SPRING_BILINEAR, 1, 0, k, d),
                     VI_OK);
    assert_int_equal(vi_sim_run(s, 5.0 * T), VI_OK);
    vi_sim_state(s, &t, &x, &v);
    print_message("bilinear %d: T = %.12f, x(5 T) + X = %.2g, v = %.2g\n", k2,
                  T, x + X, v);
    /* the kink at d is integrated through, not located: a few 1e-8 */
    assert_close(x, -X, 1e-6);
    assert_close(v, 0.0, 1e-6);
    vi_sim_destroy(&s);
  }
  vi_model_destroy(&m);
}

/* The ledger books the nonlinear force's work: over any run, the summed NE
 * equals minus the change of the cubic spring's potential eps x^4 / 4, and
 * with r = 1, C = 0 the linear energy changes by FE + NE only. */
static void test_ledger_force_column(void **state)
{
  (void)state;
  double eps = 0.5;
  const double a[2] = {0.3, 0.0};
  vi_model *m = vi_test_chain(2, 1.0, 1.0, 0.0, 0.4, 1.0, 0.9, a);
  double x0[2] = {0.1, -0.2}, v0[2] = {0.0, 0.0};
  vi_sim *s = vi_test_sim(m, VI_METHOD_ADAMS, 1e-11, 1e-13, x0, v0, NULL);
  assert_int_equal(vi_sim_add_spring(s, VI_SPRING_CUBIC, 1, 2, eps, 0.0), VI_OK);
  assert_int_equal(vi_sim_enable_ledger(s, 1), VI_OK);
  assert_int_equal(vi_sim_run(s, 200.0), VI_OK);
  double FE[2], NE[2], x[2], v[2], ie;
  assert_int_equal(vi_sim_ledger(s, NULL, FE, NULL, NULL, NULL, NULL, &ie),
                   VI_OK);
  assert_int_equal(vi_sim_ledger_force(s, NE), VI_OK);
  vi_sim_state(s, NULL, x, v);
  double d0 = x0[0] - x0[1], d1 = x[0] - x[1];
  double dV = 0.25 * eps * (pow(d1, 4) - pow(d0, 4));
  double dE = vi_model_energy(m, x, v) - vi_model_energy(m, x0, v0);
  print_message("ledger: %lld impacts, sum NE = %.12g, -dV = %.12g, residual "
                "%.2g\n", (long long)vi_sim_stat(s, VI_STAT_IMPACTS),
                NE[0] + NE[1], -dV, vi_sim_ledger_max_residual(s));
  assert_true(vi_sim_stat(s, VI_STAT_IMPACTS) > 10);
  assert_close(ie, 0.0, 0.0);
  /* quadratures under rtol 1e-11 over 25 intervals of unit energy scale */
  assert_close(NE[0] + NE[1], -dV, 1e-9);
  assert_close(FE[0] + FE[1] + NE[0] + NE[1], dE, 1e-8);
  assert_true(vi_sim_ledger_max_residual(s) < 1e-8);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
}

static int failing_force(double t, int n, const double *x, const double *v,
                         double *g, void *user)
{
  (void)n;
  (void)x;
  (void)v;
  (void)user;
  g[0] = 0.0;
  return t > 1.0; /* e.g. the host's material law left its table */
}

/* A linear host force g_4 = -kappa x_4 on a 10-mass chain (n >= 8: the
 * BLAS path of M^-1 g = Psi Psi^T g and of its Jacobian) is the chain with
 * kappa added to K(4,4): the same impacts, by Adams (the force in the
 * right-hand side) and BDF (its Jacobian too). */
static int ground_spring(double t, int n, const double *x, const double *v,
                         double *g, void *user)
{
  (void)t; (void)n; (void)v;
  g[4] = -*(double *)user * x[4];
  return 0;
}

static int ground_spring_jac(double t, int n, const double *x,
                             const double *v, double *gx, double *gv, int ld,
                             void *user)
{
  (void)t; (void)n; (void)x; (void)v; (void)gv;
  gx[4 + 4 * ld] = -*(double *)user;
  return 0;
}

static void test_linear_force_is_stiffness(void **state)
{
  (void)state;
  enum { N = 10 };
  double kappa = 0.7, M[N * N] = {0}, K[N * N] = {0}, C[N * N], a[N] = {0},
         w[N] = {0}, mass[N], k[N], c[N];
  for (int i = 0; i < N; i++) {
    mass[i] = 1.0;
    k[i] = 1.0;
    c[i] = 0.02;
  }
  assert_int_equal(vi_build_chain(N, mass, k, c, M, C, K, N), VI_OK);
  a[N - 1] = 0.3;
  w[N - 1] = 1.0;
  vi_model *plain = vi_test_model(N, M, C, K, 0.15, a, NULL, w, 0.5, 0.8);
  K[4 + 4 * N] += kappa;
  vi_model *stiff = vi_test_model(N, M, C, K, 0.15, a, NULL, w, 0.5, 0.8);
  for (int v = 0; v < 2; v++) {
    vi_test_events e1 = {0}, e2 = {0};
    vi_sim *s = vi_test_sim(plain, cv_methods[v], 1e-10, 1e-12, NULL, NULL, &e1);
    assert_int_equal(vi_sim_set_force(s, ground_spring, v ? ground_spring_jac : NULL,
                                      &kappa, NULL), VI_OK);
    assert_int_equal(vi_sim_run(s, 300.0), VI_OK);
    vi_sim_destroy(&s);
    assert_int_equal(vi_test_run(stiff, cv_methods[v], 1e-10, 1e-12, NULL, NULL, 300.0, &e2), VI_OK);
    assert_true(e2.count >= 5);
    assert_int_equal(e1.count, e2.count);
    /* the two integrate the same ODE; rtol 1e-10 over a few hundred time
     * units of a lightly damped chain: 1e-6 */
    for (int q = 0; q < e1.count; q++) {
      assert_close(e1.t[q], e2.t[q], 1e-6);
      assert_close(e1.vn[q], e2.vn[q], 1e-6);
    }
    vi_test_events_free(&e1);
    vi_test_events_free(&e2);
  }
  vi_model_destroy(&plain);
  vi_model_destroy(&stiff);
}

static void test_force_refusals(void **state)
{
  (void)state;
  vi_model *m = vi_test_sdof(1.0, 0.1, 1.0, 0.5, 0.0, 0.9, 10.0, 0.8);
  vi_sim *s = vi_test_sim(m, VI_METHOD_ADAMS, 1e-8, 1e-10, NULL, NULL, NULL);
  assert_int_equal(vi_sim_add_spring(s, 7, 1, 0, 1.0, 0.0), VI_ERR_ARG);
  assert_int_equal(vi_sim_add_spring(s, VI_SPRING_CUBIC, 2, 0, 1.0, 0.0), VI_ERR_DIM);
  assert_int_equal(vi_sim_add_spring(s, VI_SPRING_CUBIC, 1, 1, 1.0, 0.0), VI_ERR_DIM);
  assert_int_equal(vi_sim_add_spring(s, VI_SPRING_CUBIC, 1, 0, NAN, 0.0), VI_ERR_NONFINITE);
  assert_int_equal(vi_sim_set_force(s, NULL, cubic_jac, NULL, NULL), VI_ERR_ARG);
  assert_int_equal(vi_sim_set_force(s, failing_force, NULL, NULL, NULL), VI_OK);
  assert_int_equal(vi_sim_run(s, 5.0), VI_ERR_CALLBACK);
  assert_non_null(strstr(vi_sim_errmsg(s), "force callback"));
  vi_sim_destroy(&s);
  s = vi_test_sim(m, VI_METHOD_EXACT, 1e-8, 1e-10, NULL, NULL, NULL);
  assert_int_equal(vi_sim_add_spring(s, VI_SPRING_CUBIC, 1, 0, 1.0, 0.0),
                   VI_ERR_UNSUPPORTED);
  assert_int_equal(vi_sim_set_force(s, cubic_force, NULL, NULL, NULL),
                   VI_ERR_UNSUPPORTED);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
}

static int nan_force(double t, int n, const double *x, const double *v,
                     double *g, void *user)
{
  (void)n;
  (void)x;
  (void)v;
  g[0] = t > 1.0 ? *(const double *)user : 0.0; /* status 0 all the same */
  return 0;
}

/* Runs whose time stops advancing fail with a message instead of looping:
 * a softening cubic spring (x'' + 0.05 x' + x - 0.5 x^3 = 0.3 cos 1.2 t,
 * v0 = 1.5) whose motion escapes the potential well and blows up in finite
 * time, and a host force that returns NaN or inf with status 0. */
static void test_no_progress(void **state)
{
  (void)state;
  vi_model *m = vi_test_sdof(1.0, 0.05, 1.0, 0.3, 0.0, 1.2, 0.8, 0.8);
  const int methods[3] = {VI_METHOD_ADAMS, VI_METHOD_BDF, VI_METHOD_ERK};
  double v0 = 1.5, T = 20 * 2 * M_PI / 1.2;
  for (int k = 0; k < 3; k++) {
    vi_sim *s = vi_test_sim(m, methods[k], 1e-8, 1e-10, NULL, &v0, NULL);
    assert_int_equal(vi_sim_add_spring(s, VI_SPRING_CUBIC, 1, 0, -0.5, 0.0), VI_OK);
    int st = vi_sim_run(s, T);
    double t;
    vi_sim_state(s, &t, NULL, NULL);
    printf("softening cubic, %s: status %d at t = %.9g: %s\n",
           vi_method_name(methods[k]), st, t, vi_sim_errmsg(s));
    assert_true(st == VI_ERR_INTEGRATOR || st == VI_ERR_CALLBACK);
    assert_true(strstr(vi_sim_errmsg(s), "no progress") ||
                strstr(vi_sim_errmsg(s), "not finite"));
    assert_true(t < T);
    vi_sim_destroy(&s);
  }
  const double bad[2] = {NAN, INFINITY};
  for (int k = 0; k < 3; k++)
    for (int b = 0; b < 2; b++) {
      vi_sim *s = vi_test_sim(m, methods[k], 1e-8, 1e-10, NULL, NULL, NULL);
      assert_int_equal(vi_sim_set_force(s, nan_force, NULL, (void *)&bad[b], NULL), VI_OK);
      assert_int_equal(vi_sim_run(s, 5.0), VI_ERR_CALLBACK);
      assert_non_null(strstr(vi_sim_errmsg(s), "not finite"));
      double t;
      vi_sim_state(s, &t, NULL, NULL);
      assert_true(t > 0.5 && t <= 1.0 + 1e-9); /* stopped where it started */
      vi_sim_destroy(&s);
    }
  vi_model_destroy(&m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_duffing_period_and_energy),
      cmocka_unit_test(test_bilinear_period),
      cmocka_unit_test(test_ledger_force_column),
      cmocka_unit_test(test_linear_force_is_stiffness),
      cmocka_unit_test(test_force_refusals),
      cmocka_unit_test(test_no_progress),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
