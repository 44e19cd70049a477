/* tissue_coupling.h: a rod's punctures in an elastic pad (a [surface] box
 * with model = elastic: rod_surface.solid), coupled two ways.
 *
 * Each puncture in a pad is a material point of it (a tet and barycentric
 * weights, found where the puncture is when it is linked) and moves with
 * it. The pad is quasi-static: after every rod step it is solved to
 * equilibrium under the forces the thread exerts at its punctures, and the
 * punctures move with it. Within the rod's step the pad's compliance at each
 * puncture and between every two of a pad's punctures (the 3P x 3P block
 * of its P punctures, at the last equilibrium) is folded into the
 * punctures' laws (puncture.h), solved together: a point moves by
 * sum_l C_kl (F_l - F_l,last) with the forces F_l on the pad, so the
 * coupling is implicit within the step (docs/decisions/0070-tissue-coupling.md;
 * the cross blocks: 0075-stitch-compliance.md).
 *
 * The thread lies on the pad's deformed surface (a moving triangle mesh of
 * its boundary faces, rod_surface.mesh, moved to the pad before each rod
 * step): its contact forces (across and friction) go on the pad after the
 * step at the touched triangles' nodes by barycentric weights, and the
 * pad's give (its vertices' compliances along their normals, scaled by the
 * give the last update met) is folded into each node's contact law. The
 * surface's velocity, which the friction acts relative to, is the pad's
 * motion apart from the thread's contact: an update under the punctures'
 * new forces and the contact's forces as carried, before the update under
 * the contact's new forces (docs/decisions/0073-tissue-contact.md). */
#ifndef RODSIM_SIM_TISSUE_TISSUE_COUPLING_H
#define RODSIM_SIM_TISSUE_TISSUE_COUPLING_H

#include <stddef.h>

#include "sim/rod_types.h"

/* After a rod step (and before the first): links the punctures not yet
 * linked that lie in an elastic pad (made there by the needle, or given in
 * the scene inside its box), puts every linked puncture's force on its pad
 * and the thread's contact on its surface (pad_force, 2 x nodes x 3, N: what
 * the pad's surface exerted on each node over the step, then the record of
 * what it exerted at the last call, renewed here: rod_contact.pad_last; may
 * be NULL), brings each pad towards equilibrium (up to two Newton updates),
 * moves the punctures with their material points and renews their
 * compliances (all of a pad's together, when its factor was renewed or a
 * puncture linked). 0, or -1 with a message (the pad's
 * Newton failed: the state's punctures are left as they were). A model
 * without an elastic pad: nothing, 0. */
int tissue_coupling_step(const rod_model *m, rod_state *s, double *pad_force, char *err,
                         size_t errlen);

/* The same for `count` rods sharing their pads (sim/rod_set.h: each
 * model's surface j is the same pad, rod_surface.solid_shared but for
 * m[0]'s): after every rod's step, every rod's punctures and contact
 * (pad_force[q], may be NULL) load each pad, one solve, and every rod's
 * punctures move with it. A puncture's compliance folds in the pad's give
 * under its own rod's punctures only: the other rods' pulls reach it
 * through the pad's solve, a step late. count 1 is tissue_coupling_step. */
int tissue_coupling_step_rods(int count, const rod_model *const *m, rod_state *const *s,
                              double *const *pad_force, char *err, size_t errlen);

/* Before a rod step: links the punctures not yet linked (as above) and
 * sets their compliance, without solving the pads, and moves each pad's
 * surface mesh (rod_surface.mesh) to the pad's nodes, its velocity the
 * change since the last step. 0, or -1 with a message. */
int tissue_coupling_link(const rod_model *m, rod_state *s, char *err, size_t errlen);

/* The surface the rod's contact sees of a pad (rod_surface.mesh): a moving
 * mesh over all its nodes (vertex i is node i), of its boundary's faces
 * except the wound's slit (the thread passes the wound there; the slit's
 * opening is a hole in the surface), a quadratic face cut into four flat
 * triangles at its midpoints. NULL with a message when out of memory. */
struct rod_mesh *tissue_coupling_surface(struct tissue_solid *t, char *err, size_t errlen);

/* The first elastic pad's surface index, or -1. */
int tissue_coupling_pad(const rod_model *m);

/* The wound's opening (m) at the slit's top-face node pair nearest to p
 * along the slit (the gap at a stitch's place): the pair's separation
 * across the slit; 0 without a wound. */
double tissue_coupling_gap_at(const struct tissue_solid *t, const double p[3]);

/* m: the largest displacement of a node of the pad from its rest place. */
double tissue_coupling_max_displacement(const struct tissue_solid *t);

#endif
