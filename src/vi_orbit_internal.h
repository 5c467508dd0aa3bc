/* vi_orbit_internal.h - the variational flow of impacting orbits
 * (vi_orbit_var.c), shared by the orbit files; never installed. */
#ifndef VI_ORBIT_INTERNAL_H
#define VI_ORBIT_INTERNAL_H

#include "vi_flow_internal.h"

/* State-transition matrix e^{A tau} [2n x 2n] (z = (x, v), column-major,
 * leading dimension 2n) of the free motion: closed form per mode for
 * proportional damping, Pade scaling and squaring otherwise.  VI_OK,
 * VI_ERR_TIME (tau < 0), VI_ERR_NOMEM, VI_ERR_LAPACK. */
int vi_var_stm(const vi_model *m, double tau, double *Phi);
/* Vector field f = z' [2n] of the free motion at t (z, f stacked (x, v)). */
void vi_var_field(const vi_model *m, double t, const double *z, double *f);
/* Post-impact state zp [2n] of z on stop k (WB 2, stop k's own r_k); zp
 * may be z. */
void vi_var_impact(const vi_model *m, int k, const double *z, double *zp);
/* Saltation matrix S [2n x 2n] of an impact on stop k at t from the state
 * z [2n] just before it; work [8n]. */
void vi_var_saltation(const vi_model *m, int k, double t, const double *z,
                      double *S, double *work);
/* d/dOmega of the harmonic particular solution z_p = (x_p, v_p) at the
 * times t [nt] into dz [2n x nt].  VI_OK, VI_ERR_NOMEM, VI_ERR_UNSUPPORTED
 * (an undamped mode forced at resonance), VI_ERR_LAPACK. */
int vi_var_dpart_domega(const vi_model *m, int nt, const double *t, double *dz);

#endif
