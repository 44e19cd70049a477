/* test_jacobian.c: the implicit scheme's Jacobian in closed form against
 * its finite differences (independent: only residual evaluations) on every
 * kind of end, both thetas, follower and dead tip loads, rotary inertia on
 * and off, at a state some steps into each run and away from it. A wrong
 * term shows as an error of order 1; the differences' own error is near
 * 1e-7 of a column's largest entry. Then the whole Jacobian Newton uses
 * with contact (the rod's part and contact's, friction and punctures
 * included) against differences of the whole residual, with a thread on
 * a skin pad and in the running suture while the needle pulls thread
 * through its punctures (contact_cases). Graded grids (rod.refine) too. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "base/ini.h"
#include "sim/rod.h"
#include "sim/scene.h"
#include "sim/scheme_implicit.h"
#include "test.h"

#define SCENES RODSIM_SOURCE_DIR "/scenes"
#define TOLERANCE 1e-6
#define FLOOR_LIMIT 1e-2 /* the comparison means something only above it */

typedef struct jacobian_case {
    const char *scene;
    const char *set[10]; /* overrides, NULL-terminated */
    int steps;          /* taken before the comparison */
} jacobian_case;

static const jacobian_case cases[] = {
    {"impulse.ini", {"physics.planar=off", NULL}, 20},
    {"impulse.ini", {"physics.planar=off", "solver.theta=1", "physics.rotary_inertia=off", NULL}, 20},
    {"table2_450nN.ini", {"solver.scheme=implicit", "solver.dt=0.01", "physics.planar=off",
                          "tip.frame=director", NULL}, 30},
    {"table2_450nN.ini", {"solver.scheme=implicit", "solver.dt=0.01", "physics.planar=off",
                          "tip.frame=director", "solver.theta=0.5", "tip.moment=1e-7 -2e-7 3e-7", NULL}, 30},
    {"free_fall.ini", {NULL}, 40},
    {"needle_lift.ini", {NULL}, 200},
    {"clamped_buckling.ini", {NULL}, 40},
    {"suture_gravity.ini", {NULL}, 100},
    {"skin_drop.ini", {NULL}, 60},
    {"buckling_twist.ini", {"rod.nodes=41", NULL}, 400},
    {"suture.ini", {"solver.dt=0.005", NULL}, 300}, /* 1.5 s in: the thread on the skin */
    /* graded grids (rod.refine): each segment's own length and each node's cell */
    {"impulse.ini", {"physics.planar=off", "rod.self_contact=no", "rod.refine=0 0.2 5, 0.6 0.7 3",
                     NULL}, 20},
    {"table2_450nN.ini", {"solver.scheme=implicit", "solver.dt=0.01", "physics.planar=off",
                          "tip.frame=director", "solver.theta=0.5", "tip.moment=1e-7 -2e-7 3e-7",
                          "rod.self_contact=no", "rod.refine=0.1 0.3 8", NULL}, 30},
    {"impulse.ini", {"physics.planar=off", "rod.self_contact=no", "rod.refine=0.5 1 4",
                     "ends.root=pinned", "loads.gravity=0 -1e-3 0", "loads.linear_damping=1e-4",
                     NULL}, 20},
};

static int load(const jacobian_case *c, rod_model *m)
{
    char err[512], path[512];
    snprintf(path, sizeof path, "%s/%s", SCENES, c->scene);
    ini_doc *doc = ini_load(path, err, sizeof err);
    if (!doc) {
        printf("     %s\n", err);
        return -1;
    }
    int rc = 0;
    for (int k = 0; c->set[k] && rc == 0; k++) rc = ini_set(doc, c->set[k], err, sizeof err);
    if (rc == 0) rc = scene_read_rod(doc, m, err, sizeof err);
    if (rc) printf("     %s: %s\n", c->scene, err);
    ini_destroy(doc);
    return rc;
}

/* with contact: the error allowed (differences by steps of 1e-7 of each
 * unknown's size, through friction's steep creep region) */
#define CONTACT_TOLERANCE 1e-4

static const jacobian_case contact_cases[] = {
    {"skin_drop.ini", {NULL}, 60},
    {"suture.ini", {"solver.dt=0.005", NULL}, 1100}, /* 5.5 s in: two punctures, thread pulled */
    /* 0.09 s in at dt = 1/240 s from the unsettled U: the thread, springing
     * open, runs over the pad's near edge, and nodes meet its rounded edge
     * on their swept path (the hit point and normal turn with the iterate;
     * with them held fixed the closed form is off by 0.64 of a column) */
    {"suture.ini", {"solver.dt=0.00417", "rod.shape=suture_shape_u.csv", NULL}, 22},
    /* 1.5 s in: lifted by the forceps' grasp (a point carried by the jaws,
     * sliding beyond the grip), its ends dragged on the pads */
    {"grasp_lift.ini", {NULL}, 1500},
};

static void test_case(const jacobian_case *c, int with_contact)
{
    rod_model m;
    char label[256] = "", err[512];
    snprintf(label, sizeof label, "%s", c->scene);
    for (int k = 0; c->set[k]; k++) {
        strncat(label, " ", sizeof label - strlen(label) - 1);
        strncat(label, c->set[k], sizeof label - strlen(label) - 1);
    }
    if (!check(load(c, &m) == 0, "%s: the scene reads", label)) return;
    rod_state *s = rod_state_create(&m);
    rod_solver solver;
    int ok = s && rod_solver_init(&solver, &m, err, sizeof err) == 0;
    rod_report report;
    memset(&report, 0, sizeof report);
    for (int k = 0; ok && k < c->steps; k++)
        ok = rod_solver_step(&solver, &m, s, m.options.dt, &report) == ROD_OK;
    if (s && ok) rod_solver_release(&solver);
    if (check(ok, "%s: %d steps run (%s)", label, c->steps, ok ? "ok" : report.message)) {
        for (int p = 0; p < 2; p++) {
            const double perturb = p ? 0.3 : 0.0;
            int column;
            double floor;
            const double moved = with_contact ? 0.01 * perturb : perturb;
            const double tolerance = with_contact ? CONTACT_TOLERANCE : TOLERANCE;
            double e = with_contact
                           ? rod_implicit_contact_jacobian_error(&m, s, m.options.dt, moved, &column, &floor)
                           : rod_implicit_jacobian_error(&m, s, m.options.dt, moved, &column, &floor);
            check(isfinite(e) && e <= tolerance && floor <= FLOOR_LIMIT,
                  "%s%s at t = %g s (%d punctures), iterate moved by %g: closed form vs central "
                  "differences, largest difference %.3e of its column's largest entry (column %d; "
                  "tolerance %.0e; the differences' rounding resolves %.1e of it, limit %.0e)",
                  label, with_contact ? ", with contact" : "", s->time, s->puncture_count, moved, e,
                  column, tolerance, floor, FLOOR_LIMIT);
        }
    }
    rod_state_destroy(s);
    rod_model_release(&m);
}

int main(void)
{
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) test_case(&cases[k], 0);
    for (size_t k = 0; k < sizeof contact_cases / sizeof contact_cases[0]; k++)
        test_case(&contact_cases[k], 1);
    return test_finish();
}
