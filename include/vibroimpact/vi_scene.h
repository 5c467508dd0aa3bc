/** @file vi_scene.h
 * scene files (YAML, read with libyaml): part of the companion
 * library vibroimpact_scene, so that the numerical core links no YAML.
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
 *            or {omega, on: [coordinate indices, 1-based], amplitude}
 *            (any model: a builder's coordinates are its own, a
 *            cantilever's its modal ones)
 *            or, for a cantilever, {omega, base: A} (base acceleration);
 *            the whole section may be left out (free motion: give t_end)
 *   stop:    {w: [...] | dof: j (1-based; `mass: j` is a synonym),
 *            direction: +1 | -1 (with dof: w = +-e_j, default +1), xs, r}
 *   stops:   a list of stops as stop: takes one, instead of stop: (several
 *            stops, vi_model_add_stop order: the first is stop 0; on a
 *            cantilever a stop without w or mass is at the tip)
 *   initial: {t0, x, v}  x, v lists of n numbers, or one number for every
 *            coordinate
 *   run:     {t_end | periods, rtol, atol, method: any vi_method_name,
 *             impact_resolution: every impact whose v_n is at least this
 *             fraction of the run's fastest impact is reported
 *             individually, only a chattering tail below it is summed
 *             (default 1e-5, 0: accuracy-driven; in [0, 0.5];
 *             vi_sim_set_impact_resolution)}
 *   output:  {impacts: bool (default true), samples_per_period: int
 *             (per forcing period; without forcing, per 1/100 of the run)
 *             (default 0), ledger: bool (false), modes: bool (false: no
 *             /modal group), compress: bool (true: deflate the trajectory),
 *             shapes: bool (false: no /fe/Psi, the full mode shapes of a
 *             model.matrix_market)}
 *   springs: a list of built-in nonlinear springs (vi_force.h) between
 *            coordinates i and j (1-based; j = 0, the default, is the
 *            ground): {type: cubic, i, j, k3} (force k3 (x_i - x_j)^3) or
 *            {type: bilinear, i, j, k, gap} (a soft stop past the gap)
 *
 * Numbers are plain scalars ("0.1" quoted or `!!str 0.1` is text) of
 * magnitude at most 1e100.  Ranges checked (VI_ERR_LIMIT or the key's own
 * code, naming the key): rtol in [VI_SCENE_RTOL_MIN, VI_SCENE_RTOL_MAX];
 * atol at most 0.01 of the problem's length scale (the clearance, the
 * static response to the loads, the initial state); forcing.omega within
 * 1e-8 .. 1e8 times the highest natural frequency; masses and stiffnesses
 * within a factor 1e12 of each other; modal damping ratios up to 1e6; an
 * initial state within 1e8 times the length scale (velocities: times the
 * highest frequency); a run whose times double precision resolves.
 * Limits (each overridable): VI_SCENE_MAX_BYTES of text, VI_SCENE_MAX_DEPTH
 * levels of nesting, one YAML document, and the model's memory
 * (vi_scene_check_memory).
 */
#ifndef VI_SCENE_H
#define VI_SCENE_H

#include <stdint.h>

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_model.h"
#include "vibroimpact/vi_sim.h"
#include "vibroimpact/vi_sparse.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Default limits and ranges of scene values (see the file comment). */
#define VI_SCENE_MAX_BYTES 16777216 /**< largest scene text (16 MiB) */
#define VI_SCENE_MAX_DEPTH 32                  /**< deepest YAML nesting */
#define VI_SCENE_NUM_MAX 1e100           /**< largest magnitude of a number */
#define VI_SCENE_RATIO_MAX 1e12          /**< spread of masses, stiffnesses */
/* the ranges of a run are the library's own (vi_model_check_run) */
#define VI_SCENE_RTOL_MIN VI_RUN_RTOL_MIN /**< 2 DBL_EPSILON */
#define VI_SCENE_RTOL_MAX VI_RUN_RTOL_MAX /**< loosest relative tolerance */
#define VI_SCENE_ATOL_RATIO VI_RUN_ATOL_RATIO /**< atol / length, at most */
#define VI_SCENE_FREQ_RATIO_MIN VI_RUN_FREQ_RATIO_MIN /**< Omega / omega_hi, at least */
#define VI_SCENE_FREQ_RATIO_MAX VI_RUN_FREQ_RATIO_MAX /**< Omega / omega_hi, at most */
#define VI_SCENE_ZETA_MAX VI_RUN_ZETA_MAX /**< largest modal damping ratio */
#define VI_SCENE_STATE_RATIO VI_RUN_STATE_RATIO /**< initial state / length */

/** Where and why a scene (or a step before a handle exists) failed.  Fixed
 * arrays only, so Fortran can read it. */
typedef struct vi_diag {
  int code;          /**< a vi_status */
  int line;          /**< 1-based line; 0 when not known */
  int column;        /**< 1-based column; 0 when not known */
  char file[256];    /**< the file (or name given to vi_scene_parse) */
  char key[128];     /**< dotted path of the key, e.g. "stop.r" */
  char value[128];   /**< the offending value as written, or "" */
  char message[512]; /**< what is wrong */
} vi_diag;

/** Opaque parsed scene: plain, validated data. */
typedef struct vi_scene vi_scene;

/** Read and validate a scene file.  *out receives the scene (NULL on
 *  failure); diag (may be NULL) says where and why it failed.
 *  @return VI_OK, VI_ERR_IO (cannot read), VI_ERR_PARSE (syntax, unknown or
 *  missing key, wrong type), VI_ERR_DIM (wrong length), VI_ERR_NONFINITE,
 *  VI_ERR_RESTITUTION, VI_ERR_TOLERANCE, VI_ERR_TIME, VI_ERR_NOMEM. */
VI_API int vi_scene_load(const char *path, vi_scene **out, vi_diag *diag);
/** Parse from memory (len < 0: NUL-terminated); `name` stands for the file
 *  name in messages.  Returns as vi_scene_load. */
VI_API int vi_scene_parse(const char *text, int64_t len, const char *name,
                          vi_scene **out, vi_diag *diag);
/** vi_scene_load with limits: at most max_bytes of text (<= 0:
 *  VI_SCENE_MAX_BYTES) and max_depth levels of nesting (<= 0:
 *  VI_SCENE_MAX_DEPTH); VI_ERR_LIMIT when one is exceeded, found before
 *  the whole file is read or parsed. */
VI_API int vi_scene_load_limited(const char *path, int64_t max_bytes,
                                 int max_depth, vi_scene **out, vi_diag *diag);
/** vi_scene_load_limited within a memory budget: the scene's own vectors
 *  of n (56 n bytes) are compared with max_memory (<= 0:
 *  vi_scene_memory_available, no check when that is unknown) before they are
 *  allocated, so that a matrix file whose header claims a huge n is
 *  refused at once; the whole model is compared by vi_scene_check_memory
 *  after the load.  @return as vi_scene_load_limited, VI_ERR_LIMIT (diag
 *  names the key giving n and both figures), VI_ERR_ARG (max_memory NaN). */
VI_API int vi_scene_load_within(const char *path, int64_t max_bytes,
                                int max_depth, double max_memory,
                                vi_scene **out, vi_diag *diag);
/** vi_scene_parse with a nesting limit (<= 0: VI_SCENE_MAX_DEPTH). */
VI_API int vi_scene_parse_limited(const char *text, int64_t len, const char *name,
                                  int max_depth, vi_scene **out,
                                  vi_diag *diag);
/** Destroy and set *scene to NULL; NULL-safe. */
VI_API void vi_scene_destroy(vi_scene **scene);

/** Build and set up the scene's model (a new handle in *out); the model's
 *  own validation errors (VI_ERR_NOT_SYMMETRIC, VI_ERR_NOT_SPD, ...) come
 *  back in diag with the scene's key and line. */
VI_API int vi_scene_create_model(const vi_scene *sc, vi_model **out,
                                 vi_diag *diag);
/** The reduction of a model.matrix_market scene (vi_sparse.h), set up:
 *  its Matrix Market files read (vi_mmio.h), the scene's damping, stops
 *  and forcing given, `modes` lowest modes solved (0: the scene's
 *  model.modes; more than a per-mode model.zeta list covers is refused),
 *  the full Psi kept when keep is 1.  For studies across the number of
 *  modes (vibroimpact truncation) and the frequencies, compliances and
 *  shapes the model itself does not hold.  *out is NULL on failure.
 *  @return VI_OK, VI_ERR_ARG, VI_ERR_UNSUPPORTED (another kind of model),
 *  VI_ERR_DIM, the reader's codes (diag naming the matrix file and line)
 *  and vi_fe_setup's (diag naming the scene's key). */
VI_API int vi_scene_create_fe(const vi_scene *sc, int modes, int keep,
                              vi_fe **out, vi_diag *diag);
/** Bytes the scene's model and a simulation of it need (an estimate
 *  measured on chains, dense storage; for a model.matrix_market, the
 *  files read, the reduction before its sparse factor
 *  (vi_fe_memory_estimate) and the modal model's run); 0 for NULL. */
VI_API double vi_scene_memory_estimate(const vi_scene *sc);
/** Bytes this process may still allocate: MemAvailable of /proc/meminfo,
 *  capped by what the address-space limit (RLIMIT_AS, `ulimit -v`) leaves
 *  above the process's present size; 0 when neither is known.  The
 *  budget the checks below use when none is given. */
VI_API double vi_scene_memory_available(void);
/** Compare vi_scene_memory_estimate with max_bytes (<= 0:
 *  vi_scene_memory_available; no check when that is unknown), before anything is
 *  allocated.  @return VI_OK, VI_ERR_LIMIT (diag names the key giving the
 *  size and both figures), VI_ERR_ARG. */
VI_API int vi_scene_check_memory(const vi_scene *sc, double max_bytes,
                                 vi_diag *diag);
/** Apply the scene's method, tolerances and initial state to a sim of its
 *  model.  @return VI_OK, VI_ERR_DIM (a sim of another n), or the sim
 *  setter's error (e.g. VI_ERR_INITIAL_STATE) with the scene's key and
 *  line in diag. */
VI_API int vi_scene_configure_sim(const vi_scene *sc, vi_sim *sim,
                                  vi_diag *diag);

/** The scene's `name` (the file name if it has none); owned by the scene. */
VI_API const char *vi_scene_name(const vi_scene *sc);
/** The YAML text as read; owned by the scene. */
VI_API const char *vi_scene_text(const vi_scene *sc);
/** Number of coordinates of the scene's model (the kept modes of a
 *  model.matrix_market). */
VI_API int vi_scene_n(const vi_scene *sc);
/** Number of physical coordinates (dofs) the scene's vectors have: the
 *  Matrix Market files' size for a model.matrix_market, else as
 *  vi_scene_n. */
VI_API int vi_scene_dofs(const vi_scene *sc);
/** What the reduction of a model.matrix_market scene did, once
 *  vi_scene_create_model has made its model (each pointer may be NULL):
 *  *modes kept of vi_scene_dofs, *rule how they were chosen (a
 *  vi_fe_modes_rule: VI_FE_MODES_GIVEN by model.modes, VI_FE_MODES_WHOLE
 *  without it), *massless dofs, *rigid modes found (K psi at round-off),
 *  the largest residual of a kept mode and the modes' M-orthonormality
 *  error (vi_fe_summary).  @return VI_OK, VI_ERR_ARG (NULL scene),
 *  VI_ERR_UNSUPPORTED (not a model.matrix_market scene), VI_ERR_STATE (no
 *  model made yet). */
VI_API int vi_scene_fe_summary(const vi_scene *sc, int *modes, int *rule,
                               int *massless, int *rigid,
                               double *max_residual, double *orthogonality);
/** The scene's initial state as written: x0 and v0 [vi_scene_dofs] (either
 *  may be NULL), physical coordinates (a model.matrix_market's dofs; its
 *  model starts from their projection onto the modes).  @return VI_OK,
 *  VI_ERR_ARG (NULL scene). */
VI_API int vi_scene_initial(const vi_scene *sc, double *x0, double *v0);
/** Initial time (initial.t0, default 0). */
VI_API double vi_scene_t0(const vi_scene *sc);
/** End time: run.t_end, or t0 + periods 2 pi / omega (default 100 periods). */
VI_API double vi_scene_t_end(const vi_scene *sc);
/** Relative tolerance (run.rtol, default 1e-8). */
VI_API double vi_scene_rtol(const vi_scene *sc);
/** Absolute tolerance (run.atol, default 1e-10). */
VI_API double vi_scene_atol(const vi_scene *sc);
/** Method, VI_METHOD_* (run.method, default auto). */
VI_API int vi_scene_method(const vi_scene *sc);
/** output.samples_per_period (0: no sampling). */
VI_API int vi_scene_samples_per_period(const vi_scene *sc);
/** What a scene's `output:` asks for, one bit each (vi_scene_outputs). */
typedef enum vi_scene_output {
  VI_SCENE_OUT_IMPACTS = 1,  /**< output.impacts (default on): /impacts */
  VI_SCENE_OUT_LEDGER = 2,   /**< output.ledger: the energy ledger, /ledger */
  VI_SCENE_OUT_MODES = 4,    /**< output.modes: the /modal group */
  VI_SCENE_OUT_COMPRESS = 8, /**< output.compress (default on): deflate */
  VI_SCENE_OUT_SHAPES = 16   /**< output.shapes: the kept modes' full Psi
                                  of a model.matrix_market (/fe/Psi) */
} vi_scene_output;
/** The scene's outputs: an OR of vi_scene_output bits; 0 for NULL.  Test
 *  one with `vi_scene_outputs(sc) & VI_SCENE_OUT_LEDGER`. */
VI_API int vi_scene_outputs(const vi_scene *sc);
/** Override the run from the command line (code overrides scene): values
 *  <= 0 (method < 0) keep the scene's.  @return VI_OK, VI_ERR_ARG (NaN, an
 *  unknown method), VI_ERR_TOLERANCE (rtol outside [VI_SCENE_RTOL_MIN,
 *  VI_SCENE_RTOL_MAX]), VI_ERR_FREQUENCY (periods without a forcing
 *  frequency).  The other ranges are checked by vi_scene_create_model. */
VI_API int vi_scene_set_run(vi_scene *sc, double rtol, double atol,
                            double periods, int method);

/** Print-free formatting of a diag: "file:line:column: key = value: message". */
VI_API void vi_diag_format(const vi_diag *d, char *buf, int len);

/** The embedded default scene, share/scenes/fig2.yaml compiled in: the
 *  paper's Fig. 2 (static storage). */
VI_API const char *vi_scene_default_text(void);

#ifdef __cplusplus
}
#endif
#endif
