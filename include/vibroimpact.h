/** @file vibroimpact.h
 * simulate multi-degree-of-freedom vibro-impact systems.
 *
 * Linear structures M x'' + C x' + K x = f(t) driven against a one-sided stop
 * w.x <= x_s with a Newton restitution law, after D. J. Wagg and S. R. Bishop,
 * J. Sound Vib. 236(1):176-184 (2000).  See MODEL.md for notation.
 *
 * The library never prints and never exits.  It uses GSL but leaves GSL's
 * process-wide error handler alone; it never passes GSL invalid input, but a
 * host program should still call gsl_set_error_handler_off() once. */
#ifndef VIBROIMPACT_H
#define VIBROIMPACT_H

#include "vibroimpact/vi_version.h"
#include "vibroimpact/vi_status.h"
#include "vibroimpact/vi_model.h"
#include "vibroimpact/vi_builders.h"
#include "vibroimpact/vi_impact.h"
#include "vibroimpact/vi_flow.h"
#include "vibroimpact/vi_sim.h"
#include "vibroimpact/vi_ledger.h"
#include "vibroimpact/vi_force.h"
#include "vibroimpact/vi_orbit.h"

#endif
