/* test_dynlib.c: the libraries only drawing needs are opened at run time.
 * dynlib opens a library and finds a function in it (cos from
 * libm gives cos(pi/3) = 1/2) or says which library, which package; the
 * binary does not link OSMesa, EGL or libav* (its ELF NEEDED list); and,
 * with one of them made unloadable (a mount namespace binds /dev/null over
 * the file), a run that draws exits 1 naming the library and the Debian
 * package and leaves no video, while --help and --no-video runs do not
 * notice; with one GL backend missing, the default draws with the other. */
#define _GNU_SOURCE /* dladdr */
#include <dlfcn.h>
#include <libavcodec/avcodec.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "render/dynlib.h"
#include "render/gl_context.h"
#include "test.h"
#include "test_process.h"

static char tmp_dir[] = "/tmp/rodsim_dynlib_XXXXXX";

static void test_open_and_symbol(void)
{
    char err[512] = "";
    const char *libm[] = {"libm.so.6", NULL};
    void *lib = dynlib_open(libm, "libc6", err, sizeof err);
    dynlib_function f = lib ? dynlib_symbol(lib, "libm.so.6", "cos", err, sizeof err) : NULL;
    double value = f ? ((double (*)(double))f)(acos(-1.0) / 3) : NAN;
    check_rel("dynlib: cos(pi/3) through libm.so.6 opened at run time", value, 0.5, 1e-15);

    err[0] = '\0';
    dynlib_function none = lib ? dynlib_symbol(lib, "libm.so.6", "no_such_function", err,
                                               sizeof err) : NULL;
    check(lib && !none && strstr(err, "libm.so.6") && strstr(err, "no_such_function"),
          "dynlib: a missing function is NULL, message '%s' names it and the library", err);

    err[0] = '\0';
    const char *missing[] = {"librodsim_missing.so.3", "librodsim_missing.so", NULL};
    void *nothing = dynlib_open(missing, "rodsim-missing3", err, sizeof err);
    check(!nothing && strstr(err, "librodsim_missing.so.3, librodsim_missing.so") &&
              strstr(err, "install the Debian package rodsim-missing3"),
          "dynlib: a missing library is NULL, message '%s' names every name tried and the "
          "package", err);
}

/* The binary's NEEDED entries (readelf -d): what the loader maps at start. */
static void test_not_linked(void)
{
    char command[512], line[512], needed[2048] = "";
    snprintf(command, sizeof command, "readelf -d '%s' 2>/dev/null", RODSIM_BIN);
    FILE *p = popen(command, "r");
    int entries = 0;
    while (p && fgets(line, sizeof line, p))
        if (strstr(line, "(NEEDED)")) {
            entries++;
            char *name = strchr(line, '[');
            if (name && strlen(needed) + strlen(name) < sizeof needed - 2) strcat(needed, name);
        }
    if (p) pclose(p);
    for (char *c = needed; *c; c++)
        if (*c == '\n') *c = ' ';
    const char *unwanted[] = {"libOSMesa", "libEGL", "libavcodec", "libavformat", "libavutil",
                              "libswscale", "libGL", NULL};
    const char *found = NULL;
    for (int i = 0; unwanted[i]; i++)
        if (strstr(needed, unwanted[i])) found = unwanted[i];
    check(entries > 0 && !found, "%s NEEDED: %s(%s linked)", RODSIM_BIN, needed,
          found ? found : "neither OSMesa, EGL nor libav*");
}

/* The file the loader opens for `soname`, into path; 0 when found. */
static int library_file(const char *soname, const char *symbol, char *path, size_t pathlen)
{
    void *lib = dlopen(soname, RTLD_NOW | RTLD_LOCAL);
    void *address = lib ? dlsym(lib, symbol) : NULL;
    Dl_info info;
    if (!address || !dladdr(address, &info) || !info.dli_fname) return -1;
    /* resolve the links: binding over the real file hides every name of it */
    char *real = realpath(info.dli_fname, NULL);
    if (!real) return -1;
    snprintf(path, pathlen, "%s", real);
    free(real);
    return 0;
}

/* Runs rodsim `args` with `library` replaced by an empty file and RODSIM_GL
 * = gl ("" unset). Output (stdout and stderr) into output; returns the exit
 * status, -2 when no namespace could be made. */
static int run_without(const char *library, const char *gl, const char *args, char *output,
                       size_t outlen)
{
    char command[2048], log[160];
    snprintf(log, sizeof log, "%s/log", tmp_dir);
    snprintf(command, sizeof command,
             "unshare -rm sh -c 'mount --bind /dev/null \"$0\" && exec \"$@\"' '%s' "
             "env %s%s '%s' %s >'%s' 2>&1",
             library, gl[0] ? "RODSIM_GL=" : "-u RODSIM_GL", gl, RODSIM_BIN, args, log);
    fflush(stdout);
    int status = system(command);
    output[0] = '\0';
    FILE *f = fopen(log, "r");
    if (f) {
        output[fread(output, 1, outlen - 1, f)] = '\0';
        fclose(f);
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/* The line of output that has `word` (or the first line), one line, into line. */
static const char *line_with(const char *output, const char *word, char *line, size_t linelen)
{
    const char *at = strstr(output, word);
    if (!at) at = output;
    while (at > output && at[-1] != '\n') at--;
    size_t n = strcspn(at, "\n");
    snprintf(line, linelen, "%.*s", (int)(n < linelen ? n : linelen - 1), at);
    return line;
}

/* A run that draws with `library` replaced by an empty file and RODSIM_GL =
 * gl: refused with exit 1 naming `names` (the library the user must get)
 * and `package`, no video left; or, when package is NULL, drawn (exit 0)
 * by the backend `names` (the other one: the default falls back). */
static void check_drawing_run(const char *library, const char *gl, const char *names,
                              const char *package)
{
    char output[8192], args[1024], out[160], mp4[200], line[512];
    snprintf(out, sizeof out, "%s/out", tmp_dir);
    snprintf(args, sizeof args,
             "run '%s/scenes/suture_cantilever.ini' -o '%s' --set solver.duration=0.1 --set render.width=160 "
             "--set render.height=120",
             RODSIM_SOURCE_DIR, out);
    int status = run_without(library, gl, args, output, sizeof output);
    snprintf(mp4, sizeof mp4, "%s/suture_cantilever.mp4", out);
    int written = access(mp4, F_OK) == 0;
    if (package) {
        check(status == 1 && strstr(output, names) && strstr(output, package) && !written,
              "without %s, RODSIM_GL=%s: a run that draws exits %d (want 1), message '%s' names "
              "%s and package %s; %s %s", library, gl, status,
              line_with(output, package, line, sizeof line), names, package, mp4,
              written ? "WRITTEN" : "not written");
    } else {
        char drawn[64];
        snprintf(drawn, sizeof drawn, "drawn by %s)", names);
        check(status == 0 && strstr(output, drawn) && written,
              "without %s, RODSIM_GL %s: the run exits %d (want 0) and says '%s' (want '%s')",
              library, gl[0] ? gl : "unset", status,
              line_with(output, "drawn by", line, sizeof line), drawn);
    }
    test_remove_tree(out);
}

/* A run without video and --help do not load the library: they do not notice. */
static void check_not_drawing(const char *library)
{
    char output[8192], args[1024], out[160], line[512];
    snprintf(out, sizeof out, "%s/out", tmp_dir);
    snprintf(args, sizeof args, "run '%s/scenes/suture_cantilever.ini' -o '%s' --set solver.duration=0.1 "
                                "--no-video --quiet", RODSIM_SOURCE_DIR, out);
    int status = run_without(library, "", args, output, sizeof output);
    check(status == 0, "without %s: run --no-video exits %d (want 0) %s", library, status,
          line_with(output, "rodsim", line, sizeof line));
    status = run_without(library, "", "--help", output, sizeof output);
    check(status == 0, "without %s: --help exits %d (want 0) %s", library, status,
          line_with(output, "rodsim", line, sizeof line));
    test_remove_tree(out);
}

/* The file of `soname` (found by `symbol` in it), or the file a mapping of
 * this process ends in (`tail`, for a library the loader does not find by
 * name, Mesa's dri/swrast_dri.so), into path; 0 when found. */
static int mapped_file(const char *tail, char *path, size_t pathlen)
{
    FILE *f = fopen("/proc/self/maps", "r");
    char line[1024];
    int found = 0;
    while (!found && f && fgets(line, sizeof line, f)) {
        char *file = strchr(line, '/');
        if (!file) continue;
        file[strcspn(file, "\n")] = '\0';
        size_t n = strlen(file), t = strlen(tail);
        if (n >= t && strcmp(file + n - t, tail) == 0) {
            snprintf(path, pathlen, "%s", file);
            found = 1;
        }
    }
    if (f) fclose(f);
    return found ? 0 : -1;
}

/* two backends. Without OSMesa (a Mesa of 25.1 or later) the
 * default draws with EGL; without EGL, with OSMesa; a backend asked for by
 * RODSIM_GL but missing stops the run naming what to install: libEGL.so.1
 * (libegl1), Mesa's EGL driver (libegl-mesa0), its llvmpipe swrast_dri.so
 * (libgl1-mesa-dri). */
static void test_backends_missing(void)
{
    char library[1024];
    if (library_file("libOSMesa.so.8", "OSMesaGetProcAddress", library, sizeof library) == 0) {
        check_drawing_run(library, "osmesa", "libOSMesa.so.8", "libosmesa6");
        check_drawing_run(library, "", "EGL", NULL);
        check_not_drawing(library);
    } else {
        check(0, "cannot find the file of libOSMesa.so.8");
    }
    if (library_file("libEGL.so.1", "eglGetProcAddress", library, sizeof library) == 0) {
        check_drawing_run(library, "egl", "libEGL.so.1", "libegl1");
        check_drawing_run(library, "", "OSMesa", NULL);
    } else {
        check(0, "cannot find the file of libEGL.so.1");
    }
    if (library_file("libEGL_mesa.so.0", "__egl_Main", library, sizeof library) == 0)
        check_drawing_run(library, "egl", "EGL_MESA_device_software", "libegl-mesa0");
    else
        check(0, "cannot find the file of libEGL_mesa.so.0");
    /* Mesa loads swrast_dri.so by path: an EGL context made here maps it */
    char err[512];
    setenv("RODSIM_GL", "egl", 1);
    gl_context *ctx = gl_context_create(16, 16, err, sizeof err);
    if (ctx && mapped_file("/swrast_dri.so", library, sizeof library) == 0)
        check_drawing_run(library, "egl", "software device", "libgl1-mesa-dri");
    else
        check(0, "cannot find the file of swrast_dri.so (%s)", ctx ? "not mapped" : err);
    gl_context_destroy(ctx);
    unsetenv("RODSIM_GL");
}

static void test_missing_at_run_time(const char *soname, const char *symbol, const char *package)
{
    char library[1024];
    if (library_file(soname, symbol, library, sizeof library)) {
        check(0, "cannot find the file of %s", soname);
        return;
    }
    check_drawing_run(library, "", soname, package);
    check_not_drawing(library);
}

int main(void)
{
    test_open_and_symbol();
    test_not_linked();
    if (!mkdtemp(tmp_dir)) {
        check(0, "cannot make a scratch directory");
        return test_finish();
    }
    if (system("unshare -rm true >/dev/null 2>&1") == 0) {
        test_backends_missing();
        /* the major version the build compiled against, as video.c asks for */
        char soname[64], package[64];
        snprintf(soname, sizeof soname, "libavcodec.so.%d", LIBAVCODEC_VERSION_MAJOR);
        snprintf(package, sizeof package, "libavcodec%d", LIBAVCODEC_VERSION_MAJOR);
        test_missing_at_run_time(soname, "avcodec_open2", package);
    } else {
        printf("note: no mount namespace here (unshare -rm): the missing-library runs are "
               "skipped\n");
    }
    test_remove_tree(tmp_dir);
    return test_finish();
}
