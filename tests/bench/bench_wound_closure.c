/* bench_wound_closure.c: what scenes/wound_closure.ini (a stitch closing a
 * wound in an elastic pad) costs a step, split into the rod, the pad and
 * the coupling between them. A benchmark: it reports, never fails on time.
 * CPU time is the process clock (user + sys).
 *
 * The whole run at rodsim run's steps (equal, n per frame interval, none
 * over the scene's dt), three times; the run of the median CPU time. The
 * split: the pad (tissue_cost: its forces and matrix assemblies, the
 * inversion tests after each Newton update, the numeric factorisations,
 * the triangular solves of Newton and of the compliances), the coupling (its calls' time
 * less the pad's parts: surface mesh moves, i.e. normals and tree refits,
 * contact loads, patch positions, the bookkeeping of compliance renewals)
 * and the rod (the rest: the rod's implicit step with its contact queries
 * on the pad's surface). The pad's counts a step: assemblies (with the
 * matrix; forces reused at unchanged positions), factorisations and solves. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "base/ini.h"
#include "cli/scene_outputs.h"
#include "sim/rod.h"
#include "sim/scene.h"
#include "sim/tissue/tissue.h"
#include "sim/tissue/tissue_coupling.h"

static double cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int by_value(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, by_value);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

enum { TOTAL, ROD, PAD, ASSEMBLY, CHECK, FACTOR, SOLVE, COUPLING, PARTS };

/* One whole run: us a step of each part (PARTS), the pad's counts a step
 * (assemblies, of them with the matrix, factorisations, solves), the steps
 * and the simulated time (s). 0, or -1 with a message printed. */
static int run_once(const char *path, double us[PARTS], double counts[5], long *steps_out,
                    double *simulated)
{
    char err[1024];
    ini_doc *doc = ini_load(path, err, sizeof err);
    rod_model m = rod_model_default();
    run_output out;
    rod_state *s = NULL;
    rod_solver solver;
    int solver_ok = 0, rc = -1;
    if (!doc || scene_read_rod(doc, &m, err, sizeof err) ||
        run_read_output(doc, &out, err, sizeof err)) {
        printf("  %s: %s\n", path, err);
        goto done;
    }
    const int pad = tissue_coupling_pad(&m);
    s = rod_state_create(&m);
    if (pad < 0 || !s || rod_solver_init(&solver, &m, err, sizeof err)) {
        printf("  %s: %s\n", path, pad < 0 ? "no elastic pad" : s ? err : "out of memory");
        goto done;
    }
    solver_ok = 1;
    rod_state_reset(&m, s);
    const double frame = 1.0 / out.fps;
    const double dt = frame / ceil(frame / rod_choose_dt(&m, NULL) - 1e-9);
    const long steps = lround(m.options.duration / dt);
    tissue_solid *t = m.surfaces[pad].solid;
    const tissue_costs c0 = tissue_cost(t);
    const long f0 = tissue_factorisations(t);
    rod_report report;
    memset(&report, 0, sizeof report);
    const double t0 = cpu();
    long k = 0;
    for (; k < steps; k++)
        if (rod_solver_step(&solver, &m, s, dt, &report) != ROD_OK) {
            printf("  step %ld: %s\n", k, report.message);
            goto done;
        }
    const double total = cpu() - t0;
    const tissue_costs c1 = tissue_cost(t);
    const double n = (double)steps, to_us = 1e6 / n;
    us[TOTAL] = total * to_us;
    us[ASSEMBLY] = (c1.assembly_s - c0.assembly_s) * to_us;
    us[CHECK] = (c1.check_s - c0.check_s) * to_us;
    us[FACTOR] = (c1.factor_s - c0.factor_s) * to_us;
    us[SOLVE] = (c1.solve_s - c0.solve_s) * to_us;
    us[PAD] = us[ASSEMBLY] + us[CHECK] + us[FACTOR] + us[SOLVE];
    us[COUPLING] = (c1.coupling_s - c0.coupling_s) * to_us - us[PAD];
    us[ROD] = us[TOTAL] - us[PAD] - us[COUPLING];
    counts[0] = (double)(c1.assemblies - c0.assemblies) / n;
    counts[1] = (double)(c1.matrix_assemblies - c0.matrix_assemblies) / n;
    counts[2] = (double)(tissue_factorisations(t) - f0) / n;
    counts[3] = (double)(c1.solves - c0.solves) / n;
    counts[4] = (double)(c1.forces_reused - c0.forces_reused) / n;
    *steps_out = steps;
    *simulated = n * dt;
    rc = 0;
done:
    if (solver_ok) rod_solver_release(&solver);
    rod_state_destroy(s);
    if (doc) ini_destroy(doc);
    rod_model_release(&m);
    return rc;
}

int main(void)
{
    char path[512];
    snprintf(path, sizeof path, "%s/scenes/wound_closure.ini", RODSIM_SOURCE_DIR);
    enum { RUNS = 3 };
    double us[PARTS][RUNS], counts[5][RUNS], simulated = 0.0;
    long steps = 0;
    for (int r = 0; r < RUNS; r++) {
        double u[PARTS], c[5];
        if (run_once(path, u, c, &steps, &simulated)) return 1;
        for (int p = 0; p < PARTS; p++) us[p][r] = u[p];
        for (int p = 0; p < 5; p++) counts[p][r] = c[p];
    }
    /* the run of the median total, its parts as they were */
    double totals[RUNS];
    memcpy(totals, us[TOTAL], sizeof totals);
    const double mid = median(totals, RUNS);
    int r = 0;
    while (r + 1 < RUNS && us[TOTAL][r] != mid) r++;
    double med[PARTS], cnt[5];
    for (int p = 0; p < PARTS; p++) med[p] = us[p][r];
    for (int p = 0; p < 5; p++) cnt[p] = counts[p][r];
    printf("wound_closure.ini, the whole run (%ld steps, %.2f s simulated), the run of the "
           "median CPU time of %d:\n",
           steps, simulated, RUNS);
    printf("  %.0f us CPU a step, %.2f CPU s per simulated s: rod %.0f us, pad %.0f us "
           "(assembly %.0f, inversion tests %.0f, factorisation %.0f, solves %.0f), "
           "coupling %.0f us\n",
           med[TOTAL], med[TOTAL] * 1e-6 * (double)steps / simulated, med[ROD], med[PAD],
           med[ASSEMBLY], med[CHECK], med[FACTOR], med[SOLVE], med[COUPLING]);
    printf("  the pad a step: %.2f assemblies (%.4f with the matrix; %.2f more forces taken from "
           "the last at the same positions), %.4f factorisations, %.2f solves\n",
           cnt[0], cnt[1], cnt[4], cnt[2], cnt[3]);
    return 0;
}
