/* fuzz_scene.c - libFuzzer target: a scene's text through the reader,
 * the range checks, model building and a short run.  Any crash, leak,
 * sanitizer report or hang is a bug; every rejection must come with a
 * diagnostic.  Models are kept small (n <= 40) and runs short so that the
 * fuzzer spends its time on the reader. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "vibroimpact.h"
#include "vibroimpact/vi_scene.h"

static int polls;
static int cancel_after(void *user)
{
  (void)user;
  return ++polls > 20000; /* bounds the run's work, not its time */
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  static int init;
  if (!init) {
    gsl_set_error_handler_off();
    init = 1;
  }
  vi_scene *sc = NULL;
  vi_model *m = NULL;
  vi_sim *s = NULL;
  vi_diag d;
  char msg[1200];
  int st = vi_scene_parse((const char *)data, (long)size, "fuzz", &sc, &d);
  if (st) {
    if (!d.message[0]) abort(); /* a rejection without a reason */
    vi_diag_format(&d, msg, sizeof msg);
    return 0;
  }
  if (vi_scene_n(sc) > 40 || vi_scene_check_memory(sc, 64.0 * 1024 * 1024, &d)) {
    vi_scene_destroy(&sc);
    return 0;
  }
  st = vi_scene_create_model(sc, &m, &d);
  if (!st) st = vi_sim_create(m, &s);
  if (!st) st = vi_scene_configure_sim(sc, s, &d);
  if (!st) {
    polls = 0;
    vi_sim_set_cancel(s, cancel_after, NULL, NULL);
    double t0 = vi_scene_t0(sc), t1 = vi_scene_t_end(sc);
    vi_sim_run(s, t0 + (t1 - t0 < 1.0 ? t1 - t0 : 1.0));
  }
  vi_sim_destroy(&s);
  vi_model_destroy(&m);
  vi_scene_destroy(&sc);
  return 0;
}
