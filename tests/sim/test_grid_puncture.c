/* test_grid_puncture.c: a puncture on a graded grid (scene [rod] refine,
 * sim/rod_grid.h, sim/contact/puncture.h) against independent values:
 *   - where a point carried in arc length sits on a straight graded thread:
 *     s_j + alpha ds_j is the point's distance from the root (to rounding),
 *     continuous across the node where the spacing jumps, and the nearest
 *     arc length of a point of the thread is its distance from the root;
 *   - a thread drawn slowly through a puncture with friction, its turn at
 *     the hole 30 degrees, the hole sliding 20 mm across a node where the
 *     spacing halves: the root's tension against Coulomb's law at the hole
 *     (the force across the thread limits the friction along it), the
 *     thread's slide against the root's speed at every step (no jump in the
 *     puncture's arc length where it crosses a node), no jump in the
 *     puncture's force from step to step, and the root's tension against the
 *     same pull on a fine uniform grid;
 *   - a graded scene with a [puncture] runs (rodsim run, exit 0). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/contact/puncture.h"
#include "sim/path.h"
#include "sim/rod.h"
#include "sim/rod_grid.h"
#include "test.h"
#include "test_process.h"
#include "test_puncture_pull.h"
#include "test_run_start.h"

/* A thread of table 1's material (0.2 m, 0.3 mm), implicit, root pinned,
 * straight along +x from the origin; `refine` intervals (count of them) or
 * a uniform grid. */
static rod_model thread_model(int nodes, const rod_refine *refine, int refine_count)
{
    rod_model m = rod_model_default();
    m.length = 0.2;
    m.diameter = 0.0003;
    m.nodes = nodes;
    m.options.scheme = ROD_SCHEME_IMPLICIT;
    m.self_contact = 0;
    m.root_end = ROD_END_PINNED;
    m.tip_end = ROD_END_FREE;
    m.refine_count = refine_count;
    for (int k = 0; k < refine_count; k++) m.refine[k] = refine[k];
    return m;
}

/* The straight graded thread: puncture_locate's (j, alpha) for arc lengths
 * swept across the whole thread put the point (1 - alpha) r_j + alpha r_j+1
 * at x = s; the nearest arc length of a point beside the thread is its x. */
static void test_locate(void)
{
    const rod_refine refine = {0.11, 0.2, 4.0};
    rod_model m = thread_model(101, &refine, 1);
    if (!check(model_derive(&m) == 0 && m.segment_length, "a graded thread with a puncture derives"))
        return;
    rod_state *s = rod_state_create(&m);
    if (!s) {
        rod_model_release(&m);
        return;
    }
    double worst = 0.0, worst_near = 0.0;
    int crossings = 0, last_j = -1;
    for (int q = 0; q <= 20000; q++) {
        const double arc = 0.2 * q / 20000.0;
        int j;
        double alpha;
        puncture_locate(&m, arc, &j, &alpha);
        crossings += j != last_j;
        last_j = j;
        const double x = (1.0 - alpha) * s->position[3 * j] + alpha * s->position[3 * (j + 1)];
        worst = fmax(worst, fabs(x - arc));
        const double p[3] = {arc, 1e-4, 0.0};
        double dist;
        worst_near = fmax(worst_near, fabs(rod_nearest_arc_length(&m, s->position, p, &dist) - arc));
    }
    /* the jump: the segment before node 45 (s = 0.11 - 0.00025 m) against the next */
    int jump = 0;
    for (int j = 1; j + 1 < m.nodes; j++)
        if (m.segment_length[j - 1] > 1.5 * m.segment_length[j]) jump = j;
    check(jump > 0, "the grid's spacing jumps at node %d (s = %.6g m, segments %.4g and %.4g mm)",
          jump, rod_node_arc(&m, jump), 1e3 * m.segment_length[jump - 1],
          1e3 * m.segment_length[jump]);
    check(crossings == m.nodes - 1, "the sweep visits every segment once (%d of %d)", crossings,
          m.nodes - 1);
    check_abs("s_j + alpha ds_j against the point's distance from the root, worst over 20001 "
              "arc lengths (m)", worst, 0.0, 1e-15);
    check_abs("nearest arc length of a point beside the thread against its x, worst (m)",
              worst_near, 0.0, 1e-15);
    /* across the jump node: from just before to just after */
    int ja, jb;
    double aa, ab;
    const double sj = rod_node_arc(&m, jump), eps = 1e-12;
    puncture_locate(&m, sj - eps, &ja, &aa);
    puncture_locate(&m, sj + eps, &jb, &ab);
    const double xa = rod_node_arc(&m, ja) + aa * m.segment_length[ja],
                 xb = rod_node_arc(&m, jb) + ab * m.segment_length[jb];
    check(ja == jump - 1 && jb == jump && fabs(xb - xa - 2.0 * eps) < 1e-15,
          "across node %d the point goes from segment %d (alpha %.12f) to %d (alpha %.3g): "
          "arc %.15g to %.15g m", jump, ja, aa, jb, ab, xa, xb);
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* The pull: a thread of 60 mm, a 30 degree turn at the hole (30, 0, 0) mm,
 * the tip's load W at 30 degrees above +x ramped over 0.05 s, the root
 * pulled along -x at v = 20 mm/s for 0.3 s (6 mm). */
typedef struct pull_result {
    double t_root;       /* N: the root's mean support force over 0.12 .. 0.18 s */
    double u1[3], u2[3]; /* the strands' directions away from the hole */
    double slid;         /* m: the puncture's arc length's change */
    double speed_err;    /* the worst |ds/dt - v| / v over 0.1 .. 0.3 s */
    double cross_err;    /* the same at the steps where the hole crosses a node */
    int crossings;       /* nodes the hole crossed in that time */
    double force_jump;   /* the largest step-to-step change of |F| over 0.1 .. 0.3 s / mean |F| */
    double miss;         /* m: the largest distance from the hole to the thread */
} pull_result;

#define PULL_LENGTH 0.06
#define PULL_HOLE 0.03

static int pull(int nodes, const rod_refine *refine, int refine_count, double mu, double w_load,
                pull_result *r)
{
    const double duration = 0.3, speed = 0.02, turn = M_PI / 6.0, dt = 2e-3;
    rod_model m = thread_model(nodes, refine, refine_count);
    m.length = PULL_LENGTH;
    m.tip_frame = ROD_FRAME_GLOBAL;
    const double out[3] = {cos(turn), 0.0, sin(turn)};
    v3_scale(m.tip_force, out, w_load);
    m.profile.kind = ROD_PROFILE_RAMP;
    m.profile.t1 = 0.05;
    m.linear_damping = 1e-3;
    char err[512];
    const double rows[14] = {0.0,      0.0,    0.0, 0.0, -speed, 0.0, 0.0,
                             duration, -speed * duration, 0.0, 0.0, -speed, 0.0, 0.0};
    m.root_motion = rod_path_create_with_velocity(rows, 2, 4, err, sizeof err);
    rod_puncture hole = {{PULL_HOLE, 0.0, 0.0}, mu, 0};
    m.puncture_count = 1;
    m.punctures = &hole;
    int rc = -1;
    memset(r, 0, sizeof *r);
    if (!m.root_motion || model_derive(&m)) goto done_model;
    rod_solver solver;
    rod_state *s = run_start(&m, &solver);
    if (!s) goto done_model;
    rod_report report;
    memset(&report, 0, sizeof report);
    const int steps = (int)lround(duration / dt);
    int count = 0, fcount = 0, last_j = -1;
    double sum = 0.0, s_start = s->puncture[0].s, s_last = s_start, f_last = NAN, fsum = 0.0;
    double fjump = 0.0;
    rc = 0;
    for (int k = 1; k <= steps; k++) {
        if (rod_solver_step(&solver, &m, s, dt, &report)) {
            printf("     pull step %d (t = %g s): %s\n", k, s->time, report.message);
            rc = -1;
            break;
        }
        double dist;
        rod_nearest_arc_length(&m, s->position, hole.point, &dist);
        r->miss = fmax(r->miss, dist);
        const double sk = s->puncture[0].s, fk = v3_norm(s->puncture[0].force);
        int j;
        double alpha;
        puncture_locate(&m, sk, &j, &alpha);
        if (s->time > 0.1 - 1e-9) {
            const double err_k = fabs((sk - s_last) / dt - speed) / speed;
            r->speed_err = fmax(r->speed_err, err_k);
            if (last_j >= 0 && j != last_j) {
                r->crossings++;
                r->cross_err = fmax(r->cross_err, err_k);
            }
            if (isfinite(f_last)) fjump = fmax(fjump, fabs(fk - f_last));
            fsum += fk;
            fcount++;
        }
        last_j = j;
        s_last = sk;
        f_last = fk;
        if (s->time >= 0.4 * duration && s->time <= 0.6 * duration) {
            sum += v3_norm(s->end_force[0]);
            count++;
        }
    }
    if (rc == 0 && count && fcount) {
        r->t_root = sum / count;
        r->slid = s->puncture[0].s - s_start;
        r->force_jump = fjump / (fsum / fcount);
        strand_directions(s->position, m.nodes, hole.point, r->u1, r->u2);
    } else {
        rc = -1;
    }
    rod_solver_release(&solver);
    rod_state_destroy(s);
done_model:
    m.punctures = NULL;
    m.puncture_count = 0;
    rod_model_release(&m);
    return rc;
}

static void test_pull(void)
{
    const double mu = 0.3, w_load = 0.05;
    /* 61 nodes, twice as fine from s = 32 mm on: 1.47 mm segments before
     * (the hole's start at 30 mm), 0.73 mm after; the hole slides 30 to
     * 36 mm across the jump (node 22, s = 32.2 mm, at t = 0.11 s). The turn's
     * radius sqrt(EI / T) = 0.8 mm. */
    const rod_refine refine = {0.032, PULL_LENGTH, 2.0};
    pull_result g, u;
    const int graded_ok = pull(61, &refine, 1, mu, w_load, &g) == 0;
    check(graded_ok, "the pull through the puncture runs on the graded grid");
    if (!graded_ok) return;
    check(g.slid > 0.0057 && g.slid < 0.0063, "graded: the thread slid %.5g m through the hole "
          "(the root pulled 0.006 m)", g.slid);
    const double reference = coulomb_root_tension(mu, w_load, g.u1, g.u2);
    check_rel("graded, mu = 0.3: root tension vs Coulomb's law at the puncture (N)", g.t_root,
              reference, 0.02);
    check(g.crossings >= 4, "graded: the hole crossed %d nodes over 0.1 .. 0.3 s, the jump "
          "among them", g.crossings);
    check_abs("graded: the slide's speed against the root's 0.02 m/s, worst relative error "
              "over the steps where the hole crosses a node", g.cross_err, 0.0, 0.05);
    check_abs("graded: the same over every step of 0.1 .. 0.3 s", g.speed_err, 0.0, 0.05);
    check_abs("graded: the puncture's force, largest step-to-step change over its mean",
              g.force_jump, 0.0, 0.02);
    check(g.miss < 0.15 * 0.00015, "graded: the thread passes through the point (largest miss "
          "%.3g m, limit 15 %% of the radius %.3g m)", g.miss, 0.00015);
    /* the same pull on a uniform grid finer than the graded one's fine part */
    if (!check(pull(121, NULL, 0, mu, w_load, &u) == 0, "the pull runs on a uniform grid of 121 "
               "nodes (0.5 mm)"))
        return;
    check_rel("graded (61 nodes) against uniform (121 nodes): the root's tension (N)", g.t_root,
              u.t_root, 0.01);
    check_rel("uniform 121 nodes: root tension vs Coulomb's law (N)", u.t_root,
              coulomb_root_tension(mu, w_load, u.u1, u.u2), 0.02);
    printf("     uniform 121 nodes: slide speed's worst relative error %.3g (at node crossings "
           "%.3g), force's largest step change %.3g of its mean\n", u.speed_err, u.cross_err,
           u.force_jump);
}

/* A graded scene with a [puncture] runs from the command line. */
static void test_scene(void)
{
    const char *dir = test_dir();
    char out_dir[512], scene[512];
    static char output[1 << 16];
    snprintf(out_dir, sizeof out_dir, "%s/out", dir);
    snprintf(scene, sizeof scene, "%s/graded.ini", dir);
    test_write_in(dir, "graded.ini",
                  "[rod]\nlength = 0.2\ndiameter = 0.0003\ndensity = 850\nyoungs_modulus = 87.5e6\n"
                  "shear_modulus = 31.25e6\nnodes = 41\nself_contact = no\n"
                  "refine = 0.08 0.12 4\n[ends]\nroot = pinned\n[tip]\nforce = 0.01 0 0.005\nframe = global\n"
                  "[puncture]\npoint = 0.1 0 0\nfriction = 0.3\n[solver]\nduration = 0.05\n");
    const char *args[] = {"run", scene, "-o", out_dir, "--no-video", NULL};
    const int status = test_run_rodsim(args, output, sizeof output);
    check(status == 0, "rodsim run of a graded scene with a [puncture]: exit %d (0)%s%s", status,
          status ? ": " : "", status ? output : "");
}

int main(void)
{
    test_locate();
    test_pull();
    test_scene();
    return test_finish();
}
