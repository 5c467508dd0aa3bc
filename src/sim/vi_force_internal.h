/* vi_force_internal.h - nonlinear forces g(t, x, v): the host's callback
 * and the built-in springs (vi_force.c). */
#ifndef VI_FORCE_INTERNAL_H
#define VI_FORCE_INTERNAL_H

#include "vi_sim_state.h"

/* Nonlinear forces (vi_force.c).  acc += M^-1 g(t, x, v) for an
 * interleaved state z; with gq != NULL the modal force Psi^T g too. */
void vi_force_add_accel(vi_sim *s, double t, const double *z, double *acc);
/* The message and status of a failed force evaluation (s->force_failed). */
int vi_force_failure(vi_sim *s);
/* The modal force Psi^T g [n] at (t, z) into gq: for the ledger. */
void vi_force_modal(vi_sim *s, double t, const double *z, double *gq);
/* d(M^-1 g)/dx and d(M^-1 g)/dv [n x n], column-major, at (t, z). */
int vi_force_jacobian(vi_sim *s, double t, const double *z, double **Ax,
                      double **Av); /* into the sim's workspace */
void vi_force_free(vi_sim *s);

#endif
