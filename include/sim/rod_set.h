/* rod_set.h: several rods in one scene ([rod NAME], [ends NAME], [tip
 * NAME]), each its own rod_model (material, shape, ends, paths, tip loads,
 * needle) and state, advanced together by one implicit step of one dt and
 * coupled only through contact: each rod's strands touch the others' as
 * they touch their own, every contact force acting on both rods, equal and
 * opposite, at the end of the step (sim/contact/between_rods.h). A scene
 * with a bare [rod] is a set of one rod named "rod".
 *
 * The step: each rod's own Newton solve, repeated in sweeps over the rods
 * in contact until the contact forces agree with both rods' motion to the
 * Newton tolerance; a rod in no contact is solved once. Why separate models
 * with a Newton each, not one system of all nodes:
 * docs/decisions/0078-several-rods.md; why the sweeps: the decision record
 * on one step for all rods. */
#ifndef RODSIM_SIM_ROD_SET_H
#define RODSIM_SIM_ROD_SET_H

#include <stddef.h>

#include "base/ini.h"
#include "sim/rod.h"
#include "sim/rod_types.h"

/* The most rods a scene holds */
#define ROD_SET_MAX 8
/* The longest rod name (bytes, with its NUL) */
#define ROD_NAME_LEN 32

struct rod_link; /* sim/contact/between_rods.h */

typedef struct rod_set {
    int count;                         /* rods, 1 .. ROD_SET_MAX */
    int named;                         /* 1: [rod NAME] sections; 0: one bare [rod] */
    char name[ROD_SET_MAX][ROD_NAME_LEN]; /* "rod" for a bare [rod] */
    rod_model model[ROD_SET_MAX];      /* owned (rod_set_release) */
} rod_set;

/* The scene's rods: the bare [rod] (with [ends], [tip]) as one rod named
 * "rod", or every [rod NAME] with its [ends NAME] and [tip NAME], each read
 * by scene_read_rod (the shared sections, [solver], [loads], [physics],
 * [surface], read for each; each rod's the [puncture]s naming it, and
 * one elastic pad, the first rod's, shared by all: rod_surface.solid_shared,
 * rod_model.pad_by_set). Several rods need the implicit scheme (else the
 * message names the file, line and key). Each rod's the [cut]s naming it
 * (rod = NAME, required with several rods). Every [instrument] is the
 * scene's: each rod touches all of them; rod = NAME keeps the other rods
 * out of its grasps and cuts; a needle holder with needle = yes holds the
 * needle of the rod its rod key names (required with several rods): only
 * that rod's copy has needle set and its tip driven. Returns 0, or -1 with
 * a message in err (nothing owned then). */
int scene_read_rods(ini_doc *doc, rod_set *set, char *err, size_t errlen);
void rod_set_release(rod_set *set);

/* 1 when the scene has named rods ([rod NAME]); the count in *count. */
int scene_has_named_rods(const ini_doc *doc, int *count);

/* The run of a set: each rod's state and solver, and the contact between
 * rods. */
typedef struct rod_set_run {
    int count;
    rod_state *state[ROD_SET_MAX];
    rod_state *begin[ROD_SET_MAX];     /* the step's start, for a rod's solve again */
    rod_solver solver[ROD_SET_MAX];
    struct rod_link *link;             /* contact between rods; NULL for one rod */
    long steps;                        /* taken */
    long sweeps;                       /* sweeps over the rods in contact, in all steps */
    long solves;                       /* rods' Newton solves, in all steps */
    long unsettled;                    /* steps whose sweeps stopped at ROD_SET_SWEEPS short
                                          of the tolerance */
    double touch_force[ROD_SET_MAX][3];/* N, global: the force the other rods exert on each
                                          rod, at the end of the last step */
    int jaw_closed[ROD_MAX_INSTRUMENTS]; /* 1: instrument k's jaws were closed at the last
                                          step's end (a closing takes a grasp) */
} rod_set_run;

/* Makes the states (at t = 0) and solvers. 0, or -1 with err (nothing
 * owned then). */
int rod_set_run_create(const rod_set *set, rod_set_run *run, char *err, size_t errlen);
void rod_set_run_destroy(rod_set_run *run);

/* The most sweeps of a step */
#define ROD_SET_SWEEPS 30
/* The sweeps end when the pairs' forces change by less than this times the
 * rods' Newton tolerance, relative to the largest: each Newton solve leaves
 * the other rods' motion, and so the forces, uncertain by about 3e-7 of
 * them at a tolerance of 1e-8 (measured on the crossing) */
#define ROD_SET_SWEEP_TOLERANCE 100.0

/* One step of dt for every rod: the contact between rods is found from the
 * states at the start, then the rods solve in sweeps until every contact
 * force agrees with both rods' motion (the largest newton_tolerance of the
 * rods, relative to the largest contact force); then the elastic pad they
 * share, once, under every rod's punctures and contact
 * (tissue_coupling_step_rods). Jaws that closed in the step then take the
 * rod nearest their middle line within their reach (rod_grasp_nearest),
 * once; scissors that closed ask the nearest rod within reach for a cut
 * (rod_cut_nearest). Then the cuts due (scissors', each rod's [cut]s) are
 * made (rod_cut_apply), each cut rod's solver made again for the thread
 * left and linked to the others (rod_link_cut): between steps, so that
 * the sweeps never see a rod change. On failure the message names the
 * rod. */
rod_status rod_set_step(const rod_set *set, rod_set_run *run, double dt, rod_report *report);

/* The step every rod takes: the smallest of each rod's rod_choose_dt. */
double rod_set_choose_dt(const rod_set *set, const char **why);

#endif
