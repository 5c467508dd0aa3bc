/* vi_period.h - the time of P forcing periods, P 2 pi / W: the one place
 * the project writes the period out.  A header of its own, with no
 * dependency, so that the scene library and the program (which see src/
 * but not the core's internals) take the same expression as the core
 * (vi_forcing_period, model/vi_forcing.h): a run's end time and a model's
 * period then agree to the bit. */
#ifndef VI_PERIOD_H
#define VI_PERIOD_H

#include <math.h>

/* P periods of the frequency W, evaluated as (P 2) pi / W: P = 1 gives
 * 2 pi / W exactly (1 x 2 is exact). */
static inline double vi_periods_time(double P, double W)
{
  return P * 2 * M_PI / W;
}

#endif
