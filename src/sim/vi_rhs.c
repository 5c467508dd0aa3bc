/* vi_rhs.c - the SUNDIALS backends' right-hand side, and the rates of the
 * free acceleration.
 *
 * The generic acceleration (vi_sim_accel) walks the dense column-major
 * M^-1 K and M^-1 C inside the band with a varying inner trip count, and
 * takes the forcing's phase afresh at every evaluation.  Here each row of
 * the band is stored (the storage's pack_rows, vi_storage.h)
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
  /* a storage without dense M^-1 K has no rows to pack (band storage
   * evaluates it in O(n kd)); a wide band gains nothing from packing but
   * the memory of a third copy: both take vi_sim_accel */
  if (!m->ops->pack_rows || width > VI_RHS_WIDTH_MAX) {
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
  m->ops->pack_rows(m, width, r->lo, r->R);
  vi_forcing_vectors(m, VI_FORCING_MINV, &r->fa, &r->fb, &r->f0);
  r->harmonic = s->harmonic;
  vi_phase_cache_init(&r->phase, m->omega_f);
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

void vi_rhs_rate(vi_sim *s, vi_rhs *r, double t, const double *z, double *zd)
{
  int n = r->n, width = r->width;
  double *restrict acc = r->acc;
  if (!r->R) {
    vi_sim_accel(s, t, z, s->sticking, acc);
  } else {
    vi_phase p = r->harmonic ? vi_phase_cached(&r->phase, t)
                             : vi_phase_none(r->phase.W);
    /* locals: acc may not alias the coefficients, so they stay in registers */
    const double *restrict R = r->R;
    const double *restrict fa = r->fa, *restrict fb = r->fb, *restrict f0 = r->f0;
    const int *restrict lo = r->lo;
    if (width == 4) { /* two degrees of freedom, dense */
      for (int i = 0; i < n; i++) {
        const double *row = R + 4 * (size_t)i;
        acc[i] = vi_harm(&p, 0, fa[i], fb[i], f0[i]) + row[0] * z[0] +
                 row[1] * z[1] + row[2] * z[2] + row[3] * z[3];
      }
    } else if (width == 6) { /* a chain: tridiagonal M^-1 K, M^-1 C */
      for (int i = 0; i < n; i++) {
        const double *row = R + 6 * (size_t)i, *zi = z + lo[i];
        acc[i] = vi_harm(&p, 0, fa[i], fb[i], f0[i]) + row[0] * zi[0] +
                 row[1] * zi[1] + row[2] * zi[2] + row[3] * zi[3] +
                 row[4] * zi[4] + row[5] * zi[5];
      }
    } else {
      for (int i = 0; i < n; i++) {
        const double *row = R + (size_t)width * (size_t)i, *zi = z + lo[i];
        double a = vi_harm(&p, 0, fa[i], fb[i], f0[i]);
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

/* out = M^-1 (f^(k)(t) - K u - C ud): the k-th time derivative (k = 1, 2)
 * of the free acceleration M^-1 (f - K x - C v) along a motion whose k-th
 * and (k+1)-th derivatives of x are u and ud. */
void vi_sim_accel_rate(const vi_sim *s, double t, int k, const double *u,
                       const double *ud, double *out)
{
  vi_phase p = vi_sim_phase(s, t);
  s->m->ops->accel_rate(s->m, &p, k, u, ud, out);
}
