/* vi_storage.h - how a model stores M, C, K: a const table of operations
 * chosen once when the model is created (vi_model_create: dense,
 * vi_model_create_band: band), in the spirit of SUNDIALS' N_Vector_Ops, so
 * that the layers above call m->ops->... and never ask which storage it is.
 * An operation a storage cannot do is NULL; a capability is a flag. */
#ifndef VI_STORAGE_H
#define VI_STORAGE_H

#include <stddef.h>

#include "vi_forcing.h"
#include "vi_model_internal.h"

struct vi_storage_ops {
  const char *name; /* "dense" or "band" */
  /* the modes exist after setup (Psi, PsiTM, lambda, D, Fa, Fb, F0, psi,
   * PsiW): the ledger, the closed-form flow, forces, orbits and the
   * reduced models need them; band models have none */
  int modal;
  /* n-vectors per stop that setup derives: M^-1 w_k, and Psi^T w_k with
   * the modes (vi_model_memory, vi_model_copy) */
  int stop_vectors;
  /* the largest n for which the integrator may assemble a dense Jacobian
   * column by column from apply() when no dense M^-1 K exists */
  int dense_jac_max;
  /* freeze: factor M, M^-1 of the forcing and the stops, then the modes
   * (dense) or the row form KR, CR (band) */
  int (*setup)(vi_model *m);
  /* acc [n] = M^-1 (f(t) - K x - C v) of an interleaved z = (x_1, v_1, ..)
   * with the forcing's phase p of t */
  void (*accel)(const vi_model *m, const vi_phase *p, const double *z,
                double *acc);
  /* out [n] = M^-1 (f^(k)(t) - K u - C ud), k = 1, 2 */
  void (*accel_rate)(const vi_model *m, const vi_phase *p, int k,
                     const double *u, const double *ud, double *out);
  /* y [n] = M^-1 (K x + C v), x and v with strides incx, incv */
  void (*apply)(const vi_model *m, const double *x, int incx,
                const double *v, int incv, double *y);
  /* 1/2 v^T M v + 1/2 x^T K x */
  double (*energy)(const vi_model *m, const double *x, const double *v);
  /* x [n x nrhs] <- M^-1 x (0 or a LAPACK info) */
  int (*solve_mass)(const vi_model *m, int nrhs, double *x);
  /* the storage of M (which 0), C (1) or K (2) as set, *len doubles */
  double *(*matrix)(const vi_model *m, int which, size_t *len);
  /* an upper bound of the highest natural frequency (set-up model) */
  double (*omega_bound)(const vi_model *m);
  /* column j of M^-1 K (which 0) or M^-1 C (which 1), dense [n]; NULL: the
   * storage holds no dense M^-1 K (the integrator's band Jacobian,
   * src/sim/vi_band.c, then builds from apply()) */
  const double *(*minv_col)(const vi_model *m, int which, int j);
  /* -(M^-1 K), -(M^-1 C) packed by rows over the band and interleaved like
   * the state: row i's `width` coefficients at R [i width] multiply z
   * [lo[i] ...]; NULL: not available (vi_rhs.c then calls accel) */
  void (*pack_rows)(const vi_model *m, int width, int *lo, double *R);
};

/* The modal capability, asked here and nowhere else (as SUNDIALS asks for
 * a missing operation only in its generic wrapper): 1 if the model's
 * storage keeps modes after setup (dense), 0 if not (band).  A caller that
 * can go on without them branches on this; one that cannot refuses
 * through vi_model_need_modes. */
static inline int vi_model_has_modes(const vi_model *m)
{
  return m->ops->modal;
}
/* VI_OK if the model has modes, else VI_ERR_UNSUPPORTED with the message
 * "<what> the modes, which a band-storage model does not have" in buf
 * (what: e.g. "forces need"; buf NULL: the code alone) (vi_model.c). */
int vi_model_need_modes(const vi_model *m, char *buf, const char *what);

extern const vi_storage_ops vi_storage_dense; /* vi_dense_model.c */
extern const vi_storage_ops vi_storage_band;  /* vi_band_model.c */

/* The dense setup (vi_model.c): Cholesky of M, M^-1 K, M^-1 C, the
 * forcing and the stops, the bandwidth, the modes. */
int vi_dense_setup(vi_model *m);

#endif
