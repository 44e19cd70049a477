/* instrument_path.h: the check of an instrument's path against the scene's
 * solid surfaces before a run. Instruments do not collide with surfaces
 * (only the thread does), so a path that drives an instrument through a
 * pad, the table or a mesh goes on silently; this finds where it does, for
 * a warning. */
#ifndef RODSIM_SIM_INSTRUMENT_PATH_H
#define RODSIM_SIM_INSTRUMENT_PATH_H

#include <stddef.h>

#include "sim/rod_types.h"

/* The time step (s) the path is sampled at; finer where the capsules move
 * more than half a capsule's radius in one (ROD_INSTRUMENT_PATH_MOVE). */
#define ROD_INSTRUMENT_PATH_STEP 1e-3
#define ROD_INSTRUMENT_PATH_MOVE 0.5

/* Where a path takes an instrument into a surface. */
typedef struct rod_instrument_intrusion {
    double t;     /* s: the first sampled time a capsule is more than its radius inside */
    double depth; /* m: the deepest its capsules go into that surface over the path: the
                     capsule's radius less its axis' signed distance (inside a solid, the
                     distance out through its nearest face: a pad 10 mm thick is at most
                     5 mm + the radius deep) */
    int surface;  /* index in the model's surfaces */
    int jaw;      /* 1: a jaw's capsule went in first; 0: a shank's */
} rod_instrument_intrusion;

/* Samples instrument k's path from its first row to its last (or the run's
 * end, m->options.duration, when that comes first and is > 0) every
 * ROD_INSTRUMENT_PATH_STEP and finer where it moves fast; at each time,
 * every capsule against every surface (an elastic pad by its box at rest).
 * Returns 1 with *out when a capsule goes deeper than its own radius into a
 * surface (its axis inside the solid: a graze of the skin is not counted),
 * the first such surface in time; else 0. */
int rod_instrument_path_intrusion(const rod_model *m, int k, rod_instrument_intrusion *out);

/* The same as a warning for people into out: names `file`, the
 * [instrument]'s line, its name, the first time, the depth (mm) and the
 * [surface]'s line. Returns 1 when it wrote one, else 0 (out empty). */
int rod_instrument_path_warning(const rod_model *m, int k, const char *file, char *out,
                                size_t n);

#endif
