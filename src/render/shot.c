/* shot.c: the camera a scene asks for (shot.h). */
#include "render/shot.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "render/camera.h"

#define DEG (M_PI / 180.0)

/* The view direction of azimuth and elevation (deg): azimuth from +x
 * towards +y, elevation above the x-y plane towards +z. */
static void view_from_angles(double azimuth, double elevation, double view[3])
{
    v3_set(view, cos(elevation * DEG) * cos(azimuth * DEG),
           cos(elevation * DEG) * sin(azimuth * DEG), sin(elevation * DEG));
}

/* The camera keys of one section (section, index) over *s. 0, or -1. */
static int read_camera_keys(ini_doc *doc, const char *section, int index, const double view[3],
                            render_shot *s, char *err, size_t errlen)
{
    double v[3];
    int status = ini_get_vector(doc, section, index, "look_at", v, 3, err, errlen);
    if (status < 0) return -1;
    if (status > 0) {
        if (!isfinite(v[0]) || !isfinite(v[1]) || !isfinite(v[2]))
            return ini_error(doc, section, index, "look_at", err, errlen,
                             "must be a point x y z (m, global)");
        v3_copy(s->look_at, v);
        s->has_look_at = 1;
    }
    static const char *const follows[] = {"none", "knot", NULL};
    int choice;
    status = ini_get_choice(doc, section, index, "follow", follows, &choice, err, errlen);
    if (status < 0) return -1;
    if (status > 0) s->follow_knot = choice;
    double x;
    status = ini_get_double(doc, section, index, "distance", &x, err, errlen);
    if (status < 0) return -1;
    if (status > 0) {
        if (!(x > 0 && x <= 1e6))
            return ini_error(doc, section, index, "distance", err, errlen,
                             "must be the eye's distance from the point looked at, m, > 0");
        s->distance = x;
    }
    status = ini_get_double(doc, section, index, "fov", &x, err, errlen);
    if (status < 0) return -1;
    if (status > 0) {
        if (!(x >= 1 && x <= 120))
            return ini_error(doc, section, index, "fov", err, errlen,
                             "must be the vertical field of view in degrees, 1 .. 120");
        s->fov = x;
    }
    /* the angles of the direction the section starts from, for the one not given */
    double azimuth = atan2(view[1], view[0]) / DEG;
    double elevation = atan2(view[2], hypot(view[0], view[1])) / DEG;
    int given = 0;
    status = ini_get_double(doc, section, index, "azimuth", &x, err, errlen);
    if (status < 0) return -1;
    if (status > 0) {
        if (!(x >= -360 && x <= 360))
            return ini_error(doc, section, index, "azimuth", err, errlen,
                             "must be degrees from +x towards +y, -360 .. 360");
        azimuth = x;
        given = 1;
    }
    status = ini_get_double(doc, section, index, "elevation", &x, err, errlen);
    if (status < 0) return -1;
    if (status > 0) {
        if (!(x >= -90 && x <= 90))
            return ini_error(doc, section, index, "elevation", err, errlen,
                             "must be degrees above the x-y plane, -90 .. 90");
        elevation = x;
        given = 1;
    }
    if (given) {
        view_from_angles(azimuth, elevation, s->view);
        s->has_view = 1;
    }
    status = ini_get_vector(doc, section, index, "eye", v, 3, err, errlen);
    if (status < 0) return -1;
    if (status > 0) {
        if (given)
            return ini_error(doc, section, index, "eye", err, errlen,
                             "sets the view direction: give eye or azimuth/elevation, not both");
        if (!isfinite(v[0]) || !isfinite(v[1]) || !isfinite(v[2]))
            return ini_error(doc, section, index, "eye", err, errlen,
                             "must be a point x y z (m, global)");
        v3_copy(s->eye, v);
        s->has_eye = 1;
        s->has_view = 0;
    }
    double apart[3];
    v3_sub(apart, s->eye, s->look_at);
    if (s->has_eye && s->has_look_at && !(v3_norm(apart) > 0))
        return ini_error(doc, section, index, "eye", err, errlen,
                         "is the point looked at (look_at): the eye must stand away from it");
    return 0;
}

static int by_start(const void *a, const void *b)
{
    double x = ((const render_shot *)a)->start, y = ((const render_shot *)b)->start;
    return x < y ? -1 : x > y;
}

/* [shot] number k into *s: its times, then its camera keys over [render]'s.
 * asked_only: no [shot] exists, the keys are asked for (ini strictness is
 * by use) and nothing is required. */
static int read_shot(ini_doc *doc, int k, render_options *o, render_shot *s, int asked_only,
                     char *err, size_t errlen)
{
    *s = o->camera_keys;
    double from = 0, to = 1;
    int status = ini_get_double(doc, "shot", k, "from", &from, err, errlen);
    if (status < 0) return -1;
    if (asked_only) status = 1;
    if (status == 0 || !(from >= 0 && isfinite(from)))
        return ini_error(doc, "shot", k, "from", err, errlen,
                         "is required: the shot's start, s of simulated time, >= 0");
    status = ini_get_double(doc, "shot", k, "to", &to, err, errlen);
    if (status < 0) return -1;
    if (asked_only) status = 1;
    if (status == 0 || !(to > from && isfinite(to)))
        return ini_error(doc, "shot", k, "to", err, errlen,
                         "is required: the shot's end, s of simulated time, > from (%g)", from);
    s->start = from;
    s->end = to;
    double ease = 0;
    status = ini_get_double(doc, "shot", k, "ease", &ease, err, errlen);
    if (status < 0) return -1;
    if (status > 0 && !(ease >= 0 && ease <= to - from))
        return ini_error(doc, "shot", k, "ease", err, errlen,
                         "must be 0 (a cut) .. the shot's length %g s", to - from);
    s->ease = ease;
    const char *caption;
    status = ini_get_string(doc, "shot", k, "caption", &caption, err, errlen);
    if (status < 0) return -1;
    if (status > 0) {
        if (strlen(caption) >= sizeof s->caption)
            return ini_error(doc, "shot", k, "caption", err, errlen,
                             "must be shorter than %d characters", (int)sizeof s->caption);
        snprintf(s->caption, sizeof s->caption, "%s", caption);
    }
    /* a shot's azimuth or elevation alone turns the direction the scene gives */
    double view[3];
    v3_copy(view, s->has_view ? s->view : o->view);
    return read_camera_keys(doc, "shot", k, view, s, err, errlen);
}

int render_shots_read(ini_doc *doc, render_options *o, char *err, size_t errlen)
{
    render_shot *keys = &o->camera_keys;
    memset(keys, 0, sizeof *keys);
    keys->start = -INFINITY;
    keys->end = INFINITY;
    if (read_camera_keys(doc, "render", 0, o->view, keys, err, errlen)) return -1;
    /* [render] azimuth and elevation are render.view in angles */
    if (keys->has_view) v3_copy(o->view, keys->view);
    int count = ini_section_count(doc, "shot");
    if (count > RENDER_MAX_SHOTS)
        return ini_error(doc, "shot", RENDER_MAX_SHOTS, "from", err, errlen,
                         "is one [shot] too many: at most %d", RENDER_MAX_SHOTS);
    render_shot asked;
    for (int k = 0; k < (count > 0 ? count : 1); k++)
        if (read_shot(doc, k, o, count > 0 ? &o->shots[k] : &asked, count == 0, err, errlen))
            return -1;
    o->shot_count = count;
    qsort(o->shots, (size_t)count, sizeof *o->shots, by_start);
    for (int k = 1; k < count; k++)
        if (o->shots[k].start < o->shots[k - 1].end)
            return ini_error(doc, "shot", 0, "from", err, errlen,
                             "the shots %g .. %g s and %g .. %g s overlap: one camera at a time",
                             o->shots[k - 1].start, o->shots[k - 1].end, o->shots[k].start,
                             o->shots[k].end);
    o->directed = count > 0 || keys->has_look_at || keys->follow_knot || keys->distance > 0 ||
                  (keys->fov > 0 && keys->fov != 30) || keys->has_eye;
    return 0;
}

const render_shot *render_shot_at(const render_options *o, double t, int *index)
{
    for (int k = 0; k < o->shot_count; k++) {
        const render_shot *s = &o->shots[k];
        /* the end is the shot's, unless the next one starts there */
        int shared = k + 1 < o->shot_count && o->shots[k + 1].start <= s->end;
        if (t >= s->start && (t < s->end || (!shared && t <= s->end))) {
            if (index) *index = k;
            return s;
        }
    }
    if (index) *index = -1;
    return &o->camera_keys;
}

const char *render_caption_at(const render_options *o, double t)
{
    const render_shot *s = render_shot_at(o, t, NULL);
    return s->caption[0] ? s->caption : o->caption;
}

int render_has_caption(const render_options *o)
{
    if (o->caption[0]) return 1;
    for (int k = 0; k < o->shot_count; k++)
        if (o->shots[k].caption[0]) return 1;
    return 0;
}

/* The camera looking at target from direction back (unit) at distance
 * (m) with field of view fovy (rad): the point at the picture's centre,
 * 2 distance tan(fovy / 2) metres over its height. */
static void camera_at(render_camera *cam, const render_camera *base, const double target[3],
                      const double back[3], double distance, double fovy, double extent)
{
    int width = base->width, height = base->height, orthographic = base->orthographic;
    memset(cam, 0, sizeof *cam);
    cam->width = width;
    cam->height = height;
    cam->orthographic = orthographic;
    cam->fovy = fovy;
    camera_basis(back, cam->direction, cam->right, cam->up);
    double half_height = distance * tan(0.5 * fovy), stand = distance, near, far;
    if (orthographic) {
        /* the picture does not change with the distance: the eye stands
         * beyond the whole run so nothing is clipped */
        stand = distance + 2 * extent;
        near = 1e-4 * stand;
        far = stand + 4 * extent;
    } else {
        near = 1e-2 * distance;
        far = 2 * distance + 4 * extent;
    }
    v3_copy(cam->target, target);
    v3_copy(cam->eye, target);
    v3_axpy(cam->eye, stand, cam->direction);
    cam->metres_per_pixel = 2 * half_height / height;
    camera_matrices(cam, half_height, near, far);
}

/* The shot's target, direction (unit, to the eye), distance and field of view. */
static void shot_pose(const render_shot *s, const render_camera *base, const double knot[3],
                      double target[3], double back[3], double *distance, double *fovy)
{
    *fovy = s->fov > 0 ? s->fov * DEG : PERSPECTIVE_FOVY;
    if (s->follow_knot && knot) v3_copy(target, knot);
    else if (s->has_look_at) v3_copy(target, s->look_at);
    else v3_copy(target, base->target);
    double half = 0.5 * base->metres_per_pixel * base->height; /* the framing's scale */
    *distance = half / tan(0.5 * *fovy);
    v3_copy(back, base->direction);
    if (s->has_view) {
        v3_scale(back, s->view, 1 / v3_norm(s->view));
    }
    if (s->has_eye) {
        v3_sub(back, s->eye, target);
        double d = v3_norm(back);
        if (d > 0) {
            v3_scale(back, back, 1 / d);
            *distance = d;
        }
    }
    if (s->distance > 0) *distance = s->distance;
}

void render_shot_camera(const render_shot *s, const render_camera *base,
                        const double knot_centre[3], double extent, render_camera *cam)
{
    double target[3], back[3], distance, fovy;
    shot_pose(s, base, knot_centre, target, back, &distance, &fovy);
    camera_at(cam, base, target, back, distance, fovy, extent);
}

void render_directed_camera(const render_options *o, double t, render_base_fn base_at,
                            void *context, double extent, render_camera *cam)
{
    render_camera base;
    double knot[3];
    int has_knot = 0, index;
    base_at(context, t, &base, knot, &has_knot);
    const render_shot *s = render_shot_at(o, t, &index);
    double target[3], back[3], distance, fovy;
    shot_pose(s, &base, has_knot ? knot : NULL, target, back, &distance, &fovy);
    if (index >= 0 && s->ease > 0 && t < s->start + s->ease) {
        /* eased from the camera just before the shot: the shot ending where
         * this one starts, else the scene's */
        const render_shot *before = index > 0 && o->shots[index - 1].end >= s->start
                                        ? &o->shots[index - 1]
                                        : &o->camera_keys;
        double from_target[3], from_back[3], from_distance, from_fovy;
        shot_pose(before, &base, has_knot ? knot : NULL, from_target, from_back, &from_distance,
                  &from_fovy);
        double u = (t - s->start) / s->ease, w = u * u * (3 - 2 * u); /* smoothstep */
        double from_eye[3], eye[3];
        v3_copy(from_eye, from_target);
        v3_axpy(from_eye, from_distance, from_back);
        v3_copy(eye, target);
        v3_axpy(eye, distance, back);
        for (int c = 0; c < 3; c++) {
            target[c] = (1 - w) * from_target[c] + w * target[c];
            eye[c] = (1 - w) * from_eye[c] + w * eye[c];
        }
        /* the scale eased as a ratio (a zoom reads as one) */
        double from_half = from_distance * tan(0.5 * from_fovy), half = distance * tan(0.5 * fovy);
        fovy = (1 - w) * from_fovy + w * fovy;
        v3_sub(back, eye, target);
        double d = v3_norm(back);
        if (d > 0) v3_scale(back, back, 1 / d);
        else v3_copy(back, base.direction);
        distance = exp((1 - w) * log(from_half) + w * log(half)) / tan(0.5 * fovy);
    }
    camera_at(cam, &base, target, back, distance, fovy, extent);
}
