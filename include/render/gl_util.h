/* gl_util.h: the GL layer's helpers: shader programs and a
 * multisampled offscreen render target. Needs a current context
 * (gl_context.h). Only gl_*.c files include GL headers; this header does not. */
#ifndef RODSIM_GL_UTIL_H
#define RODSIM_GL_UTIL_H

#include <stddef.h>

#include "render/image.h"

/* Compiles and links shaders/NAME.vert and shaders/NAME.frag, as compiled
 * into the binary, or as files in $RODSIM_SHADER_DIR when that is set (for
 * shader development). Returns the program name (> 0), or 0 with a message
 * naming the file and the GLSL compiler's log. */
unsigned gl_program_load(const char *name, char *err, size_t errlen);
/* The same with `defines` ("#define X 1\n" lines; NULL: none) after each
 * shader's #version line: a variant with constants folded in. */
unsigned gl_program_load_defined(const char *name, const char *defines, char *err, size_t errlen);

typedef struct gl_target gl_target;

/* An offscreen target of width x height with depth, multisampled with
 * `samples` samples (0 or 1: none; clamped to what GL allows). */
gl_target *gl_target_create(int width, int height, int samples, char *err, size_t errlen);
void gl_target_destroy(gl_target *t);
/* Draws into the target from now on (and sets the viewport). */
void gl_target_bind(gl_target *t);
/* Resolves the samples and reads the pixels into out (same size), top row
 * first. Returns 0, or -1 when the sizes differ or GL reports an error. */
int gl_target_read(gl_target *t, image *out);
/* Resolves and reads only the box x, y, width, height (image coordinates:
 * y down) as RGBA into rgba (width x height x 4), rows bottom-up (GL's
 * order). For drawing that touches a known part of the picture only: the
 * multisample resolve costs time in proportion to the area. 0, or -1. */
int gl_target_read_box_rgba(gl_target *t, int x, int y, int width, int height,
                            unsigned char *rgba);
/* The two halves of gl_target_read_box_rgba, so that several boxes can be
 * resolved and then read with one glReadPixels (one wait for the GL). */
int gl_target_resolve_box(gl_target *t, int x, int y, int width, int height);
int gl_target_read_resolved_rgba(gl_target *t, int x, int y, int width, int height,
                                 unsigned char *rgba);
/* Samples actually in use. */
int gl_target_samples(const gl_target *t);
/* The framebuffer drawn into (colour RGBA8, depth 24 bits), e.g. to blit a
 * cached picture of the same formats into. */
unsigned gl_target_framebuffer(const gl_target *t);

#endif
