/* gl_context.h: a headless OpenGL context (no display, no GPU).
 *
 * The only module that knows how the context is made (OSMesa today; Mesa
 * 25.1 removed OSMesa, so a surfaceless-EGL file with the same two
 * functions can replace src/render/gl_context.c, filling the GL function
 * table with gl_functions_load(eglGetProcAddress)). The library is opened
 * (dlopen) by the first gl_context_create, so a program that never draws
 * never loads it. Creating it makes it current on the calling thread; all
 * GL calls must come from that thread. */
#ifndef RODSIM_GL_CONTEXT_H
#define RODSIM_GL_CONTEXT_H

#include <stddef.h>

typedef struct gl_context gl_context;

/* A context with a default framebuffer of width x height, made current.
 * Asks for an OpenGL 3.3 core profile (Mesa's llvmpipe gives 4.5 core);
 * NULL with a message when the context cannot be made (or the library
 * cannot be loaded: the message names it and its Debian package). */
gl_context *gl_context_create(int width, int height, char *err, size_t errlen);
void gl_context_destroy(gl_context *ctx);
/* "OpenGL 4.5 (Core Profile) Mesa ..., llvmpipe": for logs and reports. */
const char *gl_context_description(const gl_context *ctx);

#endif
