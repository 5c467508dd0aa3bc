/* vi_scene.c - scene files read with libyaml's document API.  Only this file
 * knows YAML; it does no numerics beyond assembling the model's matrices. */
#include <errno.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <yaml.h>

#include "vibroimpact.h"
#include "vibroimpact/vi_scene.h"

enum { MODEL_EXPLICIT, MODEL_CHAIN, MODEL_CANTILEVER };

struct vi_scene {
  char *name, *text, *file;
  int n, kind;
  double *M, *C, *K;            /* explicit matrices [n*n], or NULL */
  double *cm, *ck, *cc;         /* chain parameters [n] */
  double omega1, zeta, xi_stop; /* cantilever */
  int has_rayleigh;
  double ra, rb;
  double omega, base;
  int has_base;
  double *a, *b, *f0, *w, *x0, *v0;
  int has_w;
  double xs, r, t0, t_end, periods, rtol, atol;
  int method, samples, out_impacts, out_ledger, out_modes, compress;
  int line_model, line_stop, line_initial, line_run, line_forcing;
  /* built-in nonlinear springs (vi_force.h), applied to the sim */
  struct scene_spring {
    int type, i, j, line;
    double k, gap;
  } *springs;
  int nsprings;
  /* stops: the first is w, xs, r above; the others here: xw [n x nx],
   * xxs, xr [nx]; xint [2 nx]: has_w, then the entry's line */
  int nx, stop_list;
  double *xw, *xxs, *xr;
  int *xint;
};

/* ---- diagnostics -------------------------------------------------------- */
typedef struct ctx {
  yaml_document_t doc;
  vi_diag *d;
  const char *file;
} ctx;

static int diag(vi_diag *d, const char *file, int code, int line, int col,
                const char *key, const char *value, const char *fmt, ...)
    __attribute__((format(printf, 8, 9)));

static int diag(vi_diag *d, const char *file, int code, int line, int col,
                const char *key, const char *value, const char *fmt, ...)
{
  if (!d) return code;
  memset(d, 0, sizeof *d);
  d->code = code;
  d->line = line;
  d->column = col;
  snprintf(d->file, sizeof d->file, "%s", file ? file : "");
  snprintf(d->key, sizeof d->key, "%s", key ? key : "");
  snprintf(d->value, sizeof d->value, "%s", value ? value : "");
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(d->message, sizeof d->message, fmt, ap);
  va_end(ap);
  return code;
}

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
  return diag(c->d, c->file, code, nd ? LINE(nd) : 0, nd ? COL(nd) : 0, key,
              val, fmt, detail);
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
      return diag(c->d, c->file, VI_ERR_PARSE, LINE(k), COL(k), full, ks,
                  "unknown key (allowed here: %s)", list);
    }
    for (yaml_node_pair_t *q = map->data.mapping.pairs.start; q < p; q++)
      if (!strcmp((const char *)node(c, q->key)->data.scalar.value, ks))
        return diag(c->d, c->file, VI_ERR_PARSE, LINE(k), COL(k), full, ks,
                    "%s", "key given twice");
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
  if (end == s || *end || errno == ERANGE)
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

/* Optional keys of a section: an absent key leaves *out at its default. */
static int opt_number(ctx *c, yaml_node_t *map, const char *path,
                      const char *key, double *out)
{
  char full[128];
  yaml_node_t *v = find(c, map, key);
  join(full, path, key);
  return v ? number(c, v, full, out) : VI_OK;
}

static int opt_vector(ctx *c, yaml_node_t *map, const char *path,
                      const char *key, int n, double *out)
{
  char full[128];
  yaml_node_t *v = find(c, map, key);
  join(full, path, key);
  return v ? vector(c, v, full, n, 0, out) : VI_OK;
}

static int opt_boolean(ctx *c, yaml_node_t *map, const char *path,
                       const char *key, int *out)
{
  char full[128];
  yaml_node_t *v = find(c, map, key);
  join(full, path, key);
  return v ? boolean(c, v, full, out) : VI_OK;
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

static int parse_model(ctx *c, vi_scene *s, yaml_node_t *mod)
{
  static const char *const keys[] = {"M",          "C",        "K", "chain",
                                     "cantilever", "rayleigh", NULL};
  int st = check_map(c, mod, "model", keys);
  if (st) return st;
  s->line_model = LINE(mod);
  yaml_node_t *K = find(c, mod, "K"), *ch = find(c, mod, "chain"),
              *ca = find(c, mod, "cantilever");
  if ((K != NULL) + (ch != NULL) + (ca != NULL) != 1)
    return fail(c, mod, VI_ERR_PARSE, "model", "%s",
                "give exactly one of K (with M, C), chain or cantilever");
  if (K) {
    s->kind = MODEL_EXPLICIT;
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
    s->kind = MODEL_CHAIN;
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
    s->kind = MODEL_CANTILEVER;
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
    if (!(s->omega1 > 0) || s->zeta < 0 || s->xi_stop < 0 || s->xi_stop > 1)
      return fail(c, ca, VI_ERR_ARG, "model.cantilever", "%s",
                  "need omega1 > 0, zeta >= 0, 0 <= xi_stop <= 1");
  }
  yaml_node_t *ra = find(c, mod, "rayleigh");
  if (ra) {
    static const char *const rk[] = {"alpha", "beta", NULL};
    if ((st = check_map(c, ra, "model.rayleigh", rk))) return st;
    if (find(c, mod, "C") || (ch && find(c, ch, "c")) ||
        (ca && find(c, ca, "zeta")))
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
    double A;
    if (find(c, f, "a"))
      return fail(c, on, VI_ERR_PARSE, "forcing.on", "%s",
                  "give 'a' or 'on', not both");
    if ((st = number(c, amp, "forcing.amplitude", &A))) return st;
    if (on->type != YAML_SEQUENCE_NODE)
      return fail(c, on, VI_ERR_PARSE, "forcing.on", "%s",
                  "expected a list of mass indices");
    for (yaml_node_item_t *it = on->data.sequence.items.start;
         it < on->data.sequence.items.top; it++) {
      int j;
      if ((st = integer(c, node(c, *it), "forcing.on", 1, s->n, &j))) return st;
      s->a[j - 1] = A;
    }
  }
  if (base) {
    if (s->kind != MODEL_CANTILEVER)
      return fail(c, base, VI_ERR_PARSE, "forcing.base", "%s",
                  "base excitation needs a cantilever model");
    if ((st = number(c, base, "forcing.base", &s->base))) return st;
    s->has_base = 1;
  }
  return VI_OK;
}

/* One stop {w: [...] | mass: j, xs, r} at `path` ("stop", "stops[2]")
 * into w [n] (zeroed), *has_w, *xs, *r. */
static int parse_stop_at(ctx *c, vi_scene *s, yaml_node_t *sp,
                         const char *path, double *w, int *has_w, double *xs,
                         double *r)
{
  static const char *const keys[] = {"w", "mass", "xs", "r", NULL};
  char key[128];
  int st = check_map(c, sp, path, keys);
  if (st) return st;
  yaml_node_t *wn = find(c, sp, "w"), *mass = find(c, sp, "mass");
  join(key, path, "mass");
  if (wn && mass)
    return fail(c, mass, VI_ERR_PARSE, key, "%s", "give w or mass, not both");
  if (wn) {
    join(key, path, "w");
    if ((st = vector(c, wn, key, s->n, 0, w))) return st;
    *has_w = 1;
  }
  if (mass) {
    int j;
    if ((st = integer(c, mass, key, 1, s->n, &j))) return st;
    w[j - 1] = 1.0;
    *has_w = 1;
  }
  if (!*has_w && s->kind != MODEL_CANTILEVER)
    return fail(c, sp, VI_ERR_PARSE, path, "%s", "missing w or mass");
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
    if (!bil && strcmp(tname, "cubic")) {
      join(key, path, "type");
      return fail(c, ty ? ty : sp, VI_ERR_PARSE, key, "%s",
                  "expected type: cubic or bilinear");
    }
    int st = check_map(c, sp, path, bil ? bilinear : cubic);
    if (st) return st;
    struct scene_spring *q = &s->springs[k];
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
      if (q->k < 0)
        return fail(c, kk, VI_ERR_PARSE, key, "%s",
                    "a soft stop's stiffness must be >= 0");
    }
  }
  s->nsprings = (int)count;
  return VI_OK;
}

static int parse_run(ctx *c, vi_scene *s, yaml_node_t *root)
{
  static const char *const ik[] = {"t0", "x", "v", NULL};
  static const char *const rk[] = {"t_end", "periods", "rtol",
                                   "atol",  "method",  NULL};
  static const char *const ok[] = {"impacts", "samples_per_period", "ledger",
                                   "modes",   "compress",           NULL};
  yaml_node_t *in = find(c, root, "initial"), *run = find(c, root, "run"),
              *out = find(c, root, "output"), *v;
  int st;
  if (in) {
    s->line_initial = LINE(in);
    if ((st = check_map(c, in, "initial", ik)) ||
        (st = opt_number(c, in, "initial", "t0", &s->t0)) ||
        (st = opt_vector(c, in, "initial", "x", s->n, s->x0)) ||
        (st = opt_vector(c, in, "initial", "v", s->n, s->v0)))
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
        (st = opt_boolean(c, out, "output", "impacts", &s->out_impacts)) ||
        (st = opt_boolean(c, out, "output", "ledger", &s->out_ledger)) ||
        (st = opt_boolean(c, out, "output", "modes", &s->out_modes)) ||
        (st = opt_boolean(c, out, "output", "compress", &s->compress)))
      return st;
    if ((v = find(c, out, "samples_per_period")) &&
        (st = integer(c, v, "output.samples_per_period", 0, 1000000,
                      &s->samples)))
      return st;
    if (s->samples > 0 && !(s->omega > 0))
      return fail(c, v, VI_ERR_ARG, "output.samples_per_period", "%s",
                  "needs a forcing frequency");
  }
  return VI_OK;
}

static int parse_root(ctx *c, vi_scene *s)
{
  static const char *const keys[] = {"name",    "model", "forcing", "stop",
                                     "initial", "run",   "output",  "springs",
                                     "stops",   NULL};
  yaml_node_t *root = yaml_document_get_root_node(&c->doc);
  if (!root)
    return diag(c->d, c->file, VI_ERR_PARSE, 1, 1, "", "", "empty scene");
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
  s->a = alloc_n(s, 7);
  if (!s->a) return fail(c, root, VI_ERR_NOMEM, "", "%s", "out of memory");
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
  return diag(c->d, c->file, VI_ERR_PARSE, (int)p->problem_mark.line + 1,
              (int)p->problem_mark.column + 1, "", "", "YAML syntax: %s%s%s",
              p->problem ? p->problem : "error", p->context ? " " : "",
              p->context ? p->context : "");
}

static int ev_fail(ctx *c, const yaml_event_t *e, int code, const char *msg)
{
  return diag(c->d, c->file, code, (int)e->start_mark.line + 1,
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
    return diag(c->d, c->file, VI_ERR_NOMEM, 0, 0, "", "", "out of memory");
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
        char msg[160];
        snprintf(msg, sizeof msg, "nesting deeper than %d levels (the limit; "
                 "a scene needs 5)", max_depth);
        st = ev_fail(c, &e, VI_ERR_LIMIT, msg);
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
      return diag(c->d, c->file, VI_ERR_NOMEM, 0, 0, "", "", "out of memory");
    have_doc = 1;
  }
  if (st && have_doc) yaml_document_delete(&c->doc);
  return st;
}

int vi_scene_parse_limited(const char *text, int64_t len, const char *name,
                           int max_depth, vi_scene **out, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (out) *out = NULL;
  if (!out || !text)
    return diag(d, name, VI_ERR_ARG, 0, 0, "", "", "%s",
                "vi_scene_parse: text and out are required");
  if (len < 0) len = (long)strlen(text);
  if (max_depth <= 0) max_depth = VI_SCENE_MAX_DEPTH;
  vi_scene *s = calloc(1, sizeof *s);
  if (!s) return diag(d, name, VI_ERR_NOMEM, 0, 0, "", "", "out of memory");
  s->text = malloc((size_t)len + 1);
  s->file = strdup(name ? name : "<input>");
  if (!s->text || !s->file) {
    vi_scene_destroy(&s);
    return diag(d, name, VI_ERR_NOMEM, 0, 0, "", "", "out of memory");
  }
  memcpy(s->text, text, (size_t)len);
  s->text[len] = '\0';
  s->rtol = 1e-8;
  s->atol = 1e-10;
  s->method = VI_METHOD_AUTO;
  s->out_impacts = 1;
  s->compress = 1;
  ctx c = {.d = d, .file = s->file};
  int st = compose(&c, s->text, (size_t)len, max_depth);
  if (st) {
    vi_scene_destroy(&s);
    return st;
  }
  st = parse_root(&c, s);
  yaml_document_delete(&c.doc);
  if (!st && !s->name && !(s->name = strdup(s->file)))
    st = diag(d, s->file, VI_ERR_NOMEM, 0, 0, "", "", "out of memory");
  if (st) {
    vi_scene_destroy(&s);
    return st;
  }
  if (s->periods > 0 || !(s->t_end > 0))
    s->t_end =
        s->t0 + (s->periods > 0 ? s->periods : 100.0) * 2 * M_PI / s->omega;
  *out = s;
  return VI_OK;
}

int vi_scene_parse(const char *text, int64_t len, const char *name, vi_scene **out,
                   vi_diag *d)
{
  return vi_scene_parse_limited(text, len, name, 0, out, d);
}

int vi_scene_load_limited(const char *path, int64_t max_bytes, int max_depth,
                          vi_scene **out, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (out) *out = NULL;
  if (!path || !out)
    return diag(d, path, VI_ERR_ARG, 0, 0, "", "", "%s",
                "vi_scene_load: path and out are required");
  if (max_bytes <= 0) max_bytes = VI_SCENE_MAX_BYTES;
  if (max_bytes > LONG_MAX - 1) max_bytes = LONG_MAX - 1;
  FILE *f = fopen(path, "rb");
  if (!f)
    return diag(d, path, VI_ERR_IO, 0, 0, "", "", "cannot open: %s",
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
      return diag(d, path, VI_ERR_LIMIT, 0, 0, "", "",
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
        return diag(d, path, VI_ERR_NOMEM, 0, 0, "", "", "out of memory");
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
    return diag(d, path, VI_ERR_IO, 0, 0, "", "", "cannot read: %s",
                strerror(e));
  }
  int st = vi_scene_parse_limited(buf ? buf : "", len, path, max_depth, out, d);
  free(buf);
  return st;
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
  free(s);
  *scene = NULL;
}

/* ---- ranges that need the model's frequencies ---------------------------
 * Scales: omega_hi, the fastest of the natural frequencies and the forcing;
 * L, a length (the clearance, or the static response to the loads).  The
 * run must be resolvable in double precision and the state within a few
 * orders of magnitude of the problem's own scales. */
static int range_fail(vi_diag *d, const vi_scene *s, int line, const char *key,
                      double v, const char *fmt, double a, double b)
{
  char val[64], msg[256];
  snprintf(val, sizeof val, "%.6g", v);
  snprintf(msg, sizeof msg, fmt, a, b);
  return diag(d, s->file, VI_ERR_LIMIT, line, line ? 1 : 0, key, val, "%s",
              msg);
}

static double maxabs(const double *v, int n)
{
  double m = 0;
  for (int i = 0; i < n; i++) m = fabs(v[i]) > m ? fabs(v[i]) : m;
  return m;
}

static int check_ranges(const vi_scene *s, const vi_model *m, vi_diag *d)
{
  int n = s->n;
  const double *om = vi_model_omega(m), *ze = vi_model_zeta(m),
               *K = vi_model_stiffness(m);
  double wmax = 0, zmax = 0, kmax = 0;
  for (int j = 0; j < n; j++) {
    wmax = om[j] > wmax ? om[j] : wmax;
    zmax = isfinite(ze[j]) && ze[j] > zmax ? ze[j] : zmax;
    kmax = fabs(K[j + (size_t)j * n]) > kmax ? fabs(K[j + (size_t)j * n]) : kmax;
  }
  double W = s->omega > wmax ? s->omega : wmax;
  if (s->omega > 0 && wmax > 0 &&
      (s->omega < VI_SCENE_FREQ_RATIO_MIN * wmax ||
       s->omega > VI_SCENE_FREQ_RATIO_MAX * wmax))
    return range_fail(d, s, s->line_forcing, "forcing.omega", s->omega,
                      "must lie in [%.3g, %.3g]: within 1e-8 .. 1e8 times "
                      "the highest natural frequency",
                      VI_SCENE_FREQ_RATIO_MIN * wmax,
                      VI_SCENE_FREQ_RATIO_MAX * wmax);
  if (zmax > VI_SCENE_ZETA_MAX)
    return range_fail(d, s, s->line_model, "model", zmax,
                      "a modal damping ratio above %.3g (limit; got %.3g): "
                      "the damping is out of proportion to the stiffness",
                      VI_SCENE_ZETA_MAX, zmax);
  /* time: t must resolve the fastest motion: |t| eps omega_hi <= 1e-3 */
  if (W > 0) {
    double tmax = 1e-3 / (DBL_EPSILON * W),
           span = fabs(s->t_end) > fabs(s->t0) ? fabs(s->t_end) : fabs(s->t0);
    const char *key = s->periods > 0 ? "run.periods" : "run.t_end";
    if (span > tmax)
      return range_fail(d, s, s->line_run, key,
                        s->periods > 0 ? s->periods : s->t_end,
                        "the run reaches |t| = %.3g; above %.3g double "
                        "precision no longer resolves the fastest motion",
                        span, tmax);
    if (!(s->t_end - s->t0 >= 1e-9 / W))
      return range_fail(d, s, s->line_run, key,
                        s->periods > 0 ? s->periods : s->t_end,
                        "the run spans %.3g time units, less than %.3g "
                        "(1e-9 of the fastest period)",
                        s->t_end - s->t0, 1e-9 / W);
  }
  /* lengths: the clearance or the static response to the loads */
  double F = 0;
  for (int i = 0; i < n; i++) {
    double f = fabs(s->a[i]) + fabs(s->b[i]) + fabs(s->f0[i]) +
               (s->has_base ? fabs(s->base) : 0);
    F = f > F ? f : F;
  }
  double L = fabs(s->xs), Ls = kmax > 0 ? F / kmax : 0;
  L = Ls > L ? Ls : L;
  double x0 = maxabs(s->x0, n), v0 = maxabs(s->v0, n);
  if (L > 0 && x0 > VI_SCENE_STATE_RATIO * L)
    return range_fail(d, s, s->line_initial, "initial.x", x0,
                      "|x0| above %.3g: 1e8 times the problem's length "
                      "scale %.3g (clearance or static response)",
                      VI_SCENE_STATE_RATIO * L, L);
  if (L > 0 && W > 0 && v0 > VI_SCENE_STATE_RATIO * L * W)
    return range_fail(d, s, s->line_initial, "initial.v", v0,
                      "|v0| above %.3g: 1e8 times the length scale %.3g "
                      "times the highest frequency",
                      VI_SCENE_STATE_RATIO * L * W, L);
  double La = L;
  La = x0 > La ? x0 : La;
  La = W > 0 && v0 / W > La ? v0 / W : La;
  if (La > 0 && s->atol > VI_SCENE_ATOL_RATIO * La)
    return range_fail(d, s, s->line_run, "run.atol", s->atol,
                      "must be at most %.3g: 0.01 of the problem's length "
                      "scale %.3g",
                      VI_SCENE_ATOL_RATIO * La, La);
  if (!(s->atol >= DBL_MIN))
    return range_fail(d, s, s->line_run, "run.atol", s->atol,
                      "must be at least %.3g%.0g", DBL_MIN, 0);
  if (!(s->rtol >= VI_SCENE_RTOL_MIN && s->rtol <= VI_SCENE_RTOL_MAX))
    return range_fail(d, s, s->line_run, "run.rtol", s->rtol,
                      "must lie in [%.3g, %.3g]", VI_SCENE_RTOL_MIN,
                      VI_SCENE_RTOL_MAX);
  return VI_OK;
}

/* Bytes a model of n coordinates and its simulation take, measured on
 * chains (max RSS of `vibroimpact -o` less the empty process: 14 n^2
 * doubles at n = 1000 for adams, bdf and exact alike): about
 * VI_MEM_N2 n^2 + VI_MEM_N n doubles. */
#define VI_MEM_N2 16.0
#define VI_MEM_N 400.0
double vi_scene_memory_estimate(const vi_scene *s)
{
  if (!s) return 0;
  double n = s->n;
  return 8.0 * (VI_MEM_N2 * n * n + VI_MEM_N * n);
}

/* MemAvailable from /proc/meminfo in bytes; 0 when unknown. */
static double mem_available(void)
{
  FILE *f = fopen("/proc/meminfo", "r");
  if (!f) return 0;
  char line[256];
  double kb = 0;
  while (fgets(line, sizeof line, f))
    if (sscanf(line, "MemAvailable: %lf kB", &kb) == 1) break;
  fclose(f);
  return kb * 1024.0;
}

int vi_scene_check_memory(const vi_scene *s, double max_bytes, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (!s) return VI_ERR_ARG;
  int from_machine = !(max_bytes > 0);
  if (from_machine) max_bytes = mem_available();
  if (!(max_bytes > 0)) return VI_OK; /* not known: nothing to compare */
  double need = vi_scene_memory_estimate(s);
  if (need <= max_bytes) return VI_OK;
  const char *key = s->kind == MODEL_CHAIN        ? "model.chain.n"
                    : s->kind == MODEL_CANTILEVER ? "model.cantilever.modes"
                                                  : "model.K";
  char val[32];
  snprintf(val, sizeof val, "%d", s->n);
  return diag(d, s->file, VI_ERR_LIMIT, s->line_model, s->line_model ? 1 : 0,
              key, val,
              "the model would need about %.3g MB, more than the %.3g MB %s "
              "(--max-memory raises the limit)",
              need / 1048576.0, max_bytes / 1048576.0,
              from_machine ? "available on this machine" : "allowed");
}

/* ---- building the model ------------------------------------------------- */
int vi_scene_create_model(const vi_scene *s, vi_model **out, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (out) *out = NULL;
  if (!s || !out)
    return diag(d, s ? s->file : "", VI_ERR_ARG, 0, 0, "", "", "%s",
                "vi_scene_create_model: scene and out are required");
  int n = s->n, st;
  size_t nn = (size_t)n * n;
  double *buf = calloc(3 * nn + 3 * (size_t)n, sizeof(double));
  if (!buf)
    return diag(d, s->file, VI_ERR_NOMEM, 0, 0, "", "", "out of memory");
  double *M = buf, *C = M + nn, *K = C + nn, *w = K + nn, *a = w + n;
  double *tip = a + n; /* a cantilever's tip: the stops that give no w */
  memcpy(w, s->w, sizeof(double) * n);
  memcpy(a, s->a, sizeof(double) * n);
  const char *where = "model";
  if (s->kind == MODEL_EXPLICIT) {
    memcpy(M, s->M, sizeof(double) * 3 * nn);
  } else if (s->kind == MODEL_CHAIN) {
    vi_build_chain(n, s->cm, s->ck, s->cc, M, C, K, n);
  } else {
    double *gamma = malloc(sizeof(double) * n);
    if (!gamma) {
      free(buf);
      return VI_ERR_NOMEM;
    }
    vi_build_cantilever(n, s->omega1, s->zeta, s->xi_stop, M, C, K, n, w,
                        gamma);
    memcpy(tip, w, sizeof(double) * n);
    if (s->has_w)
      memcpy(w, s->w, sizeof(double) * n); /* an explicit stop wins */
    if (s->has_base)
      for (int j = 0; j < n; j++)
        a[j] = s->a[j] - s->base * gamma[j];
    else
      memcpy(a, s->a, sizeof(double) * n);
    free(gamma);
  }
  if (s->has_rayleigh)
    for (size_t i = 0; i < nn; i++)
      C[i] = s->ra * M[i] + s->rb * K[i];
  vi_model *m = NULL;
  st = vi_model_create(n, &m);
  if (!st) {
    where = "model.M";
    st = vi_model_set_mass(m, M, n);
  }
  if (!st) {
    where = "model.K";
    st = vi_model_set_stiffness(m, K, n);
  }
  if (!st) {
    where = "model.C";
    st = vi_model_set_damping(m, C, n);
  }
  if (!st) {
    where = "forcing";
    st = vi_model_set_forcing(m, s->omega, a, s->b, s->f0);
  }
  if (!st) {
    where = s->stop_list ? "stops[1]" : "stop";
    st = vi_model_set_stop(m, w, s->xs, s->r);
  }
  char xkey[32] = "";
  int xline = 0;
  for (int k = 0; k < s->nx && !st; k++) {
    snprintf(xkey, sizeof xkey, "stops[%d]", k + 2);
    where = xkey;
    xline = s->xint[s->nx + k];
    st = vi_model_add_stop(m, s->xint[k] ? s->xw + (size_t)k * n : tip,
                           s->xxs[k], s->xr[k]);
  }
  if (!st) {
    where = "model";
    st = vi_model_setup(m);
  }
  free(buf);
  if (st) {
    int line = where == xkey                 ? xline
               : !strncmp(where, "stop", 4) ? s->line_stop
                                             : s->line_model;
    diag(d, s->file, st, line, line ? 1 : 0, where, "", "%s",
         m ? vi_model_errmsg(m) : vi_strerror(st));
    vi_model_destroy(&m);
    return st;
  }
  if ((st = check_ranges(s, m, d))) {
    vi_model_destroy(&m);
    return st;
  }
  *out = m;
  return VI_OK;
}

int vi_scene_configure_sim(const vi_scene *s, vi_sim *sim, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (!s || !sim)
    return diag(d, s ? s->file : "", VI_ERR_ARG, 0, 0, "", "", "%s",
                "vi_scene_configure_sim: scene and sim are required");
  if (vi_sim_n(sim) != s->n)
    return diag(d, s->file, VI_ERR_DIM, s->line_model, 0, "model", "",
                "the scene has n = %d, the simulation n = %d", s->n,
                vi_sim_n(sim));
  int st = vi_sim_set_method(sim, s->method);
  if (st)
    return diag(d, s->file, st, s->line_run, 1, "run.method", "", "%s",
                vi_sim_errmsg(sim));
  if ((st = vi_sim_set_tolerances(sim, s->rtol, s->atol)))
    return diag(d, s->file, st, s->line_run, 1, "run", "", "%s",
                vi_sim_errmsg(sim));
  if ((st = vi_sim_set_initial(sim, s->t0, s->x0, s->v0)))
    return diag(d, s->file, st, s->line_initial, 1, "initial", "", "%s",
                vi_sim_errmsg(sim));
  vi_sim_clear_springs(sim);
  for (int k = 0; k < s->nsprings; k++) {
    const struct scene_spring *q = &s->springs[k];
    if ((st = vi_sim_add_spring(sim, q->type, q->i, q->j, q->k, q->gap))) {
      char key[32];
      snprintf(key, sizeof key, "springs[%d]", k + 1);
      return diag(d, s->file, st, q->line, 1, key, "", "%s",
                  vi_sim_errmsg(sim));
    }
  }
  return VI_OK;
}

/* ---- getters and overrides ---------------------------------------------- */
const char *vi_scene_name(const vi_scene *s) { return s ? s->name : ""; }
const char *vi_scene_text(const vi_scene *s) { return s ? s->text : ""; }

int vi_scene_n(const vi_scene *s) { return s ? s->n : 0; }
double vi_scene_t0(const vi_scene *s) { return s ? s->t0 : 0.0; }
double vi_scene_t_end(const vi_scene *s) { return s ? s->t_end : 0.0; }
double vi_scene_rtol(const vi_scene *s) { return s ? s->rtol : 0.0; }
double vi_scene_atol(const vi_scene *s) { return s ? s->atol : 0.0; }
int vi_scene_method(const vi_scene *s) { return s ? s->method : 0; }
int vi_scene_samples_per_period(const vi_scene *s)
{
  return s ? s->samples : 0;
}

int vi_scene_wants(const vi_scene *s, const char *what)
{
  if (!s || !what) return 0;
  if (!strcmp(what, "impacts")) return s->out_impacts;
  if (!strcmp(what, "ledger")) return s->out_ledger;
  if (!strcmp(what, "modes")) return s->out_modes;
  if (!strcmp(what, "compress")) return s->compress;
  return 0;
}

int vi_scene_set_run(vi_scene *s, double rtol, double atol, double periods,
                     int method)
{
  if (!s || isnan(rtol) || isnan(atol) || isnan(periods) ||
      !(periods < INFINITY) || (method >= 0 && !vi_method_name(method)))
    return VI_ERR_ARG;
  if (rtol > 0 && !(rtol >= VI_SCENE_RTOL_MIN && rtol <= VI_SCENE_RTOL_MAX))
    return VI_ERR_TOLERANCE;
  if (atol > 0 && !(atol < INFINITY)) return VI_ERR_TOLERANCE;
  if (rtol > 0) s->rtol = rtol;
  if (atol > 0) s->atol = atol;
  if (method >= 0) s->method = method;
  if (periods > 0) {
    if (!(s->omega > 0)) return VI_ERR_FREQUENCY;
    s->periods = periods;
    s->t_end = s->t0 + periods * 2 * M_PI / s->omega;
  }
  return VI_OK;
}
