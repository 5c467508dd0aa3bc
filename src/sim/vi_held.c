/* vi_held.c - sticking phases of the exact method in closed form (MODEL.md
 * section 9): while the stops S hold, the motion is the flow of the
 * constrained modes (vi_constrained.c, one set of modes per held set,
 * cached here), and every event is the first root of a function that is
 * linear in the constrained modal state and the forcing:
 *   - release of held stop k: -lambda_k(t) rising through 0;
 *   - contact with a stop not held: its gap rising through 0.
 * Each such f = a.w + c.w' + GA cos + GB sin + f0, w the constrained modes
 * less their harmonic part (u = H + w, w'' + d w' + Omega^2 w = F0), is
 * searched as vi_exact.c searches the gap: a uniform grid at a quarter
 * period of the fastest mode, each interval skipped only when a rigorous
 * upper bound of f on it (the cubic Hermite through f, f' at its ends plus
 * B4 h^4 / 384) stays below the round-off of f; else a left-first
 * bisection finds the first crossing - a maximum of f touching zero
 * between grid points included - and the root is refined to round-off in
 * t.  The bounds |f''|, |f'''|, |f''''| come from the modes' energies:
 * every derivative w^(k), k >= 1, is a free damped oscillation whose
 * energy w^(k+1)^2 + Omega^2 w^(k)^2 cannot grow.  Sign changes of a
 * reaction are therefore resolved like grazing contacts, never stepped
 * over.  The held stops do no work (fixed stops); the ledger books the
 * constraint's exchange between modes (CE) by the same quadrature as the
 * free flight's. */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "vi_grid.h"
#include "vi_held_internal.h"
#include "vi_quadmap.h"
#include "vi_vec.h"

#define HD_CACHE 8       /* held sets kept */
#define HD_ANCHOR 64     /* grid steps between direct evaluations */
#define HD_BATCH 512     /* grid steps per call of step() at most */
#define HD_GRID 1.5707963267948966 /* grid step, radians of the fastest rate */
#define HD_DEPTH 60      /* bisection levels below the grid's */

/* A watched function: kind 0 the release of held stop `stop` (f =
 * -lambda), kind 1 the gap of stop `stop`. */
typedef struct hd_fun {
  int kind, stop, slot;          /* slot: index in the held set (kind 0) */
  const double *a, *c;           /* weights of w, w' of the active modes
                                    (c NULL: none) */
  double GA, GB, GH, f0;         /* harmonic part, its amplitude; constant */
  double off, noise, tol;        /* offset at t0; round-off; gap tolerance */
  double B2, B3, B4;             /* bounds of |f''|, |f'''|, |f''''| */
} hd_fun;

/* Constrained modes of held sets: a simulation's own, or one a study
 * shares across the simulations of its points (vi_held_share_cache). */
struct vi_held_cache {
  vi_cmodes *cache[HD_CACHE];
  int ncache, next;
};

struct vi_held {
  vi_held_cache own, *hc;        /* hc: own, or a study's */
  const vi_cmodes *cm;
  int m, na, nf, *act;
  size_t cap_act, cap_w;         /* capacities of act and w0's block: a
                                    phase reuses the last one's */
  /* per phase */
  double t0, Om, h;
  double *w0, *wd0;              /* every constrained mode at t0 [m] */
  double *lam, *dmp, *F0;        /* of the active modes [na] */
  double *wts;                   /* weights of the functions [2 nf na] */
  vi_grid g;                     /* the grid t_k = t0 + k h: the active
                                    modes [na] and the functions [nf]
                                    there */
  double *wa, *wda;              /* scratch [na] */
  double *T;                     /* the grid step's maps B, Bp, phi [3 na] */
  double *u, *ud, *q, *qd;       /* [m], [m], [n], [n] */
  hd_fun f[2 * VI_CONTACT_MAX + 64];
  double hq, *wf;                 /* wf: scratch [m] */
  vi_quadmap qm;                 /* the ledger quadrature's node maps */
  int64_t evals;
  const vi_sim *s;               /* the host's poll in hd_search */
  unsigned polls;
};

static void hd_phase_free(vi_held *H)
{
  free(H->act);
  free(H->w0);
  H->act = NULL;
  H->w0 = NULL;
  H->cap_act = H->cap_w = 0;
}

/* p with room for n elements of size sz: grown, never shrunk, so that a
 * held phase allocates nothing after the first of its size.  NULL when
 * out of memory (p is then still valid). */
static void *hd_grow(void *p, size_t *cap, size_t n, size_t sz)
{
  if (p && n <= *cap) return p;
  void *q = realloc(p, n * sz);
  if (q) *cap = n;
  return q;
}

void vi_held_cache_clear(vi_held_cache *hc)
{
  if (!hc) return;
  for (int i = 0; i < hc->ncache; i++) vi_cmodes_destroy(&hc->cache[i]);
  hc->ncache = hc->next = 0;
}

vi_held_cache *vi_held_cache_create(void)
{
  return calloc(1, sizeof(vi_held_cache));
}

void vi_held_cache_destroy(vi_held_cache **hc)
{
  if (!hc || !*hc) return;
  vi_held_cache_clear(*hc);
  free(*hc);
  *hc = NULL;
}

static vi_held *hd_get(vi_sim *s)
{
  if (!s->held && (s->held = calloc(1, sizeof *s->held)))
    s->held->hc = &s->held->own;
  return s->held;
}

int vi_held_share_cache(vi_sim *s, vi_held_cache *hc)
{
  vi_held *H = hd_get(s);
  if (!H) return VI_ERR_NOMEM;
  H->hc = hc ? hc : &H->own;
  return VI_OK;
}

void vi_held_free(vi_sim *s)
{
  vi_held *H = s->held;
  if (!H) return;
  vi_held_cache_clear(&H->own);
  hd_phase_free(H);
  vi_quadmap_free(&H->qm);
  free(H);
  s->held = NULL;
}

/* The constrained modes of the current sticking set, built on first use
 * (NULL with s->errmsg on failure). */
static const vi_cmodes *hd_modes(vi_sim *s)
{
  vi_held *H = hd_get(s);
  if (!H) return NULL;
  vi_held_cache *hc = H->hc;
  for (int i = 0; i < hc->ncache; i++) {
    vi_cmodes *c = hc->cache[i];
    if (c->cnt == s->nstick &&
        !memcmp(c->set, s->stick_k, sizeof(int) * (size_t)s->nstick)) {
      vi_cmodes_retune(c, s->m->omega_f); /* a shared cache's new Omega */
      return c;
    }
  }
  vi_cmodes *c = NULL;
  if (vi_cmodes_create(s->m, s->stick_k, s->nstick, &c, s->errmsg)) return NULL;
  if (hc->ncache < HD_CACHE) {
    hc->cache[hc->ncache++] = c;
  } else { /* a few sets per run: replace round-robin */
    if (H->cm == hc->cache[hc->next]) hc->next = (hc->next + 1) % HD_CACHE;
    vi_cmodes_destroy(&hc->cache[hc->next]);
    hc->cache[hc->next] = c;
    hc->next = (hc->next + 1) % HD_CACHE;
  }
  return c;
}

int vi_held_available(vi_sim *s)
{
  if (!s->sticking || s->ns > 2 * VI_CONTACT_MAX + 64) return 0;
  const vi_cmodes *c = hd_modes(s);
  if (!c) s->errmsg[0] = '\0'; /* CVODE holds it instead */
  return c && c->ok;
}

/* Constrained mode i's rest part at t (from the phase start). */
static inline void hd_mode(const vi_held *H, int i, double t, double *w,
                           double *wd)
{
  const vi_cmodes *c = H->cm;
  double B, Bp, ph, l = c->om2[i];
  vi_flow_basis(l, c->dmp[i], t - H->t0, &B, &Bp, &ph);
  double f = c->F0[i] - l * H->w0[i];
  *w = H->w0[i] + B * H->wd0[i] + ph * f;
  *wd = Bp * H->wd0[i] + B * f;
}

/* f, f' of function e from the active modes (w, wd) and cos, sin of Om t. */
static inline void hd_eval(const vi_held *H, const hd_fun *e, const double *w,
                           const double *wd, double c, double sn, double *f,
                           double *fd)
{
  const double *restrict a = e->a, *restrict cc = e->c;
  const double *restrict F0 = H->F0, *restrict dm = H->dmp, *restrict lam = H->lam;
  /* four partial sums in two pairs (vi_vec.h) */
  vi_v2 X[2] = {{0.0, 0.0}, {0.0, 0.0}}, V[2] = {{0.0, 0.0}, {0.0, 0.0}};
  int na = H->na, i = 0;
  for (; i + 4 <= na; i += 4)
    for (int h = 0; h < 2; h++) {
      int k = i + 2 * h;
      vi_v2 ak = vi_v2_ld(a + k), wk = vi_v2_ld(w + k), wdk = vi_v2_ld(wd + k);
      X[h] += ak * wk;
      V[h] += ak * wdk;
      if (cc) {
        vi_v2 ck = vi_v2_ld(cc + k);
        vi_v2 acc = vi_v2_ld(F0 + k) - vi_v2_ld(dm + k) * wdk - vi_v2_ld(lam + k) * wk;
        X[h] += ck * wdk;
        V[h] += ck * acc;
      }
    }
  double x = vi_v2_sum4(X), v = vi_v2_sum4(V);
  for (; i < na; i++) {
    x += a[i] * w[i];
    v += a[i] * wd[i];
    if (cc) {
      double acc = F0[i] - dm[i] * wd[i] - lam[i] * w[i];
      x += cc[i] * wd[i];
      v += cc[i] * acc;
    }
  }
  vi_phase p = {H->Om, c, sn};
  *f = x + vi_harm(&p, 0, e->GA, e->GB, e->f0) - e->off;
  *fd = v + vi_harm(&p, 1, e->GA, e->GB, 0.0);
}

/* Active modes at t directly, and every function there. */
static void hd_anchor(vi_held *H, double t, double *w, double *wd, double *c,
                      double *sn, double *f, double *fd)
{
  for (int i = 0; i < H->na; i++) hd_mode(H, H->act[i], t, w + i, wd + i);
  vi_phase p = vi_phase_at(H->Om, t);
  *c = p.c;
  *sn = p.s;
  for (int j = 0; j < H->nf; j++) hd_eval(H, H->f + j, w, wd, *c, *sn, f + j, fd + j);
  H->evals++;
}

/* Function e at t directly (the bisection's points). */
static void hd_at(vi_held *H, const hd_fun *e, double t, double *f, double *fd)
{
  for (int i = 0; i < H->na; i++) hd_mode(H, H->act[i], t, H->wa + i, H->wda + i);
  vi_phase p = vi_phase_at(H->Om, t);
  hd_eval(H, e, H->wa, H->wda, p.c, p.s, f, fd);
  H->evals++;
}

/* Bounds of every function's |f''|, |f'''|, |f''''| from the active modes
 * (w, wd) on: |w^(k)| <= sqrt(w^(k)^2 + Omega^2 w^(k-1)^2), k >= 2. */
static void hd_bounds(vi_held *H, const double *w, const double *wd)
{
  double O = H->Om, O2 = O * O;
  for (int j = 0; j < H->nf; j++) {
    hd_fun *e = H->f + j;
    double b2 = 0.0, b3 = 0.0, b4 = 0.0;
    for (int i = 0; i < H->na; i++) {
      double l = H->lam[i], d = H->dmp[i];
      double w2 = H->F0[i] - d * wd[i] - l * w[i];
      double w3 = -d * w2 - l * wd[i], w4 = -d * w3 - l * w2;
      double w5 = -d * w4 - l * w3;
      double e2 = sqrt(w2 * w2 + l * wd[i] * wd[i]);
      double e3 = sqrt(w3 * w3 + l * w2 * w2), e4 = sqrt(w4 * w4 + l * w3 * w3);
      double e5 = sqrt(w5 * w5 + l * w4 * w4);
      double aa = fabs(e->a[i]), cc = e->c ? fabs(e->c[i]) : 0.0;
      b2 += aa * e2 + cc * e3;
      b3 += aa * e3 + cc * e4;
      b4 += aa * e4 + cc * e5;
    }
    e->B2 = (b2 + e->GH * O2) * (1.0 + 1e-9);
    e->B3 = (b3 + e->GH * O2 * O) * (1.0 + 1e-9);
    e->B4 = (b4 + e->GH * O2 * O2) * (1.0 + 1e-9);
  }
}

/* Root of e in [a, b], f(a) < 0 <= f(b), f increasing: regula falsi
 * (Illinois) to round-off in t; the upper end (f >= 0) is returned, so
 * that the event is never reported before its root. */
static double hd_root(vi_held *H, const hd_fun *e, double a, double fa,
                      double b, double fb)
{
  int side = 0;
  for (int it = 0; it < 200; it++) {
    if (b - a <= 2.0 * DBL_EPSILON * fmax(fabs(a), fabs(b))) break;
    double t = (a * fb - b * fa) / (fb - fa);
    if (!(t > a && t < b)) t = 0.5 * (a + b);
    double ft, fdt;
    hd_at(H, e, t, &ft, &fdt);
    if (ft >= 0.0) {
      b = t;
      fb = ft;
      if (side == 1) fa *= 0.5;
      side = 1;
    } else {
      a = t;
      fa = ft;
      if (side == -1) fb *= 0.5;
      side = -1;
    }
  }
  return b;
}

/* First t in (a, b] with f(t) >= 0, left first. 1 with *tc, 0: none,
 * VI_CANCELLED: the host cancelled (polled: 2^HD_DEPTH leaves at worst). */
static int hd_search(vi_held *H, const hd_fun *e, int depth, double a,
                     double fa, double fda, double b, double fb, double fdb,
                     double *tc)
{
  double w = b - a, w2 = w * w;
  if (vi_sim_cancelled_every(H->s, &H->polls)) return VI_CANCELLED;
  if (vi_herm_max(fa, fda, fb, fdb, w, NULL) + e->B4 * w2 * w2 / 384.0 <
      e->noise)
    return 0;
  double fdlo = 0.5 * (fda + fdb - e->B2 * w);
  double fdhi = 0.5 * (fda + fdb + e->B2 * w);
  if (fdhi < 0.0 && fa <= 0.0) return 0; /* decreasing */
  if (fdlo > 0.0 && fa < 0.0) {          /* increasing */
    if (fb < 0.0) return 0;
    *tc = hd_root(H, e, a, fa, b, fb);
    return 1;
  }
  if (fdlo > 0.0 && a > H->t0) { /* rising from f(a) >= 0 */
    *tc = a;
    return 1;
  }
  if (depth >= HD_DEPTH || w <= 4.0 * DBL_EPSILON * fabs(b)) {
    /* next to the start, only beyond round-off */
    if (fb < 0.0 || (a <= H->t0 && fb <= e->noise)) return 0;
    *tc = b;
    return 1;
  }
  double mid = a + 0.5 * w, fm, fdm;
  hd_at(H, e, mid, &fm, &fdm);
  int st = hd_search(H, e, depth + 1, a, fa, fda, mid, fm, fdm, tc);
  if (st) return st;
  return hd_search(H, e, depth + 1, mid, fm, fdm, b, fb, fdb, tc);
}

/* The functions of the current held set, over the active modes. */
static int hd_setup(vi_sim *s, vi_held *H)
{
  const vi_model *m = s->m;
  const vi_cmodes *c = H->cm;
  int mm = c->m, nst = s->nstick, nf = s->ns;
  /* active: some function sees the mode */
  int na = 0;
  size_t nd = 2 * (size_t)mm + 3 * (size_t)mm + 2 * (size_t)nf * mm +
              6 * (size_t)mm + 3 * (size_t)mm + 2 * (size_t)mm +
              2 * (size_t)c->n + 4 * (size_t)nf + (size_t)mm + 8;
  int *act = hd_grow(H->act, &H->cap_act, (size_t)mm + 1, sizeof(int));
  if (act) H->act = act;
  double *w0 = act ? hd_grow(H->w0, &H->cap_w, nd, sizeof(double)) : NULL;
  if (w0) H->w0 = w0;
  if (!act || !w0) {
    hd_phase_free(H);
    return vi_fail(s->errmsg, VI_ERR_NOMEM, "out of memory");
  }
  for (int i = 0; i < mm; i++) {
    int on = 0;
    for (int j = 0; j < nst && !on; j++) on = c->R[(size_t)j * mm + i] != 0.0;
    for (int k = 0; k < m->ns && !on; k++)
      on = !vi_sim_in_stick_set(s, k) && c->Pg[(size_t)k * mm + i] != 0.0;
    if (on) H->act[na++] = i;
  }
  double *p = H->w0;
  p += mm;
  H->wd0 = p; p += mm;
  H->lam = p; p += mm;
  H->dmp = p; p += mm;
  H->F0 = p; p += mm;
  H->wts = p; p += 2 * (size_t)nf * mm;
  H->g.wk = p; p += mm;
  H->g.wdk = p; p += mm;
  H->g.wn = p; p += mm;
  H->g.wdn = p; p += mm;
  H->wa = p; p += mm;
  H->wda = p; p += mm;
  H->T = p; p += 3 * (size_t)mm;
  H->u = p; p += mm;
  H->ud = p; p += mm;
  H->q = p; p += c->n;
  H->qd = p; p += c->n;
  H->wf = p; p += mm;
  H->g.fk = p; p += nf;
  H->g.fdk = p; p += nf;
  H->g.fn = p; p += nf;
  H->g.fdn = p;
  H->m = mm;
  H->na = na;
  H->Om = m->omega_f;
  double top = 0.0;
  for (int i = 0; i < na; i++) {
    int j = H->act[i];
    H->lam[i] = c->om2[j];
    H->dmp[i] = c->dmp[j];
    H->F0[i] = c->F0[j];
    top = fmax(top, fmax(sqrt(c->om2[j]), c->dmp[j]));
  }
  /* the functions: releases of the held stops, gaps of the others */
  int j = 0;
  double *wt = H->wts, Om = H->Om, b = c->brl;
  for (int i = 0; i < nst; i++, j++) {
    hd_fun *e = H->f + j;
    memset(e, 0, sizeof *e);
    e->kind = 0;
    e->stop = s->stick_k[i];
    e->slot = i;
    double *a = wt, *cc = wt + na;
    wt += 2 * (size_t)na;
    const double *R = c->R + (size_t)i * mm;
    double GA = -c->lA[i], GB = -c->lB[i];
    for (int q = 0; q < mm; q++) {
      GA += R[q] * (c->pA[q] + b * Om * c->pB[q]);
      GB += R[q] * (c->pB[q] - b * Om * c->pA[q]);
    }
    for (int q = 0; q < na; q++) {
      a[q] = R[H->act[q]];
      cc[q] = b * R[H->act[q]];
    }
    e->a = a;
    e->c = b != 0.0 ? cc : NULL;
    e->GA = GA;
    e->GB = GB;
    e->f0 = -c->lc[i];
  }
  for (int k = 0; k < m->ns; k++) {
    if (vi_sim_in_stick_set(s, k)) continue;
    hd_fun *e = H->f + j++;
    memset(e, 0, sizeof *e);
    e->kind = 1;
    e->stop = k;
    double *a = wt;
    wt += (size_t)na;
    const double *P = c->Pg + (size_t)k * mm;
    double GA = 0.0, GB = 0.0;
    for (int q = 0; q < mm; q++) {
      GA += P[q] * c->pA[q];
      GB += P[q] * c->pB[q];
    }
    for (int q = 0; q < na; q++) a[q] = P[H->act[q]];
    e->a = a;
    e->GA = GA;
    e->GB = GB;
    e->f0 = c->gc[k];
    e->tol = vi_sim_gap_tol(s, k);
  }
  H->nf = j;
  int harm = 0;
  for (int q = 0; q < j; q++) {
    H->f[q].GH = hypot(H->f[q].GA, H->f[q].GB);
    harm |= H->f[q].GH != 0.0;
  }
  if (harm) top = fmax(top, Om);
  H->h = top > 0.0 ? HD_GRID / top : 1.0;
  double all = Om;
  for (int i = 0; i < mm; i++)
    all = fmax(all, fmax(sqrt(c->om2[i]), c->dmp[i]));
  H->hq = all > 0.0 ? 0.7853981633974483 / all : HUGE_VAL;
  for (int i = 0; i < na; i++)
    vi_flow_basis(H->lam[i], H->dmp[i], H->h, H->T + i, H->T + na + i,
                  H->T + 2 * (size_t)na + i);
  return VI_OK;
}

/* Every constrained mode's u, u' at t. */
static void hd_modes_phase(vi_held *H, const vi_phase *p, double t,
                           double *u, double *ud)
{
  const vi_cmodes *c = H->cm;
  for (int i = 0; i < H->m; i++) {
    double w, wd;
    hd_mode(H, i, t, &w, &wd);
    u[i] = w + vi_harm(p, 0, c->pA[i], c->pB[i], 0.0);
    ud[i] = wd + vi_harm(p, 1, c->pA[i], c->pB[i], 0.0);
  }
}

static void hd_modes_at(vi_held *H, double t, double *u, double *ud)
{
  vi_phase p = vi_phase_at(H->Om, t);
  hd_modes_phase(H, &p, t, u, ud);
}

/* Free modal q, q' [n] of the constrained state (u, ud). */
static void hd_free_modal(const vi_cmodes *c, const double *u, const double *ud,
                          double *q, double *qd)
{
  int n = c->n;
  memcpy(q, c->qc, sizeof(double) * (size_t)n);
  memset(qd, 0, sizeof(double) * (size_t)n);
  for (int i = 0; i < c->m; i++) { /* column order: Phi is column-major */
    const double *col = c->Phi + (size_t)i * n;
    double a = u[i], b = ud[i];
    for (int r = 0; r < n; r++) {
      q[r] += col[r] * a;
      qd[r] += col[r] * b;
    }
  }
}

/* Physical interleaved state of the constrained state at t into z. */
static void hd_state(vi_sim *s, vi_held *H, double t, double *z)
{
  const vi_model *m = s->m;
  int n = m->n;
  hd_modes_at(H, t, H->u, H->ud);
  hd_free_modal(H->cm, H->u, H->ud, H->q, H->qd);
  for (int i = 0; i < 2 * n; i++) z[i] = 0.0;
  for (int j = 0; j < n; j++) {
    const double *col = m->Psi + (size_t)j * n;
    double a = H->q[j], b = H->qd[j];
    for (int i = 0; i < n; i++) {
      z[2 * (size_t)i] += col[i] * a;
      z[2 * (size_t)i + 1] += col[i] * b;
    }
  }
  H->evals++;
}

int vi_held_start(vi_sim *s)
{
  const vi_cmodes *c = hd_modes(s);
  if (!c || !c->ok)
    return vi_fail(s->errmsg, VI_ERR_STATE, "internal: the held set has no "
                   "closed form (%s)", c ? c->why : s->errmsg);
  vi_held *H = s->held;
  int st;
  H->cm = c; /* the stops not held may differ: set up every time */
  if ((st = hd_setup(s, H))) return st;
  if (!H->w0 || !H->act) /* hd_setup's success says so; the analyzer */
    return vi_fail(s->errmsg, VI_ERR_NOMEM, "out of memory"); /* can't */
  if (!H->qm.buf && vi_quadmap_init(&H->qm, s->n))
    return vi_fail(s->errmsg, VI_ERR_NOMEM, "out of memory");
  vi_quadmap_reset(&H->qm, c->m); /* these modes' maps (Omega too) */
  int n = c->n, mm = c->m, na = H->na;
  vi_modal_project(s->m, s->z, H->q, H->qd);
  vi_phase p = vi_phase_at(H->Om, s->t);
  for (int i = 0; i < mm; i++) {
    const double *col = c->Phi + (size_t)i * n;
    double u = 0.0, ud = 0.0;
    for (int r = 0; r < n; r++) {
      u += col[r] * (H->q[r] - c->qc[r]);
      ud += col[r] * H->qd[r];
    }
    H->w0[i] = u - vi_harm(&p, 0, c->pA[i], c->pB[i], 0.0);
    H->wd0[i] = ud - vi_harm(&p, 1, c->pA[i], c->pB[i], 0.0);
  }
  H->t0 = s->t;
  H->s = s;
  for (int i = 0; i < na; i++) {
    H->g.wk[i] = H->w0[H->act[i]];
    H->g.wdk[i] = H->wd0[H->act[i]];
  }
  /* each function now, its round-off, and an offset when it starts on
   * zero (a release or contact at the start is one beyond round-off) */
  double worst = -HUGE_VAL, tol0 = s->ns ? vi_sim_gap_tol(s, 0) : 0.0;
  for (int j = 0; j < H->nf; j++) {
    hd_fun *e = H->f + j;
    e->off = 0.0;
    hd_eval(H, e, H->g.wk, H->g.wdk, p.c, p.s, H->g.fk + j, H->g.fdk + j);
    double sc = e->GH + fabs(e->f0);
    for (int i = 0; i < na; i++)
      sc += fabs(e->a[i] * H->g.wk[i]) + (e->c ? fabs(e->c[i] * H->g.wdk[i]) : 0.0);
    if (e->kind == 0) sc += c->lscale[e->slot];
    else sc += 1e-3 * s->atol * s->wnorms[e->stop];
    e->noise = 64.0 * DBL_EPSILON * sc;
    /* a hold the driver began with its force at zero and rising (pressed
     * at a higher order) starts on zero too */
    if (fabs(H->g.fk[j]) <= e->noise || (e->kind == 0 && H->g.fk[j] > 0.0) ||
        (e->kind == 1 && H->g.fk[j] > 0.0 && H->g.fk[j] <= e->tol)) {
      e->off = H->g.fk[j];
      H->g.fk[j] = 0.0;
    }
    if (e->kind == 1) worst = fmax(worst, H->g.fk[j] + e->off - e->tol);
  }
  s->gap = H->nf > H->cm->cnt ? worst + tol0 : 0.0;
  hd_bounds(H, H->g.wk, H->g.wdk);
  vi_grid_start(&H->g, H->t0, H->h, H->Om);
  H->g.ck = p.c;
  H->g.sk = p.s;
  s->z_stale = 0;
  return VI_OK;
}

/* The reported gap (worst stop not held, against its tolerance, as
 * vi_exact.c reports it) from the functions' values f [nf]. */
static double hd_report(const vi_sim *s, const vi_held *H, const double *f)
{
  double worst = -HUGE_VAL;
  int any = 0;
  for (int j = 0; j < H->nf; j++) {
    const hd_fun *e = H->f + j;
    if (e->kind != 1) continue;
    double x = f[j] + e->off - e->tol;
    if (!(x <= worst)) worst = x;
    any = 1;
  }
  return any ? worst + vi_sim_gap_tol(s, 0) : 0.0;
}

/* Ledger integrals over [a, b] (8-point Gauss-Legendre in equal panels
 * of at most a quarter radian of the fastest rate, as vi_exact.c, every
 * constrained mode taken at a panel's midpoint and carried to the nodes by
 * the maps of their offsets, vi_quadmap.h): forcing and damping of the
 * free modes, and the held stops' constraint exchange CE_j = -sum_k
 * lambda_k psi_kj q_j'.  VI_CANCELLED on the host's poll, the integrals
 * then taken to *done (b otherwise). */
static int hd_quadrature(vi_sim *s, vi_held *H, double a, double b,
                         double *done)
{
  *done = b;
  if (!(b > a)) return VI_OK;
  const vi_cmodes *c = H->cm;
  double lam[VI_CONTACT_MAX];
  const vi_ledger_held held = {c->cnt, c->set, lam};
  double npf = ceil((b - a) / H->hq);
  int64_t np = npf >= 1.0 ? (int64_t)fmin(npf, 1e15) : 1;
  double h = 0.5 * (b - a) / (double)np;
  const vi_quadmap_set *S = vi_quadmap_get(&H->qm, h, H->Om, c->om2,
                                           c->dmp, 1);
  size_t mm = (size_t)H->m;
  double *restrict w = H->wa, *restrict wd = H->wda, *restrict f = H->wf;
  for (int64_t k = 0; k < np; k++) {
    double mid = a + h * (double)(2 * k + 1);
    vi_phase p0 = vi_phase_at(H->Om, mid);
    for (size_t i = 0; i < mm; i++) {
      hd_mode(H, (int)i, mid, w + i, wd + i);
      f[i] = c->F0[i] - c->om2[i] * w[i];
    }
    for (int nd = 0; nd < VI_QUADMAP_NODES; nd++) {
      const double *restrict B = S->T + 3 * (size_t)nd * mm;
      const double *restrict Bp = B + mm, *restrict ph = B + 2 * mm;
      /* one phase per node: the modes, the reactions and the ledger's
       * forcing all take it (an unforced model's harmonic terms vanish
       * whatever it is) */
      vi_phase p = {H->Om, 0.0, 0.0};
      vi_quadmap_phase(S, nd, p0.c, p0.s, &p.c, &p.s);
      for (size_t i = 0; i < mm; i++) {
        H->u[i] = w[i] + B[i] * wd[i] + ph[i] * f[i] +
                  vi_harm(&p, 0, c->pA[i], c->pB[i], 0.0);
        H->ud[i] = Bp[i] * wd[i] + B[i] * f[i] +
                   vi_harm(&p, 1, c->pA[i], c->pB[i], 0.0);
      }
      hd_free_modal(c, H->u, H->ud, H->q, H->qd);
      for (int q = 0; q < c->cnt; q++) {
        const double *R = c->R + (size_t)q * c->m;
        lam[q] = vi_harm(&p, 0, c->lA[q], c->lB[q], c->lc[q]);
        for (int r = 0; r < c->m; r++)
          lam[q] -= R[r] * (H->u[r] + c->brl * H->ud[r]);
      }
      vi_ledger_accumulate_phase(s->led, &p, H->qd, &held, S->w[nd]);
    }
    if (vi_sim_quad_cancelled(s, k, np)) {
      *done = k + 1 == np ? b : a + 2.0 * h * (double)(k + 1);
      return VI_CANCELLED;
    }
  }
  return VI_OK;
}

/* The reported gap at t between grid points, directly. */
static double hd_gap_at(vi_sim *s, vi_held *H, double t)
{
  vi_phase p = vi_phase_at(H->Om, t);
  for (int i = 0; i < H->na; i++) hd_mode(H, H->act[i], t, H->wa + i, H->wda + i);
  for (int j = 0; j < H->nf; j++) {
    double fd;
    hd_eval(H, H->f + j, H->wa, H->wda, p.c, p.s, H->g.fn + j, &fd);
  }
  H->evals++;
  H->g.next_ok = 0; /* fn was scratch */
  return hd_report(s, H, H->g.fn);
}

/* The ledger's integrals from s->t to t; cancelled inside them, the
 * simulation stops where they end (its time and gap there). */
static int hd_ledger_to(vi_sim *s, vi_held *H, double t)
{
  if (!s->led || hd_quadrature(s, H, s->t, t, &t) != VI_CANCELLED)
    return VI_OK;
  s->t = t;
  s->gap = hd_gap_at(s, H, t);
  s->z_stale = 1;
  return VI_CANCELLED;
}

static int hd_move(vi_sim *s, vi_held *H, double t, double g)
{
  int st = hd_ledger_to(s, H, t);
  if (st) return st;
  s->t = t;
  s->gap = g;
  s->z_stale = 1;
  return VI_OK;
}

/* The grid scanner's view of a held phase (vi_grid.h): the constrained
 * modes advance by the grid step's maps, every function (the held stops'
 * reactions, the free stops' gaps) is followed. */
static void hd_g_anchor(void *hp, double t)
{
  vi_held *H = hp;
  hd_anchor(H, t, H->g.wn, H->g.wdn, &H->g.cn, &H->g.sn, H->g.fn, H->g.fdn);
}

static int hd_g_advance(void *hp)
{
  vi_held *H = hp;
  const double *restrict B = H->T, *restrict Bp = H->T + H->na;
  const double *restrict ph = H->T + 2 * (size_t)H->na;
  const double *restrict F0 = H->F0, *restrict lam = H->lam;
  const double *restrict wk = H->g.wk, *restrict wdk = H->g.wdk;
  double *restrict wn = H->g.wn, *restrict wdn = H->g.wdn;
  int na = H->na, i = 0;
  for (; i + 2 <= na; i += 2) {
    vi_v2 w = vi_v2_ld(wk + i), wd = vi_v2_ld(wdk + i), b = vi_v2_ld(B + i);
    vi_v2 f = vi_v2_ld(F0 + i) - vi_v2_ld(lam + i) * w;
    vi_v2_st(wn + i, w + b * wd + vi_v2_ld(ph + i) * f);
    vi_v2_st(wdn + i, vi_v2_ld(Bp + i) * wd + b * f);
  }
  for (; i < na; i++) {
    double f = F0[i] - lam[i] * wk[i];
    wn[i] = wk[i] + B[i] * wdk[i] + ph[i] * f;
    wdn[i] = Bp[i] * wdk[i] + B[i] * f;
  }
  for (int j = 0; j < H->nf; j++)
    hd_eval(H, H->f + j, H->g.wn, H->g.wdn, H->g.cn, H->g.sn, H->g.fn + j,
            H->g.fdn + j);
  H->evals++;
  return VI_OK;
}

static int hd_g_search(void *hp, double tk, double tb, double *tstar,
                       int *which)
{
  vi_held *H = hp;
  double best = HUGE_VAL;
  int found = -1;
  for (int j = 0; j < H->nf; j++) {
    double tc;
    int hit = hd_search(H, H->f + j, 0, tk, H->g.fk[j], H->g.fdk[j], tb,
                        H->g.fn[j], H->g.fdn[j], &tc);
    if (hit == VI_CANCELLED) return hit;
    if (hit && tc < best) {
      best = tc;
      found = j;
    }
  }
  *tstar = best;
  *which = found;
  return VI_OK;
}

/* Function `which` crosses zero at tc: a held stop releases (kind 0) or
 * a free one makes contact. */
static int hd_g_crossing(vi_sim *s, void *hp, double tc, int which,
                         int *event)
{
  vi_held *H = hp;
  const hd_fun *e = H->f + which;
  int st = hd_ledger_to(s, H, tc);
  if (st) return st;
  s->t = tc;
  s->gap = 0.0;
  s->contact_stop = e->stop;
  s->z_stale = 1;
  H->g.steps++;
  *event = e->kind == 0 ? VI_STEP_RELEASE : VI_STEP_CONTACT;
  return VI_OK;
}

static double hd_g_gap_at(vi_sim *s, void *hp, double t)
{
  return hd_gap_at(s, hp, t);
}

static double hd_g_report(vi_sim *s, void *hp, const double *f)
{
  return hd_report(s, hp, f);
}

static int hd_g_move(vi_sim *s, void *hp, double t, double g)
{
  return hd_move(s, hp, t, g);
}

static void hd_g_bounds(void *hp)
{
  vi_held *H = hp;
  hd_bounds(H, H->g.wk, H->g.wdk);
}

static const vi_grid_ops hd_grid = {
    .anchor_every = HD_ANCHOR,
    .batch = HD_BATCH,
    .anchor = hd_g_anchor,
    .advance = hd_g_advance,
    .search = hd_g_search,
    .crossing = hd_g_crossing,
    .gap_at = hd_g_gap_at,
    .report = hd_g_report,
    .move = hd_g_move,
    .bounds = hd_g_bounds,
};

int vi_held_step(vi_sim *s, double t_end, int *event)
{
  return vi_grid_step(s, &s->held->g, &hd_grid, s->held, t_end, event);
}

int vi_held_sync(vi_sim *s)
{
  hd_state(s, s->held, s->t, s->z);
  return VI_OK;
}

int vi_held_dense(vi_sim *s, double t)
{
  hd_state(s, s->held, t, s->zs);
  return VI_OK;
}

int64_t vi_held_stat(const vi_sim *s, int which)
{
  const vi_held *H = s->held;
  if (!H) return 0;
  if (which == VI_STAT_STEPS) return H->g.steps;
  if (which == VI_STAT_ROOT_EVALS) return H->evals;
  return 0;
}
