/* video.h: H.264 MP4 writer (libx264 through libavcodec, MP4 through
 * libavformat, RGB to yuv420p (BT.709) by hand, only where a frame changed
 * since the one before). The only module that includes libav*; it opens
 * them (dlopen) at the first video_writer_create, so a program that writes
 * no video never loads them. The file is written under a temporary name and renamed
 * by video_writer_finish(); destroying an unfinished writer removes it. */
#ifndef RODSIM_VIDEO_H
#define RODSIM_VIDEO_H

#include <stddef.h>

#include "render/image.h"

typedef struct video_writer video_writer;

/* path: the final .mp4 name. width and height must be even (yuv420p).
 * crf: 0..51; preset: an x264 preset name ("veryfast"), NULL for "veryfast";
 * veryfast searches motion as superfast does (me=dia, subme=1).
 * The MP4 gets +faststart (index first: plays while downloading). NULL with
 * a message on failure (a missing libav* library: named, with its package). */
video_writer *video_writer_create(const char *path, int width, int height, int fps, int crf,
                                  const char *preset, char *err, size_t errlen);
/* Encodes one frame (same size as the writer). 0, or -1 with a message. */
int video_writer_add(video_writer *v, const image *frame, char *err, size_t errlen);
/* Seconds spent so far converting RGB to yuv420p and encoding + muxing. */
void video_writer_times(const video_writer *v, double *convert, double *encode);
/* Flushes the encoder, writes the index and renames the file into place. */
int video_writer_finish(video_writer *v, char *err, size_t errlen);
/* Frees everything; an unfinished file is removed. */
void video_writer_destroy(video_writer *v);

/* For the benchmark's baseline: decodes the video in_path and encodes its
 * frames again into out_path with this writer's encoder settings (crf,
 * preset; what `ffmpeg -i in -c:v libx264 -preset P -crf C -bf 0` does), the
 * count of frames into *frames (may be NULL). 0, or -1 with a message. */
int video_reencode(const char *in_path, const char *out_path, int crf, const char *preset,
                   int *frames, char *err, size_t errlen);

#endif
