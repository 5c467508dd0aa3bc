/* vi_identify_global.c - identification that needs no good guess: starts
 * spread over every parameter's admissible range, the model's orbits with
 * the recording's period at each (its transient and the impact-phase
 * scan), scored against the recording; the trust-region fit from the best
 * distinct candidates; the distinct minima whose residual the noise
 * explains, best first; and profile-likelihood intervals (the others
 * re-fitted along each parameter) beside the Jacobian's. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_cdf.h>

#include "vi_identify_internal.h"

/* A start: its values, the orbit chosen there and its score (the shift
 * scan's cost on the recording's first two orbit periods). */
typedef struct cand {
  double p[MAXP], t0, cost;
  orb o;
  int picked;
} cand;

/* 1 when the observation is stop k's own gap coordinate w_k. */
static int observes_stop(const vi_identify *id, int k)
{
  const double *w = vi_stop_w(id->base, k);
  for (int i = 0; i < id->N; i++)
    if (fabs(id->c[i] - w[i]) > 1e-12 * (fabs(w[i]) + 1e-300)) return 0;
  return 1;
}

/* The range the starts cover for parameter j: r within [0, 1]; a stop
 * observed through its own gap coordinate within 5 % of the recorded
 * span of its top (the stop cannot lie below the motion, which would
 * cross it, nor far above it, which would never reach it); otherwise the
 * given bounds, or +-50 % of the starting value where there are none (or,
 * when widened, a factor id->widen either way of a positive start of a key
 * with no natural range; about a minimum, id->widen < 0, +-50 % of such
 * a key's value where its bounds are open or decades apart); in log (*lg =
 * 1) where the range is positive and a decade or more wide. */
static void start_range(const vi_identify *id, int j, double *a, double *b, int *lg)
{
  double lo = id->lo[j], hi = id->hi[j], p0 = id->p0[j];
  *lg = 0;
  if (id->kind[j] == VI_IDENTIFY_XS && id->ych == 0 && observes_stop(id, id->kst[j])) {
    double ymin = HUGE_VAL, ymax = -HUGE_VAL;
    for (int i = 0; i < id->ns; i++) {
      ymin = fmin(ymin, id->y[i]);
      ymax = fmax(ymax, id->y[i]);
    }
    double sp = ymax - ymin;
    lo = fmax(lo, ymax - 0.05 * sp);
    hi = fmin(hi, ymax + 0.05 * sp);
  }
  double h = p0 != 0.0 ? 0.5 * fabs(p0) : 0.5;
  if (id->widen < 0.0 && id->kind[j] == VI_IDENTIFY_OTHER &&
      (!isfinite(lo) || !isfinite(hi) || (lo > 0.0 && hi >= 10.0 * lo))) {
    /* about a minimum (p0 its value): +-|widen| of it within the bounds,
     * where they are open or decades apart (not r's [0, 1]: five starts
     * cover it, and the minimum's r may be the wrong one) */
    double hz = p0 != 0.0 ? -id->widen * fabs(p0) : h;
    lo = fmax(id->lo[j], p0 - hz);
    hi = fmin(id->hi[j], p0 + hz);
  }
  if (id->widen > 0.0 && vi_id_open_key(id, j)) {
    if (!isfinite(lo)) lo = fmax(id->lo[j], p0 / id->widen);
    if (!isfinite(hi)) hi = fmin(id->hi[j], p0 * id->widen);
    *lg = lo > 0.0 && lo < hi;
  }
  if (!isfinite(lo)) lo = fmax(id->lo[j], p0 - h);
  if (!isfinite(hi)) hi = fmin(id->hi[j], p0 + h);
  if (!(lo < hi)) { /* the data's range outside the bounds: the bounds */
    lo = fmax(id->lo[j], p0 - h);
    hi = fmin(id->hi[j], p0 + h);
    *lg = 0;
  }
  /* bounds a decade or more apart on a positive key (a damping ratio
   * bounded to [0.001, 0.9]): starts even in log, or the lowest of five
   * would lie at 0.09 */
  if (lo > 0.0 && hi >= 10.0 * lo && id->kind[j] != VI_IDENTIFY_OMEGA) *lg = 1;
  *a = lo;
  *b = hi;
}

/* Parameter j's start at u in (0, 1) of its range. */
static double from_unit(const vi_identify *id, int j, double u)
{
  double a = id->glo[j], b = id->ghi[j];
  return id->glog[j] ? a * pow(b / a, u) : a + u * (b - a);
}

/* Radical inverse of k in base b (a Halton coordinate in (0, 1)). */
static double halton(int k, int b)
{
  double f = 1.0, r = 0.0;
  for (int i = k; i > 0; i /= b) {
    f /= b;
    r += f * (i % b);
  }
  return r;
}

/* The starts in np parameters: a grid of cell centres for one and two
 * (8, and 5 x 5), a Halton design of 8 np points for more, one for none;
 * their number. */
static int starts(int np, double *u)
{
  if (np == 0) return 1;
  static const int primes[MAXP] = {2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31,
                                   37, 41, 43, 47, 53, 59, 61, 67, 71, 73,
                                   79, 83, 89, 97, 101, 103, 107, 109, 113,
                                   127, 131};
  if (np == 1) {
    for (int k = 0; k < 8; k++) u[k] = (k + 0.5) / 8.0;
    return 8;
  }
  if (np == 2) {
    for (int a = 0; a < 5; a++)
      for (int b = 0; b < 5; b++) {
        u[(size_t)2 * (a * 5 + b)] = (a + 0.5) / 5.0;
        u[(size_t)2 * (a * 5 + b) + 1] = (b + 0.5) / 5.0;
      }
    return 25;
  }
  int ns = 8 * np;
  for (int k = 0; k < ns; k++)
    for (int j = 0; j < np; j++) u[(size_t)k * np + j] = halton(k + 1, primes[j]);
  return ns;
}

/* |log| of frequency w over the given start's, nearest first. */
static double om_dist(const vi_identify *id, double w)
{
  return fabs(log(w / id->p0[id->jom]));
}

/* The forcing frequencies the starts take when it is fitted: the
 * recording's period (vi_id_data_lag) allows only 2 pi n / lag, n <=
 * MAX_N, and at each the motion's period d T for a divisor d of n (lag
 * may be a multiple of the recording's own period: an accelerometer's
 * samples, out of step with the forcing, line up only there).  Those in
 * its range into om, nd [4 MAX_N], nearest the given frequency first,
 * the smaller d first (about a minimum, the nearest alone); their number.
 * One, the given frequency (or none, NaN) with nd0, where none is in the
 * range or it is not fitted. */
static int om_starts(const vi_identify *id, int nd0, double *om, int *nd)
{
  int jo = id->jom, nq = 0;
  for (int n = 1; jo >= 0 && n <= MAX_N; n++) {
    double w = 2.0 * M_PI * n / id->lag;
    for (int d = 1; w >= id->glo[jo] && w <= id->ghi[jo] && d <= n; d++)
      if (n % d == 0) {
        om[nq] = w;
        nd[nq++] = d;
      }
  }
  if (!nq) {
    om[0] = jo >= 0 ? id->p0[jo] : NAN;
    nd[0] = nd0;
    return 1;
  }
  for (int a = 1; a < nq; a++) /* insertion: stable, so d stays ascending */
    for (int b = a; b > 0 && om_dist(id, om[b]) < om_dist(id, om[b - 1]); b--) {
      double w = om[b];
      int d = nd[b];
      om[b] = om[b - 1];
      nd[b] = nd[b - 1];
      om[b - 1] = w;
      nd[b - 1] = d;
    }
  /* about a minimum (id->widen < 0): its own frequency alone, with each
   * period multiple there; the others were searched before */
  for (int q = 1; id->widen < 0.0 && q < nq; q++)
    if (om[q] != om[0]) return q;
  return nq;
}

/* The model and its orbits at the start p: one candidate per orbit type
 * found there (P(n,1), P(n,2), the transient's other), appended to c
 * (*nc grows; their buffers allocated here); best [VI_ID_SLOTS] is work.
 * VI_OK, or non-zero where the start gives none. */
static int at_start(vi_identify *id, int nd, const double *p, orb *best,
                    cand *c, int *nc)
{
  vi_model *m = NULL;
  double bc[VI_ID_SLOTS];
  vi_id_drop_cur(id);
  id->have_pred = 0;
  int st = vi_id_make_model(id, p, &m);
  if (st) return st;
  id->cur = m;
  if ((st = vi_xflow_create(m, &id->xf))) return st;
  if ((st = vi_id_orbit_types(id, nd, best, bc))) return st;
  memcpy(id->pcur, p, sizeof(double) * id->np);
  id->have_cur = 1;
  for (int s = 0; s < VI_ID_SLOTS; s++) {
    if (!(bc[s] < HUGE_VAL)) continue;
    cand *ck = &c[*nc];
    if ((st = vi_id_orb_alloc(&ck->o, id->N))) {
      free(ck->o.x);
      free(ck->o.v);
      ck->o.x = ck->o.v = NULL;
      return st;
    }
    memcpy(ck->p, p, sizeof(double) * id->np);
    vi_id_orb_copy(&id->o, &best[s], id->N);
    ck->cost = bc[s];
    ck->t0 = id->fit_shift && isnan(id->shift0) ? vi_id_scan_shift(id, NULL) : vi_id_shift0(id);
    vi_id_orb_copy(&ck->o, &best[s], id->N);
    (*nc)++;
  }
  return VI_OK;
}

static int cmp_cost(const void *a, const void *b)
{
  double x = ((const cand *)a)->cost, y = ((const cand *)b)->cost;
  return (x > y) - (x < y);
}

/* Distance of two starts in units of the range. */
static double udist(const vi_identify *id, const double *p, const double *q)
{
  double d = 0.0;
  for (int j = 0; j < id->np; j++) {
    double e = id->glog[j] ? log(p[j] / q[j]) / log(id->ghi[j] / id->glo[j])
                           : (p[j] - q[j]) / (id->ghi[j] - id->glo[j]);
    d = fmax(d, fabs(e));
  }
  return d;
}

/* The candidates the fits start from: the best of each orbit type, then
 * the next best by score that lie two grid cells from any picked one of
 * the same type; at most 2 + np. */
static int pick(vi_identify *id, cand *c, int nc, double cell)
{
  int want = 2 + id->np, got = 0;
  for (int k = 0; k < nc && got < want; k++) {
    int seen = 0;
    for (int q = 0; q < k; q++)
      seen |= c[q].o.n == c[k].o.n && c[q].o.m == c[k].o.m;
    if (!seen) {
      c[k].picked = 1;
      got++;
    }
  }
  for (int k = 0; k < nc && got < want; k++) {
    if (c[k].picked) continue;
    int near = 0;
    for (int q = 0; q < nc; q++)
      near |= c[q].picked && c[q].o.n == c[k].o.n && c[q].o.m == c[k].o.m &&
              udist(id, c[q].p, c[k].p) < 1.5 * cell;
    if (!near) {
      c[k].picked = 1;
      got++;
    }
  }
  return got;
}

/* Sort key of a minimum: converged first, then by displacement residual. */
static int cmp_sol(const void *a, const void *b)
{
  const vi_id_sol *x = a, *y = b;
  if (x->conv != y->conv) return y->conv - x->conv;
  return (x->rms > y->rms) - (x->rms < y->rms);
}

/* The same minimum: one orbit type, every value within 3 standard errors
 * (or 1e-6 of its range). */
static int same_min(const vi_identify *id, const vi_id_sol *a, const vi_id_sol *b)
{
  if (a->n != b->n || a->m != b->m) return 0;
  for (int j = 0; j < id->np; j++) {
    double se = fmax(isfinite(a->se[j]) ? a->se[j] : 0.0, isfinite(b->se[j]) ? b->se[j] : 0.0);
    double tol = fmax(3.0 * se, 1e-6 * (id->ghi[j] - id->glo[j]));
    if (fabs(a->p[j] - b->p[j]) > tol) return 0;
  }
  return 1;
}

/* The first channel of minimum a at the recording's samples into y [ns];
 * non-zero where its model cannot be built. */
static int response_of(vi_identify *id, const vi_id_sol *a, double *y)
{
  vi_model *m = NULL;
  vi_xflow *xf = NULL;
  int st = vi_id_make_model(id, a->p, &m);
  if (!st) st = vi_xflow_create(m, &xf);
  if (!st) st = vi_id_first_channel(id, m, xf, &a->o, a->t0, y);
  vi_xflow_destroy(&xf);
  vi_model_destroy(&m);
  return st;
}

/* How far the best and minimum k lie apart: D = sum (y_0 - y_k)^2 / s^2
 * over the samples, the mean of the likelihood-ratio statistic were either
 * true (its spread 2 sqrt(D)), growing with the record's length L.  The
 * test at level c = chi2_0.95(P) rejects the wrong one with 95 % power
 * once L D - 1.645 * 2 sqrt(L D) >= c: L = y^2 / D,
 * y = (3.29 + sqrt(3.29^2 + 4 c)) / 2 (21 / D for P = 2). */
static void separation(vi_identify *id, vi_id_sol *s, int n, double s2, double c)
{
  double *y = malloc(sizeof(double) * 2 * id->ns);
  for (int k = 0; k < n; k++) s[k].dsep = s[k].lsep = NAN;
  if (!y || response_of(id, &s[0], y)) {
    free(y);
    return;
  }
  double yq = 0.5 * (3.29 + sqrt(3.29 * 3.29 + 4.0 * c));
  for (int k = 1; k < n; k++) {
    if (response_of(id, &s[k], y + id->ns)) continue;
    double d = 0.0;
    for (int i = 0; i < id->ns; i++) d += (y[i] - y[id->ns + i]) * (y[i] - y[id->ns + i]);
    s[k].dsep = d / s2;
    s[k].lsep = s[k].dsep > 0.0 ? yq * yq / s[k].dsep : INFINITY;
  }
  s[0].dsep = 0.0;
  free(y);
}

/* Rank the minima, drop repeats, and count those the data cannot tell from
 * the best: a residual the noise explains, sum of squared residuals of the
 * first channel <= s^2 chi2_0.95(ns - P), and no worse than the best by
 * more than the likelihood-ratio test allows, delta chi^2 <=
 * chi2_0.95(P) (a minimum 145 noise variances worse is explained by the
 * noise on its own, but the best explains the data better beyond doubt).
 * s is the stated noise, or the estimated one capped at
 * 1.1 times the best's residual level (an estimate is an upper bound: on
 * a record of about one period only the 4th differences are left, and
 * they hold the signal's own too), and never below the best's level (a
 * model error the best shares). */
void vi_id_rank(vi_identify *id, vi_id_sol *s, int *ns_)
{
  int n = *ns_, keep = 0, P = id->np + id->fit_shift, dof = id->ns - P;
  if (n < 1 || !s) return;
  qsort(s, n, sizeof *s, cmp_sol);
  for (int k = 0; k < n; k++) {
    int dup = 0;
    for (int q = 0; q < keep && !dup; q++) dup = same_min(id, &s[q], &s[k]);
    if (dup) {
      free(s[k].o.x);
      free(s[k].o.v);
      continue;
    }
    if (keep != k) s[keep] = s[k];
    keep++;
  }
  *ns_ = keep;
  double nz = id->noise, best = s[0].rms * s[0].rms * id->ns / (dof > 0 ? dof : 1);
  if (!(id->sigma > 0.0) && isfinite(nz)) nz = fmin(nz, 1.1 * sqrt(best));
  double s2 = isfinite(nz) ? fmax(nz * nz, best) : best;
  double lim = dof > 0 ? gsl_cdf_chisq_Pinv(0.95, dof) : HUGE_VAL;
  double dlim = gsl_cdf_chisq_Pinv(0.95, P);
  id->nfound = 1;
  for (int k = 0; k < keep; k++)
    s[k].dchi2 = (s[k].rms * s[k].rms - s[0].rms * s[0].rms) * id->ns / s2;
  for (int k = 1; k < keep; k++)
    if (s[k].conv && s[k].rms * s[k].rms * id->ns / s2 <= lim &&
        s[k].dchi2 <= dlim)
      id->nfound = k + 1;
    else break;
  id->unique = id->nfound == 1;
  separation(id, s, id->nfound, s2, dlim);
}

int vi_id_global(vi_identify *id, int nd)
{
  int np = id->np, N = id->N, st = VI_OK, nc = 0, nsol = 0;
  for (int j = 0; j < np; j++) {
    start_range(id, j, &id->glo[j], &id->ghi[j], &id->glog[j]);
    id->slo[j] = id->nsearch ? fmin(id->slo[j], id->glo[j]) : id->glo[j];
    id->shi[j] = id->nsearch ? fmax(id->shi[j], id->ghi[j]) : id->ghi[j];
  }
  id->nsearch++;
  double om_at[4 * MAX_N], *u = malloc(sizeof(double) * 8 * MAXP * MAXP);
  cand *c = calloc((size_t)8 * MAXP * VI_ID_SLOTS, sizeof *c);
  orb best[VI_ID_SLOTS];
  char why[VI_MSG_LEN] = "";
  memset(best, 0, sizeof best);
  for (int q = 0; q < VI_ID_SLOTS && u && c && !st; q++) st = vi_id_orb_alloc(&best[q], N);
  if (!u || !c || st) {
    free(u);
    free(c);
    for (int q = 0; q < VI_ID_SLOTS; q++) {
      free(best[q].x);
      free(best[q].v);
    }
    return vi_fail(id->errmsg, VI_ERR_NOMEM, "out of memory");
  }
  int om_nd[4 * MAX_N], nq = om_starts(id, nd, om_at, om_nd), npo = np - (id->jom >= 0);
  int ns = starts(npo, u), jo = id->jom;
  if (nq * ns > 8 * MAXP) nq = ns >= 8 * MAXP ? 1 : 8 * MAXP / ns; /* the candidates' room */
  double cell = npo <= 1 ? 1.0 / 8 : npo == 2 ? 1.0 / 5 : pow(1.0 / ns, 1.0 / npo);
  for (int q = 0; q < nq && !st; q++)
    for (int k = 0; k < ns && !st; k++) {
      double p[MAXP];
      for (int j = 0, i = 0; j < np; j++)
        p[j] = j == jo ? om_at[q] : from_unit(id, j, u[(size_t)k * npo + i++]);
      int sk = at_start(id, om_nd[q], p, best, c, &nc);
      if (id->cancel_hit) st = VI_CANCELLED;
      else if (sk == VI_ERR_NOMEM) st = sk;
      else if (sk) snprintf(why, sizeof why, "%s", id->errmsg);
    }
  ns *= nq;
  free(u);
  for (int q = 0; q < VI_ID_SLOTS; q++) {
    free(best[q].x);
    free(best[q].v);
  }
  if (!st && nc == 0)
    st = vi_fail(id->errmsg, VI_ERR_NOT_CONVERGED,
                 "at none of %d starts over the parameters' ranges does the "
                 "model show a %sP(%d,m) orbit, the recording's period (the "
                 "last: %s)", ns, id->stable_only ? "stable " : "", nd, why);
  int want = st ? 0 : (qsort(c, nc, sizeof *c, cmp_cost), pick(id, c, nc, cell));
  vi_id_sol *s = want ? calloc(want, sizeof *s) : NULL;
  if (want && !s) st = vi_fail(id->errmsg, VI_ERR_NOMEM, "out of memory");
  for (int k = 0; !st && s && k < nc; k++) {
    if (!c[k].picked) continue;
    vi_id_sol *sk = &s[nsol];
    if ((st = vi_id_orb_alloc(&sk->o, N))) break;
    /* the model and orbit at the candidate, current */
    vi_model *m = NULL;
    vi_id_drop_cur(id);
    id->have_pred = 0;
    int e = vi_id_make_model(id, c[k].p, &m);
    if (!e) {
      id->cur = m;
      e = vi_xflow_create(m, &id->xf);
    }
    if (!e) {
      vi_id_orb_copy(&id->o, &c[k].o, N);
      memcpy(id->pcur, c[k].p, sizeof(double) * np);
      id->have_cur = 1;
      e = vi_id_local(id, c[k].p, c[k].t0, sk);
    }
    if (id->cancel_hit) st = VI_CANCELLED;
    else if (e == VI_ERR_NOMEM) st = e;
    else if (e) snprintf(why, sizeof why, "%s", id->errmsg);
    if (e) {
      free(sk->o.x);
      free(sk->o.v);
      sk->o.x = sk->o.v = NULL;
    } else {
      nsol++;
    }
  }
  for (int k = 0; k < nc; k++) {
    free(c[k].o.x);
    free(c[k].o.v);
  }
  free(c);
  if (!st && nsol == 0)
    st = vi_fail(id->errmsg, VI_ERR_NOT_CONVERGED, "no fit from the %d best "
                 "starts converged (the last: %s)", want, why);
  if (st) {
    for (int k = 0; s && k < nsol; k++) {
      free(s[k].o.x);
      free(s[k].o.v);
    }
    free(s);
    return st == VI_CANCELLED ? vi_fail(id->errmsg, st, "cancelled") : st;
  }
  vi_id_rank(id, s, &nsol);
  id->sol = s;
  id->nsol = nsol;
  return VI_OK;
}

/* ---- profile-likelihood intervals ---------------------------------------- */

/* The model and orbit of solution s current again. */
static int restore(vi_identify *id, const vi_id_sol *s)
{
  vi_id_hold(id, -1, NAN);
  vi_id_drop_cur(id);
  id->have_pred = 0;
  vi_id_orb_copy(&id->o, &s->o, id->N);
  return vi_id_ensure(id, s->p);
}

/* The profile's rise at p_j = v: the least cost with p_j held there, the
 * others and the shift re-fitted from *q, *t0 (updated to the new
 * optimum), minus the minimum's; NaN where the orbit cannot be continued
 * there (a change of orbit type, or no admissible stable orbit). */
static double rise(vi_identify *id, const vi_id_sol *s, int j, double v,
                   double *q, double *t0)
{
  double pq[MAXP], ssr, t1;
  int it, cv;
  q[j] = v;
  vi_id_hold(id, j, v);
  if (vi_id_ensure(id, q)) return NAN;
  if (vi_id_lm(id, q, *t0, pq, &t1, &ssr, &it, &cv)) return NAN;
  if (vi_id_ensure(id, pq)) return NAN;
  memcpy(q, pq, sizeof(double) * id->np);
  *t0 = t1;
  return ssr - s->ssr;
}

/* One side (dir +-1) of parameter j's profile interval: where the cost has
 * risen by lim; *flag gets VI_IDENTIFY_PROFILE_BOUND or _ORBIT where the
 * bound or a change of orbit ends it first. */
static double side(vi_identify *id, const vi_id_sol *s, int j, int dir,
                   double lim, int *flag)
{
  double q[MAXP], t0 = s->t0, bnd = dir > 0 ? id->hi[j] : id->lo[j];
  double room = dir > 0 ? bnd - s->p[j] : s->p[j] - bnd;
  double d = s->h95[j] - s->p[j], in = 0.0, out = HUGE_VAL;
  if (!(d > 0.0) || !isfinite(d)) d = 1e-3 * (id->ghi[j] - id->glo[j]);
  if (!(room > 0.0)) {
    *flag |= VI_IDENTIFY_PROFILE_BOUND;
    return s->p[j];
  }
  if (restore(id, s)) return NAN;
  memcpy(q, s->p, sizeof(double) * id->np);
  for (int it = 0; it < 12; it++) {
    int atb = d >= room;
    if (atb) d = room;
    double r = rise(id, s, j, atb ? bnd : s->p[j] + dir * d, q, &t0);
    if (isnan(r)) { /* no orbit there: back towards what continues */
      out = d;
      if (out - in < 0.02 * out) {
        *flag |= VI_IDENTIFY_PROFILE_ORBIT;
        return s->p[j] + dir * in;
      }
      d = 0.5 * (in + out);
      continue;
    }
    if (r <= lim) {
      in = d;
      if (atb) {
        *flag |= VI_IDENTIFY_PROFILE_BOUND;
        return bnd;
      }
    } else {
      out = d;
    }
    if (fabs(r - lim) < 0.005 * lim) return s->p[j] + dir * d;
    /* the rise is quadratic near a minimum: d to lim's level on it, kept
     * inside the bracket */
    double dn = r > 0.0 ? d * sqrt(lim / r) : 2.0 * d;
    if (dn <= in || dn >= out) dn = isfinite(out) ? 0.5 * (in + out) : 2.0 * in;
    d = dn;
  }
  return s->p[j] + dir * d;
}

int vi_id_profile(vi_identify *id, vi_id_sol *s)
{
  int np = id->np, P = np + id->fit_shift, dof = vi_id_nres(id) - P;
  if (dof < 1) return VI_OK;
  double tq = gsl_cdf_tdist_Pinv(0.975, dof);
  double lim = s->ssr / dof * tq * tq; /* a rise of t^2 s^2: the 95 % level */
  for (int j = 0; j < np; j++) {
    int fl = 0;
    if (s->flags[j] & VI_IDENTIFY_UNDETERMINED) continue;
    s->pl95[j] = side(id, s, j, -1, lim, &fl);
    s->ph95[j] = side(id, s, j, +1, lim, &fl);
    if (id->cancel_hit) return VI_CANCELLED;
    double jl = s->p[j] - s->l95[j], jh = s->h95[j] - s->p[j];
    double pl = s->p[j] - s->pl95[j], ph = s->ph95[j] - s->p[j];
    if (!(fabs(pl - jl) <= 0.2 * jl) || !(fabs(ph - jh) <= 0.2 * jh))
      fl |= VI_IDENTIFY_PROFILE_DIFFERS;
    s->pflags[j] = fl;
  }
  vi_id_hold(id, -1, NAN);
  return VI_OK;
}
