/* vi_diagram.c - brute-force bifurcation diagrams: the sweep itself (warm
 * start, stroboscopic sampling, impact map, P(n, m) classification) and
 * its JSON form.  The HDF5 form: vi_diagram_file.c flattens a diagram for
 * the writer in src/io/vi_diagram_h5.c. */
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif
#ifdef VI_HAVE_MPI
#include <mpi.h>
#endif

#include "vibroimpact.h"
#include "vibroimpact/vi_scene.h"
#include "vibroimpact/vi_scene_edit.h"
#include "vibroimpact/vi_scene_param.h"
#include "vi_app.h"
#include "vi_diagram.h"

static double now(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void msg(char *err, int len, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static void msg(char *err, int len, const char *fmt, ...)
{
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(err, (size_t)len, fmt, ap);
  va_end(ap);
}

static void diag_msg(const vi_diag *d, int st, char *err, int len)
{
  vi_diag dd = *d;
  if (!dd.code) {
    dd.code = st;
    snprintf(dd.message, sizeof dd.message, "%s", vi_strerror(st));
  }
  vi_diag_format(&dd, err, len);
}

/* ---- one piece: consecutive values with warm start ---------------------- */
/* Seeded chunks (spec.chunks > 1 with warm start): each line's first value
 * of every chunk is computed by one serial chain along the line (a coarse
 * sweep, warm-started value to value), which hands the state it ends in
 * to the chunk; the chunk goes on from there.  Every value is computed
 * once, each from a state that depends on the chunk count alone, so the
 * diagram does not depend on the threads or ranks. */
enum { SEED_PENDING = 0, SEED_STATE, SEED_COLD, SEED_NONE };
typedef struct seedbox {
  pthread_mutex_t mu;
  pthread_cond_t cv;
  int C, n;     /* chunks per line, coordinates */
  int *state;   /* [nlines x C] SEED_* */
  double *xv;   /* [nlines x C][2n]: x then v */
} seedbox;

typedef struct piece {
  const vi_diagram *sw;
  vi_diagram_line *ln;
  int pos0, pos1; /* positions in the line's sweep order */
  int chain;      /* 1: the line's seed chain (first value of each chunk) */
  int slot;       /* seedbox index of the chunk's seed (line x C + chunk) */
  seedbox *box;   /* NULL: not seeded, the piece starts cold */
  volatile sig_atomic_t *cancel;
  int code; /* 0, 1 run-time, 2 input, 3 cancelled */
  char err[1400];
} piece;

static int on_cancel(void *user)
{
  return *(volatile sig_atomic_t *)user != 0;
}

/* The scene's run settings and springs on each simulation of the study. */
static int scene_hook(vi_sim *sim, void *user)
{
  return vi_scene_configure_sim(user, sim, NULL);
}

/* Copy the study's last point into the diagram's point k. */
/* A point's orbit arrays for pt->norb orbits; 0, or 1 out of memory. */
static int alloc_orbits(vi_diagram_point *pt)
{
  size_t no = (size_t)pt->norb;
  pt->ovn = malloc(sizeof(double) * no);
  pt->ophase = malloc(sizeof(double) * no);
  pt->ostable = malloc(sizeof(int) * no);
  pt->oadm = malloc(sizeof(int) * no);
  return !pt->ovn || !pt->ophase || !pt->ostable || !pt->oadm;
}

static int keep_point(const vi_sweep *st, const vi_diagram *sw,
                      vi_diagram_line *ln, int k)
{
  vi_diagram_point *pt = &ln->pt[k];
  int ld, R;
  const double *t, *ph, *vn, *z = vi_sweep_strobe(st, &ld, &R);
  vi_sweep_period(st, &pt->n, &pt->m);
  vi_sweep_impacts(st, &pt->nimp, &t, &ph, &vn);
  pt->lyap = vi_sweep_lyapunov(st);
  pt->T = vi_sweep_forcing_period(st);
  if (z) memcpy(ln->strobe + (size_t)k * R * ld, z, sizeof(double) * R * ld);
  if (pt->nimp) {
    size_t b = sizeof(double) * (size_t)pt->nimp;
    pt->t = malloc(b);
    pt->phase = malloc(b);
    pt->vn = malloc(b);
    if (!pt->t || !pt->phase || !pt->vn) return 1;
    memcpy(pt->t, t, b);
    memcpy(pt->phase, ph, b);
    memcpy(pt->vn, vn, b);
  }
  if (sw->spec.orbits <= 0) return 0;
  const double *ov, *op;
  const int *os, *oa;
  vi_sweep_orbits(st, &pt->norb, &ov, &op, &os, &oa);
  if (pt->norb <= 0) return 0;
  size_t no = (size_t)pt->norb;
  if (alloc_orbits(pt)) return 1;
  memcpy(pt->ovn, ov, sizeof(double) * no);
  memcpy(pt->ophase, op, sizeof(double) * no);
  memcpy(pt->ostable, os, sizeof(int) * no);
  memcpy(pt->oadm, oa, sizeof(int) * no);
  return 0;
}

/* The initial state the scene gives its model (projected onto the modes
 * of a finite-element scene), read back once from a sim it configured:
 * every piece starts its study from it.  0, or a status. */
static int initial_state(vi_diagram *sw)
{
  vi_sim *s = NULL;
  sw->z0 = malloc(sizeof(double) * 2 * (size_t)sw->N);
  if (!sw->z0) return VI_ERR_NOMEM;
  int st = vi_sim_create(sw->model, &s);
  if (!st) st = vi_scene_configure_sim(sw->sc, s, NULL);
  if (!st) st = vi_sim_state(s, &sw->t0, sw->z0, sw->z0 + sw->N);
  vi_sim_destroy(&s);
  return st;
}

/* A study of the diagram's model with the scene's settings. */
static int make_study(const vi_diagram *sw, vi_sweep **out, char *err, int len)
{
  const vi_diagram_spec *sp = &sw->spec;
  if (vi_sweep_create(sw->model, out) || !*out) {
    msg(err, len, "out of memory");
    return 1;
  }
  int st = vi_sweep_set_initial(*out, sw->t0, sw->z0, sw->z0 + sw->N);
  if (!st) st = vi_sweep_set_periods(*out, sp->transient, sp->record);
  if (!st) st = vi_sweep_set_classify(*out, sp->tol, sp->nmax);
  if (!st) st = vi_sweep_set_orbits(*out, sp->orbits);
  if (!st) st = vi_sweep_set_warm(*out, sw->warm);
  if (!st) st = vi_sweep_set_lyapunov(*out, sp->lyapunov);
  if (!st) st = vi_sweep_set_run(*out, vi_scene_method(sw->sc), vi_scene_rtol(sw->sc),
                                 vi_scene_atol(sw->sc));
  if (!st) st = vi_sweep_set_sim_hook(*out, scene_hook, (void *)sw->sc, NULL);
  if (st) msg(err, len, "%s", vi_sweep_errmsg(*out));
  return st ? 2 : 0;
}

/* Value at position pos of the piece's line: 0 to go on, else stop (the
 * piece's code and err say why). */
static int run_value(piece *p, vi_sweep *study, int pos)
{
  const vi_diagram *sw = p->sw;
  vi_diagram_line *ln = p->ln;
  int K = sw->spec.steps, k = ln->dir > 0 ? pos : K - 1 - pos;
  double val = sw->param[k];
  if (vi_sweep_set_param(study, sw->pkey, val)) {
    p->code = 2;
    msg(p->err, sizeof p->err, "%s: %s", sw->name, vi_sweep_errmsg(study));
    return 1;
  }
  int st = vi_sweep_iterate(study);
  if (st == VI_CANCELLED || st == VI_STOPPED || st == VI_ERR_NOMEM) {
    p->code = st == VI_ERR_NOMEM ? 1 : 3; /* the value in progress is dropped */
    if (st == VI_ERR_NOMEM) msg(p->err, sizeof p->err, "out of memory");
    else msg(p->err, sizeof p->err, "interrupted at %s = %.17g", sw->spec.key, val);
    return 1;
  }
  if (keep_point(study, sw, ln, k)) {
    p->code = 1;
    msg(p->err, sizeof p->err, "out of memory");
    return 1;
  }
  ln->pt[k].done = 1;
  if (st) {
    /* one value's failure does not sink the diagram: it is marked, and
     * the next value starts cold (from the scene's initial state) */
    char e[1400];
    if (sw->spec.key2) /* a map's cell: both of its values */
      msg(e, sizeof e, "%s = %.17g, %s = %.17g: %s", sw->spec.key, val,
          sw->spec.key2, sw->param2[ln->row], vi_sweep_errmsg(study));
    else
      msg(e, sizeof e, "%s = %.17g: %s", sw->spec.key, val, vi_sweep_errmsg(study));
    ln->pt[k].failed = 1;
    ln->pt[k].error = strdup(e);
  }
  return 0;
}

/* Publish chunk c's seed: the chain's warm state, a cold start after a
 * failed value, or none (the chain stopped). */
static void put_seed(seedbox *b, int slot, const vi_sweep *study, int stopped)
{
  double *x = b->xv + (size_t)slot * 2 * b->n;
  int s = stopped ? SEED_NONE
                  : vi_sweep_warm_state(study, x, x + b->n) ? SEED_COLD : SEED_STATE;
  pthread_mutex_lock(&b->mu);
  b->state[slot] = s;
  pthread_cond_broadcast(&b->cv);
  pthread_mutex_unlock(&b->mu);
}

/* The chunk's seed, waited for; 1 when the chain stopped before it. */
static int take_seed(piece *p, vi_sweep *study)
{
  seedbox *b = p->box;
  pthread_mutex_lock(&b->mu);
  while (b->state[p->slot] == SEED_PENDING) pthread_cond_wait(&b->cv, &b->mu);
  int s = b->state[p->slot];
  pthread_mutex_unlock(&b->mu);
  if (s == SEED_NONE) return 1; /* the chain's code says why */
  const double *x = b->xv + (size_t)p->slot * 2 * b->n;
  if (s == SEED_STATE && vi_sweep_set_warm_state(study, x, x + b->n)) {
    p->code = 1;
    msg(p->err, sizeof p->err, "%s: %s", p->sw->name, vi_sweep_errmsg(study));
    return 1;
  }
  return 0;
}

/* A piece: a chunk of values, or a line's seed chain (the first value of
 * each of its chunks, p->slot the first chunk's seed). */
static void run_piece(piece *p)
{
  const vi_diagram *sw = p->sw;
  int K = sw->spec.steps, C = sw->spec.chunks, c = 0;
  vi_sweep *study = NULL;
  if ((p->code = make_study(sw, &study, p->err, sizeof p->err)) || !study) goto done;
  if (p->cancel) vi_sweep_set_cancel(study, on_cancel, (void *)p->cancel, NULL);
  if (sw->spec.key2 && vi_sweep_set_param(study, sw->pkey2, sw->param2[p->ln->row])) {
    p->code = 2;
    msg(p->err, sizeof p->err, "%s: %s", sw->name, vi_sweep_errmsg(study));
    goto done;
  }
  if (p->chain) {
    for (; c < C; c++) {
      if (run_value(p, study, (int)((int64_t)K * c / C))) break;
      put_seed(p->box, p->slot + c, study, 0);
    }
    goto done;
  }
  int pos = p->pos0;
  if (p->box) {
    if (take_seed(p, study)) goto done;
    pos++; /* the chain computed the chunk's first value */
  }
  for (; pos < p->pos1; pos++)
    if (run_value(p, study, pos)) break;
done:
  /* chunks waiting on a chain that stopped are released */
  for (; p->chain && c < C; c++) put_seed(p->box, p->slot + c, study, 1);
  vi_sweep_destroy(&study);
}

/* ---- the whole sweep ------------------------------------------------------ */
void vi_diagram_free(vi_diagram **swp)
{
  if (!swp || !*swp) return;
  vi_diagram *sw = *swp;
  for (int l = 0; l < sw->nlines && sw->lines; l++) {
    vi_diagram_line *ln = &sw->lines[l];
    for (int k = 0; k < sw->spec.steps && ln->pt; k++) {
      free(ln->pt[k].t);
      free(ln->pt[k].phase);
      free(ln->pt[k].vn);
      free(ln->pt[k].error);
      free(ln->pt[k].ovn);
      free(ln->pt[k].ophase);
      free(ln->pt[k].ostable);
      free(ln->pt[k].oadm);
    }
    free(ln->pt);
    free(ln->strobe);
  }
  free(sw->lines);
  free(sw->param);
  free(sw->param2);
  free(sw->z0);
  free(sw->text);
  free(sw->name);
  free(sw->attractor);
  vi_model_destroy(&sw->model);
  vi_scene_destroy(&sw->sc);
  free(sw);
  *swp = NULL;
}

/* The key at a value: the scene text (its ranges, with file:line) and the
 * model's parameter (vi_model_check_param: no copy of the model unless the
 * key redoes its set-up); catches an unknown key or a bad value before any
 * simulation.  *pkey [64] receives the parameter key. */
static int trial(const vi_diagram *sw, const char *key, double val, char *pkey,
                 char *err, int len)
{
  vi_scene_edit *ed = NULL;
  vi_scene *sc = NULL;
  vi_diag d;
  memset(&d, 0, sizeof d);
  vi_diag dk; /* a key no study changes (model.chain.n) is named as such,
                 not by what its value breaks elsewhere in the scene */
  int kst = vi_scene_param_key(sw->sc, key, pkey, 64, &dk);
  int st = vi_scene_edit_create_limited(sw->text, -1, sw->name,
                                        sw->spec.max_depth, &ed, &d);
  if (!st) st = vi_scene_edit_set_number(ed, key, val, &d);
  if (!st) st = vi_scene_edit_parse(ed, &sc, &d);
  if (kst && (!st || strcmp(d.key, key) != 0)) { /* the scene blames another key */
    st = kst;
    d = dk;
  }
  int omega = !st && !strcmp(pkey, "forcing.omega");
  if (st && !kst && strcmp(d.key, key) != 0 && vi_param_kind(key) != VI_PARAM_UNKNOWN)
    /* a library name the scene does not spell (damping.scale): the scene
     * blamed its own prefix ("damping: unknown key") */
    msg(err, len, "%s: %s is a parameter of the model (vi_param.h), not a key of "
        "the scene, and a sweep sets the scene's keys: a uniform chain's "
        "model.chain.m, .k, .c scale its mass, stiffness and damping; "
        "model.rayleigh.alpha/beta and model.cantilever.zeta its damping",
        sw->name, key);
  else if (st) diag_msg(&d, st, err, len);
  else if (vi_param_kind(pkey) == VI_PARAM_MODEL &&
           (st = vi_model_check_param(sw->model, pkey, val)))
    msg(err, len, "%s: %s", sw->name, vi_model_errmsg(sw->model));
  else if (!((omega ? val : vi_model_omega_forcing(sw->model)) > 0)) {
    st = VI_ERR_FREQUENCY;
    msg(err, len, "%s: %s = %.17g leaves no harmonic forcing (forcing.omega "
        "must be > 0 for a sweep)", sw->name, key, val);
  }
  vi_scene_destroy(&sc);
  vi_scene_edit_destroy(&ed);
  return st;
}

#ifdef VI_HAVE_MPI
/* ---- MPI: results of every piece to rank 0 -------------------------------- */
typedef struct pbuf { char *b; size_t len, cap; int oom; } pbuf;

static void put_bytes(pbuf *p, const void *x, size_t k)
{
  if (p->oom) return;
  if (p->len + k > p->cap) {
    size_t cap = 2 * (p->len + k) + 1024;
    char *nb = realloc(p->b, cap);
    if (!nb) { p->oom = 1; return; }
    p->b = nb;
    p->cap = cap;
  }
  memcpy(p->b + p->len, x, k);
  p->len += k;
}

static void pack_piece(const vi_diagram *sw, const piece *pc, pbuf *p)
{
  int K = sw->spec.steps, R = sw->spec.record, n2 = 2 * sw->N;
  /* a seeded chunk's first value: every rank's chain computed it */
  for (int pos = pc->pos0 + (pc->box != NULL); pos < pc->pos1; pos++) {
    int k = pc->ln->dir > 0 ? pos : K - 1 - pos;
    const vi_diagram_point *pt = &pc->ln->pt[k];
    int hdr[4] = {pt->n, pt->m, pt->failed, pt->done};
    int64_t ni = pt->nimp, el = pt->error ? (int64_t)strlen(pt->error) : -1;
    put_bytes(p, hdr, sizeof hdr);
    put_bytes(p, &pt->T, sizeof pt->T);
    put_bytes(p, &pt->lyap, sizeof pt->lyap);
    put_bytes(p, &ni, sizeof ni);
    if (ni) {
      put_bytes(p, pt->t, sizeof(double) * ni);
      put_bytes(p, pt->phase, sizeof(double) * ni);
      put_bytes(p, pt->vn, sizeof(double) * ni);
    }
    put_bytes(p, &el, sizeof el);
    if (el > 0) put_bytes(p, pt->error, (size_t)el);
    put_bytes(p, &pt->norb, sizeof pt->norb);
    if (pt->norb > 0) {
      put_bytes(p, pt->ovn, sizeof(double) * pt->norb);
      put_bytes(p, pt->ophase, sizeof(double) * pt->norb);
      put_bytes(p, pt->ostable, sizeof(int) * pt->norb);
      put_bytes(p, pt->oadm, sizeof(int) * pt->norb);
    }
    put_bytes(p, pc->ln->strobe + (size_t)k * R * n2, sizeof(double) * R * n2);
  }
}

static int unpack_piece(const vi_diagram *sw, const piece *pc, const char *b,
                        size_t len, size_t *off)
{
  int K = sw->spec.steps, R = sw->spec.record, n2 = 2 * sw->N;
#define TAKE(dst, k) do { if (*off + (k) > len) return 1; memcpy((dst), b + *off, (k)); *off += (k); } while (0)
  for (int pos = pc->pos0 + (pc->box != NULL); pos < pc->pos1; pos++) {
    int k = pc->ln->dir > 0 ? pos : K - 1 - pos, hdr[4];
    vi_diagram_point *pt = &pc->ln->pt[k];
    int64_t ni, el;
    TAKE(hdr, sizeof hdr);
    pt->n = hdr[0];
    pt->m = hdr[1];
    pt->failed = hdr[2];
    pt->done = hdr[3];
    TAKE(&pt->T, sizeof pt->T);
    TAKE(&pt->lyap, sizeof pt->lyap);
    TAKE(&ni, sizeof ni);
    pt->nimp = ni;
    if (ni) {
      pt->t = malloc(sizeof(double) * ni);
      pt->phase = malloc(sizeof(double) * ni);
      pt->vn = malloc(sizeof(double) * ni);
      if (!pt->t || !pt->phase || !pt->vn) return 1;
      TAKE(pt->t, sizeof(double) * ni);
      TAKE(pt->phase, sizeof(double) * ni);
      TAKE(pt->vn, sizeof(double) * ni);
    }
    TAKE(&el, sizeof el);
    if (el >= 0) {
      pt->error = calloc((size_t)el + 1, 1);
      if (!pt->error) return 1;
      if (el > 0) TAKE(pt->error, (size_t)el);
    }
    TAKE(&pt->norb, sizeof pt->norb);
    if (pt->norb > 0) {
      size_t no = (size_t)pt->norb;
      if (alloc_orbits(pt)) return 1;
      TAKE(pt->ovn, sizeof(double) * no);
      TAKE(pt->ophase, sizeof(double) * no);
      TAKE(pt->ostable, sizeof(int) * no);
      TAKE(pt->oadm, sizeof(int) * no);
    }
    TAKE(pc->ln->strobe + (size_t)k * R * n2, sizeof(double) * R * n2);
  }
#undef TAKE
  return 0;
}

/* Every rank's code is agreed on first (an error anywhere fails the sweep
 * everywhere); then ranks 1.. send their pieces' results to rank 0. */
static int vi_diagram_gather(vi_diagram *sw, piece *ps, int ntask, int rank,
                             int size, int code, char *err, int errlen)
{
  /* a cancelled rank (code 3) still sends the points it did */
  int all = 0, mine[2] = {code == 3 ? 0 : code, code == 3}, both[2];
  MPI_Allreduce(mine, both, 2, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  all = both[0];
  if (all) {
    if (!code) msg(err, errlen, "another MPI rank failed (its message is on its stderr)");
    else if (rank) fprintf(stderr, "vibroimpact: sweep (rank %d): %s\n", rank, err);
    return all;
  }
  if (rank) {
    pbuf p = {NULL, 0, 0, 0};
    for (int i = rank; i < ntask; i += size) pack_piece(sw, &ps[i], &p);
    long long len = p.oom ? -1 : (long long)p.len;
    MPI_Send(&len, 1, MPI_LONG_LONG, 0, 1, MPI_COMM_WORLD);
    if (len > 0) MPI_Send(p.b, (int)len, MPI_BYTE, 0, 2, MPI_COMM_WORLD);
    free(p.b);
    return len < 0 ? 1 : both[1] ? 3 : 0;
  }
  int bad = 0;
  for (int r = 1; r < size; r++) {
    long long len;
    MPI_Recv(&len, 1, MPI_LONG_LONG, r, 1, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (len <= 0) {
      bad |= len < 0;
      continue;
    }
    char *b = malloc((size_t)len);
    if (!b) {
      bad = 1;
      MPI_Recv(NULL, 0, MPI_BYTE, r, 2, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      continue;
    }
    MPI_Recv(b, (int)len, MPI_BYTE, r, 2, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    size_t off = 0;
    for (int i = r; i < ntask && !bad; i += size)
      bad |= unpack_piece(sw, &ps[i], b, (size_t)len, &off);
    free(b);
  }
  if (bad) msg(err, errlen, "gathering the results of the MPI ranks failed");
  return bad ? 1 : both[1] ? 3 : 0;
}
#endif

static int threads_of(const vi_diagram_spec *sp)
{
  int nth = sp->threads > 0 ? sp->threads : 1;
#ifdef _OPENMP
  if (sp->threads <= 0) nth = omp_get_max_threads();
#endif
  return nth;
}

int vi_diagram_default_chunks(const vi_diagram_spec *sp)
{
  int K = sp->steps, lines = (sp->key2 ? sp->steps2 : 1) * (sp->dirs == 3 ? 2 : 1);
  if (K < 2 || sp->dirs == 3 || lines >= 16) return 1;
  int L = (int)ceil(sqrt((double)K));
  if (L > 16) L = 16;
  return (K + L - 1) / L;
}

void vi_diagram_split(const vi_diagram *sw, char *s, int len)
{
  const vi_diagram_spec *sp = &sw->spec;
  int C = sp->chunks;
  if (sp->cold) snprintf(s, (size_t)len, "every value from the initial state, %d "
                         "piece%s a line", C, C > 1 ? "s" : "");
  else if (C > 1) snprintf(s, (size_t)len, "%d chunks a line of about %d values, "
                           "seeded by a chain through their first values", C,
                           (sp->steps + C - 1) / C);
  else snprintf(s, (size_t)len, "each line in order, warm start exact");
}

double vi_diagram_memory_estimate(const vi_diagram_spec *sp, int N,
                                  double scene_bytes, int writes)
{
  double L = (double)(sp->key2 ? sp->steps2 : 1) * (sp->dirs == 3 ? 2 : 1),
         K = sp->steps, R = sp->record, n2 = 2.0 * N,
         pieces = L * (sp->chunks < sp->steps ? sp->chunks : sp->steps),
         run = fmin(threads_of(sp), pieces);
  double strobe = 8 * L * K * R * n2, /* the stroboscopic states */
         impacts = 24 * L * K * R,    /* one impact a recorded period */
         points = L * K * (double)sizeof(vi_diagram_point);
  /* the base model, then per running thread its copy, a simulation and
   * the study's own record; the file is built in memory (a copy of the
   * arrays and HDF5's image); basins compare copies of the strobes */
  return scene_bytes + run * (scene_bytes + 8 * R * (n2 + 3)) + strobe +
         impacts + points + (writes ? 2 * (strobe + impacts) : 0) +
         (sp->cold ? strobe : 0);
}

/* Refuse a diagram larger than the limit before anything is allocated:
 * 0, or 2 with the flags and the figures in err. */
static int check_memory(const vi_diagram *sw, char *err, int errlen)
{
  const vi_diagram_spec *sp = &sw->spec;
  double lim = sw->max_memory > 0 ? sw->max_memory : vi_scene_memory_available();
  if (!(lim > 0)) return 0; /* not known: nothing to compare */
  double scene = vi_scene_memory_estimate(sw->sc),
         need = vi_diagram_memory_estimate(sp, sw->N, scene, sw->writes);
  if (need <= lim) return 0;
  char rows[64] = "";
  if (sp->key2) snprintf(rows, sizeof rows, " x --steps2 %d", sp->steps2);
  msg(err, errlen, "%s: --steps %d%s x --record %d%s (%d coordinates%s%s) would "
      "need about %.3g MB (%.3g MB of stroboscopic states), more than the %.3g "
      "MB %s (--max-memory raises the limit)", sw->name, sp->steps, rows,
      sp->record, sp->dirs == 3 ? " x --both" : "", sw->N, sw->writes ? ", -o" : "",
      sp->cold ? ", basins" : "", need / 1048576.0,
      8.0 * sp->steps * sp->steps2 * (sp->dirs == 3 ? 2 : 1) * sp->record * 2 *
          sw->N / 1048576.0,
      lim / 1048576.0, sw->max_memory > 0 ? "allowed" : "available to this process");
  return 2;
}

/* The base scene (text with the --set assignments), its model built
 * once, the values, and the keys tried at both ends.  0, 1 (memory), 2
 * (input) with err. */
static int prepare(vi_diagram *sw, const char *text, const char *name,
                   const char *const *sets, int nsets, char *err, int errlen)
{
  const vi_diagram_spec *sp = &sw->spec;
  int K = sp->steps, rows = sp->steps2;
  vi_scene_edit *ed = NULL;
  vi_diag d;
  memset(&d, 0, sizeof d);
  int st = vi_scene_edit_create_limited(text, -1, name, sp->max_depth, &ed, &d);
  for (int i = 0; i < nsets && !st; i++) st = vi_scene_edit_assign(ed, sets[i], &d);
  if (!st) st = vi_scene_edit_parse_within(ed, sw->max_memory, &sw->sc, &d);
  if (!st) {
    sw->text = strdup(vi_scene_edit_text(ed));
    sw->name = strdup(name);
  }
  vi_scene_edit_destroy(&ed);
  if (st) {
    diag_msg(&d, st, err, errlen);
    return st == VI_ERR_NOMEM ? 1 : 2;
  }
  sw->N = vi_scene_n(sw->sc);
  sw->t0 = vi_scene_t0(sw->sc);
  sw->warm = !sp->cold;
  sw->param = malloc(sizeof(double) * K);
  sw->param2 = malloc(sizeof(double) * rows);
  if (!sw->text || !sw->name || !sw->param || !sw->param2) {
    msg(err, errlen, "out of memory");
    return 1;
  }
  for (int k = 0; k < K; k++)
    sw->param[k] = K > 1 ? sp->from + (sp->to - sp->from) * k / (K - 1) : sp->from;
  for (int r = 0; r < rows; r++)
    sw->param2[r] = rows > 1 ? sp->from2 + (sp->to2 - sp->from2) * r / (rows - 1)
                             : sp->from2;
  if (sp->orbits > 0 && vi_app_text_nonlinear(sw->text)) {
    msg(err, errlen, "%s: --orbits: the scene has nonlinear springs, and the "
        "P(1,1) orbits are found with the linear closed-form flow", sw->name);
    return 2;
  }
  /* the memory the whole study needs, before any of it is allocated */
  if (check_memory(sw, err, errlen)) return 2;
  /* the model, once: every value is a parameter change on a copy */
  if ((st = vi_scene_create_model(sw->sc, &sw->model, &d))) {
    diag_msg(&d, st, err, errlen);
    return st == VI_ERR_NOMEM ? 1 : 2;
  }
  if ((st = initial_state(sw))) {
    msg(err, errlen, "%s: the scene's initial state: %s", sw->name, vi_strerror(st));
    return st == VI_ERR_NOMEM ? 1 : 2;
  }
  /* bad keys and values show up here, before any simulation */
  if (trial(sw, sp->key, sp->from, sw->pkey, err, errlen) ||
      trial(sw, sp->key, sp->to, sw->pkey, err, errlen) ||
      (sp->key2 && (trial(sw, sp->key2, sp->from2, sw->pkey2, err, errlen) ||
                    trial(sw, sp->key2, sp->to2, sw->pkey2, err, errlen))))
    return 2;
  return 0;
}

/* The lines (rows x directions), their points and NaN-filled strobes. */
static int make_lines(vi_diagram *sw)
{
  const vi_diagram_spec *sp = &sw->spec;
  int K = sp->steps, ndir = sp->dirs == 3 ? 2 : 1;
  size_t nz = (size_t)K * sp->record * 2 * sw->N;
  sw->nlines = sp->steps2 * ndir;
  sw->lines = calloc((size_t)sw->nlines, sizeof *sw->lines);
  if (!sw->lines) return 1;
  for (int l = 0; l < sw->nlines; l++) {
    vi_diagram_line *ln = &sw->lines[l];
    ln->row = l / ndir;
    ln->dir = sp->dirs == 2 || (sp->dirs == 3 && l % ndir) ? -1 : 1;
    ln->pt = calloc((size_t)K, sizeof *ln->pt);
    ln->strobe = malloc(sizeof(double) * nz);
    if (!ln->pt || !ln->strobe) return 1;
    /* a value that fails leaves NaN, not garbage, in the file */
    for (size_t i = 0; i < nz; i++) ln->strobe[i] = NAN;
  }
  return 0;
}

/* The seeds' mailbox: nlines x C slots of 2N doubles. */
static int box_init(seedbox *b, const vi_diagram *sw)
{
  b->C = sw->spec.chunks;
  b->n = sw->N;
  size_t ns = (size_t)sw->nlines * b->C;
  b->state = calloc(ns, sizeof *b->state);
  b->xv = malloc(sizeof(double) * ns * 2 * b->n);
  pthread_mutex_init(&b->mu, NULL);
  pthread_cond_init(&b->cv, NULL);
  return !b->state || !b->xv;
}

static void box_free(seedbox *b)
{
  free(b->state);
  free(b->xv);
  pthread_mutex_destroy(&b->mu);
  pthread_cond_destroy(&b->cv);
}

/* The pieces: with seeds, each line's chain first (they never wait, so a
 * thread that waits for a seed waits for a chain already running), then
 * the chunks; *nchain receives the number of chains.  NULL out of memory. */
static piece *make_pieces(vi_diagram *sw, seedbox *box, volatile sig_atomic_t *cancel,
                          int ntask, int *nchain)
{
  int K = sw->spec.steps, C = sw->spec.chunks, nc = box ? sw->nlines : 0;
  piece *ps = calloc((size_t)nc + (size_t)ntask, sizeof *ps);
  if (!ps) return NULL;
  for (int i = 0; i < nc + ntask; i++) {
    piece *p = &ps[i];
    int chunk = i < nc ? 0 : (i - nc) % C, line = i < nc ? i : (i - nc) / C;
    p->sw = sw;
    p->ln = &sw->lines[line];
    p->chain = i < nc;
    p->box = box;
    p->slot = line * C + chunk;
    p->pos0 = (int)((int64_t)K * chunk / C);
    p->pos1 = (int)((int64_t)K * (chunk + 1) / C);
    p->cancel = cancel;
  }
  *nchain = nc;
  return ps;
}

#ifdef _OPENMP
/* The threads for nq pieces: the spec's (<= 0: OpenMP's default), no more
 * than the pieces. */
static int team(int threads, int nq)
{
  int nth = threads > 0 ? threads : omp_get_max_threads();
  return nth > nq ? (nq > 0 ? nq : 1) : nth;
}
#endif

/* Deal the pieces: MPI ranks take the chunks round-robin (rank r: chunks
 * r, r + size, ...), each rank's on its OpenMP threads, and every rank
 * runs the seed chains itself (no messages, the same seeds); each piece
 * is computed the same way wherever it runs.  The exit code, err. */
static int deal(vi_diagram *sw, volatile sig_atomic_t *cancel, char *err,
                int errlen)
{
  int C = sw->spec.chunks, ntask = sw->nlines * C, nchain = 0;
  seedbox box = {0}, *bp = sw->spec.chunks > 1 && sw->warm ? &box : NULL;
  if (bp && box_init(bp, sw)) {
    box_free(bp);
    msg(err, errlen, "out of memory");
    return 1;
  }
  piece *ps = make_pieces(sw, bp, cancel, ntask, &nchain);
  if (!ps) {
    if (bp) box_free(bp);
    msg(err, errlen, "out of memory");
    return 1;
  }
  int rank = 0, size = 1;
#ifdef VI_HAVE_MPI
  int mpi_on = 0;
  MPI_Initialized(&mpi_on);
  if (mpi_on) {
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
  }
#endif
  piece *chunks = ps + nchain;
  int nmine = ntask > rank ? (ntask - rank + size - 1) / size : 0;
  int nq = nchain + nmine, next = 0;
#ifdef _OPENMP
#pragma omp parallel num_threads(team(sw->spec.threads, nq))
#endif
  /* taken in order, chains first (an explicit counter: OpenMP's dynamic
   * schedule does not promise the order) */
  for (;;) {
    int q = __atomic_fetch_add(&next, 1, __ATOMIC_RELAXED);
    if (q >= nq) break;
    run_piece(q < nchain ? &ps[q] : &chunks[rank + (q - nchain) * size]);
  }
  int code = 0; /* a failure before a cancellation */
  for (int i = 0; i < nchain + ntask; i++)
    if (ps[i].code && (!code || code == 3)) {
      code = ps[i].code;
      msg(err, errlen, "%s", ps[i].err);
    }
#ifdef VI_HAVE_MPI
  if (size > 1) code = vi_diagram_gather(sw, chunks, ntask, rank, size, code, err, errlen);
  sw->rank = rank;
#endif
  free(ps);
  if (bp) box_free(bp);
  return code;
}

int vi_diagram_run(const char *text, const char *name, const char *const *sets,
                   int nsets, const vi_diagram_spec *spec,
                   volatile sig_atomic_t *cancel, vi_diagram **out, char *err,
                   int errlen)
{
  return vi_diagram_run_limited(text, name, sets, nsets, spec, 0, 0, cancel, out,
                                err, errlen);
}

int vi_diagram_run_limited(const char *text, const char *name,
                           const char *const *sets, int nsets,
                           const vi_diagram_spec *spec, double max_memory,
                           int writes, volatile sig_atomic_t *cancel,
                           vi_diagram **out, char *err, int errlen)
{
  double w0 = now();
  *out = NULL;
  err[0] = '\0';
  const vi_diagram_spec *sp = spec;
  if (!sp->key || sp->steps < 1 || sp->record < 2 || sp->transient < 0 ||
      sp->chunks < 1 || sp->dirs < 1 || sp->dirs > 3 || !(sp->tol > 0) ||
      sp->nmax < 1 || (sp->key2 && sp->steps2 < 1)) {
    msg(err, errlen, "sweep: need --param, --steps >= 1, --record >= 2, "
        "--transient >= 0, --chunks >= 1, --tol > 0");
    return 2;
  }
  vi_diagram *sw = calloc(1, sizeof *sw);
  if (!sw) {
    msg(err, errlen, "out of memory");
    return 1;
  }
  sw->spec = *sp;
  sw->max_memory = max_memory;
  sw->writes = writes;
  if (!sw->spec.key2) sw->spec.steps2 = 1;
  if (sw->spec.chunks > sw->spec.steps) sw->spec.chunks = sw->spec.steps;
  int code = prepare(sw, text, name, sets, nsets, err, errlen);
  if (!code && make_lines(sw)) {
    msg(err, errlen, "out of memory");
    code = 1;
  }
  if (!code) code = deal(sw, cancel, err, errlen);
  if (code && code != 3) {
    vi_diagram_free(&sw);
    return code;
  }
  /* cancelled: the diagram of the points done, marked incomplete */
  for (int l = 0; l < sw->nlines; l++)
    for (int k = 0; k < sw->spec.steps; k++) sw->points_done += sw->lines[l].pt[k].done;
  sw->incomplete = code == 3;
  sw->wall = now() - w0;
  *out = sw;
  return code;
}

/* ---- JSON ------------------------------------------------------------------ */
static void json_str(FILE *f, const char *s)
{
  fputc('"', f);
  for (; *s; s++) {
    if (*s == '"' || *s == '\\') fprintf(f, "\\%c", *s);
    else if ((unsigned char)*s < 0x20) fprintf(f, "\\u%04x", *s);
    else fputc(*s, f);
  }
  fputc('"', f);
}

static void json_nums(FILE *f, const double *x, int64_t n)
{
  fputc('[', f);
  for (int64_t i = 0; i < n; i++) fprintf(f, "%s%.17g", i ? ", " : "", x[i]);
  fputc(']', f);
}

/* One failed value of the "failed" list: its parameters (param2 NaN: a
 * 1-D sweep) and message; *first cleared. */
static void json_failure(FILE *f, int *first, double param, double param2,
                         const vi_diagram_point *pt)
{
  fprintf(f, "%s{\"param\": %.17g, ", *first ? "" : ", ", param);
  if (!isnan(param2)) fprintf(f, "\"param2\": %.17g, ", param2);
  fprintf(f, "\"error\": ");
  json_str(f, pt->error ? pt->error : "");
  fputc('}', f);
  *first = 0;
}

/* One line: param in sweep order, and per value n, m, vn, phase. */
static void json_line(const vi_diagram *sw, const vi_diagram_line *ln, FILE *f)
{
  int K = sw->spec.steps;
  fprintf(f, "\"direction\": \"%s\", \"param\": [", ln->dir > 0 ? "up" : "down");
  for (int p = 0; p < K; p++)
    fprintf(f, "%s%.17g", p ? ", " : "", sw->param[ln->dir > 0 ? p : K - 1 - p]);
  static const char *what[] = {"n", "m", "vn", "impact_time_mod_T"};
  for (int w = 0; w < 4; w++) {
    fprintf(f, "], \"%s\": [", what[w]);
    for (int p = 0; p < K; p++) {
      const vi_diagram_point *pt = &ln->pt[ln->dir > 0 ? p : K - 1 - p];
      if (p) fprintf(f, ", ");
      if (w < 2) {
        if (pt->n) fprintf(f, "%d", w ? pt->m : pt->n);
        else fprintf(f, "null");
      } else {
        /* one period of a periodic motion, else all recorded impacts */
        int64_t a = pt->n ? pt->nimp - pt->m : 0;
        json_nums(f, (w == 2 ? pt->vn : pt->phase) + a, pt->nimp - a);
      }
    }
  }
  if (sw->spec.orbits > 0) {
    fprintf(f, "], \"p11_orbits\": [");
    for (int p = 0; p < K; p++) {
      const vi_diagram_point *pt = &ln->pt[ln->dir > 0 ? p : K - 1 - p];
      fprintf(f, "%s[", p ? ", " : "");
      for (int i = 0; i < pt->norb; i++)
        fprintf(f, "%s{\"vN\": %.17g, \"impact_time_mod_T\": %.17g, \"stable\": %s, "
                "\"admissible\": %s}", i ? ", " : "", pt->ovn[i], pt->ophase[i],
                pt->ostable[i] ? "true" : "false", pt->oadm[i] ? "true" : "false");
      fprintf(f, "]");
    }
  }
  if (sw->spec.lyapunov) { /* null where refused */
    fprintf(f, "], \"lyapunov\": [");
    for (int p = 0; p < K; p++) {
      double l = ln->pt[ln->dir > 0 ? p : K - 1 - p].lyap;
      if (isnan(l)) fprintf(f, "%snull", p ? ", " : "");
      else fprintf(f, "%s%.17g", p ? ", " : "", l);
    }
  }
  fprintf(f, "], \"failed\": [");
  int first = 1;
  for (int p = 0; p < K; p++) {
    int k = ln->dir > 0 ? p : K - 1 - p;
    if (ln->pt[k].failed) json_failure(f, &first, sw->param[k], NAN, &ln->pt[k]);
  }
  fprintf(f, "]");
}

void vi_diagram_print_json(const vi_diagram *sw, FILE *f)
{
  const vi_diagram_spec *sp = &sw->spec;
  fprintf(f, "{\"scene\": ");
  json_str(f, sw->name);
  fprintf(f, ", ");
  vi_app_fe_json(f, sw->sc);
  fprintf(f, "\"key\": ");
  json_str(f, sp->key);
  char split[160];
  vi_diagram_split(sw, split, sizeof split);
  fprintf(f, ", \"transient\": %d, \"record\": %d, \"chunks\": %d, "
          "\"seeded\": %s, \"split\": ", sp->transient, sp->record, sp->chunks,
          sp->chunks > 1 && sw->warm ? "true" : "false");
  json_str(f, split);
  fprintf(f, ", \"complete\": %s, \"points_done\": %lld, ",
          sw->incomplete ? "false" : "true", (long long)sw->points_done);
  if (!sp->key2) {
    json_line(sw, &sw->lines[0], f);
    if (sw->nlines > 1) {
      fprintf(f, ", \"down\": {");
      json_line(sw, &sw->lines[1], f);
      fprintf(f, "}");
    }
  } else {
    fprintf(f, "\"key2\": ");
    json_str(f, sp->key2);
    fprintf(f, ", \"param2\": ");
    json_nums(f, sw->param2, sp->steps2);
    fprintf(f, ", \"lines\": [");
    for (int l = 0; l < sw->nlines; l++) {
      fprintf(f, "%s{\"param2\": %.17g, ", l ? ", " : "",
              sw->param2[sw->lines[l].row]);
      json_line(sw, &sw->lines[l], f);
      fprintf(f, "}");
    }
    fprintf(f, "]");
  }
  fprintf(f, "}\n");
}

/* ---- basins of attraction ------------------------------------------------- */
/* Attractor ids of every cell (vi_sweep_attractors): cells whose last n
 * stroboscopic states agree to 100 tol (both are within about tol of
 * their orbit) up to a cyclic shift share one.  Returns 0, 1 out of memory. */
int vi_basins_identify(vi_diagram *sw)
{
  int K = sw->spec.steps, R = sw->spec.record, n2 = 2 * sw->N;
  size_t LK = (size_t)sw->nlines * K, blk = (size_t)K * R * n2;
  double *z = malloc(sizeof(double) * blk * sw->nlines + 1);
  int *per = malloc(sizeof(int) * LK + 1);
  free(sw->attractor);
  sw->attractor = malloc(sizeof(int) * LK + 1);
  int bad = !z || !per || !sw->attractor;
  for (size_t i = 0; !bad && i < LK; i++) {
    const vi_diagram_point *pt = &sw->lines[i / K].pt[i % K];
    per[i] = pt->failed ? 0 : pt->n;
  }
  for (int l = 0; !bad && l < sw->nlines; l++)
    memcpy(z + (size_t)l * blk, sw->lines[l].strobe, sizeof(double) * blk);
  if (!bad)
    bad = vi_sweep_attractors((int64_t)LK, sw->N, R, per, z, n2,
                              100 * sw->spec.tol, sw->attractor, &sw->nattr) != VI_OK;
  free(z);
  free(per);
  return bad;
}

/* Basins as JSON: one flat entry per cell (row-major: param2 rows). */
void vi_basins_print_json(const vi_diagram *sw, FILE *f)
{
  const vi_diagram_spec *sp = &sw->spec;
  int K = sp->steps, L = sw->nlines;
  fprintf(f, "{\"scene\": ");
  json_str(f, sw->name);
  fprintf(f, ", \"kind\": \"basins\", \"key\": ");
  json_str(f, sp->key);
  fprintf(f, ", \"key2\": ");
  json_str(f, sp->key2);
  fprintf(f, ", \"transient\": %d, \"record\": %d, \"steps\": %d, "
          "\"steps2\": %d, \"attractors\": %d, \"complete\": %s, "
          "\"points_done\": %lld", sp->transient, sp->record, K, sp->steps2,
          sw->nattr, sw->incomplete ? "false" : "true", (long long)sw->points_done);
  static const char *what[] = {"param", "param2", "n", "m", "attractor"};
  /* each value printed once: a map of K x K2 cells repeats them K2 and K
   * times, and their conversion was most of the serial time after the
   * parallel cells */
  char *v1 = malloc((size_t)K * 32), *v2 = malloc((size_t)sp->steps2 * 32);
  for (int k = 0; v1 && k < K; k++) snprintf(v1 + (size_t)32 * k, 32, "%.17g", sw->param[k]);
  for (int r = 0; v2 && r < sp->steps2; r++)
    snprintf(v2 + (size_t)32 * r, 32, "%.17g", sw->param2[r]);
  for (int w = 0; w < 5; w++) {
    fprintf(f, ", \"%s\": [", what[w]);
    for (int l = 0; l < L; l++)
      for (int k = 0; k < K; k++) {
        const vi_diagram_point *pt = &sw->lines[l].pt[k];
        int row = sw->lines[l].row;
        if (l || k) fputs(", ", f);
        if (w == 0 && v1) fputs(v1 + (size_t)32 * k, f);
        else if (w == 0) fprintf(f, "%.17g", sw->param[k]);
        else if (w == 1 && v2) fputs(v2 + (size_t)32 * row, f);
        else if (w == 1) fprintf(f, "%.17g", sw->param2[row]);
        else if (w == 4) fprintf(f, "%d", sw->attractor[(size_t)l * K + k]);
        else if (pt->n && !pt->failed) fprintf(f, "%d", w == 2 ? pt->n : pt->m);
        else fputs("null", f);
      }
    fputc(']', f);
  }
  free(v1);
  free(v2);
  /* every failed cell with its message (the terminal shows the first) */
  fprintf(f, ", \"failed\": [");
  int first = 1;
  for (int l = 0; l < L; l++)
    for (int k = 0; k < K; k++)
      if (sw->lines[l].pt[k].failed)
        json_failure(f, &first, sw->param[k], sw->param2[sw->lines[l].row],
                     &sw->lines[l].pt[k]);
  fprintf(f, "]}\n");
}

/* Basins as text: the attractors, then the grid of their ids. */
void vi_basins_table(const vi_diagram *sw, FILE *f)
{
  const vi_diagram_spec *sp = &sw->spec;
  int K = sp->steps;
  fprintf(f, "basins of %s x %s, %d x %d cells, %d transient + %d recorded "
          "periods each, %.3f s: %d attractor%s\n", sp->key, sp->key2, K,
          sp->steps2, sp->transient, sp->record, sw->wall, sw->nattr,
          sw->nattr == 1 ? "" : "s");
  for (int a = 0; a < sw->nattr; a++)
    for (size_t i = 0; i < (size_t)sw->nlines * K; i++)
      if (sw->attractor[i] == a) {
        const vi_diagram_point *pt = &sw->lines[i / K].pt[i % K];
        int cells = 0;
        for (size_t j = 0; j < (size_t)sw->nlines * K; j++) cells += sw->attractor[j] == a;
        fprintf(f, "  %2d: P(%d,%d), %d cells\n", a, pt->n, pt->m, cells);
        break;
      }
  fprintf(f, "rows %s (%.6g .. %.6g), columns %s (%.6g .. %.6g); '.': none\n",
          sp->key2, sw->param2[0], sw->param2[sp->steps2 - 1], sp->key,
          sw->param[0], sw->param[K - 1]);
  for (int l = sw->nlines - 1; l >= 0; l--) {
    for (int k = 0; k < K; k++) {
      int id = sw->attractor[(size_t)l * K + k];
      if (id < 0) fprintf(f, "  .");
      else fprintf(f, " %2d", id);
    }
    fprintf(f, "\n");
  }
}
