/* live_needle.h: `rodsim live` handing the needle between jaws as `rodsim
 * run` does (scene [needle_grasp], sim/needle_grasp.h). Before the first
 * grasp the tip's lines drive the needle (the driven tip: its back, the
 * thread's tip); from a grasp's time t the named instrument's jaws hold it,
 * keeping the needle's pose relative to them as it was at t: the tip's path
 * gets the pose A(t') Ra(t)^T (b(t) - a(t)) + a(t'), rotation Ra(t') Ra(t)^T
 * Rb(t) at each later line's time t' (A: the jaws' path, live or the
 * scene's; b: the needle's), as rod_path_handover (sim/path.h) gives run.
 * A tip line after a grasp steps the time, its pose not used. */
#ifndef RODSIM_CLI_LIVE_NEEDLE_H
#define RODSIM_CLI_LIVE_NEEDLE_H

#include "sim/path.h"
#include "sim/rod_types.h"

typedef struct live_needle {
    const rod_model *model; /* its grasps and instruments' paths (not owned) */
    int next;               /* the first grasp not taken yet */
    int jaws;               /* the instrument holding the needle, -1: the tip's lines */
    double offset[3];       /* m: the needle's back in the jaws' frame at the grasp */
    double turn[9];         /* the needle's rotation in the jaws' frame (row-major) */
} live_needle;

/* No grasp taken; m's [needle_grasp] (none: nothing is ever handed over). */
void live_needle_init(live_needle *n, const rod_model *m);

/* Takes the grasps whose time is before t (s): the needle's pose at a
 * grasp's time is `tip`'s there (the tip's live path, every row up to the
 * line's), its jaws' pose their path's. How many it took. */
int live_needle_take(live_needle *n, const rod_path *tip, double t);

/* The tip's row at t when jaws hold the needle: row[0] = t, then x,y,z
 * (m) and with columns 7 the rotation vector (rad) nearest `previous`
 * (the last row's rx,ry,rz: a needle turned through pi keeps a continuous
 * path). 1 when jaws hold it (row written), 0 when the tip's lines drive it. */
int live_needle_row(const live_needle *n, double t, int columns, const double *previous,
                    double *row);

#endif
