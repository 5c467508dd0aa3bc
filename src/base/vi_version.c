/* vi_version.c - run-time version, to check against the header's. */
#include <sundials/sundials_config.h>

#include "vi_internal.h"

int vi_version_number(void) { return VI_VERSION_NUMBER; }
const char *vi_version_string(void) { return VI_VERSION_STRING; }
const char *vi_sundials_version(void) { return SUNDIALS_VERSION; }
