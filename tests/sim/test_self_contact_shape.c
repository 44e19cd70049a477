/* test_self_contact_shape.c: the searches self-contact makes while nothing
 * touches skip the pairs the rod's own shape shows apart (a gently bent
 * stretch near itself in arc length: raised_skip in self_contact.c), and
 * must answer as a search of every pair would. On a grid finer than the
 * diameter (ds = d / 4) and on shapes that raise the skip and shapes that
 * defeat it (arcs of 50 d down to 2 d, a helix whose turns lie 1.2 d
 * apart, hairpins closing from 10 d to 0.4 d, wavy strands with rough
 * nodes), each search is checked against this file's brute force over
 * every pair, with its own segment distance (test_segment.h):
 * rod_self_contact_nothing_near (no pair within d + near, none beyond a
 * straight arc's span within d + margin), rod_self_contact_near_motion (the
 * largest motion of a node of a pair within d + 2 moved) and
 * rod_self_contact_reachable (the pairs within d + margin whose distance
 * less their nodes' largest relative displacement falls below d), for
 * swinging, shearing, random motions and a wave of compression along the
 * rod. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/contact/self_contact.h"
#include "test.h"
#include "test_segment.h"

#define NODES 241

static const double d = 0.001, ds = 0.00025; /* m */

/* A uniform deviate in [0, 1) (a fixed sequence: the checks repeat) */
static double uniform(unsigned *state)
{
    *state = *state * 1664525u + 1013904223u;
    return (double)(*state >> 8) / 16777216.0;
}

/* The shapes, NODES nodes ds apart along the curve (chords of it):
 * 0..3 arcs of radius 50, 12, 4, 2 d (the last ones wrap round into a
 * helix of pitch 1.2 d), 4..8 hairpins of gap 10, 3, 1.6, 0.9, 0.4 d, 9..11
 * wavy strands, the last with nodes displaced by up to ds / 20 at random */
enum { SHAPES = 12 };

static void shape(int which, double *pos, unsigned *state)
{
    const double radius[4] = {50 * d, 12 * d, 4 * d, 2 * d};
    const double gap[5] = {10 * d, 3 * d, 1.6 * d, 0.9 * d, 0.4 * d};
    for (int k = 0; k < NODES; k++) {
        const double s = k * ds;
        double *p = &pos[3 * k];
        if (which < 4) {
            const double r = radius[which], a = s / r;
            v3_set(p, r * sin(a), r * (1 - cos(a)), 1.2 * d * a / (2 * M_PI));
        } else if (which < 9) {
            const double r = 0.5 * gap[which - 4], leg = 0.5 * (NODES - 1) * ds - 0.5 * M_PI * r;
            if (s <= leg) {
                v3_set(p, s, 0, 0);
            } else if (s <= leg + M_PI * r) {
                const double a = (s - leg) / r;
                v3_set(p, leg + r * sin(a), r * (1 - cos(a)), 0);
            } else {
                v3_set(p, leg - (s - leg - M_PI * r), 2 * r, 0);
            }
        } else {
            const double amplitude = (which - 8) * 2 * d, wave = 40 * d;
            v3_set(p, s, amplitude * sin(2 * M_PI * s / wave), 0.5 * amplitude * cos(2 * M_PI * s / (1.7 * wave)));
            if (which == 11)
                for (int c = 0; c < 3; c++) p[c] += 0.05 * ds * (uniform(state) - 0.5);
        }
    }
}

/* The distance of segments i, j, by this file's own minimisation, or
 * beyond `within` when their midpoints show them farther apart than that */
static double apart(const double *pos, int i, int j, double within)
{
    double mi[3], mj[3], li[3], lj[3], m[3];
    for (int c = 0; c < 3; c++) {
        mi[c] = 0.5 * (pos[3 * i + c] + pos[3 * (i + 1) + c]);
        mj[c] = 0.5 * (pos[3 * j + c] + pos[3 * (j + 1) + c]);
        li[c] = pos[3 * (i + 1) + c] - pos[3 * i + c];
        lj[c] = pos[3 * (j + 1) + c] - pos[3 * j + c];
    }
    v3_sub(m, mi, mj);
    if (v3_norm(m) > within + 0.5 * (v3_norm(li) + v3_norm(lj)) + 1e-9) return INFINITY;
    return segment_distance(&pos[3 * i], &pos[3 * (i + 1)], &pos[3 * j], &pos[3 * (j + 1)]);
}

/* Whether a pair j - i > gap lies closer than within (brute force) */
static int any_within(const double *pos, int gap, double within)
{
    for (int i = 0; i + 1 < NODES; i++)
        for (int j = i + gap + 1; j + 1 < NODES; j++)
            if (apart(pos, i, j, within) < within) return 1;
    return 0;
}

/* rod_self_contact_near_motion by brute force */
static double near_motion(const double *pos, const double *vbar, double dt, double moved, int skip)
{
    double near = 0.0;
    for (int i = 0; i + 1 < NODES; i++)
        for (int j = i + skip + 1; j + 1 < NODES; j++) {
            if (!(apart(pos, i, j, d + 2 * moved) < d + 2 * moved)) continue;
            const int node[4] = {i, i + 1, j, j + 1};
            for (int e = 0; e < 4; e++) near = fmax(near, dt * v3_norm(&vbar[3 * node[e]]));
        }
    return near;
}

/* rod_self_contact_reachable by brute force */
static int reachable(const double *pos, const double *vbar, double dt, double margin, int skip)
{
    int count = 0;
    for (int i = 0; i + 1 < NODES; i++)
        for (int j = i + skip + 1; j + 1 < NODES; j++) {
            const double distance = apart(pos, i, j, d + margin);
            if (!(distance < d + margin)) continue;
            double rel = 0.0;
            const int e[2] = {i, i + 1}, f[2] = {j, j + 1};
            for (int x = 0; x < 2; x++)
                for (int y = 0; y < 2; y++) {
                    double r[3];
                    v3_sub(r, &vbar[3 * e[x]], &vbar[3 * f[y]]);
                    rel = fmax(rel, dt * v3_norm(r));
                }
            count += distance - rel < d;
        }
    return count;
}

/* Velocities (m/s) of motion `kind` at speed scale v: 0 the whole rod
 * swinging about the z axis through its first node, 1 swinging and
 * shearing (the second half moving across the first), 2 random per node,
 * 3 a wave of compression along the rod (8 d long: arc neighbours close
 * on one another by up to some 1.3 v dt) */
static void motion(int kind, double v, const double *pos, double *vbar, unsigned *state)
{
    for (int k = 0; k < NODES; k++) {
        const double *p = &pos[3 * k];
        double *u = &vbar[3 * k];
        v3_set(u, -v * p[1] / (NODES * ds), v * p[0] / (NODES * ds), 0);
        if (kind == 1 && k > NODES / 2) u[2] += 0.3 * v * (k - NODES / 2) / (double)NODES;
        if (kind == 2)
            for (int c = 0; c < 3; c++) u[c] = v * (uniform(state) - 0.5);
        if (kind == 3) {
            double t[3];
            v3_sub(t, &pos[3 * (k < NODES - 1 ? k + 1 : k)], &pos[3 * (k > 0 ? k - 1 : k)]);
            v3_scale(u, t, v * sin(2 * M_PI * k * ds / (8 * d)) / v3_norm(t));
        }
    }
}

static void test_same_answers(void)
{
    static double pos[3 * NODES], vbar[3 * NODES];
    rod_self_contact *sc = rod_self_contact_create(NODES, 6 * (NODES - 1), 1, 6, d, ds, 0.0);
    if (!check(sc != NULL, "shape skip: self-contact scratch")) return;
    unsigned state = 12345u;
    const double margins[3] = {0.6 * d, 1.2 * d, 2 * d};
    const double dt = 1e-3;
    int near_calls = 0, near_agree = 0, motion_calls = 0, motion_agree = 0;
    int reach_calls = 0, reach_agree = 0, nothing = 0, something = 0, reached = 0, first_bad = -1;
    for (int which = 0; which < SHAPES; which++) {
        shape(which, pos, &state);
        for (int k = 0; k < 3; k++) {
            const double margin = margins[k], near = 0.5 * d;
            const int straight = 1 + (int)ceil((d + margin) / sc->ds);
            const int expect = !any_within(pos, sc->skip, d + near) &&
                               (straight <= sc->skip || !any_within(pos, straight, d + margin));
            const int got = rod_self_contact_nothing_near(sc, pos, near, margin);
            near_calls++;
            if (got == expect) near_agree++;
            else if (first_bad < 0) first_bad = 100 * which + k;
            nothing += expect, something += !expect;
        }
        for (int kind = 0; kind < 4; kind++)
            for (int k = 0; k < 3; k++) {
                /* the fastest node's motion over the step: 0.1 to 1.5 d
                 * (the wave's: 0.3 to 0.7 d, arc neighbours 1.75 d apart) */
                const double moved_scale = (kind == 3 ? 0.3 + 0.2 * k : 0.1 + 0.7 * k) * d;
                motion(kind, moved_scale / dt, pos, vbar, &state);
                double moved = 0.0;
                for (int i = 0; i < NODES; i++) moved = fmax(moved, dt * v3_norm(&vbar[3 * i]));
                const double expect = near_motion(pos, vbar, dt, moved, sc->skip);
                const double got = rod_self_contact_near_motion(sc, pos, vbar, dt, moved);
                motion_calls++;
                if (got == expect) motion_agree++;
                else if (first_bad < 0) first_bad = 10000 + 100 * which + 10 * kind + k;
                const int count = reachable(pos, vbar, dt, 2 * moved, sc->skip);
                reach_calls++;
                reached += count > 0;
                if (rod_self_contact_reachable(sc, pos, vbar, dt, 2 * moved) == count) reach_agree++;
                else if (first_bad < 0) first_bad = 20000 + 100 * which + 10 * kind + k;
            }
    }
    check(near_agree == near_calls, "shape skip: nothing_near as every pair's distances say at "
          "%d of %d calls (%d with nothing near, %d with something; first disagreement %d)",
          near_agree, near_calls, nothing, something, first_bad);
    check(motion_agree == motion_calls, "shape skip: near_motion equal to the brute force's at %d "
          "of %d calls", motion_agree, motion_calls);
    check(reach_agree == reach_calls, "shape skip: reachable counts equal to the brute force's at "
          "%d of %d calls (%d with a pair that can reach)", reach_agree, reach_calls, reached);
    check(nothing > 0 && something > 0 && reached > 0 && reached < reach_calls,
          "shape skip: both answers met (nothing near %d, something %d, reachable %d of %d)",
          nothing, something, reached, reach_calls);
    check(sc->shape_skipped > 0, "shape skip: searches whose skip the shape raised: %ld (> 0)",
          sc->shape_skipped);
    rod_self_contact_destroy(sc);
}

int main(void)
{
    test_same_answers();
    return test_finish();
}
