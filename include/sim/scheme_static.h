/* scheme_static.h: what other code may use of the static scheme besides
 * rod_scheme_static (rod.h): its scratch memory, and the two questions the
 * study layer asks of it, the stability of a state and the tangent
 * stiffness of the discrete equilibrium at the straight rod under axial tip
 * loads (buckling.h). The scheme lives in src/sim/scheme_static.c and the
 * room src/sim/static/ (static_work.c, static_stability.c and
 * static_buckling.c define these).
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

#include "sim/rod_types.h"

typedef struct static_work static_work;

/* The scheme's scratch memory for model m (as rod_scheme_static.create). */
static_work *static_work_create(const rod_model *m, char *err, size_t errlen);
/* Frees what static_work_create made (NULL: nothing). */
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

/* The number of unstable modes of the equilibrium in state `s` (as this
 * scheme writes it) under the loads at s->time: the negative eigenvalues
 * (below -1e-3 in the stiffness rows' units, where the unloaded
 * cantilever's softest mode is about pi^2/4) of the tangent stiffness on
 * the constraint manifold, the check every static step makes. Returns 0
 * with *count (-1: undecided, a critical point), or -1 with a message when
 * the loads are not dead forces (no static criterion for a follower load
 * or a dead moment at the tip, a node or along the rod: not conservative).
 * Held ends count as constraints (a tip on its sleeve or in place). */
int static_unstable_modes(static_work *w, const rod_model *m, const rod_state *s, int *count,
                          char *err, size_t errlen);

#endif
