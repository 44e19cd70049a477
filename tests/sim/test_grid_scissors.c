/* test_grid_scissors.c: scissors on a graded grid (rod.refine,
 * sim/rod_grid.h) and the grasp log after a cut, against independent
 * values:
 *   - a graded thread hanging straight down from its clamped root, its
 *     segments 5 times shorter between 0.06 and 0.1 m; scissors whose
 *     closed blades cross it at depth z (inside the fine interval, beside
 *     the grading's jump, in the long segments): the cut's arc length is z
 *     (the thread hangs straight: its stretch is below 1e-6 of L), it lands
 *     on the node nearest z by the nodes' arc lengths (summed here), the
 *     length left is that node's arc length, the pieces sum to L, and the
 *     tail is L - z to half the local segment;
 *   - the thread hung by its tip, its root's side cut off at a node of the
 *     fine interval, then grasped by forceps closing at height z: the grasp
 *     log's arc length is the uncut thread's at that height, L + z (the tip
 *     at z = 0), not the thread left's plus first_node L / (NS - 1);
 *   - a graded scene with scissors runs (rodsim run --no-video, exit 0)
 *     and its summary names the cut. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/cut.h"
#include "sim/instrument.h"
#include "sim/path.h"
#include "sim/rod.h"
#include "sim/rod_grid.h"
#include "test.h"
#include "test_hanging_thread.h"
#include "test_instrument_rows.h"
#include "test_process.h"

#define LENGTH HANGING_LENGTH /* m */
#define NODES HANGING_NODES
#define FINE0 0.06   /* m: the refine interval, factor 5 */
#define FINE1 0.10

/* The cut tests' hanging thread, 5 times finer between FINE0 and FINE1. */
static rod_model graded_model(rod_end_kind root, rod_end_kind tip, const double origin[3],
                              const double direction[3])
{
    rod_model m = hanging_model(root, tip, origin, direction);
    m.refine[0].s0 = FINE0;
    m.refine[0].s1 = FINE1;
    m.refine[0].factor = 5.0;
    m.refine_count = 1;
    return m;
}

/* Node arc lengths summed from the segment lengths (arc[NODES]). */
static void node_arcs(const rod_model *m, double *arc)
{
    arc[0] = 0.0;
    for (int i = 1; i < m->nodes; i++) arc[i] = arc[i - 1] + m->segment_length[i - 1];
}

/* Blades (or jaws) of `kind`, 10 cm, lying along +y with their middle line
 * crossing the z axis at height z, opening in the x-y plane; open until
 * 0.05 s, closed at 0.1 s. */
static rod_instrument blades(rod_instrument_kind kind, double z)
{
    double lj, rj, rs;
    rod_instrument probe;
    memset(&probe, 0, sizeof probe);
    probe.kind = kind;
    probe.size = 0.1;
    rod_instrument_dimensions(&probe, &lj, &rj, &rs);
    /* columns: local x = +y, local y = +z, local z = +x */
    const double ex[3] = {0.0, 1.0, 0.0}, ey[3] = {0.0, 0.0, 1.0}, ez[3] = {1.0, 0.0, 0.0};
    double rv[3];
    rotation_vector(ex, ey, ez, rv);
    const double tip = 0.5 * lj; /* the middle line from y = lj / 2 back to -lj / 2 */
    const double rows[] = {0.0,  0.0, tip, z, rv[0], rv[1], rv[2], 1.0,
                           0.05, 0.0, tip, z, rv[0], rv[1], rv[2], 1.0,
                           0.1,  0.0, tip, z, rv[0], rv[1], rv[2], 0.0,
                           1.0,  0.0, tip, z, rv[0], rv[1], rv[2], 0.0};
    return instrument(kind, 0.1, rows, 4, 0.2, 1.0);
}

/* Frees a run's solver, state, the instrument's paths and the model
 * (which does not own the instrument). */
static void release_run(rod_model *m, rod_instrument *in, rod_solver *solver, rod_state *s)
{
    m->instruments = NULL;
    m->instrument_count = 0;
    rod_path_destroy(in->pose);
    rod_path_destroy(in->jaw);
    rod_solver_release(solver);
    rod_state_destroy(s);
    rod_model_release(m);
}

/* Scissors closing across the graded thread hanging from its root at
 * depth `depth` (m of arc length): the cut against the grid. */
static void scissors_cut(const char *where, double depth)
{
    const double origin[3] = {0.0, 0.0, 0.0}, down[3] = {0.0, 0.0, -1.0};
    rod_model m = graded_model(ROD_END_CLAMPED, ROD_END_FREE, origin, down);
    rod_instrument in = blades(ROD_INSTRUMENT_SCISSORS, -depth);
    m.instruments = &in;
    m.instrument_count = 1;
    rod_state *s = NULL;
    rod_solver solver = {0};
    if (derive(&m)) goto done;
    s = hanging_start(&m, &solver, where);
    if (!s) goto done;
    rod_report report;
    memset(&report, 0, sizeof report);
    if (run_to(&solver, &m, s, 0.2, 1e-3, &report)) goto done;
    if (!check(s->cut_count == 1 && s->cut_log[0].instrument == 0 && s->cut && s->first_node == 0,
               "%s: one cut, by the scissors, the tip's side gone (cuts %d, first node %d)%s%s",
               where, s->cut_count, s->first_node, report.warning[0] ? ": " : "", report.warning))
        goto done;
    double arc[NODES];
    node_arcs(&m, arc);
    /* the node nearest the depth and the segment the depth lies in */
    int near = 0, seg = 0;
    for (int i = 1; i < NODES; i++)
        if (fabs(arc[i] - depth) < fabs(arc[near] - depth)) near = i;
    while (seg < NODES - 2 && arc[seg + 1] <= depth) seg++;
    const double local = m.segment_length[seg];
    const rod_model *cut = rod_cut_model(&m, s);
    const double removed = s->cut_log[0].removed;
    printf("     %s: blades at depth %.6g m (segment %d, %.4g m long), nearest node %d at s = "
           "%.9g m; left %.9g m (%d nodes), removed %.9g m\n", where, depth, seg, local, near,
           arc[near], cut->length, s->nodes, removed);
    check_rel("  the cut's arc length (logged, m) against the blades' depth", s->cut_log[0].s,
              depth, 1e-5);
    check(s->nodes == near + 1, "  the cut on the node nearest the depth by arc length: %d nodes "
          "left (%d)", s->nodes, near + 1);
    check_rel("  the length left (m) against the cut node's arc length (summed here)",
              cut->length, arc[near], 1e-13);
    check_rel("  the pieces' lengths' sum (m) against L", cut->length + removed, LENGTH, 1e-14);
    printf("     the tail: computed %.9g m, reference L - depth %.9g m, difference %.3e m (half "
           "the local segment %.3e m)\n", removed, LENGTH - depth,
           fabs(removed - (LENGTH - depth)), 0.5 * local);
    check(fabs(removed - (LENGTH - depth)) <= 0.5 * local * (1.0 + 1e-9),
          "  the tail within half the local segment of L - depth");
    double span[3];
    v3_sub(span, &s->position[3 * (s->nodes - 1)], &s->position[0]);
    check_rel("  the thread left's span (m) against its length", v3_norm(span), cut->length, 1e-5);
done:
    release_run(&m, &in, &solver, s);
}

static void test_scissors(void)
{
    const double origin[3] = {0.0, 0.0, 0.0}, down[3] = {0.0, 0.0, -1.0};
    rod_model m = graded_model(ROD_END_CLAMPED, ROD_END_FREE, origin, down);
    if (derive(&m)) return;
    double arc[NODES];
    node_arcs(&m, arc);
    int jump = 0; /* the last node a short segment reaches */
    for (int i = 1; i < NODES - 1; i++)
        if (m.segment_length[i] > 2.0 * m.segment_length[i - 1]) jump = i;
    printf("     thread: L = %g m, %d nodes, ds %.4g m out, %.4g m in (%g .. %g m); node %d at "
           "s = %.9g m ends the short segments\n", LENGTH, NODES, m.segment_length[0],
           m.segment_length[NODES / 2 - 5], FINE0, FINE1, jump, arc[jump]);
    rod_model_release(&m);
    if (!check(jump > 3, "the grading's jump found (node %d)", jump)) return;
    const double ds_in = arc[jump] - arc[jump - 1], ds_out = arc[jump + 1] - arc[jump];
    scissors_cut("inside the fine interval, 0.4 into a segment", arc[jump - 5] + 0.4 * ds_in);
    scissors_cut("0.7 into the segment across the interval's end", arc[jump - 1] + 0.7 * ds_in);
    /* past the jump: 0.3 of the long segment goes to the jump's node, 0.7
     * to the next (an index rounded on one ds would pick neither) */
    scissors_cut("0.3 into the long segment after the jump", arc[jump] + 0.3 * ds_out);
    scissors_cut("0.7 into the long segment after the jump", arc[jump] + 0.7 * ds_out);
    scissors_cut("in the long segments, at a node", arc[jump + 6]);
}

/* The thread hung by its tip (at z = 0), its root's side cut at the first
 * node past the fine interval's middle, then forceps (scissors) closing at
 * height z: the grasp log's (the second cut's) arc length against L + z. */
static void after_root_cut(rod_instrument_kind kind)
{
    const double origin[3] = {0.0, 0.0, -LENGTH}, up[3] = {0.0, 0.0, 1.0}, z = -0.05;
    const int scissors = kind == ROD_INSTRUMENT_SCISSORS;
    const char *who = scissors ? "scissors" : "forceps";
    rod_model m = graded_model(ROD_END_FREE, ROD_END_CLAMPED, origin, up);
    rod_instrument in = blades(kind, z);
    m.instruments = &in;
    m.instrument_count = 1;
    rod_state *s = NULL;
    rod_solver solver = {0};
    if (derive(&m)) goto done;
    double arc[NODES];
    node_arcs(&m, arc);
    int cut_node = 0;
    while (cut_node < NODES - 1 && arc[cut_node] < 0.5 * (FINE0 + FINE1)) cut_node++;
    s = hanging_start(&m, &solver, who);
    if (!s) goto done;
    rod_report report;
    memset(&report, 0, sizeof report);
    rod_cut_ask(s, -1, arc[cut_node]);
    const int applied = rod_cut_apply(&m, s, &report);
    if (!check(applied == 0 && s->cut_count == 1 && s->first_node == cut_node,
               "%s: the root's side cut at node %d (s = %.6g m): first node %d", who, cut_node,
               arc[cut_node], s->first_node))
        goto done;
    if (run_to(&solver, &m, s, 0.2, 1e-3, &report)) goto done;
    const double hand = LENGTH + z;
    if (!scissors) {
        if (!check(s->grasp_log_count == 1 && s->grasp[0].held, "the forceps took the thread "
                   "left (%d grasps logged)%s%s", s->grasp_log_count,
                   report.warning[0] ? ": " : "", report.warning))
            goto done;
        const double logged = s->grasp_log[0].s, by_index = s->grasp[0].s + cut_node * m.ds;
        printf("     grasp after the root's side went (first node %d, uncut s = %.9g m, %d * "
               "L/(NS-1) = %.9g m): logged %.9g m, on the thread left %.9g m\n", cut_node,
               arc[cut_node], cut_node, cut_node * m.ds, logged, s->grasp[0].s);
        check_rel("  the grasp log's arc length (m) against the forceps' height, L + z", logged,
                  hand, 1e-5);
        check_rel("  the grasp log's arc length (m) against the first node's uncut arc (summed "
                  "here) + the grasp's", logged, arc[cut_node] + s->grasp[0].s, 1e-15);
        printf("     (the thread left's s + first_node L / (NS - 1) gives %.9g m, %.3e off)\n",
               by_index, fabs(by_index - hand) / hand);
    } else {
        if (!check(s->cut_count == 2 && s->cut_log[1].instrument == 0, "the scissors cut the "
                   "thread left (%d cuts)%s%s", s->cut_count, report.warning[0] ? ": " : "",
                   report.warning))
            goto done;
        int near = 0;
        for (int i = 1; i < NODES; i++)
            if (fabs(arc[i] - hand) < fabs(arc[near] - hand)) near = i;
        const rod_model *cut = rod_cut_model(&m, s);
        printf("     scissors after the root's side went: the cut logged at s = %.9g m, first "
               "node %d (%d expected), length left %.9g m\n", s->cut_log[1].s, s->first_node,
               near, cut->length);
        check_rel("  the second cut's arc length (logged, m) against the blades' height, L + z",
                  s->cut_log[1].s, hand, 1e-5);
        check(s->first_node == near, "  the second cut on the uncut node nearest L + z");
        check_rel("  the length left (m) against L - that node's arc length (summed here)",
                  cut->length, LENGTH - arc[near], 1e-13);
        check_rel("  the pieces' lengths' sum (m) against L",
                  cut->length + s->cut_log[0].removed + s->cut_log[1].removed, LENGTH, 1e-14);
    }
done:
    release_run(&m, &in, &solver, s);
}

/* A graded scene with scissors runs ---------------------------------------- */

static void test_scene(void)
{
    const char *dir = test_dir();
    char out_dir[512], scene[512];
    static char output[1 << 16];
    snprintf(out_dir, sizeof out_dir, "%s/out", dir);
    snprintf(scene, sizeof scene, "%s/graded_scissors.ini", dir);
    /* blades along +y crossing the thread (along x, on a plane) at x = 0.09 m */
    test_write_in(dir, "blades.csv", "t,x,y,z,rx,ry,rz,jaw\n0,0.09,0.0165,0.00025,0,0,1.5707963267948966,1\n"
                  "0.02,0.09,0.0165,0.00025,0,0,1.5707963267948966,1\n"
                  "0.04,0.09,0.0165,0.00025,0,0,1.5707963267948966,0\n");
    test_write_in(dir, "graded_scissors.ini",
                  "[rod]\nlength = 0.2\ndiameter = 0.0005\ndensity = 1100\n"
                  "youngs_modulus = 3e9\nshear_modulus = 1e9\nnodes = 41\n"
                  "self_contact = no\nrefine = 0.08 0.12 5\norigin = 0 0 0.00025\n"
                  "[ends]\nroot = clamped\ntip = free\n[solver]\nduration = 0.06\n"
                  "[instrument]\nkind = scissors\npath = blades.csv\n");
    const char *args[] = {"run", scene, "-o", out_dir, "--no-video", NULL};
    const int status = test_run_rodsim(args, output, sizeof output);
    const char *cut = strstr(output, "cut 1 by scissors");
    double at = -1.0, away = -1.0;
    if (cut) sscanf(cut, "cut 1 by scissors: at t = %*g s, the thread at s = %lf m, %lf m", &at,
                    &away);
    if (!check(status == 0 && cut && away > 0.0, "a graded scene with scissors runs and cuts "
               "(rodsim run --no-video): exit %d (0)%s%.600s", status, status ? ": " : "",
               status ? output : ""))
        return;
    /* the blades cross the thread at x = 0.09 m, inside the interval, where
     * the segments are 0.0018 m (0.2 m over 40 segments, 5 times finer over 0.04 m) */
    check_rel("  the summary's cut s (m) against the blades' x", at, 0.09, 1e-3);
    printf("     the length left: computed %.6g m, reference 0.09 m, difference %.3e m (half a "
           "fine segment 9e-4 m)\n", LENGTH - away, fabs(LENGTH - away - 0.09));
    check(fabs(LENGTH - away - 0.09) <= 9e-4, "  the length left within half a fine segment of "
          "the blades' x");
}

int main(void)
{
    test_scissors();
    after_root_cut(ROD_INSTRUMENT_FORCEPS);
    after_root_cut(ROD_INSTRUMENT_SCISSORS);
    test_scene();
    return test_finish();
}
