/* instrument.h: surgical instruments (scene [instrument]): rigid tools whose
 * jaws' tip follows a path of poses (sim/path.h's smooth interpolation) with
 * the jaws' opening interpolated the same way; their shapes as capsules the
 * thread touches (sim/contact/instrument.h); the grasps their closed jaws
 * make on the thread (rod_grasp_state), updated after each step. */
#ifndef RODSIM_SIM_INSTRUMENT_H
#define RODSIM_SIM_INSTRUMENT_H

#include <stddef.h>

#include "sim/path.h"
#include "sim/rod_types.h"

/* Jaws at an opening below this are closed: they grasp what is between them. */
#define ROD_JAW_CLOSED 0.1

/* The most capsules an instrument is made of: two jaws, two shanks and a
 * needle holder's box lock. */
#define ROD_INSTRUMENT_CAPSULES 5

/* One capsule of an instrument at a time: the segment a..b (m, global) grown
 * by radius (m). jaw: 1 for a jaw (the grasp holds the thread between them). */
typedef struct rod_capsule {
    double a[3], b[3];
    double radius;
    int jaw;
} rod_capsule;

/* "needle_holder", "forceps", "scissors". */
const char *rod_instrument_kind_name(rod_instrument_kind kind);
/* The names above, NULL-terminated (scene reading, did-you-mean). */
extern const char *const rod_instrument_kind_names[];

/* The instrument's dimensions from its kind and size (m): the jaws' length
 * (from the tip back to the box lock or, for forceps, the tines' gripping
 * part), a jaw's radius and a shank's radius. */
void rod_instrument_dimensions(const rod_instrument *in, double *jaw_length, double *jaw_radius,
                               double *shank_radius);

/* The pose of the jaws' tip at time t (sim/path.h) and the jaws' opening
 * (0 closed .. 1 open, clamped). */
void rod_instrument_pose(const rod_instrument *in, double t, rod_pose *pose, double *jaw);

/* From the jaws' tip back to where the jaws turn (m): the box lock, or the
 * forceps' sprung back end. */
double rod_instrument_hinge(const rod_instrument *in);

/* A needle holder's box lock, the block at the hinge where the jaws cross:
 * a capsule across the hinge along the local z axis (the jaws' opening plane
 * with x, through both jaws), its segment from (-hinge, 0, -half_span) to
 * (-hinge, 0, half_span), grown by radius (m). Returns 1, or 0 (and zeros)
 * for kinds without one. Drawn and touched alike. */
int rod_instrument_box_lock(const rod_instrument *in, double *radius, double *half_span);

/* The angle each jaw turns from the axis at opening `jaw` (rad). */
double rod_instrument_jaw_angle(const rod_instrument *in, double jaw);

/* The capsules at time t (global), into out (ROD_INSTRUMENT_CAPSULES):
 * the two jaws, the two shanks (or tines' back parts), then the box lock
 * when the kind has one; returns how many (4 or 5). */
int rod_instrument_capsules(const rod_instrument *in, double t, rod_capsule *out);

/* The jaws' opening from rows of (t, opening, 0, 0, 0, 0, 0): at rest at
 * every row (a cubic from row to row with zero slope at both: monotone, so
 * closed jaws held over several rows never open between them). */
rod_path *rod_instrument_jaw_path(const double *rows, int count, char *err, size_t errlen);

/* Reads an instrument's path: a CSV text with the header
 * t,x,y,z,rx,ry,rz,jaw and rows of 8 numbers (times increasing, jaw 0..1).
 * Makes *pose (7 columns) and *jaw (rod_instrument_jaw_path). Returns 0, or -1
 * with "FILE:LINE: ..." in err. */
int rod_instrument_parse_path(const char *filename, const char *text, rod_path **pose,
                              rod_path **jaw, char *err, size_t errlen);
/* The same from the file (at most 64 MiB). */
int rod_instrument_load_path(const char *filename, rod_path **pose, rod_path **jaw, char *err,
                             size_t errlen);

/* The point of the grasp of instrument k at time t (global, m): its
 * held point carried by the jaws, and the jaws' velocity there (m/s). */
void rod_grasp_point(const rod_model *m, int k, const rod_grasp_state *g, double t,
                     double point[3], double velocity[3]);

/* The segment j (0..nodes-2) holding arc length arc (m) on the model's
 * grid and the point's fraction along it in *fraction (arc = s_j +
 * fraction ds_j, rod_grid.h), clamped to the thread. */
int rod_grasp_segment(const rod_model *m, double arc, double *fraction);

/* The thread's point nearest the middle line of instrument k's jaws at
 * s->time: its distance (m), its arc length in *arc (m) and the distance
 * within which the jaws take it in *reach (m: two jaw radii plus d). */
double rod_grasp_nearest(const rod_model *m, int k, const rod_state *s, double *arc,
                         double *reach);
/* Instrument k's jaws take the thread at arc length arc (m) at s->time: the
 * grasp held, logged (grasp_log). */
void rod_grasp_take(const rod_model *m, int k, rod_state *s, double arc);
/* Jaws closed on nothing: the warning, in report->warning when it is empty. */
void rod_grasp_missed(const rod_instrument *in, double t, double distance, double reach,
                      rod_report *report);

/* After a step (s at its end): jaws that closed grasp the thread's point
 * between them (the nearest within the jaws' reach; none: a warning in
 * report->warning, when it is empty), jaws that opened release it, and a
 * held point's arc length follows the thread sliding through. A rod of
 * several (m->between_rods) takes no grasp here: the set gives each
 * closing to the rod nearest the jaws (rod_set_step). */
void rod_instruments_update(const rod_model *m, rod_state *s, rod_report *report);

/* 1 when an instrument holds the needle (needle = yes). */
int rod_instrument_holds_needle(const rod_model *m);

#endif
