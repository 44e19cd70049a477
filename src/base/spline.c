/* spline.c: natural cubic spline through 3-D points, chord-length parameter. */
#include "base/spline.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"

struct spline3 {
    int count;       /* distinct points */
    double *knot;    /* (count) parameter of each point: chord length from the first */
    double *point;   /* (count x 3) */
    double *second;  /* (count x 3) second derivatives at the points; 0 at the ends */
};

void spline3_destroy(spline3 *s)
{
    if (!s) return;
    free(s->knot);
    free(s->point);
    free(s->second);
    free(s);
}

/* The natural spline's second derivatives: for each coordinate the
 * tridiagonal system h_{j-1} M_{j-1} + 2 (h_{j-1} + h_j) M_j + h_j M_{j+1}
 * = 6 (slope_j - slope_{j-1}), M = 0 at both ends, by the Thomas algorithm
 * (diagonally dominant: no pivoting). `scratch` holds count doubles. */
static void solve_second(spline3 *s, double *scratch)
{
    const int n = s->count;
    memset(s->second, 0, (size_t)n * 3 * sizeof(double));
    if (n < 3) return;
    double *upper = scratch; /* the eliminated super-diagonal, per row */
    for (int c = 0; c < 3; c++) {
        double previous_rhs = 0.0;
        for (int j = 1; j + 1 < n; j++) {
            double h0 = s->knot[j] - s->knot[j - 1], h1 = s->knot[j + 1] - s->knot[j];
            double slope0 = (s->point[3 * j + c] - s->point[3 * (j - 1) + c]) / h0;
            double slope1 = (s->point[3 * (j + 1) + c] - s->point[3 * j + c]) / h1;
            double diagonal = 2.0 * (h0 + h1), rhs = 6.0 * (slope1 - slope0);
            if (j > 1) {
                diagonal -= h0 * upper[j - 1];
                rhs -= h0 * previous_rhs;
            }
            upper[j] = h1 / diagonal;
            previous_rhs = rhs / diagonal;
            s->second[3 * j + c] = previous_rhs;
        }
        for (int j = n - 3; j >= 1; j--) s->second[3 * j + c] -= upper[j] * s->second[3 * (j + 1) + c];
    }
}

spline3 *spline3_create(const double *points, int count)
{
    spline3 *s = calloc(1, sizeof *s);
    if (!s || count < 2) {
        free(s);
        return NULL;
    }
    s->knot = malloc((size_t)count * sizeof(double));
    s->point = malloc((size_t)count * 3 * sizeof(double));
    s->second = malloc((size_t)count * 3 * sizeof(double));
    double *scratch = malloc((size_t)count * sizeof(double));
    if (!s->knot || !s->point || !s->second || !scratch) {
        free(scratch);
        spline3_destroy(s);
        return NULL;
    }
    int n = 0;
    for (int i = 0; i < count; i++) {
        double d[3] = {0, 0, 0};
        if (n > 0) v3_sub(d, &points[3 * i], &s->point[3 * (n - 1)]);
        if (n > 0 && v3_norm(d) == 0.0) continue;
        s->knot[n] = n > 0 ? s->knot[n - 1] + v3_norm(d) : 0.0;
        v3_copy(&s->point[3 * n], &points[3 * i]);
        n++;
    }
    s->count = n;
    if (n < 2) {
        free(scratch);
        spline3_destroy(s);
        return NULL;
    }
    solve_second(s, scratch);
    free(scratch);
    return s;
}

double spline3_end(const spline3 *s) { return s->knot[s->count - 1]; }

/* Value and first derivative on interval j at parameter u. */
static void eval_interval(const spline3 *s, int j, double u, double out[3], double slope[3])
{
    double h = s->knot[j + 1] - s->knot[j];
    double a = (s->knot[j + 1] - u) / h, b = (u - s->knot[j]) / h;
    for (int c = 0; c < 3; c++) {
        double y0 = s->point[3 * j + c], y1 = s->point[3 * (j + 1) + c];
        double m0 = s->second[3 * j + c], m1 = s->second[3 * (j + 1) + c];
        out[c] = a * y0 + b * y1 + ((a * a * a - a) * m0 + (b * b * b - b) * m1) * h * h / 6.0;
        slope[c] = (y1 - y0) / h + ((1.0 - 3.0 * a * a) * m0 + (3.0 * b * b - 1.0) * m1) * h / 6.0;
    }
}

/* Interval holding u: the largest j with knot[j] <= u, searched from `hint`
 * (the walk moves forward, so this is amortised constant time). */
static int interval_of(const spline3 *s, double u, int hint)
{
    int j = hint < 0 ? 0 : hint > s->count - 2 ? s->count - 2 : hint;
    while (j > 0 && u < s->knot[j]) j--;
    while (j + 2 < s->count && u >= s->knot[j + 1]) j++;
    return j;
}

static void eval_hinted(const spline3 *s, double u, int *hint, double out[3])
{
    double slope[3], end = spline3_end(s);
    if (u <= 0.0 || u >= end) { /* the straight continuation along the end's tangent */
        int j = u <= 0.0 ? 0 : s->count - 2;
        double at = u <= 0.0 ? 0.0 : end;
        eval_interval(s, j, at, out, slope);
        double length = v3_norm(slope);
        if (length > 0.0) v3_axpy(out, (u - at) / length, slope);
        return;
    }
    *hint = interval_of(s, u, *hint);
    eval_interval(s, *hint, u, out, slope);
}

void spline3_eval(const spline3 *s, double u, double out[3])
{
    int hint = 0;
    eval_hinted(s, u, &hint, out);
}

/* Straight distance from `from` to the curve at u. */
static double distance_at(const spline3 *s, double u, int *hint, const double from[3])
{
    double x[3], d[3];
    eval_hinted(s, u, hint, x);
    v3_sub(d, x, from);
    return v3_norm(d);
}

/* spline3_walk with step `step`, or steps[i - 1] before out[i] when steps
 * is given. */
static void walk(const spline3 *s, double step, const double *steps, int points, double *out)
{
    int hint = 0;
    double u = 0.0;
    spline3_eval(s, 0.0, out);
    /* The parameter is arc length to within the chords' shortfall, so a
     * march of step / 4 cannot jump over the first crossing; then bisection.
     * Each march ends: beyond the curve's end the distance grows linearly. */
    for (int i = 1; i < points; i++) {
        const double *from = &out[3 * (i - 1)];
        if (steps) step = steps[i - 1];
        double below = u, above = u + 0.25 * step;
        while (distance_at(s, above, &hint, from) < step) {
            below = above;
            above += 0.25 * step;
        }
        for (int k = 0; k < 200 && above - below > 1e-13 * step; k++) {
            double middle = 0.5 * (below + above);
            if (distance_at(s, middle, &hint, from) < step) below = middle;
            else above = middle;
        }
        u = above;
        eval_hinted(s, u, &hint, &out[3 * i]);
    }
}

void spline3_walk(const spline3 *s, double step, int points, double *out)
{
    walk(s, step, NULL, points, out);
}

void spline3_walk_steps(const spline3 *s, const double *steps, int points, double *out)
{
    walk(s, 0.0, steps, points, out);
}
