/* test_summary_fields.c: every field `rodsim run --summary` writes is in the
 * field table of docs/commands.md, for a scene of one rod and one of two
 * named rods (crossing.ini, 0.02 s): each top-level key as "| `KEY`", each
 * rod's key as "| `rods[].KEY" (ends: `rods[].ends.root`, `.tip`). And the
 * rods' names are the scene's: `[rod lower]`, `[rod upper]`. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "json.h"
#include "test.h"
#include "test_process.h"

#define COMMANDS_DOC RODSIM_SOURCE_DIR "/docs/commands.md"

static char doc[200000]; /* docs/commands.md: about 30 KB */

static int documented(const char *prefix, const char *key)
{
    char row[160];
    snprintf(row, sizeof row, "| `%s%s", prefix, key);
    size_t n = strlen(row);
    /* the field's own row ("| `rods[].tip`") or its parts' ("| `rods[].ends.root`") */
    for (const char *at = strstr(doc, row); at; at = strstr(at + 1, row))
        if (at[n] == '`' || at[n] == '.') return 1;
    return 0;
}

/* Runs the scene briefly with --summary, parses it; NULL on failure. */
static json_value *summary_of(const char *scene, const char *dir)
{
    char path[160], output[8192], err[256];
    snprintf(path, sizeof path, "%s/summary.json", dir);
    const char *args[] = {"run", scene, "--no-video", "--quiet", "--set",
                          "solver.duration=0.02", "--summary", path, NULL};
    int status = test_run_rodsim(args, output, sizeof output);
    FILE *f = fopen(path, "rb");
    static char text[1 << 20];
    size_t got = f ? fread(text, 1, sizeof text - 1, f) : 0;
    text[got] = '\0';
    if (f) fclose(f);
    unlink(path);
    json_value *v = json_parse(text, err, sizeof err);
    check(status == 0 && v, "%s: exit %d, summary parsed (%s)", scene, status, v ? "yes" : err);
    return v;
}

static void check_fields(const char *what, const json_value *v)
{
    int keys = 0, missing = 0;
    for (int i = 0; i < v->count; i++, keys++)
        if (!documented("", v->keys[i])) {
            missing++;
            check(0, "%s: field '%s' is not in docs/commands.md", what, v->keys[i]);
        }
    const json_value *rods = json_get(v, "rods");
    for (int r = 0; rods && r < rods->count; r++)
        for (int i = 0; i < rods->items[r]->count; i++, keys++)
            if (!documented("rods[].", rods->items[r]->keys[i])) {
                missing++;
                check(0, "%s: field 'rods[].%s' is not in docs/commands.md", what,
                      rods->items[r]->keys[i]);
            }
    check(keys > 10 && missing == 0, "%s: %d fields written, %d not in docs/commands.md", what,
          keys, missing);
}

int main(void)
{
    FILE *f = fopen(COMMANDS_DOC, "rb");
    size_t got = f ? fread(doc, 1, sizeof doc - 1, f) : 0;
    doc[got] = '\0';
    if (f) fclose(f);
    if (!check(got > 1000, "docs/commands.md reads (%zu bytes)", got)) return test_finish();
    char dir[] = "/tmp/rodsim_summary_fields_XXXXXX";
    if (!check(mkdtemp(dir) != NULL, "scratch directory")) return test_finish();

    json_value *one = summary_of(RODSIM_SOURCE_DIR "/scenes/table2_450nN.ini", dir);
    if (one) check_fields("table2_450nN.ini (one rod)", one);
    json_free(one);

    json_value *two = summary_of(RODSIM_SOURCE_DIR "/scenes/crossing.ini", dir);
    if (two) {
        check_fields("crossing.ini (two rods)", two);
        const json_value *rods = json_get(two, "rods");
        const json_value *na = rods && rods->count == 2 ? json_get(rods->items[0], "name") : NULL;
        const json_value *nb = rods && rods->count == 2 ? json_get(rods->items[1], "name") : NULL;
        const char *a = json_is(na, JSON_STRING) ? na->string : "";
        const char *b = json_is(nb, JSON_STRING) ? nb->string : "";
        check(strcmp(a, "lower") == 0 && strcmp(b, "upper") == 0,
              "crossing.ini's rods are named by their sections: '%s', '%s' (want lower, upper)",
              a, b);
    }
    json_free(two);
    test_remove_tree(dir);
    return test_finish();
}
