/* test_live_needle.c: `rodsim live` hands the needle between jaws as
 * `rodsim run` does ([needle_grasp], cli/live_needle.h).
 *
 * A 5 cm thread hanging from its clamped tip, the needle's back (a 5 mm
 * needle), carried by a needle holder (needle = yes) 1 mm along y over
 * 0.1 s (then it opens and backs away 3 cm up); the forceps' jaws still
 * 2 mm beyond it until they take the needle at T_GRASP = 0.1 s, then turning about the x axis through C = (0, 5 mm,
 * 0) by TURN = 4 rad (the needle's rotation passes pi) over 0.4 s, from
 * rest to rest (a = TURN (3 u^2 - 2 u^3)).
 * The live session: the holder's path as tip lines every 1 ms to T_GRASP,
 * then the forceps' path as lines `forceps: ...` every 1 ms to 0.5 s, each
 * the pose the scene's path gives at that t; against `rodsim run` of the
 * scene in steps of the same 1 ms:
 *   - the needle's back (the tip node) where run puts it at every 10 ms,
 *     before and after the grasp, within 1e-12 m (both are the paths'
 *     poses at the step's end: the same to rounding; a live session that
 *     does not hand the needle over leaves it where the last tip line left
 *     it, 7.8 mm off by 0.5 s); the whole thread within 1e-11 m (the
 *     answers' 12 digits are 5e-14 m here; at a Newton tolerance of 1e-12:
 *     at 1e-10 a step's iterates, the live session's Jacobian renewed
 *     between lines, leave the soft thread up to 2.8e-6 m apart);
 *   - the record replayed by `rodsim run` (--set ends.tip_motion=RECORD: the
 *     needle's path given whole, the instruments' paths the scene's): the
 *     thread where the session left it, within 1e-11 m;
 *   - the record's rows, the needle's path: continuous across T_GRASP (a
 *     step of at most what the jaws move in that 1 ms), their rotation
 *     vectors without a jump of 2 pi where the turn passes pi (consecutive
 *     rows within the jaws' largest turn in 1 ms, 1.5 TURN / 0.4 s), and
 *     after the grasp the needle still in the jaws' frame: R_f^T (p - g) and
 *     R_f^T R_n as at T_GRASP within 1e-12;
 *   - a tip line after the grasp (a pose 0.17 m off) is answered ok, the
 *     needle where the jaws, still, hold it (within 1e-12 m). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include "base/vec3.h"
#include "sim/instrument.h"
#include "sim/path.h"
#include "test.h"
#include "test_csv.h"

#define NODES 26
#define T_GRASP 0.1   /* s */
#define T_END 0.5     /* s */
#define T_TURN 0.4    /* s: the forceps' turn, from T_GRASP */
#define TURN 4.0      /* rad */
#define DIAMETER 0.0002 /* m */

static int write_file(const char *name, const char *text)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", test_dir(), name);
    FILE *f = fopen(path, "w");
    if (!f) return -1;
    fputs(text, f);
    return fclose(f);
}

/* The forceps' turn at t, rad */
static double turned(double t)
{
    const double u = fmin(fmax((t - T_GRASP) / T_TURN, 0.0), 1.0);
    return TURN * u * u * (3.0 - 2.0 * u);
}

#define LINES 500
static double jaws[LINES + 1][6]; /* the forceps' lines' poses: x,y,z,rx,ry,rz */

static int write_scene(void)
{
    /* the holder: 1 mm along y over 0.1 s, at rest at both ends */
    char holder[4096] = "t,x,y,z,rx,ry,rz,jaw\n";
    size_t used = strlen(holder);
    for (int k = 0; k <= 10; k++) {
        const double t = 0.01 * k, y = 0.001 * (3.0 * pow(t / T_GRASP, 2) - 2.0 * pow(t / T_GRASP, 3));
        used += (size_t)snprintf(holder + used, sizeof holder - used, "%.17g,0,%.17g,0,0,0,0,0\n",
                                 t, y);
    }
    /* then it opens and backs away 3 cm up, clear of the thread */
    snprintf(holder + used, sizeof holder - used,
             "0.12,0,0.001,0,0,0,0,1\n0.22,0,0.001,0.03,0,0,0,1\n1,0,0.001,0.03,0,0,0,1\n");
    /* the forceps: still at (0, 3 mm, 0), then about x through C */
    char forceps[16384] = "t,x,y,z,rx,ry,rz,jaw\n0,0,0.003,0,0,0,0,0\n";
    used = strlen(forceps);
    for (int k = 0; k <= 40; k++) {
        const double t = T_GRASP + 0.01 * k, a = turned(t);
        /* (0, 3 mm, 0) - C = (0, -2 mm, 0) turned by a about x */
        used += (size_t)snprintf(forceps + used, sizeof forceps - used,
                                 "%.17g,0,%.17g,%.17g,%.17g,0,0,0\n", t, 0.005 - 0.002 * cos(a),
                                 -0.002 * sin(a), a);
    }
    char scene[2048];
    snprintf(scene, sizeof scene,
             "[rod]\nlength = 0.05\ndiameter = %g\nnodes = %d\ndensity = 1140\n"
             "youngs_modulus = 1.5e9\nshear_modulus = 0.55e9\n"
             "origin = 0 0 0.05\ndirection = 0 0 -1\n"
             "[ends]\nroot = free\ntip = clamped\nneedle = 0.005\n"
             "[instrument]\nkind = needle_holder\nname = holder\npath = holder.csv\n"
             "needle = yes\nsize = 0.12\n"
             "[instrument]\nkind = forceps\nname = forceps\npath = forceps.csv\nsize = 0.12\n"
             "may_overlap = yes\n" /* its shank 3 mm beside the holder's: 0.35 mm into it */
             "[needle_grasp]\nt = %g\ninstrument = forceps\n"
             "[loads]\ngravity = 0 0 -9.81\n"
             "[solver]\nscheme = implicit\ndt = 0.001\nduration = %g\nnewton_tolerance = 1e-12\n"
             "[render]\nneedle_arc = 1/2\nfps = 100\n",
             DIAMETER, NODES, T_GRASP, T_END);
    return write_file("holder.csv", holder) || write_file("forceps.csv", forceps) ||
           write_file("needle.ini", scene);
}

/* The live lines: the holder's pose as tip lines to T_GRASP, then the
 * forceps' as their lines to T_END, every 1 ms */
static int write_lines(void)
{
    rod_instrument holder, forceps;
    memset(&holder, 0, sizeof holder);
    memset(&forceps, 0, sizeof forceps);
    char err[512];
    if (rod_instrument_load_path(test_path("holder.csv"), &holder.pose, &holder.jaw, err,
                                 sizeof err) ||
        rod_instrument_load_path(test_path("forceps.csv"), &forceps.pose, &forceps.jaw, err,
                                 sizeof err))
        return -1;
    FILE *f = fopen(test_path("lines.txt"), "w");
    for (int i = 1; f && i <= (int)lround(T_END * 1e3); i++) {
        const double t = 1e-3 * i;
        const int tip = t <= T_GRASP + 1e-12;
        rod_pose pose;
        double jaw, rv[3];
        rod_instrument_pose(tip ? &holder : &forceps, t, &pose, &jaw);
        m3_log(rv, pose.rotation);
        if (!tip) { /* the path's own rotation vector (a, 0, 0), a past pi */
            const double k = round((turned(t) - rv[0]) / (2.0 * M_PI));
            rv[0] += 2.0 * M_PI * k;
            memcpy(jaws[i], pose.position, 3 * sizeof(double));
            memcpy(&jaws[i][3], rv, 3 * sizeof(double));
        }
        fprintf(f, "%s%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g", tip ? "" : "forceps: ", t,
                pose.position[0], pose.position[1], pose.position[2], rv[0], rv[1], rv[2]);
        if (!tip) fprintf(f, ",%.17g", jaw);
        fputc('\n', f);
    }
    /* a tip line after the grasp: its pose (far off) not used */
    if (f) fprintf(f, "%.17g,0.1,0.1,0.1,0,0,0\n", T_END + 1e-3);
    rod_path_destroy(holder.pose);
    rod_path_destroy(holder.jaw);
    rod_path_destroy(forceps.pose);
    rod_path_destroy(forceps.jaw);
    return f ? fclose(f) : -1;
}

/* The run's node positions (t,node,s,x,y,z,...) at t; 0 when all found */
static int run_nodes(const char *rows, double t, double pos[NODES][3])
{
    int found = 0;
    for (const char *p = rows; p && *p; p = strchr(p, '\n') ? strchr(p, '\n') + 1 : NULL) {
        double time, x[3];
        int node;
        if (sscanf(p, "%lf,%d,%*f,%lf,%lf,%lf", &time, &node, &x[0], &x[1], &x[2]) != 5 ||
            fabs(time - t) > 1e-9 || node < 0 || node >= NODES)
            continue;
        memcpy(pos[node], x, sizeof x);
        found++;
    }
    return found == NODES ? 0 : -1;
}

static double live_pos[LINES + 2][NODES][3];
static int live_have[LINES + 2];

/* The answers' centrelines (tip lines: t,6 loads,status,xyz...; forceps
 * lines: forceps,t,fx,fy,fz,held,s,status,xyz...) by the line's ms */
static int read_answers(const char *text)
{
    int ok = 0;
    for (const char *p = text; p && *p; p = strchr(p, '\n') ? strchr(p, '\n') + 1 : NULL) {
        const int forceps = strncmp(p, "forceps,", 8) == 0;
        const char *q = forceps ? p + 8 : p;
        const int skip = forceps ? 6 : 7; /* numbers before the status */
        double t = strtod(q, NULL);
        const char *status = q;
        for (int c = 0; c < skip && status; c++) status = strchr(status, ',') ? strchr(status, ',') + 1 : NULL;
        if (!status || strncmp(status, "ok,", 3) != 0) continue;
        const long k = lround(t * 1e3);
        if (k < 1 || k > LINES + 1) continue;
        const char *n = status + 2;
        for (int i = 0; i < NODES; i++)
            for (int c = 0; c < 3; c++) live_pos[k][i][c] = strtod(n + 1, (char **)&n);
        live_have[k] = 1;
        ok++;
    }
    return ok;
}

/* The record's rows t,x,y,z,rx,ry,rz,v... by the line's ms */
static double rec_row[LINES + 1][7];
static int rec_have[LINES + 1];
static void read_record(const char *text)
{
    for (const char *p = text; p && *p; p = strchr(p, '\n') ? strchr(p, '\n') + 1 : NULL) {
        double r[7];
        if (*p == '#' ||
            sscanf(p, "%lf,%lf,%lf,%lf,%lf,%lf,%lf", &r[0], &r[1], &r[2], &r[3], &r[4], &r[5],
                   &r[6]) != 7)
            continue;
        const long k = lround(r[0] * 1e3);
        if (k < 0 || k > LINES) continue;
        memcpy(rec_row[k], r, sizeof r);
        rec_have[k] = 1;
    }
}

static void test_handover(void)
{
    if (!check(write_scene() == 0 && write_lines() == 0, "scene, paths and lines written")) return;
    char cmd[1024];
    const char *dir = test_dir();
    snprintf(cmd, sizeof cmd, "%s live %s/needle.ini --centreline --record %s/rec.csv < "
             "%s/lines.txt > %s/answers.csv 2> %s/live.log", RODSIM_BIN, dir, dir, dir, dir, dir);
    const int live_rc = system(cmd);
    snprintf(cmd, sizeof cmd, "%s run %s/needle.ini --no-video --quiet --csv %s/run.csv -o "
             "%s/out > %s/run.log 2>&1", RODSIM_BIN, dir, dir, dir, dir);
    const int run_rc = system(cmd);
    /* the record replayed: the needle's path from it (the holder's and the
     * forceps' paths the scene's, as the lines gave them) */
    snprintf(cmd, sizeof cmd, "%s run %s/needle.ini --set ends.tip_motion=%s/rec.csv --no-video "
             "--quiet --csv %s/replay.csv -o %s/out > %s/replay.log 2>&1", RODSIM_BIN, dir, dir,
             dir, dir, dir);
    const int replay_rc = system(cmd);
    check(live_rc == 0 && run_rc == 0 && replay_rc == 0, "live, run and the replay ended (%d, %d, "
          "%d)", live_rc, run_rc, replay_rc);
    char *answers = read_text(test_path("answers.csv")), *rows = read_text(test_path("run.csv")),
         *record = read_text(test_path("rec.csv")), *log = read_text(test_path("live.log")),
         *replayed = read_text(test_path("replay.csv"));
    if (!check(answers && rows && record && log && replayed, "answers, run CSV, record, "
               "messages and the replay's CSV read"))
        goto done;
    const int ok = read_answers(answers);
    check(ok == LINES + 1, "every line answered ok: %d of %d", ok, LINES + 1);
    double far[3];
    v3_sub(far, live_pos[LINES + 1][NODES - 1], live_pos[LINES][NODES - 1]);
    check(live_have[LINES + 1] && v3_norm(far) <= 1e-12, "a tip line after the grasp steps the "
          "time, the needle kept in the still jaws: moved %.3e m (its line asked 0.17 m)",
          v3_norm(far));
    check(strstr(log, "the needle in forceps's jaws from t = 0.1 s") != NULL,
          "the session says the handover");

    /* against run, every 10 ms */
    double tip_worst = 0.0, thread_worst = 0.0, thread_before = 0.0, tip_after = 0.0;
    double replay_worst = 0.0;
    int compared = 0;
    for (int k = 10; k <= LINES; k += 10) {
        static double run[NODES][3], replay[NODES][3];
        if (!live_have[k] || run_nodes(rows, k * 1e-3, run) ||
            run_nodes(replayed, k * 1e-3, replay))
            continue;
        compared++;
        for (int i = 0; i < NODES; i++)
            for (int c = 0; c < 3; c++)
                replay_worst = fmax(replay_worst, fabs(replay[i][c] - live_pos[k][i][c]));
        for (int i = 0; i < NODES; i++)
            for (int c = 0; c < 3; c++) {
                const double d = fabs(run[i][c] - live_pos[k][i][c]);
                if (k * 1e-3 <= T_GRASP + 1e-9) thread_before = fmax(thread_before, d);
                else thread_worst = fmax(thread_worst, d);
                if (i == NODES - 1) tip_worst = fmax(tip_worst, d);
            }
        if (k == LINES) tip_after = v3_norm(run[NODES - 1]);
    }
    check(compared == LINES / 10, "compared at %d times of %d", compared, LINES / 10);
    check(tip_worst <= 1e-12, "the needle's back where run puts it: within %.3e m (bound 1e-12; "
          "it moved to %.4f m from the origin)", tip_worst, tip_after);
    check(replay_worst <= 1e-11, "the record replayed by run: the thread where the session left "
          "it within %.3e m (bound 1e-11)", replay_worst);
    check(thread_before <= 1e-11 && thread_worst <= 1e-11, "the thread where run leaves it: "
          "within %.3e m before the grasp, %.3e m after it (bound 1e-11)", thread_before,
          thread_worst);

    /* the record: the needle's path */
    read_record(record);
    int rows_ok = 1;
    for (int k = 0; k <= LINES; k++) rows_ok &= rec_have[k];
    if (!check(rows_ok, "the record has the needle's row at every 1 ms")) goto done;
    const int g = (int)lround(T_GRASP * 1e3);
    const double still[6] = {0.0, 0.003, 0.0, 0.0, 0.0, 0.0}; /* the forceps until T_GRASP */
    memcpy(jaws[g], still, sizeof still);
    double jump[3];
    v3_sub(jump, &rec_row[g + 1][1], &rec_row[g][1]);
    double moved_jaws[3];
    v3_sub(moved_jaws, jaws[g + 1], jaws[g]);
    const double bound = (v3_norm(moved_jaws) + 0.002 * fabs(jaws[g + 1][3] - jaws[g][3])) * 1.01;
    check(v3_norm(jump) <= bound, "the needle's back continuous across t = %g s: %.3e m in the "
          "1 ms after (the jaws' turn then moves it %.3e m)", T_GRASP, v3_norm(jump), bound / 1.01);
    double turn_step = 0.0;
    for (int k = 1; k <= LINES; k++) {
        double d[3];
        v3_sub(d, &rec_row[k][4], &rec_row[k - 1][4]);
        turn_step = fmax(turn_step, v3_norm(d));
    }
    check(turn_step <= 1.5 * TURN / T_TURN * 1e-3 * 1.01, "the rotation vector continuous "
          "through pi: at most %.4f rad a row (the jaws' fastest %.4f)", turn_step,
          1.5 * TURN / T_TURN * 1e-3);
    check(fabs(rec_row[LINES][4] - TURN) < 1e-9 && fabs(rec_row[LINES][5]) < 1e-12 &&
              fabs(rec_row[LINES][6]) < 1e-12,
          "the needle turned with the jaws: (%.9f, %.1e, %.1e) rad at %g s (%.9f, 0, 0)",
          rec_row[LINES][4], rec_row[LINES][5], rec_row[LINES][6], T_END, TURN);
    /* in the jaws' frame (the forceps' lines' poses) */
    double local0[3] = {0}, rot0[9] = {0}, moved = 0.0, turned = 0.0;
    for (int k = g; k <= LINES; k++) {
        const double *gpos = jaws[k], *rv = &jaws[k][3];
        double rf[9], rn[9], d[3], local[3], rot[9];
        m3_exp(rf, rv);
        m3_exp(rn, &rec_row[k][4]);
        v3_sub(d, &rec_row[k][1], gpos);
        m3_mul_tv(local, rf, d);
        m3_mul_tn(rot, rf, rn);
        if (k == g) {
            memcpy(local0, local, sizeof local);
            memcpy(rot0, rot, sizeof rot);
        }
        double dl[3];
        v3_sub(dl, local, local0);
        moved = fmax(moved, v3_norm(dl));
        for (int c = 0; c < 9; c++) turned = fmax(turned, fabs(rot[c] - rot0[c]));
    }
    check(moved <= 1e-12 && turned <= 1e-12, "after the grasp the needle keeps its place in the "
          "jaws: moved %.3e m, turned %.3e (bound 1e-12)", moved, turned);
done:
    free(answers);
    free(rows);
    free(record);
    free(log);
    free(replayed);
}

int main(void)
{
    test_handover();
    return test_finish();
}
