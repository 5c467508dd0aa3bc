/* vi_scene.h - scene files (YAML, read with libyaml): part of the companion
 * library vibroimpact_io, so that the numerical core links no YAML.
 *
 * A scene is plain, validated data: the model (explicit M, C, K or a
 * builder), forcing, stop, initial state, run settings and what to output.
 * Errors fill a caller-owned vi_diag naming file, line, column, key and
 * value.  Keys (the scenes in share/scenes are examples):
 *
 *   name: text
 *   model:   one of  M, C, K (lists of rows) | chain: {n, m, k, c}
 *                  | cantilever: {modes, omega1, zeta, xi_stop}
 *            rayleigh: {alpha, beta}            (C = alpha M + beta K)
 *   forcing: {omega, a, b, f0}  vectors of length n, omitted = 0;
 *            or {omega, on: [mass indices, 1-based], amplitude}
 *            or, for a cantilever, {omega, base: A} (base acceleration)
 *   stop:    {w: [...] | mass: j (1-based), xs, r}
 *   initial: {t0, x, v}
 *   run:     {t_end | periods, rtol, atol, method: adams|bdf|exact}
 *   output:  {impacts: bool, samples_per_period: int, ledger: bool,
 *             modes: bool, compress: bool}
 */
#ifndef VI_SCENE_H
#define VI_SCENE_H

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_model.h"
#include "vibroimpact/vi_sim.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Where and why a scene (or a step before a handle exists) failed.  Fixed
 * arrays only, so Fortran can read it. */
typedef struct vi_diag {
  int code;          /* a vi_status */
  int line, column;  /* 1-based; 0 when not known */
  char file[256];
  char key[128];     /* dotted path, e.g. "stop.r" */
  char value[128];
  char message[512];
} vi_diag;

typedef struct vi_scene vi_scene;

VI_API int vi_scene_load(const char *path, vi_scene **out, vi_diag *diag);
/* Parse from memory; `name` stands for the file name in messages. */
VI_API int vi_scene_parse(const char *text, long len, const char *name,
                          vi_scene **out, vi_diag *diag);
VI_API void vi_scene_destroy(vi_scene **scene);

/* A new, set-up model (validation messages carry the scene's key and line). */
VI_API int vi_scene_create_model(const vi_scene *sc, vi_model **out,
                                 vi_diag *diag);
/* Apply method, tolerances and initial state to a sim of that model. */
VI_API int vi_scene_configure_sim(const vi_scene *sc, vi_sim *sim,
                                  vi_diag *diag);

VI_API const char *vi_scene_name(const vi_scene *sc);
VI_API const char *vi_scene_text(const vi_scene *sc); /* the YAML as read */
VI_API int vi_scene_n(const vi_scene *sc);
VI_API double vi_scene_t0(const vi_scene *sc);
VI_API double vi_scene_t_end(const vi_scene *sc);
VI_API double vi_scene_rtol(const vi_scene *sc);
VI_API double vi_scene_atol(const vi_scene *sc);
VI_API int vi_scene_method(const vi_scene *sc);
VI_API int vi_scene_samples_per_period(const vi_scene *sc);
VI_API int vi_scene_wants(const vi_scene *sc, const char *what); /* "impacts",
                                     "ledger", "modes", "compress" */
/* Overrides from the command line (code overrides scene). */
VI_API int vi_scene_set_run(vi_scene *sc, double rtol, double atol,
                            double periods, int method);

/* Print-free formatting of a diag: "file:line:column: key = value: message". */
VI_API void vi_diag_format(const vi_diag *d, char *buf, int len);

/* The embedded default scene: the paper's Fig. 2. */
VI_API const char *vi_scene_default_text(void);

#ifdef __cplusplus
}
#endif
#endif
