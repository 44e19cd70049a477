/* test_scene.c: scene files -> rod_model. Every scene in scenes/ parses and
 * derives; a few values are checked against the numbers written in the file
 * and against hand-computed physics (PL^3/3EI, Euler's load, rho A g);
 * --set overrides; bad values give file:line and the key; load tables;
 * the keys (starting shape and state, ends, paths, point loads): read
 * into the model, shape files resampled to nodes exactly ds apart on the
 * polyline, and every bad value named at its line. */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/ini.h"
#include "base/vec3.h"
#include "cli/run.h"
#include "cli/scene_outputs.h"
#include "sim/path.h"
#include "sim/rod.h"
#include "sim/rod_set.h"
#include "sim/scene.h"
#include "test.h"

#define SCENES RODSIM_SOURCE_DIR "/scenes"

/* Loads and reads a scene file the way `rodsim run` does. 0 on success. */
static int read_scene_file(const char *path, rod_model *m, run_output *out, char *err,
                           size_t errlen)
{
    ini_doc *doc = ini_load(path, err, errlen);
    if (!doc) return -1;
    int rc = scene_read_rod(doc, m, err, errlen);
    if (rc == 0 && (run_read_output(doc, out, err, errlen) || ini_check_unused(doc, err, errlen))) {
        rod_model_release(m);
        rc = -1;
    }
    ini_destroy(doc);
    return rc;
}

static void test_every_scene_parses(void)
{
    DIR *dir = opendir(SCENES);
    check(dir != NULL, "scenes directory %s opens", SCENES);
    if (!dir) return;
    int count = 0;
    struct dirent *e;
    while ((e = readdir(dir))) {
        size_t n = strlen(e->d_name);
        if (n < 5 || strcmp(e->d_name + n - 4, ".ini") != 0) continue;
        char path[1024], err[1024] = "";
        snprintf(path, sizeof path, "%s/%s", SCENES, e->d_name);
        if (test_is_fem_scene(path)) continue; /* checked by test_fem */
        /* every rod of it (several: [rod NAME]), as `rodsim run` reads them */
        rod_set set;
        run_output out;
        ini_doc *doc = ini_load(path, err, sizeof err);
        int ok = doc && scene_read_rods(doc, &set, err, sizeof err) == 0;
        if (ok && (run_read_output(doc, &out, err, sizeof err) ||
                   ini_check_unused(doc, err, sizeof err))) {
            rod_set_release(&set);
            ok = 0;
        }
        ini_destroy(doc);
        for (int k = 0; ok && k < set.count; k++)
            ok = set.model[k].ds > 0.0 && set.model[k].stiffness[0] > 0.0;
        check(ok, "scene %s parses and derives %s", e->d_name, err);
        if (ok) rod_set_release(&set);
        count++;
    }
    closedir(dir);
    check(count >= 9, "scenes/ holds one scene per thesis scenario and the demos: %d files", count);
}

static void test_scene_values(void)
{
    char err[1024] = "";
    rod_model m;
    run_output out;
    /* table 2, P = 8e-7 N: values as written in the file */
    if (check(read_scene_file(SCENES "/table2_800nN.ini", &m, &out, err, sizeof err) == 0,
              "table2_800nN.ini reads (%s)", err)) {
        check(m.nodes == 51 && m.options.scheme == ROD_SCHEME_STATIC &&
                  m.tip_frame == ROD_FRAME_GLOBAL && m.tip_force[1] == 8e-7 &&
                  m.youngs_modulus == 87.5e6 && out.fps == 30,
              "table2_800nN: NS %d, scheme static, global frame, force %g N, E %g Pa, fps %d",
              m.nodes, m.tip_force[1], m.youngs_modulus, out.fps);
        /* thesis table 2, y_exp = PL^3/3EI for P = 8e-7 N: 0.0620856 m */
        double linear = m.tip_force[1] * pow(m.length, 3) / (3.0 * m.stiffness[0]);
        check_rel("table2_800nN: PL^3/3EI from the scene vs issue value", linear, 0.0620856, 1e-5);
        rod_model_release(&m);
    }
    /* bending moments: |M| L / EI = pi/2, the quarter circle */
    if (check(read_scene_file(SCENES "/bending_moments.ini", &m, &out, err, sizeof err) == 0,
              "bending_moments.ini reads (%s)", err)) {
        double moment = hypot(m.tip_moment[0], m.tip_moment[1]);
        check_rel("bending_moments: |M| L / EI vs pi/2", moment * m.length / m.stiffness[0],
                  M_PI / 2.0, 1e-4);
        rod_model_release(&m);
    }
    /* axial buckling: dead load of 2 P_cr, P_cr = pi^2 EI / (4 L^2) */
    if (check(read_scene_file(SCENES "/buckling_axial.ini", &m, &out, err, sizeof err) == 0,
              "buckling_axial.ini reads (%s)", err)) {
        double euler = M_PI * M_PI * 87.5e6 * M_PI * 1e-12 / 64.0 / 4.0; /* by hand, L = 1 */
        check(m.tip_frame == ROD_FRAME_GLOBAL && m.tip_force[0] < 0.0,
              "buckling_axial: a dead (global) compressive load along -x");
        check_rel("buckling_axial: axial force / Euler load", -m.tip_force[0] / euler, 2.0, 1e-3);
        check_rel("buckling_axial: ramp ends at the duration", m.profile.t1, m.options.duration,
                  1e-12);
        rod_model_release(&m);
    }
    /* impulse: thesis fig. 10 profile, Crank-Nicolson */
    if (check(read_scene_file(SCENES "/impulse.ini", &m, &out, err, sizeof err) == 0,
              "impulse.ini reads (%s)", err)) {
        check(m.profile.kind == ROD_PROFILE_IMPULSE && m.profile.t1 == 0.005 &&
                  m.options.theta == 0.5 && m.options.dt == 0.0005,
              "impulse: profile impulse 0.005 s, theta 0.5, dt 0.0005 s");
        check(rod_profile_factor(&m.profile, 0.002) == 1.0 &&
                  rod_profile_factor(&m.profile, 0.007) == -1.0 &&
                  rod_profile_factor(&m.profile, 0.012) == 0.0,
              "impulse: +1 during the first 5 ms, -1 during the next, then 0");
        rod_model_release(&m);
    }
    /* gravity: rho A g = 850 * pi/4 * 1e-6 * 9.81 N/m, by hand */
    if (check(read_scene_file(SCENES "/suture_gravity.ini", &m, &out, err, sizeof err) == 0,
              "suture_gravity.ini reads (%s)", err)) {
        check_rel("suture_gravity: distributed force z = -rho A g", m.distributed_force[2],
                  -850.0 * 0.785398163397448 * 1e-6 * 9.81, 1e-12);
        check(m.linear_damping == 1e-3 && m.distributed_force[0] == 0.0,
              "suture_gravity: damping %g N s/m^2", m.linear_damping);
        rod_model_release(&m);
    }
    if (check(read_scene_file(SCENES "/suture_cantilever.ini", &m, &out, err, sizeof err) == 0,
              "suture_cantilever.ini reads (%s)", err)) {
        check(out.width == 1280 && out.height == 720 && m.tip_moment[2] == 4e-6 &&
                  m.profile.kind == ROD_PROFILE_RAMP && m.profile.t1 == 4.0,
              "suture: 1280x720, M3 = %g N m, ramp %g s", m.tip_moment[2], m.profile.t1);
        rod_model_release(&m);
    }
}

static void test_set_overrides(void)
{
    char err[1024] = "";
    ini_doc *doc = ini_load(SCENES "/table2_450nN.ini", err, sizeof err);
    if (!check(doc != NULL, "table2_450nN.ini loads (%s)", err)) return;
    rod_model m;
    int ok = ini_set(doc, "rod.nodes=101", err, sizeof err) == 0 &&
             ini_set(doc, "tip.force=\"0 8e-7 0\"", err, sizeof err) == 0 &&
             ini_set(doc, "solver.scheme=thesis", err, sizeof err) == 0 &&
             ini_set(doc, "solver.dt=0.001", err, sizeof err) == 0 &&
             ini_set(doc, "rod.nodes=201", err, sizeof err) == 0 && /* later --set wins */
             ini_set(doc, "loads.gravity=0 0 -9.81", err, sizeof err) == 0 &&
             scene_read_rod(doc, &m, err, sizeof err) == 0;
    if (check(ok, "--set overrides apply (%s)", err)) {
        check(m.nodes == 201 && m.tip_force[1] == 8e-7 && m.options.scheme == ROD_SCHEME_THESIS &&
                  m.options.dt == 0.001 && m.distributed_force[2] < 0.0,
              "--set: NS %d (last wins), force %g, scheme thesis, dt %g, gravity added", m.nodes,
              m.tip_force[1], m.options.dt);
        check_rel("--set rod.nodes=201: ds = L/200", m.ds, 1.0 / 200.0, 1e-12);
        rod_model_release(&m);
    }
    ini_destroy(doc);
}

static const char valid_rod[] = "[rod]\nlength = 1.0\ndiameter = 0.001\ndensity = 850\n"
                                "youngs_modulus = 87.5e6\nshear_modulus = 31.25e6\nnodes = 51\n";

/* Parses valid_rod + extra (or `text` alone when replace is set) and expects an error
 * containing every needle. */
static void expect_bad(const char *extra, const char *what, const char *needle1,
                       const char *needle2)
{
    char text[2048], err[1024] = "";
    snprintf(text, sizeof text, "%s%s", valid_rod, extra);
    ini_doc *doc = ini_parse("bad.ini", text, err, sizeof err);
    int failed = 1;
    if (doc) {
        rod_model m;
        run_output out;
        failed = scene_read_rod(doc, &m, err, sizeof err) != 0;
        if (!failed) {
            failed = run_read_output(doc, &out, err, sizeof err) || ini_check_unused(doc, err, sizeof err);
            rod_model_release(&m);
        }
        ini_destroy(doc);
    }
    check(failed && strstr(err, needle1) && strstr(err, needle2),
          "%s: error '%s' names '%s' and '%s'", what, err, needle1, needle2);
}

static void expect_bad_rod(const char *rod_text, const char *what, const char *needle1,
                           const char *needle2)
{
    char err[1024] = "";
    ini_doc *doc = ini_parse("bad.ini", rod_text, err, sizeof err);
    int failed = 1;
    if (doc) {
        rod_model m;
        failed = scene_read_rod(doc, &m, err, sizeof err) != 0;
        if (!failed) rod_model_release(&m);
        ini_destroy(doc);
    }
    check(failed && strstr(err, needle1) && strstr(err, needle2),
          "%s: error '%s' names '%s' and '%s'", what, err, needle1, needle2);
}

static void test_bad_values(void)
{
    /* line numbers: valid_rod is 7 lines, so extra text starts on line 8 */
    expect_bad("[solver]\nscheme = euler\n", "unknown scheme", "bad.ini:9:", "thesis | implicit | static");
    expect_bad("[solver]\ndt = -1\n", "negative dt", "bad.ini:9:", "auto");
    expect_bad("[solver]\ntheta = 0.3\n", "theta out of range", "bad.ini:9:", "crank_nicolson");
    expect_bad("[solver]\nduration = 0\n", "zero duration", "bad.ini:9:", "duration");
    expect_bad("[tip]\nprofile = wobble\n", "bad profile word", "bad.ini:9:", "ramp T");
    expect_bad("[tip]\nprofile = ramp\n", "ramp without T", "bad.ini:9:", "profile");
    expect_bad("[tip]\nprofile = pulse 2 1\n", "pulse off before on", "bad.ini:9:", "T_on < T_off");
    expect_bad("[tip]\nframe = local\n", "bad frame", "bad.ini:9:", "director | global");
    expect_bad("[tip]\nforce = 0 1\n", "force with 2 numbers", "bad.ini:9:", "force");
    expect_bad("[loads]\nlinear_damping = -1\n", "negative damping", "bad.ini:9:", "linear_damping");
    expect_bad("[render]\nwidth = 641\n", "odd video width", "bad.ini:9:", "even");
    expect_bad("[render]\ncolour = red\n", "unknown key", "bad.ini:9:", "colour");
    expect_bad("[camera]\nfov = 30\n", "unknown section", "bad.ini:8:", "camera");
    expect_bad("[tip]\nprofile = table /nonexistent/load.csv\n", "missing table file",
               "bad.ini:9:", "/nonexistent/load.csv");
    expect_bad_rod("[rod]\nlength = -1\ndiameter = 0.001\ndensity = 850\nyoungs_modulus = 1e6\n"
                   "shear_modulus = 1e6\nnodes = 51\n",
                   "negative length", "bad.ini:2:", "length");
    expect_bad_rod("[rod]\nlength = 1\ndiameter = 0.001\ndensity = 850\nyoungs_modulus = 1e6\n"
                   "shear_modulus = 1e6\nnodes = 2\n",
                   "NS < 3", "bad.ini:7:", "nodes");
    expect_bad_rod("[rod]\nlength = 1\ndiameter = 2\ndensity = 850\nyoungs_modulus = 1e6\n"
                   "shear_modulus = 1e6\nnodes = 51\n",
                   "diameter >= length", "bad.ini:3:", "diameter");
    expect_bad_rod("[rod]\nlength = 1\ndiameter = 0.001\ndensity = 85O\nyoungs_modulus = 1e6\n"
                   "shear_modulus = 1e6\nnodes = 51\n",
                   "malformed number", "bad.ini:4:", "density");
    expect_bad_rod("[rod]\nlength = 1\ndiameter = 0.001\ndensity = 850\n"
                   "shear_modulus = 1e6\nnodes = 51\n",
                   "missing youngs_modulus", "bad.ini:1:", "[rod] youngs_modulus");
    expect_bad_rod("[solver]\nscheme = static\n", "no [rod] section", "bad.ini", "[rod] length");
    /* a normal whose length overflows was scaled to 0 0 0 and the plane then
     * reported at its center, at the rod's radius deep; one whose length
     * underflows to a subnormal was left off unit length */
    expect_bad("[surface]\nshape = plane\ncenter = 0 -1 0\nnormal = 1e308 1e308 0\n",
               "a normal whose length overflows", "bad.ini:11: [surface] normal = 1e308 1e308 0",
               "must be a direction: 3 numbers, not all 0, of length 1e-150 to 1e150");
    expect_bad("[surface]\nshape = cylinder\nsize = 0.1\ncenter = 0 -1 0\nnormal = 1e-160 0 0\n",
               "an axis whose length underflows", "bad.ini:12: [surface] normal = 1e-160 0 0",
               "cylinder's axis direction");
    expect_bad("[rod]\nnodes = 21\n", "[rod] given twice", "bad.ini:8: [rod] is given again "
               "(first on line 1)", "accepted: one [rod] section holding all its keys");
}

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

static void test_tables(void)
{
    char dir[] = "/tmp/rodsim_scene_XXXXXX";
    if (!check(mkdtemp(dir) != NULL, "temporary directory")) return;
    char path[256], scene[256], err[1024] = "";
    rod_table t;

    snprintf(path, sizeof path, "%s/two.csv", dir);
    write_file(path, "t,factor\n0,0\n1,1\n# hold\n\n3,0.5\n");
    if (check(scene_load_table(path, &t, err, sizeof err) == 0 && t.rows == 3 && t.columns == 2,
              "2-column table: %d rows (%s)", t.rows, err)) {
        rod_profile p = {.kind = ROD_PROFILE_TABLE, .table = t};
        /* piecewise linear: at t = 2 halfway between 1 and 0.5 */
        check_abs("table factor at t = 2 s", rod_profile_factor(&p, 2.0), 0.75, 1e-15);
        free(t.data);
    }
    snprintf(path, sizeof path, "%s/seven.csv", dir);
    write_file(path, "t,fx,fy,fz,mx,my,mz\n0, 0,0,0, 0,0,0\n2, 0,2e-6,0, 0,0,1e-6\n");
    check(scene_load_table(path, &t, err, sizeof err) == 0 && t.rows == 2 && t.columns == 7 &&
              t.data[9] == 2e-6,
          "7-column table (%s)", err);
    free(t.data);

    snprintf(path, sizeof path, "%s/back.csv", dir);
    write_file(path, "t,factor\n0,0\n1,1\n1,2\n");
    check(scene_load_table(path, &t, err, sizeof err) == -1 && strstr(err, "back.csv:4:") &&
              strstr(err, "increase"),
          "times must increase: '%s'", err);
    snprintf(path, sizeof path, "%s/mixed.csv", dir);
    write_file(path, "t,factor\n0,0\n1,1,2,3,4,5,6\n");
    check(scene_load_table(path, &t, err, sizeof err) == -1 && strstr(err, "mixed.csv:3:"),
          "rows of different widths: '%s'", err);
    snprintf(path, sizeof path, "%s/word.csv", dir);
    write_file(path, "t,factor\n0,zero\n");
    check(scene_load_table(path, &t, err, sizeof err) == -1 && strstr(err, "word.csv:2:"),
          "a word in a data row: '%s'", err);

    /* an empty table, named from a scene relative to the scene's directory */
    snprintf(path, sizeof path, "%s/empty.csv", dir);
    write_file(path, "t,factor\n");
    snprintf(scene, sizeof scene, "%s/s.ini", dir);
    char text[1024];
    snprintf(text, sizeof text, "%s[tip]\nforce = 0 1e-7 0\nprofile = table empty.csv\n", valid_rod);
    write_file(scene, text);
    rod_model m;
    run_output out;
    check(read_scene_file(scene, &m, &out, err, sizeof err) == -1 && strstr(err, "s.ini:10:") &&
              strstr(err, "profile") && strstr(err, "empty.csv:1:") && strstr(err, "empty"),
          "empty table: '%s'", err);
    snprintf(text, sizeof text, "%s[tip]\nforce = 0 1e-7 0\nprofile = table two.csv\n", valid_rod);
    write_file(scene, text);
    if (check(read_scene_file(scene, &m, &out, err, sizeof err) == 0 &&
                  m.profile.kind == ROD_PROFILE_TABLE && m.profile.table.rows == 3,
              "table path relative to the scene file (%s)", err)) {
        double f[3], mo[3];
        rod_tip_load(&m, 0.5, f, mo);
        check_abs("tip force from the table at t = 0.5 s", f[1], 0.5e-7, 1e-20);
        rod_model_release(&m);
    }
    /* files that are not tables: refused before a byte is read (/dev/zero
     * never ends: the reader hung there, growing without bound) */
    check(scene_load_table("/dev/zero", &t, err, sizeof err) == -1 && t.data == NULL &&
              strstr(err, "/dev/zero: a character device, not a load table file") &&
              strstr(err, "at most 256 MiB"),
          "/dev/zero as a load table: '%s'", err);
    check(scene_load_table(dir, &t, err, sizeof err) == -1 && strstr(err, "a directory"),
          "a directory as a load table: '%s'", err);
    snprintf(text, sizeof text, "%s[tip]\nforce = 0 1e-7 0\nprofile = table /dev/zero\n",
             valid_rod);
    write_file(scene, text);
    check(read_scene_file(scene, &m, &out, err, sizeof err) == -1 && strstr(err, "s.ini:10:") &&
              strstr(err, "profile") && strstr(err, "a character device"),
          "profile = table /dev/zero: '%s'", err);
    /* from memory: a byte-order mark before the header, CR LF line ends */
    err[0] = '\0';
    check(scene_parse_table("mem.csv", "\xEF\xBB\xBFt,factor\r\n0,0\r\n1,2\r\n", &t, err,
                            sizeof err) == 0 && t.rows == 2 && t.data[3] == 2.0,
          "a table parsed from memory, with a byte-order mark and CR LF (%s)", err);
    free(t.data);
    check(scene_parse_table("mem.csv", "t,factor\n0\n", &t, err, sizeof err) == -1 &&
              strstr(err, "mem.csv:2:") && t.data == NULL && t.rows == 0,
          "a bad row parsed from memory, named by the given name: '%s'", err);
    const char *names[] = {"two.csv", "seven.csv", "back.csv", "mixed.csv", "word.csv",
                           "empty.csv", "s.ini"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        unlink(path);
    }
    rmdir(dir);
}

static void test_frame_count(void)
{
    check(run_frame_count(10.0, 30) == 301, "10 s at 30 fps: 301 frames (t = 0 included): %d",
          run_frame_count(10.0, 30));
    check(run_frame_count(0.1, 30) == 4, "0.1 s at 30 fps: 4 frames: %d", run_frame_count(0.1, 30));
    check(run_frame_count(1.01, 30) == 32, "1.01 s at 30 fps: 31 regular + the end: %d",
          run_frame_count(1.01, 30));
}

/* Reads `text` as dir/s.ini (so files it names are relative to dir). */
static int read_text_scene(const char *dir, const char *text, rod_model *m, char *err,
                           size_t errlen)
{
    char scene[512];
    snprintf(scene, sizeof scene, "%s/s.ini", dir);
    write_file(scene, text);
    run_output out;
    return read_scene_file(scene, m, &out, err, errlen);
}

static void expect_scene_error(const char *dir, const char *extra, const char *what,
                               const char *needle1, const char *needle2)
{
    char text[4096], err[2048] = "";
    snprintf(text, sizeof text, "%s%s", valid_rod, extra);
    rod_model m;
    int failed = read_text_scene(dir, text, &m, err, sizeof err) != 0;
    if (!failed) rod_model_release(&m);
    check(failed && strstr(err, needle1) && strstr(err, needle2), "%s: error '%s' names '%s' and '%s'",
          what, err, needle1, needle2);
}

/* A rod of length 1 m that runs 0.15 m along x, winds once round a circle of
 * radius 0.1 m in the x-y plane while rising `rise` in z (a helical loop),
 * then runs on along x at z = rise to the end: its in and out straight parts
 * are parallel, `rise` apart, one over the other. Writes it to path. */
static void write_loop_shape(const char *path, double rise)
{
    const double a = 0.15, r = 0.1;
    const int points = 2000;
    double loop = 0.0, prev[3] = {a, 0.0, 0.0};
    FILE *f = fopen(path, "w");
    if (!f) return;
    fprintf(f, "x,y,z\n0,0,0\n%.17g,0,0\n", a);
    for (int i = 1; i <= points; i++) {
        double th = 2.0 * M_PI * i / points;
        double q[3] = {a + r * sin(th), r * (1.0 - cos(th)), rise * th / (2.0 * M_PI)};
        if (i == points) q[0] = a, q[1] = 0.0;
        loop += hypot(hypot(q[0] - prev[0], q[1] - prev[1]), q[2] - prev[2]);
        fprintf(f, "%.17g,%.17g,%.17g\n", q[0], q[1], q[2]);
        memcpy(prev, q, sizeof prev);
    }
    fprintf(f, "%.17g,0,%.17g\n", 1.0 - loop, rise); /* the rest of the 1 m */
    fclose(f);
}

/* a starting shape that already intersects itself is refused,
 * naming the segments and how far apart they are; one that keeps its strands
 * a diameter apart is read. */
static void test_self_intersecting_shape(void)
{
    char dir[] = "/tmp/rodsim_loop_XXXXXX", path[512], text[1024], err[2048] = "";
    if (!check(mkdtemp(dir) != NULL, "temporary directory")) return;
    snprintf(path, sizeof path, "%s/loop.csv", dir);
    /* d = 1 mm: the strands 0.5 mm apart (refused), then 1.5 mm (read) */
    write_loop_shape(path, 0.0005);
    snprintf(text, sizeof text, "%sshape = loop.csv\n", valid_rod);
    rod_model m;
    int failed = read_text_scene(dir, text, &m, err, sizeof err) != 0;
    if (!failed) rod_model_release(&m);
    const char *at = strstr(err, " come "); /* "... come 0.0005 m apart" */
    double reported = at ? strtod(at + 6, NULL) : 0.0;
    check(failed && strstr(err, "s.ini:8:") && strstr(err, "shape") &&
              strstr(err, "intersects itself") && strstr(err, "segments 8 "),
          "strands 0.5 mm apart, d = 1 mm: refused at the shape key, naming segment 8 (s = "
          "0.14..0.16 m, where the loop starts): '%s'", err);
    /* the resampled rod's chord from the loop's last node onto the straight part
     * runs a little below z = rise: the reported distance is within 5 % of it */
    check_rel("  the distance it reports (the loop's rise, 0.5 mm)", reported, 0.0005, 0.05);
    write_loop_shape(path, 0.0015);
    err[0] = '\0';
    failed = read_text_scene(dir, text, &m, err, sizeof err) != 0;
    if (!failed) rod_model_release(&m);
    check(!failed, "strands 1.5 mm apart, d = 1 mm: read (%s)", err);
    unlink(path);
    snprintf(path, sizeof path, "%s/s.ini", dir);
    unlink(path);
    rmdir(dir);
}

static void test_issue10_keys(void)
{
    char dir[] = "/tmp/rodsim_ends_XXXXXX";
    if (!check(mkdtemp(dir) != NULL, "temporary directory")) return;
    char text[4096], err[2048] = "", path[512];
    rod_model m;

    /* the starting state, ends and loads as written */
    snprintf(text, sizeof text, "%s"
             "origin = 0.1 0.2 0.3\ndirection = 0 0 -2\ncurvature = 0 3 0\ninitial_velocity = 1 2 3\n"
             "[loads]\ndistributed_moment = 0 0 1e-6\n"
             "[ends]\nroot = free\ntip = free\nneedle = 0.01\n"
             "[point_load]\ns = 0.509\nforce = 0 0 -1e-3\n[point_load]\ns = 1\nmoment = 1e-6 0 0\n",
             valid_rod);
    if (check(read_text_scene(dir, text, &m, err, sizeof err) == 0, "keys read (%s)", err)) {
        check(m.origin[2] == 0.3 && m.direction[2] == -1.0 && m.intrinsic_curvature[1] == 3.0 &&
                  m.initial_velocity[1] == 2.0 && m.distributed_moment[2] == 1e-6 &&
                  m.root_end == ROD_END_FREE && m.tip_end == ROD_END_FREE && m.needle_radius == 0.01,
              "origin, direction (normalised to 0 0 -1), curvature, initial velocity, distributed "
              "moment, root = free, needle as written");
        check(m.point_load_count == 2 && m.point_loads[0].node == 25 &&
                  m.point_loads[0].force[2] == -1e-3 && m.point_loads[1].node == 50 &&
                  m.point_loads[1].moment[0] == 1e-6,
              "two point loads: s = 0.509 m at node %d (nearest, ds = 0.02 m), s = 1 m at node %d",
              m.point_load_count > 0 ? m.point_loads[0].node : -1,
              m.point_load_count > 1 ? m.point_loads[1].node : -1);
        rod_model_release(&m);
    }

    /* a shape file: a half circle of radius 1/pi (length 1), 2001 points, relative path */
    snprintf(path, sizeof path, "%s/arc.csv", dir);
    FILE *f = fopen(path, "w");
    const double radius = 1.0 / M_PI;
    if (f) {
        fprintf(f, "# a half circle\nx, y, z\n");
        for (int i = 0; i <= 2000; i++) {
            double a = M_PI * i / 2000.0;
            fprintf(f, "%.17g,%.17g,0\n", radius * sin(a), radius * (1.0 - cos(a)));
        }
        fclose(f);
    }
    snprintf(text, sizeof text, "%sshape = arc.csv\n", valid_rod);
    if (check(read_text_scene(dir, text, &m, err, sizeof err) == 0 && m.initial_shape,
              "shape = arc.csv (relative to the scene) reads (%s)", err)) {
        double chord = 0.0, off = 0.0;
        for (int i = 0; i < m.nodes; i++) {
            const double *r = &m.initial_shape[3 * i];
            off = fmax(off, fabs(hypot(r[0], r[1] - radius) - radius));
            if (i > 0) {
                double d[3];
                v3_sub(d, r, r - 3);
                chord = fmax(chord, fabs(v3_norm(d) - m.ds) / m.ds);
            }
        }
        const double *tip = &m.initial_shape[3 * (m.nodes - 1)];
        double shortfall = hypot(tip[0], tip[1] - 2.0 * radius);
        double k = 1.0 / radius;
        printf("    half circle: last node %.3e m from the polyline's end (chord shortfall, about "
               "L (k ds)^2 / 24 along the arc: %.3e m)\n", shortfall, k * k * m.ds * m.ds / 24.0);
        check(chord < 1e-12 && off < 1e-6 && m.initial_shape[0] == 0.0 && m.origin[1] == 0.0 &&
                  fabs(m.direction[0] - 1.0) < 1e-6,
              "resampled: every segment ds within %.1e (relative), every node on the circle "
              "within %.1e m (the polyline's sagitta), origin at the first point, direction "
              "(%.6f, %.6f, 0) along the start's tangent", chord, off, m.direction[0],
              m.direction[1]);
        check(shortfall < 2.0 * k * k * m.ds * m.ds / 24.0,
              "the last node falls short of the end by %.3e m, below 2 L (k ds)^2/24 = %.3e m",
              shortfall, 2.0 * k * k * m.ds * m.ds / 24.0);
        rod_model_release(&m);
    }
    /* the same shape with length 1.001: refused, naming the scene line and the shape's last line */
    snprintf(text, sizeof text, "[rod]\nlength = 1.001\ndiameter = 0.001\ndensity = 850\n"
             "youngs_modulus = 87.5e6\nshear_modulus = 31.25e6\nnodes = 51\nshape = arc.csv\n");
    err[0] = '\0';
    int failed = read_text_scene(dir, text, &m, err, sizeof err) != 0;
    if (!failed) rod_model_release(&m);
    check(failed && strstr(err, "s.ini:8:") && strstr(err, "arc.csv:2003:") && strstr(err, "1e-6"),
          "shape length 1 m against length 1.001 m: '%s'", err);

    static const struct { const char *name, *content, *needle; } shapes[] = {
        {"head.csv", "x,y\n0,0\n1,0\n", "head.csv:1:"},
        {"two.csv", "x,y,z\n0,0,0\n1,0\n", "two.csv:3:"},
        {"nan.csv", "x,y,z\n0,0,0\nnan,0,0\n", "nan.csv:3:"},
        {"same.csv", "x,y,z\n0,0,0\n0,0,0\n1,0,0\n", "same.csv:3:"},
        {"one.csv", "x,y,z\n0,0,0\n", "one.csv:2:"},
    };
    for (size_t i = 0; i < sizeof shapes / sizeof shapes[0]; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, shapes[i].name);
        write_file(path, shapes[i].content);
        char extra[128];
        snprintf(extra, sizeof extra, "shape = %s\n", shapes[i].name);
        expect_scene_error(dir, extra, "bad shape file", "s.ini:8:", shapes[i].needle);
        unlink(path);
    }
    {
        /* a line past the reader's buffer was read as two rows (class):
         * now refused at its line, as the load table and path readers do */
        static char long_line[1400];
        snprintf(long_line, sizeof long_line, "x,y,z\n0,0,0\n1,0,%01100d\n", 0);
        snprintf(path, sizeof path, "%s/long.csv", dir);
        write_file(path, long_line);
        expect_scene_error(dir, "shape = long.csv\n", "shape file with a 1106-character line",
                           "s.ini:8:", "long.csv:3: line longer than");
        unlink(path);
    }
    expect_scene_error(dir, "shape = missing.csv\n", "missing shape file", "s.ini:8:", "cannot open");
    /* not shape files: refused unread (/dev/zero hung the reader) */
    expect_scene_error(dir, "shape = /dev/zero\n", "/dev/zero as the shape", "s.ini:8:",
                       "/dev/zero: a character device, not a shape file; a shape file is text "
                       "of at most 128 MiB");
    expect_scene_error(dir, "shape = .\n", "a directory as the shape", "s.ini:8:",
                       "a directory, not a shape file");
    {
        /* a byte-order mark before the header (a spreadsheet's CSV) is skipped */
        double *points = NULL;
        int count = 0, last = 0;
        err[0] = '\0';
        int rc = scene_parse_shape("bom.csv", "\xEF\xBB\xBFx,y,z\n0,0,0\n1,0,0\n", &points, &count,
                                   &last, err, sizeof err);
        check(rc == 0 && count == 2 && last == 3 && points[3] == 1.0,
              "a shape parsed from memory, with a byte-order mark: %d points, the last on line %d "
              "(%s)", count, last, err);
        free(points);
        rc = scene_parse_shape("mem.csv", "x,y,z\n0,0,0\n", &points, &count, &last, err,
                               sizeof err);
        check(rc == -1 && points == NULL && count == 0 && strstr(err, "mem.csv:2:"),
              "a one-point shape from memory: refused, owning nothing: '%s'", err);
    }
    expect_scene_error(dir, "shape = arc.csv\norigin = 1 0 0\n", "origin with a shape", "s.ini:9:",
                       "remove this key");
    expect_scene_error(dir, "direction = 0 0 0\n", "zero direction", "s.ini:8:", "0 0 0");
    expect_scene_error(dir, "shape = curly\n", "a shape word", "s.ini:8:", "straight | FILE.csv");

    /* driven ends: a path relative to the scene, starting where the end starts */
    snprintf(path, sizeof path, "%s/lift.csv", dir);
    write_file(path, "t,x,y,z,rx,ry,rz\n0,1,0,0,0,0,0\n1,1,0,0.1,0,0.2,0\n");
    snprintf(text, sizeof text, "%s[ends]\ntip = clamped\ntip_motion = lift.csv\n", valid_rod);
    if (check(read_text_scene(dir, text, &m, err, sizeof err) == 0 && m.tip_motion &&
                  rod_path_columns(m.tip_motion) == 7 && rod_path_end(m.tip_motion) == 1.0,
              "tip = clamped, tip_motion = lift.csv: a 7-column path ending at 1 s (%s)", err)) {
        rod_pose pose;
        rod_path_eval(m.tip_motion, 1.0, &pose);
        check(pose.position[2] == 0.1, "the path lifts the tip to z = %g m", pose.position[2]);
        rod_model_release(&m);
    }
    expect_scene_error(dir, "[ends]\ntip_motion = lift.csv\n", "a free tip driven", "s.ini:9:",
                       "the tip is free");
    expect_scene_error(dir, "[ends]\ntip = pinned\ntip_motion = lift.csv\n", "a pinned tip with a "
                       "rotation path", "s.ini:10:", "no rotation");
    expect_scene_error(dir, "[ends]\ntip = clamped\nroot_motion = lift.csv\n",
                       "a root path starting at the tip", "s.ini:10:", "starts at (0, 0, 0)");
    snprintf(path, sizeof path, "%s/back.csv", dir);
    write_file(path, "t,x,y,z\n0,1,0,0\n0,1,0,0\n");
    expect_scene_error(dir, "[ends]\ntip = pinned\ntip_motion = back.csv\n",
                       "times that do not increase", "s.ini:10:", "back.csv:3:");
    unlink(path);
    snprintf(path, sizeof path, "%s/rot.csv", dir);
    write_file(path, "t,x,y,z,rx,ry,rz\n0,1,0,0,0,0,0\n1,1,0,0,inf,0,0\n");
    expect_scene_error(dir, "[ends]\ntip = clamped\ntip_motion = rot.csv\n",
                       "a rotation that is not finite", "s.ini:10:", "rot.csv:3: rx");
    unlink(path);

    expect_scene_error(dir, "[ends]\ntip = pinned\ntip_motion = /dev/zero\n",
                       "/dev/zero as a path", "s.ini:10:",
                       "/dev/zero: a character device, not a path file");

    /* ends, slides, needle, point loads */
    expect_scene_error(dir, "[ends]\nroot = loose\n", "bad root word", "s.ini:9:",
                       "clamped | pinned | free");
    expect_scene_error(dir, "[ends]\ntip_slide = 1 0 0\n", "a free tip that slides", "s.ini:9:",
                       "the tip is free");
    expect_scene_error(dir, "[ends]\ntip = clamped\ntip_slide = 0 1 0\n",
                       "a clamped tip sliding across", "s.ini:10:", "along the slide");
    expect_scene_error(dir, "[ends]\ntip = clamped\ntip_twist = held\n",
                       "a held twist without a slide", "s.ini:10:", "on a slide");
    expect_scene_error(dir, "[ends]\ntip = pinned\ntip_slide = 1 0 0\ntip_twist = held\n",
                       "a held twist on a pinned tip", "s.ini:11:", "clamped tip on a slide");
    expect_scene_error(dir, "[ends]\ntip = clamped\ntip_slide = 1 0 0\ntip_twist = fixed\n",
                       "a bad twist word", "s.ini:11:", "free | held");
    expect_scene_error(dir, "[ends]\nneedle = -1\n", "negative needle", "s.ini:9:", ">= 0");
    expect_scene_error(dir, "[point_load]\ns = 1.5\n", "point load beyond the tip", "s.ini:9:",
                       "from 0 to the length");
    expect_scene_error(dir, "[point_load]\nforce = 0 0 1\n", "point load without s", "s.ini:8:",
                       "missing; required");
    expect_scene_error(dir, "[point_load]\ns = 0.5\n[point_load]\nforce = 1 0\n",
                       "second point load's force", "s.ini:11:", "[point_load #2] force");
    expect_scene_error(dir, "[loads]\ndistributed_moment = 0 1\n", "distributed moment",
                       "s.ini:9:", "distributed_moment");
    expect_scene_error(dir, "curvature = 0 nan 0\n", "curvature not a number", "s.ini:8:",
                       "curvature");
    const char *names[] = {"arc.csv", "lift.csv", "s.ini"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        unlink(path);
    }
    rmdir(dir);
}

/* A direction of extreme length keeps its direction: its length would
 * overflow (1e308 1e308 0) or underflow (1e-170 0 0) if squared as given. */
static void test_extreme_direction(void)
{
    static const struct { const char *value; double x, y; } cases[] = {
        {"1e308 1e308 0", M_SQRT1_2, M_SQRT1_2}, {"1e-170 0 0", 1.0, 0.0}, {"0 -3e200 0", 0.0, -1.0}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        char text[2048], err[1024] = "", set[96];
        snprintf(text, sizeof text, "%s", valid_rod);
        snprintf(set, sizeof set, "rod.direction=%s", cases[k].value);
        ini_doc *doc = ini_parse("direction.ini", text, err, sizeof err);
        rod_model m;
        int ok = doc && ini_set(doc, set, err, sizeof err) == 0 &&
                 scene_read_rod(doc, &m, err, sizeof err) == 0;
        ini_destroy(doc);
        check(ok && fabs(m.direction[0] - cases[k].x) < 1e-15 &&
                  fabs(m.direction[1] - cases[k].y) < 1e-15 && m.direction[2] == 0.0,
              "direction = %s reads as (%.17g, %.17g, %.17g), expected (%.17g, %.17g, 0) %s",
              cases[k].value, ok ? m.direction[0] : NAN, ok ? m.direction[1] : NAN,
              ok ? m.direction[2] : NAN, cases[k].x, cases[k].y, err);
        if (ok) rod_model_release(&m);
    }
}

/* A clamped sliding tip whose start is off its slide by rounding (5e-4 rad)
 * gets the slide turned onto its tangent, reported; 1e-2 rad is refused. */
static void test_slide_alignment(void)
{
    char text[2048], err[1024] = "";
    snprintf(text, sizeof text, "%s[ends]\ntip = clamped\ntip_slide = 1 0.0005 0\n", valid_rod);
    ini_doc *doc = ini_parse("slide.ini", text, err, sizeof err);
    rod_model m;
    int ok = doc && scene_read_rod(doc, &m, err, sizeof err) == 0;
    ini_destroy(doc);
    check(ok && m.tip_slide[0] == 1.0 && m.tip_slide[1] == 0.0 &&
              strstr(m.adjusted, "tip_slide: turned by 0.0005 rad") != NULL,
          "tip_slide 5e-4 rad off the straight tip: turned onto it (%g %g %g), reported '%s' %s",
          ok ? m.tip_slide[0] : NAN, ok ? m.tip_slide[1] : NAN, ok ? m.tip_slide[2] : NAN,
          ok ? m.adjusted : "", err);
    if (ok) rod_model_release(&m);
    snprintf(text, sizeof text, "%s[ends]\ntip = clamped\ntip_slide = 1 0.01 0\n", valid_rod);
    doc = ini_parse("slide.ini", text, err, sizeof err);
    ok = doc && scene_read_rod(doc, &m, err, sizeof err) == 0;
    ini_destroy(doc);
    check(!ok && strstr(err, "keeps its tangent d3 along the slide") != NULL,
          "tip_slide 1e-2 rad off: refused (%s)", err);
    if (ok) rod_model_release(&m);
}

int main(void)
{
    test_every_scene_parses();
    test_scene_values();
    test_set_overrides();
    test_bad_values();
    test_tables();
    test_frame_count();
    test_issue10_keys();
    test_self_intersecting_shape();
    test_extreme_direction();
    test_slide_alignment();
    return test_finish();
}
