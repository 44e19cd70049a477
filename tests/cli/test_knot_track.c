/* test_knot_track.c: telling a knot that came undone over an end from a
 * strand that passed through another.
 *
 * An open overhand knot (a 0.97-turn trefoil about 1 m long, d = 2 mm,
 * between tails drawn out 0.15 m, NS = 401) is the first frame; in the
 * second the rope's tail has been drawn back out of the loop (the same
 * curve from 0.6 of the turn laid straight radially out, away from every
 * other strand), so the knot is gone.
 * Whether that was a slip or a pass-through depends on how close the strands
 * came in between: with no strand ever closer than 0.996 d (a loop passing
 * over the end, as in a tightening knot whose tail slides out), it is a slip;
 * with two strands 0.1 d apart at some step, a pass-through. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "cli/knot_track.h"
#include "test.h"
#include "sim/rod.h"

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

static void two_frames(double gap_between, knot_track *k, rod_model *m)
{
    rod_state *s = rod_state_create(m);
    memset(s->self_force, 0, (size_t)NODES * 3 * sizeof(double));
    knot_track_init(k, NODES);
    overhand(s->position, 0);
    s->time = 0.0;
    knot_track_frame(k, m, s, INFINITY);
    overhand(s->position, 1);
    s->time = 0.1;
    knot_track_frame(k, m, s, gap_between);
    rod_state_destroy(s);
}

int main(void)
{
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

    rod_model_release(&m);
    return test_finish();
}
