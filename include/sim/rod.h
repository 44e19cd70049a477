/* rod.h: the functions of the rod model (rod.c): its defaults and derived
 * quantities, the state's creation and measures, and the time-stepping
 * schemes behind one interface (rod_scheme_ops). The types are in
 * rod_types.h. */
#ifndef RODSIM_ROD_H
#define RODSIM_ROD_H

#include <stddef.h>

#include "sim/rod_types.h"

/* Model --------------------------------------------------------------- */

/* Table 1 of the thesis: L = 1 m, d = 1 mm, rho = 850, E = 87.5 MPa,
 * G = 31.25 MPa, NS = 51, T = 10 s; no load, implicit scheme, dt auto. */
rod_model rod_model_default(void);

/* Fills the derived fields. Returns 0, or -1 with a message naming the
 * offending quantity and what is accepted when an input is not physical. */
int rod_model_derive(rod_model *m, char *err, size_t errlen);

/* Releases what the model owns (the profile table, initial_shape, initial_frames,
 * point_loads, root_motion, tip_motion) and sets them to NULL. A model copied
 * by assignment shares them: release exactly one of the copies. */
void rod_model_release(rod_model *m);

/* 1 when every load keeps the rod in the x-y plane: tip force on d1/d3 (or
 * global x, y), tip moment about d2 (or global z), distributed force in x-y,
 * and the ends allow it. Independent of physics.planar. */
int rod_model_loads_planar(const rod_model *m);

/* For a scheme that models only a clamped root and a free tip: 0 when the
 * model has those ends, else -1 with a message naming the scheme, the end
 * condition asked for and what to use instead. */
int rod_model_require_cantilever(const rod_model *m, const char *scheme, char *err,
                                 size_t errlen);

/* For a scheme without contact: 0 when the model has no surfaces and no
 * punctures, else -1 with a message naming the scheme that has them. */
int rod_model_refuse_obstacles(const rod_model *m, const char *scheme, char *err, size_t errlen);

/* Profile factor in [-1, 1] at time t, s (1 for step). For a 7-column
 * table use rod_tip_load() instead. */
double rod_profile_factor(const rod_profile *p, double t);

/* Tip force (N) and moment (N m) at time t, on the model's tip_frame. */
void rod_tip_load(const rod_model *m, double t, double force[3], double moment[3]);

/* First cantilever bending frequency 1.8751^2/(2 pi L^2) sqrt(EI/m), Hz. */
double rod_first_bending_frequency(const rod_model *m);

/* State --------------------------------------------------------------- */

rod_state *rod_state_create(const rod_model *m);
void rod_state_destroy(rod_state *s);
/* Copies everything a step changes from one state into another made for
 * the same model (no allocation): a state kept to go back to. */
void rod_state_copy(rod_state *to, const rod_state *from);
/* t = 0: the starting shape (initial_shape, or straight from origin along
 * direction: thesis 4.2's initial condition when those are the defaults),
 * frames twist-free along it (or a settled start's, initial_frames), every node moving with initial_velocity, no
 * angular velocity, darboux from the frames, no contact force. */
void rod_state_reset(const rod_model *m, rod_state *s);
/* The arc length (m) of the polygon `position` (nodes x 3, the model's
 * segments apart: s_j + f ds_j on segment j, rod_grid.h) nearest the point p, and that distance (m) in *distance when not NULL. */
double rod_nearest_arc_length(const rod_model *m, const double *position, const double p[3],
                              double *distance);
/* Which nodes are threaded through each tissue surface (bit j: surface j,
 * the first 32): a surface's punctures pair up in order (in, out, in, ...:
 * the needle's in the order it made them, after the scene's in the order
 * given), the thread between a pair is inside the tissue, and so is the
 * thread past an unpaired one towards the tip; a segment's length of slack
 * each side (at least the thread's diameter; on a graded grid the longer of
 * the node's two segments) covers the nodes beside a puncture. threaded: nodes entries. */
void rod_threaded_nodes(const rod_model *m, const rod_state *s, unsigned *threaded);
/* The same over segments first..last only (clamped to the rod's). */
double rod_nearest_arc_length_between(const rod_model *m, const double *position,
                                      const double p[3], int first, int last, double *distance);
/* The internal (contact) force N(s) of the thesis at every node, global
 * components, N: `out` is (nodes x 3). At a held or driven end it is the
 * force between the rod and its support; inside, the mean of the two
 * neighbouring segments' N for a staggered state. Staggered: node 0 is
 * end_force[0] (N(0), 0 at a free root), node NS-1 the tip entry of
 * contact_force (N(L): the applied tip force at a free tip, -end_force[1] at
 * a held one; the scheme writes it). */
void rod_internal_force(const rod_state *s, double *out);
/* Kinetic energy, J (translational + rotational, lumped at the nodes). */
double rod_kinetic_energy(const rod_model *m, const rod_state *s);
/* Largest |Q^T Q - I| entry over all frames. */
double rod_frame_orthonormality_error(const rod_state *s);
/* Largest relative deviation of |r_{i+1} - r_i| from ds. */
double rod_segment_length_error(const rod_model *m, const rod_state *s);
/* 1 when every number in the state is finite. */
int rod_state_is_finite(const rod_state *s);

/* Schemes ------------------------------------------------------------- */

typedef struct rod_scheme_ops {
    const char *name; /* as in scene files: "thesis", "implicit", "static" */
    /* Sizes all scratch memory; returns NULL with a message on failure. */
    void *(*create)(const rod_model *m, char *err, size_t errlen);
    /* Advances s by dt (the static scheme: solves equilibrium at s->time + dt). */
    rod_status (*step)(void *work, const rod_model *m, rod_state *s, double dt,
                       rod_report *report);
    void (*destroy)(void *work);
    /* Largest dt believed stable for this model, s (INFINITY when unconditional),
     * and which limit decides it (a static string). May be NULL. */
    double (*stable_dt)(const rod_model *m, const char **limit);
    /* Idle time before a step of dt from s (rod_solver_refresh). May be NULL. */
    int (*refresh)(void *work, const rod_model *m, const rod_state *s, double dt);
} rod_scheme_ops;

extern const rod_scheme_ops rod_scheme_thesis;
extern const rod_scheme_ops rod_scheme_implicit;
extern const rod_scheme_ops rod_scheme_static;

const rod_scheme_ops *rod_scheme_get(rod_scheme_kind kind);
/* Scheme by scene name; NULL when unknown. */
const rod_scheme_ops *rod_scheme_find(const char *name, rod_scheme_kind *kind);

/* A solver: the chosen scheme and its scratch memory. */
typedef struct rod_solver {
    const rod_scheme_ops *ops;
    void *work;
    int cuts;  /* the cuts of the thread its work is made for (rod_state cut_count; sim/cut.h) */
} rod_solver;

int rod_solver_init(rod_solver *solver, const rod_model *m, char *err, size_t errlen);
/* One step of dt from s, m the scene's model. A cut (sim/cut.h) asked for
 * in the step (scissors closing, the scene's [cut]) is made after it; the
 * next step then makes the work again for the thread left and steps that
 * (rod_cut_model(m, s)). A rod of several (m->between_rods) is not cut
 * here: the set cuts it after every rod's solve (rod_set_step). */
rod_status rod_solver_step(rod_solver *solver, const rod_model *m, rod_state *s, double dt,
                           rod_report *report);
void rod_solver_release(rod_solver *solver);
/* Work that makes the next step, of dt from s, cheaper, for a caller with
 * idle time between steps (rodsim live, after an answer): the implicit
 * scheme renews a Jacobian that slowed the last steps' Newton iterations.
 * s is not changed, and the next step's result is the same to the Newton
 * tolerance. Returns 1 when work was done, 0 when none was due (and for
 * the other schemes), -1 when it failed (the next step builds its own). */
int rod_solver_refresh(rod_solver *solver, const rod_model *m, const rod_state *s, double dt);

/* The time step the run will use: options.dt if > 0, else the scheme's
 * stable limit times a safety factor (capped for accuracy); `why` says
 * which limit decided it. */
double rod_choose_dt(const rod_model *m, const char **why);

#endif
