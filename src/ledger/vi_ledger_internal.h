/* vi_ledger_internal.h - the per-mode energy ledger as an object of its own
 * (MODEL.md section 4): the simulation owns one when the ledger is enabled
 * and tells it where intervals begin and end; the integrator backends only
 * feed it integrand rates (vi_ledger_rates*) and hold its running integrals
 * (vi_ledger_integrals) under their own error control or quadrature. */
#ifndef VI_LEDGER_INTERNAL_H
#define VI_LEDGER_INTERNAL_H

#include "vi_forcing.h"
#include "vi_model_internal.h"

typedef struct vi_ledger vi_ledger;

/* The integrals, n each: FE, DE, XE, CE and NE (work of the nonlinear
 * forces, vi_force.h). */
enum { VI_LEDGER_BLOCKS = 5 };

vi_ledger *vi_ledger_create(const vi_model *m);
void vi_ledger_destroy(vi_ledger *L);
void vi_ledger_set_callback(vi_ledger *L, vi_ledger_fn fn, void *user);

/* Cumulative FE, DE, XE, CE, NE [5n] since the ledger was created: the array
 * the backends integrate into. */
double *vi_ledger_integrals(vi_ledger *L);

/* The held stops while sticking (MODEL.md section 9): cnt stops set [cnt]
 * with their reactions lam [cnt] (the multipliers G_SS^-1 W_S^T a_free,
 * pressing into the stops).  NULL, or cnt = 0, in free flight. */
typedef struct vi_ledger_held {
  int cnt;
  const int *set;
  const double *lam;
} vi_ledger_held;

/* Rates of FE, DE, XE, CE [4n] at t from modal velocities qd [n], or from
 * an interleaved state z [2n]; h the held stops, whose reactions give CE
 * (NULL in free flight).  With the modal nonlinear force gq = Psi^T g
 * also NE (rates [5n]); gq = NULL leaves NE out (and at zero), so that a
 * run without nonlinear forces integrates 4n quadratures, as it always did. */
void vi_ledger_rates(vi_ledger *L, double t, const double *qd,
                     const vi_ledger_held *h, const double *gq, double *rates);
/* The same with the forcing's phase at t already taken (vi_forcing.h). */
void vi_ledger_rates_phase(vi_ledger *L, const vi_phase *p, const double *qd,
                           const vi_ledger_held *h, const double *gq,
                           double *rates);
void vi_ledger_rates_state(vi_ledger *L, double t, const double *z,
                           const vi_ledger_held *h, const double *gq,
                           double *rates);
/* Node i (0..7) of the 8-point Gauss-Legendre rule on [mid - h, mid + h]
 * and its weight *w: the rule of the ledger's integrals in every backend
 * that integrates them itself (the exact method's two, the held motion). */
static inline double vi_gl8_node(int i, double mid, double h, double *w)
{
  static const double gx[4] = {0.1834346424956498, 0.5255324099163290,
                               0.7966664774136267, 0.9602898564975363};
  static const double gw[4] = {0.3626837833783620, 0.3137066458778873,
                               0.2223810344533745, 0.1012285362903763};
  *w = gw[i % 4] * h;
  return mid + (i < 4 ? -gx[i] : gx[i - 4]) * h;
}

/* Q += weight * rates(t, qd) (no NE): one node of a quadrature rule; the
 * _phase form with the forcing's phase at the node already taken. */
void vi_ledger_accumulate(vi_ledger *L, double t, const double *qd,
                          const vi_ledger_held *h, double weight);
void vi_ledger_accumulate_phase(vi_ledger *L, const vi_phase *p,
                                const double *qd, const vi_ledger_held *h,
                                double weight);

/* The same three from the modal state q, q' [n] instead of z. */
void vi_ledger_pre_jump_modal(vi_ledger *L, const double *q, const double *qd);
int vi_ledger_close_modal(vi_ledger *L, double t, const double *q,
                          const double *qd, int jump, double ie, int quiet);
void vi_ledger_begin_modal(vi_ledger *L, double t, const double *q,
                           const double *qd);
/* An interval starts at t in state z. */
void vi_ledger_begin(vi_ledger *L, double t, const double *z);
/* The open interval ends in state z: record its energies before any jump. */
void vi_ledger_pre_jump(vi_ledger *L, const double *z);
/* Close it at t, the state having jumped to z (an impact: jump = 1 with the
 * energy ie lost; else z is the state vi_ledger_pre_jump saw), and begin the
 * next.  Calls the callback unless `quiet`; returns non-zero when the
 * callback asks to stop. */
int vi_ledger_close(vi_ledger *L, double t, const double *z, int jump,
                    double ie, int quiet);
/* Start time of the open interval. */
double vi_ledger_open_since(const vi_ledger *L);

/* Totals for vi_sim_ledger: E [n] of the state z, cumulative FE, DE,
 * XE, CE, jumps dE [n] and ie (any may be NULL). */
void vi_ledger_totals(vi_ledger *L, const double *z, double *E, double *FE,
                      double *DE, double *XE, double *CE, double *dE,
                      double *ie);
double vi_ledger_max_residual(const vi_ledger *L);
void vi_ledger_force_totals(vi_ledger *L, double *NE);

/* Integrals owed: a backend whose closed form gives the integrals at any
 * time of its flight (vi_ledger_flight.h) computes them only when they are
 * read.  fn(data, Q) sets Q [5n] to their values at the sim's present
 * time; every reader of Q calls it first.  vi_ledger_settle brings Q up to
 * date and ends the debt: the backend calls it before its flight's data
 * change, and whoever takes Q to integrate into (vi_ledger_integrals,
 * vi_ledger_accumulate*) settles it first. */
typedef void (*vi_ledger_pending_fn)(void *data, double *Q);
/* since (may be NULL): where the open interval began at ta with integrals
 * QA [5n], the FE and DE [2n] accrued since, exactly (1), or 0 when the
 * backend cannot tell: the interval's own integrals, not the difference
 * of two running totals. */
typedef int (*vi_ledger_since_fn)(void *data, double ta, const double *QA,
                                  double *I);
void vi_ledger_defer(vi_ledger *L, vi_ledger_pending_fn fn,
                     vi_ledger_since_fn since, void *data);
void vi_ledger_settle(vi_ledger *L);

#endif
