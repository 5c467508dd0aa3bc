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
 * The study is the library's (vi_truncation.h); this command makes its
 * reference from the scene, runs it row by row and prints or writes each.
 * The reference is a model with more modes than any studied: for a
 * model.matrix_market scene its max(2B, B + 20) lowest modes (at most the
 * dofs; vi_scene_create_fe) or --reference N of them (N >= B), for the
 * other kinds the scene's model with all its modes (B at most n). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vi_app.h"
#include "vi_diagram.h" /* --set */
#include "vibroimpact/vi_sparse.h"
#include "vibroimpact/vi_truncation_io.h"

/* Columns of a row (vi_truncation.h) that the printing reads. */
enum { C_K = 0, C_OMEGA = 1, C_FD = 2, C_FS = 3, C_RESP = 4, C_FIRST = 8,
       C_RS = 22, C_RESP_RS = 23, C_SC = 27, C_SC_FD = 28, C_SC_RESP = 29,
       C_SC_FIRST = 33 };

/* A progress line per forcing period of the reference's orbit search (on
 * a terminal, see note_reference). */
static int on_period(const vi_progress *p, void *user)
{
  (void)user;
  fprintf(stderr, "\r  reference orbit: t = %-12.6g %lld impacts ", p->t,
          (long long)p->impacts);
  return 0;
}

static void json_num(const char *key, double v, int comma)
{
  if (isfinite(v))
    printf("\"%s\": %.17g%s", key, v, comma ? ", " : "");
  else
    printf("\"%s\": null%s", key, comma ? ", " : "");
}

/* The first impacts at columns c.. of row, against the reference's row
 * (NULL: none). */
static void json_first(const char *key, const double *row, int c,
                       const double *ref)
{
  int n = (int)row[c], nref = ref ? (int)ref[C_FIRST] : 0;
  printf("\"%s\": {\"t\": [", key);
  for (int j = 0; j < n; j++) printf("%s%.17g", j ? ", " : "", row[c + 1 + j]);
  printf("], \"vn\": [");
  for (int j = 0; j < n; j++) printf("%s%.17g", j ? ", " : "", row[c + 4 + j]);
  printf("]");
  if (ref) { /* errors against the reference's, impact by impact */
    printf(", \"dt\": [");
    for (int j = 0; j < n && j < nref; j++)
      printf("%s%.3g", j ? ", " : "", row[c + 7 + j]);
    printf("], \"dvn_rel\": [");
    for (int j = 0; j < n && j < nref; j++)
      printf("%s%.3g", j ? ", " : "", row[c + 10 + j]);
    printf("]");
  }
  printf(", ");
  json_num("release", row[c + 13], 0);
  printf("}");
}

/* The response at columns c..c+3: class_n (-1: no search), class_m, vN,
 * phase. */
static void json_response(const double *row, int c)
{
  int pn = (int)row[c], pm = pn < 0 ? 0 : (int)row[c + 1];
  if (pn < 0)
    printf("{\"class\": null}");
  else if (pn == 1 && pm == 1)
    printf("{\"class\": \"P(1,1)\", \"vN\": %.17g, \"phase\": %.17g}",
           row[c + 2], row[c + 3]);
  else if (pn)
    printf("{\"class\": \"P(%d,%d)\"}", pn, pm);
  else
    printf("{\"class\": \"not periodic\", \"impacts_per_period\": %d}", pm);
}

static const char *text_response(const double *row, int c, char *buf,
                                 size_t len)
{
  int pn = (int)row[c], pm = pn < 0 ? 0 : (int)row[c + 1];
  if (pn < 0)
    snprintf(buf, len, "%s", "no orbit");
  else if (pn == 1 && pm == 1)
    snprintf(buf, len, "%.6g @%.4f", row[c + 2], row[c + 3]);
  else if (pn)
    snprintf(buf, len, "P(%d,%d)", pn, pm);
  else
    snprintf(buf, len, "aperiodic");
  return buf;
}

typedef int (*trunc_h5_fn)(const char *, const char *, const char *,
                           const double *, const double *, int,
                           const double *, int, vi_diag *);

/* The study's state: the scene, what the reference was made from, the
 * library's study, its information and the reference's row. */
typedef struct study {
  const app_opts *o;
  vi_scene *sc;
  vi_model *dense;
  vi_fe *fe;
  vi_truncation *tr;
  int lo, hi, nR, forced, p11;
  double info[VI_TRUNCATION_INFO], ref[VI_TRUNCATION_COLUMNS];
} study;

/* -o: the study through vi_truncation_write_h5 (libvibroimpact_h5); 0 or 1
 * after a message.  complete: 0 for an interrupted study (the rows done). */
static int study_write(study *S, int complete)
{
  union { void *p; trunc_h5_fn f; } u;
  int n = 0, st = 1;
  vi_truncation_table(S->tr, NULL, 0, &n);
  double *rows = malloc(sizeof(double) * (size_t)(n > 1 ? n : 1) *
                        VI_TRUNCATION_COLUMNS);
  u.p = rows ? vi_app_io_symbol("vi_truncation_write_h5") : NULL;
  if (u.p) {
    vi_diag d;
    vi_truncation_table(S->tr, rows, n > 1 ? n : 1, &n);
    vi_truncation_summary(S->tr, S->info);
    S->info[VI_TRUNCATION_INFO - 1] = complete;
    st = u.f(S->o->out_target, vi_scene_name(S->sc), vi_scene_text(S->sc),
             S->info, S->ref, n, rows, n > 1 ? n : 1, &d);
    if (st) fprintf(stderr, "vibroimpact: %s\n",
                    st == VI_ERR_IO ? d.message : vi_strerror(st));
  } else if (!rows)
    fprintf(stderr, "vibroimpact: truncation: %s\n", vi_strerror(VI_ERR_NOMEM));
  free(rows);
  return st ? 1 : 0;
}

/* The scene (with --set and the run overrides); 0 or 2 after a message. */
static int study_scene(study *S)
{
  const app_opts *o = S->o;
  vi_diag d;
  memset(&d, 0, sizeof d);
  /* the scene's own vectors within --max-memory too, before they are
   * allocated (a matrix file's header may claim any n) */
  int st = vi_sets_active()
               ? vi_sets_load(o->scene, o->max_scene_bytes, o->max_depth, o->max_memory, &S->sc,
                              &d) /* --set */
           : o->scene ? vi_scene_load_within(o->scene, o->max_scene_bytes,
                                             o->max_depth, o->max_memory,
                                             &S->sc, &d)
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

/* An FE scene's study: its reference the nref lowest modes; 0 or the
 * exit status. */
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
  if ((st = vi_truncation_create_fe(S->fe, &S->tr)) != VI_OK) {
    const char *m = vi_fe_errmsg(S->fe);
    fprintf(stderr, "vibroimpact: truncation: %s\n", *m ? m : vi_strerror(st));
    return 1;
  }
  return 0;
}

/* Any other scene's study: its reference the model with all its modes;
 * 0 or the exit status. */
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
  if ((st = vi_truncation_create(S->dense, &S->tr))) {
    fprintf(stderr, "vibroimpact: truncation: %s\n", vi_strerror(st));
    return 1;
  }
  return 0;
}

/* The modes asked for, checked, and the study with its reference; 0 or
 * the exit status. */
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
  int rc = is_fe ? reference_fe(S) : reference_dense(S);
  if (rc) return rc;
  S->nR = vi_model_n(vi_truncation_model(S->tr));
  if (S->hi > S->nR) S->hi = S->nR;
  if (vi_truncation_set_modes(S->tr, S->lo, S->hi)) {
    fprintf(stderr, "vibroimpact: truncation: %s\n", vi_truncation_errmsg(S->tr));
    return 2;
  }
  return 0;
}

/* The scene's initial state, projected by the study onto the reference's
 * coordinates; 0 or 1 after a message. */
static int study_initial(study *S)
{
  int dofs = vi_scene_dofs(S->sc), st;
  double *x0 = calloc(2 * (size_t)dofs, sizeof(double));
  if (!x0) return 1;
  vi_scene_initial(S->sc, x0, x0 + dofs);
  st = vi_truncation_set_initial(S->tr, vi_scene_t0(S->sc),
                                 vi_scene_t_end(S->sc), x0, x0 + dofs);
  free(x0);
  if (st) {
    fprintf(stderr, "vibroimpact: truncation: cannot project the initial "
            "state onto the modes\n");
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
  const vi_model *R = vi_truncation_model(S->tr);
  const double *om = vi_model_omega(R);
  double Om = vi_model_omega_forcing(R);
  if (S->o->quiet || !om || !(Om > 0)) return;
  double steps = 4.0 * om[S->nR - 1] / Om;
  if (steps * S->nR < 1e6) return; /* seconds at most: nothing to say */
  fprintf(stderr, "vibroimpact: truncation: the reference's %d modes reach "
          "omega = %.4g: about %.2g steps per forcing period, each over all "
          "modes; its orbit search may take minutes (a smaller --reference "
          "is faster; Ctrl-C stops)\n", S->nR, om[S->nR - 1], steps);
}

/* The reference orbit (the balance every reduced model is measured by)
 * and the reference's first impacts: the study's first step; 0 or the
 * exit status. */
static int study_reference_runs(study *S)
{
  note_reference(S);
  vi_truncation_set_cancel(S->tr, vi_app_cancel, NULL, NULL);
  if (S->o->progress) vi_truncation_set_monitor(S->tr, on_period, NULL, NULL);
  vi_app_set_polling(1); /* the study polls a signal (vi_app_cancel) */
  int st = vi_truncation_iterate(S->tr);
  if (S->o->progress) fputc('\n', stderr);
  if (st == VI_CANCELLED || st == VI_STOPPED) return vi_app_interrupt_status();
  if (st) {
    fprintf(stderr, "vibroimpact: truncation: %s\n", vi_truncation_errmsg(S->tr));
    return 1;
  }
  vi_truncation_row(S->tr, 0, S->ref);
  vi_truncation_summary(S->tr, S->info);
  S->forced = vi_model_omega_forcing(vi_truncation_model(S->tr)) > 0;
  S->p11 = S->ref[C_RESP] == 1 && S->ref[C_RESP + 1] == 1;
  return 0;
}

static void print_header(const study *S)
{
  const vi_scene *sc = S->sc;
  double r = S->info[4], Gd = S->info[5], Gs = S->info[6];
  if (S->o->json) {
    printf("{\"scene\": \"%s\", \"dofs\": %d, \"modes\": [%d, %d], "
           "\"restitution\": %.17g, ", vi_scene_name(sc), vi_scene_dofs(sc),
           S->lo, S->hi, r);
    json_num("compliance_dynamic", Gd, 1);
    json_num("compliance_static", Gs, 1);
    printf("\"reference\": ");
    json_response(S->ref, C_RESP);
    printf(", ");
    json_first("first_impacts", S->ref, C_FIRST, NULL);
    printf(", \"rows\": [");
    return;
  }
  printf("truncation study, scene %s: %d dofs, reference %d modes, r = %g\n",
         vi_scene_name(sc), vi_scene_dofs(sc), S->nR, r);
  printf("  stop compliance w^T M^-1 w = %.6g, w^T K^-1 w = %.6g; "
         "reference orbit: ", Gd, Gs);
  char b[64];
  printf("%s\n", S->forced ? text_response(S->ref, C_RESP, b, sizeof b)
                           : "none (no harmonic forcing)");
  if (S->ref[C_FIRST] > 0)
    printf("  reference's first impact from the initial state: t = %.10g, "
           "v_n = %.8g\n", S->ref[C_FIRST + 1], S->ref[C_FIRST + 4]);
  printf("  %3s %12s %9s %9s %22s %10s %22s | %9s %22s | %9s %9s\n", "k",
         "omega_k", "dyn.frac", "stat.frac", "v_N @phase (r)", "r_S",
         "v_N @phase (r_S)", "+static", "v_N @phase (+static)", "dt1",
         "dt1+stat");
}

static void json_row(const study *S, const double *w)
{
  int k = (int)w[C_K];
  printf("%s{\"k\": %d, ", k > S->lo ? ", " : "", k);
  json_num("omega", w[C_OMEGA], 1);
  json_num("dynamic_fraction", w[C_FD], 1);
  json_num("static_fraction", w[C_FS], 1);
  printf("\"response\": ");
  json_response(w, C_RESP);
  printf(", ");
  json_first("first_impacts", w, C_FIRST, S->ref);
  printf(", ");
  json_num("r_S", w[C_RS], 1);
  printf("\"response_r_S\": ");
  json_response(w, C_RESP_RS);
  if (w[C_SC] == 1) {
    printf(", \"static_corrected\": {");
    json_num("dynamic_fraction", w[C_SC_FD], 1);
    printf("\"response\": ");
    json_response(w, C_SC_RESP);
    printf(", ");
    json_first("first_impacts", w, C_SC_FIRST, S->ref);
    printf("}}");
  } else /* no mode beyond k: no residual */
    printf(", \"static_corrected\": null}");
}

static void text_row(const study *S, const double *w)
{
  int k = (int)w[C_K], sc = w[C_SC] == 1, nref = S->ref[C_FIRST] > 0;
  char b1[64], b2[64], b3[64], f3[32] = "-", d1[32] = "-", d2[32] = "-";
  if (sc) snprintf(f3, sizeof f3, "%.6f", w[C_SC_FD]);
  if (w[C_FIRST] > 0 && nref)
    snprintf(d1, sizeof d1, "%.2e", w[C_FIRST + 7]);
  if (sc && w[C_SC_FIRST] > 0 && nref)
    snprintf(d2, sizeof d2, "%.2e", w[C_SC_FIRST + 7]);
  printf("  %3d %12.6g %9.6f %9.6f %22s %10.6f %22s | %9s %22s | %9s "
         "%9s\n", k, w[C_OMEGA], w[C_FD], w[C_FS],
         S->forced ? text_response(w, C_RESP, b1, sizeof b1) : "-", w[C_RS],
         S->forced && S->p11 ? text_response(w, C_RESP_RS, b2, sizeof b2) : "-",
         f3, S->forced && sc ? text_response(w, C_SC_RESP, b3, sizeof b3) : "-",
         d1, d2);
}

/* The rows k = lo..hi, each printed when done, until a signal (the
 * study polls it); 1 after an error. */
static int study_rows(study *S)
{
  double w[VI_TRUNCATION_COLUMNS]; /* a signal ends the rows */
  for (int k = S->lo; !vi_truncation_done(S->tr); k++) {
    int st = vi_truncation_iterate(S->tr);
    if (st == VI_CANCELLED) break;
    if (st) {
      fprintf(stderr, "vibroimpact: truncation: %s\n", vi_strerror(st));
      return 1;
    }
    vi_truncation_row(S->tr, k, w);
    if (S->o->json) json_row(S, w);
    else text_row(S, w);
    fflush(stdout);
  }
  return 0;
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
  if ((rc = study_scene(&S)) || (rc = study_reference(&S)) ||
      (rc = study_initial(&S)) || (rc = study_reference_runs(&S)))
    goto done;
  print_header(&S);
  int bad = study_rows(&S), intr = vi_app_signal != 0;
  if (o->json) printf("], \"complete\": %s}\n", intr ? "false" : "true");
  rc = bad ? 1 : intr ? vi_app_interrupt_status() : 0;
  if (o->out && !bad) {
    /* interrupted: the rows done, marked incomplete */
    int n = 0;
    vi_truncation_table(S.tr, NULL, 0, &n);
    if (study_write(&S, !intr)) rc = 1;
    else if (intr)
      fprintf(stderr, "vibroimpact: truncation: interrupted after %d rows; "
              "the output file is valid and marked incomplete\n", n);
  }
done:
  vi_truncation_destroy(&S.tr);
  vi_model_destroy(&S.dense);
  vi_fe_destroy(&S.fe);
  vi_scene_destroy(&S.sc);
  return rc;
}
