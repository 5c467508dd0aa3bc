/* vi_app_scene.c - reading a scene file with `--set KEY=VALUE` overrides
 * applied (shared by sweep, orbits, and the run / energy commands). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "vibroimpact.h"
#include "vibroimpact/vi_scene.h"
#include "vibroimpact/vi_scene_edit.h"
#include "vi_diagram.h"

/* vi_app_read_text with a size limit: max_bytes (<= 0, or above it: the
 * reader's own, VI_SCENE_MAX_BYTES). */
static char *read_text_limited(const char *path, int64_t max_bytes, char *err, int errlen)
{
  int64_t limit = max_bytes > 0 && max_bytes < VI_SCENE_MAX_BYTES ? max_bytes
                                                                  : VI_SCENE_MAX_BYTES;
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
    if ((int64_t)len > limit) { /* --max-scene-size, or the reader's own */
      fclose(f);
      free(buf);
      if (limit == VI_SCENE_MAX_BYTES)
        snprintf(err, (size_t)errlen, "%s: larger than %d bytes: not a scene", path,
                 VI_SCENE_MAX_BYTES);
      else
        snprintf(err, (size_t)errlen, "%s: the scene is larger than %lld bytes (the limit; "
                 "--max-scene-size raises it)", path, (long long)limit);
      return NULL;
    }
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

char *vi_app_read_text(const char *path, char *err, int errlen)
{
  return read_text_limited(path, 0, err, errlen);
}

int vi_app_load_scene(const char *path, const char *const *sets, int nsets,
                      int max_depth, double max_memory, vi_scene **out,
                      char *err, int errlen)
{
  vi_scene_edit *ed = NULL;
  vi_diag d;
  memset(&d, 0, sizeof d);
  *out = NULL;
  char *text = vi_app_read_text(path, err, errlen);
  if (!text) return 1;
  int st = vi_scene_edit_create_limited(text, -1, path ? path : "<default "
                                        "scene: fig2>", max_depth, &ed, &d);
  for (int i = 0; i < nsets && !st; i++) st = vi_scene_edit_assign(ed, sets[i], &d);
  if (!st) st = vi_scene_edit_parse_within(ed, max_memory, out, &d);
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

/* ---- --set for the commands that share the app's option parser --------- */
/* The program's own list, filled once by main() before any thread starts. */
static const char **set_list;
static int set_count;

int vi_sets_take(int argc, char **argv)
{
  int k = 1;
  set_list = calloc((size_t)argc + 1, sizeof *set_list);
  if (!set_list) return -1;
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--set")) {
      if (i + 1 >= argc) return -1;
      set_list[set_count++] = argv[++i];
    } else if (!strncmp(argv[i], "--set=", 6)) {
      set_list[set_count++] = argv[i] + 6;
    } else {
      argv[k++] = argv[i];
    }
  }
  argv[k] = NULL;
  return k;
}

int vi_sets_active(void) { return set_count; }

int vi_sets_load(const char *path, int64_t max_bytes, int max_depth, double max_memory,
                 vi_scene **out, vi_diag *d)
{
  if (!set_count)
    return path ? vi_scene_load_within(path, max_bytes, max_depth, max_memory, out, d)
                : vi_scene_parse(vi_scene_default_text(), -1,
                                 "<default scene: fig2>", out, d);
  char err[512];
  vi_scene_edit *ed = NULL;
  if (d) memset(d, 0, sizeof *d);
  *out = NULL;
  char *text = read_text_limited(path, max_bytes, err, sizeof err);
  if (!text) {
    if (d) {
      d->code = VI_ERR_IO;
      snprintf(d->file, sizeof d->file, "%s", path ? path : "");
      size_t k = path ? strlen(path) : 0; /* err starts "path: " */
      snprintf(d->message, sizeof d->message, "%s",
               k && !strncmp(err, path, k) && err[k] == ':' ? err + k + 2 : err);
    }
    return VI_ERR_IO;
  }
  int st = vi_scene_edit_create_limited(text, -1, path ? path : "<default "
                                        "scene: fig2>", max_depth, &ed, d);
  for (int i = 0; i < set_count && !st; i++) st = vi_scene_edit_assign(ed, set_list[i], d);
  if (!st) st = vi_scene_edit_parse_within(ed, max_memory, out, d);
  free(text);
  vi_scene_edit_destroy(&ed);
  return st;
}

/* ---- `vibroimpact sweep`: run vibroimpact-sweep in this process's place -- */
int vi_app_sweep_exec(int argc, char **argv)
{
  char self[4096];
  /* `basins` is the sweep program's other mode: it gets --basins first */
  int basins = !strcmp(argv[0], "basins");
  char **av = calloc((size_t)argc + 2, sizeof *av);
  if (!av) {
    fprintf(stderr, "vibroimpact: %s: out of memory\n", argv[0]);
    return 1;
  }
  av[0] = argv[0];
  if (basins) av[1] = (char *)"--basins";
  for (int i = 1; i < argc; i++) av[i + basins] = argv[i];
  argv = av;
  ssize_t k = readlink("/proc/self/exe", self, sizeof self - 32);
  if (k <= 0) {
    fprintf(stderr, "vibroimpact: sweep: cannot locate the program: %s\n", strerror(errno));
    free(av);
    return 1;
  }
  self[k] = '\0';
  char *slash = strrchr(self, '/');
  snprintf(slash ? slash + 1 : self, sizeof self - (size_t)(slash ? slash + 1 - self : 0),
           "vibroimpact-sweep");
  argv[0] = self;
  /* the study's threads wait for work only at the end (each piece is
   * milliseconds or more): waiting threads sleep rather than spin, leaving
   * the cores to those still working.  Read by libgomp as it loads, so set
   * before the exec; a user's own setting stands. */
  setenv("OMP_WAIT_POLICY", "passive", 0);
  execv(self, argv);
  fprintf(stderr, "vibroimpact: sweep: cannot run %s: %s\n", self, strerror(errno));
  free(av);
  return 1;
}

int vi_app_same_key(const char *k1, const char *k2)
{
  char a[64], b[64];
  snprintf(a, sizeof a, "%s", strncmp(k1, "stop.", 5) ? k1 : "");
  snprintf(b, sizeof b, "%s", strncmp(k2, "stop.", 5) ? k2 : "");
  if (!a[0]) snprintf(a, sizeof a, "stops[1].%.40s", k1 + 5);
  if (!b[0]) snprintf(b, sizeof b, "stops[1].%.40s", k2 + 5);
  return !strcmp(a, b);
}

int vi_app_text_nonlinear(const char *text)
{
  vi_scene_edit *ed = NULL;
  char buf[64];
  int has = 0;
  if (!vi_scene_edit_create(text, -1, "", &ed, NULL))
    has = vi_scene_edit_get(ed, "springs[1].type", buf, sizeof buf, NULL) == VI_OK;
  vi_scene_edit_destroy(&ed);
  return has;
}
