/* vi_ledger_flight.h - the ledger's FE and DE over a free flight in closed
 * form (MODEL.md section 4), for proportional damping and underdamped
 * modes.  Between impacts mode j moves as
 *   q_j' = Re(A e^{i W tau}) + Re(G e^{kappa tau}),  kappa = -h + i mu,
 * (the harmonic particular solution's rate and the free part, tau = t -
 * t0) under the force F_j = Re(P e^{i W tau}) + F0, so the integrands q_j'
 * F_j and D_jj q_j'^2 are sums of exponentials e^{z tau} with Re z <= 0,
 * each integrated exactly: int_0^tau e^{z s} ds = (e^{z tau} - 1) / z,
 * its numerator formed without cancellation.  No quadrature rule, no
 * panels; the integrals at any time of the flight cost one sincos of W
 * tau / 2 and per mode one sincos and one expm1, which the flow shares
 * where it took them at the same time (vi_lflight_share). */
#ifndef VI_LEDGER_FLIGHT_H
#define VI_LEDGER_FLIGHT_H

#include "vi_forcing.h"
#include "vi_model_internal.h"

/* One mode's coefficients: its rates (vi_lflight_mode_rates: the model's,
 * set once) and its flight's (vi_lflight_start). */
typedef struct vi_lflight_mode {
  double h, mu, d, F0;
  double Ar, Ai, Gr, Gi, Pr, Pi; /* A, G, P as above */
  double iz[5]; /* 1 / |z|^2 of the exponents kappa, kappa +- iW, 2 kappa,
                   -2h */
  double tau_h, half[4]; /* the flow's values at tau_h (vi_lflight_share) */
} vi_lflight_mode;

typedef struct vi_lflight {
  int n;
  double W, t0;
  vi_lflight_mode *md; /* [n] */
  double *QS;          /* FE, DE at t0 [2n] */
  double tau_done;     /* the last tau integrated to (NaN: none) */
  double *I;           /* FE, DE over [t0, t0 + tau_done] [2n] */
} vi_lflight;

/* 1 if every mode of m is underdamped with damping ratio <= 1/2 (lambda >
 * 0, D_jj^2 <= lambda_j; then mu >= sqrt(3 lambda) / 2 and the free part's
 * coefficients carry no cancellation) and the damping is proportional. */
int vi_lflight_ok(const vi_model *m);
/* Room for m's modes and their rates: VI_OK or VI_ERR_NOMEM. */
int vi_lflight_init(vi_lflight *f, const vi_model *m);
void vi_lflight_free(vi_lflight *f);
/* A flight from t0, p the forcing's phase there (vi_phase_at; any phase
 * if the forcing has no harmonic part): w, w' [n] the free parts (q = H +
 * w, H the harmonic particular solution pA cos + pB sin [n]), Q the
 * ledger's integrals then (FE [n], DE [n]). */
void vi_lflight_start(vi_lflight *f, const vi_model *m, const double *pA,
                      const double *pB, double t0, const vi_phase *p,
                      const double *w, const double *wd, const double *Q);
/* One mode of it: lambda, D_jj, the forcing frequency W and its phase c0,
 * s0 = cos, sin(W t0), the particular solution pA, pB, the modal force
 * Fa, Fb, F0, the free part's w, w' at t0 (vi_lflight_mode_rates, then
 * the flight's coefficients). */
void vi_lflight_mode_set(vi_lflight_mode *e, double lam, double d, double W,
                         double c0, double s0, double pA, double pB,
                         double Fa, double Fb, double F0, double w, double wd);
/* The part of it that depends on the mode alone: h, mu, d and the
 * exponents' 1 / |z|^2 (vi_lflight_init sets them once per mode). */
void vi_lflight_mode_rates(vi_lflight_mode *e, double lam, double d, double W);
/* The flow's sin, cos (mu tau / 2), e^{-h tau} - 1 and e^{-h tau} of mode
 * j at tau from the flight's start (vi_flow_basis_half, the same
 * expressions as the integrals'), which the integrals to that tau take
 * instead of computing them again. */
void vi_lflight_share(vi_lflight *f, int j, double tau, const double half[4]);
/* Q's FE, DE blocks at t0 + tau: the values at t0 plus the integrals
 * (computed once for a repeated tau: the ledger reads them several times
 * at one instant, at close, begin and the next flight's start). */
void vi_lflight_eval(vi_lflight *f, double tau, double *Q);
/* The integrals alone over [t0, t0 + tau] into I [2n], where the ledger's
 * interval began at this flight's start (ta = t0 and its integrals then,
 * QA [2n], are QS): 1; else 0 and I untouched.  They spare the interval
 * the rounding of the cumulative totals it would be the difference of. */
int vi_lflight_since(vi_lflight *f, double tau, double ta, const double *QA,
                     double *I);

#endif
