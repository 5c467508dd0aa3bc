/* vi_general.c - the exact flow for any damping (MODEL.md section 8).
 *
 * In first-order form z = (x, v), z' = A z + b(t) with
 * A = [[0, I], [-M^-1 K, -M^-1 C]].  When A is diagonalisable, A = V L V^-1
 * (LAPACK dgeev), the complex modal coordinates y = V^-1 z obey
 * y_k' = l_k y_k + beta_k(t) and each has a closed form:
 *   y_k(t) = P_k cos(W t) + Q_k sin(W t) + R_k + e^{l_k (t - t0)} u_k.
 * This extends the exact method to non-proportional damping.  A defective
 * or ill-conditioned V (rigid-body modes, critical damping of a mode) is
 * refused: CVODE covers those. */
#define LAPACK_COMPLEX_C99
#include <complex.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <lapacke.h>

#include "vi_flow_internal.h"

typedef double complex cplx;

struct vi_general {
  int n2;
  cplx *lam, *V, *Vinv; /* eigenvalues [n2], V and V^-1 [n2 x n2] col-major */
  cplx *P, *Q, *R;      /* particular solution per complex mode [n2] */
  int ns;
  cplx *cw, *cv;        /* w_k^T V restricted to positions / velocities, per
                           stop k [n2 x ns] */
};

struct vi_gflow {
  const vi_general *g;
  double t0;
  cplx *u, *y; /* homogeneous amplitudes at t0, modal state at t [n2] */
};

void vi_general_destroy(vi_general **g)
{
  if (!g || !*g) return;
  free((*g)->lam);
  free(*g);
  *g = NULL;
}

int vi_general_create(const vi_model *m, vi_general **out, char *why)
{
  int n = m->n, n2 = 2 * n, st = VI_OK;
  *out = NULL;
  size_t nn2 = (size_t)n2 * n2;
  double *A = calloc(nn2 * 2 + 2 * (size_t)n2, sizeof(double));
  struct vi_general *g = calloc(1, sizeof *g);
  int ns = m->ns;
  cplx *mem = calloc(3 * nn2 + (5 + 2 * (size_t)ns) * n2, sizeof(cplx));
  lapack_int *ipiv = malloc(sizeof(lapack_int) * n2);
  if (!A || !g || !mem || !ipiv) {
    st = vi_fail(why, VI_ERR_NOMEM, "out of memory");
    goto cleanup;
  }
  double *VR = A + nn2, *wr = VR + nn2, *wi = wr + n2;
  g->n2 = n2;
  g->lam = mem;
  g->V = g->lam + n2;
  g->Vinv = g->V + nn2;
  cplx *LU = g->Vinv + nn2;
  g->P = LU + nn2;
  g->Q = g->P + n2;
  g->R = g->Q + n2;
  g->ns = ns;
  cplx *beta0 = g->R + n2;
  g->cw = beta0 + n2;
  g->cv = g->cw + (size_t)n2 * ns;
  for (int i = 0; i < n; i++) {
    A[i + (size_t)(n + i) * n2] = 1.0;
    for (int j = 0; j < n; j++) {
      A[(n + i) + (size_t)j * n2] = -m->MinvK[i + (size_t)j * n];
      A[(n + i) + (size_t)(n + j) * n2] = -m->MinvC[i + (size_t)j * n];
    }
  }
  lapack_int info = LAPACKE_dgeev(LAPACK_COL_MAJOR, 'N', 'V', n2, A, n2, wr, wi,
                                  NULL, 1, VR, n2);
  if (info != 0) {
    st = vi_fail(why, VI_ERR_LAPACK, "dgeev failed (info %d)", (int)info);
    goto cleanup;
  }
  for (int k = 0; k < n2; k++) {
    g->lam[k] = wr[k] + I * wi[k];
    for (int i = 0; i < n2; i++) {
      cplx v = VR[i + (size_t)k * n2];
      if (wi[k] > 0.0) v += I * VR[i + (size_t)(k + 1) * n2];      /* first of a pair */
      else if (wi[k] < 0.0) v = VR[i + (size_t)(k - 1) * n2] - I * VR[i + (size_t)k * n2];
      g->V[i + (size_t)k * n2] = v;
    }
  }
  /* V^-1 by LU; its reciprocal condition number says whether A is safely
   * diagonalisable.  A defective A (a Jordan block, such as an undamped
   * rigid-body mode) comes back from dgeev split into eigenvalues ~1e-8
   * apart with nearly parallel eigenvectors, rcond ~1e-8: round-off would
   * be amplified a hundred-million-fold, so demand rcond >= 1e-6 (lose at
   * most six digits; well-separated modes give 1e-2 or better). */
  memcpy(LU, g->V, sizeof(cplx) * nn2);
  double anorm = LAPACKE_zlange(LAPACK_COL_MAJOR, '1', n2, n2, LU, n2), rcond = 0.0;
  info = LAPACKE_zgetrf(LAPACK_COL_MAJOR, n2, n2, LU, n2, ipiv);
  if (info == 0) LAPACKE_zgecon(LAPACK_COL_MAJOR, '1', n2, LU, n2, anorm, &rcond);
  if (info != 0 || rcond < 1e-6) {
    st = vi_fail(why, VI_ERR_UNSUPPORTED,
                 "the first-order system is not safely diagonalisable "
                 "(eigenvector condition %.2g): rigid-body or critically "
                 "damped modes", rcond);
    goto cleanup;
  }
  memcpy(g->Vinv, LU, sizeof(cplx) * nn2);
  LAPACKE_zgetri(LAPACK_COL_MAJOR, n2, g->Vinv, n2, ipiv);
  /* beta = V^-1 [0; M^-1 f]: only the velocity half of V^-1's columns */
  double Om = m->omega_f;
  for (int k = 0; k < n2; k++) {
    cplx bc = 0, bs = 0, b0 = 0;
    for (int j = 0; j < n; j++) {
      cplx vij = g->Vinv[k + (size_t)(n + j) * n2];
      bc += vij * m->Minv_a[j];
      bs += vij * m->Minv_b[j];
      b0 += vij * m->Minv_f0[j];
    }
    for (int q = 0; q < ns; q++) { /* every stop's gap in these modes */
      const double *w = vi_stop_w(m, q);
      cplx cw = 0, cv = 0;
      for (int j = 0; j < n; j++) {
        cw += w[j] * g->V[j + (size_t)k * n2];
        cv += w[j] * g->V[(n + j) + (size_t)k * n2];
      }
      g->cw[k + (size_t)q * n2] = cw;
      g->cv[k + (size_t)q * n2] = cv;
    }
    cplx l = g->lam[k], den = l * l + Om * Om;
    beta0[k] = b0;
    if ((bc != 0 || bs != 0) && cabs(den) <= 1e-14 * (cabs(l * l) + Om * Om)) {
      st = vi_fail(why, VI_ERR_UNSUPPORTED,
                   "a mode is undamped and forced at resonance");
      goto cleanup;
    }
    if (b0 != 0 && cabs(l) <= 1e-14) {
      st = vi_fail(why, VI_ERR_UNSUPPORTED,
                   "a constant load on a zero eigenvalue (rigid-body drift)");
      goto cleanup;
    }
    /* y' = l y + bc cos + bs sin + b0: match cos, sin and constant terms */
    g->P[k] = (bc != 0 || bs != 0) ? -(l * bc + Om * bs) / den : 0;
    g->Q[k] = (bc != 0 || bs != 0) ? (l * g->P[k] + bc) / Om : 0;
    g->R[k] = b0 != 0 ? -b0 / l : 0;
  }
  *out = g;
  g = NULL;
  mem = NULL;
cleanup:
  free(A);
  free(g);
  free(mem);
  free(ipiv);
  return st;
}

double vi_general_top_frequency(const vi_general *g, double omega_f)
{
  double top = omega_f;
  for (int k = 0; k < g->n2; k++) top = fmax(top, fabs(cimag(g->lam[k])));
  return top;
}

double vi_gflow_live_rate(const vi_gflow *f, double t, double tol)
{
  const struct vi_general *g = f->g;
  double top = 0.0, tau = t - f->t0;
  for (int k = 0; k < g->n2; k++) {
    double a = cabs(f->u[k]) * exp(creal(g->lam[k]) * tau), w = 0.0;
    for (int q = 0; q < g->ns; q++)
      w = fmax(w, cabs(g->cw[(size_t)q * g->n2 + k]));
    if (a * w > tol) top = fmax(top, cabs(g->lam[k]));
  }
  return top;
}

double vi_general_particular_scale(const vi_general *g, int q)
{
  double sc = 0.0;
  const cplx *cw = g->cw + (size_t)q * g->n2;
  for (int k = 0; k < g->n2; k++)
    sc += cabs(cw[k]) * (cabs(g->P[k]) + cabs(g->Q[k]) + cabs(g->R[k]));
  return sc;
}

vi_gflow *vi_gflow_create(const vi_general *g)
{
  vi_gflow *f = calloc(1, sizeof *f);
  if (f) f->u = calloc(2 * (size_t)g->n2, sizeof(cplx));
  if (f && !f->u) {
    free(f);
    return NULL;
  }
  if (f) {
    f->g = g;
    f->y = f->u + g->n2;
  }
  return f;
}

void vi_gflow_free(vi_gflow *f)
{
  if (f) free(f->u);
  free(f);
}

/* Particular solution of complex mode k at t (the forcing's phase p of t):
 * complex amplitudes, so vi_harm's real form does not apply. */
static cplx particular(const struct vi_general *g, int k, const vi_phase *p)
{
  return g->P[k] * p->c + g->Q[k] * p->s + g->R[k];
}

void vi_gflow_start(vi_gflow *f, const vi_model *m, double t0, const double *z)
{
  const struct vi_general *g = f->g;
  int n = m->n, n2 = g->n2;
  vi_phase p = vi_phase_at(m->omega_f, t0);
  f->t0 = t0;
  for (int k = 0; k < n2; k++) {
    cplx y = 0;
    for (int i = 0; i < n; i++)
      y += g->Vinv[k + (size_t)i * n2] * z[2 * (size_t)i] +
           g->Vinv[k + (size_t)(n + i) * n2] * z[2 * (size_t)i + 1];
    f->u[k] = y - particular(g, k, &p);
  }
}

void vi_gflow_eval(vi_gflow *f, const vi_model *m, double t, int q,
                   double *gap, double *rate, double *z)
{
  const struct vi_general *g = f->g;
  int n = m->n, n2 = g->n2;
  double tau = t - f->t0;
  vi_phase p = vi_phase_at(m->omega_f, t);
  for (int k = 0; k < n2; k++)
    f->y[k] = particular(g, k, &p) + cexp(g->lam[k] * tau) * f->u[k];
  int q0 = q < 0 ? 0 : q, q1 = q < 0 ? g->ns : q + 1;
  for (int j = q0; gap && j < q1; j++) {
    const cplx *cw = g->cw + (size_t)j * n2, *cv = g->cv + (size_t)j * n2;
    cplx a = 0, b = 0;
    for (int k = 0; k < n2; k++) {
      a += cw[k] * f->y[k];
      b += cv[k] * f->y[k];
    }
    gap[j - q0] = creal(a) - m->xsv[j];
    rate[j - q0] = creal(b);
  }
  if (!z) return;
  for (int i = 0; i < n; i++) {
    cplx x = 0, v = 0;
    for (int k = 0; k < n2; k++) {
      x += g->V[i + (size_t)k * n2] * f->y[k];
      v += g->V[(n + i) + (size_t)k * n2] * f->y[k];
    }
    z[2 * (size_t)i] = creal(x);
    z[2 * (size_t)i + 1] = creal(v);
  }
}
