/* camera.h: the camera, pure C: its basis along a view, the points it must
 * keep in the picture, the band of the picture the overlay leaves free, its
 * matrices, and the camera that frames the whole motion. */
#ifndef RODSIM_RENDER_CAMERA_H
#define RODSIM_RENDER_CAMERA_H

#include <math.h>

#include "render/glyphs.h"
#include "render/options.h"
#include "render/render_types.h"
#include "sim/recording.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* rad: the perspective camera's vertical field of view */
#define PERSPECTIVE_FOVY (30.0 * M_PI / 180.0)
/* Fractions of the picture kept free for overlay text (top, bottom) and a side margin. */
#define FRAME_TOP 0.15
#define FRAME_BOTTOM 0.15
#define FRAME_SIDE 0.05

/* tan of half the camera's vertical field of view (perspective). */
double camera_tan_half_fov(const render_camera *cam);

/* The camera's unit basis looking along -view: back (towards the eye),
 * right and up (y up when looking along z, the thesis' x-y plane, else z). */
void camera_basis(const double view[3], double back[3], double right[3], double up[3]);

/* Points the camera must keep in the picture: every node of every frame
 * (padded by the tube radius), the end glyphs and the arrow ends. */
typedef struct point_cloud {
    double *points; /* (count x 3), m */
    int count;
    double pad;     /* m, added around every point */
} point_cloud;

/* Points one frame adds at most beyond its nodes: both arrows' ends, and
 * each end's glyph points (6 for a padded one). */
#define FRAME_EXTRA_POINTS (4 + 12 * GLYPH_MAX_POINTS)
/* Frame f's points: its nodes (when with_nodes), the arrows' ends and the
 * end glyphs (pc->pad is the tube's radius). */
void point_cloud_add_frame(point_cloud *pc, const rod_recording *rec,
                           const render_options *o, const arrow_scales *arrows, int f,
                           int with_nodes);
/* The cloud of every frame of rec: the nodes (of every frame, or of evenly
 * spaced ones for a long run), the glyphs and the arrows, padded by the
 * tube's radius. 0, or -1 when out of memory (pc->points NULL). */
int point_cloud_create(point_cloud *pc, const rod_recording *rec, const render_options *o,
                       double radius, const arrow_scales *arrows);

/* The part of the picture the content may use: fractions of the height
 * (top, bottom) and of the width (each side) kept free for the overlay. */
typedef struct frame_band {
    double top, bottom, side;
} frame_band;

/* The whole picture less the overlay's top and bottom bands and the side margins. */
extern const frame_band frame_band_full;

/* 1 when the overlay names what holds the ends: not for the thesis'
 * cantilever (the old scenes look as before) */
int ends_line_shown(const rod_recording *rec, const render_options *o);
/* base with its top grown to clear the overlay's left column (its title,
 * caption, time and ends' lines, as drawn by overlay_draw). */
frame_band overlay_band(const rod_recording *rec, const render_options *o, frame_band base);
/* The view, projection and their product from cam's eye, basis and target. */
void camera_matrices(render_camera *cam, double half_height, double near, double far);
/* The camera of rec's whole motion (as render_camera_fit) with the content
 * kept inside `band` of the picture. */
void camera_fit(render_camera *cam, const rod_recording *rec, const render_options *o,
                const frame_band *band);

/* Frames the whole motion: the bounds over all frames of the tube (visual
 * radius included), the end glyphs (block, ball, needle) and the arrows,
 * seen along o->view, leave room for the overlay text at the top and bottom,
 * and do not change per frame: the camera of framing run with one view
 * (framing follow moves it frame by frame, a split frame has one per tile:
 * render_options.cameras reports the cameras drawn). */
void render_camera_fit(render_camera *cam, const rod_recording *rec, const render_options *o);
/* Pixel position (x right, y down, pixel centres at +0.5) of a world point.
 * Returns 0, or -1 when the point is behind the camera. */
int render_project(const render_camera *cam, const double point[3], double pixel[2]);

#endif
