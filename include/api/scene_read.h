/* scene_read.h: a rod scene read whole (its model and its [render]
 * section), strictly: every section and key checked against the one key
 * table (scene_keys.h) before any value is read. The cli's commands (run,
 * render, sweep, live) and the library (rodsim.h) read scenes through it,
 * so a bad scene gets the same message from both.
 *
 * The readers keep their run_ names: every command that reads a rod scene
 * calls them. */
#ifndef RODSIM_SCENE_READ_H
#define RODSIM_SCENE_READ_H

#include <stddef.h>

#include "base/ini.h"
#include "render/options.h"
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

#endif
