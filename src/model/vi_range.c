/* vi_range.c - the ranges a run's values must lie in: one check for the
 * scene reader (which adds the key's line) and for vi_sim_run, so that the
 * API refuses exactly what a scene refuses.
 *
 * Scales: W, the fastest of the natural frequencies and the forcing; L, a
 * length (the clearance, or the static response to the loads).  The run
 * must be resolvable in double precision and the state within a few orders
 * of magnitude of the problem's own scales. */
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "vibroimpact.h"

static double maxabs(const double *v, int n)
{
  double m = 0;
  for (int i = 0; v && i < n; i++) m = fabs(v[i]) > m ? fabs(v[i]) : m;
  return m;
}

static int refuse(const char **key, double *value, char *msg, int len,
                  int code, const char *k, double v, const char *fmt, ...)
    __attribute__((format(printf, 8, 9)));

static int refuse(const char **key, double *value, char *msg, int len,
                  int code, const char *k, double v, const char *fmt, ...)
{
  if (key) *key = k;
  if (value) *value = v;
  if (msg && len > 0) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, (size_t)len, fmt, ap);
    va_end(ap);
  }
  return code;
}

int vi_model_check_run(const vi_model *m, double t0, double t_end,
                       const double *x0, const double *v0, double rtol,
                       double atol, const char **key, double *value,
                       char *msg, int len)
{
  if (key) *key = "";
  if (value) *value = 0.0;
  if (msg && len > 0) msg[0] = '\0';
  int n = vi_model_n(m);
  if (!m || n < 1 || !(vi_model_stop_compliance(m) > 0))
    return refuse(key, value, msg, len, VI_ERR_ARG, "model", 0.0, "%s",
                  "a model that is set up is required");
  if (!isfinite(t0) || !isfinite(t_end) || !isfinite(rtol) || !isfinite(atol))
    return refuse(key, value, msg, len, VI_ERR_NONFINITE, "run", t0, "%s",
                  "times and tolerances must be finite");
  int kd, ldab;
  const double *om = vi_model_omega(m), *ze = vi_model_zeta(m),
               *K = vi_model_stiffness(m),
               *KB = vi_model_stiffness_band(m, &kd, &ldab);
  /* a band model has no modes: its frequencies are bounded (Gershgorin) */
  double wmax = om ? 0 : vi_model_omega_bound(m), zmax = 0, kmax = 0;
  for (int j = 0; j < n; j++) {
    if (om) wmax = om[j] > wmax ? om[j] : wmax;
    if (ze) zmax = isfinite(ze[j]) && ze[j] > zmax ? ze[j] : zmax;
    double kjj = fabs(K ? K[(size_t)j * ((size_t)n + 1)]
                        : KB[(size_t)kd + (size_t)j * (size_t)ldab]);
    kmax = kjj > kmax ? kjj : kmax;
  }
  double omega = vi_model_omega_forcing(m);
  double W = omega > wmax ? omega : wmax;
  if (omega > 0 && wmax > 0 &&
      (omega < VI_RUN_FREQ_RATIO_MIN * wmax || omega > VI_RUN_FREQ_RATIO_MAX * wmax))
    return refuse(key, value, msg, len, VI_ERR_LIMIT, "forcing.omega", omega,
                  "must lie in [%.3g, %.3g]: within 1e-8 .. 1e8 times the "
                  "highest natural frequency", VI_RUN_FREQ_RATIO_MIN * wmax,
                  VI_RUN_FREQ_RATIO_MAX * wmax);
  if (zmax > VI_RUN_ZETA_MAX)
    return refuse(key, value, msg, len, VI_ERR_LIMIT, "model", zmax,
                  "a modal damping ratio above %.3g (limit; got %.3g): the "
                  "damping is out of proportion to the stiffness",
                  VI_RUN_ZETA_MAX, zmax);
  /* time: t must resolve the fastest motion: |t| eps W <= 1e-3 */
  double span = fabs(t_end) > fabs(t0) ? fabs(t_end) : fabs(t0);
  if (W > 0) {
    double tmax = 1e-3 / (DBL_EPSILON * W);
    if (span > tmax)
      return refuse(key, value, msg, len, VI_ERR_LIMIT, "run.t_end", t_end,
                    "the run reaches |t| = %.3g; above %.3g double precision "
                    "no longer resolves the fastest motion", span, tmax);
    if (!(t_end - t0 >= 1e-9 / W))
      return refuse(key, value, msg, len, VI_ERR_LIMIT, "run.t_end", t_end,
                    "the run spans %.3g time units, less than %.3g (1e-9 of "
                    "the fastest period)", t_end - t0, 1e-9 / W);
  } else if (span > 1e-3 / DBL_EPSILON) {
    /* no frequency at all (a free body, unforced): the run's own span */
    return refuse(key, value, msg, len, VI_ERR_LIMIT, "run.t_end", t_end,
                  "the run reaches |t| = %.3g; above %.3g double precision "
                  "no longer resolves it", span, 1e-3 / DBL_EPSILON);
  }
  /* lengths: the clearance or the static response to the loads */
  const double *a = vi_model_forcing_cos(m), *b = vi_model_forcing_sin(m),
               *f0 = vi_model_forcing_const(m);
  double F = 0;
  for (int i = 0; i < n; i++) {
    double f = (a ? fabs(a[i]) : 0) + (b ? fabs(b[i]) : 0) + (f0 ? fabs(f0[i]) : 0);
    F = f > F ? f : F;
  }
  double L = fabs(vi_model_clearance(m)), Ls = kmax > 0 ? F / kmax : 0;
  L = Ls > L ? Ls : L;
  double xm = maxabs(x0, n), vm = maxabs(v0, n);
  if (L > 0 && xm > VI_RUN_STATE_RATIO * L)
    return refuse(key, value, msg, len, VI_ERR_LIMIT, "initial.x", xm,
                  "|x0| above %.3g: 1e8 times the problem's length scale "
                  "%.3g (clearance or static response)",
                  VI_RUN_STATE_RATIO * L, L);
  if (L > 0 && W > 0 && vm > VI_RUN_STATE_RATIO * L * W)
    return refuse(key, value, msg, len, VI_ERR_LIMIT, "initial.v", vm,
                  "|v0| above %.3g: 1e8 times the length scale %.3g times "
                  "the highest frequency", VI_RUN_STATE_RATIO * L * W, L);
  double La = L;
  La = xm > La ? xm : La;
  La = W > 0 && vm / W > La ? vm / W : La;
  if (La > 0 && atol > VI_RUN_ATOL_RATIO * La)
    return refuse(key, value, msg, len, VI_ERR_LIMIT, "run.atol", atol,
                  "must be at most %.3g: 0.01 of the problem's length scale "
                  "%.3g", VI_RUN_ATOL_RATIO * La, La);
  if (!(atol >= DBL_MIN))
    return refuse(key, value, msg, len, VI_ERR_LIMIT, "run.atol", atol,
                  "must be at least %.3g", DBL_MIN);
  if (!(rtol >= VI_RUN_RTOL_MIN && rtol <= VI_RUN_RTOL_MAX))
    return refuse(key, value, msg, len, VI_ERR_LIMIT, "run.rtol", rtol,
                  "must lie in [%.3g, %.3g]", VI_RUN_RTOL_MIN, VI_RUN_RTOL_MAX);
  return VI_OK;
}
