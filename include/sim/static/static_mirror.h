/* static_mirror.h: internal to the static scheme's room (static_internal.h).
 * A free root with a held tip, and a sliding root with a tip held in place,
 * are solved as the mirrored rod (node i <-> NS-1-i), whose root is held. */
#ifndef RODSIM_STATIC_MIRROR_H
#define RODSIM_STATIC_MIRROR_H

#include <stddef.h>

#include "sim/rod.h"
#include "sim/rod_types.h"
#include "sim/scheme_static.h"

/* The work of a mirrored rod (w->mirror set, owning the mirror's model,
 * state and inner work), or NULL with a message for ends the mirror does
 * not solve. Freed by static_mirror_destroy. */
static_work *static_mirror_create(const rod_model *m, char *err, size_t errlen);

/* One step of the mirrored rod, its answer mirrored back into s. */
rod_status static_mirror_step(static_work *w, const rod_model *m, rod_state *s, double dt,
                              rod_report *report);

/* Frees the mirror, then the work itself (static_work_destroy, which
 * frees only what static_work_create makes); NULL: nothing. */
void static_mirror_destroy(static_work *w);

#endif
