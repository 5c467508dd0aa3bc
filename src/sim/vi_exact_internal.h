/* vi_exact_internal.h - the pieces of the exact method (vi_exact*.c). */
#ifndef VI_EXACT_INTERNAL_H
#define VI_EXACT_INTERNAL_H

#include "vi_flow_internal.h"
#include "vi_sim_internal.h"

/* The step-by-step scan of the closed form (vi_exact_scan.c): the exact
 * method for non-proportional damping. */
extern const vi_backend vi_backend_exact_scan;

/* The first member of either backend's data says which it is. */
enum { EX_KIND_SCAN = 1, EX_KIND_FAST = 2 };

/* The constrained modes of a held set S of stops (MODEL.md section 9;
 * src/flow/vi_constrained.c).  In the free modal coordinates q (Psi^T M
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
  double *qc;                   /* q_c [n] */
  double *R;                    /* reaction weights, stop i's at [i m] */
  double *Pg;                   /* Phi^T psi_k of every stop, at [k m] */
  double *gc;                   /* psi_k.q_c - x_k of every stop [ns] */
  double lc[VI_CONTACT_MAX], lA[VI_CONTACT_MAX], lB[VI_CONTACT_MAX];
  double lscale[VI_CONTACT_MAX]; /* size of the terms lambda_k sums */
  double top;                   /* fastest rate of the constrained modes */
} vi_cmodes;

/* Build the constrained modes of the stops set [cnt] of a set-up model
 * with modes: VI_OK with *out (out->ok says whether the closed form
 * applies, out->why why not), VI_ERR_NOMEM or VI_ERR_LAPACK. */
int vi_cmodes_create(const vi_model *m, const int *set, int cnt,
                     vi_cmodes **out, char *errmsg);
void vi_cmodes_destroy(vi_cmodes **cm);

/* Held phases of the exact method in closed form (src/sim/vi_held.c): the
 * simulation's cache of constrained modes and the flow of the current
 * phase live in s->held.  vi_held_available: the closed form can hold the
 * current sticking set (builds and caches its modes; 0 on failure, and
 * the sticking phase then runs on CVODE).  The others are the exact
 * backend's entries while s->sticking. */
typedef struct vi_held vi_held;
int vi_held_available(vi_sim *s);
int vi_held_start(vi_sim *s);
int vi_held_step(vi_sim *s, double t_end, int *event);
int vi_held_dense(vi_sim *s, double t);
int vi_held_sync(vi_sim *s);
int64_t vi_held_stat(const vi_sim *s, int which);
void vi_held_free(vi_sim *s);

#endif
