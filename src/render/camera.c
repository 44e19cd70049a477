/* camera.c: the camera and the framing of the whole motion (camera.h). */
#include "render/camera.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "render/geometry.h"
#include "render/shot.h"
#include "render/surface.h"

void camera_basis(const double view[3], double back[3], double right[3], double up[3])
{
    double n = v3_norm(view);
    if (n > 0) v3_scale(back, view, 1.0 / n);
    else v3_set(back, 0, 0, 1);
    /* y is up when looking along z (the thesis' x-y plane), else z is up */
    double world_up[3] = {0, 0, 1};
    if (fabs(back[2]) >= fabs(back[0]) && fabs(back[2]) >= fabs(back[1])) v3_set(world_up, 0, 1, 0);
    v3_cross(right, world_up, back);
    v3_scale(right, right, 1.0 / v3_norm(right));
    v3_cross(up, back, right);
}

/* The bounded surfaces near the motion join the cloud: each one's bounding
 * box, cut to the motion's own box grown by half its size on every side, so
 * that a skin pad under the thread is framed but a large table or an
 * unbounded cylinder does not shrink the rod (a plane is never framed). */
static void point_cloud_add_surfaces(point_cloud *pc, const rod_recording *rec)
{
    if (rec->surface_count <= 0 || pc->count == 0) return;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < pc->count; i++)
        for (int c = 0; c < 3; c++) {
            lo[c] = fmin(lo[c], pc->points[3 * i + c] - pc->pad);
            hi[c] = fmax(hi[c], pc->points[3 * i + c] + pc->pad);
        }
    double size = fmax(fmax(hi[0] - lo[0], hi[1] - lo[1]), hi[2] - lo[2]);
    for (int k = 0; k < rec->surface_count; k++) {
        const recording_surface *sf = &rec->surfaces[k];
        if (sf->shape == RECORDING_SURFACE_PLANE) continue;
        double slo[3], shi[3];
        surface_bounds(sf, slo, shi);
        int empty = 0;
        for (int c = 0; c < 3; c++) {
            slo[c] = fmax(slo[c], lo[c] - 0.5 * size);
            shi[c] = fmin(shi[c], hi[c] + 0.5 * size);
            if (!(slo[c] <= shi[c])) empty = 1;
        }
        for (int corner = 0; !empty && corner < 8; corner++) {
            double *p = &pc->points[3 * pc->count++];
            for (int c = 0; c < 3; c++) p[c] = corner >> c & 1 ? shi[c] : slo[c];
        }
    }
}

void point_cloud_add_frame(point_cloud *pc, const rod_recording *rec,
                           const render_options *o, const arrow_scales *arrows, int f,
                           int with_nodes)
{
    for (int k = 0; with_nodes && k < rec->nodes; k++)
        v3_copy(&pc->points[3 * pc->count++], node_position(rec, f, k));
    for (int which = 0; which < 2; which++) {
        double tail[3], d[3], length;
        if (!arrow_geometry(arrows, rec, f, which, tail, d, &length)) continue;
        /* both ends: a pushing arrow's tail lies beyond the tip */
        v3_copy(&pc->points[3 * pc->count++], tail);
        double *p = &pc->points[3 * pc->count++];
        v3_copy(p, tail);
        v3_axpy(p, length, d);
    }
    for (int end = 0; end < 2; end++) {
        double glyph[3 * GLYPH_MAX_POINTS], pad;
        int chain, count = glyph_points(rec, o, pc->pad, f, end, glyph, &pad, &chain);
        for (int i = 0; i < count; i++) {
            if (pad <= pc->pad) {
                v3_copy(&pc->points[3 * pc->count++], &glyph[3 * i]);
                continue;
            }
            /* a wider pad (the ball): its extremes along x, y, z bound it with pc->pad */
            for (int a = 0; a < 6; a++) {
                double *p = &pc->points[3 * pc->count++];
                v3_copy(p, &glyph[3 * i]);
                p[a / 2] += a % 2 ? pad : -pad;
            }
        }
    }
}

int point_cloud_create(point_cloud *pc, const rod_recording *rec, const render_options *o,
                       double radius, const arrow_scales *arrows)
{
    int stride = 1;
    while ((size_t)(rec->frame_count / stride + 1) * (size_t)rec->nodes > 400000) stride++;
    /* the glyphs every frame (a driven end moves them): at most GLYPH_MAX_POINTS each, or 6
     * for a ball (its padded centre) */
    size_t capacity = (size_t)(rec->frame_count / stride + 2) * (size_t)rec->nodes +
                      (size_t)rec->frame_count * (4 + 2 * GLYPH_MAX_POINTS) + 8 +
                      8 * (size_t)(rec->surface_count > 0 ? rec->surface_count : 0);
    pc->points = malloc(capacity * 3 * sizeof(double));
    pc->count = 0;
    pc->pad = radius;
    if (!pc->points) return -1;
    for (int f = 0; f < rec->frame_count; f++)
        point_cloud_add_frame(pc, rec, o, arrows, f, f % stride == 0 || f == rec->frame_count - 1);
    return 0;
}

static void look_at(double m[16], const double eye[3], const double right[3], const double up[3],
                    const double back[3])
{
    memset(m, 0, 16 * sizeof(double));
    for (int c = 0; c < 3; c++) {
        m[4 * c + 0] = right[c];
        m[4 * c + 1] = up[c];
        m[4 * c + 2] = back[c];
    }
    m[12] = -v3_dot(right, eye);
    m[13] = -v3_dot(up, eye);
    m[14] = -v3_dot(back, eye);
    m[15] = 1;
}

static void mat4_mul(double r[16], const double a[16], const double b[16])
{
    for (int col = 0; col < 4; col++)
        for (int row = 0; row < 4; row++) {
            double sum = 0;
            for (int k = 0; k < 4; k++) sum += a[4 * k + row] * b[4 * col + k];
            r[4 * col + row] = sum;
        }
}

const frame_band frame_band_full = {FRAME_TOP, FRAME_BOTTOM, FRAME_SIDE};

int ends_line_shown(const rod_recording *rec, const render_options *o)
{
    const recording_end *root = &rec->ends[0], *tip = &rec->ends[1];
    return (o->show & RENDER_SHOW_ENDS) &&
           (root->kind != RECORDING_END_CLAMPED || root->driven ||
            tip->kind != RECORDING_END_FREE || tip->driven || rec->needle_radius > 0);
}

/* base with its top grown to clear the overlay's left column (overlay_draw:
 * a title of height / 22 px, lines of height / 34 px type, each ascent +
 * descent + 4 px apart, from a margin of height / 40 + 4 px, and 12 px
 * below the last): FRAME_TOP holds a title and the time line; a caption and
 * the ends' line need more (buckling_twist.ini's plectoneme, framed by
 * `follow`, ran into its fourth line with FRAME_TOP alone). */
frame_band overlay_band(const rod_recording *rec, const render_options *o, frame_band base)
{
    if (!o->overlay || o->height <= 0) return base;
    const unsigned show = o->show;
    int lines = 0;
    if (show & RENDER_SHOW_TITLE) lines++;
    if ((show & RENDER_SHOW_CAPTION) && render_has_caption(o)) lines++;
    if (show & RENDER_SHOW_TIME) lines++;
    if (ends_line_shown(rec, o)) lines++;
    if (lines == 0) return base;
    const double h = o->height, body = fmax(h / 34.0, 7.0), title = fmax(h / 22.0, 8.0);
    const double line = 1.2 * body + 4.0;
    double px = h / 40.0 + 4.0 + ((show & RENDER_SHOW_TITLE) ? title : body) + (lines - 1) * line +
                0.3 * body + 12.0;
    base.top = fmax(base.top, px / h);
    return base;
}

double camera_tan_half_fov(const render_camera *cam)
{
    return tan(0.5 * (cam->fovy > 0 ? cam->fovy : PERSPECTIVE_FOVY));
}

void camera_matrices(render_camera *cam, double half_height, double near, double far)
{
    double aspect = (double)cam->width / cam->height;
    look_at(cam->view, cam->eye, cam->right, cam->up, cam->direction);
    double *p = cam->projection;
    memset(p, 0, sizeof cam->projection);
    if (cam->orthographic) {
        p[0] = 1.0 / (aspect * half_height);
        p[5] = 1.0 / half_height;
        p[10] = -2.0 / (far - near);
        p[14] = -(far + near) / (far - near);
        p[15] = 1;
    } else {
        double f = 1.0 / camera_tan_half_fov(cam);
        p[0] = f / aspect;
        p[5] = f;
        p[10] = (far + near) / (near - far);
        p[11] = -1;
        p[14] = 2 * far * near / (near - far);
    }
    mat4_mul(cam->view_projection, cam->projection, cam->view);
}

void camera_fit(render_camera *cam, const rod_recording *rec, const render_options *o,
                const frame_band *band)
{
    memset(cam, 0, sizeof *cam);
    cam->width = o->width;
    cam->height = o->height;
    cam->orthographic = o->camera == RENDER_CAMERA_ORTHOGRAPHIC;
    double *back = cam->direction, *right = cam->right, *up = cam->up;
    camera_basis(o->view, back, right, up);
    double radius = render_visual_radius(rec, o);
    arrow_scales arrows;
    arrow_scales_compute(&arrows, rec, radius, o->arrows);
    point_cloud pc;
    if (point_cloud_create(&pc, rec, o, radius, &arrows)) {
        /* out of memory: frame the first frame's ends */
        pc.count = 0;
    }
    point_cloud_add_surfaces(&pc, rec);
    double aspect = (double)o->width / o->height;
    /* the band of the picture the content may use, as fractions of the half-size */
    double use_x = 1 - 2 * band->side, use_y = 1 - band->top - band->bottom;
    double centre_shift_y = band->bottom - band->top; /* NDC centre of the usable band */

    /* camera-basis coordinates of the content */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    const double *basis[3] = {right, up, back};
    for (int i = 0; i < pc.count; i++)
        for (int a = 0; a < 3; a++) {
            double x = v3_dot(&pc.points[3 * i], basis[a]);
            lo[a] = fmin(lo[a], x - pc.pad);
            hi[a] = fmax(hi[a], x + pc.pad);
        }
    if (pc.count == 0)
        for (int a = 0; a < 3; a++) lo[a] = -0.5 * rec->length, hi[a] = 0.5 * rec->length;
    double centre[3] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
    double size = fmax(fmax(hi[0] - lo[0], hi[1] - lo[1]), hi[2] - lo[2]);
    double near, far, distance, half_height;
    if (cam->orthographic) {
        half_height = fmax(0.5 * (hi[1] - lo[1]) / use_y, 0.5 * (hi[0] - lo[0]) / (use_x * aspect));
        centre[1] -= centre_shift_y * half_height;
        distance = 0.5 * (hi[2] - lo[2]) + 0.5 * size + 1e-3;
        near = 1e-4 * size;
        far = distance + 4 * size;
        if (rec->surface_count > 0 || v3_norm(rec->distributed_force) > 0) {
            /* a floor (a plane, the ground) reaches 3 sizes and more from the
             * motion: the eye stands back so that no part of it is clipped
             * (an orthographic picture does not change with the distance) */
            distance += 6 * size;
            far = distance + 6 * size;
        }
        cam->metres_per_pixel = 2 * half_height / o->height;
    } else {
        double tan_y = tan(0.5 * PERSPECTIVE_FOVY), tan_x = tan_y * aspect;
        distance = size;
        for (int iteration = 0; iteration < 4; iteration++) {
            /* the nearest eye distance that keeps every padded point inside the usable band */
            distance = 0;
            for (int i = 0; i < pc.count; i++) {
                double x = v3_dot(&pc.points[3 * i], right) - centre[0];
                double y = v3_dot(&pc.points[3 * i], up) - centre[1];
                double z = v3_dot(&pc.points[3 * i], back) - centre[2];
                double need = z + pc.pad + fmax((fabs(x) + pc.pad) / (tan_x * use_x),
                                                (fabs(y) + pc.pad) / (tan_y * use_y));
                distance = fmax(distance, need);
            }
            if (pc.count == 0) distance = 2 * size;
            /* re-centre on the projected extent (perspective shifts near parts outward) */
            double nlo[2] = {INFINITY, INFINITY}, nhi[2] = {-INFINITY, -INFINITY};
            for (int i = 0; i < pc.count; i++) {
                double x = v3_dot(&pc.points[3 * i], right) - centre[0];
                double y = v3_dot(&pc.points[3 * i], up) - centre[1];
                double depth = distance - (v3_dot(&pc.points[3 * i], back) - centre[2]);
                double nx = x / (depth * tan_x), ny = y / (depth * tan_y);
                double px = pc.pad / (depth * tan_x), py = pc.pad / (depth * tan_y);
                nlo[0] = fmin(nlo[0], nx - px);
                nhi[0] = fmax(nhi[0], nx + px);
                nlo[1] = fmin(nlo[1], ny - py);
                nhi[1] = fmax(nhi[1], ny + py);
            }
            if (pc.count == 0) break;
            centre[0] += 0.5 * (nlo[0] + nhi[0]) * distance * tan_x;
            centre[1] += 0.5 * (nlo[1] + nhi[1]) * distance * tan_y;
        }
        half_height = distance * tan_y;
        /* shift the content into the usable band's centre (equal bands: no shift) */
        centre[1] -= centre_shift_y * half_height;
        double nearest = INFINITY;
        for (int i = 0; i < pc.count; i++)
            nearest = fmin(nearest, distance - (v3_dot(&pc.points[3 * i], back) - centre[2]) - pc.pad);
        near = fmax(0.5 * nearest, 1e-3 * distance);
        if (!isfinite(near)) near = 1e-3 * distance;
        far = distance + 6 * size + distance;
        cam->metres_per_pixel = 2 * half_height / o->height;
    }
    free(pc.points);

    for (int c = 0; c < 3; c++) {
        cam->target[c] = centre[0] * right[c] + centre[1] * up[c] + centre[2] * back[c];
        cam->eye[c] = cam->target[c] + distance * back[c];
    }
    camera_matrices(cam, half_height, near, far);
}

void render_camera_fit(render_camera *cam, const rod_recording *rec, const render_options *o)
{
    /* the motion as drawn: magnified (out of memory: the true motion) */
    rod_recording *shown = o->magnify != 1 ? magnified_copy(rec, o->magnify) : NULL;
    const frame_band band = overlay_band(rec, o, frame_band_full);
    camera_fit(cam, shown ? shown : rec, o, &band);
    rod_recording_destroy(shown);
}

int render_project(const render_camera *cam, const double point[3], double pixel[2])
{
    const double *m = cam->view_projection;
    double clip[4];
    for (int row = 0; row < 4; row++)
        clip[row] = m[row] * point[0] + m[4 + row] * point[1] + m[8 + row] * point[2] + m[12 + row];
    if (clip[3] <= 0) return -1;
    pixel[0] = (clip[0] / clip[3] + 1) * 0.5 * cam->width;
    pixel[1] = (1 - clip[1] / clip[3]) * 0.5 * cam->height;
    return 0;
}
