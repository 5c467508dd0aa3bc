/* vi_sim_state.h - the simulation object, its integrator backends' table
 * and the helpers every part of the simulator shares: state access, the
 * sticking set and its projection, gaps, cancellation, root bracketing.
 * The lowest layer of src/sim: it includes nothing of the simulator;
 * forces (vi_force_internal.h), the right-hand side (vi_rhs.h), the
 * chatter map (vi_chatter_internal.h), the backends and, on top, the
 * driver vi_sim.c (vi_sim_internal.h) build on it. */
#ifndef VI_SIM_STATE_H
#define VI_SIM_STATE_H

#include <float.h>
#include <math.h>

#include <gsl/gsl_roots.h>

#include "vi_ledger_internal.h"
#include "vi_model_internal.h"
#include "vi_storage.h"

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
  /* A backend that keeps its own coordinates (the exact method's modes)
   * can take a lone impact there, in O(n) where the physical state costs
   * O(n^2) to build and to convert back (NULL: the driver works on s->z).
   * normal: stop k's gap g = w_k.x - x_k, its rate and its acceleration at
   * s->t, from the backend's state; non-zero: not available now (the
   * driver then reads s->z).  kick: the state at s->t changed by dx = a
   * M^-1 w_k, dv = b M^-1 w_k (an impulse and the projection on the stop)
   * in those coordinates, which stay the state's own: s->z goes stale and
   * start() continues from them. */
  int (*normal)(vi_sim *s, int k, double *g, double *gd, double *gdd);
  void (*kick)(vi_sim *s, int k, double a, double b);
  /* The modal state q, q' [n] at s->t where the backend holds it (the
   * ledger's energies need no physical state then); non-zero: not now. */
  int (*modal)(vi_sim *s, const double **q, const double **qd);
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
  int ns;        /* number of stops (vi_model_add_stop) */
  double *wnorms, *ie_stop; /* |w_k| and the energy lost at stop k [ns] */
  /* the harmonic response's size as stop k's gap sees it (the modes'
   * particular solutions, which the closed form sums and cancels) [ns]:
   * with |x_s| and the state's own terms, the scale of the gap's
   * round-off (vi_sim.c, particular_scale) */
  double *pscale;
  /* the round-off of stop k's gap along the current flight, as the
   * closed form estimates it at its start (vi_exact.c; 0: none) [ns] */
  double *gnoise;
  double *vn_last; /* stop k's last approach velocity (vi_chatter.c) [ns] */
  double *sbuf;  /* scratch of the several-stop code [4n], then the
                    per-stop arrays above [5 ns] */
  /* Sticking holds the stops stick_k [nstick] (nstick = 0 in free flight,
   * sticking = nstick > 0); for more than one, stick_L is the Cholesky
   * factor of their Delassus block G_SS. */
  int nstick, stick_k[VI_CONTACT_MAX];
  double stick_L[VI_CONTACT_MAX * VI_CONTACT_MAX];
  int contact_stop; /* set by the backend with VI_STEP_CONTACT/RELEASE */
  int fast_nvector; /* our vector ops instead of Debian's -O0 ones */

  double t, *z;   /* current time and state [2n] */
  int z_stale;    /* s->z lags s->t: call vi_sim_sync() before reading it;
                     the driver writes s->z only after a sync */
  int ev_states;  /* events carry x, v-, v+ (vi_sim_set_event_states) */
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
/* The same poll every 1024th call (*count counts them), for recursive
 * searches whose nodes cost nanoseconds but may number 2^60 at round-off
 * (a load near the range's end). */
static inline int vi_sim_cancelled_every(const vi_sim *s, unsigned *count)
{
  return !(++*count & 1023u) && vi_sim_cancelled(s);
}
/* The poll after panel k of a ledger quadrature of np panels, every 64th
 * (8 nodes of every mode each): one grid step of the closed forms spans a
 * quarter period of the fastest mode the gaps see, the panels a quarter
 * radian of the fastest of all, so a stiff mode the stops do not see can
 * put 1e6 panels, seconds, into one step (issue 29). */
static inline int vi_sim_quad_cancelled(const vi_sim *s, int64_t k,
                                        int64_t np)
{
  return !((k + 1) & 63) && k + 1 < np && vi_sim_cancelled(s);
}


/* The sticking set (vi_sim_state.c): make the stops list [cnt] the stops
 * held (the projection needs the Cholesky factor of their Delassus block;
 * VI_ERR_UNSUPPORTED if it is singular), and whether stop k is held. */
int vi_sim_set_sticking(vi_sim *s, const int *list, int cnt);
int vi_sim_in_stick_set(const vi_sim *s, int k);
/* The Cholesky factor L [cnt x cnt] of the Delassus block G_LL of the
 * stops list [cnt]: 0, or -1 if their stop vectors are dependent. */
int vi_sim_stick_factor(const vi_model *m, int cnt, const int *list,
                        double *L);
/* a - M^-1 W_L G_LL^-1 W_L^T a for the stops list [cnt], L the Cholesky
 * factor of their Delassus block G_LL: what remains of a with w_k.a = 0 on
 * each (lam [cnt], may be NULL: the multipliers G_LL^-1 W_L^T a). */
void vi_sim_project(const vi_sim *s, int cnt, const int *list,
                    const double *L, double *a, double *lam);

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

/* The forcing's phase at t (no cos/sin without harmonic forcing). */
static inline vi_phase vi_sim_phase(const vi_sim *s, double t)
{
  return s->harmonic ? vi_phase_at(s->m->omega_f, t)
                     : vi_phase_none(s->m->omega_f);
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

/* The root layout of the SUNDIALS backends with several stops or while
 * sticking: first the reaction of each held stop (its multiplier, falling
 * through zero), then the pair (gap rising, rate falling) of every stop
 * not held, in stop order.  The slot of stop k's gap there, or -1 (held). */
static inline int vi_sim_gap_root(const vi_sim *s, int k)
{
  int i = s->nstick;
  for (int j = 0; j < s->ns; j++) {
    int held = 0;
    for (int q = 0; q < s->nstick; q++) held |= s->stick_k[q] == j;
    if (held) {
      if (j == k) return -1;
      continue;
    }
    if (j == k) return i;
    i += 2;
  }
  return -1;
}

/* How far beyond stop k a state may sit: the integration error, or the
 * round-off of a gap summed from terms of the harmonic response's size
 * where that is larger (a load so large that atol is below its digits) */
static inline double vi_sim_gap_tol(const vi_sim *s, int k)
{
  double xs = s->m->xsv[k];
  double tol = 100.0 * (s->atol + s->rtol * fabs(xs)) * s->wnorms[k] +
               1e-12 * fabs(xs);
  return fmax(tol, 256.0 * DBL_EPSILON * s->pscale[k]);
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
