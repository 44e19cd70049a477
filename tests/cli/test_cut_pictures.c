/* test_cut_pictures.c: two small scenes with [cut]s, run as `rodsim run`
 * runs them (the scene read, the solver's steps, a frame recorded every
 * 0.1 s), and what the picture makes of their last frames:
 *  - the needle's piece cut away: a 5 cm thread, a 5 mm needle at its tip
 *    (clamped) in a needle holder's jaws, handed to forceps at 0.3 s, the
 *    holder opening and drawn off; a puncture at s = 2 cm; cut at s = 4 cm
 *    at 0.6 s, the piece with the needle (its tip side) goes (the summary's
 *    "taken away from the tip's side"); the forceps move 5 mm along x and
 *    1 cm down from 0.7 s to 1 s. The needle is drawn in the forceps' jaws
 *    at the end: its back where it was in them at the last frame before
 *    the cut (R^T (r - p) the same within 1e-12 m), 11 mm or more from the
 *    thread's cut end (its 5 mm arc drawn there before); the knot line
 *    after the cut reads the thread left's unknot (it read "not
 *    identified");
 *  - a loose overhand knot (overhand_tight.ini's shape, both ends free, no
 *    load) whose root tail is cut 15 mm from its end at 0.1 s: the knot
 *    line of every frame after the cut names the knot the summary names,
 *    identified from the state's own nodes (the thread left), a
 *    right-handed trefoil (it read "not identified" with the nodes cut away
 *    piled on the cut end). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "api/scene_read.h"
#include "base/ini.h"
#include "base/vec3.h"
#include "render/glyphs.h"
#include "render/options.h"
#include "render/overlay.h"
#include "sim/cut.h"
#include "sim/geometry/knot.h"
#include "sim/recording.h"
#include "sim/rod.h"
#include "test.h"
#include "test_process.h"

#define FRAME_STEP 0.1 /* s between recorded frames */

static char dir[] = "/tmp/rodsim_cut_picturesXXXXXX";

static void write_file(const char *name, const char *text)
{
    test_write_in(dir, name, text);
}

/* The scene run with frames every FRAME_STEP to its duration: the
 * recording (and the state and model, for the caller's checks), or NULL. */
typedef struct run {
    rod_model m;
    run_output out;
    rod_state *s;
    rod_recording *rec;
    char knot_after[160]; /* the knot of the state's own nodes in each frame after the cut */
    int knot_mismatch;    /* frames whose overlay line differs from it */
    int frames_after_cut;
} run;

static int run_scene(const char *name, double duration, run *r)
{
    char path[512], err[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    memset(r, 0, sizeof *r);
    ini_doc *doc = ini_load(path, err, sizeof err);
    if (!doc) return printf("%s\n", err), -1;
    r->m = rod_model_default();
    int rc = run_read_scene(doc, &r->m, &r->out, err, sizeof err);
    ini_destroy(doc);
    if (rc) return printf("%s\n", err), -1;
    const int frames = (int)lround(duration / FRAME_STEP) + 1;
    r->rec = rod_recording_create(&r->m, name, frames);
    r->s = rod_state_create(&r->m);
    rod_solver solver;
    if (!r->rec || !r->s || rod_solver_init(&solver, &r->m, err, sizeof err)) return -1;
    rod_state_reset(&r->m, r->s);
    render_overlay ov;
    memset(&ov, 0, sizeof ov);
    ov.knot_shown = 1;
    rod_report report;
    for (int f = 0; f < frames; f++) {
        for (int k = 0; f > 0 && k < 100; k++)
            if (rod_solver_step(&solver, &r->m, r->s, FRAME_STEP / 100, &report) != ROD_OK) {
                printf("step at t = %g s: %s\n", r->s->time, report.message);
                rod_solver_release(&solver);
                return -1;
            }
        if (rod_recording_append(r->rec, rod_cut_model(&r->m, r->s), r->s)) return -1;
        if (r->s->cut_count > 0) {
            rod_knot k;
            char why[200], line[200];
            int ok = rod_knot_identify_in(NULL, r->s->position, r->s->nodes, 0, &k, why,
                                          sizeof why) == 0;
            snprintf(r->knot_after, sizeof r->knot_after, "%s", ok ? k.name : "(none)");
            overlay_knot(&ov, r->rec, f);
            snprintf(line, sizeof line, "knot: %s", r->knot_after);
            /* the overlay adds Rolfsen's label: compare the name's words */
            int same = ok && strncmp(ov.knot_text, "knot: ", 6) == 0 &&
                       strncmp(ov.knot_text + 6, k.name, strcspn(k.name, ",")) == 0 &&
                       strstr(ov.knot_text, strchr(k.name, ',') ? strchr(k.name, ',') : "");
            if (!same) {
                r->knot_mismatch++;
                printf("  t = %.2f s: overlay \"%s\", the thread left \"%s\"\n", r->s->time,
                       ov.knot_text, line);
            }
            r->frames_after_cut++;
        }
    }
    rod_solver_release(&solver);
    return 0;
}

static void run_free(run *r)
{
    rod_recording_destroy(r->rec);
    rod_state_destroy(r->s);
    rod_model_release(&r->m);
}

/* The needle's back relative to instrument k in frame f: R^T (r - p). */
static void in_jaws(const rod_recording *rec, int f, int k, const double back[3], double out[3])
{
    const double *pose = rod_recording_instrument(rec, f, k);
    double d[3];
    v3_sub(d, back, pose);
    m3_mul_tv(out, pose + 3, d);
}

static void test_needle(void)
{
    write_file("holder.csv", "t,x,y,z,rx,ry,rz,jaw\n0,0,0,0,0,0,0,0\n0.35,0,0,0,0,0,0,0\n"
                             "0.45,0,0,0,0,0,0,1\n0.55,-0.01,0,0.01,0,0,0,1\n"
                             "1.2,-0.01,0,0.01,0,0,0,1\n");
    write_file("forceps.csv", "t,x,y,z,rx,ry,rz,jaw\n0,0,0.002,0,0,0,0,0\n0.7,0,0.002,0,0,0,0,0\n"
                              "1.0,0.005,0.002,-0.01,0,0,0,0\n1.2,0.005,0.002,-0.01,0,0,0,0\n");
    write_file("needle_cut.ini",
               "[rod]\nlength = 0.05\ndiameter = 0.0005\nnodes = 26\ndensity = 1140\n"
               "youngs_modulus = 1.5e9\nshear_modulus = 0.55e9\norigin = 0 -0.05 0\n"
               "direction = 0 1 0\n[ends]\nroot = free\ntip = clamped\nneedle = 0.005\n"
               "[instrument]\nkind = needle_holder\nname = holder\npath = holder.csv\n"
               "needle = yes\nsize = 0.12\n"
               "[instrument]\nkind = forceps\nname = forceps\npath = forceps.csv\nsize = 0.12\n"
               "may_overlap = yes\n[needle_grasp]\nt = 0.3\ninstrument = forceps\n"
               "[puncture]\npoint = 0 -0.03 0\nfriction = 0.3\n[cut]\nt = 0.6\ns = 0.04\n"
               "[solver]\nscheme = implicit\ndt = 0.001\nduration = 1.2\n"
               "[render]\nneedle_arc = 1/2\n");
    run r;
    if (!check(run_scene("needle_cut.ini", 1.2, &r) == 0, "the needle scene runs to 1.2 s")) {
        run_free(&r);
        return;
    }
    const rod_recording *rec = r.rec;
    const int last = rec->frame_count - 1, before = (int)lround(0.6 / FRAME_STEP) - 1;
    check(r.s->cut_count == 1 && r.s->nodes == 21 && r.s->first_node == 0,
          "one cut, the tip's side gone: %d nodes left from node %d (expected 21 from 0)",
          r.s->nodes, r.s->first_node);
    render_options o = r.out.render;
    double arc[3 * GLYPH_MAX_POINTS], pad, then[3], now[3], off[3];
    int chain, forceps = 1;
    int count = glyph_points(rec, &o, 0.0005, before, 1, arc, &pad, &chain);
    double back_before[3];
    v3_copy(back_before, arc);
    in_jaws(rec, before, forceps, back_before, then);
    count = glyph_points(rec, &o, 0.0005, last, 1, arc, &pad, &chain);
    in_jaws(rec, last, forceps, arc, now);
    v3_sub(off, now, then);
    printf("needle's back in the forceps: (%.6f, %.6f, %.6f) mm at %.1f s, (%.6f, %.6f, %.6f) mm "
           "at %.1f s\n", 1e3 * then[0], 1e3 * then[1], 1e3 * then[2], rec->time[before],
           1e3 * now[0], 1e3 * now[1], 1e3 * now[2], rec->time[last]);
    check(count == NEEDLE_SEGMENTS + 1 && v3_norm(off) < 1e-12,
          "the needle drawn in the forceps' jaws where it was before the cut (moved %.2e m in "
          "them)", v3_norm(off));
    const double *cut_end = &rec->position[3 * ((size_t)last * (size_t)rec->nodes + 20)];
    double nearest = INFINITY;
    for (int k = 0; k < count; k++) {
        v3_sub(off, &arc[3 * k], cut_end);
        nearest = fmin(nearest, v3_norm(off));
    }
    check(nearest > 0.011, "the needle %.2f mm from the thread's cut end at %.1f s (it moved "
          "with the forceps, 5 mm along x and 10 mm down)", 1e3 * nearest, rec->time[last]);
    check(r.knot_mismatch == 0 && strcmp(r.knot_after, "unknot") == 0,
          "the knot line after the cut: the thread left's \"%s\" (%d of %d frames differ)",
          r.knot_after, r.knot_mismatch, r.frames_after_cut);
    run_free(&r);
}

static void test_knot(void)
{
    char text[1024];
    snprintf(text, sizeof text,
             "[rod]\nlength = 0.609684253\ndiameter = 0.004\ndensity = 1100\n"
             "youngs_modulus = 5e7\nshear_modulus = 2e7\nnodes = 241\n"
             "shape = %s/scenes/overhand_shape.csv\nfriction = 0.2\n"
             "[ends]\nroot = free\ntip = free\n[cut]\nt = 0.1\ns = 0.015\n"
             "[solver]\nscheme = implicit\ndt = 0.005\nduration = 0.3\n"
             "[loads]\nlinear_damping = 0.05\n",
             RODSIM_SOURCE_DIR);
    write_file("knot_cut.ini", text);
    run r;
    if (!check(run_scene("knot_cut.ini", 0.3, &r) == 0, "the knot scene runs to 0.3 s")) {
        run_free(&r);
        return;
    }
    check(r.s->cut_count == 1 && r.s->nodes < 241,
          "the root's tail cut: %d nodes left of 241", r.s->nodes);
    check(r.frames_after_cut == 3 && r.knot_mismatch == 0 &&
              strcmp(r.knot_after, "trefoil, right-handed") == 0,
          "the knot line of each of the %d frames after the cut names the thread left's knot "
          "(\"%s\"): %d differ", r.frames_after_cut, r.knot_after, r.knot_mismatch);
    run_free(&r);
}

int main(void)
{
    if (!check(mkdtemp(dir) != NULL, "scratch directory")) return test_finish();
    test_needle();
    test_knot();
    test_remove_tree(dir);
    return test_finish();
}
