/* video.c: the MP4 writer (see video.h), after FFmpeg's doc/examples/mux.c:
 * one struct owns the encoder, frame, packet and scaler, all made once. */
#include "video.h"

#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "outfile.h"

struct video_writer {
    outfile file;
    AVFormatContext *format;
    AVCodecContext *codec;
    AVStream *stream;
    AVFrame *frame;     /* yuv420p, reused */
    AVPacket *packet;   /* reused */
    struct SwsContext *scaler;
    int width, height;
    int64_t next_pts;
    int header_written, finished;
    double convert_seconds, encode_seconds; /* for the benchmark */
};

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void av_message(char *err, size_t errlen, const char *path, const char *what, int code)
{
    char text[AV_ERROR_MAX_STRING_SIZE] = "";
    av_strerror(code, text, sizeof text);
    snprintf(err, errlen, "%s: %s: %s", path, what, text);
}

video_writer *video_writer_create(const char *path, int width, int height, int fps, int crf,
                                  const char *preset, char *err, size_t errlen)
{
    if (width <= 0 || height <= 0 || width % 2 || height % 2) {
        snprintf(err, errlen, "%s: video size %dx%d must be positive and even (yuv420p)", path,
                 width, height);
        return NULL;
    }
    av_log_set_level(AV_LOG_ERROR); /* x264's banner is not for our users */
    const AVCodec *encoder = avcodec_find_encoder_by_name("libx264");
    if (!encoder) {
        snprintf(err, errlen, "%s: libavcodec has no libx264 encoder", path);
        return NULL;
    }
    video_writer *v = calloc(1, sizeof *v);
    if (!v) {
        snprintf(err, errlen, "%s: out of memory", path);
        return NULL;
    }
    v->width = width;
    v->height = height;
    v->file.slot = -1;
    if (outfile_reserve(&v->file, path, err, errlen)) {
        free(v);
        return NULL;
    }
    int code = avformat_alloc_output_context2(&v->format, NULL, "mp4", v->file.tmp_path);
    if (code < 0 || !v->format) {
        av_message(err, errlen, path, "cannot set up the MP4 muxer", code);
        video_writer_destroy(v);
        return NULL;
    }
    v->stream = avformat_new_stream(v->format, NULL);
    v->codec = avcodec_alloc_context3(encoder);
    v->frame = av_frame_alloc();
    v->packet = av_packet_alloc();
    if (!v->stream || !v->codec || !v->frame || !v->packet) {
        snprintf(err, errlen, "%s: out of memory", path);
        video_writer_destroy(v);
        return NULL;
    }
    v->codec->width = width;
    v->codec->height = height;
    v->codec->pix_fmt = AV_PIX_FMT_YUV420P;
    v->codec->time_base = (AVRational){1, fps};
    v->codec->framerate = (AVRational){fps, 1};
    v->codec->gop_size = 2 * fps;
    /* BT.709, limited range: what browsers assume for HD H.264 */
    v->codec->colorspace = AVCOL_SPC_BT709;
    v->codec->color_primaries = AVCOL_PRI_BT709;
    v->codec->color_trc = AVCOL_TRC_BT709;
    v->codec->color_range = AVCOL_RANGE_MPEG;
    if (v->format->oformat->flags & AVFMT_GLOBALHEADER)
        v->codec->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
    av_opt_set(v->codec->priv_data, "preset", preset ? preset : "veryfast", 0);
    av_opt_set_int(v->codec->priv_data, "crf", crf, 0);
    code = avcodec_open2(v->codec, encoder, NULL);
    if (code < 0) {
        av_message(err, errlen, path, "cannot open the H.264 encoder (bad preset?)", code);
        video_writer_destroy(v);
        return NULL;
    }
    avcodec_parameters_from_context(v->stream->codecpar, v->codec);
    v->stream->time_base = v->codec->time_base;
    v->stream->avg_frame_rate = v->codec->framerate;

    v->frame->format = AV_PIX_FMT_YUV420P;
    v->frame->width = width;
    v->frame->height = height;
    if (av_frame_get_buffer(v->frame, 0) < 0) {
        snprintf(err, errlen, "%s: out of memory", path);
        video_writer_destroy(v);
        return NULL;
    }
    v->scaler = sws_getContext(width, height, AV_PIX_FMT_RGB24, width, height, AV_PIX_FMT_YUV420P,
                               SWS_BICUBIC | SWS_ACCURATE_RND | SWS_FULL_CHR_H_INT, NULL, NULL,
                               NULL);
    if (!v->scaler) {
        snprintf(err, errlen, "%s: cannot set up the RGB to yuv420p converter", path);
        video_writer_destroy(v);
        return NULL;
    }
    /* RGB in full range, BT.709 limited-range YUV out (matches the tags above) */
    const int *coefficients = sws_getCoefficients(SWS_CS_ITU709);
    sws_setColorspaceDetails(v->scaler, coefficients, 1, coefficients, 0, 0, 1 << 16, 1 << 16);

    code = avio_open(&v->format->pb, v->file.tmp_path, AVIO_FLAG_WRITE);
    if (code < 0) {
        av_message(err, errlen, path, "cannot write", code);
        video_writer_destroy(v);
        return NULL;
    }
    AVDictionary *options = NULL;
    av_dict_set(&options, "movflags", "+faststart", 0);
    code = avformat_write_header(v->format, &options);
    av_dict_free(&options);
    if (code < 0) {
        av_message(err, errlen, path, "cannot write the MP4 header", code);
        video_writer_destroy(v);
        return NULL;
    }
    v->header_written = 1;
    return v;
}

/* Sends a frame (NULL flushes) and writes every packet the encoder has. */
static int encode(video_writer *v, AVFrame *frame, char *err, size_t errlen)
{
    int code = avcodec_send_frame(v->codec, frame);
    if (code < 0) {
        av_message(err, errlen, v->file.path, "encoding failed", code);
        return -1;
    }
    for (;;) {
        code = avcodec_receive_packet(v->codec, v->packet);
        if (code == AVERROR(EAGAIN) || code == AVERROR_EOF) return 0;
        if (code < 0) {
            av_message(err, errlen, v->file.path, "encoding failed", code);
            return -1;
        }
        av_packet_rescale_ts(v->packet, v->codec->time_base, v->stream->time_base);
        v->packet->stream_index = v->stream->index;
        code = av_interleaved_write_frame(v->format, v->packet);
        if (code < 0) {
            av_message(err, errlen, v->file.path, "cannot write (disk full?)", code);
            return -1;
        }
    }
}

int video_writer_add(video_writer *v, const image *frame, char *err, size_t errlen)
{
    if (frame->width != v->width || frame->height != v->height) {
        snprintf(err, errlen, "%s: frame %dx%d differs from the video's %dx%d", v->file.path,
                 frame->width, frame->height, v->width, v->height);
        return -1;
    }
    if (av_frame_make_writable(v->frame) < 0) {
        snprintf(err, errlen, "%s: out of memory", v->file.path);
        return -1;
    }
    double start = now_seconds();
    const uint8_t *source[1] = {frame->rgb};
    const int stride[1] = {3 * frame->width};
    sws_scale(v->scaler, source, stride, 0, v->height, v->frame->data, v->frame->linesize);
    v->frame->pts = v->next_pts++;
    double converted = now_seconds();
    int status = encode(v, v->frame, err, errlen);
    v->convert_seconds += converted - start;
    v->encode_seconds += now_seconds() - converted;
    return status;
}

void video_writer_times(const video_writer *v, double *convert, double *encode_seconds)
{
    *convert = v->convert_seconds;
    *encode_seconds = v->encode_seconds;
}

int video_writer_finish(video_writer *v, char *err, size_t errlen)
{
    double start = now_seconds();
    int status = encode(v, NULL, err, errlen); /* the frames x264 still holds */
    v->encode_seconds += now_seconds() - start;
    if (status) return -1;
    int code = av_write_trailer(v->format);
    if (code < 0) {
        av_message(err, errlen, v->file.path, "cannot finish the MP4", code);
        return -1;
    }
    avio_closep(&v->format->pb);
    if (outfile_commit(&v->file, err, errlen)) return -1;
    v->finished = 1;
    return 0;
}

void video_writer_destroy(video_writer *v)
{
    if (!v) return;
    if (v->format && v->format->pb) avio_closep(&v->format->pb);
    if (!v->finished) outfile_abort(&v->file);
    sws_freeContext(v->scaler);
    av_packet_free(&v->packet);
    av_frame_free(&v->frame);
    avcodec_free_context(&v->codec);
    avformat_free_context(v->format);
    free(v);
}
