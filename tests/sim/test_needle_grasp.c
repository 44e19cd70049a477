/* test_needle_grasp.c: the needle handed between instruments ([needle_grasp],
 * sim/needle_grasp.h), against independent values:
 *  - the needle's pose (the thread's tip) is continuous across the grasp's
 *    time t: position within 1e-12 m, rotation within 1e-12;
 *  - after t it keeps its pose relative to the new jaws as it was at t
 *    (the jaws' rotation and tip from their own path: R_f^T (p - g) and
 *    R_f^T R_needle at t and at later times, within 1e-12);
 *  - where the new jaws turn about a fixed axis through a fixed point, the
 *    needle's back moves on the circle about that axis (the closed form);
 *  - its velocity and angular velocity match central differences of its
 *    pose (relative error under 1e-6);
 *  - a run of the scene steps through the handover, the summary lists it;
 *  - refused, naming file, line, key and what is accepted: an unknown name,
 *    times out of order or at the holder's path's start, jaws farther than a
 *    jaw length from the needle, scissors, the instrument holding it
 *    already, no instrument named. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/ini.h"
#include "base/vec3.h"
#include "sim/instrument.h"
#include "sim/needle_grasp.h"
#include "sim/path.h"
#include "sim/rod.h"
#include "sim/scene.h"
#include "test.h"
#include "test_process.h"
#include "test_scene_file.h"

#define T_GRASP 0.5 /* s */
#define OMEGA 2.0   /* rad/s: the forceps' turn about x after the grasp */

static char dir[] = "/tmp/rodsim_needle_graspXXXXXX";

static void write_file(const char *name, const char *text)
{
    test_write_in(dir, name, text);
}

/* The scene: a 5 cm thread along -z from (0, 0, 0.05), its tip (0, 0, 0)
 * clamped, a 5 mm needle; the holder still at the tip; the forceps'
 * jaws' tip at the needle's point side, 2 mm off the back along y, still
 * until the grasp, then turning about the x axis through C = (0, 0.004, 0)
 * at OMEGA (rows every 0.01 s on the circle, the rotation vector (a, 0, 0)). */
static void write_scene(const char *extra, const char *forceps, const char *name)
{
    char text[4096];
    snprintf(text, sizeof text,
             "[rod]\nlength = 0.05\ndiameter = 0.0002\nnodes = 26\ndensity = 1140\n"
             "youngs_modulus = 1.5e9\nshear_modulus = 0.55e9\n"
             "origin = 0 0 0.05\ndirection = 0 0 -1\n"
             "[ends]\nroot = free\ntip = clamped\nneedle = 0.005\n"
             "[instrument]\nkind = needle_holder\nname = holder\npath = holder.csv\n"
             "needle = yes\nsize = 0.12\n"
             "[instrument]\nkind = forceps\nname = forceps\npath = %s\nsize = 0.12\n"
             /* the forceps come to the needle where the holder's jaws are, their
              * bodies on the same line: the test's placement, not a surgeon's */
             "may_overlap = yes\n"
             "[instrument]\nkind = scissors\nname = scissors\npath = scissors.csv\n"
             "[solver]\nscheme = implicit\ndt = 0.001\nduration = 0.6\n"
             "[render]\nneedle_arc = 1/2\n%s",
             forceps, extra);
    write_file(name, text);
}

static void write_paths(void)
{
    write_file("holder.csv", "t,x,y,z,rx,ry,rz,jaw\n0,0,0,0,0,0,0,0\n2,0,0,0,0,0,0,0\n");
    /* open scissors and forceps far from the needle (3 cm off along y) */
    write_file("scissors.csv", "t,x,y,z,rx,ry,rz,jaw\n0,0,0.03,0,0,0,0,1\n");
    write_file("far.csv", "t,x,y,z,rx,ry,rz,jaw\n0,0,0.03,0,0,0,0,1\n");
    char text[16384] = "t,x,y,z,rx,ry,rz,jaw\n";
    size_t used = strlen(text);
    /* still at (0, 0.002, 0) until T_GRASP, then on the circle about C */
    used += (size_t)snprintf(text + used, sizeof text - used, "0,0,0.002,0,0,0,0,0\n");
    for (int k = 0; k <= 100; k++) {
        const double t = T_GRASP + 0.01 * k, a = k ? OMEGA * (t - T_GRASP) : 0.0;
        /* (0, 0.002, 0) - C = (0, -0.002, 0) turned by a about x */
        used += (size_t)snprintf(text + used, sizeof text - used, "%.17g,0,%.17g,%.17g,%.17g,0,0,0\n",
                                 t, 0.004 - 0.002 * cos(a), -0.002 * sin(a), a);
    }
    write_file("forceps.csv", text);
}

/* Reads scene `name`; 0 or -1 with err. */
static int read_scene(const char *name, rod_model *m, char *err, size_t errlen)
{
    return test_read_scene_in(dir, name, m, err, errlen);
}

static double rot_diff(const double *a, const double *b)
{
    double d = 0.0;
    for (int k = 0; k < 9; k++) d = fmax(d, fabs(a[k] - b[k]));
    return d;
}

/* R_f^T (p - g) and R_f^T R of the needle at t */
static void relative(const rod_model *m, int k, double t, double local[3], double rot[9])
{
    rod_pose needle, jaws;
    rod_path_eval(m->tip_motion, t, &needle);
    rod_instrument_pose(&m->instruments[k], t, &jaws, NULL);
    double d[3];
    v3_sub(d, needle.position, jaws.position);
    m3_mul_tv(local, jaws.rotation, d);
    m3_mul_tn(rot, jaws.rotation, needle.rotation);
}

static void check_motion(const rod_model *m)
{
    rod_pose before, at;
    const double tb = nextafter(T_GRASP, 0.0);
    rod_path_eval(m->tip_motion, tb, &before);
    rod_path_eval(m->tip_motion, T_GRASP, &at);
    double d[3];
    v3_sub(d, at.position, before.position);
    check(v3_norm(d) <= 1e-12, "the needle's back continuous across t = %g s: a jump of %.3e m "
          "(tolerance 1e-12)", T_GRASP, v3_norm(d));
    check(rot_diff(at.rotation, before.rotation) <= 1e-12,
          "its rotation continuous: a jump of %.3e (tolerance 1e-12)",
          rot_diff(at.rotation, before.rotation));
    /* held by the forceps (instrument 1) as it was at T_GRASP */
    double l0[3], r0[9];
    relative(m, 1, T_GRASP, l0, r0);
    double worst = 0.0, worst_r = 0.0;
    for (int i = 1; i <= 20; i++) {
        double l[3], r[9];
        relative(m, 1, T_GRASP + 0.03 * i, l, r);
        v3_sub(d, l, l0);
        worst = fmax(worst, v3_norm(d));
        worst_r = fmax(worst_r, rot_diff(r, r0));
    }
    check(worst <= 1e-12 && worst_r <= 1e-12,
          "after t the needle keeps its place in the forceps' jaws: moved %.3e m, turned "
          "%.3e in their frame (tolerance 1e-12)", worst, worst_r);
    /* the forceps turn about x through C = (0, 0.004, 0) by a = OMEGA (t - T_GRASP)
     * on their circle's rows: the back, at the origin at T_GRASP, is at
     * C + Rx(a) (0, -0.004, 0) where the path passes a row exactly */
    rod_pose later, forceps;
    const double t = T_GRASP + 0.3, a = OMEGA * 0.3;
    rod_path_eval(m->tip_motion, t, &later);
    rod_instrument_pose(&m->instruments[1], t, &forceps, NULL);
    const double want[3] = {0.0, 0.004 - 0.004 * cos(a), -0.004 * sin(a)};
    v3_sub(d, later.position, want);
    check(v3_norm(d) <= 1e-12, "at t = %.2f s the back at (0, %.9g, %.9g) m, the closed form "
          "(0, %.9g, %.9g): off by %.3e m (tolerance 1e-12)", t, later.position[1],
          later.position[2], want[1], want[2], v3_norm(d));
    /* velocities against central differences of the pose */
    const double h = 1e-6, tv = T_GRASP + 0.237;
    rod_pose lo, hi, mid;
    rod_path_eval(m->tip_motion, tv - h, &lo);
    rod_path_eval(m->tip_motion, tv + h, &hi);
    rod_path_eval(m->tip_motion, tv, &mid);
    double fd[3], dr[9], w[3];
    for (int k = 0; k < 3; k++) fd[k] = (hi.position[k] - lo.position[k]) / (2 * h);
    check_rel("the needle's speed |v| against the central difference (m/s)",
              v3_norm(mid.velocity), v3_norm(fd), 1e-6);
    v3_sub(d, mid.velocity, fd);
    check(v3_norm(d) <= 1e-6 * v3_norm(fd), "its velocity's direction: |v - v_fd| = %.3e m/s",
          v3_norm(d));
    /* W = dR/dt R^T, the skew matrix of omega */
    for (int k = 0; k < 9; k++) dr[k] = (hi.rotation[k] - lo.rotation[k]) / (2 * h);
    double wm[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            wm[3 * i + j] = dr[3 * i] * mid.rotation[3 * j] + dr[3 * i + 1] * mid.rotation[3 * j + 1] +
                            dr[3 * i + 2] * mid.rotation[3 * j + 2];
    w[0] = wm[7];
    w[1] = wm[2];
    w[2] = wm[3];
    check_rel("its angular velocity about x against dR/dt R^T (rad/s)", mid.angular_velocity[0],
              w[0], 1e-6);
    check_rel("... and against the forceps' turn OMEGA (rad/s)", mid.angular_velocity[0], OMEGA,
              1e-3);
}

/* The scene with `extra` refused, its message naming `key` and `accepted`. */
static void refused(const char *extra, const char *forceps, const char *key,
                    const char *accepted, const char *what)
{
    write_scene(extra, forceps, "bad.ini");
    rod_model m;
    char err[1024] = "";
    const int rc = read_scene("bad.ini", &m, err, sizeof err);
    check(rc != 0 && strstr(err, "bad.ini:") && strstr(err, key) && strstr(err, accepted),
          "%s: refused (%s)", what, err);
    if (rc == 0) rod_model_release(&m);
}

int main(void)
{
    if (!check(mkdtemp(dir) != NULL, "scratch directory")) return test_finish();
    write_paths();
    write_scene("[needle_grasp]\nt = 0.5\ninstrument = forceps\n", "forceps.csv", "ok.ini");
    rod_model m;
    char err[1024] = "";
    if (check(read_scene("ok.ini", &m, err, sizeof err) == 0, "the scene reads (%s)",
              err[0] ? err : "ok")) {
        check(m.needle_grasp_count == 1 && m.needle_grasps[0].instrument == 1,
              "one grasp, by the forceps");
        check_motion(&m);
        rod_model_release(&m);
    }
    /* the run: stepped through the handover, the summary lists it */
    char ok[320], summary[320], out[8192];
    snprintf(ok, sizeof ok, "%s/ok.ini", dir);
    snprintf(summary, sizeof summary, "%s/summary.json", dir);
    const char *args[] = {"run", ok, "--no-video", "--quiet", "--summary", summary, "-o", dir, NULL};
    const int rc = test_run_rodsim(args, out, sizeof out);
    check(rc == 0, "rodsim run steps through the handover (exit %d)", rc);
    FILE *f = fopen(summary, "r");
    char json[65536] = "";
    if (f) {
        size_t got = fread(json, 1, sizeof json - 1, f);
        json[got] = '\0';
        fclose(f);
    }
    check(strstr(json, "\"needle_grasps\":[{\"t\":0.5,\"from\":\"holder\",\"to\":\"forceps\"}]") != NULL,
          "the summary lists the handover (%s)", strstr(json, "needle_grasps") ? "needle_grasps" : "none");

    refused("[needle_grasp]\nt = 0.5\ninstrument = clamp\n", "forceps.csv",
            "[needle_grasp] instrument", "accepted: holder | forceps | scissors", "an unknown name");
    refused("[needle_grasp]\nt = 0.5\ninstrument = forceps\n[needle_grasp]\nt = 0.4\n"
            "instrument = holder\n", "forceps.csv", "t = 0.4", "after the grasp before it",
            "times out of order");
    refused("[needle_grasp]\nt = 0\ninstrument = forceps\n", "forceps.csv", "[needle_grasp] t",
            "after the needle holder's path starts", "a grasp at the path's start");
    /* the forceps 30 mm off the back, the needle (a 1/2 circle of 5 mm from
     * the origin, in the plane of d3 and d1) at most 10 mm across: at least
     * 20 mm off, beyond their 18 mm jaws */
    refused("[needle_grasp]\nt = 0.5\ninstrument = forceps\n", "far.csv", "[needle_grasp] t",
            "accepted: a time when its path has the jaws' tip on the needle",
            "jaws 20 mm or more from the needle");
    refused("[needle_grasp]\nt = 0.5\ninstrument = scissors\n", "forceps.csv",
            "[needle_grasp] instrument", "accepted: a needle_holder or forceps", "scissors");
    refused("[needle_grasp]\nt = 0.5\ninstrument = holder\n", "forceps.csv",
            "[needle_grasp] instrument", "accepted: another instrument's name",
            "the holder handing it to itself");
    refused("[needle_grasp]\nt = 0.5\n", "forceps.csv", "[needle_grasp] instrument", "required",
            "no instrument named");
    test_remove_tree(dir);
    return test_finish();
}
