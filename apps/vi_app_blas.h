/* vi_app_blas.h - the programs' first act: OpenBLAS's thread pool put to
 * rest until a product large enough to use it.
 *
 * OpenBLAS (its pthreads build, Debian's default BLAS where installed)
 * starts one worker per core when it is loaded, and each worker spins in
 * sched_yield for about 2^28 cycles (0.1 s) before it sleeps.  A run of a
 * small model is over well inside that time, so it ran beside every spinning
 * worker (issue 29: a 2-dof run on 16 cores).  At the start of main no BLAS
 * call is in flight, so the pool can be shut down there, exactly as
 * OpenBLAS does itself before every fork(); it starts again by itself at
 * the first call large enough to be split over threads (a small model makes
 * none).  Another BLAS has no such symbol: nothing is done.  Only the
 * programs do this: a library cannot know that no other thread of its host
 * is inside BLAS. */
#ifndef VI_APP_BLAS_H
#define VI_APP_BLAS_H

#include <dlfcn.h>

static inline void vi_app_blas_rest(void)
{
  void *sym = dlsym(RTLD_DEFAULT, "blas_thread_shutdown_");
  int (*shutdown)(void) = NULL;
  if (!sym) return;
  /* a data pointer to a function pointer: POSIX guarantees dlsym's */
  *(void **)&shutdown = sym;
  (void)shutdown();
}

#endif
