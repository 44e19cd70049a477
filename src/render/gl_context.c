/* gl_context.c: the EGL and OSMesa contexts (see gl_context.h). The only
 * file that includes EGL or OSMesa. The libraries are opened (dlopen) when
 * the first context is made, not linked: loading them (and LLVM) cost every
 * start of the program ~40 ms, drawing or not. */
#define GL_API_LOADER_ONLY
#include "render/gl_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/osmesa.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "render/dynlib.h"
#include "render/gl_api.h"

enum { BACKEND_EGL, BACKEND_OSMESA, BACKEND_COUNT };
/* In the default order: EGL first, since Mesa 25.1 has no OSMesa */
static const char *const backend_names[BACKEND_COUNT] = {"EGL", "OSMesa"};
static const char *const backend_values[BACKEND_COUNT] = {"egl", "osmesa"};

typedef const GLubyte *(*get_string_fn)(GLenum);

/* ---- OSMesa ---- */

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

static gl_proc osmesa_gl_proc(const char *name) { return (gl_proc)osmesa.get_proc_address(name); }

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
}

/* ---- EGL ---- */

/* The EGL entry points used, typed as egl.h / eglext.h declare them */
_Static_assert(_Generic(&eglGetProcAddress, PFNEGLGETPROCADDRESSPROC: 1, default: 0) &&
                   _Generic(&eglCreateContext, PFNEGLCREATECONTEXTPROC: 1, default: 0) &&
                   _Generic(&eglMakeCurrent, PFNEGLMAKECURRENTPROC: 1, default: 0),
               "the EGL pointer types match <EGL/egl.h>");

static struct {
    PFNEGLGETPROCADDRESSPROC get_proc_address;
    PFNEGLGETERRORPROC get_error;
    PFNEGLQUERYSTRINGPROC query_string;
    PFNEGLINITIALIZEPROC initialize;
    PFNEGLBINDAPIPROC bind_api;
    PFNEGLCHOOSECONFIGPROC choose_config;
    PFNEGLCREATEPBUFFERSURFACEPROC create_pbuffer_surface;
    PFNEGLCREATECONTEXTPROC create_context;
    PFNEGLMAKECURRENTPROC make_current;
    PFNEGLGETCURRENTCONTEXTPROC get_current_context;
    PFNEGLDESTROYCONTEXTPROC destroy_context;
    PFNEGLDESTROYSURFACEPROC destroy_surface;
    /* extensions (eglGetProcAddress) */
    PFNEGLQUERYDEVICESEXTPROC query_devices;
    PFNEGLQUERYDEVICESTRINGEXTPROC query_device_string;
    PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display;
    EGLDisplay display; /* initialised once, kept for the process, as the library */
    EGLConfig config;
} egl;

/* glvnd's libEGL.so.1 (Debian libegl1): it dispatches to Mesa's
 * libEGL_mesa.so.0 (libegl-mesa0), which draws with llvmpipe from
 * swrast_dri.so (libgl1-mesa-dri). */
static const char *const egl_sonames[] = {"libEGL.so.1", NULL};
static pthread_once_t egl_once = PTHREAD_ONCE_INIT;
static char egl_error[512]; /* empty once a display is initialised */

/* EGL's error codes by name, for messages */
static const char *egl_error_name(EGLint code)
{
    static const struct {
        EGLint code;
        const char *name;
    } names[] = {{EGL_SUCCESS, "EGL_SUCCESS"},
                 {EGL_NOT_INITIALIZED, "EGL_NOT_INITIALIZED"},
                 {EGL_BAD_ACCESS, "EGL_BAD_ACCESS"},
                 {EGL_BAD_ALLOC, "EGL_BAD_ALLOC"},
                 {EGL_BAD_ATTRIBUTE, "EGL_BAD_ATTRIBUTE"},
                 {EGL_BAD_CONFIG, "EGL_BAD_CONFIG"},
                 {EGL_BAD_CONTEXT, "EGL_BAD_CONTEXT"},
                 {EGL_BAD_CURRENT_SURFACE, "EGL_BAD_CURRENT_SURFACE"},
                 {EGL_BAD_DISPLAY, "EGL_BAD_DISPLAY"},
                 {EGL_BAD_MATCH, "EGL_BAD_MATCH"},
                 {EGL_BAD_NATIVE_PIXMAP, "EGL_BAD_NATIVE_PIXMAP"},
                 {EGL_BAD_NATIVE_WINDOW, "EGL_BAD_NATIVE_WINDOW"},
                 {EGL_BAD_PARAMETER, "EGL_BAD_PARAMETER"},
                 {EGL_BAD_SURFACE, "EGL_BAD_SURFACE"},
                 {EGL_CONTEXT_LOST, "EGL_CONTEXT_LOST"}};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (names[i].code == code) return names[i].name;
    return "an unknown EGL error";
}

static gl_proc egl_gl_proc(const char *name) { return (gl_proc)egl.get_proc_address(name); }

/* 1 when the space-separated list has the extension */
static int has_extension(const char *list, const char *name)
{
    size_t n = strlen(name);
    for (const char *p = list; p && (p = strstr(p, name)); p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return 1;
    return 0;
}

/* Mesa's software device (llvmpipe), or NULL with a message. Decision: the
 * device platform's software device, never the surfaceless platform, which
 * would pick a GPU's render node where there is one: the frames stay those
 * of llvmpipe (the same as OSMesa's) on every machine. */
static EGLDeviceEXT egl_software_device(char *err, size_t errlen)
{
    const char *client = egl.query_string(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    /* glvnd's libEGL.so.1 without a vendor library (libEGL_mesa.so.0) has
     * neither the device extensions nor a device */
    if (has_extension(client, "EGL_EXT_platform_device") &&
        has_extension(client, "EGL_EXT_device_enumeration")) {
        egl.query_devices = (PFNEGLQUERYDEVICESEXTPROC)egl.get_proc_address("eglQueryDevicesEXT");
        egl.query_device_string =
            (PFNEGLQUERYDEVICESTRINGEXTPROC)egl.get_proc_address("eglQueryDeviceStringEXT");
        egl.get_platform_display =
            (PFNEGLGETPLATFORMDISPLAYEXTPROC)egl.get_proc_address("eglGetPlatformDisplayEXT");
        if (egl.query_devices && egl.query_device_string && egl.get_platform_display &&
            egl.query_devices(16, devices, &count))
            for (EGLint i = 0; i < count; i++)
                if (has_extension(egl.query_device_string(devices[i], EGL_EXTENSIONS),
                                  "EGL_MESA_device_software")) {
                    if (has_extension(client, "EGL_KHR_client_get_all_proc_addresses"))
                        return devices[i];
                    /* else core GL would need libOpenGL.so.0 too: not worth it */
                    snprintf(err, errlen, "EGL lacks EGL_KHR_client_get_all_proc_addresses");
                    return NULL;
                }
    }
    snprintf(err, errlen, "EGL offers no software device (EGL_MESA_device_software; %d "
                          "device(s) found): Mesa's EGL driver libEGL_mesa.so.0 is missing; "
                          "install the Debian package libegl-mesa0", (int)count);
    return NULL;
}

static void egl_open(void)
{
    char *err = egl_error;
    size_t errlen = sizeof egl_error;
    void *lib = dynlib_open(egl_sonames, "libegl1", err, errlen);
    if (!lib) return;
    const char *soname = "libEGL.so.1";
    dynlib_function f[12];
    const char *const names[12] = {"eglGetProcAddress",       "eglGetError",
                                   "eglQueryString",          "eglInitialize",
                                   "eglBindAPI",              "eglChooseConfig",
                                   "eglCreatePbufferSurface", "eglCreateContext",
                                   "eglMakeCurrent",          "eglGetCurrentContext",
                                   "eglDestroyContext",       "eglDestroySurface"};
    for (int i = 0; i < 12; i++)
        if (!(f[i] = dynlib_symbol(lib, soname, names[i], err, errlen))) return;
    egl.get_proc_address = (PFNEGLGETPROCADDRESSPROC)f[0];
    egl.get_error = (PFNEGLGETERRORPROC)f[1];
    egl.query_string = (PFNEGLQUERYSTRINGPROC)f[2];
    egl.initialize = (PFNEGLINITIALIZEPROC)f[3];
    egl.bind_api = (PFNEGLBINDAPIPROC)f[4];
    egl.choose_config = (PFNEGLCHOOSECONFIGPROC)f[5];
    egl.create_pbuffer_surface = (PFNEGLCREATEPBUFFERSURFACEPROC)f[6];
    egl.create_context = (PFNEGLCREATECONTEXTPROC)f[7];
    egl.make_current = (PFNEGLMAKECURRENTPROC)f[8];
    egl.get_current_context = (PFNEGLGETCURRENTCONTEXTPROC)f[9];
    egl.destroy_context = (PFNEGLDESTROYCONTEXTPROC)f[10];
    egl.destroy_surface = (PFNEGLDESTROYSURFACEPROC)f[11];

    EGLDeviceEXT device = egl_software_device(err, errlen);
    if (!device) return;
    EGLDisplay display = egl.get_platform_display(EGL_PLATFORM_DEVICE_EXT, device, NULL);
    EGLint major = 0, minor = 0;
    if (display == EGL_NO_DISPLAY || !egl.initialize(display, &major, &minor)) {
        /* Mesa cannot load its software rasteriser (dri/swrast_dri.so) */
        snprintf(err, errlen, "EGL cannot initialise Mesa's software device (%s); install the "
                              "Debian package libgl1-mesa-dri (llvmpipe, dri/swrast_dri.so)",
                 egl_error_name(egl.get_error()));
        return;
    }
    const EGLint config_attributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT,
                                        EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                                        EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8,
                                        EGL_ALPHA_SIZE, 8, EGL_DEPTH_SIZE, 24, EGL_NONE};
    EGLint configs = 0;
    if (!egl.choose_config(display, config_attributes, &egl.config, 1, &configs) ||
        configs < 1) {
        snprintf(err, errlen, "EGL %d.%d on Mesa's software device offers no RGBA8 pbuffer "
                              "config for desktop OpenGL (%s)", (int)major, (int)minor,
                 egl_error_name(egl.get_error()));
        return;
    }
    egl.display = display;
}

/* ---- the context, either backend ---- */

struct gl_context {
    int backend;
    int width, height;     /* the default framebuffer */
    OSMesaContext osmesa;
    unsigned char *buffer; /* OSMesa's default framebuffer, RGBA */
    EGLContext egl;
    EGLSurface surface;    /* EGL's default framebuffer, a pbuffer */
    char description[256];
};

static gl_context *create_osmesa(gl_context *ctx, int width, int height, char *err,
                                 size_t errlen)
{
    /* Core 3.3 first: the shaders are GLSL 330 core. */
    const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                              OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                              OSMESA_CONTEXT_MAJOR_VERSION, 3, OSMESA_CONTEXT_MINOR_VERSION, 3,
                              0};
    ctx->osmesa = osmesa.create_context(attributes, NULL);
    if (!ctx->osmesa) {
        snprintf(err, errlen, "gl: OSMesa could not create an OpenGL 3.3 core context "
                              "(libosmesa6 with llvmpipe is needed)");
        gl_context_destroy(ctx);
        return NULL;
    }
    ctx->buffer = malloc((size_t)width * (size_t)height * 4);
    if (!ctx->buffer ||
        !osmesa.make_current(ctx->osmesa, ctx->buffer, GL_UNSIGNED_BYTE, width, height)) {
        snprintf(err, errlen, "gl: cannot make the OSMesa context current (%dx%d)", width, height);
        gl_context_destroy(ctx);
        return NULL;
    }
    return ctx;
}

static gl_context *create_egl(gl_context *ctx, int width, int height, char *err, size_t errlen)
{
    const EGLint surface_attributes[] = {EGL_WIDTH, width, EGL_HEIGHT, height, EGL_NONE};
    const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3,
                                         EGL_CONTEXT_MINOR_VERSION, 3,
                                         EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                         EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    /* the API is a per-thread state: bound on the thread that draws */
    if (!egl.bind_api(EGL_OPENGL_API)) {
        snprintf(err, errlen, "gl: EGL cannot bind desktop OpenGL (%s)",
                 egl_error_name(egl.get_error()));
        gl_context_destroy(ctx);
        return NULL;
    }
    ctx->surface = egl.create_pbuffer_surface(egl.display, egl.config, surface_attributes);
    if (ctx->surface == EGL_NO_SURFACE) {
        snprintf(err, errlen, "gl: EGL cannot create a %dx%d pbuffer (%s)", width, height,
                 egl_error_name(egl.get_error()));
        gl_context_destroy(ctx);
        return NULL;
    }
    ctx->egl = egl.create_context(egl.display, egl.config, EGL_NO_CONTEXT, context_attributes);
    if (ctx->egl == EGL_NO_CONTEXT) {
        snprintf(err, errlen, "gl: EGL could not create an OpenGL 3.3 core context (%s)",
                 egl_error_name(egl.get_error()));
        gl_context_destroy(ctx);
        return NULL;
    }
    if (!egl.make_current(egl.display, ctx->surface, ctx->surface, ctx->egl)) {
        snprintf(err, errlen, "gl: cannot make the EGL context current (%s)",
                 egl_error_name(egl.get_error()));
        gl_context_destroy(ctx);
        return NULL;
    }
    return ctx;
}

/* 1 when `value` names backend b (any case: "EGL" works too) */
static int names_backend(const char *value, int b)
{
    return strcasecmp(value, backend_values[b]) == 0;
}

int gl_context_check_env(char *err, size_t errlen)
{
    const char *value = getenv("RODSIM_GL");
    if (!value || !value[0]) return 0;
    for (int b = 0; b < BACKEND_COUNT; b++)
        if (names_backend(value, b)) return 0;
    snprintf(err, errlen, "RODSIM_GL=%s: no such OpenGL backend; accepted: egl, osmesa "
                          "(unset or empty: EGL, then OSMesa)", value);
    return -1;
}

/* The process's backend, chosen once (the GL function table serves one):
 * RODSIM_GL's, or the first that opens. */
static pthread_once_t choose_once = PTHREAD_ONCE_INIT;
static int chosen = -1;
static char choose_error[1200];

/* Opens backend b; its message, or "" when it can be used. */
static const char *backend_open(int b)
{
    if (b == BACKEND_EGL) {
        pthread_once(&egl_once, egl_open);
        return egl_error;
    }
    pthread_once(&osmesa_once, osmesa_open);
    return osmesa_error;
}

static void choose_backend(void)
{
    char *err = choose_error;
    size_t errlen = sizeof choose_error;
    if (gl_context_check_env(err, errlen)) return;
    const char *value = getenv("RODSIM_GL");
    int b;
    for (b = 0; b < BACKEND_COUNT; b++) {
        if (value && value[0] && !names_backend(value, b)) continue;
        if (!backend_open(b)[0]) break;
    }
    if (b == BACKEND_COUNT) {
        if (value && value[0]) {
            for (b = 0; !names_backend(value, b); b++) continue;
            snprintf(err, errlen, "%s (RODSIM_GL=%s)", backend_open(b), value);
        } else {
            snprintf(err, errlen, "no OpenGL backend: EGL: %s; OSMesa: %s",
                     backend_open(BACKEND_EGL), backend_open(BACKEND_OSMESA));
        }
        return;
    }
    /* Mesa's GL entry points are dispatch stubs, the same for every context
     * of a backend: one table, filled once (no current context needed: OSMesa,
     * and EGL with EGL_KHR_client_get_all_proc_addresses) */
    if (gl_functions_load(b == BACKEND_EGL ? egl_gl_proc : osmesa_gl_proc, err, errlen)) return;
    chosen = b;
}

/* The context current on this thread, as far as gl_context knows. */
static _Thread_local gl_context *current_context;

int gl_context_make_current(gl_context *ctx)
{
    if (ctx == current_context) return 0;
    int made = ctx->backend == BACKEND_EGL
                   ? egl.make_current(egl.display, ctx->surface, ctx->surface, ctx->egl) != 0
                   : osmesa.make_current(ctx->osmesa, ctx->buffer, GL_UNSIGNED_BYTE, ctx->width,
                                         ctx->height) != 0;
    if (!made) return -1;
    current_context = ctx;
    return 0;
}

gl_context *gl_context_create(int width, int height, char *err, size_t errlen)
{
    if (width <= 0 || height <= 0 || width > 16384 || height > 16384) {
        snprintf(err, errlen, "gl: framebuffer size %dx%d is outside 1..16384", width, height);
        return NULL;
    }
    pthread_once(&choose_once, choose_backend);
    if (chosen < 0) {
        snprintf(err, errlen, "gl: %s", choose_error);
        return NULL;
    }
    gl_context *ctx = calloc(1, sizeof *ctx);
    if (!ctx) {
        snprintf(err, errlen, "gl: out of memory");
        return NULL;
    }
    ctx->backend = chosen;
    ctx->width = width;
    ctx->height = height;
    ctx = chosen == BACKEND_EGL ? create_egl(ctx, width, height, err, errlen)
                                : create_osmesa(ctx, width, height, err, errlen);
    if (!ctx) return NULL;
    current_context = ctx;
    gl_proc (*get_proc)(const char *) = chosen == BACKEND_EGL ? egl_gl_proc : osmesa_gl_proc;
    get_string_fn get_string = (get_string_fn)get_proc("glGetString");
    snprintf(ctx->description, sizeof ctx->description, "%s: OpenGL %s, %s",
             backend_names[chosen], (const char *)get_string(GL_VERSION),
             (const char *)get_string(GL_RENDERER));
    return ctx;
}

void gl_context_destroy(gl_context *ctx)
{
    if (!ctx) return;
    if (current_context == ctx) current_context = NULL;
    if (ctx->osmesa) osmesa.destroy_context(ctx->osmesa);
    free(ctx->buffer);
    if (ctx->egl && egl.get_current_context() == ctx->egl)
        egl.make_current(egl.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (ctx->egl) egl.destroy_context(egl.display, ctx->egl);
    if (ctx->surface) egl.destroy_surface(egl.display, ctx->surface);
    free(ctx);
}

const char *gl_context_description(const gl_context *ctx) { return ctx->description; }

const char *gl_context_backend(const gl_context *ctx) { return backend_names[ctx->backend]; }

const char *gl_context_backend_used(void) { return chosen >= 0 ? backend_names[chosen] : NULL; }

char *gl_context_backends_report(char *out, size_t outlen)
{
    static const char *const what[BACKEND_COUNT] = {"libEGL.so.1, Mesa's software device",
                                                    "libOSMesa.so.8"};
    size_t used = 0;
    out[0] = '\0';
    int first = -1;
    for (int b = 0; b < BACKEND_COUNT && used < outlen; b++) {
        const char *why_not = backend_open(b);
        if (!why_not[0] && first < 0) first = b;
        used += (size_t)snprintf(out + used, outlen - used, "%-7s %s%s\n", backend_names[b],
                                 why_not[0] ? "unavailable: " : "available: ",
                                 why_not[0] ? why_not : what[b]);
    }
    if (used >= outlen) return out;
    char err[256];
    const char *value = getenv("RODSIM_GL");
    int b = 0;
    if (gl_context_check_env(err, sizeof err)) {
        snprintf(out + used, outlen - used, "%s\n", err);
    } else if (value && value[0]) {
        while (!names_backend(value, b)) b++;
        if (backend_open(b)[0])
            snprintf(out + used, outlen - used, "RODSIM_GL=%s: %s is unavailable: drawing fails\n",
                     value, backend_names[b]);
        else
            snprintf(out + used, outlen - used, "RODSIM_GL=%s: draws with %s\n", value,
                     backend_names[b]);
    } else if (first < 0) {
        snprintf(out + used, outlen - used, "RODSIM_GL unset: none is available: drawing fails\n");
    } else {
        snprintf(out + used, outlen - used,
                 "RODSIM_GL unset: draws with %s (RODSIM_GL=egl|osmesa chooses)\n",
                 backend_names[first]);
    }
    return out;
}
