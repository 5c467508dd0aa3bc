/* test_band.c - models in band storage (vi_model_create_band) against
 * physics and against the same model in dense storage: the impacts of a
 * band chain and of the dense one agree to the integration tolerance (a
 * diagonal and a banded, consistent mass; Adams, BDF with SUNDIALS' band
 * solver, ERK; impacts, chattering, sticking and release); an undamped,
 * unforced 20000-mass chain with r = 1 conserves its total energy
 * 1/2 v^T M v + 1/2 x^T K x, computed here from the masses and springs,
 * across its impacts; the model's memory is linear in n; what needs the
 * modes is refused with a message. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vi_testutil.h"

/* Uniform chain data: masses m, springs k, dampers c [n]. */
static void chain_data(int n, double m, double k, double c, double **mass,
                       double **kk, double **cc)
{
  double *p = malloc(sizeof(double) * 3 * (size_t)n);
  if (!p) abort();
  for (int j = 0; j < n; j++) {
    p[j] = m * (1.0 + 0.1 * (j % 3)); /* not uniform: rows differ */
    p[n + j] = k;
    p[2 * n + j] = c;
  }
  *mass = p; /* one block: free(*mass) releases all three */
  *kk = p + n;
  *cc = p + 2 * (size_t)n;
}

/* The chain in band storage (vi_model_create_chain) or dense
 * (vi_build_chain), forcing a cos(omega t) on mass 1 plus f0 on the last,
 * stop on the last mass at xs with r; set up. */
static vi_model *chain(int n, int band, double c, double amp, double omega,
                       double f0last, double xs, double r)
{
  double *mass, *k, *cd;
  chain_data(n, 1.0, 1.0, c, &mass, &k, &cd);
  vi_model *m = NULL;
  if (band) {
    assert_int_equal(vi_model_create_chain(n, mass, k, cd, &m), VI_OK);
    assert_int_equal(vi_model_bandwidth(m), 1);
  } else {
    size_t nn = (size_t)n * (size_t)n;
    double *M = malloc(sizeof(double) * 3 * nn);
    if (!M) abort();
    assert_int_equal(vi_build_chain(n, mass, k, cd, M, M + nn, M + 2 * nn, n),
                     VI_OK);
    assert_int_equal(vi_model_create(n, &m), VI_OK);
    assert_int_equal(vi_model_bandwidth(m), -1);
    assert_int_equal(vi_model_set_mass(m, M, n), VI_OK);
    assert_int_equal(vi_model_set_damping(m, M + nn, n), VI_OK);
    assert_int_equal(vi_model_set_stiffness(m, M + 2 * nn, n), VI_OK);
    free(M);
  }
  double *a = calloc(n, sizeof(double)), *f0 = calloc(n, sizeof(double)),
         *w = calloc(n, sizeof(double));
  assert_true(a && f0 && w);
  a[0] = amp;
  f0[n - 1] = f0last;
  w[n - 1] = 1.0;
  assert_int_equal(vi_model_set_forcing(m, omega, a, NULL, f0), VI_OK);
  assert_int_equal(vi_model_set_stop(m, w, xs, r), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  free(a); free(f0); free(w); free(mass);
  return m;
}

/* Events of both models agree: kinds, times and approach speeds.  A
 * grazing contact (v_n below 1e-9: the gap's maximum touches the stop to
 * round-off) may be seen by one evaluation order and not the other, so
 * those are left out of the comparison. */
static int next_event(const vi_test_events *e, int i)
{
  while (i < e->count && e->kind[i] == VI_EVENT_IMPACT && e->vn[i] < 1e-9) i++;
  return i;
}

static void same_events(const vi_test_events *d, const vi_test_events *b,
                        double tol)
{
  assert_true(d->count > 0);
  int i = next_event(d, 0), j = next_event(b, 0), matched = 0;
  while (i < d->count && j < b->count) {
    assert_int_equal(d->kind[i], b->kind[j]);
    assert_close(b->t[j], d->t[i], tol);
    assert_close(b->vn[j], d->vn[i], tol);
    i = next_event(d, i + 1);
    j = next_event(b, j + 1);
    matched++;
  }
  assert_int_equal(i, d->count);
  assert_int_equal(j, b->count);
  assert_true(matched > 0);
}

/* A forced, damped 12-mass chain with its stop on the last mass: the band
 * model's impacts are the dense model's to the integration tolerance (the
 * two evaluate the same ODE in a different order, so they differ by
 * round-off amplified along the run: 1e-6 against rtol 1e-10). */
static void band_equals_dense(void **state)
{
  (void)state;
  const int methods[3] = {VI_METHOD_ADAMS, VI_METHOD_BDF, VI_METHOD_ERK};
  vi_model *md = chain(12, 0, 0.05, 0.5, 0.6, 0.0, 0.1, 0.7);
  vi_model *mb = chain(12, 1, 0.05, 0.5, 0.6, 0.0, 0.1, 0.7);
  /* the stop's compliance w^T M^-1 w = 1/m_12 (m_12 = 1.2) in both */
  assert_close(vi_model_stop_compliance(mb), 1.0 / 1.2, 1e-15);
  assert_close(vi_model_stop_compliance(md), 1.0 / 1.2, 1e-15);
  /* Gershgorin: omega_max^2 <= max_i sum_j |K_ij| / m_i = 4 (mass 1,
   * springs 1 on both sides), above the dense model's omega_12 */
  assert_close(vi_model_omega_bound(mb), 2.0, 1e-15);
  assert_true(vi_model_omega_bound(md) < 2.0);
  assert_true(vi_model_omega_bound(md) > 1.5);
  double t_end = 20 * 2 * M_PI / 0.6;
  for (int k = 0; k < 3; k++) {
    vi_test_events ed = {0}, eb = {0};
    assert_int_equal(vi_test_run(md, methods[k], 1e-10, 1e-12, NULL, NULL,
                                 t_end, &ed), VI_OK);
    assert_int_equal(vi_test_run(mb, methods[k], 1e-10, 1e-12, NULL, NULL,
                                 t_end, &eb), VI_OK);
    same_events(&ed, &eb, 1e-6);
    vi_test_events_free(&ed);
    vi_test_events_free(&eb);
  }
  vi_model_destroy(&md);
  vi_model_destroy(&mb);
}

/* With r = 0.5 and a constant load into the stop the last mass chatters,
 * sticks and is released by the forcing: the band Jacobian's projection
 * (BDF) and the band right-hand side (Adams) give the dense model's
 * events. */
static void band_sticking(void **state)
{
  (void)state;
  const int methods[2] = {VI_METHOD_ADAMS, VI_METHOD_BDF};
  vi_model *md = chain(12, 0, 0.05, 0.5, 0.6, 0.3, 0.1, 0.5);
  vi_model *mb = chain(12, 1, 0.05, 0.5, 0.6, 0.3, 0.1, 0.5);
  double t_end = 8 * 2 * M_PI / 0.6;
  for (int k = 0; k < 2; k++) {
    vi_test_events ed = {0}, eb = {0};
    assert_int_equal(vi_test_run(md, methods[k], 1e-10, 1e-12, NULL, NULL,
                                 t_end, &ed), VI_OK);
    assert_int_equal(vi_test_run(mb, methods[k], 1e-10, 1e-12, NULL, NULL,
                                 t_end, &eb), VI_OK);
    int sticks = 0;
    for (int i = 0; i < ed.count; i++) sticks += ed.kind[i] == VI_EVENT_STICK;
    assert_true(sticks > 0);
    same_events(&ed, &eb, 1e-5);
    vi_test_events_free(&ed);
    vi_test_events_free(&eb);
  }
  vi_model_destroy(&md);
  vi_model_destroy(&mb);
}

/* Events with their stop, and whether two stops were ever held at once. */
typedef struct two_rec {
  vi_test_events e;
  int *stop, cap, held[2], both;
} two_rec;

static int two_collect(const vi_event *ev, void *user)
{
  two_rec *r = user;
  vi_test_collect(ev, &r->e);
  if (r->e.count > r->cap) {
    r->cap = 2 * r->e.count;
    r->stop = realloc(r->stop, sizeof(int) * r->cap);
    assert_non_null(r->stop);
  }
  r->stop[r->e.count - 1] = ev->stop;
  if (ev->kind == VI_EVENT_STICK) r->held[ev->stop] = 1;
  if (ev->kind == VI_EVENT_RELEASE) r->held[ev->stop] = 0;
  r->both |= r->held[0] && r->held[1];
  return 0;
}

/* Two stops, on masses 12 and 6 of a 12-mass chain, each pressed by a
 * constant load and shaken by the forcing: both stick, and before t = 12
 * both at once, so the band Jacobian's projection on a sticking set of two
 * (BDF) and the right-hand side's (Adams) are exercised; the band model
 * gives the dense model's events, stop by stop.  (Later, near t = 14, the
 * several-stop code reports "state beyond stop 1" for the dense model and
 * the band one alike: a limit of that code, not of the storage.) */
/* The 12-mass chain with its two stops, dense (b = 0) or band (b = 1). */
static vi_model *two_stop_chain(int b)
{
  int n = 12;
  vi_model *m = NULL;
  double *mass, *k, *c;
  chain_data(n, 1.0, 1.0, 0.05, &mass, &k, &c);
  if (b) {
    assert_int_equal(vi_model_create_chain(n, mass, k, c, &m), VI_OK);
  } else {
    double M[3 * 144];
    assert_int_equal(vi_build_chain(n, mass, k, c, M, M + 144, M + 288, n),
                     VI_OK);
    assert_int_equal(vi_model_create(n, &m), VI_OK);
    assert_int_equal(vi_model_set_mass(m, M, n), VI_OK);
    assert_int_equal(vi_model_set_damping(m, M + 144, n), VI_OK);
    assert_int_equal(vi_model_set_stiffness(m, M + 288, n), VI_OK);
  }
  double a[12] = {0.6}, f0[12] = {0}, w1[12] = {0}, w2[12] = {0};
  f0[5] = f0[11] = 0.4;
  w1[11] = w2[5] = 1.0;
  assert_int_equal(vi_model_set_forcing(m, 0.6, a, NULL, f0), VI_OK);
  assert_int_equal(vi_model_add_stop(m, w1, 0.1, 0.5), VI_OK);
  assert_int_equal(vi_model_add_stop(m, w2, 0.1, 0.5), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  free(mass);
  return m;
}

/* m's events to t_end with a method, into r. */
static void two_stop_run(const vi_model *m, int method, double t_end, two_rec *r)
{
  vi_sim *s = NULL;
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_sim_set_method(s, method), VI_OK);
  assert_int_equal(vi_sim_set_tolerances(s, 1e-10, 1e-12), VI_OK);
  assert_int_equal(vi_sim_set_event_callback(s, two_collect, r, NULL), VI_OK);
  assert_int_equal(vi_sim_run(s, t_end), VI_OK);
  vi_sim_destroy(&s);
}

static void band_two_stops(void **state)
{
  (void)state;
  const int methods[2] = {VI_METHOD_ADAMS, VI_METHOD_BDF};
  vi_model *m[2] = {two_stop_chain(0), two_stop_chain(1)};
  for (int q = 0; q < 2; q++) {
    two_rec r[2];
    memset(r, 0, sizeof r);
    for (int b = 0; b < 2; b++) two_stop_run(m[b], methods[q], 12.0, &r[b]);
    assert_true(r[0].both);
    same_events(&r[0].e, &r[1].e, 1e-5);
    for (int i = 0; i < r[0].e.count && i < r[1].e.count; i++)
      assert_int_equal(r[0].stop[i], r[1].stop[i]);
    for (int b = 0; b < 2; b++) {
      vi_test_events_free(&r[b].e);
      free(r[b].stop);
    }
  }
  vi_model_destroy(&m[0]);
  vi_model_destroy(&m[1]);
}

/* A consistent (banded, not diagonal) mass matrix M = m/6 tridiag(1, 4, 1)
 * given in band form to a band model and to a dense one: the band model
 * applies M^-1 by band Cholesky solves; same impacts, same compliance. */
static void banded_mass(void **state)
{
  (void)state;
  int n = 8, ld = 2;
  double MB[16], KB[16], CB[16];
  for (size_t j = 0; j < 8; j++) {
    MB[1 + 2 * j] = 4.0 / 6.0;
    MB[2 * j] = j ? 1.0 / 6.0 : 0.0;
    KB[1 + 2 * j] = j == 7 ? 1.0 : 2.0;
    KB[2 * j] = j ? -1.0 : 0.0;
    CB[1 + 2 * j] = 0.02 * KB[1 + 2 * j];
    CB[2 * j] = 0.02 * KB[2 * j];
  }
  double a[8] = {0.4}, w[8] = {0};
  w[n - 1] = 1.0;
  vi_model *m[2];
  assert_int_equal(vi_model_create(n, &m[0]), VI_OK);
  assert_int_equal(vi_model_create_band(n, 1, &m[1]), VI_OK);
  for (int i = 0; i < 2; i++) {
    assert_int_equal(vi_model_set_mass_band(m[i], 1, MB, ld), VI_OK);
    assert_int_equal(vi_model_set_damping_band(m[i], 1, CB, ld), VI_OK);
    assert_int_equal(vi_model_set_stiffness_band(m[i], 1, KB, ld), VI_OK);
    assert_int_equal(vi_model_set_forcing(m[i], 0.5, a, NULL, NULL), VI_OK);
    assert_int_equal(vi_model_set_stop(m[i], w, 0.2, 0.8), VI_OK);
    assert_int_equal(vi_model_setup(m[i]), VI_OK);
  }
  assert_close(vi_model_stop_compliance(m[1]), vi_model_stop_compliance(m[0]),
               1e-14);
  /* Gershgorin: rows of |K| sum to <= 4, M's smallest eigenvalue is
   * >= 4/6 - 2/6 = 1/3: omega_max <= sqrt(12) */
  assert_close(vi_model_omega_bound(m[1]), sqrt(12.0), 1e-14);
  assert_true(vi_model_omega_bound(m[0]) <= sqrt(12.0));
  /* the band view returns what was set */
  int kd, ldab;
  const double *mb = vi_model_mass_band(m[1], &kd, &ldab);
  assert_non_null(mb);
  assert_int_equal(kd, 1);
  assert_int_equal(ldab, 2);
  assert_true(mb[1 + 3 * (size_t)ldab] == 4.0 / 6.0 &&
              mb[3 * (size_t)ldab] == 1.0 / 6.0);
  assert_null(vi_model_mass_band(m[0], &kd, &ldab));
  vi_test_events e[2] = {{0}, {0}};
  for (int i = 0; i < 2; i++)
    assert_int_equal(vi_test_run(m[i], VI_METHOD_ADAMS, 1e-10, 1e-12, NULL,
                                 NULL, 15 * 2 * M_PI / 0.5, &e[i]), VI_OK);
  same_events(&e[0], &e[1], 1e-6);
  for (int i = 0; i < 2; i++) {
    vi_test_events_free(&e[i]);
    vi_model_destroy(&m[i]);
  }
}

typedef struct energy_ctx {
  int n, impacts;
  const double *mass, *k;
  double e0, worst, ie;
} energy_ctx;

/* 1/2 sum m_j v_j^2 + 1/2 sum k_j (x_j - x_{j-1})^2 (x_0 the ground) */
static double chain_energy(const energy_ctx *c, const double *x,
                           const double *v)
{
  double e = 0.0;
  for (int j = 0; j < c->n; j++) {
    double s = x[j] - (j ? x[j - 1] : 0.0);
    e += 0.5 * c->mass[j] * v[j] * v[j] + 0.5 * c->k[j] * s * s;
  }
  return e;
}

static int on_impact(const vi_event *ev, void *user)
{
  energy_ctx *c = user;
  if (ev->kind != VI_EVENT_IMPACT) return 0;
  c->impacts++;
  c->ie += ev->ie;
  /* r = 1: the impact keeps the kinetic energy; the state's energy is
   * the initial one to the integration error */
  double e = chain_energy(c, ev->x, ev->v_plus);
  c->worst = fmax(c->worst, fabs(e - c->e0) / c->e0);
  return 0;
}

/* 20000 masses, no damping, no forcing, r = 1: the last 100 masses start
 * at speed 1 towards the stop 0.01 away from the last; it rebounds off the
 * stop and off its neighbours, back and forth.  Total energy is
 * conserved (MODEL.md section 7, long runs): to 100 rtol relative (rtol
 * 1e-9; measured 1e-8 over 13 impacts), at every impact and at the end. */
static void long_chain_energy(void **state)
{
  (void)state;
  int n = 20000;
  double *mass, *k, *c;
  chain_data(n, 1.0, 1.0, 0.0, &mass, &k, &c);
  vi_model *m = NULL;
  assert_int_equal(vi_model_create_chain(n, mass, k, NULL, &m), VI_OK);
  double *w = calloc(n, sizeof(double)), *v0 = calloc(n, sizeof(double)),
         *x = calloc(n, sizeof(double)), *v = calloc(n, sizeof(double));
  assert_true(w && v0 && x && v);
  w[n - 1] = 1.0;
  for (int j = n - 100; j < n; j++) v0[j] = 1.0;
  assert_int_equal(vi_model_set_stop(m, w, 0.01, 1.0), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  energy_ctx ctx = {n, 0, mass, k, 0.0, 0.0, 0.0};
  ctx.e0 = chain_energy(&ctx, x, v0);
  double e0 = 0.0;
  for (int j = n - 100; j < n; j++) e0 += 0.5 * mass[j];
  assert_close(ctx.e0, e0, 1e-12);
  vi_sim *s = NULL;
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_sim_set_tolerances(s, 1e-9, 1e-12), VI_OK);
  assert_int_equal(vi_sim_set_initial(s, 0.0, NULL, v0), VI_OK);
  assert_int_equal(vi_sim_set_event_callback(s, on_impact, &ctx, NULL), VI_OK);
  assert_int_equal(vi_sim_run(s, 30.0), VI_OK);
  assert_int_equal(vi_sim_method_used(s), VI_METHOD_ADAMS); /* auto */
  double t;
  assert_int_equal(vi_sim_state(s, &t, x, v), VI_OK);
  assert_true(ctx.impacts >= 2);
  assert_close(ctx.ie, 0.0, 1e-15); /* r = 1: no loss (WB 10) */
  double e = chain_energy(&ctx, x, v);
  assert_close(e / ctx.e0, 1.0, 1e-7);
  assert_true(ctx.worst < 1e-7);
  /* the model's energy (band form) is the chain's */
  assert_close(vi_model_energy(m, x, v), e, 1e-12 * e);
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
  free(w); free(v0); free(x); free(v); free(mass);
}

/* The memory of a band chain is linear in n (a few (kd + 1) n arrays),
 * within the estimate made before allocating; dense storage of the same
 * chain would need 12 n^2 doubles. */
static void memory_linear(void **state)
{
  (void)state;
  int64_t b[2], est, dense;
  for (int i = 0; i < 2; i++) {
    int n = i ? 20000 : 10000;
    double *mass, *k, *c;
    chain_data(n, 1.0, 1.0, 0.01, &mass, &k, &c);
    vi_model *m = NULL;
    assert_int_equal(vi_model_create_chain(n, mass, k, c, &m), VI_OK);
    double *w = calloc(n, sizeof(double));
    assert_non_null(w);
    w[n - 1] = 1.0;
    assert_int_equal(vi_model_set_stop(m, w, 0.01, 1.0), VI_OK);
    assert_int_equal(vi_model_setup(m), VI_OK);
    b[i] = vi_model_memory(m);
    /* M, C, K, factor: 2 n each (kd = 1); rows KR, CR: 3 n each; eight
     * vectors; the stop: 2 n + 4, M^-1 w: n; the struct: under 4 KiB */
    int64_t formula = (int64_t)sizeof(double) * (4 * 2 + 2 * 3 + 8 + 3) * n +
                      4096;
    assert_true(b[i] > (int64_t)sizeof(double) * 20 * n);
    assert_true(b[i] <= formula);
    assert_int_equal(vi_model_memory_estimate(n, 1, 1, VI_METHOD_ADAMS, 0,
                                              &est), VI_OK);
    assert_true(est >= b[i]);
    assert_true(est <= (int64_t)sizeof(double) * 200 * n); /* with the sim */
    assert_int_equal(vi_model_memory_estimate(n, -1, 1, VI_METHOD_ADAMS, 0,
                                              &dense), VI_OK);
    assert_true(dense >= (int64_t)sizeof(double) * 12 * n * (int64_t)n);
    vi_model_destroy(&m);
    free(w); free(mass);
  }
  assert_close((double)b[1] / (double)b[0], 2.0, 0.01); /* linear in n */
  /* what the band form cannot do */
  assert_int_equal(vi_model_memory_estimate(100, 1, 1, VI_METHOD_ADAMS, 1,
                                            &est), VI_ERR_UNSUPPORTED);
  assert_int_equal(vi_model_memory_estimate(100, 1, 1, VI_METHOD_EXACT, 0,
                                            &est), VI_ERR_UNSUPPORTED);
  assert_int_equal(vi_model_memory_estimate(0, 1, 1, VI_METHOD_ADAMS, 0,
                                            &est), VI_ERR_DIM);
  assert_int_equal(vi_model_memory_estimate(10, 1, 1, 99, 0, &est),
                   VI_ERR_ARG);
  /* BDF's band Jacobian: O(n kd) too */
  int64_t bdf;
  assert_int_equal(vi_model_memory_estimate(20000, 1, 1, VI_METHOD_BDF, 0,
                                            &bdf), VI_OK);
  assert_true(bdf <= (int64_t)sizeof(double) * 250 * 20000);
}

/* The estimate counts the model exactly as vi_model_memory reports it once
 * built and set up: what it adds is the setup's and the integrator's
 * workspace, which does not depend on the stops (est - mem the same for
 * 1, 2, 3 and 5 stops, the stop arrays growing 2, 2, 4, 8) and is, for
 * Adams without the ledger, dense 4 n^2 + 8 n (dsygvd, LAPACK) and band
 * (kd + 1) n (the PSD check's copy), plus (23 + 8) 2 n doubles of CVODE and
 * the sim, and 4096 bytes.  (The old estimate counted three removed
 * per-model vectors, 24 n bytes too many.) */
static void memory_exact(void **state)
{
  (void)state;
  for (int band = 0; band < 2; band++) {
    int n = band ? 40 : 6, kd = band ? 1 : -1;
    int64_t extra = -1;
    const int nss[4] = {1, 2, 3, 5};
    for (int q = 0; q < 4; q++) {
      int ns = nss[q];
      vi_model *m = NULL;
      double *mass, *k, *c;
      chain_data(n, 1.0, 1.0, 0.01, &mass, &k, &c);
      if (band) {
        assert_int_equal(vi_model_create_chain(n, mass, k, c, &m), VI_OK);
      } else {
        double *M = calloc((size_t)n * n, sizeof(double));
        double *K = calloc((size_t)n * n, sizeof(double));
        assert_non_null(M);
        assert_non_null(K);
        for (int i = 0; i < n; i++) {
          M[i + (size_t)i * n] = 1.0;
          K[i + (size_t)i * n] = 2.0;
          if (i) K[i + (size_t)(i - 1) * n] = K[i - 1 + (size_t)i * n] = -1.0;
        }
        assert_int_equal(vi_model_create(n, &m), VI_OK);
        assert_int_equal(vi_model_set_mass(m, M, n), VI_OK);
        assert_int_equal(vi_model_set_stiffness(m, K, n), VI_OK);
        free(M);
        free(K);
      }
      double *w = calloc((size_t)n, sizeof(double)), *a = calloc((size_t)n, sizeof(double));
      assert_non_null(w);
      assert_non_null(a);
      a[0] = 0.5;
      assert_int_equal(vi_model_set_forcing(m, 0.9, a, NULL, NULL), VI_OK);
      for (int j = 0; j < ns; j++) { /* stops on distinct coordinates */
        memset(w, 0, sizeof(double) * (size_t)n);
        w[n - 1 - j] = 1.0;
        assert_int_equal(j ? vi_model_add_stop(m, w, 0.1, 0.7)
                           : vi_model_set_stop(m, w, 0.1, 0.7), VI_OK);
      }
      assert_int_equal(vi_model_setup(m), VI_OK);
      int64_t est = 0, mem = vi_model_memory(m);
      assert_int_equal(vi_model_memory_estimate(n, kd, ns, VI_METHOD_ADAMS, 0,
                                                &est), VI_OK);
      double dn = n;
      double work = band ? 2.0 * dn : 4.0 * dn * dn + 8.0 * dn;
      int64_t want = (int64_t)((work + 31.0 * 2.0 * dn) * sizeof(double)) +
                     4096;
      printf("memory %s n = %d, %d stops: model %lld bytes, estimate %lld, "
             "difference %lld (workspace %lld)\n", band ? "band" : "dense", n,
             ns, (long long)mem, (long long)est, (long long)(est - mem),
             (long long)want);
      if (extra < 0) extra = est - mem;
      assert_int_equal(est - mem, extra);
      assert_int_equal(est - mem, want);
      vi_model_destroy(&m);
      free(w);
      free(a);
      free(mass);
    }
  }
}

static int no_force(double t, int n, const double *x, const double *v,
                    double *g, void *user)
{
  (void)t, (void)x, (void)v, (void)user;
  for (int i = 0; i < n; i++) g[i] = 0.0;
  return 0;
}

/* What needs the modes says so; the dense getters return NULL. */
static void refusals(void **state)
{
  (void)state;
  vi_model *m = chain(10, 1, 0.05, 0.5, 0.6, 0.0, 0.1, 0.7);
  assert_null(vi_model_mass(m));
  assert_null(vi_model_stiffness(m));
  assert_null(vi_model_damping(m));
  assert_null(vi_model_omega(m));
  assert_null(vi_model_zeta(m));
  assert_null(vi_model_modal_stop(m));
  int ld = -7;
  assert_null(vi_model_modal_shapes(m, &ld));
  assert_null(vi_model_modal_damping(m, &ld));
  assert_non_null(vi_model_delassus(m, &ld));
  assert_int_equal(ld, 1);
  double x[10] = {0}, q[10];
  assert_int_equal(vi_model_to_modal(m, x, q), VI_ERR_UNSUPPORTED);
  assert_int_equal(vi_model_from_modal(m, q, x), VI_ERR_UNSUPPORTED);
  vi_orbit *o = NULL;
  assert_int_equal(vi_orbit_create(m, &o), VI_ERR_UNSUPPORTED);
  vi_sim *s = NULL;
  assert_int_equal(vi_sim_create(m, &s), VI_OK);
  assert_int_equal(vi_sim_set_method(s, VI_METHOD_EXACT), VI_ERR_UNSUPPORTED);
  assert_non_null(strstr(vi_sim_errmsg(s), "band"));
  assert_int_equal(vi_sim_enable_ledger(s, 1), VI_ERR_UNSUPPORTED);
  assert_non_null(strstr(vi_sim_errmsg(s), "band"));
  assert_int_equal(vi_sim_add_spring(s, VI_SPRING_CUBIC, 1, 0, 1.0, 0.0),
                   VI_ERR_UNSUPPORTED);
  assert_string_equal(vi_sim_errmsg(s), "forces need the modes, which a "
                                        "band-storage model does not have");
  assert_int_equal(vi_sim_set_force(s, no_force, NULL, NULL, NULL),
                   VI_ERR_UNSUPPORTED);
  assert_int_equal(vi_sim_set_method(s, VI_METHOD_AUTO), VI_OK);
  assert_int_equal(vi_sim_method_used(s), VI_METHOD_ADAMS);
  vi_sim_destroy(&s);
  /* every other door that needs the modes: one test decides them all
   * (vi_model_has_modes, src/model/vi_storage.h) */
  vi_census *c = NULL;
  assert_int_equal(vi_census_create(m, 1, 1, &c), VI_ERR_UNSUPPORTED);
  assert_null(c);
  double t1[2] = {0}, x1[20] = {0}, v1[20] = {0};
  int iters = 0, found = 0, mode1 = 1;
  assert_int_equal(vi_orbit_pnm_solve(m, 1, 1, t1, x1, v1, 10, 1e-10, &iters),
                   VI_ERR_UNSUPPORTED);
  assert_int_equal(vi_orbit_p1_scan(m, 1, 8, t1, x1, v1, 10, 2, &found),
                   VI_ERR_UNSUPPORTED);
  vi_model *red = NULL;
  assert_int_equal(vi_model_create_reduced(m, &mode1, 1, 0.7, &red),
                   VI_ERR_UNSUPPORTED);
  assert_int_equal(vi_model_create_truncated(m, 2, 0, 0.7, NULL, NULL, NULL,
                                             &red),
                   VI_ERR_UNSUPPORTED);
  assert_null(red);
  double dyn = 0.0, stat = 0.0;
  assert_int_equal(vi_model_modal_compliance(m, 0, 2, &dyn, &stat),
                   VI_ERR_UNSUPPORTED);
  vi_identify *id = NULL;
  assert_int_equal(vi_identify_create(m, 1, &id), VI_ERR_UNSUPPORTED);
  assert_null(id);
  vi_model_destroy(&m);

  /* a dense matrix with an entry outside the band is refused, naming it */
  assert_int_equal(vi_model_create_band(4, 1, &m), VI_OK);
  double K[16] = {0};
  for (int i = 0; i < 4; i++) K[i + 4 * i] = 2.0;
  K[0 + 4 * 2] = K[2 + 4 * 0] = -1.0;
  assert_int_equal(vi_model_set_stiffness(m, K, 4), VI_ERR_DIM);
  assert_non_null(strstr(vi_model_errmsg(m), "K(3,1)"));
  /* a band wider than the model's, with a non-zero beyond it */
  double AB[12] = {0, 0, 1, 0, -1, 1, 0, 0, 1, 0, 0, 1}; /* kd = 2 */
  assert_int_equal(vi_model_set_stiffness_band(m, 2, AB, 3), VI_OK);
  AB[6] = 0.5; /* K(1,3) */
  assert_int_equal(vi_model_set_stiffness_band(m, 2, AB, 3), VI_ERR_DIM);
  assert_int_equal(vi_model_set_stiffness_band(m, 1, AB, 1), VI_ERR_DIM);
  assert_int_equal(vi_model_set_stiffness_band(m, -1, AB, 3), VI_ERR_DIM);
  /* an indefinite K: the shifted band Cholesky fails */
  double KB[8] = {0, 1, -2, 1, -2, 1, -2, 1}; /* tridiag(-2, 1, -2) */
  assert_int_equal(vi_model_set_stiffness_band(m, 1, KB, 2), VI_OK);
  double w[4] = {0, 0, 0, 1};
  assert_int_equal(vi_model_set_stop(m, w, 0.1, 0.5), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_ERR_NOT_PSD);
  vi_model_destroy(&m);
  /* a mass that is not positive */
  double mass[3] = {1, -1, 1}, k[3] = {1, 1, 1};
  assert_int_equal(vi_model_create_chain(3, mass, k, NULL, &m), VI_ERR_ARG);
  assert_null(m);
  assert_int_equal(vi_model_create_band(0, 1, &m), VI_ERR_DIM);
  assert_int_equal(vi_model_create_band(3, -1, &m), VI_ERR_DIM);
}

/* NULL, zero and negative arguments of the band functions. */
static void misuse(void **state)
{
  (void)state;
  double AB[4] = {0, 1, 0, 1}, mass[2] = {1, 1}, k[2] = {1, 1};
  int64_t b = 5;
  int kd = 9, ld = 9;
  vi_model *m = NULL;
  assert_int_equal(vi_model_create_band(2, 1, NULL), VI_ERR_ARG);
  assert_int_equal(vi_model_set_mass_band(NULL, 1, AB, 2), VI_ERR_ARG);
  assert_int_equal(vi_model_set_damping_band(NULL, 1, AB, 2), VI_ERR_ARG);
  assert_int_equal(vi_model_set_stiffness_band(NULL, 1, AB, 2), VI_ERR_ARG);
  assert_int_equal(vi_model_create_chain(2, mass, k, NULL, NULL), VI_ERR_ARG);
  assert_int_equal(vi_model_create_chain(2, NULL, k, NULL, &m), VI_ERR_ARG);
  assert_int_equal(vi_model_create_chain(0, mass, k, NULL, &m), VI_ERR_DIM);
  assert_int_equal(vi_model_memory_estimate(2, 1, 1, 0, 0, NULL), VI_ERR_ARG);
  assert_int_equal(vi_model_memory_estimate(2, 1, -1, 0, 0, &b), VI_ERR_DIM);
  assert_int_equal(vi_model_memory_estimate(2, 1, 1, 0, 2, &b), VI_ERR_ARG);
  assert_true(vi_model_memory(NULL) == 0);
  assert_int_equal(vi_model_bandwidth(NULL), -1);
  assert_null(vi_model_mass_band(NULL, &kd, &ld));
  assert_int_equal(kd, 0);
  assert_null(vi_model_damping_band(NULL, NULL, NULL));
  assert_null(vi_model_stiffness_band(NULL, NULL, NULL));
  assert_true(vi_model_omega_bound(NULL) == 0.0);
  double MB[4], CB[4], KB[4];
  assert_int_equal(vi_build_chain_band(2, mass, k, NULL, MB, CB, KB, 1),
                   VI_ERR_DIM);
  assert_int_equal(vi_build_chain_band(2, mass, k, NULL, NULL, CB, KB, 2),
                   VI_ERR_ARG);
  assert_int_equal(vi_build_chain_band(2, mass, k, NULL, MB, CB, KB, 2), VI_OK);
  /* chain of 2: K = [[2, -1], [-1, 1]] in 'U' form */
  assert_true(KB[1] == 2.0 && KB[2] == -1.0 && KB[3] == 1.0);
  assert_true(MB[1] == 1.0 && MB[2] == 0.0 && MB[3] == 1.0 && CB[3] == 0.0);
  /* before setup: views NULL; after it the setters are refused */
  assert_int_equal(vi_model_create_chain(2, mass, k, NULL, &m), VI_OK);
  assert_null(vi_model_stiffness_band(m, &kd, &ld));
  assert_true(vi_model_omega_bound(m) == 0.0);
  assert_int_equal(vi_model_set_mass_band(m, 1, NULL, 2), VI_ERR_ARG);
  double w[2] = {0, 1};
  assert_int_equal(vi_model_set_stop(m, w, 0.1, 0.5), VI_OK);
  assert_int_equal(vi_model_setup(m), VI_OK);
  assert_int_equal(vi_model_set_stiffness_band(m, 1, KB, 2), VI_ERR_STATE);
  assert_int_equal(vi_model_set_damping_band(m, 1, NULL, 2), VI_ERR_STATE);
  assert_int_equal(vi_model_set_damping(m, NULL, 2), VI_ERR_STATE);
  const double *kb = vi_model_stiffness_band(m, &kd, &ld);
  assert_non_null(kb);
  assert_true(kd == 1 && ld == 2 && kb[1] == 2.0 && kb[2] == -1.0);
  vi_model_destroy(&m);
  /* n = 1: the band is clamped to the diagonal */
  assert_int_equal(vi_model_create_chain(1, mass, k, NULL, &m), VI_OK);
  assert_int_equal(vi_model_bandwidth(m), 0);
  vi_model_destroy(&m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(band_equals_dense),
      cmocka_unit_test(band_sticking),
      cmocka_unit_test(band_two_stops),
      cmocka_unit_test(banded_mass),
      cmocka_unit_test(long_chain_energy),
      cmocka_unit_test(memory_linear),
      cmocka_unit_test(memory_exact),
      cmocka_unit_test(refusals),
      cmocka_unit_test(misuse),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
