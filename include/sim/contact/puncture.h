/* puncture.h: the punctures a thread passes through (tissue surfaces,
 * rod_puncture_state) inside the implicit scheme's step: a sliding point
 * constraint with the contact law of friction.h (its smooth friction), and
 * the holes a needle on the driven tip makes. */
#ifndef RODSIM_SIM_CONTACT_PUNCTURE_H
#define RODSIM_SIM_CONTACT_PUNCTURE_H

#include "sim/contact/contact.h"
#include "sim/rod_types.h"

/* The segment j (nodes j, j + 1) holding arc length s (m) and the fraction
 * alpha in [0, 1] along it: s = s_j + alpha ds_j (rod_grid.h), clamped to
 * the thread. A point carried in arc length so crosses a node where the
 * spacing jumps without a jump in its place. */
void puncture_locate(const rod_model *m, double s, int *j, double *alpha);

/* Segment and fraction of each puncture for the step from the state, and
 * the thread's direction there (from the start of the step). */
void puncture_prepare(rod_contact *ct, const rod_model *m, const rod_state *s);

/* The punctures' forces, inside the residual, after every node's velocity
 * and surface contact: a sliding point constraint. The thread's point at
 * (segment j, fraction alpha) must pass through the puncture's point P: the
 * force across the thread (perpendicular to the segment) that puts it
 * there, short by 1 / (1 + CONTACT_STIFF) as the surfaces' normal force,
 * and Coulomb friction along the thread limited by mu times that force
 * (contact_creep_speed), so the tension drops across a puncture by at most
 * mu |F_across| while the thread slides through. The force acts on the two
 * nodes by the weights 1 - alpha, alpha; the point's velocity responds with
 * the compliance (1-alpha)^2 push_j + alpha^2 push_j+1 (push: a uniform
 * grid's interior node's compliance, m/s per N; twice at a free end, 0 at a
 * held one; on a graded grid push ds / w_i, w_i node i's cell).
 * Where the thread passes is updated after each step (puncture_update), so
 * it slides through at whatever arc length. */
void puncture_forces(rod_contact *ct, const rod_model *m, double push, double dt);

/* After a step: where the thread passes each puncture now (the nearest
 * point of the segments near the old one), and the force it exerts there. */
void puncture_update(const rod_contact *ct, const rod_model *m, rod_state *s);

/* After a step: where the thread near a needle-carrying driven tip (within
 * a needle radius of it: the part that follows the needle through the hole
 * its point cut) crosses a tissue surface at a point no puncture holds yet,
 * a puncture is made: at the thread's own crossing, so the thread passes
 * through it from the start. Returns -1 when there is no room for one more
 * (ROD_MAX_PUNCTURES; report->message set). */
int puncture_needle_holes(const rod_model *m, rod_state *s, rod_report *report);

#endif
