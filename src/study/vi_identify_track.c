/* vi_identify_track.c - the orbit at many times (the recording's samples,
 * the residuals' and the Jacobian's): the flight from each impact's
 * post-impact state is started once per orbit (vi_xseg), and a block of
 * samples is evaluated in modal coordinates and mapped to physical ones by
 * one product with Psi.  Per sample that leaves the forcing's phase and
 * each mode's propagator: when every sample redid the start (the impact
 * law, two products with Psi^T M, the phase at the impact) and mapped
 * itself back with two matrix-vector products, that was 54 % of
 * test_identify's time (Release, reference BLAS). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>

#include "vi_identify_internal.h"

void vi_id_locate(const orb *o, double P, double s, int *j, double *tau,
                  double *k)
{
  double ph = s - o->t[0], kk = floor(ph / P);
  ph -= kk * P;
  if (ph >= P) {
    ph -= P;
    kk += 1.0;
  }
  if (ph < 0.0) ph = 0.0;
  int jj = o->m - 1;
  while (jj > 0 && o->t[jj] - o->t[0] > ph) jj--;
  *j = jj;
  *tau = ph - (o->t[jj] - o->t[0]);
  *k = kk;
}

int vi_id_track_init(vi_id_track *tk, const vi_model *m, const vi_xflow *xf,
                     const orb *o)
{
  int N = m->n, N2 = 2 * N;
  memset(tk, 0, sizeof *tk);
  tk->m = m;
  tk->o = o;
  tk->N = N;
  tk->P = vi_id_period_of(m, o->n);
  tk->halves = 3;
  /* per impact: the flight's start [3N] and post-impact state [2N]; the
   * block's modal and physical states [2N x VI_ID_BLOCK], work [2N] and
   * accelerations [N x VI_ID_BLOCK] */
  size_t seg = 5 * (size_t)N * o->m, blk = (size_t)N2 * VI_ID_BLOCK;
  tk->mem = malloc(sizeof(double) * (seg + 2 * blk + N2 + (size_t)N * VI_ID_BLOCK));
  if (!tk->mem) return VI_ERR_NOMEM;
  tk->zp = tk->mem + 3 * (size_t)N * o->m;
  tk->Q = tk->mem + seg;
  tk->Z = tk->Q + blk;
  tk->work = tk->Z + blk;
  tk->A = tk->work + N2;
  for (int j = 0; j < o->m; j++) {
    double *zp = tk->zp + (size_t)j * N2;
    int st = vi_xseg_init(&tk->seg[j], xf, m, tk->mem + 3 * (size_t)N * j);
    if (st) {
      vi_id_track_free(tk);
      return st;
    }
    tk->nseg = j + 1;
    memcpy(zp, o->x + (size_t)j * N, sizeof(double) * N);
    memcpy(zp + N, o->v + (size_t)j * N, sizeof(double) * N);
    vi_var_impact(m, o->stop[j], zp, zp);
    vi_xseg_start(&tk->seg[j], o->t[j], zp, zp + N);
  }
  return VI_OK;
}

void vi_id_track_free(vi_id_track *tk)
{
  for (int j = 0; j < tk->nseg; j++) vi_xseg_release(&tk->seg[j]);
  free(tk->mem);
  tk->mem = NULL;
  tk->nseg = 0;
}

/* How many of the k samples from the first lie in its flight at a steady
 * step (*h): a recording's, whose times are uniform to their round-off
 * (at most VI_XSEG_RUN, at least 1).  A time off the step by more than a
 * few ulp of the flight's start ends the run. */
static int uniform_run(int k, const int *j, const double *tau, double t0,
                       double *h)
{
  int r = 1;
  *h = 0.0;
  if (k < 2 || j[1] != j[0]) return 1;
  *h = tau[1] - tau[0];
  double tol = 16.0 * DBL_EPSILON * (fabs(t0) + fabs(tau[0]) + VI_XSEG_RUN * fabs(*h));
  while (r < k && r < VI_XSEG_RUN && j[r] == j[0] &&
         fabs(tau[r] - (tau[0] + r * *h)) <= tol)
    r++;
  return r;
}

void vi_id_track_at(vi_id_track *tk, int k, const int *j, const double *tau,
                    double *Z, double *C)
{
  int N = tk->N, N2 = 2 * N;
  const orb *o = tk->o;
  if (tk->seg[0].g) { /* other damping: the first-order flow's own map */
    for (int i = 0; i < k; i++) {
      double *z = Z + (size_t)i * N2;
      vi_xseg_physical(&tk->seg[j[i]], o->t[j[i]] + tau[i], z, z + N, tk->Q);
    }
    return;
  }
  int hx = tk->halves & 1, hv = tk->halves & 2;
  for (int i = 0, r; i < k; i += r) {
    double *q = tk->Q + (size_t)i * N2, h;
    r = uniform_run(k - i, j + i, tau + i, o->t[j[i]], &h);
    vi_xseg_modal_run(&tk->seg[j[i]], o->t[j[i]] + tau[i], h, r, hx ? q : NULL,
                      hv ? q + N : NULL, (size_t)N2, C ? C + 4 * (size_t)N * i : NULL);
  }
  /* x = Psi q, v = Psi q' for the whole block */
  if (hx)
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, N, k, N, 1.0,
                tk->m->Psi, N, tk->Q, N2, 0.0, Z, N2);
  if (hv)
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, N, k, N, 1.0,
                tk->m->Psi, N, tk->Q + N, N2, 0.0, Z + N, N2);
}

void vi_id_track_states(vi_id_track *tk, int k, const double *s, int *j,
                        double *tau, double *kper, double *Z, double *C)
{
  for (int i = 0; i < k; i++) {
    double kk;
    vi_id_locate(tk->o, tk->P, s[i], &j[i], &tau[i], &kk);
    if (kper) kper[i] = kk;
  }
  vi_id_track_at(tk, k, j, tau, Z, C);
}

int vi_id_halves(int order) { return order == 0 ? 1 : order == 1 ? 2 : 3; }

void vi_id_accel_block(const vi_model *m, int k, int rep, const double *t,
                       const double *Z, double *F)
{
  int N = m->n, N2 = 2 * N;
  /* vi_var_field's velocity half, M^-1 (f(t) - K x - C v), column by
   * column in the same order of summation; the forcing once per time */
  for (int i = 0; i < k; i++) {
    double *f = F + (size_t)i * rep * N;
    vi_phase p = vi_phase_at(m->omega_f, t[i]);
    for (int r = 0; r < N; r++)
      f[r] = vi_harm(&p, 0, m->Minv_a[r], m->Minv_b[r], m->Minv_f0[r]);
    for (int c = 1; c < rep; c++) memcpy(f + (size_t)c * N, f, sizeof(double) * N);
  }
  int nc = k * rep;
  cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, N, nc, N, -1.0,
              m->MinvK, N, Z, N2, 1.0, F, N);
  cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, N, nc, N, -1.0,
              m->MinvC, N, Z + N, N2, 1.0, F, N);
}
