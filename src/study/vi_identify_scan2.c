/* vi_identify_scan2.c - every P(n, 2) orbit on one stop from a scan of
 * impact phases, the way vi_orbit_p1_scan finds every P(n, 1) orbit: a
 * model whose transient settles elsewhere still offers the recording's
 * two-impact motion to the fit (issue 28).
 *
 * For impacts at t1 and t2 = t1 + tau the flow between them is affine,
 * so the periodic motion with those impacts is one linear solve: with J
 * the impact map (WB 2) and Phi the transition matrix,
 *   z1 = Phi(P - tau) J (Phi(tau) J z1 + g1) + g2,
 * g1, g2 the forced response from rest over each leg.  It is a P(n, 2)
 * orbit where both gaps w.x1 - x_s and w.x2 - x_s vanish: the cells of a
 * grid over (t1, tau) where both change sign seed Newton on the full
 * conditions (vi_orbit_pnm_solve_stops). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>
#include <lapacke.h>

#include "vi_identify_internal.h"

#define MAXN2 32 /* 2N at most: larger models keep their transients only */

/* The matrices of one tau: LU of I - Phi2 J Phi1 J, Phi2 J, Phi1 J. */
typedef struct leg {
  double *lu, *c2, *c1;
  lapack_int *piv;
  int ok;
} leg;

/* a [n2 x n2] = b c (column-major). */
static void mul(int n2, const double *b, const double *c, double *a)
{
  cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n2, n2, n2, 1.0, b, n2,
              c, n2, 0.0, a, n2);
}

static void matvec(int n2, const double *a, const double *x, double *y)
{
  cblas_dgemv(CblasColMajor, CblasNoTrans, n2, n2, 1.0, a, n2, x, 1, 0.0, y, 1);
}

/* The matrices of the legs tau and P - tau; work [3 n2^2]. */
static void leg_setup(const vi_model *m, const double *J, double tau, double P,
                      leg *L, double *work)
{
  int n2 = 2 * m->n;
  size_t nn = (size_t)n2 * n2;
  double *ph = work, *b = ph + nn;
  L->ok = 0;
  if (vi_var_stm(m, tau, ph)) return;
  mul(n2, ph, J, L->c1);
  if (vi_var_stm(m, P - tau, ph)) return;
  mul(n2, ph, J, L->c2);
  mul(n2, L->c2, L->c1, b);
  for (size_t i = 0; i < nn; i++) L->lu[i] = -b[i];
  for (int i = 0; i < n2; i++) L->lu[i + (size_t)i * n2] += 1.0;
  L->ok = LAPACKE_dgetrf(LAPACK_COL_MAJOR, n2, n2, L->lu, n2, L->piv) == 0;
}

/* The forced response from rest over both legs of the impacts at t1[i]
 * and t1[i] + tau, i < k: g1 from t1 to t1 + tau and g2 from there to
 * t1 + P into the columns of G1, G2 [2N x k].  At rest the modal start is
 * 0: the modal responses of all k go to physical coordinates in one
 * product per block; Q [2N x k], sg a flight of the model's flow. */
static void rest_response(const vi_model *m, vi_xseg *sg, int k,
                          const double *t1, double tau, double P, double *Q,
                          double *G1, double *G2)
{
  int N = m->n, n2 = 2 * N;
  double zero[MAXN2] = {0};
  for (int second = 0; second < 2; second++) {
    double *G = second ? G2 : G1;
    for (int i = 0; i < k; i++) {
      double ta = second ? t1[i] + tau : t1[i], tb = second ? t1[i] + P : t1[i] + tau;
      double *g = G + (size_t)i * n2;
      if (sg->g) { /* other damping: the first-order flow's own map */
        vi_xseg_start(sg, ta, zero, zero);
        vi_xseg_physical(sg, tb, g, g + N, Q);
      } else {
        vi_xseg_start_modal(sg, ta, zero, zero);
        vi_xseg_modal(sg, tb, Q + (size_t)i * n2, Q + (size_t)i * n2 + N, NULL);
      }
    }
    if (sg->g) continue;
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, N, k, N, 1.0, m->Psi,
                N, Q, n2, 0.0, G, n2);
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, N, k, N, 1.0, m->Psi,
                N, Q + N, n2, 0.0, G + N, n2);
  }
}

/* The periodic motion with impacts at t1 and t1 + tau from the forced
 * response g1, g2 [2N] of its legs (rest_response): pre-impact states
 * z1, z2 [2N].  0, or non-zero where the leg is singular. */
static int fixed_point(const leg *L, int n2, const double *g1,
                       const double *g2, double *z1, double *z2)
{
  if (!L->ok) return 1;
  matvec(n2, L->c2, g1, z1);
  for (int i = 0; i < n2; i++) z1[i] += g2[i];
  if (LAPACKE_dgetrs(LAPACK_COL_MAJOR, 'N', n2, 1, L->lu, n2, L->piv, z1, n2)) return 1;
  matvec(n2, L->c1, z1, z2);
  for (int i = 0; i < n2; i++) z2[i] += g1[i];
  for (int i = 0; i < n2; i++)
    if (!isfinite(z1[i]) || !isfinite(z2[i])) return 1;
  return 0;
}

/* The same orbit: impact times equal modulo P up to a cyclic shift. */
static int same_orbit(const orb *a, const orb *b, double P)
{
  for (int s = 0; s < 2; s++) {
    int eq = 1;
    for (int j = 0; j < 2; j++) {
      double d = fmod(fabs(a->t[j] - b->t[(j + s) % 2]), P);
      eq &= fmin(d, P - d) < 1e-7 * P;
    }
    if (eq) return 1;
  }
  return 0;
}

/* Grid point u in (0, K + 1) of the lag between the impacts: a smooth
 * step in u / (K + 1), its points 1e-3 P apart at either end. */
static double tau_at(double P, double u, int K)
{
  double s = u / (K + 1);
  return P * s * s * (3.0 - 2.0 * s);
}

int vi_id_scan_p2(vi_identify *id, int nd, orb *out, int cap, int *found)
{
  const vi_model *m = id->cur;
  int N = m->n, n2 = 2 * N, st = VI_OK;
  *found = 0;
  /* one stop (the scan's impact map), a closed-form flow, a small model,
   * orbits of at most 2 forcing periods: else the transients alone */
  if (m->ns != 1 || n2 > MAXN2 || !id->xf || !id->xf->ok || nd > 2 || cap < 1)
    return VI_OK;
  const int K1 = 64 * nd, K2 = 64 * nd;
  double P = vi_id_period_of(m, nd), xs = m->xsv[0];
  const double *w = vi_stop_w(m, 0);
  size_t nn = (size_t)n2 * n2;
  double *J = malloc(sizeof(double) * (nn * (3 * (size_t)K2 + 7) + (size_t)n2 * 12 +
                                       4 * (size_t)K1 * K2 + 3 * (size_t)n2 * K1));
  lapack_int *piv = malloc(sizeof(lapack_int) * (size_t)n2 * (K2 + 1));
  leg *L = malloc(sizeof *L * (size_t)(K2 + 1));
  if (!J || !piv || !L) {
    free(J);
    free(piv);
    free(L);
    return VI_ERR_NOMEM;
  }
  double *mats = J + nn, *work = mats + nn * 3 * (size_t)(K2 + 1);
  double *z1 = work + 3 * nn, *z2 = z1 + n2, *fw = z2 + n2;
  double *h1 = fw + 3 * (size_t)n2, *h2 = h1 + (size_t)K1 * K2,
         *a1 = h2 + (size_t)K1 * K2, *a2 = a1 + (size_t)K1 * K2;
  double *Q = a2 + (size_t)K1 * K2, *G1 = Q + (size_t)n2 * K1, *G2 = G1 + (size_t)n2 * K1;
  double t1s[64 * 2], sbuf[3 * MAXN2 / 2];
  vi_xseg sg;
  if (vi_xseg_init(&sg, id->xf, m, sbuf)) {
    free(J);
    free(piv);
    free(L);
    return VI_ERR_NOMEM;
  }
  for (int i = 0; i < K1; i++) t1s[i] = P * i / K1;
  for (int k = 0; k <= K2; k++) {
    L[k].lu = mats + nn * 3 * (size_t)k;
    L[k].c2 = L[k].lu + nn;
    L[k].c1 = L[k].c2 + nn;
    L[k].piv = piv + (size_t)n2 * k;
  }
  /* J: the impact map's columns */
  for (int k = 0; k < n2; k++) {
    memset(z1, 0, sizeof(double) * n2);
    z1[k] = 1.0;
    vi_var_impact(m, 0, z1, J + (size_t)k * n2);
  }
  /* the gaps over the grid: t1_i = P i / K1, tau_k dense near 0 and P
   * (a second impact just after the first, near grazing, is the common
   * P(n,2): 0.012 T apart on the 4-mode beam at r = 0.29) */
  for (int k = 0; k < K2 && !st; k++) {
    if (vi_id_poll_cancel(id)) st = VI_CANCELLED;
    double tau = tau_at(P, k + 1.0, K2);
    leg_setup(m, J, tau, P, &L[k], work);
    if (L[k].ok) rest_response(m, &sg, K1, t1s, tau, P, Q, G1, G2);
    for (int i = 0; i < K1; i++) {
      size_t q = (size_t)i + (size_t)K1 * k;
      if (fixed_point(&L[k], n2, G1 + (size_t)i * n2, G2 + (size_t)i * n2, z1, z2)) {
        h1[q] = h2[q] = NAN;
        continue;
      }
      h1[q] = vi_dot(N, w, z1) - xs;
      h2[q] = vi_dot(N, w, z2) - xs;
      a1[q] = vi_dot(N, w, z1 + N); /* approach velocities */
      a2[q] = vi_dot(N, w, z2 + N);
    }
  }
  /* cells where both gaps change sign and both impacts can approach:
   * Newton from the fixed point at the cell's centre */
  leg *Lc = &L[K2];
  for (int k = 0; k + 1 < K2 && !st; k++) {
    if (vi_id_poll_cancel(id)) st = VI_CANCELLED;
    for (int i = 0; i < K1 && !st; i++) {
      size_t q[4] = {(size_t)i + (size_t)K1 * k, (size_t)(i + 1) % K1 + (size_t)K1 * k,
                     (size_t)i + (size_t)K1 * (k + 1), (size_t)(i + 1) % K1 + (size_t)K1 * (k + 1)};
      double l1 = HUGE_VAL, u1 = -HUGE_VAL, l2 = HUGE_VAL, u2 = -HUGE_VAL;
      int app = 0, bad = 0;
      for (int c = 0; c < 4; c++) {
        bad |= isnan(h1[q[c]]);
        l1 = fmin(l1, h1[q[c]]);
        u1 = fmax(u1, h1[q[c]]);
        l2 = fmin(l2, h2[q[c]]);
        u2 = fmax(u2, h2[q[c]]);
        app |= a1[q[c]] > 0.0 && a2[q[c]] > 0.0;
      }
      if (bad || !app || !(l1 <= 0.0 && u1 >= 0.0 && l2 <= 0.0 && u2 >= 0.0)) continue;
      double t1 = P * (i + 0.5) / K1, tau = tau_at(P, k + 1.5, K2);
      leg_setup(m, J, tau, P, Lc, work);
      if (Lc->ok) rest_response(m, &sg, 1, &t1, tau, P, Q, G1, G2);
      if (fixed_point(Lc, n2, G1, G2, z1, z2)) continue;
      orb *o = &out[*found < cap ? *found : cap - 1];
      orb c;
      c.n = nd;
      c.m = 2;
      c.stop[0] = c.stop[1] = 0;
      c.t[0] = t1;
      c.t[1] = t1 + tau;
      /* fw is free: the seed's states */
      c.x = fw;
      c.v = fw + 2 * (size_t)N;
      memcpy(c.x, z1, sizeof(double) * N);
      memcpy(c.x + N, z2, sizeof(double) * N);
      memcpy(c.v, z1 + N, sizeof(double) * N);
      memcpy(c.v + N, z2 + N, sizeof(double) * N);
      if (vi_orbit_pnm_solve_stops(m, nd, 2, c.stop, c.t, c.x, c.v, N, 0.0, NULL) ||
          !(c.t[1] > c.t[0] && c.t[1] < c.t[0] + P) ||
          !(vi_dot(N, w, c.v) > 0.0 && vi_dot(N, w, c.v + N) > 0.0))
        continue;
      vi_id_orb_normalise(&c, P);
      int dup = 0;
      for (int f = 0; f < *found && f < cap && !dup; f++) dup = same_orbit(&out[f], &c, P);
      if (dup) continue;
      if (*found < cap) {
        o->n = nd;
        o->m = 2;
        o->stop[0] = o->stop[1] = 0;
        o->t[0] = c.t[0];
        o->t[1] = c.t[1];
        memcpy(o->x, c.x, sizeof(double) * 2 * N);
        memcpy(o->v, c.v, sizeof(double) * 2 * N);
        (*found)++;
      }
    }
  }
  vi_xseg_release(&sg);
  free(J);
  free(piv);
  free(L);
  return st;
}
