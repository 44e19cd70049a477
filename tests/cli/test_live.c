/* test_live.c: `rodsim live` through pipes. A thread hanging from a driven
 * clamped tip, held still, answers its weight m L g (rho pi d^2/4 L g, an
 * independent formula); every answer arrives before the next line is written
 * (lock-step through pipes: a missing flush would hang, caught by alarm());
 * bad lines get their line number and the policy (skip: answered bad_input;
 * stop: exit 2, the record kept), exactly one answer each whatever their
 * bytes; a repeated message is said once with its count; the record replayed
 * by `rodsim run` gives the same tip force and centreline as the live
 * session; a pose beyond reach costs a bounded count of Newton iterations
 * and the stream goes on once the pose is reachable; a line too far ahead is
 * refused before --realtime waits for it, and a stop signal ends a long line;
 * an unreadable input, an unwritable record exit 1. Several rods: two rods
 * hanging from pinned tips (test_hanging_rods.h), driven by lines that
 * name each rod, answer each rod's own weight rho A g L at rest; a line
 * without a name drives --rod's rod; a name the scene lacks is refused
 * naming the line and the accepted names; "rod:" is the name of a bare
 * [rod]. */
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "cli/live.h"
#include "test.h"
#include "test_hanging_rods.h"
#include "test_process.h"
#include "sim/rod.h"

static const char scene_text[] =
    "[rod]\nlength = 0.5\ndiameter = 0.001\ndensity = 1000\nyoungs_modulus = 87.5e6\n"
    "shear_modulus = 31.25e6\nnodes = 21\ndirection = 0 0 1\n"
    "[solver]\nscheme = implicit\ndt = 0.001\nduration = 1\n"
    "[loads]\ngravity = 0 0 -9.81\n[ends]\nroot = free\ntip = clamped\n";

typedef struct live_proc {
    pid_t pid;
    FILE *in, *out; /* its stdin (we write), its stdout (we read) */
} live_proc;

/* Starts rodsim live with args; stderr to stderr.txt in the test's folder;
 * killed after 60 s. */
static int live_start(live_proc *p, const char *const *args)
{
    int to[2], from[2];
    if (pipe(to) || pipe(from)) return -1;
    const char *argv[32];
    int n = 0;
    argv[n++] = RODSIM_BIN;
    argv[n++] = "live";
    for (int i = 0; args[i] && n < 31; i++) argv[n++] = args[i];
    argv[n] = NULL;
    const char *stderr_path = test_path("stderr.txt");
    fflush(stdout);
    p->pid = fork();
    if (p->pid == 0) {
        dup2(to[0], 0);
        dup2(from[1], 1);
        int e = open(stderr_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (e >= 0) dup2(e, 2);
        close(to[0]); close(to[1]); close(from[0]); close(from[1]);
        alarm(60);
        execv(RODSIM_BIN, (char *const *)argv);
        _exit(127);
    }
    close(to[0]);
    close(from[1]);
    p->in = fdopen(to[1], "w");
    p->out = fdopen(from[0], "r");
    return p->in && p->out ? 0 : -1;
}

static int live_finish(live_proc *p)
{
    if (p->in) fclose(p->in);
    char rest[4096];
    while (fgets(rest, sizeof rest, p->out)) {}
    fclose(p->out);
    int status = 0;
    waitpid(p->pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/* Writes one line and reads its answer (lock-step). 0, or -1 at EOF. */
static int exchange(live_proc *p, const char *line, char *answer, size_t n)
{
    fputs(line, p->in);
    fflush(p->in);
    return fgets(answer, (int)n, p->out) ? 0 : -1;
}

static char stderr_text[1 << 16];
static void read_stderr(void)
{
    FILE *f = fopen(test_path("stderr.txt"), "r");
    size_t got = f ? fread(stderr_text, 1, sizeof stderr_text - 1, f) : 0;
    stderr_text[got] = '\0';
    if (f) fclose(f);
}

static void test_hanging_weight_lockstep(void)
{
    live_proc p;
    const char *args[] = {test_path("hang.ini"), NULL};
    alarm(120); /* a lost flush would block both sides: the alarm ends the test */
    if (!check(live_start(&p, args) == 0, "rodsim live started")) return;
    char answer[8192], line[256];
    int header = fgets(answer, sizeof answer, p.out) != NULL &&
                 strcmp(answer, "t,fx,fy,fz,mx,my,mz,status\n") == 0;
    check(header, "header line t,fx,fy,fz,mx,my,mz,status");
    int answered = 0;
    double fz = 0.0, fx = 1.0;
    for (int k = 1; k <= 200; k++) { /* the tip held where it starts, 0.2 s at 1 kHz */
        snprintf(line, sizeof line, "%.3f,0,0,0.5\n", k * 1e-3);
        if (exchange(&p, line, answer, sizeof answer)) break;
        double t;
        char status[32] = "";
        if (sscanf(answer, "%lf,%lf,%*f,%lf,%*f,%*f,%*f,%31s", &t, &fx, &fz, status) == 4 &&
            fabs(t - k * 1e-3) < 1e-12 && strcmp(status, "ok") == 0)
            answered++;
    }
    check(answered == 200, "200 lines, each answered (ok, its t) before the next was written: %d",
          answered);
    const double weight = 1000.0 * M_PI * 0.001 * 0.001 / 4.0 * 0.5 * 9.81;
    check_rel("held still: vertical force on the holder = -weight m L g", -fz, weight, 1e-8);
    check_abs("held still: horizontal force", fx, 0.0, 1e-12);
    check(live_finish(&p) == 0, "exit 0 at the end of input");
    alarm(0);
}

static void test_bad_lines(void)
{
    live_proc p;
    const char *args[] = {test_path("hang.ini"), "--record", test_path("bad.csv"), NULL};
    alarm(120);
    if (!check(live_start(&p, args) == 0, "rodsim live started (skip)")) return;
    char answer[8192];
    if (!fgets(answer, sizeof answer, p.out)) return;
    static char huge[1 << 20];
    memset(huge, '1', sizeof huge - 2);
    huge[sizeof huge - 2] = '\n';
    const char *lines[] = {"0.001,0,0,0.5\n", "0.002,zero,0,0.5\n", "0.002,0,0\n",
                           "0.0005,0,0,0.5\n", "nan,0,0,0.5\n", huge, "0.002,0,-inf,0.5\n",
                           "0.002,0,0,0.5\n"};
    const char *expect[] = {"ok", "bad_input", "bad_input", "bad_input", "bad_input", "bad_input",
                            "bad_input", "ok"};
    int right = 0;
    for (int i = 0; i < 8; i++) {
        if (exchange(&p, lines[i], answer, sizeof answer)) break;
        size_t len = strlen(answer);
        while (len && answer[len - 1] == '\n') answer[--len] = '\0';
        const char *comma = strrchr(answer, ',');
        right += comma && strcmp(comma + 1, expect[i]) == 0;
    }
    check(right == 8, "good lines ok, bad lines answered bad_input and skipped: %d of 8", right);
    check(live_finish(&p) == 0, "--on-error skip: exit 0");
    read_stderr();
    const char *msgs[] = {"input line 2: a field is not a number", "input line 3: 3 numbers",
                          "input line 4: t = 0.0005", "input line 5: column 1 is not a finite",
                          "input line 6: longer than 4095 bytes",
                          "input line 7: column 3 is not a finite", "accepted: t,x,y,z or"};
    for (int i = 0; i < 7; i++)
        check(strstr(stderr_text, msgs[i]) != NULL, "stderr names the line: \"%s\"", msgs[i]);

    const char *stop_args[] = {test_path("hang.ini"), "--on-error", "stop", "--record",
                               test_path("stop.csv"), NULL};
    if (!check(live_start(&p, stop_args) == 0, "rodsim live started (stop)")) return;
    if (!fgets(answer, sizeof answer, p.out)) return;
    int first_ok = exchange(&p, "0.001,0,0,0.5\n", answer, sizeof answer) == 0;
    fputs("0.002,0,0,x\n0.003,0,0,0.5\n", p.in);
    check(live_finish(&p) == 2 && first_ok, "--on-error stop: exit 2 at the bad line");
    FILE *f = fopen(test_path("stop.csv"), "r");
    int rows = 0, has_first = 0;
    char row[512];
    while (f && fgets(row, sizeof row, f)) {
        if (row[0] == '#' || row[0] == 't') continue;
        rows++;
        has_first |= strncmp(row, "0.001,", 6) == 0;
    }
    if (f) fclose(f);
    check(rows == 2 && has_first, "the record keeps the start and the line before the bad one "
          "(%d rows)", rows);
    alarm(0);
}

/* Named pipes (a sensor bridge writes one, an app reads the other): 50
 * lines in lock-step, each answered ok before the next is written. */
static void test_fifos(void)
{
    const char *in_fifo = test_path("in.fifo"), *out_fifo = test_path("out.fifo");
    const char *stderr_path = test_path("stderr.txt"), *scene = test_path("hang.ini");
    unlink(in_fifo);
    unlink(out_fifo);
    if (!check(mkfifo(in_fifo, 0600) == 0 && mkfifo(out_fifo, 0600) == 0, "two FIFOs made"))
        return;
    alarm(120); /* a lost flush or open would block: the alarm ends the test */
    fflush(stdout);
    pid_t pid = fork();
    if (pid == 0) { /* opens in the same order as the parent: in, then out */
        int in = open(in_fifo, O_RDONLY), out = open(out_fifo, O_WRONLY);
        int e = open(stderr_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (in < 0 || out < 0) _exit(126);
        dup2(in, 0);
        dup2(out, 1);
        if (e >= 0) dup2(e, 2);
        execl(RODSIM_BIN, RODSIM_BIN, "live", scene, (char *)NULL);
        _exit(127);
    }
    FILE *in = fopen(in_fifo, "w"), *out = fopen(out_fifo, "r");
    char answer[512];
    int ok = 0;
    if (in && out && fgets(answer, sizeof answer, out))
        for (int k = 1; k <= 50; k++) {
            fprintf(in, "%.3f,0,0,0.5\n", k * 1e-3);
            fflush(in);
            if (!fgets(answer, sizeof answer, out)) break;
            ok += strstr(answer, ",ok\n") != NULL;
        }
    if (in) fclose(in);
    if (out) fclose(out);
    int status = 0;
    waitpid(pid, &status, 0);
    alarm(0);
    check(ok == 50 && WIFEXITED(status) && WEXITSTATUS(status) == 0,
          "through FIFOs: %d of 50 lines answered ok in lock-step, exit 0", ok);
}

/* Lines 1 ms apart take one step of dt = 1 ms each, also after t = 8.192 s,
 * where the rounding of t (ulp 1.8e-15 s) makes a gap differ from dt by more
 * than 1e-12 of it: the step count was ceil(gap / dt (1 - 1e-12)), and 62
 * of these 8500 lines took two half steps (and two Jacobian builds for the
 * changed dt; 1571 builds instead of 369 in bench_live's 10 s). */
static void test_one_step_per_line(void)
{
    FILE *f = fopen(test_path("still.csv"), "w");
    if (!f) return;
    for (int k = 1; k <= 8500; k++) fprintf(f, "%.3f,0,0,0.5\n", k * 1e-3);
    fclose(f);
    int rc = system(RODSIM_BIN " live $RODSIM_TEST_DIR/hang.ini < $RODSIM_TEST_DIR/still.csv > "
                    "/dev/null 2> $RODSIM_TEST_DIR/stderr.txt");
    read_stderr();
    const char *steps = strstr(stderr_text, " steps to t = 8.5 s");
    const char *count = steps;
    while (count && count > stderr_text && count[-1] >= '0' && count[-1] <= '9') count--;
    check(rc == 0 && strstr(stderr_text, "8500 lines: 8500 ok") && steps &&
              strncmp(count, "8500 steps", 10) == 0,
          "8500 lines 1 ms apart, dt = 1 ms: one step each (%.24s), exit %d",
          count ? count : "no summary", rc);
}

/* --realtime paces a replayed path to the wall clock: 100 lines 1 ms apart
 * cannot end before 0.1 s have passed (a lower bound: sleeping makes it
 * longer, never shorter), each answered ok; the summary counts overruns;
 * what the process may not do (lock memory, real-time priority) is said
 * and the session goes on. */
static void test_realtime(void)
{
    FILE *f = fopen(test_path("paced.csv"), "w");
    if (!f) return;
    for (int k = 1; k <= 100; k++) fprintf(f, "%.3f,0,0,0.5\n", k * 1e-3);
    fclose(f);
    struct timespec a, b;
    clock_gettime(CLOCK_MONOTONIC, &a);
    int rc = system(RODSIM_BIN " live $RODSIM_TEST_DIR/hang.ini --realtime < "
                    "$RODSIM_TEST_DIR/paced.csv > $RODSIM_TEST_DIR/paced_out.csv 2> "
                    "$RODSIM_TEST_DIR/stderr.txt");
    clock_gettime(CLOCK_MONOTONIC, &b);
    double wall = (double)(b.tv_sec - a.tv_sec) + 1e-9 * (double)(b.tv_nsec - a.tv_nsec);
    read_stderr();
    f = fopen(test_path("paced_out.csv"), "r");
    char line[512];
    int ok = 0;
    while (f && fgets(line, sizeof line, f)) ok += strstr(line, ",ok") != NULL;
    if (f) fclose(f);
    check(rc == 0 && ok == 100 && wall >= 0.1 && strstr(stderr_text, "realtime overruns"),
          "--realtime: 100 lines 1 ms apart answered ok (%d) in %.3f s >= 0.1 s, overruns "
          "counted, exit %d", ok, wall, rc);
}

/* The same path live and replayed by rodsim run from the record: tip force. */
static void test_replay(void)
{
    FILE *in = fopen(test_path("path_in.csv"), "w");
    if (!in) return;
    for (int k = 1; k <= 40; k++) { /* every 10 ms: one frame interval at fps 100 */
        double t = 0.01 * k, a = fmin(t / 0.2, 1.0);
        fprintf(in, "%.17g,%.17g,%.17g,%.17g,%.17g,0,0\n", t, 0.02 * a * sin(5 * t),
                0.01 * a * (1 - cos(5 * t)), 0.5 - 0.005 * a * a, 0.1 * a * sin(3 * t));
    }
    fclose(in);
    char out[1 << 14];
    /* both at a Newton tolerance of 1e-10: live renews its Jacobians between
     * lines (rod_solver_refresh), so its steps iterate with other Jacobians
     * than the replay's and converge to other points within the tolerance;
     * at the default 1e-8 those differ by up to 1e-8 L a step, over 400
     * steps of 1 ms (1.8e-8 L seen), beyond the bounds below. At 1e-10 the
     * differences stay 100 times below them, which are the default's */
    int rc = system(RODSIM_BIN " live $RODSIM_TEST_DIR/hang.ini "
                    "--set solver.newton_tolerance=1e-10 --centreline --record "
                    "$RODSIM_TEST_DIR/rec.csv < $RODSIM_TEST_DIR/path_in.csv > "
                    "$RODSIM_TEST_DIR/live_out.csv 2>/dev/null");
    check(rc == 0, "live session with --record: exit 0");
    char tip_motion[600];
    snprintf(tip_motion, sizeof tip_motion, "ends.tip_motion=%s", test_path("rec.csv"));
    const char *run_args[] = {"run", test_path("hang.ini"), "--set",
                              "solver.newton_tolerance=1e-10", "--set", tip_motion,
                              "--set", "solver.duration=0.4", "--set", "render.fps=100",
                              "--no-video", "--csv", test_path("run.csv"), "-o", test_dir(), NULL};
    rc = test_run_rodsim_within(run_args, 120, out, sizeof out);
    if (!check(rc == 0, "rodsim run replays the record: exit %d", rc)) {
        printf("%s\n", out);
        return;
    }
    static double live_force[64][3], live_centreline[64][63];
    FILE *f = fopen(test_path("live_out.csv"), "r");
    char line[4096];
    int n = 0;
    while (f && fgets(line, sizeof line, f) && n < 64) {
        double t, x, y, z;
        if (sscanf(line, "%lf,%lf,%lf,%lf", &t, &x, &y, &z) == 4) {
            int k = (int)lround(t / 0.01);
            if (k < 0 || k >= 64) continue;
            live_force[k][0] = x, live_force[k][1] = y, live_force[k][2] = z;
            char *p = line; /* after the status: x0,y0,z0,... */
            for (int c = 0; c < 8 && p; c++) p = strchr(p, ',') ? strchr(p, ',') + 1 : NULL;
            for (int i = 0; i < 63 && p; i++) {
                live_centreline[k][i] = strtod(p, NULL);
                p = strchr(p, ',') ? strchr(p, ',') + 1 : NULL;
            }
            n++;
        }
    }
    if (f) fclose(f);
    f = fopen(test_path("run.csv"), "r");
    double worst = 0.0, worst_position = 0.0;
    int compared = 0, positions = 0;
    while (f && fgets(line, sizeof line, f)) {
        double t, r[3], nx, ny, nz;
        int node;
        if (sscanf(line, "%lf,%d,%*f,%lf,%lf,%lf,%*f,%*f,%*f,%*f,%lf,%lf,%lf", &t, &node, &r[0],
                   &r[1], &r[2], &nx, &ny, &nz) != 8 || t <= 0.0 || node < 0 || node > 20)
            continue;
        int k = (int)lround(t / 0.01);
        for (int c = 0; c < 3; c++)
            worst_position = fmax(worst_position, fabs(r[c] - live_centreline[k][3 * node + c]));
        positions++;
        if (node != 20) continue;
        double d = fmax(fabs(-nx - live_force[k][0]),
                        fmax(fabs(-ny - live_force[k][1]), fabs(-nz - live_force[k][2])));
        worst = fmax(worst, d);
        compared++;
    }
    if (f) fclose(f);
    const double weight = 1000.0 * M_PI * 0.001 * 0.001 / 4.0 * 0.5 * 9.81;
    check(compared == 40 && worst <= 1e-5 * weight,
          "live and replayed tip force agree at %d output times: largest difference %.3e N "
          "(%.1e of the weight; Newton tolerance 1e-8 on a force differenced over dt)",
          compared, worst, worst / weight);
    /* to the Newton tolerance 1e-8, relative to the length 0.5 m (run's CSV
     * writes 10 digits: 5e-11 m) */
    check(positions == 40 * 21 && worst_position <= 1e-8 * 0.5,
          "live (--centreline) and replayed centreline agree at %d node positions: largest "
          "difference %.3e m (%.1e of the length)", positions, worst_position,
          worst_position / 0.5);
}

/* The example driver (tests/live_driver.c, built beside the tests) plays
 * its needle-holder path at 1 kHz for 0.3 s: every line answered. */
static void test_driver(void)
{
    char driver[1024];
    snprintf(driver, sizeof driver, "%s", RODSIM_BIN);
    char *slash = strrchr(driver, '/');
    if (!slash) return;
    snprintf(slash + 1, sizeof driver - (size_t)(slash + 1 - driver), "tests/live_driver");
    char command[2048];
    snprintf(command, sizeof command, "%s %s %s/hang.ini 0.3 > %s/driver.txt 2>&1", driver,
             RODSIM_BIN, test_dir(), test_dir());
    int rc = system(command);
    FILE *f = fopen(test_path("driver.txt"), "r");
    char text[2048] = "";
    size_t got = f ? fread(text, 1, sizeof text - 1, f) : 0;
    text[got] = '\0';
    if (f) fclose(f);
    check(rc == 0 && strstr(text, "300 lines, 300 answered, 0 failed") != NULL,
          "live_driver plays 0.3 s at 1 kHz, every line answered: %s", text);
}

/* A free tip takes its loads live; under the static scheme each line is an
 * equilibrium, so what the thread exerts on its root is the tip load (force
 * balance) and the tip moment plus r_tip x F (moment balance about the root
 * at the origin), r_tip from the --centreline columns. */
static void test_free_tip_loads(void)
{
    FILE *f = fopen(test_path("cant.ini"), "w");
    if (!f) return;
    fputs("[rod]\nlength = 1\ndiameter = 0.001\ndensity = 850\nyoungs_modulus = 87.5e6\n"
          "shear_modulus = 31.25e6\nnodes = 21\n[solver]\nscheme = static\ndt = 0.01\n"
          "[tip]\nframe = global\n", f);
    fclose(f);
    f = fopen(test_path("loads_in.csv"), "w");
    if (!f) return;
    fputs("0.01,0,1e-7,0,0,0,0\n0.02,2e-7,1e-7,0,0,0,3e-8\n", f);
    fclose(f);
    int rc = system(RODSIM_BIN " live $RODSIM_TEST_DIR/cant.ini --centreline < "
                    "$RODSIM_TEST_DIR/loads_in.csv > $RODSIM_TEST_DIR/loads_out.csv 2>/dev/null");
    f = fopen(test_path("loads_out.csv"), "r");
    static char line[1 << 14];
    double v[8 + 63] = {0};
    int rows = 0;
    while (f && fgets(line, sizeof line, f)) {
        if (line[0] == 't') continue;
        char *p = line;
        for (int k = 0; k < 8 + 63 && *p; k++) {
            v[k] = k == 7 ? 0.0 : strtod(p, NULL); /* column 8: the status word */
            p = strchr(p, ',');
            if (!p) break;
            p++;
        }
        rows++;
    }
    if (f) fclose(f);
    const double *tip = &v[8 + 3 * 20], F[3] = {2e-7, 1e-7, 0.0};
    double moment_z = 3e-8 + tip[0] * F[1] - tip[1] * F[0];
    check(rc == 0 && rows == 2, "free tip, loads live, static scheme: 2 answers");
    check_rel("root force x = tip load (force balance)", v[1], F[0], 1e-8);
    check_rel("root force y = tip load", v[2], F[1], 1e-8);
    check_rel("root moment z = tip moment + (r_tip x F)_z (moment balance)", v[6], moment_z, 1e-6);
}

/* A step that fails (a load that kinks the rod beyond its grid) answers
 * failed: the load is held at the last good one (the loads' half way fails
 * too), the time goes on to the line's, and the stream goes on. */
static void test_failed_step(void)
{
    FILE *f = fopen(test_path("kink_in.csv"), "w");
    if (!f) return;
    fputs("0.01,0,1e-7,0,0,0,0\n0.02,0,1e3,0,0,0,0\n0.03,0,1e-7,0,0,0,0\n", f);
    fclose(f);
    int rc = system(RODSIM_BIN " live $RODSIM_TEST_DIR/cant.ini --set solver.scheme=implicit < "
                    "$RODSIM_TEST_DIR/kink_in.csv > $RODSIM_TEST_DIR/kink_out.csv 2> "
                    "$RODSIM_TEST_DIR/stderr.txt");
    f = fopen(test_path("kink_out.csv"), "r");
    char line[1024], statuses[64] = "";
    double t2 = -1.0;
    while (f && fgets(line, sizeof line, f)) {
        if (line[0] == 't') continue;
        line[strcspn(line, "\n")] = '\0';
        const char *c = strrchr(line, ',');
        if (c) strncat(statuses, c, sizeof statuses - strlen(statuses) - 1);
        if (strstr(line, ",failed")) t2 = strtod(line, NULL);
    }
    if (f) fclose(f);
    read_stderr();
    check(rc == 0 && strcmp(statuses, ",ok,failed,ok") == 0 && t2 == 0.02 &&
              strstr(stderr_text, "input line 2 (t = 0.02 s): the step failed") != NULL &&
              strstr(stderr_text, "held where it was") != NULL,
          "a failed step: answers %s, the failed line at its own t = %g s with the load held, "
          "stderr names line 2, exit %d", statuses, t2, rc);
}

/* The holder lowers the hanging thread from 0.5 m to 0.3 m above a table
 * (a plane through (0, 0, -1 mm), 1 mm under its lower end, with the given
 * normal), the thread's E given: the lines answered, those answered ok,
 * the failed ones among the first 100 (the first touch, at 0.072-0.078 s),
 * the holder's last force z (N) and the least distance of a centreline
 * point from the plane (m). */
typedef struct lowered {
    int lines, ok, failed_early, rc;
    double fz, closest;
} lowered;

static lowered lower_onto_table(const char *normal, const char *youngs)
{
    lowered r = {0, 0, 0, -1, 0.0, 1.0};
    FILE *f = fopen(test_path("table.ini"), "w");
    if (!f) return r;
    fprintf(f,
            "[rod]\nlength = 0.5\ndiameter = 0.001\ndensity = 1000\nyoungs_modulus = %s\n"
            "shear_modulus = 31.25e6\nnodes = 21\ndirection = 0 0 1\n"
            "[solver]\nscheme = implicit\ndt = 0.001\nduration = 1\n"
            "[loads]\ngravity = 0 0 -9.81\n[ends]\nroot = free\ntip = clamped\n"
            "[surface]\nshape = plane\ncenter = 0 0 -0.001\nnormal = %s\nfriction = 0.3\n",
            youngs, normal);
    fclose(f);
    double nrm[3] = {0.0, 0.0, 0.0};
    if (sscanf(normal, "%lf %lf %lf", &nrm[0], &nrm[1], &nrm[2]) != 3) return r;
    const double len = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
    f = fopen(test_path("lower.csv"), "w");
    if (!f) return r;
    for (int k = 1; k <= 1500; k++) { /* 1 s lowering 0.2 m (smoothly), 0.5 s held */
        double t = k * 1e-3, u = t < 1.0 ? t : 1.0;
        double z = 0.5 - 0.2 * (u - sin(2.0 * M_PI * u) / (2.0 * M_PI));
        fprintf(f, "%.3f,0,0,%.9f\n", t, z);
    }
    fclose(f);
    r.rc = system(RODSIM_BIN " live $RODSIM_TEST_DIR/table.ini --centreline < "
                  "$RODSIM_TEST_DIR/lower.csv > $RODSIM_TEST_DIR/lower_out.csv 2> "
                  "$RODSIM_TEST_DIR/stderr.txt");
    f = fopen(test_path("lower_out.csv"), "r");
    static char line[65536];
    if (f && fgets(line, sizeof line, f)) {
        while (fgets(line, sizeof line, f)) {
            r.lines++;
            /* t,fx,fy,fz,mx,my,mz,status,x0,y0,z0,... */
            char *field = line, *next;
            double value[8] = {0};
            int column = 0;
            for (; column < 7 && field; column++) {
                value[column] = strtod(field, &next);
                field = strchr(next, ',');
                if (field) field++;
            }
            if (field && strncmp(field, "ok,", 3) == 0) r.ok++;
            else if (r.lines <= 100) r.failed_early++;
            r.fz = value[3];
            double p[3];
            for (int c = 0; field && (field = strchr(field, ',')); c++) {
                field++;
                p[c % 3] = strtod(field, NULL);
                if (c % 3 == 2)
                    r.closest = fmin(r.closest, (nrm[0] * p[0] + nrm[1] * p[1] +
                                                 nrm[2] * (p[2] + 0.001)) / len);
            }
        }
    }
    if (f) fclose(f);
    return r;
}

/* Live with contact: the part of the thread that reaches the table rests
 * on it, so the holder carries less than the whole weight, and no node
 * sinks into the table by more than 1 % of the radius.
 *
 * The step of the first touch (at 0.072-0.078 s) is the hardest of the
 * session: with the scheme's own budget it converged in 200-300 Newton
 * iterations; within a live line's budget (LIVE_STEP_BUDGET_MIN) it may
 * fail and the end move half way (line_tries), and the stream goes on. On
 * a table tilted by 2.9 degrees, at three stiffnesses within 1.1e-6 of each
 * other: every line answered, at most 5 failed, all at the first touch.
 *
 * On a level table the thread lands end-on, straight along the normal:
 * the known gap (README, Decisions). The step of its first touch has no
 * solution near the straight iterate (the sink is capped at 1 % of the
 * radius, the holder lowers the thread 20 um a step, and the thread must
 * bend), and whether Newton finds the bent one is chance. The stream goes
 * on: checked here are every line answered, at most 10 failed, all at the
 * first touch, and the sink. */
static void test_contact_live(void)
{
    const double radius = 0.0005, weight = 1000.0 * M_PI * 0.001 * 0.001 / 4.0 * 9.81;
    const char *stiffness[3] = {"87.5e6", "87.500001e6", "87.5001e6"};
    for (int k = 0; k < 3; k++) {
        lowered r = lower_onto_table("0.05 0 1", stiffness[k]);
        check(r.rc == 0 && r.lines == 1500 && r.ok + r.failed_early == 1500 &&
                  r.failed_early <= 5,
              "live with a table tilted 2.9 degrees, E = %s Pa: every line answered, %d of "
              "1500 ok, %d failed, all at the first touch (at most 5; exit %d)", stiffness[k],
              r.ok, r.failed_early, r.rc);
        /* the lowered 0.2 m folds onto the table as a stiff column (bending
         * length (EI / rho A g)^(1/3) = 8 cm), which carries part of the rest */
        check(-r.fz < 0.8 * weight * 0.5 && -r.fz > 0.0,
              "the holder carries %.4g N, less than the thread's weight %.4g N: the table "
              "takes the part lowered onto it (a limp thread would leave %.4g N, the 0.3 m "
              "still hanging)", -r.fz, weight * 0.5, weight * 0.3);
        check(r.closest >= radius * 0.99,
              "no node sinks into the tilted table: the closest centreline point is %.6g m "
              "from it, the radius %.6g m", r.closest, radius);
    }
    lowered r = lower_onto_table("0 0 1", "87.5e6");
    check(r.rc == 0 && r.lines == 1500 && r.ok + r.failed_early == 1500 && r.failed_early <= 10,
          "live with a level table (the thread end-on): every line answered, %d of 1500 ok, "
          "%d failed, all at the first touch (at most 10; exit %d)", r.ok, r.failed_early, r.rc);
    check(-r.fz < 0.8 * weight * 0.5 && -r.fz > 0.0 && r.closest >= radius * 0.99,
          "on the level table the holder carries %.4g N (the weight %.4g N), the closest "
          "centreline point is %.6g m from it (the radius %.6g m)", -r.fz, weight * 0.5,
          r.closest, radius);
}

/* The number after `key` in the session's summary line on stderr
 * ("rodsim live: N lines: ..."; -1: none). */
static double summary_number(const char *key)
{
    const char *summary = strstr(stderr_text, " lines: ");
    if (!summary) return -1.0;
    while (summary > stderr_text && summary[-1] != '\n') summary--;
    const char *end = strchr(summary, '\n'), *at = strstr(summary, key);
    return at && (!end || at < end) ? strtod(at + strlen(key), NULL) : -1.0;
}

/* A pose beyond reach: the holder pushes the thread's tip up into a
 * ceiling (a plane 2 cm above it, solid above) and brings it back. Each
 * line beyond reach fails within its budget (counted in Newton iterations,
 * the scheme's own count), the end held where the ceiling stops it and the
 * time going on, so every line after the pose is reachable again is ok:
 * before, a line beyond reach took Newton's whole budget (some 380 Jacobian
 * builds a line here), was dropped, and the next line asked for a jump from
 * the last good pose that never came back within reach (470 ok, then 1030
 * failed to the end). */
static void test_pose_beyond_reach(void)
{
    FILE *f = fopen(test_path("ceiling.ini"), "w");
    if (!f) return;
    fputs(scene_text, f);
    fputs("[surface]\nshape = plane\ncenter = 0 0 0.52\nnormal = 0 0 -1\nfriction = 0.3\n", f);
    fclose(f);
    f = fopen(test_path("up.csv"), "w");
    if (!f) return;
    const int lines = 1500;
    for (int k = 1; k <= lines; k++) { /* up 5 cm and back within 1.2 s, then held */
        double t = k * 1e-3, a = t < 1.2 ? sin(M_PI * t / 1.2) : 0.0;
        fprintf(f, "%.3f,0,0,%.9f\n", t, 0.5 + 0.05 * a * a);
    }
    fclose(f);
    int rc = system(RODSIM_BIN " live $RODSIM_TEST_DIR/ceiling.ini < $RODSIM_TEST_DIR/up.csv > "
                    "$RODSIM_TEST_DIR/up_out.csv 2> $RODSIM_TEST_DIR/stderr.txt");
    read_stderr();
    f = fopen(test_path("up_out.csv"), "r");
    static char line[4096];
    int answered = 0, failed = 0, own_t = 0, last_failed = 0, first_failed = 0;
    while (f && fgets(line, sizeof line, f)) {
        if (line[0] == 't') continue;
        answered++;
        own_t += fabs(strtod(line, NULL) - answered * 1e-3) < 1e-12;
        if (strstr(line, ",failed")) {
            failed++;
            last_failed = answered;
            if (!first_failed) first_failed = answered;
        }
    }
    if (f) fclose(f);
    /* the request passes the height it failed at on its way back at the
     * mirror time, 1.2 s - t_first: the lines after are within reach */
    const int reachable = 1200 - first_failed + 2;
    check(rc == 0 && answered == lines && failed > 50 && last_failed <= reachable,
          "pushed into a ceiling and back: %d lines answered, %d failed (lines %d to %d), every "
          "line ok from line %d on, where the pose is within reach again (exit %d)", answered,
          failed, first_failed, last_failed, reachable, rc);
    check(own_t == lines && summary_number("failed (") == failed,
          "each answer at its own line's t (%d of %d): the failed lines moved part of the way "
          "or held (%g of %d), none dropped", own_t, lines, summary_number("failed ("), failed);
    char key[64];
    snprintf(key, sizeof key, "budget %d to ", LIVE_STEP_BUDGET_MIN);
    const double mean = summary_number("failed mean "), budget = summary_number(key);
    const double worst = mean > 0.0 ? strtod(strstr(strstr(stderr_text, "failed mean "), ", max ") +
                                                 6, NULL)
                                    : -1.0;
    check(mean > 0.0 && budget == LIVE_STEP_BUDGET_MIN && worst > 0.0 &&
              worst <= 9.0 * LIVE_STEP_BUDGET_MIN,
          "a failed line: at most %g Newton iterations (mean %g), within 9 x %d (its tries: as "
          "asked, half way, held; each a step whose two retries with contact have the budget "
          "too; before: the scheme's own, 4000 a try)", worst, mean, LIVE_STEP_BUDGET_MIN);
}

/* The same push at 10 ms a line (10 steps each), recorded and replayed by
 * `rodsim run`: the held rows (the end at rest one step after the last good
 * row: over 10 ms the last velocity carried it into the ceiling, and the
 * stream stuck from line 48 on) replay to the live forces, also on the
 * failed lines. Newton tolerance 1e-10 in both (test_replay). */
static void test_beyond_reach_replay(void)
{
    FILE *f = fopen(test_path("up10.csv"), "w");
    if (!f) return;
    for (int k = 1; k <= 150; k++) {
        double t = k * 0.01, a = t < 1.2 ? sin(M_PI * t / 1.2) : 0.0;
        fprintf(f, "%.2f,0,0,%.9f\n", t, 0.5 + 0.05 * a * a);
    }
    fclose(f);
    int rc = system(RODSIM_BIN " live $RODSIM_TEST_DIR/ceiling.ini "
                    "--set solver.newton_tolerance=1e-10 --record $RODSIM_TEST_DIR/up10_rec.csv "
                    "< $RODSIM_TEST_DIR/up10.csv > $RODSIM_TEST_DIR/up10_out.csv 2>/dev/null");
    char out[1 << 14];
    char tip_motion[600];
    snprintf(tip_motion, sizeof tip_motion, "ends.tip_motion=%s", test_path("up10_rec.csv"));
    const char *run_args[] = {"run", test_path("ceiling.ini"), "--set",
                              "solver.newton_tolerance=1e-10", "--set", tip_motion,
                              "--set", "solver.duration=1.5", "--set", "render.fps=100",
                              "--no-video", "--csv", test_path("up10_run.csv"), "-o", test_dir(),
                              NULL};
    int run_rc = test_run_rodsim_within(run_args, 120, out, sizeof out);
    static double live_force[160][3];
    static int live_failed[160];
    f = fopen(test_path("up10_out.csv"), "r");
    char line[1024];
    int answers = 0, failed = 0;
    while (f && fgets(line, sizeof line, f)) {
        double t, x, y, z;
        if (sscanf(line, "%lf,%lf,%lf,%lf", &t, &x, &y, &z) != 4) continue;
        int k = (int)lround(t / 0.01);
        if (k < 0 || k >= 160) continue;
        live_force[k][0] = x, live_force[k][1] = y, live_force[k][2] = z;
        live_failed[k] = strstr(line, ",failed") != NULL;
        failed += live_failed[k];
        answers++;
    }
    if (f) fclose(f);
    f = fopen(test_path("up10_run.csv"), "r");
    double worst = 0.0, worst_failed = 0.0;
    int compared = 0;
    while (f && fgets(line, sizeof line, f)) {
        double t, nx, ny, nz;
        int node;
        if (sscanf(line, "%lf,%d,%*f,%*f,%*f,%*f,%*f,%*f,%*f,%*f,%lf,%lf,%lf", &t, &node, &nx, &ny,
                   &nz) != 5 || t <= 0.0 || node != 20)
            continue;
        int k = (int)lround(t / 0.01);
        if (k < 0 || k >= 160) continue;
        double d = fmax(fabs(-nx - live_force[k][0]),
                        fmax(fabs(-ny - live_force[k][1]), fabs(-nz - live_force[k][2])));
        worst = fmax(worst, d);
        if (live_failed[k]) worst_failed = fmax(worst_failed, d);
        compared++;
    }
    if (f) fclose(f);
    const double weight = 1000.0 * M_PI * 0.001 * 0.001 / 4.0 * 0.5 * 9.81;
    check(rc == 0 && run_rc == 0 && answers == 150 && failed > 5 && failed < 50 &&
              live_failed[149] == 0,
          "10 ms a line into the ceiling and back: %d answers, %d failed, the last ok; the "
          "record replayed (exit %d, %d)", answers, failed, rc, run_rc);
    check(compared == 150 && worst <= 1e-5 * weight,
          "live and replayed tip force agree at %d times: largest difference %.3e N (%.1e of the "
          "weight), %.3e N on the failed lines", compared, worst, worst / weight, worst_failed);
}

/* A line too far ahead is refused before --realtime waits for it: t = 1e6 s
 * (it slept 11.6 days before), t = 1e300 (a conversion to time_t out of
 * range), one step more than LIVE_MAX_STEPS_AHEAD; the line at exactly
 * that many steps is stepped. alarm() ends a session that waits. */
static void test_far_ahead(void)
{
    live_proc p;
    const char *args[] = {test_path("hang.ini"), "--realtime", NULL};
    alarm(60);
    if (!check(live_start(&p, args) == 0, "rodsim live --realtime started")) return;
    char answer[8192], limit[64];
    if (!fgets(answer, sizeof answer, p.out)) return;
    const double last = 0.001 + LIVE_MAX_STEPS_AHEAD * 0.001; /* dt = 1 ms */
    char at_limit[64], beyond[64]; /* at_limit: not with --realtime, which would wait 10 s */
    snprintf(at_limit, sizeof at_limit, "%.3f,0,0,0.5\n", last);
    snprintf(beyond, sizeof beyond, "%.4f,0,0,0.5\n", last + LIVE_MAX_STEPS_AHEAD * 0.001 + 1e-4);
    const char *lines[] = {"0.001,0,0,0.5\n", "1e6,0,0,0.5\n", "1e300,0,0,0.5\n", beyond};
    int refused = 0, first_ok = 0;
    for (int i = 0; i < 4; i++) {
        if (exchange(&p, lines[i], answer, sizeof answer)) break;
        if (i == 0) first_ok = strstr(answer, ",ok\n") != NULL;
        else refused += strstr(answer, ",bad_input\n") != NULL;
    }
    check(live_finish(&p) == 0 && first_ok && refused == 3,
          "t = 1e6 s, 1e300 s and %d steps + 0.1 ahead: refused at once (%d of 3), exit 0",
          LIVE_MAX_STEPS_AHEAD, refused);
    read_stderr();
    snprintf(limit, sizeof limit, "more than %d steps of solver.dt", LIVE_MAX_STEPS_AHEAD);
    check(strstr(stderr_text, "input line 2: t = 1000000 s is") != NULL &&
              strstr(stderr_text, limit) != NULL,
          "the message names the line and the limit (\"%s\")", limit);
    /* exactly LIVE_MAX_STEPS_AHEAD steps ahead is stepped (without --realtime) */
    FILE *f = fopen(test_path("ahead.csv"), "w");
    if (!f) return;
    fprintf(f, "0.001,0,0,0.5\n%s", at_limit);
    fclose(f);
    int rc = system(RODSIM_BIN " live $RODSIM_TEST_DIR/hang.ini < $RODSIM_TEST_DIR/ahead.csv > "
                    "$RODSIM_TEST_DIR/ahead_out.csv 2> $RODSIM_TEST_DIR/stderr.txt");
    read_stderr();
    char text[128];
    snprintf(text, sizeof text, "2 lines: 2 ok, 0 failed (0 moved part of the way or held), "
             "0 bad; %d steps", LIVE_MAX_STEPS_AHEAD + 1);
    check(rc == 0 && strstr(stderr_text, text) != NULL, "a line %d steps ahead is stepped: "
          "\"%s\"", LIVE_MAX_STEPS_AHEAD, text);
    alarm(0);
}

/* SIGTERM while a line is being stepped (10^4 steps at NS = 401, the end
 * moved 10 cm: about a second of work, the signal after 50 ms) ends it at
 * once: the line is answered failed (interrupted), the session ends with
 * its summary, exit 0 (a line before was ok). Before, the signal waited
 * for the line's last step. */
static void test_signal_within_line(void)
{
    const char *args[] = {test_path("hang.ini"), "--set", "rod.nodes=401", NULL};
    live_proc p;
    alarm(60);
    if (!check(live_start(&p, args) == 0, "rodsim live started (signal)")) return;
    char answer[8192], line[64];
    if (!fgets(answer, sizeof answer, p.out)) return;
    int first_ok = exchange(&p, "0.001,0,0,0.5\n", answer, sizeof answer) == 0 &&
                   strstr(answer, ",ok\n") != NULL;
    snprintf(line, sizeof line, "%.3f,0.1,0,0.5\n", 0.001 + LIVE_MAX_STEPS_AHEAD * 0.001);
    fputs(line, p.in);
    fflush(p.in);
    struct timespec pause = {0, 50000000}; /* 50 ms: well within the line's steps */
    nanosleep(&pause, NULL);
    kill(p.pid, SIGTERM);
    int interrupted = fgets(answer, sizeof answer, p.out) != NULL &&
                      strstr(answer, ",failed\n") != NULL;
    int rc = live_finish(&p);
    alarm(0);
    read_stderr();
    const double steps = summary_number("bad; ");
    check(first_ok && interrupted && rc == 0 && steps >= 1.0 && steps < LIVE_MAX_STEPS_AHEAD &&
              strstr(stderr_text, "interrupted by a stop signal") != NULL &&
              strstr(stderr_text, "ended by a signal") != NULL,
          "SIGTERM within a line of %d steps: answered failed (%d), %g steps taken, exit %d",
          LIVE_MAX_STEPS_AHEAD, interrupted, steps, rc);
}

/* One answer per line whatever its bytes: a NUL followed by more than
 * 4095 bytes (two answers before: fgets cut it), a NUL in a short line; a
 * line of exactly LIVE_MAX bytes is stepped (refused before, though --help
 * said "over 4095"), also with \r\n, one byte more is refused. */
static void test_line_bytes(void)
{
    static char text[3 * 8192];
    size_t n = 0;
    const char *prefix = "0.001,0,0,0.5";
    /* 1: exactly LIVE_LINE_MAX bytes: the numbers, then blanks */
    n += (size_t)snprintf(text + n, sizeof text - n, "%s", prefix);
    memset(text + n, ' ', LIVE_LINE_MAX - strlen(prefix));
    n += LIVE_LINE_MAX - strlen(prefix);
    text[n++] = '\n';
    /* 2: a NUL, then 5000 bytes: one line, too long */
    memcpy(text + n, "0.002,0,0,0.5", 13);
    n += 13;
    text[n++] = '\0';
    memset(text + n, '7', 5000);
    n += 5000;
    text[n++] = '\n';
    /* 3: LIVE_LINE_MAX + 1 bytes */
    n += (size_t)snprintf(text + n, sizeof text - n, "0.002,0,0,0.5");
    memset(text + n, ' ', LIVE_LINE_MAX + 1 - 13);
    n += LIVE_LINE_MAX + 1 - 13;
    text[n++] = '\n';
    /* 4: a NUL within a short line */
    memcpy(text + n, "0.002,0\0,0,0.5\n", 15);
    n += 15;
    /* 5: LIVE_LINE_MAX bytes and \r\n */
    n += (size_t)snprintf(text + n, sizeof text - n, "0.002,0,0,0.5");
    memset(text + n, ' ', LIVE_LINE_MAX - 13);
    n += LIVE_LINE_MAX - 13;
    text[n++] = '\r';
    text[n++] = '\n';
    /* 6: the last line without its newline */
    n += (size_t)snprintf(text + n, sizeof text - n, "0.003,0,0,0.5");
    FILE *f = fopen(test_path("bytes.csv"), "w");
    if (!f) return;
    fwrite(text, 1, n, f);
    fclose(f);
    int rc = system(RODSIM_BIN " live $RODSIM_TEST_DIR/hang.ini < $RODSIM_TEST_DIR/bytes.csv > "
                    "$RODSIM_TEST_DIR/bytes_out.csv 2> $RODSIM_TEST_DIR/stderr.txt");
    f = fopen(test_path("bytes_out.csv"), "r");
    char line[512], statuses[128] = "";
    int answers = 0;
    while (f && fgets(line, sizeof line, f)) {
        if (line[0] == 't') continue;
        answers++;
        line[strcspn(line, "\n")] = '\0';
        const char *c = strrchr(line, ',');
        if (c) strncat(statuses, c, sizeof statuses - strlen(statuses) - 1);
    }
    if (f) fclose(f);
    read_stderr();
    check(rc == 0 && answers == 6 &&
              strcmp(statuses, ",ok,bad_input,bad_input,bad_input,ok,ok") == 0,
          "6 lines, 6 answers: %s (a line of %d bytes ok, with \\r\\n too; a NUL, a byte over: "
          "refused), exit %d", statuses, LIVE_LINE_MAX, rc);
    check(strstr(stderr_text, "input line 2: longer than 4095 bytes") &&
              strstr(stderr_text, "input line 3: the same as line 2 (a line too long)") &&
              strstr(stderr_text, "input line 4: a NUL byte at byte 8"),
          "stderr names the length and the NUL's byte");
    char out[4096];
    const char *help[] = {"live", "--help", NULL};
    test_run_rodsim_within(help, 30, out, sizeof out);
    check(strstr(out, "over 4095 bytes") != NULL && LIVE_LINE_MAX == 4095,
          "--help says what is refused: a line of over 4095 bytes");
}

/* 6000 lines, none a number: one message, then its count (6000 of them
 * before), exit 2 as no line was answered ok. */
static void test_repeated_message(void)
{
    FILE *f = fopen(test_path("junk.csv"), "w");
    if (!f) return;
    for (int k = 0; k < 6000; k++) fputs("junk\n", f);
    fclose(f);
    int rc = system(RODSIM_BIN " live $RODSIM_TEST_DIR/hang.ini < $RODSIM_TEST_DIR/junk.csv > "
                    "$RODSIM_TEST_DIR/junk_out.csv 2> $RODSIM_TEST_DIR/stderr.txt");
    read_stderr();
    int messages = 0;
    for (const char *c = stderr_text; (c = strstr(c, "rodsim live: ")); c++) messages++;
    check(WIFEXITED(rc) && WEXITSTATUS(rc) == 2 && messages <= 5 &&
              strstr(stderr_text, "input line 1: a field is not a number") &&
              strstr(stderr_text, "input lines 2 to 6000: 5999 more lines like line 1") &&
              strstr(stderr_text, "none of the 6000 lines was answered ok"),
          "6000 malformed lines: %d messages on stderr (the first, its count, the summary), "
          "exit %d (2: no line answered ok)", messages, WIFEXITED(rc) ? WEXITSTATUS(rc) : -1);
}

/* Standard input closed or unreadable (a directory): exit 1, said. */
static void test_unreadable_input(void)
{
    int rc = system(RODSIM_BIN " live $RODSIM_TEST_DIR/hang.ini <&- > /dev/null 2> "
                    "$RODSIM_TEST_DIR/stderr.txt");
    read_stderr();
    check(WIFEXITED(rc) && WEXITSTATUS(rc) == 1 &&
              strstr(stderr_text, "standard input is closed"),
          "standard input closed: exit %d (1), said", WIFEXITED(rc) ? WEXITSTATUS(rc) : -1);
    rc = system(RODSIM_BIN " live $RODSIM_TEST_DIR/hang.ini < $RODSIM_TEST_DIR > /dev/null 2> "
                "$RODSIM_TEST_DIR/stderr.txt");
    read_stderr();
    check(WIFEXITED(rc) && WEXITSTATUS(rc) == 1 &&
              strstr(stderr_text, "reading standard input after input line 0"),
          "standard input a directory (a read error): exit %d (1), said",
          WIFEXITED(rc) ? WEXITSTATUS(rc) : -1);
}

/* A record that cannot be written stops the session when it happens, exit
 * 1: on /dev/full at its first row (no line answered), and with the file
 * size limited to 16 kB in the middle of the session (before: said only
 * at the end, every line answered as if recorded). */
static void test_record_write_error(void)
{
    FILE *f = fopen(test_path("rec_in.csv"), "w");
    if (!f) return;
    for (int k = 1; k <= 400; k++) fprintf(f, "%.3f,0,0,0.5\n", k * 1e-3);
    fclose(f);
    int rc = system(RODSIM_BIN " live $RODSIM_TEST_DIR/hang.ini --record /dev/full < "
                    "$RODSIM_TEST_DIR/rec_in.csv > $RODSIM_TEST_DIR/rec_out.csv 2> "
                    "$RODSIM_TEST_DIR/stderr.txt");
    read_stderr();
    f = fopen(test_path("rec_out.csv"), "r");
    char line[512];
    int answers = 0;
    while (f && fgets(line, sizeof line, f)) answers += line[0] != 't';
    if (f) fclose(f);
    check(WIFEXITED(rc) && WEXITSTATUS(rc) == 1 && answers == 0 &&
              strstr(stderr_text, "--record /dev/full: write error before the first line "
                                  "(No space left on device)"),
          "--record /dev/full: exit %d (1) before any line (%d answered), said at once",
          WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, answers);

    const char *rec_in = test_path("rec_in.csv"), *stderr_path = test_path("stderr.txt");
    const char *scene = test_path("hang.ini"), *full = test_path("full.csv");
    fflush(stdout);
    pid_t pid = fork();
    if (pid == 0) {
        struct rlimit limit = {16384, 16384};
        setrlimit(RLIMIT_FSIZE, &limit);
        signal(SIGXFSZ, SIG_IGN); /* the write fails with EFBIG instead */
        int in = open(rec_in, O_RDONLY), out = open("/dev/null", O_WRONLY);
        int e = open(stderr_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (in < 0 || out < 0 || e < 0) _exit(126);
        dup2(in, 0);
        dup2(out, 1);
        dup2(e, 2);
        execl(RODSIM_BIN, RODSIM_BIN, "live", scene, "--record", full, (char *)NULL);
        _exit(127);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    read_stderr();
    const char *at = strstr(stderr_text, "write error at input line ");
    const long stopped = at ? strtol(at + strlen("write error at input line "), NULL, 10) : -1;
    const double lines = summary_number("rodsim live: ");
    check(WIFEXITED(status) && WEXITSTATUS(status) == 1 && stopped > 10 && stopped < 400 &&
              lines == stopped && strstr(stderr_text, "File too large"),
          "a record that fills its 16 kB: stopped at input line %ld of 400 (%g read), exit %d (1)",
          stopped, lines, WIFEXITED(status) ? WEXITSTATUS(status) : -1);
}

/* Two named rods: lines alternate between them (100 Hz each rod, 50 Hz a
 * rod), each tip moved 0.2 s to a pose of its own then held to t = 5 s;
 * the last answer of each rod: its tip force -rho A g L (the swing damped
 * near critically, 1e-8 of it left). Then bad names, and --rod. */
static void test_several_rods(void)
{
    if (!check(hanging_rods_write(test_path("rods.ini")) == 0, "wrote the two rods' scene")) return;
    live_proc p;
    const char *args[] = {test_path("rods.ini"), "--rod", "long", NULL};
    alarm(120);
    if (!check(live_start(&p, args) == 0, "rodsim live of two rods started")) return;
    char answer[8192], line[256];
    int header = fgets(answer, sizeof answer, p.out) != NULL &&
                 strcmp(answer, "rod,t,fx,fy,fz,mx,my,mz,status\n") == 0;
    check(header, "header line rod,t,fx,fy,fz,mx,my,mz,status: %s", answer);
    const char *names[2] = {"short", "long"};
    const double length[2] = {0.3, 0.5};
    const double start[2][3] = {{0, 0, 0}, {0.2, 0, 0}}, goal[2][3] = {{0.01, 0, 0.02},
                                                                       {0.2, -0.015, 0.01}};
    double force[2][3] = {{0}};
    int answered = 0;
    for (int i = 1; i <= 500; i++) {
        const int k = i % 2 == 1 ? 0 : 1;
        const double f = i >= 20 ? 1.0 : i / 20.0;
        snprintf(line, sizeof line, "%s:%.2f,%.17g,%.17g,%.17g\n", names[k], i * 0.01,
                 start[k][0] + f * (goal[k][0] - start[k][0]),
                 start[k][1] + f * (goal[k][1] - start[k][1]),
                 start[k][2] + f * (goal[k][2] - start[k][2]));
        if (exchange(&p, line, answer, sizeof answer)) break;
        char rod[32] = "", status[32] = "";
        double t, v[6];
        if (sscanf(answer, "%31[^,],%lf,%lf,%lf,%lf,%lf,%lf,%lf,%31s", rod, &t, &v[0], &v[1],
                   &v[2], &v[3], &v[4], &v[5], status) == 9 &&
            strcmp(rod, names[k]) == 0 && fabs(t - i * 0.01) < 1e-12 &&
            strcmp(status, "ok") == 0) {
            answered++;
            memcpy(force[k], v, sizeof force[k]);
        }
    }
    check(answered == 500, "500 lines naming short and long in turn, each answered ok with its "
                           "rod's name and t: %d", answered);
    for (int k = 0; k < 2; k++) {
        const double weight = hanging_rod_weight(length[k], 1000.0);
        printf("rod %s at rest: tip force %.12g %.12g %.12g N; rho A g L = %.12g N\n", names[k],
               force[k][0], force[k][1], force[k][2], weight);
        check_rel(k ? "rod long's answer -fz at rest, N: rho A g L (0.5 m)"
                    : "rod short's answer -fz at rest, N: rho A g L (0.3 m)",
                  -force[k][2], weight, 1e-6);
        check_abs("its horizontal force, N", hypot(force[k][0], force[k][1]), 0.0,
                  1e-6 * weight);
    }
    /* no name: --rod long's; a name the scene lacks: refused, named */
    exchange(&p, "5.01,0.2,-0.015,0.01\n", answer, sizeof answer);
    check(strncmp(answer, "long,5.01,", 10) == 0 && strstr(answer, ",ok\n"),
          "a line without a name drives --rod long: %s", answer);
    exchange(&p, "middle:5.02,0,0,0\n", answer, sizeof answer);
    check(strncmp(answer, ",5.01,0,0,0,0,0,0,bad_input", 27) == 0,
          "a line naming rod middle: answered bad_input with no name: %s", answer);
    exchange(&p, "short:5.02,0,0,0,1,0,0\n", answer, sizeof answer);
    check(strncmp(answer, "short,5.01,", 11) == 0 && strstr(answer, ",bad_input\n"),
          "a rotation for short's pinned tip: bad_input: %s", answer);
    fwrite("short:5.02,0,0,0\0x\n", 1, 19, p.in); /* a NUL within the line */
    fflush(p.in);
    if (!fgets(answer, sizeof answer, p.out)) answer[0] = '\0';
    check(strncmp(answer, ",5.01,", 6) == 0 && strstr(answer, ",bad_input\n"),
          "a line holding a NUL byte: bad_input: %s", answer);
    check(live_finish(&p) == 0, "exit 0 at the end of input");
    read_stderr();
    check(strstr(stderr_text, "input line 504: a NUL byte") != NULL, "line 504: a NUL byte");
    check(strstr(stderr_text, "input line 502: no rod named 'middle'; accepted: short, long") !=
              NULL,
          "the message names line 502 and the accepted rods: %s", stderr_text);
    check(strstr(stderr_text, "input line 503: 4 numbers") == NULL &&
              strstr(stderr_text, "input line 503: 7 numbers; accepted for rod short: t,x,y,z"),
          "and the pinned tip's accepted numbers");
    /* --rod a name the scene lacks, refused before any line */
    char out[4096];
    const char *bad_rod[] = {"live", test_path("rods.ini"), "--rod", "middle", NULL};
    int rc = test_run_rodsim_within(bad_rod, 30, out, sizeof out);
    check(rc == 2 && strstr(out, "--rod middle:") && strstr(out, "its rods: short, long"),
          "--rod middle: exit %d (2): %s", rc, out);
    /* one bare [rod]: its name is rod */
    const char *one[] = {test_path("hang.ini"), NULL};
    if (live_start(&p, one) == 0) {
        fgets(answer, sizeof answer, p.out);
        char first[256] = "", second[256] = "";
        exchange(&p, "rod:0.001,0,0,0.5\n", first, sizeof first);
        exchange(&p, "thread:0.002,0,0,0.5\n", second, sizeof second);
        check(strstr(first, ",ok\n") && strstr(second, ",bad_input\n"),
              "one bare [rod]: rod: is its name (%s), thread: is refused (%s)", first, second);
        live_finish(&p);
        read_stderr();
        check(strstr(stderr_text, "input line 2: no rod named 'thread'; accepted: rod") != NULL,
              "naming line 2 and the accepted name");
    }
    alarm(0);
}

/* A free tip of one of several rods, driven by its loads: a rod clamped at
 * its root at z = 0 hanging down, a tip force of 10 mN down ramped in over
 * 0.2 s; its root carries its weight and the force, rho A g L + F. */
static void test_several_rods_loads(void)
{
    FILE *f = fopen(test_path("loaded.ini"), "w");
    if (!f) return;
    fputs(HANGING_RODS_SCENE "[tip long]\nframe = global\n", f);
    fclose(f);
    live_proc p;
    const char *args[] = {test_path("loaded.ini"), "--set", "ends long.root=clamped", "--set",
                          "ends long.tip=free", "--set", "rod long.origin=0.2 0 0", "--set",
                          "rod long.direction=0 0 -1", NULL};
    alarm(120);
    if (!check(live_start(&p, args) == 0, "rodsim live of a held and a loaded rod started"))
        return;
    char answer[8192], line[256];
    if (!fgets(answer, sizeof answer, p.out)) answer[0] = '\0';
    double fz = 0.0, fx = 1.0;
    int answered = 0;
    for (int i = 1; i <= 300; i++) {
        if (i % 2) snprintf(line, sizeof line, "long:%.2f,0,0,%.17g,0,0,0\n", i * 0.01,
                            -0.01 * (i >= 20 ? 1.0 : i / 20.0));
        else snprintf(line, sizeof line, "short:%.2f,0,0,0\n", i * 0.01);
        if (exchange(&p, line, answer, sizeof answer)) break;
        char status[32] = "";
        if (i % 2 && sscanf(answer, "long,%*f,%lf,%*f,%lf,%*f,%*f,%*f,%31s", &fx, &fz,
                            status) == 3 && strcmp(status, "ok") == 0)
            answered++;
    }
    exchange(&p, "long:3.01,0,0,0\n", answer, sizeof answer);
    check(answered == 150 && strstr(answer, ",bad_input\n"),
          "150 load lines to rod long answered ok (%d); 4 numbers to it refused: %s", answered,
          answer);
    const double expected = hanging_rod_weight(0.5, 1000.0) + 0.01;
    check_rel("rod long's root at rest (-fz, N): rho A g L + 10 mN of tip load", -fz, expected,
              1e-6);
    check_abs("its horizontal force, N", fx, 0.0, 1e-6 * expected);
    check(live_finish(&p) == 0, "exit 0 at the end of input");
    read_stderr();
    check(strstr(stderr_text, "accepted for rod long: t,fx,fy,fz,mx,my,mz") != NULL,
          "the message names the free tip's numbers");
    alarm(0);
}

int main(void)
{
    signal(SIGPIPE, SIG_IGN);
    test_dir(); /* made now: the shell commands name it $RODSIM_TEST_DIR */
    FILE *f = fopen(test_path("hang.ini"), "w");
    if (!f) return 1;
    fputs(scene_text, f);
    fclose(f);
    char out[4096];
    const char *help[] = {"live", "--help", NULL};
    int rc = test_run_rodsim_within(help, 30, out, sizeof out);
    int lines = 0;
    for (const char *c = out; *c; c++) lines += *c == '\n';
    check(rc == 0 && lines <= 20, "rodsim live --help: exit 0, %d lines (at most 20)", lines);
    test_hanging_weight_lockstep();
    test_several_rods();
    test_several_rods_loads();
    test_bad_lines();
    test_one_step_per_line();
    test_fifos();
    test_realtime();
    test_replay();
    test_driver();
    test_free_tip_loads();
    test_failed_step();
    test_contact_live();
    test_pose_beyond_reach();
    test_beyond_reach_replay();
    test_far_ahead();
    test_signal_within_line();
    test_line_bytes();
    test_repeated_message();
    test_unreadable_input();
    test_record_write_error();
    return test_finish();
}
