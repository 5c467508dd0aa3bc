/* vi_cmd_orbits.c - `vibroimpact orbits`: P(n,m) orbits found by Newton. */
#include <stdio.h>

#include "vi_sweep.h"

int vi_cmd_orbits_main(int argc, char **argv)
{
  (void)argc;
  (void)argv;
  fprintf(stderr, "vibroimpact: orbits: not yet implemented\n");
  return 2;
}
