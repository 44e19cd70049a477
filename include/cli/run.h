/* run.h: `rodsim run`: load a scene, simulate it, write its outputs.
 *
 * The run loop steps the chosen scheme to the scene's duration, records a
 * frame at every output time k/fps (the step that crosses an output time is
 * shortened to land on it), stops at the first unstable or non-finite step
 * with the scheme's advice, and only then writes anything: a diverged run
 * writes nothing.
 */
#ifndef RODSIM_RUN_H
#define RODSIM_RUN_H

#include <stddef.h>
#include <stdio.h>

#include "base/ini.h"
#include "sim/recording.h"
#include "render/render.h"
#include "sim/rod.h"

/* Exit statuses of every command (PRODUCT.md "Command line"). */
enum {
    RUN_EXIT_OK = 0,
    RUN_EXIT_FAILURE = 1, /* out of memory, a file that cannot be written, ... */
    RUN_EXIT_BAD_INPUT = 2 /* bad scene or usage, or a numerically unstable run */
};

/* The [render] section: how the run is turned into frames and video. Read
 * here (and range-checked) so the scene stays strict before the renderer
 * lands; the renderer reads the same struct. */
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

/* Reads a whole rod scene the way `rodsim run` does: every section and key
 * checked against scene_keys_rod first (an unknown one is reported at its
 * line, with the nearest accepted key), then the model (scene_read_rod), then
 * [render]. Returns 0, or -1 with a message; on failure *m owns nothing. */
int run_read_scene(ini_doc *doc, rod_model *m, run_output *out, char *err, size_t errlen);

/* Output times k/fps <= duration, plus the end time when it is not one of them. */
int run_frame_count(double duration, int fps);

/* What a run cost. */
typedef struct run_stats {
    long steps;
    double wall_seconds;  /* s, of stepping and recording */
    double smallest_step; /* s */
    double largest_step;  /* s */
    int non_finite;       /* 1 when the run stopped on a non-finite state */
} run_stats;

/* Steps `solver` from the state s (at t = 0) to m->options.duration with steps
 * of at most dt, appending a frame to rec at t = 0 and at every output time
 * (run_frame_count); the step that crosses an output time is shortened to
 * land on it exactly. Stops at the first step that is not ROD_OK or leaves a
 * non-finite state (then ROD_UNSTABLE with stats->non_finite = 1); report
 * holds the scheme's message. rec should have room for every frame so that
 * nothing is allocated while stepping. */
rod_status run_simulate(rod_solver *solver, const rod_model *m, rod_state *s,
                        rod_recording *rec, double dt, int fps, rod_report *report,
                        run_stats *stats);

/* Writes t,node,s,x,y,z,d3x,d3y,d3z,twist (s, -, m, m, m, m, -, -, -, 1/m),
 * one row per node per frame, with a header row, atomically (outfile.h).
 * Returns 0, or -1 with a message. */
int run_write_csv(const rod_recording *rec, const char *path, char *err, size_t errlen);

/* The renderer's hook: writes the video of `rec` into out_dir. */
int run_write_video(const rod_recording *rec, const run_output *out, const char *out_dir,
                    char *err, size_t errlen);

/* `rodsim run ...`: argv[0] is "run". Returns an exit status (RUN_EXIT_*);
 * messages go to stdout (summary) and stderr (errors). Never calls exit(). */
int run_command(int argc, char **argv);

/* Prints the usage of `rodsim run` to f. */
void run_usage(FILE *f);

#endif
