/* figure_cli.c: `rodsim figure` (see figure_cli.h). */
#include "cli/figure_cli.h"

#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli/args.h"
#include "cli/print_commands.h"
#include "cli/sweep_figure.h"
#include "study/figure.h"
#include "base/outfile.h"
#include "base/worker.h"

typedef struct figure_args {
    const char *name;      /* a figure or "all" */
    const char *out_dir;   /* PNGs (and, for --print-commands, DIR/points) */
    const char *from_dir;  /* --from: draw from the points' CSVs in this directory */
    const char *csv;       /* --point K --csv FILE|- */
    const char *result_dir; /* a sweep figure's result files (--result) */
    int point;             /* -1: every point */
    int print_sweep;       /* a sweep figure as `rodsim sweep` lines */
    int jobs;              /* processes at a time */
    int quick;
    int print_commands;
    int list;
} figure_args;

void figure_usage(FILE *f)
{
    fprintf(f,
            "usage: rodsim figure NAME|all [--out DIR] [--jobs N] [--quick] [--print-commands]\n"
            "       rodsim figure NAME --point K --csv FILE|- | --from DIR   (not a sweep)\n"
            "       rodsim figure NAME --point K --result DIR | --print-sweep (a sweep)\n"
            "       rodsim figure --list\n\n"
            "  --out DIR         where the figures go (default out/figures)\n"
            "  --jobs N          points at once, one process each (1..64; default: cores)\n"
            "  --quick           fewer points and shorter runs (what the tests use)\n"
            "  --print-commands  a command line per point, then a '# assemble:' line\n"
            "  --point K         point K only: into --csv F (- = stdout), or --result DIR\n"
            "  --from DIR        draw from DIR/NAME-K.csv, K = 0 .. points-1\n"
            "  --print-sweep     the `rodsim sweep` lines of a sweep (FILE_sweep*.csv)\n\n"
            "figures (sweep: drawn by `rodsim sweep`'s code):\n");
    const figure_def *const *list = figure_list();
    for (int i = 0; list[i]; i++) {
        const int full = figure_point_count(list[i], 0);
        fprintf(f, "  %-17s %2d %-6s (%d quick): %s\n", figure_name(list[i]), full,
                full == 1 ? "point" : "points", figure_point_count(list[i], 1),
                figure_summary(list[i]));
    }
    const figure_spec *const *specs = figure_spec_list();
    for (int i = 0; specs[i]; i++) {
        int full = 0, quick = 0;
        for (int k = 0; k < specs[i]->parts; k++) {
            full += figure_spec_points(specs[i], k, 0);
            quick += figure_spec_points(specs[i], k, 1);
        }
        fprintf(f, "  %-17s %2d %-6s (%d quick): sweep: %s\n", specs[i]->name, full,
                full == 1 ? "point" : "points", quick, specs[i]->summary);
    }
}

/* Which options go together, once parsed. 0, or -1 with a message. */
static int check_args(const figure_args *a, char *err, size_t errlen)
{
    if (a->list) return 0;
    if (!a->name) {
        snprintf(err, errlen, "no figure named; give one of rodsim figure --list, or all");
        return -1;
    }
    const figure_spec *spec = figure_spec_find(a->name);
    if (spec) {
        if (a->csv || a->from_dir) {
            snprintf(err, errlen, "%s is a sweep figure: not %s (its points go to --result DIR; "
                                  "--print-commands prints them)", a->name,
                     a->csv ? "--csv" : "--from");
            return -1;
        }
        if (a->point >= 0 && !a->result_dir) {
            snprintf(err, errlen, "--point K of the sweep figure %s needs --result DIR", a->name);
            return -1;
        }
    } else if (a->result_dir || a->print_sweep) {
        snprintf(err, errlen, "%s: only a sweep figure (SWEEP in the list) takes %s", a->name,
                 a->result_dir ? "--result" : "--print-sweep");
        return -1;
    } else if ((a->point >= 0) != (a->csv != NULL)) {
        snprintf(err, errlen, "--point K and --csv FILE go together");
        return -1;
    }
    if (a->point >= 0 && (a->from_dir || a->print_commands || strcmp(a->name, "all") == 0)) {
        snprintf(err, errlen, "--point computes one point of one figure; not with %s",
                 a->from_dir ? "--from" : a->print_commands ? "--print-commands" : "all");
        return -1;
    }
    if (a->from_dir && a->print_commands) {
        snprintf(err, errlen, "--from and --print-commands exclude each other");
        return -1;
    }
    return 0;
}

/* CLI_PARSED, CLI_HELP or CLI_ERROR with a message (args.h). */
static int parse_args(int argc, char **argv, figure_args *a, char *err, size_t errlen)
{
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    if (cores > WORKER_MAX_JOBS) cores = WORKER_MAX_JOBS;
    *a = (figure_args){.out_dir = "out/figures", .point = -1, .jobs = cores > 0 ? (int)cores : 1};
    const cli_option options[] = {
        {.name = "--list", .value = CLI_FLAG, .target = &a->list},
        {.name = "--quick", .value = CLI_FLAG, .target = &a->quick},
        {.name = "--print-commands", .value = CLI_FLAG, .target = &a->print_commands},
        {.name = "--print-sweep", .value = CLI_FLAG, .target = &a->print_sweep},
        {.name = "--result", .value = CLI_DIR, .target = &a->result_dir},
        {.name = "--out", .value = CLI_DIR, .target = &a->out_dir},
        {.name = "--from", .value = CLI_DIR, .target = &a->from_dir},
        {.name = "--csv", .value = CLI_OUTPUT, .target = &a->csv},
        {.name = "--jobs", .value = CLI_COUNT, .target = &a->jobs, .lo = 1,
         .hi = WORKER_MAX_JOBS},
        {.name = "--point", .value = CLI_COUNT, .target = &a->point, .lo = 0, .hi = 999999},
        {0}};
    const cli_operand name = {.name = "NAME", .optional = 1, .target = &a->name};
    int parsed = cli_parse(argc, argv, options, &name, err, errlen);
    if (parsed != CLI_PARSED) return parsed;
    return check_args(a, err, errlen) ? CLI_ERROR : CLI_PARSED;
}

/* The figures NAME stands for: one, or all of them (figures, then sweep figures). */
static int select_figures(const char *name, const figure_def **out, int *n,
                          const figure_spec **specs, int *n_specs)
{
    const figure_def *const *list = figure_list();
    const figure_spec *const *spec_list = figure_spec_list();
    *n = *n_specs = 0;
    if (strcmp(name, "all") == 0) {
        for (int i = 0; list[i]; i++) out[(*n)++] = list[i];
        for (int i = 0; spec_list[i]; i++) specs[(*n_specs)++] = spec_list[i];
        return 0;
    }
    const figure_def *f = figure_find(name);
    const figure_spec *spec = figure_spec_find(name);
    if (f) out[(*n)++] = f;
    if (spec) specs[(*n_specs)++] = spec;
    return f || spec ? 0 : -1;
}

/* A sweep figure through `rodsim sweep`'s machinery (sweep.h); --print-commands
 * keeps its points in OUT/points/NAME unless --result says where. */
static int run_spec(const figure_spec *spec, const figure_args *a)
{
    char points[OUTFILE_PATH_MAX];
    snprintf(points, sizeof points, "%s/points/%s", a->out_dir, spec->name);
    sweep_figure_options o = {
        .out_dir = a->out_dir,
        .result_dir = a->result_dir ? a->result_dir : a->print_commands ? points : NULL,
        .quick = a->quick,
        .jobs = a->jobs,
        .point = a->point,
        .print_commands = a->print_commands,
        .print_sweep = a->print_sweep,
    };
    return sweep_figure_command(spec, &o);
}

/* Every line runs as printed, from any directory and with any PATH: the
 * binary and the directories by absolute paths, quoted for /bin/sh. */
static int print_commands(const figure_def *const *figs, int n, const figure_args *a)
{
    char self[PATH_MAX], out_dir[PATH_MAX], err[PATH_MAX + 128], path[PATH_MAX + 300];
    if (cli_self_path(self, sizeof self, err, sizeof err) ||
        cli_absolute_path(a->out_dir, out_dir, sizeof out_dir, err, sizeof err)) {
        fprintf(stderr, "rodsim figure: %s\n", err);
        return RUN_EXIT_FAILURE;
    }
    const char *quick = a->quick ? " --quick" : "";
    printf("# rodsim figure %s: one independent command per point (run them in any order, in\n"
           "# parallel: grep -v '^#' FILE | parallel; Slurm array: line $SLURM_ARRAY_TASK_ID),\n"
           "# then the '# assemble:' line(s) at the end, which draw from their CSVs.\n",
           a->name);
    for (int k = 0; k < n; k++)
        for (int i = 0; i < figure_point_count(figs[k], a->quick); i++) {
            cli_print_shell_word(stdout, self);
            printf(" figure %s --point %d --csv ", figure_name(figs[k]), i);
            snprintf(path, sizeof path, "%s/points/%s-%d.csv", out_dir, figure_name(figs[k]), i);
            cli_print_shell_word(stdout, path);
            printf("%s\n", quick);
        }
    for (int k = 0; k < n; k++) {
        printf("# assemble: ");
        cli_print_shell_word(stdout, self);
        printf(" figure %s --from ", figure_name(figs[k]));
        snprintf(path, sizeof path, "%s/points", out_dir);
        cli_print_shell_word(stdout, path);
        printf(" --out ");
        cli_print_shell_word(stdout, out_dir);
        printf("%s\n", quick);
    }
    return fflush(stdout) ? RUN_EXIT_FAILURE : RUN_EXIT_OK;
}

/* --point K --csv FILE: one point, written atomically (or to stdout). */
static int compute_one(const figure_def *f, const figure_args *a)
{
    char err[1024];
    figure_points rows;
    figure_points_init(&rows, f);
    int status = RUN_EXIT_OK;
    if (figure_compute_point(f, a->point, a->quick, &rows, err, sizeof err)) {
        fprintf(stderr, "rodsim figure %s: point %d: %s\n", figure_name(f), a->point, err);
        status = a->point >= figure_point_count(f, a->quick) ? RUN_EXIT_BAD_INPUT : RUN_EXIT_FAILURE;
    } else if (strcmp(a->csv, "-") == 0) {
        if (figure_points_write_csv(f, &rows, stdout) || fflush(stdout)) status = RUN_EXIT_FAILURE;
    } else {
        outfile file;
        if (outfile_open(&file, a->csv, err, sizeof err)) {
            status = RUN_EXIT_FAILURE;
        } else if (figure_points_write_csv(f, &rows, file.fp)) {
            outfile_abort(&file);
            snprintf(err, sizeof err, "%s: write failed", a->csv);
            status = RUN_EXIT_FAILURE;
        } else if (outfile_commit(&file, err, sizeof err)) {
            status = RUN_EXIT_FAILURE;
        }
        if (status) fprintf(stderr, "rodsim figure: %s\n", err);
    }
    figure_points_release(&rows);
    return status;
}

static void print_outputs(const figure_def *f, const char *out_dir)
{
    const char *const *files = figure_outputs(f);
    for (int i = 0; files[i]; i++) printf("wrote %s/%s\n", out_dir, files[i]);
}

/* Where the outputs go, checked before any point is computed: --csv FILE
 * and --result DIR of one point, else --out DIR (and --result DIR, whose
 * result files a sweep figure reuses). The --print-* forms write only to
 * standard output. 0, or -1 with a message naming the option and the path. */
static int check_outputs(const figure_args *a, char *err, size_t errlen)
{
    if (a->print_commands || a->print_sweep) return 0;
    if (a->csv) return cli_check_output_file("--csv", a->csv, err, errlen);
    char why[512];
    if (a->result_dir && outfile_check_dir(a->result_dir, why, sizeof why)) {
        snprintf(err, errlen, "--result %s: %s", a->result_dir, why);
        return -1;
    }
    if (a->point < 0 && outfile_check_dir(a->out_dir, why, sizeof why)) {
        snprintf(err, errlen, "--out %s: %s", a->out_dir, why);
        return -1;
    }
    return 0;
}

int figure_command(int argc, char **argv)
{
    char err[1024] = "";
    figure_args a;
    int parsed = parse_args(argc, argv, &a, err, sizeof err);
    if (parsed == CLI_ERROR) return cli_usage_error("figure", err);
    if (parsed == CLI_HELP || a.list) {
        figure_usage(stdout);
        return RUN_EXIT_OK;
    }
    const figure_def *figs[64];
    const figure_spec *specs[64];
    int n = 0, n_specs = 0;
    if (select_figures(a.name, figs, &n, specs, &n_specs)) {
        const char *names[64];
        int k = 0;
        for (const figure_def *const *f = figure_list(); *f && k < 62; f++)
            names[k++] = figure_name(*f);
        for (const figure_spec *const *f = figure_spec_list(); *f && k < 62; f++)
            names[k++] = (*f)->name;
        names[k++] = "all";
        names[k] = NULL;
        cli_unknown_name(err, sizeof err, "figure", a.name, "figure", names);
        fprintf(stderr, "rodsim figure: %s\n\n", err);
        figure_usage(stderr);
        return RUN_EXIT_BAD_INPUT;
    }
    if (check_outputs(&a, err, sizeof err)) return cli_usage_error("figure", err);
    int status = RUN_EXIT_OK;
    if (a.print_commands && n > 0) status = print_commands(figs, n, &a);
    if (a.print_commands || a.print_sweep || a.point >= 0 || n == 0) {
        for (int k = 0; k < n_specs && status == RUN_EXIT_OK; k++) status = run_spec(specs[k], &a);
        if (a.point >= 0 && n > 0) status = compute_one(figs[0], &a);
        return status;
    }

    figure_points points[64];
    if (a.from_dir) {
        /* the points' CSVs are the user's input: a missing directory, a
         * missing or malformed file is bad input (exit 2) */
        struct stat info;
        if (stat(a.from_dir, &info) != 0 || !S_ISDIR(info.st_mode)) {
            fprintf(stderr, "rodsim figure: --from %s: %s; give the directory holding "
                            "NAME-K.csv (what the --print-commands lines wrote)\n",
                    a.from_dir, stat(a.from_dir, &info) != 0 ? strerror(errno)
                                                             : "not a directory");
            return RUN_EXIT_BAD_INPUT;
        }
        for (int k = 0; k < n; k++) figure_points_init(&points[k], figs[k]);
        for (int k = 0; k < n && status == RUN_EXIT_OK; k++) {
            for (int i = 0; i < figure_point_count(figs[k], a.quick); i++) {
                char path[OUTFILE_PATH_MAX];
                snprintf(path, sizeof path, "%s/%s-%d.csv", a.from_dir, figure_name(figs[k]), i);
                if (figure_points_read_csv(figs[k], path, &points[k], err, sizeof err)) {
                    fprintf(stderr, "rodsim figure: %s\n", err);
                    status = RUN_EXIT_BAD_INPUT;
                    break;
                }
            }
        }
    } else {
        int total = 0;
        for (int k = 0; k < n; k++) total += figure_point_count(figs[k], a.quick);
        printf("rodsim figure %s: %d point%s, %d at a time%s\n", a.name, total,
               total == 1 ? "" : "s", a.jobs, a.quick ? " (quick)" : "");
        if (figure_sweep(figs, n, a.quick, a.jobs, stdout, points, err, sizeof err)) {
            fprintf(stderr, "rodsim figure: %s\n", err);
            status = RUN_EXIT_FAILURE;
        }
    }
    for (int k = 0; k < n && status == RUN_EXIT_OK; k++) {
        if (figure_draw(figs[k], &points[k], a.quick, a.out_dir, stdout, err, sizeof err)) {
            fprintf(stderr, "rodsim figure %s: %s\n", figure_name(figs[k]), err);
            status = RUN_EXIT_FAILURE;
        } else {
            print_outputs(figs[k], a.out_dir);
        }
    }
    for (int k = 0; k < n; k++) figure_points_release(&points[k]);
    for (int k = 0; k < n_specs && status == RUN_EXIT_OK; k++) status = run_spec(specs[k], &a);
    return status;
}
