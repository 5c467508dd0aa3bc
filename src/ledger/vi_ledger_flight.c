/* vi_ledger_flight.c - the ledger's FE and DE over a free flight in closed
 * form (vi_ledger_flight.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vi_forcing.h"
#include "vi_internal.h"
#include "vi_ledger_flight.h"

typedef struct cx {
  double r, i;
} cx;

static inline cx cmul(cx a, cx b)
{
  return (cx){a.r * b.r - a.i * b.i, a.r * b.i + a.i * b.r};
}

static inline cx conj_(cx a) { return (cx){a.r, -a.i}; }

/* int_0^tau e^{z s} ds, z = x + i y with x <= 0, from e^{x tau} - 1 = em,
 * e^{x tau} = ea and sh, ch = sin, cos(y tau / 2):
 *   e^{z tau} - 1 = em cos(y tau) - 2 sh^2 + i ea sin(y tau),
 * whose real part adds two terms of one sign where cos(y tau) >= 0 (no
 * cancellation as z tau -> 0).  Below |z tau| = 1e-5 the series, whose
 * fourth term is under 1e-22 of the first (and |z|^2 cannot underflow).
 * iz = 1 / |z|^2 (inv2), the mode's. */
static inline cx eint(double x, double y, double tau, double em, double ea, double sh,
               double ch, double iz)
{
  double zr = x * tau, zi = y * tau;
  if (fabs(zr) + fabs(zi) < 1e-5) {
    cx z = {zr, zi}, z2 = cmul(z, z), z3 = cmul(z2, z);
    return (cx){tau * (1.0 + zr / 2.0 + z2.r / 6.0 + z3.r / 24.0),
                tau * (zi / 2.0 + z2.i / 6.0 + z3.i / 24.0)};
  }
  double nr = em * ((ch - sh) * (ch + sh)) - 2.0 * sh * sh;
  double ni = ea * (2.0 * sh * ch);
  return (cx){(nr * x + ni * y) * iz, (ni * x - nr * y) * iz};
}

/* e^{x tau} - 1 and e^{x tau}, x <= 0, each to its relative accuracy. */
static void expo(double x, double tau, double *em, double *ea)
{
  *em = expm1(x * tau);
  *ea = *em >= -0.5 ? 1.0 + *em : exp(x * tau);
}

/* 1 / |x + i y|^2, eint's quotient. */
static double inv2(double x, double y) { return 1.0 / (x * x + y * y); }

int vi_lflight_ok(const vi_model *m)
{
  if (!m->proportional) return 0;
  for (int j = 0; j < m->n; j++) {
    double lam = m->lambda[j], d = m->D[j + (size_t)j * (size_t)m->n];
    if (!(lam > 0.0) || !(d >= 0.0) || !(d * d <= lam) || !isfinite(lam))
      return 0;
  }
  return 1;
}

int vi_lflight_init(vi_lflight *f, const vi_model *m)
{
  size_t n = (size_t)m->n, c = n ? n : 1;
  f->n = m->n;
  /* the modes [n], then QS and I [2n each]: one block */
  f->md = malloc((sizeof *f->md + sizeof(double) * 4) * c);
  if (!f->md) return VI_ERR_NOMEM;
  void *rest = f->md + c; /* a mode is doubles only */
  f->QS = rest;
  f->I = f->QS + 2 * c;
  for (size_t j = 0; j < n; j++) /* the model's: not again at every flight */
    vi_lflight_mode_rates(f->md + j, m->lambda[j], m->D[j + j * n], m->omega_f);
  return VI_OK;
}

void vi_lflight_free(vi_lflight *f)
{
  free(f->md); /* and QS, I */
  f->md = NULL;
  f->QS = NULL;
  f->I = NULL;
}

static void mode_flight(vi_lflight_mode *e, double lam, double W, double c0,
                        double s0, double pA, double pB, double Fa, double Fb,
                        double F0, double w, double wd);

void vi_lflight_start(vi_lflight *f, const vi_model *m, const double *pA,
                      const double *pB, double t0, const vi_phase *p,
                      const double *w, const double *wd, const double *Q)
{
  int n = f->n;
  const double *Fa, *Fb, *F0;
  vi_forcing_vectors(m, VI_FORCING_MODAL, &Fa, &Fb, &F0);
  double W = m->omega_f;
  f->W = W;
  f->t0 = t0;
  f->tau_done = NAN;
  memcpy(f->QS, Q, sizeof(double) * 2 * (size_t)n);
  for (int j = 0; j < n; j++)
    mode_flight(f->md + j, m->lambda[j], W, p->c, p->s, pA[j], pB[j], Fa[j],
                Fb[j], F0[j], w[j], wd[j]);
}

void vi_lflight_share(vi_lflight *f, int j, double tau, const double half[4])
{
  vi_lflight_mode *e = f->md + j;
  e->tau_h = tau;
  memcpy(e->half, half, sizeof e->half);
}

void vi_lflight_mode_rates(vi_lflight_mode *e, double lam, double d, double W)
{
  e->d = d;
  e->h = 0.5 * d;
  e->mu = sqrt(lam - e->h * e->h);
  double h = e->h, mu = e->mu;
  e->iz[0] = inv2(-h, mu);
  e->iz[1] = inv2(-h, mu + W);
  e->iz[2] = inv2(-h, mu - W);
  e->iz[3] = inv2(-2.0 * h, 2.0 * mu);
  e->iz[4] = inv2(-2.0 * h, 0.0);
  e->tau_h = NAN; /* no values of the flow's yet */
}

void vi_lflight_mode_set(vi_lflight_mode *e, double lam, double d, double W,
                         double c0, double s0, double pA, double pB,
                         double Fa, double Fb, double F0, double w, double wd)
{
  vi_lflight_mode_rates(e, lam, d, W);
  mode_flight(e, lam, W, c0, s0, pA, pB, Fa, Fb, F0, w, wd);
}

/* A flight's coefficients of mode e, whose rates are set. */
static void mode_flight(vi_lflight_mode *e, double lam, double W, double c0,
                        double s0, double pA, double pB, double Fa, double Fb,
                        double F0, double w, double wd)
{
  e->F0 = F0;
  e->tau_h = NAN; /* none of this flight's yet */
  /* H' = Re(i W (pA - i pB) e^{i W t}), F - F0 = Re((Fa - i Fb) e^{i W t}),
   * e^{i W t} = e^{i W t0} e^{i W tau} */
  cx P0 = {c0, s0};
  cx A = cmul((cx){pA, -pB}, P0);
  e->Ar = -W * A.i;
  e->Ai = W * A.r;
  cx P = cmul((cx){Fa, -Fb}, P0);
  e->Pr = P.r;
  e->Pi = P.i;
  /* w' = e^{-h tau} (alpha cos + beta sin)(mu tau): alpha = w'(0),
   * w''(0) = F0 - d w' - lambda w = -h alpha + mu beta */
  double al = wd, f0 = F0 - lam * w;
  e->Gr = al;
  e->Gi = -(f0 - e->h * al) / e->mu;
}

/* sin, cos (mu tau / 2), e^{-h tau} - 1 and e^{-h tau} of mode e: the
 * flow's where it shared them at this tau (vi_lflight_share), the same
 * expressions of the same values, so the same numbers. */
static void mode_half(const vi_lflight_mode *e, double tau, double *sm,
                      double *cm, double *em, double *ea)
{
  if (tau == e->tau_h) {
    *sm = e->half[0];
    *cm = e->half[1];
    *em = e->half[2];
    *ea = e->half[3];
    return;
  }
  expo(-e->h, tau, em, ea);
  *sm = sin(0.5 * e->mu * tau);
  *cm = cos(0.5 * e->mu * tau);
}

/* FE, DE of mode e over [t0, t0 + tau] into *fe, *q2 (DE / d): EW, E2W
 * the integrals of e^{i W s}, e^{2 i W s}, sw, cw = sin, cos(W tau / 2). */
static void mode_integrals(const vi_lflight_mode *e, double W, double tau,
                           double sw, double cw, cx EW, cx E2W, double *fe,
                           double *q2)
{
  double h = e->h, mu = e->mu, em, ea, sm, cm, sp, cp, sn, cn;
  mode_half(e, tau, &sm, &cm, &em, &ea);
  /* e^{-2 h tau} - 1 = em (2 + em): no cancellation, em in (-1, 0] */
  double em2 = em * (2.0 + em), ea2 = ea * ea;
  /* the half angles of (mu +- W) tau by the addition theorem, to a few
   * ulp of 1; directly where one is small and needs its relative
   * accuracy (mu near W over a short time) */
  if (fabs((mu - W) * tau) >= 0.5) {
    sp = sm * cw + cm * sw;
    cp = cm * cw - sm * sw;
    sn = sm * cw - cm * sw;
    cn = cm * cw + sm * sw;
  } else {
    sp = sin(0.5 * (mu + W) * tau);
    cp = cos(0.5 * (mu + W) * tau);
    sn = sin(0.5 * (mu - W) * tau);
    cn = cos(0.5 * (mu - W) * tau);
  }
  /* kappa: only in the terms of a constant force (F0 0 * any finite
   * value: the 0 the integral would give) */
  cx Ek = e->F0 != 0.0 ? eint(-h, mu, tau, em, ea, sm, cm, e->iz[0])
                       : (cx){0.0, 0.0};
  cx Ekp = eint(-h, mu + W, tau, em, ea, sp, cp, e->iz[1]); /* kappa + iW */
  cx Ekm = eint(-h, mu - W, tau, em, ea, sn, cn, e->iz[2]); /* kappa - iW */
  cx E2k = eint(-2.0 * h, 2.0 * mu, tau, em2, ea2, 2.0 * sm * cm,
                (cm - sm) * (cm + sm), e->iz[3]);         /* 2 kappa */
  cx Eh = eint(-2.0 * h, 0.0, tau, em2, ea2, 0.0, 1.0, e->iz[4]); /* -2h */
  cx A = {e->Ar, e->Ai}, G = {e->Gr, e->Gi}, P = {e->Pr, e->Pi};
  /* Re(X) Re(Y) = (Re(X Y) + Re(X conj Y)) / 2 */
  *fe = 0.5 * cmul(cmul(A, P), E2W).r + 0.5 * cmul(A, conj_(P)).r * tau +
        e->F0 * cmul(A, EW).r + 0.5 * cmul(cmul(G, P), Ekp).r +
        0.5 * cmul(cmul(G, conj_(P)), Ekm).r + e->F0 * cmul(G, Ek).r;
  *q2 = 0.5 * cmul(cmul(A, A), E2W).r + 0.5 * (A.r * A.r + A.i * A.i) * tau +
        cmul(cmul(A, G), Ekp).r + cmul(cmul(A, conj_(G)), conj_(Ekm)).r +
        0.5 * cmul(cmul(G, G), E2k).r + 0.5 * (G.r * G.r + G.i * G.i) * Eh.r;
}

/* f->I: FE, DE over [t0, t0 + tau] (once per tau). */
static void integrals(vi_lflight *f, double tau)
{
  if (tau == f->tau_done) return;
  f->tau_done = tau;
  int n = f->n;
  double W = f->W, sw = sin(0.5 * W * tau), cw = cos(0.5 * W * tau);
  double s2 = 2.0 * sw * cw, c2 = (cw - sw) * (cw + sw);
  cx EW = {0.0, 0.0}; /* e^{i W s}: only in the terms of a constant force */
  for (int j = 0; j < n; j++)
    if (f->md[j].F0 != 0.0) {
      EW = eint(0.0, W, tau, 0.0, 1.0, sw, cw, inv2(0.0, W));
      break;
    }
  cx E2W = eint(0.0, 2.0 * W, tau, 0.0, 1.0, s2, c2,
                inv2(0.0, 2.0 * W));                      /* e^{2 i W s} */
  double *FE = f->I, *DE = f->I + n;
  for (int j = 0; j < n; j++) {
    double q2;
    mode_integrals(f->md + j, W, tau, sw, cw, EW, E2W, FE + j, &q2);
    DE[j] = f->md[j].d * q2;
  }
}

void vi_lflight_eval(vi_lflight *f, double tau, double *Q)
{
  integrals(f, tau);
  for (int k = 0; k < 2 * f->n; k++) Q[k] = f->QS[k] + f->I[k];
}

int vi_lflight_since(vi_lflight *f, double tau, double ta, const double *QA,
                     double *I)
{
  size_t b = sizeof(double) * 2 * (size_t)f->n;
  if (ta != f->t0 || memcmp(QA, f->QS, b) != 0) return 0;
  integrals(f, tau);
  memcpy(I, f->I, b);
  return 1;
}
