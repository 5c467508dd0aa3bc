/* vi_hbio.c - Harwell-Boeing and Rutherford-Boeing files into compressed
 * sparse columns (vi_mmio.h: VI_MATRIX_HARWELL_BOEING).  Our own reader,
 * after the formats' descriptions: Duff, Grimes and Lewis, "Users' guide
 * for the Harwell-Boeing sparse matrix collection" (1992) and "The
 * Rutherford-Boeing sparse matrix collection" (RAL-TR-97-031), and
 * Fortran's rules for reading I, E, D, F and G fields (ISO/IEC 1539,
 * "numeric editing").  The header is checked whole (its counts against its
 * formats) before anything is allocated; then the three sections are read
 * field by field, each field refused with its line and column, straight
 * into the triplets that vi_mx_build (vi_mmio.c) sorts into CSC. */
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "vi_matrix_internal.h"

typedef vi_mx_reader reader;

/* One section's Fortran format: r fields a line, w columns each; values
 * with d fraction digits (for a field written without a point) and the
 * scale factor k of kP (for a field written without an exponent). */
typedef struct ffmt {
  int per_line, width, digits, scale, integer;
  char text[48]; /* as written (blanks out, capitals), for messages */
} ffmt;

typedef struct hb_header {
  int totcrd, ptrcrd, indcrd, valcrd, rhscrd;
  int rows, cols, symmetric, integer_values;
  int64_t nnz;
  ffmt ptr, ind, val;
} hb_header;

/* Columns [col, col + width) of s (shorter when s ends), blanks trimmed,
 * into out; the 1-based column of its first character in *at. */
static void field(const char *s, int col, int width, char *out, size_t len,
                  int *at)
{
  size_t n = strlen(s), b = (size_t)col,
         e = (size_t)col + (size_t)width < n ? (size_t)col + (size_t)width : n;
  if (b > n) b = n;
  while (b < e && (s[b] == ' ' || s[b] == '\t')) b++;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t')) e--;
  size_t k = e - b < len - 1 ? e - b : len - 1;
  memcpy(out, s + b, k);
  out[k] = '\0';
  *at = (int)b + 1;
}

/* A whole number as Fortran's I edit reads it (blanks trimmed): an
 * optional sign and digits, nothing else; 1 if it is one within int. */
static int fortran_int(const char *s, long long *out)
{
  const char *p = s + (*s == '+' || *s == '-');
  if (!*p || strspn(p, "0123456789") != strlen(p)) return 0;
  errno = 0;
  long long v = strtoll(s, NULL, 10);
  if (errno == ERANGE || v < INT_MIN || v > INT_MAX) return 0;
  *out = v;
  return 1;
}

/* A header's whole number in columns [col, col + 14): 0 when blank and
 * optional. */
static int head_int(reader *r, int col, const char *name, int required,
                    long long lo, int *out)
{
  char s[32];
  int at;
  long long v = 0;
  field(r->buf, col, 14, s, sizeof s, &at);
  if (!*s) {
    if (!required) {
      *out = 0;
      return VI_OK;
    }
    return vi_mx_fail_at(r, VI_ERR_PARSE, col + 1, "header", "%s missing "
                         "(columns %d-%d: a whole number, I14)", name,
                         col + 1, col + 14);
  }
  if (!fortran_int(s, &v))
    return vi_mx_fail_at(r, VI_ERR_PARSE, at, "header", "%s: '%s' is not a "
                         "whole number in columns %d-%d (I14)", name, s,
                         col + 1, col + 14);
  if (v < lo)
    return vi_mx_fail_at(r, VI_ERR_PARSE, at, "header", "%s = %lld: must be "
                         ">= %lld", name, v, lo);
  *out = (int)v;
  return VI_OK;
}

/* Nothing but blanks from column col on. */
static int rest_blank(reader *r, int col, const char *what)
{
  size_t n = strlen(r->buf);
  for (size_t k = (size_t)col; k < n; k++)
    if (r->buf[k] != ' ' && r->buf[k] != '\t')
      return vi_mx_fail_at(r, VI_ERR_PARSE, (int)k + 1, "header", "text "
                           "after %s (from column %d)", what, (int)k + 1);
  return VI_OK;
}

/* Digits at *p into *v (at most 9 of them); 1 if there was one. */
static int digits(const char **p, int *v)
{
  int k = 0;
  *v = 0;
  while (isdigit((unsigned char)**p)) {
    if (k++ < 9) *v = *v * 10 + (**p - '0');
    ++*p;
  }
  return k > 0 && k <= 9;
}

/* A format such as (10I8), (4E20.12), (1P5D16.9), (1P,4E20.12), (5ES16.8E3):
 * [kP[,]][r]X w[.d[Ee]] with X one of I, E, D, F, G, ES, EN; blanks
 * ignored, either case.  0, or 1 with *why set. */
static int parse_format(const char *in, ffmt *f, const char **why)
{
  char s[sizeof f->text];
  size_t k = 0;
  for (const char *p = in; *p && k < sizeof s - 1; p++)
    if (*p != ' ') s[k++] = (char)toupper((unsigned char)*p);
  s[k] = '\0';
  snprintf(f->text, sizeof f->text, "%s", s);
  const char *p = s;
  *why = "expected a format such as (10I8) or (4E20.12)";
  if (*p++ != '(' || k < 2 || s[k - 1] != ')') return 1;
  s[k - 1] = '\0';
  int sign = 1, n = 0;
  f->scale = 0;
  f->per_line = 1;
  /* a scale factor kP (a signed number before P), then a repeat count */
  const char *q = p + (*p == '-' || *p == '+');
  if (isdigit((unsigned char)*q)) {
    const char *t = q;
    int v;
    digits(&t, &v);
    if (*t == 'P') {
      sign = *p == '-' ? -1 : 1;
      f->scale = sign * v;
      p = t + 1;
      if (*p == ',') p++;
    }
  }
  if (isdigit((unsigned char)*p)) {
    if (!digits(&p, &n) || n < 1) return 1;
    f->per_line = n;
  }
  f->integer = *p == 'I';
  if (*p == 'I' || *p == 'F' || *p == 'G')
    p++;
  else if (*p == 'E' || *p == 'D') {
    p++;
    if (p[-1] == 'E' && (*p == 'S' || *p == 'N')) p++; /* ES, EN */
  } else {
    *why = "not an I, E, D, F or G edit descriptor";
    return 1;
  }
  if (!digits(&p, &f->width) || f->width < 1) {
    *why = "no field width";
    return 1;
  }
  f->digits = 0;
  if (*p == '.') {
    p++;
    if (!digits(&p, &f->digits)) return 1;
    if (*p == 'E' && !f->integer) { /* an exponent width: read alike */
      p++;
      if (!digits(&p, &n)) return 1;
    }
  } else if (!f->integer) {
    *why = "a real field needs its digits (w.d)";
    return 1;
  }
  if (*p) {
    *why = "more than one edit descriptor (or nested parentheses)";
    return 1;
  }
  if (f->digits > f->width) { /* also bounds a value's text (fortran_real) */
    *why = "more fraction digits than the field's width";
    return 1;
  }
  if (f->integer && f->scale) {
    *why = "a scale factor (P) with an integer field";
    return 1;
  }
  if ((double)f->per_line * f->width > VI_MM_MAX_LINE) {
    *why = "its lines would be longer than 1024 characters";
    return 1;
  }
  return 0;
}

/* Lines a section of count fields takes in format f. */
static int64_t lines_for(int64_t count, const ffmt *f)
{
  int r = f->per_line > 0 ? f->per_line : 1; /* parse_format: >= 1 */
  return (count + r - 1) / r;
}

static int check_format(reader *r, int col, int width, const char *name,
                        int want_int, ffmt *f)
{
  char s[32];
  int at;
  const char *why;
  field(r->buf, col, width, s, sizeof s, &at);
  if (!*s)
    return vi_mx_fail_at(r, VI_ERR_PARSE, col + 1, "header", "%s missing "
                         "(columns %d-%d)", name, col + 1, col + width);
  if (parse_format(s, f, &why))
    return vi_mx_fail_at(r, VI_ERR_PARSE, at, "header", "%s '%s': %s", name,
                         s, why);
  if (want_int == 1 && !f->integer)
    return vi_mx_fail_at(r, VI_ERR_PARSE, at, "header", "%s '%s': pointers "
                         "and indices are integers (an I format)", name, s);
  if (want_int == 0 && f->integer)
    return vi_mx_fail_at(r, VI_ERR_PARSE, at, "header", "%s '%s': a real "
                         "matrix's values need an E, D, F or G format", name,
                         s);
  return VI_OK;
}

/* Line 3's type: R or I values, S, U or R(ectangular) shape, A(ssembled). */
static int check_type(reader *r, hb_header *h)
{
  char t[4] = {0};
  for (int k = 0; k < 3 && r->buf[k]; k++)
    t[k] = (char)toupper((unsigned char)r->buf[k]);
  if (strlen(t) < 3 || !strchr("RCPIQ", t[0]) || !strchr("SUHZR", t[1]) ||
      !strchr("AE", t[2]))
    return vi_mx_fail_at(r, VI_ERR_PARSE, 1, "header", "type '%.3s': "
                         "expected three letters such as RSA (value R, C, "
                         "P, I; shape S, U, H, Z, R; A assembled or E "
                         "elemental)", r->buf);
  if (t[0] == 'C' || t[0] == 'Q')
    return vi_mx_fail_at(r, VI_ERR_UNSUPPORTED, 1, "header", "type %s: a "
                         "complex matrix; M, C and K are real", t);
  if (t[0] == 'P')
    return vi_mx_fail_at(r, VI_ERR_UNSUPPORTED, 1, "header", "type %s: a "
                         "pattern (structure only, no values); M, C and K "
                         "need their values", t);
  if (t[1] == 'H' || t[1] == 'Z')
    return vi_mx_fail_at(r, VI_ERR_UNSUPPORTED, 1, "header", "type %s: a "
                         "%s matrix; M, C and K are real symmetric", t,
                         t[1] == 'H' ? "hermitian" : "skew-symmetric");
  if (t[2] == 'E')
    return vi_mx_fail_at(r, VI_ERR_UNSUPPORTED, 1, "header", "type %s: "
                         "elemental (unassembled element matrices); write "
                         "the assembled matrix (%c%cA)", t, t[0], t[1]);
  h->symmetric = t[1] == 'S';
  h->integer_values = t[0] == 'I';
  return VI_OK;
}

/* The header's four lines (five with right-hand sides): every count
 * checked against the formats, so that what follows has a known size. */
static int read_hb_header(reader *r, hb_header *h)
{
  int st;
  memset(h, 0, sizeof *h);
  if (!vi_mx_next_line(r, &st)) {
    if (st) return st;
    r->line = 1;
    return vi_mx_fail(r, VI_ERR_PARSE, "header", "%s", "an empty file: "
                      "expected a Harwell-Boeing header (title and key)");
  }
  const char *what[4] = {"the title line", "line 2 (TOTCRD PTRCRD INDCRD "
                         "VALCRD [RHSCRD], I14 each)", "line 3 (type, NROW "
                         "NCOL NNZERO [NELTVL])", "line 4 (PTRFMT INDFMT "
                         "VALFMT [RHSFMT])"};
  for (int k = 1; k < 4; k++)
    if (!vi_mx_next_line(r, &st))
      return st ? st : vi_mx_fail(r, VI_ERR_PARSE, "header", "the file ends "
                                  "before %s (truncated header)", what[k]);
    else if (k == 1) { /* line 2: the line counts */
      if ((st = head_int(r, 0, "TOTCRD", 1, 1, &h->totcrd)) ||
          (st = head_int(r, 14, "PTRCRD", 1, 1, &h->ptrcrd)) ||
          (st = head_int(r, 28, "INDCRD", 1, 0, &h->indcrd)) ||
          (st = head_int(r, 42, "VALCRD", 1, 0, &h->valcrd)) ||
          (st = head_int(r, 56, "RHSCRD", 0, 0, &h->rhscrd)) ||
          (st = rest_blank(r, 70, "RHSCRD")))
        return st;
    } else if (k == 2) { /* line 3: type and sizes */
      int neltvl = 0, rows = 0, cols = 0, nnz = 0;
      if ((st = check_type(r, h))) return st;
      for (int c = 3; c < 14 && r->buf[c]; c++)
        if (r->buf[c] != ' ')
          return vi_mx_fail_at(r, VI_ERR_PARSE, c + 1, "header", "%s",
                               "columns 4-14 of line 3 must be blank (the "
                               "type is A3, the sizes start at column 15)");
      if ((st = head_int(r, 14, "NROW", 1, 1, &rows)) ||
          (st = head_int(r, 28, "NCOL", 1, 1, &cols)) ||
          (st = head_int(r, 42, "NNZERO", 1, 0, &nnz)) ||
          (st = head_int(r, 56, "NELTVL", 0, 0, &neltvl)) ||
          (st = rest_blank(r, 70, "NELTVL")))
        return st;
      h->rows = rows;
      h->cols = cols;
      h->nnz = nnz;
      if (h->symmetric && rows != cols)
        return vi_mx_fail_at(r, VI_ERR_DIM, 15, "header", "a symmetric "
                             "matrix must be square (%d x %d)", rows, cols);
      double cap = h->symmetric ? 0.5 * (double)rows * (rows + 1.0)
                                : (double)rows * cols;
      if ((double)nnz > cap)
        return vi_mx_fail_at(r, VI_ERR_DIM, 43, "header", "NNZERO = %d, "
                             "more than the %.0f a %d x %d matrix holds", nnz,
                             cap, rows, cols);
      if (2.0 * nnz > INT_MAX)
        return vi_mx_fail_at(r, VI_ERR_LIMIT, 43, "header", "NNZERO = %d: "
                             "more than the %d that int indices hold", nnz,
                             INT_MAX / 2);
    } else { /* line 4: the formats */
      if ((st = check_format(r, 0, 16, "PTRFMT", 1, &h->ptr)) ||
          (st = check_format(r, 16, 16, "INDFMT", 1, &h->ind)) ||
          (st = check_format(r, 32, 20, "VALFMT", h->integer_values,
                             &h->val)))
        return st;
    }
  /* the counts against the formats: each section has its exact lines */
  const struct {
    const char *name;
    int have, col;
    int64_t count;
    const ffmt *f;
  } sec[3] = {{"PTRCRD", h->ptrcrd, 15, (int64_t)h->cols + 1, &h->ptr},
              {"INDCRD", h->indcrd, 29, h->nnz, &h->ind},
              {"VALCRD", h->valcrd, 43, h->nnz, &h->val}};
  for (int k = 0; k < 3; k++) {
    int64_t want = lines_for(sec[k].count, sec[k].f);
    if (sec[k].have != want)
      return vi_diag_set(r->d, r->path, VI_ERR_PARSE, 2, sec[k].col, "header",
                         "", "%s = %d, but %lld %s in the format %s take "
                         "%lld line%s", sec[k].name, sec[k].have,
                         (long long)sec[k].count,
                         k == 0 ? "pointers (NCOL + 1)"
                         : k == 1 ? "row indices (NNZERO)" : "values (NNZERO)",
                         sec[k].f->text, (long long)want, want == 1 ? "" : "s");
  }
  int64_t sum = (int64_t)h->ptrcrd + h->indcrd + h->valcrd + h->rhscrd;
  if (h->totcrd != sum)
    return vi_diag_set(r->d, r->path, VI_ERR_PARSE, 2, 1, "header", "",
                       "TOTCRD = %d, but PTRCRD + INDCRD + VALCRD + RHSCRD "
                       "= %lld", h->totcrd, (long long)sum);
  /* Harwell-Boeing's fifth line (RHSTYP NRHS NRHSIX): read past, unused */
  if (h->rhscrd > 0 && !vi_mx_next_line(r, &st))
    return st ? st : vi_mx_fail(r, VI_ERR_PARSE, "header", "%s", "the file "
                                "ends before line 5 (RHSCRD > 0: the "
                                "right-hand sides' header)");
  return VI_OK;
}

/* ---- the sections --------------------------------------------------------
 * A value as Fortran's E, D, F, G edits read it: sign, digits with an
 * optional point (none: the last d digits are the fraction), an optional
 * exponent (a letter E, D or Q with an optional sign, or a bare sign);
 * without an exponent, kP divides by 10^k.  0, 1 (not a number) or 2 (not
 * finite). */
static int fortran_real(const char *s, const ffmt *f, double *out)
{
  char c[VI_MM_MAX_LINE + 48];
  const char *p = s;
  size_t k = 0;
  if (*p == '+' || *p == '-') c[k++] = *p++;
  const char *m0 = p;
  int point = 0, nd = 0;
  char mant[VI_MM_MAX_LINE + 2];
  size_t nm = 0;
  for (; isdigit((unsigned char)*p) || (*p == '.' && !point); p++)
    if (*p == '.')
      point = (int)nm + 1;
    else {
      mant[nm++] = *p;
      nd++;
    }
  if (nd == 0) {
    /* Fortran 2003 reads Inf, Infinity and NaN: refused as not finite */
    if (!strncasecmp(m0, "inf", 3) || !strncasecmp(m0, "nan", 3)) return 2;
    return 1;
  }
  /* the mantissa with its point placed */
  size_t at = point ? (size_t)point - 1
                    : (nm > (size_t)f->digits ? nm - (size_t)f->digits : 0);
  if (!point && nm < (size_t)f->digits) {
    c[k++] = '.';
    for (size_t z = nm; z < (size_t)f->digits; z++) c[k++] = '0';
    memcpy(c + k, mant, nm);
    k += nm;
  } else {
    memcpy(c + k, mant, at);
    k += at;
    c[k++] = '.';
    memcpy(c + k, mant + at, nm - at);
    k += nm - at;
  }
  long e = -f->scale;
  if (*p) {
    if (strchr("EeDdQq", *p)) p++;
    else if (*p != '+' && *p != '-') return 1;
    int neg = *p == '-';
    if (*p == '+' || *p == '-') p++;
    if (!isdigit((unsigned char)*p)) return 1;
    e = 0;
    for (; isdigit((unsigned char)*p); p++)
      if (e < 100000) e = e * 10 + (*p - '0'); /* beyond: not finite anyway */
    if (*p) return 1;
    e = neg ? -e : e;
  }
  char ed[16]; /* "e" and the exponent, written by hand: snprintf is slow */
  int ne = 0;
  for (long a = e < 0 ? -e : e; ne == 0 || a > 0; a /= 10)
    ed[ne++] = (char)('0' + a % 10);
  c[k++] = 'e';
  if (e < 0) c[k++] = '-';
  while (ne) c[k++] = ed[--ne];
  c[k] = '\0';
  errno = 0;
  char *end;
  double v = strtod(c, &end);
  if (*end) return 1;
  if (!isfinite(v) || (errno == ERANGE && fabs(v) > 1.0)) return 2;
  *out = v;
  return 0;
}

typedef struct section {
  const char *name, *item; /* "pointers", "pointer" */
  const ffmt *f;
  int64_t count;
} section;

/* Field q of the current line into s; refuses a blank or short field and
 * blanks inside a number. */
static int get_field(reader *r, const section *sc, int q, int64_t k,
                     char *s, size_t len)
{
  int w = sc->f->width, at;
  char key[48]; /* made only for a message: formatting costs more than parsing */
  field(r->buf, q * w, w, s, len, &at);
  if (*s && !strpbrk(s, " \t")) return VI_OK;
  snprintf(key, sizeof key, "%s %lld", sc->item, (long long)k + 1);
  if (!*s)
    return vi_mx_fail_at(r, VI_ERR_PARSE, q * w + 1, key, "%s %lld of %lld "
                         "missing: columns %d-%d blank (format %s)", sc->item,
                         (long long)k + 1, (long long)sc->count, q * w + 1,
                         q * w + w, sc->f->text);
  return vi_mx_fail_at(r, VI_ERR_PARSE, at, key, "'%s': a blank inside "
                         "the field in columns %d-%d (does the format %s "
                         "match the file?)", s, q * w + 1, q * w + w,
                         sc->f->text);
}

/* The next line of a section, which must be there and hold nothing after
 * its nf fields. */
static int section_line(reader *r, const section *sc, int64_t k, int nf)
{
  int st;
  if (!vi_mx_next_line(r, &st))
    return st ? st : vi_mx_fail(r, VI_ERR_PARSE, sc->name, "the file ends "
                                "after %lld of its %lld %s (truncated?)",
                                (long long)k, (long long)sc->count, sc->name);
  size_t n = strlen(r->buf), from = (size_t)nf * (size_t)sc->f->width;
  for (size_t c = from; c < n; c++)
    if (r->buf[c] != ' ' && r->buf[c] != '\t')
      return vi_mx_fail_at(r, VI_ERR_PARSE, (int)c + 1, sc->name, "text "
                           "after the %d field%s of format %s (from column "
                           "%d)", nf, nf == 1 ? "" : "s", sc->f->text,
                           (int)c + 1);
  return VI_OK;
}

/* The column pointers: from 1, never decreasing, to NNZERO + 1. */
static int read_pointers(reader *r, const hb_header *h, int *colptr)
{
  section sc = {"pointers", "pointer", &h->ptr, (int64_t)h->cols + 1};
  char s[VI_MM_MAX_LINE + 2], key[48];
  int st, r_ = h->ptr.per_line > 0 ? h->ptr.per_line : 1, w = h->ptr.width;
  for (int64_t k = 0; k < sc.count; k++) {
    int q = (int)(k % r_);
    if (q == 0) {
      int nf = sc.count - k < r_ ? (int)(sc.count - k) : r_;
      if ((st = section_line(r, &sc, k, nf))) return st;
    }
    if ((st = get_field(r, &sc, q, k, s, sizeof s))) return st;
    long long v = 0, prev = k ? colptr[k - 1] + 1 : 1;
    int ok = fortran_int(s, &v);
    if (ok && !((k == 0 && v != 1) || v < prev || v > h->nnz + 1 ||
                (k == sc.count - 1 && v != h->nnz + 1))) {
      colptr[k] = (int)v - 1;
      continue;
    }
    snprintf(key, sizeof key, "pointer %lld", (long long)k + 1);
    if (!ok)
      return vi_mx_fail_at(r, VI_ERR_PARSE, q * w + 1, key, "'%s' is not a "
                           "whole number (format %s)", s, h->ptr.text);
    return vi_mx_fail_at(r, VI_ERR_PARSE, q * w + 1, key, "column "
                           "pointer %lld = %lld: pointers start at 1, never "
                           "decrease and end at NNZERO + 1 = %lld",
                           (long long)k + 1, v, (long long)h->nnz + 1);
  }
  return VI_OK;
}

/* Row indices (1..NROW; on or below the diagonal of a symmetric matrix)
 * then the values, into the triplets. */
static int read_entries(reader *r, const hb_header *h, const int *colptr,
                        vi_mx_triplets *t)
{
  section si = {"row indices", "row index", &h->ind, h->nnz};
  section sv = {"values", "value", &h->val, h->nnz};
  char s[VI_MM_MAX_LINE + 2], key[48];
  int st, j = 0;
  for (int64_t k = 0; k < h->nnz; k++) {
    int r_ = h->ind.per_line > 0 ? h->ind.per_line : 1, w = h->ind.width,
        q = (int)(k % r_);
    if (q == 0) {
      int nf = h->nnz - k < r_ ? (int)(h->nnz - k) : r_;
      if ((st = section_line(r, &si, k, nf))) return st;
    }
    if ((st = get_field(r, &si, q, k, s, sizeof s))) return st;
    long long v = 0;
    int ok = fortran_int(s, &v);
    while (colptr[j + 1] <= k) j++; /* the entry's column */
    if (ok && v >= 1 && v <= h->rows && !(h->symmetric && v - 1 < j)) {
      t->i[k] = (int)v - 1;
      t->j[k] = j;
      t->line[k] = r->line;
      continue;
    }
    snprintf(key, sizeof key, "row index %lld", (long long)k + 1);
    if (!ok)
      return vi_mx_fail_at(r, VI_ERR_PARSE, q * w + 1, key, "'%s' is not a "
                           "whole number (format %s)", s, h->ind.text);
    if (v < 1 || v > h->rows)
      return vi_mx_fail_at(r, VI_ERR_DIM, q * w + 1, key, "row %lld of "
                           "column %d outside the %d rows (indices are "
                           "1-based)", v, j + 1, h->rows);
    return vi_mx_fail_at(r, VI_ERR_NOT_SYMMETRIC, q * w + 1, key, "entry "
                         "(%lld, %d) above the diagonal of a symmetric file "
                         "(the format stores the lower triangle)", v, j + 1);
  }
  for (int64_t k = 0; k < h->nnz; k++) {
    int r_ = h->val.per_line > 0 ? h->val.per_line : 1, w = h->val.width,
        q = (int)(k % r_);
    if (q == 0) {
      int nf = h->nnz - k < r_ ? (int)(h->nnz - k) : r_;
      if ((st = section_line(r, &sv, k, nf))) return st;
    }
    if ((st = get_field(r, &sv, q, k, s, sizeof s))) return st;
    long long iv = 0;
    int bad = 0;
    if (h->val.integer) {
      bad = !fortran_int(s, &iv);
      t->v[k] = (double)iv;
    } else
      bad = fortran_real(s, &h->val, &t->v[k]);
    if (!bad) continue;
    snprintf(key, sizeof key, "value %lld", (long long)k + 1);
    if (bad == 2)
      return vi_mx_fail_at(r, VI_ERR_NONFINITE, q * w + 1, key, "'%s' is "
                           "not a finite number", s);
    if (bad)
      return vi_mx_fail_at(r, VI_ERR_PARSE, q * w + 1, key, "'%s' is not a "
                           "number in format %s", s, h->val.text);
  }
  t->count = h->nnz;
  return VI_OK;
}

int vi_hb_header(const char *path, int *rows, int *cols, int64_t *entries,
                 int *symmetric, vi_diag *d)
{
  reader r;
  hb_header h;
  int st = vi_mx_open(&r, path, d);
  if (st) return st;
  st = read_hb_header(&r, &h);
  fclose(r.f);
  if (st) return st;
  if (rows) *rows = h.rows;
  if (cols) *cols = h.cols;
  if (entries) *entries = h.nnz;
  if (symmetric) *symmetric = h.symmetric;
  return VI_OK;
}

/* Bytes at least in a section of count fields: full fields but the last
 * of each line (one character at least) and a line end. */
static double least_bytes(int64_t count, const ffmt *f)
{
  double lines = (double)lines_for(count, f);
  return ((double)count - lines) * f->width + 2.0 * lines;
}

int vi_hb_load(const char *path, int storage, double max_bytes, vi_mm **out,
               vi_diag *d)
{
  reader r;
  hb_header h;
  int st = vi_mx_open(&r, path, d);
  if (st) return st;
  if ((st = read_hb_header(&r, &h))) {
    fclose(r.f);
    return st;
  }
  /* as vi_mm_load: the triplets (twice for a mirrored file), the sort,
   * the CSC; and the pointers */
  int64_t cap = h.symmetric && storage == VI_CSC_FULL ? 2 * h.nnz : h.nnz;
  double need = 40.0 * (double)cap + 16.0 * (double)h.cols;
  if (max_bytes > 0 && need > max_bytes) {
    fclose(r.f);
    return vi_diag_set(d, path, VI_ERR_LIMIT, 3, 43, "header", "",
                       "reading %lld entries needs about %.3g MB, more than "
                       "the %.3g MB allowed", (long long)h.nnz,
                       need / 1048576.0, max_bytes / 1048576.0);
  }
  double least = least_bytes((int64_t)h.cols + 1, &h.ptr) +
                 least_bytes(h.nnz, &h.ind) + least_bytes(h.nnz, &h.val) - 1;
  if ((st = vi_mx_check_room(&r, least, h.nnz, "header"))) {
    fclose(r.f);
    return st;
  }
  vi_mx_triplets t;
  int *colptr = calloc((size_t)h.cols + 1, sizeof(int));
  if (!vi_mx_trip_alloc(&t, cap) || !colptr) {
    vi_mx_trip_free(&t);
    free(colptr);
    fclose(r.f);
    return vi_diag_nomem(d, path);
  }
  st = read_pointers(&r, &h, colptr);
  if (!st) st = read_entries(&r, &h, colptr, &t);
  fclose(r.f); /* right-hand sides, if any, are not read */
  free(colptr);
  if (!st)
    st = vi_mx_build(&r, h.rows, h.cols, h.symmetric, &t, storage, out);
  vi_mx_trip_free(&t);
  return st;
}
