/* accept.h: a converged implicit step taken into the state, internal to the
 * implicit room. */
#ifndef RODSIM_SIM_IMPLICIT_ACCEPT_H
#define RODSIM_SIM_IMPLICIT_ACCEPT_H

#include "sim/implicit/work.h"

/* The solution in w->x of the step of dt written into s (frames, strains,
 * centreline, velocities, forces, supports' loads, punctures; s->time moves
 * on by dt), and kept as the next step's start (continuing: the step
 * continued the last, implicit_prepare_step). Returns 0, or -2
 * (report->message set) when the needle's new hole finds no room; s is then
 * half written (the caller restores it). */
int implicit_accept_step(implicit_work *w, const rod_model *m, rod_state *s, double dt,
                         int continuing, rod_report *report);

#endif
