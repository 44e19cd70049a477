/* test_video.c: render a synthetic recording to MP4 and decode it with
 * libavformat/libavcodec: frame count, size, duration, +faststart, and a
 * decoded frame against the PNG of the same frame (PSNR); a video
 * re-encoded (the benchmark's baseline) keeps its frames. */
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "render/image.h"
#include "render/render.h"
#include "synthetic_recording.h"
#include "test.h"
#include "render/video.h"

#define FRAMES 12
#define FPS 24
#define WIDTH 640
#define HEIGHT 360
#define DECODE_KEEP FRAMES
#include "test_media.h"

/* The writer converts only what changed since the last frame: a square
 * that appears, moves and disappears must leave no trace in the decoded
 * frames. Lossless (CRF 0), squares on even pixels, so each decoded frame
 * must match its source up to the chroma subsampling of the square edges.
 * tracked: the frames mark what was drawn over their grey (image.h), and
 * the writer looks only there and where the frame before was marked. */
static void test_changed_regions_only(const char *dir, int tracked)
{
    enum { W = 100, H = 64, N = 5 }; /* 100: the last 32-pixel block is partial */
    char path[400], err[1024];
    snprintf(path, sizeof path, "%s/squares%s.mp4", dir, tracked ? "_tracked" : "");
    image *frames[N];
    static const unsigned char grey[3] = {246, 247, 249}, red[3] = {200, 30, 20},
                               blue[3] = {20, 60, 220};
    for (int k = 0; k < N; k++) {
        frames[k] = image_create(W, H);
        image_fill(frames[k], grey[0], grey[1], grey[2]);
        if (tracked && !check(image_track_changes(frames[k]) == 0, "frame %d tracked", k)) return;
        image_changes_reset(frames[k]); /* the grey is every frame's backdrop */
    }
    image_fill_rect(frames[1], 10, 8, 20, 16, red, 1.0);   /* appears */
    image_fill_rect(frames[2], 40, 30, 20, 16, red, 1.0);  /* moves */
    image_fill_rect(frames[2], 88, 50, 12, 10, blue, 1.0); /* and one at the right edge */
    image_fill_rect(frames[3], 40, 30, 20, 16, blue, 1.0); /* changes colour */
    /* frames[4]: gone again, all grey */
    video_writer *v = video_writer_create(path, W, H, 10, 0, "veryfast", err, sizeof err);
    int status = v ? 0 : -1;
    for (int k = 0; !status && k < N; k++) status = video_writer_add(v, frames[k], err, sizeof err);
    if (!status) status = video_writer_finish(v, err, sizeof err);
    video_writer_destroy(v);
    check(status == 0, "write %d frames of moving squares (%s)", N, status ? err : "ok");
    decoded video;
    if (check(decode_video(path, &video) == 0 && video.frames == N, "decode %d frames", N)) {
        for (int k = 0; k < N; k++) {
            double psnr = image_psnr(frames[k], video.picked[k]);
            check(psnr >= 35, "%slossless frame %d vs its source: PSNR %.1f dB (>= 35, chroma edges; a square "
                              "left behind gives about 16)", tracked ? "tracked: " : "", k, psnr);
        }
    }
    if (tracked) {
        for (int k = 0; k < N; k++) {
            image_destroy(frames[k]);
            image_destroy(video.picked[k]);
        }
        return;
    }
    /* the bench's baseline: decoded and encoded again, lossless, the same pictures */
    char again[400];
    snprintf(again, sizeof again, "%s/again.mp4", dir);
    int count = 0;
    status = video_reencode(path, again, 0, "veryfast", &count, err, sizeof err);
    check(status == 0 && count == N, "re-encode: %d frames, expected %d (%s)", count, N,
          status ? err : "ok");
    decoded twice;
    if (check(decode_video(again, &twice) == 0 && twice.frames == N, "decode the re-encode")) {
        for (int k = 0; k < N; k++) {
            double psnr = image_psnr(video.picked[k], twice.picked[k]);
            check(psnr == INFINITY, "re-encoded frame %d vs the first decode: PSNR %.1f dB (inf: "
                                    "lossless both times)", k, psnr);
            image_destroy(twice.picked[k]);
        }
    }
    check(video_reencode(again, path, 18, "no-such-preset", NULL, err, sizeof err) == -1 &&
              strstr(err, "preset"),
          "a bad preset: refused with a message (%s)", err);
    for (int k = 0; k < N; k++) {
        image_destroy(frames[k]);
        image_destroy(video.picked[k]);
    }
}

int main(void)
{
    char dir[256], err[1024], path[1200];
    snprintf(dir, sizeof dir, "%s", test_path("video")); /* render_recording makes it */
    rod_recording *rec = synthetic_recording_create(31, FRAMES, 1.0, 0.002);
    for (int f = 0; f < FRAMES; f++) {
        double k = (f + 1.0) / FRAMES;
        synthetic_arc(rec, f, 0.4 / k, 8.0 * k); /* bends and twists more every frame */
        rec->time[f] = (double)f / FPS;
        rec->tip_force[3 * f + 1] = 1e-6 * k;
    }
    render_options o;
    render_options_default(&o);
    o.width = WIDTH;
    o.height = HEIGHT;
    o.fps = FPS;
    o.frames_png = 1;
    int status = render_recording(rec, &o, dir, "clip", 1, err, sizeof err);
    check(status == 0, "render 12 frames at 640x360 with video and PNG frames (%s)", status ? err : "ok");

    snprintf(path, sizeof path, "%s/clip.mp4", dir);
    decoded video;
    if (check(decode_video(path, &video) == 0, "%s decodes with libavformat/libavcodec", path)) {
        check(video.frames == FRAMES, "decoded frame count %d, expected %d", video.frames, FRAMES);
        check(video.width == WIDTH && video.height == HEIGHT, "size %dx%d, expected %dx%d",
              video.width, video.height, WIDTH, HEIGHT);
        check_rel("duration, s (frames / fps)", video.duration, (double)FRAMES / FPS, 1e-6);
        long moov = box_offset(path, "moov"), mdat = box_offset(path, "mdat");
        check(moov >= 0 && mdat > moov, "+faststart: moov at %ld before mdat at %ld", moov, mdat);
        int picks[3] = {0, FRAMES / 2, FRAMES - 1};
        for (int i = 0; i < 3; i++) {
            int k = picks[i];
            snprintf(path, sizeof path, "%s/clip_frames/%05d.png", dir, k);
            image *png = image_read_png(path, err, sizeof err);
            if (!check(png && video.picked[k], "PNG frame %d read (%s)", k, png ? "ok" : err)) {
                image_destroy(png);
                continue;
            }
            double psnr = image_psnr(png, video.picked[k]);
            check(psnr >= 35, "decoded frame %d vs its PNG: PSNR %.1f dB (>= 35)", k, psnr);
            image_destroy(png);
        }
        /* the poster is the last frame */
        snprintf(path, sizeof path, "%s/clip.png", dir);
        image *poster = image_read_png(path, err, sizeof err);
        snprintf(path, sizeof path, "%s/clip_frames/%05d.png", dir, FRAMES - 1);
        image *last = image_read_png(path, err, sizeof err);
        check(poster && last && image_psnr(poster, last) == INFINITY,
              "the poster equals the last PNG frame");
        image_destroy(poster);
        image_destroy(last);
        for (int k = 0; k < FRAMES; k++) image_destroy(video.picked[k]);
    }
    test_changed_regions_only(dir, 0);
    test_changed_regions_only(dir, 1);
    rod_recording_destroy(rec);
    test_remove_tree(dir);
    return test_finish();
}
