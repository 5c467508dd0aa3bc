/* vi_model_internal.h - the model's definition, private to the library
 * and never installed.  The layers above model/ (impact, flow, ledger,
 * sim, orbit, study) read its arrays through this header; base/ does not
 * know it.  The storage's operations are in vi_storage.h, the modal
 * capability's one test is vi_model_has_modes there. */
#ifndef VI_MODEL_INTERNAL_H
#define VI_MODEL_INTERNAL_H

#include <stddef.h>

#include "vi_internal.h"

/* How a model stores M, C, K (vi_storage.h). */
typedef struct vi_storage_ops vi_storage_ops;

struct vi_model {
  const vi_storage_ops *ops; /* dense or band, set at creation */
  int n;
  int frozen;
  double omega_f;
  /* as set; column-major, leading dimension n */
  double *M, *C, *K;
  double *a, *b, *f0;
  /* derived at setup */
  double *MinvK, *MinvC;          /* M^-1 K, M^-1 C */
  double *Minv_a, *Minv_b, *Minv_f0;
  /* every stop w_k.x <= xs_k (restitution r_k), ns >= 1 once set up; the
   * single-stop API ("the stop") is stop 0 of these arrays */
  int ns, ns_cap;
  double *Ws, *xsv, *rv;          /* W [n x ns], x_s [ns], r [ns] as set */
  double *MinvW, *G, *PsiW;       /* M^-1 W [n x ns], W^T M^-1 W [ns x ns],
                                     Psi^T W [n x ns]: at setup */
  int bw;                         /* half-bandwidth of M^-1 K and M^-1 C */
  double *omega, *lambda, *Psi, *PsiTM, *D, *zeta;
  double *Fa, *Fb, *F0;           /* Psi^T a, Psi^T b, Psi^T f0 */
  int proportional;               /* modes decouple (the exact flow, built
                                     on the model: vi_flow_internal.h) */
  double *block;                  /* single allocation behind the arrays */
  /* Band storage (vi_model_create_band): M, C, K in LAPACK symmetric-band
   * 'U' form, entry (i, j), i <= j, at [kd + i - j + j ldb]; the dense n x n
   * arrays and the modal ones are then NULL: a band model has no modes. */
  int band;                       /* 1 for band storage */
  int kd, ldb;                    /* storage half-bandwidth, ldb = kd + 1 */
  int kdm;                        /* M's own half-bandwidth (0: diagonal) */
  double *MB, *CB, *KB;           /* as set */
  double *LB;                     /* band Cholesky of M, or 1/m_i (kdm 0) */
  double *KR, *CR;                /* rows of K, C, scaled by 1/m_i when M is
                                     diagonal (then rows of M^-1 K, M^-1 C):
                                     row i, column j at [i (2kd+1) + j-i+kd] */
  size_t nblock;                  /* doubles in block (vi_model_copy) */
  /* how C was given: 0 a matrix, 1 Rayleigh alpha M + beta K, 2 modal
   * ratios (vi_param.c: the keys damping.alpha, .beta, .zeta) */
  int damp_kind;
  double ray_alpha, ray_beta;
  /* structural keys mass.scale, stiffness.scale, damping.scale (vi_param.c):
   * M, K, C = scale * base; sbase [3 x len] (NULL until one is set), the
   * bit j of shave when base j is captured */
  double *sbase, sscale[3];
  int shave;
  /* handles holding the model (simulations, censuses, fits, writers):
   * vi_model_set_param refuses while any does, since they keep data
   * derived from it (vi_model_hold; atomic, several threads share one) */
  int users;
  char errmsg[VI_MSG_LEN];
};

/* Largest magnitude of a load or parameter value, as a scene's numbers
 * (VI_SCENE_NUM_MAX): beyond it the energies overflow and the searches
 * for contact crawl at round-off. */
#define VI_NUM_MAX 1e100

/* A handle takes (+1) or gives back (-1) its hold on model m (vi_model.c). */
void vi_model_hold(const vi_model *m, int delta);

/* Stop k's vector w_k [n], its M^-1 w_k [n] and its modal psi_k [n]. */
static inline const double *vi_stop_w(const vi_model *m, int k)
{
  return m->Ws + (size_t)k * (size_t)m->n;
}
static inline const double *vi_stop_minvw(const vi_model *m, int k)
{
  return m->MinvW + (size_t)k * (size_t)m->n;
}
static inline const double *vi_stop_psi(const vi_model *m, int k)
{
  return m->PsiW + (size_t)k * (size_t)m->n;
}

/* The most stops in contact at once: Newton's law enumerates their active
 * sets (vi_contact.c), the held motion solves with their G (vi_sim). */
#define VI_CONTACT_MAX 12

/* Whether M is diagonal with a positive diagonal (lumped masses, and what
 * condensing massless dofs leaves of them): decided once per set-up, by
 * vi_dense_setup (vi_modal.c). */
int vi_mass_lumped(int n, const double *M);

/* K z = lambda M z for a lumped M (itype 1, Z^T M Z = I), eigenvalues
 * ascending into lam [n]: the standard problem of S K S, S = M^-1/2, with
 * Z = S Y, by dsyevd alone (dsygvd would spend two n^3 triangular
 * products on the diagonal factor).  K in A (lda), overwritten by Z; the
 * masses m_i = mass[i inc]; s [n] workspace.  dsyevd's info (vi_modal.c;
 * the dense set-up and the FE reduction's dense path). */
int vi_eig_lumped(int n, double *A, int lda, const double *mass, int inc,
                  double *lam, double *s);

/* Modal analysis (vi_modal.c), called by vi_model_setup after M's
 * Cholesky factorisation; checks K and C (c_zero: C = 0) semidefinite;
 * diag: M is lumped (vi_mass_lumped). */
int vi_modal_setup(vi_model *m, int c_zero, int diag);

/* Modal coordinates q = Psi^T M x and velocities qd = Psi^T M v of an
 * interleaved state z = (x_1, v_1, ...); q or qd may be NULL
 * (vi_modal.c). */
void vi_modal_project(const vi_model *m, const double *z, double *q,
                      double *qd);

#endif
