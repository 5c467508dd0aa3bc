/* vi_bench_sparse - figures of issue 21 (finite-element structures in),
 * every ratio measured within this one run:
 *
 *  1. a fixed-free steel rod of N linear elements (consistent mass; N =
 *     100 000 by default) reduced to 20 modes through vi_sparse.h: set-up
 *     time (assembly, factorisation and eigensolve), peak RSS, frequency
 *     error against the exact discrete modes (test_sparse.c derives them),
 *     then its impacts and run time against the same 20-mode model written
 *     explicitly from the closed-form modes;
 *  2. the dense set-up, vi_model_setup at n = 2000 (a damped chain), against
 *     LAPACK dsygvd plus the two BLAS-3 products D = Psi^T C Psi and
 *     Psi^T M timed on the same matrices.
 *
 *   vi_bench_sparse [N [n_dense]]   (0 skips a part) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include <cblas.h>
#include <lapacke.h>

#include "vibroimpact.h"

static double now(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static double peak_rss_mb(void)
{
  struct rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_maxrss / 1024.0; /* Linux: kilobytes */
}

static const double E = 210e9, RHO = 7800.0, AREA = 3.14e-4, LEN = 1.0;

static double rod_lambda(int N, double th)
{
  double h = LEN / N;
  double s = sin(0.5 * th); /* 1 - cos th without cancellation */
  return 6.0 * E / (RHO * h * h) * 2.0 * s * s / (2.0 + cos(th));
}

typedef struct events {
  int count, cap;
  double *t, *vn;
} events;

static int collect(const vi_event *ev, void *user)
{
  events *e = user;
  if (ev->kind != VI_EVENT_IMPACT) return 0;
  if (e->count == e->cap) {
    e->cap = e->cap ? 2 * e->cap : 256;
    double *t = realloc(e->t, sizeof(double) * e->cap);
    if (!t) return 1;
    e->t = t;
    double *v = realloc(e->vn, sizeof(double) * e->cap);
    if (!v) return 1;
    e->vn = v;
  }
  e->t[e->count] = ev->t;
  e->vn[e->count++] = ev->vn;
  return 0;
}

static double run(const vi_model *m, double t_end, events *e)
{
  vi_sim *s = NULL;
  int st = vi_sim_create(m, &s);
  if (!st) st = vi_sim_set_method(s, VI_METHOD_EXACT);
  if (!st) st = vi_sim_set_tolerances(s, 1e-10, 1e-16);
  if (!st) st = vi_sim_set_initial(s, 0.0, NULL, NULL);
  if (!st) st = vi_sim_set_event_callback(s, collect, e, NULL);
  double t0 = now();
  if (!st) st = vi_sim_run(s, t_end);
  double dt = now() - t0;
  if (st < 0) fprintf(stderr, "run: %s\n", s ? vi_sim_errmsg(s) : "");
  vi_sim_destroy(&s);
  return st < 0 ? -1.0 : dt;
}

static int bench_rod(int N)
{
  const int k = 20, n = N;
  const double zeta = 0.02;
  printf("== fixed-free rod, %d linear elements (consistent mass), %d modes "
         "==\n", N, k);
  vi_fe *fe = NULL;
  vi_model *mex = NULL, *mfe = NULL;
  events ef = {0}, ex = {0};
  double *a = NULL;
  int rc = 1;
  double t0 = now();
  int *cp = malloc(sizeof(int) * (n + 1)), *ri = malloc(sizeof(int) * 2 * n);
  double *mv = malloc(sizeof(double) * 2 * n), *kv = malloc(sizeof(double) * 2 * n);
  if (!cp || !ri || !mv || !kv) goto done;
  double h = LEN / N, ke = E * AREA / h, me = RHO * AREA * h / 6.0;
  int c = 0;
  for (int j = 0; j < n; j++) { /* dof j = node j + 1; node 0 clamped */
    int nel = j + 1 < N ? 2 : 1;
    cp[j] = c;
    ri[c] = j;
    kv[c] = ke * nel;
    mv[c++] = 2.0 * me * nel;
    if (j + 1 < n) {
      ri[c] = j + 1;
      kv[c] = -ke;
      mv[c++] = me;
    }
  }
  cp[n] = c;
  double t_asm = now() - t0;
  double force = 1e3, xs = 2e-5, r = 0.7;
  double w1 = sqrt(rod_lambda(N, M_PI / (2.0 * N))), Om = 0.9 * w1;
  a = calloc((size_t)n, sizeof(double));
  if (!a) goto done;
  a[n - 1] = force;
  t0 = now();
  int st = vi_fe_create(n, &fe);
  if (!st) st = vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 0, cp, ri, mv);
  if (!st) st = vi_fe_set_stiffness_csc(fe, VI_CSC_LOWER, 0, cp, ri, kv);
  if (!st) st = vi_fe_set_modes(fe, k);
  if (!st) st = vi_fe_set_modal_damping(fe, 1, &zeta);
  if (!st) st = vi_fe_add_stop_dof(fe, n - 1, 1, xs, r);
  if (!st) st = vi_fe_set_forcing(fe, Om, a, NULL, NULL);
  double t_in = now() - t0;
  t0 = now();
  if (!st) st = vi_fe_setup(fe);
  double t_setup = now() - t0;
  if (st) {
    fprintf(stderr, "setup: %s\n", vi_fe_errmsg(fe));
    goto done;
  }
  printf("set-up: assembly %.3f s, CSC input %.3f s, factorise + "
         "eigensolve %.3f s; total %.3f s (target <= 10 s)\n", t_asm, t_in,
         t_setup, t_asm + t_in + t_setup);
  printf("peak RSS after set-up: %.1f MB (target <= 1536 MB)\n",
         peak_rss_mb());
  const double *om = vi_fe_omega(fe);
  double emax = 0.0, e1 = 0.0;
  for (int j = 1; j <= k; j++) {
    double exact = sqrt(rod_lambda(N, (2 * j - 1) * M_PI / (2.0 * N)));
    double e = fabs(om[j - 1] / exact - 1.0);
    emax = fmax(emax, e);
    if (j == 1) e1 = e;
  }
  printf("frequency error vs the closed form: max %.2e (mode 1 %.2e), "
         "backward error %.2e; lambda_max / lambda_1 = %.2e, so eps times "
         "it bounds lambda_1 to %.1e\n", emax, e1, vi_fe_residual(fe),
         rod_lambda(N, M_PI) / (w1 * w1),
         2.2e-16 * rod_lambda(N, M_PI) / (w1 * w1));
  /* the same model written from the closed-form modes */
  double K[400] = {0}, C[400] = {0}, wv[20], av[20];
  for (int j = 1; j <= k; j++) {
    double th = (2 * j - 1) * M_PI / (2.0 * N), q = 0.0;
    for (int e = 0; e < N; e++) {
      double sa = sin(e * th), sb = sin((e + 1) * th);
      q += me * (2 * sa * sa + 2 * sa * sb + 2 * sb * sb);
    }
    double lam = rod_lambda(N, th), tip = sin(N * th) / sqrt(q);
    K[(size_t)(j - 1) * 21] = lam;
    C[(size_t)(j - 1) * 21] = 2.0 * zeta * sqrt(lam);
    /* the sign of a mode is free: keep the reduction's */
    double sg = vi_fe_modal_stops(fe, NULL)[j - 1] * tip < 0 ? -1.0 : 1.0;
    wv[j - 1] = sg * tip;
    av[j - 1] = force * sg * tip;
  }
  st = vi_model_create(k, &mex);
  if (!st) st = vi_model_set_stiffness(mex, K, k);
  if (!st) st = vi_model_set_damping(mex, C, k);
  if (!st) st = vi_model_set_forcing(mex, Om, av, NULL, NULL);
  if (!st) st = vi_model_set_stop(mex, wv, xs, r);
  if (!st) st = vi_model_setup(mex);
  if (!st) st = vi_fe_create_model(fe, &mfe);
  if (st) {
    fprintf(stderr, "models: %s\n", vi_model_errmsg(mex));
    goto done;
  }
  double t_end = 60.0 * 2.0 * M_PI / Om;
  /* each twice, alternating, the faster kept: the first run also warms
   * the caches, and the machine may be shared */
  double tf = run(mfe, t_end, &ef), tx = run(mex, t_end, &ex);
  if (tf < 0 || tx < 0) goto done;
  events e2 = {0};
  double tf2 = run(mfe, t_end, &e2);
  free(e2.t); free(e2.vn);
  e2 = (events){0};
  double tx2 = run(mex, t_end, &e2);
  free(e2.t); free(e2.vn);
  if (tf2 > 0) tf = fmin(tf, tf2);
  if (tx2 > 0) tx = fmin(tx, tx2);
  double vmax = 0.0, dt = 0.0, dv = 0.0;
  int used = 0;
  for (int i = 0; i < ex.count; i++) vmax = fmax(vmax, fabs(ex.vn[i]));
  /* impacts above 1e-3 of the velocity scale, matched in order */
  int i = 0, j = 0;
  while (i < ef.count && j < ex.count) {
    if (fabs(ef.vn[i]) < 1e-3 * vmax) { i++; continue; }
    if (fabs(ex.vn[j]) < 1e-3 * vmax) { j++; continue; }
    dt = fmax(dt, fabs(ef.t[i] - ex.t[j]) / (2.0 * M_PI / Om));
    dv = fmax(dv, fabs(ef.vn[i] - ex.vn[j]) / vmax);
    used++;
    i++;
    j++;
  }
  printf("impacts over %.0f forcing periods: %d (FE) and %d (closed-form "
         "modes); %d above 1e-3 of v_max = %.3e m/s compared: max |dt| = "
         "%.2e periods (target 1e-5), max |dv_n| = %.2e v_max (target "
         "1e-4)\n", t_end * Om / (2.0 * M_PI), ef.count, ex.count, used,
         vmax, dt, dv);
  printf("run time (best of 2): FE model %.3f s, explicit 20-mode model "
         "%.3f s, ratio %.2f\n", tf, tx, tf / tx);
  rc = 0;
done:
  free(ef.t); free(ef.vn); free(ex.t); free(ex.vn);
  vi_model_destroy(&mex);
  vi_model_destroy(&mfe);
  vi_fe_destroy(&fe);
  free(a); free(cp); free(ri); free(mv); free(kv);
  return rc;
}

static int bench_dense(int n)
{
  printf("== dense set-up, damped chain of %d masses ==\n", n);
  size_t nn = (size_t)n * n;
  double *M = malloc(sizeof(double) * nn), *C = malloc(sizeof(double) * nn);
  double *K = malloc(sizeof(double) * nn), *W1 = malloc(sizeof(double) * nn);
  double *W2 = malloc(sizeof(double) * nn), *W3 = malloc(sizeof(double) * nn);
  double *mass = malloc(sizeof(double) * n), *kk = malloc(sizeof(double) * n);
  double *cc = malloc(sizeof(double) * n), *lam = malloc(sizeof(double) * n);
  double *w = calloc((size_t)n, sizeof(double));
  if (!M || !C || !K || !W1 || !W2 || !W3 || !mass || !kk || !cc || !lam ||
      !w) {
    free(M); free(C); free(K); free(W1); free(W2); free(W3);
    free(mass); free(kk); free(cc); free(lam); free(w);
    return 1;
  }
  for (int i = 0; i < n; i++) {
    mass[i] = 1.0 + 0.1 * (i % 3);
    kk[i] = 1.0 + 0.05 * (i % 5);
    cc[i] = 0.02 * kk[i];
  }
  w[n - 1] = 1.0;
  vi_build_chain(n, mass, kk, cc, M, C, K, n);
  vi_model *m = NULL;
  int st = vi_model_create(n, &m);
  if (!st) st = vi_model_set_mass(m, M, n);
  if (!st) st = vi_model_set_damping(m, C, n);
  if (!st) st = vi_model_set_stiffness(m, K, n);
  if (!st) st = vi_model_set_stop(m, w, 0.1, 0.7);
  double t0 = now();
  if (!st) st = vi_model_setup(m);
  double t_model = now() - t0;
  if (st) {
    fprintf(stderr, "setup: %s\n", vi_model_errmsg(m));
    goto done;
  }
  /* the reference: dsygvd and the two products, on copies */
  memcpy(W1, K, sizeof(double) * nn);
  memcpy(W2, M, sizeof(double) * nn);
  t0 = now();
  LAPACKE_dsygvd(LAPACK_COL_MAJOR, 1, 'V', 'L', n, W1, n, W2, n, lam);
  double t_eig = now() - t0;
  t0 = now();
  cblas_dsymm(CblasColMajor, CblasLeft, CblasLower, n, n, 1.0, C, n, W1, n,
              0.0, W2, n);
  cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, n, n, n, 1.0, W1, n,
              W2, n, 0.0, W3, n);
  cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, n, n, n, 1.0, W1, n,
              M, n, 0.0, W2, n);
  double t_prod = now() - t0;
  printf("vi_model_setup %.3f s; dsygvd %.3f s + products %.3f s = %.3f s; "
         "ratio %.2f (target <= 2)\n", t_model, t_eig, t_prod,
         t_eig + t_prod, t_model / (t_eig + t_prod));
  /* the same modes: omega_1 from the model and from the reference */
  printf("check: omega_1 %.15g vs %.15g\n", vi_model_omega(m)[0], sqrt(lam[0]));
done:
  vi_model_destroy(&m);
  free(M); free(C); free(K); free(W1); free(W2); free(W3);
  free(mass); free(kk); free(cc); free(lam); free(w);
  return st != 0;
}

int main(int argc, char **argv)
{
  int N = argc > 1 ? (int)strtol(argv[1], NULL, 10) : 100000;
  int nd = argc > 2 ? (int)strtol(argv[2], NULL, 10) : 2000;
  int st = 0;
  if (N > 40) st |= bench_rod(N);
  if (nd > 0) st |= bench_dense(nd);
  return st;
}
