/* bench_render.c (make bench, never a test): first the video of a real
 * scene (suture.ini, 720p): the CPU its drawing and encoding cost against a
 * re-encode of the same video (its frames decoded and encoded again by the
 * same libx264 through libav*, CRF and preset as the run's: what `ffmpeg -i
 * suture.mp4 -c:v libx264 -preset veryfast -crf 18 -bf 0` does), and the
 * whole run's CPU per simulated second; then frames per second of render +
 * encode at 1280x720 H.264 over synthetic frames, and the floor: the same
 * encoder fed frames with nothing drawn; then the same at 1920x1080.
 * Reports the ratios; no pass/fail on wall time.
 *
 * The machine is shared, so every measurement is repeated (argv[1] times,
 * default 3) and reported as best and worst; CPU time per frame (all
 * threads) is reported too: it moves much less with the other load. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "render/image.h"
#include "render/render.h"
#include "synthetic_recording.h"
#include "render/video.h"
#include "test.h"

#define FRAMES 240
#define MAX_REPEATS 20

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* CPU seconds of this process, all threads. */
static double cpu_seconds(void)
{
    struct rusage u;
    getrusage(RUSAGE_SELF, &u);
    return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

/* CPU seconds of the children waited for, all threads. */
static double children_cpu_seconds(void)
{
    struct rusage u;
    getrusage(RUSAGE_CHILDREN, &u);
    return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

/* rodsim run SCENE -o dir --quiet --summary summary [--no-video]: its CPU
 * seconds, or -1 when it failed. */
static double run_scene(const char *scene, const char *dir, const char *summary, int video)
{
    const char *argv[] = {RODSIM_BIN, "run", scene, "-o", dir, "--quiet", "--summary", summary,
                          video ? NULL : "--no-video", NULL};
    double cpu = children_cpu_seconds();
    pid_t pid = fork();
    if (pid == 0) {
        execv(RODSIM_BIN, (char *const *)argv);
        _exit(127);
    }
    int status = 0;
    if (pid < 0 || waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || WEXITSTATUS(status))
        return -1;
    return children_cpu_seconds() - cpu;
}

/* The simulated seconds of a run: "t_end" in its summary; 0 if absent. */
static double summary_t_end(const char *summary)
{
    char text[16384];
    FILE *f = fopen(summary, "r");
    size_t n = f ? fread(text, 1, sizeof text - 1, f) : 0;
    if (f) fclose(f);
    text[n] = '\0';
    const char *at = strstr(text, "\"t_end\":");
    return at ? atof(at + 8) : 0;
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *values, int count)
{
    qsort(values, (size_t)count, sizeof *values, compare_doubles);
    return count % 2 ? values[count / 2] : 0.5 * (values[count / 2 - 1] + values[count / 2]);
}

/* The video of suture.ini: repeats triples of runs (with its video,
 * without, and the video re-encoded), each triple one pair of ratios;
 * prints their medians. 0, or -1 with the reason printed. */
static int suture_rows(int repeats)
{
    const char *scene = RODSIM_SOURCE_DIR "/scenes/suture.ini";
    char dir[256], summary[400], video[400], again[400], err[1024];
    snprintf(dir, sizeof dir, "%s/suture", test_dir());
    snprintf(summary, sizeof summary, "%s/summary.json", dir);
    snprintf(video, sizeof video, "%s/suture.mp4", dir);
    snprintf(again, sizeof again, "%s/again.mp4", dir);
    mkdir(dir, 0777);
    render_options o;
    render_options_default(&o); /* suture.ini keeps the default size, CRF and preset */
    double ratio[MAX_REPEATS], real_time[MAX_REPEATS], frame_ms[MAX_REPEATS], again_ms[MAX_REPEATS];
    double t_end = 0;
    int frames = 0, reencoded = 1;
    for (int k = 0; k < repeats; k++) {
        double with = run_scene(scene, dir, summary, 1);
        t_end = summary_t_end(summary);
        double without = run_scene(scene, dir, summary, 0);
        if (with < 0 || without < 0 || t_end <= 0) {
            printf("suture.ini: rodsim run failed (%s)\n", RODSIM_BIN);
            return -1;
        }
        double cpu = cpu_seconds();
        if (video_reencode(video, again, o.crf, o.preset, &frames, err, sizeof err)) {
            /* no libav* to decode with: the row is skipped, saying why */
            printf("suture.ini video: re-encode baseline skipped: %s\n", err);
            reencoded = 0;
        }
        double reencode = cpu_seconds() - cpu;
        unlink(again);
        if (frames < 1) frames = 1;
        frame_ms[k] = 1000 * (with - without) / frames;
        again_ms[k] = 1000 * reencode / frames;
        ratio[k] = (with - without) / reencode;
        real_time[k] = t_end / with;
        unlink(video);
    }
    unlink(summary);
    snprintf(video, sizeof video, "%s/suture.png", dir);
    unlink(video);
    rmdir(dir);
    printf("suture.ini, %dx%d, %d frames, x264 %s CRF %d, no B-frames; medians of %d paired "
           "runs (CPU time, all threads):\n", o.width, o.height, frames, o.preset, o.crf, repeats);
    if (reencoded)
        printf("  draw + encode / re-encode of the same video: %.2fx (%.1f ms against %.1f ms "
               "of CPU a frame; target <= 2)\n",
               median(ratio, repeats), median(frame_ms, repeats), median(again_ms, repeats));
    printf("  the run with its video: %.2fx real time (%.1f simulated s; target >= 4)\n",
           median(real_time, repeats), t_end);
    printf("  on a GPU: not measured (%s)\n",
           access("/dev/dri", F_OK) == 0
               ? "the renderer draws with EGL's software device, llvmpipe, on every machine"
               : "this machine has no GPU; the renderer draws with llvmpipe");
    fflush(stdout);
    return 0;
}

typedef struct measured {
    double best, worst; /* frames/s */
    double cpu_ms;      /* CPU ms per frame in the best run */
    render_timing timing; /* stages in the best run */
} measured;

static void note(measured *m, int repeat, double rate, double cpu, const render_timing *t)
{
    if (repeat == 0 || rate > m->best) {
        m->best = rate;
        m->cpu_ms = 1000 * cpu / FRAMES;
        if (t) m->timing = *t;
    }
    if (repeat == 0 || rate < m->worst) m->worst = rate;
}

int main(int argc, char **argv)
{
    int repeats = argc > 1 ? atoi(argv[1]) : 3;
    if (repeats < 1 || repeats > MAX_REPEATS) repeats = 3;
    if (suture_rows(repeats)) return 1;
    char dir[256], path[400], err[1024];
    snprintf(dir, sizeof dir, "%s/render", test_dir());
    snprintf(path, sizeof path, "%s/bench.mp4", dir);
    rod_recording *rec = synthetic_recording_create(51, FRAMES, 1.0, 0.001);
    for (int f = 0; f < FRAMES; f++) {
        double k = (f + 1.0) / FRAMES;
        synthetic_arc(rec, f, 0.35 / k, 10.0 * k);
        rec->time[f] = f / 30.0;
        rec->tip_force[3 * f + 1] = 4.5e-7 * k;
        rec->tip_moment[3 * f] = 1e-7 * k;
    }
    render_options o;
    render_options_default(&o);
    o.poster = 0;
    image *blank = image_create(o.width, o.height);
    image_fill(blank, o.background[0], o.background[1], o.background[2]);

    /* render + encode at the default antialiasing, then with none (what it
     * costs), then over a floor and a skin pad with the shadow map and
     * without it (what the shadows cost), then the floor: the
     * same encoder, frames of plain background */
    /* and the default (FXAA) against 4x multisampling, the old default */
    const int samples[5] = {o.samples, 0, o.samples, o.samples, o.samples};
    const recording_surface surfaces[2] = {
        {.shape = RECORDING_SURFACE_PLANE, .center = {0, 0, -0.1}, .normal = {0, 0, 1}},
        {.shape = RECORDING_SURFACE_BOX, .center = {0.3, 0.3, -0.08}, .size = {0.3, 0.2, 0.04},
         .tissue = 1}};
    measured pipeline[5], floor_run;
    for (int repeat = 0; repeat < repeats; repeat++) {
        for (int run = 0; run < 5; run++) {
            render_timing timing;
            o.samples = samples[run];
            o.antialias = run == 4 ? RENDER_AA_MSAA : RENDER_AA_FXAA;
            synthetic_recording_surfaces(rec, surfaces, run == 2 || run == 3 ? 2 : 0);
            o.shadows = run != 3;
            o.timing = &timing;
            double start = now_seconds(), cpu = cpu_seconds();
            if (render_recording(rec, &o, dir, "bench", 1, err, sizeof err)) {
                fprintf(stderr, "bench_render: %s\n", err);
                return 1;
            }
            note(&pipeline[run], repeat, FRAMES / (now_seconds() - start), cpu_seconds() - cpu,
                 &timing);
            unlink(path);
        }
        o.samples = samples[0];
        o.timing = NULL;
        double start = now_seconds(), cpu = cpu_seconds();
        video_writer *v = video_writer_create(path, o.width, o.height, o.fps, o.crf, o.preset, err,
                                              sizeof err);
        for (int f = 0; v && f < FRAMES; f++)
            if (video_writer_add(v, blank, err, sizeof err)) break;
        if (!v || video_writer_finish(v, err, sizeof err)) {
            fprintf(stderr, "bench_render: %s\n", err);
            return 1;
        }
        render_timing floor_timing = {0};
        video_writer_times(v, &floor_timing.convert, &floor_timing.encode);
        floor_timing.frames = FRAMES;
        note(&floor_run, repeat, FRAMES / (now_seconds() - start), cpu_seconds() - cpu,
             &floor_timing);
        video_writer_destroy(v);
        unlink(path);
    }
    rmdir(dir);
    image_destroy(blank);
    rod_recording *rec_hd = rec; /* the 1080p runs draw the same recording */

    printf("renderer %dx%d, %d frames, %d nodes, %d sides, x264 %s CRF %d; best and worst of %d\n",
           o.width, o.height, FRAMES, 51, o.sides, o.preset, o.crf, repeats);
    const char *names[6] = {"render + encode, default AA", "render + encode, no AA     ",
                            "surfaces, shadows, def. AA ", "surfaces, no shadows       ",
                            "render + encode, 4x MSAA   ", "floor (blank frames)       "};
    for (int run = 0; run < 6; run++) {
        const measured *m = run < 5 ? &pipeline[run] : &floor_run;
        printf("  %s %6.1f .. %6.1f frames/s, CPU %5.2f ms/frame\n", names[run], m->worst, m->best,
               m->cpu_ms);
    }
    printf("  where the time goes, ms per frame (drawing thread | writing thread), best run:\n");
    for (int run = 0; run < 6; run++) {
        const render_timing *t = run < 5 ? &pipeline[run].timing : &floor_run.timing;
        double per = 1000.0 / t->frames;
        printf("    %s mesh %.2f, gl %.2f (shadow pass %.2f), composite %.2f, overlay %.2f, "
               "wait %.2f | convert %.2f, encode %.2f\n", names[run], per * t->mesh, per * t->gl,
               per * t->shadow, per * t->composite, per * t->overlay, per * t->wait,
               per * t->convert, per * t->encode);
    }
    printf("  ratio floor / render+encode (best runs): %.2f with default AA (FXAA), %.2f with "
           "4x MSAA, %.2f without (target <= 1.3 and >= 80 frames/s)\n",
           floor_run.best / pipeline[0].best, floor_run.best / pipeline[4].best,
           floor_run.best / pipeline[1].best);

    /* 1080p in the same run: the default picture and its floor */
    o.width = 1920;
    o.height = 1080;
    o.samples = samples[0];
    o.antialias = RENDER_AA_FXAA;
    synthetic_recording_surfaces(rec_hd, NULL, 0);
    o.shadows = 1;
    o.timing = NULL;
    image *blank_hd = image_create(o.width, o.height);
    image_fill(blank_hd, o.background[0], o.background[1], o.background[2]);
    measured hd = {0}, hd_floor = {0};
    mkdir(dir, 0777);
    for (int repeat = 0; repeat < repeats; repeat++) {
        double start = now_seconds(), cpu = cpu_seconds();
        if (render_recording(rec_hd, &o, dir, "bench", 1, err, sizeof err)) {
            fprintf(stderr, "bench_render: %s\n", err);
            return 1;
        }
        note(&hd, repeat, FRAMES / (now_seconds() - start), cpu_seconds() - cpu, NULL);
        unlink(path);
        start = now_seconds();
        cpu = cpu_seconds();
        video_writer *v = video_writer_create(path, o.width, o.height, o.fps, o.crf, o.preset, err,
                                              sizeof err);
        for (int f = 0; v && f < FRAMES; f++)
            if (video_writer_add(v, blank_hd, err, sizeof err)) break;
        if (!v || video_writer_finish(v, err, sizeof err)) {
            fprintf(stderr, "bench_render: %s\n", err);
            return 1;
        }
        note(&hd_floor, repeat, FRAMES / (now_seconds() - start), cpu_seconds() - cpu, NULL);
        video_writer_destroy(v);
        unlink(path);
    }
    rmdir(dir);
    image_destroy(blank_hd);
    rod_recording_destroy(rec_hd);
    printf("renderer 1920x1080, the same frames; best and worst of %d\n", repeats);
    printf("  render + encode, default AA %6.1f .. %6.1f frames/s, CPU %5.2f ms/frame\n", hd.worst,
           hd.best, hd.cpu_ms);
    printf("  floor (blank frames)        %6.1f .. %6.1f frames/s, CPU %5.2f ms/frame\n",
           hd_floor.worst, hd_floor.best, hd_floor.cpu_ms);
    printf("  cost / floor (best runs): 720p %.2f, 1080p %.2f with default AA (FXAA; 720p with "
           "4x MSAA %.2f) (target at 720p: <= 1.5)\n",
           floor_run.best / pipeline[0].best, hd_floor.best / hd.best,
           floor_run.best / pipeline[4].best);
    test_dir_remove();
    return 0;
}
