/* figure_cli.h: `rodsim figure NAME [--out DIR] [--jobs N] [--print-commands]
 * [--quick]`: computes a figure's points in parallel (figure.h) and draws it.
 *
 *   rodsim figure NAME|all              all points, --jobs processes at a time, then the PNGs
 *   rodsim figure NAME --point K --csv FILE|-   one point's rows (CSV) only
 *   rodsim figure NAME --from DIR       draws from DIR/NAME-K.csv (K = every point)
 *   rodsim figure NAME --print-commands one command line per point, then (as a
 *                                       "# assemble:" comment) the one that draws
 *   rodsim figure --list                the figures and their point counts
 */
#ifndef RODSIM_FIGURE_CLI_H
#define RODSIM_FIGURE_CLI_H

#include <stdio.h>

/* argv[0] is "figure". Returns an exit status (0, 1 failure, 2 bad usage);
 * never calls exit(). */
int figure_command(int argc, char **argv);

void figure_usage(FILE *f);

#endif
