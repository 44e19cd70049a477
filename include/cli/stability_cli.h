/* stability_cli.h: `rodsim stability`: the largest stable dt of each scheme
 * over the grid of stability.h, printed as a table, optionally written as CSV
 * and drawn as a map (largest stable dt against NS, log-log, plot.h). */
#ifndef RODSIM_STABILITY_CLI_H
#define RODSIM_STABILITY_CLI_H

#include <stdio.h>

#include "plot/plot.h"
#include "study/stability.h"

/* Prints the rows as an aligned table on f. */
void stability_print_table(FILE *f, const stability_row *rows, int n);
/* Writes the rows as CSV atomically. 0, or -1 with a message. */
int stability_write_csv(const char *path, const stability_row *rows, int n, char *err,
                        size_t errlen);
/* The map: largest stable dt against NS for table 1's rod (rows named
 * "table1" with no load), one curve per scheme, with the predicted lines.
 * NULL when there is nothing to draw or out of memory; caller destroys it. */
plot *stability_map_create(const stability_row *rows, int n);

/* `rodsim stability [--scheme S]... [--quick] [--csv FILE] [--png FILE] [--jobs N]`.
 * argv[0] is "stability". Exit status: 0 every run completed or stopped with
 * the scheme's message; 1 a finding (crash, hang, NaN without a message) or an
 * output that could not be written; 2 usage. */
int stability_command(int argc, char **argv);

#endif
