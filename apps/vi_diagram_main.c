/* vi_diagram_main.c - vibroimpact-sweep: the `sweep` subcommand as its own
 * program, which `vibroimpact sweep ...` runs in its place (execv, same
 * process: mpirun sees the same ranks), so that HDF5, OpenMP and MPI are
 * loaded only by sweeps. */
#include <stdio.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "vibroimpact.h"
#include "vi_diagram.h"
#include "vi_app_blas.h"

int main(int argc, char **argv)
{
  vi_app_blas_rest();
  gsl_set_error_handler_off();
  if (vi_version_number() != VI_VERSION_NUMBER) {
    fprintf(stderr, "vibroimpact-sweep: header %s and library %s differ\n",
            VI_VERSION_STRING, vi_version_string());
    return 1;
  }
  /* argv[0] stands for the subcommand, as in `vibroimpact sweep` */
  return vi_cmd_sweep_main(argc, argv);
}
