/* stability_cli.c: `rodsim stability`: table, CSV and map of the largest
 * stable dt per scheme (stability.h). */
#include "cli/stability_cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/outfile.h"
#include "base/worker.h"
#include "cli/args.h"
#include "sim/rod.h"

static const char *load_text(const stability_case *c, char *buf, size_t n)
{
    if (c->load == STABILITY_LOAD_NONE) snprintf(buf, n, "none");
    else snprintf(buf, n, "%s x%g", c->load == STABILITY_LOAD_AXIAL ? "axial" : "transverse",
                  c->load_factor);
    return buf;
}

/* "none", ">= 10", or the number. */
static const char *measured_text(const stability_row *r, char *buf, size_t n)
{
    if (r->scheme == ROD_SCHEME_STATIC) snprintf(buf, n, "-");
    else if (r->measured_dt <= 0.0) snprintf(buf, n, "none");
    else if (r->unstable_dt <= 0.0) snprintf(buf, n, ">=%.3g", r->measured_dt);
    else snprintf(buf, n, "%.4g", r->measured_dt);
    return buf;
}

static const char *number_text(double x, char *buf, size_t n)
{
    if (isinf(x)) snprintf(buf, n, "inf");
    else if (x <= 0.0) snprintf(buf, n, "none");
    else snprintf(buf, n, "%.4g", x);
    return buf;
}

/* What ended the runs at the edge: the failing trial's outcome, or the
 * static solve's. */
static stability_outcome row_outcome(const stability_row *r)
{
    return r->first_failure.outcome;
}

void stability_print_table(FILE *f, const stability_row *rows, int n)
{
    fprintf(f, "%-30s %-8s %5s %8s %7s %6s %-15s %8s %10s %10s %8s %10s %10s %7s %-14s %6s %7s\n",
            "case", "scheme", "NS", "E [Pa]", "d [m]", "L [m]", "load", "scale",
            "EB dt [s]", "twist [s]", "gain", "predicted", "measured", "ratio", "beyond",
            "trials", "wall s");
    for (int k = 0; k < n; k++) {
        const stability_row *r = &rows[k];
        const stability_prediction *p = &r->predicted;
        char load[32], meas[32], eb[32], tw[32], pred[32], ratio[32];
        double rt = r->measured_dt > 0.0 && r->unstable_dt > 0.0 && isfinite(p->scheme_dt) &&
                            p->scheme_dt > 0.0
                        ? r->measured_dt / p->scheme_dt
                        : NAN;
        if (isnan(rt)) snprintf(ratio, sizeof ratio, "-");
        else snprintf(ratio, sizeof ratio, "%.4f", rt);
        fprintf(f, "%-30s %-8s %5d %8.3g %7.2g %6.3g %-15s %8.3g %10s %10s %8.3g %10s %10s %7s "
                   "%-14s %6d %7.2f%s\n",
                r->c.name, rod_scheme_get(r->scheme)->name, r->c.nodes, r->c.youngs_modulus,
                r->c.diameter, r->c.length, load_text(&r->c, load, sizeof load),
                p->rotary_inertia_scale, number_text(p->euler_bernoulli_dt, eb, sizeof eb),
                number_text(p->twist_dt, tw, sizeof tw), p->rotary_inertia_gain,
                r->scheme == ROD_SCHEME_STATIC ? "-" : number_text(p->scheme_dt, pred, sizeof pred),
                measured_text(r, meas, sizeof meas), ratio,
                stability_outcome_name(row_outcome(r)), r->trials, r->wall_seconds,
                r->finding ? "  FINDING" : "");
    }
    /* what stopped the runs that never ran, and every finding, in words */
    int printed = 0;
    for (int k = 0; k < n; k++) {
        const stability_row *r = &rows[k];
        int never = r->scheme != ROD_SCHEME_STATIC && r->measured_dt <= 0.0;
        /* short of the prediction (a load, a nonlinearity), or an implicit limit */
        int short_of = r->unstable_dt > 0.0 &&
                       (!isfinite(r->predicted.scheme_dt) ||
                        r->measured_dt < 0.9 * r->predicted.scheme_dt);
        int static_failed = r->scheme == ROD_SCHEME_STATIC && row_outcome(r) != STABILITY_STABLE;
        if (!never && !static_failed && !r->finding && !short_of) continue;
        if (!printed++)
            fprintf(f, "\nwhat stopped the runs that never completed, fell short of the "
                       "prediction, or are findings (at the smallest unstable dt):\n");
        fprintf(f, "  %s, %s, NS %d, dt %.3g s: %s: %.300s\n", r->c.name,
                rod_scheme_get(r->scheme)->name, r->c.nodes, r->first_failure.dt,
                stability_outcome_name(row_outcome(r)), r->first_failure.message);
    }
}

int stability_write_csv(const char *path, const stability_row *rows, int n, char *err,
                        size_t errlen)
{
    outfile out;
    if (outfile_open(&out, path, err, errlen)) return -1;
    FILE *f = out.fp;
    fprintf(f, "case,scheme,nodes,youngs_modulus,diameter,length,load,load_factor,"
               "rotary_inertia_scale,euler_bernoulli_dt,twist_dt,rotation_wave_dt,"
               "rotary_inertia_gain,predicted_dt,measured_dt,unstable_dt,outcome,trials,"
               "wall_seconds,finding\n");
    for (int k = 0; k < n; k++) {
        const stability_row *r = &rows[k];
        const stability_prediction *p = &r->predicted;
        static const char *const loads[] = {"none", "transverse", "axial"};
        fprintf(f, "\"%s\",%s,%d,%.6g,%.6g,%.6g,%s,%g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%s,%d,"
                   "%.4f,%d\n",
                r->c.name, rod_scheme_get(r->scheme)->name, r->c.nodes, r->c.youngs_modulus,
                r->c.diameter, r->c.length, loads[r->c.load], r->c.load_factor,
                p->rotary_inertia_scale, p->euler_bernoulli_dt, p->twist_dt, p->rotation_wave_dt,
                p->rotary_inertia_gain, p->scheme_dt, r->measured_dt, r->unstable_dt,
                stability_outcome_name(row_outcome(r)), r->trials, r->wall_seconds, r->finding);
    }
    if (ferror(f)) {
        snprintf(err, errlen, "%s: write error", path);
        outfile_abort(&out);
        return -1;
    }
    return outfile_commit(&out, err, errlen);
}

static int is_map_row(const stability_row *r)
{
    return strcmp(r->c.name, "table1") == 0 && r->c.load == STABILITY_LOAD_NONE &&
           !r->c.physical_inertia;
}

plot *stability_map_create(const stability_row *rows, int n)
{
    double *x = calloc((size_t)n, sizeof *x), *y = calloc((size_t)n, sizeof *y);
    double *eb = calloc((size_t)n, sizeof *eb), *tw = calloc((size_t)n, sizeof *tw);
    double *yi = calloc((size_t)n, sizeof *yi), *xi = calloc((size_t)n, sizeof *xi);
    double *pred = calloc((size_t)n, sizeof *pred);
    plot *p = NULL;
    if (!x || !y || !eb || !tw || !yi || !xi || !pred) goto done;
    int nt = 0, ni = 0;
    for (int k = 0; k < n; k++) {
        const stability_row *r = &rows[k];
        if (!is_map_row(r)) continue;
        if (r->scheme == ROD_SCHEME_THESIS && r->measured_dt > 0.0) {
            x[nt] = r->c.nodes;
            y[nt] = r->measured_dt;
            pred[nt] = r->predicted.scheme_dt;
            eb[nt] = r->predicted.euler_bernoulli_dt;
            tw[nt] = r->predicted.twist_dt;
            nt++;
        }
        if (r->scheme == ROD_SCHEME_IMPLICIT && r->measured_dt > 0.0) {
            xi[ni] = r->c.nodes;
            yi[ni] = r->measured_dt;
            ni++;
        }
    }
    if (nt < 2 && ni < 1) goto done;
    p = plot_create(1100, 700);
    if (!p) goto done;
    plot_set_title(p, "Largest stable dt against resolution (table 1 rod: L = 1 m, d = 1 mm)");
    plot_set_axis_labels(p, "nodes NS", "largest stable dt [s]");
    plot_set_log(p, 1, 1);
    int rc = 0;
    if (nt >= 2) {
        rc |= plot_add_line(p, x, pred, nt, plot_style_line(30, 90, 200, 2, PLOT_SOLID),
                            "thesis: predicted (stable_dt, scale 2 x 64L^2/(pi^2 d^2))");
        rc |= plot_add_line(p, x, tw, nt, plot_style_line(30, 150, 60, 2, PLOT_DOTTED),
                            "twist 2 ds/sqrt(G/(rho s)), same scale");
        rc |= plot_add_line(p, x, eb, nt, plot_style_line(120, 120, 120, 2, PLOT_DASHED),
                            "no rotary inertia: 2 ds^2 sqrt(m/EI)");
        plot_style mark = plot_style_line(30, 90, 200, 2, PLOT_SOLID);
        mark.marker_size = 10;
        rc |= plot_add_markers(p, x, y, nt, mark, NULL, 0, 0, "thesis: measured (bisection)");
    }
    if (ni >= 1) {
        plot_style mark = plot_style_line(200, 60, 40, 2, PLOT_SOLID);
        mark.marker_size = 10;
        mark.filled = 1;
        mark.fill_rgb[0] = 200;
        mark.fill_rgb[1] = 60;
        mark.fill_rgb[2] = 40;
        rc |= plot_add_markers(p, xi, yi, ni, mark, NULL, 0, 0,
                               "implicit: stable at the largest dt tried");
    }
    if (rc) {
        plot_destroy(p);
        p = NULL;
    }
done:
    free(x);
    free(y);
    free(eb);
    free(tw);
    free(yi);
    free(xi);
    free(pred);
    return p;
}

static void usage(FILE *f)
{
    fprintf(f,
            "usage: rodsim stability [--scheme S]... [--quick] [--csv FILE] [--png FILE] [--jobs N]\n"
            "  For each scheme (thesis, implicit, static; default all), the largest stable dt by\n"
            "  bisection over NS 11..1001, E 1e5..2e11 Pa, d 0.1..10 mm, L 1 cm..100 m and tip\n"
            "  loads up to 100 x pi^2 EI/(4 L^2), against the predicted limits. Each trial runs\n"
            "  in a child process with a wall-time limit, so a hang or a crash is reported.\n"
            "  --quick      a reduced grid (NS <= 21), shorter trials\n"
            "  --csv FILE   the table as CSV\n"
            "  --png FILE   the map: largest stable dt against NS, log-log\n"
            "  --jobs N     rows computed by N processes at a time (default 1)\n"
            "exit status: 0 every run completed or stopped with the scheme's message; 1 a finding\n"
            "(crash, hang, NaN without a message) or an output not written; 2 usage; 130 SIGINT,\n"
            "143 SIGTERM.\n");
}

/* The grid over the schemes: the table, then the CSV and the map. An exit
 * status. */
static int stability_run(const rod_scheme_kind *schemes, int n_schemes, int quick, int jobs,
                         const char *csv, const char *png)
{
    int n_cases = 0;
    const stability_case *cases = stability_grid(quick, &n_cases);
    stability_options o = stability_options_default(quick);
    int n = n_cases * n_schemes;
    stability_row *rows = calloc((size_t)n, sizeof *rows);
    if (!rows) {
        fprintf(stderr, "rodsim stability: out of memory\n");
        return 1;
    }
    printf("rodsim stability: %d cases x %d schemes, %d steps per explicit trial, %d per implicit "
           "trial, dt in [%g, %g] s, bisection to %g, %g s wall limit per trial, %d jobs\n",
           n_cases, n_schemes, o.steps, o.implicit_steps, o.dt_min, o.dt_max,
           o.relative_tolerance, o.trial_wall_limit, jobs);
    printf("stable: every step OK, finite, kinetic energy below 100 x (initial + 2 L |F|).\n"
           "EB dt = 2 ds^2 sqrt(m/EI) (no rotary inertia); twist = 2 ds/sqrt(G/(rho s)); gain = "
           "2 ds sqrt(rho s/E) / EB dt;\npredicted = the scheme's stable_dt; ratio = measured / "
           "predicted; beyond = what ended the runs just above the measured dt.\n\n");
    fflush(stdout);
    char err[512] = "";
    int status = 0;
    if (stability_sweep(cases, n_cases, schemes, n_schemes, &o, jobs, rows, err, sizeof err)) {
        fprintf(stderr, "rodsim stability: %s\n", err);
        free(rows);
        return 1;
    }
    stability_print_table(stdout, rows, n);
    int findings = 0;
    for (int k = 0; k < n; k++) findings += rows[k].finding;
    printf("\n%d runs: %d findings (crash, hang or NaN without a message)\n", n, findings);
    if (findings) status = 1;
    if (csv && stability_write_csv(csv, rows, n, err, sizeof err)) {
        fprintf(stderr, "rodsim stability: %s\n", err);
        status = 1;
    }
    if (png) {
        plot *p = stability_map_create(rows, n);
        if (!p) {
            fprintf(stderr, "rodsim stability: nothing to draw in %s (the map needs the thesis "
                            "or implicit rows of table 1's rod)\n", png);
            status = 1;
        } else {
            if (plot_write_png(p, png, err, sizeof err)) {
                fprintf(stderr, "rodsim stability: %s\n", err);
                status = 1;
            } else {
                printf("map written to %s\n", png);
            }
            plot_destroy(p);
        }
    }
    free(rows);
    return status;
}

/* --scheme NAME: a scheme, each once. 0, or -1 with a message. */
static int add_scheme(const char *name, rod_scheme_kind *schemes, int *n, char *err,
                      size_t errlen)
{
    rod_scheme_kind kind;
    if (!rod_scheme_find(name, &kind)) {
        cli_unknown_name(err, errlen, "--scheme", name, "scheme", cli_scheme_names());
        return -1;
    }
    for (int k = 0; k < *n; k++)
        if (schemes[k] == kind) return 0;
    schemes[(*n)++] = kind;
    return 0;
}

int stability_command(int argc, char **argv)
{
    rod_scheme_kind schemes[ROD_SCHEME_COUNT];
    int n_schemes = 0, quick = 0, jobs = 1;
    const char *csv = NULL, *png = NULL;
    cli_list scheme_names = {0};
    char err[512] = "";
    const cli_option options[] = {
        {.name = "--quick", .value = CLI_FLAG, .target = &quick},
        {.name = "--scheme", .value = CLI_WORD, .target = &scheme_names, .repeated = 1,
         .noun = "a scheme"},
        {.name = "--csv", .value = CLI_FILE, .target = &csv},
        {.name = "--png", .value = CLI_FILE, .target = &png},
        {.name = "--jobs", .value = CLI_COUNT, .target = &jobs, .lo = 1,
         .hi = WORKER_MAX_JOBS},
        {0}};
    int parsed = cli_parse(argc, argv, options, NULL, err, sizeof err);
    for (int i = 0; parsed == CLI_PARSED && i < scheme_names.count; i++)
        if (add_scheme(scheme_names.items[i], schemes, &n_schemes, err, sizeof err))
            parsed = CLI_ERROR;
    cli_release(options);
    if (parsed == CLI_HELP) {
        usage(stdout);
        return RUN_EXIT_OK;
    }
    if (parsed != CLI_PARSED) return cli_usage_error("stability", err);
    if (n_schemes == 0)
        for (int k = 0; k < ROD_SCHEME_COUNT; k++) schemes[n_schemes++] = (rod_scheme_kind)k;
    char where[1024];
    if ((csv && cli_check_output_file("--csv", csv, where, sizeof where)) ||
        (png && cli_check_output_file("--png", png, where, sizeof where)))
        return cli_usage_error("stability", where); /* before the trials, not after */
    return stability_run(schemes, n_schemes, quick, jobs, csv, png);
}
