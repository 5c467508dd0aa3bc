/* vi_cmd_identify.c - `vibroimpact identify`: scene parameters from a
 * recorded periodic response (issue 22; the paper's section 4).
 *
 *   vibroimpact identify SCENE --data REC.csv --fit KEY[,KEY...] [--dof I]
 *                        [--noise S] [--set KEY=VALUE]... [--json] [-o OUT.h5]
 *
 * The recording is CSV with a header: t and x required (x = w.x at the
 * stop, or coordinate I with --dof I), v used when present (c.x'), f (the
 * forcing signal) used to report the forcing phase it implies.  '#' lines
 * are comments.  Each KEY is a numeric scene key (stop.r, stop.xs,
 * forcing.omega, forcing.a[1], model.cantilever.zeta, ...) whose scene
 * value is the starting guess; keys that vi_param.h knows are set on a
 * copy of the model, any other by re-reading the edited scene.  The fit
 * itself is vi_identify.h.  Exit status: 0 converged, 1 a run-time failure
 * or a fit that did not converge, 2 bad input. */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vibroimpact.h"
#include "vibroimpact/vi_identify_io.h"
#include "vibroimpact/vi_param.h"
#include "vibroimpact/vi_scene.h"
#include "vibroimpact/vi_scene_edit.h"
#include "vi_app.h"
#include "vi_sweep.h"

#define MAXKEY 16

/* ---- the recording ------------------------------------------------------- */

typedef struct recording {
  int ns, cap;
  double *t, *x, *v, *f; /* v, f NULL when absent */
} recording;

static void rec_free(recording *r)
{
  free(r->t);
  free(r->x);
  free(r->v);
  free(r->f);
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

/* Read the CSV; 0, or 2 after printing file:line:column: why. */
static int read_csv(const char *path, recording *r)
{
  memset(r, 0, sizeof *r);
  FILE *fp = fopen(path, "r");
  if (!fp) {
    fprintf(stderr, "vibroimpact: %s: cannot open: %s\n", path, strerror(errno));
    return 2;
  }
  char *line = NULL;
  size_t lcap = 0;
  long lno = 0;
  int ncol = 0, col[4] = {-1, -1, -1, -1}; /* t, x, v, f */
  static const char *names[4] = {"t", "x", "v", "f"};
  int rc = 0;
  while (getline(&line, &lcap, fp) >= 0) {
    lno++;
    const char *p = line;
    while (*p == ' ' || *p == '\t') p++;
    if (*p == '#' || *p == '\n' || *p == '\r' || !*p) continue;
    int k = 0;
    const char *a = line;
    double val[4] = {0, 0, 0, 0};
    for (;;) {
      const char *b = strchr(a, ',');
      if (!b) b = a + strlen(a);
      const char *fa = a, *fb = b;
      trim(&fa, &fb);
      if (!ncol) { /* the header */
        for (int c = 0; c < 4; c++)
          if ((size_t)(fb - fa) == strlen(names[c]) && !strncmp(fa, names[c], fb - fa)) {
            if (col[c] >= 0) {
              fprintf(stderr, "vibroimpact: %s:%ld:%d: column '%s' twice\n",
                      path, lno, (int)(fa - line) + 1, names[c]);
              rc = 2;
              goto done;
            }
            col[c] = k;
          }
      } else {
        for (int c = 0; c < 4; c++) {
          if (col[c] != k) continue;
          char buf[128], *end;
          int len = (int)(fb - fa);
          if (len <= 0 || len >= (int)sizeof buf) {
            fprintf(stderr, "vibroimpact: %s:%ld:%d: %s: empty or overlong "
                    "field\n", path, lno, (int)(fa - line) + 1, names[c]);
            rc = 2;
            goto done;
          }
          memcpy(buf, fa, len);
          buf[len] = 0;
          errno = 0;
          double v = strtod(buf, &end);
          if (end == buf || *end) {
            fprintf(stderr, "vibroimpact: %s:%ld:%d: %s = '%s': not a number\n",
                    path, lno, (int)(fa - line) + 1, names[c], buf);
            rc = 2;
            goto done;
          }
          if (!isfinite(v)) {
            fprintf(stderr, "vibroimpact: %s:%ld:%d: %s = '%s': not finite\n",
                    path, lno, (int)(fa - line) + 1, names[c], buf);
            rc = 2;
            goto done;
          }
          val[c] = v;
        }
      }
      k++;
      if (!*b) break;
      a = b + 1;
    }
    if (!ncol) {
      ncol = k;
      if (col[0] < 0 || col[1] < 0) {
        fprintf(stderr, "vibroimpact: %s:%ld: the header needs columns t and "
                "x (has: %s)", path, lno, line);
        rc = 2;
        goto done;
      }
      continue;
    }
    if (k != ncol) {
      fprintf(stderr, "vibroimpact: %s:%ld: %d fields, the header has %d\n",
              path, lno, k, ncol);
      rc = 2;
      goto done;
    }
    if (r->ns > 0 && !(val[0] > r->t[r->ns - 1])) {
      fprintf(stderr, "vibroimpact: %s:%ld:%d: t = %.17g does not increase "
              "(the sample before: %.17g)\n", path, lno, 1, val[0], r->t[r->ns - 1]);
      rc = 2;
      goto done;
    }
    if (r->ns == r->cap) {
      int nc = r->cap ? 2 * r->cap : 1024;
      double *q[4] = {r->t, r->x, r->v, r->f};
      for (int c = 0; c < 4; c++) {
        if (c >= 2 && col[c] < 0) continue;
        double *nq = realloc(q[c], sizeof(double) * nc);
        if (!nq) {
          fprintf(stderr, "vibroimpact: %s: out of memory\n", path);
          rc = 1;
          goto done;
        }
        q[c] = nq;
      }
      r->t = q[0];
      r->x = q[1];
      r->v = q[2];
      r->f = q[3];
      r->cap = nc;
    }
    r->t[r->ns] = val[0];
    r->x[r->ns] = val[1];
    if (r->v) r->v[r->ns] = val[2];
    if (r->f) r->f[r->ns] = val[3];
    r->ns++;
  }
  if (!ncol) {
    fprintf(stderr, "vibroimpact: %s: no header line (t,x[,v][,f])\n", path);
    rc = 2;
  } else if (r->ns < 16) {
    fprintf(stderr, "vibroimpact: %s: too few samples: %d (at least 16)\n",
            path, r->ns);
    rc = 2;
  }
done:
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
  for (int j = 0; !st && j < b->nk; j++) st = vi_scene_edit_set_number(e, b->key[j], p[j], &d);
  if (!st) st = vi_scene_edit_parse(e, &sc, &d);
  if (!st) st = vi_scene_create_model(sc, out, &d);
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

static double forcing_shift(const recording *r, double omega)
{
  /* f = alpha cos(Omega t) + beta sin(Omega t) by least squares: the
   * forcing phase of the recording, f = A cos(Omega (t + t0)) */
  if (!r->f) return NAN;
  double cc = 0, cs = 0, ss = 0, fc = 0, fs = 0;
  for (int i = 0; i < r->ns; i++) {
    double c = cos(omega * r->t[i]), s = sin(omega * r->t[i]);
    cc += c * c;
    cs += c * s;
    ss += s * s;
    fc += r->f[i] * c;
    fs += r->f[i] * s;
  }
  double det = cc * ss - cs * cs;
  if (!(fabs(det) > 0)) return NAN;
  double al = (fc * ss - fs * cs) / det, be = (fs * cc - fc * cs) / det;
  double T = 2 * M_PI / omega, t0 = fmod(atan2(-be, al) / omega, T);
  return t0 < 0 ? t0 + T : t0;
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
    "                            [--json] [-o OUT.h5]\n"
    "Fit scene parameters to a recorded periodic response (nonlinear least\n"
    "squares on the model's periodic orbit; an unknown forcing phase is\n"
    "fitted as a time shift).  The scene's values are the starting guesses.\n\n"
    "  --data FILE   CSV with a header: t, x required (x = w.x at the stop,\n"
    "                or coordinate I with --dof); v (velocity), f (forcing)\n"
    "                used when present; '#' lines are comments\n"
    "  --fit KEYS    numeric scene keys, comma-separated: stop.r, stop.xs,\n"
    "                forcing.omega, forcing.a[1], model.cantilever.zeta, ...\n"
    "  --dof I       the recording is coordinate I (1-based), not w.x\n"
    "  --noise S     the recording's noise standard deviation, if known\n"
    "                (else estimated from its 4th differences)\n"
    "  --unstable    also fit unstable orbits (a model that cannot hold the\n"
    "                recorded motion: which shape would it need?)\n"
    "  --set K=V     override a scene key first\n"
    "  --json        one JSON object on standard output\n"
    "  -o FILE.h5    the recording, fitted response, residuals and fit\n"
    "                (share/plot_identify.py plots it)\n"
    "Exit status: 0 converged, 1 run-time failure or no convergence, 2 bad "
    "input.\n");
}

int vi_cmd_identify_main(int argc, char **argv)
{
  const char *data = NULL, *fit = NULL, *out = NULL, *scene_path = NULL;
  const char *sets[64];
  int nsets = 0, json = 0, dof = 0, unstable = 0;
  double noise = 0.0;
  static const struct option lo[] = {
      {"data", required_argument, 0, 'd'}, {"fit", required_argument, 0, 'F'},
      {"dof", required_argument, 0, 'D'},  {"noise", required_argument, 0, 'n'},
      {"set", required_argument, 0, 's'},  {"json", no_argument, 0, 'j'},
      {"output", required_argument, 0, 'o'}, {"help", no_argument, 0, 'h'},
      {"unstable", no_argument, 0, 'u'},
      {0, 0, 0, 0}};
  int c;
  char *end;
  optind = 0;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "o:", lo, NULL)) != -1) {
    switch (c) {
    case 'd': data = optarg; break;
    case 'F': fit = optarg; break;
    case 'o': out = optarg; break;
    case 'j': json = 1; break;
    case 'u': unstable = 1; break;
    case 'D':
      dof = (int)strtol(optarg, &end, 10);
      if (end == optarg || *end || dof < 1) {
        fprintf(stderr, "vibroimpact: --dof: '%s' is not a coordinate number "
                "(1, 2, ...)\n", optarg);
        return 2;
      }
      break;
    case 'n':
      noise = strtod(optarg, &end);
      if (end == optarg || *end || !(noise > 0) || !isfinite(noise)) {
        fprintf(stderr, "vibroimpact: --noise: '%s' is not a number > 0\n", optarg);
        return 2;
      }
      break;
    case 's':
      if (nsets == 64) {
        fprintf(stderr, "vibroimpact: more than 64 --set\n");
        return 2;
      }
      sets[nsets++] = optarg;
      break;
    case 'h': usage(stdout); return 0;
    default:
      fprintf(stderr, "vibroimpact: identify: unknown or incomplete option '%s'\n",
              optind > 0 && optind <= argc ? argv[optind - 1] : "?");
      usage(stderr);
      return 2;
    }
  }
  if (optind < argc) scene_path = argv[optind++];
  if (optind < argc || !scene_path || !data || !fit) {
    fprintf(stderr, "vibroimpact: identify needs SCENE, --data and --fit\n");
    usage(stderr);
    return 2;
  }
  char target[VI_APP_PATH];
  vi_diag d;
  if (out && vi_output_resolve(out, target, sizeof target, &d)) {
    fprintf(stderr, "vibroimpact: %s\n", d.message);
    return 1;
  }
  /* the scene, with --set applied, kept as text for the builder */
  char err[600];
  int rc = 2, st;
  char *text = vi_sweep_read_text(scene_path, err, sizeof err);
  if (!text) {
    fprintf(stderr, "vibroimpact: %s\n", err);
    return 2;
  }
  vi_scene_edit *ed = NULL;
  vi_scene *sc = NULL;
  vi_model *model = NULL;
  vi_identify *id = NULL;
  recording rec;
  memset(&rec, 0, sizeof rec);
  builder b;
  memset(&b, 0, sizeof b);
  char *keys = strdup(fit), *edited = NULL;
  st = keys ? vi_scene_edit_create(text, -1, scene_path, &ed, &d) : VI_ERR_NOMEM;
  for (int i = 0; i < nsets && !st; i++) st = vi_scene_edit_assign(ed, sets[i], &d);
  if (!st) st = vi_scene_edit_parse(ed, &sc, &d);
  if (!st) st = vi_scene_create_model(sc, &model, &d);
  if (st) {
    vi_app_print_diag(&d, st);
    goto done;
  }
  edited = strdup(vi_scene_edit_text(ed));
  b.text = edited;
  b.name = scene_path;
  /* the keys: numeric scene values, or vi_param.h keys of the model */
  int use_builder = 0;
  double start[MAXKEY];
  for (char *save = NULL, *k = strtok_r(keys, ",", &save); k;
       k = strtok_r(NULL, ",", &save)) {
    if (b.nk == MAXKEY) {
      fprintf(stderr, "vibroimpact: --fit: more than %d keys\n", MAXKEY);
      goto done;
    }
    char buf[128];
    vi_diag kd;
    int gs = vi_scene_edit_get(ed, k, buf, sizeof buf, &kd);
    if (gs == VI_OK) {
      char *e2;
      double v = strtod(buf, &e2);
      if (e2 == buf || *e2 || !isfinite(v)) {
        int line, col;
        locate(edited, k, buf, &line, &col);
        fprintf(stderr, "vibroimpact: %s:%d:%d: %s = %s: not a number, cannot "
                "be fitted\n", scene_path, line, col, k, buf);
        goto done;
      }
      start[b.nk] = v;
      if (vi_param_kind(k) != VI_PARAM_MODEL) use_builder = 1;
    } else if (vi_param_kind(k) == VI_PARAM_MODEL &&
               vi_model_param(model, k, &start[b.nk]) == VI_OK) {
      /* a model key the scene does not write (stops[2].r, damping.zeta) */
    } else {
      fprintf(stderr, "vibroimpact: %s: --fit %s: %s\n", scene_path, k,
              gs == VI_ERR_PARSE ? kd.message : "not a numeric key");
      goto done;
    }
    b.key[b.nk++] = k;
  }
  if ((rc = read_csv(data, &rec))) goto done;
  int n = vi_model_n(model);
  if (dof > n) {
    fprintf(stderr, "vibroimpact: --dof %d: the model has %d coordinates\n", dof, n);
    rc = 2;
    goto done;
  }
  if ((st = vi_identify_create(model, b.nk, &id))) {
    fprintf(stderr, "vibroimpact: %s: cannot identify this model: %s\n",
            scene_path, vi_strerror(st));
    rc = st == VI_ERR_NOMEM ? 1 : 2;
    goto done;
  }
  for (int j = 0; j < b.nk && !st; j++) {
    st = vi_identify_set_param_key(id, j, b.key[j], NAN, NAN);
    if (st) { /* a scene key vi_param.h does not know: the builder sets it */
      int kind = VI_IDENTIFY_OTHER;
      st = vi_identify_set_param(id, j, kind, 0, start[j], -HUGE_VAL, HUGE_VAL);
    }
  }
  if (!st && use_builder) st = vi_identify_set_builder(id, build, &b, NULL);
  if (!st && dof) {
    double *cv = calloc(n, sizeof(double));
    st = cv ? VI_OK : VI_ERR_NOMEM;
    if (cv) {
      cv[dof - 1] = 1.0;
      st = vi_identify_set_observation(id, cv);
      free(cv);
    }
  }
  if (!st) st = vi_identify_set_noise(id, noise);
  if (!st && unstable) st = vi_identify_set_stable_only(id, 0);
  if (!st) st = vi_identify_set_data(id, rec.ns, rec.t, rec.x, rec.v);
  if (st) {
    fprintf(stderr, "vibroimpact: %s: %s\n", data, vi_identify_errmsg(id));
    rc = st == VI_ERR_NOMEM ? 1 : 2;
    goto done;
  }
  st = vi_identify_run(id);
  if (st) {
    fprintf(stderr, "vibroimpact: identify %s with %s: %s\n", scene_path, data,
            vi_identify_errmsg(id));
    rc = st == VI_ERR_ARG || st == VI_ERR_NOT_CONVERGED || st == VI_ERR_STATE ? 2 : 1;
    goto done;
  }
  /* the results */
  int np = b.nk, conv, iters, on, om;
  double p[MAXKEY], se[MAXKEY], l95[MAXKEY], h95[MAXKEY], R[MAXKEY * MAXKEY];
  int fl[MAXKEY];
  double rms, nz, rcond, t0, t0se, r12, vN, KE, RE, P, mu = NAN;
  vi_identify_params(id, p, se, l95, h95, fl);
  vi_identify_correlation(id, R, np);
  vi_identify_summary(id, &conv, &iters, &rms, &nz, &rcond, &on, &om);
  vi_identify_shift(id, &t0, &t0se);
  vi_identify_energy_restitution(id, &r12, &vN, &KE, &RE);
  vi_identify_orbit_period(id, &P, NULL);
  vi_identify_stability(id, &mu);
  double tf = forcing_shift(&rec, vi_model_omega_forcing(model));
  if (json) {
    printf("{\"fit\": {");
    for (int j = 0; j < np; j++) {
      printf("%s\"%s\": {\"value\": ", j ? ", " : "", b.key[j]);
      json_num(p[j]);
      printf(", \"stderr\": ");
      json_num(se[j]);
      printf(", \"ci95\": [");
      json_num(l95[j]);
      printf(", ");
      json_num(h95[j]);
      printf("], \"on_bound\": %s, \"undetermined\": %s}",
             fl[j] & VI_IDENTIFY_ON_BOUND ? "true" : "false",
             fl[j] & VI_IDENTIFY_UNDETERMINED ? "true" : "false");
    }
    printf("}, \"converged\": %s, \"iterations\": %d, \"rms_residual\": ",
           conv ? "true" : "false", iters);
    json_num(rms);
    printf(", \"noise\": ");
    json_num(nz);
    printf(", \"shift\": ");
    json_num(t0);
    printf(", \"shift_stderr\": ");
    json_num(t0se);
    printf(", \"shift_forcing\": ");
    json_num(tf);
    printf(", \"period\": ");
    json_num(P);
    printf(", \"orbit\": {\"n\": %d, \"m\": %d, \"stable\": %s, \"multiplier\": ",
           on, om, mu < 1.0 ? "true" : "false");
    json_num(mu);
    printf("}, \"samples\": %d, \"correlation\": [", rec.ns);
    for (int i = 0; i < np; i++) {
      printf("%s[", i ? ", " : "");
      for (int j = 0; j < np; j++) {
        printf("%s", j ? ", " : "");
        json_num(R[i + j * np]);
      }
      printf("]");
    }
    printf("], \"rcond\": ");
    json_num(rcond);
    printf(", \"r_energy_balance\": ");
    json_num(r12);
    printf(", \"vN_recorded\": ");
    json_num(vN);
    printf("}\n");
  } else {
    printf("identify: scene %s, recording %s: %d samples over %.1f periods of "
           "the fitted P(%d,%d) orbit\n", vi_scene_name(sc), data, rec.ns,
           (rec.t[rec.ns - 1] - rec.t[0]) / P, on, om);
    for (int j = 0; j < np; j++) {
      printf("  %-22s = %.6g +- %.2g   (95 %%: [%.6g, %.6g])%s%s%s\n", b.key[j],
             p[j], se[j], l95[j], h95[j],
             fl[j] & VI_IDENTIFY_ON_BOUND ? "  ON A BOUND" : "",
             fl[j] & VI_IDENTIFY_UNDETERMINED ? "  NOT DETERMINED by the data" : "",
             fl[j] & VI_IDENTIFY_CORRELATED ? "  correlated > 0.99" : "");
    }
    printf("  shift t0               = %.6g +- %.2g (model time = t + t0)", t0, t0se);
    if (isfinite(tf)) printf("; forcing column's phase: %.6g", tf);
    printf("\n  %s in %d iterations; residual RMS %.3g", conv ? "converged" : "NOT CONVERGED",
           iters, rms);
    if (isfinite(nz)) printf(" against a noise level %.3g (ratio %.2f%s)", nz, rms / nz,
                             rms > 1.5 * nz ? ": the model does not explain the data" : "");
    printf("\n");
    if (np > 1) {
      printf("  correlations:");
      for (int i = 0; i < np; i++)
        for (int j = i + 1; j < np; j++) printf(" %s/%s %.3f", b.key[i], b.key[j], R[i + j * np]);
      printf("\n");
    }
    if (isfinite(vN))
      printf("  WB 12 route: recorded v_N %.6g, KE_i %.6g, the model's RE %.6g: "
             "r = %.6g\n", vN, KE, RE, r12);
    if (!(mu < 1.0))
      printf("  the fitted orbit is UNSTABLE (largest |multiplier| %.3g): the "
             "model cannot show this motion\n", mu);
    if (rcond < 1e-10)
      printf("  warning: the Jacobian is ill-conditioned (rcond %.2g): the data "
             "do not determine every parameter\n", rcond);
  }
  rc = conv ? 0 : 1;
  if (out) {
    write_h5_fn w = load_writer();
    if (!w || w(target, id, fit, rec.ns, rec.t, rec.x, &d)) {
      if (w) fprintf(stderr, "vibroimpact: %s\n", d.message);
      rc = 1;
    }
  }
done:
  vi_identify_destroy(&id);
  vi_model_destroy(&model);
  vi_scene_destroy(&sc);
  vi_scene_edit_destroy(&ed);
  rec_free(&rec);
  free(text);
  free(keys);
  free(edited);
  return rc;
}
