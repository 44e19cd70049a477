/* main.c: the rodsim command line: a table of subcommands. Only main decides
 * the exit status (0 success, 2 bad input/usage/unstable run, 1 other failure). */
#include <stdio.h>
#include <string.h>

#include "base/outfile.h"
#include "base/suggest.h"
#include "cli/args.h"
#include "cli/fem_cli.h"
#include "cli/figure_cli.h"
#include "cli/live.h"
#include "cli/render_cli.h"
#include "cli/run_cli.h"
#include "api/scene_keys.h"
#include "cli/stability_cli.h"
#include "cli/sweep.h"
#include "cli/validate_cli.h"
#include "cli/version.h"
#include "render/gl_context.h"

static int version_command(int argc, char **argv)
{
    char err[256];
    int gl_report = 0;
    const cli_option options[] = {{.name = "--gl", .value = CLI_FLAG, .target = &gl_report},
                                  {0}};
    int parsed = cli_parse(argc, argv, options, NULL, err, sizeof err);
    if (parsed == CLI_HELP) {
        printf("usage: rodsim version [--gl]   (or rodsim --version [--gl])\n"
               "Prints rodsim's version.\n"
               "  --gl   also which GL backends (EGL, OSMesa) this machine has, and which draws\n");
        return RUN_EXIT_OK;
    }
    if (parsed != CLI_PARSED) return cli_usage_error("version", err);
    printf("rodsim %s\n", RODSIM_VERSION);
    if (gl_report) {
        /* opens both libraries (Mesa, LLVM: ~100 ms of CPU), makes no
         * context: only when asked, so that --version stays instant */
        char gl[2048];
        printf("%s", gl_context_backends_report(gl, sizeof gl));
    }
    return RUN_EXIT_OK;
}

typedef struct command {
    const char *name;
    int (*run)(int argc, char **argv); /* argv[0] is the command name; returns the exit status */
    const char *summary;
} command;

/* Another subcommand is one more row here. */
static const command commands[] = {
    {"run", run_command, "simulate a rod scene; render its video and poster, write its CSV"},
    {"fem", fem_command, "solve a 2-D beam FEM scene (the fishing rod); print, plot, tabulate"},
    {"live", live_command, "drive a scene's tip from standard input; answer the force, flushed"},
    {"render", render_command, "turn a rodsim live --record session into its video and poster"},
    {"sweep", sweep_command, "run a scene over the product of --vary lists; one CSV row per point"},
    {"stability", stability_command, "largest stable dt per scheme at the extremes; table, map"},
    {"figure", figure_command, "regenerate the thesis' figures (parallel sweeps) as PNG plots"},
    {"validate", validate_command, "run the validation cases: errors, orders of convergence"},
    {"version", version_command, "print rodsim's version (--gl: and the GL backends)"},
};

static void usage(FILE *f)
{
    fprintf(f, "usage: rodsim COMMAND [options]   (rodsim COMMAND --help for its options)\n"
               "       rodsim --version [--gl]\n\n"
               "commands:\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        fprintf(f, "  %-10s %s\n", commands[i].name, commands[i].summary);
    fprintf(f, "\n  rodsim help COMMAND   the same as rodsim COMMAND --help\n"
               "  rodsim help scene     every key of a rod scene (run), as a Markdown table\n"
               "  rodsim help beam      every key of a beam scene (fem), as a Markdown table\n");
    fprintf(f, "\nexit status: 0 success, 2 bad input or usage (or a numerically unstable run),\n"
               "1 any other failure, 130 stopped by SIGINT (Ctrl-C), 143 by SIGTERM (unfinished\n"
               "outputs removed; live ends its session instead: 0).\n");
}

/* `rodsim help [COMMAND | scene | beam]`: argv[0] is "help". */
static int help_command(int argc, char **argv)
{
    char err[256];
    const char *topic = NULL;
    const cli_option none[] = {{0}};
    const cli_operand operand = {.name = "TOPIC", .optional = 1, .target = &topic};
    int parsed = cli_parse(argc, argv, none, &operand, err, sizeof err);
    if (parsed == CLI_HELP || (parsed == CLI_PARSED && !topic)) {
        usage(stdout);
        return RUN_EXIT_OK;
    }
    if (parsed != CLI_PARSED) return cli_usage_error("help", err);
    if (strcmp(topic, "scene") == 0 || strcmp(topic, "beam") == 0) {
        scene_keys_print_markdown(stdout, topic[0] == 's' ? scene_keys_rod : scene_keys_beam);
        return RUN_EXIT_OK;
    }
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++) {
        if (strcmp(topic, commands[i].name) == 0) {
            char name[32], option[] = "--help";
            snprintf(name, sizeof name, "%s", topic);
            char *args[] = {name, option, NULL};
            return commands[i].run(2, args);
        }
    }
    fprintf(stderr, "rodsim help: unknown topic '%s'; accepted: scene, beam or a command\n",
            topic);
    usage(stderr);
    return RUN_EXIT_BAD_INPUT;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "rodsim: no command given\n");
        usage(stderr);
        return 2;
    }
    if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
        usage(stdout);
        return 0;
    }
    if (strcmp(argv[1], "help") == 0) return help_command(argc - 1, argv + 1);
    if (strcmp(argv[1], "--version") == 0 || strcmp(argv[1], "-V") == 0)
        return version_command(argc - 1, argv + 1);
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++) {
        if (strcmp(argv[1], commands[i].name) == 0) {
            outfile_install_signal_cleanup();
            return commands[i].run(argc - 1, argv + 1);
        }
    }
    const char *names[sizeof commands / sizeof commands[0] + 2];
    size_t n = 0;
    for (; n < sizeof commands / sizeof commands[0]; n++) names[n] = commands[n].name;
    names[n++] = "help";
    names[n] = NULL;
    const char *near = suggest_nearest(argv[1], names);
    if (near) fprintf(stderr, "rodsim: unknown command '%s'; did you mean %s?\n", argv[1], near);
    else fprintf(stderr, "rodsim: unknown command '%s'\n", argv[1]);
    usage(stderr);
    return 2;
}
