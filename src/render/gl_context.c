/* gl_context.c: the OSMesa context (see gl_context.h). The only file that
 * includes OSMesa. */
#define GL_GLEXT_PROTOTYPES
#include "render/gl_context.h"

#include <GL/osmesa.h>
#include <GL/gl.h>
#include <stdio.h>
#include <stdlib.h>

struct gl_context {
    OSMesaContext osmesa;
    int width, height;
    unsigned char *buffer; /* the default framebuffer, RGBA */
    char description[256];
};

gl_context *gl_context_create(int width, int height, char *err, size_t errlen)
{
    if (width <= 0 || height <= 0 || width > 16384 || height > 16384) {
        snprintf(err, errlen, "gl: framebuffer size %dx%d is outside 1..16384", width, height);
        return NULL;
    }
    gl_context *ctx = calloc(1, sizeof *ctx);
    if (!ctx) {
        snprintf(err, errlen, "gl: out of memory");
        return NULL;
    }
    ctx->width = width;
    ctx->height = height;
    /* Core 3.3 first: the shaders are GLSL 330 core. */
    const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                              OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                              OSMESA_CONTEXT_MAJOR_VERSION, 3, OSMESA_CONTEXT_MINOR_VERSION, 3,
                              0};
    ctx->osmesa = OSMesaCreateContextAttribs(attributes, NULL);
    if (!ctx->osmesa) {
        snprintf(err, errlen, "gl: OSMesa could not create an OpenGL 3.3 core context "
                              "(libosmesa6 with llvmpipe is needed)");
        free(ctx);
        return NULL;
    }
    ctx->buffer = malloc((size_t)width * (size_t)height * 4);
    if (!ctx->buffer ||
        !OSMesaMakeCurrent(ctx->osmesa, ctx->buffer, GL_UNSIGNED_BYTE, width, height)) {
        snprintf(err, errlen, "gl: cannot make the OSMesa context current (%dx%d)", width, height);
        gl_context_destroy(ctx);
        return NULL;
    }
    snprintf(ctx->description, sizeof ctx->description, "OpenGL %s, %s",
             (const char *)glGetString(GL_VERSION), (const char *)glGetString(GL_RENDERER));
    return ctx;
}

void gl_context_destroy(gl_context *ctx)
{
    if (!ctx) return;
    if (ctx->osmesa) OSMesaDestroyContext(ctx->osmesa);
    free(ctx->buffer);
    free(ctx);
}

const char *gl_context_description(const gl_context *ctx) { return ctx->description; }
