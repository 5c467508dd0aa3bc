/* vi_grid.c - the uniform-grid scanner of the closed-form flows
 * (vi_grid.h). */
#include <math.h>

#include "vi_grid.h"

static inline double mx(double a, double b) { return a > b ? a : b; }

void vi_grid_start(vi_grid *g, double t0, double h, double W)
{
  g->t0 = t0;
  g->h = h;
  g->k = 0;
  vi_phase r = vi_phase_at(W, h); /* the grid step's rotation */
  g->cr = r.c;
  g->sr = r.s;
  g->next_ok = 0;
  g->srch = 0;
  g->since = 0;
  g->found = -1;
}

/* t_k becomes t_{k+1}: the buffers swap. */
static void commit(vi_grid *g)
{
  double *t1 = g->wk, *t2 = g->wdk;
  g->wk = g->wn;
  g->wdk = g->wdn;
  g->wn = t1;
  g->wdn = t2;
  t1 = g->fk;
  t2 = g->fdk;
  g->fk = g->fn;
  g->fdk = g->fdn;
  g->fn = t1;
  g->fdn = t2;
  g->ck = g->cn;
  g->sk = g->sn;
  g->k++;
  g->steps++;
  g->next_ok = 0;
}

int vi_grid_step(vi_sim *s, vi_grid *g, const vi_grid_ops *ops, void *d,
                 double t_end, int *event)
{
  *event = VI_STEP_NONE;
  for (int it = 0; it < ops->batch; it++) {
    /* the host's poll between grid steps: a pointer test without one */
    if (it > 0 && vi_sim_cancelled(s)) return VI_CANCELLED;
    double tk = g->t0 + (double)g->k * g->h;
    double tb = g->t0 + (double)(g->k + 1) * g->h;
    if (!g->next_ok) {
      g->anch = ++g->since >= ops->anchor_every;
      if (g->anch) {
        ops->anchor(d, tb);
      } else {
        g->cn = g->ck * g->cr - g->sk * g->sr;
        g->sn = g->sk * g->cr + g->ck * g->sr;
        int st = ops->advance(d);
        if (st) return st;
      }
      g->next_ok = 1;
      g->srch = 0;
    }
    if (!g->srch) {
      int st = ops->search(d, tk, tb, &g->tstar, &g->found);
      if (st < 0 || st == VI_CANCELLED) return st;
      g->srch = 1;
    }
    if (g->found >= 0 && g->tstar <= t_end)
      return ops->crossing(s, d, fmax(g->tstar, s->t), g->found, event);
    if (t_end < tb) { /* the run ends inside this interval: keep t_{k+1} */
      double gap = ops->gap_at(s, d, t_end);
      return ops->move(s, d, t_end, gap);
    }
    int st = ops->move(s, d, tb, ops->report(s, d, g->fn));
    if (st) return st;
    commit(g);
    if (g->anch) {
      g->since = 0;
      ops->bounds(d);
    }
    if (s->t >= t_end) return VI_OK;
  }
  return VI_OK;
}

double vi_herm_max(double fa, double fda, double fb, double fdb, double w,
                   double *c)
{
  double cc[4];
  if (!c) c = cc;
  c[0] = fa;
  c[1] = w * fda;
  c[2] = 3.0 * (fb - fa) - w * (2.0 * fda + fdb);
  c[3] = 2.0 * (fa - fb) + w * (fda + fdb);
  double top = mx(fa, fb);
  /* stationary points: c1 + 2 c2 s + 3 c3 s^2 = 0 */
  double A = 3.0 * c[3], B = 2.0 * c[2], C = c[1], r[2];
  int nr = 0;
  if (A == 0.0) {
    if (B != 0.0) r[nr++] = -C / B;
  } else {
    double disc = B * B - 4.0 * A * C;
    if (disc >= 0.0) {
      double qq = -0.5 * (B + copysign(sqrt(disc), B));
      if (qq != 0.0) {
        r[nr++] = qq / A;
        r[nr++] = C / qq;
      }
    }
  }
  for (int i = 0; i < nr; i++)
    if (r[i] > 0.0 && r[i] < 1.0) {
      double s = r[i];
      top = mx(top, c[0] + s * (c[1] + s * (c[2] + s * c[3])));
    }
  return top;
}
