/* vi_quadmap.c - the maps of the ledger's quadrature panels (vi_quadmap.h). */
#include <math.h>
#include <stdlib.h>

#include "vi_flow_internal.h"
#include "vi_internal.h"
#include "vi_ledger_internal.h"
#include "vi_quadmap.h"

int vi_quadmap_init(vi_quadmap *Q, int cap)
{
  size_t per = (size_t)(cap > 0 ? cap : 1) * 3 * VI_QUADMAP_NODES;
  Q->cap = cap;
  Q->buf = malloc(sizeof(double) * per * VI_QUADMAP_WAYS);
  if (!Q->buf) return VI_ERR_NOMEM;
  for (int k = 0; k < VI_QUADMAP_WAYS; k++) Q->set[k].T = Q->buf + per * k;
  vi_quadmap_reset(Q, cap);
  return VI_OK;
}

void vi_quadmap_free(vi_quadmap *Q)
{
  free(Q->buf);
  Q->buf = NULL;
}

void vi_quadmap_reset(vi_quadmap *Q, int n)
{
  Q->n = n <= Q->cap ? n : Q->cap;
  Q->next = 0;
  for (int k = 0; k < VI_QUADMAP_WAYS; k++) Q->set[k].h = 0.0;
}

const vi_quadmap_set *vi_quadmap_get(vi_quadmap *Q, double h, double Om,
                                     const double *lam, const double *dmp,
                                     int inc)
{
  for (int k = 0; k < VI_QUADMAP_WAYS; k++)
    if (Q->set[k].h == h) return Q->set + k;
  vi_quadmap_set *S = Q->set + Q->next;
  Q->next = (Q->next + 1) % VI_QUADMAP_WAYS;
  size_t n = (size_t)Q->n, half = VI_QUADMAP_NODES / 2;
  for (size_t i = half; i < VI_QUADMAP_NODES; i++) {
    /* nodes half.. lie at +tau from the midpoint, their mirrors i - half
     * (the rule's order, vi_gl8_node) at -tau */
    double tau = vi_gl8_node((int)i, 0.0, h, S->w + i);
    (void)vi_gl8_node((int)(i - half), 0.0, h, S->w + i - half);
    S->c[i] = S->c[i - half] = cos(Om * tau);
    S->s[i] = sin(Om * tau);
    S->s[i - half] = -S->s[i];
    double *T = S->T + 3 * i * n, *R = S->T + 3 * (i - half) * n;
    for (size_t j = 0; j < n; j++) {
      double l = lam[j], B, Bp, ph;
      vi_flow_basis(l, dmp[j * (size_t)inc], tau, &B, &Bp, &ph);
      T[j] = B;
      T[n + j] = Bp;
      T[2 * n + j] = ph;
      /* -tau: the inverse of the affine map (u, u') -> (A u + B u' + phi
       * F, ...), A = 1 - lambda phi, determinant A Bp + lambda B^2 =
       * e^{-d tau}; the panels are short (d tau, lambda tau^2 < 1/2), so
       * nothing cancels or grows */
      double A = 1.0 - l * ph, e = 1.0 / (A * Bp + l * B * B);
      R[j] = -B * e;
      R[n + j] = A * e;
      R[2 * n + j] = (B * B - Bp * ph) * e;
    }
  }
  S->h = h;
  return S;
}
