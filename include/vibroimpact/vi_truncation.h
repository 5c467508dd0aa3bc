/** @file vi_truncation.h
 * The truncation study (MODEL.md sections 5 and 10): how many modes an
 * impacting structure needs, and what restitution a reduced model then
 * uses, one kept-mode count k at a time, the loop in the caller's hands
 * (as vi_cont.h).  `vibroimpact truncation` is a loop over it.
 *
 * For each k = lo..hi the study reports, in a row of VI_TRUNCATION_COLUMNS
 * numbers (the layout below, which vi_truncation_write_h5 stores):
 *   - omega_k, the mode added;
 *   - the fraction of the stop's compliance the first k modes carry:
 *     dynamic, sum_{j<=k} psi_j^2 / w^T M^-1 w (the Delassus number of
 *     Newton's law, WB 2, 10), and static, sum_{j<=k} psi_j^2 / omega_j^2
 *     / w^T K^-1 w;
 *   - the k-mode model's response with the reference's r: the orbit
 *     search's class, and v_N and impact phase of a P(1,1) orbit;
 *   - the r_S a k-mode model needs to carry the reference orbit's energy
 *     balance (WB 12-13, vi_orbit_reduced_restitution) and that model's
 *     response;
 *   - the first impacts from the initial state (vi_truncation_set_initial)
 *     against the reference's;
 *   - the same k modes plus one static (residual-flexibility) vector at the
 *     stop (vi_model_create_truncated): its compliance fraction, response
 *     and first impacts (k below the reference's modes only).
 *
 * The reference is the model every reduced one is measured by, in its own
 * modal coordinates (M = I): all the modes of a dense model
 * (vi_truncation_create), or the modes an FE reduction kept
 * (vi_truncation_create_fe).  The static vector of a k-mode model is built
 * from the reference's modes beyond k, so the reference must reach well
 * past hi for it to be the residual flexibility.
 *
 *   vi_truncation_create_fe(fe, &tr)      or vi_truncation_create(model, &tr)
 *   vi_truncation_set_modes(tr, 1, 4)
 *   vi_truncation_set_initial(tr, t0, t_end, x0, v0)
 *   while (!vi_truncation_done(tr)) {
 *     int st = vi_truncation_iterate(tr);  first the reference, then a row
 *     if (st != VI_OK) break;               VI_CANCELLED with a cancel fn
 *     vi_truncation_row(tr, k, row);        k = 0: the reference
 *   }
 *   vi_truncation_destroy(&tr)
 *
 * A row, 0-based columns ([3]: three columns, the first three impacts):
 *
 *   0 k, 1 omega, 2 dynamic_fraction, 3 static_fraction,
 *   4 class_n, 5 class_m, 6 vN, 7 phase   (the k-mode response with r:
 *        class_n -1 no orbit search ran, 0 not periodic with class_m
 *        impacts per period, else P(class_n, class_m); vN, phase (impact
 *        time mod T / T) of P(1,1))
 *   8 first_n (impacts found, -1 the run failed), 9 first_t [3],
 *   12 first_vn [3], 15 first_dt [3], 18 first_dvn_rel [3] (against the
 *        reference's, NaN where either has no such impact), 21 release
 *        (the first end of sticking),
 *   22 r_S, 23 r_S_class_n, 24 r_S_class_m, 25 r_S_vN, 26 r_S_phase,
 *   27 static_corrected (1: the variant exists, 0: no mode beyond k),
 *   28 sc_dynamic_fraction, 29 sc_class_n, 30 sc_class_m, 31 sc_vN,
 *   32 sc_phase, 33 sc_first_n, 34 sc_first_t [3], 37 sc_first_vn [3],
 *   40 sc_first_dt [3], 43 sc_first_dvn_rel [3], 46 sc_release.
 *
 * Missing values are NaN.  The reference's row has the same layout: its k
 * is its number of modes, its response and first impacts (no dt), NaN
 * elsewhere.  A study is one thread's; it works on its own reference
 * model.
 */
#ifndef VI_TRUNCATION_H
#define VI_TRUNCATION_H

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_model.h"
#include "vibroimpact/vi_sim.h"
#include "vibroimpact/vi_sparse.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Sizes of a study's row and information (vi_truncation_row,
 *  vi_truncation_summary, vi_truncation_write_h5). */
enum vi_truncation_size {
  VI_TRUNCATION_COLUMNS = 47, /**< numbers in a row (the layout above) */
  VI_TRUNCATION_INFO = 8      /**< dofs, modes_lo, modes_hi,
                                   reference_modes, restitution,
                                   compliance_dynamic, compliance_static,
                                   complete (1, 0 while rows remain) */
};

/** Opaque truncation-study handle. */
typedef struct vi_truncation vi_truncation;

/** A study of the set-up model m (not band storage: it needs the modes),
 *  whose reference is m with all its modes, in m's modal coordinates
 *  (vi_model_create_reduced with every mode, restitution m's); the
 *  compliances are m's w^T M^-1 w and the sum over its modes of
 *  psi_j^2 / omega_j^2 (= w^T K^-1 w).  m is borrowed: it must outlive
 *  the study.  Modes 1..n by default, no initial state.
 *  @return VI_OK, VI_ERR_ARG (NULL), VI_ERR_STATE (m not set up),
 *  VI_ERR_UNSUPPORTED (no modes: band storage, or several stops),
 *  VI_ERR_NOMEM, or the reduction's error. */
VI_API int vi_truncation_create(const vi_model *m, vi_truncation **out);
/** A study of a set-up FE reduction (vi_sparse.h): the reference is its
 *  kept modes (vi_fe_create_model), the compliances the full model's
 *  (vi_fe_stop_compliance, stop 0).  fe is borrowed: it must outlive the
 *  study; keep its shapes (vi_fe_set_keep_shapes) for an initial state.
 *  @return VI_OK, VI_ERR_ARG (NULL), VI_ERR_STATE (fe not set up),
 *  VI_ERR_NOMEM, or vi_fe_create_model's error (message in
 *  vi_fe_errmsg). */
VI_API int vi_truncation_create_fe(const vi_fe *fe, vi_truncation **out);
/** Destroy and set *tr to NULL; NULL-safe. */
VI_API void vi_truncation_destroy(vi_truncation **tr);
/** Detail of the last error ("" if none), owned by the study. */
VI_API const char *vi_truncation_errmsg(const vi_truncation *tr);

/** The kept-mode counts studied, 1 <= lo <= hi <= the reference's modes;
 *  before the first vi_truncation_iterate.  @return VI_OK, VI_ERR_ARG,
 *  VI_ERR_STATE (the study has begun). */
VI_API int vi_truncation_set_modes(vi_truncation *tr, int lo, int hi);
/** The first-impact runs: from x, v [dofs] (the full model's coordinates,
 *  projected onto the reference's modes; NULL = 0) at t0 to t_end > t0.
 *  Without it no first impacts are sought (first_n 0).  Before the first
 *  vi_truncation_iterate.  @return VI_OK, VI_ERR_ARG, VI_ERR_NONFINITE,
 *  VI_ERR_TIME (t_end <= t0), VI_ERR_STATE (the study has begun, or an FE
 *  reduction without its shapes). */
VI_API int vi_truncation_set_initial(vi_truncation *tr, double t0,
                                     double t_end, const double *x,
                                     const double *v);
/** Monitor of the reference's orbit search (the study's long part),
 *  called once per forcing period as vi_orbit_set_monitor (fn NULL:
 *  none); non-zero makes vi_truncation_iterate return VI_STOPPED.  user
 *  is handed over as vi_sim_set_event_callback does.
 *  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_truncation_set_monitor(vi_truncation *tr, vi_monitor_fn fn,
                                     void *user, vi_destroy_fn destroy);
/** Cancellation (fn NULL: none): polled at the start of each
 *  vi_truncation_iterate and at every step of the orbit searches'
 *  simulations (vi_orbit_set_cancel) and of the first-impact runs
 *  (vi_sim_set_cancel, also in a held phase).  A cancelled step returns VI_CANCELLED and leaves the
 *  study where it was (iterating again redoes that step).  user is
 *  handed over as vi_truncation_set_monitor does.
 *  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_truncation_set_cancel(vi_truncation *tr, vi_cancel_fn fn,
                                    void *user, vi_destroy_fn destroy);

/** One step: the first analyses the reference (its orbit search, where
 *  the model is harmonically forced, and its first impacts), each later
 *  one the next row k.  A failed orbit search or run is a result of the
 *  row (class_n -1, first_n -1), not an error.  @return VI_OK,
 *  VI_STOPPED (the monitor asked), VI_CANCELLED, VI_ERR_ARG,
 *  VI_ERR_STATE (done), VI_ERR_NOMEM, or the compliances' error. */
VI_API int vi_truncation_iterate(vi_truncation *tr);
/** 1 when every row lo..hi is done, else 0 (also for NULL). */
VI_API int vi_truncation_done(const vi_truncation *tr);
/** The row of k (lo <= k <= hi, done) or, k = 0, the reference's into
 *  row [VI_TRUNCATION_COLUMNS].  @return VI_OK, VI_ERR_ARG, VI_ERR_STATE
 *  (not computed yet). */
VI_API int vi_truncation_row(const vi_truncation *tr, int k, double *row);
/** The rows done so far: *nrows receives their number; with rows
 *  non-NULL they fill rows [ldrows x VI_TRUNCATION_COLUMNS], column-major
 *  (row i: k = lo + i), ldrows >= max(1, *nrows).  @return VI_OK,
 *  VI_ERR_ARG. */
VI_API int vi_truncation_table(const vi_truncation *tr, double *rows,
                               int ldrows, int *nrows);
/** The study's summary into info [VI_TRUNCATION_INFO] (the enum's
 *  order; a function named vi_truncation_info would clash with the
 *  constant in Fortran).  @return VI_OK, VI_ERR_ARG. */
VI_API int vi_truncation_summary(const vi_truncation *tr, double *info);
/** The reference model (a view owned by the study; in the reference's
 *  modal coordinates); NULL for NULL. */
VI_API const vi_model *vi_truncation_model(const vi_truncation *tr);

#ifdef __cplusplus
}
#endif
#endif
