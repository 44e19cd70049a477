/* run_cli.h: `rodsim run SCENE`: load a scene, simulate it, write its
 * outputs (scene_outputs.h). A SCENE that is a `rodsim live` record is
 * rendered as `rodsim render` does (render_cli.h). */
#ifndef RODSIM_RUN_CLI_H
#define RODSIM_RUN_CLI_H

#include <stdio.h>

/* `rodsim run ...`: argv[0] is "run". Returns an exit status (RUN_EXIT_*,
 * args.h); messages go to stdout (the prose) and stderr (errors, warnings,
 * the progress line); --summary FILE writes the JSON summary (summary.h)
 * whatever the outcome. Never calls exit(). */
int run_command(int argc, char **argv);

/* Prints the usage of `rodsim run` to f. */
void run_usage(FILE *f);

#endif
