/* vi_orbit_handle.h - the orbit analysis handle (struct vi_orbit) and its
 * limits, below every orbit file: vi_orbit.c (search, shooting,
 * multipliers) drives vi_balance.c (WB 11-13), which needs the handle and
 * nothing of vi_orbit.c, so the calls run one way.  Never installed. */
#ifndef VI_ORBIT_HANDLE_H
#define VI_ORBIT_HANDLE_H

#include <math.h>

#include "vi_flow_internal.h"

#define RING 4096 /* impacts remembered for classification */
#define MAX_N 8   /* longest orbit period looked for, in forcing periods */

#define MAX_M 8 /* most impacts per period analysed (several stops) */

struct vi_orbit {
  const vi_model *m;
  int n, ns, method;
  double rtol, atol, max_periods, tol, T;
  double *x0, *v0;
  vi_sim *sim;
  /* classification */
  int pn, pm, analysed;
  int classified; /* vi_orbit_find classified a transient */
  /* impact ring: t, stop, then x, v per impact */
  int64_t nimp;
  double *rt, *rz;
  int *rs;
  /* states at the last 3 MAX_N + 1 forcing-period ends (stroboscopic) */
  double *pz;
  /* the analysed P(1, m) orbit: section time, its mi impacts in the period
   * from t_s (time, stop, x, v-, v+ [n x MAX_M], v_n, energy lost) and the
   * ledger of the interval ending at each (its approach: FE, DE, XE
   * [n x MAX_M]) */
  double t_s, KEi, RE, IE, r_rec, closure, gmin;
  int mi, istop[MAX_M];
  double it[MAX_M], ivn[MAX_M], iie[MAX_M];
  double *ix, *iv, *ivp, *aFE, *aDE, *aXE;
  double *mz; /* a shooting map's pre-impact states, stacked [2n x MAX_M] */
  /* totals over the period [n] and per stop [n x ns], [ns] */
  double *zfix, *FE, *DE, *XE, *reff, *mre, *mim, *kFE, *kDE, *kXE;
  double *kKE, *kRE, *kIE, *kr, *kcl;
  int *kcnt;
  double *scr, *dE; /* scratch: map output [2n], impact jumps [n] */
  double *block;
  int map_impacts;
  /* direct search: the transient's own classification, and whether the
   * analysed orbit came from the impact-phase scan */
  int direct, tn, tm, by_scan;
  char errmsg[VI_MSG_LEN];
};

/* the P(1,1) getters: one impact per period; the rest: any analysed orbit */
#define NEED_ORBIT(o) \
  do { if (!(o)) return VI_ERR_ARG; if (!(o)->analysed) return VI_ERR_STATE; } while (0)
#define NEED_P11(o) \
  do { NEED_ORBIT(o); if ((o)->mi != 1) return VI_ERR_STATE; } while (0)

/* One period from the refined fixed point o->zfix at o->t_s with the
 * ledger: the impacts of the period and WB 11-13 in total and per stop
 * (vi_balance.c).  VI_OK or a code with o->errmsg set. */
int vi_balance_run(vi_orbit *o);

/* The stops' length scale max_k |x_k| (every stop, not stop 0 alone):
 * tolerances on states are relative to it and to the states' own size. */
static inline double vi_orbit_xs_scale(const vi_model *m)
{
  double s = 0.0;
  for (int k = 0; k < m->ns; k++) s = fmax(s, fabs(m->xsv[k]));
  return s;
}

#endif
