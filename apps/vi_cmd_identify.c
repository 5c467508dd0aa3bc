/* vi_cmd_identify.c - `vibroimpact identify`: scene parameters from a
 * recorded periodic response (issue 22; the paper's section 4).
 *
 *   vibroimpact identify SCENE --data REC.csv --fit KEY[,KEY...] [--dof I[,J...]]
 *                        [--noise S] [--set KEY=VALUE]... [--range KEY=LO:HI]...
 *                        [--local] [--json] [-o OUT.h5]
 *
 * The recording is CSV with a header: t and at least one of x (x = w.x at
 * the stop, or coordinate I with --dof I), v (c.x') and a (c.x''), the
 * columns xJ of further --dof coordinates, f (the forcing signal) used to
 * report the forcing phase it implies.  '#' lines are comments.  Each KEY
 * is a numeric scene key (stop.r, stop.xs, forcing.omega, forcing.a[1],
 * model.cantilever.zeta, ...); the global stage searches its range from
 * any start (--local: a fit from the scene's value); keys that vi_param.h
 * knows are set on a
 * copy of the model, any other by re-reading the edited scene.  The fit
 * itself is vi_identify.h.  Exit status: 0 converged, 1 a run-time failure
 * or a fit that did not converge, 2 bad input. */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>

#include "vibroimpact.h"
#include "vibroimpact/vi_identify_io.h"
#include "vibroimpact/vi_param.h"
#include "vibroimpact/vi_scene.h"
#include "vibroimpact/vi_scene_edit.h"
#include "vi_app.h"
#include "vi_diagram.h"

#define MAXKEY 16

/* ---- the recording ------------------------------------------------------- */

typedef struct recording {
  int ns, cap;
  double *t, *x, *v, *f, *a; /* x, v, f, a NULL when absent */
  int nxe;
  double *xe[8]; /* columns xJ of the further --dof coordinates */
} recording;

static void rec_free(recording *r)
{
  free(r->t);
  free(r->x);
  free(r->v);
  free(r->f);
  free(r->a);
  for (int k = 0; k < r->nxe; k++) free(r->xe[k]);
  memset(r, 0, sizeof *r);
}

/* Field [a, b) of a line, trimmed. */
static void trim(const char **a, const char **b)
{
  while (*a < *b && (**a == ' ' || **a == '\t')) (*a)++;
  while (*b > *a && ((*b)[-1] == ' ' || (*b)[-1] == '\t' || (*b)[-1] == '\r' ||
                     (*b)[-1] == '\n'))
    (*b)--;
}

/* The CSV being read: its columns (t, x, v, f; -1 absent), where. */
typedef struct csv {
  const char *path;
  const char *line;
  long lno;
  int ncol, col[13], nnames;
  const char *names[13]; /* t, x, v, f, a and the xJ of --dof I,J,... */
  char xn[8][24];
} csv;

static const char *const csv_names[5] = {"t", "x", "v", "f", "a"};

/* Header field k [fa, fb): note which column it is; 0, or 2 after a
 * message (a column twice). */
static int csv_header_field(csv *c, int k, const char *fa, const char *fb)
{
  for (int j = 0; j < c->nnames; j++)
    if ((size_t)(fb - fa) == strlen(c->names[j]) && !strncmp(fa, c->names[j], fb - fa)) {
      if (c->col[j] >= 0) {
        fprintf(stderr, "vibroimpact: %s:%ld:%d: column '%s' twice\n",
                c->path, c->lno, (int)(fa - c->line) + 1, c->names[j]);
        return 2;
      }
      c->col[j] = k;
    }
  return 0;
}

/* Data field k [fa, fb) into val[] if it is a column we read; 0, or 2
 * after a message naming file:line:column. */
static int csv_data_field(const csv *c, int k, const char *fa, const char *fb,
                          double *val)
{
  for (int j = 0; j < c->nnames; j++) {
    if (c->col[j] != k) continue;
    char buf[128], *end;
    int len = (int)(fb - fa), at = (int)(fa - c->line) + 1;
    if (len <= 0 || len >= (int)sizeof buf) {
      fprintf(stderr, "vibroimpact: %s:%ld:%d: %s: empty or overlong "
              "field\n", c->path, c->lno, at, c->names[j]);
      return 2;
    }
    memcpy(buf, fa, len);
    buf[len] = 0;
    errno = 0;
    double v = strtod(buf, &end);
    if (end == buf || *end) {
      fprintf(stderr, "vibroimpact: %s:%ld:%d: %s = '%s': not a number\n",
              c->path, c->lno, at, c->names[j], buf);
      return 2;
    }
    if (!isfinite(v)) {
      fprintf(stderr, "vibroimpact: %s:%ld:%d: %s = '%s': not finite\n",
              c->path, c->lno, at, c->names[j], buf);
      return 2;
    }
    val[j] = v;
  }
  return 0;
}

/* The fields of one line (the header while c->ncol = 0): *k receives
 * their number; 0, or 2 after a message. */
static int csv_fields(csv *c, double *val, int *k)
{
  const char *a = c->line;
  for (*k = 0;; (*k)++) {
    const char *b = strchr(a, ',');
    if (!b) b = a + strlen(a);
    const char *fa = a, *fb = b;
    trim(&fa, &fb);
    int rc = !c->ncol ? csv_header_field(c, *k, fa, fb) : csv_data_field(c, *k, fa, fb, val);
    if (rc) return rc;
    if (!*b) break;
    a = b + 1;
  }
  (*k)++;
  return 0;
}

/* Append a sample (t, x and the optional v, f); 0, or 1 out of memory. */
static int rec_push(recording *r, const csv *c, const double *val)
{
  if (r->ns == r->cap) {
    int nc = r->cap ? 2 * r->cap : 1024;
    double **q[13] = {&r->t, &r->x, &r->v, &r->f, &r->a};
    for (int k = 0; k < r->nxe; k++) q[5 + k] = &r->xe[k];
    for (int j = 0; j < 5 + r->nxe; j++) {
      if (j >= 1 && c->col[j] < 0) continue;
      double *nq = realloc(*q[j], sizeof(double) * nc);
      if (!nq) {
        fprintf(stderr, "vibroimpact: %s: out of memory\n", c->path);
        return 1;
      }
      *q[j] = nq;
    }
    r->cap = nc;
  }
  r->t[r->ns] = val[0];
  if (r->x) r->x[r->ns] = val[1];
  if (r->a) r->a[r->ns] = val[4];
  for (int k = 0; k < r->nxe; k++) r->xe[k][r->ns] = val[5 + k];
  if (r->v) r->v[r->ns] = val[2];
  if (r->f) r->f[r->ns] = val[3];
  r->ns++;
  return 0;
}

/* The line for a message: up to its end, at most len - 4 characters (a
 * file with no line ends is one long line), "..." when cut. */
static const char *shown(const char *line, char *buf, size_t len)
{
  size_t n = strcspn(line, "\r\n");
  if (n + 1 > len) {
    memcpy(buf, line, len - 4);
    memcpy(buf + len - 4, "...", 4);
  } else {
    memcpy(buf, line, n);
    buf[n] = 0;
  }
  return buf;
}

/* One non-comment line: the header, or a sample; 0, or the exit status
 * after a message. */
static int csv_line(csv *c, recording *r)
{
  double val[13] = {0};
  int k, rc = csv_fields(c, val, &k);
  if (rc) return rc;
  if (!c->ncol) {
    c->ncol = k;
    if (c->col[0] < 0 || (c->col[1] < 0 && c->col[2] < 0 && c->col[4] < 0)) {
      char sh[80];
      fprintf(stderr, "vibroimpact: %s:%ld: the header needs columns t and "
              "x, v or a (has: %s)\n", c->path, c->lno, shown(c->line, sh, sizeof sh));
      return 2;
    }
    for (int j = 5; j < c->nnames; j++)
      if (c->col[j] < 0) {
        char sh[80];
        fprintf(stderr, "vibroimpact: %s:%ld: --dof lists coordinate %s, the header "
                "has no column '%s' (has: %s)\n", c->path, c->lno, c->names[j] + 1,
                c->names[j], shown(c->line, sh, sizeof sh));
        return 2;
      }
    return 0;
  }
  if (k != c->ncol) {
    fprintf(stderr, "vibroimpact: %s:%ld: %d fields, the header has %d\n",
            c->path, c->lno, k, c->ncol);
    return 2;
  }
  if (r->ns > 0 && !(val[0] > r->t[r->ns - 1])) {
    fprintf(stderr, "vibroimpact: %s:%ld:%d: t = %.17g does not increase "
            "(the sample before: %.17g)\n", c->path, c->lno, 1, val[0], r->t[r->ns - 1]);
    return 2;
  }
  return rec_push(r, c, val);
}

/* A NUL byte in the line buf [len] read at c->lno (strtod and strchr
 * would stop there and drop the rest silently): 1 after a message naming
 * its line and column (lone \r counted as line ends), else 0. */
static int nul_byte(const csv *c, const char *buf, size_t len)
{
  const char *z = memchr(buf, 0, len);
  if (!z) return 0;
  long lno = c->lno;
  const char *ls = buf;
  for (const char *q = buf; q < z; q++)
    if (*q == '\r' && q + 1 < z && q[1] != '\n') {
      lno++;
      ls = q + 1;
    }
  fprintf(stderr, "vibroimpact: %s:%ld:%d: a NUL byte: not a text recording\n",
          c->path, lno, (int)(z - ls) + 1);
  return 1;
}

/* Read the CSV; 0, or 2 after printing file:line:column: why (1 out of
 * memory). */
static int read_csv(const char *path, recording *r, int nxe, const long *dofs)
{
  memset(r, 0, sizeof *r);
  r->nxe = nxe;
  FILE *fp = fopen(path, "r");
  if (!fp) {
    fprintf(stderr, "vibroimpact: %s: cannot open: %s\n", path, strerror(errno));
    return 2;
  }
  char *line = NULL;
  size_t lcap = 0;
  csv c;
  memset(&c, 0, sizeof c);
  c.path = path;
  for (int j = 0; j < 13; j++) c.col[j] = -1;
  for (int j = 0; j < 5; j++) c.names[j] = csv_names[j];
  for (int k = 0; k < nxe; k++) {
    snprintf(c.xn[k], sizeof c.xn[k], "x%ld", dofs[k]);
    c.names[5 + k] = c.xn[k];
  }
  c.nnames = 5 + nxe;
  int rc = 0;
  ssize_t len;
  while (!rc && (len = getline(&line, &lcap, fp)) >= 0) {
    c.lno++;
    if (nul_byte(&c, line, (size_t)len)) {
      rc = 2;
      break;
    }
    char *seg = line;
    /* a UTF-8 byte-order mark (spreadsheets write one) is no part of the header */
    if (c.lno == 1 && !strncmp(seg, "\xEF\xBB\xBF", 3)) seg += 3;
    /* lines end with \n, \r\n or a lone \r (old Mac files: one getline) */
    for (;;) {
      char *cr = strchr(seg, '\r');
      if (cr) *cr = 0;
      c.line = seg;
      const char *p = seg;
      while (*p == ' ' || *p == '\t') p++;
      if (!(*p == '#' || *p == '\n' || !*p)) rc = csv_line(&c, r);
      if (!cr || rc) break;
      seg = cr + 1;
      if (*seg == '\n' || !*seg) break;
      c.lno++;
    }
  }
  if (!rc && !c.ncol) {
    fprintf(stderr, "vibroimpact: %s: no header line (t,x[,v][,a][,f])\n", path);
    rc = 2;
  } else if (!rc && r->ns < 16) {
    fprintf(stderr, "vibroimpact: %s: too few samples: %d (at least 16)\n",
            path, r->ns);
    rc = 2;
  }
  free(line);
  fclose(fp);
  if (rc) rec_free(r);
  return rc;
}

/* ---- parameters by scene key --------------------------------------------- */

typedef struct builder {
  const char *text, *name; /* the scene after --set */
  int nk;
  const char *key[MAXKEY];
  int onmodel[MAXKEY]; /* a model key the scene does not write (forcing.b[1]) */
} builder;

/* The model at trial values by re-reading the scene with the keys set. */
static int build(const double *p, void *user, vi_model **out)
{
  builder *b = user;
  vi_scene_edit *e = NULL;
  vi_scene *sc = NULL;
  vi_diag d;
  *out = NULL;
  int st = vi_scene_edit_create(b->text, -1, b->name, &e, &d);
  for (int j = 0; !st && j < b->nk; j++)
    if (!b->onmodel[j]) st = vi_scene_edit_set_number(e, b->key[j], p[j], &d);
  if (!st) st = vi_scene_edit_parse(e, &sc, &d);
  if (!st) st = vi_scene_create_model(sc, out, &d);
  /* keys the scene does not write cannot be edited into it: set on the
   * model, as without the builder */
  for (int j = 0; !st && j < b->nk; j++)
    if (b->onmodel[j]) st = vi_model_set_param(*out, b->key[j], p[j]);
  if (st) vi_model_destroy(out);
  vi_scene_destroy(&sc);
  vi_scene_edit_destroy(&e);
  return st;
}

/* Line and column of `value` after `name:` in the text (1-based; 0 when
 * not found): where a key's value is written, for messages. */
static void locate(const char *text, const char *key, const char *value,
                   int *line, int *col)
{
  *line = *col = 0;
  const char *dot = strrchr(key, '.');
  const char *nm = dot ? dot + 1 : key;
  size_t nl = strcspn(nm, "[");
  for (const char *p = text; (p = strstr(p, nm)) != NULL; p++) {
    if (p > text && (p[-1] == '_' || p[-1] == '.' || (p[-1] >= 'a' && p[-1] <= 'z'))) continue;
    const char *q = p + nl;
    while (*q == ' ') q++;
    if (*q != ':') continue;
    const char *v = strstr(q, value);
    const char *eol = strchr(q, '\n');
    if (!v || (eol && v > eol)) continue;
    int l = 1;
    const char *ls = text;
    for (const char *c = text; c < v; c++)
      if (*c == '\n') {
        l++;
        ls = c + 1;
      }
    *line = l;
    *col = (int)(v - ls) + 1;
    return;
  }
}

/* ---- output --------------------------------------------------------------- */

static void json_num(double v)
{
  if (isfinite(v)) printf("%.10g", v);
  else printf("null");
}

/* The forcing phase the recording's f column implies (NaN without one). */
static double forcing_shift(const recording *r, double omega)
{
  double t0 = NAN;
  if (r->f) vi_identify_forcing_phase(r->ns, r->t, r->f, omega, &t0);
  return t0;
}

typedef int (*write_h5_fn)(const char *, const vi_identify *, const char *,
                           int, const double *, const double *, vi_diag *);

/* vi_identify_write_h5 (libvibroimpact_h5). */
static write_h5_fn load_writer(void) { return vi_identify_write_h5; }

static void usage(FILE *f)
{
  fprintf(f,
    "usage: vibroimpact identify SCENE.yaml --data REC.csv --fit KEY[,KEY...]\n"
    "                            [--dof I] [--noise S] [--unstable] [--set KEY=VALUE]...\n"
    "                            [--range KEY=LO:HI]... [--local] [--json] [-o OUT.h5]\n"
    "Fit scene parameters to a recorded periodic response (nonlinear least\n"
    "squares on the model's periodic orbit; an unknown forcing phase is\n"
    "fitted as a time shift).  Starts spread over each key's range find every\n"
    "orbit the recording's period admits; every distinct fit the noise\n"
    "explains is reported, best first.\n\n"
    "  --data FILE   CSV with a header: t and at least one of x (x = w.x at\n"
    "                the stop, or coordinate I with --dof), v (velocity), a\n"
    "                (acceleration); f (forcing) used when present; '#' lines\n"
    "                are comments\n"
    "  --fit KEYS    numeric scene keys, comma-separated: stop.r, stop.xs,\n"
    "                forcing.omega, forcing.a[1], model.cantilever.zeta, ...\n"
    "  --dof I[,J..] the recording is coordinate I (1-based), not w.x; further\n"
    "                coordinates J from columns named xJ (several dofs at once)\n"
    "  --noise S     the recording's noise standard deviation, if known\n"
    "                (else estimated from the recording: its periods folded\n"
    "                onto one, or its 4th differences)\n"
    "  --unstable    also fit unstable orbits (a model that cannot hold the\n"
    "                recorded motion: which shape would it need?)\n"
    "  --set K=V     override a scene key first\n"
    "  --range K=LO:HI  the admissible range of a fitted key (default: r in\n"
    "                [0, 1], a stop near the recording's top, forcing.omega\n"
    "                2 pi n / the recording's own period, else +-50 %%)\n"
    "  --local       one fit from the scene's values only (no global stage)\n"
    "  --json        one JSON object on standard output\n"
    "  -o FILE.h5    the recording, fitted response, residuals and fit\n"
    "                (share/plot_identify.py plots it)\n"
    "Exit status: 0 converged, 1 run-time failure or no convergence, 2 bad "
    "input.\n");
}

/* The command line. */
typedef struct id_args {
  const char *data, *fit, *out, *scene_path;
  const char *sets[64], *ranges[MAXKEY];
  int nsets, nranges, json, unstable, local, nxdof;
  long dof, xdof[8]; /* --dof: 1-based coordinates (0: w.x) */
  double noise;
} id_args;

/* One option c into a: -1 to go on, else the exit status (0 after --help,
 * 2 for a bad value, with the message). */
static int identify_option(int c, int argc, char **argv, id_args *a)
{
  char *end;
  switch (c) {
  case 'd': a->data = optarg; break;
  case 'F': a->fit = optarg; break;
  case 'o': a->out = optarg; break;
  case 'j': a->json = 1; break;
  case 'u': a->unstable = 1; break;
  case 'l': a->local = 1; break;
  case 'r':
    if (a->nranges == MAXKEY) {
      fprintf(stderr, "vibroimpact: more than %d --range\n", MAXKEY);
      return 2;
    }
    a->ranges[a->nranges++] = optarg;
    break;
  case 'D':
    /* long, compared with the model's size later: no int wraps
     * 99999999999 into a coordinate */
    errno = 0;
    a->dof = strtol(optarg, &end, 10);
    a->nxdof = 0;
    while (*end == ',' && a->nxdof < 8 && a->dof >= 1) {
      char *s0 = end + 1;
      a->xdof[a->nxdof] = strtol(s0, &end, 10);
      if (end == s0 || a->xdof[a->nxdof] < 1) break;
      a->nxdof++;
    }
    if (end == optarg || *end || a->dof < 1 || errno == ERANGE) {
      fprintf(stderr, "vibroimpact: --dof: '%s' is not a coordinate number "
              "(1, 2, ...) or a list of at most 9\n", optarg);
      return 2;
    }
    break;
  case 'n':
    a->noise = strtod(optarg, &end);
    if (end == optarg || *end || !(a->noise > 0) || !isfinite(a->noise)) {
      fprintf(stderr, "vibroimpact: --noise: '%s' is not a number > 0\n", optarg);
      return 2;
    }
    break;
  case 's':
    if (a->nsets == 64) {
      fprintf(stderr, "vibroimpact: more than 64 --set\n");
      return 2;
    }
    a->sets[a->nsets++] = optarg;
    break;
  case 'h': usage(stdout); return 0;
  default:
    fprintf(stderr, "vibroimpact: identify: unknown or incomplete option '%s'\n",
            optind > 0 && optind <= argc ? argv[optind - 1] : "?");
    usage(stderr);
    return 2;
  }
  return -1;
}

/* -1 to go on, else the exit status. */
static int identify_parse(int argc, char **argv, id_args *a)
{
  static const struct option lo[] = {
      {"data", required_argument, 0, 'd'}, {"fit", required_argument, 0, 'F'},
      {"dof", required_argument, 0, 'D'},  {"noise", required_argument, 0, 'n'},
      {"set", required_argument, 0, 's'},  {"json", no_argument, 0, 'j'},
      {"output", required_argument, 0, 'o'}, {"help", no_argument, 0, 'h'},
      {"unstable", no_argument, 0, 'u'},  {"local", no_argument, 0, 'l'},
      {"range", required_argument, 0, 'r'},
      {0, 0, 0, 0}};
  int c, rc;
  optind = 0;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "o:", lo, NULL)) != -1)
    if ((rc = identify_option(c, argc, argv, a)) >= 0) return rc;
  if (optind < argc) a->scene_path = argv[optind++];
  if (optind < argc || !a->scene_path || !a->data || !a->fit) {
    fprintf(stderr, "vibroimpact: identify needs SCENE, --data and --fit\n");
    usage(stderr);
    return 2;
  }
  return -1;
}

/* The identification's state. */
typedef struct ident {
  id_args a;
  char *text, *keys, *edited;
  vi_scene_edit *ed;
  vi_scene *sc;
  vi_model *model;
  vi_identify *id;
  recording rec;
  builder b;
  int use_builder;
  double start[MAXKEY];
} ident;

/* The scene with --set applied (kept as text for the builder) and its
 * model; 0 or 2 after a message. */
static int identify_scene(ident *I)
{
  char err[600];
  vi_diag d;
  int st;
  I->text = vi_app_read_text(I->a.scene_path, err, sizeof err);
  if (!I->text) {
    fprintf(stderr, "vibroimpact: %s\n", err);
    return 2;
  }
  I->keys = strdup(I->a.fit);
  st = I->keys ? vi_scene_edit_create(I->text, -1, I->a.scene_path, &I->ed, &d) : VI_ERR_NOMEM;
  for (int i = 0; i < I->a.nsets && !st; i++) st = vi_scene_edit_assign(I->ed, I->a.sets[i], &d);
  /* the scene's vectors within what the machine has (0) */
  if (!st) st = vi_scene_edit_parse_within(I->ed, 0, &I->sc, &d);
  if (!st) st = vi_scene_create_model(I->sc, &I->model, &d);
  if (st) {
    vi_app_print_diag(&d, st);
    return 2;
  }
  I->edited = strdup(vi_scene_edit_text(I->ed));
  I->b.text = I->edited;
  I->b.name = I->a.scene_path;
  return 0;
}

/* One --fit key: a numeric scene value, or a vi_param.h key of the model;
 * its starting value into I->start.  0 or 2 after a message. */
static int identify_key(ident *I, const char *k)
{
  char buf[128];
  vi_diag kd;
  int gs = vi_scene_edit_get(I->ed, k, buf, sizeof buf, &kd);
  if (gs == VI_OK) {
    char *e2;
    double v = strtod(buf, &e2);
    if (e2 == buf || *e2 || !isfinite(v)) {
      int line, col;
      locate(I->edited, k, buf, &line, &col);
      fprintf(stderr, "vibroimpact: %s:%d:%d: %s = %s: not a number, cannot "
              "be fitted\n", I->a.scene_path, line, col, k, buf);
      return 2;
    }
    I->start[I->b.nk] = v;
    if (vi_param_kind(k) != VI_PARAM_MODEL) I->use_builder = 1;
  } else if (vi_param_kind(k) == VI_PARAM_MODEL &&
             vi_model_param(I->model, k, &I->start[I->b.nk]) == VI_OK) {
    /* a model key the scene does not write (stops[2].r, damping.zeta) */
    I->b.onmodel[I->b.nk] = 1;
  } else {
    fprintf(stderr, "vibroimpact: %s: --fit %s: %s\n", I->a.scene_path, k,
            gs == VI_ERR_PARSE ? kd.message : "not a numeric key");
    return 2;
  }
  return 0;
}

/* The --fit keys, comma-separated; 0 or 2 after a message. */
static int identify_keys(ident *I)
{
  for (char *save = NULL, *k = strtok_r(I->keys, ",", &save); k;
       k = strtok_r(NULL, ",", &save)) {
    if (I->b.nk == MAXKEY) {
      fprintf(stderr, "vibroimpact: --fit: more than %d keys\n", MAXKEY);
      return 2;
    }
    for (int q = 0; q < I->b.nk; q++)
      if (!strcmp(I->b.key[q], k)) {
        fprintf(stderr, "vibroimpact: --fit: %s is listed twice\n", k);
        return 2;
      }
    if (identify_key(I, k)) return 2;
    I->b.key[I->b.nk++] = k;
  }
  return 0;
}

/* The --range KEY=LO:HI options onto the fitted keys; 0 or 2 after a
 * message. */
static int identify_ranges(ident *I)
{
  for (int i = 0; i < I->a.nranges; i++) {
    const char *r = I->a.ranges[i], *eq = strchr(r, '=');
    char *e1, *e2;
    int j = -1;
    double lo = NAN, hi = NAN;
    if (eq) {
      for (int q = 0; q < I->b.nk; q++)
        if (strlen(I->b.key[q]) == (size_t)(eq - r) && !strncmp(I->b.key[q], r, eq - r)) j = q;
      lo = strtod(eq + 1, &e1);
      hi = *e1 == ':' ? strtod(e1 + 1, &e2) : NAN;
      if (*e1 != ':' || *e2 || !isfinite(lo) || !isfinite(hi) || !(lo < hi)) j = -2;
    }
    if (j < 0) {
      fprintf(stderr, "vibroimpact: --range %s: %s\n", r,
              j == -2 ? "want KEY=LO:HI with finite LO < HI" : "not one of the --fit keys");
      return 2;
    }
    int st = vi_identify_set_param_key(I->id, j, I->b.key[j], lo, hi);
    if (st) st = vi_identify_set_param(I->id, j, VI_IDENTIFY_OTHER, 0, I->start[j], lo, hi);
    if (st) {
      fprintf(stderr, "vibroimpact: --range %s: %s\n", r, vi_identify_errmsg(I->id));
      return 2;
    }
  }
  return 0;
}

/* The fit set up: parameters, builder, observation, noise, data; 0 or the
 * exit status after a message. */
static int identify_setup(ident *I)
{
  const id_args *a = &I->a;
  int n = vi_model_n(I->model), st, nk = I->b.nk, rc;
  if (a->out && !I->rec.x) {
    fprintf(stderr, "vibroimpact: %s: -o writes the displacement column x, which "
            "this recording has not\n", a->data);
    return 2;
  }
  if (a->dof > n) {
    fprintf(stderr, "vibroimpact: --dof %ld: the model has %d coordinates\n", a->dof, n);
    return 2;
  }
  for (int k = 0; k < a->nxdof; k++)
    if (a->xdof[k] > n) {
      fprintf(stderr, "vibroimpact: --dof ...,%ld: the model has %d coordinates\n",
              a->xdof[k], n);
      return 2;
    }
  if ((st = vi_identify_create(I->model, nk, &I->id))) {
    fprintf(stderr, "vibroimpact: %s: cannot identify this model: %s\n",
            a->scene_path, vi_strerror(st));
    return st == VI_ERR_NOMEM ? 1 : 2;
  }
  for (int j = 0; j < nk && !st; j++) {
    st = vi_identify_set_param_key(I->id, j, I->b.key[j], NAN, NAN);
    if (st && vi_param_kind(I->b.key[j]) == VI_PARAM_MODEL) { /* stop.r and stops[1].r */
      fprintf(stderr, "vibroimpact: --fit: %s\n", vi_identify_errmsg(I->id));
      return 2;
    }
    if (st) /* a scene key vi_param.h does not know: the builder sets it */
      st = vi_identify_set_param(I->id, j, VI_IDENTIFY_OTHER, 0, I->start[j],
                                 -HUGE_VAL, HUGE_VAL);
  }
  if (!st && I->use_builder) st = vi_identify_set_builder(I->id, build, &I->b, NULL);
  if (!st && (rc = identify_ranges(I))) return rc;
  if (!st && a->local) st = vi_identify_set_global(I->id, 0);
  if (!st && a->dof) {
    double *cv = calloc(n, sizeof(double));
    st = cv ? VI_OK : VI_ERR_NOMEM;
    if (cv) {
      cv[a->dof - 1] = 1.0;
      st = vi_identify_set_observation(I->id, cv);
      free(cv);
    }
  }
  if (!st) st = vi_identify_set_noise(I->id, a->noise);
  if (!st && a->unstable) st = vi_identify_set_stable_only(I->id, 0);
  if (!st) st = vi_identify_set_sensors(I->id, I->rec.ns, I->rec.t, I->rec.x, I->rec.v, I->rec.a);
  for (int k = 0; !st && k < I->rec.nxe; k++) { /* the further --dof columns */
    double *cv = calloc(n, sizeof(double));
    st = cv ? VI_OK : VI_ERR_NOMEM;
    if (cv) {
      cv[a->xdof[k] - 1] = 1.0;
      st = vi_identify_add_channel(I->id, cv, 0, I->rec.xe[k]);
      free(cv);
    }
  }
  if (st) {
    fprintf(stderr, "vibroimpact: %s: %s\n", a->data, vi_identify_errmsg(I->id));
    return st == VI_ERR_NOMEM ? 1 : 2;
  }
  return 0;
}

/* What the fit gives, read from the identification. */
typedef struct fit_result {
  int np, conv, iters, on, om, fl[MAXKEY], pfl[MAXKEY], nsol, unique;
  double p[MAXKEY], se[MAXKEY], l95[MAXKEY], h95[MAXKEY], R[MAXKEY * MAXKEY];
  double pl[MAXKEY], ph[MAXKEY];
  double rms, nz, rcond, t0, t0se, r12, vN, KE, RE, P, mu, tf;
  int nout, out[8];     /* samples beyond OUTLIER noise levels: count, the worst */
  double outz[8], rest; /* their distances in noise levels; the others' RMS / noise */
} fit_result;

/* A sample this many noise levels from the fitted motion is an outlier
 * (a Gaussian sample lies beyond 6 sigma once in 5e8). */
#define OUTLIER 6.0

/* The samples of the first channel beyond OUTLIER noise levels from the
 * fitted response, the worst 8, and the others' RMS (vi_identify_outliers):
 * a glitch of one sample makes a least-squares fit's residual read "not
 * explained" (Fig. 2 with one sample 0.5 off: ratio 23.5). */
static void identify_outliers(const ident *I, fit_result *f)
{
  if (vi_identify_outliers(I->id, OUTLIER, 8, f->out, f->outz, &f->nout, &f->rest)) {
    f->nout = 0;
    f->rest = NAN;
  }
}

static void identify_results(const ident *I, fit_result *f)
{
  const vi_identify *id = I->id;
  f->np = I->b.nk;
  f->mu = NAN;
  vi_identify_params(id, f->p, f->se, f->l95, f->h95, f->fl);
  vi_identify_profile(id, f->pl, f->ph, f->pfl);
  f->nsol = vi_identify_nsolutions(id, &f->unique);
  vi_identify_correlation(id, f->R, f->np);
  vi_identify_summary(id, &f->conv, &f->iters, &f->rms, &f->nz, &f->rcond, &f->on, &f->om);
  vi_identify_shift(id, &f->t0, &f->t0se);
  vi_identify_energy_restitution(id, &f->r12, &f->vN, &f->KE, &f->RE);
  vi_identify_orbit_period(id, &f->P, NULL);
  vi_identify_stability(id, &f->mu);
  f->tf = forcing_shift(&I->rec, vi_model_omega_forcing(I->model));
  identify_outliers(I, f);
}

/* One fit's keys: {KEY: {value, stderr, ci95, profile_ci95, ...}}. */
static void json_keys(const ident *I, const double *p, const double *se,
                      const double *l95, const double *h95, const double *pl,
                      const double *ph, const int *fl, const int *pfl)
{
  printf("{");
  for (int j = 0; j < I->b.nk; j++) {
    printf("%s\"%s\": {\"value\": ", j ? ", " : "", I->b.key[j]);
    json_num(p[j]);
    printf(", \"stderr\": ");
    json_num(se[j]);
    printf(", \"ci95\": [");
    json_num(l95[j]);
    printf(", ");
    json_num(h95[j]);
    printf("], \"profile_ci95\": [");
    json_num(pl[j]);
    printf(", ");
    json_num(ph[j]);
    printf("], \"on_bound\": %s, \"undetermined\": %s, \"profile_differs\": %s, "
           "\"profile_at_bound\": %s, \"profile_orbit_change\": %s}",
           fl[j] & VI_IDENTIFY_ON_BOUND ? "true" : "false",
           fl[j] & VI_IDENTIFY_UNDETERMINED ? "true" : "false",
           pfl[j] & VI_IDENTIFY_PROFILE_DIFFERS ? "true" : "false",
           pfl[j] & VI_IDENTIFY_PROFILE_BOUND ? "true" : "false",
           pfl[j] & VI_IDENTIFY_PROFILE_ORBIT ? "true" : "false");
  }
  printf("}");
}

/* The smallest separation of a solution from the best (noise variances
 * over the record). */
static double sep_of(const ident *I, const fit_result *f)
{
  double dmin = HUGE_VAL;
  for (int k = 1; k < f->nsol; k++) {
    double d = NAN;
    vi_identify_solution_separation(I->id, k, &d, NULL);
    dmin = fmin(dmin, d);
  }
  return dmin;
}

/* "solutions": every fit the data admit, best first. */
static void json_solutions(const ident *I, const fit_result *f)
{
  printf(", \"unique\": %s, \"solutions\": [", f->unique ? "true" : "false");
  for (int k = 0; k < f->nsol; k++) {
    double p[MAXKEY], se[MAXKEY], l[MAXKEY], h[MAXKEY], pl[MAXKEY], ph[MAXKEY], rms, ratio, dc;
    int fl[MAXKEY], pfl[MAXKEY], n, m;
    vi_identify_solution(I->id, k, p, se, l, h, fl);
    vi_identify_solution_profile(I->id, k, pl, ph, pfl);
    vi_identify_solution_summary(I->id, k, &n, &m, &rms, &ratio, &dc, NULL);
    printf("%s{\"fit\": ", k ? ", " : "");
    json_keys(I, p, se, l, h, pl, ph, fl, pfl);
    printf(", \"orbit\": {\"n\": %d, \"m\": %d}, \"rms_residual\": ", n, m);
    json_num(rms);
    printf(", \"residual_ratio\": ");
    json_num(ratio);
    printf(", \"delta_chi2\": ");
    json_num(dc);
    double sd = NAN, sl = NAN;
    vi_identify_solution_separation(I->id, k, &sd, &sl);
    printf(", \"separation\": ");
    json_num(sd);
    printf(", \"record_factor\": ");
    json_num(sl);
    printf("}");
  }
  printf("]");
}

static void identify_json(const ident *I, const fit_result *f)
{
  int np = f->np;
  printf("{\"fit\": ");
  json_keys(I, f->p, f->se, f->l95, f->h95, f->pl, f->ph, f->fl, f->pfl);
  printf(", \"converged\": %s, \"iterations\": %d, \"rms_residual\": ",
         f->conv ? "true" : "false", f->iters);
  json_num(f->rms);
  printf(", \"noise\": ");
  json_num(f->nz);
  printf(", \"shift\": ");
  if (isfinite(f->t0)) printf("%.17g", f->t0); /* an absolute clock's needs them all */
  else printf("null");
  printf(", \"shift_stderr\": ");
  json_num(f->t0se);
  printf(", \"shift_forcing\": ");
  json_num(f->tf);
  printf(", \"period\": ");
  json_num(f->P);
  printf(", \"orbit\": {\"n\": %d, \"m\": %d, \"stable\": %s, \"multiplier\": ",
         f->on, f->om, f->mu < 1.0 ? "true" : "false");
  json_num(f->mu);
  printf("}, \"samples\": %d, \"outliers\": {\"count\": %d, \"samples\": [", I->rec.ns,
         f->nout);
  for (int k = 0; k < f->nout && k < 8; k++) printf("%s%d", k ? ", " : "", f->out[k] + 1);
  printf("], \"rms_ratio_without\": ");
  json_num(f->nout ? f->rest : NAN);
  printf("}, \"correlation\": [");
  for (int i = 0; i < np; i++) {
    printf("%s[", i ? ", " : "");
    for (int j = 0; j < np; j++) {
      printf("%s", j ? ", " : "");
      json_num(f->R[i + j * np]);
    }
    printf("]");
  }
  printf("], \"rcond\": ");
  json_num(f->rcond);
  printf(", \"r_energy_balance\": ");
  json_num(f->r12);
  printf(", \"vN_recorded\": ");
  json_num(f->vN);
  json_solutions(I, f);
  printf("}\n");
}

/* The fits the data admit beside the best: each, and what would separate
 * them (vi_identify_solution_separation: the record length at this noise
 * for which the likelihood-ratio test tells the closest pair apart). */
static void identify_text_solutions(const ident *I, const fit_result *f)
{
  if (f->unique) return;
  printf("  NOT UNIQUE: the recording is explained to its noise level by");
  double dc[64], L = 0.0;
  for (int k = 0; k < f->nsol && k < 64; k++) {
    double p[MAXKEY], se[MAXKEY], lk = NAN;
    int n, m;
    vi_identify_solution(I->id, k, p, se, NULL, NULL, NULL);
    vi_identify_solution_summary(I->id, k, &n, &m, NULL, NULL, &dc[k], NULL);
    vi_identify_solution_separation(I->id, k, NULL, &lk);
    if (k > 0) L = isnan(lk) || isnan(L) ? NAN : fmax(L, lk);
    printf("%s P(%d,%d) with", k ? (k + 1 == f->nsol ? " and by" : ", by") : "", n, m);
    for (int j = 0; j < f->np; j++)
      printf("%s %s = %.4g +- %.2g", j ? "," : "", I->b.key[j], p[j], se[j]);
  }
  printf("\n");
  for (int k = 1; k < f->nsol && k < 64; k++)
    if (dc[k] > 3.84) /* chi2_0.95(1) */
      printf("  (solution %d's residual is at the noise level, but %.3g noise "
             "variances above the best's: a likelihood-ratio test prefers the "
             "best)\n", k + 1, dc[k]);
  const char *other = "a second sensor (another dof, v or a) or another forcing "
                      "level where their responses differ";
  if (!(L <= 100.0)) /* NaN included: no estimate */
    printf("  to tell them apart: %s%s\n", isnan(L) ? "" : "no practical record "
           "length at this noise (over 100 times longer); ", other);
  else
    printf("  to tell them apart: a record about %.2g times longer at this noise "
           "(their responses differ by %.3g noise variances over this one), or %s\n",
           fmax(L, 1.1), f->nsol > 1 ? sep_of(I, f) : NAN, other);
}

/* The text report's warnings: the fit's noise ratio, correlations, the
 * WB 12 route, stability and conditioning. */
static void identify_text_notes(const ident *I, const fit_result *f)
{
  int np = f->np;
  if (isfinite(f->nz)) printf(" against a noise level %.3g (ratio %.2f%s)", f->nz, f->rms / f->nz,
                              f->rms > 1.5 * f->nz ? ": the model does not explain the data" : "");
  printf("\n");
  if (np > 1) {
    printf("  correlations:");
    for (int i = 0; i < np; i++)
      for (int j = i + 1; j < np; j++)
        printf(" %s/%s %.3f", I->b.key[i], I->b.key[j], f->R[i + j * np]);
    printf("\n");
  }
  if (isfinite(f->vN))
    printf("  WB 12 route: recorded v_N %.6g, KE_i %.6g, the model's RE %.6g: "
           "r = %.6g\n", f->vN, f->KE, f->RE, f->r12);
  if (!(f->mu < 1.0))
    printf("  the fitted orbit is UNSTABLE (largest |multiplier| %.3g): the "
           "model cannot show this motion\n", f->mu);
  if (f->rcond < 1e-10)
    printf("  warning: the Jacobian is ill-conditioned (rcond %.2g): the data "
           "do not determine every parameter\n", f->rcond);
  if (f->nout) {
    const recording *r = &I->rec;
    printf("  note: %d sample%s beyond %g noise levels from the fitted motion (sample %d, "
           "t = %.6g: %.3g noise levels%s); the others' residual RMS is %.3g of the noise%s\n",
           f->nout, f->nout > 1 ? "s lie" : " lies", OUTLIER, f->out[0] + 1, r->t[f->out[0]],
           f->outz[0], f->nout > 1 ? ", the worst" : "", f->rest,
           f->nout <= r->ns / 100 + 1 ? ": outliers? A least-squares fit moves with them" : "");
  }
  /* fewer than 2 samples a forcing period, and the model does not explain
   * them: a recording in milliseconds against a model in seconds reads so */
  const recording *rec = &I->rec;
  double per = f->P / f->on, dt = (rec->t[rec->ns - 1] - rec->t[0]) / (rec->ns - 1);
  if (dt > 0.5 * per && f->rms > 1.5 * f->nz)
    printf("  note: %.3g samples a forcing period (2 pi / Omega = %.6g): is the "
           "recording's time in the model's unit?\n", per / dt, per);
}

static void identify_text(const ident *I, const fit_result *f)
{
  const recording *rec = &I->rec;
  printf("identify: scene %s, recording %s: %d samples over %.1f periods of "
         "the fitted P(%d,%d) orbit\n", vi_scene_name(I->sc), I->a.data, rec->ns,
         (rec->t[rec->ns - 1] - rec->t[0]) / f->P, f->on, f->om);
  for (int j = 0; j < f->np; j++) {
    int fl = f->fl[j];
    printf("  %-22s = %.6g +- %.2g   (95 %%: [%.6g, %.6g])%s%s%s\n", I->b.key[j],
           f->p[j], f->se[j], f->l95[j], f->h95[j],
           fl & VI_IDENTIFY_ON_BOUND ? "  ON A BOUND" : "",
           fl & VI_IDENTIFY_UNDETERMINED ? "  NOT DETERMINED by the data" : "",
           fl & VI_IDENTIFY_CORRELATED ? "  correlated > 0.99" : "");
    if (isfinite(f->pl[j]) || isfinite(f->ph[j]))
      printf("  %-22s   profile 95 %%: [%.6g, %.6g]%s%s%s\n", "", f->pl[j], f->ph[j],
             f->pfl[j] & VI_IDENTIFY_PROFILE_DIFFERS ? "  differs from the Jacobian's by > 20 %" : "",
             f->pfl[j] & VI_IDENTIFY_PROFILE_BOUND ? "  reaches the bound" : "",
             f->pfl[j] & VI_IDENTIFY_PROFILE_ORBIT ? "  ends where the orbit changes" : "");
  }
  /* digits enough for its error: a recording on an absolute clock (1.7e9
   * s) has t0 near minus that */
  double rel = fabs(f->t0) / f->t0se;
  int dg = isfinite(rel) && rel > 1e5 ? (int)fmin(17.0, ceil(log10(rel)) + 2.0) : 6;
  printf("  shift t0               = %.*g +- %.2g (model time = t + t0)", dg, f->t0, f->t0se);
  if (isfinite(f->tf)) printf("; forcing column's phase: %.6g", f->tf);
  printf("\n  %s in %d iterations; residual RMS %.3g", f->conv ? "converged" : "NOT CONVERGED",
         f->iters, f->rms);
  identify_text_notes(I, f);
  identify_text_solutions(I, f);
}

/* The library's message with "parameter j" named by its --fit key (the
 * keys only the scene knows reach the library without a name). */
static void print_named(const ident *I, const char *msg)
{
  const char *tag = "parameter ";
  for (const char *p = msg, *q; *p; p = q) {
    q = strstr(p, tag);
    if (!q) {
      fputs(p, stderr);
      break;
    }
    char *end;
    long j = strtol(q + strlen(tag), &end, 10);
    fwrite(p, 1, (size_t)(q - p), stderr);
    if (end > q + strlen(tag) && j >= 1 && j <= I->b.nk) fputs(I->b.key[j - 1], stderr);
    else fwrite(q, 1, (size_t)(end - q), stderr);
    q = end;
  }
}

/* Run the fit; 0, or the exit status after a message. */
static int identify_run(ident *I)
{
  int st = vi_identify_run(I->id);
  if (!st) return 0;
  fprintf(stderr, "vibroimpact: identify %s with %s: ", I->a.scene_path, I->a.data);
  print_named(I, vi_identify_errmsg(I->id));
  fputc('\n', stderr);
  return st == VI_ERR_ARG || st == VI_ERR_NOT_CONVERGED || st == VI_ERR_STATE ? 2 : 1;
}

int vi_cmd_identify_main(int argc, char **argv)
{
  ident I;
  memset(&I, 0, sizeof I);
  int rc = identify_parse(argc, argv, &I.a);
  if (rc >= 0) return rc;
  char target[VI_APP_PATH];
  vi_diag d;
  if (I.a.out) {
    /* the scene or the recording as -o would be overwritten: usage errors */
    int st = vi_output_check(I.a.out, VI_OUTPUT_REGULAR, I.a.scene_path, target,
                             sizeof target, NULL, &d);
    if (st) {
      fprintf(stderr, "vibroimpact: %s\n", d.message);
      return st == VI_ERR_ARG ? 2 : 1;
    }
    if (vi_output_same(target, I.a.data)) {
      fprintf(stderr, "vibroimpact: -o %s is the recording --data %s: it would be "
              "overwritten\n", I.a.out, I.a.data);
      return 2;
    }
  }
  if ((rc = identify_scene(&I)) || (rc = identify_keys(&I)) ||
      (rc = read_csv(I.a.data, &I.rec, I.a.nxdof, I.a.xdof)) || (rc = identify_setup(&I)) ||
      (rc = identify_run(&I)))
    goto done;
  fit_result f;
  identify_results(&I, &f);
  if (I.a.json) identify_json(&I, &f);
  else identify_text(&I, &f);
  rc = f.conv ? 0 : 1;
  if (I.a.out && !f.conv) /* an existing file keeps what it held */
    fprintf(stderr, "vibroimpact: the fit did not converge: %s not written\n", I.a.out);
  if (I.a.out && f.conv) {
    write_h5_fn w = load_writer();
    /* the writer commits through TARGET.part: a signal now removes it */
    char part[VI_APP_PATH + 8] = "";
    vi_output_part(target, part, (int)sizeof part);
    vi_app_arm_parts(part, NULL);
    if (!w || w(target, I.id, I.a.fit, I.rec.ns, I.rec.t, I.rec.x, &d)) {
      if (w) fprintf(stderr, "vibroimpact: %s\n", d.message);
      rc = 1;
    }
  }
done:
  vi_identify_destroy(&I.id);
  vi_model_destroy(&I.model);
  vi_scene_destroy(&I.sc);
  vi_scene_edit_destroy(&I.ed);
  rec_free(&I.rec);
  free(I.text);
  free(I.keys);
  free(I.edited);
  return rc;
}
