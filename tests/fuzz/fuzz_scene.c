/* fuzz_scene.c: libFuzzer harness for rod scenes, the path of `rodsim run`
 * up to the simulation: ini_parse (base/ini.c) -> scene_read_rod
 * (sim/scene.c, with rod_model_derive) -> run_read_output ([render]) ->
 * ini_check_unused.
 *
 * Every '/' of the input becomes '_', so `profile = table NAME` can only
 * open files in the harness' folder (where two valid tables wait); an
 * absolute path could name a FIFO that waits for a writer (a device is
 * refused unread, base/textfile.c). */
#include <math.h>

#include "base/ini.h"
#include "cli/scene_outputs.h"
#include "fuzz.h"
#include "sim/rod.h"
#include "sim/scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerInitialize(int *argc, char ***argv);

static char scene_path[600];

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    const char *dir = fuzz_dir();
    static const char *const tables[][2] = {
        {"f.csv", "t,factor\n0,0\n0.5,1\n1,0.25\n"},
        {"l.csv", "t,fx,fy,fz,mx,my,mz\n0,0,0,0,0,0,0\n1,0,1e-6,0,0,0,1e-9\n"},
    };
    for (size_t k = 0; k < sizeof tables / sizeof tables[0]; k++) {
        char path[700];
        snprintf(path, sizeof path, "%s/%s", dir, tables[k][0]);
        FILE *f = fopen(path, "w");
        if (!f || fputs(tables[k][1], f) < 0 || fclose(f) != 0) abort();
    }
    snprintf(scene_path, sizeof scene_path, "%s/fuzz.ini", dir);
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = fuzz_text(data, size);
    for (char *c = text; *c; c++)
        if (*c == '/') *c = '_';
    char err[1024] = "";
    ini_doc *doc = ini_parse(scene_path, text, err, sizeof err);
    if (!doc) {
        fuzz_require(fuzz_starts(err, scene_path), "an ini_parse message names the file", err);
        free(text);
        return 0;
    }
    rod_model m;
    if (scene_read_rod(doc, &m, err, sizeof err) != 0) {
        /* scene.h: the message names the file; on failure *m owns nothing */
        fuzz_require(fuzz_starts(err, scene_path), "a scene_read_rod message names the file", err);
        fuzz_require(m.profile.table.data == NULL, "a failed read owns no table", err);
    } else {
        fuzz_require(m.nodes >= 3 && isfinite(m.length) && m.length > 0, "a read model is valid",
                     NULL);
        double force[3], moment[3];
        rod_tip_load(&m, 0.5 * m.options.duration, force, moment);
        run_output out;
        err[0] = '\0';
        if (run_read_output(doc, &out, err, sizeof err) != 0 ||
            ini_check_unused(doc, err, sizeof err) != 0)
            fuzz_require(fuzz_starts(err, scene_path), "a [render] message names the file", err);
        rod_model_release(&m);
    }
    ini_destroy(doc);
    free(text);
    return 0;
}
