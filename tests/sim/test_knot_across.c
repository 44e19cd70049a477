/* test_knot_across.c: two threads tied together by a reef (square) knot or
 * a granny knot, named across the two (sim/geometry/knot_across.h).
 *
 * The shapes: two threads a and b tied as a bend, each a bight whose two
 * legs leave the knot on its own side (a's to -y, b's to +y), built as the
 * two throws of a knot tied over a bite (scenes/surgeons_knot_path.py's
 * construction, here with single throws): two double helices about lines
 * along y, of 1.5 turns each (3 half-twists), the lower at z = Z1 and the
 * upper at z = Z2, joined by two U-turns at y = +-OUT. Thread a: its tail
 * leaves the upper throw at the top to -y, it runs the upper throw to +y,
 * turns down at +y, runs the lower throw back to -y and leaves at its
 * bottom to -y (its standing part); b is a turned through y -> -y, half a
 * turn on. The upper throw's helix turned the other way along its strands
 * (HAND2 = HAND1 as the script reads) is the reef knot, the same way the
 * granny.
 *
 * References, independent of the closure: the same two threads joined into
 * one cord under the knot (the standing parts joined by a bite, the tails
 * left free: a reef knot tied round a bundle) and named by the single
 * thread's closure (tested in test_knot_surgical); and the table values
 * (Rolfsen; Livingston, Knot Theory, 1993): the square knot 3_1 # 3_1*,
 * Delta = (1 - t + t^2)^2, determinant 9, signature 0 and its own mirror
 * image; the granny 3_1 # 3_1, the same Delta and determinant, signature
 * +-4, its mirror image of the other sign. Each shape is named as built,
 * under 30 random rotations (other viewing directions) and mirrored; with
 * a and b swapped and each reversed too (the closure must not depend on the
 * rods' order or direction). Then two straight threads far apart, one laid
 * across another, and two bights merely hooked through each other: the
 * unknot. Last, the starting shapes of reef_knot.ini and granny_knot.ini. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sim/geometry/knot.h"
#include "sim/geometry/knot_across.h"
#include "test.h"

#define MAX_POINTS 2000
#define ROTATIONS 30

typedef struct polygon {
    int n;
    double p[3 * MAX_POINTS];
} polygon;

/* lengths in thread diameters */
#define R 4.0      /* throw radius */
#define P 8.0      /* throw pitch */
#define Z1 7.0     /* lower throw's axis */
#define Z2 23.0    /* upper throw's axis */
#define TAIL 16.0  /* the legs beyond the U-turns */
#define A (1.5 * P / 2.0) /* a throw's half length along y */
#define OUT (A + 0.5 * R) /* the U-turns' y */

static void add(polygon *g, double x, double y, double z)
{
    g->p[3 * g->n] = x;
    g->p[3 * g->n + 1] = y;
    g->p[3 * g->n + 2] = z;
    g->n++;
}

/* a strand along a throw at height z from y0 to y1: angle phi(y) + shift */
static void sweep(polygon *g, double z, int upper, double hand, double shift, double y0, double y1)
{
    const int n = 120;
    for (int k = 0; k <= n; k++) {
        const double y = y0 + (y1 - y0) * k / n;
        const double phi = upper ? -M_PI / 2 + hand * 2 * M_PI * 1.5 * (A - y) / (2 * A)
                                 : -M_PI / 2 + 2 * M_PI * 1.5 * (y + A) / (2 * A);
        add(g, R * cos(phi + shift), y, z + R * sin(phi + shift));
    }
}

static void u_turn(polygon *g, double y, double side, int downward)
{
    const double zm = 0.5 * (Z1 + Z2), ru = 0.5 * (Z2 - Z1 - 2 * R);
    for (int k = 1; k < 40; k++) {
        double t = M_PI * k / 40;
        t = downward ? t : M_PI - t;
        add(g, 0.0, y + side * ru * sin(t), zm + ru * cos(t));
    }
}

/* Thread a from its tail (at -y, top) to its standing end (at -y, bottom);
 * thread b from its standing end (+y, bottom) to its tail (+y, top). hand2:
 * +1 the reef knot, -1 the granny. */
static void build(polygon *a, polygon *b, double hand2)
{
    a->n = b->n = 0;
    add(a, 0.0, -(OUT + TAIL), Z2 + R);
    add(a, 0.0, -A - 0.5 * R, Z2 + R);
    sweep(a, Z2, 1, hand2, 0.0, -A, A);
    add(a, 0.0, OUT, Z2 - R);
    u_turn(a, OUT, 1.0, 1);
    add(a, 0.0, OUT, Z1 + R);
    sweep(a, Z1, 0, 1.0, 0.0, A, -A);
    add(a, 0.0, -A - 0.5 * R, Z1 - R);
    add(a, 0.0, -(OUT + TAIL), Z1 - R);

    add(b, 0.0, OUT + TAIL, Z1 - R);
    add(b, 0.0, A + 0.5 * R, Z1 - R);
    sweep(b, Z1, 0, 1.0, M_PI, A, -A);
    add(b, 0.0, -OUT, Z1 + R);
    u_turn(b, -OUT, -1.0, 0);
    add(b, 0.0, -OUT, Z2 - R);
    sweep(b, Z2, 1, hand2, M_PI, -A, A);
    add(b, 0.0, A + 0.5 * R, Z2 + R);
    add(b, 0.0, OUT + TAIL, Z2 + R);
}

/* The reference: one cord, a then a bite under the knot joining a's
 * standing end to b's, then b (a reef knot tied round a bundle) */
static void one_cord(const polygon *a, const polygon *b, polygon *cord)
{
    cord->n = 0;
    for (int i = 0; i < a->n; i++) add(cord, a->p[3 * i], a->p[3 * i + 1], a->p[3 * i + 2]);
    const double depth = Z1 - R + 12.0, w = OUT + TAIL;
    for (int k = 1; k < 60; k++) /* half an ellipse below, y from -w to +w */
        add(cord, 0.0, -w * cos(M_PI * k / 60), Z1 - R - depth * sin(M_PI * k / 60));
    for (int i = 0; i < b->n; i++) add(cord, b->p[3 * i], b->p[3 * i + 1], b->p[3 * i + 2]);
}

static void random_rotation(double q[9])
{
    double u[4], len = 0.0;
    for (int k = 0; k < 4; k++) {
        u[k] = 2.0 * rand() / RAND_MAX - 1.0;
        len += u[k] * u[k];
    }
    len = sqrt(len);
    double w = u[0] / len, x = u[1] / len, y = u[2] / len, z = u[3] / len;
    double m[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
                   2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                   2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)};
    memcpy(q, m, sizeof m);
}

static void transform(const polygon *in, polygon *out, const double q[9], int mirror, int reverse)
{
    out->n = in->n;
    for (int i = 0; i < in->n; i++) {
        const double *p = &in->p[3 * (reverse ? in->n - 1 - i : i)];
        for (int r = 0; r < 3; r++)
            out->p[3 * i + r] = q[3 * r] * p[0] + q[3 * r + 1] * p[1] + q[3 * r + 2] * p[2];
        if (mirror) out->p[3 * i + 2] = -out->p[3 * i + 2];
    }
}

static double work[3 * (2 * MAX_POINTS + 400)];

static int name_across(const polygon *a, const polygon *b, rod_knot *k)
{
    char err[256];
    if (rod_knot_identify_across(NULL, a->p, a->n, b->p, b->n, work, k, err, sizeof err)) {
        printf("  identification failed: %s\n", err);
        return -1;
    }
    return 0;
}

/* names (a, b) as built, rotated, mirrored, swapped and reversed against the
 * names expected of it and of its mirror image */
static void check_pair(const char *what, const polygon *a, const polygon *b, const char *name,
                       int signature, const char *mirror_name)
{
    static polygon ra, rb;
    rod_knot k;
    int agree = 0, tries = 0;
    double q[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, seconds = 0.0;
    char first_wrong[200] = "";
    for (int r = 0; r <= ROTATIONS; r++) {
        if (r > 0) random_rotation(q);
        for (int variant = 0; variant < 8; variant++) {
            const int mirror = variant & 1, swap = (variant >> 1) & 1, reverse = variant >> 2;
            transform(swap ? b : a, &ra, q, mirror, reverse);
            transform(swap ? a : b, &rb, q, mirror, 0);
            const clock_t t0 = clock();
            const int failed = name_across(&ra, &rb, &k);
            seconds += (double)(clock() - t0) / CLOCKS_PER_SEC;
            const char *want = mirror ? mirror_name : name;
            const int want_sig = mirror ? -signature : signature;
            tries++;
            if (!failed && strcmp(k.name, want) == 0 && k.has_signature && k.signature == want_sig)
                agree++;
            else if (!first_wrong[0])
                snprintf(first_wrong, sizeof first_wrong, " (first wrong: rotation %d, %s%s%s: "
                         "%s, signature %d)", r, mirror ? "mirrored " : "", swap ? "swapped " : "",
                         reverse ? "reversed" : "", failed ? "failed" : k.name, k.signature);
        }
    }
    check(agree == tries, "%s: %s (signature %d; mirrored: %s) in %d of %d views%s; %.3g ms "
          "each", what, name, signature, mirror_name, agree, tries, first_wrong,
          1e3 * seconds / tries);
}

static polygon a, b, cord;

/* A shape file's points (header x,y,z) into g; 0 or -1 */
static int read_shape(const char *name, polygon *g)
{
    char path[1024], line[256];
    snprintf(path, sizeof path, "%s/scenes/%s", RODSIM_SOURCE_DIR, name);
    FILE *f = fopen(path, "r");
    g->n = 0;
    if (!f || !fgets(line, sizeof line, f)) {
        if (f) fclose(f);
        return -1;
    }
    double x, y, z;
    while (g->n < MAX_POINTS && fgets(line, sizeof line, f) &&
           sscanf(line, "%lf,%lf,%lf", &x, &y, &z) == 3)
        add(g, x, y, z);
    fclose(f);
    return g->n > 1 ? 0 : -1;
}

int main(void)
{
    srand(12345);
    const char *square = "square knot (trefoil # mirror trefoil)";
    const char *granny_r = "granny knot (trefoil # trefoil), right-handed";
    const char *granny_l = "granny knot (trefoil # trefoil), left-handed";
    for (int g = 0; g < 2; g++) {
        build(&a, &b, g ? -1.0 : 1.0);
        rod_knot k, ka, kb, kc;
        char err[256];
        /* each thread alone is no knot; the one cord is the reference */
        const int fa = rod_knot_identify(a.p, a.n, &ka, err, sizeof err);
        const int fb = rod_knot_identify(b.p, b.n, &kb, err, sizeof err);
        check(!fa && !fb && strcmp(ka.name, "unknot") == 0 && strcmp(kb.name, "unknot") == 0,
              "%s: each thread alone (%d, %d points) is the unknot: %s, %s", g ? "granny" : "reef",
              a.n, b.n, fa ? "failed" : ka.name, fb ? "failed" : kb.name);
        one_cord(&a, &b, &cord);
        const int fc = rod_knot_identify(cord.p, cord.n, &kc, err, sizeof err);
        const char *want = g ? NULL : square;
        if (g) want = !fc && kc.signature < 0 ? granny_r : granny_l;
        check(!fc && strcmp(kc.name, want) == 0 && kc.determinant == 9 &&
                  abs(kc.signature) == (g ? 4 : 0),
              "%s: one cord round a bundle: %s, determinant %lld, signature %d (reference: %s, "
              "determinant 9, signature %s)", g ? "granny" : "reef", fc ? "failed" : kc.name,
              kc.determinant, kc.signature, g ? "granny" : "square", g ? "+-4" : "0");
        const int f = name_across(&a, &b, &k);
        check(!f && strcmp(k.name, kc.name) == 0 && k.signature == kc.signature &&
                  k.determinant == 9 && k.terms == 5,
              "%s across the two threads: %s (Alexander %lld %lld %lld %lld %lld, determinant "
              "%lld, signature %d) = the one cord's", g ? "granny" : "reef", f ? "failed" : k.name,
              k.coefficient[0], k.coefficient[1], k.coefficient[2], k.coefficient[3],
              k.coefficient[4], k.determinant, k.signature);
        check_pair(g ? "granny" : "reef", &a, &b, kc.name, kc.signature,
                   g ? (strcmp(kc.name, granny_r) == 0 ? granny_l : granny_r) : square);
    }

    /* two straight threads far apart, and one laid across the other (the
     * crossing of crossing.ini): nothing tied */
    for (int far = 0; far < 2; far++) {
        a.n = b.n = 0;
        for (int i = 0; i < 50; i++) {
            add(&a, 0.0, -20.0 + 0.8 * i, 0.0);
            if (far) add(&b, 1000.0, -20.0 + 0.8 * i, 0.0);
            else add(&b, -30.0 + 1.2 * i, 0.0, 1.0);
        }
        check_pair(far ? "two straight threads 1000 apart" : "one straight thread across another",
                   &a, &b, "unknot", 0, "unknot");
    }
    /* two bights hooked through each other (a chain's two links, opened):
     * the unknot */
    a.n = b.n = 0;
    for (int i = 0; i <= 60; i++) { /* a: from -y over a U at y = +4 back to -y, in z = 0 */
        const double t = M_PI * i / 60;
        if (i == 0) add(&a, 2.0, -40.0, 0.0);
        add(&a, 2.0 * cos(t), 4.0 + 2.0 * sin(t) * 2.0 - 4.0, 0.0);
        if (i == 60) add(&a, -2.0, -40.0, 0.0);
    }
    for (int i = 0; i <= 60; i++) { /* b: from +y over a U at y = -4 in x = 0, through a's */
        const double t = M_PI * i / 60;
        if (i == 0) add(&b, 0.0, 40.0, 2.0);
        add(&b, 0.0, -4.0 * sin(t) + 2.0, 2.0 * cos(t));
        if (i == 60) add(&b, 0.0, 40.0, -2.0);
    }
    check_pair("two bights hooked", &a, &b, "unknot", 0, "unknot");
    /* the shipped scenes' starting shapes, as reef_knot_path.py ties them */
    const char *files[2][3] = {{"reef_knot_a.csv", "reef_knot_b.csv", square},
                               {"granny_knot_a.csv", "granny_knot_b.csv", granny_l}};
    for (int g = 0; g < 2; g++) {
        rod_knot k;
        const int ok = read_shape(files[g][0], &a) == 0 && read_shape(files[g][1], &b) == 0 &&
                       name_across(&a, &b, &k) == 0;
        check(ok && strcmp(k.name, files[g][2]) == 0, "scenes/%s and %s (%d, %d nodes): %s "
              "(reference %s, as the script builds it)", files[g][0], files[g][1], a.n, b.n,
              ok ? k.name : "not read or not identified", files[g][2]);
    }
    return test_finish();
}
