/* vi_flow.c - closed-form motion between impacts (MODEL.md section 8):
 * the flow object (vi_flow_internal.h), proportionally damped modes here,
 * any other damping in vi_general.c. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vi_flow_internal.h"

int vi_harmonic_particular(double lambda, double d, double Om, double Fc,
                           double Fs, double *A, double *B)
{
  *A = *B = 0.0;
  if (Fc == 0.0 && Fs == 0.0) return 1;
  double p = lambda - Om * Om, s = d * Om, det = p * p + s * s;
  if (det <= 1e-28 * fmax(lambda * lambda, Om * Om * Om * Om)) return 0;
  *A = (p * Fc - s * Fs) / det;
  *B = (s * Fc + p * Fs) / det;
  return 1;
}

int vi_xflow_create(const vi_model *m, vi_xflow **out)
{
  *out = NULL;
  int n = m->n;
  vi_xflow *f = calloc(1, sizeof *f);
  if (!f) return VI_ERR_NOMEM;
  f->pA = malloc(sizeof(double) * 2 * (size_t)n);
  if (!f->pA) {
    free(f);
    return VI_ERR_NOMEM;
  }
  f->pB = f->pA + n;
  f->ok = 1;
  if (!vi_model_has_modes(m)) { /* band storage (vi_band_model.c) */
    f->ok = 0;
    vi_fail(f->why, VI_ERR_UNSUPPORTED, "the model is in band storage: it "
            "has no modes, so no closed-form flow");
    *out = f;
    return VI_OK;
  }
  if (!m->proportional) {
    /* modes couple between impacts: the first-order eigen-solution; a
     * LAPACK failure only means no closed form (CVODE remains) */
    int st = vi_general_create(m, &f->gen, f->why);
    if (st == VI_ERR_NOMEM) {
      vi_xflow_destroy(&f);
      return st;
    }
    f->ok = st == VI_OK;
  }
  for (int j = 0; j < n; j++) {
    double d = m->D[j + (size_t)j * n];
    if (!vi_harmonic_particular(m->lambda[j], d, m->omega_f, m->Fa[j], m->Fb[j], &f->pA[j],
                    &f->pB[j]) && f->ok && m->proportional) {
      f->ok = 0;
      vi_fail(f->why, VI_ERR_UNSUPPORTED,
              "mode %d (omega = %.17g) is undamped and forced at resonance",
              j + 1, m->omega[j]);
    }
  }
  *out = f;
  return VI_OK;
}

void vi_xflow_destroy(vi_xflow **f)
{
  if (!f || !*f) return;
  vi_general_destroy(&(*f)->gen);
  free((*f)->pA);
  free(*f);
  *f = NULL;
}

int vi_xflow_available(const vi_model *m)
{
  vi_xflow *f = NULL;
  if (vi_xflow_create(m, &f)) return 0;
  int ok = f->ok;
  vi_xflow_destroy(&f);
  return ok;
}

/* The one propagator of a damped mode u'' + d u' + lambda u = F (d, lambda
 * >= 0) after tau: B = response from (u, u') = (0, 1), Bp = B', A =
 * response from (1, 0) when F = 0, and phi = response to F = 1 from rest,
 * so that from (u0, v0) with f = F - lambda u0
 *   u = u0 + B v0 + phi f,   u' = Bp v0 + B f,
 * and, unforced, u = A u0 + B v0, u' = Bp v0 - lambda B u0.
 * Written relative to the start, a static offset F/lambda of any size (a
 * very soft structure, lambda -> 0, a rigid-body mode) never enters: there
 * is nothing to cancel (issue 9).  phi is the second divided difference of
 * e^{r tau} over the roots (0, r1, r2); for short times (d tau, lambda
 * tau^2 <= 1) its Taylor series from the ODE, else the closed forms for
 * under-, over- and critically damped modes, each evaluated where it has
 * no cancellation (A = 1 - lambda phi only on the short-time branch, where
 * lambda phi <= 1/2; the overdamped branch folds the exponential into the
 * hyperbolic functions, so that a heavily damped mode cannot overflow).
 * half (may be NULL): sin, cos (mu tau / 2), e^{-h tau} - 1, e^{-h tau}
 * where the underdamped closed form took them (returns 1; else 0). */
static int propagate(double lambda, double d, double tau, double *A,
                     double *B, double *Bp, double *phi, double *half)
{
  double D = d * tau, L = lambda * tau * tau;
  if (tau == 0.0) {
    *B = *phi = 0.0;
    *A = *Bp = 1.0;
    return 0;
  }
  if (D <= 1.0 && L <= 1.0) {
    /* phi = sum T_k, T_{k+2} = -(D (k+1) T_{k+1} + L T_k) / ((k+2)(k+1)) */
    double Tm = 0.0, T = 0.5 * tau * tau, ph = T, b = 2.0 * T;
    for (int k = 1; k < 60; k++) {
      double Tn = -(D * (k + 1) * T + L * Tm) / ((k + 2.0) * (k + 1.0));
      ph += Tn;
      b += (k + 2) * Tn;
      Tm = T;
      T = Tn;
      if (fabs(T) + fabs(Tm) <= 1e-18 * fabs(ph)) break;
    }
    *phi = ph;
    *B = b / tau;
    *Bp = 1.0 - d * *B - lambda * ph;
    *A = 1.0 - lambda * ph;
    return 0;
  }
  double h = 0.5 * d, mu2 = lambda - h * h;
  if (mu2 > 0.0) {
    /* one sincos of the half angle: sin = 2 s c, cos = (c - s)(c + s),
     * 1 - cos = 2 s^2 (no cancellation); e from expm1 where that keeps
     * its relative accuracy (e >= 1/2) */
    double mu = sqrt(mu2), th = 0.5 * mu * tau, sh, ch;
    sincos(th, &sh, &ch); /* what an optimised build makes of sin, cos */
    double em1 = expm1(-h * tau), e = em1 >= -0.5 ? 1.0 + em1 : exp(-h * tau);
    double c = (ch - sh) * (ch + sh), sn = 2.0 * sh * ch;
    *B = e * sn / mu;
    *Bp = e * (c - h * sn / mu);
    *A = e * (c + h * sn / mu);
    /* 1 - A = (1 - e) + e (1 - cos) - h B */
    *phi = (-em1 + 2.0 * e * sh * sh - h * *B) / lambda;
    if (!half) return 0;
    half[0] = sh;
    half[1] = ch;
    half[2] = em1;
    half[3] = e;
    return 1;
  }
  if (mu2 < 0.0) {
    double ka = sqrt(-mu2), r1 = -lambda / (h + ka), r2 = -(h + ka);
    double e1 = exp(r1 * tau), e2 = exp(r2 * tau);
    if (ka * tau < 0.5) {
      double e = exp(-h * tau);
      *B = e * sinh(ka * tau) / ka;
      *A = e * (cosh(ka * tau) + h * sinh(ka * tau) / ka);
    } else {
      *B = (e1 - e2) / (2.0 * ka);
      *A = (r1 * e2 - r2 * e1) / (2.0 * ka);
    }
    *Bp = (r1 * e1 - r2 * e2) / (2.0 * ka);
    if (L >= 0.1) {
      *phi = (1.0 - *A) / lambda;
    } else { /* (E(r1) - E(r2)) / (r1 - r2), E(r) = expm1(r tau) / r */
      double E1 = r1 != 0.0 ? expm1(r1 * tau) / r1 : tau;
      double E2 = expm1(r2 * tau) / r2;
      *phi = (E1 - E2) / (2.0 * ka);
    }
    return 0;
  }
  double e = exp(-h * tau); /* critical damping, lambda = h^2 > 0 */
  *B = tau * e;
  *Bp = e * (1.0 - h * tau);
  *A = e * (1.0 + h * tau);
  *phi = (1.0 - *A) / lambda;
  return 0;
}

void vi_flow_homogeneous(double lambda, double d, double u0, double v0,
                         double tau, double *u, double *ud)
{
  double A, B, Bp, phi;
  propagate(lambda, d, tau, &A, &B, &Bp, &phi, NULL);
  *u = A * u0 + B * v0;
  *ud = Bp * v0 - lambda * B * u0;
}

void vi_flow_basis(double lambda, double d, double tau, double *B, double *Bp,
                   double *phi)
{
  double A;
  propagate(lambda, d, tau, &A, B, Bp, phi, NULL);
}

int vi_flow_basis_half(double lambda, double d, double tau, double *B,
                       double *Bp, double *phi, double half[4])
{
  double A;
  return propagate(lambda, d, tau, &A, B, Bp, phi, half);
}

void vi_flow_stm2(double lambda, double d, double tau, double c[4])
{
  double A, B, Bp, phi;
  propagate(lambda, d, tau, &A, &B, &Bp, &phi, NULL);
  c[0] = A;
  c[1] = -lambda * B;
  c[2] = B;
  c[3] = Bp;
}

void vi_flow_particular(const vi_model *m, const vi_xflow *f, int j,
                        const vi_phase *p, double tau, double *qp,
                        double *qpd)
{
  double lam = m->lambda[j], d = m->D[j + (size_t)j * m->n];
  double q = vi_harm(p, 0, f->pA[j], f->pB[j], 0.0);
  double qd = vi_harm(p, 1, f->pA[j], f->pB[j], 0.0);
  double F0 = m->F0[j];
  if (F0 != 0.0) {
    if (lam > 0.0) {
      q += F0 / lam;
    } else if (d > 0.0) { /* rigid mode with damping: drift at F0/d */
      q += F0 / d * tau;
      qd += F0 / d;
    } else { /* free rigid mode: uniform acceleration */
      q += 0.5 * F0 * tau * tau;
      qd += F0 * tau;
    }
  }
  *qp = q;
  *qpd = qd;
}

/* ---- one flight from its start (vi_xseg) ---------------------------------- */

int vi_xseg_init(vi_xseg *s, const vi_xflow *fl, const vi_model *m, double *buf)
{
  int n = m->n;
  memset(s, 0, sizeof *s);
  s->fl = fl;
  s->m = m;
  s->w = buf;
  s->wd = buf + n;
  s->f = buf + 2 * (size_t)n;
  if (!fl->gen) return VI_OK;
  /* non-proportional damping: the first-order eigen-solution (vi_general.c),
   * which holds interleaved states (x_1, v_1, ...) */
  s->g = vi_gflow_create(fl->gen);
  s->z = malloc(sizeof(double) * 2 * (size_t)n);
  if (!s->g || !s->z) {
    vi_xseg_release(s);
    return VI_ERR_NOMEM;
  }
  return VI_OK;
}

void vi_xseg_release(vi_xseg *s)
{
  vi_gflow_free(s->g);
  free(s->z);
  s->g = NULL;
  s->z = NULL;
}

/* q = H(t) + w: H the harmonic particular solution, w the rest, which obeys
 * w'' + d w' + lambda w = F0 and runs relative to its start */
void vi_xseg_start_modal(vi_xseg *s, double t0, const double *q0,
                         const double *qd0)
{
  const vi_model *m = s->m;
  vi_phase p0 = vi_phase_at(m->omega_f, t0);
  const double *pA = s->fl->pA, *pB = s->fl->pB;
  s->t0 = t0;
  for (int j = 0; j < m->n; j++) {
    s->w[j] = q0[j] - vi_harm(&p0, 0, pA[j], pB[j], 0.0);
    s->wd[j] = qd0[j] - vi_harm(&p0, 1, pA[j], pB[j], 0.0);
    s->f[j] = m->F0[j] - m->lambda[j] * s->w[j];
  }
}

void vi_xseg_modal(const vi_xseg *s, double t, double *q, double *qd, double *c)
{
  vi_xseg_modal_run(s, t, 0.0, 1, q, qd, 0, c); /* a run of one */
}

/* c [4] (a 2 x 2 transition matrix, column-major) carried over a step
 * whose own is (Ah, -lam Bh; Bh, Bph). */
static void stm_step(double c[4], double lam, double Ah, double Bh, double Bph)
{
  for (int col = 0; col < 4; col += 2) {
    double u = c[col], v = c[col + 1];
    c[col] = Ah * u + Bh * v;
    c[col + 1] = -lam * Bh * u + Bph * v;
  }
}

void vi_xseg_modal_run(const vi_xseg *s, double t, double h, int k,
                       double *q, double *qd, size_t ld, double *c)
{
  const vi_model *m = s->m;
  double cs[VI_XSEG_RUN], sn[VI_XSEG_RUN];
  vi_phase p = vi_phase_at(m->omega_f, t);
  vi_phase ph = k > 1 ? vi_phase_at(m->omega_f, h) : p;
  for (int i = 0; i < k; i++) {
    double c0 = p.c;
    cs[i] = p.c;
    sn[i] = p.s;
    p.c = c0 * ph.c - p.s * ph.s;
    p.s = p.s * ph.c + c0 * ph.s;
  }
  int n = m->n;
  double tau = t - s->t0;
  for (int j = 0; j < n; j++) {
    double lam = m->lambda[j], d = m->D[j + (size_t)j * n], F0 = m->F0[j];
    double A, B, Bp, phi, Ah = 1.0, Bh = 0.0, Bph = 1.0, phih = 0.0;
    propagate(lam, d, tau, &A, &B, &Bp, &phi, NULL);
    if (k > 1) propagate(lam, d, h, &Ah, &Bh, &Bph, &phih, NULL);
    /* the deviation from the harmonic, in closed form at t, then by steps:
     * u(tau + h) = A(h) u + B(h) u' + phi(h) F0, u' likewise */
    double u = s->w[j] + B * s->wd[j] + phi * s->f[j];
    double v = Bp * s->wd[j] + B * s->f[j], st[4] = {A, -lam * B, B, Bp};
    double pA = s->fl->pA[j], pB = s->fl->pB[j];
    for (int i = 0; i < k; i++) {
      vi_phase pi = {p.W, cs[i], sn[i]};
      if (q) q[i * ld + j] = vi_harm(&pi, 0, pA, pB, 0.0) + u;
      if (qd) qd[i * ld + j] = vi_harm(&pi, 1, pA, pB, 0.0) + v;
      if (c) memcpy(c + 4 * ((size_t)n * i + j), st, sizeof st);
      if (i + 1 == k) break;
      if (c) stm_step(st, lam, Ah, Bh, Bph);
      double un = Ah * u + Bh * v + phih * F0;
      v = -lam * Bh * u + Bph * v + Bh * F0;
      u = un;
    }
  }
}

void vi_xseg_start(vi_xseg *s, double t0, const double *x0, const double *v0)
{
  int n = s->m->n;
  if (s->g) {
    for (int i = 0; i < n; i++) {
      s->z[2 * (size_t)i] = x0[i];
      s->z[2 * (size_t)i + 1] = v0[i];
    }
    s->t0 = t0;
    vi_gflow_start(s->g, s->m, t0, s->z);
    return;
  }
  /* the modal start in w, wd, then its own flight from there */
  vi_matvec(n, s->m->PsiTM, x0, s->w);
  vi_matvec(n, s->m->PsiTM, v0, s->wd);
  vi_xseg_start_modal(s, t0, s->w, s->wd);
}

void vi_xseg_physical(vi_xseg *s, double t, double *x, double *v,
                      double *work)
{
  int n = s->m->n;
  if (s->g) {
    vi_gflow_eval(s->g, s->m, t, 0, NULL, NULL, s->z);
    for (int i = 0; i < n; i++) {
      x[i] = s->z[2 * (size_t)i];
      v[i] = s->z[2 * (size_t)i + 1];
    }
    return;
  }
  vi_xseg_modal(s, t, work, work + n, NULL);
  vi_matvec(n, s->m->Psi, work, x);
  vi_matvec(n, s->m->Psi, work + n, v);
}

/* ---- the flow from one start to one time ----------------------------------- */

int vi_xflow_modal(const vi_xflow *fl, const vi_model *m, double t0,
                   const double *q0, const double *qd0, double t, double *q,
                   double *qd)
{
  if (!fl->ok) return VI_ERR_UNSUPPORTED;
  int n = m->n;
  double small[7 * VI_FLOW_SMALL];
  double *buf = n <= VI_FLOW_SMALL ? small : malloc(sizeof(double) * 7 * (size_t)n);
  if (!buf) return VI_ERR_NOMEM;
  vi_xseg s;
  int st = vi_xseg_init(&s, fl, m, buf);
  if (!st && fl->gen) { /* through physical coordinates: x = Psi q, q = Psi^T M x */
    double *x = buf + 3 * (size_t)n, *v = x + n;
    vi_matvec(n, m->Psi, q0, x);
    vi_matvec(n, m->Psi, qd0, v);
    vi_xseg_start(&s, t0, x, v);
    vi_xseg_physical(&s, t, x, v, buf + 5 * (size_t)n);
    vi_matvec(n, m->PsiTM, x, q);
    vi_matvec(n, m->PsiTM, v, qd);
  } else if (!st) {
    vi_xseg_start_modal(&s, t0, q0, qd0);
    vi_xseg_modal(&s, t, q, qd, NULL);
  }
  vi_xseg_release(&s);
  if (buf != small) free(buf);
  return st;
}

int vi_xflow_physical(const vi_xflow *fl, const vi_model *m, double t0,
                      const double *x0, const double *v0, double t, double *x,
                      double *v)
{
  if (!fl->ok) return VI_ERR_UNSUPPORTED;
  int n = m->n;
  double small[5 * VI_FLOW_SMALL];
  double *buf = n <= VI_FLOW_SMALL ? small : malloc(sizeof(double) * 5 * (size_t)n);
  if (!buf) return VI_ERR_NOMEM;
  vi_xseg s;
  int st = vi_xseg_init(&s, fl, m, buf);
  if (!st) {
    vi_xseg_start(&s, t0, x0, v0);
    vi_xseg_physical(&s, t, x, v, buf + 3 * (size_t)n);
  }
  vi_xseg_release(&s);
  if (buf != small) free(buf);
  return st;
}

/* The public calls build a flow for the call: O(n) for proportional
 * damping, a dgeev otherwise (hold a vi_xflow to advance many states).
 * (y0, yd0) -> (y, yd) in modal or physical coordinates. */
static int flow_call(const vi_model *m, int physical, double t0,
                     const double *y0, const double *yd0, double t, double *y,
                     double *yd)
{
  if (!m || !y0 || !yd0 || !y || !yd) return VI_ERR_ARG;
  if (m->frozen && (vi_overlap(y, yd, m->n) || vi_overlap(y, y0, m->n) ||
                    vi_overlap(y, yd0, m->n) || vi_overlap(yd, y0, m->n) ||
                    vi_overlap(yd, yd0, m->n)))
    return VI_ERR_ARG; /* outputs would overwrite inputs still being read */
  if (!m->frozen) return VI_ERR_STATE;
  if (!isfinite(t0) || !isfinite(t)) return VI_ERR_NONFINITE;
  /* the phase Omega t and omega_j t must be resolved: |t| eps W <= 1e-3,
   * the range vi_model_check_run gives a run (t = 1e300 is no time) */
  double W = fmax(vi_model_omega_bound(m), m->omega_f);
  if (fmax(fabs(t0), fabs(t)) * DBL_EPSILON * W > 1e-3) return VI_ERR_LIMIT;
  vi_xflow *fl = NULL;
  int st = vi_xflow_create(m, &fl);
  if (st) return st;
  if (!fl->ok) st = VI_ERR_UNSUPPORTED;
  else if (!(t >= t0)) st = VI_ERR_TIME;
  else if (physical) st = vi_xflow_physical(fl, m, t0, y0, yd0, t, y, yd);
  else st = vi_xflow_modal(fl, m, t0, y0, yd0, t, y, yd);
  vi_xflow_destroy(&fl);
  return st;
}

int vi_flow_modal(const vi_model *m, double t0, const double *q0,
                  const double *qd0, double t, double *q, double *qd)
{
  return flow_call(m, 0, t0, q0, qd0, t, q, qd);
}

int vi_flow_physical(const vi_model *m, double t0, const double *x0,
                     const double *v0, double t, double *x, double *v)
{
  return flow_call(m, 1, t0, x0, v0, t, x, v);
}
