/* vi_rhs.c - the SUNDIALS backends' right-hand side.
 *
 * The generic acceleration (vi_sim_accel) walks the dense column-major
 * M^-1 K and M^-1 C inside the band with a varying inner trip count, and
 * calls sincos at every evaluation.  Here each row of the band is stored
 * contiguously, already interleaved as the state is (x_j, v_j), so a row is
 * a fixed-length dot product with a contiguous slice of z; edge rows read a
 * slice shifted inwards, with zero coefficients where the band ends. */
#include <stdlib.h>
#include <string.h>

#include "vi_rhs.h"

int vi_rhs_create(const vi_sim *s, vi_rhs **out)
{
  const vi_model *m = s->m;
  int n = m->n, bw = m->bw;
  *out = NULL;
  vi_rhs *r = calloc(1, sizeof *r);
  if (!r) return VI_ERR_NOMEM;
  r->n = n;
  r->acc = malloc(sizeof(double) * (size_t)n);
  if (!r->acc) {
    vi_rhs_destroy(&r);
    return VI_ERR_NOMEM;
  }
  int width = 2 * (2 * bw + 1);
  if (width > 2 * n) width = 2 * n;
  /* band storage has no dense M^-1 K (vi_band.c evaluates it in O(n kd));
   * a wide band gains nothing from packing but the memory of a third copy:
   * both take vi_sim_accel */
  if (m->band || width > VI_RHS_WIDTH_MAX) {
    *out = r;
    return VI_OK;
  }
  r->width = width;
  r->R = calloc((size_t)n * (size_t)width, sizeof(double));
  r->lo = malloc(sizeof(int) * (size_t)n);
  if (!r->R || !r->lo) {
    vi_rhs_destroy(&r);
    return VI_ERR_NOMEM;
  }
  for (int i = 0; i < n; i++) {
    int lo = 2 * (i - bw);
    if (lo > 2 * n - width) lo = 2 * n - width;
    if (lo < 0) lo = 0;
    r->lo[i] = lo;
    double *row = r->R + (size_t)i * (size_t)width;
    for (int j = 0; j < n; j++) {
      int q = 2 * j - lo;
      if (q < 0 || q >= width || j < i - bw || j > i + bw) continue;
      size_t ij = (size_t)i + (size_t)j * (size_t)n;
      row[q] = -m->MinvK[ij];
      row[q + 1] = -m->MinvC[ij];
    }
  }
  r->fa = m->Minv_a;
  r->fb = m->Minv_b;
  r->f0 = m->Minv_f0;
  r->harmonic = s->harmonic;
  r->W = m->omega_f;
  for (int k = 0; k < VI_RHS_TRIG; k++) r->tc[k] = NAN;
  r->ta = NAN; /* no anchor yet: the first evaluation makes one */
  *out = r;
  return VI_OK;
}

void vi_rhs_destroy(vi_rhs **r)
{
  if (!r || !*r) return;
  free((*r)->R);
  free((*r)->lo);
  free((*r)->acc);
  free(*r);
  *r = NULL;
}

/* cos(W t), sin(W t): from the cache; else, within a quarter radian of the
 * last point evaluated by the library (the anchor, t_a), by the angle
 * addition theorem with sin and cos of x = W (t - t_a) from their Taylor
 * series (|x| <= 1/4: the terms beyond x^15 are below 1e-19; t - t_a is
 * exact for nearby t); else by sin and cos, which becomes the anchor.
 * Either way the result is within a few ulp of cos and sin of W t: about
 * the rounding of W t itself. */
static void trig(vi_rhs *r, double t, double *c, double *sn)
{
  for (int k = 0; k < VI_RHS_TRIG; k++)
    if (r->tc[k] == t) {
      *c = r->cc[k];
      *sn = r->sc[k];
      return;
    }
  int k = r->next;
  r->next = k + 1 == VI_RHS_TRIG ? 0 : k + 1;
  r->tc[k] = t;
  double x = r->W * (t - r->ta);
  if (fabs(x) <= 0.25) {
    double x2 = x * x;
    double sx = x * (1.0 + x2 * (-1.0 / 6 + x2 * (1.0 / 120 + x2 * (-1.0 / 5040 +
                x2 * (1.0 / 362880 + x2 * (-1.0 / 39916800 + x2 * (1.0 / 6227020800.0 +
                x2 * (-1.0 / 1307674368000.0))))))));
    double cx = 1.0 + x2 * (-0.5 + x2 * (1.0 / 24 + x2 * (-1.0 / 720 + x2 * (1.0 / 40320 +
                x2 * (-1.0 / 3628800 + x2 * (1.0 / 479001600 + x2 * (-1.0 / 87178291200.0 +
                x2 * (1.0 / 20922789888000.0))))))));
    r->cc[k] = *c = r->ca * cx - r->sa * sx;
    r->sc[k] = *sn = r->sa * cx + r->ca * sx;
    return;
  }
  r->cc[k] = *c = cos(r->W * t);
  r->sc[k] = *sn = sin(r->W * t);
  r->ta = t;
  r->ca = *c;
  r->sa = *sn;
}

void vi_rhs_rate(vi_sim *s, vi_rhs *r, double t, const double *z, double *zd)
{
  int n = r->n, width = r->width;
  double *restrict acc = r->acc;
  if (!r->R) {
    vi_sim_accel(s, t, z, s->sticking, acc);
  } else {
    double c = 1.0, sn = 0.0;
    if (r->harmonic) trig(r, t, &c, &sn);
    /* locals: acc may not alias the coefficients, so they stay in registers */
    const double *restrict R = r->R;
    const double *restrict fa = r->fa, *restrict fb = r->fb, *restrict f0 = r->f0;
    const int *restrict lo = r->lo;
    if (width == 4) { /* two degrees of freedom, dense */
      for (int i = 0; i < n; i++) {
        const double *row = R + 4 * (size_t)i;
        acc[i] = fa[i] * c + fb[i] * sn + f0[i] + row[0] * z[0] + row[1] * z[1] +
                 row[2] * z[2] + row[3] * z[3];
      }
    } else if (width == 6) { /* a chain: tridiagonal M^-1 K, M^-1 C */
      for (int i = 0; i < n; i++) {
        const double *row = R + 6 * (size_t)i, *zi = z + lo[i];
        acc[i] = fa[i] * c + fb[i] * sn + f0[i] + row[0] * zi[0] +
                 row[1] * zi[1] + row[2] * zi[2] + row[3] * zi[3] +
                 row[4] * zi[4] + row[5] * zi[5];
      }
    } else {
      for (int i = 0; i < n; i++) {
        const double *row = R + (size_t)width * (size_t)i, *zi = z + lo[i];
        double a = fa[i] * c + fb[i] * sn + f0[i];
        for (int q = 0; q < width; q++) a += row[q] * zi[q];
        acc[i] = a;
      }
    }
    if (s->nforces) vi_force_add_accel(s, t, z, acc);
    if (s->sticking) vi_sim_constrain(s, acc, NULL);
  }
  for (int i = 0; i < n; i++) {
    zd[2 * (size_t)i] = z[2 * (size_t)i + 1];
    zd[2 * (size_t)i + 1] = acc[i];
  }
}
