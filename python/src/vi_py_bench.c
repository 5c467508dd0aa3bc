/* vi_py_bench.c - the C loops bench/python_bench.py times the Python
 * package against, compiled into the extension so that both run on the
 * same model in the same process (ratios within one run). */
#include <time.h>

#include "vi_py.h"

static double now(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* reps runs of model to t_end as Model.simulate does them: a new sim,
 * method and tolerances, the event collectors (states kept), the run, the
 * buffers freed.  Seconds per run; < 0 on an error. */
double vi_py_bench_simulate(const vi_model *model, int reps, double t_end,
                            int method, double rtol, double atol)
{
  double t0 = now();
  for (int k = 0; k < reps; k++) {
    vi_sim *s = NULL;
    vi_py_run *r = vi_py_run_new(vi_model_n(model), 1);
    int st = r ? vi_sim_create(model, &s) : VI_ERR_NOMEM;
    if (!st) st = vi_py_prepare(r, s, method, rtol, atol, 0.0, 0);
    if (!st) st = vi_sim_run(s, t_end);
    vi_sim_destroy(&s);
    vi_py_run_free(r);
    if (st < 0) return st;
  }
  return (now() - t0) / reps;
}

/* A warm-started sweep of `key` over values [nv] with transient and
 * record periods per value on `method`, each point's impacts and
 * stroboscopic states read as studies.sweep reads them (copied out).
 * Seconds; < 0 on an error. */
double vi_py_bench_sweep(const vi_model *model, const char *key,
                         const double *values, int nv, int transient,
                         int record, int method, double *sink)
{
  double t0 = now();
  vi_sweep *sw = NULL;
  int st = vi_sweep_create(model, &sw);
  if (!st) st = vi_sweep_set_periods(sw, transient, record);
  if (!st) st = vi_sweep_set_run(sw, method, 1e-8, 1e-10);
  double acc = 0;
  for (int i = 0; i < nv && !st; i++) {
    st = vi_sweep_set_param(sw, key, values[i]);
    if (!st) st = vi_sweep_iterate(sw);
    int n, m, ld, rec;
    int64_t cnt;
    const double *t, *ph, *vn;
    vi_sweep_period(sw, &n, &m);
    vi_sweep_impacts(sw, &cnt, &t, &ph, &vn);
    const double *s = vi_sweep_strobe(sw, &ld, &rec);
    for (int64_t j = 0; j < cnt; j++) acc += t[j] + ph[j] + vn[j];
    if (s) acc += s[0];
  }
  vi_sweep_destroy(&sw);
  *sink = acc;
  return st < 0 ? st : now() - t0;
}
