/* test_rodsim_api.c: the library (rodsim.h) against `rodsim run` and against
 * independent values: the same scene stepped by the CLI and by the API
 * gives the same numbers bit for bit (the CLI's own loop in process, and its
 * CSV's text); a save and its restore step identically; a bad scene gets the
 * CLI's message; overrides apply; a thread hanging from a driven needle
 * pulls on it with its weight, rho A L g; a scene of two named rods, each
 * hanging from its own driven tip, pulls on each with that rod's weight. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "api/scene_read.h"
#include "base/dtoa.h"
#include "cli/run.h"
#include "rodsim.h"
#include "sim/rod.h"
#include "test.h"
#include "test_hanging_rods.h"
#include "test_process.h"

#define SCENE(name) RODSIM_SOURCE_DIR "/scenes/" name
#define MAX_FRAMES 16
#define MAX_NODES 64

/* The CLI's loop (run_simulate), in process: each frame's positions,
 * frames and internal forces. */
typedef struct frames {
    int count, nodes;
    double time[MAX_FRAMES];
    double position[MAX_FRAMES][MAX_NODES * 3];
    double frame[MAX_FRAMES][MAX_NODES * 9];
    double force[MAX_FRAMES][MAX_NODES * 3];
} frames;

static int keep_frame(void *context, const rod_model *m, const rod_state *s, char *err,
                      size_t errlen)
{
    (void)m, (void)err, (void)errlen;
    frames *f = context;
    if (f->count >= MAX_FRAMES) return 0;
    f->time[f->count] = s->time;
    memcpy(f->position[f->count], s->position, (size_t)s->nodes * 3 * sizeof(double));
    memcpy(f->frame[f->count], s->frame, (size_t)s->nodes * 9 * sizeof(double));
    rod_internal_force(s, f->force[f->count]);
    f->count++;
    return 0;
}

static const char *const impulse_sets[] = {"solver.duration=0.2"};

/* The CLI's loop on impulse.ini (0.2 s: 6 frames of 1/30 s, 67 steps of
 * 1/2010 s each); 0 when it ran. */
static int cli_loop(frames *f)
{
    char err[1024] = "";
    ini_doc *doc = ini_load(SCENE("impulse.ini"), err, sizeof err);
    rod_model m = rod_model_default();
    run_output out;
    int ok = doc && ini_set(doc, impulse_sets[0], err, sizeof err) == 0 &&
             run_read_scene(doc, &m, &out, err, sizeof err) == 0;
    ini_destroy(doc);
    if (!ok) return check(0, "impulse.ini read: %s", err), -1;
    rod_solver solver = {0};
    rod_state *s = rod_state_create(&m);
    run_plan plan;
    rod_report report;
    run_stats stats;
    double dt = rod_choose_dt(&m, NULL);
    ok = s && rod_solver_init(&solver, &m, err, sizeof err) == 0 &&
         run_plan_make(&m, dt, out.fps, &plan) == 0;
    f->nodes = m.nodes;
    if (ok) {
        rod_state_reset(&m, s);
        ok = run_simulate(&solver, &m, s, &plan, out.fps, keep_frame, f, &report, &stats) ==
             ROD_OK;
    }
    rod_solver_release(&solver);
    rod_state_destroy(s);
    rod_model_release(&m);
    return ok ? 0 : -1;
}

/* The API and the CLI's loop agree bit for bit at every output frame; and
 * the API's state printed as the CSV is the CLI's --csv text. */
static void test_same_as_cli(void)
{
    static frames cli;
    if (cli_loop(&cli)) return;
    rodsim_scene *sc = NULL;
    if (!check(rodsim_load_file(SCENE("impulse.ini"), impulse_sets, 1, &sc) == RODSIM_OK,
               "impulse.ini loads: %s", rodsim_last_error(NULL)))
        return;
    const int n = rodsim_nodes(sc);
    double *pos = malloc(sizeof(double) * 3 * (size_t)n);
    double *dir = malloc(sizeof(double) * 9 * (size_t)n);
    double *force = malloc(sizeof(double) * 3 * (size_t)n);
    int same = 1, frames_seen = 0;
    double worst = 0.0;
    char csv[] = "/tmp/rodsim_api_csvXXXXXX";
    int fd = mkstemp(csv);
    FILE *api_csv = fd >= 0 ? fdopen(fd, "w") : NULL;
    if (api_csv) fprintf(api_csv, "t,node,s,x,y,z,d3x,d3y,d3z,twist,nx,ny,nz\n");
    for (int k = 0; k < cli.count; k++) {
        if (k > 0 && rodsim_run(sc, (double)k / rodsim_frame_rate(sc)) != RODSIM_OK) break;
        rodsim_get(sc, RODSIM_POSITIONS, pos, 3 * (size_t)n);
        rodsim_get(sc, RODSIM_DIRECTORS, dir, 9 * (size_t)n);
        rodsim_get(sc, RODSIM_FORCES, force, 3 * (size_t)n);
        for (int i = 0; i < n; i++)
            for (int a = 0; a < 3; a++) {
                double d = fabs(pos[3 * i + a] - cli.position[k][3 * i + a]);
                worst = fmax(worst, d);
                same &= pos[3 * i + a] == cli.position[k][3 * i + a];
                same &= force[3 * i + a] == cli.force[k][3 * i + a];
                for (int b = 0; b < 3; b++) /* directors' rows are Q's columns */
                    same &= dir[9 * i + 3 * a + b] == cli.frame[k][9 * i + 3 * b + a];
            }
        same &= rodsim_time(sc) == cli.time[k];
        frames_seen++;
        /* the CSV's row, as run_csv_frame prints it */
        for (int i = 0; api_csv && i < n; i++) {
            const double field[12] = {rodsim_time(sc), (double)i * (rodsim_length(sc) / (n - 1)),
                                      pos[3 * i], pos[3 * i + 1], pos[3 * i + 2], dir[9 * i + 6],
                                      dir[9 * i + 7], dir[9 * i + 8], 0.0, force[3 * i] + 0.0,
                                      force[3 * i + 1] + 0.0, force[3 * i + 2] + 0.0};
            char line[13 * DTOA_MAX];
            char *p = line + dtoa_shortest(line, field[0]);
            p += snprintf(p, 16, ",%d", i);
            for (int c = 1; c < 12; c++) {
                *p++ = ',';
                p += dtoa_shortest(p, field[c]);
            }
            *p++ = '\n';
            fwrite(line, 1, (size_t)(p - line), api_csv);
        }
    }
    check(same && frames_seen == cli.count && cli.count == 7,
          "impulse.ini to 0.2 s: the API's positions, directors, internal forces and times at "
          "the %d output frames are the CLI loop's bit for bit (largest position difference "
          "%.3g m, reference 0)", frames_seen, worst);
    if (api_csv) fclose(api_csv);
    /* the CLI's --csv text, the twist column set aside (the API has none) */
    char cli_csv[] = "/tmp/rodsim_cli_csvXXXXXX";
    int cfd = mkstemp(cli_csv);
    if (cfd >= 0) close(cfd);
    char output[8192];
    const char *args[] = {"run", SCENE("impulse.ini"), "--set", impulse_sets[0], "--no-video",
                          "--quiet", "--csv", cli_csv, NULL};
    int status = test_run_rodsim(args, output, sizeof output);
    FILE *a = fopen(csv, "r"), *b = fopen(cli_csv, "r");
    long rows = 0, differ = 0;
    char la[512], lb[512];
    while (a && b && fgets(la, sizeof la, a) && fgets(lb, sizeof lb, b)) {
        /* blank the twist (field 10) in both */
        char *fa[16], *fb[16];
        int na = 0, nb = 0;
        for (char *t = strtok(la, ","); t && na < 16; t = strtok(NULL, ",")) fa[na++] = t;
        for (char *t = strtok(lb, ","); t && nb < 16; t = strtok(NULL, ",")) fb[nb++] = t;
        int row_same = na == nb && na == 13;
        for (int k = 0; row_same && k < na; k++)
            if (k != 9) row_same &= strcmp(fa[k], fb[k]) == 0;
        if (!row_same && differ == 0)
            printf("     first differing row %ld: field %s vs %s\n", rows, fa[0], fb[0]);
        for (int k = 0; !row_same && differ == 0 && k < na && k < nb; k++)
            if (k != 9 && strcmp(fa[k], fb[k]) != 0) printf("     field %d: API %s, CLI %s\n", k, fa[k], fb[k]);
        differ += !row_same;
        rows++;
    }
    if (a) fclose(a);
    if (b) fclose(b);
    check(status == 0 && rows == 1 + 7 * 51 && differ == 0,
          "rodsim run --csv and the API's state printed alike: %ld rows, %ld differ (exit %d)",
          rows, differ, status);
    unlink(csv);
    unlink(cli_csv);
    /* a second scene object steps the same: no state shared between handles */
    rodsim_scene *again = NULL;
    rodsim_load_file(SCENE("impulse.ini"), impulse_sets, 1, &again);
    int run_ok = again && rodsim_run(again, -1.0) == RODSIM_OK;
    check(run_ok && memcmp(rodsim_view(again, RODSIM_POSITIONS), cli.position[cli.count - 1],
                           sizeof(double) * 3 * (size_t)n) == 0 &&
              rodsim_time(again) == cli.time[cli.count - 1],
          "rodsim_run(-1) runs to solver.duration = %g s in one call: the CLI's last frame bit "
          "for bit", again ? rodsim_duration(again) : 0.0);
    rodsim_free(again);
    free(pos);
    free(dir);
    free(force);
    rodsim_free(sc);
}

/* A thread hanging from a clamped, driven needle: the tip moved along a
 * path from Python's side (set_end_pose at every step), a save half way;
 * the restore steps the same bit for bit; at rest the needle holds the
 * thread's weight, rho A L g downward. */
static const char hanging[] =
    "[rod]\nlength = 0.3\ndiameter = 0.0005\ndensity = 850\nyoungs_modulus = 87.5e6\n"
    "shear_modulus = 31.25e6\nnodes = 31\norigin = 0 0 0\ndirection = 0 0 1\n"
    "[ends]\nroot = free\ntip = clamped\n"
    "[solver]\nscheme = implicit\ndt = 0.002\nduration = 6\n"
    "[loads]\ngravity = 0 0 -9.81\nlinear_damping = 2e-3\n"
    "[render]\nfps = 30\n";

static void drive(rodsim_scene *sc, double from, double to, double h)
{
    for (double t = from; t < to - 1e-12; t += h) {
        double p[3] = {0.05 * sin(2.0 * (t + h)), 0.0, 0.3 + 0.02 * (t + h)}, r[3] = {0, 0, 0};
        if (t + h > 3.0) p[0] = 0.05 * sin(6.0), p[2] = 0.36;
        if (rodsim_set_end_pose(sc, RODSIM_TIP, p, r) || rodsim_step(sc, h)) return;
    }
}

static void test_save_restore_and_weight(void)
{
    rodsim_scene *sc = NULL;
    if (!check(rodsim_load_text("hanging", hanging, NULL, 0, &sc) == RODSIM_OK,
               "the hanging thread loads: %s", rodsim_last_error(NULL)))
        return;
    const int n = rodsim_nodes(sc);
    const double h = 0.01;
    drive(sc, 0.0, 1.0, h);
    size_t size = rodsim_state_size(sc);
    void *blob = malloc(size);
    check(rodsim_save(sc, blob, size) == RODSIM_OK, "save at t = %g s: %zu bytes",
          rodsim_time(sc), size);
    const double saved_t = rodsim_time(sc);
    drive(sc, saved_t, 2.0, h);
    double *first = malloc(sizeof(double) * 9 * (size_t)n);
    double *second = malloc(sizeof(double) * 9 * (size_t)n);
    double f1[3], f2[3], m1[3], m2[3];
    rodsim_get(sc, RODSIM_DIRECTORS, first, 9 * (size_t)n);
    rodsim_end_load(sc, RODSIM_TIP, f1, m1);
    double p1[3 * 64];
    memcpy(p1, rodsim_view(sc, RODSIM_POSITIONS), sizeof(double) * 3 * (size_t)n);
    const double t1 = rodsim_time(sc);
    check(rodsim_restore(sc, blob, size) == RODSIM_OK && rodsim_time(sc) == saved_t,
          "restore: back at t = %g s", saved_t);
    drive(sc, saved_t, 2.0, h);
    rodsim_get(sc, RODSIM_DIRECTORS, second, 9 * (size_t)n);
    rodsim_end_load(sc, RODSIM_TIP, f2, m2);
    int same = memcmp(first, second, sizeof(double) * 9 * (size_t)n) == 0 &&
               memcmp(p1, rodsim_view(sc, RODSIM_POSITIONS), sizeof(double) * 3 * (size_t)n) == 0 &&
               memcmp(f1, f2, sizeof f1) == 0 && memcmp(m1, m2, sizeof m1) == 0 &&
               t1 == rodsim_time(sc);
    check(same, "driven from t = %g to %g s twice, from the save and from its restore: positions, "
                "directors, the tip's force and moment bit for bit (tip force %.9g %.9g %.9g N)",
          saved_t, t1, f1[0], f1[1], f1[2]);
    /* a blob of another scene is refused */
    rodsim_scene *other = NULL;
    const char *const sets[] = {"rod.nodes=21"};
    rodsim_load_text("hanging", hanging, sets, 1, &other);
    check(other && rodsim_restore(other, blob, size) == RODSIM_BAD_INPUT &&
              strstr(rodsim_last_error(other), "not"),
          "a blob restored into a scene of 21 nodes is refused: %s",
          other ? rodsim_last_error(other) : "(no scene)");
    rodsim_free(other);
    /* a state saved before the tip was driven: after driving, its restore
     * holds the tip as the scene does again, and steps as after the save */
    rodsim_scene *fresh = NULL;
    rodsim_load_text("hanging", hanging, NULL, 0, &fresh);
    void *early = fresh ? malloc(size) : NULL;
    int early_same = 0;
    if (early && rodsim_step(fresh, 0.1) == RODSIM_OK &&
        rodsim_save(fresh, early, size) == RODSIM_OK && rodsim_step(fresh, 0.2) == RODSIM_OK) {
        memcpy(p1, rodsim_view(fresh, RODSIM_POSITIONS), sizeof(double) * 3 * (size_t)n);
        drive(fresh, 0.3, 0.6, h);
        early_same = rodsim_restore(fresh, early, size) == RODSIM_OK &&
                     rodsim_step(fresh, 0.2) == RODSIM_OK &&
                     memcmp(p1, rodsim_view(fresh, RODSIM_POSITIONS),
                            sizeof(double) * 3 * (size_t)n) == 0;
    }
    check(early_same, "a state saved before the tip was driven, restored after driving it: "
                      "the tip held again, the next 0.2 s bit for bit as after the save");
    free(early);
    rodsim_free(fresh);
    /* at rest under gravity the needle holds the thread's weight */
    drive(sc, rodsim_time(sc), 6.0, 0.05);
    rodsim_end_load(sc, RODSIM_TIP, f1, m1);
    const double weight = 850 * M_PI * 0.0005 * 0.0005 / 4 * 0.3 * 9.81; /* rho A L g, N */
    check_rel("the thread's pull on the needle at rest (-fz), N: rho A L g", -f1[2], weight, 1e-3);
    check_abs("its horizontal pull, N", hypot(f1[0], f1[1]), 0.0, 1e-3 * weight);
    free(blob);
    free(first);
    free(second);
    rodsim_free(sc);
}

/* A bad scene gets `rodsim run`'s message; so does a bad override. */
static void test_bad_scene(void)
{
    char path[] = "/tmp/rodsim_api_badXXXXXX.ini";
    int fd = mkstemps(path, 4);
    FILE *f = fd >= 0 ? fdopen(fd, "w") : NULL;
    if (!f) return;
    fprintf(f, "%s", hanging);
    fprintf(f, "[tip]\nfroce = 1 0 0\n");
    fclose(f);
    char output[4096], expected[2048];
    const char *args[] = {"run", path, "--no-video", NULL};
    int status = test_run_rodsim(args, output, sizeof output);
    rodsim_scene *sc = NULL;
    rodsim_status st = rodsim_load_file(path, NULL, 0, &sc);
    snprintf(expected, sizeof expected, "rodsim run: %s\n", rodsim_last_error(NULL));
    check(status == 2 && st == RODSIM_BAD_INPUT && !sc && strcmp(output, expected) == 0 &&
              strstr(output, "froce"),
          "a misspelt key: the CLI prints (exit %d) %sthe API says (status %d) the same after "
          "\"rodsim run: \"", status, output, (int)st);
    const char *sets[] = {"solver.dt=-1"};
    const char *args2[] = {"run", path, "--no-video", "--set", sets[0], NULL};
    unlink(path);
    f = fopen(path, "w");
    fprintf(f, "%s", hanging);
    fclose(f);
    status = test_run_rodsim(args2, output, sizeof output);
    st = rodsim_load_file(path, sets, 1, &sc);
    snprintf(expected, sizeof expected, "rodsim run: %s\n", rodsim_last_error(NULL));
    check(status == 2 && st == RODSIM_BAD_INPUT && strcmp(output, expected) == 0,
          "a bad override: the CLI prints (exit %d) %sthe API the same", status, output);
    /* several rods: a misspelt key of a named rod */
    unlink(path);
    f = fopen(path, "w");
    fprintf(f, "%s[tip long]\nfroce = 1 0 0\n", HANGING_RODS_SCENE);
    fclose(f);
    status = test_run_rodsim(args, output, sizeof output);
    st = rodsim_load_file(path, NULL, 0, &sc);
    snprintf(expected, sizeof expected, "rodsim run: %s\n", rodsim_last_error(NULL));
    check(status == 2 && st == RODSIM_BAD_INPUT && !sc && strcmp(output, expected) == 0 &&
              strstr(output, "froce"),
          "several rods, a misspelt key: the CLI prints (exit %d) %sthe API the same", status,
          output);
    unlink(path);
    st = rodsim_load_file("/nonexistent/scene.ini", NULL, 0, &sc);
    check(st == RODSIM_BAD_INPUT && strstr(rodsim_last_error(NULL), "/nonexistent/scene.ini"),
          "a missing file: %s", rodsim_last_error(NULL));
}

/* Overrides apply in order; the version; the fields' sizes; errors of use. */
static void test_overrides_and_use(void)
{
    const char *const sets[] = {"solver.dt=0.004", "rod.nodes=11", "solver.dt=0.003"};
    rodsim_scene *sc = NULL;
    if (!check(rodsim_load_text("hanging", hanging, sets, 3, &sc) == RODSIM_OK, "loads"))
        return;
    check(rodsim_dt(sc) == 0.003 && rodsim_nodes(sc) == 11 &&
              rodsim_field_size(sc, RODSIM_DIRECTORS) == 99,
          "overrides in order: solver.dt = %g s (0.003: the last wins), rod.nodes = %d (11), "
          "directors %zu doubles (99)", rodsim_dt(sc), rodsim_nodes(sc),
          rodsim_field_size(sc, RODSIM_DIRECTORS));
    check(rodsim_api_version() == RODSIM_API_VERSION && RODSIM_API_VERSION_MAJOR == 1,
          "rodsim_api_version() = %d, the header's %d", rodsim_api_version(), RODSIM_API_VERSION);
    /* one step of 0.01 s is ceil(0.01 / 0.003) = 4 steps; the time lands on it */
    check(rodsim_step(sc, 0.01) == RODSIM_OK && rodsim_time(sc) == 0.01,
          "rodsim_step(0.01) from t = 0: t = 0.01 s exactly");
    double small[3];
    check(rodsim_get(sc, RODSIM_POSITIONS, small, 3) == RODSIM_BAD_INPUT &&
              strstr(rodsim_last_error(sc), "33"),
          "a buffer too small is refused: %s", rodsim_last_error(sc));
    double f[3] = {1, 0, 0};
    check(rodsim_set_tip_load(sc, f, NULL) == RODSIM_BAD_INPUT &&
              rodsim_set_end_pose(sc, RODSIM_ROOT, f, NULL) == RODSIM_BAD_INPUT,
          "loads on a held tip, a pose for a free root: refused (%s)", rodsim_last_error(sc));
    char knot[96];
    check(rodsim_knot_type(sc, knot, sizeof knot) == RODSIM_OK && strcmp(knot, "unknot") == 0,
          "a hanging thread's knot type: %s", knot);
    rodsim_free(sc);
    rodsim_free(NULL);
}

/* A step that diverges: the status and `rodsim run`'s words for it; the
 * state stays the one before the call, frames and all. */
static void test_divergence(void)
{
    const char *const sets[] = {"solver.scheme=thesis", "solver.dt=0.01"};
    rodsim_scene *sc = NULL;
    if (rodsim_load_file(SCENE("impulse.ini"), sets, 2, &sc)) return;
    double before[3 * 51];
    rodsim_get(sc, RODSIM_POSITIONS, before, 3 * 51);
    rodsim_status st = rodsim_run(sc, 1.0);
    check(st == RODSIM_UNSTABLE && strstr(rodsim_last_error(sc), "the thesis scheme stopped: the "
                                                                 "run became unstable at t =") &&
              rodsim_time(sc) == 0.0 &&
              memcmp(before, rodsim_view(sc, RODSIM_POSITIONS), sizeof before) == 0,
          "the thesis scheme at dt = 0.01 s: status %d (unstable, 2), the state back at t = %g s; "
          "%s", (int)st, rodsim_time(sc), rodsim_last_error(sc));
    rodsim_free(sc);
}

/* A free tip loaded from the API as the scene would load it: a dead load
 * of 1 mN along z set at t = 0 gives the same state as tip.force. */
static void test_tip_load(void)
{
    const char *const scene_sets[] = {"tip.frame=global", "tip.force=0 0 1e-3",
                                      "tip.moment=0 0 0", "tip.profile=step",
                                      "solver.duration=0.1"};
    const char *const api_sets[] = {"tip.frame=global", "solver.duration=0.1"};
    rodsim_scene *a = NULL, *b = NULL;
    rodsim_load_file(SCENE("suture_cantilever.ini"), scene_sets, 5, &a);
    rodsim_load_file(SCENE("suture_cantilever.ini"), api_sets, 2, &b);
    const double f[3] = {0, 0, 1e-3};
    int ok = a && b && rodsim_set_tip_load(b, f, NULL) == RODSIM_OK &&
             rodsim_run(a, -1) == RODSIM_OK && rodsim_run(b, -1) == RODSIM_OK;
    const double *pa = ok ? rodsim_view(a, RODSIM_POSITIONS) : NULL;
    const double *pb = ok ? rodsim_view(b, RODSIM_POSITIONS) : NULL;
    int n = ok ? rodsim_nodes(a) : 0;
    check(ok && memcmp(pa, pb, sizeof(double) * 3 * (size_t)n) == 0,
          "tip.force = 0 0 1e-3 (step, global) and rodsim_set_tip_load(0 0 1e-3) at t = 0: the "
          "same tip at t = 0.1 s bit for bit (z = %.9g m)", ok ? pa[3 * n - 1] : 0.0);
    rodsim_free(a);
    rodsim_free(b);
}

/* Distinct handles in distinct threads: each thread's run is the one a
 * single thread makes, bit for bit; a failed load's message is the
 * thread's own. */
typedef struct thread_run {
    double tip[3];
    const char *sets[2];
    int ok;
    char error[256];
} thread_run;

static void *run_in_thread(void *arg)
{
    thread_run *r = arg;
    rodsim_scene *sc = NULL;
    r->ok = rodsim_load_file(SCENE("impulse.ini"), r->sets, 2, &sc) == RODSIM_OK &&
            rodsim_run(sc, -1.0) == RODSIM_OK;
    if (r->ok) memcpy(r->tip, rodsim_view(sc, RODSIM_POSITIONS) + 3 * 50, sizeof r->tip);
    const char *const bad[] = {"rod.nodes=1"};
    rodsim_scene *none = NULL;
    rodsim_load_file(SCENE("impulse.ini"), bad, 1, &none);
    snprintf(r->error, sizeof r->error, "%s", rodsim_last_error(NULL));
    rodsim_free(sc);
    return NULL;
}

static void test_threads(void)
{
    thread_run runs[3] = {{.sets = {"solver.duration=0.1", "tip.force=1e-3 0 0"}},
                          {.sets = {"solver.duration=0.1", "tip.force=2e-3 0 0"}},
                          {.sets = {"solver.duration=0.1", "tip.force=1e-3 0 0"}}};
    pthread_t threads[2];
    int started = 0;
    for (int k = 0; k < 2; k++)
        started += pthread_create(&threads[k], NULL, run_in_thread, &runs[k]) == 0;
    for (int k = 0; k < started; k++) pthread_join(threads[k], NULL);
    run_in_thread(&runs[2]); /* the first thread's scene, alone */
    check(started == 2 && runs[0].ok && runs[1].ok && runs[2].ok &&
              memcmp(runs[0].tip, runs[2].tip, sizeof runs[0].tip) == 0 &&
              runs[0].tip[1] != runs[1].tip[1] && strstr(runs[0].error, "nodes"),
          "two scenes stepped in two threads at once: the first's tip (%.9g, %.9g) m is the "
          "one it reaches alone, bit for bit; each thread keeps its own message (%s)",
          runs[0].tip[0], runs[0].tip[1], runs[0].error);
}

/* make install (release flavour): the library, its soname links, the header
 * and rodsim.pc under DESTDIR; a C client built by pkg-config against them
 * runs a scene through the installed librodsim.so.1. */
static void test_install(void)
{
    const char *flavour = getenv("RODSIM_TEST_FLAVOUR");
    if (flavour && strcmp(flavour, "release") != 0) return; /* one install is enough */
    char dir[] = "/tmp/rodsim_api_installXXXXXX";
    if (!mkdtemp(dir)) return;
    char cmd[4096], app[600];
    snprintf(cmd, sizeof cmd, "make -s --no-print-directory -C '%s' install PREFIX=/usr/local "
             "DESTDIR='%s' >'%s/log' 2>&1", RODSIM_SOURCE_DIR, dir, dir);
    int made = system(cmd) == 0;
    const char *files[] = {"lib/librodsim.so.1", "lib/librodsim.so", "include/rodsim.h",
                           "lib/pkgconfig/rodsim.pc"};
    int present = 0;
    for (int k = 0; k < 4; k++) {
        char path[700];
        snprintf(path, sizeof path, "%s/usr/local/%s", dir, files[k]);
        present += access(path, R_OK) == 0;
    }
    check(made && present == 4, "make install DESTDIR: lib/librodsim.so.1 and .so, "
                                "include/rodsim.h, lib/pkgconfig/rodsim.pc (%d of 4)", present);
    snprintf(app, sizeof app, "%s/app.c", dir);
    FILE *f = fopen(app, "w");
    if (!f) return;
    fprintf(f, "#include <stdio.h>\n#include <rodsim.h>\nint main(int c, char **v)\n{\n"
               "    rodsim_scene *s;\n    if (c < 2 || rodsim_load_file(v[1], 0, 0, &s)) "
               "return 2;\n    int ok = rodsim_run(s, 0.1) == RODSIM_OK;\n"
               "    printf(\"%%d %%.17g\\n\", rodsim_api_version(), rodsim_time(s));\n"
               "    rodsim_free(s);\n    return ok ? 0 : 1;\n}\n");
    fclose(f);
    snprintf(cmd, sizeof cmd,
             "cd '%s' && export PKG_CONFIG_SYSROOT_DIR='%s' "
             "PKG_CONFIG_PATH='%s/usr/local/lib/pkgconfig' && cc -o app app.c "
             "$(pkg-config --cflags --libs rodsim) >>log 2>&1 && "
             "LD_LIBRARY_PATH='%s/usr/local/lib' ./app '%s' >out 2>>log",
             dir, dir, dir, dir, SCENE("impulse.ini"));
    int ran = system(cmd) == 0;
    char out[128] = "";
    snprintf(app, sizeof app, "%s/out", dir);
    f = fopen(app, "r");
    if (f) {
        if (!fgets(out, sizeof out, f)) out[0] = '\0';
        fclose(f);
    }
    char expect[64];
    snprintf(expect, sizeof expect, "%d 0.10000000000000001\n", RODSIM_API_VERSION);
    check(ran && strcmp(out, expect) == 0,
          "a C client built with pkg-config --cflags --libs rodsim runs impulse.ini to 0.1 s "
          "on the installed library: %s", out[0] ? out : "(no output)\n");
    test_remove_tree(dir);
}

/* Two named rods hanging from pinned tips (test_hanging_rods.h): the list
 * of rods, each driven by rodsim_set_end_pose_rod to a pose of its own and
 * held; at rest each tip carries its own rod's weight rho A g L, the tip
 * node is where it was driven and the root hangs L below it (the stretch
 * w / (2 EA) = 3e-7 m at most); the calls without a rod read rod 0; a bad
 * rod and the calls for one rod only are refused, naming what is accepted. */
static void test_several_rods(void)
{
    rodsim_scene *sc = NULL;
    if (!check(rodsim_load_text("hanging_rods", HANGING_RODS_SCENE, NULL, 0, &sc) == RODSIM_OK,
               "two hanging rods load%s%s", sc ? "" : ": ", sc ? "" : rodsim_last_error(NULL)))
        return;
    check(rodsim_rod_count(sc) == 2 && strcmp(rodsim_rod_name(sc, 0), "short") == 0 &&
              strcmp(rodsim_rod_name(sc, 1), "long") == 0 && rodsim_rod_name(sc, 2) == NULL,
          "rods: %d (2), named %s, %s", rodsim_rod_count(sc), rodsim_rod_name(sc, 0),
          rodsim_rod_name(sc, 1));
    check(rodsim_rod_index(sc, "long") == 1 && rodsim_rod_nodes(sc, 1) == 26 &&
              rodsim_rod_nodes(sc, 0) == 16 && rodsim_nodes(sc) == 16,
          "rod 'long' is index %d (1) of 26 nodes (%d); rod 0 and rodsim_nodes: 16 (%d, %d)",
          rodsim_rod_index(sc, "long"), rodsim_rod_nodes(sc, 1), rodsim_rod_nodes(sc, 0),
          rodsim_nodes(sc));
    check(rodsim_rod_index(sc, "middle") == -1 &&
              strstr(rodsim_last_error(sc), "no rod named 'middle'") &&
              strstr(rodsim_last_error(sc), "its rods: short, long"),
          "an unknown rod name: -1, %s", rodsim_last_error(sc));
    const double length[2] = {0.3, 0.5};
    const double goal[2][3] = {{0.01, 0.0, 0.02}, {0.2, -0.015, 0.01}}; /* m, the tips' poses */
    /* 0.2 s to the goal in steps of 10 ms (straight, in ramps), then held
     * 4.8 s: the swing (2 pi sqrt(L / g) = 1.1 s at most) near critically
     * damped, 1e-8 of it left */
    int ok = 1;
    for (int i = 1; ok && i <= 500; i++) {
        const double f = i >= 20 ? 1.0 : i / 20.0;
        for (int k = 0; k < 2 && ok; k++) {
            const double start[3] = {k ? 0.2 : 0.0, 0.0, 0.0};
            double p[3];
            for (int a = 0; a < 3; a++) p[a] = start[a] + f * (goal[k][a] - start[a]);
            ok = rodsim_set_end_pose_rod(sc, k, RODSIM_TIP, p, NULL) == RODSIM_OK;
        }
        ok = ok && rodsim_step(sc, 0.01) == RODSIM_OK;
    }
    check(ok, "both tips driven for 5 s: t = %g s%s%s", rodsim_time(sc), ok ? "" : ": ",
          ok ? "" : rodsim_last_error(sc));
    for (int k = 0; k < 2; k++) {
        double f[3], m[3], x[26 * 3];
        const int n = rodsim_rod_nodes(sc, k);
        rodsim_end_load_rod(sc, k, RODSIM_TIP, f, m);
        rodsim_get_rod(sc, k, RODSIM_POSITIONS, x, sizeof x / sizeof x[0]);
        const double weight = hanging_rod_weight(length[k], 1000.0);
        printf("rod %s: tip force %.12g %.12g %.12g N, weight %.12g N\n", rodsim_rod_name(sc, k),
               f[0], f[1], f[2], weight);
        check_rel("the rod's pull on its tip's holder at rest (-fz), N: rho A g L", -f[2], weight,
                  1e-6);
        check_abs("its horizontal pull, N", hypot(f[0], f[1]), 0.0, 1e-6 * weight);
        double off = 0.0;
        for (int a = 0; a < 3; a++) off = fmax(off, fabs(x[3 * (n - 1) + a] - goal[k][a]));
        check_abs("the tip node off its driven pose, m", off, 0.0, 1e-12);
        check_abs("the root below the tip by L, m", x[3 * (n - 1) + 2] - x[2], length[k], 1e-6);
    }
    double f0[3], r0[3];
    rodsim_end_load(sc, RODSIM_TIP, f0, NULL);
    rodsim_end_load_rod(sc, 0, RODSIM_TIP, r0, NULL);
    check(memcmp(f0, r0, sizeof f0) == 0, "rodsim_end_load reads rod 0: fz %.12g and %.12g N",
          f0[2], r0[2]);
    double tip[3] = {0, 0, 0}, buf[3];
    check(rodsim_set_end_pose_rod(sc, 2, RODSIM_TIP, tip, NULL) == RODSIM_BAD_INPUT &&
              strstr(rodsim_last_error(sc), "0 .. 1 (short, long)"),
          "rod 2 is refused: %s", rodsim_last_error(sc));
    check(rodsim_get_rod(sc, 1, RODSIM_POSITIONS, buf, 3) == RODSIM_BAD_INPUT,
          "rod 1's positions need 78 doubles: %s", rodsim_last_error(sc));
    check(rodsim_set_end_pose_rod(sc, 0, RODSIM_ROOT, tip, NULL) == RODSIM_BAD_INPUT &&
              strstr(rodsim_last_error(sc), "rod short: the root is free (ends short.root"),
          "a free root is not driven: %s", rodsim_last_error(sc));
    check(rodsim_save(sc, buf, 3) == RODSIM_BAD_INPUT &&
              strstr(rodsim_last_error(sc), "rodsim_save: the blob takes"),
          "a save into 3 bytes is refused: %s", rodsim_last_error(sc));
    check(rodsim_set_tip_load(sc, NULL, NULL) == RODSIM_BAD_INPUT,
          "tip loads on several rods are refused: %s", rodsim_last_error(sc));
    rodsim_free(sc);
}

/* Several rods (test_hanging_rods.h) saved at 0.1 s, stepped 0.2 s with
 * both tips moving (A), restored and stepped the same way (B): B is A,
 * every bit; a scene never saved stepped the same way (C) agrees to the
 * Newton tolerance (a save starts the scheme afresh). */
static void drive_two_rods(rodsim_scene *sc, int from, int to, int *ok)
{
    for (int i = from; *ok && i <= to; i++) {
        const double p[2][3] = {{0.001 * i, 0.0, 0.0}, {0.2, -0.0005 * i, 0.0}}; /* m */
        *ok = rodsim_set_end_pose_rod(sc, 0, RODSIM_TIP, p[0], NULL) == RODSIM_OK &&
              rodsim_set_end_pose_rod(sc, 1, RODSIM_TIP, p[1], NULL) == RODSIM_OK &&
              rodsim_step(sc, 0.01) == RODSIM_OK;
    }
}

static void test_several_rods_save(void)
{
    rodsim_scene *sc = NULL, *never = NULL;
    if (!check(rodsim_load_text("hanging_rods", HANGING_RODS_SCENE, NULL, 0, &sc) == RODSIM_OK &&
                   rodsim_load_text("hanging_rods", HANGING_RODS_SCENE, NULL, 0, &never) ==
                       RODSIM_OK,
               "two scenes of two hanging rods load"))
        goto done;
    const size_t size = rodsim_state_size(sc);
    /* 2 rods: 1 + (2 + 30 NS + 12 + 4 + 12 + 2 paths) numbers after the header */
    check(size > (size_t)(16 + 26) * 30 * sizeof(double), "several rods' saved state: %zu bytes",
          size);
    void *blob = malloc(size);
    static double a[2][26 * 3], b[2][26 * 3], c[2][26 * 3];
    int ok = blob != NULL;
    drive_two_rods(sc, 1, 10, &ok);
    drive_two_rods(never, 1, 10, &ok);
    ok = ok && rodsim_save(sc, blob, size) == RODSIM_OK;
    check(ok, "both rods' tips driven 0.1 s, saved: %s", ok ? "ok" : rodsim_last_error(sc));
    drive_two_rods(sc, 11, 30, &ok);
    for (int k = 0; k < 2; k++) rodsim_get_rod(sc, k, RODSIM_POSITIONS, a[k], 26 * 3);
    const double t_a = rodsim_time(sc);
    ok = ok && rodsim_restore(sc, blob, size) == RODSIM_OK;
    check(ok && rodsim_time(sc) == 0.1, "restored: t = %.17g s (0.1)", rodsim_time(sc));
    drive_two_rods(sc, 11, 30, &ok);
    drive_two_rods(never, 11, 30, &ok);
    for (int k = 0; k < 2; k++) {
        rodsim_get_rod(sc, k, RODSIM_POSITIONS, b[k], 26 * 3);
        rodsim_get_rod(never, k, RODSIM_POSITIONS, c[k], 26 * 3);
    }
    double moved = 0.0, diff_ab = 0.0, diff_bc = 0.0;
    for (int i = 0; i < 2 * 26 * 3; i++) {
        const double *pa = &a[0][0], *pb = &b[0][0], *pc = &c[0][0];
        diff_ab = fmax(diff_ab, fabs(pa[i] - pb[i]));
        diff_bc = fmax(diff_bc, fabs(pb[i] - pc[i]));
    }
    moved = fabs(b[1][3 * 25 + 1] - (-0.0005 * 10));
    printf("after the restore: t = %.17g s (%.17g s before it); long's tip moved %.3g m "
           "since the save; largest difference: restored-stepped %.3g m, never saved %.3g m\n",
           rodsim_time(sc), t_a, moved, diff_ab, diff_bc);
    check(ok && rodsim_time(sc) == t_a && moved > 0.009,
          "stepped 0.2 s again after the restore, the tips moving: %s",
          ok ? "ok" : rodsim_last_error(sc));
    check(memcmp(a, b, sizeof a) == 0, "restored then stepped = stepped after the save, every "
          "bit of both rods' positions (largest difference %.3g m)", diff_ab);
    /* a save starts the rods' scheme afresh (Jacobians rebuilt, the contact
     * between rods found anew), as for one rod: a scene never saved steps
     * the same to the Newton tolerance, not the bit */
    check_abs("a scene never saved, stepped the same: largest difference of the positions, m "
              "(1e-6 of the 0.01 m moved)", diff_bc, 0.0, 1e-8);
    /* a state saved before any tip was driven: its restore drops the live
     * paths, the tips held as the scene holds them, the next 0.1 s as after
     * the save */
    rodsim_scene *early = NULL;
    static double p1[26 * 3], p2[26 * 3];
    int early_ok = rodsim_load_text("hanging_rods", HANGING_RODS_SCENE, NULL, 0, &early) ==
                       RODSIM_OK && rodsim_save(early, blob, size) == RODSIM_OK &&
                   rodsim_step(early, 0.1) == RODSIM_OK &&
                   rodsim_get_rod(early, 1, RODSIM_POSITIONS, p1, 26 * 3) == RODSIM_OK;
    drive_two_rods(early, 1, 10, &early_ok);
    early_ok = early_ok && rodsim_restore(early, blob, size) == RODSIM_OK &&
               rodsim_step(early, 0.1) == RODSIM_OK &&
               rodsim_get_rod(early, 1, RODSIM_POSITIONS, p2, 26 * 3) == RODSIM_OK;
    check(early_ok && memcmp(p1, p2, sizeof p1) == 0,
          "a state saved before the tips were driven, restored after driving them: the tips "
          "held again, the next 0.1 s bit for bit as after the save%s%s",
          early_ok ? "" : ": ", early_ok ? "" : rodsim_last_error(early));
    rodsim_free(early);
    unsigned char *bad = blob;
    bad[0] ^= 1;
    check(rodsim_restore(sc, blob, size) == RODSIM_BAD_INPUT &&
              strstr(rodsim_last_error(sc), "not a saved state of this scene"),
          "a damaged blob is refused: %s", rodsim_last_error(sc));
    free(blob);
done:
    rodsim_free(sc);
    rodsim_free(never);
}

int main(void)
{
    test_same_as_cli();
    test_save_restore_and_weight();
    test_bad_scene();
    test_overrides_and_use();
    test_tip_load();
    test_several_rods();
    test_several_rods_save();
    test_divergence();
    test_threads();
    test_install();
    return test_finish();
}
