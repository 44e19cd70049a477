/* static_settle.c: an unstable answer of the static scheme
 * (static_stability.c) is left along its critical mode, to the side the
 * load's transverse part pulls (or +y, with a warning, when the load is
 * symmetric), by an over-damped descent (pseudo-transient continuation) to
 * a stable rest; when none is found the step fails rather than return it. */
#include "sim/static/static_settle.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sim/rod_geometry.h"
#include "sim/static/static_continuation.h"
#include "sim/static/static_internal.h"
#include "sim/static/static_solve.h"
#include "sim/static/static_stability.h"
#include "base/vec3.h"

/* Budget (a step always ends): pseudo-time iterations of the descent off
 * an unstable equilibrium. */
static const int max_descent_iterations = 300;

/* The push along the critical mode off an unstable equilibrium: largest
 * node rotation, rad. */
static const double mode_push = 0.05;

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

/* Pushes the base point off an unstable equilibrium along the critical mode
 * (largest node turn mode_push). The side: the one the load's transverse
 * part (tip force plus distributed load, across the chord root-tip) pulls
 * the rod towards, like an imperfection would; when the load has none (a
 * symmetric bifurcation) the side where the centreline moves to +y (then
 * +z) and `symmetric` is set: the mirror image is an equally valid answer. */
static void push_along_mode(static_work *w, const rod_model *m, const static_load *load,
                            int *symmetric)
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
    double largest = 0.0;
    for (int b = 0; b < dofs; b++) largest = fmax(largest, fabs(w->mode[b]));
    double scale = largest > 0.0 ? mode_push / largest : 0.0;
    turn_along_mode(w, side < 0.0 ? -scale : scale);
    static_forces_from_statics(w, m, load);
}

/* Pseudo-transient continuation (an over-damped motion to rest, implicit
 * in pseudo-time): (J - c D) step = -R, D the identity on the free
 * rotations' moment rows, so K + c I is positive definite while c exceeds
 * -lambda_min(K): every step goes downhill in the potential energy and the
 * motion leaves an unstable equilibrium, as a real rod would; c -> 0 turns
 * it into Newton near the stable rest. Returns 0 at residual <= tolerance,
 * -1 when the budget runs out or a step fails. */
static int descend(static_work *w, const rod_model *m, const static_load *load, double tolerance,
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

/* Checks the solved base point's stability and, when it is unstable,
 * follows the rod off it: a push along the critical mode, then the
 * over-damped descent to a stable rest (at most `tries` times). Returns
 * ROD_OK with the base point stable (or not checkable), else a status with
 * the report's message written. */
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
        int symmetric = 0, descent_iterations = 0;
        double residual = 0.0;
        push_along_mode(w, m, load, &symmetric);
        if (symmetric && !report->warning[0])
            snprintf(report->warning, sizeof report->warning,
                     "static: at t = %g s the equilibrium on the path was unstable (a symmetric "
                     "bifurcation: the load has no transverse part that picks a side); the rod "
                     "was pushed along its buckling mode to the side where it moves towards "
                     "+y (else +z). The mirror image is an equally valid equilibrium; a small "
                     "transverse load picks the side.", time);
        int rc = descend(w, m, load, tolerance, fabs(lowest) + negative_eigenvalue,
                         &descent_iterations, &residual);
        *iterations += descent_iterations;
        if (rc != 0) {
            static_describe_load(m, load, text, sizeof text);
            snprintf(report->message, sizeof report->message,
                     "static: the equilibrium at t = %g s (%s) is unstable (%d unstable mode%s) "
                     "and the descent to a stable one did not settle within %d iterations "
                     "(scaled residual %.3e, tolerance %.1e). The state is left at the last "
                     "stable time. A ramped load with more output frames (render.fps), or a "
                     "dynamic scheme (solver.scheme = implicit), follows the rod through the "
                     "instability.", time, text, count, count == 1 ? "" : "s",
                     max_descent_iterations, residual, tolerance);
            return ROD_NO_CONVERGENCE;
        }
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
