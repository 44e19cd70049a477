/* render.h: the headless renderer. Turns a rod_recording (the frames of a
 * run) into pictures: a tube swept with the rod's own director frames, the
 * twist stripe, what holds each end (a block, a ball) and the needle, the
 * tip load arrows, a backdrop grid with a scale bar and overlay text;
 * writes the MP4, the poster PNG and, on request, every frame as PNG.
 *
 * This header is the renderer's front: the options (options.h), the drive
 * of a run's frames (render.c: render_recording, the stream), and, for the
 * tests, the pure-C geometry its parts expose: the stripe (geometry.h), the
 * camera (camera.h), the ground (shadow.h), the colours (color.h), the
 * strands' occlusion (mesh.h) and the overlay's text (overlay.h). GL
 * drawing lives in gl_render.c, encoding in video.c. */
#ifndef RODSIM_RENDER_H
#define RODSIM_RENDER_H

#include <stddef.h>

#include "base/ini.h"
#include "render/camera.h"
#include "render/color.h"
#include "render/geometry.h"
#include "render/mesh.h"
#include "render/options.h"
#include "render/overlay.h"
#include "render/render_types.h"
#include "render/shadow.h"
#include "sim/recording.h"

/* Renders every frame of rec: out_dir/<scene>.mp4 when want_video,
 * out_dir/<scene>.png (last frame) when o->poster, out_dir/<scene>_frames/
 * NNNNN.png when o->frames_png. Every file is written atomically (outfile.h):
 * on failure nothing half-written remains; inside an outfile transaction
 * they are named only when the transaction commits. A progress line goes to stderr
 * when it is a terminal. Returns 0, or -1 with a message. */
int render_recording(const rod_recording *rec, const render_options *o, const char *out_dir,
                     const char *scene_name, int want_video, char *err, size_t errlen);

/* The same, frame by frame, for a run too long to keep (scene_outputs.c streams it):
 * `extent` frames the camera, the arrows and the grid (frames sampled over
 * the whole run, with the peak loads of all; render_recording passes the
 * recording itself), then render_stream_frame() is called total_frames
 * times, in order, with a recording whose frame 0 is the run's first (the
 * clamp and the stripe's material direction) and `frame` the one to draw.
 * A frame drawn is a function of `extent`, o and the frame alone, not of
 * the frames drawn before it; only render.color = speed takes its
 * difference with the frame given before (the order matters for it).
 * render_stream_finish() completes the outputs (0, or -1 with a message);
 * render_stream_destroy() frees, discarding what is not finished. */
typedef struct render_stream render_stream;
render_stream *render_stream_begin(const rod_recording *extent, const render_options *o,
                                   const char *out_dir, const char *scene_name, int want_video,
                                   int total_frames, char *err, size_t errlen);
int render_stream_frame(render_stream *st, const rod_recording *rec, int frame, char *err,
                        size_t errlen);
int render_stream_finish(render_stream *st, char *err, size_t errlen);
void render_stream_destroy(render_stream *st);

#endif
