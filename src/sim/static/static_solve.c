/* static_solve.c: the static scheme's discrete equilibrium: residual,
 * Jacobian, the bordered band solve of a Newton step (scheme_static.c has
 * the map of the room; Newton itself is in static_settle.c, for it watches
 * the tangent stiffness of static_stability.c).
 *
 * Discrete equations (6 per node i = 1..NS-1, global components). Between
 * the nodes the rod is made of straight segments of length ds along
 * d3_{i+1/2}, carrying the force N_{i+1/2} and the moment M_{i+1/2} =
 * Q_{i+1/2} B u_{i+1/2} (3.4); distributed loads are lumped at the nodes
 * (ds T inside, ds/2 T at the tip). Balance of the piece between two
 * midpoints, (3.3) integrated over a cell:
 *   force   N_{i+1/2} - N_{i-1/2} + ds T = 0
 *   moment  M_{i+1/2} - M_{i-1/2} + ds/2 (d3_{i+1/2} x N_{i+1/2} + d3_{i-1/2} x N_{i-1/2}) = 0
 * and the tip half cell
 *   force   N_tip - N_{NS-3/2} + ds/2 T = 0
 *   moment  M_tip - M_{NS-3/2} + ds/2 d3_{NS-3/2} x N_{NS-3/2} = 0
 * with N_tip = Q_tip N_bar, M_tip = Q_tip M_bar for a follower load (thesis
 * 4.2: components on the tip directors) and the given vectors for a dead
 * load. The moment jump uses the midpoint rule on each half segment, so the
 * scheme is second order in ds; a constant moment (pure bending, twist) is
 * reproduced exactly in u.
 *
 * Unknowns of node i: an incremental rotation phi_i (Q_i <- Q_i exp([phi_i]x))
 * and N_{i-1/2}; equations of node i involve nodes i-1, i, i+1 only, so the
 * Jacobian is banded (kl = ku = 11). It is formed by finite differences
 * with 3 colours (nodes 3 apart never share an equation): 18 residual
 * evaluations per Newton iteration, then a banded LU (LAPACK dgbtrf,
 * bordered for a held tip). Newton (static_settle.c) has a step limit, a
 * backtracking line search and, after a poor step, a damping of the
 * rotations past null modes (newton_damping); static_continuation.c splits
 * a load increment into sub-steps when it is large or when Newton fails.
 *
 * Constitutive law with a rest curvature: M = B (u - u0)
 * (thesis nomenclature, (3.4)); point loads F_i, M_i (dead, global, times
 * the tip's profile factor) enter node i's balance, a distributed moment m
 * (dead, global) enters as ds m (ds/2 m in the end half cells).
 *
 * End conditions (rod_end_kind in rod.h). Every node i = 0..NS-1 owns a
 * block of 6 unknowns and 6 equations; node 0's block holds phi_0 and 3
 * unused unknowns, and a held quantity gets the identity row (its increment
 * is zero). The ends' initial poses are the state's at t = 0 (the root's
 * position r_0 and frame Q_0^init, the tip's likewise); a driven end follows
 * rod_path_eval (position, and rotation R(t) of its initial frame for a
 * clamped end), a held one stays where it started. The centreline is
 * r_0(t) + sum ds d3_{j+1/2} (3.12).
 *   root clamped: Q_0 = R(t) Q_0^init held: the whole block is identity rows.
 *   root pinned: Q_0 = Q_0 exp(phi_0); r_0 held. "Twist held" is the
 *     holonomic swing-twist condition: the quaternion of Q_0 Q_0^init^T has
 *     no component along the initial d3 (Q_0 is the initial frame turned
 *     about an axis normal to it). The root moment M(0) = M_{1/2} + ds/2
 *     (d3_{1/2} x N_{1/2} + m) + M_0 (root half cell, as at the tip) has no
 *     components on the initial d1, d2: the torsion stop acts about the fixed
 *     initial d3 (see pinned_root_rows).
 *   root pinned, tip free: the rod hangs from the pin along its loads; a
 *     force must act off the pin (else its direction is undetermined:
 *     refused, at create or at the step). The rod is first swung rigidly to
 *     the least potential of the loads (swing_to_rest, static_continuation.c:
 *     Newton cannot reach a rest a quarter turn away, the swing's stiffness
 *     being the loads'), and the pin's moment rows are the workless ones of
 *     its swing-twist condition (static_swing_axes).
 *   root free, tip pinned or clamped (in place or driven), and a sliding
 *     root with a tip held in place: solved as the mirrored rod
 *     (static_mirror.c), a root held in place or driven with a
 *     free or sliding tip. static_work_create itself refuses a free root,
 *     and a sliding root with a free or sliding tip (the rod could slide
 *     along the sleeve as a whole: not determined), as static_mirror_create
 *     refuses a free root with a sliding tip.
 *   tip pinned / clamped: r_tip on its sleeve (the line through its target
 *     along tip_slide: 2 rows, the reaction R on the sleeve's two normals) or
 *     in place (3 rows, R with 3 components), R added to the tip force. Those
 *     rows are dense (every rotation moves the tip), so the linear system is
 *     the band bordered by 2 or 3 rows and columns, solved by block
 *     elimination (Schur complement of the band's LU).
 *   tip clamped in place: Q_tip = R(t) Q_tip^init held (identity rows in
 *     place of the tip moment rows; the moment is the reaction).
 *   tip clamped on a sleeve: the tip moment rows across the slide are
 *     replaced by d3_tip . n = 0 for its two normals n (bending held, twist
 *     about the slide free).
 * Reactions at a held tip are reported in the state's tip entries: the tip
 * contact_force entry is the applied tip force plus R, and the tip darboux
 * entry is u0 + B^-1 (applied moment + reaction moment), on the tip
 * directors; end_force / end_moment are what the rod exerts on its supports
 * (N(0), M(0) at the root; -R and minus the reaction moment at the tip). */
#include "sim/static/static_solve.h"

#include <math.h>
#include <string.h>

#include "sim/rod_geometry.h"
#include "sim/static/static_internal.h"
#include "base/vec3.h"

/* Tip force and moment in global components for the tip frame q_tip. */
void static_tip_load_global(const static_work *w, const rod_model *m, const static_load *load,
                            const double q_tip[9], double force[3], double moment[3])
{
    int tip = w->nodes - 1;
    if (m->tip_frame == ROD_FRAME_DIRECTOR) { /* follower: N = Q_tip N_bar (thesis 4.2) */
        m3_mul_v(force, q_tip, load->tip_force);
        m3_mul_v(moment, q_tip, load->tip_moment);
    } else {
        v3_copy(force, load->tip_force);
        v3_copy(moment, load->tip_moment);
    }
    /* a point load at the tip node acts with the tip load (dead, global) */
    v3_axpy(force, load->point_factor, &w->node_force[3 * tip]);
    v3_axpy(moment, load->point_factor, &w->node_moment[3 * tip]);
}

/* The held tip's reaction at the trial point (the base point for a NULL
 * increment), N, global. */
void static_tip_reaction(const static_work *w, const double *increment, double reaction[3])
{
    v3_set(reaction, 0.0, 0.0, 0.0);
    for (int k = 0; k < w->border; k++)
        v3_axpy(reaction, w->reaction[k] +
                              (increment ? w->force_scale * increment[w->band_unknowns + k] : 0.0),
                w->reaction_dir[k]);
}

/* N_{j+1/2} at the trial point: the force unknown of node j + 1. */
static void trial_force(const static_work *w, const double *increment, int j, double force[3])
{
    const double *change = &increment[UNKNOWNS_PER_NODE * (j + 1) + 3];
    for (int k = 0; k < 3; k++) force[k] = w->force[3 * j + k] + w->force_scale * change[k];
}

/* The axes about which a pinned root at frame q0 may turn, and about
 * which the pin carries no moment (pinned_root_rows). With a held tip: the
 * initial d1, d2 (the fixed-axis stop of Greenhill's problem, for the small
 * swings there). With a free tip the rod swings far, to hang along its
 * loads (by pi/2 from a horizontal start), and a fixed-axis stop would
 * hold its bending there; decided: the stop's reaction is then the
 * workless one of the swing-twist condition, along c = q_w t0 + q_v x t0
 * (the quaternion (q_w, q_v) of Q_0 Q_init^T: the turns that keep its t0
 * component zero are those normal to c), and the axes span the plane
 * normal to c (the initial d1, d2 at no swing). */
void static_swing_axes(const static_work *w, const double q0[9], double axes[2][3])
{
    v3_copy(axes[0], w->root_axes[1]);
    v3_copy(axes[1], w->root_axes[2]);
    if (!swinging(w)) return;
    double r[9], v[3], c[3];
    for (int a = 0; a < 3; a++) /* Q_0 Q_init^T */
        for (int b = 0; b < 3; b++) r[3 * a + b] = v3_dot(&q0[3 * a], &w->root_frame0[3 * b]);
    v3_set(v, r[7] - r[5], r[2] - r[6], r[3] - r[1]); /* 4 q_w q_v */
    v3_cross(c, v, w->root_axes[0]);
    v3_axpy(c, 1.0 + r[0] + r[4] + r[8], w->root_axes[0]); /* 4 q_w c */
    double norm = v3_norm(c);
    if (!(norm > 1e-12)) return; /* a half turn: the rows are singular there anyway */
    v3_scale(c, c, 1.0 / norm);
    v3_axpy(axes[0], -v3_dot(axes[0], c), c);
    v3_scale(axes[0], axes[0], 1.0 / v3_norm(axes[0]));
    v3_cross(axes[1], c, axes[0]);
}

/* Rows of a pinned root (block 0, rows 0-2), on its initial frame (t0 =
 * d3, a0 = d1, b0 = d2 at t = 0). Twist held: the quaternion of
 * Q_0 Q_init^T has no t0 component (a holonomic condition: Q_0 is the
 * initial frame turned about an axis normal to t0). The torsion stop is a
 * moment about the fixed t0 axis, so the pin carries no moment about a0 and
 * b0: M(0).a0 = M(0).b0 = 0. This is the support Greenhill's problem assumes
 * (an axial, dead moment at both ends); the stop's moment about t0 then does
 * a little work when the root swings, as any dead axial moment does. */
static void pinned_root_rows(const static_work *w, const double root_moment[3], double *row)
{
    double q[9], v[3], axes[2][3];
    for (int r = 0; r < 3; r++) /* Q_0 Q_init^T */
        for (int c = 0; c < 3; c++)
            q[3 * r + c] = w->frame_trial[3 * r] * w->root_frame0[3 * c] +
                           w->frame_trial[3 * r + 1] * w->root_frame0[3 * c + 1] +
                           w->frame_trial[3 * r + 2] * w->root_frame0[3 * c + 2];
    double c = 0.5 * sqrt(fmax(1e-300, 1.0 + q[0] + q[4] + q[8]));
    v3_set(v, q[7] - q[5], q[2] - q[6], q[3] - q[1]);
    static_swing_axes(w, w->frame_trial, axes);
    row[0] = w->angle_row_scale * 2.0 * v3_dot(v, w->root_axes[0]) / (4.0 * c);
    row[1] = w->moment_row_scale * v3_dot(root_moment, axes[0]);
    row[2] = w->moment_row_scale * v3_dot(root_moment, axes[1]);
}

/* The moment M_{j+1/2} = Q B (u - u_rest) (thesis (3.4) with a rest
 * curvature, nomenclature), global, for the trial Darboux vectors. The rest
 * curvature goes from the starting state's own u (so that any starting
 * shape is the path's unloaded start: an initial centreline bent without
 * u0 springs back along the path) to u0. */
void static_midpoint_moments(static_work *w, const rod_model *m, double curvature)
{
    for (int j = 0; j + 1 < w->nodes; j++) {
        const double *u = &w->darboux[3 * j], *start = &w->start_darboux[3 * j];
        double bu[3];
        for (int k = 0; k < 3; k++)
            bu[k] = m->stiffness[k] * (u[k] - curvature * m->intrinsic_curvature[k] -
                                       (1.0 - curvature) * start[k]);
        m3_mul_v(&w->moment[3 * j], &w->mid[9 * j], bu);
    }
}

/* Residual of the discrete equilibrium at frames Q_i exp(phi_i) and forces
 * N + force_scale dN, with (phi, dN) = `increment`. Writes `out` and leaves
 * the trial frames, Darboux vectors and midpoint frames in the work.
 * Loads at node i: ds T and ds m (distributed force and moment, half at
 * the tip), the point load F_i, M_i. */
void static_evaluate_residual(static_work *w, const rod_model *m, const static_load *load,
                              const double *increment, double *out)
{
    int n = w->nodes;
    double ds = m->ds;
    int tip_frame_held = w->tip_end == ROD_END_CLAMPED && !w->tip_sliding;
    for (int i = 0; i < n; i++) {
        if ((i == 0 && w->root_end == ROD_END_CLAMPED) || (i == n - 1 && tip_frame_held)) {
            memcpy(&w->frame_trial[9 * i], &w->frame[9 * i], 9 * sizeof(double)); /* held */
            continue;
        }
        double rot[9];
        m3_exp(rot, &increment[UNKNOWNS_PER_NODE * i]);
        m3_mul(&w->frame_trial[9 * i], &w->frame[9 * i], rot);
    }
    rod_darboux_from_frames(m, w->frame_trial, w->darboux);
    rod_midpoint_frames(m, w->frame_trial, w->darboux, w->mid);
    static_midpoint_moments(w, m, load->curvature);
    double tip_force[3], tip_moment[3], reaction[3];
    static_tip_load_global(w, m, load, &w->frame_trial[9 * (n - 1)], tip_force, tip_moment);
    static_tip_reaction(w, increment, reaction);
    v3_add(tip_force, tip_force, reaction);
    double pf = load->point_factor;

    double force_left[3], d3_left[3], torque_left[3];
    trial_force(w, increment, 0, force_left);
    m3_column(d3_left, &w->mid[0], 2);
    v3_cross(torque_left, d3_left, force_left);

    /* node 0: held unknowns get identity rows, ordered like the other
     * blocks' rows (axial, y, z): row 0 holds phi_3 (about d3 = x) */
    out[0] = increment[2];
    out[1] = increment[0];
    out[2] = increment[1];
    for (int k = 3; k < UNKNOWNS_PER_NODE; k++) out[k] = increment[k];
    if (w->root_end == ROD_END_PINNED) {
        double root_moment[3]; /* root half cell: M(0) = M_{1/2} + ds/2 (d3_{1/2} x N_{1/2} + m) + M_0 */
        for (int k = 0; k < 3; k++)
            root_moment[k] = w->moment[k] + 0.5 * ds * (torque_left[k] + load->distributed_moment[k]) +
                             pf * w->node_moment[k];
        pinned_root_rows(w, root_moment, out);
    }
    for (int i = 1; i < n; i++) {
        double *row = &out[UNKNOWNS_PER_NODE * i];
        const double *moment_left = &w->moment[3 * (i - 1)];
        if (i < n - 1) {
            double force_right[3], d3_right[3], torque_right[3];
            trial_force(w, increment, i, force_right);
            m3_column(d3_right, &w->mid[9 * i], 2);
            v3_cross(torque_right, d3_right, force_right);
            const double *moment_right = &w->moment[3 * i];
            /* (3.3)_1 and (3.3)_2 without inertia, integrated over the cell
             * between midpoints i-1/2 and i+1/2 (global components) */
            for (int k = 0; k < 3; k++) {
                row[k] = w->force_row_scale * (force_right[k] - force_left[k] +
                                               ds * load->distributed[k] + pf * w->node_force[3 * i + k]);
                row[3 + k] = w->moment_row_scale *
                             (moment_right[k] - moment_left[k] +
                              0.5 * ds * (torque_right[k] + torque_left[k]) +
                              ds * load->distributed_moment[k] + pf * w->node_moment[3 * i + k]);
            }
            v3_copy(force_left, force_right);
            v3_copy(torque_left, torque_right);
            continue;
        }
        /* tip half cell: N(L) = N_bar, M(L) = M_bar (thesis 4.2 boundary condition) */
        double balance[3];
        for (int k = 0; k < 3; k++) {
            row[k] = w->force_row_scale *
                     (tip_force[k] - force_left[k] + 0.5 * ds * load->distributed[k]);
            balance[k] = tip_moment[k] - moment_left[k] +
                         0.5 * ds * (torque_left[k] + load->distributed_moment[k]);
            row[3 + k] = w->moment_row_scale * balance[k];
        }
        if (tip_frame_held) { /* the frame is held; the moment is a reaction */
            for (int k = 0; k < 3; k++) row[3 + k] = increment[UNKNOWNS_PER_NODE * i + k];
        } else if (w->tip_end == ROD_END_CLAMPED) {
            /* d3 held along the slide, twist about it free: the moment along
             * the slide balances, the others are reactions */
            double d3_tip[3];
            m3_column(d3_tip, &w->frame_trial[9 * (n - 1)], 2);
            row[3] = w->moment_row_scale * v3_dot(balance, w->slide);
            row[4] = w->angle_row_scale * v3_dot(d3_tip, w->reaction_dir[0]);
            row[5] = w->angle_row_scale * v3_dot(d3_tip, w->reaction_dir[1]);
        }
    }
    if (tip_held(w)) { /* r_tip = r_0 + sum ds d3_{j+1/2} (3.12): on its line, or in place */
        double gap[3];
        v3_sub(gap, load->root_position, load->tip_position);
        for (int j = 0; j + 1 < n; j++)
            for (int k = 0; k < 3; k++) gap[k] += ds * w->mid[9 * j + 3 * k + 2];
        for (int k = 0; k < w->border; k++)
            out[w->band_unknowns + k] = w->position_row_scale * v3_dot(gap, w->reaction_dir[k]);
    }
}

/* Forces that satisfy the force balance exactly for the current tip frame
 * and reaction: N_{NS-3/2} = N_tip + ds/2 T, N_{i-1/2} = N_{i+1/2} + ds T + F_i. */
void static_forces_from_statics(static_work *w, const rod_model *m, const static_load *load)
{
    int n = w->nodes;
    double tip_force[3], tip_moment[3], reaction[3];
    static_tip_load_global(w, m, load, &w->frame[9 * (n - 1)], tip_force, tip_moment);
    static_tip_reaction(w, NULL, reaction);
    double *last = &w->force[3 * (n - 2)];
    for (int k = 0; k < 3; k++)
        last[k] = tip_force[k] + reaction[k] + 0.5 * m->ds * load->distributed[k];
    for (int j = n - 3; j >= 0; j--)
        for (int k = 0; k < 3; k++)
            w->force[3 * j + k] = w->force[3 * (j + 1) + k] + m->ds * load->distributed[k] +
                                  load->point_factor * w->node_force[3 * (j + 1) + k];
}

/* Jacobian at the base point by finite differences: the band with 3 colours
 * x 6 components (nodes 3 apart never share an equation), and for a held
 * tip the border. A node's turn moves the tip only through the two midpoint
 * frames next to it, so the dense position rows come from the same colour
 * sweeps, node by node. Leaves the base residual in `w->residual`. */
void static_build_jacobian(static_work *w, const rod_model *m, const static_load *load)
{
    int n = w->nodes, nb = w->band_unknowns, ldab = w->band_rows;
    double ds = m->ds, h = w->fd_increment;
    memset(w->increment, 0, (size_t)w->unknowns * sizeof(double));
    static_evaluate_residual(w, m, load, w->increment, w->residual);
    memcpy(w->mid_base, w->mid, (size_t)(n - 1) * 9 * sizeof(double));
    memset(w->band, 0, (size_t)ldab * (size_t)nb * sizeof(double));
    for (int colour = 0; colour < COLOURS; colour++) {
        for (int b = 0; b < UNKNOWNS_PER_NODE; b++) {
            memset(w->increment, 0, (size_t)w->unknowns * sizeof(double));
            for (int i = colour; i < n; i += COLOURS) w->increment[UNKNOWNS_PER_NODE * i + b] = h;
            static_evaluate_residual(w, m, load, w->increment, w->residual_trial);
            for (int i = colour; i < n; i += COLOURS) {
                int col = UNKNOWNS_PER_NODE * i + b;
                int first = i - 1 < 0 ? 0 : i - 1, last = i + 1 > n - 1 ? n - 1 : i + 1;
                for (int row = UNKNOWNS_PER_NODE * first; row < UNKNOWNS_PER_NODE * (last + 1); row++)
                    w->band[(size_t)col * ldab + (BAND_LOWER + BAND_UPPER + row - col)] =
                        (w->residual_trial[row] - w->residual[row]) / h;
                if (!w->border) continue;
                double moved[3] = {0.0, 0.0, 0.0};
                for (int j = i - 1; j <= i; j++) {
                    if (j < 0 || j > n - 2 || b >= 3) continue;
                    for (int k = 0; k < 3; k++)
                        moved[k] += ds * (w->mid[9 * j + 3 * k + 2] - w->mid_base[9 * j + 3 * k + 2]);
                }
                for (int k = 0; k < w->border; k++)
                    w->border_rows[(size_t)k * nb + col] =
                        w->position_row_scale * v3_dot(moved, w->reaction_dir[k]) / h;
            }
        }
    }
    if (w->border) { /* the reaction enters the tip force rows along its directions */
        memset(w->border_columns, 0, (size_t)nb * w->border * sizeof(double));
        for (int k = 0; k < w->border; k++)
            for (int r = 0; r < 3; r++)
                w->border_columns[(size_t)k * nb + UNKNOWNS_PER_NODE * (n - 1) + r] =
                    w->force_row_scale * w->force_scale * w->reaction_dir[k][r];
    }
}

/* Solves the size x size system a x = b (size <= MAX_BORDER) in place in b
 * by elimination with partial pivoting. Returns -1 when a pivot is below
 * `smallest` times the matrix's largest entry (singular). */
static int solve_small_below(int size, double a[MAX_BORDER][MAX_BORDER], double b[MAX_BORDER],
                             double smallest)
{
    double largest = 0.0;
    for (int r = 0; r < size; r++)
        for (int c = 0; c < size; c++) largest = fmax(largest, fabs(a[r][c]));
    if (!(largest > 0.0) || !isfinite(largest)) return -1;
    for (int k = 0; k < size; k++) {
        int pivot = k;
        for (int r = k + 1; r < size; r++)
            if (fabs(a[r][k]) > fabs(a[pivot][k])) pivot = r;
        if (!(fabs(a[pivot][k]) > smallest * largest)) return -1;
        if (pivot != k) {
            for (int c = 0; c < size; c++) {
                double t = a[k][c];
                a[k][c] = a[pivot][c];
                a[pivot][c] = t;
            }
            double t = b[k];
            b[k] = b[pivot];
            b[pivot] = t;
        }
        for (int r = k + 1; r < size; r++) {
            double f = a[r][k] / a[k][k];
            for (int c = k; c < size; c++) a[r][c] -= f * a[k][c];
            b[r] -= f * b[k];
        }
    }
    for (int k = size - 1; k >= 0; k--) {
        for (int c = k + 1; c < size; c++) b[k] -= a[k][c] * b[c];
        b[k] /= a[k][k];
    }
    return 0;
}

/* The same, singular to round-off below 1e-13. */
int static_solve_small(int size, double a[MAX_BORDER][MAX_BORDER], double b[MAX_BORDER])
{
    return solve_small_below(size, a, b, 1e-13);
}

/* Solves J step = -residual with the Jacobian of static_build_jacobian (the band
 * is overwritten by its LU). For a held tip, J = [A B; C 0] by block
 * elimination. A alone (the tip reaction fixed) is singular for a pinned
 * root: the rod would swing about the pin. So the reaction is split as
 * R = R'' + G x, with G x = a transverse spring on the tip's turn (a tip
 * force -k L times its tilt across the initial chord c, k L^3/EI =
 * tip_spring), which only moves the unknown: A' = A + B G is regular for
 * every end pair (a beam pinned or clamped at the root with that spring at
 * its tip has no zero-load mode) and stays banded (G reaches the tip block
 * only). Then A' X = B, A' y = -r_band, (C X) dR'' = C y + r_border,
 * step = y - X dR'', dR = dR'' + G step. Returns 0, or -1 when singular. */
int static_solve_newton_step(static_work *w)
{
    static const double tip_spring = 10.0;
    int nb = w->band_unknowns, tip_block = UNKNOWNS_PER_NODE * (w->nodes - 1), nr = w->border;
    double spring[MAX_BORDER][3] = {{0}}; /* G on the tip's phi, in force_scale per rad */
    for (int i = 0; i < w->unknowns; i++) w->newton_step[i] = -w->residual[i];
    if (nr) {
        /* global turn omega = Q_tip phi; the tip moves by L omega x c, so the
         * spring along dir_k is -k omega . (c x dir_k) */
        const double *q_tip = &w->frame[9 * (w->nodes - 1)];
        double chord[3];
        v3_sub(chord, w->tip_position0, w->root_position0);
        if (!(v3_norm(chord) > 1e-6 * w->length)) m3_column(chord, w->root_frame0, 2);
        v3_scale(chord, chord, 1.0 / v3_norm(chord));
        double coupling = w->force_row_scale * w->force_scale;
        for (int k = 0; k < nr; k++) {
            double across[3];
            v3_cross(across, chord, w->reaction_dir[k]);
            for (int b = 0; b < 3; b++)
                spring[k][b] = -tip_spring * (q_tip[b] * across[0] + q_tip[3 + b] * across[1] +
                                              q_tip[6 + b] * across[2]);
        }
        for (int b = 0; b < 3; b++)
            for (int r = 0; r < 3; r++) { /* B G: the tip force rows */
                double value = 0.0;
                for (int k = 0; k < nr; k++) value += w->reaction_dir[k][r] * spring[k][b];
                int row = tip_block + r, col = tip_block + b;
                w->band[(size_t)col * w->band_rows + (BAND_LOWER + BAND_UPPER + row - col)] +=
                    coupling * value;
            }
    }
    lapack_int info = LAPACKE_dgbtrf(LAPACK_COL_MAJOR, nb, nb, BAND_LOWER, BAND_UPPER, w->band,
                                     w->band_rows, w->pivots);
    if (info != 0) return -1;
    info = LAPACKE_dgbtrs(LAPACK_COL_MAJOR, 'N', nb, BAND_LOWER, BAND_UPPER, 1, w->band,
                          w->band_rows, w->pivots, w->newton_step, nb);
    if (info != 0) return -1;
    if (!nr) return 0;
    memcpy(w->border_solution, w->border_columns, (size_t)nb * nr * sizeof(double));
    info = LAPACKE_dgbtrs(LAPACK_COL_MAJOR, 'N', nb, BAND_LOWER, BAND_UPPER, nr, w->band,
                          w->band_rows, w->pivots, w->border_solution, nb);
    if (info != 0) return -1;
    double schur[MAX_BORDER][MAX_BORDER] = {{0}}, d_reaction[MAX_BORDER];
    for (int k = 0; k < nr; k++) {
        const double *c = &w->border_rows[(size_t)k * nb];
        d_reaction[k] = w->residual[nb + k];
        for (int i = 0; i < nb; i++) d_reaction[k] += c[i] * w->newton_step[i];
        for (int l = 0; l < nr; l++)
            for (int i = 0; i < nb; i++) schur[k][l] += c[i] * w->border_solution[(size_t)l * nb + i];
    }
    double schur_copy[MAX_BORDER][MAX_BORDER], rhs[MAX_BORDER];
    memcpy(schur_copy, schur, sizeof schur);
    memcpy(rhs, d_reaction, sizeof rhs);
    /* A straight rod between ends held exactly L apart: the chord's length
     * is stationary, so the axial reaction is undetermined (any tension
     * balances: an axial force turns no node of a straight rod, so the
     * Schur complement's axial pivot is round-off; a rod bent by a has one
     * of ~a^2 relative). Below 1e-9: least squares with a ridge, the
     * smallest reaction change that meets the other rows. */
    if (solve_small_below(nr, schur, d_reaction, nr == 3 ? 1e-9 : 1e-13) != 0) {
        double normal[MAX_BORDER][MAX_BORDER] = {{0}}, largest = 0.0;
        for (int k = 0; k < nr; k++)
            for (int l = 0; l < nr; l++) {
                for (int i = 0; i < nr; i++) normal[k][l] += schur_copy[i][k] * schur_copy[i][l];
                largest = fmax(largest, fabs(normal[k][l]));
            }
        for (int k = 0; k < nr; k++) {
            d_reaction[k] = 0.0;
            for (int i = 0; i < nr; i++) d_reaction[k] += schur_copy[i][k] * rhs[i];
            normal[k][k] += 1e-12 * largest;
        }
        if (static_solve_small(nr, normal, d_reaction) != 0) return -1;
    }
    for (int l = 0; l < nr; l++)
        for (int i = 0; i < nb; i++)
            w->newton_step[i] -= w->border_solution[(size_t)l * nb + i] * d_reaction[l];
    for (int k = 0; k < nr; k++) {
        w->newton_step[nb + k] = d_reaction[k];
        for (int b = 0; b < 3; b++) w->newton_step[nb + k] += spring[k][b] * w->newton_step[tip_block + b];
    }
    return 0;
}

/* Moves the base point to the trial point left by the last evaluation. */
void static_accept_trial(static_work *w)
{
    int n = w->nodes;
    for (int i = w->root_end == ROD_END_PINNED ? 0 : 1; i < n; i++) {
        memcpy(&w->frame[9 * i], &w->frame_trial[9 * i], 9 * sizeof(double));
        m3_orthonormalize(&w->frame[9 * i]);
    }
    for (int j = 0; j + 1 < n; j++)
        for (int k = 0; k < 3; k++)
            w->force[3 * j + k] += w->force_scale * w->increment[UNKNOWNS_PER_NODE * (j + 1) + 3 + k];
    for (int k = 0; k < w->border; k++)
        w->reaction[k] += w->force_scale * w->increment[w->band_unknowns + k];
}

/* J - c D on the Jacobian just built: D the identity on the free
 * rotations' moment rows (omega = Q phi), c in the reduced stiffness' units
 * (static_capture_stiffness). */
void static_damp_rotations(static_work *w, double damping)
{
    if (damping == 0.0) return;
    for (int a = 0; a < w->dofs; a++) { /* row_a -= c omega_a, omega = Q phi */
        const double *q = &w->frame[9 * w->dof_node[a]], *dir = &w->dof_dir[3 * a];
        int row = w->dof_row[a];
        for (int c = 0; c < 3; c++) {
            int col = UNKNOWNS_PER_NODE * w->dof_node[a] + c;
            w->band[(size_t)col * w->band_rows + (BAND_LOWER + BAND_UPPER + row - col)] -=
                damping * (q[c] * dir[0] + q[3 + c] * dir[1] + q[6 + c] * dir[2]);
        }
    }
}
