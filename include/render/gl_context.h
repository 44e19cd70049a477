/* gl_context.h: a headless OpenGL context (no display, no GPU).
 *
 * The only module that knows how the context is made. Two backends, both
 * Mesa's llvmpipe: EGL on Mesa's software device (EGL_EXT_platform_device +
 * EGL_MESA_device_software; Mesa 25.1 removed OSMesa) and OSMesa. The
 * environment variable RODSIM_GL (MuJoCo's MUJOCO_GL convention) chooses:
 * "egl", "osmesa", or unset/empty: EGL, then OSMesa when EGL cannot be used.
 * The choice is made once per process, by the first gl_context_create, which
 * also opens the library (dlopen): a program that never draws never loads
 * either. Creating a context makes it current on the calling thread; all GL
 * calls must come from that thread. */
#ifndef RODSIM_GL_CONTEXT_H
#define RODSIM_GL_CONTEXT_H

#include <stddef.h>

typedef struct gl_context gl_context;

/* A context with a default framebuffer of width x height, made current.
 * Asks for an OpenGL 3.3 core profile (Mesa's llvmpipe gives 4.5 core);
 * NULL with a message when the context cannot be made (or the library
 * cannot be loaded: the message names it and its Debian package; or
 * RODSIM_GL names no backend). */
gl_context *gl_context_create(int width, int height, char *err, size_t errlen);
void gl_context_destroy(gl_context *ctx);
/* Makes ctx current on the calling thread (a no-op when it is): a process
 * with several contexts (the views of a split frame) switches before each
 * one's GL calls. 0, or -1 when the library refuses. */
int gl_context_make_current(gl_context *ctx);
/* "EGL: OpenGL 4.5 (Core Profile) Mesa ..., llvmpipe ...": for logs and reports. */
const char *gl_context_description(const gl_context *ctx);
/* "EGL" or "OSMesa": the backend that made ctx. */
const char *gl_context_backend(const gl_context *ctx);

/* Checks RODSIM_GL without loading anything (so a run can refuse a bad
 * value before it simulates): 0, or -1 with a message naming the value and
 * the accepted ones. */
int gl_context_check_env(char *err, size_t errlen);
/* The backend this process draws with ("EGL", "OSMesa"); NULL before the
 * first gl_context_create, or when it found none. */
const char *gl_context_backend_used(void);
/* For `rodsim --version`: one line per backend, in the default order, saying
 * whether it can be used here ("EGL     available: libEGL.so.1, Mesa's
 * software device" or why not), then which one RODSIM_GL selects. Opens
 * both libraries (~40 ms) but makes no context. Returns out. */
char *gl_context_backends_report(char *out, size_t outlen);

#endif
