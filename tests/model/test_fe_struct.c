/* test_fe_struct.c - structures as FE codes write them (vi_sparse.h):
 * lumped masses with massless dofs, masses spanning many orders (a scale
 * that once made elastic modes rigid), rigid-body modes decided from K,
 * the default number of modes, the accuracy check, and setups from several
 * threads at once.
 *
 * The closed form (a textbook result, derived again here): a fixed-free
 * chain of N masses m joined by springs k (the first to the ground, the
 * last mass free) has lambda_j = (4 k / m) sin^2((2j - 1) pi / (2 (2N + 1))),
 * j = 1..N.  The test chain has 2N dofs, all springs 1: odd dofs (0-based
 * even) massless or nearly so, even dofs of mass 1.  A massless dof between
 * two springs is their series connection, so the chain condenses to N unit
 * masses on springs 1/2: lambda_j = 2 sin^2((2j - 1) pi / (2 (2N + 1))). */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "vi_testutil.h"

#define assert_fe_msg(fe, s) assert_non_null(strstr(vi_fe_errmsg(fe), (s)))

enum { NMASS = 60, NDOF = 2 * NMASS };

/* A chain of n dofs in lower CSC storage: springs kspr[i] between dof i - 1
 * and i (kspr[0] to the ground; 0 leaves the chain free), lumped masses
 * mass[i] (a zero is a massless dof). */
typedef struct chain {
  int n;
  int cp[2 * NDOF + 2], ri[2 * NDOF], cpm[2 * NDOF + 2], rim[2 * NDOF];
  double kv[2 * NDOF], mv[2 * NDOF];
} chain;

static void chain_build(chain *c, int n, const double *kspr,
                        const double *mass)
{
  int q = 0;
  c->n = n;
  for (int j = 0; j < n; j++) {
    c->cp[j] = q;
    c->ri[q] = j;
    c->kv[q++] = kspr[j] + (j + 1 < n ? kspr[j + 1] : 0.0);
    if (j + 1 < n) {
      c->ri[q] = j + 1;
      c->kv[q++] = -kspr[j + 1];
    }
    c->cpm[j] = j;
    c->rim[j] = j;
    c->mv[j] = mass[j];
  }
  c->cp[n] = q;
  c->cpm[n] = n;
}

static vi_fe *chain_fe(const chain *c, int k)
{
  vi_fe *fe = NULL;
  assert_int_equal(vi_fe_create(c->n, &fe), VI_OK);
  assert_int_equal(vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 0, c->cpm, c->rim,
                                      c->mv), VI_OK);
  assert_int_equal(vi_fe_set_stiffness_csc(fe, VI_CSC_LOWER, 0, c->cp, c->ri,
                                           c->kv), VI_OK);
  if (k > 0) assert_int_equal(vi_fe_set_modes(fe, k), VI_OK);
  return fe;
}

static double lambda_condensed(int j) /* j = 1..NMASS */
{
  double s = sin((2.0 * j - 1.0) * M_PI / (2.0 * (2.0 * NMASS + 1.0)));
  return 2.0 * s * s;
}

static chain C; /* large: static storage */

static void build_test_chain(double small_mass)
{
  double kspr[NDOF], mass[NDOF];
  for (int i = 0; i < NDOF; i++) {
    kspr[i] = 1.0;
    mass[i] = i % 2 ? 1.0 : small_mass;
  }
  chain_build(&C, NDOF, kspr, mass);
}

/* Massless dofs: the Lanczos path (6 modes) and the dense path (every
 * finite mode, the default) against the condensed closed form; the shapes
 * carry the massless dofs statically; a stop on a massless dof sees the
 * condensed compliance, 1/2 in closed form. */
static void test_massless_dofs(void **state)
{
  (void)state;
  build_test_chain(0.0);
  for (int pass = 0; pass < 2; pass++) {
    vi_fe *fe = chain_fe(&C, pass == 0 ? 6 : 0);
    int sdof = NDOF - 4; /* 0-based even: massless, between two masses */
    assert_int_equal(vi_fe_add_stop_dof(fe, sdof, 1, 0.1, 0.7), VI_OK);
    assert_int_equal(vi_fe_set_keep_shapes(fe, 1), VI_OK);
    assert_int_equal(vi_fe_setup(fe), VI_OK);
    int k = vi_fe_num_modes(fe), massless, rigid, rule;
    double orth;
    assert_int_equal(vi_fe_summary(fe, &massless, &rigid, &rule, &orth),
                     VI_OK);
    assert_int_equal(massless, NMASS);
    assert_int_equal(rigid, 0);
    assert_int_equal(k, pass == 0 ? 6 : NMASS);
    assert_int_equal(rule, pass == 0 ? VI_FE_MODES_GIVEN : VI_FE_MODES_WHOLE);
    assert_true(orth < 1e-12);
    const double *om = vi_fe_omega(fe);
    double worst = 0.0;
    for (int j = 0; j < k; j++)
      worst = fmax(worst, fabs(om[j] * om[j] / lambda_condensed(j + 1) - 1.0));
    print_message("massless dofs, %s: %d modes, worst relative error of "
                  "omega^2 %.2g, M-orthonormality %.2g\n",
                  pass == 0 ? "Lanczos" : "dense", k, worst, orth);
    assert_true(worst < 1e-11);
    /* a massless dof moves as the average of its two neighbours */
    int ld;
    const double *Psi = vi_fe_shapes(fe, &ld);
    double slave = 0.0;
    for (int j = 0; j < k; j++)
      for (int i = 2; i < NDOF; i += 2) {
        const double *z = Psi + (size_t)j * ld;
        slave = fmax(slave, fabs(z[i] - 0.5 * (z[i - 1] + z[i + 1])));
      }
    print_message("massless dofs off their neighbours' mean by %.2g\n", slave);
    assert_true(slave < 1e-11);
    /* the stop's compliance: t = (e_{d-1} + e_{d+1}) / 2 through unit
     * masses, 1/4 + 1/4; over every finite mode the modes carry it all */
    double dyn, sta;
    assert_int_equal(vi_fe_stop_compliance(fe, 0, &dyn, &sta), VI_OK);
    assert_true(fabs(dyn - 0.5) < 1e-13);
    if (pass == 1) {
      double carried = 0.0;
      for (int j = 0; j < k; j++) carried += Psi[sdof + (size_t)j * ld] *
                                             Psi[sdof + (size_t)j * ld];
      print_message("massless stop: w^T M^-1 w = %.15g (1/2), carried by "
                    "the %d modes %.15g\n", dyn, k, carried);
      assert_true(fabs(carried - 0.5) < 1e-11);
    }
    vi_fe_destroy(&fe);
  }
}

/* The same chain reduced from its FE form and written as the condensed
 * chain directly (N unit masses, springs 1/2): the same impacts. */
/* The modal model of chain c with every mode kept, zeta = 0.02, forced
 * 0.05 cos(0.02 t) at its last dof and stopped there at 1.0, r = 0.7. */
static vi_model *forced_last(const chain *c)
{
  vi_fe *fe = chain_fe(c, 0);
  double *a = calloc((size_t)c->n, sizeof(double));
  assert_non_null(a);
  a[c->n - 1] = 0.05;
  assert_int_equal(vi_fe_set_forcing(fe, 0.02, a, NULL, NULL), VI_OK);
  assert_int_equal(vi_fe_add_stop_dof(fe, c->n - 1, 1, 1.0, 0.7), VI_OK);
  assert_int_equal(vi_fe_set_modal_damping(fe, 1, (double[]){0.02}), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_OK);
  vi_model *m = NULL;
  assert_int_equal(vi_fe_create_model(fe, &m), VI_OK);
  vi_fe_destroy(&fe);
  free(a);
  return m;
}

static void test_massless_run(void **state)
{
  (void)state;
  build_test_chain(0.0);
  vi_model *mf = forced_last(&C);
  /* the condensed chain, reduced the same way: it has no massless dof, so
   * its modes come from the ordinary pencil */
  double kspr[NMASS], mass[NMASS];
  for (int i = 0; i < NMASS; i++) kspr[i] = 0.5, mass[i] = 1.0;
  chain Cc;
  chain_build(&Cc, NMASS, kspr, mass);
  vi_model *mc = forced_last(&Cc);
  vi_test_events ef = {0}, ec = {0};
  double T = 2.0 * M_PI / 0.02;
  assert_true(vi_test_run(mf, VI_METHOD_EXACT, 1e-12, 1e-14, NULL, NULL,
                          6 * T, &ef) >= 0);
  assert_true(vi_test_run(mc, VI_METHOD_EXACT, 1e-12, 1e-14, NULL, NULL,
                          6 * T, &ec) >= 0);
  print_message("massless FE chain: %d impacts, condensed chain: %d\n",
                ef.count, ec.count);
  assert_true(ef.count > 5);
  assert_int_equal(ef.count, ec.count);
  double dt = 0.0, dv = 0.0, vmax = 0.0;
  for (int i = 0; i < ef.count; i++) vmax = fmax(vmax, fabs(ec.vn[i]));
  for (int i = 0; i < ef.count; i++) {
    dt = fmax(dt, fabs(ef.t[i] - ec.t[i]) / T);
    dv = fmax(dv, fabs(ef.vn[i] - ec.vn[i]) / vmax);
  }
  print_message("impact times within %.2g of a period, speeds %.2g of the "
                "largest\n", dt, dv);
  assert_true(dt < 1e-9 && dv < 1e-7);
  vi_test_events_free(&ef);
  vi_test_events_free(&ec);
  vi_model_destroy(&mf);
  vi_model_destroy(&mc);
}

/* Masses spanning 14 orders: max K_jj / M_jj = 2e14, so the former rule
 * "rigid below 1e-13 of that scale" (20) took every mode of this chain,
 * all below 2, for a rigid one.  K psi decides instead. */
static void test_tiny_masses(void **state)
{
  (void)state;
  build_test_chain(1e-14);
  vi_fe *fe = chain_fe(&C, 6);
  assert_int_equal(vi_fe_add_stop_dof(fe, NDOF - 1, 1, 0.1, 0.7), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_OK);
  const double *om = vi_fe_omega(fe), *rig = vi_fe_mode_rigidity(fe);
  int rigid;
  assert_int_equal(vi_fe_summary(fe, NULL, &rigid, NULL, NULL), VI_OK);
  assert_int_equal(rigid, 0);
  for (int j = 0; j < 6; j++) {
    /* the tiny masses shift lambda by O(1e-14) relative */
    double e = fabs(om[j] * om[j] / lambda_condensed(j + 1) - 1.0);
    print_message("tiny masses: mode %d omega^2 %.15g (condensed %.15g), "
                  "rigidity %.2g\n", j + 1, om[j] * om[j],
                  lambda_condensed(j + 1), rig[j]);
    assert_true(e < 1e-10);
    assert_true(rig[j] > 1e-6);
  }
  vi_fe_destroy(&fe);
}

/* A free chain: one rigid mode, decided from K and checked against a
 * count the user states. */
static void test_rigid_count(void **state)
{
  (void)state;
  double kspr[40], mass[40];
  for (int i = 0; i < 40; i++) kspr[i] = i ? 1.0 : 0.0, mass[i] = 1.0;
  chain fc;
  chain_build(&fc, 40, kspr, mass);
  for (int stated = -1; stated <= 2; stated++) {
    vi_fe *fe = chain_fe(&fc, 5);
    assert_int_equal(vi_fe_add_stop_dof(fe, 39, 1, 0.1, 0.7), VI_OK);
    assert_int_equal(vi_fe_set_rigid_modes(fe, stated), VI_OK);
    int st = vi_fe_setup(fe);
    if (stated == 0 || stated == 2) {
      assert_int_equal(st, VI_ERR_ARG);
      assert_fe_msg(fe, stated == 0 ? "mode 1" : "mode 2");
      print_message("stated %d rigid: %s\n", stated, vi_fe_errmsg(fe));
    } else {
      assert_int_equal(st, VI_OK);
      int rigid;
      assert_int_equal(vi_fe_summary(fe, NULL, &rigid, NULL, NULL), VI_OK);
      assert_int_equal(rigid, 1);
      const double *om = vi_fe_omega(fe), *rig = vi_fe_mode_rigidity(fe);
      assert_true(om[0] == 0.0);
      /* free chain of 40 unit masses: lambda_j = 4 sin^2(j pi / 80) */
      double s = sin(M_PI / 80.0);
      assert_true(fabs(om[1] * om[1] / (4.0 * s * s) - 1.0) < 1e-11);
      print_message("free chain: rigidity of the rigid mode %.2g, of the "
                    "first elastic one %.2g\n", rig[0], rig[1]);
      assert_true(rig[0] < 1e-13 && rig[1] > 1e-4);
    }
    vi_fe_destroy(&fe);
  }
}

/* Ten free masses beside a pair on a spring: eleven rigid modes.  Four of
 * them would be an arbitrary part of the group (once a run went on with
 * its first impact at t = 17.04 instead of 4.53): refused; all eleven and
 * the elastic one are kept. */
static void test_cut_in_group(void **state)
{
  (void)state;
  double kspr[12] = {0}, mass[12];
  for (int i = 0; i < 12; i++) mass[i] = 1.0;
  kspr[11] = 1.0; /* between masses 11 and 12 (1-based) */
  chain g;
  chain_build(&g, 12, kspr, mass);
  vi_fe *fe = chain_fe(&g, 4);
  assert_int_equal(vi_fe_add_stop_dof(fe, 11, 1, 0.1, 0.7), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_ERR_DIM);
  assert_fe_msg(fe, "cuts through a group of equal frequencies");
  print_message("modes: 4 of 11 rigid: %s\n", vi_fe_errmsg(fe));
  vi_fe_destroy(&fe);
  fe = chain_fe(&g, 12);
  assert_int_equal(vi_fe_add_stop_dof(fe, 11, 1, 0.1, 0.7), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_OK);
  int rigid;
  assert_int_equal(vi_fe_summary(fe, NULL, &rigid, NULL, NULL), VI_OK);
  assert_int_equal(rigid, 11);
  /* the pair's relative motion: lambda = k (1/m + 1/m) = 2 */
  assert_true(fabs(vi_fe_omega(fe)[11] - sqrt(2.0)) < 1e-13);
  vi_fe_destroy(&fe);
}

/* Without vi_fe_set_modes a large structure is refused, not cut; an
 * accuracy nothing attains is refused; more modes than finite ones too. */
static void test_defaults_and_checks(void **state)
{
  (void)state;
  enum { NBIG = 1001 };
  /* a fixed-free chain of 1001 unit masses (more than a chain holds) */
  int *cp = malloc(sizeof(int) * (NBIG + 1)), *ri = malloc(sizeof(int) * 2 * NBIG);
  int *cpm = malloc(sizeof(int) * (NBIG + 1)), *rim = malloc(sizeof(int) * NBIG);
  double *kv = malloc(sizeof(double) * 2 * NBIG), *mv = malloc(sizeof(double) * NBIG);
  assert_true(cp && ri && cpm && rim && kv && mv);
  int q = 0;
  for (int j = 0; j < NBIG; j++) {
    cp[j] = q;
    ri[q] = j;
    kv[q++] = j + 1 < NBIG ? 2.0 : 1.0;
    if (j + 1 < NBIG) ri[q] = j + 1, kv[q++] = -1.0;
    cpm[j] = rim[j] = j;
    mv[j] = 1.0;
  }
  cp[NBIG] = q;
  cpm[NBIG] = NBIG;
  vi_fe *fe = NULL;
  assert_int_equal(vi_fe_create(NBIG, &fe), VI_OK);
  assert_int_equal(vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 0, cpm, rim, mv), VI_OK);
  assert_int_equal(vi_fe_set_stiffness_csc(fe, VI_CSC_LOWER, 0, cp, ri, kv), VI_OK);
  assert_int_equal(vi_fe_add_stop_dof(fe, NBIG - 1, 1, 0.1, 0.7), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_ERR_STATE);
  assert_fe_msg(fe, "vi_fe_set_modes");
  print_message("no mode count: %s\n", vi_fe_errmsg(fe));
  assert_int_equal(vi_fe_set_accuracy(fe, 0.0), VI_ERR_TOLERANCE);
  assert_int_equal(vi_fe_set_accuracy(fe, 1e-19), VI_OK);
  assert_int_equal(vi_fe_set_modes(fe, 4), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_ERR_NOT_CONVERGED);
  assert_fe_msg(fe, "above the accuracy");
  assert_int_equal(vi_fe_set_accuracy(fe, 1e-10), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_OK);
  const double *res = vi_fe_mode_residuals(fe);
  for (int j = 0; j < 4; j++) assert_true(res[j] > 0.0 && res[j] < 1e-10);
  vi_fe_destroy(&fe);
  free(cp); free(ri); free(cpm); free(rim); free(kv); free(mv);
  /* more modes than the massless chain has finite ones */
  build_test_chain(0.0);
  fe = chain_fe(&C, NMASS + 1);
  assert_int_equal(vi_fe_add_stop_dof(fe, 1, 1, 0.1, 0.7), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_ERR_DIM);
  assert_fe_msg(fe, "only 60 finite");
  vi_fe_destroy(&fe);
  /* a dof with neither mass nor stiffness */
  double ks[4] = {1, 1, 0, 1}, ms[4] = {1, 1, 0, 1};
  chain bad;
  chain_build(&bad, 4, ks, ms);
  bad.kv[4] = 0.0; /* dof 3: K(3,3) = k3 + k4 = 1 -> 0, and no mass */
  bad.kv[5] = 0.0;
  fe = chain_fe(&bad, 2);
  assert_int_equal(vi_fe_add_stop_dof(fe, 1, 1, 0.1, 0.7), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_ERR_NOT_SPD);
  assert_fe_msg(fe, "dof 3 has neither mass nor stiffness");
  vi_fe_destroy(&fe);
}

/* Setups from several threads at once (ARPACK's saved state is shared by
 * the process): every thread gets the single-thread frequencies, bit for
 * bit. */
typedef struct job {
  const double *want;
  int ok;
} job;

static void *setup_many(void *arg)
{
  job *jb = arg;
  jb->ok = 1;
  for (int rep = 0; rep < 8 && jb->ok; rep++) {
    vi_fe *fe = NULL;
    if (vi_fe_create(C.n, &fe) ||
        vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 0, C.cpm, C.rim, C.mv) ||
        vi_fe_set_stiffness_csc(fe, VI_CSC_LOWER, 0, C.cp, C.ri, C.kv) ||
        vi_fe_set_modes(fe, 6) || vi_fe_add_stop_dof(fe, 1, 1, 0.1, 0.7) ||
        vi_fe_setup(fe))
      jb->ok = 0;
    else
      for (int j = 0; j < 6; j++) jb->ok &= vi_fe_omega(fe)[j] == jb->want[j];
    vi_fe_destroy(&fe);
  }
  return NULL;
}

static void test_threads(void **state)
{
  (void)state;
  build_test_chain(0.0);
  vi_fe *fe = chain_fe(&C, 6);
  assert_int_equal(vi_fe_add_stop_dof(fe, 1, 1, 0.1, 0.7), VI_OK);
  assert_int_equal(vi_fe_setup(fe), VI_OK);
  double want[6];
  memcpy(want, vi_fe_omega(fe), sizeof want);
  vi_fe_destroy(&fe);
  pthread_t th[4];
  job jobs[4];
  for (int i = 0; i < 4; i++) {
    jobs[i].want = want;
    assert_int_equal(pthread_create(&th[i], NULL, setup_many, &jobs[i]), 0);
  }
  for (int i = 0; i < 4; i++) {
    pthread_join(th[i], NULL);
    assert_true(jobs[i].ok);
  }
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_massless_dofs),
      cmocka_unit_test(test_massless_run),
      cmocka_unit_test(test_tiny_masses),
      cmocka_unit_test(test_rigid_count),
      cmocka_unit_test(test_cut_in_group),
      cmocka_unit_test(test_defaults_and_checks),
      cmocka_unit_test(test_threads),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
