/* static_settle.h: internal to the static scheme's room (static_internal.h).
 * The two iterations to a rest that the load continuation uses, Newton and
 * the descent downhill (both watch the tangent stiffness), and the
 * stability check of a solved answer with the way off an unstable one. */
#ifndef RODSIM_STATIC_SETTLE_H
#define RODSIM_STATIC_SETTLE_H

#include "sim/static/static_internal.h"

/* static_newton's answer when `downhill` was asked and its first step
 * would climb. */
enum { NEWTON_NOT_DOWNHILL = 1 };

/* Newton from the base point; 0 when the largest scaled residual is <=
 * tolerance (the base point is then the answer), -1 otherwise. With
 * `downhill` set (dead loads only) NEWTON_NOT_DOWNHILL, the base point
 * unmoved, when the potential curves down along the first Newton step
 * (static_step_curvature < 0): the step climbs towards a saddle or beyond
 * it (static_descend then goes downhill instead).
 * *iterations counts the Jacobians formed, *residual_out the last norm. */
int static_newton(static_work *w, const rod_model *m, const static_load *load, double tolerance,
                  int max_iterations, int downhill, int *iterations, double *residual_out);

/* The over-damped descent (pseudo-transient continuation) from the base
 * point under `load` (dead forces), downhill in the potential energy, to a
 * rest: 0 at a scaled residual <= tolerance, -1 when its budget runs out or
 * a step fails. relax: the damping added at the start, halved each
 * iteration (reduced stiffness' units). *iterations counts the Jacobians,
 * *residual_out the last norm. */
int static_descend(static_work *w, const rod_model *m, const static_load *load, double tolerance,
                   double relax, int *iterations, double *residual_out);

/* Checks the solved base point's stability under `load` (at time, s) and,
 * when it is unstable, follows the rod off it to a stable rest (adding the
 * Jacobians formed to *iterations). Returns ROD_OK with the base point
 * stable (or not checkable: loads without a potential), else a status with
 * the report's message written. */
rod_status static_settle_stable(static_work *w, const rod_model *m, const static_load *load,
                                double tolerance, double time, int *iterations, rod_report *report);

#endif
