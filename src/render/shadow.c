/* shadow.c: the receivers and the shadow map's light (shadow.h). */
#include "render/shadow.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "render/geometry.h"
#include "render/mesh.h"
#include "render/surface.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define PLANE_FADE_START 1.5  /* a plane fades out from this many motion sizes from its centre ... */
#define PLANE_FADE_END 3.0    /* ... to this many: a large finite floor, never the framing */
/* texels a side: at most 512 (2 mm for a 1 m motion), fewer when two
 * thirds of the visual radius need fewer (the depth pass's cost is its
 * area). Each look-up is one bilinear comparison, whose soft edge is two
 * texels wide: with four comparisons on a map of texels half the size
 * suture.ini's run with its video took 6.8 s of CPU against 5.9, for the
 * same picture (docs/decisions/0105-video-speed.md). */
#define SHADOW_MAP_MAX 512
#define SHADOW_MAP_MIN 128

/* The motion's bounds: the point cloud of the casters (nodes, glyphs,
 * arrows), padded. 0, or -1 when out of memory. */
static int content_bounds(const rod_recording *rec, const render_options *o, double radius,
                          double lo[3], double hi[3])
{
    arrow_scales arrows;
    arrow_scales_compute(&arrows, rec, radius, o->arrows);
    point_cloud pc;
    if (point_cloud_create(&pc, rec, o, radius, &arrows)) return -1;
    for (int c = 0; c < 3; c++) lo[c] = INFINITY, hi[c] = -INFINITY;
    for (int i = 0; i < pc.count; i++)
        for (int c = 0; c < 3; c++) {
            lo[c] = fmin(lo[c], pc.points[3 * i + c] - pc.pad);
            hi[c] = fmax(hi[c], pc.points[3 * i + c] + pc.pad);
        }
    free(pc.points);
    return pc.count > 0 ? 0 : -1;
}

/* Decision: the ground lies across the distributed load's direction
 * (gravity's, when that is the load), a visual radius below the lowest point
 * the run reaches (tube surface and glyphs included), so the shadow meets
 * the rod where it comes lowest. auto draws it when such a load acts, no
 * plane surface is given (the plane is the floor then) and the camera looks
 * at its top side from at least 6 degrees above. */
int render_ground_plane(const rod_recording *rec, const render_options *o, double point[3],
                        double normal[3])
{
    double load = v3_norm(rec->distributed_force);
    if (o->ground == RENDER_GROUND_NO || !(load > 0) || rec->frame_count <= 0) return 0;
    double down[3], back[3], right[3], up[3];
    v3_scale(down, rec->distributed_force, 1 / load);
    camera_basis(o->view, back, right, up);
    if (o->ground == RENDER_GROUND_AUTO) {
        for (int k = 0; k < rec->surface_count; k++)
            if (rec->surfaces[k].shape == RECORDING_SURFACE_PLANE) return 0;
        if (-v3_dot(back, down) < sin(6 * M_PI / 180)) return 0;
    }
    double radius = render_visual_radius(rec, o), lowest = -INFINITY;
    for (int f = 0; f < rec->frame_count; f++) {
        for (int k = 0; k < rec->nodes; k++)
            lowest = fmax(lowest, v3_dot(node_position(rec, f, k), down) + radius);
        for (int end = 0; end < 2; end++) {
            double glyph[3 * GLYPH_MAX_POINTS], pad;
            int chain, count = glyph_points(rec, o, radius, f, end, glyph, &pad, &chain);
            for (int i = 0; i < count; i++)
                lowest = fmax(lowest, v3_dot(&glyph[3 * i], down) + pad);
        }
    }
    v3_scale(normal, down, -1);
    v3_scale(point, down, lowest + radius);
    return 1;
}

static void catcher_slab(shadow_catcher *k, const double point[3], const double n[3], double half)
{
    k->count = 2;
    v3_copy(k->normal[0], n);
    k->offset[0] = v3_dot(n, point) + half;
    v3_scale(k->normal[1], n, -1);
    k->offset[1] = -v3_dot(n, point) + half;
}

static void catcher_box(shadow_catcher *k, const double lo[3], const double hi[3])
{
    k->count = 6;
    for (int c = 0; c < 3; c++) {
        v3_set(k->normal[2 * c], 0, 0, 0);
        v3_set(k->normal[2 * c + 1], 0, 0, 0);
        k->normal[2 * c][c] = 1;
        k->offset[2 * c] = hi[c];
        k->normal[2 * c + 1][c] = -1;
        k->offset[2 * c + 1] = -lo[c];
    }
}

int shadow_clip_polygon(double *poly, int count, const shadow_catcher *k)
{
    double work[3 * 16];
    for (int h = 0; h < k->count && count > 0; h++) {
        int kept = 0;
        for (int i = 0; i < count; i++) {
            const double *a = &poly[3 * i], *b = &poly[3 * ((i + 1) % count)];
            double da = v3_dot(k->normal[h], a) - k->offset[h];
            double db = v3_dot(k->normal[h], b) - k->offset[h];
            if (da <= 0 && kept < 16) v3_copy(&work[3 * kept++], a);
            if ((da < 0 && db > 0) || (da > 0 && db < 0)) {
                double t = da / (da - db), *p = &work[3 * kept];
                if (kept >= 16) continue;
                for (int c = 0; c < 3; c++) p[c] = a[c] + t * (b[c] - a[c]);
                kept++;
            }
        }
        memcpy(poly, work, (size_t)kept * 3 * sizeof(double));
        count = kept;
    }
    return count;
}

void receiver_plan_make(receiver_plan *p, const rod_recording *rec, const render_options *o,
                        double radius)
{
    memset(p, 0, sizeof *p);
    p->have_bounds = content_bounds(rec, o, radius, p->lo, p->hi) == 0;
    p->ground = p->have_bounds && render_ground_plane(rec, o, p->ground_point, p->ground_normal);
    p->radius = radius;
    p->pad = STRIPE_LIFT * radius;
    p->length = rec->length;
}

/* The vertices of the convex set n_k . p <= offset_k (count planes, up to
 * 12) into out (up to 220 points): every point where three of the planes
 * meet that lies inside the others. Returns how many. */
static int polytope_vertices(const double (*n)[3], const double *offset, int count, double *out)
{
    int found = 0;
    for (int a = 0; a < count; a++)
        for (int b = a + 1; b < count; b++)
            for (int c = b + 1; c < count; c++) {
                /* p = (offset_a (n_b x n_c) + offset_b (n_c x n_a) + offset_c (n_a x n_b)) / det */
                double bc[3], ca[3], ab[3];
                v3_cross(bc, n[b], n[c]);
                v3_cross(ca, n[c], n[a]);
                v3_cross(ab, n[a], n[b]);
                const double det = v3_dot(n[a], bc);
                if (fabs(det) < 1e-9) continue;
                double p[3];
                for (int i = 0; i < 3; i++)
                    p[i] = (offset[a] * bc[i] + offset[b] * ca[i] + offset[c] * ab[i]) / det;
                int inside = 1;
                for (int k = 0; k < count && inside; k++)
                    inside = v3_dot(n[k], p) <= offset[k] + 1e-9 * (1 + fabs(offset[k]));
                if (inside) v3_copy(&out[3 * found++], p);
            }
    return found;
}

/* The six half-spaces of what the camera draws (its frustum, or the
 * orthographic box), read off its matrices (camera_matrices). */
static void view_planes(const render_camera *cam, double (*n)[3], double *offset)
{
    const double *p = cam->projection, *back = cam->direction;
    double near, far;
    if (cam->orthographic) {
        const double span = -2.0 / p[10], sum = -p[14] * span;
        near = 0.5 * (sum - span), far = 0.5 * (sum + span);
    } else {
        near = p[14] / (p[10] - 1.0), far = p[14] / (p[10] + 1.0);
    }
    /* across: |right . (q - eye)| <= w, |up . (q - eye)| <= h, w and h
     * constant (orthographic) or growing with the depth -back . (q - eye) */
    const double *axis[2] = {cam->right, cam->up};
    const double half[2] = {1.0 / p[0], 1.0 / p[5]};
    for (int k = 0; k < 2; k++)
        for (int side = 0; side < 2; side++) {
            double *m = n[2 * k + side];
            const double sign = side ? -1.0 : 1.0;
            for (int c = 0; c < 3; c++)
                m[c] = sign * axis[k][c] + (cam->orthographic ? 0.0 : half[k] * back[c]);
            offset[2 * k + side] = v3_dot(m, cam->eye) + (cam->orthographic ? half[k] : 0.0);
        }
    /* in depth: near <= -back . (q - eye) <= far */
    for (int c = 0; c < 3; c++) n[4][c] = back[c], n[5][c] = -back[c];
    offset[4] = v3_dot(back, cam->eye) - near;
    offset[5] = -v3_dot(back, cam->eye) + far;
}

int shadow_fit(shadow_scene *s, gl_renderer *gl, const render_camera *cam, double radius,
               const double *own_lo, const double *own_hi, char *err, size_t errlen)
{
    double lo[3], hi[3];
    for (int a = 0; a < 3; a++) lo[a] = s->light_lo[a], hi[a] = s->light_hi[a];
    double n[12][3], offset[12], points[3 * 220];
    view_planes(cam, n, offset);
    double seen_lo[2] = {INFINITY, INFINITY}, seen_hi[2] = {-INFINITY, -INFINITY};
    /* the rod shadows itself: inside this frame's box (own_lo, own_hi), or
     * the world box around the light's box over the whole run */
    shadow_catcher own;
    if (own_lo) {
        catcher_box(&own, own_lo, own_hi);
    } else {
        double box_lo[3], box_hi[3];
        for (int c = 0; c < 3; c++) box_lo[c] = INFINITY, box_hi[c] = -INFINITY;
        for (int corner = 0; corner < 8; corner++)
            for (int c = 0; c < 3; c++) {
                double q = 0;
                for (int a = 0; a < 3; a++)
                    q += (corner >> a & 1 ? s->light_hi[a] : s->light_lo[a]) * s->light_basis[a][c];
                box_lo[c] = fmin(box_lo[c], q);
                box_hi[c] = fmax(box_hi[c], q);
            }
        catcher_box(&own, box_lo, box_hi);
    }
    for (int k = 0; k <= s->catcher_count; k++) {
        const shadow_catcher *catcher = k < s->catcher_count ? &s->catchers[k] : &own;
        for (int j = 0; j < catcher->count; j++) {
            v3_copy(n[6 + j], catcher->normal[j]);
            offset[6 + j] = catcher->offset[j];
        }
        const int count = polytope_vertices((const double (*)[3])n, offset, 6 + catcher->count,
                                            points);
        for (int i = 0; i < count; i++)
            for (int a = 0; a < 2; a++) {
                const double q = v3_dot(&points[3 * i], s->light_basis[a]);
                seen_lo[a] = fmin(seen_lo[a], q);
                seen_hi[a] = fmax(seen_hi[a], q);
            }
    }
    /* the soft edges' filter reaches past what is seen by 1.5 texels at
     * most, and the looked-up point moves by its offset: 3 of the whole
     * box's texels bound both, whatever the fitted texel */
    const double whole = fmax(hi[0] - lo[0], hi[1] - lo[1]);
    const double reach = 0.5 * radius + 3.0 * whole / s->map_size;
    for (int a = 0; a < 2; a++) {
        if (seen_lo[a] <= seen_hi[a]) {
            lo[a] = fmax(lo[a], seen_lo[a] - reach);
            hi[a] = fmin(hi[a], seen_hi[a] + reach);
        }
        if (!(lo[a] < hi[a])) hi[a] = lo[a] + s->thinnest; /* nothing seen: any small box */
    }
    /* square texels: the longer side sets the scale */
    const double extent = fmax(hi[0] - lo[0], hi[1] - lo[1]);
    for (int a = 0; a < 2; a++) {
        double middle = 0.5 * (lo[a] + hi[a]);
        lo[a] = middle - 0.5 * extent;
        hi[a] = middle + 0.5 * extent;
    }
    const double *e1 = s->light_basis[0], *e2 = s->light_basis[1], *key = s->light_basis[2];
    double light[16] = {0};
    for (int c = 0; c < 3; c++) {
        light[4 * c + 0] = 2 * e1[c] / extent;
        light[4 * c + 1] = 2 * e2[c] / extent;
        light[4 * c + 2] = -2 * key[c] / (hi[2] - lo[2]); /* depth grows away from the light */
    }
    light[12] = -2 * lo[0] / extent - 1;
    light[13] = -2 * lo[1] / extent - 1;
    light[14] = 2 * hi[2] / (hi[2] - lo[2]) - 1;
    light[15] = 1;
    const double texel = extent / s->map_size;
    if (gl_renderer_set_shadows(gl, light, s->map_size, 1.5 * texel, err, errlen)) return -1;
    /* the soft edge (one bilinear comparison) reaches a texel past the
     * caster's, the look-up's offset and a margin 3 more */
    s->shadow_pad = 4 * texel;
    return 0;
}

/* The planes' receivers (the ground first) and their catchers: one fade
 * about the motion's centre, sized for the nearest plane's distance from
 * it, which is returned (m; INFINITY: no plane). */
static double receiver_planes(shadow_scene *s, render_mesh *m, const receiver_plan *plan,
                              const rod_recording *rec, const double centre[3], double size)
{
    int surfaces = rec->surfaces ? rec->surface_count : 0;
    double plane_distance = INFINITY;
    const float *ground_color = render_surface_color;
    for (int pass = 0; pass < 2; pass++) {
        for (int k = -1; k < surfaces; k++) {
            const double *point, *n;
            const float *color;
            if (k < 0) {
                if (!plan->ground) continue;
                point = plan->ground_point;
                n = plan->ground_normal;
                color = ground_color;
            } else {
                if (rec->surfaces[k].shape != RECORDING_SURFACE_PLANE) continue;
                point = rec->surfaces[k].center;
                n = rec->surfaces[k].normal;
                color = rec->surfaces[k].tissue ? render_skin_color : render_surface_color;
            }
            double to[3];
            v3_sub(to, centre, point);
            double h = fabs(v3_dot(to, n));
            if (pass == 0) {
                plane_distance = fmin(plane_distance, h);
                continue;
            }
            surface_add_plane(m, point, n, centre, PLANE_FADE_END * size + h, color);
            if (s->catcher_count < ROD_MAX_SURFACES_DRAWN + 1) {
                shadow_catcher *c = &s->catchers[s->catcher_count++];
                catcher_slab(c, point, n, plan->pad);
                c->stretch = 1 / fmax(fabs(v3_dot(n, s->key)), 0.25);
            }
        }
    }
    return plane_distance;
}

/* The solids' receivers (boxes, spheres, the drawn piece of a cylinder)
 * and their catchers. */
static void receiver_solids(shadow_scene *s, render_mesh *m, const receiver_plan *plan,
                            const rod_recording *rec, double size, cutaway_scratch *cut)
{
    int surfaces = rec->surfaces ? rec->surface_count : 0;
    for (int k = 0; k < surfaces; k++) {
        const recording_surface *sf = &rec->surfaces[k];
        const float *color = sf->tissue ? render_skin_color : render_surface_color;
        double lo[3], hi[3];
        const int first = m->index_count;
        if (sf->pad_node_count > 0) continue; /* an elastic pad: drawn each frame (renderer.c) */
        switch (sf->shape) {
        case RECORDING_SURFACE_BOX: {
            double axes[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
            double half[3] = {0.5 * sf->size[0], 0.5 * sf->size[1], 0.5 * sf->size[2]};
            if (sf->rounding > 0) mesh_rounded_block(m, sf->center, half, sf->rounding, color);
            else mesh_block(m, sf->center, axes, half, color);
            surface_bounds(sf, lo, hi);
            break;
        }
        case RECORDING_SURFACE_MESH:
            if (surface_add_mesh(m, sf, color)) continue;
            surface_bounds(sf, lo, hi);
            break;
        case RECORDING_SURFACE_SPHERE:
            surface_add_sphere(m, sf->center, sf->size[0], color);
            surface_bounds(sf, lo, hi);
            break;
        case RECORDING_SURFACE_CYLINDER: {
            double middle[3], half;
            surface_cylinder_piece(sf, plan->lo, plan->hi, size, middle, &half);
            surface_add_cylinder(m, middle, sf->normal, sf->size[0], half, color);
            for (int c = 0; c < 3; c++) {
                double reach = half * fabs(sf->normal[c]) +
                               sf->size[0] * sqrt(fmax(0, 1 - sf->normal[c] * sf->normal[c]));
                lo[c] = middle[c] - reach;
                hi[c] = middle[c] + reach;
            }
            break;
        }
        default:
            continue;
        }
        if (plan->cut.on && sf->tissue) {
            /* cut open: its cap, and nothing on the eye's side */
            cutaway_cut(m, first, &plan->cut, cutaway_dermis(lo, hi), cut);
        }
        if (s->catcher_count < ROD_MAX_SURFACES_DRAWN + 1) {
            shadow_catcher *c = &s->catchers[s->catcher_count++];
            for (int a = 0; a < 3; a++) lo[a] -= plan->pad, hi[a] += plan->pad;
            catcher_box(c, lo, hi);
            c->stretch = 4; /* any face, any slant: a bound */
        }
    }
}

/* The light's orthographic box around the casters, seen along -key, and
 * the shadow map's size. */
static void shadow_light_box(shadow_scene *s, const receiver_plan *plan,
                             const rod_recording *rec, double size)
{
    /* the light's orthographic box around the casters, seen along -key */
    double e1[3], e2[3], lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    perpendicular_basis(s->key, e1, e2);
    const double *basis[3] = {e1, e2, s->key};
    for (int corner = 0; corner < 8; corner++) {
        double p[3];
        for (int c = 0; c < 3; c++) p[c] = corner >> c & 1 ? plan->hi[c] : plan->lo[c];
        for (int a = 0; a < 3; a++) {
            lo[a] = fmin(lo[a], v3_dot(p, basis[a]));
            hi[a] = fmax(hi[a], v3_dot(p, basis[a]));
        }
    }
    double margin = 0.02 * size, extent = 0;
    for (int a = 0; a < 3; a++) {
        lo[a] -= margin;
        hi[a] += margin;
        extent = fmax(extent, hi[a] - lo[a]);
        v3_copy(s->light_basis[a], basis[a]);
        s->light_lo[a] = lo[a];
        s->light_hi[a] = hi[a];
    }
    /* the thinnest caster (the tube, or the needle's wire) spans 1.5 texels
     * or more of the whole box; the map keeps this size when it is fitted to a
     * view (shadow_fit), whose texels are then finer */
    s->thinnest = rec->needle_radius > 0 ? fmin(plan->radius, glyph_needle_wire(rec, plan->radius))
                                         : plan->radius;
    s->map_size = SHADOW_MAP_MIN;
    while (s->map_size < SHADOW_MAP_MAX && extent / s->map_size > s->thinnest / 1.5)
        s->map_size *= 2;
}

int shadow_receivers(shadow_scene *s, gl_renderer *gl, const receiver_plan *plan,
                     const rod_recording *rec, const render_options *o,
                     const render_camera *cam, char *err, size_t errlen)
{
    int surfaces = rec->surfaces ? rec->surface_count : 0;
    if (!plan->have_bounds || (surfaces <= 0 && !plan->ground)) return 0;
    double centre[3], size = 0;
    for (int c = 0; c < 3; c++) {
        centre[c] = 0.5 * (plan->lo[c] + plan->hi[c]);
        size = fmax(size, plan->hi[c] - plan->lo[c]);
    }
    size = fmax(size, 0.1 * plan->length);
    s->size = size;
    s->receivers = 1;
    s->lift = 0.05 * plan->radius + 2e-4 * size;
    render_key_light(cam, s->key);

    render_mesh m = {0};
    m.max_vertices = (surfaces + 1) * SURFACE_VERTICES + 2 * (WOUND_SEGMENTS + 1);
    m.max_indices = (surfaces + 1) * SURFACE_INDICES + 6 * WOUND_SEGMENTS;
    for (int k = 0; k < surfaces; k++) {
        /* a mesh: three vertices a triangle (each corner its own normal) */
        const int triangles = rec->surfaces[k].mesh_triangle_count;
        m.max_vertices += 3 * triangles;
        m.max_indices += 3 * triangles;
        if (plan->cut.on) {
            /* cut open: the cap and the cut triangles' pieces */
            m.max_vertices += CUTAWAY_EXTRA_VERTICES(triangles + SURFACE_INDICES / 3);
            m.max_indices += CUTAWAY_EXTRA_INDICES(triangles + SURFACE_INDICES / 3);
        }
    }
    if (plan->cut.on) {
        /* the wound line cut too */
        m.max_vertices += CUTAWAY_EXTRA_VERTICES(2 * WOUND_SEGMENTS);
        m.max_indices += CUTAWAY_EXTRA_INDICES(2 * WOUND_SEGMENTS);
    }
    m.vertices = malloc((size_t)m.max_vertices * sizeof(render_vertex));
    m.indices = malloc((size_t)m.max_indices * sizeof(unsigned));
    cutaway_scratch *cut = plan->cut.on ? cutaway_scratch_create() : NULL;
    if (!m.vertices || !m.indices || (plan->cut.on && !cut)) {
        free(m.vertices);
        free(m.indices);
        cutaway_scratch_destroy(cut);
        snprintf(err, errlen, "render: out of memory");
        return -1;
    }
    const double plane_distance = receiver_planes(s, &m, plan, rec, centre, size);
    int plane_indices = m.index_count;
    receiver_solids(s, &m, plan, rec, size, cut);
    cutaway_scratch_destroy(cut);
    if (o->wound) {
        double up[3];
        const int first = m.index_count;
        v3_copy(up, plan->ground ? plan->ground_normal : cam->up);
        surface_add_wound(&m, rec, o, 1.2 * plan->radius, s->lift, up);
        if (plan->cut.on) cutaway_clip(&m, first, &plan->cut);
    }
    /* the fade: from PLANE_FADE_START to PLANE_FADE_END motion sizes along the
     * nearest plane, measured from the motion's centre */
    double h = isfinite(plane_distance) ? plane_distance : 0;
    double fade[5] = {centre[0], centre[1], centre[2],
                      sqrt(h * h + PLANE_FADE_START * PLANE_FADE_START * size * size),
                      sqrt(h * h + PLANE_FADE_END * PLANE_FADE_END * size * size)};
    int status = gl_renderer_set_receivers(gl, m.vertices, m.vertex_count, m.indices,
                                           plane_indices, m.index_count, fade, o->background);
    free(m.vertices);
    free(m.indices);
    if (status) {
        snprintf(err, errlen, "render: cannot upload the surfaces (OpenGL error)");
        return -1;
    }
    if (!o->shadows) return 0;
    shadow_light_box(s, plan, rec, size);
    if (shadow_fit(s, gl, cam, plan->radius, NULL, NULL, err, errlen)) return -1;
    s->shadows = 1;
    return 0;
}
