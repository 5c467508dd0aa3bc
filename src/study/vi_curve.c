/* vi_curve.c - codimension-one points of P(n,m) and P(1,0) orbits solved
 * exactly and followed in two parameters (vi_cont_curve.h): Newton and
 * pseudo-arclength on the orbit's equations plus the defining condition,
 * codimension-two points located on the curve by regula falsi. */
#include <complex.h>
#include <limits.h>
#include <stdio.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cblas.h>
#include <lapacke.h>

#include "vibroimpact/vi_cont_curve.h"
#include "vibroimpact/vi_flow.h"
#include "vibroimpact/vi_orbit.h"
#include "vibroimpact/vi_param.h"
#include "vi_orbit_internal.h"
#include "vi_forcing.h"
#include "vi_model_internal.h"

#define MAXSP 16
/* impacts per orbit (their stops and times are kept in the handle) */
#define VI_CURVE_MAXI 32
/* the test functions watched along a curve */
enum { T_FOLD, T_PD, T_NS, T_GRAZE, T_VN, T_RES, NT };
/* locate's zero other than a test's: the fold's cusp test */
enum { K_CUSP = -1 };

typedef struct special {
  int type, located;
  double p, p2;
} special;

struct vi_cont_curve {
  vi_model *m;
  char key[64], key2[64];
  int par[2], pk[2];   /* vi_orbit_pnm_dparam's parameter (or -1), stop */
  int kind, n, mi, N, D, np; /* np: free parameters now (1 or 2) */
  int blk, ld;         /* one impact's block 2N + 1 of Y; ld of x, v in Y */
  int stops[VI_CURVE_MAXI]; /* each impact's stop */
  double tt[VI_CURVE_MAXI]; /* the impact times gathered from Y (mi > 1) */
  int have_orbit, located, have_range, state, started;
  int start_state;     /* why the backward pass ended (vi_cont_curve_start) */
  double from2, to2, dsmax, ds;
  int64_t npts, maxpts, nback; /* nback: the backward pass's steps */
  double far;          /* the farthest the curve has gone from Y0 (closure) */
  /* Y = (t, x, v, p, p2) [D + 2]; scales S; tangents; scratch */
  double *Y, *Yl, *Ys, *tau, *taul, *S, *Yt, *Yq, *Yr, *Yg, *Ye, *Y0, *bord, *bord2, *H;
  double *J, *B, *re, *im;
  double *tnew;       /* the new tangent [nu] */
  double *fz;         /* a flight's post-impact state, state and field [2N] each */
  lapack_int *ip;     /* the dense solves' pivots [nu] */
  double *lm;         /* the condition's state derivatives (lemma_prep), or NULL */
  lapack_int *lip;    /* and their LU's pivots [2N] */
  double lm_det, lm_vn; /* det(Mo + s I), the product of the v_N */
  double T[NT], Tl[NT];
  double rho;
  double tg;          /* grazing: the gap's maximum, time after impact jg */
  int jg, kg;         /* grazing: its flight and stop */
  special sp[MAXSP], endsp; /* endsp: where the backward pass ended */
  int nsp, have_endsp;
  char errmsg[VI_MSG_LEN];
};

/* ---- the conditions -------------------------------------------------------- */

/* The model at Y's parameters; 0, or -1 if one is refused. */
static int setp(vi_cont_curve *c, const double *Y)
{
  if (vi_model_set_param(c->m, c->key, Y[c->D])) return -1;
  if (c->np == 2 && vi_model_set_param(c->m, c->key2, Y[c->D + 1])) return -1;
  return 0;
}

/* The impact times of Y: Y itself for one impact (t at Y[0]), else
 * gathered from the impacts' blocks (t_j at Y[j B]) into c->tt. */
static const double *times(vi_cont_curve *c, const double *Y)
{
  if (c->mi <= 1) return Y;
  for (int j = 0; j < c->mi; j++) c->tt[j] = Y[(size_t)j * c->blk];
  return c->tt;
}

/* Whether unknown j of Y is an impact time (left out of the state's
 * scale and of the closure test: it drifts by whole periods). */
static int is_time(const vi_cont_curve *c, int j) { return c->mi && j < c->D && j % c->blk == 0; }

/* P(1,0): the largest gap over the stops of the harmonic steady state,
 * w.K^-1 f0 + |w.(K - W^2 M + i W C)^-1 (a - i b)| - x_s (MODEL.md
 * section 2's particular solution; a cos + b sin = Re (a - i b) e^{iWt}). */
static int p10_gap(const vi_cont_curve *c, double *g)
{
  const vi_model *m = c->m;
  int N = c->N, st = 0;
  double W = m->omega_f;
  double complex *Z = malloc(sizeof *Z * ((size_t)N * N + N));
  double *K0 = malloc(sizeof(double) * ((size_t)N * N + N));
  lapack_int *ip = malloc(sizeof(lapack_int) * (size_t)N);
  if (!Z || !K0 || !ip) st = VI_ERR_NOMEM;
  double complex *X = Z ? Z + (size_t)N * N : NULL;
  double *x0 = K0 ? K0 + (size_t)N * N : NULL;
  int f0 = 0;
  for (int i = 0; !st && i < N; i++) {
    X[i] = (m->a ? m->a[i] : 0) - I * (m->b ? m->b[i] : 0);
    x0[i] = m->f0 ? m->f0[i] : 0;
    f0 |= x0[i] != 0;
    for (int j = 0; j < N; j++) {
      size_t ij = i + (size_t)j * N;
      Z[ij] = m->K[ij] - W * W * m->M[ij] + I * W * m->C[ij];
      K0[ij] = m->K[ij];
    }
  }
  if (!st && LAPACKE_zgesv(LAPACK_COL_MAJOR, N, 1, (lapack_complex_double *)Z, N, ip,
                           (lapack_complex_double *)X, N))
    st = VI_ERR_LAPACK;
  if (!st && f0 && LAPACKE_dgesv(LAPACK_COL_MAJOR, N, 1, K0, N, ip, x0, N)) st = VI_ERR_LAPACK;
  if (!st) {
    *g = -HUGE_VAL;
    for (int k = 0; k < m->ns; k++) {
      const double *w = vi_stop_w(m, k);
      double complex a = 0;
      double s = 0;
      for (int i = 0; i < N; i++) {
        a += w[i] * X[i];
        if (f0) s += w[i] * x0[i];
      }
      *g = fmax(*g, s + cabs(a) - m->xsv[k]);
    }
  }
  free(Z);
  free(K0);
  free(ip);
  return st;
}

/* The multipliers of the orbit at Y (model at Y's parameters) into re, im. */
static int mults(vi_cont_curve *c, const double *Y)
{
  int N = c->N;
  return vi_orbit_pnm_multipliers_stops(c->m, c->n, c->mi, c->stops, times(c, Y), Y + 1,
                                        Y + 1 + N, c->ld,
                                        c->re, c->im);
}

/* The product form of the fold (s = -1) and pd (s = 1) conditions,
 * prod_i (mu_i + s). */
static double prod_shift(const vi_cont_curve *c, double s)
{
  double complex p = 1;
  for (int i = 0; i < 2 * c->N; i++) p *= c->re[i] + I * c->im[i] + s;
  return creal(p);
}

static double prod_pairs(const vi_cont_curve *c)
{
  double complex p = 1;
  for (int i = 0; i < 2 * c->N; i++)
    for (int j = i + 1; j < 2 * c->N; j++)
      p *= (c->re[i] + I * c->im[i]) * (c->re[j] + I * c->im[j]) - 1;
  return creal(p);
}

/* The pair (i, j) whose product is nearest 1: the NS pair. */
static void ns_pair(const vi_cont_curve *c, int *bi, int *bj)
{
  double best = HUGE_VAL;
  *bi = 0;
  *bj = 1;
  for (int i = 0; i < 2 * c->N; i++)
    for (int j = i + 1; j < 2 * c->N; j++) {
      double complex d = (c->re[i] + I * c->im[i]) * (c->re[j] + I * c->im[j]) - 1;
      if (cabs(d) < best) {
        best = cabs(d);
        *bi = i;
        *bj = j;
      }
    }
}

/* d/dz prod_i (mu_i + z) at z = s, sum_i prod_{j != i} (mu_j + s): where
 * one multiplier is at -s it is the product over the others, the 1:1 or
 * 1:2 test on a fold or pd curve.  A symmetric function of the
 * multipliers, so as exact as the monodromy's entries: near a double
 * multiplier each one alone is only good to the square root of the
 * rounding (the product over the others of the nearest one jumped by
 * 1e-8 there, and regula falsi could not locate its zero). */
static double dprod_shift(const vi_cont_curve *c, double s)
{
  double complex sum = 0;
  for (int i = 0; i < 2 * c->N; i++) {
    double complex p = 1;
    for (int j = 0; j < 2 * c->N; j++)
      if (j != i) p *= c->re[j] + I * c->im[j] + s;
    sum += p;
  }
  return creal(sum);
}

/* det(Mo + s I) = prod_i (mu_i + s) of the orbit at Y (model at its
 * parameters) by LU, without the eigenvalues: the curve's condition is
 * evaluated 2 nu times a step for its row of the Jacobian, and the
 * Hessenberg QR of every evaluation was most of a large model's time.
 * Mo lies in c->B, free while sys evaluates g. */
static int det_shift(vi_cont_curve *c, const double *Y, double s, double *d)
{
  int N = c->N, n2 = 2 * N;
  double *A = c->B;
  int st = vi_orbit_pnm_monodromy(c->m, c->n, c->mi, c->stops, times(c, Y), Y + 1, Y + 1 + N,
                                  c->ld, A);
  if (st) return st;
  for (int i = 0; i < n2; i++) A[i + (size_t)i * n2] += s;
  if (LAPACKE_dgetrf(LAPACK_COL_MAJOR, n2, n2, A, n2, c->ip) < 0) return VI_ERR_LAPACK;
  double p = 1; /* a zero pivot (info > 0) gives 0 */
  for (int i = 0; i < n2; i++) {
    double u = A[i + (size_t)i * n2];
    p *= c->ip[i] != i + 1 ? -u : u;
  }
  *d = p;
  return VI_OK;
}

/* The largest gap between impacts of the P(n,1) orbit at Y. */
static int gap_max(vi_cont_curve *c, const double *Y, double *g)
{
  int ok, N = c->N;
  return vi_orbit_pnm_admissible_stops(c->m, c->n, c->mi, c->stops, times(c, Y), Y + 1,
                                       Y + 1 + N, c->ld, g,
                                       &ok);
}

/* Flight j of the orbit at Y: from impact j's post-impact state (its
 * stop's impact law) to impact j + 1, the last to the first + nT; one
 * exact flow for every time asked (times relative to the impact, within
 * the flight of length L). */
typedef struct flight {
  const vi_model *m;
  vi_xflow *fl;
  double t0, L, *zp; /* zp: the handle's scratch */
  int N;
} flight;

static int flight_start(const vi_cont_curve *c, const double *Y, int j, flight *f)
{
  const vi_model *m = c->m;
  int N = c->N, B = c->blk;
  const double *Yj = Y + (size_t)j * B; /* t, x, v of impact j */
  f->fl = NULL;
  if (!m->MinvK || !m->MinvC) return 1;
  f->zp = c->fz;
  memcpy(f->zp, Yj + 1, sizeof(double) * 2 * (size_t)N); /* x, v before the impact */
  vi_var_impact(m, c->stops[j], f->zp, f->zp);
  f->m = m;
  f->N = N;
  f->t0 = Yj[0];
  double tn = j + 1 < c->mi ? Y[(size_t)(j + 1) * B] : Y[0] + c->n * vi_forcing_period(m->omega_f);
  f->L = tn - f->t0;
  return !(f->L > 0) || vi_xflow_create(m, &f->fl) != VI_OK;
}

/* The state z [2N] at t after the impact. */
static int flight_at(const flight *f, double t, double *z)
{
  return vi_xflow_physical(f->fl, f->m, f->t0, f->zp, f->zp + f->N, f->t0 + t, z,
                           z + f->N);
}

/* The gap's interior maximum at stop k of the flight by Newton on
 * w.v(t) = 0 (w.a < 0) from tau0; *g the gap there, *tau its time.  0, or
 * 1 when Newton leaves the flight or finds no maximum. */
static int graze_newton(vi_cont_curve *c, const flight *f, int k, double tau0, double *g,
                        double *tau)
{
  const vi_model *m = c->m;
  int N = c->N;
  const double *w = vi_stop_w(m, k);
  double *z = c->fz + 2 * (size_t)N, *dz = z + 2 * (size_t)N, t = tau0;
  for (int it = 0; it < 12; it++) {
    if (!(t > 0 && t < f->L) || flight_at(f, t, z)) return 1;
    vi_var_field(m, f->t0 + t, z, dz); /* (v, a) */
    double wv = vi_dot(N, w, z + N), wa = vi_dot(N, w, dz + N);
    if (!(wa < 0)) return 1;
    double dt = -wv / wa;
    t += dt;
    if (fabs(dt) <= 1e-13 * f->L) {
      if (!(t > 0 && t < f->L) || flight_at(f, t, z)) return 1;
      *g = vi_dot(N, w, z) - m->xsv[k];
      *tau = t;
      return 0;
    }
  }
  return 1;
}

/* Grazing of the orbit at Y in flight j at stop k from the time tau0
 * after its impact. */
static int graze_local(vi_cont_curve *c, const double *Y, int j, int k, double tau0,
                       double *g, double *tau)
{
  flight f;
  int r = flight_start(c, Y, j, &f) || graze_newton(c, &f, k, tau0, g, tau);
  vi_xflow_destroy(&f.fl);
  return r;
}

/* The grazing flight, stop and time from scratch: in each flight, at
 * each stop (a two-sided orbit's flight may graze the stop it did not
 * leave), the largest of 512 samples per forcing period, refined; the
 * largest gap of those (*jg its flight, *kg its stop); 0, or 1 if none. */
static int graze_scan(vi_cont_curve *c, const double *Y, double *g, int *jg, int *kg,
                      double *tau)
{
  const vi_model *m = c->m;
  int N = c->N, ns = m->ns, found = 0;
  double *z = c->fz + 2 * (size_t)N, T = vi_forcing_period(m->omega_f);
  /* per stop: the best sample, its gap, the two samples before */
  double *gb = malloc(sizeof(double) * 4 * (size_t)ns), *g1 = gb + ns, *g2 = g1 + ns;
  int *best = malloc(sizeof(int) * (size_t)ns);
  for (int j = 0; gb && best && j < c->mi; j++) {
    int K;
    flight f;
    if (flight_start(c, Y, j, &f)) {
      vi_xflow_destroy(&f.fl);
      found = 0;
      break;
    }
    for (int k = 0; k < ns; k++) {
      best[k] = -1;
      gb[k] = g1[k] = g2[k] = -HUGE_VAL;
    }
    /* P(n,1): 512 n samples, as before; one of several flights: as many
     * per forcing period, at least 64 */
    K = c->mi == 1 ? 512 * c->n : (int)fmax(64, ceil(512 * f.L / T));
    for (int s = 1; s < K; s++) {
      if (flight_at(&f, s * f.L / K, z)) {
        K = -1;
        break;
      }
      for (int k = 0; k < ns; k++) {
        double gs = vi_dot(N, vi_stop_w(m, k), z) - m->xsv[k];
        if (s > 2 && g1[k] >= g2[k] && g1[k] >= gs && g1[k] > gb[k]) { /* interior maxima */
          gb[k] = g1[k];
          best[k] = s - 1;
        }
        g2[k] = g1[k];
        g1[k] = gs;
      }
    }
    if (K < 0) {
      vi_xflow_destroy(&f.fl);
      found = 0;
      break;
    }
    for (int k = 0; k < ns; k++) {
      double gj, tj;
      if (best[k] >= 0 && !graze_newton(c, &f, k, best[k] * f.L / K, &gj, &tj) &&
          (!found || gj > *g)) {
        *g = gj;
        *tau = tj;
        *jg = j;
        *kg = k;
        found = 1;
      }
    }
    vi_xflow_destroy(&f.fl);
  }
  free(gb);
  free(best);
  return !found;
}

/* The grazing condition of the orbit, from the tracked flight and time. */
static int graze_g(vi_cont_curve *c, const double *Y, double *g)
{
  double tau;
  int jg, kg;
  if (c->tg > 0 && !graze_local(c, Y, c->jg, c->kg, c->tg, g, &tau)) return VI_OK;
  return graze_scan(c, Y, g, &jg, &kg, &tau) ? VI_ERR_NOT_CONVERGED : VI_OK;
}

/* Follow the grazing flight and time to the accepted point Y. */
static void graze_track(vi_cont_curve *c, const double *Y)
{
  double g, tau;
  int jg = c->jg, kg = c->kg;
  if (c->kind != VI_CONT_CURVE_GRAZING || !c->mi || setp(c, Y)) return;
  if ((c->tg > 0 && !graze_local(c, Y, jg, kg, c->tg, &g, &tau)) ||
      !graze_scan(c, Y, &g, &jg, &kg, &tau)) {
    c->tg = tau;
    c->jg = jg;
    c->kg = kg;
  }
}

/* The curve's condition g at Y (sets the model's parameters). */
static int gfun(vi_cont_curve *c, const double *Y, double *g)
{
  if (setp(c, Y)) return VI_ERR_ARG;
  if (c->kind == VI_CONT_CURVE_GRAZING)
    return c->mi ? graze_g(c, Y, g) : p10_gap(c, g);
  if (c->kind == VI_CONT_CURVE_NS) {
    int st = mults(c, Y);
    if (!st) *g = prod_pairs(c);
    return st;
  }
  /* times v_N: the saltation matrix is a rank-one update of order 1/v_N,
   * so v_N det(Mo -+ I) stays smooth up to the end of the impacting
   * branch (v_N = 0), where a fold or PD curve may end */
  double vn = 1, d; /* each impact's S has its own 1/v_N: their product */
  for (int j = 0; j < c->mi; j++)
    vn *= vi_dot(c->N, vi_stop_w(c->m, c->stops[j]), Y + (size_t)j * c->blk + 1 + c->N);
  int st = det_shift(c, Y, c->kind == VI_CONT_CURVE_FOLD ? -1 : 1, &d);
  if (!st) *g = vn * d;
  return st;
}

/* ---- the condition's change with an impact's state ------------------------ */

/* The fold or pd condition g = v_N det(Mo + s I) changes with impact j's
 * state z_j only through its saltation matrix S_j = R + d_j g_j^T / v_n,j
 * (the flows between impacts do not depend on it), and only by a rank
 * one term: with Mo = P_j S_j Q_j, a change D of d_j / v_n,j gives
 *   det(C + P_j D g_j^T Q_j) = det C (1 + rho_j . D),  C = Mo + s I,
 *   rho_j = g_j^T Q_j C^-1 P_j
 * (the matrix determinant lemma).  So the condition at z_j +- h e_k, the
 * Jacobian's row by central differences as for every other unknown, costs
 * one jump d (O(n^2)) instead of a monodromy and its factorisation
 * (O(n^3)): a step of a model of n coordinates costs O(n^3), not O(n^4).
 * lemma_prep factors C and forms rho_j and d_j / v_n,j for every impact;
 * 1 if it cannot (no memory, or C exactly singular: then the monodromy
 * is recomputed for each difference, as for the times and parameters). */
static int lemma_prep(vi_cont_curve *c, const double *Y, double s)
{
  int N = c->N, n2 = 2 * N, mi = c->mi;
  size_t nn = (size_t)n2 * n2;
  if (!c->lm) {
    c->lm = malloc(sizeof(double) * ((1 + 2 * (size_t)mi) * nn + 2 * (size_t)mi * n2 + mi +
                                     8 * (size_t)n2));
    c->lip = malloc(sizeof(lapack_int) * (size_t)n2);
    if (!c->lm || !c->lip) {
      free(c->lm);
      free(c->lip);
      c->lm = NULL;
      c->lip = NULL;
      return 1;
    }
  }
  double *C = c->lm, *Phi = C + nn, *Sa = Phi + mi * nn, *rho = Sa + mi * nn;
  double *q = rho + (size_t)mi * n2, *vnj = q + (size_t)mi * n2, *r = vnj + mi, *b = r + n2,
         *work = b + n2;
  const double *tj = times(c, Y);
  if (vi_orbit_pnm_monodromy_parts(c->m, c->n, mi, c->stops, tj, Y + 1, Y + 1 + N, c->ld, C, Phi,
                                   Sa))
    return 1;
  for (int i = 0; i < n2; i++) C[i + (size_t)i * n2] += s;
  if (LAPACKE_dgetrf(LAPACK_COL_MAJOR, n2, n2, C, n2, c->lip)) return 1;
  c->lm_det = 1;
  for (int i = 0; i < n2; i++)
    c->lm_det *= c->lip[i] != i + 1 ? -C[i + (size_t)i * n2] : C[i + (size_t)i * n2];
  c->lm_vn = 1;
  for (int j = 0; j < mi; j++) {
    const double *zj = Y + (size_t)j * c->blk + 1, *w = vi_stop_w(c->m, c->stops[j]);
    double *qj = q + (size_t)j * n2;
    vnj[j] = vi_var_salt_jump(c->m, c->stops[j], tj[j], zj, qj, work);
    for (int i = 0; i < n2; i++) qj[i] /= vnj[j];
    c->lm_vn *= vnj[j];
    /* r = g_j^T Q_j, Q_j = Phi_{j-1} S_{j-1} ... Phi_0 S_0 */
    for (int i = 0; i < n2; i++) r[i] = i < N ? w[i] : 0;
    for (int i = j - 1; i >= 0; i--) {
      cblas_dgemv(CblasColMajor, CblasTrans, n2, n2, 1.0, Phi + i * nn, n2, r, 1, 0.0, b, 1);
      cblas_dgemv(CblasColMajor, CblasTrans, n2, n2, 1.0, Sa + i * nn, n2, b, 1, 0.0, r, 1);
    }
    /* rho_j = r C^-1 P_j, P_j = Phi_{m-1} S_{m-1} ... S_{j+1} Phi_j */
    if (LAPACKE_dgetrs(LAPACK_COL_MAJOR, 'T', n2, 1, C, n2, c->lip, r, n2)) return 1;
    for (int i = mi - 1; i > j; i--) {
      cblas_dgemv(CblasColMajor, CblasTrans, n2, n2, 1.0, Phi + i * nn, n2, r, 1, 0.0, b, 1);
      cblas_dgemv(CblasColMajor, CblasTrans, n2, n2, 1.0, Sa + i * nn, n2, b, 1, 0.0, r, 1);
    }
    cblas_dgemv(CblasColMajor, CblasTrans, n2, n2, 1.0, Phi + j * nn, n2, r, 1, 0.0,
                rho + (size_t)j * n2, 1);
  }
  return 0;
}

/* The condition with unknown k of Y (a state entry of impact k / blk)
 * moved by h, from lemma_prep's pieces. */
static double lemma_g(vi_cont_curve *c, const double *Y, int k, double h)
{
  int N = c->N, n2 = 2 * N, mi = c->mi, j = k / c->blk;
  size_t nn = (size_t)n2 * n2;
  double *rho = c->lm + (1 + 2 * (size_t)mi) * nn, *q = rho + (size_t)mi * n2;
  double *vnj = q + (size_t)mi * n2, *z = vnj + mi, *d = z + n2, *work = d + n2;
  memcpy(z, Y + (size_t)j * c->blk + 1, sizeof(double) * n2);
  z[k % c->blk - 1] += h;
  double vn = vi_var_salt_jump(c->m, c->stops[j], times(c, Y)[j], z, d, work), e = 0;
  for (int i = 0; i < n2; i++) e += rho[(size_t)j * n2 + i] * (d[i] / vn - q[(size_t)j * n2 + i]);
  return c->lm_vn / vnj[j] * vn * c->lm_det * (1 + e);
}

/* The conditions at Y: F [D] (the orbit's) and, with withg, g; with J,
 * their Jacobian in the nu = D + np unknowns (column-major, leading
 * dimension ldj): J_u exact, dF/dp exact or central differences, g's row
 * central differences. */
static int sys(vi_cont_curve *c, const double *Y, int withg, double *H, double *J, int ldj)
{
  int N = c->N, D = c->D, nu = D + c->np, st = 0;
  double *Jf = c->B; /* D x D scratch, then dF/dp [D] */
  if (setp(c, Y)) return VI_ERR_ARG;
  int mi = c->mi, ld = c->ld;
  const double *tj = D ? times(c, Y) : NULL;
  if (D) st = vi_orbit_pnm_residual_stops(c->m, c->n, mi, c->stops, tj, Y + 1, Y + 1 + N, ld, H,
                                          J ? Jf : NULL);
  if (!st && D && J) {
    for (int j = 0; j < D; j++)
      for (int i = 0; i < D; i++) J[i + (size_t)j * ldj] = Jf[i + (size_t)j * D];
    for (int k = 0; k < c->np && !st; k++) {
      double *dF = Jf + (size_t)D * D, *Fm = dF + D;
      if (c->par[k] >= 0) {
        st = vi_orbit_pnm_dparam(c->m, c->n, mi, c->stops, tj, Y + 1, Y + 1 + N, ld, c->par[k],
                                 c->pk[k], dF);
      } else {
        double *Yq = c->Yq, h = 1e-6 * fmax(1.0, fabs(Y[D + k]));
        memcpy(Yq, Y, sizeof(double) * (size_t)nu);
        Yq[D + k] += h;
        st = setp(c, Yq) ? VI_ERR_ARG
             : vi_orbit_pnm_residual_stops(c->m, c->n, mi, c->stops, tj, Y + 1, Y + 1 + N, ld, dF,
                                           NULL);
        Yq[D + k] -= 2 * h;
        if (!st) st = setp(c, Yq) ? VI_ERR_ARG
                      : vi_orbit_pnm_residual_stops(c->m, c->n, mi, c->stops, tj, Y + 1,
                                                    Y + 1 + N, ld, Fm, NULL);
        for (int i = 0; i < D && !st; i++) dF[i] = (dF[i] - Fm[i]) / (2 * h);
        if (setp(c, Y)) st = VI_ERR_ARG;
      }
      for (int i = 0; i < D && !st; i++) J[i + (size_t)(D + k) * ldj] = dF[i];
    }
  }
  /* fold, pd: the state entries of g's row by the determinant lemma,
   * whose factorisation also gives g itself (gfun's value, the same LU) */
  int lem = withg && J && (c->kind == VI_CONT_CURVE_FOLD || c->kind == VI_CONT_CURVE_PD) &&
            c->mi && !st && !lemma_prep(c, Y, c->kind == VI_CONT_CURVE_FOLD ? -1 : 1);
  if (lem) H[D] = c->lm_vn * c->lm_det;
  else if (!st && withg) st = gfun(c, Y, H + D);
  if (!st && withg && J) {
    double *Yq = c->Yq, gp = 0, gm = 0;
    memcpy(Yq, Y, sizeof(double) * (size_t)nu);
    for (int j = 0; j < nu && !st; j++) {
      double h = 1e-6 * c->S[j];
      if (lem && j < D && !is_time(c, j)) {
        J[D + (size_t)j * ldj] = (lemma_g(c, Y, j, h) - lemma_g(c, Y, j, -h)) / (2 * h);
        continue;
      }
      Yq[j] = Y[j] + h;
      st = gfun(c, Yq, &gp);
      Yq[j] = Y[j] - h;
      if (!st) st = gfun(c, Yq, &gm);
      Yq[j] = Y[j];
      J[D + (size_t)j * ldj] = (gp - gm) / (2 * h);
    }
    if (setp(c, Y)) st = VI_ERR_ARG;
  }
  return st;
}

/* Dense solve A y = b (A [k x k], overwritten); 0 or 1 (singular). */
static int gauss(vi_cont_curve *c, int k, double *A, double *b)
{
  return LAPACKE_dgesv(LAPACK_COL_MAJOR, k, 1, A, k, c->ip, b, k) != 0;
}

/* Newton on the conditions (withg: g too) and, where they are one short,
 * the border bord.(Y - Yref) = 0, in the nu unknowns; Y in and out.
 * 0, or 1 if it fails (Y then undefined). */
static int newton(vi_cont_curve *c, double *Y, int withg, const double *bord,
                  const double *Yref)
{
  int D = c->D, nu = D + c->np, nh = D + withg;
  double *H = c->H, *A = c->J;
  if (nh + (bord != NULL) != nu) return 1;
  for (int it = 0; it < 25; it++) {
    if (sys(c, Y, withg, H, A, nu)) return 1;
    if (bord) {
      H[nh] = 0;
      for (int j = 0; j < nu; j++) {
        H[nh] += bord[j] * (Y[j] - Yref[j]);
        A[nh + (size_t)j * nu] = bord[j];
      }
    }
    if (gauss(c, nu, A, H)) return 1;
    double dmax = 0;
    for (int j = 0; j < nu; j++) {
      if (!isfinite(H[j])) return 1;
      Y[j] -= H[j];
      dmax = fmax(dmax, fabs(H[j]) / c->S[j]);
    }
    if (dmax > 0.5) return 1; /* a jump: another branch */
    if (dmax <= 1e-12) {
      /* the F residual itself as vi_orbit_pnm_solve's test */
      if (sys(c, Y, 0, H, NULL, nu)) return 1;
      double fn = 0, sc = 1e-12;
      for (int r = 0; r < D; r++) fn = fmax(fn, fabs(H[r]));
      for (int r = 1; r < D; r++)
        if (!is_time(c, r)) sc = fmax(sc, fabs(Y[r]));
      return fn <= 1e-10 * sc ? 0 : 1;
    }
  }
  return 1;
}

/* Tangent at Y of the solution set (nu - 1 conditions in nu unknowns):
 * the null vector, oriented along taul, unit in the scaled norm. */
static int tangent(vi_cont_curve *c, const double *Y, int withg, const double *taul,
                   double *tau)
{
  int nu = c->D + c->np, nh = c->D + withg;
  double *A = c->J;
  if (nh + 1 != nu || sys(c, Y, withg, c->H, A, nu)) return 1;
  for (int j = 0; j < nu; j++) {
    A[nh + (size_t)j * nu] = taul[j] / (c->S[j] * c->S[j]);
    tau[j] = j == nh;
  }
  if (gauss(c, nu, A, tau)) return 1;
  double nrm = 0;
  for (int j = 0; j < nu; j++) nrm += tau[j] * tau[j] / (c->S[j] * c->S[j]);
  nrm = sqrt(nrm);
  for (int j = 0; j < nu; j++) tau[j] /= nrm;
  return !(nrm > 0) || !isfinite(nrm);
}

/* The watched test functions at Y (an orbit: model at its parameters). */
static int tests(vi_cont_curve *c, const double *Y, double *T)
{
  int N = c->N;
  for (int i = 0; i < NT; i++) T[i] = NAN;
  c->rho = NAN;
  if (setp(c, Y)) return VI_ERR_ARG;
  if (!c->mi) return VI_OK;
  int st = mults(c, Y);
  if (!st) st = gap_max(c, Y, &T[T_GRAZE]);
  if (st) return st;
  c->rho = 0;
  for (int i = 0; i < 2 * N; i++) c->rho = fmax(c->rho, hypot(c->re[i], c->im[i]));
  T[T_VN] = HUGE_VAL; /* the smallest approach velocity */
  for (int j = 0; j < c->mi; j++)
    T[T_VN] = fmin(T[T_VN], vi_dot(N, vi_stop_w(c->m, c->stops[j]), Y + (size_t)j * c->blk + 1 + N));
  T[T_FOLD] = prod_shift(c, -1);
  T[T_PD] = prod_shift(c, 1);
  T[T_NS] = prod_pairs(c);
  if (c->kind == VI_CONT_CURVE_FOLD) T[T_RES] = dprod_shift(c, -1);
  if (c->kind == VI_CONT_CURVE_PD) T[T_RES] = dprod_shift(c, 1);
  if (c->kind == VI_CONT_CURVE_NS) { /* 4 p - s^2 of the pair: > 0 complex */
    int i, j;
    ns_pair(c, &i, &j);
    double complex a = c->re[i] + I * c->im[i], b = c->re[j] + I * c->im[j];
    T[T_RES] = creal(4 * a * b - (a + b) * (a + b));
  }
  return VI_OK;
}

/* ---- the handle ------------------------------------------------------------- */

/* Two keys of one number (stop.r is stops[1].r). */
static int same_param(const char *key, const char *key2)
{
  int k1, k2, a = vi_orbit_param_of_key(key, &k1), b = vi_orbit_param_of_key(key2, &k2);
  return !strcmp(key, key2) || (a >= 0 && a == b && k1 == k2);
}

int vi_cont_curve_create(const vi_model *m, int kind, int n, int mi, const char *key,
                         const char *key2, vi_cont_curve **out)
{
  if (!out) return VI_ERR_ARG;
  *out = NULL;
  if (!m || !key || kind < VI_CONT_CURVE_GRAZING || kind > VI_CONT_CURVE_NS || n < 1 ||
      mi < 0 || mi > VI_CURVE_MAXI || (mi == 0 && (n != 1 || kind != VI_CONT_CURVE_GRAZING)) ||
      vi_param_kind(key) != VI_PARAM_MODEL || strlen(key) >= 64 ||
      (key2 && (vi_param_kind(key2) != VI_PARAM_MODEL || strlen(key2) >= 64 ||
                same_param(key, key2))))
    return VI_ERR_ARG;
  if (!m->frozen) return VI_ERR_STATE;
  if (mi == 0 && (m->band || !m->M || !m->C || !m->K)) return VI_ERR_UNSUPPORTED;
  vi_cont_curve *c = calloc(1, sizeof *c);
  if (!c) return VI_ERR_NOMEM;
  int N = m->n, D = mi * (2 * N + 1), nu = D + 2;
  size_t nd = 16 * ((size_t)nu + 1) + (size_t)nu * nu + 10 * (size_t)N + (size_t)D * D +
              2 * (size_t)D + 1;
  double v0;
  c->Y = malloc(sizeof(double) * nd);
  c->ip = malloc(sizeof(lapack_int) * ((size_t)nu + 1));
  if (!c->Y || !c->ip || vi_model_copy(m, &c->m) || vi_model_param(c->m, key, &v0) ||
      (key2 && vi_model_param(c->m, key2, &v0))) {
    int st = c->Y && c->m ? VI_ERR_ARG : VI_ERR_NOMEM;
    vi_cont_curve_destroy(&c);
    return st;
  }
  memset(c->Y, 0, sizeof(double) * nd);
  double **slot[] = {&c->Yl, &c->Ys, &c->tau, &c->taul, &c->S, &c->Yt, &c->Yq,
                     &c->Yr, &c->Yg, &c->Ye, &c->Y0, &c->bord, &c->bord2, &c->H, &c->tnew};
  double *p = c->Y;
  for (size_t k = 0; k < sizeof slot / sizeof slot[0]; k++) *slot[k] = p += nu + 1;
  c->re = p += nu + 1;
  c->im = p += 2 * (size_t)N;
  c->J = p += 2 * (size_t)N;
  c->B = p + (size_t)nu * nu; /* J_u [D x D], dF/dp and a spare [D] each */
  c->fz = c->B + (size_t)D * D + 2 * (size_t)D + 1;
  snprintf(c->key, sizeof c->key, "%s", key);
  snprintf(c->key2, sizeof c->key2, "%s", key2 ? key2 : "");
  c->par[0] = vi_orbit_param_of_key(key, &c->pk[0]);
  c->par[1] = key2 ? vi_orbit_param_of_key(key2, &c->pk[1]) : -1;
  for (int k = 0; k < 2; k++)
    if (c->pk[k] >= c->m->ns) c->par[k] = -1;
  c->kind = kind;
  c->n = n;
  c->mi = mi;
  c->N = N;
  c->D = D;
  c->blk = 2 * N + 1;
  c->ld = mi > 1 ? c->blk : N; /* impact j's x, v at Y + j B + 1, + 1 + N */
  c->np = 1;
  vi_model_param(c->m, key, &c->Y[D]);
  if (key2) vi_model_param(c->m, key2, &c->Y[D + 1]);
  for (int j = 0; j < nu; j++) c->S[j] = 1;
  *out = c;
  return VI_OK;
}

void vi_cont_curve_destroy(vi_cont_curve **cp)
{
  if (!cp || !*cp) return;
  vi_model_destroy(&(*cp)->m);
  free((*cp)->Y);
  free((*cp)->ip);
  free((*cp)->lm);
  free((*cp)->lip);
  free(*cp);
  *cp = NULL;
}

const char *vi_cont_curve_errmsg(const vi_cont_curve *c) { return c ? c->errmsg : ""; }

/* Impact j's stop: the one whose gap is nearest 0 at x. */
static void pick_stop(vi_cont_curve *c, int j, const double *x)
{
  double best = HUGE_VAL;
  c->stops[j] = 0;
  for (int k = 0; k < c->m->ns; k++) {
    double g = fabs(vi_dot(c->N, vi_stop_w(c->m, k), x) - c->m->xsv[k]);
    if (g < best) {
      best = g;
      c->stops[j] = k;
    }
  }
}

int vi_cont_curve_set_impacts(vi_cont_curve *c, const double *t, const double *x,
                              const double *v, int ld)
{
  if (!c || !t || !x || !v || !c->mi || ld < c->N) return VI_ERR_ARG;
  if (c->located) return vi_fail(c->errmsg, VI_ERR_STATE, "the point is already located");
  int N = c->N, B = c->blk;
  for (int j = 0; j < c->mi; j++) {
    if (!isfinite(t[j])) return VI_ERR_NONFINITE;
    for (int i = 0; i < N; i++)
      if (!isfinite(x[i + (size_t)j * ld]) || !isfinite(v[i + (size_t)j * ld]))
        return VI_ERR_NONFINITE;
  }
  for (int j = 0; j < c->mi; j++) {
    c->Y[(size_t)j * B] = t[j];
    memcpy(c->Y + (size_t)j * B + 1, x + (size_t)j * ld, sizeof(double) * N);
    memcpy(c->Y + (size_t)j * B + 1 + N, v + (size_t)j * ld, sizeof(double) * N);
    pick_stop(c, j, x + (size_t)j * ld);
  }
  c->have_orbit = 1;
  return VI_OK;
}

int vi_cont_curve_set_orbit(vi_cont_curve *c, double t, const double *x, const double *v)
{
  if (!c || !x || !v || c->mi != 1) return VI_ERR_ARG;
  return vi_cont_curve_set_impacts(c, &t, x, v, c->N);
}

/* Scales of the unknowns: the impact time by 1/Omega, the state by its
 * size, the parameters by |p| and the range of p2. */
static void set_scales(vi_cont_curve *c)
{
  int N = c->N, D = c->D;
  double xs = 0;
  for (int i = 1; i < D; i++)
    if (!is_time(c, i)) xs = fmax(xs, fabs(c->Y[i]));
  if (!(xs > 0)) xs = 1;
  for (int i = 0; i < D; i++) c->S[i] = is_time(c, i) ? 1 / vi_model_omega_forcing(c->m) : xs;
  (void)N;
  double p = fabs(c->Y[D]);
  c->S[D] = p > 0 ? p : 1;
  c->S[D + 1] = c->have_range ? fabs(c->to2 - c->from2) : 1;
  /* P(1,0): the resonance peaks of lightly damped modes are hairpins of
   * width zeta omega in key2 (the grazing curve x_s(Omega) of a published
   * 48-dof model over Omega 10..200 at zeta = 0.02: 0.3 wide); scaled by
   * a range much wider than key2's own size they are too tight to turn,
   * so key2 is scaled by its size where that is smaller */
  if (!c->mi && c->have_range && fabs(c->Y[D + 1]) > 0)
    c->S[D + 1] = fmin(c->S[D + 1], fabs(c->Y[D + 1]));
  c->S[D + 2] = c->S[D];
}

/* ---- refining a point --------------------------------------------------------- */

/* The point of the kind from Y (np = 1): Newton on (F, g) in (u, p). */
static int refine(vi_cont_curve *c, double *Y)
{
  c->np = 1;
  /* the largest gap from scratch: the one tracked while following the
   * orbit may be another flight's or stop's (a two-sided orbit's other
   * stop comes nearer as the parameter moves) */
  c->tg = 0;
  graze_track(c, Y);
  memcpy(c->Yt, Y, sizeof(double) * (size_t)(c->D + 1));
  if (newton(c, c->Yt, 1, NULL, NULL)) return VI_ERR_NOT_CONVERGED;
  memcpy(Y, c->Yt, sizeof(double) * (size_t)(c->D + 1));
  graze_track(c, Y);
  return VI_OK;
}

/* A pair on the circle, not a real pair with product 1 (ns only). */
static int ns_complex(vi_cont_curve *c, const double *Y)
{
  if (c->kind != VI_CONT_CURVE_NS) return 1;
  int i, j;
  if (setp(c, Y) || mults(c, Y)) return 0;
  ns_pair(c, &i, &j);
  return fabs(c->im[i]) > 1e-9;
}

int vi_cont_refine_pnm(const vi_model *m, const char *key, int n, int mi, int kind,
                       double *p, double *t, double *x, double *v, int ld)
{
  if (!m || !key || !p || !t || !x || !v || mi < 1) return VI_ERR_ARG;
  if (!isfinite(*p)) return VI_ERR_NONFINITE;
  vi_cont_curve *c = NULL;
  /* the same handle and Newton as vi_cont_curve_locate's */
  int st = vi_cont_curve_create(m, kind, n, mi, key, NULL, &c);
  if (!st) st = vi_cont_curve_set_impacts(c, t, x, v, ld);
  if (!st && vi_model_set_param(c->m, key, *p)) st = VI_ERR_ARG;
  if (!st) {
    int N = c->N, B = c->blk;
    c->Y[c->D] = *p;
    set_scales(c);
    st = refine(c, c->Y);
    if (!st && !ns_complex(c, c->Y)) st = VI_ERR_NOT_CONVERGED;
    if (!st) {
      *p = c->Y[c->D];
      for (int j = 0; j < mi; j++) {
        t[j] = c->Y[(size_t)j * B];
        memcpy(x + (size_t)j * ld, c->Y + (size_t)j * B + 1, sizeof(double) * N);
        memcpy(v + (size_t)j * ld, c->Y + (size_t)j * B + 1 + N, sizeof(double) * N);
      }
    }
  }
  vi_cont_curve_destroy(&c);
  return st;
}

int vi_cont_refine(const vi_model *m, const char *key, int n, int kind, double *p,
                   double *t, double *x, double *v)
{
  return vi_cont_refine_pnm(m, key, n, 1, kind, p, t, x, v, m ? m->n : 0);
}

/* ---- pseudo-arclength --------------------------------------------------------- */

/* One step from Y along tau (withg: the curve's condition too): predictor,
 * corrector on the scaled border, the new tangent, a turn of more than
 * about 25 degrees refused; ds halved on failure.  0, or 1 when ds falls
 * below dsmax / 4096.  Y, tau advance; Yl, taul keep the last ones. */
static int advance(vi_cont_curve *c, int withg)
{
  int nu = c->D + c->np;
  double *bord = c->bord, dsm = c->dsmax;
  /* Following an orbit in one parameter (locate), dsmax is the parameter's
   * step |to - p0| / steps: where the orbit moves faster than the
   * parameter (the scaled tangent's parameter part below 1/4: the P(2,2)
   * branch of Fig. 2 moves its impact phases 40 times faster than Omega
   * before its fold) the step in arclength grows, up to 16 times, so that
   * the parameter still advances by about a quarter of that step and the
   * point budget (20 steps + 100) reaches `to`; the turn test below keeps
   * it short where the branch turns. */
  if (!withg && c->np == 1) {
    double tp = fabs(c->tau[c->D]) / c->S[c->D];
    if (tp < 0.25) dsm *= tp > 0.25 / 16 ? 0.25 / tp : 16;
  }
  /* a step of no length is no step (ds halved from 0 stays 0) */
  while (c->ds >= c->dsmax / 4096 && c->ds > 0) {
    for (int j = 0; j < nu; j++) {
      c->Ys[j] = c->Y[j] + c->ds * c->tau[j]; /* Ys: the prediction here */
      c->Yt[j] = c->Ys[j];
      bord[j] = c->tau[j] / (c->S[j] * c->S[j]);
    }
    double *tnew = c->tnew;
    int bad = newton(c, c->Yt, withg, bord, c->Ys) || tangent(c, c->Yt, withg, c->tau, tnew);
    /* the corrector moves on the border perpendicular to tau: a point
     * farther than 2 ds from Y is another branch crossing that border
     * (a grazing curve x_s(Omega) stepping over a resonance peak to the
     * same x_s on its other flank), even where the tangents agree */
    double cs = 0, ch = 0;
    for (int j = 0; !bad && j < nu; j++) {
      double e = (c->Yt[j] - c->Y[j]) / c->S[j];
      cs += tnew[j] * c->tau[j] / (c->S[j] * c->S[j]);
      if (!is_time(c, j)) ch += e * e;
    }
    if (bad || cs < 0.9 || sqrt(ch) > 2 * c->ds) {
      c->ds /= 2;
      continue;
    }
    memcpy(c->Yl, c->Y, sizeof(double) * nu);
    memcpy(c->taul, c->tau, sizeof(double) * nu);
    memcpy(c->Y, c->Yt, sizeof(double) * nu);
    memcpy(c->tau, tnew, sizeof(double) * nu);
    c->ds = fmin(dsm, 1.5 * c->ds);
    graze_track(c, c->Y);
    if (!c->mi && c->np == 2) /* the parameter's own size: through resonance peaks */
      c->S[0] = fmax(c->S[c->D + 2], fabs(c->Y[0]));
    return 0;
  }
  return 1;
}

/* The fold curve's cusp test at Y: the component of its tangent in the
 * parameter plane along the last point's (taul's), scaled.  At a cusp the
 * curve's tangent in (orbit, p, p2) stays smooth and lies along the
 * orbit alone, so its plane part goes through zero (p' ~ s, p2' ~ s^2 in
 * arclength s) and this component changes sign; the tangent at Y is taken
 * oriented along dir (the chord).  1 if there is none. */
static int cusp_test(vi_cont_curve *c, const double *Y, const double *dir, double *f)
{
  int D = c->D;
  if (tangent(c, Y, 1, dir, c->tnew)) return 1;
  *f = 0;
  for (int j = D; j < D + 2; j++) *f += c->tnew[j] * c->taul[j] / (c->S[j] * c->S[j]);
  return 0;
}

/* Y on the solution set between Ya and Yb (withg: the curve) where the
 * test T[k] (or, k = K_CUSP, the cusp test) vanishes: regula falsi
 * (Illinois) on the chord, each point corrected on the border
 * perpendicular to it.  0 (Y found), or 1 (Y the interpolation). */
static int locate(vi_cont_curve *c, const double *Ya, const double *Yb, double ta,
                  double tb, int k, int withg, double *Y)
{
  int nu = c->D + c->np, side = 0;
  double *bord = c->bord2, d2 = 0, Tq[NT];
  /* v_N = 0 itself has no monodromy (the saltation matrix is singular):
   * the point 1e-9 of the state scale before it */
  double off = k == T_VN ? 1e-9 * c->S[1] * (ta > 0 ? 1 : -1) : 0;
  ta -= off;
  tb -= off;
  double a = 0, b = 1, fa = ta, fb = tb, th;
  double *Yr = c->Yr; /* the chord's point */
  for (int j = 0; j < nu; j++) {
    bord[j] = (Yb[j] - Ya[j]) / (c->S[j] * c->S[j]);
    d2 += bord[j] * (Yb[j] - Ya[j]);
  }
  if (!(d2 > 0)) return 1;
  for (int it = 0; it < 60; it++) {
    th = (a * fb - b * fa) / (fb - fa);
    for (int j = 0; j < nu; j++) Yr[j] = Ya[j] + th * (Yb[j] - Ya[j]);
    memcpy(Y, Yr, sizeof(double) * nu);
    if (newton(c, Y, withg, bord, Yr)) break;
    double f;
    if (k >= 0) {
      if (tests(c, Y, Tq)) break;
      f = Tq[k] - off;
    } else {
      for (int j = 0; j < nu; j++) c->bord[j] = Yb[j] - Ya[j];
      if (cusp_test(c, Y, c->bord, &f)) break;
    }
    if (f == 0 || fabs(b - a) < 1e-14) return 0;
    if ((f < 0) == (fa < 0)) {
      a = th;
      fa = f;
      if (side == -1) fb /= 2;
      side = -1;
    } else {
      b = th;
      fb = f;
      if (side == 1) fa /= 2;
      side = 1;
    }
    if (fabs(b - a) < 1e-13) return 0;
  }
  th = ta / (ta - tb);
  for (int j = 0; j < nu; j++) Y[j] = Ya[j] + th * (Yb[j] - Ya[j]);
  return 1;
}

/* ---- locating the first point ----------------------------------------------- */

/* P(1,0): the gap on a grid of key from its value to `to`. */
static int locate_p10(vi_cont_curve *c, double to, int steps)
{
  double p0 = c->Y[0], g0, g1;
  c->S[0] = fabs(p0) > 0 ? fabs(p0) : 1;
  int st = gfun(c, c->Y, &g0);
  for (int k = 1; !st && k <= steps; k++) {
    double y = p0 + (to - p0) * k / steps;
    st = gfun(c, &y, &g1);
    if (st || (g1 < 0) == (g0 < 0)) {
      g0 = g1;
      continue;
    }
    c->Y[0] = y - (to - p0) / steps * g1 / (g1 - g0);
    if (refine(c, c->Y)) return vi_fail(c->errmsg, VI_ERR_NOT_CONVERGED, "%s: the grazing "
                                        "point near %.17g did not converge", c->key, y);
    return VI_OK;
  }
  if (st) return vi_fail(c->errmsg, st, "%s: the non-impacting orbit: %s", c->key,
                         vi_strerror(st));
  return vi_fail(c->errmsg, VI_STOPPED, "no grazing of the non-impacting orbit between "
                 "%s = %.17g and %.17g", c->key, p0, to);
}

/* The kind's test among the watched ones. */
static int kind_test(int kind)
{
  return kind == VI_CONT_CURVE_GRAZING ? T_GRAZE
         : kind == VI_CONT_CURVE_FOLD ? T_FOLD : kind == VI_CONT_CURVE_PD ? T_PD : T_NS;
}

int vi_cont_curve_locate(vi_cont_curve *c, double to, int steps, double *param)
{
  if (!c || steps < 1) return VI_ERR_ARG;
  if (!isfinite(to)) return VI_ERR_NONFINITE;
  if (c->located || (c->mi && !c->have_orbit))
    return vi_fail(c->errmsg, VI_ERR_STATE, "%s", c->located ? "already located"
                   : "set the orbit first");
  int D = c->D, st;
  c->np = 1;
  double p0 = c->Y[D];
  if (to == p0) /* a search of no length: its step would be 0 */
    return vi_fail(c->errmsg, VI_ERR_ARG, "%s: the search's end %.17g is the model's "
                   "value: nothing to search", c->key, to);
  if (!c->mi) st = locate_p10(c, to, steps);
  else {
    /* the orbit at p0: Newton with p held by the border */
    set_scales(c);
    double *bord = c->bord;
    for (int j = 0; j <= D; j++) {
      bord[j] = j == D;
      c->taul[j] = j == D ? (to > p0 ? 1 : -1) * c->S[D] : 0;
    }
    memcpy(c->Ys, c->Y, sizeof(double) * (D + 1));
    if (newton(c, c->Y, 0, bord, c->Ys) || tangent(c, c->Y, 0, c->taul, c->tau))
      return vi_fail(c->errmsg, VI_ERR_NOT_CONVERGED, "%s = %.17g: no P(%d,%d) orbit from "
                     "the orbit given", c->key, p0, c->n, c->mi);
    set_scales(c);
    c->dsmax = c->ds = fabs(to - p0) / steps / c->S[D];
    int k = kind_test(c->kind);
    st = tests(c, c->Y, c->T);
    for (int it = 0; !st; it++) {
      if (it > 20 * steps + 100 || advance(c, 0)) {
        st = vi_fail(c->errmsg, VI_STOPPED, "no %s point: the P(%d,%d) branch in %s is lost "
                     "after %.17g", k == T_GRAZE ? "grazing" : k == T_FOLD ? "fold"
                     : k == T_PD ? "period-doubling" : "Neimark-Sacker", c->n, c->mi, c->key,
                     c->Y[D]);
        break;
      }
      memcpy(c->Tl, c->T, sizeof c->T);
      if ((st = tests(c, c->Y, c->T))) break;
      if (c->T[T_VN] <= 0 && c->Tl[T_VN] > 0) { /* beyond, no impact: not an orbit */
        st = vi_fail(c->errmsg, VI_STOPPED, "no %s point: the P(%d,%d) orbit stops impacting "
                     "(v_N = 0) near %s = %.17g", k == T_GRAZE ? "grazing" : k == T_FOLD ?
                     "fold" : k == T_PD ? "period-doubling" : "Neimark-Sacker", c->n, c->mi,
                     c->key, c->Y[D]);
        break;
      }
      int cross = (c->T[k] < 0) != (c->Tl[k] < 0);
      if (cross && k == T_GRAZE && c->T[T_VN] <= 0 && c->Tl[T_VN] <= 0) cross = 0;
      /* the gap between impacts reaching the stop: beyond, the orbit goes
       * through it (a point found there would be of no motion) */
      int out = k != T_GRAZE && c->Tl[T_GRAZE] < 0 && !(c->T[T_GRAZE] < 0);
      double Tq[NT];
      if (cross) {
        double *Yg = c->Yg;
        locate(c, c->Yl, c->Y, c->Tl[k], c->T[k], k, 0, Yg);
        if (!refine(c, Yg) && ns_complex(c, Yg) &&
            !(out && (tests(c, Yg, Tq) || !(Tq[T_GRAZE] < 0)))) {
          memcpy(c->Y, Yg, sizeof(double) * (D + 1));
          break;
        }
      }
      if (out) {
        st = vi_fail(c->errmsg, VI_STOPPED, "no %s point: the P(%d,%d) orbit grazes the stop "
                     "(not admissible beyond) near %s = %.17g", k == T_FOLD ? "fold" : k == T_PD
                     ? "period-doubling" : "Neimark-Sacker", c->n, c->mi, c->key, c->Y[D]);
        break;
      }
      if (cross && c->kind != VI_CONT_CURVE_NS) {
        st = vi_fail(c->errmsg, VI_ERR_NOT_CONVERGED, "%s: the point near %.17g did not "
                     "converge", c->key, c->Yg[D]);
        break;
      }
      if ((c->Y[D] - to) * (to > p0 ? 1 : -1) > 0) {
        st = vi_fail(c->errmsg, VI_STOPPED, "no such point of the P(%d,%d) orbit between "
                     "%s = %.17g and %.17g", c->n, c->mi, c->key, p0, to);
        break;
      }
    }
  }
  if (st) return st;
  c->located = 1;
  c->npts = 0;
  if (c->mi) tests(c, c->Y, c->T);
  if (param) *param = c->Y[D];
  return VI_OK;
}

/* ---- the curve ------------------------------------------------------------------- */

int vi_cont_curve_set_range(vi_cont_curve *c, double from2, double to2, int steps)
{
  if (!c || steps < 1 || !c->key2[0] || from2 == to2) return VI_ERR_ARG;
  if (!isfinite(from2) || !isfinite(to2)) return VI_ERR_NONFINITE;
  c->from2 = from2;
  c->to2 = to2;
  c->maxpts = 20 * (int64_t)steps + 100;
  c->dsmax = 1.0 / steps;
  c->have_range = 1;
  return VI_OK;
}

static void add_special(vi_cont_curve *c, int type, const double *Y, int located)
{
  if (c->nsp >= MAXSP) return;
  special s = {type, located, Y[c->D], Y[c->D + 1]};
  c->sp[c->nsp++] = s;
}

/* The point on the curve where p2 = b, between Yl and Y: Newton with p2
 * held, from the chord.  Y receives it (or stays). */
static void to_bound(vi_cont_curve *c, double b)
{
  int D = c->D, nu = D + 2;
  double th = (b - c->Yl[D + 1]) / (c->Y[D + 1] - c->Yl[D + 1]);
  double *bord = c->bord;
  for (int j = 0; j < nu; j++) {
    c->Yt[j] = c->Yl[j] + th * (c->Y[j] - c->Yl[j]);
    bord[j] = j == D + 1;
  }
  c->Yt[D + 1] = b;
  memcpy(c->Ys, c->Yt, sizeof(double) * nu);
  if (!newton(c, c->Yt, 1, bord, c->Ys)) memcpy(c->Y, c->Yt, sizeof(double) * nu);
}

/* Whether test k's sign change from Tl to T ends the curve: the orbit
 * stops being admissible (its gap reaches the stop, or v_N falls through
 * 0), or (ns) its pair turns real. */
static int ends_at(const vi_cont_curve *c, int k, const double *T)
{
  return (k == T_GRAZE && c->Tl[T_GRAZE] < 0) || (k == T_VN && c->Tl[T_VN] > 0) ||
         (k == T_RES && c->kind == VI_CONT_CURVE_NS && c->Tl[T_RES] > 0 && !(T[T_RES] > 0));
}

/* A cusp of the fold curve between the last point and this one: the
 * plane tangent's component along the last one's changes sign.  Located
 * where it vanishes, and a cusp only if the whole plane tangent vanishes
 * there (else the curve merely turned by more than a right angle in the
 * plane within a step, which it does not at a step's 25 degrees in the
 * whole space unless its plane part is small: then it is reported as
 * seen, unlocated). */
static void cusp(vi_cont_curve *c)
{
  int D = c->D, nu = D + 2;
  double fa = 0, fb = 0;
  for (int j = D; j < nu; j++) {
    double s2 = c->S[j] * c->S[j];
    fa += c->taul[j] * c->taul[j] / s2;
    fb += c->tau[j] * c->taul[j] / s2;
  }
  if (!(fb < 0)) return;
  double *Yq = c->Yg;
  int loc = !locate(c, c->Yl, c->Y, fa, fb, K_CUSP, 1, Yq);
  if (loc) { /* the plane tangent there, against the whole (unit) one */
    double pl = 0;
    loc = !tangent(c, Yq, 1, c->tau, c->tnew);
    for (int j = D; loc && j < nu; j++) pl += c->tnew[j] * c->tnew[j] / (c->S[j] * c->S[j]);
    loc = loc && sqrt(pl) <= 1e-6;
  }
  add_special(c, VI_CONT_SP_CUSP, loc ? Yq : c->Y, loc);
}

/* The codimension-two points between the last point and this one; 1 if
 * one ends the curve (Y is then that point). */
static int specials(vi_cont_curve *c, int report)
{
  static const int watch[4][5] = {{T_FOLD, T_PD, T_VN, -1, -1},
                                  {T_PD, T_GRAZE, T_VN, T_RES, -1},
                                  {T_FOLD, T_GRAZE, T_VN, T_RES, -1},
                                  {T_FOLD, T_PD, T_GRAZE, T_VN, T_RES}};
  int D = c->D, nu = D + 2;
  if (!c->mi) return 0;
  double *Yq = c->Yg, Tq[NT], Te[NT];
  if (c->kind == VI_CONT_CURVE_FOLD && report) cusp(c);
  /* A step that ends the curve (admissibility lost) is cut at that end,
   * located first: beyond v_N = 0 a multiplier comes back from infinity
   * (the saltation matrix's 1/v_N), and the products of the fold and pd
   * tests change sign through that pole, not through a zero. */
  int ke = -1, le = 0;
  const double *Tb = c->T, *Yb = c->Y;
  for (int w = 0; w < 5 && watch[c->kind][w] >= 0 && ke < 0; w++) {
    int k = watch[c->kind][w];
    if ((k == T_GRAZE || k == T_VN) && (c->T[k] < 0) != (c->Tl[k] < 0) && !isnan(c->T[k]) &&
        !isnan(c->Tl[k]) && ends_at(c, k, c->T))
      ke = k;
  }
  if (ke >= 0) {
    le = !locate(c, c->Yl, c->Y, c->Tl[ke], c->T[ke], ke, 1, c->Ye);
    if (!tests(c, c->Ye, Te)) {
      Te[ke] = c->T[ke]; /* the end's own side: it is the one crossing */
      Tb = Te;
      Yb = c->Ye;
    }
  }
  int ns_res = c->kind == VI_CONT_CURVE_NS && (Tb[T_RES] < 0) != (c->Tl[T_RES] < 0);
  for (int w = 0; w < 5 && watch[c->kind][w] >= 0; w++) {
    int k = watch[c->kind][w];
    if (!((Tb[k] < 0) != (c->Tl[k] < 0)) || isnan(Tb[k]) || isnan(c->Tl[k])) continue;
    if (ns_res && (k == T_FOLD || k == T_PD)) continue; /* the resonance itself */
    int loc, type;
    if (k == ke) {
      memcpy(Yq, c->Ye, sizeof(double) * nu);
      loc = le;
    } else {
      loc = !locate(c, c->Yl, Yb, c->Tl[k], Tb[k], k, 1, Yq);
    }
    if (k == T_RES && c->kind == VI_CONT_CURVE_NS) {
      tests(c, Yq, Tq);
      int i, j;
      ns_pair(c, &i, &j);
      type = c->re[i] > 0 ? VI_CONT_SP_RESONANCE_11 : VI_CONT_SP_RESONANCE_12;
    } else {
      type = k == T_FOLD ? VI_CONT_SP_FOLD : k == T_PD ? VI_CONT_SP_PD
             : k == T_GRAZE ? VI_CONT_SP_GRAZING : k == T_VN ? VI_CONT_SP_ADMISSIBILITY
             : c->kind == VI_CONT_CURVE_FOLD ? VI_CONT_SP_RESONANCE_11 : VI_CONT_SP_RESONANCE_12;
    }
    if (report) add_special(c, type, Yq, loc);
    /* ends: admissibility lost, or an NS pair turning real (beyond, a
     * neutral saddle, no bifurcation) */
    if (ends_at(c, k, Tb)) {
      if (!report) { /* the backward pass's end: reported with the first point */
        special e = {type, loc, Yq[D], Yq[D + 1]};
        c->endsp = e;
        c->have_endsp = 1;
      }
      memcpy(c->Y, Yq, sizeof(double) * nu);
      tests(c, c->Y, c->T);
      return k == T_RES ? 2 : 1;
    }
  }
  return 0;
}

/* Follow the curve from the located point backwards to its end, unreported;
 * then turn round.  0, or a status. */
static int start_curve(vi_cont_curve *c)
{
  int D = c->D, nu = D + 2;
  double lo = fmin(c->from2, c->to2), hi = fmax(c->from2, c->to2);
  c->np = 2;
  if (!(c->Y[D + 1] >= lo && c->Y[D + 1] <= hi))
    return vi_fail(c->errmsg, VI_ERR_ARG, "%s = %.17g at the located point is outside the "
                   "range %.17g to %.17g", c->key2, c->Y[D + 1], c->from2, c->to2);
  set_scales(c);
  for (int j = 0; j < nu; j++) c->taul[j] = j == D + 1 ? (c->from2 < c->to2 ? -1 : 1) : 0;
  if (tangent(c, c->Y, 1, c->taul, c->tau)) { /* perpendicular to p2: along p */
    for (int j = 0; j < nu; j++) c->taul[j] = j == D;
    if (tangent(c, c->Y, 1, c->taul, c->tau))
      return vi_fail(c->errmsg, VI_ERR_NOT_CONVERGED, "no tangent to the curve at %s = "
                     "%.17g, %s = %.17g", c->key, c->Y[D], c->key2, c->Y[D + 1]);
  }
  double *Y0 = c->Y0;
  memcpy(Y0, c->Y, sizeof(double) * nu);
  c->far = 0;
  c->ds = c->dsmax;
  if (c->mi) tests(c, c->Y, c->T);
  c->start_state = VI_CONT_CURVE_STALLED; /* unless the loop ends otherwise */
  /* the budget holds each way from the located point: the pass from the
   * start retraces these steps, then has maxpts more (with one budget for
   * both, a long way back left none ahead: the 4-mode FE beam's grazing
   * curve ran 4100 points back from Omega 0.855 to 0.11 and stopped short
   * of where it was located, never going on towards --to) */
  c->nback = 0;
  for (int64_t k = 0; k < c->maxpts; k++, c->nback++) {
    if (advance(c, 1)) {
      c->start_state = VI_CONT_CURVE_CORRECTOR;
      break;
    }
    memcpy(c->Tl, c->T, sizeof c->T);
    if (c->mi) tests(c, c->Y, c->T);
    if (c->Y[D + 1] < lo || c->Y[D + 1] > hi) {
      to_bound(c, c->Y[D + 1] < lo ? lo : hi);
      c->start_state = VI_CONT_CURVE_END;
      break;
    }
    int e = specials(c, 0);
    if (e) {
      c->start_state = e == 2 ? VI_CONT_CURVE_RESONANCE : VI_CONT_CURVE_ENDS;
      break;
    }
    double dist = 0;
    for (int j = 0; j < nu; j++)
      if (!is_time(c, j)) dist = fmax(dist, fabs(c->Y[j] - Y0[j]) / c->S[j]);
    c->far = fmax(c->far, dist);
    /* closed: back where it began, after going away (not a stall) */
    if (k > 3 && c->far > 2 * c->dsmax && dist < 0.5 * c->dsmax) {
      memcpy(c->Y, Y0, sizeof(double) * nu);
      c->start_state = VI_CONT_CURVE_CLOSES;
      break;
    }
  }
  /* turn round: the tangent at the end, reversed (at an end where the
   * orbit stops impacting, v_N = 0, none: from the point before it) */
  for (int j = 0; j < nu; j++) c->taul[j] = -c->tau[j];
  if (tangent(c, c->Y, 1, c->taul, c->tau)) {
    memcpy(c->Y, c->Yl, sizeof(double) * nu);
    if (tangent(c, c->Y, 1, c->taul, c->tau))
      return vi_fail(c->errmsg, VI_ERR_NOT_CONVERGED, "no tangent at the end of the curve");
  }
  memcpy(c->Ys, c->Y, sizeof(double) * nu);
  memcpy(Y0, c->Y, sizeof(double) * nu);
  c->far = 0;
  c->ds = c->dsmax;
  if (c->mi) tests(c, c->Y, c->T);
  c->npts = 1;
  if (c->have_endsp) c->sp[c->nsp++] = c->endsp;
  return VI_OK;
}

int vi_cont_curve_iterate(vi_cont_curve *c)
{
  if (!c) return VI_ERR_ARG;
  c->nsp = 0;
  if (!c->located || !c->have_range || c->state)
    return vi_fail(c->errmsg, VI_ERR_STATE, "%s", c->state ? "the curve is done"
                   : "locate the point and set the range first");
  int D = c->D, nu = D + 2;
  if (!c->started) {
    c->started = 1;
    int st = start_curve(c);
    if (st) c->state = VI_CONT_CURVE_STALLED;
    return st;
  }
  if (c->npts >= c->nback + c->maxpts) {
    c->state = VI_CONT_CURVE_STALLED;
    return VI_STOPPED;
  }
  if (advance(c, 1)) {
    c->state = VI_CONT_CURVE_CORRECTOR;
    return VI_STOPPED;
  }
  memcpy(c->Tl, c->T, sizeof c->T);
  if (c->mi) tests(c, c->Y, c->T);
  double lo = fmin(c->from2, c->to2), hi = fmax(c->from2, c->to2);
  if (c->Y[D + 1] < lo || c->Y[D + 1] > hi) {
    to_bound(c, c->Y[D + 1] < lo ? lo : hi);
    if (c->mi) tests(c, c->Y, c->T);
    c->state = VI_CONT_CURVE_END;
  }
  int e = specials(c, 1);
  if (e) c->state = e == 2 ? VI_CONT_CURVE_RESONANCE : VI_CONT_CURVE_ENDS;
  c->npts++;
  const double *Y0 = c->Y0;
  double dist = 0;
  for (int j = 0; j < nu; j++)
    if (!is_time(c, j)) dist = fmax(dist, fabs(c->Y[j] - Y0[j]) / c->S[j]);
  c->far = fmax(c->far, dist);
  if (!c->state && c->npts > 4 && c->far > 2 * c->dsmax && dist < 0.5 * c->dsmax)
    c->state = VI_CONT_CURVE_CLOSES;
  return VI_OK;
}

int vi_cont_curve_done(const vi_cont_curve *c) { return c ? c->state : 0; }

int vi_cont_curve_start(const vi_cont_curve *c) { return c && c->started ? c->start_state : 0; }

int vi_cont_curve_point(const vi_cont_curve *c, double *p, double *p2, double *t,
                        double *x, double *v, double *rho)
{
  if (!c) return VI_ERR_ARG;
  if (!c->located) return VI_ERR_STATE;
  int D = c->D, N = c->N;
  if (p) *p = c->Y[D];
  if (p2) {
    double v2 = NAN;
    if (c->key2[0]) v2 = c->Y[D + 1];
    *p2 = v2;
  }
  if (c->mi) {
    if (t) *t = c->Y[0];
    if (x) memcpy(x, c->Y + 1, sizeof(double) * N);
    if (v) memcpy(v, c->Y + 1 + N, sizeof(double) * N);
  }
  if (rho) *rho = c->mi ? c->rho : NAN;
  return VI_OK;
}

int vi_cont_curve_impacts(const vi_cont_curve *c, double *t, double *x, double *v, int ld)
{
  if (!c || !c->mi || ld < c->N) return VI_ERR_ARG;
  if (!c->located) return VI_ERR_STATE;
  int N = c->N, B = c->blk;
  for (int j = 0; j < c->mi; j++) {
    if (t) t[j] = c->Y[(size_t)j * B];
    if (x) memcpy(x + (size_t)j * ld, c->Y + (size_t)j * B + 1, sizeof(double) * N);
    if (v) memcpy(v + (size_t)j * ld, c->Y + (size_t)j * B + 1 + N, sizeof(double) * N);
  }
  return VI_OK;
}

int vi_cont_curve_num_special(const vi_cont_curve *c) { return c ? c->nsp : 0; }

int vi_cont_curve_special(const vi_cont_curve *c, int i, int *type, double *p, double *p2,
                          int *located)
{
  if (!c || i < 0 || i >= c->nsp) return VI_ERR_ARG;
  const special *s = &c->sp[i];
  if (type) *type = s->type;
  if (p) *p = s->p;
  if (p2) *p2 = s->p2;
  if (located) *located = s->located;
  return VI_OK;
}
