/* vi_sim_internal.h - the driver's view (vi_sim.c and its settings,
 * vi_sim_io.c): the simulator's layers from the bottom up.  Only the
 * driver includes it; the parts below include what they use and never the
 * driver. */
#ifndef VI_SIM_INTERNAL_H
#define VI_SIM_INTERNAL_H

#include "vi_chatter_internal.h"
#include "vi_exact_internal.h"
#include "vi_force_internal.h"
#include "vi_rhs.h"
#include "vi_sim_state.h"

/* Drop the backend (and a parked one) so the next run rebuilds it for the
 * current method and tolerances (vi_sim.c). */
void vi_sim_backend_reset(vi_sim *s);
/* Which method runs, and the run's note saying why (vi_sim.c). */
void vi_sim_note_method(vi_sim *s);

#endif
