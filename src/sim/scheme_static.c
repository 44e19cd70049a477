/* scheme_static.c: the equilibrium of the rod under the loads at
 * s->time + dt, solved directly (no time stepping): thesis (3.6) with the
 * time derivatives dropped and (3.4) M = B u, on the staggered grid of
 * rod_geometry.h. A sequence of steps follows the quasi-static load path:
 * each step starts from the current state.
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
 * evaluations per Newton iteration, then a banded LU (LAPACK dgbtrf, bordered for a held tip). Newton has a step
 * limit and a backtracking line search; a load increment is split into
 * sub-steps (load continuation) when it is large or when Newton fails.
 *
 * Past the buckling load a straight rod is an (unstable) equilibrium too,
 * and Newton finds it. So every answer under dead forces is checked: the
 * tangent stiffness on the free rotations (the forces N, multipliers of
 * inextensibility, eliminated by statics) must be positive definite on the
 * constraint manifold (a held tip's sleeve); its negative eigenvalues are
 * counted by a band LDL^T (Sylvester's law of inertia). An unstable answer
 * is left along its critical mode, to the side the load's transverse part
 * pulls (or +y, with a warning, when the load is symmetric), by an
 * over-damped descent (pseudo-transient continuation) to a stable rest; when
 * none is found the step fails rather than return it. A follower load or a
 * tip moment is not conservative and has no static criterion: not checked.
 * rod_buckling_factor (buckling.h) finds where the straight rod stops being
 * stable from this scheme's Jacobian.
 *
 * Every loop has a budget (Newton iterations, line-search halvings, load
 * sub-steps, descent iterations, solves per run), a load whose size in the
 * rod's scales is not finite is refused, and a bend of more than
 * ROD_UNRESOLVED_BEND between nodes is refused as the implicit scheme does.
 *
 * End conditions (rod_end_kind in rod.h). Every node i = 0..NS-1 owns a
 * block of 6 unknowns and 6 equations; node 0's block holds phi_0 and 3
 * unused unknowns, and a held quantity gets the identity row (its increment
 * is zero):
 *   root clamped: Q_0 held: the whole block is identity rows.
 *   root pinned: Q_0 = Q_0 exp(phi_0); r_0 held. "Twist about x held" is the
 *     holonomic swing-twist condition: the quaternion of Q_0 Q_init^T has no
 *     x component (Q_0 is the straight frame turned about an axis normal to
 *     x). The root moment M(0) = M_{1/2} + ds/2 d3_{1/2} x N_{1/2} (root half
 *     cell, as at the tip) has no y, z components: the torsion stop acts
 *     about the fixed x axis (see pinned_root_rows).
 *     A pinned root with a free tip is a mechanism and is refused.
 *   tip pinned / clamped: r_tip = sum ds d3_{j+1/2} must stay on the x axis:
 *     two more unknowns, the support reaction R = (0, R_y, R_z) global added
 *     to the tip force, and two more rows y_tip = z_tip = 0. Those rows are
 *     dense (every rotation moves the tip), so the linear system is the band
 *     bordered by 2 rows and columns, solved by block elimination (Schur
 *     complement of the band's LU).
 *   tip clamped: the tip moment rows y, z are replaced by d3_tip,y = d3_tip,z
 *     = 0 (bending rotations held, twist about x free); the held moment
 *     components become the reaction.
 * Reactions at a held tip are reported in the state's tip entries: the tip
 * contact_force entry is the applied tip force plus R, and the tip darboux
 * entry is B^-1 (applied moment + reaction moment), on the tip directors. */
#include "sim/scheme_static.h"

#include <complex.h>
#include <float.h>
#include <lapacke.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sim/rod_geometry.h"
#include "base/vec3.h"

enum {
    UNKNOWNS_PER_NODE = 6,
    BAND_LOWER = 11, /* node i's equations reach the unknowns of nodes i-1..i+1 */
    BAND_UPPER = 11,
    COLOURS = 3,
    MAX_BORDER = 2,  /* tip reaction R_y, R_z and the rows y_tip = z_tip = 0 */
    STIFFNESS_BAND = 5 /* half bandwidth of the reduced stiffness: up to 3 rotations a node */
};

/* Largest load change per continuation sub-step, in units of the rod's own
 * scales (|F| L^2/EI + |M| L/EI + |T| L^3/EI): about one radian of bending. */
static const double max_load_increment = 1.0;
/* Smallest continuation sub-step, as a fraction of the step's load change. */
static const double min_load_fraction = 1.0 / 4096.0;
/* Newton step limit: largest rotation increment of a node, rad. */
static const double max_rotation_step = 1.0;
/* Budgets (a step always ends): continuation sub-steps of one step, and
 * pseudo-time iterations of the descent off an unstable equilibrium. */
static const int max_sub_steps = 400;
static const int max_descent_iterations = 300;
/* Relative load increment once the load is large: a sub-step may add half
 * the load reached (the rod stiffens), so huge loads take log(size) steps. */
static const double relative_load_increment = 0.5;
/* A run of more static solves than this is refused (solver.dt far below the
 * output interval buys nothing: the equilibrium does not depend on dt). */
static const double max_solves_per_run = 1e6;
/* An eigenvalue of the reduced stiffness below -this is a loss of stability.
 * Unit: the stiffness rows' scale, in which the unloaded cantilever's
 * softest mode is about pi^2/4 at every NS (buckling at P = P_E (1 + 4e-4)
 * is seen); the finite-difference Jacobian's noise is ~1e-8 (L/ds)^2. */
static const double negative_eigenvalue = 1e-3;
/* The push along the critical mode off an unstable equilibrium: largest
 * node rotation, rad. */
static const double mode_push = 0.05;

/* The straight initial frame: d1 = +y, d2 = +z, d3 = +x (thesis 4.2). */
static const double straight_frame[9] = {0, 0, 1,
                                         1, 0, 0,
                                         0, 1, 0};

typedef struct static_load {
    double tip_force[3];   /* N, on the model's tip_frame */
    double tip_moment[3];  /* N m, on the model's tip_frame */
    double distributed[3]; /* N/m, global */
} static_load;

struct static_work {
    int nodes;
    int band_unknowns;   /* 6 nodes: the banded part */
    int border;          /* 0, or 2 when the tip is held (reaction unknowns, position rows) */
    int unknowns;        /* band_unknowns + border */
    int band_rows;       /* LAPACK band storage rows: 2 kl + ku + 1 */
    rod_end_kind root_end, tip_end;
    double force_scale;  /* EI / L^2, N: unknown forces are stored in this unit */
    double force_row_scale;  /* L^3 / (ds EI): force rows, dimensionless */
    double moment_row_scale; /* L^2 / (ds EI): moment rows, dimensionless */
    double angle_row_scale;  /* L^2 / ds^2: rows holding an angle (constraints), like a moment row */
    double position_row_scale; /* L / ds^2: rows holding a tip position, 1/m */
    double fd_increment;     /* finite-difference step: rad, and EI/L^2 for forces */

    double *frame;        /* (nodes x 9) the Newton base point */
    double *force;        /* (nodes-1 x 3) N_{j+1/2}, N, global, base point */
    double reaction[2];   /* R_y, R_z at a held tip, N, global, base point */
    double *frame_trial;  /* (nodes x 9) Q exp(phi) */
    double *darboux;      /* (nodes-1 x 3) 1/m, of the trial frames */
    double *mid;          /* (nodes-1 x 9) midpoint frames */
    double *mid_base;     /* (nodes-1 x 9) midpoint frames at the base point */
    double *moment;       /* (nodes-1 x 3) M_{j+1/2}, N m, global */
    double *increment;    /* (unknowns) trial increment: phi (rad), force (force_scale) */
    double *newton_step;  /* (unknowns) */
    double *residual;     /* (unknowns) at the base point */
    double *residual_trial; /* (unknowns) */
    double *band;         /* (band_rows x band_unknowns) column-major Jacobian / LU */
    double *border_columns; /* (band_unknowns x border) column-major: d rows / d R */
    double *border_rows;  /* (border x band_unknowns) row-major: d (y_tip, z_tip) rows / d unknowns */
    double *border_solution; /* (band_unknowns x border) A^-1 border_columns */
    lapack_int *pivots;   /* (band_unknowns) */
    double *saved_frame;  /* (nodes x 9) last converged continuation point */
    double *saved_force;  /* (nodes-1 x 3) */
    double saved_reaction[2];
    double complex *tangent; /* (transverse x transverse) for the buckling determinant, made on first use */

    /* Stability: the tangent stiffness reduced to the free rotations (global
     * components omega, the forces N eliminated by statics), symmetric, on
     * `dofs` rotations; K = -Q^T dR/dphi in moment-row units (see
     * capture_stiffness). Constrained to the held tip's sleeve by `constraint`. */
    int dofs;
    int *dof_node;        /* (dofs) */
    int *dof_axis;        /* (dofs) global axis 0..2 of the rotation */
    int *dof_row;         /* (dofs) residual row of its moment balance */
    double *stiffness;    /* (STIFFNESS_BAND+1 x dofs) lower band, column-major */
    double *stiffness_work; /* (3 STIFFNESS_BAND+1 x dofs) copy destroyed by LAPACK */
    lapack_int *stiffness_pivots; /* (dofs) */
    double *constraint;   /* (2 x dofs) row-major: d (y_tip, z_tip) / d omega */
    double *eigen_work;   /* (2 dofs) inverse iteration: the iterate, K x */
    double *rotation_blocks; /* (nodes x 3 x 9) -d(moment rows of i)/d(omega of i-1, i, i+1) */
    double *mode;         /* (dofs x 3): mode, and two solves for the constraint */
    int stiffness_fresh;  /* stiffness captured at this step's solution's Newton */
    int have_verdict;     /* the state's unstable-mode count below is known */
    int negative_modes;   /* of the last solution */

    /* the load of the last solved step, the start of the next step's path */
    int have_previous;
    double previous_time; /* s */
    static_load previous;
};

static int tip_held(const static_work *w) { return w->tip_end != ROD_END_FREE; }

void static_work_destroy(static_work *w)
{
    if (!w) return;
    free(w->frame);
    free(w->force);
    free(w->frame_trial);
    free(w->darboux);
    free(w->mid);
    free(w->mid_base);
    free(w->moment);
    free(w->increment);
    free(w->newton_step);
    free(w->residual);
    free(w->residual_trial);
    free(w->band);
    free(w->border_columns);
    free(w->border_rows);
    free(w->border_solution);
    free(w->pivots);
    free(w->saved_frame);
    free(w->saved_force);
    free(w->tangent);
    free(w->dof_node);
    free(w->dof_axis);
    free(w->dof_row);
    free(w->stiffness);
    free(w->stiffness_work);
    free(w->stiffness_pivots);
    free(w->constraint);
    free(w->eigen_work);
    free(w->rotation_blocks);
    free(w->mode);
    free(w);
}

static void destroy(void *work) { static_work_destroy(work); }

static_work *static_work_create(const rod_model *m, char *err, size_t errlen)
{
    static const char *const end_names[] = {"clamped", "pinned", "free"};
    if (m->nodes < 3 || !(m->ds > 0.0)) {
        snprintf(err, errlen, "static: model not derived (nodes %d, ds %g)", m->nodes, m->ds);
        return NULL;
    }
    if (m->root_end == ROD_END_FREE) {
        snprintf(err, errlen, "static: the root (s = 0) must be clamped or pinned");
        return NULL;
    }
    if (m->root_end == ROD_END_PINNED && m->tip_end == ROD_END_FREE) {
        snprintf(err, errlen,
                 "static: ends root = pinned, tip = free make a mechanism (the rod swings "
                 "freely about the pin, so there is no static equilibrium to solve for); use "
                 "root = clamped, or hold the tip (tip = pinned or clamped)");
        return NULL;
    }
    if (m->tip_end != ROD_END_FREE && m->tip_end != ROD_END_PINNED &&
        m->tip_end != ROD_END_CLAMPED) {
        snprintf(err, errlen, "static: unknown tip end condition %d", (int)m->tip_end);
        return NULL;
    }
    (void)end_names;
    static_work *w = calloc(1, sizeof *w);
    if (!w) {
        snprintf(err, errlen, "static: out of memory");
        return NULL;
    }
    size_t n = (size_t)m->nodes;
    w->nodes = m->nodes;
    w->root_end = m->root_end;
    w->tip_end = m->tip_end;
    w->band_unknowns = UNKNOWNS_PER_NODE * m->nodes;
    w->border = tip_held(w) ? MAX_BORDER : 0;
    w->unknowns = w->band_unknowns + w->border;
    w->band_rows = 2 * BAND_LOWER + BAND_UPPER + 1;
    double ei = m->stiffness[0], length = m->length;
    w->force_scale = ei / (length * length);
    w->force_row_scale = length * length * length / (m->ds * ei);
    w->moment_row_scale = length * length / (m->ds * ei);
    w->angle_row_scale = length * length / (m->ds * m->ds);
    w->position_row_scale = length / (m->ds * m->ds);
    /* The residual carries round-off ~eps (L/ds)^2 (see `step`); balancing
     * that against the O(h) truncation gives h ~ sqrt(eps) L/ds. */
    w->fd_increment = sqrt(DBL_EPSILON) * length / m->ds;
    size_t nu = (size_t)w->unknowns, nb = (size_t)w->band_unknowns;
    size_t border = (size_t)(w->border > 0 ? w->border : 1);
    w->frame = malloc(n * 9 * sizeof(double));
    w->force = malloc((n - 1) * 3 * sizeof(double));
    w->frame_trial = malloc(n * 9 * sizeof(double));
    w->darboux = malloc((n - 1) * 3 * sizeof(double));
    w->mid = malloc((n - 1) * 9 * sizeof(double));
    w->mid_base = malloc((n - 1) * 9 * sizeof(double));
    w->moment = malloc((n - 1) * 3 * sizeof(double));
    w->increment = malloc(nu * sizeof(double));
    w->newton_step = malloc(nu * sizeof(double));
    w->residual = malloc(nu * sizeof(double));
    w->residual_trial = malloc(nu * sizeof(double));
    w->band = malloc((size_t)w->band_rows * nb * sizeof(double));
    w->border_columns = calloc(nb * border, sizeof(double));
    w->border_rows = calloc(nb * border, sizeof(double));
    w->border_solution = calloc(nb * border, sizeof(double));
    w->pivots = malloc(nb * sizeof(lapack_int));
    w->saved_frame = malloc(n * 9 * sizeof(double));
    w->saved_force = malloc((n - 1) * 3 * sizeof(double));
    /* the free rotations: none at a clamped root, swing (y, z) at a pinned
     * one, twist (x) only at a clamped tip, all three elsewhere */
    size_t most = 3 * n;
    w->dof_node = malloc(most * sizeof(int));
    w->dof_axis = malloc(most * sizeof(int));
    w->dof_row = malloc(most * sizeof(int));
    if (w->dof_node && w->dof_axis && w->dof_row) {
        for (int i = 0; i < m->nodes; i++) {
            for (int axis = 0; axis < 3; axis++) {
                int row = UNKNOWNS_PER_NODE * i + 3 + axis;
                if (i == 0 && (m->root_end == ROD_END_CLAMPED || axis == 0)) continue;
                if (i == 0) row = axis; /* pinned root: rows 1, 2 hold M(0)_y, M(0)_z */
                if (i == m->nodes - 1 && m->tip_end == ROD_END_CLAMPED && axis > 0) continue;
                w->dof_node[w->dofs] = i;
                w->dof_axis[w->dofs] = axis;
                w->dof_row[w->dofs] = row;
                w->dofs++;
            }
        }
    }
    size_t dofs = (size_t)w->dofs;
    w->stiffness = malloc((STIFFNESS_BAND + 1) * dofs * sizeof(double));
    w->stiffness_work = malloc((3 * STIFFNESS_BAND + 1) * dofs * sizeof(double));
    w->stiffness_pivots = malloc(dofs * sizeof(lapack_int));
    w->constraint = calloc(2 * dofs, sizeof(double));
    w->eigen_work = malloc(2 * dofs * sizeof(double));
    w->rotation_blocks = malloc(n * 27 * sizeof(double));
    w->mode = malloc(3 * dofs * sizeof(double));
    if (!w->frame || !w->force || !w->frame_trial || !w->darboux || !w->mid || !w->mid_base ||
        !w->moment || !w->increment || !w->newton_step || !w->residual || !w->residual_trial ||
        !w->band || !w->border_columns || !w->border_rows || !w->border_solution || !w->pivots ||
        !w->saved_frame || !w->saved_force || !w->dof_node || !w->dof_axis || !w->dof_row ||
        !w->stiffness || !w->stiffness_work || !w->stiffness_pivots || !w->constraint ||
        !w->eigen_work || !w->mode || !w->rotation_blocks) {
        static_work_destroy(w);
        snprintf(err, errlen, "static: out of memory for %d nodes", m->nodes);
        return NULL;
    }
    return w;
}

static void *create(const rod_model *m, char *err, size_t errlen)
{
    return static_work_create(m, err, errlen);
}

/* Tip force and moment in global components for the tip frame q_tip. */
static void tip_load_global(const rod_model *m, const static_load *load, const double q_tip[9],
                            double force[3], double moment[3])
{
    if (m->tip_frame == ROD_FRAME_DIRECTOR) { /* follower: N = Q_tip N_bar (thesis 4.2) */
        m3_mul_v(force, q_tip, load->tip_force);
        m3_mul_v(moment, q_tip, load->tip_moment);
    } else {
        v3_copy(force, load->tip_force);
        v3_copy(moment, load->tip_moment);
    }
}

/* N_{j+1/2} at the trial point: the force unknown of node j + 1. */
static void trial_force(const static_work *w, const double *increment, int j, double force[3])
{
    const double *change = &increment[UNKNOWNS_PER_NODE * (j + 1) + 3];
    for (int k = 0; k < 3; k++) force[k] = w->force[3 * j + k] + w->force_scale * change[k];
}

/* Rows of a pinned root (block 0, rows 0-2). Twist held: the quaternion
 * of Q_0 Q_init^T has no x component (a holonomic condition: Q_0 is the
 * straight frame turned about an axis normal to x). The torsion stop is a
 * moment about the fixed x axis, so the pin carries no moment about y and z:
 * M(0)_y = M(0)_z = 0. This is the support Greenhill's problem assumes (an
 * axial, dead moment at both ends); the stop's moment about x then does a
 * little work when the root swings, as any dead axial moment does. */
static void pinned_root_rows(const static_work *w, const double root_moment[3], double *row)
{
    double q[9];
    m3_mul(q, w->frame_trial, (const double[9]){0, 1, 0, 0, 0, 1, 1, 0, 0}); /* Q_0 Q_init^T */
    double c = 0.5 * sqrt(fmax(1e-300, 1.0 + q[0] + q[4] + q[8]));
    row[0] = w->angle_row_scale * 2.0 * (q[7] - q[5]) / (4.0 * c);
    row[1] = w->moment_row_scale * root_moment[1];
    row[2] = w->moment_row_scale * root_moment[2];
}

/* Residual of the discrete equilibrium at frames Q_i exp(phi_i) and forces
 * N + force_scale dN, with (phi, dN) = `increment`. Writes `out` and leaves
 * the trial frames, Darboux vectors and midpoint frames in the work. */
static void evaluate_residual(static_work *w, const rod_model *m, const static_load *load,
                              const double *increment, double *out)
{
    int n = w->nodes;
    double ds = m->ds;
    for (int i = 0; i < n; i++) {
        if (i == 0 && w->root_end == ROD_END_CLAMPED) { /* Q_0 held */
            memcpy(w->frame_trial, w->frame, 9 * sizeof(double));
            continue;
        }
        double rot[9];
        m3_exp(rot, &increment[UNKNOWNS_PER_NODE * i]);
        m3_mul(&w->frame_trial[9 * i], &w->frame[9 * i], rot);
    }
    rod_darboux_from_frames(m, w->frame_trial, w->darboux);
    rod_midpoint_frames(m, w->frame_trial, w->darboux, w->mid);
    for (int j = 0; j + 1 < n; j++) { /* (3.4) M = B u, to global components */
        const double *u = &w->darboux[3 * j];
        double bu[3] = {m->stiffness[0] * u[0], m->stiffness[1] * u[1], m->stiffness[2] * u[2]};
        m3_mul_v(&w->moment[3 * j], &w->mid[9 * j], bu);
    }
    double tip_force[3], tip_moment[3];
    tip_load_global(m, load, &w->frame_trial[9 * (n - 1)], tip_force, tip_moment);
    if (tip_held(w)) /* the support's reaction on the x axis sleeve */
        for (int k = 0; k < 2; k++)
            tip_force[1 + k] += w->reaction[k] + w->force_scale * increment[w->band_unknowns + k];

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
        double root_moment[3]; /* root half cell: M(0) = M_{1/2} + ds/2 d3_{1/2} x N_{1/2} */
        for (int k = 0; k < 3; k++) root_moment[k] = w->moment[k] + 0.5 * ds * torque_left[k];
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
                row[k] = w->force_row_scale *
                         (force_right[k] - force_left[k] + ds * load->distributed[k]);
                row[3 + k] = w->moment_row_scale *
                             (moment_right[k] - moment_left[k] +
                              0.5 * ds * (torque_right[k] + torque_left[k]));
            }
            v3_copy(force_left, force_right);
            v3_copy(torque_left, torque_right);
        } else { /* tip half cell: N(L) = N_bar, M(L) = M_bar (thesis 4.2 boundary condition) */
            for (int k = 0; k < 3; k++) {
                row[k] = w->force_row_scale *
                         (tip_force[k] - force_left[k] + 0.5 * ds * load->distributed[k]);
                row[3 + k] = w->moment_row_scale *
                             (tip_moment[k] - moment_left[k] + 0.5 * ds * torque_left[k]);
            }
            if (w->tip_end == ROD_END_CLAMPED) { /* d3 held along x; the moment is a reaction */
                double d3_tip[3];
                m3_column(d3_tip, &w->frame_trial[9 * (n - 1)], 2);
                row[4] = w->angle_row_scale * d3_tip[1];
                row[5] = w->angle_row_scale * d3_tip[2];
            }
        }
    }
    if (tip_held(w)) { /* r_tip = sum ds d3_{j+1/2} (3.12) stays on the x axis */
        double tip[2] = {0.0, 0.0};
        for (int j = 0; j + 1 < n; j++) {
            tip[0] += ds * w->mid[9 * j + 5]; /* d3 is column 2: entries 2, 5, 8 */
            tip[1] += ds * w->mid[9 * j + 8];
        }
        out[w->band_unknowns] = w->position_row_scale * tip[0];
        out[w->band_unknowns + 1] = w->position_row_scale * tip[1];
    }
}

/* Forces that satisfy the force balance exactly for the current tip frame
 * and reaction: N_{NS-3/2} = N_tip + ds/2 T, N_{i-1/2} = N_{i+1/2} + ds T. */
static void forces_from_statics(static_work *w, const rod_model *m, const static_load *load)
{
    int n = w->nodes;
    double tip_force[3], tip_moment[3];
    tip_load_global(m, load, &w->frame[9 * (n - 1)], tip_force, tip_moment);
    if (tip_held(w))
        for (int k = 0; k < 2; k++) tip_force[1 + k] += w->reaction[k];
    double *last = &w->force[3 * (n - 2)];
    for (int k = 0; k < 3; k++) last[k] = tip_force[k] + 0.5 * m->ds * load->distributed[k];
    for (int j = n - 3; j >= 0; j--)
        for (int k = 0; k < 3; k++)
            w->force[3 * j + k] = w->force[3 * (j + 1) + k] + m->ds * load->distributed[k];
}

static double max_abs(const double *a, int count)
{
    double worst = 0.0;
    for (int i = 0; i < count; i++) worst = fmax(worst, fabs(a[i]));
    return worst;
}

static double sum_squares(const double *a, int count)
{
    double sum = 0.0;
    for (int i = 0; i < count; i++) sum += a[i] * a[i];
    return sum;
}

/* Jacobian at the base point by finite differences: the band with 3 colours
 * x 6 components (nodes 3 apart never share an equation), and for a held
 * tip the border. A node's turn moves the tip only through the two midpoint
 * frames next to it, so the dense position rows come from the same colour
 * sweeps, node by node. Leaves the base residual in `w->residual`. */
static void build_jacobian(static_work *w, const rod_model *m, const static_load *load)
{
    int n = w->nodes, nb = w->band_unknowns, ldab = w->band_rows;
    double ds = m->ds, h = w->fd_increment;
    memset(w->increment, 0, (size_t)w->unknowns * sizeof(double));
    evaluate_residual(w, m, load, w->increment, w->residual);
    memcpy(w->mid_base, w->mid, (size_t)(n - 1) * 9 * sizeof(double));
    memset(w->band, 0, (size_t)ldab * (size_t)nb * sizeof(double));
    for (int colour = 0; colour < COLOURS; colour++) {
        for (int b = 0; b < UNKNOWNS_PER_NODE; b++) {
            memset(w->increment, 0, (size_t)w->unknowns * sizeof(double));
            for (int i = colour; i < n; i += COLOURS) w->increment[UNKNOWNS_PER_NODE * i + b] = h;
            evaluate_residual(w, m, load, w->increment, w->residual_trial);
            for (int i = colour; i < n; i += COLOURS) {
                int col = UNKNOWNS_PER_NODE * i + b;
                int first = i - 1 < 0 ? 0 : i - 1, last = i + 1 > n - 1 ? n - 1 : i + 1;
                for (int row = UNKNOWNS_PER_NODE * first; row < UNKNOWNS_PER_NODE * (last + 1); row++)
                    w->band[(size_t)col * ldab + (BAND_LOWER + BAND_UPPER + row - col)] =
                        (w->residual_trial[row] - w->residual[row]) / h;
                if (!w->border) continue;
                double moved[2] = {0.0, 0.0};
                for (int j = i - 1; j <= i; j++) {
                    if (j < 0 || j > n - 2 || b >= 3) continue;
                    moved[0] += ds * (w->mid[9 * j + 5] - w->mid_base[9 * j + 5]);
                    moved[1] += ds * (w->mid[9 * j + 8] - w->mid_base[9 * j + 8]);
                }
                for (int k = 0; k < 2; k++)
                    w->border_rows[(size_t)k * nb + col] = w->position_row_scale * moved[k] / h;
            }
        }
    }
    if (w->border) { /* the reaction enters the tip force rows y, z only */
        memset(w->border_columns, 0, (size_t)nb * 2 * sizeof(double));
        for (int k = 0; k < 2; k++)
            w->border_columns[(size_t)k * nb + UNKNOWNS_PER_NODE * (n - 1) + 1 + k] =
                w->force_row_scale * w->force_scale;
    }
}

/* Solves J step = -residual with the Jacobian of build_jacobian (the band
 * is overwritten by its LU). For a held tip, J = [A B; C 0] by block
 * elimination. A alone (the tip reaction fixed) is singular for a pinned
 * root: the rod would swing about the pin. So the reaction is split as
 * R = R'' + G x, with G x = a transverse spring on the tip's turn (a tip
 * force -k L times its tilt, k L^3/EI = tip_spring), which only moves the
 * unknown: A' = A + B G is regular for every end pair (a beam pinned or
 * clamped at the root with that spring at its tip has no zero-load mode)
 * and stays banded (G reaches the tip block only). Then A' X = B,
 * A' y = -r_band, (C X) dR'' = C y + r_border, step = y - X dR'',
 * dR = dR'' + G step. Returns 0, or -1 when singular. */
static int solve_newton_step(static_work *w)
{
    static const double tip_spring = 10.0;
    int nb = w->band_unknowns, tip_block = UNKNOWNS_PER_NODE * (w->nodes - 1);
    double spring[2][3] = {{0}}; /* G on the tip's phi, in force_scale per rad */
    for (int i = 0; i < w->unknowns; i++) w->newton_step[i] = -w->residual[i];
    if (w->border) {
        /* global turn omega = Q_tip phi; the tip moves by L (omega_z, -omega_y) */
        const double *q_tip = &w->frame[9 * (w->nodes - 1)];
        double coupling = w->force_row_scale * w->force_scale;
        for (int b = 0; b < 3; b++) {
            spring[0][b] = -tip_spring * q_tip[6 + b];
            spring[1][b] = tip_spring * q_tip[3 + b];
            for (int k = 0; k < 2; k++) {
                int row = tip_block + 1 + k, col = tip_block + b;
                w->band[(size_t)col * w->band_rows + (BAND_LOWER + BAND_UPPER + row - col)] +=
                    coupling * spring[k][b];
            }
        }
    }
    lapack_int info = LAPACKE_dgbtrf(LAPACK_COL_MAJOR, nb, nb, BAND_LOWER, BAND_UPPER, w->band,
                                     w->band_rows, w->pivots);
    if (info != 0) return -1;
    info = LAPACKE_dgbtrs(LAPACK_COL_MAJOR, 'N', nb, BAND_LOWER, BAND_UPPER, 1, w->band,
                          w->band_rows, w->pivots, w->newton_step, nb);
    if (info != 0) return -1;
    if (!w->border) return 0;
    memcpy(w->border_solution, w->border_columns, (size_t)nb * 2 * sizeof(double));
    info = LAPACKE_dgbtrs(LAPACK_COL_MAJOR, 'N', nb, BAND_LOWER, BAND_UPPER, 2, w->band,
                          w->band_rows, w->pivots, w->border_solution, nb);
    if (info != 0) return -1;
    double schur[2][2] = {{0, 0}, {0, 0}}, rhs[2];
    for (int k = 0; k < 2; k++) {
        const double *c = &w->border_rows[(size_t)k * nb];
        rhs[k] = w->residual[nb + k];
        for (int i = 0; i < nb; i++) rhs[k] += c[i] * w->newton_step[i];
        for (int l = 0; l < 2; l++)
            for (int i = 0; i < nb; i++) schur[k][l] += c[i] * w->border_solution[(size_t)l * nb + i];
    }
    double det = schur[0][0] * schur[1][1] - schur[0][1] * schur[1][0];
    if (!(fabs(det) > 0.0) || !isfinite(det)) return -1;
    double d_reaction[2] = {(schur[1][1] * rhs[0] - schur[0][1] * rhs[1]) / det,
                            (schur[0][0] * rhs[1] - schur[1][0] * rhs[0]) / det};
    for (int l = 0; l < 2; l++)
        for (int i = 0; i < nb; i++)
            w->newton_step[i] -= w->border_solution[(size_t)l * nb + i] * d_reaction[l];
    for (int k = 0; k < 2; k++) {
        w->newton_step[nb + k] = d_reaction[k];
        for (int b = 0; b < 3; b++) w->newton_step[nb + k] += spring[k][b] * w->newton_step[tip_block + b];
    }
    return 0;
}

/* Moves the base point to the trial point left by the last evaluation. */
static void accept_trial(static_work *w)
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

/* Stability ----------------------------------------------------------- */

static double *stiffness_at(static_work *w, int a, int b) /* lower band, a >= b */
{
    return &w->stiffness[(size_t)b * (STIFFNESS_BAND + 1) + (size_t)(a - b)];
}

/* From the Jacobian just built (band before its LU): the reduced tangent
 * stiffness K[a][b] = -d row_a / d omega_b on the free rotations. The
 * moment rows are -dPi/domega (Pi the potential energy; the forces N are
 * multipliers of inextensibility, fixed by statics independently of the
 * frames for dead loads), so K is the Hessian of Pi in global rotations,
 * in row units. The discrete moment balance is variational only up to
 * O(ds^2) (midpoint torques), so K is symmetrised. */
static void capture_stiffness(static_work *w)
{
    int dofs = w->dofs, nb = w->band_unknowns, n = w->nodes, ldab = w->band_rows;
    w->stiffness_fresh = 1;
    /* 3 x 3 blocks -J(moment rows of i, phi of j) Q_j^T, j = i-1, i, i+1
     * (d omega = Q d phi); a pinned root's moment rows are 0..2 */
    for (int i = 0; i < n; i++) {
        int first_row = i == 0 ? 0 : UNKNOWNS_PER_NODE * i + 3;
        for (int p = 0; p < 3; p++) {
            int j = i + p - 1;
            if (j < 0 || j >= n) continue;
            const double *q = &w->frame[9 * j];
            double *block = &w->rotation_blocks[27 * i + 9 * p];
            for (int r = 0; r < 3; r++) {
                double entry[3];
                for (int c = 0; c < 3; c++) {
                    int row = first_row + r, col = UNKNOWNS_PER_NODE * j + c;
                    entry[c] = w->band[(size_t)col * ldab + (BAND_LOWER + BAND_UPPER + row - col)];
                }
                for (int axis = 0; axis < 3; axis++)
                    block[3 * r + axis] = -(entry[0] * q[3 * axis] + entry[1] * q[3 * axis + 1] +
                                            entry[2] * q[3 * axis + 2]);
            }
        }
    }
    for (int a = 0; a < dofs; a++) { /* symmetrised: the discrete balance is variational to O(ds^2) */
        int i = w->dof_node[a], ra = w->dof_axis[a];
        for (int b = a; b >= 0 && a - b <= STIFFNESS_BAND; b--) {
            int j = w->dof_node[b], rb = w->dof_axis[b];
            double value = 0.0;
            if (abs(i - j) <= 1)
                value = 0.5 * (w->rotation_blocks[27 * i + 9 * (j - i + 1) + 3 * ra + rb] +
                               w->rotation_blocks[27 * j + 9 * (i - j + 1) + 3 * rb + ra]);
            *stiffness_at(w, a, b) = value;
        }
    }
    if (!w->border) return;
    for (int k = 0; k < 2; k++) /* the sleeve rows y_tip = z_tip = 0, by omega */
        for (int b = 0; b < dofs; b++) {
            const double *q = &w->frame[9 * w->dof_node[b]];
            const double *row = &w->border_rows[(size_t)k * nb + UNKNOWNS_PER_NODE * w->dof_node[b]];
            double sum = 0.0;
            for (int c = 0; c < 3; c++) sum += row[c] * q[3 * w->dof_axis[b] + c];
            w->constraint[(size_t)k * dofs + b] = sum;
        }
}

/* Factors K - shift I (general band LU in stiffness_work). Returns LAPACK's info. */
static lapack_int factor_shifted(static_work *w, double shift)
{
    int dofs = w->dofs, kd = STIFFNESS_BAND, ldab = 3 * kd + 1;
    memset(w->stiffness_work, 0, (size_t)ldab * (size_t)dofs * sizeof(double));
    for (int b = 0; b < dofs; b++)
        for (int a = b; a < dofs && a - b <= kd; a++) {
            double value = *stiffness_at(w, a, b) - (a == b ? shift : 0.0);
            w->stiffness_work[(size_t)b * ldab + (2 * kd + a - b)] = value; /* (a, b) */
            w->stiffness_work[(size_t)a * ldab + (2 * kd + b - a)] = value; /* (b, a) */
        }
    return LAPACKE_dgbtrf_work(LAPACK_COL_MAJOR, dofs, dofs, kd, kd, w->stiffness_work, ldab,
                               w->stiffness_pivots);
}

static int solve_shifted(static_work *w, double *x, int columns)
{
    int kd = STIFFNESS_BAND;
    return LAPACKE_dgbtrs_work(LAPACK_COL_MAJOR, 'N', w->dofs, kd, kd, columns, w->stiffness_work,
                               3 * kd + 1, w->stiffness_pivots, x, w->dofs) == 0 ? 0 : -1;
}

/* The number of eigenvalues of K below `shift`: the negative pivots of
 * the band LDL^T of K - shift I without pivoting (Sylvester's law of
 * inertia; the Sturm count of structural eigen solvers), O(dofs kd^2).
 * Returns -1 at an exactly zero pivot. */
static int eigenvalues_below(static_work *w, double shift)
{
    int dofs = w->dofs, kd = STIFFNESS_BAND, ldab = kd + 1, count = 0;
    double *l = w->stiffness_work; /* L below the diagonal, D on it, lower band */
    memcpy(l, w->stiffness, (size_t)ldab * (size_t)dofs * sizeof(double));
    for (int j = 0; j < dofs; j++) {
        int first = j - kd > 0 ? j - kd : 0;
        double d = l[(size_t)j * ldab] - shift;
        for (int k = first; k < j; k++) {
            double ljk = l[(size_t)k * ldab + (j - k)];
            d -= ljk * ljk * l[(size_t)k * ldab];
        }
        if (d == 0.0 || !isfinite(d)) return -1;
        l[(size_t)j * ldab] = d;
        if (d < 0.0) count++;
        for (int i = j + 1; i < dofs && i - j <= kd; i++) {
            double sum = l[(size_t)j * ldab + (i - j)];
            for (int k = (i - kd > first ? i - kd : first); k < j; k++)
                sum -= l[(size_t)k * ldab + (i - k)] * l[(size_t)k * ldab + (j - k)] * l[(size_t)k * ldab];
            l[(size_t)j * ldab + (i - j)] = sum / d;
        }
    }
    return count;
}

/* Solves (K - shift I) x = b in place with the LDL^T left by eigenvalues_below. */
static void ldlt_solve(const static_work *w, double *x)
{
    int dofs = w->dofs, kd = STIFFNESS_BAND, ldab = kd + 1;
    const double *l = w->stiffness_work;
    for (int j = 0; j < dofs; j++) /* L y = b */
        for (int i = j + 1; i < dofs && i - j <= kd; i++) x[i] -= l[(size_t)j * ldab + (i - j)] * x[j];
    for (int j = 0; j < dofs; j++) x[j] /= l[(size_t)j * ldab];
    for (int j = dofs - 1; j >= 0; j--) /* L^T x = y */
        for (int i = j + 1; i < dofs && i - j <= kd; i++) x[j] -= l[(size_t)j * ldab + (i - j)] * x[i];
}

/* The number of eigenvalues below `shift` of K on the constraint manifold.
 * A held tip adds the sleeve constraints C (2 rows): by Haynsworth's inertia
 * additivity the KKT matrix [K - shift I, C^T; C, 0] has the inertia of
 * K - shift I plus that of S = -C (K - shift I)^-1 C^T and, C being of full
 * rank, 2 negative eigenvalues more than K - shift I on the null space of C.
 * Returns -1 when it cannot be decided (a zero pivot: shift is an eigenvalue). */
static int manifold_eigenvalues_below(static_work *w, double shift)
{
    int count = eigenvalues_below(w, shift);
    if (count < 0 || !w->border) return count;
    int dofs = w->dofs;
    double *solved = &w->mode[dofs]; /* (K - shift I)^-1 C^T, 2 columns */
    memcpy(solved, w->constraint, 2 * (size_t)dofs * sizeof(double));
    ldlt_solve(w, solved);
    ldlt_solve(w, &solved[dofs]);
    double schur[2][2];
    for (int k = 0; k < 2; k++)
        for (int l = 0; l < 2; l++) {
            double sum = 0.0;
            for (int b = 0; b < dofs; b++) sum += w->constraint[(size_t)k * dofs + b] * solved[(size_t)l * dofs + b];
            schur[k][l] = -sum;
        }
    double trace = schur[0][0] + schur[1][1];
    double det = schur[0][0] * schur[1][1] - 0.25 * pow(schur[0][1] + schur[1][0], 2);
    if (!isfinite(det) || det == 0.0) return -1;
    int schur_negative = det < 0.0 ? 1 : trace < 0.0 ? 2 : 0;
    count += schur_negative - 2;
    return count < 0 ? 0 : count;
}

/* The number of unstable modes of the captured stiffness (eigenvalues below
 * -negative_eigenvalue on the constraint manifold), or -1: undecided. */
static int unstable_modes(static_work *w)
{
    return manifold_eigenvalues_below(w, -negative_eigenvalue);
}

/* The lowest eigenvalue of K on the constraint manifold, when it is below
 * `upper` (count there >= 1), by bisection on the count from Gershgorin's
 * lower bound, to 1e-4 relative. */
static double lowest_eigenvalue(static_work *w, double upper)
{
    int dofs = w->dofs;
    double low = 0.0;
    for (int a = 0; a < dofs; a++) {
        double bound = *stiffness_at(w, a, a);
        for (int b = a - STIFFNESS_BAND; b <= a + STIFFNESS_BAND; b++) {
            if (b < 0 || b >= dofs || b == a) continue;
            bound -= fabs(b < a ? *stiffness_at(w, a, b) : *stiffness_at(w, b, a));
        }
        low = fmin(low, bound);
    }
    low -= negative_eigenvalue;
    double high = upper;
    for (int iteration = 0; iteration < 80 && high - low > 1e-4 * fabs(high) + 1e-12; iteration++) {
        double middle = 0.5 * (low + high);
        int count = manifold_eigenvalues_below(w, middle);
        if (count < 0) count = manifold_eigenvalues_below(w, middle + 1e-9 * (high - low));
        if (count != 0) high = middle;
        else low = middle;
    }
    return high;
}

/* y = K x (symmetric, lower band) */
static void stiffness_multiply(static_work *w, const double *x, double *y)
{
    int dofs = w->dofs;
    for (int a = 0; a < dofs; a++) y[a] = 0.0;
    for (int b = 0; b < dofs; b++)
        for (int a = b; a < dofs && a - b <= STIFFNESS_BAND; a++) {
            double k = *stiffness_at(w, a, b);
            y[a] += k * x[b];
            if (a != b) y[b] += k * x[a];
        }
}

/* Inverse iteration with the factored K - shift I from `start` (per axis),
 * kept on the sleeve by Z = A^-1 C^T (columns z, y) and C Z = projection
 * (determinant det) for a held tip. Writes w->mode; returns the Rayleigh
 * quotient, NAN on failure. */
static double inverse_iteration(static_work *w, const double start[3], const double *z,
                                const double *y, double projection[2][2], double det)
{
    int dofs = w->dofs;
    double *x = w->mode;
    double *v = w->eigen_work; /* v, then K x */
    for (int a = 0; a < dofs; a++) v[a] = start[w->dof_axis[a]];
    for (int iteration = 0; iteration < 12; iteration++) {
        if (solve_shifted(w, v, 1)) return NAN;
        if (w->border) { /* v -= Z (C Z)^-1 C v: stay on the sleeve */
            double cv[2] = {0, 0}, mu[2];
            for (int k = 0; k < 2; k++)
                for (int b = 0; b < dofs; b++) cv[k] += w->constraint[(size_t)k * dofs + b] * v[b];
            mu[0] = (projection[1][1] * cv[0] - projection[0][1] * cv[1]) / det;
            mu[1] = (projection[0][0] * cv[1] - projection[1][0] * cv[0]) / det;
            for (int b = 0; b < dofs; b++) v[b] -= z[b] * mu[0] + y[b] * mu[1];
        }
        double norm = sqrt(sum_squares(v, dofs));
        if (!(norm > 0.0) || !isfinite(norm)) return NAN;
        for (int a = 0; a < dofs; a++) v[a] /= norm;
    }
    memcpy(x, v, (size_t)dofs * sizeof(double));
    double *kx = &w->eigen_work[dofs];
    stiffness_multiply(w, x, kx);
    double rayleigh = 0.0;
    for (int a = 0; a < dofs; a++) rayleigh += x[a] * kx[a];
    return rayleigh;
}

/* The critical mode: the eigenvector of K's lowest eigenvalue on the
 * constraint manifold (found by bisection on the count), by inverse
 * iteration with a shift just below it, into w->mode (unit norm).
 * Of a double eigenvalue (the round rod's y and z bending) the x-y plane's
 * mode is taken: a fixed, documented choice. Returns the Rayleigh quotient, or NAN on failure. */
static double critical_mode(static_work *w)
{
    int dofs = w->dofs;
    double lowest = lowest_eigenvalue(w, 0.0);
    double shift = lowest - fmax(0.01 * fabs(lowest), negative_eigenvalue);
    if (factor_shifted(w, shift) != 0) return NAN;
    double *z = &w->mode[dofs], *y = &w->mode[2 * dofs];
    double projection[2][2] = {{0, 0}, {0, 0}}, det = 1.0;
    if (w->border) { /* Z = A^-1 C^T (2 columns in z and y), and C Z */
        memcpy(z, w->constraint, 2 * (size_t)dofs * sizeof(double));
        if (solve_shifted(w, z, 2)) return NAN;
        for (int k = 0; k < 2; k++)
            for (int l = 0; l < 2; l++)
                for (int b = 0; b < dofs; b++)
                    projection[k][l] += w->constraint[(size_t)k * dofs + b] * z[(size_t)l * dofs + b];
        det = projection[0][0] * projection[1][1] - projection[0][1] * projection[1][0];
        if (!(fabs(det) > 0.0)) return NAN;
    }
    /* rotations about z first (the x-y plane's mode of a double eigenvalue,
     * exactly in plane); when that start misses the lowest eigenvalue (a
     * mode with no z turn), a start leaning on z with some x and y */
    static const double starts[2][3] = {{0.0, 0.0, 1.0}, {0.1, 0.3, 1.0}}; /* about x, y, z */
    double rayleigh = NAN;
    for (int attempt = 0; attempt < 2; attempt++) {
        rayleigh = inverse_iteration(w, starts[attempt], z, y, projection, det);
        if (rayleigh <= lowest + 0.05 * fabs(lowest) + negative_eigenvalue) break;
    }
    return rayleigh;
}

/* Turns every node by `scale` times the mode (global rotations). */
static void turn_along_mode(static_work *w, double scale)
{
    double omega[3];
    int a = 0;
    for (int i = 0; i < w->nodes; i++) {
        v3_set(omega, 0.0, 0.0, 0.0);
        for (; a < w->dofs && w->dof_node[a] == i; a++) omega[w->dof_axis[a]] = scale * w->mode[a];
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
        for (; a < dofs && w->dof_node[a] == i; a++) omega[i & 1][w->dof_axis[a]] = w->mode[a];
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
    tip_load_global(m, load, &w->frame[9 * (n - 1)], tip_force, tip_moment);
    for (int k = 0; k < 3; k++) pull[k] = tip_force[k] + m->length * load->distributed[k];
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
    forces_from_statics(w, m, load);
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
        evaluate_residual(w, m, load, w->increment, w->residual);
        double norm = max_abs(w->residual, nu);
        *residual_out = norm;
        if (!isfinite(norm)) return -1;
        if (norm <= tolerance && *iterations > 0) return 0;
        build_jacobian(w, m, load);
        capture_stiffness(w);
        /* stable here (on the sleeve, for a held tip): damping fades to Newton */
        double lowest = unstable_modes(w) != 0 ? critical_mode(w) : 0.0;
        if (isnan(lowest)) return -1;
        double damping = 1.5 * fmax(0.0, -lowest) + relax;
        relax *= 0.5;
        for (int a = 0; a < w->dofs; a++) { /* row_a -= c omega_a, omega = Q phi */
            const double *q = &w->frame[9 * w->dof_node[a]];
            int row = w->dof_row[a];
            for (int c = 0; c < 3; c++) {
                int col = UNKNOWNS_PER_NODE * w->dof_node[a] + c;
                w->band[(size_t)col * w->band_rows + (BAND_LOWER + BAND_UPPER + row - col)] -=
                    damping * q[3 * w->dof_axis[a] + c];
            }
        }
        if (solve_newton_step(w) != 0) return -1;
        double largest_turn = 0.0;
        for (int i = 0; i < n; i++)
            largest_turn = fmax(largest_turn, v3_norm(&w->newton_step[UNKNOWNS_PER_NODE * i]));
        double alpha = largest_turn > max_rotation_step ? max_rotation_step / largest_turn : 1.0;
        for (int i = 0; i < nu; i++) w->increment[i] = alpha * w->newton_step[i];
        evaluate_residual(w, m, load, w->increment, w->residual_trial);
        accept_trial(w);
    }
    return -1;
}

/* Newton on the discrete equilibrium from the base point in the work.
 * Returns 0 when the largest scaled residual is <= tolerance; then the base
 * point is the solution. `iterations` counts Jacobians formed. */
static int newton(static_work *w, const rod_model *m, const static_load *load, double tolerance,
                  int max_iterations, int *iterations, double *residual_out)
{
    int n = w->nodes, nu = w->unknowns;
    *iterations = 0;
    memset(w->increment, 0, (size_t)nu * sizeof(double));
    evaluate_residual(w, m, load, w->increment, w->residual);
    for (;;) {
        double norm = max_abs(w->residual, nu);
        *residual_out = norm;
        if (!isfinite(norm)) return -1;
        if (norm <= tolerance) return 0;
        if (*iterations >= max_iterations) return -1;
        ++*iterations;

        build_jacobian(w, m, load);
        capture_stiffness(w); /* for the stability check (cheap: 3 x 3 blocks) */
        if (solve_newton_step(w) != 0) return -1; /* singular Jacobian */

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
            evaluate_residual(w, m, load, w->increment, w->residual_trial);
            double trial = sum_squares(w->residual_trial, nu);
            if (isfinite(trial) && trial <= (1.0 - 1e-4 * alpha) * merit) {
                accepted = 1;
                break;
            }
            alpha *= 0.5;
        }
        if (!accepted) return -1;
        accept_trial(w);
        memset(w->increment, 0, (size_t)nu * sizeof(double));
        evaluate_residual(w, m, load, w->increment, w->residual);
    }
}

/* The size of a load change in the rod's own units: |F| L^2/EI + |M| L/EI + |T| L^3/EI. */
static double load_size(const rod_model *m, const static_load *a, const static_load *b)
{
    double df[3], dm[3], dt[3], ei = m->stiffness[0], length = m->length;
    v3_sub(df, a->tip_force, b->tip_force);
    v3_sub(dm, a->tip_moment, b->tip_moment);
    v3_sub(dt, a->distributed, b->distributed);
    return v3_norm(df) * length * length / ei + v3_norm(dm) * length / ei +
           v3_norm(dt) * length * length * length / ei;
}

static void load_between(const static_load *a, const static_load *b, double fraction,
                         static_load *out)
{
    for (int k = 0; k < 3; k++) {
        out->tip_force[k] = a->tip_force[k] + fraction * (b->tip_force[k] - a->tip_force[k]);
        out->tip_moment[k] = a->tip_moment[k] + fraction * (b->tip_moment[k] - a->tip_moment[k]);
        out->distributed[k] = a->distributed[k] + fraction * (b->distributed[k] - a->distributed[k]);
    }
}

/* Writes the solved base point into the state (staggered layout). */
static void write_state(static_work *w, const rod_model *m, const static_load *load, rod_state *s)
{
    int n = w->nodes;
    memcpy(s->frame, w->frame, (size_t)n * 9 * sizeof(double));
    rod_darboux_from_frames(m, s->frame, s->darboux);
    rod_midpoint_frames(m, s->frame, s->darboux, w->mid);
    rod_positions_from_midframes(m, w->mid, s->position);
    for (int j = 0; j + 1 < n; j++) /* midpoint N on the midpoint directors */
        m3_mul_tv(&s->contact_force[3 * j], &w->mid[9 * j], &w->force[3 * j]);
    /* tip entries: N(L) and u = B^-1 M(L) on the tip directors (thesis 4.2):
     * the applied load plus the support's reaction at a held tip */
    const double *q_tip = &s->frame[9 * (n - 1)];
    double tip_force[3], tip_moment[3], moment_bar[3];
    tip_load_global(m, load, q_tip, tip_force, tip_moment);
    if (tip_held(w))
        for (int k = 0; k < 2; k++) tip_force[1 + k] += w->reaction[k];
    if (w->tip_end == ROD_END_CLAMPED) { /* M(L) = M_{NS-3/2} - ds/2 d3 x N (tip half cell) */
        double d3[3], torque[3];
        m3_column(d3, &w->mid[9 * (n - 2)], 2);
        v3_cross(torque, d3, &w->force[3 * (n - 2)]);
        for (int k = 1; k < 3; k++)
            tip_moment[k] = w->moment[3 * (n - 2) + k] - 0.5 * m->ds * torque[k];
    }
    m3_mul_tv(&s->contact_force[3 * (n - 1)], q_tip, tip_force);
    m3_mul_tv(moment_bar, q_tip, tip_moment);
    for (int k = 0; k < 3; k++) s->darboux[3 * (n - 1) + k] = moment_bar[k] / m->stiffness[k];
    memset(s->velocity, 0, (size_t)n * 3 * sizeof(double));
    memset(s->angular_velocity, 0, (size_t)n * 3 * sizeof(double));
    s->staggered = 1;
}

static void describe_load(const rod_model *m, const static_load *load, char *text, size_t length)
{
    snprintf(text, length,
             "tip force %g %g %g N, tip moment %g %g %g N m on the %s frame, distributed %g %g %g N/m",
             load->tip_force[0], load->tip_force[1], load->tip_force[2], load->tip_moment[0],
             load->tip_moment[1], load->tip_moment[2],
             m->tip_frame == ROD_FRAME_DIRECTOR ? "tip director" : "global",
             load->distributed[0], load->distributed[1], load->distributed[2]);
}

/* 1 when the loads have a potential, so that stability is the positive
 * definiteness of the tangent stiffness: dead forces (tip and distributed).
 * A follower tip load is not conservative (Beck's column loses stability by
 * flutter, which no static criterion sees), nor is a dead tip moment in 3-D
 * (its work on finite rotations depends on the path, Ziegler; a cantilever
 * bent by one into 3/4 of a circle shows negative eigenvalues in the
 * symmetric part of its tangent): neither is checked, decided here. */
static int loads_conservative(const rod_model *m, const static_load *load)
{
    if (v3_norm(load->tip_moment) != 0.0) return 0;
    return m->tip_frame == ROD_FRAME_GLOBAL || v3_norm(load->tip_force) == 0.0;
}

/* Checks the solved base point's stability and, when it is unstable,
 * follows the rod off it: a push along the critical mode, then the
 * over-damped descent to a stable rest (at most `tries` times). Returns
 * ROD_OK with the base point stable (or not checkable), else a status with
 * the report's message written. */
static rod_status settle_stable(static_work *w, const rod_model *m, const static_load *load,
                                double tolerance, double time, int *iterations, rod_report *report)
{
    char text[256];
    if (!loads_conservative(m, load)) {
        w->have_verdict = 0;
        return ROD_OK;
    }
    if (!w->stiffness_fresh) {
        build_jacobian(w, m, load);
        capture_stiffness(w);
    }
    int count = unstable_modes(w);
    for (int tries = 0; count != 0 && tries < 3; tries++) {
        double lowest = critical_mode(w);
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
            describe_load(m, load, text, sizeof text);
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
        count = unstable_modes(w);
    }
    if (count != 0) {
        describe_load(m, load, text, sizeof text);
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

static rod_status step(void *work, const rod_model *m, rod_state *s, double dt,
                       rod_report *report)
{
    static_work *w = work;
    int n = w->nodes;
    double target_time = s->time + dt;
    static_load target, start, load, zero;
    memset(&zero, 0, sizeof zero);
    char text[256];
    rod_tip_load(m, target_time, target.tip_force, target.tip_moment);
    v3_copy(target.distributed, m->distributed_force);
    report->newton_iterations = 0;
    /* A run of static solves far beyond the frames asked for loops for
     * hours to no purpose: the equilibrium does not depend on dt. */
    if (m->options.dt > 0.0 && m->options.duration / m->options.dt > max_solves_per_run) {
        snprintf(report->message, sizeof report->message,
                 "static: solver.dt = %g s asks for %.3g equilibrium solves over %g s (at most "
                 "%.0f): the static scheme needs no time step (each output frame is one load "
                 "increment, and the answer does not depend on dt). Use solver.dt = auto.",
                 m->options.dt, m->options.duration / m->options.dt, m->options.duration,
                 max_solves_per_run);
        return ROD_UNSTABLE;
    }
    /* The path starts at the load the state was solved for; a state this
     * scheme did not produce (the straight initial rod) is taken as the
     * unloaded equilibrium. */
    int continuing = w->have_previous && w->previous_time == s->time;
    if (continuing) start = w->previous;
    else {
        start = zero;
        w->reaction[0] = w->reaction[1] = 0.0;
        w->have_verdict = 0;
    }

    double size = load_size(m, &target, &start), target_size = load_size(m, &target, &zero);
    if (!isfinite(size) || !isfinite(target_size)) {
        describe_load(m, &target, text, sizeof text);
        snprintf(report->message, sizeof report->message,
                 "static: the load at t = %g s (%s) is not finite in the rod's own scales "
                 "(|F| L^2/EI + |M| L/EI + |T| L^3/EI overflows; EI = %g N m^2, L = %g m): "
                 "no rod carries it. Give a load of the order of EI/L^2 = %g N.",
                 target_time, text, m->stiffness[0], m->length,
                 m->stiffness[0] / (m->length * m->length));
        return ROD_UNSTABLE;
    }
    /* Residual rows are per unit length in units of the rod's scales, so the
     * tolerance is relative to the load (and at least to EI/L^2). The log map
     * of nearly equal neighbouring frames loses ~eps/ds in u, which puts a
     * round-off floor of ~eps (L/ds)^2 under the residual (measured 1.6e-10
     * at NS = 10001); the tolerance never asks for less. The load's size is
     * finite (checked above), so the tolerance is. */
    double length_ratio = m->length / m->ds;
    double tolerance = fmax(1.0, target_size) *
                       (m->options.newton_tolerance + DBL_EPSILON * length_ratio * length_ratio);
    int max_iterations = m->options.newton_max_iterations > 0 ? m->options.newton_max_iterations : 25;

    memcpy(w->frame, s->frame, (size_t)n * 9 * sizeof(double));
    load_between(&start, &target, 0.0, &load);
    forces_from_statics(w, m, &load);
    memcpy(w->saved_frame, w->frame, (size_t)n * 9 * sizeof(double));
    memcpy(w->saved_force, w->force, (size_t)(n - 1) * 3 * sizeof(double));
    memcpy(w->saved_reaction, w->reaction, sizeof w->reaction);

    double reached = 0.0;
    double fraction_step = size > max_load_increment ? max_load_increment / size : 1.0;
    int total_iterations = 0, solved_once = 0, sub_steps = 0;
    double last_residual = 0.0;
    int last_iterations = 0;
    const char *why = NULL;
    while (reached < 1.0) {
        if (++sub_steps > max_sub_steps) {
            why = "the continuation's budget of sub-steps ran out";
            break;
        }
        /* up to max_load_increment, or half the load reached when larger */
        load_between(&start, &target, reached, &load);
        double allowed = fmax(max_load_increment, relative_load_increment * load_size(m, &load, &zero));
        double largest_fraction = size > allowed ? allowed / size : 1.0;
        double trying = fmin(1.0, reached + fmin(fraction_step, largest_fraction));
        load_between(&start, &target, trying, &load);
        forces_from_statics(w, m, &load);
        w->stiffness_fresh = 0;
        int rc = newton(w, m, &load, tolerance, max_iterations, &last_iterations, &last_residual);
        total_iterations += last_iterations;
        if (rc == 0) {
            fraction_step = fmin(2.0 * (trying - reached), 1.0);
            reached = trying;
            solved_once = 1;
            memcpy(w->saved_frame, w->frame, (size_t)n * 9 * sizeof(double));
            memcpy(w->saved_force, w->force, (size_t)(n - 1) * 3 * sizeof(double));
            memcpy(w->saved_reaction, w->reaction, sizeof w->reaction);
            continue;
        }
        /* back to the last converged point, with a smaller load increment */
        memcpy(w->frame, w->saved_frame, (size_t)n * 9 * sizeof(double));
        memcpy(w->force, w->saved_force, (size_t)(n - 1) * 3 * sizeof(double));
        memcpy(w->reaction, w->saved_reaction, sizeof w->reaction);
        fraction_step = 0.5 * (trying - reached);
        if (fraction_step < min_load_fraction) {
            why = "the load sub-step fell below its smallest size";
            break;
        }
    }
    report->newton_iterations = total_iterations;
    int segment;
    if (why) {
        /* as the implicit scheme: a failure on the way into a kink is the grid's */
        rod_darboux_from_frames(m, w->frame, w->darboux); /* the last converged point */
        double bend = rod_sharpest_bend(m, w->darboux, &segment);
        if (solved_once && bend > 0.5 * ROD_UNRESOLVED_BEND) {
            rod_unresolved_bend_message(m, "static", target_time, bend, segment,
                                        report->message, sizeof report->message);
            return ROD_UNSTABLE;
        }
        describe_load(m, &target, text, sizeof text);
        snprintf(report->message, sizeof report->message,
                 "static: Newton did not converge for the load at t = %g s (%.200s): %s; reached "
                 "%.4g%% of the load change from t = %g s%s; scaled residual %.3e above the "
                 "tolerance %.1e after %d iterations (newton_max_iterations = %d). The state "
                 "is left at t = %g s. Smaller load steps (a ramp profile, shorter dt), more "
                 "Newton iterations or a looser newton_tolerance may work; a load far beyond "
                 "EI/L^2 = %g N bends the rod into a kink no grid resolves.",
                 target_time, text, why, 100.0 * reached, s->time,
                 solved_once ? "" : " (no sub-step converged)", last_residual, tolerance,
                 last_iterations, max_iterations, s->time,
                 m->stiffness[0] / (m->length * m->length));
        return ROD_NO_CONVERGENCE;
    }
    /* a bend the grid cannot resolve is no answer either (one definition
     * with the implicit scheme: rod_geometry.h), nor worth a stability check */
    rod_darboux_from_frames(m, w->frame, w->darboux);
    double angle = rod_sharpest_bend(m, w->darboux, &segment);
    if (angle > ROD_UNRESOLVED_BEND) {
        rod_unresolved_bend_message(m, "static", target_time, angle, segment, report->message,
                                    sizeof report->message);
        return ROD_UNSTABLE;
    }
    /* Stability of the answer: the same state as the last solved one keeps
     * its verdict; otherwise check it, and leave an unstable equilibrium. */
    if (!(total_iterations == 0 && continuing && w->have_verdict)) {
        rod_status verdict = settle_stable(w, m, &target, tolerance, target_time,
                                           &total_iterations, report);
        report->newton_iterations = total_iterations;
        if (verdict != ROD_OK) return verdict;
    }
    write_state(w, m, &target, s);
    s->time = target_time;
    w->have_previous = 1;
    w->previous_time = s->time;
    w->previous = target;
    return ROD_OK;
}

static double stable_dt(const rod_model *m, const char **limit)
{
    (void)m;
    if (limit) *limit = "static: no time step";
    return INFINITY;
}

const rod_scheme_ops rod_scheme_static = {"static", create, step, destroy, stable_dt};

int static_unstable_modes(static_work *w, const rod_model *m, const rod_state *s, int *count,
                          char *err, size_t errlen)
{
    int n = w->nodes;
    static_load load;
    rod_tip_load(m, s->time, load.tip_force, load.tip_moment);
    v3_copy(load.distributed, m->distributed_force);
    if (!loads_conservative(m, &load)) {
        snprintf(err, errlen, "static: a follower tip load or a tip moment has no static "
                              "stability criterion (not conservative)");
        return -1;
    }
    memcpy(w->frame, s->frame, (size_t)n * 9 * sizeof(double));
    w->reaction[0] = w->reaction[1] = 0.0;
    if (tip_held(w)) { /* the state's tip force entry is the applied force plus R */
        double applied[3], moment[3], total[3];
        const double *q_tip = &s->frame[9 * (n - 1)];
        tip_load_global(m, &load, q_tip, applied, moment);
        m3_mul_v(total, q_tip, &s->contact_force[3 * (n - 1)]);
        for (int k = 0; k < 2; k++) w->reaction[k] = total[1 + k] - applied[1 + k];
    }
    forces_from_statics(w, m, &load);
    build_jacobian(w, m, &load);
    capture_stiffness(w);
    *count = unstable_modes(w);
    return 0;
}

/* Buckling support ---------------------------------------------------- */

/* Entry (row, col) of the Jacobian of build_jacobian, before its LU. */
static double jacobian_entry(const static_work *w, int row, int col)
{
    int nb = w->band_unknowns;
    if (row < nb && col < nb) {
        if (row - col > BAND_LOWER || col - row > BAND_UPPER) return 0.0;
        return w->band[(size_t)col * w->band_rows + (BAND_LOWER + BAND_UPPER + row - col)];
    }
    if (row < nb) return w->border_columns[(size_t)(col - nb) * nb + row];
    if (col < nb) return w->border_rows[(size_t)(row - nb) * nb + col];
    return 0.0;
}

/* The transverse pairs of a block of 6: unknowns (phi_1, phi_2) on d1, d2
 * (y, z at the straight rod, turned by its twist) and (N_y, N_z); rows
 * (force y, z) and (moment y, z, or their replacements). The border is one
 * more pair of each. The axial rest (phi_3, N_x, force x, moment x) does not
 * couple to them by the symmetry and never becomes singular. */
static int transverse_unknown(const static_work *w, int k, int *second)
{
    int block = k / 2, pair = k % 2;
    if (block * UNKNOWNS_PER_NODE >= w->band_unknowns) {
        *second = w->band_unknowns + 1;
        return w->band_unknowns;
    }
    int first = block * UNKNOWNS_PER_NODE + (pair == 0 ? 0 : 4);
    *second = first + 1;
    return first;
}

static int transverse_row(const static_work *w, int k, int *second)
{
    int block = k / 2, pair = k % 2;
    if (block * UNKNOWNS_PER_NODE >= w->band_unknowns) {
        *second = w->band_unknowns + 1;
        return w->band_unknowns;
    }
    /* a pinned root's block 0 has its pair in rows 1, 2; rows 4, 5 are identity */
    int first = block * UNKNOWNS_PER_NODE + (pair == 0 ? 1 : 4);
    *second = first + 1;
    return first;
}

int static_straight_determinant(static_work *w, const rod_model *m, double lambda,
                                double *log_abs, double *phase, double *residual, char *err,
                                size_t errlen)
{
    int n = w->nodes;
    static_load load;
    memset(&load, 0, sizeof load);
    v3_scale(load.tip_force, m->tip_force, lambda);
    v3_scale(load.tip_moment, m->tip_moment, lambda);
    /* axial components: on d3 = x for a follower load, global x for a dead one */
    int axis = m->tip_frame == ROD_FRAME_DIRECTOR ? 2 : 0;
    double twist_rate = load.tip_moment[axis] / m->stiffness[2]; /* u3 = M3 / C, 1/m */
    for (int i = 0; i < n; i++) { /* Q_i = exp(u3 s_i [e_x]) Q_init: straight, twisted */
        double turn[3] = {twist_rate * m->ds * i, 0.0, 0.0}, rot[9];
        m3_exp(rot, turn);
        m3_mul(&w->frame[9 * i], rot, straight_frame);
    }
    for (int j = 0; j + 1 < n; j++) v3_set(&w->force[3 * j], load.tip_force[axis], 0.0, 0.0);
    w->reaction[0] = w->reaction[1] = 0.0;
    build_jacobian(w, m, &load);
    *residual = max_abs(w->residual, w->unknowns);

    int size = 2 * n + (w->border ? 1 : 0);
    if (!w->tangent) {
        w->tangent = malloc((size_t)size * (size_t)size * sizeof *w->tangent);
        if (!w->tangent) {
            snprintf(err, errlen, "static: out of memory for the %d x %d tangent", size, size);
            return -1;
        }
    }
    /* K = A + i B from the real 2 x 2 blocks [[A, -B], [B, A]]; check that form */
    double largest = 0.0, asymmetry = 0.0;
    for (int r = 0; r < size; r++) {
        int ry2, ry = transverse_row(w, r, &ry2);
        for (int c = 0; c < size; c++) {
            int cy2, cy = transverse_unknown(w, c, &cy2);
            double a = jacobian_entry(w, ry, cy), b = jacobian_entry(w, ry2, cy);
            double a2 = jacobian_entry(w, ry2, cy2), minus_b = jacobian_entry(w, ry, cy2);
            largest = fmax(largest, fmax(fabs(a), fabs(b)));
            asymmetry = fmax(asymmetry, fmax(fabs(a - a2), fabs(b + minus_b)));
            w->tangent[(size_t)r * size + c] = a + I * b;
        }
    }
    if (asymmetry > 1e-4 * largest) {
        snprintf(err, errlen,
                 "static: the tangent at the straight rod is not symmetric about the x axis "
                 "(largest deviation %.2e of %.2e): the load is not purely axial", asymmetry,
                 largest);
        return -1;
    }
    /* LU with partial pivoting: det = (-1)^swaps prod pivots */
    double log_sum = 0.0, angle = 0.0;
    double complex *a = w->tangent;
    for (int k = 0; k < size; k++) {
        int pivot = k;
        for (int r = k + 1; r < size; r++)
            if (cabs(a[(size_t)r * size + k]) > cabs(a[(size_t)pivot * size + k])) pivot = r;
        if (pivot != k) {
            for (int c = 0; c < size; c++) {
                double complex t = a[(size_t)k * size + c];
                a[(size_t)k * size + c] = a[(size_t)pivot * size + c];
                a[(size_t)pivot * size + c] = t;
            }
            angle += M_PI;
        }
        double complex p = a[(size_t)k * size + k];
        if (cabs(p) == 0.0) {
            *log_abs = -INFINITY;
            *phase = 0.0;
            return 0;
        }
        log_sum += log(cabs(p));
        angle += carg(p);
        for (int r = k + 1; r < size; r++) {
            double complex f = a[(size_t)r * size + k] / p;
            if (f == 0.0) continue;
            for (int c = k + 1; c < size; c++) a[(size_t)r * size + c] -= f * a[(size_t)k * size + c];
        }
    }
    /* The phi unknowns are on the twisted directors: w_global = e^{i theta_i} w_director
     * with theta_i = u3 s_i, so det K_director = det K_global e^{i sum theta_i}; report
     * the global one, whose phase does not wind with the twist. */
    for (int i = 0; i < n; i++) angle -= twist_rate * m->ds * i;
    *log_abs = log_sum;
    *phase = remainder(angle, 2.0 * M_PI);
    return 0;
}
