/* vi_param.c - parameters by key (vi_param.h): a table from key to setter
 * and getter; a change to a set-up model redoes only what it touches. */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vibroimpact/vi_param.h"
#include "vi_storage.h"

enum {
  P_OMEGA, P_A, P_B, P_F0, P_XS, P_R, P_ALPHA, P_BETA, P_ZETA, P_ZETA_ALL,
  P_MSCALE, P_KSCALE, P_CSCALE, P_T0, P_X, P_V, P_COUNT
};

/* The key patterns: "[]" stands for a 1-based index. */
static const struct {
  const char *shape; /* the key with its indices removed */
  const char *name;  /* as documented */
  int kind;
} keys[] = {
    {"forcing.omega", "forcing.omega", VI_PARAM_MODEL},
    {"forcing.a[]", "forcing.a[i]", VI_PARAM_MODEL},
    {"forcing.b[]", "forcing.b[i]", VI_PARAM_MODEL},
    {"forcing.f0[]", "forcing.f0[i]", VI_PARAM_MODEL},
    {"stops[].xs", "stops[k].xs", VI_PARAM_MODEL},
    {"stops[].r", "stops[k].r", VI_PARAM_MODEL},
    {"damping.alpha", "damping.alpha", VI_PARAM_MODEL},
    {"damping.beta", "damping.beta", VI_PARAM_MODEL},
    {"damping.zeta[]", "damping.zeta[j]", VI_PARAM_MODEL},
    {"damping.zeta", "damping.zeta", VI_PARAM_MODEL},
    {"mass.scale", "mass.scale", VI_PARAM_MODEL},
    {"stiffness.scale", "stiffness.scale", VI_PARAM_MODEL},
    {"damping.scale", "damping.scale", VI_PARAM_MODEL},
    {"initial.t0", "initial.t0", VI_PARAM_INITIAL_STATE},
    {"initial.x[]", "initial.x[i]", VI_PARAM_INITIAL_STATE},
    {"initial.v[]", "initial.v[i]", VI_PARAM_INITIAL_STATE},
};

/* A parsed key: its table entry and its 1-based index (0: none). */
typedef struct pkey {
  int id, idx;
} pkey;

/* Parse `key`: -1 if it matches no pattern.  "stop.xs" is stops[1].xs. */
static int parse_key(const char *key, pkey *out)
{
  char shape[64];
  size_t k = 0;
  int nidx = 0;
  long idx = 0;
  if (!key) return -1;
  if (!strcmp(key, "stop.xs")) key = "stops[1].xs";
  else if (!strcmp(key, "stop.r")) key = "stops[1].r";
  for (const char *p = key; *p; p++) {
    if (k + 3 >= sizeof shape) return -1;
    if (*p != '[') {
      shape[k++] = *p;
      continue;
    }
    char *end;
    if (p[1] < '0' || p[1] > '9' || nidx++) return -1;
    idx = strtol(p + 1, &end, 10);
    if (*end != ']' || idx > INT_MAX) return -1;
    shape[k++] = '[';
    shape[k++] = ']';
    p = end;
  }
  shape[k] = '\0';
  for (int i = 0; i < P_COUNT; i++)
    if (!strcmp(shape, keys[i].shape)) {
      out->id = i;
      out->idx = (int)idx;
      return 0;
    }
  return -1;
}

static int unknown(char *buf, const char *key)
{
  char list[400];
  size_t k = 0;
  for (int i = 0; i < P_COUNT && k < sizeof list; i++)
    k += (size_t)snprintf(list + k, sizeof list - k, "%s%s", i ? ", " : "",
                          keys[i].name);
  return vi_fail(buf, VI_ERR_ARG, "unknown parameter key \"%s\" (the keys "
                 "are %s; indices 1-based)", key ? key : "(null)", list);
}

int vi_param_kind(const char *key)
{
  pkey p;
  return parse_key(key, &p) ? VI_PARAM_UNKNOWN : keys[p.id].kind;
}

int vi_param_key_count(void) { return P_COUNT; }

const char *vi_param_key_name(int i)
{
  return i >= 0 && i < P_COUNT ? keys[i].name : NULL;
}

/* ---- what a change redoes on a set-up model ------------------------------ */

/* M^-1 f and Psi^T f of a forcing vector f [n]: dense M^-1 f by the
 * Cholesky factor of M, solved as vi_model_setup solves it (so that a
 * changed model and one built with the value agree to the last bit); band
 * by the model's band factor. */
static int refresh_vector(vi_model *m, const double *f, double *minvf,
                          double *modal)
{
  int n = m->n;
  memcpy(minvf, f, sizeof(double) * (size_t)n);
  int info = m->ops->solve_mass(m, 1, minvf);
  if (info) return info < 0 ? VI_ERR_NOMEM : VI_ERR_LAPACK;
  if (!vi_model_has_modes(m)) return VI_OK;
  vi_matvec_t(n, m->Psi, f, modal);
  return VI_OK;
}

/* Half-bandwidth of the dense M^-1 K and M^-1 C (as vi_model_setup). */
static void dense_bandwidth(vi_model *m)
{
  int n = m->n;
  m->bw = 0;
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++)
      if ((m->MinvK[i + (size_t)j * n] != 0.0 ||
           m->MinvC[i + (size_t)j * n] != 0.0) && abs(i - j) > m->bw)
        m->bw = abs(i - j);
}

/* Largest |i - j| with a non-zero entry of a 'U' band matrix. */
static int band_extent(const double *AB, int n, int kd, int ldb)
{
  for (int d = kd; d > 0; d--)
    for (int j = d; j < n; j++)
      if (AB[kd - d + (size_t)j * ldb] != 0.0) return d;
  return 0;
}

/* A new band C: its rows CR (scaled by 1/m_i for a diagonal M) and the
 * Jacobian's half-bandwidth, as the band setup (vi_band_model.c) makes them. */
static void refresh_band_damping(vi_model *m)
{
  int n = m->n, kd = m->kd, ldb = m->ldb, w = 2 * kd + 1;
  for (int i = 0; i < n; i++) {
    double s = m->kdm == 0 ? m->LB[i] : 1.0, *cr = m->CR + (size_t)i * w;
    for (int d = -kd; d <= kd; d++) {
      int j = i + d;
      if (j < 0 || j >= n) {
        cr[d + kd] = 0.0;
        continue;
      }
      int lo = i < j ? i : j, hi = i < j ? j : i;
      cr[d + kd] = s * m->CB[kd + lo - hi + (size_t)hi * ldb];
    }
  }
  int bk = band_extent(m->KB, n, kd, ldb), bc = band_extent(m->CB, n, kd, ldb);
  m->bw = m->kdm == 0 ? (bk > bc ? bk : bc) : n - 1;
}

/* Modal damping ratios from D's diagonal. */
static void refresh_zeta(vi_model *m)
{
  int n = m->n;
  for (int j = 0; j < n; j++) {
    double d = m->D[j + (size_t)j * n];
    m->zeta[j] = m->omega[j] > 0.0 ? d / (2.0 * m->omega[j]) : 0.0;
  }
}

/* C = alpha M + beta K; on a set-up model M^-1 C = alpha I + beta M^-1 K
 * and D = Psi^T C Psi = alpha I + beta Lambda (Psi^T M Psi = I, Psi^T K Psi
 * = Lambda, MODEL.md section 3): no modal analysis. */
static int set_rayleigh(vi_model *m, double alpha, double beta)
{
  int n = m->n;
  size_t len;
  const double *M = m->ops->matrix(m, 0, NULL), *K = m->ops->matrix(m, 2, NULL);
  double *C = m->ops->matrix(m, 1, &len);
  for (size_t i = 0; i < len; i++) C[i] = alpha * M[i] + beta * K[i];
  m->damp_kind = 1;
  m->ray_alpha = alpha;
  m->ray_beta = beta;
  if (!m->frozen) return VI_OK;
  if (!vi_model_has_modes(m)) { /* band: its row form; no modes to redo */
    refresh_band_damping(m);
    return VI_OK;
  }
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      size_t ij = i + (size_t)j * n;
      m->MinvC[ij] = (i == j ? alpha : 0.0) + beta * m->MinvK[ij];
      m->D[ij] = i == j ? alpha + beta * m->lambda[j] : 0.0;
    }
  m->proportional = 1;
  refresh_zeta(m);
  dense_bandwidth(m);
  return VI_OK;
}

/* Modal damping ratios zeta [n]: D = diag(2 zeta_j omega_j), C = M Psi D
 * Psi^T M = PsiTM^T D PsiTM, M^-1 C = Psi D PsiTM. */
static int set_modal_damping(vi_model *m, const double *zeta)
{
  int n = m->n;
  double *DP = malloc(sizeof(double) * (size_t)n * n);
  if (!DP) return vi_fail(m->errmsg, VI_ERR_NOMEM, "out of memory");
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      double d = 2.0 * zeta[i] * m->omega[i];
      DP[i + (size_t)j * n] = d * m->PsiTM[i + (size_t)j * n];
      m->D[i + (size_t)j * n] = i == j ? d : 0.0;
    }
  for (int j = 0; j < n; j++) {
    vi_matvec_t(n, m->PsiTM, DP + (size_t)j * n, m->C + (size_t)j * n);
    vi_matvec(n, m->Psi, DP + (size_t)j * n, m->MinvC + (size_t)j * n);
  }
  free(DP);
  for (int j = 0; j < n; j++) /* exactly symmetric, as set_symmetric */
    for (int i = j + 1; i < n; i++)
      m->C[i + (size_t)j * n] = m->C[j + (size_t)i * n] =
          0.5 * (m->C[i + (size_t)j * n] + m->C[j + (size_t)i * n]);
  m->damp_kind = 2;
  m->ray_alpha = m->ray_beta = NAN;
  m->proportional = 1;
  for (int j = 0; j < n; j++) /* as given, not D_jj / (2 omega_j) again */
    m->zeta[j] = m->omega[j] > 0.0 ? zeta[j] : 0.0;
  dense_bandwidth(m);
  return VI_OK;
}

/* ---- structural keys: M, K or C scaled, the set-up redone -----------------
 * mass.scale, stiffness.scale and damping.scale multiply the matrix as it
 * was given (its base, captured at the first change: a scene builds a
 * uniform chain from unit matrices and sets m, k, c this way, so a study
 * changing one gets the model the scene would build with that value, bit
 * for bit).  A new M or K changes the modes: the whole set-up (M^-1 K,
 * the stops' M^-1 W and G, the modal analysis, or the band set-up) is
 * redone on a copy that replaces the model only when it succeeds;
 * Rayleigh damping follows M and K (C = alpha M + beta K), modal damping
 * keeps its ratios on the new modes, a matrix C stays. */

/* Matrix j (0 M, 1 K, 2 C) as stored and its length. */
static double *scaled_matrix(vi_model *m, int j, size_t *len)
{
  return m->ops->matrix(m, j == 0 ? 0 : j == 1 ? 2 : 1, len);
}

/* The base of matrix j: captured now if it was not, or if the matrix is no
 * longer scale * base (given again since, or damping made Rayleigh). */
static int capture_base(vi_model *m, int j)
{
  size_t len;
  const double *X = scaled_matrix(m, j, &len);
  if (!m->sbase && !(m->sbase = calloc(3 * len, sizeof(double))))
    return vi_fail(m->errmsg, VI_ERR_NOMEM, "out of memory");
  double *B = m->sbase + (size_t)j * len;
  int ok = (m->shave >> j) & 1;
  for (size_t i = 0; ok && i < len; i++) ok = X[i] == m->sscale[j] * B[i];
  if (!ok) {
    memcpy(B, X, sizeof(double) * len);
    m->sscale[j] = 1.0;
    m->shave |= 1 << j;
  }
  return VI_OK;
}

static int check_scale(vi_model *m, int j, const char *key, double v)
{
  if (j == 0 ? !(v > 0.0) : v < 0.0)
    return vi_fail(m->errmsg, j == 0 ? VI_ERR_NOT_SPD : VI_ERR_NOT_PSD,
                   "%s = %.17g: the %s must be %s", key, v,
                   j == 0 ? "mass" : j == 1 ? "stiffness" : "damping",
                   j == 0 ? "positive definite (scale > 0)"
                          : "semidefinite (scale >= 0)");
  if (j == 2 && m->damp_kind != 0)
    return vi_fail(m->errmsg, VI_ERR_UNSUPPORTED, "%s: the damping is %s; "
                   "change %s instead", key,
                   m->damp_kind == 1 ? "Rayleigh" : "given by modal ratios",
                   m->damp_kind == 1 ? "damping.alpha, damping.beta"
                                     : "damping.zeta");
  return VI_OK;
}

/* Matrix j = s * base on a model not set up (or a copy being redone), C
 * following M and K when it is Rayleigh damping. */
static int apply_scale(vi_model *m, int j, double s)
{
  int st = capture_base(m, j);
  if (st) return st;
  size_t len;
  double *X = scaled_matrix(m, j, &len);
  const double *B = m->sbase + (size_t)j * len;
  for (size_t i = 0; i < len; i++) X[i] = s * B[i];
  m->sscale[j] = s;
  if (j < 2 && m->damp_kind == 1) return set_rayleigh(m, m->ray_alpha, m->ray_beta);
  return VI_OK;
}

/* On a set-up model: a copy scaled and set up again, which replaces the
 * model on success (the caller's pointer stays valid); the model is
 * unchanged on an error. */
static int set_scale(vi_model *m, int j, const char *key, double s)
{
  if (!m->frozen) return apply_scale(m, j, s);
  vi_model *c = NULL;
  double *zeta = NULL;
  int st = vi_model_copy(m, &c);
  if (!st && m->damp_kind == 2) { /* the ratios outlive the modes */
    zeta = malloc(sizeof(double) * (size_t)m->n);
    if (zeta) memcpy(zeta, m->zeta, sizeof(double) * (size_t)m->n);
    else st = VI_ERR_NOMEM;
  }
  if (!st) {
    c->frozen = 0;
    st = apply_scale(c, j, s);
  }
  if (!st) st = vi_model_setup(c);
  if (!st && zeta) st = set_modal_damping(c, zeta);
  free(zeta);
  if (st) {
    vi_fail(m->errmsg, st, "%s = %.17g: %s", key, s,
            c && c->errmsg[0] ? c->errmsg : vi_strerror(st));
    vi_model_destroy(&c);
    return st;
  }
  vi_model old = *m;
  *m = *c;
  *c = old;
  vi_model_destroy(&c);
  return VI_OK;
}

static double get_scale(const vi_model *m, int j)
{
  return (m->shave >> j) & 1 ? m->sscale[j] : 1.0;
}

/* ---- checks ---------------------------------------------------------------- */

static int check_index(char *buf, const char *key, int idx, int count,
                       const char *what)
{
  if (idx >= 1 && idx <= count) return VI_OK;
  return vi_fail(buf, VI_ERR_DIM, "%s: index %d is outside 1..%d (%s)", key,
                 idx, count, what);
}

static int is_zero(int n, const double *v)
{
  for (int i = 0; i < n; i++)
    if (v[i] != 0.0) return 0;
  return 1;
}

static int check_modal(vi_model *m, const char *key)
{
  if (!vi_model_has_modes(m))
    return vi_fail(m->errmsg, VI_ERR_UNSUPPORTED, "%s: a band model has no "
                   "modes (use damping.alpha, damping.beta)", key);
  if (!m->frozen)
    return vi_fail(m->errmsg, VI_ERR_STATE, "%s: modal damping needs the "
                   "modes: set it after vi_model_setup", key);
  if (!m->proportional)
    return vi_fail(m->errmsg, VI_ERR_UNSUPPORTED, "%s: the damping is not "
                   "proportional, so it has no modal ratios", key);
  return VI_OK;
}

/* A model held by a handle (a simulation, orbit, census or fit made from
 * it keeps its flow, forcing and stops as they were; a change under it
 * was ignored or read freed memory) is immutable until they are gone. */
static int check_free(vi_model *m, const char *key)
{
  int users = __atomic_load_n(&m->users, __ATOMIC_ACQUIRE);
  if (users <= 0) return VI_OK;
  return vi_fail(m->errmsg, VI_ERR_STATE, "%s: the model is in use by %d "
                 "handle%s made from it (simulation, orbit, census or fit), "
                 "which keep%s data derived from it: destroy %s first, or "
                 "change a copy (vi_model_copy)", key, users,
                 users == 1 ? "" : "s", users == 1 ? "s" : "",
                 users == 1 ? "it" : "them");
}

/* Validate (key, value) for model m: VI_OK when the setter may run. */
static int check_set(vi_model *m, const pkey *p, const char *key, double v)
{
  int n = m->n, st;
  if (!isfinite(v))
    return vi_fail(m->errmsg, VI_ERR_NONFINITE, "%s = %g is not finite", key,
                   v);
  if (fabs(v) > VI_NUM_MAX)
    return vi_fail(m->errmsg, VI_ERR_LIMIT, "%s = %g: magnitude above 1e100, "
                   "outside the range where the energies stay finite", key, v);
  switch (p->id) {
  case P_OMEGA:
    if (v < 0.0 || (v == 0.0 && (!is_zero(n, m->a) || !is_zero(n, m->b))))
      return vi_fail(m->errmsg, VI_ERR_FREQUENCY, "%s = %.17g: the forcing "
                     "frequency must be %s", key, v,
                     v < 0.0 ? "non-negative" : "> 0 with harmonic forcing");
    return VI_OK;
  case P_A: case P_B: case P_F0:
    if ((st = check_index(m->errmsg, key, p->idx, n, "coordinates")))
      return st;
    if (p->id != P_F0 && v != 0.0 && !(m->omega_f > 0.0))
      return vi_fail(m->errmsg, VI_ERR_FREQUENCY, "%s = %.17g: harmonic "
                     "forcing needs forcing.omega > 0 (it is %g)", key, v,
                     m->omega_f);
    return VI_OK;
  case P_XS: case P_R:
    if ((st = check_index(m->errmsg, key, p->idx, m->ns, "stops")))
      return st;
    if (p->id == P_R && (v < 0.0 || v > 1.0))
      return vi_fail(m->errmsg, VI_ERR_RESTITUTION, "%s = %.17g: the "
                     "restitution must lie in [0, 1]", key, v);
    return VI_OK;
  case P_ALPHA: case P_BETA:
    if (v < 0.0)
      return vi_fail(m->errmsg, VI_ERR_NOT_PSD, "%s = %.17g: negative "
                     "Rayleigh damping makes C indefinite", key, v);
    return VI_OK;
  case P_ZETA: case P_ZETA_ALL:
    if ((st = check_modal(m, key))) return st;
    if (p->id == P_ZETA &&
        (st = check_index(m->errmsg, key, p->idx, n, "modes")))
      return st;
    if (v < 0.0)
      return vi_fail(m->errmsg, VI_ERR_NOT_PSD, "%s = %.17g: a negative "
                     "damping ratio makes C indefinite", key, v);
    return VI_OK;
  case P_MSCALE: case P_KSCALE: case P_CSCALE:
    return check_scale(m, p->id - P_MSCALE, key, v);
  default:
    return vi_fail(m->errmsg, VI_ERR_ARG, "%s is the initial state, not a "
                   "parameter of the model (vi_param_set_initial)", key);
  }
}

/* ---- the table's setters and getters -------------------------------------- */

static int set_forcing_entry(vi_model *m, int id, int i, double v)
{
  double *f = id == P_A ? m->a : id == P_B ? m->b : m->f0;
  double *minvf = id == P_A ? m->Minv_a : id == P_B ? m->Minv_b : m->Minv_f0;
  double *modal = id == P_A ? m->Fa : id == P_B ? m->Fb : m->F0;
  double was = f[i];
  f[i] = v;
  if (!m->frozen) return VI_OK;
  int st = refresh_vector(m, f, minvf, modal);
  if (st) f[i] = was; /* unchanged on an error */
  return st ? vi_fail(m->errmsg, st, "M^-1 of the forcing: %s",
                      vi_strerror(st)) : VI_OK;
}

int vi_model_set_param(vi_model *m, const char *key, double value)
{
  pkey p;
  if (!m) return VI_ERR_ARG;
  if (parse_key(key, &p)) return unknown(m->errmsg, key);
  int st = check_set(m, &p, key, value);
  if (st) return st;
  if ((st = check_free(m, key))) return st;
  switch (p.id) {
  case P_OMEGA: m->omega_f = value; break;
  case P_A: case P_B: case P_F0:
    st = set_forcing_entry(m, p.id, p.idx - 1, value);
    break;
  case P_XS:
    m->xsv[p.idx - 1] = value;
    break;
  case P_R:
    m->rv[p.idx - 1] = value;
    break;
  case P_ALPHA: case P_BETA: {
    double a = m->damp_kind == 1 ? m->ray_alpha : 0.0;
    double b = m->damp_kind == 1 ? m->ray_beta : 0.0;
    st = set_rayleigh(m, p.id == P_ALPHA ? value : a,
                      p.id == P_BETA ? value : b);
    break;
  }
  case P_MSCALE: case P_KSCALE: case P_CSCALE:
    st = set_scale(m, p.id - P_MSCALE, key, value);
    break;
  default: { /* P_ZETA, P_ZETA_ALL */
    double *z = malloc(sizeof(double) * (size_t)m->n);
    if (!z) return vi_fail(m->errmsg, VI_ERR_NOMEM, "out of memory");
    for (int j = 0; j < m->n; j++)
      z[j] = p.id == P_ZETA_ALL || j == p.idx - 1 ? value : m->zeta[j];
    st = set_modal_damping(m, z);
    free(z);
  }
  }
  if (!st) m->errmsg[0] = '\0';
  return st;
}

int vi_model_check_param(const vi_model *m, const char *key, double value)
{
  pkey p;
  if (!m) return VI_ERR_ARG;
  vi_model *mm = (vi_model *)m; /* only errmsg is written */
  if (parse_key(key, &p)) return unknown(mm->errmsg, key);
  int st = check_set(mm, &p, key, value);
  if (!st) st = check_free(mm, key);
  /* Omega, the forcing entries, x_s and r (the table's first keys, up to
   * P_R) and any key of a model not yet set up derive nothing that can
   * fail; damping and the scales redo a set-up, which only doing tells */
  if (st || !m->frozen || p.id <= P_R) return st;
  vi_model *c = NULL;
  if ((st = vi_model_copy(m, &c)))
    return vi_fail(mm->errmsg, st, "out of memory");
  if ((st = vi_model_set_param(c, key, value)))
    snprintf(mm->errmsg, VI_MSG_LEN, "%s", c->errmsg);
  vi_model_destroy(&c);
  return st;
}

int vi_model_param(const vi_model *m, const char *key, double *value)
{
  pkey p;
  char buf[VI_MSG_LEN];
  if (!m || !value) return VI_ERR_ARG;
  *value = NAN;
  vi_model *mm = (vi_model *)m; /* only errmsg is written */
  if (parse_key(key, &p)) return unknown(mm->errmsg, key);
  int n = m->n, st = VI_OK;
  switch (p.id) {
  case P_OMEGA: *value = m->omega_f; return VI_OK;
  case P_A: case P_B: case P_F0:
    if ((st = check_index(buf, key, p.idx, n, "coordinates"))) break;
    *value = (p.id == P_A ? m->a : p.id == P_B ? m->b : m->f0)[p.idx - 1];
    return VI_OK;
  case P_XS: case P_R:
    if ((st = check_index(buf, key, p.idx, m->ns, "stops"))) break;
    *value = (p.id == P_XS ? m->xsv : m->rv)[p.idx - 1];
    return VI_OK;
  case P_ALPHA: case P_BETA:
    *value = m->damp_kind != 1 ? NAN
             : p.id == P_ALPHA ? m->ray_alpha : m->ray_beta;
    return VI_OK;
  case P_ZETA: case P_ZETA_ALL:
    if ((st = check_modal(mm, key))) return st;
    if (p.id == P_ZETA) {
      if ((st = check_index(buf, key, p.idx, n, "modes"))) break;
      *value = m->zeta[p.idx - 1];
      return VI_OK;
    }
    for (int j = 1; j < n; j++)
      if (m->zeta[j] != m->zeta[0])
        return vi_fail(mm->errmsg, VI_ERR_UNSUPPORTED, "%s: the modes have "
                       "different ratios (read damping.zeta[j])", key);
    *value = m->zeta[0];
    return VI_OK;
  case P_MSCALE: case P_KSCALE: case P_CSCALE:
    *value = get_scale(m, p.id - P_MSCALE);
    return VI_OK;
  default:
    st = vi_fail(buf, VI_ERR_ARG, "%s is the initial state, not a parameter "
                 "of the model (vi_param_initial)", key);
  }
  snprintf(mm->errmsg, sizeof mm->errmsg, "%s", buf);
  return st;
}

/* ---- the initial state ------------------------------------------------------ */

static int initial_slot(const char *key, int n, pkey *p)
{
  if (parse_key(key, p) || keys[p->id].kind != VI_PARAM_INITIAL_STATE)
    return VI_ERR_ARG;
  if (p->id != P_T0 && (p->idx < 1 || p->idx > n)) return VI_ERR_DIM;
  return VI_OK;
}

int vi_param_set_initial(const char *key, double value, int n, double *t0,
                         double *x, double *v)
{
  pkey p;
  int st = initial_slot(key, n, &p);
  if (st) return st;
  if (!isfinite(value)) return VI_ERR_NONFINITE;
  double *dst = p.id == P_T0 ? t0 : p.id == P_X ? x : v;
  if (!dst) return VI_ERR_ARG;
  dst[p.id == P_T0 ? 0 : p.idx - 1] = value;
  return VI_OK;
}

int vi_param_initial(const char *key, int n, double t0, const double *x,
                     const double *v, double *value)
{
  pkey p;
  if (!value) return VI_ERR_ARG;
  *value = NAN;
  int st = initial_slot(key, n, &p);
  if (st) return st;
  if (p.id == P_T0) {
    *value = t0;
    return VI_OK;
  }
  const double *src = p.id == P_X ? x : v;
  if (!src) return VI_ERR_ARG;
  *value = src[p.idx - 1];
  return VI_OK;
}

/* ---- copies ------------------------------------------------------------------ */

/* A pointer into the old block, moved to the same place in the new one. */
static double *rebase(const double *p, const double *from, size_t len,
                      double *to)
{
  return p && p >= from && p < from + len ? to + (p - from) : NULL;
}

int vi_model_copy(const vi_model *m, vi_model **out)
{
  if (!out) return VI_ERR_ARG;
  *out = NULL;
  if (!m) return VI_ERR_ARG;
  vi_model *c = malloc(sizeof *c);
  if (!c) return VI_ERR_NOMEM;
  *c = *m;
  c->users = 0; /* nothing holds the copy yet */
  c->block = malloc(sizeof(double) * (m->nblock ? m->nblock : 1));
  c->Ws = NULL;
  c->MinvW = NULL;
  size_t nw = (size_t)m->ns_cap * (size_t)(m->n + 2);
  size_t nS = (size_t)m->n * m->ns;
  size_t nmw = (size_t)m->ops->stop_vectors * nS + (size_t)m->ns * m->ns;
  if (m->ns_cap) c->Ws = malloc(sizeof(double) * nw);
  if (m->MinvW) c->MinvW = malloc(sizeof(double) * nmw);
  size_t nb;
  m->ops->matrix(m, 0, &nb);
  nb *= 3;
  c->sbase = m->sbase ? malloc(sizeof(double) * nb) : NULL;
  if (!c->block || (m->ns_cap && !c->Ws) || (m->MinvW && !c->MinvW) ||
      (m->sbase && !c->sbase)) {
    free(c->block);
    free(c->Ws);
    free(c->MinvW);
    free(c->sbase);
    free(c);
    return VI_ERR_NOMEM;
  }
  if (m->sbase) memcpy(c->sbase, m->sbase, sizeof(double) * nb);
  memcpy(c->block, m->block, sizeof(double) * m->nblock);
  double *const fields_m[] = {
      m->M, m->C, m->K, m->MinvK, m->MinvC, m->Psi, m->PsiTM, m->D,
      m->a, m->b, m->f0, m->Minv_a, m->Minv_b, m->Minv_f0,
      m->omega, m->lambda, m->zeta, m->Fa, m->Fb, m->F0,
      m->MB, m->CB, m->KB, m->LB, m->KR, m->CR};
  double **fields_c[] = {
      &c->M, &c->C, &c->K, &c->MinvK, &c->MinvC, &c->Psi, &c->PsiTM, &c->D,
      &c->a, &c->b, &c->f0, &c->Minv_a, &c->Minv_b, &c->Minv_f0,
      &c->omega, &c->lambda, &c->zeta, &c->Fa, &c->Fb,
      &c->F0, &c->MB, &c->CB, &c->KB, &c->LB, &c->KR, &c->CR};
  for (size_t i = 0; i < sizeof fields_c / sizeof *fields_c; i++)
    *fields_c[i] = rebase(fields_m[i], m->block, m->nblock, c->block);
  if (m->ns_cap) {
    memcpy(c->Ws, m->Ws, sizeof(double) * nw);
    c->xsv = c->Ws + (m->xsv - m->Ws);
    c->rv = c->Ws + (m->rv - m->Ws);
  }
  if (m->MinvW) {
    memcpy(c->MinvW, m->MinvW, sizeof(double) * nmw);
    c->PsiW = m->PsiW ? c->MinvW + (m->PsiW - m->MinvW) : NULL;
    c->G = c->MinvW + (m->G - m->MinvW);
  }
  *out = c;
  return VI_OK;
}
