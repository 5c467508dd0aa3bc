/* vi_scene.c - reading a scene: YAML text (libyaml's events, our own
 * composer) into the plain description of vi_scene_internal.h, every value
 * checked where it is read and every error reported with file:line:column
 * and key.  The only file of the scene that knows YAML; the model is
 * assembled in vi_scene_model.c, the run options' getters and overrides
 * live in vi_scene_options.c (above this file: it calls nothing there). */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <yaml.h>

#include "base/vi_period.h"
#include "vi_matrix_internal.h"
#include "vi_scene_internal.h"
#include "vibroimpact.h"
#include "vibroimpact/vi_mmio.h"


/* ---- diagnostics -------------------------------------------------------- */
typedef struct ctx {
  yaml_document_t doc;
  vi_diag *d;
  const char *file;
  const double *max_memory; /* the caller's budget (<= 0: the machine's);
                             * NULL: none checked while parsing */
} ctx;

void vi_diag_format(const vi_diag *d, char *buf, int len)
{
  if (!buf || len <= 0) return;
  if (!d) {
    buf[0] = '\0';
    return;
  }
  int k = snprintf(buf, len, "%s", d->file[0] ? d->file : "<input>");
  if (d->line > 0 && k < len)
    k += snprintf(buf + k, len - k, ":%d:%d", d->line, d->column);
  if (d->key[0] && k < len) k += snprintf(buf + k, len - k, ": %s", d->key);
  if (d->value[0] && k < len)
    k += snprintf(buf + k, len - k, " = %s", d->value);
  if (k < len) snprintf(buf + k, len - k, ": %s", d->message);
}

#define LINE(nd) ((int)(nd)->start_mark.line + 1)
#define COL(nd) ((int)(nd)->start_mark.column + 1)

static int fail(ctx *c, yaml_node_t *nd, int code, const char *key,
                const char *fmt, const char *detail)
{
  const char *val = nd && nd->type == YAML_SCALAR_NODE
                        ? (const char *)nd->data.scalar.value
                        : "";
  return vi_diag_set(c->d, c->file, code, nd ? LINE(nd) : 0,
                     nd ? COL(nd) : 0, key, val, fmt, detail);
}

/* ---- typed access ------------------------------------------------------- */
static yaml_node_t *node(ctx *c, int id)
{
  return yaml_document_get_node(&c->doc, id);
}

static void join(char *out, const char *path, const char *key)
{
  snprintf(out, 128, "%s%s%s", path, path[0] ? "." : "", key);
}

/* Check that a mapping holds only allowed keys, each once. */
static int check_map(ctx *c, yaml_node_t *map, const char *path,
                     const char *const *allowed)
{
  if (!map || map->type != YAML_MAPPING_NODE)
    return fail(c, map, VI_ERR_PARSE, path, "%s", "expected a mapping of keys");
  for (yaml_node_pair_t *p = map->data.mapping.pairs.start;
       p < map->data.mapping.pairs.top; p++) {
    yaml_node_t *k = node(c, p->key);
    char full[128];
    if (k->type != YAML_SCALAR_NODE)
      return fail(c, k, VI_ERR_PARSE, path, "%s", "keys must be plain words");
    const char *ks = (const char *)k->data.scalar.value;
    join(full, path, ks);
    int ok = 0;
    for (const char *const *a = allowed; *a; a++)
      ok |= !strcmp(*a, ks);
    if (!ok) {
      char list[256] = "";
      for (const char *const *a = allowed; *a; a++)
        snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s",
                 a == allowed ? "" : ", ", *a);
      return vi_diag_set(c->d, c->file, VI_ERR_PARSE, LINE(k), COL(k), full, ks,
                         "unknown key (allowed here: %s)", list);
    }
    for (yaml_node_pair_t *q = map->data.mapping.pairs.start; q < p; q++)
      if (!strcmp((const char *)node(c, q->key)->data.scalar.value, ks))
        return vi_diag_set(c->d, c->file, VI_ERR_PARSE, LINE(k), COL(k), full,
                           ks, "%s", "key given twice");
  }
  return VI_OK;
}

static yaml_node_t *find(ctx *c, yaml_node_t *map, const char *key)
{
  if (!map || map->type != YAML_MAPPING_NODE) return NULL;
  for (yaml_node_pair_t *p = map->data.mapping.pairs.start;
       p < map->data.mapping.pairs.top; p++) {
    yaml_node_t *k = node(c, p->key);
    if (k->type == YAML_SCALAR_NODE &&
        !strcmp((const char *)k->data.scalar.value, key))
      return node(c, p->value);
  }
  return NULL;
}

/* Tags the composer gives untagged scalars: "?" plain, "!" quoted (YAML's
 * non-specific tags).  A number must be plain, or tagged !!int / !!float:
 * `!!str 0.1` and "0.1" are text. */
#define TAG_PLAIN "?"
#define TAG_QUOTED "!"
static int numeric_tag(const yaml_node_t *nd)
{
  const char *t = (const char *)nd->tag;
  return t && (!strcmp(t, TAG_PLAIN) || !strcmp(t, YAML_INT_TAG) ||
               !strcmp(t, YAML_FLOAT_TAG));
}

static int number(ctx *c, yaml_node_t *nd, const char *key, double *out)
{
  if (!nd || nd->type != YAML_SCALAR_NODE)
    return fail(c, nd, VI_ERR_PARSE, key, "%s", "expected a number");
  if (!numeric_tag(nd))
    return fail(c, nd, VI_ERR_PARSE, key, "%s",
                "expected a number, got text (quoted or tagged)");
  const char *s = (const char *)nd->data.scalar.value;
  char *end;
  errno = 0;
  double v = strtod(s, &end);
  if (end != s && !*end && errno == ERANGE) /* 1e-400, 1e-308: numbers */
    return fail(c, nd, VI_ERR_LIMIT, key, "%s", "beyond double precision's "
                "range (it under- or overflows)");
  if (end == s || *end)
    return fail(c, nd, VI_ERR_PARSE, key, "%s", "expected a number");
  if (!isfinite(v))
    return fail(c, nd, VI_ERR_NONFINITE, key, "%s", "must be finite");
  if (fabs(v) > VI_SCENE_NUM_MAX)
    return fail(c, nd, VI_ERR_LIMIT, key, "%s",
                "magnitude above 1e100: outside the range where the "
                "energies stay finite");
  *out = v;
  return VI_OK;
}

/* v within [lo, hi], else an error naming the key and the range. */
static int in_range(ctx *c, yaml_node_t *nd, const char *key, double v,
                    double lo, double hi, int code)
{
  if (v >= lo && v <= hi) return VI_OK;
  char why[160];
  snprintf(why, sizeof why, "must lie in [%.3g, %.3g]", lo, hi);
  return fail(c, nd, code, key, "%s", why);
}

static int integer(ctx *c, yaml_node_t *nd, const char *key, int lo, int hi,
                   int *out)
{
  double v = 0;
  int st = number(c, nd, key, &v);
  if (st) return st;
  if (v != floor(v) || v < lo || v > hi) {
    char why[64];
    snprintf(why, sizeof why, "expected a whole number in [%d, %d]", lo, hi);
    return fail(c, nd, VI_ERR_PARSE, key, "%s", why);
  }
  *out = (int)v;
  return VI_OK;
}

/* A dof of the model (stop.dof, forcing.on): its 1-based index, or in a
 * model of coordinate files a [node, dof] pair of its dof map. */
static int dof_index(ctx *c, const vi_scene *s, yaml_node_t *nd,
                     const char *key, int *out)
{
  if (!nd || nd->type != YAML_SEQUENCE_NODE)
    return integer(c, nd, key, 1, s->n, out);
  if (!s->fe.map)
    return fail(c, nd, VI_ERR_PARSE, key, "%s", "a [node, dof] pair names "
                "a dof of a model read from coordinate files; give the "
                "dof's index");
  yaml_node_item_t *it = nd->data.sequence.items.start;
  int label = 0, comp = 0, st;
  if (nd->data.sequence.items.top - it != 2)
    return fail(c, nd, VI_ERR_PARSE, key, "%s", "expected [node, dof]");
  if ((st = integer(c, node(c, it[0]), key, INT_MIN, INT_MAX, &label)) ||
      (st = integer(c, node(c, it[1]), key, 1, INT_MAX, &comp)))
    return st;
  if (!(*out = vi_dofmap_index(s->fe.map, label, comp))) {
    char why[128];
    snprintf(why, sizeof why, "(node %d, dof %d) is not a dof of the model "
             "(no file names it)", label, comp);
    return fail(c, nd, VI_ERR_DIM, key, "%s", why);
  }
  return VI_OK;
}

static int boolean(ctx *c, yaml_node_t *nd, const char *key, int *out)
{
  const char *s = nd && nd->type == YAML_SCALAR_NODE && nd->tag &&
                          (!strcmp((const char *)nd->tag, TAG_PLAIN) ||
                           !strcmp((const char *)nd->tag, YAML_BOOL_TAG))
                      ? (const char *)nd->data.scalar.value
                      : "";
  if (!strcmp(s, "true"))
    *out = 1;
  else if (!strcmp(s, "false"))
    *out = 0;
  else
    return fail(c, nd, VI_ERR_PARSE, key, "%s", "expected true or false");
  return VI_OK;
}

/* A list of exactly n numbers; with `scalar_ok` a single number is repeated. */
static int vector(ctx *c, yaml_node_t *nd, const char *key, int n,
                  int scalar_ok, double *out)
{
  if (nd && nd->type == YAML_SCALAR_NODE && scalar_ok) {
    double v;
    int st = number(c, nd, key, &v);
    for (int i = 0; i < n && !st; i++)
      out[i] = v;
    return st;
  }
  if (!nd || nd->type != YAML_SEQUENCE_NODE)
    return fail(c, nd, VI_ERR_PARSE, key, "%s", "expected a list of numbers");
  int len = (int)(nd->data.sequence.items.top - nd->data.sequence.items.start);
  if (len != n) {
    char why[96];
    snprintf(why, sizeof why,
             "expected %d numbers (the model has n = %d), got %d", n, n, len);
    return fail(c, nd, VI_ERR_DIM, key, "%s", why);
  }
  for (int i = 0; i < n; i++) {
    char k[128];
    snprintf(k, sizeof k, "%s[%d]", key, i + 1);
    int st = number(c, node(c, nd->data.sequence.items.start[i]), k, &out[i]);
    if (st) return st;
  }
  return VI_OK;
}

/* n rows of n numbers into column-major storage. */
static int matrix(ctx *c, yaml_node_t *nd, const char *key, int n, double *out)
{
  if (!nd || nd->type != YAML_SEQUENCE_NODE)
    return fail(c, nd, VI_ERR_PARSE, key, "%s", "expected a list of rows");
  int rows = (int)(nd->data.sequence.items.top - nd->data.sequence.items.start);
  if (rows != n) {
    char why[96];
    snprintf(why, sizeof why, "expected %d rows, got %d", n, rows);
    return fail(c, nd, VI_ERR_DIM, key, "%s", why);
  }
  double *row = malloc(sizeof(double) * n);
  if (!row) return fail(c, nd, VI_ERR_NOMEM, key, "%s", "out of memory");
  int st = VI_OK;
  for (int i = 0; i < n && !st; i++) {
    char k[128];
    snprintf(k, sizeof k, "%s row %d", key, i + 1);
    st = vector(c, node(c, nd->data.sequence.items.start[i]), k, n, 0, row);
    for (int j = 0; j < n && !st; j++)
      out[i + (size_t)j * n] = row[j];
  }
  free(row);
  return st;
}

/* An optional key of a section: its node (NULL when absent: the value
 * keeps its default) and its dotted name in full[128]. */
static yaml_node_t *optional(ctx *c, yaml_node_t *map, const char *path,
                             const char *key, char *full)
{
  join(full, path, key);
  return find(c, map, key);
}

static int opt_number(ctx *c, yaml_node_t *map, const char *path,
                      const char *key, double *out)
{
  char full[128];
  yaml_node_t *v = optional(c, map, path, key, full);
  return v ? number(c, v, full, out) : VI_OK;
}

static int opt_vector(ctx *c, yaml_node_t *map, const char *path,
                      const char *key, int n, double *out)
{
  char full[128];
  yaml_node_t *v = optional(c, map, path, key, full);
  return v ? vector(c, v, full, n, 0, out) : VI_OK;
}

/* initial.x / initial.v: a list of n numbers, or one number for every
 * coordinate (a large model starting from a uniform state). */
static int opt_state(ctx *c, yaml_node_t *map, const char *key, int n,
                     double *out)
{
  char full[128];
  yaml_node_t *v = optional(c, map, "initial", key, full);
  return v ? vector(c, v, full, n, 1, out) : VI_OK;
}

/* An optional boolean as one bit of *flags. */
static int opt_flag(ctx *c, yaml_node_t *map, const char *path,
                    const char *key, int bit, int *flags)
{
  char full[128];
  yaml_node_t *v = optional(c, map, path, key, full);
  int on = 0, st = v ? boolean(c, v, full, &on) : VI_OK;
  if (v && !st) *flags = on ? *flags | bit : *flags & ~bit;
  return st;
}

/* ---- the sections ------------------------------------------------------- */
static double *alloc_n(vi_scene *s, int count)
{
  return calloc((size_t)count * s->n, sizeof(double));
}

/* Largest over smallest of the non-zero |v[i*stride]|: the spread of masses
 * or stiffnesses, which bounds how stiff the equations get. */
static double spread(const double *v, int n, size_t stride)
{
  double lo = INFINITY, hi = 0;
  for (int i = 0; i < n; i++) {
    double a = fabs(v[(size_t)i * stride]);
    if (a > 0) {
      lo = a < lo ? a : lo;
      hi = a > hi ? a : hi;
    }
  }
  return hi > 0 ? hi / lo : 1.0;
}

static int check_spread(ctx *c, yaml_node_t *nd, const char *key,
                        const char *what, const double *v, int n,
                        size_t stride)
{
  double sp = spread(v, n, stride);
  if (sp <= VI_SCENE_RATIO_MAX) return VI_OK;
  char why[200];
  snprintf(why, sizeof why,
           "the largest %s is %.3g times the smallest (limit 1e12: beyond "
           "it the equations are too stiff for double precision)",
           what, sp);
  return fail(c, nd, VI_ERR_LIMIT, key, "%s", why);
}

/* A matrix file's error at the scene's key: a place in the file, there
 * with the scene's key in front; none (it cannot be opened, or the
 * coordinate files' map), at the scene's key (v; NULL: no place). */
static int file_fail(ctx *c, yaml_node_t *v, const char *key, int st,
                     const vi_diag *hd, const char *path)
{
  if (!hd->line)
    return vi_diag_set(c->d, c->file, st, v ? LINE(v) : 0, v ? COL(v) : 0, key,
                       v ? (const char *)v->data.scalar.value : "", "%s: %s",
                       hd->file[0] ? hd->file : path, hd->message);
  if (c->d) {
    *c->d = *hd;
    snprintf(c->d->key, sizeof c->d->key, "%.60s %.60s", key, hd->key);
  }
  return st;
}

static char *scene_relative(const char *scene_file, const char *path);

/* The files of model.matrices (or model.matrix_market): {M: FILE, K: FILE,
 * C: FILE, format: auto|matrix_market|harwell_boeing|coordinate}.  Each
 * path resolved, each format told by its content unless format names it;
 * coordinate files (all of a model's, or none) numbered by one dof map
 * built over all of them (vi_dofmap_scan: their (node, dof) pairs,
 * sorted). */
static int fe_files(ctx *c, vi_scene *s, yaml_node_t *mm, const char *section)
{
  static const char *const fk[] = {"M", "K", "C", "format", NULL};
  static const char *const names[3] = {"M", "K", "C"};
  static const int slot[3] = {VI_FE_MASS, VI_FE_STIFFNESS, VI_FE_DAMPING};
  static const char *const fmts[] = {"auto", "matrix_market",
                                     "harwell_boeing", "coordinate"};
  int st = check_map(c, mm, section, fk);
  if (st) return st;
  s->kind = VI_SCENE_FE;
  s->fe.section = section;
  char key[64];
  int format = VI_MATRIX_AUTO;
  yaml_node_t *fn = find(c, mm, "format");
  if (fn) {
    snprintf(key, sizeof key, "%s.format", section);
    const char *fv = fn->type == YAML_SCALAR_NODE
                         ? (const char *)fn->data.scalar.value : "";
    format = 0;
    while (format < 4 && strcmp(fv, fmts[format]) != 0) format++;
    if (format == 4)
      return fail(c, fn, VI_ERR_PARSE, key, "%s", "expected auto, "
                  "matrix_market, harwell_boeing or coordinate");
  }
  for (int k = 0; k < 3; k++) {
    snprintf(key, sizeof key, "%s.%s", section, names[k]);
    yaml_node_t *v = find(c, mm, names[k]);
    if (!v) {
      if (k == 2) continue; /* C is optional */
      return fail(c, mm, VI_ERR_PARSE, key, "%s",
                  "missing: M and K are required (C is optional)");
    }
    if (v->type != YAML_SCALAR_NODE || !v->data.scalar.length ||
        strlen((const char *)v->data.scalar.value) != v->data.scalar.length)
      return fail(c, v, VI_ERR_PARSE, key, "%s",
                  "expected the path of a matrix file");
    char *path = scene_relative(c->file, (const char *)v->data.scalar.value);
    if (!path) return fail(c, v, VI_ERR_NOMEM, key, "%s", "out of memory");
    s->fe.path[slot[k]] = path;
    s->fe.line[slot[k]] = LINE(v);
    vi_diag hd;
    int f = format;
    if (!f && (st = vi_matrix_detect(path, &f, &hd)))
      return file_fail(c, v, key, st, &hd, path);
    s->fe.format[slot[k]] = f;
    if (k > 0 && (f == VI_MATRIX_COORDINATE) !=
                     (s->fe.format[VI_FE_MASS] == VI_MATRIX_COORDINATE))
      return fail(c, v, VI_ERR_PARSE, key, "%s", "coordinate files "
                  "(node, dof, node, dof, value) number their dofs by one "
                  "map over all of a model's files: M, K and C must all be "
                  "coordinate files or none");
  }
  if (s->fe.format[VI_FE_MASS] != VI_MATRIX_COORDINATE) return VI_OK;
  const char *paths[3];
  int np = 0;
  for (int k = 0; k < 3; k++)
    if (s->fe.path[slot[k]]) paths[np++] = s->fe.path[slot[k]];
  vi_diag hd;
  if ((st = vi_dofmap_scan(np, paths, 0, &s->fe.map, &hd)))
    return file_fail(c, NULL, section, st, &hd, paths[0]);
  return VI_OK;
}

/* A matrix file named in the scene: relative to the scene's folder (the
 * folder of the name it was read under), absolute as written. */
static char *scene_relative(const char *scene_file, const char *path)
{
  const char *slash = strrchr(scene_file, '/');
  size_t dl = path[0] == '/' || !slash ? 0 : (size_t)(slash - scene_file) + 1;
  char *out = malloc(dl + strlen(path) + 1);
  if (!out) return NULL;
  memcpy(out, scene_file, dl);
  strcpy(out + dl, path);
  return out;
}

/* Without model.modes an FE scene keeps every finite mode (vi_fe_create's
 * rule): the dofs with mass, counted from M now, since the model's size is
 * the scene's.  Beyond VI_SCENE_FE_WHOLE_MAX dofs the user must choose:
 * a cut made by default would change the model without a word. */
#define VI_SCENE_FE_WHOLE_MAX 1000
static int whole_model(ctx *c, vi_scene *s, yaml_node_t *mm)
{
  char why[256];
  if (s->n > VI_SCENE_FE_WHOLE_MAX) {
    snprintf(why, sizeof why, "missing: the structure has %d dofs, more than "
             "the %d up to which the whole model is kept by default; say how "
             "many of its lowest modes to keep (`vibroimpact truncation` "
             "tells how many a stop needs)", s->n, VI_SCENE_FE_WHOLE_MAX);
    return fail(c, mm, VI_ERR_PARSE, "model.modes", "%s", why);
  }
  vi_mm *M = NULL;
  vi_diag d;
  int st = vi_matrix_load(s->fe.path[VI_FE_MASS], s->fe.format[VI_FE_MASS],
                          s->fe.map, VI_CSC_LOWER, 0, &M, &d);
  if (st) { /* a place in the matrix file, with the scene's key in front */
    if (c->d) {
      *c->d = d;
      snprintf(c->d->key, sizeof c->d->key, "%s.M %.60s", s->fe.section,
               d.key);
    }
    return st;
  }
  const int *cp = vi_mm_colptr(M), *ri = vi_mm_rowind(M);
  const double *v = vi_mm_values(M);
  char *massive = calloc((size_t)s->n, 1);
  if (!massive) {
    vi_mm_destroy(&M);
    return fail(c, mm, VI_ERR_NOMEM, "model", "%s", "out of memory");
  }
  for (int j = 0; j < s->n; j++)
    for (int p = cp[j]; p < cp[j + 1]; p++)
      if (v[p] != 0.0) massive[j] = massive[ri[p]] = 1;
  s->fe.massless = 0;
  for (int j = 0; j < s->n; j++) s->fe.massless += !massive[j];
  free(massive);
  vi_mm_destroy(&M);
  s->fe.modes = s->n - s->fe.massless;
  if (s->fe.modes < 1)
    return fail(c, mm, VI_ERR_NOT_SPD, s->fe.section, "%s",
                "M is zero: no dof has mass");
  return VI_OK;
}

/* model.matrix_market: {M: FILE, K: FILE, C: FILE} with modes and zeta
 * beside it.  The files' headers are read now (their size is the model's n
 * and, with the modes, its memory); their entries when the model is made.
 * model.matrices is its new name (either may be used), with format:
 * auto|matrix_market|harwell_boeing|coordinate (fe_files).  section: the
 * name the scene used. */
static int parse_fe(ctx *c, vi_scene *s, yaml_node_t *mod, yaml_node_t *mm,
                    const char *section)
{
  static const char *const names[3] = {"M", "K", "C"};
  static const int slot[3] = {VI_FE_MASS, VI_FE_STIFFNESS, VI_FE_DAMPING};
  int st = fe_files(c, s, mm, section);
  if (st) return st;
  for (int k = 0; k < 3; k++) {
    char key[64];
    snprintf(key, sizeof key, "%s.%s", section, names[k]);
    yaml_node_t *v = find(c, mm, names[k]);
    const char *path = s->fe.path[slot[k]];
    if (!v || !path) continue; /* C is optional (M and K: fe_files) */
    vi_diag hd;
    int rows = 0, cols = 0, sym = 0;
    int64_t entries = 0;
    if (s->fe.map) { /* coordinate files: the shared map's size */
      rows = cols = vi_dofmap_n(s->fe.map);
      entries = vi_dofmap_entries(s->fe.map);
    } else if ((st = vi_matrix_read_header(path, s->fe.format[slot[k]], &rows,
                                           &cols, &entries, &sym, &hd)))
      return file_fail(c, v, key, st, &hd, path);
    char why[160];
    if (rows != cols) {
      snprintf(why, sizeof why, "a %d x %d matrix: M, C and K are square",
               rows, cols);
      return fail(c, v, VI_ERR_DIM, key, "%s", why);
    }
    if (k > 0 && rows != s->n) {
      snprintf(why, sizeof why, "%d x %d, but M is %d x %d", rows, rows, s->n,
               s->n);
      return fail(c, v, VI_ERR_DIM, key, "%s", why);
    }
    s->n = rows;
    s->fe.entries = entries > s->fe.entries ? entries : s->fe.entries;
  }
  yaml_node_t *mo = find(c, mod, "modes"), *ze = find(c, mod, "zeta");
  yaml_node_t *rg = find(c, mod, "rigid_modes");
  s->fe.modes_given = mo != NULL;
  s->fe.rigid = -1; /* decided from K */
  if (rg && (st = integer(c, rg, "model.rigid_modes", 0, s->n, &s->fe.rigid)))
    return st;
  s->fe.line_rigid = rg ? LINE(rg) : 0;
  if (mo && (st = integer(c, mo, "model.modes", 1, s->n, &s->fe.modes)))
    return st;
  if (!mo && (st = whole_model(c, s, mm))) return st;
  if (s->fe.modes > 100000)
    return fail(c, mo, VI_ERR_LIMIT, "model.modes", "%s",
                "more than 100000 modes");
  if (ze) {
    if (s->fe.path[VI_FE_DAMPING])
      return fail(c, ze, VI_ERR_PARSE, "model.zeta", "%s",
                  "give damping once: C or zeta, not both");
    s->fe.nzeta = ze->type == YAML_SCALAR_NODE ? 1 : s->fe.modes;
    if (s->fe.nzeta < 1)
      return fail(c, ze, VI_ERR_PARSE, "model.zeta", "%s", "no modes to damp");
    if (!(s->fe.zeta = malloc(sizeof(double) * (size_t)s->fe.nzeta)))
      return fail(c, ze, VI_ERR_NOMEM, "model.zeta", "%s", "out of memory");
    if ((st = vector(c, ze, "model.zeta", s->fe.nzeta, 1, s->fe.zeta)))
      return st;
    for (int j = 0; j < s->fe.nzeta; j++)
      if (!(s->fe.zeta[j] >= 0 && s->fe.zeta[j] <= VI_SCENE_ZETA_MAX))
        return fail(c, ze, VI_ERR_ARG, "model.zeta", "%s",
                    "damping ratios must lie in [0, 1e6]");
  }
  if (!(s->fe.q0 = calloc(2 * (size_t)s->fe.modes + 1, sizeof(double))) ||
      !(s->fe.report = calloc(1, sizeof *s->fe.report)))
    return fail(c, mm, VI_ERR_NOMEM, "model", "%s", "out of memory");
  return VI_OK;
}

static int parse_model(ctx *c, vi_scene *s, yaml_node_t *mod)
{
  static const char *const keys[] = {"M",        "C",        "K",
                                     "chain",    "cantilever", "rayleigh",
                                     "matrix_market", "matrices", "modes",
                                     "zeta", "rigid_modes", NULL};
  int st = check_map(c, mod, "model", keys);
  if (st) return st;
  s->line_model = LINE(mod);
  yaml_node_t *K = find(c, mod, "K"), *ch = find(c, mod, "chain"),
              *ca = find(c, mod, "cantilever"),
              *mm = find(c, mod, "matrices"),
              *mmold = find(c, mod, "matrix_market");
  if ((K != NULL) + (ch != NULL) + (ca != NULL) + (mm != NULL) +
          (mmold != NULL) != 1)
    return fail(c, mod, VI_ERR_PARSE, "model", "%s",
                "give exactly one of K (with M, C), chain, cantilever or "
                "matrices (or its old name matrix_market)");
  const char *section = mm ? "model.matrices" : "model.matrix_market";
  mm = mm ? mm : mmold;
  if (!mm) {
    yaml_node_t *x = find(c, mod, "modes");
    x = x ? x : find(c, mod, "zeta");
    x = x ? x : find(c, mod, "rigid_modes");
    if (x)
      return fail(c, x, VI_ERR_PARSE, find(c, mod, "modes") ? "model.modes"
                  : find(c, mod, "zeta") ? "model.zeta" : "model.rigid_modes",
                  "%s", "modes, zeta and rigid_modes go with matrices (a "
                  "cantilever takes its modes and zeta in cantilever:)");
  }
  if (mm) {
    if (find(c, mod, "M") || find(c, mod, "C"))
      return fail(c, mod, VI_ERR_PARSE, "model", "%s",
                  "matrices give M, K and C: no explicit matrices beside "
                  "them");
    if ((st = parse_fe(c, s, mod, mm, section))) return st;
  } else if (K) {
    s->kind = VI_SCENE_EXPLICIT;
    if (K->type != YAML_SEQUENCE_NODE)
      return fail(c, K, VI_ERR_PARSE, "model.K", "%s",
                  "expected a list of rows");
    s->n = (int)(K->data.sequence.items.top - K->data.sequence.items.start);
    if (s->n < 1)
      return fail(c, K, VI_ERR_DIM, "model.K", "%s", "empty matrix");
    /* n x n numbers must be written out (an alias repeating a row would
     * let a small file ask for a huge matrix), and every row must hold n
     * of them, before n x n storage is allocated: the text then bounds the
     * memory */
    double nodes = (double)(c->doc.nodes.top - c->doc.nodes.start);
    if ((double)s->n * s->n > nodes)
      return fail(c, K, VI_ERR_LIMIT, "model.K", "%s",
                  "an n x n matrix needs its n^2 numbers written out "
                  "(aliased rows are not expanded)");
    for (int i = 0; i < s->n; i++) {
      yaml_node_t *row = node(c, K->data.sequence.items.start[i]);
      char k[64];
      snprintf(k, sizeof k, "model.K row %d", i + 1);
      if (!row || row->type != YAML_SEQUENCE_NODE)
        return fail(c, row, VI_ERR_PARSE, k, "%s", "expected a list of numbers");
      if (row->data.sequence.items.top - row->data.sequence.items.start !=
          s->n) {
        char why[96];
        snprintf(why, sizeof why, "expected %d numbers (K has %d rows), got %d",
                 s->n, s->n,
                 (int)(row->data.sequence.items.top -
                       row->data.sequence.items.start));
        return fail(c, row, VI_ERR_DIM, k, "%s", why);
      }
    }
    s->M = alloc_n(s, 3 * s->n);
    if (!s->M) return fail(c, K, VI_ERR_NOMEM, "model", "%s", "out of memory");
    s->C = s->M + (size_t)s->n * s->n;
    s->K = s->C + (size_t)s->n * s->n;
    if ((st = matrix(c, K, "model.K", s->n, s->K))) return st;
    yaml_node_t *M = find(c, mod, "M"), *C = find(c, mod, "C");
    if (M) {
      if ((st = matrix(c, M, "model.M", s->n, s->M))) return st;
    } else
      for (int i = 0; i < s->n; i++)
        s->M[i + (size_t)i * s->n] = 1.0;
    if (C && (st = matrix(c, C, "model.C", s->n, s->C))) return st;
    if ((st = check_spread(c, M ? M : K, M ? "model.M" : "model.K",
                           "diagonal mass", s->M, s->n, (size_t)s->n + 1)) ||
        (st = check_spread(c, K, "model.K", "diagonal stiffness", s->K, s->n,
                           (size_t)s->n + 1)))
      return st;
  } else if (ch) {
    static const char *const ck[] = {"n", "m", "k", "c", NULL};
    s->kind = VI_SCENE_CHAIN;
    if ((st = check_map(c, ch, "model.chain", ck)) ||
        (st = integer(c, find(c, ch, "n"), "model.chain.n", 1, 100000, &s->n)))
      return st;
    s->cm = alloc_n(s, 3);
    if (!s->cm)
      return fail(c, ch, VI_ERR_NOMEM, "model", "%s", "out of memory");
    s->ck = s->cm + s->n;
    s->cc = s->ck + s->n;
    yaml_node_t *cn = find(c, ch, "c");
    if ((st = vector(c, find(c, ch, "m"), "model.chain.m", s->n, 1, s->cm)) ||
        (st = vector(c, find(c, ch, "k"), "model.chain.k", s->n, 1, s->ck)) ||
        (cn && (st = vector(c, cn, "model.chain.c", s->n, 1, s->cc))) ||
        (st = check_spread(c, find(c, ch, "m"), "model.chain.m", "mass",
                           s->cm, s->n, 1)) ||
        (st = check_spread(c, find(c, ch, "k"), "model.chain.k", "stiffness",
                           s->ck, s->n, 1)))
      return st;
  } else {
    static const char *const bk[] = {"modes", "omega1", "zeta", "xi_stop",
                                     NULL};
    s->kind = VI_SCENE_CANTILEVER;
    s->omega1 = 1.0;
    s->xi_stop = 1.0;
    const char *p = "model.cantilever";
    if ((st = check_map(c, ca, p, bk)) ||
        (st = integer(c, find(c, ca, "modes"), "model.cantilever.modes", 1, 50,
                      &s->n)) ||
        (st = opt_number(c, ca, p, "omega1", &s->omega1)) ||
        (st = opt_number(c, ca, p, "zeta", &s->zeta)) ||
        (st = opt_number(c, ca, p, "xi_stop", &s->xi_stop)))
      return st;
    if (!(s->omega1 > 0) || s->zeta < 0 || !(s->xi_stop > 0) || s->xi_stop > 1)
      return fail(c, ca, VI_ERR_ARG, "model.cantilever", "%s",
                  "need omega1 > 0, zeta >= 0, 0 < xi_stop <= 1 (at the "
                  "clamp, xi_stop = 0, no mode moves and no impact can "
                  "happen)");
  }
  yaml_node_t *ra = find(c, mod, "rayleigh");
  if (ra) {
    static const char *const rk[] = {"alpha", "beta", NULL};
    if ((st = check_map(c, ra, "model.rayleigh", rk))) return st;
    if (find(c, mod, "C") || (ch && find(c, ch, "c")) ||
        (ca && find(c, ca, "zeta")) || find(c, mod, "zeta") ||
        (mm && find(c, mm, "C")))
      return fail(c, ra, VI_ERR_PARSE, "model.rayleigh", "%s",
                  "give damping once: rayleigh or C / c / zeta, not both");
    s->has_rayleigh = 1;
    if ((st = opt_number(c, ra, "model.rayleigh", "alpha", &s->ra)) ||
        (st = opt_number(c, ra, "model.rayleigh", "beta", &s->rb)))
      return st;
  }
  return VI_OK;
}

static int parse_forcing(ctx *c, vi_scene *s, yaml_node_t *f)
{
  static const char *const keys[] = {"omega", "a",         "b",    "f0",
                                     "on",    "amplitude", "base", NULL};
  int st = check_map(c, f, "forcing", keys);
  if (st) return st;
  s->line_forcing = LINE(f);
  if ((st = opt_number(c, f, "forcing", "omega", &s->omega)) ||
      (st = opt_vector(c, f, "forcing", "a", s->n, s->a)) ||
      (st = opt_vector(c, f, "forcing", "b", s->n, s->b)) ||
      (st = opt_vector(c, f, "forcing", "f0", s->n, s->f0)))
    return st;
  if (s->omega < 0)
    return fail(c, find(c, f, "omega"), VI_ERR_FREQUENCY, "forcing.omega",
                "%s", "must be >= 0 (0: no harmonic forcing)");
  yaml_node_t *on = find(c, f, "on"), *amp = find(c, f, "amplitude"),
              *base = find(c, f, "base");
  if ((on != NULL) != (amp != NULL))
    return fail(c, on ? on : amp, VI_ERR_PARSE, "forcing", "%s",
                "'on' and 'amplitude' go together");
  if (on) {
    double A = 0;
    if (find(c, f, "a"))
      return fail(c, on, VI_ERR_PARSE, "forcing.on", "%s",
                  "give 'a' or 'on', not both");
    if ((st = number(c, amp, "forcing.amplitude", &A))) return st;
    if (on->type != YAML_SEQUENCE_NODE)
      return fail(c, on, VI_ERR_PARSE, "forcing.on", "%s",
                  "expected a list of mass indices");
    for (yaml_node_item_t *it = on->data.sequence.items.start;
         it < on->data.sequence.items.top; it++) {
      int j = 1;
      if ((st = dof_index(c, s, node(c, *it), "forcing.on", &j))) return st;
      s->a[j - 1] = A;
    }
  }
  if (base) {
    if (s->kind != VI_SCENE_CANTILEVER)
      return fail(c, base, VI_ERR_PARSE, "forcing.base", "%s",
                  "base excitation needs a cantilever model");
    if ((st = number(c, base, "forcing.base", &s->base))) return st;
    s->has_base = 1;
  }
  return VI_OK;
}

/* One stop {w: [...] | dof: j (or its synonym mass: j, 1-based; in a
 * model of coordinate files also [node, dof]),
 * direction: +1 | -1, xs, r} at `path` ("stop", "stops[2]") into w [n]
 * (zeroed), *has_w, *xs, *r.  direction -1 makes the stop push the other
 * way: w = -e_j, so that -x_j <= xs (a stop below the coordinate). */
static int parse_stop_at(ctx *c, vi_scene *s, yaml_node_t *sp,
                         const char *path, double *w, int *has_w, double *xs,
                         double *r)
{
  static const char *const keys[] = {"w",  "mass", "dof", "direction",
                                     "xs", "r",    NULL};
  char key[128];
  int st = check_map(c, sp, path, keys);
  if (st) return st;
  yaml_node_t *wn = find(c, sp, "w"), *mass = find(c, sp, "mass"),
              *dof = find(c, sp, "dof"), *dir = find(c, sp, "direction");
  if (mass && dof) {
    join(key, path, "dof");
    return fail(c, dof, VI_ERR_PARSE, key, "%s",
                "give dof or its synonym mass, not both");
  }
  const char *dname = dof ? "dof" : "mass";
  if (!dof) dof = mass;
  join(key, path, dname);
  if (wn && dof)
    return fail(c, dof, VI_ERR_PARSE, key, "%s", "give w or dof, not both");
  if (wn) {
    join(key, path, "w");
    if ((st = vector(c, wn, key, s->n, 0, w))) return st;
    *has_w = 1;
  }
  double sign = 1.0;
  if (dir) {
    join(key, path, "direction");
    if (!dof)
      return fail(c, dir, VI_ERR_PARSE, key, "%s",
                  "direction goes with dof (w carries its own sign)");
    int dv = 0;
    if ((st = integer(c, dir, key, -1, 1, &dv))) return st;
    if (dv == 0)
      return fail(c, dir, VI_ERR_PARSE, key, "%s", "expected +1 or -1");
    sign = dv;
  }
  if (dof) {
    int j = 1;
    join(key, path, dname);
    if ((st = dof_index(c, s, dof, key, &j))) return st;
    w[j - 1] = sign;
    *has_w = 1;
  }
  if (!*has_w && s->kind != VI_SCENE_CANTILEVER)
    return fail(c, sp, VI_ERR_PARSE, path, "%s", "missing w or dof");
  yaml_node_t *xn = find(c, sp, "xs"), *rn = find(c, sp, "r");
  join(key, path, "xs");
  if (!xn)
    return fail(c, sp, VI_ERR_PARSE, key, "%s", "missing clearance xs");
  join(key, path, "r");
  if (!rn)
    return fail(c, sp, VI_ERR_PARSE, key, "%s", "missing restitution r");
  join(key, path, "xs");
  if ((st = number(c, xn, key, xs))) return st;
  join(key, path, "r");
  if ((st = number(c, rn, key, r))) return st;
  if (*r < 0 || *r > 1)
    return fail(c, rn, VI_ERR_RESTITUTION, key, "%s",
                "restitution must lie in [0, 1]");
  return VI_OK;
}

static int parse_stop(ctx *c, vi_scene *s, yaml_node_t *sp)
{
  s->line_stop = LINE(sp);
  return parse_stop_at(c, s, sp, "stop", s->w, &s->has_w, &s->xs, &s->r);
}

/* stops: a list of stops as stop: takes one (vi_model_add_stop order);
 * the first is the model's stop 0. */
static int parse_stops(ctx *c, vi_scene *s, yaml_node_t *list)
{
  if (list->type != YAML_SEQUENCE_NODE)
    return fail(c, list, VI_ERR_PARSE, "stops", "%s",
                "expected a list of stops");
  size_t count = (size_t)(list->data.sequence.items.top -
                          list->data.sequence.items.start);
  if (count < 1)
    return fail(c, list, VI_ERR_PARSE, "stops", "%s", "an empty list");
  if (count > 10000)
    return fail(c, list, VI_ERR_LIMIT, "stops", "%s", "more than 10000");
  size_t nx = count - 1, n = (size_t)s->n;
  s->xw = calloc(nx * (n + 2) + 1, sizeof(double));
  s->xint = calloc(2 * nx + 1, sizeof(int));
  if (!s->xw || !s->xint)
    return fail(c, list, VI_ERR_NOMEM, "stops", "%s", "out of memory");
  s->xxs = s->xw + nx * n;
  s->xr = s->xxs + nx;
  for (size_t k = 0; k < count; k++) {
    yaml_node_t *sp = node(c, list->data.sequence.items.start[k]);
    char path[64];
    snprintf(path, sizeof path, "stops[%zu]", k + 1);
    int st;
    if (k == 0) {
      s->line_stop = LINE(sp);
      st = parse_stop_at(c, s, sp, path, s->w, &s->has_w, &s->xs, &s->r);
    } else {
      s->xint[nx + k - 1] = LINE(sp);
      st = parse_stop_at(c, s, sp, path, s->xw + (k - 1) * n,
                         &s->xint[k - 1], &s->xxs[k - 1], &s->xr[k - 1]);
    }
    if (st) return st;
  }
  s->nx = (int)nx;
  s->stop_list = 1;
  return VI_OK;
}

/* springs: a list of {type: cubic, i, j, k3} (force k3 (x_i - x_j)^3) and
 * {type: bilinear, i, j, k, gap} (a soft stop past a gap); j = 0 is the
 * ground and may be left out. */
static int parse_springs(ctx *c, vi_scene *s, yaml_node_t *list)
{
  static const char *const cubic[] = {"type", "i", "j", "k3", NULL};
  static const char *const bilinear[] = {"type", "i", "j", "k", "gap", NULL};
  if (list->type != YAML_SEQUENCE_NODE)
    return fail(c, list, VI_ERR_PARSE, "springs", "%s",
                "expected a list of springs");
  size_t count = (size_t)(list->data.sequence.items.top -
                          list->data.sequence.items.start);
  if (count > 10000)
    return fail(c, list, VI_ERR_LIMIT, "springs", "%s", "more than 10000");
  s->springs = calloc(count ? count : 1, sizeof *s->springs);
  if (!s->springs)
    return fail(c, list, VI_ERR_NOMEM, "springs", "%s", "out of memory");
  for (size_t k = 0; k < count; k++) {
    yaml_node_t *sp = node(c, list->data.sequence.items.start[k]);
    char path[64], key[128];
    snprintf(path, sizeof path, "springs[%zu]", k + 1);
    yaml_node_t *ty = find(c, sp, "type");
    const char *tname = ty && ty->type == YAML_SCALAR_NODE
                            ? (const char *)ty->data.scalar.value : "";
    int bil = !strcmp(tname, "bilinear");
    if (!bil && strcmp(tname, "cubic") != 0) {
      join(key, path, "type");
      return fail(c, ty ? ty : sp, VI_ERR_PARSE, key, "%s",
                  "expected type: cubic or bilinear");
    }
    int st = check_map(c, sp, path, bil ? bilinear : cubic);
    if (st) return st;
    vi_scene_spring *q = &s->springs[k];
    q->type = bil ? VI_SPRING_BILINEAR : VI_SPRING_CUBIC;
    q->line = LINE(sp);
    yaml_node_t *i = find(c, sp, "i"), *j = find(c, sp, "j");
    yaml_node_t *kk = find(c, sp, bil ? "k" : "k3"), *gap = find(c, sp, "gap");
    join(key, path, "i");
    if (!i) return fail(c, sp, VI_ERR_PARSE, key, "%s", "missing coordinate i");
    if ((st = integer(c, i, key, 1, s->n, &q->i))) return st;
    join(key, path, "j");
    if (j && (st = integer(c, j, key, 0, s->n, &q->j))) return st;
    if (q->i == q->j)
      return fail(c, j, VI_ERR_PARSE, key, "%s", "a spring needs i != j");
    join(key, path, bil ? "k" : "k3");
    if (!kk) return fail(c, sp, VI_ERR_PARSE, key, "%s", "missing stiffness");
    if ((st = number(c, kk, key, &q->k))) return st;
    if (bil) {
      join(key, path, "gap");
      if (!gap) return fail(c, sp, VI_ERR_PARSE, key, "%s", "missing gap");
      if ((st = number(c, gap, key, &q->gap))) return st;
      if (q->k < 0) {
        join(key, path, "k"); /* the key of the value refused */
        return fail(c, kk, VI_ERR_PARSE, key, "%s",
                    "a soft stop's stiffness must be >= 0");
      }
    }
  }
  s->nsprings = (int)count;
  return VI_OK;
}

static int parse_run(ctx *c, vi_scene *s, yaml_node_t *root)
{
  static const char *const ik[] = {"t0", "x", "v", NULL};
  static const char *const rk[] = {"t_end", "periods", "rtol",
                                   "atol",  "method",  "impact_resolution",
                                   NULL};
  static const char *const ok[] = {"impacts", "samples_per_period", "ledger",
                                   "modes",   "compress", "shapes",  NULL};
  yaml_node_t *in = find(c, root, "initial"), *run = find(c, root, "run"),
              *out = find(c, root, "output"), *v;
  int st;
  if (in) {
    s->line_initial = LINE(in);
    if ((st = check_map(c, in, "initial", ik)) ||
        (st = opt_number(c, in, "initial", "t0", &s->t0)) ||
        (st = opt_state(c, in, "x", s->n, s->x0)) ||
        (st = opt_state(c, in, "v", s->n, s->v0)))
      return st;
  }
  if (run) {
    s->line_run = LINE(run);
    if ((st = check_map(c, run, "run", rk))) return st;
    yaml_node_t *te = find(c, run, "t_end"), *pe = find(c, run, "periods");
    if (te && pe)
      return fail(c, pe, VI_ERR_PARSE, "run.periods", "%s",
                  "give t_end or periods, not both");
    if (te && (st = number(c, te, "run.t_end", &s->t_end))) return st;
    if (pe) {
      if ((st = number(c, pe, "run.periods", &s->periods))) return st;
      if (!(s->periods > 0))
        return fail(c, pe, VI_ERR_TIME, "run.periods", "%s", "must be > 0");
      s->t_end = 0.0;
    }
    if (te && !(s->t_end > s->t0))
      return fail(c, te, VI_ERR_TIME, "run.t_end", "%s",
                  "must be after initial.t0");
    if ((v = find(c, run, "rtol"))) {
      if ((st = number(c, v, "run.rtol", &s->rtol))) return st;
      if ((st = in_range(c, v, "run.rtol", s->rtol, VI_SCENE_RTOL_MIN,
                         VI_SCENE_RTOL_MAX, VI_ERR_TOLERANCE)))
        return st;
    }
    if ((v = find(c, run, "atol"))) {
      if ((st = number(c, v, "run.atol", &s->atol))) return st;
      if (!(s->atol > 0))
        return fail(c, v, VI_ERR_TOLERANCE, "run.atol", "%s", "must be > 0");
    }
    if ((v = find(c, run, "impact_resolution"))) {
      if ((st = number(c, v, "run.impact_resolution", &s->impact_resolution)))
        return st;
      if ((st = in_range(c, v, "run.impact_resolution", s->impact_resolution,
                         0.0, 0.5, VI_ERR_ARG)))
        return st;
    }
    if ((v = find(c, run, "method"))) {
      const char *m =
          v->type == YAML_SCALAR_NODE ? (const char *)v->data.scalar.value : "";
      if ((s->method = vi_method_from_name(m)) < 0) {
        char list[160] = "expected one of";
        for (int k = 0; vi_method_name(k); k++)
          snprintf(list + strlen(list), sizeof list - strlen(list), "%s %s",
                   k ? "," : "", vi_method_name(k));
        return fail(c, v, VI_ERR_PARSE, "run.method", "%s", list);
      }
    }
  }
  if (!(s->t_end > 0) && !(s->periods > 0) && !(s->omega > 0))
    return fail(c, run ? run : root, VI_ERR_TIME, "run.t_end", "%s",
                "without a forcing frequency give run.t_end");
  if (out) {
    if ((st = check_map(c, out, "output", ok)) ||
        (st = opt_flag(c, out, "output", "impacts", VI_SCENE_OUT_IMPACTS,
                       &s->outputs)) ||
        (st = opt_flag(c, out, "output", "ledger", VI_SCENE_OUT_LEDGER,
                       &s->outputs)) ||
        (st = opt_flag(c, out, "output", "modes", VI_SCENE_OUT_MODES,
                       &s->outputs)) ||
        (st = opt_flag(c, out, "output", "compress", VI_SCENE_OUT_COMPRESS,
                       &s->outputs)) ||
        (st = opt_flag(c, out, "output", "shapes", VI_SCENE_OUT_SHAPES,
                       &s->outputs)))
      return st;
    if ((s->outputs & VI_SCENE_OUT_SHAPES) && s->kind != VI_SCENE_FE)
      return fail(c, find(c, out, "shapes"), VI_ERR_PARSE, "output.shapes",
                  "%s", "the shapes of a model.matrices: other models "
                  "write theirs in /modal (output.modes)");
    if ((v = find(c, out, "samples_per_period")) &&
        (st = integer(c, v, "output.samples_per_period", 0, 1000000,
                      &s->samples)))
      return st;
    /* without a forcing frequency a "period" is 1/100 of the run (as the
     * program's progress and sampling take it): a transient is sampled */
  }
  return VI_OK;
}

/* The scene's 7 vectors of n (a, b, f0, w, x0, v0 and a spare) within the
 * caller's memory budget, checked before they are allocated: a matrix
 * file's header may claim any n, and a calloc of 7 n doubles that fails
 * under a memory limit said "out of memory" instead of naming the budget
 * (issue 29).  The whole model's estimate is checked after the parse
 * (vi_scene_check_memory); this is the part the parse itself needs. */
static int vectors_fit(ctx *c, vi_scene *s, yaml_node_t *mod)
{
  if (!c->max_memory) return VI_OK;
  double lim = *c->max_memory, need = 56.0 * s->n;
  int from_machine = !(lim > 0);
  if (from_machine) lim = vi_scene_memory_available();
  if (!(lim > 0) || need <= lim) return VI_OK; /* unknown, or it fits */
  char why[224];
  snprintf(why, sizeof why, "the scene's vectors of %d dofs alone would "
           "need %.3g MB (the model more), more than the %.3g MB %s "
           "(--max-memory raises the limit)", s->n, need / 1048576.0,
           lim / 1048576.0, from_machine ? "available to this process"
                                         : "allowed");
  const char *key = vi_scene_size_key(s);
  char val[32];
  snprintf(val, sizeof val, "%d", s->n);
  return vi_diag_set(c->d, c->file, VI_ERR_LIMIT, LINE(mod), 1, key, val,
                     "%s", why);
}

static int parse_root(ctx *c, vi_scene *s)
{
  static const char *const keys[] = {"name",    "model", "forcing", "stop",
                                     "initial", "run",   "output",  "springs",
                                     "stops",   NULL};
  yaml_node_t *root = yaml_document_get_root_node(&c->doc);
  if (!root)
    return vi_diag_set(c->d, c->file, VI_ERR_PARSE, 1, 1, "", "", "%s",
                       "empty scene");
  int st = check_map(c, root, "", keys);
  if (st) return st;
  yaml_node_t *v;
  if ((v = find(c, root, "name"))) {
    if (v->type != YAML_SCALAR_NODE)
      return fail(c, v, VI_ERR_PARSE, "name", "%s", "expected one line of text");
    if (v->data.scalar.length > 256 ||
        strlen((const char *)v->data.scalar.value) != v->data.scalar.length)
      return fail(c, v, VI_ERR_LIMIT, "name", "%s",
                  "at most 256 characters, no NUL");
    s->name = strdup((const char *)v->data.scalar.value);
    if (!s->name) return fail(c, v, VI_ERR_NOMEM, "name", "%s", "out of memory");
  }
  yaml_node_t *mod = find(c, root, "model"), *stop = find(c, root, "stop");
  yaml_node_t *stops = find(c, root, "stops");
  if (!mod)
    return fail(c, root, VI_ERR_PARSE, "model", "%s", "missing section");
  if (stop && stops)
    return fail(c, stops, VI_ERR_PARSE, "stops", "%s",
                "give stop or stops, not both");
  if (!stop && !stops)
    return fail(c, root, VI_ERR_PARSE, "stop", "%s", "missing section");
  if ((st = parse_model(c, s, mod))) return st;
  if ((st = vectors_fit(c, s, mod))) return st;
  s->a = alloc_n(s, 7);
  if (!s->a) {
    char why[160]; /* a file header's n, say, that no machine could hold */
    snprintf(why, sizeof why, "out of memory for the scene's vectors of "
             "%d dofs (%.3g MB)", s->n, 56.0 * s->n / 1048576.0);
    return fail(c, mod, VI_ERR_NOMEM, "model", "%s", why);
  }
  s->b = s->a + s->n;
  s->f0 = s->b + s->n;
  s->w = s->f0 + s->n;
  s->x0 = s->w + s->n;
  s->v0 = s->x0 + s->n;
  if ((v = find(c, root, "forcing")) && (st = parse_forcing(c, s, v)))
    return st;
  if ((st = stop ? parse_stop(c, s, stop) : parse_stops(c, s, stops)))
    return st;
  if ((v = find(c, root, "springs")) && (st = parse_springs(c, s, v)))
    return st;
  return parse_run(c, s, root);
}

/* ---- reading YAML ----------------------------------------------------------
 * Our own composer over libyaml's events instead of yaml_parser_load: it
 * stops at the nesting limit as soon as it is crossed (the scanner's work
 * per token grows with the depth, so a deep file would cost quadratic
 * time), rejects a second document, keeps whether a scalar was plain,
 * quoted or tagged (libyaml's loader tags all three alike) and resolves an
 * alias only to a node that is complete (no cycles). */
typedef struct anchor {
  char *name;
  int id;
} anchor;

typedef struct level {
  int id, key;       /* node, and a mapping's pending key (0: none) */
  char *anchor;      /* anchor of this collection, registered at its end */
} level;

static int syntax(ctx *c, yaml_parser_t *p)
{
  return vi_diag_set(c->d, c->file, VI_ERR_PARSE,
                     (int)p->problem_mark.line + 1,
                     (int)p->problem_mark.column + 1, "", "",
                     "YAML syntax: %s%s%s",
                     p->problem ? p->problem : "error", p->context ? " " : "",
                     p->context ? p->context : "");
}

static int ev_fail(ctx *c, const yaml_event_t *e, int code, const char *msg)
{
  return vi_diag_set(c->d, c->file, code, (int)e->start_mark.line + 1,
                     (int)e->start_mark.column + 1, "", "", "%s", msg);
}

static int attach(ctx *c, level *top, int id)
{
  yaml_node_t *parent = node(c, top->id);
  if (parent->type == YAML_SEQUENCE_NODE)
    return yaml_document_append_sequence_item(&c->doc, top->id, id);
  if (!top->key) {
    top->key = id;
    return 1;
  }
  int ok = yaml_document_append_mapping_pair(&c->doc, top->id, top->key, id);
  top->key = 0;
  return ok;
}

static int add_anchor(anchor **list, int *count, int *cap, char *name, int id)
{
  if (*count == *cap) {
    int nc = *cap ? 2 * *cap : 16;
    anchor *nl = realloc(*list, sizeof(anchor) * (size_t)nc);
    if (!nl) return 0;
    *list = nl;
    *cap = nc;
  }
  (*list)[*count].name = name;
  (*list)[*count].id = id;
  (*count)++;
  return 1;
}

static int compose(ctx *c, const char *text, size_t len, int max_depth)
{
  yaml_parser_t p;
  yaml_event_t e;
  level *stack = calloc((size_t)max_depth + 1, sizeof(level));
  anchor *anchors = NULL;
  int depth = 0, docs = 0, nanch = 0, canch = 0, st = VI_OK, done = 0,
      have_doc = 0;
  if (!stack)
    return vi_diag_nomem(c->d, c->file);
  yaml_parser_initialize(&p);
  yaml_parser_set_input_string(&p, (const unsigned char *)text, len);
  while (!done && st == VI_OK) {
    if (!yaml_parser_parse(&p, &e)) {
      st = syntax(c, &p);
      break;
    }
    int id = 0, nest = 0;
    char *anc = NULL;
    switch (e.type) {
    case YAML_STREAM_END_EVENT: done = 1; break;
    case YAML_DOCUMENT_START_EVENT:
      if (++docs > 1) {
        st = ev_fail(c, &e, VI_ERR_PARSE,
                     "a second YAML document: a scene is one document");
        break;
      }
      if (!yaml_document_initialize(&c->doc, NULL, NULL, NULL, 1, 1))
        st = ev_fail(c, &e, VI_ERR_NOMEM, "out of memory");
      else
        have_doc = 1;
      break;
    case YAML_SCALAR_EVENT: {
      const char *tag =
          e.data.scalar.tag ? (const char *)e.data.scalar.tag
          : e.data.scalar.style == YAML_PLAIN_SCALAR_STYLE ? TAG_PLAIN
                                                            : TAG_QUOTED;
      id = yaml_document_add_scalar(&c->doc, (yaml_char_t *)tag,
                                    e.data.scalar.value,
                                    (int)e.data.scalar.length,
                                    e.data.scalar.style);
      anc = (char *)e.data.scalar.anchor;
      break;
    }
    case YAML_SEQUENCE_START_EVENT:
    case YAML_MAPPING_START_EVENT:
      if (depth >= max_depth) {
        st = vi_diag_too_deep(c->d, c->file, (int)e.start_mark.line + 1,
                              (int)e.start_mark.column + 1, max_depth);
        break;
      }
      id = e.type == YAML_SEQUENCE_START_EVENT
               ? yaml_document_add_sequence(&c->doc, NULL,
                                            e.data.sequence_start.style)
               : yaml_document_add_mapping(&c->doc, NULL,
                                           e.data.mapping_start.style);
      anc = (char *)(e.type == YAML_SEQUENCE_START_EVENT
                         ? e.data.sequence_start.anchor
                         : e.data.mapping_start.anchor);
      nest = 1;
      break;
    case YAML_SEQUENCE_END_EVENT:
    case YAML_MAPPING_END_EVENT:
      if (depth < 1) break;
      depth--;
      if (stack[depth].anchor) {
        if (!add_anchor(&anchors, &nanch, &canch, stack[depth].anchor,
                        stack[depth].id))
          st = ev_fail(c, &e, VI_ERR_NOMEM, "out of memory");
        else
          stack[depth].anchor = NULL;
      }
      break;
    case YAML_ALIAS_EVENT: {
      const char *nm = (const char *)e.data.alias.anchor;
      for (int k = nanch - 1; k >= 0 && !id; k--)
        if (!strcmp(anchors[k].name, nm)) id = anchors[k].id;
      if (!id) st = ev_fail(c, &e, VI_ERR_PARSE, "alias to an unknown anchor");
      break;
    }
    default: break;
    }
    if (st == VI_OK && id) {
      yaml_node_t *nd = node(c, id);
      if (e.type != YAML_ALIAS_EVENT) {
        nd->start_mark = e.start_mark;
        nd->end_mark = e.end_mark;
      }
      if (depth > 0 && !attach(c, &stack[depth - 1], id))
        st = ev_fail(c, &e, VI_ERR_NOMEM, "out of memory");
      if (anc && st == VI_OK) {
        char *cp = strdup(anc);
        if (!cp)
          st = ev_fail(c, &e, VI_ERR_NOMEM, "out of memory");
        else if (nest)
          stack[depth].anchor = cp; /* usable once the collection is done */
        else if (!add_anchor(&anchors, &nanch, &canch, cp, id)) {
          free(cp);
          st = ev_fail(c, &e, VI_ERR_NOMEM, "out of memory");
        }
      }
      if (nest && st == VI_OK) {
        stack[depth].id = id;
        stack[depth].key = 0;
        depth++;
      }
    } else if (st == VI_OK && !id &&
               (e.type == YAML_SCALAR_EVENT ||
                e.type == YAML_SEQUENCE_START_EVENT ||
                e.type == YAML_MAPPING_START_EVENT))
      st = ev_fail(c, &e, VI_ERR_NOMEM, "out of memory");
    yaml_event_delete(&e);
  }
  yaml_parser_delete(&p);
  for (int k = 0; k <= max_depth; k++) free(stack[k].anchor);
  free(stack);
  for (int k = 0; k < nanch; k++) free(anchors[k].name);
  free(anchors);
  if (!have_doc && st == VI_OK) {
    /* an empty stream: an empty document, reported by parse_root */
    if (!yaml_document_initialize(&c->doc, NULL, NULL, NULL, 1, 1))
      return vi_diag_nomem(c->d, c->file);
    have_doc = 1;
  }
  if (st && have_doc) yaml_document_delete(&c->doc);
  return st;
}
/* The run options' defaults, before the YAML is read (their getters and
 * overrides: vi_scene_options.c). */
static void options_init(vi_scene *s)
{
  s->rtol = 1e-8;
  s->atol = 1e-10;
  s->impact_resolution = 1e-5;
  s->method = VI_METHOD_AUTO;
  s->outputs = VI_SCENE_OUT_IMPACTS | VI_SCENE_OUT_COMPRESS;
}

/* After a successful parse: t_end from run.periods (default 100 periods)
 * when run.t_end was not given. */
static void options_finish(vi_scene *s)
{
  if (s->periods > 0 || !(s->t_end > 0))
    s->t_end = s->t0 + vi_periods_time(s->periods > 0 ? s->periods : 100.0,
                                       s->omega);
}


int vi_scene_parse_limited(const char *text, int64_t len, const char *name,
                           int max_depth, vi_scene **out, vi_diag *d)
{
  return vi_scene_parse_within(text, len, name, max_depth, NULL, out, d);
}

int vi_scene_parse_within(const char *text, int64_t len, const char *name,
                          int max_depth, const double *max_memory,
                          vi_scene **out, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (out) *out = NULL;
  if (!out || !text)
    return vi_diag_set(d, name, VI_ERR_ARG, 0, 0, "", "", "%s",
                       "vi_scene_parse: text and out are required");
  if (len < 0) len = (long)strlen(text);
  if (max_depth <= 0) max_depth = VI_SCENE_MAX_DEPTH;
  vi_scene *s = calloc(1, sizeof *s);
  if (!s) return vi_diag_nomem(d, name);
  s->text = malloc((size_t)len + 1);
  s->file = strdup(name ? name : "<input>");
  if (!s->text || !s->file) {
    vi_scene_destroy(&s);
    return vi_diag_nomem(d, name);
  }
  memcpy(s->text, text, (size_t)len);
  s->text[len] = '\0';
  options_init(s);
  ctx c = {.d = d, .file = s->file, .max_memory = max_memory};
  int st = compose(&c, s->text, (size_t)len, max_depth);
  if (st) {
    vi_scene_destroy(&s);
    return st;
  }
  st = parse_root(&c, s);
  yaml_document_delete(&c.doc);
  if (!st && !s->name && !(s->name = strdup(s->file)))
    st = vi_diag_nomem(d, s->file);
  if (st) {
    vi_scene_destroy(&s);
    return st;
  }
  options_finish(s);
  if (s->kind == VI_SCENE_FE) {
    s->fe.at_rest = 1;
    /* only a scene with an initial section can leave rest: a Matrix
     * Market header of 3e8 dofs read 2 n zeros here, 6 s before the
     * memory check refused it (issue 29) */
    for (int i = 0; s->line_initial && i < s->n; i++)
      if (s->x0[i] != 0 || s->v0[i] != 0) s->fe.at_rest = 0;
  }
  *out = s;
  return VI_OK;
}

int vi_scene_parse(const char *text, int64_t len, const char *name, vi_scene **out,
                   vi_diag *d)
{
  return vi_scene_parse_limited(text, len, name, 0, out, d);
}

/* vi_scene_load_limited and vi_scene_load_within: max_memory as in
 * vi_scene_parse_within. */
static int load(const char *path, int64_t max_bytes, int max_depth,
                const double *max_memory, vi_scene **out, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (out) *out = NULL;
  if (!path || !out)
    return vi_diag_set(d, path, VI_ERR_ARG, 0, 0, "", "", "%s",
                       "vi_scene_load: path and out are required");
  if (max_memory && isnan(*max_memory))
    return vi_diag_set(d, path, VI_ERR_ARG, 0, 0, "max_memory", "nan", "%s",
                       "the memory limit is not a number");
  if (max_bytes <= 0) max_bytes = VI_SCENE_MAX_BYTES;
  if (max_bytes > LONG_MAX - 1) max_bytes = LONG_MAX - 1;
  FILE *f = fopen(path, "rb");
  if (!f)
    return vi_diag_set(d, path, VI_ERR_IO, 0, 0, "", "", "cannot open: %s",
                       strerror(errno));
  char *buf = NULL;
  long len = 0, cap = 0;
  size_t got;
  char chunk[8192];
  /* read at most max_bytes + 1: a larger file (or /dev/zero) is refused
   * without reading it all */
  while ((got = fread(chunk, 1, sizeof chunk, f)) > 0) {
    if (len + (long)got > max_bytes) {
      free(buf);
      fclose(f);
      return vi_diag_set(d, path, VI_ERR_LIMIT, 0, 0, "", "",
                         "the scene is larger than %lld bytes (the limit; "
                         "--max-scene-size raises it)", (long long)max_bytes);
    }
    if (len + (long)got > cap) {
      cap = 2 * (len + (long)got);
      if (cap > max_bytes + 1) cap = (long)max_bytes + 1;
      char *nb = realloc(buf, (size_t)cap);
      if (!nb) {
        free(buf);
        fclose(f);
        return vi_diag_nomem(d, path);
      }
      buf = nb;
    }
    memcpy(buf + len, chunk, got);
    len += (long)got;
  }
  int bad = ferror(f);
  int e = errno;
  fclose(f);
  if (bad) {
    free(buf);
    return vi_diag_set(d, path, VI_ERR_IO, 0, 0, "", "", "cannot read: %s",
                       strerror(e));
  }
  int st = vi_scene_parse_within(buf ? buf : "", len, path, max_depth,
                                  max_memory, out, d);
  free(buf);
  return st;
}

int vi_scene_load_limited(const char *path, int64_t max_bytes, int max_depth,
                          vi_scene **out, vi_diag *d)
{
  return load(path, max_bytes, max_depth, NULL, out, d);
}

int vi_scene_load_within(const char *path, int64_t max_bytes, int max_depth,
                         double max_memory, vi_scene **out, vi_diag *d)
{
  return load(path, max_bytes, max_depth, &max_memory, out, d);
}

int vi_scene_load(const char *path, vi_scene **out, vi_diag *d)
{
  return vi_scene_load_limited(path, 0, 0, out, d);
}

void vi_scene_destroy(vi_scene **scene)
{
  if (!scene || !*scene) return;
  vi_scene *s = *scene;
  free(s->name);
  free(s->text);
  free(s->file);
  free(s->M);
  free(s->cm);
  free(s->a);
  free(s->springs);
  free(s->xw);
  free(s->xint);
  for (int k = 0; k < 3; k++) free(s->fe.path[k]);
  vi_dofmap_destroy(&s->fe.map);
  free(s->fe.zeta);
  free(s->fe.q0);
  if (s->fe.report) free(s->fe.report->mresid);
  free(s->fe.report);
  free(s);
  *scene = NULL;
}

/* ---- the description's own getters -------------------------------------- */
const char *vi_scene_name(const vi_scene *s) { return s ? s->name : ""; }
const char *vi_scene_text(const vi_scene *s) { return s ? s->text : ""; }
int vi_scene_model_n(const vi_scene *s)
{
  return s->kind == VI_SCENE_FE ? s->fe.modes : s->n;
}
int vi_scene_n(const vi_scene *s) { return s ? vi_scene_model_n(s) : 0; }
int vi_scene_dofs(const vi_scene *s) { return s ? s->n : 0; }

int vi_scene_fe_summary(const vi_scene *s, int *modes, int *rule,
                        int *massless, int *rigid, double *max_residual,
                        double *orthogonality)
{
  const struct vi_scene_fe_report *r =
      s && s->kind == VI_SCENE_FE ? s->fe.report : NULL;
  int ok = r && r->done;
  if (modes) *modes = ok ? r->modes : 0;
  if (rule) *rule = ok ? r->rule : 0;
  if (massless) *massless = ok ? r->massless : 0;
  if (rigid) *rigid = ok ? r->rigid : 0;
  if (max_residual) *max_residual = ok ? r->resid : NAN;
  if (orthogonality) *orthogonality = ok ? r->orth : NAN;
  if (!s) return VI_ERR_ARG;
  if (s->kind != VI_SCENE_FE) return VI_ERR_UNSUPPORTED;
  return ok ? VI_OK : VI_ERR_STATE;
}
