/* static_solve.h: internal to the static scheme's room (static_internal.h).
 * The discrete equilibrium (residual, Jacobian, bordered band solve), at
 * the base point and load in the work; Newton on it is static_settle.h's. */
#ifndef RODSIM_STATIC_SOLVE_H
#define RODSIM_STATIC_SOLVE_H

#include "sim/static/static_internal.h"

/* The tip force and moment (N, N m), global, for the tip frame q_tip: the
 * tip load (follower or dead) plus the point load at the tip node. */
void static_tip_load_global(const static_work *w, const rod_model *m, const static_load *load,
                            const double q_tip[9], double force[3], double moment[3]);

/* The held tip's reaction, N, global, at the trial point `increment` (the
 * base point when NULL). */
void static_tip_reaction(const static_work *w, const double *increment, double reaction[3]);

/* The two axes a pinned root at frame q0 may turn about, unit, global. */
void static_swing_axes(const static_work *w, const double q0[9], double axes[2][3]);

/* M_{j+1/2}, N m, global, into w->moment from w->darboux and w->mid, at rest
 * curvature `curvature` along the load path (static_load). */
void static_midpoint_moments(static_work *w, const rod_model *m, double curvature);

/* The scaled residual at the trial point `increment` (unknowns long) into
 * out; leaves the trial frames, Darboux vectors and midpoint frames in w. */
void static_evaluate_residual(static_work *w, const rod_model *m, const static_load *load,
                              const double *increment, double *out);

/* The forces N (and nothing else) from the force balance at the base point. */
void static_forces_from_statics(static_work *w, const rod_model *m, const static_load *load);

/* The Jacobian at the base point by finite differences into w->band and the
 * border; the base residual into w->residual. */
void static_build_jacobian(static_work *w, const rod_model *m, const static_load *load);

/* Solves a x = b in place in b (size <= MAX_BORDER); -1 when singular. */
int static_solve_small(int size, double a[MAX_BORDER][MAX_BORDER], double b[MAX_BORDER]);

/* w->newton_step = -J^-1 w->residual (the band overwritten by its LU);
 * -1 when singular. */
int static_solve_newton_step(static_work *w);

/* The base point moved to the trial point of the last evaluation. */
void static_accept_trial(static_work *w);

/* J - damping D on the band: D the identity on the free rotations' moment
 * rows (damping in the reduced stiffness' units). */
void static_damp_rotations(static_work *w, double damping);

#endif
