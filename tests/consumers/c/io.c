/* Outside consumer of the I/O libraries: the embedded Fig. 2 scene read by
 * libvibroimpact_scene, its model set up, and the header of an HDF5 file
 * written by libvibroimpact_h5 (the path: argv[1]).  With SCENE_ONLY it
 * links the scene library alone (no HDF5).  Prints "ok" and exits 0. */
#include <stdio.h>

#include <vibroimpact.h>
#include <vibroimpact/vi_scene.h>
#ifndef SCENE_ONLY
#include <vibroimpact/vi_writer.h>
#endif

int main(int argc, char **argv)
{
  vi_scene *sc = NULL;
  vi_model *m = NULL;
  vi_diag d;
  if (vi_scene_parse(vi_scene_default_text(), -1, "fig2", &sc, &d) ||
      vi_scene_create_model(sc, &m, &d)) {
    fprintf(stderr, "%s\n", d.message);
    return 1;
  }
  /* Fig. 2 is the two-mass chain: n = 2 */
  int ok = vi_scene_n(sc) == 2 && vi_model_n(m) == 2;
#ifndef SCENE_ONLY
  vi_writer *w = NULL;
  ok = ok && argc > 1 && !vi_writer_create(argv[1], m, 0, &w, &d) &&
       !vi_writer_write_header(w, sc, vi_scene_rtol(sc), vi_scene_atol(sc),
                               vi_scene_method(sc)) &&
       !vi_writer_close(&w, 1);
  if (w) vi_writer_abort(&w);
#else
  (void)argc;
  (void)argv;
#endif
  vi_model_destroy(&m);
  vi_scene_destroy(&sc);
  puts(ok ? "ok" : "FAILED");
  return ok ? 0 : 1;
}
