/* vi_band_internal.h - the integrator's Jacobian of a band-storage model
 * (vi_band.c); the model side is declared in vi_model_internal.h. */
#ifndef VI_BAND_INTERNAL_H
#define VI_BAND_INTERNAL_H

#include <sundials/sundials_matrix.h>

#include "vi_sim_state.h"

/* The Jacobian of the interleaved first-order system into J (band or
 * dense), projected while sticking like the right-hand side; 0 on success. */
int vi_band_jac(vi_sim *s, SUNMatrix J);

#endif
