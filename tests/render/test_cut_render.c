/* test_cut_render.c: what the picture shows of a thread after a cut
 * (sim/cut.h). A frame of a cut thread keeps the recording's node count,
 * the nodes cut away put on the cut end as copies of it
 * (rod_recording_append). Against hand-made recordings and closed forms:
 *  - rod_recording_kept finds the thread left: all 11 nodes uncut; nodes
 *    0-7 when 8-10 are piled on the tip's cut end; nodes 3-10 when 0-2 are
 *    piled on the root's;
 *  - the knot line of a frame whose tail was cut names the knot of the
 *    thread left: the (2,3) torus knot opened (a left-handed trefoil), 40
 *    nodes piled on either end, reads "knot: trefoil (3_1), left-handed"
 *    (with the pile in the polygon the closure has no last segment to draw
 *    the end out along: "not identified"), and `render.knot = auto` shows
 *    the line;
 *  - the needle, its piece cut away while forceps' jaws hold it, is drawn
 *    in the jaws where it was at the last frame before the cut: its arc
 *    (p(theta) = r + R sin(theta) d3 + R (1 - cos(theta)) d1 at the tip of
 *    that frame) moved as the forceps moved since (2 cm along z, a quarter
 *    turn about z), every point within 1e-12 m; every vertex drawn within
 *    the wire's radius of that arc, none at the thread's cut end; with no
 *    jaws within reach it is not drawn at all (it fell with its piece);
 *  - a driven clamped root cut away draws no block at the cut end. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "render/glyphs.h"
#include "render/mesh.h"
#include "render/options.h"
#include "render/overlay.h"
#include "synthetic_recording.h"
#include "test.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* Nodes [from, to) of frame f made copies of node `end` (what
 * rod_recording_append does with the nodes cut away). */
static void pile(rod_recording *r, int f, int from, int to, int end)
{
    for (int i = from; i < to; i++) {
        size_t at = (size_t)f * (size_t)r->nodes + (size_t)i;
        size_t e = (size_t)f * (size_t)r->nodes + (size_t)end;
        memcpy(&r->position[3 * at], &r->position[3 * e], 3 * sizeof(double));
        memcpy(&r->frame[9 * at], &r->frame[9 * e], 9 * sizeof(double));
    }
}

static void test_kept(void)
{
    rod_recording *r = synthetic_recording_create(11, 3, 0.1, 0.001);
    for (int f = 0; f < 3; f++) synthetic_arc(r, f, 0.05, 0);
    pile(r, 1, 8, 11, 7);
    pile(r, 2, 0, 3, 3);
    const int want[3][2] = {{0, 11}, {0, 8}, {3, 8}};
    for (int f = 0; f < 3; f++) {
        int first, kept = rod_recording_kept(r, f, 0, r->nodes, &first);
        check(first == want[f][0] && kept == want[f][1],
              "frame %d: the thread left is nodes %d-%d (expected %d-%d)", f, first,
              first + kept - 1, want[f][0], want[f][0] + want[f][1] - 1);
    }
    rod_recording_destroy(r);
}

/* The (2, 3) torus knot opened at (3, 0, 0) (test_crossings.c: the
 * left-handed trefoil), N nodes, then `extra` nodes piled on one end. */
static void test_knot_after_cut(void)
{
    enum { N = 300, EXTRA = 40 };
    for (int end = 0; end < 2; end++) {
        rod_recording *r = synthetic_recording_create(N + EXTRA, 1, 1.0, 0.01);
        const int lo = end ? 0 : EXTRA;
        for (int i = 1; i <= N; i++) {
            double f = 2 * M_PI * i / (N + 1), rr = 2 + cos(3 * f);
            v3_set(&r->position[3 * (lo + i - 1)], rr * cos(2 * f), rr * sin(2 * f), sin(3 * f));
        }
        if (end) pile(r, 0, N, N + EXTRA, N - 1);
        else pile(r, 0, 0, EXTRA, EXTRA);
        render_overlay ov;
        memset(&ov, 0, sizeof ov);
        ov.knot_shown = 1;
        overlay_knot(&ov, r, 0);
        const char *want = "knot: trefoil (3_1), left-handed";
        check(strcmp(ov.knot_text, want) == 0, "the %s's tail cut (%d nodes piled on it): \"%s\" "
              "(expected \"%s\")", end ? "tip" : "root", EXTRA, ov.knot_text, want);
        render_options o;
        render_options_default(&o);
        o.knot = RENDER_KNOT_AUTO;
        check(render_knot_shown(r, &o) == 1, "render.knot = auto shows the knot line of the cut "
              "thread");
        rod_recording_destroy(r);
    }
}

/* p + R (x - p0) for the rotation R = Rz(turn). */
static void carried(const double x[3], const double p0[3], const double p[3], double turn,
                    double out[3])
{
    double d[3];
    v3_sub(d, x, p0);
    v3_set(out, p[0] + cos(turn) * d[0] - sin(turn) * d[1],
           p[1] + sin(turn) * d[0] + cos(turn) * d[1], p[2] + d[2]);
}

static void test_needle_after_cut(void)
{
    /* a straight 0.1 m thread along +x (d1 = +y, d3 = +x), a 1/2-circle
     * needle of radius 1 cm at its tip; frame 1: nodes 16-20 cut away */
    const double length = 0.1, big = 0.01, turn = 0.5 * M_PI, radius = 0.0005;
    rod_recording *r = synthetic_recording_create(21, 2, length, 0.0003);
    for (int f = 0; f < 2; f++) synthetic_arc(r, f, INFINITY, 0);
    pile(r, 1, 16, 21, 15);
    r->needle_radius = big;
    r->ends[0].kind = RECORDING_END_FREE; /* only the needle drawn */
    r->ends[1].kind = RECORDING_END_CLAMPED;
    r->ends[1].driven = 1;
    /* forceps whose jaws' tip is on the needle's middle (theta = pi/2) in
     * frame 0, their jaws along x behind it; 2 cm up and a quarter turn
     * about z in frame 1 */
    r->instrument_count = 1;
    r->instruments[0] = (recording_instrument){.kind = RECORDING_FORCEPS, .size = 0.12,
                                               .hinge = 0.03, .jaw_length = 0.012,
                                               .jaw_radius = 0.0008, .shank_radius = 0.001};
    r->instrument_pose = calloc(2 * RECORDING_INSTRUMENT_NUMBERS, sizeof(double));
    double *pose0 = r->instrument_pose, *pose1 = pose0 + RECORDING_INSTRUMENT_NUMBERS;
    const double tip[3] = {length, 0, 0}, grip[3] = {length + big, big, 0};
    const double moved[3] = {length + big, big, 0.02};
    v3_copy(pose0, grip);
    m3_identity(pose0 + 3);
    v3_copy(pose1, moved);
    const double rz[9] = {cos(turn), -sin(turn), 0, sin(turn), cos(turn), 0, 0, 0, 1};
    memcpy(pose1 + 3, rz, sizeof rz);

    render_options o;
    render_options_default(&o);
    o.needle_arc = 0.5;
    double points[3 * GLYPH_MAX_POINTS], pad;
    int chain;
    int count = glyph_points(r, &o, radius, 1, 1, points, &pad, &chain);
    double worst = count == NEEDLE_SEGMENTS + 1 ? 0 : INFINITY;
    for (int k = 0; k < count && k <= NEEDLE_SEGMENTS; k++) {
        double theta = 2 * M_PI * o.needle_arc * k / NEEDLE_SEGMENTS, at[3], want[3], off[3];
        v3_set(at, tip[0] + big * sin(theta), tip[1] + big * (1 - cos(theta)), tip[2]);
        carried(at, grip, moved, turn, want);
        v3_sub(off, &points[3 * k], want);
        worst = fmax(worst, v3_norm(off));
    }
    printf("needle after the cut: %d arc points, worst %.3e m from the arc carried by the jaws\n",
           count, worst);
    check(count == NEEDLE_SEGMENTS + 1 && worst < 1e-12,
          "the needle cut away is in the forceps' jaws, carried as they moved (%d points, off by "
          "%.2e m)", count, worst);

    /* what is drawn: within the wire of that arc; nothing at the cut end */
    render_mesh m = {0};
    m.max_vertices = 2 * GLYPH_VERTICES;
    m.max_indices = 2 * GLYPH_INDICES;
    m.vertices = malloc((size_t)m.max_vertices * sizeof *m.vertices);
    m.indices = malloc((size_t)m.max_indices * sizeof *m.indices);
    glyph_add_ends(&m, r, &o, 1, radius);
    const double *cut_end = &r->position[3 * (21 + 15)];
    double far = 0, nearest_cut = INFINITY, wire = glyph_needle_wire(r, radius);
    for (int i = 0; i < m.vertex_count; i++) {
        double p[3], best = INFINITY, off[3];
        for (int c = 0; c < 3; c++) p[c] = m.vertices[i].position[c];
        for (int k = 0; k <= NEEDLE_SEGMENTS; k++) {
            v3_sub(off, p, &points[3 * k]);
            best = fmin(best, v3_norm(off));
        }
        far = fmax(far, best);
        v3_sub(off, p, cut_end);
        nearest_cut = fmin(nearest_cut, v3_norm(off));
    }
    check(m.vertex_count > 0 && far <= wire + 1e-7, /* vertices in float: 1e-8 m at 0.1 m */
          "%d vertices drawn, each within %.3e m of the carried arc (the wire %.3e m)",
          m.vertex_count, far, wire);
    check(nearest_cut > 0.5 * big, "none at the thread's cut end (the nearest %.3e m away)",
          nearest_cut);
    free(m.vertices);
    free(m.indices);

    /* the jaws 5 cm away: the needle fell with its piece */
    v3_set(pose0, length, 0.05, 0.05);
    count = glyph_points(r, &o, radius, 1, 1, points, &pad, &chain);
    check(count == 0, "no jaws within reach of the needle at the cut: not drawn (%d points)",
          count);
    /* before the cut: at the tip, as ever */
    count = glyph_points(r, &o, radius, 0, 1, points, &pad, &chain);
    double back[3];
    v3_sub(back, points, tip);
    check(count == NEEDLE_SEGMENTS + 1 && v3_norm(back) < 1e-15,
          "before the cut the needle's back is the thread's tip (%d points)", count);
    rod_recording_destroy(r);
}

static void test_root_block_after_cut(void)
{
    rod_recording *r = synthetic_recording_create(11, 2, 0.1, 0.001);
    for (int f = 0; f < 2; f++) synthetic_arc(r, f, INFINITY, 0);
    pile(r, 1, 0, 3, 3);
    r->ends[0].kind = RECORDING_END_CLAMPED;
    r->ends[0].driven = 1;
    render_options o;
    render_options_default(&o);
    double points[3 * GLYPH_MAX_POINTS], pad;
    int chain;
    const int before = glyph_points(r, &o, 0.001, 0, 0, points, &pad, &chain);
    const int after = glyph_points(r, &o, 0.001, 1, 0, points, &pad, &chain);
    check(before == 8 && after == 0, "a driven clamped root: its block drawn (%d corners), "
          "then cut away with its piece (%d)", before, after);
    rod_recording_destroy(r);
}

int main(void)
{
    test_kept();
    test_knot_after_cut();
    test_needle_after_cut();
    test_root_block_after_cut();
    return test_finish();
}
