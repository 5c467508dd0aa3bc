/* vi_sim_io.c - a simulation's settings and what it reports: the public
 * setters and getters of vi_sim.h, kept apart from the run loop (vi_sim.c)
 * as CVODE keeps its own in cvode_io.c.  A setting that shapes the
 * integrator drops the backend, rebuilt at the next vi_sim_run. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vi_sim_internal.h"

static const char *const method_names[VI_METHOD_COUNT] = {
    "adams", "bdf", "exact", "auto", "erk"};

const char *vi_method_name(int method)
{
  return method >= 0 && method < VI_METHOD_COUNT ? method_names[method] : NULL;
}

int vi_method_from_name(const char *name)
{
  for (int k = 0; name && k < VI_METHOD_COUNT; k++)
    if (!strcmp(name, method_names[k])) return k;
  return -1;
}

const char *vi_stat_name(int which)
{
  static const char *const names[VI_STAT_COUNT] = {
      "steps", "rhs_evals", "jac_evals", "root_evals", "impacts", "sticks",
      "graze_checks", "reinits", "handovers", "chatter_skipped", "floors",
      "polishes"};
  return which >= 0 && which < VI_STAT_COUNT ? names[which] : NULL;
}

/* Settings that shape the integrator take effect at the next restart: the
 * backend is rebuilt lazily by vi_sim_run. */
int vi_sim_set_method(vi_sim *s, int method)
{
  if (!s) return VI_ERR_ARG;
  VI_SIM_IDLE(s);
  if (!vi_method_name(method))
    return vi_fail(s->errmsg, VI_ERR_ARG, "unknown method %d", method);
  if (method == VI_METHOD_EXACT && !s->flow->ok)
    return vi_fail(s->errmsg, VI_ERR_UNSUPPORTED,
                   "exact method unavailable: %s", s->flow->why);
  if (method == VI_METHOD_EXACT && s->nforces)
    return vi_fail(s->errmsg, VI_ERR_UNSUPPORTED, "exact method unavailable: "
                   "nonlinear forces have no closed form");
  s->method = method;
  s->handed_over = 0;
  vi_sim_backend_reset(s);
  vi_sim_note_method(s);
  return VI_OK;
}

int vi_sim_set_tolerances(vi_sim *s, double rtol, double atol)
{
  if (!s) return VI_ERR_ARG;
  VI_SIM_IDLE(s);
  if (!(rtol > 0.0) || !(atol > 0.0) || !isfinite(rtol) || !isfinite(atol))
    return vi_fail(s->errmsg, VI_ERR_TOLERANCE,
                   "tolerances rtol = %g, atol = %g must be positive and "
                   "finite", rtol, atol);
  if (rtol >= 1.0)
    return vi_fail(s->errmsg, VI_ERR_TOLERANCE,
                   "rtol = %g must be below 1 (a relative accuracy)", rtol);
  if (rtol < 2.0 * DBL_EPSILON)
    return vi_fail(s->errmsg, VI_ERR_TOLERANCE,
                   "rtol = %g is below twice the machine epsilon", rtol);
  s->rtol = rtol;
  s->atol = atol;
  vi_sim_backend_reset(s);
  return VI_OK;
}

int vi_sim_set_initial(vi_sim *s, double t0, const double *x0, const double *v0)
{
  if (!s) return VI_ERR_ARG;
  VI_SIM_IDLE(s);
  const vi_model *m = s->m;
  int n = s->n;
  if (!isfinite(t0))
    return vi_fail(s->errmsg, VI_ERR_NONFINITE, "t0 = %g is not finite", t0);
  /* validate in scratch: a refused state leaves the sim as it was */
  for (int i = 0; i < n; i++) {
    double xi = x0 ? x0[i] : 0.0, vi = v0 ? v0[i] : 0.0;
    if (!isfinite(xi) || !isfinite(vi))
      return vi_fail(s->errmsg, VI_ERR_NONFINITE,
                     "initial state x(%d) = %g, v(%d) = %g is not finite",
                     i + 1, xi, i + 1, vi);
    s->zs[2 * (size_t)i] = xi;
    s->zs[2 * (size_t)i + 1] = vi;
  }
  for (int k = 0; k < s->ns; k++) {
    double g, gd, xs = m->xsv[k];
    vi_sim_gap_k(s, k, s->zs, &g, &gd);
    /* allow round-off of a state handed over from an earlier contact */
    if (g > 1e-13 * fmax(1.0, fabs(xs))) {
      if (s->ns == 1)
        return vi_fail(s->errmsg, VI_ERR_INITIAL_STATE,
                       "initial state violates the stop: w.x0 = %.17g > x_s "
                       "= %.17g", g + xs, xs);
      return vi_fail(s->errmsg, VI_ERR_INITIAL_STATE,
                     "initial state violates stop %d: w.x0 = %.17g > x_s = "
                     "%.17g", k + 1, g + xs, xs);
    }
  }
  vi_ledger_settle(s->led); /* owed up to the old time */
  memcpy(s->z, s->zs, sizeof(double) * 2 * (size_t)n);
  s->z_stale = 0;
  s->t = t0;
  s->sticking = 0;
  s->nstick = 0;
  s->started = 0;
  vi_chatter_unpend(s, -1);
  s->t_last_contact = -HUGE_VAL;
  if (s->led) vi_ledger_begin(s->led, s->t, s->z);
  return VI_OK;
}

int vi_sim_set_chatter_threshold(vi_sim *s, double vmin)
{
  if (!s) return VI_ERR_ARG;
  VI_SIM_IDLE(s);
  if (!(vmin >= 0.0) || !isfinite(vmin))
    return vi_fail(s->errmsg, VI_ERR_ARG, "chatter threshold %g must be a "
                   "finite non-negative velocity", vmin);
  s->vchat = vmin;
  return VI_OK;
}

int vi_sim_set_impact_resolution(vi_sim *s, double ratio)
{
  if (!s) return VI_ERR_ARG;
  VI_SIM_IDLE(s);
  if (!(ratio >= 0.0 && ratio < 1.0))
    return vi_fail(s->errmsg, VI_ERR_ARG, "impact resolution %g must lie in "
                   "[0, 1) (a fraction of the run's velocity scale)", ratio);
  s->impact_ratio = ratio;
  s->vres = ratio * s->vscale;
  return VI_OK;
}

double vi_sim_velocity_scale(const vi_sim *s) { return s ? s->vscale : 0.0; }

int vi_sim_set_restart_step(vi_sim *s, double h)
{
  if (!s) return VI_ERR_ARG;
  VI_SIM_IDLE(s);
  if (!(h >= 0.0) || !isfinite(h))
    return vi_fail(s->errmsg, VI_ERR_ARG, "restart step %g must be >= 0", h);
  s->h_restart = h;
  return VI_OK;
}

int vi_sim_set_max_step(vi_sim *s, double hmax)
{
  if (!s) return VI_ERR_ARG;
  VI_SIM_IDLE(s);
  if (!(hmax >= 0.0) || !isfinite(hmax))
    return vi_fail(s->errmsg, VI_ERR_ARG, "max step %g must be >= 0", hmax);
  s->hmax = hmax;
  vi_sim_backend_reset(s);
  return VI_OK;
}

int vi_sim_set_native_vector_ops(vi_sim *s, int on)
{
  if (!s) return VI_ERR_ARG;
  VI_SIM_IDLE(s);
  if (on != 0 && on != 1)
    return vi_fail(s->errmsg, VI_ERR_ARG, "native vector ops: %d is not 0 or 1", on);
  s->fast_nvector = on;
  vi_sim_backend_reset(s);
  return VI_OK;
}

int vi_sim_set_cancel(vi_sim *s, vi_cancel_fn fn, void *user,
                      vi_destroy_fn destroy)
{
  if (!s) return VI_ERR_ARG;
  VI_SIM_IDLE(s);
  s->cancel_fn = fn;
  vi_user_set(&s->cancel_user, &s->cancel_free, user, destroy);
  return VI_OK;
}

int vi_sim_set_floors(vi_sim *s, double vn_min, double dt_min)
{
  if (!s) return VI_ERR_ARG;
  VI_SIM_IDLE(s);
  if (!(vn_min >= 0.0) || !isfinite(vn_min) || !(dt_min >= 0.0) ||
      !isfinite(dt_min))
    return vi_fail(s->errmsg, VI_ERR_ARG, "floors v_n = %g, dt = %g must be "
                   "finite and >= 0", vn_min, dt_min);
  s->vn_floor = vn_min;
  s->dt_floor = dt_min;
  return VI_OK;
}

int vi_sim_method_used(const vi_sim *s) { return s ? s->method_used : -1; }

const char *vi_sim_method_note(const vi_sim *s)
{
  return s ? s->method_note : "";
}

int vi_sim_set_event_callback(vi_sim *s, vi_event_fn fn, void *user,
                              vi_destroy_fn destroy)
{
  if (!s) return VI_ERR_ARG;
  VI_SIM_IDLE(s);
  s->ev_fn = fn;
  vi_user_set(&s->ev_user, &s->ev_free, user, destroy);
  return VI_OK;
}

int vi_sim_set_event_states(vi_sim *s, int on)
{
  if (!s) return VI_ERR_ARG;
  VI_SIM_IDLE(s);
  if (on != 0 && on != 1)
    return vi_fail(s->errmsg, VI_ERR_ARG, "event states switch %d is not 0 "
                   "or 1", on);
  s->ev_states = on;
  return VI_OK;
}

int vi_sim_set_sampling(vi_sim *s, double dt, vi_sample_fn fn, void *user,
                        vi_destroy_fn destroy)
{
  if (!s) return VI_ERR_ARG;
  VI_SIM_IDLE(s);
  if (fn && !(dt > 0.0 && isfinite(dt)))
    return vi_fail(s->errmsg, VI_ERR_ARG, "sampling interval %g must be "
                   "positive and finite", dt);
  s->smp_fn = fn;
  vi_user_set(&s->smp_user, &s->smp_free, user, destroy);
  s->smp_dt = dt;
  s->smp_t0 = s->t;
  s->smp_k = 0;
  return VI_OK;
}

int vi_sim_set_monitor(vi_sim *s, double every, vi_monitor_fn fn, void *user,
                       vi_destroy_fn destroy)
{
  if (!s) return VI_ERR_ARG;
  VI_SIM_IDLE(s);
  if (fn && !(every > 0.0))
    return vi_fail(s->errmsg, VI_ERR_ARG, "monitor interval %g must be > 0",
                   every);
  s->mon_fn = fn;
  vi_user_set(&s->mon_user, &s->mon_free, user, destroy);
  s->mon_every = every;
  s->mon_next = s->t;
  return VI_OK;
}

int vi_sim_state(const vi_sim *s, double *t, double *x, double *v)
{
  if (!s) return VI_ERR_ARG;
  /* s->z is a view of the backend's state, built when read (from a
   * callback, after a bounce kept in modes): building it changes nothing
   * that a caller can see, so the handle counts as const here */
  int st = vi_sim_sync((vi_sim *)s);
  if (st) return st;
  if (t) *t = s->t;
  for (int i = 0; i < s->n; i++) {
    if (x) x[i] = s->z[2 * (size_t)i];
    if (v) v[i] = s->z[2 * (size_t)i + 1];
  }
  return VI_OK;
}

int vi_sim_n(const vi_sim *s) { return s ? s->n : 0; }

int vi_sim_is_sticking(const vi_sim *s) { return s ? s->sticking : 0; }

int vi_sim_stop_losses(const vi_sim *s, double *ie)
{
  if (!s || !ie) return VI_ERR_ARG;
  memcpy(ie, s->ie_stop, sizeof(double) * (size_t)s->ns);
  return VI_OK;
}

int64_t vi_sim_stat(const vi_sim *s, int which)
{
  if (!s || which < 0 || which >= VI_STAT_COUNT) return -1;
  int64_t v = s->stats[which];
  if (s->be_data) v += s->be->stat(s->be_data, which);
  if (s->park_data) v += s->park_be->stat(s->park_data, which);
  return v + vi_held_stat(s, which);
}

/* ---- the energy ledger's public face (the bookkeeping: vi_ledger.c) ---- */
int vi_sim_enable_ledger(vi_sim *s, int on)
{
  if (!s) return VI_ERR_ARG;
  VI_SIM_IDLE(s);
  if (on != 0 && on != 1)
    return vi_fail(s->errmsg, VI_ERR_ARG, "ledger switch %d is not 0 or 1", on);
  int st = on ? vi_model_need_modes(s->m, s->errmsg, "the energy ledger needs")
               : VI_OK;
  if (st) return st;
  vi_ledger_destroy(s->led);
  s->led = NULL;
  if (on) {
    if (!(s->led = vi_ledger_create(s->m)))
      return vi_fail(s->errmsg, VI_ERR_NOMEM, "out of memory for the ledger");
    vi_ledger_set_callback(s->led, s->led_fn, s->led_user);
    if (vi_sim_sync(s) == VI_OK)
      vi_ledger_begin(s->led, s->t, s->z);
  }
  /* the integrator must be rebuilt with (or without) the quadratures */
  if (s->be_data) s->be->destroy(s);
  s->started = 0;
  return VI_OK;
}

int vi_sim_set_ledger_callback(vi_sim *s, vi_ledger_fn fn, void *user,
                               vi_destroy_fn destroy)
{
  if (!s) return VI_ERR_ARG;
  VI_SIM_IDLE(s);
  s->led_fn = fn;
  vi_user_set(&s->led_user, &s->led_free, user, destroy);
  if (s->led) vi_ledger_set_callback(s->led, fn, user);
  return VI_OK;
}

int vi_sim_ledger(const vi_sim *s, double *E, double *FE, double *DE,
                      double *XE, double *CE, double *dE, double *ie)
{
  if (!s) return VI_ERR_ARG;
  if (!s->led) return VI_ERR_STATE;
  vi_ledger_totals(s->led, s->z, E, FE, DE, XE, CE, dE, ie);
  return VI_OK;
}

double vi_sim_ledger_max_residual(const vi_sim *s)
{
  return s && s->led ? vi_ledger_max_residual(s->led) : 0.0;
}

int vi_sim_ledger_force(const vi_sim *s, double *NE)
{
  if (!s || !NE) return VI_ERR_ARG;
  if (!s->led) return VI_ERR_STATE;
  vi_ledger_force_totals(s->led, NE);
  return VI_OK;
}
