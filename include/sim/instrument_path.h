/* instrument_path.h: the check of an instrument's path against the scene's
 * solid surfaces before a run. Instruments do not collide with surfaces
 * (only the thread does), so a path that drives an instrument through a
 * pad, the table or a mesh goes on silently; this finds where it does, for
 * a warning, and refuses a path that drives the jaws deeper into a rigid
 * surface than a limit (a touch is a warning; a path through the table is
 * a mistake). */
#ifndef RODSIM_SIM_INSTRUMENT_PATH_H
#define RODSIM_SIM_INSTRUMENT_PATH_H

#include <stddef.h>

#include "sim/rod_types.h"

/* The time step (s) the path is sampled at; finer where the capsules move
 * more than half a capsule's radius in one (ROD_INSTRUMENT_PATH_MOVE). */
#define ROD_INSTRUMENT_PATH_STEP 1e-3
#define ROD_INSTRUMENT_PATH_MOVE 0.5

/* The parts of an instrument, as its capsules (rod_instrument_capsules):
 * 0, 1 the jaws, 2, 3 the shanks, 4 the box lock. */
typedef enum {
    ROD_PART_JAWS = 0,
    ROD_PART_SHANKS,
    ROD_PART_BOX_LOCK
} rod_instrument_part;

/* "jaws", "shanks", "box lock" */
const char *rod_instrument_part_name(rod_instrument_part part);

/* Where a path takes an instrument into a surface. */
typedef struct rod_instrument_intrusion {
    double t;     /* s: the first sampled time a capsule is more than its radius inside */
    double depth; /* m: the deepest its capsules go into that surface over the path: the
                     capsule's radius less its axis' signed distance (inside a solid, the
                     distance out through its nearest face: a pad 10 mm thick is at most
                     5 mm + the radius deep) */
    double depth_t; /* s: when it is that deep */
    int surface;  /* index in the model's surfaces */
    int part;     /* rod_instrument_part: the part that went in first */
    int depth_part; /* the part that goes deepest */
    /* the jaws against every rigid surface (not an elastic pad): their
     * deepest over the path (m; 0: they never touch one), when and where */
    double jaw_depth, jaw_t;
    int jaw_surface;
} rod_instrument_intrusion;

/* The deepest the jaws may go into a rigid surface (m): [instrument]
 * max_depth, or, absent (0), the jaws' thickness (two jaw radii). */
double rod_instrument_max_depth(const rod_instrument *in);

/* Samples instrument k's path from its first row to its last (or the run's
 * end, m->options.duration, when that comes first and is > 0) every
 * ROD_INSTRUMENT_PATH_STEP and finer where it moves fast; at each time,
 * every capsule against every surface (an elastic pad by its box at rest).
 * Returns 1 with *out when a capsule goes deeper than its own radius into a
 * surface (its axis inside the solid: a graze of the skin is not counted),
 * the first such surface in time, or when the jaws go deeper than
 * rod_instrument_max_depth into a rigid one; else 0. */
int rod_instrument_path_intrusion(const rod_model *m, int k, rod_instrument_intrusion *out);

/* The same over [t0, t1] only (rodsim live: the stretch one line adds). */
int rod_instrument_path_intrusion_between(const rod_model *m, int k, double t0, double t1,
                                          rod_instrument_intrusion *out);

/* When hit's jaws go deeper than rod_instrument_max_depth into a rigid
 * surface: 1 with "the forceps' jaws 2.10 mm into the rigid [surface] of
 * line 30 at t = 0.800 s, deeper than max_depth = ...: the thread would be
 * pressed into the surface" in out; else 0 (out empty). */
int rod_instrument_jaws_too_deep(const rod_model *m, int k, const rod_instrument_intrusion *hit,
                                 char *out, size_t n);

/* The same as a warning for people into out: names `file`, the
 * [instrument]'s line, its name, the part that goes in first (jaws,
 * shanks, box lock), the first time, the depth (mm) and the [surface]'s
 * line. Returns 1 when it wrote one, else 0 (out empty). When the jaws go
 * deeper than rod_instrument_max_depth into a rigid surface, returns -1
 * with a refusal in out instead: the depth, the time, the limit and the
 * key that changes it ([instrument] max_depth). */
int rod_instrument_path_warning(const rod_model *m, int k, const char *file, char *out,
                                size_t n);

#endif
