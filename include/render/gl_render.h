/* gl_render.h: draws render_vertex triangles and lines with the scene
 * shader (shaders/scene.*) into a multisampled offscreen target and reads
 * the picture back. The GL layer of the renderer: owns the context. */
#ifndef RODSIM_GL_RENDER_H
#define RODSIM_GL_RENDER_H

#include <stddef.h>

#include "render/image.h"
#include "render/render_types.h"

typedef struct gl_renderer gl_renderer;

/* Makes the GL context (current on this thread), the target, the program
 * and buffers for up to max_vertices / max_indices triangles per frame and
 * max_line_vertices of static lines. NULL with a message. */
gl_renderer *gl_renderer_create(int width, int height, int samples, int max_vertices,
                                int max_indices, int max_line_vertices, char *err, size_t errlen);
void gl_renderer_destroy(gl_renderer *r);
/* Replaces the target by one of `samples` samples (0: one per pixel), e.g.
 * after a multisampled backdrop, for frames antialiased by their edges
 * (edge_aa.h). 0, or -1 with a message (the old target kept). */
int gl_renderer_set_samples(gl_renderer *r, int samples, char *err, size_t errlen);
/* Static lines (the grid), drawn unlit every frame; count <= max_line_vertices. */
void gl_renderer_set_lines(gl_renderer *r, const render_vertex *lines, int count);
/* The static part of the picture, drawn once: clears to background, draws
 * the lines (multisampled), reads the whole picture into out. 0, or -1. */
int gl_renderer_draw_backdrop(gl_renderer *r, const render_camera *cam,
                              const unsigned char background[3], image *out);
/* Static receivers of the shadow (the surfaces, the ground, the wound),
 * matte: indices [0, plane_index_count) are planes, faded to the background
 * from fade[3] (m) to fade[4] (m) away from the point fade[0..2]; the rest
 * are solids. With receivers the backdrop has them, and each box is drawn
 * whole (background, grid, receivers, then the frame's triangles) instead of
 * composited. Call before gl_renderer_draw_backdrop. 0, or -1 on a GL error. */
int gl_renderer_set_receivers(gl_renderer *r, const render_vertex *vertices, int vertex_count,
                              const unsigned *indices, int plane_index_count, int index_count,
                              const double fade[5], const unsigned char background[3]);
/* Whole boxes: each box is drawn whole (background, lines, receivers, then
 * the frame's triangles) as with receivers, even without any; for a camera
 * that moves every frame (no backdrop to composite over). */
void gl_renderer_set_whole_boxes(gl_renderer *r, int whole, const unsigned char background[3]);
/* Faces of this unit normal (world; a cutaway's cap, all of whose vertices
 * carry the plane's normal) receive no shadow; the key light shades them
 * as if nothing stood in its way. */
void gl_renderer_set_unshadowed(gl_renderer *r, const double normal[3]);
/* Shadows from the key light: a size x size depth map drawn through
 * light_view_projection (column-major, orthographic); a receiver's point is
 * moved `offset` (m) along its normal before the look-up (no self-shadow
 * acne), which compares the 2 x 2 texels around it (soft edges). 0, or -1
 * with a message. */
int gl_renderer_set_shadows(gl_renderer *r, const double light_view_projection[16], int size,
                            double offset, char *err, size_t errlen);
/* The moving part: with shadows, draws the first caster_index_count
 * indices into the shadow map (its time added to *shadow_seconds unless
 * NULL); clears each box (4 ints each: x, y, width, height in
 * pixels, y down; boxes disjoint, covering the triangles) to transparent,
 * draws the lit triangles once with back faces culled (closed surfaces,
 * wound counter-clockwise seen from outside; the indices after
 * caster_index_count matte: the punctures), resolves each box, and reads
 * the boxes' bounding rectangle back (a still camera over receivers
 * without samples: only drawn_boxes, the boxes something is drawn in, and
 * they hold only the frame's triangles, their depth from the receivers
 * drawn once; see gl_renderer_darken)
 * as premultiplied RGBA (coverage in alpha), rows bottom-up; read_box gets
 * that rectangle (x, y, width, height). Only the boxes cost much time
 * (clear, multisample resolve). Returns the pixels, owned by r and valid
 * until the next call, or NULL on a GL error. */
const unsigned char *gl_renderer_draw_boxes(gl_renderer *r, const render_camera *cam,
                                            const render_vertex *vertices, int vertex_count,
                                            const unsigned *indices, int index_count,
                                            int caster_index_count, const int *boxes,
                                            int box_count, const int *drawn_boxes,
                                            int drawn_box_count, int read_box[4],
                                            double *shadow_seconds);
/* After gl_renderer_draw_boxes: 1 when its boxes came from the receivers'
 * cache (a still camera over receivers, no samples), transparent but for
 * the frame's triangles (composite them over the backdrop); then, with
 * shadows, the backdrop's pixels in the boxes (out, y down) darkened where
 * the key light's shadow falls on a receiver, as the receivers' shading
 * darkens them. 0: the boxes are whole, out untouched. */
int gl_renderer_darken(const gl_renderer *r, const int *boxes, int box_count, image *out);
const char *gl_renderer_description(const gl_renderer *r);

#endif
