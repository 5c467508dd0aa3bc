/* vi_sim_state.c - what every part of the simulator shares
 * (vi_sim_state.h): the sticking set and its projection, the refusal of
 * calls from inside a run, and the root bracketing of the backends. */
#include <float.h>
#include <string.h>

#include "vi_sim_state.h"

int vi_sim_busy(vi_sim *s, const char *name)
{
  return vi_fail(s->errmsg, VI_ERR_STATE, "%s called from inside a callback "
                 "of this sim's own run: refused (only the queries listed in "
                 "vi_sim.h may be called there)", name);
}

/* a - M^-1 W_L G_LL^-1 W_L^T a for the stops list [cnt], L the Cholesky
 * factor of their Delassus block G_LL: what remains of a with w_k.a = 0 on
 * each (lam [cnt], may be NULL: the multipliers G_LL^-1 W_L^T a). */
void vi_sim_project(const vi_sim *s, int cnt, const int *list,
                    const double *L, double *a, double *lam)
{
  const vi_model *m = s->m;
  int n = s->n;
  double b[VI_CONTACT_MAX];
  for (int i = 0; i < cnt; i++) b[i] = vi_dot(n, vi_stop_w(m, list[i]), a);
  vi_small_solve(cnt, L, b);
  for (int i = 0; i < cnt; i++) {
    const double *mw = vi_stop_minvw(m, list[i]);
    for (int j = 0; j < n; j++) a[j] -= b[i] * mw[j];
    if (lam) lam[i] = b[i];
  }
}

/* The Cholesky factor of the Delassus block G_LL of the stops list [cnt]:
 * 0, or -1 if their stop vectors are dependent. */
int vi_sim_stick_factor(const vi_model *m, int cnt, const int *list,
                        double *L)
{
  for (int i = 0; i < cnt; i++)
    for (int j = 0; j < cnt; j++)
      L[i + j * cnt] = m->G[list[i] + (size_t)list[j] * m->ns];
  return vi_small_cholesky(cnt, L);
}

void vi_sim_constrain_set(const vi_sim *s, double *a, double *lam)
{
  vi_sim_project(s, s->nstick, s->stick_k, s->stick_L, a, lam);
}

/* Make the stops list [cnt] the sticking set: the projection of the
 * right-hand side needs the factor of their Delassus block. */
int vi_sim_set_sticking(vi_sim *s, const int *list, int cnt)
{
  for (int i = 0; i < cnt; i++) s->stick_k[i] = list[i];
  s->nstick = cnt;
  s->sticking = cnt > 0;
  if (vi_sim_stick_factor(s->m, cnt, list, s->stick_L)) {
    s->nstick = 0;
    s->sticking = 0;
    return vi_fail(s->errmsg, VI_ERR_UNSUPPORTED, "sticking on %d stops at "
                   "once at t = %.17g, whose stop vectors are dependent "
                   "(Delassus block singular)", cnt, s->t);
  }
  return VI_OK;
}

int vi_sim_in_stick_set(const vi_sim *s, int k)
{
  for (int i = 0; i < s->nstick; i++)
    if (s->stick_k[i] == k) return 1;
  return 0;
}

/* ---- root bracketing shared by the backends ----------------------------- */
int vi_sim_bracket(vi_sim *s, double (*f)(double, void *), void *params,
                   double lo, double hi, double *root)
{
  double flo = f(lo, params), fhi = f(hi, params);
  if (fhi == 0.0) { *root = hi; return VI_OK; }
  if (flo == 0.0) { *root = lo; return VI_OK; }
  if ((flo < 0.0) == (fhi < 0.0) || !isfinite(flo) || !isfinite(fhi))
    return vi_fail(s->errmsg, VI_ERR_ROOT,
                   "event not bracketed in [%.17g, %.17g]: f = %g, %g", lo, hi,
                   flo, fhi);
  gsl_function F = {f, params};
  gsl_root_fsolver_set(s->brent, &F, lo, hi);
  for (int it = 0; it < 200; it++) {
    if (gsl_root_fsolver_iterate(s->brent) != 0) break;
    double a = gsl_root_fsolver_x_lower(s->brent);
    double b = gsl_root_fsolver_x_upper(s->brent);
    if (b - a <= 4.0 * DBL_EPSILON * fmax(fabs(a), fabs(b)) + DBL_MIN) {
      *root = gsl_root_fsolver_root(s->brent);
      return VI_OK;
    }
  }
  *root = gsl_root_fsolver_root(s->brent);
  return VI_OK; /* Brent's bracket still holds the root: report its best */
}

