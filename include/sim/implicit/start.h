/* start.h: the start of an implicit step, internal to the implicit room:
 * the step's data from the state at its start (frames, velocities, the
 * ends' paths, contacts, self-contact's candidate pairs) and Newton's first
 * iterate. */
#ifndef RODSIM_SIM_IMPLICIT_START_H
#define RODSIM_SIM_IMPLICIT_START_H

#include "sim/implicit/work.h"

/* Self-contact's candidate pairs lie within this many diameters of one
 * diameter apart at the start of a step, at most */
#define SELF_MARGIN 2.0
/* ... and at least this many: with no pair that near, none is a candidate
 * (prepare_contact) */
#define SELF_NEAR 0.5

/* Prepares the step of dt from s (read only) up to Newton: its data and the
 * first iterate in w->x; *continuing: s is the state the last accepted step
 * produced (implicit_continues_from). renew_stale: a factorisation the last
 * step found stale is dropped for Newton to renew (0 when the caller builds
 * its own: implicit_refresh, the test functions). Returns 0; -1 when the
 * planar path cannot start from s; -2 (report->message set) when
 * self-contact's pairs are more than its scratch holds. */
int implicit_prepare_step(implicit_work *w, const rod_model *m, const rod_state *s, double dt,
                          rod_report *report, int renew_stale, int *continuing);

/* 1 when s is the state the last accepted step produced (its frames bit for
 * bit, at its time): the step's start-of-step quantities and the last
 * solutions (the first iterate) carry over. The time within 1e-6 dt, not
 * equal: a run sets t to the output time after a frame's steps (no drift),
 * which differs from the sum of the steps in the last bits, and an exact
 * test made every frame's first step start cold
 * (docs/decisions/0029-first-iterate-with-pairs.md). */
int implicit_continues_from(const implicit_work *w, const rod_state *s, double dt);

/* Self-contact's data of a step: each node's compliance over the step and
 * the candidate pairs closer than one diameter + margin (m) at its start.
 * Returns -1 (report->message set) when there are more than the scratch
 * holds. */
int implicit_prepare_self_contact(implicit_work *w, const rod_model *m, double dt, double margin,
                                  rod_report *report);

/* Which extrapolation would have foreseen the solution x of the step of dt
 * just solved better, from the three before it (x_last, x_before,
 * x_before2, all of steps of dt): 2 for the parabola 3 (x_last - x_before)
 * + x_before2, 1 for the line 2 x_last - x_before (also when there are
 * fewer than three such steps). Each unknown's error is measured on its
 * kind's typical size (var_scale), summed in squares. The next step takes
 * the one that did better: where the motion is smooth the parabola's error
 * is O(dt^3) against the line's O(dt^2), while just after a contact
 * switches or a puncture is made the parabola carries the jump on for two
 * steps and the line for one. Used only with surfaces or punctures and no
 * self-contact pairs (docs/decisions/0029-first-iterate-with-pairs.md). */
int implicit_first_iterate_order(const implicit_work *w, double dt);

#endif
