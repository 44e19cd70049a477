/* test_knot.c: the knot type of polygons of known knots generated here.
 * References: the Alexander polynomials of Rolfsen's table
 * (Rolfsen, Knots and Links, 1976, appendix C; Livingston, Knot Theory,
 * 1993, table), normalised with the lowest term constant and positive, and
 * the determinants |Delta(-1)| computed by hand from them. Each knot is
 * checked closed, and open (cut at an outer point, the ends pulled far out),
 * and under random rotations (other projections). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sim/geometry/knot.h"
#include "test.h"

#define MAX_POINTS 20000

typedef struct polygon {
    int n;
    double p[3 * MAX_POINTS];
} polygon;

static polygon poly, work;

/* (p, q) torus knot on a torus of radii 2 and 1; mirror: z -> -z. */
static void torus_knot(polygon *g, int n, int p, int q, int mirror, double shift_x)
{
    g->n = n;
    for (int i = 0; i < n; i++) {
        double f = 2.0 * M_PI * i / n, r = 2.0 + cos(q * f);
        g->p[3 * i] = r * cos(p * f) + shift_x;
        g->p[3 * i + 1] = r * sin(p * f);
        g->p[3 * i + 2] = (mirror ? -1.0 : 1.0) * sin(q * f);
    }
}

/* The figure-eight's standard parametrisation (outermost at f = 0: (3, 0, 0)). */
static void figure_eight(polygon *g, int n, double shift_x)
{
    g->n = n;
    for (int i = 0; i < n; i++) {
        double f = 2.0 * M_PI * i / n, r = 2.0 + cos(2.0 * f);
        g->p[3 * i] = r * cos(3.0 * f) + shift_x;
        g->p[3 * i + 1] = r * sin(3.0 * f);
        g->p[3 * i + 2] = sin(4.0 * f);
    }
}

static void circle(polygon *g, int n)
{
    g->n = n;
    for (int i = 0; i < n; i++) {
        double f = 2.0 * M_PI * i / n;
        g->p[3 * i] = cos(f);
        g->p[3 * i + 1] = sin(f);
        g->p[3 * i + 2] = 0.0;
    }
}

/* An unknot with 7 Reidemeister-I curls (an epitrochoid, a k = 1.6 > 1, lifted
 * a little in z): 7 crossings in the plane's projection, each a kink. */
static void curly_circle(polygon *g, int n)
{
    g->n = n;
    for (int i = 0; i < n; i++) {
        double f = 2.0 * M_PI * i / n;
        g->p[3 * i] = cos(f) + 0.2 * cos(8.0 * f);
        g->p[3 * i + 1] = sin(f) + 0.2 * sin(8.0 * f);
        g->p[3 * i + 2] = 0.1 * sin(8.0 * f + 0.3);
    }
}

/* An unknot wound 9 times around a circle (the (1, 9) torus curve): seen from
 * the side, many Reidemeister-II pairs of crossings. */
static void wound_circle(polygon *g, int n)
{
    g->n = n;
    for (int i = 0; i < n; i++) {
        double f = 2.0 * M_PI * i / n, r = 2.0 + 0.5 * cos(9.0 * f);
        g->p[3 * i] = r * cos(f);
        g->p[3 * i + 1] = r * sin(f);
        g->p[3 * i + 2] = 0.5 * sin(9.0 * f);
    }
}

/* An unknot wound `turns` times round a circle, seen from the side (x-z
 * plane, y the view): two crossings per turn. */
static void wound_side(polygon *g, int n, int turns)
{
    g->n = n;
    for (int i = 0; i < n; i++) {
        double f = 2.0 * M_PI * i / n, r = 2.0 + 0.5 * cos(turns * f);
        g->p[3 * i] = r * cos(f);
        g->p[3 * i + 2] = r * sin(f) * 0.999 + 0.001 * cos(f);
        g->p[3 * i + 1] = 0.5 * sin(turns * f);
    }
}

/* Connected sum of two knots, each in the ball of radius 3 about its centre
 * (x = 0 and x = 10) and outermost at its f = 0 point (3, 0, 0): the second
 * is turned by pi about z so that point faces the first. Each is cut open at
 * that point and the ends joined by two strands across the gap. */
static void connected_sum(polygon *g, const polygon *a, const polygon *b)
{
    int na = a->n, nb = b->n;
    g->n = 0;
    /* a from its point 1 round to its last; then b (turned) from 1 to last */
    for (int i = 1; i < na; i++) {
        memcpy(&g->p[3 * g->n], &a->p[3 * i], 3 * sizeof(double));
        g->n++;
    }
    for (int i = 1; i < nb; i++) {
        const double *r = &b->p[3 * i];
        g->p[3 * g->n] = 10.0 - r[0]; /* turned by pi about z, centred at x = 10 */
        g->p[3 * g->n + 1] = -r[1];
        g->p[3 * g->n + 2] = r[2];
        g->n++;
    }
}

/* Open a closed polygon at its point `cut` (dropped) and pull the two ends
 * out by `reach` along `dir`, spreading apart: a thread with the knot in its
 * middle. The tails are 20 segments each, spreading apart by `spreading`
 * (per unit of reach). */
static void cut_open(polygon *out, const polygon *g, int cut, const double dir[3], double reach,
                     double spreading)
{
    int n = g->n, tail = 20;
    const double *first = &g->p[3 * ((cut + 1) % n)], *last = &g->p[3 * ((cut + n - 1) % n)];
    double spread[3];
    for (int k = 0; k < 3; k++) spread[k] = first[k] - last[k];
    double l = sqrt(spread[0] * spread[0] + spread[1] * spread[1] + spread[2] * spread[2]);
    out->n = 0;
    for (int i = tail; i >= 1; i--) { /* the root's tail, from far in */
        double f = (double)i / tail;
        for (int k = 0; k < 3; k++)
            out->p[3 * out->n + k] = first[k] + f * reach * (dir[k] + spreading * spread[k] / l);
        out->n++;
    }
    for (int i = 1; i < n; i++) {
        memcpy(&out->p[3 * out->n], &g->p[3 * ((cut + i) % n)], 3 * sizeof(double));
        out->n++;
    }
    for (int i = 1; i <= tail; i++) {
        double f = (double)i / tail;
        for (int k = 0; k < 3; k++)
            out->p[3 * out->n + k] = last[k] + f * reach * (dir[k] - spreading * spread[k] / l);
        out->n++;
    }
}

/* A knot's tails leaving in opposite directions: the tip's tail first runs
 * round the knot's side (radius 4 about the centre, z = 0, through y < 0) to
 * (-4, 0, 0), then out along -x. The knot is outermost at (3, 0, 0), cut there. */
static void cut_open_opposite(polygon *out, const polygon *g, double reach)
{
    int n = g->n;
    out->n = 0;
    for (int i = 20; i >= 1; i--) {
        double f = (double)i / 20;
        out->p[3 * out->n] = g->p[3] + f * reach;
        out->p[3 * out->n + 1] = g->p[4];
        out->p[3 * out->n + 2] = g->p[5];
        out->n++;
    }
    for (int i = 1; i < n; i++) {
        memcpy(&out->p[3 * out->n], &g->p[3 * i], 3 * sizeof(double));
        out->n++;
    }
    for (int i = 0; i <= 40; i++) { /* half circle of radius 4 from (4, 0) to (-4, 0) */
        double f = -M_PI * i / 40.0;
        out->p[3 * out->n] = 4.0 * cos(f);
        out->p[3 * out->n + 1] = 4.0 * sin(f);
        out->p[3 * out->n + 2] = 0.0;
        out->n++;
    }
    for (int i = 1; i <= 20; i++) {
        out->p[3 * out->n] = -4.0 - reach * i / 20.0;
        out->p[3 * out->n + 1] = 0.0;
        out->p[3 * out->n + 2] = 0.0;
        out->n++;
    }
}

static unsigned long long rng = 0x9E3779B97F4A7C15ull;
static double uniform(void)
{
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(rng >> 11) / 9007199254740992.0;
}

/* A random rotation (a uniform unit quaternion) applied to every point. */
static void rotate_random(polygon *out, const polygon *g)
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
            out->p[3 * i + r] = R[3 * r] * g->p[3 * i] + R[3 * r + 1] * g->p[3 * i + 1] +
                                R[3 * r + 2] * g->p[3 * i + 2];
}

typedef struct reference {
    const char *name;
    int terms;
    long long c[7];
    long long determinant;
    int signature; /* additive under # (Livingston, Knot Theory, ch. 6) */
} reference;

/* The (2,q) torus knots as parametrised here are left-handed: every crossing
 * negative (the trefoil's 3-crossing diagram has writhe -3, checked below; the
 * Gauss writhe integral of the 400-point curve, computed separately, is
 * -3.52). Their signatures are then positive: +2 (trefoil), +4 (5_1), the
 * convention in which the right-handed trefoil has -2 (sign(V + V^T) of its
 * Seifert matrix V = [-1 1; 0 -1]). */
static const reference UNKNOT = {"unknot", 1, {1}, 1, 0};
static const reference TREFOIL = {"trefoil, left-handed", 3, {1, -1, 1}, 3, 2};
static const reference MIRROR_TREFOIL = {"trefoil, right-handed", 3, {1, -1, 1}, 3, -2};
static const reference FIGURE_EIGHT = {"figure-eight", 3, {1, -3, 1}, 5, 0};
static const reference CINQUEFOIL = {"cinquefoil (5_1), left-handed", 5, {1, -1, 1, -1, 1}, 5, 4};
static const reference GRANNY = {"granny knot (trefoil # trefoil), left-handed", 5,
                                 {1, -2, 3, -2, 1}, 9, 4};
static const reference SQUARE = {"square knot (trefoil # mirror trefoil)", 5, {1, -2, 3, -2, 1},
                                 9, 0};
/* the cinquefoil (+4) with a mirror trefoil (-2): the surgeon's knot's
 * double throw and its single throw turned the other way; with a trefoil of
 * its own hand (+2), the surgeon's granny. Delta = (t^4 - t^3 + t^2 - t + 1)
 * (t^2 - t + 1) expanded by hand; determinant 5 x 3. */
static const reference SURGEONS = {
    "surgeon's knot (cinquefoil # mirror trefoil), left-handed", 7, {1, -2, 3, -3, 3, -2, 1}, 15,
    2};
static const reference SURGEONS_GRANNY = {
    "granny surgeon's knot (cinquefoil # trefoil), left-handed", 7, {1, -2, 3, -3, 3, -2, 1}, 15,
    6};
static const reference TREFOIL_FIGURE_EIGHT = {"trefoil # figure-eight, left-handed", 5,
                                               {1, -4, 5, -4, 1}, 15, 2};

/* Identifies g (closed or open) and checks name, polynomial and determinant. */
static void expect(const char *what, const polygon *g, int closed, const reference *ref)
{
    rod_knot k;
    char err[256] = "", text[128] = "?", want[128];
    int rc = closed ? rod_knot_identify_closed(g->p, g->n, &k, err, sizeof err)
                    : rod_knot_identify(g->p, g->n, &k, err, sizeof err);
    if (!check(rc == 0, "%s (%s, %d points): identified (%s)", what, closed ? "closed" : "open",
               g->n, err))
        return;
    rod_knot_polynomial_text(&k, text, sizeof text);
    rod_knot refk = {.terms = ref->terms};
    memcpy(refk.coefficient, ref->c, sizeof ref->c);
    rod_knot_polynomial_text(&refk, want, sizeof want);
    int same = k.terms == ref->terms &&
               memcmp(k.coefficient, ref->c, (size_t)ref->terms * sizeof(long long)) == 0;
    check(same && strcmp(k.name, ref->name) == 0 && k.determinant == ref->determinant &&
              k.has_signature && k.signature == ref->signature,
          "%s (%s): computed %s, Delta = %s, det %lld, signature %d%s (%d crossings, writhe %d, "
          "%d tries); reference %s, Delta = %s, det %lld, signature %d",
          what, closed ? "closed" : "open", k.name, text, k.determinant, k.signature,
          k.has_signature ? "" : " (not computed)", k.crossings, k.writhe, k.tries, ref->name, want,
          ref->determinant, ref->signature);
}

/* Closed, open, and 4 random rotations of the open one. opposite: 1 tails
 * leave in opposite directions; 2 (a connected sum): cut at the middle of the
 * strand that joins the second knot back to the first, both tails along +y. */
static void expect_all(const char *what, const polygon *g, const reference *ref, int opposite)
{
    static polygon open, turned, split;
    expect(what, g, 1, ref);
    double out_x[3] = {1.0, 0.0, 0.0}, out_y[3] = {0.0, 1.0, 0.0};
    if (opposite == 2) {
        split = *g;
        const double *from = &g->p[3 * (g->n - 1)], *to = &g->p[0];
        for (int k = 0; k < 3; k++) split.p[3 * split.n + k] = 0.5 * (from[k] + to[k]);
        split.n++;
        cut_open(&open, &split, split.n - 1, out_y, 30.0, 0.0);
    } else if (opposite) cut_open_opposite(&open, g, 30.0);
    else cut_open(&open, g, 0, out_x, 30.0, 0.2);
    expect(what, &open, 0, ref);
    for (int r = 0; r < 4; r++) {
        char label[128];
        snprintf(label, sizeof label, "%s, random rotation %d", what, r + 1);
        rotate_random(&turned, r % 2 ? g : &open);
        expect(label, &turned, r % 2, ref);
    }
}

int main(void)
{
    printf("-- unknots\n");
    circle(&poly, 100);
    expect_all("circle", &poly, &UNKNOT, 0);
    curly_circle(&poly, 400);
    expect_all("circle with 7 curls", &poly, &UNKNOT, 0);
    wound_circle(&poly, 600);
    expect_all("circle wound 9 times", &poly, &UNKNOT, 0);
    {
        /* many crossings: the determinant of a large Alexander matrix */
        rod_knot k;
        char err[256] = "";
        wound_side(&poly, 4000, 60);
        int rc = rod_knot_identify_closed(poly.p, poly.n, &k, err, sizeof err);
        check(rc == 0 && strcmp(k.name, "unknot") == 0 && k.crossings >= 100 &&
                  k.has_signature && k.signature == 0,
              "circle wound 60 times: computed %s, signature %d, with %d crossings (%s); "
              "reference unknot, signature 0, >= 100 crossings", rc ? "?" : k.name, k.signature,
              k.crossings, err);
    }
    {
        static polygon line;
        line.n = 50;
        for (int i = 0; i < 50; i++) {
            line.p[3 * i] = 0.02 * i;
            line.p[3 * i + 1] = line.p[3 * i + 2] = 0.0;
        }
        expect("straight rod", &line, 0, &UNKNOT);
        line.n = 2;
        expect("a single segment", &line, 0, &UNKNOT);
    }

    printf("-- prime knots\n");
    torus_knot(&poly, 300, 2, 3, 0, 0.0);
    {
        /* handedness of the parametrisation: a 3-crossing diagram of it */
        rod_knot k;
        char err[256] = "";
        int rc = rod_knot_identify_closed(poly.p, poly.n, &k, err, sizeof err);
        check(rc == 0 && k.crossings == 3 && k.writhe == -3,
              "the (2,3) torus knot's first projection: %d crossings, writhe %d (reference 3, -3: "
              "every crossing negative, the left-handed trefoil, as its Gauss writhe -3.52)",
              k.crossings, k.writhe);
    }
    expect_all("trefoil (2,3) torus knot", &poly, &TREFOIL, 0);
    {
        /* a circle in a plane holding the first direction tried is seen edge-on
         * there, its halves overlapping: that projection is dropped, the next used */
        rod_knot k;
        char err[256] = "";
        int rc = rod_knot_identify_closed(poly.p, poly.n, &k, err, sizeof err);
        const double *w = k.direction;
        double a[3] = {w[1], -w[0], 0.0}, l = hypot(a[0], a[1]); /* perpendicular to w */
        work.n = 64;
        for (int i = 0; i < work.n; i++) {
            double f = 2.0 * M_PI * i / work.n;
            for (int j = 0; j < 3; j++) work.p[3 * i + j] = cos(f) * w[j] + sin(f) * a[j] / l;
        }
        rod_knot again;
        int rc2 = rod_knot_identify_closed(work.p, work.n, &again, err, sizeof err);
        check(rc == 0 && k.tries == 1 && rc2 == 0 && again.tries >= 2 &&
                  strcmp(again.name, "unknot") == 0,
              "a circle seen edge-on from the first direction: %d directions tried (reference "
              ">= 2), computed %s (reference unknot) (%s)", again.tries, rc2 ? "?" : again.name,
              err);
    }
    expect_all("trefoil, tails opposite", &poly, &TREFOIL, 1);
    torus_knot(&poly, 300, 2, 3, 1, 0.0);
    expect_all("mirror trefoil", &poly, &MIRROR_TREFOIL, 0);
    figure_eight(&poly, 400, 0.0);
    expect_all("figure-eight", &poly, &FIGURE_EIGHT, 0);
    expect_all("figure-eight, tails opposite", &poly, &FIGURE_EIGHT, 1);
    torus_knot(&poly, 500, 2, 5, 0, 0.0);
    expect_all("(2,5) torus knot", &poly, &CINQUEFOIL, 0);

    printf("-- composites\n");
    static polygon a, b;
    torus_knot(&a, 300, 2, 3, 0, 0.0);
    torus_knot(&b, 300, 2, 3, 0, 0.0);
    connected_sum(&poly, &a, &b);
    expect_all("granny (trefoil # trefoil)", &poly, &GRANNY, 2);
    torus_knot(&b, 300, 2, 3, 1, 0.0);
    connected_sum(&poly, &a, &b);
    expect_all("square (trefoil # mirror)", &poly, &SQUARE, 2);
    figure_eight(&b, 400, 0.0);
    connected_sum(&poly, &a, &b);
    expect_all("trefoil # figure-eight", &poly, &TREFOIL_FIGURE_EIGHT, 2);
    torus_knot(&a, 500, 2, 5, 0, 0.0);
    torus_knot(&b, 300, 2, 3, 1, 0.0);
    connected_sum(&poly, &a, &b);
    expect_all("surgeon's (cinquefoil # mirror trefoil)", &poly, &SURGEONS, 2);
    torus_knot(&b, 300, 2, 3, 0, 0.0);
    connected_sum(&poly, &a, &b);
    expect_all("surgeon's granny (cinquefoil # trefoil)", &poly, &SURGEONS_GRANNY, 2);

    printf("-- refused\n");
    {
        rod_knot k;
        char err[256] = "";
        /* a plane polygon through itself: (0,0)-(2,0) meets (1,1)-(1,-1) */
        static const double through[] = {0, 0, 0, 2, 0, 0, 2, 1, 0, 1, 1, 0, 1, -1, 0, 0, -1, 0};
        int rc = rod_knot_identify_closed(through, 6, &k, err, sizeof err);
        check(rc == -1 && strstr(err, "passes through itself") && strstr(err, "segments 1 and 4"),
              "a polygon through itself is refused, naming segments 1 and 4: '%s'", err);
        /* a tight coil of 300 turns: thousands of crossings in every projection */
        work.n = 12000;
        for (int i = 0; i < work.n; i++) {
            double f = 2.0 * M_PI * 300.0 * i / work.n;
            work.p[3 * i] = cos(f);
            work.p[3 * i + 1] = sin(f);
            work.p[3 * i + 2] = 0.01 * f;
        }
        rc = rod_knot_identify(work.p, work.n, &k, err, sizeof err);
        check(rc == -1 && strstr(err, "more than 400 crossings"),
              "a coil of 300 turns is refused in bounded time: '%s'", err);
        rc = rod_knot_identify(work.p, 1, &k, err, sizeof err);
        check(rc == -1 && strstr(err, "not 1"), "one point is refused: '%s'", err);
        work.p[4] = NAN;
        rc = rod_knot_identify(work.p, 10, &k, err, sizeof err);
        check(rc == -1 && strstr(err, "point 2 is not finite"), "NaN refused: '%s'", err);
    }
    return test_finish();
}
