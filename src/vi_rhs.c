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
  int width = 2 * (2 * bw + 1);
  if (width > 2 * n) width = 2 * n;
  r->n = n;
  r->width = width;
  r->R = calloc((size_t)n * (size_t)width, sizeof(double));
  r->lo = malloc(sizeof(int) * (size_t)n);
  r->acc = malloc(sizeof(double) * (size_t)n);
  if (!r->R || !r->lo || !r->acc) {
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
  r->cc[k] = *c = cos(r->W * t);
  r->sc[k] = *sn = sin(r->W * t);
}

void vi_rhs_rate(vi_sim *s, vi_rhs *r, double t, const double *z, double *zd)
{
  int n = r->n, width = r->width;
  double c = 1.0, sn = 0.0;
  if (r->harmonic) trig(r, t, &c, &sn);
  /* locals: acc may not alias the coefficients, so they stay in registers */
  double *restrict acc = r->acc;
  const double *restrict R = r->R;
  const double *restrict fa = r->fa, *restrict fb = r->fb, *restrict f0 = r->f0;
  const int *restrict lo = r->lo;
  if (width == 6) { /* a chain: tridiagonal M^-1 K, M^-1 C */
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
  for (int i = 0; i < n; i++) {
    zd[2 * (size_t)i] = z[2 * (size_t)i + 1];
    zd[2 * (size_t)i + 1] = acc[i];
  }
}
