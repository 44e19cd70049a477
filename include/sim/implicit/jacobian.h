/* jacobian.h: the implicit scheme's Jacobian J = d r / d x of the residual
 * (residual.h), internal to the implicit room. Built in closed form
 * (analytic: one residual evaluation and 3 x 3 algebra per node) or, in the
 * plane and in a step's retry, by finite differences with a colouring of
 * the block-tridiagonal pattern (18 residual evaluations; 15 in the plane),
 * and factored by a banded LU with partial pivoting (base/band.h). Contact's
 * part is in closed form (add_contact_jacobian); when to renew which part is
 * Newton's (newton.h). */
#ifndef RODSIM_SIM_IMPLICIT_JACOBIAN_H
#define RODSIM_SIM_IMPLICIT_JACOBIAN_H

#include "sim/implicit/work.h"

/* The Jacobian at the iterate x, factored. With contact: the rod's part
 * (rod_jacobian, the residual without contact), kept in band_smooth, and
 * the contact's part in closed form (add_contact_jacobian); in step's retry
 * (contact_fd) the whole by finite differences. Returns 0, or -1 when the
 * matrix is singular. */
int implicit_factor_jacobian(implicit_work *w, const rod_model *m, double t, double dt);

/* The contact's part alone renewed at the iterate x onto the kept rod's
 * part, band_smooth (the rod's own Jacobian changes slowly; which
 * nodes touch, stick or slip changes from one iterate to the next), and
 * factored: from the first column that part changes on (the factors'
 * columns before it stand). Returns 0, or -1 when the matrix is singular. */
int implicit_refresh_contact_jacobian(implicit_work *w, const rod_model *m, double t, double dt);

/* The rod's part in closed form at x into lu, unfactored (contact, punctures
 * and the pairs' laws left out: contact_off, self_off; 3-D only). */
void implicit_analytic_jacobian(implicit_work *w, const rod_model *m, double t, double dt);

/* The contact's part of the Jacobian at the iterate x, added onto lu's
 * columns from col_from on.
 * Only the (3.14) rows see contact, through the end-of-step velocities:
 * r_b = theta dt/ds (v_b - v_{b-1}) + ..., v = V(u) the velocities after
 * contact and punctures, u the free ones of (3.3)_1, d u_b / d N_{b-1/2} =
 * -p_b I and d u_b / d N_{b+1/2} = p_b I with p_b the node's compliance
 * (push; twice at a free end; 0 at a held end, whose velocity is its
 * support's). The rod's part (the residual without contact) is the
 * Jacobian for V(u) = u, so this adds theta dt/ds E (dV/du - I) du/dN,
 * dV/du recorded in closed form by surface_contact_node and puncture_forces (no
 * finite difference resolves friction's turn within its creep speed well).
 * Left out: a follower tip load's turn with the tip's omega at a free tip
 * in contact, and a sliding end's motion under a puncture beside it. */
void implicit_add_contact_jacobian(implicit_work *w, const rod_model *m, double t, double dt,
                                   int col_from);

/* lu factored in place (band_factor); the scheme's count of builds. Returns
 * 0, or -1 when the matrix is singular. */
int implicit_factor_band(implicit_work *w, double dt);

#endif
