/* knot_across.c: the knot of two threads tied together (knot_across.h).
 *
 * Which ends are joined. Two threads joined by a bend are pulled apart:
 * each thread leaves the knot with both of its ends on its own side, a's to
 * one side and b's to the other (in a reef or granny knot each thread is a
 * bight, a U whose two legs leave side by side). Let e be the line from the
 * middle of a's two ends to the middle of b's, and call the ends' offsets
 * across it their sides: a's two ends lie on opposite sides, and so do b's.
 * The closure joins a's end on one side to b's end on the same side, and a's
 * other end to b's other end, the two joins running far outside the knot
 * around opposite sides (the first join between 10 and 20 extents through the side's
 * direction, the second between 30 and 60 through the other side's: they never
 * meet). This is the cord of a reef knot tied round a bundle: that cord's
 * two standing parts leave the knot on one side (into the bundle) and its
 * two tails on the other; cutting the bundle's loop leaves two threads, each
 * a bight holding one standing part and one tail, which is a two-thread
 * reef knot; joining standing part to standing part and tail to tail, each
 * on its own side, gives back the closed cord: the square knot (trefoil #
 * its mirror, signature 0), and for the granny the granny (trefoil #
 * trefoil, signature +-4). Joining a's end to b's end on the other side
 * instead crosses the joins over each other: a half twist between the
 * threads' legs, which names another knot; joining a's two ends to each
 * other makes two loops, a link and no knot. Two threads that are not tied
 * together close to the unknot whichever way.
 *
 * What is not decided by the closure: a thread's two legs twisted about each
 * other between the knot and their ends (the sides read at the ends then
 * differ from those at the knot) name the knot with that twist in; a bend
 * pulled apart by its ends keeps its legs from twisting. */
#include "sim/geometry/knot_across.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define ACROSS_RADIUS 10.0                  /* x the extent: the first join's sphere */
#define ACROSS_JOIN_STEPS 36 /* points of a join at its radius, after its ray */

int rod_knot_across_points(int na, int nb) { return na + nb + 2 * (ACROSS_JOIN_STEPS + 1); }

static double dot3(const double *u, const double *v)
{
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
}

/* u normalised in place; 0 when it is shorter than tiny (left as is) */
static int normalise(double *u, double tiny)
{
    const double len = sqrt(dot3(u, u));
    if (!(len > tiny)) return 0;
    for (int k = 0; k < 3; k++) u[k] /= len;
    return 1;
}

/* u minus its part along the unit e */
static void across(const double *u, const double *e, double *out)
{
    const double along = dot3(u, e);
    for (int k = 0; k < 3; k++) out[k] = u[k] - along * e[k];
}

/* any unit vector perpendicular to the unit e */
static void perpendicular(const double *e, double *out)
{
    const double axis[3] = {fabs(e[0]) < 0.6 ? 1.0 : 0.0, fabs(e[0]) < 0.6 ? 0.0 : 1.0, 0.0};
    across(axis, e, out);
    normalise(out, 0.0);
}

/* The direction of an end p from c (its tangent, from the node next to it,
 * when it sits at c). */
static void end_direction(const double *p, const double *next, const double *c, double tiny,
                          double *out)
{
    for (int k = 0; k < 3; k++) out[k] = p[k] - c[k];
    if (normalise(out, tiny)) return;
    for (int k = 0; k < 3; k++) out[k] = p[k] - next[k];
    normalise(out, 0.0);
}

/* A join from end p to end q, bulging out through the side direction
 * `side`: the ray out from p to radius R0 about c, then the points along
 * (1 - f) from + f to + 2 sin(pi f) side for f in (0, 1] (the side's term
 * outweighs the chord's halfway, so the join passes round that side) at a
 * radius growing from R0 to 2 R0 (ends in nearly one direction would
 * otherwise have the join go out and back along one path); q follows in
 * the polygon. */
static int join(const double *p, const double *p_next, const double *q, const double *q_next,
                const double *c, double R0, const double *side, double tiny, double *out, int at)
{
    double from[3], to[3];
    end_direction(p, p_next, c, tiny, from);
    end_direction(q, q_next, c, tiny, to);
    for (int j = 0; j < 3; j++) out[3 * at + j] = c[j] + R0 * from[j];
    at++;
    for (int k = 1; k <= ACROSS_JOIN_STEPS; k++) {
        const double f = (double)k / ACROSS_JOIN_STEPS, bulge = 2.0 * sin(M_PI * f);
        double w[3];
        for (int j = 0; j < 3; j++) w[j] = (1.0 - f) * from[j] + f * to[j] + bulge * side[j];
        normalise(w, 0.0);
        for (int j = 0; j < 3; j++) out[3 * at + j] = c[j] + (1.0 + f) * R0 * w[j];
        at++;
    }
    return at;
}

int rod_knot_close_across(const double *a, int na, const double *b, int nb, double *work,
                          int *b_reversed, int *b_first)
{
    if (!a || !b || na < 2 || nb < 2) return -1;
    double c[3] = {0, 0, 0}, extent = 0.0;
    for (int i = 0; i < na + nb; i++) {
        const double *p = i < na ? &a[3 * i] : &b[3 * (i - na)];
        for (int k = 0; k < 3; k++) {
            if (!isfinite(p[k])) return -1;
            c[k] += p[k] / (na + nb);
        }
    }
    for (int i = 0; i < na + nb; i++) {
        const double *p = i < na ? &a[3 * i] : &b[3 * (i - na)];
        const double d[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
        extent = fmax(extent, sqrt(dot3(d, d)));
    }
    if (!(extent > 0.0)) return -1;
    const double tiny = 1e-9 * extent;
    const double *a0 = a, *a1 = &a[3 * (na - 1)], *b0 = b, *b1 = &b[3 * (nb - 1)];
    /* e: from the middle of a's ends to the middle of b's (else from a's
     * centroid to b's, else any) */
    double e[3];
    for (int k = 0; k < 3; k++) e[k] = 0.5 * (b0[k] + b1[k]) - 0.5 * (a0[k] + a1[k]);
    if (!normalise(e, tiny)) {
        double ca[3] = {0, 0, 0}, cb[3] = {0, 0, 0};
        for (int i = 0; i < na; i++)
            for (int k = 0; k < 3; k++) ca[k] += a[3 * i + k] / na;
        for (int i = 0; i < nb; i++)
            for (int k = 0; k < 3; k++) cb[k] += b[3 * i + k] / nb;
        for (int k = 0; k < 3; k++) e[k] = cb[k] - ca[k];
        if (!normalise(e, tiny)) e[0] = 1.0, e[1] = e[2] = 0.0;
    }
    /* the sides: each thread's last end's offset across e from its first */
    double ua[3], ub[3], d[3];
    for (int k = 0; k < 3; k++) d[k] = a1[k] - a0[k];
    across(d, e, ua);
    for (int k = 0; k < 3; k++) d[k] = b1[k] - b0[k];
    across(d, e, ub);
    const int has_a = normalise(ua, tiny), has_b = normalise(ub, tiny);
    const int reversed = dot3(ua, ub) >= 0.0; /* a's last end with b's last */
    /* the first join's side: where a's last end and its partner lie */
    double side[3];
    for (int k = 0; k < 3; k++)
        side[k] = (has_a ? ua[k] : 0.0) + (has_b ? (reversed ? ub[k] : -ub[k]) : 0.0);
    if (!normalise(side, 1e-9)) {
        across((double[3]){a1[0] - c[0], a1[1] - c[1], a1[2] - c[2]}, e, side);
        if (!normalise(side, tiny)) perpendicular(e, side);
    }
    const double other[3] = {-side[0], -side[1], -side[2]};
    const double R = ACROSS_RADIUS * extent;
    int at = na;
    memcpy(work, a, (size_t)na * 3 * sizeof *work);
    const double *bf = reversed ? b1 : b0, *bf_next = reversed ? &b[3 * (nb - 2)] : &b[3];
    const double *bl = reversed ? b0 : b1, *bl_next = reversed ? &b[3] : &b[3 * (nb - 2)];
    at = join(a1, &a[3 * (na - 2)], bf, bf_next, c, R, side, tiny, work, at);
    if (b_first) *b_first = at;
    for (int i = 0; i < nb; i++) {
        const double *p = &b[3 * (reversed ? nb - 1 - i : i)];
        memcpy(&work[3 * at], p, 3 * sizeof *work);
        at++;
    }
    at = join(bl, bl_next, a0, &a[3], c, 3.0 * R, other, tiny, work, at);
    if (b_reversed) *b_reversed = reversed;
    return at;
}

int rod_knot_identify_across(rod_knot_scratch *scratch, const double *a, int na,
                             const double *b, int nb, double *work, rod_knot *out, char *err,
                             size_t errlen)
{
    int b_first = 0;
    const int count = rod_knot_close_across(a, na, b, nb, work, NULL, &b_first);
    if (count < 0) {
        memset(out, 0, sizeof *out);
        snprintf(err, errlen, "two threads of at least 2 finite points each are needed "
                 "(%d and %d points)", na, nb);
        return -1;
    }
    /* a's segments and b's are short, the joins long */
    const int short_ranges[4] = {0, na - 1, b_first, b_first + nb - 1};
    return rod_knot_identify_joined(scratch, work, count, short_ranges, out, err, errlen);
}
