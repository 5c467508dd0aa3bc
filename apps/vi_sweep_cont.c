/* vi_sweep_cont.c - a P(n,1) orbit followed in one scene parameter
 * (natural-parameter continuation with a secant predictor and step
 * halving), with the loss of stability located by bisection: a real
 * multiplier through -1 (period doubling), through +1 (fold or pitchfork),
 * a complex pair through the unit circle (Neimark-Sacker), and grazing (the
 * largest gap between impacts reaching the stop).  Folds themselves are
 * not passed: natural continuation stops there and says so. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vibroimpact.h"
#include "vibroimpact/vi_scene.h"
#include "vibroimpact/vi_scene_edit.h"
#include "vi_sweep.h"

typedef struct cstate {
  double p, t, vn, rho, gmax;
  int kind;     /* of the largest multiplier: 0 real < 0, 1 real > 0, 2 complex */
  double re, im;
  int ok;
} cstate;

/* Model at parameter value p (a new handle), or NULL with err. */
static vi_model *model_at(vi_scene_edit *ed, const char *key, double p,
                          char *err, int len)
{
  vi_diag d;
  vi_scene *sc = NULL;
  vi_model *m = NULL;
  memset(&d, 0, sizeof d);
  int st = vi_scene_edit_set_number(ed, key, p, &d);
  if (!st) st = vi_scene_edit_parse(ed, &sc, &d);
  if (!st) st = vi_scene_create_model(sc, &m, &d);
  if (st) {
    if (!d.code) {
      d.code = st;
      snprintf(d.message, sizeof d.message, "%s", vi_strerror(st));
    }
    vi_diag_format(&d, err, len);
  }
  vi_scene_destroy(&sc);
  return m;
}

/* Solve at p from the seed (t, x, v) (overwritten), and evaluate. */
static int solve_at(vi_scene_edit *ed, const char *key, int np, int N,
                    double p, double *t, double *x, double *v, cstate *c,
                    char *err, int len)
{
  vi_model *m = model_at(ed, key, p, err, len);
  if (!m) return -1;
  double re[64], im[64];
  int ok = 0, st = 2 * N > 64 ? VI_ERR_DIM : vi_orbit_pnm_solve(m, np, 1, t, x, v, N, 0.0, NULL);
  if (!st) st = vi_orbit_pnm_multipliers(m, np, 1, t, x, v, N, re, im);
  if (!st) st = vi_orbit_pnm_admissible(m, np, 1, t, x, v, N, &c->gmax, &ok);
  if (!st) {
    const double *w = vi_model_stop_vector(m);
    c->p = p;
    c->t = *t;
    c->vn = 0;
    for (int i = 0; i < N; i++) c->vn += w[i] * v[i];
    c->rho = 0;
    for (int i = 0; i < 2 * N; i++) {
      double r = hypot(re[i], im[i]);
      if (r > c->rho) {
        c->rho = r;
        c->re = re[i];
        c->im = im[i];
      }
    }
    c->kind = fabs(c->im) > 1e-9 * c->rho ? 2 : c->re > 0;
    c->ok = ok;
  }
  vi_model_destroy(&m);
  return st ? 1 : 0;
}

static const char *event_name(int kind)
{
  return kind == 0 ? "period_doubling" : kind == 1 ? "fold_or_pitchfork" : "neimark_sacker";
}

int vi_sweep_continue(const char *text, const char *name, const char *key,
                      double to, int steps, int np, const double *t0,
                      const double *x0, const double *v0, int N, int json,
                      char *err, int errlen)
{
  vi_scene_edit *ed = NULL;
  vi_diag d;
  char buf[64];
  int rc = 2;
  if (vi_scene_edit_create(text, -1, name, &ed, &d) ||
      vi_scene_edit_get(ed, key, buf, sizeof buf, &d)) {
    vi_diag_format(&d, err, errlen);
    vi_scene_edit_destroy(&ed);
    return 2;
  }
  double p0 = strtod(buf, NULL), h = (to - p0) / steps;
  double *z = malloc(sizeof(double) * (6 * (size_t)N + 2));
  if (!z) {
    vi_scene_edit_destroy(&ed);
    return 1;
  }
  double *x = z, *v = x + N, *xp = v + N, *vp = xp + N, *xs = vp + N, *vs = xs + N;
  double t = *t0, tp, ts;
  memcpy(x, x0, sizeof(double) * N);
  memcpy(v, v0, sizeof(double) * N);
  cstate c, prev;
  if (solve_at(ed, key, np, N, p0, &t, x, v, &c, err, errlen)) goto done;
  rc = 0;
  if (json) printf("{\"key\": \"%s\", \"n\": %d, \"m\": 1, \"branch\": [", key, np);
  else printf("P(%d,1) orbit followed in %s from %.10g to %.10g\n  %14s %14s %12s %8s %s\n",
              np, key, p0, to, key, "v_N", "max|mu|", "stable", "admissible");
  int nev = 0, npts = 0;
  double step = h;
  char events[4096] = "";
  for (;;) {
    if (json)
      printf("%s{\"param\": %.17g, \"vN\": %.17g, \"impact_time\": %.17g, \"max_multiplier\": %.17g, "
             "\"stable\": %s, \"admissible\": %s}", npts ? ", " : "", c.p, c.vn, c.t, c.rho,
             c.rho < 1 ? "true" : "false", c.ok ? "true" : "false");
    else
      printf("  %14.10g %14.10g %12.8g %8s %s\n", c.p, c.vn, c.rho,
             c.rho < 1 ? "yes" : "no", c.ok ? "yes" : "no");
    if (npts++) {
      /* a crossing between prev and c: bisection on p, each point solved
       * from the orbit at c */
      /* e = 0: stability; 1: an interior maximum of the gap touches the
       * stop; 2: the impact velocity goes through 0 (grazing impact) */
      int cross[3] = {(prev.rho < 1) != (c.rho < 1), (prev.gmax < 0) != (c.gmax < 0),
                      (prev.vn > 0) != (c.vn > 0)};
      if (prev.vn <= 0 && c.vn <= 0) cross[1] = 0; /* no impact: no contact */
      for (int e = 0; e < 3; e++) {
        if (!cross[e]) continue;
        double a = prev.p, b = c.p;
        double fa = e == 0 ? prev.rho - 1 : e == 1 ? prev.gmax : prev.vn;
        cstate mid = c;
        for (int it = 0; it < 60 && fabs(b - a) > 1e-13 * fmax(1.0, fabs(b)); it++) {
          double pm = 0.5 * (a + b);
          memcpy(xs, x, sizeof(double) * N);
          memcpy(vs, v, sizeof(double) * N);
          ts = t;
          if (solve_at(ed, key, np, N, pm, &ts, xs, vs, &mid, err, errlen)) break;
          double fm = e == 0 ? mid.rho - 1 : e == 1 ? mid.gmax : mid.vn;
          if ((fm < 0) == (fa < 0)) {
            a = pm;
            fa = fm;
          } else {
            b = pm;
          }
        }
        int k = (int)strlen(events);
        if (e)
          snprintf(events + k, sizeof events - (size_t)k,
                   "%s{\"type\": \"%s\", \"param\": %.17g, \"vN\": %.17g}",
                   nev++ ? ", " : "", e == 1 ? "grazing" : "grazing_impact", mid.p, mid.vn);
        else
          snprintf(events + k, sizeof events - (size_t)k,
                   "%s{\"type\": \"%s\", \"param\": %.17g, \"multiplier\": [%.17g, %.17g]}",
                   nev++ ? ", " : "", event_name(mid.kind), mid.p, mid.re, mid.im);
        if (!json)
          printf("    -> %s at %s = %.12g%s\n",
                 e == 0 ? event_name(mid.kind) : e == 1 ? "grazing" : "grazing impact",
                 key, mid.p,
                 e == 0 ? " (a multiplier on the unit circle)"
                 : e == 1 ? " (the gap between impacts touches the stop)"
                          : " (v_N = 0)");
      }
    }
    if ((to - c.p) * h <= 1e-12 * fabs(h)) break; /* reached the end */
    /* next point from this orbit; halve the step when Newton fails */
    prev = c;
    memcpy(xp, x, sizeof(double) * N);
    memcpy(vp, v, sizeof(double) * N);
    tp = t;
    int got = 0;
    while (!got && fabs(step) >= fabs(h) / 64) {
      double pn = (to - (prev.p + step)) * h < 0 ? to : prev.p + step;
      t = tp;
      memcpy(x, xp, sizeof(double) * N);
      memcpy(v, vp, sizeof(double) * N);
      got = !solve_at(ed, key, np, N, pn, &t, x, v, &c, err, errlen);
      if (!got) step /= 2;
    }
    if (!got) {
      /* where Newton stops finding the orbit: bisection between the last
       * success and the smallest failed step, each try seeded from the
       * latest success (at a fold a multiplier approaches +1) */
      double a = prev.p, b = prev.p + 2 * step;
      cstate ca = prev, cm;
      t = tp;
      memcpy(x, xp, sizeof(double) * N);
      memcpy(v, vp, sizeof(double) * N);
      for (int it = 0; it < 50 && fabs(b - a) > 1e-12 * fmax(1.0, fabs(a)); it++) {
        double pm = 0.5 * (a + b);
        memcpy(xs, x, sizeof(double) * N);
        memcpy(vs, v, sizeof(double) * N);
        ts = t;
        if (!solve_at(ed, key, np, N, pm, &ts, xs, vs, &cm, err, errlen)) {
          a = pm;
          ca = cm;
          t = ts;
          memcpy(x, xs, sizeof(double) * N);
          memcpy(v, vs, sizeof(double) * N);
        } else {
          b = pm;
        }
      }
      if (!json)
        printf("  the branch ends at %s = %.12g (v_N %.10g, largest multiplier "
               "%.6g%+.6gi): a fold, or the orbit stops impacting\n", key, a,
               ca.vn, ca.re, ca.im);
      int k = (int)strlen(events);
      snprintf(events + k, sizeof events - (size_t)k,
               "%s{\"type\": \"lost\", \"param\": %.17g, \"vN\": %.17g, "
               "\"multiplier\": [%.17g, %.17g]}", nev++ ? ", " : "", a, ca.vn, ca.re, ca.im);
      break;
    }
    step = fabs(2 * step) < fabs(h) ? 2 * step : h;
  }
  if (json) printf("], \"events\": [%s]}\n", events);
done:
  free(z);
  vi_scene_edit_destroy(&ed);
  return rc;
}
