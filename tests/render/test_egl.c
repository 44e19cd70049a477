/* test_egl.c: the two headless backends. RODSIM_GL is checked without
 * loading anything; then the same synthetic recording is drawn by EGL, by
 * OSMesa and by the default, each in a child process (a process keeps the
 * backend it chose first), and the frames must agree: PSNR at least 35 dB,
 * computed here from its definition. That a backend really drew is checked
 * two ways: the name the context reports, and which Mesa library the child
 * mapped (/proc/self/maps: OSMesa is libOSMesa.so, EGL's llvmpipe is
 * dri/swrast_dri.so behind libEGL_mesa.so). No skip: a backend that cannot
 * be made here is a failure naming why. Under ASan, an EGL-drawn video run
 * must exit 0 with a dynamic TLS block of its drawing thread 16 bytes past
 * a page boundary, the place whose range this GCC's LeakSanitizer misreads
 * (tests/run_tests.sh). Last, the report `rodsim version --gl` prints. */
#define _GNU_SOURCE /* dl_iterate_phdr, in <link.h> */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#ifdef __SANITIZE_ADDRESS__
#include <link.h>
#include <stdint.h>
#endif

#include "render/gl_context.h"
#include "render/image.h"
#include "render/render.h"
#include "synthetic_recording.h"
#include "test.h"
#include "test_process.h"

#define FRAMES 3
#define WIDTH 320
#define HEIGHT 240

static char tmp_dir[] = "/tmp/rodsim_egl_XXXXXX";

static void test_env_check(void)
{
    const char *good[] = {"", "egl", "osmesa", "EGL", "OSMesa"};
    char err[512];
    int accepted = 0;
    for (size_t i = 0; i < sizeof good / sizeof good[0]; i++) {
        setenv("RODSIM_GL", good[i], 1);
        accepted += gl_context_check_env(err, sizeof err) == 0;
    }
    unsetenv("RODSIM_GL");
    accepted += gl_context_check_env(err, sizeof err) == 0;
    check(accepted == 6, "RODSIM_GL unset, empty, egl, osmesa, EGL, OSMesa: %d of 6 accepted",
          accepted);
    setenv("RODSIM_GL", "vulkan", 1);
    err[0] = '\0';
    int status = gl_context_check_env(err, sizeof err);
    check(status == -1 && strstr(err, "RODSIM_GL=vulkan") && strstr(err, "egl") &&
              strstr(err, "osmesa"),
          "RODSIM_GL=vulkan refused: '%s' names the value and the accepted ones", err);
    unsetenv("RODSIM_GL");
    check(gl_context_backend_used() == NULL, "no backend chosen before a context is made");
}

/* What a child reports through its pipe. */
typedef struct child_report {
    int made;                /* gl_context_create succeeded */
    int rendered;            /* render_recording returned 0 */
    char backend[16];        /* gl_context_backend of the context */
    char used[16];           /* gl_context_backend_used after the render */
    char description[256];
    int mapped_osmesa;       /* libOSMesa.so in /proc/self/maps */
    int mapped_egl_llvmpipe; /* dri/swrast_dri.so in /proc/self/maps */
    char err[1024];
} child_report;

static void scan_maps(child_report *r)
{
    FILE *f = fopen("/proc/self/maps", "r");
    char line[1024];
    while (f && fgets(line, sizeof line, f)) {
        if (strstr(line, "/libOSMesa.so")) r->mapped_osmesa = 1;
        if (strstr(line, "/swrast_dri.so")) r->mapped_egl_llvmpipe = 1;
    }
    if (f) fclose(f);
}

/* The recording both backends draw: three frames, straight to bent, an
 * arrow in the last, over a plane and a skin pad (the shadow map's depth
 * texture and its filtered look-ups). */
static rod_recording *three_frames(render_options *o)
{
    rod_recording *rec = synthetic_recording_create(41, FRAMES, 1.0, 0.01);
    synthetic_arc(rec, 0, INFINITY, 6.0); /* straight, twisted */
    synthetic_arc(rec, 1, 1.0, 6.0);      /* bent, radius 1 m */
    synthetic_arc(rec, 2, 0.4, 6.0);      /* bent further */
    for (int f = 0; f < FRAMES; f++) rec->time[f] = 0.1 * f;
    rec->tip_force[3 * 2 + 1] = 1e-3; /* an arrow in the last frame */
    render_options_default(o);
    o->width = WIDTH;
    o->height = HEIGHT;
    snprintf(o->title, sizeof o->title, "two backends"); /* not the name, which differs */
    const recording_surface surfaces[2] = {
        {.shape = RECORDING_SURFACE_PLANE, .center = {0, 0, -0.1}, .normal = {0, 0, 1}},
        {.shape = RECORDING_SURFACE_BOX, .center = {0.5, 0.3, -0.08}, .size = {0.3, 0.2, 0.04},
         .tissue = 1}};
    synthetic_recording_surfaces(rec, surfaces, 2);
    return rec;
}

/* In the child: RODSIM_GL = value (NULL: unset), a context, then the
 * recording drawn into dir/<name>_frames/. */
static void child_draw(const char *value, const char *dir, const char *name, child_report *r)
{
    if (value) setenv("RODSIM_GL", value, 1);
    else unsetenv("RODSIM_GL");
    gl_context *ctx = gl_context_create(64, 48, r->err, sizeof r->err);
    if (!ctx) return;
    r->made = 1;
    snprintf(r->backend, sizeof r->backend, "%s", gl_context_backend(ctx));
    snprintf(r->description, sizeof r->description, "%s", gl_context_description(ctx));
    gl_context_destroy(ctx);

    render_options o;
    rod_recording *rec = three_frames(&o);
    o.frames_png = 1;
    r->rendered = render_recording(rec, &o, dir, name, 0, r->err, sizeof r->err) == 0;
    rod_recording_destroy(rec);
    const char *used = gl_context_backend_used();
    snprintf(r->used, sizeof r->used, "%s", used ? used : "none");
    scan_maps(r);
}

/* Runs body(report, arg) in a child process that ends with exit(), so that
 * LeakSanitizer checks the child too (ASan flavour); the child's report
 * (size bytes) comes back through a pipe. The child's exit status; -1 when
 * it did not exit or its report did not arrive whole. */
static int run_in_child(void (*body)(void *report, const void *arg), const void *arg,
                        void *report, size_t size)
{
    memset(report, 0, size);
    int fds[2];
    if (pipe(fds)) return -1;
    fflush(stdout);
    pid_t pid = fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        close(fds[0]);
        void *mine = calloc(1, size);
        if (mine) body(mine, arg);
        ssize_t written = mine ? write(fds[1], mine, size) : -1;
        free(mine);
        close(fds[1]);
        exit(written == (ssize_t)size ? 0 : 1);
    }
    close(fds[1]);
    size_t got = 0;
    while (got < size) {
        ssize_t n = read(fds[0], (char *)report + got, size - got);
        if (n <= 0) break;
        got += (size_t)n;
    }
    close(fds[0]);
    int status;
    if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || got != size) return -1;
    return WEXITSTATUS(status);
}

typedef struct draw_args {
    const char *value, *name; /* RODSIM_GL (NULL: unset), the frames' name */
} draw_args;

static void draw_body(void *report, const void *arg)
{
    const draw_args *a = arg;
    child_draw(a->value, tmp_dir, a->name, report);
}

/* Runs child_draw in a child process; its report into r. 0 when it ended. */
static int draw_in_child(const char *value, const char *name, child_report *r)
{
    draw_args a = {value, name};
    return run_in_child(draw_body, &a, r, sizeof *r) == 0 ? 0 : -1;
}

/* PSNR, dB, over the RGB bytes: 10 log10(255^2 / MSE); INFINITY when equal. */
static double psnr(const image *a, const image *b)
{
    double sum = 0;
    size_t n = (size_t)a->width * (size_t)a->height * 3;
    for (size_t i = 0; i < n; i++) {
        double d = (double)a->rgb[i] - (double)b->rgb[i];
        sum += d * d;
    }
    return sum == 0 ? INFINITY : 10 * log10(255.0 * 255.0 / (sum / (double)n));
}

/* Pixels unlike the top-left pixel (the background) by more than 60 in a channel */
static int drawn_pixels(const image *img)
{
    int count = 0;
    for (int i = 0; i < img->width * img->height; i++)
        for (int c = 0; c < 3; c++)
            if (abs(img->rgb[3 * i + c] - img->rgb[c]) > 60) {
                count++;
                break;
            }
    return count;
}

static image *read_frame(const char *name, int frame)
{
    char path[512], err[512];
    snprintf(path, sizeof path, "%s/%s_frames/%05d.png", tmp_dir, name, frame);
    image *img = image_read_png(path, err, sizeof err);
    if (!img) check(0, "%s: %s", path, err);
    return img;
}

static void test_backends_agree(void)
{
    /* RODSIM_GL value, the frames' name, the backend expected to draw */
    const struct {
        const char *value, *name, *backend;
    } runs[3] = {{"egl", "egl", "EGL"}, {"osmesa", "osmesa", "OSMesa"}, {NULL, "default", "EGL"}};
    child_report r[3];
    for (int k = 0; k < 3; k++) {
        int ended = draw_in_child(runs[k].value, runs[k].name, &r[k]);
        int is_egl = strcmp(runs[k].backend, "EGL") == 0;
        check(ended == 0 && r[k].made && r[k].rendered &&
                  strcmp(r[k].backend, runs[k].backend) == 0 &&
                  strcmp(r[k].used, runs[k].backend) == 0 && strstr(r[k].description, "llvmpipe"),
              "RODSIM_GL=%s: the context says %s (want %s), the render used %s: '%s'%s%s",
              runs[k].value ? runs[k].value : "(unset)", r[k].backend, runs[k].backend, r[k].used,
              r[k].description, r[k].err[0] ? "; error: " : "", r[k].err);
        check(r[k].mapped_osmesa == !is_egl && r[k].mapped_egl_llvmpipe == is_egl,
              "RODSIM_GL=%s: the process mapped libOSMesa.so %s and dri/swrast_dri.so %s "
              "(want %s only)", runs[k].value ? runs[k].value : "(unset)",
              r[k].mapped_osmesa ? "yes" : "no", r[k].mapped_egl_llvmpipe ? "yes" : "no",
              is_egl ? "swrast_dri" : "libOSMesa");
    }
    if (!r[0].rendered || !r[1].rendered) return;

    double worst = INFINITY, apart = INFINITY;
    int drawn_min = WIDTH * HEIGHT;
    for (int f = 0; f < FRAMES; f++) {
        image *egl = read_frame("egl", f), *osmesa = read_frame("osmesa", f);
        if (egl && osmesa) {
            double p = psnr(egl, osmesa);
            if (p < worst) worst = p;
            int d = drawn_pixels(egl) < drawn_pixels(osmesa) ? drawn_pixels(egl)
                                                              : drawn_pixels(osmesa);
            if (d < drawn_min) drawn_min = d;
        }
        image_destroy(egl);
        image_destroy(osmesa);
    }
    /* the measure tells pictures apart: the straight and the most bent frame */
    image *straight = read_frame("osmesa", 0), *bent = read_frame("osmesa", FRAMES - 1);
    if (straight && bent) apart = psnr(straight, bent);
    image_destroy(straight);
    image_destroy(bent);
    check(drawn_min > WIDTH * HEIGHT / 100,
          "both backends drew something: at least %d of %d pixels unlike the background in "
          "every frame", drawn_min, WIDTH * HEIGHT);
    check(worst >= 35.0 && apart < 35.0,
          "EGL and OSMesa frames agree: PSNR %.2f dB at worst over %d frames (want >= 35; %s); "
          "the straight and the bent frame of one backend: %.2f dB (< 35: the measure sees a "
          "change)", worst, FRAMES, isinf(worst) ? "identical" : "not identical", apart);
}

#ifdef __SANITIZE_ADDRESS__
/* glibc's argument to __tls_get_addr (no public header declares either):
 * a module's TLS id and an offset in its block. */
typedef struct tls_index {
    unsigned long module, offset;
} tls_index;
extern void *__tls_get_addr(tls_index *ti);

/* A module with dynamic TLS whose block this thread has not yet made. */
typedef struct tls_module {
    size_t id;    /* its TLS module id, 0: none found */
    size_t size;  /* its block, bytes */
    char name[256];
} tls_module;

/* dl_iterate_phdr callback: such a module, libLLVM when there is one (the
 * block at fault in test_run_scenes' suture.ini is libLLVM's: llvmpipe's
 * shader compiler, whose TLS the drawing thread makes at its first draw). */
static int find_tls_module(struct dl_phdr_info *info, size_t info_size, void *data)
{
    (void)info_size;
    tls_module *m = data;
    /* static TLS blocks exist from a thread's start: their data is set */
    if (!info->dlpi_tls_modid || info->dlpi_tls_data) return 0;
    for (int i = 0; i < info->dlpi_phnum; i++) {
        const ElfW(Phdr) *ph = &info->dlpi_phdr[i];
        /* alignment up to 16: glibc mallocs the block itself, unpadded */
        if (ph->p_type != PT_TLS || ph->p_align > 16) continue;
        if (m->id && !strstr(info->dlpi_name, "libLLVM")) continue;
        m->id = info->dlpi_tls_modid;
        m->size = ph->p_memsz;
        snprintf(m->name, sizeof m->name, "%s", info->dlpi_name);
    }
    return 0;
}

/* Makes this thread's block of m (glibc mallocs it at the first
 * __tls_get_addr) start 16 bytes past a page boundary; the block's address.
 * ASan hands out a size class's chunks at a steady stride: blocks of m's
 * size are taken until the next one falls there. */
static uintptr_t place_tls_block(const tls_module *m)
{
    enum { TRIES = 8192 };
    void **taken = calloc(TRIES, sizeof *taken);
    if (!taken) return 0;
    uintptr_t previous = 0, stride = 0;
    int n = 0;
    while (n < TRIES) {
        taken[n] = malloc(m->size);
        uintptr_t p = (uintptr_t)taken[n++];
        if (previous && p - previous == stride && (p + stride) % 4096 == 16) break;
        stride = p - previous;
        previous = p;
    }
    tls_index ti = {m->id, 0};
    uintptr_t block = (uintptr_t)__tls_get_addr(&ti);
    for (int i = 0; i < n; i++) free(taken[i]);
    free(taken);
    return block;
}

/* What the child of test_dynamic_tls_at_exit reports. */
typedef struct tls_report {
    char module[256];
    unsigned long block; /* address of the placed block */
    int rendered;        /* render_recording returned 0 */
    char err[1024];
} tls_report;

/* In the child: an EGL context (which loads llvmpipe and LLVM), one
 * dynamic TLS block of the drawing thread 16 bytes past a page boundary,
 * then a video drawn with EGL. */
static void tls_body(void *report, const void *arg)
{
    (void)arg;
    tls_report *r = report;
    setenv("RODSIM_GL", "egl", 1);
    gl_context *ctx = gl_context_create(64, 48, r->err, sizeof r->err);
    if (!ctx) return;
    gl_context_destroy(ctx);
    tls_module m = {0};
    dl_iterate_phdr(find_tls_module, &m);
    if (!m.id) {
        snprintf(r->err, sizeof r->err, "no module with a dynamic TLS block left to make");
        return;
    }
    snprintf(r->module, sizeof r->module, "%s", m.name);
    r->block = (unsigned long)place_tls_block(&m);
    render_options o;
    rod_recording *rec = three_frames(&o);
    o.fps = 10;
    r->rendered = render_recording(rec, &o, tmp_dir, "tls", 1, r->err, sizeof r->err) == 0;
    rod_recording_destroy(rec);
}

/* This GCC's LeakSanitizer reads the two words before a dynamic TLS block
 * that starts 16 bytes past a page boundary as the block's range, and dies
 * scanning it at exit (exit status 1, "Tracer caught signal 11") unless
 * tests/run_tests.sh turns that guess off (intercept_tls_get_addr=0). */
static void test_dynamic_tls_at_exit(void)
{
    tls_report r;
    int status = run_in_child(tls_body, NULL, &r, sizeof r);
    check(r.block % 4096 == 16,
          "a dynamic TLS block of the drawing thread placed 16 bytes past a page boundary: "
          "%s's at %#lx%s%s", r.module[0] ? r.module : "(none)", r.block,
          r.err[0] ? "; error: " : "", r.err);
    check(status == 0 && r.rendered,
          "an EGL-drawn video run with that block exits 0 under LeakSanitizer (status %d, "
          "video %s; -1: killed or no report)", status, r.rendered ? "drawn" : "not drawn");
}
#endif

/* What `rodsim version --gl` prints: both backends available here, EGL
 * first; RODSIM_GL's choice. Run last: it opens both libraries in this
 * process, which the children above must not inherit. */
static void test_report(void)
{
    char report[2048];
    unsetenv("RODSIM_GL");
    gl_context_backends_report(report, sizeof report);
    const char *egl = strstr(report, "EGL     available");
    const char *osmesa = strstr(report, "OSMesa  available");
    check(egl && osmesa && egl < osmesa && strstr(report, "RODSIM_GL unset: draws with EGL"),
          "backends report, EGL then OSMesa, both available, EGL by default:\n%s", report);
    setenv("RODSIM_GL", "osmesa", 1);
    gl_context_backends_report(report, sizeof report);
    check(strstr(report, "RODSIM_GL=osmesa: draws with OSMesa") != NULL,
          "with RODSIM_GL=osmesa:\n%s", report);
    unsetenv("RODSIM_GL");
}

int main(void)
{
    test_env_check();
    if (!mkdtemp(tmp_dir)) {
        check(0, "cannot make a scratch directory");
        return test_finish();
    }
    test_backends_agree();
#ifdef __SANITIZE_ADDRESS__
    test_dynamic_tls_at_exit();
#endif
    test_remove_tree(tmp_dir);
    test_report();
    return test_finish();
}
