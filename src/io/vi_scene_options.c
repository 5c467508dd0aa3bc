/* vi_scene_options.c - a scene's run options: method, tolerances, times,
 * sampling and outputs (typed getters), overrides from the command line,
 * and applying them to a simulation.  No YAML here; their defaults are
 * set by the reader (vi_scene.c), which calls nothing of this file. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "base/vi_period.h"
#include "vi_scene_internal.h"
#include "vibroimpact.h"

int vi_scene_configure_sim(const vi_scene *s, vi_sim *sim, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (!s || !sim)
    return vi_diag_set(d, s ? s->file : "", VI_ERR_ARG, 0, 0, "", "", "%s",
                       "vi_scene_configure_sim: scene and sim are required");
  int n = vi_scene_model_n(s);
  if (vi_sim_n(sim) != n)
    return vi_diag_set(d, s->file, VI_ERR_DIM, s->line_model, 0, "model", "",
                       "the scene has n = %d, the simulation n = %d", n,
                       vi_sim_n(sim));
  /* an FE scene's state is physical: its modal projection is made with
   * the model (vi_scene_create_model) */
  const double *x0 = s->x0, *v0 = s->v0;
  if (s->kind == VI_SCENE_FE) {
    if (!s->fe.at_rest && s->fe.q0[(size_t)2 * n] != 1.0)
      return vi_diag_set(d, s->file, VI_ERR_STATE, s->line_initial, 1,
                         "initial", "", "%s", "an FE scene's initial state "
                         "is projected onto its modes by "
                         "vi_scene_create_model: call it first");
    x0 = s->fe.q0;
    v0 = s->fe.q0 + n;
  }
  int st = vi_sim_set_method(sim, s->method);
  if (st)
    return vi_diag_set(d, s->file, st, s->line_run, 1, "run.method", "", "%s",
                       vi_sim_errmsg(sim));
  if ((st = vi_sim_set_tolerances(sim, s->rtol, s->atol)))
    return vi_diag_set(d, s->file, st, s->line_run, 1, "run", "", "%s",
                       vi_sim_errmsg(sim));
  if ((st = vi_sim_set_impact_resolution(sim, s->impact_resolution)))
    return vi_diag_set(d, s->file, st, s->line_run, 1, "run.impact_resolution",
                       "", "%s", vi_sim_errmsg(sim));
  if ((st = vi_sim_set_initial(sim, s->t0, x0, v0)))
    return vi_diag_set(d, s->file, st, s->line_initial, 1, "initial", "", "%s",
                       vi_sim_errmsg(sim));
  vi_sim_clear_springs(sim);
  for (int k = 0; k < s->nsprings; k++) {
    const vi_scene_spring *q = &s->springs[k];
    if ((st = vi_sim_add_spring(sim, q->type, q->i, q->j, q->k, q->gap))) {
      char key[32];
      snprintf(key, sizeof key, "springs[%d]", k + 1);
      return vi_diag_set(d, s->file, st, q->line, 1, key, "", "%s",
                         vi_sim_errmsg(sim));
    }
  }
  return VI_OK;
}

/* ---- getters and overrides ---------------------------------------------- */
double vi_scene_t0(const vi_scene *s) { return s ? s->t0 : 0.0; }
int vi_scene_initial(const vi_scene *s, double *x0, double *v0)
{
  if (!s) return VI_ERR_ARG;
  if (x0) memcpy(x0, s->x0, sizeof(double) * (size_t)s->n);
  if (v0) memcpy(v0, s->v0, sizeof(double) * (size_t)s->n);
  return VI_OK;
}
double vi_scene_t_end(const vi_scene *s) { return s ? s->t_end : 0.0; }
double vi_scene_rtol(const vi_scene *s) { return s ? s->rtol : 0.0; }
double vi_scene_atol(const vi_scene *s) { return s ? s->atol : 0.0; }
int vi_scene_method(const vi_scene *s) { return s ? s->method : 0; }
int vi_scene_samples_per_period(const vi_scene *s)
{
  return s ? s->samples : 0;
}

int vi_scene_outputs(const vi_scene *s) { return s ? s->outputs : 0; }

int vi_scene_set_run(vi_scene *s, double rtol, double atol, double periods,
                     int method)
{
  if (!s || isnan(rtol) || isnan(atol) || isnan(periods) ||
      !(periods < INFINITY) || (method >= 0 && !vi_method_name(method)))
    return VI_ERR_ARG;
  if (rtol > 0 && !(rtol >= VI_SCENE_RTOL_MIN && rtol <= VI_SCENE_RTOL_MAX))
    return VI_ERR_TOLERANCE;
  if (atol > 0 && !(atol < INFINITY)) return VI_ERR_TOLERANCE;
  if (rtol > 0) s->rtol = rtol;
  if (atol > 0) s->atol = atol;
  if (method >= 0) s->method = method;
  if (periods > 0) {
    if (!(s->omega > 0)) return VI_ERR_FREQUENCY;
    s->periods = periods;
    s->t_end = s->t0 + vi_periods_time(periods, s->omega);
  }
  return VI_OK;
}