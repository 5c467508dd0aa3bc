/* vi_orbit_pnm.c - P(n, m) orbits found directly: Newton on the impact
 * conditions with the closed-form flow, an exhaustive impact-phase scan for
 * P(n, 1), admissibility, and Floquet multipliers from the monodromy matrix
 * with the saltation matrix at each impact.
 *
 * An orbit is its m impacts in one orbit period nT: times t_j and the
 * states just before them, (x_j, v_j).  Between impacts the motion is the
 * free flow (vi_flow_physical), which is affine in the state:
 *   z(t) = Phi(t - t0) z0 + c(t0, t),
 * so D_z0 z(t) = Phi is the difference of two flows with no truncation
 * error, and the time derivatives are the vector field itself.  These are
 * the exact derivatives of the variational flow, up to round-off. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <lapacke.h>

#include "vi_flow_internal.h"

typedef struct ws {
  const vi_model *m;
  int n, n2;
  double *Q;   /* velocity impact map [n x n] (WB 2) */
  double *buf; /* scratch */
  vi_xflow *fl; /* the exact flow, built once per call (vi_flow_internal.h) */
} ws;

static int ws_init(ws *w, const vi_model *m)
{
  int n = m->n;
  w->m = m;
  w->n = n;
  w->n2 = 2 * n;
  w->Q = malloc(sizeof(double) * ((size_t)n * n + 16 * (size_t)n));
  w->buf = w->Q ? w->Q + (size_t)n * n : NULL;
  if (!w->Q) return VI_ERR_NOMEM;
  /* Q = I - (1 + r) M^-1 w w^T / (w^T M^-1 w) */
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++)
      w->Q[i + (size_t)j * n] =
          (i == j) - (1.0 + m->r) * m->Minv_w[i] * m->w[j] / m->wMw;
  int st = vi_xflow_create(m, &w->fl);
  if (st) free(w->Q);
  return st;
}

static void ws_free(ws *w)
{
  vi_xflow_destroy(&w->fl);
  free(w->Q);
}

/* f = z' = (v, M^-1 (f(t) - C v - K x)) */
static void field(const vi_model *m, double t, const double *z, double *f)
{
  int n = m->n;
  double c = cos(m->omega_f * t), s = sin(m->omega_f * t);
  memcpy(f, z + n, sizeof(double) * n);
  for (int i = 0; i < n; i++) {
    double a = m->Minv_a[i] * c + m->Minv_b[i] * s + m->Minv_f0[i];
    for (int k = 0; k < n; k++)
      a -= m->MinvK[i + (size_t)k * n] * z[k] + m->MinvC[i + (size_t)k * n] * z[n + k];
    f[n + i] = a;
  }
}

static int flow(const ws *w, double t0, const double *z0, double t1,
                double *z1)
{
  int n = w->n;
  if (!(t1 >= t0)) return VI_ERR_TIME;
  return vi_xflow_physical(w->fl, w->m, t0, z0, z0 + n, t1, z1, z1 + n);
}

/* Phi(t1 - t0) [2n x 2n] by the affine difference; c = flow of 0. */
static int stm(const ws *w, double t0, double t1, double *Phi,
               double *e, double *c)
{
  int n2 = w->n2, st;
  memset(e, 0, sizeof(double) * n2);
  if ((st = flow(w, t0, e, t1, c))) return st;
  for (int j = 0; j < n2; j++) {
    e[j] = 1.0;
    st = flow(w, t0, e, t1, Phi + (size_t)j * n2);
    e[j] = 0.0;
    if (st) return st;
    for (int i = 0; i < n2; i++) Phi[i + (size_t)j * n2] -= c[i];
  }
  return VI_OK;
}

/* post-impact state zp = (x, Q v) of the pre-impact z */
static void impact(const ws *w, const double *z, double *zp)
{
  int n = w->n;
  memcpy(zp, z, sizeof(double) * n);
  vi_matvec(n, w->Q, z + n, zp + n);
}

/* unknowns u = [t_j, x_j, v_j] for j = 0..m-1 (2n + 1 each) */
static int residual(const ws *w, int np, int mi, const double *u, double *F,
                    double *J, int want_j)
{
  const vi_model *m = w->m;
  int n = w->n, n2 = w->n2, B = n2 + 1, D = mi * B, st;
  double T = 2.0 * M_PI / m->omega_f;
  double *zp = malloc(sizeof(double) * ((size_t)n2 * n2 + 6 * (size_t)n2));
  if (!zp) return VI_ERR_NOMEM;
  double *ze = zp + n2, *f0 = ze + n2, *f1 = f0 + n2, *e = f1 + n2,
         *c = e + n2, *Phi = c + n2;
  if (want_j) memset(J, 0, sizeof(double) * (size_t)D * D);
  for (int j = 0; j < mi; j++) {
    int k = (j + 1) % mi;
    const double *uj = u + (size_t)j * B, *uk = u + (size_t)k * B;
    double t0 = uj[0], t1 = uk[0] + (j + 1 == mi ? np * T : 0.0);
    if (!(t1 > t0)) {
      free(zp);
      return VI_ERR_NOT_CONVERGED; /* impacts out of order */
    }
    impact(w, uj + 1, zp);
    if ((st = flow(w, t0, zp, t1, ze))) {
      free(zp);
      return st;
    }
    double *Fj = F + (size_t)j * B;
    for (int i = 0; i < n2; i++) Fj[i] = ze[i] - uk[1 + i];
    Fj[n2] = vi_dot(n, m->w, uj + 1) - m->xs;
    if (!want_j) continue;
    if ((st = stm(w, t0, t1, Phi, e, c))) {
      free(zp);
      return st;
    }
    field(m, t0, zp, f0);
    field(m, t1, ze, f1);
    /* rows of segment j: columns of block j (t, x, v) and of block k */
    for (int i = 0; i < n2; i++) {
      size_t row = (size_t)j * B + i;
      double dt0 = 0.0;
      for (int q = 0; q < n2; q++) dt0 -= Phi[i + (size_t)q * n2] * f0[q];
      J[row + (size_t)(j * B) * D] += dt0;
      J[row + (size_t)(k * B) * D] += f1[i];
      for (int q = 0; q < n; q++) /* d/dx_j */
        J[row + (size_t)(j * B + 1 + q) * D] += Phi[i + (size_t)q * n2];
      for (int q = 0; q < n; q++) { /* d/dv_j through Q */
        double s = 0.0;
        for (int p = 0; p < n; p++)
          s += Phi[i + (size_t)(n + p) * n2] * w->Q[p + (size_t)q * n];
        J[row + (size_t)(j * B + 1 + n + q) * D] += s;
      }
      J[row + (size_t)(k * B + 1 + i) * D] -= 1.0;
    }
    for (int q = 0; q < n; q++) /* the impact condition w.x_j = x_s */
      J[(size_t)j * B + n2 + (size_t)(j * B + 1 + q) * D] = m->w[q];
  }
  free(zp);
  return VI_OK;
}

static double norm_inf(int k, const double *x)
{
  double s = 0.0;
  for (int i = 0; i < k; i++) s = fmax(s, fabs(x[i]));
  return s;
}

int vi_orbit_pnm_solve(const vi_model *m, int np, int mi, double *t,
                       double *x, double *v, int ld, double tol, int *iters)
{
  if (!m || !t || !x || !v || np < 1 || mi < 1 || ld < (m ? m->n : 1))
    return VI_ERR_ARG;
  if (!m->frozen) return VI_ERR_STATE;
  if (m->ns > 1) return VI_ERR_UNSUPPORTED; /* the impact map of one stop */
  if (!vi_xflow_available(m)) return VI_ERR_UNSUPPORTED;
  if (!(m->omega_f > 0.0)) return VI_ERR_FREQUENCY;
  ws w;
  int st = ws_init(&w, m), n = m->n, B = 2 * n + 1, D = mi * B, it = 0;
  if (st) return st;
  double *u = malloc(sizeof(double) * ((size_t)D * D + 3 * (size_t)D));
  lapack_int *piv = malloc(sizeof(lapack_int) * (size_t)D);
  if (!u || !piv) {
    st = VI_ERR_NOMEM;
    goto cleanup;
  }
  double *F = u + D, *du = F + D, *J = du + D;
  for (int j = 0; j < mi; j++) {
    u[(size_t)j * B] = t[j];
    memcpy(u + (size_t)j * B + 1, x + (size_t)j * ld, sizeof(double) * n);
    memcpy(u + (size_t)j * B + 1 + n, v + (size_t)j * ld, sizeof(double) * n);
  }
  double scale = fabs(m->xs);
  for (int i = 0; i < D; i++)
    if (i % B) scale = fmax(scale, fabs(u[i]));
  if (!(tol > 0.0)) tol = 1e-12;
  st = VI_ERR_NOT_CONVERGED;
  for (it = 0; it < 40; it++) {
    int rs = residual(&w, np, mi, u, F, J, 1);
    if (rs) {
      st = rs == VI_ERR_NOMEM ? rs : VI_ERR_NOT_CONVERGED;
      break;
    }
    double r = norm_inf(D, F);
    /* the closed-form flow is exact to round-off: a residual of a few
     * hundred ulps of the state is what it can deliver */
    if (r <= tol * scale) {
      st = VI_OK;
      break;
    }
    memcpy(du, F, sizeof(double) * D);
    if (LAPACKE_dgesv(LAPACK_COL_MAJOR, D, 1, J, D, piv, du, D) != 0) break;
    /* damped step: never more than a tenth of a period in time, nor
     * twice the state scale */
    double lam = 1.0, T = 2.0 * M_PI / m->omega_f;
    for (int i = 0; i < D; i++) {
      double lim = i % B ? 2.0 * scale : 0.1 * T;
      if (fabs(du[i]) * lam > lim) lam = lim / fabs(du[i]);
    }
    for (int i = 0; i < D; i++) u[i] -= lam * du[i];
  }
  if (st == VI_OK)
    for (int j = 0; j < mi; j++) {
      t[j] = u[(size_t)j * B];
      memcpy(x + (size_t)j * ld, u + (size_t)j * B + 1, sizeof(double) * n);
      memcpy(v + (size_t)j * ld, u + (size_t)j * B + 1 + n, sizeof(double) * n);
    }
cleanup:
  if (iters) *iters = it;
  free(piv);
  free(u);
  ws_free(&w);
  return st;
}

int vi_orbit_pnm_residual(const vi_model *m, int np, int mi, const double *t,
                          const double *x, const double *v, int ld, double *F,
                          double *J)
{
  if (!m || !t || !x || !v || !F || np < 1 || mi < 1 || ld < (m ? m->n : 1))
    return VI_ERR_ARG;
  if (!m->frozen) return VI_ERR_STATE;
  if (m->ns > 1) return VI_ERR_UNSUPPORTED; /* the impact map of one stop */
  if (!vi_xflow_available(m)) return VI_ERR_UNSUPPORTED;
  if (!(m->omega_f > 0.0)) return VI_ERR_FREQUENCY;
  ws w;
  int st = ws_init(&w, m), n = m->n, B = 2 * n + 1, D = mi * B;
  if (st) return st;
  double *u = malloc(sizeof(double) * (size_t)D);
  if (!u) {
    ws_free(&w);
    return VI_ERR_NOMEM;
  }
  for (int j = 0; j < mi; j++) {
    u[(size_t)j * B] = t[j];
    memcpy(u + (size_t)j * B + 1, x + (size_t)j * ld, sizeof(double) * n);
    memcpy(u + (size_t)j * B + 1 + n, v + (size_t)j * ld, sizeof(double) * n);
  }
  st = residual(&w, np, mi, u, F, J, J != NULL);
  free(u);
  ws_free(&w);
  return st;
}

int vi_orbit_pnm_multipliers(const vi_model *m, int np, int mi,
                             const double *t, const double *x, const double *v,
                             int ld, double *re, double *im)
{
  if (!m || !t || !x || !v || !re || !im || np < 1 || mi < 1 || ld < (m ? m->n : 1))
    return VI_ERR_ARG;
  if (!m->frozen) return VI_ERR_STATE;
  if (m->ns > 1) return VI_ERR_UNSUPPORTED; /* the impact map of one stop */
  if (!vi_xflow_available(m)) return VI_ERR_UNSUPPORTED;
  ws w;
  int st = ws_init(&w, m), n = m->n, n2 = 2 * n;
  if (st) return st;
  double T = 2.0 * M_PI / m->omega_f;
  size_t nn = (size_t)n2 * n2;
  double *Mo = malloc(sizeof(double) * (4 * nn + 8 * (size_t)n2));
  if (!Mo) {
    ws_free(&w);
    return VI_ERR_NOMEM;
  }
  double *S = Mo + nn, *Phi = S + nn, *tmp = Phi + nn, *z = tmp + nn,
         *zp = z + n2, *fm = zp + n2, *fp = fm + n2, *e = fp + n2, *c = e + n2;
  for (size_t i = 0; i < nn; i++) Mo[i] = 0.0;
  for (int i = 0; i < n2; i++) Mo[i + (size_t)i * n2] = 1.0;
  for (int j = 0; j < mi && !st; j++) {
    memcpy(z, x + (size_t)j * ld, sizeof(double) * n);
    memcpy(z + n, v + (size_t)j * ld, sizeof(double) * n);
    impact(&w, z, zp);
    field(m, t[j], z, fm);
    field(m, t[j], zp, fp);
    /* saltation S = R + (f+ - R f-) g^T / (g^T f-), g = (w, 0), R =
     * diag(I, Q): the jump of the flow's derivative across the impact */
    double gf = vi_dot(n, m->w, z + n);
    double *Rf = e;
    impact(&w, fm, Rf);
    for (int b = 0; b < n2; b++)
      for (int a = 0; a < n2; a++) {
        double R = a < n ? (a == b) : (b >= n ? w.Q[(a - n) + (size_t)(b - n) * n] : 0.0);
        double g = b < n ? m->w[b] : 0.0;
        S[a + (size_t)b * n2] = R + (fp[a] - Rf[a]) * g / gf;
      }
    double t1 = j + 1 < mi ? t[j + 1] : t[0] + np * T;
    if ((st = stm(&w, t[j], t1, Phi, e, c))) break;
    /* Mo <- Phi S Mo */
    for (size_t i = 0; i < nn; i++) tmp[i] = 0.0;
    for (int b = 0; b < n2; b++)
      for (int k = 0; k < n2; k++)
        for (int a = 0; a < n2; a++)
          tmp[a + (size_t)b * n2] += S[a + (size_t)k * n2] * Mo[k + (size_t)b * n2];
    for (size_t i = 0; i < nn; i++) Mo[i] = 0.0;
    for (int b = 0; b < n2; b++)
      for (int k = 0; k < n2; k++)
        for (int a = 0; a < n2; a++)
          Mo[a + (size_t)b * n2] += Phi[a + (size_t)k * n2] * tmp[k + (size_t)b * n2];
  }
  if (!st &&
      LAPACKE_dgeev(LAPACK_COL_MAJOR, 'N', 'N', n2, Mo, n2, re, im, NULL, 1,
                    NULL, 1) != 0)
    st = VI_ERR_LAPACK;
  free(Mo);
  ws_free(&w);
  return st;
}

/* gap w.x - x_s of the free flow from (t0, zp) at t */
static double gap_at(const ws *w, double t0, const double *zp, double t,
                     double *z)
{
  if (flow(w, t0, zp, t, z)) return NAN;
  return vi_dot(w->n, w->m->w, z) - w->m->xs;
}

int vi_orbit_pnm_admissible(const vi_model *m, int np, int mi,
                            const double *t, const double *x, const double *v,
                            int ld, double *gmax, int *ok)
{
  if (!m || !t || !x || !v || !ok || np < 1 || mi < 1 || ld < (m ? m->n : 1))
    return VI_ERR_ARG;
  if (!m->frozen) return VI_ERR_STATE;
  if (m->ns > 1) return VI_ERR_UNSUPPORTED; /* the impact map of one stop */
  if (m->band) return VI_ERR_UNSUPPORTED; /* no modes: vi_band.c */
  ws w;
  int st = ws_init(&w, m), n = m->n;
  if (st) return st;
  double T = 2.0 * M_PI / m->omega_f, worst = -HUGE_VAL;
  double *z = w.buf, *zp = z + (size_t)2 * n, *zz = zp + (size_t)2 * n;
  double scale = fabs(m->xs);
  for (int j = 0; j < mi; j++) scale = fmax(scale, norm_inf(n, x + (size_t)j * ld));
  *ok = 1;
  for (int j = 0; j < mi; j++) {
    memcpy(z, x + (size_t)j * ld, sizeof(double) * n);
    memcpy(z + n, v + (size_t)j * ld, sizeof(double) * n);
    if (!(vi_dot(n, m->w, z + n) > 0.0)) *ok = 0; /* no approach: no impact */
    impact(&w, z, zp);
    double t0 = t[j], t1 = j + 1 < mi ? t[j + 1] : t[0] + np * T;
    if (!(t1 > t0)) *ok = 0;
    /* 512 samples per forcing period, then golden-section on each
     * interior local maximum of the gap */
    int K = (int)fmax(64.0, 512.0 * (t1 - t0) / T);
    double h = (t1 - t0) / K, gp = -HUGE_VAL, gc = gap_at(&w, t0, zp, t0 + h, zz);
    for (int k = 1; k < K; k++) {
      double gn = gap_at(&w, t0, zp, t0 + (k + 1) * h, zz);
      /* interior maxima only: the gap rises to 0 at the next impact */
      if (k > 1 && k + 1 < K - 1 && gc >= gp && gc >= gn) {
        double a = t0 + (k - 1) * h, b = t0 + (k + 1) * h;
        const double gr = 0.6180339887498949;
        double c1 = b - gr * (b - a), c2 = a + gr * (b - a);
        double g1 = gap_at(&w, t0, zp, c1, zz), g2 = gap_at(&w, t0, zp, c2, zz);
        for (int it = 0; it < 40; it++) {
          if (g1 > g2) { b = c2; c2 = c1; g2 = g1; c1 = b - gr * (b - a); g1 = gap_at(&w, t0, zp, c1, zz); }
          else { a = c1; c1 = c2; g1 = g2; c2 = a + gr * (b - a); g2 = gap_at(&w, t0, zp, c2, zz); }
        }
        worst = fmax(worst, fmax(fmax(g1, g2), gc));
      }
      if (k > 1 && k + 1 < K - 1) worst = fmax(worst, gc);
      gp = gc;
      gc = gn;
    }
  }
  if (isnan(worst)) st = VI_ERR_UNSUPPORTED;
  /* contact between impacts beyond round-off of the flow */
  if (worst > 1e-10 * scale) *ok = 0;
  if (gmax) *gmax = worst;
  ws_free(&w);
  return st;
}

int vi_orbit_p1_scan(const vi_model *m, int np, int nphase, double *t,
                     double *x, double *v, int ld, int cap, int *found)
{
  if (!m || !t || !x || !v || !found || np < 1 || nphase < 8 || cap < 0 ||
      ld < (m ? m->n : 1))
    return VI_ERR_ARG;
  if (!m->frozen) return VI_ERR_STATE;
  if (m->ns > 1) return VI_ERR_UNSUPPORTED; /* the impact map of one stop */
  if (!vi_xflow_available(m)) return VI_ERR_UNSUPPORTED;
  if (!(m->omega_f > 0.0)) return VI_ERR_FREQUENCY;
  *found = 0;
  ws w;
  int st = ws_init(&w, m), n = m->n, n2 = 2 * n;
  if (st) return st;
  size_t nn = (size_t)n2 * n2;
  double T = 2.0 * M_PI / m->omega_f, P = np * T;
  double *A = malloc(sizeof(double) * (2 * nn + 8 * (size_t)n2 + 2 * (size_t)nphase + 2));
  lapack_int *piv = malloc(sizeof(lapack_int) * (size_t)n2);
  if (!A || !piv) {
    st = VI_ERR_NOMEM;
    goto cleanup;
  }
  double *Phi = A + nn, *c = Phi + nn, *e = c + n2, *zs = e + n2,
         *h = zs + n2, *vn = h + nphase + 1;
  /* the affine map z -> flow(phi, J z, phi + P) has one fixed point for
   * each phase phi: the periodic motion with an impact at phi.  It is a
   * P(np,1) orbit where its gap h(phi) = w.x - x_s vanishes. */
  for (int k = 0; k <= nphase && !st; k++) {
    double phi = P * k / nphase;
    if ((st = stm(&w, phi, phi + P, Phi, e, c))) break;
    /* A = I - Phi J, J = diag(I, Q) */
    for (int b = 0; b < n2; b++)
      for (int a = 0; a < n2; a++) {
        double s = 0.0;
        if (b < n) s = Phi[a + (size_t)b * n2];
        else
          for (int p = 0; p < n; p++)
            s += Phi[a + (size_t)(n + p) * n2] * w.Q[p + (size_t)(b - n) * n];
        A[a + (size_t)b * n2] = (a == b) - s;
      }
    memcpy(zs, c, sizeof(double) * n2);
    if (LAPACKE_dgesv(LAPACK_COL_MAJOR, n2, 1, A, n2, piv, zs, n2) != 0) {
      h[k] = NAN;
      vn[k] = NAN;
      continue;
    }
    h[k] = vi_dot(n, m->w, zs) - m->xs;
    vn[k] = vi_dot(n, m->w, zs + n);
  }
  if (st) goto cleanup;
  for (int k = 0; k < nphase; k++) {
    if (!(h[k] * h[k + 1] <= 0.0) || h[k] == h[k + 1]) continue;
    /* linear interpolation of the root, then Newton on the full system */
    double s = h[k] / (h[k] - h[k + 1]), phi = P * (k + s) / nphase;
    if (!(vn[k] > 0.0 || vn[k + 1] > 0.0)) continue;
    if ((st = stm(&w, phi, phi + P, Phi, e, c))) break;
    for (int b = 0; b < n2; b++)
      for (int a = 0; a < n2; a++) {
        double sm = 0.0;
        if (b < n) sm = Phi[a + (size_t)b * n2];
        else
          for (int p = 0; p < n; p++)
            sm += Phi[a + (size_t)(n + p) * n2] * w.Q[p + (size_t)(b - n) * n];
        A[a + (size_t)b * n2] = (a == b) - sm;
      }
    memcpy(zs, c, sizeof(double) * n2);
    if (LAPACKE_dgesv(LAPACK_COL_MAJOR, n2, 1, A, n2, piv, zs, n2) != 0) continue;
    double tt = phi, *xx = w.buf, *vv = xx + n;
    memcpy(xx, zs, sizeof(double) * n);
    memcpy(vv, zs + n, sizeof(double) * n);
    if (vi_orbit_pnm_solve(m, np, 1, &tt, xx, vv, n, 0.0, NULL) != VI_OK) continue;
    if (!(vi_dot(n, m->w, vv) > 0.0)) continue; /* not an approach */
    tt = fmod(tt, P);
    if (tt < 0) tt += P;
    int dup = 0;
    for (int q = 0; q < *found && q < cap; q++)
      dup |= fabs(t[q] - tt) < 1e-7 * P || fabs(fabs(t[q] - tt) - P) < 1e-7 * P;
    if (dup) continue;
    if (*found < cap) {
      t[*found] = tt;
      memcpy(x + (size_t)*found * ld, xx, sizeof(double) * n);
      memcpy(v + (size_t)*found * ld, vv, sizeof(double) * n);
    }
    (*found)++;
  }
cleanup:
  free(piv);
  free(A);
  ws_free(&w);
  return st;
}
