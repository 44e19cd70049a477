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
 * Past the buckling load a straight rod is an (unstable) equilibrium too:
 * Newton started from the straight state under a purely axial load (or a
 * pure twisting moment) stays straight. That is a correct equilibrium, just
 * not the one a perturbed rod would find; add a small transverse load to
 * follow the buckled branch; rod_buckling_factor (buckling.h) finds where
 * the straight rod stops being stable from this scheme's Jacobian.
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
    MAX_BORDER = 2   /* tip reaction R_y, R_z and the rows y_tip = z_tip = 0 */
};

/* Largest load change per continuation sub-step, in units of the rod's own
 * scales (|F| L^2/EI + |M| L/EI + |T| L^3/EI): about one radian of bending. */
static const double max_load_increment = 1.0;
/* Smallest continuation sub-step, as a fraction of the step's load change. */
static const double min_load_fraction = 1.0 / 4096.0;
/* Newton step limit: largest rotation increment of a node, rad. */
static const double max_rotation_step = 1.0;

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
    if (!w->frame || !w->force || !w->frame_trial || !w->darboux || !w->mid || !w->mid_base ||
        !w->moment || !w->increment || !w->newton_step || !w->residual || !w->residual_trial ||
        !w->band || !w->border_columns || !w->border_rows || !w->border_solution || !w->pivots ||
        !w->saved_frame || !w->saved_force) {
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

static rod_status step(void *work, const rod_model *m, rod_state *s, double dt,
                       rod_report *report)
{
    static_work *w = work;
    int n = w->nodes;
    double target_time = s->time + dt;
    static_load target, start, load;
    rod_tip_load(m, target_time, target.tip_force, target.tip_moment);
    v3_copy(target.distributed, m->distributed_force);
    /* The path starts at the load the state was solved for; a state this
     * scheme did not produce (the straight initial rod) is taken as the
     * unloaded equilibrium. */
    if (w->have_previous && w->previous_time == s->time) start = w->previous;
    else {
        memset(&start, 0, sizeof start);
        w->reaction[0] = w->reaction[1] = 0.0;
    }

    double size = load_size(m, &target, &start);
    /* Residual rows are per unit length in units of the rod's scales, so the
     * tolerance is relative to the load (and at least to EI/L^2). The log map
     * of nearly equal neighbouring frames loses ~eps/ds in u, which puts a
     * round-off floor of ~eps (L/ds)^2 under the residual (measured 1.6e-10
     * at NS = 10001); the tolerance never asks for less. */
    double length_ratio = m->length / m->ds;
    double tolerance = fmax(1.0, load_size(m, &target, &(static_load){0})) *
                       (m->options.newton_tolerance + DBL_EPSILON * length_ratio * length_ratio);
    int max_iterations = m->options.newton_max_iterations > 0 ? m->options.newton_max_iterations : 25;

    memcpy(w->frame, s->frame, (size_t)n * 9 * sizeof(double));
    load_between(&start, &target, 0.0, &load);
    forces_from_statics(w, m, &load);
    memcpy(w->saved_frame, w->frame, (size_t)n * 9 * sizeof(double));
    memcpy(w->saved_force, w->force, (size_t)(n - 1) * 3 * sizeof(double));
    memcpy(w->saved_reaction, w->reaction, sizeof w->reaction);

    double reached = 0.0;
    double largest_fraction = size > max_load_increment ? max_load_increment / size : 1.0;
    double fraction_step = largest_fraction;
    int total_iterations = 0, solved_once = 0;
    double last_residual = 0.0;
    int last_iterations = 0;
    while (reached < 1.0) {
        double trying = fmin(1.0, reached + fraction_step);
        load_between(&start, &target, trying, &load);
        forces_from_statics(w, m, &load);
        int rc = newton(w, m, &load, tolerance, max_iterations, &last_iterations, &last_residual);
        total_iterations += last_iterations;
        if (rc == 0) {
            reached = trying;
            solved_once = 1;
            memcpy(w->saved_frame, w->frame, (size_t)n * 9 * sizeof(double));
            memcpy(w->saved_force, w->force, (size_t)(n - 1) * 3 * sizeof(double));
            memcpy(w->saved_reaction, w->reaction, sizeof w->reaction);
            fraction_step = fmin(2.0 * fraction_step, largest_fraction);
            continue;
        }
        /* back to the last converged point, with a smaller load increment */
        memcpy(w->frame, w->saved_frame, (size_t)n * 9 * sizeof(double));
        memcpy(w->force, w->saved_force, (size_t)(n - 1) * 3 * sizeof(double));
        memcpy(w->reaction, w->saved_reaction, sizeof w->reaction);
        fraction_step *= 0.5;
        if (fraction_step < min_load_fraction) {
            report->newton_iterations = total_iterations;
            snprintf(report->message, sizeof report->message,
                     "static: Newton did not converge for the load at t = %g s (tip force %g %g %g N, "
                     "tip moment %g %g %g N m on the %s frame, distributed %g %g %g N/m): reached "
                     "%.4g%% of the load change from t = %g s%s; scaled residual %.3e above the "
                     "tolerance %.1e after %d iterations (newton_max_iterations = %d). The state "
                     "is left at t = %g s. Smaller load steps (a ramp profile, shorter dt), more "
                     "Newton iterations or a looser newton_tolerance may work.",
                     target_time, target.tip_force[0], target.tip_force[1], target.tip_force[2],
                     target.tip_moment[0], target.tip_moment[1], target.tip_moment[2],
                     m->tip_frame == ROD_FRAME_DIRECTOR ? "tip director" : "global",
                     target.distributed[0], target.distributed[1], target.distributed[2],
                     100.0 * reached, s->time, solved_once ? "" : " (no sub-step converged)",
                     last_residual, tolerance, last_iterations, max_iterations, s->time);
            return ROD_NO_CONVERGENCE;
        }
    }
    write_state(w, m, &target, s);
    s->time = target_time;
    w->have_previous = 1;
    w->previous_time = s->time;
    w->previous = target;
    report->newton_iterations = total_iterations;
    return ROD_OK;
}

static double stable_dt(const rod_model *m, const char **limit)
{
    (void)m;
    if (limit) *limit = "static: no time step";
    return INFINITY;
}

const rod_scheme_ops rod_scheme_static = {"static", create, step, destroy, stable_dt};

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
