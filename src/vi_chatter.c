/* vi_chatter.c - the sticking set and the chatter map: which stops are held,
 * the constrained acceleration, and the closed-form sum of a chattering
 * tail (Nordmark & Piiroinen 2009) that puts the start of sticking at its
 * accumulation point. */
#include <float.h>
#include <string.h>

#include "vi_sim_internal.h"

/* Remove the component along M^-1 w_k so that w_k.a = 0 (stop k's
 * constraint). */
static void constrain(const vi_sim *s, int k, double *a)
{
  const vi_model *m = s->m;
  const double *mw = vi_stop_minvw(m, k);
  double lam = vi_dot(s->n, vi_stop_w(m, k), a) / m->G[k + (size_t)k * m->ns];
  for (int i = 0; i < s->n; i++) a[i] -= lam * mw[i];
}

void vi_sim_constrain_set(const vi_sim *s, double *a, double *lam)
{
  const vi_model *m = s->m;
  int n = s->n, ns = s->nstick;
  double b[VI_CONTACT_MAX];
  for (int i = 0; i < ns; i++) b[i] = vi_dot(n, vi_stop_w(m, s->stick_k[i]), a);
  vi_small_solve(ns, s->stick_L, b);
  for (int i = 0; i < ns; i++) {
    const double *mw = vi_stop_minvw(m, s->stick_k[i]);
    for (int j = 0; j < n; j++) a[j] -= b[i] * mw[j];
    if (lam) lam[i] = b[i];
  }
}

/* Make the stops list [cnt] the sticking set: the projection of the
 * right-hand side needs the factor of their Delassus block. */
int vi_sim_set_sticking(vi_sim *s, const int *list, int cnt)
{
  const vi_model *m = s->m;
  for (int i = 0; i < cnt; i++) {
    s->stick_k[i] = list[i];
    for (int j = 0; j < cnt; j++)
      s->stick_L[i + j * cnt] = m->G[list[i] + (size_t)list[j] * m->ns];
  }
  s->nstick = cnt;
  s->sticking = cnt > 0;
  if (cnt > 1 && vi_small_cholesky(cnt, s->stick_L)) {
    s->nstick = 0;
    s->sticking = 0;
    return vi_fail(s->errmsg, VI_ERR_UNSUPPORTED, "sticking on %d stops at "
                   "once at t = %.17g, whose stop vectors are dependent "
                   "(Delassus block singular)", cnt, s->t);
  }
  return VI_OK;
}

int vi_sim_in_stick_set(const vi_sim *s, int k)
{
  for (int i = 0; i < s->nstick; i++)
    if (s->stick_k[i] == k) return 1;
  return 0;
}

/* The gap's free acceleration p = w_k.M^-1 (f - C v - K x) of stop k and
 * its first two rates along the constrained (sticking) motion from x, v
 * at t. */
void vi_chatter_push(vi_sim *s, int k, double t, const double *x,
                     const double *v, double *p)
{
  int n = s->n;
  const double *w = vi_stop_w(s->m, k);
  double *zz = s->zs, *acc = s->w1, *jerk = s->w2, *snap = s->w3;
  for (int i = 0; i < n; i++) {
    zz[2 * (size_t)i] = x[i];
    zz[2 * (size_t)i + 1] = v[i];
  }
  vi_sim_accel(s, t, zz, 0, acc);
  p[0] = vi_dot(n, w, acc);
  constrain(s, k, acc);
  vi_sim_accel_rate(s, t, 1, v, acc, jerk);
  p[1] = vi_dot(n, w, jerk);
  constrain(s, k, jerk);
  vi_sim_accel_rate(s, t, 2, acc, jerk, snap);
  p[2] = vi_dot(n, w, snap);
}

/* Sum a chattering tail in closed form (the chatter map of Nordmark &
 * Piiroinen 2009).  During a flight the gap obeys
 *   g'' + gamma g' + kappa g = p0 + p1 t,
 * the push p of the contact force and its rate along the sticking motion,
 * with the normal stiffness kappa and damping gamma of the structure seen
 * through the stop.  Each flight, from g = 0 at rate -u, is its Taylor
 * series (exact for this equation, and converging fast: a flight lasts at
 * most about half a normal period); its root gives the flight time and
 * the return speed, r times which starts the next.  The bounces are summed
 * until their speed is round-off of the first; for a constant load
 * (kappa = gamma = p1 = 0) this is the exact accumulation time
 * 2 u / (p0 (1 - r)).  Returns the duration, or -1 if by the model the
 * sequence does not accumulate (the mass leaves before the bounces die). */
enum { TAIL_TERMS = 40 };

static int tail_flight(double u, double a, double p1, double kappa,
                       double gamma, double *tau, double *vret)
{
  double c[TAIL_TERMS]; /* g(t) = sum c_k t^k */
  c[0] = 0.0;
  c[1] = -u;
  for (int k = 0; k + 2 < TAIL_TERMS; k++) {
    double q = k == 0 ? a : k == 1 ? p1 : 0.0;
    c[k + 2] = (q - kappa * c[k] - gamma * (k + 1) * c[k + 1]) /
               ((k + 2.0) * (k + 1.0));
  }
  /* start from the undamped flight's own root, (2 / w) atan(u w / a) */
  double w = sqrt(fmax(kappa, 0.0));
  double t = w > 0.0 ? 2.0 * atan(u * w / a) / w : 2.0 * u / a;
  for (int it = 0; it < 30; it++) { /* Newton on g(t) / t, root t > 0 */
    double f = 0.0, df = 0.0;
    for (int k = TAIL_TERMS - 1; k >= 1; k--) {
      df = df * t + f;
      f = f * t + c[k];
    }
    if (!(df != 0.0) || !isfinite(f)) return -1;
    double dt = f / df;
    t -= dt;
    if (!(t > 0.0)) return -1;
    if (fabs(dt) <= 4.0 * DBL_EPSILON * t) break;
  }
  /* the series must have converged at t: its last term is round-off */
  if (!(fabs(c[TAIL_TERMS - 1]) * pow(t, TAIL_TERMS - 1) <= 1e-16 * u * t))
    return -1;
  double v = 0.0;
  for (int k = TAIL_TERMS - 1; k >= 1; k--) v = v * t + k * c[k];
  *tau = t;
  *vret = v;
  return 0;
}

double vi_chatter_tail(double u, double r, double p0, double p1,
                       double kappa, double gamma, int64_t *count)
{
  double T = 0.0, u0 = u;
  int64_t k = 0;
  while (u > 1e-17 * u0) {
    double a = p0 + p1 * T, tau, vret;
    if (!(a > 0.0) || k > 1000000) return -1.0;
    if (tail_flight(u, a, p1, kappa, gamma, &tau, &vret) || !(vret > 0.0))
      return -1.0;
    T += tau;
    k++;
    u = r * vret;
  }
  *count = k;
  return T;
}

/* Normal stiffness and damping of the structure seen through stop k:
 * a displacement xi along n = M^-1 w / (w^T M^-1 w) changes the gap by xi
 * and its acceleration by -kappa xi (and -gamma xi' for a rate). */
void vi_chatter_normal(const vi_sim *s, int k, double *kappa,
                       double *gamma)
{
  const vi_model *m = s->m;
  const double *w = vi_stop_w(m, k), *mw = vi_stop_minvw(m, k);
  int n = s->n;
  double kk = 0.0, c = 0.0;
  for (int i = 0; i < n; i++) {
    if (w[i] == 0.0) continue;
    double ki = 0.0, ci = 0.0;
    for (int j = 0; j < n; j++) {
      size_t ij = (size_t)i + (size_t)j * (size_t)n;
      ki += m->MinvK[ij] * mw[j];
      ci += m->MinvC[ij] * mw[j];
    }
    kk += w[i] * ki;
    c += w[i] * ci;
  }
  double wmw = m->G[k + (size_t)k * m->ns];
  *kappa = kk / wmw;
  *gamma = c / wmw;
}
