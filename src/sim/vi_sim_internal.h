/* vi_sim_internal.h - the simulation object and its integrator backends. */
#ifndef VI_SIM_INTERNAL_H
#define VI_SIM_INTERNAL_H

#include <math.h>

#include <gsl/gsl_roots.h>

#include "vi_internal.h"
#include "vi_ledger_internal.h"

/* What a backend step ended on.  HANDOVER: the backend cannot go on
 * accurately from s->t (the closed form lost its conditioning); s->t and the
 * state are those of the last good point, s->handover_why says why, and the
 * driver continues on CVODE. */
enum { VI_STEP_NONE = 0, VI_STEP_CONTACT = 1, VI_STEP_RELEASE = 2,
       VI_STEP_HANDOVER = 3 };

/* An integrator, chosen by pointer like gsl_odeiv2_step_type.  The state is
 * interleaved, z = (x_1, v_1, x_2, v_2, ...), so that a chain's Jacobian is
 * banded.  After step() s->t and s->z hold the new time and state. */
typedef struct vi_backend {
  const char *name;
  int (*start)(vi_sim *s);  /* (re)start from s->t, s->z, s->sticking */
  int (*step)(vi_sim *s, double t_end, int *event);
  int (*dense)(vi_sim *s, double t); /* state at t in the last step -> s->zs */
  int64_t (*stat)(const void *data, int which); /* counters of be_data */
  void (*destroy)(vi_sim *s);
  /* Make s->z the state at s->t.  NULL: step() always keeps s->z current.
   * A backend that builds physical states lazily sets s->z_stale after a
   * step; the driver calls vi_sim_sync() before it reads s->z. */
  int (*sync)(vi_sim *s);
  /* After a contact step's samples went out: locate the contact (s->t,
   * s->z) more accurately, or leave it (NULL: nothing to refine). */
  int (*refine)(vi_sim *s);
} vi_backend;

extern const vi_backend vi_backend_cvode;
extern const vi_backend vi_backend_exact;
extern const vi_backend vi_backend_arkode;

struct vi_sim {
  const vi_model *m;
  struct vi_xflow *flow; /* the model's exact flow (vi_flow_internal.h) */
  int n, method;
  double rtol, atol, vchat, h_restart, hmax;
  /* impacts resolved individually down to vres = impact_ratio * vscale
   * (the run's velocity scale, fixed at its first start); 0: the older
   * accuracy-driven summing */
  double impact_ratio, vscale, vres;
  int harmonic; /* a or b non-zero: cos/sin needed in the RHS */
  double wnorm;  /* |w|, the scale of gap tolerances */
  int ns;        /* number of stops (vi_model_add_stop) */
  double *wnorms, *ie_stop; /* |w_k| and the energy lost at stop k [ns] */
  double *sbuf;  /* scratch of the several-stop code [4n + 4 ns] */
  /* Sticking holds the stops stick_k [nstick] (nstick = 0 in free flight,
   * sticking = nstick > 0); for more than one, stick_L is the Cholesky
   * factor of their Delassus block G_SS. */
  int nstick, stick_k[VI_CONTACT_MAX];
  double stick_L[VI_CONTACT_MAX * VI_CONTACT_MAX];
  int contact_stop; /* set by the backend with VI_STEP_CONTACT/RELEASE */
  int fast_nvector; /* our vector ops instead of Debian's -O0 ones */

  double t, *z;   /* current time and state [2n] */
  int z_stale;    /* s->z lags s->t: call vi_sim_sync() before reading it */
  double gap;     /* g = w.x - x_s at s->t as the backend last saw it */
  int sticking, started;
  int method_used;                 /* VI_METHOD_* actually running */
  int handed_over;                 /* the closed form gave up: CVODE from now */
  char method_note[VI_MSG_LEN];    /* which ran and why */
  char handover_why[VI_MSG_LEN];   /* set by a backend with VI_STEP_HANDOVER */
  vi_cancel_fn cancel_fn; void *cancel_user; vi_destroy_fn cancel_free;
  double vn_floor, dt_floor, t_last_contact;
  /* summed chattering tails: stop k sticks from its tail's first impact,
   * its STICK event is due at the accumulation point pend[k].at (with the
   * rebound speed vn and the tail's loss ie); stick_pending of them, the
   * first due at stick_at (vi_chatter.c keeps both) */
  struct vi_pending { int on; double at, vn, ie; } *pend; /* [ns] */
  int stick_pending;
  double stick_at;
  double t_end;   /* of the current vi_sim_run call */

  vi_event_fn ev_fn;    void *ev_user;   vi_destroy_fn ev_free;
  vi_sample_fn smp_fn;  void *smp_user;  vi_destroy_fn smp_free;
  double smp_dt, smp_t0;  int64_t smp_k;
  vi_monitor_fn mon_fn; void *mon_user;  vi_destroy_fn mon_free;
  double mon_every, mon_next;
  double run_t0;
  int stop;       /* a callback asked to stop */
  int running;    /* inside vi_sim_run: state-changing calls refused */
  int destroy_asked; /* vi_sim_destroy from a callback: the run ends */
  int press_next; /* initial_contact: at rest on the stop, pressed next */
  double h_flight; /* first step after an impact: within the rebound's
                      flight (0: none); consumed by the backend's start */
  double tol_scale; /* rtol and atol of the integrators' flight after the
                       last contact, times this (<= 1; on_contact_one) */
  int event_stop; /* vi_sim_run_to_event: stop after the step of an event */
  int last_event; /* kind of the last event emitted */

  int64_t stats[VI_STAT_COUNT]; /* driver-owned counters */
  int64_t nevents[3];

  const vi_backend *be;
  void *be_data;
  /* the exact method runs sticking phases on CVODE: the other backend and
   * its data wait here meanwhile */
  const vi_backend *park_be;
  void *park_data;
  struct vi_held *held; /* the exact method's held phases (vi_held.c) */
  gsl_root_fsolver *brent;

  double *x, *v, *vp, *zs; /* scratch: n, n, n, 2n */
  double *w1, *w2, *w3;    /* scratch of the chatter map: n each */

  /* nonlinear forces (vi_force.c): the host's callback and built-in springs */
  vi_force_fn force_fn; vi_force_jac_fn force_jac; void *force_user;
  vi_destroy_fn force_free;
  struct vi_spring *springs;
  int nsprings, nforces;  /* nforces: springs plus the callback, if any */
  double *fbuf;           /* scratch [4n]: x, v, g, Psi^T g */
  double *fjac;           /* Jacobian workspace, made at first use */
  int force_failed;       /* 1 the callback failed, 2 a force not finite */
  double force_fail_t, force_fail_g;
  int force_fail_i;

  /* energy ledger (vi_ledger.c); NULL unless enabled */
  vi_ledger *led;
  vi_ledger_fn led_fn; void *led_user; vi_destroy_fn led_free;

  char errmsg[VI_MSG_LEN];
};

/* A call that changes the sim, made from inside a callback of its own run
 * (the run holds pointers into the state it would change): VI_ERR_STATE. */
int vi_sim_busy(vi_sim *s, const char *name);
#define VI_SIM_IDLE(s)                                                    \
  do {                                                                    \
    if ((s)->running) return vi_sim_busy((s), __func__);                  \
  } while (0)

/* A SUNDIALS call in a backend function with `int st` and a `cleanup`
 * label: a negative flag records the call in s->errmsg (unless SUNDIALS'
 * error handler already left a message) and leaves with
 * VI_ERR_INTEGRATOR. */
#define VI_SUN_TRY(call)                                               \
  do {                                                                 \
    int flag_ = (call);                                                \
    if (flag_ < 0) {                                                   \
      if (!s->errmsg[0] || st == VI_OK)                                \
        vi_fail(s->errmsg, VI_ERR_INTEGRATOR, "%s failed (flag %d)",   \
                #call, flag_);                                         \
      st = VI_ERR_INTEGRATOR;                                          \
      goto cleanup;                                                    \
    }                                                                  \
  } while (0)

/* Bring s->z up to s->t (see vi_backend.sync). */
static inline int vi_sim_sync(vi_sim *s)
{
  if (!s->z_stale || !s->be->sync) return 0;
  int st = s->be->sync(s);
  if (!st) s->z_stale = 0;
  return st;
}

/* A callback asked to stop (not merely vi_sim_run_to_event's pause): later
 * callbacks of the step are not called. */
static inline int vi_sim_user_stopped(const vi_sim *s)
{
  return s->stop && !s->event_stop;
}

/* The host's cancellation poll; backends call it inside long loops. */
static inline int vi_sim_cancelled(const vi_sim *s)
{
  return s->cancel_fn && s->cancel_fn(s->cancel_user);
}

/* Nonlinear forces (vi_force.c).  acc += M^-1 g(t, x, v) for an
 * interleaved state z; with gq != NULL the modal force Psi^T g too. */
void vi_force_add_accel(vi_sim *s, double t, const double *z, double *acc);
/* The message and status of a failed force evaluation (s->force_failed). */
int vi_force_failure(vi_sim *s);
/* The modal force Psi^T g [n] at (t, z) into gq: for the ledger. */
void vi_force_modal(vi_sim *s, double t, const double *z, double *gq);
/* d(M^-1 g)/dx and d(M^-1 g)/dv [n x n], column-major, at (t, z). */
int vi_force_jacobian(vi_sim *s, double t, const double *z, double **Ax,
                      double **Av); /* into the sim's workspace */
void vi_force_free(vi_sim *s);

/* The sticking set (vi_chatter.c): make the stops list [cnt] the stops
 * held (the projection needs the Cholesky factor of their Delassus block;
 * VI_ERR_UNSUPPORTED if it is singular), and whether stop k is held. */
int vi_sim_set_sticking(vi_sim *s, const int *list, int cnt);
int vi_sim_in_stick_set(const vi_sim *s, int k);

/* out = M^-1 (f^(k)(t) - K u - C ud), k = 1, 2: the k-th time derivative
 * of the free acceleration along a motion whose k-th and (k+1)-th
 * derivatives of x are u and ud (vi_sim.c). */
void vi_sim_accel_rate(const vi_sim *s, double t, int k, const double *u,
                       const double *ud, double *out);

/* The chatter map (vi_chatter.c), for stop k while the other stops of the
 * sticking set hold.  push: stop k's gap acceleration p [3] (the push of
 * its contact force) and its first two rates along the motion sticking on
 * stop k and the held ones from x, v at t.  normal: the structure's
 * stiffness kappa and damping gamma seen through stop k with the held
 * stops on theirs.  tail: the duration of the chattering sequence that
 * starts at rebound speed u (restitution r) under g'' + gamma g' + kappa g
 * = p0 + p1 t + p2 t^2 / 2, its bounces counted in *count; -1 if by the
 * model it does not accumulate. */
void vi_chatter_push(vi_sim *s, int k, double t, const double *x,
                     const double *v, double *p);
void vi_chatter_normal(vi_sim *s, int k, double *kappa, double *gamma);
double vi_chatter_tail(double u, double r, double p0, double p1, double p2,
                       double kappa, double gamma, int64_t *count);
/* Whether stop k's bounces end at this impact (see vi_chatter.c); *floor_hit
 * says a floor of vi_sim_set_floors decided it. */
int vi_chatter_wanted(vi_sim *s, int k, double vn, double push,
                      double dt_prev, const double *x, const double *v,
                      int *floor_hit);
/* Stop k's tail from rebound speed u at s->t, with the other held stops
 * on theirs: its duration (0: it holds at once), bounces in *count. */
double vi_chatter_sum(vi_sim *s, int k, double u, const double *x,
                      const double *v, int64_t *count);
/* Pending STICK events: record stop k's (due at `at`), the stop whose
 * event is due first by t (-1: none), and forget stop k's (-1: all). */
void vi_chatter_pend(vi_sim *s, int k, double at, double vn, double ie);
int vi_chatter_due(const vi_sim *s, double t);
void vi_chatter_unpend(vi_sim *s, int k);

/* Remove from a [n] the components along M^-1 w_k of the sticking stops
 * so that w_k.a = 0 for each: a -= M^-1 W_S G_SS^-1 W_S^T a; lam [nstick]
 * (may be NULL) receives the multipliers G_SS^-1 W_S^T a. */
void vi_sim_constrain_set(const vi_sim *s, double *a, double *lam);
static inline void vi_sim_constrain(const vi_sim *s, double *a, double *lam)
{
  if (s->nstick != 1) {
    vi_sim_constrain_set(s, a, lam);
    return;
  }
  const vi_model *m = s->m;
  int k = s->stick_k[0];
  const double *mw = vi_stop_minvw(m, k);
  double l = vi_dot(s->n, vi_stop_w(m, k), a) / m->G[k + (size_t)k * m->ns];
  for (int i = 0; i < s->n; i++) a[i] -= l * mw[i];
  if (lam) lam[0] = l;
}

/* Free acceleration M^-1 (f - C v - K x) at t for interleaved z; in a
 * sticking phase the components along M^-1 w_k of the sticking stops are
 * removed so that w_k.x'' = 0.  This is the right-hand side's hot loop,
 * hence inline. */
static inline void vi_sim_accel(vi_sim *s, double t, const double *z,
                                int sticking, double *acc)
{
  const vi_model *m = s->m;
  int n = s->n, bw = m->bw;
  double c = 1.0, sn = 0.0;
  if (s->harmonic) {
    c = cos(m->omega_f * t);
    sn = sin(m->omega_f * t);
  }
  if (m->band) vi_band_accel(m, t, z, acc); /* band storage: vi_band.c */
  else for (int i = 0; i < n; i++) {
    double a = m->Minv_a[i] * c + m->Minv_b[i] * sn + m->Minv_f0[i];
    int j0 = i - bw < 0 ? 0 : i - bw, j1 = i + bw >= n ? n - 1 : i + bw;
    for (int j = j0; j <= j1; j++) {
      size_t ij = (size_t)i + (size_t)j * n;
      a -= m->MinvK[ij] * z[2 * (size_t)j] + m->MinvC[ij] * z[2 * (size_t)j + 1];
    }
    acc[i] = a;
  }
  if (s->nforces) vi_force_add_accel(s, t, z, acc);
  if (sticking) vi_sim_constrain(s, acc, NULL);
}

/* Gap g = w.x - x_s and its rate w.x' of an interleaved state. */
static inline void vi_sim_gap(const vi_sim *s, const double *z, double *g,
                              double *gd)
{
  double a = 0.0, b = 0.0;
  for (int i = 0; i < s->n; i++) {
    a += s->m->Ws[i] * z[2 * (size_t)i];
    b += s->m->Ws[i] * z[2 * (size_t)i + 1];
  }
  *g = a - s->m->xsv[0];
  *gd = b;
}

/* Gap g = w_k.x - x_k and its rate w_k.x' of stop k. */
static inline void vi_sim_gap_k(const vi_sim *s, int k, const double *z,
                                double *g, double *gd)
{
  const double *w = vi_stop_w(s->m, k);
  double a = 0.0, b = 0.0;
  for (int i = 0; i < s->n; i++) {
    a += w[i] * z[2 * (size_t)i];
    b += w[i] * z[2 * (size_t)i + 1];
  }
  *g = a - s->m->xsv[k];
  *gd = b;
}

/* How far beyond stop k a state may sit: the integration error. */
static inline double vi_sim_gap_tol(const vi_sim *s, int k)
{
  double xs = s->m->xsv[k];
  return 100.0 * (s->atol + s->rtol * fabs(xs)) * s->wnorms[k] +
         1e-12 * fabs(xs);
}

/* Replace the hot operations of a SUNDIALS serial vector (and of its future
 * clones) with ours, compiled with optimisation (vi_nvector.c). */
struct _generic_N_Vector;
void vi_nvector_fast_ops(struct _generic_N_Vector *v);

/* Root of f in [lo, hi] with f(lo) < 0 <= f(hi) (or the reverse), to
 * round-off in t, by GSL's Brent solver. */
int vi_sim_bracket(vi_sim *s, double (*f)(double, void *), void *params,
                   double lo, double hi, double *root);

#endif
