/* test_scene_run.h: a scene's rod read from text, and a run of it from rest
 * step by step, for the tests that build their scenes inline. */
#ifndef RODSIM_TEST_SCENE_RUN_H
#define RODSIM_TEST_SCENE_RUN_H

#include <stdio.h>
#include <string.h>

#include "base/ini.h"
#include "sim/rod.h"
#include "sim/scene.h"

/* The rod of the scene `text` (read as scenes/test.ini, so relative files
 * are the shipped scenes') into m; 0, or -1 with a message */
static inline int read_scene_text(const char *text, rod_model *m, char *err, size_t errlen)
{
    ini_doc *doc = ini_parse(RODSIM_SOURCE_DIR "/scenes/test.ini", text, err, errlen);
    int rc = !doc || scene_read_rod(doc, m, err, errlen) != 0 ? -1 : 0;
    ini_destroy(doc);
    return rc;
}

/* Runs m from its state s for `steps` steps of dt; 0 or -1 (message printed) */
static inline int run_steps(const rod_model *m, rod_state *s, int steps, double dt)
{
    rod_solver solver;
    char err[512];
    if (rod_solver_init(&solver, m, err, sizeof err)) {
        printf("solver: %s\n", err);
        return -1;
    }
    rod_report report;
    memset(&report, 0, sizeof report);
    int rc = 0;
    for (int k = 0; k < steps && rc == 0; k++)
        if (rod_solver_step(&solver, m, s, dt, &report) != ROD_OK) {
            printf("step %d: %s\n", k, report.message);
            rc = -1;
        }
    rod_solver_release(&solver);
    return rc;
}

#endif
