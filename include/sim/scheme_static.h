/* scheme_static.h: internals of the static scheme that the buckling module
 * uses (not for other callers): the tangent stiffness of the discrete
 * equilibrium at the straight rod under axial tip loads.
 *
 * At the straight (possibly twisted) rod under axial loads the problem is
 * symmetric under rotations about x, so every bending mode comes with a copy
 * turned by 90 degrees and the real Jacobian's determinant touches zero
 * without changing sign. The transverse part of the Jacobian is complex
 * linear in w = y + i z (a rotation about x multiplies w by e^{i alpha}); its
 * complex determinant has a simple zero where the real one has a double one. */
#ifndef RODSIM_SCHEME_STATIC_H
#define RODSIM_SCHEME_STATIC_H

#include <stddef.h>

#include "sim/rod.h"

typedef struct static_work static_work;

/* The scheme's scratch memory for model m (as rod_scheme_static.create). */
static_work *static_work_create(const rod_model *m, char *err, size_t errlen);
void static_work_destroy(static_work *w);

/* Sets the Newton base point to the straight rod along +x, twisted uniformly
 * by the axial tip moment, carrying the axial tip force, under `lambda` times
 * the model's tip force and moment (no distributed load), and returns in
 * *log_abs and *phase the complex determinant of the transverse tangent
 * stiffness there (natural log of its modulus, and its argument in rad).
 * *residual is the largest scaled residual of that straight state (about
 * round-off when it is an equilibrium). Returns 0, or -1 when the Jacobian is
 * not complex linear (the straight state is not axisymmetric) with a message. */
int static_straight_determinant(static_work *w, const rod_model *m, double lambda,
                                double *log_abs, double *phase, double *residual, char *err,
                                size_t errlen);

#endif
