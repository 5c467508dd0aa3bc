/* vi_bench_identify - how long an identification takes and what the data
 * hold (issue 22): fits of the 4-mode beam's restitution (and clearance)
 * and of Fig. 2 on recordings built from the independent SciPy period in
 * tests/study/data (repeated over P periods, Gaussian noise of a fraction
 * of the peak-to-peak, 10 seeds).  Prints per case the mean and largest
 * wall time of a fit, the mean stderr, the scatter of the estimates over
 * the seeds, how many 95 % intervals cover the truth, and the response
 * sensitivity the stderr implies (RMS change of the recording for a change
 * of 0.01 in r, sigma / (stderr sqrt(N)) x 0.01).  No timing is asserted.
 *   vi_bench_identify [DATA_DIR] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "vibroimpact.h"

#ifndef VI_IDENT_DATA
#define VI_IDENT_DATA "tests/study/data"
#endif

static double now(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int load(const char *dir, const char *name, double *t, double *x)
{
  char path[1024], line[256];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *f = fopen(path, "r");
  if (!f) return 0;
  int n = 0;
  while (fgets(line, sizeof line, f) && n < 64) {
    if (line[0] == '#' || line[0] == 't') continue;
    char *e1, *e2;
    t[n] = strtod(line, &e1);
    if (*e1 != ',') continue;
    x[n] = strtod(e1 + 1, &e2);
    if (e2 > e1 + 1) n++;
  }
  fclose(f);
  return n;
}

static vi_model *beam(double xs, double r)
{
  double M[16], C[16], K[16], w[4], g[4], a[4];
  vi_model *m = NULL;
  vi_build_cantilever(4, 1.0, 0.05, 1.0, M, C, K, 4, w, g);
  for (int j = 0; j < 4; j++) a[j] = -0.01 * g[j];
  if (vi_model_create(4, &m) || vi_model_set_mass(m, M, 4) ||
      vi_model_set_damping(m, C, 4) || vi_model_set_stiffness(m, K, 4) ||
      vi_model_set_forcing(m, 0.85, a, NULL, NULL) ||
      vi_model_set_stop(m, w, xs, r) || vi_model_setup(m))
    vi_model_destroy(&m);
  return m;
}

static vi_model *fig2(void)
{
  double M[4] = {1, 0, 0, 1}, C[4] = {0.2, -0.1, -0.1, 0.1}, K[4] = {2, -1, -1, 1};
  double a[2] = {0.5, 0}, w[2] = {0, 1};
  vi_model *m = NULL;
  if (vi_model_create(2, &m) || vi_model_set_mass(m, M, 2) ||
      vi_model_set_damping(m, C, 2) || vi_model_set_stiffness(m, K, 2) ||
      vi_model_set_forcing(m, 0.9, a, NULL, NULL) ||
      vi_model_set_stop(m, w, 0.1, 0.6) || vi_model_setup(m))
    vi_model_destroy(&m);
  return m;
}

typedef struct bcase {
  const char *name, *file;
  int periods, nfit;
  double level, truth[2], start[2];
} bcase;

int main(int argc, char **argv)
{
  const char *dir = argc > 1 ? argv[1] : VI_IDENT_DATA;
  static const bcase cs[] = {
      {"beam4 r, 0.2 % noise, 50 periods", "beam4.csv", 50, 1, 0.002, {0.75, 0}, {0.6, 0}},
      {"beam4 r, 1 % noise, 20 periods", "beam4.csv", 20, 1, 0.01, {0.75, 0}, {0.6, 0}},
      {"beam4 r + xs, 0.2 %, 50 periods", "beam4.csv", 50, 2, 0.002, {0.75, 0.05}, {0.7, 0.0495}},
      {"fig2 r, 0.2 % noise, 20 periods", "fig2.csv", 20, 1, 0.002, {0.7, 0}, {0.6, 0}},
  };
  printf("%-34s %9s %9s %9s %9s %7s %12s\n", "case", "mean s", "max s", "stderr",
         "scatter", "cover", "RMS/0.01 r");
  for (size_t c = 0; c < sizeof cs / sizeof cs[0]; c++) {
    double t1[64], x1[64];
    int n1 = load(dir, cs[c].file, t1, x1);
    if (n1 != 64) {
      fprintf(stderr, "vi_bench_identify: cannot read %s/%s\n", dir, cs[c].file);
      return 1;
    }
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    for (int i = 0; i < 64; i++) {
      lo = fmin(lo, x1[i]);
      hi = fmax(hi, x1[i]);
    }
    double sigma = cs[c].level * (hi - lo), T = t1[1] * 64;
    int ns = 64 * cs[c].periods, cover = 0, seeds = 10;
    double *t = malloc(sizeof(double) * ns), *x = malloc(sizeof(double) * ns);
    double tsum = 0, tmax = 0, sesum = 0, e1 = 0, e2 = 0;
    vi_model *m = c < 3 ? beam(0.05, 0.75) : fig2();
    gsl_rng *g = gsl_rng_alloc(gsl_rng_mt19937);
    for (int s = 1; s <= seeds; s++) {
      gsl_rng_set(g, (unsigned long)s);
      for (int i = 0; i < ns; i++) {
        t[i] = t1[i % 64] + floor(i / 64.0) * T;
        x[i] = x1[i % 64] + gsl_ran_gaussian(g, sigma);
      }
      vi_identify *id = NULL;
      double p[2], se[2], l[2], h[2];
      double w0 = now();
      int st = vi_identify_create(m, cs[c].nfit, &id);
      if (!st) st = vi_identify_set_param(id, 0, VI_IDENTIFY_R, 0, cs[c].start[0], 0, 1);
      if (!st && cs[c].nfit > 1)
        st = vi_identify_set_param(id, 1, VI_IDENTIFY_XS, 0, cs[c].start[1], 0.03, 0.07);
      if (!st) st = vi_identify_set_data(id, ns, t, x, NULL);
      if (!st) st = vi_identify_run(id);
      double w = now() - w0;
      if (st || vi_identify_params(id, p, se, l, h, NULL)) {
        fprintf(stderr, "vi_bench_identify: %s seed %d: %s\n", cs[c].name, s,
                vi_identify_errmsg(id));
        return 1;
      }
      vi_identify_destroy(&id);
      tsum += w;
      tmax = fmax(tmax, w);
      sesum += se[0];
      e1 += p[0] - cs[c].truth[0];
      e2 += (p[0] - cs[c].truth[0]) * (p[0] - cs[c].truth[0]);
      cover += l[0] <= cs[c].truth[0] && cs[c].truth[0] <= h[0];
    }
    double scatter = sqrt((e2 - e1 * e1 / seeds) / (seeds - 1));
    printf("%-34s %9.3f %9.3f %9.4f %9.4f %4d/10 %12.3g\n", cs[c].name,
           tsum / seeds, tmax, sesum / seeds, scatter, cover,
           sigma / (sesum / seeds * sqrt(ns)) * 0.01);
    gsl_rng_free(g);
    vi_model_destroy(&m);
    free(t);
    free(x);
  }
  return 0;
}
