/** @file vi_status.h
 * status codes shared by every vibroimpact call.
 *
 * 0 is success, positive codes are normal stops, negative codes are errors.
 * The enum, vi_status_name() and vi_strerror() are generated from one list so
 * they cannot disagree. */
#ifndef VI_STATUS_H
#define VI_STATUS_H

#include "vibroimpact/vi_export.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The status codes as an X-macro list X(name, value, message): the single
 *  source of the enum, vi_status_name(), vi_strerror() and the Fortran
 *  constants.  0 is success, positive a normal stop, negative an error. */
#define VI_STATUS_LIST(X)                                                    \
  X(VI_OK,                    0, "success")                                  \
  X(VI_STOPPED,               1, "stopped by a user callback")               \
  X(VI_CANCELLED,             2, "cancelled through the cancellation callback") \
  X(VI_ERR_ARG,              -1, "invalid argument")                         \
  X(VI_ERR_DIM,              -2, "dimension or leading-dimension mismatch")  \
  X(VI_ERR_NONFINITE,        -3, "NaN or Inf in the input")                  \
  X(VI_ERR_NOT_SYMMETRIC,    -4, "matrix not symmetric")                     \
  X(VI_ERR_NOT_SPD,          -5, "matrix not positive definite")             \
  X(VI_ERR_NOT_PSD,          -6, "matrix not positive semidefinite")         \
  X(VI_ERR_RESTITUTION,      -7, "coefficient of restitution outside [0, 1]") \
  X(VI_ERR_STOP_VECTOR,      -8, "stop vector w is zero")                    \
  X(VI_ERR_FREQUENCY,        -9, "forcing frequency must be positive")       \
  X(VI_ERR_INITIAL_STATE,   -10, "initial state violates the stop")          \
  X(VI_ERR_TIME,            -11, "end time not after the current time")      \
  X(VI_ERR_TOLERANCE,       -12, "tolerances must be positive and finite")   \
  X(VI_ERR_STATE,           -13, "call out of order for this object")       \
  X(VI_ERR_NOMEM,           -14, "out of memory")                            \
  X(VI_ERR_LAPACK,          -15, "LAPACK failure")                           \
  X(VI_ERR_INTEGRATOR,      -16, "integrator failure (CVODE or ARKODE)")      \
  X(VI_ERR_UNSUPPORTED,     -17, "not supported for this model")             \
  X(VI_ERR_ROOT,            -18, "event location failed")                    \
  X(VI_ERR_NOT_CONVERGED,   -19, "iteration did not converge")               \
  X(VI_ERR_IO,              -20, "input/output failure")                     \
  X(VI_ERR_PARSE,           -21, "malformed input file")                    \
  X(VI_ERR_INVARIANT,       -22, "physical invariant violated (state beyond " \
                                 "the stop or not finite)")                  \
  X(VI_ERR_LIMIT,           -23, "size or resource limit exceeded")        \
  X(VI_ERR_CALLBACK,        -24, "a host callback reported a failure")

/// @cond INTERNAL
#define VI_STATUS_ENUM_(name, value, msg) name = (value),
/// @endcond
/** Status of every call (values and messages: VI_STATUS_LIST). */
typedef enum vi_status { VI_STATUS_LIST(VI_STATUS_ENUM_) } vi_status;
#undef VI_STATUS_ENUM_

/** Symbolic name of a code ("VI_ERR_NOT_SPD"); "VI_UNKNOWN" for others. */
VI_API const char *vi_status_name(int code);
/** Fixed English message for a code; never NULL. */
VI_API const char *vi_strerror(int code);

#ifdef __cplusplus
}
#endif
#endif
