/* bench_live.c: `rodsim live` latency (issue 13), run by `make bench`, never
 * a test (it measures wall time). A thread hanging from its driven clamped
 * tip follows tests/live_driver.h's needle-holder path at 1 kHz through
 * pipes; for NS = 51 and 101 it prints the latency from writing a line to
 * reading its answer (p50, p99, p99.9, max) and the answers later than one
 * period (1 ms, overruns), beside rodsim's own account of the work per line
 * (parse + step + format; the rest of the latency is the pipes and the
 * scheduler). The 60 s per point would make `make bench` long: the
 * duration is BENCH_LIVE_SECONDS (default 10 s). Targets (issue 13): p99 at
 * most 200 us at NS = 51 without contact. No contact or knot yet. */
#include "live_driver.h"

int main(void)
{
    const char *env = getenv("BENCH_LIVE_SECONDS");
    double seconds = env ? atof(env) : 10.0;
    if (!(seconds > 0.0)) seconds = 10.0;
    const char *scene = "/tmp/rodsim_bench_live.ini";
    FILE *f = fopen(scene, "w");
    if (!f) return 1;
    fputs("[rod]\nlength = 0.5\ndiameter = 0.001\ndensity = 1000\nyoungs_modulus = 87.5e6\n"
          "shear_modulus = 31.25e6\nnodes = 51\ndirection = 0 0 1\n"
          "[solver]\nscheme = implicit\ndt = 0.001\nduration = 1\n"
          "[loads]\ngravity = 0 0 -9.81\n[ends]\nroot = free\ntip = clamped\n", f);
    fclose(f);
    printf("bench_live: rodsim live at 1 kHz through pipes, %g s per point "
           "(BENCH_LIVE_SECONDS), thread hanging from its driven tip, dt = 1 ms\n", seconds);
    printf("%5s %8s %9s %9s %9s %9s %9s  %s\n", "NS", "lines", "p50 us", "p99 us", "p99.9 us",
           "max us", "overruns", "rodsim: steps, Jacobian builds, work per line");
    const int sizes[2] = {51, 101};
    int status = 0;
    for (int i = 0; i < 2; i++) {
        char set[64], log[] = "/tmp/rodsim_bench_live_stderr.txt";
        snprintf(set, sizeof set, "rod.nodes=%d", sizes[i]);
        char *argv[] = {RODSIM_BIN, "live", (char *)scene, "--set", set, NULL};
        const double start[3] = {0.0, 0.0, 0.5};
        live_driver_result r;
        if (live_driver_play(argv, start, seconds, 1000.0, log, &r)) status = 1;
        char work[512] = "";
        /* "N steps to t = T s (J Jacobian builds); work per line ..." */
        FILE *e = fopen(log, "r");
        char line[512];
        while (e && fgets(line, sizeof line, e)) {
            char *w = strstr(line, "steps to");
            if (w) snprintf(work, sizeof work, "%s", w);
        }
        if (e) fclose(e);
        remove(log);
        work[strcspn(work, "\n")] = '\0';
        printf("%5d %8ld %9.1f %9.1f %9.1f %9.1f %9ld  %s\n", sizes[i], r.answered, 1e6 * r.p50,
               1e6 * r.p99, 1e6 * r.p999, 1e6 * r.max, r.late, work);
        if (r.failed) printf("      (%ld steps failed)\n", r.failed);
    }
    remove(scene);
    return status;
}
