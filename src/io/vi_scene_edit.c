/* vi_scene_edit.c - `--set KEY=VALUE` overrides spliced into the scene text.
 *
 * Why a splice and not a re-emitted document: yaml_emitter drops comments
 * and re-flows every line, so a bad value would be reported at a line of a
 * text the user never saw.  libyaml still does the locating: the document
 * is loaded, the path walked node by node, and the node's marks give the
 * span to replace. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <yaml.h>

#include "vi_io_internal.h"
#include "vi_scene_internal.h"
#include "vibroimpact/vi_scene_edit.h"
#include "vibroimpact/vi_status.h"

#define MAX_TOK 16   /* path components */
#define MAX_EDITS 64 /* lines remembered for messages */

struct vi_scene_edit {
  char *text, *name;
  size_t len;
  int max_depth; /* the nesting limit (vi_scene_edit_create_limited) */
  int nedits, lines[MAX_EDITS];
};

typedef struct tok {
  int index; /* 0: a key; else a 1-based list index */
  char key[64];
} tok;

/* "a.b[2].c" -> tokens; 0 on a malformed path. */
static int split_path(const char *key, tok *t, int *nt)
{
  int n = 0;
  const char *s = key;
  if (!*s) return 0;
  while (*s) {
    if (n == MAX_TOK) return 0;
    if (*s == '[') {
      char *end;
      long i = strtol(s + 1, &end, 10);
      if (end == s + 1 || *end != ']' || i < 1 || i > 1000000) return 0;
      t[n].index = (int)i;
      t[n++].key[0] = '\0';
      s = end + 1;
      if (*s == '.') {
        s++;
        if (!*s || *s == '.' || *s == '[') return 0;
      }
      continue;
    }
    size_t k = strcspn(s, ".[");
    if (k == 0 || k >= sizeof t[n].key) return 0;
    memcpy(t[n].key, s, k);
    t[n].key[k] = '\0';
    t[n++].index = 0;
    s += k;
    if (*s == '.') {
      s++;
      if (!*s || *s == '.' || *s == '[') return 0;
    }
  }
  *nt = n;
  return 1;
}

/* libyaml marks count characters; the splice needs bytes (UTF-8 comments).
 * A UTF-8 byte-order mark is skipped by libyaml before counting starts. */
static size_t byte_of(const char *text, size_t len, size_t chars)
{
  size_t b = 0, c = 0;
  if (len >= 3 && !memcmp(text, "\xEF\xBB\xBF", 3)) b = 3;
  while (b < len && c < chars) {
    b++;
    while (b < len && ((unsigned char)text[b] & 0xC0) == 0x80) b++;
    c++;
  }
  return b;
}

/* The scene reader's nesting limit (max_depth, VI_SCENE_MAX_DEPTH by
 * default, refused with its message, vi_diag_too_deep), applied before the
 * document is loaded: an event scan that stops at the first level too
 * deep, so 100 000 levels cost what 33 do, as with `run`. */
static int too_deep(const char *text, size_t len, int max_depth,
                    yaml_mark_t *where)
{
  yaml_parser_t p;
  if (!yaml_parser_initialize(&p)) return 0;
  yaml_parser_set_input_string(&p, (const unsigned char *)text, len);
  int depth = 0, deep = 0, end = 0;
  while (!end && !deep) {
    yaml_event_t ev;
    if (!yaml_parser_parse(&p, &ev)) break; /* the loader reports it */
    if (ev.type == YAML_MAPPING_START_EVENT || ev.type == YAML_SEQUENCE_START_EVENT) {
      if (++depth > max_depth) {
        deep = 1;
        if (where) *where = ev.start_mark;
      }
    } else if (ev.type == YAML_MAPPING_END_EVENT || ev.type == YAML_SEQUENCE_END_EVENT) {
      depth--;
    } else if (ev.type == YAML_STREAM_END_EVENT) {
      end = 1;
    }
    yaml_event_delete(&ev);
  }
  yaml_parser_delete(&p);
  return deep;
}

static int load(const char *text, size_t len, int max_depth,
                yaml_document_t *doc, yaml_mark_t *where, const char **problem)
{
  if (too_deep(text, len, max_depth, where)) { /* never loaded: quadratic in the depth */
    if (problem) *problem = "nested too deep";
    return 0;
  }
  yaml_parser_t p;
  if (!yaml_parser_initialize(&p)) return 0;
  yaml_parser_set_input_string(&p, (const unsigned char *)text, len);
  int ok = yaml_parser_load(&p, doc);
  if (!ok) {
    if (where) *where = p.problem_mark;
    if (problem) *problem = p.problem ? p.problem : "error";
  }
  yaml_parser_delete(&p);
  return ok;
}

int vi_scene_edit_create(const char *text, int64_t len, const char *name,
                         vi_scene_edit **out, vi_diag *d)
{
  return vi_scene_edit_create_limited(text, len, name, 0, out, d);
}

int vi_scene_edit_create_limited(const char *text, int64_t len,
                                 const char *name, int max_depth,
                                 vi_scene_edit **out, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (!out || !text) return VI_ERR_ARG;
  *out = NULL;
  if (len < 0) len = (long)strlen(text);
  vi_scene_edit *e = calloc(1, sizeof *e);
  if (!e) return VI_ERR_NOMEM;
  e->text = malloc((size_t)len + 1);
  e->name = strdup(name ? name : "<input>");
  if (!e->text || !e->name) {
    vi_scene_edit_destroy(&e);
    return VI_ERR_NOMEM;
  }
  memcpy(e->text, text, (size_t)len);
  e->text[len] = '\0';
  e->len = (size_t)len;
  e->max_depth = max_depth > 0 ? max_depth : VI_SCENE_MAX_DEPTH;
  yaml_document_t doc;
  yaml_mark_t mk = {0, 0, 0};
  const char *why = "";
  if (too_deep(e->text, e->len, e->max_depth, &mk)) {
    int st = vi_diag_too_deep(d, e->name, (int)mk.line + 1, (int)mk.column + 1,
                              e->max_depth);
    vi_scene_edit_destroy(&e);
    return st;
  }
  if (!load(e->text, e->len, e->max_depth, &doc, &mk, &why)) {
    int st = vi_diag_set(d, e->name, VI_ERR_PARSE, (int)mk.line + 1,
                         (int)mk.column + 1, "", "", "YAML syntax: %s", why);
    vi_scene_edit_destroy(&e);
    return st;
  }
  yaml_document_delete(&doc);
  *out = e;
  return VI_OK;
}

void vi_scene_edit_destroy(vi_scene_edit **ep)
{
  if (!ep || !*ep) return;
  free((*ep)->text);
  free((*ep)->name);
  free(*ep);
  *ep = NULL;
}

const char *vi_scene_edit_text(const vi_scene_edit *e)
{
  return e ? e->text : "";
}

/* Replace bytes [a, b) of the text with s. */
static int splice(vi_scene_edit *e, size_t a, size_t b, const char *s)
{
  size_t k = strlen(s), nl = e->len - (b - a) + k;
  char *t = malloc(nl + 1);
  if (!t) return VI_ERR_NOMEM;
  memcpy(t, e->text, a);
  memcpy(t + a, s, k);
  memcpy(t + a + k, e->text + b, e->len - b);
  t[nl] = '\0';
  e->text = t; /* the old text is the caller's: vi_scene_edit_set */
  e->len = nl;
  return VI_OK;
}

static void remember(vi_scene_edit *e, int line)
{
  for (int i = 0; i < e->nedits; i++)
    if (e->lines[i] == line) return;
  if (e->nedits < MAX_EDITS) e->lines[e->nedits++] = line;
}

static yaml_node_t *child(yaml_document_t *doc, yaml_node_t *map,
                          const char *key, yaml_node_t **keynode)
{
  for (yaml_node_pair_t *p = map->data.mapping.pairs.start;
       p < map->data.mapping.pairs.top; p++) {
    yaml_node_t *k = yaml_document_get_node(doc, p->key);
    if (k && k->type == YAML_SCALAR_NODE &&
        !strcmp((const char *)k->data.scalar.value, key)) {
      if (keynode) *keynode = k;
      return yaml_document_get_node(doc, p->value);
    }
  }
  return NULL;
}

/* Walk the path as far as it exists: *found = number of tokens matched,
 * *nd = the last node reached. */
static int walk(const vi_scene_edit *e, yaml_document_t *doc, const tok *t, int nt,
                const char *key, yaml_node_t **nd, int *found, vi_diag *d)
{
  yaml_node_t *cur = yaml_document_get_root_node(doc);
  if (!cur)
    return vi_diag_set(d, e->name, VI_ERR_PARSE, 0, 0, key, "",
                       "the scene is empty");
  int i;
  for (i = 0; i < nt; i++) {
    int line = (int)cur->start_mark.line + 1, col = (int)cur->start_mark.column + 1;
    if (!t[i].index) {
      if (cur->type != YAML_MAPPING_NODE)
        return vi_diag_set(d, e->name, VI_ERR_PARSE, line, col, key, "",
                           "'%s' is looked up in something that is not a "
                           "mapping",
                           t[i].key);
      yaml_node_t *c = child(doc, cur, t[i].key, NULL);
      if (!c) break;
      cur = c;
    } else {
      if (cur->type != YAML_SEQUENCE_NODE)
        return vi_diag_set(d, e->name, VI_ERR_PARSE, line, col, key, "",
                           "index [%d] applied to something that is not a list",
                           t[i].index);
      long cnt = cur->data.sequence.items.top - cur->data.sequence.items.start;
      if (t[i].index > cnt)
        return vi_diag_set(d, e->name, VI_ERR_PARSE, line, col, key, "",
                           "index [%d] out of range: the list has %ld entries "
                           "(indices are 1-based)", t[i].index, cnt);
      cur = yaml_document_get_node(doc,
                                   cur->data.sequence.items.start[t[i].index - 1]);
      if (!cur)
        return vi_diag_set(d, e->name, VI_ERR_PARSE, line, col, key, "",
                           "malformed list");
    }
  }
  *nd = cur;
  *found = i;
  return VI_OK;
}

/* VALUE must be a single YAML node on a single line. */
static int check_value(const vi_scene_edit *e, const char *key,
                       const char *value, vi_diag *d)
{
  if (!*value || strpbrk(value, "\n\r#"))
    return vi_diag_set(d, e->name, VI_ERR_PARSE, 0, 0, key, value,
                       "the value must be one YAML value on one line "
                       "(no comment)");
  yaml_document_t doc;
  if (too_deep(value, strlen(value), e->max_depth, NULL)) {
    vi_diag_too_deep(d, e->name, 0, 0, e->max_depth);
    if (d) {
      snprintf(d->key, sizeof d->key, "%s", key);
      snprintf(d->value, sizeof d->value, "%s", value);
    }
    return VI_ERR_LIMIT;
  }
  if (!load(value, strlen(value), e->max_depth, &doc, NULL, NULL))
    return vi_diag_set(d, e->name, VI_ERR_PARSE, 0, 0, key, value,
                       "the value is not valid YAML");
  yaml_node_t *r = yaml_document_get_root_node(&doc);
  int ok = r && (r->type != YAML_MAPPING_NODE ||
                 r->data.mapping.style == YAML_FLOW_MAPPING_STYLE) &&
           (r->type != YAML_SEQUENCE_NODE ||
            r->data.sequence.style == YAML_FLOW_SEQUENCE_STYLE);
  yaml_document_delete(&doc);
  if (!ok)
    return vi_diag_set(d, e->name, VI_ERR_PARSE, 0, 0, key, value,
                       "the value must be a number, a word or a flow list "
                       "[..]");
  return VI_OK;
}

int vi_scene_edit_set(vi_scene_edit *e, const char *key, const char *value,
                      vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (!e || !key || !value) return VI_ERR_ARG;
  tok t[MAX_TOK];
  int nt = 0, st, found = 0;
  if (!split_path(key, t, &nt))
    return vi_diag_set(d, e->name, VI_ERR_PARSE, 0, 0, key, value,
                       "malformed key: expected words joined by '.', with "
                       "1-based list indices such as forcing.a[1]");
  if ((st = check_value(e, key, value, d))) return st;
  yaml_document_t doc;
  if (!load(e->text, e->len, e->max_depth, &doc, NULL, NULL))
    return vi_diag_set(d, e->name, VI_ERR_PARSE, 0, 0, key, value,
                       "the scene is no longer valid YAML");
  char *old = e->text; /* kept until the edited text is known to nest
                          within the limit (a value at a deep key) */
  size_t olen = e->len;
  int onedits = e->nedits;
  yaml_node_t *nd = NULL;
  if ((st = walk(e, &doc, t, nt, key, &nd, &found, d))) goto done;
  if (found == nt) {
    /* replace the node's own text */
    size_t a = byte_of(e->text, e->len, nd->start_mark.index);
    size_t b = byte_of(e->text, e->len, nd->end_mark.index);
    int line = (int)nd->start_mark.line + 1;
    if ((st = splice(e, a, b, value))) goto done;
    remember(e, line);
    goto done;
  }
  /* add the missing keys to the innermost mapping that exists */
  for (int i = found; i < nt; i++)
    if (t[i].index) {
      st = vi_diag_set(d, e->name, VI_ERR_PARSE, (int)nd->start_mark.line + 1,
                       (int)nd->start_mark.column + 1, key, value,
                       "'%s' is not in the scene, and list entries cannot "
                       "be added",
                       t[found].key);
      goto done;
    }
  char ins[1024] = "";
  int k = 0;
  for (int i = found; i < nt; i++)
    k += snprintf(ins + k, sizeof ins - (size_t)k, "%s: %s", t[i].key,
                  i + 1 < nt ? "{" : "");
  k += snprintf(ins + k, sizeof ins - (size_t)k, "%s", value);
  for (int i = found; i + 1 < nt; i++)
    k += snprintf(ins + k, sizeof ins - (size_t)k, "}");
  if (k >= (int)sizeof ins - 8) {
    st = vi_diag_set(d, e->name, VI_ERR_PARSE, 0, 0, key, value, "%s",
                     "value too long");
    goto done;
  }
  long npairs = nd->data.mapping.pairs.top - nd->data.mapping.pairs.start;
  char buf[1200];
  if (nd->data.mapping.style == YAML_FLOW_MAPPING_STYLE) {
    size_t b = byte_of(e->text, e->len, nd->end_mark.index);
    while (b > 0 && e->text[b - 1] != '}') b--;
    if (b == 0) {
      st = vi_diag_set(d, e->name, VI_ERR_PARSE, 0, 0, key, value,
                       "cannot find the end of the mapping");
      goto done;
    }
    snprintf(buf, sizeof buf, "%s%s", npairs ? ", " : "", ins);
    if ((st = splice(e, b - 1, b - 1, buf))) goto done;
    remember(e, (int)nd->end_mark.line + 1);
  } else {
    if (!npairs) {
      st = vi_diag_set(d, e->name, VI_ERR_PARSE, 0, 0, key, value,
                       "cannot add a key to an empty mapping");
      goto done;
    }
    yaml_node_t *k0 = yaml_document_get_node(&doc, nd->data.mapping.pairs.start->key);
    yaml_node_t *vl = yaml_document_get_node(&doc, (nd->data.mapping.pairs.top - 1)->value);
    size_t b = byte_of(e->text, e->len, vl->end_mark.index);
    /* a block value ends at the start of the next line: step back */
    if (vl->end_mark.column == 0 && b > 0) b--;
    while (b < e->len && e->text[b] != '\n') b++;
    int ind = (int)k0->start_mark.column;
    snprintf(buf, sizeof buf, "\n%*s%s", ind, "", ins);
    /* the new line is counted from the line b sits on */
    int line = 1;
    for (size_t i = 0; i < b; i++) line += e->text[i] == '\n';
    if ((st = splice(e, b, b, buf))) goto done;
    remember(e, line + 1);
  }
done:
  yaml_document_delete(&doc);
  if (e->text != old) {
    yaml_mark_t mk = {0, 0, 0};
    if (!st && too_deep(e->text, e->len, e->max_depth, &mk)) {
      free(e->text);
      e->text = old;
      e->len = olen;
      e->nedits = onedits;
      st = vi_diag_too_deep(d, e->name, (int)mk.line + 1, (int)mk.column + 1,
                            e->max_depth);
      if (d) {
        snprintf(d->key, sizeof d->key, "%s", key);
        snprintf(d->value, sizeof d->value, "%s", value);
      }
    } else {
      free(old);
    }
  }
  return st;
}

int vi_scene_edit_assign(vi_scene_edit *e, const char *assignment, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (!e || !assignment) return VI_ERR_ARG;
  const char *eq = strchr(assignment, '=');
  char key[256];
  if (!eq || eq == assignment || (size_t)(eq - assignment) >= sizeof key)
    return vi_diag_set(d, e->name, VI_ERR_PARSE, 0, 0, assignment, "",
                       "expected KEY=VALUE, e.g. forcing.omega=0.9");
  memcpy(key, assignment, (size_t)(eq - assignment));
  key[eq - assignment] = '\0';
  return vi_scene_edit_set(e, key, eq + 1, d);
}

int vi_scene_edit_set_number(vi_scene_edit *e, const char *key, double value,
                             vi_diag *d)
{
  char buf[40];
  snprintf(buf, sizeof buf, "%.17g", value);
  return vi_scene_edit_set(e, key, buf, d);
}

int vi_scene_edit_get(const vi_scene_edit *e, const char *key, char *buf,
                      int len, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (!e || !key || !buf || len < 1) return VI_ERR_ARG;
  buf[0] = '\0';
  tok t[MAX_TOK];
  int nt = 0, st, found = 0;
  if (!split_path(key, t, &nt))
    return vi_diag_set(d, e->name, VI_ERR_PARSE, 0, 0, key, "", "%s",
                       "malformed key");
  yaml_document_t doc;
  if (!load(e->text, e->len, e->max_depth, &doc, NULL, NULL))
    return vi_diag_set(d, e->name, VI_ERR_PARSE, 0, 0, key, "", "invalid YAML");
  yaml_node_t *nd = NULL;
  st = walk(e, &doc, t, nt, key, &nd, &found, d);
  if (!st && (found < nt || !nd || nd->type != YAML_SCALAR_NODE))
    st = vi_diag_set(d, e->name, VI_ERR_PARSE, 0, 0, key, "", "%s",
                     found < nt ? "the scene has no such key"
                                : "not a single value");
  if (!st && nd) {
    const char *v = (const char *)nd->data.scalar.value;
    /* a value cut to fit would pass for another value: refuse it */
    if (strlen(v) >= (size_t)len)
      st = vi_diag_set(d, e->name, VI_ERR_LIMIT, 0, 0, key, "",
                       "the value needs %zu bytes, the buffer has %d",
                       strlen(v) + 1, len);
    else
      snprintf(buf, (size_t)len, "%s", v);
  }
  yaml_document_delete(&doc);
  return st;
}

/* vi_scene_edit_parse and vi_scene_edit_parse_within: max_memory as in
 * vi_scene_parse_within. */
static int parse(const vi_scene_edit *e, const double *max_memory,
                 vi_scene **out, vi_diag *d)
{
  if (!e || !out) return VI_ERR_ARG;
  if (max_memory && isnan(*max_memory)) return VI_ERR_ARG;
  int st = vi_scene_parse_within(e->text, (long)e->len, e->name, e->max_depth,
                                 max_memory, out, d);
  if (st && d)
    for (int i = 0; i < e->nedits; i++)
      if (d->line == e->lines[i]) {
        size_t k = strlen(d->message);
        snprintf(d->message + k, sizeof d->message - k,
                 " (a value set on the command line)");
        break;
      }
  return st;
}

int vi_scene_edit_parse(const vi_scene_edit *e, vi_scene **out, vi_diag *d)
{
  return parse(e, NULL, out, d);
}

int vi_scene_edit_parse_within(const vi_scene_edit *e, double max_memory,
                               vi_scene **out, vi_diag *d)
{
  return parse(e, &max_memory, out, d);
}
