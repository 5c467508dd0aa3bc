/* vi_orbit_internal.h - the orbit analysis handle and the variational
 * flow of impacting orbits, shared by the orbit files (vi_orbit.c: the
 * search, shooting and multipliers; vi_classify.c: the P(n, m)
 * classification of a transient; vi_balance.c: WB 11-13; vi_orbit_var.c:
 * exact derivatives); never installed. */
#ifndef VI_ORBIT_INTERNAL_H
#define VI_ORBIT_INTERNAL_H

#include <math.h>

#include "vi_flow_internal.h"
#include "vi_orbit_handle.h"

/* State-transition matrix e^{A tau} [2n x 2n] (z = (x, v), column-major,
 * leading dimension 2n) of the free motion: closed form per mode for
 * proportional damping, Pade scaling and squaring otherwise.  VI_OK,
 * VI_ERR_TIME (tau < 0), VI_ERR_NOMEM, VI_ERR_LAPACK. */
int vi_var_stm(const vi_model *m, double tau, double *Phi);
/* u [2n] <- e^{A tau} u without forming e^{A tau}: O(n^2) through the
 * modes of a proportional model; work [2n].  VI_ERR_UNSUPPORTED for any
 * other damping (then vi_var_stm), VI_ERR_TIME (tau < 0). */
int vi_var_stm_apply(const vi_model *m, double tau, double *u, double *work);
/* Vector field f = z' [2n] of the free motion at t (z, f stacked (x, v)). */
void vi_var_field(const vi_model *m, double t, const double *z, double *f);
/* Post-impact state zp [2n] of z on stop k (WB 2, stop k's own r_k); zp
 * may be z. */
void vi_var_impact(const vi_model *m, int k, const double *z, double *zp);
/* Saltation matrix S [2n x 2n] of an impact on stop k at t from the state
 * z [2n] just before it; work [8n].  vi_var_salt_jump: its pieces for
 * vi_impact_salt_apply, the jump d [2n] and the return value v_n; work [4n]. */
double vi_var_salt_jump(const vi_model *m, int k, double t, const double *z,
                        double *d, double *work);
void vi_var_saltation(const vi_model *m, int k, double t, const double *z,
                      double *S, double *work);
/* vi_orbit_pnm_monodromy keeping its factors: Phis and Ss (each NULL or
 * mi blocks of 2n x 2n) receive impact j's flow to the next impact and its
 * saltation matrix, Mo = Phi_{mi-1} S_{mi-1} ... Phi_0 S_0. */
int vi_orbit_pnm_monodromy_parts(const vi_model *m, int np, int mi, const int *stop,
                                 const double *t, const double *x, const double *v,
                                 int ld, double *Mo, double *Phis, double *Ss);
/* D z(tb) / D z(ta) [2n x 2n] of the motion from ta to tb through mi
 * impacts at t [mi] on stop [mi], pre-impact states z [2n x mi] (stacked
 * x, v per impact): the exact derivative of a shooting map. */
int vi_var_map_jacobian(const vi_model *m, double ta, double tb, int mi,
                        const int *stop, const double *t, const double *z,
                        double *J);
/* d/dOmega of the harmonic particular solution z_p = (x_p, v_p) at the
 * times t [nt] into dz [2n x nt].  VI_OK, VI_ERR_NOMEM, VI_ERR_UNSUPPORTED
 * (an undamped mode forced at resonance), VI_ERR_LAPACK. */
int vi_var_dpart_domega(const vi_model *m, int nt, const double *t, double *dz);

/* the handle itself: vi_orbit_handle.h */

/* Classification of the transient (vi_classify.c): the event callback that
 * records impacts into the ring; the ring index of the first impact at or
 * after t; the stroboscopic state kept for the end of forcing period k;
 * whether the motion repeats with period n forcing periods at the end of
 * period kp (then *m impacts per orbit period). */
int vi_classify_record(const vi_event *ev, void *user);
int64_t vi_classify_first_after(const vi_orbit *o, double t);
double *vi_classify_strobe(const vi_orbit *o, int64_t k);
int vi_classify_repeats(const vi_orbit *o, int64_t kp, int n, int *m);

/* P(n, m) of a recorded motion: R + 1 stroboscopic states z [n2 each],
 * impacts t [nimp], the stops' scale xscale; returns n (0: none <= nmax),
 * *m (vi_classify.c). */
int vi_classify_strobes(int R, int n2, const double *z, double xscale, double tol,
                        int nmax, const double *t, int64_t nimp, double T,
                        double t_end, int *m);

/* Seeds of a census from the phase scan only, no transients (the sweep's
 * P(1,1) orbits at each point): vi_census_run then returns
 * VI_ERR_UNSUPPORTED unless m = 1 and the model has one stop. */
struct vi_census;
void vi_census_scan_only(struct vi_census *c);

/* The VI_ORBIT_PARAM_* that vi_orbit_pnm_dparam differentiates exactly for
 * a parameter key (forcing.omega, stop.xs, stop.r, stops[K].xs,
 * stops[K].r), *pk the 0-based stop (stop.* is stop 0, stops[K].* the
 * 1-based K); -1 for any other key (the continuations then difference). */
int vi_orbit_param_of_key(const char *key, int *pk);

#endif
