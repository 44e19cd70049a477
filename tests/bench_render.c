/* bench_render.c (make bench, never a test): frames per second of render +
 * encode at 1280x720 H.264, and the floor: the same encoder fed frames with
 * nothing drawn. Reports the ratio; no pass/fail on wall time. */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

#include "image.h"
#include "render.h"
#include "synthetic_recording.h"
#include "video.h"

#define FRAMES 240

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

int main(void)
{
    char dir[256], path[400], err[1024];
    snprintf(dir, sizeof dir, "/tmp/rodsim_bench_render_%ld", (long)getpid());
    rod_recording *rec = synthetic_recording_create(51, FRAMES, 1.0, 0.001);
    for (int f = 0; f < FRAMES; f++) {
        double k = (f + 1.0) / FRAMES;
        synthetic_arc(rec, f, 0.35 / k, 10.0 * k);
        rec->time[f] = f / 30.0;
        rec->tip_force[3 * f + 1] = 4.5e-7 * k;
        rec->tip_moment[3 * f] = 1e-7 * k;
    }
    render_options o;
    render_options_default(&o); /* 1280x720, 30 fps, CRF 18, veryfast, 4x MSAA, 24 sides */
    o.poster = 0;

    /* render + encode at the default 4x MSAA, then without MSAA (what antialiasing costs) */
    double pipeline[2];
    const int samples[2] = {o.samples, 0};
    render_timing timing[2];
    for (int run = 0; run < 2; run++) {
        o.samples = samples[run];
        o.timing = &timing[run];
        double start = now_seconds();
        if (render_recording(rec, &o, dir, "bench", 1, err, sizeof err)) {
            fprintf(stderr, "bench_render: %s\n", err);
            return 1;
        }
        pipeline[run] = FRAMES / (now_seconds() - start);
        snprintf(path, sizeof path, "%s/bench.mp4", dir);
        unlink(path);
    }
    o.samples = samples[0];

    /* the floor: the same encoder, frames of plain background */
    image *blank = image_create(o.width, o.height);
    image_fill(blank, o.background[0], o.background[1], o.background[2]);
    double start = now_seconds();
    video_writer *v = video_writer_create(path, o.width, o.height, o.fps, o.crf, o.preset, err,
                                          sizeof err);
    for (int f = 0; v && f < FRAMES; f++)
        if (video_writer_add(v, blank, err, sizeof err)) break;
    if (!v || video_writer_finish(v, err, sizeof err)) {
        fprintf(stderr, "bench_render: %s\n", err);
        return 1;
    }
    double floor_rate = FRAMES / (now_seconds() - start);
    double floor_convert, floor_encode;
    video_writer_times(v, &floor_convert, &floor_encode);
    video_writer_destroy(v);
    unlink(path);
    rmdir(dir);
    image_destroy(blank);
    rod_recording_destroy(rec);

    printf("renderer %dx%d, %d frames, %d nodes, %d sides, x264 %s CRF %d\n", o.width, o.height,
           FRAMES, 51, o.sides, o.preset, o.crf);
    printf("  render + encode, %dx MSAA: %6.1f frames/s (%.2f ms/frame)\n", samples[0],
           pipeline[0], 1000 / pipeline[0]);
    printf("  render + encode, no MSAA:  %6.1f frames/s (%.2f ms/frame)\n", pipeline[1],
           1000 / pipeline[1]);
    printf("  floor (encoder fed blank frames): %6.1f frames/s (%.2f ms/frame)\n", floor_rate,
           1000 / floor_rate);
    printf("  where the time goes, ms per frame (drawing thread | writing thread):\n");
    for (int run = 0; run < 2; run++) {
        const render_timing *t = &timing[run];
        double per = 1000.0 / t->frames;
        printf("    %dx MSAA: mesh %.2f, gl %.2f, composite %.2f, overlay %.2f, wait %.2f | "
               "convert %.2f, encode %.2f; wall %.2f\n", samples[run], per * t->mesh, per * t->gl,
               per * t->composite, per * t->overlay, per * t->wait, per * t->convert,
               per * t->encode, per * t->wall);
    }
    printf("    floor: convert %.2f, encode %.2f\n", 1000 * floor_convert / FRAMES,
           1000 * floor_encode / FRAMES);
    printf("  ratio floor / render+encode: %.2f at %dx MSAA, %.2f without "
           "(target <= 1.3 and >= 80 frames/s)\n", floor_rate / pipeline[0], samples[0],
           floor_rate / pipeline[1]);
    return 0;
}
