/* vi_orbit.c - the orbit analysis handle: a transient classified P(n, m)
 * (vi_classify.c), the P(1,1) orbit (or P(1, m), one stop or several)
 * refined by shooting or found by the direct search, its Floquet
 * multipliers from exact derivatives (vi_orbit_pnm.c), and its energy
 * balance (vi_balance.c). */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_multiroots.h>

#include "vi_forcing.h"
#include "vi_orbit_internal.h"


int vi_orbit_create(const vi_model *model, vi_orbit **out)
{
  if (!out) return VI_ERR_ARG;
  *out = NULL;
  if (!model) return VI_ERR_ARG;
  if (!model->frozen) return VI_ERR_STATE;
  if (!(model->omega_f > 0.0)) return VI_ERR_FREQUENCY;
  if (model->ns < 1) return VI_ERR_STATE; /* nothing to impact */
  if (!vi_model_has_modes(model)) return VI_ERR_UNSUPPORTED; /* band: no modes */
  vi_orbit *o = calloc(1, sizeof *o);
  if (!o) return VI_ERR_NOMEM;
  int n = model->n, ns = model->ns;
  size_t nM = (size_t)n * MAX_M, nS = (size_t)n * ns;
  o->block = calloc(19 * (size_t)n + 8 * nM + 3 * nS + 5 * (size_t)ns, sizeof(double));
  o->rt = malloc(sizeof(double) * RING);
  o->rs = malloc(sizeof(int) * RING);
  o->kcnt = calloc((size_t)ns, sizeof(int));
  o->rz = malloc(sizeof(double) * RING * 2 * (size_t)n);
  o->pz = malloc(sizeof(double) * (3 * MAX_N + 1) * 2 * (size_t)n);
  int st = o->block && o->rt && o->rs && o->kcnt && o->rz && o->pz
               ? vi_sim_create(model, &o->sim) : VI_ERR_NOMEM;
  if (st) { /* vi_sim_create's own code, not a blanket NOMEM */
    vi_orbit_destroy(&o);
    return st;
  }
  double *p = o->block;
  o->x0 = p; p += n;
  o->v0 = p; p += n;
  o->zfix = p; p += (size_t)2 * n;
  o->FE = p; p += n;
  o->DE = p; p += n;
  o->XE = p; p += n;
  o->reff = p; p += n;
  o->mre = p; p += (size_t)2 * n;
  o->mim = p; p += (size_t)2 * n;
  o->scr = p; p += (size_t)2 * n;
  o->dE = p; p += n;
  o->ix = p; p += nM;
  o->mz = p; p += 2 * nM;
  o->iv = p; p += nM;
  o->ivp = p; p += nM;
  o->aFE = p; p += nM;
  o->aDE = p; p += nM;
  o->aXE = p; p += nM;
  o->kFE = p; p += nS;
  o->kDE = p; p += nS;
  o->kXE = p; p += nS;
  o->kKE = p; p += ns;
  o->kRE = p; p += ns;
  o->kIE = p; p += ns;
  o->kr = p; p += ns;
  o->kcl = p;
  o->ns = ns;
  o->m = model;
  o->n = n;
  o->method = vi_xflow_available(model) ? VI_METHOD_EXACT : VI_METHOD_ADAMS;
  o->rtol = 1e-11;
  o->atol = 1e-13;
  o->max_periods = 3000;
  o->tol = 1e-6;
  o->T = vi_forcing_period(model->omega_f);
  o->direct = 1;
  /* the exact method where the simulation offers it for this model */
  if (o->method == VI_METHOD_EXACT && vi_sim_set_method(o->sim, o->method))
    o->method = VI_METHOD_ADAMS;
  if (vi_sim_set_method(o->sim, o->method) ||
      vi_sim_set_tolerances(o->sim, o->rtol, o->atol)) {
    vi_orbit_destroy(&o);
    return VI_ERR_STATE;
  }
  *out = o;
  return VI_OK;
}

void vi_orbit_destroy(vi_orbit **orbit)
{
  if (!orbit || !*orbit) return;
  vi_orbit *o = *orbit;
  vi_sim_destroy(&o->sim);
  free(o->block);
  free(o->rt);
  free(o->rs);
  free(o->kcnt);
  free(o->rz);
  free(o->pz);
  free(o);
  *orbit = NULL;
}

const char *vi_orbit_errmsg(const vi_orbit *o) { return o ? o->errmsg : ""; }

int vi_orbit_set_method(vi_orbit *o, int method)
{
  if (!o) return VI_ERR_ARG;
  int st = vi_sim_set_method(o->sim, method);
  if (st) return vi_fail(o->errmsg, st, "%s", vi_sim_errmsg(o->sim));
  o->method = method;
  return VI_OK;
}

int vi_orbit_set_tolerances(vi_orbit *o, double rtol, double atol)
{
  if (!o) return VI_ERR_ARG;
  int st = vi_sim_set_tolerances(o->sim, rtol, atol);
  if (st) return vi_fail(o->errmsg, st, "%s", vi_sim_errmsg(o->sim));
  o->rtol = rtol;
  o->atol = atol;
  return VI_OK;
}

int vi_orbit_set_initial(vi_orbit *o, const double *x0, const double *v0)
{
  if (!o) return VI_ERR_ARG;
  int st = vi_sim_set_initial(o->sim, 0.0, x0, v0);
  if (st) return vi_fail(o->errmsg, st, "%s", vi_sim_errmsg(o->sim));
  for (int i = 0; i < o->n; i++) {
    o->x0[i] = x0 ? x0[i] : 0.0;
    o->v0[i] = v0 ? v0[i] : 0.0;
  }
  return VI_OK;
}

int vi_orbit_set_monitor(vi_orbit *o, vi_monitor_fn fn, void *user,
                         vi_destroy_fn destroy)
{
  if (!o) return VI_ERR_ARG;
  int st = vi_sim_set_monitor(o->sim, o->T, fn, user, destroy);
  return st ? vi_fail(o->errmsg, st, "%s", vi_sim_errmsg(o->sim)) : VI_OK;
}

int vi_orbit_set_cancel(vi_orbit *o, vi_cancel_fn fn, void *user,
                        vi_destroy_fn destroy)
{
  if (!o) return VI_ERR_ARG;
  int st = vi_sim_set_cancel(o->sim, fn, user, destroy);
  return st ? vi_fail(o->errmsg, st, "%s", vi_sim_errmsg(o->sim)) : VI_OK;
}

int vi_orbit_set_transient(vi_orbit *o, double max_periods, double tol)
{
  if (!o) return VI_ERR_ARG;
  if (!(max_periods >= 4 * MAX_N) || !isfinite(max_periods) || !(tol > 0.0))
    return vi_fail(o->errmsg, VI_ERR_ARG, "transient: max_periods %g must be "
                   ">= %d and tol %g > 0", max_periods, 4 * MAX_N, tol);
  o->max_periods = max_periods;
  o->tol = tol;
  return VI_OK;
}


/* ---- shooting on the stroboscopic map --------------------------------- */
/* impacts of a map run: counted, and the first MAX_M kept (time, stop,
 * pre-impact state) for the map's exact Jacobian */
static int count_map(const vi_event *ev, void *user)
{
  vi_orbit *o = user;
  if (ev->kind != VI_EVENT_IMPACT) return 0;
  int j = o->map_impacts++, n = o->n;
  if (j < MAX_M) {
    o->it[j] = ev->t;
    o->istop[j] = ev->stop;
    memcpy(o->mz + (size_t)j * 2 * n, ev->x, sizeof(double) * n);
    memcpy(o->mz + (size_t)j * 2 * n + n, ev->v_minus, sizeof(double) * n);
  }
  return 0;
}

/* Phi_T(z) from t_s; z = (x, v) stacked [2n]. */
static int flow_map(vi_orbit *o, const double *z, double *out)
{
  int n = o->n, st;
  o->map_impacts = 0;
  if ((st = vi_sim_set_initial(o->sim, o->t_s, z, z + n)) ||
      (st = vi_sim_run(o->sim, o->t_s + o->T)))
    return vi_fail(o->errmsg, st, "map: %s", vi_sim_errmsg(o->sim));
  vi_sim_state(o->sim, NULL, out, out + n);
  return VI_OK;
}

/* F(z) = Phi_T(z) - z and its exact Jacobian D Phi_T - I: the variational
 * flow through the impacts of this run (vi_var_map_jacobian); the map's
 * impacts are kept in o->it, o->istop (which the balance run overwrites
 * afterwards) and o->mz */
static int shoot_fdf(const gsl_vector *z, void *params, gsl_vector *f,
                     gsl_matrix *J)
{
  vi_orbit *o = params;
  int n2 = 2 * o->n;
  double *out = o->scr;
  if (flow_map(o, z->data, out) || o->map_impacts != o->pm) return GSL_EDOM;
  for (int i = 0; f && i < n2; i++) gsl_vector_set(f, i, out[i] - gsl_vector_get(z, i));
  if (!J) return GSL_SUCCESS;
  double *Jm = malloc(sizeof(double) * (size_t)n2 * n2);
  if (!Jm || vi_var_map_jacobian(o->m, o->t_s, o->t_s + o->T, o->pm, o->istop,
                                 o->it, o->mz, Jm)) {
    free(Jm);
    return GSL_EDOM;
  }
  for (int i = 0; i < n2; i++) /* gsl_matrix is row-major */
    for (int j = 0; j < n2; j++) gsl_matrix_set(J, i, j, Jm[i + (size_t)j * n2] - (i == j));
  free(Jm);
  return GSL_SUCCESS;
}

static int shoot_f(const gsl_vector *z, void *params, gsl_vector *f)
{
  return shoot_fdf(z, params, f, NULL);
}

static int shoot_df(const gsl_vector *z, void *params, gsl_matrix *J)
{
  return shoot_fdf(z, params, NULL, J);
}

/* Newton (GSL hybridsj) on Phi_T(z) = z with the exact Jacobian */
static int refine(vi_orbit *o)
{
  int n2 = 2 * o->n, status = VI_OK;
  gsl_multiroot_function_fdf F = {shoot_f, shoot_df, shoot_fdf, (size_t)n2, o};
  gsl_vector *z = gsl_vector_alloc(n2);
  gsl_multiroot_fdfsolver *sv =
      gsl_multiroot_fdfsolver_alloc(gsl_multiroot_fdfsolver_hybridsj, n2);
  if (!z || !sv) {
    status = vi_fail(o->errmsg, VI_ERR_NOMEM, "out of memory");
    goto done;
  }
  double scale = vi_orbit_xs_scale(o->m);
  for (int i = 0; i < n2; i++) {
    gsl_vector_set(z, i, o->zfix[i]);
    scale = fmax(scale, fabs(o->zfix[i]));
  }
  /* the map is exact to round-off (exact flow) or to the tolerance */
  double eps = (o->method == VI_METHOD_EXACT ? 1e-13 : 100.0 * o->rtol) * scale;
  if (gsl_multiroot_fdfsolver_set(sv, &F, z) != GSL_SUCCESS) {
    status = vi_fail(o->errmsg, VI_ERR_NOT_CONVERGED,
                     "shooting: the map left P(1,%d) at the start", o->pm);
    goto done;
  }
  int it;
  for (it = 0; it < 50; it++) {
    if (gsl_multiroot_test_residual(sv->f, eps) == GSL_SUCCESS) break;
    if (gsl_multiroot_fdfsolver_iterate(sv)) break;
  }
  if (gsl_multiroot_test_residual(sv->f, eps) != GSL_SUCCESS) {
    status = vi_fail(o->errmsg, VI_ERR_NOT_CONVERGED,
                     "shooting did not converge: residual %.3g > %.3g after "
                     "%d iterations", gsl_blas_dnrm2(sv->f), eps, it);
    goto done;
  }
  for (int i = 0; i < n2; i++) o->zfix[i] = gsl_vector_get(sv->x, i);
done:
  gsl_multiroot_fdfsolver_free(sv);
  gsl_vector_free(z);
  return status;
}

/* The most stable admissible P(1,1) orbit of the impact-phase scan
 * (vi_orbit_pnm.c), as the state half a period after its impact: 1 if one
 * exists, 0 if none, < 0 on failure. */
static int direct_p11(vi_orbit *o)
{
  int n = o->n, cap = 32, found = 0, best = -1, ok, st;
  double *t = malloc(sizeof(double) * ((size_t)cap * (2 * n + 1) + 5 * (size_t)n));
  if (!t) return VI_ERR_NOMEM;
  double *x = t + cap, *v = x + (size_t)cap * n, *re = v + (size_t)cap * n,
         *im = re + (size_t)2 * n, *vp = im + (size_t)2 * n, rho_best = 1.0;
  st = vi_orbit_p1_scan(o->m, 1, 720, t, x, v, n, cap, &found);
  for (int i = 0; !st && i < found && i < cap; i++) {
    if (vi_orbit_pnm_admissible(o->m, 1, 1, &t[i], x + (size_t)i * n,
                                v + (size_t)i * n, n, NULL, &ok) || !ok ||
        vi_orbit_pnm_multipliers(o->m, 1, 1, &t[i], x + (size_t)i * n,
                                 v + (size_t)i * n, n, re, im))
      continue;
    double rho = 0.0;
    for (int j = 0; j < 2 * n; j++) rho = fmax(rho, hypot(re[j], im[j]));
    if (rho < rho_best) {
      rho_best = rho;
      best = i;
    }
  }
  if (!st && best >= 0) {
    o->t_s = t[best] + 0.5 * o->T;
    st = vi_impact_apply(o->m, v + (size_t)best * n, vp, NULL, NULL);
    if (!st)
      st = vi_flow_physical(o->m, t[best], x + (size_t)best * n, vp, o->t_s,
                            o->zfix, o->zfix + n);
  }
  free(t);
  return st ? (st < 0 ? st : -st) : best >= 0;
}

int vi_orbit_set_direct_search(vi_orbit *o, int on)
{
  if (!o || (on != 0 && on != 1)) return VI_ERR_ARG;
  o->direct = on;
  return VI_OK;
}

int vi_orbit_search_info(const vi_orbit *o, int *tn, int *tm, int *by_scan)
{
  if (!o) return VI_ERR_ARG;
  if (tn) *tn = o->tn;
  if (tm) *tm = o->tm;
  if (by_scan) *by_scan = o->by_scan;
  return VI_OK;
}

int vi_orbit_find(vi_orbit *o)
{
  if (!o) return VI_ERR_ARG;
  int st, n = o->n;
  double t;
  o->analysed = 0;
  o->classified = 0;
  o->pn = o->pm = 0;
  o->tn = o->tm = 0;
  o->by_scan = 0;
  o->nimp = 0;
  if ((st = vi_sim_set_initial(o->sim, 0.0, o->x0, o->v0)) ||
      (st = vi_sim_set_event_callback(o->sim, vi_classify_record, o, NULL)))
    return vi_fail(o->errmsg, st, "%s", vi_sim_errmsg(o->sim));
  int64_t kmax = (int64_t)o->max_periods;
  for (int64_t k = 1; k <= kmax && !o->pn; k++) {
    if ((st = vi_sim_run(o->sim, k * o->T)) == VI_STOPPED)
      return vi_fail(o->errmsg, st, "stopped by the monitor at t = %g",
                     k * o->T);
    if (st)
      return vi_fail(o->errmsg, st, "transient: %s", vi_sim_errmsg(o->sim));
    double *z = vi_classify_strobe(o, k);
    vi_sim_state(o->sim, NULL, z, z + n);
    for (int p = 1; p <= MAX_N && k >= 3 * p + 16; p++) {
      int mm;
      if (vi_classify_repeats(o, k, p, &mm)) {
        o->pn = p;
        o->pm = mm;
        break;
      }
    }
  }
  if (!o->pn) { /* not periodic: report the recent impact rate */
    double tn = kmax * o->T;
    o->pm = (int)lround((o->nimp - vi_classify_first_after(o, tn - 8 * o->T)) / 8.0);
  }
  o->tn = o->pn;
  o->tm = o->pm;
  o->classified = 1;
  /* analysed: P(1,1), else (one stop) a stable P(1,1) orbit the transient
   * missed, else P(1, m), m <= MAX_M (the impacts of a period, on one stop
   * or alternating between several) */
  int multi = o->pn == 1 && o->pm > 1 && o->pm <= MAX_M, got = 0;
  if (o->pn != 1 || o->pm != 1) {
    /* the transient went elsewhere; a stable P(1,1) orbit may still
     * exist (another attractor): look for it directly */
    if (o->direct && o->ns == 1 && vi_xflow_available(o->m)) {
      got = direct_p11(o);
      if (got < 0)
        return vi_fail(o->errmsg, got, "direct P(1,1) search: %s",
                       vi_strerror(got));
    }
    if (!got && !multi) return VI_OK;
  }
  if (got) {
    o->pn = o->pm = 1;
    o->by_scan = 1;
    if ((st = vi_sim_set_event_callback(o->sim, count_map, o, NULL)))
      return vi_fail(o->errmsg, st, "%s", vi_sim_errmsg(o->sim));
  } else {
    /* the section: mid-way in the longest impact-free stretch of the last
     * period, away from every impact */
    vi_sim_state(o->sim, &t, NULL, NULL);
    double best = -1.0, ti = 0.0;
    for (int j = 0; j < o->pm; j++) {
      double a = o->rt[(o->nimp - 1 - j) % RING];
      double b = j == 0 ? o->rt[(o->nimp - o->pm) % RING] + o->T
                        : o->rt[(o->nimp - j) % RING];
      if (b - a > best) {
        best = b - a;
        ti = a + 0.5 * (b - a);
      }
    }
    o->t_s = ti;
    while (o->t_s <= t) o->t_s += o->T;
    if ((st = vi_sim_set_event_callback(o->sim, count_map, o, NULL)) ||
        (st = vi_sim_run(o->sim, o->t_s)))
      return vi_fail(o->errmsg, st < 0 ? st : VI_ERR_STATE, "%s",
                     vi_sim_errmsg(o->sim));
    vi_sim_state(o->sim, NULL, o->zfix, o->zfix + n);
  }
  if ((st = refine(o)) || (st = vi_balance_run(o))) {
    /* a P(1, m) orbit that shooting cannot hold stays classified only */
    if (o->pm > 1 && st == VI_ERR_NOT_CONVERGED) return VI_OK;
    return st;
  }
  /* multipliers from exact derivatives (closed-form state-transition and
   * saltation matrices, vi_orbit_pnm.c) at the impacts of the refined
   * orbit, whichever method integrated it */
  st = vi_orbit_pnm_multipliers_stops(o->m, 1, o->mi, o->istop, o->it, o->ix,
                                      o->iv, n, o->mre, o->mim);
  if (st) return vi_fail(o->errmsg, st, "multipliers: %s", vi_strerror(st));
  o->analysed = 1;
  return VI_OK;
}

/* ---- getters ------------------------------------------------------------ */
int vi_orbit_classify(const vi_orbit *o, int *n, int *m)
{
  if (!o) return VI_ERR_ARG;
  if (n) *n = o->pn;
  if (m) *m = o->pm;
  return o->classified ? VI_OK : VI_ERR_STATE; /* 0, 0: nothing sought */
}

int vi_orbit_multipliers(const vi_orbit *o, double *re, double *im)
{
  NEED_ORBIT(o);
  if (re) memcpy(re, o->mre, sizeof(double) * 2 * o->n);
  if (im) memcpy(im, o->mim, sizeof(double) * 2 * o->n);
  return VI_OK;
}

