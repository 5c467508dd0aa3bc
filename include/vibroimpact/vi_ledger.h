/** @file vi_ledger.h
 * the per-mode energy ledger (MODEL.md section 4; WB 7, 8).
 *
 * Modal energy E_j = 1/2 q_j'^2 + 1/2 omega_j^2 q_j^2.  Between impacts
 *   E_j(t_b) - E_j(t_a) = FE_j - DE_j - XE_j + CE_j + NE_j
 *   FE_j = int q_j' F_j dt                 forcing work into mode j
 *   DE_j = int D_jj q_j'^2 dt              damping loss of mode j
 *   XE_j = int q_j' sum_{k!=j} D_jk q_k'   damping coupling (0, and not
 *                                          computed, for proportional damping)
 *   CE_j = int lambda psi_j q_j' dt        work of the contact force while
 *                                          sticking (sums to 0 over modes)
 *   NE_j = int q_j' (Psi^T g)_j dt         work of the nonlinear forces g
 *                                          (vi_force.h; 0 without them)
 * and at an impact E_j jumps by dE_j = 1/2 (q_j'(t+)^2 - q_j'(t-)^2), the
 * jumps summing to -IE (WB 10).
 *
 * The ledger costs nothing unless enabled: vi_sim_enable_ledger adds the
 * quadratures to the integration (CVODES quadratures under the same error
 * control; for VI_METHOD_EXACT the free flights' integrals in closed form
 * where damping is proportional and every mode underdamped with damping
 * ratio <= 1/2, else Gauss-Legendre on the closed form). */
#ifndef VI_LEDGER_H
#define VI_LEDGER_H

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_sim.h"

#ifdef __cplusplus
extern "C" {
#endif

/** One impact-free interval [t_a, t_b] and the event that ends it; every
 * array is [n], valid only during the callback.  dE is NULL when the
 * interval ends without an impact (end of a vi_sim_run call, release). */
typedef struct vi_ledger_interval {
  int n;             /**< number of modes */
  double t_a;        /**< start of the interval */
  double t_b;        /**< end of the interval (the event's time) */
  const double *Ea;  /**< E_j at t_a */
  const double *Eb;  /**< E_j at t_b, before the jump */
  const double *Ka;  /**< kinetic part 1/2 q_j'^2 at t_a */
  const double *Kb;  /**< kinetic part at t_b, before the jump */
  const double *FE;  /**< forcing work into each mode over the interval */
  const double *DE;  /**< damping loss of each mode */
  const double *XE;  /**< damping-coupling work (0 for proportional damping) */
  const double *CE;  /**< contact-force work while sticking */
  const double *dE;                /**< impact jumps at t_b, or NULL */
  double ie;                       /**< energy lost at t_b (WB 10) */
  double residual;  /**< |sum_j (Eb - Ea - FE + DE + XE - CE - NE)| divided
                       by the energy scale: the largest total energy at any
                       interval end so far, or this interval's summed |work|
                       if larger */
  const double *NE; /**< work of the nonlinear forces (vi_force.h) on each
                       mode; 0 without them */
} vi_ledger_interval;

/** Ledger callback: return 0 to go on, non-zero to stop the run. */
typedef int (*vi_ledger_fn)(const vi_ledger_interval *iv, void *user);

/** Enable (on = 1) or disable the ledger; before the first vi_sim_run or
 * between runs (the cumulative totals restart from zero). */
VI_API int vi_sim_enable_ledger(vi_sim *sim, int on);
/** Called at the end of each interval: at every impact, stick, release, and
 * at the end of each vi_sim_run call. */
VI_API int vi_sim_set_ledger_callback(vi_sim *sim, vi_ledger_fn fn,
                                      void *user, vi_destroy_fn destroy);
/** Cumulative totals since the ledger was enabled, at the current time:
 * E [n] modal energies now; FE, DE, XE, CE, dE [n]; *ie the summed impact
 * losses.  Any pointer may be NULL.  A window's ledger is the difference of
 * two calls, E excepted. */
VI_API int vi_sim_ledger(const vi_sim *sim, double *E, double *FE,
                         double *DE, double *XE, double *CE, double *dE,
                         double *ie);
/** Largest closure residual of any interval so far (0 before any). */
VI_API double vi_sim_ledger_max_residual(const vi_sim *sim);

#ifdef __cplusplus
}
#endif
#endif
