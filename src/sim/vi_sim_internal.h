/* vi_sim_internal.h - the driver's view (vi_sim.c): the simulator's
 * layers from the bottom up.  Only the driver includes it; the parts below
 * include what they use and never the driver. */
#ifndef VI_SIM_INTERNAL_H
#define VI_SIM_INTERNAL_H

#include "vi_chatter_internal.h"
#include "vi_exact_internal.h"
#include "vi_force_internal.h"
#include "vi_rhs.h"
#include "vi_sim_state.h"

#endif
