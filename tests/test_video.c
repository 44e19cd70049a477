/* test_video.c: render a synthetic recording to MP4 and decode it with
 * libavformat/libavcodec: frame count, size, duration, +faststart, and a
 * decoded frame against the PNG of the same frame (PSNR). */
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libswscale/swscale.h>
#include <dirent.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "image.h"
#include "render.h"
#include "synthetic_recording.h"
#include "test.h"

#define FRAMES 12
#define FPS 24
#define WIDTH 640
#define HEIGHT 360

typedef struct decoded {
    int frames, width, height;
    double duration; /* s, from the stream */
    image *picked[FRAMES];
} decoded;

/* Decodes every frame; converts each to RGB with BT.709 limited range
 * (what the writer tags). Returns 0 or -1. */
static int decode_video(const char *path, decoded *out)
{
    memset(out, 0, sizeof *out);
    AVFormatContext *format = NULL;
    if (avformat_open_input(&format, path, NULL, NULL) < 0) return -1;
    avformat_find_stream_info(format, NULL);
    int index = av_find_best_stream(format, AVMEDIA_TYPE_VIDEO, -1, -1, NULL, 0);
    if (index < 0) {
        avformat_close_input(&format);
        return -1;
    }
    AVStream *stream = format->streams[index];
    const AVCodec *codec = avcodec_find_decoder(stream->codecpar->codec_id);
    AVCodecContext *context = avcodec_alloc_context3(codec);
    avcodec_parameters_to_context(context, stream->codecpar);
    avcodec_open2(context, codec, NULL);
    out->width = stream->codecpar->width;
    out->height = stream->codecpar->height;
    out->duration = stream->duration * av_q2d(stream->time_base);
    AVPacket *packet = av_packet_alloc();
    AVFrame *frame = av_frame_alloc();
    struct SwsContext *scaler = NULL;
    int draining = 0;
    while (!draining) {
        if (av_read_frame(format, packet) < 0) {
            draining = 1;
            avcodec_send_packet(context, NULL);
        } else {
            if (packet->stream_index == index) avcodec_send_packet(context, packet);
            av_packet_unref(packet);
        }
        while (avcodec_receive_frame(context, frame) == 0) {
            if (!scaler) {
                scaler = sws_getContext(frame->width, frame->height, frame->format, frame->width,
                                        frame->height, AV_PIX_FMT_RGB24,
                                        SWS_BICUBIC | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INT | SWS_FULL_CHR_H_INP, NULL,
                                        NULL, NULL);
                const int *bt709 = sws_getCoefficients(SWS_CS_ITU709);
                sws_setColorspaceDetails(scaler, bt709, 0, bt709, 1, 0, 1 << 16, 1 << 16);
            }
            if (out->frames < FRAMES) {
                image *img = image_create(frame->width, frame->height);
                uint8_t *dst[1] = {img->rgb};
                int stride[1] = {3 * img->width};
                sws_scale(scaler, (const uint8_t *const *)frame->data, frame->linesize, 0,
                          frame->height, dst, stride);
                out->picked[out->frames] = img;
            }
            out->frames++;
        }
    }
    sws_freeContext(scaler);
    av_frame_free(&frame);
    av_packet_free(&packet);
    avcodec_free_context(&context);
    avformat_close_input(&format);
    return 0;
}

/* Offset of a top-level MP4 box, or -1. */
static long box_offset(const char *path, const char *type)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) return -1;
    long offset = 0, found = -1;
    unsigned char header[8];
    while (fread(header, 1, 8, fp) == 8) {
        unsigned long size = (unsigned long)header[0] << 24 | header[1] << 16 | header[2] << 8 | header[3];
        if (memcmp(header + 4, type, 4) == 0) {
            found = offset;
            break;
        }
        if (size < 8 || fseek(fp, offset + (long)size, SEEK_SET)) break;
        offset += (long)size;
    }
    fclose(fp);
    return found;
}

static void remove_tree(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d) return;
    struct dirent *e;
    char path[1200];
    while ((e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        if (unlink(path)) remove_tree(path);
    }
    closedir(d);
    rmdir(dir);
}

int main(void)
{
    char dir[256], err[1024], path[1200];
    snprintf(dir, sizeof dir, "/tmp/rodsim_test_video_%ld", (long)getpid());
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
    rod_recording_destroy(rec);
    remove_tree(dir);
    return test_finish();
}
