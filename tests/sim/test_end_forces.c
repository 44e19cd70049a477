/* test_end_forces.c: one sign convention for the forces at the ends.
 *
 * A rod hangs under gravity from a clamp, once held at its root (the rod
 * below it along -z) and once held at its tip (the rod below it, root free).
 * Either way the support carries the weight W = rho A g L, and:
 *   - rod_state.end_force[e] (the summary's "support" lines, --summary's
 *     ends) is the force the rod exerts on that support: -W z at both ends;
 *   - the CSV's nx,ny,nz is the internal force N(s), the force the part of
 *     the rod beyond s (towards the tip) exerts on the part before it: at the
 *     root N(0) = what the rod exerts on its support (-W z), at the tip
 *     N(L) = what the support exerts on the rod (+W z). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/ini.h"
#include "sim/rod.h"
#include "sim/scene.h"
#include "test.h"

static int read_text(const char *text, rod_model *m, char *err, size_t errlen)
{
    ini_doc *doc = ini_parse("hanging.ini", text, err, errlen);
    if (!doc) return -1;
    int rc = scene_read_rod(doc, m, err, errlen);
    ini_destroy(doc);
    return rc;
}

/* Hangs the rod (held at `end`) and checks both conventions there. */
static void hang(int held_tip, const char *scheme)
{
    char text[1024], err[1024] = "";
    snprintf(text, sizeof text,
             "[rod]\nlength = 0.5\ndiameter = 0.001\ndensity = 1000\nyoungs_modulus = 1e8\n"
             "shear_modulus = 3.8e7\nnodes = 21\norigin = 0 0 %s\ndirection = 0 0 %s\n"
             "[ends]\nroot = %s\ntip = %s\n[solver]\nscheme = %s\ndt = 0.01\nduration = 1\n"
             "[loads]\ngravity = 0 0 -9.81\nlinear_damping = 0.5\n",
             held_tip ? "-0.5" : "0", held_tip ? "1" : "-1", held_tip ? "free" : "clamped",
             held_tip ? "clamped" : "free", scheme);
    rod_model m;
    if (!check(read_text(text, &m, err, sizeof err) == 0, "hanging rod reads %s", err)) return;
    rod_state *s = rod_state_create(&m);
    rod_state_reset(&m, s);
    rod_solver solver = {0};
    rod_report report;
    int ok = rod_solver_init(&solver, &m, err, sizeof err) == 0;
    for (int k = 0; ok && k < 100; k++) ok = rod_solver_step(&solver, &m, s, 0.01, &report) == ROD_OK;
    check(ok, "%s, held at its %s: 100 steps %s", scheme, held_tip ? "tip" : "root",
          ok ? "" : report.message);
    if (ok) {
        const double weight = m.density * M_PI * 0.25 * m.diameter * m.diameter * 9.81 * m.length;
        const int e = held_tip ? 1 : 0, node = held_tip ? m.nodes - 1 : 0;
        double *internal = malloc((size_t)m.nodes * 3 * sizeof(double));
        rod_internal_force(s, internal);
        const double *support = s->end_force[e], *n = &internal[3 * node];
        char what[160];
        snprintf(what, sizeof what, "%s, held at its %s: the rod on its support, z (reference -W)",
                 scheme, held_tip ? "tip" : "root");
        check_rel(what, support[2], -weight, 1e-6);
        snprintf(what, sizeof what, "%s, held at its %s: CSV N at node %d, z (reference %sW)",
                 scheme, held_tip ? "tip" : "root", node, held_tip ? "+" : "-");
        check_rel(what, n[2], held_tip ? weight : -weight, 1e-6);
        check(fabs(support[0]) + fabs(support[1]) <= 1e-9 * weight &&
                  fabs(n[0]) + fabs(n[1]) <= 1e-9 * weight,
              "%s, held at its %s: no horizontal force (%.2e, %.2e N)", scheme,
              held_tip ? "tip" : "root", hypot(support[0], support[1]), hypot(n[0], n[1]));
        free(internal);
    }
    rod_solver_release(&solver);
    rod_state_destroy(s);
    rod_model_release(&m);
}

int main(void)
{
    hang(0, "implicit");
    hang(1, "implicit");
    hang(0, "static");
    hang(1, "static");
    return test_finish();
}
