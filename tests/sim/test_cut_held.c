/* test_cut_held.c: a tail cut while an instrument holds it (sim/cut.h):
 * a thread through two punctures, its root in a hand (ends.root_motion, a
 * driven end), its tip's tail in forceps' closed jaws. Against independent
 * values (the thread's ds, the cuts' arc lengths, free fall):
 *  - [cut] beyond the tip's puncture: the tail goes, the forceps' grasp
 *    ends at the cut's time (the summary's t_off), removed 0.05 m exactly;
 *  - [cut] beyond the root's puncture: the tail goes with the hand's hold
 *    (a driven end lets go as a grasp does; both sides anchored by a fixed
 *    end or puncture is refused), removed 0.05 m exactly, 0.1 m left
 *    between the cuts (whole segments: the cuts on nodes);
 *  - the hand, rising 2 cm after the second cut, carries nothing: the cut
 *    end left stays within 1 mm of where it was cut (x = 0.05 m, z = 0);
 *  - both punctures stay in the summary, the knot tracker's thread is the
 *    one left; the warning list empty (no cut refused). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sim/instrument.h"
#include "test.h"
#include "test_process.h"

static char dir[] = "/tmp/rodsim_cut_heldXXXXXX";

static void write_file(const char *name, const char *text)
{
    test_write_in(dir, name, text);
}

/* The number after "key": in text, or NAN. */
static double number_after(const char *text, const char *key)
{
    const char *p = text ? strstr(text, key) : NULL;
    return p ? atof(p + strlen(key)) : NAN;
}

int main(void)
{
    if (!check(mkdtemp(dir) != NULL, "scratch directory")) return test_finish();
    /* forceps pointing down (local x = -z, local y = +x: closing across the
     * thread along x), their jaws' middle on the thread at x = 0.19 m, shut
     * from the start: 120 degrees about (1, 1, -1) / sqrt 3 */
    rod_instrument probe = {.kind = ROD_INSTRUMENT_FORCEPS, .size = 0.12};
    double lj, rj, rs;
    rod_instrument_dimensions(&probe, &lj, &rj, &rs);
    const double a = 2.0 * M_PI / 3.0 / sqrt(3.0);
    char rows[512];
    snprintf(rows, sizeof rows, "t,x,y,z,rx,ry,rz,jaw\n0,0.19,0,%.17g,%.17g,%.17g,%.17g,0\n",
             -0.5 * lj, a, a, -a);
    write_file("forceps.csv", rows);
    /* the hand still to the second cut, then 2 cm up by 0.45 s */
    write_file("hand.csv", "t,x,y,z,rx,ry,rz\n0,0,0,0,0,0,0\n0.3,0,0,0,0,0,0\n0.45,0,0,0.02,0,0,0\n"
                           "1,0,0,0.02,0,0,0\n");
    write_file("cut.ini",
               "[rod]\nlength = 0.2\ndiameter = 0.0005\nnodes = 41\ndensity = 1140\n"
               "youngs_modulus = 1.5e9\nshear_modulus = 0.55e9\n"
               "origin = 0 0 0\ndirection = 1 0 0\n"
               "[ends]\nroot = clamped\nroot_motion = hand.csv\ntip = free\n"
               "[loads]\ngravity = 0 0 -9.81\n"
               "[instrument]\nkind = forceps\nname = forceps\npath = forceps.csv\nsize = 0.12\n"
               "[puncture]\npoint = 0.08 0 0\n[puncture]\npoint = 0.12 0 0\n"
               "[cut]\nt = 0.2\ns = 0.15\n[cut]\nt = 0.3\ns = 0.05\n"
               "[solver]\nscheme = implicit\ndt = 0.001\nduration = 0.45\n");
    char scene[320], summary[320], csv[320], out[8192];
    snprintf(scene, sizeof scene, "%s/cut.ini", dir);
    snprintf(summary, sizeof summary, "%s/summary.json", dir);
    snprintf(csv, sizeof csv, "%s/cut.csv", dir);
    const char *args[] = {"run", scene, "--no-video", "--quiet", "--summary", summary,
                          "--csv", csv, "-o", dir, NULL};
    const int rc = test_run_rodsim(args, out, sizeof out);
    check(rc == 0, "rodsim run (exit %d) %s", rc, rc ? out : "");
    static char json[65536];
    json[0] = '\0';
    FILE *f = fopen(summary, "r");
    if (f) {
        size_t got = fread(json, 1, sizeof json - 1, f);
        json[got] = '\0';
        fclose(f);
    }
    const char *warnings = strstr(json, "\"warnings\":");
    check(warnings && strncmp(warnings, "\"warnings\":[]", 13) == 0, "no warning: %.160s",
          warnings ? warnings : "(none)");
    const char *grasp = strstr(json, "\"grasps\":[{\"instrument\":\"forceps\"");
    const double t_off = number_after(grasp, "\"t_off\":");
    printf("     %.120s\n", grasp ? grasp : "(no grasp)");
    check(grasp && fabs(t_off - 0.2) < 1.5e-3 && fabs(number_after(grasp, "\"s\":") - 0.19) < 2.5e-3,
          "the forceps held the tip's tail at s = 0.19 m and let go at the cut: t_off %g s "
          "(0.2 within a step)", t_off);
    const char *cuts = strstr(json, "\"cuts\":[");
    const char *second = cuts ? strstr(cuts + 8, "},{") : NULL;
    const double r1 = number_after(cuts, "\"removed\":"), r2 = number_after(second, "\"removed\":");
    printf("     %.200s\n", cuts ? cuts : "(no cuts)");
    check_abs("the tip's tail cut off beyond its puncture, m", r1, 0.05, 1e-12);
    check_abs("the root's tail cut off with the hand's hold, m", r2, 0.05, 1e-12);
    check_abs("the cut at s, m", number_after(second, "\"s\":"), 0.05, 1e-12);
    const char *punctures = strstr(json, "\"punctures\":[");
    int count = 0;
    for (const char *p = punctures; p && (p = strstr(p, "\"point\":")) != NULL; p++) count++;
    check(count == 2, "both punctures in the summary (%d)", count);
    /* the CSV's last frame: nodes 10 to 30 of the uncut thread (0.1 m), the
     * cut end at node 10 where it was (held by the punctures' 3 cm of stiff
     * thread), not 2 cm up with the hand */
    f = fopen(csv, "r");
    char line[512];
    double t_last = -1.0, x10 = 0.0, z10 = 0.0;
    int first = 1000, last = -1;
    while (f && fgets(line, sizeof line, f)) {
        double t, sv, x, y, z;
        int node;
        if (sscanf(line, "%lf,%d,%lf,%lf,%lf,%lf", &t, &node, &sv, &x, &y, &z) != 6) continue;
        if (t > t_last + 1e-9) {
            t_last = t;
            first = 1000;
            last = -1;
        }
        if (node < first) first = node;
        if (node > last) last = node;
        if (node == 10) {
            x10 = x;
            z10 = z;
        }
    }
    if (f) fclose(f);
    check(first == 10 && last == 30, "the thread left: nodes %d to %d (10 to 30: 0.1 m) at "
          "t = %g s", first, last, t_last);
    check(fabs(x10 - 0.05) < 0.001 && fabs(z10) < 0.001,
          "the cut end let go by the hand (2 cm up): at (%.4g, %.4g) mm, within 1 mm of "
          "(50, 0) mm", 1e3 * x10, 1e3 * z10);
    if (!getenv("KEEP")) test_remove_tree(dir);
    return test_finish();
}
