/* residual.h: the implicit scheme's equations, internal to the implicit room:
 * the rod equations (3.15) advanced by the theta-method
 * (backward Euler by default, Crank-Nicolson at theta = 1/2), all unknowns of
 * a step solved together by Newton's method on one banded system.
 *
 * Grid (staggered, which avoids the odd/even decoupling of one collocated
 * grid): velocity v and angular velocity omega at the nodes i = 0..NS-1;
 * Darboux vector u and contact force N at the segment midpoints i+1/2.
 *
 * Unknowns of a step, per block b = 1..NS-1 (6 each, 6 (NS-1) in all; a
 * root that may turn adds block 0, see Ends):
 *   N_{b-1/2}  contact force, global components (the multiplier of (3.14));
 *   omega_b    angular velocity at the end of the step, director components.
 * The velocity v_b at the end of the step (global components) is not an
 * unknown either: the linear momentum balance (3.3)_1 below is linear in v_b
 * and in N, so it gives v_b from the two contact forces beside node b; the
 * Newton system keeps (3.14) and (3.6)_2 (6 equations per node, half
 * bandwidth 8 instead of 9 unknowns and 11).
 * u is not an unknown: the frames advance by the exact exponential map
 *   Q_i(t+dt) = Q_i(t) exp(dt [omega_bar_i]x),  omega_bar = theta w(t+dt) + (1-theta) w(t)
 * (integrating (3.1)_2), and u_{i+1/2} = log(Q_i^T Q_{i+1}) / ds (integrating
 * (3.1)_1 exactly over the segment). The compatibility equation (3.10) then
 * holds exactly in discrete form and frames and curvature never drift apart.
 *
 * Equations, per block b:
 *   (3.14) inextensible, unshearable: (v_bar_{b} - v_bar_{b-1}) dt / ds
 *          = d3_{b-1/2}(t+dt) - d3_{b-1/2}(t), the time difference of
 *          r_{i+1} - r_i = ds d3_{i+1/2}; so r(t+dt) = r(t) + dt v_bar agrees
 *          with the centreline integrated from d3 (3.12).
 *   (3.6)_1 (written in the fixed frame, (3.3)_1) over the cell of node b,
 *          solved for v_b:
 *          m w_b (v_b - v_b(t)) / dt = N_{b+1/2} - N_{b-1/2} + w_b (T - c v_bar)
 *   (3.6)_2 in director components of node b:
 *          I w_b (omega - omega(t)) / dt + w_b omega_bar x I omega_bar
 *          = Q^T [ M_{b+1/2} - M_{b-1/2} + ds/2 (d3 x N)_{b+1/2} + ds/2 (d3 x N)_{b-1/2} ]
 *            - w_b c_w omega_bar,      M_{i+1/2} = Q_{i+1/2} B (u_{i+1/2} - u0)  (3.4)
 *   with w_b = ds inside and ds/2 at either end, where N_{NS-1/2} and
 *   M_{NS-1/2} are the tip force and moment (4.2) and the tip force has no
 *   arm; T holds the distributed force, and each node's point loads (times
 *   the profile factor) join its cell, as the distributed moment joins
 *   (3.6)_2.
 * Elastic terms are theta-weighted between the start and the end of the step.
 *
 * Ends: node 0 and node NS-1 each have a cell of half length
 * ds/2. A free end's velocity comes from its cell's (3.3)_1 like any other;
 * a held end's is prescribed (zero, or its path's), and a sliding end's is
 * the free one projected on the slide, so v stays eliminated at every end
 * and the support's force is what that end's balance leaves over (computed
 * after Newton, never an unknown). The root's omega_0 is an unknown (block
 * 0, its first three entries unused) when the root may turn (pinned, free,
 * clamped sliding); rotations an end holds replace their (3.6)_2 rows by
 * omega_k = 0, and the leftover of those rows is the support's moment. A
 * clamped end's frame is its path's R(t) Q(0), not integrated. The band
 * does not grow: block 0 couples to block 1 as every block to its
 * neighbours. A held end's mean velocity over the step returns it to its
 * place (or its slide's line, or its path) from wherever rounding left it,
 * so held ends never drift; the centreline is chained from a held end.
 * The planar path models only today's cantilever; every other case is 3-D.
 * A graded grid (rod.refine) replaces ds by each segment's ds_j and w_b by
 * node b's cell (sim/rod_grid.h, where the orders of accuracy are). */
#ifndef RODSIM_SIM_IMPLICIT_RESIDUAL_H
#define RODSIM_SIM_IMPLICIT_RESIDUAL_H

#include "sim/implicit/work.h"

/* The scaled residual of the step t -> t + dt at x into res (unknowns): the
 * 3-D equations above, or the planar ones (planar.h). Leaves the work's
 * end-of-step arrays (frames, darboux1, d3mid1, moment1, vel1, vbar, the
 * contact forces) for x. */
void implicit_evaluate(implicit_work *w, const rod_model *m, const double *x, double t, double dt,
                       double *res);

/* The residual at Newton's iterate x. With contact (its part of the
 * Jacobian in closed form), contact's velocity_jac is recorded too, so that
 * a Jacobian renewed at this iterate need not evaluate it again. */
void implicit_evaluate_iterate(implicit_work *w, const rod_model *m, double t, double dt);

/* implicit_evaluate_iterate unless the last evaluation already was it: a
 * Jacobian renewed in Newton's loop is built at the iterate the loop has
 * just evaluated, and Newton's first residual follows a Jacobian built at
 * the first iterate (a suture: 1 evaluation in 7 spared) */
void implicit_evaluate_iterate_once(implicit_work *w, const rod_model *m, double t, double dt);

/* The largest |a_i|, or NaN when any entry is NaN or infinite (such a
 * residual is never "converged"). */
double implicit_max_abs(const double *a, int n);

/* Tip force and moment at time t in global components, given the tip frame. */
void implicit_tip_load_global(const rod_model *m, double t, const double *tip_frame,
                              double force[3], double moment[3]);

/* The theta-mean tip force and moment over the step, global. */
void implicit_tip_load_mean(const implicit_work *w, const rod_model *m, double t, double dt,
                            const double *frame_th, double tipf[3], double tipm[3]);

/* Midpoint frames, d3 (d3mid may be NULL) and elastic moment M = Q_mid B u
 * (global) for given frames. */
void implicit_elastic_state(const rod_model *m, const double *frame, double *darboux,
                            double *mid, double *d3mid, double *moment);

/* The moment (3.6)_2 balances over the cell of node b, global: the
 * theta-weighted elastic moments of the segments beside it (left, right: 1
 * where there is one) and the arms ds/2 d3 x N of their contact forces (the
 * tip moment tipm at the tip), the distributed and point moments. d3l and
 * d3r get the theta-weighted d3 of the segments left and right of it
 * (unset when there is none). From the residual's last evaluation. */
void implicit_cell_moment(const implicit_work *w, const rod_model *m, const double *x, int b,
                          const double tipm[3], int left, int right, double total[3],
                          double d3l[3], double d3r[3]);

/* What the supports exert on the rod over the accepted step (the leftover
 * of the held ends' balances), from the residual's last evaluation at x,
 * into the ends' reaction and reaction_moment. */
void implicit_end_reactions(implicit_work *w, const rod_model *m, double t, double dt);

#endif
