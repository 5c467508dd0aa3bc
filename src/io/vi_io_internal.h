/* vi_io_internal.h - helpers shared by the files of libvibroimpact_scene and
 * libvibroimpact_h5; never installed.
 *
 * Header-only on purpose: each library hides its non-API symbols, so a
 * helper both use cannot live in a .c of one of them. */
#ifndef VI_IO_INTERNAL_H
#define VI_IO_INTERNAL_H

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "vibroimpact/vi_scene.h"
#include "vibroimpact/vi_status.h"

static inline int vi_diag_set(vi_diag *d, const char *file, int code,
                              int line, int col, const char *key,
                              const char *value, const char *fmt, ...)
    __attribute__((format(printf, 8, 9)));

/* Fill *d (NULL: nothing) with where and why; returns code, so that a
 * failure reads `return vi_diag_set(d, ...)`. */
static inline int vi_diag_set(vi_diag *d, const char *file, int code,
                              int line, int col, const char *key,
                              const char *value, const char *fmt, ...)
{
  if (!d) return code;
  memset(d, 0, sizeof *d);
  d->code = code;
  d->line = line;
  d->column = col;
  snprintf(d->file, sizeof d->file, "%s", file ? file : "");
  snprintf(d->key, sizeof d->key, "%s", key ? key : "");
  snprintf(d->value, sizeof d->value, "%s", value ? value : "");
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(d->message, sizeof d->message, fmt, ap);
  va_end(ap);
  return code;
}

/* Out of memory, with no place in the input to name. */
static inline int vi_diag_nomem(vi_diag *d, const char *file)
{
  return vi_diag_set(d, file, VI_ERR_NOMEM, 0, 0, "", "", "%s",
                     "out of memory");
}

#endif
