/* vi_scene_internal.h - the scene description shared by the scene files of
 * libvibroimpact_scene (and read, never written, by vi_writer.c of
 * libvibroimpact_h5 for an FE scene's files); never installed.
 *
 *   vi_scene.c          YAML (libyaml) -> struct vi_scene, with file:line:col
 *                       diagnostics; the only file that knows YAML
 *   vi_scene_model.c    struct vi_scene -> a vi_model (M, C, K, stops, ...),
 *                       the ranges that need its frequencies, the memory
 *                       estimate
 *   vi_scene_options.c  the typed run options (method, tolerances, times,
 *                       sampling, outputs) and applying them to a vi_sim */
#ifndef VI_SCENE_INTERNAL_H
#define VI_SCENE_INTERNAL_H

#include "vi_io_internal.h"
#include "vibroimpact/vi_scene.h"

enum { VI_SCENE_EXPLICIT, VI_SCENE_CHAIN, VI_SCENE_CANTILEVER, VI_SCENE_FE };

/* A finite-element model from matrix files (model.matrices, or its alias
 * model.matrix_market): the files' paths (resolved against the scene's
 * folder; C may be NULL), their formats (VI_MATRIX_*, vi_mmio.h), the dof
 * map of coordinate files (NULL for the others),
 * the modes kept and their damping.  Its vectors (forcing, stops, initial
 * state) are physical: n dofs; the model made has `modes` coordinates. */
typedef struct vi_scene_fe {
  char *path[3];       /* M, K, C (VI_FE_MASS, VI_FE_STIFFNESS, ...) */
  int line[3];         /* their lines in the scene */
  int format[3];       /* VI_MATRIX_MARKET, ..._HARWELL_BOEING, ... */
  struct vi_dofmap *map;
  const char *section; /* "model.matrices" or "model.matrix_market" */
  int64_t entries;     /* the most values any of the files holds */
  int modes, nzeta;    /* kept modes; 0, 1 or `modes` damping ratios */
  int modes_given;     /* model.modes was written; else every finite mode */
  int rigid, line_rigid; /* model.rigid_modes (-1: decided from K), line */
  int massless;        /* dofs without mass (counted when modes is not
                        * given: the whole model's size needs it) */
  double *zeta;
  /* the initial state in modal coordinates, q0 [2 modes + 1]: positions,
   * velocities, then 1 once vi_scene_create_model has projected the
   * physical state (it needs the modes) for vi_scene_configure_sim.  A
   * buffer of the scene filled by create_model (the scene itself is
   * const there); at rest it needs no projection: all zeros. */
  double *q0;
  int at_rest;
  /* what the reduction did, for the report (vi_scene_fe_summary): filled
   * by create_model through this pointer, as q0 */
  struct vi_scene_fe_report {
    int done, modes, rule, massless, rigid;
    double resid, orth;
    double *mresid;   /* [modes]: each kept mode's residual */
  } *report;
} vi_scene_fe;

/* A built-in nonlinear spring (vi_force.h), applied to the sim. */
typedef struct vi_scene_spring {
  int type, i, j, line; /* VI_SPRING_*, 1-based coordinates, YAML line */
  double k, gap;
} vi_scene_spring;

/* Plain, validated data: what the YAML said, with its defaults filled in.
 * The line_* fields are the 1-based lines of the sections (0: absent) for
 * the messages of later steps. */
struct vi_scene {
  char *name, *text, *file;
  /* ---- the model ---- */
  int n, kind;                  /* kind: VI_SCENE_EXPLICIT, ... */
  double *M, *C, *K;            /* explicit [n*n] (one block), or NULL */
  double *cm, *ck, *cc;         /* chain parameters [n] (one block) */
  double omega1, zeta, xi_stop; /* cantilever */
  int has_rayleigh;
  double ra, rb;                /* C = ra M + rb K */
  vi_scene_fe fe;               /* kind VI_SCENE_FE */
  /* forcing, stops and initial state: one block of 6 n from a */
  double omega, base;           /* base: a cantilever's base acceleration */
  int has_base;
  double *a, *b, *f0, *w, *x0, *v0;
  int has_w;                    /* the first stop gave w or mass */
  double xs, r;                 /* the first stop */
  /* stops after the first (a `stops:` list): xw [n x nx] then xxs, xr
   * [nx] in one block; xint [2 nx]: has_w per stop, then its line */
  int nx, stop_list;
  double *xw, *xxs, *xr;
  int *xint;
  vi_scene_spring *springs;
  int nsprings;
  /* ---- run options (vi_scene_options.c) ---- */
  double t0, t_end, periods, rtol, atol;
  double impact_resolution; /* run.impact_resolution (vi_sim_set_impact_resolution) */
  int method, samples, outputs; /* outputs: vi_scene_output flags */
  int line_model, line_stop, line_initial, line_run, line_forcing;
};


/* The key that gives the scene's size n, for messages (vi_scene_model.c):
 * model.chain.n, model.cantilever.modes, the matrix files' section or
 * model.K. */
const char *vi_scene_size_key(const vi_scene *s);

/* vi_scene_parse_limited with a memory budget (vi_scene.c): the scene's
 * own vectors of n are checked against *max_memory (<= 0: what the
 * machine has) before they are allocated; NULL: not checked. */
int vi_scene_parse_within(const char *text, int64_t len, const char *name,
                          int max_depth, const double *max_memory,
                          vi_scene **out, vi_diag *d);

/* Coordinates of the scene's model: n, or the kept modes of an FE model. */
int vi_scene_model_n(const vi_scene *s);

/* A chain's m, k, c as model parameters (vi_scene_param.c): the mask of
 * those a study may change (bit 0 m, 1 k, 2 c: uniform, and not replaced
 * by Rayleigh damping), the per-element values to build M, K, C from, u
 * [3 n] (1 for each such parameter), and their values set on the model as
 * mass.scale, stiffness.scale, damping.scale (before setup). */
int vi_scene_chain_scalable(const vi_scene *s);
void vi_scene_chain_elements(const vi_scene *s, double *u);
int vi_scene_chain_scale(const vi_scene *s, vi_model *m);

#endif
