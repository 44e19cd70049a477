/* instrument_overlap.h: the instruments' paths checked against each other
 * before a run, and their closest approach over it. Instruments are driven
 * (sim/instrument.h): nothing pushes two apart, so paths that take one
 * through another go on silently; this finds where they do. Their shapes
 * are the capsules the thread touches (rod_instrument_capsules); the needle
 * touches nothing (no shape) and is not checked.
 *
 * The rule: two capsules of different instruments overlap by
 * r_a + r_b - (their segments' distance). Jaw against jaw may overlap by up
 * to the thinner jaw's radius: jaws meet only where they work on the same
 * thing (a needle handed over, the thread taken from other jaws), and a
 * hand-made path's tips graze there. Any other pair (a shank, a box lock)
 * may overlap by ROD_INSTRUMENT_OVERLAP_SHARE of the thinner capsule's
 * radius: a touch. Deeper is an overlap: refused, unless either instrument
 * has [instrument] may_overlap = yes (then allowed). */
#ifndef RODSIM_SIM_INSTRUMENT_OVERLAP_H
#define RODSIM_SIM_INSTRUMENT_OVERLAP_H

#include <stddef.h>

#include "sim/instrument.h"
#include "sim/rod_types.h"

/* A touch of a shank or box lock: this share of the thinner capsule's
 * radius (0.17 mm for a 14 cm needle holder's jaw against a shank). */
#define ROD_INSTRUMENT_OVERLAP_SHARE 0.1

/* The surfaces' distance of two capsules (m): their segments' distance
 * less both radii; below 0, minus how deep they overlap. */
double rod_capsule_gap(const rod_capsule *p, const rod_capsule *q);

/* How deep p and q may overlap without being called an overlap (m): the
 * thinner jaw's radius for two jaws, else ROD_INSTRUMENT_OVERLAP_SHARE of
 * the thinner radius. */
double rod_capsule_overlap_allowed(const rod_capsule *p, const rod_capsule *q);

/* "jaw", "shank", "box lock": capsule i of rod_instrument_capsules' order. */
const char *rod_instrument_capsule_name(int i);

/* Two instruments at their closest, or overlapping. */
typedef struct rod_instrument_contact {
    double t;     /* s; < 0: none */
    double gap;   /* m: the capsules' gap (rod_capsule_gap; < 0: overlapping) */
    int a, b;     /* instruments, a < b */
    int part_a, part_b; /* capsule index of each (rod_instrument_capsule_name) */
} rod_instrument_contact;

typedef struct rod_instrument_overlap {
    rod_instrument_contact closest; /* the least gap of any two instruments over the time */
    rod_instrument_contact first;   /* the first sampled overlap beyond the allowed depth,
                                       of two instruments neither of which has may_overlap
                                       when there is one, else of any two */
    rod_instrument_contact deepest; /* the same two instruments' deepest overlap beyond it */
    double allowed;                 /* m: the depth allowed to first's two capsules */
} rod_instrument_overlap;

/* Samples every instrument's path from the earliest first row to t_end
 * (s; < 0: the latest last row, or m->options.duration when that comes
 * first and is > 0) every ROD_INSTRUMENT_PATH_STEP, finer where a capsule
 * moves more than ROD_INSTRUMENT_PATH_MOVE of the thinnest radius between
 * samples; at each time, every capsule of every instrument against every
 * other instrument's. Fewer than two instruments: closest.t = first.t = -1,
 * returns 0. Returns 1 when an overlap beyond the allowed depth is found
 * (first, deepest), else 0. */
int rod_instruments_overlap(const rod_model *m, double t_end, rod_instrument_overlap *out);

/* The same over [t0, t1] only (s; the ends sampled, every
 * ROD_INSTRUMENT_PATH_STEP from t0 between them): what a step from t0 to
 * t1 does, where the paths grow as it goes (rodsim live's lines). */
int rod_instruments_overlap_between(const rod_model *m, double t0, double t1,
                                    rod_instrument_overlap *out);

/* 1 when the pair of o's first overlap may overlap (either has
 * may_overlap = yes), 0 when it is refused; o from a call that returned 1. */
int rod_instruments_overlap_allowed(const rod_model *m, const rod_instrument_overlap *o);

/* o's first overlap as a short line for people into out: "the forceps'
 * shank (forceps) and the needle holder's box lock (holder) overlap by
 * 2.28 mm at t = 0.512 s (0.14 mm allowed)". */
void rod_instruments_overlap_text(const rod_model *m, const rod_instrument_overlap *o, char *out,
                                  size_t n);

/* The check over the whole paths as a message for people into out: names
 * `file`, both [instrument]s' lines and names, the parts, the first time,
 * the depth, the deepest, and the keys that change it (both paths,
 * may_overlap). Returns 0 (no overlap; out empty), -1 (a refusal) or 1
 * (either instrument has may_overlap = yes: allowed, the message says so;
 * a run says nothing of it, the summary's closest approach shows it). */
int rod_instruments_overlap_message(const rod_model *m, const char *file, char *out, size_t n);

/* The closest two instruments come up to t_end (s; < 0: the whole paths)
 * as a line for people into out: "forceps (shank) and holder (box lock)
 * 1.2 mm apart at t = 3.420 s" (or "... overlap by 1.2 mm at ..."), by
 * their names. Returns 0 with fewer than two instruments (out empty),
 * else 1. */
int rod_instruments_closest_text(const rod_model *m, double t_end, char *out, size_t n);

#endif
