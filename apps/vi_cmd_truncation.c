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
 * coordinates, where M = I: reduced models keep its first k coordinates. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vi_app.h"
#include "vi_sweep.h" /* --set */
#include "vibroimpact/vi_sparse.h"
#include "vibroimpact/vi_truncation_io.h"

/* The outcome of the orbit search on one model. */
typedef struct response {
  int pn, pm;      /* class: (1, 1) P(1,1); (0, m) not periodic */
  double vN, phase; /* P(1,1): approach velocity, impact time mod T / T */
  int ok;          /* the search ran */
} response;

static void find_orbit(const vi_model *m, response *r, vi_orbit **keep)
{
  vi_orbit *o = NULL;
  memset(r, 0, sizeof *r);
  r->vN = r->phase = NAN;
  if (!vi_orbit_create(m, &o) && !vi_orbit_set_initial(o, NULL, NULL) &&
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

/* k modes of the reference R (n_R modal coordinates, M = I) plus, when
 * `corr`, the static residual vector at the stop: c_j = psi_j / omega_j^2
 * for j > k (K^-1 w less its part in the kept modes, in modal coordinates),
 * normalised.  Projected: M = I, K = T^T K T, C = T^T C T, stop T^T psi,
 * forcing T^T (a, b, f0), the stop's x_s and the given r.  Small dense
 * matrices (k + 1 <= a few hundred): plain loops. */
static int build_model(const vi_model *R, int k, int corr, double r,
                       const double *q0R, vi_model **out, double *carried,
                       double *q0)
{
  int nR = vi_model_n(R), n = k + corr, st;
  const double *K = vi_model_stiffness(R), *C = vi_model_damping(R),
               *psi = vi_model_stop_vector(R), *fa = vi_model_forcing_cos(R),
               *fb = vi_model_forcing_sin(R), *fc = vi_model_forcing_const(R);
  /* the reference's own coordinates are its modes (M = I, K diagonal) */
  double *T = calloc((size_t)nR * n + 5 * (size_t)n * n + 5 * (size_t)n,
                     sizeof(double));
  if (!T) return VI_ERR_NOMEM;
  double *Mn = T + (size_t)nR * n, *Kn = Mn + (size_t)n * n,
         *Cn = Kn + (size_t)n * n, *tmp = Cn + (size_t)n * n,
         *w = tmp + 2 * (size_t)n * n, *a = w + n, *b = a + n, *f0 = b + n;
  for (int j = 0; j < k; j++) T[j + (size_t)j * nR] = 1.0;
  if (corr) {
    double nrm = 0;
    for (int j = k; j < nR; j++) {
      double lam = K[j + (size_t)j * nR];
      double c = lam > 0 ? psi[j] / lam : 0.0;
      T[j + (size_t)k * nR] = c;
      nrm += c * c;
    }
    nrm = sqrt(nrm);
    if (!(nrm > 0)) {
      free(T);
      return VI_ERR_ARG; /* no residual: nothing beyond the kept modes */
    }
    for (int j = k; j < nR; j++) T[j + (size_t)k * nR] /= nrm;
  }
  /* X_n = T^T X T for X = I, K, C; vectors T^T v */
  for (int p = 0; p < n; p++) {
    for (int q = 0; q < n; q++) {
      double sm = 0, sk = 0, sc = 0;
      for (int i = 0; i < nR; i++) {
        double ti = T[i + (size_t)p * nR];
        if (ti == 0) continue;
        sm += ti * T[i + (size_t)q * nR];
        for (int j = 0; j < nR; j++) {
          double tj = T[j + (size_t)q * nR];
          if (tj == 0) continue;
          sk += ti * K[i + (size_t)j * nR] * tj;
          sc += ti * C[i + (size_t)j * nR] * tj;
        }
      }
      Mn[p + (size_t)q * n] = sm;
      Kn[p + (size_t)q * n] = sk;
      Cn[p + (size_t)q * n] = sc;
    }
    double sw = 0, sa = 0, sb = 0, sf = 0;
    for (int i = 0; i < nR; i++) {
      double ti = T[i + (size_t)p * nR];
      sw += ti * psi[i];
      sa += ti * fa[i];
      sb += ti * fb[i];
      sf += ti * fc[i];
    }
    w[p] = sw;
    a[p] = sa;
    b[p] = sb;
    f0[p] = sf;
  }
  double g = 0;
  for (int p = 0; p < n; p++) g += w[p] * w[p]; /* w^T M^-1 w, M = I */
  /* the reference's initial state [2 nR] projected: T^T q (T orthonormal) */
  for (int h = 0; q0R && q0 && h < 2; h++)
    for (int p = 0; p < n; p++) {
      double sum = 0;
      for (int i = 0; i < nR; i++)
        sum += T[i + (size_t)p * nR] * q0R[i + (size_t)h * nR];
      q0[p + (size_t)h * n] = sum;
    }
  if (carried) *carried = g;
  vi_model *m = NULL;
  if (!(st = vi_model_create(n, &m)) && !(st = vi_model_set_mass(m, Mn, n)) &&
      !(st = vi_model_set_stiffness(m, Kn, n)) &&
      !(st = vi_model_set_damping(m, Cn, n)) &&
      !(st = vi_model_set_forcing(m, vi_model_omega_forcing(R), a, b, f0)) &&
      !(st = vi_model_set_stop(m, w, vi_model_clearance(R), r)))
    st = vi_model_setup(m);
  free(T);
  if (st)
    vi_model_destroy(&m);
  else
    *out = m;
  return st;
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
      !vi_sim_set_event_callback(s, on_first, f, NULL)) {
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


int vi_cmd_truncation(const app_opts *o)
{
  vi_scene *sc = NULL;
  vi_model *R = NULL, *dense = NULL;
  vi_fe *fe = NULL;
  vi_orbit *oref = NULL;
  vi_diag d;
  int rc = 2, st;
  memset(&d, 0, sizeof d);
  int lo = o->modes_lo > 0 ? o->modes_lo : 1, hi = o->modes_hi;
  if (o->csv || o->periods > 0) {
    /* the study's machine-readable forms are --json (share/plot_truncation.py
     * reads it) and -o; nothing is silently ignored */
    fprintf(stderr, "vibroimpact: truncation: %s is not an option of this "
            "command (--json or -o give the study)\n",
            o->csv ? "--impacts-csv" : "--periods");
    return 2;
  }
  st = vi_sets_active() ? vi_sets_load(o->scene, &sc, &d) /* --set */
       : o->scene ? vi_scene_load_limited(o->scene, o->max_scene_bytes,
                                          o->max_depth, &sc, &d)
                  : vi_scene_parse(vi_scene_default_text(), -1,
                                   "<default scene: fig2>", &sc, &d);
  if (!st) st = vi_scene_set_run(sc, o->rtol, o->atol, 0, o->method);
  if (!st) st = vi_scene_check_memory(sc, o->max_memory, &d);
  if (st) {
    vi_app_print_diag(&d, st);
    goto done;
  }
  /* an FE scene refuses -1 modes, any other kind the FE reduction */
  int is_fe = vi_scene_create_fe(sc, -1, 0, &fe, NULL) != VI_ERR_UNSUPPORTED;
  if (hi <= 0) hi = is_fe ? vi_scene_n(sc) : vi_scene_dofs(sc);
  if (lo > hi || hi > vi_scene_dofs(sc)) {
    fprintf(stderr, "vibroimpact: truncation: --modes %d..%d: need 1 <= A <= "
            "B <= %d (the model's coordinates)\n", lo, hi, vi_scene_dofs(sc));
    goto done;
  }
  double Gd = NAN, Gs = NAN; /* the full model's w^T M^-1 w, w^T K^-1 w */
  rc = 1;
  if (is_fe) {
    int nref = 2 * hi > hi + 20 ? 2 * hi : hi + 20;
    nref = nref < vi_scene_dofs(sc) ? nref : vi_scene_dofs(sc);
    if (o->modes_ref > 0) nref = o->modes_ref;
    if (nref < hi || nref > vi_scene_dofs(sc)) {
      fprintf(stderr, "vibroimpact: truncation: --reference %d: need B = %d "
              "<= N <= %d (the dofs)\n", nref, hi, vi_scene_dofs(sc));
      rc = 2;
      goto done;
    }
    if ((st = vi_scene_create_fe(sc, nref, 1, &fe, &d))) {
      vi_app_print_diag(&d, st);
      rc = st == VI_ERR_NOMEM ? 1 : 2;
      goto done;
    }
    if (vi_fe_create_model(fe, &R) != VI_OK) {
      fprintf(stderr, "vibroimpact: truncation: %s\n", vi_fe_errmsg(fe));
      goto done;
    }
    vi_fe_stop_compliance(fe, 0, &Gd, &Gs);
  } else {
    if ((st = vi_scene_create_model(sc, &dense, &d))) {
      vi_app_print_diag(&d, st);
      rc = st == VI_ERR_NOMEM ? 1 : 2;
      goto done;
    }
    if (!vi_model_omega(dense)) {
      fprintf(stderr, "vibroimpact: truncation: the scene's model has no "
              "modes (band storage): ask for them (output.modes: true)\n");
      rc = 2;
      goto done;
    }
    /* the dense model in its own modal coordinates: the reference */
    int n = vi_model_n(dense), all[4096];
    if (n > 4096) {
      fprintf(stderr, "vibroimpact: truncation: more than 4096 coordinates "
              "in a dense scene: write it as Matrix Market files\n");
      rc = 2;
      goto done;
    }
    for (int j = 0; j < n; j++) all[j] = j;
    if ((st = vi_model_create_reduced(dense, all, n,
                                      vi_model_restitution(dense), &R))) {
      fprintf(stderr, "vibroimpact: truncation: %s\n", vi_strerror(st));
      goto done;
    }
    const double *om = vi_model_omega(dense), *ps = vi_model_modal_stop(dense);
    Gd = vi_model_stop_compliance(dense);
    Gs = 0;
    for (int j = 0; j < n; j++)
      Gs += om[j] > 0 ? ps[j] * ps[j] / (om[j] * om[j])
                      : (ps[j] != 0 ? INFINITY : 0);
  }
  int nR = vi_model_n(R);
  if (hi > nR) hi = nR;
  /* the scene's initial state in the reference's coordinates: q = Psi^T M x
   * (the FE reduction's kept shapes, or the dense model's modes) */
  int dofs = vi_scene_dofs(sc);
  int nrows = 0, ldt = hi - lo + 1 > 0 ? hi - lo + 1 : 1; /* -o: rows */
  double *x0 = calloc(2 * (size_t)dofs + 2 * (size_t)nR + 4 * (size_t)hi + 4 +
                          (o->out ? (size_t)(ldt + 1) * VI_TRUNCATION_COLUMNS
                                  : 0),
                      sizeof(double));
  if (!x0) goto done;
  double *tab = x0 + 2 * (size_t)dofs + 2 * (size_t)nR + 4 * (size_t)hi + 4,
         *tref = tab + (size_t)ldt * VI_TRUNCATION_COLUMNS;
  double *q0R = x0 + 2 * (size_t)dofs, *qk = q0R + 2 * (size_t)nR;
  vi_scene_initial(sc, x0, x0 + dofs);
  if ((fe && (vi_fe_to_modal(fe, x0, q0R) ||
              vi_fe_to_modal(fe, x0 + dofs, q0R + nR))) ||
      (dense && (vi_model_to_modal(dense, x0, q0R) ||
                 vi_model_to_modal(dense, x0 + dofs, q0R + nR)))) {
    fprintf(stderr, "vibroimpact: truncation: cannot project the initial "
            "state onto the modes\n");
    free(x0);
    goto done;
  }
  if (nR > 4096) {
    fprintf(stderr, "vibroimpact: truncation: a reference of %d modes: at "
            "most 4096\n", nR);
    free(x0);
    goto done;
  }
  const double *K = vi_model_stiffness(R), *psi = vi_model_stop_vector(R);
  double r = vi_model_restitution(R);
  int forced = vi_model_omega_forcing(R) > 0;
  /* the reference orbit: the balance every reduced model is measured by */
  response ref;
  memset(&ref, 0, sizeof ref);
  ref.vN = ref.phase = NAN;
  if (forced) {
    vi_app_set_polling(0);
    find_orbit(R, &ref, &oref);
  }
  int p11 = oref && ref.pn == 1 && ref.pm == 1;
  double t0 = vi_scene_t0(sc), tend = vi_scene_t_end(sc);
  first fref;
  first_impacts(R, t0, tend, q0R, &fref);
  if (o->json) {
    printf("{\"scene\": \"%s\", \"dofs\": %d, \"modes\": [%d, %d], "
           "\"restitution\": %.17g, ", vi_scene_name(sc), vi_scene_dofs(sc),
           lo, hi, r);
    json_num("compliance_dynamic", Gd, 1);
    json_num("compliance_static", Gs, 1);
    printf("\"reference\": ");
    json_response(&ref);
    printf(", ");
    json_first("first_impacts", &fref, NULL);
    printf(", \"rows\": [");
  } else {
    printf("truncation study, scene %s: %d dofs, reference %d modes, r = %g\n",
           vi_scene_name(sc), vi_scene_dofs(sc), nR, r);
    printf("  stop compliance w^T M^-1 w = %.6g, w^T K^-1 w = %.6g; "
           "reference orbit: ", Gd, Gs);
    char b[64];
    printf("%s\n", forced ? text_response(&ref, b, sizeof b)
                          : "none (no harmonic forcing)");
    if (fref.n > 0)
      printf("  reference's first impact from the initial state: t = %.10g, "
             "v_n = %.8g\n", fref.t[0], fref.vn[0]);
    printf("  %3s %12s %9s %9s %22s %10s %22s | %9s %22s | %9s %9s\n", "k",
           "omega_k", "dyn.frac", "stat.frac", "v_N @phase (r)", "r_S",
           "v_N @phase (r_S)", "+static", "v_N @phase (+static)", "dt1",
           "dt1+stat");
  }
  int modes_idx[4096];
  for (int j = 0; j < nR && j < 4096; j++) modes_idx[j] = j;
  double cd = 0, cs = 0;
  for (int k = 1; k <= hi; k++) {
    double lam = K[(k - 1) + (size_t)(k - 1) * nR];
    cd += psi[k - 1] * psi[k - 1];
    cs += lam > 0 ? psi[k - 1] * psi[k - 1] / lam : INFINITY;
    if (k < lo) continue;
    if (vi_app_signal) break;
    double fd = cd / Gd, fs = isfinite(Gs) && isfinite(cs) ? cs / Gs : NAN;
    response rk, rs, rc2;
    memset(&rk, 0, sizeof rk);
    memset(&rs, 0, sizeof rs);
    memset(&rc2, 0, sizeof rc2);
    rk.vN = rk.phase = rs.vN = rs.phase = rc2.vN = rc2.phase = NAN;
    double rS = NAN, carried = NAN;
    vi_model *mk = NULL, *ms = NULL, *mc = NULL;
    first fk, fc1;
    memset(&fk, 0, sizeof fk);
    memset(&fc1, 0, sizeof fc1);
    if (!build_model(R, k, 0, r, q0R, &mk, NULL, qk))
      first_impacts(mk, t0, tend, qk, &fk);
    if (forced) {
      if (mk) find_orbit(mk, &rk, NULL);
      if (p11 && !vi_orbit_reduced_restitution(oref, modes_idx, k, &rS) &&
          !build_model(R, k, 0, rS, NULL, &ms, NULL, NULL))
        find_orbit(ms, &rs, NULL);
    }
    if (k < nR && !build_model(R, k, 1, r, q0R, &mc, &carried, qk)) {
      first_impacts(mc, t0, tend, qk, &fc1);
      if (forced) find_orbit(mc, &rc2, NULL);
    }
    double fc = carried / Gd;
    vi_model_destroy(&mk);
    vi_model_destroy(&ms);
    vi_model_destroy(&mc);
    double omk = sqrt(lam > 0 ? lam : 0);
    if (o->out) {
      double *t = tab + nrows++;
      t[0] = k;
      t[ldt] = omk;
      t[2 * (size_t)ldt] = fd;
      t[3 * (size_t)ldt] = fs;
      tab_response(t, ldt, 4, &rk);
      tab_first(t, ldt, 8, &fk, &fref);
      t[22 * (size_t)ldt] = rS;
      tab_response(t, ldt, 23, &rs);
      t[27 * (size_t)ldt] = k < nR;
      t[28 * (size_t)ldt] = k < nR ? fc : NAN;
      tab_response(t, ldt, 29, &rc2);
      tab_first(t, ldt, 33, &fc1, &fref);
      if (k >= nR) /* no mode beyond k: no variant */
        for (int c = 29; c < VI_TRUNCATION_COLUMNS; c++)
          t[(size_t)c * ldt] = NAN;
    }
    if (o->json) {
      printf("%s{\"k\": %d, ", k > lo ? ", " : "", k);
      json_num("omega", omk, 1);
      json_num("dynamic_fraction", fd, 1);
      json_num("static_fraction", fs, 1);
      printf("\"response\": ");
      json_response(&rk);
      printf(", ");
      json_first("first_impacts", &fk, &fref);
      printf(", ");
      json_num("r_S", rS, 1);
      printf("\"response_r_S\": ");
      json_response(&rs);
      if (k < nR) {
        printf(", \"static_corrected\": {");
        json_num("dynamic_fraction", fc, 1);
        printf("\"response\": ");
        json_response(&rc2);
        printf(", ");
        json_first("first_impacts", &fc1, &fref);
        printf("}}");
      } else /* no mode beyond k: no residual */
        printf(", \"static_corrected\": null}");
    } else {
      char b1[64], b2[64], b3[64], f3[32] = "-", d1[32] = "-", d2[32] = "-";
      if (k < nR) snprintf(f3, sizeof f3, "%.6f", fc);
      if (fk.n > 0 && fref.n > 0)
        snprintf(d1, sizeof d1, "%.2e", fk.t[0] - fref.t[0]);
      if (fc1.n > 0 && fref.n > 0)
        snprintf(d2, sizeof d2, "%.2e", fc1.t[0] - fref.t[0]);
      printf("  %3d %12.6g %9.6f %9.6f %22s %10.6f %22s | %9s %22s | %9s "
             "%9s\n", k, omk, fd, fs,
             forced ? text_response(&rk, b1, sizeof b1) : "-", rS,
             forced && p11 ? text_response(&rs, b2, sizeof b2) : "-", f3,
             forced && k < nR ? text_response(&rc2, b3, sizeof b3) : "-", d1,
             d2);
    }
    fflush(stdout);
  }
  if (o->json) printf("]}\n");
  rc = vi_app_signal ? vi_app_interrupt_status() : 0;
  if (o->out && !rc) { /* interrupted: no file */
    double info[VI_TRUNCATION_INFO] = {dofs, lo, hi, nR, r, Gd, Gs};
    for (int c = 0; c < VI_TRUNCATION_COLUMNS; c++) tref[c] = NAN;
    tref[0] = nR;
    tab_response(tref, 1, 4, &ref);
    tab_first(tref, 1, 8, &fref, NULL);
    rc = write_h5(o, sc, info, tref, nrows, tab, ldt);
  }
  free(x0);
done:
  vi_orbit_destroy(&oref);
  vi_model_destroy(&R);
  vi_model_destroy(&dense);
  vi_fe_destroy(&fe);
  vi_scene_destroy(&sc);
  return rc;
}
