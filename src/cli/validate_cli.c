/* validate_cli.c: `rodsim validate` (see validate_cli.h). The plan is a list
 * of points (case, scheme, NS, dt); each runs in this process, or with
 * --jobs N in forked worker processes (one per point, the row sent back
 * through a pipe). Rows print in plan order as soon as they and every row
 * before them are done. */
#include "cli/validate_cli.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "base/outfile.h"
#include "base/worker.h"
#include "cli/args.h"
#include "cli/print_commands.h"
#include "sim/rod.h"
#include "study/validate.h"

enum { max_list = 64, max_points = 4096 };

static const int full_nodes[] = {11, 21, 51, 101, 201};
static const int quick_nodes[] = {11, 21};
/* dt sweep at the finest NS (where the error in ds is smallest), as
 * multiples of the case's default dt: the implicit default (2000 steps per
 * period) is so fine that its time error hides under the error in ds, so the
 * sweep takes 100, 50 and 25 steps per period; the thesis default sits at
 * half its stable limit, so the sweep refines it. */
static const double implicit_dt_factors[] = {20.0, 40.0, 80.0};
static const double thesis_dt_factors[] = {0.5, 0.25};

typedef struct point {
    int case_index;
    rod_scheme_kind scheme;
    int nodes;
    double dt;       /* s; 0: the case's default */
    int ds_sweep;    /* counts for the order in ds */
    int dt_sweep;    /* counts for the order in dt */
    int precomputed; /* row already filled (not applicable) */
} point;

typedef struct plan {
    point points[max_points];
    validate_row rows[max_points];
    int done[max_points];
    int count;
} plan;

static void usage(FILE *out)
{
    fprintf(out,
            "usage: rodsim validate [--case NAME]... [--scheme NAME]... [--nodes N]... [--dt DT]...\n"
            "                       [--quick] [--csv FILE|-] [--jobs N] [--print-commands]\n\n"
            "One row per run against an independent reference (computed, reference, relative\n"
            "error, wall time), then the observed orders of convergence in ds and dt.\n"
            "  --case NAME    repeatable; default all:");
    int column = 40;
    for (const char *const *n = validate_case_names(); *n; n++) {
        if (column + 1 + (int)strlen(*n) > 84) {
            fprintf(out, "\n                ");
            column = 16;
        }
        column += fprintf(out, " %s", *n);
    }
    fprintf(out,
            "\n  --scheme NAME  thesis | implicit | static (repeatable; default all)\n"
            "  --nodes N      NS, 3..100001 (repeatable; default 11 21 51 101 201)\n"
            "  --dt DT        s (repeatable; default: per case, and a dt sweep at the finest NS)\n"
            "  --quick        NS 11 and 21, shorter frequency runs (the tests' set, seconds)\n"
            "  --csv FILE     also the rows as CSV (- for stdout, then no table)\n"
            "  --jobs N       N worker processes (1..64; default 1)\n"
            "  --print-commands  one command line per point instead of running them\n"
            "exit status: 0 every applicable row ran (errors are data), 1 a run failed, 2 usage;\n"
            "130 SIGINT, 143 SIGTERM.\n");
}

static int parse_int(const char *text, long lo, long hi, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (errno || end == text || *end || v < lo || v > hi) return -1;
    *out = (int)v;
    return 0;
}

static int parse_positive(const char *text, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(text, &end);
    if (errno || end == text || *end || !isfinite(v) || v <= 0.0) return -1;
    *out = v;
    return 0;
}

static const char *status_word(int status)
{
    return status == 0 ? "ok" : status == 1 ? "n/a" : "FAILED";
}

static void print_header(void)
{
    printf("%-23s %-8s %5s %10s %14s %14s %10s %8s %-6s %s\n", "case", "scheme", "NS", "dt [s]",
           "computed", "reference", "rel.error", "wall [s]", "status", "quantity; note");
}

static void print_row(const validate_row *r)
{
    char dt[16], nodes[16];
    if (r->dt > 0.0) snprintf(dt, sizeof dt, "%.4g", r->dt);
    else snprintf(dt, sizeof dt, "%s", r->status == 1 ? "-" : "static");
    if (r->nodes > 0) snprintf(nodes, sizeof nodes, "%d", r->nodes);
    else snprintf(nodes, sizeof nodes, "-");
    printf("%-23s %-8s %5s %10s %14.8g %14.8g %10.3e %8.3f %-6s %s%s%s\n", r->case_name, r->scheme,
           nodes, dt, r->computed, r->reference, r->relative_error, r->wall_seconds,
           status_word(r->status), r->quantity, r->note[0] ? "; " : "", r->note);
    fflush(stdout);
}

static void csv_field(FILE *f, const char *text)
{
    fputc('"', f);
    for (const char *c = text; *c; c++) {
        if (*c == '"') fputc('"', f);
        fputc(*c, f);
    }
    fputc('"', f);
}

static void write_csv_rows(FILE *f, const plan *p)
{
    fprintf(f, "case,scheme,nodes,dt,computed,reference,relative_error,wall_seconds,status,"
               "quantity,note\n");
    for (int k = 0; k < p->count; k++) {
        const validate_row *r = &p->rows[k];
        /* status as the table words it (ok, n/a, FAILED), not validate_row's code */
        fprintf(f, "%s,%s,%d,%.9g,%.12g,%.12g,%.6e,%.6f,%s,", r->case_name, r->scheme, r->nodes,
                r->dt, r->computed, r->reference, r->relative_error, r->wall_seconds,
                status_word(r->status));
        csv_field(f, r->quantity);
        fputc(',', f);
        csv_field(f, r->note);
        fputc('\n', f);
    }
}

static int add_point(plan *p, point pt)
{
    if (p->count >= max_points) return -1;
    p->points[p->count++] = pt;
    return 0;
}

/* Prints every finished row not yet printed, in plan order. */
static void flush_rows(plan *p, int *printed, int table)
{
    while (*printed < p->count && p->done[*printed]) {
        if (table) print_row(&p->rows[*printed]);
        (*printed)++;
    }
}

static void run_point(const point *pt, validate_row *row)
{
    validate_run(validate_case_names()[pt->case_index], pt->scheme, pt->nodes, pt->dt, row);
}

typedef struct pool_context {
    plan *p;
    int table, *printed;
} pool_context;

static int pool_run_point(void *context, int k, FILE *out)
{
    const pool_context *c = context;
    validate_row row;
    run_point(&c->p->points[k], &row);
    return fwrite(&row, sizeof row, 1, out) == 1 ? 0 : 1;
}

/* A worker that died leaves a failed row saying so. */
static int pool_point_done(void *context, int k, const char *bytes, size_t n, int status)
{
    pool_context *c = context;
    plan *p = c->p;
    validate_row *row = &p->rows[k];
    if (status == 0 && n == sizeof *row) {
        memcpy(row, bytes, sizeof *row);
    } else {
        const point *pt = &p->points[k];
        memset(row, 0, sizeof *row);
        snprintf(row->case_name, sizeof row->case_name, "%s",
                 validate_case_names()[pt->case_index]);
        snprintf(row->scheme, sizeof row->scheme, "%s", rod_scheme_get(pt->scheme)->name);
        row->nodes = pt->nodes;
        row->dt = pt->dt;
        row->computed = row->reference = row->relative_error = NAN;
        row->status = 2;
        snprintf(row->note, sizeof row->note, "worker process died (%s %d)",
                 WIFSIGNALED(status) ? "signal" : "exit status",
                 WIFSIGNALED(status) ? WTERMSIG(status) : WEXITSTATUS(status));
    }
    p->done[k] = 1;
    flush_rows(p, c->printed, c->table);
    return 0;
}

/* Runs the points not done yet in up to `jobs` forked workers (worker.h;
 * jobs 1: here), printing the rows in plan order as they come. */
static int run_points(plan *p, int jobs, int table, int *printed, char *err, size_t errlen)
{
    int *todo = malloc(sizeof(int) * (size_t)(p->count + 1)), count = 0;
    if (!todo) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    for (int k = 0; k < p->count; k++)
        if (!p->done[k]) todo[count++] = k;
    flush_rows(p, printed, table);
    pool_context c = {p, table, printed};
    worker_pool pool = {.jobs = jobs, .context = &c, .run = pool_run_point,
                        .done = pool_point_done};
    int rc = worker_pool_run(&pool, todo, count, err, errlen);
    free(todo);
    return rc ? -1 : 0;
}

/* Observed orders: least-squares slope of log(error) over log(h) for the
 * rows of one case and scheme in a sweep, and the successive local orders
 * log(e_k/e_k+1)/log(h_k/h_k+1). */
static void print_orders(const plan *p)
{
    printf("\nobserved order of convergence (least-squares slope of log relative error against "
           "log h over the runs; local orders between successive runs in brackets):\n");
    for (int k = 0; k < p->count; k++) {
        const point *pt = &p->points[k];
        int first = 1;
        for (int j = 0; j < k; j++)
            if (p->points[j].case_index == pt->case_index && p->points[j].scheme == pt->scheme)
                first = 0;
        if (!first) continue;
        for (int sweep = 0; sweep < 2; sweep++) {
            double h[max_list], err[max_list];
            int n = 0;
            double largest = 0.0;
            for (int j = k; j < p->count && n < max_list; j++) {
                const point *q = &p->points[j];
                const validate_row *r = &p->rows[j];
                if (q->case_index != pt->case_index || q->scheme != pt->scheme) continue;
                if (!(sweep == 0 ? q->ds_sweep : q->dt_sweep) || r->status != 0) continue;
                h[n] = sweep == 0 ? 1.0 / (r->nodes - 1) : r->dt;
                err[n] = r->relative_error;
                largest = fmax(largest, err[n]);
                n++;
            }
            if (n < 2) continue;
            printf("  %-23s %-8s in %s: ", validate_case_names()[pt->case_index],
                   rod_scheme_get(pt->scheme)->name, sweep == 0 ? "ds" : "dt");
            if (largest < 1e-6) {
                /* round-off, Newton tolerance or the residual motion of a settling run */
                printf("every error <= %.1e over %d runs: no discretisation error to observe\n",
                       largest, n);
                continue;
            }
            /* sort by h, largest first */
            for (int a = 0; a < n; a++)
                for (int b = a + 1; b < n; b++)
                    if (h[b] > h[a]) {
                        double t = h[a]; h[a] = h[b]; h[b] = t;
                        t = err[a]; err[a] = err[b]; err[b] = t;
                    }
            printf("%.2f over %d runs [", validate_order_fit(h, err, n), n);
            for (int a = 0; a + 1 < n; a++)
                printf("%s%.2f", a ? " " : "", log(err[a] / err[a + 1]) / log(h[a] / h[a + 1]));
            printf("]\n");
        }
    }
}

/* What `rodsim validate` was asked for, the defaults filled in. */
typedef struct validate_args {
    int case_list[max_list], case_count;
    rod_scheme_kind scheme_list[ROD_SCHEME_COUNT * 4];
    int scheme_count;
    int node_list[max_list], node_count;
    double dt_list[max_list]; /* s */
    int dt_count, quick, jobs, print_commands;
    const char *csv; /* "-": standard output, then no table */
} validate_args;

/* The repeated options' values into the lists. 0, or -1 with a message. */
static int read_lists(validate_args *a, const cli_list *cases, const cli_list *schemes,
                      const cli_list *nodes, const cli_list *dts, char *err, size_t errlen)
{
    for (int i = 0; i < cases->count; i++) {
        int c = validate_case_index(cases->items[i]);
        if (c < 0) {
            cli_unknown_name(err, errlen, "--case", cases->items[i], "case",
                             validate_case_names());
            return -1;
        }
        if (a->case_count < max_list) a->case_list[a->case_count++] = c;
    }
    for (int i = 0; i < schemes->count; i++) {
        rod_scheme_kind kind;
        if (!rod_scheme_find(schemes->items[i], &kind)) {
            cli_unknown_name(err, errlen, "--scheme", schemes->items[i], "scheme",
                             cli_scheme_names());
            return -1;
        }
        if (a->scheme_count < (int)(sizeof a->scheme_list / sizeof a->scheme_list[0]))
            a->scheme_list[a->scheme_count++] = kind;
    }
    for (int i = 0; i < nodes->count; i++) {
        int n;
        if (parse_int(nodes->items[i], 3, 100001, &n) || a->node_count >= max_list) {
            snprintf(err, errlen, "--nodes '%s': accepted: an integer 3..100001 (at most %d "
                                  "values)", nodes->items[i], max_list);
            return -1;
        }
        a->node_list[a->node_count++] = n;
    }
    for (int i = 0; i < dts->count; i++) {
        double dt;
        if (parse_positive(dts->items[i], &dt) || a->dt_count >= max_list) {
            snprintf(err, errlen, "--dt '%s': accepted: a time step > 0 s (at most %d values)",
                     dts->items[i], max_list);
            return -1;
        }
        a->dt_list[a->dt_count++] = dt;
    }
    return 0;
}

/* Every case, scheme and the default NS where none was given. */
static void fill_defaults(validate_args *a)
{
    const char *const *names = validate_case_names();
    if (a->case_count == 0)
        for (int c = 0; names[c]; c++) a->case_list[a->case_count++] = c;
    if (a->scheme_count == 0)
        for (int s = 0; s < ROD_SCHEME_COUNT; s++)
            a->scheme_list[a->scheme_count++] = (rod_scheme_kind)s;
    if (a->node_count == 0) {
        const int *defaults = a->quick ? quick_nodes : full_nodes;
        a->node_count = a->quick ? 2 : 5;
        for (int k = 0; k < a->node_count; k++) a->node_list[k] = defaults[k];
    }
}

/* CLI_PARSED (defaults filled in), CLI_HELP, or CLI_ERROR with a message. */
static int parse_args(int argc, char **argv, validate_args *a, char *err, size_t errlen)
{
    cli_list cases = {0}, schemes = {0}, nodes = {0}, dts = {0};
    memset(a, 0, sizeof *a);
    a->jobs = 1;
    const cli_option options[] = {
        {.name = "--quick", .value = CLI_FLAG, .target = &a->quick},
        {.name = "--print-commands", .value = CLI_FLAG, .target = &a->print_commands},
        {.name = "--case", .value = CLI_WORD, .target = &cases, .repeated = 1, .noun = "a case"},
        {.name = "--scheme", .value = CLI_WORD, .target = &schemes, .repeated = 1,
         .noun = "a scheme"},
        {.name = "--nodes", .value = CLI_WORD, .target = &nodes, .repeated = 1, .noun = "NS"},
        {.name = "--dt", .value = CLI_WORD, .target = &dts, .repeated = 1, .noun = "a time step"},
        {.name = "--csv", .value = CLI_OUTPUT, .target = &a->csv},
        {.name = "--jobs", .value = CLI_COUNT, .target = &a->jobs, .lo = 1,
         .hi = WORKER_MAX_JOBS},
        {0}};
    int parsed = cli_parse(argc, argv, options, NULL, err, errlen);
    if (parsed == CLI_PARSED && read_lists(a, &cases, &schemes, &nodes, &dts, err, errlen))
        parsed = CLI_ERROR;
    cli_release(options);
    if (parsed == CLI_PARSED) fill_defaults(a);
    return parsed;
}

/* The points of one case and scheme that applies: each NS (at each --dt),
 * then the dt sweep at the finest NS. 0, or -1 when the plan is full. */
static int plan_case(plan *p, const validate_args *a, int case_index, rod_scheme_kind scheme,
                     int finest_nodes)
{
    const char *name = validate_case_names()[case_index];
    int too_many = 0, dynamic = validate_case_depends_on_dt(name, scheme);
    point base = {.case_index = case_index, .scheme = scheme};
    for (int ni = 0; ni < a->node_count; ni++) {
        base.nodes = a->node_list[ni];
        if (a->dt_count > 0) {
            for (int di = 0; di < a->dt_count; di++) {
                base.dt = a->dt_list[di];
                base.ds_sweep = di == 0;
                base.dt_sweep = dynamic && base.nodes == finest_nodes;
                too_many |= add_point(p, base) != 0;
            }
        } else {
            /* quick: 200 steps per period instead of 2000 for the implicit scheme */
            base.dt = a->quick && dynamic && scheme == ROD_SCHEME_IMPLICIT
                          ? 10.0 * validate_default_dt(name, scheme, base.nodes)
                          : 0.0;
            base.ds_sweep = 1;
            /* the thesis default belongs to its sweep; the implicit one is far
               finer than its sweep (see implicit_dt_factors) */
            base.dt_sweep = dynamic && base.nodes == finest_nodes && scheme == ROD_SCHEME_THESIS;
            too_many |= add_point(p, base) != 0;
        }
    }
    if (dynamic && a->dt_count == 0) {
        const double *factors =
            scheme == ROD_SCHEME_THESIS ? thesis_dt_factors : implicit_dt_factors;
        int n_factors = scheme == ROD_SCHEME_THESIS ? (a->quick ? 1 : 2) : (a->quick ? 2 : 3);
        double default_dt = validate_default_dt(name, scheme, finest_nodes);
        for (int f = 0; f < n_factors && default_dt > 0.0; f++) {
            point sweep = {.case_index = case_index, .scheme = scheme, .nodes = finest_nodes,
                           .dt = factors[f] * default_dt, .dt_sweep = 1};
            too_many |= add_point(p, sweep) != 0;
        }
    }
    return too_many ? -1 : 0;
}

/* The plan: every case and scheme; one row says why where one does not
 * apply. 0, or -1 when it holds more than max_points runs. */
static int make_plan(plan *p, const validate_args *a)
{
    int finest_nodes = a->node_list[0];
    for (int k = 1; k < a->node_count; k++)
        if (a->node_list[k] > finest_nodes) finest_nodes = a->node_list[k];
    int too_many = 0;
    for (int ci = 0; ci < a->case_count; ci++) {
        for (int si = 0; si < a->scheme_count; si++) {
            const char *name = validate_case_names()[a->case_list[ci]];
            rod_scheme_kind scheme = a->scheme_list[si];
            validate_row row;
            if (validate_applicable(name, scheme, &row)) {
                too_many |= plan_case(p, a, a->case_list[ci], scheme, finest_nodes) != 0;
                continue;
            }
            /* one row says why; nothing to run */
            point base = {.case_index = a->case_list[ci], .scheme = scheme, .precomputed = 1};
            if (add_point(p, base) == 0) {
                p->rows[p->count - 1] = row;
                p->done[p->count - 1] = 1;
            } else too_many = 1;
        }
    }
    return too_many ? -1 : 0;
}

/* A --dt far from the case's own (1e-300 or 1e300) made a step count that
 * overflows, or a run of 0 steps reported "ok" with its initial value:
 * accept 1e-6 .. 100 x the case's default dt (a finer dt is refused by the
 * run's own step limit as a row; a coarser one leaves the frequency cases
 * fewer than 20 steps per period). 0, or -1 with a message. */
static int check_dt_range(const plan *p, char *err, size_t errlen)
{
    for (int k = 0; k < p->count; k++) {
        const point *pt = &p->points[k];
        if (pt->precomputed) continue;
        const char *name = validate_case_names()[pt->case_index];
        double reference_dt = validate_default_dt(name, pt->scheme, pt->nodes);
        if (reference_dt > 0.0 &&
            !(pt->dt >= 1e-6 * reference_dt && pt->dt <= 100 * reference_dt)) {
            snprintf(err, errlen, "--dt %g: for case %s, scheme %s, NS %d accepted: %.3g .. %.3g "
                                  "s (1e-6 .. 100 x its default dt, %.3g s)",
                     pt->dt, name, rod_scheme_get(pt->scheme)->name, pt->nodes,
                     1e-6 * reference_dt, 100 * reference_dt, reference_dt);
            return -1;
        }
    }
    return 0;
}

/* --print-commands: one independent command line per point (a cluster user
 * runs them with GNU parallel or a job array); each prints its CSV row with
 * a header. The binary by its absolute path: a bare `rodsim` is not on a
 * node's PATH. A point that does not apply (no NS) is asked for by case and
 * scheme alone, which prints its n/a row. An exit status. */
static int print_point_commands(const plan *p)
{
    char self[PATH_MAX], err[PATH_MAX + 128];
    if (cli_self_path(self, sizeof self, err, sizeof err)) {
        fprintf(stderr, "rodsim validate: %s\n", err);
        return RUN_EXIT_FAILURE;
    }
    printf("# %d points; each line is one run. Concatenate their CSV output (one header)\n"
           "# for the table; the orders of convergence need the whole set, as\n"
           "# `rodsim validate` with the same options prints them.\n", p->count);
    for (int k = 0; k < p->count; k++) {
        const point *pt = &p->points[k];
        const char *name = validate_case_names()[pt->case_index];
        cli_print_shell_word(stdout, self);
        printf(" validate --case %s --scheme %s", name, rod_scheme_get(pt->scheme)->name);
        if (!pt->precomputed) {
            double dt = pt->dt > 0.0 ? pt->dt : validate_default_dt(name, pt->scheme, pt->nodes);
            printf(" --nodes %d", pt->nodes);
            if (dt > 0.0) printf(" --dt %.17g", dt);
        }
        printf(" --csv - > validate_point_%03d.csv\n", k);
    }
    return fflush(stdout) ? RUN_EXIT_FAILURE : RUN_EXIT_OK;
}

/* The CSV of the rows, to a file (atomically) or standard output. 0, or 1
 * (reported). */
static int write_csv(const char *csv, const plan *p)
{
    if (strcmp(csv, "-") == 0) {
        write_csv_rows(stdout, p);
        return 0;
    }
    outfile out;
    char err[512];
    if (outfile_open(&out, csv, err, sizeof err) != 0) {
        fprintf(stderr, "rodsim validate: --csv %s: %s\n", csv, err);
        return 1;
    }
    write_csv_rows(out.fp, p);
    if (outfile_commit(&out, err, sizeof err) != 0) {
        fprintf(stderr, "rodsim validate: --csv %s: %s\n", csv, err);
        return 1;
    }
    return 0;
}

/* Runs the plan: the table as rows come and the orders (or the CSV on
 * standard output), then the CSV. An exit status. */
static int run_plan(plan *p, const validate_args *a)
{
    int table = !(a->csv && strcmp(a->csv, "-") == 0);
    int printed = 0;
    if (table) print_header();
    char pool_err[256];
    if (run_points(p, a->jobs, table, &printed, pool_err, sizeof pool_err)) {
        fprintf(stderr, "rodsim validate: %s\n", pool_err);
        return RUN_EXIT_FAILURE;
    }
    if (table) print_orders(p);
    int failed = 0;
    for (int k = 0; k < p->count; k++) failed |= p->rows[k].status == 2;
    int status = failed ? RUN_EXIT_FAILURE : RUN_EXIT_OK;
    if (a->csv && write_csv(a->csv, p)) status = RUN_EXIT_FAILURE;
    if (failed && table) printf("\nsome runs FAILED (status 2): see their notes\n");
    return status;
}

int validate_command(int argc, char **argv)
{
    char err[1024] = "";
    validate_args a;
    int parsed = parse_args(argc, argv, &a, err, sizeof err);
    if (parsed == CLI_HELP) {
        usage(stdout);
        return RUN_EXIT_OK;
    }
    if (parsed != CLI_PARSED) return cli_usage_error("validate", err);
    plan *p = calloc(1, sizeof *p);
    if (!p) {
        fprintf(stderr, "rodsim validate: out of memory\n");
        return RUN_EXIT_FAILURE;
    }
    int status, too_many = make_plan(p, &a);
    if (a.csv && !a.print_commands && cli_check_output_file("--csv", a.csv, err, sizeof err)) {
        status = cli_usage_error("validate", err); /* before minutes of runs, not after */
    } else if (a.dt_count > 0 && check_dt_range(p, err, sizeof err)) {
        status = cli_usage_error("validate", err);
    } else if (too_many) {
        snprintf(err, sizeof err, "more than %d runs asked for; give fewer --case, --scheme, "
                                  "--nodes or --dt", max_points);
        status = cli_usage_error("validate", err);
    } else {
        status = a.print_commands ? print_point_commands(p) : run_plan(p, &a);
    }
    free(p);
    return status;
}
