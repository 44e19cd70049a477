/* surface.c: the surfaces as drawn (surface.h). */
#include "render/surface.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "render/geometry.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

void surface_bounds(const recording_surface *s, double lo[3], double hi[3])
{
    for (int c = 0; c < 3; c++) {
        double reach;
        switch (s->shape) {
        case RECORDING_SURFACE_BOX: reach = 0.5 * s->size[c]; break;
        case RECORDING_SURFACE_SPHERE: reach = s->size[0]; break;
        case RECORDING_SURFACE_MESH: {
            double a = INFINITY, b = -INFINITY;
            for (int i = 0; i < s->mesh_vertex_count; i++) {
                a = fmin(a, s->mesh_vertices[3 * i + c]);
                b = fmax(b, s->mesh_vertices[3 * i + c]);
            }
            lo[c] = a;
            hi[c] = b;
            continue;
        }
        case RECORDING_SURFACE_CYLINDER:
            reach = fabs(s->normal[c]) > 1e-12 ? INFINITY
                                                : s->size[0] * sqrt(1 - s->normal[c] * s->normal[c]);
            break;
        default: reach = INFINITY; break;
        }
        lo[c] = s->center[c] - reach;
        hi[c] = s->center[c] + reach;
    }
}

/* The point of the surface nearest p (into near) and the outward normal
 * there; returns the distance. The renderer's own: it does not see
 * sim/contact/surface.h (layer rule), and needs no grown solid. */
static double surface_nearest(const recording_surface *s, const double p[3], double near[3],
                              double n[3])
{
    double d[3];
    v3_sub(d, p, s->center);
    switch (s->shape) {
    case RECORDING_SURFACE_MESH: /* not a surface a wound or a puncture is laid on */
        v3_copy(near, p);
        v3_set(n, 0, 0, 1);
        return INFINITY;
    default: /* RECORDING_SURFACE_PLANE */
        v3_copy(n, s->normal);
        v3_copy(near, p);
        v3_axpy(near, -v3_dot(d, n), n);
        break;
    case RECORDING_SURFACE_SPHERE:
    case RECORDING_SURFACE_CYLINDER: {
        double radial[3];
        v3_copy(radial, d);
        if (s->shape == RECORDING_SURFACE_CYLINDER)
            v3_axpy(radial, -v3_dot(d, s->normal), s->normal);
        double length = v3_norm(radial);
        if (length > 0) v3_scale(n, radial, 1 / length);
        else perpendicular_basis(s->normal, n, radial);
        v3_copy(near, p);
        v3_axpy(near, s->size[0] - length, n);
        break;
    }
    case RECORDING_SURFACE_BOX: {
        /* the face whose slab p is farthest out of (or least inside) */
        int face = 0;
        double out = -INFINITY;
        for (int c = 0; c < 3; c++) {
            double beyond = fabs(d[c]) - 0.5 * s->size[c];
            if (beyond > out) out = beyond, face = c;
        }
        for (int c = 0; c < 3; c++) {
            double h = 0.5 * s->size[c];
            near[c] = s->center[c] + fmax(-h, fmin(h, d[c]));
            n[c] = 0;
        }
        n[face] = d[face] < 0 ? -1 : 1;
        near[face] = s->center[face] + n[face] * 0.5 * s->size[face];
        break;
    }
    }
    double gap[3];
    v3_sub(gap, p, near);
    return v3_norm(gap);
}

void surface_add_plane(render_mesh *m, const double point[3], const double n[3],
                       const double centre[3], double half, const float color[3])
{
    double e1[3], e2[3], middle[3];
    perpendicular_basis(n, e1, e2);
    v3_copy(middle, centre);
    v3_axpy(middle, -v3_dot(n, (double[3]){centre[0] - point[0], centre[1] - point[1],
                                           centre[2] - point[2]}),
            n);
    unsigned first = (unsigned)m->vertex_count;
    for (int corner = 0; corner < 4; corner++) {
        double p[3];
        v3_copy(p, middle);
        v3_axpy(p, (corner & 1 ? 1 : -1) * half, e1);
        v3_axpy(p, (corner & 2 ? 1 : -1) * half, e2);
        mesh_vertex(m, p, n, color);
    }
    mesh_triangle(m, first, first + 1, first + 3);
    mesh_triangle(m, first, first + 3, first + 2);
}

void surface_add_sphere(render_mesh *m, const double centre[3], double radius,
                        const float color[3])
{
    mesh_globe(m, centre, radius, SURFACE_STACKS, SURFACE_SIDES, color);
}

void surface_add_cylinder(render_mesh *m, const double centre[3], const double a[3], double radius,
                          double half, const float color[3])
{
    double e1[3], e2[3];
    perpendicular_basis(a, e1, e2);
    unsigned first = (unsigned)m->vertex_count;
    for (int end = 0; end < 2; end++)
        for (int j = 0; j <= SURFACE_SIDES; j++) {
            double phi = 2 * M_PI * j / SURFACE_SIDES, n[3] = {0, 0, 0}, p[3];
            v3_axpy(n, cos(phi), e1);
            v3_axpy(n, sin(phi), e2);
            v3_copy(p, centre);
            v3_axpy(p, end ? half : -half, a);
            v3_axpy(p, radius, n);
            mesh_vertex(m, p, n, color);
        }
    for (int j = 0; j < SURFACE_SIDES; j++) {
        unsigned p0 = first + (unsigned)j, q0 = p0 + SURFACE_SIDES + 1;
        mesh_triangle(m, p0, q0, q0 + 1);
        mesh_triangle(m, p0, q0 + 1, p0 + 1);
    }
    for (int end = 0; end < 2; end++) {
        double c[3], n[3];
        v3_copy(c, centre);
        v3_axpy(c, end ? half : -half, a);
        v3_scale(n, a, end ? 1 : -1);
        mesh_disc(m, c, e1, e2, radius, n, SURFACE_SIDES, color);
    }
}

void surface_cylinder_piece(const recording_surface *s, const double lo[3], const double hi[3],
                            double size, double centre[3], double *half)
{
    double t0 = INFINITY, t1 = -INFINITY;
    for (int corner = 0; corner < 8; corner++) {
        double p[3];
        for (int c = 0; c < 3; c++) p[c] = (corner >> c & 1 ? hi[c] : lo[c]) - s->center[c];
        double t = v3_dot(p, s->normal);
        t0 = fmin(t0, t);
        t1 = fmax(t1, t);
    }
    v3_copy(centre, s->center);
    v3_axpy(centre, 0.5 * (t0 + t1), s->normal);
    *half = 0.5 * (t1 - t0) + size;
}

/* The surface nearest p among rec's (-1: none), its nearest point and normal. */
static int nearest_surface(const rod_recording *rec, const double p[3], double near[3],
                           double n[3])
{
    int best = -1;
    double best_gap = INFINITY;
    for (int k = 0; k < rec->surface_count; k++) {
        double q[3], m[3], gap = surface_nearest(&rec->surfaces[k], p, q, m);
        if (gap < best_gap) {
            best_gap = gap;
            best = k;
            v3_copy(near, q);
            v3_copy(n, m);
        }
    }
    return best;
}

void surface_add_wound(render_mesh *m, const rod_recording *rec, const render_options *o,
                       double width, double lift, const double up_fallback[3])
{
    const double *a = o->wound_line, *b = &o->wound_line[3];
    double along[3];
    v3_sub(along, b, a);
    v3_scale(along, along, 1 / v3_norm(along));
    unsigned first = (unsigned)m->vertex_count;
    for (int k = 0; k <= WOUND_SEGMENTS; k++) {
        double f = (double)k / WOUND_SEGMENTS, p[3], near[3], n[3], side[3];
        for (int c = 0; c < 3; c++) p[c] = a[c] + f * (b[c] - a[c]);
        if (nearest_surface(rec, p, near, n) < 0) {
            v3_copy(near, p);
            v3_copy(n, up_fallback);
        }
        v3_axpy(near, lift, n);
        v3_cross(side, n, along);
        double length = v3_norm(side);
        if (!(length > 0)) perpendicular_basis(n, side, p);
        else v3_scale(side, side, 1 / length);
        for (int e = -1; e <= 1; e += 2) {
            double q[3];
            v3_copy(q, near);
            v3_axpy(q, 0.5 * width * e, side);
            mesh_vertex(m, q, n, render_wound_color);
        }
    }
    for (int k = 0; k < WOUND_SEGMENTS; k++) {
        unsigned i = first + 2 * (unsigned)k;
        mesh_triangle(m, i, i + 2, i + 3);
        mesh_triangle(m, i, i + 3, i + 1);
    }
}

/* The point of triangle a b c nearest p (Ericson, Real-Time Collision
 * Detection, 5.1.5) into q. */
static void triangle_nearest(const double p[3], const double a[3], const double b[3],
                             const double c[3], double q[3])
{
    double ab[3], ac[3], ap[3], bp[3], cp[3];
    v3_sub(ab, b, a);
    v3_sub(ac, c, a);
    v3_sub(ap, p, a);
    double d1 = v3_dot(ab, ap), d2 = v3_dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) {
        v3_copy(q, a);
        return;
    }
    v3_sub(bp, p, b);
    double d3 = v3_dot(ab, bp), d4 = v3_dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) {
        v3_copy(q, b);
        return;
    }
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        v3_copy(q, a);
        v3_axpy(q, d1 / (d1 - d3), ab);
        return;
    }
    v3_sub(cp, p, c);
    double d5 = v3_dot(ab, cp), d6 = v3_dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) {
        v3_copy(q, c);
        return;
    }
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        v3_copy(q, a);
        v3_axpy(q, d2 / (d2 - d6), ac);
        return;
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
        double bc[3];
        v3_sub(bc, c, b);
        v3_copy(q, b);
        v3_axpy(q, (d4 - d3) / ((d4 - d3) + (d5 - d6)), bc);
        return;
    }
    double denom = 1 / (va + vb + vc);
    v3_copy(q, a);
    v3_axpy(q, vb * denom, ab);
    v3_axpy(q, vc * denom, ac);
}

/* The point of elastic pad k's surface at `frame` nearest p, and the
 * outward normal of its triangle there; the distance (m), or INFINITY
 * when the frame holds no pad. */
static double pad_nearest(const rod_recording *rec, int k, int frame, const double p[3],
                          double near[3], double n[3])
{
    const recording_surface *s = &rec->surfaces[k];
    const double *x = rod_recording_pad_positions(rec, k, frame);
    double best = INFINITY;
    for (int t = 0; x && t < s->pad_triangle_count; t++) {
        const int *v = &s->pad_triangles[3 * t];
        double q[3], gap[3], outside = 0;
        for (int c = 0; c < 3; c++) {
            /* the triangle's box no nearer than the best: skip it */
            double lo = fmin(x[3 * v[0] + c], fmin(x[3 * v[1] + c], x[3 * v[2] + c]));
            double hi = fmax(x[3 * v[0] + c], fmax(x[3 * v[1] + c], x[3 * v[2] + c]));
            double beyond = fmax(lo - p[c], p[c] - hi);
            if (beyond > 0) outside += beyond * beyond;
        }
        if (outside >= best * best) continue;
        triangle_nearest(p, &x[3 * v[0]], &x[3 * v[1]], &x[3 * v[2]], q);
        v3_sub(gap, p, q);
        double d = v3_norm(gap);
        if (d >= best) continue;
        double ab[3], ac[3], face[3];
        v3_sub(ab, &x[3 * v[1]], &x[3 * v[0]]);
        v3_sub(ac, &x[3 * v[2]], &x[3 * v[0]]);
        v3_cross(face, ab, ac);
        double length = v3_norm(face);
        if (!(length > 0)) continue;
        best = d;
        v3_copy(near, q);
        v3_scale(n, face, 1 / length);
    }
    return best;
}

/* Where segment j of the thread of `frame` crosses the pad's triangles x
 * (Moller-Trumbore), if nearer p than *best: the point and the outward
 * normal of the triangle crossed, *best its distance from p. */
static void segment_crossing(const rod_recording *rec, const recording_surface *s,
                             const double *x, int frame, int j, const double p[3], double *best,
                             double at[3], double n[3])
{
    const double *q0 = node_position(rec, frame, j), *q1 = node_position(rec, frame, j + 1);
    double d[3], mid[3], to[3];
    v3_sub(d, q1, q0);
    v3_copy(mid, q0);
    v3_axpy(mid, 0.5, d);
    v3_sub(to, mid, p);
    if (v3_norm(to) - 0.5 * v3_norm(d) >= *best) return; /* no point of it nearer */
    for (int t = 0; t < s->pad_triangle_count; t++) {
        const int *v = &s->pad_triangles[3 * t];
        const double *a = &x[3 * v[0]];
        double ab[3], ac[3], h[3], w[3], q[3];
        v3_sub(ab, &x[3 * v[1]], a);
        v3_sub(ac, &x[3 * v[2]], a);
        v3_cross(h, d, ac);
        double det = v3_dot(ab, h);
        if (fabs(det) < 1e-30) continue;
        v3_sub(w, q0, a);
        double u = v3_dot(w, h) / det;
        if (u < 0 || u > 1) continue;
        v3_cross(q, w, ab);
        double second = v3_dot(d, q) / det, f = v3_dot(ac, q) / det;
        if (second < 0 || u + second > 1 || f < 0 || f > 1) continue;
        double hit[3], gap[3], face[3];
        v3_copy(hit, q0);
        v3_axpy(hit, f, d);
        v3_sub(gap, hit, p);
        if (v3_norm(gap) >= *best) continue;
        *best = v3_norm(gap);
        v3_copy(at, hit);
        v3_cross(face, ab, ac);
        v3_scale(n, face, 1 / v3_norm(face));
    }
}

/* Where the thread of `frame` crosses elastic pad k's surface nearest p:
 * 1 with the point and the outward normal of the triangle crossed, 0 when
 * it crosses none. The segments beside the one nearest p are tried first,
 * so that the others, farther than the crossing found, are not. */
static int thread_crossing(const rod_recording *rec, int k, int frame, const double p[3],
                           double at[3], double n[3])
{
    const recording_surface *s = &rec->surfaces[k];
    const double *x = rod_recording_pad_positions(rec, k, frame);
    if (!x) return 0;
    int nearest = 0;
    double least = INFINITY, best = INFINITY;
    for (int j = 0; j + 1 < rec->nodes; j++) {
        double to[3];
        v3_sub(to, node_position(rec, frame, j), p);
        if (v3_norm(to) < least) least = v3_norm(to), nearest = j;
    }
    for (int j = nearest - 2; j <= nearest + 1; j++)
        if (j >= 0 && j + 1 < rec->nodes) segment_crossing(rec, s, x, frame, j, p, &best, at, n);
    for (int j = 0; j + 1 < rec->nodes; j++)
        if (j < nearest - 2 || j > nearest + 1)
            segment_crossing(rec, s, x, frame, j, p, &best, at, n);
    return isfinite(best);
}

void surface_add_punctures(render_mesh *m, const rod_recording *rec, int frame, double radius,
                           double lift)
{
    const double *points;
    int count = rod_recording_punctures(rec, frame, &points);
    for (int i = 0; i < count; i++) {
        double near[3], n[3], e1[3], e2[3];
        /* on the surface nearest the point, just off it */
        int k = nearest_surface(rec, &points[3 * i], near, n);
        if (k < 0) continue;
        if (rec->surfaces[k].pad_node_count > 0) {
            /* an elastic pad: where the thread goes through its surface as it
             * is at this frame, nearest the point; a point inside it (more
             * than a disc's radius: where the thread passes under the skin)
             * has no hole to draw */
            double off[3];
            if (!isfinite(pad_nearest(rec, k, frame, &points[3 * i], near, n))) continue;
            v3_sub(off, &points[3 * i], near);
            if (v3_dot(off, n) < -PUNCTURE_DISC * radius) continue;
            (void)thread_crossing(rec, k, frame, &points[3 * i], near, n);
        }
        v3_axpy(near, lift, n);
        perpendicular_basis(n, e1, e2);
        mesh_disc(m, near, e1, e2, PUNCTURE_DISC * radius, n, PUNCTURE_SIDES,
                  render_puncture_color);
    }
}

/* The unit normal of triangle t of a mesh surface (0 0 0 for a degenerate one). */
static void mesh_face_normal(const recording_surface *s, int t, double n[3])
{
    const int *v = &s->mesh_triangles[3 * t];
    double ab[3], ac[3];
    v3_sub(ab, &s->mesh_vertices[3 * v[1]], &s->mesh_vertices[3 * v[0]]);
    v3_sub(ac, &s->mesh_vertices[3 * v[2]], &s->mesh_vertices[3 * v[0]]);
    v3_cross(n, ab, ac);
    double length = v3_norm(n);
    if (length > 0) v3_scale(n, n, 1 / length);
}

/* The corner angle of triangle t at its k-th vertex, rad. */
static double mesh_corner_angle(const recording_surface *s, int t, int k)
{
    const int *v = &s->mesh_triangles[3 * t];
    const double *p = &s->mesh_vertices[3 * v[k]];
    double e1[3], e2[3];
    v3_sub(e1, &s->mesh_vertices[3 * v[(k + 1) % 3]], p);
    v3_sub(e2, &s->mesh_vertices[3 * v[(k + 2) % 3]], p);
    double l = v3_norm(e1) * v3_norm(e2);
    if (!(l > 0)) return 0;
    double c = v3_dot(e1, e2) / l;
    return acos(c > 1 ? 1 : c < -1 ? -1 : c);
}

int surface_mesh_topology_init(surface_mesh_topology *t, const recording_surface *s)
{
    memset(t, 0, sizeof *t);
    const int nv = s->mesh_vertex_count, nt = s->mesh_triangle_count;
    if (nv <= 0 || nt <= 0) return 0;
    t->start = calloc((size_t)nv + 1, sizeof(int));
    t->list = malloc((size_t)nt * 3 * sizeof(int));
    t->normal = malloc((size_t)nt * 3 * sizeof(double));
    if (!t->start || !t->list || !t->normal) {
        surface_mesh_topology_release(t);
        return -1;
    }
    t->vertices = nv;
    t->triangles = nt;
    /* each vertex's triangles (CSR) */
    int *start = t->start, *list = t->list;
    for (int e = 0; e < 3 * nt; e++) start[s->mesh_triangles[e] + 1]++;
    for (int i = 0; i < nv; i++) start[i + 1] += start[i];
    for (int e = 0; e < 3 * nt; e++) list[start[s->mesh_triangles[e]]++] = e;
    for (int i = nv; i > 0; i--) start[i] = start[i - 1];
    start[0] = 0;
    return 0;
}

void surface_mesh_topology_release(surface_mesh_topology *t)
{
    free(t->start);
    free(t->list);
    free(t->normal);
    memset(t, 0, sizeof *t);
}

void surface_add_mesh_shaded(render_mesh *m, const recording_surface *s, surface_mesh_topology *t,
                             const float color[3])
{
    const int nt = t->triangles;
    const int *start = t->start, *list = t->list;
    double *normal = t->normal;
    for (int f = 0; f < nt; f++) mesh_face_normal(s, f, &normal[3 * f]);
    const double crease = cos(MESH_CREASE_ANGLE);
    for (int f = 0; f < nt; f++) {
        const double *own = &normal[3 * f];
        unsigned first = (unsigned)m->vertex_count;
        for (int k = 0; k < 3; k++) {
            const int v = s->mesh_triangles[3 * f + k];
            /* smooth across the faces at the vertex within the crease angle
             * of this one (angle-weighted); flat across sharper edges */
            double n[3] = {0, 0, 0};
            for (int e = start[v]; e < start[v + 1]; e++) {
                const int u = list[e] / 3;
                if (v3_dot(&normal[3 * u], own) < crease) continue;
                v3_axpy(n, mesh_corner_angle(s, u, list[e] % 3), &normal[3 * u]);
            }
            double length = v3_norm(n);
            if (length > 0) v3_scale(n, n, 1 / length);
            else v3_copy(n, own);
            mesh_vertex(m, &s->mesh_vertices[3 * v], n, color);
        }
        mesh_triangle(m, first, first + 1, first + 2);
    }
}

int surface_add_mesh(render_mesh *m, const recording_surface *s, const float color[3])
{
    surface_mesh_topology t;
    if (surface_mesh_topology_init(&t, s)) return -1;
    surface_add_mesh_shaded(m, s, &t, color);
    surface_mesh_topology_release(&t);
    return 0;
}
