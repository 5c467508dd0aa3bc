/* vi_app_fe.c - what the reduction of a finite-element scene did, as the
 * commands report it: a summary line and a JSON member (vi_app.h).  A
 * model is never cut or changed without the run saying so. */
#include <stdio.h>

#include "vi_app.h"

static const char *rule_words(int rule)
{
  return rule == VI_FE_MODES_GIVEN ? "as model.modes asks"
         : rule == VI_FE_MODES_WHOLE ? "the whole model: no model.modes"
                                     : "the host's modes";
}

void vi_app_fe_report(FILE *f, const vi_scene *sc)
{
  int k, rule, nz, nr;
  double res, orth;
  if (vi_scene_fe_summary(sc, &k, &rule, &nz, &nr, &res, &orth)) return;
  fprintf(f, "  reduction %d of %d modes (%s); %d rigid (K psi at round-off)"
          ", %d massless dofs; residuals <= %.2g, M-orthonormal to %.2g\n",
          k, vi_scene_dofs(sc) - nz, rule_words(rule), nr, nz, res, orth);
}

void vi_app_fe_json(FILE *f, const vi_scene *sc)
{
  int k, rule, nz, nr;
  double res, orth;
  if (vi_scene_fe_summary(sc, &k, &rule, &nz, &nr, &res, &orth)) return;
  fprintf(f, "\"fe\": {\"dofs\": %d, \"modes\": %d, \"finite_modes\": %d, "
          "\"modes_rule\": \"%s\", \"rigid\": %d, \"massless\": %d, "
          "\"max_residual\": %.3g, \"orthogonality\": %.3g}, ",
          vi_scene_dofs(sc), k, vi_scene_dofs(sc) - nz,
          rule == VI_FE_MODES_GIVEN ? "given" : rule == VI_FE_MODES_WHOLE
                                                    ? "whole" : "host",
          nr, nz, res, orth);
}
