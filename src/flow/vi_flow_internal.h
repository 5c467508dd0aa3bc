/* vi_flow_internal.h - the exact flow between impacts, the third layer
 * above the model (M, C, K, forcing, stops) and its modes (vi_modal.c).
 *
 * A vi_xflow is built from a set-up model by whoever needs it and never
 * changes afterwards; the model knows nothing of it.  A simulation builds
 * its own at vi_sim_create: for proportional damping that is the harmonic
 * particular solution of each mode, O(n) in one allocation (measured: no
 * change in build/rel/vi_bench_sweep, which creates a simulation per
 * forcing frequency), and a per-simulation object needs no reference
 * counting or locking when sweeps create simulations from one model on
 * several threads.  Non-proportional damping adds the first-order
 * eigen-solution (LAPACK dgeev on 2n x 2n), so a caller that advances
 * many states holds one flow and calls vi_xflow_physical rather than the
 * public vi_flow_physical, which builds a flow per call. */
#ifndef VI_FLOW_INTERNAL_H
#define VI_FLOW_INTERNAL_H

#include "vi_model_internal.h"
#include "vi_storage.h"

/* Models of up to this many dofs keep a flow's scratch vectors on the stack:
 * the per-sample flows of identification and orbits allocated at every call
 * (15 % of a sanitized identification in the allocator). */
#define VI_FLOW_SMALL 16

typedef struct vi_general vi_general; /* vi_general.c */

typedef struct vi_xflow {
  int ok;                 /* closed-form flow available */
  char why[VI_MSG_LEN];   /* if not, why */
  double *pA, *pB;        /* harmonic particular solution per mode [n] */
  vi_general *gen;        /* non-proportional damping: first-order modes */
} vi_xflow;

/* Build the flow of a set-up model.  VI_OK (f->ok says whether the closed
 * form applies) or VI_ERR_NOMEM; *out is NULL on failure. */
int vi_xflow_create(const vi_model *m, vi_xflow **out);
void vi_xflow_destroy(vi_xflow **f);

/* Free motion with a flow of m (arguments as vi_flow_physical /
 * vi_flow_modal, unchecked). */
int vi_xflow_physical(const vi_xflow *f, const vi_model *m, double t0,
                      const double *x0, const double *v0, double t, double *x,
                      double *v);
int vi_xflow_modal(const vi_xflow *f, const vi_model *m, double t0,
                   const double *q0, const double *qd0, double t, double *q,
                   double *qd);
/* One flight of a flow (ok) from its start: what every time of it shares,
 * the modal start relative to the harmonic particular solution (or the
 * first-order modal amplitudes of vi_general.c), so that a caller
 * evaluating many times of one flight (identification: every sample
 * between two impacts) starts it once.  vi_xflow_physical and
 * vi_xflow_modal are a start and one evaluation of a vi_xseg. */
typedef struct vi_gflow vi_gflow;
typedef struct vi_xseg {
  const vi_xflow *fl;
  const vi_model *m;
  double t0;
  double *w, *wd, *f; /* per mode: q - H, q' - H' at t0, F0 - lambda w [n] */
  vi_gflow *g;        /* non-proportional damping: the first-order flow */
  double *z;          /* and its interleaved state [2n] */
} vi_xseg;
/* s for flights of the flow fl of m; buf [3n] is the caller's and is
 * kept.  VI_OK or VI_ERR_NOMEM (non-proportional damping allocates);
 * vi_xseg_release frees what init allocated (not buf). */
int vi_xseg_init(vi_xseg *s, const vi_xflow *fl, const vi_model *m, double *buf);
void vi_xseg_release(vi_xseg *s);
/* Start from (x0, v0) at t0, or (proportional damping only) from the
 * modal (q0, qd0), which may be s->w, s->wd. */
void vi_xseg_start(vi_xseg *s, double t0, const double *x0, const double *v0);
void vi_xseg_start_modal(vi_xseg *s, double t0, const double *q0,
                         const double *qd0);
/* The state at t >= t0: modal (proportional damping only; q or qd may be
 * NULL where that half is not wanted; with c [4n] not NULL each mode's
 * 2 x 2 state-transition matrix over t - t0 too, as vi_flow_stm2's, from
 * the same propagator) or physical, through work [2n] (which other
 * damping, evaluated in s's own scratch, leaves alone). */
void vi_xseg_modal(const vi_xseg *s, double t, double *q, double *qd, double *c);
/* The longest run of vi_xseg_modal_run. */
#define VI_XSEG_RUN 64
/* vi_xseg_modal at the k <= VI_XSEG_RUN times t + i h, i = 0..k-1 (a
 * recording's samples within one flight): sample i's q, qd at q + i ld,
 * qd + i ld and its c at c + 4 n i (any may be NULL).  The closed form is
 * evaluated at t only; each later sample is the one before carried over h
 * by the flight's own map (the flow's exact affine step, its propagator
 * taken once per mode) and the forcing's phase by one rotation: no sine
 * or exponential per sample, a few ulp more per step. */
void vi_xseg_modal_run(const vi_xseg *s, double t, double h, int k,
                       double *q, double *qd, size_t ld, double *c);
void vi_xseg_physical(vi_xseg *s, double t, double *x, double *v,
                      double *work);
/* 1 if the closed-form flow of m exists (builds one to find out: cheap
 * for proportional damping), 0 if not or out of memory. */
int vi_xflow_available(const vi_model *m);

/* The harmonic particular solution A cos + B sin of q'' + d q' + lambda q
 * = Fc cos(Om t) + Fs sin(Om t), the one home of the formula (free and
 * held modes alike): 0 when the mode is forced at an undamped resonance
 * (|lambda - Om^2|^2 + (d Om)^2 below 1e-28 of max(lambda^2, Om^4)), with
 * A = B = 0; unforced modes get 0 and return 1. */
int vi_harmonic_particular(double lambda, double d, double Om, double Fc,
                           double Fs, double *A, double *B);
/* Closed-form mode j (vi_flow.c): particular solution at the forcing's
 * phase p of t, with tau = t - t0 for the polynomial part of a rigid-body
 * mode, and the homogeneous solution from (u0, v0) after tau. */
void vi_flow_particular(const vi_model *m, const vi_xflow *f, int j,
                        const vi_phase *p, double tau, double *qp,
                        double *qpd);
void vi_flow_homogeneous(double lambda, double d, double u0, double v0,
                         double tau, double *u, double *ud);
/* Mode u'' + d u' + lambda u = F relative to its start (vi_flow.c):
 * u = u0 + B v0 + phi (F - lambda u0), u' = Bp v0 + B (F - lambda u0).
 * One propagator computes both this basis and the homogeneous solution
 * above (its F = 0 case). */
void vi_flow_basis(double lambda, double d, double tau, double *B, double *Bp,
                   double *phi);
/* The same, and where the underdamped closed form took them (1; else 0)
 * the values it shares with the ledger's integrals over the flight
 * (vi_ledger_flight.h), which would compute them again: sin, cos (mu tau /
 * 2), e^{-h tau} - 1 and e^{-h tau} (h = d / 2, mu = sqrt(lambda - h^2))
 * into half [4]. */
int vi_flow_basis_half(double lambda, double d, double tau, double *B,
                       double *Bp, double *phi, double half[4]);
/* The mode's 2 x 2 state-transition matrix after tau, column-major:
 * (u, u') from (1, 0) in c[0], c[1] and from (0, 1) in c[2], c[3]. */
void vi_flow_stm2(double lambda, double d, double tau, double c[4]);

/* Exact flow for any damping (vi_general.c): the first-order
 * eigen-solution of a model whose damping is not proportional; a vi_gflow
 * is the flow from one start.  vi_general_create: VI_OK, VI_ERR_NOMEM,
 * VI_ERR_LAPACK or VI_ERR_UNSUPPORTED (not safely diagonalisable, or a
 * resonance), with the reason in why [VI_MSG_LEN]. */
int vi_general_create(const vi_model *m, vi_general **out, char *why);
void vi_general_destroy(vi_general **g);
double vi_general_top_frequency(const vi_general *g, double omega_f);
/* The largest |lambda_k| among the modes whose transient still moves some
 * stop's gap by more than tol at t (vi_gflow_start's state): the rates a
 * scan must resolve besides the oscillations, where modes are overdamped
 * (real lambda, no period) */
double vi_gflow_live_rate(const vi_gflow *f, double t, double tol);
/* sum_k |w_q.V_k| (|P_k| + |Q_k| + |R_k|): the size of the particular
 * solution as stop q's gap sees it, against which the flow cancels */
double vi_general_particular_scale(const vi_general *g, int q);
vi_gflow *vi_gflow_create(const vi_general *g);
void vi_gflow_free(vi_gflow *f);
/* z: interleaved state (x_1, v_1, ...) at t0 */
void vi_gflow_start(vi_gflow *f, const vi_model *m, double t0, const double *z);
/* At t: stop q's gap w_q.x - x_q and rate w_q.x' (q >= 0), or every
 * stop's (q < 0: gap, rate [ns]); gap NULL: none; with z != NULL the state
 * too */
void vi_gflow_eval(vi_gflow *f, const vi_model *m, double t, int q,
                   double *gap, double *rate, double *z);

/* The constrained modes of a held set S of stops (MODEL.md section 9;
 * vi_constrained.c).  In the free modal coordinates q (Psi^T M
 * Psi = I) the held gaps are P^T q = x_S with P = [psi_k], k in S; the
 * motions that keep them are q = q_c + Phi u, q_c = P G^-1 x_S (G = P^T P,
 * the Delassus block), Phi an orthonormal basis of null(P^T) that
 * diagonalises Phi^T Lambda Phi.  Rayleigh damping D = a I + b Lambda
 * stays diagonal in u, so each constrained mode is a damped oscillator:
 *   u_i'' + dmp_i u_i' + om2_i u_i = Phi_i^T (F(t) - Lambda q_c)
 * and the reactions lambda_S = G^-1 P^T (F - D q' - Lambda q) are
 *   lambda_k = lc_k + lA_k cos + lB_k sin - R_k.(u + b u')
 * (P^T Phi = 0 removes the a part of the damping). */
typedef struct vi_cmodes {
  int cnt, set[VI_CONTACT_MAX]; /* the held stops, in the driver's order */
  int ok;                       /* the closed form applies */
  char why[VI_MSG_LEN];         /* if not, why */
  int n, m;                     /* free modes; constrained modes n - cnt */
  double brl;                   /* Rayleigh b */
  double *Phi;                  /* [n x m], orthonormal columns */
  double *om2, *dmp;            /* Omega_i^2, a + b Omega_i^2 [m] */
  double *F0, *pA, *pB;         /* constant forcing, harmonic particular
                                   solution pA cos + pB sin [m] */
  double *fa, *fb;              /* harmonic forcing amplitudes [m] */
  double Om;                    /* the Omega of pA, pB and top */
  int built;                    /* every part but pA, pB, top is set: a
                                   new non-zero Omega may retune them */
  double *qc;                   /* q_c [n] */
  double *R;                    /* reaction weights, stop i's at [i m] */
  double *Pg;                   /* Phi^T psi_k of every stop, at [k m] */
  double *gc;                   /* psi_k.q_c - x_k of every stop [ns] */
  double lc[VI_CONTACT_MAX], lA[VI_CONTACT_MAX], lB[VI_CONTACT_MAX];
  double lscale[VI_CONTACT_MAX]; /* size of the terms lambda_k sums */
  double top;                   /* fastest rate of the constrained modes */
} vi_cmodes;

/* pA, pB, top (and ok) for a new forcing frequency Om, both it and the
 * one the modes were built for non-zero: the eigen-solve is kept (a
 * study sweeping Omega shares the modes across its points). */
void vi_cmodes_retune(vi_cmodes *c, double Om);

/* Build the constrained modes of the stops set [cnt] of a set-up model
 * with modes: VI_OK with *out (out->ok says whether the closed form
 * applies, out->why why not), VI_ERR_NOMEM or VI_ERR_LAPACK. */
int vi_cmodes_create(const vi_model *m, const int *set, int cnt,
                     vi_cmodes **out, char *errmsg);
void vi_cmodes_destroy(vi_cmodes **cm);

#endif
