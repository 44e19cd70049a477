/* bench_schemes.c: the cost of each scheme, measured in one run (make bench).
 * Prints microseconds per step at NS = 51, 201 and 1001, and wall seconds
 * per simulated second on table 2's first load. Never a test: nothing here
 * passes or fails on time. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "base/ini.h"
#include "sim/rod.h"
#include "sim/scene.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Table 1, table 2's first load (4.5e-7 N on d1) ramped over 2 s, damped. */
static rod_model table2_model(rod_scheme_kind scheme, int nodes)
{
    rod_model m = rod_model_default();
    m.nodes = nodes;
    m.options.scheme = scheme;
    m.tip_force[0] = 4.5e-7;
    m.profile.kind = ROD_PROFILE_RAMP;
    m.profile.t1 = 2.0;
    m.linear_damping = 4e-4;
    char err[256];
    rod_model_derive(&m, err, sizeof err);
    return m;
}

/* The thesis scheme needs its rotary inertia scaled up to run at all: ask
 * the scheme (one step with the physical inertia reports the scale). */
static void stabilise(rod_model *m)
{
    if (m->options.scheme != ROD_SCHEME_THESIS) return;
    char err[256];
    rod_solver solver;
    if (rod_solver_init(&solver, m, err, sizeof err)) return;
    rod_state *s = rod_state_create(m);
    rod_report report;
    double dt = 1.0 / 60.0; /* any dt: below the threshold scale it diverges at every dt */
    for (int k = 0; k < 10; k++)
        if (rod_solver_step(&solver, m, s, dt, &report) != ROD_OK) break;
    rod_solver_release(&solver);
    rod_state_destroy(s);
    if (report.suggested_scale > 0) {
        m->rotary_inertia_scale = report.suggested_scale;
        rod_model_derive(m, err, sizeof err);
    }
}

/* Times `steps` steps of dt after `warmup` steps; returns microseconds per
 * step, or -1 when the run fails (the message is printed). */
static double time_steps(const rod_model *m, double dt, int warmup, int steps)
{
    char err[256];
    rod_solver solver;
    if (rod_solver_init(&solver, m, err, sizeof err)) {
        printf("    (%s)\n", err);
        return -1;
    }
    rod_state *s = rod_state_create(m);
    rod_report report;
    double start = 0, result = -1;
    int k;
    for (k = 0; k < warmup + steps; k++) {
        if (k == warmup) start = now();
        if (rod_solver_step(&solver, m, s, dt, &report) != ROD_OK) {
            printf("    (step %d failed: %.200s)\n", k, report.message);
            break;
        }
    }
    if (k == warmup + steps) result = (now() - start) / steps * 1e6;
    rod_solver_release(&solver);
    rod_state_destroy(s);
    return result;
}

typedef struct variant {
    rod_scheme_kind scheme;
    int planar; /* physics.planar */
    const char *label;
} variant;

static const variant variants[] = {
    {ROD_SCHEME_THESIS, 1, "thesis"},
    {ROD_SCHEME_IMPLICIT, 1, "implicit (planar path)"},
    {ROD_SCHEME_IMPLICIT, 0, "implicit (3-D)"},
    {ROD_SCHEME_STATIC, 1, "static"},
};

int main(void)
{
    static const int sizes[] = {51, 201, 1001};
    printf("rodsim bench: cost per step (table 1 rod, 4.5e-7 N tip load on d1 ramped over 2 s)\n");
    printf("%-24s %6s %10s %12s  %s\n", "scheme", "NS", "dt (s)", "us per step", "dt chosen by");
    for (size_t a = 0; a < sizeof variants / sizeof *variants; a++) {
        for (size_t b = 0; b < sizeof sizes / sizeof *sizes; b++) {
            rod_model m = table2_model(variants[a].scheme, sizes[b]);
            m.physics.planar = variants[a].planar;
            stabilise(&m);
            const char *why = "";
            double dt = rod_choose_dt(&m, &why);
            if (variants[a].scheme == ROD_SCHEME_IMPLICIT) {
                dt = 1.0 / 60.0;
                why = "fixed: one step per 60 Hz frame";
            }
            if (variants[a].scheme == ROD_SCHEME_STATIC) {
                dt = 0.05; /* one equilibrium solve per 5% of the ramp */
                why = "static: one solve per load increment";
            }
            int steps = sizes[b] >= 1001 ? 30 : 200;
            double us = time_steps(&m, dt, 5, steps);
            printf("%-24s %6d %10.4g %12.2f  %s%s\n", variants[a].label, sizes[b], dt, us, why,
                   m.rotary_inertia_scale != 1.0 ? " (rotary inertia scaled to run)" : "");
        }
    }

    /* the table 2 scene itself (scenes/table2_450nN.ini), run dynamically for
     * the 10 s of the thesis by each time-stepping scheme */
    printf("\nwall seconds per simulated second, scenes/table2_450nN.ini, 10 s, NS = 51:\n");
    for (size_t a = 0; a < 3; a++) {
        char err[512];
        ini_doc *doc = ini_load(RODSIM_SOURCE_DIR "/scenes/table2_450nN.ini", err, sizeof err);
        rod_model m = rod_model_default();
        if (!doc || scene_read_rod(doc, &m, err, sizeof err)) {
            printf("  cannot read the scene: %s\n", err);
            ini_destroy(doc);
            return 1;
        }
        ini_destroy(doc);
        m.options.scheme = variants[a].scheme;
        m.physics.planar = variants[a].planar;
        m.options.duration = 10.0;
        char derr[256];
        rod_model_derive(&m, derr, sizeof derr);
        stabilise(&m);
        double dt = variants[a].scheme == ROD_SCHEME_IMPLICIT ? 1.0 / 60.0 : rod_choose_dt(&m, NULL);
        int steps = (int)ceil(10.0 / dt);
        double us = time_steps(&m, dt, 0, steps);
        rod_model_release(&m);
        if (us < 0) continue;
        double per_second = us * 1e-6 * steps / 10.0;
        printf("  %-24s dt = %-10.4g %.3e s per simulated s (%.0fx faster than real time)%s\n",
               variants[a].label, dt, per_second, 1.0 / per_second,
               m.rotary_inertia_scale != 1.0 ? " (rotary inertia scaled to run)" : "");
    }
    return 0;
}
