/* test_path.c: driven-end paths (sim/path.h). The interpolant passes every
 * row exactly; its velocity and acceleration agree with finite differences of
 * its own position, are continuous at the rows (left and right limits) and
 * zero at the first row and after the last; a path sampled from a known
 * smooth motion reproduces that motion's velocity and acceleration with an
 * error that shrinks as the rows get denser; the angular velocity against
 * the exact one of a fixed-axis rotation and against a finite difference of
 * R(t); bad CSV files give file:line. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/vec3.h"
#include "sim/path.h"
#include "test.h"

/* Rows of an irregular 7-column path: uneven times, a wandering position and
 * a rotation vector that passes |r| = 1 (the series/closed-form switch). */
#define ROWS 9
static void sample_rows(double *data)
{
    double t = 0.25;
    for (int r = 0; r < ROWS; r++) {
        double *row = &data[7 * r];
        row[0] = t;
        row[1] = 0.1 * sin(1.3 * r) + 0.02 * r;
        row[2] = 0.05 * cos(0.7 * r * r);
        row[3] = -0.03 * r;
        row[4] = 0.4 * sin(0.9 * r);
        row[5] = 0.3 * r - 0.5;
        row[6] = 0.2 * cos(1.7 * r);
        t += 0.1 + 0.07 * (r % 3); /* uneven spacing */
    }
}

static double pose_component(const rod_pose *p, int which, int k)
{
    switch (which) {
    case 0: return p->position[k];
    case 1: return p->velocity[k];
    case 2: return p->acceleration[k];
    case 3: return p->angular_velocity[k];
    default: return p->angular_acceleration[k];
    }
}

static void test_rows_exact(void)
{
    double data[7 * ROWS];
    sample_rows(data);
    char err[256] = "";
    rod_path *p = rod_path_create(data, ROWS, 7, err, sizeof err);
    if (!check(p != NULL, "7-column path of %d rows created (%s)", ROWS, err)) return;
    check(rod_path_columns(p) == 7 && rod_path_start(p) == data[0] &&
              rod_path_end(p) == data[7 * (ROWS - 1)],
          "columns 7, start %g s, end %g s", rod_path_start(p), rod_path_end(p));
    int exact = 1;
    double worst_rotation = 0.0;
    for (int r = 0; r < ROWS; r++) {
        rod_pose pose;
        rod_path_eval(p, data[7 * r], &pose);
        for (int k = 0; k < 3; k++) exact = exact && pose.position[k] == data[7 * r + 1 + k];
        double expect[9];
        m3_exp(expect, &data[7 * r + 4]);
        for (int k = 0; k < 9; k++)
            worst_rotation = fmax(worst_rotation, fabs(pose.rotation[k] - expect[k]));
    }
    check(exact && worst_rotation == 0.0,
          "every row is passed exactly: position bit for bit, rotation exp([r]x) (largest "
          "difference %.1e)", worst_rotation);
    rod_path_destroy(p);

    /* one row: a constant pose */
    p = rod_path_create(data, 1, 4, err, sizeof err);
    if (check(p != NULL, "a 1-row path is a constant pose (%s)", err)) {
        rod_pose pose;
        rod_path_eval(p, 7.0, &pose);
        check(pose.position[1] == data[2] && pose.velocity[0] == 0.0 &&
                  pose.rotation[0] == 1.0 && pose.rotation[1] == 0.0,
              "1 row: position %g, at rest, identity rotation", pose.position[1]);
        rod_path_destroy(p);
    }
}

/* Derivatives against central differences of the interpolant itself inside
 * each interval, and left/right limits at every row. */
static void test_continuity(void)
{
    double data[7 * ROWS];
    sample_rows(data);
    char err[256] = "";
    rod_path *p = rod_path_create(data, ROWS, 7, err, sizeof err);
    if (!p) return;
    /* inside intervals: velocity = d position/dt, acceleration = d velocity/dt, alpha = d omega/dt */
    double worst[3] = {0, 0, 0};
    const double h = 1e-6;
    for (int r = 0; r + 1 < ROWS; r++)
        for (int j = 1; j < 4; j++) {
            double t = data[7 * r] + j * 0.25 * (data[7 * (r + 1)] - data[7 * r]);
            rod_pose a, b, c;
            rod_path_eval(p, t - h, &a);
            rod_path_eval(p, t, &b);
            rod_path_eval(p, t + h, &c);
            for (int k = 0; k < 3; k++) {
                double fd_v = (c.position[k] - a.position[k]) / (2 * h);
                double fd_a = (c.velocity[k] - a.velocity[k]) / (2 * h);
                double fd_al = (c.angular_velocity[k] - a.angular_velocity[k]) / (2 * h);
                worst[0] = fmax(worst[0], fabs(fd_v - b.velocity[k]) / (1 + fabs(b.velocity[k])));
                worst[1] = fmax(worst[1], fabs(fd_a - b.acceleration[k]) / (1 + fabs(b.acceleration[k])));
                worst[2] = fmax(worst[2], fabs(fd_al - b.angular_acceleration[k]) /
                                              (1 + fabs(b.angular_acceleration[k])));
            }
        }
    check(worst[0] < 1e-8 && worst[1] < 1e-7 && worst[2] < 1e-7,
          "inside intervals: velocity, acceleration and angular acceleration equal central "
          "differences (h = 1e-6 s) of position, velocity and omega: largest errors %.1e %.1e "
          "%.1e (tolerance 1e-8, 1e-7, 1e-7)", worst[0], worst[1], worst[2]);

    /* at the rows: left and right limits of velocity, acceleration, omega, alpha agree
     * to O(eps) (jerk eps); and the one-sided differences of position match */
    const double eps = 1e-9;
    double jump[5] = {0, 0, 0, 0, 0}, one_sided = 0.0;
    for (int r = 1; r + 1 < ROWS; r++) {
        double t = data[7 * r];
        rod_pose left, right, at, left_far, right_far;
        rod_path_eval(p, t - eps, &left);
        rod_path_eval(p, t + eps, &right);
        rod_path_eval(p, t, &at);
        rod_path_eval(p, t - 1e-5, &left_far);
        rod_path_eval(p, t + 1e-5, &right_far);
        for (int w = 0; w < 5; w++)
            for (int k = 0; k < 3; k++)
                jump[w] = fmax(jump[w], fabs(pose_component(&left, w, k) - pose_component(&right, w, k)));
        /* left difference = v - a h/2, right = v + a h/2, to O(h^2): their mean is v */
        for (int k = 0; k < 3; k++) {
            double dl = (at.position[k] - left_far.position[k]) / 1e-5;
            double dr = (right_far.position[k] - at.position[k]) / 1e-5;
            one_sided = fmax(one_sided, fabs(0.5 * (dl + dr) - at.velocity[k]));
            one_sided = fmax(one_sided, fabs((dr - dl) / 1e-5 - at.acceleration[k]) * 1e-4);
        }
    }
    check(jump[1] < 1e-6 && jump[2] < 1e-5 && jump[3] < 1e-6 && jump[4] < 1e-5,
          "at every inner row: left and right limits (1e-9 s either side) of velocity %.1e, "
          "acceleration %.1e, omega %.1e, alpha %.1e (a jump would be O(1))",
          jump[1], jump[2], jump[3], jump[4]);
    check(one_sided < 1e-6,
          "at every inner row: one-sided differences of position from the left and the right "
          "give the same velocity and acceleration (largest mismatch %.1e)", one_sided);

    /* at rest at the first row and after the last, and continuously so */
    rod_pose pose;
    double t0 = data[0], t1 = data[7 * (ROWS - 1)];
    double at_rest = 0.0;
    const double times[] = {t0 - 1.0, t0, t1, t1 + 1e-12, t1 + 5.0};
    for (int i = 0; i < 5; i++) {
        rod_path_eval(p, times[i], &pose);
        for (int w = 1; w < 5; w++)
            for (int k = 0; k < 3; k++) at_rest = fmax(at_rest, fabs(pose_component(&pose, w, k)));
    }
    check(at_rest == 0.0, "before the first row, at it, at the last and after: velocity, "
                          "acceleration, omega, alpha all exactly 0");
    /* acceleration grows from 0 linearly (the jerk is finite): the largest velocity or
     * acceleration 1e-7 s and 1e-8 s inside either end shrinks with the distance */
    double near[2] = {0.0, 0.0};
    for (int j = 0; j < 2; j++) {
        double d = j ? 1e-8 : 1e-7;
        rod_path_eval(p, t0 + d, &pose);
        for (int w = 1; w < 5; w++)
            for (int k = 0; k < 3; k++) near[j] = fmax(near[j], fabs(pose_component(&pose, w, k)));
        rod_path_eval(p, t1 - d, &pose);
        for (int w = 1; w < 5; w++)
            for (int k = 0; k < 3; k++) near[j] = fmax(near[j], fabs(pose_component(&pose, w, k)));
    }
    check(near[0] < 1e-2 && near[1] < 0.15 * near[0],
          "1e-7 s and 1e-8 s inside the first and last rows: largest velocity or acceleration "
          "%.2e, %.2e (-> 0 linearly: no jump at the ends)", near[0], near[1]);
    rod_path_destroy(p);
}

/* x(t) = sin^3 t on [0, pi] starts and ends at rest (x' = x'' = 0 at both
 * ends): its exact velocity and acceleration are the reference. */
static void test_convergence(void)
{
    double previous_v = 0.0, previous_a = 0.0;
    int shrinking = 1;
    double last_v = 0.0, last_a = 0.0;
    for (int rows = 11; rows <= 161; rows = 2 * rows - 1) {
        double *data = malloc((size_t)rows * 4 * sizeof(double));
        for (int r = 0; r < rows; r++) {
            double t = M_PI * r / (rows - 1), s = sin(t);
            data[4 * r] = t;
            data[4 * r + 1] = s * s * s;
            data[4 * r + 2] = data[4 * r + 3] = 0.0;
        }
        char err[256];
        rod_path *p = rod_path_create(data, rows, 4, err, sizeof err);
        free(data);
        if (!p) return;
        double err_v = 0.0, err_a = 0.0;
        for (int i = 0; i <= 2000; i++) {
            double t = M_PI * i / 2000.0, s = sin(t), c = cos(t);
            rod_pose pose;
            rod_path_eval(p, t, &pose);
            err_v = fmax(err_v, fabs(pose.velocity[0] - 3 * s * s * c));
            err_a = fmax(err_a, fabs(pose.acceleration[0] - (6 * s * c * c - 3 * s * s * s)));
        }
        rod_path_destroy(p);
        /* relative to the largest |x'| = 2/sqrt(3) and |x''| = 3 */
        printf("    x = sin^3 t, %3d rows: velocity error %.3e (relative %.2e), acceleration "
               "error %.3e (relative %.2e)\n", rows, err_v, err_v / 1.1547, err_a, err_a / 3.0);
        if (previous_v > 0.0 && !(err_v < previous_v / 3.0 && err_a < previous_a / 2.0)) shrinking = 0;
        previous_v = err_v;
        previous_a = err_a;
        last_v = err_v;
        last_a = err_a;
    }
    check(shrinking && last_v < 1e-5 && last_a < 1e-3,
          "sin^3 t sampled at 11..161 rows: velocity error shrinks at least 3x and acceleration "
          "error at least 2x per halving of the spacing; at 161 rows %.2e m/s and %.2e m/s^2 "
          "(reference: the exact derivatives)", last_v, last_a);
}

static void test_rotation(void)
{
    /* rotation about a fixed axis n: r = theta(t) n, omega = theta_dot n exactly; the x
     * column carries theta itself, so its velocity is theta_dot from the same interpolation */
    const double n[3] = {2.0 / 7.0, 3.0 / 7.0, 6.0 / 7.0}; /* unit */
    double data[7 * 6];
    for (int r = 0; r < 6; r++) {
        double theta = 0.8 * r + 0.1 * r * r; /* past pi at the end */
        double *row = &data[7 * r];
        row[0] = 0.5 * r;
        row[1] = theta;
        row[2] = row[3] = 0.0;
        for (int k = 0; k < 3; k++) row[4 + k] = theta * n[k];
    }
    char err[256];
    rod_path *p = rod_path_create(data, 6, 7, err, sizeof err);
    if (!p) return;
    double worst_w = 0.0, worst_a = 0.0;
    for (int i = 0; i <= 100; i++) {
        rod_pose pose;
        rod_path_eval(p, 2.5 * i / 100.0, &pose);
        for (int k = 0; k < 3; k++) {
            worst_w = fmax(worst_w, fabs(pose.angular_velocity[k] - pose.velocity[0] * n[k]));
            worst_a = fmax(worst_a, fabs(pose.angular_acceleration[k] - pose.acceleration[0] * n[k]));
        }
    }
    check(worst_w < 1e-14 && worst_a < 1e-13,
          "fixed axis: omega = theta_dot n (largest difference %.1e rad/s), alpha = theta_ddot n "
          "(%.1e rad/s^2)", worst_w, worst_a);
    rod_path_destroy(p);

    /* r = (0, 0, w t) between rows: omega = (0, 0, r_z dot) with no x, y part, exactly */
    double spin[7 * 3] = {0, 0, 0, 0, 0, 0, 0,  1, 1, 0, 0, 0, 0, 2.0,  2, 2, 0, 0, 0, 0, 4.0};
    p = rod_path_create(spin, 3, 7, err, sizeof err);
    if (p) {
        rod_pose pose;
        rod_path_eval(p, 1.0, &pose);
        check(pose.angular_velocity[0] == 0.0 && pose.angular_velocity[1] == 0.0 &&
                  pose.angular_velocity[2] == 2.0 * pose.velocity[0],
              "r = (0, 0, 2 t) at the middle row: omega = (%g, %g, %g), (0, 0, 2 x_dot = %g) exactly",
              pose.angular_velocity[0], pose.angular_velocity[1], pose.angular_velocity[2],
              2.0 * pose.velocity[0]);
        rod_path_destroy(p);
    }

    /* a general rotation: omega against finite differences of R(t):
     * [omega]x = dR/dt R^T (global), R^T dR/dt = [R^T omega]x (body) */
    double data2[7 * ROWS];
    sample_rows(data2);
    p = rod_path_create(data2, ROWS, 7, err, sizeof err);
    if (!p) return;
    /* fourth-order central differences, h = 1e-4 s: truncation h^4 f^(5)/30, round-off
     * 1e-16/h, both below 1e-10 here */
    const double h = 1e-4;
    double worst_global = 0.0, worst_body = 0.0, worst_alpha = 0.0, scale = 0.0, scale_alpha = 0.0;
    for (int i = 1; i < 40; i++) {
        double t = data2[0] + (data2[7 * (ROWS - 1)] - data2[0]) * i / 40.0;
        rod_pose a2, a, b, c, c2;
        rod_path_eval(p, t - 2 * h, &a2);
        rod_path_eval(p, t - h, &a);
        rod_path_eval(p, t, &b);
        rod_path_eval(p, t + h, &c);
        rod_path_eval(p, t + 2 * h, &c2);
        double dr[9], spatial[9], body[9], wb[3];
        for (int k = 0; k < 9; k++)
            dr[k] = (8.0 * (c.rotation[k] - a.rotation[k]) - (c2.rotation[k] - a2.rotation[k])) /
                    (12.0 * h);
        /* spatial = dR R^T */
        for (int r = 0; r < 3; r++)
            for (int col = 0; col < 3; col++) {
                double sum = 0.0;
                for (int k = 0; k < 3; k++) sum += dr[3 * r + k] * b.rotation[3 * col + k];
                spatial[3 * r + col] = sum;
            }
        m3_mul_tn(body, b.rotation, dr);
        m3_mul_tv(wb, b.rotation, b.angular_velocity);
        /* skew parts: (m[7] - m[5]) / 2, (m[2] - m[6]) / 2, (m[3] - m[1]) / 2 */
        double ws[3] = {0.5 * (spatial[7] - spatial[5]), 0.5 * (spatial[2] - spatial[6]),
                        0.5 * (spatial[3] - spatial[1])};
        double wbd[3] = {0.5 * (body[7] - body[5]), 0.5 * (body[2] - body[6]),
                         0.5 * (body[3] - body[1])};
        for (int k = 0; k < 3; k++) {
            double alpha = (8.0 * (c.angular_velocity[k] - a.angular_velocity[k]) -
                            (c2.angular_velocity[k] - a2.angular_velocity[k])) / (12.0 * h);
            worst_global = fmax(worst_global, fabs(ws[k] - b.angular_velocity[k]));
            worst_body = fmax(worst_body, fabs(wbd[k] - wb[k]));
            worst_alpha = fmax(worst_alpha, fabs(alpha - b.angular_acceleration[k]));
            scale = fmax(scale, fabs(b.angular_velocity[k]));
            scale_alpha = fmax(scale_alpha, fabs(b.angular_acceleration[k]));
        }
    }
    printf("    general rotation: |omega| up to %.3f rad/s, |alpha| up to %.3f rad/s^2; "
           "finite-difference mismatch global %.2e, body %.2e rad/s, alpha %.2e rad/s^2\n",
           scale, scale_alpha, worst_global, worst_body, worst_alpha);
    check(worst_global < 1e-9 * scale && worst_body < 1e-9 * scale,
          "general rotation: omega (global) equals the skew part of dR/dt R^T and R^T omega that "
          "of R^T dR/dt (fourth-order differences, h = 1e-4 s): relative %.1e (tolerance 1e-9)",
          fmax(worst_global, worst_body) / scale);
    check(worst_alpha < 1e-9 * scale_alpha,
          "general rotation: alpha equals d omega/dt (fourth-order differences): relative %.1e "
          "(tolerance 1e-9)", worst_alpha / scale_alpha);
    rod_path_destroy(p);
}

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

static void expect_load_error(const char *dir, const char *name, const char *text,
                              const char *needle1, const char *needle2)
{
    char path[512], err[512] = "", want[600];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    write_file(path, text);
    snprintf(want, sizeof want, "%s:%s", name, needle1);
    rod_path *p = rod_path_load(path, err, sizeof err);
    check(p == NULL && strstr(err, want) && strstr(err, needle2), "%s: '%s' names '%s' and '%s'",
          name, err, want, needle2);
    rod_path_destroy(p);
    unlink(path);
}

static void test_csv(void)
{
    char dir[] = "/tmp/rodsim_path_XXXXXX";
    if (!check(mkdtemp(dir) != NULL, "temporary directory")) return;
    char path[512], err[512] = "";
    snprintf(path, sizeof path, "%s/good.csv", dir);
    write_file(path, "# a needle holder\nt, x, y, z, rx, ry, rz\n0,1,0,0,0,0,0\n\n0.5,1,0,0.1,0,0,0.3 "
                     "# lift and turn\n1.5,1.2,0,0.1,0,0,0.3\n");
    rod_path *p = rod_path_load(path, err, sizeof err);
    if (check(p != NULL && rod_path_columns(p) == 7 && rod_path_end(p) == 1.5,
              "CSV with comments, blanks and spaces: 7 columns, end 1.5 s (%s)", err)) {
        rod_pose pose;
        rod_path_eval(p, 0.5, &pose);
        check(pose.position[2] == 0.1, "row 2 read: z = %g at t = 0.5 s", pose.position[2]);
        rod_path_destroy(p);
    }
    unlink(path);
    snprintf(path, sizeof path, "%s/four.csv", dir);
    write_file(path, "t,x,y,z\n0,0,0,0\n1,0,0,1\n");
    p = rod_path_load(path, err, sizeof err);
    check(p != NULL && rod_path_columns(p) == 4 && rod_path_planar(p) == 0,
          "4-column path reads; it leaves the x-y plane (%s)", err);
    rod_path_destroy(p);
    unlink(path);

    expect_load_error(dir, "back.csv", "t,x,y,z\n0,0,0,0\n1,0,0,1\n1,0,0,2\n", "4:", "increase");
    expect_load_error(dir, "nan.csv", "t,x,y,z,rx,ry,rz\n0,0,0,0,0,0,0\n1,0,0,0,nan,0,0\n", "3:",
                      "rx is not a finite number");
    expect_load_error(dir, "inf.csv", "t,x,y,z\n0,0,0,0\n1,0,inf,0\n", "3:", "y is not a finite");
    expect_load_error(dir, "width.csv", "t,x,y,z\n0,0,0,0\n1,0,0\n", "3:", "expected 4 numbers");
    expect_load_error(dir, "seven.csv", "t,x,y,z\n0,0,0,0,0,0,0\n", "2:", "t,x,y,z");
    expect_load_error(dir, "header.csv", "time,x,y,z\n0,0,0,0\n", "1:", "header t,x,y,z");
    expect_load_error(dir, "word.csv", "t,x,y,z\n0,zero,0,0\n", "2:", "numbers");
    expect_load_error(dir, "empty.csv", "# nothing\n", "1:", "empty path");
    expect_load_error(dir, "norows.csv", "t,x,y,z\n", "1:", "no rows");
    snprintf(path, sizeof path, "%s/missing.csv", dir);
    p = rod_path_load(path, err, sizeof err);
    check(p == NULL && strstr(err, "missing.csv") && strstr(err, "cannot open"), "missing file: '%s'",
          err);

    /* not path files: refused before a byte is read (/dev/zero never ends:
     * the reader hung there); a file over 512 MiB by its size (sparse here) */
    p = rod_path_load("/dev/zero", err, sizeof err);
    check(p == NULL && strstr(err, "/dev/zero: a character device, not a path file") &&
              strstr(err, "at most 512 MiB (536870912 bytes)"),
          "/dev/zero: '%s'", err);
    p = rod_path_load(dir, err, sizeof err);
    check(p == NULL && strstr(err, "a directory, not a path file"), "a directory: '%s'", err);
    snprintf(path, sizeof path, "%s/sparse.csv", dir);
    FILE *sparse = fopen(path, "w");
    if (sparse) {
        int grown = ftruncate(fileno(sparse), ((off_t)512 << 20) + 1) == 0;
        fclose(sparse);
        p = rod_path_load(path, err, sizeof err);
        check(grown && p == NULL && strstr(err, "sparse.csv: the path file is 536870913 bytes"),
              "a path one byte over 512 MiB: '%s'", err);
        unlink(path);
    }
    /* from memory: a byte-order mark before the header (a spreadsheet's CSV) */
    err[0] = '\0';
    p = rod_path_parse("mem.csv", "\xEF\xBB\xBFt,x,y,z\r\n0,0,0,0\r\n1,0,0,1\r\n", err, sizeof err);
    check(p != NULL && rod_path_columns(p) == 4 && rod_path_end(p) == 1.0,
          "a path parsed from memory, with a byte-order mark and CR LF (%s)", err);
    rod_path_destroy(p);
    p = rod_path_parse("mem.csv", "t,x,y,z\n0,0,0\n", err, sizeof err);
    check(p == NULL && strstr(err, "mem.csv:2: expected 4 numbers"),
          "a short row from memory, named by the given name: '%s'", err);

    /* finite rows whose motion overflows (1 m in 1e-300 s: the velocity was
     * inf, the acceleration NaN), or out of range: refused, naming the rows */
    p = rod_path_parse("fast.csv", "t,x,y,z\n0,0,0,0\n1e-300,1,0,0\n1,2,0,0\n", err, sizeof err);
    check(p == NULL && strstr(err, "fast.csv: rows 1 to 2 (t = 0 to 1e-300 s): x goes from 0 "
                                   "to 1 in 1e-300 s, a motion out of range") &&
              strstr(err, "accepted: values within 1e+12 and rates within 1e+50"),
          "a motion that overflows: '%s'", err);
    p = rod_path_parse("far.csv", "t,x,y,z\n0,0,0,0\n1,0,1e300,0\n", err, sizeof err);
    check(p == NULL && strstr(err, "far.csv: row 2: y = 1e+300 is out of range"),
          "a position out of range: '%s'", err);
    p = rod_path_parse("fast.csv", "t,x,y,z,vx,vy,vz\n0,0,0,0,1e300,0,0\n", err, sizeof err);
    check(p == NULL && strstr(err, "fast.csv: row 1: vx = 1e+300 is out of range"),
          "a one-row path with a velocity out of range: '%s'", err);
    err[0] = '\0';
    p = rod_path_parse("quick.csv", "t,x,y,z,rx,ry,rz\n0,0,0,0,0,0,0\n1e-6,1e-3,0,0,0,0,1e-3\n",
                       err, sizeof err);
    check(p != NULL, "1 mm and 1 mrad in 1 us (a fast but finite motion) read (%s)", err);
    rod_path_destroy(p);

    /* more rows than the bound: refused at the first row past it */
    snprintf(path, sizeof path, "%s/huge.csv", dir);
    FILE *f = fopen(path, "w");
    if (f) {
        fputs("t,x,y,z\n", f);
        for (int r = 0; r <= 1000000; r++) fprintf(f, "%d,0,0,0\n", r);
        fclose(f);
        p = rod_path_load(path, err, sizeof err);
        check(p == NULL && strstr(err, "huge.csv:1000002:") && strstr(err, "1000000 rows"),
              "1000001 rows: '%s'", err);
        rod_path_destroy(p);
        unlink(path);
    }

    /* rod_path_create names the row */
    double back[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    p = rod_path_create(back, 2, 4, err, sizeof err);
    check(p == NULL && strstr(err, "row 2") && strstr(err, "increase"), "create: '%s'", err);
    p = rod_path_create(back, 2, 5, err, sizeof err);
    check(p == NULL && strstr(err, "4 columns"), "create, 5 columns: '%s'", err);
    rmdir(dir);
}


/* Live paths: the pushed velocity is the one-sided three-point
 * difference, exact for a quadratic on uneven times; the interpolant passes
 * the rows and their velocities; a velocity-given path made from the same
 * rows and velocities evaluates identically (the record replays); pop. */
static void test_live(void)
{
    char err[256] = "";
    const double first[4] = {0.0, 0.0, 0.0, 0.0};
    rod_path *p = rod_path_create_live(4, first, err, sizeof err);
    if (!check(p != NULL, "live path created (%s)", err)) return;
    /* x = 3 t^2 - t, uneven times: velocity 6 t - 1 exactly from the third row */
    const double times[5] = {0.1, 0.25, 0.3, 0.45, 0.5};
    double rec[6 * 7] = {0.0}; /* t,x,y,z,vx,vy,vz rows, first the start at rest */
    double worst = 0.0;
    for (int i = 0; i < 5; i++) {
        double t = times[i], row[4] = {t, 3 * t * t - t, 0.0, 0.0}, v[3];
        if (rod_path_push(p, row, v, err, sizeof err)) break;
        if (i >= 1) worst = fmax(worst, fabs(v[0] - (6 * t - 1)));
        memcpy(&rec[7 * (i + 1)], row, sizeof row);
        memcpy(&rec[7 * (i + 1) + 4], v, sizeof v);
    }
    check(worst < 1e-12, "three-point velocity exact for a quadratic on uneven times (largest "
          "error %.1e)", worst);
    rod_pose a, b;
    rod_path_eval(p, 0.5, &a);
    check(a.position[0] == 3 * 0.25 - 0.5 && fabs(a.velocity[0] - 2.0) < 1e-12,
          "at the newest row: its position and velocity (%g, %g)", a.position[0], a.velocity[0]);
    rod_path *replay = rod_path_create_with_velocity(rec, 6, 4, err, sizeof err);
    if (check(replay != NULL, "velocity-given path from the same rows (%s)", err)) {
        double diff = 0.0;
        for (double t = 0.3; t <= 0.5; t += 0.01) {
            rod_path_eval(p, t, &a);
            rod_path_eval(replay, t, &b);
            diff = fmax(diff, fabs(a.position[0] - b.position[0]) +
                                  fabs(a.velocity[0] - b.velocity[0]));
        }
        /* a cubic Hermite through a quadratic's values and exact slopes is that quadratic */
        rod_path_eval(replay, 0.4, &b);
        check(diff == 0.0 && fabs(b.position[0] - (3 * 0.16 - 0.4)) < 1e-14 &&
                  fabs(b.velocity[0] - (6 * 0.4 - 1)) < 1e-13,
              "live and replayed evaluate identically (%.1e); between rows the quadratic: "
              "x(0.4) = %.15g (reference %.15g)", diff, b.position[0], 3 * 0.16 - 0.4);
        rod_path_destroy(replay);
    }
    double back[4] = {0.5, 0, 0, 0};
    check(rod_path_push(p, back, NULL, err, sizeof err) == -1 && strstr(err, "does not increase"),
          "a row whose time does not increase is refused: %s", err);
    double next[4] = {0.6, 1.0, 0, 0};
    rod_path_push(p, next, NULL, err, sizeof err);
    rod_path_pop(p);
    rod_path_eval(p, 0.55, &a);
    check(a.position[0] == 3 * 0.25 - 0.5 && a.velocity[0] == 0.0,
          "after pop the newest row is again t = 0.5, held after it");
    rod_path_destroy(p);
}

int main(void)
{
    test_rows_exact();
    test_continuity();
    test_convergence();
    test_rotation();
    test_csv();
    test_live();
    return test_finish();
}
