/** @file vi_scene_param.h
 * Scene keys as parameters (vi_param.h): part of the companion library
 * vibroimpact_scene.  A study changes a parameter on its model (no scene text
 * is rewritten, no model rebuilt); this maps the scene's own key onto the
 * parameter key.
 *
 *   scene key                          parameter key
 *   forcing.omega, forcing.a[i], forcing.b[i], forcing.f0[i]   the same
 *   stop.xs, stop.r, stops[k].xs, stops[k].r                   the same
 *   model.rayleigh.alpha, model.rayleigh.beta   damping.alpha, damping.beta
 *   model.cantilever.zeta                       damping.zeta
 *   model.chain.m, model.chain.k, model.chain.c  mass.scale, stiffness.scale,
 *       damping.scale, the same value: a uniform chain is built from unit
 *       elements scaled by them, so a study changing one gets the model the
 *       scene builds with that value (the modes redone); refused for a
 *       chain given element by element, and model.chain.c when Rayleigh
 *       damping replaces C
 *   initial.t0, initial.x[i], initial.v[i]                     the same
 *   damping.*                                                  the same
 */
#ifndef VI_SCENE_PARAM_H
#define VI_SCENE_PARAM_H

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The parameter key of the scene key `key` into out [len].  @return
 *  VI_OK, VI_ERR_ARG (NULL), VI_ERR_PARSE (not a parameter: a key such as
 *  model.chain.n that changes the model's size, or one that is not a
 *  number; diag names the key and lists the parameters), VI_ERR_LIMIT
 *  (len too small). */
VI_API int vi_scene_param_key(const vi_scene *sc, const char *key, char *out,
                              int len, vi_diag *diag);

#ifdef __cplusplus
}
#endif
#endif
