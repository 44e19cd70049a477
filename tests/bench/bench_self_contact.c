/* bench_self_contact.c: what self-contact costs per implicit step (issue
 * 12). A benchmark: it reports, never fails on time.
 *
 * A coil (D = 2 mm, E = 1 GPa, helix of radius 5 cm and pitch 1.01 D, one
 * and a half turns, NS = 201, root clamped) sagging under gravity along its
 * axis: its last half turn comes to lie on the first along ~50 segments.
 * Timed over steps 120 to 240 (dt = 1/240 s), CPU time per step (the process
 * clock), with self-contact and without (the same motion, the strands
 * passing through each other), Newton iterations per step and the pairs
 * touching, and the ratio of the two costs. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "base/vec3.h"
#include "sim/rod.h"
#include "test_helix.h"

static double cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct result {
    double per_step, iterations;
    int touching, ok;
} result;

static result run(int self_contact, int nodes)
{
    result r = {0.0, 0.0, 0, 0};
    rod_model m = rod_model_default();
    m.diameter = 0.002;
    m.density = 1100.0;
    m.youngs_modulus = 1e9;
    m.shear_modulus = 1e9 / 2.6;
    helix_model(&m, 0.05, 1.01 * m.diameter, M_PI * 0.05, nodes);
    m.linear_damping = 0.02;
    m.self_contact = self_contact;
    char err[256];
    if (rod_model_derive(&m, err, sizeof err)) {
        printf("  derive: %s\n", err);
        rod_model_release(&m);
        return r;
    }
    v3_set(m.distributed_force, 0.0, 0.0, -9.81 * m.mass_per_length);
    rod_state *s = rod_state_create(&m);
    rod_solver solver;
    if (!s || rod_solver_init(&solver, &m, err, sizeof err)) {
        printf("  create: %s\n", err);
        rod_state_destroy(s);
        rod_model_release(&m);
        return r;
    }
    helix_state(&m, s);
    rod_report report;
    memset(&report, 0, sizeof report);
    const double dt = 1.0 / 240.0;
    double t0 = 0.0;
    long its = 0;
    r.ok = 1;
    for (int k = 0; k < 240 && r.ok; k++) {
        if (k == 120) t0 = cpu();
        r.ok = rod_solver_step(&solver, &m, s, dt, &report) == ROD_OK;
        if (k >= 120) its += report.newton_iterations;
    }
    if (!r.ok) printf("  step: %s\n", report.message);
    r.per_step = (cpu() - t0) / 120.0;
    r.iterations = its / 120.0;
    for (int i = 0; i < m.nodes; i++) r.touching += v3_norm(&s->self_force[3 * i]) > 0.0;
    rod_solver_release(&solver);
    rod_state_destroy(s);
    rod_model_release(&m);
    return r;
}

int main(void)
{
    printf("self-contact: a sagging coil, its last half turn on its first (dt = 1/240 s)\n");
    const int sizes[2] = {101, 201};
    for (int k = 0; k < 2; k++) {
        result off = run(0, sizes[k]), on = run(1, sizes[k]);
        if (!off.ok || !on.ok) {
            printf("  NS = %d: a run failed\n", sizes[k]);
            continue;
        }
        printf("  NS = %4d  without: %8.1f us/step, %.2f Newton iterations\n", sizes[k],
               1e6 * off.per_step, off.iterations);
        printf("  NS = %4d  with:    %8.1f us/step, %.2f Newton iterations, %d nodes touching: "
               "%.2fx the step without\n", sizes[k], 1e6 * on.per_step, on.iterations, on.touching,
               on.per_step / off.per_step);
    }
    return 0;
}
