/* vi_diagram_file.c - a diagram into the flat arrays of the sweep file's
 * writer (src/io/vi_diagram_h5.h, in libvibroimpact_h5's objects; layout:
 * doc/sweep-layout.md).  The HDF5 itself is the writer's. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/vi_diagram_h5.h"
#include "vi_diagram.h"

/* The arrays a diagram is flattened into (one allocation each). */
typedef struct flat {
  int *ni, *pi;
  int64_t *cnt, *pstart;
  double *T, *imp, *strobe, *pd, *lyap;
  int *done;
} flat;

static void flat_free(flat *b)
{
  free(b->ni);
  free(b->pi);
  free(b->cnt);
  free(b->pstart);
  free(b->T);
  free(b->imp);
  free(b->strobe);
  free(b->pd);
  free(b->lyap);
  free(b->done);
}

/* /sweep/p11: every P(1,1) orbit at each value (sweep --orbits); 0 or 1
 * out of memory. */
static int flat_p11(const vi_diagram *sw, vi_diagram_file *d, flat *b)
{
  int K = sw->spec.steps, L = sw->nlines;
  size_t LK = (size_t)L * K, J = 0;
  for (size_t i = 0; i < LK; i++) {
    int no = sw->lines[i / K].pt[i % K].norb;
    J += no > 0 ? (size_t)no : 0;
  }
  b->pi = malloc(sizeof(int) * (LK + 2 * J + 1));
  b->pstart = malloc(sizeof(int64_t) * LK);
  b->pd = malloc(sizeof(double) * (2 * J + 1));
  if (!b->pi || !b->pstart || !b->pd) return 1;
  int *st = b->pi + LK, *ad = st + J;
  size_t off = 0;
  for (size_t i = 0; i < LK; i++) {
    const vi_diagram_point *pt = &sw->lines[i / K].pt[i % K];
    b->pi[i] = pt->norb;
    b->pstart[i] = (int64_t)off;
    for (int j = 0; j < pt->norb; j++, off++) {
      b->pd[off] = pt->ovn[j];
      b->pd[J + off] = pt->ophase[j];
      st[off] = pt->ostable[j];
      ad[off] = pt->oadm[j];
    }
  }
  d->p11_count = b->pi;
  d->p11_start = b->pstart;
  d->np11 = (int64_t)J;
  d->p11_vn = b->pd;
  d->p11_phase = b->pd + J;
  d->p11_stable = st;
  d->p11_admissible = ad;
  return 0;
}

/* Each point's class, period, impacts and stroboscopic states, the
 * lines' directions and rows, the points done; 0 or 1 out of memory. */
static int flat_points(const vi_diagram *sw, vi_diagram_file *d, flat *b)
{
  int K = sw->spec.steps, L = sw->nlines, R = sw->spec.record, n2 = 2 * sw->N;
  size_t LK = (size_t)L * K;
  int64_t I = 0, off = 0;
  for (int l = 0; l < L; l++)
    for (int k = 0; k < K; k++) I += sw->lines[l].pt[k].nimp;
  b->ni = malloc(sizeof(int) * (LK * 2 + 2 * (size_t)L));
  b->cnt = malloc(sizeof(int64_t) * LK * 2);
  b->T = malloc(sizeof(double) * LK);
  b->imp = malloc(sizeof(double) * (size_t)(3 * I + 1));
  b->strobe = malloc(sizeof(double) * LK * R * n2 + 1);
  b->done = malloc(sizeof(int) * LK);
  if (!b->ni || !b->cnt || !b->T || !b->imp || !b->strobe || !b->done) return 1;
  int *nn = b->ni, *mm = b->ni + LK, *dir = b->ni + 2 * LK, *row = dir + L;
  int64_t *start = b->cnt + LK;
  for (int l = 0; l < L; l++) {
    const vi_diagram_line *ln = &sw->lines[l];
    dir[l] = ln->dir;
    row[l] = ln->row;
    memcpy(b->strobe + (size_t)l * K * R * n2, ln->strobe, sizeof(double) * K * R * n2);
    for (int k = 0; k < K; k++) {
      const vi_diagram_point *pt = &ln->pt[k];
      size_t i = (size_t)l * K + k;
      nn[i] = pt->failed ? -1 : pt->n;
      mm[i] = pt->n ? pt->m : 0;
      b->T[i] = pt->T;
      b->cnt[i] = pt->nimp;
      b->done[i] = pt->done;
      start[i] = off;
      for (int64_t j = 0; j < pt->nimp; j++, off++) {
        b->imp[off] = pt->t[j];
        b->imp[I + off] = pt->phase[j];
        b->imp[2 * I + off] = pt->vn[j];
      }
    }
  }
  d->n = nn, d->m = mm, d->dir = dir, d->row = row, d->period = b->T;
  d->strobe = b->strobe, d->impact_count = b->cnt, d->impact_start = start;
  d->nimpacts = I, d->impact_time = b->imp, d->impact_phase = b->imp + I;
  d->impact_vn = b->imp + 2 * I, d->done = b->done;
  return 0;
}

/* The diagram's settings and the --lyapunov exponents; 0 or 1 out of
 * memory. */
static int flat_spec(const vi_diagram *sw, vi_diagram_file *d, flat *b)
{
  const vi_diagram_spec *sp = &sw->spec;
  size_t LK = (size_t)sw->nlines * sp->steps;
  d->text = sw->text, d->name = sw->name, d->basins = sw->attractor != NULL;
  d->complete = !sw->incomplete, d->points_done = sw->points_done;
  d->key = sp->key, d->key2 = sp->key2, d->steps = sp->steps;
  d->steps2 = sp->steps2, d->nlines = sw->nlines, d->ncoord = sw->N;
  d->transient = sp->transient, d->record = sp->record, d->chunks = sp->chunks;
  d->seeded = sp->chunks > 1 && sw->warm, d->nmax = sp->nmax;
  d->orbits = sp->orbits, d->tol = sp->tol, d->t0 = sw->t0;
  d->param = sw->param, d->param2 = sw->param2;
  d->attractor = sw->attractor, d->nattr = sw->nattr;
  if (!sp->lyapunov) return 0;
  if (!(b->lyap = malloc(sizeof(double) * LK))) return 1;
  for (size_t i = 0; i < LK; i++)
    b->lyap[i] = sw->lines[i / sp->steps].pt[i % sp->steps].lyap;
  d->lyapunov = b->lyap;
  return 0;
}

int vi_diagram_write_h5(const vi_diagram *sw, const char *path, char *err, int errlen)
{
  vi_diagram_file d;
  flat b;
  memset(&d, 0, sizeof d);
  memset(&b, 0, sizeof b);
  int bad = flat_spec(sw, &d, &b) || flat_points(sw, &d, &b) ||
            (sw->spec.orbits > 0 && flat_p11(sw, &d, &b));
  if (bad) snprintf(err, (size_t)errlen, "out of memory");
  else bad = vi_diagram_file_write(&d, path, err, errlen);
  flat_free(&b);
  return bad;
}
