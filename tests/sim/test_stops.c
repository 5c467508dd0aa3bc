/* test_stops.c - several stops (vi_model_add_stop) against physics: a
 * two-sided clearance with r = 1 conserves energy and its free flights take
 * 2 x_s / |v|; mirror-symmetric scenes give mirrored motions; Newton's law
 * for simultaneous contacts against its closed forms (uncoupled and coupled
 * G); stops on different coordinates; sticking on one stop while another
 * is hit, and its release; single-stop refusals and limits. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vi_testutil.h"

/* ---- the model's API -------------------------------------------------------- */
static void test_model_api(void **state)
{
  (void)state;
  vi_model *m = NULL;
  assert_int_equal(vi_model_create(2, &m), VI_OK);
  const double M[4] = {2.0, 0.0, 0.0, 4.0}, K[4] = {1.0, 0.0, 0.0, 1.0};
  const double w0[2] = {1.0, 0.0}, w1[2] = {-1.0, 1.0}, zero[2] = {0.0, 0.0};
  assert_int_equal(vi_model_num_stops(m), 0);
  assert_int_equal(vi_model_set_mass(m, M, 2), VI_OK);
  assert_int_equal(vi_model_set_stiffness(m, K, 2), VI_OK);
  assert_int_equal(vi_model_add_stop(m, w0, 0.5, 0.9), VI_OK);
  assert_int_equal(vi_model_add_stop(m, w1, 0.25, 0.4), VI_OK);
  assert_int_equal(vi_model_num_stops(m), 2);
  /* validation names the stop */
  assert_int_equal(vi_model_add_stop(m, zero, 0.1, 0.5), VI_ERR_STOP_VECTOR);
  assert_non_null(strstr(vi_model_errmsg(m), "stop 3"));
  assert_int_equal(vi_model_add_stop(m, w0, 0.1, 1.5), VI_ERR_RESTITUTION);
  assert_int_equal(vi_model_add_stop(m, w0, NAN, 0.5), VI_ERR_NONFINITE);
  assert_int_equal(vi_model_add_stop(m, NULL, 0.1, 0.5), VI_ERR_ARG);
  assert_int_equal(vi_model_num_stops(m), 2);
  /* set_stop replaces stop 0 and keeps the others */
  const double w0b[2] = {0.0, -1.0};
  assert_int_equal(vi_model_set_stop(m, w0b, 0.75, 0.6), VI_OK);
  assert_int_equal(vi_model_num_stops(m), 2);
  double w[2], xs, r;
  assert_int_equal(vi_model_stop(m, 0, w, &xs, &r), VI_OK);
  assert_true(w[0] == 0.0 && w[1] == -1.0 && xs == 0.75 && r == 0.6);
  assert_int_equal(vi_model_stop(m, 1, w, &xs, &r), VI_OK);
  assert_true(w[0] == -1.0 && w[1] == 1.0 && xs == 0.25 && r == 0.4);
  assert_int_equal(vi_model_stop(m, 2, w, &xs, &r), VI_ERR_ARG);
  assert_int_equal(vi_model_stop(m, -1, NULL, NULL, NULL), VI_ERR_ARG);
  int ld = 0;
  assert_null(vi_model_delassus(m, &ld)); /* before setup */
  assert_int_equal(vi_model_setup(m), VI_OK);
  assert_int_equal(vi_model_add_stop(m, w0, 0.1, 0.5), VI_ERR_STATE);
  /* G = W^T M^-1 W with M^-1 = diag(1/2, 1/4), W = [(0,-1) (-1,1)] */
  const double *G = vi_model_delassus(m, &ld);
  assert_non_null(G);
  assert_int_equal(ld, 2);
  assert_close(G[0], 0.25, 1e-15);
  assert_close(G[1], -0.25, 1e-15);
  assert_close(G[2], -0.25, 1e-15);
  assert_close(G[3], 0.75, 1e-15);
  /* stop 0 is "the stop" of the single-stop getters */
  assert_close(vi_model_clearance(m), 0.75, 0.0);
  assert_close(vi_model_restitution(m), 0.6, 0.0);
  assert_close(vi_model_stop_compliance(m), 0.25, 1e-15);
  vi_model_destroy(&m);
}

/* Several stops: the exact method and erk take them; auto picks the exact
 * method. */
static void test_exact_refused(void **state)
{
  (void)state;
  const double M = 1.0, K = 1.0, W[2] = {1.0, -1.0}, xs[2] = {0.5, 0.5},
               r[2] = {1.0, 1.0};
  vi_model *m = vi_test_model_stops(1, &M, NULL, &K, 0.0, NULL, NULL, 2, W, xs, r);
  vi_sim *s = NULL;
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  /* the closed form handles several stops (tests/sim/test_exact_stops.c), and
   * so does erk (tests/sim/test_arkode.c) */
  assert_int_equal(vi_sim_set_method(s, VI_METHOD_EXACT), VI_OK);
  assert_int_equal(vi_sim_set_method(s, VI_METHOD_ERK), VI_OK);
  assert_int_equal(vi_sim_set_method(s, VI_METHOD_AUTO), VI_OK);
  const double v0 = 1.0;
  assert_int_equal(vi_sim_set_initial(s, 0.0, NULL, &v0), VI_OK);
  assert_int_equal(vi_sim_run(s, 10.0), VI_OK);
  assert_int_equal(vi_sim_method_used(s), VI_METHOD_EXACT);
  /* an initial state beyond stop 2 is named */
  const double xbad = -0.6;
  assert_int_equal(vi_sim_set_initial(s, 0.0, &xbad, NULL), VI_ERR_INITIAL_STATE);
  assert_non_null(strstr(vi_sim_errmsg(s), "stop 2"));
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
}

/* ---- two-sided clearance ---------------------------------------------------- */
typedef struct energy_watch {
  const vi_model *m;
  double E0, err;
  int n;
} energy_watch;

static int watch_energy(double t, int n, const double *x, const double *v,
                        void *u)
{
  (void)t;
  (void)n;
  energy_watch *e = u;
  e->err = fmax(e->err, fabs(vi_model_energy(e->m, x, v) - e->E0));
  e->n++;
  return 0;
}

/* A free particle between walls at +-x_s (w = e1 and w = -e1), r = 1, C = K
 * = 0: it flies 2 x_s / |v| between impacts, alternately on each wall, at
 * the same speed.  Closed form: t_j = (x_s + 2 j x_s) / v0. */
static void test_clearance_free_particle(void **state)
{
  (void)state;
  const double M = 1.0, K = 0.0, W[2] = {1.0, -1.0}, xs[2] = {0.5, 0.5},
               r[2] = {1.0, 1.0}, v0 = 1.3;
  vi_model *m = vi_test_model_stops(1, &M, NULL, &K, 0.0, NULL, NULL, 2, W, xs, r);
  for (int meth = 0; meth < 2; meth++) {
    vi_test_rec ev = {0};
    vi_sim *s = vi_test_sim_stops(m, meth ? VI_METHOD_BDF : VI_METHOD_ADAMS, 1e-10, 1e-12, 0.0, NULL, &v0, &ev);
    assert_int_equal(vi_sim_run(s, 1000.0), VI_OK);
    int expect = (int)floor((1000.0 * v0 - 0.5) / 1.0) + 1;
    assert_int_equal(ev.count, expect);
    /* Each contact is located to CVODE's root tolerance 100 eps (|t| +
     * |h|) <= 200 eps t, and the next flight starts from it: the time
     * errors add up, while each flight lasts 2 x_s / v0 to round-off. */
    double et = 0.0, ef = 0.0, ev_ = 0.0;
    for (int j = 0; j < ev.count; j++) {
      double tj = (0.5 + 1.0 * j) / v0;
      assert_int_equal(ev.kind[j], VI_EVENT_IMPACT);
      assert_int_equal(ev.stop[j], j % 2);
      et = fmax(et, fabs(ev.t[j] - tj) / (200.0 * DBL_EPSILON * (j + 1) * tj));
      if (j)
        ef = fmax(ef, fabs(ev.t[j] - ev.t[j - 1] - 1.0 / v0) /
                          (400.0 * DBL_EPSILON * tj));
      ev_ = fmax(ev_, fabs(ev.vn[j] - v0));
      assert_true(ev.ie[j] == 0.0); /* r = 1: WB 10 gives exactly 0 */
    }
    print_message("free particle (%s): %d impacts, time error %.3g and flight "
                  "time error %.3g of their root-tolerance bounds, speed error "
                  "%.3g\n", meth ? "bdf" : "adams", ev.count, et, ef, ev_);
    assert_true(et < 1.0);
    assert_true(ef < 1.0);
    assert_true(ev_ < 1e-10);
    double ie[2];
    assert_int_equal(vi_sim_stop_losses(s, ie), VI_OK);
    assert_true(ie[0] == 0.0 && ie[1] == 0.0);
    vi_sim_destroy(&s);
    vi_test_rec_free(&ev);
  }
  vi_model_destroy(&m);
}

/* The same walls with r < 1: the speed after j impacts is r^j v0, the
 * flights last 2 x_s / (r^j v0), and stop k's losses are the sum of
 * 1/2 (r^{2j} - r^{2j+2}) v0^2 over its impacts. */
static void test_clearance_restitution(void **state)
{
  (void)state;
  const double M = 1.0, K = 0.0, W[2] = {1.0, -1.0}, xs[2] = {0.5, 0.5},
               r[2] = {0.9, 0.9}, v0 = 2.0;
  vi_model *m = vi_test_model_stops(1, &M, NULL, &K, 0.0, NULL, NULL, 2, W, xs, r);
  vi_test_rec ev = {0};
  vi_sim *s = vi_test_sim_stops(m, VI_METHOD_ADAMS, 1e-10, 1e-12, 0.0, NULL, &v0, &ev);
  assert_int_equal(vi_sim_enable_ledger(s, 1), VI_OK);
  assert_int_equal(vi_sim_run(s, 60.0), VI_OK);
  double t = 0.5 / v0, v = v0, loss[2] = {0.0, 0.0}, et = 0.0;
  int j = 0;
  for (; t < 60.0; j++) {
    assert_true(j < ev.count);
    assert_int_equal(ev.stop[j], j % 2);
    et = fmax(et, fabs(ev.t[j] - t) / t);
    assert_close(ev.vn[j], v, 1e-9 * v0);
    loss[j % 2] += 0.5 * v * v * (1.0 - 0.81);
    v *= 0.9;
    t += 1.0 / v;
  }
  assert_int_equal(ev.count, j);
  double ie[2], ie_led;
  assert_int_equal(vi_sim_stop_losses(s, ie), VI_OK);
  assert_int_equal(vi_sim_ledger(s, NULL, NULL, NULL, NULL, NULL, NULL,
                                     &ie_led), VI_OK);
  print_message("walls r = 0.9: %d impacts, relative time error %.3g, losses "
                "%.12g + %.12g (closed form %.12g + %.12g)\n", j, et, ie[0],
                ie[1], loss[0], loss[1]);
  assert_true(et < 1e-9);
  assert_close(ie[0], loss[0], 1e-9);
  assert_close(ie[1], loss[1], 1e-9);
  assert_close(ie[0] + ie[1], ie_led, 1e-14);
  assert_true(vi_sim_ledger_max_residual(s) < 1e-8);
  vi_sim_destroy(&s);
  vi_test_rec_free(&ev);
  vi_model_destroy(&m);
}

/* An oscillator in a symmetric clearance, r = 1, C = 0, unforced: its
 * energy 1/2 v^T v + 1/2 x^T K x is conserved through over a thousand
 * impacts up to the integration error: each restart and each contact
 * location costs of the order of rtol (bound: 10 rtol per impact), and the
 * drift shrinks in proportion to the tolerance (10x less for 100x tighter
 * tolerances), which an error in the impact law would not. */
static void test_clearance_energy(void **state)
{
  (void)state;
  const double M[4] = {1.0, 0.0, 0.0, 1.0}, K[4] = {2.0, -1.0, -1.0, 1.0};
  /* a 2-DOF chain whose tip (mass 2) rattles in a clearance +-0.2 */
  const double W[4] = {0.0, 1.0, 0.0, -1.0}, xs[2] = {0.2, 0.2},
               r[2] = {1.0, 1.0};
  vi_model *m = vi_test_model_stops(2, M, NULL, K, 0.0, NULL, NULL, 2, W, xs, r);
  const double x0[2] = {0.3, 0.0}, v0[2] = {0.0, 1.0};
  const int meths[3] = {VI_METHOD_ADAMS, VI_METHOD_ADAMS, VI_METHOD_BDF};
  const double rtols[3] = {1e-10, 1e-12, 1e-10};
  double drift[3];
  for (int q = 0; q < 3; q++) {
    vi_test_rec ev = {0};
    vi_sim *s = vi_test_sim_stops(m, meths[q], rtols[q], 1e-2 * rtols[q], 0.0, x0, v0, &ev);
    energy_watch e = {m, vi_model_energy(m, x0, v0), 0.0, 0};
    assert_int_equal(vi_sim_set_sampling(s, 0.05, watch_energy, &e, NULL), VI_OK);
    assert_int_equal(vi_sim_run(s, 500.0), VI_OK);
    int hits[2] = {0, 0};
    for (int j = 0; j < ev.count; j++) hits[ev.stop[j]]++;
    drift[q] = e.err / e.E0;
    print_message("clearance (%s, rtol %g): %d + %d impacts, relative energy "
                  "drift %.3g\n", vi_method_name(meths[q]), rtols[q], hits[0],
                  hits[1], drift[q]);
    assert_true(hits[0] > 500 && hits[1] > 500);
    assert_true(drift[q] < 10.0 * rtols[q] * ev.count);
    vi_sim_destroy(&s);
    vi_test_rec_free(&ev);
  }
  assert_true(drift[1] < 0.1 * drift[0]);
  vi_model_destroy(&m);
}

/* ---- symmetry ----------------------------------------------------------------- */
/* A symmetric 2-DOF chain fixed at both ends, M = I, K = [2 -1; -1 2],
 * C = 0.05 K, mass 1 stopped at x1 <= x_s, mass 2 at -x2 <= x_s.  The map
 * S (x1, x2) -> (-x2, -x1) swaps the stops and leaves M, C, K and the
 * forcing a = (1, -1) cos(Omega t) unchanged, so S maps solutions to
 * solutions with the stops' roles swapped. */
static vi_model *mirror_model(void)
{
  const double M[4] = {1.0, 0.0, 0.0, 1.0}, K[4] = {2.0, -1.0, -1.0, 2.0};
  const double C[4] = {0.1, -0.05, -0.05, 0.1}, a[2] = {0.6, -0.6};
  const double W[4] = {1.0, 0.0, 0.0, -1.0}, xs[2] = {0.15, 0.15},
               r[2] = {0.8, 0.8};
  return vi_test_model_stops(2, M, C, K, 1.3, a, NULL, 2, W, xs, r);
}

typedef struct traj {
  int n;
  double x[4001][2];
} traj;

static int keep(double t, int n, const double *x, const double *v, void *u)
{
  (void)t;
  (void)n;
  (void)v;
  traj *p = u;
  if (p->n < 4001) {
    p->x[p->n][0] = x[0];
    p->x[p->n][1] = x[1];
  }
  p->n++;
  return 0;
}

/* From an asymmetric state and from its mirror image: x_B(t) = S x_A(t),
 * each impact of A on one stop an impact of B on the other. */
static void test_mirror_equivariance(void **state)
{
  (void)state;
  vi_model *m = mirror_model();
  const double xa[2] = {0.05, -0.02}, va[2] = {0.3, 0.1};
  const double xb[2] = {0.02, -0.05}, vb[2] = {-0.1, -0.3};
  vi_test_rec ea = {0}, eb = {0};
  traj *pa = calloc(1, sizeof *pa), *pb = calloc(1, sizeof *pb);
  assert_non_null(pa);
  assert_non_null(pb);
  vi_sim *a = vi_test_sim_stops(m, VI_METHOD_ADAMS, 1e-11, 1e-13, 0.0, xa, va, &ea);
  vi_sim *b = vi_test_sim_stops(m, VI_METHOD_ADAMS, 1e-11, 1e-13, 0.0, xb, vb, &eb);
  assert_int_equal(vi_sim_set_sampling(a, 0.025, keep, pa, NULL), VI_OK);
  assert_int_equal(vi_sim_set_sampling(b, 0.025, keep, pb, NULL), VI_OK);
  assert_int_equal(vi_sim_run(a, 100.0), VI_OK);
  assert_int_equal(vi_sim_run(b, 100.0), VI_OK);
  assert_int_equal(ea.count, eb.count);
  assert_true(ea.count > 20);
  int hits[2] = {0, 0};
  double et = 0.0, ex = 0.0;
  for (int j = 0; j < ea.count; j++) {
    assert_int_equal(ea.kind[j], eb.kind[j]);
    assert_int_equal(ea.stop[j], 1 - eb.stop[j]);
    hits[ea.stop[j]]++;
    et = fmax(et, fabs(ea.t[j] - eb.t[j]));
  }
  assert_int_equal(pa->n, pb->n);
  for (int i = 0; i < pa->n && i < 4001; i++)
    ex = fmax(ex, fmax(fabs(pb->x[i][0] + pa->x[i][1]),
                       fabs(pb->x[i][1] + pa->x[i][0])));
  print_message("mirror: %d + %d impacts, event times differ by %.3g, "
                "|x_B - S x_A| <= %.3g\n", hits[0], hits[1], et, ex);
  assert_true(hits[0] > 5 && hits[1] > 5);
  assert_true(et < 1e-7);
  assert_true(ex < 1e-7);
  /* the orbit analysis takes several stops (test_orbits); a reduced model
   * keeps one stop and refuses the model */
  vi_model *red = NULL;
  const int mode0 = 0;
  assert_int_equal(vi_model_create_reduced(m, &mode0, 1, 0.8, &red),
                   VI_ERR_UNSUPPORTED);
  assert_null(red);
  vi_sim_destroy(&a);
  vi_sim_destroy(&b);
  free(pa);
  free(pb);
  vi_test_rec_free(&ea);
  vi_test_rec_free(&eb);
  vi_model_destroy(&m);
}

/* From a symmetric state (S z0 = z0) the motion stays symmetric: x2 = -x1,
 * and the impacts come in pairs, one on each stop at the same instant, of
 * equal speed: simultaneous contacts in the integrator. */
static void test_mirror_symmetric_orbit(void **state)
{
  (void)state;
  vi_model *m = mirror_model();
  const double x0[2] = {0.05, -0.05}, v0[2] = {0.2, -0.2};
  vi_test_rec ev = {0};
  traj *p = calloc(1, sizeof *p);
  assert_non_null(p);
  vi_sim *s = vi_test_sim_stops(m, VI_METHOD_ADAMS, 1e-11, 1e-13, 0.0, x0, v0, &ev);
  assert_int_equal(vi_sim_set_sampling(s, 0.025, keep, p, NULL), VI_OK);
  assert_int_equal(vi_sim_run(s, 100.0), VI_OK);
  double asym = 0.0, et = 0.0, evn = 0.0;
  for (int i = 0; i < p->n && i < 4001; i++)
    asym = fmax(asym, fabs(p->x[i][0] + p->x[i][1]));
  assert_true(ev.count >= 10);
  assert_int_equal(ev.count % 2, 0);
  for (int j = 0; j < ev.count; j += 2) {
    assert_int_equal(ev.kind[j], VI_EVENT_IMPACT);
    assert_int_equal(ev.stop[j], 0);
    assert_int_equal(ev.stop[j + 1], 1);
    et = fmax(et, fabs(ev.t[j] - ev.t[j + 1]));
    evn = fmax(evn, fabs(ev.vn[j] - ev.vn[j + 1]) / ev.vn[j]);
  }
  print_message("symmetric orbit: %d impact pairs, |x1 + x2| <= %.3g, pair "
                "times differ by %.3g, speeds by %.3g\n", ev.count / 2, asym,
                et, evn);
  assert_true(asym < 1e-8);
  assert_true(et < 1e-9);
  assert_true(evn < 1e-6);
  vi_sim_destroy(&s);
  free(p);
  vi_test_rec_free(&ev);
  vi_model_destroy(&m);
}

/* ---- Newton's law for simultaneous contacts --------------------------------- */
/* Uncoupled: M = diag(m1, m2), w = e1, e2.  Each rebounds with -r_k v_k,
 * P_k = m_k (1 + r_k) v_k, and loses 1/2 m_k v_k^2 (1 - r_k^2). */
static void test_newton_uncoupled(void **state)
{
  (void)state;
  const double M[4] = {2.0, 0.0, 0.0, 0.5}, K[4] = {1.0, 0.0, 0.0, 1.0};
  const double W[4] = {1.0, 0.0, 0.0, 1.0}, xs[2] = {0.1, 0.1},
               r[2] = {0.8, 0.3};
  vi_model *m = vi_test_model_stops(2, M, NULL, K, 0.0, NULL, NULL, 2, W, xs, r);
  const double vm[2] = {1.5, 0.7};
  const int both[2] = {0, 1};
  double vp[2], P[2], ie[2];
  assert_int_equal(vi_impact_apply_multi(m, 2, both, vm, vp, P, ie), VI_OK);
  for (int k = 0; k < 2; k++) {
    double mk = M[3 * (size_t)k];
    assert_close(vp[k], -r[k] * vm[k], 1e-15);
    assert_close(P[k], mk * (1.0 + r[k]) * vm[k], 1e-14);
    assert_close(ie[k], 0.5 * mk * vm[k] * vm[k] * (1.0 - r[k] * r[k]), 1e-14);
  }
  /* one contact is WB 2 (vi_impact_apply) to the last bit */
  double v1[2], vn, ie1, P1;
  const int one = 0;
  assert_int_equal(vi_impact_apply(m, vm, v1, &vn, &ie1), VI_OK);
  assert_int_equal(vi_impact_apply_multi(m, 1, &one, vm, vp, &P1, ie), VI_OK);
  assert_true(vp[0] == v1[0] && vp[1] == v1[1] && ie[0] == ie1);
  /* bad lists */
  const int dup[2] = {1, 1}, out[1] = {2};
  assert_int_equal(vi_impact_apply_multi(m, 2, dup, vm, vp, NULL, NULL), VI_ERR_ARG);
  assert_int_equal(vi_impact_apply_multi(m, 1, out, vm, vp, NULL, NULL), VI_ERR_ARG);
  assert_int_equal(vi_impact_apply_multi(m, 0, out, vm, vp, NULL, NULL), VI_ERR_ARG);
  vi_model_destroy(&m);

  /* in the integrator: two equal oscillators x'' + x = 0 from x = 0, v = v0
   * reach x_s together at t* = asin(x_s / v0), speed v0 cos t* */
  const double Mi[4] = {1.0, 0.0, 0.0, 1.0};
  m = vi_test_model_stops(2, Mi, NULL, K, 0.0, NULL, NULL, 2, W, xs, r);
  const double v0[2] = {0.5, 0.5};
  vi_test_rec ev = {0};
  vi_sim *s = vi_test_sim_stops(m, VI_METHOD_ADAMS, 1e-11, 1e-13, 0.0, NULL, v0, &ev);
  assert_int_equal(vi_sim_run(s, 1.0), VI_OK);
  double ts = asin(0.1 / 0.5), us = 0.5 * cos(ts);
  assert_int_equal(ev.count, 2);
  for (int k = 0; k < 2; k++) {
    assert_int_equal(ev.stop[k], k);
    assert_close(ev.t[k], ts, 1e-9);
    assert_close(ev.vn[k], us, 1e-9);
    assert_close(ev.vp[2 * k + k], -r[k] * us, 1e-9);
    assert_close(ev.ie[k], 0.5 * us * us * (1.0 - r[k] * r[k]), 1e-9);
  }
  vi_sim_destroy(&s);
  vi_test_rec_free(&ev);
  vi_model_destroy(&m);
}

/* Coupled: M = I, w1 = e1, w2 = (cos th, sin th), so G = [1 c; c 1] with
 * c = cos th.  With u = W^T v and e = (1 + r) u (both approaching), the
 * two-contact LCP has the closed form: both act when P = G^-1 e = (e1 -
 * c e2, e2 - c e1) / (1 - c^2) >= 0, and then w_k.v+ = -r_k u_k; if e2 <
 * c e1 only stop 1 acts, P1 = e1, and stop 2 separates faster than Newton
 * asks, y2 = c e1 - e2 > 0 (and symmetrically).  The energy lost is
 * P.u - P.G P / 2 = 1/2 sum P_k u_k (1 - r_k): none for r = 1. */
static void test_newton_coupled(void **state)
{
  (void)state;
  const double th = M_PI / 3.0, c = cos(th), sn = sin(th);
  const double M[4] = {1.0, 0.0, 0.0, 1.0}, K[4] = {1.0, 0.0, 0.0, 1.0};
  const double W[4] = {1.0, 0.0, c, sn}, xs[2] = {0.1, 0.1};
  const double rr[3][2] = {{0.5, 0.5}, {0.9, 0.2}, {1.0, 1.0}};
  const double vms[4][2] = {{1.0, 0.2}, {1.0, -0.2}, {0.3, 1.0}, {0.2, 0.05}};
  const int both[2] = {0, 1};
  int cases[3] = {0, 0, 0};
  for (int q = 0; q < 3; q++) {
    vi_model *m = vi_test_model_stops(2, M, NULL, K, 0.0, NULL, NULL, 2, W, xs, rr[q]);
    for (int iv = 0; iv < 4; iv++) {
      const double *vm = vms[iv];
      double u[2] = {vm[0], c * vm[0] + sn * vm[1]}, e[2], Pe[2], P[2],
             vp[2], ie[2];
      assert_true(u[0] > 0.0 && u[1] > 0.0);
      for (int k = 0; k < 2; k++) e[k] = (1.0 + rr[q][k]) * u[k];
      Pe[0] = (e[0] - c * e[1]) / (1.0 - c * c);
      Pe[1] = (e[1] - c * e[0]) / (1.0 - c * c);
      int which = 2; /* both */
      if (e[1] < c * e[0]) {
        Pe[0] = e[0];
        Pe[1] = 0.0;
        which = 0;
      } else if (e[0] < c * e[1]) {
        Pe[0] = 0.0;
        Pe[1] = e[1];
        which = 1;
      }
      cases[which]++;
      assert_int_equal(vi_impact_apply_multi(m, 2, both, vm, vp, P, ie), VI_OK);
      assert_close(P[0], Pe[0], 1e-14);
      assert_close(P[1], Pe[1], 1e-14);
      /* complementarity from the velocities: y_k = -w_k.v+ - r_k u_k */
      for (int k = 0; k < 2; k++) {
        const double *wk = W + 2 * (size_t)k;
        double y = -(wk[0] * vp[0] + wk[1] * vp[1]) - rr[q][k] * u[k];
        assert_true(P[k] >= 0.0);
        assert_true(y >= -1e-14);
        assert_true(fabs(P[k] * y) <= 1e-14);
        if (which != 2 && k != which) assert_true(y > 1e-3); /* separates */
      }
      double dKE = 0.5 * (vm[0] * vm[0] + vm[1] * vm[1]) -
                   0.5 * (vp[0] * vp[0] + vp[1] * vp[1]);
      double formula = 0.5 * (P[0] * u[0] * (1.0 - rr[q][0]) +
                              P[1] * u[1] * (1.0 - rr[q][1]));
      print_message("coupled r = (%.1f, %.1f), v = (%.2f, %.2f): %s, P = "
                    "(%.6f, %.6f), KE loss %.15g, formula %.15g\n", rr[q][0],
                    rr[q][1], vm[0], vm[1],
                    which == 2 ? "both act" : which ? "stop 2 acts"
                                                    : "stop 1 acts",
                    P[0], P[1], dKE, formula);
      assert_close(dKE, formula, 1e-14);
      assert_close(ie[0] + ie[1], dKE, 1e-14);
      if (q == 2) assert_true(fabs(dKE) < 1e-14); /* r = 1: no loss */
    }
    vi_model_destroy(&m);
  }
  /* every branch of the closed form was exercised */
  assert_true(cases[0] > 0 && cases[1] > 0 && cases[2] > 0);
}

/* The coupled case in the integrator: a free particle in the plane (M = I,
 * K = 0) heading with v = (1, 0.2) straight into the corner of the stops
 * x1 <= 0.1 and cos th x1 + sin th x2 <= 0.1 (th = 60 degrees) meets both
 * at t = 1.  With r = 0.5 both act (the closed form above): P = G^-1
 * (1 + r) u and v+ = (-0.5, -0.1), after which it leaves both stops. */
static void test_newton_corner(void **state)
{
  (void)state;
  const double th = M_PI / 3.0, c = cos(th), sn = sin(th);
  const double M[4] = {1.0, 0.0, 0.0, 1.0}, K[4] = {0.0, 0.0, 0.0, 0.0};
  const double W[4] = {1.0, 0.0, c, sn}, xs[2] = {0.1, 0.1},
               r[2] = {0.5, 0.5};
  vi_model *m = vi_test_model_stops(2, M, NULL, K, 0.0, NULL, NULL, 2, W, xs, r);
  const double v0[2] = {1.0, 0.2}, corner[2] = {0.1, (0.1 - c * 0.1) / sn};
  const double x0[2] = {corner[0] - v0[0], corner[1] - v0[1]};
  vi_test_rec ev = {0};
  vi_sim *s = vi_test_sim_stops(m, VI_METHOD_ADAMS, 1e-11, 1e-13, 0.0, x0, v0, &ev);
  assert_int_equal(vi_sim_enable_ledger(s, 1), VI_OK);
  assert_int_equal(vi_sim_run(s, 5.0), VI_OK);
  assert_int_equal(ev.count, 2);
  double u[2] = {v0[0], c * v0[0] + sn * v0[1]}, ie = 0.0;
  double P[2] = {(1.5 * u[0] - c * 1.5 * u[1]) / (1.0 - c * c),
                 (1.5 * u[1] - c * 1.5 * u[0]) / (1.0 - c * c)};
  for (int k = 0; k < 2; k++) {
    assert_int_equal(ev.kind[k], VI_EVENT_IMPACT);
    assert_int_equal(ev.stop[k], k);
    assert_close(ev.t[k], 1.0, 1e-9);
    assert_close(ev.vn[k], u[k], 1e-9);
    assert_close(ev.vp[2 * (size_t)k], -0.5, 1e-9);
    assert_close(ev.vp[2 * k + 1], -0.1, 1e-9);
    assert_close(ev.ie[k], 0.5 * P[k] * u[k] * 0.5, 1e-9);
    ie += ev.ie[k];
  }
  double dKE = 0.5 * (1.0 + 0.04) - 0.5 * (0.25 + 0.01), ie_led;
  assert_int_equal(vi_sim_ledger(s, NULL, NULL, NULL, NULL, NULL, NULL,
                                     &ie_led), VI_OK);
  print_message("corner: both stops at t = %.15f, v+ = (%.12f, %.12f), "
                "loss %.15f (closed form %.15f), ledger residual %.3g\n",
                ev.t[0], ev.vp[0], ev.vp[1], ie, dKE,
                vi_sim_ledger_max_residual(s));
  assert_close(ie, dKE, 1e-9);
  assert_close(ie_led, dKE, 1e-9);
  assert_true(vi_sim_ledger_max_residual(s) < 1e-9);
  vi_sim_destroy(&s);
  vi_test_rec_free(&ev);
  vi_model_destroy(&m);
}

/* More stops touching at once than the enumeration takes: VI_ERR_LIMIT;
 * dependent stop vectors with no solution: VI_ERR_NOT_CONVERGED, or the
 * one-stop solution when it fits. */
static void test_newton_limits(void **state)
{
  (void)state;
  enum { N = 13 };
  double M[N * N] = {0}, W[N * N] = {0}, xs[N], r[N];
  for (int i = 0; i < N; i++) {
    M[i + i * N] = 1.0;
    W[i + i * N] = 1.0;
    xs[i] = 1.0;
    r[i] = 0.5;
  }
  vi_model *m = vi_test_model_stops(N, M, NULL, M, 0.0, NULL, NULL, N, W, xs, r);
  int all[N];
  double v[N], vp[N];
  for (int i = 0; i < N; i++) {
    all[i] = i;
    v[i] = 1.0;
  }
  assert_int_equal(vi_impact_apply_multi(m, N, all, v, vp, NULL, NULL), VI_ERR_LIMIT);
  /* twelve are solved: each rebounds alone (G = I) */
  assert_int_equal(vi_impact_apply_multi(m, N - 1, all, v, vp, NULL, NULL), VI_OK);
  for (int i = 0; i < N - 1; i++) assert_close(vp[i], -0.5, 1e-15);
  assert_close(vp[N - 1], 1.0, 0.0);
  vi_model_destroy(&m);
  /* the same stop twice with different r: the one with the larger r alone
   * satisfies both Newton bounds */
  const double M1 = 1.0, W2[2] = {1.0, 1.0}, xs2[2] = {1.0, 1.0},
               r2[2] = {0.3, 0.6};
  m = vi_test_model_stops(1, &M1, NULL, &M1, 0.0, NULL, NULL, 2, W2, xs2, r2);
  const int both[2] = {0, 1};
  double v1 = 1.0, vp1, P[2];
  assert_int_equal(vi_impact_apply_multi(m, 2, both, &v1, &vp1, P, NULL), VI_OK);
  assert_close(vp1, -0.6, 1e-15);
  assert_true(P[0] == 0.0);
  vi_model_destroy(&m);
}

/* ---- stops on different coordinates ----------------------------------------- */
/* A 3-DOF chain with a stop on mass 1 and a far stop on mass 3 that is
 * never reached: the same impacts as the single-stop model, whichever
 * index the near stop has. */
static void test_stops_on_coordinates(void **state)
{
  (void)state;
  double M[9], C[9], K[9];
  const double mass[3] = {1.0, 1.0, 1.0}, k[3] = {1.0, 1.0, 1.0},
               c[3] = {0.05, 0.05, 0.05}, a[3] = {0.0, 0.0, 0.4};
  assert_int_equal(vi_build_chain(3, mass, k, c, M, C, K, 3), VI_OK);
  const double e1[3] = {1.0, 0.0, 0.0}, e3[3] = {0.0, 0.0, 1.0};
  double W_near_far[6], W_far_near[6];
  memcpy(W_near_far, e1, sizeof e1);
  memcpy(W_near_far + 3, e3, sizeof e3);
  memcpy(W_far_near, e3, sizeof e3);
  memcpy(W_far_near + 3, e1, sizeof e1);
  const double xs_nf[2] = {0.05, 100.0}, xs_fn[2] = {100.0, 0.05},
               r2[2] = {0.7, 0.7};
  vi_model *one = vi_test_model_stops(3, M, C, K, 0.7, a, NULL, 1, e1, xs_nf, r2);
  vi_model *nf = vi_test_model_stops(3, M, C, K, 0.7, a, NULL, 2, W_near_far, xs_nf, r2);
  vi_model *fn = vi_test_model_stops(3, M, C, K, 0.7, a, NULL, 2, W_far_near, xs_fn, r2);
  vi_test_rec e0 = {0}, e_nf = {0}, e_fn = {0};
  vi_sim *s0 = vi_test_sim_stops(one, VI_METHOD_ADAMS, 1e-10, 1e-12, 0.0, NULL, NULL, &e0);
  vi_sim *s1 = vi_test_sim_stops(nf, VI_METHOD_ADAMS, 1e-10, 1e-12, 0.0, NULL, NULL, &e_nf);
  vi_sim *s2 = vi_test_sim_stops(fn, VI_METHOD_ADAMS, 1e-10, 1e-12, 0.0, NULL, NULL, &e_fn);
  assert_int_equal(vi_sim_run(s0, 150.0), VI_OK);
  assert_int_equal(vi_sim_run(s1, 150.0), VI_OK);
  assert_int_equal(vi_sim_run(s2, 150.0), VI_OK);
  assert_true(e0.count > 10);
  assert_int_equal(e_nf.count, e0.count);
  assert_int_equal(e_fn.count, e0.count);
  double et = 0.0;
  for (int j = 0; j < e0.count; j++) {
    assert_int_equal(e_nf.stop[j], 0);
    assert_int_equal(e_fn.stop[j], 1);
    et = fmax(et, fmax(fabs(e_nf.t[j] - e0.t[j]), fabs(e_fn.t[j] - e0.t[j])));
  }
  print_message("stop on mass 1 beside an unreached one: %d impacts, times "
                "within %.3g of the single-stop model\n", e0.count, et);
  assert_true(et < 1e-6);
  vi_sim_destroy(&s0);
  vi_sim_destroy(&s1);
  vi_sim_destroy(&s2);
  vi_test_rec_free(&e0);
  vi_test_rec_free(&e_nf);
  vi_test_rec_free(&e_fn);
  vi_model_destroy(&one);
  vi_model_destroy(&nf);
  vi_model_destroy(&fn);
}

/* ---- sticking on one stop while another is hit ------------------------------ */
typedef struct stick_watch {
  double xs, dev, t_release;
} stick_watch;

static int watch_stick(double t, int n, const double *x, const double *v,
                       void *u)
{
  (void)n;
  (void)v;
  stick_watch *w = u;
  if (t < w->t_release) w->dev = fmax(w->dev, fabs(x[0] - w->xs));
  return 0;
}

/* Two uncoupled unit oscillators.  Mass 1 rests on its stop x1 <= 0.1 (r =
 * 0.5), pressed by f0 = 0.3 + 0.25 cos(t / 2): the contact force f0 - x_s
 * = 0.2 + 0.25 cos(t / 2) falls through 0 at t_r = 2 acos(-0.8).  Mass 2
 * bounces elastically (r = 1) on x2 <= 0.1 from x = 0, v = 0.5: x2 = 0.5
 * sin t reflected, impacts every pi + 2 th1 from th1 = asin(0.2). */
static void test_stick_while_other_hit(void **state)
{
  (void)state;
  const double M[4] = {1.0, 0.0, 0.0, 1.0}, K[4] = {1.0, 0.0, 0.0, 1.0};
  const double W[4] = {1.0, 0.0, 0.0, 1.0}, xs[2] = {0.1, 0.1},
               r[2] = {0.5, 1.0};
  const double a[2] = {0.25, 0.0}, f0[2] = {0.3, 0.0};
  vi_model *m = vi_test_model_stops(2, M, NULL, K, 0.5, a, f0, 2, W, xs, r);
  const double x0[2] = {0.1, 0.0}, v0[2] = {0.0, 0.5};
  double t_r = 2.0 * acos(-0.8), th1 = asin(0.2);
  for (int meth = 0; meth < 2; meth++) {
    vi_test_rec ev = {0};
    vi_sim *s = vi_test_sim_stops(m, meth ? VI_METHOD_BDF : VI_METHOD_ADAMS, 1e-10, 1e-12, 0.0, x0, v0, &ev);
    stick_watch w = {0.1, 0.0, t_r};
    assert_int_equal(vi_sim_enable_ledger(s, 1), VI_OK);
    assert_int_equal(vi_sim_set_sampling(s, 0.01, watch_stick, &w, NULL), VI_OK);
    assert_int_equal(vi_sim_run(s, t_r + 0.5), VI_OK);
    int hits = 0, sticks = 0, releases = 0;
    double et = 0.0, t_rel = -1.0;
    for (int j = 0; j < ev.count; j++) {
      if (ev.kind[j] == VI_EVENT_STICK) {
        sticks++;
        assert_int_equal(ev.stop[j], 0);
        assert_close(ev.t[j], 0.0, 0.0);
      } else if (ev.kind[j] == VI_EVENT_RELEASE) {
        releases++;
        assert_int_equal(ev.stop[j], 0);
        t_rel = ev.t[j];
      } else {
        assert_int_equal(ev.stop[j], 1);
        et = fmax(et, fabs(ev.t[j] - (th1 + hits * (M_PI + 2.0 * th1))));
        assert_close(ev.vn[j], 0.5 * cos(th1), 1e-8);
        hits++;
      }
    }
    print_message("sticking (%s): %d impacts on stop 2 while stuck on stop "
                  "1 (times within %.3g), |x1 - x_s| <= %.3g, release at "
                  "%.12f (closed form %.12f), ledger residual %.3g\n",
                  meth ? "bdf" : "adams", hits, et, w.dev, t_rel, t_r,
                  vi_sim_ledger_max_residual(s));
    assert_int_equal(sticks, 1);
    assert_int_equal(releases, 1);
    assert_true(hits >= 2);
    assert_true(et < 1e-8);
    assert_true(w.dev < 1e-9);
    assert_close(t_rel, t_r, 1e-9);
    assert_true(vi_sim_ledger_max_residual(s) < 1e-7);
    vi_sim_destroy(&s);
    vi_test_rec_free(&ev);
  }
  vi_model_destroy(&m);
}

/* Both masses pressed onto their stops with r = 0.5 and dropped from rest
 * below them: each chatters into sticking; the constrained motion holds
 * both stops at once (the projection with G_SS) and the contact forces
 * f0_k - x_s stay positive, so neither releases. */
static void test_stick_on_two(void **state)
{
  (void)state;
  const double M[4] = {1.0, 0.0, 0.0, 1.0}, K[4] = {1.5, -0.5, -0.5, 1.5};
  const double W[4] = {1.0, 0.0, 0.0, 1.0}, xs[2] = {0.1, 0.1},
               r[2] = {0.5, 0.5};
  const double f0[2] = {0.6, 0.6};
  vi_model *m = vi_test_model_stops(2, M, NULL, K, 0.0, NULL, f0, 2, W, xs, r);
  const double x0[2] = {0.05, 0.0};
  vi_test_rec ev = {0};
  vi_sim *s = vi_test_sim_stops(m, VI_METHOD_ADAMS, 1e-10, 1e-12, 0.0, x0, NULL, &ev);
  assert_int_equal(vi_sim_enable_ledger(s, 1), VI_OK);
  assert_int_equal(vi_sim_run(s, 40.0), VI_OK);
  int stuck[2] = {0, 0}, rel = 0;
  for (int j = 0; j < ev.count; j++) {
    if (ev.kind[j] == VI_EVENT_STICK) stuck[ev.stop[j]]++;
    if (ev.kind[j] == VI_EVENT_RELEASE) rel++;
  }
  double x[2], v[2];
  assert_int_equal(vi_sim_state(s, NULL, x, v), VI_OK);
  print_message("two stops held: %d events, sticks (%d, %d), x = (%.12g, "
                "%.12g), v = (%.3g, %.3g), ledger residual %.3g\n", ev.count,
                stuck[0], stuck[1], x[0], x[1], v[0], v[1],
                vi_sim_ledger_max_residual(s));
  assert_true(vi_sim_is_sticking(s));
  assert_true(stuck[0] >= 1 && stuck[1] >= 1);
  assert_int_equal(rel, 0);
  assert_close(x[0], 0.1, 1e-9);
  assert_close(x[1], 0.1, 1e-9);
  assert_close(v[0], 0.0, 1e-9);
  assert_close(v[1], 0.0, 1e-9);
  assert_true(vi_sim_ledger_max_residual(s) < 1e-7);
  vi_sim_destroy(&s);
  vi_test_rec_free(&ev);
  vi_model_destroy(&m);
}

/* Both masses start at rest on their stops (x = (0.1, 0.1)), pressed, r =
 * 0.5: both stick at once.  Held on both (G = I), the contact forces are
 * the free accelerations f - K x: stop 1's 0.5 + 0.625 cos(t / 2) falls
 * through 0 at t_r = 2 acos(-0.8) and releases it, while stop 2's 0.45 +
 * x1 / 2 stays positive and keeps mass 2 on its stop. */
static void test_release_one_of_two(void **state)
{
  (void)state;
  const double M[4] = {1.0, 0.0, 0.0, 1.0}, K[4] = {1.5, -0.5, -0.5, 1.5};
  const double W[4] = {1.0, 0.0, 0.0, 1.0}, xs[2] = {0.1, 0.1},
               r[2] = {0.5, 0.5};
  const double a[2] = {0.625, 0.0}, f0[2] = {0.6, 0.6};
  vi_model *m = vi_test_model_stops(2, M, NULL, K, 0.5, a, f0, 2, W, xs, r);
  const double x0[2] = {0.1, 0.1};
  double t_r = 2.0 * acos(-0.8);
  for (int meth = 0; meth < 2; meth++) {
    vi_test_rec ev = {0};
    vi_sim *s = vi_test_sim_stops(m, meth ? VI_METHOD_BDF : VI_METHOD_ADAMS, 1e-10, 1e-12, 0.0, x0, NULL, &ev);
    assert_int_equal(vi_sim_enable_ledger(s, 1), VI_OK);
    assert_int_equal(vi_sim_run(s, t_r + 1.0), VI_OK);
    int stick[2] = {0, 0}, rel[2] = {0, 0};
    double t_rel = -1.0;
    for (int j = 0; j < ev.count; j++) {
      assert_true(ev.kind[j] != VI_EVENT_IMPACT);
      if (ev.kind[j] == VI_EVENT_STICK) {
        stick[ev.stop[j]]++;
        assert_close(ev.t[j], 0.0, 0.0);
      }
      if (ev.kind[j] == VI_EVENT_RELEASE) {
        rel[ev.stop[j]]++;
        t_rel = ev.t[j];
      }
    }
    double x[2];
    assert_int_equal(vi_sim_state(s, NULL, x, NULL), VI_OK);
    print_message("release one of two (%s): release of stop 1 at %.12f "
                  "(closed form %.12f), x = (%.6f, %.12f), ledger residual "
                  "%.3g\n", meth ? "bdf" : "adams", t_rel, t_r, x[0], x[1],
                  vi_sim_ledger_max_residual(s));
    assert_int_equal(stick[0], 1);
    assert_int_equal(stick[1], 1);
    assert_int_equal(rel[0], 1);
    assert_int_equal(rel[1], 0);
    assert_close(t_rel, t_r, 1e-9);
    assert_true(vi_sim_is_sticking(s));
    assert_true(x[0] < 0.1 - 1e-3); /* mass 1 has left its stop */
    assert_close(x[1], 0.1, 1e-9);
    assert_true(vi_sim_ledger_max_residual(s) < 1e-7);
    vi_sim_destroy(&s);
    vi_test_rec_free(&ev);
  }
  vi_model_destroy(&m);
}

/* A plastic impact (r = 0) leaves the mass on its stop with no normal
 * velocity.  Whether it then sticks depends on the contact force after the
 * impact: the damping force changes with the velocity jump, and a mass
 * pressed only afterwards must stick, not restart on g = g' = 0 where the
 * contact root cannot be seen (the run once ended in VI_ERR_INVARIANT at
 * t = 6.39 here).  One stop on mass 1 of a damped 3-DOF chain. */
static void test_plastic_pressed_after(void **state)
{
  (void)state;
  double M[9], C[9], K[9];
  const double mass[3] = {1.0, 1.0, 1.0}, k[3] = {1.0, 1.0, 1.0},
               c[3] = {0.05, 0.05, 0.05}, a[3] = {0.8, 0.0, -0.4},
               f0[3] = {0.0, 0.05, 0.0}, w[3] = {1.0, 0.0, 0.0}, xs = 0.2,
               r = 0.0;
  assert_int_equal(vi_build_chain(3, mass, k, c, M, C, K, 3), VI_OK);
  vi_model *m = vi_test_model_stops(3, M, C, K, 0.8, a, f0, 1, w, &xs, &r);
  for (int meth = 0; meth < 2; meth++) {
    vi_test_rec ev = {0};
    vi_sim *s = vi_test_sim_stops(m, meth ? VI_METHOD_BDF : VI_METHOD_ADAMS, 1e-8, 1e-10, 0.0, NULL, NULL, &ev);
    assert_int_equal(vi_sim_enable_ledger(s, 1), VI_OK);
    assert_int_equal(vi_sim_run(s, 300.0), VI_OK);
    int counts[3] = {0, 0, 0};
    for (int j = 0; j < ev.count; j++) counts[ev.kind[j]]++;
    print_message("plastic (%s): %d impacts, %d sticks, %d releases, ledger "
                  "residual %.3g\n", meth ? "bdf" : "adams", counts[0],
                  counts[1], counts[2], vi_sim_ledger_max_residual(s));
    /* each impact sticks (pressed) or leaves; every stick is released */
    assert_true(counts[0] > 10);
    assert_true(counts[1] > 10);
    assert_true(counts[2] >= counts[1] - 1);
    assert_true(vi_sim_ledger_max_residual(s) < 1e-6);
    vi_sim_destroy(&s);
    vi_test_rec_free(&ev);
  }
  vi_model_destroy(&m);
}

/* Rattling in a clearance: a free mass (K = 0, c = 0.02) between walls at
 * +-0.1 (r = 0.6), driven by f = 0.2 + 1.5 cos(0.7 t), chatters into
 * sticking on each wall in turn (tails summed).  Stuck on a wall at rest,
 * the contact force is +-f(t) (no spring, no damping force at v = 0), so
 * every release of wall 1 falls where f falls through 0 and every release
 * of wall 2 where f rises through 0; the per-stop losses add up to the
 * ledger's. */
static void test_rattle_stick_release(void **state)
{
  (void)state;
  const double M = 1.0, K = 0.0, C = 0.02, a = 1.5, f0 = 0.2, W = 0.7;
  const double Ws[2] = {1.0, -1.0}, xs[2] = {0.1, 0.1}, r[2] = {0.6, 0.6};
  vi_model *m = vi_test_model_stops(1, &M, &C, &K, W, &a, &f0, 2, Ws, xs, r);
  vi_test_rec ev = {0};
  vi_sim *s = vi_test_sim_stops(m, VI_METHOD_ADAMS, 1e-10, 1e-12, 0.0, NULL, NULL, &ev);
  assert_int_equal(vi_sim_enable_ledger(s, 1), VI_OK);
  assert_int_equal(vi_sim_run(s, 200.0), VI_OK);
  int rel[2] = {0, 0}, stick[2] = {0, 0}, held = -1;
  double ef = 0.0;
  for (int j = 0; j < ev.count; j++) {
    int k = ev.stop[j];
    assert_true(k == 0 || k == 1);
    if (ev.kind[j] == VI_EVENT_STICK) {
      assert_int_equal(held, -1); /* one wall at a time */
      held = k;
      stick[k]++;
    } else if (ev.kind[j] == VI_EVENT_RELEASE) {
      assert_int_equal(held, k);
      held = -1;
      rel[k]++;
      double t = ev.t[j], f = f0 + a * cos(W * t), fd = -a * W * sin(W * t);
      ef = fmax(ef, fabs(f));
      assert_true(k == 0 ? fd < 0.0 : fd > 0.0);
    } else {
      assert_int_equal(held, -1); /* no impact while stuck here */
    }
  }
  double ie[2], ie_led;
  assert_int_equal(vi_sim_stop_losses(s, ie), VI_OK);
  assert_int_equal(vi_sim_ledger(s, NULL, NULL, NULL, NULL, NULL, NULL,
                                     &ie_led), VI_OK);
  print_message("rattle: sticks (%d, %d), releases (%d, %d), |f| at release "
                "<= %.3g, %lld bounces summed, losses %.9g + %.9g = %.9g "
                "(ledger %.9g), residual %.3g\n", stick[0], stick[1], rel[0],
                rel[1], ef,
                (long long)vi_sim_stat(s, VI_STAT_CHATTER_SKIPPED), ie[0],
                ie[1], ie[0] + ie[1], ie_led, vi_sim_ledger_max_residual(s));
  assert_true(rel[0] >= 5 && rel[1] >= 5);
  assert_true(ef < 1e-8);
  assert_close(ie[0] + ie[1], ie_led, 1e-12 * ie_led);
  assert_true(vi_sim_ledger_max_residual(s) < 1e-6);
  vi_sim_destroy(&s);
  vi_test_rec_free(&ev);
  vi_model_destroy(&m);
}

/* Two independent integrators on a 12-mass chain with a clearance at the
 * tip and a stop on mass 3 (impacts, chattering, sticking on the stops):
 * BDF with the band Jacobian projected on the held stops, and Adams with
 * fixed-point iteration and no Jacobian, see the same events, the same
 * stops, at the same times (to 1e-4: sticking starts and releases are
 * located through slow crossings). */
static void test_band_vs_adams(void **state)
{
  (void)state;
  enum { N = 12 };
  double M[N * N], C[N * N], K[N * N], mass[N], k[N], c[N];
  for (int i = 0; i < N; i++) {
    mass[i] = 1.0;
    k[i] = 1.0;
    c[i] = 0.02;
  }
  assert_int_equal(vi_build_chain(N, mass, k, c, M, C, K, N), VI_OK);
  double a[N] = {0}, f0[N] = {0}, W[3 * N] = {0};
  a[0] = 0.3;
  f0[N - 1] = 0.02;
  W[N - 1] = 1.0;          /* tip <= 0.3 */
  W[N + N - 1] = -1.0;     /* tip >= -0.1 */
  W[2 * N + 2] = 1.0;      /* mass 3 <= 0.05 */
  const double xs[3] = {0.3, 0.1, 0.05}, r[3] = {0.5, 0.5, 0.5};
  vi_model *m = vi_test_model_stops(N, M, C, K, 0.3, a, f0, 3, W, xs, r);
  vi_test_rec ev[2] = {{0}, {0}};
  for (int q = 0; q < 2; q++) {
    vi_sim *s = vi_test_sim_stops(m, q ? VI_METHOD_BDF : VI_METHOD_ADAMS, 1e-10, 1e-12, 0.0, NULL, NULL, &ev[q]);
    /* the accumulation point to rtol: the accuracy-driven summing (the
     * default resolves every impact above 1e-5 V, at the cost of timing
     * the late, grazing ones to dx / v_n only) */
    assert_int_equal(vi_sim_set_impact_resolution(s, 0.0), VI_OK);
    assert_int_equal(vi_sim_run(s, 300.0), VI_OK);
    if (q) assert_true(vi_sim_stat(s, VI_STAT_JAC_EVALS) > 0);
    vi_sim_destroy(&s);
  }
  assert_int_equal(ev[0].count, ev[1].count);
  int sticks = 0, hits[3] = {0, 0, 0};
  double et = 0.0;
  for (int j = 0; j < ev[0].count; j++) {
    assert_int_equal(ev[0].kind[j], ev[1].kind[j]);
    assert_int_equal(ev[0].stop[j], ev[1].stop[j]);
    et = fmax(et, fabs(ev[0].t[j] - ev[1].t[j]));
    sticks += ev[0].kind[j] == VI_EVENT_STICK;
    if (ev[0].kind[j] == VI_EVENT_IMPACT) hits[ev[0].stop[j]]++;
  }
  print_message("band BDF vs Adams: %d events (impacts %d, %d, %d; %d "
                "sticks), times within %.3g\n", ev[0].count, hits[0], hits[1],
                hits[2], sticks, et);
  assert_true(sticks > 0 && hits[0] > 0 && hits[1] > 0 && hits[2] > 0);
  assert_true(et < 1e-4);
  vi_test_rec_free(&ev[0]);
  vi_test_rec_free(&ev[1]);
  vi_model_destroy(&m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_model_api),
      cmocka_unit_test(test_exact_refused),
      cmocka_unit_test(test_clearance_free_particle),
      cmocka_unit_test(test_clearance_restitution),
      cmocka_unit_test(test_clearance_energy),
      cmocka_unit_test(test_mirror_equivariance),
      cmocka_unit_test(test_mirror_symmetric_orbit),
      cmocka_unit_test(test_newton_uncoupled),
      cmocka_unit_test(test_newton_coupled),
      cmocka_unit_test(test_newton_corner),
      cmocka_unit_test(test_newton_limits),
      cmocka_unit_test(test_stops_on_coordinates),
      cmocka_unit_test(test_stick_while_other_hit),
      cmocka_unit_test(test_stick_on_two),
      cmocka_unit_test(test_release_one_of_two),
      cmocka_unit_test(test_plastic_pressed_after),
      cmocka_unit_test(test_rattle_stick_release),
      cmocka_unit_test(test_band_vs_adams),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
