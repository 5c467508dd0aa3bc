/* vi_wp - one work-precision point of vibroimpact for bench/workprec.py.
 *
 *   vi_wp SCENE.yaml METHOD RTOL ATOL T_END REPEATS [OUT]
 *   vi_wp SCENE.yaml model       (the model as JSON, for the peers)
 *
 * Runs the scene from its initial state to T_END with METHOD (adams, bdf,
 * exact, erk, auto) REPEATS times in this process and prints the best wall
 * time of the integration loop alone (vi_sim_run), the statistics, and
 * the impacts (time and approach velocity, 17 digits) to OUT or stdout. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "vibroimpact.h"
#include "vibroimpact/vi_scene.h"

typedef struct rec { int n, cap; double *t, *vn; } rec;

static int collect(const vi_event *ev, void *u)
{
  rec *r = u;
  if (ev->kind != VI_EVENT_IMPACT) return 0;
  if (r->n == r->cap) {
    r->cap = r->cap ? 2 * r->cap : 1024;
    r->t = realloc(r->t, sizeof(double) * r->cap);
    r->vn = realloc(r->vn, sizeof(double) * r->cap);
    if (!r->t || !r->vn) return 1;
  }
  r->t[r->n] = ev->t;
  r->vn[r->n++] = ev->vn;
  return 0;
}

static void vec(const char *key, const double *x, int n, const char *end)
{
  printf("\"%s\": [", key);
  for (int i = 0; i < n; i++) printf("%s%.17g", i ? ", " : "", x[i]);
  printf("]%s\n", end);
}

/* M, C, K (row-major nested lists), forcing, stop and initial state. */
static int dump_model(const vi_scene *sc, const vi_model *m)
{
  int n = vi_model_n(m);
  const double *mats[3] = {vi_model_mass(m), vi_model_damping(m),
                           vi_model_stiffness(m)};
  const char *names[3] = {"M", "C", "K"};
  vi_sim *s = NULL;
  vi_diag dg;
  double t0, *x0 = calloc(2 * (size_t)n, sizeof(double)), *v0 = x0 + n;
  if (!x0 || vi_sim_create(m, &s) || vi_scene_configure_sim(sc, s, &dg) ||
      vi_sim_state(s, &t0, x0, v0))
    return 1;
  printf("{\"n\": %d, \"omega\": %.17g, \"xs\": %.17g, \"r\": %.17g, "
         "\"t0\": %.17g,\n", n, vi_model_omega_forcing(m), vi_model_clearance(m),
         vi_model_restitution(m), t0);
  for (int k = 0; k < 3; k++) {
    printf("\"%s\": [", names[k]);
    for (int i = 0; i < n; i++) {
      printf("%s[", i ? ", " : "");
      for (int j = 0; j < n; j++)
        printf("%s%.17g", j ? ", " : "", mats[k][i + (size_t)j * n]);
      printf("]");
    }
    printf("],\n");
  }
  vec("a", vi_model_forcing_cos(m), n, ",");
  vec("b", vi_model_forcing_sin(m), n, ",");
  vec("f0", vi_model_forcing_const(m), n, ",");
  vec("w", vi_model_stop_vector(m), n, ",");
  vec("x0", x0, n, ",");
  vec("v0", v0, n, "}");
  vi_sim_destroy(&s);
  free(x0);
  return 0;
}

static double now(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts); /* CPU: the machine is shared */
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

int main(int argc, char **argv)
{
  vi_scene *sc = NULL;
  vi_model *m = NULL;
  vi_diag dg;
  if (argc == 3 && !strcmp(argv[2], "model")) {
    if (vi_scene_load(argv[1], &sc, &dg) || vi_scene_create_model(sc, &m, &dg) ||
        dump_model(sc, m)) {
      fprintf(stderr, "vi_wp: cannot read the model of %s\n", argv[1]);
      return 1;
    }
    vi_model_destroy(&m);
    vi_scene_destroy(&sc);
    return 0;
  }
  if (argc < 7) {
    fprintf(stderr, "usage: vi_wp SCENE.yaml METHOD RTOL ATOL T_END REPEATS [OUT]\n");
    return 2;
  }
  char msg[1024];
  if (vi_scene_load(argv[1], &sc, &dg) || vi_scene_create_model(sc, &m, &dg)) {
    vi_diag_format(&dg, msg, sizeof msg);
    fprintf(stderr, "vi_wp: %s\n", msg);
    return 1;
  }
  int method = vi_method_from_name(argv[2]);
  double rtol = atof(argv[3]), atol = atof(argv[4]), t_end = atof(argv[5]);
  int repeats = atoi(argv[6]);
  double best = 1e300;
  int64_t st_best[VI_STAT_COUNT] = {0};
  rec keep = {0, 0, NULL, NULL};
  char note[600] = "";
  for (int k = 0; k < repeats; k++) {
    vi_sim *s = NULL;
    rec r = {0, 0, NULL, NULL};
    if (vi_sim_create(m, &s) || vi_scene_configure_sim(sc, s, &dg) ||
        vi_sim_set_method(s, method) || vi_sim_set_tolerances(s, rtol, atol) ||
        vi_sim_set_event_callback(s, collect, &r, NULL) ||
        vi_sim_setup(s)) { /* the integrator's set-up is not the loop */
      fprintf(stderr, "vi_wp: set-up: %s\n", vi_sim_errmsg(s));
      return 1;
    }
    double t0 = now();
    int st = vi_sim_run(s, t_end);
    double wall = now() - t0;
    if (st) {
      fprintf(stderr, "vi_wp: run: %s\n", vi_sim_errmsg(s));
      return 1;
    }
    if (wall < best) {
      best = wall;
      for (int j = 0; j < VI_STAT_COUNT; j++) st_best[j] = vi_sim_stat(s, j);
      snprintf(note, sizeof note, "%s", vi_sim_method_note(s));
    }
    free(keep.t);
    free(keep.vn);
    keep = r;
    vi_sim_destroy(&s);
  }
  FILE *out = argc > 7 ? fopen(argv[7], "w") : stdout;
  if (!out) {
    perror(argv[7]);
    return 1;
  }
  fprintf(out, "# wall %.9g s  method %s  rhs %lld  steps %lld  polishes %lld  "
          "impacts %d\n", best, note, (long long)st_best[VI_STAT_RHS_EVALS],
          (long long)st_best[VI_STAT_STEPS],
          (long long)st_best[VI_STAT_POLISHES], keep.n);
  for (int i = 0; i < keep.n; i++)
    fprintf(out, "%.17g %.17g\n", keep.t[i], keep.vn[i]);
  if (out != stdout) fclose(out);
  free(keep.t);
  free(keep.vn);
  vi_model_destroy(&m);
  vi_scene_destroy(&sc);
  return 0;
}
