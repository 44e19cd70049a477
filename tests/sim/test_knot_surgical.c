/* test_knot_surgical.c: the knots a surgeon ties, named from every viewing
 * direction.
 *
 * Each shape is an open thread whose two ends leave far apart (as the two
 * ends of a suture), with its throws tied in a row along it: a single throw
 * closes to a trefoil (the (2,3) torus knot), a double throw to a cinquefoil
 * (the (2,5) torus knot), and throws one after the other along the thread
 * are their connected sum. Each throw lies in its own ball of radius 3 that
 * the thread enters and leaves once from below, so the row is the connected
 * sum of its throws.
 *
 * References, independent of knot.c: the hand of each throw from the Gauss
 * writhe integral of its closed curve, computed here (positive: a
 * right-handed throw); Delta and signature from KnotInfo
 * (knotinfo.math.indiana.edu) and Rolfsen (Knots and Links, 1976, app. C):
 * 3_1 1 - t + t^2, determinant 3, signature -2 right-handed; 5_1
 * 1 - t + t^2 - t^3 + t^4, determinant 5, signature -4 right-handed; under
 * the connected sum Delta multiplies (the product computed here), the
 * determinant multiplies and the signature adds (Livingston, Knot Theory,
 * 1993, ch. 6 and 8). So the square knot 3_1 # 3_1* has 0, the granny +-4,
 * the surgeon's knot 5_1 # 3_1* +-2 and the surgeon's granny 5_1 # 3_1 +-6.
 *
 * Then the starting shapes of two shipped scenes, tied from throw geometry
 * by their generators: overhand.ini's overhand (its hand from the Gauss
 * writhe of the open thread) and surgeons_knot.ini's surgeon's knot (each
 * throw a double helix of the two strands; left-handed, signature 2, as its
 * generator builds it).
 *
 * Every shape is identified as built and under 50 random rotations (knot.c
 * projects along a fixed direction: a rotation is another viewing
 * direction), and each rotated copy's mirror image too: all must agree. The
 * CPU time per identification is printed (not checked). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sim/geometry/knot.h"
#include "test.h"

#define MAX_POINTS 4000
#define ROTATIONS 50
#define THROW_POINTS 240 /* per half-twist pair of a throw's closed curve */

typedef struct polygon {
    int n;
    double p[3 * MAX_POINTS];
} polygon;

/* A throw: q half-twists (3 single, 5 double), hand +1 right, -1 left. */
typedef struct throw_spec {
    int q, hand;
} throw_spec;

typedef struct shape {
    const char *what;
    int throws;
    throw_spec t[2];
    const char *name;        /* reference name (knot.h's naming) */
    const char *mirror_name; /* of its mirror image */
} shape;

/* The closed (2,q) torus knot of the given hand on a torus of radii 2 and 1
 * about the origin, outermost (radius 3) at its point 0. */
static void throw_curve(polygon *g, int n, int q, int hand)
{
    g->n = n;
    for (int i = 0; i < n; i++) {
        double f = 2.0 * M_PI * i / n, r = 2.0 + cos(q * f);
        g->p[3 * i] = r * cos(2.0 * f);
        g->p[3 * i + 1] = r * sin(2.0 * f);
        g->p[3 * i + 2] = -hand * sin(q * f);
    }
}

/* Gauss writhe integral of a polygon (closed: the last point joins the
 * first), midpoint rule:
 * (1 / 4 pi) sum_{i != j} (r_i - r_j) . (dr_i x dr_j) / |r_i - r_j|^3 */
static double writhe(const polygon *g, int closed)
{
    int n = g->n, segments = closed ? n : n - 1;
    double w = 0.0;
    for (int i = 0; i < segments; i++) {
        const double *a0 = &g->p[3 * i], *a1 = &g->p[3 * ((i + 1) % n)];
        for (int j = 0; j < segments; j++) {
            if (j == i) continue;
            const double *b0 = &g->p[3 * j], *b1 = &g->p[3 * ((j + 1) % n)];
            double da[3], db[3], r[3];
            for (int k = 0; k < 3; k++) {
                da[k] = a1[k] - a0[k];
                db[k] = b1[k] - b0[k];
                r[k] = 0.5 * (a0[k] + a1[k]) - 0.5 * (b0[k] + b1[k]);
            }
            double c[3] = {da[1] * db[2] - da[2] * db[1], da[2] * db[0] - da[0] * db[2],
                           da[0] * db[1] - da[1] * db[0]};
            double d = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
            w += (r[0] * c[0] + r[1] * c[1] + r[2] * c[2]) / (d * d * d);
        }
    }
    return w / (4.0 * M_PI);
}

static void add_point(polygon *g, double x, double y, double z)
{
    g->p[3 * g->n] = x;
    g->p[3 * g->n + 1] = y;
    g->p[3 * g->n + 2] = z;
    g->n++;
}

/* The thread: from (-30, -5, 0) along y = -5 to the right; throw k sits in
 * the ball of radius 3 about (8 k, 0, 0), turned so its outermost point
 * faces the thread (at (8 k, -3, 0)), opened there and entered from the
 * thread and left back to it; the thread then runs on 30 beyond the last. */
static void build_thread(polygon *out, const shape *s)
{
    static polygon curve;
    out->n = 0;
    for (int i = 0; i < 20; i++) add_point(out, -30.0 + 29.6 * i / 20.0, -5.0, 0.0);
    for (int k = 0; k < s->throws; k++) {
        double cx = 8.0 * k;
        throw_curve(&curve, THROW_POINTS * (s->t[k].q + 1) / 4, s->t[k].q, s->t[k].hand);
        int n = curve.n;
        if (k > 0)
            for (int i = 1; i <= 10; i++) add_point(out, cx - 7.2 + 6.8 * i / 10.0, -5.0, 0.0);
        else add_point(out, cx - 0.4, -5.0, 0.0);
        /* turned by -90 degrees about z: (x, y) -> (y, -x); point 0 left out */
        for (int i = n - 1; i >= 1; i--)
            add_point(out, cx + curve.p[3 * i + 1], -curve.p[3 * i], curve.p[3 * i + 2]);
        add_point(out, cx + 0.4, -5.0, 0.0);
    }
    double last = 8.0 * (s->throws - 1) + 0.4;
    for (int i = 1; i <= 20; i++) add_point(out, last + 29.6 * i / 20.0, -5.0, 0.0);
}

/* Squared distance between segments [p0, p1] and [q0, q1] (clamped
 * closest points; sampled finely enough for a positive lower bound here). */
static double segment_distance2(const double *p0, const double *p1, const double *q0,
                                const double *q1)
{
    double d1[3], d2[3], r[3];
    for (int k = 0; k < 3; k++) {
        d1[k] = p1[k] - p0[k];
        d2[k] = q1[k] - q0[k];
        r[k] = p0[k] - q0[k];
    }
    double a = d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2];
    double e = d2[0] * d2[0] + d2[1] * d2[1] + d2[2] * d2[2];
    double b = d1[0] * d2[0] + d1[1] * d2[1] + d1[2] * d2[2];
    double c = d1[0] * r[0] + d1[1] * r[1] + d1[2] * r[2];
    double f = d2[0] * r[0] + d2[1] * r[1] + d2[2] * r[2];
    double den = a * e - b * b, s = den > 1e-14 * a * e ? (b * f - c * e) / den : 0.0;
    s = fmin(1.0, fmax(0.0, s));
    double t = (b * s + f) / e;
    if (t < 0.0) {
        t = 0.0;
        s = fmin(1.0, fmax(0.0, -c / a));
    } else if (t > 1.0) {
        t = 1.0;
        s = fmin(1.0, fmax(0.0, (b - c) / a));
    }
    double d2sum = 0.0;
    for (int k = 0; k < 3; k++) {
        double v = r[k] + s * d1[k] - t * d2[k];
        d2sum += v * v;
    }
    return d2sum;
}

/* Least distance between non-adjacent segments of the open polygon, m. */
static double closest_approach(const polygon *g)
{
    double best = INFINITY;
    for (int i = 0; i + 1 < g->n; i++)
        for (int j = i + 2; j + 1 < g->n; j++)
            best = fmin(best, segment_distance2(&g->p[3 * i], &g->p[3 * i + 3], &g->p[3 * j],
                                                &g->p[3 * j + 3]));
    return sqrt(best);
}

static unsigned long long rng = 0x2545F4914F6CDD1Dull;
static double uniform(void)
{
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(rng >> 11) / 9007199254740992.0;
}

/* A random rotation (a uniform unit quaternion); mirror: then z -> -z. */
static void rotate_random(polygon *out, const polygon *g, int mirror)
{
    double u1 = uniform(), u2 = uniform(), u3 = uniform();
    double a = sqrt(1 - u1) * sin(2 * M_PI * u2), b = sqrt(1 - u1) * cos(2 * M_PI * u2);
    double c = sqrt(u1) * sin(2 * M_PI * u3), d = sqrt(u1) * cos(2 * M_PI * u3);
    double R[9] = {1 - 2 * (c * c + d * d), 2 * (b * c - a * d), 2 * (b * d + a * c),
                   2 * (b * c + a * d), 1 - 2 * (b * b + d * d), 2 * (c * d - a * b),
                   2 * (b * d - a * c), 2 * (c * d + a * b), 1 - 2 * (b * b + c * c)};
    out->n = g->n;
    for (int i = 0; i < g->n; i++)
        for (int r = 0; r < 3; r++)
            out->p[3 * i + r] = (mirror && r == 2 ? -1.0 : 1.0) *
                                (R[3 * r] * g->p[3 * i] + R[3 * r + 1] * g->p[3 * i + 1] +
                                 R[3 * r + 2] * g->p[3 * i + 2]);
}

static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* The reference knot of a row of throws (file comment). */
static void reference_of(const shape *s, int mirror, rod_knot *ref)
{
    memset(ref, 0, sizeof *ref);
    ref->terms = 1;
    ref->coefficient[0] = 1;
    ref->determinant = 1;
    for (int k = 0; k < s->throws; k++) {
        int q = s->t[k].q, hand = mirror ? -s->t[k].hand : s->t[k].hand;
        long long product[ROD_KNOT_MAX_TERMS] = {0};
        for (int i = 0; i < ref->terms; i++) /* (2,q) torus knot: 1 - t + ... + t^(q-1) */
            for (int j = 0; j < q; j++)
                product[i + j] += ref->coefficient[i] * (j % 2 ? -1 : 1);
        ref->terms += q - 1;
        memcpy(ref->coefficient, product, sizeof product);
        ref->determinant *= q;
        ref->signature += -(q - 1) * hand;
    }
    snprintf(ref->name, sizeof ref->name, "%s", mirror ? s->mirror_name : s->name);
}

static int same_knot(const rod_knot *a, const rod_knot *b)
{
    return strcmp(a->name, b->name) == 0 && a->terms == b->terms &&
           memcmp(a->coefficient, b->coefficient, (size_t)a->terms * sizeof(long long)) == 0 &&
           a->determinant == b->determinant && a->signature == b->signature;
}

static void print_knot(const char *label, const rod_knot *k)
{
    char text[160];
    rod_knot_polynomial_text(k, text, sizeof text);
    printf("    %s: %s, Delta = %s, determinant %lld, signature %d\n", label, k->name, text,
           k->determinant, k->signature);
}

static double total_seconds;
static int total_calls;

/* The thread as given and under ROTATIONS random rotations, each also
 * mirrored: every call must give ref[0] (ref[1] mirrored). */
static void expect_thread(rod_knot_scratch *scratch, const char *what, const polygon *thread,
                          const rod_knot ref[2])
{
    static polygon turned;
    rod_knot first = {0};
    int agree[2] = {0, 0}, tried[2] = {0, 0}, lo = 1 << 30, hi = 0, fails = 0;
    char err[256] = "", bad[640] = "";
    double t0 = cpu_seconds();
    for (int r = 0; r <= ROTATIONS; r++)
        for (int mirror = 0; mirror < 2; mirror++) {
            if (r == 0) { /* as built (the mirror: z -> -z) */
                turned = *thread;
                if (mirror)
                    for (int i = 0; i < turned.n; i++) turned.p[3 * i + 2] *= -1.0;
            } else rotate_random(&turned, thread, mirror);
            rod_knot k;
            int rc = rod_knot_identify_in(scratch, turned.p, turned.n, 0, &k, err, sizeof err);
            tried[mirror]++;
            if (rc) {
                fails++;
                snprintf(bad, sizeof bad, "rotation %d%s: %s", r, mirror ? " mirrored" : "", err);
                continue;
            }
            if (r == 0 && !mirror) first = k;
            if (same_knot(&k, &ref[mirror]) && k.has_signature) agree[mirror]++;
            else if (!bad[0]) {
                char text[160];
                rod_knot_polynomial_text(&k, text, sizeof text);
                snprintf(bad, sizeof bad, "rotation %d%s: %s, Delta = %s, signature %d", r,
                         mirror ? " mirrored" : "", k.name, text, k.signature);
            }
            lo = k.crossings < lo ? k.crossings : lo;
            hi = k.crossings > hi ? k.crossings : hi;
        }
    double seconds = cpu_seconds() - t0;
    total_seconds += seconds;
    total_calls += tried[0] + tried[1];
    print_knot("computed (as built)", &first);
    print_knot("reference", &ref[0]);
    print_knot("reference, mirrored", &ref[1]);
    check(agree[0] == tried[0] && agree[1] == tried[1] && fails == 0,
          "%s: %d of %d directions name it %s and %d of %d mirrored ones %s (%d to %d "
          "crossings; %.3f ms per call)%s%s",
          what, agree[0], tried[0], ref[0].name, agree[1], tried[1], ref[1].name, lo, hi,
          1e3 * seconds / (tried[0] + tried[1]), bad[0] ? "; first disagreement " : "", bad);
}

static void expect_shape(rod_knot_scratch *scratch, const shape *s)
{
    static polygon thread;
    build_thread(&thread, s);
    double gap = closest_approach(&thread);
    check(gap > 0.05, "%s: %d points, least distance between non-adjacent segments %.3f "
          "(reference > 0.05, the throws' radius 3)", s->what, thread.n, gap);
    rod_knot ref[2];
    reference_of(s, 0, &ref[0]);
    reference_of(s, 1, &ref[1]);
    expect_thread(scratch, s->what, &thread, ref);
}

/* A shipped scene's starting shape (x,y,z per line after a header, m);
 * 0 or -1. */
static int load_shape(const char *path, polygon *g)
{
    FILE *f = fopen(path, "r");
    if (!f) return -1;
    char line[256];
    g->n = 0;
    if (!fgets(line, sizeof line, f)) g->n = -1;
    while (g->n >= 0 && g->n < MAX_POINTS && fgets(line, sizeof line, f)) {
        double *r = &g->p[3 * g->n];
        if (sscanf(line, "%lf,%lf,%lf", &r[0], &r[1], &r[2]) == 3) g->n++;
    }
    fclose(f);
    return g->n > 1 ? 0 : -1;
}

/* The scenes' knots tied from throws by their generators (a double helix
 * per throw: surgeons_knot_path.py; Shastri's long trefoil:
 * overhand_path.py), with their tissue-side tails: the same from every
 * direction. */
static void expect_scene_shape(rod_knot_scratch *scratch, const char *file, const shape *s,
                               double diameter)
{
    static polygon thread;
    char path[512];
    snprintf(path, sizeof path, "%s/scenes/%s", RODSIM_SOURCE_DIR, file);
    if (!check(load_shape(path, &thread) == 0, "%s: read (%s)", file, path)) return;
    double gap = closest_approach(&thread);
    check(gap > 0.5 * diameter, "%s: %d points, least distance between non-adjacent segments "
          "%.3g m (reference > half the cord's %.3g m)", file, thread.n, gap, diameter);
    rod_knot ref[2];
    reference_of(s, 0, &ref[0]);
    reference_of(s, 1, &ref[1]);
    expect_thread(scratch, s->what, &thread, ref);
}

int main(void)
{
    printf("-- the throws' hands (Gauss writhe integral of the closed curve)\n");
    static polygon curve;
    for (int q = 3; q <= 5; q += 2)
        for (int hand = -1; hand <= 1; hand += 2) {
            throw_curve(&curve, THROW_POINTS * (q + 1) / 4, q, hand);
            double w = writhe(&curve, 1);
            check(w * hand > 1.0, "(2,%d) torus knot built %s-handed: Gauss writhe %.3f "
                  "(reference: sign %+d, |writhe| > 1)", q, hand > 0 ? "right" : "left", w, hand);
        }

    static const shape shapes[] = {
        {"single throw, right", 1, {{3, 1}}, "trefoil, right-handed", "trefoil, left-handed"},
        {"double throw, right", 1, {{5, 1}}, "cinquefoil (5_1), right-handed",
         "cinquefoil (5_1), left-handed"},
        {"square knot, right then left", 2, {{3, 1}, {3, -1}},
         "square knot (trefoil # mirror trefoil)", "square knot (trefoil # mirror trefoil)"},
        {"square knot, left then right", 2, {{3, -1}, {3, 1}},
         "square knot (trefoil # mirror trefoil)", "square knot (trefoil # mirror trefoil)"},
        {"granny knot, right twice", 2, {{3, 1}, {3, 1}},
         "granny knot (trefoil # trefoil), right-handed",
         "granny knot (trefoil # trefoil), left-handed"},
        {"granny knot, left twice", 2, {{3, -1}, {3, -1}},
         "granny knot (trefoil # trefoil), left-handed",
         "granny knot (trefoil # trefoil), right-handed"},
        {"surgeon's knot, double left then single right", 2, {{5, -1}, {3, 1}},
         "surgeon's knot (cinquefoil # mirror trefoil), left-handed",
         "surgeon's knot (cinquefoil # mirror trefoil), right-handed"},
        {"surgeon's knot, double right then single left", 2, {{5, 1}, {3, -1}},
         "surgeon's knot (cinquefoil # mirror trefoil), right-handed",
         "surgeon's knot (cinquefoil # mirror trefoil), left-handed"},
        {"surgeon's knot, single left after double right", 2, {{3, -1}, {5, 1}},
         "surgeon's knot (cinquefoil # mirror trefoil), right-handed",
         "surgeon's knot (cinquefoil # mirror trefoil), left-handed"},
        {"surgeon's granny, double right then single right", 2, {{5, 1}, {3, 1}},
         "granny surgeon's knot (cinquefoil # trefoil), right-handed",
         "granny surgeon's knot (cinquefoil # trefoil), left-handed"},
    };
    rod_knot_scratch *scratch = rod_knot_scratch_create();
    if (!check(scratch != NULL, "scratch created")) return 1;
    for (size_t i = 0; i < sizeof shapes / sizeof shapes[0]; i++) {
        printf("-- %s\n", shapes[i].what);
        expect_shape(scratch, &shapes[i]);
    }
    printf("-- the scenes' starting shapes\n");
    /* the overhand: its hand from the open thread's Gauss writhe integral */
    static polygon overhand;
    char path[512];
    snprintf(path, sizeof path, "%s/scenes/overhand_shape.csv", RODSIM_SOURCE_DIR);
    double w = load_shape(path, &overhand) == 0 ? writhe(&overhand, 0) : NAN;
    check(w > 1.0, "overhand_shape.csv: Gauss writhe of the open thread %.3f (reference > 1: "
          "right-handed)", w);
    const shape overhand_knot = {"overhand.ini's overhand", 1, {{3, 1}}, "trefoil, right-handed",
                                 "trefoil, left-handed"};
    expect_scene_shape(scratch, "overhand_shape.csv", &overhand_knot, 0.004);
    /* the surgeon's knot: a left-handed double throw, the single throw the
     * other way (its generator: signature 2) */
    const shape surgeons = {"surgeons_knot.ini's surgeon's knot", 2, {{5, -1}, {3, 1}},
                            "surgeon's knot (cinquefoil # mirror trefoil), left-handed",
                            "surgeon's knot (cinquefoil # mirror trefoil), right-handed"};
    expect_scene_shape(scratch, "surgeons_knot_shape.csv", &surgeons, 0.004);
    rod_knot_scratch_destroy(scratch);
    printf("-- identification cost: %.3f ms CPU per call over %d calls (not checked)\n",
           1e3 * total_seconds / total_calls, total_calls);
    return test_finish();
}
