/* scheme_implicit.h: what the implicit scheme (rod_scheme_implicit, sim/rod.h)
 * shows beyond rod_scheme_ops, for its tests. The rod equations (3.15)
 * advanced by the theta-method, all unknowns of a step solved together by
 * Newton's method on one banded system: src/sim/implicit/ (the equations:
 * sim/implicit/residual.h); contact's laws: src/sim/contact/. */
#ifndef RODSIM_SIM_SCHEME_IMPLICIT_H
#define RODSIM_SIM_SCHEME_IMPLICIT_H

#include "sim/rod.h"

struct rod_cross; /* sim/contact/between_rods.h */

/* Joins a rod's implicit work (rod_solver.work of rod_scheme_implicit) to
 * its view of the other rods of a set, which the set keeps and fills
 * at each step (rod_link_begin, rod_link_before); NULL: alone. */
void rod_implicit_link(void *work, struct rod_cross *cross);

/* The rod's record of its contact on an elastic pad (rod_contact.pad_last,
 * 2 x nodes x 3, N; NULL without a pad), for a set that couples a shared
 * pad after every rod's step (tissue_coupling_step_rods). */
double *rod_implicit_pad_record(void *work);

/* The largest difference, over the Jacobian's columns, between the rod's
 * Jacobian in closed form and by finite differences (contact left out),
 * relative to the column's largest entry, for the step of dt from s at its
 * first iterate moved by `perturb` of each unknown's typical size; the
 * worst column in *column. Entries the differences' rounding cannot
 * resolve (3e-16 / h, h their step) are not held against the closed form;
 * *floor gets that limit's largest share of a column's largest entry. NaN when the scheme cannot be set up or the
 * model takes the planar path (finite differences only). */
double rod_implicit_jacobian_error(const rod_model *m, const rod_state *s, double dt,
                                   double perturb, int *column, double *floor);

/* The same for the whole Jacobian Newton uses with surfaces and punctures:
 * the rod's part and contact's in closed form (friction, punctures'
 * sliding and friction) against differences of the whole residual, by
 * steps of 1e-7 of each unknown's size (self-contact's pairs left out:
 * they join Newton's solve as a correction of their own). */
double rod_implicit_contact_jacobian_error(const rod_model *m, const rod_state *s, double dt,
                                           double perturb, int *column, double *floor);

/* band_solve_rows (several right-hand sides side by side, by rows) and
 * band_solve_entries (the same given by their entries) against band_solve
 * (one at a time) on the rod's Jacobian at the first iterate of the step
 * of dt from s, factored: `count` right-hand sides, zero above row
 * `first`. Returns the largest entry of A x - b (A the Jacobian, x the
 * rows kernel's solution, b's entries within 1); *differ = the entries
 * where either differs from band_solve's in any bit. NaN (*differ = -1) when it
 * cannot be set up (the planar path, or self-contact off: the rows kernel
 * is self-contact's). */
double rod_implicit_rows_solve_check(const rod_model *m, const rod_state *s, double dt, int count,
                                     int first, long *differ);

#endif
