/* sweep_figure.c: `rodsim figure` of a sweep figure (see sweep_figure.h):
 * its parts as sweeps, their points run or handed on, the figure drawn. */
#include "cli/sweep_figure.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/embedded.h"
#include "base/outfile.h"
#include "base/worker.h"
#include "cli/print_commands.h"
#include "cli/sweep.h"
#include "cli/sweep_plot.h"

#define FIGURE_MAX_ARGS 64

/* One part of a figure: its sweep, built from the arguments `rodsim sweep`
 * would be given, and its points' state. */
typedef struct figure_part {
    const char *argv[FIGURE_MAX_ARGS];
    int argc;
    char csv[OUTFILE_PATH_MAX], png[OUTFILE_PATH_MAX], svg[OUTFILE_PATH_MAX];
    char jobs[16], plot_arg[2 * SWEEP_KEY_LEN];
    sweep sw;
    sweep_setting *set;
    sweep_progress pg;
    double *reference; /* the figure's reference at each point, the measure's unit */
} figure_part;

/* The part's results CSV and (with --print-sweep, one figure per part) its figure. */
static void figure_files(const figure_spec *fig, int k, const char *out_dir, int own_figure,
                         figure_part *part)
{
    const char *label = fig->part[k].label;
    int named = fig->parts > 1 && label[0];
    snprintf(part->csv, sizeof part->csv, "%s/%s_sweep%s%s.csv", out_dir, fig->file,
             named ? "_" : "", named ? label : "");
    snprintf(part->png, sizeof part->png, "%s/%s%s%s.png", out_dir, fig->file,
             named && own_figure ? "_" : "", named && own_figure ? label : "");
    snprintf(part->svg, sizeof part->svg, "%s/%s%s%s.svg", out_dir, fig->file,
             named && own_figure ? "_" : "", named && own_figure ? label : "");
}

/* The `rodsim sweep` arguments of part k (argv[0] "sweep", then the scene,
 * the part's own, the measure and plot, the outputs). */
static int figure_argv(const figure_spec *fig, int k, const sweep_figure_options *o,
                       figure_part *part, char *err, size_t errlen)
{
    snprintf(part->plot_arg, sizeof part->plot_arg, "%s:%s", fig->x_key, fig->measure);
    const char *const *args = o->quick ? fig->part[k].quick_args : fig->part[k].args;
    int n = 0;
    part->argv[n++] = "sweep";
    part->argv[n++] = fig->scene;
    for (int i = 0; args[i]; i++) {
        if (n == FIGURE_MAX_ARGS - 16) { /* room for the tail below */
            snprintf(err, errlen, "part %d: more than %d arguments", k, FIGURE_MAX_ARGS - 18);
            return -1;
        }
        part->argv[n++] = args[i];
    }
    snprintf(part->jobs, sizeof part->jobs, "%d",
             o->jobs < 1 ? 1 : o->jobs > WORKER_MAX_JOBS ? WORKER_MAX_JOBS : o->jobs);
    const char *tail[] = {"--measure", fig->measure, "--plot", part->plot_arg, "--png", part->png,
                          "--svg", part->svg, "--csv", part->csv, "--jobs", part->jobs};
    for (size_t i = 0; i < sizeof tail / sizeof tail[0]; i++) part->argv[n++] = tail[i];
    if (o->result_dir) {
        part->argv[n++] = "--result";
        part->argv[n++] = o->result_dir;
    }
    part->argc = n;
    if (sweep_parse_args(n, (char **)part->argv, &part->sw, err, errlen)) return -1;
    /* the scene compiled in: no checkout needed */
    const char *text = embedded_text(fig->scene);
    if (!text || !(part->sw.text = strdup(text))) {
        snprintf(err, errlen, "%s: %s", fig->scene, text ? "out of memory"
                                                         : "not compiled into this binary");
        return -1;
    }
    part->sw.text_len = strlen(text);
    snprintf(part->sw.scene_path, sizeof part->sw.scene_path, "%s", fig->scene);
    return 0;
}

/* --print-sweep: the parts as `rodsim sweep` command lines, the binary by
 * its absolute path as in --print-commands. */
static int figure_print_sweep(const figure_spec *fig, const figure_part *parts)
{
    char scene[OUTFILE_PATH_MAX], self[OUTFILE_PATH_MAX], err[SWEEP_ERR_LEN];
    if (cli_self_path(self, sizeof self, err, sizeof err)) {
        fprintf(stderr, "rodsim figure: %s\n", err);
        return RUN_EXIT_FAILURE;
    }
    /* Decision: the scene's path in the source tree, absolute when it is
     * there (run from the checkout); else as is, and the comment says so. */
    if (access(fig->scene, R_OK) != 0 ||
        cli_absolute_path(fig->scene, scene, sizeof scene, err, sizeof err))
        snprintf(scene, sizeof scene, "%s", fig->scene);
    printf("# rodsim figure %s as %d sweep%s of %s, the scene compiled into\n"
           "# rodsim (installed: PREFIX/share/rodsim/%s); the figure adds the reference\n"
           "# curves and draws the sweeps together\n",
           fig->name, fig->parts, fig->parts > 1 ? "s" : "", fig->scene, fig->scene);
    for (int k = 0; k < fig->parts; k++) {
        const figure_part *part = &parts[k];
        cli_print_shell_word(stdout, self);
        printf(" sweep ");
        cli_print_shell_word(stdout, scene);
        /* from the scene on, less the jobs and result files (a machine's choice) */
        for (int i = 2; i < part->argc; i++) {
            if (strcmp(part->argv[i], "--jobs") == 0 || strcmp(part->argv[i], "--result") == 0) {
                i++;
                continue;
            }
            putchar(' ');
            cli_print_shell_word(stdout, part->argv[i]);
        }
        putchar('\n');
    }
    return fflush(stdout) == 0 ? RUN_EXIT_OK : RUN_EXIT_FAILURE;
}

/* --print-commands: `rodsim figure NAME --point K --result DIR` per point
 * (the scene is compiled in, so each runs anywhere), then the line that
 * draws the figure from DIR. */
static int figure_print_commands(const figure_spec *fig, const figure_part *parts,
                                 const sweep_figure_options *o)
{
    char self[OUTFILE_PATH_MAX], dir[OUTFILE_PATH_MAX], out[OUTFILE_PATH_MAX];
    char err[SWEEP_ERR_LEN];
    if (cli_self_path(self, sizeof self, err, sizeof err) ||
        cli_absolute_path(o->result_dir, dir, sizeof dir, err, sizeof err) ||
        cli_absolute_path(o->out_dir, out, sizeof out, err, sizeof err)) {
        fprintf(stderr, "rodsim figure: %s\n", err);
        return RUN_EXIT_FAILURE;
    }
    int total = 0;
    for (int k = 0; k < fig->parts; k++) total += parts[k].sw.point_count;
    printf("# rodsim figure %s: %d point%s; each line runs one into %s (skipped when its\n"
           "# result file is there); then the # assemble: line draws the figure\n",
           fig->name, total, total == 1 ? "" : "s", dir);
    for (int point = 0; point < total; point++) {
        cli_print_shell_word(stdout, self);
        printf(" figure %s%s --point %d --result ", fig->name, o->quick ? " --quick" : "",
               point);
        cli_print_shell_word(stdout, dir);
        putchar('\n');
    }
    printf("# assemble: ");
    cli_print_shell_word(stdout, self);
    printf(" figure %s%s --result ", fig->name, o->quick ? " --quick" : "");
    cli_print_shell_word(stdout, dir);
    printf(" --out ");
    cli_print_shell_word(stdout, out);
    putchar('\n');
    return fflush(stdout) == 0 ? RUN_EXIT_OK : RUN_EXIT_FAILURE;
}

/* Each point's reference, once (an elastica is a shooting solve). 0, or -1
 * with a message. */
static int figure_references(const figure_spec *fig, figure_part *parts, char *err,
                             size_t errlen)
{
    for (int k = 0; k < fig->parts; k++) {
        const sweep *sw = &parts[k].sw;
        if (!(parts[k].reference = malloc(sizeof(double) * (size_t)sw->point_count))) {
            snprintf(err, errlen, "out of memory");
            return -1;
        }
        for (int point = 0; point < sw->point_count; point++) {
            const sweep_vary *v = &sw->varies[sw->plot_x];
            double x = strtod(v->values[sweep_value_index(sw, point, sw->plot_x)], NULL);
            if (fig->reference(k, x, &parts[k].reference[point], err, errlen)) return -1;
        }
    }
    return 0;
}

/* Computed, reference and relative error of every point, for people. */
static void print_figure_summary(const figure_spec *fig, const figure_part *parts)
{
    for (int k = 0; k < fig->parts; k++) {
        const sweep *sw = &parts[k].sw;
        for (int point = 0; point < sw->point_count; point++) {
            const sweep_point_result *r = &parts[k].pg.rows[point];
            double reference = parts[k].reference[point], computed = r->value[sw->plot_y];
            char what[512];
            sweep_describe_point(sw, point, what, sizeof what);
            printf("%s%s%s: %s: %s computed %.6e, reference %.6e, relative error %.2e\n",
                   fig->name, fig->part[k].label[0] ? " " : "", fig->part[k].label, what,
                   fig->measure, computed, reference, fabs(computed / reference - 1.0));
        }
    }
}

/* The message of a failure; RUN_EXIT_FAILURE. */
static int failure(const figure_spec *fig, const char *err)
{
    fprintf(stderr, "rodsim figure %s: %s\n", fig->name, err);
    return RUN_EXIT_FAILURE;
}

/* Each part's sweep from its arguments, and how many points in all. 0, or
 * -1 with a message (the figure table's fault). */
static int make_parts(const figure_spec *fig, const sweep_figure_options *o, figure_part *parts,
                      int *total, char *err, size_t errlen)
{
    *total = 0;
    for (int k = 0; k < fig->parts; k++) {
        figure_files(fig, k, o->out_dir, o->print_sweep, &parts[k]);
        if (figure_argv(fig, k, o, &parts[k], err, errlen)) return -1;
        *total += parts[k].sw.point_count;
    }
    return 0;
}

/* Where the outputs go, each part's points' scratch, and every point
 * checked before any runs. 0, or -1 with a message. */
static int prepare_parts(const figure_spec *fig, const sweep_figure_options *o,
                         figure_part *parts, char *err, size_t errlen)
{
    if (!o->print_commands && o->point < 0 && outfile_mkdirs(o->out_dir, err, errlen)) return -1;
    for (int k = 0; k < fig->parts; k++) {
        figure_part *part = &parts[k];
        sweep *sw = &part->sw;
        int n = sw->point_count;
        part->set = calloc((size_t)(sw->sets.count + sw->vary_count + 1), sizeof *part->set);
        part->pg = (sweep_progress){.sw = sw};
        part->pg.rows = calloc((size_t)n, sizeof *part->pg.rows);
        part->pg.digests = calloc((size_t)n, sizeof *part->pg.digests);
        part->pg.done = calloc((size_t)n, sizeof *part->pg.done);
        if (!part->set || !part->pg.rows || !part->pg.digests || !part->pg.done) {
            snprintf(err, errlen, "out of memory for %d point%s", n, n == 1 ? "" : "s");
            return -1;
        }
        if ((!o->print_commands && o->point < 0 && sweep_check_outputs(sw, err, errlen)) ||
            sweep_read_bases(sw, err, errlen) ||
            sweep_check_points(sw, part->set, part->pg.digests, err, errlen))
            return -1;
    }
    return 0;
}

/* The points whose result files are not there (or --point K only) run.
 * 0, or -1 with a message. */
static int run_parts(const figure_spec *fig, const sweep_figure_options *o, figure_part *parts,
                     char *err, size_t errlen)
{
    if (o->result_dir && outfile_mkdirs(o->result_dir, err, errlen)) return -1;
    for (int k = 0, first = 0; k < fig->parts; first += parts[k++].sw.point_count) {
        sweep_progress *pg = &parts[k].pg;
        const sweep *sw = pg->sw;
        for (int point = 0; point < sw->point_count; point++) {
            int got = 0;
            if (o->result_dir &&
                (got = sweep_read_result(sw, pg->digests[point], &pg->rows[point], err,
                                         errlen)) < 0)
                return -1;
            /* --point K: only K is left to run */
            pg->done[point] = got || (o->point >= 0 && o->point != first + point);
            pg->reused += got;
        }
        if (sweep_run_points(pg, err, errlen)) return -1;
        if (pg->failed_writes) {
            snprintf(err, errlen, "%d result files could not be written", pg->failed_writes);
            return -1;
        }
    }
    return 0;
}

/* Every point is ok, or the figure is not drawn. 0, or -1 with a message. */
static int check_all_ok(const figure_spec *fig, const figure_part *parts, char *err,
                        size_t errlen)
{
    for (int k = 0; k < fig->parts; k++)
        for (int point = 0; point < parts[k].sw.point_count; point++) {
            const sweep_point_result *r = &parts[k].pg.rows[point];
            if (r->status == SWEEP_POINT_OK) continue;
            char what[512];
            sweep_describe_point(&parts[k].sw, point, what, sizeof what);
            /* the message cut to what err holds beside the point */
            snprintf(err, errlen, "point %s: %s: %.1400s; nothing drawn", what,
                     sweep_status_names[r->status], r->message);
            return -1;
        }
    return 0;
}

/* The parts' CSVs and the figure with its data: all or none (outfile.h;
 * the caller aborts a transaction left open); then the summary. 0, or -1
 * with a message. */
static int draw_figure(const figure_spec *fig, figure_part *parts, char *err, size_t errlen)
{
    if (check_all_ok(fig, parts, err, errlen) || figure_references(fig, parts, err, errlen))
        return -1;
    const sweep *sws[FIGURE_SPEC_MAX_PARTS];
    const sweep_point_result *rows[FIGURE_SPEC_MAX_PARTS];
    const double *references[FIGURE_SPEC_MAX_PARTS];
    outfile_transaction_begin();
    for (int k = 0; k < fig->parts; k++) {
        outfile csv = {.fd = -1, .slot = -1};
        sws[k] = &parts[k].sw;
        rows[k] = parts[k].pg.rows;
        references[k] = parts[k].reference;
        if (outfile_open(&csv, parts[k].sw.csv, err, errlen)) return -1;
        sweep_write_csv(csv.fp, &parts[k].sw, parts[k].pg.rows);
        if (ferror(csv.fp)) {
            outfile_abort(&csv);
            snprintf(err, errlen, "%s: write failed (disk full?)", parts[k].sw.csv);
            return -1;
        }
        if (outfile_commit(&csv, err, errlen)) return -1;
    }
    if (sweep_plot_write(sws, rows, fig->parts, fig, references, err, errlen) ||
        outfile_transaction_commit(err, errlen))
        return -1;
    print_figure_summary(fig, parts);
    for (int k = 0; k < fig->parts; k++) printf("wrote %s\n", parts[k].sw.csv);
    printf("wrote %s\nwrote %s\nwrote %s\n", parts[0].sw.png, parts[0].sw.svg,
           parts[0].sw.plot_csv);
    if (fig->ratio_divisor) {
        char path[OUTFILE_PATH_MAX + 8];
        sweep_ratio_path(parts[0].sw.png, path, sizeof path);
        printf("wrote %s\n", path);
        sweep_ratio_path(parts[0].sw.svg, path, sizeof path);
        printf("wrote %s\n", path);
    }
    return 0;
}

int sweep_figure_command(const figure_spec *fig, const sweep_figure_options *o)
{
    char err[SWEEP_ERR_LEN] = "";
    int status, total = 0;
    figure_part *parts = calloc((size_t)fig->parts, sizeof *parts);
    if (!parts) {
        fprintf(stderr, "rodsim figure %s: out of memory\n", fig->name);
        return RUN_EXIT_FAILURE;
    }
    if (make_parts(fig, o, parts, &total, err, sizeof err)) {
        status = failure(fig, err);
    } else if (o->print_sweep) {
        status = figure_print_sweep(fig, parts);
    } else if (o->point >= total) {
        fprintf(stderr, "rodsim figure %s: --point %d: accepted 0 .. %d%s\n", fig->name,
                o->point, total - 1, o->quick ? " (with --quick)" : "");
        status = RUN_EXIT_BAD_INPUT;
    } else if (prepare_parts(fig, o, parts, err, sizeof err)) {
        status = failure(fig, err);
    } else if (o->print_commands) {
        status = figure_print_commands(fig, parts, o);
    } else if (run_parts(fig, o, parts, err, sizeof err)) {
        status = failure(fig, err);
    } else if (o->point >= 0) {
        status = RUN_EXIT_OK;
    } else {
        status = draw_figure(fig, parts, err, sizeof err) ? failure(fig, err) : RUN_EXIT_OK;
    }
    if (outfile_transaction_active()) outfile_transaction_abort();
    for (int k = 0; k < fig->parts; k++) {
        free(parts[k].set);
        free(parts[k].pg.rows);
        free(parts[k].pg.digests);
        free(parts[k].pg.done);
        free(parts[k].reference);
        sweep_release(&parts[k].sw);
    }
    free(parts);
    return status;
}
