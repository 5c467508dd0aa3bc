/* vi_rhs.h - the one right-hand side: the free acceleration of the
 * simulator (vi_sim_accel, its rates vi_sim_accel_rate) by the model's
 * storage, and the SUNDIALS backends' form of it, laid out for speed. */
#ifndef VI_RHS_H
#define VI_RHS_H

#include "vi_force_internal.h"
#include "vi_forcing.h"
#include "vi_sim_state.h"

/* Free acceleration M^-1 (f - C v - K x) at t for interleaved z, by the
 * model's storage; in a sticking phase the components along M^-1 w_k of
 * the sticking stops are removed so that w_k.x'' = 0. */
static inline void vi_sim_accel(vi_sim *s, double t, const double *z,
                                int sticking, double *acc)
{
  vi_phase p = vi_sim_phase(s, t);
  s->m->ops->accel(s->m, &p, z, acc);
  if (s->nforces) vi_force_add_accel(s, t, z, acc);
  if (sticking) vi_sim_constrain(s, acc, NULL);
}

/* out = M^-1 (f^(k)(t) - K u - C ud), k = 1, 2: the k-th time derivative
 * of the free acceleration along a motion whose k-th and (k+1)-th
 * derivatives of x are u and ud (vi_rhs.c). */
void vi_sim_accel_rate(const vi_sim *s, double t, int k, const double *u,
                       const double *ud, double *out);

/* Widest band packed (coefficients per row, 2 (2 bw + 1)): bw <= 15 */
#define VI_RHS_WIDTH_MAX 62

/* M^-1 K and M^-1 C packed by rows over their band, interleaved like the
 * state so that each acceleration is one short dot product with z, and a
 * small cache of the forcing's phase (a Runge-Kutta step asks for the same
 * stage times again: a 13-stage step revisits c = 1/6 and c = 1 twice, and
 * its c = 0 is the last step's c = 1, ten evaluations back). */
typedef struct vi_rhs {
  int n, width;     /* width: coefficients per row, 2 (2 bw + 1) or 2n */
  int *lo;          /* [n] first state index each row reads */
  double *R;        /* [n * width] -(M^-1 K), -(M^-1 C) interleaved; NULL:
                       band storage or a wide band, vi_sim_accel instead */
  const double *fa, *fb, *f0; /* M^-1 a, M^-1 b, M^-1 f0 [n] (model's) */
  double *acc;      /* [n] scratch: a backend may evaluate the right-hand
                       side while the driver holds s->vp (dense output) */
  int harmonic;
  vi_phase_cache phase;
} vi_rhs;

int vi_rhs_create(const vi_sim *s, vi_rhs **out);
void vi_rhs_destroy(vi_rhs **r);

/* The state's rate zd = (x', x'') of interleaved z at t: the free
 * acceleration M^-1 (f - C v - K x), plus the nonlinear forces, projected
 * onto the sticking constraints when sticking.  The one right-hand side of
 * the CVODE and ARKODE backends (other storage dispatches here). */
void vi_rhs_rate(vi_sim *s, vi_rhs *r, double t, const double *z, double *zd);

#endif
