/* static_work.h: internal to the static scheme's room (static_internal.h).
 * static_work_create and static_work_destroy (scheme_static.h) make and free
 * the scheme's scratch memory; these helpers of theirs serve the room too. */
#ifndef RODSIM_STATIC_WORK_H
#define RODSIM_STATIC_WORK_H

#include "sim/rod.h"
#include "sim/rod_types.h"
#include "sim/scheme_static.h"

/* out = v / |v|; returns 1, or 0 with out = 0 when v is zero, -1 when v is
 * not finite. */
int static_unit_or_zero(const double v[3], double out[3]);

/* The held ends' initial poses from a state at t = 0: position (nodes x 3,
 * m) and frame (nodes x 9), as rod_state_reset builds them. */
void static_set_initial_ends(static_work *w, const double *position, const double *frame);

/* 1 when a force acts on a rod pinned at node `pinned` (0 or NS-1) off the
 * pin, so that the loads decide its direction about the pin. */
int static_swing_determined(const rod_model *m, int pinned);

#endif
