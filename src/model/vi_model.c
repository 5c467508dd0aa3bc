/* vi_model.c - store, validate and freeze M, C, K, the forcing and the stop. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <lapacke.h>

#include "vi_storage.h"

/* Relative tolerance for symmetry (semidefiniteness: vi_modal.c): generous
 * enough for matrices read from text with 15-17 digits, tight enough to
 * catch typos. */
#define VI_SYM_TOL 1e-12

/* Doubles of a model's one block.  Dense: 10 n x n matrices (M, C, K,
 * M^-1 K, M^-1 C, Psi, Psi^T M, D and two of setup workspace) and 12
 * vectors (a, b, f0, M^-1 a, M^-1 b, M^-1 f0, omega, lambda, zeta, Fa, Fb,
 * F0).  Band (kd >= 0, at most n - 1): M, C, K and M's factor [kd + 1 x n],
 * the rows KR, CR [2 kd + 1 x n] and the six vectors a, b, f0, M^-1 a,
 * M^-1 b, M^-1 f0.  vi_model_memory_estimate counts the same. */
static double block_doubles(int n, int kd)
{
  double dn = n;
  if (kd < 0) return 10.0 * dn * dn + 12.0 * dn;
  double ldb = (double)kd + 1.0, w = 2.0 * kd + 1.0;
  return 4.0 * ldb * dn + 2.0 * w * dn + 6.0 * dn;
}

/* Capacity of the stop arrays holding ns stops (store_stop's growth). */
static double stop_capacity(int ns)
{
  if (ns < 1) return 0.0;
  double cap = 2.0;
  while (cap < ns) cap *= 2.0;
  return cap;
}

/* Bytes of a model of n coordinates in storage kd (as block_doubles) with
 * ns stops held in arrays of capacity cap: the struct, the block, the
 * stops [W | x_s | r] and, set up, M^-1 W and G (dense: also Psi^T W). */
static double model_bytes(double n, double nblock, double ns, double cap,
                          int stop_vectors, int set_up)
{
  double d = nblock + cap * (n + 2.0);
  if (set_up) d += stop_vectors * n * ns + ns * ns;
  return (double)sizeof(vi_model) + d * (double)sizeof(double);
}

int vi_model_create(int n, vi_model **out)
{
  if (!out) return VI_ERR_ARG;
  *out = NULL;
  if (n < 1) return VI_ERR_DIM;
  vi_model *m = calloc(1, sizeof *m);
  if (!m) return VI_ERR_NOMEM;
  size_t nn = (size_t)n * n;
  /* n beyond the address space: refused, not wrapped around */
  double nb = block_doubles(n, -1);
  m->block = nb < 0x1p60 ? calloc((size_t)nb, sizeof(double)) : NULL;
  if (!m->block) {
    free(m);
    return VI_ERR_NOMEM;
  }
  double *p = m->block;
  m->M = p; p += nn;
  m->C = p; p += nn;
  m->K = p; p += nn;
  m->MinvK = p; p += nn;
  m->MinvC = p; p += nn;
  m->Psi = p; p += nn;
  m->PsiTM = p; p += nn;
  m->D = p; p += nn;
  p += 2 * nn; /* spare: workspace for setup */
  m->a = p; p += n;
  m->b = p; p += n;
  m->f0 = p; p += n;
  m->Minv_a = p; p += n;
  m->Minv_b = p; p += n;
  m->Minv_f0 = p; p += n;
  m->omega = p; p += n;
  m->lambda = p; p += n;
  m->zeta = p; p += n;
  m->Fa = p; p += n;
  m->Fb = p; p += n;
  m->F0 = p;
  m->ops = &vi_storage_dense;
  m->n = n;
  m->kd = -1;
  m->nblock = (size_t)nb;
  for (int i = 0; i < n; i++) m->M[i + (size_t)i * n] = 1.0;
  *out = m;
  return VI_OK;
}

int vi_model_create_band(int n, int kd, vi_model **out)
{
  if (!out) return VI_ERR_ARG;
  *out = NULL;
  if (n < 1 || kd < 0) return VI_ERR_DIM;
  if (kd > n - 1) kd = n - 1; /* a wider band holds nothing more */
  vi_model *m = calloc(1, sizeof *m);
  if (!m) return VI_ERR_NOMEM;
  size_t ldb = (size_t)kd + 1, w = 2 * (size_t)kd + 1, nb = ldb * n;
  double nbd = block_doubles(n, kd);
  size_t count = (size_t)nbd;
  m->block = nbd < 0x1p60 ? calloc(count, sizeof(double)) : NULL;
  if (!m->block) {
    free(m);
    return VI_ERR_NOMEM;
  }
  double *p = m->block;
  m->MB = p; p += nb;
  m->CB = p; p += nb;
  m->KB = p; p += nb;
  m->LB = p; p += nb;
  m->KR = p; p += w * n;
  m->CR = p; p += w * n;
  m->a = p; p += n;
  m->b = p; p += n;
  m->f0 = p; p += n;
  m->Minv_a = p; p += n;
  m->Minv_b = p; p += n;
  m->Minv_f0 = p;
  m->n = n;
  m->nblock = count;
  m->ops = &vi_storage_band;
  m->band = 1;
  m->kd = kd;
  m->ldb = (int)ldb;
  for (int i = 0; i < n; i++) m->MB[kd + (size_t)i * ldb] = 1.0;
  *out = m;
  return VI_OK;
}

void vi_model_destroy(vi_model **model)
{
  if (!model || !*model) return;
  free((*model)->Ws);
  free((*model)->MinvW);
  free((*model)->sbase); /* vi_param.c: the structural keys */
  free((*model)->block);
  free(*model);
  *model = NULL;
}

const char *vi_model_errmsg(const vi_model *m) { return m ? m->errmsg : ""; }

void vi_model_hold(const vi_model *m, int delta)
{
  /* the count is the only field a holder writes: threads share the model */
  if (m) __atomic_add_fetch(&((vi_model *)m)->users, delta, __ATOMIC_ACQ_REL);
}

/* Common checks of every setter: not frozen, finite values. */
static int check_open(vi_model *m)
{
  if (!m) return VI_ERR_ARG;
  if (m->frozen)
    return vi_fail(m->errmsg, VI_ERR_STATE,
                   "the model is frozen by vi_model_setup; create a new one");
  return VI_OK;
}

static int check_vector(vi_model *m, const char *name, const double *v)
{
  if (!v) return VI_OK;
  for (int i = 0; i < m->n; i++)
    if (!isfinite(v[i]))
      return vi_fail(m->errmsg, VI_ERR_NONFINITE, "%s(%d) = %g is not finite",
                     name, i + 1, v[i]);
    else if (fabs(v[i]) > VI_NUM_MAX)
      return vi_fail(m->errmsg, VI_ERR_LIMIT, "%s(%d) = %g: magnitude above "
                     "1e100, outside the range where the energies stay "
                     "finite", name, i + 1, v[i]);
  return VI_OK;
}

/* Copy a symmetric matrix, checking size, finiteness and symmetry; the stored
 * copy is exactly symmetric (averaged) so later factorisations see one. */
static int set_symmetric(vi_model *m, const char *name, double *dst,
                         const double *src, int ld)
{
  int st = check_open(m);
  if (st) return st;
  int n = m->n;
  if (!src)
    return vi_fail(m->errmsg, VI_ERR_ARG, "%s: NULL array", name);
  if (ld < n)
    return vi_fail(m->errmsg, VI_ERR_DIM,
                   "%s: leading dimension %d is less than n = %d", name, ld, n);
  if (m->band) { /* a dense matrix given to a band model: outside the band
                    it must be zero */
    for (int j = 0; j < n; j++)
      for (int i = 0; i < n; i++)
        if (abs(i - j) > m->kd && src[i + (size_t)j * ld] != 0.0)
          return vi_fail(m->errmsg, VI_ERR_DIM, "%s(%d,%d) = %g lies outside "
                         "the model's half-bandwidth %d", name, i + 1, j + 1,
                         src[i + (size_t)j * ld], m->kd);
  }
  double amax = 0.0;
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      double v = src[i + (size_t)j * ld];
      if (!isfinite(v))
        return vi_fail(m->errmsg, VI_ERR_NONFINITE,
                       "%s(%d,%d) = %g is not finite", name, i + 1, j + 1, v);
      amax = fmax(amax, fabs(v));
    }
  for (int j = 0; j < n; j++)
    for (int i = j + 1; i < n; i++) {
      double lo = src[i + (size_t)j * ld], up = src[j + (size_t)i * ld];
      if (fabs(lo - up) > VI_SYM_TOL * amax)
        return vi_fail(m->errmsg, VI_ERR_NOT_SYMMETRIC,
                       "%s is not symmetric: %s(%d,%d) = %.17g but "
                       "%s(%d,%d) = %.17g",
                       name, name, i + 1, j + 1, lo, name, j + 1, i + 1, up);
    }
  if (m->band) {
    for (int j = 0; j < n; j++)
      for (int i = j - m->kd < 0 ? 0 : j - m->kd; i <= j; i++)
        dst[m->kd + i - j + (size_t)j * m->ldb] =
            0.5 * (src[i + (size_t)j * ld] + src[j + (size_t)i * ld]);
    return VI_OK;
  }
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++)
      dst[i + (size_t)j * n] =
          0.5 * (src[i + (size_t)j * ld] + src[j + (size_t)i * ld]);
  return VI_OK;
}

/* Copy a symmetric band matrix in LAPACK 'U' form (entry (i, j), i <= j,
 * at AB[kd + i - j + j ldab]) into the model's storage, band or dense. */
static int set_band(vi_model *m, const char *name, int which, int kd,
                    const double *AB, int ldab)
{
  int st = check_open(m);
  if (st) return st;
  int n = m->n;
  if (!AB) return vi_fail(m->errmsg, VI_ERR_ARG, "%s: NULL array", name);
  if (kd < 0)
    return vi_fail(m->errmsg, VI_ERR_DIM, "%s: half-bandwidth %d is "
                   "negative", name, kd);
  if (ldab < kd + 1)
    return vi_fail(m->errmsg, VI_ERR_DIM, "%s: leading dimension %d is less "
                   "than kd + 1 = %d", name, ldab, kd + 1);
  for (int j = 0; j < n; j++)
    for (int i = j - kd < 0 ? 0 : j - kd; i <= j; i++) {
      double v = AB[kd + i - j + (size_t)j * ldab];
      if (!isfinite(v))
        return vi_fail(m->errmsg, VI_ERR_NONFINITE,
                       "%s(%d,%d) = %g is not finite", name, i + 1, j + 1, v);
      if (m->band && j - i > m->kd && v != 0.0)
        return vi_fail(m->errmsg, VI_ERR_DIM, "%s(%d,%d) = %g lies outside "
                       "the model's half-bandwidth %d", name, i + 1, j + 1, v,
                       m->kd);
    }
  double *dst = m->ops->matrix(m, which, NULL);
  if (m->band) {
    memset(dst, 0, sizeof(double) * (size_t)m->ldb * n);
    int k = kd < m->kd ? kd : m->kd;
    for (int j = 0; j < n; j++)
      for (int i = j - k < 0 ? 0 : j - k; i <= j; i++)
        dst[m->kd + i - j + (size_t)j * m->ldb] =
            AB[kd + i - j + (size_t)j * ldab];
    return VI_OK;
  }
  memset(dst, 0, sizeof(double) * (size_t)n * n);
  for (int j = 0; j < n; j++)
    for (int i = j - kd < 0 ? 0 : j - kd; i <= j; i++)
      dst[i + (size_t)j * n] = dst[j + (size_t)i * n] =
          AB[kd + i - j + (size_t)j * ldab];
  return VI_OK;
}

int vi_model_set_mass_band(vi_model *m, int kd, const double *AB, int ldab)
{
  return set_band(m, "M", 0, kd, AB, ldab);
}

int vi_model_set_damping_band(vi_model *m, int kd, const double *AB, int ldab)
{
  if (m && !m->frozen) m->damp_kind = 0; /* C as a matrix */
  if (m && !AB && !m->frozen) { /* C = 0 */
    size_t sz;
    double *C = m->ops->matrix(m, 1, &sz);
    memset(C, 0, sizeof(double) * sz);
    return VI_OK;
  }
  return set_band(m, "C", 1, kd, AB, ldab);
}

int vi_model_set_stiffness_band(vi_model *m, int kd, const double *AB,
                                int ldab)
{
  return set_band(m, "K", 2, kd, AB, ldab);
}

int vi_model_set_mass(vi_model *m, const double *M, int ldm)
{
  return set_symmetric(m, "M", m ? m->ops->matrix(m, 0, NULL) : NULL, M, ldm);
}

int vi_model_set_damping(vi_model *m, const double *C, int ldc)
{
  if (m && !m->frozen) m->damp_kind = 0; /* C as a matrix */
  if (m && !C) return vi_model_set_damping_band(m, 0, NULL, 1);
  return set_symmetric(m, "C", m ? m->ops->matrix(m, 1, NULL) : NULL, C, ldc);
}

int vi_model_set_stiffness(vi_model *m, const double *K, int ldk)
{
  return set_symmetric(m, "K", m ? m->ops->matrix(m, 2, NULL) : NULL, K, ldk);
}

static int is_zero(int n, const double *v)
{
  if (!v) return 1;
  for (int i = 0; i < n; i++)
    if (v[i] != 0.0) return 0;
  return 1;
}

int vi_model_set_forcing(vi_model *m, double omega, const double *a,
                         const double *b, const double *f0)
{
  int st = check_open(m);
  if (st) return st;
  if ((st = check_vector(m, "a", a)) || (st = check_vector(m, "b", b)) ||
      (st = check_vector(m, "f0", f0)))
    return st;
  int harmonic = !is_zero(m->n, a) || !is_zero(m->n, b);
  if (!isfinite(omega))
    return vi_fail(m->errmsg, VI_ERR_NONFINITE,
                   "forcing frequency Omega = %g is not finite", omega);
  if (omega < 0.0)
    return vi_fail(m->errmsg, VI_ERR_FREQUENCY,
                   "forcing frequency Omega = %g must not be negative", omega);
  if (harmonic && omega <= 0.0)
    return vi_fail(m->errmsg, VI_ERR_FREQUENCY,
                   "forcing frequency Omega = %g must be > 0 when a or b is "
                   "non-zero", omega);
  size_t bytes = sizeof(double) * (size_t)m->n;
  a ? memcpy(m->a, a, bytes) : memset(m->a, 0, bytes);
  b ? memcpy(m->b, b, bytes) : memset(m->b, 0, bytes);
  f0 ? memcpy(m->f0, f0, bytes) : memset(m->f0, 0, bytes);
  m->omega_f = harmonic ? omega : (omega > 0.0 ? omega : 0.0);
  return VI_OK;
}

/* Validate a stop's data (w [n], x_s, r); `what` ("" or "stop 2: ")
 * prefixes the messages. */
static int check_stop(vi_model *m, const char *what, const double *w,
                      double x_s, double r)
{
  int st = check_open(m);
  if (st) return st;
  if (!w) return vi_fail(m->errmsg, VI_ERR_ARG, "%sstop vector w is NULL",
                         what);
  for (int i = 0; i < m->n; i++)
    if (!isfinite(w[i]))
      return vi_fail(m->errmsg, VI_ERR_NONFINITE, "%sw(%d) = %g is not "
                     "finite", what, i + 1, w[i]);
  if (!isfinite(x_s))
    return vi_fail(m->errmsg, VI_ERR_NONFINITE, "%sclearance x_s = %g is "
                   "not finite", what, x_s);
  if (!isfinite(r))
    return vi_fail(m->errmsg, VI_ERR_NONFINITE,
                   "%srestitution r = %g is not finite", what, r);
  if (r < 0.0 || r > 1.0)
    return vi_fail(m->errmsg, VI_ERR_RESTITUTION,
                   "%srestitution r = %g is outside [0, 1]", what, r);
  if (is_zero(m->n, w))
    return vi_fail(m->errmsg, VI_ERR_STOP_VECTOR,
                   "%sstop vector w is zero: no coordinate meets the stop",
                   what);
  return VI_OK;
}

/* Store stop k (k <= ns: k == ns appends), growing the arrays. */
static int store_stop(vi_model *m, int k, const double *w, double x_s,
                      double r)
{
  int n = m->n;
  if (k >= m->ns_cap) {
    int cap = m->ns_cap ? 2 * m->ns_cap : 2;
    if (cap > (1 << 20))
      return vi_fail(m->errmsg, VI_ERR_LIMIT, "too many stops (%d)", k + 1);
    double *p = realloc(m->Ws, sizeof(double) * (size_t)cap * (size_t)(n + 2));
    if (!p) return vi_fail(m->errmsg, VI_ERR_NOMEM, "out of memory for stops");
    /* the layout is [W | x_s | r]: move x_s and r up to the new capacity */
    memmove(p + (size_t)cap * n + cap, p + (size_t)m->ns_cap * n + m->ns_cap,
            sizeof(double) * (size_t)m->ns_cap);
    memmove(p + (size_t)cap * n, p + (size_t)m->ns_cap * n,
            sizeof(double) * (size_t)m->ns_cap);
    m->Ws = p;
    m->xsv = p + (size_t)cap * n;
    m->rv = m->xsv + cap;
    m->ns_cap = cap;
  }
  memcpy(m->Ws + (size_t)k * n, w, sizeof(double) * (size_t)n);
  m->xsv[k] = x_s;
  m->rv[k] = r;
  if (k == m->ns) m->ns++;
  return VI_OK;
}

int vi_model_set_stop(vi_model *m, const double *w, double x_s, double r)
{
  int st = check_stop(m, "", w, x_s, r);
  return st ? st : store_stop(m, 0, w, x_s, r);
}

int vi_model_add_stop(vi_model *m, const double *w, double x_s, double r)
{
  char what[32];
  snprintf(what, sizeof what, "stop %d: ", m ? m->ns + 1 : 0);
  int st = check_stop(m, what, w, x_s, r);
  return st ? st : store_stop(m, m->ns, w, x_s, r);
}

int vi_model_num_stops(const vi_model *m) { return m ? m->ns : 0; }

int vi_model_stop(const vi_model *m, int k, double *w, double *x_s,
                      double *r)
{
  if (!m || k < 0 || k >= m->ns) return VI_ERR_ARG;
  if (w) memcpy(w, m->Ws + (size_t)k * m->n, sizeof(double) * (size_t)m->n);
  if (x_s) *x_s = m->xsv[k];
  if (r) *r = m->rv[k];
  return VI_OK;
}

const double *vi_model_delassus(const vi_model *m, int *ld)
{
  if (ld) *ld = m ? m->ns : 0;
  return m && m->frozen ? m->G : NULL;
}

/* M^-1 w_k for every stop (reusing the Cholesky factor L of M), the
 * Delassus matrix G = W^T M^-1 W of Newton's law for simultaneous contacts,
 * and the modal stop vectors Psi^T w_k (after the modal setup). */
static int setup_stops(vi_model *m, const double *L)
{
  int n = m->n, ns = m->ns;
  size_t nS = (size_t)n * ns;
  free(m->MinvW);
  m->MinvW = malloc(sizeof(double) * (2 * nS + (size_t)ns * ns));
  if (!m->MinvW) return vi_fail(m->errmsg, VI_ERR_NOMEM, "out of memory");
  m->PsiW = m->MinvW + nS;
  m->G = m->PsiW + nS;
  memcpy(m->MinvW, m->Ws, sizeof(double) * nS);
  lapack_int info = LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'L', n, (lapack_int)ns,
                                   L, n, m->MinvW, n);
  if (info != 0)
    return vi_fail(m->errmsg, VI_ERR_LAPACK, "dpotrs failed on the stops "
                   "(info %d)", (int)info);
  for (int k = 0; k < ns; k++)
    for (int j = 0; j < ns; j++)
      m->G[j + (size_t)k * ns] =
          vi_dot(n, m->Ws + (size_t)j * n, m->MinvW + (size_t)k * n);
  /* exactly symmetric, as the LCP's Cholesky factorisations expect */
  for (int k = 0; k < ns; k++)
    for (int j = k + 1; j < ns; j++)
      m->G[j + (size_t)k * ns] = m->G[k + (size_t)j * ns] =
          0.5 * (m->G[j + (size_t)k * ns] + m->G[k + (size_t)j * ns]);
  return VI_OK;
}

int vi_model_setup(vi_model *m)
{
  int st = check_open(m);
  if (st) return st;
  if (m->ns < 1)
    return vi_fail(m->errmsg, VI_ERR_STOP_VECTOR,
                   "no stop: call vi_model_set_stop before setup");
  /* dense: the modal analysis; band: O(n kd), no modes */
  if ((st = m->ops->setup(m))) return st;
  m->frozen = 1;
  m->errmsg[0] = '\0';
  return VI_OK;
}

/* M^-1 [K C a b f0] in place (the copies in MinvK, MinvC, Minv_a..f0) by
 * M's Cholesky factor L: dpotrs's info. */
static lapack_int minv_solve(vi_model *m, const double *L, int c_zero)
{
  int n = m->n;
  lapack_int info = LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'L', n, n, L, n, m->MinvK, n);
  if (info == 0 && !c_zero)
    info = LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'L', n, n, L, n, m->MinvC, n);
  /* the three vectors are contiguous in the block: one solve */
  if (info == 0)
    info = LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'L', n, 3, L, n, m->Minv_a, n);
  return info;
}

/* The same for a lumped M: row i divided by m_ii. */
static void lumped_solve(vi_model *m, int c_zero)
{
  int n = m->n;
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      double mi = m->M[i + (size_t)i * n];
      m->MinvK[i + (size_t)j * n] /= mi;
      if (!c_zero) m->MinvC[i + (size_t)j * n] /= mi;
    }
  for (int i = 0; i < n; i++) {
    double mi = m->M[i + (size_t)i * n];
    m->Minv_a[i] /= mi;
    m->Minv_b[i] /= mi;
    m->Minv_f0[i] /= mi;
  }
}

int vi_dense_setup(vi_model *m)
{
  int st, n = m->n;
  size_t nn = (size_t)n * n;
  double *work = m->D + nn; /* the two spare n x n blocks */
  double *L = work + nn;
  /* K and C are checked semidefinite on the modes (vi_modal.c), at no
   * extra O(n^3) cost */
  int c_zero = 1;
  for (size_t k = 0; k < nn && c_zero; k++) c_zero = m->C[k] == 0.0;

  /* Cholesky of M: the positive-definiteness test, and M^-1 for the RHS;
   * a lumped M's factor is its square root, and M^-1 a row scaling: the
   * n^3 / 3 factorisation and two n^3 triangular solves of n right-hand
   * sides spared (a fifth of a 1000-mass chain's set-up) */
  int diag = vi_mass_lumped(n, m->M);
  lapack_int info = 0;
  if (diag) {
    memset(L, 0, sizeof(double) * nn);
    for (int i = 0; i < n; i++) L[i + (size_t)i * n] = sqrt(m->M[i + (size_t)i * n]);
  } else {
    memcpy(L, m->M, sizeof(double) * nn);
    info = LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'L', n, L, n);
  }
  if (info != 0) {
    /* a zero row is the common case from an FE code: a massless dof,
     * which the finite-element set-up condenses and this one cannot */
    int j = (int)info - 1, zero = j < n;
    for (int i = 0; i < n && zero; i++) zero = m->M[i + (size_t)j * n] == 0.0;
    if (zero)
      return vi_fail(m->errmsg, VI_ERR_NOT_SPD, "M is not positive definite: "
                     "dof %d has no mass (row %d of M is zero); the finite-element "
                     "set-up (vi_fe_setup) condenses massless dofs",
                     j + 1, j + 1);
    return vi_fail(m->errmsg, VI_ERR_NOT_SPD,
                   "M is not positive definite (Cholesky fails at column %d)",
                   (int)info);
  }
  /* right-hand sides [K C a b f0] (C only if non-zero), solved in place in
   * the model's own arrays */
  memcpy(m->MinvK, m->K, sizeof(double) * nn);
  if (!c_zero) memcpy(m->MinvC, m->C, sizeof(double) * nn);
  const double *vecs[3] = {m->a, m->b, m->f0};
  double *outs[3] = {m->Minv_a, m->Minv_b, m->Minv_f0};
  for (int k = 0; k < 3; k++) memcpy(outs[k], vecs[k], sizeof(double) * n);
  if (diag)
    lumped_solve(m, c_zero);
  else
    info = minv_solve(m, L, c_zero);
  if (c_zero) memset(m->MinvC, 0, sizeof(double) * nn);
  if (info != 0)
    return vi_fail(m->errmsg, VI_ERR_LAPACK, "dpotrs failed (info %d)",
                   (int)info);
  if ((st = setup_stops(m, L))) return st;

  /* half-bandwidth of the RHS matrices: a chain with diagonal M is
   * tridiagonal, and the RHS and band Jacobian exploit it */
  m->bw = 0;
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++)
      if ((m->MinvK[i + (size_t)j * n] != 0.0 ||
           m->MinvC[i + (size_t)j * n] != 0.0) && abs(i - j) > m->bw)
        m->bw = abs(i - j);

  if ((st = vi_modal_setup(m, c_zero, diag))) return st;
  for (int k = 0; k < m->ns; k++)
    vi_matvec_t(n, m->Psi, m->Ws + (size_t)k * n, m->PsiW + (size_t)k * n);
  return VI_OK;
}

/* ---- getters ------------------------------------------------------------ */
#define FROZEN_OR(m, v) (((m) && (m)->frozen) ? (v) : 0)

int vi_model_n(const vi_model *m) { return m ? m->n : 0; }
double vi_model_omega_forcing(const vi_model *m) { return FROZEN_OR(m, m->omega_f); }
double vi_model_forcing_period(const vi_model *m)
{
  double w = vi_model_omega_forcing(m);
  return w > 0 ? vi_forcing_period(w) : 0.0;
}
double vi_model_clearance(const vi_model *m) { return FROZEN_OR(m, m->xsv[0]); }
double vi_model_restitution(const vi_model *m) { return FROZEN_OR(m, m->rv[0]); }
const double *vi_model_mass(const vi_model *m) { return FROZEN_OR(m, m->M); }
const double *vi_model_damping(const vi_model *m) { return FROZEN_OR(m, m->C); }
const double *vi_model_stiffness(const vi_model *m) { return FROZEN_OR(m, m->K); }
const double *vi_model_stop_vector(const vi_model *m) { return FROZEN_OR(m, m->Ws); }
const double *vi_model_forcing_cos(const vi_model *m) { return FROZEN_OR(m, m->a); }
const double *vi_model_forcing_sin(const vi_model *m) { return FROZEN_OR(m, m->b); }
const double *vi_model_forcing_const(const vi_model *m) { return FROZEN_OR(m, m->f0); }
const double *vi_model_omega(const vi_model *m) { return FROZEN_OR(m, m->omega); }
const double *vi_model_zeta(const vi_model *m) { return FROZEN_OR(m, m->zeta); }
const double *vi_model_modal_stop(const vi_model *m) { return FROZEN_OR(m, m->PsiW); }
const double *vi_model_modal_forcing_cos(const vi_model *m) { return FROZEN_OR(m, m->Fa); }
const double *vi_model_modal_forcing_sin(const vi_model *m) { return FROZEN_OR(m, m->Fb); }
const double *vi_model_modal_forcing_const(const vi_model *m) { return FROZEN_OR(m, m->F0); }
int vi_model_is_proportional(const vi_model *m) { return FROZEN_OR(m, m->proportional); }
double vi_model_stop_compliance(const vi_model *m) { return FROZEN_OR(m, m->G[0]); }

const double *vi_model_modal_shapes(const vi_model *m, int *ld)
{
  if (ld) *ld = m ? m->n : 0;
  return FROZEN_OR(m, m->Psi);
}

const double *vi_model_modal_damping(const vi_model *m, int *ld)
{
  if (ld) *ld = m ? m->n : 0;
  return FROZEN_OR(m, m->D);
}

int vi_model_need_modes(const vi_model *m, char *buf, const char *what)
{
  if (vi_model_has_modes(m)) return VI_OK;
  if (!buf) return VI_ERR_UNSUPPORTED;
  return vi_fail(buf, VI_ERR_UNSUPPORTED, "%s the modes, which a "
                 "band-storage model does not have", what);
}

int vi_model_to_modal(const vi_model *m, const double *x, double *q)
{
  if (!m || !x || !q) return VI_ERR_ARG;
  if (!m->frozen) return VI_ERR_STATE;
  if (!vi_model_has_modes(m)) return VI_ERR_UNSUPPORTED; /* band: no modes */
  if (vi_overlap(x, q, m->n)) return VI_ERR_ARG;
  vi_matvec(m->n, m->PsiTM, x, q);
  return VI_OK;
}

int vi_model_from_modal(const vi_model *m, const double *q, double *x)
{
  if (!m || !x || !q) return VI_ERR_ARG;
  if (!m->frozen) return VI_ERR_STATE;
  if (!vi_model_has_modes(m)) return VI_ERR_UNSUPPORTED; /* band: no modes */
  if (vi_overlap(q, x, m->n)) return VI_ERR_ARG;
  vi_matvec(m->n, m->Psi, q, x);
  return VI_OK;
}

double vi_model_energy(const vi_model *m, const double *x, const double *v)
{
  if (!m || !x || !v) return NAN;
  return m->ops->energy(m, x, v);
}

/* ---- builders ----------------------------------------------------------- */
int vi_build_chain(int n, const double *mass, const double *k,
                   const double *c, double *M, double *C, double *K, int ld)
{
  if (n < 1 || ld < n) return VI_ERR_DIM;
  if (!mass || !k || !M || !C || !K) return VI_ERR_ARG;
  /* a chain needs positive masses and non-negative springs and dampers */
  for (int j = 0; j < n; j++) {
    double cj = c ? c[j] : 0.0;
    if (!isfinite(mass[j]) || !isfinite(k[j]) || !isfinite(cj))
      return VI_ERR_NONFINITE;
    if (!(mass[j] > 0.0) || k[j] < 0.0 || cj < 0.0) return VI_ERR_ARG;
  }
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++)
      M[i + (size_t)j * ld] = C[i + (size_t)j * ld] = K[i + (size_t)j * ld] = 0;
  for (int j = 0; j < n; j++) {
    double cj = c ? c[j] : 0.0;
    M[j + (size_t)j * ld] = mass[j];
    /* element j joins mass j-1 (the ground for j = 0) to mass j */
    K[j + (size_t)j * ld] += k[j];
    C[j + (size_t)j * ld] += cj;
    if (j > 0) {
      K[(j - 1) + (size_t)(j - 1) * ld] += k[j];
      C[(j - 1) + (size_t)(j - 1) * ld] += cj;
      K[(j - 1) + (size_t)j * ld] = K[j + (size_t)(j - 1) * ld] = -k[j];
      C[(j - 1) + (size_t)j * ld] = C[j + (size_t)(j - 1) * ld] = -cj;
    }
  }
  return VI_OK;
}

/* ---- band storage ------------------------------------------------------- */
int vi_model_bandwidth(const vi_model *m) { return m && m->band ? m->kd : -1; }

static const double *band_view(const vi_model *m, const double *AB, int *kd,
                               int *ldab)
{
  int ok = m && m->band && m->frozen;
  if (kd) *kd = ok ? m->kd : 0;
  if (ldab) *ldab = ok ? m->ldb : 0;
  return ok ? AB : NULL;
}

const double *vi_model_mass_band(const vi_model *m, int *kd, int *ldab)
{
  return band_view(m, m ? m->MB : NULL, kd, ldab);
}

const double *vi_model_damping_band(const vi_model *m, int *kd, int *ldab)
{
  return band_view(m, m ? m->CB : NULL, kd, ldab);
}

const double *vi_model_stiffness_band(const vi_model *m, int *kd, int *ldab)
{
  return band_view(m, m ? m->KB : NULL, kd, ldab);
}

double vi_model_omega_bound(const vi_model *m)
{
  if (!m || !m->frozen) return 0.0;
  return m->ops->omega_bound(m);
}

int64_t vi_model_memory(const vi_model *m)
{
  if (!m) return 0;
  return (int64_t)model_bytes(m->n, (double)m->nblock, m->ns, m->ns_cap,
                              m->ops->stop_vectors, m->MinvW != NULL);
}

/* What the integrators allocate per method, in doubles, for a state of
 * N = 2n and a ledger of 4n quadratures (SUNDIALS 6.4: CVODE keeps q_max+1
 * Nordsieck arrays and ~10 work vectors, ARKODE's ERK its stages and ~8). */
static double integrator_doubles(int method, double n, int ledger)
{
  double N = 2.0 * n;
  double v = method == VI_METHOD_ERK ? (13.0 + 8.0 + 13.0 + 4.0) * N
             : method == VI_METHOD_BDF ? (6.0 + 10.0) * N
                                       : (13.0 + 10.0) * N;
  if (ledger) v += (method == VI_METHOD_ERK ? 38.0 : 23.0) * 5.0 * n + 16.0 * n;
  return v + 16.0 * n; /* the sim's own state and scratch */
}

int vi_model_memory_estimate(int n, int kd, int ns, int method, int ledger,
                             int64_t *bytes)
{
  if (!bytes) return VI_ERR_ARG;
  *bytes = 0;
  if (n < 1 || ns < 0) return VI_ERR_DIM;
  if (method < 0 || method >= VI_METHOD_COUNT || (ledger != 0 && ledger != 1))
    return VI_ERR_ARG;
  double dn = n, d;
  int kb = kd < 0 ? -1 : kd > n - 1 ? n - 1 : kd;
  /* the model itself, set up, exactly as vi_model_memory will count it */
  double model = model_bytes(
      dn, block_doubles(n, kb), ns, stop_capacity(ns),
      kb >= 0 ? vi_storage_band.stop_vectors : vi_storage_dense.stop_vectors,
      1);
  if (kd >= 0) { /* band storage */
    if (method == VI_METHOD_EXACT || ledger) return VI_ERR_UNSUPPORTED;
    double k = kb, ldb = k + 1.0;
    /* the PSD check's copy at setup */
    d = ldb * dn;
    if (method == VI_METHOD_BDF) { /* SUNBandMatrix(N, 2k, 2k + 1) stores
                                      smu + ml + 1 rows (smu = mu + ml),
                                      and CVODE keeps a saved copy */
      double N = 2.0 * dn, ml = 2.0 * k + 1.0;
      double smu = fmin(N - 1.0, 2.0 * k + ml);
      d += 2.0 * (smu + ml + 1.0) * N + N;
    }
  } else { /* dense: beside the model's 10 n^2, dsygvd's 2 n^2 at setup
              and LAPACK's workspaces: 14 n^2 in all measured (max RSS at
              n = 1000) */
    d = 4.0 * dn * dn + 8.0 * dn;
    if (method == VI_METHOD_BDF) d += 2.0 * 4.0 * dn * dn + 2.0 * dn;
    /* non-proportional damping: the complex 2n x 2n eigenvectors and their
     * inverse of the closed form (an upper bound: proportional needs none) */
    if (method == VI_METHOD_EXACT || method == VI_METHOD_AUTO)
      d += 16.0 * dn * dn;
    if (ledger) d += 8.0 * dn;
  }
  d += integrator_doubles(method == VI_METHOD_AUTO ? VI_METHOD_ADAMS : method,
                          dn, ledger);
  double b = model + d * (double)sizeof(double) + 4096.0;
  if (!(b < 9.0e18)) return VI_ERR_LIMIT;
  *bytes = (int64_t)b;
  return VI_OK;
}

/* Validate a chain's masses, springs and dampers. */
static int check_chain(int n, const double *mass, const double *k,
                       const double *c)
{
  if (n < 1) return VI_ERR_DIM;
  if (!mass || !k) return VI_ERR_ARG;
  /* a chain needs positive masses and non-negative springs and dampers */
  for (int j = 0; j < n; j++) {
    double cj = c ? c[j] : 0.0;
    if (!isfinite(mass[j]) || !isfinite(k[j]) || !isfinite(cj))
      return VI_ERR_NONFINITE;
    if (!(mass[j] > 0.0) || k[j] < 0.0 || cj < 0.0) return VI_ERR_ARG;
  }
  return VI_OK;
}

int vi_build_chain_band(int n, const double *mass, const double *k,
                        const double *c, double *MB, double *CB, double *KB,
                        int ldab)
{
  if (ldab < 2) return VI_ERR_DIM;
  int st = check_chain(n, mass, k, c);
  if (st) return st;
  if (!MB || !CB || !KB) return VI_ERR_ARG;
  for (int j = 0; j < n; j++) {
    double *mj = MB + (size_t)j * ldab, *cj = CB + (size_t)j * ldab,
           *kj = KB + (size_t)j * ldab;
    for (int i = 0; i < ldab; i++) mj[i] = cj[i] = kj[i] = 0.0;
  }
  /* 'U' form, kd = 1: row 1 the diagonal, row 0 the superdiagonal */
  for (int j = 0; j < n; j++) {
    double cv = c ? c[j] : 0.0;
    size_t d = 1 + (size_t)j * ldab;
    MB[d] = mass[j];
    /* element j joins mass j-1 (the ground for j = 0) to mass j */
    KB[d] += k[j];
    CB[d] += cv;
    if (j > 0) {
      KB[d - ldab] += k[j];
      CB[d - ldab] += cv;
      KB[d - 1] = -k[j];
      CB[d - 1] = -cv;
    }
  }
  return VI_OK;
}

int vi_model_create_chain(int n, const double *mass, const double *k,
                          const double *c, vi_model **out)
{
  if (!out) return VI_ERR_ARG;
  *out = NULL;
  int st = check_chain(n, mass, k, c);
  if (st) return st;
  vi_model *m;
  if ((st = vi_model_create_band(n, 1, &m))) return st;
  if (n == 1) { /* kd is clamped to n - 1 = 0: the diagonal only */
    m->MB[0] = mass[0];
    m->KB[0] = k[0];
    m->CB[0] = c ? c[0] : 0.0;
  } else {
    vi_build_chain_band(n, mass, k, c, m->MB, m->CB, m->KB, m->ldb);
  }
  *out = m;
  return VI_OK;
}
