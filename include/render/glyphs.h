/* glyphs.h: what the picture shows besides the tube, pure C: what holds
 * each end (a clamp's block, a pin's ball) or the curved needle at the tip,
 * and the tip load's arrows (force, moment). */
#ifndef RODSIM_RENDER_GLYPHS_H
#define RODSIM_RENDER_GLYPHS_H

#include "render/mesh.h"
#include "render/options.h"
#include "sim/recording.h"

#define ARROW_MAX_VERTICES 200
#define ARROW_MAX_INDICES 700
#define BALL_STACKS 12
#define BALL_SLICES 20
#define BALL_VERTICES ((BALL_STACKS + 1) * (BALL_SLICES + 1))
#define BALL_INDICES (6 * BALL_STACKS * BALL_SLICES)
#define NEEDLE_SEGMENTS 40                 /* along the arc */
#define NEEDLE_SIDES 12
#define NEEDLE_VERTICES ((NEEDLE_SEGMENTS + 1) * NEEDLE_SIDES + NEEDLE_SIDES + 1)
#define NEEDLE_INDICES (6 * NEEDLE_SEGMENTS * NEEDLE_SIDES + 3 * NEEDLE_SIDES)
/* one end's glyph at most: block (24 vertices, 36 indices), ball or needle */
#define GLYPH_VERTICES (24 + BALL_VERTICES + NEEDLE_VERTICES)
#define GLYPH_INDICES (36 + BALL_INDICES + NEEDLE_INDICES)
/* points that bound one end's glyph, for framing and tiles: block corners,
 * ball extremes or the needle's arc */
#define GLYPH_MAX_POINTS (NEEDLE_SEGMENTS + 1)

/* The needle's wire radius, m: as thick as the drawn thread at most (a real
 * needle is thicker than its thread, but a thicker wire hides the arc),
 * and thin beside the arc's radius. */
double glyph_needle_wire(const rod_recording *rec, double radius);
/* Points whose padded hull holds the glyph at `end` in `frame` (padded by
 * *pad, m); returns how many (0: nothing drawn). *chain = 1 when they are
 * a polyline (consecutive pairs bound it), 0 when a hull. */
int glyph_points(const rod_recording *rec, const render_options *o, double radius, int frame,
                 int end, double *out, double *pad, int *chain);
/* The glyph of each end in frame `frame` (tube radius `radius`, m) into m. */
void glyph_add_ends(render_mesh *m, const rod_recording *rec, const render_options *o, int frame,
                    double radius);

typedef struct arrow_style {
    double shaft_radius, head_radius, head_length; /* m */
} arrow_style;

/* Arrow geometry shared by drawing and camera framing. */
typedef struct arrow_scales {
    double force_scale, moment_scale; /* m per N, m per N m; 0 = no arrow */
    double max_force, max_moment;     /* N, N m: the largest over the run */
    double tube_radius;               /* m, drawn: arrows start outside it */
    arrow_style style;
} arrow_scales;

/* The arrows' scales over the whole of rec (its peak loads included): the
 * largest load a fixed fraction of the length; enabled 0: no arrows. */
void arrow_scales_compute(arrow_scales *a, const rod_recording *rec, double radius,
                          int enabled);
/* Tail, unit direction and length of the force (which = 0) or moment arrow,
 * outside the tube: a load pointing away from the rod (or across it) starts
 * at the tube's surface; one pointing back into the rod (a compressive
 * force along -d3) ends at the tip's end face, its tail beyond the tip,
 * pushing on it. 0 when the load is too small to draw. */
int arrow_geometry(const arrow_scales *a, const rod_recording *rec, int frame, int which,
                   double tail[3], double d[3], double *length);
/* Both arrows of frame `frame` into m (those of a load too small to see left out). */
void glyph_add_arrows(render_mesh *m, const arrow_scales *a, const rod_recording *rec, int frame);

#endif
