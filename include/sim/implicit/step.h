/* step.h: the implicit scheme's step driver, internal to the implicit room
 * (rod_scheme_implicit's step and refresh: scheme_implicit.c). A step is
 * the start (start.h), Newton (newton.h), the strands' no-pass-through test
 * and the acceptance (accept.h); a step whose Newton iteration fails is
 * split in two, recursively, and with contact retried with finite
 * differences, before it gives up. */
#ifndef RODSIM_SIM_IMPLICIT_STEP_H
#define RODSIM_SIM_IMPLICIT_STEP_H

#include "sim/implicit/work.h"

/* rod_scheme_ops.step: s advanced by dt (s restored and a message set when
 * the step fails). */
rod_status implicit_step(implicit_work *w, const rod_model *m, rod_state *s, double dt,
                         rod_report *report);

/* rod_scheme_ops.refresh, between steps: a stale factorisation (newton.c's
 * IDLE_REFRESH_CONTRACTION) renewed for the next step of dt from s, at that
 * step's first iterate, by that step's own preparation, so that the step
 * need not rebuild it on its own time (live mode, between lines; a loop of
 * steps leaves it to the step, which then spares an evaluation). Only when
 * continuing a run of steps (s is read, not changed) and while the last
 * step had no self-contact candidates (the pairs and their forces are the
 * step's own: none are sought here). Returns 1 when renewed, 0 when not
 * needed, -1 when the matrix is singular. */
int implicit_refresh(implicit_work *w, const rod_model *m, const rod_state *s, double dt);

#endif
