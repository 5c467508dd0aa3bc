/* vi_identify_seed.c - where the fit starts: the period the recording
 * repeats with, the model's orbit at a start (its transient and the
 * impact-phase scan, the one closest to the recording) and the shift. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vi_identify_internal.h"

/* ---- the steps of vi_identify_run ---------------------------------------- */

/* The model's steady motion at the starting values: a transient classified
 * P(n, m), its last m impacts refined by Newton. */
static int seed_orbit(vi_identify *id, orb *o)
{
  vi_orbit *ob = NULL;
  const vi_model *m = id->cur;
  int st = vi_orbit_create(m, &ob), pn = 0, pm = 0, N = id->N, cnt = 0;
  if (!st && id->cancel) st = vi_orbit_set_monitor(ob, vi_id_poll_mon, id, NULL);
  if (!st) st = vi_orbit_find(ob);
  if (!st) st = vi_orbit_classify(ob, &pn, &pm);
  if (st) {
    vi_fail(id->errmsg, st, "the transient at the starting values failed: %s",
            vi_orbit_errmsg(ob));
    vi_orbit_destroy(&ob);
    return st;
  }
  if (pn < 1 || pm < 1 || pm > MAX_M) {
    vi_orbit_destroy(&ob);
    return vi_fail(id->errmsg, VI_ERR_NOT_CONVERGED,
                   pn < 1 ? "the model's motion at the starting values is not "
                            "periodic (no period up to %d forcing periods)"
                          : "the model's motion at the starting values has "
                            "%d impacts per period (1 to %d identifiable)",
                   pn < 1 ? MAX_N : pm, MAX_M);
  }
  o->n = pn;
  o->m = pm;
  if (!vi_orbit_impacts(ob, &cnt, o->t, o->stop, NULL, o->x, o->v, N) &&
      cnt == pm) {
    /* the analysed P(1, m) orbit */
  } else {
    /* its last pm impacts in the transient's record */
    for (int j = 0; j < pm; j++) {
      size_t r = (size_t)((ob->nimp - pm + j) % RING);
      o->t[j] = ob->rt[r];
      o->stop[j] = ob->rs[r];
      memcpy(o->x + (size_t)j * N, ob->rz + r * 2 * N, sizeof(double) * N);
      memcpy(o->v + (size_t)j * N, ob->rz + r * 2 * N + N, sizeof(double) * N);
    }
  }
  vi_orbit_destroy(&ob);
  int ok = 0;
  st = vi_orbit_pnm_solve_stops(m, o->n, o->m, o->stop, o->t, o->x, o->v, N,
                                0.0, NULL);
  if (!st)
    st = vi_orbit_pnm_admissible_stops(m, o->n, o->m, o->stop, o->t, o->x,
                                       o->v, N, NULL, &ok);
  if (st || !ok)
    return vi_fail(id->errmsg, VI_ERR_NOT_CONVERGED,
                   "the model's P(%d,%d) motion at the starting values cannot "
                   "be refined to a periodic orbit (%s)", pn, pm,
                   st ? vi_strerror(st) : "not admissible");
  vi_id_orb_normalise(o, vi_id_period_of(m, o->n));
  return VI_OK;
}

/* Linear interpolation of the recording at time s (inside its span). */
static double interp(const vi_identify *id, double s)
{
  int a = 0, b = id->ns - 1;
  while (b - a > 1) {
    int c = (a + b) / 2;
    if (id->t[c] <= s) a = c;
    else b = c;
  }
  double u = (s - id->t[a]) / (id->t[b] - id->t[a]);
  return id->y[a] + u * (id->y[b] - id->y[a]);
}

/* The recording's RMS variation about its mean. */
static double rms_of(const vi_identify *id)
{
  int ns = id->ns;
  double mean = 0.0, var = 0.0;
  for (int i = 0; i < ns; i++) mean += id->y[i] / ns;
  for (int i = 0; i < ns; i++) var += (id->y[i] - mean) * (id->y[i] - mean);
  return sqrt(var / ns);
}

/* RMS change of the recording over a time lag P against rms, its RMS
 * variation, over every stride-th sample that has a partner; NaN if fewer
 * than 8. */
static double lag_change(const vi_identify *id, double P, double rms, int stride)
{
  int ns = id->ns, cnt = 0;
  double d = 0.0;
  for (int i = 0; i < ns && id->t[i] + P <= id->t[ns - 1]; i += stride, cnt++) {
    double e = interp(id, id->t[i] + P) - id->y[i];
    d += e * e;
  }
  if (cnt < 8 || !(rms > 0.0)) return NAN;
  return sqrt(d / cnt) / rms;
}


/* The recording's period in forcing periods T: the smallest n <= MAX_N it
 * repeats with, as well as with the best one up to the noise (0 if none;
 * 1 when it is too short to tell). */
int vi_id_data_period(vi_identify *id, double T)
{
  double rat[MAX_N + 1], best = HUGE_VAL, rms = rms_of(id);
  int known = 0;
  for (int n = 1; n <= MAX_N; n++) {
    /* the change over nT from the linear interpolant of the samples, or,
     * where smaller, the recording folded with period nT: an
     * accelerometer's signal sampled at a rate not locked to the forcing
     * is too rich in harmonics to interpolate between samples (61.3
     * samples per period: no repeat over T, one over 3 T where 3 x 61.3
     * is almost whole), not between periods */
    rat[n] = lag_change(id, n * T, rms, 1);
    double fr = rms > 0.0 ? vi_id_fold(id, n * T) / rms : NAN;
    if (isfinite(fr) && !(rat[n] <= fr)) rat[n] = fr;
    if (isfinite(rat[n])) {
      best = fmin(best, rat[n]);
      known = n;
    }
  }
  if (!known) return 1;
  for (int n = 1; n <= known; n++)
    if (rat[n] < 0.3 && rat[n] <= fmax(1.5 * best, best + 0.05)) return n;
  vi_fail(id->errmsg, VI_ERR_ARG,
          "the recording does not repeat with any period up to %d forcing "
          "periods (2 pi / Omega = %g): its change over one period is %.2g "
          "of its RMS variation (a motion that is not periodic)", known, T,
          rat[1]);
  return 0;
}

/* lag_change as vi_golden_min's function of the lag. */
typedef struct lag_ctx {
  const vi_identify *id;
  double rms;
  int stride;
} lag_ctx;

static double lag_at(void *ctx, double P)
{
  const lag_ctx *c = ctx;
  return lag_change(c->id, P, c->rms, c->stride);
}

/* lag_change's least value over [a, b]: its lag, the value into *r.  (Not
 * the fold: its median is small at lags that are no period, where a
 * sample's neighbours in phase fall half a sample apart.) */
static double lag_min(const vi_identify *id, double a, double b, double rms, int stride,
                      double *r)
{
  lag_ctx c = {id, rms, stride};
  return vi_golden_min(lag_at, &c, a, b, 1e-12 * b, 48, r);
}

/* The first lag in [a, b] where the change dips below 0.3 of the
 * variation (it rises from 0 at lag 0, so a dip is a local minimum after a
 * fall), on a grid of h, refined: the lag and its change into *q; 0 if
 * none. */
static double first_dip(const vi_identify *id, double a, double b, double h, double rms,
                        int sd, double *q)
{
  double r0 = NAN, r1 = NAN;
  int nl = (int)((b - a) / h) + 1;
  for (int l = 0; l <= nl; l++) {
    double P = a + l * h, r2 = lag_change(id, P, rms, sd);
    if (r1 < 0.3 && r1 <= r2 && r1 < r0) return lag_min(id, P - 2.0 * h, P, rms, sd, q);
    r0 = r1;
    r1 = r2;
  }
  return 0.0;
}

double vi_id_data_lag(vi_identify *id, double pmax)
{
  /* the change over a lag from at most 4096 samples of the recording (a
   * long one's 64 000 took 5 s of scanning otherwise) against its partners
   * interpolated in the whole */
  int ns = id->ns, sd = ns > 4096 ? ns / 4096 : 1;
  double span = id->t[ns - 1] - id->t[0], dt = span / (ns - 1);
  double rms = rms_of(id), pmin = 4.0 * dt;
  pmax = fmin(pmax, span / 1.5);
  if (!(pmax > pmin) || !(rms > 0.0)) {
    vi_fail(id->errmsg, VI_ERR_ARG, "the recording is too short (or constant) to show "
            "its own period, which fits the forcing frequency");
    return 0.0;
  }
  /* the first dip on a grid of half a sample or finer */
  double h = fmax(0.5 * dt, (pmax - pmin) / 4000.0), q1 = NAN;
  double P1 = first_dip(id, pmin, pmax, h, rms, sd, &q1);
  if (P1 == 0.0 && pmax < span / 1.5) {
    /* none where the forcing frequency's range puts it: look on, to say
     * where it repeats (a recording in milliseconds, a model in seconds) */
    h = fmax(0.5 * dt, (span / 1.5 - pmax) / 4000.0);
    P1 = first_dip(id, pmax, span / 1.5, h, rms, sd, &q1);
    pmax = span / 1.5;
  }
  if (P1 == 0.0) {
    vi_fail(id->errmsg, VI_ERR_ARG, "the recording repeats with no period up to %g (its "
            "span %g / 1.5): a motion that is not periodic, or too short a recording to "
            "fit the forcing frequency from", pmax, span);
    return 0.0;
  }
  /* a motion of period k P1 whose parts nearly repeat: the smallest
   * multiple that repeats as well as the best (vi_id_data_period's rule) */
  double rk[MAX_N + 1], Pk[MAX_N + 1], best = q1, P = P1;
  int K = 1;
  rk[1] = q1;
  Pk[1] = P1;
  for (int k = 2; k <= MAX_N && k * P1 <= pmax; k++, K++) {
    Pk[k] = lag_min(id, k * P1 - 2.0 * h, k * P1 + 2.0 * h, rms, sd, &rk[k]);
    best = fmin(best, rk[k]);
  }
  for (int k = K; k >= 1; k--)
    if (rk[k] < 0.3 && rk[k] <= fmax(1.5 * best, best + 0.05)) P = Pk[k];
  /* a signal too rich in harmonics to interpolate, an accelerometer's,
   * repeats only where its samples line up (61.3 samples a period: every
   * 3 periods, to about a sample): P may be a multiple of its period,
   * known to a sample.  The whole record folded with P / k, for each k,
   * finds the period to a fraction of a sample over the span: the
   * shortest of those that fold clearly better than P (folded with a lag
   * its samples nearly repeat over, the record lands them on each other
   * and shows no error of the lag) and within twice the best RMS.  Not
   * where P folds as well: a recording sampled in step with its period
   * folds as well with many a P / k that lands each sample on its own
   * copies from other periods (Fig. 2's 64 a period: k = 3, 5, 7). */
  double fr[MAX_N + 1], Pf[MAX_N + 1], fbest = HUGE_VAL;
  int kf = 0;
  for (int k = 1; k <= MAX_N && P / k >= pmin; k++, kf++) {
    Pf[k] = vi_id_fold_period(id, P / k, 2.0 * h / k, k == 1 ? HUGE_VAL : fr[1], &fr[k]);
    if (fr[k] < fbest) fbest = fr[k];
  }
  for (int k = kf; k >= 2; k--)
    if (fr[k] < 0.5 * fr[1] && fr[k] <= 2.0 * fbest) return Pf[k];
  return kf ? Pf[1] : P;
}

/* Starting shift: the best of 128 over one orbit period, on the first two
 * periods of the recording. */
double vi_id_scan_shift(vi_identify *id, double *cost_out)
{
  if (cost_out) *cost_out = HUGE_VAL;
  double best = 0.0, bc = HUGE_VAL, s[VI_ID_BLOCK], tau[VI_ID_BLOCK];
  int N = id->N, use = 0, jj[VI_ID_BLOCK];
  vi_id_track tk;
  if (vi_id_track_init(&tk, id->cur, id->xf, &id->o)) return 0.0;
  double P = tk.P;
  tk.halves = vi_id_halves(id->ych);
  while (use < id->ns && id->t[use] - id->t[0] < 2.0 * P && use < 1024) use++;
  for (int k = 0; k < 128; k++) {
    double t0 = k * P / 128.0, cost = 0.0;
    for (int i0 = 0; i0 < use; i0 += VI_ID_BLOCK) {
      int nk = use - i0 < VI_ID_BLOCK ? use - i0 : VI_ID_BLOCK;
      for (int i = 0; i < nk; i++) s[i] = id->t[i0 + i] + t0;
      vi_id_track_states(&tk, nk, s, jj, tau, NULL, tk.Z, NULL);
      if (id->ych == 2) vi_id_accel_block(id->cur, nk, 1, s, tk.Z, tk.A);
      for (int i = 0; i < nk; i++) {
        const double *z = id->ych == 2 ? tk.A + (size_t)i * N
                                       : tk.Z + (size_t)i * 2 * N + (size_t)id->ych * N;
        double e = id->y[i0 + i] - vi_dot(N, id->c, z);
        cost += e * e;
      }
    }
    if (cost < bc) {
      bc = cost;
      best = t0;
    }
  }
  vi_id_track_free(&tk);
  if (cost_out) *cost_out = bc;
  return best;
}

/* 1 when orbit c is one the fit may use: admissible, and stable unless
 * unstable ones are wanted. */
static int usable(vi_identify *id, const orb *c)
{
  const vi_model *m = id->cur;
  int ok = 0;
  if (vi_orbit_pnm_admissible_stops(m, c->n, c->m, c->stop, c->t, c->x, c->v, id->N,
                                    NULL, &ok) || !ok ||
      vi_orbit_pnm_multipliers_stops(m, c->n, c->m, c->stop, c->t, c->x, c->v,
                                     id->N, id->mre, id->mim))
    return 0;
  if (!id->stable_only) return 1;
  for (int i = 0; i < 2 * id->N; i++)
    if (!(hypot(id->mre[i], id->mim[i]) < 1.0)) return 0;
  return 1;
}

/* Orbit c scored against the recording (the shift scan's cost); kept in
 * slot s of best[] when it scores better than what is there. */
static void consider(vi_identify *id, const orb *c, orb *best, double *bc, int s)
{
  orb save = id->o;
  double cost = HUGE_VAL;
  id->o = *c; /* borrow its buffers for the scan */
  vi_id_scan_shift(id, &cost);
  id->o = save;
  if (cost < bc[s]) {
    bc[s] = cost;
    vi_id_orb_copy(&best[s], c, id->N);
  }
}

int vi_id_orbit_types(vi_identify *id, int nd, orb *best, double *bc)
{
  const vi_model *m = id->cur;
  int N = id->N, found = 0, cap = 16, st;
  for (int s = 0; s < VI_ID_SLOTS; s++) bc[s] = HUGE_VAL;
  orb cand, p2[8];
  memset(&cand, 0, sizeof cand);
  memset(p2, 0, sizeof p2);
  int nomem = vi_id_orb_alloc(&cand, N);
  for (int k = 0; k < 8; k++) nomem |= vi_id_orb_alloc(&p2[k], N);
  double *sx = malloc(sizeof(double) * (size_t)N * 2 * cap), *sv = sx ? sx + (size_t)N * cap : NULL;
  double *st_ = malloc(sizeof(double) * cap);
  if (nomem || !sx || !st_) {
    st = vi_fail(id->errmsg, VI_ERR_NOMEM, "out of memory");
    goto done;
  }
  char why[VI_MSG_LEN] = "";
  int tn = 0, tm = 0;
  /* the transient's motion, whatever its impacts per period */
  if (!seed_orbit(id, &cand)) {
    tn = cand.n;
    tm = cand.m;
    if (cand.n == nd) consider(id, &cand, best, bc, cand.m == 1 ? 0 : cand.m == 2 ? 1 : 2);
  } else {
    snprintf(why, sizeof why, "%s", id->errmsg);
  }
  /* every stable admissible P(nd, 1) of the impact-phase scan (none
   * where it does not apply: several stops, no modes) */
  st = vi_orbit_p1_scan_polled(m, nd, 256, st_, sx, sv, N, cap, &found,
                               vi_id_poll_fn, id);
  if (st != VI_CANCELLED && st != VI_ERR_NOMEM) st = VI_OK;
  else found = 0;
  for (int k = 0; !st && k < found && k < cap; k++) {
    orb c1 = cand;
    c1.n = nd;
    c1.m = 1;
    c1.stop[0] = 0;
    c1.t[0] = st_[k];
    memcpy(c1.x, sx + (size_t)k * N, sizeof(double) * N);
    memcpy(c1.v, sv + (size_t)k * N, sizeof(double) * N);
    if (!usable(id, &c1)) continue;
    vi_id_orb_normalise(&c1, vi_id_period_of(m, nd));
    consider(id, &c1, best, bc, 0);
  }
  /* and of the two-impact scan (one stop, small models) */
  if (!st) st = vi_id_scan_p2(id, nd, p2, 8, &found);
  if (st == VI_CANCELLED) st = vi_fail(id->errmsg, st, "cancelled");
  else if (st) st = vi_fail(id->errmsg, st, "out of memory");
  for (int k = 0; !st && k < found; k++)
    if (usable(id, &p2[k])) consider(id, &p2[k], best, bc, 1);
  if (!st && !(bc[0] < HUGE_VAL || bc[1] < HUGE_VAL || bc[2] < HUGE_VAL)) {
    if (tn)
      st = vi_fail(id->errmsg, VI_ERR_NOT_CONVERGED,
                   "the recording repeats every %d forcing period(s), but "
                   "the model at the starting values settles on P(%d,%d) "
                   "and the impact-phase scans find no %sP(%d,1) or P(%d,2) "
                   "orbit: start nearer", nd, tn, tm,
                   id->stable_only ? "stable " : "", nd, nd);
    else
      st = vi_fail(id->errmsg, VI_ERR_NOT_CONVERGED, "%s",
                   why[0] ? why : "no periodic orbit at the starting values");
  }
done:
  free(cand.x);
  free(cand.v);
  for (int k = 0; k < 8; k++) {
    free(p2[k].x);
    free(p2[k].v);
  }
  free(sx);
  free(st_);
  return st;
}

/* The model's orbit the recording shows, period nd forcing periods: the
 * transient's motion and every stable admissible P(nd, 1) and P(nd, 2)
 * orbit of the impact-phase scans (the start may lie where several
 * coexist, or where the transient settles on another), the one closest to
 * the recording. */
int vi_id_choose_orbit(vi_identify *id, int nd, double *cost_out)
{
  orb best[VI_ID_SLOTS];
  double bc[VI_ID_SLOTS];
  int st = VI_OK, N = id->N;
  memset(best, 0, sizeof best);
  for (int s = 0; s < VI_ID_SLOTS && !st; s++) st = vi_id_orb_alloc(&best[s], N);
  if (st) st = vi_fail(id->errmsg, VI_ERR_NOMEM, "out of memory");
  if (!st) st = vi_id_orbit_types(id, nd, best, bc);
  if (!st) {
    int b = 0;
    for (int s = 1; s < VI_ID_SLOTS; s++)
      if (bc[s] < bc[b]) b = s;
    vi_id_orb_copy(&id->o, &best[b], N);
    if (cost_out) *cost_out = bc[b];
  }
  for (int s = 0; s < VI_ID_SLOTS; s++) {
    free(best[s].x);
    free(best[s].v);
  }
  return st;
}
