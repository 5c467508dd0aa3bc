/* vi_classify.c - is a transient periodic?  The impacts and the
 * stroboscopic states of the recent past, and the test that they repeat
 * with a period of n forcing periods: the P(n, m) classification of
 * vi_orbit_find. */
#include <math.h>
#include <string.h>

#include "vi_orbit_internal.h"

int vi_classify_record(const vi_event *ev, void *user)
{
  vi_orbit *o = user;
  if (ev->kind != VI_EVENT_IMPACT) return 0;
  int k = (int)(o->nimp % RING), n = o->n;
  o->rt[k] = ev->t;
  o->rs[k] = ev->stop;
  memcpy(o->rz + (size_t)k * 2 * n, ev->x, sizeof(double) * n);
  memcpy(o->rz + (size_t)k * 2 * n + n, ev->v_minus, sizeof(double) * n);
  o->nimp++;
  return 0;
}

/* Ring index of the first impact at or after time t (nimp if none). */
int64_t vi_classify_first_after(const vi_orbit *o, double t)
{
  int64_t k = o->nimp;
  while (k > 0 && k > o->nimp - RING && o->rt[(k - 1) % RING] >= t) k--;
  return k;
}

/* Stroboscopic state at the end of forcing period k (kept for the last
 * 3 MAX_N + 1 periods). */
double *vi_classify_strobe(const vi_orbit *o, int64_t k)
{
  return o->pz + (size_t)(k % (3 * MAX_N + 1)) * 2 * o->n;
}

/* Period n needs the states at the ends of periods k, k - n, k - 2n, k - 3n
 * to agree (a run of impact-free periods is not yet periodic: the motion
 * may still be creeping towards the stop), and the impacts of the three
 * windows between them to repeat, shifted by n T. */
int vi_classify_repeats(const vi_orbit *o, int64_t kp, int n, int *m)
{
  double nT = n * o->T, t_now = kp * o->T, zscale = vi_orbit_xs_scale(o->m);
  const double *zk = vi_classify_strobe(o, kp);
  for (int i = 0; i < 2 * o->n; i++) zscale = fmax(zscale, fabs(zk[i]));
  for (int j = 1; j <= 3; j++)
    for (int i = 0; i < 2 * o->n; i++)
      if (fabs(vi_classify_strobe(o, kp - (int64_t)j * n)[i] - zk[i]) > o->tol * zscale) return 0;
  /* nor still settling to a period q dividing n: its change over q periods
   * shrinking beyond the noise.  A transient can repeat over n periods
   * long before it does over q: a free vibration at 1.26 Omega (5 cycles
   * in 4 periods, the NLEVP sandwich beam at Omega = 100) read P(4,0) for
   * a damped linear motion, whose only steady state is P(1,0); so would a
   * multiplier near -1 read P(2,2) */
  for (int q = 1; q < n; q++) {
    if (n % q) continue;
    const double *zq = vi_classify_strobe(o, kp - q), *zn = vi_classify_strobe(o, kp - n),
                 *znq = vi_classify_strobe(o, kp - n - q);
    double a = 0.0, b = 0.0;
    for (int i = 0; i < 2 * o->n; i++) {
      a = fmax(a, fabs(zk[i] - zq[i]));
      b = fmax(b, fabs(zn[i] - znq[i]));
    }
    /* (the strobes are good to the integration's tolerance, far below
     * the classification's: two states that repeat within tol may still
     * show a change shrinking well beyond their own error) */
    if (b - a > fmax(1e-2 * b, 100.0 * o->rtol * zscale)) return 0;
  }
  int64_t k0 = vi_classify_first_after(o, t_now - 3 * nT), k1 = vi_classify_first_after(o, t_now - 2 * nT),
          k2 = vi_classify_first_after(o, t_now - nT), k3 = o->nimp;
  if (k0 <= o->nimp - RING) return 0; /* the ring no longer holds them */
  int64_t c = k3 - k2;
  if (k2 - k1 != c || k1 - k0 != c) return 0;
  double scale = vi_orbit_xs_scale(o->m);
  for (int64_t k = k0; k < k3; k++)
    for (int i = 0; i < 2 * o->n; i++)
      scale = fmax(scale, fabs(o->rz[(size_t)(k % RING) * 2 * o->n + i]));
  for (int64_t k = k0; k + c < k3; k++) {
    size_t a = (size_t)(k % RING), b = (size_t)((k + c) % RING);
    if (fabs(o->rt[b] - o->rt[a] - nT) > o->tol * o->T) return 0;
    if (o->rs[b] != o->rs[a]) return 0;
    for (int i = 0; i < 2 * o->n; i++)
      if (fabs(o->rz[b * 2 * o->n + i] - o->rz[a * 2 * o->n + i]) > o->tol * scale)
        return 0;
  }
  *m = (int)c;
  return 1;
}

/* P(n, m) of a recorded motion (the studies, vi_study.h): the smallest
 * n <= nmax, n <= R, with z_{k+n} = z_k for every recorded stroboscopic
 * state z_0..z_R [n2 each] (to tol relative to the largest entry or the
 * stops' scale xscale, vi_orbit_xs_scale);
 * m the impacts t [nimp] in the last n periods before t_end.  0 for n
 * when none repeats, or when the motion is still settling towards a
 * shorter period. */
int vi_classify_strobes(int R, int n2, const double *z, double xscale, double tol,
                        int nmax, const double *t, int64_t nimp, double T,
                        double t_end, int *m)
{
  double scale = fabs(xscale);
  for (size_t i = 0; i < (size_t)(R + 1) * n2; i++) scale = fmax(scale, fabs(z[i]));
  double eps = tol * scale;
  *m = 0;
  for (int n = 1; n <= nmax && n <= R; n++) {
    int ok = 1;
    for (int k = 0; ok && k + n <= R; k++)
      for (int i = 0; ok && i < n2; i++)
        ok = fabs(z[(size_t)(k + n) * n2 + i] - z[(size_t)k * n2 + i]) <= eps;
    if (!ok) continue;
    /* a motion still settling to a period q dividing n (vi_classify_repeats):
     * its change over q periods at the record's end shrunk from the
     * record's start, at the same place in the n periods, by more than
     * the tolerance; not periodic yet */
    for (int q = 1; q < n; q++) {
      if (n % q) continue;
      int k0 = R - n * ((R - q) / n); /* the first k = R mod n with k >= q */
      double a = 0.0, b = 0.0;
      for (int i = 0; i < n2; i++) {
        a = fmax(a, fabs(z[(size_t)R * n2 + i] - z[(size_t)(R - q) * n2 + i]));
        b = fmax(b, fabs(z[(size_t)k0 * n2 + i] - z[(size_t)(k0 - q) * n2 + i]));
      }
      if (b - a > fmax(1e-2 * b, eps)) return 0;
    }
    double t1 = t_end - n * T - 1e-9 * T;
    for (int64_t j = 0; j < nimp; j++) *m += t[j] >= t1;
    return n;
  }
  return 0;
}
