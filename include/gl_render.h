/* gl_render.h: draws render_vertex triangles and lines with the scene
 * shader (shaders/scene.*) into a multisampled offscreen target and reads
 * the picture back. The GL layer of the renderer: owns the context. */
#ifndef RODSIM_GL_RENDER_H
#define RODSIM_GL_RENDER_H

#include <stddef.h>

#include "image.h"
#include "render.h"

typedef struct gl_renderer gl_renderer;

/* Makes the GL context (current on this thread), the target, the program
 * and buffers for up to max_vertices / max_indices triangles per frame and
 * max_line_vertices of static lines. NULL with a message. */
gl_renderer *gl_renderer_create(int width, int height, int samples, int max_vertices,
                                int max_indices, int max_line_vertices, char *err, size_t errlen);
void gl_renderer_destroy(gl_renderer *r);
/* Static lines (the grid), drawn unlit every frame; count <= max_line_vertices. */
void gl_renderer_set_lines(gl_renderer *r, const render_vertex *lines, int count);
/* Clears to background, draws the lines and the lit triangles. */
void gl_renderer_draw(gl_renderer *r, const render_camera *cam, const render_vertex *vertices,
                      int vertex_count, const unsigned *indices, int index_count,
                      const unsigned char background[3]);
/* Reads the picture (top row first). 0, or -1. */
int gl_renderer_read(gl_renderer *r, image *out);
const char *gl_renderer_description(const gl_renderer *r);

#endif
