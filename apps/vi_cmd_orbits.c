/* vi_cmd_orbits.c - `vibroimpact orbits`: P(n, m) orbits found directly.
 *
 *   vibroimpact orbits [SCENE.yaml] [--n N] [--m M] [--json] [--phases K]
 *                      [--set KEY=VALUE]... [--continue KEY --to B [--steps K]]
 *
 * The census itself (seeds, Newton, duplicates, multipliers,
 * admissibility) is the library's (vi_census.h); this command parses the
 * arguments, hands the scene's run settings and initial state to the
 * census, and prints (text or JSON) or follows each admissible orbit
 * (--continue, vi_cmd_orbits_cont.c). */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vibroimpact.h"
#include "vibroimpact/vi_census.h"
#include "vibroimpact/vi_output.h"
#include "vibroimpact/vi_scene.h"
#include "vibroimpact/vi_scene_edit.h"
#include "vi_diagram.h"

/* The census (vi_census.h) and the model it was run on. */
typedef struct list {
  const vi_model *mdl;
  vi_census *c;
  int N, n, m, count;
} list;

/* A whole number in [lo, hi] or -1. */
static int whole(const char *s, int lo, int hi)
{
  char *end;
  long v = strtol(s, &end, 10);
  return end != s && !*end && v >= lo && v <= hi ? (int)v : -1;
}

/* One orbit's impacts and stability, read from the census into buffers of
 * m and 2N entries (no numerics here). */
typedef struct orbit_view {
  int *stop, stable, admissible;
  double *t, *vn, *re, *im, gmax;
} orbit_view;

static int view_alloc(const list *L, orbit_view *o)
{
  memset(o, 0, sizeof *o);
  o->stop = malloc(sizeof(int) * (size_t)L->m);
  o->t = malloc(sizeof(double) * (size_t)L->m);
  o->vn = malloc(sizeof(double) * (size_t)L->m);
  o->re = malloc(sizeof(double) * 2 * (size_t)L->N);
  o->im = malloc(sizeof(double) * 2 * (size_t)L->N);
  return o->stop && o->t && o->vn && o->re && o->im ? 0 : 1;
}

static void view_free(orbit_view *o)
{
  free(o->stop);
  free(o->t);
  free(o->vn);
  free(o->re);
  free(o->im);
}

static void view_read(const list *L, int i, orbit_view *o)
{
  vi_census_orbit(L->c, i, o->t, NULL, NULL, L->N, o->stop, o->vn);
  vi_census_stability(L->c, i, o->re, o->im, &o->stable, &o->admissible, &o->gmax);
}

static void print_json_orbit(const list *L, const orbit_view *o, int i)
{
  int N = L->N, m = L->m;
  double T = vi_model_forcing_period(L->mdl);
  printf("%s{\"n\": %d, \"m\": %d, \"vN\": [", i ? ", " : "", L->n, m);
  for (int j = 0; j < m; j++) printf("%s%.17g", j ? ", " : "", o->vn[j]);
  printf("], \"stop\": [");
  for (int j = 0; j < m; j++) printf("%s%d", j ? ", " : "", o->stop[j]);
  printf("], \"impact_time_mod_T\": [");
  for (int j = 0; j < m; j++) printf("%s%.17g", j ? ", " : "", fmod(o->t[j], T));
  printf("], \"impact_time\": [");
  for (int j = 0; j < m; j++) printf("%s%.17g", j ? ", " : "", o->t[j]);
  printf("], \"multipliers\": [");
  for (int j = 0; j < 2 * N; j++)
    printf("%s[%.17g, %.17g]", j ? ", " : "", o->re[j], o->im[j]);
  printf("], \"stable\": %s, \"admissible\": %s, \"max_gap_between_impacts\": %.17g}",
         o->stable ? "true" : "false", o->admissible ? "true" : "false", o->gmax);
}

static void print_text_orbit(const list *L, const orbit_view *o, int i)
{
  int N = L->N, ns = vi_model_num_stops(L->mdl);
  double T = vi_model_forcing_period(L->mdl);
  printf("  orbit %d: %s, %s\n", i + 1, o->stable ? "stable" : "unstable",
         o->admissible ? "admissible" : "NOT admissible (contact between impacts, or no approach)");
  for (int j = 0; j < L->m; j++) {
    printf("    impact %d: t mod T = %.12g, v_N = %.12g", j + 1, fmod(o->t[j], T), o->vn[j]);
    if (ns > 1) printf(" (stop %d)", o->stop[j] + 1);
    printf("\n");
  }
  printf("    multipliers:");
  for (int j = 0; j < 2 * N; j++)
    printf(" %.8g%+.8gi (|%.6g|)", o->re[j], o->im[j], hypot(o->re[j], o->im[j]));
  printf("\n    largest gap between impacts %.3g\n", o->gmax);
}

/* The census as text (name: the scene) or JSON; 0, or 1 out of memory. */
static int print_orbits(const list *L, int json, const char *name)
{
  orbit_view o;
  if (view_alloc(L, &o)) {
    view_free(&o);
    return 1;
  }
  double T = vi_model_forcing_period(L->mdl);
  if (json) printf("{\"orbits\": [");
  else
    printf("P(%d,%d) orbits of %s (Omega = %.10g, T = %.10g): %d found\n", L->n,
           L->m, name, vi_model_omega_forcing(L->mdl), T, L->count);
  for (int i = 0; i < L->count; i++) {
    view_read(L, i, &o);
    if (json) print_json_orbit(L, &o, i);
    else print_text_orbit(L, &o, i);
  }
  if (json) printf("]}\n");
  view_free(&o);
  return 0;
}

typedef struct oargs {
  int np, mi, json, phases, nsets, csteps, arclength, max_depth;
  const char *scene, *ckey, **sets;
  double cto;
} oargs;

static void orbits_usage(void)
{
  printf("usage: vibroimpact orbits [SCENE.yaml] [--n N] [--m M] [--json] "
         "[--phases K] [--set KEY=VALUE]...\n"
         "Every P(n,m) orbit found (default P(1,1)): by an exhaustive scan of "
         "K impact phases\n(m = 1) and from transients, refined by Newton; "
         "stability from the Floquet\nmultipliers (monodromy with saltation "
         "matrices), admissibility checked.\n"
         "--continue KEY --to B [--steps K]: follow each admissible P(n,1) orbit in KEY\n"
         "to B (K steps, default 50), locating where it loses stability (period\n"
         "doubling, fold, Neimark-Sacker) or grazes; --arclength: pseudo-arclength,\n"
         "around folds.\n"
         "--max-depth D: deepest YAML nesting of the scene and the --set values\n"
         "(default %d).\n", VI_SCENE_MAX_DEPTH);
}

/* The command line; 0 to go on, -1 after --help, else the exit status. */
static int orbits_parse(int argc, char **argv, oargs *a)
{
  static const struct option lo[] = {
      {"n", required_argument, 0, 'n'},      {"m", required_argument, 0, 'm'},
      {"json", no_argument, 0, 'j'},         {"phases", required_argument, 0, 'p'},
      {"set", required_argument, 0, 's'},    {"help", no_argument, 0, 'h'},
      {"continue", required_argument, 0, 'C'}, {"to", required_argument, 0, 'T'},
      {"steps", required_argument, 0, 'S'},  {"arclength", no_argument, 0, 'A'},
      {"max-depth", required_argument, 0, 'D'}, {0, 0, 0, 0}};
  int c;
  optind = 1;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "", lo, NULL)) != -1) {
    switch (c) {
    case 'n': a->np = whole(optarg, 1, 64); break;
    case 'm': a->mi = whole(optarg, 1, 64); break;
    case 'j': a->json = 1; break;
    case 'p': a->phases = whole(optarg, 8, 1000000); break;
    case 's': a->sets[a->nsets++] = optarg; break;
    case 'C': a->ckey = optarg; break;
    case 'A': a->arclength = 1; break;
    case 'T': {
      char *end;
      a->cto = strtod(optarg, &end);
      if (end == optarg || *end || !isfinite(a->cto)) a->cto = NAN, a->np = -1;
      break;
    }
    case 'S': a->csteps = whole(optarg, 1, 1000000); break;
    case 'D': a->max_depth = whole(optarg, 1, 1000000); break;
    case 'h': orbits_usage(); return -1;
    default:
      fprintf(stderr, "vibroimpact: orbits: unknown or incomplete option '%s'\n",
              argv[optind - 1]);
      return 2;
    }
  }
  if (optind < argc) a->scene = argv[optind++];
  if (optind < argc || a->np < 1 || a->np > 64 || a->mi < 1 || a->mi > 64 ||
      a->phases < 8 || a->csteps < 1 || a->max_depth < 0 || (a->ckey && (isnan(a->cto) || a->mi != 1))) {
    fprintf(stderr, "vibroimpact: orbits: bad arguments (need 1 <= n, m <= 64, "
            "--phases >= 8, --max-depth >= 1, one scene; --continue KEY needs --to B, --steps K >= 1 "
            "and m = 1)\n");
    return 2;
  }
  return 0;
}

/* The scene and its model (harmonic forcing, no springs); 0 or the exit
 * status with the message printed. */
static int orbits_model(const oargs *a, vi_scene **sc, vi_model **mdl)
{
  char err[2048];
  vi_diag d;
  int rc = vi_app_load_scene(a->scene, a->sets, a->nsets, a->max_depth, 0, sc, err,
                             sizeof err);
  if (rc) {
    fprintf(stderr, "vibroimpact: %s\n", err);
    return rc;
  }
  if (vi_app_text_nonlinear(vi_scene_text(*sc))) {
    fprintf(stderr, "vibroimpact: orbits: %s has nonlinear springs; orbits are "
            "found with the linear closed-form flow, which would ignore them\n",
            a->scene ? a->scene : "the scene");
    return 2;
  }
  if (vi_scene_check_memory(*sc, 0, &d) || vi_scene_create_model(*sc, mdl, &d)) {
    vi_diag_format(&d, err, sizeof err);
    fprintf(stderr, "vibroimpact: %s\n", err);
    return 2;
  }
  if (!(vi_model_omega_forcing(*mdl) > 0)) {
    fprintf(stderr, "vibroimpact: orbits: the scene has no harmonic forcing\n");
    return 2;
  }
  return 0;
}

/* The sim hook: the scene's run settings on each transient. */
static int configure(vi_sim *sim, void *user)
{
  return vi_scene_configure_sim(user, sim, NULL);
}

/* The census (vi_census.h) seeded also from the scene's initial state;
 * 0, or the exit status with the message printed. */
static int census(list *L, const vi_scene *sc, int phases)
{
  int st = vi_census_create(L->mdl, L->n, L->m, &L->c);
  if (!st) st = vi_census_set_phases(L->c, phases);
  if (!st) st = vi_census_set_sim_hook(L->c, configure, (void *)sc, NULL);
  vi_sim *s0 = NULL;
  double t0, *xs = malloc(sizeof(double) * 2 * (size_t)L->N);
  if (!st && xs && !vi_sim_create(L->mdl, &s0) && !vi_scene_configure_sim(sc, s0, NULL) &&
      !vi_sim_state(s0, &t0, xs, xs + L->N))
    st = vi_census_set_initial(L->c, t0, xs, xs + L->N);
  vi_sim_destroy(&s0);
  free(xs);
  if (!st) st = vi_census_run(L->c);
  if (st) {
    fprintf(stderr, "vibroimpact: orbits: %s\n",
            L->c ? vi_census_errmsg(L->c) : vi_strerror(st));
    return st == VI_ERR_UNSUPPORTED || st == VI_ERR_STATE ? 2 : 1;
  }
  L->count = vi_census_count(L->c);
  return 0;
}

/* Follow every admissible orbit found in the key (vi_cmd_orbits_cont.c). */
static int follow_all(const list *L, const vi_scene *sc, const oargs *a)
{
  char err[2048];
  int rc = 0, adm;
  double t, *x = malloc(sizeof(double) * 2 * (size_t)L->N);
  if (!x) return 1;
  if (a->json) printf("{\"branches\": [");
  for (int i = 0, k = 0; i < L->count; i++) {
    vi_census_stability(L->c, i, NULL, NULL, NULL, &adm, NULL);
    if (!adm) continue;
    if (a->json && k++) printf(", ");
    vi_census_orbit(L->c, i, &t, x, x + L->N, L->N, NULL, NULL);
    int r = vi_orbits_follow(L->mdl, sc, a->ckey, a->arclength, a->cto, a->csteps,
                             a->np, t, x, x + L->N, a->json, err, sizeof err);
    if (r) {
      fprintf(stderr, "vibroimpact: orbits: --continue: %s\n", err);
      rc = r;
      break;
    }
  }
  if (a->json) printf("]}\n");
  free(x);
  return rc;
}

int vi_cmd_orbits_main(int argc, char **argv)
{
  oargs a = {1, 1, 0, 720, 0, 50, 0, 0, NULL, NULL, NULL, NAN};
  a.sets = calloc((size_t)argc + 1, sizeof *a.sets);
  if (!a.sets) return 1;
  vi_scene *sc = NULL;
  vi_model *mdl = NULL;
  list *L = NULL;
  int rc = orbits_parse(argc, argv, &a);
  if (rc < 0) rc = 0;
  else if (!rc && !(rc = orbits_model(&a, &sc, &mdl)) && !(L = calloc(1, sizeof *L)))
    rc = 1;
  if (L) {
    L->mdl = mdl;
    L->N = vi_model_n(mdl);
    L->n = a.np;
    L->m = a.mi;
    rc = census(L, sc, a.phases);
    if (!rc && a.ckey) rc = follow_all(L, sc, &a);
    else if (!rc)
      rc = print_orbits(L, a.json, a.scene ? a.scene : "the default scene (Fig. 2)");
    vi_census_destroy(&L->c);
    free(L);
  }
  vi_model_destroy(&mdl);
  vi_scene_destroy(&sc);
  free(a.sets);
  if (!rc) { /* a lost table or JSON is an error (> /dev/full) */
    vi_diag od;
    FILE *so = stdout;
    if (vi_output_close(&so, "-", VI_OUTPUT_STDOUT, &od)) {
      fprintf(stderr, "vibroimpact: orbits: %s\n", od.message);
      rc = 1;
    }
  }
  return rc;
}
