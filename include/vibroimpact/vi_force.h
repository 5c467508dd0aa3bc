/** @file vi_force.h
 * nonlinear forces beyond M, C, K: from the host code, or built in.
 *
 * The equations of motion become M x'' + C x' + K x = f(t) + g(t, x, x'),
 * where g is the sum of the built-in springs (vi_sim_add_spring) and the
 * host's callback (vi_sim_set_force).  CVODE integrates them (Adams, BDF
 * with the callback's Jacobian or finite differences of it, ERK); the exact
 * method has no closed form for them and refuses, so `auto` picks Adams.
 * The energy ledger books their work as a column of its own (NE). */
#ifndef VI_FORCE_H
#define VI_FORCE_H

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_sim.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Host force: fill g [n] with the force at time t on positions x [n] and
 *  velocities v [n] (physical coordinates).  Return 0 on success, non-zero
 *  to fail the run (VI_ERR_CALLBACK). */
typedef int (*vi_force_fn)(double t, int n, const double *x, const double *v,
                           double *g, void *user);
/** Optional Jacobian of the host force: dgdx, dgdv [n x n], column-major
 *  with leading dimension ld (entry (i, j) = dg_i / dx_j), zeroed before
 *  the call.  Return 0 on success. */
typedef int (*vi_force_jac_fn)(double t, int n, const double *x,
                               const double *v, double *dgdx, double *dgdv,
                               int ld, void *user);

/** Built-in springs (vi_sim_add_spring), between coordinate i and j
 *  (1-based; j = 0 is the ground), with d = x_i - x_j: */
enum {
  VI_SPRING_CUBIC = 0,    /**< force -k d^3 on i (+ on j): Duffing hardening
                               (k > 0) or softening (k < 0) */
  VI_SPRING_BILINEAR = 1  /**< force -k (d - gap) on i (+ on j) once d > gap:
                               a soft stop that engages past a gap */
};

/** Set (fn != NULL) or remove the host force; jac may be NULL (BDF then
 *  differences the force).  Takes effect at the next run.
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_UNSUPPORTED (the method is exact). */
VI_API int vi_sim_set_force(vi_sim *sim, vi_force_fn fn, vi_force_jac_fn jac,
                            void *user, vi_destroy_fn destroy);
/** Add a built-in spring (VI_SPRING_*) between coordinates i and j (1-based,
 *  j = 0 the ground, i != j) with stiffness k and, for a bilinear spring,
 *  the gap; gap is ignored for a cubic one.  @return VI_OK, VI_ERR_ARG,
 *  VI_ERR_DIM (i or j out of range), VI_ERR_NONFINITE,
 *  VI_ERR_UNSUPPORTED (the method is exact). */
VI_API int vi_sim_add_spring(vi_sim *sim, int type, int i, int j, double k,
                             double gap);
/** Remove every built-in spring.  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_sim_clear_springs(vi_sim *sim);
/** Cumulative work NE [n] of the nonlinear forces on each mode since the
 *  ledger was enabled.  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE (no ledger). */
VI_API int vi_sim_ledger_force(const vi_sim *sim, double *NE);

#ifdef __cplusplus
}
#endif
#endif
