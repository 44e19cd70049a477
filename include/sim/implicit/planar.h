/* planar.h: the implicit scheme's planar path, internal to the implicit
 * room (today's cantilever only: work.c's choose_layout). Every load keeps
 * the rod in the x-y plane, so d2 stays along +z, each frame is a rotation
 * about z by phi (d3 = (cos phi, sin phi), d1 = (-sin phi, cos phi)), omega
 * = omega_2 d2 and u = u_2 d2 with u_{i+1/2} = (phi_{i+1} - phi_i) / ds: the
 * same discrete equations as in 3-D (residual.h), restricted to the plane
 * (the out-of-plane unknowns stay exactly zero), with 5 unknowns per block
 * and no rotation matrices. */
#ifndef RODSIM_SIM_IMPLICIT_PLANAR_H
#define RODSIM_SIM_IMPLICIT_PLANAR_H

#include "sim/implicit/work.h"

/* Scaled residual of the planar step; leaves phi1, phi_th, darboux1 (u_2 at
 * 3j+1) and moment1 (z at 3j+2) for the iterate x. */
void implicit_residual_planar(implicit_work *w, const rod_model *m, const double *x, double t,
                              double dt, double *res);

/* Planar start of a step from the state's frames: phi (unwrapped along the
 * rod so that u is continuous), and the z parts of the elastic state.
 * Returns -1 when a frame is not a turn about z. */
int implicit_begin_planar(implicit_work *w, const rod_model *m, const rod_state *s);

/* Planar end of a step: frames, strains, positions, velocities and forces
 * from phi1 and x, in the state's conventions; the next step's start. */
void implicit_accept_planar(implicit_work *w, const rod_model *m, rod_state *s);

#endif
