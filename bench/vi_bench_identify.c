/* vi_bench_identify - how long an identification takes and what the data
 * hold (issues 22, 28): fits of the 4-mode beam's restitution (and
 * clearance, and from its tip acceleration alone) and of Fig. 2 on
 * recordings built from the independent SciPy period in tests/study/data
 * (repeated over P periods, Gaussian noise of a fraction of the
 * peak-to-peak, 10 seeds), from starts across the range (the global
 * stage) and, for comparison, the local fit alone from near the truth.
 * Prints per case the mean and largest wall time of a fit, the mean and
 * smallest stderr of r, the scatter of the estimates over the seeds, how
 * many best fits lie within 0.01 and 1.96 stderr of the truth ("hit"),
 * how many 95 % intervals cover it (of the best fit / of any reported
 * solution, within 3 stderr for two keys; P11: of the reported P(1,1)
 * solution, the recordings' own orbit type), how many fits were unique,
 * the profile interval's width against the Jacobian's, and the range of
 * the noise estimate over the noise that was added.  No timing is
 * asserted.
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

/* Column col (1-based after t) of the generator's 64 rows. */
static int load(const char *dir, const char *name, int col, double *t, double *x)
{
  char path[1024], line[512];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *f = fopen(path, "r");
  if (!f) return 0;
  int n = 0;
  while (fgets(line, sizeof line, f) && n < 64) {
    if (line[0] == '#' || line[0] == 't') continue;
    char *e = line;
    t[n] = strtod(line, &e);
    for (int c = 0; c < col && *e == ','; c++) x[n] = strtod(e + 1, &e);
    n++;
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
  int col, periods, nfit, global;
  double level, truth[2], start[2];
} bcase;

/* The counts over the seeds of one case. */
typedef struct tally {
  double tsum, tmax, sesum, semin, e1, e2, pwid, nzlo, nzhi;
  int hit, cover, cover_any, cover_true, unique, npw;
} tally;

/* One fit of the case on the recording t, x [ns]; 0 or 1 after a message. */
static int one(const bcase *c, const vi_model *m, int ns, const double *t,
               const double *x, double sigma, tally *ty)
{
  vi_identify *id = NULL;
  double p[2], se[2], l[2], h[2], pl[2], ph[2];
  double w0 = now();
  int np = c->nfit, acc = c->col == 3, uq = 0;
  int st = vi_identify_create(m, np, &id);
  if (!st) st = vi_identify_set_param(id, 0, VI_IDENTIFY_R, 0, c->start[0], 0, 1);
  if (!st && np > 1)
    st = vi_identify_set_param(id, 1, VI_IDENTIFY_XS, 0, c->start[1], 0.03, 0.07);
  if (!st) st = vi_identify_set_global(id, c->global);
  if (!st) st = vi_identify_set_sensors(id, ns, t, acc ? NULL : x, NULL, acc ? x : NULL);
  if (!st) st = vi_identify_run(id);
  double w = now() - w0;
  if (st || vi_identify_params(id, p, se, l, h, NULL) ||
      vi_identify_profile(id, pl, ph, NULL)) {
    fprintf(stderr, "vi_bench_identify: %s: %s\n", c->name, vi_identify_errmsg(id));
    vi_identify_destroy(&id);
    return 1;
  }
  int nsol = vi_identify_nsolutions(id, &uq), any = 0, tru = 0, on, om;
  double nz = NAN;
  vi_identify_summary(id, NULL, NULL, NULL, &nz, NULL, NULL, NULL);
  ty->nzlo = fmin(ty->nzlo, nz / sigma);
  ty->nzhi = fmax(ty->nzhi, nz / sigma);
  for (int k = 0; k < nsol; k++) {
    double q[2], qs[2], ql[2], qh[2];
    vi_identify_solution(id, k, q, qs, ql, qh, NULL);
    vi_identify_solution_summary(id, k, &on, &om, NULL, NULL, NULL, NULL);
    int in = 1;
    for (int j = 0; j < np; j++)
      in &= np > 1 ? fabs(q[j] - c->truth[j]) <= 3 * qs[j]
                   : ql[j] <= c->truth[j] && c->truth[j] <= qh[j];
    any |= in;
    tru |= in && on == 1 && om == 1; /* the recordings' own orbit type */
  }
  ty->cover_true += tru;
  vi_identify_destroy(&id);
  double e = p[0] - c->truth[0];
  ty->tsum += w;
  ty->tmax = fmax(ty->tmax, w);
  ty->sesum += se[0];
  ty->semin = fmin(ty->semin, se[0]);
  ty->e1 += e;
  ty->e2 += e * e;
  ty->hit += fabs(e) < 0.01 && fabs(e) < 1.96 * se[0];
  int cov = 1;
  for (int j = 0; j < np; j++)
    cov &= np > 1 ? fabs(p[j] - c->truth[j]) <= 3 * se[j] : l[j] <= c->truth[j] && c->truth[j] <= h[j];
  ty->cover += cov;
  ty->cover_any += any;
  ty->unique += uq;
  if (isfinite(pl[0]) && isfinite(ph[0]) && h[0] > l[0]) {
    ty->pwid += (ph[0] - pl[0]) / (h[0] - l[0]);
    ty->npw++;
  }
  return 0;
}

int main(int argc, char **argv)
{
  const char *dir = argc > 1 ? argv[1] : VI_IDENT_DATA;
  static const bcase cs[] = {
      {"beam4 r 0.2%/50T from 0.05", "beam4.csv", 1, 50, 1, 1, 0.002, {0.75, 0}, {0.05, 0}},
      {"beam4 r 0.2%/50T from 0.5", "beam4.csv", 1, 50, 1, 1, 0.002, {0.75, 0}, {0.5, 0}},
      {"beam4 r 0.2%/50T from 0.95", "beam4.csv", 1, 50, 1, 1, 0.002, {0.75, 0}, {0.95, 0}},
      {"beam4 r 0.2%/50T local 0.6", "beam4.csv", 1, 50, 1, 0, 0.002, {0.75, 0}, {0.6, 0}},
      {"beam4 r 1%/20T from 0.5", "beam4.csv", 1, 20, 1, 1, 0.01, {0.75, 0}, {0.5, 0}},
      {"beam4 r+xs 0.2%/50T (.05,.046)", "beam4.csv", 1, 50, 2, 1, 0.002, {0.75, 0.05}, {0.05, 0.046}},
      {"beam4 r+xs 0.2%/50T (.5,.045)", "beam4.csv", 1, 50, 2, 1, 0.002, {0.75, 0.05}, {0.5, 0.045}},
      {"beam4 r+xs 0.2%/50T (.95,.054)", "beam4.csv", 1, 50, 2, 1, 0.002, {0.75, 0.05}, {0.95, 0.054}},
      {"beam4 r+xs local (.7,.0495)", "beam4.csv", 1, 50, 2, 0, 0.002, {0.75, 0.05}, {0.7, 0.0495}},
      {"beam4 r, a only 0.2%/50T", "beam4_acc.csv", 3, 50, 1, 1, 0.002, {0.75, 0}, {0.5, 0}},
      {"fig2 r 0.2%/20T from 0.5", "fig2.csv", 1, 20, 1, 1, 0.002, {0.7, 0}, {0.5, 0}},
  };
  printf("%-31s %6s %6s %7s %7s %7s %5s %5s %5s %5s %5s %6s %11s\n", "case", "mean s",
         "max s", "stderr", "min se", "scatter", "hit", "cover", "any", "P11",
         "uniq", "prof/J", "noise/sig");
  for (size_t c = 0; c < sizeof cs / sizeof cs[0]; c++) {
    double t1[64], x1[64];
    int n1 = load(dir, cs[c].file, cs[c].col, t1, x1);
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
    int ns = 64 * cs[c].periods, seeds = 10;
    double *t = malloc(sizeof(double) * ns), *x = malloc(sizeof(double) * ns);
    tally ty;
    memset(&ty, 0, sizeof ty);
    ty.semin = ty.nzlo = HUGE_VAL;
    ty.nzhi = -HUGE_VAL;
    int isfig2 = !strcmp(cs[c].file, "fig2.csv");
    vi_model *m = isfig2 ? fig2() : beam(cs[c].nfit > 1 ? cs[c].start[1] : 0.05, cs[c].start[0]);
    gsl_rng *g = gsl_rng_alloc(gsl_rng_mt19937);
    for (int s = 1; s <= seeds; s++) {
      gsl_rng_set(g, (unsigned long)s);
      for (int i = 0; i < ns; i++) {
        t[i] = t1[i % 64] + floor(i / 64.0) * T;
        x[i] = x1[i % 64] + gsl_ran_gaussian(g, sigma);
      }
      if (one(&cs[c], m, ns, t, x, sigma, &ty)) return 1;
    }
    double scatter = sqrt((ty.e2 - ty.e1 * ty.e1 / seeds) / (seeds - 1));
    printf("%-31s %6.2f %6.2f %7.4f %7.4f %7.4f %2d/10 %2d/10 %2d/10 %2d/10 %2d/10 %6.3f %5.3f-%5.3f\n",
           cs[c].name, ty.tsum / seeds, ty.tmax, ty.sesum / seeds, ty.semin, scatter,
           ty.hit, ty.cover, ty.cover_any, ty.cover_true, ty.unique,
           ty.npw ? ty.pwid / ty.npw : NAN, ty.nzlo, ty.nzhi);
    fflush(stdout);
    gsl_rng_free(g);
    vi_model_destroy(&m);
    free(t);
    free(x);
  }
  return 0;
}
