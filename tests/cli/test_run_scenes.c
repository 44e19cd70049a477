/* test_run_scenes.c: every scene in scenes/ runs and renders end to end
 * through the real binary (short duration, small frames: the scene's own
 * physics, shortened), and its video decodes to the expected frame count,
 * size and duration; the poster PNG has the video's size and is not blank. */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test.h"
#include "test_media.h"

#define WIDTH 192
#define HEIGHT 108
#define FPS 10
#define DURATION 0.5 /* s: frames at 0, 0.1, ..., 0.5 */

/* Fraction of pixels that differ from the top-left corner (the background). */
static double non_background(const image *img)
{
    long differ = 0, n = (long)img->width * img->height;
    for (long i = 0; i < n; i++)
        for (int c = 0; c < 3; c++)
            if (abs(img->rgb[3 * i + c] - img->rgb[c]) > 24) { differ++; break; }
    return (double)differ / (double)n;
}

static void run_scene(const char *dir, const char *file)
{
    char scene[512], out[] = "/tmp/rodsim_scenesXXXXXX", cmd[2048], path[1024], name[256];
    if (snprintf(scene, sizeof scene, "%s/%s", dir, file) >= (int)sizeof scene) return;
    snprintf(name, sizeof name, "%.*s", (int)(strlen(file) - 4), file);
    if (!mkdtemp(out)) {
        check(0, "mkdtemp");
        return;
    }
    snprintf(cmd, sizeof cmd,
             "%s run %s --quiet -o %s --set solver.duration=%g --set render.fps=%d --set render.speed=1 "
             "--set render.slow_motion=none "
             "--set render.width=%d --set render.height=%d > %s/log.txt 2>&1",
             RODSIM_BIN, scene, out, DURATION, FPS, WIDTH, HEIGHT, out);
    int status = system(cmd);
    check(status == 0, "%s: rodsim run exits 0 (status %d)", name, status);
    snprintf(path, sizeof path, "%s/%s.mp4", out, name);
    decoded video;
    if (decode_video(path, &video) == 0) {
        int expected = (int)(DURATION * FPS + 0.5) + 1;
        check(video.frames == expected && video.width == WIDTH && video.height == HEIGHT,
              "%s: video has %d frames of %dx%d (expected %d of %dx%d)", name, video.frames,
              video.width, video.height, expected, WIDTH, HEIGHT);
        check_rel("video duration, s", video.duration, (double)expected / FPS, 1e-6);
        decoded_release(&video);
    } else {
        check(0, "%s: %s decodes", name, path);
    }
    char err[256];
    snprintf(path, sizeof path, "%s/%s.png", out, name);
    image *poster = image_read_png(path, err, sizeof err);
    if (poster) {
        /* not blank, and not one flat fill: a floor or a skin pad may cover
         * most of the frame, but the sky above it stays background */
        double drawn = non_background(poster);
        check(poster->width == WIDTH && poster->height == HEIGHT && drawn > 0.01 && drawn < 0.97,
              "%s: poster %dx%d, %.1f%% of pixels drawn (rod, grid, text; not blank)", name,
              poster->width, poster->height, 100 * drawn);
        image_destroy(poster);
    } else {
        check(0, "%s: poster readable (%s)", name, err);
    }
    test_remove_tree(out);
}

/* A scene that draws another's run differently (its physics copied: the
 * scene format has no include) must keep the same physics: every key line
 * before [render], comments and spacing aside, is the same in both */
static int physics_lines(const char *path, char *out, size_t size)
{
    FILE *f = fopen(path, "r");
    if (!f) return -1;
    char line[512];
    size_t used = 0;
    out[0] = '\0';
    while (fgets(line, sizeof line, f)) {
        if (strncmp(line, "[render]", 8) == 0) break;
        char *hash = strchr(line, '#');
        if (hash) *hash = '\0';
        size_t n = strlen(line);
        while (n > 0 && (line[n - 1] == '\n' || line[n - 1] == ' ' || line[n - 1] == '\t')) n--;
        if (n == 0) continue;
        if (used + n + 2 > size) break;
        memcpy(out + used, line, n);
        used += n;
        out[used++] = '\n';
        out[used] = '\0';
    }
    fclose(f);
    return (int)used;
}

static void same_physics(const char *dir, const char *copy, const char *original)
{
    static char a[16384], b[16384];
    char pa[600], pb[600];
    snprintf(pa, sizeof pa, "%s/%s", dir, copy);
    snprintf(pb, sizeof pb, "%s/%s", dir, original);
    const int na = physics_lines(pa, a, sizeof a), nb = physics_lines(pb, b, sizeof b);
    check(na > 0 && nb > 0 && strcmp(a, b) == 0,
          "%s keeps %s's physics: every key before [render] the same (%d and %d bytes)", copy,
          original, na, nb);
}

int main(void)
{
    const char *dir = RODSIM_SOURCE_DIR "/scenes";
    DIR *d = opendir(dir);
    if (!check(d != NULL, "scenes/ directory opens")) return test_finish();
    char names[64][128];
    int count = 0;
    struct dirent *e;
    while ((e = readdir(d)) && count < 64) {
        size_t n = strlen(e->d_name);
        char path[600];
        if (n <= 4 || strcmp(e->d_name + n - 4, ".ini") != 0 ||
            snprintf(path, sizeof path, "%s/%s", dir, e->d_name) >= (int)sizeof path)
            continue;
        /* rod scenes only: the FEM scenes run through `rodsim fem` in test_fem */
        if (!test_is_fem_scene(path))
            if (snprintf(names[count], sizeof names[0], "%s", e->d_name) < (int)sizeof names[0])
                count++;
    }
    closedir(d);
    check(count >= 9, "found %d rod scenes", count);
    for (int i = 0; i < count; i++) run_scene(dir, names[i]);
    same_physics(dir, "wound_closure_section.ini", "wound_closure.ini");
    return test_finish();
}
