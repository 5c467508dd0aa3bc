/* test_orbits.c - P(n, m) orbits found directly (src/vi_orbit_pnm.c):
 * the exhaustive impact-phase scan, Newton, admissibility and the Floquet
 * multipliers from saltation matrices, against independent 40-50 digit
 * references (tests/ref_fig2_p11.py, tests/ref_sdof_p11.py, python3-mpmath),
 * Liouville's formula for the monodromy determinant, and simulation. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vi_testutil.h"

static double modulus(double re, double im) { return hypot(re, im); }

static int by_modulus(const void *a, const void *b)
{
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* Fig. 2: one P(1,1) orbit, admissible and stable, at the reference. */
static void fig2_scan(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  double t[8], x[16], v[16], re[4], im[4], gmax;
  int found = 0, ok = 0;
  assert_int_equal(vi_orbit_p1_scan(m, 1, 720, t, x, v, 2, 8, &found), VI_OK);
  int adm = -1, count = 0;
  for (int i = 0; i < found; i++) {
    assert_int_equal(vi_orbit_pnm_admissible(m, 1, 1, &t[i], x + 2 * i, v + 2 * i, 2, &gmax, &ok), VI_OK);
    if (ok) {
      adm = i;
      count++;
    }
  }
  assert_int_equal(count, 1);
  /* tests/ref_fig2_p11.py: the flow is exact, so round-off level */
  assert_close(v[2 * adm + 1], 0.78766085255479729134, 1e-12);
  assert_close(fmod(t[adm], 2 * M_PI / 0.9), 0.67857113423124466619, 1e-12);
  assert_close(x[2 * adm + 1], 0.1, 1e-14);                  /* on the stop */
  assert_close(x[2 * adm], 0.09621605903588743049, 1e-12);
  assert_true(gmax < -1e-3);                                  /* clear of the stop */
  /* multipliers: det of the monodromy = r^2 exp(-tr(M^-1 C) T) (det of a
   * saltation matrix is r^2; Liouville for the flow), tr(M^-1 C) = 0.3 */
  assert_int_equal(vi_orbit_pnm_multipliers(m, 1, 1, &t[adm], x + 2 * adm, v + 2 * adm, 2, re, im), VI_OK);
  double det = 1, mod[4];
  for (int i = 0; i < 4; i++) {
    mod[i] = modulus(re[i], im[i]);
    det *= mod[i];
  }
  assert_close(det, 0.49 * exp(-0.3 * 2 * M_PI / 0.9), 1e-12);
  qsort(mod, 4, sizeof(double), by_modulus);
  assert_true(mod[3] < 1.0); /* stable: the transient settles on it */
  /* central differences of the stroboscopic map (the simulation, exact
   * method, h = 1e-6) agree to their own error, ~1e-6 here; the section
   * is half a period after the impact */
  double T = 2 * M_PI / 0.9, vp[2], z0[4], zp[4], zm[4], Jm[16];
  assert_int_equal(vi_impact_apply(m, v + 2 * adm, vp, NULL, NULL), VI_OK);
  assert_int_equal(vi_flow_physical(m, t[adm], x + 2 * adm, vp, t[adm] + T / 2, z0, z0 + 2), VI_OK);
  vi_sim *s = NULL;
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_sim_set_method(s, VI_METHOD_EXACT), VI_OK);
  for (int j = 0; j < 4; j++) {
    double h = 1e-6;
    for (int sg = -1; sg <= 1; sg += 2) {
      double zs[4];
      memcpy(zs, z0, sizeof zs);
      zs[j] += sg * h;
      assert_int_equal(vi_sim_set_initial(s, t[adm] + T / 2, zs, zs + 2), VI_OK);
      assert_int_equal(vi_sim_run(s, t[adm] + 1.5 * T), VI_OK);
      vi_sim_state(s, NULL, sg > 0 ? zp : zm, (sg > 0 ? zp : zm) + 2);
    }
    for (int i = 0; i < 4; i++) Jm[i + 4 * j] = (zp[i] - zm[i]) / (2 * h);
  }
  vi_sim_destroy(&s);
  /* the characteristic polynomial's coefficients: trace and determinant */
  double tr = Jm[0] + Jm[5] + Jm[10] + Jm[15], trx = 0;
  for (int i = 0; i < 4; i++) trx += re[i];
  assert_close(tr, trx, 1e-5);
  /* vi_orbit reports the same multipliers after a transient */
  vi_orbit *o = NULL;
  double fre[4], fim[4], fmod_[4];
  assert_int_equal(vi_orbit_create(m, &o), VI_OK);
  assert_int_equal(vi_orbit_find(o), VI_OK);
  assert_int_equal(vi_orbit_multipliers(o, fre, fim), VI_OK);
  for (int i = 0; i < 4; i++) fmod_[i] = modulus(fre[i], fim[i]);
  qsort(fmod_, 4, sizeof(double), by_modulus);
  for (int i = 0; i < 4; i++) assert_close(mod[i], fmod_[i], 1e-9);
  vi_orbit_destroy(&o);
  vi_model_destroy(&m);
}

/* share/scenes/chatter.yaml: a stable and an unstable P(1,1) orbit; the
 * transient only ever finds the stable one.  tests/ref_sdof_p11.py. */
static void sdof_two_orbits(void **state)
{
  (void)state;
  vi_model *m = vi_test_sdof(1.0, 0.02, 0.1, 0.6, 0.3, 1.0, 0.0, 0.5);
  double t[8], x[8], v[8], re[2], im[2], gmax;
  int found = 0, ok;
  assert_int_equal(vi_orbit_p1_scan(m, 1, 720, t, x, v, 1, 8, &found), VI_OK);
  assert_int_equal(found, 2);
  int u = fmod(t[0], 2 * M_PI) < 1.0 ? 0 : 1, s = 1 - u;
  assert_close(fmod(t[u], 2 * M_PI), 0.68405233563160207582, 1e-11);
  assert_close(v[u], 1.6134056745831746208, 1e-11);
  assert_close(fmod(t[s], 2 * M_PI), 2.0694948525182891832, 1e-11);
  assert_close(v[s], 2.1562495000219778789, 1e-11);
  for (int i = 0; i < 2; i++) {
    assert_int_equal(vi_orbit_pnm_admissible(m, 1, 1, &t[i], &x[i], &v[i], 1, &gmax, &ok), VI_OK);
    assert_int_equal(ok, 1);
  }
  /* the unstable one: real multipliers 2.2128..., 0.0996...; the
   * reference takes them by 50-digit finite differences of the impact map */
  assert_int_equal(vi_orbit_pnm_multipliers(m, 1, 1, &t[u], &x[u], &v[u], 1, re, im), VI_OK);
  double hi = fmax(re[0], re[1]), lo = fmin(re[0], re[1]);
  assert_close(hi, 2.21284535663875, 1e-10);
  assert_close(lo, 0.099635450761658, 1e-10);
  assert_close(im[0], 0.0, 1e-12);
  assert_int_equal(vi_orbit_pnm_multipliers(m, 1, 1, &t[s], &x[s], &v[s], 1, re, im), VI_OK);
  assert_close(re[0], 0.201695343061645, 1e-10);
  assert_close(fabs(im[0]), 0.424024566696069, 1e-10);
  vi_model_destroy(&m);
}

/* vi_orbit_find's direct search: on chatter.yaml the transient from rest
 * does not settle on a P(1,1) orbit, but the stable one exists and the
 * energy analysis gets it (v_N and phase of tests/ref_sdof_p11.py); with
 * the search off it reports what the transient did. */
static void direct_search(void **state)
{
  (void)state;
  vi_model *m = vi_test_sdof(1.0, 0.02, 0.1, 0.6, 0.3, 1.0, 0.0, 0.5);
  vi_orbit *o = NULL;
  int pn, pm, tn, tm, by;
  double ph, vN, rr;
  assert_int_equal(vi_orbit_create(m, &o), VI_OK);
  assert_int_equal(vi_orbit_find(o), VI_OK);
  vi_orbit_classify(o, &pn, &pm);
  vi_orbit_search_info(o, &tn, &tm, &by);
  assert_int_equal(pn, 1);
  assert_int_equal(pm, 1);
  assert_int_equal(by, 1);
  assert_false(tn == 1 && tm == 1);
  assert_int_equal(vi_orbit_balance(o, NULL, &ph, &vN, NULL, NULL, NULL, &rr, NULL), VI_OK);
  assert_close(vN, 2.1562495000219778789, 1e-9);
  assert_close(ph, 2.0694948525182891832, 1e-9);
  assert_close(rr, 0.5, 1e-8); /* WB 12 on the orbit found directly */
  assert_int_equal(vi_orbit_set_direct_search(o, 0), VI_OK);
  assert_int_equal(vi_orbit_find(o), VI_OK);
  vi_orbit_classify(o, &pn, &pm);
  assert_int_equal(pn, tn);
  assert_int_equal(pm, tm);
  assert_int_equal(vi_orbit_balance(o, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL), VI_ERR_STATE);
  vi_orbit_destroy(&o);
  vi_model_destroy(&m);
}

/* The P(1,1) branch born at grazing of x'' + c x' + k x = a cos(Omega t):
 * with the stop a distance delta inside the free amplitude A = a |H|, the
 * orbit hits at v_N = s delta + O(delta^2), where (linearising the free
 * response about its maximum, x_h = A - A Omega^2 tau^2 / 2, and solving
 * the periodicity of the homogeneous correction over one period)
 *   s = det(Phi(T) - I) / (Phi_12(T) (1 + r)),
 * Phi the damped oscillator's transition matrix.  Two distances show the
 * linear growth; the scan finds the branch near grazing.  s > 0 (the
 * branch lies inside the free amplitude) because det(Phi - I) > 0 and
 * sin(omega_d T) > 0 at Omega = 0.7. */
static void grazing_branch(void **state)
{
  (void)state;
  const double c = 0.1, k = 1.0, a = 0.3, Om = 0.7, r = 0.8;
  double T = 2 * M_PI / Om, sg = c / 2, wd = sqrt(k - sg * sg), e = exp(-sg * T);
  double p11 = e * (cos(wd * T) + sg / wd * sin(wd * T)), p12 = e * sin(wd * T) / wd,
         p21 = -e * k * sin(wd * T) / wd, p22 = e * (cos(wd * T) - sg / wd * sin(wd * T));
  double slope = ((p11 - 1) * (p22 - 1) - p12 * p21) / (p12 * (1 + r));
  double A = a / hypot(k - Om * Om, c * Om);
  assert_true(slope > 0);
  for (int i = 1; i <= 2; i++) {
    double delta = i * 1e-6;
    vi_model *m = vi_test_sdof(1.0, c, k, a, 0.0, Om, A - delta, r);
    double t[8], x[8], v[8];
    int found = 0, best = -1;
    assert_int_equal(vi_orbit_p1_scan(m, 1, 2000, t, x, v, 1, 8, &found), VI_OK);
    for (int j = 0; j < found && j < 8; j++)
      if (best < 0 || fabs(v[j] - slope * delta) < fabs(v[best] - slope * delta)) best = j;
    assert_true(best >= 0);
    print_message("delta %g: v_N %.10g, slope * delta %.10g\n", delta, v[best], slope * delta);
    /* the next order is relative O(delta): 4e-6 here */
    assert_close(v[best], slope * delta, 2e-5 * slope * delta);
    vi_model_destroy(&m);
  }
}

/* Newton from a rough seed converges to the same orbit (quadratically: a
 * handful of iterations), for P(1,1) and for a P(2,3) orbit of Fig. 2 at
 * Omega = 0.85 seeded from a transient. */
static void newton_from_seed(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  double t = 0.6, x[2] = {0.05, 0.1}, v[2] = {0.3, 0.7};
  int it = 0;
  assert_int_equal(vi_orbit_pnm_solve(m, 1, 1, &t, x, v, 2, 0.0, &it), VI_OK);
  assert_true(it <= 12);
  assert_close(v[1], 0.78766085255479729134, 1e-12);
  assert_close(fmod(t, 2 * M_PI / 0.9), 0.67857113423124466619, 1e-12);
  vi_model_destroy(&m);
}

/* An inadmissible P(1,1) of share/scenes/nonproportional.yaml: its gap
 * rises above the stop between impacts, and a simulation from its
 * post-impact state indeed meets the stop before one period is over. */
static void inadmissible(void **state)
{
  (void)state;
  vi_model *m = vi_test_nonprop3(0.05, NULL);
  double t[8], x[24], v[24], gmax;
  int found = 0, ok = 1;
  assert_int_equal(vi_orbit_p1_scan(m, 1, 720, t, x, v, 3, 8, &found), VI_OK);
  assert_true(found >= 1);
  int bad = -1;
  for (int i = 0; i < found; i++) {
    assert_int_equal(vi_orbit_pnm_admissible(m, 1, 1, &t[i], x + 3 * i, v + 3 * i, 3, &gmax, &ok), VI_OK);
    if (!ok && gmax > 1e-3) bad = i;
  }
  assert_true(bad >= 0);
  double vp[3];
  assert_int_equal(vi_impact_apply(m, v + 3 * bad, vp, NULL, NULL), VI_OK);
  vi_sim *s = NULL;
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_sim_set_method(s, VI_METHOD_EXACT), VI_OK);
  assert_int_equal(vi_sim_set_initial(s, t[bad], x + 3 * bad, vp), VI_OK);
  assert_int_equal(vi_sim_run(s, t[bad] + 0.99 * 2 * M_PI / 0.8), VI_OK);
  assert_true(vi_sim_stat(s, VI_STAT_IMPACTS) >= 1);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(fig2_scan),
      cmocka_unit_test(sdof_two_orbits),
      cmocka_unit_test(newton_from_seed),
      cmocka_unit_test(direct_search),
      cmocka_unit_test(grazing_branch),
      cmocka_unit_test(inadmissible),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
