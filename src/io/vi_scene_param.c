/* vi_scene_param.c - scene keys as the parameters of vi_param.h: the few
 * keys whose names differ, and a uniform chain's m, k, c as the structural
 * parameters mass.scale, stiffness.scale, damping.scale. */
#include <stdio.h>
#include <string.h>

#include "vi_scene_internal.h"
#include "vibroimpact/vi_param.h"
#include "vibroimpact/vi_scene_param.h"

/* Scene keys named differently from their parameter. */
static const char *const renamed[][2] = {
    {"model.rayleigh.alpha", "damping.alpha"},
    {"model.rayleigh.beta", "damping.beta"},
    {"model.cantilever.zeta", "damping.zeta"},
};

/* A uniform chain's element values: structural parameters (vi_param.h),
 * M = m M_1, K = k K_1, C = c C_1 with the unit-element matrices the
 * scene builds (vi_scene_model.c), so that a study setting k gets the
 * model the scene builds with that k, bit for bit. */
static const char *const chain_keys[3][2] = {
    {"model.chain.m", "mass.scale"},
    {"model.chain.k", "stiffness.scale"},
    {"model.chain.c", "damping.scale"},
};

int vi_scene_chain_scalable(const vi_scene *s)
{
  if (s->kind != VI_SCENE_CHAIN || !s->cm) return 0;
  const double *v[3] = {s->cm, s->ck, s->cc};
  /* Rayleigh damping replaces C, and follows M and K when its alpha and
   * beta are the model's (>= 0, vi_scene_model.c) */
  int ray_ok = !s->has_rayleigh || (s->ra >= 0.0 && s->rb >= 0.0), mask = 0;
  for (int j = 0; j < 3; j++) {
    int uniform = j < 2 ? ray_ok : !s->has_rayleigh;
    for (int i = 1; i < s->n && uniform; i++) uniform = v[j][i] == v[j][0];
    if (uniform) mask |= 1 << j;
  }
  return mask;
}

void vi_scene_chain_elements(const vi_scene *s, double *u)
{
  int n = s->n, mask = vi_scene_chain_scalable(s);
  const double *v[3] = {s->cm, s->ck, s->cc};
  for (int j = 0; j < 3; j++)
    for (int i = 0; i < n; i++)
      u[(size_t)j * n + i] = (mask >> j) & 1 ? 1.0 : v[j][i];
}

int vi_scene_chain_scale(const vi_scene *s, vi_model *m)
{
  int mask = vi_scene_chain_scalable(s), st = VI_OK;
  const double *v[3] = {s->cm, s->ck, s->cc};
  for (int j = 0; j < 3 && !st; j++)
    if ((mask >> j) & 1) st = vi_model_set_param(m, chain_keys[j][1], v[j][0]);
  return st;
}

/* model.chain.m, .k, .c: their parameter, or why not. */
static int chain_key(const vi_scene *sc, const char *key, const char **p,
                     vi_diag *d)
{
  for (int j = 0; j < 3; j++) {
    if (strcmp(key, chain_keys[j][0]) != 0) continue;
    if (sc->kind != VI_SCENE_CHAIN)
      return vi_diag_set(d, sc->file, VI_ERR_PARSE, sc->line_model, 0, key, "",
                         "%s", "the scene's model is not a chain (model.chain)");
    if (!((vi_scene_chain_scalable(sc) >> j) & 1))
      return vi_diag_set(d, sc->file, VI_ERR_PARSE, sc->line_model, 0, key, "",
                         "%s", j == 2 && sc->has_rayleigh
                         ? "the chain's damping is Rayleigh: change "
                           "model.rayleigh.alpha or model.rayleigh.beta"
                         : "the chain's elements differ (a list): only a "
                           "uniform value is a parameter");
    *p = chain_keys[j][1];
    return VI_OK;
  }
  return VI_OK;
}

int vi_scene_param_key(const vi_scene *sc, const char *key, char *out,
                       int len, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (!sc || !key || !out || len < 1)
    return vi_diag_set(d, sc ? sc->file : "", VI_ERR_ARG, 0, 0, "", "", "%s",
                       "vi_scene_param_key: scene, key and out are required");
  const char *p = key;
  for (size_t i = 0; i < sizeof renamed / sizeof *renamed; i++)
    if (!strcmp(key, renamed[i][0])) p = renamed[i][1];
  int st = chain_key(sc, key, &p, d);
  if (st) return st;
  if (vi_param_kind(p) == VI_PARAM_UNKNOWN) {
    char list[400];
    size_t k = 0;
    for (int i = 0; i < vi_param_key_count() && k < sizeof list; i++)
      k += (size_t)snprintf(list + k, sizeof list - k, "%s%s", i ? ", " : "",
                            vi_param_key_name(i));
    return vi_diag_set(d, sc->file, VI_ERR_PARSE, 0, 0, key, "",
                       "not a parameter a study can change (the parameters "
                       "are %s; model.rayleigh.alpha/beta, "
                       "model.cantilever.zeta, a uniform chain's "
                       "model.chain.m/k/c; indices 1-based)", list);
  }
  if ((int)strlen(p) >= len)
    return vi_diag_set(d, sc->file, VI_ERR_LIMIT, 0, 0, key, "", "%s",
                       "the parameter key does not fit the buffer");
  snprintf(out, (size_t)len, "%s", p);
  return VI_OK;
}
