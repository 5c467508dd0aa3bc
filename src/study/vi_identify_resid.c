/* vi_identify_resid.c - the model at trial values, its orbit continued
 * from trial to trial (Newton on the impact conditions from the last
 * Jacobian's linear predictor), the residuals at the recording's samples
 * and their Jacobian: the orbit's exact parameter sensitivities carried
 * to every sample by the state-transition matrix. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <lapacke.h>

#include "vi_identify_internal.h"

/* ---- models at trial values ------------------------------------------- */

/* A copy of the base model with the parameters set by key (vi_param.h:
 * only what each touches is redone). */
static int copy_model(vi_identify *id, const double *p, vi_model **out)
{
  vi_model *m = NULL;
  int st = vi_model_copy(id->base, &m);
  for (int j = 0; !st && j < id->np; j++)
    if ((st = vi_model_set_param(m, id->key[j], p[j])))
      vi_fail(id->errmsg, st, "%s", vi_model_errmsg(m));
  if (st) vi_model_destroy(&m);
  *out = m;
  return st;
}

int vi_id_make_model(vi_identify *id, const double *p, vi_model **out)
{
  *out = NULL;
  for (int j = 0; j < id->np; j++)
    if (!(p[j] >= id->lo[j] && p[j] <= id->hi[j])) return VI_ERR_ARG;
  if (!id->fn) return copy_model(id, p, out);
  int st = id->fn(p, id->user, out);
  if (st || !*out) {
    vi_model_destroy(out);
    return st ? st : VI_ERR_CALLBACK;
  }
  const vi_model *m = *out;
  if (!m->frozen || m->n != id->N || m->ns != id->base->ns || !vi_model_has_modes(m) ||
      !(m->omega_f > 0.0)) {
    vi_model_destroy(out);
    return vi_fail(id->errmsg, VI_ERR_CALLBACK,
                   "the builder's model is not set up like the base model "
                   "(%d coordinates, %d stops, harmonic forcing)",
                   id->N, id->base->ns);
  }
  return VI_OK;
}

double vi_id_period_of(const vi_model *m, int n) { return n * vi_forcing_period(m->omega_f); }

/* Bring the orbit's first impact into [0, P): the same periodic orbit. */
void vi_id_orb_normalise(orb *o, double P)
{
  double k = floor(o->t[0] / P);
  for (int j = 0; j < o->m; j++) o->t[j] -= k * P;
}

/* The model and its orbit at p: continued by Newton on the impact
 * conditions from the linear predictor u + du/dp (p - p_J) of the last
 * Jacobian's point (else from the current orbit).  The orbit must stay
 * admissible (one that hits a stop between impacts is not this motion)
 * and stable (an unstable orbit is not what a recording shows; Newton
 * may land on one from a far trial). */
int vi_id_ensure(vi_identify *id, const double *p)
{
  if (id->have_cur && !memcmp(p, id->pcur, sizeof(double) * id->np))
    return VI_OK;
  vi_model *m = NULL;
  vi_xflow *xf = NULL;
  int st = vi_id_make_model(id, p, &m), ok = 0, N = id->N;
  if (st) return st;
  orb *tr = &id->trial;
  if (id->have_pred) {
    int B = 2 * N + 1, D = id->acc.m * B;
    vi_id_orb_copy(tr, &id->acc, N);
    for (int q = 0; q < id->np; q++) {
      double dp = p[q] - id->pacc[q];
      const double *du = id->dudp + (size_t)q * D;
      for (int j = 0; j < tr->m; j++) {
        tr->t[j] += du[(size_t)j * B] * dp;
        for (int i = 0; i < N; i++) {
          tr->x[i + (size_t)j * N] += du[(size_t)j * B + 1 + i] * dp;
          tr->v[i + (size_t)j * N] += du[(size_t)j * B + 1 + N + i] * dp;
        }
      }
    }
  } else {
    vi_id_orb_copy(tr, &id->o, N);
  }
  st = vi_orbit_pnm_solve_stops(m, tr->n, tr->m, tr->stop, tr->t, tr->x,
                                tr->v, N, 0.0, NULL);
  if (!st)
    st = vi_orbit_pnm_admissible_stops(m, tr->n, tr->m, tr->stop, tr->t,
                                       tr->x, tr->v, N, NULL, &ok);
  if (!st && !ok) st = VI_ERR_NOT_CONVERGED;
  if (!st)
    st = vi_orbit_pnm_multipliers_stops(m, tr->n, tr->m, tr->stop, tr->t,
                                        tr->x, tr->v, N, id->mre, id->mim);
  for (int i = 0; !st && id->stable_only && i < 2 * N; i++)
    if (!(hypot(id->mre[i], id->mim[i]) < 1.0)) st = VI_ERR_NOT_CONVERGED;
  if (!st) st = vi_xflow_create(m, &xf);
  if (st) {
    vi_model_destroy(&m);
    return st;
  }
  vi_id_drop_cur(id);
  id->cur = m;
  id->xf = xf;
  vi_id_orb_normalise(tr, vi_id_period_of(m, tr->n));
  vi_id_orb_copy(&id->o, tr, N);
  memcpy(id->pcur, p, sizeof(double) * id->np);
  id->have_cur = 1;
  return VI_OK;
}

/* State z = (x, v) [2N] of the orbit of m at model time s; zp [2N] the
 * post-impact state of the segment. */
void vi_id_orbit_state(const vi_model *m, const vi_xflow *xf, const orb *o,
                        double s, double *z, double *zp, int *jo,
                        double *tauo, double *ko)
{
  int N = m->n, j;
  double tau, k;
  vi_id_locate(o, vi_id_period_of(m, o->n), s, &j, &tau, &k);
  memcpy(z, o->x + (size_t)j * N, sizeof(double) * N);
  memcpy(z + N, o->v + (size_t)j * N, sizeof(double) * N);
  vi_var_impact(m, o->stop[j], z, zp);
  vi_xflow_physical(xf, m, o->t[j], zp, zp + N, o->t[j] + tau, z, z + N);
  if (jo) *jo = j;
  if (tauo) *tauo = tau;
  if (ko) *ko = k;
}

/* ---- the least-squares problem ------------------------------------------- */

int vi_id_nres(const vi_identify *id)
{
  return id->ns * (1 + (id->vy != NULL) + (id->ay != NULL) + id->nch);
}

#define NB (3 + MAXCH)

/* The recorded channels as blocks of ns residuals: data, order of the
 * derivative (0 c.x, 1 c.x', 2 c.x''), observation vector, and weight
 * (Omega^(order of y - order): each block on the scale of the first);
 * their number. */
static int blocks(const vi_identify *id, const double **d, int *ord,
                  double *wt, const double **cv)
{
  int nb = 0;
  d[nb] = id->y;
  ord[nb] = id->ych;
  cv[nb] = id->c;
  wt[nb++] = 1.0;
  if (id->vy) {
    d[nb] = id->vy;
    ord[nb] = 1;
    cv[nb] = id->c;
    wt[nb++] = pow(id->Om0, id->ych - 1);
  }
  if (id->ay) {
    d[nb] = id->ay;
    ord[nb] = 2;
    cv[nb] = id->c;
    wt[nb++] = pow(id->Om0, id->ych - 2);
  }
  for (int k = 0; k < id->nch; k++) {
    d[nb] = id->chy[k];
    ord[nb] = id->chord[k];
    cv[nb] = id->chc[k];
    wt[nb++] = pow(id->Om0, id->ych - id->chord[k]);
  }
  return nb;
}

/* c.x, c.x' or c.x'' (order 0, 1, 2) of the state z [2N] of m at model
 * time s, for the observation c [N]; work [2N]. */
static double chan(int N, const double *c, const vi_model *m, double s,
                   const double *z, int order, double *work)
{
  if (order < 2) return vi_dot(N, c, z + (size_t)order * N);
  vi_var_field(m, s, z, work);
  return vi_dot(N, c, work + N);
}

/* The same from the state z [2N] and its acceleration a [N]
 * (vi_id_accel_block). */
static double chan_of(int N, const double *c, const double *z, const double *a,
                      int order)
{
  return vi_dot(N, c, order < 2 ? z + (size_t)order * N : a);
}

/* c.x, c.x' or c.x'' (order 0, 1, 2) of the state z [2N] of m at model
 * time s; work [2N]. */
double vi_id_channel(const vi_identify *id, const vi_model *m, double s,
                     const double *z, int order, double *work)
{
  return chan(id->N, id->c, m, s, z, order, work);
}

/* The first channel of the motion o of m (xf its flow) shifted by t0 at
 * every sample of the recording into y [ns]; VI_OK or VI_ERR_NOMEM. */
int vi_id_first_channel(const vi_identify *id, const vi_model *m, const vi_xflow *xf,
                        const orb *o, double t0, double *y)
{
  int N = id->N;
  double *w = malloc(sizeof(double) * 6 * N);
  if (!w) return VI_ERR_NOMEM;
  for (int i = 0; i < id->ns; i++) {
    double s = id->t[i] + t0;
    vi_id_orbit_state(m, xf, o, s, w, w + (size_t)2 * N, NULL, NULL, NULL);
    y[i] = vi_id_channel(id, m, s, w, id->ych, w + (size_t)4 * N);
  }
  free(w);
  return VI_OK;
}

/* The parameters and shift of the fit's vector th (held ones at their
 * values). */
void vi_id_split(const vi_identify *id, const gsl_vector *th, double *p,
                 double *t0)
{
  for (int j = 0; j < id->np; j++)
    p[j] = id->col[j] >= 0 ? gsl_vector_get(th, id->col[j]) : id->hval[j];
  *t0 = id->fit_shift ? gsl_vector_get(th, id->nfree) : vi_id_shift0(id);
}

int vi_id_res_f(const gsl_vector *th, void *ctx, gsl_vector *f)
{
  vi_identify *id = ctx;
  int N = id->N, ns = id->ns, ord[NB], jj[VI_ID_BLOCK];
  double p[MAXP] = {0}, t0, wt[NB], s[VI_ID_BLOCK], tau[VI_ID_BLOCK];
  const double *d[NB], *cv[NB];
  if (vi_id_poll_cancel(id)) return GSL_EBADFUNC; /* stops the GSL iteration */
  vi_id_split(id, th, p, &t0);
  if (vi_id_ensure(id, p)) {
    /* no admissible orbit there: a cost no step can accept */
    gsl_vector_set_all(f, 1e3 * id->scale);
    return GSL_SUCCESS;
  }
  vi_id_track tk;
  if (vi_id_track_init(&tk, id->cur, id->xf, &id->o)) return GSL_ENOMEM;
  int nb = blocks(id, d, ord, wt, cv), acc = 0;
  tk.halves = 0;
  for (int b = 0; b < nb; b++) {
    acc |= ord[b] == 2;
    tk.halves |= vi_id_halves(ord[b]);
  }
  for (int i0 = 0; i0 < ns; i0 += VI_ID_BLOCK) {
    int k = ns - i0 < VI_ID_BLOCK ? ns - i0 : VI_ID_BLOCK;
    for (int i = 0; i < k; i++) s[i] = id->t[i0 + i] + t0;
    vi_id_track_states(&tk, k, s, jj, tau, NULL, tk.Z, NULL);
    if (acc) vi_id_accel_block(id->cur, k, 1, s, tk.Z, tk.A);
    for (int i = 0; i < k; i++) {
      const double *z = tk.Z + (size_t)i * 2 * N, *a = tk.A + (size_t)i * N;
      for (int b = 0; b < nb; b++)
        gsl_vector_set(f, b * ns + i0 + i,
                       (d[b][i0 + i] - chan_of(N, cv[b], z, a, ord[b])) * wt[b]);
    }
  }
  vi_id_track_free(&tk);
  return GSL_SUCCESS;
}

/* Difference step of parameter j at p, kept inside its range. */
static void dstep(const vi_identify *id, const double *p, int j, double *hp,
                  double *hm)
{
  double h = 1e-6 * fmax(fabs(p[j]), 1e-3);
  *hp = p[j] + h <= id->hi[j] ? h : 0.0;
  *hm = p[j] - h >= id->lo[j] ? h : 0.0;
}

typedef struct jac_ws {
  double *Fu, *Fp, *F, *Fa, *Fb, *Phi, *dz, *g1, *zt; /* g1, zt: chan's work */
  int *ipiv;
  vi_model *mp[MAXP], *mm[MAXP];
  vi_xflow *xp[MAXP], *xm[MAXP];
  double hp[MAXP], hm[MAXP];
} jac_ws;

static void jac_free(jac_ws *w, int np)
{
  free(w->Fu);
  free(w->ipiv);
  for (int j = 0; j < np; j++) {
    vi_xflow_destroy(&w->xp[j]);
    vi_xflow_destroy(&w->xm[j]);
    vi_model_destroy(&w->mp[j]);
    vi_model_destroy(&w->mm[j]);
  }
}

/* Models at p +- h e_j for the differenced parts (VI_IDENTIFY_OTHER: the
 * conditions and the response; Omega: the response at a fixed orbit). */
static int jac_models(vi_identify *id, const double *p, jac_ws *w, int j)
{
  double q[MAXP];
  int st;
  dstep(id, p, j, &w->hp[j], &w->hm[j]);
  memcpy(q, p, sizeof(double) * id->np);
  q[j] = p[j] + w->hp[j];
  if ((st = vi_id_make_model(id, q, &w->mp[j]))) return st;
  q[j] = p[j] - w->hm[j];
  if ((st = vi_id_make_model(id, q, &w->mm[j]))) return st;
  if ((st = vi_xflow_create(w->mp[j], &w->xp[j]))) return st;
  return vi_xflow_create(w->mm[j], &w->xm[j]);
}

/* The Jacobian's rows at the samples from the orbit's sensitivity du/dp
 * (w->Fp, negated): impact j's du/dp through the impact law, moved to the
 * sample by the state-transition matrix, dz(s) = Phi(tau) zeta_j with
 * zeta_j = R (dx_j, dv_j) - dt_j f+; zeta_j is the impact's alone, so it
 * is formed once per impact (and, for proportional damping, taken to modal
 * coordinates once: Phi(tau) is then each mode's 2 x 2 flow); a block of
 * samples goes back to physical coordinates in one product. */
typedef struct jac_blk {
  double *Zeta, *Zm, *fseg; /* per impact: zeta [2N x np], modal, f+ [2N] */
  double *U, *dZ;           /* a block's modal and physical dz [2N x np x B] */
  double *Za, *Zb, *Zhp, *Zhm, *Zero; /* states [2N x B] */
  double *C;                /* the modes' 2 x 2 flows [4N x B] */
  double *G0, *Af, *Ahp, *Ahm; /* accelerations [N x B]: of the forcing
                                  alone, of the states, at s +- h */
  double *G1;               /* of the dz [N x np x B] */
  vi_id_track tk, tp[MAXP], tm[MAXP];
} jac_blk;

static void blk_free(jac_blk *k, int np)
{
  vi_id_track_free(&k->tk);
  for (int q = 0; q < np; q++) {
    if (k->tp[q].mem) vi_id_track_free(&k->tp[q]);
    if (k->tm[q].mem) vi_id_track_free(&k->tm[q]);
  }
  free(k->Zeta);
}

/* zeta and f+ of each impact (free parameters only; the rest stay 0) */
static void blk_zeta(const vi_identify *id, const jac_ws *w, jac_blk *k)
{
  const vi_model *m = id->cur;
  const orb *o = &id->o;
  int N = id->N, N2 = 2 * N, np = id->np, B = N2 + 1, D = o->m * B;
  for (int j = 0; j < o->m; j++) {
    int sj = o->stop[j];
    double *f = k->fseg + (size_t)j * N2;
    vi_var_field(m, o->t[j], k->tk.zp + (size_t)j * N2, f);
    for (int q = 0; q < np; q++) {
      if (id->col[q] < 0) continue; /* held */
      const double *du = w->Fp + (size_t)q * D + (size_t)j * B;
      double dt = -du[0], *zeta = k->Zeta + ((size_t)j * np + q) * N2;
      for (int r = 0; r < N2; r++) w->dz[r] = -du[1 + r];
      vi_var_impact(m, sj, w->dz, zeta);
      for (int r = 0; r < N2; r++) zeta[r] -= dt * f[r];
      if (id->kind[q] == VI_IDENTIFY_R && id->kst[q] == sj) {
        /* d v+/dr = -(w.v-) M^-1 w / (w^T M^-1 w) (WB 2) */
        const double *vj = o->v + (size_t)j * N, *Mw = vi_stop_minvw(m, sj);
        double g = vi_dot(N, vi_stop_w(m, sj), vj) / m->G[sj + (size_t)sj * m->ns];
        for (int r = 0; r < N; r++) zeta[N + r] -= g * Mw[r];
      }
    }
  }
  if (m->proportional) { /* [q; q'] = Psi^T M [x; v] of every column */
    int nc = o->m * np;
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, N, nc, N, 1.0,
                m->PsiTM, N, k->Zeta, N2, 0.0, k->Zm, N2);
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, N, nc, N, 1.0,
                m->PsiTM, N, k->Zeta + N, N2, 0.0, k->Zm + N, N2);
  }
}

/* dz = Phi(tau_i) zeta_{j_i} of every free parameter and sample of a
 * block into k->dZ (column i np + q); proportional damping: each mode's
 * 2 x 2 flow from k->C, the flights' own (vi_id_track_at) */
static int blk_dz(const vi_identify *id, jac_blk *k, jac_ws *w, int nk,
                  const int *jj, const double *tau)
{
  const vi_model *m = id->cur;
  int N = id->N, N2 = 2 * N, np = id->np;
  if (!m->proportional) {
    for (int i = 0; i < nk; i++) {
      if (vi_var_stm(m, tau[i], w->Phi)) return VI_ERR_TIME;
      cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, N2, np, N2, 1.0,
                  w->Phi, N2, k->Zeta + (size_t)jj[i] * np * N2, N2, 0.0,
                  k->dZ + (size_t)i * np * N2, N2);
    }
    return VI_OK;
  }
  for (int i = 0; i < nk; i++) {
    if (!(tau[i] >= 0.0) || !isfinite(tau[i])) return VI_ERR_TIME;
    for (int a = 0; a < N; a++) {
      const double *c = k->C + 4 * ((size_t)i * N + a);
      for (int q = 0; q < np; q++) {
        if (id->col[q] < 0) continue;
        const double *zm = k->Zm + ((size_t)jj[i] * np + q) * N2;
        double *u = k->U + ((size_t)i * np + q) * N2;
        u[a] = c[0] * zm[a] + c[2] * zm[N + a];
        u[N + a] = c[1] * zm[a] + c[3] * zm[N + a];
      }
    }
  }
  int nc = nk * np; /* x = Psi q, v = Psi q' */
  cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, N, nc, N, 1.0,
              m->Psi, N, k->U, N2, 0.0, k->dZ, N2);
  cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, N, nc, N, 1.0,
              m->Psi, N, k->U + N, N2, 0.0, k->dZ + N, N2);
  return VI_OK;
}

/* d/ds of each channel at a block's samples into dds [nb x VI_ID_BLOCK]
 * (the response's rate along the orbit): of c.x, c.x' from the field at
 * the sample, of c.x'' centrally differenced. */
static void blk_rate(const vi_identify *id, jac_blk *k, int nk, const double *s,
                     const double *tt, double *dds)
{
  const vi_model *m = id->cur;
  int N = id->N, N2 = 2 * N;
  double P = vi_id_period_of(m, id->o.n), wt[NB];
  const double *dat[NB], *cv[NB];
  int ord[NB], nb = blocks(id, dat, ord, wt, cv), acc = 0;
  for (int b = 0; b < nb; b++) acc |= ord[b] == 2;
  double hs = 1e-6 * P, sp[VI_ID_BLOCK], sm[VI_ID_BLOCK], th[VI_ID_BLOCK];
  int jh[VI_ID_BLOCK];
  if (acc) { /* d/ds of the acceleration, centrally differenced */
    for (int i = 0; i < nk; i++) {
      sp[i] = s[i] + hs;
      sm[i] = s[i] - hs;
    }
    vi_id_track_states(&k->tk, nk, sp, jh, th, NULL, k->Zhp, NULL);
    vi_id_track_states(&k->tk, nk, sm, jh, th, NULL, k->Zhm, NULL);
    vi_id_accel_block(m, nk, 1, sp, k->Zhp, k->Ahp);
    vi_id_accel_block(m, nk, 1, sm, k->Zhm, k->Ahm);
  }
  /* d/ds of c.x, c.x': the field z' at the sample */
  vi_id_accel_block(m, nk, 1, tt, k->tk.Z, k->Af);
  for (int i = 0; i < nk; i++)
    for (int b = 0; b < nb; b++)
      dds[b * VI_ID_BLOCK + i] =
          ord[b] < 2 ? vi_dot(N, cv[b], ord[b] ? k->Af + (size_t)i * N
                                                : k->tk.Z + (size_t)i * N2 + N)
                     : (vi_dot(N, cv[b], k->Ahp + (size_t)i * N) -
                        vi_dot(N, cv[b], k->Ahm + (size_t)i * N)) / (2.0 * hs);
}

static int jac_samples(vi_identify *id, jac_ws *w, double t0, gsl_matrix *J)
{
  const vi_model *m = id->cur;
  const orb *o = &id->o;
  int N = id->N, N2 = 2 * N, ns = id->ns, np = id->np, st;
  double wt[NB];
  const double *dat[NB], *cv[NB];
  int ord[NB], nb = blocks(id, dat, ord, wt, cv), acc = 0;
  for (int b = 0; b < nb; b++) acc |= ord[b] == 2;
  jac_blk k;
  memset(&k, 0, sizeof k);
  size_t zs = (size_t)N2 * np * o->m, bs = (size_t)N2 * np * VI_ID_BLOCK,
         vs = (size_t)N2 * VI_ID_BLOCK;
  k.Zeta = calloc(2 * zs + (size_t)N2 * o->m + 3 * bs + 9 * vs, sizeof(double));
  if (!k.Zeta) return VI_ERR_NOMEM;
  k.Zm = k.Zeta + zs;
  k.fseg = k.Zm + zs;
  k.U = k.fseg + (size_t)N2 * o->m;
  k.dZ = k.U + bs;
  k.Za = k.dZ + bs;
  k.Zb = k.Za + vs;
  k.Zhp = k.Zb + vs;
  k.Zhm = k.Zhp + vs;
  k.Zero = k.Zhm + vs;
  k.C = k.Zero + vs;      /* 2 vs */
  k.G0 = k.C + 2 * vs;    /* vs / 2 each */
  k.Af = k.G0 + vs / 2;
  k.Ahp = k.Af + vs / 2;
  k.Ahm = k.Ahp + vs / 2;
  k.G1 = k.Ahm + vs / 2;  /* bs / 2 */
  st = vi_id_track_init(&k.tk, m, id->xf, o);
  for (int q = 0; !st && q < np; q++)
    if (w->mp[q] && id->col[q] >= 0 &&
        !(st = vi_id_track_init(&k.tp[q], w->mp[q], w->xp[q], o)))
      st = vi_id_track_init(&k.tm[q], w->mm[q], w->xm[q], o);
  if (st) {
    blk_free(&k, np);
    return st;
  }
  blk_zeta(id, w, &k);
  for (int i0 = 0; i0 < ns; i0 += VI_ID_BLOCK) {
    int nk = ns - i0 < VI_ID_BLOCK ? ns - i0 : VI_ID_BLOCK, jj[VI_ID_BLOCK];
    double s[VI_ID_BLOCK], tau[VI_ID_BLOCK], kper[VI_ID_BLOCK];
    for (int i = 0; i < nk; i++) s[i] = id->t[i0 + i] + t0;
    vi_id_track_states(&k.tk, nk, s, jj, tau, kper, k.tk.Z, k.C);
    if ((st = blk_dz(id, &k, w, nk, jj, tau))) break;
    double tt[VI_ID_BLOCK], dds[NB * VI_ID_BLOCK] = {0};
    for (int i = 0; i < nk; i++) tt[i] = o->t[jj[i]] + tau[i];
    if (acc) { /* the field is affine in the state: A dz = g(dz) - g(0) */
      vi_id_accel_block(m, nk, 1, tt, k.Zero, k.G0);
      vi_id_accel_block(m, nk, np, tt, k.dZ, k.G1);
    }
    /* the rate serves the shift's column and a period's change (Omega) */
    if (id->fit_shift || id->jom >= 0) blk_rate(id, &k, nk, s, tt, dds);
    for (int q = 0; q < np; q++) {
      if (id->col[q] < 0) continue; /* held */
      double h = w->hp[q] + w->hm[q], dper = 0.0;
      if (w->mp[q]) {
        /* the response's own dependence at a fixed orbit (Omega: the
         * forcing), differenced at the sample's place in its period; the
         * period's change moves that place by kper dP (the sample kper
         * periods on), taken with the response's rate, not differenced:
         * a recording whose clock starts 10^5 periods before its first
         * sample moves it by a large part of a period at the step h */
        dper = (vi_id_period_of(w->mm[q], o->n) - vi_id_period_of(w->mp[q], o->n)) / h;
        vi_id_track_at(&k.tp[q], nk, jj, tau, k.Za, NULL);
        vi_id_track_at(&k.tm[q], nk, jj, tau, k.Zb, NULL);
      }
      for (int i = 0; i < nk; i++) {
        double tj = o->t[jj[i]], dc[NB];
        const double *dz = k.dZ + ((size_t)i * np + q) * N2,
                     *g1 = k.G1 + ((size_t)i * np + q) * N, *g0 = k.G0 + (size_t)i * N;
        for (int b = 0; b < nb; b++)
          dc[b] = ord[b] < 2 ? vi_dot(N, cv[b], dz + (size_t)ord[b] * N)
                             : vi_dot(N, cv[b], g1) - vi_dot(N, cv[b], g0);
        for (int b = 0; w->mp[q] && b < nb; b++)
          dc[b] += (chan(N, cv[b], w->mp[q], tj + tau[i], k.Za + (size_t)i * N2,
                         ord[b], w->g1) -
                    chan(N, cv[b], w->mm[q], tj + tau[i], k.Zb + (size_t)i * N2,
                         ord[b], w->zt)) / h +
                   dds[b * VI_ID_BLOCK + i] * kper[i] * dper;
        for (int b = 0; b < nb; b++)
          gsl_matrix_set(J, b * ns + i0 + i, id->col[q], -dc[b] * wt[b]);
      }
    }
    /* the shift's column: the response's rate */
    for (int i = 0; id->fit_shift && i < nk; i++)
      for (int b = 0; b < nb; b++)
        gsl_matrix_set(J, b * ns + i0 + i, id->nfree, -dds[b * VI_ID_BLOCK + i] * wt[b]);
  }
  blk_free(&k, np);
  return st;
}

int vi_id_res_df(const gsl_vector *th, void *ctx, gsl_matrix *J)
{
  vi_identify *id = ctx;
  int N = id->N, N2 = 2 * N, np = id->np, st;
  double p[MAXP] = {0}, t0;
  if (vi_id_poll_cancel(id)) return GSL_EBADFUNC;
  vi_id_split(id, th, p, &t0);
  if (vi_id_ensure(id, p)) return GSL_EBADFUNC;
  const vi_model *m = id->cur;
  const orb *o = &id->o;
  int B = N2 + 1, D = o->m * B;
  jac_ws w;
  memset(&w, 0, sizeof w);
  size_t nd = (size_t)D * D + (size_t)D * np + 3 * (size_t)D +
              (size_t)N2 * N2 + 3 * (size_t)N2;
  w.Fu = malloc(sizeof(double) * nd);
  w.ipiv = malloc(sizeof(int) * D);
  if (!w.Fu || !w.ipiv) {
    jac_free(&w, np);
    return GSL_ENOMEM;
  }
  w.Fp = w.Fu + (size_t)D * D;
  w.F = w.Fp + (size_t)D * np;
  w.Fa = w.F + D;
  w.Fb = w.Fa + D;
  w.Phi = w.Fb + D;
  w.dz = w.Phi + (size_t)N2 * N2;
  w.g1 = w.dz + N2;
  w.zt = w.g1 + N2;
  /* the orbit's sensitivity du/dp = -F_u^-1 F_p (exact F_u) */
  st = vi_orbit_pnm_residual_stops(m, o->n, o->m, o->stop, o->t, o->x, o->v,
                                   N, w.F, w.Fu);
  for (int j = 0; !st && j < np; j++) {
    double *Fpj = w.Fp + (size_t)j * D;
    int k = id->kind[j];
    if (k == VI_IDENTIFY_OMEGA || k == VI_IDENTIFY_OTHER)
      st = jac_models(id, p, &w, j);
    if (st) break;
    if (k != VI_IDENTIFY_OTHER) {
      st = vi_orbit_pnm_dparam(m, o->n, o->m, o->stop, o->t, o->x, o->v, N,
                               k, id->kst[j], Fpj);
      continue;
    }
    st = vi_orbit_pnm_residual_stops(w.mp[j], o->n, o->m, o->stop, o->t,
                                     o->x, o->v, N, w.Fa, NULL);
    if (!st)
      st = vi_orbit_pnm_residual_stops(w.mm[j], o->n, o->m, o->stop, o->t,
                                       o->x, o->v, N, w.Fb, NULL);
    for (int i = 0; !st && i < D; i++)
      Fpj[i] = (w.Fa[i] - w.Fb[i]) / (w.hp[j] + w.hm[j]);
  }
  if (!st && LAPACKE_dgesv(LAPACK_COL_MAJOR, D, np, w.Fu, D, w.ipiv, w.Fp, D))
    st = VI_ERR_LAPACK;
  if (st) {
    jac_free(&w, np);
    return GSL_EBADFUNC;
  }
  /* the predictor for the next trials */
  vi_id_orb_copy(&id->acc, o, N);
  memcpy(id->pacc, p, sizeof(double) * np);
  for (size_t i = 0; i < (size_t)D * np; i++) id->dudp[i] = -w.Fp[i];
  id->have_pred = 1;
  st = jac_samples(id, &w, t0, J);
  jac_free(&w, np);
  return st ? (st == VI_ERR_NOMEM ? GSL_ENOMEM : GSL_EBADFUNC) : GSL_SUCCESS;
}
