/* test_exact_stops.c - the exact (closed-form) method with several stops
 * against physics: a two-sided clearance with r = 1 and C = 0 conserves
 * energy to round-off over thousands of impacts; mirror-symmetric scenes
 * give mirrored motions and a symmetric forced orbit; a 2-DOF chain with a
 * stop on each coordinate agrees impact for impact with an independent
 * 30-digit reference (tests/stress/ref/exact_two_stops.py) and with Adams;
 * two stops hit at the same instant take Newton's multiple-contact
 * impulses (closed form); a graze of the second stop between grid points
 * is found. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vi_testutil.h"

/* ---- two-sided clearance, r = 1, C = 0: energy ------------------------------ */
/* A 2-DOF chain (M = diag(1, 2), K = [[3, -1], [-1, 1]]) whose mass 1 rattles
 * in a clearance |x_1| <= 0.4 with r = 1 and no damping or forcing: the
 * energy E = (v.M v + x.K x) / 2 is a constant of the motion, and each
 * impact keeps the kinetic energy to round-off (WB 10).  The closed form
 * makes each flight exact to round-off, but a contact time t_j exists in
 * double precision only to eps t_j: the state is taken a phase of up to
 * omega_max eps t_j off the contact, which moves at most that fraction of
 * E between the gap's direction and the rest.  So after impact i
 *   |E - E0| <= eps E0 (16 + sum_{j <= i} (1 + omega_max t_j)),
 * the 16 for evaluating E itself; the sum grows like t^2 (no integrator's
 * error can be below it). */
static void test_clearance_energy(void **state)
{
  (void)state;
  const double M[4] = {1.0, 0.0, 0.0, 2.0}, K[4] = {3.0, -1.0, -1.0, 1.0};
  const double W[4] = {1.0, 0.0, -1.0, 0.0}, xs[2] = {0.4, 0.4}, r[2] = {1.0, 1.0};
  vi_model *m = vi_test_model_stops(2, M, NULL, K, 0.0, NULL, NULL, 2, W, xs, r);
  const double x0[2] = {0.0, 0.1}, v0[2] = {1.5, -0.7};
  vi_test_rec ev = {0};
  vi_sim *s = vi_test_sim_stops(m, VI_METHOD_AUTO, 1e-10, 1e-12, 0.0, x0, v0, &ev);
  assert_int_equal(vi_sim_run(s, 2000.0), VI_OK);
  assert_int_equal(vi_sim_method_used(s), VI_METHOD_EXACT); /* auto's choice */
  double E0 = vi_model_energy(m, x0, v0), worst = 0.0;
  double bound = 16.0 * DBL_EPSILON * E0;
  const double om = vi_model_omega(m)[1]; /* the faster mode */
  int hits[2] = {0, 0};
  assert_true(ev.count > 1000);
  for (int i = 0; i < ev.count; i++) {
    assert_int_equal(ev.kind[i], VI_EVENT_IMPACT);
    hits[ev.stop[i]]++;
    double E = vi_model_energy(m, ev.x + 2 * (size_t)i, ev.vp + 2 * (size_t)i);
    bound += DBL_EPSILON * E0 * (1.0 + om * ev.t[i]);
    worst = fmax(worst, fabs(E - E0) / bound);
    assert_true(ev.ie[i] <= 4.0 * DBL_EPSILON * E0); /* r = 1: no loss */
  }
  double x[2], v[2], t;
  assert_int_equal(vi_sim_state(s, &t, x, v), VI_OK);
  double Eend = vi_model_energy(m, x, v);
  print_message("clearance (exact): %d + %d impacts, |E - E0| <= %.2g of the "
                "time-resolution bound, at the end %.2g E0 (bound %.2g)\n",
                hits[0], hits[1], worst, fabs(Eend - E0) / E0, bound / E0);
  assert_true(hits[0] > 400 && hits[1] > 400);
  assert_true(worst <= 1.0);
  assert_true(fabs(Eend - E0) <= bound);
  vi_test_rec_free(&ev);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
}

/* ---- mirror symmetry ---------------------------------------------------------- */
/* The clearance scene is symmetric under x -> -x with the stops swapped: the
 * motion from (-x0, -v0) is the mirror of the one from (x0, v0).  Negation
 * commutes with every rounding, so the closed form reproduces it to the
 * last bit; allow 4 eps of the scale for library functions. */
static void test_mirror(void **state)
{
  (void)state;
  const double M[4] = {1.0, 0.0, 0.0, 2.0}, K[4] = {3.0, -1.0, -1.0, 1.0};
  const double C[4] = {0.03, -0.01, -0.01, 0.01};
  const double W[4] = {1.0, 0.0, -1.0, 0.0}, xs[2] = {0.4, 0.4}, r[2] = {0.9, 0.9};
  vi_model *m = vi_test_model_stops(2, M, C, K, 0.0, NULL, NULL, 2, W, xs, r);
  const double xa[2] = {0.0, 0.1}, va[2] = {1.5, -0.7};
  const double xb[2] = {-0.0, -0.1}, vb[2] = {-1.5, 0.7};
  vi_test_rec ea = {0}, eb = {0};
  vi_sim *a = vi_test_sim_stops(m, VI_METHOD_EXACT, 1e-10, 1e-12, 0.0, xa, va, &ea);
  vi_sim *b = vi_test_sim_stops(m, VI_METHOD_EXACT, 1e-10, 1e-12, 0.0, xb, vb, &eb);
  assert_int_equal(vi_sim_run(a, 60.0), VI_OK);
  assert_int_equal(vi_sim_run(b, 60.0), VI_OK);
  assert_int_equal(ea.count, eb.count);
  assert_true(ea.count >= 10);
  double dt = 0.0, dx = 0.0;
  for (int i = 0; i < ea.count; i++) {
    assert_int_equal(ea.kind[i], eb.kind[i]);
    assert_int_equal(ea.stop[i], 1 - eb.stop[i]);
    dt = fmax(dt, fabs(ea.t[i] - eb.t[i]));
    for (int j = 0; j < 2; j++)
      dx = fmax(dx, fabs(ea.vp[2 * (size_t)i + j] + eb.vp[2 * (size_t)i + j]) +
                        fabs(ea.x[2 * (size_t)i + j] + eb.x[2 * (size_t)i + j]));
  }
  print_message("mirror (exact): %d events, times differ by %.2g, states by "
                "%.2g\n", ea.count, dt, dx);
  assert_true(dt <= 4.0 * DBL_EPSILON * 60.0);
  assert_true(dx <= 4.0 * DBL_EPSILON * 2.0);
  vi_test_rec_free(&ea);
  vi_test_rec_free(&eb);
  vi_sim_destroy(&a);
  vi_sim_destroy(&b);
  vi_model_destroy(&m);
}

/* A forced oscillator x'' + 0.3 x' + x = 0.5 cos(0.9 t) in a clearance
 * |x| <= 0.3, r = 0.7: the scene is invariant under (t, x) -> (t + T/2,
 * -x), and its attracting orbit is symmetric: impacts alternate between the
 * stops, half a period apart, with equal speeds.  After 150 periods the
 * transient has decayed by e^{-0.15 t} and far more through the impacts;
 * the orbit's symmetry holds to 1e-9 (the contraction's remainder). */
static void test_symmetric_orbit(void **state)
{
  (void)state;
  const double M = 1.0, C = 0.3, K = 1.0, a = 0.5, Om = 0.9, T = 2.0 * M_PI / Om;
  const double W[2] = {1.0, -1.0}, xs[2] = {0.3, 0.3}, r[2] = {0.7, 0.7};
  vi_model *m = vi_test_model_stops(1, &M, &C, &K, Om, &a, NULL, 2, W, xs, r);
  vi_test_rec ev = {0};
  vi_sim *s = vi_test_sim_stops(m, VI_METHOD_EXACT, 1e-10, 1e-12, 0.0, NULL, NULL, &ev);
  assert_int_equal(vi_sim_run(s, 160.0 * T), VI_OK);
  int i0 = 0;
  while (i0 < ev.count && ev.t[i0] < 150.0 * T) i0++;
  assert_true(ev.count - i0 >= 10);
  double dt = 0.0, dv = 0.0;
  for (int i = i0; i + 1 < ev.count; i++) {
    assert_int_equal(ev.kind[i], VI_EVENT_IMPACT);
    assert_int_equal(ev.stop[i + 1], 1 - ev.stop[i]);
    dt = fmax(dt, fabs(ev.t[i + 1] - ev.t[i] - 0.5 * T));
    dv = fmax(dv, fabs(ev.vn[i + 1] - ev.vn[i]));
  }
  print_message("symmetric orbit (exact): %d impacts, alternating, spacing - "
                "T/2 <= %.2g, speeds differ by %.2g (speed %.6f)\n",
                ev.count - i0, dt, dv, ev.vn[i0]);
  assert_true(dt <= 1e-9 * T);
  assert_true(dv <= 1e-9 * ev.vn[i0]);
  vi_test_rec_free(&ev);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
}

/* ---- stops on different coordinates against a 30-digit reference ------------ */
/* M = I, K = [[2, -1], [-1, 2]], C = 0.05 K, a = (1, 0) cos(1.3 t); stop 0:
 * x_1 <= 0.3 (r = 0.8), stop 1: x_2 >= -0.25 (r = 0.6); from rest at the
 * origin.  {t, stop, w.v-, v+_1, v+_2} from tests/stress/ref/
 * exact_two_stops.py (mpmath, 30 digits, its own closed form and root
 * bracketing). */
static const double ref2[][5] = {
    {0.89340088161087178095, 0, 0.48189761999761518961, -0.38551809599809215169, 0.10206204266866199058},
    {3.007059512288294385, 1, 0.61360353214309618033, -0.38535939093031437832, 0.3681621192858577082},
    {4.6823962749635617759, 0, 1.5281272488781082772, -1.2225017991024866218, 0.0560964414816613621},
    {9.0044780598970364211, 1, 0.19852288665812621454, 0.45291985477272446684, 0.11911373199487572872},
    {9.8598133401262474938, 0, 1.2894616654372853215, -1.0315693323498282572, 0.31783314255225315345},
    {12.293215043078026806, 1, 0.39068509461103161876, -0.254387041577063464, 0.23441105676661897125},
    {14.511902655861040574, 0, 1.2098216973674473257, -0.96785735789395786059, 0.057684431136741419306},
    {17.746353430657821595, 1, 0.20479419387010331914, -0.37091147099597205242, 0.12287651632206199149},
    {19.44090634845814027, 0, 1.2795338562536729335, -1.0236270850029383468, 0.21441191760827329828},
    {22.156789870045730558, 1, 0.27364513834956204146, -0.34405323464358086309, 0.16418708300973722487},
    {24.237640684883966715, 0, 1.2395331762261024611, -0.99162654098088196892, 0.13554826290109525134},
    {27.148788801704774146, 1, 0.22534924787010553207, -0.39086245484851874956, 0.13520954872206331924},
    {29.089263461409546599, 0, 1.2571650576160053442, -1.0057320460928042754, 0.18428845700602695676},
    {31.9069971623114001, 1, 0.25333114138156780423, -0.37498187498134086493, 0.15199868482894068254},
    {33.916743586183729708, 0, 1.2497948399851759596, -0.99983587198814076766, 0.15712036413053320659},
    {36.762821830685100348, 1, 0.2384102183118839326, -0.3784263919309569061, 0.14304613098713035956},
    {38.749548761745651473, 0, 1.2509968782474916532, -1.0007975025979933225, 0.17119828249791342725},
    {41.595419337025898894, 1, 0.24449062848563995347, -0.3833599583863853971, 0.14669437709138397208},
    {43.586138312729662443, 0, 1.2535677428901271251, -1.0028541943121017001, 0.16556931672946361599},
    {46.419103004925651578, 1, 0.2437685579136331472, -0.37436870938510503243, 0.14626113474817988832},
    {48.415071943381969112, 0, 1.2488476403203284068, -0.99907811225626272542, 0.16613080478230504806},
    {51.265011641033252463, 1, 0.24167855260833221284, -0.38463612400661276231, 0.14500713156499932771},
    {53.252352350040015987, 0, 1.2544174174989716633, -1.0035339339991773306, 0.168298530091241938},
    {56.086185200249900639, 1, 0.24493732164073415021, -0.37484386073968958883, 0.14696239298444049013},
};

/* Error bounds: the closed form locates each contact to round-off (~1e-15
 * in t), which the impact sequence carries on with an amplification of a
 * few per impact over these 24 (the motion settles on a stable orbit): 1e-11
 * on times and velocities.  Adams at rtol 1e-12 (atol 1e-14): a global
 * error some hundred times the tolerance, divided by the approach speed
 * (>= 0.2) for a contact time: 1e-8. */
static void test_two_coordinates(void **state)
{
  (void)state;
  const double M[4] = {1.0, 0.0, 0.0, 1.0}, K[4] = {2.0, -1.0, -1.0, 2.0};
  const double C[4] = {0.1, -0.05, -0.05, 0.1}, a[2] = {1.0, 0.0};
  const double W[4] = {1.0, 0.0, 0.0, -1.0}, xs[2] = {0.3, 0.25}, r[2] = {0.8, 0.6};
  vi_model *m = vi_test_model_stops(2, M, C, K, 1.3, a, NULL, 2, W, xs, r);
  const int nref = (int)(sizeof ref2 / sizeof ref2[0]);
  const int meth[2] = {VI_METHOD_EXACT, VI_METHOD_ADAMS};
  const double tol[2] = {1e-11, 1e-8};
  for (int q = 0; q < 2; q++) {
    vi_test_rec ev = {0};
    vi_sim *s = vi_test_sim_stops(m, meth[q], 1e-12, 1e-14, 0.0, NULL, NULL, &ev);
    assert_int_equal(vi_sim_run(s, 57.0), VI_OK);
    assert_int_equal(vi_sim_method_used(s), meth[q]);
    assert_int_equal(ev.count, nref);
    double et = 0.0, ev_ = 0.0;
    for (int i = 0; i < nref; i++) {
      assert_int_equal(ev.kind[i], VI_EVENT_IMPACT);
      assert_int_equal(ev.stop[i], (int)ref2[i][1]);
      et = fmax(et, fabs(ev.t[i] - ref2[i][0]));
      ev_ = fmax(ev_, fabs(ev.vn[i] - ref2[i][2]));
      ev_ = fmax(ev_, fabs(ev.vp[2 * (size_t)i] - ref2[i][3]));
      ev_ = fmax(ev_, fabs(ev.vp[2 * (size_t)i + 1] - ref2[i][4]));
    }
    print_message("two coordinates (%s): %d impacts against the 30-digit "
                  "reference: times within %.2g, velocities within %.2g\n",
                  vi_method_name(meth[q]), nref, et, ev_);
    assert_true(et <= tol[q]);
    assert_true(ev_ <= tol[q]);
    vi_test_rec_free(&ev);
    vi_sim_destroy(&s);
  }
  vi_model_destroy(&m);
}

/* The same scene with damping that is not proportional (C = [[0.15,
 * -0.05], [-0.05, 0.05]]): the exact method runs on the first-order
 * eigen-solution, scanning both gaps; it must agree impact for impact with
 * Adams at rtol 1e-12, within Adams' error (1e-8 as above). */
static void test_two_coordinates_nonproportional(void **state)
{
  (void)state;
  const double M[4] = {1.0, 0.0, 0.0, 1.0}, K[4] = {2.0, -1.0, -1.0, 2.0};
  const double C[4] = {0.15, -0.05, -0.05, 0.05}, a[2] = {1.0, 0.0};
  const double W[4] = {1.0, 0.0, 0.0, -1.0}, xs[2] = {0.3, 0.25}, r[2] = {0.8, 0.6};
  vi_model *m = vi_test_model_stops(2, M, C, K, 1.3, a, NULL, 2, W, xs, r);
  vi_test_rec e[2] = {{0}, {0}};
  const int meth[2] = {VI_METHOD_EXACT, VI_METHOD_ADAMS};
  for (int q = 0; q < 2; q++) {
    vi_sim *s = vi_test_sim_stops(m, meth[q], 1e-12, 1e-14, 0.0, NULL, NULL, &e[q]);
    assert_int_equal(vi_sim_run(s, 60.0), VI_OK);
    assert_int_equal(vi_sim_method_used(s), meth[q]);
    vi_sim_destroy(&s);
  }
  assert_int_equal(e[0].count, e[1].count);
  assert_true(e[0].count >= 20);
  double et = 0.0, ev_ = 0.0;
  int hits[2] = {0, 0};
  for (int i = 0; i < e[0].count; i++) {
    assert_int_equal(e[0].kind[i], e[1].kind[i]);
    assert_int_equal(e[0].stop[i], e[1].stop[i]);
    hits[e[0].stop[i]]++;
    et = fmax(et, fabs(e[0].t[i] - e[1].t[i]));
    ev_ = fmax(ev_, fabs(e[0].vn[i] - e[1].vn[i]));
  }
  print_message("two coordinates, non-proportional damping: %d + %d impacts, "
                "exact and adams agree within %.2g in time, %.2g in speed\n",
                hits[0], hits[1], et, ev_);
  assert_true(hits[0] > 5 && hits[1] > 5);
  assert_true(et <= 1e-8);
  assert_true(ev_ <= 1e-8);
  vi_test_rec_free(&e[0]);
  vi_test_rec_free(&e[1]);
  vi_model_destroy(&m);
}

/* ---- two stops at the same instant ------------------------------------------- */
/* Free masses M = diag(1, 2) (K = C = 0) from the origin at v = (1, 0.25);
 * stop 0: x_1 <= 1, stop 1: x_1 + x_2 <= 1.25, r = 0.5 each: both gaps
 * t - 1 and 1.25 (t - 1) vanish at t = 1.  G = W^T M^-1 W = [[1, 1], [1,
 * 1.5]], approach speeds u = W^T v = (1, 1.25); with both contacts active
 * Newton's law gives G P = (1 + r) u, P = 1.5 G^-1 u = (0.75, 0.75) > 0, so
 * v+ = v - M^-1 W P = (-0.5, -0.125), W^T v+ = -r u, and the kinetic energy
 * lost is 0.5625 - 0.140625 = 0.421875. */
static void test_simultaneous(void **state)
{
  (void)state;
  const double M[4] = {1.0, 0.0, 0.0, 2.0}, Z[4] = {0.0, 0.0, 0.0, 0.0};
  const double W[4] = {1.0, 0.0, 1.0, 1.0}, xs[2] = {1.0, 1.25}, r[2] = {0.5, 0.5};
  vi_model *m = vi_test_model_stops(2, M, NULL, Z, 0.0, NULL, NULL, 2, W, xs, r);
  const double v0[2] = {1.0, 0.25};
  vi_test_rec ev = {0};
  vi_sim *s = vi_test_sim_stops(m, VI_METHOD_AUTO, 1e-10, 1e-12, 0.0, NULL, v0, &ev);
  assert_int_equal(vi_sim_run(s, 3.0), VI_OK);
  assert_int_equal(vi_sim_method_used(s), VI_METHOD_EXACT);
  assert_int_equal(ev.count, 2);
  double loss = 0.0;
  for (int i = 0; i < 2; i++) {
    assert_int_equal(ev.kind[i], VI_EVENT_IMPACT);
    assert_int_equal(ev.stop[i], i);
    assert_close(ev.t[i], 1.0, 8.0 * DBL_EPSILON);
    assert_close(ev.vn[i], i ? 1.25 : 1.0, 8.0 * DBL_EPSILON);
    assert_close(ev.vp[2 * (size_t)i], -0.5, 8.0 * DBL_EPSILON);
    assert_close(ev.vp[2 * (size_t)i + 1], -0.125, 8.0 * DBL_EPSILON);
    loss += ev.ie[i];
  }
  assert_close(loss, 0.421875, 8.0 * DBL_EPSILON);
  double x[2], v[2], t;
  assert_int_equal(vi_sim_state(s, &t, x, v), VI_OK);
  /* free flight back from the stops: x = (1, 0.25) + (t - 1) v+ */
  assert_close(x[0], 1.0 - 0.5 * 2.0, 32.0 * DBL_EPSILON);
  assert_close(x[1], 0.25 - 0.125 * 2.0, 32.0 * DBL_EPSILON);
  print_message("simultaneous (exact): both stops at t = %.16f, v+ = (%.15f, "
                "%.15f), loss %.15f (closed form 0.421875)\n", ev.t[0],
                ev.vp[0], ev.vp[1], loss);
  vi_test_rec_free(&ev);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
}

/* ---- a graze of stop 1 between grid points ------------------------------------ */
/* x'' + x = 0 from t0 = 0.3 on x = sin t: its maximum 1 at pi/2 overshoots
 * stop 1, x <= 1 - delta, by delta = 1e-10 for |t - pi/2| < 1.4e-5, far
 * inside one grid step (pi/2, from t0), where both ends lie 0.04 and 0.7
 * below the stop.  Stop 0 (x >= -0.8) would be hit later, at pi + asin 0.8:
 * missing the graze would report that.  The contact is at sin t = 1 -
 * delta, t_c = pi/2 - theta with theta = 2 asin(sqrt(delta / 2)), speed
 * cos t_c = sin theta; the closed form's time is limited by g's round-off
 * (64 eps) over the slope sin theta. */
static void test_graze_second_stop(void **state)
{
  (void)state;
  const double M = 1.0, K = 1.0, delta = 1e-10, t0 = 0.3;
  const double W[2] = {-1.0, 1.0}, xs[2] = {0.8, 1.0 - delta}, r[2] = {0.9, 0.9};
  vi_model *m = vi_test_model_stops(1, &M, NULL, &K, 0.0, NULL, NULL, 2, W, xs, r);
  const double x0 = sin(t0), v0 = cos(t0);
  vi_test_rec ev = {0};
  vi_sim *s = vi_test_sim_stops(m, VI_METHOD_EXACT, 1e-10, 1e-12, t0, &x0, &v0, &ev);
  assert_int_equal(vi_sim_run(s, 2.0), VI_OK);
  double theta = 2.0 * asin(sqrt(0.5 * delta)), tc = 0.5 * M_PI - theta;
  assert_int_equal(ev.count, 1);
  assert_int_equal(ev.kind[0], VI_EVENT_IMPACT);
  assert_int_equal(ev.stop[0], 1);
  print_message("graze of stop 1: t = %.15f (closed form %.15f), v_n = %.6g "
                "(%.6g), %lld graze checks\n", ev.t[0], tc, ev.vn[0],
                sin(theta), (long long)vi_sim_stat(s, VI_STAT_GRAZE_CHECKS));
  assert_close(ev.t[0], tc, 64.0 * DBL_EPSILON / sin(theta));
  assert_close(ev.vn[0], sin(theta), 64.0 * DBL_EPSILON / sin(theta));
  vi_test_rec_free(&ev);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_clearance_energy),
      cmocka_unit_test(test_mirror),
      cmocka_unit_test(test_symmetric_orbit),
      cmocka_unit_test(test_two_coordinates),
      cmocka_unit_test(test_two_coordinates_nonproportional),
      cmocka_unit_test(test_simultaneous),
      cmocka_unit_test(test_graze_second_stop),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
