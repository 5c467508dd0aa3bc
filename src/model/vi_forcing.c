/* vi_forcing.c - the harmonic forcing and its derivatives (vi_forcing.h). */
#include <math.h>

#include "vi_forcing.h"
#include "vi_model_internal.h"

void vi_forcing_vectors(const vi_model *m, int form, const double **A,
                        const double **B, const double **C)
{
  if (form == VI_FORCING_MINV) {
    *A = m->Minv_a;
    *B = m->Minv_b;
    *C = m->Minv_f0;
  } else if (form == VI_FORCING_MODAL) {
    *A = m->Fa;
    *B = m->Fb;
    *C = m->F0;
  } else {
    *A = m->a;
    *B = m->b;
    *C = m->f0;
  }
}

int vi_forcing_harmonic(const vi_model *m)
{
  for (int i = 0; i < m->n; i++)
    if (m->a[i] != 0.0 || m->b[i] != 0.0) return 1;
  return 0;
}

void vi_phase_cache_init(vi_phase_cache *pc, double W)
{
  pc->W = W;
  for (int k = 0; k < VI_PHASE_CACHE; k++) pc->tc[k] = NAN;
  pc->ta = NAN; /* no anchor yet: the first evaluation makes one */
  pc->ca = 1.0;
  pc->sa = 0.0;
  pc->next = 0;
}

/* From the cache; else, within a quarter radian of the anchor t_a, by the
 * angle addition theorem with sin and cos of x = W (t - t_a) from their
 * Taylor series (|x| <= 1/4: the terms beyond x^15 are below 1e-19; t - t_a
 * is exact for nearby t); else by vi_phase_at, which becomes the anchor.
 * Either way the result is within a few ulp of cos and sin of W t: about
 * the rounding of W t itself. */
vi_phase vi_phase_cached(vi_phase_cache *pc, double t)
{
  vi_phase p = {pc->W, 1.0, 0.0};
  for (int k = 0; k < VI_PHASE_CACHE; k++)
    if (pc->tc[k] == t) {
      p.c = pc->cc[k];
      p.s = pc->sc[k];
      return p;
    }
  int k = pc->next;
  pc->next = k + 1 == VI_PHASE_CACHE ? 0 : k + 1;
  pc->tc[k] = t;
  double x = pc->W * (t - pc->ta);
  if (fabs(x) <= 0.25) {
    double x2 = x * x;
    double sx = x * (1.0 + x2 * (-1.0 / 6 + x2 * (1.0 / 120 + x2 * (-1.0 / 5040 +
                x2 * (1.0 / 362880 + x2 * (-1.0 / 39916800 + x2 * (1.0 / 6227020800.0 +
                x2 * (-1.0 / 1307674368000.0))))))));
    double cx = 1.0 + x2 * (-0.5 + x2 * (1.0 / 24 + x2 * (-1.0 / 720 + x2 * (1.0 / 40320 +
                x2 * (-1.0 / 3628800 + x2 * (1.0 / 479001600 + x2 * (-1.0 / 87178291200.0 +
                x2 * (1.0 / 20922789888000.0))))))));
    pc->cc[k] = p.c = pc->ca * cx - pc->sa * sx;
    pc->sc[k] = p.s = pc->sa * cx + pc->ca * sx;
    return p;
  }
  p = vi_phase_at(pc->W, t);
  pc->cc[k] = p.c;
  pc->sc[k] = p.s;
  pc->ta = t;
  pc->ca = p.c;
  pc->sa = p.s;
  return p;
}
