/* vi_grid.h - the uniform-grid scanner of the closed-form flows (the exact
 * method's free flight, vi_exact.c, and its held phases, vi_held.c): the
 * bookkeeping of a grid t_k = t0 + k h along which the active modes and
 * the functions they make (gaps, reactions) advance, anchored on the
 * direct formula every few steps, searched interval by interval for the
 * first crossing of zero.  What is followed, and how, comes in by a table
 * of operations on the caller's data. */
#ifndef VI_GRID_H
#define VI_GRID_H

#include <stdint.h>

#include "vi_sim_state.h"

typedef struct vi_grid {
  double t0, h;                 /* t_k = t0 + k h */
  int64_t k;
  double cr, sr;                /* the forcing phase's rotation by Om h */
  double ck, sk, cn, sn;        /* cos, sin of Om t at t_k, t_{k+1} */
  double *wk, *wdk, *wn, *wdn;  /* the active modes there [na] */
  double *fk, *fdk, *fn, *fdn;  /* the followed functions there [nf] */
  int next_ok, srch, since, anch; /* t_{k+1} made, its interval searched,
                                     steps since the last anchor, and
                                     whether t_{k+1} is one */
  int found;                    /* the function crossing first, or -1 */
  double tstar;                 /* where */
  int64_t steps;
} vi_grid;

typedef struct vi_grid_ops {
  int anchor_every, batch; /* steps between anchors; steps per call */
  /* t_{k+1} = t directly: wn, wdn, cn, sn, fn, fdn */
  void (*anchor)(void *d, double t);
  /* t_{k+1} from t_k by the grid step's maps (cn, sn already rotated) */
  int (*advance)(void *d);
  /* the first crossing in (tk, tb] over all functions: *tc, *which (-1:
   * none); a negative return is an error status */
  int (*search)(void *d, double tk, double tb, double *tc, int *which);
  /* the crossing of function `which` at tc <= t_end is the step's end:
   * the state there and the event (VI_STEP_*) */
  int (*crossing)(vi_sim *s, void *d, double tc, int which, int *event);
  /* the run ends at t inside an interval: the gap reported there */
  double (*gap_at)(vi_sim *s, void *d, double t);
  /* the gap reported from the functions f at a grid point */
  double (*report)(vi_sim *s, void *d, const double *f);
  /* move to t (no crossing before it): time, gap g, ledger; VI_CANCELLED
   * on the host's poll inside the ledger's quadrature */
  int (*move)(vi_sim *s, void *d, double t, double g);
  /* after an anchor is committed: new derivative bounds from (wk, wdk) */
  void (*bounds)(void *d);
} vi_grid_ops;

/* Start the grid at t0 with step h (phase rotation by W h). */
void vi_grid_start(vi_grid *g, double t0, double h, double W);

/* Scan on to t_end or the first crossing (*event VI_STEP_NONE or what
 * ops->crossing made it), at most ops->batch grid steps; VI_CANCELLED on
 * the host's poll. */
int vi_grid_step(vi_sim *s, vi_grid *g, const vi_grid_ops *ops, void *d,
                 double t_end, int *event);

/* Maximum on [0, 1] of the cubic Hermite through (fa, w fda) at 0 and
 * (fb, w fdb) at 1; c[4] (may be NULL) receives its coefficients in
 * s = (t - a) / w. */
double vi_herm_max(double fa, double fda, double fb, double fdb, double w,
                   double *c);

#endif
