/* vi_impact_internal.h - Newton's law with a caller's restitutions and its
 * linearisation, for the impact wrappers and the orbit code (MODEL.md
 * sections 2, 11 and 13); never installed.
 *
 * The law has one home, vi_contact_solve_r (vi_contact.c).  On one
 * approaching contact k it is the linear map v+ = Q_k v-,
 *
 *   Q_k = I - c_k M^-1 w_k w_k^T,   c_k = (1 + r_k) / G_kk        (WB 2)
 *
 * and the functions below (vi_impact.c) apply that Q_k, its derivative in
 * r_k and the saltation matrix built on it, so that the orbit's shooting
 * maps, monodromy matrices and tangent flows use the law's own
 * linearisation instead of a copy of it. */
#ifndef VI_IMPACT_INTERNAL_H
#define VI_IMPACT_INTERNAL_H

#include "vi_model_internal.h"

/* How high a rebound rises off its stop: the gap's acceleration w.a pulls
 * it back (push > 0) after Newton's law sent it off at r v_n, so the apex
 * is (r v_n)^2 / (2 w.a).  The one home of the formula (the run's step and
 * tolerance after an impact, the chatter's accumulation test). */
static inline double vi_rebound_apex(double r, double vn, double push)
{
  return 0.5 * r * r * vn * vn / push;
}

/* The kinetic energy of the approach to stop k at v_n, KE_i = 1/2 v_n^2 /
 * G_kk (WB 12), and the part of it that an impact with restitution r takes,
 * IE = 1/2 v_n^2 (1 - r^2) / G_kk (WB 10): the closed forms of the law for
 * one contact (vi_contact_law's impulses give the same IE to round-off),
 * for a caller that holds v_n alone (the orbit's totals, the fit's
 * statistics).  g is G_kk = w_k.M^-1 w_k. */
static inline double vi_impact_ke(double vn, double g)
{
  return 0.5 * vn * vn / g;
}
static inline double vi_impact_ie(double r, double vn, double g)
{
  return 0.5 * vn * vn * (1.0 - r * r) / g;
}

/* Newton's law for several simultaneous contacts (vi_contact.c; the rule
 * is in vi_impact.h): the impulses P [nc] >= 0 on the stops idx [nc] for
 * the velocity v [n] before; vp [n] receives the velocity after (may be v),
 * vn [nc] the approach velocities w_k.v, ie [nc] the kinetic energy each
 * contact takes (they sum to the total loss); P, vn, ie may be NULL.
 * Returns VI_OK, VI_ERR_LIMIT (nc above VI_CONTACT_MAX),
 * VI_ERR_NOT_CONVERGED (no active set fits: G singular on the contacts). */
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

/* vi_contact_solve with the restitutions r [nc] of the contacts in the
 * place of the model's (r NULL: the model's r_k). */
int vi_contact_solve_r(const vi_model *m, int nc, const int *idx,
                       const double *r, const double *v, double *vp,
                       double *P, double *vn, double *ie);

/* V [n x nrhs] (leading dimension ldv) <- Q_k V; work [nrhs]. */
void vi_impact_q_left(const vi_model *m, int k, int nrhs, double *V, int ldv,
                      double *work);
/* A [nr x n] (leading dimension lda) <- A Q_k; work [nr]. */
void vi_impact_q_right(const vi_model *m, int k, int nr, double *A, int lda,
                       double *work);
/* dv+/dr_k = -(w_k.v) M^-1 w_k / G_kk [n] of the map v+ = Q_k v. */
void vi_impact_q_dr(const vi_model *m, int k, const double *v, double *out);

/* The saltation matrix of an impact on stop k (MODEL.md section 13),
 *   S = R + d g^T / v_n,   R = diag(I, Q_k),  g = (w_k, 0),
 *   d = f+ - R f-,         v_n = w_k.v- = g.f-,
 * from the vector fields f-, f+ [2n] (stacked x, v) before and after it.
 * vi_impact_salt_jump: d [2n] (may be fm); work [1]. */
void vi_impact_salt_jump(const vi_model *m, int k, const double *fm,
                         const double *fp, double *d, double *work);
/* Z [2n x nrhs] (leading dimension ldz) <- S Z; work [2 nrhs]. */
void vi_impact_salt_apply(const vi_model *m, int k, double vn,
                          const double *d, int nrhs, double *Z, int ldz,
                          double *work);
/* S [2n x 2n] (leading dimension 2n) itself. */
void vi_impact_salt_matrix(const vi_model *m, int k, double vn,
                           const double *d, double *S);

#endif
