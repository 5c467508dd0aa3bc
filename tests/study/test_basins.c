/* test_basins.c - basins of attraction (`vibroimpact basins`, apps/vi_diagram.c
 * over the library's studies, vi_study.h) on Fig. 2 at Omega = 2.4, where
 * the non-impacting harmonic response P(1,0) and an impacting P(3,1) orbit
 * coexist:
 *  - every one of 20 x 20 cells (initial.x[2] x initial.v[2]) agrees, bit
 *    for bit, with a one-value study of the library started there;
 *  - the P(1,0) attractor is the closed-form harmonic response
 *    x = Re(H a e^{i Omega t}), H = (K - Omega^2 M + i Omega C)^-1;
 *  - cells with the same attractor id have the same P(n, m) and the same
 *    impact velocities, cells with different ids do not, and the answer
 *    does not depend on the number of threads. */
#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vi_testutil.h"
#include "vibroimpact/vi_scene.h"
#include "vi_diagram.h"

#define OMEGA 2.4
#define NX 20
#define NV 20

static const char *sets[] = {"run.method=exact", "forcing.omega=2.4"};

static vi_diagram *basins(int threads)
{
  vi_diagram_spec sp = {"initial.x[2]", -4.0, 0.09, NX, "initial.v[2]", -6.0, 6.0,
                      NV, 1, 1000, 30, NX, threads, 1e-6, 32, 0, 1, 0, 0};
  vi_diagram *sw = NULL;
  char err[2048];
  int rc = vi_diagram_run(vi_scene_default_text(), "fig2.yaml", sets, 2, &sp,
                          NULL, &sw, err, sizeof err);
  if (rc) fprintf(stderr, "basins failed: %s\n", err);
  assert_int_equal(rc, 0);
  assert_int_equal(vi_basins_identify(sw), 0);
  return sw;
}

/* Fig. 2's harmonic response at t (stop out of reach): M = I,
 * K = [2 -1; -1 1], C = 0.1 K, a = (0.5, 0). */
static void harmonic(double t, double *z)
{
  double complex h11 = 2 - OMEGA * OMEGA + I * OMEGA * 0.2,
                 h12 = -1 - I * OMEGA * 0.1,
                 h22 = 1 - OMEGA * OMEGA + I * OMEGA * 0.1,
                 det = h11 * h22 - h12 * h12, e = cexp(I * OMEGA * t);
  double complex X1 = h22 * 0.5 / det, X2 = -h12 * 0.5 / det;
  z[0] = creal(X1 * e);
  z[1] = creal(X2 * e);
  z[2] = creal(I * OMEGA * X1 * e);
  z[3] = creal(I * OMEGA * X2 * e);
}

/* Cell (l, k) of the basins sw rerun alone by st: the same period,
 * impacts and strobe, and the same attractor id as the other cells of its
 * orbit (*id10, *id31: -2 until the first), counted in counts.  (Its own
 * function: the lint's path-sensitive analyser explored the loop over the
 * cells to its node budget.) */
static void cell_agrees(vi_sweep *st, const vi_diagram *sw, int l, int k, int counts[2],
                        int *id10, int *id31)
{
  const vi_diagram_point *pt = &sw->lines[l].pt[k];
  int n, mm, ld, R;
  int64_t ni;
  const double *vn;
  assert_int_equal(vi_sweep_set_param(st, "initial.x[2]", sw->param[k]), VI_OK);
  assert_int_equal(vi_sweep_set_param(st, "initial.v[2]", sw->param2[l]), VI_OK);
  assert_int_equal(vi_sweep_iterate(st), VI_OK);
  assert_int_equal(vi_sweep_period(st, &n, &mm), VI_OK);
  assert_int_equal(vi_sweep_impacts(st, &ni, NULL, NULL, &vn), VI_OK);
  const double *z = vi_sweep_strobe(st, &ld, &R);
  assert_int_equal(n, pt->n);
  assert_int_equal(mm, pt->m);
  assert_int_equal(ni, pt->nimp);
  if (ni) assert_memory_equal(vn, pt->vn, sizeof(double) * (size_t)ni);
  assert_memory_equal(z, sw->lines[l].strobe + (size_t)k * R * ld,
                      sizeof(double) * (size_t)R * ld);
  int id = sw->attractor[l * NX + k];
  if (n == 1 && mm == 0) {
    if (*id10 == -2) *id10 = id;
    assert_int_equal(id, *id10);
    counts[0]++;
    /* the harmonic response, to the classification tolerance */
    double zr[4], t = 1000 * 2 * M_PI / OMEGA;
    harmonic(t + 30 * 2 * M_PI / OMEGA, zr);
    for (int i = 0; i < 4; i++) assert_close(z[29 * ld + i], zr[i], 1e-6);
  } else if (n == 3 && mm == 1) {
    if (*id31 == -2) *id31 = id;
    assert_int_equal(id, *id31);
    counts[1]++;
  }
}

static void cells_agree(void **state)
{
  (void)state;
  vi_diagram *sw = basins(2);
  vi_model *m = vi_test_fig2();
  vi_sweep *st = NULL;
  assert_int_equal(vi_model_set_param(m, "forcing.omega", OMEGA), VI_OK);
  assert_int_equal(vi_sweep_create(m, &st), VI_OK);
  assert_int_equal(vi_sweep_set_run(st, VI_METHOD_EXACT, 1e-8, 1e-10), VI_OK);
  assert_int_equal(vi_sweep_set_periods(st, 1000, 30), VI_OK);
  assert_int_equal(vi_sweep_set_warm(st, 0), VI_OK);
  int counts[2] = {0, 0}; /* cells of P(1,0) and of P(3,1) */
  int id10 = -2, id31 = -2;
  for (int l = 0; l < NV; l++)
    for (int k = 0; k < NX; k++) cell_agrees(st, sw, l, k, counts, &id10, &id31);
  /* both attractors present, with different ids, and nothing else */
  assert_true(counts[0] > 20 && counts[1] > 20);
  assert_int_equal(counts[0] + counts[1], NX * NV);
  assert_true(id10 != id31 && id10 >= 0 && id31 >= 0);
  assert_int_equal(sw->nattr, 2);
  vi_sweep_destroy(&st);
  vi_model_destroy(&m);
  vi_diagram *s1 = basins(1);
  assert_memory_equal(s1->attractor, sw->attractor, sizeof(int) * NX * NV);
  vi_diagram_free(&s1);
  vi_diagram_free(&sw);
}

/* Cell i of the basins sw, if of period 3: its impact velocity against
 * *vref (the first such cell's, NAN until then), and *shifted counted up
 * if its phase differs from the first such cell's (*first, -1 until then).
 * (Its own function, as cell_agrees.) */
static void p31_cell(const vi_diagram *sw, int i, double *vref, int *first, int *shifted)
{
  const vi_diagram_point *pt = &sw->lines[i / NX].pt[i % NX];
  if (pt->n != 3) return;
  double v = pt->vn[pt->nimp - 1];
  if (isnan(*vref)) *vref = v;
  /* the same impact, seen one, two or three periods apart */
  double best = 1e9;
  for (int j = 1; j <= 3 && j <= pt->nimp; j++)
    best = fmin(best, fabs(pt->vn[pt->nimp - j] - *vref));
  assert_true(best < 1e-6);
  const double *z = sw->lines[i / NX].strobe + (size_t)(i % NX) * 30 * 4;
  if (*first < 0) *first = i;
  else {
    const double *z0 = sw->lines[*first / NX].strobe + (size_t)(*first % NX) * 30 * 4;
    *shifted += fabs(z[(size_t)29 * 4] - z0[(size_t)29 * 4]) > 1e-3; /* another phase */
  }
}

/* The P(3,1) cells share one orbit whatever their phase: their last
 * three stroboscopic states are the same set, and the one recorded impact
 * velocity per period is the same to 1e-6. */
static void one_orbit_many_phases(void **state)
{
  (void)state;
  vi_diagram *sw = basins(2);
  double vref = NAN;
  int shifted = 0, first = -1;
  for (int i = 0; i < NX * NV; i++) p31_cell(sw, i, &vref, &first, &shifted);
  /* cells landed on the orbit in different phases, and still share an id */
  assert_true(shifted > 0);
  vi_diagram_free(&sw);
}

int main(void)
{
  const struct CMUnitTest tests[] = {cmocka_unit_test(cells_agree),
                                     cmocka_unit_test(one_orbit_many_phases)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
