/* vi_app.h - shared pieces of the vibroimpact program. */
#ifndef VI_APP_H
#define VI_APP_H

#include <signal.h>

#include "vibroimpact.h"
#include "vibroimpact/vi_scene.h"
#include "vibroimpact/vi_writer.h"

typedef struct app_opts {
  const char *scene;  /* NULL: the embedded default (Fig. 2) */
  const char *out;    /* -o FILE.h5 */
  const char *csv;    /* --impacts-csv FILE or - */
  double rtol, atol, periods; /* <= 0: from the scene */
  int method;         /* -1: from the scene */
  int quiet, json, progress;
} app_opts;

/* Set by SIGINT / SIGTERM; the monitors return it to stop the run. */
extern volatile sig_atomic_t vi_app_interrupted;

/* Load the scene (or the default) with the command-line overrides and build
 * its model; prints the diagnostic and returns an exit status on failure. */
int vi_app_load(const app_opts *o, vi_scene **scene, vi_model **model);

int vi_cmd_run(const app_opts *o);
int vi_cmd_energy(const app_opts *o);

#endif
