/* vi_band_internal.h - the band-storage model's hooks into the integrator
 * (vi_band.c): each dense code path that reads M^-1 K or M^-1 C dispatches
 * here when m->band is set. */
#ifndef VI_BAND_INTERNAL_H
#define VI_BAND_INTERNAL_H

#include <sundials/sundials_matrix.h>

#include "vi_internal.h"

/* The Jacobian of the interleaved first-order system into J (band or
 * dense), projected while sticking like the right-hand side; 0 on success. */
int vi_band_jac(vi_sim *s, SUNMatrix J);
/* out = M^-1 (f^(k)(t) - K u - C ud), k = 1, 2 (vi_sim.c's accel_rate). */
void vi_band_accel_rate(const vi_model *m, double t, int k, const double *u,
                        const double *ud, double *out);
/* kappa = w_k^T M^-1 K M^-1 w_k / G_kk, gamma likewise with C (vi_sim.c's
 * normal_stiffness); NaN if out of memory. */
void vi_band_normal_stiffness(const vi_model *m, int k, double *kappa,
                              double *gamma);

#endif
