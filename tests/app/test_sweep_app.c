/* test_sweep_app.c - the sweep program (apps/vi_diagram.c over the library's
 * studies) against physics: the Fig. 2 P(1,1) orbit from an independent 40-digit shooting
 * (tests/orbit/ref_fig2_p11.py), the closed-form harmonic response when the stop
 * is out of reach, up and down sweeps agreeing where the motion is unique,
 * and thread-count independence of the results. */
#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hdf5.h>

#include "vi_testutil.h"
#include "vibroimpact/vi_scene.h"
#include "vi_diagram.h"

/* tests/orbit/ref_fig2_p11.py (mpmath, 40 digits) */
#define FIG2_VN 0.78766085255479729134
#define FIG2_PHASE 0.67857113423124466619

static const char *exact[] = {"run.method=exact"};

static vi_diagram_spec spec(const char *key, double from, double to, int steps)
{
  vi_diagram_spec s = {key, from, to, steps, NULL, NAN, NAN, 1, 1, 500, 100, 1, 1, 1e-6, 32, 0, 0, 0, 0};
  return s;
}

static vi_diagram *run(const vi_diagram_spec *sp, const char *const *sets, int nsets)
{
  vi_diagram *sw = NULL;
  char err[2048];
  int rc = vi_diagram_run(vi_scene_default_text(), "fig2.yaml", sets, nsets, sp,
                          NULL, &sw, err, sizeof err);
  if (rc) fprintf(stderr, "sweep failed: %s\n", err);
  assert_int_equal(rc, 0);
  assert_non_null(sw);
  return sw;
}

/* Fig. 2 at Omega = 0.9: P(1,1), v_N and impact phase of the exact orbit.
 * The exact flow's error is round-off and the transient (500 periods,
 * Floquet multipliers well inside the unit circle) has decayed, so 1e-9. */
static void fig2_p11(void **state)
{
  (void)state;
  vi_diagram_spec sp = spec("forcing.omega", 0.9, 0.9, 1);
  vi_diagram *sw = run(&sp, exact, 1);
  const vi_diagram_point *pt = &sw->lines[0].pt[0];
  assert_int_equal(pt->n, 1);
  assert_int_equal(pt->m, 1);
  assert_int_equal(pt->nimp, 100); /* one per recorded period */
  assert_close(pt->vn[pt->nimp - 1], FIG2_VN, 1e-9);
  assert_close(pt->phase[pt->nimp - 1], FIG2_PHASE, 1e-9);
  /* the published README value, 6 digits */
  assert_close(pt->vn[0], 0.787661, 5e-7);
  vi_diagram_free(&sw);
}

/* Stop out of reach (x_s = 100): no impacts, P(1,0), and the stroboscopic
 * states are the harmonic response x = Re(H a), v = Re(i Omega H a) with
 * H = (K - Omega^2 M + i Omega C)^-1 at t = kT (phase 0), K = E, C = 0.1 E. */
static void harmonic_response(void **state)
{
  (void)state;
  const char *sets[] = {"run.method=exact", "stop.xs=100"};
  vi_diagram_spec sp = spec("forcing.omega", 0.2, 3.0, 15);
  sp.transient = 400;
  sp.record = 4;
  vi_diagram *sw = run(&sp, sets, 2);
  for (int k = 0; k < sp.steps; k++) {
    const vi_diagram_point *pt = &sw->lines[0].pt[k];
    double Om = sw->param[k];
    assert_int_equal(pt->n, 1);
    assert_int_equal(pt->m, 0);
    assert_int_equal(pt->nimp, 0);
    /* 2x2 complex solve (Cramer) */
    double complex h11 = 2 - Om * Om + I * Om * 0.2, h12 = -1 - I * Om * 0.1,
                   h22 = 1 - Om * Om + I * Om * 0.1, det = h11 * h22 - h12 * h12;
    double complex X1 = h22 * 0.5 / det, X2 = -h12 * 0.5 / det;
    double want[4] = {creal(X1), creal(X2), creal(I * Om * X1), creal(I * Om * X2)};
    double amp = cabs(X1) + cabs(X2);
    for (int j = 0; j < sp.record; j++)
      for (int i = 0; i < 4; i++)
        assert_close(sw->lines[0].strobe[((size_t)k * sp.record + j) * 4 + i],
                     want[i], 1e-8 * amp * (1 + Om));
  }
  vi_diagram_free(&sw);
}

/* Up and down sweeps over 0.88..0.95, where the P(1,1) orbit is the only
 * attractor, agree value by value; --both gives the same as two runs. */
static void up_down_agree(void **state)
{
  (void)state;
  vi_diagram_spec sp = spec("forcing.omega", 0.88, 0.95, 8);
  sp.dirs = 3;
  vi_diagram *sw = run(&sp, exact, 1);
  assert_int_equal(sw->nlines, 2);
  assert_int_equal(sw->lines[0].dir, 1);
  assert_int_equal(sw->lines[1].dir, -1);
  for (int k = 0; k < sp.steps; k++) {
    const vi_diagram_point *u = &sw->lines[0].pt[k], *d = &sw->lines[1].pt[k];
    assert_int_equal(u->n, 1);
    assert_int_equal(u->m, 1);
    assert_int_equal(d->n, 1);
    assert_int_equal(d->m, 1);
    assert_close(u->vn[u->nimp - 1], d->vn[d->nimp - 1], 1e-9);
    assert_close(u->phase[u->nimp - 1], d->phase[d->nimp - 1], 1e-9);
  }
  vi_diagram_free(&sw);
}

/* Warm start: value 2 starts where value 1 ended (same forcing phase), so
 * with Omega unchanged it continues the same trajectory: its states equal
 * one run with transient P + R + P, while a cold start (from rest, transient
 * P) is elsewhere.  Short runs, so the transient has not yet died out. */
static void warm_start(void **state)
{
  (void)state;
  vi_diagram_spec sp = spec("forcing.omega", 0.9, 0.9, 2);
  sp.transient = 5;
  sp.record = 5;
  vi_diagram *warm = run(&sp, exact, 1);
  sp.steps = 1;
  sp.transient = 15;
  vi_diagram *longer = run(&sp, exact, 1);
  sp.transient = 5;
  vi_diagram *cold = run(&sp, exact, 1);
  const double *w = warm->lines[0].strobe + 20, /* value 5 of 2 x 2 */ *l = longer->lines[0].strobe,
               *c = cold->lines[0].strobe;
  double far = 0;
  for (int i = 0; i < 5 * 4; i++) {
    assert_close(w[i], l[i], 1e-10);
    far = fmax(far, fabs(w[i] - c[i]));
  }
  assert_true(far > 1e-3);
  vi_diagram_free(&warm);
  vi_diagram_free(&longer);
  vi_diagram_free(&cold);
}

static void assert_lines_equal(const vi_diagram *a, const vi_diagram *b, int K, int R)
{
  assert_int_equal(a->nlines, b->nlines);
  for (int l = 0; l < a->nlines; l++) {
    assert_memory_equal(a->lines[l].strobe, b->lines[l].strobe,
                        sizeof(double) * K * R * 4);
    for (int k = 0; k < K; k++) {
      const vi_diagram_point *p = &a->lines[l].pt[k], *q = &b->lines[l].pt[k];
      assert_int_equal(p->n, q->n);
      assert_int_equal(p->m, q->m);
      assert_int_equal(p->nimp, q->nimp);
      if (p->nimp) assert_memory_equal(p->vn, q->vn, sizeof(double) * p->nimp);
    }
  }
}

/* Pieces run on any number of threads give bit-identical diagrams: each
 * value starts from a state fixed by the chunk count alone (the seed
 * chain's for a chunk's first value), whatever runs where. */
static void threads_identical(void **state)
{
  (void)state;
  vi_diagram_spec sp = spec("forcing.omega", 0.7, 1.3, 32);
  sp.transient = 100;
  sp.record = 20;
  sp.chunks = 16; /* a piece for each of 16 threads */
  sp.dirs = 3;
  sp.threads = 1;
  vi_diagram *a = run(&sp, exact, 1);
  for (int t = 2; t <= 16; t *= 2) { /* 1, 2, 4, 8, 16 (issue 29) */
    sp.threads = t;
    vi_diagram *b = run(&sp, exact, 1);
    assert_lines_equal(a, b, 32, 20);
    vi_diagram_free(&b);
  }
  vi_diagram_free(&a);
}

/* Seeded chunks compute every value once, warm-started as a serial sweep
 * does: with one value per chunk the seed chain is the whole line, so the
 * diagram equals the unsplit one bit for bit; with the default split
 * (vi_diagram_default_chunks: sqrt(K) values a chunk here) each chunk after
 * the first goes on from the chain's state, and where the motion is
 * unique (Fig. 2, Omega 0.7-1.3: P(1,2) below 0.8, P(1,1) above; up and
 * down sweeps agree there) every value
 * settles on the same orbit: classes equal, v_n within the transient's
 * decay (1e-9). */
static void seeded_chunks(void **state)
{
  (void)state;
  vi_diagram_spec sp = spec("forcing.omega", 0.7, 1.3, 16);
  sp.transient = 200;
  sp.record = 10;
  vi_diagram *one = run(&sp, exact, 1);
  sp.chunks = 16;
  vi_diagram *chain = run(&sp, exact, 1);
  assert_lines_equal(one, chain, 16, 10);
  sp.chunks = vi_diagram_default_chunks(&sp);
  assert_int_equal(sp.chunks, 4); /* ceil(sqrt(16)) = 4 values a chunk */
  sp.threads = 2;
  vi_diagram *split = run(&sp, exact, 1);
  for (int k = 0; k < 16; k++) {
    const vi_diagram_point *p = &one->lines[0].pt[k], *q = &split->lines[0].pt[k];
    assert_int_equal(p->n, q->n);
    assert_int_equal(p->m, q->m);
    assert_int_equal(p->nimp, q->nimp);
    for (int64_t i = 0; i < p->nimp; i++) assert_close(p->vn[i], q->vn[i], 1e-9);
  }
  /* the defaults: 1000 values in chunks of 16; --both and wide maps unsplit */
  sp.steps = 1000;
  assert_int_equal(vi_diagram_default_chunks(&sp), 63);
  sp.dirs = 3;
  assert_int_equal(vi_diagram_default_chunks(&sp), 1);
  sp.dirs = 1;
  sp.key2 = "stop.xs";
  sp.steps2 = 16;
  assert_int_equal(vi_diagram_default_chunks(&sp), 1);
  vi_diagram_free(&one);
  vi_diagram_free(&chain);
  vi_diagram_free(&split);
}

/* A two-parameter map: rows of the second key; row x_s = 100 is impact
 * free, row x_s = 0.1 at Omega = 0.9 is the Fig. 2 orbit. */
static void two_parameter_map(void **state)
{
  (void)state;
  vi_diagram_spec sp = spec("forcing.omega", 0.85, 0.9, 2);
  sp.key2 = "stop.xs";
  sp.from2 = 0.1;
  sp.to2 = 100;
  sp.steps2 = 2;
  vi_diagram *sw = run(&sp, exact, 1);
  assert_int_equal(sw->nlines, 2);
  const vi_diagram_point *p = &sw->lines[0].pt[1], *q = &sw->lines[1].pt[1];
  assert_int_equal(p->n, 1);
  assert_int_equal(p->m, 1);
  assert_close(p->vn[p->nimp - 1], FIG2_VN, 1e-9);
  assert_int_equal(q->m, 0);
  vi_diagram_free(&sw);
}

/* --orbits: every P(1,1) orbit at each value.  Fig. 2 at 0.9: one, stable
 * and admissible, the one the brute-force sweep settles on.  chatter.yaml
 * (written out here): the stable one the sweep reaches and the unstable one
 * no simulation shows (tests/orbit/ref_sdof_p11.py). */
static void p11_orbits(void **state)
{
  (void)state;
  vi_diagram_spec sp = spec("forcing.omega", 0.9, 0.9, 1);
  sp.transient = 300;
  sp.record = 10;
  sp.orbits = 360;
  vi_diagram *sw = run(&sp, exact, 1);
  const vi_diagram_point *pt = &sw->lines[0].pt[0];
  int adm = 0;
  for (int i = 0; i < pt->norb; i++)
    if (pt->oadm[i]) {
      adm++;
      assert_true(pt->ostable[i]);
      assert_close(pt->ovn[i], FIG2_VN, 1e-12);
      assert_close(pt->ovn[i], pt->vn[pt->nimp - 1], 1e-9);
    }
  assert_int_equal(adm, 1);
  vi_diagram_free(&sw);
  static const char *chatter =
      "name: chatter\nmodel: {M: [[1.0]], C: [[0.02]], K: [[0.1]]}\n"
      "forcing: {omega: 1.0, a: [0.6], f0: [0.3]}\n"
      "stop: {w: [1.0], xs: 0.0, r: 0.5}\nrun: {method: exact}\n";
  char err[2048];
  sp = spec("forcing.omega", 1.0, 1.0, 1);
  sp.transient = 10;
  sp.record = 2;
  sp.orbits = 360;
  assert_int_equal(vi_diagram_run(chatter, "chatter.yaml", NULL, 0, &sp, NULL, &sw, err, sizeof err), 0);
  pt = &sw->lines[0].pt[0];
  assert_int_equal(pt->norb, 2);
  int u = pt->ostable[0] ? 1 : 0;
  assert_false(pt->ostable[u]);
  assert_true(pt->ostable[1 - u]);
  assert_close(pt->ovn[u], 1.6134056745831746208, 1e-11);
  assert_close(pt->ovn[1 - u], 2.1562495000219778789, 1e-11);
  vi_diagram_free(&sw);
}

/* JSON: the keys the issue names, null for an unclassified value. */
static void json_form(void **state)
{
  (void)state;
  vi_diagram_spec sp = spec("forcing.omega", 0.9, 0.9, 1);
  sp.transient = 0;
  sp.record = 4;
  vi_diagram *sw = run(&sp, exact, 1);
  char *buf = NULL;
  size_t len = 0;
  FILE *f = open_memstream(&buf, &len);
  vi_diagram_print_json(sw, f);
  fclose(f);
  assert_non_null(strstr(buf, "\"param\": [0.90000000000000002]"));
  assert_non_null(strstr(buf, "\"n\": [null]"));
  assert_non_null(strstr(buf, "\"m\": [null]"));
  assert_non_null(strstr(buf, "\"vn\": [["));
  free(buf);
  vi_diagram_free(&sw);
}

/* Bad input: unknown key named at its place; no output file on failure. */
static void bad_input(void **state)
{
  (void)state;
  vi_diagram *sw = NULL;
  char err[2048];
  vi_diagram_spec sp = spec("forcing.omgea", 0.8, 0.9, 2);
  int rc = vi_diagram_run(vi_scene_default_text(), "fig2.yaml", exact, 1, &sp,
                          NULL, &sw, err, sizeof err);
  assert_int_equal(rc, 2);
  assert_null(sw);
  assert_non_null(strstr(err, "fig2.yaml:9:"));
  assert_non_null(strstr(err, "forcing.omgea"));
  sp = spec("stop.r", 0.5, 1.5, 3); /* r = 1.5 is not a restitution */
  rc = vi_diagram_run(vi_scene_default_text(), "fig2.yaml", exact, 1, &sp, NULL,
                      &sw, err, sizeof err);
  assert_int_equal(rc, 2);
  assert_non_null(strstr(err, "fig2.yaml:10:"));
  assert_non_null(strstr(err, "stop.r = 1.5"));
}

/* HDF5: the layout of share/doc/sweep-layout.md read back. */
static void hdf5_layout(void **state)
{
  (void)state;
  vi_diagram_spec sp = spec("forcing.omega", 0.88, 0.9, 3);
  sp.transient = 200;
  sp.record = 10;
  vi_diagram *sw = run(&sp, exact, 1);
  char err[256];
  const char *path = "test_sweep_out.h5";
  assert_int_equal(vi_diagram_write_h5(sw, path, err, sizeof err), 0);
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  int n[3], m[3];
  long long cnt[3];
  double vn[30], param[3];
  hid_t d = H5Dopen2(f, "/sweep/n", H5P_DEFAULT);
  H5Dread(d, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, n);
  H5Dclose(d);
  d = H5Dopen2(f, "/sweep/m", H5P_DEFAULT);
  H5Dread(d, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, m);
  H5Dclose(d);
  d = H5Dopen2(f, "/sweep/param", H5P_DEFAULT);
  H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, param);
  H5Dclose(d);
  d = H5Dopen2(f, "/sweep/impact_count", H5P_DEFAULT);
  H5Dread(d, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, cnt);
  H5Dclose(d);
  d = H5Dopen2(f, "/sweep/impacts/v_n", H5P_DEFAULT);
  H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, vn);
  H5Dclose(d);
  H5Fclose(f);
  assert_close(param[2], 0.9, 1e-15);
  for (int k = 0; k < 3; k++) {
    assert_int_equal(n[k], 1);
    assert_int_equal(m[k], 1);
    assert_int_equal(cnt[k], 10);
  }
  assert_close(vn[29], FIG2_VN, 1e-9);
  remove(path);
  vi_diagram_free(&sw);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(fig2_p11),         cmocka_unit_test(harmonic_response),
      cmocka_unit_test(up_down_agree),    cmocka_unit_test(warm_start),
      cmocka_unit_test(threads_identical),
      cmocka_unit_test(seeded_chunks), cmocka_unit_test(two_parameter_map),
      cmocka_unit_test(json_form),        cmocka_unit_test(p11_orbits),        cmocka_unit_test(bad_input),
      cmocka_unit_test(hdf5_layout),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
