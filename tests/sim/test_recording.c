/* test_recording.c: the frames a run hands to the renderer: the punctures
 * each frame carries survive append and halve, and the memory a
 * recording is charged for is what it allocates. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/path.h"
#include "sim/recording.h"
#include "test.h"
#include "sim/rod.h"

static void test_punctures(void)
{
    char err[256] = "";
    rod_model m = rod_model_default();
    m.nodes = 11;
    if (!check(rod_model_derive(&m, err, sizeof err) == 0, "model derived%s%s", err[0] ? ": " : "", err)) return;
    rod_state *s = rod_state_create(&m);
    rod_recording *r = rod_recording_create(&m, "punctures", 2);
    if (!check(s && r, "state and recording made")) return;
    /* frames 0..4 with 0, 1, 2, 3 and ROD_MAX_PUNCTURES + 5 punctures (the state's
     * count beyond the array is clamped, never read past it) */
    const int counts[5] = {0, 1, 2, 3, ROD_MAX_PUNCTURES + 5};
    for (int f = 0; f < 5; f++) {
        s->time = 0.1 * f;
        s->puncture_count = counts[f] < ROD_MAX_PUNCTURES ? counts[f] : ROD_MAX_PUNCTURES;
        for (int i = 0; i < ROD_MAX_PUNCTURES; i++) {
            s->puncture[i].point[0] = f;
            s->puncture[i].point[1] = i;
            s->puncture[i].point[2] = -0.01 * i;
        }
        if (f == 4) s->puncture_count = counts[f]; /* a corrupt count must not overrun */
        check(rod_recording_append(r, &m, s) == 0, "frame %d appended (capacity grows from 2)", f);
    }
    int good = 1;
    for (int f = 0; f < 5; f++) {
        const double *p;
        int n = rod_recording_punctures(r, f, &p);
        int want = counts[f] < ROD_MAX_PUNCTURES ? counts[f] : ROD_MAX_PUNCTURES;
        if (n != want) good = 0;
        for (int i = 0; i < n; i++)
            if (p[3 * i] != f || p[3 * i + 1] != i || p[3 * i + 2] != -0.01 * i) good = 0;
    }
    check(good, "each frame keeps its own punctures (0, 1, 2, 3, %d: clamped to the most)",
          ROD_MAX_PUNCTURES);
    rod_recording_halve(r);
    const double *p;
    int n0 = rod_recording_punctures(r, 0, &p), n1 = rod_recording_punctures(r, 1, &p);
    int ok1 = n1 == 2 && p[0] == 2 && p[4] == 1;
    int n2 = rod_recording_punctures(r, 2, &p);
    check(r->frame_count == 3 && n0 == 0 && ok1 && n2 == ROD_MAX_PUNCTURES && p[0] == 4,
          "halved: frames 0, 2, 4 keep their punctures (%d, %d, %d)", n0, n1, n2);
    check(rod_recording_punctures(r, 7, &p) == 0 && p == NULL, "a frame past the end has none");

    /* the bytes charged for `capacity` frames are what reserve() allocates:
     * counted here from the element sizes of each array */
    size_t nodes = (size_t)r->nodes, cap = (size_t)r->capacity;
    double allocated = (double)(cap * sizeof *r->time + cap * nodes * 3 * sizeof *r->position +
                                cap * nodes * 9 * sizeof *r->frame + cap * nodes * sizeof *r->twist +
                                cap * nodes * sizeof *r->tension +
                                cap * 3 * sizeof *r->tip_force + cap * 3 * sizeof *r->tip_moment +
                                cap * sizeof *r->puncture_count +
                                cap * ROD_MAX_PUNCTURES * 3 * sizeof *r->puncture);
    check_rel("rod_recording_bytes vs the arrays' sizes, bytes", rod_recording_bytes(r->nodes, cap),
              allocated, 1e-15);
    /* a recording made by hand without punctures has none */
    rod_recording bare = *r;
    bare.puncture_count = NULL;
    bare.puncture = NULL;
    check(rod_recording_punctures(&bare, 0, &p) == 0, "no puncture arrays: no punctures");
    rod_recording_destroy(r);
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* A pinned tip carrying a needle records the needle's frame, turned by its
 * path's rotation (R(t) R(t0)^T Q_tip(0)), so the needle is drawn along its
 * arc; the thread's own frame stays in the state. Here the path turns the
 * tip a quarter turn about z over 1 s, in place: d3 goes from +x to +y. */
static void test_needle_frame(void)
{
    rod_model m = rod_model_default();
    m.tip_end = ROD_END_PINNED;
    m.needle_radius = 0.01;
    double rows[14] = {0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, M_PI / 2};
    char err[256];
    m.tip_motion = rod_path_create(rows, 2, 7, err, sizeof err);
    if (!check(m.tip_motion && rod_model_derive(&m, err, sizeof err) == 0,
               "a pinned tip with a needle takes a path with rotation (%s)", err)) {
        rod_model_release(&m);
        return;
    }
    rod_state *s = rod_state_create(&m);
    rod_recording *r = rod_recording_create(&m, "needle", 4);
    if (!s || !r) {
        check(0, "out of memory");
    } else {
        rod_recording_append(r, &m, s);
        s->time = 1.0;
        rod_recording_append(r, &m, s);
        const int n = m.nodes;
        const double *q0 = &r->frame[(size_t)(n - 1) * 9], *q1 = &r->frame[((size_t)n + n - 1) * 9];
        /* row-major Q, columns d1 d2 d3: d3 = (q[2], q[5], q[8]) */
        check(fabs(q0[2] - 1.0) < 1e-12 && fabs(q0[5]) < 1e-12,
              "needle frame at t = 0: d3 = (%g, %g, %g), reference (1, 0, 0)", q0[2], q0[5], q0[8]);
        check(fabs(q1[2]) < 1e-9 && fabs(q1[5] - 1.0) < 1e-9 && fabs(q1[8]) < 1e-9,
              "needle frame after a quarter turn about z: d3 = (%g, %g, %g), reference (0, 1, 0)",
              q1[2], q1[5], q1[8]);
        const double *state_tip = &s->frame[(size_t)(n - 1) * 9];
        check(fabs(state_tip[2] - 1.0) < 1e-12, "the state's own tip frame is untouched "
              "(d3 x = %g)", state_tip[2]);
    }
    rod_recording_destroy(r);
    rod_state_destroy(s);
    rod_model_release(&m);
    /* without a needle a pinned tip's path has no rotation */
    rod_model plain = rod_model_default();
    plain.tip_end = ROD_END_PINNED;
    plain.tip_motion = rod_path_create(rows, 2, 7, err, sizeof err);
    check(plain.tip_motion && rod_model_derive(&plain, err, sizeof err) != 0 &&
              strstr(err, "tip_motion"), "without a needle it is refused: %s", err);
    rod_model_release(&plain);
}

/* The tension recorded for colour by tension is N . d3: a thread hanging
 * straight down from its clamped root carries the weight below each point,
 * rho A g (L - s) (statics, independent of the scheme), here solved by the
 * static scheme. */
static void test_tension(void)
{
    rod_model m = rod_model_default();
    m.options.scheme = ROD_SCHEME_STATIC;
    v3_set(m.direction, 0.0, 0.0, -1.0);
    char err[512];
    if (!check(rod_model_derive(&m, err, sizeof err) == 0, "hanging thread model (%s)", err)) return;
    v3_set(m.distributed_force, 0.0, 0.0, -9.81 * m.mass_per_length);
    rod_state *s = rod_state_create(&m);
    rod_solver solver;
    rod_report report;
    memset(&report, 0, sizeof report);
    rod_recording *r = rod_recording_create(&m, "hanging", 2);
    if (s && r && rod_solver_init(&solver, &m, err, sizeof err) == 0) {
        int ok = rod_solver_step(&solver, &m, s, 1.0, &report) == ROD_OK;
        rod_solver_release(&solver);
        if (check(ok && rod_recording_append(r, &m, s) == 0, "the static solve and the frame (%s)",
                  report.message)) {
            double worst = 0.0;
            for (int i = 1; i < m.nodes; i++) { /* node 0 is the support's force */
                double ref = m.mass_per_length * 9.81 * (m.length - i * m.ds);
                worst = fmax(worst, fabs(r->tension[i] - ref));
            }
            double top = m.mass_per_length * 9.81 * m.length;
            check(worst <= 1e-9 * top, "recorded tension vs rho A g (L - s) at every node: largest "
                  "error %.3g N against %.3g N at the root (relative %.2e)", worst, top,
                  worst / top);
        }
    } else {
        check(0, "create (%s)", err);
    }
    rod_recording_destroy(r);
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* What the picture needs of the model travels in the recording: what holds
 * each end, the needle, the distributed load and a copy of the surfaces
 * (the recording's own: it outlives the model's). */
static void test_scene(void)
{
    rod_model m = rod_model_default();
    char err[256] = "";
    rod_recording *r = NULL;
    if (!check(rod_model_derive(&m, err, sizeof err) == 0, "default model (%s)", err)) return;
    r = rod_recording_create(&m, "cantilever", 2);
    if (check(r != NULL, "recording of the default model")) {
        check(r->ends[0].kind == RECORDING_END_CLAMPED && r->ends[1].kind == RECORDING_END_FREE &&
                  !r->ends[0].driven && !r->ends[1].driven && !r->ends[0].sliding &&
                  !r->ends[1].sliding && r->needle_radius == 0 && r->surface_count == 0 &&
                  r->surfaces == NULL && v3_norm(r->distributed_force) == 0,
              "the default model: clamped root, free tip, no needle, load or surface");
        rod_recording_destroy(r);
    }
    rod_model_release(&m);

    m = rod_model_default();
    m.root_end = ROD_END_PINNED;
    m.tip_end = ROD_END_CLAMPED;
    v3_set(m.tip_slide, 1.0, 0.0, 0.0);
    m.slide_twist_held[1] = 1;
    m.needle_radius = 0.02;
    v3_set(m.distributed_force, 0.0, 0.0, -1e-3);
    m.surface_count = 2;
    m.surfaces = calloc(2, sizeof *m.surfaces);
    if (!check(m.surfaces != NULL, "surfaces made")) return;
    m.surfaces[0] = (rod_surface){.shape = ROD_SURFACE_PLANE, .center = {0, 0, -0.1},
                                  .normal = {0, 0, 1}, .friction = 0.3, .line = 7};
    m.surfaces[1] = (rod_surface){.shape = ROD_SURFACE_BOX, .center = {0.5, 0.1, -0.05},
                                  .size = {0.3, 0.2, 0.04}, .rounding = 0.005, .tissue = 1};
    r = rod_recording_create(&m, "sleeve", 2);
    rod_model_release(&m); /* frees the model's surfaces: the recording keeps its own */
    if (!check(r != NULL, "recording of the model with a sleeve, a needle and surfaces")) return;
    check(r->ends[0].kind == RECORDING_END_PINNED && r->ends[1].kind == RECORDING_END_CLAMPED &&
              r->ends[0].sliding == 0 && r->ends[1].sliding == 2 && !r->ends[1].driven,
          "pinned root; clamped tip on a slide, not turning (sliding %d)", r->ends[1].sliding);
    check(r->needle_radius == 0.02 && r->distributed_force[2] == -1e-3,
          "needle radius %g m, distributed force z %g N/m", r->needle_radius,
          r->distributed_force[2]);
    int same = r->surface_count == 2 && r->surfaces != NULL;
    if (same) {
        const recording_surface *a = &r->surfaces[0], *b = &r->surfaces[1];
        same = a->shape == RECORDING_SURFACE_PLANE && a->center[2] == -0.1 &&
               a->normal[2] == 1 && a->tissue == 0 && b->shape == RECORDING_SURFACE_BOX &&
               b->center[0] == 0.5 && b->size[1] == 0.2 && b->rounding == 0.005 && b->tissue == 1;
    }
    check(same, "the two surfaces copied: shape, centre, normal, size, rounding, tissue");
    rod_recording_destroy(r);
}

int main(void)
{
    test_scene();
    test_tension();
    test_needle_frame();
    test_punctures();
    return test_finish();
}
