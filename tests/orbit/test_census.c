/* test_census.c - the orbit census (vi_census.h) against physics:
 * - Fig. 2 (MODEL.md section 6): exactly one P(1,1) orbit, admissible and
 *   stable, whose impact velocity and phase are those of the 30-digit
 *   closed-form solution (tests/orbit/ref_fig2_p11.py), multipliers equal
 *   to the shooting ones (vi_orbit_pnm_multipliers) and to Liouville's
 *   determinant r^2 exp(-tr(M^-1 C) T);
 * - chatter.yaml's SDOF oscillator: both P(1,1) orbits (one unstable, only
 *   the scan reaches it) with the 50-digit v_N (tests/orbit/ref_sdof_p11.py)
 *   and the closed-form trace and determinant of the monodromy;
 * - rattle.yaml's symmetric clearance, P(1,2): the mirror pair (stops
 *   swapped, impact times half a period apart, equal v_N and multipliers);
 * - a P(2,2) census does not list a P(1,1) orbit traversed twice;
 * - a monitor sees each new orbit once, in order, and can stop the census;
 *   a second run gives the same census (duplicates dropped). */
#include <math.h>
#include <stdlib.h>

#include "vi_testutil.h"
#include "vibroimpact/vi_census.h"

typedef struct seen {
  int calls, last;
} seen;

static int count_orbits(const vi_census *c, int index, void *user)
{
  seen *s = user;
  assert_int_equal(index, s->calls); /* each new orbit once, in order */
  assert_int_equal(vi_census_count(c), index + 1);
  s->calls++;
  s->last = index;
  return 0;
}

static void fig2_p11(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  vi_census *c = NULL;
  seen s = {0, -1};
  assert_int_equal(vi_census_create(m, 1, 1, &c), VI_OK);
  assert_int_equal(vi_census_set_monitor(c, count_orbits, &s, NULL), VI_OK);
  assert_int_equal(vi_census_run(c), VI_OK);
  assert_int_equal(vi_census_count(c), 1);
  assert_int_equal(s.calls, 1);
  double t, x[2], v[2], vn, re[4], im[4], gmax, sre[4], sim[4];
  int stop = -1, stable, adm;
  assert_int_equal(vi_census_orbit(c, 0, &t, x, v, 2, &stop, &vn), VI_OK);
  assert_int_equal(vi_census_stability(c, 0, re, im, &stable, &adm, &gmax), VI_OK);
  double T = 2 * M_PI / 0.9;
  /* tests/orbit/ref_fig2_p11.py: the flow is exact, so round-off level */
  assert_close(vn, 0.78766085255479729134, 1e-12);
  assert_close(vn, v[1], 0.0); /* w = e_2 */
  assert_close(t, 0.67857113423124466619, 1e-12); /* in [0, T) */
  assert_close(x[1], 0.1, 1e-14);                  /* on the stop */
  assert_close(x[0], 0.09621605903588743049, 1e-12);
  assert_int_equal(stop, 0);
  assert_true(stable && adm && gmax < -1e-3);
  /* the multipliers are the shooting ones, and Liouville's determinant */
  assert_int_equal(vi_orbit_pnm_multipliers(m, 1, 1, &t, x, v, 2, sre, sim), VI_OK);
  double det = 1, mx = 0;
  for (int i = 0; i < 4; i++) {
    assert_close(re[i], sre[i], 0.0);
    assert_close(im[i], sim[i], 0.0);
    det *= hypot(re[i], im[i]);
    mx = fmax(mx, hypot(re[i], im[i]));
  }
  assert_close(det, 0.49 * exp(-0.3 * T), 1e-12);
  assert_true(mx < 1.0);
  /* a second run starts afresh: the same single orbit, seen once more */
  s.calls = 0;
  assert_int_equal(vi_census_run(c), VI_OK);
  assert_int_equal(vi_census_count(c), 1);
  assert_int_equal(s.calls, 1);
  double t2;
  assert_int_equal(vi_census_orbit(c, 0, &t2, NULL, NULL, 0, NULL, NULL), VI_OK);
  assert_close(t2, t, 0.0);
  vi_census_destroy(&c);
  vi_model_destroy(&m);
}

/* x'' + 0.02 x' + 0.1 x = 0.6 cos t + 0.3, stop x <= 0, r = 0.5 */
static void sdof_both_orbits(void **state)
{
  (void)state;
  const double c = 0.02, k = 0.1, r = 0.5, T = 2 * M_PI;
  vi_model *m = vi_test_sdof(1.0, c, k, 0.6, 0.3, 1.0, 0.0, r);
  vi_census *cs = NULL;
  assert_int_equal(vi_census_create(m, 1, 1, &cs), VI_OK);
  assert_int_equal(vi_census_run(cs), VI_OK);
  assert_int_equal(vi_census_count(cs), 2);
  int nst = 0;
  for (int i = 0; i < 2; i++) {
    double t, x, v, vn, re[2], im[2];
    int stable, adm;
    assert_int_equal(vi_census_orbit(cs, i, &t, &x, &v, 1, NULL, &vn), VI_OK);
    assert_int_equal(vi_census_stability(cs, i, re, im, &stable, &adm, NULL), VI_OK);
    assert_true(adm);
    /* ref_sdof_p11.py (50 digits) */
    int u = t < 1.0; /* the unstable orbit impacts earlier in the period */
    assert_close(t, u ? 0.68405233563160207582 : 2.0694948525182891832, 1e-11);
    assert_close(vn, u ? 1.6134056745831746208 : 2.1562495000219778789, 1e-11);
    assert_int_equal(stable, !u);
    nst += stable;
    /* the closed-form monodromy (test_orbits.c, sdof_floquet_closed_form):
     * tr = e^{-hT}(-2 r cos(mu T) + (1 + r)(A0 / V) sin(mu T) / mu),
     * det = r^2 e^{-cT}, A0 = F(t_i) - k x_s */
    double h = c / 2, mu = sqrt(k - h * h), A0 = 0.6 * cos(t) + 0.3;
    double tr = exp(-h * T) * (-2 * r * cos(mu * T) + (1 + r) * A0 / vn * sin(mu * T) / mu);
    assert_close(re[0] + re[1], tr, 1e-11);
    assert_close(re[0] * re[1] - im[0] * im[1], r * r * exp(-c * T), 1e-11);
  }
  assert_int_equal(nst, 1);
  vi_census_destroy(&cs);
  vi_model_destroy(&m);
}

/* rattle.yaml at Omega = 1.2: x'' + 0.1 x' + x = 0.5 cos(1.2 t) between
 * x = +-0.3 (r = 0.8).  The system is symmetric under (x, t) -> (-x, t +
 * T/2), so P(1,2) orbits come in mirror pairs. */
static void rattle_mirror_pair(void **state)
{
  (void)state;
  const double wm = -1.0, Om = 1.2, T = 2 * M_PI / Om;
  vi_model *m = NULL;
  assert_int_equal(vi_model_create(1, &m), VI_OK);
  const double one = 1.0, cc = 0.1, a = 0.5;
  assert_int_equal(vi_model_set_mass(m, &one, 1), VI_OK);
  assert_int_equal(vi_model_set_damping(m, &cc, 1), VI_OK);
  assert_int_equal(vi_model_set_stiffness(m, &one, 1), VI_OK);
  assert_int_equal(vi_model_set_forcing(m, Om, &a, NULL, NULL), VI_OK);
  assert_int_equal(vi_model_set_stop(m, &one, 0.3, 0.8), VI_OK);
  assert_int_equal(vi_model_add_stop(m, &wm, 0.3, 0.8), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  vi_census *c = NULL;
  assert_int_equal(vi_census_create(m, 1, 2, &c), VI_OK);
  assert_int_equal(vi_census_run(c), VI_OK);
  assert_int_equal(vi_census_count(c), 2);
  double t[2][2], vn[2][2], re[2][2], im[2][2];
  int stop[2][2], stable, adm;
  for (int i = 0; i < 2; i++) {
    assert_int_equal(vi_census_orbit(c, i, t[i], NULL, NULL, 0, stop[i], vn[i]), VI_OK);
    assert_int_equal(vi_census_stability(c, i, re[i], im[i], &stable, &adm, NULL), VI_OK);
    assert_true(stable && adm);
    assert_int_equal(stop[i][0] + stop[i][1], 1); /* one impact on each */
    assert_true(vn[i][0] > 0 && vn[i][1] > 0);
  }
  /* the mirror image: impact j of one orbit is impact j of the other on the
   * other stop, half a period later (mod T), with the same v_N */
  for (int j = 0; j < 2; j++) {
    assert_int_equal(stop[0][j], 1 - stop[1][j]);
    double d = fmod(fabs(t[0][j] - t[1][j]), T);
    assert_close(d, T / 2, 1e-9);
    assert_close(vn[0][j], vn[1][j], 1e-9);
  }
  for (int i = 0; i < 2; i++)
    assert_close(hypot(re[0][i], im[0][i]), hypot(re[1][i], im[1][i]), 1e-9);
  /* det of the monodromy: r^2 per impact, e^{-cT} from the flow */
  double det = re[0][0] * re[0][1] - im[0][0] * im[0][1];
  assert_close(det, pow(0.8, 4) * exp(-0.1 * T), 1e-10);
  vi_census_destroy(&c);
  vi_model_destroy(&m);
}

/* A P(2,2) census lists primitive orbits only.  On the lightly damped
 * chain (Fig. 2 with c = 0.02, r = 0.8, Omega = 0.5, x_s = 1.2) transients
 * settle on a stable P(1,1) orbit; their states repeat with period 2T as
 * well, and Newton keeps that seed, so the P(2,2) census used to list the
 * P(1,1) orbit traversed twice (both impacts at the same phase, the same
 * v_N), which `curves --orbit 2,2` then followed. */
static void p22_not_p11_twice(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  assert_int_equal(vi_model_set_param(m, "damping.scale", 0.2), VI_OK);
  assert_int_equal(vi_model_set_param(m, "stop.r", 0.8), VI_OK);
  assert_int_equal(vi_model_set_param(m, "forcing.omega", 0.5), VI_OK);
  assert_int_equal(vi_model_set_param(m, "stop.xs", 1.2), VI_OK);
  double T = 2 * M_PI / 0.5, t[2], v[4], vn[2];
  vi_census *c = NULL;
  int stable = 0, adm = 0;
  /* the P(1,1) orbit the transients reach */
  assert_int_equal(vi_census_create(m, 1, 1, &c), VI_OK);
  assert_int_equal(vi_census_run(c), VI_OK);
  int found = 0;
  for (int i = 0; i < vi_census_count(c); i++) {
    assert_int_equal(vi_census_stability(c, i, NULL, NULL, &stable, &adm, NULL), VI_OK);
    found |= stable && adm;
  }
  assert_true(found);
  vi_census_destroy(&c);
  /* no P(2,2) orbit is it twice: impacts T apart with equal velocities */
  assert_int_equal(vi_census_create(m, 2, 2, &c), VI_OK);
  assert_int_equal(vi_census_run(c), VI_OK);
  for (int i = 0; i < vi_census_count(c); i++) {
    assert_int_equal(vi_census_orbit(c, i, t, NULL, v, 2, NULL, vn), VI_OK);
    double lag = fmod(fabs(t[1] - t[0]), 2 * T);
    int twice = fabs(lag - T) < 1e-7 * T && fabs(vn[1] - vn[0]) < 1e-6 * fabs(vn[0]);
    print_message("P(2,2) orbit %d: t1 - t0 = %.10g T, v_N %.10g %.10g\n", i, lag / T, vn[0],
                  vn[1]);
    assert_false(twice);
  }
  vi_census_destroy(&c);
  vi_model_destroy(&m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(fig2_p11),
      cmocka_unit_test(sdof_both_orbits),
      cmocka_unit_test(rattle_mirror_pair),
      cmocka_unit_test(p22_not_p11_twice),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
