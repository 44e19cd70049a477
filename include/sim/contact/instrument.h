/* instrument.h (contact): the thread against the instruments (sim/instrument.h)
 * inside the implicit scheme's residual, and the grasps of their closed jaws.
 *
 * Contact: each node against each capsule with the surfaces' law
 * (surface_contact.h): the half-space tangent to the capsule grown by the
 * thread's radius at the node's nearest point at the step's start, carried
 * with the capsule to the step's end, takes back the node's free motion into
 * it (contact_fraction), and regularised Coulomb friction limited by mu times
 * the normal force acts on the node's velocity RELATIVE to the capsule's
 * material point there. A moving capsule pushes the thread; the velocity map
 * is the surfaces' flat one, composed with theirs.
 *
 * Grasp: closed jaws hold the thread's point between them (a point carried
 * by the jaws): a puncture-like sliding point constraint (puncture.h) whose
 * point and velocity are the jaws', the friction's limit the instrument's
 * grip (N) instead of mu times the force across. While the jaws are nearly
 * closed (below twice ROD_JAW_CLOSED) or hold the needle, the jaws' capsules
 * do not touch the thread: the grasp holds it. */
#ifndef RODSIM_SIM_CONTACT_INSTRUMENT_H
#define RODSIM_SIM_CONTACT_INSTRUMENT_H

#include "sim/contact/contact.h"
#include "sim/rod_types.h"

/* The step from s (its start) over dt: each node's gap to each capsule, the
 * capsules' points and velocities, and the grasps appended to the punctures
 * (after puncture_prepare). */
void instrument_contact_prepare(rod_contact *ct, const rod_model *m, const rod_state *s,
                                double dt);

/* Contact of node b with the instruments inside the residual (after the
 * surfaces' surface_contact_node): corrects its vel1 and vbar, sets its
 * instrument_force and, with want_jacobian, composes its velocity map. */
void instrument_contact_node(rod_contact *ct, const rod_model *m, int b, double push, double dt);

/* After a step: what the thread exerts on each instrument's parts by
 * contact (rod_grasp_state touch), each grasp's arc length (where the thread passes the jaws
 * now) and the force the thread exerts on them; a grasp the thread slid out
 * of past its end (farther than a diameter beyond it) is released. */
void instrument_contact_update(const rod_contact *ct, const rod_model *m, rod_state *s);

#endif
