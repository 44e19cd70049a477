/* main.c: the rodsim command line: a table of subcommands. Only main decides
 * the exit status (0 success, 2 bad input/usage/unstable run, 1 other failure). */
#include <stdio.h>
#include <string.h>

#include "cli/fem_cli.h"
#include "cli/figure_cli.h"
#include "cli/live.h"
#include "cli/render_cli.h"

#include "base/outfile.h"
#include "cli/run.h"
#include "cli/scene_keys.h"
#include "cli/stability_cli.h"
#include "cli/sweep.h"
#include "cli/validate_cli.h"
#include "cli/version.h"
#include "render/gl_context.h"

static int version_command(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    char gl[2048]; /* the GL backends: opens both libraries (~50 ms), makes no context */
    printf("rodsim %s\n%s", RODSIM_VERSION, gl_context_backends_report(gl, sizeof gl));
    return 0;
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
    {"version", version_command, "print rodsim's version (also rodsim --version)"},
};

static void usage(FILE *f)
{
    fprintf(f, "usage: rodsim COMMAND [options]   (rodsim COMMAND --help for its options)\n"
               "       rodsim --version\n\n"
               "commands:\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        fprintf(f, "  %-10s %s\n", commands[i].name, commands[i].summary);
    fprintf(f, "\n  rodsim help COMMAND   the same as rodsim COMMAND --help\n"
               "  rodsim help scene     every key of a rod scene (run), as a Markdown table\n"
               "  rodsim help beam      every key of a beam scene (fem), as a Markdown table\n");
    fprintf(f, "\nexit status: 0 success, 2 bad input or usage (or a numerically unstable run),\n"
               "1 any other failure.\n");
}

/* `rodsim help [COMMAND | scene | beam]`. */
static int help(int argc, char **argv)
{
    if (argc < 3) {
        usage(stdout);
        return 0;
    }
    if (strcmp(argv[2], "scene") == 0 || strcmp(argv[2], "beam") == 0) {
        scene_keys_print_markdown(stdout, argv[2][0] == 's' ? scene_keys_rod : scene_keys_beam);
        return 0;
    }
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++) {
        if (strcmp(argv[2], commands[i].name) == 0) {
            char *args[] = {argv[2], "--help", NULL};
            return commands[i].run(2, args);
        }
    }
    fprintf(stderr, "rodsim help: unknown topic '%s'; accepted: scene, beam or a command\n",
            argv[2]);
    usage(stderr);
    return 2;
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
    if (strcmp(argv[1], "help") == 0) return help(argc, argv);
    if (strcmp(argv[1], "--version") == 0 || strcmp(argv[1], "-V") == 0)
        return version_command(argc - 1, argv + 1);
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++) {
        if (strcmp(argv[1], commands[i].name) == 0) {
            outfile_install_signal_cleanup();
            return commands[i].run(argc - 1, argv + 1);
        }
    }
    fprintf(stderr, "rodsim: unknown command '%s'\n", argv[1]);
    usage(stderr);
    return 2;
}
