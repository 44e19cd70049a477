/* test_ini.c: strict scene parsing. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/ini.h"
#include "test.h"

static void test_values(void)
{
    char err[512] = "";
    const char *text = "# comment\n[rod]\nlength = 1.5 # m\nnodes=51\n"
                       "[tip]\nforce = 0 4.5e-7 0\nframe = global\n"
                       "[load]\nnode = 2\n[load]\nnode = 5\n";
    ini_doc *doc = ini_parse("t.ini", text, err, sizeof err);
    check(doc != NULL, "parses a valid scene (%s)", err);
    if (!doc) return;
    double length = 0, force[3] = {0};
    int nodes = 0, frame = -1, node2 = 0;
    static const char *const frames[] = {"director", "global", NULL};
    check(ini_get_double(doc, "rod", 0, "length", &length, err, sizeof err) == 1 && length == 1.5,
          "double value with trailing comment: %g", length);
    check(ini_get_int(doc, "rod", 0, "nodes", &nodes, err, sizeof err) == 1 && nodes == 51,
          "int value: %d", nodes);
    check(ini_get_vector(doc, "tip", 0, "force", force, 3, err, sizeof err) == 1 &&
              force[1] == 4.5e-7,
          "vector value: %g %g %g", force[0], force[1], force[2]);
    check(ini_get_choice(doc, "tip", 0, "frame", frames, &frame, err, sizeof err) == 1 &&
              frame == 1,
          "choice value: %d", frame);
    check(ini_section_count(doc, "load") == 2, "repeated section counted twice");
    ini_get_int(doc, "load", 0, "node", &node2, err, sizeof err);
    ini_get_int(doc, "load", 1, "node", &node2, err, sizeof err);
    check(node2 == 5, "second instance of a repeated section: node %d", node2);
    double absent = 7;
    check(ini_get_double(doc, "rod", 0, "density", &absent, err, sizeof err) == 0 && absent == 7,
          "absent key returns 0 and leaves the value");
    check(ini_check_unused(doc, err, sizeof err) == 0, "all keys used: no error (%s)", err);
    check(ini_set(doc, "rod.length=2", err, sizeof err) == 0 &&
              ini_get_double(doc, "rod", 0, "length", &length, err, sizeof err) == 1 &&
              length == 2.0,
          "--set overrides a value: %g", length);
    ini_destroy(doc);
}

static void expect_error(const char *text, const char *needle, const char *what)
{
    char err[512] = "";
    ini_doc *doc = ini_parse("bad.ini", text, err, sizeof err);
    if (doc) {
        double x;
        int n;
        double v[3];
        static const char *const frames[] = {"director", "global", NULL};
        if (ini_get_double(doc, "rod", 0, "length", &x, err, sizeof err) >= 0 &&
            ini_get_int(doc, "rod", 0, "nodes", &n, err, sizeof err) >= 0 &&
            ini_get_vector(doc, "tip", 0, "force", v, 3, err, sizeof err) >= 0 &&
            ini_get_choice(doc, "tip", 0, "frame", frames, &n, err, sizeof err) >= 0)
            ini_check_unused(doc, err, sizeof err);
        ini_destroy(doc);
    }
    check(strstr(err, needle) != NULL, "%s: message '%s' contains '%s'", what, err, needle);
}

static void test_errors(void)
{
    expect_error("[rod]\nlength = 1\nlenght = 2\n", "bad.ini:3: [rod] lenght: unknown key",
                 "unknown key names file:line");
    expect_error("[rod]\nlength = 1\nlenght = 2\n", "accepted keys in [rod]: length, nodes",
                 "unknown key lists accepted keys");
    expect_error("[rodd]\nlength = 1\n", "bad.ini:1: unknown section [rodd]", "unknown section");
    expect_error("[rod]\nlength = 1.0.0\n", "bad.ini:2: [rod] length = 1.0.0: not a number",
                 "malformed number");
    expect_error("[rod]\nnodes = 5.5\n", "bad.ini:2: [rod] nodes = 5.5: not a whole number",
                 "malformed integer");
    expect_error("[tip]\nforce = 0 1\n", "bad.ini:2: [tip] force = 0 1: expected 3 numbers",
                 "short vector");
    expect_error("[tip]\nframe = local\n", "accepted: director | global", "bad choice");
    expect_error("length = 1\n[rod]\n", "bad.ini:1: key outside any section: length comes before "
                 "the first [section] line; accepted before it: only blank lines and # comments",
                 "a key before any section: named, and what may come before a section");
    expect_error("[rod]\nlength = 1\n[tip]\nframe = global\n[rod]\nnodes = 3\n",
                 "bad.ini:5: [rod] is given again (first on line 1); accepted: one [rod] section",
                 "a section read once, given twice: named at its second line");
    expect_error("[rod]\nlength = 1\nlength = 2\n", "given twice", "duplicate key");
    expect_error("[rod]\nlength\n", "bad.ini:2: expected 'key = value'", "line without =");
    expect_error("[rod]\nlength = nan\n", "not a number", "nan is refused");
    char err[256];
    check(ini_load("/nonexistent/scene.ini", err, sizeof err) == NULL &&
              strstr(err, "/nonexistent/scene.ini: cannot open") != NULL,
          "missing file: '%s'", err);
    /* "rodsim run my_rod" where my_rod.ini is: the message names it */
    const char *with_ini = test_path("my_rod.ini");
    FILE *f = fopen(with_ini, "w");
    if (f) {
        fputs("[rod]\nlength = 1\n", f);
        fclose(f);
    }
    char bare[256], want[700];
    snprintf(bare, sizeof bare, "%.*s", (int)(strlen(with_ini) - 4), with_ini);
    snprintf(want, sizeof want, "%s: cannot open the scene file: No such file or directory; "
             "did you mean %s?", bare, with_ini);
    check(f && ini_load(bare, err, sizeof err) == NULL && strcmp(err, want) == 0,
          "the name without .ini: '%s' (want '%s')", err, want);
    check(ini_load("/nonexistent/scene", err, sizeof err) == NULL && !strstr(err, "did you mean"),
          "no .ini beside it, no suggestion: '%s'", err);
}

/* A UTF-8 byte-order mark before the first line is skipped; files that are
 * not scenes (a directory, a device that never ends, a file over the
 * limit) are refused before they are read. */
static void test_files(void)
{
    char err[512] = "";
    ini_doc *doc = ini_parse("bom.ini", "\xEF\xBB\xBF[rod]\nlength = 2\n", err, sizeof err);
    double length = 0.0;
    int read = doc && ini_get_double(doc, "rod", 0, "length", &length, err, sizeof err) == 1 &&
               ini_check_unused(doc, err, sizeof err) == 0;
    check(read && length == 2.0,
          "a byte-order mark before [rod] is skipped: length = %g (%s)", length, err);
    ini_destroy(doc);
    check(ini_load("/dev/zero", err, sizeof err) == NULL &&
              strstr(err, "/dev/zero: a character device, not a scene file") &&
              strstr(err, "at most 1 MiB"),
          "/dev/zero as the scene: refused unread: '%s'", err);
    check(ini_load("/tmp", err, sizeof err) == NULL &&
              strstr(err, "/tmp: a directory, not a scene file"),
          "a directory as the scene: '%s'", err);
    char path[] = "/tmp/rodsim_ini_XXXXXX";
    int fd = mkstemp(path);
    if (fd >= 0) {
        int grown = ftruncate(fd, (off_t)INI_MAX_BYTES + 1) == 0;
        close(fd);
        check(grown && ini_load(path, err, sizeof err) == NULL && strstr(err, path) &&
                  strstr(err, "1048577 bytes") && strstr(err, "at most 1 MiB (1048576 bytes)"),
              "a scene one byte over 1 MiB: '%s'", err);
        unlink(path);
    }
}

/* Edit distances counted by hand; a key table checked before any read. */
static void test_key_table(void)
{
    static const struct { const char *a, *b; int d; } pairs[] = {
        {"densty", "density", 1},   /* one deletion */
        {"lenght", "length", 1},    /* one swap of neighbours */
        {"kitten", "sitting", 3},   /* k->s, e->i, +g */
        {"", "abc", 3}, {"node", "node", 0}, {"ca", "abc", 3},
    };
    for (size_t i = 0; i < sizeof pairs / sizeof pairs[0]; i++)
        check(ini_edit_distance(pairs[i].a, pairs[i].b) == pairs[i].d,
              "edit distance '%s' -> '%s' = %d (by hand %d)", pairs[i].a, pairs[i].b,
              ini_edit_distance(pairs[i].a, pairs[i].b), pairs[i].d);
    static const ini_key table[] = {
        {"rod", "length", "m", "required", "> 0", ""},
        {"rod", "density", "kg/m^3", "required", "> 0", ""},
        {"tip", "force", "N", "0 0 0", "3 numbers", ""},
        {NULL, NULL, NULL, NULL, NULL, NULL},
    };
    char err[512] = "";
    ini_doc *doc = ini_parse("k.ini", "[rod]\nlength = 1\n[tip]\nforce = 0 0 0\n", err, sizeof err);
    check(doc && ini_check_keys(doc, table, err, sizeof err) == 0, "known keys pass (%s)", err);
    check(doc && ini_set(doc, "rod.densty=3", err, sizeof err) == 0 &&
              ini_check_keys(doc, table, err, sizeof err) < 0 &&
              strstr(err, "--set rod.densty=3: unknown key; did you mean rod.density? "
                          "accepted keys in [rod]: length, density"),
          "--set of a misspelt key: '%s'", err);
    ini_destroy(doc);
    doc = ini_parse("k.ini", "[rod]\nlength = 1\ndensity = x\n[tipp]\nforce = 1\n", err, sizeof err);
    check(doc && ini_check_keys(doc, table, err, sizeof err) < 0 &&
              strstr(err, "k.ini:4: unknown section [tipp]; did you mean [tip]? accepted "
                          "sections: rod, tip"),
          "misspelt section at its line: '%s'", err);
    ini_destroy(doc);

    /* a unit after a number: refused at its line, the value converted by hand */
    static const struct { const char *text, *needle; } units[] = {
        {"[rod]\nlength = 50 cm\n", "k.ini:2: [rod] length = 50 cm: a unit after the number "
                                    "('cm'); a scene's values are bare numbers in the key's "
                                    "unit: write 0.5 (m)"},
        {"[rod]\nlength = 0.5mm\n", "length = 0.5mm: a unit after the number ('mm'); "},
        {"[rod]\nlength = 0.5mm\n", "write 0.0005 (m)"},
        {"[rod]\ndensity = 1.14 g/cm^3\n", "write 1140 (kg/m^3)"},
        {"[tip]\nforce = 0 -10 0 uN\n", "a unit after the numbers ('uN'); a scene's values are "
                                        "bare numbers in the key's unit: write 0 -1e-05 0 (N)"},
        {"[rod]\nlength = 2 furlongs\n", "('furlongs'); a scene's values are bare numbers in the "
                                         "key's unit: write the number in m, without a unit"},
        {"[rod]\nlength = 1 m\ndensity = 2 kg\n", "k.ini:2: [rod] length = 1 m: a unit"},
    };
    for (size_t i = 0; i < sizeof units / sizeof units[0]; i++) {
        doc = ini_parse("k.ini", units[i].text, err, sizeof err);
        check(doc && ini_check_keys(doc, table, err, sizeof err) < 0 &&
                  strstr(err, units[i].needle),
              "a unit after the number, '%s': '%s' contains '%s'", units[i].text, err,
              units[i].needle);
        ini_destroy(doc);
    }
    doc = ini_parse("k.ini", "[rod]\nlength = 1\n", err, sizeof err);
    check(doc && ini_set(doc, "rod.length=3 mm", err, sizeof err) == 0 &&
              ini_check_keys(doc, table, err, sizeof err) < 0 &&
              strstr(err, "--set rod.length=3 mm: a unit after the number ('mm'); a scene's "
                          "values are bare numbers in the key's unit: write 0.003 (m)"),
          "--set of a value with a unit: '%s'", err);
    ini_destroy(doc);
    /* not units: a cut exponent, a non-finite number, plain numbers */
    static const char *const plain[] = {"[rod]\nlength = 5e\n", "[tip]\nforce = 0 0 inf\n",
                                        "[rod]\nlength = 1e-3\ndensity = +2.5E+3\n"};
    for (size_t i = 0; i < sizeof plain / sizeof plain[0]; i++) {
        doc = ini_parse("k.ini", plain[i], err, sizeof err);
        err[0] = '\0';
        check(doc && ini_check_keys(doc, table, err, sizeof err) == 0,
              "'%s' is not a number with a unit (left to the value's reader): '%s'", plain[i],
              err);
        ini_destroy(doc);
    }
}

/* [variant NAME]: a named set of --set assignments, applied by
 * --set variant=NAME in file order; the file's values stand without it. */
static void test_variants(void)
{
    const char *text = "[rod]\nlength = 1\n[tip]\nforce = 0 0 0\n"
                       "[variant long]   # a variant\nrod.length = 3\ntip.force = 1 2 3\n"
                       "[variant bad]\nrod.length = x\n";
    char err[512] = "";
    double length = 0, force[3] = {0};
    ini_doc *doc = ini_parse("v.ini", text, err, sizeof err);
    int ok = doc && ini_get_double(doc, "rod", 0, "length", &length, err, sizeof err) == 1 &&
             ini_get_vector(doc, "tip", 0, "force", force, 3, err, sizeof err) == 1 &&
             ini_check_unused(doc, err, sizeof err) == 0;
    check(ok && length == 1.0, "a scene with variants, none chosen: the file's length %g (1), "
          "its variants not unused keys (%s)", length, err);
    ini_destroy(doc);
    doc = ini_parse("v.ini", text, err, sizeof err);
    ok = doc && ini_set(doc, "variant=long", err, sizeof err) == 0 &&
         ini_get_double(doc, "rod", 0, "length", &length, err, sizeof err) == 1 &&
         ini_get_vector(doc, "tip", 0, "force", force, 3, err, sizeof err) == 1 &&
         ini_check_unused(doc, err, sizeof err) == 0;
    check(ok && length == 3.0 && force[0] == 1.0 && force[1] == 2.0 && force[2] == 3.0,
          "--set variant=long: length %g (3), force %g %g %g (1 2 3) (%s)", length, force[0],
          force[1], force[2], err);
    ini_destroy(doc);
    doc = ini_parse("v.ini", text, err, sizeof err);
    ok = doc && ini_set(doc, "variant=long", err, sizeof err) == 0 &&
         ini_set(doc, "rod.length=5", err, sizeof err) == 0 &&
         ini_get_double(doc, "rod", 0, "length", &length, err, sizeof err) == 1;
    check(ok && length == 5.0, "a --set after the variant's overrides it: length %g (5)", length);
    check(doc && ini_set(doc, "variant=lon", err, sizeof err) < 0 &&
              strstr(err, "--set variant=lon: v.ini has no [variant lon]; accepted: long, bad"),
          "an unknown variant named with those accepted: '%s'", err);
    check(doc && ini_set(doc, "variant=bad", err, sizeof err) == 0 &&
              ini_get_double(doc, "rod", 0, "length", &length, err, sizeof err) < 0 &&
              strstr(err, "v.ini:9: [rod] length = x: not a number"),
          "a variant's bad value reported at the variant's line: '%s'", err);
    ini_destroy(doc);
    expect_error("[rod]\nlength = 1\n[variant a]\nlength = 2\n",
                 "bad.ini:4: [variant a]: bad key 'length'; accepted: section.key = value",
                 "a variant's key without its section");
    expect_error("[rod]\nlength = 1\n[variant]\nrod.length = 2\n",
                 "bad.ini:3: [variant] needs a name: [variant NAME]", "a variant without a name");
    static const ini_key table[] = {
        {"rod", "length", "m", "required", "> 0", ""},
        {NULL, NULL, NULL, NULL, NULL, NULL},
    };
    doc = ini_parse("v.ini", "[rod]\nlength = 1\n[variant a]\nrod.lenth = 2\n", err, sizeof err);
    check(doc && ini_check_keys(doc, table, err, sizeof err) == 0 &&
              ini_set(doc, "variant=a", err, sizeof err) == 0 &&
              ini_check_keys(doc, table, err, sizeof err) < 0 &&
              strstr(err, "v.ini:4: [rod] lenth: unknown key"),
          "a variant's misspelt key reported at its line when chosen, not before: '%s'", err);
    ini_destroy(doc);
    doc = ini_parse("v.ini", "[rod]\nlength = 1\n", err, sizeof err);
    check(doc && ini_set(doc, "variant=a", err, sizeof err) < 0 &&
              strstr(err, "v.ini has no [variant a]; accepted: none"),
          "a variant asked of a scene with none: '%s'", err);
    ini_destroy(doc);
}

int main(void)
{
    test_values();
    test_errors();
    test_files();
    test_key_table();
    test_variants();
    return test_finish();
}
