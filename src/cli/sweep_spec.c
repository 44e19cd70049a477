/* sweep_spec.c: a sweep's options and points (see sweep_spec.h): --vary
 * lists and ranges, measures, the plot's axes, the scene's bytes, each
 * point's settings, scene and digest. */
#include "cli/sweep_spec.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/ini.h"
#include "base/suggest.h"
#include "base/textfile.h"
#include "base/worker.h"
#include "cli/print_commands.h"
#include "api/scene_keys.h"
#include "cli/scene_outputs.h"
#include "cli/version.h"
#include "plot/plot.h"
#include "api/scene_read.h"
#include "sim/rod.h"
#include "sim/rod_set.h"

const char *const sweep_measure_names[SWEEP_M_COUNT] = {
    "tip_x", "tip_y", "tip_z", "root_fx", "root_fy", "root_fz", "tip_fx", "tip_fy", "tip_fz",
    "max_curvature", "first_frequency", "critical_load", "critical_moment", "root_f", "tip_f",
    "knot", "rope_in_knot_d", "min_strand_gap_d", "puncture_count",
    "puncture_f[0]", "puncture_f[1]", "puncture_f[2]", "puncture_f[3]", "puncture_f[4]",
    "puncture_f[5]", "puncture_f[6]", "puncture_f[7]", "puncture_f[8]", "puncture_f[9]",
    "puncture_f[10]", "puncture_f[11]", "puncture_f[12]", "puncture_f[13]", "puncture_f[14]",
    "puncture_f[15]", "steps", "wall_s", "cpu_s"};

const char *const sweep_measure_units[SWEEP_M_COUNT] = {
    "m", "m", "m", "N", "N", "N", "N", "N", "N", "1/m", "Hz", "N", "N m", "N", "N", "-", "d",
    "d", "-", "N", "N", "N", "N", "N", "N", "N", "N", "N", "N", "N", "N", "N", "N", "N", "N",
    "-", "s", "s"};

const char *const sweep_measure_labels[SWEEP_M_COUNT] = {
    "tip x", "tip y", "tip z", "root force x", "root force y", "root force z", "tip force x",
    "tip force y", "tip force z", "max curvature", "first frequency", "critical load",
    "critical moment", "root force |F|", "tip force |F|", "knot", "rope in knot",
    "closest strands", "punctures", "puncture 1 force |F|", "puncture 2 force |F|",
    "puncture 3 force |F|", "puncture 4 force |F|", "puncture 5 force |F|",
    "puncture 6 force |F|", "puncture 7 force |F|", "puncture 8 force |F|",
    "puncture 9 force |F|", "puncture 10 force |F|", "puncture 11 force |F|",
    "puncture 12 force |F|", "puncture 13 force |F|", "puncture 14 force |F|",
    "puncture 15 force |F|", "puncture 16 force |F|", "steps", "wall time", "CPU time"};

const char *const sweep_status_names[SWEEP_POINT_STATUS_COUNT] = {
    "ok", "unstable", "no_convergence", "refused", "failed"};

int sweep_rod_slot(int m)
{
    if (m >= SWEEP_M_TIP_X && m <= SWEEP_M_TIP_FZ) return m - SWEEP_M_TIP_X;
    if (m == SWEEP_M_ROOT_F) return SWEEP_M_TIP_FZ - SWEEP_M_TIP_X + 1;
    if (m == SWEEP_M_TIP_F) return SWEEP_M_TIP_FZ - SWEEP_M_TIP_X + 2;
    return -1;
}

uint64_t sweep_fnv1a64(uint64_t h, const void *bytes, size_t n)
{
    const unsigned char *b = bytes;
    for (size_t i = 0; i < n; i++) {
        h ^= b[i];
        h *= 0x100000001b3ULL; /* the FNV 64-bit prime */
    }
    return h;
}

void sweep_format_double(double x, char *out, size_t n)
{
    if (isnan(x)) {
        out[0] = '\0';
        return;
    }
    for (int p = 15; p <= 17; p++) {
        snprintf(out, n, "%.*g", p, x);
        if (strtod(out, NULL) == x) return;
    }
}

void sweep_csv_field(FILE *f, const char *text, int quote)
{
    if (!quote && !strpbrk(text, ",\"\r\n")) {
        fputs(text, f);
        return;
    }
    fputc('"', f);
    for (const char *c = text; *c; c++) {
        if (*c == '"') fputc('"', f);
        fputc(*c, f);
    }
    fputc('"', f);
}

/* The value as ini_set keeps it: blanks trimmed, one pair of quotes off. */
static void canonical_value(const char *v, char *out, size_t n)
{
    const char *b = v, *e = v + strlen(v);
    while (b < e && (*b == ' ' || *b == '\t')) b++;
    while (e > b && (e[-1] == ' ' || e[-1] == '\t')) e--;
    if (e - b >= 2 && *b == '"' && e[-1] == '"') { b++; e--; }
    snprintf(out, n, "%.*s", (int)(e - b), b);
}

void sweep_release(sweep *sw)
{
    for (int i = 0; i < sw->vary_count; i++) {
        for (int j = 0; j < sw->varies[i].count; j++) free(sw->varies[i].values[j]);
        free(sw->varies[i].values);
    }
    free(sw->varies);
    free(sw->sets.items);
    free(sw->vary_args.items);
    free(sw->text);
}

/* Splits a --vary value into its list: V1,V2,... or START:STOP:COUNT[:log].
 * 0, or -1 with a message naming the argument. */
static int parse_values(sweep_vary *v, const char *list, char *err, size_t errlen)
{
    if (list[0] == '\0') {
        snprintf(err, errlen, "--vary %s: empty list; expected KEY=V1,V2,... or "
                              "KEY=START:STOP:COUNT[:log]", v->arg);
        return -1;
    }
    if (!strchr(list, ',') && strchr(list, ':')) {
        /* Decision: a value with ':' and no ',' is a range; a list of one
         * value that holds ':' cannot be given. */
        char buf[256], *parts[5];
        int n = 0;
        snprintf(buf, sizeof buf, "%s", list);
        for (char *p = buf, *tok; n < 5 && (tok = strsep(&p, ":")); ) parts[n++] = tok;
        char *end;
        double start = n >= 3 ? strtod(parts[0], &end) : 0;
        int ok = n >= 3 && n <= 4 && end != parts[0] && *end == '\0' && isfinite(start);
        double stop = ok ? strtod(parts[1], &end) : 0;
        ok = ok && end != parts[1] && *end == '\0' && isfinite(stop);
        long count = ok ? strtol(parts[2], &end, 10) : 0;
        ok = ok && end != parts[2] && *end == '\0';
        int log_scale = ok && n == 4 && strcmp(parts[3], "log") == 0;
        if (!ok || (n == 4 && !log_scale)) {
            snprintf(err, errlen, "--vary %s: a range is START:STOP:COUNT or "
                                  "START:STOP:COUNT:log (numbers; COUNT a whole number)",
                     v->arg);
            return -1;
        }
        if (count < 1 || count > SWEEP_MAX_POINTS) {
            snprintf(err, errlen, "--vary %s: COUNT = %ld; accepted 1 .. %d", v->arg, count,
                     SWEEP_MAX_POINTS);
            return -1;
        }
        if (log_scale && !(start > 0.0 && stop > 0.0)) {
            snprintf(err, errlen, "--vary %s: a log range needs START > 0 and STOP > 0", v->arg);
            return -1;
        }
        v->values = calloc((size_t)count, sizeof *v->values);
        if (!v->values) goto oom;
        for (long i = 0; i < count; i++) {
            /* the ends exactly as given; inside, evenly (in log when asked) */
            double f = count > 1 ? (double)i / (double)(count - 1) : 0.0;
            double x = i == 0 ? start : i == count - 1 ? stop
                     : log_scale ? start * pow(stop / start, f) : start + (stop - start) * f;
            char text[40];
            sweep_format_double(x, text, sizeof text);
            if (!(v->values[i] = strdup(text))) goto oom;
            v->count++;
        }
        return 0;
    }
    int count = 1;
    for (const char *c = list; *c; c++) count += *c == ',';
    v->values = calloc((size_t)count, sizeof *v->values);
    if (!v->values) goto oom;
    for (const char *b = list;;) {
        const char *e = strchr(b, ',');
        size_t len = e ? (size_t)(e - b) : strlen(b);
        char item[SWEEP_VALUE_LEN];
        snprintf(item, sizeof item, "%.*s", (int)len, b);
        char canon[SWEEP_VALUE_LEN];
        canonical_value(item, canon, sizeof canon);
        if (canon[0] == '\0' || len >= SWEEP_VALUE_LEN) {
            snprintf(err, errlen, "--vary %s: value %d is %s", v->arg, v->count + 1,
                     canon[0] ? "too long" : "empty");
            return -1;
        }
        if (!(v->values[v->count++] = strdup(canon))) goto oom;
        if (!e) break;
        b = e + 1;
    }
    return 0;
oom:
    snprintf(err, errlen, "out of memory");
    return -1;
}


/* The key of a --vary: known to the scene key table (the same message as an
 * unknown --set key, with its suggestion), and `[i]` for a component. */
static int parse_vary(sweep_vary *v, const char *arg, char *err, size_t errlen)
{
    memset(v, 0, sizeof *v);
    v->arg = arg;
    v->component = -1;
    const char *eq = strchr(arg, '=');
    if (!eq || eq == arg) {
        snprintf(err, errlen, "--vary %s: expected KEY=V1,V2,... or KEY=START:STOP:COUNT[:log]",
                 arg);
        return -1;
    }
    size_t klen = (size_t)(eq - arg);
    if (klen >= SWEEP_KEY_LEN) {
        snprintf(err, errlen, "--vary %s: key too long", arg);
        return -1;
    }
    snprintf(v->name, sizeof v->name, "%.*s", (int)klen, arg);
    snprintf(v->key, sizeof v->key, "%s", v->name);
    char *bracket = strchr(v->key, '[');
    if (bracket) {
        char *end;
        long c = strtol(bracket + 1, &end, 10);
        if (end == bracket + 1 || strcmp(end, "]") != 0 || c < 0 || c > 15) {
            snprintf(err, errlen, "--vary %s: a component is written section.key[i], i = 0, 1, "
                                  "2 ... (0-based: tip.force[1] is the y component)", arg);
            return -1;
        }
        v->component = (int)c;
        *bracket = '\0';
    }
    /* the table's check, on a scene holding only this key */
    char assignment[SWEEP_KEY_LEN + 8];
    snprintf(assignment, sizeof assignment, "%s=0", v->key);
    ini_doc *probe = ini_parse("--vary", "", err, errlen);
    if (!probe) return -1;
    int rc = ini_set(probe, assignment, err, errlen);
    if (rc == 0 && ini_check_keys(probe, scene_keys_rod, err, errlen)) {
        /* "--set KEY=0: unknown key; did you mean ..." -> "--vary ARG: ..." */
        char prefix[SWEEP_KEY_LEN + 16], rest[SWEEP_ERR_LEN];
        snprintf(prefix, sizeof prefix, "--set %s: ", assignment);
        size_t plen = strlen(prefix);
        snprintf(rest, sizeof rest, "%s", strncmp(err, prefix, plen) == 0 ? err + plen : err);
        snprintf(err, errlen, "--vary %.200s: %.1800s", arg, rest);
        rc = -1;
    } else if (rc) {
        snprintf(err, errlen, "--vary %s: expected section.key=V1,V2,... (e.g. "
                              "tip.force[1]=1e-7,2e-7)", arg);
    }
    ini_destroy(probe);
    if (rc) return -1;
    return parse_values(v, eq + 1, err, errlen);
}

/* Which measures apply to every scene: not the knot's (self-contact) nor
 * the punctures' (punctures or tissue), nor a puncture's own column. */
static int measure_is_general(int m)
{
    return !(m >= SWEEP_M_KNOT && m < SWEEP_M_STEPS);
}

/* The measures of a --measure group into first..last; `all` is those that
 * apply to every scene. 0, or -1 when `tok` names no group. */
static int measure_group(const char *tok, int *first, int *last)
{
    if (strcmp(tok, "tip") == 0) *first = SWEEP_M_TIP_X, *last = SWEEP_M_TIP_Z;
    else if (strcmp(tok, "root_force") == 0) *first = SWEEP_M_ROOT_FX, *last = SWEEP_M_ROOT_FZ;
    else if (strcmp(tok, "tip_force") == 0) *first = SWEEP_M_TIP_FX, *last = SWEEP_M_TIP_FZ;
    else if (strcmp(tok, "knots") == 0) *first = SWEEP_M_KNOT, *last = SWEEP_M_MIN_STRAND_GAP;
    else if (strcmp(tok, "all") == 0) *first = 0, *last = SWEEP_M_COUNT - 1;
    else return -1;
    return 0;
}

static void add_measure(sweep *sw, int m)
{
    for (int i = 0; i < sw->measure_count; i++)
        if (sw->measures[i] == m) return;
    sw->measures[sw->measure_count++] = m;
}

static int add_measures(sweep *sw, const char *list, char *err, size_t errlen)
{
    char buf[512];
    snprintf(buf, sizeof buf, "%s", list);
    sw->measure_count = 0;
    for (char *p = buf, *tok; (tok = strsep(&p, ",")); ) {
        int first = -1, last = -1, all = strcmp(tok, "all") == 0;
        if (strcmp(tok, "punctures") == 0 || strcmp(tok, "puncture_f") == 0) {
            if (strcmp(tok, "punctures") == 0) add_measure(sw, SWEEP_M_PUNCTURE_COUNT);
            add_measure(sw, SWEEP_M_PUNCTURE_COLUMNS);
            continue;
        }
        measure_group(tok, &first, &last);
        for (int m = 0; m < SWEEP_M_COUNT && first < 0; m++)
            if (strcmp(tok, sweep_measure_names[m]) == 0) first = last = m;
        if (first < 0) {
            char accepted[1024] = "";
            for (int m = 0; m < SWEEP_M_COUNT; m++) {
                if (m > SWEEP_M_PUNCTURE_F && m < SWEEP_M_STEPS) continue;
                strcat(accepted, m == SWEEP_M_PUNCTURE_F ? "puncture_f (puncture_f[i] one)"
                                                         : sweep_measure_names[m]);
                strcat(accepted, ", ");
            }
            snprintf(err, errlen, "--measure %s: unknown measure '%s'; accepted: %sand the "
                                  "groups tip, root_force, tip_force, knots, punctures, all",
                     list, tok, accepted);
            return -1;
        }
        for (int m = first; m <= last; m++)
            if (!all || measure_is_general(m)) add_measure(sw, m);
    }
    return 0;
}

/* --plot X:Y: X a varied key with numeric values, Y a measure; with --png. */
static int parse_plot(sweep *sw, char *err, size_t errlen)
{
    if (!sw->plot_arg) {
        const char *figure_only[][2] = {
            {"--png", sw->png}, {"--svg", sw->svg}, {"--log", sw->log_axes},
            {"--title", sw->title}, {"--xlabel", sw->xlabel}, {"--ylabel", sw->ylabel},
            {"--xformat", sw->xformat}, {"--yformat", sw->yformat}};
        for (size_t i = 0; i < sizeof figure_only / sizeof figure_only[0]; i++)
            if (figure_only[i][1]) {
                snprintf(err, errlen, "%s needs --plot X:Y", figure_only[i][0]);
                return -1;
            }
        return 0;
    }
    const char *formats[2][2] = {{"--xformat", sw->xformat}, {"--yformat", sw->yformat}};
    for (int i = 0; i < 2; i++)
        if (formats[i][1] && plot_check_tick_format(formats[i][1])) {
            snprintf(err, errlen, "%s %s: a tick format is one printf conversion of a number "
                                  "(%%e, %%f or %%g, with flags, width and precision, e.g. "
                                  "%%.2g or %%.0f%%%%), and any other text",
                     formats[i][0], formats[i][1]);
            return -1;
        }
    if (!sw->png && !sw->svg) {
        snprintf(err, errlen, "--plot %s needs --png FILE or --svg FILE (or both)", sw->plot_arg);
        return -1;
    }
    if (sw->log_axes && strcmp(sw->log_axes, "x") && strcmp(sw->log_axes, "y") &&
        strcmp(sw->log_axes, "xy")) {
        snprintf(err, errlen, "--log %s: accepted x, y, xy", sw->log_axes);
        return -1;
    }
    const char *colon = strrchr(sw->plot_arg, ':');
    char x[SWEEP_KEY_LEN] = "", varied[512] = "", measures[512] = "";
    if (colon) snprintf(x, sizeof x, "%.*s", (int)(colon - sw->plot_arg), sw->plot_arg);
    sw->plot_x = sw->plot_y = -1;
    for (int i = 0; i < sw->vary_count; i++) {
        if (strcmp(x, sw->varies[i].name) == 0) sw->plot_x = i;
        snprintf(varied + strlen(varied), sizeof varied - strlen(varied), "%s%s", i ? ", " : "",
                 sw->varies[i].name);
    }
    /* the y axes offered: every measure but the knot's type (a name, below) */
    for (int m = 0; m < SWEEP_M_COUNT; m++) {
        if (colon && strcmp(colon + 1, sweep_measure_names[m]) == 0) sw->plot_y = m;
        if (m == SWEEP_M_KNOT) continue;
        snprintf(measures + strlen(measures), sizeof measures - strlen(measures), "%s%s",
                 measures[0] ? ", " : "", sweep_measure_names[m]);
    }
    /* "did you mean ...?" for a misspelt axis, as for a misspelt --set key */
    const char *names[SWEEP_M_COUNT + 65]; /* the measures, or the first 64 varied keys */
    const char *near = NULL;
    if (sw->plot_x < 0) {
        int n = 0;
        for (int i = 0; i < sw->vary_count && i < 64; i++) names[n++] = sw->varies[i].name;
        names[n] = NULL;
        near = suggest_nearest(x, names);
        snprintf(err, errlen, "--plot %s: the x axis must be a varied key; %s%s%saccepted: %s",
                 sw->plot_arg, near ? "did you mean " : "", near ? near : "", near ? "? " : "",
                 sw->vary_count ? varied : "(no --vary given)");
        return -1;
    }
    if (sw->plot_y < 0) {
        int n = 0;
        for (int m = 0; m < SWEEP_M_COUNT; m++)
            if (m != SWEEP_M_KNOT) names[n++] = sweep_measure_names[m];
        names[n] = NULL;
        near = colon ? suggest_nearest(colon + 1, names) : NULL;
        snprintf(err, errlen, "--plot %s: the y axis must be a measure; %s%s%saccepted: %s",
                 sw->plot_arg, near ? "did you mean " : "", near ? near : "", near ? "? " : "",
                 measures);
        return -1;
    }
    if (sw->plot_y == SWEEP_M_KNOT) {
        snprintf(err, errlen, "--plot %s: the knot type is a name, not a number: it goes into "
                              "the CSV (--measure knot); plot rope_in_knot_d or "
                              "min_strand_gap_d", sw->plot_arg);
        return -1;
    }
    const sweep_vary *v = &sw->varies[sw->plot_x];
    for (int j = 0; j < v->count; j++) {
        char *end;
        double value = strtod(v->values[j], &end);
        if (end == v->values[j] || *end != '\0' || !isfinite(value)) {
            snprintf(err, errlen, "--plot %s: the x axis needs numbers; %s has '%s'",
                     sw->plot_arg, v->name, v->values[j]);
            return -1;
        }
    }
    /* Decision: the plotted data go beside the figure, FILE.png (or FILE.svg)
     * -> FILE.csv */
    const char *figure = sw->png ? sw->png : sw->svg;
    size_t len = strlen(figure);
    int ext = len > 4 && (strcmp(figure + len - 4, ".png") == 0 ||
                          strcmp(figure + len - 4, ".svg") == 0);
    snprintf(sw->plot_csv, sizeof sw->plot_csv, "%.*s.csv", (int)(ext ? len - 4 : len), figure);
    if (sw->csv && strcmp(sw->csv, sw->plot_csv) == 0) {
        snprintf(err, errlen, "--csv %s is where the figure %s puts its plotted data; choose "
                              "another name", sw->csv, figure);
        return -1;
    }
    return 0;
}

/* The --vary arguments into sw->varies (each key once) and the --measure
 * list into sw->measures. 0, or -1 with a message. */
static int parse_varies_and_measures(sweep *sw, const char *measure, char *err, size_t errlen)
{
    sw->varies = calloc((size_t)sw->vary_args.count + 1, sizeof *sw->varies);
    if (!sw->varies) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    for (int i = 0; i < sw->vary_args.count; i++)
        if (parse_vary(&sw->varies[sw->vary_count++], sw->vary_args.items[i], err, errlen))
            return -1;
    sw->measure_arg = measure;
    if (add_measures(sw, measure, err, errlen)) return -1;
    for (int i = 0; i < sw->vary_count; i++)
        for (int j = 0; j < i; j++)
            if (strcmp(sw->varies[i].name, sw->varies[j].name) == 0) {
                snprintf(err, errlen, "--vary %s: %s is already varied by --vary %s",
                         sw->varies[i].arg, sw->varies[i].name, sw->varies[j].arg);
                return -1;
            }
    return 0;
}

/* --print-commands, --assemble, --snakefile and --sbatch: one of them, with
 * the result directory (and a CSV file for the Snakefile). */
static int check_exports(const sweep *sw, char *err, size_t errlen)
{
    if ((sw->print_commands || sw->assemble || sw->snakefile || sw->sbatch) &&
        !sw->result_dir) {
        snprintf(err, errlen, "%s needs --result DIR (where the points' result files go)",
                 sw->print_commands ? "--print-commands"
                 : sw->assemble     ? "--assemble"
                 : sw->snakefile    ? "--snakefile"
                                    : "--sbatch");
        return -1;
    }
    if (sw->print_commands + sw->assemble + (sw->snakefile != NULL) + (sw->sbatch != NULL) > 1) {
        snprintf(err, errlen, "--print-commands, --assemble, --snakefile and --sbatch: give "
                              "one of them");
        return -1;
    }
    if (sw->snakefile && (!sw->csv || strcmp(sw->csv, "-") == 0)) {
        snprintf(err, errlen, "--snakefile %s needs --csv FILE (the file its rule assemble "
                              "writes)", sw->snakefile);
        return -1;
    }
    return 0;
}

/* How many points the --vary lists make; -1 over SWEEP_MAX_POINTS. */
static int count_points(sweep *sw, char *err, size_t errlen)
{
    double points = 1.0;
    for (int i = 0; i < sw->vary_count; i++) points *= sw->varies[i].count;
    if (points > SWEEP_MAX_POINTS) {
        snprintf(err, errlen, "the --vary lists make %.3g points; at most %d are accepted",
                 points, SWEEP_MAX_POINTS);
        return -1;
    }
    sw->point_count = (int)points;
    return 0;
}

int sweep_parse_args(int argc, char **argv, sweep *sw, char *err, size_t errlen)
{
    const char *measure = "tip,wall_s,cpu_s";
    sw->jobs = 1;
    const cli_option options[] = {
        {.name = "--quiet", .alias = "-q", .value = CLI_FLAG, .target = &sw->quiet},
        {.name = "--allow-long", .value = CLI_FLAG, .target = &sw->allow_long},
        {.name = "--print-commands", .value = CLI_FLAG, .target = &sw->print_commands},
        {.name = "--assemble", .value = CLI_FLAG, .target = &sw->assemble},
        {.name = "--set", .value = CLI_SETTING, .target = &sw->sets, .repeated = 1},
        {.name = "--vary", .value = CLI_WORD, .target = &sw->vary_args, .repeated = 1,
         .noun = "KEY=V1,V2,... or KEY=START:STOP:COUNT[:log]"},
        {.name = "--measure", .value = CLI_WORD, .target = &measure, .noun = "WHAT,..."},
        {.name = "--csv", .value = CLI_OUTPUT, .target = &sw->csv},
        {.name = "--plot", .value = CLI_WORD, .target = &sw->plot_arg, .noun = "X:Y"},
        {.name = "--png", .value = CLI_FILE, .target = &sw->png},
        {.name = "--svg", .value = CLI_FILE, .target = &sw->svg},
        {.name = "--log", .value = CLI_WORD, .target = &sw->log_axes, .noun = "x, y or xy"},
        {.name = "--title", .value = CLI_WORD, .target = &sw->title, .noun = "TEXT"},
        {.name = "--xlabel", .value = CLI_WORD, .target = &sw->xlabel, .noun = "TEXT"},
        {.name = "--ylabel", .value = CLI_WORD, .target = &sw->ylabel, .noun = "TEXT"},
        {.name = "--xformat", .value = CLI_WORD, .target = &sw->xformat, .noun = "FORMAT"},
        {.name = "--yformat", .value = CLI_WORD, .target = &sw->yformat, .noun = "FORMAT"},
        {.name = "--sbatch", .value = CLI_FILE, .target = &sw->sbatch},
        {.name = "--snakefile", .value = CLI_FILE, .target = &sw->snakefile},
        {.name = "--result", .value = CLI_DIR, .target = &sw->result_dir},
        {.name = "--jobs", .alias = "-j", .value = CLI_COUNT, .target = &sw->jobs, .lo = 1,
         .hi = WORKER_MAX_JOBS},
        {0}};
    const cli_operand scene = {.name = "SCENE", .target = &sw->scene_arg};
    int parsed = cli_parse(argc, argv, options, &scene, err, errlen);
    if (parsed != CLI_PARSED) return parsed;
    if (parse_varies_and_measures(sw, measure, err, errlen) || check_exports(sw, err, errlen) ||
        parse_plot(sw, err, errlen))
        return CLI_ERROR;
    /* Decision: the buckling search costs more than a short run (2 s at NS =
     * 401), so it runs only when asked; the request is part of the points'
     * digests, so a result file without it is never taken for one with it. */
    for (int i = 0; i < sw->measure_count; i++)
        sw->critical |= sw->measures[i] == SWEEP_M_CRITICAL_LOAD ||
                        sw->measures[i] == SWEEP_M_CRITICAL_MOMENT;
    sw->critical |= sw->plot_arg &&
                    (sw->plot_y == SWEEP_M_CRITICAL_LOAD || sw->plot_y == SWEEP_M_CRITICAL_MOMENT);
    return count_points(sw, err, errlen) ? CLI_ERROR : CLI_PARSED;
}
/* Reads the scene's bytes once (they are also the digest's input). */
int sweep_read_scene(sweep *sw, char *err, size_t errlen)
{
    if (cli_absolute_path(sw->scene_arg, sw->scene_path, sizeof sw->scene_path, err, errlen))
        return -1;
    char *text;
    size_t len;
    if (textfile_read(sw->scene_arg, "scene", INI_MAX_BYTES, &text, &len, err, errlen)) return -1;
    sw->text = text;
    sw->text_len = len;
    return 0;
}


/* A component --vary starts from the key's value in the scene, or else its
 * default (scene_keys.c). */
int sweep_read_bases(sweep *sw, char *err, size_t errlen)
{
    ini_doc *doc = ini_parse(sw->scene_arg, sw->text, err, errlen);
    if (!doc) return -1;
    const char *names[SWEEP_MAX_RODS];
    int rods = ini_section_names(doc, "rod", names, SWEEP_MAX_RODS);
    sw->rod_count = rods < SWEEP_MAX_RODS ? rods : SWEEP_MAX_RODS;
    char listed[SWEEP_MAX_RODS * (SWEEP_ROD_NAME_LEN + 2)] = "";
    for (int k = 0; k < sw->rod_count; k++) {
        snprintf(sw->rod_names[k], sizeof sw->rod_names[k], "%s", names[k]);
        snprintf(listed + strlen(listed), sizeof listed - strlen(listed), "%s%s", k ? ", " : "",
                 sw->rod_names[k]);
    }
    for (int i = 0; i < sw->vary_count; i++) {
        sweep_vary *v = &sw->varies[i];
        char section[SWEEP_KEY_LEN];
        snprintf(section, sizeof section, "%s", v->key);
        char *dot = strchr(section, '.');
        *dot = '\0';
        char *space = strchr(section, ' '); /* [rod NAME], [ends NAME], [tip NAME] */
        int known = !space;
        for (int k = 0; space && k < sw->rod_count; k++)
            known |= strcmp(space + 1, sw->rod_names[k]) == 0;
        if (!known) {
            if (sw->rod_count)
                snprintf(err, errlen, "--vary %s: %s: the scene has no rod named '%s'; its "
                                      "rods: %s", v->arg, sw->scene_arg, space + 1, listed);
            else
                snprintf(err, errlen, "--vary %s: %s has one bare [rod], no named rods; "
                                      "accepted here: %.*s.KEY", v->arg, sw->scene_arg,
                         (int)(space - section), section);
            ini_destroy(doc);
            return -1;
        }
        if (v->component < 0) continue;
        const char *value = NULL;
        if (ini_get_string(doc, section, 0, dot + 1, &value, err, errlen) != 1) {
            value = NULL;
            if (space) *space = '\0'; /* a named rod's default is the bare section's */
            for (const ini_key *k = scene_keys_rod; k->section; k++)
                if (strcmp(k->section, section) == 0 && strcmp(k->key, dot + 1) == 0)
                    value = k->fallback;
        }
        snprintf(v->base, sizeof v->base, "%s", value ? value : "");
    }
    ini_destroy(doc);
    return 0;
}

/* The point's index in each list: the first --vary varies slowest. */
int sweep_value_index(const sweep *sw, int point, int which)
{
    int stride = 1;
    for (int i = sw->vary_count - 1; i > which; i--) stride *= sw->varies[i].count;
    return point / stride % sw->varies[which].count;
}

static sweep_setting *find_setting(sweep_setting *s, int n, const char *key)
{
    for (int i = 0; i < n; i++)
        if (strcmp(s[i].key, key) == 0) return &s[i];
    return NULL;
}

static int compare_settings(const void *a, const void *b)
{
    return strcmp(((const sweep_setting *)a)->key, ((const sweep_setting *)b)->key);
}

/* Numbers separated by blanks or commas; how many, or -1. */
static int parse_vector(const char *text, double *out, int max)
{
    int n = 0;
    const char *p = text;
    for (;;) {
        while (*p == ' ' || *p == '\t' || *p == ',') p++;
        if (!*p) return n;
        char *end;
        double x = strtod(p, &end);
        if (end == p || n == max) return -1;
        out[n++] = x;
        p = end;
    }
}


/* The point's settings: the --set ones (the last of a key wins), then the
 * point's values, a component put into its key's whole value; sorted by
 * key. Returns how many, or -1 with a message. `out` holds set_count +
 * vary_count entries. */
int sweep_point_settings(const sweep *sw, int point, sweep_setting *out, char *err, size_t errlen)
{
    int n = 0;
    for (int i = 0; i < sw->sets.count; i++) {
        const char *eq = strchr(sw->sets.items[i], '=');
        char raw[SWEEP_KEY_LEN], key[SWEEP_KEY_LEN];
        snprintf(raw, sizeof raw, "%.*s", (int)(eq - sw->sets.items[i]), sw->sets.items[i]);
        canonical_value(raw, key, sizeof key);
        sweep_setting *s = find_setting(out, n, key);
        if (!s) {
            s = &out[n++];
            snprintf(s->key, sizeof s->key, "%s", key);
        }
        canonical_value(eq + 1, s->value, sizeof s->value);
    }
    for (int i = 0; i < sw->vary_count; i++) {
        const sweep_vary *v = &sw->varies[i];
        const char *value = v->values[sweep_value_index(sw, point, i)];
        sweep_setting *s = find_setting(out, n, v->key);
        if (v->component >= 0) {
            double x[16], c;
            char *end;
            int count = parse_vector(s ? s->value : v->base, x, 16);
            c = strtod(value, &end);
            if (count < 0 || end == value || *end != '\0' || !isfinite(c) ||
                v->component >= count) {
                if (count <= v->component)
                    snprintf(err, errlen, "--vary %s: %s is '%s', %d number%s: component %d "
                                          "does not exist (components are 0-based)",
                             v->arg, v->key, s ? s->value : v->base, count < 0 ? 0 : count,
                             count == 1 ? "" : "s", v->component);
                else
                    snprintf(err, errlen, "--vary %s: '%s' is not a number (a component takes "
                                          "one number)", v->arg, value);
                return -1;
            }
            x[v->component] = c;
            char whole[SWEEP_VALUE_LEN] = "";
            for (int k = 0; k < count; k++) {
                char num[40];
                sweep_format_double(x[k], num, sizeof num);
                if (k) strcat(whole, " ");
                strcat(whole, num);
            }
            if (!s) {
                s = &out[n++];
                snprintf(s->key, sizeof s->key, "%s", v->key);
            }
            snprintf(s->value, sizeof s->value, "%s", whole);
            continue;
        }
        if (!s) {
            s = &out[n++];
            snprintf(s->key, sizeof s->key, "%s", v->key);
        }
        snprintf(s->value, sizeof s->value, "%s", value);
    }
    qsort(out, (size_t)n, sizeof *out, compare_settings);
    return n;
}

/* The point's scene: the file's text with its settings applied. */
ini_doc *sweep_point_doc(const sweep *sw, const sweep_setting *s, int n, char *err, size_t errlen)
{
    ini_doc *doc = ini_parse(sw->scene_arg, sw->text, err, errlen);
    for (int i = 0; doc && i < n; i++) {
        char assignment[SWEEP_KEY_LEN + SWEEP_VALUE_LEN + 2];
        snprintf(assignment, sizeof assignment, "%s=%s", s[i].key, s[i].value);
        if (ini_set(doc, assignment, err, errlen)) {
            ini_destroy(doc);
            return NULL;
        }
    }
    return doc;
}

/* The digest of a point's inputs: version, scene bytes, sorted settings. */
uint64_t sweep_point_digest(const sweep *sw, const sweep_setting *s, int n)
{
    static const char version[] = "rodsim " RODSIM_VERSION "\n";
    uint64_t h = sweep_fnv1a64(SWEEP_FNV_BASIS, version, sizeof version - 1);
    h = sweep_fnv1a64(h, sw->text, sw->text_len);
    for (int i = 0; i < n; i++) {
        h = sweep_fnv1a64(h, "\n", 1);
        h = sweep_fnv1a64(h, s[i].key, strlen(s[i].key));
        h = sweep_fnv1a64(h, "=", 1);
        h = sweep_fnv1a64(h, s[i].value, strlen(s[i].value));
    }
    if (sw->critical) h = sweep_fnv1a64(h, "\n#critical", 10);
    return h;
}

void sweep_describe_point(const sweep *sw, int point, char *out, size_t n)
{
    out[0] = '\0';
    for (int i = 0; i < sw->vary_count; i++) {
        size_t len = strlen(out);
        snprintf(out + len, n - len, "%s%s=%s", i ? ", " : "", sw->varies[i].name,
                 sw->varies[i].values[sweep_value_index(sw, point, i)]);
    }
}

/* A bit per measure kind that not every scene has (1 knot, 2 punctures). */
static int measure_kind(int m)
{
    if (m >= SWEEP_M_KNOT && m <= SWEEP_M_MIN_STRAND_GAP) return 1;
    if ((m >= SWEEP_M_PUNCTURE_COUNT && m < SWEEP_M_STEPS) || m == SWEEP_M_PUNCTURE_COLUMNS)
        return 2;
    return 0;
}

/* A knot measure needs strands that touch (self-contact, the implicit
 * scheme: elsewhere a strand passes through another and no knot holds);
 * a puncture measure needs punctures (given, or a tissue a needle makes
 * them in). 0, or -1 with a message naming the measures that apply. */
static int check_measures_apply(const sweep *sw, const rod_model *m, const char *where,
                                char *err, size_t errlen)
{
    int kinds = 0, plotted = sw->plot_arg ? measure_kind(sw->plot_y) : 0;
    for (int i = 0; i < sw->measure_count; i++) kinds |= measure_kind(sw->measures[i]);
    int tissue = m->puncture_count > 0;
    for (int i = 0; i < m->surface_count; i++) tissue |= m->surfaces[i].tissue;
    int knots = m->self_contact && m->options.scheme == ROD_SCHEME_IMPLICIT;
    const char *why = NULL, *which = NULL;
    kinds |= plotted;
    if ((kinds & 1) && !knots) {
        which = "knot, rope_in_knot_d and min_strand_gap_d";
        why = m->self_contact ? "its scheme is not implicit: strands pass through each other, "
                                "no knot holds"
                              : "rod.self_contact = no: strands pass through each other, no "
                                "knot holds";
    } else if ((kinds & 2) && !tissue) {
        which = "puncture_count and puncture_f";
        why = "it has no [puncture] and no tissue surface (surface.tissue = yes) for a needle "
              "to puncture";
    }
    if (!which) return 0;
    char apply[1024] = "";
    for (int k = 0; k < SWEEP_M_COUNT; k++) {
        int general = measure_is_general(k);
        int knot = k >= SWEEP_M_KNOT && k <= SWEEP_M_MIN_STRAND_GAP;
        if (!general && !(knot && knots) && !(!knot && tissue && k <= SWEEP_M_PUNCTURE_F))
            continue;
        snprintf(apply + strlen(apply), sizeof apply - strlen(apply), "%s%s", apply[0] ? ", " : "",
                 k == SWEEP_M_PUNCTURE_F ? "puncture_f" : sweep_measure_names[k]);
    }
    int by_plot = (plotted & ((kinds & 1) && !knots ? 1 : 2)) != 0;
    snprintf(err, errlen, "%s %.200s: %.60s do not apply to %.300s: %.200s; the measures "
                          "that apply: %.900s",
             by_plot ? "--plot" : "--measure", by_plot ? sw->plot_arg : sw->measure_arg, which,
             where, why, apply);
    return -1;
}

/* A scene of named rods is run by rods_run.h: its measures are each rod's
 * tip and end forces (a column per rod) and the run's steps and times; the
 * result files and the figure hold one rod's measures. 0, or -1 with a
 * message. */
static int check_rods_apply(const sweep *sw, char *err, size_t errlen)
{
    char listed[SWEEP_MAX_RODS * (SWEEP_ROD_NAME_LEN + 2)] = "";
    for (int k = 0; k < sw->rod_count; k++)
        snprintf(listed + strlen(listed), sizeof listed - strlen(listed), "%s%s", k ? ", " : "",
                 sw->rod_names[k]);
    for (int i = 0; i < sw->measure_count; i++) {
        int m = sw->measures[i];
        if (sweep_rod_slot(m) >= 0 || m == SWEEP_M_STEPS || m == SWEEP_M_WALL ||
            m == SWEEP_M_CPU)
            continue;
        snprintf(err, errlen, "--measure %.200s: %s does not apply to %.300s, a scene of "
                              "several rods (%s); the measures that apply: tip_x, tip_y, "
                              "tip_z, root_fx .. root_fz, tip_fx .. tip_fz, root_f, tip_f (a "
                              "column per rod: tip_fz[%s]), steps, wall_s, cpu_s",
                 sw->measure_arg ? sw->measure_arg : "",
                 m == SWEEP_M_PUNCTURE_COLUMNS ? "puncture_f" : sweep_measure_names[m],
                 sw->scene_arg, listed, sw->rod_names[0]);
        return -1;
    }
    const char *option = sw->plot_arg ? "--plot" : sw->result_dir ? "--result" : NULL;
    if (option) {
        snprintf(err, errlen, "%s: a scene of several rods (%s) is swept into the CSV only "
                              "(--csv); %s holds one rod's measures", option, listed, option);
        return -1;
    }
    return 0;
}

/* Every point's scene read before anything runs: a value a key does not
 * accept is bad input naming the --vary argument. */
int sweep_check_points(const sweep *sw, sweep_setting *set, uint64_t *digests, char *err,
                       size_t errlen)
{
    for (int k = 0; k < sw->point_count; k++) {
        char msg[SWEEP_ERR_LEN] = "";
        int n = sweep_point_settings(sw, k, set, err, errlen);
        if (n < 0) return -1;
        digests[k] = sweep_point_digest(sw, set, n);
        rod_model m = rod_model_default();
        run_output out;
        ini_doc *doc = sweep_point_doc(sw, set, n, msg, sizeof msg);
        if (sw->rod_count > 0) { /* named rods: read as `rodsim run` reads them */
            rod_set rods;
            int bad = !doc || ini_check_keys(doc, scene_keys_rod, msg, sizeof msg) ||
                      scene_read_rods(doc, &rods, msg, sizeof msg);
            if (!bad) {
                bad = run_read_output(doc, &out, msg, sizeof msg) ||
                      ini_check_unused(doc, msg, sizeof msg);
                rod_set_release(&rods);
            }
            if (!bad) {
                ini_destroy(doc);
                if (k == 0 && check_rods_apply(sw, err, errlen)) return -1;
                continue;
            }
            ini_destroy(doc);
            doc = NULL;
            goto refused;
        }
        int bad = !doc || run_read_scene(doc, &m, &out, msg, sizeof msg);
        if (!bad) {
            char what[512], where[OUTFILE_PATH_MAX + 600];
            sweep_describe_point(sw, k, what, sizeof what);
            if (what[0])
                snprintf(where, sizeof where, "%s at point %d (%s)", sw->scene_arg, k + 1, what);
            else
                snprintf(where, sizeof where, "%s", sw->scene_arg);
            int inapt = check_measures_apply(sw, &m, where, err, errlen);
            rod_model_release(&m);
            ini_destroy(doc);
            if (inapt) return -1;
            continue;
        }
        ini_destroy(doc);
    refused:;
        const char *arg = NULL;
        for (int i = 0; i < sw->vary_count && !arg; i++) {
            char named[SWEEP_KEY_LEN + 8];
            snprintf(named, sizeof named, "--set %s", sw->varies[i].key);
            if (strstr(msg, named)) arg = sw->varies[i].arg;
        }
        char what[512];
        sweep_describe_point(sw, k, what, sizeof what);
        if (arg)
            snprintf(err, errlen, "--vary %.200s: point %d of %d (%.200s): %.1500s", arg, k + 1,
                     sw->point_count, what, msg);
        else if (what[0])
            snprintf(err, errlen, "point %d of %d (%.200s): %.1500s", k + 1, sw->point_count,
                     what, msg);
        else
            snprintf(err, errlen, "%s", msg);
        return -1;
    }
    return 0;
}

/* Checks where the outputs go before any work. */
int sweep_check_outputs(const sweep *sw, char *err, size_t errlen)
{
    /* --print-commands, --snakefile, --sbatch write no results now: only the script */
    int later = sw->print_commands || sw->snakefile || sw->sbatch;
    char why[512];
    if (sw->result_dir && !later && outfile_check_dir(sw->result_dir, why, sizeof why)) {
        snprintf(err, errlen, "--result %s: %s", sw->result_dir, why);
        return -1;
    }
    const char *files[6] = {sw->csv && strcmp(sw->csv, "-") != 0 ? sw->csv : NULL, sw->png,
                            sw->svg, sw->plot_arg ? sw->plot_csv : NULL, sw->snakefile,
                            sw->sbatch};
    /* the option that names each file (the plot's data is FILE.csv beside --png) */
    const char *const option[6] = {"--csv", "--png", "--svg", "the plot's data", "--snakefile",
                                   "--sbatch"};
    for (int i = later ? 4 : 0; i < 6; i++)
        if (files[i] && cli_check_output_file(option[i], files[i], err, errlen)) return -1;
    return 0;
}
