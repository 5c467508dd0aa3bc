/* test_identify.c - model parameters from recorded data (src/study/
 * vi_identify.c) on synthetic recordings made outside the library
 * (tests/study/gen_identify_data.py: SciPy DOP853 with event location; one
 * settled period at 64 samples, repeated here over P periods, with
 * Gaussian noise of a fraction of the peak-to-peak and an unknown phase).
 *
 * The tolerances come from what the data hold (issue 22): on the 4-mode
 * beam a change of 0.01 in r moves the tip by ~1.3e-5 RMS against a
 * peak-to-peak of 0.1, so 50 periods at 0.2 % noise determine r to about
 * +-0.003 and 20 periods at 1 % to about +-0.02.  The 95 % intervals must
 * cover the truth in >= 8 of 10 noise seeds (binomial: P(<= 7 of 10 |
 * 0.95) = 1.2 %, fixed seeds).  Measured here: the stderr implies 6.4e-6
 * RMS per 0.01 in r (half the estimate), so the stderr is 0.0055
 * at 0.2 % over 50 periods and 0.043 at 1 % over 20 periods. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "vi_testutil.h"

#ifndef VI_IDENT_DATA
#define VI_IDENT_DATA "tests/study/data"
#endif

typedef struct rec {
  int ns;
  double T0, t[2048], x[2048], v[2048], a[2048]; /* a: NaN without */
} rec;

/* The generator's CSV: "# T0 = ..." then t,x,v rows. */
static void load(const char *name, rec *r)
{
  char path[512], line[256];
  snprintf(path, sizeof path, "%s/%s", VI_IDENT_DATA, name);
  FILE *f = fopen(path, "r");
  assert_non_null(f);
  r->ns = 0;
  r->T0 = NAN;
  while (fgets(line, sizeof line, f)) {
    if (!strncmp(line, "# T0 = ", 7)) r->T0 = strtod(line + 7, NULL);
    if (line[0] == '#' || line[0] == 't') continue;
    assert_true(r->ns < 2048);
    char *e1, *e2, *e3;
    r->t[r->ns] = strtod(line, &e1);
    assert_true(*e1 == ',');
    r->x[r->ns] = strtod(e1 + 1, &e2);
    assert_true(*e2 == ',');
    r->v[r->ns] = strtod(e2 + 1, &e3);
    assert_true(e3 > e2 + 1);
    r->a[r->ns] = *e3 == ',' ? strtod(e3 + 1, NULL) : NAN;
    r->ns++;
  }
  fclose(f);
  assert_true(isfinite(r->T0));
}

/* One period of 64 samples repeated over `periods`, noise sigma. */
typedef struct series {
  int ns;
  double *t, *x, *v;
} series;

static series repeat(const rec *r, int periods, double sigma, unsigned long seed)
{
  series s;
  double T = r->t[1] * 64.0;
  s.ns = r->ns * periods;
  s.t = malloc(sizeof(double) * (s.ns + 1));
  s.x = malloc(sizeof(double) * (s.ns + 1));
  s.v = malloc(sizeof(double) * (s.ns + 1));
  gsl_rng *g = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(g, seed);
  for (int p = 0; p < periods; p++)
    for (int i = 0; i < r->ns; i++) {
      int k = p * r->ns + i;
      s.t[k] = r->t[i] + p * T;
      s.x[k] = r->x[i] + (sigma > 0 ? gsl_ran_gaussian(g, sigma) : 0.0);
      s.v[k] = r->v[i];
    }
  gsl_rng_free(g);
  return s;
}

static void series_free(series *s)
{
  free(s->t);
  free(s->x);
  free(s->v);
}

static double peak_to_peak(const rec *r)
{
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (int i = 0; i < r->ns; i++) {
    lo = fmin(lo, r->x[i]);
    hi = fmax(hi, r->x[i]);
  }
  return hi - lo;
}

/* vi_identify_run, its message shown where it fails. */
static void run_ok(vi_identify *id)
{
  int st = vi_identify_run(id);
  if (st) fprintf(stderr, "identify: %s\n", vi_identify_errmsg(id));
  assert_int_equal(st, VI_OK);
}

/* Fit r (from r0) of the model m to s; the results. */
typedef struct fit {
  double p[2], se[2], lo[2], hi[2], t0, rms, noise;
  int flags[2], conv, iters;
} fit;

static fit fit_rg(const vi_model *m, const series *s, double r0, int with_v,
                  int global)
{
  vi_identify *id = NULL;
  fit f;
  assert_int_equal(vi_identify_create(m, 1, &id), VI_OK);
  assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_R, 0, r0, 0, 1), VI_OK);
  assert_int_equal(vi_identify_set_global(id, global), VI_OK);
  assert_int_equal(vi_identify_set_data(id, s->ns, s->t, s->x, with_v ? s->v : NULL), VI_OK);
  run_ok(id);
  assert_int_equal(vi_identify_params(id, f.p, f.se, f.lo, f.hi, f.flags), VI_OK);
  assert_int_equal(vi_identify_shift(id, &f.t0, NULL), VI_OK);
  assert_int_equal(vi_identify_summary(id, &f.conv, &f.iters, &f.rms, &f.noise,
                                       NULL, NULL, NULL), VI_OK);
  vi_identify_destroy(&id);
  return f;
}

static fit fit_r(const vi_model *m, const series *s, double r0, int with_v)
{
  return fit_rg(m, s, r0, with_v, 1);
}

/* Distance of two shifts modulo the period T. */
static double phase_err(double a, double b, double T)
{
  double d = fmod(a - b, T);
  if (d < 0) d += T;
  return fmin(d, T - d);
}

/* Noise-free: the model reproduces the independent simulation to its
 * tolerance, r to 1e-6, the phase to 1e-6 of the period. */
static void beam_exact(void **state)
{
  (void)state;
  static rec r;
  load("beam4.csv", &r);
  double T = 2 * M_PI / 0.85;
  vi_model *m = vi_test_beam(4, 0.05, 0.75);
  series s = repeat(&r, 3, 0.0, 1);
  fit f = fit_r(m, &s, 0.6, 0);
  assert_true(f.conv);
  assert_close(f.p[0], 0.75, 1e-6);
  assert_true(f.rms < 1e-8); /* DOP853 at rtol 1e-12 against the closed form */
  assert_true(phase_err(f.t0, r.T0, T) < 1e-6 * T);
  assert_close(peak_to_peak(&r), 0.1, 0.02); /* the scale the noise refers to */
  /* the WB 12 route on the fitted orbit with the recorded v_N: with
   * exact data and the right model it gives the same r (WB 11 closure) */
  vi_identify *id = NULL;
  double r12, vN, KE, RE, x1[1], t1[1] = {0.0};
  assert_int_equal(vi_identify_create(m, 1, &id), VI_OK);
  assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_R, 0, 0.7, 0, 1), VI_OK);
  assert_int_equal(vi_identify_set_data(id, s.ns, s.t, s.x, s.v), VI_OK);
  assert_int_equal(vi_identify_run(id), VI_OK);
  assert_int_equal(vi_identify_energy_restitution(id, &r12, &vN, &KE, &RE), VI_OK);
  assert_close(r12, 0.75, 1e-6);
  assert_true(vN > 0.0 && RE > 0.0 && RE < KE);
  assert_int_equal(vi_identify_response(id, 1, t1, x1, NULL), VI_OK);
  assert_close(x1[0], r.x[0], 1e-9);
  vi_identify_destroy(&id);
  series_free(&s);
  vi_model_destroy(&m);
}

/* 0.2 % noise over 50 periods: r within 0.01 (in fact within 3 stderr),
 * stderr about 0.003; and the intervals' coverage over 10 seeds.  The
 * fits here are local, from 0.6 (the statistics of the one minimum near
 * the truth; at 1 % noise a second one, P(1,2) near r = 0.3, explains
 * some seeds as well: beam_not_unique, and vi_bench_identify for the
 * global stage over seeds and starts). */
static void beam_noise(void **state)
{
  (void)state;
  static rec r;
  load("beam4.csv", &r);
  vi_model *m = vi_test_beam(4, 0.05, 0.75);
  double pp = peak_to_peak(&r);
  struct { int periods; double level, se_lo, se_hi; } cs[2] = {
      {50, 0.002, 0.003, 0.008}, {20, 0.01, 0.02, 0.06}};
  for (int c = 0; c < 2; c++) {
    int cover = 0;
    for (unsigned long seed = 1; seed <= 10; seed++) {
      series s = repeat(&r, cs[c].periods, cs[c].level * pp, seed);
      fit f = fit_rg(m, &s, 0.6, 0, 0);
      assert_true(f.conv);
      if (c == 0) assert_close(f.p[0], 0.75, 0.01);
      assert_true(f.se[0] > cs[c].se_lo && f.se[0] < cs[c].se_hi);
      cover += f.lo[0] <= 0.75 && 0.75 <= f.hi[0];
      /* the residual is the noise: the model is right */
      assert_close(f.rms / (cs[c].level * pp), 1.0, 0.05);
      assert_close(f.noise / (cs[c].level * pp), 1.0, 0.25);
      series_free(&s);
    }
    assert_true(cover >= 8);
  }
  vi_model_destroy(&m);
}

/* r and x_s together, and the exact derivative against a builder's
 * differenced one (the same optimum and errors). */
/* The 4-mode beam (vi_test_beam) forced at om with restitution r,
 * clearance xs and base amplitude b, built as a builder must: a status,
 * never an abort. */
static int beam_model(double om, double r, double xs, double b, vi_model **out)
{
  double M[16], C[16], K[16], w[4], g[4], a[4];
  vi_build_cantilever(4, 1.0, 0.05, 1.0, M, C, K, 4, w, g);
  for (int j = 0; j < 4; j++) a[j] = -b * g[j];
  vi_model *m = NULL;
  int st = vi_model_create(4, &m);
  if (!st) st = vi_model_set_mass(m, M, 4);
  if (!st) st = vi_model_set_damping(m, C, 4);
  if (!st) st = vi_model_set_stiffness(m, K, 4);
  if (!st) st = vi_model_set_forcing(m, om, a, NULL, NULL);
  if (!st) st = vi_model_set_stop(m, w, xs, r);
  if (!st) st = vi_model_setup(m);
  if (st) vi_model_destroy(&m);
  *out = m;
  return st;
}

typedef struct bctx { int calls; } bctx;
static int build_r(const double *p, void *user, vi_model **out)
{
  ((bctx *)user)->calls++;
  return beam_model(0.85, p[0], p[1], 0.01, out);
}

static void beam_r_xs(void **state)
{
  (void)state;
  static rec r;
  load("beam4.csv", &r);
  vi_model *m = vi_test_beam(4, 0.0495, 0.7);
  double pp = peak_to_peak(&r);
  series s = repeat(&r, 50, 0.002 * pp, 11);
  double p[2][2], se[2][2], R[4];
  bctx bc = {0};
  for (int way = 0; way < 2; way++) {
    vi_identify *id = NULL;
    assert_int_equal(vi_identify_create(m, 2, &id), VI_OK);
    int kr = way ? VI_IDENTIFY_OTHER : VI_IDENTIFY_R;
    int kx = way ? VI_IDENTIFY_OTHER : VI_IDENTIFY_XS;
    if (way) assert_int_equal(vi_identify_set_builder(id, build_r, &bc, NULL), VI_OK);
    assert_int_equal(vi_identify_set_global(id, 0), VI_OK); /* one minimum, two ways */
    assert_int_equal(vi_identify_set_param(id, 0, kr, 0, 0.7, 0, 1), VI_OK);
    assert_int_equal(vi_identify_set_param(id, 1, kx, 0, 0.0495, 0.03, 0.07), VI_OK);
    assert_int_equal(vi_identify_set_data(id, s.ns, s.t, s.x, NULL), VI_OK);
    run_ok(id);
    assert_int_equal(vi_identify_params(id, p[way], se[way], NULL, NULL, NULL), VI_OK);
    assert_int_equal(vi_identify_correlation(id, R, 2), VI_OK);
    assert_close(R[0], 1.0, 1e-12);
    assert_close(R[1], R[2], 1e-12);
    assert_true(fabs(p[way][0] - 0.75) < 3 * se[way][0]);
    assert_true(fabs(p[way][1] - 0.05) < 3 * se[way][1]);
    vi_identify_destroy(&id);
  }
  assert_true(bc.calls > 0);
  /* differences of 1e-6 relative against the exact sensitivities */
  for (int j = 0; j < 2; j++) {
    assert_close(p[1][j], p[0][j], 1e-4 * se[0][j]);
    assert_close(se[1][j] / se[0][j], 1.0, 1e-4);
  }
  series_free(&s);
  vi_model_destroy(&m);
}

/* Non-uniform samples with the velocity column. */
static void beam_jitter(void **state)
{
  (void)state;
  static rec r;
  load("beam4_jitter.csv", &r);
  vi_model *m = vi_test_beam(4, 0.05, 0.75);
  gsl_rng *g = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(g, 5);
  for (int i = 0; i < r.ns; i++) r.x[i] += gsl_ran_gaussian(g, 1e-4);
  gsl_rng_free(g);
  series s = {r.ns, r.t, r.x, r.v};
  fit f = fit_r(m, &s, 0.6, 0);
  assert_true(f.conv);
  assert_true(fabs(f.p[0] - 0.75) < 3 * f.se[0]);
  /* no 4th differences of non-uniform samples, but the 10 periods folded
   * onto one: each sample against its neighbours in phase (640 samples:
   * the median's spread is about 5 %) */
  print_message("jitter: noise estimate %.4g of 1e-4\n", f.noise);
  assert_close(f.noise / 1e-4, 1.0, 0.15);
  assert_close(f.rms / 1e-4, 1.0, 0.1);
  vi_model_destroy(&m);
}

/* r and the base excitation's amplitude b (a = -b g) by a builder. */
static int build_rb(const double *p, void *user, vi_model **out)
{
  (void)user;
  return beam_model(0.85, p[0], 0.05, p[1], out);
}

/* Omega, r and the base amplitude by a builder. */
static int build_orb(const double *p, void *user, vi_model **out)
{
  (void)user;
  return beam_model(p[0], p[1], 0.05, p[2], out);
}

/* A naive amplitude: the beam's base amplitude (truth 0.01) from 0.005
 * with no bounds, and from 0.03 within bounds [0.001, 0.1], r from 0.5,
 * 10 periods at 0.1 % noise.  The recording's P(1,1) exists, stable and
 * admissible, only for bases within about 5 % of 0.01, which no start of
 * the +-50 % grid about 0.005 (nor of 4 or 8 times it), nor of five even
 * starts over the bounds, reaches; the searches ended instead on a P(1,2)
 * orbit at r = 0.31, base 0.0100, whose residual (1.03 noise levels) the
 * noise explains, and which was reported as the only answer (the P(1,1)
 * leaves 0.97, 79 noise variances less over the 640 samples).  The search
 * about that minimum's values finds the P(1,1): r and b within 3
 * standard errors of the truth, the residual at the noise. */
static void beam_base_naive(void **state)
{
  (void)state;
  static rec r;
  load("beam4.csv", &r);
  vi_model *m = vi_test_beam(4, 0.05, 0.75);
  series s = repeat(&r, 10, 0.001 * peak_to_peak(&r), 3);
  static const double b0[2] = {0.005, 0.03}, blo[2] = {-HUGE_VAL, 0.001},
                      bhi[2] = {HUGE_VAL, 0.1};
  for (int k = 0; k < 2; k++) {
    vi_identify *id = NULL;
    double p[2], se[2], rms, nz;
    int n, mm;
    assert_int_equal(vi_identify_create(m, 2, &id), VI_OK);
    assert_int_equal(vi_identify_set_builder(id, build_rb, NULL, NULL), VI_OK);
    assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_OTHER, 0, 0.5, 0, 1), VI_OK);
    assert_int_equal(vi_identify_set_param(id, 1, VI_IDENTIFY_OTHER, 0, b0[k], blo[k],
                                           bhi[k]), VI_OK);
    assert_int_equal(vi_identify_set_data(id, s.ns, s.t, s.x, NULL), VI_OK);
    run_ok(id);
    assert_int_equal(vi_identify_params(id, p, se, NULL, NULL, NULL), VI_OK);
    assert_int_equal(vi_identify_summary(id, NULL, NULL, &rms, &nz, NULL, &n, &mm), VI_OK);
    print_message("base from %g in [%g, %g]: r %.5f +- %.1e, b %.7f +- %.1e, P(%d,%d), "
                  "rms / noise %.3f\n", b0[k], blo[k], bhi[k], p[0], se[0], p[1], se[1],
                  n, mm, rms / nz);
    assert_true(n == 1 && mm == 1);
    assert_true(fabs(p[0] - 0.75) < 3 * se[0]);
    assert_true(fabs(p[1] - 0.01) < 3 * se[1]);
    assert_true(rms < 1.05 * nz);
    /* the range every stage searched: with no bounds, 8 times the start
     * either way (the stage that found the P(1,2)); within bounds, them */
    double lo[2], hi[2];
    assert_int_equal(vi_identify_search_range(id, lo, hi), VI_OK);
    print_message("  searched r %g to %g, b %g to %g\n", lo[0], hi[0], lo[1], hi[1]);
    assert_true(lo[0] == 0.0 && hi[0] == 1.0);
    assert_close(lo[1], k ? 0.001 : 0.005 / 8, 1e-12);
    assert_close(hi[1], k ? 0.1 : 0.005 * 8, 1e-12);
    vi_identify_destroy(&id);
  }
  series_free(&s);
  vi_model_destroy(&m);
}

/* Outliers (vi_identify_outliers): 50 periods of the beam at 0.2 % noise
 * (3200 samples; a Gaussian sample lies beyond 6 noise levels once in
 * 5e8, so none is expected: 6e-6 for the record).  One sample moved by 100
 * noise levels is the one named, at 100 noise levels to within its own
 * noise and the fit's pull on it (4 levels), the others' RMS
 * the noise's (the noise level being estimated: within 10 %); moved by a
 * constant 10 noise levels over its last 40 samples, all 40 are counted
 * and the worst two returned farthest first. */
static void outliers(void **state)
{
  (void)state;
  static rec r;
  load("beam4.csv", &r);
  vi_model *m = vi_test_beam(4, 0.05, 0.75);
  double sig = 0.002 * peak_to_peak(&r);
  series s = repeat(&r, 50, sig, 4);
  for (int way = 0; way < 3; way++) {
    if (way == 1) s.x[1234] += 100.0 * sig;
    if (way == 2) {
      s.x[1234] -= 100.0 * sig;
      for (int i = s.ns - 40; i < s.ns; i++) s.x[i] += 10.0 * sig;
    }
    vi_identify *id = NULL;
    assert_int_equal(vi_identify_create(m, 1, &id), VI_OK);
    assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_R, 0, 0.6, 0, 1), VI_OK);
    assert_int_equal(vi_identify_set_data(id, s.ns, s.t, s.x, NULL), VI_OK);
    run_ok(id);
    int idx[2] = {-1, -1}, n = -1;
    double z[2] = {NAN, NAN}, rest = NAN, nz;
    assert_int_equal(vi_identify_summary(id, NULL, NULL, NULL, &nz, NULL, NULL, NULL), VI_OK);
    assert_int_equal(vi_identify_outliers(id, 6.0, 2, idx, z, &n, &rest), VI_OK);
    print_message("outliers, case %d: %d (sample %d at %.2f, %d at %.2f), the others' RMS "
                  "%.3f of the noise %.3g (%.3g)\n", way, n, idx[0], z[0], idx[1], z[1],
                  rest, nz, sig);
    assert_close(nz / sig, 1.0, 0.1);
    assert_close(rest, 1.0, 0.1);
    if (way == 0) assert_int_equal(n, 0);
    if (way == 1) {
      assert_int_equal(n, 1);
      assert_int_equal(idx[0], 1234);
      assert_true(fabs(z[0] * nz / sig - 100.0) < 4.0);
    }
    if (way == 2) {
      assert_int_equal(n, 40);
      assert_true(idx[0] >= s.ns - 40 && idx[1] >= s.ns - 40 && z[0] >= z[1] && z[1] > 6.0);
    }
    vi_identify_destroy(&id);
  }
  series_free(&s);
  vi_model_destroy(&m);
}

/* Fig. 2 (the 2-mass chain): r from 0.5 at 0.2 % noise over 20 periods. */
static void fig2(void **state)
{
  (void)state;
  static rec r;
  load("fig2.csv", &r);
  vi_model *m = vi_test_fig2();
  series s = repeat(&r, 20, 0.002 * peak_to_peak(&r), 3);
  fit f = fit_r(m, &s, 0.5, 0);
  assert_true(f.conv);
  assert_true(fabs(f.p[0] - 0.7) < 3 * f.se[0] && f.se[0] < 0.01);
  assert_true(phase_err(f.t0, r.T0, 2 * M_PI / 0.9) < 0.01);
  /* by vi_param.h keys: r (exact) and the unknown forcing amplitude a_1
   * (differenced), from 0.6 and 0.32: the global stage's starts cover
   * [0, 1] x [0.3, 0.7] */
  vi_identify *id = NULL;
  double p[2], se[2];
  int conv;
  assert_int_equal(vi_identify_create(m, 2, &id), VI_OK);
  assert_int_equal(vi_identify_set_param_key(id, 0, "stop.r", NAN, NAN), VI_OK);
  assert_int_equal(vi_identify_set_param_key(id, 1, "forcing.a[1]", 0.3, 0.7), VI_OK);
  assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_R, 0, 0.6, 0, 1), VI_OK);
  assert_int_equal(vi_identify_set_param(id, 1, VI_IDENTIFY_OTHER, 0, 0.32, 0.3, 0.7), VI_OK);
  assert_int_equal(vi_identify_set_data(id, s.ns, s.t, s.x, NULL), VI_OK);
  assert_int_equal(vi_identify_run(id), VI_OK);
  assert_int_equal(vi_identify_params(id, p, se, NULL, NULL, NULL), VI_OK);
  assert_int_equal(vi_identify_summary(id, &conv, NULL, NULL, NULL, NULL, NULL, NULL), VI_OK);
  assert_true(conv);
  assert_true(fabs(p[0] - 0.7) < 3 * se[0] && fabs(p[1] - 0.5) < 3 * se[1]);
  assert_true(se[1] < 0.01);
  vi_identify_destroy(&id);
  series_free(&s);
  vi_model_destroy(&m);
}

/* The forcing frequency fitted from a naive guess: the recording's own
 * period (SciPy's Fig. 2 orbit, Omega = 0.9) sets the starts, 2 pi n / its
 * period, so guesses 0.55 and 1.44 times the truth end on it, with r
 * (1.3 starts from the multiple 1.8, its nearest, and finds 0.9 among
 * the others in range; Python's test starts from 1.6);
 * and with the stop's position, which a global stage spreading Omega over
 * +-50 % missed even from the truth (its residual 3000 times the noise).
 * A recording that repeats with no period says so. */
static void fig2_omega(void **state)
{
  (void)state;
  static rec r;
  load("fig2.csv", &r);
  vi_model *m = vi_test_fig2();
  series s = repeat(&r, 20, 0.002 * peak_to_peak(&r), 5);
  const double guess[] = {0.5, 1.3}, om = 0.9;
  for (int g = 0; g < 3; g++) {
    int with_xs = g == 2, conv = 0;
    vi_identify *id = NULL;
    double p[2], se[2];
    assert_int_equal(vi_identify_create(m, 2, &id), VI_OK);
    assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_OMEGA, 0, with_xs ? om : guess[g],
                                           0.0, HUGE_VAL), VI_OK);
    if (with_xs)
      assert_int_equal(vi_identify_set_param_key(id, 1, "stop.xs", NAN, NAN), VI_OK);
    else
      assert_int_equal(vi_identify_set_param(id, 1, VI_IDENTIFY_R, 0, 0.5, 0, 1), VI_OK);
    assert_int_equal(vi_identify_set_data(id, s.ns, s.t, s.x, NULL), VI_OK);
    assert_int_equal(vi_identify_run(id), VI_OK);
    assert_int_equal(vi_identify_params(id, p, se, NULL, NULL, NULL), VI_OK);
    assert_int_equal(vi_identify_summary(id, &conv, NULL, NULL, NULL, NULL, NULL, NULL), VI_OK);
    print_message("from Omega %.2f: Omega %.8f +- %.1e, %s %.6f +- %.1e\n",
                  with_xs ? om : guess[g], p[0], se[0], with_xs ? "xs" : "r", p[1], se[1]);
    assert_true(conv);
    assert_true(fabs(p[0] - om) < 3 * se[0] && se[0] < 1e-4 * om);
    assert_true(fabs(p[1] - (with_xs ? 0.1 : 0.7)) < 3 * se[1] && se[1] < 0.01);
    vi_identify_destroy(&id);
  }
  /* noise repeats with no period */
  unsigned long x = 12345;
  for (int i = 0; i < s.ns; i++) {
    x = x * 6364136223846793005UL + 1442695040888963407UL;
    s.x[i] = (double)(x >> 11) / 9007199254740992.0 - 0.5;
  }
  vi_identify *id = NULL;
  assert_int_equal(vi_identify_create(m, 1, &id), VI_OK);
  assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_OMEGA, 0, 0.9, 0.0, HUGE_VAL),
                   VI_OK);
  assert_int_equal(vi_identify_set_data(id, s.ns, s.t, s.x, NULL), VI_OK);
  assert_int_equal(vi_identify_run(id), VI_ERR_ARG);
  assert_non_null(strstr(vi_identify_errmsg(id), "repeats with no period"));
  vi_identify_destroy(&id);
  series_free(&s);
  vi_model_destroy(&m);
}

/* A recording on an absolute clock: SciPy's Fig. 2 orbit with its times
 * 1.7e9 on (a data logger's Unix seconds), Omega and r fitted from 0.85.  The fit is the same as from 0 (to a tenth of a
 * standard error: 1.7e9 has a quantum of 2.4e-7 in double), so are the
 * profile intervals, and the shift moves with the clock, t0 + offset
 * equal to the first fit's within its standard error (model time t + t0).
 * With the shift measured from the caller's 0, Omega and the shift were
 * one direction: at 123456.789 the profile of Omega collapsed to a point
 * and its stderr read 1700 times too small (9.3e-11 on the beam). */
static void clock_offset(void **state)
{
  (void)state;
  static rec r;
  load("fig2.csv", &r);
  vi_model *m = vi_test_fig2();
  series s = repeat(&r, 20, 0.002 * peak_to_peak(&r), 9);
  const double off[] = {0.0, 1.7e9};
  double p0[2], se0[2], lo0[2], hi0[2], t00 = 0.0, x0 = 0.0;
  double *t = malloc(sizeof(double) * s.ns);
  for (int k = 0; k < 2; k++) {
    vi_identify *id = NULL;
    double p[2], se[2], lo[2], hi[2], t0, t0se, x;
    int pfl[2], conv;
    for (int i = 0; i < s.ns; i++) t[i] = s.t[i] + off[k];
    assert_int_equal(vi_identify_create(m, 2, &id), VI_OK);
    assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_OMEGA, 0, 0.85, 0.0, HUGE_VAL),
                     VI_OK);
    assert_int_equal(vi_identify_set_param(id, 1, VI_IDENTIFY_R, 0, 0.5, 0, 1), VI_OK);
    assert_int_equal(vi_identify_set_data(id, s.ns, t, s.x, NULL), VI_OK);
    assert_int_equal(vi_identify_run(id), VI_OK);
    assert_int_equal(vi_identify_params(id, p, se, NULL, NULL, NULL), VI_OK);
    assert_int_equal(vi_identify_profile(id, lo, hi, pfl), VI_OK);
    assert_int_equal(vi_identify_shift(id, &t0, &t0se), VI_OK);
    double ts;
    assert_int_equal(vi_identify_solution_summary(id, 0, NULL, NULL, NULL, NULL, NULL, &ts),
                     VI_OK);
    assert_true(ts == t0); /* every door on the caller's clock */
    assert_int_equal(vi_identify_summary(id, &conv, NULL, NULL, NULL, NULL, NULL, NULL), VI_OK);
    assert_int_equal(vi_identify_response(id, 1, t + 100, &x, NULL), VI_OK);
    print_message("clock + %.10g: Omega %.10f +- %.2e [%.10f, %.10f], r %.6f +- %.1e, t0 %.17g "
                  "+- %.1e\n", off[k], p[0], se[0], lo[0], hi[0], p[1], se[1], t0, t0se);
    assert_true(conv);
    assert_int_equal(pfl[0] & VI_IDENTIFY_PROFILE_DIFFERS, 0);
    assert_true(fabs(p[0] - 0.9) < 3 * se[0] && fabs(p[1] - 0.7) < 3 * se[1]);
    if (k == 0) {
      memcpy(p0, p, sizeof p);
      memcpy(se0, se, sizeof se);
      memcpy(lo0, lo, sizeof lo);
      memcpy(hi0, hi, sizeof hi);
      t00 = t0;
      x0 = x;
    } else {
      for (int j = 0; j < 2; j++) {
        assert_true(fabs(p[j] - p0[j]) < 0.1 * se0[j]);
        assert_close(se[j] / se0[j], 1.0, 0.01);
        assert_true(fabs(lo[j] - lo0[j]) < 0.1 * se0[j] && fabs(hi[j] - hi0[j]) < 0.1 * se0[j]);
      }
      assert_true(fabs(t0 + off[k] - t00) < t0se);
      assert_close(x, x0, 1e-3 * peak_to_peak(&r)); /* the same response at the same sample */
    }
    vi_identify_destroy(&id);
  }
  free(t);
  series_free(&s);
  vi_model_destroy(&m);
}

/* What the data cannot say: the restitution of a stop the motion never
 * reaches is flagged, its error infinite; a fit on a bound is flagged. */
static void undetermined(void **state)
{
  (void)state;
  static rec r;
  load("fig2.csv", &r);
  vi_model *f2 = vi_test_fig2();
  vi_model *m = NULL;
  double M[4] = {1, 0, 0, 1}, C[4] = {0.2, -0.1, -0.1, 0.1}, K[4] = {2, -1, -1, 1};
  double a[2] = {0.5, 0}, w[2] = {0, 1}, w2[2] = {1, 0};
  assert_int_equal(vi_model_create(2, &m), VI_OK);
  assert_int_equal(vi_model_set_mass(m, M, 2), VI_OK);
  assert_int_equal(vi_model_set_damping(m, C, 2), VI_OK);
  assert_int_equal(vi_model_set_stiffness(m, K, 2), VI_OK);
  assert_int_equal(vi_model_set_forcing(m, 0.9, a, NULL, NULL), VI_OK);
  assert_int_equal(vi_model_set_stop(m, w, 0.1, 0.7), VI_OK);
  assert_int_equal(vi_model_add_stop(m, w2, 5.0, 0.5), VI_OK); /* never hit */
  assert_int_equal(vi_model_setup(m), VI_OK);
  series s = repeat(&r, 10, 0.002 * peak_to_peak(&r), 4);
  vi_identify *id = NULL;
  double p[2], se[2];
  int fl[2];
  assert_int_equal(vi_identify_create(m, 2, &id), VI_OK);
  assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_R, 0, 0.6, 0, 1), VI_OK);
  assert_int_equal(vi_identify_set_param(id, 1, VI_IDENTIFY_R, 1, 0.5, 0, 1), VI_OK);
  assert_int_equal(vi_identify_set_data(id, s.ns, s.t, s.x, NULL), VI_OK);
  assert_int_equal(vi_identify_run(id), VI_OK);
  assert_int_equal(vi_identify_params(id, p, se, NULL, NULL, fl), VI_OK);
  assert_true(fabs(p[0] - 0.7) < 3 * se[0]);
  assert_false(fl[0] & VI_IDENTIFY_UNDETERMINED);
  assert_true(fl[1] & VI_IDENTIFY_UNDETERMINED);
  assert_true(isinf(se[1]));
  vi_identify_destroy(&id);
  /* r of Fig. 2 from data made with r = 0.7, confined to [0, 0.6] */
  assert_int_equal(vi_identify_create(f2, 1, &id), VI_OK);
  assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_R, 0, 0.5, 0, 0.6), VI_OK);
  assert_int_equal(vi_identify_set_data(id, s.ns, s.t, s.x, NULL), VI_OK);
  assert_int_equal(vi_identify_run(id), VI_OK);
  assert_int_equal(vi_identify_params(id, p, se, NULL, NULL, fl), VI_OK);
  assert_close(p[0], 0.6, 1e-6);
  assert_true(fl[0] & VI_IDENTIFY_ON_BOUND);
  vi_identify_destroy(&id);
  series_free(&s);
  vi_model_destroy(&m);
  vi_model_destroy(&f2);
}

/* Bad recordings: named errors, no fit. */
static void bad_data(void **state)
{
  (void)state;
  static rec r;
  load("fig2.csv", &r);
  vi_model *m = vi_test_fig2();
  vi_identify *id = NULL;
  assert_int_equal(vi_identify_create(m, 1, &id), VI_OK);
  assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_R, 0, 0.6, 0, 1), VI_OK);
  series s = repeat(&r, 4, 0.0, 1);
  /* one number twice: refused, by kind and by key (stop.r is stops[1].r) */
  vi_identify *i2 = NULL;
  assert_int_equal(vi_identify_create(m, 2, &i2), VI_OK);
  assert_int_equal(vi_identify_set_param_key(i2, 0, "stop.r", NAN, NAN), VI_OK);
  assert_int_equal(vi_identify_set_param_key(i2, 1, "stops[1].r", NAN, NAN), VI_ERR_ARG);
  assert_non_null(strstr(vi_identify_errmsg(i2), "is parameter 1 already"));
  assert_int_equal(vi_identify_set_param(i2, 1, VI_IDENTIFY_R, 0, 0.6, 0, 1), VI_ERR_ARG);
  assert_int_equal(vi_identify_set_param_key(i2, 0, "stop.r", 0.2, 0.9), VI_OK); /* itself */
  assert_int_equal(vi_identify_set_param(i2, 1, VI_IDENTIFY_XS, 0, 0.1, 0, 1), VI_OK);
  vi_identify_destroy(&i2);
  assert_int_equal(vi_identify_set_data(id, 10, s.t, s.x, NULL), VI_ERR_ARG);
  assert_non_null(strstr(vi_identify_errmsg(id), "too few"));
  s.t[7] = s.t[6];
  assert_int_equal(vi_identify_set_data(id, s.ns, s.t, s.x, NULL), VI_ERR_ARG);
  assert_non_null(strstr(vi_identify_errmsg(id), "sample 8"));
  s.t[7] = 0.5 * (s.t[6] + s.t[8]);
  s.x[9] = NAN;
  assert_int_equal(vi_identify_set_data(id, s.ns, s.t, s.x, NULL), VI_ERR_NONFINITE);
  assert_non_null(strstr(vi_identify_errmsg(id), "sample 10"));
  /* not periodic with the orbit's period: a sine at another frequency */
  for (int i = 0; i < s.ns; i++) s.x[i] = 0.3 * sin(0.63 * s.t[i]);
  assert_int_equal(vi_identify_set_data(id, s.ns, s.t, s.x, NULL), VI_OK);
  assert_int_equal(vi_identify_run(id), VI_ERR_ARG);
  assert_non_null(strstr(vi_identify_errmsg(id), "does not repeat"));
  assert_int_equal(vi_identify_params(id, NULL, NULL, NULL, NULL, NULL), VI_ERR_STATE);
  /* shorter than one period */
  assert_int_equal(vi_identify_set_data(id, 40, s.t, s.x, NULL), VI_OK);
  assert_int_equal(vi_identify_run(id), VI_ERR_ARG);
  vi_identify_destroy(&id);
  series_free(&s);
  vi_model_destroy(&m);
}

/* A P(1,2) orbit on two stops (share/scenes/clearance.yaml at a = (0.3, 0),
 * Omega = 1.7: one impact on each side): both restitutions from 0.75. */
static void clearance(void **state)
{
  (void)state;
  static rec r;
  load("clearance.csv", &r);
  double M[4] = {1, 0, 0, 1}, C[4] = {0.1, -0.05, -0.05, 0.05}, K[4] = {2, -1, -1, 1};
  double a[2] = {0.3, 0}, w[2] = {0, 1}, wm[2] = {0, -1};
  vi_model *m = NULL;
  assert_int_equal(vi_model_create(2, &m), VI_OK);
  assert_int_equal(vi_model_set_mass(m, M, 2), VI_OK);
  assert_int_equal(vi_model_set_damping(m, C, 2), VI_OK);
  assert_int_equal(vi_model_set_stiffness(m, K, 2), VI_OK);
  assert_int_equal(vi_model_set_forcing(m, 1.7, a, NULL, NULL), VI_OK);
  assert_int_equal(vi_model_add_stop(m, w, 0.1, 0.75), VI_OK);
  assert_int_equal(vi_model_add_stop(m, wm, 0.1, 0.75), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  series s = repeat(&r, 20, 0.002 * peak_to_peak(&r), 9);
  vi_identify *id = NULL;
  double p[2], se[2];
  int n, mm, conv;
  assert_int_equal(vi_identify_create(m, 2, &id), VI_OK);
  assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_R, 0, 0.75, 0, 1), VI_OK);
  assert_int_equal(vi_identify_set_param(id, 1, VI_IDENTIFY_R, 1, 0.75, 0, 1), VI_OK);
  assert_int_equal(vi_identify_set_data(id, s.ns, s.t, s.x, NULL), VI_OK);
  assert_int_equal(vi_identify_run(id), VI_OK);
  assert_int_equal(vi_identify_params(id, p, se, NULL, NULL, NULL), VI_OK);
  assert_int_equal(vi_identify_summary(id, &conv, NULL, NULL, NULL, NULL, &n, &mm), VI_OK);
  assert_true(conv && n == 1 && mm == 2);
  for (int j = 0; j < 2; j++) assert_true(fabs(p[j] - 0.8) < 3 * se[j] && se[j] < 0.01);
  vi_identify_destroy(&id);
  /* the forcing amplitude with stop 1's r, from a naive 1.0 (3.3 times
   * the truth, 0.3): +-50 % of it held no start whose orbit the local fits
   * could follow down (the fit ended 280 noise levels off); the global
   * stage widened to a factor 4 in log finds it */
  assert_int_equal(vi_model_set_param(m, "forcing.a[1]", 1.0), VI_OK);
  assert_int_equal(vi_model_set_param(m, "stops[2].r", 0.8), VI_OK); /* the truth, held */
  assert_int_equal(vi_identify_create(m, 2, &id), VI_OK);
  assert_int_equal(vi_identify_set_param_key(id, 0, "forcing.a[1]", NAN, NAN), VI_OK);
  assert_int_equal(vi_identify_set_param(id, 1, VI_IDENTIFY_R, 0, 0.75, 0, 1), VI_OK);
  assert_int_equal(vi_identify_set_data(id, s.ns, s.t, s.x, NULL), VI_OK);
  assert_int_equal(vi_identify_run(id), VI_OK);
  assert_int_equal(vi_identify_params(id, p, se, NULL, NULL, NULL), VI_OK);
  double rms, nz;
  assert_int_equal(vi_identify_summary(id, &conv, NULL, &rms, &nz, NULL, &n, &mm), VI_OK);
  print_message("clearance from a = 1.0: a %.6f +- %.1e, r %.5f +- %.1e, P(%d,%d), rms / noise "
                "%.3f\n", p[0], se[0], p[1], se[1], n, mm, rms / nz);
  assert_true(conv && n == 1 && mm == 2 && rms < 1.5 * nz);
  assert_true(fabs(p[0] - 0.3) < 3 * se[0] && fabs(p[1] - 0.8) < 3 * se[1]);
  vi_identify_destroy(&id);
  series_free(&s);
  vi_model_destroy(&m);
}

/* The forcing phase of a recorded f = A cos(Omega (t + t0)): exact data
 * at uneven times give t0 to round-off, a negative shift wraps into
 * [0, T), and noise of 1 % moves it by about 1 % of a radian / Omega. */
static void forcing_phase(void **state)
{
  (void)state;
  const double Om = 0.9, T = 2 * M_PI / Om;
  double t[200], f[200], ph;
  static const double shifts[3] = {0.4, -0.4, 5.0};
  for (int q = 0; q < 3; q++) {
    for (int i = 0; i < 200; i++) {
      t[i] = 3.0 + 0.137 * i + 0.01 * sin(7.0 * i); /* uneven */
      f[i] = 0.7 * cos(Om * (t[i] + shifts[q]));
    }
    assert_int_equal(vi_identify_forcing_phase(200, t, f, Om, &ph), VI_OK);
    double want = fmod(shifts[q] + T, T);
    assert_close(ph, want, 1e-12 * T);
  }
  /* 1 % deterministic "noise": the phase moves by O(1e-2) / Omega at most */
  for (int i = 0; i < 200; i++) f[i] = 0.7 * cos(Om * (t[i] + 0.4)) + 0.007 * sin(13.1 * i);
  assert_int_equal(vi_identify_forcing_phase(200, t, f, Om, &ph), VI_OK);
  assert_true(fabs(ph - 0.4) < 0.02 / Om);
}

/* The global stage (issue 28): from r = 0.05, 0.5 and 0.95 (at 0.5 the
 * model settles on P(4,6), far from the recording's P(1,1), and the local
 * fit alone has nowhere to start) the same best fit, P(1,1) within 0.01
 * and 1.96 stderr of the truth, over the range r in [0, 1]; the profile
 * interval agrees with the Jacobian's within 20 % (r moves the response
 * nearly linearly over +-0.01) and holds the fit. */
static void beam_global(void **state)
{
  (void)state;
  static rec r;
  load("beam4.csv", &r);
  vi_model *m = vi_test_beam(4, 0.05, 0.75);
  series s = repeat(&r, 50, 0.002 * peak_to_peak(&r), 1);
  static const double r0[3] = {0.05, 0.5, 0.95};
  double first = NAN;
  for (int k = 0; k < 3; k++) {
    vi_identify *id = NULL;
    double p, se, l, h, pl, ph, q, lo, hi, rms;
    int fl, pfl, n, mm, uq;
    assert_int_equal(vi_identify_create(m, 1, &id), VI_OK);
    assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_R, 0, r0[k], 0, 1), VI_OK);
    assert_int_equal(vi_identify_set_data(id, s.ns, s.t, s.x, NULL), VI_OK);
    run_ok(id);
    assert_int_equal(vi_identify_params(id, &p, &se, &l, &h, &fl), VI_OK);
    assert_int_equal(vi_identify_profile(id, &pl, &ph, &pfl), VI_OK);
    assert_int_equal(vi_identify_summary(id, NULL, NULL, &rms, NULL, NULL, &n, &mm), VI_OK);
    assert_true(n == 1 && mm == 1);
    assert_true(fabs(p - 0.75) < 0.01 && fabs(p - 0.75) < 1.96 * se);
    if (k == 0) first = p;
    else assert_close(p, first, 1e-6);
    assert_false(pfl & VI_IDENTIFY_PROFILE_DIFFERS);
    assert_true(pl < p && p < ph);
    assert_close((ph - pl) / (h - l), 1.0, 0.2);
    assert_int_equal(vi_identify_search_range(id, &lo, &hi), VI_OK);
    assert_true(lo == 0.0 && hi == 1.0);
    /* solution 0 is the best fit */
    assert_true(vi_identify_nsolutions(id, &uq) >= 1);
    assert_int_equal(vi_identify_solution(id, 0, &q, NULL, NULL, NULL, NULL), VI_OK);
    assert_true(q == p);
    assert_int_equal(vi_identify_solution(id, 99, &q, NULL, NULL, NULL, NULL), VI_ERR_ARG);
    vi_identify_destroy(&id);
  }
  series_free(&s);
  vi_model_destroy(&m);
}

/* Two explanations (issue 28): at 1 % noise over 20 periods the P(1,1)
 * orbit near the truth and a P(1,2) orbit near r = 0.3 both leave a
 * residual at the noise level (chi-square at 95 %); both are reported,
 * best first, not unique, and the truth lies in one's 95 % interval. */
static void beam_not_unique(void **state)
{
  (void)state;
  static rec r;
  load("beam4.csv", &r);
  vi_model *m = vi_test_beam(4, 0.05, 0.75);
  series s = repeat(&r, 20, 0.01 * peak_to_peak(&r), 3);
  vi_identify *id = NULL;
  assert_int_equal(vi_identify_create(m, 1, &id), VI_OK);
  assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_R, 0, 0.5, 0, 1), VI_OK);
  assert_int_equal(vi_identify_set_data(id, s.ns, s.t, s.x, NULL), VI_OK);
  assert_int_equal(vi_identify_run(id), VI_OK);
  int uq = 1, ns = vi_identify_nsolutions(id, &uq), cover = 0, types = 0;
  assert_true(ns >= 2);
  assert_false(uq);
  double last = 0.0;
  for (int k = 0; k < ns; k++) {
    double p, se, l, h, rms, ratio, dc;
    int n, mm;
    assert_int_equal(vi_identify_solution(id, k, &p, &se, &l, &h, NULL), VI_OK);
    assert_int_equal(vi_identify_solution_summary(id, k, &n, &mm, &rms, &ratio, &dc, NULL), VI_OK);
    assert_true(rms >= last); /* best first */
    last = rms;
    assert_true(ratio < 1.1 && dc >= 0.0 && (k > 0 || dc == 0.0));
    assert_true(se > 0.005);
    cover += l <= 0.75 && 0.75 <= h;
    types |= n == 1 && mm == 1 ? 1 : n == 1 && mm == 2 ? 2 : 4;
  }
  assert_true(cover >= 1);
  assert_int_equal(types & 3, 3); /* P(1,1) and P(1,2) */
  /* what separates them: their responses differ by D noise variances over
   * the record (the likelihood-ratio statistic's mean, so the realised
   * dchi2 of a few lies within its spread 2 sqrt(D) of it), and the record
   * length that makes the test reject the wrong one with 95 % power is
   * y^2 / D, y = (3.29 + sqrt(3.29^2 + 4 chi2_0.95(2))) / 2 = 4.59415 */
  double d0, l0, d1, l1, dc1;
  assert_int_equal(vi_identify_solution_separation(id, 0, &d0, &l0), VI_OK);
  assert_true(d0 == 0.0 && isnan(l0));
  assert_int_equal(vi_identify_solution_separation(id, 1, &d1, &l1), VI_OK);
  assert_int_equal(vi_identify_solution_summary(id, 1, NULL, NULL, NULL, NULL, &dc1, NULL), VI_OK);
  print_message("not unique: D %.3g, record factor %.3g, dchi2 %.3g\n", d1, l1, dc1);
  assert_true(d1 > 0.0 && fabs(dc1 - d1) < 3.0 * 2.0 * sqrt(d1) + 1.0);
  assert_close(l1 * d1 / (4.59415 * 4.59415), 1.0, 1e-5);
  assert_int_equal(vi_identify_solution_separation(id, ns, &d1, &l1), VI_ERR_ARG);
  /* the P(1,2) solution from the impact-phase scan alone (issue 28 item
   * 5): from r = 0.35 the transient settles on P(2,3), where the local fit
   * used to stop ("start nearer"); the two-impact scan offers the P(1,2)
   * orbit, and the local fit ends on the global stage's P(1,2) minimum */
  double q12 = NAN;
  for (int k = 0; k < ns; k++) {
    double p;
    int n, mm;
    vi_identify_solution(id, k, &p, NULL, NULL, NULL, NULL);
    vi_identify_solution_summary(id, k, &n, &mm, NULL, NULL, NULL, NULL);
    if (n == 1 && mm == 2) q12 = p;
  }
  vi_identify_destroy(&id);
  assert_int_equal(vi_identify_create(m, 1, &id), VI_OK);
  assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_R, 0, 0.35, 0, 1), VI_OK);
  assert_int_equal(vi_identify_set_global(id, 0), VI_OK);
  assert_int_equal(vi_identify_set_data(id, s.ns, s.t, s.x, NULL), VI_OK);
  run_ok(id);
  double p12, rms, ratio;
  int n12, m12;
  assert_int_equal(vi_identify_params(id, &p12, NULL, NULL, NULL, NULL), VI_OK);
  assert_int_equal(vi_identify_solution_summary(id, 0, &n12, &m12, &rms, &ratio, NULL, NULL), VI_OK);
  print_message("local from 0.35: P(%d,%d) r %.6f (global stage's P(1,2): %.6f), ratio %.3f\n",
                n12, m12, p12, q12, ratio);
  assert_true(n12 == 1 && m12 == 2 && ratio < 1.1);
  assert_close(p12, q12, 1e-5);
  vi_identify_destroy(&id);
  series_free(&s);
  vi_model_destroy(&m);
}

/* An accelerometer at the tip (issue 28): the independent recording's
 * w.x'' with 0.2 % noise over 50 periods, alone from r = 0.5, gives r
 * within 0.02 (and 3 stderr); with the displacement beside it too. */
static void beam_accel(void **state)
{
  (void)state;
  static rec r;
  load("beam4_acc.csv", &r);
  vi_model *m = vi_test_beam(4, 0.05, 0.75);
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (int i = 0; i < r.ns; i++) {
    lo = fmin(lo, r.a[i]);
    hi = fmax(hi, r.a[i]);
  }
  series s = repeat(&r, 50, 0.0, 1), sa = repeat(&r, 50, 0.0, 1);
  gsl_rng *g = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(g, 21);
  for (int i = 0; i < sa.ns; i++)
    sa.x[i] = r.a[i % r.ns] + gsl_ran_gaussian(g, 0.002 * (hi - lo));
  for (int i = 0; i < s.ns; i++)
    s.x[i] += gsl_ran_gaussian(g, 0.002 * peak_to_peak(&r));
  gsl_rng_free(g);
  for (int way = 0; way < 2; way++) {
    vi_identify *id = NULL;
    double p, se, rms, nz;
    assert_int_equal(vi_identify_create(m, 1, &id), VI_OK);
    assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_R, 0, 0.5, 0, 1), VI_OK);
    assert_int_equal(vi_identify_set_sensors(id, s.ns, s.t, way ? s.x : NULL, NULL, sa.x), VI_OK);
    run_ok(id);
    assert_int_equal(vi_identify_params(id, &p, &se, NULL, NULL, NULL), VI_OK);
    assert_int_equal(vi_identify_summary(id, NULL, NULL, &rms, &nz, NULL, NULL, NULL), VI_OK);
    double sig = 0.002 * (way ? peak_to_peak(&r) : hi - lo);
    print_message("accel way %d r %.5f +- %.5f rms %.3g noise estimate %.3g of %.3g\n",
                  way, p, se, rms, nz, sig);
    assert_true(fabs(p - 0.75) < 0.02 && fabs(p - 0.75) < 3 * se);
    /* the residual is the first channel's noise: a's alone, x's with x */
    assert_close(rms / sig, 1.0, 0.1);
    /* and so is the estimate, from the recording alone (the 4th
     * differences of a alone were 11 times it: its higher modes); 3200
     * samples: the median's spread is about 2.5 % */
    assert_close(nz / sig, 1.0, 0.1);
    vi_identify_destroy(&id);
  }
  series_free(&s);
  series_free(&sa);
  vi_model_destroy(&m);
}

/* The beam's tip acceleration (beam4_acc_rate.csv, 1226 samples at 61.3
 * a period) into r, and a copy with noise of 0.2 % of its span (seed 31),
 * *sig, returned (the caller frees it). */
static double *accel_record(rec *r, double *sig)
{
  load("beam4_acc_rate.csv", r);
  assert_int_equal(r->ns, 1226);
  double lo = HUGE_VAL, hi = -HUGE_VAL, *a = malloc(sizeof(double) * r->ns);
  assert_non_null(a);
  for (int i = 0; i < r->ns; i++) {
    lo = fmin(lo, r->a[i]);
    hi = fmax(hi, r->a[i]);
  }
  *sig = 0.002 * (hi - lo);
  gsl_rng *g = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(g, 31);
  for (int i = 0; i < r->ns; i++) a[i] = r->a[i] + gsl_ran_gaussian(g, *sig);
  gsl_rng_free(g);
  return a;
}

/* An accelerometer sampled at a rate not locked to the forcing (issue 28
 * item 4): the independent recording of the tip's w.x'' at 61.3 samples
 * per period over 20 periods, 0.2 % noise.  No two periods share sample
 * phases, so neither a lag of T between samples nor their 4th
 * differences cancel the signal (its higher modes); the periods folded
 * onto one do: the recording's period is T (it used to read 3 T, where
 * 3 x 61.3 is almost whole) and the noise estimate is the noise added
 * (1226 samples: the median's spread is about 4 %); r within 0.02. */
static void beam_accel_rate(void **state)
{
  (void)state;
  static rec r;
  double sig, *a = accel_record(&r, &sig);
  vi_model *m = vi_test_beam(4, 0.05, 0.75);
  vi_identify *id = NULL;
  double p, se, rms, nz;
  int n, mm;
  assert_int_equal(vi_identify_create(m, 1, &id), VI_OK);
  assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_R, 0, 0.5, 0, 1), VI_OK);
  assert_int_equal(vi_identify_set_sensors(id, r.ns, r.t, NULL, NULL, a), VI_OK);
  run_ok(id);
  assert_int_equal(vi_identify_params(id, &p, &se, NULL, NULL, NULL), VI_OK);
  assert_int_equal(vi_identify_summary(id, NULL, NULL, &rms, &nz, NULL, &n, &mm), VI_OK);
  print_message("accel at 61.3 per period: r %.5f +- %.5f, P(%d,%d), rms %.3g, noise "
                "estimate %.3g of %.3g\n", p, se, n, mm, rms, nz, sig);
  assert_true(n == 1 && mm == 1);
  assert_true(fabs(p - 0.75) < 0.02 && fabs(p - 0.75) < 3 * se);
  assert_close(nz / sig, 1.0, 0.15);
  assert_close(rms / sig, 1.0, 0.1);
  vi_identify_destroy(&id);
  /* and the forcing frequency with r, from a guess 1.53 times the truth
   * (the command from 0.5 to 3.0: doc/identify.md): the record repeats
   * only every 3 periods, to about a sample, so its period comes from the
   * record folded with a third of that lag (it used to end on a P(1,2) at
   * Omega 0.8498 with residuals 53 times the noise, whatever the guess) */
  const double guess[] = {1.3};
  for (int k = 0; k < 1; k++) {
    double q[2], sq[2];
    assert_int_equal(vi_identify_create(m, 2, &id), VI_OK);
    assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_OMEGA, 0, guess[k], 0.0,
                                           HUGE_VAL), VI_OK);
    assert_int_equal(vi_identify_set_param(id, 1, VI_IDENTIFY_R, 0, 0.5, 0, 1), VI_OK);
    assert_int_equal(vi_identify_set_sensors(id, r.ns, r.t, NULL, NULL, a), VI_OK);
    assert_int_equal(vi_identify_run(id), VI_OK);
    assert_int_equal(vi_identify_params(id, q, sq, NULL, NULL, NULL), VI_OK);
    assert_int_equal(vi_identify_summary(id, NULL, NULL, &rms, NULL, NULL, &n, &mm), VI_OK);
    print_message("accel at 61.3 per period from Omega %.2f: Omega %.8f +- %.1e, r %.5f +- "
                  "%.5f, P(%d,%d), rms / noise %.3f\n", guess[k], q[0], sq[0], q[1], sq[1], n,
                  mm, rms / sig);
    assert_true(n == 1 && mm == 1);
    assert_true(fabs(q[0] - 0.85) < 3 * sq[0] && sq[0] < 1e-5);
    assert_true(fabs(q[1] - 0.75) < 0.02 && fabs(q[1] - 0.75) < 3 * sq[1]);
    assert_close(rms / sig, 1.0, 0.1);
    vi_identify_destroy(&id);
  }
  /* its first 6 periods (368 samples): the period found to a part of a
   * sample over the record only, and the noise estimated from the record
   * folded at that start's period read 50 times the noise; at the fitted
   * orbit's period, within a factor 3 (an accelerometer's higher modes
   * still differ between neighbours in phase 1/368 of a period apart) */
  {
    double q[2], sq[2];
    assert_int_equal(vi_identify_create(m, 2, &id), VI_OK);
    assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_OMEGA, 0, 1.3, 0.0, HUGE_VAL),
                     VI_OK);
    assert_int_equal(vi_identify_set_param(id, 1, VI_IDENTIFY_R, 0, 0.5, 0, 1), VI_OK);
    assert_int_equal(vi_identify_set_sensors(id, 368, r.t, NULL, NULL, a), VI_OK);
    assert_int_equal(vi_identify_run(id), VI_OK);
    assert_int_equal(vi_identify_params(id, q, sq, NULL, NULL, NULL), VI_OK);
    assert_int_equal(vi_identify_summary(id, NULL, NULL, &rms, &nz, NULL, &n, &mm), VI_OK);
    print_message("accel, 6 periods: Omega %.8f +- %.1e, r %.5f +- %.5f, noise estimate %.3g "
                  "of %.3g\n", q[0], sq[0], q[1], sq[1], nz, sig);
    assert_true(n == 1 && mm == 1);
    assert_true(fabs(q[0] - 0.85) < 3 * sq[0] && fabs(q[1] - 0.75) < 3 * sq[1]);
    assert_true(nz / sig < 3.0 && nz / sig > 0.8);
    vi_identify_destroy(&id);
  }
  free(a);
  vi_model_destroy(&m);
}

/* The forcing frequency, r and the base amplitude from the accelerometer
 * (beam4_acc_rate.csv, 61.3 samples a period, 0.2 % noise) from Omega
 * 1.3 (within [0.5, 1.5]: fewer multiples to start from), r 0.5 and half
 * the base.  The searches about the best minimum
 * (+-50 %) end on a P(1,3) at base 0.01043 at 14 noise levels: the
 * recording's P(1,1) exists for bases within a few per cent of 0.01 and
 * the grid's starts lie 20 % apart.  Searched again closer about that
 * minimum (+-25 %, then +-12.5 %) while it does not explain the data, the
 * fit ends on the truth: all three within 3 standard errors, the residual
 * at the noise.  (From a base of 0.003 the +-50 % searches happen to
 * reach it.) */
static void beam_accel_naive(void **state)
{
  (void)state;
  static rec r;
  double sig, *a = accel_record(&r, &sig), p[3], se[3], rms;
  vi_model *m = vi_test_beam(4, 0.05, 0.75);
  vi_identify *id = NULL;
  int n, mm;
  assert_int_equal(vi_identify_create(m, 3, &id), VI_OK);
  assert_int_equal(vi_identify_set_builder(id, build_orb, NULL, NULL), VI_OK);
  assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_OMEGA, 0, 1.3, 0.5, 1.5), VI_OK);
  assert_int_equal(vi_identify_set_param(id, 1, VI_IDENTIFY_OTHER, 0, 0.5, 0, 1), VI_OK);
  assert_int_equal(vi_identify_set_param(id, 2, VI_IDENTIFY_OTHER, 0, 0.005, -HUGE_VAL,
                                         HUGE_VAL), VI_OK);
  assert_int_equal(vi_identify_set_sensors(id, r.ns, r.t, NULL, NULL, a), VI_OK);
  run_ok(id);
  assert_int_equal(vi_identify_params(id, p, se, NULL, NULL, NULL), VI_OK);
  assert_int_equal(vi_identify_summary(id, NULL, NULL, &rms, NULL, NULL, &n, &mm), VI_OK);
  print_message("accel from Omega 1.3, base 0.005: Omega %.8f +- %.1e, r %.5f +- %.1e, "
                "base %.7f +- %.1e, P(%d,%d), rms / noise %.3f\n", p[0], se[0], p[1], se[1],
                p[2], se[2], n, mm, rms / sig);
  assert_true(n == 1 && mm == 1);
  assert_true(fabs(p[0] - 0.85) < 3 * se[0]);
  assert_true(fabs(p[1] - 0.75) < 3 * se[1]);
  assert_true(fabs(p[2] - 0.01) < 3 * se[2]);
  assert_close(rms / sig, 1.0, 0.1);
  vi_identify_destroy(&id);
  free(a);
  vi_model_destroy(&m);
}

/* Sensors elsewhere (issue 28): Fig. 2 recorded at mass 1 (x_1; the stop
 * is on x_2), 0.2 % noise over 20 periods, r from 0.5; the velocity of
 * x_2 alone; and both masses at once (x_1 with x_2 as an added channel:
 * the same recordings, a smaller stderr than either alone). */
static void fig2_sensors(void **state)
{
  (void)state;
  static rec r1, r2;
  load("fig2_dof1.csv", &r1);
  load("fig2.csv", &r2);
  vi_model *m = vi_test_fig2();
  series s1 = repeat(&r1, 20, 0.002 * peak_to_peak(&r1), 5);
  series s2 = repeat(&r2, 20, 0.0, 6);
  double vlo = HUGE_VAL, vhi = -HUGE_VAL;
  for (int i = 0; i < r2.ns; i++) {
    vlo = fmin(vlo, r2.v[i]);
    vhi = fmax(vhi, r2.v[i]);
  }
  gsl_rng *g = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(g, 7);
  for (int i = 0; i < s2.ns; i++) s2.v[i] += gsl_ran_gaussian(g, 0.002 * (vhi - vlo));
  gsl_rng_free(g);
  series s3 = repeat(&r2, 20, 0.002 * peak_to_peak(&r2), 8);
  double se_alone[2] = {0, 0};
  for (int way = 0; way < 3; way++) {
    vi_identify *id = NULL;
    double p, se, c[2] = {1.0, 0.0}, c2[2] = {0.0, 1.0};
    assert_int_equal(vi_identify_create(m, 1, &id), VI_OK);
    assert_int_equal(vi_identify_set_param(id, 0, VI_IDENTIFY_R, 0, 0.5, 0, 1), VI_OK);
    if (way == 0) {
      assert_int_equal(vi_identify_set_observation(id, c), VI_OK);
      assert_int_equal(vi_identify_set_data(id, s1.ns, s1.t, s1.x, NULL), VI_OK);
    } else if (way == 1) {
      assert_int_equal(vi_identify_set_sensors(id, s2.ns, s2.t, NULL, s2.v, NULL), VI_OK);
    } else {
      assert_int_equal(vi_identify_set_observation(id, c), VI_OK);
      assert_int_equal(vi_identify_set_data(id, s1.ns, s1.t, s1.x, NULL), VI_OK);
      assert_int_equal(vi_identify_add_channel(id, c2, 0, s3.x), VI_OK);
    }
    run_ok(id);
    assert_int_equal(vi_identify_params(id, &p, &se, NULL, NULL, NULL), VI_OK);
    print_message("fig2 way %d r %.5f +- %.5f\n", way, p, se);
    assert_true(fabs(p - 0.7) < 3 * se && se < 0.02);
    if (way < 2) se_alone[way] = se;
    else assert_true(se < se_alone[0]);
    vi_identify_destroy(&id);
  }
  series_free(&s1);
  series_free(&s2);
  series_free(&s3);
  vi_model_destroy(&m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(beam_exact),   cmocka_unit_test(fig2),
      cmocka_unit_test(fig2_omega),
      cmocka_unit_test(clock_offset),
      cmocka_unit_test(bad_data),     cmocka_unit_test(undetermined),
      cmocka_unit_test(beam_jitter),  cmocka_unit_test(beam_r_xs),
      cmocka_unit_test(beam_noise),    cmocka_unit_test(clearance),
      cmocka_unit_test(forcing_phase), cmocka_unit_test(beam_global),
      cmocka_unit_test(beam_not_unique), cmocka_unit_test(beam_accel),
      cmocka_unit_test(beam_accel_rate), cmocka_unit_test(beam_base_naive),
      cmocka_unit_test(outliers),      cmocka_unit_test(beam_accel_naive),
      cmocka_unit_test(fig2_sensors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
