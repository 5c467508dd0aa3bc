/* vi_quadmap.c - the maps of the ledger's quadrature panels (vi_quadmap.h). */
#include <math.h>
#include <stdlib.h>

#include "vi_flow_internal.h"
#include "vi_internal.h"
#include "vi_ledger_internal.h"
#include "vi_quadmap.h"

int vi_quadmap_init(vi_quadmap *Q, int n)
{
  size_t per = 3 * VI_QUADMAP_NODES * (size_t)(n > 0 ? n : 1);
  Q->n = n;
  Q->next = 0;
  Q->buf = malloc(sizeof(double) * per * VI_QUADMAP_WAYS);
  if (!Q->buf) return VI_ERR_NOMEM;
  for (int k = 0; k < VI_QUADMAP_WAYS; k++) Q->set[k].T = Q->buf + per * k;
  vi_quadmap_reset(Q);
  return VI_OK;
}

void vi_quadmap_free(vi_quadmap *Q)
{
  free(Q->buf);
  Q->buf = NULL;
}

void vi_quadmap_reset(vi_quadmap *Q)
{
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
  size_t n = (size_t)Q->n;
  for (int i = 0; i < VI_QUADMAP_NODES; i++) {
    /* node i of the rule on [0, 2h]: its offset from the panel's start */
    double tau = vi_gl8_node(i, h, h, S->w + i);
    S->c[i] = cos(Om * tau);
    S->s[i] = sin(Om * tau);
    double *T = S->T + 3 * (size_t)i * n;
    for (size_t j = 0; j < n; j++)
      vi_flow_basis(lam[j], dmp[j * (size_t)inc], tau, T + j, T + n + j,
                    T + 2 * n + j);
  }
  S->h = h;
  return S;
}
