/* test_ledger_flight.c - the ledger's FE and DE over a free flight in
 * closed form (vi_ledger_flight.h) against an independent reference: the
 * mode's motion written here in long double (the free part from its
 * initial value, the harmonic part as given) and the integrands q' F and
 * D q'^2 integrated by composite 8-point Gauss-Legendre in long double on
 * panels of 1/20 radian of the fastest rate (rule error below 1e-30).
 * Also against the ledger's former double-precision rule (the same 8
 * nodes, panels of a quarter radian), the quadrature the closed form
 * replaces.  Tolerance: each integral is a sum of a few dozen products,
 * none larger than the integrand's L1 norm S = int |integrand| (or, for
 * the free part's terms, its amplitude over the decay rate), so its
 * rounding is a small multiple of eps S; 64 eps S is asserted. */
#include <float.h>
#include <math.h>

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "vibroimpact.h"
#include "vi_flow_internal.h"
#include "vi_ledger_flight.h"
#include "vi_ledger_internal.h"

/* the 8-point rule (Abramowitz & Stegun 25.4.30) */
static const long double gx[4] = {0.183434642495649804939L,
                                  0.525532409916328985818L,
                                  0.796666477413626739592L,
                                  0.960289856497536231684L};
static const long double gw[4] = {0.362683783378361982965L,
                                  0.313706645877887287338L,
                                  0.222381034453374470544L,
                                  0.101228536290376259153L};

typedef struct mode_case {
  double lam, d, W, t0, pA, pB, Fa, Fb, F0, w, wd;
} mode_case;

/* q'(t0 + s) and F(t0 + s) in long double: the free part u = w - F0 /
 * lambda = e^{-h s} (u0 cos mu s + (u0' + h u0) / mu sin mu s) and the
 * harmonic part's rate W (pB cos - pA sin)(W t). */
static void motion(const mode_case *c, long double s, long double *qd,
                   long double *F)
{
  long double h = 0.5L * c->d, mu = sqrtl(c->lam - h * h);
  long double u0 = c->w - c->F0 / (long double)c->lam, ud0 = c->wd;
  long double Bc = (ud0 + h * u0) / mu, e = expl(-h * s);
  long double cs = cosl(mu * s), sn = sinl(mu * s);
  long double ud = e * ((-h * u0 + mu * Bc) * cs + (-h * Bc - mu * u0) * sn);
  /* the phase at t0 as the library takes it, cos and sin of W t0 rounded
   * to double (ex_start's, and the former quadrature's at its nodes) */
  long double ph = (long double)(c->W * c->t0) + (long double)c->W * s;
  long double Hd = c->W * (c->pB * cosl(ph) - c->pA * sinl(ph));
  *qd = ud + Hd;
  *F = c->Fa * cosl(ph) + c->Fb * sinl(ph) + c->F0;
}

/* FE, DE over [t0, t0 + tau] and their L1 norms, long double, panels of
 * width <= dw / rate. */
static void reference(const mode_case *c, double tau, long double dw,
                      long double *FE, long double *DE, long double *SF,
                      long double *SD)
{
  long double rate = fmaxl(sqrtl(c->lam), fmaxl(c->W, c->d));
  long double np = ceill(tau * rate / dw);
  if (np < 1) np = 1;
  long double hw = 0.5L * tau / np;
  *FE = *DE = *SF = *SD = 0.0L;
  for (long k = 0; k < (long)np; k++) {
    long double mid = hw * (2 * k + 1);
    for (int i = 0; i < 8; i++) {
      long double s = mid + (i < 4 ? -gx[i] : gx[i - 4]) * hw;
      long double wgt = gw[i % 4] * hw, qd, F;
      motion(c, s, &qd, &F);
      *FE += wgt * qd * F;
      *DE += wgt * c->d * qd * qd;
      *SF += wgt * fabsl(qd * F);
      *SD += wgt * c->d * qd * qd;
    }
  }
}

/* The closed form for one mode, QS = q0 (its values at t0). */
static void closed(const mode_case *c, double tau, double q0, double *FE,
                   double *DE)
{
  vi_lflight_mode md;
  double QS[2] = {q0, q0}, Q[2], I[2];
  vi_lflight f = {1, c->W, c->t0, &md, QS, NAN, I};
  vi_lflight_mode_set(&md, c->lam, c->d, c->W, cos(c->W * c->t0),
                      sin(c->W * c->t0), c->pA, c->pB, c->Fa, c->Fb, c->F0,
                      c->w, c->wd);
  vi_lflight_eval(&f, tau, Q);
  *FE = Q[0];
  *DE = Q[1];
}

/* The former rule in double: the library's nodes (vi_gl8_node) on panels
 * of a quarter radian of the fastest rate, the integrand from the long
 * double motion rounded to double. */
static void former(const mode_case *c, double tau, double *FE, double *DE)
{
  double rate = fmax(sqrt(c->lam), fmax(c->W, c->d));
  double np = fmax(1.0, ceil(tau * rate / 0.7853981633974483));
  double h = 0.5 * tau / np, fe = 0.0, de = 0.0;
  for (long k = 0; k < (long)np; k++)
    for (int i = 0; i < 8; i++) {
      double w, s = vi_gl8_node(i, h * (double)(2 * k + 1), h, &w);
      long double qd, F;
      motion(c, s, &qd, &F);
      fe += w * ((double)qd * (double)F);
      de += w * (c->d * (double)qd * (double)qd);
    }
  *FE = fe;
  *DE = de;
}

static const mode_case cases[] = {
    /* Fig. 2's modes under its forcing (Omega = 0.9) */
    {0.3819660112501051, 0.0381966011250105, 0.9, 573.1, -0.31, 0.12, 0.26,
     0.0, 0.0, 0.05, -0.4},
    {2.618033988749895, 0.2618033988749895, 0.9, 12.0, 0.07, -0.02, -0.43,
     0.0, 0.0, -0.03, 0.2},
    /* lightly damped, off resonance, a static load */
    {4.0, 0.02, 1.7, 3.0, 0.4, -0.2, 1.0, 0.5, 0.8, 0.3, -1.0},
    /* damping ratio 1/4, and 1/2 (the largest taken) */
    {9.0, 1.5, 1.7, 0.0, 0.1, 0.3, -0.6, 0.2, 0.0, -0.2, 0.7},
    {1.0, 1.0, 1.7, 40.0, -0.5, 0.1, 0.3, 0.9, -0.4, 1.0, 0.0},
    /* undamped */
    {2.25, 0.0, 0.6, 1.0, 0.2, 0.5, 0.3, -0.3, 0.1, 0.0, 1.0},
    /* near resonance, little damping: mu - W = 4e-4 */
    {1.0008001600000001, 1e-3, 1.0, 7.0, 30.0, -12.0, 0.01, 0.02, 0.0, 0.5,
     0.1},
    /* unforced harmonic (W = 0) */
    {3.0, 0.3, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.25, 0.1, -0.1},
};

static const double taus[] = {1e-9, 1e-4, 0.03, 0.7, 7.0, 60.0};

static void test_against_reference(void **state)
{
  (void)state;
  double worst_ref = 0.0, worst_former = 0.0;
  for (size_t k = 0; k < sizeof cases / sizeof *cases; k++)
    for (size_t i = 0; i < sizeof taus / sizeof *taus; i++) {
      const mode_case *c = cases + k;
      double tau = taus[i], FE, DE, fFE, fDE;
      long double rFE, rDE, SF, SD;
      reference(c, tau, 0.05L, &rFE, &rDE, &SF, &SD);
      closed(c, tau, 0.0, &FE, &DE);
      former(c, tau, &fFE, &fDE);
      /* the free part's terms: amplitude^2 over the decay rate at most */
      long double eF = fabsl(FE - rFE) / (SF + LDBL_MIN);
      long double eD = fabsl(DE - rDE) / (SD + LDBL_MIN);
      long double gF = fabsl(fFE - rFE) / (SF + LDBL_MIN);
      long double gD = fabsl(fDE - rDE) / (SD + LDBL_MIN);
      worst_ref = fmax(worst_ref, (double)fmaxl(eF, eD));
      worst_former = fmax(worst_former, (double)fmaxl(gF, gD));
      if (fmaxl(eF, eD) > 64 * DBL_EPSILON)
        print_error("case %zu tau %g: FE %.17g ref %.17Lg (S %.3Lg), DE "
                    "%.17g ref %.17Lg (S %.3Lg)\n", k, tau, FE, rFE, SF, DE,
                    rDE, SD);
      assert_true(eF <= 64 * DBL_EPSILON);
      assert_true(eD <= 64 * DBL_EPSILON);
      /* the former rule agrees to the same order, where its quarter-radian
       * panels resolve the integrand */
      assert_true(gF <= 64 * DBL_EPSILON);
      assert_true(gD <= 64 * DBL_EPSILON);
    }
  print_message("closed form vs long double reference: %.3g eps S; former "
                "rule: %.3g eps S\n", worst_ref / DBL_EPSILON,
                worst_former / DBL_EPSILON);
}

/* The values at t0 are carried: Q = QS + integrals, the same for a
 * repeated tau; the integrals alone where the interval began with the
 * flight (ta = t0, QA = QS), not otherwise. */
static void test_offset_and_since(void **state)
{
  (void)state;
  const mode_case *c = cases + 2;
  double FE0, DE0, FE1, DE1;
  closed(c, 7.0, 0.0, &FE0, &DE0);
  closed(c, 7.0, 100.0, &FE1, &DE1);
  assert_true(fabs(FE1 - (100.0 + FE0)) <= 2 * DBL_EPSILON * 100.0);
  assert_true(fabs(DE1 - (100.0 + DE0)) <= 2 * DBL_EPSILON * 100.0);
  vi_lflight_mode md;
  double QS[2] = {100.0, 100.0}, Q[2], I[2], J[2] = {-1.0, -1.0};
  vi_lflight f = {1, c->W, c->t0, &md, QS, NAN, I};
  vi_lflight_mode_set(&md, c->lam, c->d, c->W, cos(c->W * c->t0),
                      sin(c->W * c->t0), c->pA, c->pB, c->Fa, c->Fb, c->F0,
                      c->w, c->wd);
  vi_lflight_eval(&f, 7.0, Q);
  assert_true(Q[0] == FE1 && Q[1] == DE1);
  Q[0] = Q[1] = -1.0;
  vi_lflight_eval(&f, 7.0, Q);
  assert_true(Q[0] == FE1 && Q[1] == DE1);
  const double QA[2] = {100.0, 100.0}, QB[2] = {100.0, 99.0};
  assert_int_equal(vi_lflight_since(&f, 7.0, c->t0, QA, J), 1);
  assert_true(J[0] == FE0 && J[1] == DE0);
  J[0] = J[1] = -1.0;
  assert_int_equal(vi_lflight_since(&f, 7.0, c->t0 + 1.0, QA, J), 0);
  assert_int_equal(vi_lflight_since(&f, 7.0, c->t0, QB, J), 0);
  assert_true(J[0] == -1.0 && J[1] == -1.0);
  vi_lflight_eval(&f, 0.0, Q); /* tau = 0: nothing integrated */
  assert_true(Q[0] == 100.0 && Q[1] == 100.0);
}

/* |x - ref| within k ulp of ref (long double reference) */
static int near_ulp(double x, long double ref, double k)
{
  return fabsl(x - ref) <= k * DBL_EPSILON * fabsl(ref);
}

/* The flow's own sin, cos (mu tau / 2) and exponentials, shared at a
 * contact (vi_flow_basis_half, vi_lflight_share): they are those
 * functions' values at the arguments the library rounds (2 eps against
 * long double), and the integrals taking them are the integrals computing
 * them again, bit for bit; a share for another tau is not taken. */
static void test_shared_values(void **state)
{
  (void)state;
  int shared = 0;
  for (size_t k = 0; k < sizeof cases / sizeof *cases; k++)
    for (size_t i = 0; i < sizeof taus / sizeof *taus; i++) {
      const mode_case *c = cases + k;
      double tau = taus[i], B, Bp, ph, v[4], FE, DE, Q[2];
      if (!vi_flow_basis_half(c->lam, c->d, tau, &B, &Bp, &ph, v)) continue;
      shared++;
      double h = 0.5 * c->d, mu = sqrt(c->lam - h * h), a = 0.5 * mu * tau;
      assert_true(near_ulp(v[0], sinl(a), 2) && near_ulp(v[1], cosl(a), 2));
      assert_true(near_ulp(v[2], expm1l(-h * tau), 2));
      assert_true(near_ulp(v[3], expl(-h * tau), 2));
      closed(c, tau, 0.0, &FE, &DE);
      vi_lflight_mode md;
      double QS[2] = {0.0, 0.0}, I[2];
      vi_lflight f = {1, c->W, c->t0, &md, QS, NAN, I};
      vi_lflight_mode_set(&md, c->lam, c->d, c->W, cos(c->W * c->t0),
                          sin(c->W * c->t0), c->pA, c->pB, c->Fa, c->Fb,
                          c->F0, c->w, c->wd);
      vi_lflight_share(&f, 0, 2.0 * tau, v); /* another time's: not taken */
      vi_lflight_eval(&f, tau, Q);
      assert_true(Q[0] == FE && Q[1] == DE);
      f.tau_done = NAN;
      vi_lflight_share(&f, 0, tau, v);
      vi_lflight_eval(&f, tau, Q);
      assert_true(Q[0] == FE && Q[1] == DE);
    }
  assert_true(shared >= 20); /* the flow's closed form past its series */
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_against_reference),
      cmocka_unit_test(test_offset_and_since),
      cmocka_unit_test(test_shared_values),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
