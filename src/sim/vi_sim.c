/* vi_sim.c - the event-driven simulation: impacts, sticking, samples,
 * monitors and callbacks, over an integrator backend.  The settings and
 * the getters are in vi_sim_io.c. */
#include <float.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vi_exact_internal.h"
#include "vi_flow_internal.h"
#include "vi_impact_internal.h"
#include "vi_sim_internal.h"

static const vi_backend *method_backend(const vi_sim *s);

/* The size of the harmonic response's terms in stop k's gap, each taken
 * whole (the closed form sums them, with their round-off, and cancels
 * them against the transient's while the motion builds up): the
 * particular solution of every mode.  (The static response is carried
 * relative to each start, vi_flow_basis; band models have no modes, and
 * their integrators carry the load in the state.) */
static double particular_scale(const vi_sim *s, int k)
{
  const vi_model *m = s->m;
  if (s->flow->gen) return vi_general_particular_scale(s->flow->gen, k);
  if (!vi_model_has_modes(m)) return 0.0;
  const double *psi = vi_stop_psi(m, k);
  double sc = 0.0;
  for (int j = 0; j < m->n; j++)
    sc += fabs(psi[j]) * hypot(s->flow->pA[j], s->flow->pB[j]);
  return sc;
}

int vi_sim_create(const vi_model *model, vi_sim **out)
{
  if (!out) return VI_ERR_ARG;
  *out = NULL;
  if (!model) return VI_ERR_ARG;
  if (!model->frozen) return VI_ERR_STATE;
  vi_sim *s = calloc(1, sizeof *s);
  if (!s) return VI_ERR_NOMEM;
  int n = model->n;
  s->z = calloc(10 * (size_t)n, sizeof(double));
  s->sbuf = calloc(4 * (size_t)n + 5 * (size_t)model->ns, sizeof(double));
  s->brent = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
  s->pend = calloc((size_t)model->ns, sizeof *s->pend);
  /* each simulation builds its own exact flow (vi_flow_internal.h) */
  int fst = vi_xflow_create(model, &s->flow);
  if (!s->z || !s->sbuf || !s->brent || !s->pend || fst) {
    vi_xflow_destroy(&s->flow);
    gsl_root_fsolver_free(s->brent);
    free(s->pend);
    free(s->sbuf);
    free(s->z);
    free(s);
    return VI_ERR_NOMEM;
  }
  s->x = s->z + 2 * (size_t)n;
  s->v = s->x + n;
  s->vp = s->v + n;
  s->zs = s->vp + n; /* 2n */
  s->w1 = s->zs + 2 * (size_t)n;
  s->w2 = s->w1 + n;
  s->w3 = s->w2 + n; /* ends at 10n */
  s->m = model;
  s->n = n;
  s->method = VI_METHOD_AUTO;
  s->be = method_backend(s);
  vi_sim_note_method(s);
  s->rtol = 1e-8;
  s->atol = 1e-10;
  s->vchat = -1.0; /* the default: 1e-7 of the run's velocity scale */
  s->impact_ratio = 1e-5;
  s->ev_states = 1;
  s->tol_scale = 1.0;
  s->t_last_contact = -HUGE_VAL;
  s->stick_at = HUGE_VAL;
  s->fast_nvector = 1;
  s->ns = model->ns;
  s->wnorms = s->sbuf + 4 * (size_t)n;
  s->ie_stop = s->wnorms + s->ns;
  s->pscale = s->ie_stop + s->ns;
  s->gnoise = s->pscale + s->ns;
  s->vn_last = s->gnoise + s->ns;
  for (int k = 0; k < s->ns; k++) {
    const double *w = vi_stop_w(model, k);
    s->wnorms[k] = sqrt(vi_dot(n, w, w));
    s->pscale[k] = particular_scale(s, k);
  }
  s->harmonic = vi_forcing_harmonic(model);
  vi_model_hold(model, 1); /* its flow and forcing are derived from it */
  *out = s;
  return VI_OK;
}

/* The closed form runs where it applies; after a hand-over (it lost its
 * conditioning) the rest of the simulation stays on CVODE. */
static int uses_exact(const vi_sim *s)
{
  return (s->method == VI_METHOD_EXACT || s->method == VI_METHOD_AUTO) &&
         s->flow->ok && !s->handed_over && !s->nforces;
}

static const vi_backend *method_backend(const vi_sim *s)
{
  if (uses_exact(s)) return &vi_backend_exact;
  return s->method == VI_METHOD_ERK ? &vi_backend_arkode : &vi_backend_cvode;
}

/* A sticking phase runs on the exact method's constrained modes where the
 * held set has them (vi_held.c), else on CVODE. */
static const vi_backend *held_backend(vi_sim *s)
{
  if (uses_exact(s) && vi_held_available(s)) return &vi_backend_exact;
  return &vi_backend_cvode;
}

/* The method note's text from *at on: src, at most max characters of it,
 * cut where the note is full (as snprintf would); no printf at every
 * set-up (a thousand instructions, and its code's first use). */
static void note_put(vi_sim *s, size_t *at, const char *src, size_t max)
{
  size_t cap = sizeof s->method_note - 1;
  for (size_t k = 0; k < max && src[k] && *at < cap; k++)
    s->method_note[(*at)++] = src[k];
  s->method_note[*at] = '\0';
}

void vi_sim_note_method(vi_sim *s)
{
  s->method_used = uses_exact(s)                  ? VI_METHOD_EXACT
                   : s->method == VI_METHOD_BDF   ? VI_METHOD_BDF
                   : s->method == VI_METHOD_ERK   ? VI_METHOD_ERK
                                                  : VI_METHOD_ADAMS;
  if (s->handed_over) return; /* the hand-over wrote its own note */
  size_t at = 0;
  note_put(s, &at, vi_method_name(s->method_used), SIZE_MAX);
  if (s->method != VI_METHOD_AUTO) return;
  note_put(s, &at, " (auto: ", SIZE_MAX);
  note_put(s, &at,
           s->nforces     ? "nonlinear forces have no closed form"
           : s->flow->ok ? "closed-form flow available"
                         : s->flow->why,
           400);
  note_put(s, &at, ")", SIZE_MAX);
}

void vi_sim_backend_reset(vi_sim *s)
{
  for (;;) {
    if (s->be_data) s->be->destroy(s);
    s->be_data = NULL;
    if (!s->park_be) break;
    s->be = s->park_be;
    s->be_data = s->park_data;
    s->park_be = NULL;
    s->park_data = NULL;
  }
  s->be = method_backend(s);
  s->started = 0;
}

/* The closed form has no constrained flow: an exact-method simulation runs
 * its sticking phases on CVODE (Adams) and returns at release.  The
 * backend not in use keeps its data for the next switch. */
static void use_backend(vi_sim *s, const vi_backend *be)
{
  if (s->be == be) return;
  vi_ledger_settle(s->led); /* integrals the leaving backend owes */
  void *pd = s->park_be == be ? s->park_data : NULL;
  s->park_be = s->be;
  s->park_data = s->be_data;
  s->be = be;
  s->be_data = pd;
}

void vi_sim_destroy(vi_sim **sim)
{
  if (!sim || !*sim) return;
  vi_sim *s = *sim;
  if (s->running) {
    /* the run still holds s: end it, and let the host destroy afterwards */
    s->destroy_asked = 1;
    s->stop = 1;
    return;
  }
  /* the host's user data handed over with a destroy function */
  vi_user_set(&s->cancel_user, &s->cancel_free, NULL, NULL);
  vi_user_set(&s->ev_user, &s->ev_free, NULL, NULL);
  vi_user_set(&s->smp_user, &s->smp_free, NULL, NULL);
  vi_user_set(&s->mon_user, &s->mon_free, NULL, NULL);
  vi_user_set(&s->force_user, &s->force_free, NULL, NULL);
  vi_user_set(&s->led_user, &s->led_free, NULL, NULL);
  vi_sim_backend_reset(s);
  vi_held_free(s);
  vi_ledger_destroy(s->led);
  vi_force_free(s);
  vi_xflow_destroy(&s->flow);
  gsl_root_fsolver_free(s->brent);
  vi_model_hold(s->m, -1);
  free(s->pend);
  free(s->sbuf);
  free(s->z);
  free(s);
  *sim = NULL;
}

const char *vi_sim_errmsg(const vi_sim *s) { return s ? s->errmsg : ""; }

/* ---- events ------------------------------------------------------------- */
static void split(vi_sim *s, const double *z)
{
  for (int i = 0; i < s->n; i++) {
    s->x[i] = z[2 * (size_t)i];
    s->v[i] = z[2 * (size_t)i + 1];
  }
}

static void emit(vi_sim *s, int kind, int stop, double vn, double ie)
{
  int64_t idx = s->nevents[kind]++;
  s->last_event = kind;
  if (s->event_stop) s->stop = 1;
  if (!s->ev_fn || (s->stop && !s->event_stop)) return;
  int x = s->ev_states;
  vi_event ev = {kind, s->n, idx, s->t, vn, ie, x ? s->x : NULL,
                 x ? s->v : NULL, x ? s->vp : NULL, stop};
  if (s->ev_fn(&ev, s->ev_user)) {
    s->stop = 1;
    s->event_stop = 0; /* the user's request: the run returns VI_STOPPED */
  }
}

/* Sticking after a summed chattering tail begins at its accumulation point:
 * stop k's STICK event, pending until the run reaches it, goes out now (at
 * its time, or earlier if the stop is let go before). */
static void emit_stick(vi_sim *s, int k)
{
  if (!s->pend[k].on) return;
  double vn = s->pend[k].vn, ie = s->pend[k].ie;
  vi_chatter_unpend(s, k);
  vi_sim_sync(s); /* a bounce in the backend's coordinates left s->z stale */
  split(s, s->z);
  memcpy(s->vp, s->v, sizeof(double) * (size_t)s->n);
  emit(s, VI_EVENT_STICK, k, vn, ie);
}

/* Every pending STICK event due by t, the earliest first. */
static void emit_sticks_due(vi_sim *s, double t)
{
  for (int k; (k = vi_chatter_due(s, t)) >= 0;) emit_stick(s, k);
}

/* End the ledger's open interval at s->t (vi_ledger_pre_jump saw the state
 * before any jump; s->z is the state after it). */
static void close_interval(vi_sim *s, int jump, double ie)
{
  const double *q, *qd;
  if (!s->led) return;
  /* a stale s->z: the backend's own modes are the state (after a kick) */
  int modal = s->z_stale && s->be->modal && !s->be->modal(s, &q, &qd);
  if (modal ? vi_ledger_close_modal(s->led, s->t, q, qd, jump, ie,
                                    vi_sim_user_stopped(s))
            : vi_ledger_close(s->led, s->t, s->z, jump, ie,
                              vi_sim_user_stopped(s))) {
    s->stop = 1;
    s->event_stop = 0;
  }
}

/* The physical state at s->t into s->x, s->v (built now where the backend
 * keeps its own coordinates). */
static int physical(vi_sim *s)
{
  int st = vi_sim_sync(s);
  if (!st) split(s, s->z);
  return st;
}

/* A contact with stop k alone, located at s->t: impact, start of sticking,
 * or a tangential touch that needs nothing but a restart past it.  (With
 * one stop, the arithmetic of the single-stop simulator.)  Where the
 * backend keeps its own coordinates (vi_backend.normal), a bounce is made
 * there, in O(n), and the physical state is built only for whoever reads
 * it (the event's states, the ledger, a stick); the motion is the same
 * whether or not it is built. */
static int on_contact_one(vi_sim *s, int k)
{
  const vi_model *m = s->m;
  int n = s->n, st;
  const double *w = vi_stop_w(m, k), *mw = vi_stop_minvw(m, k);
  double r = m->rv[k], wmw = m->G[k + (size_t)k * m->ns], xs = m->xsv[k];
  emit_sticks_due(s, HUGE_VAL); /* an earlier stop's tail, if any, ends */
  /* gap, approach velocity and push (> 0: pressed into the stop) */
  double g, vn, push;
  int own = s->be->normal && !s->be->normal(s, k, &g, &vn, &push);
  int have_x = !own; /* s->x, s->v hold the state */
  if (!own) {
    if ((st = physical(s))) return st;
    vn = vi_dot(n, w, s->v);
    vi_sim_accel(s, s->t, s->z, 0, s->vp);
    push = vi_dot(n, w, s->vp);
  }
  if (s->led) {
    const double *q, *qd;
    if (own && s->be->modal && !s->be->modal(s, &q, &qd)) {
      vi_ledger_pre_jump_modal(s->led, q, qd);
    } else {
      if ((st = vi_sim_sync(s))) return st;
      vi_ledger_pre_jump(s->led, s->z);
    }
  }
  double dt_prev = s->t - s->t_last_contact;
  s->t_last_contact = s->t;
  /* the accuracy-driven chatter test (no impact resolution) reads x, v */
  if (!have_x && !(s->impact_ratio > 0.0)) {
    if ((st = physical(s))) return st;
    have_x = 1;
  }
  int floor_hit;
  int chatter = vi_chatter_wanted(s, k, vn, push, dt_prev, s->x, s->v,
                                  &floor_hit);
  if (floor_hit) s->stats[VI_STAT_FLOORS]++;
  double ie = 0.0, P = 0.0;
  if (vn > 0.0 && (st = vi_contact_law(m, 1, &k, NULL, &vn, &P, &ie)))
    return st; /* one contact: always solvable */
  int stick = chatter || (vn > 0.0 && r == 0.0 && push > 0.0) ||
              (vn <= 0.0 && s->press_next);
  s->press_next = 0;
  /* the physical state: for the event's states, a plastic impact's or a
   * stick's tests below */
  if (!have_x && (stick || (vn > 0.0 && r == 0.0) ||
                  (vn > 0.0 && s->ev_fn && s->ev_states))) {
    if ((st = physical(s))) return st;
    have_x = 1;
  }
  if (have_x) {
    memcpy(s->vp, s->v, sizeof(double) * (size_t)n);
    if (P != 0.0)
      for (int i = 0; i < n; i++) s->vp[i] -= P * mw[i];
  }
  if (vn > 0.0) {
    s->stats[VI_STAT_IMPACTS]++;
    emit(s, VI_EVENT_IMPACT, k, vn, ie);
  }
  if (!stick && vn > 0.0 && r == 0.0) {
    /* a plastic impact leaves the mass on the stop at rest along w: it
     * sticks if pressed with the velocity after the impact (damping), else
     * a restart on g = g' = 0 would miss the contact root as it presses */
    for (int i = 0; i < n; i++) {
      s->zs[2 * (size_t)i] = s->x[i];
      s->zs[2 * (size_t)i + 1] = s->vp[i];
    }
    vi_sim_accel(s, s->t, s->zs, 0, s->w1);
    double p2 = vi_dot(n, w, s->w1);
    stick = p2 > 0.0;
    if (!stick) {
      /* pressed at the next order: no contact force yet (a body arriving
       * undeformed, as Siconos' impacting bar) but a positive third
       * derivative of the gap, so that it presses within a round-off of
       * p2; a restart on g = g' = g'' = 0 would miss that contact (no sign
       * change from zero) */
      vi_sim_accel_rate(s, s->t, 1, s->vp, s->w1, s->w2);
      double jerk = vi_dot(n, w, s->w2), om = vi_model_omega_bound(m);
      stick = jerk > 0.0 && om > 0.0 && -p2 <= jerk * 1e-3 / om;
    }
  }
  double ie_tail = 0.0;
  if (stick) {
    /* remove the rebound's normal velocity: the tail's impacts absorb its
     * kinetic energy, and the constraint holds exactly from here on */
    double u = vi_dot(n, w, s->vp) / wmw;
    ie_tail = 0.5 * u * u * wmw;
    for (int i = 0; i < n; i++) s->vp[i] -= u * mw[i];
    int64_t count;
    double tail = vi_chatter_sum(s, k, -u * wmw, s->x, s->vp, &count);
    vi_sim_set_sticking(s, &k, 1);
    s->stats[VI_STAT_STICKS]++;
    s->stats[VI_STAT_CHATTER_SKIPPED] += count;
    vi_chatter_pend(s, k, s->t + tail, -u * wmw, ie_tail);
  }
  /* the rebound's flight 2 r v_n / w.a: the integrator's first step must
   * end inside it, or it steps from the stop (g = 0) to beyond it (g > 0)
   * with no sign change for the root finding (a chattering tail, where
   * the flights shrink geometrically; ERK missed such a landing).  Used by
   * ERK, whose first step after a restart is otherwise its own estimate */
  s->h_flight = vn > 0.0 && !stick && push > 0.0 ? 0.5 * r * vn / push : 0.0;
  /* The rebound rises only (r v_n)^2 / (2 w.a) off the stop.  A position
   * error dx along w at the next landing changes its approach velocity by
   * dx / (2 apex) of itself, so where the next impact is one to report
   * (about r v_n, above vres / 2) the integrator's tolerances are tightened
   * for this flight until dx is a 1/50 of the apex (down to rtol 1e-15):
   * every reported v_n to about 1 %, whatever the method (issue 20). */
  s->tol_scale = 1.0;
  if (s->h_flight > 0.0 && s->vres > 0.0 && r * vn >= 0.5 * s->vres) {
    double apex = vi_rebound_apex(r, vn, push);
    double dx = 10.0 * (s->atol * s->wnorms[k] + s->rtol * fabs(xs));
    s->tol_scale = fmin(1.0, fmax(1e-15 / s->rtol, 0.02 * apex / dx));
  }
  s->ie_stop[k] += ie + ie_tail;
  /* The contact is at g = 0 by definition, but the located state carries
   * the integrator's position error along w.  Near grazing that error is
   * amplified into the next approach velocity as dv ~ g'' dx / v (the
   * square-root singularity), so put the state back on the stop: the
   * M-orthogonal projection, the smallest change in kinetic-energy norm. */
  if (own && !stick) {
    s->be->kick(s, k, -g / wmw, -P);
    const double *q, *qd; /* the ledger's state after the jump */
    if (s->led && !(s->be->modal && !s->be->modal(s, &q, &qd)) &&
        (st = vi_sim_sync(s)))
      return st;
  } else {
    g = vi_dot(n, w, s->x) - xs;
    for (int i = 0; i < n; i++) s->x[i] -= g * mw[i] / wmw;
    for (int i = 0; i < n; i++) {
      s->z[2 * (size_t)i] = s->x[i];
      s->z[2 * (size_t)i + 1] = s->vp[i];
    }
  }
  close_interval(s, vn > 0.0 || stick, ie + ie_tail);
  emit_sticks_due(s, s->t); /* a tail of no duration */
  s->stats[VI_STAT_REINITS]++;
  use_backend(s, stick ? held_backend(s) : method_backend(s));
  return s->be->start(s);
}

/* Put x on the stops list [cnt] (w_k.x = x_k): the M-orthogonal projection
 * x -= M^-1 W G^-1 (W^T x - x_s), as in on_contact_one for one stop.  Left
 * as it is if their Delassus block is singular. */
static void project_on_stops(vi_sim *s, const int *list, int cnt, double *x)
{
  const vi_model *m = s->m;
  double L[VI_CONTACT_MAX * VI_CONTACT_MAX], g[VI_CONTACT_MAX];
  for (int i = 0; i < cnt; i++) {
    g[i] = vi_dot(s->n, vi_stop_w(m, list[i]), x) - m->xsv[list[i]];
    for (int j = 0; j < cnt; j++)
      L[i + j * cnt] = m->G[list[i] + (size_t)list[j] * m->ns];
  }
  if (!cnt || vi_small_cholesky(cnt, L)) return;
  vi_small_solve(cnt, L, g);
  for (int i = 0; i < cnt; i++) {
    const double *mw = vi_stop_minvw(m, list[i]);
    for (int j = 0; j < s->n; j++) x[j] -= g[i] * mw[j];
  }
}

/* Several stops touch at s->t (idx [nc]: those within the gap tolerance,
 * and every stop held while sticking): Newton's law for simultaneous
 * contacts (vi_contact.c).  Then the stops that hold from here on: a
 * sticking stop that the impulses keep on its stop, and a stop whose
 * bounces die out (vi_chatter_wanted with the other held stops on theirs,
 * or r = 0, pressed on), as long as its contact force pushes (lambda_S =
 * G_SS^-1 W_S^T a_free > 0).  A stop whose bounces die out holds from
 * here; its STICK event waits for the accumulation point of its tail,
 * summed with the other held stops' constraint forces in its normal
 * dynamics (vi_chatter_sum). */
static int on_contact_multi(vi_sim *s, int nc, int *idx)
{
  const vi_model *m = s->m;
  int n = s->n, st;
  double P[VI_CONTACT_MAX], u[VI_CONTACT_MAX], ie[VI_CONTACT_MAX];
  if (s->led) vi_ledger_pre_jump(s->led, s->z);
  split(s, s->z);
  st = vi_contact_solve(m, nc, idx, s->v, s->vp, P, u, ie);
  if (st == VI_ERR_LIMIT)
    return vi_fail(s->errmsg, st, "%d stops touch at once at t = %.17g: "
                   "Newton's law for simultaneous contacts is solved by "
                   "enumeration for at most %d", nc, s->t, VI_CONTACT_MAX);
  if (st)
    return vi_fail(s->errmsg, VI_ERR_NOT_CONVERGED, "no impulses satisfy "
                   "Newton's law for the %d stops touching at t = %.17g "
                   "(dependent stop vectors?)", nc, s->t);
  double dt_prev = s->t - s->t_last_contact;
  s->t_last_contact = s->t;
  double ie_sum = 0.0;
  int impacted = 0;
  for (int k = 0; k < nc; k++) {
    ie_sum += ie[k];
    s->ie_stop[idx[k]] += ie[k];
    /* a held stop takes a constraint impulse (its approach speed is
     * round-off), not an impact */
    if (u[k] > 0.0 && P[k] > 0.0 && !vi_sim_in_stick_set(s, idx[k])) {
      impacted = 1;
      s->stats[VI_STAT_IMPACTS]++;
      emit(s, VI_EVENT_IMPACT, idx[k], u[k], ie[k]);
    }
  }
  /* free acceleration after the jump (damping sees the new velocity), and
   * a2: the same with the stops held so far on theirs, the push that a
   * stop not held feels */
  double *zz = s->sbuf, *acc = zz + 2 * (size_t)n, *a2 = acc + n;
  for (int i = 0; i < n; i++) {
    zz[2 * (size_t)i] = s->x[i];
    zz[2 * (size_t)i + 1] = s->vp[i];
  }
  vi_sim_accel(s, s->t, zz, 0, acc);
  memcpy(a2, acc, sizeof(double) * (size_t)n);
  if (s->sticking) vi_sim_constrain(s, a2, NULL);
  int hold[VI_CONTACT_MAX] = {0}, was[VI_CONTACT_MAX], nh = 0;
  int tailing[VI_CONTACT_MAX] = {0}; /* hold[i]'s bounces die out here */
  int nwas = s->nstick;
  memcpy(was, s->stick_k, sizeof(int) * (size_t)nwas);
  for (int k = 0; k < nc; k++) {
    int j = idx[k];
    const double *w = vi_stop_w(m, j);
    double un = vi_dot(n, w, s->vp), push = vi_dot(n, w, a2);
    double vscale = fmax(fabs(u[k]), s->atol);
    if (vi_sim_in_stick_set(s, j)) {
      /* held on: pushed by its impulse, or left with a normal speed within
       * the integration error (atol) of rest */
      double vtol = fmax(1e-9 * fabs(u[k]), s->atol * s->wnorms[j]);
      if (P[k] > 0.0 || fabs(un) <= vtol) hold[nh++] = j;
      continue;
    }
    if (!(push > 0.0)) continue;
    if (u[k] <= 0.0) {
      /* resting on the stop, pressed (a touch at a gap maximum, or a start
       * on the stop): sticking at any r, as for one stop */
      if (fabs(un) <= fmax(vi_chatter_threshold(s), 1e-9 * vscale)) hold[nh++] = j;
      continue;
    }
    if (!(P[k] > 0.0)) continue;
    int floor_hit;
    int chatter = vi_chatter_wanted(s, j, u[k], push, dt_prev, s->x, s->v,
                                    &floor_hit);
    if (floor_hit) s->stats[VI_STAT_FLOORS]++;
    if (chatter || m->rv[j] == 0.0) {
      tailing[nh] = 1;
      hold[nh++] = j;
    }
  }
  /* drop the stops that would pull (lambda <= 0) until the rest push */
  for (int pass = 0; pass <= VI_CONTACT_MAX && nh > 0; pass++) {
    double lam[VI_CONTACT_MAX];
    if ((st = vi_sim_set_sticking(s, hold, nh))) return st;
    memcpy(a2, acc, sizeof(double) * (size_t)n);
    vi_sim_constrain(s, a2, lam);
    int keep = 0;
    for (int i = 0; i < nh; i++)
      if (lam[i] > 0.0) {
        tailing[keep] = tailing[i];
        hold[keep++] = hold[i];
      }
    if (keep == nh) break;
    nh = keep;
  }
  if ((st = vi_sim_set_sticking(s, hold, nh))) return st;
  /* the held stops' normal velocities go: their bounces' energy */
  double ie_tail = 0.0, b[VI_CONTACT_MAX], e[VI_CONTACT_MAX];
  if (nh) {
    double lam[VI_CONTACT_MAX];
    for (int i = 0; i < nh; i++) b[i] = vi_dot(n, vi_stop_w(m, hold[i]), s->vp);
    vi_sim_constrain(s, s->vp, lam);
    for (int i = 0; i < nh; i++) {
      e[i] = 0.5 * lam[i] * b[i];
      ie_tail += e[i];
      s->ie_stop[hold[i]] += e[i];
    }
  }
  /* back on the stops that took an impulse or hold */
  int on[VI_CONTACT_MAX], non = 0;
  for (int k = 0; k < nc; k++)
    if (P[k] > 0.0 || vi_sim_in_stick_set(s, idx[k])) on[non++] = idx[k];
  project_on_stops(s, on, non, s->x);
  for (int i = 0; i < n; i++) {
    s->z[2 * (size_t)i] = s->x[i];
    s->z[2 * (size_t)i + 1] = s->vp[i];
  }
  /* a new hold's STICK event is due at the end of its tail (rebound speed
   * -b) */
  double due[VI_CONTACT_MAX];
  for (int i = 0; i < nh; i++) {
    int64_t count = 0;
    due[i] = s->t;
    if (tailing[i])
      due[i] += vi_chatter_sum(s, hold[i], -b[i], s->x, s->vp, &count);
    s->stats[VI_STAT_CHATTER_SKIPPED] += count;
  }
  close_interval(s, impacted || nh > 0, ie_sum + ie_tail);
  split(s, s->z);
  memcpy(s->vp, s->v, sizeof(double) * (size_t)n);
  for (int i = 0; i < nwas; i++)
    if (!vi_sim_in_stick_set(s, was[i])) {
      emit_stick(s, was[i]); /* let go before its tail's end */
      emit(s, VI_EVENT_RELEASE, was[i], 0.0, 0.0);
    }
  for (int i = 0; i < nh; i++) {
    int old = 0;
    for (int j = 0; j < nwas; j++) old |= was[j] == hold[i];
    if (old) continue;
    s->stats[VI_STAT_STICKS]++;
    vi_chatter_pend(s, hold[i], due[i], fmax(-b[i], 0.0), e[i]);
  }
  emit_sticks_due(s, s->t);
  s->stats[VI_STAT_REINITS]++;
  use_backend(s, s->sticking ? held_backend(s) : method_backend(s));
  return s->be->start(s);
}

/* A contact located at s->t (with stop s->contact_stop): stop k alone, or
 * several at once (within the gap tolerance, or while sticking). */
static int on_contact(vi_sim *s)
{
  int k0 = s->contact_stop, st;
  if (s->ns == 1 && !s->sticking) return on_contact_one(s, 0);
  if ((st = vi_sim_sync(s))) return st;
  int idx[VI_CONTACT_MAX], nc = 0;
  for (int k = 0; k < s->ns; k++) {
    double g, gd;
    vi_sim_gap_k(s, k, s->z, &g, &gd);
    /* a stop within a few integration errors touches too */
    double tol = 10.0 * (s->atol + s->rtol * fabs(s->m->xsv[k])) * s->wnorms[k];
    if (k != k0 && !vi_sim_in_stick_set(s, k) && g < -tol) continue;
    if (nc == VI_CONTACT_MAX)
      return vi_fail(s->errmsg, VI_ERR_LIMIT, "more than %d stops touch at "
                     "once at t = %.17g: Newton's law for simultaneous "
                     "contacts is solved by enumeration for at most %d",
                     VI_CONTACT_MAX, s->t, VI_CONTACT_MAX);
    idx[nc++] = k;
  }
  if (nc == 1 && !s->sticking) return on_contact_one(s, idx[0]);
  return on_contact_multi(s, nc, idx);
}

/* The contact force of sticking stop s->contact_stop fell through zero. */
static int on_release(vi_sim *s)
{
  int k = s->contact_stop, keep[VI_CONTACT_MAX], nk = 0, st;
  for (int i = 0; i < s->nstick; i++)
    if (s->stick_k[i] != k) keep[nk++] = s->stick_k[i];
  if (nk == s->nstick) k = s->stick_k[--nk]; /* not held: the last one */
  emit_stick(s, k); /* released before its tail's end: the stick was brief */
  split(s, s->z);
  if (s->ns > 1) {
    /* leave from exactly on the stops at rest along their normals: a
     * round-off normal speed into the released stop would be found again
     * as a contact at the gap's first maximum */
    project_on_stops(s, s->stick_k, s->nstick, s->x);
    vi_sim_constrain(s, s->v, NULL);
    for (int i = 0; i < s->n; i++) {
      s->z[2 * (size_t)i] = s->x[i];
      s->z[2 * (size_t)i + 1] = s->v[i];
    }
  }
  if (s->led) vi_ledger_pre_jump(s->led, s->z);
  close_interval(s, 0, 0.0);
  memcpy(s->vp, s->v, sizeof(double) * s->n);
  if ((st = vi_sim_set_sticking(s, keep, nk))) return st;
  emit(s, VI_EVENT_RELEASE, k, 0.0, 0.0);
  s->stats[VI_STAT_REINITS]++;
  /* free again: back to the method's own integrator (the closed form's
   * search starts from gap, rate and acceleration all zero here) */
  if (!s->sticking) use_backend(s, method_backend(s));
  return s->be->start(s);
}

/* At the start of a run the state may already sit on a stop: moving into
 * it is an impact now, resting on it and pressed is sticking. */
static int initial_contact(vi_sim *s)
{
  if (s->sticking) return 0;
  for (int k = 0; k < s->ns; k++) {
    double g, gd, xs = s->m->xsv[k];
    vi_sim_gap_k(s, k, s->z, &g, &gd);
    /* on the stop within the round-off of the gap's terms: x_s, the
     * state's and the forced response's (a stop at 0.1 under a load of
     * 1e90 is at 0 to every digit the motion has) */
    const double *w = vi_stop_w(s->m, k);
    double sc = fmax(fabs(xs), s->pscale[k]);
    for (int i = 0; i < s->n; i++)
      sc = fmax(sc, fabs(w[i] * s->z[2 * (size_t)i]));
    if (g < -1e-13 * sc) continue;
    /* and at rest on it within the round-off of the velocities' terms,
     * the state's and the forced response's: a state handed on from a
     * sticking phase (a sweep's warm start) carries w.x' of 1e-21 either
     * way, which started free would let the load press it through the
     * stop with no sign change of the gap to see */
    double vsc = fabs(s->m->omega_f) * s->pscale[k];
    for (int i = 0; i < s->n; i++)
      vsc = fmax(vsc, fabs(w[i] * s->z[2 * (size_t)i + 1]));
    if (fabs(gd) <= 1e-13 * vsc) gd = 0.0;
    s->contact_stop = k;
    if (gd > 0.0) return 1;
    double push;
    vi_sim_accel(s, s->t, s->z, 0, s->vp);
    push = vi_dot(s->n, vi_stop_w(s->m, k), s->vp);
    if (gd == 0.0 && push > 0.0) return 1; /* at rest and pressed: sticks,
                                              any r */
    if (gd == 0.0 && push == 0.0) {
      /* at rest on the stop and not yet pressed (Fig. 2 from rest with
       * x_s = 0: g = g' = g'' = 0 at t0): the contact force's next rates
       * along the held motion decide.  Rising, the mass is pressed from
       * t0 on and sticks; started free, the gap would grow from exactly 0
       * with no sign change for the integrator's root finding to see. */
      double p[3];
      split(s, s->z);
      vi_chatter_push(s, k, s->t, s->x, s->v, p);
      if (p[1] > 0.0 || (p[1] == 0.0 && p[2] > 0.0)) {
        s->press_next = 1;
        return 1;
      }
    }
  }
  return 0;
}

/* The stop a state is deepest beyond, relative to its tolerance, and its
 * gap: the integration error's check on samples and steps. */
static int worst_gap(const vi_sim *s, const double *z, double *g,
                     double *tol)
{
  int kw = 0;
  double worst = -HUGE_VAL;
  for (int k = 0; k < s->ns; k++) {
    double gk, gd, tk = vi_sim_gap_tol(s, k);
    vi_sim_gap_k(s, k, z, &gk, &gd);
    /* the integrator controls each coordinate to rtol |x_i| + atol, so w.x
     * carries rtol sum |w_i x_i| besides the atol part: the state's scale
     * (a stop near the origin of a structure far from it) */
    const double *w = vi_stop_w(s->m, k);
    double sc = 0.0;
    for (int i = 0; i < s->n; i++) sc += fabs(w[i] * z[2 * (size_t)i]);
    tk += 100.0 * s->rtol * sc;
    /* written so that a NaN gap is the worst */
    if (!(gk - tk <= worst)) {
      worst = gk - tk;
      kw = k;
      *g = gk;
      *tol = tk;
      if (isnan(worst)) break;
    }
  }
  return kw;
}

/* Deliver the uniform samples that fall in (t_prev, t] from the backend's
 * interpolant; nothing here forces the integrator's steps. */
static int samples(vi_sim *s, double t)
{
  for (;;) {
    double ts = s->smp_t0 + (double)s->smp_k * s->smp_dt;
    /* t0 + k dt may land a rounding above an end time it should equal */
    if (ts > s->t_end && ts - s->t_end <= 8 * DBL_EPSILON * fabs(s->t_end))
      ts = s->t_end;
    if (ts > t || ts > s->t_end) return VI_OK;
    if ((s->smp_k & 4095) == 4095 && vi_sim_cancelled(s)) return VI_CANCELLED;
    s->smp_k++;
    if (vi_sim_user_stopped(s)) continue;
    /* at the current time the state itself, not the interpolant (which
     * CVODE has not built before its first step) */
    const double *zs = s->z;
    int st = ts == s->t ? vi_sim_sync(s) : s->be->dense(s, ts);
    if (st) return st;
    if (ts != s->t) zs = s->zs;
    for (int i = 0; i < s->n; i++) {
      s->x[i] = zs[2 * (size_t)i];
      s->v[i] = zs[2 * (size_t)i + 1];
      if (!isfinite(s->x[i]) || !isfinite(s->v[i]))
        return vi_fail(s->errmsg, VI_ERR_INVARIANT, "sample at t = %.17g "
                       "not finite: x(%d) = %g, v(%d) = %g", ts, i + 1,
                       s->x[i], i + 1, s->v[i]);
    }
    double g = 0.0, tol = 0.0;
    int k = worst_gap(s, zs, &g, &tol);
    if (!(g <= tol) && s->ns == 1)
      return vi_fail(s->errmsg, VI_ERR_INVARIANT, "sample at t = %.17g lies "
                     "beyond the stop: w.x - x_s = %.3g", ts, g);
    if (!(g <= tol))
      return vi_fail(s->errmsg, VI_ERR_INVARIANT, "sample at t = %.17g lies "
                     "beyond stop %d: w.x - x_s = %.3g", ts, k + 1, g);
    if (s->smp_fn(ts, s->n, s->x, s->v, s->smp_user)) s->stop = 1;
  }
}

static void monitor(vi_sim *s)
{
  if (!s->mon_fn || s->t < s->mon_next || vi_sim_user_stopped(s)) return;
  vi_progress p = {s->t, s->run_t0, s->t_end, vi_sim_stat(s, VI_STAT_STEPS),
                   s->stats[VI_STAT_IMPACTS]};
  if (s->mon_fn(&p, s->mon_user)) s->stop = 1;
  /* the next report after t, in one step: a loop of additions would never
   * end where mon_every is below the resolution of t (vi_sim_run refuses
   * such intervals; this keeps the arithmetic safe regardless) */
  double k = floor((s->t - s->mon_next) / s->mon_every) + 1.0;
  s->mon_next += k * s->mon_every;
  if (!(s->mon_next > s->t)) s->mon_next = nextafter(s->t, HUGE_VAL);
}

/* The closed form lost its conditioning at s->t: go on with CVODE (Adams,
 * or BDF if that was asked for) for the rest of the simulation. */
static int hand_over(vi_sim *s)
{
  int st = vi_sim_sync(s);
  if (st) return st;
  s->stats[VI_STAT_HANDOVERS]++;
  s->handed_over = 1;
  s->method_used = VI_METHOD_ADAMS;
  snprintf(s->method_note, sizeof s->method_note,
           "exact until t = %.9g, then adams: %.400s", s->t, s->handover_why);
  use_backend(s, &vi_backend_cvode);
  return s->be->start(s);
}

/* Invariants a step must keep, checked cheaply after every step: finite
 * values and no penetration of the stop beyond the integration tolerance.
 * Written so that a NaN fails every test. */
static int check_invariants(vi_sim *s)
{
  double g = s->gap, tol = vi_sim_gap_tol(s, 0);
  int k = 0;
  if (!s->be->sync) k = worst_gap(s, s->z, &g, &tol);
  if (!isfinite(g) || !isfinite(s->t))
    return vi_fail(s->errmsg, VI_ERR_INVARIANT,
                   "state not finite at t = %.17g (%s method): w.x - x_s = %g",
                   s->t, vi_method_name(s->method_used), g);
  if (!(g <= tol) && s->ns > 1)
    return vi_fail(s->errmsg, VI_ERR_INVARIANT,
                   "state beyond stop %d at t = %.17g (%s method): w.x - x_s "
                   "= %.3g exceeds the tolerance %.3g", k + 1, s->t,
                   vi_method_name(s->method_used), g, tol);
  if (!(g <= tol))
    return vi_fail(s->errmsg, VI_ERR_INVARIANT,
                   "state beyond the stop at t = %.17g (%s method): w.x - x_s "
                   "= %.3g exceeds the tolerance %.3g", s->t,
                   vi_method_name(s->method_used), g, tol);
  return VI_OK;
}

static int check_finite_state(vi_sim *s)
{
  for (int i = 0; i < 2 * s->n; i++)
    if (!isfinite(s->z[i]))
      return vi_fail(s->errmsg, VI_ERR_INVARIANT,
                     "%s(%d) = %g is not finite at t = %.17g (%s method)",
                     i % 2 ? "v" : "x", i / 2 + 1, s->z[i], s->t,
                     vi_method_name(s->method_used));
  return VI_OK;
}

static int run(vi_sim *s, double t_end);

int vi_sim_run(vi_sim *s, double t_end)
{
  if (!s) return VI_ERR_ARG;
  VI_SIM_IDLE(s); /* a nested run would corrupt this one's integrator */
  s->running = 1;
  int st = run(s, t_end);
  s->running = 0;
  if (s->destroy_asked) {
    s->destroy_asked = 0;
    return vi_fail(s->errmsg, VI_ERR_STATE, "vi_sim_destroy was called from "
                   "inside a callback of this sim's run: the run ended at t = "
                   "%.17g and the sim was not destroyed (destroy it after "
                   "vi_sim_run returns)", s->t);
  }
  return st;
}

/* Consecutive steps that may leave t where it was (events at one instant,
 * a restart after a contact) before the run is declared stuck. */
#define VI_STUCK_STEPS 1000

/* An integrator's failure under a load whose response is far beyond
 * atol's scale: say so after its message.  (Near a release the motion
 * grows from rest like a power of the time since, and right after an
 * impact a coordinate at the stop moves at the load's speed: a step
 * within atol + rtol |x| falls below the resolution of t, or below the
 * round-off of the error estimate.) */
static int scale_hint(vi_sim *s, int st)
{
  int kp = 0;
  for (int k = 1; k < s->ns; k++)
    if (s->pscale[k] > s->pscale[kp]) kp = k;
  size_t len = strlen(s->errmsg);
  if (st == VI_ERR_INTEGRATOR && s->ns &&
      DBL_EPSILON * s->pscale[kp] > s->atol * s->wnorms[kp] &&
      len < sizeof s->errmsg)
    snprintf(s->errmsg + len, sizeof s->errmsg - len, "; atol = %.3g is "
             "far below the scale of the motion (the load's response along "
             "stop %d is %.3g): raise atol to about 1e-10 of it, or use the "
             "exact method", s->atol, kp + 1, s->pscale[kp]);
  return st;
}

/* The run made no progress for VI_STUCK_STEPS steps: say why it may be. */
static int stuck(vi_sim *s, double t_before)
{
  int st = vi_sim_sync(s);
  double zmax = 0.0;
  int imax = 0;
  for (int i = 0; i < 2 * s->n && !st; i++)
    if (!(fabs(s->z[i]) <= zmax)) {
      zmax = fabs(s->z[i]);
      imax = i;
    }
  return vi_fail(s->errmsg, VI_ERR_INTEGRATOR,
                 "no progress: time stuck at t = %.17g for %d steps (%s "
                 "method; from t = %.17g): the step size collapsed below the "
                 "resolution of t.  Largest state entry %s(%d) = %.3g: a "
                 "solution that blows up in finite time (a softening spring) "
                 "or a force that is not finite there", s->t, VI_STUCK_STEPS,
                 vi_method_name(s->method_used), t_before, imax % 2 ? "v" : "x",
                 imax / 2 + 1, zmax);
}

static int run(vi_sim *s, double t_end)
{
  if (!isfinite(t_end) || !(t_end > s->t))
    return vi_fail(s->errmsg, VI_ERR_TIME,
                   "end time %.17g is not after the current time %.17g", t_end,
                   s->t);
  if (!s->started) {
    /* the ranges a scene must lie in, checked by the same code (before a
     * first start: later calls continue a motion already accepted) */
    const char *key = "";
    char why[300];
    vi_sim_sync(s);
    for (int i = 0; i < s->n; i++) {
      s->x[i] = s->z[2 * (size_t)i];
      s->v[i] = s->z[2 * (size_t)i + 1];
    }
    int st = vi_model_check_run(s->m, s->t, t_end, s->x, s->v, s->rtol,
                                s->atol, &key, NULL, why, (int)sizeof why);
    /* the run's velocity scale starts at the initial speeds and grows
     * with every approach velocity (vi_chatter_wanted) */
    double vmax = 0.0;
    for (int i = 0; i < s->n; i++) vmax = fmax(vmax, fabs(s->v[i]));
    s->vscale = vmax;
    s->vres = s->impact_ratio * s->vscale;
    if (st) {
      static const char *const api[][2] = {
          {"forcing.omega", "the forcing frequency (vi_model_set_forcing)"},
          {"run.t_end", "the run's times (t0 of vi_sim_set_initial, t_end)"},
          {"initial.x", "the initial x (vi_sim_set_initial)"},
          {"initial.v", "the initial v (vi_sim_set_initial)"},
          {"run.atol", "atol (vi_sim_set_tolerances)"},
          {"run.rtol", "rtol (vi_sim_set_tolerances)"}};
      const char *what = "the model";
      for (size_t k = 0; k < sizeof api / sizeof api[0]; k++)
        if (!strcmp(key, api[k][0])) what = api[k][1];
      return vi_fail(s->errmsg, st == VI_ERR_LIMIT ? VI_ERR_LIMIT : st,
                     "%s %s", what, why);
    }
  }
  if (s->hmax > 0 &&
      s->hmax <= 4.0 * DBL_EPSILON * fmax(fabs(t_end), fabs(s->t)))
    return vi_fail(s->errmsg, VI_ERR_LIMIT, "max step %g is below the "
                   "resolution of t up to t = %g (vi_sim_set_max_step)",
                   s->hmax, t_end);
  if (s->mon_fn) {
    /* a report interval t cannot resolve would report at every step */
    double ts = fmax(fabs(t_end), fabs(s->t));
    if (s->mon_every <= 4.0 * DBL_EPSILON * ts ||
        (t_end - s->t) / s->mon_every > 1e12)
      return vi_fail(s->errmsg, VI_ERR_LIMIT,
                     "monitor interval %g is below the resolution of t up to "
                     "t = %g (at least %.3g, and at most 1e12 reports)",
                     s->mon_every, t_end,
                     fmax(8.0 * DBL_EPSILON * ts, (t_end - s->t) / 1e12));
  }
  if (s->smp_fn) {
    /* refuse a sampling interval whose samples could never all be made */
    double span = t_end - fmax(s->t, s->smp_t0), ts = fmax(fabs(t_end), fabs(s->smp_t0));
    if (s->smp_dt <= 4.0 * DBL_EPSILON * ts || span / s->smp_dt > 1e10)
      return vi_fail(s->errmsg, VI_ERR_LIMIT,
                     "sampling interval %g would need %.3g samples up to t = "
                     "%g (limit 1e10, and dt above the time's round-off)",
                     s->smp_dt, span / s->smp_dt, t_end);
  }
  int st = VI_OK, cancelled = 0;
  s->force_failed = 0;
  s->t_end = t_end;
  s->run_t0 = s->t;
  s->stop = 0;
  if (s->smp_fn && s->smp_k == 0) s->smp_t0 = s->t;
  if (!s->started) {
    /* the default state (rest at the origin) was never checked */
    for (int k = 0; k < s->ns && !s->sticking; k++) {
      double g, gd, xs = s->m->xsv[k];
      vi_sim_gap_k(s, k, s->z, &g, &gd);
      if (g > 1e-13 * fmax(1.0, fabs(xs)) && s->ns == 1)
        return vi_fail(s->errmsg, VI_ERR_INITIAL_STATE, "the state at t = "
                       "%.17g violates the stop: w.x = %.17g > x_s = %.17g "
                       "(set an initial state with vi_sim_set_initial)", s->t,
                       g + xs, xs);
      if (g > 1e-13 * fmax(1.0, fabs(xs)))
        return vi_fail(s->errmsg, VI_ERR_INITIAL_STATE, "the state at t = "
                       "%.17g violates stop %d: w.x = %.17g > x_s = %.17g "
                       "(set an initial state with vi_sim_set_initial)", s->t,
                       k + 1, g + xs, xs);
    }
    vi_sim_note_method(s);
    use_backend(s, s->sticking ? held_backend(s) : method_backend(s));
    if ((st = s->be->start(s))) return st;
    s->started = 1;
    if (s->smp_fn && (st = samples(s, s->t))) return st;
    if (initial_contact(s) && (st = on_contact(s))) return st;
  }
  int still = 0;             /* consecutive steps that left t in place */
  double t_moved = s->t;     /* where t last advanced */
  while (s->t < t_end && !s->stop) {
    if (vi_sim_cancelled(s)) {
      cancelled = 1;
      break;
    }
    if (s->t > t_moved + 4.0 * DBL_EPSILON * fabs(t_moved)) {
      still = 0;
      t_moved = s->t;
    } else if (++still > VI_STUCK_STEPS) {
      return scale_hint(s, stuck(s, t_moved));
    }
    int event = VI_STEP_NONE;
    s->contact_stop = 0; /* a multi-stop backend says which */
    double t_to = s->stick_pending && s->stick_at < t_end ? s->stick_at : t_end;
    if ((st = s->be->step(s, t_to, &event))) {
      if (st == VI_CANCELLED) {
        cancelled = 1;
        break;
      }
      return scale_hint(s, st);
    }
    if (event == VI_STEP_HANDOVER) {
      if ((st = hand_over(s))) return st;
      continue;
    }
    if (s->smp_fn && (st = samples(s, s->t))) {
      if (st != VI_CANCELLED) return st;
      cancelled = 1; /* the step is complete: its events are applied below */
    }
    /* a lone contact on a backend with its own coordinates builds the
     * physical state only where it reads it (on_contact_one) */
    if (event != VI_STEP_NONE &&
        !(event == VI_STEP_CONTACT && s->be->normal) &&
        (st = vi_sim_sync(s)))
      return st;
    if (event == VI_STEP_CONTACT && s->be->refine && (st = s->be->refine(s)))
      return st;
    if (event == VI_STEP_CONTACT) st = on_contact(s);
    else if (event == VI_STEP_RELEASE) st = on_release(s);
    if (st) return st;
    if (s->stick_pending && s->t >= s->stick_at) {
      if ((st = vi_sim_sync(s))) return st;
      emit_sticks_due(s, s->t);
    }
    if ((st = check_invariants(s))) return st;
    monitor(s);
    if (cancelled) break;
  }
  if ((st = vi_sim_sync(s)) || (st = check_finite_state(s))) return st;
  if (s->led && s->t > vi_ledger_open_since(s->led)) {
    vi_ledger_pre_jump(s->led, s->z);
    close_interval(s, 0, 0.0);
  }
  if (cancelled) {
    vi_fail(s->errmsg, VI_CANCELLED, "cancelled at t = %.17g", s->t);
    return VI_CANCELLED;
  }
  return s->stop ? VI_STOPPED : VI_OK;
}

int vi_sim_setup(vi_sim *s)
{
  if (!s) return VI_ERR_ARG;
  VI_SIM_IDLE(s);
  if (s->started) return VI_OK;
  vi_sim_note_method(s);
  use_backend(s, s->sticking ? held_backend(s) : method_backend(s));
  return s->be->start(s); /* allocates; vi_sim_run restarts it cheaply */
}

int vi_sim_run_to_event(vi_sim *s, double t_end, int *kind)
{
  if (!s || !kind) return VI_ERR_ARG;
  VI_SIM_IDLE(s);
  *kind = -1;
  s->event_stop = 1;
  s->last_event = -1;
  int st = vi_sim_run(s, t_end);
  int by_event = s->event_stop && st == VI_STOPPED;
  s->event_stop = 0;
  if (by_event) {
    *kind = s->last_event;
    return VI_OK;
  }
  return st;
}
