/* test_pile.c: a rope fed onto a floor piles onto itself (cosseratbench's
 * "pile": a 1.5 m rope, d 5 mm, E 1 MPa, 990 kg/m^3, NS = 101, hanging from
 * a clamp that descends to 6 cm above a floor with friction 0.3, strands with
 * friction 0.3, gravity, backward Euler at 1/60 s, settling damping). The
 * strands then press each other into the floor: the floor must answer the
 * pair forces too (a node pressed by another strand used to sink with no
 * floor reaction, and Newton stalled at t = 4.2 s).
 *
 * Checked at the end (12 s): the run converged at every step; no node below
 * the floor by more than 1 % of the radius (the contact's own bound); no two
 * non-neighbouring strands closer than 0.95 d; every segment ds long to
 * 1e-9; and the rope lies as a pile: strands on strands (its highest point
 * past the first 15 cm above 1.5 d) but no tower (below 6 d). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/ini.h"
#include "sim/geometry/proximity.h"
#include "sim/rod.h"
#include "sim/scene.h"
#include "test.h"

#define DIAMETER 0.005

int main(void)
{
    char dir[] = "/tmp/rodsim_pile_XXXXXX", path[256], text[2048], err[1024] = "";
    if (!check(mkdtemp(dir) != NULL, "temporary directory")) return test_finish();
    snprintf(path, sizeof path, "%s/root.csv", dir);
    FILE *f = fopen(path, "w");
    if (f) {
        /* the clamp comes down, drifting a little sideways: a 3-D pile */
        fprintf(f, "t,x,y,z\n0,0,0,1.55\n10,0.03,0.05,0.06\n");
        fclose(f);
    }
    snprintf(text, sizeof text,
             "[rod]\nlength = 1.5\ndiameter = %g\ndensity = 990\nyoungs_modulus = 1e6\n"
             "shear_modulus = 3.4e5\nnodes = 101\norigin = 0 0 1.55\ndirection = 0.02 0 -1\n"
             "friction = 0.3\n[ends]\nroot = clamped\ntip = free\nroot_motion = %s\n"
             "[solver]\nscheme = implicit\ndt = 0.0166666666667\nduration = 12\n"
             "[loads]\ngravity = 0 0 -9.81\nlinear_damping = 0.5\n"
             "[surface]\nshape = plane\ncenter = 0 0 0\nnormal = 0 0 1\nfriction = 0.3\n",
             DIAMETER, path);
    rod_model m;
    ini_doc *doc = ini_parse("pile.ini", text, err, sizeof err);
    int ok = doc && scene_read_rod(doc, &m, err, sizeof err) == 0;
    ini_destroy(doc);
    if (!check(ok, "the pile scene reads %s", err)) return test_finish();
    rod_state *s = rod_state_create(&m);
    rod_state_reset(&m, s);
    rod_solver solver = {0};
    rod_report report = {0};
    ok = rod_solver_init(&solver, &m, err, sizeof err) == 0;
    int steps = 0;
    const double dt = 1.0 / 60.0;
    for (; ok && steps < 720; steps++)
        ok = rod_solver_step(&solver, &m, s, dt, &report) == ROD_OK;
    check(ok, "the rope is fed onto the floor for 12 s: %d steps converged %s", steps,
          ok ? "" : report.message);
    if (ok) {
        const double r = 0.5 * DIAMETER;
        double lowest = INFINITY, highest = -INFINITY;
        for (int i = 0; i < m.nodes; i++) {
            lowest = fmin(lowest, s->position[3 * i + 2]);
            if (i * m.ds > 0.15) highest = fmax(highest, s->position[3 * i + 2]);
        }
        check(lowest >= r * (1.0 - 0.01), "lowest node at z = %.6g m, the radius %.6g m less "
              "1 %% at most", lowest, r);
        rod_proximity *prox = rod_proximity_create(m.nodes);
        rod_segment_pair closest = {0};
        int found = prox ? rod_proximity_min(prox, s->position, m.nodes,
                                             rod_proximity_skip(m.diameter, m.ds), &closest)
                         : -1;
        rod_proximity_destroy(prox);
        check(found == 1 && closest.distance >= 0.95 * DIAMETER,
              "closest non-neighbouring strands %.4f d apart (segments %d and %d; >= 0.95 d)",
              closest.distance / DIAMETER, closest.i, closest.j);
        double stretch = rod_segment_length_error(&m, s);
        check(stretch <= 1e-9, "every segment ds long to %.2e (<= 1e-9)", stretch);
        check(highest >= 1.5 * DIAMETER && highest <= 6.0 * DIAMETER,
              "a pile: its highest point %.3f d above the floor (strands on strands, 1.5 d to "
              "6 d)", highest / DIAMETER);
    }
    rod_solver_release(&solver);
    rod_state_destroy(s);
    rod_model_release(&m);
    unlink(path);
    rmdir(dir);
    return test_finish();
}
