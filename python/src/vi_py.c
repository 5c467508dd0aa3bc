/* vi_py.c - collectors and the Ctrl-C hook of the Python package (vi_py.h). */
#include "vi_py.h"

#include <pthread.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>

static int buf_push(vi_py_buf *b, const double *x, int64_t k)
{
  if (b->len + k > b->cap) {
    int64_t cap = b->cap ? 2 * b->cap : 64;
    while (cap < b->len + k) cap *= 2;
    double *d = realloc(b->d, (size_t)cap * sizeof(double));
    if (!d) return -1;
    b->d = d;
    b->cap = cap;
  }
  if (x)
    memcpy(b->d + b->len, x, (size_t)k * sizeof(double));
  else /* a row the library left out (dE of an interval without impact) */
    memset(b->d + b->len, 0, (size_t)k * sizeof(double));
  b->len += k;
  return 0;
}

static double *row(vi_py_run *r, int k)
{
  vi_py_buf *b = &r->tab[k];
  if (buf_push(b, NULL, r->width[k])) {
    r->nomem = 1;
    return NULL;
  }
  return b->d + b->len - r->width[k];
}

static void put(double *d, const double *x, int n)
{
  if (x) memcpy(d, x, (size_t)n * sizeof(double));
  else memset(d, 0, (size_t)n * sizeof(double)); /* dE without an impact */
}

vi_py_run *vi_py_run_new(int n, int states)
{
  vi_py_run *r = calloc(1, sizeof *r);
  if (!r) return NULL;
  r->n = n;
  r->states = states;
  r->width[0] = 4 + (states ? 3 * n : 0);
  r->width[1] = 1 + 2 * n;
  r->width[2] = 5 + 10 * n;
  return r;
}

void vi_py_run_free(vi_py_run *r)
{
  if (!r) return;
  for (int k = 0; k < 3; k++) free(r->tab[k].d);
  free(r);
}

int vi_py_nomem(const vi_py_run *r) { return r->nomem; }

void vi_py_sim_free(vi_sim *sim) { vi_sim_destroy(&sim); }

static int on_event(const vi_event *ev, void *user)
{
  vi_py_run *r = user;
  double *d = row(r, 0);
  if (!d) return 1; /* out of memory: stop the run, reported by the caller */
  int n = r->n;
  int32_t ks[2] = {ev->kind, ev->stop}; /* two int32 columns for numpy */
  d[0] = ev->t, d[1] = ev->vn, d[2] = ev->ie;
  memcpy(d + 3, ks, sizeof ks);
  if (r->states) {
    put(d + 4, ev->x, n);
    put(d + 4 + n, ev->v_minus, n);
    put(d + 4 + 2 * n, ev->v_plus, n);
  }
  return 0;
}

static int on_sample(double t, int n, const double *x, const double *v,
                     void *user)
{
  vi_py_run *r = user;
  double *d = row(r, 1);
  if (!d) return 1;
  d[0] = t;
  put(d + 1, x, n);
  put(d + 1 + n, v, n);
  return 0;
}

static int on_ledger(const vi_ledger_interval *iv, void *user)
{
  vi_py_run *r = user;
  double *d = row(r, 2);
  if (!d) return 1;
  int n = r->n;
  const double *rows[10] = {iv->Ea, iv->Eb, iv->Ka, iv->Kb, iv->FE,
                            iv->DE, iv->XE, iv->CE, iv->NE, iv->dE};
  d[0] = iv->t_a, d[1] = iv->t_b, d[2] = iv->ie, d[3] = iv->residual;
  d[4] = iv->dE != NULL;
  for (int k = 0; k < 10; k++) put(d + 5 + k * n, rows[k], n);
  return 0;
}

int vi_py_prepare(vi_py_run *r, vi_sim *sim, int method, double rtol,
                  double atol, double dt, int ledger)
{
  int st = vi_sim_set_method(sim, method);
  if (!st) st = vi_sim_set_tolerances(sim, rtol, atol);
  if (!st) st = vi_sim_set_event_callback(sim, on_event, r, NULL);
  if (!st) st = vi_sim_set_event_states(sim, r->states);
  if (!st) st = vi_sim_set_cancel(sim, vi_py_cancel, r, NULL);
  if (!st && dt > 0) st = vi_sim_set_sampling(sim, dt, on_sample, r, NULL);
  if (!st && ledger) st = vi_sim_enable_ledger(sim, 1);
  if (!st && ledger) st = vi_sim_set_ledger_callback(sim, on_ledger, r, NULL);
  return st;
}

const double *vi_py_table(const vi_py_run *r, int which, int64_t *rows,
                          int *width)
{
  if (which < 0 || which > 2) {
    *rows = 0, *width = 0;
    return NULL;
  }
  *width = r->width[which];
  *rows = r->tab[which].len / r->width[which];
  return r->tab[which].d;
}

int vi_py_replay(const vi_py_run *r, vi_writer *w)
{
  int n = r->n, st = 0;
  const vi_py_buf *e = &r->tab[0], *s = &r->tab[1], *l = &r->tab[2];
  for (int64_t i = 0; i * r->width[0] < e->len && !st; i++) {
    const double *d = e->d + i * r->width[0];
    vi_event ev;
    int32_t ks[2];
    memset(&ev, 0, sizeof ev);
    memcpy(ks, d + 3, sizeof ks);
    ev.t = d[0], ev.vn = d[1], ev.ie = d[2];
    ev.kind = ks[0], ev.stop = ks[1], ev.n = n;
    ev.x = d + 4, ev.v_minus = d + 4 + n, ev.v_plus = d + 4 + 2 * n;
    st = vi_writer_event(w, &ev);
  }
  for (int64_t i = 0; i * r->width[1] < s->len && !st; i++) {
    const double *d = s->d + i * r->width[1];
    st = vi_writer_sample(w, d[0], d + 1, d + 1 + n);
  }
  for (int64_t i = 0; i * r->width[2] < l->len && !st; i++) {
    const double *d = l->d + i * r->width[2];
    vi_ledger_interval iv;
    iv.n = n;
    iv.t_a = d[0], iv.t_b = d[1], iv.ie = d[2], iv.residual = d[3];
    iv.Ea = d + 5, iv.Eb = d + 5 + n, iv.Ka = d + 5 + 2 * n;
    iv.Kb = d + 5 + 3 * n, iv.FE = d + 5 + 4 * n, iv.DE = d + 5 + 5 * n;
    iv.XE = d + 5 + 6 * n, iv.CE = d + 5 + 7 * n, iv.NE = d + 5 + 8 * n;
    iv.dE = d[4] != 0 ? d + 5 + 9 * n : NULL;
    st = vi_writer_ledger(w, &iv);
  }
  return st;
}

/* ---- Ctrl-C --------------------------------------------------------- */

static volatile sig_atomic_t sigint_count;
static struct sigaction sigint_old;
static int sigint_depth, sigint_installed;
static pthread_mutex_t sigint_mu = PTHREAD_MUTEX_INITIALIZER;

static void on_sigint(int sig, siginfo_t *info, void *ctx)
{
  sigint_count++;
  /* the handler we replaced (Python's) learns of it too */
  if (sigint_old.sa_flags & SA_SIGINFO) {
    if (sigint_old.sa_sigaction) sigint_old.sa_sigaction(sig, info, ctx);
  } else if (sigint_old.sa_handler == SIG_DFL) {
    /* a process that asked for the default ends as it would have */
    signal(sig, SIG_DFL);
    raise(sig);
  } else if (sigint_old.sa_handler != SIG_IGN) {
    sigint_old.sa_handler(sig);
  }
}

int vi_py_sigint_arm(void)
{
  int st = 0;
  pthread_mutex_lock(&sigint_mu);
  if (sigint_depth++ == 0) {
    struct sigaction sa, old;
    memset(&sa, 0, sizeof sa);
    sa.sa_sigaction = on_sigint;
    sa.sa_flags = SA_SIGINFO | SA_ONSTACK;
    sigemptyset(&sa.sa_mask);
    /* an ignored SIGINT stays ignored: nothing to cancel on */
    if (sigaction(SIGINT, NULL, &old) == 0 &&
        !(!(old.sa_flags & SA_SIGINFO) && old.sa_handler == SIG_IGN)) {
      sigint_old = old;
      if (sigaction(SIGINT, &sa, NULL) == 0) sigint_installed = 1;
      else st = -1;
    }
  }
  pthread_mutex_unlock(&sigint_mu);
  return st;
}

void vi_py_sigint_disarm(void)
{
  pthread_mutex_lock(&sigint_mu);
  if (sigint_depth > 0 && --sigint_depth == 0 && sigint_installed) {
    sigaction(SIGINT, &sigint_old, NULL);
    sigint_installed = 0;
  }
  pthread_mutex_unlock(&sigint_mu);
}

unsigned vi_py_sigint_count(void) { return (unsigned)sigint_count; }

int vi_py_cancel(void *user)
{
  const vi_py_run *r = user;
  return (unsigned)sigint_count != r->sig0;
}

int vi_py_cancel_since(void *user)
{
  return (unsigned)sigint_count != *(const unsigned *)user;
}

int vi_py_sim_run(vi_sim *sim, vi_py_run *r, double t_end, int *interrupted)
{
  vi_py_sigint_arm();
  r->sig0 = vi_py_sigint_count();
  int st = vi_sim_run(sim, t_end);
  *interrupted = st == VI_CANCELLED && vi_py_sigint_count() != r->sig0;
  vi_py_sigint_disarm();
  return st;
}
