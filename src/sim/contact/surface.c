/* surface.c: distance to the rigid obstacles and the first crossing of a
 * moving point (see surface.h). */
#include "sim/contact/surface.h"

#include <math.h>
#include <string.h>
#include <stdio.h>

#include "base/vec3.h"
#include "sim/contact/mesh.h"

const char *rod_surface_name(rod_surface_shape shape)
{
    static const char *const names[] = {"plane", "box", "cylinder", "sphere", "mesh"};
    return shape >= ROD_SURFACE_PLANE && shape <= ROD_SURFACE_MESH ? names[shape] : "?";
}

/* A unit vector normal to `a` (for the degenerate point on an axis or at a
 * centre, where every direction is as near). */
static void any_normal(const double a[3], double out[3])
{
    double t[3] = {0.0, 0.0, 1.0};
    if (fabs(a[2]) > 0.9) v3_set(t, 1.0, 0.0, 0.0);
    v3_cross(out, a, t);
    v3_scale(out, out, 1.0 / v3_norm(out));
}

/* Half an edge of the box's core: the box less its rounding on each side
 * (its surface is the core grown by the rounding, then by the rod's radius) */
static double box_half(const rod_surface *s, int k)
{
    return 0.5 * s->size[k] - s->rounding;
}

double rod_surface_gap(const rod_surface *s, const double p[3], double grow, double normal[3],
                       double nearest[3])
{
    double q[3], n[3], gap, near[3];
    v3_sub(q, p, s->center);
    switch (s->shape) {
    case ROD_SURFACE_PLANE:
        v3_copy(n, s->normal);
        gap = v3_dot(q, n) - grow;
        for (int k = 0; k < 3; k++) near[k] = p[k] - gap * n[k];
        break;
    case ROD_SURFACE_SPHERE: {
        double d = v3_norm(q), r = s->size[0] + grow;
        if (d > 0.0) v3_scale(n, q, 1.0 / d);
        else v3_set(n, 0.0, 0.0, 1.0);
        gap = d - r;
        for (int k = 0; k < 3; k++) near[k] = s->center[k] + r * n[k];
        break;
    }
    case ROD_SURFACE_CYLINDER: {
        double along = v3_dot(q, s->normal), radial[3], r = s->size[0] + grow;
        for (int k = 0; k < 3; k++) radial[k] = q[k] - along * s->normal[k];
        double d = v3_norm(radial);
        if (d > 0.0) v3_scale(n, radial, 1.0 / d);
        else any_normal(s->normal, n);
        gap = d - r;
        for (int k = 0; k < 3; k++) near[k] = s->center[k] + along * s->normal[k] + r * n[k];
        break;
    }
    case ROD_SURFACE_MESH: {
        /* the distance to the triangles less the rod's radius (exact
         * outside: the grown solid is the mesh's solid grown by a ball) */
        double d = rod_mesh_distance(s->mesh, p, n, near);
        gap = d - grow;
        v3_axpy(near, grow, n);
        break;
    }
    case ROD_SURFACE_BOX:
    default: {
        /* a box rounded by R: the box shrunk by R on every side, grown by R
         * (box_half) */
        grow += s->rounding;
        double h[3], clamp[3], diff[3];
        int outside = 0, face = 0;
        double most = -INFINITY;
        for (int k = 0; k < 3; k++) {
            h[k] = box_half(s, k);
            clamp[k] = q[k] < -h[k] ? -h[k] : q[k] > h[k] ? h[k] : q[k];
            diff[k] = q[k] - clamp[k];
            if (fabs(q[k]) > h[k]) outside = 1;
            if (fabs(q[k]) - h[k] > most) {
                most = fabs(q[k]) - h[k];
                face = k;
            }
        }
        if (outside) {
            /* nearest point of the box, then out by `grow` (the grown box is rounded) */
            double d = v3_norm(diff);
            v3_scale(n, diff, 1.0 / d);
            gap = d - grow;
            for (int k = 0; k < 3; k++) near[k] = s->center[k] + clamp[k] + grow * n[k];
        } else {
            /* inside: out through the nearest face */
            v3_set(n, 0.0, 0.0, 0.0);
            n[face] = q[face] < 0.0 ? -1.0 : 1.0;
            gap = most - grow;
            v3_copy(near, p);
            near[face] = s->center[face] + n[face] * (h[face] + grow);
        }
        break;
    }
    }
    if (normal) v3_copy(normal, n);
    if (nearest) v3_copy(nearest, near);
    return gap;
}

static double gap_at(const rod_surface *s, const double a[3], const double ab[3], double f,
                     double grow)
{
    double p[3];
    for (int k = 0; k < 3; k++) p[k] = a[k] + f * ab[k];
    return rod_surface_gap(s, p, grow, NULL, NULL);
}

/* The entry of the segment a + f ab into a box grown by `grow` where it is
 * exact in closed form, for rod_surface_sweep: the box grown square by grow
 * holds the rounded one, so a segment that misses it misses (returns 0), and
 * one that enters it through the flat part of a face (within the box's own
 * extent on the other two axes) enters the rounded box there (returns 1,
 * *f). Returns -1 where only a search answers: entering over an edge or a
 * corner's rounding, or starting inside the square box. */
static int box_entry(const rod_surface *s, const double a[3], const double ab[3], double grow,
                     double *f)
{
    double enter = -INFINITY, leave = INFINITY;
    int face = -1;
    for (int k = 0; k < 3; k++) {
        /* the square box: a rounded one's core grown square by its rounding + grow */
        const double h = 0.5 * s->size[k], lo = s->center[k] - h - grow, hi = s->center[k] + h + grow;
        if (ab[k] == 0.0) {
            if (a[k] < lo || a[k] > hi) return 0;
            continue;
        }
        double t0 = (lo - a[k]) / ab[k], t1 = (hi - a[k]) / ab[k];
        if (t0 > t1) {
            double swap = t0;
            t0 = t1;
            t1 = swap;
        }
        if (t0 > enter) {
            enter = t0;
            face = k;
        }
        if (t1 < leave) leave = t1;
    }
    if (enter > leave || enter > 1.0 || leave < 0.0) return 0;
    if (!(enter >= 0.0) || face < 0) return -1;
    for (int k = 0; k < 3; k++) {
        if (k == face) continue;
        const double q = a[k] + enter * ab[k] - s->center[k];
        if (fabs(q) > box_half(s, k)) return -1;
    }
    *f = enter;
    return 1;
}

/* The entry of the segment a + f ab (length len, gap ga > 0 at a) into a
 * mesh's grown solid, which need not be convex: sphere tracing, each step
 * the gap itself (the gap is 1-Lipschitz, so no step passes the surface),
 * until within 1e-6 of the radius of it (a grazing path that stays that
 * near is taken as touching there: the caller's half-space then decides).
 * Returns 1 with *f, or 0 when the segment ends first. */
static int mesh_entry(const rod_surface *s, const double a[3], const double ab[3], double len,
                      double ga, double grow, double *f)
{
    const double near = 1e-6 * (grow > 0.0 ? grow : 1e-3 * len) + 1e-15;
    double at = 0.0, gap = ga;
    for (int it = 0; it < 200; it++) {
        if (gap <= near) {
            *f = at;
            return 1;
        }
        at += gap / len;
        if (at > 1.0) return 0;
        gap = gap_at(s, a, ab, at, grow);
    }
    *f = at;
    return 1;
}

int rod_surface_sweep(const rod_surface *s, const double a[3], const double b[3], double grow,
                      double *f, double point[3], double normal[3])
{
    double ab[3];
    v3_sub(ab, b, a);
    const double len = v3_norm(ab);
    const double ga = rod_surface_gap(s, a, grow, NULL, NULL);
    if (!(ga > 0.0) || len == 0.0) return 0;
    double hi = 1.0;
    /* closed forms where they are exact (the search below answers the rest):
     * a plane's gap is linear along the segment; a box is entered through a
     * face's flat part */
    int closed = -1;
    if (s->shape == ROD_SURFACE_MESH) {
        if (!mesh_entry(s, a, ab, len, ga, grow, &hi)) return 0;
        closed = 1;
    } else if (s->shape == ROD_SURFACE_PLANE) {
        const double gb = rod_surface_gap(s, b, grow, NULL, NULL);
        closed = gb > 0.0 ? 0 : 1;
        if (closed) hi = ga / (ga - gb);
    } else if (s->shape == ROD_SURFACE_BOX) {
        closed = box_entry(s, a, ab, grow, &hi);
    }
    if (closed == 0) return 0;
    if (closed < 0) {
        const double gb = rod_surface_gap(s, b, grow, NULL, NULL);
        if (!(gb <= 0.0)) {
            /* both ends outside: the distance is 1-Lipschitz, so along the
             * segment it stays above (ga + gb - len) / 2; when that is
             * positive the point never reaches the solid (one test) */
            if (ga + gb - len > 0.0) return 0;
            /* else the distance is convex along the segment: golden-section
             * search for its least value, stopping at the first point inside */
            const double golden = 0.6180339887498949;
            double lo = 0.0, top = 1.0;
            double x1 = top - golden * (top - lo), x2 = lo + golden * (top - lo);
            double g1 = gap_at(s, a, ab, x1, grow), g2 = gap_at(s, a, ab, x2, grow);
            int found = 0;
            for (int it = 0; it < 80 && !found; it++) {
                if (g1 <= 0.0) { hi = x1; found = 1; break; }
                if (g2 <= 0.0) { hi = x2; found = 1; break; }
                if (g1 < g2) {
                    top = x2; x2 = x1; g2 = g1;
                    x1 = top - golden * (top - lo);
                    g1 = gap_at(s, a, ab, x1, grow);
                } else {
                    lo = x1; x1 = x2; g1 = g2;
                    x2 = lo + golden * (top - lo);
                    g2 = gap_at(s, a, ab, x2, grow);
                }
                if ((top - lo) * len < 1e-12) break;
            }
            if (!found) return 0;
        }
        /* bisection for the entry between the outside start and a point inside */
        double lo = 0.0;
        for (int it = 0; it < 60 && (hi - lo) * len > 1e-15; it++) {
            double mid = 0.5 * (lo + hi);
            if (gap_at(s, a, ab, mid, grow) > 0.0) lo = mid;
            else hi = mid;
        }
    }
    double p[3];
    for (int k = 0; k < 3; k++) p[k] = a[k] + hi * ab[k];
    double n[3], near[3];
    rod_surface_gap(s, p, grow, n, near);
    if (f) *f = hi;
    if (point) v3_copy(point, near);
    if (normal) v3_copy(normal, n);
    return 1;
}

int rod_surface_curvature(const rod_surface *s, const double p[3], const double n[3], double grow,
                          double hessian[9])
{
    double axis[3] = {0.0, 0.0, 0.0}, radius = 0.0;
    int along = 0; /* 1: a cylinder's side or an edge (no curvature along axis) */
    switch (s->shape) {
    case ROD_SURFACE_PLANE:
        break;
    case ROD_SURFACE_MESH: /* flat faces; edges and vertices grown round by `grow` */
        return rod_mesh_curvature(s->mesh, p, hessian);
    case ROD_SURFACE_SPHERE:
        radius = s->size[0] + grow;
        break;
    case ROD_SURFACE_CYLINDER:
        radius = s->size[0] + grow;
        v3_copy(axis, s->normal);
        along = 1;
        break;
    case ROD_SURFACE_BOX:
    default: {
        /* the rounded part: two axes out of the box's extent (an edge, along
         * the third) or three (a corner) */
        int out = 0, in = 0;
        for (int k = 0; k < 3; k++) {
            if (fabs(p[k] - s->center[k]) > box_half(s, k)) out++;
            else in = k;
        }
        if (out >= 2) radius = grow + s->rounding;
        if (out == 2) {
            axis[in] = 1.0;
            along = 1;
        }
        break;
    }
    }
    if (!(radius > 0.0)) {
        memset(hessian, 0, 9 * sizeof(double));
        return 0;
    }
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            hessian[3 * i + j] = ((i == j) - n[i] * n[j] - (along ? axis[i] * axis[j] : 0.0)) / radius;
    return 1;
}

const rod_surface *rod_surface_contact_view(const rod_surface *s, rod_surface *scratch)
{
    if (!s->solid || !s->mesh) return s;
    *scratch = *s;
    scratch->shape = ROD_SURFACE_MESH;
    return scratch;
}

static int finite3(const double a[3])
{
    return isfinite(a[0]) && isfinite(a[1]) && isfinite(a[2]);
}

int rod_surface_check(rod_surface *s, char *err, size_t errlen)
{
    if (!finite3(s->center)) {
        snprintf(err, errlen, "center: must be 3 finite numbers, m");
        return -1;
    }
    if (!(s->friction >= 0.0) || !isfinite(s->friction)) {
        snprintf(err, errlen, "friction: must be a Coulomb coefficient >= 0 (0: frictionless)");
        return -1;
    }
    if (s->shape == ROD_SURFACE_PLANE || s->shape == ROD_SURFACE_CYLINDER) {
        double len = v3_norm(s->normal);
        /* a length that overflows (1e308 1e308 0) or underflows would scale
         * the normal to 0 or leave it off unit length */
        if (!finite3(s->normal) || !(len >= 1e-150 && len <= 1e150)) {
            snprintf(err, errlen, "normal: must be a direction: 3 numbers, not all 0, of length "
                     "1e-150 to 1e150 (it is normalised; e.g. 0 0 1) (the %s)",
                     s->shape == ROD_SURFACE_PLANE ? "plane's outward normal"
                                                   : "cylinder's axis direction");
            return -1;
        }
        v3_scale(s->normal, s->normal, 1.0 / len);
    }
    if (s->shape == ROD_SURFACE_MESH && !s->mesh) {
        snprintf(err, errlen, "file: a mesh needs its triangles: file = FILE.stl");
        return -1;
    }
    if (s->shape == ROD_SURFACE_BOX) {
        for (int k = 0; k < 3; k++)
            if (!(s->size[k] > 0.0) || !isfinite(s->size[k])) {
                snprintf(err, errlen, "size: a box needs 3 edge lengths x y z > 0 m (edge %c is "
                         "%g)", "xyz"[k], s->size[k]);
                return -1;
            }
        const double least = fmin(s->size[0], fmin(s->size[1], s->size[2]));
        if (!(s->rounding >= 0.0 && s->rounding < 0.5 * least)) {
            snprintf(err, errlen, "rounding: a box's edges are rounded by a radius from 0 m up "
                     "to less than half its shortest edge (%g m), not %g", 0.5 * least,
                     s->rounding);
            return -1;
        }
    } else if (s->rounding != 0.0) {
        snprintf(err, errlen, "rounding: only a box has edges to round (this is a %s); remove "
                 "the key", rod_surface_name(s->shape));
        return -1;
    } else if (s->shape == ROD_SURFACE_CYLINDER || s->shape == ROD_SURFACE_SPHERE) {
        if (!(s->size[0] > 0.0) || !isfinite(s->size[0])) {
            snprintf(err, errlen, "size: a %s needs its radius > 0 m (one number)",
                     rod_surface_name(s->shape));
            return -1;
        }
    }
    return 0;
}
