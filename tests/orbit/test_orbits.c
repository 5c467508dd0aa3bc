/* test_orbits.c - P(n, m) orbits found directly (src/orbit/vi_orbit_pnm.c):
 * the exhaustive impact-phase scan, Newton, admissibility and the Floquet
 * multipliers from exact derivatives (closed-form transition and saltation
 * matrices), against independent 40-60 digit references
 * (tests/orbit/ref_fig2_p11.py, tests/orbit/ref_sdof_p11.py, tests/orbit/ref_fig2_floquet.py,
 * python3-mpmath), the SDOF oscillator's closed-form multipliers,
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
/* The one-period map of a 2-DOF model by central differences (h = 1e-6)
 * of exact-method runs, J [4 x 4] column-major in (x, v), on the section
 * half a period T after the orbit's impact at ti (state xi, vi before). */
static void differenced_map(const vi_model *m, double ti, const double *xi,
                            const double *vi, double T, double *J)
{
  double vp[2], z0[4], zp[4] = {0}, zm[4] = {0};
  assert_int_equal(vi_impact_apply(m, vi, vp, NULL, NULL), VI_OK);
  assert_int_equal(vi_flow_physical(m, ti, xi, vp, ti + T / 2, z0, z0 + 2), VI_OK);
  vi_sim *s = NULL;
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_sim_set_method(s, VI_METHOD_EXACT), VI_OK);
  for (int j = 0; j < 4; j++) {
    double h = 1e-6;
    for (int sg = -1; sg <= 1; sg += 2) {
      double zs[4];
      memcpy(zs, z0, sizeof zs);
      zs[j] += sg * h;
      assert_int_equal(vi_sim_set_initial(s, ti + T / 2, zs, zs + 2), VI_OK);
      assert_int_equal(vi_sim_run(s, ti + 1.5 * T), VI_OK);
      vi_sim_state(s, NULL, sg > 0 ? zp : zm, (sg > 0 ? zp : zm) + 2);
    }
    for (int i = 0; i < 4; i++) J[i + (size_t)4 * j] = (zp[i] - zm[i]) / (2 * h);
  }
  vi_sim_destroy(&s);
}

static void fig2_scan(void **state)
{
  (void)state;
  vi_model *m = vi_test_fig2();
  double t[8], x[16], v[16], re[4], im[4], gmax = 0;
  int found = 0, ok = 0;
  assert_int_equal(vi_orbit_p1_scan(m, 1, 720, t, x, v, 2, 8, &found), VI_OK);
  int adm = -1, count = 0;
  for (int i = 0; i < found; i++) {
    assert_int_equal(vi_orbit_pnm_admissible(m, 1, 1, &t[i], x + (size_t)2 * i, v + (size_t)2 * i, 2, &gmax, &ok), VI_OK);
    if (ok) {
      adm = i;
      count++;
    }
  }
  assert_int_equal(count, 1);
  size_t a2 = (size_t)2 * (size_t)(adm > 0 ? adm : 0), a = a2 / 2;
  /* tests/orbit/ref_fig2_p11.py: the flow is exact, so round-off level */
  assert_close(v[a2 + 1], 0.78766085255479729134, 1e-12);
  assert_close(fmod(t[a], 2 * M_PI / 0.9), 0.67857113423124466619, 1e-12);
  assert_close(x[a2 + 1], 0.1, 1e-14);                  /* on the stop */
  assert_close(x[a2], 0.09621605903588743049, 1e-12);
  assert_int_equal(vi_orbit_pnm_admissible(m, 1, 1, &t[a], x + a2, v + a2, 2,
                                           &gmax, &ok), VI_OK);
  assert_true(ok && gmax < -1e-3); /* the admissible orbit: clear of the stop */
  /* multipliers: det of the monodromy = r^2 exp(-tr(M^-1 C) T) (det of a
   * saltation matrix is r^2; Liouville for the flow), tr(M^-1 C) = 0.3 */
  assert_int_equal(vi_orbit_pnm_multipliers(m, 1, 1, &t[adm], x + (size_t)2 * adm, v + (size_t)2 * adm, 2, re, im), VI_OK);
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
  double T = 2 * M_PI / 0.9, Jm[16];
  differenced_map(m, t[adm], x + (size_t)2 * adm, v + (size_t)2 * adm, T, Jm);
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
 * transient only ever finds the stable one.  tests/orbit/ref_sdof_p11.py. */
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
 * energy analysis gets it (v_N and phase of tests/orbit/ref_sdof_p11.py); with
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
    int found = 0, best = 0;
    assert_int_equal(vi_orbit_p1_scan(m, 1, 2000, t, x, v, 1, 8, &found), VI_OK);
    assert_true(found >= 1);
    for (int j = 1; j < found && j < 8; j++)
      if (fabs(v[j] - slope * delta) < fabs(v[best] - slope * delta)) best = j;
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
    assert_int_equal(vi_orbit_pnm_admissible(m, 1, 1, &t[i], x + (size_t)3 * i, v + (size_t)3 * i, 3, &gmax, &ok), VI_OK);
    if (!ok && gmax > 1e-3) bad = i;
  }
  assert_true(bad >= 0);
  if (bad < 0) return; /* (not reached: cmocka's asserts are not noreturn to the lint) */
  double vp[3];
  assert_int_equal(vi_impact_apply(m, v + (size_t)3 * bad, vp, NULL, NULL), VI_OK);
  vi_sim *s = NULL;
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_sim_set_method(s, VI_METHOD_EXACT), VI_OK);
  assert_int_equal(vi_sim_set_initial(s, t[bad], x + (size_t)3 * bad, vp), VI_OK);
  assert_int_equal(vi_sim_run(s, t[bad] + 0.99 * 2 * M_PI / 0.8), VI_OK);
  assert_true(vi_sim_stat(s, VI_STAT_IMPACTS) >= 1);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
}

/* Floquet multipliers of Fig. 2 P(1,1) orbits against
 * tests/orbit/ref_fig2_floquet.py (60 digits, central differences of the
 * stroboscopic map at h = 1e-25 with the impact time found anew: no
 * saltation matrix): the paper's x_s = 0.1 and x_s = 0.6413, just past the
 * grazing of the free response (v_N = 1.5e-4, a multiplier of 6052).  The
 * derivatives are exact, so the multipliers carry only round-off
 * (amplified by 1 / v_N near grazing).  Then the same through vi_orbit
 * with CVODE (Adams): the derivatives are still exact, the orbit carries
 * the integration tolerance. */
static void fig2_floquet_reference(void **state)
{
  (void)state;
  const double T = 2 * M_PI / 0.9;
  static const struct {
    double xs, ti, vN, x1, v1, mre[4], mim[4];
  } ref[2] = {
      {0.1, 0.6785711342312446661871593, 0.7876608525547972913352433,
       0.09621605903588743048985405, 0.350895028519530632997108,
       {0.116686159216583746482, 0.116686159216583746482,
        0.02338564662802082552921, 0.02338564662802082552921},
       {0.7375326321473639436344, -0.7375326321473639436344,
        0.3281376664482915451069, -0.3281376664482915451069}},
      {0.6413, 3.445743526779776863914692, 0.0001474647115564261984697974,
       0.1260350962595802072312218, -0.04167070576716502107283747,
       {6052.272968775146976849, 0.0751998434823551904546,
        0.0751998434823551904546, 0.00004972512811868649049441},
       {0.0, -0.4414140813655959127781, 0.4414140813655959127781, 0.0}},
  };
  for (int c = 0; c < 2; c++) {
    const double M[4] = {1, 0, 0, 1}, K[4] = {2, -1, -1, 1},
                 C[4] = {0.2, -0.1, -0.1, 0.1}, a[2] = {0.5, 0}, w[2] = {0, 1};
    vi_model *m = vi_test_model(2, M, C, K, 0.9, a, NULL, w, ref[c].xs, 0.7);
    double t[8], x[16], v[16], re[4], im[4];
    int found = 0, k = -1;
    assert_int_equal(vi_orbit_p1_scan(m, 1, 2000, t, x, v, 2, 8, &found), VI_OK);
    for (int i = 0; i < found && i < 8; i++)
      if (fabs(v[2 * i + 1] - ref[c].vN) < 1e-3 * ref[c].vN) k = i;
    assert_true(k >= 0);
    if (k < 0) break; /* (not reached: for the lint, as above) */
    assert_close(fmod(t[k], T), ref[c].ti, 1e-12);
    assert_close(v[2 * k + 1], ref[c].vN, 1e-13);
    /* the derivatives alone: at the reference orbit (rounded to double),
     * then at the orbit the library found (Newton polished to round-off;
     * an error in v_N is amplified as 1 / v_N) */
    double tr_ = ref[c].ti, xr[2] = {ref[c].x1, ref[c].xs}, vr[2] = {ref[c].v1, ref[c].vN};
    for (int pass = 0; pass < 2; pass++) {
      if (pass == 0)
        assert_int_equal(vi_orbit_pnm_multipliers(m, 1, 1, &tr_, xr, vr, 2, re, im), VI_OK);
      else
        assert_int_equal(vi_orbit_pnm_multipliers(m, 1, 1, &t[k], x + (size_t)2 * k, v + (size_t)2 * k, 2, re, im), VI_OK);
      double worst = 0.0;
      for (int j = 0; j < 4; j++) { /* match each reference to the nearest */
        double d = HUGE_VAL;
        for (int i = 0; i < 4; i++)
          d = fmin(d, hypot(re[i] - ref[c].mre[j], im[i] - ref[c].mim[j]));
        /* relative to the multiplier, absolute below 1 */
        worst = fmax(worst, d / fmax(1.0, hypot(ref[c].mre[j], ref[c].mim[j])));
      }
      print_message("x_s %g, %s orbit: exact multipliers' largest error %.2e\n",
                    ref[c].xs, pass ? "library's" : "reference", worst);
      assert_true(worst < (pass ? 1e-15 / ref[c].vN : 1e-11));
    }
    if (c == 0) { /* vi_orbit through CVODE */
      vi_orbit *o = NULL;
      double fre[4], fim[4];
      assert_int_equal(vi_orbit_create(m, &o), VI_OK);
      assert_int_equal(vi_orbit_set_method(o, VI_METHOD_ADAMS), VI_OK);
      assert_int_equal(vi_orbit_set_tolerances(o, 1e-12, 1e-14), VI_OK);
      assert_int_equal(vi_orbit_find(o), VI_OK);
      assert_int_equal(vi_orbit_multipliers(o, fre, fim), VI_OK);
      double wc = 0.0;
      for (int j = 0; j < 4; j++) {
        double d = HUGE_VAL;
        for (int i = 0; i < 4; i++)
          d = fmin(d, hypot(fre[i] - ref[c].mre[j], fim[i] - ref[c].mim[j]));
        wc = fmax(wc, d);
      }
      print_message("x_s %g: CVODE (rtol 1e-12) orbit's multipliers' error %.2e\n",
                    ref[c].xs, wc);
      assert_true(wc < 1e-8);
      vi_orbit_destroy(&o);
    }
    vi_model_destroy(&m);
  }
}

/* The SDOF impact oscillator x'' + c x' + k x = F(t) = a cos(Omega t) + f0,
 * stop x <= x_s, has closed-form P(1,1) multipliers.  With the impact at
 * t_i, approach velocity V > 0, h = c/2, mu = sqrt(k - h^2):
 *  - the saltation matrix (g = (1, 0), R = diag(1, -r),
 *    f- = (V, A0 - cV), f+ = (-rV, A0 + crV), A0 = F(t_i) - k x_s) is
 *      S = R + (f+ - R f-) g^T / V = [[-r, 0], [(1 + r) A0 / V, -r]]
 *    (the damping terms cancel: a+ + r a- = (1 + r) A0);
 *  - Phi(T) = e^{-hT} [[cos + h sin/mu, sin/mu], [-k sin/mu, cos - h sin/mu]]
 *    (arguments mu T);
 * so the monodromy Phi(T) S has
 *   tr  = e^{-hT} (-2 r cos(mu T) + (1 + r) (A0 / V) sin(mu T) / mu),
 *   det = r^2 e^{-cT},
 * and the multipliers are the roots of l^2 - tr l + det.  Checked on
 * chatter.yaml's two orbits and on the branch born at grazing (V = s delta,
 * delta = 1e-6 and 1e-4 past grazing: multipliers ~ 1 / V, up to 1e6),
 * where finite differences of the map lose everything. */
static void sdof_floquet_closed_form(void **state)
{
  (void)state;
  static const struct {
    double c, k, a, f0, Om, xs, r;
  } sc[3] = {
      {0.02, 0.1, 0.6, 0.3, 1.0, 0.0, 0.5},                    /* chatter */
      {0.1, 1.0, 0.3, 0.0, 0.7, -1e-6, 0.8},                   /* grazing - 1e-6 */
      {0.1, 1.0, 0.3, 0.0, 0.7, -1e-4, 0.8},                   /* grazing - 1e-4 */
  };
  int checked = 0;
  for (int q = 0; q < 3; q++) {
    double c = sc[q].c, k = sc[q].k, Om = sc[q].Om, r = sc[q].r;
    double xs = sc[q].xs;
    if (q > 0) xs += sc[q].a / hypot(k - Om * Om, c * Om); /* free amplitude */
    vi_model *m = vi_test_sdof(1.0, c, k, sc[q].a, sc[q].f0, Om, xs, r);
    double t[8], x[8], v[8], Mo[4], T = 2 * M_PI / Om;
    int found = 0;
    assert_int_equal(vi_orbit_p1_scan(m, 1, 2000, t, x, v, 1, 8, &found), VI_OK);
    assert_true(found >= 1);
    for (int i = 0; i < found && i < 8; i++) {
      double h = c / 2, mu = sqrt(k - h * h), e = exp(-h * T);
      double A0 = sc[q].a * cos(Om * t[i]) + sc[q].f0 - k * xs;
      double tr = e * (-2 * r * cos(mu * T) + (1 + r) * A0 / v[i] * sin(mu * T) / mu);
      double det = r * r * exp(-c * T);
      assert_int_equal(vi_orbit_pnm_monodromy(m, 1, 1, NULL, &t[i], &x[i], &v[i], 1, Mo), VI_OK);
      double trm = Mo[0] + Mo[3], detm = Mo[0] * Mo[3] - Mo[1] * Mo[2];
      double disc = tr * tr - 4 * det, big = disc > 0 ? 0.5 * (fabs(tr) + sqrt(disc)) : sqrt(det);
      print_message("case %d orbit %d: V %.3e, |tr| %.3e, largest |multiplier| %.6g, "
                    "tr error %.1e, det error %.1e (relative)\n", q, i, v[i], fabs(tr),
                    big, fabs(trm - tr) / fmax(1.0, fabs(tr)), fabs(detm - det) / det);
      /* round-off of Phi S: eps times the largest entry of S (~1/V) */
      assert_close(trm, tr, 1e-12 * fmax(1.0, fabs(tr)));
      assert_close(detm, det, 1e-12 * det * fmax(1.0, fabs(tr)));
      checked++;
    }
    vi_model_destroy(&m);
  }
  assert_true(checked >= 4);
}

/* Non-proportional damping: the state-transition matrix comes from Pade
 * scaling and squaring, not from the modes.  The Fig. 2 chain with a
 * damper on mass 1 only (C = diag(0.2, 0)).  Liouville: det of the
 * monodromy = r^2 exp(-tr(M^-1 C) T); and the multipliers agree with
 * central differences of the exact simulation's stroboscopic map (which
 * integrates with vi_general.c's eigen-solution; h = 1e-6: error ~1e-9). */
static void nonprop_floquet(void **state)
{
  (void)state;
  const double M[4] = {1, 0, 0, 1}, K[4] = {2, -1, -1, 1}, C[4] = {0.2, 0, 0, 0},
               a[2] = {0.5, 0}, w[2] = {0, 1};
  vi_model *m = vi_test_model(2, M, C, K, 0.9, a, NULL, w, 0.1, 0.7);
  assert_int_equal(vi_model_is_proportional(m), 0);
  double t[8], x[16], v[16], Mo[16], T = 2 * M_PI / 0.9, re[4], im[4];
  int found = 0, k = -1, ok;
  assert_int_equal(vi_orbit_p1_scan(m, 1, 720, t, x, v, 2, 8, &found), VI_OK);
  for (int i = 0; i < found && i < 8 && k < 0; i++) {
    assert_int_equal(vi_orbit_pnm_admissible(m, 1, 1, &t[i], x + (size_t)2 * i, v + (size_t)2 * i, 2, NULL, &ok), VI_OK);
    if (ok) k = i;
  }
  assert_true(k >= 0);
  if (k < 0) return; /* (not reached: for the lint, as above) */
  assert_int_equal(vi_orbit_pnm_monodromy(m, 1, 1, NULL, &t[k], x + (size_t)2 * k, v + (size_t)2 * k, 2, Mo), VI_OK);
  assert_int_equal(vi_orbit_pnm_multipliers(m, 1, 1, &t[k], x + (size_t)2 * k, v + (size_t)2 * k, 2, re, im), VI_OK);
  double det = 1.0;
  for (int i = 0; i < 4; i++) det *= hypot(re[i], im[i]);
  assert_close(det, 0.49 * exp(-0.2 * T), 1e-13);
  /* central differences of the exact simulation's map, section half a
   * period after the impact */
  double J[16];
  differenced_map(m, t[k], x + (size_t)2 * k, v + (size_t)2 * k, T, J);
  /* trace and the sum of principal 2 x 2 minors: the first two
   * coefficients of the characteristic polynomial */
  double tr = 0, trx = 0, m2 = 0, m2x = 0;
  for (int i = 0; i < 4; i++) {
    tr += J[i + 4 * i];
    trx += Mo[i + 4 * i];
    for (int j = i + 1; j < 4; j++) {
      m2 += J[i + 4 * i] * J[j + 4 * j] - J[i + 4 * j] * J[j + 4 * i];
      m2x += Mo[i + 4 * i] * Mo[j + 4 * j] - Mo[i + 4 * j] * Mo[j + 4 * i];
    }
  }
  print_message("non-proportional: tr %.15g (differenced map %.15g), minors %.15g (%.15g)\n",
                trx, tr, m2x, m2);
  assert_close(tr, trx, 1e-8);
  assert_close(m2, m2x, 1e-8);
  vi_model_destroy(&m);
}

/* The parameter derivative of the orbit conditions (continuation's last
 * column): exact for Omega, x_s and r, against central differences of the
 * residual over rebuilt models (h = 1e-6: truncation ~1e-12, round-off
 * ~1e-10).  At a point off the orbit too, so that nothing vanishes by
 * periodicity. */
static void dparam_exact(void **state)
{
  (void)state;
  const double M[4] = {1, 0, 0, 1}, K[4] = {2, -1, -1, 1},
               C[4] = {0.2, -0.1, -0.1, 0.1}, a[2] = {0.5, 0}, w[2] = {0, 1};
  const double p0[3] = {0.9, 0.1, 0.7}; /* Omega, x_s, r */
  double t = 0.7, x[2] = {0.09, 0.1}, v[2] = {0.35, 0.8};
  for (int par = 0; par < 3; par++) {
    double dF[5], Fp[5] = {0}, Fm[5] = {0}, h = 1e-6;
    vi_model *m = vi_test_model(2, M, C, K, p0[0], a, NULL, w, p0[1], p0[2]);
    assert_int_equal(vi_orbit_pnm_dparam(m, 1, 1, NULL, &t, x, v, 2, par, 0, dF), VI_OK);
    vi_model_destroy(&m);
    for (int sg = -1; sg <= 1; sg += 2) {
      double p[3] = {p0[0], p0[1], p0[2]};
      p[par] += sg * h;
      m = vi_test_model(2, M, C, K, p[0], a, NULL, w, p[1], p[2]);
      assert_int_equal(vi_orbit_pnm_residual(m, 1, 1, &t, x, v, 2, sg > 0 ? Fp : Fm, NULL), VI_OK);
      vi_model_destroy(&m);
    }
    double worst = 0;
    for (int i = 0; i < 5; i++) worst = fmax(worst, fabs(dF[i] - (Fp[i] - Fm[i]) / (2 * h)));
    print_message("parameter %d: |dF - central difference| %.2e\n", par, worst);
    assert_true(worst < 1e-8);
  }
  /* an unknown parameter or stop is refused */
  vi_model *m = vi_test_fig2();
  double dF[5];
  assert_int_equal(vi_orbit_pnm_dparam(m, 1, 1, NULL, &t, x, v, 2, 7, 0, dF), VI_ERR_ARG);
  assert_int_equal(vi_orbit_pnm_dparam(m, 1, 1, NULL, &t, x, v, 2, VI_ORBIT_PARAM_R, 1, dF), VI_ERR_ARG);
  vi_model_destroy(&m);
}

/* x'' + c x' + x = a cos(Omega t) between two stops x <= d and -x <= d. */
static vi_model *clearance_sdof(double c, double a, double Om, double d,
                                double r0, double r1)
{
  const double M = 1, K = 1, b = 0, f0 = 0, w0 = 1, w1 = -1;
  vi_model *m = NULL;
  assert_int_equal(vi_model_create(1, &m), VI_OK);
  assert_int_equal(vi_model_set_mass(m, &M, 1), VI_OK);
  assert_int_equal(vi_model_set_stiffness(m, &K, 1), VI_OK);
  assert_int_equal(vi_model_set_damping(m, &c, 1), VI_OK);
  assert_int_equal(vi_model_set_forcing(m, Om, &a, &b, &f0), VI_OK);
  assert_int_equal(vi_model_add_stop(m, &w0, d, r0), VI_OK);
  assert_int_equal(vi_model_add_stop(m, &w1, d, r1), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  return m;
}

/* The test's own closed-form flow of x'' + c x' + x = a cos(Omega t)
 * (underdamped), from (x0, v0) at t0 to t1. */
static void sdof_flow(double c, double a, double Om, double t0, double x0,
                      double v0, double t1, double *x1, double *v1)
{
  double h = c / 2, mu = sqrt(1 - h * h), den = (1 - Om * Om) * (1 - Om * Om) + c * c * Om * Om;
  double P = a * (1 - Om * Om) / den, Q = a * c * Om / den; /* xp = P cos + Q sin */
  double xp0 = P * cos(Om * t0) + Q * sin(Om * t0), vp0 = Om * (Q * cos(Om * t0) - P * sin(Om * t0));
  double u = x0 - xp0, ud = v0 - vp0, tau = t1 - t0, e = exp(-h * tau);
  double cs = cos(mu * tau), sn = sin(mu * tau);
  double uu = e * (u * cs + (ud + h * u) * sn / mu);
  double uud = e * (ud * cs - (h * ud + u) * sn / mu);
  *x1 = P * cos(Om * t1) + Q * sin(Om * t1) + uu;
  *v1 = Om * (Q * cos(Om * t1) - P * sin(Om * t1)) + uud;
}

/* Issue 13: orbits with several stops.  A symmetric two-sided clearance
 * (SDOF, stops at +-0.3, r = 0.8 on both) settles on a symmetric P(1,2)
 * orbit: one impact on each stop, half a period apart, equal approach
 * speeds, mirrored states.  It is checked against the test's own closed
 * form: from the impact on stop 0 the free flow over T/2 lands on the
 * mirror image (-d, -V) (the forcing changes sign over T/2).  The energy
 * balance closes per stop (WB 11 for each: by symmetry the approach work
 * to each stop equals what it takes) and r_rec = r per stop (WB 13);
 * det of the monodromy = r^4 e^{-cT}.  Newton over the impact sequence
 * (vi_orbit_pnm_solve_stops) from a rough seed finds the same orbit to
 * round-off.  With unequal restitutions (0.8, 0.6) the orbit is not
 * symmetric: each stop's RE - IE is the energy carried between the stops,
 * and they sum to zero. */
static void two_sided_clearance(void **state)
{
  (void)state;
  const double c = 0.1, a = 0.5, Om = 0.9, d = 0.3, r = 0.8, T = 2 * M_PI / Om;
  vi_model *m = clearance_sdof(c, a, Om, d, r, r);
  vi_orbit *o = NULL;
  assert_int_equal(vi_orbit_create(m, &o), VI_OK);
  assert_int_equal(vi_orbit_find(o), VI_OK);
  int pn, pm, cnt, sp[8];
  assert_int_equal(vi_orbit_classify(o, &pn, &pm), VI_OK);
  assert_int_equal(pn, 1);
  assert_int_equal(pm, 2);
  double t[8], vn[8], x[8], v[8];
  assert_int_equal(vi_orbit_impacts(o, &cnt, t, sp, vn, x, v, 1), VI_OK);
  assert_int_equal(cnt, 2);
  assert_int_equal(sp[0] + sp[1], 1); /* one on each stop */
  /* the exact method (several stops) delivers round-off; the ledger's
   * quadrature ~1e-13 */
  assert_close(t[1] - t[0], T / 2, 1e-11);
  assert_close(vn[0], vn[1], 1e-11);
  assert_close(x[0], -x[1], 1e-12);
  int k0 = sp[0] == 0 ? 0 : 1; /* the impact on stop 0: x = d, v = V */
  double V = vn[k0], x1, v1;
  sdof_flow(c, a, Om, t[k0], d, -r * V, t[k0] + T / 2, &x1, &v1);
  print_message("symmetric P(1,2): V = %.12f, half-period image (%.3g, %.3g) off "
                "the mirror\n", V, x1 + d, v1 + V);
  assert_close(x1, -d, 1e-11);
  assert_close(v1, -V, 1e-11);
  for (int k = 0; k < 2; k++) {
    int n1;
    double KE, RE, IE, rr, cl;
    assert_int_equal(vi_orbit_stop_balance(o, k, &n1, &KE, &RE, &IE, &rr, &cl), VI_OK);
    print_message("stop %d: RE %.12f IE %.12f r_rec %.12f closure %.2e\n", k, RE, IE, rr, cl);
    assert_int_equal(n1, 1);
    assert_close(KE, 0.5 * V * V, 1e-12);
    assert_close(IE, 0.5 * V * V * (1 - r * r), 1e-12);
    assert_true(cl < 1e-10);
    assert_close(rr, r, 1e-10);
  }
  assert_int_equal(vi_orbit_stop_balance(o, 2, NULL, NULL, NULL, NULL, NULL, NULL), VI_ERR_ARG);
  assert_int_equal(vi_orbit_balance(o, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL),
                   VI_ERR_STATE); /* the P(1,1) getters */
  double re[2], im[2];
  assert_int_equal(vi_orbit_multipliers(o, re, im), VI_OK);
  double det = hypot(re[0], im[0]) * hypot(re[1], im[1]);
  assert_close(det, pow(r, 4) * exp(-c * T), 1e-12);
  /* Newton over the impact sequence, closed-form flow, from a rough seed */
  double ts[2] = {t[0] + 0.05, t[1] - 0.03}, xs_[2] = {x[0], x[1]},
         vs[2] = {v[0] * 1.1, v[1] * 0.9}, re2[2], im2[2], gmax;
  int ok, it;
  assert_int_equal(vi_orbit_pnm_solve_stops(m, 1, 2, sp, ts, xs_, vs, 1, 0.0, &it), VI_OK);
  print_message("Newton over the impact sequence: %d iterations, |t - t_orbit| %.2e, "
                "|vn - V| %.2e\n", it, fabs(ts[0] - t[0]), fabs(sp[0] ? -vs[0] - V : vs[0] - V));
  assert_close(ts[1] - ts[0], T / 2, 1e-12);
  assert_close(vs[0], -vs[1], 1e-12);
  assert_close(ts[0], t[0], 1e-10);
  assert_int_equal(vi_orbit_pnm_admissible_stops(m, 1, 2, sp, ts, xs_, vs, 1, &gmax, &ok), VI_OK);
  assert_int_equal(ok, 1);
  assert_int_equal(vi_orbit_pnm_multipliers_stops(m, 1, 2, sp, ts, xs_, vs, 1, re2, im2), VI_OK);
  for (int i = 0; i < 2; i++) /* a conjugate pair: compare the set */
    assert_close(hypot(re2[i], im2[i]), hypot(re[i], im[i]), 1e-10);
  assert_close(fmax(re2[0], re2[1]), fmax(re[0], re[1]), 1e-10);
  /* the wrong stop sequence is refused (no approach) or not admissible */
  int bad[2] = {sp[0], sp[0]};
  assert_int_equal(vi_orbit_pnm_admissible_stops(m, 1, 2, bad, ts, xs_, vs, 1, NULL, &ok), VI_OK);
  assert_int_equal(ok, 0);
  bad[0] = 2;
  assert_int_equal(vi_orbit_pnm_solve_stops(m, 1, 2, bad, ts, xs_, vs, 1, 0.0, NULL), VI_ERR_ARG);
  vi_orbit_destroy(&o);
  vi_model_destroy(&m);

  /* unequal restitutions: per-stop balances shift, their sum closes */
  m = clearance_sdof(c, a, Om, d, 0.8, 0.6);
  assert_int_equal(vi_orbit_create(m, &o), VI_OK);
  assert_int_equal(vi_orbit_find(o), VI_OK);
  assert_int_equal(vi_orbit_classify(o, &pn, &pm), VI_OK);
  assert_int_equal(pm, 2);
  double sum = 0, kes = 0, shift = 0;
  for (int k = 0; k < 2; k++) {
    double KE, RE, IE, FE, DE, XE;
    assert_int_equal(vi_orbit_stop_balance(o, k, NULL, &KE, &RE, &IE, NULL, NULL), VI_OK);
    assert_int_equal(vi_orbit_stop_modal_balance(o, k, &FE, &DE, &XE), VI_OK);
    assert_close(FE - DE - XE, RE, 1e-14);
    sum += RE - IE;
    kes += KE;
    shift = fmax(shift, fabs(RE - IE) / KE);
  }
  print_message("r = (0.8, 0.6): per-stop |RE - IE| / KE up to %.3f, their sum %.2e\n",
                shift, sum / kes);
  assert_true(shift > 0.1);
  assert_true(fabs(sum) < 1e-10 * kes);
  vi_orbit_destroy(&o);
  vi_model_destroy(&m);
}

/* Where the closed-form flow does not apply, vi_orbit integrates with
 * CVODE and still takes exact derivatives (the transition matrix by Pade
 * scaling and squaring needs only M, C, K).  The undamped oscillator forced
 * at its resonance (x'' + x = a cos t: secular growth, the closed form
 * refuses it) against a stop at x_s = 0 settles on a P(1,2) orbit (also a
 * one-stop P(1, m) the analysis now covers).  Checks from physics: the
 * monodromy's determinant is r^4 (Liouville with C = 0: each saltation
 * matrix has det r^2); with x_s = 0 the equations are homogeneous in
 * (x, a), so the orbit scales with a and its multipliers do not change;
 * the balance closes over the period (RE = IE) and recovers r (WB 13 with
 * both impacts). */
static void resonant_cvode_floquet(void **state)
{
  (void)state;
  const double r = 0.8, amp[2] = {0.05, 0.5};
  double mre[2][2], mim[2][2];
  for (int c = 0; c < 2; c++) {
    vi_model *m = vi_test_sdof(1.0, 0.0, 1.0, amp[c], 0.0, 1.0, 0.0, r);
    vi_orbit *o = NULL;
    int pn, pm, cnt, sp[8];
    assert_int_equal(vi_orbit_create(m, &o), VI_OK);
    assert_int_equal(vi_orbit_set_direct_search(o, 0), VI_OK);
    assert_int_equal(vi_orbit_find(o), VI_OK);
    assert_int_equal(vi_orbit_classify(o, &pn, &pm), VI_OK);
    assert_int_equal(pn, 1);
    assert_int_equal(pm, 2);
    assert_int_equal(vi_orbit_impacts(o, &cnt, NULL, sp, NULL, NULL, NULL, 1), VI_OK);
    assert_int_equal(cnt, 2);
    assert_int_equal(sp[0] + sp[1], 0);
    assert_int_equal(vi_orbit_multipliers(o, mre[c], mim[c]), VI_OK);
    double det = hypot(mre[c][0], mim[c][0]) * hypot(mre[c][1], mim[c][1]);
    double KE, RE, IE, rr, cl;
    assert_int_equal(vi_orbit_stop_balance(o, 0, &cnt, &KE, &RE, &IE, &rr, &cl), VI_OK);
    print_message("a = %g, CVODE orbit: multipliers %.10g%+.10gi, %.10g%+.10gi; "
                  "det - r^4 %.2e; closure %.2e, r recovered %.10f\n", amp[c],
                  mre[c][0], mim[c][0], mre[c][1], mim[c][1], det - pow(r, 4), cl, rr);
    assert_int_equal(cnt, 2);
    assert_close(det, pow(r, 4), 1e-9);
    assert_true(cl < 1e-7);
    assert_close(rr, r, 1e-7);
    vi_orbit_destroy(&o);
    vi_model_destroy(&m);
  }
  for (int i = 0; i < 2; i++) { /* the same multipliers, as a set */
    double best = HUGE_VAL;
    for (int j = 0; j < 2; j++)
      best = fmin(best, hypot(mre[0][i] - mre[1][j], mim[0][i] - mim[1][j]));
    assert_true(best < 1e-8);
  }
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
      cmocka_unit_test(fig2_floquet_reference),
      cmocka_unit_test(sdof_floquet_closed_form),
      cmocka_unit_test(nonprop_floquet),
      cmocka_unit_test(dparam_exact),
      cmocka_unit_test(two_sided_clearance),
      cmocka_unit_test(resonant_cvode_floquet),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
