/* vi_chatter_internal.h - the chatter map (vi_chatter.c). */
#ifndef VI_CHATTER_INTERNAL_H
#define VI_CHATTER_INTERNAL_H

#include "vi_sim_state.h"

/* The chatter map (vi_chatter.c), for stop k while the other stops of the
 * sticking set hold.  push: stop k's gap acceleration p [3] (the push of
 * its contact force) and its first two rates along the motion sticking on
 * stop k and the held ones from x, v at t.  normal: the structure's
 * stiffness kappa and damping gamma seen through stop k with the held
 * stops on theirs.  tail: the duration of the chattering sequence that
 * starts at rebound speed u (restitution r) under g'' + gamma g' + kappa g
 * = p0 + p1 t + p2 t^2 / 2, its bounces counted in *count; -1 if by the
 * model it does not accumulate. */
void vi_chatter_push(vi_sim *s, int k, double t, const double *x,
                     const double *v, double *p);
void vi_chatter_normal(vi_sim *s, int k, double *kappa, double *gamma);
double vi_chatter_tail(double u, double r, double p0, double p1, double p2,
                       double kappa, double gamma, int64_t *count);
/* The chatter threshold in force: the one set (vi_sim_set_chatter_threshold),
 * else 1e-7 of the run's velocity scale (a default in any units). */
double vi_chatter_threshold(const vi_sim *s);
/* Whether stop k's bounces end at this impact (see vi_chatter.c); *floor_hit
 * says a floor of vi_sim_set_floors decided it. */
int vi_chatter_wanted(vi_sim *s, int k, double vn, double push,
                      double dt_prev, const double *x, const double *v,
                      int *floor_hit);
/* Stop k's tail from rebound speed u at s->t, with the other held stops
 * on theirs: its duration (0: it holds at once), bounces in *count. */
double vi_chatter_sum(vi_sim *s, int k, double u, const double *x,
                      const double *v, int64_t *count);
/* Pending STICK events: record stop k's (due at `at`), the stop whose
 * event is due first by t (-1: none), and forget stop k's (-1: all). */
void vi_chatter_pend(vi_sim *s, int k, double at, double vn, double ie);
int vi_chatter_due(const vi_sim *s, double t);
void vi_chatter_unpend(vi_sim *s, int k);

#endif
