/* run_cli.c: `rodsim run` (see run_cli.h): the options, the scene with its
 * --set overrides, then scene_outputs.h. */
#include "cli/run_cli.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "base/ini.h"
#include "cli/args.h"
#include "cli/live.h"
#include "cli/render_cli.h"
#include "cli/scene_outputs.h"
#include "sim/rod.h"

#define RUN_ERR_LEN 1024

void run_usage(FILE *f)
{
    fprintf(f,
            "usage: rodsim run SCENE [--set section.key=value]... [-o DIR] [--csv FILE]\n"
            "                        [--no-video] [--allow-long] [--quiet]\n"
            "\n"
            "Simulates the rod scene SCENE (an INI file; its keys: rodsim help scene).\n"
            "  --set section.key=value  override a scene key (repeatable, applied in order),\n"
            "                           e.g. --set solver.scheme=thesis --set tip.force=\"0 8e-7 0\"\n"
            "  -o DIR                   directory for the video (default out/)\n"
            "  --csv FILE               write the centreline at every output frame:\n"
            "                           t,node,s,x,y,z,d3x,d3y,d3z,twist (s, m, 1/m);\n"
            "                           --csv - writes it to standard output\n"
            "  --no-video               do not render the video\n"
            "  --allow-long             run even when the estimated time is over 1 hour\n"
            "  --quiet                  print only errors\n"
            "The outputs (CSV, video, poster) appear together when the run succeeds, and\n"
            "none otherwise. Exit status: 0 success; 2 bad scene, bad usage, a run refused up\n"
            "front or stopped (too long, too large) or numerically unstable (nothing is\n"
            "written then); 1 any other failure; 130 SIGINT, 143 SIGTERM.\n");
}

/* 1 when the file starts as a `rodsim live --record` record does. Only a
 * regular file is looked into: a pipe would lose what was peeked (the scene
 * read next would start 4 KiB in), and a record is read twice anyway. */
static int is_live_record(const char *path)
{
    char head[sizeof LIVE_RECORD_MAGIC] = "";
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISREG(st.st_mode)) return 0;
    FILE *f = fopen(path, "rb");
    size_t got = f ? fread(head, 1, sizeof head - 1, f) : 0;
    if (f) fclose(f);
    return got == sizeof head - 1 && memcmp(head, LIVE_RECORD_MAGIC, got) == 0;
}

/* The scene with its overrides, then its outputs. Returns an exit status. */
static int run_scene(const scene_outputs_options *o, const cli_list *sets)
{
    char err[RUN_ERR_LEN] = "";
    int status = RUN_EXIT_BAD_INPUT;
    rod_model m = rod_model_default();
    run_output out;
    char scene[128];
    ini_doc *doc = ini_load(o->label, err, sizeof err);
    if (!doc) goto fail;
    for (int i = 0; i < sets->count; i++)
        if (ini_set(doc, sets->items[i], err, sizeof err)) goto fail;
    if (run_read_scene(doc, &m, &out, err, sizeof err)) goto fail;
    ini_scene_name(doc, scene, sizeof scene);
    status = scene_outputs_write(o, scene, &m, &out);
    goto done;
fail:
    fprintf(stderr, "rodsim run: %s\n", err);
done:
    rod_model_release(&m);
    ini_destroy(doc);
    return status;
}

int run_command(int argc, char **argv)
{
    char err[RUN_ERR_LEN] = "";
    scene_outputs_options o = {.out_dir = "out"};
    cli_list sets = {0};
    const cli_option options[] = {
        {.name = "--set", .value = CLI_SETTING, .target = &sets, .repeated = 1},
        {.name = "-o", .value = CLI_DIR, .target = &o.out_dir},
        {.name = "--csv", .value = CLI_OUTPUT, .target = &o.csv},
        {.name = "--no-video", .value = CLI_FLAG, .target = &o.no_video},
        {.name = "--allow-long", .value = CLI_FLAG, .target = &o.allow_long},
        {.name = "--quiet", .alias = "-q", .value = CLI_FLAG, .target = &o.quiet},
        {0}};
    const cli_operand scene = {.name = "SCENE", .target = &o.label};
    int parsed = cli_parse(argc, argv, options, &scene, err, sizeof err);
    int status;
    if (parsed == CLI_HELP) {
        run_usage(stdout);
        status = RUN_EXIT_OK;
    } else if (parsed != CLI_PARSED) {
        status = cli_usage_error("run", err);
    } else if (is_live_record(o.label)) { /* `run` on a recording: its video */
        status = render_command(argc, argv);
    } else if (scene_outputs_check(&o, err, sizeof err)) {
        fprintf(stderr, "rodsim run: %s\n", err);
        status = RUN_EXIT_BAD_INPUT;
    } else {
        status = run_scene(&o, &sets);
    }
    cli_release(options);
    return status;
}
