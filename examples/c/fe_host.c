/* fe_host.c - a host finite-element code hands its structure to
 * vibroimpact, twice (vi_sparse.h):
 *
 *  A. its sparse M and K in compressed sparse column form (lower triangle,
 *     0-based): vibroimpact finds the 10 lowest modes itself (shift-invert
 *     Lanczos on a sparse Cholesky factor);
 *  B. its own modes: frequencies and the rows of the mode shapes at the two
 *     dofs that matter (the stop's and the load's), as the host's own
 *     eigensolver would give them; no M, no K.
 *
 * The structure: a clamped-free steel rod of 200 linear elements
 * (consistent mass), a stop 20 micrometres beyond the free end (r = 0.7),
 * a harmonic end load at 0.9 times the first frequency, 2 % modal damping.
 * Both models give the same impacts; the program prints the first ones and
 * fails (exit 1) if the two disagree beyond 1e-7 of a period.
 *
 *   vi_fe_host_c */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "vibroimpact.h"

enum { N = 200, K_MODES = 10, MAXIMP = 4096 };

static const double E = 210e9, RHO = 7800.0, AREA = 3.14e-4, LEN = 1.0;

typedef struct impacts {
  int count;
  double t[MAXIMP], vn[MAXIMP];
} impacts;

static int on_event(const vi_event *ev, void *user)
{
  impacts *im = user;
  if (ev->kind == VI_EVENT_IMPACT && im->count < MAXIMP) {
    im->t[im->count] = ev->t;
    im->vn[im->count++] = ev->vn;
  }
  return 0;
}

static int run(const vi_model *m, double t_end, impacts *im)
{
  vi_sim *s = NULL;
  int st = vi_sim_create(m, &s);
  if (!st) st = vi_sim_set_method(s, VI_METHOD_EXACT);
  if (!st) st = vi_sim_set_tolerances(s, 1e-11, 1e-16);
  if (!st) st = vi_sim_set_event_callback(s, on_event, im, NULL);
  /* on_event reads t and vn only: events without states, so that the
   * exact method takes each bounce in modes, O(n) instead of O(n^2) */
  if (!st) st = vi_sim_set_event_states(s, 0);
  if (!st) st = vi_sim_run(s, t_end);
  if (st < 0) fprintf(stderr, "run: %s\n", s ? vi_sim_errmsg(s) : "");
  vi_sim_destroy(&s);
  return st < 0;
}

/* The host's eigenvalue of mode j (1-based) of its mesh: for this rod it
 * is known in closed form (tests/model/test_sparse.c derives it). */
static double host_lambda(int j, double *theta)
{
  double h = LEN / N, th = (2 * j - 1) * M_PI / (2.0 * N), s = sin(0.5 * th);
  *theta = th;
  return 6.0 * E / (RHO * h * h) * 2.0 * s * s / (2.0 + cos(th));
}

int main(void)
{
  static int colptr[N + 1], rowind[2 * N];
  static double mval[2 * N], kval[2 * N], load[N];
  double h = LEN / N, ke = E * AREA / h, me = RHO * AREA * h / 6.0;
  /* the host's assembly: dof j is node j + 1 (node 0 clamped) */
  int c = 0;
  for (int j = 0; j < N; j++) {
    colptr[j] = c;
    rowind[c] = j;
    kval[c] = ke * (j + 1 < N ? 2 : 1);
    mval[c++] = 2.0 * me * (j + 1 < N ? 2 : 1);
    if (j + 1 < N) {
      rowind[c] = j + 1;
      kval[c] = -ke;
      mval[c++] = me;
    }
  }
  colptr[N] = c;
  double th, w1 = sqrt(host_lambda(1, &th)), Om = 0.9 * w1, zeta = 0.02;
  double xs = 2e-5, r = 0.7, t_end = 20.0 * 2.0 * M_PI / Om;
  load[N - 1] = 1e3; /* N, at the free end */

  /* A. sparse matrices */
  vi_fe *fe = NULL;
  vi_model *ma = NULL, *mb = NULL;
  int st = vi_fe_create(N, &fe);
  if (!st) st = vi_fe_set_mass_csc(fe, VI_CSC_LOWER, 0, colptr, rowind, mval);
  if (!st) st = vi_fe_set_stiffness_csc(fe, VI_CSC_LOWER, 0, colptr, rowind, kval);
  if (!st) st = vi_fe_set_modes(fe, K_MODES);
  if (!st) st = vi_fe_set_modal_damping(fe, 1, &zeta);
  if (!st) st = vi_fe_add_stop_dof(fe, N - 1, 1, xs, r);
  if (!st) st = vi_fe_set_forcing(fe, Om, load, NULL, NULL);
  if (!st) st = vi_fe_setup(fe);
  if (!st) st = vi_fe_create_model(fe, &ma);
  if (st) {
    fprintf(stderr, "A: %s (%s)\n", vi_strerror(st), vi_fe_errmsg(fe));
    return 1;
  }
  printf("A. from CSC M, K: omega_1 = %.6f rad/s, shift %g, backward error "
         "%.1e\n", vi_fe_omega(fe)[0], vi_fe_shift(fe), vi_fe_residual(fe));
  vi_fe_destroy(&fe);

  /* B. the host's modes: omega_j and Psi at the stop and load dof (both
   * the free end here: one row), mass-normalised */
  double omega[K_MODES], Psi[K_MODES];
  int rows[1] = {N - 1};
  for (int j = 1; j <= K_MODES; j++) {
    double lam = host_lambda(j, &th), q = 0.0;
    for (int e = 0; e < N; e++) { /* u^T M u of u_i = sin(i theta) */
      double a = sin(e * th), b = sin((e + 1) * th);
      q += me * (2 * a * a + 2 * a * b + 2 * b * b);
    }
    omega[j - 1] = sqrt(lam);
    Psi[j - 1] = sin(N * th) / sqrt(q); /* row N - 1, column j - 1 */
  }
  st = vi_fe_create(N, &fe);
  if (!st) st = vi_fe_set_host_modes(fe, K_MODES, omega, NULL, NULL, 0, 1,
                                     rows, Psi, 1);
  if (!st) st = vi_fe_set_modal_damping(fe, 1, &zeta);
  if (!st) st = vi_fe_add_stop_dof(fe, N - 1, 1, xs, r);
  if (!st) st = vi_fe_set_forcing(fe, Om, load, NULL, NULL);
  if (!st) st = vi_fe_setup(fe);
  if (!st) st = vi_fe_create_model(fe, &mb);
  if (st) {
    fprintf(stderr, "B: %s (%s)\n", vi_strerror(st), vi_fe_errmsg(fe));
    return 1;
  }
  printf("B. from the host's modes: omega_1 = %.6f rad/s\n", omega[0]);
  vi_fe_destroy(&fe);

  static impacts ia, ib;
  if (run(ma, t_end, &ia) || run(mb, t_end, &ib)) return 1;
  double dmax = 0.0, T = 2.0 * M_PI / Om;
  for (int i = 0; i < ia.count && i < ib.count; i++)
    dmax = fmax(dmax, fabs(ia.t[i] - ib.t[i]) / T);
  for (int i = 0; i < 5 && i < ia.count && i < ib.count; i++)
    printf("impact %d: t = %.9e s (A) %.9e s (B), v_n = %+.6e m/s (A) "
           "%+.6e m/s (B)\n", i, ia.t[i], ib.t[i], ia.vn[i], ib.vn[i]);
  printf("%d and %d impacts in 20 forcing periods; largest time difference "
         "%.2e periods\n", ia.count, ib.count, dmax);
  vi_model_destroy(&ma);
  vi_model_destroy(&mb);
  return ia.count == ib.count && ia.count > 0 && dmax < 1e-7 ? 0 : 1;
}
