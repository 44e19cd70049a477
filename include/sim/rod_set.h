/* rod_set.h: several rods in one scene ([rod NAME], [ends NAME], [tip
 * NAME]), each its own rod_model (material, shape, ends, paths, tip loads,
 * needle) and state, each advanced by its own implicit step, in the scene's
 * order, with one dt, and coupled only through contact: each rod's strands
 * touch the others' as they touch their own, the later rod solving the
 * contact against the earlier's motion and the earlier taking the reaction
 * a step late (sim/contact/between_rods.h). A scene with a bare
 * [rod] is a set of one rod named "rod".
 *
 * Why separate models with a Newton each, not one system of all nodes:
 * docs/decisions/0078-several-rods.md. */
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

struct rod_link; /* sim/contact/rod_contact.h */

typedef struct rod_set {
    int count;                         /* rods, 1 .. ROD_SET_MAX */
    int named;                         /* 1: [rod NAME] sections; 0: one bare [rod] */
    char name[ROD_SET_MAX][ROD_NAME_LEN]; /* "rod" for a bare [rod] */
    rod_model model[ROD_SET_MAX];      /* owned (rod_set_release) */
} rod_set;

/* The scene's rods: the bare [rod] (with [ends], [tip]) as one rod named
 * "rod", or every [rod NAME] with its [ends NAME] and [tip NAME], each read
 * by scene_read_rod (the shared sections, [solver], [loads], [physics],
 * [surface], read for each). Several rods need the implicit scheme and
 * refuse what is not modelled between rods yet (instruments, punctures,
 * point loads, an elastic pad): the message names the file, line and key.
 * Returns 0, or -1 with a message in err (nothing owned then). */
int scene_read_rods(ini_doc *doc, rod_set *set, char *err, size_t errlen);
void rod_set_release(rod_set *set);

/* 1 when the scene has named rods ([rod NAME]); the count in *count. */
int scene_has_named_rods(const ini_doc *doc, int *count);

/* The run of a set: each rod's state and solver, and the contact between
 * rods. */
typedef struct rod_set_run {
    int count;
    rod_state *state[ROD_SET_MAX];
    rod_solver solver[ROD_SET_MAX];
    struct rod_link *link;             /* contact between rods; NULL for one rod */
    long steps;                        /* taken */
    double touch_force[ROD_SET_MAX][3];/* N, global: the force the other rods exert on each
                                          rod, at the end of the last step */
} rod_set_run;

/* Makes the states (at t = 0) and solvers. 0, or -1 with err (nothing
 * owned then). */
int rod_set_run_create(const rod_set *set, rod_set_run *run, char *err, size_t errlen);
void rod_set_run_destroy(rod_set_run *run);

/* One step of dt for every rod: the contact between rods is found from the
 * states at the start, then each rod takes its implicit step. On failure
 * the message names the rod. */
rod_status rod_set_step(const rod_set *set, rod_set_run *run, double dt, rod_report *report);

/* The step every rod takes: the smallest of each rod's rod_choose_dt. */
double rod_set_choose_dt(const rod_set *set, const char **why);

#endif
