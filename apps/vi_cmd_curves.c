/* vi_cmd_curves.c - `vibroimpact curves`: a codimension-one point of the
 * scene's orbit followed in two parameters (vi_cont_curve.h), printed as
 * text or JSON and written to HDF5 (vi_curves_h5.c).  The numerics are the
 * library's; this parses, finds the scene's orbit and prints.
 *
 *   vibroimpact curves [SCENE] --kind grazing|fold|pd|ns [--orbit N,M]
 *       --param KEY --to B --param2 KEY2 --from2 C --to2 D [--steps K]
 *       [--json] [-o OUT.h5] [--set KEY=VALUE]... */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vibroimpact.h"
#include "vibroimpact/vi_output.h"
#include "vibroimpact/vi_scene.h"
#include "vibroimpact/vi_scene_param.h"
#include "vi_app.h"
#include "vi_curves.h"
#include "vi_diagram.h"

static const char *const kinds[] = {"grazing", "fold", "pd", "ns"};
static const char *const sp_names[] = {"grazing", "fold", "period_doubling", "cusp",
                                       "resonance_1_1", "resonance_1_2", "admissibility"};

static const char *kind_name(int k) { return k >= 0 && k < 4 ? kinds[k] : "?"; }
static const char *sp_name(int t) { return t >= 0 && t < 7 ? sp_names[t] : "?"; }

typedef struct cargs {
  int kind, n, m, steps, json, nsets, max_depth;
  const char *scene, *key, *key2, *out, **sets;
  double to, from2, to2;
} cargs;

static void curves_usage(void)
{
  printf("usage: vibroimpact curves [SCENE.yaml] --kind grazing|fold|pd|ns [--orbit N,M]\n"
         "         --param KEY --to B --param2 KEY2 --from2 C --to2 D [--steps K]\n"
         "         [--json] [-o OUT.h5] [--set KEY=VALUE]... [--max-depth D]\n"
         "Follow the scene's P(N,M) orbit (default 1,1; 1,0 the non-impacting one; M > 1\n"
         "the census's, as `orbits --n N --m M` finds it) in\n"
         "KEY from the scene's value towards B to its first point of the kind (grazing:\n"
         "the gap between impacts, or of the free motion, reaches the stop; fold: a\n"
         "multiplier +1; pd: -1; ns: a complex pair on the unit circle), solved by\n"
         "Newton on the orbit's equations plus that condition, then follow the point in\n"
         "(KEY, KEY2) by pseudo-arclength over KEY2 from C to D (largest step 1/K of the\n"
         "range, default K = 200), listing the codimension-two points met: grazing,\n"
         "fold, period_doubling (another curve met), cusp, resonance_1_1,\n"
         "resonance_1_2, admissibility (v_N = 0).  Points in order along the curve.\n");
}

static int num(const char *s, double *out)
{
  char *end;
  double v = strtod(s, &end);
  if (end == s || *end || !isfinite(v)) return 1;
  *out = v;
  return 0;
}

static int set_kind(cargs *a, const char *s)
{
  for (int k = 0; k < 4; k++)
    if (!strcmp(s, kinds[k])) {
      a->kind = k;
      return 0;
    }
  return 1;
}

static int set_orbit(cargs *a, const char *s)
{
  char *end;
  long n = strtol(s, &end, 10);
  if (end == s || *end != ',') return 1;
  const char *ms = end + 1;
  long m = strtol(ms, &end, 10);
  if (end == ms || *end || n < 1 || n > 64 || m < 0 || m > 32 || (m == 0 && n != 1)) return 1;
  a->n = (int)n;
  a->m = (int)m;
  return 0;
}

/* The command line; 0 to go on, -1 after --help, else the exit status. */
static int curves_parse(int argc, char **argv, cargs *a)
{
  static const struct option lo[] = {
      {"kind", required_argument, 0, 'k'},   {"orbit", required_argument, 0, 'O'},
      {"param", required_argument, 0, 'p'},  {"to", required_argument, 0, 't'},
      {"param2", required_argument, 0, 'P'}, {"from2", required_argument, 0, 'f'},
      {"to2", required_argument, 0, 'T'},    {"steps", required_argument, 0, 'S'},
      {"json", no_argument, 0, 'j'},         {"output", required_argument, 0, 'o'},
      {"set", required_argument, 0, 's'},    {"max-depth", required_argument, 0, 'D'},
      {"help", no_argument, 0, 'h'},         {0, 0, 0, 0}};
  int c, bad = 0;
  const char *what = NULL;
  optind = 1;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "o:", lo, NULL)) != -1) {
    char *end;
    what = argv[optind - 1];
    switch (c) {
    case 'k': bad |= set_kind(a, optarg); break;
    case 'O': bad |= set_orbit(a, optarg); break;
    case 'p': a->key = optarg; break;
    case 'P': a->key2 = optarg; break;
    case 't': bad |= num(optarg, &a->to); break;
    case 'f': bad |= num(optarg, &a->from2); break;
    case 'T': bad |= num(optarg, &a->to2); break;
    case 'S': {
      long k = strtol(optarg, &end, 10);
      if (*end || end == optarg || k < 1 || k > 1000000) {
        fprintf(stderr, "vibroimpact: curves: --steps must be a whole number in [1, 1000000] "
                "(got '%s')\n", optarg);
        return 2;
      }
      a->steps = (int)k;
      break;
    }
    case 'D':
      a->max_depth = (int)strtol(optarg, &end, 10);
      bad |= *end || a->max_depth < 1;
      break;
    case 'j': a->json = 1; break;
    case 'o': a->out = optarg; break;
    case 's': a->sets[a->nsets++] = optarg; break;
    case 'h': curves_usage(); return -1;
    default: bad = 1; break;
    }
    if (bad) {
      fprintf(stderr, "vibroimpact: curves: bad or incomplete option '%s'%s%s\n", what,
              optarg ? " value " : "", optarg ? optarg : "");
      return 2;
    }
  }
  if (optind < argc) a->scene = argv[optind++];
  if (optind < argc || a->kind < 0 || !a->key || !a->key2 || isnan(a->to) || isnan(a->from2) ||
      isnan(a->to2) || a->from2 == a->to2 || (a->m == 0 && a->kind != 0)) {
    fprintf(stderr, "vibroimpact: curves: need --kind grazing|fold|pd|ns, --param KEY --to B, "
            "--param2 KEY2 --from2 C --to2 D (C != D), one scene; --orbit 1,0 is for "
            "--kind grazing only (vibroimpact curves --help)\n");
    return 2;
  }
  return 0;
}

/* The scene's model and parameter keys; 0 or the exit status, printed. */
static int curves_model(const cargs *a, vi_scene **sc, vi_model **mdl, char *k1, char *k2)
{
  char err[2048];
  vi_diag d;
  int rc = vi_app_load_scene(a->scene, a->sets, a->nsets, a->max_depth, 0, sc, err,
                             sizeof err);
  if (!rc && vi_app_text_nonlinear(vi_scene_text(*sc))) {
    snprintf(err, sizeof err, "curves: the scene has nonlinear springs; orbits are found "
             "with the linear closed-form flow, which would ignore them");
    rc = 2;
  }
  if (!rc && (vi_scene_check_memory(*sc, 0, &d) || vi_scene_create_model(*sc, mdl, &d) ||
              vi_scene_param_key(*sc, a->key, k1, 64, &d) ||
              vi_scene_param_key(*sc, a->key2, k2, 64, &d))) {
    vi_diag_format(&d, err, sizeof err);
    rc = 2;
  }
  if (!rc && !(vi_model_omega_forcing(*mdl) > 0)) {
    snprintf(err, sizeof err, "curves: the scene has no harmonic forcing");
    rc = 2;
  }
  /* what vi_cont_curve_create refuses without a handle to say why */
  for (int k = 0; k < 2 && !rc; k++)
    if (vi_param_kind(k ? k2 : k1) == VI_PARAM_INITIAL_STATE) {
      snprintf(err, sizeof err, "curves: %s %s is an initial-state key: a curve's two "
               "parameters are the model's (forcing, stop, damping, ...), and an orbit "
               "makes its own initial state", k ? "--param2" : "--param", k ? k2 : k1);
      rc = 2;
    }
  if (!rc && vi_app_same_key(k1, k2)) {
    snprintf(err, sizeof err, "curves: --param %s and --param2 %s name one parameter: a "
             "curve needs two different parameters", k1, k2);
    rc = 2;
  }
  double v; /* an index beyond the model's coordinates, stops or modes */
  for (int k = 0; k < 2 && !rc; k++)
    if (vi_model_param(*mdl, k ? k2 : k1, &v)) {
      snprintf(err, sizeof err, "curves: %s: %s", k ? "--param2" : "--param",
               vi_model_errmsg(*mdl));
      rc = 2;
    }
  if (rc) fprintf(stderr, "vibroimpact: %s\n", err);
  return rc;
}

/* The scene's P(n,1) orbit: of those the phase scan finds, the admissible
 * one with the smallest largest multiplier.  0, or 1 if none. */
static int scene_orbit(const vi_model *m, int n, double *t, double *x, double *v)
{
  int N = vi_model_n(m), found = 0, best = -1, cap = 16, ok;
  double *tt = malloc(sizeof(double) * cap * (2 * (size_t)N + 1)), rb = HUGE_VAL, gmax;
  double *re = malloc(sizeof(double) * 4 * (size_t)N), *im = re ? re + 2 * (size_t)N : NULL;
  if (tt && re && !vi_orbit_p1_scan(m, n, 720, tt, tt + cap, tt + cap + (size_t)N * cap, N, cap,
                                    &found)) {
    for (int i = 0; i < found && i < cap; i++) {
      double *xi = tt + cap + (size_t)N * i, *vi = xi + (size_t)N * cap, rho = 0;
      if (vi_orbit_pnm_admissible(m, n, 1, tt + i, xi, vi, N, &gmax, &ok) || !ok ||
          vi_orbit_pnm_multipliers(m, n, 1, tt + i, xi, vi, N, re, im))
        continue;
      for (int j = 0; j < 2 * N; j++) rho = fmax(rho, hypot(re[j], im[j]));
      if (rho < rb) {
        rb = rho;
        best = i;
      }
    }
  }
  if (best >= 0) {
    *t = tt[best];
    memcpy(x, tt + cap + (size_t)N * best, sizeof(double) * N);
    memcpy(v, tt + cap + (size_t)N * (cap + best), sizeof(double) * N);
  }
  free(tt);
  free(re);
  return best < 0;
}

/* The sim hook: the scene's run settings on each transient. */
static int configure(vi_sim *sim, void *user)
{
  return vi_scene_configure_sim(user, sim, NULL);
}

/* The impacts of orbit i of census L, rotated to start at the earliest
 * (ascending within one orbit period, as vi_cont_curve_set_impacts wants). */
static void census_impacts(const vi_census *L, int i, int N, int mi, double *t, double *x,
                           double *v)
{
  double *b = malloc(sizeof(double) * (size_t)mi * (2 * (size_t)N + 1));
  if (!b) return;
  vi_census_orbit(L, i, b, b + mi, b + mi + (size_t)N * mi, N, NULL, NULL);
  int j0 = 0;
  for (int j = 1; j < mi; j++)
    if (b[j] < b[j0]) j0 = j;
  for (int j = 0; j < mi; j++) {
    int k = (j0 + j) % mi;
    t[j] = b[k];
    memcpy(x + (size_t)N * j, b + mi + (size_t)N * k, sizeof(double) * N);
    memcpy(v + (size_t)N * j, b + mi + (size_t)N * (mi + k), sizeof(double) * N);
  }
  free(b);
}

/* The scene's P(n,m) orbit, m > 1: of those the census finds (vi_census.h:
 * transients from the scene's initial state and from rest, refined by
 * Newton), the admissible one with the smallest largest multiplier.  0, or
 * 1 if none. */
static int scene_orbit_m(const vi_scene *sc, const vi_model *m, int n, int mi, double *t,
                         double *x, double *v)
{
  int N = vi_model_n(m), best = -1, adm;
  double rb = HUGE_VAL, t0, *re = malloc(sizeof(double) * 4 * (size_t)N), *im = NULL;
  vi_census *L = NULL;
  vi_sim *s0 = NULL;
  if (re && !vi_census_create(m, n, mi, &L) && !vi_census_set_sim_hook(L, configure, (void *)sc,
                                                                       NULL)) {
    im = re + 2 * (size_t)N; /* x, v as the initial state's scratch */
    if (!vi_sim_create(m, &s0) && !vi_scene_configure_sim(sc, s0, NULL) &&
        !vi_sim_state(s0, &t0, x, v))
      vi_census_set_initial(L, t0, x, v);
    if (!vi_census_run(L))
      for (int i = 0; i < vi_census_count(L); i++) {
        double rho = 0;
        vi_census_stability(L, i, re, im, NULL, &adm, NULL);
        for (int j = 0; adm && j < 2 * N; j++) rho = fmax(rho, hypot(re[j], im[j]));
        if (adm && rho < rb) {
          rb = rho;
          best = i;
        }
      }
  }
  if (best >= 0) census_impacts(L, best, N, mi, t, x, v);
  vi_sim_destroy(&s0);
  vi_census_destroy(&L);
  free(re);
  return best < 0;
}

/* The curve from the located point, collected into r; 0, or the status. */
static int trace(vi_cont_curve *c, vi_curve_result *r)
{
  int st = VI_OK;
  while (!vi_cont_curve_done(c)) {
    st = vi_cont_curve_iterate(c);
    if (st < 0) return st;
    if (st) break;
    double p, p2;
    vi_cont_curve_point(c, &p, &p2, NULL, NULL, NULL, NULL);
    if (vi_curve_result_add(r, p, p2)) return VI_ERR_NOMEM;
    for (int i = 0; i < vi_cont_curve_num_special(c); i++) {
      int type, loc;
      vi_cont_curve_special(c, i, &type, &p, &p2, &loc);
      if (vi_curve_result_special(r, type, p, p2, loc)) return VI_ERR_NOMEM;
    }
  }
  r->state = vi_cont_curve_done(c);
  r->start = vi_cont_curve_start(c);
  return VI_OK;
}

/* Locate and follow; 0, or the exit status with the message printed. */
static int run_curve(const cargs *a, const vi_scene *sc, const vi_model *m, const char *k1,
                     const char *k2, vi_curve_result *r)
{
  int N = vi_model_n(m), st, mi = a->m > 1 ? a->m : 1;
  double t[32] = {0}, *x = calloc(2 * (size_t)N * mi, sizeof(double));
  vi_cont_curve *c = NULL;
  if (!x) return 1;
  if (a->m && (a->m > 1 ? scene_orbit_m(sc, m, a->n, a->m, t, x, x + (size_t)N * mi)
               : scene_orbit(m, a->n, t, x, x + N))) {
    fprintf(stderr, "vibroimpact: curves: the scene has no admissible P(%d,%d) orbit\n", a->n,
            a->m);
    free(x);
    return 1;
  }
  st = vi_cont_curve_create(m, a->kind, a->n, a->m, k1, k2, &c);
  if (!st && a->m) st = vi_cont_curve_set_impacts(c, t, x, x + (size_t)N * mi, N);
  if (!st) st = vi_cont_curve_locate(c, a->to, a->steps, &r->located);
  if (!st) st = vi_cont_curve_point(c, NULL, &r->located2, NULL, NULL, NULL, NULL);
  if (!st) st = vi_cont_curve_set_range(c, a->from2, a->to2, a->steps);
  if (!st) st = trace(c, r);
  if (st)
    fprintf(stderr, "vibroimpact: curves: %s\n",
            c && vi_cont_curve_errmsg(c)[0] ? vi_cont_curve_errmsg(c) : vi_strerror(st));
  vi_cont_curve_destroy(&c);
  free(x);
  return st == VI_ERR_ARG || st == VI_ERR_UNSUPPORTED ? 2 : st ? 1 : 0;
}

static void print_result(const cargs *a, const vi_curve_result *r)
{
  if (a->json) {
    printf("{\"kind\": \"%s\", \"param\": \"%s\", \"param2\": \"%s\", \"orbit\": [%d, %d], "
           "\"located\": [%.17g, %.17g], \"points\": [", kind_name(a->kind), a->key, a->key2,
           a->n, a->m, r->located, r->located2);
    for (int i = 0; i < r->npts; i++)
      printf("%s[%.17g, %.17g]", i ? ", " : "", r->pts[2 * (size_t)i], r->pts[2 * (size_t)i + 1]);
    printf("], \"special\": [");
    for (int i = 0; i < r->nsp; i++)
      printf("%s{\"type\": \"%s\", \"point\": [%.17g, %.17g], \"located\": %s}", i ? ", " : "",
             sp_name(r->sp_type[i]), r->sp_pts[2 * (size_t)i], r->sp_pts[2 * (size_t)i + 1],
             r->sp_loc[i] ? "true" : "false");
    printf("], \"start\": \"%s\", \"end\": \"%s\"}\n", vi_curve_end_name(r->start),
           vi_curve_end_name(r->state));
    return;
  }
  printf("%s curve of the P(%d,%d) orbit in (%s, %s): located at %s = %.12g (%s = %.12g)\n",
         kind_name(a->kind), a->n, a->m, a->key, a->key2, a->key, r->located, a->key2, r->located2);
  printf("  %d points (first: %s; last: %s) %18s %18s\n", r->npts,
         vi_curve_end_name(r->start), vi_curve_end_name(r->state), a->key, a->key2);
  for (int i = 0; i < r->npts; i++)
    printf("  %42.12g %18.12g\n", r->pts[2 * (size_t)i], r->pts[2 * (size_t)i + 1]);
  for (int i = 0; i < r->nsp; i++)
    printf("  -> %s at %s = %.12g, %s = %.12g%s\n", sp_name(r->sp_type[i]), a->key,
           r->sp_pts[2 * (size_t)i], a->key2, r->sp_pts[2 * (size_t)i + 1],
           r->sp_loc[i] ? "" : " (interpolated)");
}

int vi_cmd_curves_main(int argc, char **argv)
{
  cargs a = {-1, 1, 1, 200, 0, 0, 0, NULL, NULL, NULL, NULL, NULL, NAN, NAN, NAN};
  char k1[64], k2[64];
  vi_scene *sc = NULL;
  vi_model *mdl = NULL;
  vi_curve_result r;
  memset(&r, 0, sizeof r);
  a.sets = calloc((size_t)argc + 1, sizeof *a.sets);
  if (!a.sets) return 1;
  int rc = curves_parse(argc, argv, &a), help = rc < 0; /* help: printed, no curve */
  if (help) rc = 0;
  else if (!rc && !(rc = curves_model(&a, &sc, &mdl, k1, k2)))
    rc = run_curve(&a, sc, mdl, k1, k2, &r);
  if (!rc && !help && a.out) {
    char err[1024];
    if (vi_curves_write_h5(a.out, kind_name(a.kind), a.key, a.key2, a.n, a.m, &r, err,
                           sizeof err)) {
      fprintf(stderr, "vibroimpact: curves: %s\n", err);
      rc = 1;
    }
  }
  if (!rc && !help) print_result(&a, &r);
  vi_curve_result_free(&r);
  vi_model_destroy(&mdl);
  vi_scene_destroy(&sc);
  free(a.sets);
  if (!rc) {
    vi_diag od;
    FILE *so = stdout;
    if (vi_output_close(&so, "-", VI_OUTPUT_STDOUT, &od)) {
      fprintf(stderr, "vibroimpact: curves: %s\n", od.message);
      rc = 1;
    }
  }
  return rc;
}
