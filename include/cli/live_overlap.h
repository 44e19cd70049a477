/* live_overlap.h: `rodsim live` keeps instruments out of each other as
 * `rodsim run` does (sim/instrument_overlap.h), where the paths are known:
 * the session's start (every instrument at its scene path's pose at t = 0)
 * and each line's step, from the state's time to the line's with the
 * line's row on its instrument's live path and the scene's path of a
 * needle holder holding the needle (the one path live does not replace). A
 * pair either of which has may_overlap = yes is not refused. The jaws
 * driven deeper than max_depth into a rigid surface are refused as
 * `rodsim run` refuses them (sim/instrument_path.h): at the session's start
 * and at each instrument line's pose (the line not stepped). */
#ifndef RODSIM_CLI_LIVE_OVERLAP_H
#define RODSIM_CLI_LIVE_OVERLAP_H

#include <stddef.h>

#include "sim/rod_types.h"

/* Room for live_overlap_line's text. */
#define LIVE_OVERLAP_LEN 320

/* The session's start: 0, or -1 with "FILE: [instrument] A and B (line N)
 * ..." in err naming both, their parts, the depth and the keys to change. */
int live_overlap_start(const rod_model *m, const char *file, char *err, size_t errlen);

/* The jaws against the rigid surfaces along the paths the session keeps
 * (m's, live paths in place: each instrument at its pose at t = 0, a
 * needle holder holding the needle along its scene path): 0, or -1 with
 * `rodsim run`'s refusal in err (the jaws deeper than max_depth: the
 * instrument, the depth, the surface's line, the key). */
int live_jaws_start(const rod_model *m, const char *file, char *err, size_t errlen);

/* A line's step from t0 to t1 (s), its rows pushed: 0, or -1 with the
 * overlap in words in text (rod_instruments_overlap_text). */
int live_overlap_line(const rod_model *m, double t0, double t1, char *text, size_t n);

/* Instrument k at its line's pose (time t, s, its row pushed): 0, or -1
 * with "the forceps' jaws 4.20 mm into the rigid [surface] of line 30 at
 * t = ..., deeper than max_depth = ..." in text (rod_instrument_jaws_too_deep).
 * The pose asked for, not the way there: a line that turns the jaws back
 * from near the limit (their path a cubic through the rows, sim/path.h)
 * may overshoot by a fraction of a line's motion on the way, and checking
 * it would refuse every line that turns back. */
int live_jaws_line(const rod_model *m, int k, double t, char *text, size_t n);

#endif
