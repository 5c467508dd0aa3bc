/** @file vi_orbit.h
 * periodic impacting orbits and the coefficient-of-restitution
 * analysis of the paper (MODEL.md section 5; WB 11-13).
 *
 * vi_orbit_find runs past the transient, classifies the motion as P(n, m)
 * (period n forcing periods, m impacts in it) or not periodic, and for a
 * P(1,1) orbit refines it by Newton shooting on the stroboscopic map (GSL
 * hybrids), computes its Floquet multipliers and the energy balance over one
 * period:
 *   IE = 1/2 v_N^2 (1 - r^2) / psi.psi = sum_j (FE_j - DE_j - XE_j) = RE (WB 11)
 *   r  = sqrt(1 - RE / KE_i),  KE_i = 1/2 v_N^2 / psi.psi            (WB 12, 13)
 * and the restitution r_S a reduced model keeping only the modes in S needs
 * to reproduce the orbit. */
#ifndef VI_ORBIT_H
#define VI_ORBIT_H

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_model.h"
#include "vibroimpact/vi_sim.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Opaque periodic-orbit analysis handle. */
typedef struct vi_orbit vi_orbit;

/** Create an orbit analysis of a set-up model with harmonic forcing (the
 *  model is borrowed and must outlive the orbit).  @return VI_OK, VI_ERR_ARG,
 *  VI_ERR_STATE (model not set up), VI_ERR_FREQUENCY (Omega = 0),
 *  VI_ERR_UNSUPPORTED (a model with several stops: the balance of WB 11-13
 *  is that of one stop), VI_ERR_NOMEM. */
VI_API int vi_orbit_create(const vi_model *model, vi_orbit **out);
/** Destroy and set *orbit to NULL; NULL-safe. */
VI_API void vi_orbit_destroy(vi_orbit **orbit);
/** Detail of the last error ("" if none), owned by the orbit. */
VI_API const char *vi_orbit_errmsg(const vi_orbit *orbit);

/** Integration method (VI_METHOD_*): default VI_METHOD_EXACT when the model
 *  allows it, else VI_METHOD_ADAMS.  @return VI_OK, VI_ERR_ARG,
 *  VI_ERR_UNSUPPORTED. */
VI_API int vi_orbit_set_method(vi_orbit *o, int method);
/** Tolerances of the integrations, as vi_sim_set_tolerances (defaults
 *  1e-11, 1e-13).  @return VI_OK, VI_ERR_TOLERANCE. */
VI_API int vi_orbit_set_tolerances(vi_orbit *o, double rtol, double atol);
/** Start of the transient run (default rest at t = 0); x0, v0 [n] or NULL. */
VI_API int vi_orbit_set_initial(vi_orbit *o, const double *x0,
                                const double *v0);
/** At most max_periods forcing periods of transient (default 3000); the
 * motion counts as periodic when impact states repeat to tol (relative,
 * default 1e-6) over 3 consecutive orbit periods. */
VI_API int vi_orbit_set_transient(vi_orbit *o, double max_periods, double tol);
/** Monitor of the transient run, called once per forcing period (see
 *  vi_sim_set_monitor); a non-zero return stops vi_orbit_find with
 *  VI_STOPPED.  fn NULL removes it.  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_orbit_set_monitor(vi_orbit *o, vi_monitor_fn fn, void *user);

/** Run, classify, and for P(1,1) refine and analyse.  VI_OK whatever the
 * motion turns out to be: ask vi_orbit_classify.  VI_STOPPED if the monitor
 * asked to stop; a negative code means the computation itself failed. */
VI_API int vi_orbit_find(vi_orbit *o);
/** *n periods of forcing, *m impacts per orbit period; n = 0 when no period
 * up to 8 was found within the transient (m is then the mean number of
 * impacts per forcing period over the last 8 periods, rounded). */
VI_API int vi_orbit_classify(const vi_orbit *o, int *n, int *m);

/* ---- P(1,1) results: VI_ERR_STATE unless the orbit is P(1,1) ---------- */
/** period = 2 pi / Omega; phase = impact time modulo the period (time
 * units); vN = approach velocity w.x'(t-); KE_i, RE, IE as in WB 11-13;
 * r_rec from WB 12; closure = |RE - IE| / KE_i.  Any pointer may be NULL. */
VI_API int vi_orbit_balance(const vi_orbit *o, double *period, double *phase,
                            double *vN, double *KE_i, double *RE, double *IE,
                            double *r_rec, double *closure);
/** Per mode [n] over one period: FE, DE, XE and the effective restitution
 * r_eff_j = -q_j'(t+) / q_j'(t-).  Any pointer may be NULL. */
VI_API int vi_orbit_modal_balance(const vi_orbit *o, double *FE, double *DE,
                                  double *XE, double *r_eff);
/** The state just before the impact: t, x [n], v [n] (any may be NULL). */
VI_API int vi_orbit_impact_state(const vi_orbit *o, double *t, double *x,
                                 double *v);
/** Floquet multipliers of the stroboscopic map, re and im [2n]. */
VI_API int vi_orbit_multipliers(const vi_orbit *o, double *re, double *im);
/** Smallest value of the gap w.x - x_s over the period (the deepest
 * excursion from the stop, <= 0). */
VI_API int vi_orbit_min_gap(const vi_orbit *o, double *gmin);
/** Equivalent restitution of a reduced model keeping the modes modes[0..k)
 * (0-based, ascending omega): r_S = sqrt(1 - RE_S / KE_S) with
 * KE_S = 1/2 (psi_S.q_S'(t-))^2 / psi_S.psi_S and RE_S the modes' residual
 * energy.  VI_ERR_ARG (and *r_S = NaN) if a mode index is outside 0..n-1
 * or RE_S is outside [0, KE_S] (no real r_S). */
VI_API int vi_orbit_reduced_restitution(const vi_orbit *o, const int *modes,
                                        int k, double *r_S);

/** The reduced model itself, in the modal coordinates of `full`: M = I,
 * K = diag(omega_S^2), C = D_SS, forcing Psi_S^T (a, b, f0), stop psi_S
 * with the same x_s and restitution r.  A new, set-up model. */
VI_API int vi_model_create_reduced(const vi_model *full, const int *modes,
                                   int k, double r, vi_model **out);

/** The paper's beam: a clamped-free Euler-Bernoulli cantilever.
 * Mode j (0-based) of a unit-length, unit-mass-per-length cantilever: beta_j
 * solves cos(beta) cosh(beta) = -1 and the mass-normalised shape is
 *   phi_j(xi) = cosh(b xi) - cos(b xi) - s_j (sinh(b xi) - sin(b xi)).
 * vi_cantilever_shape evaluates phi_j(xi), xi in [0, 1], stably for large
 * beta.  vi_cantilever_beta returns beta_j (j = 0: 1.8751041), NaN for j
 * outside 0..200. */
VI_API double vi_cantilever_beta(int j);
/** phi_j(xi) of the cantilever, xi in [0, 1] (0 the clamp, 1 the tip);
 *  |phi_j(1)| = 2; NaN for j outside 0..200. */
VI_API double vi_cantilever_shape(int j, double xi);
/** Integral of phi_j over the span (the participation of a uniform base
 * acceleration): 2 s_j / beta_j. */
VI_API double vi_cantilever_participation(int j);
/** Galerkin model with `modes` modes in modal coordinates: M = I,
 * K = diag(omega_j^2) with omega_j = omega1 (beta_j / beta_1)^2,
 * C = diag(2 zeta omega_j); w_j = phi_j(xi_stop) (the stop acts at
 * xi_stop, 1 = the free end); gamma_j = participation.  A base acceleration
 * A cos(Omega t) is the forcing a = -A gamma.  M, C, K [ld x modes]. */
VI_API int vi_build_cantilever(int modes, double omega1, double zeta,
                               double xi_stop, double *M, double *C,
                               double *K, int ld, double *w, double *gamma);

#ifdef __cplusplus
}
#endif
#endif
