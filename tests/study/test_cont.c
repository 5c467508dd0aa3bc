/* test_cont.c - continuation (vi_cont.h, src/study/vi_cont.c) on Fig. 2's
 * P(1,1) orbit in Omega: the branch points are the orbits a long
 * simulation settles on (a study with 500 transient periods), the period
 * doubling found by bisection has its multiplier at -1, a pseudo-arclength
 * point is an orbit (residual of the shooting map at round-off), and the
 * start is the 40-digit reference orbit (tests/orbit/ref_fig2_p11.py); on
 * a two-stop model whose orbit hits stop 1 the branch is the same. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vi_testutil.h"

#define FIG2_VN 0.78766085255479729134

/* A P(1,1) seed of Fig. 2 at Omega = 0.9 (Newton refines it). */
static const double X0[2] = {-0.0563, 0.1}, V0[2] = {0.11, 0.79}, T0 = 0.68;

/* The stable orbit a long simulation settles on at Omega: its v_N. */
static double settled_vn(double omega)
{
  vi_model *m = vi_test_fig2();
  vi_sweep *sw = NULL;
  int64_t n;
  const double *vn;
  assert_int_equal(vi_sweep_create(m, &sw), VI_OK);
  assert_int_equal(vi_sweep_set_run(sw, VI_METHOD_EXACT, 1e-8, 1e-10), VI_OK);
  assert_int_equal(vi_sweep_set_periods(sw, 500, 4), VI_OK);
  assert_int_equal(vi_sweep_set_param(sw, "forcing.omega", omega), VI_OK);
  assert_int_equal(vi_sweep_iterate(sw), VI_OK);
  assert_int_equal(vi_sweep_impacts(sw, &n, NULL, NULL, &vn), VI_OK);
  double v = vn[n - 1];
  vi_sweep_destroy(&sw);
  vi_model_destroy(&m);
  return v;
}

/* Natural continuation down from 0.9: stable points agree with the
 * simulated orbit to 1e-8 (transient decayed as 0.75^500); the period
 * doubling's critical multiplier is -1 to 1e-8 (p bisected to 1e-13). */
static void natural_down(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  vi_cont *c = NULL;
  assert_int_equal(vi_cont_create(m, "forcing.omega", 1, VI_CONT_NATURAL, &c), VI_OK);
  assert_int_equal(vi_cont_set_range(c, 0.6, 20), VI_OK);
  assert_int_equal(vi_cont_set_orbit(c, T0, X0, V0), VI_OK);
  int npts = 0, pd = 0, graze = 0, checked = 0;
  while (!vi_cont_done(c)) {
    int st = vi_cont_iterate(c);
    double p, vn, t, rho;
    int adm;
    if (st == VI_OK) {
      assert_int_equal(vi_cont_point(c, &p, &vn, &t, &rho, &adm), VI_OK);
      if (!npts++) assert_close(vn, FIG2_VN, 1e-12);
      if (rho < 0.9 && adm && checked < 3) {
        assert_close(vn, settled_vn(p), 1e-8);
        checked++;
      }
    }
    for (int i = 0; i < vi_cont_num_events(c); i++) {
      int type;
      double re, im;
      assert_int_equal(vi_cont_event(c, i, &type, &p, &vn, &re, &im, &adm), VI_OK);
      if (type == VI_CONT_PERIOD_DOUBLING && !pd++) {
        assert_close(re, -1.0, 1e-8);
        assert_close(im, 0.0, 1e-12);
        assert_close(p, 0.791491132172, 1e-9);
      }
      graze += type == VI_CONT_GRAZING;
    }
  }
  assert_int_equal(vi_cont_done(c), VI_CONT_END);
  assert_int_equal(npts, 21);
  assert_int_equal(checked, 3);
  assert_true(pd >= 1);
  assert_true(graze >= 1);
  vi_cont_destroy(&c);
  vi_model_destroy(&m);
}

/* Pseudo-arclength up from 0.9: every point's orbit closes the shooting
 * map at its parameter (residual at round-off, 1e-9). */
static void arclength_orbits(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2(), *at = vi_test_fig2();
  vi_cont *c = NULL;
  assert_int_equal(vi_cont_create(m, "forcing.omega", 1, VI_CONT_ARCLENGTH, &c), VI_OK);
  assert_int_equal(vi_cont_set_range(c, 1.2, 10), VI_OK);
  assert_int_equal(vi_cont_set_orbit(c, T0, X0, V0), VI_OK);
  int npts = 0;
  while (!vi_cont_done(c)) {
    if (vi_cont_iterate(c) != VI_OK) continue;
    double p, t, x[2], v[2], F[5];
    assert_int_equal(vi_cont_point(c, &p, NULL, NULL, NULL, NULL), VI_OK);
    assert_int_equal(vi_cont_orbit(c, &t, x, v), VI_OK);
    assert_int_equal(vi_model_set_param(at, "forcing.omega", p), VI_OK);
    assert_int_equal(vi_orbit_pnm_residual(at, 1, 1, &t, x, v, 2, F, NULL), VI_OK);
    for (int i = 0; i < 5; i++) assert_true(fabs(F[i]) < 1e-9);
    npts++;
  }
  assert_int_equal(vi_cont_done(c), VI_CONT_END);
  assert_true(npts >= 10);
  vi_cont_destroy(&c);
  vi_model_destroy(&m);
  vi_model_destroy(&at);
}

/* Fig. 2 with a second stop that the orbit never reaches put first: stop 0
 * holds mass 1 above x_1 = -5, stop 1 is the paper's on mass 2.  The orbit
 * impacts stop 1, so continuation must follow the impact on its own stop
 * (v_n = w_1.v, the shooting map with stop 1's law), not on stop 0: the
 * branch is Fig. 2's, point for point, in Omega and in stop 1's clearance
 * (stops[2].xs against stops[1].xs of the one-stop model, both with their
 * exact dF/dp). */
static vi_model *fig2_second_stop(void)
{
  vi_model *f = vi_test_fig2();
  const double a[2] = {0.5, 0.0}, W[4] = {-1.0, 0.0, 0.0, 1.0},
               xs[2] = {5.0, 0.1}, r[2] = {0.5, 0.7};
  vi_model *m = vi_test_model_stops(2, vi_model_mass(f), vi_model_damping(f),
                                    vi_model_stiffness(f), 0.9, a, NULL, 2, W,
                                    xs, r);
  vi_model_destroy(&f);
  return m;
}

static void branch(const vi_model *m, const char *key, int method, double to,
                   double *out, int cap, int *npts)
{
  vi_cont *c = NULL;
  assert_int_equal(vi_cont_create(m, key, 1, method, &c), VI_OK);
  assert_int_equal(vi_cont_set_range(c, to, 12), VI_OK);
  assert_int_equal(vi_cont_set_orbit(c, T0, X0, V0), VI_OK);
  *npts = 0;
  while (!vi_cont_done(c) && *npts < cap) {
    if (vi_cont_iterate(c) != VI_OK) continue;
    double *o = out + 4 * (size_t)*npts;
    assert_int_equal(vi_cont_point(c, &o[0], &o[1], &o[2], &o[3], NULL), VI_OK);
    (*npts)++;
  }
  vi_cont_destroy(&c);
}

static void impact_on_stop_1(void **state)
{
  (void)state;
  vi_model *one = vi_test_fig2(), *two = fig2_second_stop();
  const char *keys[2][2] = {{"forcing.omega", "forcing.omega"},
                            {"stops[1].xs", "stops[2].xs"}};
  const double to[2] = {0.7, 0.2};
  for (int q = 0; q < 2; q++) {
    double a[4 * 16] = {0}, b[4 * 16] = {0};
    int na, nb;
    int method = q ? VI_CONT_ARCLENGTH : VI_CONT_NATURAL;
    branch(one, keys[q][0], method, to[q], a, 16, &na);
    branch(two, keys[q][1], method, to[q], b, 16, &nb);
    assert_true(na >= 10);
    assert_int_equal(nb, na);
    assert_close(b[1], FIG2_VN, 1e-12); /* v_n of stop 1 at the start */
    for (int i = 0; i < na; i++)
      for (int j = 0; j < 4; j++) /* p, v_n, t, rho: the same orbits */
        assert_close(b[4 * i + j], a[4 * i + j], 1e-10 * fmax(1.0, fabs(a[4 * i + j])));
  }
  vi_model_destroy(&one);
  vi_model_destroy(&two);
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(natural_down),
                                     cmocka_unit_test(arclength_orbits),
                                     cmocka_unit_test(impact_on_stop_1)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
