/* bench_schemes.c: the cost of each scheme, measured in one run (make bench).
 * Prints microseconds per step at NS = 51, 201 and 1001, and CPU seconds
 * per simulated second on table 2's first load. Then the realistic cases
 * (an undamped step load, every shipped rod scene) twice: by the bench's
 * own loop of equal steps, and through run_simulate, the loop of
 * `rodsim run --no-video` (steps landing on the output times), side by side
 * with their ratio, so that the bench times what a run does. Times are CPU
 * time (see now()). Never a test: nothing here passes or fails on time. */
#include <glob.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "base/ini.h"
#include "cli/run.h"
#include "cli/scene_outputs.h"
#include "sim/path.h"
#include "sim/rod.h"
#include "sim/scene.h"

/* CPU seconds of this process: wall time on an idle machine (the stepping
 * is single-threaded), and steady on a shared one, where wall time counts
 * the other processes' turns too. */
static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
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

/* What one way of stepping cost. */
typedef struct timing {
    double us;  /* CPU microseconds per step, -1 when the run failed */
    long steps;
    long jacobian_builds; /* implicit scheme (rod_report.jacobian_builds) */
} timing;

/* The bench's loop: `steps` steps of exactly dt from the start state. */
static timing time_equal_steps(const rod_model *m, double dt, long steps)
{
    timing r = {-1.0, 0, 0};
    char err[256];
    rod_solver solver;
    if (rod_solver_init(&solver, m, err, sizeof err)) {
        printf("    (%s)\n", err);
        return r;
    }
    rod_state *s = rod_state_create(m);
    rod_report report = {0};
    double start = now();
    for (r.steps = 0; r.steps < steps; r.steps++) {
        if (rod_solver_step(&solver, m, s, dt, &report) != ROD_OK) {
            printf("    (step %ld failed: %.200s)\n", r.steps, report.message);
            break;
        }
    }
    if (r.steps == steps) r.us = (now() - start) / (double)steps * 1e6;
    r.jacobian_builds = report.jacobian_builds;
    rod_solver_release(&solver);
    rod_state_destroy(s);
    return r;
}

/* The run's loop: run_simulate to m->options.duration with steps of at most
 * dt, as `rodsim run --no-video` does (equal steps per frame interval). */
static timing time_run_loop(const rod_model *m, double dt, int fps)
{
    timing r = {-1.0, 0, 0};
    char err[256];
    rod_solver solver;
    if (rod_solver_init(&solver, m, err, sizeof err)) {
        printf("    (%s)\n", err);
        return r;
    }
    rod_state *s = rod_state_create(m);
    run_plan plan;
    rod_report report = {0};
    run_stats stats;
    if (s && run_plan_make(m, dt, fps, &plan) == 0) {
        double start = now(); /* not stats.wall_seconds: the same clock as the bench loop */
        /* no frame callback: `rodsim run --no-video` without --csv keeps nothing */
        rod_status st = run_simulate(&solver, m, s, &plan, fps, NULL, NULL, &report, &stats);
        double seconds = now() - start;
        r.steps = stats.steps;
        if (st == ROD_OK && stats.steps > 0) r.us = 1e6 * seconds / (double)stats.steps;
        else printf("    (the run stopped at t = %g s: %.200s)\n", s->time, report.message);
        r.jacobian_builds = report.jacobian_builds;
    }
    rod_solver_release(&solver);
    rod_state_destroy(s);
    return r;
}

static void print_pair_header(void)
{
    printf("%-26s %-9s %9s %4s | %7s %9s %6s | %7s %9s %6s | %6s\n", "case", "scheme", "dt (s)",
           "fps", "steps", "us/step", "Jac.", "steps", "us/step", "Jac.", "run/");
    printf("%-26s %-9s %9s %4s | %-24s | %-24s | %6s\n", "", "", "", "",
           "bench: equal steps of dt", "run: run_simulate", "bench");
}

/* One case both ways. The bench takes the run's number of steps at dt
 * capped at 1/fps (the run's own cap), so both cover the same time. */
static void time_both_ways(const char *label, const rod_model *m, double dt, int fps)
{
    double h = fmin(dt, 1.0 / fps);
    long steps = (long)ceil(m->options.duration / h - 1e-9);
    timing bench = time_equal_steps(m, h, steps);
    timing run = time_run_loop(m, dt, fps);
    printf("%-26s %-9s %9.4g %4d | %7ld %9.2f %6ld | %7ld %9.2f %6ld | %6.2f\n", label,
           rod_scheme_get(m->options.scheme)->name, h, fps, bench.steps, bench.us,
           bench.jacobian_builds, run.steps, run.us, run.jacobian_builds,
           bench.us > 0 && run.us > 0 ? run.us / bench.us : NAN);
    fflush(stdout);
}

/* Every rod scene in scenes/ (beam FEM scenes are skipped), as shipped. */
static void time_shipped_scenes(void)
{
    glob_t found;
    if (glob(RODSIM_SOURCE_DIR "/scenes/*.ini", 0, NULL, &found) != 0) {
        printf("  no scenes found\n");
        return;
    }
    for (size_t k = 0; k < found.gl_pathc; k++) {
        const char *path = found.gl_pathv[k];
        char err[1024], name[128];
        ini_doc *doc = ini_load(path, err, sizeof err);
        rod_model m = rod_model_default();
        run_output out;
        if (!doc) {
            printf("  %s\n", err);
            continue;
        }
        if (ini_section_count(doc, "rod") == 0) {
            ini_destroy(doc);
            continue; /* not a rod scene (rodsim fem) */
        }
        if (scene_read_rod(doc, &m, err, sizeof err) ||
            run_read_output(doc, &out, err, sizeof err)) {
            printf("  %s: %s\n", path, err);
            ini_destroy(doc);
            rod_model_release(&m);
            continue;
        }
        ini_scene_name(doc, name, sizeof name);
        ini_destroy(doc);
        double dt = rod_choose_dt(&m, NULL);
        if (dt > 0.0) time_both_ways(name, &m, dt, out.fps);
        else printf("%-26s (no stable dt)\n", name);
        rod_model_release(&m);
    }
    globfree(&found);
}

/* the ends in the implicit scheme (3-D), each beside today's
 * cantilever at the same NS: table 2's ramped tip load (on a held tip it
 * goes to the support) and a small distributed load along +y, so that a
 * rod held at both ends bends too. The cost per step of each, and its
 * ratio to the cantilever's (the budget: within 10 %). */
static void time_ends(void)
{
    typedef struct end_case {
        const char *label;
        rod_end_kind root, tip;
        double tip_slide; /* along x */
        int driven;       /* root driven 1 cm along +z, eased over 10 s (needs sim/path.c) */
    } end_case;
    static const end_case cases[] = {
        {"cantilever (reference)", ROD_END_CLAMPED, ROD_END_FREE, 0.0, 0},
        {"clamped-clamped, sleeve", ROD_END_CLAMPED, ROD_END_CLAMPED, 1.0, 0},
        {"pinned-pinned, sleeve", ROD_END_PINNED, ROD_END_PINNED, 1.0, 0},
        {"free-free", ROD_END_FREE, ROD_END_FREE, 0.0, 0},
        {"cantilever, root driven", ROD_END_CLAMPED, ROD_END_FREE, 0.0, 1},
    };
    static const int sizes[] = {51, 201};
    printf("\nends, implicit 3-D, dt = 1/60 s, 200 steps: us per step and the ratio "
           "to the cantilever at the same NS:\n");
    for (size_t b = 0; b < sizeof sizes / sizeof *sizes; b++) {
        double reference = -1.0;
        for (size_t c = 0; c < sizeof cases / sizeof *cases; c++) {
            rod_model m = table2_model(ROD_SCHEME_IMPLICIT, sizes[b]);
            m.physics.planar = 0;
            m.distributed_force[1] = 1e-6; /* N/m, +y */
            m.root_end = cases[c].root; /* after derive: it may not accept a free root yet */
            m.tip_end = cases[c].tip;
            m.tip_slide[0] = cases[c].tip_slide;
            /* a smooth start (held before t = 0): a driven end that starts
             * moving at once pulls an inextensible rod with an impulse */
            enum { ROWS = 101 };
            double rows[4 * ROWS];
            for (int r = 0; r < ROWS; r++) {
                double x = r / (ROWS - 1.0);
                rows[4 * r] = 10.0 * x;
                rows[4 * r + 1] = rows[4 * r + 2] = 0.0;
                rows[4 * r + 3] = 0.01 * x * x * x * (10.0 - 15.0 * x + 6.0 * x * x);
            }
            char err[256];
            if (cases[c].driven && !(m.root_motion = rod_path_create(rows, ROWS, 4, err, sizeof err))) {
                printf("    (%s)\n", err);
                continue;
            }
            timing t = time_equal_steps(&m, 1.0 / 60.0, 200);
            rod_path_destroy(m.root_motion);
            if (c == 0) reference = t.us;
            printf("  %-26s NS=%-5d %10.2f us per step  %5.3f x cantilever  (%ld Jacobians)\n",
                   cases[c].label, sizes[b], t.us, reference > 0 && t.us > 0 ? t.us / reference : NAN,
                   t.jacobian_builds);
        }
    }
}

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
    printf("\nCPU seconds per simulated second, scenes/table2_450nN.ini, 10 s, NS = 51:\n");
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

    /* what `rodsim run` meets: no damping to settle the rod, and the run
     * loop's steps landing on the output times; then the shipped scenes */
    printf("\nrealistic cases, bench loop vs run loop (Jac. = implicit Jacobians built):\n");
    print_pair_header();
    for (size_t a = 1; a < 3; a++) {
        static const int undamped_sizes[] = {51, 201};
        for (size_t b = 0; b < 2; b++) {
            rod_model m = table2_model(variants[a].scheme, undamped_sizes[b]);
            m.profile.kind = ROD_PROFILE_STEP;
            m.linear_damping = 0.0;
            m.physics.planar = variants[a].planar;
            m.options.duration = 10.0;
            char label[64];
            snprintf(label, sizeof label, "undamped step %s NS=%d",
                     variants[a].planar ? "2-D" : "3-D", undamped_sizes[b]);
            time_both_ways(label, &m, 1.0 / 60.0, 30);
        }
    }
    time_shipped_scenes();
    time_ends();
    return 0;
}
