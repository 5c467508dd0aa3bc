/* vi_forcing.h - the harmonic forcing f(t) = a cos(W t) + b sin(W t) + f0
 * (MODEL.md section 1, WB 1) and its time derivatives: the one place the
 * library takes cos and sin of the forcing phase W t.
 *
 * A vi_phase holds cos(W t), sin(W t) of one time; vi_harm gives the k-th
 * derivative (k = 0, 1, 2) of any harmonic A cos + B sin + C from it, be A,
 * B, C the forcing itself (physical), M^-1 of it, Psi^T of it (modal) or a
 * particular solution or gap that the forcing drives. */
#ifndef VI_FORCING_H
#define VI_FORCING_H

#include <math.h>

#include "vi_internal.h"
#include "vi_period.h"

/* The forcing period 2 pi / W (vi_period.h writes it out). */
static inline double vi_forcing_period(double W)
{
  return vi_periods_time(1.0, W);
}

typedef struct vi_phase {
  double W;    /* forcing frequency Omega */
  double c, s; /* cos(W t), sin(W t) */
} vi_phase;

/* cos(W t), sin(W t): one cos/sin pair (inline: the closed-form flight
 * takes it at every grid point) */
static inline vi_phase vi_phase_at(double W, double t)
{
  vi_phase p = {W, cos(W * t), sin(W * t)};
  return p;
}

/* The phase of an unforced harmonic (a = b = 0): no cos/sin needed, the
 * harmonic terms vanish whatever the phase. */
static inline vi_phase vi_phase_none(double W)
{
  vi_phase p = {W, 1.0, 0.0};
  return p;
}

/* The k-th time derivative (k = 0, 1, 2) of A cos(W t) + B sin(W t) + C
 * at phase p; the constant C counts only for k = 0. */
static inline double vi_harm(const vi_phase *p, int k, double A, double B,
                             double C)
{
  if (k == 0) return A * p->c + B * p->s + C;
  if (k == 1) return p->W * (B * p->c - A * p->s);
  return -p->W * p->W * (A * p->c + B * p->s);
}

/* Which form of the model's forcing: as set (a, b, f0), premultiplied by
 * M^-1 (Minv_a, Minv_b, Minv_f0) or modal Psi^T (Fa, Fb, F0). */
enum { VI_FORCING_PHYS = 0, VI_FORCING_MINV = 1, VI_FORCING_MODAL = 2 };

/* The vectors A, B, C [n] of a form, so that its f^(k) at phase p is
 * vi_harm(p, k, A[i], B[i], C[i]) (the modal ones are NULL for a model
 * without modes). */
void vi_forcing_vectors(const vi_model *m, int form, const double **A,
                        const double **B, const double **C);
/* 1 if a or b is non-zero: cos/sin are needed at all. */
int vi_forcing_harmonic(const vi_model *m);

/* A small cache of phases for a Runge-Kutta step, which asks for the same
 * stage times again, and nearby times by the angle addition theorem from
 * the last point evaluated by the library (the anchor). */
#define VI_PHASE_CACHE 12
typedef struct vi_phase_cache {
  double W;
  double tc[VI_PHASE_CACHE], cc[VI_PHASE_CACHE], sc[VI_PHASE_CACHE];
  double ta, ca, sa; /* the anchor */
  int next;
} vi_phase_cache;
void vi_phase_cache_init(vi_phase_cache *pc, double W);
/* The phase at t: within a few ulp of vi_phase_at(W, t). */
vi_phase vi_phase_cached(vi_phase_cache *pc, double t);

#endif
