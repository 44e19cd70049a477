/* test_live_instruments.c: `rodsim live` driving an instrument by its
 * name. grasp_lift.ini to 2 s: the forceps driven by lines `forceps:
 * t,x,y,z,rx,ry,rz,jaw` every 1 ms, each the pose and opening the scene's
 * path gives at that t (its own interpolation, evaluated here), against
 * `rodsim run` of the path file itself in steps of the same 1 ms: the jaws
 * take the thread at the same step, the same arc length, and the thread
 * lifted 2 cm ends where the run leaves it to 1e-3 d (a motion late by one
 * line, 1 ms, would put it 0.08 d off: lifted at 4 cm/s); the grasp force
 * at rest is answered; a line naming the forceps with a jaw out of 0..1 or
 * 7 numbers is refused (bad_input, the forceps' answer). Two threads
 * crossing (named rods): the forceps driven live take the upper at the
 * step rodsim run takes it, the answer names the rod, and both threads end
 * where the run leaves them. Lines driving the forceps' jaws deeper than
 * max_depth into a pad are answered failed, not stepped, with the depth,
 * the surface and the key (test_jaws_into_surface). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/vec3.h"
#include "sim/instrument.h"
#include "sim/path.h"
#include "test.h"
#include "test_csv.h"

#define DIAMETER 0.0005 /* m, grasp_lift.ini's thread */

static char dir[64];

/* The whole file (read_text stops at 1 MB), NULL when unreadable */
static char *read_all(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    const long n = ftell(f);
    rewind(f);
    char *text = n >= 0 ? malloc((size_t)n + 1) : NULL;
    if (text) text[fread(text, 1, (size_t)n, f)] = '\0';
    fclose(f);
    return text;
}

/* grasp_lift.ini to 2 s, 50 frames a second (steps of exactly 1 ms) */
static int write_scene(const char *path)
{
    char *text = read_text("scenes/grasp_lift.ini");
    if (!text) return -1;
    FILE *f = fopen(path, "w");
    if (!f) {
        free(text);
        return -1;
    }
    for (char *line = strtok(text, "\n"); line; line = strtok(NULL, "\n")) {
        if (strncmp(line, "duration", 8) == 0) fputs("duration = 2\n", f);
        else if (strncmp(line, "fps", 3) == 0) fputs("fps = 50\n", f);
        else if (strncmp(line, "path", 4) == 0) fputs("path = forceps.csv\n", f);
        else fprintf(f, "%s\n", line);
    }
    free(text);
    return fclose(f);
}

/* The live lines: the path's pose and opening every 1 ms to `end` s, then
 * (bad) two refused lines */
static int write_lines(const char *csv, const char *lines, double end, int bad)
{
    rod_instrument in;
    memset(&in, 0, sizeof in);
    char err[512];
    if (rod_instrument_load_path(csv, &in.pose, &in.jaw, err, sizeof err)) return -1;
    FILE *f = fopen(lines, "w");
    for (int i = 1; f && i <= (int)lround(end * 1e3); i++) {
        const double t = 1e-3 * i;
        rod_pose pose;
        double jaw, rv[3];
        rod_instrument_pose(&in, t, &pose, &jaw);
        m3_log(rv, pose.rotation);
        fprintf(f, "forceps: %.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", t,
                pose.position[0], pose.position[1], pose.position[2], rv[0], rv[1], rv[2], jaw);
    }
    if (f && bad) fprintf(f, "forceps: 2.001,0,0,0,0,0,0,1.5\nforceps: 2.001,0,0,0,0,0,0\n");
    rod_path_destroy(in.pose);
    rod_path_destroy(in.jaw);
    return f ? fclose(f) : -1;
}

static void test_live_against_run(void)
{
    char scene[128], csv[128], lines[128], answers[128], run_csv[128], json[128], cmd[1024];
    snprintf(scene, sizeof scene, "%s/lift.ini", dir);
    snprintf(csv, sizeof csv, "%s/forceps.csv", dir);
    snprintf(lines, sizeof lines, "%s/lines.txt", dir);
    snprintf(answers, sizeof answers, "%s/answers.csv", dir);
    snprintf(run_csv, sizeof run_csv, "%s/run.csv", dir);
    snprintf(json, sizeof json, "%s/run.json", dir);
    char *path_text = read_text("scenes/grasp_lift_forceps.csv");
    FILE *f = fopen(csv, "w");
    if (f && path_text) fputs(path_text, f);
    if (f) fclose(f);
    free(path_text);
    if (!check(write_scene(scene) == 0 && write_lines(csv, lines, 2.0, 1) == 0, "scene and lines written"))
        return;
    snprintf(cmd, sizeof cmd, "%s live %s --centreline < %s > %s 2> %s/live.log", RODSIM_BIN,
             scene, lines, answers, dir);
    const int live_rc = system(cmd);
    snprintf(cmd, sizeof cmd, "%s run %s --no-video --quiet --csv %s --summary %s", RODSIM_BIN,
             scene, run_csv, json);
    const int run_rc = system(cmd);
    check(live_rc == 0 && run_rc == 0, "live and run ended (%d, %d)", live_rc, run_rc);
    char *ans = read_all(answers), *summary = read_all(json), *rows = read_all(run_csv);
    if (!check(ans && summary && rows, "answers, summary and CSV read")) goto done;
    /* the live grasp: the first answer held */
    double t_live = -1.0, s_live = -1.0, force_z = 0.0, last[3 * 64];
    int nodes = 0, refused = 0;
    for (char *line = strtok(ans, "\n"); line; line = strtok(NULL, "\n")) {
        if (strncmp(line, "forceps,", 8) != 0) continue;
        double v[8];
        char status[16] = "";
        int at = 0;
        if (sscanf(line + 8, "%lf,%lf,%lf,%lf,%lf,%lf,%15[a-z_]%n", &v[0], &v[1], &v[2], &v[3],
                   &v[4], &v[5], status, &at) < 7)
            continue;
        if (strcmp(status, "bad_input") == 0) {
            refused++;
            continue;
        }
        if (v[4] > 0.5 && t_live < 0.0) t_live = v[0], s_live = v[5];
        force_z = v[3];
        const char *p = line + 8 + at;
        for (nodes = 0; *p == ',' && nodes < 3 * 64; nodes++) last[nodes] = strtod(p + 1, (char **)&p);
    }
    const char *on = strstr(summary, "\"t_on\":"), *sg = strstr(summary, "\"s\":");
    const double t_run = on ? atof(on + 7) : -1.0, s_run = sg ? atof(sg + 4) : -1.0;
    check(t_live > 0.0 && fabs(t_live - t_run) < 1e-9,
          "the jaws take the thread at the same step: live t = %.6f s, run t_on = %.6f s",
          t_live, t_run);
    check(fabs(s_live - s_run) < 1e-3 * DIAMETER,
          "at the same arc length: live s = %.9f m, run %.9f m, %.2e d apart", s_live, s_run,
          fabs(s_live - s_run) / DIAMETER);
    /* the run's last frame (t = 2): x,y,z of each node, after t,node */
    int last_row = -1, count = 0; /* the header is row 0 */
    for (const char *p = rows; (p = strchr(p, '\n')); p++) last_row++;
    double worst = 0.0;
    const int ns = nodes / 3, ix = csv_column(rows, "x");
    for (int b = 0; b < ns && ix >= 0; b++) {
        const int row = last_row - ns + 1 + b;
        for (int c = 0; c < 3; c++) {
            char cell[64];
            if (csv_cell(rows, row, ix + c, cell, sizeof cell)) continue;
            worst = fmax(worst, fabs(atof(cell) - last[3 * b + c]));
            count++;
        }
    }
    check(ns == 41 && count == 123 && worst < 1e-3 * DIAMETER,
          "the lifted thread at t = 2 s: live and run %.3g m apart (%.2e d; at most 1e-3 d) "
          "over %d nodes", worst, worst / DIAMETER, ns);
    /* the grasped part's weight on the jaws, lifted 2 cm: downward, about
     * the thread's off the pads (less than the whole, 3.3e-4 N) */
    check(force_z < 0.0 && force_z > -3.4e-4, "the forceps feel the thread: fz = %.4g N",
          force_z);
    check(refused == 2, "a jaw of 1.5 and a 7-number line refused (%d bad_input answers)",
          refused);
done:
    free(ans);
    free(summary);
    free(rows);
}

/* Two threads crossing, the forceps closing on the upper 6 cm from the
 * crossing and lifting it 1.8 cm (test_rod_set_instruments' scene): live
 * lines against rodsim run of the path, in steps of 1 ms */
static void test_two_rods(void)
{
    char scene[128], csv[128], lines[128], answers[128], run_csv[128], json[128], cmd[1024];
    snprintf(scene, sizeof scene, "%s/two.ini", dir);
    snprintf(csv, sizeof csv, "%s/two_forceps.csv", dir);
    snprintf(lines, sizeof lines, "%s/two_lines.txt", dir);
    snprintf(answers, sizeof answers, "%s/two_answers.csv", dir);
    snprintf(run_csv, sizeof run_csv, "%s/two_run.csv", dir);
    snprintf(json, sizeof json, "%s/two.json", dir);
    const char *rv = "1.2091996,1.2091996,-1.2091996";
    FILE *f = fopen(csv, "w");
    if (f) {
        fprintf(f, "t,x,y,z,rx,ry,rz,jaw\n0,0.1,0,0.03,%s,1\n0.8,0.1,0,-0.008,%s,1\n"
                "1,0.1,0,-0.008,%s,0\n1.5,0.1,0,0.01,%s,0\n", rv, rv, rv, rv);
        fclose(f);
    }
    const char *thread = "diameter = 0.0005\ndensity = 850\nyoungs_modulus = 87.5e6\n"
                         "shear_modulus = 31.25e6\n";
    f = fopen(scene, "w");
    if (f) {
        fprintf(f, "[rod upper]\nlength = 0.2\n%snodes = 41\norigin = 0 0 0.00075\n"
                "direction = 1 0 0\n[ends upper]\nroot = free\ntip = free\n[rod lower]\n"
                "length = 0.1\n%snodes = 21\norigin = 0.04 -0.05 0.00025\ndirection = 0 1 0\n"
                "[ends lower]\nroot = free\ntip = free\n[surface]\nshape = box\n"
                "center = 0 0 -0.005\nsize = 0.18 0.1 0.01\n[surface]\nshape = box\n"
                "center = 0.2 0 -0.005\nsize = 0.18 0.1 0.01\n[instrument]\nkind = forceps\n"
                "name = forceps\npath = two_forceps.csv\nsize = 0.12\ngrip = 2\n[solver]\n"
                "scheme = implicit\ndt = 0.001\nduration = 1.5\n[loads]\n"
                "gravity = 0 0 -9.81\n[render]\nfps = 50\n", thread, thread);
        fclose(f);
    }
    if (!check(write_lines(csv, lines, 1.5, 0) == 0, "two rods: scene and lines written")) return;
    snprintf(cmd, sizeof cmd, "%s live %s --centreline < %s > %s 2> %s/two_live.log",
             RODSIM_BIN, scene, lines, answers, dir);
    const int live_rc = system(cmd);
    snprintf(cmd, sizeof cmd, "%s run %s --no-video --quiet --csv %s --summary %s", RODSIM_BIN,
             scene, run_csv, json);
    const int run_rc = system(cmd);
    char *ans = read_all(answers), *summary = read_all(json), *rows = read_all(run_csv);
    if (!check(live_rc == 0 && run_rc == 0 && ans && summary && rows,
               "two rods: live and run ended (%d, %d)", live_rc, run_rc))
        goto done;
    double t_live = -1.0, last[3 * 62];
    int numbers = 0;
    char held_rod[32] = "";
    for (char *line = strtok(ans, "\n"); line; line = strtok(NULL, "\n")) {
        if (strncmp(line, "forceps,", 8) != 0) continue;
        double v[5];
        char rod[32] = "";
        int at = 0;
        if (sscanf(line + 8, "%lf,%lf,%lf,%lf,%31[a-z]%n", &v[0], &v[1], &v[2], &v[3], rod, &at) ==
                5 && t_live < 0.0) {
            t_live = v[0];
            snprintf(held_rod, sizeof held_rod, "%s", rod);
        }
        const char *p = strstr(line, ",ok,");
        for (numbers = 0; p && *p && numbers < 3 * 62; numbers++) {
            p = strchr(p + 1, ',');
            if (!p) break;
            last[numbers] = strtod(p + 1, NULL);
        }
    }
    const char *on = strstr(summary, "\"t_on\":");
    const double t_run = on ? atof(on + 7) : -1.0;
    check(strcmp(held_rod, "upper") == 0 && fabs(t_live - t_run) < 1e-9,
          "two rods: the forceps take rod '%s' (upper) at t = %.6f s, run t_on = %.6f s",
          held_rod, t_live, t_run);
    /* the run's last frame: the upper rod's 41 rows, then the lower's 21 */
    int last_row = -1;
    for (const char *p = rows; (p = strchr(p, '\n')); p++) last_row++;
    const int ix = csv_column(rows, "x");
    double worst = 0.0;
    for (int b = 0; b < 62 && ix >= 0; b++)
        for (int c = 0; c < 3; c++) {
            char cell[64];
            if (csv_cell(rows, last_row - 61 + b, ix + c, cell, sizeof cell) == 0)
                worst = fmax(worst, fabs(atof(cell) - last[3 * b + c]));
        }
    check(numbers == 3 * 62 && worst < 1e-3 * DIAMETER,
          "two rods at t = 1.5 s: live and run %.3g m apart (%.2e d; at most 1e-3 d)", worst,
          worst / DIAMETER);
done:
    free(ans);
    free(summary);
    free(rows);
}

/* The forceps driven open straight down beside the thread's middle, into
 * the left pad (its top z = 0, grasp_lift.ini's [surface] of line 33) at
 * 1 cm in 0.6 s, then back up: while their tips stay above the top, the
 * jaws are at most their radius deep (under max_depth = 1 mm, set) and
 * every line is stepped; the first line taking them deeper is answered
 * failed with the depth, the surface's line and the key, not stepped, and
 * so is every line deeper; a line back above the pad is stepped again. As
 * `rodsim run` refuses such a path up front (sim/instrument_path.h). */
static void test_jaws_into_surface(void)
{
    char lines[128], answers[128], log[128], cmd[1024];
    snprintf(lines, sizeof lines, "%s/deep_lines.txt", dir);
    snprintf(answers, sizeof answers, "%s/deep_answers.csv", dir);
    snprintf(log, sizeof log, "%s/deep.log", dir);
    const char *rv = "1.2091996,1.2091996,-1.2091996";
    enum { DOWN = 120, UP = 10 };
    double tip_z[DOWN + UP];
    FILE *f = fopen(lines, "w");
    if (!f) return;
    for (int i = 0; i < DOWN + UP; i++) {
        const double t = 0.005 * (i + 1);
        tip_z[i] = i < DOWN ? 0.03 - 0.04 * t / 0.6 : 0.03;
        fprintf(f, "forceps:%.3f,0.05,0,%.6f,%s,1\n", t, tip_z[i], rv);
    }
    fclose(f);
    snprintf(cmd, sizeof cmd,
             "%s live scenes/grasp_lift.ini --set instrument.forceps.max_depth=0.001 < %s > %s "
             "2> %s", RODSIM_BIN, lines, answers, log);
    const int rc = system(cmd);
    char *ans = read_all(answers), *said = read_all(log);
    if (!check(rc == 0 && ans && said, "jaws into the pad: live ended (status %d)", rc)) goto done;
    int row = -1, above_failed = 0, first_refused = -1, deep_ok = 0, back_ok = 0;
    for (char *line = strtok(ans, "\n"); line; line = strtok(NULL, "\n")) {
        if (strncmp(line, "forceps,", 8) != 0) continue;
        row++;
        const int ok = strstr(line, ",ok") != NULL;
        if (row >= DOWN + UP) break;
        if (row >= DOWN) back_ok += ok;
        else if (tip_z[row] >= 0.0) above_failed += !ok;
        else if (!ok && first_refused < 0) first_refused = row;
        else if (ok && first_refused >= 0) deep_ok++;
    }
    const char *msg = strstr(said, "the forceps' jaws ");
    const double depth = msg ? atof(msg + strlen("the forceps' jaws ")) : 0.0;
    check(row + 1 == DOWN + UP && above_failed == 0 && first_refused > 0 && deep_ok == 0 &&
              back_ok == UP,
          "jaws into the pad: %d answers; lines with the tips above the top refused %d (want 0); "
          "the first refused at tip z = %.2f mm (below the top), none deeper stepped (%d), "
          "%d of %d back above stepped",
          row + 1, above_failed, first_refused >= 0 ? 1e3 * tip_z[first_refused] : 0.0, deep_ok,
          back_ok, UP);
    check(first_refused > 0 && tip_z[first_refused] < 0.0 && msg && depth > 1.0 &&
              strstr(msg, "[surface] of line 33") && strstr(msg, "max_depth = 1.00 mm") &&
              strstr(msg, "not stepped"),
          "jaws into the pad: the message gives the depth %.2f mm > max_depth 1 mm, the "
          "[surface]'s line and the key: '%.160s'",
          depth, msg ? msg : "");
    /* named rods (test_two_rods' scene, the same pad under the forceps): the
     * same lines refused */
    snprintf(cmd, sizeof cmd,
             "%s live %s/two.ini --set instrument.forceps.max_depth=0.001 < %s 2>/dev/null",
             RODSIM_BIN, dir, lines);
    FILE *p = popen(cmd, "r");
    char line[512];
    int named_row = -1, named_first = -1, named_refused = 0;
    while (p && fgets(line, sizeof line, p)) {
        if (strncmp(line, "forceps,", 8) != 0) continue;
        named_row++;
        if (strstr(line, ",failed")) {
            named_refused++;
            if (named_first < 0) named_first = named_row;
        }
    }
    const int named_rc = p ? pclose(p) : -1;
    int refused = 0;
    for (int i = first_refused; i >= 0 && i < DOWN; i++) refused++;
    check(named_rc == 0 && named_first == first_refused && named_refused == refused,
          "jaws into the pad, named rods: line %d first refused (one rod: %d), %d refused (%d)",
          named_first + 1, first_refused + 1, named_refused, refused);
done:
    free(ans);
    free(said);
}

int main(void)
{
    snprintf(dir, sizeof dir, "%s", test_dir());
    test_live_against_run();
    test_two_rods();
    test_jaws_into_surface();
    return test_finish();
}
