/* cutaway.c: the tissue drawn cut open along a plane (cutaway.h). */
#include "render/cutaway.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "render/geometry.h"

/* ------------------------------------------------------------------ the plane */

/* The direction from the scene towards the eye the options give. */
static void eye_direction(const render_options *o, const double point[3], double out[3])
{
    const render_shot *k = &o->camera_keys;
    if (k->has_eye) v3_sub(out, k->eye, point);
    else if (k->has_view) v3_copy(out, k->view);
    else v3_copy(out, o->view);
}

/* The frame whose punctures are the most (the first such); -1: none has any. */
static int stitch_frame(const rod_recording *rec)
{
    int best = -1, most = 0;
    for (int f = 0; f < rec->frame_count; f++) {
        const double *points;
        int count = rod_recording_punctures(rec, f, &points);
        if (count > most) most = count, best = f;
    }
    return best;
}

/* The upright plane (holding z) that best fits the punctures (count >= 1)
 * seen from above: through their centroid, along the principal axis of
 * their x y spread (the line fitted by total least squares). 0, or -1 when
 * they fix no such plane (one point, or all at one x y). */
static int stitch_plane(const double *points, int count, double point[3], double normal[3])
{
    v3_set(point, 0, 0, 0);
    for (int i = 0; i < count; i++) v3_axpy(point, 1.0 / count, &points[3 * i]);
    double xx = 0, xy = 0, yy = 0;
    for (int i = 0; i < count; i++) {
        double dx = points[3 * i] - point[0], dy = points[3 * i + 1] - point[1];
        xx += dx * dx, xy += dx * dy, yy += dy * dy;
    }
    if (!(xx + yy > 0)) return -1;
    double angle = 0.5 * atan2(2 * xy, xx - yy);
    v3_set(normal, -sin(angle), cos(angle), 0);
    return 0;
}

void cutaway_resolve(cutaway_plane *c, const rod_recording *rec, const render_options *o)
{
    memset(c, 0, sizeof *c);
    if (o->cutaway == RENDER_CUTAWAY_NO) return;
    if (o->cutaway == RENDER_CUTAWAY_PLANE) {
        v3_copy(c->point, o->cutaway_plane);
        v3_scale(c->normal, &o->cutaway_plane[3], 1 / v3_norm(&o->cutaway_plane[3]));
        c->on = 1;
        return;
    }
    int f = stitch_frame(rec), placed = -1;
    if (f >= 0) {
        const double *points;
        int count = rod_recording_punctures(rec, f, &points);
        placed = stitch_plane(points, count, c->point, c->normal);
    }
    double toward[3];
    if (placed) {
        /* no stitch: across the first tissue, its centre, facing the eye horizontally */
        int k = 0;
        while (k < rec->surface_count && !rec->surfaces[k].tissue) k++;
        if (k == rec->surface_count) return; /* no tissue: nothing to cut */
        v3_copy(c->point, rec->surfaces[k].center);
        eye_direction(o, c->point, c->normal);
        c->normal[2] = 0;
        if (!(v3_norm(c->normal) > 0)) v3_set(c->normal, 0, -1, 0);
        v3_scale(c->normal, c->normal, 1 / v3_norm(c->normal));
    }
    eye_direction(o, c->point, toward);
    if (v3_dot(toward, c->normal) < 0) v3_scale(c->normal, c->normal, -1);
    c->on = 1;
}

/* ------------------------------------------------------------------ scratch */

cutaway_scratch *cutaway_scratch_create(void)
{
    cutaway_scratch *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    s->segment = malloc(CUTAWAY_MAX_SEGMENTS * 6 * sizeof(double));
    s->next = malloc(CUTAWAY_MAX_SEGMENTS * sizeof(int));
    s->loop = malloc(CUTAWAY_MAX_SEGMENTS * sizeof(int));
    s->flat = malloc(CUTAWAY_MAX_SEGMENTS * 2 * sizeof(double));
    s->top = malloc(CUTAWAY_MAX_SEGMENTS * 2 * sizeof(double));
    if (!s->segment || !s->next || !s->loop || !s->flat || !s->top) {
        cutaway_scratch_destroy(s);
        return NULL;
    }
    return s;
}

void cutaway_scratch_destroy(cutaway_scratch *s)
{
    if (!s) return;
    free(s->segment);
    free(s->next);
    free(s->loop);
    free(s->flat);
    free(s->top);
    free(s);
}

double cutaway_dermis(const double lo[3], const double hi[3])
{
    return fmin(CUTAWAY_DERMIS, 0.25 * (hi[2] - lo[2]));
}

/* ------------------------------------------------------------------ geometry */

static void vertex_position(const render_mesh *m, unsigned v, double p[3])
{
    for (int c = 0; c < 3; c++) p[c] = m->vertices[v].position[c];
}

/* Signed distance (m) of vertex v from the plane, > 0 on the side not drawn. */
static double side_of(const render_mesh *m, unsigned v, const cutaway_plane *c)
{
    double p[3];
    vertex_position(m, v, p);
    v3_sub(p, p, c->point);
    return v3_dot(p, c->normal);
}

/* Where the edge a b (signed distances da, db of opposite sides) meets the
 * plane: from the lesser vertex of the two, so that both triangles of an
 * edge find the same point. Into p; t the fraction from a to b. */
static double crossing(const render_mesh *m, unsigned a, unsigned b, double da, double db,
                       double p[3])
{
    int swap = memcmp(m->vertices[a].position, m->vertices[b].position, sizeof(float[3])) > 0;
    double pa[3], pb[3], t;
    vertex_position(m, swap ? b : a, pa);
    vertex_position(m, swap ? a : b, pb);
    t = swap ? db / (db - da) : da / (da - db);
    for (int c = 0; c < 3; c++) p[c] = pa[c] + t * (pb[c] - pa[c]);
    return swap ? 1 - t : t;
}

/* A new vertex on the edge a b where it meets the plane (normal and
 * colour interpolated); its index. */
static unsigned crossing_vertex(render_mesh *m, unsigned a, unsigned b, double da, double db)
{
    double p[3], n[3];
    double t = crossing(m, a, b, da, db, p);
    float color[3];
    for (int c = 0; c < 3; c++) {
        n[c] = (1 - t) * m->vertices[a].normal[c] + t * m->vertices[b].normal[c];
        color[c] = (float)((1 - t) * m->vertices[a].color[c] + t * m->vertices[b].color[c]);
    }
    double length = v3_norm(n);
    if (length > 0) v3_scale(n, n, 1 / length);
    return mesh_vertex(m, p, n, color);
}

void cutaway_clip(render_mesh *m, int first_index, const cutaway_plane *c)
{
    /* kept triangles are packed from first_index; a cut one's second half
     * goes after the end, then that tail moves down behind the packed ones */
    const int end = m->index_count;
    int w = first_index;
    for (int i = first_index; i < end; i += 3) {
        unsigned v[3] = {m->indices[i], m->indices[i + 1], m->indices[i + 2]};
        double d[3];
        int kept = 0;
        for (int k = 0; k < 3; k++) kept += (d[k] = side_of(m, v[k], c)) <= 0;
        if (kept == 0) continue;
        if (kept == 3) {
            memmove(&m->indices[w], v, sizeof v);
            w += 3;
            continue;
        }
        if (m->vertex_count + 2 > m->max_vertices) continue; /* sized by the caller */
        unsigned poly[4];
        int count = 0;
        for (int k = 0; k < 3; k++) {
            int next = (k + 1) % 3;
            if (d[k] <= 0) poly[count++] = v[k];
            if ((d[k] <= 0) != (d[next] <= 0))
                poly[count++] = crossing_vertex(m, v[k], v[next], d[k], d[next]);
        }
        m->indices[w++] = poly[0];
        m->indices[w++] = poly[1];
        m->indices[w++] = poly[2];
        if (count == 4 && m->index_count + 3 <= m->max_indices) {
            m->indices[m->index_count++] = poly[0];
            m->indices[m->index_count++] = poly[2];
            m->indices[m->index_count++] = poly[3];
        }
    }
    int tail = m->index_count - end;
    memmove(&m->indices[w], &m->indices[end], (size_t)tail * sizeof(unsigned));
    m->index_count = w + tail;
}

/* ------------------------------------------------------------------ the cap */

/* The section of the triangles from first_index: a segment per triangle
 * the plane crosses, oriented so that the surface's outside is on its
 * right seen from the normal's side (a cap's loop then runs counter-
 * clockwise). Their count, or -1 when more than the scratch holds. */
static int section_segments(const render_mesh *m, int first_index, const cutaway_plane *c,
                            cutaway_scratch *s)
{
    int count = 0;
    for (int i = first_index; i < m->index_count; i += 3) {
        const unsigned *v = &m->indices[i];
        double d[3];
        int removed = 0;
        for (int k = 0; k < 3; k++) removed += (d[k] = side_of(m, v[k], c)) > 0;
        if (removed == 0 || removed == 3) continue;
        if (count == CUTAWAY_MAX_SEGMENTS) return -1;
        double *seg = &s->segment[6 * count], *end = seg;
        for (int k = 0; k < 3; k++) {
            int next = (k + 1) % 3;
            if ((d[k] > 0) != (d[next] > 0)) {
                crossing(m, v[k], v[next], d[k], d[next], end);
                end += 3;
            }
        }
        double a[3], b[3], ab[3], ac[3], face[3], along[3], run[3];
        vertex_position(m, v[0], a);
        vertex_position(m, v[1], b);
        v3_sub(ab, b, a);
        vertex_position(m, v[2], b);
        v3_sub(ac, b, a);
        v3_cross(face, ab, ac);
        v3_cross(along, c->normal, face);
        v3_sub(run, &seg[3], seg);
        if (!(v3_norm(run) > 0)) continue; /* through a vertex only */
        if (v3_dot(run, along) < 0) {
            double keep[3];
            v3_copy(keep, seg);
            v3_copy(seg, &seg[3]);
            v3_copy(&seg[3], keep);
        }
        count++;
    }
    return count;
}

/* Links each segment to the one starting where it ends (within tol, m). */
static void link_segments(cutaway_scratch *s, int count, double tol)
{
    for (int i = 0; i < count; i++) {
        s->next[i] = -1;
        double best = tol;
        for (int j = 0; j < count; j++) {
            if (j == i) continue;
            double gap[3];
            v3_sub(gap, &s->segment[6 * j], &s->segment[6 * i + 3]);
            double g = v3_norm(gap);
            if (g <= best) best = g, s->next[i] = j;
        }
    }
}

/* Twice the signed area of the flat triangle a b c (> 0: counter-clockwise). */
static double turn(const double *a, const double *b, const double *c)
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* Keeps the part of the polygon (count points, up to 8) where
 * dot(p, g) + offset <= 0; the points left. */
static int clip_half(double (*poly)[3], int count, const double g[3], double offset)
{
    double out[8][3], value[8];
    int kept = 0;
    for (int k = 0; k < count; k++) value[k] = v3_dot(poly[k], g) + offset;
    for (int k = 0; k < count && kept < 7; k++) {
        int next = (k + 1) % count;
        if (value[k] <= 0) v3_copy(out[kept++], poly[k]);
        if ((value[k] <= 0) != (value[next] <= 0)) {
            double t = value[k] / (value[k] - value[next]);
            for (int c = 0; c < 3; c++) out[kept][c] = poly[k][c] + t * (poly[next][c] - poly[k][c]);
            kept++;
        }
    }
    memcpy(poly, out, (size_t)kept * sizeof out[0]);
    return kept;
}

/* One piece of the cap (a convex polygon in the plane) in one colour. */
static void cap_piece(render_mesh *m, double (*poly)[3], int count, const cutaway_plane *c,
                      const float color[3])
{
    if (count < 3 || m->vertex_count + count > m->max_vertices) return;
    unsigned first = (unsigned)m->vertex_count;
    for (int k = 0; k < count; k++) mesh_vertex(m, poly[k], c->normal, color);
    for (int k = 1; k + 1 < count; k++)
        mesh_triangle(m, first, first + (unsigned)k, first + (unsigned)k + 1);
}

/* One cap triangle (points in the plane, m), cut along the strips of the
 * skin's top (s->top) where the dermis meets the subcutis, `dermis` (m)
 * below it: each strip's part above that line in the dermis's colour,
 * below it in the subcutis's. */
static void cap_triangle(render_mesh *m, const cutaway_scratch *s, const double *p0,
                         const double *p1, const double *p2, const cutaway_plane *c,
                         double dermis)
{
    const double *corner[3] = {p0, p1, p2};
    const double *across = s->across, z[3] = {0, 0, 1};
    double lo = INFINITY, hi = -INFINITY;
    for (int k = 0; k < 3; k++) {
        lo = fmin(lo, v3_dot(corner[k], across));
        hi = fmax(hi, v3_dot(corner[k], across));
    }
    /* strip i runs from top point i - 1 to i (the first and last unbounded,
     * the top level there) */
    for (int i = 0; i <= s->top_count; i++) {
        const double *left = i > 0 ? &s->top[2 * (i - 1)] : NULL;
        const double *right = i < s->top_count ? &s->top[2 * i] : NULL;
        if ((left && left[0] >= hi) || (right && right[0] <= lo)) continue;
        double poly[8][3];
        int count = 3;
        for (int k = 0; k < 3; k++) v3_copy(poly[k], corner[k]);
        double minus[3];
        v3_scale(minus, across, -1);
        if (left) count = clip_half(poly, count, minus, left[0]);
        if (right && count >= 3) count = clip_half(poly, count, across, -right[0]);
        if (count < 3) continue;
        /* the line z = level + slope u through the strip, dermis below the top */
        const double *a = left ? left : right, *b = right ? right : left;
        double slope = b[0] > a[0] ? (b[1] - a[1]) / (b[0] - a[0]) : 0;
        double level = a[1] - dermis - slope * a[0], g[3];
        for (int k = 0; k < 3; k++) g[k] = z[k] - slope * across[k];
        double lower[8][3];
        memcpy(lower, poly, sizeof poly);
        int below = clip_half(lower, count, g, -level);
        cap_piece(m, lower, below, c, render_subcutis_color);
        double up[3];
        v3_scale(up, g, -1);
        int above = clip_half(poly, count, up, level);
        cap_piece(m, poly, above, c, render_dermis_color);
    }
}

/* The skin's top along the section into s->top: the upper envelope of the
 * segments whose outside faces up (more than 30 degrees above the
 * horizontal), over u (m) along s->across, the plane's horizontal; a gap
 * between them (the wound's mouth) bridged straight; points in a line
 * dropped. A plane near the horizontal: one level, the section's top. */
static void skin_top(cutaway_scratch *s, int count, const cutaway_plane *c)
{
    const double z[3] = {0, 0, 1};
    v3_cross(s->across, z, c->normal);
    double length = v3_norm(s->across);
    int n = 0;
    double *top = s->top, highest = -INFINITY;
    for (int i = 0; i < 2 * count; i++) highest = fmax(highest, s->segment[3 * i + 2]);
    if (length < 0.1) {
        /* within 6 degrees of the horizontal: the highest point's level */
        perpendicular_basis(c->normal, s->across, top);
        top[0] = 0;
        top[1] = highest;
        s->top_count = 1;
        return;
    }
    v3_scale(s->across, s->across, 1 / length);
    for (int i = 0; i < count && n < CUTAWAY_MAX_SEGMENTS; i++) {
        const double *a = &s->segment[6 * i], *b = a + 3;
        double run[3], outside[3];
        v3_sub(run, b, a);
        v3_cross(outside, run, c->normal);
        if (!(outside[2] > 0.5 * v3_norm(outside))) continue;
        for (int e = 0; e < 2 && n < CUTAWAY_MAX_SEGMENTS; e++) {
            top[2 * n] = v3_dot(e ? b : a, s->across);
            n++;
        }
    }
    /* sorted along u, one point per u, each the highest of the faces up there */
    for (int i = 1; i < n; i++)
        for (int j = i; j > 0 && top[2 * j] < top[2 * (j - 1)]; j--) {
            double keep = top[2 * j];
            top[2 * j] = top[2 * (j - 1)];
            top[2 * (j - 1)] = keep;
        }
    int unique = 0;
    for (int i = 0; i < n; i++)
        if (unique == 0 || top[2 * i] > top[2 * (unique - 1)] + 1e-9) top[2 * unique++] = top[2 * i];
    for (int i = 0; i < unique; i++) {
        double u = top[2 * i], best = -INFINITY;
        for (int k = 0; k < count; k++) {
            const double *a = &s->segment[6 * k], *b = a + 3;
            double run[3], outside[3];
            v3_sub(run, b, a);
            v3_cross(outside, run, c->normal);
            if (!(outside[2] > 0.5 * v3_norm(outside))) continue;
            double ua = v3_dot(a, s->across), ub = v3_dot(b, s->across);
            if (u < fmin(ua, ub) - 1e-9 || u > fmax(ua, ub) + 1e-9) continue;
            double t = ub != ua ? (u - ua) / (ub - ua) : 0;
            best = fmax(best, a[2] + fmin(1, fmax(0, t)) * (b[2] - a[2]));
        }
        top[2 * i + 1] = best;
    }
    /* points on the line through their neighbours (within a micrometre) add nothing */
    n = unique;
    for (int i = 1; i + 1 < n;) {
        const double *a = &top[2 * (i - 1)], *p = &top[2 * i], *b = &top[2 * (i + 1)];
        double on = a[1] + (p[0] - a[0]) * (b[1] - a[1]) / (b[0] - a[0]);
        if (fabs(p[1] - on) < 1e-6) {
            memmove(&top[2 * i], &top[2 * (i + 1)], (size_t)(n - i - 1) * 2 * sizeof(double));
            n--;
        } else {
            i++;
        }
    }
    if (n == 0) {
        top[0] = 0;
        top[1] = highest;
        n = 1;
    }
    s->top_count = n;
}

/* Fills one loop (its segments s->loop[0 .. count), each segment's first
 * end a corner, counter-clockwise in the plane's basis e1 e2) by ear
 * clipping: corners in a line dropped first, then an ear (a convex corner
 * whose triangle holds no other corner) cut off at a time; a loop with no
 * ear (one that touches itself) loses its most convex corner. */
static void fill_loop(render_mesh *m, cutaway_scratch *s, int count, const double e1[3],
                      const double e2[3], const cutaway_plane *c, double dermis)
{
    if (count > CUTAWAY_MAX_SEGMENTS / 2) return; /* too long a loop to fill */
    const int *order = s->loop;
    int *left = &s->loop[CUTAWAY_MAX_SEGMENTS / 2]; /* the corners left, into flat */
    double *flat = s->flat, area = 0, lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int k = 0; k < count; k++) {
        double d[3];
        v3_sub(d, &s->segment[6 * order[k]], c->point);
        flat[2 * k] = v3_dot(d, e1);
        flat[2 * k + 1] = v3_dot(d, e2);
        for (int q = 0; q < 2; q++) lo[q] = fmin(lo[q], flat[2 * k + q]), hi[q] = fmax(hi[q], flat[2 * k + q]);
    }
    for (int k = 0; k < count; k++) {
        const double *a = &flat[2 * k], *b = &flat[2 * ((k + 1) % count)];
        area += a[0] * b[1] - a[1] * b[0];
    }
    if (!(area > 0)) return; /* a hole's loop (clockwise): not filled */
    const double span = fmax(hi[0] - lo[0], hi[1] - lo[1]), tol = 1e-9 * span * span;
    int n = count;
    for (int k = 0; k < n; k++) left[k] = k;
    for (int i = 0; i < n && n > 3;) {
        const double *a = &flat[2 * left[(i + n - 1) % n]], *b = &flat[2 * left[i]],
                     *d = &flat[2 * left[(i + 1) % n]];
        if (fabs(turn(a, b, d)) <= tol) {
            memmove(&left[i], &left[i + 1], (size_t)(n - i - 1) * sizeof(int));
            n--;
            i = i > 0 ? i - 1 : 0;
        } else {
            i++;
        }
    }
    while (n >= 3) {
        int chosen = -1, convex = 0;
        double most = -INFINITY;
        for (int i = 0; i < n && chosen < 0; i++) {
            const double *a = &flat[2 * left[(i + n - 1) % n]], *b = &flat[2 * left[i]],
                         *d = &flat[2 * left[(i + 1) % n]];
            double t = turn(a, b, d);
            if (t > most) most = t, convex = i;
            if (!(t > tol)) continue;
            int inside = 0;
            for (int j = 0; j < n && !inside; j++) {
                const double *q = &flat[2 * left[j]];
                if (q == a || q == b || q == d) continue;
                inside = turn(a, b, q) > tol && turn(b, d, q) > tol && turn(d, a, q) > tol;
            }
            if (!inside) chosen = i;
        }
        if (chosen < 0) chosen = convex;
        const double *p[3];
        for (int k = 0; k < 3; k++) p[k] = &s->segment[6 * order[left[(chosen + n - 1 + k) % n]]];
        cap_triangle(m, s, p[0], p[1], p[2], c, dermis);
        memmove(&left[chosen], &left[chosen + 1], (size_t)(n - chosen - 1) * sizeof(int));
        n--;
    }
}

void cutaway_cut(render_mesh *m, int first_index, const cutaway_plane *c, double dermis,
                 cutaway_scratch *s)
{
    /* the section first, then the cut (its new triangles lie on the plane),
     * then the cap */
    int count = s ? section_segments(m, first_index, c, s) : -1;
    cutaway_clip(m, first_index, c);
    if (count <= 0) return;
    /* the loops' points meet within a millionth of the surface's size */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < 2 * count; i++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], s->segment[3 * i + k]);
            hi[k] = fmax(hi[k], s->segment[3 * i + k]);
        }
    double size = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
    link_segments(s, count, 1e-6 * size + 1e-12);
    skin_top(s, count, c);
    double e1[3], e2[3];
    perpendicular_basis(c->normal, e1, e2);
    /* each loop once: a segment's next set to -2 once taken */
    for (int start = 0; start < count; start++) {
        if (s->next[start] < 0) continue;
        int length = 0, at = start, closed = 0;
        int *order = s->loop;
        while (at >= 0 && length < count) {
            order[length++] = at;
            int next = s->next[at];
            s->next[at] = -2;
            if (next == start) {
                closed = 1;
                break;
            }
            at = next;
        }
        if (closed && length >= 3) fill_loop(m, s, length, e1, e2, c, dermis);
    }
}
