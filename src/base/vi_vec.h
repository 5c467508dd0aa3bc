/* vi_vec.h - two doubles at once (GCC/Clang vector extensions: SSE2 on
 * x86-64, NEON on aarch64) for the closed forms' loops over modes, which
 * GCC's own vectoriser leaves scalar (sums) or spills (SLP).  Loops that
 * use it keep four partial sums, lane u taking the modes i = u mod 4 and
 * combined as (s0 + s1) + (s2 + s3): the adds of one sum do not chain. */
#ifndef VI_VEC_H
#define VI_VEC_H

#include <string.h>

typedef double vi_v2 __attribute__((vector_size(16)));

static inline vi_v2 vi_v2_ld(const double *p)
{
  vi_v2 v;
  memcpy(&v, p, sizeof v);
  return v;
}

static inline void vi_v2_st(double *p, vi_v2 v) { memcpy(p, &v, sizeof v); }

/* (s0 + s1) + (s2 + s3) of the pair of pairs s */
static inline double vi_v2_sum4(const vi_v2 s[2])
{
  return (s[0][0] + s[0][1]) + (s[1][0] + s[1][1]);
}

#endif
