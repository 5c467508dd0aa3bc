/* test_quadmap.c - the ledger quadrature's node maps (vi_quadmap.h)
 * against the closed-form solution of u'' + d u' + lambda u = F written
 * independently here in long double: B, B' the response to (u, u') =
 * (0, 1), phi the response to F = 1 from rest, over the offsets +-x_k h of
 * the 8 Gauss-Legendre nodes from a panel's midpoint (the mirrors -x_k h
 * come from the library's inverse map). */
#include <complex.h>
#include <math.h>

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "vibroimpact.h"
#include "vi_quadmap.h"

/* the 8-point rule's abscissae (Abramowitz & Stegun 25.4.30) */
static const long double gx[4] = {0.183434642495649804939L,
                                  0.525532409916328985818L,
                                  0.796666477413626739592L,
                                  0.960289856497536231684L};

/* e^x - 1 without cancellation: its power series for small |x| */
static long double complex em1(long double complex x)
{
  if (cabsl(x) > 0.5L) return cexpl(x) - 1.0L;
  long double complex t = x, sum = x;
  for (int k = 2; k < 40; k++) {
    t *= x / k;
    sum += t;
  }
  return sum;
}

/* B, B', phi after tau: distinct roots r1, r2 of r^2 + d r + lambda, or
 * the rigid forms (lambda = 0) */
static void reference(long double lam, long double d, long double tau,
                      long double *B, long double *Bp, long double *phi)
{
  if (lam == 0.0L) {
    if (d == 0.0L) {
      *B = tau;
      *Bp = 1.0L;
      *phi = 0.5L * tau * tau;
    } else {
      /* B = (1 - e^{-d tau}) / d, phi = int_0^tau B, by their series */
      long double t = tau, b = 0.0L, p = 0.0L;
      for (int k = 1; k < 60; k++) {
        b += t;                  /* (-d)^{k-1} tau^k / k! */
        t *= -d * tau / (k + 1);
        p += t / -d;             /* (-d)^{k-1} tau^{k+1} / (k+1)! */
      }
      *B = b;
      *Bp = expl(-d * tau);
      *phi = p;
    }
    return;
  }
  long double complex s = csqrtl(0.25L * d * d - lam + 0.0L * I);
  long double complex r1 = -0.5L * d + s, r2 = -0.5L * d - s;
  long double complex e1 = cexpl(r1 * tau), e2 = cexpl(r2 * tau);
  *B = creall((e1 - e2) / (r1 - r2));
  *Bp = creall((r1 * e1 - r2 * e2) / (r1 - r2));
  /* phi = int_0^tau B = ((e1 - 1) / r1 - (e2 - 1) / r2) / (r1 - r2) */
  *phi = creall((em1(r1 * tau) / r1 - em1(r2 * tau) / r2) / (r1 - r2));
}

static void test_maps(void **state)
{
  (void)state;
  /* rigid, damped rigid, light, under-, over-damped modes */
  const double lam[5] = {0.0, 0.0, 4.0, 9.0, 1.0};
  const double dmp[5] = {0.0, 0.5, 0.02, 1.5, 3.0};
  const double Om = 1.7;
  double rate = Om;
  for (int j = 0; j < 5; j++) rate = fmax(rate, fmax(sqrt(lam[j]), dmp[j]));
  vi_quadmap Q;
  assert_int_equal(vi_quadmap_init(&Q, 5), VI_OK);
  /* the widest panel (a quarter radian of the fastest rate) and shorter */
  const double hs[3] = {0.5 * (M_PI / 4.0) / rate, 0.013, 0.004};
  for (int k = 0; k < 3; k++) {
    double h = hs[k];
    const vi_quadmap_set *S = vi_quadmap_get(&Q, h, Om, lam, dmp, 1);
    double wsum = 0.0;
    for (int i = 0; i < VI_QUADMAP_NODES; i++) {
      long double tau = (i < 4 ? -gx[i] : gx[i - 4]) * (long double)h;
      wsum += S->w[i];
      /* the rotation by Omega tau */
      assert_true(fabsl(S->c[i] - cosl(Om * tau)) <= 4e-16L);
      assert_true(fabsl(S->s[i] - sinl(Om * tau)) <= 4e-16L);
      const double *T = S->T + 3 * (size_t)i * 5;
      for (int j = 0; j < 5; j++) {
        long double B, Bp, ph;
        reference(lam[j], dmp[j], tau, &B, &Bp, &ph);
        /* relative to the scales tau, 1, tau^2 / 2 of the three maps: a
         * few ulp (the mirrors add the inverse map's few operations) */
        long double at = fabsl(tau);
        assert_true(fabsl(T[j] - B) <= 2e-15L * at);
        assert_true(fabsl(T[5 + j] - Bp) <= 2e-15L);
        assert_true(fabsl(T[10 + j] - ph) <= 4e-15L * 0.5L * at * at);
      }
    }
    /* the rule's weights (16-digit constants) sum to the width */
    assert_true(fabs(wsum - 2.0 * h) <= 1e-15 * h);
    /* the same width again: the kept maps */
    assert_ptr_equal(vi_quadmap_get(&Q, h, Om, lam, dmp, 1), S);
  }
  /* more widths than ways: the oldest is recomputed, the same again */
  for (int k = 0; k < VI_QUADMAP_WAYS; k++)
    (void)vi_quadmap_get(&Q, 0.001 * (k + 1), Om, lam, dmp, 1);
  const vi_quadmap_set *S = vi_quadmap_get(&Q, hs[1], Om, lam, dmp, 1);
  long double B, Bp, ph, tau = gx[3] * (long double)hs[1];
  reference(lam[3], dmp[3], tau, &B, &Bp, &ph);
  assert_true(fabsl(S->T[3 * 7 * 5 + 3] - B) <= 2e-15L * tau);
  vi_quadmap_free(&Q);
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_maps)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
