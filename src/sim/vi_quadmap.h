/* vi_quadmap.h - the maps of the ledger's quadrature panels on a
 * closed-form flow (the exact method's free flight, vi_exact.c, and its
 * held phases, vi_held.c).  A panel [m - h, m + h] takes every mode's
 * state once, at its midpoint m, directly; its 8 Gauss-Legendre nodes m +
 * tau_i follow by the mode's map over tau_i (vi_flow_basis, the mirror
 * -tau_i by the inverse map) and the forcing phase by the rotation by
 * Omega tau_i.  Those maps depend only on h, which successive
 * panels share up to the rounding of their ends (a few distinct values
 * take turns), so a few widths are kept, compared exactly and recomputed
 * on a miss: the transcendental cost per panel falls from 8 (n + 1) to
 * n + 1 cos/sin-exp evaluations, 4 (n + 1) on a miss. */
#ifndef VI_QUADMAP_H
#define VI_QUADMAP_H

enum { VI_QUADMAP_WAYS = 4, VI_QUADMAP_NODES = 8 };

typedef struct vi_quadmap_set {
  double h;                     /* half-width (0: empty) */
  double *T;                    /* node i, mode j: B, Bp, phi over its
                                   offset at T[(3 i + 0, 1, 2) n + j] */
  double c[VI_QUADMAP_NODES], s[VI_QUADMAP_NODES]; /* cos, sin Omega tau_i */
  double w[VI_QUADMAP_NODES];   /* the rule's weights (times h) */
} vi_quadmap_set;

typedef struct vi_quadmap {
  int cap, n, next;             /* room for cap modes; n of them mapped */
  double *buf;
  vi_quadmap_set set[VI_QUADMAP_WAYS];
} vi_quadmap;

/* Room for cap modes, n = cap of them mapped: VI_OK or VI_ERR_NOMEM. */
int vi_quadmap_init(vi_quadmap *Q, int cap);
void vi_quadmap_free(vi_quadmap *Q);
/* Forget every width: the modes changed, now n <= cap of them. */
void vi_quadmap_reset(vi_quadmap *Q, int n);
/* The maps for half-width h of the modes lambda [n], damping dmp[j inc]
 * and forcing frequency Om. */
const vi_quadmap_set *vi_quadmap_get(vi_quadmap *Q, double h, double Om,
                                     const double *lam, const double *dmp,
                                     int inc);

/* Node i's phase from the phase (c0, s0) at the panel's midpoint. */
static inline void vi_quadmap_phase(const vi_quadmap_set *S, int i, double c0,
                                    double s0, double *c, double *s)
{
  *c = c0 * S->c[i] - s0 * S->s[i];
  *s = s0 * S->c[i] + c0 * S->s[i];
}

#endif
