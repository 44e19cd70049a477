/* validate_cli.h: `rodsim validate`: runs the validation cases (validate.h)
 * over schemes, resolutions and time steps, prints one aligned row per run
 * and the observed orders of convergence, optionally a CSV; runs points in
 * parallel processes with --jobs. */
#ifndef RODSIM_VALIDATE_CLI_H
#define RODSIM_VALIDATE_CLI_H

/* argv[0] is "validate". Options:
 * [--case NAME]... [--scheme NAME]... [--nodes N]... [--dt DT]... [--quick]
 * [--csv FILE|-] [--jobs N]. Returns 0 when every applicable row ran, 1 when
 * a run failed (diverged, no convergence, a crashed worker) or the CSV could
 * not be written, 2 on bad usage. */
int validate_command(int argc, char **argv);

#endif
