/** @file vibroimpact.h
 * simulate multi-degree-of-freedom vibro-impact systems.
 *
 * Linear structures M x'' + C x' + K x = f(t) driven against a one-sided stop
 * w.x <= x_s with a Newton restitution law, after D. J. Wagg and S. R. Bishop,
 * J. Sound Vib. 236(1):176-184 (2000).  See MODEL.md for notation.
 *
 * The library never prints and never exits.  It uses GSL but leaves GSL's
 * process-wide error handler alone; it never passes GSL invalid input, but a
 * host program should still call gsl_set_error_handler_off() once.
 *
 * Conventions of the whole API:
 * - Handles are opaque, made by vi_OBJ_create(..., &out) and released by
 *   vi_OBJ_destroy(&h) (NULL-safe).  Every function that can fail returns
 *   a vi_status code and leaves a message in vi_OBJ_errmsg().
 * - Queries are named vi_OBJ_NOUN, without "get": one returning a single
 *   value returns it (vi_model_n, vi_sim_stat); one filling caller-owned
 *   arrays returns a status (vi_sim_state, vi_sim_ledger, vi_model_stop).
 *   Settings are vi_OBJ_set_NOUN.
 * - Arrays are the caller's, column-major, with a leading dimension where
 *   they are matrices (LAPACK's convention).
 * - A callback setter takes its settings first, then the callback(s), the
 *   user pointer and a vi_destroy_fn for the user data (NULL: the host keeps
 *   it):  vi_sim_set_sampling(sim, dt, fn, user, destroy).  On an error
 *   nothing is taken over. */
#ifndef VIBROIMPACT_H
#define VIBROIMPACT_H

#include "vibroimpact/vi_version.h"
#include "vibroimpact/vi_status.h"
#include "vibroimpact/vi_model.h"
#include "vibroimpact/vi_builders.h"
#include "vibroimpact/vi_sparse.h"
#include "vibroimpact/vi_impact.h"
#include "vibroimpact/vi_flow.h"
#include "vibroimpact/vi_sim.h"
#include "vibroimpact/vi_ledger.h"
#include "vibroimpact/vi_force.h"
#include "vibroimpact/vi_orbit.h"
#include "vibroimpact/vi_param.h"
#include "vibroimpact/vi_study.h"
#include "vibroimpact/vi_cont.h"
#include "vibroimpact/vi_cont_curve.h"
#include "vibroimpact/vi_truncation.h"
#include "vibroimpact/vi_census.h"
#include "vibroimpact/vi_identify.h"

#endif
