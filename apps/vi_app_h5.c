/* vi_app_h5.c - the HDF5 writer, loaded only when a command writes a file.
 * libvibroimpact_io links HDF5, which brings 34 shared libraries (curl,
 * gnutls, ...): loading them costs more start-up time than a whole Fig. 2
 * run with the exact method.  So the program carries its own scene reader
 * and opens the I/O library with dlopen on the first -o. */
#include <dlfcn.h>
#include <stdio.h>
#include <string.h>

#include "vi_app.h"

#ifndef VI_IO_SONAME
#define VI_IO_SONAME "libvibroimpact_io.so.1"
#endif

const app_writer_api *vi_app_writer(void)
{
  static app_writer_api api;
  static int state; /* 0 not tried, 1 loaded, -1 failed */
  if (state) return state > 0 ? &api : NULL;
  state = -1;
  /* first beside libvibroimpact (installed side by side, and the build
   * tree): a sanitizer's dlopen interceptor would not search our RUNPATH */
  void *h = NULL;
  Dl_info info;
  union { int (*f)(void); void *p; } core = {vi_version_number};
  if (dladdr(core.p, &info) && info.dli_fname) {
    const char *slash = strrchr(info.dli_fname, '/');
    if (slash) {
      char lib[4096];
      snprintf(lib, sizeof lib, "%.*s/%s", (int)(slash - info.dli_fname),
               info.dli_fname, VI_IO_SONAME);
      h = dlopen(lib, RTLD_NOW | RTLD_LOCAL);
    }
  }
  if (!h) h = dlopen(VI_IO_SONAME, RTLD_NOW | RTLD_LOCAL);
  if (!h) {
    fprintf(stderr, "vibroimpact: cannot load the HDF5 writer: %s\n",
            dlerror());
    return NULL;
  }
  /* a function pointer from dlsym's void * goes through a union: ISO C
   * has no conversion between the two */
#define SYM(field, name)                                                     \
  do {                                                                       \
    union { void *p; __typeof__(api.field) f; } u;                           \
    u.p = dlsym(h, name);                                                    \
    if (!u.p) {                                                              \
      fprintf(stderr, "vibroimpact: %s lacks %s\n", VI_IO_SONAME, name);     \
      return NULL;                                                           \
    }                                                                        \
    api.field = u.f;                                                         \
  } while (0)
  SYM(create, "vi_writer_create");
  SYM(write_header, "vi_writer_write_header");
  SYM(event, "vi_writer_event");
  SYM(sample, "vi_writer_sample");
  SYM(ledger, "vi_writer_ledger");
  SYM(orbit, "vi_writer_orbit");
  SYM(run_info, "vi_writer_run_info");
  SYM(rows, "vi_writer_rows");
  SYM(finish, "vi_writer_finish");
  SYM(abort, "vi_writer_abort");
  SYM(errmsg, "vi_writer_errmsg");
  SYM(fe_shapes, "vi_writer_fe_shapes");
#undef SYM
  state = 1;
  return &api;
}
