/* rod.c: the rod model, its state, tip loads and the scheme registry. */
#include "sim/rod.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/path.h"
#include "sim/geometry/proximity.h"
#include "sim/rod_geometry.h"
#include "sim/rod_grid.h"
#include "sim/contact/mesh.h"
#include "sim/contact/surface.h"
#include "sim/cut.h"
#include "sim/tissue/tissue.h"

/* How far (relative to the length) a path's first row may lie from the end
 * it moves, beyond what the shape's resampling moved that end: rounding. */
#define END_START_SLACK 1e-6

/* How far (rad) a clamped sliding end's starting tangent may be off its
 * slide and have the slide turned onto it: what a shape's resampling or
 * rounding leaves, far below any deliberate angle. */
#define SLIDE_ALIGN_SLACK 1e-3

rod_model rod_model_default(void)
{
    rod_model m;
    memset(&m, 0, sizeof m);
    /* table 1 */
    m.length = 1.0;
    m.diameter = 0.001;
    m.density = 850.0;
    m.youngs_modulus = 87.5e6;
    m.shear_modulus = 31.25e6;
    m.nodes = 51;
    m.rotary_inertia_scale = 1.0;
    m.tip_frame = ROD_FRAME_DIRECTOR;
    m.root_end = ROD_END_CLAMPED;
    m.tip_end = ROD_END_FREE;
    m.direction[0] = 1.0; /* straight along +x from the origin (thesis 4.2) */
    m.self_contact = 1;
    m.self_friction = 0.2;
    m.physics = (rod_physics){.twist = 1, .rotary_inertia = 1, .gravity = 1, .damping = 1,
                              .planar = 1};
    m.profile.kind = ROD_PROFILE_STEP;
    m.options.scheme = ROD_SCHEME_IMPLICIT;
    m.options.dt = 0.0;
    m.options.duration = 10.0;
    m.options.theta = 1.0;
    m.options.newton_tolerance = 1e-8;
    m.options.newton_max_iterations = 25;
    m.options.exact_rotation = 1;
    return m;
}

static int positive(double x) { return isfinite(x) && x > 0.0; }

static int finite3(const double v[3]) { return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]); }
static int zero3(const double v[3]) { return v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0; }

/* The rotation taking unit a to unit b about the axis a x b (the smallest);
 * exactly the identity when b = a. Antiparallel: half a turn about `spare`
 * (a unit vector normal to a). */
static void rotation_between(const double a[3], const double b[3], const double spare[3],
                             double r[9])
{
    double axis[3];
    v3_cross(axis, a, b);
    double sine = v3_norm(axis), cosine = v3_dot(a, b);
    if (sine == 0.0) {
        if (cosine > 0.0) {
            m3_identity(r);
            return;
        }
        v3_scale(axis, spare, M_PI);
    } else {
        v3_scale(axis, axis, atan2(sine, cosine) / sine);
    }
    m3_exp(r, axis);
}

/* The frame at the root of a rod whose tangent there is `tangent` (unit): the
 * smallest rotation taking x to it, applied to thesis 4.2's frame (d1 = y,
 * d2 = z, d3 = x). A rod along -x turns half a turn about z (d1 = -y). */
static void root_frame(const double tangent[3], double q[9])
{
    static const double x[3] = {1, 0, 0}, z[3] = {0, 0, 1};
    static const double straight[9] = {0, 0, 1,
                                       1, 0, 0,
                                       0, 1, 0}; /* columns d1 d2 d3 */
    double r[9];
    rotation_between(x, tangent, z, r);
    m3_mul(q, r, straight);
}

/* Node tangents of a polygon with segments exactly ds long (initial_shape;
 * on a graded grid each its own ds_j: the chain below holds for any lengths).
 * The staggered schemes take d3 of the midpoint frame, the geodesic midpoint
 * of the frames at a segment's two nodes, as the segment's direction (3.12),
 * so the node tangents must satisfy (n_i + n_{i+1}) / |n_i + n_{i+1}| = t_i,
 * the chord direction: n_{i+1} is n_i reflected about t_i (turned half a turn
 * about it). That fixes every n_i from n_0, and a poor n_0 leaves an
 * alternating error that reflections never damp (a zig-zag curvature). n_0 is
 * the unit vector whose chain stays nearest, in least squares, to the chords'
 * bisectors (a smooth but not exactly consistent choice): with P_k the
 * product of the first k reflections, n_0 = sum P_k^T b_k / |...|. A circle's
 * bisectors already form a chain, so there n_i are its tangents exactly.
 * Writes tangent (nodes x 3); -1 when two segments turn by more than
 * ROD_UNRESOLVED_BEND, with the node in *bad. */
static int shape_tangents(const rod_model *m, const double *shape, double *tangent, int *bad)
{
    const int n = m->nodes;
    /* bisectors b_i inside, stored in tangent[] for now */
    double previous[3] = {0, 0, 0}, t[3];
    for (int j = 0; j + 1 < n; j++) {
        v3_sub(t, &shape[3 * (j + 1)], &shape[3 * j]);
        v3_scale(t, t, 1.0 / v3_norm(t));
        if (j > 0) {
            if (acos(fmax(-1.0, fmin(1.0, v3_dot(previous, t)))) > ROD_UNRESOLVED_BEND) {
                *bad = j;
                return -1;
            }
            double sum[3];
            v3_add(sum, previous, t);
            v3_scale(&tangent[3 * j], sum, 1.0 / v3_norm(sum));
        }
        v3_copy(previous, t);
    }
    /* the ends' bisectors: mirrors of their neighbours about the end chords */
    for (int end = 0; end < 2; end++) {
        int node = end ? n - 1 : 0, next = end ? n - 2 : 1, seg = end ? n - 2 : 0;
        v3_sub(t, &shape[3 * (seg + 1)], &shape[3 * seg]);
        v3_scale(t, t, 1.0 / v3_norm(t));
        double k = 2.0 * v3_dot(&tangent[3 * next], t);
        for (int c = 0; c < 3; c++) tangent[3 * node + c] = k * t[c] - tangent[3 * next + c];
    }
    /* n_0 = sum_k P_k^T b_k normalised; P_{k+1} = (2 t_k t_k^T - I) P_k */
    double chain[9], sum[3];
    m3_identity(chain);
    v3_copy(sum, tangent);
    for (int k = 0; k + 1 < n; k++) {
        v3_sub(t, &shape[3 * (k + 1)], &shape[3 * k]);
        v3_scale(t, t, 1.0 / v3_norm(t));
        double reflect[9], back[3];
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) reflect[3 * r + c] = 2.0 * t[r] * t[c] - (r == c);
        m3_mul(chain, reflect, chain);
        m3_mul_tv(back, chain, &tangent[3 * (k + 1)]);
        v3_add(sum, sum, back);
    }
    v3_scale(tangent, sum, 1.0 / v3_norm(sum));
    for (int k = 0; k + 1 < n; k++) { /* n_{k+1} = 2 (n_k . t_k) t_k - n_k */
        v3_sub(t, &shape[3 * (k + 1)], &shape[3 * k]);
        v3_scale(t, t, 1.0 / v3_norm(t));
        double along = 2.0 * v3_dot(&tangent[3 * k], t);
        for (int c = 0; c < 3; c++) tangent[3 * (k + 1) + c] = along * t[c] - tangent[3 * k + c];
    }
    return 0;
}

/* Frames along the starting shape, twist-free: the root's by root_frame(),
 * each next one by the smallest rotation taking the node tangent to the next
 * (parallel transport: no rotation about d3, so u3 = 0). `tangent` is
 * (nodes x 3) scratch; NULL shape: straight along m->direction. Returns -1
 * as shape_tangents(). */
static int starting_frames(const rod_model *m, double *frame, double *tangent, int *bad)
{
    const int n = m->nodes;
    if (!m->initial_shape) {
        root_frame(m->direction, frame);
        for (int i = 1; i < n; i++) memcpy(&frame[9 * i], frame, 9 * sizeof(double));
        return 0;
    }
    if (shape_tangents(m, m->initial_shape, tangent, bad)) return -1;
    root_frame(tangent, frame);
    for (int i = 0; i + 1 < n; i++) {
        double r[9], spare[3];
        m3_column(spare, &frame[9 * i], 0); /* d1: normal to the tangent */
        rotation_between(&tangent[3 * i], &tangent[3 * (i + 1)], spare, r);
        m3_mul(&frame[9 * (i + 1)], r, &frame[9 * i]);
    }
    return 0;
}

/* Where end 0 (root) or 1 (tip) starts, m, global. */
static void end_start(const rod_model *m, int end, double out[3])
{
    if (m->initial_shape) {
        v3_copy(out, &m->initial_shape[3 * (end ? m->nodes - 1 : 0)]);
        return;
    }
    double unit[3];
    v3_scale(unit, m->direction, 1.0 / v3_norm(m->direction));
    for (int k = 0; k < 3; k++) out[k] = m->origin[k] + (end ? m->length : 0.0) * unit[k];
}

/* A starting shape whose strands already overlap (two non-neighbouring
 * segments closer than the diameter) is refused, naming the segments (1-based,
 * as the other shape messages) and the arc lengths of their closest points.
 * Non-neighbours: rod_proximity_skip (closer in arc length than pi d / 2 they
 * cannot touch as strands). 1e-6 relative slack: strands drawn exactly
 * touching stay accepted after the resampling's rounding. */
static int shape_self_contact(const rod_model *m, char *err, size_t errlen)
{
    rod_proximity *prox = rod_proximity_create(m->nodes);
    if (!prox) {
        snprintf(err, errlen, "shape: out of memory");
        return -1;
    }
    /* on a graded grid the neighbours skipped are counted in the shortest
     * segments (the most of them within pi d / 2) */
    double shortest = m->ds;
    for (int j = 0; m->segment_length && j + 1 < m->nodes; j++)
        shortest = fmin(shortest, m->segment_length[j]);
    rod_segment_pair c;
    int found = rod_proximity_min(prox, m->initial_shape, m->nodes,
                                  rod_proximity_skip(m->diameter, shortest), &c);
    rod_proximity_destroy(prox);
    if (found == 1 && c.distance < m->diameter * (1.0 - 1e-6)) {
        const double si = m->segment_length ? rod_node_arc(m, c.i) + c.s * rod_segment_ds(m, c.i)
                                            : (c.i + c.s) * m->ds;
        const double sj = m->segment_length ? rod_node_arc(m, c.j) + c.t * rod_segment_ds(m, c.j)
                                            : (c.j + c.t) * m->ds;
        snprintf(err, errlen, "shape: intersects itself: segments %d (s = %.6g m) and %d "
                 "(s = %.6g m) come %.6g m apart, closer than the diameter %.6g m; move the "
                 "strands at least one diameter apart",
                 c.i + 1, si, c.j + 1, sj, c.distance, m->diameter);
        return -1;
    }
    return 0;
}

/* The start's vectors and the needle: finite, the direction normalised. */
static int check_vectors(rod_model *m, char *err, size_t errlen)
{
    if (!finite3(m->origin)) {
        snprintf(err, errlen, "origin: must be 3 finite numbers, m");
        return -1;
    }
    if (!finite3(m->direction) || zero3(m->direction)) {
        snprintf(err, errlen, "direction: must be 3 finite numbers, not all 0 (the rod's "
                              "initial tangent, normalised)");
        return -1;
    }
    /* scaled by its largest component first: |v| of 1e308 1e308 0 overflows
     * and of 1e-170 0 0 underflows, either would lose the direction */
    double largest = fmax(fabs(m->direction[0]), fmax(fabs(m->direction[1]), fabs(m->direction[2])));
    v3_scale(m->direction, m->direction, 1.0 / largest);
    v3_scale(m->direction, m->direction, 1.0 / v3_norm(m->direction));
    if (!finite3(m->intrinsic_curvature)) {
        snprintf(err, errlen, "curvature: must be 3 finite numbers, 1/m (u0, director components)");
        return -1;
    }
    if (!finite3(m->initial_velocity)) {
        snprintf(err, errlen, "initial_velocity: must be 3 finite numbers, m/s");
        return -1;
    }
    if (!finite3(m->distributed_moment)) {
        snprintf(err, errlen, "distributed_moment: must be 3 finite numbers, N m/m");
        return -1;
    }
    if (!(m->needle_radius >= 0.0) || !isfinite(m->needle_radius)) {
        snprintf(err, errlen, "needle: must be a radius >= 0 m (0: no needle)");
        return -1;
    }
    return 0;
}

/* Point loads: an array for the count, each on a node, force and moment finite. */
static int check_point_loads(const rod_model *m, char *err, size_t errlen)
{
    if (m->point_load_count < 0 || (m->point_load_count > 0 && !m->point_loads)) {
        snprintf(err, errlen, "point_load: %d loads without their array", m->point_load_count);
        return -1;
    }
    for (int i = 0; i < m->point_load_count; i++) {
        const rod_point_load *p = &m->point_loads[i];
        if (p->node < 0 || p->node >= m->nodes || !finite3(p->force) || !finite3(p->moment)) {
            snprintf(err, errlen, "point_load: load %d: node %d must be 0..%d and force, moment "
                     "finite", i + 1, p->node, m->nodes - 1);
            return -1;
        }
    }
    return 0;
}

/* A starting shape: segments ds (ds_j) long, bends resolved, no self-intersection; it sets the
 * origin and the direction. */
static int check_shape(rod_model *m, char *err, size_t errlen)
{
    /* resampled (scene_read_rod): every segment ds long (on a graded grid its
     * own ds_j, sim/rod_grid.h), to 1e-6 */
    for (int j = 0; j + 1 < m->nodes; j++) {
        const double *a = &m->initial_shape[3 * j], *b = &m->initial_shape[3 * (j + 1)];
        const double ds = rod_segment_ds(m, j);
        double d[3];
        v3_sub(d, b, a);
        if (!finite3(a) || !finite3(b) || !(fabs(v3_norm(d) - ds) <= 1e-6 * ds)) {
            if (m->segment_length)
                snprintf(err, errlen, "shape: segment %d is %.9g m long; the starting shape must "
                         "have NS = %d finite nodes, segment %d %.9g m long (the graded grid of "
                         "rod.refine)", j + 1, v3_norm(d), m->nodes, j + 1, ds);
            else
                snprintf(err, errlen, "shape: segment %d is %.9g m long; the starting shape must "
                         "have NS = %d finite nodes %.9g m apart (length / (NS - 1))", j + 1,
                         v3_norm(d), m->nodes, m->ds);
            return -1;
        }
    }
    double *tangent = malloc((size_t)m->nodes * 3 * sizeof(double));
    if (!tangent) {
        snprintf(err, errlen, "shape: out of memory");
        return -1;
    }
    int bad = 0, rc = shape_tangents(m, m->initial_shape, tangent, &bad);
    if (rc == 0) {
        v3_copy(m->origin, m->initial_shape);
        v3_copy(m->direction, tangent);
    }
    free(tangent);
    if (rc) {
        snprintf(err, errlen, "shape: turns by more than %.1f rad between the segments "
                 "beside node %d (s = %.6g m): the grid does not resolve it; raise rod.nodes "
                 "or smooth the shape", ROD_UNRESOLVED_BEND, bad,
                 m->segment_length ? rod_node_arc(m, bad) : bad * m->ds);
        return -1;
    }
    return shape_self_contact(m, err, errlen);
}

/* One end's inputs, by the scene keys' prefix ("root", "tip"). */
typedef struct end_inputs {
    const char *name;
    rod_end_kind kind;
    double *slide;
    rod_path *motion;
} end_inputs;

/* An end's kind and slide: a known kind, a finite slide (normalised) only on a held end
 * (driven or not: a driven one slides along a sleeve that follows its path), a held
 * twist only on a clamped end that slides, and a clamped end on a sleeve that turns
 * (a path with rotation) holds its twist (the sleeve carries the end's frame). */
static int check_end_slide(const rod_model *m, int e, const end_inputs *end, char *err,
                           size_t errlen)
{
    if ((int)end->kind < 0 || end->kind > ROD_END_FREE) {
        snprintf(err, errlen, "%s: unknown end condition %d", end->name, (int)end->kind);
        return -1;
    }
    double *slide = end->slide;
    if (!finite3(slide)) {
        snprintf(err, errlen, "%s_slide: must be 3 finite numbers (0 0 0: held in place)",
                 end->name);
        return -1;
    }
    if (!zero3(slide)) {
        if (end->kind == ROD_END_FREE) {
            snprintf(err, errlen, "%s_slide: the %s is free: only a held end slides (set %s = "
                     "pinned or clamped)", end->name, end->name, end->name);
            return -1;
        }
        if (end->motion && end->kind == ROD_END_CLAMPED && rod_path_columns(end->motion) == 7 &&
            !m->slide_twist_held[e]) {
            snprintf(err, errlen, "%s_slide: the clamped %s slides along a sleeve that turns "
                     "(%s_motion has rotation columns), which carries the end's frame: set "
                     "%s_twist = held (a sleeve that turns the end), or give the path as "
                     "t,x,y,z (a sleeve that only moves)", end->name, end->name, end->name,
                     end->name);
            return -1;
        }
        v3_scale(slide, slide, 1.0 / v3_norm(slide));
    }
    if (m->slide_twist_held[e] && (zero3(slide) || end->kind != ROD_END_CLAMPED)) {
        snprintf(err, errlen, "%s_twist: held applies to a clamped %s on a slide (%s = "
                 "clamped and %s_slide); elsewhere the end condition says it (accepted: "
                 "free, held)", end->name, end->name, end->name, end->name);
        return -1;
    }
    return 0;
}

/* A clamped end that slides keeps d3 along the slide: it must start so. A shape's end
 * chord off the slide by rounding turns the slide onto it (reported in m->adjusted). */
static int check_clamped_slide(rod_model *m, int e, const end_inputs *end, char *err,
                               size_t errlen)
{
    double *slide = end->slide;
    if (zero3(slide) || end->kind != ROD_END_CLAMPED) return 0;
    double tangent[3], cross[3];
    if (m->initial_shape) {
        const double *a = &m->initial_shape[3 * (e ? m->nodes - 2 : 0)];
        v3_sub(tangent, &m->initial_shape[3 * (e ? m->nodes - 1 : 1)], a);
        v3_scale(tangent, tangent, 1.0 / v3_norm(tangent));
    } else {
        v3_copy(tangent, m->direction);
    }
    v3_cross(cross, tangent, slide);
    if (v3_norm(cross) > 1e-9 && v3_norm(cross) <= SLIDE_ALIGN_SLACK &&
        v3_dot(tangent, slide) > 0.0) {
        /* a shape's end chord off the slide by rounding or resampling:
         * the slide turns onto it (reported), the end does not jump */
        size_t used = strlen(m->adjusted);
        snprintf(m->adjusted + used, sizeof m->adjusted - used,
                 "%s%s_slide: turned by %.3g rad onto the %s's starting tangent", used ? "; " : "",
                 end->name, asin(fmin(1.0, v3_norm(cross))), end->name);
        v3_copy(slide, tangent);
        v3_set(cross, 0.0, 0.0, 0.0);
    }
    if (v3_norm(cross) > 1e-9) {
        snprintf(err, errlen, "%s_slide: a clamped %s that slides keeps its tangent d3 "
                 "along the slide, but it starts along (%.6g, %.6g, %.6g): give a slide "
                 "along it, or pin the %s", end->name, end->name, tangent[0],
                 tangent[1], tangent[2], end->name);
        return -1;
    }
    return 0;
}

/* A driven end's path: on a held end, rotation only where it may turn, starting where the
 * end starts (within the resampling's shift, which moves the path, reported) and with
 * no rotation. */
static int check_end_path(rod_model *m, int e, const end_inputs *end, const double start[3],
                          char *err, size_t errlen)
{
    const rod_path *path = end->motion;
    if (!path) return 0;
    if (end->kind == ROD_END_FREE) {
        snprintf(err, errlen, "%s_motion: the %s is free: a driven end must be held (set %s "
                 "= clamped or pinned)", end->name, end->name, end->name);
        return -1;
    }
    /* a pinned tip carrying a needle may take a rotation: it turns the
     * needle drawn there (the thread swivels at the needle's back; the
     * mechanics ignore it, sim/recording.c draws it) */
    if (end->kind == ROD_END_PINNED && rod_path_columns(path) == 7 &&
        !(e == 1 && m->needle_radius > 0.0)) {
        snprintf(err, errlen, "%s_motion: the %s is pinned (free to rotate): its path has no "
                 "rotation (except a tip's that turns its needle); give t,x,y,z, or set %s = "
                 "clamped", end->name, end->name,
                 end->name);
        return -1;
    }
    rod_pose first;
    rod_path_eval(path, rod_path_start(path), &first);
    double gap[3], turn = 0.0;
    v3_sub(gap, first.position, start);
    for (int k = 0; k < 9; k++) turn = fmax(turn, fabs(first.rotation[k] - (k % 4 == 0)));
    /* The resampling to NS nodes moves the tip off the shape's last point
     * (the chords' shortfall, scene.c: resample), where the path was
     * written to start: a path that starts within that of the tip is
     * shifted onto it, and the shift is reported. */
    double moved = e == 1 ? m->shape_tip_moved : 0.0;
    double tolerance = END_START_SLACK * m->length + moved;
    if (!(v3_norm(gap) <= tolerance)) {
        snprintf(err, errlen, "%s_motion: the path starts at (%.9g, %.9g, %.9g) m but the %s "
                 "starts at (%.9g, %.9g, %.9g) m, %.3g m away: the first row is the %s's "
                 "starting position (within %.3g m: %g of the length%s)", end->name,
                 first.position[0], first.position[1], first.position[2], end->name,
                 start[0], start[1], start[2], v3_norm(gap), end->name, tolerance,
                 END_START_SLACK, moved > 0.0 ? ", plus how far the resampling of the "
                 "shape to rod.nodes moved the tip" : "");
        return -1;
    }
    if (v3_norm(gap) > END_START_SLACK * m->length) {
        double shift[3];
        v3_scale(shift, gap, -1.0);
        rod_path_translate(end->motion, shift);
        size_t used = strlen(m->adjusted);
        snprintf(m->adjusted + used, sizeof m->adjusted - used,
                 "%s%s_motion: the path is shifted by %.3g m onto where the %s starts (the "
                 "shape resampled to %d nodes puts the %s %.3g m from the shape's last point)",
                 used ? "; " : "", end->name, v3_norm(gap), end->name, m->nodes,
                 end->name, moved);
    }
    if (turn > 0.0) {
        snprintf(err, errlen, "%s_motion: the first row's rotation must be 0 0 0 (the "
                 "rotation is from the %s's starting frame)", end->name, end->name);
        return -1;
    }
    return 0;
}

/* The checks of the ends' and the start's inputs. Messages start with the scene key
 * ("tip_motion: ...") so the scene reader can name its line. */
static int derive_ends_and_shape(rod_model *m, char *err, size_t errlen)
{
    if (check_vectors(m, err, errlen) || check_point_loads(m, err, errlen)) return -1;
    if (m->initial_shape && check_shape(m, err, errlen)) return -1;
    const end_inputs ends[2] = {{"root", m->root_end, m->root_slide, m->root_motion},
                                {"tip", m->tip_end, m->tip_slide, m->tip_motion}};
    for (int e = 0; e < 2; e++) {
        if (check_end_slide(m, e, &ends[e], err, errlen)) return -1;
        double start[3];
        end_start(m, e, start);
        if (check_clamped_slide(m, e, &ends[e], err, errlen) ||
            check_end_path(m, e, &ends[e], start, err, errlen))
            return -1;
    }
    return 0;
}

/* A graded grid (rod.refine): its segment lengths, and the schemes that
 * model a uniform grid only refused by name. */
static int derive_grid(rod_model *m, char *err, size_t errlen)
{
    if (m->refine_count == 0) {
        free(m->segment_length);
        m->segment_length = NULL;
        return 0;
    }
    if (rod_grid_check(m, err, errlen)) return -1;
    /* every part of a scene runs on it (records 0152-0158 and 0161) but
     * the thesis and static schemes, which keep (4.1) */
    if (m->options.scheme != ROD_SCHEME_IMPLICIT)
        return rod_grid_refuse(m, "the thesis and static schemes", err, errlen);
    if (!m->segment_length) {
        m->segment_length = malloc((size_t)(m->nodes - 1) * sizeof *m->segment_length);
        if (!m->segment_length) {
            snprintf(err, errlen, "refine: out of memory");
            return -1;
        }
    }
    rod_grid_segment_lengths(m, m->segment_length);
    return 0;
}

int rod_model_derive(rod_model *m, char *err, size_t errlen)
{
    const char *bad = NULL;
    if (!positive(m->length)) bad = "length must be > 0 m";
    else if (!positive(m->diameter)) bad = "diameter must be > 0 m";
    else if (m->diameter >= m->length) bad = "diameter must be smaller than the length (a rod is slender)";
    else if (!positive(m->density)) bad = "density must be > 0 kg/m^3";
    else if (!positive(m->youngs_modulus)) bad = "youngs_modulus must be > 0 Pa";
    else if (!positive(m->shear_modulus)) bad = "shear_modulus must be > 0 Pa";
    else if (m->nodes < 3) bad = "nodes must be >= 3";
    else if (m->nodes > 100001) bad = "nodes must be <= 100001";
    else if (!positive(m->rotary_inertia_scale)) bad = "rotary_inertia_scale must be > 0";
    else if (!(m->linear_damping >= 0.0) || !(m->angular_damping >= 0.0)) bad = "damping must be >= 0";
    else if (!(m->options.duration >= 0.0) || !isfinite(m->options.duration)) bad = "duration must be >= 0 s";
    else if (!(m->options.theta >= 0.5 && m->options.theta <= 1.0)) bad = "theta must be in [0.5, 1]";
    if (bad) {
        snprintf(err, errlen, "%s", bad);
        return -1;
    }
    double d = m->diameter;
    m->ds = m->length / (m->nodes - 1);                 /* (4.1) */
    if (derive_grid(m, err, errlen)) return -1;
    m->area = M_PI * d * d / 4.0;
    m->second_moment = M_PI * pow(d, 4) / 64.0;         /* I = pi d^4 / 64 */
    m->polar_moment = M_PI * pow(d, 4) / 32.0;          /* J = pi d^4 / 32 */
    m->stiffness[0] = m->youngs_modulus * m->second_moment; /* (3.5) B1 = E I1 */
    m->stiffness[1] = m->youngs_modulus * m->second_moment; /*       B2 = E I2 */
    m->stiffness[2] = m->shear_modulus * m->polar_moment;   /*       C  = G J  */
    m->mass_per_length = m->density * m->area;
    /* principal mass moments of inertia per length: rho I1, rho I2, rho J */
    m->rotary_inertia[0] = m->density * m->second_moment * m->rotary_inertia_scale;
    m->rotary_inertia[1] = m->density * m->second_moment * m->rotary_inertia_scale;
    m->rotary_inertia[2] = m->density * m->polar_moment * m->rotary_inertia_scale;
    if (!m->physics.twist) m->rotary_inertia[2] = 0.0;
    if (!m->physics.rotary_inertia) m->rotary_inertia[0] = m->rotary_inertia[1] = m->rotary_inertia[2] = 0.0;
    return derive_ends_and_shape(m, err, errlen);
}

int rod_model_loads_planar(const rod_model *m)
{
    /* out-of-plane components: force on d2 (global z), moment on d1/d3 (global x, y) */
    int force_z = m->tip_frame == ROD_FRAME_DIRECTOR ? 1 : 2;
    int moment_in = m->tip_frame == ROD_FRAME_DIRECTOR ? 1 : 2; /* the one allowed axis */
    const rod_profile *p = &m->profile;
    int table7 = p->kind == ROD_PROFILE_TABLE && p->table.columns == 7;
    for (int r = 0; r < (table7 ? p->table.rows : 1); r++) {
        const double *f = table7 ? &p->table.data[7 * r + 1] : m->tip_force;
        const double *mo = table7 ? &p->table.data[7 * r + 4] : m->tip_moment;
        if (f[force_z] != 0.0) return 0;
        for (int k = 0; k < 3; k++)
            if (k != moment_in && mo[k] != 0.0) return 0;
    }
    if (m->distributed_force[2] != 0.0) return 0;
    /* the starting shape in the x-y plane with d2 = z (so u0 bends about d2 only),
     * every new load in the plane, slides and paths in it, turning about z only */
    if (m->origin[2] != 0.0 || m->direction[2] != 0.0 || m->initial_velocity[2] != 0.0) return 0;
    if (m->intrinsic_curvature[0] != 0.0 || m->intrinsic_curvature[2] != 0.0) return 0;
    if (m->distributed_moment[0] != 0.0 || m->distributed_moment[1] != 0.0) return 0;
    if (m->root_slide[2] != 0.0 || m->tip_slide[2] != 0.0) return 0;
    if (m->initial_shape)
        for (int i = 0; i < m->nodes; i++)
            if (m->initial_shape[3 * i + 2] != 0.0) return 0;
    for (int i = 0; i < m->point_load_count; i++) {
        const rod_point_load *load = &m->point_loads[i];
        if (load->force[2] != 0.0 || load->moment[0] != 0.0 || load->moment[1] != 0.0) return 0;
    }
    if ((m->root_motion && !rod_path_planar(m->root_motion)) ||
        (m->tip_motion && !rod_path_planar(m->tip_motion)))
        return 0;
    /* a pinned or free root may turn out of the plane (no torsional or bending stop) */
    return m->root_end == ROD_END_CLAMPED;
}

/* Releases what the model owns. A model copied by assignment shares these
 * arrays and paths: release exactly one of the copies. */
void rod_model_release(rod_model *m)
{
    free(m->profile.table.data);
    m->profile.table.data = NULL;
    free(m->initial_shape);
    m->initial_shape = NULL;
    free(m->initial_frames);
    m->initial_frames = NULL;
    free(m->segment_length);
    m->segment_length = NULL;
    free(m->point_loads);
    m->point_loads = NULL;
    m->point_load_count = 0;
    for (int k = 0; k < m->surface_count; k++) {
        rod_mesh_destroy(m->surfaces[k].mesh);
        if (!m->surfaces[k].solid_shared) tissue_destroy(m->surfaces[k].solid);
    }
    free(m->surfaces);
    m->surfaces = NULL;
    m->surface_count = 0;
    free(m->punctures);
    m->punctures = NULL;
    m->puncture_count = 0;
    m->profile.table.rows = 0;
    rod_path_destroy(m->root_motion);
    m->root_motion = NULL;
    rod_path_destroy(m->tip_motion);
    m->tip_motion = NULL;
    for (int k = 0; k < m->instrument_count; k++) {
        rod_path_destroy(m->instruments[k].pose);
        rod_path_destroy(m->instruments[k].jaw);
    }
    free(m->instruments);
    m->instruments = NULL;
    m->instrument_count = 0;
    free(m->cut_events);
    m->cut_events = NULL;
    m->cut_event_count = 0;
}

int rod_model_refuse_obstacles(const rod_model *m, const char *scheme, char *err, size_t errlen)
{
    if (m->surface_count == 0 && m->puncture_count == 0 && m->instrument_count == 0) return 0;
    if (m->instrument_count > 0 && m->surface_count == 0 && m->puncture_count == 0) {
        snprintf(err, errlen, "the %s scheme models no contact; this scene has %d [instrument] "
                 "sections: use scheme = implicit", scheme, m->instrument_count);
        return -1;
    }
    snprintf(err, errlen,
             "the %s scheme models no contact; this scene has %d [surface] and %d [puncture] "
             "sections: use scheme = implicit", scheme, m->surface_count, m->puncture_count);
    return -1;
}

int rod_model_require_cantilever(const rod_model *m, const char *scheme, char *err,
                                 size_t errlen)
{
    static const char *const names[] = {"clamped", "pinned", "free"};
    if (m->root_end != ROD_END_CLAMPED || m->tip_end != ROD_END_FREE) {
        snprintf(err, errlen,
                 "the %s scheme models a cantilever only (ends root = clamped, tip = free); this "
                 "scene asks for root = %s, tip = %s: use a scheme that supports them",
                 scheme, names[m->root_end], names[m->tip_end]);
        return -1;
    }
    /* the ends' and the start's inputs, each named by its scene key */
    const char *key = NULL;
    if (!zero3(m->origin)) key = "[rod] origin";
    else if (m->direction[0] != 1.0 || m->direction[1] != 0.0 || m->direction[2] != 0.0)
        key = "[rod] direction";
    else if (m->initial_shape) key = "[rod] shape";
    else if (!zero3(m->intrinsic_curvature)) key = "[rod] curvature";
    else if (!zero3(m->initial_velocity)) key = "[rod] initial_velocity";
    else if (m->point_load_count > 0) key = "[point_load]";
    else if (!zero3(m->distributed_moment)) key = "[loads] distributed_moment";
    else if (!zero3(m->root_slide)) key = "[ends] root_slide";
    else if (!zero3(m->tip_slide)) key = "[ends] tip_slide";
    else if (m->root_motion) key = "[ends] root_motion";
    else if (m->tip_motion) key = "[ends] tip_motion";
    else if (m->needle_radius != 0.0) key = "[ends] needle";
    if (!key) return 0;
    snprintf(err, errlen,
             "the %s scheme models the thesis' cantilever only (a straight rod along +x from the "
             "origin, at rest, clamped at the root, loaded at the tip): it does not support %s; "
             "remove it, or use a scheme that supports it",
             scheme, key);
    return -1;
}

/* Row index k with t_k <= t < t_{k+1} (clamped), and the weight of row k+1. */
static void table_locate(const rod_table *tab, double t, int *k, double *w)
{
    const double *d = tab->data;
    int c = tab->columns, n = tab->rows;
    if (n == 1 || t <= d[0]) { *k = 0; *w = 0.0; return; }
    if (t >= d[(n - 1) * c]) { *k = n - 1; *w = 0.0; return; }
    int lo = 0, hi = n - 1; /* d[lo] <= t < d[hi] */
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (d[mid * c] <= t) lo = mid; else hi = mid;
    }
    *k = lo;
    *w = (t - d[lo * c]) / (d[hi * c] - d[lo * c]);
}

static double table_value(const rod_table *tab, double t, int column)
{
    int k;
    double w;
    table_locate(tab, t, &k, &w);
    double a = tab->data[k * tab->columns + column];
    if (w == 0.0) return a;
    double b = tab->data[(k + 1) * tab->columns + column];
    return a + w * (b - a);
}

double rod_profile_factor(const rod_profile *p, double t)
{
    switch (p->kind) {
    case ROD_PROFILE_STEP:
        return 1.0;
    case ROD_PROFILE_RAMP:
        if (p->t1 <= 0.0) return 1.0;
        return t <= 0.0 ? 0.0 : (t >= p->t1 ? 1.0 : t / p->t1);
    case ROD_PROFILE_PULSE:
        return (t >= p->t1 && t < p->t2) ? 1.0 : 0.0;
    case ROD_PROFILE_IMPULSE:
        if (t >= 0.0 && t < p->t1) return 1.0;
        if (t >= p->t1 && t < 2.0 * p->t1) return -1.0;
        return 0.0;
    case ROD_PROFILE_TABLE:
        return p->table.rows > 0 && p->table.columns == 2 ? table_value(&p->table, t, 1) : 1.0;
    }
    return 1.0;
}

void rod_tip_load(const rod_model *m, double t, double force[3], double moment[3])
{
    const rod_profile *p = &m->profile;
    if (p->kind == ROD_PROFILE_TABLE && p->table.columns == 7 && p->table.rows > 0) {
        for (int k = 0; k < 3; k++) {
            force[k] = table_value(&p->table, t, 1 + k);
            moment[k] = table_value(&p->table, t, 4 + k);
        }
        return;
    }
    double f = rod_profile_factor(p, t);
    v3_scale(force, m->tip_force, f);
    v3_scale(moment, m->tip_moment, f);
}

double rod_first_bending_frequency(const rod_model *m)
{
    const double beta1 = 1.8751040687119611; /* first root of cos x cosh x = -1 */
    return beta1 * beta1 / (2.0 * M_PI * m->length * m->length) *
           sqrt(m->stiffness[0] / m->mass_per_length);
}

rod_state *rod_state_create(const rod_model *m)
{
    rod_state *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    size_t n = (size_t)m->nodes;
    s->nodes = m->nodes;
    s->position = calloc(n * 3, sizeof(double));
    s->frame = calloc(n * 9, sizeof(double));
    s->velocity = calloc(n * 3, sizeof(double));
    s->angular_velocity = calloc(n * 3, sizeof(double));
    s->darboux = calloc(n * 3, sizeof(double));
    s->contact_force = calloc(n * 3, sizeof(double));
    s->surface_force = calloc(n * 3, sizeof(double));
    s->self_force = calloc(n * 3, sizeof(double));
    if (!s->position || !s->frame || !s->velocity || !s->angular_velocity || !s->darboux ||
        !s->contact_force || !s->surface_force || !s->self_force) {
        rod_state_destroy(s);
        return NULL;
    }
    rod_state_reset(m, s);
    return s;
}

void rod_state_destroy(rod_state *s)
{
    if (!s) return;
    rod_cut_clear(s);
    free(s->position);
    free(s->frame);
    free(s->velocity);
    free(s->angular_velocity);
    free(s->darboux);
    free(s->contact_force);
    free(s->surface_force);
    free(s->self_force);
    free(s);
}

void rod_state_copy(rod_state *to, const rod_state *from)
{
    const size_t n3 = (size_t)from->nodes * 3 * sizeof(double);
    memcpy(to->position, from->position, n3);
    memcpy(to->frame, from->frame, 3 * n3);
    memcpy(to->velocity, from->velocity, n3);
    memcpy(to->angular_velocity, from->angular_velocity, n3);
    memcpy(to->darboux, from->darboux, n3);
    memcpy(to->contact_force, from->contact_force, n3);
    memcpy(to->surface_force, from->surface_force, n3);
    memcpy(to->self_force, from->self_force, n3);
    to->staggered = from->staggered;
    to->time = from->time;
    memcpy(to->end_force, from->end_force, sizeof to->end_force);
    memcpy(to->end_moment, from->end_moment, sizeof to->end_moment);
    to->strand_gap = from->strand_gap;
    to->puncture_count = from->puncture_count;
    memcpy(to->puncture, from->puncture, sizeof to->puncture);
    memcpy(to->grasp, from->grasp, sizeof to->grasp);
    to->grasp_log_count = from->grasp_log_count;
    memcpy(to->grasp_log, from->grasp_log, sizeof to->grasp_log);
    rod_cut_share(to, from);
}

void rod_state_reset(const rod_model *m, rod_state *s)
{
    rod_cut_clear(s); /* the whole thread again */
    size_t n = (size_t)s->nodes;
    s->time = 0.0;
    memset(s->angular_velocity, 0, n * 3 * sizeof(double));
    memset(s->darboux, 0, n * 3 * sizeof(double));
    memset(s->contact_force, 0, n * 3 * sizeof(double));
    memset(s->end_force, 0, sizeof s->end_force);
    memset(s->end_moment, 0, sizeof s->end_moment);
    memset(s->surface_force, 0, n * 3 * sizeof(double));
    memset(s->self_force, 0, n * 3 * sizeof(double));
    s->strand_gap = INFINITY;
    memset(s->puncture, 0, sizeof s->puncture);
    s->puncture_count = 0;
    memset(s->grasp, 0, sizeof s->grasp);
    s->grasp_log_count = 0;
    /* the starting shape: positions exactly its nodes; frames twist-free along it. The
     * tangents go in the velocity array (n x 3) until the velocities are written. */
    int bad;
    if (m->initial_frames) {
        /* a settled start (sim/settle.h): the frames it left */
        memcpy(s->frame, m->initial_frames, n * 9 * sizeof(double));
    } else if (starting_frames(m, s->frame, s->velocity, &bad)) {
        /* rod_model_derive() refuses such a shape; a model not derived gets the default */
        static const double x[3] = {1, 0, 0};
        root_frame(x, s->frame);
        for (size_t i = 1; i < n; i++) memcpy(&s->frame[9 * i], s->frame, 9 * sizeof(double));
    }
    if (m->initial_shape) {
        memcpy(s->position, m->initial_shape, n * 3 * sizeof(double));
        /* u_{i+1/2} = log(Q_i^T Q_{i+1}) / ds at the midpoints, as the staggered schemes
         * compute it (rod_geometry.h); the tip entry repeats the last midpoint's */
        rod_darboux_from_frames(m, s->frame, s->darboux);
        v3_copy(&s->darboux[3 * (n - 1)], &s->darboux[3 * (n - 2)]);
        s->staggered = 1;
    } else {
        /* thesis 4.2: straight from the origin along d3 (+x by default: d1 = y, d2 = z) */
        double d3[3];
        m3_column(d3, s->frame, 2);
        double arc = 0.0; /* a graded grid's s_i */
        for (size_t i = 0; i < n; i++) {
            for (int k = 0; k < 3; k++)
                s->position[3 * i + k] =
                    m->origin[k] + (m->segment_length ? arc : (double)i * m->ds) * d3[k];
            if (m->segment_length && i + 1 < n) arc += m->segment_length[i];
        }
    }
    /* initial_velocity is global; the state keeps velocity in director components */
    for (size_t i = 0; i < n; i++) m3_mul_tv(&s->velocity[3 * i], &s->frame[9 * i], m->initial_velocity);
    /* an elastic pad back at its rest under its pretension and weight (a
     * model run again, or a run's second pass for its video, starts where
     * the first did); it found that rest when the scene was read, and a
     * failure here leaves it where it is */
    for (int j = 0; j < m->surface_count; j++) {
        if (!m->surfaces[j].solid) continue;
        char why[256];
        /* a pad shared by several rods is reset with its owner's */
        if (!m->surfaces[j].solid_shared) {
            tissue_clear_forces(m->surfaces[j].solid);
            (void)tissue_solve_static(m->surfaces[j].solid, NULL, why, sizeof why);
        }
        if (m->surfaces[j].mesh)
            rod_mesh_move(m->surfaces[j].mesh, tissue_positions(m->surfaces[j].solid), 0.0);
    }
    /* the scene's punctures, at the arc length of the starting shape nearest
     * them; one on a tissue surface's boundary (within 1 % of the radius)
     * or, an elastic pad's, within the thread's radius of its settled
     * surface (the scene's holes are meant on the skin as it is at t = 0)
     * belongs to that surface, so that the thread between two of them is
     * inside it (rod_threaded_nodes) */
    for (int p = 0; p < m->puncture_count && p < ROD_MAX_PUNCTURES; p++) {
        rod_puncture_state *ps = &s->puncture[s->puncture_count++];
        v3_copy(ps->point, m->punctures[p].point);
        ps->friction = m->punctures[p].friction;
        ps->surface = -1;
        for (int j = 0; j < m->surface_count && j < 32 && ps->surface < 0; j++) {
            const rod_surface *sf = &m->surfaces[j];
            if (sf->tissue && (fabs(rod_surface_gap(sf, ps->point, 0.0, NULL, NULL)) <=
                                   0.005 * m->diameter ||
                               (sf->solid && sf->mesh &&
                                fabs(rod_mesh_distance(sf->mesh, ps->point, NULL, NULL)) <=
                                    0.5 * m->diameter)))
                ps->surface = j;
        }
        ps->s = rod_nearest_arc_length(m, s->position, ps->point, NULL);
    }
}

/* A graded grid's slack beside a puncture at node i (rod_threaded_nodes):
 * the longer of the node's segments, but at least the thread's diameter. */
static double node_slack(const rod_model *m, int i)
{
    const double left = i > 0 ? m->segment_length[i - 1] : 0.0,
                 right = i < m->nodes - 1 ? m->segment_length[i] : 0.0;
    return fmax(fmax(left, right), m->diameter);
}

void rod_threaded_nodes(const rod_model *m, const rod_state *s, unsigned *threaded)
{
    /* m: the slack beside a puncture, a segment's length but at least the
     * thread's diameter: a node within a diameter of the hole along a
     * thread bending into it lies within its radius of the skin (at 45
     * degrees a node is clear of it 0.71 d from the hole), pressed by the
     * skin against the puncture that holds the thread there; the hole's rim
     * is the puncture's */
    const double slack = fmax(m->ds, m->diameter);
    const int n = m->nodes;
    /* a graded grid: s_i summed from the root as rod_node_arc, the slack by
     * node i's longer segment */
    const double *seg = m->segment_length;
    memset(threaded, 0, (size_t)n * sizeof *threaded);
    for (int j = 0; j < m->surface_count && j < 32; j++) {
        double entry = -1.0;
        for (int k = 0; k < s->puncture_count; k++) {
            /* a track's points lie between its holes: threaded with them */
            if (s->puncture[k].surface != j || s->puncture[k].track) continue;
            if (entry < 0.0) {
                entry = s->puncture[k].s;
                continue;
            }
            double exit_s = s->puncture[k].s, lo = fmin(entry, exit_s), hi = fmax(entry, exit_s);
            double arc = 0.0;
            for (int i = 0; i < n; i++) {
                const double si = seg ? arc : i * m->ds, sl = seg ? node_slack(m, i) : slack;
                if (si >= lo - sl && si <= hi + sl) threaded[i] |= 1u << j;
                if (seg && i + 1 < n) arc += seg[i];
            }
            entry = -1.0;
        }
        if (entry >= 0.0) {
            double arc = 0.0;
            for (int i = 0; i < n; i++) {
                const double si = seg ? arc : i * m->ds, sl = seg ? node_slack(m, i) : slack;
                if (si >= entry - sl) threaded[i] |= 1u << j;
                if (seg && i + 1 < n) arc += seg[i];
            }
        }
    }
}

double rod_nearest_arc_length_between(const rod_model *m, const double *position,
                                      const double p[3], int first, int last, double *distance)
{
    if (first < 0) first = 0;
    if (last > m->nodes - 2) last = m->nodes - 2;
    /* arc length s_j + f ds_j of segment j's point at fraction f */
    const double *graded = m->segment_length;
    double best = INFINITY, best_s = graded ? rod_node_arc(m, first) : first * m->ds;
    double s_j = best_s;
    for (int j = first; j <= last; s_j += graded ? graded[j] : 0.0, j++) {
        const double *a = &position[3 * j], *b = &position[3 * (j + 1)];
        double ab[3], ap[3], q[3];
        v3_sub(ab, b, a);
        v3_sub(ap, p, a);
        double len2 = v3_dot(ab, ab), f = len2 > 0.0 ? v3_dot(ap, ab) / len2 : 0.0;
        f = f < 0.0 ? 0.0 : f > 1.0 ? 1.0 : f;
        for (int k = 0; k < 3; k++) q[k] = a[k] + f * ab[k] - p[k];
        double d = v3_norm(q);
        if (d < best) {
            best = d;
            best_s = graded ? s_j + f * graded[j] : (j + f) * m->ds;
        }
    }
    if (distance) *distance = best;
    return best_s;
}

double rod_nearest_arc_length(const rod_model *m, const double *position, const double p[3],
                              double *distance)
{
    return rod_nearest_arc_length_between(m, position, p, 0, m->nodes - 2, distance);
}

void rod_internal_force(const rod_state *s, double *out)
{
    const int n = s->nodes;
    if (!s->staggered) { /* at the nodes, in the node frames */
        for (int i = 0; i < n; i++) m3_mul_v(&out[3 * i], &s->frame[9 * i], &s->contact_force[3 * i]);
        return;
    }
    /* N_{j+1/2} is held in the midpoint frame, the geodesic midpoint of Q_j and Q_{j+1}
     * (Q_j exp(ds/2 [u]x) with u = log(Q_j^T Q_{j+1}) / ds, rod_geometry.h); written into
     * out[j+1] first, then averaged to the nodes in place (going up, out[j+1] still holds
     * N_{j+1/2} when node j is done) */
    for (int j = 0; j + 1 < n; j++) {
        double rel[9], half[3], local[3];
        m3_mul_tn(rel, &s->frame[9 * j], &s->frame[9 * (j + 1)]);
        m3_log(half, rel);
        v3_scale(half, half, 0.5);
        v3_rotate(local, half, &s->contact_force[3 * j]);
        m3_mul_v(&out[3 * (j + 1)], &s->frame[9 * j], local);
    }
    /* node 0: N(0), the force the rod exerts on what holds its root (0 at a free root:
     * Antman's sign, N(s) acts on [0, s] from beyond s) */
    double previous[3];
    v3_copy(previous, &out[3]);
    v3_copy(out, s->end_force[0]);
    for (int i = 1; i + 1 < n; i++) {
        double here[3];
        v3_copy(here, &out[3 * (i + 1)]); /* N_{i+1/2} */
        for (int k = 0; k < 3; k++) out[3 * i + k] = 0.5 * (previous[k] + here[k]);
        v3_copy(previous, here);
    }
    /* node n-1: the tip entry, N(L), in the tip frame (at a held tip, -end_force[1]) */
    m3_mul_v(&out[3 * (n - 1)], &s->frame[9 * (n - 1)], &s->contact_force[3 * (n - 1)]);
}

double rod_kinetic_energy(const rod_model *m, const rod_state *s)
{
    double e = 0.0;
    for (int i = 1; i < s->nodes; i++) {
        double w = m->segment_length        ? rod_cell_length(m, i)
                   : (i == s->nodes - 1) ? 0.5 * m->ds
                                         : m->ds;
        const double *v = &s->velocity[3 * i], *om = &s->angular_velocity[3 * i];
        e += 0.5 * w * m->mass_per_length * v3_dot(v, v);
        for (int k = 0; k < 3; k++) e += 0.5 * w * m->rotary_inertia[k] * om[k] * om[k];
    }
    return e;
}

double rod_frame_orthonormality_error(const rod_state *s)
{
    double worst = 0.0;
    for (int i = 0; i < s->nodes; i++) {
        double qtq[9];
        m3_mul_tn(qtq, &s->frame[9 * i], &s->frame[9 * i]);
        for (int k = 0; k < 9; k++) {
            double e = fabs(qtq[k] - ((k % 4 == 0) ? 1.0 : 0.0));
            if (e > worst) worst = e;
        }
    }
    return worst;
}

double rod_segment_length_error(const rod_model *m, const rod_state *s)
{
    double worst = 0.0;
    for (int i = 0; i + 1 < s->nodes; i++) {
        double d[3];
        v3_sub(d, &s->position[3 * (i + 1)], &s->position[3 * i]);
        const double ds = rod_segment_ds(m, i);
        double e = fabs(v3_norm(d) - ds) / ds;
        if (e > worst) worst = e;
    }
    return worst;
}

static int all_finite(const double *a, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(a[i])) return 0;
    return 1;
}

int rod_state_is_finite(const rod_state *s)
{
    size_t n = (size_t)s->nodes;
    return isfinite(s->time) && all_finite(s->position, 3 * n) && all_finite(s->frame, 9 * n) &&
           all_finite(s->velocity, 3 * n) && all_finite(s->angular_velocity, 3 * n) &&
           all_finite(s->darboux, 3 * n) && all_finite(s->contact_force, 3 * n);
}

/* Schemes ------------------------------------------------------------- */

const rod_scheme_ops *rod_scheme_get(rod_scheme_kind kind)
{
    switch (kind) {
    case ROD_SCHEME_THESIS: return &rod_scheme_thesis;
    case ROD_SCHEME_IMPLICIT: return &rod_scheme_implicit;
    case ROD_SCHEME_STATIC: return &rod_scheme_static;
    case ROD_SCHEME_COUNT: break;
    }
    return NULL;
}

const rod_scheme_ops *rod_scheme_find(const char *name, rod_scheme_kind *kind)
{
    for (int k = 0; k < ROD_SCHEME_COUNT; k++) {
        const rod_scheme_ops *ops = rod_scheme_get((rod_scheme_kind)k);
        if (strcmp(ops->name, name) == 0) {
            if (kind) *kind = (rod_scheme_kind)k;
            return ops;
        }
    }
    return NULL;
}

int rod_solver_init(rod_solver *solver, const rod_model *m, char *err, size_t errlen)
{
    solver->ops = rod_scheme_get(m->options.scheme);
    solver->work = NULL;
    if (!solver->ops) {
        snprintf(err, errlen, "unknown scheme %d", (int)m->options.scheme);
        return -1;
    }
    if (m->segment_length && m->options.scheme != ROD_SCHEME_IMPLICIT)
        return rod_grid_refuse(m, "the thesis and static schemes", err, errlen);
    solver->work = solver->ops->create(m, err, errlen);
    solver->cuts = 0;
    return solver->work ? 0 : -1;
}

rod_status rod_solver_step(rod_solver *solver, const rod_model *m, rod_state *s, double dt,
                           rod_report *report)
{
    report->message[0] = '\0';
    report->suggested_dt = 0.0;
    report->suggested_scale = 0.0;
    report->newton_iterations = 0;
    /* a cut (sim/cut.h) changes the thread between steps: the work is made
     * again for the thread left, and cuts due after this step are made
     * (with several rods, by the set after every rod's solve: rod_set_step) */
    if (solver->cuts != s->cut_count &&
        rod_cut_solver_sync(solver, m, s, report->message, sizeof report->message))
        return ROD_FAILED;
    const double t0 = s->time;
    rod_status status = solver->ops->step(solver->work, rod_cut_model(m, s), s, dt, report);
    if (m->between_rods) return status;
    if (status == ROD_OK && m->cut_event_count > 0) rod_cut_scene_events(m, s, t0);
    if (status == ROD_OK && s->cut_request.pending && rod_cut_apply(m, s, report))
        status = ROD_FAILED;
    return status;
}

int rod_solver_refresh(rod_solver *solver, const rod_model *m, const rod_state *s, double dt)
{
    if (!solver->ops || !solver->ops->refresh || !solver->work || solver->cuts != s->cut_count)
        return 0;
    return solver->ops->refresh(solver->work, rod_cut_model(m, s), s, dt);
}

void rod_solver_release(rod_solver *solver)
{
    if (solver->ops && solver->work) solver->ops->destroy(solver->work);
    solver->work = NULL;
}

double rod_choose_dt(const rod_model *m, const char **why)
{
    if (m->options.dt > 0.0) {
        if (why) *why = "set in the scene";
        return m->options.dt;
    }
    if (m->options.scheme == ROD_SCHEME_STATIC) {
        /* no dynamics: one equilibrium solve per output frame (the run caps steps at 1/fps) */
        if (why) *why = "static: no time step, one equilibrium solve per output frame";
        return m->options.duration > 0.0 ? m->options.duration : 1.0;
    }
    /* The scheme's stability limit covers only the physics the scene turns on
     * (e.g. the thesis scheme has no twist cap with twist off or a planar load);
     * an unconditionally stable scheme is limited by accuracy alone. */
    const rod_scheme_ops *ops = rod_scheme_get(m->options.scheme);
    const char *const accuracy = "accuracy: 1/20 of the first bending period";
    double accuracy_dt = 1.0 / (20.0 * rod_first_bending_frequency(m));
    const char *limit = accuracy;
    double stable = ops && ops->stable_dt ? ops->stable_dt(m, &limit) : INFINITY;
    const double safety = 0.5; /* forward Euler near its limit amplifies round-off slowly */
    if (isfinite(stable) && safety * stable < accuracy_dt) {
        if (why) *why = limit; /* stable = 0: no stable dt exists; the limit says why */
        return safety * stable;
    }
    if (why) *why = isfinite(stable) ? accuracy
                                     : "accuracy: 1/20 of the first bending period (the scheme "
                                       "is unconditionally stable)";
    return accuracy_dt;
}
