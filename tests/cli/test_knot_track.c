/* test_knot_track.c: telling a knot that came undone over an end from a
 * strand that passed through another, and from a knot tied at an end.
 *
 * An open overhand knot (a 0.97-turn trefoil about 1 m long, d = 2 mm,
 * between tails drawn out 0.15 m, NS = 401) is the first frame; in the
 * second the rope's tail has been drawn back out of the loop (the same
 * curve from 0.6 of the turn laid straight radially out, away from every
 * other strand), so the knot is gone.
 * Whether that was a slip or a pass-through depends on how close the strands
 * came in between: with no strand ever closer than 0.996 d (a loop passing
 * over the end, as in a tightening knot whose tail slides out), it is a slip;
 * with two strands 0.1 d apart at some step, a pass-through.
 *
 * The same frames the other way round (the tail drawn back in through the
 * loop: the unknot, then the trefoil) tie a knot at that end: more
 * crossings (3, Rolfsen's table, from 0) where an end passed through a
 * loop. The nodes numbered from that end (the root) and strands touching
 * 3 segments from it the frame before, that is "tied at the root end": no
 * warning, said in the summary's change and the prose; with no touch and
 * no strands within reach, "tied at an end". The overhand undone with the
 * same touch "slipped off the root end" and is warned. A trefoil turning
 * into its mirror at the root end (3 crossings to 3) is no tie: warned as a
 * slip. The unknot to the trefoil with strands 0.1 d apart, none near an
 * end, is a pass-through: the run's error. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "cli/knot_track.h"
#include "cli/scene_outputs.h"
#include "test.h"
#include "sim/rod.h"
#include "sim/rod_grid.h"

#define NODES 401
#define TURN (0.97 * 2.0 * M_PI)

static void trefoil(double t, double x[3])
{
    v3_set(x, sin(t) + 2.0 * sin(2.0 * t), cos(t) - 2.0 * cos(2.0 * t), -sin(3.0 * t));
}

/* The open trefoil's polygon, scaled so that it is about 1 m long, between
 * two straight tails of TAIL nodes drawn out radially (0.15 m: the knot is
 * named alike under every closure of its ends, knot_track.h); with
 * `undone`, the part past parameter `cut` and the tip's tail run straight
 * out radially from there, so the tail no longer passes through the loop. */
#define TAIL 60
static void overhand(double *position, int undone)
{
    const double scale = 1.0 / 28.0, cut = 0.6 * TURN, tail = 0.15 / TAIL;
    const int knot = NODES - 2 * TAIL; /* the trefoil's nodes */
    for (int i = 0; i < knot; i++) {
        double t = TURN * i / (knot - 1), x[3];
        if (undone && t > cut) {
            double a[3], d[3];
            trefoil(cut, a);
            v3_scale(d, a, 1.0 / v3_norm(a)); /* radially out from there */
            double along = 0.0; /* the arc length the tail had past the cut */
            for (double u = cut; u < t; u += 1e-3) {
                double p[3], q[3], e[3];
                trefoil(u, p);
                trefoil(fmin(u + 1e-3, t), q);
                v3_sub(e, q, p);
                along += v3_norm(e);
            }
            v3_copy(x, a);
            v3_axpy(x, along, d);
        } else {
            trefoil(t, x);
        }
        v3_scale(&position[3 * (TAIL + i)], x, scale);
    }
    for (int e = 0; e < 2; e++) { /* the tails: radially out, or on along the last segment */
        const int from = e ? NODES - TAIL - 1 : TAIL, step = e ? 1 : -1;
        double d[3];
        if (e && undone) v3_sub(d, &position[3 * from], &position[3 * (from - 1)]);
        else v3_copy(d, &position[3 * from]);
        v3_scale(d, d, tail / v3_norm(d));
        for (int k = 1; k <= TAIL; k++) {
            v3_copy(&position[3 * (from + step * k)], &position[3 * from]);
            v3_axpy(&position[3 * (from + step * k)], k, d);
        }
    }
}

/* The nodes in reverse order: the tail drawn out is then the root's */
static void reverse_nodes(double *position)
{
    for (int i = 0, j = NODES - 1; i < j; i++, j--)
        for (int c = 0; c < 3; c++) {
            double x = position[3 * i + c];
            position[3 * i + c] = position[3 * j + c];
            position[3 * j + c] = x;
        }
}

/* Two frames, 0.1 s apart: the overhand (undone: drawn out) then again
 * (undone_after; mirror: z -> -z, the other hand); `touch`: strands press
 * on each other that many segments from the end drawn out in the first (0:
 * nowhere); `at_root`: the nodes reversed, that end the root */
static void frames_of(int undone, int undone_after, int mirror, int touch, int at_root,
                      double gap_between, knot_track *k, rod_model *m)
{
    rod_state *s = rod_state_create(m);
    memset(s->self_force, 0, (size_t)NODES * 3 * sizeof(double));
    if (touch > 0) s->self_force[3 * (at_root ? touch : NODES - 1 - touch) + 2] = 1.0;
    knot_track_init(k, NODES);
    overhand(s->position, undone);
    if (at_root) reverse_nodes(s->position);
    s->time = 0.0;
    knot_track_frame(k, m, s, INFINITY);
    memset(s->self_force, 0, (size_t)NODES * 3 * sizeof(double));
    overhand(s->position, undone_after);
    if (at_root) reverse_nodes(s->position);
    for (int i = 0; mirror && i < NODES; i++) s->position[3 * i + 2] *= -1.0;
    s->time = 0.1;
    knot_track_frame(k, m, s, gap_between);
    rod_state_destroy(s);
}

static void two_frames(double gap_between, knot_track *k, rod_model *m)
{
    frames_of(0, 1, 0, 0, 0, gap_between, k, m);
}

/* The run's warnings of k: their count, the first in `first`, 1 for an error */
static int warnings_of(const knot_track *k, const rod_model *m, char *first, size_t n)
{
    rod_report report;
    memset(&report, 0, sizeof report);
    run_warnings w = {0};
    char error[RUN_WARNING_LEN] = "";
    int failed = scene_outputs_result_warnings(m, &report, k, &w, error, sizeof error);
    snprintf(first, n, "%s", failed ? error : w.count ? w.text[0] : "");
    return failed ? -1 : w.count;
}

/* The prose knot line of k holds `text` */
static int prose_says(const knot_track *k, const rod_model *m, const char *text)
{
    char line[1024] = "";
    FILE *f = tmpfile();
    if (!f) return 0;
    knot_track_print(f, k, m);
    rewind(f);
    size_t got = fread(line, 1, sizeof line - 1, f);
    line[got] = '\0';
    fclose(f);
    return strstr(line, text) != NULL;
}

static void tied_at_an_end(rod_model *m)
{
    knot_track k;
    char said[RUN_WARNING_LEN];
    const char *how;

    frames_of(1, 0, 0, 3, 1, INFINITY, &k, m);
    how = knot_track_how_text(k.last_how, k.last_end);
    check(strcmp(k.first.name, "unknot") == 0 && strncmp(k.last.name, "trefoil", 7) == 0 &&
              k.first.crossing_number == 0 && k.last.crossing_number == 3,
          "the tail drawn through the loop: %s (%d crossings, reference 0) -> %s (%d, "
          "reference 3)", k.first.name, k.first.crossing_number, k.last.name,
          k.last.crossing_number);
    check(k.changes == 1 && k.ties == 1 && k.tie_end == 0 && how &&
              strcmp(how, "tied at the root end") == 0,
          "strands touching 3 segments from the root: %d change(s), %d tie(s), the summary "
          "says '%s' (reference 'tied at the root end')", k.changes, k.ties, how ? how : "");
    int n = warnings_of(&k, m, said, sizeof said);
    check(n == 0 && !strstr(said, "slipped"), "a knot tied: %d warnings (reference 0) %s", n,
          said);
    check(prose_says(&k, m, "first at t = 0.1 s (unknot -> trefoil, ") &&
              prose_says(&k, m, "-handed, tied at the root end)") &&
              !prose_says(&k, m, "CHANGED"),
          "the prose knot line says the knot was tied at the root end, no CHANGED");
    knot_track_release(&k);

    frames_of(1, 0, 0, 0, 0, INFINITY, &k, m);
    how = knot_track_how_text(k.last_how, k.last_end);
    n = warnings_of(&k, m, said, sizeof said);
    check(k.ties == 1 && n == 0 && how && strcmp(how, "tied at an end") == 0,
          "no strands near an end nor within reach between the frames: '%s' (reference 'tied "
          "at an end'), %d warnings", how ? how : "", n);
    knot_track_release(&k);

    frames_of(0, 1, 0, 3, 1, INFINITY, &k, m);
    how = knot_track_how_text(k.last_how, k.last_end);
    n = warnings_of(&k, m, said, sizeof said);
    check(k.changes == 1 && k.ties == 0 && n == 1 &&
              strstr(said, "slipped off the rod's root end") &&
              strstr(said, "lengthen the rod") && how &&
              strcmp(how, "slipped off the root end") == 0,
          "the reverse, trefoil -> unknot (3 crossings to 0) at the root: warned '%s'; the "
          "summary says '%s'", said, how ? how : "");
    knot_track_release(&k);

    frames_of(0, 0, 1, 3, 1, INFINITY, &k, m);
    n = warnings_of(&k, m, said, sizeof said);
    check(k.changes == 1 && k.ties == 0 && n == 1 && strstr(said, "slipped off"),
          "%s -> %s at the root (3 crossings to %d): no tie, warned '%s'", k.first.name,
          k.last.name, k.last.crossing_number, said);
    knot_track_release(&k);

    frames_of(1, 0, 0, 0, 0, 0.1 * m->diameter, &k, m);
    n = warnings_of(&k, m, said, sizeof said);
    check(k.ties == 0 && n == -1 && strstr(said, "passed through"),
          "unknot -> trefoil with strands 0.1 d apart, none near an end: no tie, the run's "
          "error '%s'", said);
    knot_track_release(&k);
}

/* A graded grid (rod.refine = 0 0.1 5 on 1 m, 400 segments: the stretched
 * length 0.1 x 5 + 0.9 = 1.4 m over 400, so ds = 0.7 mm for 0.1 m at the
 * root and 3.5 mm beyond): the tracker measures along the rod. Strands
 * touching 8 segments from the root (5.6 mm of rod, within 3 d = 6 mm of
 * the end) tie the knot at the root end (these frames move the tail by
 * decimetres, so the slide alone puts any touch near the root within
 * reach). The knot's rope between nodes 2 and 300
 * is 0.65 - 0.0014 m (the last 100 segments 3.5 mm: 1 - 0.35; the first
 * two 0.7 mm), 324.3 d (the uniform count would say 298 x 2.5 mm = 372.5
 * d). */
static void graded_grid(void)
{
    rod_model m = rod_model_default();
    m.nodes = NODES;
    m.diameter = 0.002;
    m.self_contact = 1;
    m.refine_count = 1;
    m.refine[0] = (rod_refine){0.0, 0.1, 5.0};
    char err[512] = "";
    if (!check(rod_model_derive(&m, err, sizeof err) == 0, "graded model derives %s", err))
        return;
    printf("     graded grid: ds %.6g m at the root, %.6g m at the tip\n",
           rod_segment_ds(&m, 0), rod_segment_ds(&m, NODES - 2));
    knot_track k;
    const char *how;
    frames_of(1, 0, 0, 8, 1, INFINITY, &k, &m);
    how = knot_track_how_text(k.last_how, k.last_end);
    check(k.ties == 1 && how && strcmp(how, "tied at the root end") == 0,
          "graded grid, strands touching 8 fine segments (5.6 mm) from the root: '%s' "
          "(reference 'tied at the root end')", how ? how : "");
    knot_track_release(&k);
    /* the rope: one frame of the overhand, strands pressed at nodes 2 and 300 */
    rod_state *s = rod_state_create(&m);
    memset(s->self_force, 0, (size_t)NODES * 3 * sizeof(double));
    s->self_force[3 * 2 + 2] = 1.0;
    s->self_force[3 * 300 + 2] = -1.0;
    overhand(s->position, 0);
    s->time = 0.0;
    knot_track_init(&k, NODES);
    knot_track_frame(&k, &m, s, INFINITY);
    check(strncmp(k.last.name, "trefoil", 7) == 0, "graded grid: the overhand named %s "
          "(reference trefoil)", k.last.name);
    check_rel("graded grid: the knot's rope (diameters) between nodes 2 and 300, by hand",
              knot_track_rope(&k, &m), (0.65 - 0.0014) / 0.002, 1e-9);
    knot_track_release(&k);
    rod_state_destroy(s);
    rod_model_release(&m);
}

int main(void)
{
    graded_grid();
    rod_model m = rod_model_default();
    m.nodes = NODES;
    m.diameter = 0.002;
    char err[256] = "";
    if (!check(rod_model_derive(&m, err, sizeof err) == 0, "model derives %s", err))
        return test_finish();

    knot_track k;
    two_frames(0.996 * m.diameter, &k, &m);
    check(k.frames == 2 && strncmp(k.first.name, "trefoil", 7) == 0 &&
              strcmp(k.last.name, "unknot") == 0 && k.changes == 1,
          "the overhand knot (%s) is undone in the second frame (%s), one change", k.first.name,
          k.last.name);
    check(k.slip_end < 0, "no strands touched near an end (slip_end %d)", k.slip_end);
    check(knot_track_change_is_slip(&k, &m),
          "strands never closer than %.3f d between the frames: the change is a loop passing "
          "over an end, not a pass-through", k.change_gap / m.diameter);
    knot_track_release(&k);

    two_frames(INFINITY, &k, &m);
    check(knot_track_change_is_slip(&k, &m), "strands never touching: a slip too");
    knot_track_release(&k);

    two_frames(0.1 * m.diameter, &k, &m);
    check(k.changes == 1 && !knot_track_change_is_slip(&k, &m),
          "two strands 0.1 d apart at a step between the frames (limit %.1f d): a pass-through",
          KNOT_PASS_GAP);
    knot_track_release(&k);

    tied_at_an_end(&m);

    rod_model_release(&m);
    return test_finish();
}
