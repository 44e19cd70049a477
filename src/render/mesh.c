/* mesh.c: the mesh's primitives, the tube, its stripe and its shading by
 * the other strands (mesh.h). */
#include "render/mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "render/geometry.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define STRIPE_HALF_WIDTH 0.32             /* rad, half the band's angular width */
/* rad: the most a drawn segment of the tube turns (bend and twist
 * together); a segment turning more is cut into as many as this needs */
#define SMOOTH_TURN (M_PI / 32)

unsigned mesh_vertex(render_mesh *m, const double p[3], const double n[3], const float color[3])
{
    if (m->vertex_count >= m->max_vertices) return 0; /* sized by create; never expected */
    render_vertex *v = &m->vertices[m->vertex_count];
    for (int c = 0; c < 3; c++) {
        v->position[c] = (float)p[c];
        v->normal[c] = (float)n[c];
        v->color[c] = color[c];
    }
    return (unsigned)m->vertex_count++;
}

/* Adds a triangle wound counter-clockwise seen from the side its vertex
 * normals point to. Every drawn surface is closed (tube with caps, box,
 * arrows) and its normals point out, so GL can cull the back faces: half
 * the triangles, and with 4x multisampling on llvmpipe the triangles are
 * most of the drawing time. */
void mesh_triangle(render_mesh *m, unsigned a, unsigned b, unsigned c)
{
    if (m->index_count + 3 > m->max_indices) return;
    const render_vertex *va = &m->vertices[a], *vb = &m->vertices[b], *vc = &m->vertices[c];
    float ab[3], ac[3], normal_sum[3];
    for (int i = 0; i < 3; i++) {
        ab[i] = vb->position[i] - va->position[i];
        ac[i] = vc->position[i] - va->position[i];
        normal_sum[i] = va->normal[i] + vb->normal[i] + vc->normal[i];
    }
    float facing = (ab[1] * ac[2] - ab[2] * ac[1]) * normal_sum[0] +
                   (ab[2] * ac[0] - ab[0] * ac[2]) * normal_sum[1] +
                   (ab[0] * ac[1] - ab[1] * ac[0]) * normal_sum[2];
    if (facing < 0) {
        unsigned swap = b;
        b = c;
        c = swap;
    }
    m->indices[m->index_count++] = a;
    m->indices[m->index_count++] = b;
    m->indices[m->index_count++] = c;
}

void mesh_disc(render_mesh *m, const double centre[3], const double e1[3], const double e2[3],
               double radius, const double normal[3], int sides, const float color[3])
{
    unsigned middle = mesh_vertex(m, centre, normal, color);
    for (int j = 0; j < sides; j++) {
        double phi = 2 * M_PI * j / sides, p[3];
        v3_copy(p, centre);
        v3_axpy(p, radius * cos(phi), e1);
        v3_axpy(p, radius * sin(phi), e2);
        mesh_vertex(m, p, normal, color);
    }
    for (int j = 0; j < sides; j++)
        mesh_triangle(m, middle, middle + 1 + (unsigned)j,
                      middle + 1 + (unsigned)((j + 1) % sides));
}

void mesh_block(render_mesh *m, const double centre[3], double axes[3][3],
                const double half[3], const float color[3])
{
    for (int a = 0; a < 3; a++)
        for (int sign = -1; sign <= 1; sign += 2) {
            int b = (a + 1) % 3, c = (a + 2) % 3;
            double n[3], face[3];
            v3_scale(n, axes[a], sign);
            v3_copy(face, centre);
            v3_axpy(face, sign * half[a], axes[a]);
            unsigned first = (unsigned)m->vertex_count;
            for (int corner = 0; corner < 4; corner++) {
                double p[3];
                v3_copy(p, face);
                v3_axpy(p, (corner & 1 ? 1 : -1) * half[b], axes[b]);
                v3_axpy(p, (corner & 2 ? 1 : -1) * half[c], axes[c]);
                mesh_vertex(m, p, n, color);
            }
            mesh_triangle(m, first, first + 1, first + 3);
            mesh_triangle(m, first, first + 3, first + 2);
        }
}

#define ROUNDED_STEPS 4
void mesh_rounded_block(render_mesh *m, const double centre[3], const double half[3],
                        double radius, const float color[3])
{
    const int g = 2 * (ROUNDED_STEPS + 1); /* grid points along a face's side */
    for (int a = 0; a < 3; a++)
        for (int sign = -1; sign <= 1; sign += 2) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            double ub[2 * (ROUNDED_STEPS + 1)], uc[2 * (ROUNDED_STEPS + 1)];
            for (int i = 0; i <= ROUNDED_STEPS; i++) {
                /* from the rim (45 degrees of the edge's arc) to the flat part */
                const double t = radius * tan(0.25 * M_PI * (ROUNDED_STEPS - i) / ROUNDED_STEPS);
                ub[i] = -(half[b] - radius + t), ub[g - 1 - i] = half[b] - radius + t;
                uc[i] = -(half[c] - radius + t), uc[g - 1 - i] = half[c] - radius + t;
            }
            const unsigned first = (unsigned)m->vertex_count;
            for (int j = 0; j < g; j++)
                for (int i = 0; i < g; i++) {
                    double q[3], core[3], d[3], p[3];
                    q[a] = sign * half[a], q[b] = ub[i], q[c] = uc[j];
                    for (int k = 0; k < 3; k++) {
                        const double h = half[k] - radius;
                        core[k] = q[k] < -h ? -h : q[k] > h ? h : q[k];
                    }
                    v3_sub(d, q, core);
                    v3_scale(d, d, 1.0 / v3_norm(d));
                    for (int k = 0; k < 3; k++) p[k] = centre[k] + core[k] + radius * d[k];
                    mesh_vertex(m, p, d, color);
                }
            for (int j = 0; j + 1 < g; j++)
                for (int i = 0; i + 1 < g; i++) {
                    const unsigned v = first + (unsigned)(j * g + i);
                    mesh_triangle(m, v, v + 1, v + (unsigned)g + 1);
                    mesh_triangle(m, v, v + (unsigned)g + 1, v + (unsigned)g);
                }
        }
}

void mesh_globe(render_mesh *m, const double centre[3], double radius, int stacks, int slices,
                const float color[3])
{
    unsigned first = (unsigned)m->vertex_count;
    for (int i = 0; i <= stacks; i++) {
        double polar = M_PI * i / stacks;
        for (int j = 0; j <= slices; j++) {
            double azimuth = 2 * M_PI * j / slices, p[3];
            double n[3] = {sin(polar) * cos(azimuth), sin(polar) * sin(azimuth), cos(polar)};
            v3_copy(p, centre);
            v3_axpy(p, radius, n);
            mesh_vertex(m, p, n, color);
        }
    }
    for (int i = 0; i < stacks; i++)
        for (int j = 0; j < slices; j++) {
            unsigned a = first + (unsigned)(i * (slices + 1) + j), b = a + (unsigned)slices + 1;
            if (i + 1 < stacks) mesh_triangle(m, a, b, b + 1);
            if (i > 0) mesh_triangle(m, a, b + 1, a + 1);
        }
}

/* Decision: with render.smooth (the default) the tube follows a smooth
 * curve, since a tight knot's loop drawn straight from node to node reads
 * as a polygon (docs/decisions/0037-smooth-tube.md). Between nodes k and
 * k+1 the point follows the cubic Hermite curve whose end tangents are the
 * nodes' d3 times the segment's length (C1, along each node's director),
 * the frame Q_k exp(t log(Q_k^T Q_k+1)); a segment is cut into
 * ceil(turn / SMOOTH_TURN) pieces, up to SMOOTH_MOST_RINGS (turn: the angle
 * of Q_k^T Q_k+1), so a straight stretch costs nothing. */
void centreline_rings(render_centreline *c, const rod_recording *rec, int frame, int smooth)
{
    const int n = rec->nodes;
    c->count = 0;
    for (int k = 0; k < n; k++) {
        const double *r0 = node_position(rec, frame, k), *q0 = node_frame(rec, frame, k);
        c->first[k] = c->count;
        int pieces = 1;
        double phi[3] = {0, 0, 0}, t0[3] = {0, 0, 0}, t1[3] = {0, 0, 0}, chord[3] = {0, 0, 0};
        const double *r1 = r0;
        if (smooth && k + 1 < n) {
            const double *q1 = node_frame(rec, frame, k + 1);
            double rel[9];
            r1 = node_position(rec, frame, k + 1);
            m3_mul_tn(rel, q0, q1);
            m3_log(phi, rel);
            const double turn = v3_norm(phi);
            if (isfinite(turn)) pieces = (int)ceil(turn / SMOOTH_TURN - 1e-9);
            pieces = pieces < 1 ? 1 : pieces > SMOOTH_MOST_RINGS ? SMOOTH_MOST_RINGS : pieces;
            v3_sub(chord, r1, r0);
            const double length = v3_norm(chord);
            m3_column(t0, q0, 2);
            m3_column(t1, q1, 2);
            v3_scale(t0, t0, length);
            v3_scale(t1, t1, length);
        }
        for (int piece = 0; piece < pieces; piece++) {
            const int ring = c->count++;
            const double t = (double)piece / pieces;
            double *p = &c->point[3 * ring], *q = &c->frame[9 * ring];
            c->node[ring] = k;
            c->t[ring] = t;
            if (piece == 0) {
                v3_copy(p, r0);
                memcpy(q, q0, 9 * sizeof(double));
                continue;
            }
            const double t2 = t * t, t3 = t2 * t;
            const double h00 = 2 * t3 - 3 * t2 + 1, h10 = t3 - 2 * t2 + t, h01 = -2 * t3 + 3 * t2,
                         h11 = t3 - t2;
            for (int a = 0; a < 3; a++)
                p[a] = h00 * r0[a] + h10 * t0[a] + h01 * r1[a] + h11 * t1[a];
            double step[3], turn[9];
            v3_scale(step, phi, t);
            m3_exp(turn, step);
            m3_mul(q, q0, turn);
        }
    }
}

/* A ring's colour between its segment's two nodes' */
static void ring_color(const render_centreline *c, int ring, const float *colors,
                       const float solid[3], float out[3])
{
    if (!colors) {
        memcpy(out, solid, 3 * sizeof(float));
        return;
    }
    const int k = c->node[ring];
    const double t = c->t[ring];
    for (int a = 0; a < 3; a++)
        out[a] = t > 0 ? (float)((1 - t) * colors[3 * k + a] + t * colors[3 * (k + 1) + a])
                       : colors[3 * k + a];
}

void mesh_tube(render_mesh *m, const rod_recording *rec, const render_centreline *c, int frame,
               double radius, int sides, const float *colors, const float solid[3])
{
    unsigned first = (unsigned)m->vertex_count;
    for (int ring = 0; ring < c->count; ring++) {
        const double *r = &c->point[3 * ring], *q = &c->frame[9 * ring];
        double d1[3], d2[3];
        float color[3];
        m3_column(d1, q, 0);
        m3_column(d2, q, 1);
        ring_color(c, ring, colors, solid, color);
        for (int j = 0; j < sides; j++) {
            double phi = 2 * M_PI * j / sides, n[3] = {0, 0, 0}, p[3];
            v3_axpy(n, cos(phi), d1);
            v3_axpy(n, sin(phi), d2);
            v3_copy(p, r);
            v3_axpy(p, radius, n);
            mesh_vertex(m, p, n, color);
        }
    }
    for (int k = 0; k + 1 < c->count; k++)
        for (int j = 0; j < sides; j++) {
            unsigned a = first + (unsigned)(k * sides + j);
            unsigned b = first + (unsigned)(k * sides + (j + 1) % sides);
            mesh_triangle(m, a, a + (unsigned)sides, b + (unsigned)sides);
            mesh_triangle(m, a, b + (unsigned)sides, b);
        }
    for (int end = 0; end < 2; end++) {
        int k = end ? rec->nodes - 1 : 0;
        const double *q = node_frame(rec, frame, k);
        double d1[3], d2[3], d3[3];
        m3_column(d1, q, 0);
        m3_column(d2, q, 1);
        m3_column(d3, q, 2);
        if (!end) v3_scale(d3, d3, -1);
        mesh_disc(m, node_position(rec, frame, k), d1, d2, radius, d3, sides,
                 colors ? &colors[3 * k] : solid);
    }
}

void mesh_stripe(render_mesh *m, const rod_recording *rec, render_centreline *c, int frame,
                 double radius, render_stripe_mode mode, const float color[3])
{
    double phi_material = material_stripe_angle(rec), previous = phi_material;
    for (int k = 0; k < rec->nodes; k++) {
        double phi = phi_material;
        if (mode == RENDER_STRIPE_FORMULA) {
            /* (4.17)'s offset, projected on the cross-section so the band stays on the tube */
            const double *q = node_frame(rec, frame, k);
            double d1[3], d2[3], d3[3], offset[3];
            m3_column(d1, q, 0);
            m3_column(d2, q, 1);
            m3_column(d3, q, 2);
            stripe_formula_offset(rec, frame, k, offset);
            v3_axpy(offset, -v3_dot(offset, d3), d3);
            phi = v3_norm(offset) > 1e-9 ? atan2(v3_dot(offset, d2), v3_dot(offset, d1)) : previous;
            previous = phi;
        }
        c->phi[k] = phi;
    }
    unsigned first = (unsigned)m->vertex_count;
    for (int ring = 0; ring < c->count; ring++) {
        const double *r = &c->point[3 * ring], *q = &c->frame[9 * ring];
        const int k = c->node[ring];
        double d1[3], d2[3], phi = c->phi[k];
        if (c->t[ring] > 0) phi += c->t[ring] * remainder(c->phi[k + 1] - c->phi[k], 2 * M_PI);
        m3_column(d1, q, 0);
        m3_column(d2, q, 1);
        for (int s = -1; s <= 1; s++) {
            double angle = phi + s * STRIPE_HALF_WIDTH, n[3] = {0, 0, 0}, p[3];
            v3_axpy(n, cos(angle), d1);
            v3_axpy(n, sin(angle), d2);
            v3_copy(p, r);
            v3_axpy(p, STRIPE_LIFT * radius, n);
            mesh_vertex(m, p, n, color);
        }
    }
    for (int k = 0; k + 1 < c->count; k++)
        for (int s = 0; s < 2; s++) {
            unsigned a = first + (unsigned)(3 * k + s);
            mesh_triangle(m, a, a + 3, a + 4);
            mesh_triangle(m, a, a + 4, a + 1);
        }
}

/* ------------------------------------------------------------------ occlusion */

double render_occlusion(const double p[3], const double n[3], const double axis_a[3],
                        const double axis_b[3], double radius)
{
    double along[3], to_p[3], q[3], d[3];
    v3_sub(along, axis_b, axis_a);
    v3_sub(to_p, p, axis_a);
    double length2 = v3_dot(along, along), u = length2 > 0 ? v3_dot(to_p, along) / length2 : 0;
    u = u < 0 ? 0 : u > 1 ? 1 : u;
    v3_copy(q, axis_a);
    v3_axpy(q, u, along);
    v3_sub(d, q, p);
    double distance = v3_norm(d), reach = RENDER_OCCLUSION_REACH * radius;
    double facing = v3_dot(n, d);
    if (!(distance < reach) || facing <= 0) return 0;
    if (distance <= radius) return 1; /* inside the other tube: strands drawn overlapping */
    /* the window: 1 up to 2 radii (strands touching or nearly), smoothstep to 0 at the reach */
    double t = (distance - 2 * radius) / (reach - 2 * radius), window = 1;
    if (t > 0) window = 1 - t * t * (3 - 2 * t);
    double value = radius / distance * (facing / distance) * window;
    return value > 1 ? 1 : value;
}

/* The occlusion of `count` consecutive vertices (a ring) by a segment,
 * kept as the largest so far in occlusion[] (the max, not the sum: the
 * segments of one strand beside a point all see it at about the same
 * distance, and would count it several times). */
static void occlude_ring(const render_mesh *m, unsigned first, int count,
                         const double *a, const double *b, double radius, float *occlusion)
{
    for (int j = 0; j < count; j++) {
        const render_vertex *v = &m->vertices[first + (unsigned)j];
        double p[3], n[3];
        for (int c = 0; c < 3; c++) {
            p[c] = v->position[c];
            n[c] = v->normal[c];
        }
        float value = (float)render_occlusion(p, n, a, b, radius);
        if (value > occlusion[j]) occlusion[j] = value;
    }
}

int occlusion_create(strand_occlusion *s, int nodes, int rings, int sides, double radius,
                     double ds)
{
    memset(s, 0, sizeof *s);
    /* Decision: pairs beyond 32 a segment (an exaggerated radius over a
     * tight coil) are dropped, and with them some vertices' darkening */
    s->max_pairs = 32 * nodes;
    s->proximity = rod_proximity_create(nodes);
    s->pairs = malloc((size_t)s->max_pairs * sizeof *s->pairs);
    s->occlusion = malloc((size_t)rings * (size_t)(sides + 3) * sizeof(float));
    /* as self-contact (rod_proximity_skip): points closer along the rod than a
     * half turn of radius `radius` are one strand, and a bent tube's inside
     * is not darkened by its own next segments */
    s->skip = rod_proximity_skip(2 * radius, ds);
    return s->proximity && s->pairs && s->occlusion ? 0 : -1;
}

int recording_far_pairs(const rod_recording *rec, rod_segment_pair *pairs, int count, double span)
{
    int kept = 0;
    for (int k = 0; k < count; k++)
        if (rod_recording_arc(rec, pairs[k].j) - rod_recording_arc(rec, pairs[k].i + 1) >=
            span * (1 - 1e-12))
            pairs[kept++] = pairs[k];
    return kept;
}

void occlusion_destroy(strand_occlusion *s)
{
    rod_proximity_destroy(s->proximity);
    free(s->pairs);
    free(s->occlusion);
    s->proximity = NULL;
    s->pairs = NULL;
    s->occlusion = NULL;
}

/* The index of pair (i, j) in pairs (sorted by (i, j)), or -1. */
static int find_pair(const rod_segment_pair *pairs, int count, int i, int j)
{
    int lo = 0, hi = count - 1;
    while (lo <= hi) {
        int mid = (lo + hi) / 2;
        const rod_segment_pair *p = &pairs[mid];
        if (p->i == i && p->j == j) return mid;
        if (p->i < i || (p->i == i && p->j < j)) lo = mid + 1;
        else hi = mid - 1;
    }
    return -1;
}

/* 1 when the pair at `at` is nearer than its neighbour at `beside` (-1:
 * none), ties going to the one earlier along the rod. */
static int nearer(const rod_segment_pair *pairs, int at, int beside, int beside_is_before)
{
    if (beside < 0) return 1;
    return beside_is_before ? pairs[at].distance < pairs[beside].distance
                            : pairs[at].distance <= pairs[beside].distance;
}

void occlusion_shade(strand_occlusion *s, render_mesh *m, const render_centreline *line,
                     const rod_recording *rec, int frame, int sides, double radius,
                     unsigned tube, int stripe)
{
    int nodes = rec->nodes, per_node = sides + 3;
    const double *points = node_position(rec, frame, 0);
    const rod_segment_pair *pairs = s->pairs;
    int found = rod_proximity_pairs(s->proximity, points, nodes,
                                    (RENDER_OCCLUSION_REACH + 1) * radius, s->skip,
                                    s->pairs, s->max_pairs);
    if (found <= 0) return; /* none, or a non-finite point (drawn as it is) */
    if (found > s->max_pairs) found = s->max_pairs;
    /* a graded grid: the skip counted its longest segment; one strand is
     * half a turn of radius `radius` in arc (rod_proximity_skip's rule) */
    if (rec->arc) found = recording_far_pairs(rec, s->pairs, found, M_PI * radius);
    if (found <= 0) return;
    memset(s->occlusion, 0, (size_t)line->count * (size_t)per_node * sizeof(float));
    for (int k = 0; k < found; k++) {
        int i = pairs[k].i, j = pairs[k].j;
        for (int side = 0; side < 2; side++) {
            /* side 0: the rings of segment i shaded by segment j; 1: the reverse */
            int segment = side ? i : j, ring = side ? j : i;
            int before = side ? find_pair(pairs, found, i - 1, j) : k > 0 && pairs[k - 1].i == i &&
                                pairs[k - 1].j == j - 1 ? k - 1 : -1;
            int after = side ? find_pair(pairs, found, i + 1, j) : k + 1 < found &&
                               pairs[k + 1].i == i && pairs[k + 1].j == j + 1 ? k + 1 : -1;
            if (!nearer(pairs, k, before, 1) || !nearer(pairs, k, after, 0)) continue;
            const double *a = &points[3 * segment], *b = &points[3 * (segment + 1)];
            /* the drawn rings from node `ring` to node ring + 1 */
            for (int at = line->first[ring]; at <= line->first[ring + 1]; at++) {
                float *occlusion = &s->occlusion[at * per_node];
                occlude_ring(m, tube + (unsigned)(at * sides), sides, a, b, radius,
                             occlusion);
                if (stripe >= 0)
                    occlude_ring(m, (unsigned)stripe + (unsigned)(3 * at), 3, a, b,
                                 radius, occlusion + sides);
            }
        }
    }
    for (int at = 0; at < line->count; at++)
        for (int j = 0; j < per_node; j++) {
            float shade = 1.0f - (float)RENDER_OCCLUSION_STRENGTH * s->occlusion[at * per_node + j];
            if (shade == 1.0f || (j >= sides && stripe < 0)) continue;
            unsigned index = j < sides ? tube + (unsigned)(at * sides + j)
                                       : (unsigned)stripe + (unsigned)(3 * at + j - sides);
            for (int c = 0; c < 3; c++) m->vertices[index].color[c] *= shade;
        }
}
