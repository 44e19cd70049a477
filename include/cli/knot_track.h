/* knot_track.h: the knot type of a run's centreline at every output frame,
 * for `rodsim run`'s summary: the first and last, whether and when it
 * changed, and whether a change happened at an end (the strands touched
 * near it the frame before, or no two strands came closer than
 * KNOT_PASS_GAP diameters between the two frames: a loop passed over an end
 * without touching it) rather than by a pass-through; at an end, whether the
 * knot was tied there or slipped off (KNOT_TIED, KNOT_SLIPPED).
 * Summary only, no CSV column: one name per frame would repeat itself. */
#ifndef RODSIM_KNOT_TRACK_H
#define RODSIM_KNOT_TRACK_H

#include <stdio.h>

#include "sim/geometry/knot.h"
#include "sim/rod.h"

typedef struct knot_track {
    rod_knot first, last;    /* the first and the last frame's (either may be KNOT_FORMING) */
    rod_knot named;          /* the last frame's that named a knot (has_named) */
    int has_named;
    int frames, changes, failures;
    int forming;             /* frames whose knot was KNOT_FORMING */
    double first_time, last_time; /* s */
    /* the first change that was no tie (KNOT_TIED): change_* and slip_*
     * below; ties: the changes that were, the first in tie_* */
    int ties;
    double change_time, tie_time; /* s */
    char change_from[96], change_to[96], tie_from[96], tie_to[96];
    int tie_end;             /* 0 root, 1 tip, -1 an end not told (a loop passed over it) */
    int last_how, last_end;  /* the latest change's KNOT_... and end (as tie_end) */
    char failure[256];       /* the first identification that failed, or "" */
    /* the strands' outermost touching nodes in the last frame (-1: none), to
     * tell a knot that slipped off an end from a pass-through */
    int touch_lo, touch_hi;
    double touch_time;
    int slip_end;            /* at the first change no tie: 0 root, 1 tip, -1 neither */
    int slip_reach;          /* segments from that end the strands touched */
    double *prev_pos;        /* (nodes x 3) m, owned: the last frame's positions, or NULL */
    int prev_first;          /* the uncut thread's node that was node 0 then (sim/cut.h) */
    double moved;            /* m: the largest node motion since the last frame */
    double slip_time;        /* s: the frame they touched there */
    double change_gap;       /* m: the closest two non-neighbouring strands came at a step's
                                end between the frames of the first change (INFINITY: they
                                never touched) */
    double seconds;          /* wall time spent identifying */
    rod_knot_scratch *scratch; /* owned; NULL: each call allocates */
} knot_track;

/* Makes the tracker of a rod of `nodes` nodes (its scratch and the last
 * frame's positions; either may fail to allocate: then the identification
 * allocates per call, and a slip is judged without the frame's motion). */
void knot_track_init(knot_track *k, int nodes);
void knot_track_release(knot_track *k);

/* A step-end distance between non-neighbouring strands below this many
 * diameters means they interpenetrated: with self-contact they stay about a
 * diameter apart, and a strand that passes through another is at distance 0
 * halfway. */
#define KNOT_PASS_GAP 0.5

/* The name of a frame whose knot is still forming: its ends are not drawn
 * out of it, so that the closures of knot.h (radial, tangent, apart) finish
 * it into different knots (a double throw on an instrument, its tail not
 * yet through the turns, closed radially, reads as the finished throw). A
 * knot is named only when the three agree. */
#define KNOT_FORMING "forming"

/* 1 when k is KNOT_FORMING's (its polynomial empty, determinant 0) */
int knot_track_is_forming(const rod_knot *k);

/* Identifies the knot of the output frame s (KNOT_FORMING when the
 * closures disagree) and notes a change (between the knots named: a
 * forming frame is none, so that unknot, forming, trefoil is one change,
 * at the trefoil's first frame); `gap` (m)
 * is the closest non-neighbouring strands came at a step's end since the
 * last frame (run_stats.closest_gap_frame; INFINITY when unknown or never
 * touching). */
void knot_track_frame(knot_track *k, const rod_model *m, const rod_state *s, double gap);

/* 1 when a and b are the same knot: the same Alexander polynomial and
 * signature (a knot turning into its mirror image is a change). */
int knot_track_same(const rod_knot *a, const rod_knot *b);

/* How a change of the knot named came about. At an end (strands touched
 * near it the frame before, or none came within KNOT_PASS_GAP diameters:
 * an end passed through a loop, no strand through another): KNOT_TIED when
 * the knot became more complex (a larger crossing_number, knot.h: an end
 * drawn through a loop ties a knot there) and self-contact is on (without
 * it a strand may pass through another anywhere), else KNOT_SLIPPED
 * (simpler: it slipped off or came undone at that end; as complex, e.g. a
 * knot turned into its mirror: a crossing was undone as one was made, and
 * no throw makes a knot's mirror, so it is no tie either).
 * Elsewhere KNOT_THROUGH: a strand passed through another.
 * The decision record "a knot tied at an end" has the alternatives. */
enum { KNOT_THROUGH, KNOT_SLIPPED, KNOT_TIED };

/* "tied at the root end", "slipped off the tip end", "tied at an end", "a
 * loop passed over an end" (how, end as knot_track's last_how, last_end),
 * or NULL for KNOT_THROUGH */
const char *knot_track_how_text(int how, int end);

/* The first change no tie was no pass-through: the knot slipped off an end (see
 * slip_end) or no strands came within KNOT_PASS_GAP diameters. */
int knot_track_change_is_slip(const knot_track *k, const rod_model *m);

/* The shortest rope that can hold a knot, diameters: the ideal closed
 * trefoil's ropelength. */
#define KNOT_SHORTEST_ROPE 16.37

/* 1 when the scene can knot: its strands touch (self-contact on, which the
 * implicit scheme models) and the rod is longer than KNOT_SHORTEST_ROPE
 * diameters; a run that cannot knot says nothing of knots. */
int knot_track_can_knot(const rod_model *m);

/* 1 when the run's centreline was knotted at some output frame (a scene
 * may start knotted whatever it can do): a knot named, not the unknot nor
 * KNOT_FORMING. */
int knot_track_was_knotted(const knot_track *k);

/* The rope in the knot at the last frame, diameters: the arc between the
 * outermost nodes where strands press on each other; NAN when no frame was
 * identified, the last is an unknot, or no strands touched there. */
double knot_track_rope(const knot_track *k, const rod_model *m);

/* The summary lines (knot at start and end, a change, the rope in the knot,
 * the identification's cost, failures) to f. */
void knot_track_print(FILE *f, const knot_track *k, const rod_model *m);

#endif
