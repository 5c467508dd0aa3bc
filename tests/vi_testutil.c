/* vi_testutil.c - shared fixtures for the cmocka tests. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vi_testutil.h"

void vi_assert_close_(double a, double b, double tol, const char *sa,
                      const char *sb, const char *file, int line)
{
  if (!(fabs(a - b) <= tol)) {
    print_error("%s = %.17g and %s = %.17g differ by %.3g > %.3g\n", sa, a,
                sb, b, fabs(a - b), tol);
    _fail(file, line);
  }
}

vi_model *vi_test_chain(int n, double m, double k, double c, double xs,
                        double r, double omega, const double *a)
{
  double *buf = calloc((size_t)3 * n * n + 4 * (size_t)n, sizeof(double));
  assert_non_null(buf);
  size_t nn = (size_t)n * (size_t)n;
  double *M = buf, *C = M + nn, *K = C + nn, *mv = K + nn;
  double *kv = mv + n, *cv = kv + n, *w = cv + n;
  for (int i = 0; i < n; i++) {
    mv[i] = m;
    kv[i] = k;
    cv[i] = c;
  }
  w[n - 1] = 1.0;
  assert_int_equal(vi_build_chain(n, mv, kv, cv, M, C, K, n), VI_OK);
  vi_model *md = vi_test_model(n, M, C, K, omega, a, NULL, w, xs, r);
  free(buf);
  return md;
}

vi_model *vi_test_fig2(void)
{
  const double a[2] = {0.5, 0.0};
  return vi_test_chain(2, 1.0, 1.0, 0.1, 0.1, 0.7, 0.9, a);
}

vi_model *vi_test_sdof(double m, double c, double k, double a, double f0,
                       double omega, double xs, double r)
{
  const double w = 1.0;
  return vi_test_model(1, &m, &c, &k, omega, &a, &f0, &w, xs, r);
}

vi_model *vi_test_model(int n, const double *M, const double *C,
                        const double *K, double omega, const double *a,
                        const double *f0, const double *w, double xs, double r)
{
  vi_model *m = NULL;
  assert_int_equal(vi_model_create(n, &m), VI_OK);
  assert_int_equal(vi_model_set_mass(m, M, n), VI_OK);
  assert_int_equal(vi_model_set_damping(m, C, n), VI_OK);
  assert_int_equal(vi_model_set_stiffness(m, K, n), VI_OK);
  assert_int_equal(vi_model_set_forcing(m, omega, a, NULL, f0), VI_OK);
  assert_int_equal(vi_model_set_stop(m, w, xs, r), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  return m;
}

vi_model *vi_test_beam(int modes, double xs, double r)
{
  double M[64], C[64], K[64], w[8], g[8], a[8];
  assert_true(modes >= 1 && modes <= 8);
  assert_int_equal(vi_build_cantilever(modes, 1.0, 0.05, 1.0, M, C, K, modes, w, g), VI_OK);
  for (int j = 0; j < modes; j++) a[j] = -0.01 * g[j];
  return vi_test_model(modes, M, C, K, 0.85, a, NULL, w, xs, r);
}

const double vi_test_np3_M[9] = {2.0, 0.3, 0.1, 0.3, 1.5, -0.2, 0.1, -0.2, 1.0};
const double vi_test_np3_K[9] = {3, -1, 0, -1, 2, -1, 0, -1, 1};
const double vi_test_np3_C[9] = {0.25, 0, 0, 0, 0.02, 0, 0, 0, 0.05};
const double vi_test_np3_a[3] = {0.6, 0.0, 0.3};

vi_model *vi_test_nonprop3(double xs, const double *f0)
{
  const double w[3] = {0.2, -0.5, 1.0};
  vi_model *m = vi_test_model(3, vi_test_np3_M, vi_test_np3_C, vi_test_np3_K,
                              0.8, vi_test_np3_a, f0, w, xs, 0.6);
  assert_int_equal(vi_model_is_proportional(m), 0);
  return m;
}

vi_sim *vi_test_sim(const vi_model *m, int method, double rtol, double atol,
                    const double *x0, const double *v0, vi_test_events *ev)
{
  vi_sim *s = NULL;
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_sim_set_method(s, method), VI_OK);
  assert_int_equal(vi_sim_set_tolerances(s, rtol, atol), VI_OK);
  assert_int_equal(vi_sim_set_initial(s, 0.0, x0, v0), VI_OK);
  if (ev) assert_int_equal(vi_sim_set_event_callback(s, vi_test_collect, ev, NULL), VI_OK);
  return s;
}

int vi_test_collect(const vi_event *ev, void *user)
{
  vi_test_events *e = user;
  int n = ev->n;
  if (e->count == e->cap) {
    e->cap = e->cap ? 2 * e->cap : 64;
    e->n = n;
    e->kind = realloc(e->kind, sizeof(int) * e->cap);
    e->t = realloc(e->t, sizeof(double) * e->cap);
    e->vn = realloc(e->vn, sizeof(double) * e->cap);
    e->x = realloc(e->x, sizeof(double) * e->cap * n);
    e->vm = realloc(e->vm, sizeof(double) * e->cap * n);
    e->vp = realloc(e->vp, sizeof(double) * e->cap * n);
    assert_true(e->kind && e->t && e->vn && e->x && e->vm && e->vp);
  }
  int k = e->count++;
  e->kind[k] = ev->kind;
  e->t[k] = ev->t;
  e->vn[k] = ev->vn;
  memcpy(e->x + (size_t)k * n, ev->x, sizeof(double) * n);
  memcpy(e->vm + (size_t)k * n, ev->v_minus, sizeof(double) * n);
  memcpy(e->vp + (size_t)k * n, ev->v_plus, sizeof(double) * n);
  return 0;
}

void vi_test_events_free(vi_test_events *e)
{
  free(e->kind); free(e->t); free(e->vn); free(e->x); free(e->vm); free(e->vp);
  memset(e, 0, sizeof *e);
}

int vi_test_run(const vi_model *m, int method, double rtol, double atol,
                const double *x0, const double *v0, double t_end,
                vi_test_events *ev)
{
  vi_sim *s = vi_test_sim(m, method, rtol, atol, x0, v0, ev);
  int st = vi_sim_run(s, t_end);
  if (st < 0) print_error("vi_sim_run: %s\n", vi_sim_errmsg(s));
  vi_sim_destroy(&s);
  return st;
}

/* A state row of an event, NaN for events without states
 * (vi_sim_set_event_states 0). */
static void put_row(double *dst, const double *src, size_t n)
{
  if (src) memcpy(dst, src, sizeof(double) * n);
  else
    for (size_t i = 0; i < n; i++) dst[i] = NAN;
}

int vi_test_record(const vi_event *ev, void *user)
{
  vi_test_rec *e = user;
  size_t n = (size_t)ev->n;
  if (e->count == e->cap) {
    e->cap = e->cap ? 2 * e->cap : 64;
    e->n = ev->n;
    size_t c = (size_t)e->cap;
    e->kind = realloc(e->kind, sizeof(int) * c);
    e->stop = realloc(e->stop, sizeof(int) * c);
    e->t = realloc(e->t, sizeof(double) * c);
    e->vn = realloc(e->vn, sizeof(double) * c);
    e->ie = realloc(e->ie, sizeof(double) * c);
    e->x = realloc(e->x, sizeof(double) * c * n);
    e->vm = realloc(e->vm, sizeof(double) * c * n);
    e->vp = realloc(e->vp, sizeof(double) * c * n);
    assert_true(e->kind && e->stop && e->t && e->vn && e->ie && e->x &&
                e->vm && e->vp);
  }
  size_t k = (size_t)e->count++;
  e->kind[k] = ev->kind;
  e->stop[k] = ev->stop;
  e->t[k] = ev->t;
  e->vn[k] = ev->vn;
  e->ie[k] = ev->ie;
  put_row(e->x + k * n, ev->x, n);
  put_row(e->vm + k * n, ev->v_minus, n);
  put_row(e->vp + k * n, ev->v_plus, n);
  return 0;
}

void vi_test_rec_free(vi_test_rec *e)
{
  free(e->kind);
  free(e->stop);
  free(e->t);
  free(e->vn);
  free(e->ie);
  free(e->x);
  free(e->vm);
  free(e->vp);
  memset(e, 0, sizeof *e);
}

vi_model *vi_test_model_stops(int n, const double *M, const double *C,
                              const double *K, double omega, const double *a,
                              const double *f0, int ns, const double *W,
                              const double *xs, const double *r)
{
  vi_model *m = NULL;
  assert_int_equal(vi_model_create(n, &m), VI_OK);
  assert_int_equal(vi_model_set_mass(m, M, n), VI_OK);
  assert_int_equal(vi_model_set_damping(m, C, n), VI_OK);
  assert_int_equal(vi_model_set_stiffness(m, K, n), VI_OK);
  assert_int_equal(vi_model_set_forcing(m, a ? omega : 0.0, a, NULL, f0),
                   VI_OK);
  for (int k = 0; k < ns; k++)
    assert_int_equal(vi_model_add_stop(m, W + (size_t)k * (size_t)n, xs[k],
                                       r[k]), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  return m;
}

vi_sim *vi_test_sim_stops(const vi_model *m, int method, double rtol,
                          double atol, double t0, const double *x0,
                          const double *v0, vi_test_rec *ev)
{
  vi_sim *s = NULL;
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_sim_set_method(s, method), VI_OK);
  assert_int_equal(vi_sim_set_tolerances(s, rtol, atol), VI_OK);
  assert_int_equal(vi_sim_set_initial(s, t0, x0, v0), VI_OK);
  if (ev)
    assert_int_equal(vi_sim_set_event_callback(s, vi_test_record, ev, NULL),
                     VI_OK);
  return s;
}

vi_sim *vi_test_chatter_sticks(int method, vi_model **m, vi_test_events *ev,
                               int *last)
{
  double g = 2.0, V = 1.0, r = 0.5, Tacc = 2 * V / (g * (1 - r));
  *m = vi_test_sdof(1.0, 0.0, 0.0, 0.0, g, 0.0, 0.0, r);
  double x0 = 0.0, v0 = -V;
  vi_sim *s = vi_test_sim(*m, method, 1e-12, 1e-14, &x0, &v0, ev);
  /* the accumulation point to rtol: the accuracy-driven summing (the
   * default resolves every impact above 1e-5 V, at the cost of timing the
   * late, grazing ones to dx / v_n only) */
  assert_int_equal(vi_sim_set_impact_resolution(s, 0.0), VI_OK);
  assert_int_equal(vi_sim_run(s, 5.0), VI_OK);
  *last = ev->count - 1;
  assert_true(ev->count > 4);
  assert_int_equal(ev->kind[*last], VI_EVENT_STICK);
  double tk = 0, vk = V;
  for (int i = 0; i < *last; i++) {
    tk += 2 * vk / g;
    double tol = vk > 1e-2 ? 1e-9 : 1e-6;
    assert_close(ev->t[i], tk, tol);
    assert_close(ev->vn[i], vk, tol);
    vk *= r;
  }
  assert_close(ev->t[*last], Tacc, 1e-10);
  double t, x, v;
  vi_sim_state(s, &t, &x, &v);
  assert_close(x, 0.0, 1e-12);
  assert_close(v, 0.0, 1e-12);
  assert_int_equal(vi_sim_is_sticking(s), 1);
  return s;
}
