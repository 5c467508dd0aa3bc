/* vi_orbit_var.c - the variational flow of a periodic impacting orbit:
 * the state-transition matrix between impacts in closed form and the
 * saltation matrix at each impact (vi_orbit_internal.h).
 *
 * Between impacts z = (x, v) obeys z' = A z + b(t) with
 * A = [[0, I], [-M^-1 K, -M^-1 C]], so D_z0 z(t) = e^{A tau}, tau = t - t0,
 * whatever the forcing: no integration and no differences.
 *  - Proportional damping: per mode the 2 x 2 homogeneous flow of
 *    u'' + d u' + lambda u = 0 in closed form (vi_flow_homogeneous), mapped
 *    to physical coordinates by x = Psi q, q = Psi^T M x.
 *  - Any other damping (and defective A, which the closed-form flow of
 *    vi_general.c refuses): e^{A tau} by scaling and squaring with the
 *    degree-13 Pade approximant (Higham, SIAM J. Matrix Anal. Appl. 26
 *    (2005) 1179), accurate to a few ulps of ||e^{A tau}||.
 * Both need only M, C, K: the exact derivative exists for every linear
 * model, also where the trajectory itself comes from CVODE. */
#define LAPACK_COMPLEX_C99
#include <complex.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cblas.h>
#include <lapacke.h>

#include "vi_impact_internal.h"
#include "vi_orbit_internal.h"

/* C = A B, all n x n column-major */
static void mul(int n, const double *A, const double *B, double *C)
{
  cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n, n, n, 1.0, A, n,
              B, n, 0.0, C, n);
}

static int stm_modal(const vi_model *m, double tau, double *Phi)
{
  int n = m->n, n2 = 2 * n;
  /* c: per mode the 2 x 2 flow, as four diagonals; W: Psi diag(c_ab) */
  double small[4 * VI_FLOW_SMALL + VI_FLOW_SMALL * VI_FLOW_SMALL];
  double *c = n <= VI_FLOW_SMALL ? small
                                 : malloc(sizeof(double) * (4 + (size_t)n) * n);
  if (!c) return VI_ERR_NOMEM;
  double *W = c + 4 * (size_t)n;
  for (int j = 0; j < n; j++) {
    double f[4];
    vi_flow_stm2(m->lambda[j], m->D[j + (size_t)j * n], tau, f);
    for (int bl = 0; bl < 4; bl++) c[(size_t)bl * n + j] = f[bl];
  }
  /* block (row a, column b) of Phi = Psi diag(c_ab) Psi^T M; the diagonals
   * are stored (aa, ba, ab, bb) as the 2 x 2 flows' columns */
  for (int bl = 0; bl < 4; bl++) {
    const double *dg = c + (size_t)bl * n;
    int ro = (bl & 1) ? n : 0, co = (bl & 2) ? n : 0;
    for (int j = 0; j < n; j++)
      for (int i = 0; i < n; i++)
        W[i + (size_t)j * n] = m->Psi[i + (size_t)j * n] * dg[j];
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n, n, n, 1.0, W, n,
                m->PsiTM, n, 0.0, Phi + ro + (size_t)co * n2, n2);
  }
  if (c != small) free(c);
  return VI_OK;
}

/* e^{A tau} by scaling and squaring, Pade degree 13 */
static int stm_pade(const vi_model *m, double tau, double *Phi)
{
  static const double b[14] = {
      64764752532480000.0, 32382376266240000.0, 7771770303897600.0,
      1187353796428800.0,  129060195264000.0,   10559470521600.0,
      670442572800.0,      33522128640.0,       1323241920.0,
      40840800.0,          960960.0,            16380.0,
      182.0,               1.0};
  const double theta13 = 5.371920351148152;
  int n = m->n, n2 = 2 * n;
  size_t nn = (size_t)n2 * n2;
  double *A = calloc(7 * nn, sizeof(double));
  lapack_int *piv = malloc(sizeof(lapack_int) * (size_t)n2);
  if (!A || !piv) {
    free(A);
    free(piv);
    return VI_ERR_NOMEM;
  }
  double *A2 = A + nn, *A4 = A2 + nn, *A6 = A4 + nn, *U = A6 + nn, *V = U + nn,
         *W = V + nn;
  for (int i = 0; i < n; i++) {
    A[i + (size_t)(n + i) * n2] = tau;
    for (int j = 0; j < n; j++) {
      A[(n + i) + (size_t)j * n2] = -tau * m->MinvK[i + (size_t)j * n];
      A[(n + i) + (size_t)(n + j) * n2] = -tau * m->MinvC[i + (size_t)j * n];
    }
  }
  double nrm = 0.0; /* 1-norm */
  for (int j = 0; j < n2; j++) {
    double s = 0.0;
    for (int i = 0; i < n2; i++) s += fabs(A[i + (size_t)j * n2]);
    nrm = fmax(nrm, s);
  }
  int sq = nrm > theta13 ? (int)ceil(log2(nrm / theta13)) : 0;
  if (sq > 0) {
    double sc = ldexp(1.0, -sq);
    for (size_t i = 0; i < nn; i++) A[i] *= sc;
  }
  mul(n2, A, A, A2);
  mul(n2, A2, A2, A4);
  mul(n2, A4, A2, A6);
  /* U = A (A6 (b13 A6 + b11 A4 + b9 A2) + b7 A6 + b5 A4 + b3 A2 + b1 I)
   * V = A6 (b12 A6 + b10 A4 + b8 A2) + b6 A6 + b4 A4 + b2 A2 + b0 I */
  for (size_t i = 0; i < nn; i++) W[i] = b[13] * A6[i] + b[11] * A4[i] + b[9] * A2[i];
  mul(n2, A6, W, Phi);
  for (size_t i = 0; i < nn; i++)
    Phi[i] += b[7] * A6[i] + b[5] * A4[i] + b[3] * A2[i];
  for (int i = 0; i < n2; i++) Phi[i + (size_t)i * n2] += b[1];
  mul(n2, A, Phi, U);
  for (size_t i = 0; i < nn; i++) W[i] = b[12] * A6[i] + b[10] * A4[i] + b[8] * A2[i];
  mul(n2, A6, W, V);
  for (size_t i = 0; i < nn; i++) V[i] += b[6] * A6[i] + b[4] * A4[i] + b[2] * A2[i];
  for (int i = 0; i < n2; i++) V[i + (size_t)i * n2] += b[0];
  /* (V - U) R = V + U */
  for (size_t i = 0; i < nn; i++) {
    W[i] = V[i] - U[i];
    Phi[i] = V[i] + U[i];
  }
  int st = LAPACKE_dgesv(LAPACK_COL_MAJOR, n2, n2, W, n2, piv, Phi, n2) != 0
               ? VI_ERR_LAPACK : VI_OK;
  for (int k = 0; k < sq && !st; k++) {
    mul(n2, Phi, Phi, W);
    memcpy(Phi, W, sizeof(double) * nn);
  }
  free(piv);
  free(A);
  return st;
}

int vi_var_stm(const vi_model *m, double tau, double *Phi)
{
  if (!(tau >= 0.0) || !isfinite(tau)) return VI_ERR_TIME;
  return m->proportional ? stm_modal(m, tau, Phi) : stm_pade(m, tau, Phi);
}

int vi_var_stm_apply(const vi_model *m, double tau, double *u, double *work)
{
  if (!(tau >= 0.0) || !isfinite(tau)) return VI_ERR_TIME;
  if (!m->proportional) return VI_ERR_UNSUPPORTED;
  int n = m->n;
  /* [q qd] = Psi^T M [x v], the 2 x 2 flow of each mode, [x v] = Psi [q qd] */
  cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n, 2, n, 1.0,
              m->PsiTM, n, u, n, 0.0, work, n);
  for (int j = 0; j < n; j++)
    vi_flow_homogeneous(m->lambda[j], m->D[j + (size_t)j * n], work[j],
                        work[n + j], tau, &work[j], &work[n + j]);
  cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n, 2, n, 1.0,
              m->Psi, n, work, n, 0.0, u, n);
  return VI_OK;
}

void vi_var_field(const vi_model *m, double t, const double *z, double *f)
{
  int n = m->n;
  vi_phase p = vi_phase_at(m->omega_f, t);
  memcpy(f, z + n, sizeof(double) * n);
  /* M^-1 (f(t) - K x - C v): the quantity the model's kernel computes
   * (dense_accel_k, vi_dense_model.c), but summed in BLAS's order, which
   * the Floquet multipliers, curves and identifications were computed in:
   * the kernel's band loop moves them by up to 1.6e-14 relative (Fig. 2's
   * multipliers by 3e-15, its pd curve's points by 1.6e-14; measured for
   * issue 29), so the two become one where outputs may move. */
  for (int i = 0; i < n; i++)
    f[n + i] = vi_harm(&p, 0, m->Minv_a[i], m->Minv_b[i], m->Minv_f0[i]);
  cblas_dgemv(CblasColMajor, CblasNoTrans, n, n, -1.0, m->MinvK, n, z, 1,
              1.0, f + n, 1);
  cblas_dgemv(CblasColMajor, CblasNoTrans, n, n, -1.0, m->MinvC, n, z + n, 1,
              1.0, f + n, 1);
}

/* the impact map of stop k on an approaching state: Newton's law on the
 * one contact, v+ = Q_k v- (vi_impact_internal.h) */
void vi_var_impact(const vi_model *m, int k, const double *z, double *zp)
{
  int n = m->n;
  double work;
  memmove(zp, z, sizeof(double) * n);
  memmove(zp + n, z + n, sizeof(double) * n);
  vi_impact_q_left(m, k, 1, zp + n, n, &work);
}

/* Saltation matrix of an impact on stop k (gap h(z) = g.z - x_k,
 * g = (w_k, 0)) reached at t* in the state z- = z (before), z+ = R z- after,
 * where R = diag(I, Q_k), Q_k = I - (1 + r_k) M^-1 w_k w_k^T / (w_k^T M^-1 w_k)
 * is the (linear) Jacobian of the impact law (WB 2).
 *
 * Start the flow from z0 + dz.  It reaches the stop at t* + dt with
 *   g.(dz(t*) + f- dt) = 0,  so  dt = -g.dz / g.f-,   g.f- = w_k.v- = v_n,
 * (dz(t*) = Phi dz0, first order).  Just after, at t* + dt, the state is
 * R (z- + dz + f- dt); the unperturbed one at that time is z+ + f+ dt.  The
 * difference is the perturbation carried past the impact:
 *   dz+ = R dz + (R f- - f+) dt = [R + (f+ - R f-) g^T / (g.f-)] dz = S dz
 * with f-+ the vector field before and after the impact at t*.  S has the
 * factor 1 / v_n: the square-root singularity of grazing (v_n -> 0).
 * vi_var_salt_jump gives d = f+ - R f- [2n] and v_n; work [4n]. */
double vi_var_salt_jump(const vi_model *m, int k, double t, const double *z,
                        double *d, double *work)
{
  int n = m->n, n2 = 2 * n;
  double *zp = work, *fp = zp + n2, one;
  vi_var_impact(m, k, z, zp);
  vi_var_field(m, t, z, d);
  vi_var_field(m, t, zp, fp);
  vi_impact_salt_jump(m, k, d, fp, d, &one);
  return vi_dot(n, vi_stop_w(m, k), z + n);
}

void vi_var_saltation(const vi_model *m, int k, double t, const double *z,
                      double *S, double *work)
{
  double *d = work + 4 * (size_t)m->n;
  double vn = vi_var_salt_jump(m, k, t, z, d, work);
  vi_impact_salt_matrix(m, k, vn, d, S);
}

/* D z(tb) / D z(ta) of the motion from ta to tb through mi impacts at
 * t [mi] on the stops stop [mi] with pre-impact states z [2n x mi]:
 * Phi(tb - t_last) S_last ... S_0 Phi(t_0 - ta). */
int vi_var_map_jacobian(const vi_model *m, double ta, double tb, int mi,
                        const int *stop, const double *t, const double *z,
                        double *J)
{
  int n2 = 2 * m->n, st = VI_OK;
  size_t nn = (size_t)n2 * n2;
  double *P = malloc(sizeof(double) * (3 * nn + 4 * (size_t)n2));
  if (!P) return VI_ERR_NOMEM;
  double *S = P + nn, *W = S + nn, *work = W + nn;
  if ((st = vi_var_stm(m, (mi ? t[0] : tb) - ta, J))) goto cleanup;
  for (int j = 0; j < mi; j++) {
    double t1 = j + 1 < mi ? t[j + 1] : tb;
    vi_var_saltation(m, stop[j], t[j], z + (size_t)j * n2, S, work);
    mul(n2, S, J, W);
    if ((st = vi_var_stm(m, t1 - t[j], P))) goto cleanup;
    mul(n2, P, W, J);
  }
cleanup:
  free(P);
  return st;
}

/* The harmonic particular solution x_p = Re(X e^{i Omega t}) solves
 * H X = a - i b with H = K - Omega^2 M + i Omega C, so
 *   dX/dOmega = -H^-1 (-2 Omega M + i C) X,
 *   dx_p/dOmega = Re((X' + i t X) e^{i Omega t}),
 *   dv_p/dOmega = Re((i X + i Omega X' - Omega t X) e^{i Omega t});
 * the static response to f0 does not depend on Omega. */
int vi_var_dpart_domega(const vi_model *m, int nt, const double *t, double *dz)
{
  int n = m->n, st = VI_OK;
  double Om = m->omega_f;
  size_t nn = (size_t)n * n;
  double complex *H = malloc(sizeof(double complex) * (nn + 2 * (size_t)n));
  lapack_int *piv = malloc(sizeof(lapack_int) * (size_t)n);
  if (!H || !piv) {
    st = VI_ERR_NOMEM;
    goto cleanup;
  }
  double complex *X = H + nn, *dX = X + n;
  for (size_t i = 0; i < nn; i++) H[i] = m->K[i] - Om * Om * m->M[i] + I * Om * m->C[i];
  for (int i = 0; i < n; i++) X[i] = m->a[i] - I * m->b[i];
  if (LAPACKE_zgesv(LAPACK_COL_MAJOR, n, 1, H, n, piv, X, n) != 0) {
    st = VI_ERR_UNSUPPORTED; /* undamped resonance: no harmonic solution */
    goto cleanup;
  }
  for (int i = 0; i < n; i++) {
    double complex s = 0;
    for (int k = 0; k < n; k++)
      s -= (-2.0 * Om * m->M[i + (size_t)k * n] + I * m->C[i + (size_t)k * n]) * X[k];
    dX[i] = s;
  }
  /* H is factored in place: solve with the factors */
  if (LAPACKE_zgetrs(LAPACK_COL_MAJOR, 'N', n, 1, H, n, piv, dX, n) != 0) {
    st = VI_ERR_LAPACK;
    goto cleanup;
  }
  for (int j = 0; j < nt; j++) {
    double complex e = cexp(I * Om * t[j]);
    double *d = dz + (size_t)j * 2 * n;
    for (int i = 0; i < n; i++) {
      d[i] = creal((dX[i] + I * t[j] * X[i]) * e);
      d[n + i] = creal((I * X[i] + I * Om * dX[i] - Om * t[j] * X[i]) * e);
    }
  }
cleanup:
  free(piv);
  free(H);
  return st;
}
