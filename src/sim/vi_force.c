/* vi_force.c - nonlinear forces g(t, x, x') beyond M, C, K: the host's
 * callback and the built-in springs (vi_force.h).  They enter the
 * acceleration as M^-1 g = Psi Psi^T g (mass-normalised modes: Psi^T M Psi
 * = I, so M^-1 = Psi Psi^T), which needs no factorisation of M. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cblas.h>

#include "vi_force_internal.h"

/* From this many coordinates on, BLAS dgemv/dgemm beat the hand-written
 * loops (measured: 0.2x at n = 2, 1x at n = 8, 2.5x at 16, 6x at 200). */
#define VI_FORCE_BLAS_N 8

struct vi_spring {
  int type, i, j; /* 0-based coordinates; j = -1 is the ground */
  double k, gap;
};

static int exact_in_use(const vi_sim *s) { return s->method == VI_METHOD_EXACT; }

/* Scratch for the force evaluation: x, v, g, Psi^T g [n] each. */
static int ensure_buffers(vi_sim *s)
{
  if (s->fbuf) return VI_OK;
  s->fbuf = malloc(sizeof(double) * 4 * (size_t)s->n);
  return s->fbuf ? VI_OK : vi_fail(s->errmsg, VI_ERR_NOMEM, "out of memory");
}

static void count_forces(vi_sim *s)
{
  s->nforces = s->nsprings + (s->force_fn != NULL);
  /* the integrator is rebuilt: the closed form no longer applies, and BDF
   * needs a dense Jacobian */
  if (s->be_data) s->be->destroy(s);
  s->started = 0;
}

int vi_sim_set_force(vi_sim *s, vi_force_fn fn, vi_force_jac_fn jac,
                     void *user, vi_destroy_fn destroy)
{
  if (!s) return VI_ERR_ARG;
  VI_SIM_IDLE(s);
  int st; /* M^-1 g = Psi Psi^T g needs the modes */
  if (fn && (st = vi_model_need_modes(s->m, s->errmsg, "forces need")))
    return st;
  if (fn && exact_in_use(s))
    return vi_fail(s->errmsg, VI_ERR_UNSUPPORTED, "the exact method has no "
                   "closed form for a host force: choose adams, bdf, erk or "
                   "auto first");
  if (!fn && jac)
    return vi_fail(s->errmsg, VI_ERR_ARG, "a force Jacobian without a force");
  st = fn ? ensure_buffers(s) : VI_OK;
  if (st) return st;
  s->force_fn = fn;
  s->force_jac = fn ? jac : NULL;
  vi_user_set(&s->force_user, &s->force_free, fn ? user : NULL,
              fn ? destroy : NULL);
  count_forces(s);
  return VI_OK;
}

int vi_sim_add_spring(vi_sim *s, int type, int i, int j, double k, double gap)
{
  if (!s) return VI_ERR_ARG;
  VI_SIM_IDLE(s);
  int st; /* M^-1 g = Psi Psi^T g needs the modes */
  if ((st = vi_model_need_modes(s->m, s->errmsg, "forces need"))) return st;
  if (type != VI_SPRING_CUBIC && type != VI_SPRING_BILINEAR)
    return vi_fail(s->errmsg, VI_ERR_ARG, "unknown spring type %d", type);
  if (i < 1 || i > s->n || j < 0 || j > s->n || i == j)
    return vi_fail(s->errmsg, VI_ERR_DIM, "spring between coordinates %d and "
                   "%d: need 1 <= i <= %d, 0 <= j <= %d (0 = ground), i != j",
                   i, j, s->n, s->n);
  if (!isfinite(k) || (type == VI_SPRING_BILINEAR && !isfinite(gap)))
    return vi_fail(s->errmsg, VI_ERR_NONFINITE, "spring k = %g, gap = %g",
                   k, gap);
  if (exact_in_use(s))
    return vi_fail(s->errmsg, VI_ERR_UNSUPPORTED, "the exact method has no "
                   "closed form for a nonlinear spring: choose adams, bdf, "
                   "erk or auto first");
  st = ensure_buffers(s);
  if (st) return st;
  struct vi_spring *sp =
      realloc(s->springs, sizeof *sp * ((size_t)s->nsprings + 1));
  if (!sp) return vi_fail(s->errmsg, VI_ERR_NOMEM, "out of memory");
  s->springs = sp;
  sp[s->nsprings++] = (struct vi_spring){type, i - 1, j - 1, k, gap};
  count_forces(s);
  return VI_OK;
}

int vi_sim_clear_springs(vi_sim *s)
{
  if (!s) return VI_ERR_ARG;
  VI_SIM_IDLE(s);
  free(s->springs);
  s->springs = NULL;
  s->nsprings = 0;
  count_forces(s);
  return VI_OK;
}

void vi_force_free(vi_sim *s)
{
  free(s->springs);
  free(s->fbuf);
  free(s->fjac);
  s->springs = NULL;
  s->fbuf = NULL;
  s->fjac = NULL;
}

/* Force of spring sp at relative displacement d (> 0: i beyond j) and its
 * derivative. */
static double spring_force(const struct vi_spring *sp, double d, double *dfd)
{
  if (sp->type == VI_SPRING_CUBIC) {
    *dfd = -3.0 * sp->k * d * d;
    return -sp->k * d * d * d;
  }
  if (d > sp->gap) {
    *dfd = -sp->k;
    return -sp->k * (d - sp->gap);
  }
  *dfd = 0.0;
  return 0.0;
}

/* g(t, x, v) [n] of an interleaved state into s->fbuf + 2n; 0 on success. */
static int force_eval(vi_sim *s, double t, const double *z, double *g)
{
  int n = s->n;
  double *x = s->fbuf, *v = x + n;
  for (int i = 0; i < n; i++) {
    x[i] = z[2 * (size_t)i];
    v[i] = z[2 * (size_t)i + 1];
    g[i] = 0.0;
  }
  for (int k = 0; k < s->nsprings; k++) {
    const struct vi_spring *sp = &s->springs[k];
    double d = x[sp->i] - (sp->j >= 0 ? x[sp->j] : 0.0), dfd;
    double f = spring_force(sp, d, &dfd);
    g[sp->i] += f;
    if (sp->j >= 0) g[sp->j] -= f;
  }
  if (s->force_fn) {
    double *h = v + 2 * (size_t)n; /* Psi^T g slot, free until projected */
    memset(h, 0, sizeof(double) * (size_t)n);
    if (s->force_fn(t, n, x, v, h, s->force_user) != 0) {
      if (!s->force_failed) s->force_fail_t = t;
      s->force_failed = 1;
      return -1;
    }
    for (int i = 0; i < n; i++) g[i] += h[i];
  }
  /* a NaN or inf force (the host's with status 0, or a spring's overflow)
   * would leave the integrator retrying ever smaller steps at one t: the
   * run fails instead, naming the coordinate */
  for (int i = 0; i < n; i++)
    if (!isfinite(g[i])) {
      if (!s->force_failed) {
        s->force_fail_t = t;
        s->force_fail_i = i;
        s->force_fail_g = g[i];
      }
      s->force_failed = 2;
      return -1;
    }
  return 0;
}

int vi_force_failure(vi_sim *s)
{
  if (s->force_failed == 2)
    return vi_fail(s->errmsg, VI_ERR_CALLBACK, "the nonlinear force is not "
                   "finite at t = %.17g: g(%d) = %g (%s)", s->force_fail_t,
                   s->force_fail_i + 1, s->force_fail_g,
                   s->force_fn ? "the host's force callback or a spring"
                               : "a spring: the motion has diverged");
  return vi_fail(s->errmsg, VI_ERR_CALLBACK, "the host's force callback "
                 "failed at t = %.17g", s->force_fail_t);
}

void vi_force_add_accel(vi_sim *s, double t, const double *z, double *acc)
{
  int n = s->n;
  double *g = s->fbuf + 2 * (size_t)n, *gq = g + n;
  if (force_eval(s, t, z, g)) return; /* the backend stops the run */
  const vi_model *m = s->m;
  if (n >= VI_FORCE_BLAS_N) { /* acc += Psi (Psi^T g) */
    cblas_dgemv(CblasColMajor, CblasTrans, n, n, 1.0, m->Psi, n, g, 1, 0.0,
                gq, 1);
    cblas_dgemv(CblasColMajor, CblasNoTrans, n, n, 1.0, m->Psi, n, gq, 1, 1.0,
                acc, 1);
    return;
  }
  vi_matvec_t(n, m->Psi, g, gq); /* Psi^T g */
  for (int j = 0; j < n; j++) {
    const double *col = m->Psi + (size_t)j * (size_t)n;
    for (int i = 0; i < n; i++) acc[i] += col[i] * gq[j];
  }
}

void vi_force_modal(vi_sim *s, double t, const double *z, double *gq)
{
  double *g = s->fbuf + 2 * (size_t)s->n;
  if (force_eval(s, t, z, g)) {
    memset(gq, 0, sizeof(double) * (size_t)s->n);
    return;
  }
  if (s->n >= VI_FORCE_BLAS_N)
    cblas_dgemv(CblasColMajor, CblasTrans, s->n, s->n, 1.0, s->m->Psi, s->n,
                g, 1, 0.0, gq, 1);
  else
    vi_matvec_t(s->n, s->m->Psi, g, gq);
}

/* Ax = M^-1 dg/dx, Av = M^-1 dg/dv at (t, z): the springs analytically,
 * the host force by its Jacobian or by forward differences. */
int vi_force_jacobian(vi_sim *s, double t, const double *z, double **pAx,
                      double **pAv)
{
  int n = s->n;
  size_t nn = (size_t)n * (size_t)n;
  /* one workspace per sim, made at the first Jacobian: outputs Ax, Av and
   * the force's own Gx, Gv [n x n each], then g0, g1 [n], zz [2n] */
  if (!s->fjac && !(s->fjac = malloc(sizeof(double) * (4 * nn + 4 * (size_t)n))))
    return vi_fail(s->errmsg, VI_ERR_NOMEM, "out of memory");
  double *Ax = s->fjac, *Av = Ax + nn, *Gx = Av + nn, *Gv = Gx + nn;
  double *g0 = Gv + nn, *g1 = g0 + n, *zz = g1 + n;
  memset(Gx, 0, sizeof(double) * 2 * nn);
  *pAx = Ax;
  *pAv = Av;
  for (int k = 0; k < s->nsprings; k++) {
    const struct vi_spring *sp = &s->springs[k];
    double d = z[2 * (size_t)sp->i] - (sp->j >= 0 ? z[2 * (size_t)sp->j] : 0.0), dfd;
    spring_force(sp, d, &dfd);
    Gx[sp->i + (size_t)sp->i * n] += dfd;
    if (sp->j >= 0) {
      Gx[sp->i + (size_t)sp->j * n] -= dfd;
      Gx[sp->j + (size_t)sp->i * n] -= dfd;
      Gx[sp->j + (size_t)sp->j * n] += dfd;
    }
  }
  int st = VI_OK;
  if (s->force_fn) {
    double *Hx = Ax, *Hv = Av; /* outputs as scratch until the projection */
    memset(Hx, 0, sizeof(double) * nn);
    memset(Hv, 0, sizeof(double) * nn);
    const double *x = s->fbuf, *v = x + n;
    if (s->force_jac) {
      for (int i = 0; i < n; i++) {
        s->fbuf[i] = z[2 * (size_t)i];
        s->fbuf[n + i] = z[2 * (size_t)i + 1];
      }
      if (s->force_jac(t, n, x, v, Hx, Hv, n, s->force_user) != 0) {
        s->force_failed = 1;
        s->force_fail_t = t;
        st = VI_ERR_CALLBACK;
      }
    } else {
      /* forward differences of the whole force, springs included: the
       * springs' part is subtracted again below */
      memcpy(zz, z, sizeof(double) * 2 * (size_t)n);
      if (force_eval(s, t, zz, g0)) st = VI_ERR_CALLBACK;
      for (int c = 0; c < 2 * n && !st; c++) {
        double h = 1.5e-8 * fmax(1.0, fabs(zz[c])), keep = zz[c];
        zz[c] = keep + h;
        if (force_eval(s, t, zz, g1)) st = VI_ERR_CALLBACK;
        zz[c] = keep;
        double *col = (c % 2 ? Hv : Hx) + (size_t)(c / 2) * n;
        for (int i = 0; i < n; i++) col[i] = (g1[i] - g0[i]) / h;
      }
      for (size_t k = 0; k < nn; k++) Hx[k] -= Gx[k];
    }
    for (size_t k = 0; k < nn; k++) {
      Gx[k] += Hx[k];
      Gv[k] += Hv[k];
    }
  }
  /* M^-1 G = Psi (Psi^T G), BLAS-3: the outputs Ax, Av hold Psi^T G, the
   * products go back into Gx, Gv and are copied out */
  const double *Psi = s->m->Psi;
  if (!st && n >= VI_FORCE_BLAS_N) {
    double *Tx = Ax, *Tv = Av;
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, n, n, n, 1.0, Psi, n,
                Gx, n, 0.0, Tx, n);
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n, n, n, 1.0, Psi,
                n, Tx, n, 0.0, Gx, n);
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, n, n, n, 1.0, Psi, n,
                Gv, n, 0.0, Tv, n);
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, n, n, n, 1.0, Psi,
                n, Tv, n, 0.0, Gv, n);
    memcpy(Ax, Gx, sizeof(double) * nn);
    memcpy(Av, Gv, sizeof(double) * nn);
    return st;
  }
  for (int c = 0; c < n && !st; c++) {
    vi_matvec_t(n, Psi, Gx + (size_t)c * n, g0);
    vi_matvec(n, Psi, g0, Ax + (size_t)c * n);
    vi_matvec_t(n, Psi, Gv + (size_t)c * n, g0);
    vi_matvec(n, Psi, g0, Av + (size_t)c * n);
  }
  return st;
}
