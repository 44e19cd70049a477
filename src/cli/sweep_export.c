/* sweep_export.c: a sweep's points as command lines, a Snakefile or a
 * Slurm job array (see sweep_export.h). */
#include "cli/sweep_export.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "base/outfile.h"
#include "cli/print_commands.h"
#include "cli/version.h"

/* Point k's command line (no newline): the binary and every path absolute,
 * every setting spelled out; it writes DIR/DIGEST.csv. */
static int write_point_command(FILE *f, const sweep *sw, int k, sweep_setting *set,
                               const char *self, const char *dir, char *err, size_t errlen)
{
    int n = sweep_point_settings(sw, k, set, err, errlen);
    if (n < 0) return -1;
    cli_print_shell_word(f, self);
    fprintf(f, " sweep ");
    cli_print_shell_word(f, sw->scene_path);
    for (int i = 0; i < n; i++) {
        char assignment[SWEEP_KEY_LEN + SWEEP_VALUE_LEN + 2];
        snprintf(assignment, sizeof assignment, "%s=%s", set[i].key, set[i].value);
        fprintf(f, " --set ");
        cli_print_shell_word(f, assignment);
    }
    if (sw->allow_long) fprintf(f, " --allow-long");
    if (sw->critical) fprintf(f, " --measure critical_load,critical_moment");
    fprintf(f, " --quiet --result ");
    cli_print_shell_word(f, dir);
    return 0;
}

/* The command line (no newline) that assembles the CSV (and the figure)
 * from DIR's result files. */
static int write_assemble_command(FILE *f, const sweep *sw, const char *self, const char *dir,
                                  char *err, size_t errlen)
{
    cli_print_shell_word(f, self);
    fprintf(f, " sweep ");
    cli_print_shell_word(f, sw->scene_path);
    for (int i = 0; i < sw->vary_count; i++) {
        fprintf(f, " --vary ");
        cli_print_shell_word(f, sw->vary_args.items[i]);
    }
    for (int i = 0; i < sw->sets.count; i++) {
        fprintf(f, " --set ");
        cli_print_shell_word(f, sw->sets.items[i]);
    }
    fprintf(f, " --measure ");
    cli_print_shell_word(f, sw->measure_arg);
    fprintf(f, " --result ");
    cli_print_shell_word(f, dir);
    char path[OUTFILE_PATH_MAX];
    if (sw->plot_arg) {
        fprintf(f, " --plot ");
        cli_print_shell_word(f, sw->plot_arg);
        if (sw->png) {
            if (cli_absolute_path(sw->png, path, sizeof path, err, errlen)) return -1;
            fprintf(f, " --png ");
            cli_print_shell_word(f, path);
        }
        if (sw->svg) {
            if (cli_absolute_path(sw->svg, path, sizeof path, err, errlen)) return -1;
            fprintf(f, " --svg ");
            cli_print_shell_word(f, path);
        }
        if (sw->log_axes) fprintf(f, " --log %s", sw->log_axes);
        const char *labels[][2] = {{" --title ", sw->title}, {" --xlabel ", sw->xlabel},
                                   {" --ylabel ", sw->ylabel}, {" --xformat ", sw->xformat},
                                   {" --yformat ", sw->yformat}};
        for (size_t i = 0; i < sizeof labels / sizeof labels[0]; i++)
            if (labels[i][1]) {
                fputs(labels[i][0], f);
                cli_print_shell_word(f, labels[i][1]);
            }
    }
    fprintf(f, " --assemble --csv ");
    if (!sw->csv || strcmp(sw->csv, "-") == 0) {
        fprintf(f, "-");
    } else {
        if (cli_absolute_path(sw->csv, path, sizeof path, err, errlen)) return -1;
        cli_print_shell_word(f, path);
    }
    return 0;
}

/* --print-commands: one line per point, then the line that assembles the CSV. */
int sweep_print_commands(const sweep *sw, sweep_setting *set, char *err, size_t errlen)
{
    char self[OUTFILE_PATH_MAX], dir[OUTFILE_PATH_MAX];
    if (cli_self_path(self, sizeof self, err, errlen) ||
        cli_absolute_path(sw->result_dir, dir, sizeof dir, err, errlen))
        return -1;
    printf("# rodsim sweep: %d point%s of %s; each line runs one point into %s (skipped when "
           "its result file is there)\n",
           sw->point_count, sw->point_count == 1 ? "" : "s", sw->scene_path, dir);
    for (int k = 0; k < sw->point_count; k++) {
        if (write_point_command(stdout, sw, k, set, self, dir, err, errlen)) return -1;
        printf("\n");
    }
    printf("# assemble: ");
    if (write_assemble_command(stdout, sw, self, dir, err, errlen)) return -1;
    printf("\n");
    return fflush(stdout) == 0 ? 0 : -1;
}

/* `text` as a Python string literal ("...", backslash escapes). */
static void python_string(FILE *f, const char *text)
{
    fputc('"', f);
    for (const unsigned char *c = (const unsigned char *)text; *c; c++) {
        if (*c == '"' || *c == '\\') fprintf(f, "\\%c", *c);
        else if (*c < 0x20 || *c == 0x7f) fprintf(f, "\\x%02x", *c);
        else fputc(*c, f);
    }
    fputc('"', f);
}

/* --snakefile FILE: a Snakefile whose rule `point` runs one point's command
 * (the --print-commands line) per result file DIR/{digest}.csv and whose
 * rule `assemble` writes the CSV (and figure) from them; `snakemake -s FILE
 * --cores N` runs the sweep. Every path is absolute, so it runs from any
 * directory. Decision: paths holding { or } are refused (Snakemake reads
 * them as wildcards). */
int sweep_write_snakefile(const sweep *sw, sweep_setting *set, const uint64_t *digests,
                          char *err, size_t errlen)
{
    char self[OUTFILE_PATH_MAX], dir[OUTFILE_PATH_MAX], outputs[4][OUTFILE_PATH_MAX];
    const char *given[4] = {sw->csv, sw->png, sw->svg, sw->plot_arg ? sw->plot_csv : NULL};
    if (cli_self_path(self, sizeof self, err, errlen) ||
        cli_absolute_path(sw->result_dir, dir, sizeof dir, err, errlen))
        return -1;
    for (int i = 0; i < 4; i++) {
        outputs[i][0] = '\0';
        if (given[i] && cli_absolute_path(given[i], outputs[i], sizeof outputs[i], err, errlen))
            return -1;
        if (strpbrk(outputs[i], "{}\n") || (i == 0 && strpbrk(dir, "{}\n"))) {
            snprintf(err, errlen, "--snakefile: the path %.1900s holds '{', '}' or a line break, "
                                  "which Snakemake reads as a wildcard; choose another",
                     strpbrk(outputs[i], "{}\n") ? outputs[i] : dir);
            return -1;
        }
    }
    outfile out = {.fd = -1, .slot = -1};
    if (outfile_open(&out, sw->snakefile, err, errlen)) return -1;
    FILE *f = out.fp;
    fprintf(f, "# Snakefile written by rodsim %s sweep --snakefile: %d point%s of %s.\n",
            RODSIM_VERSION, sw->point_count, sw->point_count == 1 ? "" : "s", sw->scene_path);
    fprintf(f, "# snakemake -s THIS_FILE --cores N: rule point runs one point into its result\n"
               "# file %s/DIGEST.csv (DIGEST: of the point's inputs; an existing file is not\n"
               "# run again), then rule assemble writes the results CSV from them.\n\n",
            dir);
    fprintf(f, "POINTS = {\n");
    for (int k = 0; k < sw->point_count; k++) {
        int seen = 0; /* a point listed twice (a value repeated) is one job */
        for (int j = 0; j < k && !seen; j++) seen = digests[j] == digests[k];
        if (seen) continue;
        char *line = NULL;
        size_t len = 0;
        FILE *mem = open_memstream(&line, &len);
        int rc = !mem || write_point_command(mem, sw, k, set, self, dir, err, errlen);
        if (mem) fclose(mem);
        if (rc) {
            if (!mem) snprintf(err, errlen, "out of memory");
            free(line);
            outfile_abort(&out);
            return -1;
        }
        fprintf(f, "    \"%016llx\": ", (unsigned long long)digests[k]);
        python_string(f, line);
        fprintf(f, ",\n");
        free(line);
    }
    fprintf(f, "}\n\nlocalrules: all, assemble\n\nrule all:\n    input: ");
    python_string(f, outputs[0]);
    fprintf(f, "\n\nrule assemble:\n    input:");
    for (int k = 0; k < sw->point_count; k++) {
        int seen = 0;
        for (int j = 0; j < k && !seen; j++) seen = digests[j] == digests[k];
        if (seen) continue;
        char path[OUTFILE_PATH_MAX + 32];
        snprintf(path, sizeof path, "%s/%016llx.csv", dir, (unsigned long long)digests[k]);
        fprintf(f, "\n        ");
        python_string(f, path);
        fputc(',', f);
    }
    fprintf(f, "\n    output: ");
    for (int i = 0, first = 1; i < 4; i++) {
        if (!outputs[i][0]) continue;
        fprintf(f, "%s", first ? "" : ", ");
        python_string(f, outputs[i]);
        first = 0;
    }
    char *line = NULL;
    size_t len = 0;
    FILE *mem = open_memstream(&line, &len);
    int rc = !mem || write_assemble_command(mem, sw, self, dir, err, errlen);
    if (mem) fclose(mem);
    if (!rc) {
        fprintf(f, "\n    params: command=");
        python_string(f, line);
        fprintf(f, "\n    shell: \"{params.command} --quiet\"\n\n");
        fprintf(f, "rule point:\n    output: ");
        char pattern[OUTFILE_PATH_MAX + 16];
        snprintf(pattern, sizeof pattern, "%s/{digest}.csv", dir);
        python_string(f, pattern);
        fprintf(f, "\n    wildcard_constraints: digest=\"[0-9a-f]{16}\"\n"
                   "    params: command=lambda wildcards: POINTS[wildcards.digest]\n"
                   "    shell: \"{params.command}\"\n");
    } else if (!mem) {
        snprintf(err, errlen, "out of memory");
    }
    free(line);
    if (!rc && ferror(f)) {
        snprintf(err, errlen, "%s: write failed", sw->snakefile);
        rc = 1;
    }
    if (rc || outfile_commit(&out, err, errlen)) {
        outfile_abort(&out);
        return -1;
    }
    return 0;
}

/* --sbatch FILE: a Slurm job array script, task i (1-based, the
 * --print-commands order) running point i into its result file; the
 * assemble line is in its comments. Any other SLURM_ARRAY_TASK_ID exits 2. */
int sweep_write_sbatch(const sweep *sw, sweep_setting *set, char *err, size_t errlen)
{
    char self[OUTFILE_PATH_MAX], dir[OUTFILE_PATH_MAX];
    if (cli_self_path(self, sizeof self, err, errlen) ||
        cli_absolute_path(sw->result_dir, dir, sizeof dir, err, errlen))
        return -1;
    outfile out = {.fd = -1, .slot = -1};
    if (outfile_open(&out, sw->sbatch, err, errlen)) return -1;
    FILE *f = out.fp;
    fprintf(f, "#!/bin/sh\n"
               "#SBATCH --array=1-%d\n"
               "#SBATCH --job-name=rodsim-sweep\n"
               "#SBATCH --ntasks=1\n"
               "#SBATCH --cpus-per-task=1\n",
            sw->point_count);
    fprintf(f, "# Slurm job array written by rodsim %s sweep --sbatch: %d point%s of %s.\n"
               "# sbatch THIS_FILE: task i runs point i into its result file\n"
               "# %s/DIGEST.csv (an existing file is not run again);\n"
               "# sbatch --array=1-%d%%K THIS_FILE runs at most K at once (over 1000 tasks:\n"
               "# Slurm's MaxArraySize must allow them). When all are done,\n"
               "# assemble the CSV (or: sbatch --dependency=afterok:JOBID --wrap 'LINE'):\n"
               "# assemble: ",
            RODSIM_VERSION, sw->point_count, sw->point_count == 1 ? "" : "s", sw->scene_path, dir,
            sw->point_count);
    int rc = write_assemble_command(f, sw, self, dir, err, errlen);
    fprintf(f, "\ncase \"${SLURM_ARRAY_TASK_ID:-}\" in\n");
    for (int k = 0; !rc && k < sw->point_count; k++) {
        fprintf(f, "%d) exec ", k + 1);
        rc = write_point_command(f, sw, k, set, self, dir, err, errlen);
        fprintf(f, " ;;\n");
    }
    fprintf(f, "*) echo \"rodsim sweep: SLURM_ARRAY_TASK_ID is '${SLURM_ARRAY_TASK_ID:-}'; "
               "accepted 1 .. %d (submit with sbatch)\" >&2; exit 2 ;;\nesac\n",
            sw->point_count);
    if (!rc && ferror(f)) {
        snprintf(err, errlen, "%s: write failed", sw->sbatch);
        rc = -1;
    }
    if (!rc) fchmod(fileno(f), 0755); /* runs as ./FILE too */
    if (rc || outfile_commit(&out, err, errlen)) {
        outfile_abort(&out);
        return -1;
    }
    return 0;
}
