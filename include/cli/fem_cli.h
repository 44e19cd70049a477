/* fem_cli.h: `rodsim fem`: 2-D beam (frame) finite-element scenes, the
 * nodal table (stdout, CSV, Markdown) and the figure of the undeformed and
 * deformed structure (plot.h). The solver itself is fem.h. */
#ifndef RODSIM_FEM_CLI_H
#define RODSIM_FEM_CLI_H

#include <stddef.h>

#include "fem/fem.h"
#include "base/ini.h"
#include "plot/plot.h"

typedef struct fem_figure_options {
    int width, height;  /* px */
    double scale;       /* deformation scale factor; 0 = automatic */
    char title[256];    /* UTF-8; empty: "FEM: <scene name>" */
} fem_figure_options;

/* Reads [material], [geometry], [support]..., [load]... and [plot] from a
 * scene and checks it strictly (ini_check_unused at the end). Returns the
 * model, or NULL with "file:line: [section] key = value: what is accepted"
 * in err. figure may be NULL; the [plot] keys are read and checked anyway. */
fem_model *fem_scene_read(ini_doc *doc, fem_figure_options *figure, char *err, size_t errlen);

/* The automatic deformation scale: the largest nodal displacement is drawn
 * as about 15 % of the structure's size, rounded down to 1, 2 or 5 x 10^k;
 * never below 1 (a large deflection is drawn true to scale). */
double fem_auto_scale(const fem_model *model, const fem_solution *solution);

/* Builds the figure (not yet drawn): undeformed rod (grey, dashed), deformed
 * rod (Hermite shape inside each element, displacements x scale), node
 * markers and numbers, support symbols, load arrows, axes in metres, title,
 * legend. NULL when out of memory. Caller destroys it (plot_destroy). */
plot *fem_figure_create(const fem_model *model, const fem_solution *solution,
                        const fem_figure_options *options, double scale, const char *scene_name);

/* Colour of the deformed rod in the figure (tests look for it). */
extern const unsigned char fem_deformed_rgb[3];

/* The `rodsim fem` subcommand. argv[0] is "fem", argv[1..] its arguments:
 * SCENE [--set section.key=value]... [--csv FILE] [--md FILE] [--png FILE]
 * [--no-png] [-o DIR]. Returns the exit status: 0 done, 2 bad input (scene
 * error, mechanism, usage), 1 any other failure. */
int fem_command(int argc, char **argv);

#endif
