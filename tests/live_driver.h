/* live_driver.h: plays a needle-holder path into `rodsim live` through pipes
 * at a fixed rate, paced by the wall clock, and measures the latency from
 * writing each line to reading its answer. Header-only: the example driver
 * (tests/live_driver.c) and the bench (tests/bench/bench_live.c) share it.
 *
 * The path: the tip of a thread hanging from a clamped, driven tip starts
 * at `start` and, after a smooth start (a ramp over 0.2 s), draws a loop
 * 2 cm across while turning 0.2 rad about its own axis: a needle holder
 * pulling a suture through a stitch. */
#ifndef RODSIM_LIVE_DRIVER_H
#define RODSIM_LIVE_DRIVER_H

#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

typedef struct live_driver_result {
    long lines, answered, failed;  /* written, answered, answered "failed" */
    long late;                     /* answers later than one period after their line */
    double p50, p99, p999, max;    /* s, latency write -> answer */
    double fx, fy, fz;             /* N, the last answer's force */
} live_driver_result;

static inline double live_driver_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static inline int live_driver_compare(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The path at time t, s: tip position (m) and rotation vector (rad). */
static inline void live_driver_pose(double t, const double start[3], double pos[3], double rot[3])
{
    double a = t < 0.2 ? (t / 0.2) * (t / 0.2) * (3.0 - 2.0 * t / 0.2) : 1.0; /* smooth start */
    pos[0] = start[0] + 0.01 * a * sin(2.0 * M_PI * t);
    pos[1] = start[1] + 0.01 * a * (1.0 - cos(2.0 * M_PI * t));
    pos[2] = start[2] + 0.005 * a * sin(M_PI * t);
    rot[0] = rot[1] = 0.0;
    rot[2] = 0.2 * a * sin(M_PI * t);
}

/* A path: the tip's position (m) and rotation vector (rad) at t (s) from
 * `start`, as live_driver_pose. */
typedef void (*live_driver_path)(double t, const double start[3], double pos[3], double rot[3]);

/* Runs `rodsim live` (argv: rodsim's path, "live", scene, options...,
 * NULL) for `seconds` at `rate` lines per second along `path`, lines of
 * t,x,y,z (columns 4: a pinned tip) or t,x,y,z,rx,ry,rz (7); its stderr
 * goes to `stderr_path` (NULL: inherited). 0, or -1 when it could not run. */
static inline int live_driver_play_path(char *const *argv, live_driver_path path, int columns,
                                        const double start[3], double seconds, double rate,
                                        const char *stderr_path, live_driver_result *r)
{
    memset(r, 0, sizeof *r);
    int to[2], from[2];
    if (pipe(to) || pipe(from)) return -1;
    fflush(stdout);
    pid_t pid = fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        dup2(to[0], 0);
        dup2(from[1], 1);
        if (stderr_path && !freopen(stderr_path, "w", stderr)) _exit(126);
        close(to[0]); close(to[1]); close(from[0]); close(from[1]);
        execv(argv[0], argv);
        _exit(127);
    }
    close(to[0]);
    close(from[1]);
    FILE *in = fdopen(to[1], "w"), *out = fdopen(from[0], "r");
    const long total = (long)(seconds * rate);
    double *latency = malloc((size_t)(total > 0 ? total : 1) * sizeof *latency);
    char answer[1 << 16], line[256];
    int ok = in && out && latency && fgets(answer, sizeof answer, out) != NULL; /* header */
    const double period = 1.0 / rate, origin = live_driver_now();
    for (long k = 1; ok && k <= total; k++) {
        const double t = k * period, due = origin + t;
        struct timespec ts = {(time_t)due, (long)((due - floor(due)) * 1e9)};
        while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL)) {}
        double pos[3], rot[3];
        path(t, start, pos, rot);
        if (columns == 4)
            snprintf(line, sizeof line, "%.9f,%.9g,%.9g,%.9g\n", t, pos[0], pos[1], pos[2]);
        else
            snprintf(line, sizeof line, "%.9f,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", t, pos[0], pos[1],
                     pos[2], rot[0], rot[1], rot[2]);
        const double sent = live_driver_now();
        if (fputs(line, in) == EOF || fflush(in)) break;
        r->lines++;
        if (!fgets(answer, sizeof answer, out)) break;
        const double got = live_driver_now() - sent;
        latency[r->answered++] = got;
        if (got > period) r->late++;
        if (strstr(answer, ",failed")) r->failed++;
        sscanf(answer, "%*f,%lf,%lf,%lf", &r->fx, &r->fy, &r->fz);
    }
    if (in) fclose(in);
    if (out) {
        while (fgets(answer, sizeof answer, out)) {}
        fclose(out);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    if (r->answered > 0) {
        qsort(latency, (size_t)r->answered, sizeof *latency, live_driver_compare);
        const long n = r->answered;
        r->p50 = latency[(n - 1) / 2];
        r->p99 = latency[(long)(0.99 * (double)(n - 1))];
        r->p999 = latency[(long)(0.999 * (double)(n - 1))];
        r->max = latency[n - 1];
    }
    free(latency);
    return ok && WIFEXITED(status) && WEXITSTATUS(status) == 0 ? 0 : -1;
}

/* live_driver_play_path along the needle holder's loop (live_driver_pose) */
static inline int live_driver_play(char *const *argv, const double start[3], double seconds,
                                   double rate, const char *stderr_path, live_driver_result *r)
{
    return live_driver_play_path(argv, live_driver_pose, 7, start, seconds, rate, stderr_path, r);
}

/* A knotted thread's starting centreline, written to `path` (header x,y,z,
 * m): a loose overhand knot (Shastri's polynomial trefoil, as
 * scenes/overhand_path.py, its strands 2.5 diameters of 1 mm apart at the
 * nearest) with 4 cm straight tails along its end tangents; its polyline
 * length (m) and its last point (the driven tip, m). -1 when the file
 * cannot be written. */
static inline int live_driver_write_knot(const char *path, double *length, double tip[3])
{
    FILE *f = fopen(path, "w");
    if (!f) return -1;
    const double scale = 2.5 * 0.001 / 0.424, tail = 0.04;
    const int samples = 4000;
    double p[3], prev[3] = {0.0, 0.0, 0.0};
    *length = 0.0;
    fprintf(f, "x,y,z\n");
    for (int k = -40; k <= samples + 40; k++) {
        const int j = k < 0 ? 0 : k > samples ? samples : k;
        const double t = -1.9 + 3.8 * j / samples;
        p[0] = scale * (t * t * t - 3.0 * t);
        p[1] = scale * (t * t * t * t - 4.0 * t * t);
        p[2] = scale * 0.2 * (t * t * t * t * t - 10.0 * t);
        /* the tails: along the tangent at each end (derivative of the above) */
        double d[3] = {3.0 * t * t - 3.0, 4.0 * t * t * t - 8.0 * t, 0.2 * (5.0 * t * t * t * t - 10.0)};
        const double n = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        const double along = k < 0 ? tail * k / 40.0 : k > samples ? tail * (k - samples) / 40.0 : 0.0;
        for (int c = 0; c < 3; c++) p[c] += along * d[c] / n;
        if (k > -40) {
            *length += sqrt((p[0] - prev[0]) * (p[0] - prev[0]) + (p[1] - prev[1]) * (p[1] - prev[1]) +
                            (p[2] - prev[2]) * (p[2] - prev[2]));
        }
        fprintf(f, "%.17g,%.17g,%.17g\n", p[0], p[1], p[2]);
        memcpy(prev, p, sizeof prev);
    }
    memcpy(tip, prev, sizeof prev);
    return fclose(f) ? -1 : 0;
}

#endif
