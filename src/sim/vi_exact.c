/* vi_exact.c - event-driven simulation on the closed-form flow, for
 * proportional damping (non-proportional damping: vi_exact_scan.c).
 *
 * Between impacts mode j is q_j = H_j(t) + w_j: H_j the harmonic particular
 * solution, w_j the rest, obeying w'' + d w' + lambda w = F0 and written
 * relative to its start (vi_flow_basis), so that static offsets and rigid
 * or very soft modes cost no accuracy.  The gap
 *   g(t) = sum_j psi_j w_j(t) + GA cos(Omega t) + GB sin(Omega t) - x_s
 * is followed on a uniform grid of step h = h0 2^-p (4 steps per period of
 * the fastest mode in g): each active mode (psi_j != 0) advances by a fixed
 * 2 x 2 map per step, re-anchored on the direct formula every EX_ANCHOR
 * steps.  A grid interval is skipped when a rigorous upper bound of g on it
 * stays below the stop: the cubic Hermite through g, g' at its ends plus
 * B4 h^4 / 384, with B4 >= |g''''|.  Bounds on |g''|, |g'''|, |g''''| come
 * from the modes' energies: every derivative w^(k), k >= 1, is a free
 * damped oscillation, whose energy (w^(k+1)^2 + lambda w^(k)^2) / 2 can
 * only decrease.  Where the bound fails, a left-first bisection on dyadic
 * sub-steps (tables of the same maps for h 2^-l) returns the first crossing
 * - maxima that touch the stop between grid points included - once a piece
 * is proven monotone (|g''| <= B2); the root is then refined by bisection
 * until the Hermite cubic is exact to round-off and polished by Newton on
 * it.  After an impact the time in which g provably recedes (a cubic bound
 * from g', g'' and B3) is skipped.  Physical states are built only when the
 * driver reads them: a lone bounce is made in the modes themselves
 * (ex_normal gives the driver the gap's rate and push, ex_kick applies the
 * impulse and the projection on the stop, q' -= P psi_k, q -= g psi_k /
 * G_kk), and an impact the driver made on s->z is recognised as the
 * rank-one change of the modal state that it is.
 *
 * Several stops w_k.x <= x_k: every gap g_k is a sum over the same modes
 * with its own weights psi_k = Psi^T w_k, so the modes advance once per
 * step and each stop keeps its own harmonic part, offset, round-off and
 * derivative bounds (ex_stop).  A grid interval is searched stop by stop,
 * each with its own rigorous Hermite bound, and the earliest crossing over
 * all stops is the contact; the driver then gathers every stop touching
 * at that instant (Newton's law for simultaneous contacts, vi_contact.c). */
#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cblas.h>

#include "vi_exact_internal.h"
#include "vi_grid.h"
#include "vi_ledger_flight.h"
#include "vi_quadmap.h"
#include "vi_vec.h"

#define EX_LEVELS 100 /* dyadic table levels h0 2^-l */
#define EX_DEPTH 44   /* bisection levels below the grid's */
#define EX_ANCHOR 64  /* grid steps between direct evaluations */
#define EX_BATCH 512  /* grid steps per call of step() at most */
#define EX_GRID 1.5707963267948966 /* grid step in radians of the fastest rate */

/* One stop's gap g_k = psi_k.w + GA cos + GB sin - x_k - goff. */
typedef struct ex_stop {
  const double *psi;                /* psi_k of the active modes [na] */
  double xs, GA, GB, GH;            /* x_k; harmonic part, its amplitude */
  double goff, skip, gnoise;        /* offset at t0; no contact before;
                                       round-off of g_k at t0 */
  double B2, B3, B4;                /* bounds of |g''|, |g'''|, |g''''| */
  double tol;                       /* the driver's penetration tolerance */
} ex_stop;

typedef struct ex_data {
  int kind;                         /* EX_KIND_FAST (vi_exact_internal.h) */
  vi_sim *s;
  int n, na, *act;                  /* active modes: some psi_kj != 0 */
  int ns, hit;                      /* stops; the stop of tstar */
  ex_stop *st, *cs;                 /* the stops [ns]; the one searched */
  const double *pA, *pB;            /* harmonic particular solution [n] */
  double *lam, *dmp, *F0, *psi;     /* of the active modes [na]; psi: stop
                                       0's, then the others' [ns na] */
  double Om, h0, hq;                /* forcing, grid and quadrature steps */
  double *lev[EX_LEVELS];           /* B, Bp, phi for h0 2^-l [3 na] */
  double lc[EX_LEVELS], ls[EX_LEVELS]; /* cos, sin of Omega h0 2^-l */
  /* the flight */
  double t0, *w0, *wd0;             /* w, w' of every mode at t0 [n] */
  double *amp;                      /* each mode's harmonic amplification
                                       max(lambda, Om^2) / |lambda - Om^2 +
                                       i d Om| [n] (the model's) */
  int p, lmax, handover;
  unsigned polls;                   /* ex_search's nodes (the host's poll) */
  double hp, tg;                    /* grid step and start */
  vi_grid g;                        /* the grid t_k = tg + k hp: active
                                       modes [na] and every stop's g_k,
                                       g_k' [ns] (fk, fdk) there */
  double *gs;                       /* scratch [ns] */
  double *stk;                      /* bisection states [(EX_DEPTH+2) 2 na] */
  /* modal state at tq and the physical state handed out at tz */
  double *q, *qd, tq, *z, tz, *qs, *qds, *qn; /* qs, qds, qn: scratch */
  int q_ok, z_ok;
  vi_quadmap qm;                    /* the ledger quadrature's node maps */
  vi_lflight lf;                    /* or the ledger in closed form */
  int lf_on;
  int64_t evals;
} ex_data;

static void ex_destroy(vi_sim *s)
{
  ex_data *d = s->be_data;
  if (d && d->kind != EX_KIND_FAST) { /* the scan backend's data */
    vi_backend_exact_scan.destroy(s);
    return;
  }
  if (d) {
    vi_ledger_settle(s->led); /* the integrals this flight owes */
    for (int l = 0; l < EX_LEVELS; l++) free(d->lev[l]);
    free(d->st); /* and act, lam: one block */
    vi_quadmap_free(&d->qm);
    vi_lflight_free(&d->lf);
  }
  free(d);
  s->be_data = NULL;
}

/* Tables of level l: the maps of the active modes over h0 2^-l. */
static const double *ex_level(ex_data *d, int l)
{
  if (d->lev[l]) return d->lev[l];
  double *t = malloc(sizeof(double) * 3 * (size_t)(d->na ? d->na : 1));
  if (!t) return NULL;
  double dt = ldexp(d->h0, -l);
  vi_phase r = vi_phase_at(d->Om, dt); /* the rotation by Om dt */
  d->lc[l] = r.c;
  d->ls[l] = r.s;
  for (int i = 0; i < d->na; i++)
    vi_flow_basis(d->lam[i], d->dmp[i], dt, t + i, t + d->na + i,
                  t + 2 * (size_t)d->na + i);
  d->lev[l] = t;
  return t;
}

/* Harmonic part of stop e's g and g' from cos, sin of Omega t. */
static inline void ex_harm(const ex_data *d, const ex_stop *e, double c,
                           double sn, double *g, double *gd)
{
  vi_phase p = {d->Om, c, sn};
  *g = vi_harm(&p, 0, e->GA, e->GB, 0.0);
  *gd = vi_harm(&p, 1, e->GA, e->GB, 0.0);
}

/* Active modes advanced over h0 2^-l from (w, wd) to (wo, wdo), and stop
 * e's g, g' at the new time (cos, sin of Omega t there: c, sn). */
static int ex_advance(ex_data *d, int l, const double *restrict w,
                      const double *restrict wd, double *restrict wo,
                      double *restrict wdo, double c, double sn,
                      const ex_stop *e, double *g, double *gd)
{
  const double *T = ex_level(d, l);
  if (!T) return vi_fail(d->s->errmsg, VI_ERR_NOMEM, "out of memory");
  const double *restrict B = T, *restrict Bp = T + d->na;
  const double *restrict ph = T + 2 * (size_t)d->na;
  const double *restrict lam = d->lam, *restrict F0 = d->F0;
  const double *restrict psi = e->psi;
  /* four partial sums in two pairs (vi_vec.h) */
  vi_v2 A[2] = {{0.0, 0.0}, {0.0, 0.0}}, V[2] = {{0.0, 0.0}, {0.0, 0.0}};
  int na = d->na, i = 0;
  for (; i + 4 <= na; i += 4)
    for (int h = 0; h < 2; h++) {
      int k = i + 2 * h;
      vi_v2 wi = vi_v2_ld(w + k), wdi = vi_v2_ld(wd + k), Bi = vi_v2_ld(B + k);
      vi_v2 f = vi_v2_ld(F0 + k) - vi_v2_ld(lam + k) * wi;
      vi_v2 x = wi + Bi * wdi + vi_v2_ld(ph + k) * f;
      vi_v2 v = vi_v2_ld(Bp + k) * wdi + Bi * f;
      vi_v2_st(wo + k, x);
      vi_v2_st(wdo + k, v);
      A[h] += vi_v2_ld(psi + k) * x;
      V[h] += vi_v2_ld(psi + k) * v;
    }
  double a[4] = {A[0][0], A[0][1], A[1][0], A[1][1]};
  double b[4] = {V[0][0], V[0][1], V[1][0], V[1][1]};
  for (; i < na; i++) {
    double f = F0[i] - lam[i] * w[i];
    double x = w[i] + B[i] * wd[i] + ph[i] * f;
    double v = Bp[i] * wd[i] + B[i] * f;
    wo[i] = x;
    wdo[i] = v;
    a[0] += psi[i] * x;
    b[0] += psi[i] * v;
  }
  double hg, hgd;
  ex_harm(d, e, c, sn, &hg, &hgd);
  *g = ((a[0] + a[1]) + (a[2] + a[3])) + hg - e->xs - e->goff;
  *gd = ((b[0] + b[1]) + (b[2] + b[3])) + hgd;
  d->evals++;
  return VI_OK;
}

/* g, g' of stops 1, 2, ... into g[k], gd[k] from the active modes (w, wd)
 * (stop 0's come with ex_advance). */
static void ex_other_gaps(const ex_data *d, const double *w, const double *wd,
                          double c, double sn, double *g, double *gd)
{
  for (int k = 1; k < d->ns; k++) {
    const ex_stop *e = d->st + k;
    double x = 0.0, v = 0.0, hg, hgd;
    for (int j = 0; j < d->na; j++) {
      x += e->psi[j] * w[j];
      v += e->psi[j] * wd[j];
    }
    ex_harm(d, e, c, sn, &hg, &hgd);
    g[k] = x + hg - e->xs - e->goff;
    gd[k] = v + hgd;
  }
}

/* w, w' of mode j (full index) at t from the flight's start. */
static inline void ex_mode(const ex_data *d, int j, double t, double *w,
                           double *wd)
{
  const vi_model *m = d->s->m;
  double B, Bp, ph, lam = m->lambda[j];
  vi_flow_basis(lam, m->D[j + (size_t)j * d->n], t - d->t0, &B, &Bp, &ph);
  double f = m->F0[j] - lam * d->w0[j];
  *w = d->w0[j] + B * d->wd0[j] + ph * f;
  *wd = Bp * d->wd0[j] + B * f;
}

/* Active modes at t directly (an anchor), with every stop's g, g' [ns]. */
static void ex_anchor(ex_data *d, double t, double *w, double *wd, double *c,
                      double *sn, double *g, double *gd)
{
  for (int i = 0; i < d->na; i++) ex_mode(d, d->act[i], t, w + i, wd + i);
  vi_phase p = vi_phase_at(d->Om, t);
  *c = p.c;
  *sn = p.s;
  for (int k = 0; k < d->ns; k++) {
    const ex_stop *e = d->st + k;
    double a = 0.0, b = 0.0, hg, hgd;
    for (int i = 0; i < d->na; i++) {
      a += e->psi[i] * w[i];
      b += e->psi[i] * wd[i];
    }
    ex_harm(d, e, *c, *sn, &hg, &hgd);
    g[k] = a + hg - e->xs - e->goff;
    gd[k] = b + hgd;
  }
  d->evals++;
}

/* ex_mode, and the closed form's sines and exponentials handed to the
 * ledger's flight (vi_lflight_share): its integrals to t, read at a
 * contact, would compute them again. */
static void ex_mode_led(ex_data *d, int j, double t, double *w, double *wd)
{
  const vi_model *m = d->s->m;
  double B, Bp, ph, half[4], lam = m->lambda[j], tau = t - d->t0;
  if (vi_flow_basis_half(lam, m->D[j + (size_t)j * d->n], tau, &B, &Bp, &ph,
                         half))
    vi_lflight_share(&d->lf, j, tau, half);
  double f = m->F0[j] - lam * d->w0[j];
  *w = d->w0[j] + B * d->wd0[j] + ph * f;
  *wd = Bp * d->wd0[j] + B * f;
}

/* Every mode's q, q' at t. */
static void ex_modes_at(ex_data *d, double t, double *q, double *qd)
{
  vi_phase p = vi_phase_at(d->Om, t);
  for (int j = 0; j < d->n; j++) {
    double w, wd;
    if (d->lf_on) ex_mode_led(d, j, t, &w, &wd);
    else ex_mode(d, j, t, &w, &wd);
    q[j] = w + vi_harm(&p, 0, d->pA[j], d->pB[j], 0.0);
    qd[j] = wd + vi_harm(&p, 1, d->pA[j], d->pB[j], 0.0);
  }
  d->evals++;
}

/* Bounds of every stop's |g''|, |g'''|, |g''''| from time t on, from the
 * active modes' (w, w') at t: |w^(k+1)| <= sqrt(w^(k+1)^2 + lambda w^(k)^2)
 * at t, since that energy of the free oscillation w^(k) never grows
 * (d >= 0). */
static void ex_bounds(ex_data *d, const double *w, const double *wd)
{
  double O2 = d->Om * d->Om;
  for (int k = 0; k < d->ns; k++) {
    ex_stop *e = d->st + k;
    double b2 = 0.0, b3 = 0.0, b4 = 0.0;
    for (int i = 0; i < d->na; i++) {
      double a = fabs(e->psi[i]);
      double l = d->lam[i], dm = d->dmp[i];
      double w2 = d->F0[i] - dm * wd[i] - l * w[i];
      double w3 = -dm * w2 - l * wd[i], w4 = -dm * w3 - l * w2;
      b2 += a * sqrt(w2 * w2 + l * wd[i] * wd[i]);
      b3 += a * sqrt(w3 * w3 + l * w2 * w2);
      b4 += a * sqrt(w4 * w4 + l * w3 * w3);
    }
    /* a relative margin for the rounding of the sums */
    e->B2 = (b2 + e->GH * O2) * (1.0 + 1e-9);
    e->B3 = (b3 + e->GH * O2 * d->Om) * (1.0 + 1e-9);
    e->B4 = (b4 + e->GH * O2 * O2) * (1.0 + 1e-9);
  }
}

/* fmax without the library call (no NaN reaches these) */
static inline double mx(double a, double b) { return a > b ? a : b; }

/* B4 w^4 / 384: how far g_k may rise above its cubic Hermite on a piece. */
static inline double herm_err(const ex_stop *e, double w)
{
  double w2 = w * w;
  return e->B4 * w2 * w2 / 384.0;
}

/* A cheap upper bound of the cubic Hermite on a piece: the weights of the
 * end slopes, s (1 - s)^2 and -s^2 (1 - s), lie within [0, 4/27] and
 * [-4/27, 0]. */
static inline double herm_quick(double ga, double gda, double gb, double gdb,
                                double w)
{
  return mx(ga, gb) + w * (4.0 / 27.0) * (mx(gda, 0.0) + mx(-gdb, 0.0));
}

/* Root of g on a piece [a, a + h0 2^-l] where g' > 0 is proven, ga < 0 <=
 * gb, from the active state (w, wd) at a: halve it until the Hermite cubic
 * is exact to round-off, then Newton on the cubic, safeguarded by its
 * bracket. */
static int ex_polish(ex_data *d, int l, double a, const double *w,
                     const double *wd, double ca, double sa, double ga,
                     double gda, double gb, double gdb, double gdlo,
                     double *tc)
{
  const double eps = DBL_EPSILON;
  double wdt = ldexp(d->h0, -l);
  for (;;) {
    double scale = 0.25 * eps * fmax(fabs(a), d->h0) * gdlo;
    if (l >= d->lmax || herm_err(d->cs, wdt) <= scale) break;
    double *wm = d->stk + (size_t)(l + 1 - d->p) * 2 * d->na, *wdm = wm + d->na;
    double m = a + 0.5 * wdt, gm = 0.0, gdm = 0.0;
    int st = ex_advance(d, l + 1, w, wd, wm, wdm, 0.0, 0.0, d->cs, &gm, &gdm);
    if (st) return st;
    /* the harmonic part by rotation from a (the tables are built now) */
    double c = ca * d->lc[l + 1] - sa * d->ls[l + 1];
    double sn = sa * d->lc[l + 1] + ca * d->ls[l + 1], hg, hgd;
    ex_harm(d, d->cs, c, sn, &hg, &hgd);
    gm += hg;
    gdm += hgd;
    l++;
    wdt *= 0.5;
    if (gm >= 0.0) {
      gb = gm;
      gdb = gdm;
    } else {
      a = m;
      w = wm;
      wd = wdm;
      ca = c;
      sa = sn;
      ga = gm;
      gda = gdm;
    }
  }
  double cf[4];
  vi_herm_max(ga, gda, gb, gdb, wdt, cf);
  double lo = 0.0, hi = 1.0, x = ga / (ga - gb);
  for (int it = 0; it < 60; it++) {
    double p = cf[0] + x * (cf[1] + x * (cf[2] + x * cf[3]));
    double dp = cf[1] + x * (2.0 * cf[2] + x * 3.0 * cf[3]);
    if (p < 0.0) lo = x; else hi = x;
    double xn = dp > 0.0 ? x - p / dp : 0.5 * (lo + hi);
    if (!(xn > lo && xn < hi)) xn = 0.5 * (lo + hi);
    double dx = fabs(xn - x);
    x = xn;
    if (dx * wdt <= eps * fabs(a) || dx <= 4.0 * eps || hi - lo <= eps) break;
  }
  *tc = a + x * wdt;
  return 1;
}

/* First t in (a, a + h0 2^-l] with g(t) >= 0, left first; state (w, wd) at
 * a.  1 with *tc: found; 0: none; VI_CANCELLED (polled); < 0: error. */
static int ex_search(ex_data *d, int l, double a, const double *w,
                     const double *wd, double ca, double sa, double ga,
                     double gda, double gb, double gdb, double *tc)
{
  double wdt = ldexp(d->h0, -l), b = a + wdt, cf[4], e4 = herm_err(d->cs, wdt);
  if (b <= d->cs->skip) return 0;
  if (vi_sim_cancelled_every(d->s, &d->polls)) return VI_CANCELLED;
  /* below the stop by more than g's round-off: nothing here (a touch
   * within round-off is no contact, and a motion resting on the stop must
   * not send the bisection into every leaf) */
  if (herm_quick(ga, gda, gb, gdb, wdt) + e4 < d->cs->gnoise ||
      vi_herm_max(ga, gda, gb, gdb, wdt, cf) + e4 < d->cs->gnoise)
    return 0;
  /* g' on [a, b] lies within the two lines of slope B2 through the ends */
  double gdlo = 0.5 * (gda + gdb - d->cs->B2 * wdt);
  double gdhi = 0.5 * (gda + gdb + d->cs->B2 * wdt);
  if (gdhi < 0.0 && ga <= 0.0) return 0; /* decreasing */
  if (gdlo > 0.0 && ga < 0.0) {          /* increasing */
    if (gb < 0.0) return 0;
    return ex_polish(d, l, a, w, wd, ca, sa, ga, gda, gb, gdb, gdlo, tc);
  }
  if (gdlo > 0.0 && a > d->t0) {
    /* increasing from g(a) >= 0, below the round-off that the pieces
     * before it found: the crossing is at a (a grid point on the root),
     * not at the end of the first leaf of a bisection */
    *tc = a;
    return 1;
  }
  if (l >= d->lmax) { /* at round-off in t: the sign decides */
    /* next to a start on the stop, only beyond g's round-off: a tangential
     * departure (a release) must not read as a new contact */
    if (gb < 0.0 || (a <= d->t0 && gb <= d->cs->gnoise)) return 0;
    *tc = b;
    return 1;
  }
  d->s->stats[VI_STAT_GRAZE_CHECKS] += gda > 0.0 && gdb < 0.0;
  double *wm = d->stk + (size_t)(l + 1 - d->p) * 2 * d->na, *wdm = wm + d->na;
  double m = a + 0.5 * wdt, gm = 0.0, gdm = 0.0;
  int st = ex_advance(d, l + 1, w, wd, wm, wdm, 0.0, 0.0, d->cs, &gm, &gdm);
  if (st) return st;
  double c = ca * d->lc[l + 1] - sa * d->ls[l + 1];
  double sn = sa * d->lc[l + 1] + ca * d->ls[l + 1], hg, hgd;
  ex_harm(d, d->cs, c, sn, &hg, &hgd);
  gm += hg;
  gdm += hgd;
  st = ex_search(d, l + 1, a, w, wd, ca, sa, ga, gda, gm, gdm, tc);
  if (st) return st;
  return ex_search(d, l + 1, m, wm, wdm, c, sn, gm, gdm, gb, gdb, tc);
}

/* A mode is active when some stop's gap sees it. */
static int ex_active(const vi_model *m, int j)
{
  for (int k = 0; k < m->ns; k++)
    if (vi_stop_psi(m, k)[j] != 0.0) return 1;
  return 0;
}

static int ex_alloc(vi_sim *s, ex_data **out)
{
  const vi_model *m = s->m;
  int n = s->n, na = 0, ns = m->ns;
  for (int j = 0; j < n; j++) na += ex_active(m, j);
  *out = NULL;
  ex_data *d = calloc(1, sizeof *d);
  if (!d) {
    vi_fail(s->errmsg, VI_ERR_NOMEM, "out of memory");
    return VI_ERR_NOMEM;
  }
  size_t nd = (3 + (size_t)ns) * (size_t)na + 6 * (size_t)na +
              (size_t)(EX_DEPTH + 2) * 2 * (size_t)na + 16 * (size_t)n +
              5 * (size_t)ns + 8;
  /* the stops [ns], the doubles [nd] and act [na + 1] in one block: a
   * small model's set-up allocates three times, not six */
  size_t bs = sizeof *d->st * (size_t)ns;
  d->st = malloc(bs + sizeof(double) * nd + sizeof(int) * (size_t)(na + 1));
  d->lf_on = s->led && vi_lflight_ok(m);
  /* the panels' maps only where the ledger integrates by quadrature (a
   * change of ledger rebuilds this data, vi_sim_enable_ledger) */
  int quad = s->led && !d->lf_on;
  if (!d->st || (quad && vi_quadmap_init(&d->qm, n)) ||
      (d->lf_on && vi_lflight_init(&d->lf, m))) {
    free(d->st);
    vi_quadmap_free(&d->qm);
    vi_lflight_free(&d->lf);
    free(d);
    vi_fail(s->errmsg, VI_ERR_NOMEM, "out of memory");
    return VI_ERR_NOMEM;
  }
  memset(d->st, 0, bs);
  void *rest = d->st + ns; /* ex_stop's size is a multiple of a double's */
  d->lam = rest;
  rest = d->lam + nd;
  d->act = rest;
  double *p = d->lam;
  p += na;
  d->dmp = p; p += na;
  d->F0 = p; p += na;
  d->psi = p; p += (size_t)ns * na;
  d->g.wk = p; p += na;
  d->g.wdk = p; p += na;
  d->g.wn = p; p += na;
  d->g.wdn = p; p += na;
  p += 2 * (size_t)na; /* spare */
  d->stk = p; p += (size_t)(EX_DEPTH + 2) * 2 * na;
  d->w0 = p; p += n;
  d->wd0 = p; p += n;
  d->amp = p; p += n;
  d->q = p; p += n;
  d->qd = p; p += n;
  d->qs = p; p += n;
  d->qds = p; p += n;
  d->qn = p; p += n;
  d->g.fk = p; p += ns;
  d->g.fdk = p; p += ns;
  d->g.fn = p; p += ns;
  d->g.fdn = p; p += ns;
  d->gs = p; p += ns;
  d->z = p;
  d->kind = EX_KIND_FAST;
  d->s = s;
  d->n = n;
  d->na = na;
  d->ns = ns;
  d->cs = d->st;
  d->pA = s->flow->pA;
  d->pB = s->flow->pB;
  d->Om = m->omega_f;
  double top = 0.0, all = d->Om;
  int harm = 0;
  for (int k = 0; k < ns; k++) {
    d->st[k].psi = d->psi + (size_t)k * na;
    d->st[k].xs = m->xsv[k];
  }
  for (int j = 0, i = 0; j < n; j++) {
    double dm = m->D[j + (size_t)j * n], rate = fmax(sqrt(m->lambda[j]), dm);
    double lam = m->lambda[j], Om2 = d->Om * d->Om;
    d->amp[j] = fmax(lam, Om2) / hypot(lam - Om2, dm * d->Om); /* ex_start */
    all = fmax(all, rate);
    if (!ex_active(m, j)) continue;
    d->act[i] = j;
    d->lam[i] = m->lambda[j];
    d->dmp[i] = dm;
    d->F0[i] = m->F0[j];
    for (int k = 0; k < ns; k++) {
      ex_stop *e = d->st + k;
      double pk = vi_stop_psi(m, k)[j];
      d->psi[(size_t)k * na + i] = pk;
      e->GA += pk * d->pA[j];
      e->GB += pk * d->pB[j];
    }
    top = fmax(top, rate);
    i++;
  }
  for (int k = 0; k < ns; k++) {
    ex_stop *e = d->st + k;
    e->GH = hypot(e->GA, e->GB);
    harm |= e->GH != 0.0;
  }
  if (harm) top = fmax(top, d->Om);
  /* no rate at all (free rigid modes under a constant load): g is a
   * quadratic, which the Hermite bound follows exactly at any step */
  d->h0 = top > 0.0 ? EX_GRID / top : 1.0;
  d->hq = all > 0.0 ? 0.7853981633974483 / all : HUGE_VAL;
  *out = d;
  return VI_OK;
}

/* Modal state of s->z: the driver's impact on the stop k we reported
 * changed the state we handed out by dx = a M^-1 w_k, dv = b M^-1 w_k (WB
 * 6 and the projection on the stop), which in modes is q += a psi_k, q' +=
 * b psi_k; anything else (several stops at once) is converted in full. */
static void ex_modal_from_z(ex_data *d)
{
  vi_sim *s = d->s;
  const vi_model *m = s->m;
  int n = d->n, k = d->hit;
  if (d->z_ok && d->q_ok && s->t == d->tz && s->t == d->tq) {
    const double *w = vi_stop_w(m, k), *mw = vi_stop_minvw(m, k);
    const double *psi = vi_stop_psi(m, k);
    double a = 0.0, b = 0.0, wmw = m->G[k + (size_t)k * m->ns];
    for (int i = 0; i < n; i++) {
      a += w[i] * (s->z[2 * (size_t)i] - d->z[2 * (size_t)i]);
      b += w[i] * (s->z[2 * (size_t)i + 1] - d->z[2 * (size_t)i + 1]);
    }
    a /= wmw;
    b /= wmw;
    int ok = 1;
    for (int i = 0; i < n && ok; i++) {
      double ex = s->z[2 * (size_t)i] - d->z[2 * (size_t)i] - a * mw[i];
      double ev = s->z[2 * (size_t)i + 1] - d->z[2 * (size_t)i + 1] - b * mw[i];
      double tx = 1e-13 * (fabs(s->z[2 * (size_t)i]) + fabs(a * mw[i])) + DBL_MIN;
      double tv = 1e-13 * (fabs(s->z[2 * (size_t)i + 1]) + fabs(b * mw[i])) + DBL_MIN;
      ok = fabs(ex) <= tx && fabs(ev) <= tv;
    }
    if (ok) {
      for (int j = 0; j < n; j++) {
        d->q[j] += a * psi[j];
        d->qd[j] += b * psi[j];
      }
      return;
    }
  }
  for (int j = 0; j < n; j++) {
    double q = 0.0, qd = 0.0;
    for (int i = 0; i < n; i++) {
      double pm = m->PsiTM[j + (size_t)i * n];
      q += pm * s->z[2 * (size_t)i];
      qd += pm * s->z[2 * (size_t)i + 1];
    }
    d->q[j] = q;
    d->qd[j] = qd;
  }
}

/* The gap the driver checks for penetration (s->gap, against stop 0's
 * tolerance) from every stop's g [ns] (less goff if off): the worst
 * stop's excess. */
static double ex_report(const ex_data *d, const double *g, int off)
{
  const ex_stop *e = d->st;
  if (d->ns == 1) return g[0] + (off ? e->goff : 0.0);
  double worst = g[0] + (off ? e->goff : 0.0) - e->tol;
  for (int k = 1; k < d->ns; k++) {
    double x = g[k] + (off ? e[k].goff : 0.0) - e[k].tol;
    if (!(x <= worst)) worst = x; /* a NaN is the worst */
  }
  return worst + e->tol;
}

/* sum_i |w_i x_i| of stop vector w, the round-off scale of w.x: from s->z,
 * or, where the modes are the state (after a kick), from the rows of Psi
 * that w sees (one row for a stop on one coordinate). */
static double ex_wx_scale(const ex_data *d, const double *w, int modal)
{
  const vi_sim *s = d->s;
  int n = d->n;
  double sc = 0.0;
  for (int i = 0; i < n; i++) {
    if (w[i] == 0.0) continue;
    double x = 0.0;
    if (!modal) x = s->z[2 * (size_t)i];
    else
      for (int j = 0; j < n; j++) x += s->m->Psi[i + (size_t)j * n] * d->q[j];
    sc += fabs(w[i] * x);
  }
  return sc;
}

/* The ledger's integrals at s->t, owed by the flight (vi_ledger_defer). */
static void ex_owed(void *data, double *Q)
{
  ex_data *d = data;
  vi_lflight_eval(&d->lf, d->s->t - d->lf.t0, Q);
}

static int ex_since(void *data, double ta, const double *QA, double *I)
{
  ex_data *d = data;
  return vi_lflight_since(&d->lf, d->s->t - d->lf.t0, ta, QA, I);
}

static int ex_start(vi_sim *s)
{
  const vi_model *m = s->m;
  vi_ledger_settle(s->led); /* the last flight's integrals, to here */
  if (s->sticking) /* held stops: the constrained modes' flow */
    return vi_held_start(s);
  if (!m->proportional) return vi_backend_exact_scan.start(s);
  ex_data *d = s->be_data;
  if (!d) {
    int st = ex_alloc(s, &d);
    if (st) return st;
    s->be_data = d;
  }
  int n = d->n, na = d->na;
  /* the driver writes s->z only after a sync: a stale s->z with the modes
   * at s->t means the modes were kicked (ex_kick) and are the state */
  int modal = s->z_stale && d->q_ok && d->tq == s->t;
  if (!modal) ex_modal_from_z(d);
  d->q_ok = 1;
  d->tq = s->t;
  d->z_ok = 0;
  d->t0 = s->t;
  vi_phase p = vi_phase_at(d->Om, s->t);
  double Om = d->Om, c = p.c, sn = p.s;
  /* A mode forced near its resonance with little damping has a harmonic
   * particular solution amplified by A = max(lambda, Omega^2) / |lambda -
   * Omega^2 + i d Omega| over its static scale, which q = H + w cancels
   * while the motion builds up: where A > 1e6 and the round-off of that
   * part exceeds the tolerance, CVODE goes on instead. */
  double worst = 0.0;
  int jw = -1;
  for (int j = 0; j < n; j++) {
    double H = vi_harm(&p, 0, d->pA[j], d->pB[j], 0.0);
    double Hd = vi_harm(&p, 1, d->pA[j], d->pB[j], 0.0);
    d->w0[j] = d->q[j] - H;
    d->wd0[j] = d->qd[j] - Hd;
    double amp = d->amp[j]; /* the model's: set once (ex_alloc) */
    for (int k = 0; k < d->ns && amp > 1e6; k++) {
      double hs = fabs(vi_stop_psi(m, k)[j]) * hypot(d->pA[j], d->pB[j]);
      if (4.0 * DBL_EPSILON * hs > s->atol * s->wnorms[k] && hs > worst) {
        worst = hs;
        jw = j;
      }
    }
  }
  d->handover = jw >= 0;
  if (d->lf_on) { /* FE, DE in closed form, computed where they are read */
    vi_lflight_start(&d->lf, m, d->pA, d->pB, s->t, &p, d->w0, d->wd0,
                     vi_ledger_integrals(s->led));
    vi_ledger_defer(s->led, ex_owed, ex_since, d);
  }
  if (d->handover)
    snprintf(s->handover_why, sizeof s->handover_why,
             "mode %d is forced %.3g times above its static response (near "
             "resonance, little damping): the closed form would cancel its "
             "particular solution %.3g", jw + 1, d->amp[jw], worst);
  for (int i = 0; i < na; i++) {
    int j = d->act[i];
    d->g.wk[i] = d->w0[j];
    d->g.wdk[i] = d->wd0[j];
  }
  ex_bounds(d, d->g.wk, d->g.wdk);
  /* Each stop: g, g', g'' now.  On the stop (after an impact, or a start
   * there): measure g from here, and skip the time in which g provably
   * recedes, g' tau + g'' tau^2 / 2 + B3 tau^3 / 6 < 0.  The grid starts
   * where the first stop's skip ends. */
  double tf = HUGE_VAL, tg = HUGE_VAL;
  for (int k = 0; k < d->ns; k++) {
    ex_stop *e = d->st + k;
    const double *w = vi_stop_w(m, k);
    double a = 0.0, b = 0.0, b2 = 0.0, hg, hgd;
    for (int i = 0; i < na; i++) {
      a += e->psi[i] * d->g.wk[i];
      b += e->psi[i] * d->g.wdk[i];
      b2 += e->psi[i] *
            (d->F0[i] - d->dmp[i] * d->g.wdk[i] - d->lam[i] * d->g.wk[i]);
    }
    e->goff = 0.0;
    e->tol = vi_sim_gap_tol(s, k);
    ex_harm(d, e, c, sn, &hg, &hgd);
    double g = a + hg - e->xs, gd = b + hgd, gdd = b2 - Om * Om * hg;
    d->g.fk[k] = g;
    d->g.fdk[k] = gd;
    /* the round-off of g: of its terms, physical and modal */
    double scale = fabs(e->xs) + e->GH + 1e-3 * s->atol * s->wnorms[k];
    scale += ex_wx_scale(d, w, modal);
    for (int i = 0; i < na; i++) scale += fabs(e->psi[i] * d->g.wk[i]);
    double tr = 0.0;
    e->gnoise = 64.0 * DBL_EPSILON * scale;
    s->gnoise[k] = e->gnoise;
    /* on the stop: within round-off, or beyond it by no more than the
     * driver accepts (a state handed over from CVODE after sticking),
     * which read as a contact would restart here for ever */
    if (fabs(g) <= e->gnoise || (g > 0.0 && g <= e->tol)) {
      e->goff = g;
      d->g.fk[k] = 0.0;
      double A = e->B3 / 6.0, B = 0.5 * gdd, C = gd;
      if (C < 0.0) {
        if (A > 0.0) tr = 2.0 * -C / (B + sqrt(B * B - 4.0 * A * C));
        else tr = B > 0.0 ? -C / B : HUGE_VAL;
      } else if (C == 0.0 && B < 0.0) {
        tr = A > 0.0 ? -B / A : HUGE_VAL;
      }
      tr *= 1.0 - 1e-6;
    }
    e->skip = s->t + tr;
    tg = fmin(tg, e->skip);
    /* grid: fine enough to see the end of a short flight, whose length is
     * about 2 |g'| / g'' when g'' > 0 (a bounce); a tangential departure
     * (g' ~ 0 and g'' <= 0, a release) starts no short flight */
    if (tr > 0.0 && gdd > 0.0 && gd < 0.0)
      tf = fmin(tf, fmax(tr, -2.0 * gd / gdd));
  }
  s->gap = ex_report(d, d->g.fk, 1);
  s->z_stale = modal;
  d->p = 0;
  while (d->p < 40 && ldexp(d->h0, -d->p) > 4.0 * tf &&
         ldexp(d->h0, -d->p - 1) >= 64.0 * DBL_EPSILON * fabs(s->t))
    d->p++;
  d->lmax = d->p + EX_DEPTH;
  d->hp = ldexp(d->h0, -d->p);
  d->tg = tg; /* +inf: every g recedes for ever */
  vi_grid_start(&d->g, d->tg, d->hp, Om);
  if (d->tg > s->t && isfinite(d->tg))
    ex_anchor(d, d->tg, d->g.wk, d->g.wdk, &d->g.ck, &d->g.sk, d->g.fk,
              d->g.fdk);
  else {
    d->g.ck = c;
    d->g.sk = sn;
  }
  return VI_OK;
}

/* Where the flight's ledger has no closed form (d->lf_on = 0: a mode
 * overdamped, critically damped, past damping ratio 1/2 or rigid): ledger
 * integrals over [a, b] by 8-point Gauss-Legendre in np equal
 * panels of at most a quarter radian of the fastest rate: there the rule's
 * error is below round-off for the products of modes that make the
 * integrands.  Every mode is taken directly at a panel's midpoint and carried
 * to its nodes by the maps of the node offsets (vi_quadmap.h); the ledger
 * needs only q'. */
static int ex_quadrature(vi_sim *s, ex_data *d, double a, double b,
                         double *done)
{
  *done = b;
  if (!(b > a)) return VI_OK;
  const vi_model *m = s->m;
  double npf = ceil((b - a) / d->hq);
  int64_t np = npf >= 1.0 ? (int64_t)fmin(npf, 1e15) : 1;
  double h = 0.5 * (b - a) / (double)np;
  const vi_quadmap_set *S = vi_quadmap_get(&d->qm, h, d->Om, m->lambda,
                                           m->D, d->n + 1);
  const double *restrict pA = d->pA, *restrict pB = d->pB;
  double *restrict w = d->qs, *restrict wd = d->qds, *restrict qd = d->qn;
  size_t n = (size_t)d->n;
  for (int64_t k = 0; k < np; k++) {
    double mid = a + h * (double)(2 * k + 1);
    vi_phase p0 = vi_phase_at(d->Om, mid);
    for (size_t j = 0; j < n; j++) {
      ex_mode(d, (int)j, mid, w + j, wd + j);
      w[j] = m->F0[j] - m->lambda[j] * w[j]; /* the map's forcing term */
    }
    for (int i = 0; i < VI_QUADMAP_NODES; i++) {
      const double *restrict B = S->T + 3 * (size_t)i * n, *restrict Bp = B + n;
      vi_phase p = {d->Om, 0.0, 0.0};
      vi_quadmap_phase(S, i, p0.c, p0.s, &p.c, &p.s);
      double Wc = d->Om * p.c, Ws = d->Om * p.s;
      for (size_t j = 0; j < n; j++)
        qd[j] = Bp[j] * wd[j] + B[j] * w[j] + (pB[j] * Wc - pA[j] * Ws);
      vi_ledger_accumulate_phase(s->led, &p, qd, NULL, S->w[i]);
    }
    d->evals += 1 + VI_QUADMAP_NODES;
    if (vi_sim_quad_cancelled(s, k, np)) { /* the integrals end there */
      *done = k + 1 == np ? b : a + 2.0 * h * (double)(k + 1);
      return VI_CANCELLED;
    }
  }
  return VI_OK;
}

/* The reported gap at t inside the flight, directly (an end time between
 * grid points); the bisection stack is free then. */
static double ex_gap_at(ex_data *d, double t)
{
  double *w = d->stk, *wd = w + d->na;
  vi_phase p = vi_phase_at(d->Om, t);
  double *g = d->gs;
  for (int i = 0; i < d->na; i++) ex_mode(d, d->act[i], t, w + i, wd + i);
  for (int k = 0; k < d->ns; k++) {
    const ex_stop *e = d->st + k;
    double a = 0.0;
    for (int i = 0; i < d->na; i++) a += e->psi[i] * w[i];
    g[k] = a + vi_harm(&p, 0, e->GA, e->GB, 0.0) - e->xs;
  }
  d->evals++;
  return ex_report(d, g, 0);
}

/* The ledger's integrals from s->t to t; cancelled inside them, the
 * flight stops where they end (its time and gap there). */
static int ex_ledger_to(vi_sim *s, ex_data *d, double t)
{
  if (!s->led || d->lf_on || ex_quadrature(s, d, s->t, t, &t) != VI_CANCELLED)
    return VI_OK;
  s->t = t;
  s->gap = ex_gap_at(d, t);
  s->z_stale = 1;
  d->q_ok = 0;
  return VI_CANCELLED;
}

/* Move to t (no contact before it): time, gap, ledger. */
static int ex_move(vi_sim *s, ex_data *d, double t, double g)
{
  int st = ex_ledger_to(s, d, t);
  if (st) return st;
  s->t = t;
  s->gap = g;
  s->z_stale = 1;
  d->q_ok = 0;
  return VI_OK;
}

/* The grid scanner's view of the flight (vi_grid.h): the active modes
 * advance by the maps of level p, every stop's gap is followed. */
static void ex_g_anchor(void *dp, double t)
{
  ex_data *d = dp;
  ex_anchor(d, t, d->g.wn, d->g.wdn, &d->g.cn, &d->g.sn, d->g.fn, d->g.fdn);
}

static int ex_g_advance(void *dp)
{
  ex_data *d = dp;
  int st = ex_advance(d, d->p, d->g.wk, d->g.wdk, d->g.wn, d->g.wdn, d->g.cn,
                      d->g.sn, d->st, d->g.fn, d->g.fdn);
  if (st) return st;
  if (d->ns > 1)
    ex_other_gaps(d, d->g.wn, d->g.wdn, d->g.cn, d->g.sn, d->g.fn, d->g.fdn);
  return VI_OK;
}

/* Stop by stop: the earliest crossing over all of them. */
static int ex_g_search(void *dp, double tk, double tb, double *tstar,
                       int *which)
{
  ex_data *d = dp;
  double best = HUGE_VAL, hp = d->hp;
  const double *gk = d->g.fk, *gdk = d->g.fdk, *gn = d->g.fn, *gdn = d->g.fdn;
  int found = -1;
  for (int k = 0, ns = d->ns; k < ns; k++) {
    ex_stop *e = d->st + k;
    double tc, cf[4], e4 = herm_err(e, hp);
    if (tb <= e->skip ||
        herm_quick(gk[k], gdk[k], gn[k], gdn[k], hp) + e4 < e->gnoise ||
        vi_herm_max(gk[k], gdk[k], gn[k], gdn[k], hp, cf) + e4 < e->gnoise)
      continue;
    d->cs = e;
    int hit = ex_search(d, d->p, tk, d->g.wk, d->g.wdk, d->g.ck, d->g.sk,
                        gk[k], gdk[k], gn[k], gdn[k], &tc);
    if (hit < 0 || hit == VI_CANCELLED) return hit;
    if (hit && tc < best) {
      best = tc;
      found = k;
    }
  }
  *tstar = best;
  *which = found;
  if (found >= 0) d->hit = found;
  return VI_OK;
}

/* Contact at tc: the modes there, every stop's gap from them. */
static int ex_g_crossing(vi_sim *s, void *dp, double tc, int which,
                         int *event)
{
  ex_data *d = dp;
  (void)which; /* d->hit */
  int st = ex_ledger_to(s, d, tc);
  if (st) return st;
  s->t = tc;
  ex_modes_at(d, tc, d->q, d->qd);
  d->tq = tc;
  d->q_ok = 1;
  double *g = d->gs;
  for (int k = 0; k < d->ns; k++) {
    const double *psi = vi_stop_psi(s->m, k);
    g[k] = -d->st[k].xs;
    for (int j = 0; j < d->n; j++) g[k] += psi[j] * d->q[j];
  }
  s->gap = ex_report(d, g, 0);
  s->contact_stop = d->hit;
  s->z_stale = 1;
  d->g.steps++;
  *event = VI_STEP_CONTACT;
  return VI_OK;
}

static double ex_g_gap_at(vi_sim *s, void *dp, double t)
{
  (void)s;
  return ex_gap_at(dp, t);
}

static double ex_g_report(vi_sim *s, void *dp, const double *f)
{
  (void)s;
  return ex_report(dp, f, 1);
}

static int ex_g_move(vi_sim *s, void *dp, double t, double g)
{
  return ex_move(s, dp, t, g);
}

static void ex_g_bounds(void *dp)
{
  ex_data *d = dp;
  ex_bounds(d, d->g.wk, d->g.wdk);
}

static const vi_grid_ops ex_grid = {
    .anchor_every = EX_ANCHOR,
    .batch = EX_BATCH,
    .anchor = ex_g_anchor,
    .advance = ex_g_advance,
    .search = ex_g_search,
    .crossing = ex_g_crossing,
    .gap_at = ex_g_gap_at,
    .report = ex_g_report,
    .move = ex_g_move,
    .bounds = ex_g_bounds,
};

static int ex_step(vi_sim *s, double t_end, int *event)
{
  if (s->sticking) return vi_held_step(s, t_end, event);
  if (!s->m->proportional) return vi_backend_exact_scan.step(s, t_end, event);
  ex_data *d = s->be_data;
  *event = VI_STEP_NONE;
  if (d->handover) {
    *event = VI_STEP_HANDOVER;
    return VI_OK;
  }
  if (s->t < d->tg) { /* provably receding from the stop */
    if (t_end <= d->tg) return ex_move(s, d, t_end, ex_gap_at(d, t_end));
    int st = ex_move(s, d, d->tg, ex_report(d, d->g.fk, 1));
    if (st) return st;
  }
  return vi_grid_step(s, &d->g, &ex_grid, d, t_end, event);
}

/* Physical state x = Psi q, v = Psi q' of the modal state Q = [q qd]
 * [n x 2] (ex_data keeps q, qd and qs, qds adjacent) into the interleaved
 * z = (x_1, v_1, ...): two dgemv with stride 2 (a dgemm would pack Psi at
 * every call). */
static void ex_physical(const vi_model *m, const double *Q, double *z)
{
  int n = m->n;
  cblas_dgemv(CblasColMajor, CblasNoTrans, n, n, 1.0, m->Psi, n, Q, 1, 0.0,
              z, 2);
  cblas_dgemv(CblasColMajor, CblasNoTrans, n, n, 1.0, m->Psi, n, Q + n, 1,
              0.0, z + 1, 2);
}

static int ex_sync(vi_sim *s)
{
  if (s->sticking) return vi_held_sync(s);
  if (!s->m->proportional) return VI_OK;
  ex_data *d = s->be_data;
  if (!d->q_ok || d->tq != s->t) {
    ex_modes_at(d, s->t, d->q, d->qd);
    d->tq = s->t;
    d->q_ok = 1;
  }
  ex_physical(s->m, d->q, s->z);
  memcpy(d->z, s->z, sizeof(double) * 2 * (size_t)d->n);
  d->tz = s->t;
  d->z_ok = 1;
  return VI_OK;
}

static int ex_dense(vi_sim *s, double t)
{
  if (s->sticking) return vi_held_dense(s, t);
  if (!s->m->proportional) return vi_backend_exact_scan.dense(s, t);
  ex_data *d = s->be_data;
  ex_modes_at(d, t, d->qs, d->qds);
  ex_physical(s->m, d->qs, s->zs);
  return VI_OK;
}

/* Stop k's gap, rate and acceleration at a contact from the modes there:
 * q'' = w'' + H'' with w'' = F0 - d w' - lambda w and H'' = -Omega^2 H. */
static int ex_normal(vi_sim *s, int k, double *g, double *gd, double *gdd)
{
  ex_data *d = s->be_data;
  if (s->sticking || !s->m->proportional || !d || d->kind != EX_KIND_FAST ||
      !d->q_ok || d->tq != s->t)
    return 1;
  const double *psi = d->st[k].psi;
  vi_phase p = vi_phase_at(d->Om, s->t);
  double a = 0.0, b = 0.0, c = 0.0;
  for (int i = 0; i < d->na; i++) {
    int j = d->act[i];
    double H = vi_harm(&p, 0, d->pA[j], d->pB[j], 0.0);
    double Hd = vi_harm(&p, 1, d->pA[j], d->pB[j], 0.0);
    double Hdd = vi_harm(&p, 2, d->pA[j], d->pB[j], 0.0);
    double wdd = d->F0[i] - d->dmp[i] * (d->qd[j] - Hd) -
                 d->lam[i] * (d->q[j] - H);
    a += psi[i] * d->q[j];
    b += psi[i] * d->qd[j];
    c += psi[i] * (wdd + Hdd);
  }
  *g = a - d->st[k].xs;
  *gd = b;
  *gdd = c;
  return 0;
}

/* dx = a M^-1 w_k, dv = b M^-1 w_k in modes: q += a psi_k, q' += b psi_k
 * (M^-1 w_k = Psi psi_k); after ex_normal, before ex_start. */
static void ex_kick(vi_sim *s, int k, double a, double b)
{
  ex_data *d = s->be_data;
  const double *psi = vi_stop_psi(s->m, k);
  for (int j = 0; j < d->n; j++) {
    d->q[j] += a * psi[j];
    d->qd[j] += b * psi[j];
  }
  d->hit = k;
  d->z_ok = 0;
  s->z_stale = 1;
}

static int64_t ex_stat(const void *data, int which)
{
  const ex_data *d = data;
  if (d->kind != EX_KIND_FAST) return vi_backend_exact_scan.stat(data, which);
  if (which == VI_STAT_STEPS) return d->g.steps;
  if (which == VI_STAT_ROOT_EVALS) return d->evals;
  return 0;
}

static int ex_modal(vi_sim *s, const double **q, const double **qd)
{
  ex_data *d = s->be_data;
  if (s->sticking || !s->m->proportional || !d || d->kind != EX_KIND_FAST ||
      !d->q_ok || d->tq != s->t)
    return 1;
  *q = d->q;
  *qd = d->qd;
  return 0;
}

const vi_backend vi_backend_exact = {"exact", ex_start, ex_step, ex_dense,
                                     ex_stat, ex_destroy, ex_sync, NULL,
                                     ex_normal, ex_kick, ex_modal};
