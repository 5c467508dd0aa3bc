/* vi_mmio.c - Matrix Market files into compressed sparse columns
 * (vi_mmio.h): the header, the size line and the entries read line by line
 * with every malformed line named, then sorted into CSC by two counting
 * sorts (rows, then columns, both stable: O(entries + n)), duplicates and
 * symmetry checked on the sorted columns.  Our own reader, after the NIST
 * format description (math.nist.gov/MatrixMarket/formats.html). */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include <fcntl.h>
#include <unistd.h>

#include "vi_matrix_internal.h"

/* Symmetry of a general file checked as vi_model_set_mass checks a dense
 * matrix: |A(i,j) - A(j,i)| <= 1e-12 max |A|. */
#define VI_MM_SYM_TOL 1e-12

/* ---- reading lines (shared by every format) --------------------------- */
typedef vi_mx_reader reader;

int vi_mx_fail_at(reader *r, int code, int col, const char *key,
                  const char *fmt, ...)
{
  char msg[400];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  return vi_diag_set(r->d, r->path, code, r->line,
                     r->line ? (col > 0 ? col : 1) : 0, key,
                     r->line ? r->buf : "", "%s", msg);
}

/* The next line into r->buf: 1, or 0 at the end of the file (or an
 * error, reported: *st).  Read a byte at a time so that a NUL (a binary
 * file) is seen and a long line is refused as soon as it is too long. */
int vi_mx_next_line(reader *r, int *st)
{
  *st = VI_OK;
  size_t len = 0;
  int ch = EOF, nul = 0;
  while ((ch = getc_unlocked(r->f)) != EOF && ch != '\n') {
    r->buf[len++] = (char)ch;
    nul |= ch == 0;
    if (len > VI_MM_MAX_LINE + 1) break; /* too long (CR included): stop */
  }
  r->buf[len] = '\0';
  if (ch == EOF && ferror(r->f)) {
    *st = vi_diag_set(r->d, r->path, VI_ERR_IO, r->line, 0, "", "",
                      "cannot read: %s", strerror(errno));
    return 0;
  }
  if (ch == EOF && len == 0) return 0;
  r->line++;
  if (len > 0 && r->buf[len - 1] == '\r') r->buf[--len] = '\0';
  if (len > VI_MM_MAX_LINE) {
    r->buf[60] = '\0';
    *st = vi_mx_fail(r, VI_ERR_PARSE, "", "a line longer than %d characters",
                  VI_MM_MAX_LINE);
    return 0;
  }
  if (nul) {
    *st = vi_mx_fail(r, VI_ERR_PARSE, "", "%s",
                  "a NUL byte in the line: not a text file");
    return 0;
  }
  return 1;
}

static int blank_or_comment(const char *s)
{
  s += strspn(s, " \t");
  return *s == '\0' || *s == '%';
}

/* The next line that is neither blank nor a comment: 1, or 0 at the end. */
static int next_data(reader *r, int *st)
{
  while (vi_mx_next_line(r, st))
    if (!blank_or_comment(r->buf)) return 1;
  return 0;
}

/* Split r->buf into at most max words (in place); the count, or max + 1
 * when there are more. */
static int words(char *s, char **w, int max)
{
  int k = 0;
  for (char *save = NULL, *t = strtok_r(s, " \t", &save); t;
       t = strtok_r(NULL, " \t", &save)) {
    if (k == max) return max + 1;
    w[k++] = t;
  }
  return k;
}

/* A whole number >= lo written as one word. */
static int whole(const char *s, long long lo, long long *out)
{
  char *end;
  errno = 0;
  long long v = strtoll(s, &end, 10);
  if (end == s || *end || errno == ERANGE || v < lo) return 0;
  *out = v;
  return 1;
}

/* ---- the header --------------------------------------------------------- */
enum { MM_REAL, MM_INTEGER };

typedef struct header {
  int array, field, symmetric;
  int rows, cols;
  int64_t entries; /* values in the file */
} header;

static int read_header(reader *r, header *h)
{
  int st;
  char copy[sizeof r->buf], *w[6];
  if (!vi_mx_next_line(r, &st)) {
    if (st) return st;
    r->line = 1;
    r->buf[0] = '\0';
    return vi_mx_fail(r, VI_ERR_PARSE, "header", "an empty file: expected the "
                   "header %%%%MatrixMarket matrix coordinate real symmetric");
  }
  memcpy(copy, r->buf, sizeof copy);
  int nw = words(copy, w, 5);
  if (nw < 1 || strcasecmp(w[0], "%%MatrixMarket") != 0)
    return vi_mx_fail(r, VI_ERR_PARSE, "header", "not a Matrix Market file: the "
                   "first line must start with %%%%MatrixMarket");
  if (nw != 5)
    return vi_mx_fail(r, VI_ERR_PARSE, "header", "expected %%%%MatrixMarket "
                   "matrix <coordinate|array> <real|integer> "
                   "<general|symmetric>");
  if (!strcasecmp(w[1], "vector"))
    return vi_mx_fail(r, VI_ERR_UNSUPPORTED, "header",
                   "a vector object: M, C and K are matrices");
  if (strcasecmp(w[1], "matrix") != 0)
    return vi_mx_fail(r, VI_ERR_PARSE, "header", "unknown object '%s' (expected "
                   "matrix)", w[1]);
  if (!strcasecmp(w[2], "array"))
    h->array = 1;
  else if (!strcasecmp(w[2], "coordinate"))
    h->array = 0;
  else
    return vi_mx_fail(r, VI_ERR_PARSE, "header", "unknown format '%s' (expected "
                   "coordinate or array)", w[2]);
  if (!strcasecmp(w[3], "real") || !strcasecmp(w[3], "double"))
    h->field = MM_REAL;
  else if (!strcasecmp(w[3], "integer"))
    h->field = MM_INTEGER;
  else if (!strcasecmp(w[3], "complex"))
    return vi_mx_fail(r, VI_ERR_UNSUPPORTED, "header", "a complex matrix: M, C "
                   "and K are real");
  else if (!strcasecmp(w[3], "pattern"))
    return vi_mx_fail(r, VI_ERR_UNSUPPORTED, "header", "a pattern (structure "
                   "only, no values): M, C and K need their values");
  else
    return vi_mx_fail(r, VI_ERR_PARSE, "header", "unknown field '%s' (expected "
                   "real, integer, complex or pattern)", w[3]);
  if (!strcasecmp(w[4], "general"))
    h->symmetric = 0;
  else if (!strcasecmp(w[4], "symmetric"))
    h->symmetric = 1;
  else if (!strcasecmp(w[4], "skew-symmetric"))
    return vi_mx_fail(r, VI_ERR_UNSUPPORTED, "header", "a skew-symmetric matrix: "
                   "M, C and K are symmetric");
  else if (!strcasecmp(w[4], "hermitian"))
    return vi_mx_fail(r, VI_ERR_UNSUPPORTED, "header", "a hermitian matrix (a "
                   "complex one): M, C and K are real symmetric");
  else
    return vi_mx_fail(r, VI_ERR_PARSE, "header", "unknown symmetry '%s' "
                   "(expected general or symmetric)", w[4]);
  /* the size line, after any comments */
  if (!next_data(r, &st))
    return st ? st : vi_mx_fail(r, VI_ERR_PARSE, "size", "the file ends before "
                             "its size line");
  memcpy(copy, r->buf, sizeof copy);
  nw = words(copy, w, 3);
  long long v[3] = {0, 0, 0};
  if (nw != 3 - h->array)
    return vi_mx_fail(r, VI_ERR_PARSE, "size", "expected %s",
                   h->array ? "'rows cols'" : "'rows cols entries'");
  for (int k = 0; k < nw; k++)
    if (!whole(w[k], k < 2 ? 1 : 0, &v[k]))
      return vi_mx_fail(r, VI_ERR_PARSE, "size", "'%s' is not a whole number "
                     "%s", w[k], k < 2 ? ">= 1" : ">= 0");
  if (v[0] > INT_MAX || v[1] > INT_MAX)
    return vi_mx_fail(r, VI_ERR_LIMIT, "size", "a dimension above %d", INT_MAX);
  h->rows = (int)v[0];
  h->cols = (int)v[1];
  if (h->symmetric && h->rows != h->cols)
    return vi_mx_fail(r, VI_ERR_DIM, "size", "a symmetric matrix must be "
                   "square (%d x %d)", h->rows, h->cols);
  double cap = h->symmetric ? 0.5 * (double)h->rows * (h->rows + 1.0)
                            : (double)h->rows * h->cols;
  if (h->array)
    h->entries = (int64_t)cap;
  else {
    if ((double)v[2] > cap)
      return vi_mx_fail(r, VI_ERR_DIM, "size", "%lld entries, more than the "
                     "%.0f a %s %d x %d matrix holds", v[2], cap,
                     h->symmetric ? "symmetric" : "general", h->rows, h->cols);
    h->entries = v[2];
  }
  /* VI_CSC_FULL doubles a symmetric file's entries; CSC indices are int */
  if (2.0 * (double)h->entries > INT_MAX)
    return vi_mx_fail(r, VI_ERR_LIMIT, "size", "%lld entries: more than the "
                   "%d that int indices hold", (long long)h->entries,
                   INT_MAX / 2);
  return VI_OK;
}

/* Regular files only: opened without blocking (a FIFO with no writer
 * would wait for ever) and refused unless fstat says regular (a FIFO, a
 * device such as /dev/zero that never ends, a directory). */
int vi_mx_open(reader *r, const char *path, vi_diag *d)
{
  memset(r, 0, sizeof *r);
  r->path = path;
  r->d = d;
  int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) { /* the code returned as such: the analyser follows it */
    vi_diag_set(d, path, VI_ERR_IO, 0, 0, "", "", "cannot open: %s",
                strerror(errno));
    return VI_ERR_IO;
  }
  struct stat sb;
  if (fstat(fd, &sb) || !S_ISREG(sb.st_mode)) {
    mode_t m = sb.st_mode;
    close(fd);
    vi_diag_set(d, path, VI_ERR_IO, 0, 0, "", "", "not a regular file (%s): "
                "a matrix is read from a file",
                S_ISFIFO(m)  ? "a FIFO"
                : S_ISCHR(m) ? "a character device"
                : S_ISDIR(m) ? "a directory"
                             : "not a plain file");
    return VI_ERR_IO;
  }
  int fl = fcntl(fd, F_GETFL);
  if (fl >= 0) (void)fcntl(fd, F_SETFL, fl & ~O_NONBLOCK);
  r->f = fdopen(fd, "r");
  if (!r->f) {
    close(fd);
    vi_diag_set(d, path, VI_ERR_IO, 0, 0, "", "", "cannot open: %s",
                strerror(errno));
    return VI_ERR_IO;
  }
  return VI_OK;
}

int vi_mx_check_room(reader *r, double least, int64_t entries,
                     const char *key)
{
  struct stat sb;
  long at = ftell(r->f);
  if (!fstat(fileno(r->f), &sb) && S_ISREG(sb.st_mode) && at >= 0 &&
      (double)(sb.st_size - at) < least)
    return vi_mx_fail(r, VI_ERR_PARSE, key, "%lld entries need at least %.0f "
                   "more bytes, the file has %lld (truncated?)",
                   (long long)entries, least, (long long)(sb.st_size - at));
  return VI_OK;
}

int vi_mm_read_header(const char *path, int *rows, int *cols,
                      int64_t *entries, int *symmetric, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (!path)
    return vi_diag_set(d, "", VI_ERR_ARG, 0, 0, "", "", "%s",
                       "vi_mm_read_header: path is required");
  reader r;
  header h;
  memset(&h, 0, sizeof h);
  int st = vi_mx_open(&r, path, d);
  if (st) return st;
  st = read_header(&r, &h);
  fclose(r.f);
  if (st) return st;
  if (rows) *rows = h.rows;
  if (cols) *cols = h.cols;
  if (entries) *entries = h.entries;
  if (symmetric) *symmetric = h.symmetric;
  return VI_OK;
}

/* ---- the entries -------------------------------------------------------- */
void vi_mx_trip_free(vi_mx_triplets *t)
{
  free(t->i);
  free(t->j);
  free(t->line);
  free(t->v);
  memset(t, 0, sizeof *t);
}

int vi_mx_trip_alloc(vi_mx_triplets *t, int64_t cap)
{
  size_t c = (size_t)(cap > 0 ? cap : 1);
  t->i = malloc(c * sizeof(int));
  t->j = malloc(c * sizeof(int));
  t->line = malloc(c * sizeof(int));
  t->v = malloc(c * sizeof(double));
  t->count = 0;
  t->cap = (int64_t)c;
  return t->i && t->j && t->line && t->v;
}

/* One value as written: a finite real, or (field integer) a whole number. */
static int parse_value(reader *r, const header *h, const char *s,
                       const char *key, double *out)
{
  char *end;
  if (h->field == MM_INTEGER) {
    errno = 0;
    long long v = strtoll(s, &end, 10);
    if (end == s || *end || errno == ERANGE)
      return vi_mx_fail(r, VI_ERR_PARSE, key, "'%s' is not a whole number (the "
                     "field is integer)", s);
    *out = (double)v;
    return VI_OK;
  }
  errno = 0;
  double v = strtod(s, &end);
  if (end == s || *end)
    return vi_mx_fail(r, VI_ERR_PARSE, key, "'%s' is not a number", s);
  if (!isfinite(v) || (errno == ERANGE && fabs(v) > 1.0))
    return vi_mx_fail(r, VI_ERR_NONFINITE, key, "'%s' is not a finite number",
                   s);
  *out = v;
  return VI_OK;
}

static int read_entries(reader *r, const header *h, vi_mx_triplets *t)
{
  char key[48], *w[4];
  int st;
  int64_t k = 0;
  int ai = 0, aj = 0; /* array: the position of the next value */
  for (; k < h->entries; k++) {
    snprintf(key, sizeof key, "entry %lld", (long long)k + 1);
    if (!next_data(r, &st)) {
      if (st) return st;
      return vi_mx_fail(r, VI_ERR_PARSE, key, "the file ends after %lld of its "
                     "%lld entries (truncated?)", (long long)k,
                     (long long)h->entries);
    }
    char copy[sizeof r->buf];
    memcpy(copy, r->buf, sizeof copy);
    int want = h->array ? 1 : 3, nw = words(copy, w, 3);
    if (nw != want)
      return vi_mx_fail(r, VI_ERR_PARSE, key, "expected %s, got %d word%s",
                     h->array ? "one value" : "'row column value'", nw,
                     nw == 1 ? "" : "s");
    double v = 0.0;
    int i, j;
    if (h->array) {
      i = ai;
      j = aj;
      if ((st = parse_value(r, h, w[0], key, &v))) return st;
      /* column by column; a symmetric array holds the lower triangle */
      if (++ai == h->rows) {
        aj++;
        ai = h->symmetric ? aj : 0;
      }
      if (v == 0.0) continue; /* a dense file's zeros are not entries */
    } else {
      long long li, lj;
      if (!whole(w[0], LLONG_MIN, &li) || !whole(w[1], LLONG_MIN, &lj))
        return vi_mx_fail(r, VI_ERR_PARSE, key, "'%s %s' are not whole numbers",
                       w[0], w[1]);
      if (li < 1 || li > h->rows || lj < 1 || lj > h->cols)
        return vi_mx_fail(r, VI_ERR_DIM, key, "index (%lld, %lld) outside the "
                       "%d x %d matrix (indices are 1-based)", li, lj,
                       h->rows, h->cols);
      if (h->symmetric && li < lj)
        return vi_mx_fail(r, VI_ERR_NOT_SYMMETRIC, key, "entry (%lld, %lld) above "
                       "the diagonal of a symmetric file (the format stores "
                       "the lower triangle, i >= j)", li, lj);
      if ((st = parse_value(r, h, w[2], key, &v))) return st;
      i = (int)li - 1;
      j = (int)lj - 1;
    }
    t->i[t->count] = i;
    t->j[t->count] = j;
    t->v[t->count] = v;
    t->line[t->count] = r->line;
    t->count++;
  }
  /* nothing but comments may follow */
  if (next_data(r, &st))
    return vi_mx_fail(r, VI_ERR_PARSE, "entry", "more entries than the %lld "
                   "of the size line", (long long)h->entries);
  return st;
}

/* ---- sorting into columns ----------------------------------------------- */
/* perm: the entries ordered by column, then row (two stable counting
 * sorts); colptr [cols + 1] the columns' starts. */
static int sort_csc(const vi_mx_triplets *t, int rows, int cols, int *colptr,
                    int *perm)
{
  size_t nb = (size_t)(rows > cols ? rows : cols) + 1;
  int *cnt = calloc(nb, sizeof(int)), *tmp = malloc(((size_t)t->count + 1) *
                                                    sizeof(int));
  if (!cnt || !tmp) {
    free(cnt);
    free(tmp);
    return VI_ERR_NOMEM;
  }
  for (int64_t k = 0; k < t->count; k++) cnt[t->i[k] + 1]++;
  for (int i = 0; i < rows; i++) cnt[i + 1] += cnt[i];
  for (int64_t k = 0; k < t->count; k++) tmp[cnt[t->i[k]]++] = (int)k;
  memset(colptr, 0, ((size_t)cols + 1) * sizeof(int));
  for (int64_t k = 0; k < t->count; k++) colptr[t->j[k] + 1]++;
  for (int j = 0; j < cols; j++) colptr[j + 1] += colptr[j];
  memcpy(cnt, colptr, (size_t)cols * sizeof(int));
  for (int64_t k = 0; k < t->count; k++) {
    int e = tmp[k];
    perm[cnt[t->j[e]]++] = e;
  }
  free(cnt);
  free(tmp);
  return VI_OK;
}

/* Position of row i in column j of a sorted CSC, -1 if absent. */
static int find_entry(const int *colptr, const int *rowind, int i, int j)
{
  int lo = colptr[j], hi = colptr[j + 1] - 1;
  while (lo <= hi) {
    int mid = lo + (hi - lo) / 2;
    if (rowind[mid] == i) return mid;
    if (rowind[mid] < i)
      lo = mid + 1;
    else
      hi = mid - 1;
  }
  return -1;
}

/* The triplets (symmetric files mirrored first for VI_CSC_FULL) into CSC
 * arrays; duplicates refused; a general file kept whole or, for
 * VI_CSC_LOWER, checked for symmetry and its lower triangle averaged.  The
 * arrays are made first and handed to a new vi_mm only on success. */
int vi_mx_build(reader *r, int rows, int cols, int symmetric,
                vi_mx_triplets *t, int storage, vi_mm **out)
{
  if (symmetric && storage == VI_CSC_FULL) {
    int64_t n0 = t->count;
    for (int64_t k = 0; k < n0; k++)
      if (t->i[k] != t->j[k]) {
        t->i[t->count] = t->j[k];
        t->j[t->count] = t->i[k];
        t->v[t->count] = t->v[k];
        t->line[t->count] = t->line[k];
        t->count++;
      }
  }
  size_t cnt = (size_t)t->count + 1;
  int *perm = malloc(cnt * sizeof(int)),
      *colptr = malloc(((size_t)cols + 1) * sizeof(int)),
      *rowind = malloc(cnt * sizeof(int));
  double *val = malloc(cnt * sizeof(double)), *avg = NULL;
  int st = VI_OK, nnz = (int)t->count;
  if (!perm || !colptr || !rowind || !val ||
      sort_csc(t, rows, cols, colptr, perm)) {
    st = vi_diag_nomem(r->d, r->path);
    goto out;
  }
  double amax = 0;
  for (int64_t k = 0; k < t->count; k++) {
    int e = perm[k];
    rowind[k] = t->i[e];
    val[k] = t->v[e];
    amax = fmax(amax, fabs(t->v[e]));
    if (k > 0 && t->i[e] == t->i[perm[k - 1]] &&
        t->j[e] == t->j[perm[k - 1]]) {
      int l0 = t->line[perm[k - 1]], l1 = t->line[e];
      if (l0 > l1) {
        int sw = l0;
        l0 = l1;
        l1 = sw;
      }
      /* report at the later line, naming the earlier */
      char at[48];
      if (l0 == l1) /* a fixed-width file holds several entries a line */
        snprintf(at, sizeof at, "both on line %d", l0);
      else
        snprintf(at, sizeof at, "at lines %d and %d", l0, l1);
      st = vi_diag_set(r->d, r->path, VI_ERR_PARSE, l1, 1, "entry", "",
                       "entry (%d, %d) given twice, %s (duplicates are "
                       "refused, not summed)", t->i[e] + 1, t->j[e] + 1, at);
      goto out;
    }
  }
  if (!symmetric && storage == VI_CSC_LOWER) {
    if (rows != cols) {
      st = vi_diag_set(r->d, r->path, VI_ERR_DIM, 0, 0, "size", "",
                       "a %d x %d matrix is not square: lower-triangle "
                       "storage needs a symmetric matrix", rows, cols);
      goto out;
    }
    /* every entry against its mirror (absent: 0), the average kept ... */
    if (!(avg = malloc(cnt * sizeof(double)))) {
      st = vi_diag_nomem(r->d, r->path);
      goto out;
    }
    for (int j = 0; j < cols; j++)
      for (int k = colptr[j]; k < colptr[j + 1]; k++) {
        int i = rowind[k], q = find_entry(colptr, rowind, j, i);
        double a = val[k], b = q >= 0 ? val[q] : 0.0;
        if (fabs(a - b) > VI_MM_SYM_TOL * amax) {
          int la = t->line[perm[k]];
          char other[48] = " (absent)";
          if (q >= 0)
            snprintf(other, sizeof other, " (line %d)", t->line[perm[q]]);
          st = vi_diag_set(r->d, r->path, VI_ERR_NOT_SYMMETRIC, la, 1,
                           "entry", "", "not symmetric: A(%d,%d) = %.17g "
                           "(line %d) but A(%d,%d) = %.17g%s", i + 1, j + 1,
                           a, la, j + 1, i + 1, b, other);
          goto out;
        }
        avg[k] = 0.5 * (a + b);
      }
    /* ... then the lower triangle, exactly symmetric as the model stores a
     * dense matrix */
    int kept = 0;
    for (int j = 0; j < cols; j++) {
      int start = colptr[j], end = colptr[j + 1];
      colptr[j] = kept;
      for (int k = start; k < end; k++)
        if (rowind[k] >= j) {
          rowind[kept] = rowind[k];
          val[kept] = avg[k];
          kept++;
        }
    }
    colptr[cols] = kept;
    nnz = kept;
  }
  vi_mm *m = calloc(1, sizeof *m);
  if (!m) {
    st = vi_diag_nomem(r->d, r->path);
    goto out;
  }
  m->rows = rows;
  m->cols = cols;
  m->storage = storage;
  m->nnz = nnz;
  m->colptr = colptr;
  m->rowind = rowind;
  m->val = val;
  colptr = rowind = NULL;
  val = NULL;
  *out = m;
out:
  free(perm);
  free(colptr);
  free(rowind);
  free(val);
  free(avg);
  return st;
}

int vi_mm_load_limited(const char *path, int storage, double max_bytes,
                       vi_mm **out, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (out) *out = NULL;
  if (!path || !out || (storage != VI_CSC_LOWER && storage != VI_CSC_FULL) ||
      isnan(max_bytes))
    return vi_diag_set(d, path ? path : "", VI_ERR_ARG, 0, 0, "", "", "%s",
                       "vi_mm_load: path, out, a storage (VI_CSC_LOWER or "
                       "VI_CSC_FULL) and a limit that is a number are "
                       "required");
  reader r;
  header h;
  memset(&h, 0, sizeof h);
  int st = vi_mx_open(&r, path, d);
  if (st) return st;
  if ((st = read_header(&r, &h))) {
    fclose(r.f);
    return st;
  }
  /* triplets (20 bytes each, twice as many for a mirrored file) + the
   * sort's two int arrays + the CSC copy */
  int64_t cap = h.symmetric && storage == VI_CSC_FULL ? 2 * h.entries
                                                     : h.entries;
  double need = 40.0 * (double)cap + 12.0 * (double)h.cols;
  if (max_bytes > 0 && need > max_bytes) {
    fclose(r.f);
    return vi_mx_fail(&r, VI_ERR_LIMIT, "size", "reading %lld entries needs "
                   "about %.3g MB, more than the %.3g MB allowed",
                   (long long)h.entries, need / 1048576.0,
                   max_bytes / 1048576.0);
  }
  /* the rest of a regular file must hold the entries the size line
   * promises ("i j v" or "v" and a line end each, the last line's end
   * optional), before storage for them
   * is allocated: a short file cannot ask for gigabytes */
  double least = (h.array ? 2.0 : 6.0) * (double)h.entries - 1.0;
  if ((st = vi_mx_check_room(&r, least, h.entries, "size"))) {
    fclose(r.f);
    return st;
  }
  vi_mx_triplets t;
  if (!vi_mx_trip_alloc(&t, cap)) {
    vi_mx_trip_free(&t);
    fclose(r.f);
    return vi_diag_nomem(d, path);
  }
  st = read_entries(&r, &h, &t);
  fclose(r.f);
  if (!st) st = vi_mx_build(&r, h.rows, h.cols, h.symmetric, &t, storage, out);
  vi_mx_trip_free(&t);
  return st;
}

int vi_mm_load(const char *path, int storage, vi_mm **out, vi_diag *d)
{
  return vi_mm_load_limited(path, storage, 0, out, d);
}

void vi_mm_destroy(vi_mm **mm)
{
  if (!mm || !*mm) return;
  free((*mm)->colptr);
  free((*mm)->rowind);
  free((*mm)->val);
  free(*mm);
  *mm = NULL;
}

int vi_mm_rows(const vi_mm *mm) { return mm ? mm->rows : 0; }
int vi_mm_cols(const vi_mm *mm) { return mm ? mm->cols : 0; }
int vi_mm_nnz(const vi_mm *mm) { return mm ? mm->nnz : 0; }
int vi_mm_storage_kind(const vi_mm *mm) { return mm ? mm->storage : -1; }
const int *vi_mm_colptr(const vi_mm *mm) { return mm ? mm->colptr : NULL; }
const int *vi_mm_rowind(const vi_mm *mm) { return mm ? mm->rowind : NULL; }
const double *vi_mm_values(const vi_mm *mm) { return mm ? mm->val : NULL; }
