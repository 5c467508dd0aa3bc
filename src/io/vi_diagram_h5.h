/* vi_diagram_h5.h - the sweep and basins file (doc/sweep-layout.md) for the
 * programs that write one (vibroimpact-sweep): the diagram as flat,
 * caller-owned arrays, row-major [nlines x steps] per point.  Not
 * installed, not exported (the sweep links the writer's object); no HDF5
 * type appears here, so its callers never see vi_h5_util.h. */
#ifndef VI_DIAGRAM_H5_H
#define VI_DIAGRAM_H5_H

#include <stdint.h>

typedef struct vi_diagram_file {
  const char *text, *name;  /* the scene (after --set) and its file name */
  int basins;               /* 1: kind "basins" (attractor below) */
  int complete;             /* 0: interrupted, only the points done */
  int64_t points_done;
  const char *key, *key2;   /* key2 NULL: one parameter */
  int steps, steps2, nlines, ncoord;
  int transient, record, chunks, seeded, nmax, orbits;
  double tol, t0;
  const double *param, *param2; /* [steps], [steps2] */
  const int *dir, *row;     /* [nlines] */
  const int *n, *m;         /* [nlines x steps]: P(n, m), n = -1 failed */
  const double *period;     /* [nlines x steps] */
  const double *strobe;     /* [nlines x steps x record x 2 ncoord] */
  const int64_t *impact_count, *impact_start; /* [nlines x steps] */
  int64_t nimpacts;
  const double *impact_time, *impact_phase, *impact_vn; /* [nimpacts] */
  /* orbits > 0: the P(1,1) orbits of each point, np11 in all */
  const int *p11_count;
  const int64_t *p11_start;
  int64_t np11;
  const double *p11_vn, *p11_phase;
  const int *p11_stable, *p11_admissible;
  const double *lyapunov;   /* [nlines x steps] or NULL (not asked for) */
  const int *attractor;     /* basins: [nlines x steps] ids, -1 none */
  int nattr;
  const int *done;          /* [nlines x steps]: 1 computed */
} vi_diagram_file;

/* Write d to path, as path.part renamed when complete (built in memory:
 * every write, the sync and the rename are checked).  Returns 0, or 1 with
 * a message in err [errlen]. */
int vi_diagram_file_write(const vi_diagram_file *d, const char *path,
                          char *err, int errlen);

#endif
