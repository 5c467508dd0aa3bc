/* vi_identify_stats.c - what a minimum holds: the recording's noise, the
 * parameters' standard errors, intervals and correlations from the
 * Jacobian, and the WB 12 energy route at the fitted orbit. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_linalg.h>
#include <lapacke.h>

#include "vi_identify_internal.h"
#include "vi_impact_internal.h"

static int cmp_double(const void *a, const void *b)
{
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

static double median_of(double *d, int k)
{
  qsort(d, k, sizeof(double), cmp_double);
  return k % 2 ? d[k / 2] : 0.5 * (d[k / 2 - 1] + d[k / 2]);
}

/* Noise of a near-uniform recording from its 4th differences (a smooth
 * signal's are ~ A (Omega dt)^4; noise's have variance 70 sigma^2), their
 * median absolute value robust to the impacts' kinks.  An upper bound:
 * a signal rich in high harmonics keeps its own (an accelerometer's, the
 * higher modes weighted by their frequency squared: 11 times the noise on
 * the 4-mode beam at 64 samples per period). */
static double noise_diff4(const vi_identify *id)
{
  int ns = id->ns;
  double dmin = HUGE_VAL, dmax = 0.0;
  for (int i = 1; i < ns; i++) {
    dmin = fmin(dmin, id->t[i] - id->t[i - 1]);
    dmax = fmax(dmax, id->t[i] - id->t[i - 1]);
  }
  if (dmax > 1.01 * dmin || ns < 16) return NAN;
  double *d = malloc(sizeof(double) * ns);
  if (!d) return NAN;
  int k = 0;
  for (int i = 0; i + 4 < ns; i++)
    d[k++] = fabs(id->y[i] - 4 * id->y[i + 1] + 6 * id->y[i + 2] -
                  4 * id->y[i + 3] + id->y[i + 4]);
  double med = median_of(d, k);
  free(d);
  return 1.4826 * med / sqrt(70.0);
}

/* Samples a fold looks at, at most (evenly strided over a longer record). */
#define FOLD_MAX 2048

typedef struct phs {
  double ph;
  int i;
} phs;

static int cmp_phase(const void *a, const void *b)
{
  double x = ((const phs *)a)->ph, y = ((const phs *)b)->ph;
  return (x > y) - (x < y);
}

/* Every stride-th of the first m samples folded with period P (phase
 * (t - t_1) mod P): into e each sample against the line through its two
 * neighbours in phase, which belong to other periods, so the signal
 * cancels to second order in their phase gap, whatever its harmonics
 * (the higher modes ring in step with the orbit), scaled by
 * sqrt(1 + wa^2 + wb^2) so that noise of spread sigma gives sigma; into
 * gap their phase gaps.  q, e, gap hold m / stride + 1.  The count, 0
 * where the samples span less than 1.5 P. */
static int fold_resid(const vi_identify *id, double P, int m, int stride, phs *q,
                      double *e, double *gap)
{
  if (!(P > 0.0) || m < 16 || !(id->t[m - 1] - id->t[0] > 1.5 * P)) return 0;
  int k = 0;
  for (int i = 0; i < m; i += stride, k++) {
    double f = fmod(id->t[i] - id->t[0], P) / P;
    q[k].ph = f < 0.0 ? f + 1.0 : f;
    q[k].i = i;
  }
  double step = (id->t[m - 1] - id->t[0]) / (m - 1) / P;
  qsort(q, k, sizeof *q, cmp_phase);
  for (int c = 0; c < k; c++) {
    const phs *a = &q[(c + k - 1) % k], *b = &q[(c + 1) % k], *s = &q[c];
    double pa = a->ph - (c == 0 ? 1.0 : 0.0), pb = b->ph + (c == k - 1 ? 1.0 : 0.0);
    double w = pb - pa, wa = w > 1e-12 * step ? (pb - s->ph) / w : 0.5, wb = 1.0 - wa;
    e[c] = (id->y[s->i] - wa * id->y[a->i] - wb * id->y[b->i]) / sqrt(1.0 + wa * wa + wb * wb);
    gap[c] = w;
  }
  return k;
}

/* Noise of a recording that repeats with period P, from its periods
 * folded onto one (fold_resid): the median of |e|, robust to the
 * impacts.  NaN where the neighbours are not much closer in phase than
 * successive samples (a record of about one period: nothing to fold). */
double vi_id_fold(const vi_identify *id, double P)
{
  int ns = id->ns;
  phs *q = malloc(sizeof *q * ns);
  double *d = malloc(sizeof(double) * 2 * ns), r = NAN;
  int k = q && d ? fold_resid(id, P, ns, 1, q, d, d + ns) : 0;
  if (k) {
    for (int c = 0; c < k; c++) d[c] = fabs(d[c]);
    double med = median_of(d, k), mgap = median_of(d + ns, k);
    if (mgap <= 0.5 * (id->t[ns - 1] - id->t[0]) / (ns - 1) / P) r = 1.4826 * med;
  }
  free(q);
  free(d);
  return r;
}

/* The RMS of fold_resid's e over every stride-th of the first m samples
 * (not the median: a period off by a little moves the samples far from
 * their partners only in the periods far apart, a minority); NaN where
 * it does not fold. */
static double fold_rms(const vi_identify *id, double P, int m, int stride, phs *q, double *e)
{
  int k = fold_resid(id, P, m, stride, q, e, e + m);
  double s = 0.0;
  for (int c = 0; c < k; c++) s += e[c] * e[c];
  return k ? sqrt(s / k) : NAN;
}

/* fold_rms over the whole record as vi_golden_min's function of P. */
typedef struct fold_ctx {
  const vi_identify *id;
  int stride;
  phs *q;
  double *e;
} fold_ctx;

static double fold_at(void *ctx, double P)
{
  const fold_ctx *c = ctx;
  return fold_rms(c->id, P, c->id->ns, c->stride, c->q, c->e);
}

double vi_id_fold_period(const vi_identify *id, double P, double W, double limit, double *rms)
{
  int ns = id->ns;
  double span = id->t[ns - 1] - id->t[0], dt = span / (ns - 1);
  *rms = NAN;
  if (!(span > 4.0 * P) || !(W > 0.0)) return P;
  phs *q = malloc(sizeof *q * ns);
  double *e = malloc(sizeof(double) * 2 * ns);
  if (!q || !e) {
    free(q);
    free(e);
    return P;
  }
  /* stages over ever longer parts of the record, each 8 times the last:
   * over a part S long, a change dP of the period moves its last samples
   * by S dP / P, so a quarter of dt P / S is the stage's step, and the
   * next stage searches two of them either side; at most FOLD_MAX samples
   * a stage, evenly strided (their phases still far denser than the
   * samples') */
  double c = P, S = fmin(span, fmax(4.0 * P, 32.0 * dt * P / W)), step = W;
  for (;;) {
    int m = ns;
    while (m > 16 && id->t[m - 1] - id->t[0] > S) m--;
    int sd = m > FOLD_MAX ? m / FOLD_MAX : 1;
    step = 0.25 * dt * c / S;
    int nk = (int)ceil(W / step);
    double best = c, bv = fold_rms(id, c, m, sd, q, e);
    for (int k = -nk; k <= nk; k++) {
      double v = fold_rms(id, c + k * step, m, sd, q, e);
      if (v < bv) {
        bv = v;
        best = c + k * step;
      }
    }
    c = best;
    W = 2.0 * step;
    if (!(bv <= limit)) { /* no period here that could win */
      free(q);
      free(e);
      return P;
    }
    if (S >= span) break;
    S = fmin(span, 8.0 * S);
  }
  /* to a thousandth of the last stage's step about its best */
  fold_ctx fc = {id, ns > FOLD_MAX ? ns / FOLD_MAX : 1, q, e};
  double cf = fold_at(&fc, c), pf = fold_at(&fc, P), gf;
  double gc = vi_golden_min(fold_at, &fc, c - step, c + step, 1e-3 * step, 64, &gf);
  if (gf < cf) {
    cf = gf;
    c = gc;
  }
  free(q);
  free(e);
  /* taken only where it folds clearly better: a recording sampled in
   * step with P folds at the noise over a range about dt P / span wide,
   * where the lag, which lands its samples on each other, is the better
   * estimate */
  int better = cf < 0.5 * pf;
  *rms = better ? cf : pf;
  return better ? c : P;
}

/* The recording's noise: the smaller of the two upper bounds above (each
 * holds some signal where its assumption fails: the folded one a period
 * P off, when Omega is fitted from a start away from the truth). */
double vi_id_noise_estimate(const vi_identify *id, double P)
{
  double a = noise_diff4(id), b = vi_id_fold(id, P);
  return isnan(a) ? b : isnan(b) ? a : fmin(a, b);
}

int vi_identify_outliers(const vi_identify *id, double level, int cap, int *idx,
                         double *z, int *count, double *rest)
{
  if (!id || !(level > 0.0) || cap < 0 || (cap > 0 && (!idx || !z))) return VI_ERR_ARG;
  if (!id->done) return VI_ERR_STATE;
  if (count) *count = 0;
  if (rest) *rest = NAN;
  if (!(id->noise > 0.0) || !isfinite(id->noise)) return VI_OK;
  int n = 0;
  double *m = malloc(sizeof(double) * id->ns), ss = 0.0;
  if (!m || vi_id_first_channel(id, id->cur, id->xf, &id->o, id->t0, m)) {
    free(m);
    return VI_ERR_NOMEM;
  }
  for (int i = 0; i < id->ns; i++) {
    double d = fabs(id->y[i] - m[i]) / id->noise;
    if (!(d > level)) {
      ss += d * d;
      continue;
    }
    /* the worst cap kept, farthest first: insertion from the end */
    int k = n < cap ? n : cap - 1;
    if (k >= 0 && (n < cap || d > z[cap - 1])) {
      for (; k > 0 && d > z[k - 1]; k--) {
        z[k] = z[k - 1];
        idx[k] = idx[k - 1];
      }
      z[k] = d;
      idx[k] = i;
    }
    n++;
  }
  free(m);
  if (count) *count = n;
  if (rest && n < id->ns) *rest = sqrt(ss / (id->ns - n));
  return VI_OK;
}

/* Standard errors, intervals, correlations and flags from the Jacobian at
 * the optimum, columns scaled to unit norm, by its SVD: cov = s^2 V S^-2 V^T
 * (scaled back); directions with no singular value are infinitely
 * uncertain, not zero. */
int vi_id_uncertainty(vi_identify *id, const gsl_matrix *J, double ssr)
{
  int nr = (int)J->size1, P = (int)J->size2, np = id->np, st = VI_OK;
  gsl_matrix *A = gsl_matrix_alloc(nr, P), *V = gsl_matrix_alloc(P, P);
  gsl_vector *S = gsl_vector_alloc(P), *wk = gsl_vector_alloc(P),
             *D = gsl_vector_alloc(P);
  gsl_matrix *C = gsl_matrix_calloc(P, P);
  if (!A || !V || !S || !wk || !D || !C) {
    st = VI_ERR_NOMEM;
    goto done;
  }
  gsl_matrix_memcpy(A, J);
  for (int q = 0; q < P; q++) {
    gsl_vector_view col = gsl_matrix_column(A, q);
    double nrm = gsl_blas_dnrm2(&col.vector);
    gsl_vector_set(D, q, nrm > 0.0 ? nrm : 1.0);
    gsl_vector_scale(&col.vector, 1.0 / gsl_vector_get(D, q));
  }
  if (gsl_linalg_SV_decomp(A, V, S, wk)) {
    st = VI_ERR_NOT_CONVERGED;
    goto done;
  }
  double smax = gsl_vector_get(S, 0), smin = gsl_vector_get(S, P - 1);
  id->rcond = smax > 0.0 ? smin / smax : 0.0;
  int dof = nr - P;
  double s2 = dof > 0 ? ssr / dof : NAN;
  double tq = dof > 0 ? gsl_cdf_tdist_Pinv(0.975, dof) : NAN;
  int sing[MAXP + 1] = {0};
  for (int k = 0; k < P; k++) {
    double sk = gsl_vector_get(S, k);
    int null = !(sk > 1e-13 * smax), ill = !(sk > 1e-10 * smax) || null;
    for (int a = 0; a < P; a++) {
      double va = gsl_matrix_get(V, a, k);
      if (ill && fabs(va) > (null ? 1e-3 : 0.1)) sing[a] = null ? 2 : 1;
      if (null) continue;
      for (int b = 0; b < P; b++)
        *gsl_matrix_ptr(C, a, b) += va * gsl_matrix_get(V, b, k) / (sk * sk);
    }
  }
  for (int a = 0; a < P; a++)
    for (int b = 0; b < P; b++)
      *gsl_matrix_ptr(C, a, b) *= s2 / (gsl_vector_get(D, a) * gsl_vector_get(D, b));
  for (int j = 0; j < np; j++) {
    double se = sing[j] == 2 ? INFINITY : sqrt(gsl_matrix_get(C, j, j));
    id->se[j] = se;
    id->l95[j] = id->p[j] - tq * se;
    id->h95[j] = id->p[j] + tq * se;
    int fl = 0;
    double range = id->hi[j] - id->lo[j], eps = 1e-6 * (isfinite(range) ? range : fmax(fabs(id->p[j]), 1.0));
    if (id->p[j] - id->lo[j] <= eps || id->hi[j] - id->p[j] <= eps) fl |= VI_IDENTIFY_ON_BOUND;
    if (sing[j] || !isfinite(se) || 2.0 * tq * se > range) fl |= VI_IDENTIFY_UNDETERMINED;
    for (int q = 0; q < np; q++) {
      double cc = gsl_matrix_get(C, j, q) /
                  sqrt(gsl_matrix_get(C, j, j) * gsl_matrix_get(C, q, q));
      if (sing[j] || sing[q]) cc = j == q ? 1.0 : NAN;
      id->corr[j + (size_t)q * np] = cc;
      if (q != j && fabs(cc) > 0.99) fl |= VI_IDENTIFY_CORRELATED;
    }
    id->flags[j] = fl;
  }
  id->t0se = id->fit_shift ? (sing[np] == 2 ? INFINITY : sqrt(gsl_matrix_get(C, np, np))) : 0.0;
done:
  gsl_matrix_free(A);
  gsl_matrix_free(V);
  gsl_vector_free(S);
  gsl_vector_free(wk);
  gsl_vector_free(D);
  gsl_matrix_free(C);
  return st;
}

/* Value (der = 0) or slope (der = 1) at time s of a least-squares
 * polynomial of degree deg through the k samples of f before s. */
static double local_poly(const vi_identify *id, const double *f, int last,
                         int k, int deg, double s, int der)
{
  double A[25] = {0}, r[5] = {0}, h = id->t[last] - id->t[last - k + 1];
  int d1 = deg + 1, ipiv[5];
  for (int i = last - k + 1; i <= last; i++) {
    double u = (id->t[i] - s) / h, pw[5] = {1.0, u, u * u, u * u * u, u * u * u * u};
    for (int a = 0; a < d1; a++) {
      r[a] += pw[a] * f[i];
      for (int c = 0; c < d1; c++) A[a + d1 * c] += pw[a] * pw[c];
    }
  }
  if (LAPACKE_dgesv(LAPACK_COL_MAJOR, d1, 1, A, d1, ipiv, r, d1)) return NAN;
  return der ? r[1] / h : r[0];
}

/* The recorded approach velocity at time s.  When the model explains
 * the recording (residual RMS within 1.5 times the noise): the fitted
 * model's vN plus the recording's departure from it just before s (the
 * slope of a line through the last 8 displacement residuals, or the mean
 * of the last 3 velocity residuals: low-order, so that noise is averaged,
 * not amplified); the model interpolates what 64 samples per period
 * cannot, the higher modes ringing between impacts.  Otherwise NaN:
 * 64 samples per period do not resolve the approach by themselves (a
 * local polynomial of the 4-mode beam's samples is off by 2 % of vN, and
 * a model that misses the motion puts its impacts elsewhere). */
static double recorded_slope(const vi_identify *id, const double *e,
                             const double *ev, double vNm, int assisted,
                             double s)
{
  int b = 0, en = id->ns;
  while (en - b > 1) {
    int c = (b + en) / 2;
    if (id->t[c] < s) b = c;
    else en = c;
  }
  int last = b; /* last sample before s */
  if (!(id->t[last] < s) || last < 8) return NAN;
  if (!assisted) return NAN;
  return vNm + (ev ? local_poly(id, ev, last, 3, 0, s, 0)
                   : local_poly(id, e, last, 8, 1, s, 1));
}

/* WB 12 at the fitted orbit: the model's residual energy from its modal
 * ledger over one period (vi_orbit_balance, started on the orbit), the
 * recorded approach velocity averaged over the recorded impacts. */
void vi_id_energy_route(vi_identify *id)
{
  id->r12 = id->vN = id->KE = id->RE = NAN;
  const vi_model *m = id->cur;
  const orb *o = &id->o;
  int N = id->N;
  if (o->n != 1 || o->m != 1 || o->stop[0] != 0 || id->ych != 0) return;
  const double *w = vi_stop_w(m, 0);
  for (int i = 0; i < N; i++)
    if (fabs(id->c[i] - w[i]) > 1e-12 * (fabs(w[i]) + 1e-300)) return;
  double P = vi_id_period_of(m, 1), sum = 0.0;
  int cnt = 0, ns = id->ns;
  double *e = malloc(sizeof(double) * (2 * (size_t)ns + 4 * (size_t)N));
  if (!e) return;
  double *ev = e + ns, *zz = ev + ns;
  for (int i = 0; i < ns; i++) {
    vi_id_orbit_state(m, id->xf, o, id->t[i] + id->t0, zz, zz + (size_t)2 * N, NULL, NULL,
                NULL);
    e[i] = id->y[i] - vi_dot(N, id->c, zz);
    ev[i] = id->vy ? id->vy[i] - vi_dot(N, id->c, zz + N) : 0.0;
  }
  double vNm = vi_dot(N, w, o->v);
  double nz = id->noise;
  int assisted = !(id->rms > 1.5 * nz);
  for (long k = (long)ceil((id->t[0] + id->t0 - o->t[0]) / P);; k++) {
    double s = o->t[0] + (double)k * P - id->t0; /* recording time of impact k */
    if (s > id->t[ns - 1]) break;
    double v = recorded_slope(id, e, id->vy ? ev : NULL, vNm, assisted, s);
    if (isfinite(v)) {
      sum += v;
      cnt++;
    }
  }
  free(e);
  if (cnt == 0) return;
  id->vN = sum / cnt;
  id->KE = vi_impact_ke(id->vN, m->G[0]);
  /* the modal ledger of one period, from the orbit's state at t = 0 */
  double *z = malloc(sizeof(double) * 4 * N);
  vi_orbit *ob = NULL;
  double RE = NAN;
  int pn = 0, pm = 0;
  if (z) {
    vi_id_orbit_state(m, id->xf, o, 0.0, z, z + (size_t)2 * N, NULL, NULL, NULL);
    if (!vi_orbit_create(m, &ob) && !vi_orbit_set_initial(ob, z, z + N) &&
        !vi_orbit_set_direct_search(ob, 0) && !vi_orbit_find(ob) &&
        !vi_orbit_classify(ob, &pn, &pm) && pn == 1 && pm == 1)
      vi_orbit_balance(ob, NULL, NULL, NULL, NULL, &RE, NULL, NULL, NULL);
  }
  vi_orbit_destroy(&ob);
  free(z);
  if (isnan(RE)) {
    /* an orbit the transient cannot hold (unstable): its ledger over one
     * period still closes, RE = IE (WB 10, 11) */
    RE = vi_impact_ie(m->rv[0], vNm, m->G[0]);
  }
  id->RE = RE;
  vi_restitution_from_energy(RE, id->KE, &id->r12); /* WB 13; else NaN */
}

