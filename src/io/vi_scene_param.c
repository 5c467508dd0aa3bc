/* vi_scene_param.c - scene keys as the parameters of vi_param.h: the few
 * keys whose names differ. */
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
  if (vi_param_kind(p) == VI_PARAM_UNKNOWN) {
    char list[400];
    size_t k = 0;
    for (int i = 0; i < vi_param_key_count() && k < sizeof list; i++)
      k += (size_t)snprintf(list + k, sizeof list - k, "%s%s", i ? ", " : "",
                            vi_param_key_name(i));
    return vi_diag_set(d, sc->file, VI_ERR_PARSE, 0, 0, key, "",
                       "not a parameter a study can change (the parameters "
                       "are %s; model.rayleigh.alpha/beta, "
                       "model.cantilever.zeta; indices 1-based)", list);
  }
  if ((int)strlen(p) >= len)
    return vi_diag_set(d, sc->file, VI_ERR_LIMIT, 0, 0, key, "", "%s",
                       "the parameter key does not fit the buffer");
  snprintf(out, (size_t)len, "%s", p);
  return VI_OK;
}
