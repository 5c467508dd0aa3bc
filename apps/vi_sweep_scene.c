/* vi_sweep_scene.c - reading a scene file with `--set KEY=VALUE` overrides
 * applied (shared by sweep, orbits, and the run / energy commands). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vibroimpact.h"
#include "vibroimpact/vi_scene.h"
#include "vibroimpact/vi_scene_edit.h"
#include "vi_sweep.h"

char *vi_sweep_read_text(const char *path, char *err, int errlen)
{
  if (!path) {
    char *t = strdup(vi_scene_default_text());
    if (!t) snprintf(err, (size_t)errlen, "out of memory");
    return t;
  }
  FILE *f = fopen(path, "rb");
  if (!f) {
    snprintf(err, (size_t)errlen, "%s: cannot open: %s", path, strerror(errno));
    return NULL;
  }
  size_t len = 0, cap = 8192;
  char *buf = malloc(cap);
  size_t got;
  while (buf && (got = fread(buf + len, 1, cap - len - 1, f)) > 0) {
    len += got;
    if (cap - len < 2) {
      char *nb = realloc(buf, 2 * cap);
      if (!nb) {
        free(buf);
        buf = NULL;
      }
      buf = nb;
      cap *= 2;
    }
  }
  int bad = ferror(f);
  fclose(f);
  if (!buf || bad) {
    free(buf);
    snprintf(err, (size_t)errlen, "%s: %s", path, buf ? "read error" : "out of memory");
    return NULL;
  }
  buf[len] = '\0';
  return buf;
}

int vi_sweep_load_scene(const char *path, const char *const *sets, int nsets,
                        vi_scene **out, char *err, int errlen)
{
  vi_scene_edit *ed = NULL;
  vi_diag d;
  memset(&d, 0, sizeof d);
  *out = NULL;
  char *text = vi_sweep_read_text(path, err, errlen);
  if (!text) return 1;
  int st = vi_scene_edit_create(text, -1, path ? path : "<default scene: fig2>",
                                &ed, &d);
  for (int i = 0; i < nsets && !st; i++) st = vi_scene_edit_assign(ed, sets[i], &d);
  if (!st) st = vi_scene_edit_parse(ed, out, &d);
  free(text);
  vi_scene_edit_destroy(&ed);
  if (st) {
    if (!d.code) {
      d.code = st;
      snprintf(d.message, sizeof d.message, "%s", vi_strerror(st));
    }
    vi_diag_format(&d, err, errlen);
    return st == VI_ERR_NOMEM || st == VI_ERR_IO ? 1 : 2;
  }
  return 0;
}
