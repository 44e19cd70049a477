/* figure_cli.c: `rodsim figure` (see figure_cli.h). */
#include "cli/figure_cli.h"

#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli/print_commands.h"
#include "study/figure.h"
#include "base/outfile.h"

enum { EXIT_OK = 0, EXIT_FAILURE_ = 1, EXIT_USAGE = 2 };

typedef struct figure_args {
    const char *name;      /* a figure or "all" */
    const char *out_dir;   /* PNGs (and, for --print-commands, DIR/points) */
    const char *from_dir;  /* --from: draw from the points' CSVs in this directory */
    const char *csv;       /* --point K --csv FILE|- */
    int point;             /* -1: every point */
    int jobs;              /* processes at a time */
    int quick;
    int print_commands;
    int list;
    int help;
} figure_args;

void figure_usage(FILE *f)
{
    fprintf(f,
            "usage: rodsim figure NAME|all [--out DIR] [--jobs N] [--quick]\n"
            "       rodsim figure NAME|all --print-commands [--out DIR] [--quick]\n"
            "       rodsim figure NAME --point K --csv FILE|- [--quick]\n"
            "       rodsim figure NAME --from DIR [--out DIR] [--quick]\n"
            "       rodsim figure --list\n\n"
            "  --out DIR         where the PNGs go (default out/figures)\n"
            "  --jobs N          points computed at once, one process each (default: the\n"
            "                    number of cores)\n"
            "  --quick           fewer points and shorter runs (what the tests use)\n"
            "  --print-commands  print one independent command line per point (for GNU\n"
            "                    parallel or a Slurm array), then, as a '# assemble:' comment,\n"
            "                    the command that draws the figure from their CSVs\n"
            "  --point K --csv F compute point K only and write its rows to F (- = stdout)\n"
            "  --from DIR        draw from DIR/NAME-K.csv, K = 0 .. points-1\n\n"
            "figures:\n");
    const figure_def *const *list = figure_list();
    for (int i = 0; list[i]; i++)
        fprintf(f, "  %-17s %2d points (%d quick): %s\n", figure_name(list[i]),
                figure_point_count(list[i], 0), figure_point_count(list[i], 1),
                figure_summary(list[i]));
}

static int parse_count(const char *text, int lo, int hi, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (end == text || *end || errno || v < lo || v > hi) return -1;
    *out = (int)v;
    return 0;
}

static int parse_args(int argc, char **argv, figure_args *a, char *err, size_t errlen)
{
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    *a = (figure_args){.out_dir = "out/figures", .point = -1, .jobs = cores > 0 ? (int)cores : 1};
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        const char *value = i + 1 < argc ? argv[i + 1] : NULL;
        int takes_value = strcmp(arg, "--out") == 0 || strcmp(arg, "--jobs") == 0 ||
                          strcmp(arg, "--point") == 0 || strcmp(arg, "--csv") == 0 ||
                          strcmp(arg, "--from") == 0;
        if (takes_value && !value) {
            snprintf(err, errlen, "%s needs a value", arg);
            return -1;
        }
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) a->help = 1;
        else if (strcmp(arg, "--list") == 0) a->list = 1;
        else if (strcmp(arg, "--quick") == 0) a->quick = 1;
        else if (strcmp(arg, "--print-commands") == 0) a->print_commands = 1;
        else if (strcmp(arg, "--out") == 0) a->out_dir = value;
        else if (strcmp(arg, "--from") == 0) a->from_dir = value;
        else if (strcmp(arg, "--csv") == 0) a->csv = value;
        else if (strcmp(arg, "--jobs") == 0) {
            if (parse_count(value, 1, 1024, &a->jobs)) {
                snprintf(err, errlen, "--jobs %s: accepted: a whole number 1 .. 1024", value);
                return -1;
            }
        } else if (strcmp(arg, "--point") == 0) {
            if (parse_count(value, 0, 999999, &a->point)) {
                snprintf(err, errlen, "--point %s: accepted: a point index 0, 1, ...", value);
                return -1;
            }
        } else if (arg[0] == '-' && arg[1]) {
            snprintf(err, errlen, "unknown option '%s'", arg);
            return -1;
        } else if (!a->name) {
            a->name = arg;
        } else {
            snprintf(err, errlen, "one figure at a time: '%s' after '%s'", arg, a->name);
            return -1;
        }
        if (takes_value) i++;
    }
    if (a->help || a->list) return 0;
    if (!a->name) {
        snprintf(err, errlen, "no figure named; give one of the list below, or all");
        return -1;
    }
    if ((a->point >= 0) != (a->csv != NULL)) {
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

/* The figures NAME stands for: one, or all of them. */
static int select_figures(const char *name, const figure_def **out, int *n)
{
    const figure_def *const *list = figure_list();
    *n = 0;
    if (strcmp(name, "all") == 0) {
        for (int i = 0; list[i]; i++) out[(*n)++] = list[i];
        return 0;
    }
    const figure_def *f = figure_find(name);
    if (!f) return -1;
    out[(*n)++] = f;
    return 0;
}

/* Every line runs as printed, from any directory and with any PATH: the
 * binary and the directories by absolute paths, quoted for /bin/sh. */
static int print_commands(const figure_def *const *figs, int n, const figure_args *a)
{
    char self[PATH_MAX], out_dir[PATH_MAX], err[PATH_MAX + 128], path[PATH_MAX + 300];
    if (cli_self_path(self, sizeof self, err, sizeof err) ||
        cli_absolute_path(a->out_dir, out_dir, sizeof out_dir, err, sizeof err)) {
        fprintf(stderr, "rodsim figure: %s\n", err);
        return EXIT_FAILURE_;
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
    return fflush(stdout) ? EXIT_FAILURE_ : EXIT_OK;
}

/* --point K --csv FILE: one point, written atomically (or to stdout). */
static int compute_one(const figure_def *f, const figure_args *a)
{
    char err[1024];
    figure_points rows;
    figure_points_init(&rows, f);
    int status = EXIT_OK;
    if (figure_compute_point(f, a->point, a->quick, &rows, err, sizeof err)) {
        fprintf(stderr, "rodsim figure %s: point %d: %s\n", figure_name(f), a->point, err);
        status = a->point >= figure_point_count(f, a->quick) ? EXIT_USAGE : EXIT_FAILURE_;
    } else if (strcmp(a->csv, "-") == 0) {
        if (figure_points_write_csv(f, &rows, stdout) || fflush(stdout)) status = EXIT_FAILURE_;
    } else {
        outfile file;
        if (outfile_open(&file, a->csv, err, sizeof err)) {
            status = EXIT_FAILURE_;
        } else if (figure_points_write_csv(f, &rows, file.fp)) {
            outfile_abort(&file);
            snprintf(err, sizeof err, "%s: write failed", a->csv);
            status = EXIT_FAILURE_;
        } else if (outfile_commit(&file, err, sizeof err)) {
            status = EXIT_FAILURE_;
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

int figure_command(int argc, char **argv)
{
    char err[1024] = "";
    figure_args a;
    if (parse_args(argc, argv, &a, err, sizeof err)) {
        fprintf(stderr, "rodsim figure: %s\n\n", err);
        figure_usage(stderr);
        return EXIT_USAGE;
    }
    if (a.help || a.list) {
        figure_usage(stdout);
        return EXIT_OK;
    }
    const figure_def *figs[64];
    int n = 0;
    if (select_figures(a.name, figs, &n)) {
        fprintf(stderr, "rodsim figure: unknown figure '%s'\n\n", a.name);
        figure_usage(stderr);
        return EXIT_USAGE;
    }
    if (a.print_commands) return print_commands(figs, n, &a);
    if (a.point >= 0) return compute_one(figs[0], &a);

    figure_points points[64];
    int status = EXIT_OK;
    if (a.from_dir) {
        /* the points' CSVs are the user's input: a missing directory, a
         * missing or malformed file is bad input (exit 2) */
        struct stat info;
        if (stat(a.from_dir, &info) != 0 || !S_ISDIR(info.st_mode)) {
            fprintf(stderr, "rodsim figure: --from %s: %s; give the directory holding "
                            "NAME-K.csv (what the --print-commands lines wrote)\n",
                    a.from_dir, stat(a.from_dir, &info) != 0 ? strerror(errno)
                                                             : "not a directory");
            return EXIT_USAGE;
        }
        for (int k = 0; k < n; k++) figure_points_init(&points[k], figs[k]);
        for (int k = 0; k < n && status == EXIT_OK; k++) {
            for (int i = 0; i < figure_point_count(figs[k], a.quick); i++) {
                char path[OUTFILE_PATH_MAX];
                snprintf(path, sizeof path, "%s/%s-%d.csv", a.from_dir, figure_name(figs[k]), i);
                if (figure_points_read_csv(figs[k], path, &points[k], err, sizeof err)) {
                    fprintf(stderr, "rodsim figure: %s\n", err);
                    status = EXIT_USAGE;
                    break;
                }
            }
        }
    } else {
        int total = 0;
        for (int k = 0; k < n; k++) total += figure_point_count(figs[k], a.quick);
        printf("rodsim figure %s: %d points, %d at a time%s\n", a.name, total, a.jobs,
               a.quick ? " (quick)" : "");
        if (figure_sweep(figs, n, a.quick, a.jobs, stdout, points, err, sizeof err)) {
            fprintf(stderr, "rodsim figure: %s\n", err);
            status = EXIT_FAILURE_;
        }
    }
    for (int k = 0; k < n && status == EXIT_OK; k++) {
        if (figure_draw(figs[k], &points[k], a.quick, a.out_dir, stdout, err, sizeof err)) {
            fprintf(stderr, "rodsim figure %s: %s\n", figure_name(figs[k]), err);
            status = EXIT_FAILURE_;
        } else {
            print_outputs(figs[k], a.out_dir);
        }
    }
    for (int k = 0; k < n; k++) figure_points_release(&points[k]);
    return status;
}
