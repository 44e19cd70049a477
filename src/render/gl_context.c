/* gl_context.c: the OSMesa context (see gl_context.h). The only file that
 * includes OSMesa. The library is opened (dlopen) when the first context is
 * made, not linked: loading OSMesa and LLVM cost every start of the program
 * ~40 ms, drawing or not. */
#define GL_API_LOADER_ONLY
#include "render/gl_context.h"

#include <GL/osmesa.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>

#include "render/dynlib.h"
#include "render/gl_api.h"

/* The OSMesa entry points used, typed as osmesa.h declares them (checked) */
typedef OSMesaContext (*create_context_fn)(const int *attributes, OSMesaContext share);
typedef GLboolean (*make_current_fn)(OSMesaContext, void *buffer, GLenum type, GLsizei width,
                                     GLsizei height);
typedef void (*destroy_context_fn)(OSMesaContext);
typedef OSMESAproc (*get_proc_address_fn)(const char *name);
_Static_assert(_Generic(&OSMesaCreateContextAttribs, create_context_fn: 1, default: 0) &&
                   _Generic(&OSMesaMakeCurrent, make_current_fn: 1, default: 0) &&
                   _Generic(&OSMesaDestroyContext, destroy_context_fn: 1, default: 0) &&
                   _Generic(&OSMesaGetProcAddress, get_proc_address_fn: 1, default: 0),
               "the OSMesa pointer types match <GL/osmesa.h>");

static struct {
    create_context_fn create_context;
    make_current_fn make_current;
    destroy_context_fn destroy_context;
    get_proc_address_fn get_proc_address;
} osmesa;

/* Debian 12's libosmesa6 ships libOSMesa.so.8 (and .6, a link to it) */
static const char *const osmesa_sonames[] = {"libOSMesa.so.8", "libOSMesa.so.6", NULL};
static pthread_once_t osmesa_once = PTHREAD_ONCE_INIT;
static char osmesa_error[512]; /* empty once the library is usable */

static gl_proc get_gl_proc(const char *name) { return (gl_proc)osmesa.get_proc_address(name); }

static void osmesa_open(void)
{
    char *err = osmesa_error;
    size_t errlen = sizeof osmesa_error;
    void *lib = dynlib_open(osmesa_sonames, "libosmesa6", err, errlen);
    if (!lib) return;
    const char *soname = "libOSMesa";
    dynlib_function create, make_current, destroy, get_proc;
    if (!(create = dynlib_symbol(lib, soname, "OSMesaCreateContextAttribs", err, errlen)) ||
        !(make_current = dynlib_symbol(lib, soname, "OSMesaMakeCurrent", err, errlen)) ||
        !(destroy = dynlib_symbol(lib, soname, "OSMesaDestroyContext", err, errlen)) ||
        !(get_proc = dynlib_symbol(lib, soname, "OSMesaGetProcAddress", err, errlen)))
        return;
    osmesa.create_context = (create_context_fn)create;
    osmesa.make_current = (make_current_fn)make_current;
    osmesa.destroy_context = (destroy_context_fn)destroy;
    osmesa.get_proc_address = (get_proc_address_fn)get_proc;
    /* Mesa's GL entry points are dispatch stubs, the same for every context:
     * one table, filled once (GetProcAddress needs no current context) */
    gl_functions_load(get_gl_proc, err, errlen);
}

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
    pthread_once(&osmesa_once, osmesa_open);
    if (osmesa_error[0]) {
        snprintf(err, errlen, "gl: %s", osmesa_error);
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
    ctx->osmesa = osmesa.create_context(attributes, NULL);
    if (!ctx->osmesa) {
        snprintf(err, errlen, "gl: OSMesa could not create an OpenGL 3.3 core context "
                              "(libosmesa6 with llvmpipe is needed)");
        free(ctx);
        return NULL;
    }
    ctx->buffer = malloc((size_t)width * (size_t)height * 4);
    if (!ctx->buffer ||
        !osmesa.make_current(ctx->osmesa, ctx->buffer, GL_UNSIGNED_BYTE, width, height)) {
        snprintf(err, errlen, "gl: cannot make the OSMesa context current (%dx%d)", width, height);
        gl_context_destroy(ctx);
        return NULL;
    }
    typedef const GLubyte *(*get_string_fn)(GLenum);
    get_string_fn get_string = (get_string_fn)get_gl_proc("glGetString");
    snprintf(ctx->description, sizeof ctx->description, "OpenGL %s, %s",
             (const char *)get_string(GL_VERSION), (const char *)get_string(GL_RENDERER));
    return ctx;
}

void gl_context_destroy(gl_context *ctx)
{
    if (!ctx) return;
    if (ctx->osmesa) osmesa.destroy_context(ctx->osmesa);
    free(ctx->buffer);
    free(ctx);
}

const char *gl_context_description(const gl_context *ctx) { return ctx->description; }
