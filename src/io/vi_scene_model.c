/* vi_scene_model.c - a scene's model: assembling M, C, K, the forcing and
 * the stops from the scene description (vi_scene_internal.h), the ranges
 * that need the model's frequencies, and the memory a model would take.
 * No YAML here: the description is plain data. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include "vi_scene_internal.h"
#include "vibroimpact/vi_param.h"
#include "vibroimpact.h"
#include "vibroimpact/vi_mmio.h"
#include "vibroimpact/vi_sparse.h"

/* ---- ranges that need the model's frequencies ---------------------------
 * Scales: omega_hi, the fastest of the natural frequencies and the forcing;
 * L, a length (the clearance, or the static response to the loads).  The
 * run must be resolvable in double precision and the state within a few
 * orders of magnitude of the problem's own scales. */
static int check_ranges(const vi_scene *s, const vi_model *m, vi_diag *d)
{
  const char *key = "";
  double v = 0;
  char msg[256];
  /* an FE scene's x0, v0 are of its dofs, the model's of its modes: the
   * modal state is checked by vi_sim_run's first start (the same check) */
  int fe = s->kind == VI_SCENE_FE;
  int st = vi_model_check_run(m, s->t0, s->t_end, fe ? NULL : s->x0,
                              fe ? NULL : s->v0, s->rtol, s->atol, &key, &v,
                              msg, (int)sizeof msg);
  if (!st) return VI_OK;
  /* the library's key, with the scene's line (and periods for t_end) */
  int line = !strncmp(key, "forcing", 7)   ? s->line_forcing
             : !strncmp(key, "initial", 7) ? s->line_initial
             : !strncmp(key, "run", 3)     ? s->line_run
                                           : s->line_model;
  if (!strcmp(key, "run.t_end") && s->periods > 0) {
    key = "run.periods";
    v = s->periods;
  }
  char val[64];
  snprintf(val, sizeof val, "%.6g", v);
  return vi_diag_set(d, s->file, st, line, line ? 1 : 0, key, val, "%s", msg);
}

/* Chains from this size on are stored in band form (kd = 1: O(n) memory
 * and set-up instead of 16 n^2 doubles and an O(n^3) eigen-solve) unless
 * the scene asks for something that needs the modes: the exact method, the
 * ledger, the modes themselves, or springs (their ledger column).  Below
 * it the dense model's exact method is faster (vi_bench_band). */
#define VI_SCENE_BAND_N 1000
static int uses_band(const vi_scene *s)
{
  return s->kind == VI_SCENE_CHAIN && s->n >= VI_SCENE_BAND_N &&
         s->method != VI_METHOD_EXACT && s->nsprings == 0 &&
         !(s->outputs & (VI_SCENE_OUT_LEDGER | VI_SCENE_OUT_MODES));
}

/* Bytes the model and a simulation of it will take (vi_model_memory_
 * estimate, measured on chains against max RSS). */
double vi_scene_memory_estimate(const vi_scene *s)
{
  if (!s) return 0;
  int64_t bytes = 0;
  if (s->kind == VI_SCENE_FE) {
    /* the files read (vi_mmio.h: 40 bytes an entry, 48 and the dof map
     * for coordinate files), the reduction
     * without its sparse factor (vi_fe_memory_estimate; the factor is
     * known only after CHOLMOD's analysis), the scene's 7 vectors of n
     * and the modal model's run */
    int64_t fe = 0, run = 0;
    if (vi_fe_memory_estimate(s->n, s->fe.entries, s->fe.modes,
                              !s->fe.at_rest, &fe) != VI_OK ||
        vi_model_memory_estimate(s->fe.modes, -1, 1 + s->nx, s->method,
                                 (s->outputs & VI_SCENE_OUT_LEDGER) != 0,
                                 &run) != VI_OK)
      return HUGE_VAL;
    return (s->fe.map ? 48.0 : 40.0) * (double)s->fe.entries + (double)fe +
           (double)run + 56.0 * s->n + (s->fe.map ? 8.0 * s->n : 0.0);
  }
  int method = s->method == VI_METHOD_AUTO && uses_band(s) ? VI_METHOD_ADAMS
                                                           : s->method;
  if (vi_model_memory_estimate(s->n, uses_band(s) ? 1 : -1, 1 + s->nx, method,
                               (s->outputs & VI_SCENE_OUT_LEDGER) != 0,
                               &bytes) != VI_OK)
    return HUGE_VAL;
  return (double)bytes;
}

const char *vi_scene_size_key(const vi_scene *s)
{
  return s->kind == VI_SCENE_CHAIN        ? "model.chain.n"
         : s->kind == VI_SCENE_CANTILEVER ? "model.cantilever.modes"
         : s->kind == VI_SCENE_FE         ? s->fe.section
                                          : "model.K";
}

/* MemAvailable of /proc/meminfo in bytes; 0 when unknown. */
static double meminfo_available(void)
{
  FILE *f = fopen("/proc/meminfo", "r");
  if (!f) return 0;
  static const char tag[] = "MemAvailable:";
  char line[256];
  double kb = 0;
  while (fgets(line, sizeof line, f))
    if (!strncmp(line, tag, sizeof tag - 1)) {
      char *end;
      kb = strtod(line + sizeof tag - 1, &end);
      if (end == line + sizeof tag - 1 || !(kb > 0)) kb = 0;
      break;
    }
  fclose(f);
  return kb * 1024.0;
}

/* What RLIMIT_AS leaves above the process's size (/proc/self/statm's
 * first field); HUGE_VAL without a limit, 0 if the size is unknown. */
static double rlimit_left(void)
{
  struct rlimit rl;
  if (getrlimit(RLIMIT_AS, &rl) || rl.rlim_cur == RLIM_INFINITY) return HUGE_VAL;
  FILE *f = fopen("/proc/self/statm", "r");
  char line[128];
  double pages = -1;
  if (f) {
    if (fgets(line, sizeof line, f)) {
      char *end;
      pages = strtod(line, &end);
      if (end == line) pages = -1;
    }
    fclose(f);
  }
  long pg = sysconf(_SC_PAGESIZE);
  if (!(pages >= 0) || pg <= 0) return 0;
  double left = (double)rl.rlim_cur - pages * (double)pg;
  return left > 0 ? left : 1; /* 1: known and spent (0 would mean unknown) */
}

double vi_scene_memory_available(void)
{
  double mem = meminfo_available(), as = rlimit_left();
  if (!(mem > 0)) return as < HUGE_VAL ? as : 0;
  return fmin(mem, as);
}

int vi_scene_check_memory(const vi_scene *s, double max_bytes, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (!s) return VI_ERR_ARG;
  /* NaN is no limit and no request for the machine's: refuse it */
  if (isnan(max_bytes))
    return vi_diag_set(d, s->file, VI_ERR_ARG, 0, 0, "max_bytes", "nan",
                       "the memory limit is not a number");
  int from_machine = !(max_bytes > 0);
  if (from_machine) max_bytes = vi_scene_memory_available();
  if (!(max_bytes > 0)) return VI_OK; /* not known: nothing to compare */
  double need = vi_scene_memory_estimate(s);
  if (need <= max_bytes) return VI_OK;
  const char *key = vi_scene_size_key(s);
  char val[32];
  snprintf(val, sizeof val, "%d", s->n);
  return vi_diag_set(d, s->file, VI_ERR_LIMIT, s->line_model,
                     s->line_model ? 1 : 0, key, val,
                     "the model would need about %.3g MB, more than the "
                     "%.3g MB %s (--max-memory raises the limit)",
                     need / 1048576.0, max_bytes / 1048576.0,
                     from_machine ? "available to this process" : "allowed");
}

/* ---- building the model -------------------------------------------------
 * The description is turned into dense M, C, K [n*n] (column-major, ld n),
 * w, a and the tip's stop direction [n], then handed to a new vi_model,
 * which validates them. */
typedef struct dense {
  double *buf; /* the one allocation holding the others */
  double *M, *C, *K, *w, *a, *tip;
} dense;

/* A chain of n masses (vi_build_chain).  Kept apart so that a band-stored
 * chain can take its place without touching the other kinds. */
static int assemble_chain(const vi_scene *s, dense *x)
{
  /* uniform m, k, c from unit elements, scaled in fill_model (their
   * parameters mass.scale ...: vi_scene_param.c) */
  int n = s->n;
  double *u = malloc(sizeof(double) * 3 * (size_t)n);
  if (!u) return VI_ERR_NOMEM;
  vi_scene_chain_elements(s, u);
  vi_build_chain(n, u, u + n, u + 2 * (size_t)n, x->M, x->C, x->K, n);
  free(u);
  return VI_OK;
}

/* A cantilever's first n modes (vi_build_cantilever).  Its stop is at the
 * tip unless the scene gives w (stops without w or mass take the tip too);
 * a base acceleration enters each mode through the participation factor
 * gamma_j. */
static int assemble_cantilever(const vi_scene *s, dense *x)
{
  int n = s->n;
  double *gamma = malloc(sizeof(double) * (size_t)n);
  if (!gamma) return VI_ERR_NOMEM;
  int st = vi_build_cantilever(n, s->omega1, s->zeta, s->xi_stop, x->M, x->C,
                               x->K, n, x->w, gamma);
  if (st && !(st == VI_ERR_STOP_VECTOR && s->has_w)) { /* else w is given */
    free(gamma);
    return st;
  }
  memcpy(x->tip, x->w, sizeof(double) * (size_t)n);
  if (s->has_w)
    memcpy(x->w, s->w, sizeof(double) * (size_t)n); /* an explicit stop wins */
  if (s->has_base)
    for (int j = 0; j < n; j++)
      x->a[j] = s->a[j] - s->base * gamma[j];
  free(gamma);
  return VI_OK;
}

/* Hand the arrays to the model m and set it up; on failure key[klen] and
 * *line name the part of the scene the model refused. */
static int fill_model(const vi_scene *s, const dense *x, vi_model *m,
                      char *key, size_t klen, int *line)
{
  int n = s->n, st;
  *line = s->line_model;
  if (x->M) { /* dense; a band chain has them already */
    snprintf(key, klen, "%s", "model.M");
    if ((st = vi_model_set_mass(m, x->M, n))) return st;
    snprintf(key, klen, "%s", "model.K");
    if ((st = vi_model_set_stiffness(m, x->K, n))) return st;
    snprintf(key, klen, "%s", "model.C");
    if ((st = vi_model_set_damping(m, x->C, n))) return st;
  }
  snprintf(key, klen, "%s", "forcing");
  if ((st = vi_model_set_forcing(m, s->omega, x->a, s->b, s->f0))) return st;
  *line = s->line_stop;
  snprintf(key, klen, "%s", s->stop_list ? "stops[1]" : "stop");
  if ((st = vi_model_set_stop(m, x->w, s->xs, s->r))) return st;
  for (int k = 0; k < s->nx; k++) {
    *line = s->xint[s->nx + k];
    snprintf(key, klen, "stops[%d]", k + 2);
    const double *w = s->xint[k] ? s->xw + (size_t)k * (size_t)n : x->tip;
    if ((st = vi_model_add_stop(m, w, s->xxs[k], s->xr[k]))) return st;
  }
  *line = s->line_model;
  snprintf(key, klen, "%s", "model");
  if ((st = vi_scene_chain_scale(s, m))) return st; /* a chain's m, k, c */
  /* the model keeps alpha and beta as parameters (vi_param.h): the same
   * C = alpha M + beta K, so that a study can change one of them */
  if (s->has_rayleigh && s->ra >= 0.0 && s->rb >= 0.0 &&
      ((st = vi_model_set_param(m, "damping.alpha", s->ra)) ||
       (st = vi_model_set_param(m, "damping.beta", s->rb))))
    return st;
  return vi_model_setup(m);
}

/* A band-stored chain (uses_band): M, C, K in 'U' band rows, ldab 2. */
static int create_band_chain(const vi_scene *s, vi_model **m)
{
  int n = s->n, st;
  double *B = malloc(sizeof(double) * 9 * (size_t)n);
  if (!B) return VI_ERR_NOMEM;
  double *MB = B, *CB = B + 2 * (size_t)n, *KB = B + 4 * (size_t)n, *u = B + 6 * (size_t)n;
  vi_scene_chain_elements(s, u); /* scaled in fill_model, as assemble_chain */
  st = vi_build_chain_band(n, u, u + n, u + 2 * (size_t)n, MB, CB, KB, 2);
  if (!st && s->has_rayleigh)
    for (size_t i = 0; i < 2 * (size_t)n; i++)
      CB[i] = s->ra * MB[i] + s->rb * KB[i];
  if (!st) st = vi_model_create_band(n, 1, m);
  if (!st && !(st = vi_model_set_mass_band(*m, 1, MB, 2)) &&
      !(st = vi_model_set_stiffness_band(*m, 1, KB, 2)))
    st = vi_model_set_damping_band(*m, 1, CB, 2);
  free(B);
  return st;
}

/* ---- a finite-element model: matrix files reduced to modes ------------
 * Each file read (in its format, coordinate files through the scene's dof
 * map) into lower CSC storage and handed to the reduction (vi_sparse.h),
 * which copies it: one file's arrays at a time. */
static int fe_fail(vi_diag *d, const vi_scene *s, int line, const char *key,
                   int st, const vi_fe *fe)
{
  return vi_diag_set(d, s->file, st, line, line ? 1 : 0, key, "", "%s",
                     fe && vi_fe_errmsg(fe)[0] ? vi_fe_errmsg(fe)
                                               : vi_strerror(st));
}

static int fe_matrices(const vi_scene *s, vi_fe *fe, vi_diag *d)
{
  static const char *const names[3] = {"M", "C", "K"};
  for (int k = 0; k < 3; k++) { /* VI_FE_MASS, _DAMPING, _STIFFNESS */
    if (!s->fe.path[k]) continue;
    char key[64];
    snprintf(key, sizeof key, "%s.%s", s->fe.section, names[k]);
    vi_mm *mm = NULL;
    vi_diag md;
    int st = vi_matrix_load(s->fe.path[k], s->fe.format[k], s->fe.map,
                            VI_CSC_LOWER, 0, &mm, &md);
    if (st) {
      if (!md.line) /* no place in the file: name it at the scene's key */
        return vi_diag_set(d, s->file, st, s->fe.line[k], 1, key,
                           s->fe.path[k], "%s", md.message);
      if (d) {
        *d = md;
        snprintf(d->key, sizeof d->key, "%.60s %.60s", key, md.key);
      }
      return st;
    }
    if (vi_mm_rows(mm) != s->n) { /* changed since the scene was read */
      int rows = vi_mm_rows(mm);
      vi_mm_destroy(&mm);
      return vi_diag_set(d, s->file, VI_ERR_DIM, s->fe.line[k], 1, key,
                         s->fe.path[k], "the file now holds a matrix of %d "
                         "rows, the scene was read with n = %d", rows, s->n);
    }
    const int *p = vi_mm_colptr(mm), *ri = vi_mm_rowind(mm);
    const double *v = vi_mm_values(mm);
    st = k == VI_FE_MASS        ? vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 0, p, ri, v)
         : k == VI_FE_STIFFNESS ? vi_fe_set_stiffness_csc(fe, VI_CSC_LOWER, 0, p, ri, v)
                                : vi_fe_set_damping_csc(fe, VI_CSC_LOWER, 0, p, ri, v);
    vi_mm_destroy(&mm);
    if (st) return fe_fail(d, s, s->fe.line[k], key, st, fe);
  }
  return VI_OK;
}

int vi_scene_create_fe(const vi_scene *s, int modes, int keep, vi_fe **out,
                       vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (out) *out = NULL;
  if (!s || !out || (keep != 0 && keep != 1))
    return vi_diag_set(d, s ? s->file : "", VI_ERR_ARG, 0, 0, "", "", "%s",
                       "vi_scene_create_fe: scene, out and keep 0 or 1 are "
                       "required");
  if (s->kind != VI_SCENE_FE)
    return vi_diag_set(d, s->file, VI_ERR_UNSUPPORTED, s->line_model, 1,
                       "model", "", "%s", "not a finite-element scene "
                       "(model.matrices)");
  if (modes == 0) modes = s->fe.modes;
  if (modes < 1 || modes > s->n)
    return vi_diag_set(d, s->file, VI_ERR_DIM, s->line_model, 1,
                       "model.modes", "", "%d modes asked of a model of %d "
                       "dofs", modes, s->n);
  if (s->fe.nzeta > 1 && modes > s->fe.nzeta)
    return vi_diag_set(d, s->file, VI_ERR_DIM, s->line_model, 1, "model.zeta",
                       "", "%d modes asked, model.zeta gives %d ratios",
                       modes, s->fe.nzeta);
  vi_fe *fe = NULL;
  int st = vi_fe_create(s->n, &fe);
  if (st) return vi_diag_set(d, s->file, st, s->line_model, 1, "model", "",
                             "%s", vi_strerror(st));
  const int line = s->line_model;
  if ((st = fe_matrices(s, fe, d))) goto out;
  /* the modes as accurate as the run asks (run.rtol), and no looser than
   * the library's default */
  if ((st = vi_fe_set_accuracy(fe, s->rtol < 1e-12 ? 1e-12
                                   : s->rtol > 1e-8 ? 1e-8 : s->rtol))) {
    fe_fail(d, s, line, "run.rtol", st, fe);
    goto out;
  }
  if ((st = vi_fe_set_rigid_modes(fe, s->fe.rigid))) {
    fe_fail(d, s, s->fe.line_rigid, "model.rigid_modes", st, fe);
    goto out;
  }
  /* without model.modes the reduction keeps every finite mode itself */
  if ((s->fe.modes_given || modes != s->fe.modes) &&
      (st = vi_fe_set_modes(fe, modes))) {
    fe_fail(d, s, line, "model.modes", st, fe);
    goto out;
  }
  if (s->fe.nzeta) /* one ratio, or the first `modes` of the list */
    st = vi_fe_set_modal_damping(fe, s->fe.nzeta == 1 ? 1 : modes,
                                 s->fe.zeta);
  else if (s->has_rayleigh)
    st = vi_fe_set_rayleigh(fe, s->ra, s->rb);
  if (st) {
    fe_fail(d, s, line, s->fe.nzeta ? "model.zeta" : "model.rayleigh", st,
            fe);
    goto out;
  }
  if ((st = vi_fe_add_stop(fe, s->w, s->xs, s->r))) {
    fe_fail(d, s, s->line_stop, s->stop_list ? "stops[1]" : "stop", st, fe);
    goto out;
  }
  for (int k = 0; k < s->nx; k++)
    if ((st = vi_fe_add_stop(fe, s->xw + (size_t)k * (size_t)s->n,
                             s->xxs[k], s->xr[k]))) {
      char key[32];
      snprintf(key, sizeof key, "stops[%d]", k + 2);
      fe_fail(d, s, s->xint[s->nx + k], key, st, fe);
      goto out;
    }
  if ((st = vi_fe_set_forcing(fe, s->omega, s->a, s->b, s->f0))) {
    fe_fail(d, s, s->line_forcing, "forcing", st, fe);
    goto out;
  }
  if ((st = vi_fe_set_keep_shapes(fe, keep)) || (st = vi_fe_setup(fe)))
    fe_fail(d, s, line, "model", st, fe);
out:
  if (st)
    vi_fe_destroy(&fe);
  else
    *out = fe;
  return st;
}

/* The modal model of an FE scene; its initial state projected (q = Psi^T
 * M x, the full Psi kept for that only when the state is not at rest) into
 * the scene's buffer for vi_scene_configure_sim. */
static int create_fe_model(const vi_scene *s, vi_model **out, vi_diag *d)
{
  vi_fe *fe = NULL;
  int st = vi_scene_create_fe(s, 0, !s->fe.at_rest, &fe, d);
  if (st) return st;
  int k = s->fe.modes;
  if ((st = vi_fe_create_model(fe, out)))
    fe_fail(d, s, s->line_model, "model", st, fe);
  else if (!s->fe.at_rest &&
           ((st = vi_fe_to_modal(fe, s->x0, s->fe.q0)) ||
            (st = vi_fe_to_modal(fe, s->v0, s->fe.q0 + k))))
    fe_fail(d, s, s->line_initial, "initial", st, fe);
  if (!st) s->fe.q0[(size_t)2 * k] = 1.0; /* projected */
  if (!st) {
    struct vi_scene_fe_report *r = s->fe.report;
    r->modes = vi_fe_num_modes(fe);
    r->resid = vi_fe_residual(fe);
    vi_fe_summary(fe, &r->massless, &r->rigid, &r->rule, &r->orth);
    free(r->mresid);
    r->mresid = malloc(sizeof(double) * (size_t)r->modes);
    if (r->mresid)
      memcpy(r->mresid, vi_fe_mode_residuals(fe),
             sizeof(double) * (size_t)r->modes);
    r->done = 1;
  }
  vi_fe_destroy(&fe);
  return st;
}

/* An explicit M with a zero on its diagonal: a massless dof, which only
 * the finite-element set-up condenses. */
static int massless(const vi_scene *s)
{
  for (int j = 0; s->kind == VI_SCENE_EXPLICIT && j < s->n; j++)
    if (s->M[j + (size_t)j * s->n] == 0.0) return 1;
  return 0;
}

int vi_scene_create_model(const vi_scene *s, vi_model **out, vi_diag *d)
{
  if (d) memset(d, 0, sizeof *d);
  if (out) *out = NULL;
  if (!s || !out)
    return vi_diag_set(d, s ? s->file : "", VI_ERR_ARG, 0, 0, "", "", "%s",
                       "vi_scene_create_model: scene and out are required");
  int n = s->n, st = VI_OK, band = uses_band(s);
  if (s->kind == VI_SCENE_FE) {
    vi_model *m = NULL;
    if ((st = create_fe_model(s, &m, d)) || (st = check_ranges(s, m, d))) {
      vi_model_destroy(&m);
      return st;
    }
    *out = m;
    return VI_OK;
  }
  size_t nn = band ? 0 : (size_t)n * (size_t)n;
  dense x;
  x.buf = calloc(3 * nn + 3 * (size_t)n, sizeof(double));
  if (!x.buf)
    return vi_diag_nomem(d, s->file);
  x.M = band ? NULL : x.buf;
  x.C = x.buf + nn;
  x.K = x.C + nn;
  x.w = x.K + nn;
  x.a = x.w + n;
  x.tip = x.a + n;
  memcpy(x.w, s->w, sizeof(double) * (size_t)n);
  memcpy(x.a, s->a, sizeof(double) * (size_t)n);
  if (s->kind == VI_SCENE_EXPLICIT)
    memcpy(x.M, s->M, sizeof(double) * 3 * nn); /* M, C, K: one block */
  else if (s->kind == VI_SCENE_CHAIN) {
    if (!band) st = assemble_chain(s, &x); /* else made with the model below */
  } else
    st = assemble_cantilever(s, &x);
  if (st) {
    free(x.buf);
    if (st == VI_ERR_STOP_VECTOR) {
      char val[64];
      snprintf(val, sizeof val, "%.6g", s->xi_stop);
      return vi_diag_set(d, s->file, st, s->line_model, s->line_model ? 1 : 0,
                         "model.cantilever.xi_stop", val, "%s",
                         "the stop sits at (or within round-off of) the "
                         "clamp, where no mode moves: no impact could ever "
                         "happen (give xi_stop > 0, 1 = the tip)");
    }
    return vi_diag_set(d, s->file, st, s->line_model, s->line_model ? 1 : 0,
                       "model", "", "%s", vi_strerror(st));
  }
  if (s->has_rayleigh && !band)
    for (size_t i = 0; i < nn; i++)
      x.C[i] = s->ra * x.M[i] + s->rb * x.K[i];
  vi_model *m = NULL;
  char key[32] = "model";
  int line = s->line_model;
  st = band ? create_band_chain(s, &m) : vi_model_create(n, &m);
  if (!st) st = fill_model(s, &x, m, key, sizeof key, &line);
  free(x.buf);
  if (st) {
    vi_diag_set(d, s->file, st, line, line ? 1 : 0, key, "", "%s%s",
                m ? vi_model_errmsg(m) : vi_strerror(st),
                st == VI_ERR_NOT_SPD && massless(s) ? " (a scene: M and K as "
                "files under model.matrices)" : "");
    vi_model_destroy(&m);
    return st;
  }
  if ((st = check_ranges(s, m, d))) {
    vi_model_destroy(&m);
    return st;
  }
  *out = m;
  return VI_OK;
}
