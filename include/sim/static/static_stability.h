/* static_stability.h: internal to the static scheme's room (static_internal.h).
 * The tangent stiffness of an answer reduced to its free rotations, its
 * unstable modes and its critical mode. static_unstable_modes
 * (scheme_static.h) asks the same of a given state. */
#ifndef RODSIM_STATIC_STABILITY_H
#define RODSIM_STATIC_STABILITY_H

#include "sim/static/static_internal.h"

/* The reduced tangent stiffness and the held tip's constraint rows, from
 * the Jacobian static_build_jacobian just built (before its LU). */
void static_capture_stiffness(static_work *w);

/* The number of unstable modes of the captured stiffness (eigenvalues below
 * -negative_eigenvalue on the constraint manifold), or -1: undecided. */
int static_unstable_count(static_work *w);

/* The critical mode into w->mode (unit norm); returns its Rayleigh
 * quotient, NAN on failure. */
double static_critical_mode(static_work *w);

/* The curvature of the potential along the free rotations of `step`
 * (unknowns long: phi per node, on the base point's frames), in the
 * captured stiffness: omega.K omega / omega.omega, the reduced stiffness'
 * units; 0 when the step turns no free rotation. */
double static_step_curvature(static_work *w, const double *step);

/* 1 when the loads have a potential (dead forces), so that stability is
 * the positive definiteness of the tangent stiffness. */
int static_loads_conservative(const static_work *w, const rod_model *m, const static_load *load);

#endif
