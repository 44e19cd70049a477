/* gl_plot.h: the GL layer of the plot module: flat-coloured triangles in
 * pixel coordinates drawn into a multisampled offscreen image (MSAA gives
 * the antialiasing). plot.c tessellates lines, markers and arrows on the CPU
 * and hands the triangles here; this header includes no GL. */
#ifndef RODSIM_GL_PLOT_H
#define RODSIM_GL_PLOT_H

#include <stddef.h>

#include "render/image.h"

typedef struct gl_plot gl_plot;

/* Makes a GL context, a width x height target with `samples` MSAA samples
 * and the program shaders/plot.{vert,frag}. NULL with a message. */
gl_plot *gl_plot_create(int width, int height, int samples, char *err, size_t errlen);
void gl_plot_destroy(gl_plot *g);

void gl_plot_clear(gl_plot *g, const unsigned char rgb[3]);
/* Restricts drawing to the pixel box [left, right) x [top, bottom) (y down);
 * gl_plot_clip_off() draws everywhere again. */
void gl_plot_clip(gl_plot *g, int left, int top, int right, int bottom);
void gl_plot_clip_off(gl_plot *g);
/* Triangles: vertex_count (a multiple of 3) points, x y pairs in pixels
 * (top-left origin, y down), one colour. */
void gl_plot_triangles(gl_plot *g, const float *xy, int vertex_count, const unsigned char rgb[3]);
/* Resolves and reads the picture into out (same size). 0 or -1. */
int gl_plot_read(gl_plot *g, image *out);

#endif
