/* vi_app_h5.c - the HDF5 writer's functions for the commands.
 * The program links libvibroimpact_h5 like any other consumer; the commands
 * reach the writer through this table (vi_app.h) and the truncation
 * study's writer by name. */
#include <stdio.h>
#include <string.h>

#include "vi_app.h"
#include "vibroimpact/vi_truncation_io.h"

static const app_writer_api writer_api = {
    vi_writer_create,   vi_writer_write_header, vi_writer_event,
    vi_writer_sample,   vi_writer_ledger,       vi_writer_orbit,
    vi_writer_run_info, vi_writer_rows,         vi_writer_finish,
    vi_writer_abort,    vi_writer_errmsg,       vi_writer_fe_shapes};

const app_writer_api *vi_app_writer(void) { return &writer_api; }

void *vi_app_io_symbol(const char *name)
{
  /* a function pointer becomes a void * through a union: ISO C has no
   * conversion between the two */
  union { int (*trunc)(const char *, const char *, const char *,
                       const double *, const double *, int, const double *,
                       int, vi_diag *);
          void *p; } u;
  if (name && !strcmp(name, "vi_truncation_write_h5"))
    u.trunc = vi_truncation_write_h5;
  else {
    fprintf(stderr, "vibroimpact: no HDF5 writer %s\n", name ? name : "");
    return NULL;
  }
  return u.p;
}
