/* vi_cmd_truncation.c - `vibroimpact truncation SCENE --modes A..B`: the
 * paper's question (how many modes does an impacting structure need, and
 * what restitution must a reduced model then use) asked of a scene, for
 * each number k of kept modes:
 *
 *   - the frequencies (omega_k, the mode added);
 *   - the fraction of the stop's compliance the k modes carry: dynamic,
 *     sum_{j<=k} psi_j^2 / w^T M^-1 w (the Delassus number of Newton's law,
 *     WB 2, 10), and static, sum_{j<=k} psi_j^2 / omega_j^2 / w^T K^-1 w;
 *   - the impact response of the k-mode model with the scene's r: P(1,1)
 *     v_N and impact phase where the orbit search finds one, else its class;
 *   - the r_S a k-mode model needs to carry the reference orbit's energy
 *     balance (WB 12-13 on the first k modes, MODEL.md section 5) and the
 *     v_N the k-mode model then has;
 *   - the first impacts from the scene's initial state, against the
 *     reference's;
 *   - the same k modes plus one static (residual-flexibility) vector at the
 *     stop, K^-1 w less its part in the kept modes, M-orthonormalised: its
 *     compliance fraction and impact response, to measure whether such a
 *     correction belongs in reduced models.
 *
 * The reference is a model with more modes than any studied: for a
 * model.matrix_market scene its max(2B, B + 20) lowest modes (at most the
 * dofs; vi_scene_create_fe) or --reference N of them (N >= B), for the other kinds the scene's model with all
 * its modes (B at most n).  The static vector of a k-mode model is built
 * from the reference's modes beyond k, so the reference must reach well
 * past B for it to be the residual flexibility.  The
 * compliances w^T M^-1 w and w^T K^-1 w are the full model's (the sparse
 * factorisations of vi_fe_stop_compliance; for a dense model w^T M^-1 w
 * and the sum over all its modes).  Everything is in the reference's modal
 * coordinates, where M = I: reduced models keep its first k coordinates
 * (vi_model_create_truncated builds them, static vector included). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vi_app.h"
#include "vi_diagram.h" /* --set */
#include "vibroimpact/vi_sparse.h"
#include "vibroimpact/vi_truncation_io.h"

/* The outcome of the orbit search on one model. */
typedef struct response {
  int pn, pm;      /* class: (1, 1) P(1,1); (0, m) not periodic */
  double vN, phase; /* P(1,1): approach velocity, impact time mod T / T */
  int ok;          /* the search ran */
} response;

/* A progress line per forcing period of a long orbit search (on a
 * terminal: the reference's, see note_reference). */
static int on_period(const vi_progress *p, void *user)
{
  (void)user;
  fprintf(stderr, "\r  reference orbit: t = %-12.6g %lld impacts ", p->t,
          (long long)p->impacts);
  return 0;
}

static void find_orbit(const vi_model *m, response *r, vi_orbit **keep,
                       int progress)
{
  vi_orbit *o = NULL;
  memset(r, 0, sizeof *r);
  r->vN = r->phase = NAN;
  if (!vi_orbit_create(m, &o) && !vi_orbit_set_initial(o, NULL, NULL) &&
      (!progress || !vi_orbit_set_monitor(o, on_period, NULL, NULL)) &&
      !vi_orbit_find(o)) {
    r->ok = 1;
    vi_orbit_classify(o, &r->pn, &r->pm);
    double T = 0, ph = 0;
    if (r->pn == 1 && r->pm == 1 &&
        !vi_orbit_balance(o, &T, &ph, &r->vN, NULL, NULL, NULL, NULL, NULL))
      r->phase = ph / T;
  }
  if (keep && r->ok)
    *keep = o;
  else
    vi_orbit_destroy(&o);
}

/* The first impacts from the scene's initial state (projected onto each
 * model's coordinates; the exact method where it applies): before the first contact the structure answers the forcing,
 * quasi-statically in its high modes (the static flexibility's domain);
 * after it, Newton's law acts through the dynamic compliance.  Times and
 * approach velocities of up to NHIT impacts by t_end. */
enum { NHIT = 3 };
typedef struct first {
  int n;
  double t[NHIT], vn[NHIT];
  double release; /* the first end of sticking (r = 0, chatter), or NaN */
} first;

static int on_first(const vi_event *ev, void *user)
{
  first *f = user;
  if (ev->kind == VI_EVENT_RELEASE && isnan(f->release)) f->release = ev->t;
  if (ev->kind != VI_EVENT_IMPACT) return 0;
  f->t[f->n] = ev->t;
  f->vn[f->n++] = ev->vn;
  return f->n >= NHIT; /* nonzero: stop */
}

static void first_impacts(const vi_model *m, double t0, double t_end,
                          const double *q0, first *f)
{
  vi_sim *s = NULL;
  int n = vi_model_n(m);
  memset(f, 0, sizeof *f);
  f->release = NAN;
  if (!vi_sim_create(m, &s) &&
      !vi_sim_set_initial(s, t0, q0, q0 ? q0 + n : NULL) &&
      !vi_sim_set_tolerances(s, 1e-11, 1e-14) &&
      !vi_sim_set_event_callback(s, on_first, f, NULL) &&
      !vi_sim_set_event_states(s, 0)) { /* on_first reads t and vn */
    int st = vi_sim_run(s, t_end);
    if (st != VI_OK && st != VI_STOPPED) f->n = -1;
  }
  vi_sim_destroy(&s);
}

static void json_num(const char *key, double v, int comma)
{
  if (isfinite(v))
    printf("\"%s\": %.17g%s", key, v, comma ? ", " : "");
  else
    printf("\"%s\": null%s", key, comma ? ", " : "");
}

static void json_first(const char *key, const first *f, const first *ref)
{
  printf("\"%s\": {\"t\": [", key);
  for (int j = 0; j < f->n; j++) printf("%s%.17g", j ? ", " : "", f->t[j]);
  printf("], \"vn\": [");
  for (int j = 0; j < f->n; j++) printf("%s%.17g", j ? ", " : "", f->vn[j]);
  printf("]");
  if (ref) { /* errors against the reference's, impact by impact */
    printf(", \"dt\": [");
    for (int j = 0; j < f->n && j < ref->n; j++)
      printf("%s%.3g", j ? ", " : "", f->t[j] - ref->t[j]);
    printf("], \"dvn_rel\": [");
    for (int j = 0; j < f->n && j < ref->n; j++)
      printf("%s%.3g", j ? ", " : "", (f->vn[j] - ref->vn[j]) / ref->vn[j]);
    printf("]");
  }
  printf(", ");
  json_num("release", f->release, 0);
  printf("}");
}

static void json_response(const response *r)
{
  if (!r->ok) {
    printf("{\"class\": null}");
    return;
  }
  if (r->pn == 1 && r->pm == 1)
    printf("{\"class\": \"P(1,1)\", \"vN\": %.17g, \"phase\": %.17g}", r->vN,
           r->phase);
  else if (r->pn)
    printf("{\"class\": \"P(%d,%d)\"}", r->pn, r->pm);
  else
    printf("{\"class\": \"not periodic\", \"impacts_per_period\": %d}", r->pm);
}

/* The study's table for -o (vi_truncation_io.h: its column layout). */
static void tab_response(double *t, int ld, int c, const response *r)
{
  t[(size_t)c * ld] = r->ok ? r->pn : -1;
  t[(size_t)(c + 1) * ld] = r->ok ? r->pm : NAN;
  t[(size_t)(c + 2) * ld] = r->vN;
  t[(size_t)(c + 3) * ld] = r->phase;
}

static void tab_first(double *t, int ld, int c, const first *f,
                      const first *ref)
{
  t[(size_t)c * ld] = f->n;
  for (int j = 0; j < NHIT; j++) {
    int have = j < f->n, cmp = have && ref && j < ref->n;
    t[(size_t)(c + 1 + j) * ld] = have ? f->t[j] : NAN;
    t[(size_t)(c + 4 + j) * ld] = have ? f->vn[j] : NAN;
    t[(size_t)(c + 7 + j) * ld] = cmp ? f->t[j] - ref->t[j] : NAN;
    t[(size_t)(c + 10 + j) * ld] =
        cmp ? (f->vn[j] - ref->vn[j]) / ref->vn[j] : NAN;
  }
  t[(size_t)(c + 13) * ld] = f->release;
}

typedef int (*trunc_h5_fn)(const char *, const char *, const char *,
                           const double *, const double *, int,
                           const double *, int, vi_diag *);

/* -o: the study through vi_truncation_write_h5 (libvibroimpact_h5); 0 or 1
 * after a message. */
static int write_h5(const app_opts *o, const vi_scene *sc, const double *info,
                    const double *ref, int nrows, const double *rows, int ld)
{
  union { void *p; trunc_h5_fn f; } u;
  u.p = vi_app_io_symbol("vi_truncation_write_h5");
  if (!u.p) return 1;
  vi_diag d;
  int st = u.f(o->out_target, vi_scene_name(sc), vi_scene_text(sc), info, ref,
               nrows, rows, ld, &d);
  if (st) fprintf(stderr, "vibroimpact: %s\n",
                  st == VI_ERR_IO ? d.message : vi_strerror(st));
  return st ? 1 : 0;
}

static const char *text_response(const response *r, char *buf, size_t len)
{
  if (!r->ok)
    snprintf(buf, len, "%s", "no orbit");
  else if (r->pn == 1 && r->pm == 1)
    snprintf(buf, len, "%.6g @%.4f", r->vN, r->phase);
  else if (r->pn)
    snprintf(buf, len, "P(%d,%d)", r->pn, r->pm);
  else
    snprintf(buf, len, "aperiodic");
  return buf;
}


/* The study's state: the scene, the reference model R (and what it was
 * made from), the compliances, the rows for -o. */
typedef struct study {
  const app_opts *o;
  vi_scene *sc;
  vi_model *R, *dense;
  vi_fe *fe;
  vi_orbit *oref;
  int lo, hi, nR, dofs, ldt, nrows, forced, p11;
  double Gd, Gs, r, t0, tend;      /* the full model's w^T M^-1 w, w^T K^-1 w */
  double *x0, *q0R, *qk, *tab, *tref;
  response ref;
  first fref;
} study;

/* One row: the k-mode model with r and with r_S, the static variant. */
typedef struct row {
  int k;
  double omk, fd, fs, fc, rS;
  response rk, rs, rc2;
  first fk, fc1;
} row;

/* The scene (with --set and the run overrides); 0 or 2 after a message. */
static int study_scene(study *S)
{
  const app_opts *o = S->o;
  vi_diag d;
  memset(&d, 0, sizeof d);
  int st = vi_sets_active() ? vi_sets_load(o->scene, o->max_depth, &S->sc, &d) /* --set */
           : o->scene ? vi_scene_load_limited(o->scene, o->max_scene_bytes,
                                              o->max_depth, &S->sc, &d)
                      : vi_scene_parse(vi_scene_default_text(), -1,
                                       "<default scene: fig2>", &S->sc, &d);
  if (!st) st = vi_scene_set_run(S->sc, o->rtol, o->atol, 0, o->method);
  if (!st) st = vi_scene_check_memory(S->sc, o->max_memory, &d);
  if (st) {
    vi_app_print_diag(&d, st);
    return 2;
  }
  return 0;
}

/* An FE scene's reference: its nref lowest modes; 0 or the exit status. */
static int reference_fe(study *S)
{
  vi_diag d;
  memset(&d, 0, sizeof d);
  int hi = S->hi, dofs = vi_scene_dofs(S->sc), st;
  int nref = 2 * hi > hi + 20 ? 2 * hi : hi + 20;
  nref = nref < dofs ? nref : dofs;
  if (S->o->modes_ref > 0) nref = S->o->modes_ref;
  if (nref < hi || nref > dofs) {
    fprintf(stderr, "vibroimpact: truncation: --reference %d: need B = %d "
            "<= N <= %d (the dofs)\n", nref, hi, dofs);
    return 2;
  }
  if ((st = vi_scene_create_fe(S->sc, nref, 1, &S->fe, &d))) {
    vi_app_print_diag(&d, st);
    return st == VI_ERR_NOMEM ? 1 : 2;
  }
  if (vi_fe_create_model(S->fe, &S->R) != VI_OK) {
    fprintf(stderr, "vibroimpact: truncation: %s\n", vi_fe_errmsg(S->fe));
    return 1;
  }
  vi_fe_stop_compliance(S->fe, 0, &S->Gd, &S->Gs);
  return 0;
}

/* Any other scene's reference: its model in its own modal coordinates,
 * all modes; 0 or the exit status. */
static int reference_dense(study *S)
{
  vi_diag d;
  memset(&d, 0, sizeof d);
  int st;
  if ((st = vi_scene_create_model(S->sc, &S->dense, &d))) {
    vi_app_print_diag(&d, st);
    return st == VI_ERR_NOMEM ? 1 : 2;
  }
  if (!vi_model_omega(S->dense)) {
    fprintf(stderr, "vibroimpact: truncation: the scene's model has no "
            "modes (band storage): ask for them (output.modes: true)\n");
    return 2;
  }
  int n = vi_model_n(S->dense), all[4096];
  if (n > 4096) {
    fprintf(stderr, "vibroimpact: truncation: more than 4096 coordinates "
            "in a dense scene: write it as Matrix Market files\n");
    return 2;
  }
  for (int j = 0; j < n; j++) all[j] = j;
  if ((st = vi_model_create_reduced(S->dense, all, n,
                                    vi_model_restitution(S->dense), &S->R))) {
    fprintf(stderr, "vibroimpact: truncation: %s\n", vi_strerror(st));
    return 1;
  }
  /* w^T K^-1 w: the sum over all the modes (vi_model_modal_compliance) */
  double *cs = malloc(sizeof(double) * (size_t)n);
  S->Gd = vi_model_stop_compliance(S->dense);
  if (!cs || (st = vi_model_modal_compliance(S->R, 0, n, NULL, cs))) {
    fprintf(stderr, "vibroimpact: truncation: %s\n",
            vi_strerror(cs ? st : VI_ERR_NOMEM));
    free(cs);
    return 1;
  }
  S->Gs = cs[n - 1];
  free(cs);
  return 0;
}

/* The modes asked for, checked, and the reference; 0 or the exit status. */
static int study_reference(study *S)
{
  const app_opts *o = S->o;
  S->lo = o->modes_lo > 0 ? o->modes_lo : 1;
  S->hi = o->modes_hi;
  /* an FE scene refuses -1 modes, any other kind the FE reduction */
  int is_fe = vi_scene_create_fe(S->sc, -1, 0, &S->fe, NULL) != VI_ERR_UNSUPPORTED;
  if (S->hi <= 0) S->hi = is_fe ? vi_scene_n(S->sc) : vi_scene_dofs(S->sc);
  if (S->lo > S->hi || S->hi > vi_scene_dofs(S->sc)) {
    fprintf(stderr, "vibroimpact: truncation: --modes %d..%d: need 1 <= A <= "
            "B <= %d (the model's coordinates)\n", S->lo, S->hi, vi_scene_dofs(S->sc));
    return 2;
  }
  S->Gd = S->Gs = NAN;
  return is_fe ? reference_fe(S) : reference_dense(S);
}

/* The buffers, and the scene's initial state in the reference's
 * coordinates: q = Psi^T M x (the FE reduction's kept shapes, or the dense
 * model's modes); 0 or 1 after a message. */
static int study_initial(study *S)
{
  int dofs = S->dofs = vi_scene_dofs(S->sc), nR = S->nR, hi = S->hi;
  S->ldt = hi - S->lo + 1 > 0 ? hi - S->lo + 1 : 1; /* -o: rows */
  S->x0 = calloc(2 * (size_t)dofs + 2 * (size_t)nR + 4 * (size_t)hi + 4 +
                     (S->o->out ? (size_t)(S->ldt + 1) * VI_TRUNCATION_COLUMNS : 0),
                 sizeof(double));
  if (!S->x0) return 1;
  double *x0 = S->x0;
  S->tab = x0 + 2 * (size_t)dofs + 2 * (size_t)nR + 4 * (size_t)hi + 4;
  S->tref = S->tab + (size_t)S->ldt * VI_TRUNCATION_COLUMNS;
  S->q0R = x0 + 2 * (size_t)dofs;
  S->qk = S->q0R + 2 * (size_t)nR;
  vi_scene_initial(S->sc, x0, x0 + dofs);
  if ((S->fe && (vi_fe_to_modal(S->fe, x0, S->q0R) ||
                 vi_fe_to_modal(S->fe, x0 + dofs, S->q0R + nR))) ||
      (S->dense && (vi_model_to_modal(S->dense, x0, S->q0R) ||
                    vi_model_to_modal(S->dense, x0 + dofs, S->q0R + nR)))) {
    fprintf(stderr, "vibroimpact: truncation: cannot project the initial "
            "state onto the modes\n");
    return 1;
  }
  if (nR > 4096) {
    fprintf(stderr, "vibroimpact: truncation: a reference of %d modes: at "
            "most 4096\n", nR);
    return 1;
  }
  return 0;
}

/* What the reference costs, said before its runs (issue 29: --reference
 * 198 of the 200-dof beam ran for more than 600 s without a word).  The
 * exact method steps pi/2 radians of the fastest mode, 4 omega_max / Omega
 * steps per forcing period of O(n) work each: a beam's omega_k grows as
 * k^2, so the reference costs the cube of its size (1 s for 20 modes, 5 s
 * for 40, 50 s for 80). */
static void note_reference(const study *S)
{
  const double *om = vi_model_omega(S->R);
  double Om = vi_model_omega_forcing(S->R);
  if (S->o->quiet || !om || !(Om > 0)) return;
  double steps = 4.0 * om[S->nR - 1] / Om;
  if (steps * S->nR < 1e6) return; /* seconds at most: nothing to say */
  fprintf(stderr, "vibroimpact: truncation: the reference's %d modes reach "
          "omega = %.4g: about %.2g steps per forcing period, each over all "
          "modes; its orbit search may take minutes (a smaller --reference "
          "is faster; Ctrl-C stops)\n", S->nR, om[S->nR - 1], steps);
}

/* The reference orbit (the balance every reduced model is measured by)
 * and the reference's first impacts. */
static void study_reference_runs(study *S)
{
  note_reference(S);
  memset(&S->ref, 0, sizeof S->ref);
  S->ref.vN = S->ref.phase = NAN;
  S->r = vi_model_restitution(S->R);
  S->forced = vi_model_omega_forcing(S->R) > 0;
  if (S->forced) {
    vi_app_set_polling(0);
    find_orbit(S->R, &S->ref, &S->oref, S->o->progress);
    if (S->o->progress) fputc('\n', stderr);
  }
  S->p11 = S->oref && S->ref.pn == 1 && S->ref.pm == 1;
  S->t0 = vi_scene_t0(S->sc);
  S->tend = vi_scene_t_end(S->sc);
  first_impacts(S->R, S->t0, S->tend, S->q0R, &S->fref);
}

static void print_header(const study *S)
{
  const vi_scene *sc = S->sc;
  if (S->o->json) {
    printf("{\"scene\": \"%s\", \"dofs\": %d, \"modes\": [%d, %d], "
           "\"restitution\": %.17g, ", vi_scene_name(sc), vi_scene_dofs(sc),
           S->lo, S->hi, S->r);
    json_num("compliance_dynamic", S->Gd, 1);
    json_num("compliance_static", S->Gs, 1);
    printf("\"reference\": ");
    json_response(&S->ref);
    printf(", ");
    json_first("first_impacts", &S->fref, NULL);
    printf(", \"rows\": [");
    return;
  }
  printf("truncation study, scene %s: %d dofs, reference %d modes, r = %g\n",
         vi_scene_name(sc), vi_scene_dofs(sc), S->nR, S->r);
  printf("  stop compliance w^T M^-1 w = %.6g, w^T K^-1 w = %.6g; "
         "reference orbit: ", S->Gd, S->Gs);
  char b[64];
  printf("%s\n", S->forced ? text_response(&S->ref, b, sizeof b)
                           : "none (no harmonic forcing)");
  if (S->fref.n > 0)
    printf("  reference's first impact from the initial state: t = %.10g, "
           "v_n = %.8g\n", S->fref.t[0], S->fref.vn[0]);
  printf("  %3s %12s %9s %9s %22s %10s %22s | %9s %22s | %9s %9s\n", "k",
         "omega_k", "dyn.frac", "stat.frac", "v_N @phase (r)", "r_S",
         "v_N @phase (r_S)", "+static", "v_N @phase (+static)", "dt1",
         "dt1+stat");
}

/* Row k's models run: k modes with r and with r_S, and k modes plus the
 * static vector (k < nR). */
static void compute_row(study *S, row *w, const int *modes_idx)
{
  int k = w->k;
  double carried = NAN;
  vi_model *mk = NULL, *ms = NULL, *mc = NULL;
  w->rk.vN = w->rk.phase = w->rs.vN = w->rs.phase = w->rc2.vN = w->rc2.phase = NAN;
  w->rS = NAN;
  if (!vi_model_create_truncated(S->R, k, 0, S->r, S->q0R, S->qk, NULL, &mk))
    first_impacts(mk, S->t0, S->tend, S->qk, &w->fk);
  if (S->forced) {
    if (mk) find_orbit(mk, &w->rk, NULL, 0);
    if (S->p11 && !vi_orbit_reduced_restitution(S->oref, modes_idx, k, &w->rS) &&
        !vi_model_create_truncated(S->R, k, 0, w->rS, NULL, NULL, NULL, &ms))
      find_orbit(ms, &w->rs, NULL, 0);
  }
  if (k < S->nR && !vi_model_create_truncated(S->R, k, 1, S->r, S->q0R, S->qk, &carried, &mc)) {
    first_impacts(mc, S->t0, S->tend, S->qk, &w->fc1);
    if (S->forced) find_orbit(mc, &w->rc2, NULL, 0);
  }
  w->fc = carried / S->Gd;
  vi_model_destroy(&mk);
  vi_model_destroy(&ms);
  vi_model_destroy(&mc);
}

/* Row k into the -o table (vi_truncation_io.h: its column layout). */
static void table_row(study *S, const row *w)
{
  int ldt = S->ldt, k = w->k;
  double *t = S->tab + S->nrows++;
  t[0] = k;
  t[ldt] = w->omk;
  t[2 * (size_t)ldt] = w->fd;
  t[3 * (size_t)ldt] = w->fs;
  tab_response(t, ldt, 4, &w->rk);
  tab_first(t, ldt, 8, &w->fk, &S->fref);
  t[22 * (size_t)ldt] = w->rS;
  tab_response(t, ldt, 23, &w->rs);
  t[27 * (size_t)ldt] = k < S->nR;
  t[28 * (size_t)ldt] = k < S->nR ? w->fc : NAN;
  tab_response(t, ldt, 29, &w->rc2);
  tab_first(t, ldt, 33, &w->fc1, &S->fref);
  if (k >= S->nR) /* no mode beyond k: no variant */
    for (int c = 29; c < VI_TRUNCATION_COLUMNS; c++) t[(size_t)c * ldt] = NAN;
}

static void json_row(const study *S, const row *w)
{
  printf("%s{\"k\": %d, ", w->k > S->lo ? ", " : "", w->k);
  json_num("omega", w->omk, 1);
  json_num("dynamic_fraction", w->fd, 1);
  json_num("static_fraction", w->fs, 1);
  printf("\"response\": ");
  json_response(&w->rk);
  printf(", ");
  json_first("first_impacts", &w->fk, &S->fref);
  printf(", ");
  json_num("r_S", w->rS, 1);
  printf("\"response_r_S\": ");
  json_response(&w->rs);
  if (w->k < S->nR) {
    printf(", \"static_corrected\": {");
    json_num("dynamic_fraction", w->fc, 1);
    printf("\"response\": ");
    json_response(&w->rc2);
    printf(", ");
    json_first("first_impacts", &w->fc1, &S->fref);
    printf("}}");
  } else /* no mode beyond k: no residual */
    printf(", \"static_corrected\": null}");
}

static void text_row(const study *S, const row *w)
{
  int k = w->k, nR = S->nR;
  char b1[64], b2[64], b3[64], f3[32] = "-", d1[32] = "-", d2[32] = "-";
  if (k < nR) snprintf(f3, sizeof f3, "%.6f", w->fc);
  if (w->fk.n > 0 && S->fref.n > 0)
    snprintf(d1, sizeof d1, "%.2e", w->fk.t[0] - S->fref.t[0]);
  if (w->fc1.n > 0 && S->fref.n > 0)
    snprintf(d2, sizeof d2, "%.2e", w->fc1.t[0] - S->fref.t[0]);
  printf("  %3d %12.6g %9.6f %9.6f %22s %10.6f %22s | %9s %22s | %9s "
         "%9s\n", k, w->omk, w->fd, w->fs,
         S->forced ? text_response(&w->rk, b1, sizeof b1) : "-", w->rS,
         S->forced && S->p11 ? text_response(&w->rs, b2, sizeof b2) : "-", f3,
         S->forced && k < nR ? text_response(&w->rc2, b3, sizeof b3) : "-", d1,
         d2);
}

/* The rows k = lo..hi (the compliance fractions summed from k = 1),
 * until a signal; 1 when the compliances cannot be had. */
static int study_rows(study *S)
{
  int modes_idx[4096];
  const double *K = vi_model_stiffness(S->R);
  int nR = S->nR;
  for (int j = 0; j < nR && j < 4096; j++) modes_idx[j] = j;
  /* the compliance the first k modes carry, k = 1..hi (the library's) */
  double *cd = malloc(sizeof(double) * 2 * (size_t)S->hi), *cs = cd + S->hi;
  int st = cd ? vi_model_modal_compliance(S->R, 0, S->hi, cd, cs) : VI_ERR_NOMEM;
  if (st) {
    fprintf(stderr, "vibroimpact: truncation: %s\n", vi_strerror(st));
    free(cd);
    return 1;
  }
  for (int k = 1; k <= S->hi; k++) {
    double lam = K[(k - 1) + (size_t)(k - 1) * nR];
    if (k < S->lo) continue;
    if (vi_app_signal) break;
    row w;
    memset(&w, 0, sizeof w);
    w.k = k;
    w.fd = cd[k - 1] / S->Gd;
    w.fs = isfinite(S->Gs) && isfinite(cs[k - 1]) ? cs[k - 1] / S->Gs : NAN;
    compute_row(S, &w, modes_idx);
    w.omk = sqrt(lam > 0 ? lam : 0);
    if (S->o->out) table_row(S, &w);
    if (S->o->json) json_row(S, &w);
    else text_row(S, &w);
    fflush(stdout);
  }
  free(cd);
  return 0;
}

/* -o: the reference's row and the table into the file. */
static int study_write(study *S, int complete)
{
  double info[VI_TRUNCATION_INFO] = {S->dofs, S->lo, S->hi, S->nR,
                                     S->r,    S->Gd, S->Gs, complete};
  for (int c = 0; c < VI_TRUNCATION_COLUMNS; c++) S->tref[c] = NAN;
  S->tref[0] = S->nR;
  tab_response(S->tref, 1, 4, &S->ref);
  tab_first(S->tref, 1, 8, &S->fref, NULL);
  return write_h5(S->o, S->sc, info, S->tref, S->nrows, S->tab, S->ldt);
}

int vi_cmd_truncation(const app_opts *o)
{
  study S;
  memset(&S, 0, sizeof S);
  S.o = o;
  int rc;
  if (o->csv || o->periods > 0) {
    /* the study's machine-readable forms are --json (share/plot_truncation.py
     * reads it) and -o; nothing is silently ignored */
    fprintf(stderr, "vibroimpact: truncation: %s is not an option of this "
            "command (--json or -o give the study)\n",
            o->csv ? "--impacts-csv" : "--periods");
    return 2;
  }
  if ((rc = study_scene(&S)) || (rc = study_reference(&S))) goto done;
  S.nR = vi_model_n(S.R);
  if (S.hi > S.nR) S.hi = S.nR;
  if ((rc = study_initial(&S))) goto done;
  study_reference_runs(&S);
  print_header(&S);
  vi_app_set_polling(1); /* a signal ends the rows, not the process */
  int bad = study_rows(&S), intr = vi_app_signal != 0;
  if (o->json) printf("], \"complete\": %s}\n", intr ? "false" : "true");
  rc = bad ? 1 : intr ? vi_app_interrupt_status() : 0;
  if (o->out && !bad) {
    /* interrupted: the rows done, marked incomplete */
    if (study_write(&S, !intr)) rc = 1;
    else if (intr)
      fprintf(stderr, "vibroimpact: truncation: interrupted after %d rows; "
              "the output file is valid and marked incomplete\n", S.nrows);
  }
done:
  free(S.x0);
  vi_orbit_destroy(&S.oref);
  vi_model_destroy(&S.R);
  vi_model_destroy(&S.dense);
  vi_fe_destroy(&S.fe);
  vi_scene_destroy(&S.sc);
  return rc;
}
