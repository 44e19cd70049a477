/* grid.h: the backdrop grid, pure C: lines on the world plane most facing
 * the camera, behind the motion and the surfaces, spaced 1, 2 or 5 x 10^k, and the lengths
 * the scale bar is labelled with. */
#ifndef RODSIM_RENDER_GRID_H
#define RODSIM_RENDER_GRID_H

#include <stddef.h>

#include "render/render_types.h"
#include "sim/recording.h"

#define GRID_MAX_LINES 200                 /* per direction */

/* Largest 1, 2 or 5 times a power of ten not above x. */
double nice_below(double x);
/* A length (m) for people: "2 m", "50 cm", "5 mm", "20 \u00b5m". */
void format_length(char *out, size_t outlen, double metres);

typedef struct grid {
    double spacing;     /* m, one cell */
    render_vertex *lines;
    int count, capacity;
    int axis;           /* the world axis the grid's plane is normal to */
    double plane;       /* m: the plane's coordinate on that axis */
    double size;        /* m: the motion's size, which sets the spacing */
    double fixed_spacing; /* m; > 0: the spacing for every camera (follow) */
    float minor[3], major[3];
} grid;

/* Where the picture's corner rays meet the grid's plane: the region of it
 * the camera sees, in the plane's two other axes. */
void grid_region(const grid *g, const render_camera *cam, double region_lo[2],
                 double region_hi[2]);
/* The grid lines where the camera sees the grid's plane. */
void grid_lines(grid *g, const render_camera *cam);
/* The grid for the motion of rec seen by cam (its plane, spacing and
 * colours from the background's), then its lines. Its plane lies beyond
 * the thread and every surface (an elastic pad as drawn in every frame),
 * seen from the camera; the thread's motion alone sets the spacing. */
void grid_build(grid *g, const rod_recording *rec, const render_camera *cam, double radius,
                const unsigned char background[3]);

#endif
