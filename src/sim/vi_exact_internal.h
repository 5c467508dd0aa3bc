/* vi_exact_internal.h - the pieces of the exact method (vi_exact*.c): the
 * grid backend of vi_exact.c (ex_*) and the scan of vi_exact_scan.c (sc_*)
 * share what is declared here and no names besides (the ledger's
 * quadrature rule, vi_gl8_node, is vi_ledger_internal.h's). */
#ifndef VI_EXACT_INTERNAL_H
#define VI_EXACT_INTERNAL_H

#include "vi_flow_internal.h"
#include "vi_held_internal.h"
#include "vi_sim_state.h"

/* The step-by-step scan of the closed form (vi_exact_scan.c): the exact
 * method for non-proportional damping. */
extern const vi_backend vi_backend_exact_scan;

/* The first member of either backend's data says which it is. */
enum { EX_KIND_SCAN = 1, EX_KIND_FAST = 2 };

#endif
