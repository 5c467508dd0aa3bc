/* vi_matrix.c - a matrix file in any of the formats FE codes write
 * (vi_mmio.h): the format told by content, and the dispatch to the
 * readers (vi_mmio.c, vi_hbio.c, vi_coordio.c). */
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "vi_matrix_internal.h"
#include "vi_scene_internal.h"

/* Line 3 of a Harwell-Boeing header starts with a type such as RSA. */
static int hb_type(const char *s)
{
  if (strlen(s) < 3 || (s[3] && s[3] != ' ')) return 0;
  return strchr("RCPIQ", toupper((unsigned char)s[0])) &&
         strchr("SUHZR", toupper((unsigned char)s[1])) &&
         strchr("AE", toupper((unsigned char)s[2]));
}

/* Line 2 of a Harwell-Boeing header starts with a whole number (what
 * follows is the reader's to check, with its columns). */
static int hb_counts(const char *s)
{
  return isdigit((unsigned char)s[strspn(s, " ")]);
}

/* A coordinate file's first data line: five comma-separated fields
 * (node, dof, node, dof, value), or three fields 'row column value' whose
 * first two are whole numbers (Abaqus' FORMAT=COORDINATE). */
static int coord_line(const char *s)
{
  int commas = 0;
  for (const char *p = s; *p; p++) commas += *p == ',';
  if (commas == 4) return 1;
  char *end;
  const char *p = s;
  for (int k = 0; k < 2; k++, p = end) { /* only the shape is looked at */
    (void)strtoll(p, &end, 10);
    if (end == p || (*end != ' ' && *end != '\t' && *end != ',')) return 0;
    if (*end == ',') end++;
  }
  (void)strtod(p, &end);
  if (end == p) return 0;
  end += strspn(end, " \t");
  return !*end;
}

static int coord_skip(const char *s)
{
  s += strspn(s, " \t");
  return !*s || *s == '#' || *s == '%' || (s[0] == '*' && s[1] == '*');
}

int vi_matrix_detect(const char *path, int *format, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (!path || !format)
    return vi_diag_set(d, path ? path : "", VI_ERR_ARG, 0, 0, "", "", "%s",
                       "vi_matrix_detect: path and format are required");
  *format = VI_MATRIX_AUTO;
  vi_mx_reader r;
  int st = vi_mx_open(&r, path, d);
  if (st) return st;
  char first[3][VI_MM_MAX_LINE + 2];
  int got = 0;
  while (got < 3 && vi_mx_next_line(&r, &st))
    memcpy(first[got++], r.buf, sizeof r.buf);
  if (!st && got >= 1 && !strncasecmp(first[0], "%%MatrixMarket", 14))
    *format = VI_MATRIX_MARKET;
  else if (!st && got == 3 && hb_counts(first[1]) && hb_type(first[2]))
    *format = VI_MATRIX_HARWELL_BOEING;
  else if (!st) { /* the first data line, past comments */
    int k = 0;
    while (k < got && coord_skip(first[k])) k++;
    int data = k < got;
    if (!data)
      while ((data = vi_mx_next_line(&r, &st)) && coord_skip(r.buf)) {
      }
    const char *s = k < got ? first[k] : r.buf;
    if (data && coord_line(s)) *format = VI_MATRIX_COORDINATE;
  }
  fclose(r.f);
  if (st) return st;
  if (*format != VI_MATRIX_AUTO) return VI_OK;
  return vi_diag_set(d, path, VI_ERR_PARSE, got ? 1 : 0, got ? 1 : 0,
                     "format", got ? first[0] : "", "%s",
                     got ? "not a matrix file of a known format: Matrix "
                           "Market starts %%MatrixMarket, Harwell-Boeing "
                           "has a type such as RSA on line 3, a coordinate "
                           "export has lines 'node, dof, node, dof, value' "
                           "or 'row column value'"
                         : "an empty file: no matrix in it");
}

static int check_format(const char *path, int *format, vi_diag *d)
{
  if (*format == VI_MATRIX_AUTO) return vi_matrix_detect(path, format, d);
  if (*format < VI_MATRIX_MARKET || *format > VI_MATRIX_COORDINATE)
    return vi_diag_set(d, path, VI_ERR_ARG, 0, 0, "format", "", "format %d "
                       "is not one of VI_MATRIX_*", *format);
  return VI_OK;
}

int vi_matrix_read_header(const char *path, int format, int *rows, int *cols,
                          int64_t *entries, int *symmetric, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (!path)
    return vi_diag_set(d, "", VI_ERR_ARG, 0, 0, "", "", "%s",
                       "vi_matrix_read_header: path is required");
  int st = check_format(path, &format, d);
  if (st) return st;
  if (format == VI_MATRIX_MARKET)
    return vi_mm_read_header(path, rows, cols, entries, symmetric, d);
  if (format == VI_MATRIX_HARWELL_BOEING)
    return vi_hb_header(path, rows, cols, entries, symmetric, d);
  /* coordinate: no header, the file read whole */
  vi_mm *m = NULL;
  if ((st = vi_coord_load(path, NULL, VI_CSC_LOWER, 0, &m, d))) return st;
  int n = vi_mm_rows(m);
  if (rows) *rows = n;
  if (cols) *cols = n;
  if (symmetric || entries) {
    vi_dofmap *map = NULL;
    if ((st = vi_dofmap_scan(1, &path, 0, &map, d))) {
      vi_mm_destroy(&m);
      return st;
    }
    if (entries) *entries = vi_dofmap_entries(map);
    /* one triangle: as many lines as stored lower entries */
    if (symmetric) *symmetric = vi_dofmap_entries(map) == vi_mm_nnz(m);
    vi_dofmap_destroy(&map);
  }
  vi_mm_destroy(&m);
  return VI_OK;
}

int vi_matrix_load(const char *path, int format, const vi_dofmap *map,
                   int storage, double max_bytes, vi_mm **out, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (out) *out = NULL;
  if (!path || !out || (storage != VI_CSC_LOWER && storage != VI_CSC_FULL) ||
      isnan(max_bytes))
    return vi_diag_set(d, path ? path : "", VI_ERR_ARG, 0, 0, "", "", "%s",
                       "vi_matrix_load: path, out, a storage (VI_CSC_LOWER "
                       "or VI_CSC_FULL) and a limit that is a number are "
                       "required");
  int st = check_format(path, &format, d);
  if (st) return st;
  if (format == VI_MATRIX_MARKET)
    return vi_mm_load_limited(path, storage, max_bytes, out, d);
  if (format == VI_MATRIX_HARWELL_BOEING)
    return vi_hb_load(path, storage, max_bytes, out, d);
  return vi_coord_load(path, map, storage, max_bytes, out, d);
}

const vi_dofmap *vi_scene_dofmap(const vi_scene *s)
{
  return s && s->kind == VI_SCENE_FE ? s->fe.map : NULL;
}

int vi_scene_matrix_format(const vi_scene *s, int which)
{
  static const int slot[3] = {VI_FE_MASS, VI_FE_STIFFNESS, VI_FE_DAMPING};
  if (!s || s->kind != VI_SCENE_FE || which < 0 || which > 2 ||
      !s->fe.path[slot[which]])
    return -1;
  return s->fe.format[slot[which]];
}
