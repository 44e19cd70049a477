/* instrument_mesh.c: the surgical instruments, drawn (instrument_mesh.h). */
#include "render/instrument_mesh.h"

#include <math.h>

#include "base/vec3.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define SIDES 14          /* around a tube */
#define RING_POINTS 20    /* around a ring handle */
#define CAP_STACKS 6
#define CAP_SLICES 12

/* surgical stainless steel, brighter than the clamp's block; the jaws'
 * serrated faces a shade darker */
static const float steel[3] = {0.80f, 0.82f, 0.86f};
static const float jaw_steel[3] = {0.62f, 0.64f, 0.68f};

/* An instrument's frame in one frame of the recording. */
typedef struct tool_pose {
    double origin[3], rot[9];
} tool_pose;

static void to_global(const tool_pose *t, const double local[3], double out[3])
{
    m3_mul_v(out, t->rot, local);
    v3_add(out, out, t->origin);
}

/* Two unit vectors across the unit axis d. */
static void across(const double d[3], double e1[3], double e2[3])
{
    double a[3] = {1.0, 0.0, 0.0};
    if (fabs(d[0]) > 0.8) v3_set(a, 0.0, 1.0, 0.0);
    v3_cross(e1, d, a);
    v3_scale(e1, e1, 1.0 / v3_norm(e1));
    v3_cross(e2, d, e1);
}

/* A tube through the global points p[0..n-1] with radii r[]; closed: the
 * last point joins the first (a ring); else rounded ends. */
static void tube(render_mesh *m, const double *p, const double *r, int n, int closed,
                 const float color[3])
{
    unsigned first = (unsigned)m->vertex_count;
    double e1[3], e2[3], prev_e1[3];
    for (int i = 0; i < n; i++) {
        const double *a = &p[3 * (i > 0 ? i - 1 : (closed ? n - 1 : 0))];
        const double *b = &p[3 * (i + 1 < n ? i + 1 : (closed ? 0 : n - 1))];
        double d[3];
        v3_sub(d, b, a);
        v3_scale(d, d, 1.0 / v3_norm(d));
        if (i == 0) {
            across(d, e1, e2);
        } else { /* carried along (no twist of the rings) */
            v3_axpy(prev_e1, -v3_dot(prev_e1, d), d);
            v3_scale(e1, prev_e1, 1.0 / v3_norm(prev_e1));
            v3_cross(e2, d, e1);
        }
        v3_copy(prev_e1, e1);
        for (int j = 0; j < SIDES; j++) {
            double phi = 2.0 * M_PI * j / SIDES, nrm[3] = {0.0, 0.0, 0.0}, q[3];
            v3_axpy(nrm, cos(phi), e1);
            v3_axpy(nrm, sin(phi), e2);
            v3_copy(q, &p[3 * i]);
            v3_axpy(q, r[i], nrm);
            mesh_vertex(m, q, nrm, color);
        }
    }
    const int segments = closed ? n : n - 1;
    for (int i = 0; i < segments; i++)
        for (int j = 0; j < SIDES; j++) {
            const unsigned i2 = (unsigned)((i + 1) % n);
            unsigned a = first + (unsigned)(i * SIDES + j), b = first + (unsigned)(i * SIDES + (j + 1) % SIDES);
            unsigned c = first + i2 * SIDES + (unsigned)j, d = first + i2 * SIDES + (unsigned)((j + 1) % SIDES);
            mesh_triangle(m, a, c, d);
            mesh_triangle(m, a, d, b);
        }
    if (!closed) {
        mesh_globe(m, &p[0], r[0], CAP_STACKS, CAP_SLICES, color);
        mesh_globe(m, &p[3 * (n - 1)], r[n - 1], CAP_STACKS, CAP_SLICES, color);
    }
}

/* A straight tube from local a to local b (radius ra to rb). */
static void bar(render_mesh *m, const tool_pose *t, const double a[3], const double b[3], double ra,
                double rb, const float color[3])
{
    double p[3 * 4], r[4];
    for (int i = 0; i < 4; i++) {
        double f = i / 3.0, local[3];
        for (int c = 0; c < 3; c++) local[c] = a[c] + f * (b[c] - a[c]);
        to_global(t, local, &p[3 * i]);
        r[i] = ra + f * (rb - ra);
    }
    tube(m, p, r, 4, 0, color);
}

/* A ring handle of radius big in the local x-z plane about local centre. */
static void ring(render_mesh *m, const tool_pose *t, const double centre[3], double big,
                 double wire)
{
    double p[3 * RING_POINTS], r[RING_POINTS];
    for (int i = 0; i < RING_POINTS; i++) {
        double phi = 2.0 * M_PI * i / RING_POINTS, local[3];
        v3_set(local, centre[0] + big * cos(phi), centre[1], centre[2] + 0.8 * big * sin(phi));
        to_global(t, local, &p[3 * i]);
        r[i] = wire;
    }
    tube(m, p, r, RING_POINTS, 1, steel);
}

/* The parts of one instrument in local coordinates: for each side
 * (+1 upper, -1 lower), its jaw from the hinge, its shank crossing to the
 * other side (or the tine's back part) and the ring's centre. */
typedef struct tool_parts {
    double jaw_a[2][3], jaw_b[2][3];     /* the gripping parts */
    double shank_a[2][3], shank_b[2][3]; /* shanks or tines' backs */
    double ring_centre[2][3];            /* ring handles (not for forceps) */
    double ring_radius;
    int rings;
} tool_parts;

static void tool_layout(const recording_instrument *in, double angle, double gap, tool_parts *tp)
{
    const double h = in->hinge, lj = in->jaw_length, rj = in->jaw_radius + 0.5 * gap, L = in->size;
    const int forceps = in->kind == RECORDING_FORCEPS;
    const double shank = forceps ? h - lj : (in->kind == RECORDING_SCISSORS ? 0.45 : 0.60) * L;
    tp->rings = !forceps;
    tp->ring_radius = 0.055 * L;
    for (int side = 0; side < 2; side++) {
        const double sg = side ? -1.0 : 1.0, dir[3] = {cos(angle), 0.0, sg * sin(angle)};
        const double hinge[3] = {-h, 0.0, sg * rj};
        for (int c = 0; c < 3; c++) {
            tp->jaw_a[side][c] = hinge[c] + (h - lj) * dir[c];
            tp->jaw_b[side][c] = hinge[c] + h * dir[c];
        }
        if (forceps) {
            v3_copy(tp->shank_a[side], hinge);
            v3_copy(tp->shank_b[side], tp->jaw_a[side]);
        } else {
            v3_set(tp->shank_a[side], -h, 0.0, -sg * rj);
            v3_set(tp->shank_b[side], -h - shank * cos(angle), 0.0, -sg * (rj + shank * sin(angle)));
            /* the ring beyond the shank's end, outward */
            const double back[3] = {-cos(angle), 0.0, -sg * sin(angle)};
            for (int c = 0; c < 3; c++)
                tp->ring_centre[side][c] = tp->shank_b[side][c] + 0.95 * tp->ring_radius * back[c];
        }
    }
}

static int read_pose(const rod_recording *rec, int frame, int k, tool_pose *t, double *angle)
{
    const double *v = rod_recording_instrument(rec, frame, k);
    if (!v) return 0;
    v3_copy(t->origin, v);
    for (int i = 0; i < 9; i++) t->rot[i] = v[3 + i];
    *angle = v[12];
    return 1;
}

void instrument_mesh_add(render_mesh *m, const rod_recording *rec, int frame, double gap)
{
    for (int k = 0; k < rec->instrument_count; k++) {
        tool_pose t;
        double angle;
        if (!read_pose(rec, frame, k, &t, &angle)) continue;
        const recording_instrument *in = &rec->instruments[k];
        tool_parts tp;
        tool_layout(in, angle, gap, &tp);
        const double rj = in->jaw_radius, rs = in->shank_radius;
        for (int side = 0; side < 2; side++) {
            bar(m, &t, tp.jaw_a[side], tp.jaw_b[side], rj, rj, jaw_steel);
            bar(m, &t, tp.shank_a[side], tp.shank_b[side], in->kind == RECORDING_FORCEPS ? rs : rs, rj,
                steel);
            if (tp.rings) {
                ring(m, &t, tp.ring_centre[side], tp.ring_radius, 0.5 * rs);
            }
        }
        if (in->kind == RECORDING_FORCEPS) {
            /* the tines' sprung back end: a block joining them */
            double centre[3], axes[3][3], half[3] = {2.0 * rs, 1.2 * rs, 2.0 * rj + rs};
            const double local[3] = {-in->hinge - rs, 0.0, 0.0};
            to_global(&t, local, centre);
            for (int a = 0; a < 3; a++) m3_column(axes[a], t.rot, a);
            mesh_block(m, centre, axes, half, steel);
        } else {
            /* the box lock (a needle holder): the capsule the thread touches;
             * the screw (scissors) at the hinge */
            if (in->lock_radius > 0.0) {
                const double a[3] = {-in->hinge, 0.0, -in->lock_half_span};
                const double b[3] = {-in->hinge, 0.0, in->lock_half_span};
                bar(m, &t, a, b, in->lock_radius, in->lock_radius, steel);
            } else {
                const double a[3] = {-in->hinge, -1.4 * rs, 0.0}, b[3] = {-in->hinge, 1.4 * rs, 0.0};
                bar(m, &t, a, b, 1.2 * rs, 1.2 * rs, jaw_steel);
            }
        }
    }
}

int instrument_mesh_points(const rod_recording *rec, int frame, int k, double gap, double *out,
                           double *pad)
{
    tool_pose t;
    double angle;
    *pad = 0.0;
    if (!read_pose(rec, frame, k, &t, &angle)) return 0;
    const recording_instrument *in = &rec->instruments[k];
    tool_parts tp;
    tool_layout(in, angle, gap, &tp);
    int count = 0;
    for (int side = 0; side < 2; side++) {
        to_global(&t, tp.jaw_a[side], &out[3 * count++]);
        to_global(&t, tp.jaw_b[side], &out[3 * count++]);
        to_global(&t, tp.shank_a[side], &out[3 * count++]);
        to_global(&t, tp.shank_b[side], &out[3 * count++]);
        for (int q = 0; q < 4; q++) { /* the ring's box corners (the shank's end without) */
            double local[3];
            v3_copy(local, tp.rings ? tp.ring_centre[side] : tp.shank_b[side]);
            if (tp.rings) {
                local[0] += (q & 1 ? 1.0 : -1.0) * tp.ring_radius;
                local[2] += (q & 2 ? 1.0 : -1.0) * tp.ring_radius;
            }
            to_global(&t, local, &out[3 * count++]);
        }
    }
    *pad = 2.0 * in->shank_radius + 2.0 * in->jaw_radius;
    return count;
}
