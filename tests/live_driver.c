/* live_driver.c: an example client of `rodsim live`, the shape
 * of a haptic rig's loop: it plays a needle-holder path at 1 kHz (paced by
 * the wall clock) into `rodsim live SCENE`, reads each answer before the
 * next line, and prints the last force and the latency write -> answer.
 *
 *   live_driver RODSIM SCENE SECONDS [X Y Z]
 *
 * X Y Z: the driven tip's starting position (m; default 0 0 0.5, the tip of
 * a 0.5 m thread hanging along z). The scene's tip must be clamped. Built by
 * the Makefile beside the tests (not a test itself); tests/cli/test_live.c
 * runs it briefly. C and POSIX only. */
#include "live_driver.h"

int main(int argc, char **argv)
{
    if (argc != 4 && argc != 7) {
        fprintf(stderr, "usage: live_driver RODSIM SCENE SECONDS [X Y Z]\n");
        return 2;
    }
    double start[3] = {0.0, 0.0, 0.5};
    if (argc == 7)
        for (int k = 0; k < 3; k++) start[k] = atof(argv[4 + k]);
    char *child[] = {argv[1], "live", argv[2], NULL};
    live_driver_result r;
    int rc = live_driver_play(child, start, atof(argv[3]), 1000.0, NULL, &r);
    printf("live_driver: %ld lines, %ld answered, %ld failed; last force (%.6g, %.6g, %.6g) N\n",
           r.lines, r.answered, r.failed, r.fx, r.fy, r.fz);
    printf("live_driver: latency p50 %.1f us, p99 %.1f us, p99.9 %.1f us, max %.1f us; "
           "%ld answers later than 1 ms\n",
           1e6 * r.p50, 1e6 * r.p99, 1e6 * r.p999, 1e6 * r.max, r.late);
    return rc == 0 && r.answered == r.lines && r.lines > 0 ? 0 : 1;
}
