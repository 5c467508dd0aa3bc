/* stress_util.c - shared helpers of the stress suite. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stress_util.h"

int st_failures;

void st_check_(int ok, const char *cond, const char *file, int line)
{
  if (!ok) {
    print_error("check failed: %s (%s:%d)\n", cond, file, line);
    st_failures++;
  }
}

void st_end(void)
{
  int f = st_failures;
  st_failures = 0;
  assert_int_equal(f, 0);
}

int st_log_event(const vi_event *ev, void *user)
{
  st_log *l = user;
  if (l->count == l->cap) {
    l->cap = l->cap ? 2 * l->cap : 256;
    l->kind = realloc(l->kind, sizeof(int) * (size_t)l->cap);
    l->t = realloc(l->t, sizeof(double) * (size_t)l->cap);
    l->vn = realloc(l->vn, sizeof(double) * (size_t)l->cap);
    l->ie = realloc(l->ie, sizeof(double) * (size_t)l->cap);
    l->x1 = realloc(l->x1, sizeof(double) * (size_t)l->cap);
    l->v1 = realloc(l->v1, sizeof(double) * (size_t)l->cap);
    assert_true(l->kind && l->t && l->vn && l->ie && l->x1 && l->v1);
  }
  int k = l->count++;
  double g = 0.0, u = 0.0;
  for (int i = 0; i < ev->n; i++) {
    double wi = l->w ? l->w[i] : (i == ev->n - 1);
    g += wi * ev->x[i];
    u += wi * ev->v_plus[i];
  }
  l->kind[k] = ev->kind;
  l->t[k] = ev->t;
  l->vn[k] = ev->vn;
  l->ie[k] = ev->ie;
  l->x1[k] = g - l->xs;
  l->v1[k] = u;
  return 0;
}

void st_log_free(st_log *l)
{
  free(l->kind); free(l->t); free(l->vn); free(l->ie); free(l->x1); free(l->v1);
  l->kind = NULL;
  l->t = l->vn = l->ie = l->x1 = l->v1 = NULL;
  l->count = l->cap = 0;
}

int st_log_count(const st_log *l, int kind)
{
  int c = 0;
  for (int i = 0; i < l->count; i++) c += l->kind[i] == kind;
  return c;
}

int st_log_find(const st_log *l, int kind, int k)
{
  for (int i = 0; i < l->count; i++)
    if (l->kind[i] == kind && k-- == 0) return i;
  return -1;
}

double st_log_ie(const st_log *l)
{
  double s = 0.0;
  for (int i = 0; i < l->count; i++) s += l->ie[i];
  return s;
}

int st_guard_poll(void *user)
{
  st_guard *g = user;
  return ++g->polls > g->limit;
}

int st_gap_sample(double t, int n, const double *x, const double *v, void *user)
{
  (void)t;
  (void)v;
  st_gap *s = user;
  double g = -s->xs;
  for (int i = 0; i < n; i++) g += (s->w ? s->w[i] : (i == n - 1)) * x[i];
  if (!(g <= s->gmax)) s->gmax = g; /* a NaN sticks */
  s->count++;
  return 0;
}

int st_method_ok(const vi_model *m, int method)
{
  vi_sim *s = NULL;
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  int st = vi_sim_set_method(s, method);
  if (st == VI_ERR_UNSUPPORTED)
    print_message("  (method %s skipped: %s)\n", vi_method_name(method),
                  vi_sim_errmsg(s));
  else
    assert_int_equal(st, VI_OK);
  vi_sim_destroy(&s);
  return st == VI_OK;
}

vi_sim *st_sim(const vi_model *m, int method, double rtol, double atol,
               double t0, const double *x0, const double *v0, st_log *log,
               st_guard *guard)
{
  vi_sim *s = NULL;
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_sim_set_method(s, method), VI_OK);
  assert_int_equal(vi_sim_set_tolerances(s, rtol, atol), VI_OK);
  assert_int_equal(vi_sim_set_initial(s, t0, x0, v0), VI_OK);
  /* the stress bounds are those of the accuracy-driven summing (each
   * accumulation point to rtol); the default resolution (every impact
   * above 1e-5 V) is tested in test_sim */
  assert_int_equal(vi_sim_set_impact_resolution(s, 0.0), VI_OK);
  if (log) {
    log->w = vi_model_stop_vector(m);
    log->xs = vi_model_clearance(m);
    assert_int_equal(vi_sim_set_event_callback(s, st_log_event, log, NULL), VI_OK);
  }
  if (guard) assert_int_equal(vi_sim_set_cancel(s, st_guard_poll, guard, NULL), VI_OK);
  return s;
}

vi_model *st_sdof(double m, double c, double k, double W, double a, double b,
                  double f0, double xs, double r)
{
  const double w = 1.0;
  vi_model *md = NULL;
  assert_int_equal(vi_model_create(1, &md), VI_OK);
  assert_int_equal(vi_model_set_mass(md, &m, 1), VI_OK);
  assert_int_equal(vi_model_set_damping(md, &c, 1), VI_OK);
  assert_int_equal(vi_model_set_stiffness(md, &k, 1), VI_OK);
  assert_int_equal(vi_model_set_forcing(md, W, &a, &b, &f0), VI_OK);
  assert_int_equal(vi_model_set_stop(md, &w, xs, r), VI_OK);
  assert_int_equal(vi_model_setup(md), VI_OK);
  return md;
}

long st_vmhwm_kib(void)
{
  FILE *f = fopen("/proc/self/status", "r");
  if (!f) return -1;
  char line[256];
  long kib = -1;
  while (fgets(line, sizeof line, f))
    if (!strncmp(line, "VmHWM:", 6)) kib = strtol(line + 6, NULL, 10);
  fclose(f);
  return kib;
}
