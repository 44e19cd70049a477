/* rods_run.h: `rodsim run` of a scene of named rods ([rod NAME]; sim/rod_set.h):
 * the rods stepped together, the CSV with a column rod, the summary's list
 * of rods, the video of every rod in its own colour. */
#ifndef RODSIM_CLI_RODS_RUN_H
#define RODSIM_CLI_RODS_RUN_H

#include "base/ini.h"
#include "cli/scene_outputs.h"

/* Reads the rods of doc (its --set applied) and writes the outputs o asks
 * for, named `scene`. Returns an exit status (RUN_EXIT_*, args.h). */
int rods_run_scene(const scene_outputs_options *o, ini_doc *doc, const char *scene);

#endif
