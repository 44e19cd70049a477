/* knot_across_track.h: the knot two rods of a scene make together (their
 * centrelines closed into one curve: sim/geometry/knot_across.h) at every
 * output frame of `rodsim run`: the first and last, and every change, for
 * the summary (text and `knots_across` in the JSON). */
#ifndef RODSIM_KNOT_ACROSS_TRACK_H
#define RODSIM_KNOT_ACROSS_TRACK_H

#include <stdio.h>

#include "cli/summary.h"
#include "sim/geometry/knot.h"

typedef struct knot_across_track {
    int rod[2];              /* the two rods' places in the scene's order */
    rod_knot first, last;
    int frames, failures;
    double first_time, last_time; /* s */
    int changes;             /* all of them; the first SUMMARY_MAX_KNOT_CHANGES kept */
    summary_knot_change change[SUMMARY_MAX_KNOT_CHANGES];
    char failure[256];       /* the first identification that failed, or "" */
    double seconds;          /* wall time spent identifying */
    double *work;            /* owned: the closed curve (rod_knot_across_points x 3) */
    rod_knot_scratch *scratch; /* owned */
} knot_across_track;

/* Makes the tracker of rods a and b (places in the order) of na and nb
 * nodes; 0, or -1 out of memory (then released and unusable). */
int knot_across_track_init(knot_across_track *k, int a, int b, int na, int nb);
void knot_across_track_release(knot_across_track *k);

/* Identifies the knot of the two centrelines (na x 3 and nb x 3, m) at
 * time t (s) and notes a change. */
void knot_across_track_frame(knot_across_track *k, const double *pa, int na, const double *pb,
                             int nb, double t);

/* The summary's lines (the knot at start and end, its changes, the cost)
 * to f, naming the rods. */
void knot_across_track_print(FILE *f, const knot_across_track *k, const char *name_a,
                             const char *name_b);

/* The knot at the last frame and its changes, as a rod's knot in the JSON
 * (no rope in it: NAN). */
void knot_across_track_fill(const knot_across_track *k, summary_rod_knot *out);

#endif
