/* vi_identify_fit.c - the trust-region fit from one start (GSL
 * gsl_multifit_nlinear, Levenberg-Marquardt), with parameters held for a
 * profile, and the uncertainty at the minimum it ends on. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_multifit_nlinear.h>

#include "vi_identify_internal.h"

/* Parameter j held at v (j < 0: all free again); the Jacobian's columns
 * are renumbered over the free ones. */
void vi_id_hold(vi_identify *id, int j, double v)
{
  for (int q = 0; q < id->np; q++)
    if (j < 0 || q == j) {
      id->col[q] = j < 0 ? 0 : -1;
      id->hval[q] = v;
    }
  id->nfree = 0;
  for (int q = 0; q < id->np; q++)
    if (id->col[q] >= 0) id->col[q] = id->nfree++;
}

/* The fit from the free values of p and the shift t0 (the model and its
 * orbit at p current: vi_id_ensure or the seeding).  *pout [np], *t0out,
 * *ssr (the whole cost), *iters, *conv.  VI_OK, or a code with the
 * message (VI_CANCELLED, VI_ERR_NOT_CONVERGED, VI_ERR_NOMEM). */
int vi_id_lm(vi_identify *id, const double *p, double t0, double *pout,
             double *t0out, double *ssr, int *iters, int *conv)
{
  int np = id->np, P = id->nfree + id->fit_shift, nr = vi_id_nres(id), st;
  gsl_multifit_nlinear_fdf fdf;
  gsl_multifit_nlinear_parameters par = gsl_multifit_nlinear_default_parameters();
  par.trs = gsl_multifit_nlinear_trs_lm;
  fdf.f = vi_id_res_f;
  fdf.df = vi_id_res_df;
  fdf.fvv = NULL;
  fdf.n = (size_t)nr;
  fdf.p = (size_t)P;
  fdf.params = id;
  if (P == 0) { /* nothing free: the cost at p */
    gsl_vector *f = gsl_vector_alloc(nr), *th = gsl_vector_alloc(1);
    if (!f || !th) {
      gsl_vector_free(f);
      gsl_vector_free(th);
      return vi_fail(id->errmsg, VI_ERR_NOMEM, "out of memory");
    }
    memcpy(pout, p, sizeof(double) * np);
    *t0out = vi_id_shift0(id);
    st = vi_id_ensure(id, pout);
    if (!st) vi_id_res_f(th, id, f);
    *ssr = 0.0;
    for (int i = 0; !st && i < nr; i++) *ssr += gsl_vector_get(f, i) * gsl_vector_get(f, i);
    *iters = 0;
    *conv = 1;
    gsl_vector_free(f);
    gsl_vector_free(th);
    return st ? VI_ERR_NOT_CONVERGED : VI_OK;
  }
  gsl_multifit_nlinear_workspace *w =
      gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &par, nr, P);
  gsl_vector *x0 = gsl_vector_alloc(P);
  if (!w || !x0) {
    gsl_multifit_nlinear_free(w);
    gsl_vector_free(x0);
    return vi_fail(id->errmsg, VI_ERR_NOMEM, "out of memory");
  }
  for (int j = 0; j < np; j++)
    if (id->col[j] >= 0) gsl_vector_set(x0, id->col[j], p[j]);
  if (id->fit_shift) gsl_vector_set(x0, id->nfree, t0);
  int info = 0;
  st = gsl_multifit_nlinear_init(x0, &fdf, w);
  if (!st) st = gsl_multifit_nlinear_driver(200, 1e-10, 1e-10, 0.0, NULL, NULL,
                                            &info, w);
  *iters = (int)gsl_multifit_nlinear_niter(w);
  if (id->cancel_hit) {
    gsl_multifit_nlinear_free(w);
    gsl_vector_free(x0);
    return vi_fail(id->errmsg, VI_CANCELLED, "cancelled after %d least-squares "
                   "iterations", *iters);
  }
  /* GSL_ENOPROG: no step lowers the cost any more (the optimum to round-off) */
  *conv = st == GSL_SUCCESS || st == GSL_ENOPROG;
  if (st && st != GSL_ENOPROG && st != GSL_EMAXITER) {
    int code = st == GSL_ENOMEM ? VI_ERR_NOMEM : VI_ERR_NOT_CONVERGED;
    vi_fail(id->errmsg, code, "least squares failed: %s", gsl_strerror(st));
    gsl_multifit_nlinear_free(w);
    gsl_vector_free(x0);
    return code;
  }
  const gsl_vector *xs = gsl_multifit_nlinear_position(w);
  vi_id_split(id, xs, pout, t0out);
  const gsl_vector *f = gsl_multifit_nlinear_residual(w);
  *ssr = 0.0;
  for (int i = 0; i < nr; i++) *ssr += gsl_vector_get(f, i) * gsl_vector_get(f, i);
  gsl_multifit_nlinear_free(w);
  gsl_vector_free(x0);
  return VI_OK;
}

/* The fit of every parameter from p, t0 and what its minimum holds into
 * *s (the handle's result fields too: the best's are set last). */
int vi_id_local(vi_identify *id, const double *p, double t0, vi_id_sol *s)
{
  int np = id->np, P = np + id->fit_shift, nr = vi_id_nres(id), st;
  double pp[MAXP] = {0};
  vi_id_hold(id, -1, NAN);
  st = vi_id_lm(id, p, t0, pp, &id->t0, &s->ssr, &id->iters, &id->conv);
  if (st) return st;
  memcpy(id->p, pp, sizeof(double) * np);
  /* the residual and Jacobian at the optimum, evaluated afresh */
  gsl_vector *f = gsl_vector_alloc(nr), *xs = gsl_vector_alloc(P);
  gsl_matrix *J = gsl_matrix_alloc(nr, P);
  st = f && J && xs ? VI_OK : VI_ERR_NOMEM;
  for (int j = 0; !st && j < np; j++) gsl_vector_set(xs, j, pp[j]);
  if (!st && id->fit_shift) gsl_vector_set(xs, np, id->t0);
  if (!st && vi_id_ensure(id, pp)) st = VI_ERR_NOT_CONVERGED;
  if (!st) vi_id_res_f(xs, id, f);
  if (!st && vi_id_res_df(xs, id, J)) st = VI_ERR_NOT_CONVERGED;
  if (!st) {
    double ssr = 0.0, ssx = 0.0;
    for (int i = 0; i < nr; i++) ssr += gsl_vector_get(f, i) * gsl_vector_get(f, i);
    for (int i = 0; i < id->ns; i++) ssx += gsl_vector_get(f, i) * gsl_vector_get(f, i);
    id->rms = sqrt(ssx / id->ns);
    s->ssr = ssr;
    st = vi_id_uncertainty(id, J, ssr);
  }
  gsl_vector_free(f);
  gsl_vector_free(xs);
  gsl_matrix_free(J);
  if (st)
    return vi_fail(id->errmsg, st, "no uncertainty at the optimum: %s",
                   vi_strerror(st));
  size_t b = sizeof(double) * np;
  memcpy(s->p, id->p, b);
  memcpy(s->se, id->se, b);
  memcpy(s->l95, id->l95, b);
  memcpy(s->h95, id->h95, b);
  memcpy(s->flags, id->flags, sizeof(int) * np);
  memcpy(s->corr, id->corr, b * np);
  for (int j = 0; j < np; j++) {
    s->pl95[j] = s->ph95[j] = NAN;
    s->pflags[j] = 0;
  }
  s->t0 = id->t0;
  s->t0se = id->t0se;
  s->rms = id->rms;
  s->rcond = id->rcond;
  s->conv = id->conv;
  s->iters = id->iters;
  s->n = id->o.n;
  s->m = id->o.m;
  vi_id_orb_copy(&s->o, &id->o, id->N);
  return VI_OK;
}
