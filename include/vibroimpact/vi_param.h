/** @file vi_param.h
 * Parameters by key: read and change one number of a model, set up or
 * not, redoing only what that number touches (in the spirit of SUNDIALS'
 * cvode_cli.c, a table from key to setter).  Sweeps, continuation, basins
 * and identification (vi_study.h) change parameters through it; the scene
 * layer maps its keys onto these.
 *
 * Keys (indices 1-based in brackets, as the scene keys of vi_scene_edit.h):
 *
 *   forcing.omega          Omega                        touches no modes
 *   forcing.a[i]           a_i of a cos(Omega t)        M^-1 a, Psi^T a
 *   forcing.b[i]           b_i of b sin(Omega t)        M^-1 b, Psi^T b
 *   forcing.f0[i]          constant load f0_i           M^-1 f0, Psi^T f0
 *   stop.xs, stop.r        clearance and restitution of stop 0 (stop 1 in
 *                          1-based terms)               nothing derived
 *   stops[k].xs, stops[k].r   of stop k                 nothing derived
 *   damping.alpha, damping.beta   Rayleigh damping C = alpha M + beta K
 *                          (a model whose C was set as a matrix has
 *                          alpha = beta = NaN; setting one makes C
 *                          Rayleigh with the other 0)   M^-1 C, modal D
 *   damping.zeta[j], damping.zeta   modal damping ratio of mode j (all
 *                          modes): C = M Psi diag(2 zeta_j omega_j) Psi^T M,
 *                          set-up dense model with proportional damping
 *                          only                         M^-1 C, modal D
 *   mass.scale, stiffness.scale   M = s M_0, K = s K_0: the matrix as it
 *                          was given (M_0, K_0) times s (mass.scale > 0,
 *                          stiffness.scale >= 0; 1 until set).  The modes
 *                          change: the whole set-up is redone (M^-1 K, the
 *                          stops' M^-1 W and Delassus matrix, the modal
 *                          analysis, or the band set-up), on a copy that
 *                          replaces the model only if it succeeds.
 *                          Rayleigh damping follows (C = alpha M + beta K),
 *                          modal damping keeps its ratios on the new modes,
 *                          a matrix C stays as it is.   everything
 *   damping.scale          C = s C_0 (s >= 0) of a damping given as a
 *                          matrix (VI_ERR_UNSUPPORTED for Rayleigh or modal
 *                          damping: change their own keys)   M^-1 C, D
 *
 *   A scene builds a uniform chain from unit matrices and sets its m, k,
 *   c through these keys, so that `vibroimpact sweep --param model.chain.k`
 *   gets, at each value, the model the scene would build with it.  A
 *   matrix given again (vi_model_set_stiffness before setup) becomes the
 *   new base, with scale 1.
 *
 * The initial state is not the model's: the keys initial.t0, initial.x[i]
 * and initial.v[i] are handled by vi_param_set_initial on caller arrays
 * (a study holds its own initial state, vi_study.h).
 *
 * After vi_model_setup the model is otherwise frozen and may be shared by
 * threads; vi_model_set_param is the exception and must not run while any
 * other thread reads the model.  A model held by a handle made from it
 * (a simulation, orbit, census or identification: they keep data derived
 * from its values) is immutable: vi_model_set_param refuses with
 * VI_ERR_STATE until they are destroyed, also from their own callbacks
 * during a run.  A thread that changes parameters works on its own copy
 * (vi_model_copy; sweeps and continuations make theirs).
 */
#ifndef VI_PARAM_H
#define VI_PARAM_H

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_model.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Where a key belongs (vi_param_kind). */
typedef enum vi_param_kind_t {
  VI_PARAM_UNKNOWN = 0, /**< not a parameter key */
  VI_PARAM_MODEL = 1,   /**< a number of the model: vi_model_set_param */
  VI_PARAM_INITIAL_STATE = 2  /**< the initial state: vi_param_set_initial */
} vi_param_kind_t;

/** Set the parameter `key` of model m to `value`, before or after
 *  vi_model_setup; after it, only what the parameter touches is redone
 *  (see the table in the file comment).  The model is unchanged on an
 *  error, whose message (naming the key and the value) is in
 *  vi_model_errmsg.  @return VI_OK, VI_ERR_ARG (NULL, an unknown or
 *  malformed key: the message lists the keys), VI_ERR_DIM (an index out
 *  of range), VI_ERR_NONFINITE, VI_ERR_LIMIT (|value| > 1e100),
 *  VI_ERR_FREQUENCY (Omega <= 0 with harmonic forcing), VI_ERR_RESTITUTION, VI_ERR_NOT_PSD (negative
 *  damping), VI_ERR_STATE (damping.zeta before setup; the model held
 *  by a simulation, orbit, census or identification made from it),
 *  VI_ERR_UNSUPPORTED (damping.zeta of a band or non-proportional
 *  model, damping.scale of Rayleigh or modal damping), VI_ERR_NOT_SPD
 *  (mass.scale <= 0, or the set-up redone fails), VI_ERR_NOMEM. */
VI_API int vi_model_set_param(vi_model *m, const char *key, double value);
/** What vi_model_set_param(m, key, value) would return, with its message
 *  in vi_model_errmsg, without changing m: the key's checks, and for the
 *  keys that redo part of a set-up model (damping.*, mass.scale,
 *  stiffness.scale) the change itself on a copy, since only doing it can
 *  tell (C indefinite, M not SPD).  The others cost nothing: a study
 *  checks its range's ends with it before it starts.  Like
 *  vi_model_param, it writes only m's message.  @return as
 *  vi_model_set_param. */
VI_API int vi_model_check_param(const vi_model *m, const char *key,
                                double value);
/** The parameter `key` of model m into *value (also before setup; NaN
 *  for damping.alpha/beta of a matrix C).  @return VI_OK, VI_ERR_ARG,
 *  VI_ERR_DIM, VI_ERR_STATE, VI_ERR_UNSUPPORTED as vi_model_set_param
 *  (message in vi_model_errmsg when m is not NULL). */
VI_API int vi_model_param(const vi_model *m, const char *key, double *value);
/** A deep copy of model m (set up or not) in *out: the copy is set up if
 *  m is, shares nothing with it and can be changed by
 *  vi_model_set_param independently (one per thread of a study).
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_NOMEM. */
VI_API int vi_model_copy(const vi_model *m, vi_model **out);

/** The kind of `key` (a vi_param_kind_t): VI_PARAM_MODEL for the keys of
 *  the table, VI_PARAM_INITIAL_STATE for initial.t0, initial.x[i],
 *  initial.v[i]; VI_PARAM_UNKNOWN for anything else or NULL.  Indices are
 *  not range-checked here. */
VI_API int vi_param_kind(const char *key);
/** Set an initial-state key in caller arrays: initial.t0 into *t0,
 *  initial.x[i] into x[i-1], initial.v[i] into v[i-1] (x, v [n]).
 *  @return VI_OK, VI_ERR_ARG (NULL, not an initial-state key),
 *  VI_ERR_DIM (i outside 1..n), VI_ERR_NONFINITE. */
VI_API int vi_param_set_initial(const char *key, double value, int n,
                                double *t0, double *x, double *v);
/** Read an initial-state key from t0, x, v [n] into *value.
 *  @return as vi_param_set_initial. */
VI_API int vi_param_initial(const char *key, int n, double t0,
                            const double *x, const double *v, double *value);
/** Number of key patterns of the table (for help texts). */
VI_API int vi_param_key_count(void);
/** Key pattern i (0-based, below vi_param_key_count), e.g.
 *  "forcing.a[i]"; NULL out of range.  Static storage. */
VI_API const char *vi_param_key_name(int i);

#ifdef __cplusplus
}
#endif
#endif
