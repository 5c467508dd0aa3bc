/* vi_identify_internal.h - what the files of the identification share
 * (private): the handle, the orbit record, and the steps of
 * vi_identify_run split by concern:
 *   vi_identify.c         set-up, the run's order, the result getters
 *   vi_identify_resid.c   models at trial values, the orbit continued,
 *                         residuals and their exact Jacobian
 *   vi_identify_track.c   the orbit at many times (the samples), in blocks
 *   vi_identify_seed.c    the recording's period, the orbit the model
 *                         shows at a start, the shift scan
 *   vi_identify_scan2.c   every P(n, 2) orbit from a scan of impact phases
 *   vi_identify_stats.c   noise, uncertainty, the WB 12 route
 *   vi_identify_fit.c     the trust-region fit from one start
 *   vi_identify_global.c  starts over the admissible ranges, the distinct
 *                         minima the data admit, profile intervals */
#ifndef VI_IDENTIFY_INTERNAL_H
#define VI_IDENTIFY_INTERNAL_H

#include <gsl/gsl_matrix.h>
#include <gsl/gsl_vector.h>

#include "vi_forcing.h"
#include "vi_orbit_internal.h"
#include "vibroimpact/vi_identify.h"

#define MAXP 32
#define MAXCH 8 /* channels beside the first three (vi_identify_add_channel) */

/* A P(n, m) orbit: impact times, stops, pre-impact states [N x MAX_M]. */
typedef struct orb {
  int n, m;
  int stop[MAX_M];
  double t[MAX_M];
  double *x, *v;
} orb;

/* One local minimum: what a fit from one start ended on. */
typedef struct vi_id_sol {
  double p[MAXP], se[MAXP], l95[MAXP], h95[MAXP], pl95[MAXP], ph95[MAXP];
  int flags[MAXP], pflags[MAXP];
  double corr[MAXP * MAXP];
  double t0, t0se, rms, ssr, rcond, dchi2; /* dchi2: its excess over the best */
  double dsep, lsep; /* the best's and its responses apart (noise variances
                      * over the record), the record multiple that separates them */
  int conv, iters, n, m;
  orb o; /* its orbit (buffers owned) */
} vi_id_sol;

struct vi_identify {
  const vi_model *base;
  int N, np;
  int kind[MAXP], kst[MAXP], pset[MAXP];
  double p0[MAXP], lo[MAXP], hi[MAXP];
  double pgiven[MAXP]; /* the caller's starts; p0 is a run's (Omega snapped) */
  char key[MAXP][64]; /* the vi_param.h key of each parameter */
  vi_identify_model_fn fn;
  void *user;
  vi_destroy_fn destroy;
  double *c; /* observation [N] */
  int fit_shift, stable_only;
  double shift0, sigma, mumax; /* mumax: the fitted orbit's largest |multiplier| */
  int ns;
  /* recording: y the first channel; t from its first sample, which is at
   * tref on the caller's clock (a clock that reads 1.7e9 at the record,
   * or 1e5 periods on, would make Omega and the shift one direction:
   * the shift is fitted from the record's start, reported on the
   * caller's clock) */
  double *t, *y, *vy, *ay, tref;
  int ych;                 /* y's order: 0 c.x, 1 c.x', 2 c.x'' */
  int nch, chord[MAXCH];   /* more channels: order, observation, data */
  double *chc[MAXCH], *chy[MAXCH];
  /* the model and orbit at pcur (continuation: each trial starts here) */
  vi_model *cur;
  vi_xflow *xf;
  double pcur[MAXP];
  int have_cur;
  orb o, trial;
  /* the last Jacobian's point: its orbit and du/dp [D x np], the
   * predictor of the next trials' orbits */
  orb acc;
  double pacc[MAXP], *dudp, *mre, *mim;
  int have_pred;
  double Om0, scale; /* velocity scaling; largest |y| (penalty) */
  /* parameters held during a profile: col[j] the Jacobian column of
   * parameter j (-1 held at hval[j]), nfree the free ones */
  int col[MAXP], nfree;
  double hval[MAXP];
  /* the global stage: on, and the ranges it searched */
  int global;
  double glo[MAXP], ghi[MAXP];
  int glog[MAXP]; /* 1: the starts spread in log over [glo, ghi] */
  double slo[MAXP], shi[MAXP]; /* what every global stage of the run */
  int nsearch;                 /* searched, together (the message of a
                                  search that found nothing names it) */
  double widen;   /* > 0: keys with no natural range spread a factor widen
                     either way of a positive start, in log (vi_identify.c,
                     widen_retry); 0: +-50 %; < 0: +-50 % about a minimum,
                     within the bounds */
  /* a fitted forcing frequency: its parameter (-1: none) and the
   * recording's own period, which sets its starts (2 pi n / lag) */
  int jom;
  double lag;
  /* results */
  int done, conv, iters;
  double p[MAXP], se[MAXP], l95[MAXP], h95[MAXP], t0, t0se, rms, noise, rcond;
  int flags[MAXP];
  double corr[MAXP * MAXP], r12, vN, KE, RE;
  vi_id_sol *sol; /* the minima the data admit, best first */
  int nsol, nfound, unique;
  vi_cancel_fn cancel;          /* vi_identify_set_cancel */
  void *cancel_user;
  vi_destroy_fn cancel_free;
  int cancel_hit;               /* the poll said cancel during this run */
  char errmsg[VI_MSG_LEN];
};

/* vi_identify.c */
int vi_id_poll_cancel(vi_identify *id);
int vi_id_poll_fn(void *user);
int vi_id_poll_mon(const vi_progress *p, void *user);
int vi_id_orb_alloc(orb *o, int N);
void vi_id_orb_copy(orb *d, const orb *s, int N);
void vi_id_drop_cur(vi_identify *id);
void vi_id_free_solutions(vi_identify *id);
void vi_id_free_channels(vi_identify *id);

/* vi_identify_resid.c */
int vi_id_make_model(vi_identify *id, const double *p, vi_model **out);
double vi_id_period_of(const vi_model *m, int n);
void vi_id_orb_normalise(orb *o, double P);
int vi_id_ensure(vi_identify *id, const double *p);
void vi_id_orbit_state(const vi_model *m, const vi_xflow *xf, const orb *o,
                       double s, double *z, double *zp, int *jo,
                       double *tauo, double *ko);
double vi_id_channel(const vi_identify *id, const vi_model *m, double s,
                     const double *z, int order, double *work);
int vi_id_first_channel(const vi_identify *id, const vi_model *m, const vi_xflow *xf,
                        const orb *o, double t0, double *y);
int vi_id_nres(const vi_identify *id);
void vi_id_split(const vi_identify *id, const gsl_vector *th, double *p,
                 double *t0);
int vi_id_res_f(const gsl_vector *th, void *ctx, gsl_vector *f);
int vi_id_res_df(const gsl_vector *th, void *ctx, gsl_matrix *J);

/* vi_identify_track.c: the orbit o of m at many times.  Samples are
 * evaluated in blocks of at most VI_ID_BLOCK. */
#define VI_ID_BLOCK 64
typedef struct vi_id_track {
  const vi_model *m;
  const orb *o;
  int N, nseg;
  double P;              /* the orbit's period */
  int halves;            /* of the states wanted: 1 x, 2 v, 3 both (init's
                            choice; x alone or v alone spares the other's
                            half of the work where proportional) */
  vi_xseg seg[MAX_M];    /* the flight from each impact */
  double *zp;            /* post-impact states [2N x o->m] */
  double *Q;             /* a block's modal states [2N x VI_ID_BLOCK] */
  double *Z;             /* physical states, for the caller [2N x VI_ID_BLOCK] */
  double *work;          /* [2N], free for the caller */
  double *A;             /* [N x VI_ID_BLOCK], free for the caller */
  double *mem;
} vi_id_track;
/* Where model time s falls on the orbit o of period P: after impact *j,
 * *tau later, in the *k-th orbit period from the first impact. */
void vi_id_locate(const orb *o, double P, double s, int *j, double *tau,
                  double *k);
/* Start the flights of o's impacts (o and m are kept, not copied):
 * VI_OK or VI_ERR_NOMEM; vi_id_track_free frees (also after a failure). */
int vi_id_track_init(vi_id_track *tk, const vi_model *m, const vi_xflow *xf,
                     const orb *o);
void vi_id_track_free(vi_id_track *tk);
/* The states z = (x, v) at t_j[i] + tau[i], i < k <= VI_ID_BLOCK, into the
 * columns of Z [2N x k] (tk->Z or the caller's); proportional damping
 * with C [4N x k] not NULL: each mode's 2 x 2 state-transition matrix
 * from impact j[i] to the sample too (vi_xseg_modal's). */
void vi_id_track_at(vi_id_track *tk, int k, const int *j, const double *tau,
                    double *Z, double *C);
/* The same at the model times s [k], located on the orbit: j, tau [k]
 * and kper [k] (may be NULL) as vi_id_locate's. */
void vi_id_track_states(vi_id_track *tk, int k, const double *s, int *j,
                        double *tau, double *kper, double *Z, double *C);
/* The halves (tk->halves) a channel of order 0, 1, 2 needs. */
int vi_id_halves(int order);
/* The accelerations x'' [N x k rep] (leading dimension N) of m in the
 * states Z [2N x k rep] (leading dimension 2N), columns i rep .. i rep +
 * rep - 1 at the time t[i], i < k: vi_var_field's velocity half for a
 * block (the same sums). */
void vi_id_accel_block(const vi_model *m, int k, int rep, const double *t,
                       const double *Z, double *F);

/* The held shift (vi_identify_set_shift) from the record's start; NaN if
 * none. */
static inline double vi_id_shift0(const vi_identify *id)
{
  return id->shift0 + id->tref;
}

/* A key with no natural range (not Omega, x_s or r), a positive start and
 * an open side: its starts may be widened (vi_identify.c, widen_retry). */
static inline int vi_id_open_key(const vi_identify *id, int j)
{
  return id->kind[j] == VI_IDENTIFY_OTHER && id->p0[j] > 0.0 &&
         (!isfinite(id->lo[j]) || !isfinite(id->hi[j]));
}

/* vi_identify_seed.c */
int vi_id_data_period(vi_identify *id, double T);
/* The recording's own period in time units, without the model (for a
 * fitted forcing frequency), searched up to pmax (and 1 / 1.5 of the
 * span): the first lag it repeats over, or the smallest multiple of it
 * up to MAX_N that repeats as well as the best; 0 with errmsg set where
 * there is none. */
double vi_id_data_lag(vi_identify *id, double pmax);
double vi_id_scan_shift(vi_identify *id, double *cost_out);
int vi_id_choose_orbit(vi_identify *id, int nd, double *cost);
/* The best orbit of each type at the current model, slots: m = 1, m = 2,
 * more impacts (the transient's); cost HUGE_VAL where none.  best[]'s
 * buffers are the caller's (vi_id_orb_alloc). */
#define VI_ID_SLOTS 3
int vi_id_orbit_types(vi_identify *id, int nd, orb *best, double *cost);

/* vi_identify_scan2.c: every P(nd, 2) orbit on one stop (admissibility
 * and stability not checked) into out [cap] (buffers the caller's). */
int vi_id_scan_p2(vi_identify *id, int nd, orb *out, int cap, int *found);

/* vi_identify_stats.c */
double vi_id_noise_estimate(const vi_identify *id, double P);
/* The recording folded with period P: the robust spread of each sample
 * about the line through its neighbours in phase (the noise where P is
 * its period); NaN where the neighbours are not much closer in phase
 * than successive samples. */
double vi_id_fold(const vi_identify *id, double P);
/* The period near P (within about W) over which the recording folds
 * best in RMS, that RMS into *rms (NaN where it does not fold): a
 * record's period to a fraction of a sample over its whole span, where
 * the lag between its samples' interpolants is known only to a sample
 * (an accelerometer out of step with the forcing); P where nothing folds
 * clearly better.  P and NaN where the best RMS over a part of the record
 * exceeds limit. */
double vi_id_fold_period(const vi_identify *id, double P, double W, double limit,
                         double *rms);
int vi_id_uncertainty(vi_identify *id, const gsl_matrix *J, double ssr);
void vi_id_energy_route(vi_identify *id);

/* vi_identify_fit.c */
int vi_id_lm(vi_identify *id, const double *p, double t0, double *pout,
             double *t0out, double *ssr, int *iters, int *conv);
int vi_id_local(vi_identify *id, const double *p, double t0, vi_id_sol *s);
void vi_id_hold(vi_identify *id, int j, double v);

/* vi_identify_global.c */
int vi_id_global(vi_identify *id, int nd);
/* Rank the minima s [*n] (best first, repeats dropped, *n updated) and
 * count in id those the data cannot tell from the best (nfound, unique,
 * the separations). */
void vi_id_rank(vi_identify *id, vi_id_sol *s, int *n);
int vi_id_profile(vi_identify *id, vi_id_sol *s);

#endif
