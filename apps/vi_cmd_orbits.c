/* vi_cmd_orbits.c - `vibroimpact orbits`: P(n, m) orbits found directly.
 *
 *   vibroimpact orbits [SCENE.yaml] [--n N] [--m M] [--json] [--phases K]
 *                      [--set KEY=VALUE]... [--continue KEY --to B [--steps K]]
 *
 * Seeds: for m = 1 an exhaustive scan of impact phases (vi_orbit_p1_scan:
 * every P(n,1) orbit, unstable and inadmissible ones included); for any m
 * the motions that transients settle on, from the scene's `initial:` and
 * from rest at 8 forcing phases.  Each seed is refined by Newton
 * (vi_orbit_pnm_solve_stops), checked for admissibility, and its Floquet
 * multipliers come from the monodromy matrix with saltation matrices.
 * With several stops each impact keeps the stop it hit (the seeds are
 * transients only: the scan is for one stop). */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vibroimpact.h"
#include "vibroimpact/vi_output.h"
#include "vibroimpact/vi_scene.h"
#include "vibroimpact/vi_scene_edit.h"
#include "vi_sweep.h"

#define MAXORB 64
#define RINGN 4096

typedef struct orbit {
  int n, m, admissible, stable;
  int *stop;                   /* [m] the stop of each impact */
  double *t, *x, *v, *re, *im; /* [m], [N x m], [N x m], [2N], [2N] */
  double gmax;
} orbit;

typedef struct list {
  const vi_model *mdl;
  int N, n, m, count;
  orbit o[MAXORB];
} list;

static void orbit_free(orbit *o)
{
  free(o->stop);
  free(o->t);
  free(o->x);
  free(o->v);
  free(o->re);
  free(o->im);
  memset(o, 0, sizeof *o);
}

/* A whole number in [lo, hi] or -1. */
static int whole(const char *s, int lo, int hi)
{
  char *end;
  long v = strtol(s, &end, 10);
  return end != s && !*end && v >= lo && v <= hi ? (int)v : -1;
}

/* Same orbit: the same impacts up to a cyclic shift of their order and a
 * shift of time by whole forcing periods (the forcing is T-periodic, so a
 * P(n, m) orbit and its copy started T later are one orbit). */
static int same(const list *L, const orbit *a, const double *t, const double *v,
                const int *stop)
{
  double T = 2 * M_PI / vi_model_omega_forcing(L->mdl);
  int N = L->N;
  for (int s = 0; s < L->m; s++) {
    int ok = 1;
    for (int j = 0; j < L->m && ok; j++) {
      int k = (j + s) % L->m;
      if (a->stop[j] != stop[k]) {
        ok = 0;
        break;
      }
      double d = fmod(fabs(a->t[j] - t[k]), T), dv = 0, sv = 1;
      for (int q = 0; q < N; q++) {
        dv = fmax(dv, fabs(a->v[(size_t)j * N + q] - v[(size_t)k * N + q]));
        sv = fmax(sv, fabs(v[(size_t)k * N + q]));
      }
      ok = fmin(d, T - d) < 1e-7 * T && dv < 1e-6 * sv;
    }
    if (ok) return 1;
  }
  return 0;
}

/* Refine a seed (stop: the stop of each impact, NULL for stop 0); keep it
 * if new. */
static void add(list *L, double *t, double *x, double *v, const int *stop)
{
  int N = L->N, m = L->m;
  int *sp = calloc((size_t)m, sizeof(int));
  if (!sp) return;
  for (int j = 0; stop && j < m; j++) sp[j] = stop[j];
  if (vi_orbit_pnm_solve_stops(L->mdl, L->n, m, sp, t, x, v, N, 0.0, NULL)) {
    free(sp);
    return;
  }
  double P = L->n * 2 * M_PI / vi_model_omega_forcing(L->mdl);
  /* impact times into [0, nT), order kept cyclically */
  double sh = floor(t[0] / P) * P;
  for (int j = 0; j < m; j++) t[j] -= sh;
  for (int i = 0; i < L->count; i++)
    if (same(L, &L->o[i], t, v, sp)) {
      free(sp);
      return;
    }
  if (L->count == MAXORB) {
    free(sp);
    return;
  }
  orbit *o = &L->o[L->count];
  memset(o, 0, sizeof *o);
  o->stop = sp;
  o->t = malloc(sizeof(double) * m);
  o->x = malloc(sizeof(double) * N * m);
  o->v = malloc(sizeof(double) * N * m);
  o->re = malloc(sizeof(double) * 2 * N);
  o->im = malloc(sizeof(double) * 2 * N);
  if (!o->t || !o->x || !o->v || !o->re || !o->im) {
    orbit_free(o);
    return;
  }
  memcpy(o->t, t, sizeof(double) * m);
  memcpy(o->x, x, sizeof(double) * N * m);
  memcpy(o->v, v, sizeof(double) * N * m);
  o->n = L->n;
  o->m = m;
  if (vi_orbit_pnm_multipliers_stops(L->mdl, L->n, m, sp, t, x, v, N, o->re, o->im) ||
      vi_orbit_pnm_admissible_stops(L->mdl, L->n, m, sp, t, x, v, N, &o->gmax,
                                    &o->admissible)) {
    orbit_free(o);
    return;
  }
  double mx = 0;
  for (int i = 0; i < 2 * N; i++) mx = fmax(mx, hypot(o->re[i], o->im[i]));
  o->stable = mx < 1.0;
  L->count++;
}

/* ---- seeds from transients ---------------------------------------------- */
typedef struct ring {
  int N;
  int64_t k;
  double t[RINGN], *z; /* z: RINGN x 2N, pre-impact (x, v) */
  int stop[RINGN];
} ring;

static int on_impact(const vi_event *ev, void *user)
{
  ring *r = user;
  if (ev->kind != VI_EVENT_IMPACT) return 0;
  int i = (int)(r->k % RINGN);
  r->t[i] = ev->t;
  r->stop[i] = ev->stop;
  memcpy(r->z + (size_t)i * 2 * r->N, ev->x, sizeof(double) * r->N);
  memcpy(r->z + (size_t)i * 2 * r->N + r->N, ev->v_minus, sizeof(double) * r->N);
  r->k++;
  return 0;
}

/* Run from (t0, x0, v0) until the stroboscopic states repeat with period n
 * (3 times, 1e-9 relative) with m impacts per n periods; seed from them. */
static void transient_seed(list *L, const vi_scene *sc, double t0,
                           const double *x0, const double *v0, int maxp)
{
  int N = L->N, n = L->n, m = L->m;
  vi_sim *s = NULL;
  ring *r = calloc(1, sizeof *r);
  double *z = malloc(sizeof(double) * 2 * N * (3 * n + 1)), T;
  double *st = malloc(sizeof(double) * (2 * N + 1) * m + 1);
  if (!r || !z || !st) goto done;
  r->N = N;
  r->z = malloc(sizeof(double) * RINGN * 2 * N);
  if (!r->z || vi_sim_create(L->mdl, &s) || vi_scene_configure_sim(sc, s, NULL) ||
      vi_sim_set_method(s, VI_METHOD_EXACT) || vi_sim_set_initial(s, t0, x0, v0))
    goto done;
  vi_sim_set_event_callback(s, on_impact, r, NULL);
  T = 2 * M_PI / vi_model_omega_forcing(L->mdl);
  int W = 3 * n + 1;
  for (int k = 1; k <= maxp; k++) {
    if (vi_sim_run(s, t0 + k * T)) goto done;
    double *zk = z + (size_t)(k % W) * 2 * N;
    vi_sim_state(s, NULL, zk, zk + N);
    if (k < W || r->k < m) continue;
    double scl = 1e-9;
    for (int i = 0; i < 2 * N; i++) scl = fmax(scl, fabs(zk[i]));
    int ok = 1;
    for (int j = 1; j <= 3 && ok; j++)
      for (int i = 0; i < 2 * N && ok; i++)
        ok = fabs(z[(size_t)((k - j * n) % W) * 2 * N + i] - zk[i]) <= 1e-9 * scl;
    if (!ok) continue;
    int cnt = 0;
    double tn = t0 + (k - n) * T;
    for (int64_t q = r->k - 1; q >= 0 && q > r->k - RINGN && r->t[q % RINGN] >= tn; q--) cnt++;
    if (cnt != m) goto done; /* periodic, but another P(n, m') */
    double *tt = st, *xx = tt + m, *vv = xx + (size_t)N * m;
    int *sp = malloc(sizeof(int) * (size_t)m);
    if (!sp) goto done;
    for (int j = 0; j < m; j++) {
      int64_t q = r->k - m + j;
      tt[j] = r->t[q % RINGN];
      sp[j] = r->stop[q % RINGN];
      memcpy(xx + (size_t)j * N, r->z + (size_t)(q % RINGN) * 2 * N, sizeof(double) * N);
      memcpy(vv + (size_t)j * N, r->z + (size_t)(q % RINGN) * 2 * N + N, sizeof(double) * N);
    }
    add(L, tt, xx, vv, sp);
    free(sp);
    goto done;
  }
done:
  vi_sim_destroy(&s);
  if (r) free(r->z);
  free(r);
  free(z);
  free(st);
}

/* the approach velocity w_k.v of impact j on its stop k */
static double approach(const list *L, const orbit *o, int j)
{
  int N = L->N;
  double *w = malloc(sizeof(double) * (size_t)N), vn = NAN;
  if (w && !vi_model_stop(L->mdl, o->stop[j], w, NULL, NULL)) {
    vn = 0;
    for (int q = 0; q < N; q++) vn += w[q] * o->v[(size_t)j * N + q];
  }
  free(w);
  return vn;
}

static void print_json(const list *L)
{
  int N = L->N;
  printf("{\"orbits\": [");
  for (int i = 0; i < L->count; i++) {
    const orbit *o = &L->o[i];
    double P = o->n * 2 * M_PI / vi_model_omega_forcing(L->mdl),
           T = P / o->n;
    printf("%s{\"n\": %d, \"m\": %d, \"vN\": [", i ? ", " : "", o->n, o->m);
    for (int j = 0; j < o->m; j++)
      printf("%s%.17g", j ? ", " : "", approach(L, o, j));
    printf("], \"stop\": [");
    for (int j = 0; j < o->m; j++) printf("%s%d", j ? ", " : "", o->stop[j]);
    printf("], \"impact_time_mod_T\": [");
    for (int j = 0; j < o->m; j++) printf("%s%.17g", j ? ", " : "", fmod(o->t[j], T));
    printf("], \"impact_time\": [");
    for (int j = 0; j < o->m; j++) printf("%s%.17g", j ? ", " : "", o->t[j]);
    printf("], \"multipliers\": [");
    for (int j = 0; j < 2 * N; j++)
      printf("%s[%.17g, %.17g]", j ? ", " : "", o->re[j], o->im[j]);
    printf("], \"stable\": %s, \"admissible\": %s, \"max_gap_between_impacts\": %.17g}",
           o->stable ? "true" : "false", o->admissible ? "true" : "false", o->gmax);
  }
  printf("]}\n");
}

static void print_text(const list *L, const char *name)
{
  int N = L->N, ns = vi_model_num_stops(L->mdl);
  double T = 2 * M_PI / vi_model_omega_forcing(L->mdl);
  printf("P(%d,%d) orbits of %s (Omega = %.10g, T = %.10g): %d found\n", L->n,
         L->m, name, vi_model_omega_forcing(L->mdl), T, L->count);
  for (int i = 0; i < L->count; i++) {
    const orbit *o = &L->o[i];
    printf("  orbit %d: %s, %s\n", i + 1, o->stable ? "stable" : "unstable",
           o->admissible ? "admissible" : "NOT admissible (contact between impacts, or no approach)");
    for (int j = 0; j < o->m; j++) {
      printf("    impact %d: t mod T = %.12g, v_N = %.12g", j + 1, fmod(o->t[j], T),
             approach(L, o, j));
      if (ns > 1) printf(" (stop %d)", o->stop[j] + 1);
      printf("\n");
    }
    printf("    multipliers:");
    for (int j = 0; j < 2 * N; j++)
      printf(" %.8g%+.8gi (|%.6g|)", o->re[j], o->im[j], hypot(o->re[j], o->im[j]));
    printf("\n    largest gap between impacts %.3g\n", o->gmax);
  }
}

typedef struct oargs {
  int np, mi, json, phases, nsets, csteps, arclength;
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
         "around folds.\n");
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
      {0, 0, 0, 0}};
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
    case 'h': orbits_usage(); return -1;
    default:
      fprintf(stderr, "vibroimpact: orbits: unknown or incomplete option '%s'\n",
              argv[optind - 1]);
      return 2;
    }
  }
  if (optind < argc) a->scene = argv[optind++];
  if (optind < argc || a->np < 1 || a->np > 64 || a->mi < 1 || a->mi > 64 ||
      a->phases < 8 || a->csteps < 1 || (a->ckey && (isnan(a->cto) || a->mi != 1))) {
    fprintf(stderr, "vibroimpact: orbits: bad arguments (need 1 <= n, m <= 64, "
            "--phases >= 8, one scene; --continue KEY needs --to B, --steps K >= 1 "
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
  int rc = vi_sweep_load_scene(a->scene, a->sets, a->nsets, sc, err, sizeof err);
  if (rc) {
    fprintf(stderr, "vibroimpact: %s\n", err);
    return rc;
  }
  if (vi_sweep_text_nonlinear(vi_scene_text(*sc))) {
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

/* Seeds: the phase scan (m = 1, one stop), then transients from the
 * scene's initial state and from rest at 8 forcing phases.  0, or the exit
 * status with the message printed. */
static int census(list *L, const vi_scene *sc, int phases)
{
  const vi_model *mdl = L->mdl;
  int N = L->N, st;
  if (L->m == 1 && vi_model_num_stops(mdl) == 1) { /* the scan: one stop */
    double *t = malloc(sizeof(double) * MAXORB * (2 * N + 1));
    int found = 0;
    if (!t) return 1;
    double *x = t + MAXORB, *v = x + (size_t)MAXORB * N;
    st = vi_orbit_p1_scan(mdl, L->n, phases, t, x, v, N, MAXORB, &found);
    if (st) {
      fprintf(stderr, "vibroimpact: orbits: %s\n", vi_strerror(st));
      free(t);
      return st == VI_ERR_UNSUPPORTED ? 2 : 1;
    }
    for (int i = 0; i < found && i < MAXORB; i++)
      add(L, &t[i], x + (size_t)i * N, v + (size_t)i * N, NULL);
    free(t);
  }
  double *x0 = calloc((size_t)N * 2, sizeof(double));
  if (!x0) return 0;
  double T = 2 * M_PI / vi_model_omega_forcing(mdl);
  vi_sim *s0 = NULL;
  /* the scene's initial state, then rest at 8 forcing phases */
  if (!vi_sim_create(mdl, &s0) && !vi_scene_configure_sim(sc, s0, NULL)) {
    double t0, *xs = malloc(sizeof(double) * 2 * N);
    if (xs && !vi_sim_state(s0, &t0, xs, xs + N))
      transient_seed(L, sc, t0, xs, xs + N, 2000);
    free(xs);
  }
  vi_sim_destroy(&s0);
  for (int k = 0; k < 8; k++) transient_seed(L, sc, k * T / 8, x0, x0 + N, 2000);
  free(x0);
  return 0;
}

/* Follow every admissible orbit found in the key (vi_sweep_cont.c). */
static int follow_all(const list *L, const vi_scene *sc, const oargs *a)
{
  char err[2048];
  int rc = 0;
  if (a->json) printf("{\"branches\": [");
  for (int i = 0, k = 0; i < L->count; i++) {
    if (!L->o[i].admissible) continue;
    if (a->json && k++) printf(", ");
    int r = vi_sweep_follow(L->mdl, sc, a->ckey, a->arclength, a->cto, a->csteps,
                            a->np, *L->o[i].t, L->o[i].x, L->o[i].v, a->json, err,
                            sizeof err);
    if (r) {
      fprintf(stderr, "vibroimpact: orbits: --continue: %s\n", err);
      rc = r;
      break;
    }
  }
  if (a->json) printf("]}\n");
  return rc;
}

int vi_cmd_orbits_main(int argc, char **argv)
{
  oargs a = {1, 1, 0, 720, 0, 50, 0, NULL, NULL, NULL, NAN};
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
    else if (!rc && a.json) print_json(L);
    else if (!rc) print_text(L, a.scene ? a.scene : "the default scene (Fig. 2)");
    for (int i = 0; i < L->count; i++) orbit_free(&L->o[i]);
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
