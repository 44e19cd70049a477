/* scene_outputs.h: a rod scene to its outputs, for `rodsim run` and
 * `rodsim render`: reading the scene (its model and [render] section),
 * checking where the outputs go, then simulating it (run.h's loop) and
 * writing its CSV, video and poster with the summary on the way.
 *
 * The outputs are one transaction: a diverged, refused, stopped, failed or
 * interrupted run writes nothing. A run estimated to take more than the
 * time limit (run_time_limit, an hour: run_plan_seconds up front, then
 * revised from the CPU time the run takes, run_pace) is refused up front or
 * stopped with exit 2 unless allow_long.
 *
 * The readers keep their run_ names: every command that reads a rod scene
 * (run, render, sweep, live, the tests and benchmarks) calls them. */
#ifndef RODSIM_SCENE_OUTPUTS_H
#define RODSIM_SCENE_OUTPUTS_H

#include <stddef.h>

#include "base/ini.h"
#include "cli/knot_track.h"
#include "cli/run.h"
#include "render/render.h"
#include "sim/recording.h"
#include "sim/rod.h"

/* The [render] section: how the run is turned into frames and video,
 * range-checked here so the scene stays strict; the renderer reads the
 * same struct. */
typedef struct run_output {
    int fps;    /* output frames per simulated second; also the CSV rate (1..1000) */
    int width;  /* video pixels, even, 16..7680 */
    int height; /* video pixels, even, 16..4320 */
    int crf;    /* H.264 constant rate factor, 0 (lossless) .. 51 */
    render_options render; /* every [render] key, for the renderer (fps .. crf copied in) */
} run_output;

/* The renderer's defaults (render_options_default), then the scene's
 * [render] keys. Returns 0, or -1 with "file:line: [render] key = value: ..." in err. */
int run_read_output(ini_doc *doc, run_output *out, char *err, size_t errlen);

/* Reads a whole rod scene: every section and key checked against
 * scene_keys_rod first (an unknown one is reported at its line, with the
 * nearest accepted key), then the model (scene_read_rod), then [render].
 * Returns 0, or -1 with a message; on failure *m owns nothing. */
int run_read_scene(ini_doc *doc, rod_model *m, run_output *out, char *err, size_t errlen);

/* The renderer's hook: writes the video of `rec` into out_dir. */
int run_write_video(const rod_recording *rec, const run_output *out, const char *out_dir,
                    char *err, size_t errlen);

/* Where a scene's outputs go and how it is run. */
typedef struct scene_outputs_options {
    const char *label;   /* the scene's (or record's) path: heads the summary */
    const char *out_dir; /* the video and poster, DIR/NAME.mp4 and DIR/NAME.png */
    const char *csv;     /* the centreline CSV; "-": standard output; NULL: none */
    int no_video, allow_long, quiet;
    int progress;         /* 1: the progress line on stderr whatever stderr is (--progress);
                             0: only on a terminal, for a run estimated over 2 s */
    int talk_stderr;      /* 1: the prose goes to stderr (stdout carries the summary) */
    struct run_summary *summary; /* filled as the run goes (summary.h), or NULL */
} scene_outputs_options;

/* The warnings known before a run: what the model moved to make the inputs
 * agree (m->adjusted), a dt above the scheme's stable limit. Into w. */
void scene_outputs_plan_warnings(const rod_model *m, double dt, run_warnings *w);

/* The warnings of a finished run: the scheme's caveat (report->warning), a
 * knot that changed or slipped off an end (knots). Into w. Returns 1, with
 * the message in `error`, when the knot changed where self-contact should
 * have kept it (a strand passed through another: the run fails, exit 1,
 * its outputs kept for a look); else 0. */
int scene_outputs_result_warnings(const rod_model *m, const rod_report *report,
                                  const knot_track *knots, run_warnings *w, char *error,
                                  size_t errlen);

/* Checks the output places before any work: out_dir must be a directory
 * (or creatable) when a video is made, and csv a file in one; then removes
 * the temporaries a killed run left there. 0, or -1 with a message. */
int scene_outputs_check(const scene_outputs_options *o, char *err, size_t errlen);

/* Simulates the scene read into m and out, writes its outputs named `name`
 * and prints the summary (stdout, or stderr when the CSV or the JSON summary
 * takes stdout); fills o->summary when not NULL (but its exit code and
 * times: the caller's).
 * Returns an exit status (RUN_EXIT_*, args.h). */
int scene_outputs_write(const scene_outputs_options *o, const char *name, const rod_model *m,
                        const run_output *out);

#endif
