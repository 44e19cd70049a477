/* bench_live.c: `rodsim live` latency, run by `make bench`, never
 * a test (it measures wall time). A thread hanging from its driven clamped
 * tip follows tests/live_driver.h's needle-holder path at 1 kHz through
 * pipes; for NS = 51 and 101, without contact and with tissue contact, it
 * prints the latency from writing a line to reading its answer (p50, p99,
 * p99.9, max) and the answers later than one period (1 ms, overruns),
 * beside rodsim's own account of the work per line (its distribution, and
 * the mean parse, step and answer: the rest of the latency is the pipes and
 * the scheduler). With tissue, the thread's lower 3 cm lie on a tissue
 * plane (an arc of radius 3 cm turns it up to the holder), dragged with
 * friction 0.3 as the holder moves. Each point runs twice: as an ordinary
 * process, and as a haptic rig would run it, rodsim with --realtime (memory
 * locked, SCHED_FIFO, pinned) and this driver at the same real-time
 * priority on the same CPU (when permitted: root or CAP_SYS_NICE; otherwise
 * the line says n/a). The 60 s per point would make
 * `make bench` long: the duration is BENCH_LIVE_SECONDS (default 10 s).
 * Targets: p99 at most 200 us at NS = 51 without contact, at most
 * 1 ms at NS = 101 with tissue contact. The knot (a loose overhand knot
 * hanging from the driven tip, held by self-contact with friction 0.2,
 * settled 0.2 s before t = 0: rod.settle) has no target in the issue; it is
 * measured to say what a knot costs.
 * `bench_live knot`: the knot's two points alone.
 * The pad (`bench_live pad` alone): scenes/wound_closure.ini, its elastic
 * skin pad and stitch, the thread's tip (pinned) driven at 1 kHz along the
 * scene's pull (2 mm up over 2 s) with the holder's hand wavering 1 mm
 * along the wound at 2 Hz; besides the latency, rodsim's CPU per line (p50,
 * p99, max) and its split (the pad: assembly, factorisations, solves; the
 * rod); the target: p99 below 5 ms of CPU a line. */
#define _GNU_SOURCE /* sched_setaffinity, sched_getcpu */
#include <sched.h>

#include "live_driver.h"
#include "test.h"

/* The pad point's tip: wound_closure's pinned tip at rest, pulled 2 mm up
 * over 2 s (smoothstep, as wound_closure_tip.csv), wavering 1 mm along x
 * (the wound's direction) at 2 Hz after a 0.2 s ramp, m. */
static void pad_pull(double t, const double start[3], double pos[3], double rot[3])
{
    const double s = t < 2.0 ? t / 2.0 : 1.0, r = t < 0.2 ? t / 0.2 : 1.0;
    pos[0] = start[0] + 0.001 * r * r * (3.0 - 2.0 * r) * sin(4.0 * M_PI * t);
    pos[1] = start[1];
    pos[2] = start[2] + 0.002 * s * s * (3.0 - 2.0 * s);
    rot[0] = rot[1] = rot[2] = 0.0;
}

/* The tissue setting's starting centreline: 3 cm along x on the plane z = 0,
 * a quarter circle of radius 3 cm up, then straight up to z = 0.45 m; its
 * polyline length (the scene's rod length) and its upper end (the driven
 * tip's start, m), written to path. -1 when the file cannot be written. */
static int write_tissue_shape(const char *path, double *length, double tip[3])
{
    FILE *f = fopen(path, "w");
    if (!f) return -1;
    const double flat = 0.03, radius = 0.03, top = 0.45;
    double prev[3] = {0.0, 0.0, 0.0};
    *length = 0.0;
    fprintf(f, "x,y,z\n0,0,0\n");
    for (int k = 0; k <= 400; k++) {
        double p[3];
        if (k <= 100) { /* flat, then the arc, then straight up */
            p[0] = flat * k / 100.0, p[1] = 0.0, p[2] = 0.0;
        } else if (k <= 300) {
            double a = 0.5 * M_PI * (k - 100) / 200.0;
            p[0] = flat + radius * sin(a), p[1] = 0.0, p[2] = radius * (1.0 - cos(a));
        } else {
            p[0] = flat + radius, p[1] = 0.0, p[2] = radius + (top - radius) * (k - 300) / 100.0;
        }
        if (k == 0) continue;
        *length += sqrt((p[0] - prev[0]) * (p[0] - prev[0]) + (p[2] - prev[2]) * (p[2] - prev[2]));
        fprintf(f, "%.17g,%.17g,%.17g\n", p[0], p[1], p[2]);
        memcpy(prev, p, sizeof prev);
    }
    memcpy(tip, prev, sizeof prev);
    return fclose(f) ? -1 : 0;
}

int main(int argc, char **options)
{
    /* bench_live knot | pad: the knot's or the pad's two points alone */
    const int knot_only = argc > 1 && strcmp(options[1], "knot") == 0;
    const int pad_only = argc > 1 && strcmp(options[1], "pad") == 0;
    const char *pad_scene = RODSIM_SOURCE_DIR "/scenes/wound_closure.ini";
    const double pad_tip[3] = {0.0, 0.004, 0.00955083344}; /* wound_closure_tip.csv at t = 0 */
    const char *env = getenv("BENCH_LIVE_SECONDS");
    double seconds = env ? atof(env) : 10.0;
    if (!(seconds > 0.0)) seconds = 10.0;
    const char *scene = test_path("hanging.ini"), *tissue = test_path("tissue.ini");
    const char *shape = test_path("tissue_shape.csv"), *knot_shape = test_path("knot_shape.csv");
    const char *common = "diameter = 0.001\ndensity = 1000\nyoungs_modulus = 87.5e6\n"
                         "shear_modulus = 31.25e6\nnodes = 51\n"
                         "[solver]\nscheme = implicit\ndt = 0.001\nduration = 1\n"
                         "[loads]\ngravity = 0 0 -9.81\n[ends]\nroot = free\ntip = clamped\n";
    const char *knot = test_path("knotted.ini"), *log = test_path("stderr.txt");
    double length, tissue_tip[3], knot_length, knot_tip[3];
    FILE *f = fopen(scene, "w"), *g = fopen(tissue, "w"), *h = fopen(knot, "w");
    if (!f || !g || !h || write_tissue_shape(shape, &length, tissue_tip) ||
        live_driver_write_knot(knot_shape, &knot_length, knot_tip))
        return 1;
    /* the knot hangs from the driven tip; self-contact (friction 0.2) holds
     * it; drawn from a polynomial, it settles 0.2 s before t = 0 (rod.settle:
     * its strands snap from the drawn shape at ~3 m/s, and its fastest node
     * is at 3 mm/s after 0.2 s), so the session starts from a knot at rest */
    fprintf(h, "[rod]\nlength = %.17g\nshape = %s\nsettle = 0.2\n%s", knot_length, knot_shape,
            common);
    fclose(h);
    fprintf(f, "[rod]\nlength = 0.5\ndirection = 0 0 1\n%s", common);
    /* the nodes' centres touch the plane at the radius */
    fprintf(g, "[rod]\nlength = %.17g\nshape = %s\n%s[surface]\nshape = plane\n"
               "center = 0 0 -0.0005\ntissue = yes\nfriction = 0.3\n", length, shape, common);
    fclose(f);
    fclose(g);
    printf("bench_live: rodsim live at 1 kHz through pipes, %g s per point "
           "(BENCH_LIVE_SECONDS), thread hanging from its driven tip, dt = 1 ms\n", seconds);
    printf("%5s %7s %4s %8s %9s %9s %9s %9s %9s  %s\n", "NS", "contact", "rt", "lines", "p50 us",
           "p99 us", "p99.9 us", "max us", "overruns",
           "rodsim: steps, Jacobian builds, work per line");
    /* tissue: 0 none, 1 tissue, 2 a knot (self-contact), 3 the elastic pad */
    const struct { int nodes, tissue; } points[] = {{51, 0}, {101, 0}, {51, 1}, {101, 1}, {101, 2},
                                                    {49, 3}};
    int status = 0;
    for (size_t i = 0; i < 2 * sizeof points / sizeof points[0]; i++) {
        const int p = (int)(i / 2), realtime = (int)(i % 2);
        if ((knot_only && points[p].tissue != 2) || (pad_only && points[p].tissue != 3)) continue;
        char set[64];
        snprintf(set, sizeof set, "rod.nodes=%d", points[p].nodes);
        const char *which = points[p].tissue == 3   ? pad_scene
                            : points[p].tissue == 2 ? knot
                            : points[p].tissue      ? tissue
                                                    : scene;
        char *argv[] = {RODSIM_BIN, "live", (char *)which, "--set", set,
                        realtime ? "--realtime" : NULL, NULL};
        /* rt: this driver at SCHED_FIFO 10 on the CPU it runs on; rodsim
         * inherits both (its --realtime pins it where it starts): in
         * lock-step, one CPU passes each line and answer by a context
         * switch, where two CPUs need a wake-up across (an IPI, some 30 us
         * more a round trip in this virtual machine) */
        struct sched_param rt = {.sched_priority = 10}, normal = {.sched_priority = 0};
        cpu_set_t all, one;
        CPU_ZERO(&one);
        CPU_SET(sched_getcpu() >= 0 ? sched_getcpu() : 0, &one);
        int rt_granted = realtime && sched_getaffinity(0, sizeof all, &all) == 0 &&
                         sched_setaffinity(0, sizeof one, &one) == 0 &&
                         sched_setscheduler(0, SCHED_FIFO, &rt) == 0;
        const double hanging[3] = {0.0, 0.0, 0.5};
        live_driver_result r;
        const double *start = points[p].tissue == 3   ? pad_tip
                              : points[p].tissue == 2 ? knot_tip
                              : points[p].tissue      ? tissue_tip
                                                      : hanging;
        const int played = points[p].tissue == 3
                               ? live_driver_play_path(argv, pad_pull, 4, start, seconds, 1000.0, log, &r)
                               : live_driver_play(argv, start, seconds, 1000.0, log, &r);
        if (played) status = 1;
        if (realtime) {
            sched_setscheduler(0, SCHED_OTHER, &normal);
            sched_setaffinity(0, sizeof all, &all);
        }
        char work[1024] = "", pad[1024] = "";
        /* "N steps to t = T s (J Jacobian builds: W within steps, I between
         * lines, mean X us); work per line ..." */
        FILE *e = fopen(log, "r");
        char line[1024];
        while (e && fgets(line, sizeof line, e)) {
            char *w = strstr(line, "steps to");
            if (w) snprintf(work, sizeof work, "%s", w);
            char *q = strstr(line, "the pad at");
            if (q) snprintf(pad, sizeof pad, "%s", q);
        }
        if (e) fclose(e);
        remove(log);
        work[strcspn(work, "\n")] = '\0';
        pad[strcspn(pad, "\n")] = '\0';
        printf("%5d %7s %4s %8ld %9.1f %9.1f %9.1f %9.1f %9ld  %s\n", points[p].nodes,
               points[p].tissue == 3 ? "pad" : points[p].tissue == 2 ? "knot" : points[p].tissue ? "tissue" : "none", !realtime ? "no" : rt_granted ? "yes" : "n/a",
               r.answered, 1e6 * r.p50, 1e6 * r.p99, 1e6 * r.p999, 1e6 * r.max, r.late, work);
        if (r.failed) printf("      (%ld steps failed)\n", r.failed);
        if (pad[0]) printf("      %s\n", pad);
    }
    test_dir_remove();
    return status;
}
