/* static_work.c: the static scheme's scratch memory (static_work_create,
 * static_work_destroy), made once for a model: what the scheme refuses to
 * solve, the ends' initial poses, the unknowns' scales and the free
 * rotations the stability check works on. */
#include "sim/static/static_work.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sim/rod.h"
#include "sim/static/static_internal.h"
#include "base/vec3.h"

/* The smallest rotation taking the unit vector a to the unit vector b
 * (rod.h: how d1, d2 follow the root's direction); a half turn about a
 * normal of a when b = -a. */
static void rotation_between(const double a[3], const double b[3], double r[9])
{
    double axis[3], c = v3_dot(a, b);
    v3_cross(axis, a, b);
    double sine = v3_norm(axis);
    if (sine < 1e-15 && c < 0.0) { /* opposite: turn by pi about a normal */
        double other[3] = {0.0, 0.0, 0.0};
        other[fabs(a[0]) < 0.9 ? 0 : 1] = 1.0;
        v3_cross(axis, a, other);
        v3_scale(axis, axis, M_PI / v3_norm(axis));
    } else if (sine > 0.0) {
        v3_scale(axis, axis, atan2(sine, c) / sine);
    }
    m3_exp(r, axis);
}

/* Unit vector of v, or 0 when v is zero; -1 when v is not finite or zero. */
int static_unit_or_zero(const double v[3], double out[3])
{
    double norm = v3_norm(v);
    if (!isfinite(norm)) return -1;
    if (norm == 0.0) {
        v3_set(out, 0.0, 0.0, 0.0);
        return 0;
    }
    v3_scale(out, v, 1.0 / norm);
    return 1;
}

/* The held directions of the tip: the two normals of its slide (the
 * slide's own frame, so that x gives y and z, as the buckling module's
 * transverse pairs expect), or x, y, z when held in place. */
static void set_tip_directions(static_work *w)
{
    static const double x_axis[3] = {1, 0, 0}, y_axis[3] = {0, 1, 0}, z_axis[3] = {0, 0, 1};
    if (w->tip_sliding) {
        double r[9];
        rotation_between(x_axis, w->slide, r);
        m3_mul_v(w->reaction_dir[0], r, y_axis);
        m3_mul_v(w->reaction_dir[1], r, z_axis);
        return;
    }
    v3_copy(w->reaction_dir[0], x_axis);
    v3_copy(w->reaction_dir[1], y_axis);
    v3_copy(w->reaction_dir[2], z_axis);
}

/* The ends' initial poses from the state at t = 0 (rod_state_reset builds it
 * from the model's origin, direction and initial shape). */
void static_set_initial_ends(static_work *w, const double *position, const double *frame)
{
    int n = w->nodes;
    memcpy(w->root_frame0, frame, 9 * sizeof(double));
    memcpy(w->tip_frame0, &frame[9 * (n - 1)], 9 * sizeof(double));
    v3_copy(w->root_position0, position);
    v3_copy(w->tip_position0, &position[3 * (n - 1)]);
    m3_column(w->root_axes[0], w->root_frame0, 2);
    m3_column(w->root_axes[1], w->root_frame0, 0);
    m3_column(w->root_axes[2], w->root_frame0, 1);
    /* a pinned root's swing dofs turn about its initial d1, d2 */
    for (int a = 0; a < w->dofs && w->dof_node[a] == 0; a++)
        v3_copy(&w->dof_dir[3 * a], w->root_axes[w->dof_axis[a]]);
}

/* The same from the model, before any state is seen (the buckling module's
 * straight rod): straight from origin along direction, or the initial shape. */
static void initial_ends_from_model(static_work *w, const rod_model *m)
{
    static const double x_axis[3] = {1, 0, 0};
    int n = w->nodes;
    double direction[3], turn[9], tip_direction[3];
    if (static_unit_or_zero(m->direction, direction) != 1) v3_copy(direction, x_axis);
    v3_copy(tip_direction, direction);
    double root[3], tip[3];
    v3_copy(root, m->origin);
    for (int k = 0; k < 3; k++) tip[k] = root[k] + m->length * direction[k];
    if (m->initial_shape) {
        const double *shape = m->initial_shape;
        v3_copy(root, shape);
        v3_copy(tip, &shape[3 * (n - 1)]);
        v3_sub(direction, &shape[3], shape);
        if (static_unit_or_zero(direction, direction) != 1) v3_copy(direction, x_axis);
        v3_sub(tip_direction, &shape[3 * (n - 1)], &shape[3 * (n - 2)]);
        if (static_unit_or_zero(tip_direction, tip_direction) != 1) v3_copy(tip_direction, direction);
    }
    double *positions = calloc((size_t)n * 3, sizeof(double));
    double *frames = calloc((size_t)n * 9, sizeof(double));
    if (!positions || !frames) { /* the defaults: straight along x from 0 */
        free(positions);
        free(frames);
        memcpy(w->root_frame0, straight_frame, sizeof straight_frame);
        memcpy(w->tip_frame0, straight_frame, sizeof straight_frame);
        v3_set(w->root_position0, 0.0, 0.0, 0.0);
        v3_set(w->tip_position0, m->length, 0.0, 0.0);
        m3_column(w->root_axes[0], straight_frame, 2);
        m3_column(w->root_axes[1], straight_frame, 0);
        m3_column(w->root_axes[2], straight_frame, 1);
        return;
    }
    v3_copy(positions, root);
    v3_copy(&positions[3 * (n - 1)], tip);
    rotation_between(x_axis, direction, turn);
    m3_mul(frames, turn, straight_frame);
    rotation_between(x_axis, tip_direction, turn);
    m3_mul(&frames[9 * (n - 1)], turn, straight_frame);
    static_set_initial_ends(w, positions, frames);
    free(positions);
    free(frames);
}

/* 1 when a force acts on a rod pinned at node `pinned` (0 or NS-1) whose
 * other end is free: then the loads decide the rod's direction about the
 * pin (it hangs along them). A force at the pin itself, a moment alone (it
 * turns the rod on for ever), or no load leave it undetermined. The tip
 * load counts when the pin is at the root; a 7-column table may give it. */
int static_swing_determined(const rod_model *m, int pinned)
{
    if (v3_norm(m->distributed_force) > 0.0) return 1;
    for (int p = 0; p < m->point_load_count; p++)
        if (m->point_loads[p].node != pinned && v3_norm(m->point_loads[p].force) > 0.0) return 1;
    if (pinned == 0 && (v3_norm(m->tip_force) > 0.0 ||
                        (m->profile.kind == ROD_PROFILE_TABLE && m->profile.table.columns == 7)))
        return 1;
    return 0;
}

/* 1 with a message in err when the static scheme cannot solve the model as
 * given: an end pair it does not hold, or loads that are not finite. */
static int refuse_model(const rod_model *m, char *err, size_t errlen)
{
    static const char *const end_names[] = {"clamped", "pinned", "free"};
    if (m->nodes < 3 || !(m->ds > 0.0)) {
        snprintf(err, errlen, "static: model not derived (nodes %d, ds %g)", m->nodes, m->ds);
        return 1;
    }
    for (int end = 0; end < 2; end++) {
        rod_end_kind kind = end == 0 ? m->root_end : m->tip_end;
        if (kind != ROD_END_FREE && kind != ROD_END_PINNED && kind != ROD_END_CLAMPED) {
            snprintf(err, errlen, "static: unknown %s end condition %d (accepted: clamped, "
                     "pinned, free)", end == 0 ? "root" : "tip", (int)kind);
            return 1;
        }
    }
    if (m->root_end == ROD_END_FREE && m->tip_end == ROD_END_FREE) {
        snprintf(err, errlen,
                 "static: ends root = free, tip = free: a loose thread has no static "
                 "equilibrium (nothing holds it, so any load moves it away and an unloaded one "
                 "rests anywhere); use solver.scheme = implicit");
        return 1;
    }
    /* Decided: a free root with a held tip is the mirrored problem; the
     * scheme integrates from s = 0, so it asks for the mirror instead. */
    if (m->root_end == ROD_END_FREE) {
        snprintf(err, errlen,
                 "static: ends root = free, tip = %s: the static scheme holds the root (s = 0) "
                 "and integrates from it; describe the same rod mirrored (root = %s at the held "
                 "end, tip = free) or use solver.scheme = implicit", end_names[m->tip_end],
                 end_names[m->tip_end]);
        return 1;
    }
    if (m->root_end == ROD_END_PINNED && m->tip_end == ROD_END_FREE && !static_swing_determined(m, 0)) {
        snprintf(err, errlen,
                 "static: ends root = pinned, tip = free with no force on the rod (tip force, "
                 "distributed force or gravity, point load off the pin): the rod turns freely "
                 "about the pin, so its direction is undetermined. Give it a force to hang "
                 "along, use root = clamped, or hold the tip (tip = pinned or clamped)");
        return 1;
    }
    double root_slide[3], slide[3];
    int root_sliding = static_unit_or_zero(m->root_slide, root_slide);
    int tip_sliding = static_unit_or_zero(m->tip_slide, slide);
    if (root_sliding < 0 || tip_sliding < 0) {
        snprintf(err, errlen, "static: ends %s_slide is not finite (accepted: a direction, or "
                 "0 0 0 for an end held in place)", root_sliding < 0 ? "root" : "tip");
        return 1;
    }
    /* Decided: the root is the scheme's fixed point of integration; a
     * sliding root with the tip held in place is solved as the mirrored rod
     * (scheme_static.c create). What reaches here is a sliding root with a
     * free or sliding tip: the rod can move along the sleeve as a whole (it
     * slides away under any load along it and rests anywhere without one),
     * so the equilibrium is not determined. */
    if (root_sliding) {
        snprintf(err, errlen,
                 "static: ends root_slide = %g %g %g with tip = %s%s: the rod could slide along "
                 "the root's sleeve as a whole, so its static equilibrium is not determined. The "
                 "static scheme solves a sliding root only with the tip held in place (tip = "
                 "pinned or clamped, tip_slide = 0 0 0); use solver.scheme = implicit",
                 m->root_slide[0], m->root_slide[1], m->root_slide[2], end_names[m->tip_end],
                 tip_sliding ? " on a sleeve (tip_slide)" : "");
        return 1;
    }
    for (int p = 0; p < m->point_load_count; p++) {
        const rod_point_load *load = &m->point_loads[p];
        if (load->node < 0 || load->node >= m->nodes || !isfinite(v3_norm(load->force)) ||
            !isfinite(v3_norm(load->moment))) {
            snprintf(err, errlen, "static: point load %d at node %d (force %g %g %g N, moment "
                     "%g %g %g N m): accepted a node 0..%d and finite values", p + 1, load->node,
                     load->force[0], load->force[1], load->force[2], load->moment[0],
                     load->moment[1], load->moment[2], m->nodes - 1);
            return 1;
        }
    }
    if (!isfinite(v3_norm(m->intrinsic_curvature)) || !isfinite(v3_norm(m->distributed_moment))) {
        snprintf(err, errlen, "static: intrinsic_curvature and distributed_moment must be finite");
        return 1;
    }
    if (m->tip_end == ROD_END_FREE && (tip_sliding || m->tip_motion)) {
        snprintf(err, errlen, "static: ends tip = free with %s: only a held tip (pinned or "
                 "clamped) slides or is driven", m->tip_motion ? "tip_motion" : "tip_slide");
        return 1;
    }
    return 0;
}

/* The ends, the sizes of the linear system and the scales of its unknowns
 * and rows (a model refuse_model accepted). */
static void set_sizes(static_work *w, const rod_model *m)
{
    double slide[3] = {0.0, 0.0, 0.0};
    int tip_sliding = static_unit_or_zero(m->tip_slide, slide); /* 0 or 1: finite */
    w->nodes = m->nodes;
    w->length = m->length;
    w->root_end = m->root_end;
    w->tip_end = m->tip_end;
    w->tip_sliding = tip_sliding;
    v3_copy(w->slide, slide);
    w->band_unknowns = UNKNOWNS_PER_NODE * m->nodes;
    w->border = !tip_held(w) ? 0 : tip_sliding ? 2 : 3;
    set_tip_directions(w);
    initial_ends_from_model(w, m);
    w->unknowns = w->band_unknowns + w->border;
    w->band_rows = 2 * BAND_LOWER + BAND_UPPER + 1;
    double ei = m->stiffness[0], length = m->length;
    w->force_scale = ei / (length * length);
    w->force_row_scale = length * length * length / (m->ds * ei);
    w->moment_row_scale = length * length / (m->ds * ei);
    w->angle_row_scale = length * length / (m->ds * m->ds);
    w->position_row_scale = length / (m->ds * m->ds);
    /* The residual carries round-off ~eps (L/ds)^2 (see the tolerance in
     * static_continuation.c); balancing that against the O(h) truncation
     * gives h ~ sqrt(eps) L/ds. */
    w->fd_increment = sqrt(DBL_EPSILON) * length / m->ds;
}

/* The solve's arrays: base point, trial point, residuals, the band and its
 * border, the last converged continuation point. */
static void allocate_solve(static_work *w)
{
    size_t n = (size_t)w->nodes;
    size_t nu = (size_t)w->unknowns, nb = (size_t)w->band_unknowns;
    size_t border = (size_t)(w->border > 0 ? w->border : 1);
    w->frame = malloc(n * 9 * sizeof(double));
    w->force = malloc((n - 1) * 3 * sizeof(double));
    w->frame_trial = malloc(n * 9 * sizeof(double));
    w->darboux = malloc((n - 1) * 3 * sizeof(double));
    w->mid = malloc((n - 1) * 9 * sizeof(double));
    w->mid_base = malloc((n - 1) * 9 * sizeof(double));
    w->moment = malloc((n - 1) * 3 * sizeof(double));
    w->node_force = calloc(n * 3, sizeof(double));
    w->start_darboux = calloc((n - 1) * 3, sizeof(double));
    w->node_moment = calloc(n * 3, sizeof(double));
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
}

/* The point loads summed per node (at profile factor 1). */
static void sum_point_loads(static_work *w, const rod_model *m)
{
    if (!w->node_force || !w->node_moment) return;
    for (int p = 0; p < m->point_load_count; p++) {
        int node = m->point_loads[p].node;
        if (node < 0 || node >= m->nodes) continue; /* refused by refuse_model */
        v3_add(&w->node_force[3 * node], &w->node_force[3 * node], m->point_loads[p].force);
        v3_add(&w->node_moment[3 * node], &w->node_moment[3 * node], m->point_loads[p].moment);
    }
}

/* The free rotations: none at a clamped root, swing (about its initial
 * d1, d2) at a pinned one, the twist about the slide only at a sliding
 * clamped tip, none at a clamped tip held in place, all three elsewhere. */
static void list_free_rotations(static_work *w, const rod_model *m)
{
    size_t most = 3 * (size_t)m->nodes;
    w->dof_node = malloc(most * sizeof(int));
    w->dof_axis = malloc(most * sizeof(int));
    w->dof_dir = malloc(most * 3 * sizeof(double));
    w->dof_row = malloc(most * sizeof(int));
    if (!w->dof_node || !w->dof_axis || !w->dof_row || !w->dof_dir) return;
    for (int i = 0; i < m->nodes; i++) {
        for (int axis = 0; axis < 3; axis++) {
            int row = UNKNOWNS_PER_NODE * i + 3 + axis, sub = axis;
            double dir[3] = {0, 0, 0};
            dir[axis] = 1.0;
            if (i == 0 && (m->root_end == ROD_END_CLAMPED || axis == 0)) continue;
            if (i == 0) { /* pinned root: rows 1, 2 hold M(0) on d1, d2 (initial) */
                row = axis;
                v3_copy(dir, w->root_axes[axis]);
            }
            if (i == m->nodes - 1 && m->tip_end == ROD_END_CLAMPED) {
                if (!w->tip_sliding || axis > 0) continue;
                v3_copy(dir, w->slide); /* row 3 of the tip: the moment along the slide */
            }
            w->dof_node[w->dofs] = i;
            w->dof_axis[w->dofs] = sub;
            v3_copy(&w->dof_dir[3 * w->dofs], dir);
            w->dof_row[w->dofs] = row;
            w->dofs++;
        }
    }
}

/* The stability check's arrays, sized by the free rotations. */
static void allocate_stability(static_work *w)
{
    size_t n = (size_t)w->nodes, dofs = (size_t)w->dofs;
    w->stiffness = malloc((STIFFNESS_BAND + 1) * dofs * sizeof(double));
    w->stiffness_work = malloc((3 * STIFFNESS_BAND + 1) * dofs * sizeof(double));
    w->stiffness_pivots = malloc(dofs * sizeof(lapack_int));
    w->constraint = calloc(MAX_BORDER * dofs + 1, sizeof(double));
    w->eigen_work = malloc(2 * dofs * sizeof(double));
    w->rotation_blocks = malloc(n * 27 * sizeof(double));
    w->mode = malloc((1 + MAX_BORDER) * dofs * sizeof(double));
    w->branch_start_frame = malloc(n * 9 * sizeof(double));
    w->branch_start_force = malloc((n - 1) * 3 * sizeof(double));
    w->branch_mode = malloc((dofs + 1) * sizeof(double));
    w->branch_dof_dir = malloc((dofs + 1) * 3 * sizeof(double));
    w->branch_rest_frame = malloc(n * 9 * sizeof(double));
    w->branch_rest_force = malloc((n - 1) * 3 * sizeof(double));
}

static int allocated(const static_work *w)
{
    return w->frame && w->force && w->frame_trial && w->darboux && w->mid && w->mid_base &&
           w->moment && w->node_force && w->start_darboux && w->node_moment && w->increment &&
           w->newton_step && w->residual && w->residual_trial && w->band && w->border_columns &&
           w->border_rows && w->border_solution && w->pivots && w->saved_frame && w->saved_force &&
           w->dof_node && w->dof_axis && w->dof_row && w->dof_dir && w->stiffness &&
           w->stiffness_work && w->stiffness_pivots && w->constraint && w->eigen_work && w->mode &&
           w->rotation_blocks && w->branch_start_frame && w->branch_start_force &&
           w->branch_mode && w->branch_dof_dir && w->branch_rest_frame && w->branch_rest_force;
}

static_work *static_work_create(const rod_model *m, char *err, size_t errlen)
{
    if (refuse_model(m, err, errlen)) return NULL;
    static_work *w = calloc(1, sizeof *w);
    if (!w) {
        snprintf(err, errlen, "static: out of memory");
        return NULL;
    }
    set_sizes(w, m);
    allocate_solve(w);
    sum_point_loads(w, m);
    list_free_rotations(w, m);
    allocate_stability(w);
    if (!allocated(w)) {
        static_work_destroy(w);
        snprintf(err, errlen, "static: out of memory for %d nodes", m->nodes);
        return NULL;
    }
    return w;
}

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
    free(w->node_force);
    free(w->start_darboux);
    free(w->node_moment);
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
    free(w->dof_dir);
    free(w->dof_row);
    free(w->stiffness);
    free(w->stiffness_work);
    free(w->stiffness_pivots);
    free(w->constraint);
    free(w->eigen_work);
    free(w->rotation_blocks);
    free(w->mode);
    free(w->branch_start_frame);
    free(w->branch_start_force);
    free(w->branch_mode);
    free(w->branch_dof_dir);
    free(w->branch_rest_frame);
    free(w->branch_rest_force);
    free(w);
}
