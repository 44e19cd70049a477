/* cut.h: trimming the thread. Scissors ([instrument] kind = scissors) whose
 * blades close across the thread, or the scene's [cut] events, cut it at an
 * arc length; the piece from the cut to the free end on one side is taken
 * out of the run, and the thread left has a free end at the cut.
 *
 * The cut truncates the rod: after the step that asked for it, the thread
 * left gets a model of its own (a copy of the scene's with fewer nodes, its
 * cut end free) held by the state (rod_state cut), the state's arrays keep
 * their size with `nodes` counting the nodes left (moved down to index 0
 * when the root's side goes), and the solver's work is made again for the
 * new model at the next step (rod_solver_step). Everything that reads the
 * state with rod_cut_model(m, s) (the CSV, the recording, contact, the knot
 * tracker, the summary) then sees only the thread left. The cut lands on the
 * node nearest the crossing: the length left is right to half a segment.
 * On a graded grid (rod.refine, sim/rod_grid.h) "nearest" is by the nodes'
 * arc lengths, and the thread left keeps its segments' lengths (a slice of
 * segment_length); its refine intervals stay the scene's (they only mark
 * the grid graded), and first_arc keeps the uncut arc length of its first
 * node (the CSV's s).
 *
 * Which side goes (docs/decisions/0077-trimming.md): a side is anchored
 * when an end fixed in place (clamped or pinned, no path) or a puncture is
 * on it, held when an instrument's jaws grasp it or its end is driven (a
 * path: a hand, the needle in its jaws). The side that is not anchored
 * goes; neither anchored: the side not held; both or neither held: the
 * shorter. The piece that goes takes its holds with it: its grasps let go,
 * its driven end is dropped (a tail cut in the hand or the needle's jaws).
 * Both anchored: nothing is cut (a warning): two threads are not modelled.
 *
 * Several rods (sim/rod_set.h): rod_solver_step leaves a rod of a set
 * (between_rods) uncut; the set's step makes every cut after all the rods'
 * solves and sweeps, the scissors cutting the rod nearest their blades
 * (rod_cut_nearest): the contact between rods always sees whole steps of
 * one thread per rod (the decision record on cutting one of several
 * rods). */
#ifndef RODSIM_SIM_CUT_H
#define RODSIM_SIM_CUT_H

#include <stddef.h>

#include "base/ini.h"
#include "sim/rod.h"
#include "sim/rod_types.h"

/* The model of the thread left after cuts, shared by the states copied from
 * the one that was cut (counted): one allocation per cut, none per step. */
typedef struct rod_cut_thread {
    int refs;             /* states holding it */
    int original_nodes;   /* the uncut thread's NS (the state's arrays' size) */
    rod_model model;      /* a copy of the scene's model (sharing what it owns: surfaces,
                             instruments, punctures, paths) with its own nodes, length and
                             ends; never passed to rod_model_release */
    rod_point_load *point_loads; /* owned: the point loads left, renumbered (or NULL) */
    double *segment_length; /* owned: a graded grid's segments left (model.segment_length),
                               or NULL on a uniform grid */
    double first_arc;     /* m: the uncut thread's arc length at the first node left */
} rod_cut_thread;

/* The model the state is of: the cut thread's when it was cut, else m (the
 * scene's, which every caller holds). */
const rod_model *rod_cut_model(const rod_model *m, const rod_state *s);

/* Asks for a cut at arc length `arc` (m, of the thread as it is now) after
 * the current step; `instrument` is the scissors' index, -1 for the
 * scene's. A second ask before it is made is dropped. */
void rod_cut_ask(rod_state *s, int instrument, double arc);

/* Scissors k closed their blades at s->time: asks for a cut where the
 * thread crosses their middle line (within two blade radii plus d of it),
 * or, crossing nothing, says so in report->warning (when it is empty). */
void rod_cut_on_close(const rod_model *m, int k, rod_state *s, rod_report *report);

/* The thread's point nearest the middle line of scissors k's closed blades
 * at s->time: the distance (m) returned, its arc length on the thread as it
 * is now (m) in *arc, and the distance they cut within (m: two blade radii
 * plus d) in *reach. */
double rod_cut_nearest(const rod_model *m, int k, const rod_state *s, double *arc, double *reach);

/* Scissors that closed at t on nothing within reach (m) of them, the
 * nearest thread `distance` (m) away: the warning, in report->warning
 * when it is empty. */
void rod_cut_missed(const rod_instrument *in, double t, double distance, double reach,
                    rod_report *report);

/* Makes the cut s asks for (s->cut_request), m the scene's model: a new
 * rod_cut_model, the state moved onto it, the cut logged (cut_log). A cut
 * that cannot be made (both sides anchored, within half a segment of an
 * end, fewer than 3 nodes left, the log full) is dropped with a warning in
 * report->warning (when it is empty). Returns 0, or -1 out of memory
 * (report->message says so, the state as it was). */
int rod_cut_apply(const rod_model *m, rod_state *s, rod_report *report);

/* Reads the scene's [cut] sections (repeatable, at most ROD_MAX_CUTS): t
 * (s, > 0) and s (m, inside the thread) into m->cut_events (m->length
 * read before). rod: the name of the [rod NAME] m is (only the [cut]s
 * whose rod key names it are its), NULL for a bare [rod] (a rod key is
 * refused then). 0, or -1 with "file:line: [cut] key = value: ..." in err. */
int rod_cut_read_scene(ini_doc *doc, rod_model *m, const char *rod, char *err, size_t errlen);

/* The scene's [cut] events whose time falls in the step that went from t0
 * to s->time: asked for (rod_cut_ask). */
void rod_cut_scene_events(const rod_model *m, rod_state *s, double t0);

/* The solver made again for the thread s is of (after a cut, or back to
 * the scene's model after a reset): 0, or -1 with a message. */
int rod_cut_solver_sync(rod_solver *solver, const rod_model *m, const rod_state *s, char *err,
                        size_t errlen);

/* For rod.c's state functions: a copy shares from's cut model (counted);
 * a reset or destroy lets go of it (a reset also gives the state back its
 * whole thread's node count and clears the log). */
void rod_cut_share(rod_state *to, const rod_state *from);
void rod_cut_clear(rod_state *s);

#endif
