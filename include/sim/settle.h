/* settle.h: a scene's thread let settle from its drawn shape before t = 0
 * ([rod] settle). A shape drawn by hand or by a formula (a knot from a
 * polynomial, a thread laid along a path) is seldom at rest: released, its
 * strands snap toward a shape they can hold, at metres per second for the
 * first tens of milliseconds, and those steps are the run's slowest (split
 * 4-8 ways, 3-9 Newton iterations each: a live session's slowest answers).
 * With settle = T the thread moves T seconds before t = 0 from its drawn
 * shape, by the scene's own scheme and step, its ends held where they start
 * (driven ends at their paths' first rows), the tip's loads as at t = 0,
 * gravity and the other loads as given; its velocities are zeroed whenever
 * its kinetic energy falls (kinetic damping: dynamic relaxation toward the
 * rest nearest the drawn shape), and the run starts at rest (the scene's
 * initial_velocity) from where that left it: its centreline and frames
 * become the model's starting shape (initial_shape, initial_frames), so
 * every run of the model (rodsim run, live, the library) starts there, and
 * `rodsim run` replays a live session's record from the same start
 * (docs/decisions/0110-live-knot-first.md). */
#ifndef RODSIM_SIM_SETTLE_H
#define RODSIM_SIM_SETTLE_H

#include <stddef.h>

#include "sim/rod_types.h"

/* Settles m (derived, m->settle > 0 s and at most 100,000 of its steps,
 * the implicit scheme, no puncture, elastic pad, instrument or cut) as above: its starting shape and frames
 * replaced by the settled ones. Returns 0, or -1 with a message (a step of
 * the settling that failed) and m unchanged. *fastest: the fastest node's
 * speed at the last step, before the velocities were zeroed, m/s (NULL:
 * not wanted). */
int rod_model_settle(rod_model *m, double *fastest, char *err, size_t errlen);

#endif
