/* knot_track.h: the knot type of a run's centreline at every output frame,
 * for `rodsim run`'s summary: the first and last, whether and when it
 * changed, and whether a change was the knot slipping off an end (the
 * strands touched near it the frame before) rather than a pass-through.
 * Summary only, no CSV column: one name per frame would repeat itself. */
#ifndef RODSIM_KNOT_TRACK_H
#define RODSIM_KNOT_TRACK_H

#include <stdio.h>

#include "sim/knot.h"
#include "sim/rod.h"

typedef struct knot_track {
    rod_knot first, last;
    int frames, changes, failures;
    double first_time, last_time, change_time; /* s */
    char change_from[96], change_to[96];
    char failure[256];       /* the first identification that failed, or "" */
    /* the strands' outermost touching nodes in the last frame (-1: none), to
     * tell a knot that slipped off an end from a pass-through */
    int touch_lo, touch_hi;
    double touch_time;
    int slip_end;            /* at the first change: 0 root, 1 tip, -1 neither */
    int slip_reach;          /* segments from that end the strands touched */
    double *prev_pos;        /* (nodes x 3) m, owned: the last frame's positions, or NULL */
    double moved;            /* m: the largest node motion since the last frame */
    double slip_time;        /* s: the frame they touched there */
    double seconds;          /* wall time spent identifying */
    rod_knot_scratch *scratch; /* owned; NULL: each call allocates */
} knot_track;

/* Makes the tracker of a rod of `nodes` nodes (its scratch and the last
 * frame's positions; either may fail to allocate: then the identification
 * allocates per call, and a slip is judged without the frame's motion). */
void knot_track_init(knot_track *k, int nodes);
void knot_track_release(knot_track *k);

/* Identifies the knot of the output frame s and notes a change. */
void knot_track_frame(knot_track *k, const rod_model *m, const rod_state *s);

/* The summary lines (knot at start and end, a change, the rope in the knot,
 * the identification's cost, failures) to f. */
void knot_track_print(FILE *f, const knot_track *k, const rod_model *m);

#endif
