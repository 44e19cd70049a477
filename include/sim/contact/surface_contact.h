/* surface_contact.h: contact of the rod's nodes with the scene's rigid
 * surfaces (sim/contact/surface.h) inside the implicit scheme's residual:
 * the contact law of friction.h (its smooth friction) on each node, with
 * the node's velocity map for the Jacobian. */
#ifndef RODSIM_SIM_CONTACT_SURFACE_CONTACT_H
#define RODSIM_SIM_CONTACT_SURFACE_CONTACT_H

#include "sim/contact/contact.h"
#include "sim/rod_types.h"

/* Each node's gap, normal and nearest point on each surface at the start
 * of the step (surface_contact_node reads them in every residual
 * evaluation), from ct->pos0; on an elastic pad's surface also its
 * velocity, give and last forces there (surface_motion). */
void surface_contact_prepare(rod_contact *ct, const rod_model *m);

/* Contact of node b with the surfaces inside the residual: corrects its
 * vel1 and vbar in place, sets its surface_force and, with want_jacobian,
 * its velocity map.
 *
 * The velocity is not a Newton unknown: (3.3)_1 gives it from N, and a
 * contact force F at the node changes it by push F (push = 1 / (w_b (m/dt +
 * theta c)), the node's compliance), so the end of the step moves by a F,
 * a = dt theta push. Given the iterate's N, the node's contact is a problem
 * of its own, solved here in closed form:
 *   - normal: where the free motion would end a depth e inside the surface
 *     grown by the rod's radius, the force along the outward normal that
 *     takes back the fraction kappa / (1 + kappa) of it (contact_fraction:
 *     an implicit spring; what is left is below 1 % of the radius), else 0;
 *   - friction: regularised Coulomb against the end-of-step tangential
 *     velocity relative to the surface's (an elastic pad's moves), limited
 *     by mu times the normal force (contact_creep_speed).
 * An elastic pad's surface is compliant (surface_motion: its give c, m/N,
 * and the forces its last equilibrium carries): its point moves by c times
 * the change of the force on it over the step, across and along, so the
 * depth is taken against e = depth - c lambda_last and the force across is
 * -e / (a + c); the friction's relative velocity changes by push (a + c) /
 * a per newton, from the free one less that of the last equilibrium's
 * friction (the pad's give folded in, as a puncture's; what the pad does
 * beyond c, its cross-compliance, lags a step: tissue_coupling.h). Its
 * share of the force goes to pad_force.
 * The contact force depends on the node's own N only, like v: the
 * Jacobian's band and colouring are unchanged. The residual is piecewise
 * smooth where a contact switches on; Newton takes a line search then.
 *
 * No tunnelling: a node that was clear of the surface (by more than a tenth
 * of the radius) is held by the half-space where its straight path over the
 * step enters the grown solid (rod_surface_sweep), so a node that would
 * cross a thin pad within a step stops at its entry face; a node touching at
 * the start is held by the half-space tangent at its nearest point. Only
 * nodes carry contact: a segment over a box's edge can cut it by up to
 * ds^2 / (8 R) for the rounding R of the grown edge, here the rod's radius
 * (README). Nodes threaded through tissue between punctures skip that
 * surface (puncture_prepare). */
void surface_contact_node(rod_contact *ct, const rod_model *m, int b, double push, double dt);

/* The surfaces' contact again on the nodes the strands' own contact
 * pushes (node_force, N, nodes x 3, not 0): each such node's surface force
 * is taken out of its velocity and found anew with the pair forces in
 * place, so that a strand pressed into a surface by another is held by it
 * (push: each node's compliance, 0 at a held end). Nodes of a puncture's
 * segment are left as they are. With want_jacobian, each such node's map
 * d v / d v_in (velocity_jac's own block) goes to node_map (nodes x 9) and
 * mapped[b] is set. */
void surface_contact_after_pairs(rod_contact *ct, const rod_model *m, const double *node_force,
                                 const double *push, double dt, double *node_map,
                                 unsigned char *mapped);

#endif
