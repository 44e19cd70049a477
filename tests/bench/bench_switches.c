/* bench_switches.c: what each physics switch buys (wall time for the same
 * simulated time) and what it costs (tip position against the full physics),
 * for every scheme where it applies. A benchmark: it reports, never fails on
 * time. Table 1's rod, NS = 51 unless stated.
 *
 * Scenes:
 *   planar: table 2's largest load, 1e-6 N dead along +y, ramped over 2 s,
 *           damped (1e-3 N s/m^2);
 *   3-D:    the same force on d1 plus M1 = 2e-7 N m (bends out of plane) and
 *           M3 = 2e-7 N m (twists), director frame, same ramp and damping. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "study/reference.h"
#include "sim/rod.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static rod_model scene(rod_scheme_kind scheme, int three_d)
{
    rod_model m = rod_model_default();
    m.options.scheme = scheme;
    m.tip_frame = three_d ? ROD_FRAME_DIRECTOR : ROD_FRAME_GLOBAL;
    if (three_d) {
        m.tip_force[0] = 1e-6; /* d1 */
        m.tip_moment[0] = 2e-7;
        m.tip_moment[2] = 2e-7;
    } else {
        m.tip_force[1] = 1e-6;
    }
    m.profile.kind = ROD_PROFILE_RAMP;
    m.profile.t1 = 2.0;
    m.linear_damping = 1e-3;
    if (scheme == ROD_SCHEME_THESIS) m.rotary_inertia_scale = 1e7;
    return m;
}

typedef struct outcome {
    double wall;       /* s */
    long steps;
    double tip[3];     /* m */
    int ok;
    char message[200];
} outcome;

/* Runs the model for `duration` s at dt (repeated `repeats` times; the
 * fastest wall time is kept). */
static outcome run(rod_model m, double dt, double duration, int repeats)
{
    outcome o = {0};
    char err[256];
    if (rod_model_derive(&m, err, sizeof err)) {
        snprintf(o.message, sizeof o.message, "%.190s", err);
        return o;
    }
    o.wall = INFINITY;
    for (int r = 0; r < repeats; r++) {
        rod_solver solver;
        rod_state *s = rod_state_create(&m);
        if (!s || rod_solver_init(&solver, &m, err, sizeof err)) {
            snprintf(o.message, sizeof o.message, "%.190s", err);
            rod_state_destroy(s);
            return o;
        }
        rod_report report;
        rod_status st = ROD_OK;
        long steps = (long)ceil(duration / dt - 1e-9);
        double t0 = now();
        for (long k = 0; k < steps && st == ROD_OK; k++)
            st = rod_solver_step(&solver, &m, s, dt, &report);
        double wall = now() - t0;
        if (wall < o.wall) o.wall = wall;
        o.steps = steps;
        o.ok = st == ROD_OK && rod_state_is_finite(s);
        if (!o.ok) snprintf(o.message, sizeof o.message, "%.190s", report.message);
        memcpy(o.tip, &s->position[3 * (s->nodes - 1)], sizeof o.tip);
        rod_solver_release(&solver);
        rod_state_destroy(s);
    }
    return o;
}

static double distance(const double a[3], const double b[3])
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

/* One table row: the switch, full vs switched run, speed-up and tip change. */
static void compare(const char *scheme, const char *scene_name, const char *what, outcome full,
                    outcome off)
{
    if (!full.ok || !off.ok) {
        printf("%-9s %-7s %-30s failed: %s%s\n", scheme, scene_name, what, full.message,
               off.message);
        return;
    }
    double deflection = fmax(distance(full.tip, (double[3]){1.0, 0.0, 0.0}), 1e-30);
    printf("%-9s %-7s %-30s %8ld %10.4f %10.4f %8.2fx %12.3e %12.3e\n", scheme, scene_name, what,
           full.steps, full.wall, off.wall, full.wall / off.wall, distance(full.tip, off.tip),
           distance(full.tip, off.tip) / deflection);
}

int main(void)
{
    const double duration = 20.0, thesis_duration = 400.0;
    printf("rodsim bench: physics switches (table 1 rod, NS = 51; implicit %g s simulated at "
           "dt = 0.02 s, thesis %g s at its dt = auto; best of 3)\n", duration, thesis_duration);
    printf("%-9s %-7s %-30s %8s %10s %10s %9s %12s %12s\n", "scheme", "scene", "switch", "steps",
           "full s", "switched s", "speed-up", "tip change m", "relative");

    /* thesis scheme (scale 1e7): twist off, at its own dt = auto */
    for (int three_d = 0; three_d < 2; three_d++) {
        rod_model on = scene(ROD_SCHEME_THESIS, three_d), off = on;
        off.physics.twist = 0;
        char err[256];
        rod_model_derive(&on, err, sizeof err);
        rod_model_derive(&off, err, sizeof err);
        const char *why_on = "", *why_off = "";
        double dt_on = rod_choose_dt(&on, &why_on), dt_off = rod_choose_dt(&off, &why_off);
        outcome a = run(on, dt_on, thesis_duration, 3), b = run(off, dt_off, thesis_duration, 3);
        char what[64];
        snprintf(what, sizeof what, "twist off (dt %.3g -> %.3g s)", dt_on, dt_off);
        compare("thesis", three_d ? "3-D" : "planar", what, a, b);
    }

    /* implicit scheme: one step per 20 ms for all (accuracy, not stability) */
    const double dt = 0.02;
    {
        rod_model full = scene(ROD_SCHEME_IMPLICIT, 0), off = full;
        off.physics.planar = 0; /* the 3-D solve of the same planar scene */
        compare("implicit", "planar", "planar fast path (vs 3-D)", run(off, dt, duration, 3),
                run(full, dt, duration, 3));
    }
    for (int three_d = 0; three_d < 2; three_d++) {
        rod_model full = scene(ROD_SCHEME_IMPLICIT, three_d), off = full;
        off.physics.twist = 0;
        compare("implicit", three_d ? "3-D" : "planar", "twist off", run(full, dt, duration, 3),
                run(off, dt, duration, 3));
        off = full;
        off.physics.rotary_inertia = 0;
        compare("implicit", three_d ? "3-D" : "planar", "rotary inertia off",
                run(full, dt, duration, 3), run(off, dt, duration, 3));
        off = full;
        off.physics.damping = 0;
        off.linear_damping = 0.0; /* what the scene reader does for damping = off */
        compare("implicit", three_d ? "3-D" : "planar", "damping off (changes physics)",
                run(full, dt, duration, 3), run(off, dt, duration, 3));
    }

    /* static versus dynamic for a static question: where does table 2's rod
       settle under 1e-6 N? implicit: damped run to 30 s; static: one solve */
    {
        rod_model dyn = scene(ROD_SCHEME_IMPLICIT, 0), sta = scene(ROD_SCHEME_STATIC, 0);
        dyn.linear_damping = 4e-4; /* about critical for the first mode: 2 m omega1 = 3.8e-4 */
        sta.profile.kind = ROD_PROFILE_STEP;
        outcome a = run(dyn, 0.1, 30.0, 1), b = run(sta, 1.0, 1.0, 3);
        char err[256];
        rod_model_derive(&dyn, err, sizeof err);
        elastica_tip ref;
        double reference_y = NAN;
        if (elastica_dead_load(dyn.stiffness[0], dyn.length, 0.0, 1e-6, 0.0, 4000, &ref) == 0)
            reference_y = ref.y;
        compare("implicit", "planar", "static solve instead (30 s)", a, b);
        printf("          settled tip y: implicit (30 s damped) %.7f m, static %.7f m, "
               "elastica %.7f m; errors %.2e, %.2e\n",
               a.tip[1], b.tip[1], reference_y, fabs(a.tip[1] - reference_y) / reference_y,
               fabs(b.tip[1] - reference_y) / reference_y);
    }
    return 0;
}
