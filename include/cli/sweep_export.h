/* sweep_export.h: a sweep handed to other runners, with --result DIR: one
 * self-contained command line per point (GNU parallel, any shell), a
 * Snakefile, or a Slurm job array script; each point writes its result file
 * DIR/DIGEST.csv, and the assemble line (`rodsim sweep ... --assemble`)
 * writes the CSV and figure from them. Every line names the binary and the
 * paths absolutely, so it runs from any directory with any PATH. */
#ifndef RODSIM_SWEEP_EXPORT_H
#define RODSIM_SWEEP_EXPORT_H

#include <stddef.h>
#include <stdint.h>

#include "cli/sweep_spec.h"

/* `set` below is scratch for sweep_point_settings (sets.count + vary_count
 * entries). Each returns 0, or -1 with a message. */

/* --print-commands: one line per point on stdout, then "# assemble: " and
 * the line that assembles the CSV. */
int sweep_print_commands(const sweep *sw, sweep_setting *set, char *err, size_t errlen);

/* --snakefile FILE: rule `point` runs one point's command per result file
 * DIR/{digest}.csv, rule `assemble` writes the CSV (and figure) from them;
 * `snakemake -s FILE --cores N` runs the sweep. digests: one per point. */
int sweep_write_snakefile(const sweep *sw, sweep_setting *set, const uint64_t *digests,
                          char *err, size_t errlen);

/* --sbatch FILE: a Slurm job array script, task i (1-based, the
 * --print-commands order) running point i; the assemble line is in its
 * comments. */
int sweep_write_sbatch(const sweep *sw, sweep_setting *set, char *err, size_t errlen);

#endif
