/* vi_scene.c - scene files read with libyaml's document API.  Only this file
 * knows YAML; it does no numerics beyond assembling the model's matrices. */
#include <errno.h>
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
  int line_model, line_stop, line_initial, line_run;
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

static int number(ctx *c, yaml_node_t *nd, const char *key, double *out)
{
  if (!nd || nd->type != YAML_SCALAR_NODE)
    return fail(c, nd, VI_ERR_PARSE, key, "%s", "expected a number");
  const char *s = (const char *)nd->data.scalar.value;
  char *end;
  errno = 0;
  double v = strtod(s, &end);
  if (end == s || *end || errno == ERANGE)
    return fail(c, nd, VI_ERR_PARSE, key, "%s", "expected a number");
  if (!isfinite(v))
    return fail(c, nd, VI_ERR_NONFINITE, key, "%s", "must be finite");
  *out = v;
  return VI_OK;
}

static int integer(ctx *c, yaml_node_t *nd, const char *key, int lo, int hi,
                   int *out)
{
  double v;
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
  const char *s = nd && nd->type == YAML_SCALAR_NODE
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
        (cn && (st = vector(c, cn, "model.chain.c", s->n, 1, s->cc))))
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
  if ((st = opt_number(c, f, "forcing", "omega", &s->omega)) ||
      (st = opt_vector(c, f, "forcing", "a", s->n, s->a)) ||
      (st = opt_vector(c, f, "forcing", "b", s->n, s->b)) ||
      (st = opt_vector(c, f, "forcing", "f0", s->n, s->f0)))
    return st;
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

static int parse_stop(ctx *c, vi_scene *s, yaml_node_t *sp)
{
  static const char *const keys[] = {"w", "mass", "xs", "r", NULL};
  int st = check_map(c, sp, "stop", keys);
  if (st) return st;
  s->line_stop = LINE(sp);
  yaml_node_t *w = find(c, sp, "w"), *mass = find(c, sp, "mass");
  if (w && mass)
    return fail(c, mass, VI_ERR_PARSE, "stop.mass", "%s",
                "give w or mass, not both");
  if (w) {
    if ((st = vector(c, w, "stop.w", s->n, 0, s->w))) return st;
    s->has_w = 1;
  }
  if (mass) {
    int j;
    if ((st = integer(c, mass, "stop.mass", 1, s->n, &j))) return st;
    s->w[j - 1] = 1.0;
    s->has_w = 1;
  }
  if (!s->has_w && s->kind != MODEL_CANTILEVER)
    return fail(c, sp, VI_ERR_PARSE, "stop", "%s", "missing w or mass");
  yaml_node_t *xs = find(c, sp, "xs"), *r = find(c, sp, "r");
  if (!xs)
    return fail(c, sp, VI_ERR_PARSE, "stop.xs", "%s", "missing clearance xs");
  if (!r)
    return fail(c, sp, VI_ERR_PARSE, "stop.r", "%s", "missing restitution r");
  if ((st = number(c, xs, "stop.xs", &s->xs)) ||
      (st = number(c, r, "stop.r", &s->r)))
    return st;
  if (s->r < 0 || s->r > 1)
    return fail(c, r, VI_ERR_RESTITUTION, "stop.r", "%s",
                "restitution must lie in [0, 1]");
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
      if (!(s->rtol > 0))
        return fail(c, v, VI_ERR_TOLERANCE, "run.rtol", "%s", "must be > 0");
    }
    if ((v = find(c, run, "atol"))) {
      if ((st = number(c, v, "run.atol", &s->atol))) return st;
      if (!(s->atol > 0))
        return fail(c, v, VI_ERR_TOLERANCE, "run.atol", "%s", "must be > 0");
    }
    if ((v = find(c, run, "method"))) {
      const char *m =
          v->type == YAML_SCALAR_NODE ? (const char *)v->data.scalar.value : "";
      if (!strcmp(m, "adams"))
        s->method = VI_METHOD_ADAMS;
      else if (!strcmp(m, "bdf"))
        s->method = VI_METHOD_BDF;
      else if (!strcmp(m, "exact"))
        s->method = VI_METHOD_EXACT;
      else
        return fail(c, v, VI_ERR_PARSE, "run.method", "%s",
                    "expected adams, bdf or exact");
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
                                     "initial", "run",   "output",  NULL};
  yaml_node_t *root = yaml_document_get_root_node(&c->doc);
  if (!root)
    return diag(c->d, c->file, VI_ERR_PARSE, 1, 1, "", "", "empty scene");
  int st = check_map(c, root, "", keys);
  if (st) return st;
  yaml_node_t *v;
  if ((v = find(c, root, "name")) && v->type == YAML_SCALAR_NODE)
    s->name = strdup((const char *)v->data.scalar.value);
  yaml_node_t *mod = find(c, root, "model"), *stop = find(c, root, "stop");
  if (!mod)
    return fail(c, root, VI_ERR_PARSE, "model", "%s", "missing section");
  if (!stop)
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
  if ((st = parse_stop(c, s, stop))) return st;
  return parse_run(c, s, root);
}

int vi_scene_parse(const char *text, long len, const char *name, vi_scene **out,
                   vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (!out || !text) return VI_ERR_ARG;
  *out = NULL;
  if (len < 0) len = (long)strlen(text);
  vi_scene *s = calloc(1, sizeof *s);
  if (!s) return VI_ERR_NOMEM;
  s->text = malloc((size_t)len + 1);
  s->file = strdup(name ? name : "<input>");
  if (!s->text || !s->file) {
    vi_scene_destroy(&s);
    return VI_ERR_NOMEM;
  }
  memcpy(s->text, text, (size_t)len);
  s->text[len] = '\0';
  s->rtol = 1e-8;
  s->atol = 1e-10;
  s->method = VI_METHOD_ADAMS;
  s->out_impacts = 1;
  s->compress = 1;
  ctx c = {.d = d, .file = s->file};
  yaml_parser_t p;
  yaml_parser_initialize(&p);
  yaml_parser_set_input_string(&p, (const unsigned char *)s->text, (size_t)len);
  int st;
  if (!yaml_parser_load(&p, &c.doc)) {
    st = diag(d, s->file, VI_ERR_PARSE, (int)p.problem_mark.line + 1,
              (int)p.problem_mark.column + 1, "", "", "YAML syntax: %s%s%s",
              p.problem ? p.problem : "error", p.context ? " " : "",
              p.context ? p.context : "");
    yaml_parser_delete(&p);
    vi_scene_destroy(&s);
    return st;
  }
  yaml_parser_delete(&p);
  st = parse_root(&c, s);
  yaml_document_delete(&c.doc);
  if (st) {
    vi_scene_destroy(&s);
    return st;
  }
  if (!s->name) s->name = strdup(s->file);
  if (s->periods > 0 || !(s->t_end > 0))
    s->t_end =
        s->t0 + (s->periods > 0 ? s->periods : 100.0) * 2 * M_PI / s->omega;
  *out = s;
  return VI_OK;
}

int vi_scene_load(const char *path, vi_scene **out, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (!path || !out) return VI_ERR_ARG;
  *out = NULL;
  FILE *f = fopen(path, "rb");
  if (!f)
    return diag(d, path, VI_ERR_IO, 0, 0, "", "", "cannot open: %s",
                strerror(errno));
  char *buf = NULL;
  long len = 0, cap = 0;
  size_t got;
  char chunk[8192];
  while ((got = fread(chunk, 1, sizeof chunk, f)) > 0) {
    if (len + (long)got > cap) {
      cap = 2 * (len + (long)got);
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
  fclose(f);
  if (bad) {
    free(buf);
    return diag(d, path, VI_ERR_IO, 0, 0, "", "", "read error");
  }
  int st = vi_scene_parse(buf ? buf : "", len, path, out, d);
  free(buf);
  return st;
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
  free(s);
  *scene = NULL;
}

/* ---- building the model ------------------------------------------------- */
int vi_scene_create_model(const vi_scene *s, vi_model **out, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (!s || !out) return VI_ERR_ARG;
  *out = NULL;
  int n = s->n, st;
  size_t nn = (size_t)n * n;
  double *buf = calloc(3 * nn + 2 * (size_t)n, sizeof(double));
  if (!buf)
    return diag(d, s->file, VI_ERR_NOMEM, 0, 0, "", "", "out of memory");
  double *M = buf, *C = M + nn, *K = C + nn, *w = K + nn, *a = w + n;
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
    where = "stop";
    st = vi_model_set_stop(m, w, s->xs, s->r);
  }
  if (!st) {
    where = "model";
    st = vi_model_setup(m);
  }
  free(buf);
  if (st) {
    int line = !strcmp(where, "stop") ? s->line_stop : s->line_model;
    diag(d, s->file, st, line, line ? 1 : 0, where, "", "%s",
         m ? vi_model_errmsg(m) : vi_strerror(st));
    vi_model_destroy(&m);
    return st;
  }
  *out = m;
  return VI_OK;
}

int vi_scene_configure_sim(const vi_scene *s, vi_sim *sim, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (!s || !sim) return VI_ERR_ARG;
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
  if (!s) return VI_ERR_ARG;
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
