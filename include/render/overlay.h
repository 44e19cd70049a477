/* overlay.h: the text and marks drawn over a frame: the title, the time
 * and what holds the ends (top left), the knot's type and what is not to
 * scale or real time (top right), the axes and the loads (bottom left),
 * the scale bar and the colour bar. */
#ifndef RODSIM_RENDER_OVERLAY_H
#define RODSIM_RENDER_OVERLAY_H

#include <stddef.h>

#include "render/glyphs.h"
#include "render/image.h"
#include "render/options.h"
#include "render/render_types.h"
#include "render/text.h"
#include "sim/geometry/knot.h"
#include "sim/recording.h"

/* What the overlay draws every frame with: fonts, colours and what is fixed
 * for the run. */
typedef struct render_overlay {
    text_font *title, *body;
    unsigned char ink[3], faint[3];
    double exaggeration;  /* visual radius / true radius */
    double bar_metres;    /* scale bar length, m */
    int bar_pixels;
    char bar_label[32];
    char title_text[256];
    int time_digits;      /* integer digits of the largest time of the run */
    int time_decimals;    /* enough to tell the frames apart */
    double force_scale;   /* N, the largest |tip force| of the run (0: no force line) */
    double moment_scale;  /* N m, the same for the moment */
    double playback;      /* simulated s per video s, as recorded */
    double color_lo, color_hi; /* the colour bar's range, fixed for the video */
    int color_clamped;    /* values beyond the range (drawn in the end colours) */
    int knot_shown;       /* 1: the knot line is drawn (render_knot_shown) */
    rod_knot_scratch *knot_scratch; /* identifies each frame without allocating */
    char knot_text[160];  /* this frame's knot line */
} render_overlay;

/* A number for people: `value` in `unit` with an SI prefix (f .. G) and 3
 * significant digits ("450 nN", "2.5 mN", "1.2 \u00b5N\u00b7m"), no "-0",
 * and 0 when |value| < 1e-12 |scale| (round-off of a quantity of that size).
 * A unit starting with "1/" or "" gets no prefix (plain %.3g). Returns out. */
char *render_format_quantity(char *out, size_t outlen, double value, double scale,
                             const char *unit);

/* The overlay's knot line for a centreline (nodes x 3, m, an open polygon):
 * "knot: unknot", "knot: trefoil (3_1), right-handed", ... (sim/geometry/knot.h names
 * the type). Returns 1 when the type was identified (0: "knot: not
 * identified"). Allocates per call; the renderer keeps a scratch instead. */
int render_knot_text(const double *points, int nodes, char *text, size_t n);
/* Whether a render of rec with o names the knot type: o->knot yes or no,
 * and auto when the overlay is drawn and some frame of rec (up to
 * RENDER_KNOT_SAMPLES of them, evenly spread, the first and last included)
 * is identified as other than the unknot. */
int render_knot_shown(const rod_recording *rec, const render_options *o);
#define RENDER_KNOT_SAMPLES 32

/* The overlay's fixed parts: title, time format, load scales, colour range,
 * ink, scale bar (cam); the fonts when `fonts`. 0, or -1 with a message. */
int overlay_create(render_overlay *ov, const rod_recording *rec, const render_options *o,
                   const char *scene_name, double radius, const arrow_scales *arrows,
                   const render_camera *cam, int fonts, char *err, size_t errlen);
void overlay_destroy(render_overlay *ov);
/* The scale bar for a picture `width` pixels wide at metres_per_pixel. */
void overlay_scale_bar(render_overlay *ov, int width, double metres_per_pixel);
/* This frame's knot line: the type of the true centreline, not of
 * a magnified one (render.magnify): magnified strands may pass through each
 * other on the screen, the rod's knot is the rod's. */
void overlay_knot(render_overlay *ov, const rod_recording *rec, int frame);
/* The overlay of frame `frame` of rec (the motion as drawn) over img, seen by cam. */
void overlay_draw(image *img, const render_overlay *ov, const rod_recording *rec,
                  const render_options *o, const render_camera *cam, int frame);
/* x, y, z as the camera sees them, centred at (cx, cy), `size` pixels long
 * for an axis in the picture's plane; the farthest drawn first. */
void overlay_draw_triad(image *img, const render_overlay *ov, const render_camera *cam, double cx,
                        double cy, double size);

#endif
