/* vi_constrained.c - the modes of the structure with a set of stops held
 * (MODEL.md section 9): computed once per held set, they make a sticking
 * phase a closed-form flow like free flight (section 8).
 *
 * Work in the free modal coordinates, where M = I, K = Lambda (diagonal):
 * a Householder QR of P = [psi_k] (LAPACK dgeqrf) gives Q whose last n -
 * |S| columns Z span null(P^T) orthonormally, Z^T Lambda Z is the
 * constrained stiffness (dormqr from both sides of the diagonal), its
 * eigenvectors Y (dsyevd) give Phi = Z Y (dormqr again).  Everything is
 * O(n^2 |S|) but the one eigenproblem of size n - |S|.  One held stop on
 * a large structure skips that eigenproblem: the constrained modes are
 * then the roots of a secular equation and vectors built from them
 * (cm_secular), O(n^2). */
#include <float.h>
#include <math.h>
#include <lapacke.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vi_flow_internal.h"

void vi_cmodes_destroy(vi_cmodes **cm)
{
  if (!cm || !*cm) return;
  free((*cm)->Phi);
  free(*cm);
  *cm = NULL;
}

/* Rayleigh fit d_j = a + b lambda_j of the modal damping: 1 and (a, b)
 * when it holds to round-off, else 0. */
static int rayleigh_fit(const vi_model *m, double *a, double *b)
{
  int n = m->n;
  double dmax = 0.0, lmax = 0.0;
  for (int j = 0; j < n; j++) {
    dmax = fmax(dmax, fabs(m->D[j + (size_t)j * n]));
    lmax = fmax(lmax, fabs(m->lambda[j]));
  }
  *a = *b = 0.0;
  if (dmax == 0.0) return 1;
  /* least squares in the scaled variable l / lmax */
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, r0 = 0.0, r1 = 0.0;
  for (int j = 0; j < n; j++) {
    double l = lmax > 0.0 ? m->lambda[j] / lmax : 0.0, d = m->D[j + (size_t)j * n];
    s0 += 1.0;
    s1 += l;
    s2 += l * l;
    r0 += d;
    r1 += l * d;
  }
  double det = s0 * s2 - s1 * s1;
  if (det > 1e-14 * s0 * s2) {
    *a = (s2 * r0 - s1 * r1) / det;
    *b = (s0 * r1 - s1 * r0) / det / lmax;
  } else {
    *a = r0 / s0;
  }
  for (int j = 0; j < n; j++)
    if (fabs(m->D[j + (size_t)j * n] - *a - *b * m->lambda[j]) > 1e-9 * dmax)
      return 0;
  /* a coefficient that is round-off of zero is zero (a, b >= 0 below) */
  if (fabs(*a) <= 1e-9 * dmax) *a = 0.0;
  if (fabs(*b) * lmax <= 1e-9 * dmax) *b = 0.0;
  return 1;
}

/* What depends on Omega: the particular solution pA cos + pB sin of each
 * constrained mode under its forcing amplitudes fa, fb, and the fastest
 * rate; 0 (c->why says) at an undamped resonance. */
static int particular(vi_cmodes *c, double Om)
{
  c->Om = Om;
  c->top = Om;
  for (int i = 0; i < c->m; i++) {
    c->top = fmax(c->top, fmax(sqrt(c->om2[i]), c->dmp[i]));
    if (!vi_harmonic_particular(c->om2[i], c->dmp[i], Om, c->fa[i], c->fb[i],
                                &c->pA[i], &c->pB[i])) {
      snprintf(c->why, sizeof c->why, "held mode %d is forced at its natural "
               "frequency without damping (resonance)", i + 1);
      return 0;
    }
  }
  return 1;
}

void vi_cmodes_retune(vi_cmodes *c, double Om)
{
  if (c->Om == Om || !c->built) return;
  c->why[0] = '\0';
  c->ok = particular(c, Om);
}

/* LAPACK's root of a secular equation (no LAPACKE wrapper). */
extern void dlaed4_(const int *n, const int *i, const double *d,
                    const double *z, double *delta, const double *rho,
                    double *dlam, int *info);

/* Below this many modes the dense eigen-solve costs little. */
#define CM_SECULAR_MIN 64

/* One held stop k on n >= CM_SECULAR_MIN modes.  With z = psi_k / |psi_k|,
 * the constrained modes are the limit rho -> inf of diag(lambda) + rho z
 * z^T without its one infinite eigenvalue: the roots mu_i in (lambda_i,
 * lambda_i+1) of sum_j z_j^2 / (lambda_j - mu) = 0, found by dlaed4 with
 * 1 / rho below round-off (it returns lambda_j - mu_i to full relative
 * accuracy), and the vectors y_i = zh / (lambda - mu_i), normalised, where
 * zh_j^2 = prod_i (mu_i - lambda_j) / prod_{k != j} (lambda_k - lambda_j)
 * is the vector for which the computed mu_i are exact, so that the y_i
 * are orthogonal to working precision (Gu & Eisenstat, SIAM J. Matrix
 * Anal. Appl. 15, 1994).  Phi [n x n-1] and om2 of c; z, zh [n] scratch.
 * 0, or 1 where the problem is not generic (lambda not strictly
 * increasing, a mode the stop barely sees, a root dlaed4 cannot place):
 * the caller then solves it densely. */
static int cm_secular(const vi_model *m, const double *psi, vi_cmodes *c,
                      double *z, double *zh)
{
  int n = m->n, mm = n - 1;
  const double *d = m->lambda;
  double nz = 0.0, dmax = 0.0;
  for (int j = 0; j < n; j++) {
    nz = hypot(nz, psi[j]);
    dmax = fmax(dmax, fabs(d[j]));
  }
  if (!(nz > 0.0)) return 1;
  for (int j = 0; j < n; j++) {
    z[j] = psi[j] / nz;
    if (!(fabs(z[j]) >= 1e-7)) return 1;
    if (j && !(d[j] - d[j - 1] > 1e-12 * dmax)) return 1;
  }
  /* 1 / rho far below the round-off of the secular function's terms
   * (each z_j^2 / |d_j - mu| >= 1e-14 / (d_n - d_1) with |z_j| >= 1e-7):
   * the roots are those of rho = inf to round-off */
  const double rho = 1e250 / fmax(dmax, 1.0);
  for (int i = 0; i < mm; i++) {
    int ii = i + 1, info = 0;
    dlaed4_(&n, &ii, d, z, c->Phi + (size_t)i * n, &rho, c->om2 + i, &info);
    if (info || !isfinite(c->om2[i])) return 1;
  }
  /* zh_j^2 as a product of ratios in (0, 1): root i pairs with pole i
   * below d_j and with pole i + 1 above it */
  for (int j = 0; j < n; j++) {
    double pr = 1.0;
    for (int i = 0; i < mm; i++) {
      int k = i < j ? i : i + 1;
      pr *= c->Phi[j + (size_t)i * n] / (d[j] - d[k]);
    }
    if (!(pr > 0.0) || !isfinite(pr)) return 1;
    zh[j] = copysign(sqrt(pr), z[j]);
  }
  for (int i = 0; i < mm; i++) {
    double *y = c->Phi + (size_t)i * n, s = 0.0;
    for (int j = 0; j < n; j++) {
      y[j] = zh[j] / y[j];
      s = hypot(s, y[j]);
    }
    if (!(s > 0.0) || !isfinite(s)) return 1;
    for (int j = 0; j < n; j++) y[j] /= s;
  }
  return 0;
}

/* The general case: Q of a QR of P = [psi_k] (Pw [n x cnt], tau [n]),
 * Q^T Lambda Q's trailing block (A [n x n] scratch) solved by dsyevd,
 * Phi = Q [0; Y]. */
static int cm_dense(const vi_model *m, int cnt, vi_cmodes *c, double *Pw,
                    double *tau, double *A, char *errmsg)
{
  int n = m->n, mm = n - cnt;
  lapack_int info = LAPACKE_dgeqrf(LAPACK_COL_MAJOR, n, cnt, Pw, n, tau);
  if (info)
    return vi_fail(errmsg, VI_ERR_LAPACK, "dgeqrf failed (info %d) on the "
                   "held stops' modal vectors", (int)info);
  /* A = Q^T Lambda Q */
  memset(A, 0, sizeof(double) * (size_t)n * n);
  for (int j = 0; j < n; j++) A[j + (size_t)j * n] = m->lambda[j];
  info = LAPACKE_dormqr(LAPACK_COL_MAJOR, 'L', 'T', n, n, cnt, Pw, n, tau, A, n);
  if (!info)
    info = LAPACKE_dormqr(LAPACK_COL_MAJOR, 'R', 'N', n, n, cnt, Pw, n, tau, A, n);
  if (info)
    return vi_fail(errmsg, VI_ERR_LAPACK, "dormqr failed (info %d)", (int)info);
  /* the trailing block, symmetrised, into Phi's lower rows as scratch:
   * Y (mm x mm) sits at Phi[cnt.., :] with leading dimension n */
  double *Y = c->Phi + cnt;
  for (int j = 0; j < mm; j++)
    for (int i = 0; i < mm; i++)
      Y[i + (size_t)j * n] = 0.5 * (A[cnt + i + (size_t)(cnt + j) * n] +
                                    A[cnt + j + (size_t)(cnt + i) * n]);
  if (mm <= 0) return VI_OK;
  info = LAPACKE_dsyevd(LAPACK_COL_MAJOR, 'V', 'U', mm, Y, n, c->om2);
  if (info)
    return vi_fail(errmsg, VI_ERR_LAPACK, "dsyevd failed (info %d) on the "
                   "held structure (n = %d)", (int)info, mm);
  for (int j = 0; j < mm; j++)
    for (int i = 0; i < cnt; i++) c->Phi[i + (size_t)j * n] = 0.0;
  info = LAPACKE_dormqr(LAPACK_COL_MAJOR, 'L', 'N', n, mm, cnt, Pw, n, tau,
                        c->Phi, n);
  if (info)
    return vi_fail(errmsg, VI_ERR_LAPACK, "dormqr failed (info %d)", (int)info);
  return VI_OK;
}

int vi_cmodes_create(const vi_model *m, const int *set, int cnt,
                     vi_cmodes **out, char *errmsg)
{
  int n = m->n, mm = n - cnt, ns = m->ns;
  *out = NULL;
  vi_cmodes *c = calloc(1, sizeof *c);
  size_t nw = (size_t)n * (size_t)(mm > 0 ? mm : 1) /* Phi */ +
              7 * (size_t)mm + (size_t)n + (size_t)cnt * (size_t)mm +
              (size_t)ns * (size_t)mm + (size_t)ns + 8;
  double *blk = malloc(sizeof(double) * nw);
  double *A = malloc(sizeof(double) * (size_t)n * (size_t)n);
  double *Pw = malloc(sizeof(double) * ((size_t)n * (size_t)cnt + 5 * (size_t)n + 8));
  if (!c || !blk || !A || !Pw) {
    free(c);
    free(blk);
    free(A);
    free(Pw);
    return vi_fail(errmsg, VI_ERR_NOMEM, "out of memory for the modes of "
                   "the held structure (n = %d)", n);
  }
  int st = VI_OK;
  c->Phi = blk;
  double *p = blk + (size_t)n * (size_t)(mm > 0 ? mm : 1);
  c->om2 = p; p += mm;
  c->dmp = p; p += mm;
  c->F0 = p; p += mm;
  c->pA = p; p += mm;
  c->pB = p; p += mm;
  c->fa = p; p += mm;
  c->fb = p; p += mm;
  c->qc = p; p += n;
  c->R = p; p += (size_t)cnt * mm;
  c->Pg = p; p += (size_t)ns * mm;
  c->gc = p;
  c->cnt = cnt;
  c->n = n;
  c->m = mm;
  memcpy(c->set, set, sizeof(int) * (size_t)cnt);
  double *tau = Pw + (size_t)n * cnt, *v1 = tau + n, *v2 = v1 + n, *v3 = v2 + n, *v4 = v3 + n;
  double a, b;
  if (!m->proportional || !vi_model_has_modes(m) || !m->lambda) {
    snprintf(c->why, sizeof c->why, "the held structure has no modes of "
             "its own in closed form (damping not proportional)");
    goto done;
  }
  if (!rayleigh_fit(m, &a, &b) || a < 0.0 || b < 0.0) {
    snprintf(c->why, sizeof c->why, "modal damping not of Rayleigh form "
             "(a M + b K, a, b >= 0): the held structure's modes do not "
             "decouple");
    goto done;
  }
  c->brl = b;
  /* G_SS^-1 explicitly (|S| is small) */
  double L[VI_CONTACT_MAX * VI_CONTACT_MAX], Gi[VI_CONTACT_MAX * VI_CONTACT_MAX];
  for (int i = 0; i < cnt; i++)
    for (int j = 0; j < cnt; j++)
      L[i + j * cnt] = m->G[set[i] + (size_t)set[j] * ns];
  if (vi_small_cholesky(cnt, L)) {
    snprintf(c->why, sizeof c->why, "the held stops' Delassus block is "
             "singular (dependent stop vectors)");
    goto done;
  }
  for (int j = 0; j < cnt; j++) {
    double e[VI_CONTACT_MAX] = {0.0};
    e[j] = 1.0;
    vi_small_solve(cnt, L, e);
    for (int i = 0; i < cnt; i++) Gi[i + j * cnt] = e[i];
  }
  /* q_c = P G^-1 x_S */
  {
    double y[VI_CONTACT_MAX];
    for (int i = 0; i < cnt; i++) {
      y[i] = 0.0;
      for (int j = 0; j < cnt; j++) y[i] += Gi[i + j * cnt] * m->xsv[set[j]];
    }
    for (int r = 0; r < n; r++) {
      double q = 0.0;
      for (int i = 0; i < cnt; i++) q += vi_stop_psi(m, set[i])[r] * y[i];
      c->qc[r] = q;
    }
  }
  if (cnt != 1 || n < CM_SECULAR_MIN ||
      cm_secular(m, vi_stop_psi(m, set[0]), c, Pw, tau)) {
    for (int i = 0; i < cnt; i++)
      memcpy(Pw + (size_t)i * n, vi_stop_psi(m, set[i]), sizeof(double) * n);
    if ((st = cm_dense(m, cnt, c, Pw, tau, A, errmsg))) goto done;
  }
  double Om = m->omega_f;
  for (int i = 0; i < mm; i++) {
    /* the constrained structure is semi-definite: round-off below zero */
    if (c->om2[i] < 0.0) c->om2[i] = 0.0;
    c->dmp[i] = a + b * c->om2[i];
  }
  /* forcing: Phi^T (F0 - Lambda q_c), Phi^T Fa, Phi^T Fb; with Omega = 0 the
   * cosine part is constant */
  for (int r = 0; r < n; r++) {
    v1[r] = m->F0[r] - m->lambda[r] * c->qc[r] + (Om == 0.0 ? m->Fa[r] : 0.0);
    v2[r] = Om == 0.0 ? 0.0 : m->Fa[r];
    v3[r] = Om == 0.0 ? 0.0 : m->Fb[r];
  }
  for (int i = 0; i < mm; i++) {
    const double *ph = c->Phi + (size_t)i * n;
    double f0 = vi_dot(n, ph, v1), fa = vi_dot(n, ph, v2), fb = vi_dot(n, ph, v3);
    c->F0[i] = f0;
    c->fa[i] = fa;
    c->fb[i] = fb;
  }
  /* at an undamped resonance of this Omega the rest is still built: a
   * study's next Omega may retune it */
  int tuned = particular(c, Om);
  /* reactions: R = G^-1 P^T Lambda Phi, and the forcing part */
  for (int i = 0; i < cnt; i++) {
    const double *ps = vi_stop_psi(m, set[i]);
    double x0 = 0.0, xa = 0.0, xb = 0.0, sc = 0.0;
    for (int r = 0; r < n; r++) {
      x0 += ps[r] * v1[r];
      xa += ps[r] * v2[r];
      xb += ps[r] * v3[r];
      sc += fabs(ps[r]) * (fabs(m->F0[r]) + fabs(m->Fa[r]) + fabs(m->Fb[r]) +
                           fabs(m->lambda[r] * c->qc[r]));
    }
    double *Ri = c->R + (size_t)i * mm;
    for (int r = 0; r < n; r++) v4[r] = ps[r] * m->lambda[r];
    for (int q = 0; q < mm; q++) Ri[q] = vi_dot(n, v4, c->Phi + (size_t)q * n);
    c->lc[i] = x0;
    c->lA[i] = xa;
    c->lB[i] = xb;
    c->lscale[i] = sc;
  }
  /* apply G^-1 across the held stops */
  {
    double t0[VI_CONTACT_MAX], ta[VI_CONTACT_MAX], tb[VI_CONTACT_MAX];
    double ts[VI_CONTACT_MAX];
    for (int i = 0; i < cnt; i++) {
      t0[i] = ta[i] = tb[i] = ts[i] = 0.0;
      for (int j = 0; j < cnt; j++) {
        double g = Gi[i + j * cnt];
        t0[i] += g * c->lc[j];
        ta[i] += g * c->lA[j];
        tb[i] += g * c->lB[j];
        ts[i] += fabs(g) * c->lscale[j];
      }
    }
    for (int i = 0; i < cnt; i++) {
      c->lc[i] = t0[i];
      c->lA[i] = ta[i];
      c->lB[i] = tb[i];
      c->lscale[i] = ts[i];
    }
    for (int q = 0; q < mm; q++) {
      double col[VI_CONTACT_MAX];
      for (int i = 0; i < cnt; i++) col[i] = c->R[(size_t)i * mm + q];
      for (int i = 0; i < cnt; i++) {
        double r = 0.0;
        for (int j = 0; j < cnt; j++) r += Gi[i + j * cnt] * col[j];
        c->R[(size_t)i * mm + q] = r;
      }
    }
  }
  /* every stop's gap in the constrained modes */
  for (int k = 0; k < ns; k++) {
    const double *ps = vi_stop_psi(m, k);
    for (int q = 0; q < mm; q++)
      c->Pg[(size_t)k * mm + q] = vi_dot(n, ps, c->Phi + (size_t)q * n);
    c->gc[k] = vi_dot(n, ps, c->qc) - m->xsv[k];
  }
  c->built = 1;
  c->ok = tuned;
done:
  free(A);
  free(Pw);
  if (st) {
    vi_cmodes_destroy(&c);
    return st;
  }
  *out = c;
  return VI_OK;
}
