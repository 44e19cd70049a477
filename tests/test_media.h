/* test_media.h: helpers for tests that check rodsim's media output: decode
 * an MP4 with libavformat/libavcodec (frame count, size, duration, the first
 * frames as RGB), find a top-level MP4 box, remove a scratch directory.
 * Header-only (static functions), included by tests only. */
#ifndef RODSIM_TEST_MEDIA_H
#define RODSIM_TEST_MEDIA_H

#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libswscale/swscale.h>
#include <dirent.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "render/image.h"
#include "test_process.h"

#ifndef DECODE_KEEP
#define DECODE_KEEP 12 /* frames kept as RGB images */
#endif

typedef struct decoded {
    int frames, width, height;
    double duration; /* s, from the stream */
    image *picked[DECODE_KEEP];
} decoded;

/* Decodes every frame; converts each to RGB with BT.709 limited range
 * (what the writer tags). Returns 0 or -1. */
static inline int decode_video(const char *path, decoded *out)
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
            if (out->frames < DECODE_KEEP) {
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
static inline long box_offset(const char *path, const char *type)
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

static inline void decoded_release(decoded *d)
{
    for (int i = 0; i < DECODE_KEEP && i < d->frames; i++) image_destroy(d->picked[i]);
}

#endif
