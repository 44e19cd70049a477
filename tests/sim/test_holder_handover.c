/* test_holder_handover.c: a needle holder that has handed its needle to
 * other jaws ([needle_grasp]) is an ordinary jaws instrument from the first
 * close of its jaws after they have opened after the handover
 * (sim/needle_grasp.h), against independent values:
 *  - the time the rule frees the holder: its jaws' opening, the path's C2
 *    spline from 1 at 0.95 s to 0 at 1 s, falls below ROD_JAW_CLOSED (0.1)
 *    there (within 1e-6), after 0.95 s and before 1 s; before it (closed
 *    just after the handover, opening, open) the holder's jaws are on the
 *    needle (touch and take no thread), from it on they are not;
 *  - the needle handed over at 0.45 s, the holder's jaws still closed on
 *    the needle's back, the thread's tip between them, for 50 ms, then
 *    opening: they touch and take nothing there (the run goes to its end,
 *    exit 0, no grasp by the holder before 0.9 s), and later take the
 *    thread as below; the same with a 0.2 mm thread hanging from the
 *    needle up through the jaws' opening plane under gravity (to 0.6 s):
 *    with the jaws freed at the grasp, or once open to 0.1 or 0.2, that
 *    run stalls in Newton at 0.519-0.529 s, the opening jaws against the
 *    clamped tip;
 *  - the holder hands the needle to forceps, opens, comes down over the
 *    thread's middle and closes: it takes the thread there (the summary's
 *    grasp by the holder, its time after the handover and its arc length
 *    the jaws' middle's, 25 mm, within ds), and the held point follows the
 *    jaws within 5 % of d as they lift 5 mm, rising as their held point
 *    does (the holder's grip 50 N: the 5 N default lets the thread slide
 *    through the jaws here, at the close's pinch);
 *  - the same paths with no handover: the holder, holding the needle (the
 *    thread's tip carried with it) when it closes, takes nothing (the rule
 *    before a handover as it was: jaws on the needle take no thread). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/ini.h"
#include "base/vec3.h"
#include "sim/instrument.h"
#include "sim/needle_grasp.h"
#include "sim/rod.h"
#include "sim/scene.h"
#include "test.h"
#include "test_process.h"
#include "test_scene_file.h"

#define DIAMETER 0.0005 /* m */
#define Y_GRASP -0.025  /* m: the jaws' middle over the thread, 25 mm from its root */
#define T_CLOSE 1.0     /* s: the jaws closed (they close from 0.9 s) */

static char dir[] = "/tmp/rodsim_holder_handoverXXXXXX";

static void write_file(const char *name, const char *text)
{
    test_write_in(dir, name, text);
}

/* A 5 cm thread along +y from (0, -0.05, 0), its tip (0, 0, 0) clamped to
 * a 5 mm needle, no gravity; forceps still 2 mm along the needle from its
 * back; the holder, its jaws' tip on the needle's back, its jaws along -x
 * across the thread (their rotation 0 from the tip's starting frame), shut
 * to 0.5 s, open by 0.6 s, drawn back 5 mm off the thread by 0.65 s, raised
 * 6 mm by 0.7 s, turned to point down (local x = -z) by 0.8 s, over the
 * thread at y = Y_GRASP by 0.85 s, lowered to put its jaws' middle on the
 * thread by 0.9 s, closed from 0.95 s to T_CLOSE, lifted 5 mm from 1.05 to 1.45 s (and moved 2 mm
 * toward the tip: the thread to the clamped tip is not stretched). The needle
 * handed to the forceps at t (none: t < 0). */
static void write_scene(double t_handover, const char *name)
{
    rod_instrument probe = {.kind = ROD_INSTRUMENT_NEEDLE_HOLDER, .size = 0.12};
    double lj, rj, rs;
    rod_instrument_dimensions(&probe, &lj, &rj, &rs);
    const double q = 0.5 * M_PI, z = -0.5 * lj; /* down: 90 degrees about y */
    /* each motion between rows at rest (a row repeated): the path's C2
     * spline through the rows overshoots the lift by 4.6 mm without them */
    const double y1 = Y_GRASP + 0.002, z1 = z + 0.005;
    const double rows[][6] = {
        {0.0, 0.0, 0.0, 0.0, 0.0, 0},     {0.5, 0.0, 0.0, 0.0, 0.0, 0},
        {0.6, 0.0, 0.0, 0.0, 0.0, 1},     {0.65, -0.005, 0.0, 0.0, 0.0, 1},
        {0.7, -0.005, 0.0, 0.006, 0.0, 1}, {0.8, -0.005, 0.0, 0.006, q, 1},
        {0.85, 0.0, Y_GRASP, 0.006, q, 1}, {0.9, 0.0, Y_GRASP, z, q, 1},
        {0.95, 0.0, Y_GRASP, z, q, 1},     {T_CLOSE, 0.0, Y_GRASP, z, q, 0},
        {1.05, 0.0, Y_GRASP, z, q, 0},     {1.45, 0.0, y1, z1, q, 0},
        {1.5, 0.0, y1, z1, q, 0},          {2.0, 0.0, y1, z1, q, 0}};
    char text[2048] = "t,x,y,z,rx,ry,rz,jaw\n";
    size_t used = strlen(text);
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; i++)
        used += (size_t)snprintf(text + used, sizeof text - used,
                                 "%.17g,%.17g,%.17g,%.17g,0,%.17g,0,%g\n", rows[i][0], rows[i][1],
                                 rows[i][2], rows[i][3], rows[i][4], rows[i][5]);
    write_file("holder.csv", text);
    write_file("forceps.csv", "t,x,y,z,rx,ry,rz,jaw\n0,0,0.002,0,0,0,0,0\n");
    /* the forceps out of the way where no needle is handed to them */
    write_file("away.csv", "t,x,y,z,rx,ry,rz,jaw\n0,0,0.03,0,0,0,0,1\n");
    char grasp[128] = "";
    if (t_handover >= 0.0)
        snprintf(grasp, sizeof grasp, "[needle_grasp]\nt = %g\ninstrument = forceps\n",
                 t_handover);
    snprintf(text, sizeof text,
             "[rod]\nlength = 0.05\ndiameter = %g\nnodes = 26\ndensity = 1140\n"
             "youngs_modulus = 1.5e9\nshear_modulus = 0.55e9\n"
             "origin = 0 -0.05 0\ndirection = 0 1 0\n"
             "[ends]\nroot = free\ntip = clamped\nneedle = 0.005\n"
             "[instrument]\nkind = needle_holder\nname = holder\npath = holder.csv\n"
             "needle = yes\nsize = 0.12\ngrip = 50\n"
             "[instrument]\nkind = forceps\nname = forceps\npath = %s\nsize = 0.12\n"
             /* the forceps come to the needle where the holder's jaws are, their
              * bodies on the same line: the test's placement, not a surgeon's */
             "may_overlap = yes\n"
             "%s[solver]\nscheme = implicit\ndt = 0.001\nduration = 1.6\n"
             "[render]\nneedle_arc = 1/2\n",
             DIAMETER, t_handover >= 0.0 ? "forceps.csv" : "away.csv", grasp);
    write_file(name, text);
}

/* Replaces the first `from` in text (size bytes) by `to`: 1, or 0 when none. */
static int replace(char *text, size_t size, const char *from, const char *to)
{
    char *at = strstr(text, from);
    const size_t lf = strlen(from), lt = strlen(to), rest = strlen(at ? at + lf : "");
    if (!at || (size_t)(at - text) + lt + rest + 1 > size) return 0;
    memmove(at + lt, at + lf, rest + 1);
    memcpy(at, to, lt);
    return 1;
}

static int read_scene(const char *name, rod_model *m, char *err, size_t errlen)
{
    return test_read_scene_in(dir, name, m, err, errlen);
}

/* The thread's point at arc length s. */
static void point_at(const rod_model *m, const rod_state *s, double arc, double p[3])
{
    int j = (int)floor(arc / m->ds);
    if (j > m->nodes - 2) j = m->nodes - 2;
    double f = arc / m->ds - j;
    for (int c = 0; c < 3; c++)
        p[c] = (1.0 - f) * s->position[3 * j + c] + f * s->position[3 * j + 3 + c];
}

/* Steps the scene in the library: the holder's grasp (time, arc length) and
 * the grasped point's largest distance from the jaws' held point (m). */
static void step_scene(const char *name)
{
    rod_model m;
    char err[1024] = "";
    if (!check(read_scene(name, &m, err, sizeof err) == 0, "%s reads (%s)", name,
               err[0] ? err : "ok"))
        return;
    rod_state *s = rod_state_create(&m);
    rod_solver solver;
    if (!check(s && rod_solver_init(&solver, &m, err, sizeof err) == 0, "solver: %s", err)) {
        rod_state_destroy(s);
        rod_model_release(&m);
        return;
    }
    rod_report report;
    memset(&report, 0, sizeof report);
    double worst = 0.0, t_on = -1.0, s0 = -1.0, z_on = 0.0, jaw_on = 0.0, jaw_z = 0.0;
    int ok = 1;
    for (int k = 1; k <= 1600 && ok; k++) {
        if (rod_solver_step(&solver, &m, s, 0.001, &report)) {
            check(0, "step %d (t = %g s): %s", k, s->time, report.message);
            ok = 0;
            break;
        }
        if (!s->grasp[0].held) continue;
        if (t_on < 0.0) {
            t_on = s->grasp[0].t_on;
            s0 = s->grasp[0].s;
            double p0[3];
            point_at(&m, s, s0, p0);
            z_on = p0[2];
            rod_grasp_point(&m, 0, &s->grasp[0], s->time, p0, NULL);
            jaw_on = p0[2];
        }
        /* the held point (it slides along the thread only beyond the grip) */
        double jawp[3], p[3], e[3];
        rod_grasp_point(&m, 0, &s->grasp[0], s->time, jawp, NULL);
        jaw_z = jawp[2];
        point_at(&m, s, s->grasp[0].s, p);
        v3_sub(e, p, jawp);
        worst = fmax(worst, v3_norm(e));
    }
    if (ok) {
        check(t_on > 0.5 && t_on <= T_CLOSE + 1e-9,
              "the holder takes the thread after the handover (0.5 s) as its jaws close "
              "(by %g s): at %g s", T_CLOSE, t_on);
        check_abs("the holder's grasp's arc length, m (the jaws' middle's, 25 mm)", s0,
                  0.05 + Y_GRASP, m.ds);
        printf("     the grasped point's largest distance from the jaws' point: %.3g m = "
               "%.3g d\n", worst, worst / DIAMETER);
        check(t_on > 0.0 && worst < 0.05 * DIAMETER,
              "the grasped point follows the jaws within 5 %% of d as they lift 5 mm "
              "(computed %.3g d, limit 0.05 d)", worst / DIAMETER);
        double p[3];
        point_at(&m, s, s->grasp[0].s, p);
        printf("     the jaws' held point's rise from the grasp to the end: %.4g mm (the "
               "path's 5 mm, its spline still settling)\n", 1e3 * (jaw_z - jaw_on));
        check_abs("the grasped point's rise, m, vs the jaws' held point's", p[2] - z_on,
                  jaw_z - jaw_on, 0.05 * DIAMETER);
    }
    rod_solver_release(&solver);
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* Runs `name` through rodsim; the summary's text in json. */
static int run_scene(const char *name, char *json, size_t len)
{
    char scene[320], summary[320], out[8192];
    snprintf(scene, sizeof scene, "%s/%s", dir, name);
    snprintf(summary, sizeof summary, "%s/summary.json", dir);
    unlink(summary);
    const char *args[] = {"run", scene, "--no-video", "--quiet", "--summary", summary, "-o", dir,
                          NULL};
    const int rc = test_run_rodsim(args, out, sizeof out);
    json[0] = '\0';
    FILE *f = fopen(summary, "r");
    if (f) {
        size_t got = fread(json, 1, len - 1, f);
        json[got] = '\0';
        fclose(f);
    }
    return rc;
}

/* The time the rule frees the holder (instrument 0) after the handover at
 * 0.5 s, and the rule's answers either side of it. */
static void check_freed(void)
{
    rod_model m;
    char err[1024] = "";
    if (!check(read_scene("after.ini", &m, err, sizeof err) == 0, "after.ini reads (%s)",
               err[0] ? err : "ok"))
        return;
    const double t1 = m.needle_grasps[0].freed;
    rod_pose pose;
    double jaw = -1.0;
    rod_instrument_pose(&m.instruments[0], t1, &pose, &jaw);
    printf("     the holder freed after the handover at %.9g s\n", t1);
    check(t1 > 0.95 && t1 < T_CLOSE, "freed as its jaws close again (0.95 to %g s): %.9g s",
          T_CLOSE, t1);
    check_abs("the holder's opening there (ROD_JAW_CLOSED)", jaw, ROD_JAW_CLOSED, 1e-6);
    static const double on[] = {0.501, 0.55, 0.9};
    for (int i = 0; i < 3; i++)
        check(needle_grasp_jaws_on_needle(&m, 0, on[i]) && needle_grasp_takes_needle(&m, 0, on[i]),
              "at %g s, after the handover, before the close: on the needle, touch and take "
              "no thread", on[i]);
    const double after = t1 + 1e-6;
    check(!needle_grasp_jaws_on_needle(&m, 0, after) && !needle_grasp_takes_needle(&m, 0, after),
          "closed again (%.6g s): ordinary jaws", after);
    check(!needle_grasp_jaws_on_needle(&m, 0, 1.5) && !needle_grasp_takes_needle(&m, 0, 1.5),
          "at 1.5 s: ordinary jaws");
    check(needle_grasp_jaws_on_needle(&m, 1, 1.0) && needle_grasp_takes_needle(&m, 1, 1.0),
          "the forceps holding the needle at 1 s: on the needle");
    rod_model_release(&m);
}

int main(void)
{
    if (!check(mkdtemp(dir) != NULL, "scratch directory")) return test_finish();
    static char json[65536];
    write_scene(0.5, "after.ini");
    check_freed();
    step_scene("after.ini");
    int rc = run_scene("after.ini", json, sizeof json);
    const char *g = strstr(json, "\"grasps\":[{\"instrument\":\"holder\"");
    printf("     %.90s\n", g ? g : "(no grasp by the holder)");
    double t_json = -1.0, s_json = -1.0;
    const char *ts = g ? strstr(g, "\"t_on\":") : NULL, *ss = g ? strstr(g, "\"s\":") : NULL;
    if (ts) t_json = atof(ts + 7);
    if (ss) s_json = atof(ss + 4);
    check(rc == 0 && t_json > 0.95 && t_json <= T_CLOSE && fabs(s_json - 0.025) < 0.002,
          "the summary lists the holder's grasp: t_on %g s (closing 0.95 to %g s), s %g m "
          "(0.025 within ds) (exit %d)", t_json, T_CLOSE, s_json, rc);

    /* handed over at 0.45 s: the holder's jaws closed on the needle's back,
     * the thread's tip, to 0.5 s and a little after */
    write_scene(0.45, "closed.ini");
    rc = run_scene("closed.ini", json, sizeof json);
    g = strstr(json, "\"grasps\":[{\"instrument\":\"holder\"");
    ts = g ? strstr(g, "\"t_on\":") : NULL;
    t_json = ts ? atof(ts + 7) : -1.0;
    printf("     %.90s\n", g ? g : "(no grasp by the holder)");
    check(rc == 0 && strstr(json, "\"t_end\":1.6") && t_json > 0.95 && t_json <= T_CLOSE,
          "jaws still closed on the needle after the handover touch and take nothing: the "
          "run ends at 1.6 s, the holder's only grasp at %g s (closing 0.95 to %g s) "
          "(exit %d)", t_json, T_CLOSE, rc);

    /* the same, a 0.2 mm thread hanging from the needle up through the jaws'
     * opening plane under gravity, to 0.6 s */
    write_scene(0.45, "hanging.ini");
    {
        char path[256], text[8192] = "", out[8192] = "";
        snprintf(path, sizeof path, "%s/hanging.ini", dir);
        FILE *f = fopen(path, "r");
        size_t got = f ? fread(text, 1, sizeof text - 1, f) : 0;
        if (f) fclose(f);
        text[got] = '\0';
        static const char *const from[] = {"diameter = 0.0005", "origin = 0 -0.05 0",
                                           "direction = 0 1 0", "duration = 1.6",
                                           "grip = 50\n", "[solver]\n"};
        static const char *const to[] = {"diameter = 0.0002", "origin = 0 0 0.05",
                                         "direction = 0 0 -1", "duration = 0.6", "",
                                         "[loads]\ngravity = 0 0 -9.81\n[solver]\n"};
        int all = got > 0;
        for (int i = 0; i < 6; i++) all = replace(text, sizeof text, from[i], to[i]) && all;
        write_file("hanging.ini", text);
        const char *args[] = {"run", path, "--no-video", "--quiet", "-o", dir, NULL};
        rc = test_run_rodsim(args, out, sizeof out);
        check(all && rc == 0, "a thread hanging from the needle through the holder's jaws, "
              "closed after the handover, then opening: the run ends (exit %d) %.120s", rc,
              out);
    }

    write_scene(-1.0, "before.ini");
    rc = run_scene("before.ini", json, sizeof json);
    g = strstr(json, "\"instrument\":\"holder\",\"t_on\"");
    printf("     %.60s\n", g ? g : "(no grasp by the holder)");
    check(rc == 0 && strstr(json, "\"t_end\":1.6") && !g,
          "the holder closing on the thread while it holds the needle takes nothing (exit %d)",
          rc);
    if (!getenv("KEEP")) test_remove_tree(dir); else printf("kept %s\n", dir);
    return test_finish();
}
