/* test_pile_planar.c: the pile of test_pile.c fed straight down (the clamp
 * descends along the rope's own plane, from 1.55 m to 0.30 m above the floor
 * in 10 s, then holds) at NS = 301 (ds = d), floor friction 0.3, strands'
 * friction 0.3 and 0, 12 s at 1/60 s. Its strand pressed to the floor by the
 * strands above turns nodes between stick and slip at most Newton
 * iterations; the stall test split such steps, and at the halves' smaller
 * dt a resting node's sink over the step (g dt^2) fell below the iterates'
 * error: the run stopped at t = 4.45 s (strands' friction 0.3) and 4.93 s
 * (0). The last retry lets Newton run past the stall test at the step's dt
 * (newton.h's PATIENT_FACTOR; docs/decisions/0072-pile-planar.md).
 *
 * Checked at the end (12 s) of each variant: every step converged; no node
 * below the floor by more than 1 % of the radius (the contact's own bound);
 * no two non-neighbouring strands closer than 0.95 d; every segment ds long
 * to 1e-9; and the height of the pile (the rope beyond its first point on
 * the floor: the clamp's strand hangs to it) between 1.5 d (a strand lies
 * on another somewhere: 1.2 m of rope on a floor under a clamp 0.3 m high
 * cannot lie as one straight strand within the coil it makes) and the bound
 * H = (L_p / (2 pi l_g) + 1/2) d, l_g = (EI / (rho A g))^(1/3): a rope fed
 * onto a floor lays loops no smaller than its elastogravity length (a loop
 * tighter than l_g bends more than its weight can hold down), so at most
 * L_p / (2 pi l_g) loops stack over any point of the floor, L_p <= L - 0.30 m
 * the rope on it; the top strand's centreline d / 2 above the one below. The
 * rope need not stay in its plane: fed onto the floor it coils out of it. */
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
#define LENGTH 1.5
#define CLAMP_LOW 0.30 /* m: the clamp's last height above the floor */

/* The highest centreline point of the rope beyond its first node on the
 * floor (within 0.1 d of resting on it), m; -1 when none touches it */
static double pile_height(const rod_model *m, const rod_state *s)
{
    const double r = 0.5 * DIAMETER;
    int first = -1;
    for (int i = 0; i < m->nodes && first < 0; i++)
        if (s->position[3 * i + 2] < r + 0.1 * DIAMETER) first = i;
    if (first < 0) return -1.0;
    double highest = -INFINITY;
    for (int i = first; i < m->nodes; i++) highest = fmax(highest, s->position[3 * i + 2]);
    return highest;
}

static void pile(const char *root_csv, double rope_friction)
{
    char text[2048], err[1024] = "";
    snprintf(text, sizeof text,
             "[rod]\nlength = %g\ndiameter = %g\ndensity = 990\nyoungs_modulus = 1e6\n"
             "shear_modulus = 3.4e5\nnodes = 301\norigin = 0 0 1.55\ndirection = 0.02 0 -1\n"
             "friction = %g\n[ends]\nroot = clamped\ntip = free\nroot_motion = %s\n"
             "[solver]\nscheme = implicit\ndt = 0.0166666666667\nduration = 12\n"
             "[loads]\ngravity = 0 0 -9.81\nlinear_damping = 0.5\n"
             "[surface]\nshape = plane\ncenter = 0 0 0\nnormal = 0 0 1\nfriction = 0.3\n",
             LENGTH, DIAMETER, rope_friction, root_csv);
    rod_model m;
    ini_doc *doc = ini_parse("pile_planar.ini", text, err, sizeof err);
    int ok = doc && scene_read_rod(doc, &m, err, sizeof err) == 0;
    ini_destroy(doc);
    if (!check(ok, "the planar pile scene reads %s", err)) return;
    printf("-- NS 301, floor friction 0.3, strands' friction %g\n", rope_friction);
    rod_state *s = rod_state_create(&m);
    rod_state_reset(&m, s);
    rod_solver solver = {0};
    rod_report report = {0};
    ok = rod_solver_init(&solver, &m, err, sizeof err) == 0;
    /* as rodsim run steps it: two equal steps per output interval of 1/30 s,
     * the time set to the interval's end after them */
    int steps = 0;
    const double interval = 1.0 / 30.0, dt = interval / 2.0;
    for (int k = 1; ok && k <= 360; k++) {
        for (int j = 0; ok && j < 2; j++, steps++)
            ok = rod_solver_step(&solver, &m, s, dt, &report) == ROD_OK;
        s->time = k * interval;
    }
    check(ok, "the rope is fed onto the floor for 12 s: %d steps converged %s", steps,
          ok ? "" : report.message);
    printf("   warning: %s\n", report.warning[0] ? report.warning : "(none)");
    if (ok) {
        const double r = 0.5 * DIAMETER;
        double lowest = INFINITY;
        for (int i = 0; i < m.nodes; i++) lowest = fmin(lowest, s->position[3 * i + 2]);
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
        /* the bound: EI = E pi d^4 / 64, weight per length rho A g */
        const double area = M_PI * DIAMETER * DIAMETER / 4.0;
        const double ei = 1e6 * M_PI * pow(DIAMETER, 4) / 64.0, weight = 990.0 * area * 9.81;
        const double lg = cbrt(ei / weight), on_floor = LENGTH - CLAMP_LOW;
        const double bound = (on_floor / (2.0 * M_PI * lg) + 0.5) * DIAMETER;
        const double height = pile_height(&m, s);
        check(height >= 1.5 * DIAMETER && height <= bound,
              "pile height: computed %.3f d, reference 1.5 d .. %.3f d (l_g = %.4f m, %.3f m "
              "on the floor at most), relative error to the bound %.3f",
              height / DIAMETER, bound / DIAMETER, lg, on_floor, (height - bound) / bound);
    }
    rod_solver_release(&solver);
    rod_state_destroy(s);
    rod_model_release(&m);
}

int main(void)
{
    char dir[] = "/tmp/rodsim_pile_planar_XXXXXX", path[256];
    if (!check(mkdtemp(dir) != NULL, "temporary directory")) return test_finish();
    snprintf(path, sizeof path, "%s/root.csv", dir);
    FILE *f = fopen(path, "w");
    if (f) {
        /* the clamp comes straight down, in the rope's plane */
        fprintf(f, "t,x,y,z\n0,0,0,1.55\n10,0,0,%g\n", CLAMP_LOW);
        fclose(f);
    }
    pile(path, 0.3);
    pile(path, 0.0);
    unlink(path);
    rmdir(dir);
    return test_finish();
}
