/* bench_wound_refine.c: scenes/wound_closure.ini's stitch on meshes of
 * several sizes, linear and quadratic tets: the wound's gap at the stitch at
 * rest, half way through the pull (1 s) and at the end (2.5 s; 0 once the
 * lips meet), per mesh, and the differences between successive meshes of
 * one order; the gap every 0.5 s and the closing time; CPU time per run. A study: it reports,
 * never fails (a run that fails is named with its message).
 *
 *   bench_wound_refine                 every mesh (minutes)
 *   bench_wound_refine ORDER:SIZE[:REFINE] ...  those, e.g. 1:0.006 2:0.008 2:0.006:0.1667
 *                                      (REFINE: wound_refine, the scene's 1/3) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "base/ini.h"
#include "sim/rod.h"
#include "sim/scene.h"
#include "sim/tissue/tissue.h"
#include "sim/tissue/tissue_coupling.h"

#define SCENE RODSIM_SOURCE_DIR "/scenes/wound_closure.ini"

static double cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The gap (m) at rest, at 0.5 s intervals (curve[k] at 0.5 (k + 1) s) and
 * at the scene's end; the closing time (s, the first step whose gap is
 * below 0.01 mm; NAN: open at the end); 0, or -1 (message printed). */
#define CURVE 5
static int run(int order, double size, double refine, double *rest, double *mid, double *end, int *nodes,
               double *seconds, double curve[CURVE], double *closing)
{
    char err[1024] = "", set[64];
    ini_doc *doc = ini_load(SCENE, err, sizeof err);
    rod_model m;
    int rc = !doc;
    snprintf(set, sizeof set, "surface.element_order=%d", order);
    rc = rc || ini_set(doc, set, err, sizeof err);
    snprintf(set, sizeof set, "surface.element_size=%g", size);
    rc = rc || ini_set(doc, set, err, sizeof err);
    if (refine > 0.0) {
        snprintf(set, sizeof set, "surface.wound_refine=%.17g", refine);
        rc = rc || ini_set(doc, set, err, sizeof err);
    }
    const double t0 = cpu();
    rc = rc || scene_read_rod(doc, &m, err, sizeof err);
    ini_destroy(doc);
    if (rc) {
        printf("  order %d, %g mm: %s\n", order, 1e3 * size, err);
        return -1;
    }
    const tissue_solid *t = m.surfaces[tissue_coupling_pad(&m)].solid;
    const double at[3] = {0.0, 0.0, 0.0};
    *nodes = tissue_node_count(t);
    *rest = tissue_coupling_gap_at(t, at);
    rod_state *s = rod_state_create(&m);
    rod_solver solver;
    rod_report report;
    memset(&report, 0, sizeof report);
    const int ready = s && rod_solver_init(&solver, &m, err, sizeof err) == 0;
    rc = !ready;
    if (!ready) printf("  order %d, %g mm: %s\n", order, 1e3 * size, s ? err : "out of memory");
    const int steps = (int)lround(m.options.duration / m.options.dt);
    *mid = NAN;
    *closing = NAN;
    for (int q = 0; q < CURVE; q++) curve[q] = NAN;
    for (int k = 0; k < steps && rc == 0; k++) {
        if (rod_solver_step(&solver, &m, s, m.options.dt, &report) != ROD_OK) {
            printf("  order %d, %g mm: step %d: %s\n", order, 1e3 * size, k, report.message);
            rc = -1;
        }
        if (k + 1 == (int)lround(1.0 / m.options.dt)) *mid = tissue_coupling_gap_at(t, at);
        const double gap = tissue_coupling_gap_at(t, at), time = (k + 1) * m.options.dt;
        if (isnan(*closing) && gap < 1e-5) *closing = time;
        for (int q = 0; q < CURVE; q++)
            if (k + 1 == (int)lround(0.5 * (q + 1) / m.options.dt)) curve[q] = gap;
    }
    if (ready) rod_solver_release(&solver);
    *end = tissue_coupling_gap_at(t, at);
    *seconds = cpu() - t0;
    rod_state_destroy(s);
    rod_model_release(&m);
    return rc ? -1 : 0;
}

int main(int argc, char **argv)
{
    static const char *all[] = {"1:0.006", "1:0.004", "1:0.003", "2:0.008", "2:0.006", "2:0.005"};
    const char **list = argc > 1 ? (const char **)argv + 1 : all;
    const int count = argc > 1 ? argc - 1 : (int)(sizeof all / sizeof all[0]);
    printf("wound_closure's gap at the stitch (mm), by mesh (element_size; a third of it at the "
           "wound)\n");
    int last_order = 0;
    double last_end = NAN, last_mid = NAN;
    for (int i = 0; i < count; i++) {
        int order = atoi(list[i]);
        const char *colon = strchr(list[i], ':');
        double size = colon ? atof(colon + 1) : 0.0;
        const char *third = colon ? strchr(colon + 1, ':') : NULL;
        double refine = third ? atof(third + 1) : 0.0; /* the scene's: 1/3 */
        if ((order != 1 && order != 2) || !(size > 0.0)) {
            printf("  %s: give ORDER:SIZE, e.g. 1:0.006\n", list[i]);
            continue;
        }
        double rest, mid, end, seconds, curve[CURVE], closing;
        int nodes;
        if (run(order, size, refine, &rest, &mid, &end, &nodes, &seconds, curve, &closing)) {
            last_order = 0;
            continue;
        }
        printf("  %s %4.1f mm (%.2f mm at the wound), %5d nodes: at rest %.4f, at 1 s %.4f, at 2.5 s %.4f",
               order == 1 ? "linear   " : "quadratic", 1e3 * size,
               1e3 * size * (refine > 0.0 ? refine : 1.0 / 3.0), nodes, 1e3 * rest, 1e3 * mid,
               1e3 * end);
        if (order == last_order)
            printf(" (%+.4f, %+.4f from the coarser)", 1e3 * (mid - last_mid), 1e3 * (end - last_end));
        printf("; %.1f s CPU\n", seconds);
        printf("    gap at 0.5 1.0 1.5 2.0 2.5 s:");
        for (int q = 0; q < CURVE; q++) printf(" %.4f", 1e3 * curve[q]);
        if (isnan(closing)) printf("; open at the end\n");
        else printf("; closed (below 0.01 mm) at %.3f s\n", closing);
        fflush(stdout);
        last_order = order;
        last_end = end;
        last_mid = mid;
    }
    return 0;
}
