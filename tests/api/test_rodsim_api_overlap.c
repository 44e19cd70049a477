/* test_rodsim_api_overlap.c: the library (rodsim.h) refuses a scene whose
 * instruments' paths take one through another, as `rodsim run` does and in
 * its words, and loads it with may_overlap = yes. Two straight 12 cm forceps
 * crossing at right angles 3 mm apart (test_instrument_overlap_run's
 * geometry): their shanks overlap by 2 r_jaw + 2 r_shank - h = 2.28 mm, by
 * hand. A scene of two named rods beside them: the same. Forceps driven 4
 * mm into a rigid pad (test_rods_instruments' scene: the open tines' round
 * ends 4.87 mm deep, over max_depth, 2 jaw radii = 2.40 mm): refused by
 * the library as by `rodsim run`, in its words, one rod and a named one;
 * loaded and run with max_depth = 6 mm. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "rodsim.h"
#include "test.h"
#include "test_process.h"

#define R_JAW 0.0012   /* m, 12 cm forceps' jaw (0.010 x size) */
#define R_SHANK 0.00144 /* m, their shank (0.012 x size) */

static char dir[64];

/* The lower forceps along x, tip at the origin; the upper a quarter turn
 * about z, tip at (-0.05, 0.05, 0.003); a thread (rods: two named) far
 * from both on a table */
static void write_scene(const char *name, int rods)
{
    test_write_in(dir, "lower.csv", "t,x,y,z,rx,ry,rz,jaw\n0,0,0,0,0,0,0,0\n1,0,0,0,0,0,0,0\n");
    test_write_in(dir, "upper.csv",
                  "t,x,y,z,rx,ry,rz,jaw\n0,-0.05,0.05,0.003,0,0,1.5707963267948966,0\n"
                  "1,-0.05,0.05,0.003,0,0,1.5707963267948966,0\n");
    const char *rod = "length = 0.05\ndiameter = 0.0005\ndensity = 850\n"
                      "youngs_modulus = 87.5e6\nshear_modulus = 31.25e6\nnodes = 11\n"
                      "direction = 1 0 0\n";
    char text[4096];
    if (rods)
        snprintf(text, sizeof text, "[rod a]\n%sorigin = 0 0.2 -0.00975\n[ends a]\nroot = "
                 "free\ntip = free\n[rod b]\n%sorigin = 0 0.3 -0.00975\n[ends b]\nroot = free\n"
                 "tip = free\n", rod, rod);
    else
        snprintf(text, sizeof text,
                 "[rod]\nlength = 0.05\ndiameter = 0.0005\ndensity = 850\n"
                 "youngs_modulus = 87.5e6\nshear_modulus = 31.25e6\nnodes = 11\n"
                 "origin = 0 0.2 -0.00975\ndirection = 1 0 0\n[ends]\nroot = free\ntip = free\n");
    snprintf(text + strlen(text), sizeof text - strlen(text),
             "[surface]\nshape = plane\ncenter = 0 0 -0.01\nnormal = 0 0 1\n"
             "[instrument]\nkind = forceps\nname = lower\npath = lower.csv\nsize = 0.12\n"
             "[instrument]\nkind = forceps\nname = upper\npath = upper.csv\nsize = 0.12\n"
             "[solver]\nscheme = implicit\ndt = 0.001\nduration = 0.01\n"
             "[loads]\ngravity = 0 0 -9.81\n");
    test_write_in(dir, name, text);
}

/* The scene at path through `rodsim run` (its exit status, its output in
 * output) and rodsim_load_file (*st, *sc); expected gets the run's line
 * for the library's message: "rodsim run: " and rodsim_last_error(). */
static int run_and_load(const char *path, char *output, size_t output_size, char *expected,
                        size_t expected_size, rodsim_status *st, rodsim_scene **sc)
{
    const char *args[] = {"run", path, "--no-video", "--quiet", NULL};
    const int status = test_run_rodsim(args, output, output_size);
    *st = rodsim_load_file(path, NULL, 0, sc);
    snprintf(expected, expected_size, "rodsim run: %s\n", rodsim_last_error(NULL));
    return status;
}

static void test_refused(const char *name, int rods)
{
    char path[160], output[8192], expected[2048], want[128];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    write_scene(name, rods);
    rodsim_scene *sc = NULL;
    rodsim_status st;
    const int status = run_and_load(path, output, sizeof output, expected, sizeof expected,
                                    &st, &sc);
    snprintf(want, sizeof want, "the forceps' shank and the forceps' shank overlap by %.2f mm "
             "at t = 0.000 s", 1e3 * (2.0 * R_JAW + 2.0 * R_SHANK - 0.003));
    check(status == 2 && st == RODSIM_BAD_INPUT && !sc && strstr(output, expected) &&
              strstr(expected, want) && strstr(expected, "[instrument] lower and upper"),
          "%s: rodsim run refuses it (exit %d) and rodsim_load_file (status %d, 1) says the same "
          "after \"rodsim run: \", with '%s': %s", rods ? "two named rods" : "one rod", status,
          (int)st, want, rodsim_last_error(NULL));
    const char *sets[] = {"instrument.upper.may_overlap=yes"};
    st = rodsim_load_file(path, sets, 1, &sc);
    check(st == RODSIM_OK && sc && rodsim_run(sc, -1.0) == RODSIM_OK,
          "%s, may_overlap = yes: loaded and run to its duration (%s)",
          rods ? "two named rods" : "one rod", st ? rodsim_last_error(NULL) : "ok");
    rodsim_free(sc);
}

/* A thread on a rigid pad (top at z = 0), forceps pointing down driven
 * to 4 mm under its top by t = 0.5 s; rod: "" or " thread" (named) */
static void write_pad_scene(const char *name, const char *rod)
{
    const char *rv = "1.2091996,1.2091996,-1.2091996";
    char text[1024];
    snprintf(text, sizeof text, "t,x,y,z,rx,ry,rz,jaw\n0,0,0,0.03,%s,1\n0.5,0,0,-0.004,%s,1\n",
             rv, rv);
    test_write_in(dir, "deep.csv", text);
    snprintf(text, sizeof text,
             "[rod%s]\nlength = 0.1\ndiameter = 0.0005\ndensity = 850\n"
             "youngs_modulus = 87.5e6\nshear_modulus = 31.25e6\nnodes = 11\n"
             "origin = -0.05 0.02 0.00025\ndirection = 1 0 0\n[surface]\nshape = box\n"
             "center = 0 0 -0.005\nsize = 0.2 0.2 0.01\n[instrument]\nkind = forceps\n"
             "path = deep.csv\nsize = 0.12\n[solver]\nscheme = implicit\nduration = 0.6\n"
             "[loads]\ngravity = 0 0 -9.81\n", rod);
    test_write_in(dir, name, text);
}

static void test_jaws_refused(const char *name, const char *rod)
{
    char path[160], output[8192], expected[2048];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    write_pad_scene(name, rod);
    rodsim_scene *sc = NULL;
    rodsim_status st;
    const int status = run_and_load(path, output, sizeof output, expected, sizeof expected,
                                    &st, &sc);
    const char *who = rod[0] ? "a named rod" : "one rod";
    check(status == 2 && st == RODSIM_BAD_INPUT && !sc && strstr(output, expected) &&
              strstr(expected, "forceps' jaws 4.87 mm into the rigid") &&
              strstr(expected, "max_depth = 2.40 mm"),
          "jaws into a rigid pad, %s: rodsim run refuses it (exit %d) and rodsim_load_file "
          "(status %d, 1) says the same after \"rodsim run: \": %s", who, status, (int)st,
          rodsim_last_error(NULL));
    const char *sets[] = {"instrument.max_depth=0.006"};
    st = rodsim_load_file(path, sets, 1, &sc);
    check(st == RODSIM_OK && sc && rodsim_run(sc, -1.0) == RODSIM_OK,
          "jaws into a rigid pad, %s, max_depth = 6 mm: loaded and run to its duration (%s)",
          who, st ? rodsim_last_error(NULL) : "ok");
    rodsim_free(sc);
}

int main(void)
{
    snprintf(dir, sizeof dir, "%s", test_dir());
    test_refused("through.ini", 0);
    test_refused("rods.ini", 1);
    test_jaws_refused("pad.ini", "");
    test_jaws_refused("pad_rods.ini", " thread");
    return test_finish();
}
