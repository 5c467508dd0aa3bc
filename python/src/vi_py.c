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

static int push1(vi_py_buf *b, double x) { return buf_push(b, &x, 1); }

vi_py_run *vi_py_run_new(int n, int states)
{
  vi_py_run *r = calloc(1, sizeof *r);
  if (!r) return NULL;
  r->n = n;
  r->states = states;
  return r;
}

void vi_py_run_free(vi_py_run *r)
{
  if (!r) return;
  for (int k = 0; k < 8; k++) free(r->ev[k].d);
  for (int k = 0; k < 3; k++) free(r->smp[k].d);
  for (int k = 0; k < 15; k++) free(r->led[k].d);
  free(r);
}

int vi_py_nomem(const vi_py_run *r) { return r->nomem; }

static int on_event(const vi_event *ev, void *user)
{
  vi_py_run *r = user;
  int e = push1(&r->ev[0], ev->t) | push1(&r->ev[1], ev->vn) |
          push1(&r->ev[2], ev->ie) | push1(&r->ev[3], ev->kind) |
          push1(&r->ev[4], ev->stop);
  if (r->states)
    e |= buf_push(&r->ev[5], ev->x, r->n) | buf_push(&r->ev[6], ev->v_minus, r->n) |
         buf_push(&r->ev[7], ev->v_plus, r->n);
  if (e) r->nomem = 1;
  else r->events++;
  return r->nomem; /* out of memory: stop the run, reported by the caller */
}

static int on_sample(double t, int n, const double *x, const double *v,
                     void *user)
{
  vi_py_run *r = user;
  if (push1(&r->smp[0], t) | buf_push(&r->smp[1], x, n) |
      buf_push(&r->smp[2], v, n))
    r->nomem = 1;
  else
    r->samples++;
  return r->nomem;
}

static int on_ledger(const vi_ledger_interval *iv, void *user)
{
  vi_py_run *r = user;
  int n = iv->n;
  const double *rows[10] = {iv->Ea, iv->Eb, iv->Ka, iv->Kb, iv->FE,
                            iv->DE, iv->XE, iv->CE, iv->NE, iv->dE};
  int e = push1(&r->led[0], iv->t_a) | push1(&r->led[1], iv->t_b) |
          push1(&r->led[2], iv->ie) | push1(&r->led[3], iv->residual) |
          push1(&r->led[4], iv->dE != NULL);
  for (int k = 0; k < 10; k++) e |= buf_push(&r->led[5 + k], rows[k], n);
  if (e) r->nomem = 1;
  else r->intervals++;
  return r->nomem;
}

int vi_py_attach(vi_py_run *r, vi_sim *sim, double dt, int ledger)
{
  int st = vi_sim_set_event_callback(sim, on_event, r, NULL);
  if (!st) st = vi_sim_set_event_states(sim, r->states);
  if (!st) st = vi_sim_set_cancel(sim, vi_py_cancel, r, NULL);
  if (!st && dt > 0) st = vi_sim_set_sampling(sim, dt, on_sample, r, NULL);
  if (!st && ledger) st = vi_sim_enable_ledger(sim, 1);
  if (!st && ledger) st = vi_sim_set_ledger_callback(sim, on_ledger, r, NULL);
  return st;
}

const double *vi_py_data(const vi_py_run *r, int group, int which,
                         int64_t *len)
{
  const vi_py_buf *b = group == 0 && which >= 0 && which < 8 ? &r->ev[which]
                     : group == 1 && which >= 0 && which < 3 ? &r->smp[which]
                     : group == 2 && which >= 0 && which < 15 ? &r->led[which]
                     : NULL;
  *len = b ? b->len : 0;
  return b ? b->d : NULL;
}

int vi_py_replay(const vi_py_run *r, vi_writer *w)
{
  int n = r->n, st = 0;
  for (int64_t i = 0; i < r->events && !st; i++) {
    vi_event ev;
    memset(&ev, 0, sizeof ev);
    ev.t = r->ev[0].d[i];
    ev.vn = r->ev[1].d[i];
    ev.ie = r->ev[2].d[i];
    ev.kind = (int)r->ev[3].d[i];
    ev.stop = (int)r->ev[4].d[i];
    ev.n = n;
    ev.x = r->ev[5].d + i * n;
    ev.v_minus = r->ev[6].d + i * n;
    ev.v_plus = r->ev[7].d + i * n;
    st = vi_writer_event(w, &ev);
  }
  for (int64_t i = 0; i < r->samples && !st; i++)
    st = vi_writer_sample(w, r->smp[0].d[i], r->smp[1].d + i * n,
                          r->smp[2].d + i * n);
  for (int64_t i = 0; i < r->intervals && !st; i++) {
    vi_ledger_interval iv;
    const double *row[10];
    for (int k = 0; k < 10; k++) row[k] = r->led[5 + k].d + i * n;
    iv.n = n;
    iv.t_a = r->led[0].d[i];
    iv.t_b = r->led[1].d[i];
    iv.ie = r->led[2].d[i];
    iv.residual = r->led[3].d[i];
    iv.Ea = row[0], iv.Eb = row[1], iv.Ka = row[2], iv.Kb = row[3];
    iv.FE = row[4], iv.DE = row[5], iv.XE = row[6], iv.CE = row[7];
    iv.NE = row[8];
    iv.dE = r->led[4].d[i] != 0 ? row[9] : NULL;
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
