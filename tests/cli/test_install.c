/* test_install.c: the binary works wherever it is put. A copy of
 * RODSIM_BIN in a scratch directory, run with its working directory
 * elsewhere and, where a mount namespace can be made (unshare -rm), with the
 * source tree hidden under an empty directory, renders a tiny scene (MP4 of
 * the expected frame count and size, a PNG that shows a light background and
 * a dark rod) and draws `figure impulse --quick` (its scene compiled in);
 * RODSIM_SHADER_DIR still overrides the compiled-in shaders. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "render/image.h"
#include "test.h"
#include "test_media.h"
#include "test_process.h"

static char tmp_dir[] = "/tmp/rodsim_install_XXXXXX";
static int hidden; /* 1 when the source tree is hidden from the copied binary */

static int file_size(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 ? (int)st.st_size : -1;
}

/* Runs the copied binary with `args` (a shell word list) from tmp/cwd, the
 * source tree hidden when possible, `env` (assignments) in its environment;
 * output into tmp/log. Returns the exit status. */
static int run_copy(const char *env, const char *args)
{
    char command[4096];
    const char *hide = hidden ? "unshare -rm sh -c 'mount --bind \"$0\" \"$1\" && shift && "
                                "exec \"$@\"' \"$TMP/empty\" \"$SRC\" "
                              : "";
    snprintf(command, sizeof command,
             "TMP='%s' SRC='%s'; cd \"$TMP/cwd\" && "
             "LSAN_OPTIONS=\"suppressions=$TMP/lsan.supp:print_suppressions=0\" %s "
             "%s\"$TMP/bin/rodsim\" %s >\"$TMP/log\" 2>&1",
             tmp_dir, RODSIM_SOURCE_DIR, env, hide, args);
    fflush(stdout);
    int status = system(command);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

static void print_log(void)
{
    char path[128], line[512];
    snprintf(path, sizeof path, "%s/log", tmp_dir);
    FILE *f = fopen(path, "r");
    for (int n = 0; f && n < 20 && fgets(line, sizeof line, f); n++) printf("    | %s", line);
    if (f) fclose(f);
}

static void test_run_moved(void)
{
    int status = run_copy("", "run ../suture_cantilever.ini -o out --set solver.duration=0.1 "
                              "--set render.width=320 --set render.height=240 --quiet");
    if (!check(status == 0, "moved binary: run suture_cantilever.ini exits %d (want 0)", status)) print_log();

    char mp4[128], png[128];
    snprintf(mp4, sizeof mp4, "%s/cwd/out/suture_cantilever.mp4", tmp_dir);
    snprintf(png, sizeof png, "%s/cwd/out/suture_cantilever.png", tmp_dir);
    decoded video;
    int decodes = decode_video(mp4, &video) == 0;
    /* frames at t = 0, 1/30, 2/30, 3/30 = 0.1 s */
    check(decodes && video.frames == 4 && video.width == 320 && video.height == 240,
          "moved binary: %s decodes: %d frames (want 4), %dx%d (want 320x240)", mp4,
          decodes ? video.frames : -1, decodes ? video.width : -1, decodes ? video.height : -1);
    if (decodes) decoded_release(&video);

    char err[256] = "";
    image *img = image_read_png(png, err, sizeof err);
    long light = 0, dark = 0, pixels = img ? (long)img->width * img->height : 0;
    for (long i = 0; i < pixels; i++) {
        const unsigned char *p = img->rgb + 3 * i;
        int lo = p[0] < p[1] ? (p[0] < p[2] ? p[0] : p[2]) : (p[1] < p[2] ? p[1] : p[2]);
        int hi = p[0] > p[1] ? (p[0] > p[2] ? p[0] : p[2]) : (p[1] > p[2] ? p[1] : p[2]);
        if (lo > 200) light++;    /* the light grey background (f6f7f9) */
        else if (hi < 160) dark++; /* the rod, the overlay text */
    }
    /* a black (or blank) frame fails one of the two: the background must be
     * most of the picture, and something must be drawn on it */
    check(img && light > pixels / 2 && dark > 50,
          "moved binary: %s (%d bytes): %ld of %ld pixels light (want > half), %ld dark (want > "
          "50) %s", png, file_size(png), light, pixels, dark, err);
    image_destroy(img);
}

static void test_figure_moved(void)
{
    int status = run_copy("", "figure impulse --quick --jobs 1 --out figs");
    if (!check(status == 0, "moved binary: figure impulse --quick exits %d (want 0; its scene "
                            "is compiled in)", status))
        print_log();
    char png[128], err[256] = "";
    snprintf(png, sizeof png, "%s/cwd/figs/impulse.png", tmp_dir);
    image *img = image_read_png(png, err, sizeof err);
    check(img && img->width > 0 && img->height > 0, "moved binary: %s is a PNG (%dx%d) %s", png,
          img ? img->width : 0, img ? img->height : 0, err);
    image_destroy(img);
}

/* A broken scene.frag in RODSIM_SHADER_DIR must be the one compiled. */
static void test_shader_dir_override(void)
{
    char dir[128], path[160], log_path[128], log[4096] = "";
    snprintf(dir, sizeof dir, "%s/myshaders", tmp_dir);
    mkdir(dir, 0755);
    snprintf(path, sizeof path, "%s/scene.vert", dir);
    char copy[512];
    snprintf(copy, sizeof copy, "cp '%s/shaders/scene.vert' '%s'", RODSIM_SOURCE_DIR, path);
    int copied = system(copy) == 0;
    snprintf(path, sizeof path, "%s/scene.frag", dir);
    FILE *f = fopen(path, "w");
    if (f) {
        fputs("#version 330 core\nthis is not GLSL;\n", f);
        fclose(f);
    }
    char env[192];
    snprintf(env, sizeof env, "RODSIM_SHADER_DIR='%s'", dir);
    int status = run_copy(env, "run ../suture_cantilever.ini -o out_shader --set solver.duration=0.1 "
                               "--set render.width=320 --set render.height=240 --quiet");
    snprintf(log_path, sizeof log_path, "%s/log", tmp_dir);
    f = fopen(log_path, "r");
    if (f) {
        log[fread(log, 1, sizeof log - 1, f)] = '\0';
        fclose(f);
    }
    char *nl = strchr(log, '\n');
    if (nl) *nl = '\0';
    check(copied && f && status == 1 && strstr(log, path) && strstr(log, "GLSL compile error"),
          "RODSIM_SHADER_DIR with a broken scene.frag: exit %d (want 1), message '%s' names %s "
          "and the GLSL error", status, log, path);
}

int main(void)
{
    if (!mkdtemp(tmp_dir)) {
        check(0, "cannot make a scratch directory");
        return test_finish();
    }
    char command[1024];
    snprintf(command, sizeof command,
             "cd '%s' && mkdir bin cwd empty && cp '%s' bin/rodsim && "
             "cp '%s/scenes/suture_cantilever.ini' '%s/tests/lsan.supp' .",
             tmp_dir, RODSIM_BIN, RODSIM_SOURCE_DIR, RODSIM_SOURCE_DIR);
    check(system(command) == 0, "copied %s to %s/bin (outside the source tree)", RODSIM_BIN,
          tmp_dir);
    /* the source tree hidden: proves nothing is read from it (without a
     * mount namespace, the copy still runs from elsewhere) */
    hidden = system("unshare -rm true >/dev/null 2>&1") == 0;
    printf("note: source tree %s\n", hidden ? "hidden from the binary (unshare -rm)"
                                            : "visible (no mount namespace here)");
    test_run_moved();
    test_figure_moved();
    test_shader_dir_override();
    test_remove_tree(tmp_dir);
    return test_finish();
}
