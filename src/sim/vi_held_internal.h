/* vi_held_internal.h - held phases of the exact method (vi_held.c). */
#ifndef VI_HELD_INTERNAL_H
#define VI_HELD_INTERNAL_H

#include "vi_flow_internal.h"
#include "vi_sim_state.h"

/* Held phases of the exact method in closed form (src/sim/vi_held.c): the
 * simulation's cache of constrained modes and the flow of the current
 * phase live in s->held.  vi_held_available: the closed form can hold the
 * current sticking set (builds and caches its modes; 0 on failure, and
 * the sticking phase then runs on CVODE).  The others are the exact
 * backend's entries while s->sticking. */
typedef struct vi_held vi_held;
int vi_held_available(vi_sim *s);
int vi_held_start(vi_sim *s);
int vi_held_step(vi_sim *s, double t_end, int *event);
int vi_held_dense(vi_sim *s, double t);
int vi_held_sync(vi_sim *s);
int64_t vi_held_stat(const vi_sim *s, int which);
void vi_held_free(vi_sim *s);

/* A cache of constrained modes that a study shares across the simulations
 * of its points, one at a time (not for concurrent simulations).  Its modes
 * stay valid while the model's M, K, C, stops, x_s and forcing vectors do
 * and Omega stays non-zero: a new Omega retunes them (vi_cmodes_retune),
 * r does not enter them; any other change needs vi_held_cache_clear.
 * vi_held_share_cache(s, NULL): the sim's own again. */
typedef struct vi_held_cache vi_held_cache;
vi_held_cache *vi_held_cache_create(void);
void vi_held_cache_clear(vi_held_cache *hc);
void vi_held_cache_destroy(vi_held_cache **hc);
int vi_held_share_cache(vi_sim *s, vi_held_cache *hc);

#endif
