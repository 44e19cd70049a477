/* path.c: a driven end's path (see path.h).
 *
 * Interpolation: on each interval between rows, a
 * quintic Hermite polynomial per component, fixed by the position, velocity
 * and acceleration at its two rows. Neighbouring intervals share those three
 * values at their common row, so position, velocity and acceleration are
 * continuous everywhere (C2), and every row is passed exactly. The values at
 * the rows:
 *   - first and last row: velocity 0 and acceleration 0, so the end starts
 *     from rest and is held after the last row with no jump in acceleration
 *     (a clamped cubic spline has zero end velocity but a non-zero end
 *     acceleration: the driving force would jump when the path ends);
 *   - every other row: the velocity and acceleration of the C2 cubic spline
 *     through the rows with zero velocity at both ends (one tridiagonal solve
 *     per component, diagonally dominant, no pivoting needed).
 * A global quintic spline (C4) would need a pentadiagonal solve and gives
 * continuity the dynamics does not use (it sees velocity and acceleration).
 * A path sampled from a smooth motion that starts and ends at rest is
 * reproduced to second order in the row spacing in acceleration and third in
 * velocity (tests/sim/test_path.c prints the errors).
 *
 * Rotation: the rotation vector r(t) is interpolated component-wise the same
 * way and R = exp([r]x). The angular velocity, global (space) components,
 * [omega]x = dR/dt R^T, is
 *   omega = J(r) r_dot,  J(r) = I + b(q) [r]x + c(q) [r]x^2,
 *   b = (1 - cos x) / x^2,  c = (x - sin x) / x^3,  x = |r|, q = x^2,
 * the left Jacobian (the "dexp" of r) of SO(3): G. S. Chirikjian, Stochastic
 * Models, Information Theory, and Lie Groups, vol. 2 (Birkhauser 2012),
 * section 10.6 (the Jacobians of SO(3) in exponential coordinates);
 * A. Iserles, H. Munthe-Kaas, S. Norsett, A. Zanna, Lie-group methods, Acta
 * Numerica 9 (2000), dexp. Its time derivative, exactly:
 *   alpha = J r_ddot + 2 (r . r_dot) (b'(q) r x r_dot + c'(q) r x (r x r_dot))
 *           + c(q) r_dot x (r x r_dot),
 * with b' and c' the derivatives with respect to q = |r|^2.
 *
 * Paths with their velocity given (a live session's record, and
 * the live path itself): each interval is the cubic Hermite polynomial
 * through the positions and velocities of its two rows, so position and
 * velocity are continuous and every row's velocity is the given one; the
 * acceleration steps at the rows (the implicit scheme uses position and
 * velocity only). A live path keeps the last LIVE_ROWS rows; the velocity at
 * a pushed row is the backward difference through it and the two rows
 * before, second order in the spacing on uneven times (the one-sided
 * three-point formula; the first difference at the second row). Causal: a
 * row never changes once pushed, so a record of the rows and their
 * velocities replays to the same poses. */
#include "sim/path.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/textfile.h"
#include "base/textline.h"
#include "base/vec3.h"

/* A path of more rows is refused: 1e6 rows hold a 1 kHz recording of a
 * needle holder for 16 minutes, and cost 150 MB with their derivatives. */
#define PATH_MAX_ROWS 1000000
/* A path file of more bytes is refused unread: PATH_MAX_ROWS rows of the
 * widest record (13 numbers written with 17 digits, 325 bytes a row) fit. */
#define PATH_MAX_BYTES ((size_t)512 << 20)
/* A live path keeps this many rows: the interval being stepped, the rows
 * of the backward difference, and one to restore after rod_path_pop(). */
#define LIVE_ROWS 4

struct rod_path {
    int rows;
    int columns;          /* 4 or 7 */
    int components;       /* columns - 1: x y z [rx ry rz] */
    double *time;         /* (rows), s */
    double *value;        /* (rows x components): m, rad */
    double *velocity;     /* (rows x components) at the rows: m/s, rad/s */
    double *acceleration; /* (rows x components) at the rows: m/s^2, rad/s^2; NULL when the
                             velocity is given (cubic Hermite intervals) */
    int live;             /* 1: rows are pushed (rod_path_push), at most LIVE_ROWS kept */
    /* a handed-over path (rod_path_handover): `before` until `at`, then
     * `after` carrying the pose as it was at `at`; no rows of its own */
    rod_path *before, *after; /* owned */
    double at;                /* s */
};

void rod_path_destroy(rod_path *p)
{
    if (!p) return;
    rod_path_destroy(p->before);
    rod_path_destroy(p->after);
    free(p->time);
    free(p->value);
    free(p->velocity);
    free(p->acceleration);
    free(p);
}

void rod_path_translate(rod_path *p, const double shift[3])
{
    /* the pose after the handover is carried from the one before it */
    if (p->before) rod_path_translate(p->before, shift);
    for (int r = 0; r < p->rows; r++)
        for (int k = 0; k < 3; k++) p->value[p->components * r + k] += shift[k];
}

int rod_path_columns(const rod_path *p) { return p->columns; }
int rod_path_has_velocity(const rod_path *p)
{
    return p->before ? rod_path_has_velocity(p->before) : p->acceleration == NULL;
}
double rod_path_start(const rod_path *p)
{
    return p->before ? rod_path_start(p->before) : p->time[0];
}
double rod_path_end(const rod_path *p)
{
    return p->before ? fmax(p->at, rod_path_end(p->after)) : p->time[p->rows - 1];
}

int rod_path_planar(const rod_path *p)
{
    if (p->before) return rod_path_planar(p->before) && rod_path_planar(p->after);
    for (int r = 0; r < p->rows; r++) {
        const double *v = &p->value[r * p->components];
        if (v[2] != 0.0) return 0;
        if (p->components == 6 && (v[3] != 0.0 || v[4] != 0.0)) return 0;
    }
    return 1;
}

/* Velocity and acceleration at the rows of one component (stride
 * `components`): 0 at the ends, the clamped cubic spline's inside.
 * `diag`, `rhs` are scratch (rows). */
static void row_derivatives(rod_path *p, int c, double *diag, double *rhs)
{
    const int n = p->rows, nc = p->components;
    const double *t = p->time, *y = p->value;
    double *v = p->velocity, *a = p->acceleration;
    v[c] = a[c] = 0.0;
    v[(n - 1) * nc + c] = a[(n - 1) * nc + c] = 0.0;
    if (n < 3) return;
    /* spline accelerations M_i: h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1}
     * = 6 (d_i - d_{i-1}); clamped ends (zero velocity): 2 h_0 M_0 + h_0 M_1 = 6 d_0,
     * h_{n-2} M_{n-2} + 2 h_{n-2} M_{n-1} = -6 d_{n-2}. Thomas algorithm: the
     * super-diagonal is h_i, the sub-diagonal h_{i-1}. */
#define H(i) (t[(i) + 1] - t[(i)])
#define D(i) ((y[((i) + 1) * nc + c] - y[(i) * nc + c]) / H(i))
    diag[0] = 2.0 * H(0);
    rhs[0] = 6.0 * D(0);
    for (int i = 1; i < n; i++) {
        double sub = H(i - 1);
        double b = i < n - 1 ? 2.0 * (H(i - 1) + H(i)) : 2.0 * H(n - 2);
        double r = i < n - 1 ? 6.0 * (D(i) - D(i - 1)) : -6.0 * D(n - 2);
        double f = sub / diag[i - 1]; /* super-diagonal of row i-1 is H(i-1) = sub */
        diag[i] = b - f * sub;
        rhs[i] = r - f * rhs[i - 1];
    }
    /* back substitution: M_{n-1}, then M_i = (rhs_i - h_i M_{i+1}) / diag_i; kept in rhs */
    rhs[n - 1] /= diag[n - 1];
    for (int i = n - 2; i >= 0; i--) rhs[i] = (rhs[i] - H(i) * rhs[i + 1]) / diag[i];
    for (int i = 1; i < n - 1; i++) {
        a[i * nc + c] = rhs[i];
        v[i * nc + c] = D(i) - H(i) * (2.0 * rhs[i] + rhs[i + 1]) / 6.0;
    }
#undef H
#undef D
}

/* Checks rows of `width` numbers: finite, times strictly increasing. */
static int check_rows(const double *data, int rows, int width, char *err, size_t errlen)
{
    for (int r = 0; r < rows; r++) {
        const double *row = &data[(size_t)r * (size_t)width];
        for (int k = 0; k < width; k++)
            if (!isfinite(row[k])) {
                snprintf(err, errlen, "row %d: column %d is not a finite number", r + 1, k + 1);
                return -1;
            }
        if (r > 0 && !(row[0] > row[-width])) {
            snprintf(err, errlen,
                     "row %d: time %.17g s does not increase (previous row %.17g s); times must "
                     "strictly increase", r + 1, row[0], row[-width]);
            return -1;
        }
    }
    return 0;
}

/* Bounds of a path's motion between its rows (m or rad, and their rates per
 * s and per s^2): within them every pose and the angular terms built from it
 * (r x (r x r_ddot), ~1e12^2 x 1e50) stay finite. Rows of finite numbers too
 * close in time for their change (1 m in 1e-300 s) overflow without them. */
#define PATH_MAX_VALUE 1e12
#define PATH_MAX_RATE 1e50

/* Checks that, on every interval, the value, velocity and acceleration of
 * each component are within the bounds above (bounded by the sums of the
 * magnitudes of the terms interpolate() adds, for s in [0, 1]). */
static int check_motion(const rod_path *p, char *err, size_t errlen)
{
    static const char *const names[6] = {"x", "y", "z", "rx", "ry", "rz"};
    const int nc = p->components;
    for (int i = 0; i < p->rows; i++) /* the rows as given (a one-row path is held) */
        for (int c = 0; c < nc; c++) {
            const double y = p->value[i * nc + c], v = p->velocity[i * nc + c];
            if (!(fabs(y) <= PATH_MAX_VALUE)) {
                snprintf(err, errlen, "row %d: %s = %.9g is out of range; accepted: within "
                         "%.0e (m or rad)", i + 1, names[c], y, PATH_MAX_VALUE);
                return -1;
            }
            if (!p->acceleration && !(fabs(v) <= PATH_MAX_RATE)) {
                snprintf(err, errlen, "row %d: v%s = %.9g is out of range; accepted: within "
                         "%.0e (m/s or rad/s)", i + 1, names[c], v, PATH_MAX_RATE);
                return -1;
            }
        }
    for (int i = 0; i + 1 < p->rows; i++) {
        const double h = p->time[i + 1] - p->time[i];
        for (int c = 0; c < nc; c++) {
            const double y0 = p->value[i * nc + c], y1 = p->value[(i + 1) * nc + c];
            const double v0 = p->velocity[i * nc + c], v1 = p->velocity[(i + 1) * nc + c];
            double value, rate, rate2;
            if (!p->acceleration) { /* cubic Hermite: |h00|, |h01| <= 1, |h10|, |h11| < 1 */
                value = fabs(y0) + fabs(y1) + h * (fabs(v0) + fabs(v1));
                rate = 1.5 * fabs(y1 - y0) / h + fabs(v0) + fabs(v1);
                rate2 = (6.0 * fabs(y1 - y0) / h + 4.0 * (fabs(v0) + fabs(v1))) / h;
            } else { /* the quintic of interpolate() */
                const double a0 = p->acceleration[i * nc + c];
                const double a1 = p->acceleration[(i + 1) * nc + c];
                const double A = y1 - y0 - v0 * h - 0.5 * a0 * h * h;
                const double B = (v1 - v0 - a0 * h) * h, C = (a1 - a0) * h * h;
                const double z = 0.5 * C + 6.0 * A - 3.0 * B, w = 7.0 * B - 15.0 * A - C;
                const double x = A - w - z;
                const double size = fabs(x) + fabs(w) + fabs(z);
                value = fabs(y0) + h * (fabs(v0) + 0.5 * fabs(a0) * h) + size;
                rate = fabs(v0) + fabs(a0) * h + 5.0 * size / h;
                rate2 = fabs(a0) + 20.0 * size / (h * h);
            }
            if (!(value <= PATH_MAX_VALUE && rate <= PATH_MAX_RATE && rate2 <= PATH_MAX_RATE)) {
                snprintf(err, errlen,
                         "rows %d to %d (t = %.9g to %.9g s): %s goes from %.9g to %.9g in %.3g "
                         "s, a motion out of range (bounds %.3g, %.3g /s, %.3g /s^2); accepted: "
                         "values within %.0e and rates within %.0e (m, rad, per s, per s^2)",
                         i + 1, i + 2,
                         p->time[i], p->time[i + 1], names[c], y0, y1, h, value, rate, rate2,
                         PATH_MAX_VALUE, PATH_MAX_RATE);
                return -1;
            }
        }
    }
    return 0;
}

/* An empty path with room for `capacity` rows; acceleration only when asked. */
static rod_path *path_alloc(int capacity, int columns, int with_acceleration)
{
    rod_path *p = calloc(1, sizeof *p);
    if (!p) return NULL;
    const size_t n = (size_t)capacity, nc = (size_t)columns - 1;
    p->columns = columns;
    p->components = columns - 1;
    p->time = malloc(n * sizeof(double));
    p->value = malloc(n * nc * sizeof(double));
    p->velocity = calloc(n * nc, sizeof(double));
    p->acceleration = with_acceleration ? malloc(n * nc * sizeof(double)) : NULL;
    if (!p->time || !p->value || !p->velocity || (with_acceleration && !p->acceleration)) {
        rod_path_destroy(p);
        return NULL;
    }
    return p;
}

rod_path *rod_path_copy(const rod_path *p)
{
    if (p->before) {
        rod_path *b = rod_path_copy(p->before), *a = rod_path_copy(p->after), *h = NULL;
        char why[160];
        if (a && b) h = rod_path_handover(b, p->at, a, why, sizeof why);
        if (!h) {
            rod_path_destroy(a);
            rod_path_destroy(b);
        }
        return h;
    }
    rod_path *c = path_alloc(p->rows, p->columns, p->acceleration != NULL);
    if (!c) return NULL;
    const size_t n = (size_t)p->rows, nc = (size_t)p->components;
    c->rows = p->rows;
    c->live = p->live;
    memcpy(c->time, p->time, n * sizeof(double));
    memcpy(c->value, p->value, n * nc * sizeof(double));
    memcpy(c->velocity, p->velocity, n * nc * sizeof(double));
    if (p->acceleration) memcpy(c->acceleration, p->acceleration, n * nc * sizeof(double));
    return c;
}

rod_path *rod_path_create_with_velocity(const double *data, int rows, int columns, char *err,
                                        size_t errlen)
{
    if (columns != 4 && columns != 7) {
        snprintf(err, errlen, "a path with velocities has 4 pose columns (t, x, y, z) or 7 "
                              "(t, x, y, z, rx, ry, rz), not %d", columns);
        return NULL;
    }
    if (rows < 1 || rows > PATH_MAX_ROWS) {
        snprintf(err, errlen, "a path has 1 to %d rows, not %d", PATH_MAX_ROWS, rows);
        return NULL;
    }
    const int nc = columns - 1, width = columns + nc;
    if (check_rows(data, rows, width, err, errlen)) return NULL;
    rod_path *p = path_alloc(rows, columns, 0);
    if (!p) {
        snprintf(err, errlen, "out of memory for a path of %d rows", rows);
        return NULL;
    }
    p->rows = rows;
    for (int r = 0; r < rows; r++) {
        const double *row = &data[(size_t)r * (size_t)width];
        p->time[r] = row[0];
        memcpy(&p->value[(size_t)r * (size_t)nc], row + 1, (size_t)nc * sizeof(double));
        memcpy(&p->velocity[(size_t)r * (size_t)nc], row + columns, (size_t)nc * sizeof(double));
    }
    if (check_motion(p, err, errlen)) {
        rod_path_destroy(p);
        return NULL;
    }
    return p;
}

rod_path *rod_path_create_live(int columns, const double *first_row, char *err, size_t errlen)
{
    if (columns != 4 && columns != 7) {
        snprintf(err, errlen, "a live path has 4 columns (t, x, y, z) or 7 (t, x, y, z, rx, ry, "
                              "rz), not %d", columns);
        return NULL;
    }
    if (check_rows(first_row, 1, columns, err, errlen)) return NULL;
    rod_path *p = path_alloc(LIVE_ROWS, columns, 0);
    if (!p) {
        snprintf(err, errlen, "out of memory for a live path");
        return NULL;
    }
    p->live = 1;
    p->rows = 1;
    p->time[0] = first_row[0];
    memcpy(p->value, first_row + 1, (size_t)p->components * sizeof(double));
    return p;
}

int rod_path_push(rod_path *p, const double *row, double *velocity, char *err, size_t errlen)
{
    const int nc = p->components;
    if (!p->live) {
        snprintf(err, errlen, "rows are pushed only onto a live path (rod_path_create_live)");
        return -1;
    }
    for (int k = 0; k < p->columns; k++)
        if (!isfinite(row[k])) {
            snprintf(err, errlen, "column %d is not a finite number", k + 1);
            return -1;
        }
    const double last = p->time[p->rows - 1];
    if (!(row[0] > last)) {
        snprintf(err, errlen, "time %.17g s does not increase (previous row %.17g s)", row[0],
                 last);
        return -1;
    }
    if (p->rows == LIVE_ROWS) { /* forget the oldest row: evaluation needs the last interval */
        memmove(p->time, p->time + 1, (LIVE_ROWS - 1) * sizeof(double));
        memmove(p->value, p->value + nc, (size_t)(LIVE_ROWS - 1) * (size_t)nc * sizeof(double));
        memmove(p->velocity, p->velocity + nc,
                (size_t)(LIVE_ROWS - 1) * (size_t)nc * sizeof(double));
        p->rows--;
    }
    const int r = p->rows;
    double *v = &p->velocity[r * nc], *y = &p->value[r * nc];
    p->time[r] = row[0];
    memcpy(y, row + 1, (size_t)nc * sizeof(double));
    const double h1 = p->time[r] - p->time[r - 1];
    for (int c = 0; c < nc; c++) {
        const double d1 = (y[c] - y[c - nc]) / h1;
        if (r < 2) {
            v[c] = d1; /* the second row: the first difference */
        } else {
            /* one-sided three-point difference at t_r on uneven times:
             * v = d1 + h1 (d1 - d0) / (h1 + h0), exact for a quadratic */
            const double h0 = p->time[r - 1] - p->time[r - 2];
            const double d0 = (y[c - nc] - y[c - 2 * nc]) / h0;
            v[c] = d1 + h1 * (d1 - d0) / (h1 + h0);
        }
    }
    if (velocity) memcpy(velocity, v, (size_t)nc * sizeof(double));
    p->rows++;
    return 0;
}

int rod_path_push_with_velocity(rod_path *p, const double *row, const double *velocity,
                                char *err, size_t errlen)
{
    for (int c = 0; c < p->components; c++)
        if (!isfinite(velocity[c])) {
            snprintf(err, errlen, "velocity %d is not a finite number", c + 1);
            return -1;
        }
    if (rod_path_push(p, row, NULL, err, errlen)) return -1;
    memcpy(&p->velocity[(p->rows - 1) * p->components], velocity,
           (size_t)p->components * sizeof(double));
    return 0;
}

void rod_path_pop(rod_path *p)
{
    if (p->live && p->rows > 1) p->rows--;
}

rod_path *rod_path_create(const double *data, int rows, int columns, char *err, size_t errlen)
{
    if (columns != 4 && columns != 7) {
        snprintf(err, errlen, "a path has 4 columns (t, x, y, z) or 7 (t, x, y, z, rx, ry, rz), "
                              "not %d", columns);
        return NULL;
    }
    if (rows < 1 || rows > PATH_MAX_ROWS) {
        snprintf(err, errlen, "a path has 1 to %d rows, not %d", PATH_MAX_ROWS, rows);
        return NULL;
    }
    for (int r = 0; r < rows; r++) {
        const double *row = &data[(size_t)r * (size_t)columns];
        for (int k = 0; k < columns; k++)
            if (!isfinite(row[k])) {
                snprintf(err, errlen, "row %d: column %d is not a finite number", r + 1, k + 1);
                return NULL;
            }
        if (r > 0 && !(row[0] > row[-columns])) {
            snprintf(err, errlen,
                     "row %d: time %.17g s does not increase (previous row %.17g s); times must "
                     "strictly increase", r + 1, row[0], row[-columns]);
            return NULL;
        }
    }
    rod_path *p = calloc(1, sizeof *p);
    if (!p) goto oom;
    const size_t n = (size_t)rows, nc = (size_t)columns - 1;
    p->rows = rows;
    p->columns = columns;
    p->components = columns - 1;
    p->time = malloc(n * sizeof(double));
    p->value = malloc(n * nc * sizeof(double));
    p->velocity = malloc(n * nc * sizeof(double));
    p->acceleration = malloc(n * nc * sizeof(double));
    double *diag = malloc(n * sizeof(double)), *rhs = malloc(n * sizeof(double));
    if (!p->time || !p->value || !p->velocity || !p->acceleration || !diag || !rhs) {
        free(diag);
        free(rhs);
        rod_path_destroy(p);
        goto oom;
    }
    for (size_t r = 0; r < n; r++) {
        p->time[r] = data[r * (size_t)columns];
        memcpy(&p->value[r * nc], &data[r * (size_t)columns + 1], nc * sizeof(double));
    }
    for (int c = 0; c < p->components; c++) row_derivatives(p, c, diag, rhs);
    free(diag);
    free(rhs);
    if (check_motion(p, err, errlen)) {
        rod_path_destroy(p);
        return NULL;
    }
    return p;
oom:
    snprintf(err, errlen, "out of memory for a path of %d rows", rows);
    return NULL;
}

/* Value, velocity, acceleration of every component at time t. */
static void interpolate(const rod_path *p, double t, double *value, double *velocity,
                        double *acceleration)
{
    const int n = p->rows, nc = p->components;
    if (!(t > p->time[0]) || t >= p->time[n - 1]) { /* held: at rest at the first or last row */
        int r = (t >= p->time[n - 1]) ? n - 1 : 0;
        /* exactly at the row, a given velocity (a live path's newest row, a
         * record's last); held before and after: at rest (the spline's rows
         * there have velocity 0 anyway) */
        int at_row = t == p->time[r];
        /* a time summed from steps lands on a row within rounding: with the
         * velocity given, a hair after the newest row of a live path is
         * still that row (not the rest after it) */
        if (!p->acceleration && n > 1)
            at_row = at_row || fabs(t - p->time[r]) <= 1e-9 * (p->time[n - 1] - p->time[n - 2]);
        for (int c = 0; c < nc; c++) {
            value[c] = p->value[r * nc + c];
            velocity[c] = at_row ? p->velocity[r * nc + c] : 0.0;
            acceleration[c] = 0.0;
        }
        return;
    }
    int lo = 0, hi = n - 1; /* time[lo] <= t < time[hi] */
    while (hi - lo > 1) {
        int mid = lo + (hi - lo) / 2;
        if (p->time[mid] <= t) lo = mid; else hi = mid;
    }
    const double h = p->time[lo + 1] - p->time[lo], tau = t - p->time[lo], s = tau / h;
    if (!p->acceleration) { /* velocity given: cubic Hermite on the interval */
        const double s2 = s * s, s3 = s2 * s;
        const double h00 = 2.0 * s3 - 3.0 * s2 + 1.0, h10 = s3 - 2.0 * s2 + s;
        const double h01 = -2.0 * s3 + 3.0 * s2, h11 = s3 - s2;
        const double d00 = 6.0 * s2 - 6.0 * s, d10 = 3.0 * s2 - 4.0 * s + 1.0;
        const double d11 = 3.0 * s2 - 2.0 * s;
        const double a00 = 12.0 * s - 6.0, a10 = 6.0 * s - 4.0, a11 = 6.0 * s - 2.0;
        for (int c = 0; c < nc; c++) {
            const double y0 = p->value[lo * nc + c], y1 = p->value[(lo + 1) * nc + c];
            const double v0 = p->velocity[lo * nc + c], v1 = p->velocity[(lo + 1) * nc + c];
            value[c] = h00 * y0 + h10 * h * v0 + h01 * y1 + h11 * h * v1;
            velocity[c] = (d00 * (y0 - y1)) / h + d10 * v0 + d11 * v1;
            acceleration[c] = (a00 * (y0 - y1) / h + a10 * v0 + a11 * v1) / h;
        }
        return;
    }
    for (int c = 0; c < nc; c++) {
        const double y0 = p->value[lo * nc + c], y1 = p->value[(lo + 1) * nc + c];
        const double v0 = p->velocity[lo * nc + c], v1 = p->velocity[(lo + 1) * nc + c];
        const double a0 = p->acceleration[lo * nc + c], a1 = p->acceleration[(lo + 1) * nc + c];
        /* y = y0 + v0 tau + a0 tau^2/2 + x s^3 + w s^4 + z s^5, with x, w, z from
         * y, y', y'' at tau = h (three linear conditions, solved by hand) */
        const double A = y1 - y0 - v0 * h - 0.5 * a0 * h * h;
        const double B = (v1 - v0 - a0 * h) * h;
        const double C = (a1 - a0) * h * h;
        const double z = 0.5 * C + 6.0 * A - 3.0 * B;
        const double w = 7.0 * B - 15.0 * A - C;
        const double x = A - w - z;
        const double s2 = s * s;
        value[c] = y0 + tau * (v0 + 0.5 * a0 * tau) + s2 * s * (x + s * (w + s * z));
        velocity[c] = v0 + a0 * tau + s2 * (3.0 * x + s * (4.0 * w + 5.0 * s * z)) / h;
        acceleration[c] = a0 + s * (6.0 * x + s * (12.0 * w + 20.0 * s * z)) / (h * h);
    }
}

/* b = (1 - cos x)/x^2, c = (x - sin x)/x^3 and their derivatives with
 * respect to q = x^2. Series for q < 1 (the closed forms cancel there):
 * b = sum (-q)^k/(2k+2)!, c = sum (-q)^k/(2k+3)!; 12 terms leave < 1e-22. */
static void jacobian_coefficients(double q, double *b, double *c, double *db, double *dc)
{
    if (q < 1.0) {
        double fb = 0.5, fc = 1.0 / 6.0; /* 1/(2k+2)!, 1/(2k+3)! at k = 0 */
        double power = 1.0, previous = 0.0; /* (-q)^k and (-q)^(k-1) */
        *b = *c = *db = *dc = 0.0;
        for (int k = 0; k < 12; k++) {
            *b += power * fb;
            *c += power * fc;
            *db -= k * previous * fb; /* d/dq (-q)^k = -k (-q)^(k-1) */
            *dc -= k * previous * fc;
            fb /= (double)((2 * k + 3) * (2 * k + 4));
            fc /= (double)((2 * k + 4) * (2 * k + 5));
            previous = power;
            power *= -q;
        }
        return;
    }
    double x = sqrt(q), sn = sin(x), cs = cos(x);
    *b = (1.0 - cs) / q;
    *c = (x - sn) / (q * x);
    *db = (x * sn - 2.0 * (1.0 - cs)) / (2.0 * q * q);
    *dc = ((1.0 - cs) * x - 3.0 * (x - sn)) / (2.0 * q * q * x);
}

rod_path *rod_path_handover(rod_path *before, double at, rod_path *after, char *err,
                            size_t errlen)
{
    if (!(at > rod_path_start(before)) || !isfinite(at) || rod_path_columns(before) != 7 ||
        rod_path_columns(after) != 7) {
        snprintf(err, errlen, "a handover needs two paths of poses (t,x,y,z,rx,ry,rz) and a "
                 "time after the first path's start");
        return NULL;
    }
    rod_path *p = calloc(1, sizeof *p);
    if (!p) {
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    p->columns = 7;
    p->components = 6;
    p->before = before;
    p->after = after;
    p->at = at;
    return p;
}

/* The pose of a handed-over path after its handover: A(t) carrying the
 * pose B(at) as A(at) held it. With A's rotation Ra, position a: the
 * offset d = Ra(t) Ra(at)^T (b(at) - a(at)) and rotation Ra(t) Ra(at)^T
 * Rb(at); velocity v_a + w x d, acceleration a_a + alpha x d + w x (w x d),
 * angular velocity and acceleration A's. */
static void handover_eval(const rod_path *p, double t, rod_pose *pose)
{
    rod_pose b, a0, a;
    rod_path_eval(p->before, p->at, &b);
    rod_path_eval(p->after, p->at, &a0);
    rod_path_eval(p->after, t, &a);
    double turn[9], rel[3], local[3], d[3], wd[3], wwd[3], ad[3];
    for (int i = 0; i < 3; i++) /* Ra(t) Ra(at)^T */
        for (int j = 0; j < 3; j++)
            turn[3 * i + j] = a.rotation[3 * i] * a0.rotation[3 * j] +
                              a.rotation[3 * i + 1] * a0.rotation[3 * j + 1] +
                              a.rotation[3 * i + 2] * a0.rotation[3 * j + 2];
    v3_sub(rel, b.position, a0.position);
    m3_mul_tv(local, a0.rotation, rel);
    m3_mul_v(d, a.rotation, local);
    *pose = a;
    m3_mul(pose->rotation, turn, b.rotation);
    v3_cross(wd, a.angular_velocity, d);
    v3_cross(wwd, a.angular_velocity, wd);
    v3_cross(ad, a.angular_acceleration, d);
    for (int k = 0; k < 3; k++) {
        pose->position[k] = a.position[k] + d[k];
        pose->velocity[k] = a.velocity[k] + wd[k];
        pose->acceleration[k] = a.acceleration[k] + ad[k] + wwd[k];
    }
}

void rod_path_eval(const rod_path *p, double t, rod_pose *pose)
{
    if (p->before) {
        if (t < p->at) rod_path_eval(p->before, t, pose);
        else handover_eval(p, t, pose);
        return;
    }
    double value[6], velocity[6], acceleration[6];
    interpolate(p, t, value, velocity, acceleration);
    memset(pose, 0, sizeof *pose);
    for (int k = 0; k < 3; k++) {
        pose->position[k] = value[k];
        pose->velocity[k] = velocity[k];
        pose->acceleration[k] = acceleration[k];
    }
    if (p->components < 6) {
        m3_identity(pose->rotation);
        return;
    }
    const double *r = &value[3], *rd = &velocity[3], *rdd = &acceleration[3];
    m3_exp(pose->rotation, r);
    double b, c, db, dc;
    jacobian_coefficients(v3_dot(r, r), &b, &c, &db, &dc);
    /* omega = J(r) r_dot = r_dot + b r x r_dot + c r x (r x r_dot) */
    double rxd[3], rxrxd[3];
    v3_cross(rxd, r, rd);
    v3_cross(rxrxd, r, rxd);
    for (int k = 0; k < 3; k++) pose->angular_velocity[k] = rd[k] + b * rxd[k] + c * rxrxd[k];
    /* alpha = J(r) r_ddot + dJ/dt r_dot, dJ/dt r_dot = b' r x r_dot + c' r x (r x r_dot)
     * + c r_dot x (r x r_dot), with b' = 2 (r . r_dot) db/dq (and c' likewise) */
    double rxdd[3], rxrxdd[3], dxrxd[3];
    v3_cross(rxdd, r, rdd);
    v3_cross(rxrxdd, r, rxdd);
    v3_cross(dxrxd, rd, rxd);
    const double qdot = 2.0 * v3_dot(r, rd);
    for (int k = 0; k < 3; k++)
        pose->angular_acceleration[k] = rdd[k] + b * rxdd[k] + c * rxrxdd[k] +
                                        qdot * (db * rxd[k] + dc * rxrxd[k]) + c * dxrxd[k];
}

/* CSV ------------------------------------------------------------------ */

/* Splits a data line at commas into at most `max` numbers (strtod, so "nan"
 * and "inf" parse: finiteness is checked by the caller with the column).
 * Returns the count, or -1 at a field that is not a number. */
static int split_numbers(char *line, double *values, int max)
{
    int count = 0;
    char *p = line;
    for (;;) {
        char *b = p;
        while (*p && *p != ',') p++;
        char *e = p;
        while (b < e && isspace((unsigned char)*b)) b++;
        while (e > b && isspace((unsigned char)e[-1])) e--;
        if (e == b || count == max) return -1;
        char keep = *e;
        *e = '\0';
        char *stop;
        errno = 0;
        double v = strtod(b, &stop);
        int ok = stop == e && errno != ERANGE;
        *e = keep;
        if (!ok) return -1;
        values[count++] = v;
        if (!*p) return count;
        p++; /* past the comma */
    }
}

/* The headers a path file may have: pose columns, then (with velocities)
 * their rates: vx,vy,vz (m/s) and vrx,vry,vrz (the rotation vector's rate,
 * rad/s). */
static const char *const header_names[4][13] = {
    {"t", "x", "y", "z"},
    {"t", "x", "y", "z", "rx", "ry", "rz"},
    {"t", "x", "y", "z", "vx", "vy", "vz"},
    {"t", "x", "y", "z", "rx", "ry", "rz", "vx", "vy", "vz", "vrx", "vry", "vrz"}};
static const int header_widths[4] = {4, 7, 7, 13};

/* Which of header_names the line is (blanks around the names allowed), or -1. */
static int header_kind(const char *line)
{
    const char *tokens[14];
    size_t lengths[14];
    int count = 0;
    const char *p = line;
    for (;;) {
        while (isspace((unsigned char)*p)) p++;
        const char *b = p;
        while (*p && *p != ',' && !isspace((unsigned char)*p)) p++;
        if (count == 14) return -1;
        tokens[count] = b;
        lengths[count++] = (size_t)(p - b);
        while (isspace((unsigned char)*p)) p++;
        if (!*p) break;
        if (*p != ',') return -1;
        p++;
    }
    for (int kind = 0; kind < 4; kind++) {
        if (count != header_widths[kind]) continue;
        int same = 1;
        for (int k = 0; k < count && same; k++)
            same = strlen(header_names[kind][k]) == lengths[k] &&
                   strncmp(header_names[kind][k], tokens[k], lengths[k]) == 0;
        if (same) return kind;
    }
    return -1;
}

rod_path *rod_path_load(const char *filename, char *err, size_t errlen)
{
    char *text;
    if (textfile_read(filename, "path", PATH_MAX_BYTES, &text, NULL, err, errlen)) return NULL;
    rod_path *path = rod_path_parse(filename, text, err, errlen);
    free(text);
    return path;
}

rod_path *rod_path_parse(const char *filename, const char *text, char *err, size_t errlen)
{
    static const char header_help[] = "expected the header t,x,y,z or t,x,y,z,rx,ry,rz (time s, "
                                      "position m, rotation vector rad), or with velocities "
                                      "t,x,y,z,vx,vy,vz or t,x,y,z,rx,ry,rz,vx,vy,vz,vrx,vry,vrz "
                                      "(m/s, rad/s; a rodsim live record)";
    char line[1024];
    int line_no = 0, columns = 0, kind = -1, rows = 0, capacity = 0;
    double *data = NULL;
    rod_path *path = NULL;
    char *start;
    int got;
    const char *cursor = text;
    while ((got = textline_next(&cursor, filename, line, sizeof line, &line_no, &start, err,
                                errlen))) {
        if (got < 0) goto done;
        if (columns == 0) {
            if ((kind = header_kind(start)) < 0) {
                snprintf(err, errlen, "%s:%d: %s", filename, line_no, header_help);
                goto done;
            }
            columns = header_widths[kind];
            continue;
        }
        double values[14];
        int count = split_numbers(start, values, 14);
        if (count != columns) {
            char names[64] = "";
            for (int k = 0; k < columns; k++) {
                if (k) strcat(names, ",");
                strcat(names, header_names[kind][k]);
            }
            snprintf(err, errlen, "%s:%d: expected %d numbers separated by commas (%s), as the "
                     "header says", filename, line_no, columns, names);
            goto done;
        }
        for (int k = 0; k < count; k++)
            if (!isfinite(values[k])) {
                snprintf(err, errlen, "%s:%d: %s is not a finite number", filename, line_no,
                         header_names[kind][k]);
                goto done;
            }
        if (rows > 0 && !(values[0] > data[(size_t)(rows - 1) * (size_t)columns])) {
            snprintf(err, errlen, "%s:%d: time %.17g s does not increase (previous row %.17g s); "
                     "times must strictly increase", filename, line_no, values[0],
                     data[(size_t)(rows - 1) * (size_t)columns]);
            goto done;
        }
        if (rows == PATH_MAX_ROWS) {
            snprintf(err, errlen, "%s:%d: more than %d rows: a path is at most %d rows",
                     filename, line_no, PATH_MAX_ROWS, PATH_MAX_ROWS);
            goto done;
        }
        if (rows == capacity) {
            capacity = capacity ? 2 * capacity : 64;
            if (capacity > PATH_MAX_ROWS) capacity = PATH_MAX_ROWS;
            double *bigger = realloc(data, (size_t)capacity * (size_t)columns * sizeof *bigger);
            if (!bigger) {
                snprintf(err, errlen, "%s:%d: out of memory", filename, line_no);
                goto done;
            }
            data = bigger;
        }
        memcpy(&data[(size_t)rows * (size_t)columns], values, (size_t)columns * sizeof *values);
        rows++;
    }
    if (columns == 0) {
        snprintf(err, errlen, "%s:%d: empty path: %s, then rows", filename,
                 line_no > 0 ? line_no : 1, header_help);
        goto done;
    }
    if (rows == 0) {
        snprintf(err, errlen, "%s:%d: no rows after the header: at least one row of %d "
                 "numbers", filename, line_no, columns);
        goto done;
    }
    char why[256];
    path = kind >= 2 ? rod_path_create_with_velocity(data, rows, kind == 2 ? 4 : 7, why, sizeof why)
                     : rod_path_create(data, rows, columns, why, sizeof why);
    if (!path) snprintf(err, errlen, "%s: %s", filename, why);
done:
    free(data);
    return path;
}

int rod_path_live_save(const rod_path *p, double *out)
{
    const int nc = p->components;
    int k = 0;
    out[k++] = p->rows;
    for (int r = 0; r < p->rows; r++) {
        out[k++] = p->time[r];
        for (int c = 0; c < nc; c++) out[k++] = p->value[r * nc + c];
        for (int c = 0; c < nc; c++) out[k++] = p->velocity[r * nc + c];
    }
    return k;
}

int rod_path_live_restore(rod_path *p, const double *in, int count)
{
    const int nc = p->components;
    if (!p->live || count < 1) return -1;
    const double rows = in[0];
    if (!(rows >= 1 && rows <= LIVE_ROWS) || count != 1 + (int)rows * (1 + 2 * nc)) return -1;
    p->rows = (int)rows;
    int k = 1;
    for (int r = 0; r < p->rows; r++) {
        p->time[r] = in[k++];
        for (int c = 0; c < nc; c++) p->value[r * nc + c] = in[k++];
        for (int c = 0; c < nc; c++) p->velocity[r * nc + c] = in[k++];
    }
    return 0;
}
