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
 * The scene itself is read by api/scene_read.h (run_read_scene). */
#ifndef RODSIM_SCENE_OUTPUTS_H
#define RODSIM_SCENE_OUTPUTS_H

#include <stddef.h>
#include <stdio.h>

#include "api/scene_read.h"
#include "base/ini.h"
#include "cli/knot_track.h"
#include "cli/run.h"
#include "render/render.h"
#include "sim/recording.h"
#include "sim/rod.h"

/* Where a scene's outputs go and how it is run. */
typedef struct scene_outputs_options {
    const char *label;   /* the scene's (or record's) path: heads the summary */
    const char *command; /* names the messages and the summary ("rodsim render");
                            NULL: "rodsim run" */
    const char *out_dir; /* the video and poster, DIR/NAME.mp4 and DIR/NAME.png */
    const char *csv;     /* the centreline CSV; "-": standard output; NULL: none */
    const char *tissue_csv; /* an elastic pad's top-face nodes per frame; NULL: none */
    int no_video, allow_long, quiet;
    int progress;         /* 1: the progress line on stderr whatever stderr is (--progress);
                             0: only on a terminal, for a run estimated over 2 s */
    int talk_stderr;      /* 1: the prose goes to stderr (stdout carries the summary) */
    int silent;           /* 1: nothing printed, the warnings and the error only into the
                             summary (a sweep's point: its row says them) */
    struct run_summary *summary; /* filled as the run goes (summary.h), or NULL */
} scene_outputs_options;

/* The warnings known before a run: what the model moved to make the inputs
 * agree (m->adjusted), a dt above the scheme's stable limit. Into w. */
void scene_outputs_plan_warnings(const rod_model *m, double dt, run_warnings *w);

/* The instruments' paths, checked before a run is stepped (the scene's
 * instruments, every rod's alike): a path into a surface is a warning into
 * w; the jaws driven deeper than max_depth into a rigid surface, or
 * instruments through each other (may_overlap = yes allows it), refuse the
 * run: -1 with `rodsim run`'s message in err (`file` names the scene; the
 * caller says what was not run). Else 0. */
int scene_outputs_path_checks(const rod_model *m, const char *file, run_warnings *w, char *err,
                              size_t errlen);

/* The warnings of a finished run: the scheme's caveat (report->warning), a
 * knot that changed or slipped off an end (knots; a knot tied at an end,
 * KNOT_TIED, is none). Into w. Returns 1, with
 * the message in `error`, when the knot changed where self-contact should
 * have kept it (a strand passed through another: the run fails, exit 1,
 * its outputs kept for a look); else 0. */
int scene_outputs_result_warnings(const rod_model *m, const rod_report *report,
                                  const knot_track *knots, run_warnings *w, char *error,
                                  size_t errlen);

/* The wound's opening (m) of the elastic pad (surface `pad`) at the
 * stitch of the punctures of s in it: at their mean place, or the widest
 * without one. */
double scene_outputs_stitch_gap(const rod_model *m, const rod_state *s, int pad);

/* The closest two of m's instruments come from their paths' start to
 * t_end (s) into the summary's min_instrument_gap (left out with fewer
 * than two instruments). */
void scene_outputs_instrument_gap(struct run_summary *sum, const rod_model *m, double t_end);

/* --tissue-csv's rows at a frame: t,node,x,y,z (s, -, m, m, m) of the
 * elastic pad's top-face nodes (nothing without a pad). */
void scene_outputs_tissue_csv_frame(FILE *f, const rod_model *m, const rod_state *s);

/* Checks the output places before any work: out_dir must be a directory
 * (or creatable) when a video is made, csv and tissue_csv files in one; then removes
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
