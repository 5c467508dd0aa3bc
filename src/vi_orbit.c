/* vi_orbit.c - P(n, m) classification, P(1,1) refinement by shooting, Floquet
 * multipliers and the energy balance of WB 11-13. */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_eigen.h>
#include <gsl/gsl_multiroots.h>

#include "vi_flow_internal.h"

#define RING 4096 /* impacts remembered for classification */
#define MAX_N 8   /* longest orbit period looked for, in forcing periods */

struct vi_orbit {
  const vi_model *m;
  int n, method;
  double rtol, atol, max_periods, tol, T;
  double *x0, *v0;
  vi_sim *sim;
  /* classification */
  int pn, pm, analysed;
  /* impact ring: t, then x, v per impact */
  int64_t nimp;
  double *rt, *rz;
  /* states at the last 3 MAX_N + 1 forcing-period ends (stroboscopic) */
  double *pz;
  /* P(1,1) results */
  double t_s, t_imp, vN, KEi, RE, IE, r_rec, closure, gmin;
  double *zfix, *x_imp, *v_imp, *vp_imp, *FE, *DE, *XE, *reff, *mre, *mim;
  double *scr, *dE; /* scratch: map output [2n], impact jumps [n] */
  double *block;
  int map_impacts;
  /* direct search: the transient's own classification, and whether the
   * analysed orbit came from the impact-phase scan */
  int direct, tn, tm, by_scan;
  char errmsg[VI_MSG_LEN];
};

int vi_orbit_create(const vi_model *model, vi_orbit **out)
{
  if (!out) return VI_ERR_ARG;
  *out = NULL;
  if (!model) return VI_ERR_ARG;
  if (!model->frozen) return VI_ERR_STATE;
  if (!(model->omega_f > 0.0)) return VI_ERR_FREQUENCY;
  if (model->ns > 1) return VI_ERR_UNSUPPORTED; /* WB 11-13: one stop */
  if (model->band) return VI_ERR_UNSUPPORTED; /* no modes: vi_band.c */
  vi_orbit *o = calloc(1, sizeof *o);
  if (!o) return VI_ERR_NOMEM;
  int n = model->n;
  o->block = calloc(23 * (size_t)n, sizeof(double));
  o->rt = malloc(sizeof(double) * RING);
  o->rz = malloc(sizeof(double) * RING * 2 * (size_t)n);
  o->pz = malloc(sizeof(double) * (3 * MAX_N + 1) * 2 * (size_t)n);
  int st = o->block && o->rt && o->rz && o->pz ? vi_sim_create(model, &o->sim)
                                               : VI_ERR_NOMEM;
  if (st) { /* vi_sim_create's own code, not a blanket NOMEM */
    vi_orbit_destroy(&o);
    return st;
  }
  double *p = o->block;
  o->x0 = p; p += n;
  o->v0 = p; p += n;
  o->zfix = p; p += 2 * n;
  o->x_imp = p; p += n;
  o->v_imp = p; p += n;
  o->vp_imp = p; p += n;
  o->FE = p; p += n;
  o->DE = p; p += n;
  o->XE = p; p += n;
  o->reff = p; p += n;
  o->mre = p; p += 2 * n;
  o->mim = p; p += 2 * n;
  o->scr = p; p += 2 * n;
  o->dE = p;
  o->m = model;
  o->n = n;
  o->method = vi_xflow_available(model) ? VI_METHOD_EXACT : VI_METHOD_ADAMS;
  o->rtol = 1e-11;
  o->atol = 1e-13;
  o->max_periods = 3000;
  o->tol = 1e-6;
  o->T = 2.0 * M_PI / model->omega_f;
  o->direct = 1;
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

int vi_orbit_set_monitor(vi_orbit *o, vi_monitor_fn fn, void *user)
{
  if (!o) return VI_ERR_ARG;
  int st = vi_sim_set_monitor(o->sim, fn, user, o->T);
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

/* ---- transient and classification ------------------------------------- */
static int record(const vi_event *ev, void *user)
{
  vi_orbit *o = user;
  if (ev->kind != VI_EVENT_IMPACT) return 0;
  int k = (int)(o->nimp % RING), n = o->n;
  o->rt[k] = ev->t;
  memcpy(o->rz + (size_t)k * 2 * n, ev->x, sizeof(double) * n);
  memcpy(o->rz + (size_t)k * 2 * n + n, ev->v_minus, sizeof(double) * n);
  o->nimp++;
  return 0;
}

/* Ring index of the first impact at or after time t (nimp if none). */
static int64_t first_after(const vi_orbit *o, double t)
{
  int64_t k = o->nimp;
  while (k > 0 && k > o->nimp - RING && o->rt[(k - 1) % RING] >= t) k--;
  return k;
}

/* Stroboscopic state at the end of forcing period k (kept for the last
 * 3 MAX_N + 1 periods). */
static double *strobe(const vi_orbit *o, int64_t k)
{
  return o->pz + (size_t)(k % (3 * MAX_N + 1)) * 2 * o->n;
}

/* Period n needs the states at the ends of periods k, k - n, k - 2n, k - 3n
 * to agree (a run of impact-free periods is not yet periodic: the motion
 * may still be creeping towards the stop), and the impacts of the three
 * windows between them to repeat, shifted by n T. */
static int repeats(const vi_orbit *o, int64_t kp, int n, int *m)
{
  double nT = n * o->T, t_now = kp * o->T, zscale = fabs(o->m->xs);
  const double *zk = strobe(o, kp);
  for (int i = 0; i < 2 * o->n; i++) zscale = fmax(zscale, fabs(zk[i]));
  for (int j = 1; j <= 3; j++)
    for (int i = 0; i < 2 * o->n; i++)
      if (fabs(strobe(o, kp - j * n)[i] - zk[i]) > o->tol * zscale) return 0;
  int64_t k0 = first_after(o, t_now - 3 * nT), k1 = first_after(o, t_now - 2 * nT),
          k2 = first_after(o, t_now - nT), k3 = o->nimp;
  if (k0 <= o->nimp - RING) return 0; /* the ring no longer holds them */
  int64_t c = k3 - k2;
  if (k2 - k1 != c || k1 - k0 != c) return 0;
  double scale = fabs(o->m->xs);
  for (int64_t k = k0; k < k3; k++)
    for (int i = 0; i < 2 * o->n; i++)
      scale = fmax(scale, fabs(o->rz[(size_t)(k % RING) * 2 * o->n + i]));
  for (int64_t k = k0; k + c < k3; k++) {
    size_t a = (size_t)(k % RING), b = (size_t)((k + c) % RING);
    if (fabs(o->rt[b] - o->rt[a] - nT) > o->tol * o->T) return 0;
    for (int i = 0; i < 2 * o->n; i++)
      if (fabs(o->rz[b * 2 * o->n + i] - o->rz[a * 2 * o->n + i]) > o->tol * scale)
        return 0;
  }
  *m = (int)c;
  return 1;
}

/* ---- shooting on the stroboscopic map --------------------------------- */
static int count_map(const vi_event *ev, void *user)
{
  vi_orbit *o = user;
  if (ev->kind == VI_EVENT_IMPACT) o->map_impacts++;
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
  vi_sim_get_state(o->sim, NULL, out, out + n);
  return VI_OK;
}

static int shoot_f(const gsl_vector *z, void *params, gsl_vector *f)
{
  vi_orbit *o = params;
  int n2 = 2 * o->n;
  double *out = o->scr;
  if (flow_map(o, z->data, out) || o->map_impacts != 1) return GSL_EDOM;
  for (int i = 0; i < n2; i++) gsl_vector_set(f, i, out[i] - gsl_vector_get(z, i));
  return GSL_SUCCESS;
}

static int refine(vi_orbit *o)
{
  int n2 = 2 * o->n, status = VI_OK;
  gsl_multiroot_function F = {shoot_f, (size_t)n2, o};
  gsl_vector *z = gsl_vector_alloc(n2);
  gsl_multiroot_fsolver *sv =
      gsl_multiroot_fsolver_alloc(gsl_multiroot_fsolver_hybrids, n2);
  if (!z || !sv) {
    status = vi_fail(o->errmsg, VI_ERR_NOMEM, "out of memory");
    goto done;
  }
  double scale = fabs(o->m->xs);
  for (int i = 0; i < n2; i++) {
    gsl_vector_set(z, i, o->zfix[i]);
    scale = fmax(scale, fabs(o->zfix[i]));
  }
  /* the map is exact to round-off (exact flow) or to the tolerance */
  double eps = (o->method == VI_METHOD_EXACT ? 1e-13 : 100.0 * o->rtol) * scale;
  if (gsl_multiroot_fsolver_set(sv, &F, z) != GSL_SUCCESS) {
    status = vi_fail(o->errmsg, VI_ERR_NOT_CONVERGED,
                     "shooting: the map left P(1,1) at the start");
    goto done;
  }
  int it, gs = GSL_CONTINUE;
  for (it = 0; it < 50 && gs == GSL_CONTINUE; it++) {
    if (gsl_multiroot_test_residual(sv->f, eps) == GSL_SUCCESS) {
      gs = GSL_SUCCESS;
      break;
    }
    if (gsl_multiroot_fsolver_iterate(sv)) break;
  }
  if (gsl_multiroot_test_residual(sv->f, eps) != GSL_SUCCESS) {
    status = vi_fail(o->errmsg, VI_ERR_NOT_CONVERGED,
                     "shooting did not converge: residual %.3g > %.3g after "
                     "%d iterations", gsl_blas_dnrm2(sv->f), eps, it);
    goto done;
  }
  for (int i = 0; i < n2; i++) o->zfix[i] = gsl_vector_get(sv->x, i);
done:
  gsl_multiroot_fsolver_free(sv);
  gsl_vector_free(z);
  return status;
}

/* Floquet multipliers: eigenvalues of D Phi_T by central differences. */
static int multipliers(vi_orbit *o)
{
  int n2 = 2 * o->n, st = VI_OK;
  gsl_matrix *J = gsl_matrix_alloc(n2, n2);
  gsl_vector_complex *ev = gsl_vector_complex_alloc(n2);
  gsl_eigen_nonsymm_workspace *w = gsl_eigen_nonsymm_alloc(n2);
  double *zp = malloc(sizeof(double) * 4 * n2);
  if (!J || !ev || !w || !zp) {
    st = vi_fail(o->errmsg, VI_ERR_NOMEM, "out of memory");
    goto done;
  }
  double *zm = zp + n2, *fp = zm + n2, *fm = fp + n2;
  for (int j = 0; j < n2; j++) {
    double h = 1e-6 * fmax(fabs(o->zfix[j]), fabs(o->m->xs));
    memcpy(zp, o->zfix, sizeof(double) * n2);
    memcpy(zm, o->zfix, sizeof(double) * n2);
    zp[j] += h;
    zm[j] -= h;
    if ((st = flow_map(o, zp, fp)) || (st = flow_map(o, zm, fm))) goto done;
    for (int i = 0; i < n2; i++) gsl_matrix_set(J, i, j, (fp[i] - fm[i]) / (2 * h));
  }
  if (gsl_eigen_nonsymm(J, ev, w) != GSL_SUCCESS) {
    st = vi_fail(o->errmsg, VI_ERR_NOT_CONVERGED, "eigenvalues of the map");
    goto done;
  }
  for (int i = 0; i < n2; i++) {
    o->mre[i] = GSL_REAL(gsl_vector_complex_get(ev, i));
    o->mim[i] = GSL_IMAG(gsl_vector_complex_get(ev, i));
  }
done:
  free(zp);
  gsl_eigen_nonsymm_free(w);
  gsl_vector_complex_free(ev);
  gsl_matrix_free(J);
  return st;
}

typedef struct bal_ctx { vi_orbit *o; int seen; } bal_ctx;

static int bal_event(const vi_event *ev, void *user)
{
  bal_ctx *c = user;
  vi_orbit *o = c->o;
  if (ev->kind != VI_EVENT_IMPACT) return 0;
  c->seen++;
  o->t_imp = ev->t;
  o->vN = ev->vn;
  o->IE = ev->ie;
  memcpy(o->x_imp, ev->x, sizeof(double) * o->n);
  memcpy(o->v_imp, ev->v_minus, sizeof(double) * o->n);
  memcpy(o->vp_imp, ev->v_plus, sizeof(double) * o->n);
  return 0;
}

static int bal_sample(double t, int n, const double *x, const double *v, void *u)
{
  (void)t; (void)v;
  vi_orbit *o = u;
  o->gmin = fmin(o->gmin, vi_dot(n, o->m->w, x) - o->m->xs);
  return 0;
}

/* One period from the fixed point with the ledger: WB 11-13. */
static int balance(vi_orbit *o)
{
  const vi_model *m = o->m;
  int n = o->n, st;
  bal_ctx c = {o, 0};
  double *dE = o->dE;
  o->gmin = HUGE_VAL;
  if ((st = vi_sim_enable_ledger(o->sim, 1)) ||
      (st = vi_sim_set_event_callback(o->sim, bal_event, &c)) ||
      (st = vi_sim_set_initial(o->sim, o->t_s, o->zfix, o->zfix + n)) ||
      (st = vi_sim_set_sampling(o->sim, o->T / 4096, bal_sample, o)) ||
      (st = vi_sim_run(o->sim, o->t_s + o->T)) ||
      (st = vi_sim_get_ledger(o->sim, NULL, o->FE, o->DE, o->XE, NULL, dE, NULL)))
    vi_fail(o->errmsg, st < 0 ? st : VI_ERR_STATE, "balance run: %s",
            vi_sim_errmsg(o->sim));
  /* whatever happened, the sim keeps no pointer to this frame's context
   * and no ledger or sampling it did not have before */
  vi_sim_set_event_callback(o->sim, NULL, NULL);
  vi_sim_set_sampling(o->sim, 0.0, NULL, NULL);
  vi_sim_enable_ledger(o->sim, 0);
  if (st) return st < 0 ? st : VI_ERR_STATE;
  if (c.seen != 1)
    return vi_fail(o->errmsg, VI_ERR_NOT_CONVERGED,
                   "balance run: %d impacts in the period of a P(1,1) orbit",
                   c.seen);
  o->RE = 0.0;
  for (int j = 0; j < n; j++) o->RE += o->FE[j] - o->DE[j] - o->XE[j];
  o->KEi = 0.5 * o->vN * o->vN / m->wMw;                  /* WB 12 */
  double x = 1.0 - o->RE / o->KEi;
  o->r_rec = x >= 0.0 ? sqrt(x) : NAN;                    /* WB 13 */
  o->closure = fabs(o->RE - o->IE) / o->KEi;              /* WB 11 */
  for (int j = 0; j < n; j++) {
    double qm = 0.0, qp = 0.0;
    for (int i = 0; i < n; i++) {
      qm += m->PsiTM[j + (size_t)i * n] * o->v_imp[i];
      qp += m->PsiTM[j + (size_t)i * n] * o->vp_imp[i];
    }
    o->reff[j] = qm != 0.0 ? -qp / qm : NAN;
  }
  return VI_OK;
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
         *im = re + 2 * n, *vp = im + 2 * n, rho_best = 1.0;
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
  o->pn = o->pm = 0;
  o->tn = o->tm = 0;
  o->by_scan = 0;
  o->nimp = 0;
  if ((st = vi_sim_set_initial(o->sim, 0.0, o->x0, o->v0)) ||
      (st = vi_sim_set_event_callback(o->sim, record, o)))
    return vi_fail(o->errmsg, st, "%s", vi_sim_errmsg(o->sim));
  int64_t kmax = (int64_t)o->max_periods;
  for (int64_t k = 1; k <= kmax && !o->pn; k++) {
    if ((st = vi_sim_run(o->sim, k * o->T)) == VI_STOPPED)
      return vi_fail(o->errmsg, st, "stopped by the monitor at t = %g",
                     k * o->T);
    if (st)
      return vi_fail(o->errmsg, st, "transient: %s", vi_sim_errmsg(o->sim));
    double *z = strobe(o, k);
    vi_sim_get_state(o->sim, NULL, z, z + n);
    for (int p = 1; p <= MAX_N && k >= 3 * p + 16; p++) {
      int mm;
      if (repeats(o, k, p, &mm)) {
        o->pn = p;
        o->pm = mm;
        break;
      }
    }
  }
  if (!o->pn) { /* not periodic: report the recent impact rate */
    double tn = kmax * o->T;
    o->pm = (int)lround((o->nimp - first_after(o, tn - 8 * o->T)) / 8.0);
  }
  o->tn = o->pn;
  o->tm = o->pm;
  if (o->pn != 1 || o->pm != 1) {
    /* the transient went elsewhere; a stable P(1,1) orbit may still
     * exist (another attractor): look for it directly */
    if (!o->direct || !vi_xflow_available(o->m)) return VI_OK;
    int got = direct_p11(o);
    if (got < 0)
      return vi_fail(o->errmsg, got, "direct P(1,1) search: %s",
                     vi_strerror(got));
    if (!got) return VI_OK;
    o->pn = o->pm = 1;
    o->by_scan = 1;
    if ((st = vi_sim_set_event_callback(o->sim, count_map, o)))
      return vi_fail(o->errmsg, st, "%s", vi_sim_errmsg(o->sim));
  } else {
    /* P(1,1): section half a period after the last impact, away from it */
    vi_sim_get_state(o->sim, &t, NULL, NULL);
    double ti = o->rt[(o->nimp - 1) % RING];
    o->t_s = ti + 0.5 * o->T;
    while (o->t_s <= t) o->t_s += o->T;
    if ((st = vi_sim_set_event_callback(o->sim, count_map, o)) ||
        (st = vi_sim_run(o->sim, o->t_s)))
      return vi_fail(o->errmsg, st < 0 ? st : VI_ERR_STATE, "%s",
                     vi_sim_errmsg(o->sim));
    vi_sim_get_state(o->sim, NULL, o->zfix, o->zfix + n);
  }
  if ((st = refine(o)) || (st = balance(o))) return st;
  /* multipliers: exact (saltation matrices, vi_orbit_pnm.c) where the
   * closed-form flow exists, central differences of the map otherwise */
  if (vi_xflow_available(o->m)) {
    st = vi_orbit_pnm_multipliers(o->m, 1, 1, &o->t_imp, o->x_imp, o->v_imp,
                                  n, o->mre, o->mim);
    if (st) return vi_fail(o->errmsg, st, "multipliers: %s", vi_strerror(st));
  } else if ((st = multipliers(o))) {
    return st;
  }
  o->analysed = 1;
  return VI_OK;
}

/* ---- getters ------------------------------------------------------------ */
int vi_orbit_classify(const vi_orbit *o, int *n, int *m)
{
  if (!o) return VI_ERR_ARG;
  if (n) *n = o->pn;
  if (m) *m = o->pm;
  return VI_OK;
}

#define NEED_P11(o) \
  do { if (!(o)) return VI_ERR_ARG; if (!(o)->analysed) return VI_ERR_STATE; } while (0)

int vi_orbit_balance(const vi_orbit *o, double *period, double *phase,
                     double *vN, double *KE_i, double *RE, double *IE,
                     double *r_rec, double *closure)
{
  NEED_P11(o);
  if (period) *period = o->T;
  if (phase) *phase = fmod(o->t_imp, o->T);
  if (vN) *vN = o->vN;
  if (KE_i) *KE_i = o->KEi;
  if (RE) *RE = o->RE;
  if (IE) *IE = o->IE;
  if (r_rec) *r_rec = o->r_rec;
  if (closure) *closure = o->closure;
  return VI_OK;
}

int vi_orbit_modal_balance(const vi_orbit *o, double *FE, double *DE,
                           double *XE, double *r_eff)
{
  NEED_P11(o);
  size_t b = sizeof(double) * o->n;
  if (FE) memcpy(FE, o->FE, b);
  if (DE) memcpy(DE, o->DE, b);
  if (XE) memcpy(XE, o->XE, b);
  if (r_eff) memcpy(r_eff, o->reff, b);
  return VI_OK;
}

int vi_orbit_impact_state(const vi_orbit *o, double *t, double *x, double *v)
{
  NEED_P11(o);
  if (t) *t = o->t_imp;
  if (x) memcpy(x, o->x_imp, sizeof(double) * o->n);
  if (v) memcpy(v, o->v_imp, sizeof(double) * o->n);
  return VI_OK;
}

int vi_orbit_multipliers(const vi_orbit *o, double *re, double *im)
{
  NEED_P11(o);
  if (re) memcpy(re, o->mre, sizeof(double) * 2 * o->n);
  if (im) memcpy(im, o->mim, sizeof(double) * 2 * o->n);
  return VI_OK;
}

int vi_orbit_min_gap(const vi_orbit *o, double *gmin)
{
  NEED_P11(o);
  if (gmin) *gmin = o->gmin;
  return VI_OK;
}

int vi_orbit_reduced_restitution(const vi_orbit *o, const int *modes, int k,
                                 double *r_S)
{
  NEED_P11(o);
  if (!modes || !r_S || k < 1 || k > o->n) return VI_ERR_ARG;
  const vi_model *m = o->m;
  int n = o->n;
  double pq = 0.0, pp = 0.0, re = 0.0;
  *r_S = NAN;
  for (int a = 0; a < k; a++) {
    int j = modes[a];
    if (j < 0 || j >= n) return VI_ERR_ARG; /* a getter: o stays const */
    double qd = 0.0;
    for (int i = 0; i < n; i++) qd += m->PsiTM[j + (size_t)i * n] * o->v_imp[i];
    pq += m->psi[j] * qd;
    pp += m->psi[j] * m->psi[j];
    re += o->FE[j] - o->DE[j] - o->XE[j];
  }
  double ke = 0.5 * pq * pq / pp; /* KE_S */
  if (!(pp > 0.0) || !(re >= 0.0) || re > ke) return VI_ERR_ARG;
  *r_S = sqrt(1.0 - re / ke);
  return VI_OK;
}

int vi_model_create_reduced(const vi_model *full, const int *modes, int k,
                            double r, vi_model **out)
{
  if (!out) return VI_ERR_ARG;
  *out = NULL;
  if (!full || !modes || k < 1 || k > full->n) return VI_ERR_ARG;
  if (!full->frozen) return VI_ERR_STATE;
  if (full->ns > 1) return VI_ERR_UNSUPPORTED; /* one stop is reduced */
  if (full->band) return VI_ERR_UNSUPPORTED; /* no modes: vi_band.c */
  int n = full->n, st;
  double *buf = calloc(4 * (size_t)k * k + 5 * (size_t)k, sizeof(double));
  if (!buf) return VI_ERR_NOMEM;
  double *M = buf, *K = M + k * k, *C = K + k * k, *w = C + k * k;
  double *a = w + k, *b = a + k, *f0 = b + k;
  for (int p = 0; p < k; p++) {
    int j = modes[p];
    if (j < 0 || j >= n) { free(buf); return VI_ERR_ARG; }
    M[p + p * k] = 1.0;
    K[p + p * k] = full->lambda[j];
    for (int q = 0; q < k; q++) C[p + q * k] = full->D[j + (size_t)modes[q] * n];
    w[p] = full->psi[j];
    a[p] = full->Fa[j];
    b[p] = full->Fb[j];
    f0[p] = full->F0[j];
  }
  vi_model *m = NULL;
  st = vi_model_create(k, &m);
  if (!st) st = vi_model_set_mass(m, M, k);
  if (!st) st = vi_model_set_stiffness(m, K, k);
  if (!st) st = vi_model_set_damping(m, C, k);
  if (!st) st = vi_model_set_forcing(m, full->omega_f, a, b, f0);
  if (!st) st = vi_model_set_stop(m, w, full->xs, r);
  if (!st) st = vi_model_setup(m);
  free(buf);
  if (st) vi_model_destroy(&m);
  *out = m;
  return st;
}
