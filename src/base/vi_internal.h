/* vi_internal.h - private helpers of every layer (messages, small dense
 * kernels, overlap tests); never installed.  The model's definition is in
 * model/vi_model_internal.h, out of reach of this layer. */
#ifndef VI_INTERNAL_H
#define VI_INTERNAL_H

#include <stddef.h>

#include "vibroimpact.h"

#define VI_MSG_LEN 512

/* Format a message into a fixed buffer (truncating) and return code, so that
 * a check reads  if (bad) return vi_fail(m->errmsg, VI_ERR_X, "...", ...); */
int vi_fail(char *buf, int code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* PetscCheck-style: on a false condition record the message, set `st` and
 * leave through the function's single cleanup label. */
#define VI_CHECK(cond, buf, code, ...)          \
  do {                                          \
    if (!(cond)) {                              \
      st = vi_fail((buf), (code), __VA_ARGS__); \
      goto cleanup;                             \
    }                                           \
  } while (0)

/* Cholesky of a small SPD k x k matrix in place (0, or -1 if a pivot is
 * lost to round-off) and the solve with its factor (vi_dense.c). */
int vi_small_cholesky(int k, double *A);
void vi_small_solve(int k, const double *L, double *b);
/* Dense helpers, column-major with leading dimension n (vi_dense.c). */
void vi_matvec(int n, const double *A, const double *x, double *y); /* y = A x */
void vi_matvec_t(int n, const double *A, const double *x, double *y); /* y = A^T x */
double vi_dot(int n, const double *x, const double *y);
/* Hand a callback's user data over: the data it replaces is destroyed
 * (unless it is the same pointer), the new one is kept with its destroy
 * function.  vi_user_set(&p, &f, NULL, NULL) at destroy time frees it. */
static inline void vi_user_set(void **slot, vi_destroy_fn *fslot, void *user,
                               vi_destroy_fn destroy)
{
  if (*fslot && *slot != user) (*fslot)(*slot);
  *slot = user;
  *fslot = destroy;
}

/* The x in [a, b] where f(ctx, x) is least, its value into *fx (if not
 * NULL), by golden section until the bracket is within tol or after maxit
 * steps; f unimodal there (vi_minimize.c). */
double vi_golden_min(double (*f)(void *ctx, double x), void *ctx, double a, double b,
                     double tol, int maxit, double *fx);

/* 1 if the arrays [n] at a and b share memory (the API forbids it where an
 * output would overwrite an input still being read). */
static inline int vi_overlap(const double *a, const double *b, int n)
{
  return a && b && a < b + n && b < a + n;
}
/* The same for arrays of different lengths, a [na] and b [nb]. */
static inline int vi_overlap2(const double *a, size_t na, const double *b,
                              size_t nb)
{
  return a && b && a < b + nb && b < a + na;
}

#endif
