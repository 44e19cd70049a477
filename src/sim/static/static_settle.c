/* static_settle.c: the iterations to a rest, which watch the tangent
 * stiffness (static_stability.c) as they go: Newton, which stops before a
 * first step that climbs, and the over-damped descent (pseudo-transient
 * continuation). An unstable answer of the static scheme is left along its
 * critical mode both ways, each by the descent to a stable rest, and the
 * rest of lower potential energy is kept: the side the load picks (when
 * the two agree to round-off, the side the load's transverse part pulls,
 * or +y with a warning when the load is symmetric); when no rest is found
 * the step fails rather than return an unstable answer. */
#include "sim/static/static_settle.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "base/numfmt.h"
#include "sim/rod.h"
#include "sim/rod_geometry.h"
#include "sim/static/static_internal.h"
#include "sim/static/static_load.h"
#include "sim/static/static_solve.h"
#include "sim/static/static_stability.h"
#include "base/vec3.h"

/* Budget (a step always ends): pseudo-time iterations of the descent off
 * an unstable equilibrium. */
static const int max_descent_iterations = 300;

/* The push along the critical mode off an unstable equilibrium: largest
 * node rotation, rad. */
static const double mode_push = 0.05;

/* The two sides' rests are of equal potential energy when their energies
 * differ by at most this times sqrt(NS), relative to the energies' size:
 * some 25 x the round-off between mirror images, far below what a lateral
 * load of 1e-12 of the axial one makes (docs/decisions/0046-static-branch.md). */
static const double energy_tie = 4.0 * DBL_EPSILON;

/* After a poor step (the line search cut it below newton_poor_step) Newton
 * solves with J - c D (static_damp_rotations): a null mode whose stiffness is
 * only the Jacobian's finite-difference noise gets no step, stiff modes keep
 * theirs, and the answer is unchanged. c starts at newton_damping (the noise
 * at NS = 300, in reduced stiffness units), times 10 at each further poor
 * step up to newton_damping_limit; docs/decisions/0045-static-newton-damping.md. */
static const double newton_poor_step = 0.25;
static const double newton_damping = 1e-3;
static const double newton_damping_limit = 1e-1;

/* Turns every node by `scale` times the mode (global rotations). */
static void turn_along_mode(static_work *w, double scale)
{
    double omega[3];
    int a = 0;
    for (int i = 0; i < w->nodes; i++) {
        v3_set(omega, 0.0, 0.0, 0.0);
        for (; a < w->dofs && w->dof_node[a] == i; a++)
            v3_axpy(omega, scale * w->mode[a], &w->dof_dir[3 * a]);
        double rot[9], turned[9];
        m3_exp(rot, omega);
        m3_mul(turned, rot, &w->frame[9 * i]);
        m3_orthonormalize(turned);
        memcpy(&w->frame[9 * i], turned, sizeof turned);
    }
}

/* The side of the critical mode the load's transverse part (tip force
 * plus distributed and point loads, across the chord root-tip) pulls the
 * rod towards, like an imperfection would: +1 or -1, the mode's sign. When
 * the load has none (a symmetric bifurcation) the side where the centreline
 * moves to +y (then +z), and `symmetric` is set. Read at the unstable
 * point, so only a tie-break (settle_both_sides): a chord tilted by dy
 * adds P dy across it, which outweighs a small transverse load. */
static int mode_side(static_work *w, const rod_model *m, const static_load *load, int *symmetric)
{
    int n = w->nodes, dofs = w->dofs;
    rod_darboux_from_frames(m, w->frame, w->darboux);
    rod_midpoint_frames(m, w->frame, w->darboux, w->mid);
    /* first-order displacement of the nodes, summed: segment j turns by the
     * mean of its two nodes' rotations */
    double omega[2][3], moved[3] = {0, 0, 0}, node_moved[3] = {0, 0, 0};
    int a = 0;
    for (int i = 0; i < n; i++) {
        v3_set(omega[i & 1], 0.0, 0.0, 0.0);
        for (; a < dofs && w->dof_node[a] == i; a++)
            v3_axpy(omega[i & 1], w->mode[a], &w->dof_dir[3 * a]);
        if (i == 0) continue;
        double mean[3], d3[3], dr[3];
        for (int k = 0; k < 3; k++) mean[k] = 0.5 * (omega[0][k] + omega[1][k]);
        m3_column(d3, &w->mid[9 * (i - 1)], 2);
        v3_cross(dr, mean, d3);
        for (int k = 0; k < 3; k++) {
            node_moved[k] += m->ds * dr[k];
            moved[k] += node_moved[k];
        }
    }
    double tip_force[3], tip_moment[3], pull[3], chord[3], across[3];
    static_tip_load_global(w, m, load, &w->frame[9 * (n - 1)], tip_force, tip_moment);
    for (int k = 0; k < 3; k++) pull[k] = tip_force[k] + m->length * load->distributed[k];
    for (int i = 0; i + 1 < n; i++) v3_axpy(pull, load->point_factor, &w->node_force[3 * i]);
    double ends[3] = {0, 0, 0}, first[3];
    for (int j = 0; j + 1 < n; j++) {
        m3_column(first, &w->mid[9 * j], 2);
        for (int k = 0; k < 3; k++) ends[k] += m->ds * first[k];
    }
    if (v3_norm(ends) > 1e-6 * m->length) v3_scale(chord, ends, 1.0 / v3_norm(ends));
    else v3_set(chord, 1.0, 0.0, 0.0);
    v3_scale(across, chord, v3_dot(pull, chord));
    v3_sub(across, pull, across);
    double side = v3_dot(moved, across);
    *symmetric = !(fabs(side) > 1e-9 * v3_norm(moved) * v3_norm(pull));
    if (*symmetric) side = fabs(moved[1]) > 1e-9 * v3_norm(moved) ? moved[1] : moved[2];
    return side < 0.0 ? -1 : 1;
}

/* Pushes the base point off an unstable equilibrium along `sign` times the
 * critical mode (largest node turn mode_push); the forces from statics. */
static void push_along_mode(static_work *w, const rod_model *m, const static_load *load, int sign)
{
    double largest = 0.0;
    for (int b = 0; b < w->dofs; b++) largest = fmax(largest, fabs(w->mode[b]));
    double scale = largest > 0.0 ? mode_push / largest : 0.0;
    turn_along_mode(w, sign < 0 ? -scale : scale);
    static_forces_from_statics(w, m, load);
}

/* Newton on the discrete equilibrium from the base point in the work.
 * Returns 0 when the largest scaled residual is <= tolerance; then the base
 * point is the solution. `iterations` counts Jacobians formed. With
 * `downhill` set (dead loads, from a stable point of the path), returns
 * NEWTON_NOT_DOWNHILL before taking a first step along which the potential
 * curves down: Newton heads for the stationary point that way, a saddle or
 * what lies beyond it, not for the rest the rod would slide into: past P_E
 * it went from the last answer (on the load's side, nearly straight)
 * through the straight rod to the mirror-image branch
 * (docs/decisions/0046-static-branch.md). */
int static_newton(static_work *w, const rod_model *m, const static_load *load, double tolerance,
                  int max_iterations, int downhill, int *iterations, double *residual_out)
{
    int n = w->nodes, nu = w->unknowns;
    double damping = 0.0; /* see newton_damping */
    *iterations = 0;
    memset(w->increment, 0, (size_t)nu * sizeof(double));
    static_evaluate_residual(w, m, load, w->increment, w->residual);
    for (;;) {
        double norm = max_abs(w->residual, nu);
        *residual_out = norm;
        if (!isfinite(norm)) return -1;
        if (norm <= tolerance) return 0;
        if (*iterations >= max_iterations) return -1;
        ++*iterations;

        static_build_jacobian(w, m, load);
        static_capture_stiffness(w); /* for the stability check (cheap: 3 x 3 blocks) */
        static_damp_rotations(w, damping);
        if (static_solve_newton_step(w) != 0) return -1; /* singular Jacobian */
        if (downhill && *iterations == 1 && static_step_curvature(w, w->newton_step) < 0.0)
            return NEWTON_NOT_DOWNHILL;

        /* step limit: no node turns by more than max_rotation_step */
        double largest_turn = 0.0;
        for (int i = 0; i < n; i++)
            largest_turn = fmax(largest_turn, v3_norm(&w->newton_step[UNKNOWNS_PER_NODE * i]));
        double alpha = largest_turn > max_rotation_step ? max_rotation_step / largest_turn : 1.0;

        /* backtracking line search on 1/2 |R|^2 (Armijo) */
        double merit = sum_squares(w->residual, nu);
        int accepted = 0;
        for (int halving = 0; halving < 12; halving++) {
            for (int i = 0; i < nu; i++) w->increment[i] = alpha * w->newton_step[i];
            static_evaluate_residual(w, m, load, w->increment, w->residual_trial);
            double trial = sum_squares(w->residual_trial, nu);
            if (isfinite(trial) && trial <= (1.0 - 1e-4 * alpha) * merit) {
                accepted = 1;
                break;
            }
            alpha *= 0.5;
        }
        if (alpha < newton_poor_step) {
            damping = damping > 0.0 ? 10.0 * damping : newton_damping;
            if (!accepted) {
                if (damping > newton_damping_limit) return -1;
                continue; /* from the same point, damped */
            }
        }
        if (!accepted) return -1;
        static_accept_trial(w);
        memset(w->increment, 0, (size_t)nu * sizeof(double));
        static_evaluate_residual(w, m, load, w->increment, w->residual);
    }
}

/* Pseudo-transient continuation (an over-damped motion to rest, implicit
 * in pseudo-time): (J - c D) step = -R, D the identity on the free
 * rotations' moment rows, so K + c I is positive definite while c exceeds
 * -lambda_min(K): every step goes downhill in the potential energy and the
 * motion leaves an unstable equilibrium, as a real rod would; c -> 0 turns
 * it into Newton near the stable rest. Returns 0 at residual <= tolerance,
 * -1 when the budget runs out or a step fails. */
int static_descend(static_work *w, const rod_model *m, const static_load *load, double tolerance,
                   double relax, int *iterations, double *residual_out)
{
    int n = w->nodes, nu = w->unknowns;
    for (*iterations = 0; *iterations < max_descent_iterations; ++*iterations) {
        memset(w->increment, 0, (size_t)nu * sizeof(double));
        static_evaluate_residual(w, m, load, w->increment, w->residual);
        double norm = max_abs(w->residual, nu);
        *residual_out = norm;
        if (!isfinite(norm)) return -1;
        if (norm <= tolerance && *iterations > 0) return 0;
        static_build_jacobian(w, m, load);
        static_capture_stiffness(w);
        /* stable here (on the sleeve, for a held tip): damping fades to Newton */
        double lowest = static_unstable_count(w) != 0 ? static_critical_mode(w) : 0.0;
        if (isnan(lowest)) return -1;
        double damping = 1.5 * fmax(0.0, -lowest) + relax;
        relax *= 0.5;
        static_damp_rotations(w, damping);
        if (static_solve_newton_step(w) != 0) return -1;
        double largest_turn = 0.0;
        for (int i = 0; i < n; i++)
            largest_turn = fmax(largest_turn, v3_norm(&w->newton_step[UNKNOWNS_PER_NODE * i]));
        double alpha = largest_turn > max_rotation_step ? max_rotation_step / largest_turn : 1.0;
        for (int i = 0; i < nu; i++) w->increment[i] = alpha * w->newton_step[i];
        static_evaluate_residual(w, m, load, w->increment, w->residual_trial);
        static_accept_trial(w);
    }
    return -1;
}

/* The total potential energy of the base point under the dead loads, J,
 * in two parts: `elastic` = sum ds/2 (u - u0).B(u - u0), the energy whose
 * gradient is the constitutive law M = B (u - u0) (thesis (3.4), u0 the
 * rest curvature along the load path as static_midpoint_moments has it),
 * and `work` = the dead forces . positions from the root (tip force with
 * the tip node's point load, the point loads, the distributed load lumped
 * at the nodes, half at the tip, as the residual has them). A held tip's
 * reaction does no work (its tip stays on its place or its sleeve). */
static void potential_energy(static_work *w, const rod_model *m, const static_load *load,
                             double *elastic, double *work)
{
    int n = w->nodes;
    double ds = m->ds, c = load->curvature, position[3] = {0, 0, 0};
    rod_darboux_from_frames(m, w->frame, w->darboux);
    rod_midpoint_frames(m, w->frame, w->darboux, w->mid);
    *elastic = 0.0;
    *work = 0.0;
    for (int j = 0; j + 1 < n; j++) {
        for (int k = 0; k < 3; k++) {
            double strain = w->darboux[3 * j + k] - c * m->intrinsic_curvature[k] -
                            (1.0 - c) * w->start_darboux[3 * j + k];
            *elastic += 0.5 * ds * m->stiffness[k] * strain * strain;
        }
        double d3[3], force[3];
        m3_column(d3, &w->mid[9 * j], 2);
        v3_axpy(position, ds, d3); /* node j + 1 */
        if (j + 2 < n) {
            v3_scale(force, load->distributed, ds);
            v3_axpy(force, load->point_factor, &w->node_force[3 * (j + 1)]);
        } else {
            double tip_moment[3];
            static_tip_load_global(w, m, load, &w->frame[9 * (n - 1)], force, tip_moment);
            v3_axpy(force, 0.5 * ds, load->distributed);
        }
        *work += v3_dot(force, position);
    }
}

/* The base point (frames, forces N, held tip's reaction) copied out or in. */
static void copy_point_out(const static_work *w, double *frame, double *force, double *reaction)
{
    memcpy(frame, w->frame, (size_t)w->nodes * 9 * sizeof(double));
    memcpy(force, w->force, (size_t)(w->nodes - 1) * 3 * sizeof(double));
    memcpy(reaction, w->reaction, sizeof w->reaction);
}

static void copy_point_in(static_work *w, const double *frame, const double *force,
                          const double *reaction)
{
    memcpy(w->frame, frame, (size_t)w->nodes * 9 * sizeof(double));
    memcpy(w->force, force, (size_t)(w->nodes - 1) * 3 * sizeof(double));
    memcpy(w->reaction, reaction, sizeof w->reaction);
}

/* One side's rest: from the start point (branch_start_*, its mode and
 * axes), a push along `sign` times the mode and the descent. */
typedef struct side_rest {
    int converged;     /* the descent settled */
    int iterations;    /* its Jacobians */
    double residual;   /* its last scaled residual */
    double elastic, work; /* the potential energy's parts there, J */
} side_rest;

static void settle_side(static_work *w, const rod_model *m, const static_load *load,
                        double tolerance, double relax, int sign, side_rest *rest)
{
    copy_point_in(w, w->branch_start_frame, w->branch_start_force, w->branch_start_reaction);
    memcpy(w->mode, w->branch_mode, (size_t)w->dofs * sizeof(double));
    memcpy(w->dof_dir, w->branch_dof_dir, (size_t)w->dofs * 3 * sizeof(double));
    push_along_mode(w, m, load, sign);
    rest->iterations = 0;
    rest->residual = 0.0;
    rest->converged =
        static_descend(w, m, load, tolerance, relax, &rest->iterations, &rest->residual) == 0;
    rest->elastic = rest->work = 0.0;
    if (rest->converged) potential_energy(w, m, load, &rest->elastic, &rest->work);
}

/* Leaves the unstable base point along its critical mode, both ways, and
 * keeps the rest of lower potential energy Pi = elastic - work: the side
 * the load picks. Not the side read at the unstable point (mode_side): a
 * load step past P_E lands Newton on the complementary branch's unstable
 * point, bent the wrong way, whose chord's tilt outweighs a lateral load
 * up to 1e-4 of the axial one (thesis fig. 4a's column, 2 P_E, a lateral
 * load 1e-6 of it: tip y -0.797 m, the mirror image). When the energies
 * agree to within energy_tie (a symmetric load, or one rest reached both
 * ways), mode_side's side is kept, and a symmetric choice is warned of;
 * docs/decisions/0046-static-branch.md. Returns 0 with the base point at
 * the rest kept (*symmetric set when the side was a symmetric choice),
 * -1 when neither side settled (the first side's residual in *residual). */
static int settle_both_sides(static_work *w, const rod_model *m, const static_load *load,
                             double tolerance, double relax, int *symmetric, int *iterations,
                             double *residual)
{
    int first = mode_side(w, m, load, symmetric);
    copy_point_out(w, w->branch_start_frame, w->branch_start_force, w->branch_start_reaction);
    memcpy(w->branch_mode, w->mode, (size_t)w->dofs * sizeof(double));
    memcpy(w->branch_dof_dir, w->dof_dir, (size_t)w->dofs * 3 * sizeof(double));
    side_rest rests[2];
    settle_side(w, m, load, tolerance, relax, first, &rests[0]);
    if (rests[0].converged)
        copy_point_out(w, w->branch_rest_frame, w->branch_rest_force, w->branch_rest_reaction);
    settle_side(w, m, load, tolerance, relax, -first, &rests[1]);
    *iterations += rests[0].iterations + rests[1].iterations;
    *residual = rests[0].residual;
    if (!rests[0].converged && !rests[1].converged) return -1;
    int keep = rests[0].converged ? 0 : 1;
    if (rests[0].converged && rests[1].converged) {
        double pi0 = rests[0].elastic - rests[0].work, pi1 = rests[1].elastic - rests[1].work;
        double scale = fabs(rests[0].elastic) + fabs(rests[0].work) + fabs(rests[1].elastic) +
                       fabs(rests[1].work);
        if (fabs(pi0 - pi1) > energy_tie * sqrt((double)w->nodes) * scale) {
            keep = pi1 < pi0 ? 1 : 0;
            *symmetric = 0;
        }
    } else *symmetric = *symmetric && keep == 0; /* the only rest found */
    if (keep == 0)
        copy_point_in(w, w->branch_rest_frame, w->branch_rest_force, w->branch_rest_reaction);
    return 0;
}

/* Checks the solved base point's stability and, when it is unstable,
 * follows the rod off it to the stable rest the load picks
 * (settle_both_sides; at most `tries` times). Returns ROD_OK with the base
 * point stable (or not checkable), else a status with the report's message
 * written. */
rod_status static_settle_stable(static_work *w, const rod_model *m, const static_load *load,
                                double tolerance, double time, int *iterations, rod_report *report)
{
    char text[256];
    if (!static_loads_conservative(w, m, load)) {
        w->have_verdict = 0;
        return ROD_OK;
    }
    if (!w->stiffness_fresh) {
        static_build_jacobian(w, m, load);
        static_capture_stiffness(w);
    }
    int count = static_unstable_count(w);
    for (int tries = 0; count != 0 && tries < 3; tries++) {
        double lowest = static_critical_mode(w);
        if (isnan(lowest)) break;
        int symmetric = 0;
        double residual = 0.0;
        int rc = settle_both_sides(w, m, load, tolerance, fabs(lowest) + negative_eigenvalue,
                                   &symmetric, iterations, &residual);
        if (rc != 0) {
            static_describe_load(m, load, text, sizeof text);
            char said[NUMFMT_WORDS_MAX];
            snprintf(report->message, sizeof report->message,
                     "static: the equilibrium at t = %g s (%s) is unstable (%d unstable mode%s) "
                     "and the descent to a stable one, along either side of its critical mode, "
                     "did not settle within %d iterations (scaled residual %s, tolerance "
                     "%.1e). The state is left at the last stable time. A ramped load with more "
                     "output frames (render.fps), or a dynamic scheme (solver.scheme = "
                     "implicit), follows the rod through the instability.", time, text, count,
                     count == 1 ? "" : "s", max_descent_iterations,
                     numfmt_e_or_words(said, sizeof said, residual, 3), tolerance);
            return ROD_NO_CONVERGENCE;
        }
        if (symmetric && !report->warning[0])
            snprintf(report->warning, sizeof report->warning,
                     "static: at t = %g s the equilibrium on the path was unstable (a symmetric "
                     "bifurcation: the load has no transverse part that picks a side); the rod "
                     "was pushed along its buckling mode to the side where it moves towards "
                     "+y (else +z). The mirror image is an equally valid equilibrium; a small "
                     "transverse load picks the side.", time);
        /* the stiffness at the rest kept (the last one captured may be the other side's) */
        static_build_jacobian(w, m, load);
        static_capture_stiffness(w);
        count = static_unstable_count(w);
    }
    if (count != 0) {
        static_describe_load(m, load, text, sizeof text);
        snprintf(report->message, sizeof report->message,
                 "static: the only equilibrium found at t = %g s (%s) is %s: it is not an "
                 "answer a real rod would settle in, so it is not returned. Use a dynamic "
                 "scheme (solver.scheme = implicit) to follow the rod through the "
                 "instability.", time, text,
                 count < 0 ? "critical (the tangent stiffness is singular: stability undecided)"
                           : "unstable (the tangent stiffness is not positive definite)");
        return ROD_UNSTABLE;
    }
    w->have_verdict = 1;
    w->negative_modes = 0;
    return ROD_OK;
}
