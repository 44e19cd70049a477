/* glyphs.c: the end glyphs, the needle and the arrows (glyphs.h). */
#include "render/glyphs.h"

#include <math.h>
#include <string.h>

#include "base/vec3.h"
#include "render/geometry.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define ARROW_SIDES 16
#define BALL_RADIUS 1.6                    /* over the visual radius */
#define NEEDLE_POINT 0.18                  /* fraction of the arc that tapers to the point */

/* ------------------------------------------------------------------ end glyphs */

/* What is drawn at an end: the needle (tip only) replaces the tip's block or
 * ball, since the holder grips the needle and the thread is swaged into its
 * back; a free tip with a needle still shows it (a dropped needle). An end
 * cut away (rod_recording_kept) went with its piece, and what held it:
 * nothing is drawn on the cut end; the needle, when jaws held it, is drawn
 * in them (needle_pose). */
typedef enum { GLYPH_NONE, GLYPH_BLOCK, GLYPH_BALL, GLYPH_NEEDLE } glyph_kind;

/* The nodes of the rod whose ends the glyphs are (a joined recording's
 * last: its tip is the recording's last node). */
static int glyph_rod_first(const rod_recording *rec)
{
    return rec->rod_count > 1 ? rec->rod_first[rec->rod_count - 1] : 0;
}

/* 1 when end `end` of the thread is cut away in `frame`. */
static int end_cut(const rod_recording *rec, int frame, int end)
{
    int first;
    const int lo = glyph_rod_first(rec);
    const int kept = rod_recording_kept(rec, frame, lo, rec->nodes, &first);
    return end ? first + kept < rec->nodes : first > lo;
}

/* The needle's arc from its back r and frame q (defined below). */
static void arc_points_at(const rod_recording *rec, const render_options *o, const double r[3],
                          const double q[9], double *out);

/* The distance (m) from p to the segment a-b. */
static double segment_distance(const double a[3], const double b[3], const double p[3])
{
    double ab[3], ap[3], at[3];
    v3_sub(ab, b, a);
    v3_sub(ap, p, a);
    const double len2 = v3_dot(ab, ab);
    const double t = len2 > 0 ? fmin(1.0, fmax(0.0, v3_dot(ap, ab) / len2)) : 0.0;
    v3_copy(at, a);
    v3_axpy(at, t, ab);
    v3_sub(ap, p, at);
    return v3_norm(ap);
}

/* The jaws holding the needle after its piece was cut away, as a surgeon
 * sees it: the needle stays where it was in the instrument that held it
 * (the piece left the run with it; the instrument's path carries it). At
 * the last frame before the cut the instrument whose jaws (their segment,
 * jaw_length back from the tip) come nearest the needle's arc, within two
 * jaw radii and the wire, holds it; none: the needle is not drawn (it fell
 * with its piece). The needle's back r (m) and frame q (row-major, columns
 * d1 d2 d3) in `frame` into r, q; 0 when not drawn. */
static int carried_needle(const rod_recording *rec, const render_options *o, int frame,
                          double r[3], double q[9])
{
    int before = frame - 1;
    while (before >= 0 && end_cut(rec, before, 1)) before--;
    if (before < 0 || rec->instrument_count < 1 || !rec->instrument_pose) return 0;
    const double *r0 = node_position(rec, before, rec->nodes - 1);
    const double *q0 = node_frame(rec, before, rec->nodes - 1);
    double arc[3 * (NEEDLE_SEGMENTS + 1)];
    arc_points_at(rec, o, r0, q0, arc);
    int holder = -1;
    double nearest = INFINITY;
    for (int k = 0; k < rec->instrument_count; k++) {
        const recording_instrument *in = &rec->instruments[k];
        const double *pose = rod_recording_instrument(rec, before, k);
        if (in->kind == RECORDING_SCISSORS || !pose) continue;
        double axis[3], heel[3];
        m3_column(axis, pose + 3, 0);
        v3_copy(heel, pose);
        v3_axpy(heel, -in->jaw_length, axis);
        double reach = 2 * in->jaw_radius + 0.12 * rec->needle_radius;
        for (int j = 0; j <= NEEDLE_SEGMENTS; j++) {
            double d = segment_distance(heel, pose, &arc[3 * j]);
            if (d <= reach && d < nearest) nearest = d, holder = k;
        }
    }
    if (holder < 0) return 0;
    /* q = R(t) R(t0)^T q0, r = p(t) + R(t) R(t0)^T (r0 - p(t0)) */
    const double *then = rod_recording_instrument(rec, before, holder);
    const double *now = rod_recording_instrument(rec, frame, holder);
    double rel[9], offset[3], local[3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            rel[3 * i + j] = now[3 + 3 * i] * then[3 + 3 * j] + now[4 + 3 * i] * then[4 + 3 * j] +
                             now[5 + 3 * i] * then[5 + 3 * j];
    m3_mul(q, rel, q0);
    v3_sub(offset, r0, then);
    m3_mul_v(local, rel, offset);
    v3_add(r, now, local);
    return 1;
}

/* The needle's back and frame in `frame`: the tip's, or after the tip was
 * cut away the jaws' that held it (carried_needle). 0: not drawn. */
static int needle_pose(const rod_recording *rec, const render_options *o, int frame, double r[3],
                       double q[9])
{
    if (end_cut(rec, frame, 1)) return carried_needle(rec, o, frame, r, q);
    v3_copy(r, node_position(rec, frame, rec->nodes - 1));
    memcpy(q, node_frame(rec, frame, rec->nodes - 1), 9 * sizeof(double));
    return 1;
}

static glyph_kind end_glyph(const rod_recording *rec, const render_options *o, int frame, int end)
{
    if (end_cut(rec, frame, end)) {
        double r[3], q[9];
        return end == 1 && rec->needle_radius > 0 && needle_pose(rec, o, frame, r, q) ? GLYPH_NEEDLE
                                                                                     : GLYPH_NONE;
    }
    if (end == 1 && rec->needle_radius > 0) return GLYPH_NEEDLE;
    switch (rec->ends[end].kind) {
    case RECORDING_END_CLAMPED: return GLYPH_BLOCK;
    case RECORDING_END_PINNED: return GLYPH_BALL;
    default: return GLYPH_NONE;
    }
}

static int end_node(const rod_recording *rec, int end) { return end ? rec->nodes - 1 : 0; }

/* The block of a clamped end in frame `frame`: beyond the end (behind s = 0,
 * past s = L), aligned with the end's frame there, so a driven end carries it. */
static void clamp_box(const rod_recording *rec, double radius, int frame, int end,
                      double centre[3], double axes[3][3], double half[3])
{
    int node = end_node(rec, end);
    const double *q = node_frame(rec, frame, node);
    for (int a = 0; a < 3; a++) m3_column(axes[a], q, a);
    double side = fmax(4.0 * radius, 0.05 * rec->length);
    half[0] = half[1] = 0.5 * side;
    half[2] = 0.5 * fmax(2.5 * radius, 0.03 * rec->length);
    v3_copy(centre, node_position(rec, frame, node));
    v3_axpy(centre, end ? half[2] : -half[2], axes[2]);
}

double glyph_needle_wire(const rod_recording *rec, double radius)
{
    return fmin(0.8 * radius, 0.12 * rec->needle_radius);
}

/* The needle's arc: the circle of radius R through the tip r, tangent to its
 * d3 there (the back continues the thread), in the plane of d3 and d1,
 * bending toward d1: p(theta) = r + R sin(theta) d3 + R (1 - cos(theta)) d1,
 * theta = 0 (back) .. 2 pi arc (point). NEEDLE_SEGMENTS + 1 points into out. */
static void arc_points_at(const rod_recording *rec, const render_options *o, const double r[3],
                          const double q[9], double *out)
{
    double d1[3], d3[3], big = rec->needle_radius;
    m3_column(d1, q, 0);
    m3_column(d3, q, 2);
    for (int k = 0; k <= NEEDLE_SEGMENTS; k++) {
        double theta = 2 * M_PI * o->needle_arc * k / NEEDLE_SEGMENTS, *p = &out[3 * k];
        v3_copy(p, r);
        v3_axpy(p, big * sin(theta), d3);
        v3_axpy(p, big * (1 - cos(theta)), d1);
    }
}

int glyph_points(const rod_recording *rec, const render_options *o, double radius, int frame,
                 int end, double *out, double *pad, int *chain)
{
    *pad = 0;
    *chain = 0;
    double needle_back[3], needle_frame[9];
    switch (end_glyph(rec, o, frame, end)) {
    case GLYPH_BLOCK: {
        double centre[3], axes[3][3], half[3];
        clamp_box(rec, radius, frame, end, centre, axes, half);
        for (int corner = 0; corner < 8; corner++) {
            double *p = &out[3 * corner];
            v3_copy(p, centre);
            for (int a = 0; a < 3; a++) v3_axpy(p, (corner >> a & 1 ? 1 : -1) * half[a], axes[a]);
        }
        return 8;
    }
    case GLYPH_BALL:
        v3_copy(out, node_position(rec, frame, end_node(rec, end)));
        *pad = BALL_RADIUS * radius;
        return 1;
    case GLYPH_NEEDLE:
        needle_pose(rec, o, frame, needle_back, needle_frame);
        arc_points_at(rec, o, needle_back, needle_frame, out);
        *pad = glyph_needle_wire(rec, radius);
        *chain = 1;
        return NEEDLE_SEGMENTS + 1;
    default:
        return 0;
    }
}

static void add_ball(render_mesh *m, const double centre[3], double ball_radius)
{
    mesh_globe(m, centre, ball_radius, BALL_STACKS, BALL_SLICES, render_ball_color);
}

/* The needle: a thin tube along its arc, closed at the back by a disc, its
 * last NEEDLE_POINT of the arc tapering to a sharp point (radius 0). */
static void add_needle(render_mesh *m, const rod_recording *rec, const render_options *o, int frame,
                       double radius)
{
    double arc[3 * (NEEDLE_SEGMENTS + 1)], wire = glyph_needle_wire(rec, radius), r[3], q[9];
    if (!needle_pose(rec, o, frame, r, q)) return;
    arc_points_at(rec, o, r, q, arc);
    double d1[3], d2[3], d3[3];
    m3_column(d1, q, 0);
    m3_column(d2, q, 1);
    m3_column(d3, q, 2);
    unsigned first = (unsigned)m->vertex_count;
    for (int k = 0; k <= NEEDLE_SEGMENTS; k++) {
        double theta = 2 * M_PI * o->needle_arc * k / NEEDLE_SEGMENTS;
        double f = (double)k / NEEDLE_SEGMENTS, taper = fmin(1.0, (1.0 - f) / NEEDLE_POINT);
        /* the arc's inward normal (toward its centre) and the plane's normal d2 span the ring */
        double inward[3] = {0, 0, 0};
        v3_axpy(inward, cos(theta), d1);
        v3_axpy(inward, -sin(theta), d3);
        for (int j = 0; j < NEEDLE_SIDES; j++) {
            double phi = 2 * M_PI * j / NEEDLE_SIDES, n[3] = {0, 0, 0}, p[3];
            v3_axpy(n, cos(phi), inward);
            v3_axpy(n, sin(phi), d2);
            v3_copy(p, &arc[3 * k]);
            v3_axpy(p, wire * taper, n);
            mesh_vertex(m, p, n, render_needle_color);
        }
    }
    for (int k = 0; k < NEEDLE_SEGMENTS; k++)
        for (int j = 0; j < NEEDLE_SIDES; j++) {
            unsigned a = first + (unsigned)(k * NEEDLE_SIDES + j);
            unsigned b = first + (unsigned)(k * NEEDLE_SIDES + (j + 1) % NEEDLE_SIDES);
            mesh_triangle(m, a, a + NEEDLE_SIDES, b + NEEDLE_SIDES);
            mesh_triangle(m, a, b + NEEDLE_SIDES, b);
        }
    double back[3];
    v3_scale(back, d3, -1);
    mesh_disc(m, arc, d1, d2, wire, back, NEEDLE_SIDES, render_needle_color);
}

void glyph_add_ends(render_mesh *m, const rod_recording *rec, const render_options *o, int frame,
                    double radius)
{
    for (int end = 0; end < 2; end++) {
        switch (end_glyph(rec, o, frame, end)) {
        case GLYPH_BLOCK: {
            double centre[3], axes[3][3], half[3];
            clamp_box(rec, radius, frame, end, centre, axes, half);
            mesh_block(m, centre, axes, half, render_clamp_color);
            break;
        }
        case GLYPH_BALL:
            add_ball(m, node_position(rec, frame, end_node(rec, end)), BALL_RADIUS * radius);
            break;
        case GLYPH_NEEDLE:
            add_needle(m, rec, o, frame, radius);
            break;
        default:
            break;
        }
    }
}

/* A cone from base (radius) to apex along d, with slanted smooth normals. */
static void add_cone(render_mesh *m, const double base[3], const double d[3], const double e1[3],
                     const double e2[3], double radius, double length, const float color[3])
{
    unsigned first = (unsigned)m->vertex_count;
    double apex[3];
    v3_copy(apex, base);
    v3_axpy(apex, length, d);
    for (int j = 0; j < ARROW_SIDES; j++) {
        double phi = 2 * M_PI * j / ARROW_SIDES, mid = phi + M_PI / ARROW_SIDES;
        double radial[3] = {0, 0, 0}, n[3], p[3];
        v3_axpy(radial, cos(phi), e1);
        v3_axpy(radial, sin(phi), e2);
        v3_scale(n, radial, length);
        v3_axpy(n, radius, d);
        v3_scale(n, n, 1.0 / v3_norm(n));
        v3_copy(p, base);
        v3_axpy(p, radius, radial);
        mesh_vertex(m, p, n, color);
        double mid_radial[3] = {0, 0, 0};
        v3_axpy(mid_radial, cos(mid), e1);
        v3_axpy(mid_radial, sin(mid), e2);
        v3_scale(n, mid_radial, length);
        v3_axpy(n, radius, d);
        v3_scale(n, n, 1.0 / v3_norm(n));
        mesh_vertex(m, apex, n, color);
    }
    for (int j = 0; j < ARROW_SIDES; j++) {
        unsigned a = first + (unsigned)(2 * j), b = first + (unsigned)(2 * ((j + 1) % ARROW_SIDES));
        mesh_triangle(m, a, b, a + 1);
    }
    double back[3];
    v3_scale(back, d, -1);
    mesh_disc(m, base, e1, e2, radius, back, ARROW_SIDES, color);
}

/* An arrow from tail along unit d, `length` long; heads = 2 draws the
 * double head of a moment vector. */
static void add_arrow(render_mesh *m, const double tail[3], const double d[3], double length,
                      const arrow_style *style, int heads, const float color[3])
{
    double head_length = fmin(style->head_length, 0.45 * length / heads);
    double head_radius = style->head_radius * head_length / style->head_length;
    double shaft_radius = fmin(style->shaft_radius, 0.6 * head_radius);
    double shaft_length = length - heads * head_length;
    double e1[3], e2[3];
    perpendicular_basis(d, e1, e2);
    unsigned first = (unsigned)m->vertex_count;
    for (int end = 0; end < 2; end++)
        for (int j = 0; j < ARROW_SIDES; j++) {
            double phi = 2 * M_PI * j / ARROW_SIDES, n[3] = {0, 0, 0}, p[3];
            v3_axpy(n, cos(phi), e1);
            v3_axpy(n, sin(phi), e2);
            v3_copy(p, tail);
            v3_axpy(p, end * shaft_length, d);
            v3_axpy(p, shaft_radius, n);
            mesh_vertex(m, p, n, color);
        }
    for (int j = 0; j < ARROW_SIDES; j++) {
        unsigned a = first + (unsigned)j, b = first + (unsigned)((j + 1) % ARROW_SIDES);
        mesh_triangle(m, a, b, b + ARROW_SIDES);
        mesh_triangle(m, a, b + ARROW_SIDES, a + ARROW_SIDES);
    }
    double back[3];
    v3_scale(back, d, -1);
    mesh_disc(m, tail, e1, e2, shaft_radius, back, ARROW_SIDES, color);
    for (int h = 0; h < heads; h++) {
        double base[3];
        v3_copy(base, tail);
        v3_axpy(base, shaft_length + h * head_length, d);
        add_cone(m, base, d, e1, e2, head_radius, head_length, color);
    }
}

void arrow_scales_compute(arrow_scales *a, const rod_recording *rec, double radius,
                          int enabled)
{
    double max_force = 0, max_moment = 0;
    for (int f = 0; f < rec->frame_count; f++) {
        max_force = fmax(max_force, v3_norm(&rec->tip_force[3 * f]));
        max_moment = fmax(max_moment, v3_norm(&rec->tip_moment[3 * f]));
    }
    /* a sampled recording (a streamed video) also knows the frames it dropped */
    max_force = fmax(max_force, rec->peak_force);
    max_moment = fmax(max_moment, rec->peak_moment);
    a->max_force = max_force;
    a->max_moment = max_moment;
    a->tube_radius = radius;
    /* the largest load over the run is a fixed fraction of the length: sizes compare across frames */
    a->force_scale = enabled && max_force > 0 ? 0.25 * rec->length / max_force : 0;
    a->moment_scale = enabled && max_moment > 0 ? 0.2 * rec->length / max_moment : 0;
    a->style.shaft_radius = fmax(0.55 * radius, 0.004 * rec->length);
    a->style.head_radius = 2.4 * a->style.shaft_radius;
    a->style.head_length = 6.0 * a->style.shaft_radius;
}

int arrow_geometry(const arrow_scales *a, const rod_recording *rec, int frame, int which,
                   double tail[3], double d[3], double *length)
{
    const double *load = which ? &rec->tip_moment[3 * frame] : &rec->tip_force[3 * frame];
    double scale = which ? a->moment_scale : a->force_scale;
    double magnitude = v3_norm(load);
    *length = scale * magnitude;
    if (!(*length > 1e-4 * rec->length)) return 0;
    v3_scale(d, load, 1.0 / magnitude);
    int node = rec->nodes - 1;
    double d3[3];
    m3_column(d3, node_frame(rec, frame, node), 2);
    double along = v3_dot(d, d3), gap = 0.15 * a->tube_radius;
    v3_copy(tail, node_position(rec, frame, node));
    if (along >= -0.5) {
        /* leaves the cylinder at radius / sin(angle to d3), or through the end face */
        double sine = sqrt(fmax(0, 1 - along * along));
        double out = along > 0 ? fmin(a->tube_radius / fmax(sine, 1e-9), a->tube_radius)
                               : a->tube_radius / fmax(sine, 1e-9);
        v3_axpy(tail, out + gap, d);
    } else {
        v3_axpy(tail, -(*length + gap), d);
    }
    return 1;
}

void glyph_add_arrows(render_mesh *m, const arrow_scales *a, const rod_recording *rec, int frame)
{
    for (int which = 0; which < 2; which++) {
        double tail[3], d[3], length;
        if (arrow_geometry(a, rec, frame, which, tail, d, &length))
            add_arrow(m, tail, d, length, &a->style, which ? 2 : 1,
                      which ? render_moment_color : render_force_color);
    }
}
