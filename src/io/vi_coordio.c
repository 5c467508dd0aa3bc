/* vi_coordio.c - the element-free text export of FE codes (vi_mmio.h:
 * VI_MATRIX_COORDINATE): lines "node, dof, node, dof, value" as Abaqus'
 * *MATRIX OUTPUT, FORMAT=MATRIX INPUT writes them, or "row column value"
 * (FORMAT=COORDINATE: global equation numbers), and the numbering of
 * their (node, dof) pairs as global dofs (vi_dofmap), which M, K and C of
 * one model share.  Our own reader, after Abaqus' description of the
 * format ("Matrix generation", Abaqus Analysis User's Guide). */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vi_matrix_internal.h"

typedef vi_mx_reader reader;

/* A pair's key: the node in the high 32 bits, the dof (>= 1) in the low:
 * ascending keys are sorted by node, then dof. */
static int64_t pair_key(int node, int dof)
{
  return (int64_t)node * 4294967296LL + (int64_t)dof;
}

struct vi_dofmap {
  int n;
  int equations;   /* 1: 'row column value' files: dof i is equation i */
  int64_t *key;    /* [n] ascending (NULL for equations) */
  int64_t entries; /* lines of the largest file scanned */
};

/* A line to skip: blank, or a comment (Abaqus' **, or # or %). */
static int skip_line(const char *s)
{
  s += strspn(s, " \t");
  return !*s || *s == '#' || *s == '%' || (s[0] == '*' && s[1] == '*');
}

/* One parsed line: the two pairs, the value, and where each field starts. */
typedef struct cline {
  int node[2], dof[2];
  double v;
} cline;

/* An error of entry k (its key made only then: formatting it for every
 * line would cost more than reading the line). */
#define CFAIL(code, col, ...)                                            \
  (snprintf(key, sizeof key, "entry %lld", (long long)k + 1),            \
   vi_mx_fail_at(r, code, col, key, __VA_ARGS__))

/* Split the line into trimmed fields: at commas when it has one, else at
 * blanks.  Five fields are 'node, dof, node, dof, value' (Abaqus' MATRIX
 * INPUT), three 'row column value' (Abaqus' FORMAT=COORDINATE: global
 * equation numbers, stored as node = the equation, dof = 0); *form, 0 at
 * a file's first entry, is the file's (5 or 3), which every line keeps. */
static int parse_line(reader *r, int64_t k, int *form, cline *c)
{
  char key[48];
  char copy[sizeof r->buf];
  memcpy(copy, r->buf, sizeof copy);
  char *f[6] = {copy, copy, copy, copy, copy, copy}, *save = NULL;
  int col[6] = {1, 1, 1, 1, 1, 1}, nf = 0;
  if (strchr(copy, ','))
    for (char *p = copy;; p++) {
      char *e = strchr(p, ',');
      if (nf < 6) {
        while (*p == ' ' || *p == '\t') p++;
        f[nf] = p;
        col[nf] = (int)(p - copy) + 1;
      }
      nf++;
      if (!e) break;
      *e = '\0';
      p = e;
    }
  else
    for (char *t = strtok_r(copy, " \t", &save); t;
         t = strtok_r(NULL, " \t", &save)) {
      if (nf < 6) {
        f[nf] = t;
        col[nf] = (int)(t - copy) + 1;
      }
      nf++;
    }
  for (int q = 0; q < (nf < 6 ? nf : 6); q++) {
    size_t n = strlen(f[q]);
    while (n && (f[q][n - 1] == ' ' || f[q][n - 1] == '\t')) f[q][--n] = '\0';
  }
  if (*form != 5 && *form != 3) *form = 0; /* none yet */
  if (*form == 0 && (nf == 5 || nf == 3)) *form = nf;
  if (nf != *form || *form == 0)
    return *form ? CFAIL(VI_ERR_PARSE, 0, "expected %s (%d fields, as the "
                         "file's first entry), got %d", *form == 5
                         ? "'node, dof, node, dof, value'"
                         : "'row column value'", *form, nf)
                 : CFAIL(VI_ERR_PARSE, 0, "expected 'node, dof, node, dof, "
                         "value' (5 fields) or 'row column value' (3), got "
                         "%d", nf);
  static const char *const what5[4] = {"row node", "row dof", "column node",
                                       "column dof"};
  static const char *const what3[2] = {"row", "column"};
  int ni = nf - 1;
  for (int q = 0; q < ni; q++) {
    const char *what = nf == 5 ? what5[q] : what3[q];
    char *end;
    errno = 0;
    long long v = strtoll(f[q], &end, 10);
    if (end == f[q] || *end || errno == ERANGE || v < INT_MIN || v > INT_MAX)
      return CFAIL(VI_ERR_PARSE, col[q], "%s '%s' is not a whole number",
                   what, f[q]);
    if ((nf == 3 || q % 2) && (v < 1 || v > INT_MAX / 2))
      return CFAIL(VI_ERR_PARSE, col[q], "%s %lld: %s are numbered from 1",
                   what, v, nf == 3 ? "equations" : "dofs");
    if (nf == 3) {
      c->node[q] = (int)v;
      c->dof[q] = 0;
    } else if (q % 2)
      c->dof[q / 2] = (int)v;
    else
      c->node[q / 2] = (int)v;
  }
  char *end;
  errno = 0;
  c->v = strtod(f[ni], &end);
  if (end == f[ni] || *end)
    return CFAIL(VI_ERR_PARSE, col[ni], "value '%s' is not a number", f[ni]);
  if (!isfinite(c->v) || (errno == ERANGE && fabs(c->v) > 1.0))
    return CFAIL(VI_ERR_NONFINITE, col[ni], "value '%s' is not a finite "
                 "number", f[ni]);
  return VI_OK;
}

/* The next entry line (1), or 0 at the end / on an error (*st). */
static int next_entry(reader *r, int64_t k, int *form, cline *c, int *st)
{
  while (vi_mx_next_line(r, st)) {
    if (skip_line(r->buf)) continue;
    *st = parse_line(r, k, form, c);
    return *st == VI_OK;
  }
  return 0;
}

static int cmp_i64(const void *a, const void *b)
{
  int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
  return (x > y) - (x < y);
}

/* Sort and drop repeats: the count left. */
static int64_t sort_unique(int64_t *k, int64_t n)
{
  if (n < 2) return n;
  qsort(k, (size_t)n, sizeof *k, cmp_i64);
  int64_t m = 1;
  for (int64_t q = 1; q < n; q++)
    if (k[q] != k[m - 1]) k[m++] = k[q];
  return m;
}

int vi_dofmap_scan(int nfiles, const char *const *paths, double max_bytes,
                   vi_dofmap **out, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (out) *out = NULL;
  if (nfiles < 1 || !paths || !out || isnan(max_bytes))
    return vi_diag_set(d, "", VI_ERR_ARG, 0, 0, "", "", "%s",
                       "vi_dofmap_scan: one file or more, their paths, out "
                       "and a limit that is a number are required");
  for (int f = 0; f < nfiles; f++)
    if (!paths[f])
      return vi_diag_set(d, "", VI_ERR_ARG, 0, 0, "", "", "vi_dofmap_scan: "
                         "path %d is NULL", f + 1);
  int64_t cap = 1024, n = 0, most = 0;
  int64_t *key = malloc((size_t)cap * sizeof *key);
  if (!key) return vi_diag_nomem(d, paths[0]);
  int st = VI_OK, form = 0, eqmax = 0;
  for (int f = 0; f < nfiles && !st; f++) {
    reader r;
    if ((st = vi_mx_open(&r, paths[f], d))) break;
    cline c = {{0, 0}, {0, 0}, 0.0};
    int64_t k = 0;
    int fform = 0;
    for (; next_entry(&r, k, &fform, &c, &st); k++) {
      if (form && fform != form) { /* one numbering: one kind of file */
        st = vi_mx_fail(&r, VI_ERR_PARSE, "entry", "'%s' lines, but the "
                        "model's first file has '%s' lines: the files of one "
                        "model number their dofs alike",
                        fform == 5 ? "node, dof, node, dof, value"
                                   : "row column value",
                        form == 5 ? "node, dof, node, dof, value"
                                  : "row column value");
        break;
      }
      form = fform;
      if (form == 3) { /* equation numbers: the largest is n */
        eqmax = c.node[0] > eqmax ? c.node[0] : eqmax;
        eqmax = c.node[1] > eqmax ? c.node[1] : eqmax;
        continue;
      }
      if (n + 2 > cap) { /* compact, then grow if still half full */
        n = sort_unique(key, n);
        if (n + 2 > cap / 2) {
          if (max_bytes > 0 && 16.0 * (double)cap > max_bytes) {
            st = vi_mx_fail(&r, VI_ERR_LIMIT, "entry", "more than %lld "
                            "distinct (node, dof) pairs: their map would "
                            "need more than the %.3g MB allowed",
                            (long long)n, max_bytes / 1048576.0);
            break;
          }
          int64_t *nk = realloc(key, 2 * (size_t)cap * sizeof *key);
          if (!nk) {
            st = vi_diag_nomem(d, paths[f]);
            break;
          }
          key = nk;
          cap *= 2;
        }
      }
      key[n++] = pair_key(c.node[0], c.dof[0]);
      key[n++] = pair_key(c.node[1], c.dof[1]);
    }
    if (!st && k == 0) {
      r.line = 0;
      st = vi_diag_set(d, paths[f], VI_ERR_PARSE, 0, 0, "entry", "", "%s",
                       "no entries: a coordinate file holds lines 'node, "
                       "dof, node, dof, value' or 'row column value'");
    }
    most = k > most ? k : most;
    fclose(r.f);
  }
  n = form == 3 ? eqmax : sort_unique(key, n);
  if (form == 3) { /* no keys: dof i is equation i */
    free(key);
    key = NULL;
  }
  if (!st && n > INT_MAX / 2)
    st = vi_diag_set(d, paths[0], VI_ERR_LIMIT, 0, 0, "", "", "%lld dofs: "
                     "more than int indices hold", (long long)n);
  vi_dofmap *m = st ? NULL : calloc(1, sizeof *m);
  if (!m) {
    free(key);
    return st ? st : vi_diag_nomem(d, paths[0]);
  }
  m->n = (int)n;
  m->equations = form == 3;
  m->key = key;
  m->entries = most;
  *out = m;
  return VI_OK;
}

void vi_dofmap_destroy(vi_dofmap **map)
{
  if (!map || !*map) return;
  free((*map)->key);
  free(*map);
  *map = NULL;
}

int vi_dofmap_n(const vi_dofmap *map) { return map ? map->n : 0; }

int64_t vi_dofmap_entries(const vi_dofmap *map)
{
  return map ? map->entries : 0;
}

int vi_dofmap_label(const vi_dofmap *map, int index, int *node, int *dof)
{
  if (!map || !node || !dof) return VI_ERR_ARG;
  if (index < 1 || index > map->n) return VI_ERR_DIM;
  if (map->equations) {
    *node = index;
    *dof = 0;
    return VI_OK;
  }
  int64_t k = map->key[index - 1];
  int64_t nd = k >= 0 ? k / 4294967296LL : -((-k + 4294967295LL) / 4294967296LL);
  *node = (int)nd;
  *dof = (int)(k - nd * 4294967296LL);
  return VI_OK;
}

int vi_dofmap_index(const vi_dofmap *map, int node, int dof)
{
  if (!map) return 0;
  if (map->equations) return dof == 0 && node >= 1 && node <= map->n ? node : 0;
  if (dof < 1) return 0;
  int64_t k = pair_key(node, dof);
  int lo = 0, hi = map->n - 1;
  while (lo <= hi) {
    int mid = lo + (hi - lo) / 2;
    if (map->key[mid] == k) return mid + 1;
    if (map->key[mid] < k)
      lo = mid + 1;
    else
      hi = mid - 1;
  }
  return 0;
}

/* ---- a file into CSC -------------------------------------------------- */
/* 1 when some off-diagonal pair is written both ways (the file holds the
 * whole matrix), 0 when each once (one triangle), -1 out of memory. */
static int both_ways(const vi_mx_triplets *t, int n)
{
  int64_t m = 0, *k = malloc(((size_t)t->count + 1) * sizeof *k);
  if (!k) return -1;
  for (int64_t q = 0; q < t->count; q++) {
    int i = t->i[q], j = t->j[q];
    if (i == j) continue;
    int lo = i < j ? i : j, hi = i < j ? j : i;
    k[m++] = 2 * ((int64_t)hi * n + lo) + (i > j);
  }
  qsort(k, (size_t)m, sizeof *k, cmp_i64);
  int both = 0;
  for (int64_t q = 1; q < m && !both; q++)
    both = k[q] / 2 == k[q - 1] / 2 && k[q] != k[q - 1];
  free(k);
  return both;
}

static int coord_read(reader *r, const vi_dofmap *map, int storage,
                      double max_bytes, vi_mm **out)
{
  /* count the entries first: the memory is known before it is taken */
  int st;
  int64_t count = 0;
  while (vi_mx_next_line(r, &st))
    count += !skip_line(r->buf);
  if (st) return st;
  int64_t cap = storage == VI_CSC_FULL ? 2 * count : count;
  double need = 48.0 * (double)cap + 12.0 * map->n;
  if (max_bytes > 0 && need > max_bytes)
    return vi_diag_set(r->d, r->path, VI_ERR_LIMIT, 0, 0, "", "", "reading "
                       "%lld entries needs about %.3g MB, more than the "
                       "%.3g MB allowed", (long long)count, need / 1048576.0,
                       max_bytes / 1048576.0);
  if (count == 0)
    return vi_diag_set(r->d, r->path, VI_ERR_PARSE, 0, 0, "entry", "", "%s",
                       "no entries: a coordinate file holds lines 'node, "
                       "dof, node, dof, value' or 'row column value'");
  if (2.0 * (double)count > INT_MAX)
    return vi_diag_set(r->d, r->path, VI_ERR_LIMIT, 0, 0, "", "", "%lld "
                       "entries: more than int indices hold",
                       (long long)count);
  rewind(r->f);
  r->line = 0;
  vi_mx_triplets t;
  if (!vi_mx_trip_alloc(&t, cap)) {
    vi_mx_trip_free(&t);
    return vi_diag_nomem(r->d, r->path);
  }
  cline c = {{0, 0}, {0, 0}, 0.0};
  int form = 0;
  for (int64_t k = 0; k < count && next_entry(r, k, &form, &c, &st); k++) {
    int ij[2];
    for (int s = 0; s < 2; s++)
      if (!(ij[s] = vi_dofmap_index(map, c.node[s], c.dof[s]))) {
        vi_mx_trip_free(&t);
        return c.dof[s] ? vi_mx_fail(r, VI_ERR_DIM, "entry", "(node %d, "
                                     "dof %d) is not a dof of the model's "
                                     "map (the pairs of its files)",
                                     c.node[s], c.dof[s])
                        : vi_mx_fail(r, VI_ERR_DIM, "entry", "equation %d "
                                     "is not a dof of the model's map "
                                     "(numbered by equations: %s)",
                                     c.node[s], map->equations
                                     ? "beyond its largest"
                                     : "its files name (node, dof) pairs");
      }
    t.i[t.count] = ij[0] - 1;
    t.j[t.count] = ij[1] - 1;
    t.v[t.count] = c.v;
    t.line[t.count] = r->line;
    t.count++;
  }
  if (!st && t.count != count) /* the file changed between the passes */
    st = vi_diag_set(r->d, r->path, VI_ERR_IO, 0, 0, "", "", "%s",
                     "the file changed while it was read");
  int full = st ? 0 : both_ways(&t, map->n);
  if (full < 0) st = vi_diag_nomem(r->d, r->path);
  if (!st && !full) /* one triangle: stored as the lower */
    for (int64_t q = 0; q < t.count; q++)
      if (t.i[q] < t.j[q]) {
        int s = t.i[q];
        t.i[q] = t.j[q];
        t.j[q] = s;
      }
  if (!st) st = vi_mx_build(r, map->n, map->n, !full, &t, storage, out);
  vi_mx_trip_free(&t);
  return st;
}

int vi_coord_load(const char *path, const vi_dofmap *map, int storage,
                  double max_bytes, vi_mm **out, vi_diag *d)
{
  vi_dofmap *own = NULL;
  int st;
  if (!map) { /* the file's own pairs */
    if ((st = vi_dofmap_scan(1, &path, max_bytes, &own, d))) return st;
    map = own;
  }
  if (!map) return vi_diag_nomem(d, path); /* a scan's success made one */
  reader r;
  if (!(st = vi_mx_open(&r, path, d))) {
    st = coord_read(&r, map, storage, max_bytes, out);
    fclose(r.f);
  }
  vi_dofmap_destroy(&own);
  return st;
}
