/* bench_sweep.c: how `rodsim sweep` scales with --jobs ("Speed").
 * A benchmark: it reports, never fails on time.
 *
 * The sweep: scenes/impulse.ini (implicit Crank-Nicolson, dt 0.5 ms, 10 s)
 * at rod.length 0.8, 0.9, 1.0 x rod.nodes 21, 31: 6 points of 0.4 .. 0.9 s
 * CPU. Reported per --jobs N: the sweep's wall time, the CPU time of all its
 * processes (getrusage of the children), and the bound 1.1 x the
 * slowest point's CPU time x ceil(6 / min(N, cores)) plus the processes'
 * start-up (measured: a sweep of points that take no steps). On a shared
 * machine the wall time moves with the load; the CPU time does not. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "test.h"

#define SCENES RODSIM_SOURCE_DIR "/scenes/"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double children_cpu(void)
{
    struct rusage r;
    getrusage(RUSAGE_CHILDREN, &r);
    return (double)r.ru_utime.tv_sec + 1e-6 * (double)r.ru_utime.tv_usec +
           (double)r.ru_stime.tv_sec + 1e-6 * (double)r.ru_stime.tv_usec;
}

/* Runs the binary with args, its CSV into `csv`; wall and CPU seconds. */
static int run(const char *const *args, const char *csv, double *wall, double *cpu)
{
    const char *argv[32] = {RODSIM_BIN};
    int n = 1;
    for (int i = 0; args[i]; i++) argv[n++] = args[i];
    argv[n++] = "--csv";
    argv[n++] = csv;
    argv[n++] = "--quiet";
    argv[n] = NULL;
    double cpu0 = children_cpu(), start = now();
    pid_t pid = fork();
    if (pid == 0) {
        execv(RODSIM_BIN, (char *const *)argv);
        _exit(127);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    *wall = now() - start;
    *cpu = children_cpu() - cpu0;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/* The largest and the sum of the CSV's last numeric column before status
 * (cpu_s). */
static void point_cpu(const char *csv, double *slowest, double *total)
{
    FILE *f = fopen(csv, "r");
    char line[4096];
    *slowest = *total = 0.0;
    if (!f) return;
    if (!fgets(line, sizeof line, f)) line[0] = '\0';
    while (fgets(line, sizeof line, f)) {
        char *status = strstr(line, ",ok,");
        if (!status) continue;
        *status = '\0';
        char *comma = strrchr(line, ',');
        double cpu = comma ? strtod(comma + 1, NULL) : 0.0;
        *slowest = fmax(*slowest, cpu);
        *total += cpu;
    }
    fclose(f);
}

int main(void)
{
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    const char *csv = test_path("sweep.csv");
    double wall, cpu;
    /* start-up: 6 points that read the scene and take no steps */
    const char *empty[] = {"sweep", SCENES "table2_450nN.ini", "--set", "solver.duration=1e-9",
                           "--vary", "rod.nodes=5,6,7,8,9,10", "--measure", "steps", NULL};
    run(empty, csv, &wall, &cpu);
    double startup = wall;
    printf("rodsim sweep: 6 points of scenes/impulse.ini (rod.length 0.8..1.0 x rod.nodes 21, "
           "31), %ld cores\n", cores);
    printf("start-up of the sweep and its points (6 points of no steps): %.3f s\n", startup);
    printf("%6s %10s %10s %14s %14s %10s\n", "jobs", "wall [s]", "CPU [s]", "slowest pt [s]",
           "bound [s]", "wall/bound");
    double base = 0.0;
    for (int jobs = 1; jobs <= 2; jobs++) {
        char j[8];
        snprintf(j, sizeof j, "%d", jobs);
        const char *args[] = {"sweep", SCENES "impulse.ini", "--vary", "rod.length=0.8,0.9,1.0",
                              "--vary", "rod.nodes=21,31", "--measure", "tip_y,cpu_s",
                              "--jobs", j, NULL};
        if (run(args, csv, &wall, &cpu) != 0) {
            printf("%6d  failed\n", jobs);
            continue;
        }
        double slowest, total;
        point_cpu(csv, &slowest, &total);
        long lanes = jobs < cores ? jobs : cores;
        double bound = 1.1 * slowest * ceil(6.0 / (double)lanes) + startup;
        printf("%6d %10.3f %10.3f %14.3f %14.3f %10.2f\n", jobs, wall, cpu, slowest, bound,
               wall / bound);
        if (jobs == 1) base = wall;
        else printf("speed-up of --jobs 2 over --jobs 1: %.2f (CPU of the points: %.3f s)\n",
                    base / wall, total);
    }
    test_dir_remove();
    return 0;
}
