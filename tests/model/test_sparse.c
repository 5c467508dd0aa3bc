/* test_sparse.c - finite-element structures in (vi_sparse.h): the partial
 * eigensolve against the exact discrete modes of linear-element rods, CSC
 * storage variants, malformed CSC, damping projections and host-supplied
 * modes against the same model written densely.
 *
 * The closed form (derived for this test): a rod of N linear elements of
 * length h, stiffness EA/h [1 -1; -1 1] and consistent mass rho A h / 6
 * [2 1; 1 2].  An interior row reads
 *   (EA/h)(-u_{i-1} + 2 u_i - u_{i+1}) = lambda (rho A h / 6)(u_{i-1} + 4 u_i
 *   + u_{i+1}),
 * which u_i = sin(i theta) or cos(i theta) satisfies with
 *   lambda(theta) = (6 E / (rho h^2)) (1 - cos theta) / (2 + cos theta).
 * Fixed at node 0, free at node N: the free end's half row holds when
 * u_{N+1} = u_{N-1}, i.e. cos(N theta) = 0: theta_j = (2j - 1) pi / (2N),
 * u_i = sin(i theta_j), i = 1..N.  Free-free (nodes 0..N): u_i = cos(i
 * theta_j), theta_j = j pi / N, j = 0 the rigid translation. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vi_testutil.h"

#define assert_fe_msg(fe, s) assert_non_null(strstr(vi_fe_errmsg(fe), (s)))

static const double E = 210e9, RHO = 7800.0, AREA = 3.14e-4, LEN = 1.0;

/* The rod in lower CSC storage (0-based): dofs are nodes first..N. */
typedef struct rod {
  int n, nnz;
  int colptr[2002], rowind[4004];
  double m[4004], k[4004];
} rod;

static void rod_build(rod *r, int N, int fixed)
{
  int first = fixed ? 1 : 0, n = N + 1 - first, c = 0;
  double h = LEN / N, ke = E * AREA / h, me = RHO * AREA * h / 6.0;
  r->n = n;
  for (int j = 0; j < n; j++) {
    int node = j + first;
    /* elements to the left (node - 1, node) and right (node, node + 1) */
    int nel = (node > 0) + (node < N);
    r->colptr[j] = c;
    r->rowind[c] = j;
    r->k[c] = ke * nel;
    r->m[c++] = 2.0 * me * nel;
    if (j + 1 < n) {
      r->rowind[c] = j + 1;
      r->k[c] = -ke;
      r->m[c++] = me;
    }
  }
  r->colptr[n] = c;
  r->nnz = c;
}

static double rod_lambda(int N, double theta)
{
  double h = LEN / N;
  double s = sin(0.5 * theta); /* 1 - cos theta without cancellation */
  return 6.0 * E / (RHO * h * h) * 2.0 * s * s / (2.0 + cos(theta));
}

static vi_fe *rod_fe(const rod *r, int k)
{
  vi_fe *fe = NULL;
  assert_int_equal(vi_fe_create(r->n, &fe), VI_OK);
  assert_int_equal(vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 0, r->colptr,
                                      r->rowind, r->m), VI_OK);
  assert_int_equal(vi_fe_set_stiffness_csc(fe, VI_CSC_LOWER, 0, r->colptr,
                                           r->rowind, r->k), VI_OK);
  assert_int_equal(vi_fe_set_modes(fe, k), VI_OK);
  return fe;
}

static rod R; /* large: static storage */

/* Fixed-free rod of 400 elements, 10 modes by shift-invert Lanczos. */
static void test_fixed_free_rod(void **state)
{
  (void)state;
  const int N = 400, k = 10;
  rod_build(&R, N, 1);
  vi_fe *fe = rod_fe(&R, k);
  assert_int_equal(vi_fe_add_stop_dof(fe, N - 1, 1, 1e-4, 0.8), VI_OK);
  int outs[2] = {N - 1, N / 2 - 1};
  assert_int_equal(vi_fe_set_outputs(fe, 2, outs), VI_OK);
  assert_int_equal(vi_fe_set_keep_shapes(fe, 1), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_OK);
  assert_true(vi_fe_shift(fe) == 0.0); /* K regular: no shift needed */
  const double *om = vi_fe_omega(fe);
  /* Round-off bound: the eigenpairs' backward error is ~eps ||K||, so
   * lambda_j moves by ~eps lambda_max / lambda_j relative; lambda_max /
   * lambda_1 = 12 N^2 / (pi/2)^2 * (1/3) ~ 8e5 here: 2e-10.  1e-9. */
  for (int j = 1; j <= k; j++) {
    double th = (2 * j - 1) * M_PI / (2.0 * N);
    assert_close(om[j - 1] / sqrt(rod_lambda(N, th)), 1.0, 1e-9);
  }
  assert_true(vi_fe_residual(fe) < 1e-13);
  /* the static flexibility at the tip is exact for linear elements:
   * w^T K^-1 w = L / (E A) */
  double dyn, sta;
  assert_int_equal(vi_fe_stop_compliance(fe, 0, &dyn, &sta), VI_OK);
  assert_close(sta * E * AREA / LEN, 1.0, 1e-12);
  /* the kept modes carry part of the static flexibility: sum psi^2 / lambda
   * is below and, with ten modes, within 1 % of it (8 / pi^2 sum 1/(2j-1)^2
   * of the continuous rod: 0.9797 for ten modes) */
  int ld;
  const double *ps = vi_fe_modal_stops(fe, &ld);
  double part = 0.0, dpart = 0.0;
  for (int j = 0; j < k; j++) {
    part += ps[j] * ps[j] / (om[j] * om[j]);
    dpart += ps[j] * ps[j];
  }
  assert_true(part < sta && part > 0.975 * sta);
  assert_true(dpart < dyn);
  /* shapes: mass-normalised sampled sines, largest entry positive */
  const double *Psi = vi_fe_shapes(fe, &ld);
  assert_non_null(Psi);
  assert_int_equal(ld, R.n);
  const double *Po = vi_fe_output_shapes(fe, &ld);
  assert_int_equal(ld, 2);
  for (int j = 1; j <= k; j++) {
    double th = (2 * j - 1) * M_PI / (2.0 * N), h = LEN / N;
    /* u^T M u of u_i = sin(i theta) by the element sums, independently */
    double q = 0.0;
    for (int e = 0; e < N; e++) {
      double a = sin(e * th), b = sin((e + 1) * th);
      q += RHO * AREA * h / 6.0 * (2 * a * a + 2 * a * b + 2 * b * b);
    }
    double cst = 1.0 / sqrt(q), smax = 0.0;
    int imax = 0;
    for (int i = 1; i <= N; i++)
      if (fabs(sin(i * th)) > smax * (1.0 + 1e-9)) {
        smax = fabs(sin(i * th));
        imax = i;
      }
    double sgn = sin(imax * th) < 0 ? -1.0 : 1.0;
    for (int i = 1; i <= N; i += 37)
      assert_close(Psi[(i - 1) + (size_t)(j - 1) * R.n],
                   sgn * cst * sin(i * th), 1e-9 * cst);
    assert_close(Po[0 + 2 * (j - 1)], sgn * cst * sin(N * th), 1e-9 * cst);
    assert_true(Po[1 + 2 * (j - 1)] == Psi[N / 2 - 1 + (size_t)(j - 1) * R.n]);
    assert_true(ps[j - 1] == Po[0 + 2 * (j - 1)]);
  }
  /* the physical state at the outputs from modal coordinates, and back */
  double q[10], x[2], qb[10];
  for (int j = 0; j < k; j++) q[j] = 1.0 / (j + 1);
  assert_int_equal(vi_fe_to_outputs(fe, 1, q, k, x, 2), VI_OK);
  double *xf = malloc(sizeof(double) * R.n);
  {
    double s0 = 0.0, s1 = 0.0;
    for (int j = 0; j < k; j++) {
      s0 += Po[2 * (size_t)j] * q[j];
      s1 += Po[1 + 2 * (size_t)j] * q[j];
    }
    assert_close(x[0], s0, 1e-15 * fabs(s0) + 1e-300);
    assert_close(x[1], s1, 1e-14 * fabs(s1) + 1e-300);
  }
  for (int i = 0; i < R.n; i++) {
    xf[i] = 0.0;
    for (int j = 0; j < k; j++) xf[i] += Psi[i + (size_t)j * R.n] * q[j];
  }
  assert_int_equal(vi_fe_to_modal(fe, xf, qb), VI_OK);
  for (int j = 0; j < k; j++) assert_close(qb[j], q[j], 1e-12);
  free(xf);
  /* the model: M = I, K = diag(omega^2), stop psi */
  vi_model *m = NULL;
  assert_int_equal(vi_fe_create_model(fe, &m), VI_OK);
  assert_int_equal(vi_model_n(m), k);
  for (int j = 0; j < k; j++)
    assert_close(vi_model_omega(m)[j] / om[j], 1.0, 1e-14);
  assert_close(vi_model_stop_compliance(m), dpart, 1e-12 * dpart);
  vi_model_destroy(&m);
  vi_fe_destroy(&fe);
  assert_null(fe);
}

/* Free-free rod: K singular, the rigid translation at omega = 0 found with
 * the automatic negative shift. */
static void test_free_free_rod(void **state)
{
  (void)state;
  const int N = 200, k = 6;
  rod_build(&R, N, 0);
  vi_fe *fe = rod_fe(&R, k);
  assert_int_equal(vi_fe_add_stop_dof(fe, 0, -1, 0.0, 0.0), VI_OK);
  assert_int_equal(vi_fe_set_keep_shapes(fe, 1), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_OK);
  assert_true(vi_fe_shift(fe) < 0.0);
  const double *om = vi_fe_omega(fe);
  double w1 = sqrt(rod_lambda(N, M_PI / N));
  assert_true(om[0] == 0.0); /* snapped: round-off of a zero eigenvalue */
  for (int j = 1; j < k; j++)
    assert_close(om[j] / sqrt(rod_lambda(N, j * M_PI / N)), 1.0, 1e-9);
  (void)w1;
  /* the rigid mode: uniform, 1 / sqrt(total mass) */
  int ld;
  const double *Psi = vi_fe_shapes(fe, &ld);
  double u = 1.0 / sqrt(RHO * AREA * LEN);
  for (int i = 0; i <= N; i += 20) assert_close(Psi[i], u, 1e-9 * u);
  double dyn, sta;
  assert_int_equal(vi_fe_stop_compliance(fe, 0, &dyn, &sta), VI_OK);
  assert_true(isinf(sta));
  /* a shift above the first elastic eigenvalue is refused */
  vi_fe *bad = rod_fe(&R, k);
  assert_int_equal(vi_fe_add_stop_dof(bad, 0, 1, 0.0, 0.5), VI_OK);
  assert_int_equal(vi_fe_set_shift(bad, 1.5 * w1 * w1), VI_OK);
  assert_int_equal(vi_fe_setup(bad), VI_ERR_NOT_SPD);
  assert_fe_msg(bad, "below the lowest eigenvalue");
  vi_fe_destroy(&bad);
  /* sigma = 0 on a free structure is refused with a hint */
  bad = rod_fe(&R, k);
  assert_int_equal(vi_fe_add_stop_dof(bad, 0, 1, 0.0, 0.5), VI_OK);
  assert_int_equal(vi_fe_set_shift(bad, 0.0), VI_OK);
  assert_int_equal(vi_fe_setup(bad), VI_ERR_NOT_SPD);
  assert_fe_msg(bad, "sigma < 0");
  vi_fe_destroy(&bad);
  vi_fe_destroy(&fe);
}

/* A clamped Euler-Bernoulli beam of N Hermite elements (EI = rho A = L = 1;
 * dofs w, theta per node): the tip's static flexibility is exact for
 * cubic elements, L^3 / (3 EI); the frequencies converge to the analytic
 * cantilever's beta_j^2 as h^4 (consistent mass: the eigenvalue error of
 * cubic elements is O(h^(2(p + 1 - m))) = O(h^4)), so halving h divides the
 * error by 16.  Two dofs per node of different scales (w and theta) test
 * the factorisation and the Lanczos solver on a non-M-matrix operator. */
static void beam_csc(int N, int *cp, int *ri, double *mv, double *kv)
{
  int n = 2 * N, c = 0;
  double h = 1.0 / N;
  double ke[4][4] = {{12, 6 * h, -12, 6 * h}, {6 * h, 4 * h * h, -6 * h, 2 * h * h},
                     {-12, -6 * h, 12, -6 * h}, {6 * h, 2 * h * h, -6 * h, 4 * h * h}};
  double me[4][4] = {{156, 22 * h, 54, -13 * h}, {22 * h, 4 * h * h, 13 * h, -3 * h * h},
                     {54, 13 * h, 156, -22 * h}, {-13 * h, -3 * h * h, -22 * h, 4 * h * h}};
  /* node i (1..N) has dofs 2(i-1), 2(i-1)+1; element e joins nodes e, e+1 */
  for (int j = 0; j < n; j++) {
    int node = j / 2 + 1;
    cp[j] = c;
    for (int i = j; i < n && i <= 2 * node + 1; i++) { /* lower band */
      double kk = 0.0, mm = 0.0;
      for (int e = node - 1; e <= node; e++) { /* elements holding node */
        if (e < 0 || e >= N) continue;
        int a = j - 2 * (e - 1), b = i - 2 * (e - 1); /* local 0..3 */
        if (a < 0 || a > 3 || b < 0 || b > 3) continue;
        kk += ke[b][a] / (h * h * h);
        mm += me[b][a] * h / 420.0;
      }
      if (kk == 0.0 && mm == 0.0) continue;
      ri[c] = i;
      kv[c] = kk;
      mv[c++] = mm;
    }
  }
  cp[n] = c;
}

static void test_hermite_beam(void **state)
{
  (void)state;
  double err[2][4];
  for (int pass = 0; pass < 2; pass++) {
    int N = pass ? 40 : 20, n = 2 * N;
    int *cp = malloc(sizeof(int) * (size_t)(n + 1)), *ri = malloc(sizeof(int) * 4 * (size_t)n);
    double *mv = malloc(sizeof(double) * 4 * (size_t)n), *kv = malloc(sizeof(double) * 4 * (size_t)n);
    assert_true(cp && ri && mv && kv);
    beam_csc(N, cp, ri, mv, kv);
    vi_fe *fe = NULL;
    assert_int_equal(vi_fe_create(n, &fe), VI_OK);
    assert_int_equal(vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 0, cp, ri, mv), VI_OK);
    assert_int_equal(vi_fe_set_stiffness_csc(fe, VI_CSC_LOWER, 0, cp, ri, kv), VI_OK);
    assert_int_equal(vi_fe_set_modes(fe, 4), VI_OK);
    assert_int_equal(vi_fe_add_stop_dof(fe, n - 2, 1, 0.0, 0.5), VI_OK); /* tip w */
    assert_int_equal(vi_fe_setup(fe), VI_OK);
    double dyn, sta;
    assert_int_equal(vi_fe_stop_compliance(fe, 0, &dyn, &sta), VI_OK);
    /* a solve with K, whose condition grows as N^4 (~5e7 at N = 40,
     * rotations and deflections mixed): eps cond(K) ~ 1e-8 */
    assert_close(sta * 3.0, 1.0, 1e-8);
    for (int j = 0; j < 4; j++) {
      double b = vi_cantilever_beta(j);
      err[pass][j] = vi_fe_omega(fe)[j] / (b * b) - 1.0;
      /* the consistent mass bounds the eigenvalues from above */
      assert_true(err[pass][j] > 0.0);
    }
    /* the tip's modal amplitudes: |phi_j(1)| = 2 for the unit cantilever */
    const double *ps = vi_fe_modal_stops(fe, NULL);
    for (int j = 0; j < 4; j++) assert_close(fabs(ps[j]), 2.0, 2e-3);
    vi_fe_destroy(&fe);
    free(cp); free(ri); free(mv); free(kv);
  }
  for (int j = 0; j < 4; j++) {
    double ratio = err[0][j] / err[1][j];
    print_message("beam mode %d: error %.3e (N = 20), %.3e (N = 40), ratio %.2f\n",
                  j + 1, err[0][j], err[1][j], ratio);
    assert_true(ratio > 14.0 && ratio < 17.0);
  }
}

/* Two disconnected free rods in one model: every eigenvalue double, two
 * rigid modes (as the six of a free 3-D body): Lanczos must return both
 * members of each pair, M-orthonormal. */
static void test_degenerate_modes(void **state)
{
  (void)state;
  const int N = 100, k = 8;
  rod_build(&R, N, 0);
  int n1 = R.n, n = 2 * n1, nnz = R.nnz;
  int *cp = malloc(sizeof(int) * (size_t)(n + 1)), *ri = malloc(sizeof(int) * 2 * (size_t)nnz);
  double *mv = malloc(sizeof(double) * 2 * (size_t)nnz), *kv = malloc(sizeof(double) * 2 * (size_t)nnz);
  assert_true(cp && ri && mv && kv);
  for (int b = 0; b < 2; b++) {
    for (int j = 0; j < n1; j++) cp[b * n1 + j] = R.colptr[j] + b * nnz;
    for (int p = 0; p < nnz; p++) {
      ri[b * nnz + p] = R.rowind[p] + b * n1;
      mv[b * nnz + p] = R.m[p];
      kv[b * nnz + p] = R.k[p];
    }
  }
  cp[n] = 2 * nnz;
  vi_fe *fe = NULL;
  assert_int_equal(vi_fe_create(n, &fe), VI_OK);
  assert_int_equal(vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 0, cp, ri, mv), VI_OK);
  assert_int_equal(vi_fe_set_stiffness_csc(fe, VI_CSC_LOWER, 0, cp, ri, kv), VI_OK);
  assert_int_equal(vi_fe_set_modes(fe, k), VI_OK);
  assert_int_equal(vi_fe_add_stop_dof(fe, 0, -1, 0.0, 0.5), VI_OK);
  assert_int_equal(vi_fe_set_keep_shapes(fe, 1), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_OK);
  const double *om = vi_fe_omega(fe);
  assert_true(om[0] == 0.0 && om[1] == 0.0);
  for (int j = 2; j < k; j++) {
    int pair = j / 2; /* modes 2j and 2j + 1 share theta = pair pi / N */
    assert_close(om[j] / sqrt(rod_lambda(N, pair * M_PI / N)), 1.0, 1e-9);
  }
  /* Psi^T M Psi = I, the degenerate pairs included: eps times the
   * Lanczos basis' loss of orthogonality, 1e-10 */
  int ld;
  const double *Psi = vi_fe_shapes(fe, &ld);
  /* M Psi from the stored lower triangle */
  const int *scp, *sri;
  const double *smv;
  int snz;
  assert_int_equal(vi_fe_matrix_csc(fe, VI_FE_MASS, &snz, &scp, &sri, &smv), VI_OK);
  double *Mp = calloc((size_t)n, sizeof(double));
  assert_non_null(Mp);
  for (int b = 0; b < k; b++) {
    const double *pb = Psi + (size_t)b * ld;
    memset(Mp, 0, sizeof(double) * (size_t)n);
    for (int j = 0; j < n; j++)
      for (int p = scp[j]; p < scp[j + 1]; p++) {
        Mp[sri[p]] += smv[p] * pb[j];
        if (sri[p] != j) Mp[j] += smv[p] * pb[sri[p]];
      }
    for (int a = 0; a < k; a++) {
      double d = 0.0;
      for (int i = 0; i < n; i++) d += Psi[i + (size_t)a * ld] * Mp[i];
      assert_close(d, a == b ? 1.0 : 0.0, 1e-10);
    }
  }
  free(Mp);
  vi_fe_destroy(&fe);
  free(cp); free(ri); free(mv); free(kv);
}

/* Lanczos held to one restart: the 400-element rod's 10 lowest modes need
 * several (their eigenvalues are spread by lambda_10 / lambda_1 = 361 and
 * a basis of 21 vectors sees only the start of the spectrum), so ARPACK
 * stops with info 1, which the message gives in words with the cure. */
static void test_lanczos_not_converged(void **state)
{
  (void)state;
  rod_build(&R, 400, 1);
  vi_fe *fe = rod_fe(&R, 10);
  assert_int_equal(vi_fe_set_eigensolver(fe, 0.0, 21, 1), VI_OK);
  assert_int_equal(vi_fe_add_stop_dof(fe, 399, 1, 1e-4, 0.8), VI_OK);
  int st = vi_fe_setup(fe);
  assert_int_equal(st, VI_ERR_NOT_CONVERGED);
  assert_fe_msg(fe, "info 1: the maximum number of iterations was taken");
  assert_fe_msg(fe, "raise maxit or ncv");
  vi_fe_destroy(&fe);
}

/* Every mode of a small rod (k >= n - 1: LAPACK's dense solver). */
static void test_small_rod_dense(void **state)
{
  (void)state;
  const int N = 5;
  rod_build(&R, N, 1);
  vi_fe *fe = rod_fe(&R, N);
  assert_int_equal(vi_fe_add_stop_dof(fe, N - 1, 1, 1e-4, 0.8), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_OK);
  for (int j = 1; j <= N; j++)
    assert_close(vi_fe_omega(fe)[j - 1] /
                     sqrt(rod_lambda(N, (2 * j - 1) * M_PI / (2.0 * N))),
                 1.0, 1e-13);
  double dyn, sta;
  assert_int_equal(vi_fe_stop_compliance(fe, 0, &dyn, &sta), VI_OK);
  assert_close(sta * E * AREA / LEN, 1.0, 1e-12);
  vi_fe_destroy(&fe);
}

/* Lower and full storage, 0- and 1-based: the same stored matrices and
 * bit-identical modes. */
static void test_storage_variants(void **state)
{
  (void)state;
  const int N = 60;
  rod_build(&R, N, 1);
  int n = R.n;
  /* full storage, built by mirroring */
  int *fp = malloc(sizeof(int) * (n + 1)), *fi = malloc(sizeof(int) * 3 * n);
  double *fm = malloc(sizeof(double) * 3 * n), *fk = malloc(sizeof(double) * 3 * n);
  int c = 0;
  for (int j = 0; j < n; j++) {
    fp[j] = c;
    if (j > 0) {
      fi[c] = j - 1;
      fm[c] = R.m[R.colptr[j - 1] + 1];
      fk[c++] = R.k[R.colptr[j - 1] + 1];
    }
    for (int p = R.colptr[j]; p < R.colptr[j + 1]; p++) {
      fi[c] = R.rowind[p];
      fm[c] = R.m[p];
      fk[c++] = R.k[p];
    }
  }
  fp[n] = c;
  double om[4][8];
  const int *cp[4], *ri[4];
  const double *vv[4];
  int nz[4];
  vi_fe *fes[4];
  for (int v = 0; v < 4; v++) {
    int full = v / 2, base = v % 2;
    const int *P = full ? fp : R.colptr, *I = full ? fi : R.rowind;
    int nnz = P[n];
    int *P1 = malloc(sizeof(int) * (n + 1));
    int *I1 = malloc(sizeof(int) * (size_t)(nnz > 0 ? nnz : 1));
    for (int j = 0; j <= n; j++) P1[j] = P[j] + base;
    for (int p = 0; p < nnz; p++) I1[p] = I[p] + base;
    vi_fe *fe = NULL;
    assert_int_equal(vi_fe_create(n, &fe), VI_OK);
    int st = full ? VI_CSC_FULL : VI_CSC_LOWER;
    assert_int_equal(vi_fe_set_mass_csc(fe, st, base, P1, I1, full ? fm : R.m), VI_OK);
    assert_int_equal(vi_fe_set_stiffness_csc(fe, st, base, P1, I1, full ? fk : R.k), VI_OK);
    free(P1);
    free(I1);
    assert_int_equal(vi_fe_set_modes(fe, 8), VI_OK);
    assert_int_equal(vi_fe_add_stop_dof(fe, n - 1, 1, 0.0, 0.5), VI_OK);
    assert_int_equal(vi_fe_setup(fe), VI_OK);
    memcpy(om[v], vi_fe_omega(fe), sizeof om[v]);
    assert_int_equal(vi_fe_matrix_csc(fe, VI_FE_STIFFNESS, &nz[v], &cp[v],
                                      &ri[v], &vv[v]), VI_OK);
    fes[v] = fe;
  }
  for (int v = 1; v < 4; v++) {
    assert_int_equal(nz[v], nz[0]);
    assert_memory_equal(cp[v], cp[0], sizeof(int) * (n + 1));
    assert_memory_equal(ri[v], ri[0], sizeof(int) * nz[0]);
    assert_memory_equal(vv[v], vv[0], sizeof(double) * nz[0]);
    assert_memory_equal(om[v], om[0], sizeof om[0]);
  }
  assert_int_equal(nz[0], R.nnz);
  for (int v = 0; v < 4; v++) vi_fe_destroy(&fes[v]);
  free(fp); free(fi); free(fm); free(fk);
}

/* Malformed CSC: each a clear error naming the column and row. */
static void test_bad_csc(void **state)
{
  (void)state;
  vi_fe *fe = NULL;
  assert_int_equal(vi_fe_create(3, &fe), VI_OK);
  /* 3 x 3, lower: (1,1) (2,1) (2,2) (3,2) (3,3) */
  int p[4] = {0, 2, 4, 5}, i[5] = {0, 1, 1, 2, 2};
  double v[5] = {2, -1, 2, -1, 1};
  int iu[5] = {1, 0, 1, 2, 2}; /* column 1 unsorted */
  assert_int_equal(vi_fe_set_stiffness_csc(fe, VI_CSC_LOWER, 0, p, iu, v), VI_ERR_DIM);
  assert_fe_msg(fe, "column 1: row 1 after row 2");
  int io[5] = {0, 3, 1, 2, 2}; /* row index 3 out of range (0-based) */
  assert_int_equal(vi_fe_set_stiffness_csc(fe, VI_CSC_LOWER, 0, p, io, v), VI_ERR_DIM);
  assert_fe_msg(fe, "row index 3 out of range 0..2");
  int i1[5] = {1, 2, 2, 3, 4}; /* 1-based: 4 is out of range */
  int p1[4] = {1, 3, 5, 6};
  assert_int_equal(vi_fe_set_stiffness_csc(fe, VI_CSC_LOWER, 1, p1, i1, v), VI_ERR_DIM);
  assert_fe_msg(fe, "row index 4 out of range 1..3");
  int iup[5] = {0, 1, 0, 1, 2}; /* (1,2) above the diagonal in lower storage */
  int pup[4] = {0, 2, 4, 5};
  assert_int_equal(vi_fe_set_stiffness_csc(fe, VI_CSC_LOWER, 0, pup, iup, v), VI_ERR_DIM);
  assert_fe_msg(fe, "K(1,2) lies above the diagonal");
  /* full storage, not symmetric: (2,1) = -1 but (1,2) = -0.5 */
  int pf[4] = {0, 2, 5, 7}, ifl[7] = {0, 1, 0, 1, 2, 1, 2};
  double vf[7] = {2, -1, -0.5, 2, -1, -1, 1};
  assert_int_equal(vi_fe_set_stiffness_csc(fe, VI_CSC_FULL, 0, pf, ifl, vf), VI_ERR_NOT_SYMMETRIC);
  assert_fe_msg(fe, "K(2,1) = -1 but K(1,2) = -0.5");
  /* a missing mirror is a zero: (3,2) without (2,3) */
  int pm[4] = {0, 2, 4, 6}, im[6] = {0, 1, 0, 1, 1, 2};
  double vm[6] = {2, -1, -1, 2, -1, 1};
  assert_int_equal(vi_fe_set_stiffness_csc(fe, VI_CSC_FULL, 0, pm, im, vm), VI_ERR_NOT_SYMMETRIC);
  assert_fe_msg(fe, "K(3,2) = 0 but K(2,3) = -1");
  int pd[4] = {0, 2, 1, 5}; /* colptr decreasing */
  assert_int_equal(vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 0, pd, i, v), VI_ERR_DIM);
  assert_fe_msg(fe, "colptr decreases at column 2");
  int pb[4] = {1, 3, 5, 6}; /* colptr(1) is not the base 0 */
  assert_int_equal(vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 0, pb, i, v), VI_ERR_DIM);
  assert_int_equal(vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 2, p, i, v), VI_ERR_DIM);
  assert_fe_msg(fe, "index base 2");
  double vn[5] = {2, NAN, 2, -1, 1};
  assert_int_equal(vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 0, p, i, vn), VI_ERR_NONFINITE);
  assert_fe_msg(fe, "M(2,1)");
  /* M indefinite (eigenvalues of [1 2; 2 1] block): refused at setup */
  double vmi[5] = {1, 2, 1, 0, 1};
  assert_int_equal(vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 0, p, i, vmi), VI_OK);
  assert_int_equal(vi_fe_set_stiffness_csc(fe, VI_CSC_LOWER, 0, p, i, v), VI_OK);
  assert_int_equal(vi_fe_set_modes(fe, 1), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_ERR_STOP_VECTOR);
  assert_int_equal(vi_fe_add_stop_dof(fe, 2, 1, 0.0, 0.5), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_ERR_NOT_SPD);
  assert_fe_msg(fe, "M is not positive definite");
  /* a zero diagonal of M with a non-zero in its row: indefinite, caught
   * before any factorisation (a whole zero row is a massless dof) */
  double vz[5] = {0, 0.5, 1, 0, 1};
  assert_int_equal(vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 0, p, i, vz), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_ERR_NOT_PSD);
  assert_fe_msg(fe, "M(1,1) = 0 while its row has non-zero entries");
  /* a negative mass */
  double vng[5] = {1, 0, -2, 0, 1};
  assert_int_equal(vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 0, p, i, vng), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_ERR_NOT_PSD);
  assert_fe_msg(fe, "M(2,2) = -2");
  /* K indefinite */
  double vk[5] = {1, 0, -1, 0, 1}, vmo[5] = {1, 0, 1, 0, 1};
  assert_int_equal(vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 0, p, i, vmo), VI_OK);
  assert_int_equal(vi_fe_set_stiffness_csc(fe, VI_CSC_LOWER, 0, p, i, vk), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_ERR_NOT_PSD);
  assert_fe_msg(fe, "K is not positive semidefinite");
  vi_fe_destroy(&fe);
}

/* Damping: Rayleigh, modal ratios and an explicit C = a M + b K, whose
 * projection must be diag(a + b lambda_j). */
static void test_damping(void **state)
{
  (void)state;
  const int N = 80, k = 5;
  rod_build(&R, N, 1);
  double a = 3.0, b = 2e-6;
  double cv[4004];
  for (int p = 0; p < R.nnz; p++) cv[p] = a * R.m[p] + b * R.k[p];
  for (int kind = 0; kind < 3; kind++) {
    vi_fe *fe = rod_fe(&R, k);
    assert_int_equal(vi_fe_add_stop_dof(fe, R.n - 1, 1, 0.0, 0.5), VI_OK);
    double z[5] = {0.01, 0.02, 0.03, 0.04, 0.05};
    if (kind == 0) assert_int_equal(vi_fe_set_rayleigh(fe, a, b), VI_OK);
    if (kind == 1) assert_int_equal(vi_fe_set_damping_csc(fe, VI_CSC_LOWER, 0,
                                        R.colptr, R.rowind, cv), VI_OK);
    if (kind == 2) assert_int_equal(vi_fe_set_modal_damping(fe, 5, z), VI_OK);
    assert_int_equal(vi_fe_setup(fe), VI_OK);
    int ld;
    const double *D = vi_fe_modal_damping(fe, &ld), *om = vi_fe_omega(fe);
    assert_int_equal(ld, k);
    for (int j = 0; j < k; j++)
      for (int i = 0; i < k; i++) {
        double want = i != j ? 0.0
                      : kind == 2 ? 2.0 * z[j] * om[j]
                                  : a + b * om[j] * om[j];
        /* explicit C: Psi^T C Psi is exact to eps times ||C|| / ||D_jj||,
         * C's largest eigenvalue b lambda_max ~ 4e4 * D_11 here */
        assert_close(D[i + j * k], want,
                     kind == 1 ? 1e-10 * D[0] : 1e-14 * fabs(want));
      }
    vi_model *m = NULL;
    assert_int_equal(vi_fe_create_model(fe, &m), VI_OK);
    assert_int_equal(vi_model_is_proportional(m), 1);
    vi_model_destroy(&m);
    vi_fe_destroy(&fe);
  }
  /* per-mode ratios must match the kept modes */
  vi_fe *fe = rod_fe(&R, k);
  assert_int_equal(vi_fe_add_stop_dof(fe, R.n - 1, 1, 0.0, 0.5), VI_OK);
  double z3[3] = {0.1, 0.1, 0.1};
  assert_int_equal(vi_fe_set_modal_damping(fe, 3, z3), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_ERR_DIM);
  assert_fe_msg(fe, "3 modal damping ratios for 5 kept modes");
  vi_fe_destroy(&fe);
}

/* A host's modes (here: the dense modal analysis of a 6-dof rod) give the
 * model, and the impacts, of the same rod written densely. */
static void test_host_modes(void **state)
{
  (void)state;
  const int N = 6, n = 6, stop = 5, force = 2;
  rod_build(&R, N, 1);
  /* scaled to unit-ish numbers: E / rho = 1, A = 1, L = 6 */
  double M[36] = {0}, K[36] = {0}, C[36] = {0};
  for (int j = 0; j < n; j++)
    for (int p = R.colptr[j]; p < R.colptr[j + 1]; p++) {
      int i = R.rowind[p];
      double ms = R.m[p] / (RHO * AREA * LEN / N), ks = R.k[p] / (E * AREA * N / LEN);
      M[i + j * n] = M[j + i * n] = ms;
      K[i + j * n] = K[j + i * n] = ks;
    }
  for (int q = 0; q < 36; q++) C[q] = 0.02 * M[q] + 0.01 * K[q];
  double w[6] = {0}, a[6] = {0};
  w[stop] = 1.0;
  a[force] = 0.3;
  vi_model *dense = vi_test_model(n, M, C, K, 0.7, a, NULL, w, 0.05, 0.8);
  int ld;
  const double *Psi = vi_model_modal_shapes(dense, &ld);
  const double *om = vi_model_omega(dense), *zeta = vi_model_zeta(dense);
  int rows[2] = {force, stop};
  double P[2 * 6];
  for (int j = 0; j < n; j++) {
    P[0 + 2 * j] = Psi[force + j * ld];
    P[1 + 2 * j] = Psi[stop + j * ld];
  }
  vi_fe *fe = NULL;
  assert_int_equal(vi_fe_create(n, &fe), VI_OK);
  assert_int_equal(vi_fe_set_host_modes(fe, n, om, zeta, NULL, 0, 2, rows, P, 2), VI_OK);
  assert_int_equal(vi_fe_add_stop_dof(fe, stop, 1, 0.05, 0.8), VI_OK);
  assert_int_equal(vi_fe_set_forcing(fe, 0.7, a, NULL, NULL), VI_OK);
  assert_int_equal(vi_fe_set_outputs(fe, 1, &rows[1]), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_OK);
  vi_model *modal = NULL;
  assert_int_equal(vi_fe_create_model(fe, &modal), VI_OK);
  assert_close(vi_model_stop_compliance(modal), vi_model_stop_compliance(dense), 1e-13);
  /* the same impacts (t, v_n), from rest, by the closed-form flow: both
   * models are exact between impacts, so they agree to the event
   * location's accuracy */
  vi_test_events e1 = {0}, e2 = {0};
  assert_int_equal(vi_test_run(dense, VI_METHOD_EXACT, 1e-10, 1e-12, NULL, NULL, 60.0, &e1), VI_OK);
  assert_int_equal(vi_test_run(modal, VI_METHOD_EXACT, 1e-10, 1e-12, NULL, NULL, 60.0, &e2), VI_OK);
  assert_true(e1.count >= 5);
  assert_int_equal(e1.count, e2.count);
  for (int q = 0; q < e1.count; q++) {
    assert_close(e2.t[q], e1.t[q], 1e-8);
    assert_close(e2.vn[q], e1.vn[q], 1e-8 * fabs(e1.vn[0]));
  }
  /* the stop's displacement from the modal state at the last impact */
  double y;
  assert_int_equal(vi_fe_to_outputs(fe, 1, e2.x + (size_t)(e2.count - 1) * n, n, &y, 1), VI_OK);
  assert_close(y, 0.05, 1e-9);
  vi_test_events_free(&e1);
  vi_test_events_free(&e2);
  /* vi_model_create_modal, stops and forcing by the host: the same model */
  vi_model *m3 = NULL;
  assert_int_equal(vi_model_create_modal(n, om, zeta, NULL, 0, &m3), VI_OK);
  double ps[6], fa[6];
  for (int j = 0; j < n; j++) {
    ps[j] = P[1 + 2 * j];
    fa[j] = 0.3 * P[0 + 2 * j];
  }
  assert_int_equal(vi_model_set_stop(m3, ps, 0.05, 0.8), VI_OK);
  assert_int_equal(vi_model_set_forcing(m3, 0.7, fa, NULL, NULL), VI_OK);
  assert_int_equal(vi_model_setup(m3), VI_OK);
  for (int j = 0; j < n; j++) {
    assert_close(vi_model_modal_stop(m3)[j], vi_model_modal_stop(modal)[j], 0.0);
    assert_close(vi_model_modal_forcing_cos(m3)[j],
                 vi_model_modal_forcing_cos(modal)[j], 1e-16);
  }
  /* host rules: loads and stops only on the given rows */
  vi_fe *h2 = NULL;
  assert_int_equal(vi_fe_create(n, &h2), VI_OK);
  assert_int_equal(vi_fe_set_host_modes(h2, n, om, NULL, NULL, 0, 2, rows, P, 2), VI_OK);
  assert_int_equal(vi_fe_add_stop_dof(h2, 0, 1, 0.05, 0.8), VI_ERR_UNSUPPORTED);
  assert_fe_msg(h2, "dof 1 (1-based) is not among the host's rows");
  assert_int_equal(vi_fe_set_mass_csc(h2, VI_CSC_LOWER, 0, R.colptr, R.rowind, R.m), VI_ERR_STATE);
  assert_int_equal(vi_fe_set_keep_shapes(h2, 1), VI_ERR_UNSUPPORTED);
  int dup[2] = {2, 2};
  assert_int_equal(vi_fe_set_host_modes(h2, n, om, NULL, NULL, 0, 2, dup, P, 2), VI_ERR_ARG);
  assert_fe_msg(h2, "repeated");
  double Dns[4] = {1, 0.5, 0.4, 1};
  assert_int_equal(vi_fe_set_host_modes(h2, 2, om, NULL, Dns, 2, 2, rows, P, 2), VI_ERR_NOT_SYMMETRIC);
  vi_fe_destroy(&h2);
  vi_model_destroy(&m3);
  vi_model_destroy(&modal);
  vi_model_destroy(&dense);
  vi_fe_destroy(&fe);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_fixed_free_rod),
      cmocka_unit_test(test_free_free_rod),
      cmocka_unit_test(test_hermite_beam),
      cmocka_unit_test(test_degenerate_modes),
      cmocka_unit_test(test_lanczos_not_converged),
      cmocka_unit_test(test_small_rod_dense),
      cmocka_unit_test(test_storage_variants),
      cmocka_unit_test(test_bad_csc),
      cmocka_unit_test(test_damping),
      cmocka_unit_test(test_host_modes),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
