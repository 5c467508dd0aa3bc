/* vi_exact_scan.c - the closed-form flow scanned step by step, for
 * non-proportional damping (vi_general.c): vi_exact.c hands such models to
 * this backend.
 *
 * Between impacts the motion is known exactly, so the gap g(t) = w.x(t) -
 * x_s is an explicit function.  It is scanned in steps of 1/16 of the
 * shortest period present in g; in each step the sign of g' splits the step
 * at an extremum (located by Brent), and a contact is a rising crossing of a
 * monotone piece, also located by Brent to round-off.  Checking the maxima
 * is what catches grazing contacts that a sign test at step ends misses.
 * With several stops every gap is scanned so over each step and the
 * earliest contact over all of them is the one reported. */
#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vi_exact_internal.h"

typedef struct sc_data {
  int kind; /* EX_KIND_SCAN */
  vi_sim *s;
  double t0;          /* start of the current flight */
  double *u0, *v0;    /* homogeneous initial values per mode [n] */
  double *q, *qd;     /* modal state of the last evaluation [n] */
  double h;           /* scan step */
  double ta;          /* left end of the next scan step */
  double *ga, *gda;   /* every stop's gap and rate there [ns] */
  double *gb, *gdb;   /* and at the step's end [ns] */
  int ns, stop;       /* stops; the one gap_fn and rate_fn follow */
  double *rates;      /* ledger integrands [4n] */
  vi_gflow *gf;       /* non-proportional damping: the first-order flow */
  int handover;       /* the flow would cancel a far larger particular part */
  double *zfull;      /* its state at the last full evaluation [2n] */
  int64_t steps, evals;
} sc_data;

/* At t: stop k's gap and rate (k >= 0), or every stop's (k < 0: g, gd
 * [ns]); with full != 0 (and always for k < 0) also the modal state in q,
 * qd.  No stop is special: each gap comes straight from the closed form
 * (the complex modes' w_k.V, or the modes stop k sees). */
static void sc_eval(sc_data *d, double t, int k, double *g, double *gd,
                    int full)
{
  const vi_model *m = d->s->m;
  int n = m->n;
  if (d->gf) {
    vi_gflow_eval(d->gf, m, t, k, g, gd, full || k < 0 ? d->zfull : NULL);
    d->evals++;
    if (full || k < 0) /* modal velocities for the ledger */
      for (int j = 0; j < n; j++) {
        double q = 0.0, qd = 0.0;
        for (int i = 0; i < n; i++) {
          double p = m->PsiTM[j + (size_t)i * n];
          q += p * d->zfull[2 * (size_t)i];
          qd += p * d->zfull[2 * (size_t)i + 1];
        }
        d->q[j] = q;
        d->qd[j] = qd;
      }
    return;
  }
  double tau = t - d->t0;
  vi_phase p = vi_phase_at(m->omega_f, t);
  const double *psi = vi_stop_psi(m, k < 0 ? 0 : k);
  for (int j = 0; j < n; j++) {
    if (!full && k >= 0 && psi[j] == 0.0) continue;
    double qp, qpd, u, ud;
    vi_flow_particular(m, d->s->flow, j, &p, tau, &qp, &qpd);
    vi_flow_homogeneous(m->lambda[j], m->D[j + (size_t)j * n], d->u0[j],
                        d->v0[j], tau, &u, &ud);
    d->q[j] = qp + u;
    d->qd[j] = qpd + ud;
  }
  d->evals++;
  int k0 = k < 0 ? 0 : k, k1 = k < 0 ? d->ns : k + 1;
  for (int q = k0; q < k1; q++) {
    const double *pq = vi_stop_psi(m, q);
    double a = 0.0, b = 0.0;
    for (int j = 0; j < n; j++) {
      if (pq[j] == 0.0) continue;
      a += pq[j] * d->q[j];
      b += pq[j] * d->qd[j];
    }
    g[q - k0] = a - m->xsv[q];
    gd[q - k0] = b;
  }
}

static void sc_eval_k(sc_data *d, double t, int k, double *g, double *gd)
{
  sc_eval(d, t, k, g, gd, 0);
}

/* Every stop's gap and rate at t into g, gd [ns]. */
static void sc_eval_all(sc_data *d, double t, double *g, double *gd)
{
  sc_eval(d, t, -1, g, gd, 1);
}

static double gap_fn(double t, void *p)
{
  sc_data *d = p;
  double g, gd;
  sc_eval_k(d, t, d->stop, &g, &gd);
  return g;
}

static double rate_fn(double t, void *p)
{
  sc_data *d = p;
  double g, gd;
  sc_eval_k(d, t, d->stop, &g, &gd);
  return gd;
}

/* x = Psi q, v = Psi q' into an interleaved state. */
static void to_state(const vi_model *m, const sc_data *d, double *z)
{
  int n = m->n;
  if (d->gf) {
    memcpy(z, d->zfull, sizeof(double) * 2 * n);
    return;
  }
  for (int i = 0; i < n; i++) {
    double x = 0.0, v = 0.0;
    for (int j = 0; j < n; j++) {
      double p = m->Psi[i + (size_t)j * n];
      x += p * d->q[j];
      v += p * d->qd[j];
    }
    z[2 * (size_t)i] = x;
    z[2 * (size_t)i + 1] = v;
  }
}

static void sc_destroy(vi_sim *s)
{
  sc_data *d = s->be_data;
  if (d) {
    vi_gflow_free(d->gf);
    free(d->u0);
  }
  free(d);
  s->be_data = NULL;
}

static int sc_start(vi_sim *s)
{
  const vi_model *m = s->m;
  int n = s->n;
  if (s->sticking) /* the driver runs sticking phases on CVODE */
    return vi_fail(s->errmsg, VI_ERR_STATE, "internal: the closed form "
                   "cannot start in a sticking phase (t = %.17g)", s->t);
  sc_data *d = s->be_data;
  if (!d) {
    d = calloc(1, sizeof *d);
    if (d) d->u0 = malloc(sizeof(double) * (10 * (size_t)n + 4 * (size_t)m->ns));
    if (d && !m->proportional) d->gf = vi_gflow_create(s->flow->gen);
    if (!d || !d->u0 || (!m->proportional && !d->gf)) {
      if (d) free(d->u0);
      free(d);
      return vi_fail(s->errmsg, VI_ERR_NOMEM, "out of memory");
    }
    d->v0 = d->u0 + n;
    d->q = d->v0 + n;
    d->qd = d->q + n;
    d->rates = d->qd + n;
    d->zfull = d->rates + 4 * (size_t)n;
    d->ga = d->zfull + 2 * (size_t)n;
    d->gda = d->ga + m->ns;
    d->gb = d->gda + m->ns;
    d->gdb = d->gb + m->ns;
    d->ns = m->ns;
    d->kind = EX_KIND_SCAN;
    d->s = s;
    double wtop = m->omega_f;
    for (int k = 0; k < m->ns; k++)
      for (int j = 0; j < n; j++)
        if (vi_stop_psi(m, k)[j] != 0.0) wtop = fmax(wtop, m->omega[j]);
    if (d->gf) wtop = vi_general_top_frequency(s->flow->gen, m->omega_f);
    d->h = wtop > 0.0 ? M_PI / (8.0 * wtop) : HUGE_VAL;
    s->be_data = d;
  }
  d->t0 = s->t;
  d->ta = s->t;
  if (d->gf) {
    vi_gflow_start(d->gf, m, s->t, s->z);
    sc_eval_all(d, d->ta, d->ga, d->gda);
    s->gap = d->ga[0];
    s->z_stale = 0;
    /* The gap is the sum of a particular part and a transient that cancel
     * when a static offset or a resonant response dwarfs the motion (a
     * very soft structure under load): hand over to CVODE rather than lose
     * those digits (issue 9). */
    d->handover = 0;
    for (int k = 0; k < m->ns && !d->handover; k++) { /* every stop's gap */
      const double *w = vi_stop_w(m, k);
      double hsc = vi_general_particular_scale(s->flow->gen, k);
      double msc = fabs(m->xsv[k]) + s->atol * s->wnorms[k];
      for (int i = 0; i < n; i++) msc += fabs(w[i] * s->z[2 * (size_t)i]);
      d->handover = hsc > 1e6 * msc;
      if (d->handover)
        snprintf(s->handover_why, sizeof s->handover_why,
                 "the particular solution (%.3g) is %.2g times the scale "
                 "of stop %d's gap at t = %.9g: the closed form would cancel "
                 "it", hsc, hsc / msc, k + 1, s->t);
    }
    return VI_OK;
  }
  /* modal state now, minus the particular solution: the homogeneous part */
  vi_phase ph = vi_phase_at(m->omega_f, s->t);
  for (int j = 0; j < n; j++) {
    double q = 0.0, qd = 0.0, qp, qpd;
    for (int i = 0; i < n; i++) {
      double p = m->PsiTM[j + (size_t)i * n];
      q += p * s->z[2 * (size_t)i];
      qd += p * s->z[2 * (size_t)i + 1];
    }
    vi_flow_particular(m, d->s->flow, j, &ph, 0.0, &qp, &qpd);
    d->u0[j] = q - qp;
    d->v0[j] = qd - qpd;
  }
  d->ta = s->t;
  sc_eval_all(d, d->ta, d->ga, d->gda);
  return VI_OK;
}

/* First rising crossing of the gap in [a, b], or 0 if none.  g' changes sign
 * at most once in a scan step, at an extremum c; only rising pieces count. */
static int find_contact(vi_sim *s, sc_data *d, double a, double ga,
                        double gda, double b, double gb, double gdb,
                        double *tc)
{
  double lo = a, glo = ga, hi = b, ghi = gb;
  if ((gda > 0.0) != (gdb > 0.0) && gda != 0.0 && gdb != 0.0) {
    double c;
    int st = vi_sim_bracket(s, rate_fn, d, a, b, &c);
    if (st) return st;
    double gc = gap_fn(c, d);
    if (gda > 0.0) { /* maximum at c: rising piece [a, c] */
      s->stats[VI_STAT_GRAZE_CHECKS]++;
      hi = c;
      ghi = gc;
    } else {         /* minimum at c: rising piece [c, b] */
      lo = c;
      glo = gc;
    }
  }
  if (!(glo < 0.0 && ghi >= 0.0)) return 0;
  int st = vi_sim_bracket(s, gap_fn, d, lo, hi, tc);
  return st ? st : 1;
}

/* Ledger integrals over [a, b] by 8-point Gauss-Legendre: a scan step spans
 * at most pi/4 of the fastest phase in the integrands (products of modes,
 * frequency <= 2 omega_top), where the rule's error is below round-off. */
static void sc_quadrature(vi_sim *s, sc_data *d, double a, double b)
{
  double h = 0.5 * (b - a), mid = 0.5 * (a + b), g, gd, w;
  for (int k = 0; k < 8; k++) {
    double t = vi_gl8_node(k, mid, h, &w);
    sc_eval(d, t, 0, &g, &gd, 1);
    vi_ledger_accumulate(s->led, t, d->qd, NULL, w);
  }
}

static int sc_step(vi_sim *s, double t_end, int *event)
{
  sc_data *d = s->be_data;
  if (d->handover) {
    *event = VI_STEP_HANDOVER;
    return VI_OK;
  }
  double step = d->h;
  if (d->gf) { /* overdamped transients have no period, only a rate */
    double tol = HUGE_VAL;
    for (int k = 0; k < d->ns; k++) tol = fmin(tol, vi_sim_gap_tol(s, k));
    double r = vi_gflow_live_rate(d->gf, d->ta, tol);
    if (r > 0.0) step = fmin(step, M_PI / (8.0 * r));
  }
  double b = fmin(d->ta + step, t_end), tc = HUGE_VAL;
  double *gb = d->gb, *gdb = d->gdb;
  int hit = 0;
  sc_eval_all(d, b, gb, gdb);
  d->steps++;
  for (int k = 0; k < d->ns; k++) {
    double t1 = HUGE_VAL;
    d->stop = k;
    int h = find_contact(s, d, d->ta, d->ga[k], d->gda[k], b, gb[k], gdb[k],
                         &t1);
    if (h < 0) return h;
    if (h && t1 < tc) {
      tc = t1;
      hit = 1;
      s->contact_stop = k;
    }
  }
  *event = hit ? VI_STEP_CONTACT : VI_STEP_NONE;
  s->t = hit ? tc : b;
  if (s->led) sc_quadrature(s, d, d->ta, s->t);
  double g, gd;
  sc_eval(d, s->t, 0, &g, &gd, 1);
  to_state(s->m, d, s->z);
  s->gap = g;
  s->z_stale = 0;
  d->ta = b;
  d->gb = d->ga; /* swap: the end is the next step's start */
  d->gdb = d->gda;
  d->ga = gb;
  d->gda = gdb;
  return VI_OK;
}

static int sc_dense(vi_sim *s, double t)
{
  sc_data *d = s->be_data;
  double g, gd;
  sc_eval(d, t, 0, &g, &gd, 1);
  to_state(s->m, d, s->zs);
  return VI_OK;
}

static int64_t sc_stat(const void *data, int which)
{
  const sc_data *d = data;
  if (which == VI_STAT_STEPS) return d->steps;
  if (which == VI_STAT_ROOT_EVALS) return d->evals;
  return 0;
}

const vi_backend vi_backend_exact_scan = {"exact", sc_start, sc_step,
                                          sc_dense, sc_stat, sc_destroy, NULL,
                                          NULL, NULL, NULL, NULL};
