/* video.c: the MP4 writer (see video.h), after FFmpeg's doc/examples/mux.c:
 * one struct owns the encoder, frame, packet and converter state, all made
 * once.
 *
 * RGB to yuv420p is done here, not by libswscale: consecutive frames of a
 * rod differ in a small part of the picture (the rod, a few text lines),
 * so only the blocks of 32 x 2 pixels that changed since the last frame are
 * converted; the yuv frame keeps the rest from the frame before (swscale
 * converts every pixel: docs/decisions/0052-own-yuv-conversion.md). */
#include "render/video.h"

#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/opt.h>
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/clocks.h"
#include "base/outfile.h"
#include "render/dynlib.h"

/* ---- libav* opened when the first video is made (dlopen), not linked ----
 * Linked, libavcodec/libavformat (and their codecs' libraries) were loaded
 * and relocated at every start of the program, writing video or not. The
 * headers still give the types and constants; each function the writer
 * calls is a pointer in the table `av`, named as the function (the
 * #defines below), typed as its header declares (checked at compile time). */

/* X(library, return type, name, parameters) */
#define AV_FUNCTIONS(X)                                                                     \
    X(AVUTIL, int, av_strerror, (int errnum, char *errbuf, size_t errbuf_size))             \
    X(AVUTIL, void, av_log_set_level, (int level))                                          \
    X(AVUTIL, AVFrame *, av_frame_alloc, (void))                                            \
    X(AVUTIL, int, av_frame_get_buffer, (AVFrame *frame, int align))                        \
    X(AVUTIL, int, av_frame_make_writable, (AVFrame *frame))                                \
    X(AVUTIL, void, av_frame_free, (AVFrame **frame))                                       \
    X(AVUTIL, void, av_frame_unref, (AVFrame *frame))                                       \
    X(AVCODEC, const AVCodec *, avcodec_find_decoder, (enum AVCodecID id))                  \
    X(AVCODEC, int, avcodec_parameters_to_context, (AVCodecContext *codec,                  \
                                                    const AVCodecParameters *par))          \
    X(AVCODEC, int, avcodec_send_packet, (AVCodecContext *avctx, const AVPacket *avpkt))    \
    X(AVCODEC, int, avcodec_receive_frame, (AVCodecContext *avctx, AVFrame *frame))         \
    X(AVCODEC, void, av_packet_unref, (AVPacket *pkt))                                      \
    X(AVFORMAT, int, avformat_open_input, (AVFormatContext **ps, const char *url,           \
                                           const AVInputFormat *fmt,                        \
                                           AVDictionary **options))                         \
    X(AVFORMAT, int, avformat_find_stream_info, (AVFormatContext *ic,                       \
                                                 AVDictionary **options))                   \
    X(AVFORMAT, int, av_read_frame, (AVFormatContext *s, AVPacket *pkt))                    \
    X(AVFORMAT, void, avformat_close_input, (AVFormatContext **s))                          \
    X(AVUTIL, int, av_opt_set, (void *obj, const char *name, const char *val, int flags))   \
    X(AVUTIL, int, av_opt_set_int, (void *obj, const char *name, int64_t val, int flags))   \
    X(AVUTIL, int, av_dict_set, (AVDictionary **pm, const char *key, const char *value,     \
                                 int flags))                                                \
    X(AVUTIL, void, av_dict_free, (AVDictionary **m))                                       \
    X(AVCODEC, const AVCodec *, avcodec_find_encoder_by_name, (const char *name))           \
    X(AVCODEC, AVCodecContext *, avcodec_alloc_context3, (const AVCodec *codec))            \
    X(AVCODEC, int, avcodec_open2, (AVCodecContext *avctx, const AVCodec *codec,            \
                                    AVDictionary **options))                                \
    X(AVCODEC, int, avcodec_parameters_from_context, (AVCodecParameters *par,               \
                                                      const AVCodecContext *codec))         \
    X(AVCODEC, int, avcodec_send_frame, (AVCodecContext *avctx, const AVFrame *frame))      \
    X(AVCODEC, int, avcodec_receive_packet, (AVCodecContext *avctx, AVPacket *avpkt))       \
    X(AVCODEC, void, avcodec_free_context, (AVCodecContext **avctx))                        \
    X(AVCODEC, AVPacket *, av_packet_alloc, (void))                                         \
    X(AVCODEC, void, av_packet_free, (AVPacket **pkt))                                      \
    X(AVCODEC, void, av_packet_rescale_ts, (AVPacket *pkt, AVRational src, AVRational dst)) \
    X(AVFORMAT, int, avformat_alloc_output_context2, (AVFormatContext **ctx,                \
                                                      const AVOutputFormat *oformat,        \
                                                      const char *format_name,              \
                                                      const char *filename))                \
    X(AVFORMAT, AVStream *, avformat_new_stream, (AVFormatContext *s, const AVCodec *c))    \
    X(AVFORMAT, int, avio_open, (AVIOContext **s, const char *url, int flags))              \
    X(AVFORMAT, int, avio_closep, (AVIOContext **s))                                        \
    X(AVFORMAT, int, avformat_write_header, (AVFormatContext *s, AVDictionary **options))   \
    X(AVFORMAT, int, av_interleaved_write_frame, (AVFormatContext *s, AVPacket *pkt))       \
    X(AVFORMAT, int, av_write_trailer, (AVFormatContext *s))                                \
    X(AVFORMAT, void, avformat_free_context, (AVFormatContext *s))

#define AV_MEMBER(lib, ret, name, params) ret(*name) params;
static struct {
    AV_FUNCTIONS(AV_MEMBER)
} av;
#undef AV_MEMBER
#define AV_SAME_TYPE(lib, ret, name, params) \
    _Static_assert(_Generic(&name, ret(*) params: 1, default: 0), #name " as its header declares it");
AV_FUNCTIONS(AV_SAME_TYPE)
#undef AV_SAME_TYPE

/* The sonames of the headers' major versions (what the build compiled
 * against: the ABI the table's types describe), e.g. libavcodec.so.59 from
 * Debian 12's package libavcodec59. */
enum { AVUTIL, AVCODEC, AVFORMAT, AV_LIBRARIES };
#define AV_LIBRARY(name, major) \
    {"lib" name ".so." AV_STRINGIFY(major), "lib" name AV_STRINGIFY(major)}
static const struct {
    const char *soname, *package;
} av_libraries[AV_LIBRARIES] = {
    [AVUTIL] = AV_LIBRARY("avutil", LIBAVUTIL_VERSION_MAJOR),
    [AVCODEC] = AV_LIBRARY("avcodec", LIBAVCODEC_VERSION_MAJOR),
    [AVFORMAT] = AV_LIBRARY("avformat", LIBAVFORMAT_VERSION_MAJOR),
};
static pthread_once_t av_once = PTHREAD_ONCE_INIT;
static char av_error[512]; /* empty once the libraries are usable */

static void av_open(void)
{
    void *lib[AV_LIBRARIES];
    for (int i = 0; i < AV_LIBRARIES; i++) {
        const char *sonames[] = {av_libraries[i].soname, NULL};
        if (!(lib[i] = dynlib_open(sonames, av_libraries[i].package, av_error, sizeof av_error)))
            return;
    }
    dynlib_function f;
#define AV_LOAD(library, ret, name, params)                                                  \
    if (!(f = dynlib_symbol(lib[library], av_libraries[library].soname, #name, av_error,      \
                            sizeof av_error)))                                                \
        return;                                                                               \
    av.name = (ret(*) params)f;
    AV_FUNCTIONS(AV_LOAD)
#undef AV_LOAD
}

/* 0 once libav* are loaded, or -1 with the reason */
static int av_load(const char *path, char *err, size_t errlen)
{
    pthread_once(&av_once, av_open);
    if (!av_error[0]) return 0;
    snprintf(err, errlen, "%s: %s", path, av_error);
    return -1;
}

/* From here on, the functions' names call through the table. */
#define av_strerror av.av_strerror
#define av_log_set_level av.av_log_set_level
#define av_frame_alloc av.av_frame_alloc
#define av_frame_get_buffer av.av_frame_get_buffer
#define av_frame_make_writable av.av_frame_make_writable
#define av_frame_free av.av_frame_free
#define av_frame_unref av.av_frame_unref
#define avcodec_find_decoder av.avcodec_find_decoder
#define avcodec_parameters_to_context av.avcodec_parameters_to_context
#define avcodec_send_packet av.avcodec_send_packet
#define avcodec_receive_frame av.avcodec_receive_frame
#define av_packet_unref av.av_packet_unref
#define avformat_open_input av.avformat_open_input
#define avformat_find_stream_info av.avformat_find_stream_info
#define av_read_frame av.av_read_frame
#define avformat_close_input av.avformat_close_input
#define av_opt_set av.av_opt_set
#define av_opt_set_int av.av_opt_set_int
#define av_dict_set av.av_dict_set
#define av_dict_free av.av_dict_free
#define avcodec_find_encoder_by_name av.avcodec_find_encoder_by_name
#define avcodec_alloc_context3 av.avcodec_alloc_context3
#define avcodec_open2 av.avcodec_open2
#define avcodec_parameters_from_context av.avcodec_parameters_from_context
#define avcodec_send_frame av.avcodec_send_frame
#define avcodec_receive_packet av.avcodec_receive_packet
#define avcodec_free_context av.avcodec_free_context
#define av_packet_alloc av.av_packet_alloc
#define av_packet_free av.av_packet_free
#define av_packet_rescale_ts av.av_packet_rescale_ts
#define avformat_alloc_output_context2 av.avformat_alloc_output_context2
#define avformat_new_stream av.avformat_new_stream
#define avio_open av.avio_open
#define avio_closep av.avio_closep
#define avformat_write_header av.avformat_write_header
#define av_interleaved_write_frame av.av_interleaved_write_frame
#define av_write_trailer av.av_write_trailer
#define avformat_free_context av.avformat_free_context

struct video_writer {
    outfile file;
    AVFormatContext *format;
    AVCodecContext *codec;
    AVStream *stream;
    AVFrame *frame;     /* yuv420p, reused */
    AVPacket *packet;   /* reused */
    unsigned char *previous; /* the last frame added, RGB (height x width x 3) */
    int have_previous;
    int *previous_changed;   /* (height x 2): its rows' changed columns (image.h); NULL: untracked */
    int32_t coef[9];         /* RGB to Y, Cb, Cr, 16-bit fixed point (BT.709) */
    int width, height;
    int64_t next_pts;
    int header_written, finished;
    double convert_seconds, encode_seconds; /* for the benchmark */
};

static void av_message(char *err, size_t errlen, const char *path, const char *what, int code)
{
    char text[AV_ERROR_MAX_STRING_SIZE] = "";
    av_strerror(code, text, sizeof text);
    snprintf(err, errlen, "%s: %s: %s", path, what, text);
}

/* BT.709 (Rec. ITU-R BT.709-6, item 3.2-3.3: Kr = 0.2126, Kb = 0.0722) from
 * full-range R'G'B' to limited-range Y'CbCr (Y' 16..235, Cb, Cr 16..240),
 * matching the tags set on the stream. 16-bit fixed point; the chroma rows
 * take the sum of a 2x2 block, hence the extra / 4. */
static void set_coefficients(int32_t coef[9])
{
    const double kr = 0.2126, kb = 0.0722, kg = 1 - kr - kb;
    const double luma[3] = {kr, kg, kb};
    const double cb[3] = {-kr / (2 * (1 - kb)), -kg / (2 * (1 - kb)), 0.5};
    const double cr[3] = {0.5, -kg / (2 * (1 - kr)), -kb / (2 * (1 - kr))};
    for (int c = 0; c < 3; c++) {
        coef[c] = (int32_t)lround(65536.0 * 219.0 / 255.0 * luma[c]);
        coef[3 + c] = (int32_t)lround(65536.0 * 224.0 / 255.0 / 4 * cb[c]);
        coef[6 + c] = (int32_t)lround(65536.0 * 224.0 / 255.0 / 4 * cr[c]);
    }
}

/* Converts pixels x0 .. x1 - 1 (x0, x1 even) of rows y, y + 1 (y even).
 * Chroma: the mean of each 2x2 block (centred siting, what a box filter
 * gives; the decoder's upsampling does the rest). */
static void convert_span(video_writer *v, const unsigned char *rgb, int y, int x0, int x1)
{
    const int32_t *k = v->coef;
    const int32_t luma_offset = (16 << 16) + (1 << 15), chroma_offset = (128 << 16) + (1 << 15);
    const unsigned char *top = rgb + ((size_t)y * (size_t)v->width + (size_t)x0) * 3;
    const unsigned char *bottom = top + (size_t)v->width * 3;
    uint8_t *luma_top = v->frame->data[0] + (size_t)y * (size_t)v->frame->linesize[0] + (size_t)x0;
    uint8_t *luma_bottom = luma_top + v->frame->linesize[0];
    size_t chroma_at = (size_t)(y / 2) * (size_t)v->frame->linesize[1] + (size_t)(x0 / 2);
    uint8_t *cb = v->frame->data[1] + chroma_at, *cr = v->frame->data[2] + chroma_at;
    for (int x = x0; x < x1; x += 2, top += 6, bottom += 6) {
        int32_t r = 0, g = 0, b = 0;
        for (int i = 0; i < 2; i++) {
            const unsigned char *a = top + 3 * i, *c = bottom + 3 * i;
            *luma_top++ = (uint8_t)((k[0] * a[0] + k[1] * a[1] + k[2] * a[2] + luma_offset) >> 16);
            *luma_bottom++ = (uint8_t)((k[0] * c[0] + k[1] * c[1] + k[2] * c[2] + luma_offset) >> 16);
            r += a[0] + c[0];
            g += a[1] + c[1];
            b += a[2] + c[2];
        }
        *cb++ = (uint8_t)((k[3] * r + k[4] * g + k[5] * b + chroma_offset) >> 16);
        *cr++ = (uint8_t)((k[6] * r + k[7] * g + k[8] * b + chroma_offset) >> 16);
    }
}

/* The columns [*lo, *hi) of rows y, y + 1 where this frame or the one
 * before were written over their common backdrop (image.h's tracking):
 * outside them the two are the same. The whole row when either is untracked. */
static void changed_columns(const video_writer *v, const image *frame, int y, int *lo, int *hi)
{
    *lo = 0;
    *hi = v->width;
    if (!frame->changed || !v->previous_changed) return;
    *lo = v->width;
    *hi = 0;
    for (int row = y; row < y + 2; row++)
        for (int k = 0; k < 2; k++) {
            const int *span = k ? &frame->changed[2 * row] : &v->previous_changed[2 * row];
            if (span[0] >= span[1]) continue;
            *lo = span[0] < *lo ? span[0] : *lo;
            *hi = span[1] > *hi ? span[1] : *hi;
        }
}

/* Brings the yuv frame up to date with the frame: every pixel of the first;
 * afterwards only the blocks of CHUNK x 2 pixels that differ from the frame
 * before (a rod crossing a row changes a few short runs of it), looked for
 * where either frame was written (changed_columns). */
#define CHUNK 32
static void convert_changed(video_writer *v, const image *frame)
{
    const unsigned char *rgb = frame->rgb;
    size_t row_bytes = (size_t)v->width * 3;
    for (int y = 0; y < v->height; y += 2) {
        size_t at = (size_t)y * row_bytes;
        int lo = 0, hi = v->width;
        if (v->have_previous) changed_columns(v, frame, y, &lo, &hi);
        if (lo >= hi) continue;
        /* most row pairs are unchanged: one comparison settles them */
        if (v->have_previous && lo == 0 && hi == v->width &&
            memcmp(rgb + at, v->previous + at, 2 * row_bytes) == 0)
            continue;
        for (int x0 = lo / CHUNK * CHUNK; x0 < hi; x0 += CHUNK) {
            int x1 = x0 + CHUNK < v->width ? x0 + CHUNK : v->width;
            size_t from = at + (size_t)x0 * 3, bytes = (size_t)(x1 - x0) * 3;
            const unsigned char *top = rgb + from, *bottom = top + row_bytes;
            unsigned char *old_top = v->previous + from, *old_bottom = old_top + row_bytes;
            if (v->have_previous && memcmp(top, old_top, bytes) == 0 &&
                memcmp(bottom, old_bottom, bytes) == 0)
                continue;
            convert_span(v, rgb, y, x0, x1);
            memcpy(old_top, top, bytes);
            memcpy(old_bottom, bottom, bytes);
        }
    }
    v->have_previous = 1;
    if (frame->changed && v->previous_changed)
        memcpy(v->previous_changed, frame->changed, (size_t)v->height * 2 * sizeof(int));
    else {
        free(v->previous_changed); /* untracked: whole rows from now on */
        v->previous_changed = NULL;
    }
}

video_writer *video_writer_create(const char *path, int width, int height, int fps, int crf,
                                  const char *preset, char *err, size_t errlen)
{
    if (width <= 0 || height <= 0 || width % 2 || height % 2) {
        snprintf(err, errlen, "%s: video size %dx%d must be positive and even (yuv420p)", path,
                 width, height);
        return NULL;
    }
    if (av_load(path, err, errlen)) return NULL;
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
    /* No B-frames: less of the encoder's CPU on rod frames for a somewhat
     * larger file, and not a worse picture (docs/decisions/0051-no-b-frames.md) */
    v->codec->max_b_frames = 0;
    /* x264's frame threads: one a core, not its 1.5 a core and a look-ahead
     * thread: the drawing and llvmpipe share the cores; any count gives the
     * same frames (docs/decisions/0146-video-slots.md) */
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    v->codec->thread_count = cores > 0 && cores < 64 ? (int)cores : 0;
    /* BT.709, limited range: what browsers assume for HD H.264 */
    v->codec->colorspace = AVCOL_SPC_BT709;
    v->codec->color_primaries = AVCOL_PRI_BT709;
    v->codec->color_trc = AVCOL_TRC_BT709;
    v->codec->color_range = AVCOL_RANGE_MPEG;
    if (v->format->oformat->flags & AVFMT_GLOBALHEADER)
        v->codec->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
    if (!preset) preset = "veryfast";
    av_opt_set(v->codec->priv_data, "preset", preset, 0);
    av_opt_set_int(v->codec->priv_data, "crf", crf, 0);
    /* veryfast (the default) searches motion as superfast does (diamond,
     * subpixel level 1), keeping its macroblock tree: a rod over a still
     * backdrop costs x264 about a fifth less for a file about a tenth
     * larger, every frame within 50 dB PSNR of the full search's
     * (docs/decisions/0125-video-speed-3.md) */
    if (strcmp(preset, "veryfast") == 0)
        av_opt_set(v->codec->priv_data, "x264-params", "me=dia:subme=1", 0);
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
    v->previous = malloc((size_t)width * (size_t)height * 3);
    v->previous_changed = malloc((size_t)height * 2 * sizeof(int));
    if (!v->previous || !v->previous_changed) {
        snprintf(err, errlen, "%s: out of memory", path);
        video_writer_destroy(v);
        return NULL;
    }
    set_coefficients(v->coef);

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
    /* (copies the pixels if the encoder still held them: the unchanged part stays valid) */
    if (av_frame_make_writable(v->frame) < 0) {
        snprintf(err, errlen, "%s: out of memory", v->file.path);
        return -1;
    }
    double start = wall_seconds();
    convert_changed(v, frame);
    v->frame->pts = v->next_pts++;
    double converted = wall_seconds();
    int status = encode(v, v->frame, err, errlen);
    v->convert_seconds += converted - start;
    v->encode_seconds += wall_seconds() - converted;
    return status;
}

void video_writer_times(const video_writer *v, double *convert, double *encode_seconds)
{
    *convert = v->convert_seconds;
    *encode_seconds = v->encode_seconds;
}

int video_writer_finish(video_writer *v, char *err, size_t errlen)
{
    double start = wall_seconds();
    int status = encode(v, NULL, err, errlen); /* the frames x264 still holds */
    v->encode_seconds += wall_seconds() - start;
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
    free(v->previous);
    free(v->previous_changed);
    av_packet_free(&v->packet);
    av_frame_free(&v->frame);
    avcodec_free_context(&v->codec);
    avformat_free_context(v->format);
    free(v);
}

/* ------------------------------------------------------------------ re-encoding */

/* The decoder's frames, as they come, into the writer (pts in order). */
static int reencode_frames(video_writer *v, AVCodecContext *decoder, AVFrame *frame,
                           const AVPacket *packet, char *err, size_t errlen)
{
    int code = avcodec_send_packet(decoder, packet);
    if (code < 0) {
        av_message(err, errlen, v->file.path, "cannot decode", code);
        return -1;
    }
    for (;;) {
        code = avcodec_receive_frame(decoder, frame);
        if (code == AVERROR(EAGAIN) || code == AVERROR_EOF) return 0;
        if (code < 0) {
            av_message(err, errlen, v->file.path, "cannot decode", code);
            return -1;
        }
        if (frame->format != AV_PIX_FMT_YUV420P || frame->width != v->width ||
            frame->height != v->height) {
            snprintf(err, errlen, "%s: the decoded frames are not yuv420p %dx%d", v->file.path,
                     v->width, v->height);
            av_frame_unref(frame);
            return -1;
        }
        frame->pts = v->next_pts++;
        frame->pict_type = AV_PICTURE_TYPE_NONE; /* the encoder decides, as ffmpeg's CLI does */
        int status = encode(v, frame, err, errlen);
        av_frame_unref(frame);
        if (status) return -1;
    }
}

int video_reencode(const char *in_path, const char *out_path, int crf, const char *preset,
                   int *frames, char *err, size_t errlen)
{
    if (av_load(in_path, err, errlen)) return -1;
    AVFormatContext *input = NULL;
    int code = avformat_open_input(&input, in_path, NULL, NULL);
    if (code < 0) {
        av_message(err, errlen, in_path, "cannot open", code);
        return -1;
    }
    AVCodecContext *decoder = NULL;
    video_writer *v = NULL;
    AVFrame *frame = av_frame_alloc();
    AVPacket *packet = av_packet_alloc();
    int status = -1, stream = -1;
    if (avformat_find_stream_info(input, NULL) >= 0)
        for (unsigned i = 0; i < input->nb_streams && stream < 0; i++)
            if (input->streams[i]->codecpar->codec_type == AVMEDIA_TYPE_VIDEO) stream = (int)i;
    const AVCodec *codec = stream >= 0
                               ? avcodec_find_decoder(input->streams[stream]->codecpar->codec_id)
                               : NULL;
    if (!codec || !frame || !packet || !(decoder = avcodec_alloc_context3(codec)) ||
        avcodec_parameters_to_context(decoder, input->streams[stream]->codecpar) < 0) {
        snprintf(err, errlen, "%s: no video stream that libavcodec decodes", in_path);
        goto done;
    }
    decoder->thread_count = 0; /* as many as the machine has, as ffmpeg's CLI */
    if ((code = avcodec_open2(decoder, codec, NULL)) < 0) {
        av_message(err, errlen, in_path, "cannot open the decoder", code);
        goto done;
    }
    AVRational rate = input->streams[stream]->avg_frame_rate;
    int fps = rate.den > 0 && rate.num > 0 ? (int)lround((double)rate.num / rate.den) : 30;
    v = video_writer_create(out_path, decoder->width, decoder->height, fps, crf, preset, err,
                            errlen);
    if (!v) goto done;
    status = 0;
    while (!status && av_read_frame(input, packet) >= 0) {
        if (packet->stream_index == stream)
            status = reencode_frames(v, decoder, frame, packet, err, errlen);
        av_packet_unref(packet);
    }
    if (!status) status = reencode_frames(v, decoder, frame, NULL, err, errlen); /* flush */
    if (frames) *frames = (int)v->next_pts;
    if (!status) status = video_writer_finish(v, err, errlen);
done:
    video_writer_destroy(v);
    av_packet_free(&packet);
    av_frame_free(&frame);
    avcodec_free_context(&decoder);
    avformat_close_input(&input);
    return status;
}
