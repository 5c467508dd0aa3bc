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

/* ---- pseudo-arclength: around folds --------------------------------------- */
/* Dense solve A y = b (A [k x k] column-major, overwritten), partial
 * pivoting; 0 or 1 if singular. */
static int gauss(int k, double *A, double *b)
{
  for (int c = 0; c < k; c++) {
    int p = c;
    for (int r = c + 1; r < k; r++)
      if (fabs(A[r + (size_t)c * k]) > fabs(A[p + (size_t)c * k])) p = r;
    if (!(fabs(A[p + (size_t)c * k]) > 0)) return 1;
    if (p != c) {
      for (int j = 0; j < k; j++) {
        double tmp = A[c + (size_t)j * k];
        A[c + (size_t)j * k] = A[p + (size_t)j * k];
        A[p + (size_t)j * k] = tmp;
      }
      double tmp = b[c];
      b[c] = b[p];
      b[p] = tmp;
    }
    for (int r = c + 1; r < k; r++) {
      double f = A[r + (size_t)c * k] / A[c + (size_t)c * k];
      if (f == 0) continue;
      for (int j = c; j < k; j++) A[r + (size_t)j * k] -= f * A[c + (size_t)j * k];
      b[r] -= f * b[c];
    }
  }
  for (int c = k - 1; c >= 0; c--) {
    double s = b[c];
    for (int j = c + 1; j < k; j++) s -= A[c + (size_t)j * k] * b[j];
    b[c] = s / A[c + (size_t)c * k];
  }
  return 0;
}

/* The parameter vi_orbit_pnm_dparam differentiates exactly, or -1 for a
 * key it does not know (an amplitude, a stiffness, ...). */
static int exact_param(const char *key)
{
  if (!strcmp(key, "forcing.omega")) return VI_ORBIT_PARAM_OMEGA;
  if (!strcmp(key, "stop.xs")) return VI_ORBIT_PARAM_XS;
  if (!strcmp(key, "stop.r")) return VI_ORBIT_PARAM_R;
  return -1;
}

/* F(u; p) [D] and, with Ja, the extended Jacobian's first D rows
 * [J_u | dF/dp] (Ja [(D+1) x (D+1)], leading dimension D+1): J_u exact;
 * dF/dp exact for forcing.omega, stop.xs and stop.r (vi_orbit_pnm_dparam),
 * by central differences in p (the model rebuilt at p +- dp) for any
 * other key. */
static int ext_residual(vi_scene_edit *ed, const char *key, int np, int N,
                        const double *U, double *F, double *Ja, char *err, int len)
{
  int D = 2 * N + 1, K = D + 1, st, par = exact_param(key);
  double p = U[D];
  vi_model *m = model_at(ed, key, p, err, len);
  if (!m) return -1;
  double *J = Ja ? malloc(sizeof(double) * (size_t)D * D + sizeof(double) * 2 * D) : NULL;
  if (Ja && !J) {
    vi_model_destroy(&m);
    return VI_ERR_NOMEM;
  }
  st = vi_orbit_pnm_residual(m, np, 1, U, U + 1, U + 1 + N, N, F, J);
  if (!st && Ja && par >= 0) {
    double *dF = J + (size_t)D * D;
    st = vi_orbit_pnm_dparam(m, np, 1, NULL, U, U + 1, U + 1 + N, N, par, 0, dF);
    for (int r = 0; r < D && !st; r++) Ja[r + (size_t)D * K] = dF[r];
  }
  vi_model_destroy(&m);
  if (st || !Ja) {
    free(J);
    return st;
  }
  for (int c = 0; c < D; c++)
    for (int r = 0; r < D; r++) Ja[r + (size_t)c * K] = J[r + (size_t)c * D];
  if (par >= 0) {
    free(J);
    return VI_OK;
  }
  double dp = 1e-6 * fmax(1.0, fabs(p)), *Fp = J + (size_t)D * D, *Fm = Fp + D;
  vi_model *mp = model_at(ed, key, p + dp, err, len), *mm = model_at(ed, key, p - dp, err, len);
  st = !mp || !mm ? -1 : vi_orbit_pnm_residual(mp, np, 1, U, U + 1, U + 1 + N, N, Fp, NULL);
  if (!st) st = vi_orbit_pnm_residual(mm, np, 1, U, U + 1, U + 1 + N, N, Fm, NULL);
  for (int r = 0; r < D && !st; r++) Ja[r + (size_t)D * K] = (Fp[r] - Fm[r]) / (2 * dp);
  vi_model_destroy(&mp);
  vi_model_destroy(&mm);
  free(J);
  return st;
}

/* Tangent of the branch at U: the null vector of [J_u | F_p], normalised,
 * oriented along `dir` (the previous tangent). */
static int tangent(vi_scene_edit *ed, const char *key, int np, int N,
                   const double *U, const double *dir, double *tau, char *err, int len)
{
  int D = 2 * N + 1, K = D + 1;
  double *A = malloc(sizeof(double) * ((size_t)K * K + D));
  if (!A) return VI_ERR_NOMEM;
  int st = ext_residual(ed, key, np, N, U, A + (size_t)K * K, A, err, len);
  if (!st) {
    for (int c = 0; c < K; c++) A[D + (size_t)c * K] = dir[c];
    for (int r = 0; r < K; r++) tau[r] = r == D;
    st = gauss(K, A, tau) ? VI_ERR_NOT_CONVERGED : VI_OK;
  }
  if (!st) {
    double nrm = 0, dot = 0;
    for (int r = 0; r < K; r++) nrm += tau[r] * tau[r];
    nrm = sqrt(nrm);
    for (int r = 0; r < K; r++) {
      tau[r] /= nrm;
      dot += tau[r] * dir[r];
    }
    if (dot < 0)
      for (int r = 0; r < K; r++) tau[r] = -tau[r];
  }
  free(A);
  return st;
}

int vi_sweep_arclength(const char *text, const char *name, const char *key,
                       double to, int steps, int np, const double *t0,
                       const double *x0, const double *v0, int N, int json,
                       char *err, int errlen)
{
  vi_scene_edit *ed = NULL;
  vi_diag d;
  char buf[64];
  if (vi_scene_edit_create(text, -1, name, &ed, &d) ||
      vi_scene_edit_get(ed, key, buf, sizeof buf, &d)) {
    vi_diag_format(&d, err, errlen);
    vi_scene_edit_destroy(&ed);
    return 2;
  }
  int D = 2 * N + 1, K = D + 1, rc = 1;
  double p0 = strtod(buf, NULL);
  double *U = malloc(sizeof(double) * (7 * (size_t)K + (size_t)K * K));
  if (!U) {
    vi_scene_edit_destroy(&ed);
    return 1;
  }
  double *tau = U + K, *Un = tau + K, *F = Un + K, *dir = F + K, *Up = dir + K, *U0 = Up + K,
         *A = U0 + K;
  U[0] = *t0;
  memcpy(U + 1, x0, sizeof(double) * N);
  memcpy(U + 1 + N, v0, sizeof(double) * N);
  U[D] = p0;
  memcpy(U0, U, sizeof(double) * K);
  for (int r = 0; r < K; r++) dir[r] = r == D ? (to > p0 ? 1 : -1) : 0;
  /* arclength step in the scaled space: the whole range in `steps` */
  double ds = fabs(to - p0) / steps, dsmax = ds, s = 0;
  double hs[3] = {0, 0, 0}, hp[3] = {p0, p0, p0}; /* last 3 points (s, p) */
  int nev = 0, npts = 0, prev_stable = -1;
  double prev_p = p0, prev_rho = 0, prev_vn = 0, prev_g = 0;
  char events[4096] = "";
  if (json) printf("{\"key\": \"%s\", \"n\": %d, \"m\": 1, \"method\": \"pseudo-arclength\", \"branch\": [", key, np);
  else printf("P(%d,1) orbit followed in %s from %.10g towards %.10g by pseudo-arclength\n"
              "  %14s %14s %12s %8s %s\n", np, key, p0, to, key, "v_N", "max|mu|", "stable", "admissible");
  for (int step = 0; step < 10 * steps; step++) {
    /* the orbit at U: multipliers, admissibility */
    cstate c;
    double tt = U[0];
    memcpy(Un, U + 1, sizeof(double) * 2 * N);
    if (solve_at(ed, key, np, N, U[D], &tt, Un, Un + N, &c, err, errlen)) break;
    if (json)
      printf("%s{\"param\": %.17g, \"vN\": %.17g, \"impact_time\": %.17g, \"max_multiplier\": %.17g, "
             "\"stable\": %s, \"admissible\": %s}", npts ? ", " : "", c.p, c.vn, c.t, c.rho,
             c.rho < 1 ? "true" : "false", c.ok ? "true" : "false");
    else
      printf("  %14.10g %14.10g %12.8g %8s %s\n", c.p, c.vn, c.rho, c.rho < 1 ? "yes" : "no",
             c.ok ? "yes" : "no");
    if (prev_stable >= 0 && prev_stable != (c.rho < 1)) {
      double pe = prev_p + (c.p - prev_p) * (1 - prev_rho) / (c.rho - prev_rho);
      int k = (int)strlen(events);
      snprintf(events + k, sizeof events - (size_t)k,
               "%s{\"type\": \"%s\", \"param\": %.17g, \"admissible\": %s}", nev++ ? ", " : "",
               event_name(c.kind), pe, c.ok ? "true" : "false");
      if (!json) printf("    -> %s near %s = %.10g%s\n", event_name(c.kind), key, pe,
                        c.ok ? "" : " (not admissible)");
    }
    if (prev_stable >= 0 && ((prev_vn > 0) != (c.vn > 0) ||
                             ((prev_g < 0) != (c.gmax < 0) && (prev_vn > 0 || c.vn > 0)))) {
      int imp = (prev_vn > 0) != (c.vn > 0); /* v_N through 0, else the gap */
      double f0 = imp ? prev_vn : prev_g, f1 = imp ? c.vn : c.gmax;
      double pe = prev_p + (c.p - prev_p) * f0 / (f0 - f1);
      int k = (int)strlen(events);
      snprintf(events + k, sizeof events - (size_t)k,
               "%s{\"type\": \"%s\", \"param\": %.17g}", nev++ ? ", " : "",
               imp ? "grazing_impact" : "grazing", pe);
      if (!json) printf("    -> %s near %s = %.10g\n", imp ? "grazing impact" : "grazing", key, pe);
    }
    prev_stable = c.rho < 1;
    prev_p = c.p;
    prev_rho = c.rho;
    prev_vn = c.vn;
    prev_g = c.gmax;
    hs[0] = hs[1]; hs[1] = hs[2]; hs[2] = s;
    hp[0] = hp[1]; hp[1] = hp[2]; hp[2] = U[D];
    npts++;
    if (npts > 1 && (U[D] - to) * (p0 < to ? 1 : -1) >= 0) {
      rc = 0;
      break;
    }
    /* a closed branch (an isola) is done once it comes back to its start */
    if (npts > 3 && fabs(U[D] - p0) < 0.5 * dsmax) {
      /* impact times compare modulo the forcing period */
      vi_model *m = model_at(ed, key, U[D], err, errlen);
      double T = m ? 2 * M_PI / vi_model_omega_forcing(m) : HUGE_VAL;
      vi_model_destroy(&m);
      double dt = fmod(fabs(U[0] - U0[0]), T), dist = fmin(dt, T - dt);
      for (int r = 1; r < K; r++) dist = fmax(dist, fabs(U[r] - U0[r]));
      if (dist < 0.5 * dsmax) {
        int k = (int)strlen(events);
        snprintf(events + k, sizeof events - (size_t)k,
                 "%s{\"type\": \"closed\", \"param\": %.17g}", nev++ ? ", " : "", U[D]);
        if (!json) printf("  the branch closes on itself at %s = %.10g\n", key, U[D]);
        rc = 0;
        break;
      }
    }
    if (tangent(ed, key, np, N, U, dir, tau, err, errlen)) break;
    /* a fold: dp/ds changes sign; its parameter from the parabola through
     * the last three points */
    if (npts >= 3 && tau[D] * dir[D] < 0) {
      double a1 = (hp[1] - hp[0]) / (hs[1] - hs[0]), a2 = (hp[2] - hp[1]) / (hs[2] - hs[1]);
      double c2 = (a2 - a1) / (hs[2] - hs[0]), sv = 0.5 * (hs[0] + hs[1]) - a1 / (2 * c2);
      double pf = hp[0] + a1 * (sv - hs[0]) + c2 * (sv - hs[0]) * (sv - hs[1]);
      int k = (int)strlen(events);
      snprintf(events + k, sizeof events - (size_t)k,
               "%s{\"type\": \"fold\", \"param\": %.17g, \"admissible\": %s}", nev++ ? ", " : "",
               pf, c.ok ? "true" : "false");
      if (!json) printf("    -> fold at %s = %.12g (the branch turns back)%s\n", key, pf,
                        c.ok ? "" : " (not admissible)");
    }
    memcpy(dir, tau, sizeof(double) * K);
    /* predictor-corrector: Newton on F = 0, tau.(U - Up) = 0 */
    int ok = 0;
    while (!ok && ds > dsmax / 1024) {
      for (int r = 0; r < K; r++) Up[r] = U[r] + ds * tau[r];
      memcpy(Un, Up, sizeof(double) * K);
      for (int it = 0; it < 20; it++) {
        if (ext_residual(ed, key, np, N, Un, F, A, err, errlen)) break;
        double fn = 0, sc = 1e-12;
        for (int r = 0; r < D; r++) fn = fmax(fn, fabs(F[r]));
        for (int r = 1; r < D; r++) sc = fmax(sc, fabs(Un[r]));
        F[D] = 0;
        for (int r = 0; r < K; r++) F[D] += tau[r] * (Un[r] - Up[r]);
        if (fn <= 1e-11 * sc && fabs(F[D]) <= 1e-11 * (1 + ds)) {
          ok = 1;
          break;
        }
        for (int c2 = 0; c2 < K; c2++) A[D + (size_t)c2 * K] = tau[c2];
        if (gauss(K, A, F)) break;
        for (int r = 0; r < K; r++) Un[r] -= F[r];
      }
      if (!ok) ds /= 2;
    }
    if (!ok) {
      if (!json) printf("  the corrector fails after %s = %.12g\n", key, U[D]);
      break;
    }
    s += ds;
    memcpy(U, Un, sizeof(double) * K);
    ds = fmin(dsmax, 1.5 * ds);
  }
  if (json) printf("], \"events\": [%s]}\n", events);
  free(U);
  vi_scene_edit_destroy(&ed);
  return rc == 1 && npts ? 0 : rc;
}
