/* vi_internal.h - private structures and helpers; never installed. */
#ifndef VI_INTERNAL_H
#define VI_INTERNAL_H

#include <stddef.h>

#include "vibroimpact.h"

#define VI_MSG_LEN 512

/* How a model stores M, C, K (src/model/vi_storage.h). */
typedef struct vi_storage_ops vi_storage_ops;

/* Format a message into a fixed buffer (truncating) and return code, so that
 * a check reads  if (bad) return vi_fail(m->errmsg, VI_ERR_X, "...", ...); */
int vi_fail(char *buf, int code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* PetscCheck-style: on a false condition record the message, set `st` and
 * leave through the function's single cleanup label. */
#define VI_CHECK(cond, buf, code, ...)          \
  do {                                          \
    if (!(cond)) {                              \
      st = vi_fail((buf), (code), __VA_ARGS__); \
      goto cleanup;                             \
    }                                           \
  } while (0)

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

/* Newton's law for several simultaneous contacts (vi_contact.c; the rule
 * is in vi_impact.h): the impulses P [nc] >= 0 on the stops idx [nc] for
 * the velocity v [n] before; vp [n] receives the velocity after (may be v),
 * vn [nc] the approach velocities w_k.v, ie [nc] the kinetic energy each
 * contact takes (they sum to the total loss); P, vn, ie may be NULL.
 * Returns VI_OK, VI_ERR_LIMIT (nc above VI_CONTACT_MAX),
 * VI_ERR_NOT_CONVERGED (no active set fits: G singular on the contacts). */
#define VI_CONTACT_MAX 12
/* Cholesky of a small SPD k x k matrix in place (0, or -1 if a pivot is
 * lost to round-off) and the solve with its factor (vi_dense.c). */
int vi_small_cholesky(int k, double *A);
void vi_small_solve(int k, const double *L, double *b);
int vi_contact_solve(const vi_model *m, int nc, const int *idx,
                     const double *v, double *vp, double *P, double *vn,
                     double *ie);
/* The law itself on the contacts' normal velocities u_k = w_k.v- [nc]:
 * the impulses P [nc] (v+ = v- - sum_k P_k M^-1 w_k) and the energies ie
 * [nc] (may be NULL) they take, with the restitutions r [nc] (NULL: the
 * model's).  For a caller that holds the velocities in other coordinates
 * (the exact method's modes, where q'+ = q'- - P_k psi_k). */
int vi_contact_law(const vi_model *m, int nc, const int *idx,
                   const double *r, const double *u, double *P, double *ie);

/* Modal analysis (vi_modal.c), called by vi_model_setup after M's
 * Cholesky factorisation; checks K and C (c_zero: C = 0) semidefinite. */
int vi_modal_setup(vi_model *m, int c_zero);

/* Dense helpers, column-major with leading dimension n (vi_dense.c). */
void vi_matvec(int n, const double *A, const double *x, double *y); /* y = A x */
void vi_matvec_t(int n, const double *A, const double *x, double *y); /* y = A^T x */
double vi_dot(int n, const double *x, const double *y);
/* Modal coordinates q = Psi^T M x and velocities qd = Psi^T M v of an
 * interleaved state z = (x_1, v_1, ...); q or qd may be NULL. */
void vi_modal_project(const vi_model *m, const double *z, double *q,
                      double *qd);

/* Hand a callback's user data over: the data it replaces is destroyed
 * (unless it is the same pointer), the new one is kept with its destroy
 * function.  vi_user_set(&p, &f, NULL, NULL) at destroy time frees it. */
static inline void vi_user_set(void **slot, vi_destroy_fn *fslot, void *user,
                               vi_destroy_fn destroy)
{
  if (*fslot && *slot != user) (*fslot)(*slot);
  *slot = user;
  *fslot = destroy;
}

/* 1 if the arrays [n] at a and b share memory (the API forbids it where an
 * output would overwrite an input still being read). */
static inline int vi_overlap(const double *a, const double *b, int n)
{
  return a && b && a < b + n && b < a + n;
}
/* The same for arrays of different lengths, a [na] and b [nb]. */
static inline int vi_overlap2(const double *a, size_t na, const double *b,
                              size_t nb)
{
  return a && b && a < b + nb && b < a + na;
}

#endif
