/* static_continuation.h: internal to the static scheme's room
 * (static_internal.h). One static step of a rod whose root is held. */
#ifndef RODSIM_STATIC_CONTINUATION_H
#define RODSIM_STATIC_CONTINUATION_H

#include "sim/static/static_internal.h"

/* The equilibrium under the loads at s->time + dt, from state s, written
 * into s (rod_scheme_ops.step for a rod that is not mirrored). On failure s
 * is left as it was and the report says why. */
rod_status static_step_unmirrored(static_work *w, const rod_model *m, rod_state *s, double dt,
                                  rod_report *report);

#endif
