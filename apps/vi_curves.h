/* vi_curves.h - `vibroimpact curves` (vi_cmd_curves.c): the curve as
 * collected, and its HDF5 file (vi_curves_h5.c). */
#ifndef VI_CURVES_H
#define VI_CURVES_H

typedef struct vi_curve_result {
  double located, located2; /* the codimension-one point first located */
  int npts, cap;
  double *pts;              /* [npts][2]: key, key2 along the curve */
  int nsp, spcap;
  int *sp_type, *sp_loc;    /* vi_cont_special_type; 1 solved, 0 interpolated */
  double *sp_pts;           /* [nsp][2] */
  int state, start;         /* vi_cont_curve_state at the end, at the start */
} vi_curve_result;

/* Append a point / a special point; 0, or 1 out of memory. */
int vi_curve_result_add(vi_curve_result *r, double p, double p2);
int vi_curve_result_special(vi_curve_result *r, int type, double p, double p2, int located);
void vi_curve_result_free(vi_curve_result *r);
/* "end of range", "not admissible beyond", ... for a vi_cont_curve_state */
const char *vi_curve_end_name(int state);
/* The curve to OUT.h5 (through OUT.h5.part); 0, or 1 with err set.
 * Layout (doc/curves.md): root attribute kind = "curves"; /curve/points [npts x 2], /curve/special_points
 * [nsp x 2], /curve/special_type [nsp] (names in the attribute
 * special_types), /curve/special_located [nsp]; attributes kind, param,
 * param2, orbit_n, orbit_m, located [2], start, end. */
int vi_curves_write_h5(const char *path, const char *kind, const char *key,
                       const char *key2, int n, int m, const vi_curve_result *r,
                       char *err, int errlen);

#endif
