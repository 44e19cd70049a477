/* follow.c: the follow camera (follow.h). */
#include "render/follow.h"

#include <math.h>
#include <stdlib.h>

#include "base/vec3.h"
#include "render/geometry.h"
#include "render/mesh.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* Video seconds of the follow camera's smoothing: the centre and the size
 * framed are each smoothed by a local quadratic regression with Gaussian
 * weights of this width over the whole run (smooth_path), so the camera
 * neither jitters nor lags (a steady drift or a fall is followed exactly);
 * where the smoothed framing would cut the rod it is widened to the frame's
 * own need, so nothing is ever clipped. */
#define FOLLOW_TIME 0.25

void follow_destroy(follow_path *fp)
{
    if (!fp) return;
    free(fp->time);
    free(fp->centre);
    free(fp->extent);
    free(fp->knot_centre);
    free(fp->frame.points);
    rod_proximity_destroy(fp->prox);
    free(fp->pairs);
    free(fp);
}

/* Strands nearer than this many diameters make a knot's part of the rod
 * (framing knot): the loose knots of the scenes start 2.5 apart */
#define KNOT_FRAMING_REACH 3.0

/* The points the follow camera frames in frame f into fp->frame: the
 * rod, its glyphs and arrows; with framing knot, the nodes of the knotted
 * part only (the segments within KNOT_FRAMING_REACH diameters of a far
 * strand, KNOT_FRAMING_REACH diameters of arc beyond either end), or all
 * of it while no strands are that near. */
static void follow_cloud(follow_path *fp, const rod_recording *rec, const render_options *o,
                         const arrow_scales *arrows, int f, int knot)
{
    fp->frame.count = 0;
    if (knot && fp->prox) {
        const double reach = KNOT_FRAMING_REACH * rec->diameter;
        /* far: points closer than pi reach / 2 in arc cannot come within
         * reach of each other (rod_proximity_skip's argument, for reach) */
        const double longest = rod_recording_longest_segment(rec);
        int skip = (int)ceil(0.5 * M_PI * reach / longest) + 1;
        int count = rod_proximity_pairs(fp->prox, node_position(rec, f, 0), rec->nodes, reach,
                                        skip, fp->pairs, fp->max_pairs);
        if (count > fp->max_pairs) count = fp->max_pairs; /* the rest, nearer the middle */
        /* a graded grid: the skip counted its longest segment; the pairs
         * nearer than pi reach / 2 in arc are one strand */
        if (count > 0 && rec->arc)
            count = recording_far_pairs(rec, fp->pairs, count, 0.5 * M_PI * reach);
        if (count > 0) {
            int lo = rec->nodes, hi = 0;
            for (int k = 0; k < count; k++) {
                lo = fp->pairs[k].i < lo ? fp->pairs[k].i : lo;
                hi = fp->pairs[k].j + 1 > hi ? fp->pairs[k].j + 1 : hi;
            }
            if (rec->arc) { /* reach of arc beyond either end */
                const double from = rec->arc[lo] - reach, to = rec->arc[hi] + reach;
                while (lo > 0 && rec->arc[lo] > from) lo--;
                while (hi < rec->nodes - 1 && rec->arc[hi] < to) hi++;
            } else {
                int margin = (int)ceil(reach / rec->ds);
                lo = lo - margin > 0 ? lo - margin : 0;
                hi = hi + margin < rec->nodes - 1 ? hi + margin : rec->nodes - 1;
            }
            for (int k = lo; k <= hi; k++)
                v3_copy(&fp->frame.points[3 * fp->frame.count++], node_position(rec, f, k));
            return;
        }
    }
    point_cloud_add_frame(&fp->frame, rec, o, arrows, f, 1);
}

/* The extent (orthographic half height, perspective eye distance; m) that
 * keeps every padded point of pc inside the band when the camera aims at
 * centre c (camera basis; the band's vertical offset included). */

/* The extent (orthographic half height, perspective eye distance; m) that
 * keeps every padded point of pc inside the band when the camera aims at
 * centre c (camera basis; the band's vertical offset included). */
static double follow_need(const follow_path *fp, const point_cloud *pc, const double c[3])
{
    const render_camera *cam = &fp->basis;
    double aspect = (double)cam->width / cam->height;
    double use_x = 1 - 2 * fp->band.side, use_y = 1 - fp->band.top - fp->band.bottom;
    double shift = fp->band.bottom - fp->band.top;
    double tan_y = tan(0.5 * PERSPECTIVE_FOVY), tan_x = tan_y * aspect, need = 0;
    for (int i = 0; i < pc->count; i++) {
        const double *p = &pc->points[3 * i];
        double x = v3_dot(p, cam->right) - c[0], y = v3_dot(p, cam->up) - c[1];
        double z = v3_dot(p, cam->direction) - c[2];
        if (cam->orthographic)
            need = fmax(need, fmax((fabs(x) + pc->pad) / (use_x * aspect),
                                   (fabs(y) + pc->pad) / use_y));
        else /* the depth from the eye is E - z; the band's centre sits at shift in NDC */
            need = fmax(need, z + pc->pad +
                                  fmax((fabs(x) + pc->pad) / (tan_x * use_x),
                                       (fabs(y + shift * z * tan_y) + pc->pad) / (tan_y * use_y)));
    }
    return need > 0 ? need : 1e-9;
}

/* Perspective shows the near side of a box larger: aims c (camera basis)
 * at the middle of the points' projected extent instead (as camera_fit). */
static void follow_recentre(const follow_path *fp, const point_cloud *pc, double c[3])
{
    const render_camera *cam = &fp->basis;
    double tan_y = tan(0.5 * PERSPECTIVE_FOVY), tan_x = tan_y * cam->width / cam->height;
    for (int iteration = 0; iteration < 2; iteration++) {
        double distance = follow_need(fp, pc, c);
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (int i = 0; i < pc->count; i++) {
            const double *p = &pc->points[3 * i];
            double depth = distance - (v3_dot(p, cam->direction) - c[2]);
            double x = (v3_dot(p, cam->right) - c[0]) / (depth * tan_x);
            double y = (v3_dot(p, cam->up) - c[1]) / (depth * tan_y);
            double px = pc->pad / (depth * tan_x), py = pc->pad / (depth * tan_y);
            lo[0] = fmin(lo[0], x - px);
            hi[0] = fmax(hi[0], x + px);
            lo[1] = fmin(lo[1], y - py);
            hi[1] = fmax(hi[1], y + py);
        }
        if (pc->count == 0) return;
        c[0] += 0.5 * (lo[0] + hi[0]) * distance * tan_x;
        c[1] += 0.5 * (lo[1] + hi[1]) * distance * tan_y;
    }
}

/* Smooths the path x[k stride] (samples at times t, any spacing) in place:
 * each value becomes that at t_k of the parabola fitted by least squares to
 * the samples within 3 sigma of t_k, weighted exp(-(dt / sigma)^2 / 2)
 * (local quadratic regression). A path that is a parabola in time (at rest,
 * a steady drift, a free fall) is kept exactly, with no lag at either end,
 * and a jitter from frame to frame averages out. Too few samples in the
 * window for a parabola: a line, else the weighted mean. scratch: n doubles. */
static void smooth_path(double *x, int stride, const double *t, int n, double sigma, double *scratch)
{
    for (int k = 0; k < n; k++) scratch[k] = x[(size_t)k * stride];
    for (int k = 0; k < n; k++) {
        double s[5] = {0}, m[3] = {0};
        int first = k, last = k;
        while (first > 0 && t[k] - t[first - 1] <= 3 * sigma) first--;
        while (last + 1 < n && t[last + 1] - t[k] <= 3 * sigma) last++;
        for (int g = first; g <= last; g++) {
            double d = (t[g] - t[k]) / sigma, w = exp(-0.5 * d * d), power = w;
            for (int p = 0; p < 5; p++, power *= d) {
                s[p] += power;
                if (p < 3) m[p] += power * scratch[g];
            }
        }
        /* the normal equations of a + b d + c d^2, solved for a by Cramer's rule */
        double det = s[0] * (s[2] * s[4] - s[3] * s[3]) - s[1] * (s[1] * s[4] - s[2] * s[3]) +
                     s[2] * (s[1] * s[3] - s[2] * s[2]);
        double line = s[0] * s[2] - s[1] * s[1], value;
        if (last - first >= 2 && fabs(det) > 1e-9 * s[0] * s[0] * s[0])
            value = (m[0] * (s[2] * s[4] - s[3] * s[3]) - s[1] * (m[1] * s[4] - s[3] * m[2]) +
                     s[2] * (m[1] * s[3] - s[2] * m[2])) / det;
        else if (last - first >= 1 && fabs(line) > 1e-9 * s[0] * s[0])
            value = (s[2] * m[0] - s[1] * m[1]) / line;
        else
            value = m[0] / s[0];
        x[(size_t)k * stride] = value;
    }
}

/* follow = knot: the centre of the knotted part's bounds (global) in every
 * frame, smoothed as the framing's centre is (the knot's own jitter from
 * frame to frame averages out; a steady drift is kept). scratch: count doubles. */
static void follow_knot_path(follow_path *fp, const rod_recording *rec, const render_options *o,
                             const arrow_scales *arrows, double radius, double sigma,
                             double *scratch)
{
    for (int f = 0; f < fp->count; f++) {
        follow_cloud(fp, rec, o, arrows, f, 1);
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int i = 0; i < fp->frame.count; i++)
            for (int a = 0; a < 3; a++) {
                lo[a] = fmin(lo[a], fp->frame.points[3 * i + a] - radius);
                hi[a] = fmax(hi[a], fp->frame.points[3 * i + a] + radius);
            }
        for (int a = 0; a < 3; a++)
            fp->knot_centre[3 * f + a] = fp->frame.count ? 0.5 * (lo[a] + hi[a]) : 0;
    }
    for (int a = 0; a < 3; a++)
        smooth_path(fp->knot_centre + a, 3, fp->time, fp->count, sigma, scratch);
}

follow_path *follow_create(const rod_recording *rec, const render_options *o,
                           const arrow_scales *arrows, double radius,
                           const render_camera *run_camera, const frame_band *band,
                           int floor)
{
    follow_path *fp = calloc(1, sizeof *fp);
    if (!fp) return NULL;
    int n = rec->frame_count;
    fp->count = n;
    fp->band = *band;
    fp->basis = *run_camera;
    fp->floor = floor;
    fp->time = malloc((size_t)n * sizeof(double));
    fp->centre = malloc((size_t)n * 3 * sizeof(double));
    fp->extent = malloc((size_t)n * sizeof(double));
    double *need = malloc((size_t)n * sizeof(double));
    fp->frame.points = malloc(((size_t)rec->nodes + FRAME_EXTRA_POINTS) * 3 * sizeof(double));
    fp->frame.pad = radius;
    fp->knot_framing = o->framing == RENDER_FRAMING_KNOT;
    int follow_knot = o->camera_keys.follow_knot;
    for (int k = 0; k < o->shot_count; k++) follow_knot |= o->shots[k].follow_knot;
    if (follow_knot) fp->knot_centre = malloc((size_t)n * 3 * sizeof(double));
    if (fp->knot_framing || follow_knot) {
        fp->max_pairs = 16 * rec->nodes;
        fp->prox = rod_proximity_create(rec->nodes);
        fp->pairs = malloc((size_t)fp->max_pairs * sizeof *fp->pairs);
        if (!fp->prox || !fp->pairs) {
            free(need);
            follow_destroy(fp);
            return NULL;
        }
    }
    if (!fp->time || !fp->centre || !fp->extent || !need || !fp->frame.points ||
        (follow_knot && !fp->knot_centre)) {
        free(need);
        follow_destroy(fp);
        return NULL;
    }
    const double *basis[3] = {run_camera->right, run_camera->up, run_camera->direction};
    double lo_all[3] = {INFINITY, INFINITY, INFINITY}, hi_all[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int f = 0; f < n; f++) {
        fp->time[f] = rec->time[f];
        /* the whole rod bounds the clip planes (depth, size); what is
         * framed, the centre */
        for (int pass = 0; pass < (fp->knot_framing ? 2 : 1); pass++) {
            if (pass == 0) {
                fp->frame.count = 0;
                point_cloud_add_frame(&fp->frame, rec, o, arrows, f, 1);
            } else {
                follow_cloud(fp, rec, o, arrows, f, fp->knot_framing);
            }
            double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
            for (int i = 0; i < fp->frame.count; i++)
                for (int a = 0; a < 3; a++) {
                    double x = v3_dot(&fp->frame.points[3 * i], basis[a]);
                    lo[a] = fmin(lo[a], x - radius);
                    hi[a] = fmax(hi[a], x + radius);
                }
            for (int a = 0; a < 3; a++) {
                fp->centre[3 * f + a] = 0.5 * (lo[a] + hi[a]);
                if (pass > 0) continue;
                lo_all[a] = fmin(lo_all[a], lo[a]);
                hi_all[a] = fmax(hi_all[a], hi[a]);
            }
        }
        if (!run_camera->orthographic) follow_recentre(fp, &fp->frame, &fp->centre[3 * f]);
    }
    fp->depth = hi_all[2] - lo_all[2];
    fp->size = fmax(fmax(hi_all[0] - lo_all[0], hi_all[1] - lo_all[1]), fp->depth);
    /* simulated seconds of FOLLOW_TIME video seconds at this playback rate */
    double sigma = FOLLOW_TIME * o->fps / render_output_rate(o);
    for (int a = 0; a < 3; a++) smooth_path(fp->centre + a, 3, fp->time, n, sigma, need);
    for (int f = 0; f < n; f++) {
        follow_cloud(fp, rec, o, arrows, f, fp->knot_framing);
        need[f] = follow_need(fp, &fp->frame, &fp->centre[3 * f]);
    }
    /* the size: the largest need within 2 sigma, smoothed in log (zoom reads as a ratio);
     * the window makes the smoothed curve cover the needs, the guard at draw time does
     * the rest */
    for (int f = 0; f < n; f++) {
        double most = need[f];
        for (int g = f - 1; g >= 0 && fp->time[f] - fp->time[g] <= 2 * sigma; g--)
            most = fmax(most, need[g]);
        for (int g = f + 1; g < n && fp->time[g] - fp->time[f] <= 2 * sigma; g++)
            most = fmax(most, need[g]);
        fp->extent[f] = log(most);
    }
    smooth_path(fp->extent, 1, fp->time, n, sigma, need);
    for (int f = 0; f < n; f++) fp->extent[f] = exp(fp->extent[f]);
    if (fp->knot_centre) follow_knot_path(fp, rec, o, arrows, radius, sigma, need);
    free(need);
    return fp;
}

int follow_knot_centre(const follow_path *fp, double t, double centre[3])
{
    if (!fp->knot_centre) return -1;
    int n = fp->count, i = 0, last = n - 1;
    while (last - i > 1) {
        int middle = (i + last) / 2;
        if (fp->time[middle] <= t) i = middle;
        else last = middle;
    }
    if (n == 1 || t <= fp->time[0]) {
        v3_copy(centre, fp->knot_centre);
    } else if (t >= fp->time[n - 1]) {
        v3_copy(centre, &fp->knot_centre[3 * (n - 1)]);
    } else {
        double span = fp->time[i + 1] - fp->time[i];
        double a = span > 0 ? (t - fp->time[i]) / span : 0;
        for (int k = 0; k < 3; k++)
            centre[k] = (1 - a) * fp->knot_centre[3 * i + k] + a * fp->knot_centre[3 * (i + 1) + k];
    }
    return 0;
}

void follow_camera(follow_path *fp, const rod_recording *rec, const render_options *o,
                   const arrow_scales *arrows, int frame, double t, render_camera *cam)
{
    int n = fp->count, i = 0, last = n - 1;
    while (last - i > 1) { /* the segment [i, i + 1] that holds t */
        int middle = (i + last) / 2;
        if (fp->time[middle] <= t) i = middle;
        else last = middle;
    }
    double c[3], extent;
    if (n == 1 || t <= fp->time[0]) {
        v3_copy(c, fp->centre);
        extent = fp->extent[0];
    } else if (t >= fp->time[n - 1]) {
        v3_copy(c, &fp->centre[3 * (n - 1)]);
        extent = fp->extent[n - 1];
    } else {
        double span = fp->time[i + 1] - fp->time[i];
        double a = span > 0 ? (t - fp->time[i]) / span : 0;
        for (int k = 0; k < 3; k++)
            c[k] = (1 - a) * fp->centre[3 * i + k] + a * fp->centre[3 * (i + 1) + k];
        extent = (1 - a) * fp->extent[i] + a * fp->extent[i + 1];
    }
    follow_cloud(fp, rec, o, arrows, frame, fp->knot_framing);
    extent = fmax(extent, follow_need(fp, &fp->frame, c));
    if (fp->knot_framing) { /* the near plane from the whole rod: the tails come nearer */
        fp->frame.count = 0;
        point_cloud_add_frame(&fp->frame, rec, o, arrows, frame, 1);
    }

    *cam = fp->basis;
    double shift = fp->band.bottom - fp->band.top, half_height, distance, near, far;
    if (cam->orthographic) {
        half_height = extent;
        distance = 0.5 * fp->depth + 0.5 * fp->size + 1e-3;
        near = 1e-4 * fp->size;
        far = distance + 4 * fp->size;
        if (fp->floor) {
            distance += 6 * fp->size;
            far = distance + 6 * fp->size;
        }
    } else {
        distance = extent;
        half_height = distance * tan(0.5 * PERSPECTIVE_FOVY);
        double nearest = INFINITY;
        for (int k = 0; k < fp->frame.count; k++)
            nearest = fmin(nearest, distance - (v3_dot(&fp->frame.points[3 * k], cam->direction) -
                                                c[2]) - fp->frame.pad);
        near = fmax(0.5 * nearest, 1e-3 * distance);
        if (!isfinite(near)) near = 1e-3 * distance;
        far = distance + 6 * fp->size + distance;
    }
    c[1] -= shift * half_height;
    for (int k = 0; k < 3; k++) {
        cam->target[k] = c[0] * cam->right[k] + c[1] * cam->up[k] + c[2] * cam->direction[k];
        cam->eye[k] = cam->target[k] + distance * cam->direction[k];
    }
    cam->metres_per_pixel = 2 * half_height / cam->height;
    camera_matrices(cam, half_height, near, far);
}
