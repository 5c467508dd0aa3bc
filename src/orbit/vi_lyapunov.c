/* vi_lyapunov.c - the largest Lyapunov exponent of an impacting motion
 * (MODEL.md section 13).
 *
 * A tangent vector u is carried along the simulated trajectory: between
 * impacts by the exact state-transition matrix e^{A tau}, at each impact by
 * its saltation matrix S = R + d g^T / v_n (vi_impact_salt_apply), and
 * renormalised
 * after every factor (Benettin, Galgani, Giorgilli and Strelcyn, Meccanica
 * 15 (1980) 9).  The exponent is the mean growth rate of log |u|.  Nothing
 * is differenced, so the estimate is limited by the length of the run, not
 * by a perturbation size.  A flight longer than one forcing period is cut
 * into periods so that e^{A tau} u neither underflows nor overflows.
 *
 * Nothing 2n x 2n is formed per step: S acts on u as R plus a rank-one
 * term, O(n^2) with the vector fields f-, f+; e^{A tau} u goes through the
 * modes of a proportional model (vi_var_stm_apply, O(n^2)).  Other damping
 * needs e^{A tau} itself: the one of a whole forcing period, the common
 * step, is built once per call and applied by dgemv.
 *
 * Sliding (sticking) and summed chattering tails have no saltation matrix
 * of this form: a motion that meets them is refused (VI_ERR_UNSUPPORTED),
 * never reported with a wrong exponent. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cblas.h>

#include "vi_impact_internal.h"
#include "vi_orbit_internal.h"

typedef struct {
  const vi_model *m;
  int n2;
  double t_prev, cap, sum, t_last_impact;
  /* u, the tangent [2n]; d, the saltation jump [2n]; z [2n], work [4n];
   * Phi, Pcap [2n x 2n]: non-proportional damping only */
  double *u, *d, *z, *work, *Phi, *Pcap;
  int have_cap, bad_kind, simultaneous, st;
} tangent;

/* u renormalised; the logarithm of its growth is summed */
static int renorm(tangent *L)
{
  double nrm = cblas_dnrm2(L->n2, L->u, 1);
  if (!(nrm > 0.0) || !isfinite(nrm)) return VI_ERR_NONFINITE;
  L->sum += log(nrm);
  cblas_dscal(L->n2, 1.0 / nrm, L->u, 1);
  return VI_OK;
}

/* u <- e^{A tau} u */
static int flow(tangent *L, double tau)
{
  const vi_model *m = L->m;
  if (m->proportional) return vi_var_stm_apply(m, tau, L->u, L->work);
  const double *Phi = L->Pcap;
  int st;
  if (tau != L->cap) {
    if ((st = vi_var_stm(m, tau, L->Phi))) return st;
    Phi = L->Phi;
  } else if (!L->have_cap) {
    if ((st = vi_var_stm(m, tau, L->Pcap))) return st;
    L->have_cap = 1;
  }
  cblas_dgemv(CblasColMajor, CblasNoTrans, L->n2, L->n2, 1.0, Phi, L->n2,
              L->u, 1, 0.0, L->work, 1);
  memcpy(L->u, L->work, sizeof(double) * (size_t)L->n2);
  return VI_OK;
}

/* the free flow from t_prev to t, at most one forcing period at a time */
static int advance(tangent *L, double t)
{
  while (L->t_prev < t) {
    double tau = t - L->t_prev > L->cap ? L->cap : t - L->t_prev;
    int st = flow(L, tau);
    if (st || (st = renorm(L))) return st;
    L->t_prev = tau == t - L->t_prev ? t : L->t_prev + tau;
  }
  return VI_OK;
}

static int on_event(const vi_event *ev, void *user)
{
  tangent *L = user;
  if (ev->kind != VI_EVENT_IMPACT) {
    L->bad_kind = ev->kind;
    return 1;
  }
  /* two impacts at one instant: Newton's law for simultaneous contacts,
   * whose derivative is not the product of two saltation matrices */
  if (ev->t == L->t_last_impact) {
    L->simultaneous = 1;
    return 1;
  }
  int n = L->m->n;
  if ((L->st = advance(L, ev->t))) return 1;
  memcpy(L->z, ev->x, sizeof(double) * (size_t)n);
  memcpy(L->z + n, ev->v_minus, sizeof(double) * (size_t)n);
  double vn = vi_var_salt_jump(L->m, ev->stop, ev->t, L->z, L->d, L->work);
  vi_impact_salt_apply(L->m, ev->stop, vn, L->d, 1, L->u, L->n2, L->work);
  if ((L->st = renorm(L))) return 1;
  L->t_last_impact = ev->t;
  return 0;
}

/* the run from the current time to t with the tangent carried along */
static int carry(vi_orbit *o, tangent *L, double t)
{
  int64_t chat0 = vi_sim_stat(o->sim, VI_STAT_CHATTER_SKIPPED);
  int st = vi_sim_run(o->sim, t);
  if (L->st) return vi_fail(o->errmsg, L->st, "lyapunov: the tangent flow "
                            "failed at t = %.17g", L->t_prev);
  if (L->bad_kind >= 0 || L->simultaneous)
    return vi_fail(o->errmsg, VI_ERR_UNSUPPORTED, "lyapunov: the motion %s "
                   "(t = %.17g): no saltation matrix of a single impact",
                   L->simultaneous ? "hits two stops at one instant"
                   : "sticks or releases", L->t_prev);
  if (st) return vi_fail(o->errmsg, st, "lyapunov: %s", vi_sim_errmsg(o->sim));
  if (vi_sim_stat(o->sim, VI_STAT_CHATTER_SKIPPED) != chat0)
    return vi_fail(o->errmsg, VI_ERR_UNSUPPORTED, "lyapunov: a chattering "
                   "tail was summed before t = %.17g, its impacts are not "
                   "resolved one by one", t);
  if ((st = advance(L, t)))
    return vi_fail(o->errmsg, st, "lyapunov: the tangent flow failed at "
                   "t = %.17g", L->t_prev);
  return VI_OK;
}

int vi_orbit_lyapunov(vi_orbit *o, double transient, double periods,
                      double *lambda, double *spread)
{
  if (!o) return VI_ERR_ARG;
  if (!lambda)
    return vi_fail(o->errmsg, VI_ERR_ARG, "lyapunov: lambda is NULL");
  if (!(transient >= 0.0) || !isfinite(transient) || !(periods >= 2.0) ||
      !isfinite(periods) || transient + periods > 1e9)
    return vi_fail(o->errmsg, VI_ERR_ARG, "lyapunov: transient %g must be "
                   ">= 0 and periods %g >= 2 (at most 1e9 in all)",
                   transient, periods);
  const vi_model *m = o->m;
  int n = m->n, n2 = 2 * n;
  /* the work area of the whole call: no allocation per step */
  size_t nn = m->proportional ? 0 : (size_t)n2 * n2, len = 2 * nn + 5 * (size_t)n2;
  tangent L = {.m = m, .n2 = n2, .cap = o->T, .bad_kind = -1,
               .t_last_impact = -HUGE_VAL};
  double *blk = malloc(sizeof(double) * len);
  if (!blk) return vi_fail(o->errmsg, VI_ERR_NOMEM, "lyapunov: %zu doubles", len);
  L.u = blk;
  L.d = L.u + n2;
  L.z = L.d + n2;
  L.work = L.z + n2;
  L.Phi = nn ? L.work + 2 * (size_t)n2 : NULL;
  L.Pcap = nn ? L.Phi + nn : NULL;
  /* a start vector with a component along every direction */
  for (int i = 0; i < n2; i++) L.u[i] = 1.0 / sqrt((double)n2) * (1.0 + 0.1 * i);

  double t0 = 0.0, t1 = transient * o->T, th = (transient + 0.5 * periods) * o->T,
         t2 = (transient + periods) * o->T;
  int st;
  if ((st = vi_sim_set_event_callback(o->sim, NULL, NULL, NULL)) ||
      (st = vi_sim_set_initial(o->sim, t0, o->x0, o->v0)) ||
      (t1 > t0 && (st = vi_sim_run(o->sim, t1)))) {
    st = vi_fail(o->errmsg, st, "lyapunov: transient: %s", vi_sim_errmsg(o->sim));
    goto done;
  }
  L.t_prev = t1;
  if ((st = vi_sim_set_event_callback(o->sim, on_event, &L, NULL))) {
    st = vi_fail(o->errmsg, st, "lyapunov: %s", vi_sim_errmsg(o->sim));
    goto done;
  }
  if ((st = carry(o, &L, th))) goto done;
  double first = L.sum;
  if ((st = carry(o, &L, t2))) goto done;
  double second = L.sum - first, half = th - t1;
  *lambda = L.sum / (t2 - t1);
  if (spread) *spread = fabs(first / half - second / (t2 - th));
done:
  vi_sim_set_event_callback(o->sim, NULL, NULL, NULL);
  free(blk);
  return st;
}
