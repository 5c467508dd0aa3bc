/* vi_orbit_pnm.c - P(n, m) orbits found directly: Newton on the impact
 * conditions with the closed-form flow, an exhaustive impact-phase scan for
 * P(n, 1), admissibility, and Floquet multipliers from the monodromy matrix
 * with the saltation matrix at each impact.
 *
 * An orbit is its m impacts in one orbit period nT: times t_j, the stop
 * s_j each hits, and the states just before them, (x_j, v_j).  Between
 * impacts the motion is the free flow (vi_flow_physical), affine in the
 * state: z(t) = Phi(t - t0) z0 + c(t0, t).  Its derivatives are exact:
 * D_z0 z(t) = Phi in closed form (vi_orbit_var.c), the time derivatives
 * the vector field itself, and the impact's the saltation matrix. */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cblas.h>
#include <lapacke.h>

#include "vi_forcing.h"
#include "vi_impact_internal.h"
#include "vi_orbit_internal.h"

typedef struct ws {
  const vi_model *m;
  int n, n2;
  const int *stop; /* stop of each impact (NULL: all on stop 0) */
  vi_xflow *xf;    /* the closed-form flow, built once per call */
  double *buf;     /* scratch [16n] */
} ws;

/* need_flow 1: the closed-form flow must exist (VI_ERR_UNSUPPORTED);
 * 0: built if it exists; -1: not built (derivatives only) */
static int ws_init(ws *w, const vi_model *m, const int *stop, int need_flow)
{
  w->m = m;
  w->n = m->n;
  w->n2 = 2 * m->n;
  w->stop = stop;
  w->xf = NULL;
  w->buf = malloc(sizeof(double) * 16 * (size_t)m->n);
  if (w->buf && need_flow < 0) return VI_OK;
  if (!w->buf || vi_xflow_create(m, &w->xf)) {
    free(w->buf);
    w->buf = NULL;
    return VI_ERR_NOMEM;
  }
  if (need_flow && !w->xf->ok) {
    vi_xflow_destroy(&w->xf);
    free(w->buf);
    w->buf = NULL;
    return VI_ERR_UNSUPPORTED;
  }
  return VI_OK;
}

static void ws_free(ws *w)
{
  vi_xflow_destroy(&w->xf);
  free(w->buf);
}

static int stop_of(const ws *w, int j) { return w->stop ? w->stop[j] : 0; }

/* stop indices valid for the model */
static int stops_ok(const vi_model *m, int mi, const int *stop)
{
  for (int j = 0; stop && j < mi; j++)
    if (stop[j] < 0 || stop[j] >= m->ns) return 0;
  return 1;
}

static int flow(const ws *w, double t0, const double *z0, double t1,
                double *z1)
{
  int n = w->n;
  if (!w->xf || !w->xf->ok) return VI_ERR_UNSUPPORTED;
  if (!(t1 >= t0)) return VI_ERR_TIME;
  return vi_xflow_physical(w->xf, w->m, t0, z0, z0 + n, t1, z1, z1 + n);
}

/* unknowns u = [t_j, x_j, v_j] for j = 0..m-1 (2n + 1 each) */
static int residual(const ws *w, int np, int mi, const double *u, double *F,
                    double *J, int want_j)
{
  const vi_model *m = w->m;
  int n = w->n, n2 = w->n2, B = n2 + 1, D = mi * B, st;
  double T = vi_forcing_period(m->omega_f);
  double *zp = malloc(sizeof(double) * ((size_t)n2 * n2 + 5 * (size_t)n2));
  if (!zp) return VI_ERR_NOMEM;
  double *ze = zp + n2, *f0 = ze + n2, *f1 = f0 + n2, *wk = f1 + n2,
         *Phi = wk + n2;
  if (want_j) memset(J, 0, sizeof(double) * (size_t)D * D);
  for (int j = 0; j < mi; j++) {
    int k = (j + 1) % mi, s = stop_of(w, j);
    const double *uj = u + (size_t)j * B, *uk = u + (size_t)k * B;
    const double *ws_ = vi_stop_w(m, s);
    double t0 = uj[0], t1 = uk[0] + (j + 1 == mi ? np * T : 0.0);
    if (!(t1 > t0)) {
      free(zp);
      return VI_ERR_NOT_CONVERGED; /* impacts out of order */
    }
    vi_var_impact(m, s, uj + 1, zp);
    if ((st = flow(w, t0, zp, t1, ze))) {
      free(zp);
      return st;
    }
    double *Fj = F + (size_t)j * B;
    for (int i = 0; i < n2; i++) Fj[i] = ze[i] - uk[1 + i];
    Fj[n2] = vi_dot(n, ws_, uj + 1) - m->xsv[s];
    if (!want_j) continue;
    if ((st = vi_var_stm(m, t1 - t0, Phi))) {
      free(zp);
      return st;
    }
    vi_var_field(m, t0, zp, f0);
    vi_var_field(m, t1, ze, f1);
    /* rows of segment j: columns of block j (t, x, v) and of block k;
     * d/dv_j through the impact map: Phi_v Q_k */
    cblas_dgemv(CblasColMajor, CblasNoTrans, n2, n2, -1.0, Phi, n2, f0, 1,
                0.0, wk, 1); /* d/dt_j: -Phi f(t_j+) */
    for (int i = 0; i < n2; i++) {
      size_t row = (size_t)j * B + i;
      J[row + (size_t)(j * B) * D] += wk[i];
      J[row + (size_t)(k * B) * D] += f1[i];
      J[row + (size_t)(k * B + 1 + i) * D] -= 1.0;
    }
    vi_impact_q_right(m, s, n2, Phi + (size_t)n * n2, n2, wk);
    for (int q = 0; q < n2; q++) /* d/dx_j, d/dv_j */
      for (int i = 0; i < n2; i++)
        J[(size_t)j * B + i + (size_t)(j * B + 1 + q) * D] +=
            Phi[i + (size_t)q * n2];
    for (int q = 0; q < n; q++) /* the impact condition w.x_j = x_s */
      J[(size_t)j * B + n2 + (size_t)(j * B + 1 + q) * D] = ws_[q];
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

/* common checks of the P(n, m) entry points */
static int pnm_check(const vi_model *m, int np, int mi, const int *stop)
{
  if (!m->frozen) return VI_ERR_STATE;
  if (!stops_ok(m, mi, stop) || np < 1 || mi < 1) return VI_ERR_ARG;
  if (m->ns < 1) return VI_ERR_STATE; /* no stop: nothing to impact */
  if (!vi_model_has_modes(m)) return VI_ERR_UNSUPPORTED; /* band: no modes */
  if (!(m->omega_f > 0.0)) return VI_ERR_FREQUENCY;
  return VI_OK;
}

int vi_orbit_pnm_solve_stops(const vi_model *m, int np, int mi,
                             const int *stop, double *t, double *x, double *v,
                             int ld, double tol, int *iters)
{
  if (!m || !t || !x || !v || ld < m->n) return VI_ERR_ARG;
  int st = pnm_check(m, np, mi, stop), n = m->n, B = 2 * n + 1, D = mi * B, it = 0;
  if (st) return st;
  /* t, x, v are read as the seed and overwritten with the orbit */
  size_t len = (size_t)ld * (size_t)(mi - 1) + (size_t)n;
  if (vi_overlap2(x, len, v, len) || vi_overlap2(t, (size_t)mi, x, len) ||
      vi_overlap2(t, (size_t)mi, v, len))
    return VI_ERR_ARG;
  ws w;
  if ((st = ws_init(&w, m, stop, 1))) return st;
  double *u = malloc(sizeof(double) * ((size_t)D * D + 4 * (size_t)D));
  lapack_int *piv = malloc(sizeof(lapack_int) * (size_t)D);
  if (!u || !piv) {
    st = VI_ERR_NOMEM;
    goto cleanup;
  }
  double *F = u + D, *du = F + D, *uc = du + D, *J = uc + D;
  for (int j = 0; j < mi; j++) {
    u[(size_t)j * B] = t[j];
    memcpy(u + (size_t)j * B + 1, x + (size_t)j * ld, sizeof(double) * n);
    memcpy(u + (size_t)j * B + 1 + n, v + (size_t)j * ld, sizeof(double) * n);
  }
  double scale = 0.0;
  for (int k = 0; k < m->ns; k++) scale = fmax(scale, fabs(m->xsv[k]));
  for (int i = 0; i < D; i++)
    if (i % B) scale = fmax(scale, fabs(u[i]));
  if (!(tol > 0.0)) tol = 1e-12;
  st = VI_ERR_NOT_CONVERGED;
  /* once the test passes, one more full Newton step: quadratic convergence
   * takes the error from the stopping test down to round-off (near
   * grazing the multipliers amplify it by 1 / v_N); kept only if the
   * residual does not grow */
  int polished = 0;
  double rconv = 0.0;
  for (it = 0; it < 40; it++) {
    int rs = residual(&w, np, mi, u, F, J, 1);
    double r = rs ? HUGE_VAL : norm_inf(D, F);
    if (polished) {
      if (!(r <= rconv)) memcpy(u, uc, sizeof(double) * D);
      break;
    }
    if (rs) {
      st = rs == VI_ERR_NOMEM ? rs : VI_ERR_NOT_CONVERGED;
      break;
    }
    /* the closed-form flow is exact to round-off: a residual of a few
     * hundred ulps of the state is what it can deliver */
    if (r <= tol * scale) {
      st = VI_OK;
      rconv = r;
      memcpy(uc, u, sizeof(double) * D);
    }
    memcpy(du, F, sizeof(double) * D);
    if (LAPACKE_dgesv(LAPACK_COL_MAJOR, D, 1, J, D, piv, du, D) != 0) break;
    if (st == VI_OK) {
      for (int i = 0; i < D; i++) u[i] -= du[i];
      polished = 1;
      continue;
    }
    /* damped step: never more than a tenth of a period in time, nor
     * twice the state scale */
    double lam = 1.0, T = vi_forcing_period(m->omega_f);
    for (int i = 0; i < D; i++) {
      double lim = i % B ? 2.0 * scale : 0.1 * T;
      if (fabs(du[i]) * lam > lim) lam = lim / fabs(du[i]);
    }
    for (int i = 0; i < D; i++) u[i] -= lam * du[i];
  }
  if (polished && it == 40) memcpy(u, uc, sizeof(double) * D); /* unchecked */
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

int vi_orbit_pnm_solve(const vi_model *m, int np, int mi, double *t,
                       double *x, double *v, int ld, double tol, int *iters)
{
  return vi_orbit_pnm_solve_stops(m, np, mi, NULL, t, x, v, ld, tol, iters);
}

int vi_orbit_pnm_residual_stops(const vi_model *m, int np, int mi,
                                const int *stop, const double *t,
                                const double *x, const double *v, int ld,
                                double *F, double *J)
{
  if (!m || !t || !x || !v || !F || ld < m->n) return VI_ERR_ARG;
  int st = pnm_check(m, np, mi, stop), n = m->n, B = 2 * n + 1, D = mi * B;
  if (st) return st;
  ws w;
  if ((st = ws_init(&w, m, stop, 1))) return st;
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

int vi_orbit_pnm_residual(const vi_model *m, int np, int mi, const double *t,
                          const double *x, const double *v, int ld, double *F,
                          double *J)
{
  return vi_orbit_pnm_residual_stops(m, np, mi, NULL, t, x, v, ld, F, J);
}

int vi_orbit_param_of_key(const char *key, int *pk)
{
  const char *f = NULL;
  *pk = 0;
  if (!strcmp(key, "forcing.omega")) return VI_ORBIT_PARAM_OMEGA;
  if (strncmp(key, "stop.", 5) == 0) f = key + 5;
  if (strncmp(key, "stops[", 6) == 0) {
    char *end = NULL;
    long k = strtol(key + 6, &end, 10);
    if (end == key + 6 || k < 1 || k > INT_MAX || strncmp(end, "].", 2) != 0) return -1;
    *pk = (int)(k - 1);
    f = end + 2;
  }
  if (f && strcmp(f, "xs") == 0) return VI_ORBIT_PARAM_XS;
  if (f && strcmp(f, "r") == 0) return VI_ORBIT_PARAM_R;
  return -1;
}

/* dF/dp of the conditions of residual(): for each segment j,
 *   F_j = Phi(t1 - t0) (z_j+ - z_p(t0)) + z_p(t1) - z_{j+1}-,
 *   z_j+ = (x_j, v_j - (1 + r_s) (w_s.v_j) M^-1 w_s / G_ss),
 *   last row w_s.x_j - x_s;
 * Omega enters z_p and, for the last segment, t1 = t_0 + nT (dt1/dOmega =
 * -nT / Omega, times the field f1); x_s enters only the impact rows; r_s
 * only z_j+. */
int vi_orbit_pnm_dparam(const vi_model *m, int np, int mi, const int *stop,
                        const double *t, const double *x, const double *v,
                        int ld, int param, int k, double *dF)
{
  if (!m || !t || !x || !v || !dF || ld < m->n) return VI_ERR_ARG;
  int st = pnm_check(m, np, mi, stop), n = m->n, n2 = 2 * n, B = n2 + 1;
  if (st) return st;
  if (param != VI_ORBIT_PARAM_OMEGA && param != VI_ORBIT_PARAM_XS &&
      param != VI_ORBIT_PARAM_R)
    return VI_ERR_ARG;
  if (param != VI_ORBIT_PARAM_OMEGA && (k < 0 || k >= m->ns)) return VI_ERR_ARG;
  ws w;
  if ((st = ws_init(&w, m, stop, 1))) return st;
  double T = vi_forcing_period(m->omega_f);
  double *Phi = malloc(sizeof(double) * ((size_t)n2 * n2 + 6 * (size_t)n2));
  if (!Phi) {
    ws_free(&w);
    return VI_ERR_NOMEM;
  }
  double *d = Phi + (size_t)n2 * n2, *dp = d + (size_t)2 * n2, *zp = dp + n2, *ze = zp + n2,
         *f1 = ze + n2;
  memset(dF, 0, sizeof(double) * (size_t)mi * B);
  for (int j = 0; j < mi && !st; j++) {
    int s = stop_of(&w, j), kk = (j + 1) % mi;
    double t0 = t[j], t1 = t[kk] + (j + 1 == mi ? np * T : 0.0), *Fj = dF + (size_t)j * B;
    if (param == VI_ORBIT_PARAM_XS) {
      if (s == k) Fj[n2] = -1.0;
      continue;
    }
    if ((st = vi_var_stm(m, t1 - t0, Phi))) break;
    memset(dp, 0, sizeof(double) * n2);
    if (param == VI_ORBIT_PARAM_R) {
      if (s != k) continue;
      vi_impact_q_dr(m, s, v + (size_t)j * ld, dp + n);
    } else {
      double tt[2] = {t0, t1};
      if ((st = vi_var_dpart_domega(m, 2, tt, d))) break;
      for (int i = 0; i < n2; i++) dp[i] = -d[i];
      for (int i = 0; i < n2; i++) Fj[i] += d[n2 + i];
      if (j + 1 == mi) { /* the period itself */
        memcpy(zp, x + (size_t)j * ld, sizeof(double) * n);
        memcpy(zp + n, v + (size_t)j * ld, sizeof(double) * n);
        vi_var_impact(m, s, zp, zp);
        if ((st = flow(&w, t0, zp, t1, ze))) break;
        vi_var_field(m, t1, ze, f1);
        for (int i = 0; i < n2; i++) Fj[i] += f1[i] * (-np * T / m->omega_f);
      }
    }
    cblas_dgemv(CblasColMajor, CblasNoTrans, n2, n2, 1.0, Phi, n2, dp, 1, 1.0,
                Fj, 1);
  }
  free(Phi);
  ws_free(&w);
  return st;
}

int vi_orbit_pnm_monodromy(const vi_model *m, int np, int mi, const int *stop,
                           const double *t, const double *x, const double *v,
                           int ld, double *Mo)
{
  return vi_orbit_pnm_monodromy_parts(m, np, mi, stop, t, x, v, ld, Mo, NULL, NULL);
}

int vi_orbit_pnm_monodromy_parts(const vi_model *m, int np, int mi, const int *stop,
                                 const double *t, const double *x, const double *v,
                                 int ld, double *Mo, double *Phis, double *Ss)
{
  if (!m || !t || !x || !v || !Mo || ld < m->n) return VI_ERR_ARG;
  int st = pnm_check(m, np, mi, stop), n = m->n, n2 = 2 * n;
  if (st) return st;
  ws w;
  if ((st = ws_init(&w, m, stop, -1))) return st;
  double T = vi_forcing_period(m->omega_f);
  size_t nn = (size_t)n2 * n2;
  double *S = malloc(sizeof(double) * (3 * nn + (size_t)n2));
  if (!S) {
    ws_free(&w);
    return VI_ERR_NOMEM;
  }
  double *Phi = S + nn, *tmp = Phi + nn, *z = tmp + nn;
  for (size_t i = 0; i < nn; i++) Mo[i] = 0.0;
  for (int i = 0; i < n2; i++) Mo[i + (size_t)i * n2] = 1.0;
  for (int j = 0; j < mi && !st; j++) {
    memcpy(z, x + (size_t)j * ld, sizeof(double) * n);
    memcpy(z + n, v + (size_t)j * ld, sizeof(double) * n);
    if (!(vi_dot(n, vi_stop_w(m, stop_of(&w, j)), z + n) != 0.0)) {
      st = VI_ERR_ARG; /* no approach velocity: S does not exist (grazing) */
      break;
    }
    vi_var_saltation(m, stop_of(&w, j), t[j], z, S, w.buf);
    double t1 = j + 1 < mi ? t[j + 1] : t[0] + np * T;
    if ((st = vi_var_stm(m, t1 - t[j], Phi))) break;
    if (Phis) memcpy(Phis + (size_t)j * nn, Phi, sizeof(double) * nn);
    if (Ss) memcpy(Ss + (size_t)j * nn, S, sizeof(double) * nn);
    /* Mo <- Phi S Mo */
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n2, n2, n2, 1.0, S,
                n2, Mo, n2, 0.0, tmp, n2);
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n2, n2, n2, 1.0,
                Phi, n2, tmp, n2, 0.0, Mo, n2);
  }
  free(S);
  ws_free(&w);
  return st;
}

int vi_orbit_pnm_multipliers_stops(const vi_model *m, int np, int mi,
                                   const int *stop, const double *t,
                                   const double *x, const double *v, int ld,
                                   double *re, double *im)
{
  if (!m || !re || !im) return VI_ERR_ARG;
  size_t nn = (size_t)4 * m->n * m->n;
  double *Mo = malloc(sizeof(double) * nn);
  if (!Mo) return VI_ERR_NOMEM;
  int st = vi_orbit_pnm_monodromy(m, np, mi, stop, t, x, v, ld, Mo);
  if (!st && LAPACKE_dgeev(LAPACK_COL_MAJOR, 'N', 'N', 2 * m->n, Mo, 2 * m->n,
                           re, im, NULL, 1, NULL, 1) != 0)
    st = VI_ERR_LAPACK;
  free(Mo);
  return st;
}

int vi_orbit_pnm_multipliers(const vi_model *m, int np, int mi,
                             const double *t, const double *x, const double *v,
                             int ld, double *re, double *im)
{
  return vi_orbit_pnm_multipliers_stops(m, np, mi, NULL, t, x, v, ld, re, im);
}

/* the largest gap max_k (w_k.x - x_k) over the stops of the free flow
 * from seg's start (t0, zp) at t; work [2n] */
static double gap_at(const ws *w, vi_xseg *seg, double t, double *z,
                     double *work)
{
  const vi_model *m = w->m;
  if (!w->xf || !w->xf->ok || !(t >= seg->t0)) return NAN;
  vi_xseg_physical(seg, t, z, z + w->n, work);
  double g = -HUGE_VAL;
  for (int k = 0; k < m->ns; k++)
    g = fmax(g, vi_dot(m->n, vi_stop_w(m, k), z) - m->xsv[k]);
  return g;
}

/* gap_at at t0 + k h, k = 1..K, into g [K + 1] (g[0] unused): the grid
 * in blocks of 64 whose modal states go to physical positions in one
 * product; work [3n x 64] */
static void grid_gaps(const ws *w, vi_xseg *seg, double t0, double h, int K,
                      double *g, double *work)
{
  const vi_model *m = w->m;
  int n = m->n;
  if (!w->xf || !w->xf->ok || seg->g) {
    for (int k = 1; k <= K; k++) g[k] = gap_at(w, seg, t0 + k * h, work, work + 2 * (size_t)n);
    return;
  }
  double *Q = work, *X = work + 2 * (size_t)n * 64;
  for (int k0 = 1; k0 <= K; k0 += 64) {
    int nk = K - k0 + 1 < 64 ? K - k0 + 1 : 64;
    for (int i = 0; i < nk; i++) {
      double t = t0 + (k0 + i) * h;
      if (!(t >= seg->t0)) { /* gap_at's NaN */
        memset(Q + 2 * (size_t)n * i, 0, sizeof(double) * 2 * (size_t)n);
        continue;
      }
      vi_xseg_modal(seg, t, Q + 2 * (size_t)n * i, Q + 2 * (size_t)n * i + n, NULL);
    }
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n, nk, n, 1.0, m->Psi, n,
                Q, 2 * n, 0.0, X, n);
    for (int i = 0; i < nk; i++) {
      double gi = -HUGE_VAL;
      for (int q = 0; q < m->ns; q++)
        gi = fmax(gi, vi_dot(n, vi_stop_w(m, q), X + (size_t)n * i) - m->xsv[q]);
      g[k0 + i] = t0 + (k0 + i) * h >= seg->t0 ? gi : NAN;
    }
  }
}

int vi_orbit_pnm_admissible_stops(const vi_model *m, int np, int mi,
                                  const int *stop, const double *t,
                                  const double *x, const double *v, int ld,
                                  double *gmax, int *ok)
{
  if (!m || !t || !x || !v || !ok || ld < m->n) return VI_ERR_ARG;
  int st = pnm_check(m, np, mi, stop), n = m->n;
  if (st) return st;
  ws w;
  if ((st = ws_init(&w, m, stop, 0))) return st;
  double T = vi_forcing_period(m->omega_f), worst = -HUGE_VAL;
  double *z = w.buf, *zp = z + (size_t)2 * n, *zz = zp + (size_t)2 * n,
         *wk = zz + (size_t)2 * n, *sb = wk + (size_t)2 * n;
  /* the flight from each impact is started once (sb [3n]): its gap is
   * sampled 512 times a period, in blocks (gs, gw), and more */
  vi_xseg seg;
  seg.g = NULL;
  seg.z = NULL;
  double *gs = NULL, *gw = malloc(sizeof(double) * 3 * (size_t)n * 64);
  if (!gw || (w.xf && (st = vi_xseg_init(&seg, w.xf, m, sb)))) {
    free(gw);
    ws_free(&w);
    return gw ? st : VI_ERR_NOMEM;
  }
  double scale = 0.0;
  for (int k = 0; k < m->ns; k++) scale = fmax(scale, fabs(m->xsv[k]));
  for (int j = 0; j < mi; j++) scale = fmax(scale, norm_inf(n, x + (size_t)j * ld));
  *ok = 1;
  for (int j = 0; j < mi; j++) {
    int s = stop_of(&w, j);
    memcpy(z, x + (size_t)j * ld, sizeof(double) * n);
    memcpy(z + n, v + (size_t)j * ld, sizeof(double) * n);
    if (!(vi_dot(n, vi_stop_w(m, s), z + n) > 0.0)) *ok = 0; /* no approach */
    vi_var_impact(m, s, z, zp);
    double t0 = t[j], t1 = j + 1 < mi ? t[j + 1] : t[0] + np * T;
    if (!(t1 > t0)) *ok = 0;
    seg.t0 = t0; /* gap_at's time check where there is no flow */
    if (w.xf && w.xf->ok) vi_xseg_start(&seg, t0, zp, zp + n);
    /* 512 samples per forcing period, then golden-section on each
     * interior local maximum of the gap */
    int K = (int)fmax(64.0, 512.0 * (t1 - t0) / T);
    if (K < 64) K = 64; /* a span beyond int's range */
    double h = (t1 - t0) / K;
    double *gk = realloc(gs, sizeof(double) * ((size_t)K + 1));
    if (!gk) {
      st = VI_ERR_NOMEM;
      break;
    }
    gs = gk;
    grid_gaps(&w, &seg, t0, h, K, gs, gw);
    double gp = -HUGE_VAL, gc = gs[1];
    for (int k = 1; k < K; k++) {
      double gn = gs[k + 1];
      /* interior maxima only: the gap rises to 0 at the next impact */
      if (k > 1 && k + 1 < K - 1 && gc >= gp && gc >= gn) {
        double a = t0 + (k - 1) * h, b = t0 + (k + 1) * h;
        const double gr = 0.6180339887498949;
        double c1 = b - gr * (b - a), c2 = a + gr * (b - a);
        double g1 = gap_at(&w, &seg, c1, zz, wk), g2 = gap_at(&w, &seg, c2, zz, wk);
        for (int it = 0; it < 40; it++) {
          if (g1 > g2) { b = c2; c2 = c1; g2 = g1; c1 = b - gr * (b - a); g1 = gap_at(&w, &seg, c1, zz, wk); }
          else { a = c1; c1 = c2; g1 = g2; c2 = a + gr * (b - a); g2 = gap_at(&w, &seg, c2, zz, wk); }
        }
        worst = fmax(worst, fmax(fmax(g1, g2), gc));
      }
      if (k > 1 && k + 1 < K - 1) worst = fmax(worst, gc);
      gp = gc;
      gc = gn;
    }
  }
  free(gs);
  free(gw);
  if (!st && isnan(worst)) st = VI_ERR_UNSUPPORTED;
  /* contact between impacts beyond round-off of the flow */
  if (worst > 1e-10 * scale) *ok = 0;
  if (gmax) *gmax = worst;
  vi_xseg_release(&seg);
  ws_free(&w);
  return st;
}

int vi_orbit_pnm_admissible(const vi_model *m, int np, int mi,
                            const double *t, const double *x, const double *v,
                            int ld, double *gmax, int *ok)
{
  return vi_orbit_pnm_admissible_stops(m, np, mi, NULL, t, x, v, ld, gmax, ok);
}

int vi_orbit_p1_scan(const vi_model *m, int np, int nphase, double *t,
                     double *x, double *v, int ld, int cap, int *found)
{
  return vi_orbit_p1_scan_polled(m, np, nphase, t, x, v, ld, cap, found, NULL,
                                 NULL);
}

int vi_orbit_p1_scan_polled(const vi_model *m, int np, int nphase, double *t,
                            double *x, double *v, int ld, int cap, int *found,
                            vi_cancel_fn cancel, void *user)
{
  if (!m || !t || !x || !v || !found || np < 1 || nphase < 8 || cap < 0 ||
      ld < (m ? m->n : 1))
    return VI_ERR_ARG;
  /* the orbits found go to t, x, v column by column: no sharing */
  size_t len = cap > 0 ? (size_t)ld * (size_t)(cap - 1) + (size_t)m->n : 0;
  if (vi_overlap2(x, len, v, len) || vi_overlap2(t, (size_t)cap, x, len) ||
      vi_overlap2(t, (size_t)cap, v, len))
    return VI_ERR_ARG;
  if (!m->frozen) return VI_ERR_STATE;
  if (m->ns > 1) return VI_ERR_UNSUPPORTED; /* the impact map of one stop */
  if (!vi_model_has_modes(m)) return VI_ERR_UNSUPPORTED; /* band: no modes */
  if (!(m->omega_f > 0.0)) return VI_ERR_FREQUENCY;
  *found = 0;
  ws w;
  int st = ws_init(&w, m, NULL, 1), n = m->n, n2 = 2 * n;
  if (st) return st;
  size_t nn = (size_t)n2 * n2;
  double T = vi_forcing_period(m->omega_f), P = np * T;
  double *A = malloc(sizeof(double) * (2 * nn + 8 * (size_t)n2 + 2 * (size_t)nphase + 2));
  lapack_int *piv = malloc(sizeof(lapack_int) * (size_t)n2);
  if (!A || !piv) {
    st = VI_ERR_NOMEM;
    goto cleanup;
  }
  double *Phi = A + nn, *c = Phi + nn, *e = c + n2, *zs = e + n2,
         *h = zs + n2, *vn = h + nphase + 1;
  const double *w0 = vi_stop_w(m, 0);
  memset(e, 0, sizeof(double) * n2);
  /* the affine map z -> flow(phi, J z, phi + P) has one fixed point for
   * each phase phi: the periodic motion with an impact at phi.  It is a
   * P(np,1) orbit where its gap h(phi) = w.x - x_s vanishes.  The
   * transition matrix over one orbit period is the same for every phase. */
  if ((st = vi_var_stm(m, P, Phi))) goto cleanup;
  /* A = I - Phi J, J = diag(I, Q_0), the impact map of the stop (WB 2):
   * factored once (a singular A, a resonance of the impact map, leaves no
   * isolated fixed points) */
  vi_impact_q_right(m, 0, n2, Phi + (size_t)n * n2, n2, c);
  for (size_t i = 0; i < nn; i++) A[i] = -Phi[i];
  for (int i = 0; i < n2; i++) A[i + (size_t)i * n2] += 1.0;
  if (LAPACKE_dgetrf(LAPACK_COL_MAJOR, n2, n2, A, n2, piv) != 0) goto cleanup;
  for (int k = 0; k <= nphase && !st; k++) {
    if (cancel && cancel(user)) { /* polled once a phase */
      st = VI_CANCELLED;
      break;
    }
    double phi = P * k / nphase;
    if ((st = flow(&w, phi, e, phi + P, c))) break;
    memcpy(zs, c, sizeof(double) * n2);
    if (LAPACKE_dgetrs(LAPACK_COL_MAJOR, 'N', n2, 1, A, n2, piv, zs, n2) != 0) {
      h[k] = NAN;
      vn[k] = NAN;
      continue;
    }
    h[k] = vi_dot(n, w0, zs) - m->xsv[0];
    vn[k] = vi_dot(n, w0, zs + n);
  }
  if (st) goto cleanup;
  for (int k = 0; k < nphase; k++) {
    if (cancel && cancel(user)) {
      st = VI_CANCELLED;
      break;
    }
    if (!(h[k] * h[k + 1] <= 0.0) || h[k] == h[k + 1]) continue;
    /* linear interpolation of the root, then Newton on the full system */
    double s = h[k] / (h[k] - h[k + 1]), phi = P * (k + s) / nphase;
    if (!(vn[k] > 0.0 || vn[k + 1] > 0.0)) continue;
    if ((st = flow(&w, phi, e, phi + P, c))) break;
    memcpy(zs, c, sizeof(double) * n2);
    if (LAPACKE_dgetrs(LAPACK_COL_MAJOR, 'N', n2, 1, A, n2, piv, zs, n2) != 0) continue;
    double tt = phi, *xx = w.buf, *vv = xx + n;
    memcpy(xx, zs, sizeof(double) * n);
    memcpy(vv, zs + n, sizeof(double) * n);
    if (vi_orbit_pnm_solve(m, np, 1, &tt, xx, vv, n, 0.0, NULL) != VI_OK) continue;
    if (!(vi_dot(n, w0, vv) > 0.0)) continue; /* not an approach */
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
