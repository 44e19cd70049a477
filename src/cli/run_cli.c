/* run_cli.c: `rodsim run` (see run_cli.h): the options, the scene with its
 * --set overrides, then scene_outputs.h. */
#include "cli/run_cli.h"

#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include "base/clocks.h"
#include "base/ini.h"
#include "base/outfile.h"
#include "cli/args.h"
#include "cli/live.h"
#include "cli/render_cli.h"
#include "api/scene_keys.h"
#include "cli/rods_run.h"
#include "cli/scene_outputs.h"
#include "cli/summary.h"
#include "sim/rod.h"
#include "sim/rod_set.h"

#define RUN_ERR_LEN 1024

void run_usage(FILE *f)
{
    fprintf(f,
            "usage: rodsim run SCENE [--set section.key=value]... [-o DIR] [--csv FILE]\n"
            "                        [--tissue-csv FILE] [--summary FILE] [--no-video]\n"
            "                        [--allow-long] [--progress] [--quiet]\n"
            "\n"
            "Simulates the rod scene SCENE (an INI file; its keys: rodsim help scene).\n"
            "  --set section.key=value  override a scene key (repeatable, applied in order),\n"
            "                           e.g. --set solver.scheme=thesis --set tip.force=\"0 8e-7 0\"\n"
            "  -o DIR                   directory for the video (default out/)\n"
            "  --csv FILE               write the centreline at every output frame:\n"
            "                           t,node,s,x,y,z,d3x,d3y,d3z,twist,nx,ny,nz (s, -, m,\n"
            "                           m, m, m, -, -, -, 1/m, N, N, N): nx,ny,nz is the\n"
            "                           internal force N(s), global; at a held end, the\n"
            "                           force between the rod and its support;\n"
            "                           --csv - writes it to standard output; a scene of\n"
            "                           several rods ([rod NAME]) adds the column rod (its\n"
            "                           name) after t\n"
            "  --tissue-csv FILE        write an elastic pad's top-face nodes at every\n"
            "                           output frame: t,node,x,y,z (s, -, m, m, m)\n"
            "  --summary FILE           write how the run ended as one JSON object (status,\n"
            "                           exit_code, message, warnings, counts, times, tip, end\n"
            "                           forces, knot, punctures, tissue; docs/commands.md),\n"
            "                           whatever the outcome; --summary - writes it to\n"
            "                           standard output (the prose then goes to standard\n"
            "                           error)\n"
            "  --no-video               do not render the video\n"
            "  --allow-long             run even when the estimated time is over 1 hour\n"
            "  --progress               show the progress line (simulated time, CPU s per\n"
            "                           simulated s, time left) on standard error; by\n"
            "                           default only on a terminal for a run over ~2 s\n"
            "  --quiet                  print only warnings and errors (no progress\n"
            "                           line unless --progress)\n"
            "The outputs (CSV, video, poster) appear together when the run succeeds, and\n"
            "none otherwise. Exit status: 0 success; 2 bad scene, bad usage, a run refused up\n"
            "front or stopped (too long, too large) or numerically unstable (nothing is\n"
            "written then); 1 any other failure; 130 SIGINT, 143 SIGTERM (the run ends at\n"
            "its next step, removes its outputs and writes its summary, status stopped; the\n"
            "same signal again, or one while the outputs are finished, stops at once).\n");
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
    ini_scene_name(doc, scene, sizeof scene);
    if (o->summary) snprintf(o->summary->scene, sizeof o->summary->scene, "%s", scene);
    for (int i = 0; i < sets->count; i++)
        if (ini_set(doc, sets->items[i], err, sizeof err)) goto fail;
    int named;
    if (scene_has_named_rods(doc, &named)) { /* several rods: their own run */
        status = rods_run_scene(o, doc, scene);
        goto done;
    }
    if (run_read_scene(doc, &m, &out, err, sizeof err)) goto fail;
    status = scene_outputs_write(o, scene, &m, &out);
    goto done;
fail:
    fprintf(stderr, "rodsim run: %s\n", err);
    if (o->summary) summary_set_message(o->summary, err);
done:
    rod_model_release(&m);
    ini_destroy(doc);
    return status;
}

/* s: the process's CPU so far, user + system */
static double cpu_used(void)
{
    struct rusage u;
    if (getrusage(RUSAGE_SELF, &u) != 0) return 0.0;
    return (double)(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
           1e-6 * (double)(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

/* An option that is not one of run's but names a scene key ("--fps 60",
 * "--self-contact=no"): the --set that says it. */
static void unknown_option_hint(int argc, char **argv, char *err, size_t errlen)
{
    const char *prefix = "unknown option '";
    if (strncmp(err, prefix, strlen(prefix)) != 0 || strstr(err, "did you mean")) return;
    int at = 0;
    for (int i = 1; i < argc && !at; i++)
        if (strncmp(err + strlen(prefix), argv[i], strlen(argv[i])) == 0 &&
            err[strlen(prefix) + strlen(argv[i])] == '\'')
            at = i;
    if (!at) return;
    const char *typed = argv[at] + strspn(argv[at], "-");
    char word[64];
    snprintf(word, sizeof word, "%.*s", (int)strcspn(typed, "="), typed);
    const char *value = typed[strlen(word)] == '=' ? typed + strlen(word) + 1
                        : at + 1 < argc              ? argv[at + 1]
                                                     : NULL;
    for (char *c = word; *c; c++)
        if (*c == '-') *c = '_'; /* --self-contact: rod.self_contact */
    int found = 0; /* a key of that name in several sections: each is named */
    for (const ini_key *k = scene_keys_rod; k->section; k++) {
        if (strcmp(k->key, word) != 0) continue;
        size_t used = strlen(err);
        snprintf(err + used, errlen - used, "%s--set %s.%s=%s", found++ ? " or " : "; write ",
                 k->section, k->key, value ? value : "VALUE");
    }
    if (found) {
        size_t used = strlen(err);
        snprintf(err + used, errlen - used, " (a scene key)");
    }
}

/* The --summary path of words that did not parse: what is known is still
 * written. NULL when none was given. */
static const char *summary_path_of(int argc, char **argv)
{
    const char *path = NULL;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--summary") == 0 && i + 1 < argc) path = argv[++i];
        else if (strncmp(argv[i], "--summary=", 10) == 0) path = argv[i] + 10;
    }
    return path && path[0] ? path : NULL;
}

/* The summary completed (exit status, times) and written. Returns the exit
 * status: the run's, or 1 when a run that succeeded cannot write it. */
static int finish_summary(const char *path, run_summary *summary, int status, double wall_start)
{
    summary->exit_code = status;
    summary->cpu_s = cpu_used();
    summary->wall_s = wall_seconds() - wall_start;
    size_t n = strlen(summary->message); /* the prose's last newline */
    while (n > 0 && (summary->message[n - 1] == '\n' || summary->message[n - 1] == ' '))
        summary->message[--n] = '\0';
    char err[RUN_ERR_LEN];
    if (summary_write(path, summary, err, sizeof err)) {
        fprintf(stderr, "rodsim run: %s\n", err);
        if (status == RUN_EXIT_OK) status = RUN_EXIT_FAILURE;
    }
    return status;
}

int run_command(int argc, char **argv)
{
    double wall_start = wall_seconds();
    char err[RUN_ERR_LEN] = "";
    scene_outputs_options o = {.out_dir = "out"};
    cli_list sets = {0};
    const char *summary_path = NULL;
    run_summary summary; /* ~73 KB */
    summary_init(&summary);
    const cli_option options[] = {
        {.name = "--set", .value = CLI_SETTING, .target = &sets, .repeated = 1},
        {.name = "-o", .value = CLI_DIR, .target = &o.out_dir},
        {.name = "--csv", .value = CLI_OUTPUT, .target = &o.csv},
        /* a named file only: "-" is refused, not written as a file named "-" */
        {.name = "--tissue-csv", .value = CLI_FILE, .target = &o.tissue_csv},
        {.name = "--summary", .value = CLI_OUTPUT, .target = &summary_path},
        {.name = "--no-video", .value = CLI_FLAG, .target = &o.no_video},
        {.name = "--allow-long", .value = CLI_FLAG, .target = &o.allow_long},
        {.name = "--progress", .value = CLI_FLAG, .target = &o.progress},
        {.name = "--quiet", .alias = "-q", .value = CLI_FLAG, .target = &o.quiet},
        {0}};
    const cli_operand scene = {.name = "SCENE", .target = &o.label};
    int parsed = cli_parse(argc, argv, options, &scene, err, sizeof err);
    if (parsed == CLI_PARSED && summary_path && strcmp(summary_path, "-") == 0 && o.csv &&
        strcmp(o.csv, "-") == 0) {
        snprintf(err, sizeof err, "--csv - and --summary - both ask for standard output; "
                                  "give one of them a file");
        parsed = CLI_ERROR;
    }
    if (parsed == CLI_PARSED && summary_path && cli_check_output_file("--summary", summary_path, err, sizeof err)) {
        summary_path = NULL; /* it cannot be written */
        parsed = CLI_ERROR;
    } else if (parsed == CLI_ERROR && !summary_path) {
        summary_path = summary_path_of(argc, argv);
        char unused[512];
        if (summary_path && cli_check_output_file("--summary", summary_path, unused, sizeof unused))
            summary_path = NULL; /* the usage error is the one reported */
    }
    if (summary_path) {
        o.summary = &summary;
        o.talk_stderr = strcmp(summary_path, "-") == 0;
    }
    int status;
    if (parsed == CLI_HELP) {
        run_usage(stdout);
        cli_release(options);
        return RUN_EXIT_OK;
    } else if (parsed != CLI_PARSED) {
        unknown_option_hint(argc, argv, err, sizeof err);
        summary_set_message(&summary, err);
        status = cli_usage_error("run", err);
    } else if (is_live_record(o.label)) { /* `run` on a recording: its video */
        status = render_command(argc, argv);
    } else if (scene_outputs_check(&o, err, sizeof err)) {
        fprintf(stderr, "rodsim run: %s\n", err);
        summary_set_message(&summary, err);
        status = RUN_EXIT_BAD_INPUT;
    } else {
        /* SIGINT/SIGTERM from here to the end of the step loop end the run
         * at a step, its summary written (base/outfile.h) */
        outfile_signal_defer_allow(1);
        outfile_signal_defer(1);
        status = run_scene(&o, &sets);
        outfile_signal_defer(0);
        outfile_signal_defer_allow(0);
        const int sig = outfile_stop_signal();
        if (sig) { /* the loop ended at a step; the outputs were not written */
            status = 128 + sig;
            summary.status = "stopped";
            fprintf(stderr, "rodsim: stopped by %s: exit %d, unfinished outputs removed\n",
                    outfile_signal_name(sig), status);
        }
    }
    if (summary_path) status = finish_summary(summary_path, &summary, status, wall_start);
    cli_release(options);
    return status;
}
