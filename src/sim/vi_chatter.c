/* vi_chatter.c - the chatter map: the push and normal dynamics of a stop
 * under the sticking set (vi_sim_state.c), and the closed-form sum of a chattering
 * tail (Nordmark & Piiroinen 2009) that puts the start of sticking at its
 * accumulation point. */
#include <float.h>
#include <string.h>

#include "vi_chatter_internal.h"
#include "vi_impact_internal.h"
#include "vi_rhs.h"

/* Stop k's view of the sticking set: the other held stops S (their factor
 * in LS) and S with k (in Lk), k last.  Stop k chatters while S holds, so
 * its normal dynamics are those of the structure constrained on S.  With
 * dependent stop vectors S is taken as empty (the free structure). */
typedef struct held {
  int ns, list[VI_CONTACT_MAX + 1];
  double LS[VI_CONTACT_MAX * VI_CONTACT_MAX];
  double Lk[(VI_CONTACT_MAX + 1) * (VI_CONTACT_MAX + 1)];
} held;

static void held_around(const vi_sim *s, int k, held *h)
{
  h->ns = 0;
  for (int i = 0; i < s->nstick; i++)
    if (s->stick_k[i] != k) h->list[h->ns++] = s->stick_k[i];
  h->list[h->ns] = k;
  if (h->ns > 0 && (vi_sim_stick_factor(s->m, h->ns, h->list, h->LS) ||
                    vi_sim_stick_factor(s->m, h->ns + 1, h->list, h->Lk)))
    h->ns = 0;
  if (h->ns == 0) vi_sim_stick_factor(s->m, 1, h->list, h->Lk);
}

/* The gap's free acceleration p = w_k.a of stop k, a = M^-1 (f - C v - K x)
 * constrained on the other held stops, and its first two rates along the
 * motion sticking on them and on stop k from x, v at t.  The sticking
 * motion's projection P is constant, so its rates are P times the rates of
 * the free acceleration. */
void vi_chatter_push(vi_sim *s, int k, double t, const double *x,
                     const double *v, double *p)
{
  int n = s->n;
  const double *w = vi_stop_w(s->m, k);
  double *zz = s->zs, *acc = s->w1, *jerk = s->w2, *snap = s->w3;
  held h;
  held_around(s, k, &h);
  for (int i = 0; i < n; i++) {
    zz[2 * (size_t)i] = x[i];
    zz[2 * (size_t)i + 1] = v[i];
  }
  vi_sim_accel(s, t, zz, 0, acc);
  vi_sim_project(s, h.ns, h.list, h.LS, acc, NULL);
  p[0] = vi_dot(n, w, acc);
  vi_sim_project(s, h.ns + 1, h.list, h.Lk, acc, NULL);
  vi_sim_accel_rate(s, t, 1, v, acc, jerk);
  vi_sim_project(s, h.ns, h.list, h.LS, jerk, NULL);
  p[1] = vi_dot(n, w, jerk);
  vi_sim_project(s, h.ns + 1, h.list, h.Lk, jerk, NULL);
  vi_sim_accel_rate(s, t, 2, acc, jerk, snap);
  vi_sim_project(s, h.ns, h.list, h.LS, snap, NULL);
  p[2] = vi_dot(n, w, snap);
}

/* Sum a chattering tail in closed form (the chatter map of Nordmark &
 * Piiroinen 2009).  During a flight the gap obeys
 *   g'' + gamma g' + kappa g = p0 + p1 t + p2 t^2 / 2,
 * the push p of the contact force and its first two rates along the
 * sticking motion, with the normal stiffness kappa and damping gamma of the
 * structure seen through the stop.  (The second rate matters under a
 * harmonic load: leaving it out costs about |p2| / p Delta^3 over a tail
 * of duration Delta.)  Each flight, from g = 0 at rate -u, is its Taylor
 * series (exact for this equation, and converging fast: a flight lasts at
 * most about half a normal period); its root gives the flight time and
 * the return speed, r times which starts the next.  The bounces are summed
 * until their speed is round-off of the first; for a constant load
 * (kappa = gamma = p1 = 0) this is the exact accumulation time
 * 2 u / (p0 (1 - r)).  Returns the duration, or -1 if by the model the
 * sequence does not accumulate (the mass leaves before the bounces die). */
enum { TAIL_TERMS = 40 };

static int tail_flight(double u, double a, double a1, double a2,
                       double kappa, double gamma, double *tau, double *vret)
{
  double c[TAIL_TERMS]; /* g(t) = sum c_k t^k */
  c[0] = 0.0;
  c[1] = -u;
  for (int k = 0; k + 2 < TAIL_TERMS; k++) {
    double q = k == 0 ? a : k == 1 ? a1 : k == 2 ? 0.5 * a2 : 0.0;
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

double vi_chatter_tail(double u, double r, double p0, double p1, double p2,
                       double kappa, double gamma, int64_t *count)
{
  double T = 0.0, u0 = u;
  int64_t k = 0;
  while (u > 1e-17 * u0) {
    double a = p0 + p1 * T + 0.5 * p2 * T * T, a1 = p1 + p2 * T, tau, vret;
    if (!(a > 0.0) || k > 1000000) return -1.0;
    if (tail_flight(u, a, a1, p2, kappa, gamma, &tau, &vret) ||
        !(vret > 0.0))
      return -1.0;
    T += tau;
    k++;
    /* bounces that do not shrink (r = 1 without damping) never add up: at
     * the ratio q of this one the rest would take log(1e-17 u0 / u) / log q
     * more; more than ten times the cap is no accumulation (this took a
     * million flights to find out) */
    double q = r * vret / u;
    if (!(q < 1.0) || log(1e-17 * u0 / (r * vret)) / log(q) > 1e7) return -1.0;
    u = r * vret;
  }
  *count = k;
  return T;
}

/* Normal stiffness and damping of the structure seen through stop k with
 * the other held stops S on theirs: a displacement xi along
 * nu = P_S M^-1 w / (w^T P_S M^-1 w) (P_S: the projection that keeps S's
 * gaps) changes the gap by xi and its acceleration by -kappa xi (and
 * -gamma xi' for a rate): kappa = w.P_S M^-1 K nu, as P_S M^-1 is
 * symmetric.  M^-1 K nu and M^-1 C nu are taken as differences of the free
 * acceleration's rate (vi_sim_accel_rate), whatever the model's storage;
 * at t = 0 the load's rate is W M^-1 b, zero for a cosine load. */
void vi_chatter_normal(vi_sim *s, int k, double *kappa, double *gamma)
{
  const vi_model *m = s->m;
  const double *w = vi_stop_w(m, k);
  int n = s->n;
  held h;
  held_around(s, k, &h);
  double *nu = s->w1, *yk = s->w2, *yc = s->w3, *f1 = s->zs, *zero = s->zs + n;
  memcpy(nu, vi_stop_minvw(m, k), sizeof(double) * (size_t)n);
  vi_sim_project(s, h.ns, h.list, h.LS, nu, NULL);
  double wnu = vi_dot(n, w, nu);
  memset(zero, 0, sizeof(double) * (size_t)n);
  vi_sim_accel_rate(s, 0.0, 1, zero, zero, f1);
  vi_sim_accel_rate(s, 0.0, 1, nu, zero, yk);
  vi_sim_accel_rate(s, 0.0, 1, zero, nu, yc);
  for (int i = 0; i < n; i++) {
    yk[i] = f1[i] - yk[i];
    yc[i] = f1[i] - yc[i];
  }
  vi_sim_project(s, h.ns, h.list, h.LS, yk, NULL);
  vi_sim_project(s, h.ns, h.list, h.LS, yc, NULL);
  *kappa = vi_dot(n, w, yk) / wnu;
  *gamma = vi_dot(n, w, yc) / wnu;
}

/* Whether the bounces on stop k end at this impact (approach speed vn,
 * push: its gap's acceleration with the other held stops on theirs, > 0
 * when pressed; x, v: the state before the impact at s->t; dt_prev: the
 * time since the previous contact).  Chattering (Budd & Dux 1994): with
 * r < 1 and the stop pressed on, impacts accumulate at a finite time.
 * Once the next bounce's apex (r v_n)^2 / (2 w.a) lies within a few atol
 * of the stop, further impacts are no longer resolved (a position error dx
 * turns into an approach speed error w.a dx / v_n as large as v_n itself);
 * below the chatter threshold or a floor they are not wanted.  Then the
 * rest of the sequence is summed by the chatter map and sticking begins
 * at its accumulation point (Nordmark & Piiroinen 2009). */
double vi_chatter_threshold(const vi_sim *s)
{
  return s->vchat >= 0.0 ? s->vchat : 1e-7 * s->vscale;
}

int vi_chatter_wanted(vi_sim *s, int k, double vn, double push,
                      double dt_prev, const double *x, const double *v,
                      int *floor_hit)
{
  const vi_model *m = s->m;
  double r = m->rv[k], xs = m->xsv[k], wnorm = s->wnorms[k];
  double apex = push > 0.0 ? vi_rebound_apex(r, vn, push) : HUGE_VAL;
  *floor_hit = push > 0.0 && vn > 0.0 &&
               ((s->vn_floor > 0.0 && vn < s->vn_floor) ||
                (s->dt_floor > 0.0 && dt_prev < s->dt_floor));
  /* a touch at rest or a floor ends any sequence that presses on the stop,
   * even at r = 1; a vanishing bounce only where impacts lose energy */
  if (vn > s->vscale) { /* the run's velocity scale: its fastest impact */
    s->vscale = vn;
    s->vres = s->impact_ratio * vn;
  }
  double vchat = vi_chatter_threshold(s);
  /* Round-off's bounces.  In a resolved chatter, each bounce returns at
   * about the speed r v_n it left with (exactly so under a constant push).
   * Where the closed form's round-off of the gap (its own estimate gnoise,
   * vi_exact.c) is within 1e4 of the energy a bounce loses,
   * (1 - r^2) v_n^2 / 2 against push gnoise, the gap's noise can feed each
   * flight the energy the restitution takes out: the bounces stop
   * decaying and go on at the noise's speed for ever (a 2-mass chain under
   * a = 1e8 with x_s = 0.1: millions at v_n ~ 1.2, 1e-8 of the motion's
   * speed).  A bounce that follows the last within its flight time and
   * has kept more than half of its speed beyond r (v_n > (1 + r) / 2 of
   * the last) is then no longer resolved: summed, like a tail.  (The
   * integrators' error is that of their tolerances, which the user sets:
   * vi_sim_set_impact_resolution.) */
  double vlast = s->vn_last[k];
  s->vn_last[k] = vn;
  int noise = s->be == &vi_backend_exact && push > 0.0 && r < 1.0 &&
              vn > 0.0 && vlast > 0.0 && s->gnoise[k] > 0.0 &&
              dt_prev <= 4.0 * r * vlast / push &&
              vn > 0.5 * (1.0 + r) * vlast &&
              (1.0 - r * r) * vn * vn < 2e4 * push * s->gnoise[k];
  /* A rebound whose apex lies within the gap's round-off is not resolved
   * at all, kept speed or not: the noise kicks such bounces back up now
   * and then (a 1-dof pressed on a stop 1e-9 above its start: decays at r
   * to 3.6e-7, one kick to 1.5e-6, a longer flight than the last speed
   * allows, so the test above never held: 3.4 million impacts in 0.8 ms) */
  noise = noise || (s->be == &vi_backend_exact && push > 0.0 && r < 1.0 && vn > 0.0 &&
                    apex < s->gnoise[k]);
  if (s->vres > 0.0) {
    /* impacts a user can count on: every impact at or above the run's
     * resolution (a fraction of its velocity scale) is resolved, by every
     * method alike; the chatter map sums only below it */
    return push > 0.0 && (vn <= 0.0 || *floor_hit ||
                          (r < 1.0 && (vn < s->vres || vn < vchat ||
                                       noise)));
  }
  int chatter = push > 0.0 &&
                (vn <= 0.0 || *floor_hit ||
                 (r < 1.0 && (vn < vchat || noise ||
                              apex < 10.0 * s->atol * wnorm)));
  if (!chatter && r < 1.0 && push > 0.0) {
    /* Sum the tail as soon as resolving the next impact costs more
     * accuracy than the closed-form tail: the next contact time is only
     * known to dx / (r v_n), with dx the integrator's position error along
     * w, while the chatter map neglects the contact force's second rate,
     * an error of about |p''| / p Delta^3 over the tail's duration Delta. */
    double p[3];
    vi_chatter_push(s, k, s->t, x, v, p);
    /* an integrator's global position error is some ten times its local
     * tolerance */
    double dx = s->be == &vi_backend_exact
                    ? 16.0 * DBL_EPSILON * (fabs(xs) + wnorm)
                    : 10.0 * (s->atol * wnorm + s->rtol * fabs(xs));
    double delta = 2.0 * r * vn / (p[0] * (1.0 - r));
    double e_res = dx / (r * vn), e_model = fabs(p[2]) / p[0] * pow(delta, 3);
    double tol_t = s->rtol * fmax(fabs(s->t), 2.0 * vn / p[0]);
    chatter = p[0] > 0.0 && e_res > tol_t && e_model <= e_res;
  }
  return chatter;
}

/* The duration of stop k's chattering tail from rebound speed u (the gap's
 * rate -u), x and v (v with no normal velocity on the held stops) at s->t;
 * 0 if the model says it does not accumulate (the stop then holds at
 * once).  The other held stops keep their constraint forces throughout. */
double vi_chatter_sum(vi_sim *s, int k, double u, const double *x,
                      const double *v, int64_t *count)
{
  double p[3], kappa, gamma;
  *count = 0;
  if (!(u > 0.0)) return 0.0;
  vi_chatter_push(s, k, s->t, x, v, p);
  vi_chatter_normal(s, k, &kappa, &gamma);
  double tail = vi_chatter_tail(u, s->m->rv[k], p[0], p[1], p[2], kappa,
                                gamma, count);
  if (tail < 0.0) {
    *count = 0;
    return 0.0;
  }
  return tail;
}

/* ---- STICK events due at accumulation points ---------------------------- */
static void pending_min(vi_sim *s)
{
  s->stick_pending = 0;
  s->stick_at = HUGE_VAL;
  for (int k = 0; k < s->ns; k++) {
    if (!s->pend[k].on) continue;
    s->stick_pending++;
    if (s->pend[k].at < s->stick_at) s->stick_at = s->pend[k].at;
  }
}

void vi_chatter_pend(vi_sim *s, int k, double at, double vn, double ie)
{
  s->pend[k].on = 1;
  s->pend[k].at = at;
  s->pend[k].vn = vn;
  s->pend[k].ie = ie;
  pending_min(s);
}

int vi_chatter_due(const vi_sim *s, double t)
{
  int kd = -1;
  for (int k = 0; k < s->ns; k++)
    if (s->pend[k].on && s->pend[k].at <= t &&
        (kd < 0 || s->pend[k].at < s->pend[kd].at))
      kd = k;
  return kd;
}

void vi_chatter_unpend(vi_sim *s, int k)
{
  if (k < 0) {
    for (int j = 0; j < s->ns; j++) s->pend[j].on = 0;
  } else {
    s->pend[k].on = 0;
  }
  pending_min(s);
}
