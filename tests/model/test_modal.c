/* test_modal.c - modal analysis against closed forms (MODEL.md sections 1, 3). */
#include <math.h>
#include <stdlib.h>

#include "vi_testutil.h"

/* 2-mass chain, m = k = 1: lambda = (3 -+ sqrt 5) / 2. */
static void test_two_mass_chain(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  const double *om = vi_model_omega(m);
  assert_close(om[0] * om[0], (3.0 - sqrt(5.0)) / 2.0, 1e-14);
  assert_close(om[1] * om[1], (3.0 + sqrt(5.0)) / 2.0, 1e-14);
  /* paper: omega_1 = 0.618, omega_2 = 1.618 (the golden ratio) */
  assert_close(om[0], (sqrt(5.0) - 1.0) / 2.0, 1e-14);
  assert_close(om[1], (sqrt(5.0) + 1.0) / 2.0, 1e-14);
  /* C = 0.1 K: proportional, zeta_j = 0.1 omega_j / 2 */
  assert_int_equal(vi_model_is_proportional(m), 1);
  assert_close(vi_model_zeta(m)[0], 0.05 * om[0], 1e-14);
  assert_close(vi_model_zeta(m)[1], 0.05 * om[1], 1e-14);
  /* psi.psi = w^T M^-1 w = 1 for unit masses and w = e_2 */
  const double *psi = vi_model_modal_stop(m);
  assert_close(psi[0] * psi[0] + psi[1] * psi[1], 1.0, 1e-14);
  assert_close(vi_model_stop_compliance(m), 1.0, 1e-15);
  vi_model_destroy(&m);
}

/* N = 20 chain: omega_j = 2 sin((2j-1) pi / (2(2N+1))). */
static void test_twenty_mass_chain(void **state)
{
  (void)state;
  const int N = 20;
  vi_model *m = vi_test_chain(N, 1.0, 1.0, 0.0, 0.1, 0.7, 0.0, NULL);
  const double *om = vi_model_omega(m);
  for (int j = 1; j <= N; j++)
    assert_close(om[j - 1], 2.0 * sin((2 * j - 1) * M_PI / (2.0 * (2 * N + 1))),
                 1e-12);
  vi_model_destroy(&m);
}

/* Random SPD M and PSD K: Psi^T M Psi = I, Psi^T K Psi = diag(omega^2),
 * psi.psi = w^T M^-1 w, x -> q -> x round trip; Rayleigh damping detected
 * as proportional, a random C not. */
static void test_random_spd(void **state)
{
  (void)state;
  enum { n = 7 };
  double A[n * n], B[n * n], M[n * n], K[n * n], C[n * n], w[n];
  srand(12345);
  for (int i = 0; i < n * n; i++) {
    A[i] = rand() / (double)RAND_MAX - 0.5;
    B[i] = rand() / (double)RAND_MAX - 0.5;
  }
  for (int i = 0; i < n; i++) {
    w[i] = rand() / (double)RAND_MAX - 0.3;
    for (int j = 0; j < n; j++) {
      double sm = 0, sk = 0;
      for (int k = 0; k < n; k++) {
        sm += A[i + k * n] * A[j + k * n];
        sk += B[i + k * n] * B[j + k * n];
      }
      M[i + j * n] = sm + (i == j ? 0.5 : 0.0);
      K[i + j * n] = 3.0 * sk;
    }
  }
  for (int i = 0; i < n * n; i++) C[i] = 0.02 * M[i] + 0.01 * K[i];
  vi_model *m = NULL;
  assert_int_equal(vi_model_create(n, &m), VI_OK);
  assert_int_equal(vi_model_set_mass(m, M, n), VI_OK);
  assert_int_equal(vi_model_set_stiffness(m, K, n), VI_OK);
  assert_int_equal(vi_model_set_damping(m, C, n), VI_OK);
  assert_int_equal(vi_model_set_stop(m, w, 0.1, 0.5), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  int ld;
  const double *P = vi_model_modal_shapes(m, &ld);
  const double *om = vi_model_omega(m);
  assert_int_equal(ld, n);
  for (int a = 0; a < n; a++) {
    if (a > 0) assert_true(om[a] >= om[a - 1]);
    for (int b = 0; b < n; b++) {
      double pm = 0, pk = 0;
      for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
          pm += P[i + a * n] * M[i + j * n] * P[j + b * n];
          pk += P[i + a * n] * K[i + j * n] * P[j + b * n];
        }
      assert_close(pm, a == b ? 1.0 : 0.0, 1e-12);
      assert_close(pk, a == b ? om[a] * om[a] : 0.0, 1e-11);
    }
  }
  assert_int_equal(vi_model_is_proportional(m), 1);
  /* psi.psi against w^T M^-1 w computed independently: solve M y = w by
   * the modal expansion M^-1 = Psi Psi^T is what we test, so use CG here */
  double y[n] = {0}, r[n], p[n], Ap[n], rr = 0;
  for (int i = 0; i < n; i++) { r[i] = w[i]; p[i] = w[i]; rr += w[i] * w[i]; }
  for (int it = 0; it < 50 && rr > 1e-30; it++) {
    double pAp = 0, rr2 = 0;
    for (int i = 0; i < n; i++) {
      Ap[i] = 0;
      for (int j = 0; j < n; j++) Ap[i] += M[i + j * n] * p[j];
      pAp += p[i] * Ap[i];
    }
    double al = rr / pAp;
    for (int i = 0; i < n; i++) { y[i] += al * p[i]; r[i] -= al * Ap[i]; rr2 += r[i] * r[i]; }
    for (int i = 0; i < n; i++) p[i] = r[i] + rr2 / rr * p[i];
    rr = rr2;
  }
  double wMw = 0, pp = 0;
  const double *psi = vi_model_modal_stop(m);
  for (int i = 0; i < n; i++) { wMw += w[i] * y[i]; pp += psi[i] * psi[i]; }
  assert_close(pp, wMw, 1e-12 * wMw);
  assert_close(vi_model_stop_compliance(m), wMw, 1e-12 * wMw);
  double q[n], x2[n];
  assert_int_equal(vi_model_to_modal(m, w, q), VI_OK);
  assert_int_equal(vi_model_from_modal(m, q, x2), VI_OK);
  for (int i = 0; i < n; i++) assert_close(x2[i], w[i], 1e-12);
  vi_model_destroy(&m);

  /* a damper on one mass only is not proportional */
  for (int i = 0; i < n * n; i++) C[i] = 0.0;
  C[0] = 0.3;
  assert_int_equal(vi_model_create(n, &m), VI_OK);
  assert_int_equal(vi_model_set_mass(m, M, n), VI_OK);
  assert_int_equal(vi_model_set_stiffness(m, K, n), VI_OK);
  assert_int_equal(vi_model_set_damping(m, C, n), VI_OK);
  assert_int_equal(vi_model_set_stop(m, w, 0.1, 0.5), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  assert_int_equal(vi_model_is_proportional(m), 0);
  vi_model_destroy(&m);
}

/* Energy: 1/2 v'Mv + 1/2 x'Kx equals the sum of modal energies. */
static void test_modal_energy_sum(void **state)
{
  (void)state;
  vi_model *m = vi_test_chain(5, 2.0, 3.0, 0.1, 0.1, 0.7, 0.0, NULL);
  const double x[5] = {0.1, -0.2, 0.3, 0.05, -0.07};
  const double v[5] = {-0.3, 0.2, 0.1, 0.4, 0.0};
  double q[5], qd[5], e = 0.0;
  vi_model_to_modal(m, x, q);
  vi_model_to_modal(m, v, qd);
  const double *om = vi_model_omega(m);
  for (int j = 0; j < 5; j++)
    e += 0.5 * qd[j] * qd[j] + 0.5 * om[j] * om[j] * q[j] * q[j];
  assert_close(vi_model_energy(m, x, v), e, 1e-14);
  vi_model_destroy(&m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_two_mass_chain),
      cmocka_unit_test(test_twenty_mass_chain),
      cmocka_unit_test(test_random_spd),
      cmocka_unit_test(test_modal_energy_sum),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
