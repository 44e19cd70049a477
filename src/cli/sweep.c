/* sweep.c: `rodsim sweep` (see sweep.h): points, measures, workers, result
 * files, command lines. */
#include "cli/sweep.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "base/ini.h"
#include "base/outfile.h"
#include "base/embedded.h"
#include "base/spectrum.h"
#include "base/worker.h"
#include "cli/print_commands.h"
#include "cli/run.h"
#include "cli/scene_keys.h"
#include "cli/version.h"
#include "plot/plot.h"
#include "study/buckling.h"
#include "study/figure.h"

#define SWEEP_ERR_LEN 2048
#define SWEEP_MAX_JOBS 64
#define SWEEP_MAX_POINTS 1000000
#define SWEEP_VALUE_LEN 1024 /* a setting's value, bytes */
#define SWEEP_KEY_LEN 128
/* The time budget of one point, as `rodsim run` (run.c): a point estimated
 * to take longer is a `refused` row unless --allow-long. */
#define SWEEP_POINT_BUDGET 3600.0
/* Tip samples kept for first_frequency (3 doubles each): 4M frames, 96 MiB. */
#define SWEEP_MAX_SAMPLES (1 << 22)

void sweep_usage(FILE *f)
{
    fprintf(f,
            "usage: rodsim sweep SCENE --vary KEY=V1,V2,...|KEY=START:STOP:COUNT[:log] ...\n"
            "       [--set section.key=value]... [--measure WHAT,...] [--jobs N] [--csv FILE]\n"
            "       [--result DIR [--print-commands|--assemble|--snakefile F|--sbatch F]]\n"
            "       [--plot X:Y --png|--svg FILE]\n"
            "Runs SCENE (no video) at every point of the product of the --vary lists (the\n"
            "first varies slowest); one CSV row per point: the varied keys, the measures (empty:\n"
            "none), status (ok unstable no_convergence refused failed), message.\n"
            "  KEY            section.key as --set names it, or a vector's component, 0-based:\n"
            "                 tip.force[1] is y; whole vectors: 'tip.force=0 1e-7 0,0 2e-7 0'\n"
            "  --measure      tip_x tip_y tip_z (m, end of run), root_fx.. root_fz, tip_fx..\n"
            "                 tip_fz (N, on what holds the end), max_curvature (1/m),\n"
            "                 first_frequency (Hz, tip spectrum), critical_load (N),\n"
            "                 critical_moment (N m: the axial tip load where the straight\n"
            "                 rod buckles; only when asked), steps, wall_s, cpu_s (s);\n"
            "                 groups tip, root_force, tip_force, all; default tip,wall_s,cpu_s\n"
            "  --jobs N       N worker processes (1..64); rows stay in point order\n"
            "  --csv FILE     the results (default: standard output; - too)\n"
            "  --result DIR   one file per point, DIR/DIGEST.csv; existing ones are not rerun\n"
            "  --print-commands  one command line per point, and the # assemble: line\n"
            "  --snakefile FILE  write a Snakefile (needs --result, --csv): a job per point,\n"
            "                 then the CSV; run: snakemake -s FILE --cores N\n"
            "  --sbatch FILE  write a Slurm job array script (needs --result): task i runs\n"
            "                 point i; sbatch FILE, then its # assemble: line\n"
            "  --assemble     the CSV from DIR only (exit 1 when a point has no file)\n"
            "  --plot X:Y --png FILE --svg FILE [--log x|y|xy]  measure Y against varied key\n"
            "                 X, a curve per value of the other varied keys; data in FILE.csv\n"
            "  --allow-long   run points estimated over 1 hour;  --quiet  no progress lines\n"
            "Bad key, value, list, measure or axis: exit 2, nothing run or written.\n");
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

/* Measures ------------------------------------------------------------ */

enum {
    M_TIP_X, M_TIP_Y, M_TIP_Z,
    M_ROOT_FX, M_ROOT_FY, M_ROOT_FZ,
    M_TIP_FX, M_TIP_FY, M_TIP_FZ,
    M_MAX_CURVATURE, M_FIRST_FREQUENCY, M_CRITICAL_LOAD, M_CRITICAL_MOMENT, M_STEPS, M_WALL,
    M_CPU,
    M_COUNT
};
static const char *const measure_names[M_COUNT] = {
    "tip_x", "tip_y", "tip_z", "root_fx", "root_fy", "root_fz", "tip_fx", "tip_fy", "tip_fz",
    "max_curvature", "first_frequency", "critical_load", "critical_moment", "steps", "wall_s",
    "cpu_s"};

/* The unit of each measure, for plot axes. */
static const char *const measure_units[M_COUNT] = {
    "m", "m", "m", "N", "N", "N", "N", "N", "N", "1/m", "Hz", "N", "N m", "-", "s", "s"};

typedef enum {
    POINT_OK = 0, POINT_UNSTABLE, POINT_NO_CONVERGENCE, POINT_REFUSED, POINT_FAILED,
    POINT_STATUS_COUNT
} point_status;
static const char *const status_names[POINT_STATUS_COUNT] = {"ok", "unstable", "no_convergence",
                                                             "refused", "failed"};

/* One point's outcome: every measure (NAN where none), so a result file
 * serves any --measure list. Sent whole through a pipe (< PIPE_BUF). */
typedef struct point_result {
    double value[M_COUNT];
    int status; /* point_status */
    char message[800];
} point_result;

/* The sweep ------------------------------------------------------------ */

typedef struct vary {
    const char *arg;        /* the --vary argument, for messages */
    char key[SWEEP_KEY_LEN];  /* section.key */
    char name[SWEEP_KEY_LEN]; /* the CSV column: section.key or section.key[i] */
    int component;          /* -1: the whole value; else 0-based component */
    char **values;          /* owned */
    int count;
    char base[SWEEP_VALUE_LEN]; /* component: the scene's value of key (or the default) */
} vary;

typedef struct setting {
    char key[SWEEP_KEY_LEN];
    char value[SWEEP_VALUE_LEN];
} setting;

typedef struct sweep {
    const char *scene_arg;
    char scene_path[OUTFILE_PATH_MAX]; /* absolute */
    char *text;     /* the scene file's bytes, read once */
    size_t text_len;
    const char **sets; /* --set arguments */
    int set_count;
    vary *varies;
    int vary_count;
    int measures[M_COUNT]; /* the columns, in order */
    int measure_count;
    int jobs, quiet, allow_long, print_commands, assemble, help;
    int critical; /* critical_load or critical_moment asked for (--measure, --plot) */
    const char *csv;        /* NULL: standard output */
    const char *result_dir;
    const char *snakefile;  /* --snakefile FILE */
    const char *sbatch;     /* --sbatch FILE */
    const char **vary_args; /* as given, for the assemble line */
    const char *measure_arg;
    int point_count;
    const char *plot_arg, *png, *svg, *log_axes; /* --plot X:Y, --png, --svg, --log */
    int plot_x;       /* the varied key on the x axis */
    int plot_y;       /* the measure on the y axis */
    char plot_csv[OUTFILE_PATH_MAX]; /* the plotted data, beside the PNG */
} sweep;

/* Shortest "%.*g" (15..17 digits) that reads back as x: exact, and short
 * when the value is; "" for NAN (an empty CSV field: no value). */
static void format_double(double x, char *out, size_t n)
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

/* The value as ini_set keeps it: blanks trimmed, one pair of quotes off. */
static void canonical_value(const char *v, char *out, size_t n)
{
    const char *b = v, *e = v + strlen(v);
    while (b < e && (*b == ' ' || *b == '\t')) b++;
    while (e > b && (e[-1] == ' ' || e[-1] == '\t')) e--;
    if (e - b >= 2 && *b == '"' && e[-1] == '"') { b++; e--; }
    snprintf(out, n, "%.*s", (int)(e - b), b);
}

static void free_sweep(sweep *sw)
{
    for (int i = 0; i < sw->vary_count; i++) {
        for (int j = 0; j < sw->varies[i].count; j++) free(sw->varies[i].values[j]);
        free(sw->varies[i].values);
    }
    free(sw->varies);
    free(sw->sets);
    free(sw->vary_args);
    free(sw->text);
}

/* Splits a --vary value into its list: V1,V2,... or START:STOP:COUNT[:log].
 * 0, or -1 with a message naming the argument. */
static int parse_values(vary *v, const char *list, char *err, size_t errlen)
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
            format_double(x, text, sizeof text);
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
static int parse_vary(vary *v, const char *arg, char *err, size_t errlen)
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

static int add_measures(sweep *sw, const char *list, char *err, size_t errlen)
{
    char buf[512];
    snprintf(buf, sizeof buf, "%s", list);
    sw->measure_count = 0;
    for (char *p = buf, *tok; (tok = strsep(&p, ",")); ) {
        int first = -1, last = -1;
        if (strcmp(tok, "tip") == 0) first = M_TIP_X, last = M_TIP_Z;
        else if (strcmp(tok, "root_force") == 0) first = M_ROOT_FX, last = M_ROOT_FZ;
        else if (strcmp(tok, "tip_force") == 0) first = M_TIP_FX, last = M_TIP_FZ;
        else if (strcmp(tok, "all") == 0) first = 0, last = M_COUNT - 1;
        for (int m = 0; m < M_COUNT && first < 0; m++)
            if (strcmp(tok, measure_names[m]) == 0) first = last = m;
        if (first < 0) {
            char accepted[512] = "";
            for (int m = 0; m < M_COUNT; m++) {
                strcat(accepted, measure_names[m]);
                strcat(accepted, ", ");
            }
            snprintf(err, errlen, "--measure %s: unknown measure '%s'; accepted: %sand the "
                                  "groups tip, root_force, tip_force, all", list, tok, accepted);
            return -1;
        }
        for (int m = first; m <= last; m++) {
            int seen = 0;
            for (int i = 0; i < sw->measure_count; i++) seen |= sw->measures[i] == m;
            if (!seen) sw->measures[sw->measure_count++] = m;
        }
    }
    return 0;
}

/* An option's value: present, and not an option word. */
static int take_value(int argc, char **argv, int *i, const char **out, char *err, size_t errlen)
{
    const char *opt = argv[*i];
    if (*i + 1 >= argc || (argv[*i + 1][0] == '-' && argv[*i + 1][1] != '\0')) {
        snprintf(err, errlen, "%s needs a value%s%s", opt, *i + 1 < argc ? ", got the option " : "",
                 *i + 1 < argc ? argv[*i + 1] : "");
        return -1;
    }
    *out = argv[++*i];
    return 0;
}

/* --plot X:Y: X a varied key with numeric values, Y a measure; with --png. */
static int parse_plot(sweep *sw, char *err, size_t errlen)
{
    if (!sw->plot_arg) {
        if (sw->png || sw->svg || sw->log_axes) {
            snprintf(err, errlen, "%s needs --plot X:Y",
                     sw->png ? "--png" : sw->svg ? "--svg" : "--log");
            return -1;
        }
        return 0;
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
    for (int m = 0; m < M_COUNT; m++) {
        if (colon && strcmp(colon + 1, measure_names[m]) == 0) sw->plot_y = m;
        snprintf(measures + strlen(measures), sizeof measures - strlen(measures), "%s%s",
                 m ? ", " : "", measure_names[m]);
    }
    if (sw->plot_x < 0) {
        snprintf(err, errlen, "--plot %s: the x axis must be a varied key; accepted: %s",
                 sw->plot_arg, sw->vary_count ? varied : "(no --vary given)");
        return -1;
    }
    if (sw->plot_y < 0) {
        snprintf(err, errlen, "--plot %s: the y axis must be a measure; accepted: %s",
                 sw->plot_arg, measures);
        return -1;
    }
    const vary *v = &sw->varies[sw->plot_x];
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

static int parse_args(int argc, char **argv, sweep *sw, char *err, size_t errlen)
{
    sw->jobs = 1;
    sw->sets = calloc((size_t)argc, sizeof *sw->sets);
    sw->vary_args = calloc((size_t)argc, sizeof *sw->vary_args);
    sw->varies = calloc((size_t)argc, sizeof *sw->varies);
    if (!sw->sets || !sw->vary_args || !sw->varies) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    const char *measure = "tip,wall_s,cpu_s";
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *value = NULL;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) sw->help = 1;
        else if (strcmp(a, "--quiet") == 0 || strcmp(a, "-q") == 0) sw->quiet = 1;
        else if (strcmp(a, "--allow-long") == 0) sw->allow_long = 1;
        else if (strcmp(a, "--print-commands") == 0) sw->print_commands = 1;
        else if (strcmp(a, "--assemble") == 0) sw->assemble = 1;
        else if (strcmp(a, "--set") == 0) {
            if (take_value(argc, argv, &i, &value, err, errlen)) return -1;
            if (!strchr(value, '=')) {
                snprintf(err, errlen, "--set expects section.key=value in one argument, got "
                                      "'%s'", value);
                return -1;
            }
            sw->sets[sw->set_count++] = value;
        } else if (strcmp(a, "--vary") == 0) {
            if (take_value(argc, argv, &i, &value, err, errlen)) return -1;
            sw->vary_args[sw->vary_count] = value;
            if (parse_vary(&sw->varies[sw->vary_count++], value, err, errlen)) return -1;
        } else if (strcmp(a, "--measure") == 0) {
            if (take_value(argc, argv, &i, &measure, err, errlen)) return -1;
        } else if (strcmp(a, "--csv") == 0) {
            if (i + 1 < argc && strcmp(argv[i + 1], "-") == 0) sw->csv = argv[++i];
            else if (take_value(argc, argv, &i, &sw->csv, err, errlen)) return -1;
        } else if (strcmp(a, "--plot") == 0) {
            if (take_value(argc, argv, &i, &sw->plot_arg, err, errlen)) return -1;
        } else if (strcmp(a, "--png") == 0) {
            if (take_value(argc, argv, &i, &sw->png, err, errlen)) return -1;
        } else if (strcmp(a, "--svg") == 0) {
            if (take_value(argc, argv, &i, &sw->svg, err, errlen)) return -1;
        } else if (strcmp(a, "--log") == 0) {
            if (take_value(argc, argv, &i, &sw->log_axes, err, errlen)) return -1;
        } else if (strcmp(a, "--sbatch") == 0) {
            if (take_value(argc, argv, &i, &sw->sbatch, err, errlen)) return -1;
        } else if (strcmp(a, "--snakefile") == 0) {
            if (take_value(argc, argv, &i, &sw->snakefile, err, errlen)) return -1;
        } else if (strcmp(a, "--result") == 0) {
            if (take_value(argc, argv, &i, &sw->result_dir, err, errlen)) return -1;
        } else if (strcmp(a, "--jobs") == 0 || strcmp(a, "-j") == 0) {
            if (take_value(argc, argv, &i, &value, err, errlen)) return -1;
            char *end;
            long jobs = strtol(value, &end, 10);
            if (end == value || *end != '\0' || jobs < 1 || jobs > SWEEP_MAX_JOBS) {
                snprintf(err, errlen, "--jobs %s: accepted 1 .. %d", value, SWEEP_MAX_JOBS);
                return -1;
            }
            sw->jobs = (int)jobs;
        } else if (a[0] == '-' && a[1] != '\0') {
            snprintf(err, errlen, "unknown option '%s'", a);
            return -1;
        } else if (sw->scene_arg) {
            snprintf(err, errlen, "only one SCENE may be given ('%s' and '%s'; a value with "
                                  "spaces needs quotes)", sw->scene_arg, a);
            return -1;
        } else {
            sw->scene_arg = a;
        }
    }
    if (sw->help) return 0;
    if (!sw->scene_arg) {
        snprintf(err, errlen, "no SCENE given");
        return -1;
    }
    sw->measure_arg = measure;
    if (add_measures(sw, measure, err, errlen)) return -1;
    for (int i = 0; i < sw->vary_count; i++)
        for (int j = 0; j < i; j++)
            if (strcmp(sw->varies[i].name, sw->varies[j].name) == 0) {
                snprintf(err, errlen, "--vary %s: %s is already varied by --vary %s",
                         sw->varies[i].arg, sw->varies[i].name, sw->varies[j].arg);
                return -1;
            }
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
    if (parse_plot(sw, err, errlen)) return -1;
    /* Decision: the buckling search costs more than a short run (2 s at NS =
     * 401), so it runs only when asked; the request is part of the points'
     * digests, so a result file without it is never taken for one with it. */
    for (int i = 0; i < sw->measure_count; i++)
        sw->critical |= sw->measures[i] == M_CRITICAL_LOAD ||
                        sw->measures[i] == M_CRITICAL_MOMENT;
    sw->critical |= sw->plot_arg &&
                    (sw->plot_y == M_CRITICAL_LOAD || sw->plot_y == M_CRITICAL_MOMENT);
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

/* Reads the scene's bytes once (they are also the digest's input). */
static int read_scene(sweep *sw, char *err, size_t errlen)
{
    if (cli_absolute_path(sw->scene_arg, sw->scene_path, sizeof sw->scene_path, err, errlen))
        return -1;
    FILE *f = fopen(sw->scene_arg, "rb");
    if (!f) {
        snprintf(err, errlen, "%s: cannot open scene file: %s", sw->scene_arg, strerror(errno));
        return -1;
    }
    size_t cap = 4096, len = 0, got;
    char *text = malloc(cap);
    while (text && (got = fread(text + len, 1, cap - len - 1, f)) > 0) {
        len += got;
        if (len + 1 == cap) {
            char *bigger = realloc(text, cap * 2);
            if (!bigger) { free(text); text = NULL; break; }
            text = bigger;
            cap *= 2;
        }
    }
    int bad = !text || ferror(f);
    fclose(f);
    if (bad) {
        free(text);
        snprintf(err, errlen, "%s: cannot read scene file", sw->scene_arg);
        return -1;
    }
    text[len] = '\0';
    if (strlen(text) != len) {
        free(text);
        snprintf(err, errlen, "%s: not a text file (contains a NUL byte)", sw->scene_arg);
        return -1;
    }
    sw->text = text;
    sw->text_len = len;
    return 0;
}

/* A component --vary starts from the key's value in the scene, or else its
 * default (scene_keys.c). */
static int read_bases(sweep *sw, char *err, size_t errlen)
{
    ini_doc *doc = ini_parse(sw->scene_arg, sw->text, err, errlen);
    if (!doc) return -1;
    for (int i = 0; i < sw->vary_count; i++) {
        vary *v = &sw->varies[i];
        if (v->component < 0) continue;
        char section[SWEEP_KEY_LEN];
        snprintf(section, sizeof section, "%s", v->key);
        char *dot = strchr(section, '.');
        *dot = '\0';
        const char *value = NULL;
        if (ini_get_string(doc, section, 0, dot + 1, &value, err, errlen) != 1) {
            value = NULL;
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
static int value_index(const sweep *sw, int point, int which)
{
    int stride = 1;
    for (int i = sw->vary_count - 1; i > which; i--) stride *= sw->varies[i].count;
    return point / stride % sw->varies[which].count;
}

static setting *find_setting(setting *s, int n, const char *key)
{
    for (int i = 0; i < n; i++)
        if (strcmp(s[i].key, key) == 0) return &s[i];
    return NULL;
}

static int compare_settings(const void *a, const void *b)
{
    return strcmp(((const setting *)a)->key, ((const setting *)b)->key);
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
static int point_settings(const sweep *sw, int point, setting *out, char *err, size_t errlen)
{
    int n = 0;
    for (int i = 0; i < sw->set_count; i++) {
        const char *eq = strchr(sw->sets[i], '=');
        char raw[SWEEP_KEY_LEN], key[SWEEP_KEY_LEN];
        snprintf(raw, sizeof raw, "%.*s", (int)(eq - sw->sets[i]), sw->sets[i]);
        canonical_value(raw, key, sizeof key);
        setting *s = find_setting(out, n, key);
        if (!s) {
            s = &out[n++];
            snprintf(s->key, sizeof s->key, "%s", key);
        }
        canonical_value(eq + 1, s->value, sizeof s->value);
    }
    for (int i = 0; i < sw->vary_count; i++) {
        const vary *v = &sw->varies[i];
        const char *value = v->values[value_index(sw, point, i)];
        setting *s = find_setting(out, n, v->key);
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
                format_double(x[k], num, sizeof num);
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
static ini_doc *point_doc(const sweep *sw, const setting *s, int n, char *err, size_t errlen)
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
static uint64_t point_digest(const sweep *sw, const setting *s, int n)
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

/* Running a point -------------------------------------------------------- */

static double clock_seconds(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct tip_samples {
    double *xyz; /* (count x 3), m */
    int64_t count, capacity;
} tip_samples;

static int sample_tip(void *context, const rod_model *m, const rod_state *s, char *err,
                      size_t errlen)
{
    (void)m, (void)err, (void)errlen;
    tip_samples *t = context;
    if (t->count < t->capacity)
        memcpy(&t->xyz[3 * t->count++], &s->position[3 * (s->nodes - 1)], 3 * sizeof(double));
    return 0;
}

/* The first frequency of the tip's motion, Hz: the spectral peak
 * (spectrum.h) of the tip coordinate that moves most, mean removed, sampled
 * at the output times 1/fps, searched from 1.5 cycles per run to 0.45 fps
 * (below Nyquist). Decision: NAN when the tip does not move or the peak sits
 * at the band's edge (no oscillation in the band: a static or settling run). */
static double first_frequency(const tip_samples *t, double dt)
{
    if (t->count < 8 || t->count < t->capacity) return NAN;
    int axis = 0;
    double range[3];
    for (int a = 0; a < 3; a++) {
        double lo = INFINITY, hi = -INFINITY;
        for (int64_t i = 0; i < t->count; i++) {
            lo = fmin(lo, t->xyz[3 * i + a]);
            hi = fmax(hi, t->xyz[3 * i + a]);
        }
        range[a] = hi - lo;
        if (range[a] > range[axis]) axis = a;
    }
    if (!(range[axis] > 0.0)) return NAN;
    double *y = malloc(sizeof(double) * (size_t)t->count), mean = 0.0;
    if (!y) return NAN;
    for (int64_t i = 0; i < t->count; i++) mean += t->xyz[3 * i + axis];
    mean /= (double)t->count;
    for (int64_t i = 0; i < t->count; i++) y[i] = t->xyz[3 * i + axis] - mean;
    double span = dt * (double)(t->count - 1);
    double lo = 1.5 / span, hi = 0.45 / dt;
    double f = lo < hi ? spectrum_peak(y, (int)t->count, dt, lo, hi) : NAN;
    free(y);
    if (f < lo + 1e-3 * (hi - lo) || f > hi - 1e-3 * (hi - lo)) return NAN;
    return f;
}

static void set_message(point_result *r, point_status status, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static void set_message(point_result *r, point_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->message, sizeof r->message, fmt, ap);
    va_end(ap);
    r->status = status;
}

/* How far critical_load searches: up to 100 times the scene's axial tip
 * load, and at least up to 100 times the rod's own scale, |F| L^2/EI +
 * |M| L/EI = 100 (40 times Euler's clamped-free load pi^2/4, 11 times
 * Greenhill's clamped moment 8.99), so that a figure may sweep L and d
 * (scale EI/L^2: d^4/L^2) with one small load in its scene; a rod still
 * stable there is reported as none (NAN). */
#define SWEEP_CRITICAL_FACTOR_MAX 100.0
#define SWEEP_CRITICAL_SCALE_MAX 100.0

/* critical_load (N) and critical_moment (N m): the scene's axial tip force
 * and twisting moment, scaled together by the load factor at which the
 * straight rod stops being stable (rod_buckling_factor, buckling.h: the
 * static tangent stiffness at the straight state turns singular), given as
 * magnitudes. Decision: the transverse parts of the tip load are dropped
 * first (scenes carry a small one as an imperfection that triggers the
 * bifurcation: scenes/buckling_axial.ini); its time profile is ignored. NAN
 * when the straight rod is no equilibrium (gravity, curvature, ...), the
 * axial load is zero, or no loss of stability is found up to
 * the search's end above (a tensile force; a follower force: flutter). */
static void critical_loads(const rod_model *m, point_result *r)
{
    rod_model axial = *m; /* shallow: only read, never released */
    int axis = m->tip_frame == ROD_FRAME_DIRECTOR ? 2 : 0; /* as buckling.c */
    for (int k = 0; k < 3; k++)
        if (k != axis) axial.tip_force[k] = axial.tip_moment[k] = 0.0;
    double lambda, length = m->length, ei = m->stiffness[0];
    double size = fabs(axial.tip_force[axis]) * length * length / ei +
                  fabs(axial.tip_moment[axis]) * length / ei;
    double lambda_max = size > 0.0 ? fmax(SWEEP_CRITICAL_FACTOR_MAX,
                                          SWEEP_CRITICAL_SCALE_MAX / size)
                                   : SWEEP_CRITICAL_FACTOR_MAX; /* refused below: no load */
    char err[512];
    if (!isfinite(lambda_max) ||
        rod_buckling_factor(&axial, lambda_max, 1e-7, &lambda, err, sizeof err))
        return;
    if (axial.tip_force[axis] != 0.0)
        r->value[M_CRITICAL_LOAD] = lambda * fabs(axial.tip_force[axis]);
    if (axial.tip_moment[axis] != 0.0)
        r->value[M_CRITICAL_MOMENT] = lambda * fabs(axial.tip_moment[axis]);
}

/* Runs one point as `rodsim run --no-video` would (run_read_scene, the dt
 * and plan of run.c, run_simulate) and measures it. */
static void run_point(const sweep *sw, int point, point_result *r)
{
    double wall0 = clock_seconds(CLOCK_MONOTONIC);
    double cpu0 = clock_seconds(CLOCK_PROCESS_CPUTIME_ID);
    memset(r, 0, sizeof *r);
    for (int i = 0; i < M_COUNT; i++) r->value[i] = NAN;
    char err[SWEEP_ERR_LEN] = "";
    setting *set = calloc((size_t)(sw->set_count + sw->vary_count + 1), sizeof *set);
    rod_model m = rod_model_default();
    run_output out;
    rod_solver solver = {0};
    rod_state *s = NULL;
    tip_samples tip = {0};
    ini_doc *doc = NULL;
    int n = set ? point_settings(sw, point, set, err, sizeof err) : -1;
    if (n < 0 || !(doc = point_doc(sw, set, n, err, sizeof err)) ||
        run_read_scene(doc, &m, &out, err, sizeof err)) {
        set_message(r, POINT_FAILED, "%s", set ? err : "out of memory"); /* checked up front */
        goto done;
    }
    const char *why = "";
    double dt = rod_choose_dt(&m, &why);
    if (!(dt > 0.0)) dt = 1.0 / out.fps; /* as run.c: the scheme then reports the divergence */
    run_plan plan;
    const char *scheme = rod_scheme_get(m.options.scheme)->name;
    if (run_plan_make(&m, dt, out.fps, &plan)) {
        set_message(r, POINT_REFUSED, "%.3g steps and %.3g frames: more than %.0e",
                    plan.steps_estimate, plan.frames_estimate, RUN_MAX_COUNT);
        goto done;
    }
    double estimate = run_plan_seconds(&plan, m.nodes, 0, 0);
    if (estimate > SWEEP_POINT_BUDGET && !sw->allow_long) {
        set_message(r, POINT_REFUSED, "estimated %.3g s (%lld steps of the %s scheme at "
                                      "NS = %d): over the %.0f s budget; --allow-long runs it",
                    estimate, (long long)plan.steps, scheme, m.nodes, SWEEP_POINT_BUDGET);
        goto done;
    }
    if (rod_solver_init(&solver, &m, err, sizeof err)) {
        set_message(r, POINT_REFUSED, "cannot start the %s scheme: %s", scheme, err);
        goto done;
    }
    s = rod_state_create(&m);
    if (plan.frames <= SWEEP_MAX_SAMPLES) {
        tip.capacity = plan.frames;
        tip.xyz = malloc(sizeof(double) * 3 * (size_t)plan.frames);
    }
    if (!s || !tip.xyz) {
        set_message(r, POINT_FAILED, "out of memory for rod.nodes = %d", m.nodes);
        goto done;
    }
    rod_report report;
    run_stats stats;
    rod_status st = run_simulate(&solver, &m, s, &plan, out.fps, sample_tip, &tip, &report,
                                 &stats);
    r->value[M_STEPS] = (double)stats.steps;
    if (st != ROD_OK) {
        point_status ps = st == ROD_UNSTABLE ? POINT_UNSTABLE
                        : st == ROD_NO_CONVERGENCE ? POINT_NO_CONVERGENCE : POINT_FAILED;
        char advice[160] = "";
        if (report.suggested_dt > 0.0 && !report.message[0]) /* the message has its own */
            snprintf(advice, sizeof advice, "; what would work: solver.dt = %g",
                     report.suggested_dt);
        set_message(r, ps, "the %s scheme stopped at t = %g s (dt = %g s)%s%s%s%s", scheme,
                    s->time, stats.largest_step > 0.0 ? stats.largest_step : dt,
                    stats.non_finite ? ": the state is no longer finite" : "",
                    report.message[0] ? ": " : "", report.message, advice);
        goto done;
    }
    const double *t = &s->position[3 * (s->nodes - 1)];
    for (int a = 0; a < 3; a++) {
        r->value[M_TIP_X + a] = t[a];
        r->value[M_ROOT_FX + a] = s->end_force[0][a];
        r->value[M_TIP_FX + a] = s->end_force[1][a];
    }
    double curvature = 0.0;
    for (int i = 0; i < s->nodes; i++) {
        const double *u = &s->darboux[3 * i];
        curvature = fmax(curvature, sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]));
    }
    r->value[M_MAX_CURVATURE] = curvature;
    r->value[M_FIRST_FREQUENCY] = first_frequency(&tip, 1.0 / out.fps);
    if (report.warning[0]) snprintf(r->message, sizeof r->message, "%s", report.warning);
    r->status = POINT_OK;
done:
    r->value[M_WALL] = clock_seconds(CLOCK_MONOTONIC) - wall0;
    r->value[M_CPU] = clock_seconds(CLOCK_PROCESS_CPUTIME_ID) - cpu0;
    if (sw->critical && r->status == POINT_OK) critical_loads(&m, r); /* not timed: not the run */
    free(tip.xyz);
    rod_state_destroy(s);
    rod_solver_release(&solver);
    rod_model_release(&m);
    ini_destroy(doc);
    free(set);
}

/* Result files ------------------------------------------------------------ */

/* A CSV field per RFC 4180: quoted when it holds a comma, quote or line
 * break (quotes doubled), or always when `quote`. */
static void csv_field(FILE *f, const char *text, int quote)
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

static void result_path(const sweep *sw, uint64_t digest, char *out, size_t n)
{
    snprintf(out, n, "%s/%016llx.csv", sw->result_dir, (unsigned long long)digest);
}

/* DIR/DIGEST.csv: a header of every measure, status, message, and one row.
 * Written whole or not at all (outfile.h): a killed sweep leaves none half. */
static int write_result(const sweep *sw, uint64_t digest, const point_result *r, char *err,
                        size_t errlen)
{
    char path[OUTFILE_PATH_MAX];
    result_path(sw, digest, path, sizeof path);
    outfile f = {.fd = -1, .slot = -1};
    if (outfile_open(&f, path, err, errlen)) return -1;
    for (int m = 0; m < M_COUNT; m++) fprintf(f.fp, "%s,", measure_names[m]);
    fprintf(f.fp, "status,message\n");
    for (int m = 0; m < M_COUNT; m++) {
        char num[40];
        format_double(r->value[m], num, sizeof num);
        fprintf(f.fp, "%s,", num);
    }
    fprintf(f.fp, "%s,", status_names[r->status]);
    csv_field(f.fp, r->message, 1);
    fputc('\n', f.fp);
    if (ferror(f.fp)) {
        outfile_abort(&f);
        snprintf(err, errlen, "%s: write failed", path);
        return -1;
    }
    return outfile_commit(&f, err, errlen);
}

/* Reads the next CSV field (RFC 4180) at *p into out; 1 when a field
 * followed by ',' was read, 0 at the end of the record. */
static int read_field(const char **p, char *out, size_t n)
{
    const char *c = *p;
    size_t len = 0;
    if (*c == '"') {
        for (c++; *c && !(c[0] == '"' && c[1] != '"'); c++) {
            if (c[0] == '"') c++;
            if (len + 1 < n) out[len++] = *c;
        }
        if (*c == '"') c++;
    } else {
        for (; *c && *c != ',' && *c != '\n' && *c != '\r'; c++)
            if (len + 1 < n) out[len++] = *c;
    }
    out[len] = '\0';
    *p = *c == ',' ? c + 1 : c;
    return *c == ',';
}

/* 1 when the point's result file exists (and is read into r), 0 when it
 * does not, -1 when it cannot be read (message). */
static int read_result(const sweep *sw, uint64_t digest, point_result *r, char *err,
                       size_t errlen)
{
    char path[OUTFILE_PATH_MAX];
    result_path(sw, digest, path, sizeof path);
    FILE *f = fopen(path, "rb");
    if (!f) {
        if (errno == ENOENT) return 0;
        snprintf(err, errlen, "%s: %s", path, strerror(errno));
        return -1;
    }
    char text[4096];
    size_t got = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[got] = '\0';
    char header[512] = "";
    for (int m = 0; m < M_COUNT; m++) {
        strcat(header, measure_names[m]);
        strcat(header, ",");
    }
    strcat(header, "status,message\n");
    memset(r, 0, sizeof *r);
    const char *p = text + strlen(header);
    int ok = strncmp(text, header, strlen(header)) == 0;
    char field[sizeof r->message];
    for (int m = 0; ok && m < M_COUNT; m++) {
        ok = read_field(&p, field, sizeof field);
        char *end;
        r->value[m] = field[0] ? strtod(field, &end) : NAN;
        ok = ok && (!field[0] || *end == '\0');
    }
    ok = ok && read_field(&p, field, sizeof field);
    r->status = -1;
    for (int k = 0; ok && k < POINT_STATUS_COUNT; k++)
        if (strcmp(field, status_names[k]) == 0) r->status = k;
    if (!ok || r->status < 0) {
        snprintf(err, errlen, "%s: not a rodsim sweep result file (remove it to run the point "
                              "again)", path);
        return -1;
    }
    read_field(&p, r->message, sizeof r->message);
    return 1;
}

/* Running the sweep ------------------------------------------------------- */

typedef struct progress {
    const sweep *sw;
    point_result *rows;
    uint64_t *digests;
    int *done;
    int ran, reused, failed_writes;
} progress;

static void describe_point(const sweep *sw, int point, char *out, size_t n)
{
    out[0] = '\0';
    for (int i = 0; i < sw->vary_count; i++) {
        size_t len = strlen(out);
        snprintf(out + len, n - len, "%s%s=%s", i ? ", " : "", sw->varies[i].name,
                 sw->varies[i].values[value_index(sw, point, i)]);
    }
}

/* A point's row has come: its result file (when --result), a line on stderr. */
static void finish_point(progress *pg, int k)
{
    const sweep *sw = pg->sw;
    point_result *r = &pg->rows[k];
    pg->done[k] = 1;
    pg->ran++;
    char err[SWEEP_ERR_LEN];
    /* a worker that died or ran out of memory may succeed next time: no file */
    if (sw->result_dir && r->status != POINT_FAILED &&
        write_result(sw, pg->digests[k], r, err, sizeof err)) {
        fprintf(stderr, "rodsim sweep: %s\n", err);
        pg->failed_writes++;
    }
    if (!sw->quiet) {
        char what[512];
        describe_point(sw, k, what, sizeof what);
        fprintf(stderr, "rodsim sweep: point %d/%d%s%s%s: %s (%.3g s)%s%s\n", k + 1,
                sw->point_count, what[0] ? " (" : "", what, what[0] ? ")" : "",
                status_names[r->status], r->value[M_WALL], r->status ? ": " : "",
                r->status ? r->message : "");
    }
}

static int pool_run_point(void *context, int point, FILE *out)
{
    progress *pg = context;
    point_result r;
    run_point(pg->sw, point, &r);
    return fwrite(&r, sizeof r, 1, out) == 1 ? 0 : 1;
}

static int pool_point_done(void *context, int point, const char *bytes, size_t n, int status)
{
    progress *pg = context;
    point_result *r = &pg->rows[point];
    if (status == 0 && n == sizeof *r) {
        memcpy(r, bytes, sizeof *r);
    } else {
        memset(r, 0, sizeof *r);
        for (int m = 0; m < M_COUNT; m++) r->value[m] = NAN;
        set_message(r, POINT_FAILED, "worker process died (%s %d)",
                    WIFSIGNALED(status) ? "signal" : "exit status",
                    WIFSIGNALED(status) ? WTERMSIG(status) : WEXITSTATUS(status));
    }
    finish_point(pg, point);
    return 0;
}

/* Runs the points not yet done in up to sw->jobs forked workers (worker.h);
 * --jobs 1 runs them here. 0, or -1 with a message. */
static int run_points(progress *pg, char *err, size_t errlen)
{
    const sweep *sw = pg->sw;
    int *todo = malloc(sizeof(int) * (size_t)(sw->point_count + 1)), count = 0;
    if (!todo) {
        snprintf(err, errlen, "out of memory for %d points", sw->point_count);
        return -1;
    }
    for (int k = 0; k < sw->point_count; k++)
        if (!pg->done[k]) todo[count++] = k;
    worker_pool pool = {.jobs = sw->jobs, .context = pg, .run = pool_run_point,
                        .done = pool_point_done};
    int rc = worker_pool_run(&pool, todo, count, err, errlen);
    free(todo);
    return rc ? -1 : 0;
}

/* The results CSV: the varied keys, the measures, status, message. */
static void write_csv(FILE *f, const sweep *sw, const point_result *rows)
{
    for (int i = 0; i < sw->vary_count; i++) {
        csv_field(f, sw->varies[i].name, 0);
        fputc(',', f);
    }
    for (int i = 0; i < sw->measure_count; i++) fprintf(f, "%s,", measure_names[sw->measures[i]]);
    fprintf(f, "status,message\n");
    for (int k = 0; k < sw->point_count; k++) {
        for (int i = 0; i < sw->vary_count; i++) {
            csv_field(f, sw->varies[i].values[value_index(sw, k, i)], 0);
            fputc(',', f);
        }
        for (int i = 0; i < sw->measure_count; i++) {
            char num[40];
            format_double(rows[k].value[sw->measures[i]], num, sizeof num);
            fprintf(f, "%s,", num);
        }
        fprintf(f, "%s,", status_names[rows[k].status]);
        csv_field(f, rows[k].message, 1);
        fputc('\n', f);
    }
}

static const unsigned char curve_rgb[8][3] = {
    {0, 90, 200}, {200, 30, 30}, {0, 150, 60}, {200, 110, 0},
    {120, 60, 170}, {0, 150, 160}, {170, 40, 120}, {90, 90, 90}};

/* The axis label of a varied key: its name and the scene table's unit. */
static void key_label(const vary *v, char *out, size_t n)
{
    const char *unit = "-";
    for (const ini_key *k = scene_keys_rod; k->section; k++) {
        size_t len = strlen(k->section);
        if (strncmp(v->key, k->section, len) == 0 && v->key[len] == '.' &&
            strcmp(v->key + len + 1, k->key) == 0)
            unit = k->unit;
    }
    if (strcmp(unit, "-") == 0) snprintf(out, n, "%s", v->name);
    else snprintf(out, n, "%s [%s]", v->name, unit);
}

/* Reference curve samples per curve of a figure. */
#define SWEEP_REFERENCE_SAMPLES 200

/* A figure's outputs beside FILE.png: FILE_ratio.png (or .svg). */
static void ratio_path(const char *figure, char *out, size_t n)
{
    size_t len = strlen(figure);
    int ext = len > 4 && figure[len - 4] == '.';
    snprintf(out, n, "%.*s_ratio%s", (int)(ext ? len - 4 : len), figure,
             ext ? figure + len - 4 : "");
}

/* The reference line of a figure from x0 to x1 (SI) into the plots (the
 * ratio one when not NULL), in shown units. 0, or -1 with a message. */
static int reference_line(const figure_spec *fig, int part, double x0, double x1,
                          plot_style style, const char *legend, plot *p, plot *ratio,
                          double *y_hi, char *err, size_t errlen)
{
    double x_scale = fig->x_scale > 0.0 ? fig->x_scale : 1.0;
    double y_scale = fig->y_scale > 0.0 ? fig->y_scale : 1.0;
    double rx[SWEEP_REFERENCE_SAMPLES], ry[SWEEP_REFERENCE_SAMPLES];
    double rr[SWEEP_REFERENCE_SAMPLES];
    int samples = fig->reference_samples;
    if (samples < 2 || samples > SWEEP_REFERENCE_SAMPLES) samples = SWEEP_REFERENCE_SAMPLES;
    for (int i = 0; i < samples; i++) {
        double at = x0 + (x1 - x0) * i / (samples - 1.0);
        if (fig->reference(part, at, &ry[i], err, errlen)) return -1;
        if (ratio) rr[i] = ry[i] / fig->ratio_divisor(at);
        rx[i] = at * x_scale;
        ry[i] *= y_scale;
        *y_hi = fmax(*y_hi, ry[i]);
    }
    int rc = plot_add_line(p, rx, ry, samples, style, legend);
    if (ratio) rc |= plot_add_line(ratio, rx, rr, samples, style, legend);
    if (rc) snprintf(err, errlen, "out of memory for the plot");
    return rc ? -1 : 0;
}

/* --plot X:Y: one curve per combination of the other varied keys' values
 * (in point order), the points that are ok, sorted by x; the PNG and its
 * data (curve,X,Y) beside it. A figure (rodsim figure; fig not NULL) draws
 * the curves of several sweeps, its parts, into the outputs of the first,
 * with its own title and labels, values scaled to its units, each curve's
 * reference line beside its points (the data get a reference column), its
 * own marks, and a ratio figure when it has one. 0, or -1 with a message. */
static int write_plot(const sweep *const *parts, const point_result *const *part_rows,
                      int part_count, const figure_spec *fig,
                      const double *const *part_reference, char *err, size_t errlen)
{
    const sweep *sw = parts[0];
    const vary *xv = &sw->varies[sw->plot_x];
    int rc = 0, most = 0;
    for (int k = 0; k < part_count; k++) {
        const vary *v = &parts[k]->varies[parts[k]->plot_x];
        if (v->count > most) most = v->count;
    }
    double *x = malloc(sizeof(double) * (size_t)most);
    double *y = malloc(sizeof(double) * (size_t)most);
    double *r = malloc(sizeof(double) * (size_t)most);
    double *ref = malloc(sizeof(double) * (size_t)most);
    plot *p = plot_create(1200, 800);
    plot *ratio = fig && fig->ratio_divisor ? plot_create(1200, 800) : NULL;
    outfile data = {.fd = -1, .slot = -1};
    if (!x || !y || !r || !ref || !p || (fig && fig->ratio_divisor && !ratio)) {
        snprintf(err, errlen, "out of memory for the plot");
        rc = -1;
        goto done;
    }
    if (outfile_open(&data, sw->plot_csv, err, errlen)) {
        rc = -1;
        goto done;
    }
    double x_scale = fig && fig->x_scale > 0.0 ? fig->x_scale : 1.0;
    double y_scale = fig && fig->y_scale > 0.0 ? fig->y_scale : 1.0;
    if (fig) {
        plot_set_title(p, fig->title);
        plot_set_axis_labels(p, fig->x_label, fig->y_label);
        if (ratio) {
            plot_set_title(ratio, fig->ratio_title);
            plot_set_axis_labels(ratio, fig->x_label, fig->ratio_y_label);
        }
    } else {
        char xlabel[SWEEP_KEY_LEN + 32], ylabel[64], title[OUTFILE_PATH_MAX + 256], scene[128];
        key_label(xv, xlabel, sizeof xlabel);
        if (strcmp(measure_units[sw->plot_y], "-") == 0)
            snprintf(ylabel, sizeof ylabel, "%s", measure_names[sw->plot_y]);
        else
            snprintf(ylabel, sizeof ylabel, "%s [%s]", measure_names[sw->plot_y],
                     measure_units[sw->plot_y]);
        const char *base = strrchr(sw->scene_path, '/');
        snprintf(scene, sizeof scene, "%.127s", base ? base + 1 : sw->scene_path);
        snprintf(title, sizeof title, "%s: %s against %s", scene, measure_names[sw->plot_y],
                 xv->name);
        plot_set_title(p, title);
        plot_set_axis_labels(p, xlabel, ylabel);
    }
    if (sw->log_axes) plot_set_log(p, strchr(sw->log_axes, 'x') != NULL,
                                   strchr(sw->log_axes, 'y') != NULL);
    fprintf(data.fp, "curve,");
    csv_field(data.fp, xv->name, 0);
    fprintf(data.fp, ",%s%s\n", measure_names[sw->plot_y], fig ? ",reference" : "");
    double x_hi = 0.0, y_hi = 0.0, x_last = 0.0; /* the largest x varied, SI */
    for (int k = 0; k < part_count; k++) {
        const vary *v = &parts[k]->varies[parts[k]->plot_x];
        for (int j = 0; j < v->count; j++) x_last = fmax(x_last, strtod(v->values[j], NULL));
    }
    if (fig && fig->one_reference) { /* one line from ~0 (a ratio is 0/0 at 0) to the last x */
        plot_style black = plot_style_line(0, 0, 0, 2.0, PLOT_SOLID);
        if (reference_line(fig, 0, 1e-3 * x_last, x_last, black, fig->part[0].reference_legend,
                           p, ratio, &y_hi, err, errlen)) {
            rc = -1;
            goto done;
        }
    }
    for (int k = 0, seen = 0; k < part_count && rc == 0; k++) {
        const sweep *ps = parts[k];
        const point_result *rows = part_rows[k];
        const vary *pv = &ps->varies[ps->plot_x];
        int curves = ps->point_count / pv->count;
        for (int c = 0, drawn = 0; c < ps->point_count && drawn < curves && rc == 0; c++) {
            if (value_index(ps, c, ps->plot_x) != 0) continue; /* the first point of a curve */
            drawn++;
            char legend[512] = "";
            if (fig) snprintf(legend, sizeof legend, "%s", fig->part[k].legend);
            for (int i = 0; i < ps->vary_count; i++) {
                if (i == ps->plot_x) continue;
                size_t len = strlen(legend);
                snprintf(legend + len, sizeof legend - len, "%s%s = %s", len ? ", " : "",
                         ps->varies[i].name, ps->varies[i].values[value_index(ps, c, i)]);
            }
            int n = 0, stride = 1;
            for (int i = ps->vary_count - 1; i > ps->plot_x; i--) stride *= ps->varies[i].count;
            for (int j = 0; j < pv->count; j++) {
                const point_result *pr = &rows[c + j * stride];
                double value = pr->value[ps->plot_y];
                if (pr->status != POINT_OK || !isfinite(value)) continue;
                x[n] = strtod(pv->values[j], NULL);
                ref[n] = part_reference ? part_reference[k][c + j * stride] : NAN;
                y[n++] = value;
            }
            for (int a = 1; a < n; a++) /* by x: a list need not be in order */
                for (int b = a; b > 0 && x[b - 1] > x[b]; b--) {
                    double t = x[b]; x[b] = x[b - 1]; x[b - 1] = t;
                    t = y[b]; y[b] = y[b - 1]; y[b - 1] = t;
                    t = ref[b]; ref[b] = ref[b - 1]; ref[b - 1] = t;
                }
            const unsigned char *rgb = curve_rgb[seen++ % 8];
            if (fig && (fig->part[k].rgb[0] || fig->part[k].rgb[1] || fig->part[k].rgb[2]))
                rgb = fig->part[k].rgb;
            plot_style line = plot_style_line(rgb[0], rgb[1], rgb[2], 2.0, PLOT_SOLID);
            if (fig && !fig->one_reference && n >= 1 &&
                reference_line(fig, k, x[0], x[n - 1], line,
                               drawn == 1 ? fig->part[k].reference_legend : NULL, p, NULL,
                               &y_hi, err, errlen)) {
                rc = -1;
                goto done;
            }
            for (int j = 0; j < n; j++) {
                char nx[40], ny[40], nr[40] = "";
                format_double(x[j], nx, sizeof nx);
                format_double(y[j], ny, sizeof ny);
                format_double(ref[j], nr, sizeof nr);
                csv_field(data.fp, legend, 1);
                fprintf(data.fp, ",%s,%s%s%s\n", nx, ny, fig ? "," : "", nr);
                if (ratio) r[j] = y[j] / fig->ratio_divisor(x[j]);
                x[j] *= x_scale; /* shown units from here on */
                y[j] *= y_scale;
                x_hi = fmax(x_hi, x[j]);
                y_hi = fmax(y_hi, y[j]);
            }
            plot_style marker = line;
            /* a figure's parts may share points: later ones smaller, on top */
            marker.marker_size = fig ? fmax(6.0, 14.0 - 4.0 * k) : 8.0;
            marker.filled = 1;
            if (fig && k == 0) memset(marker.fill_rgb, 255, 3); /* hollow */
            else memcpy(marker.fill_rgb, rgb, 3);
            if (n >= 2 && !fig) rc |= plot_add_line(p, x, y, n, line, NULL);
            if (n >= 1) {
                rc |= plot_add_markers(p, x, y, n, marker, NULL, 0, 0, legend[0] ? legend : NULL);
                if (ratio)
                    rc |= plot_add_markers(ratio, x, r, n, marker, NULL, 0, 0,
                                           legend[0] ? legend : NULL);
            }
        }
    }
    if (fig && rc == 0) {
        if (fig->decorate)
            rc |= fig->decorate(p, 0, x_last) | (ratio ? fig->decorate(ratio, 1, x_last) : 0);
        if (fig->note) rc |= plot_add_legend_note(p, fig->note);
        if (x_hi > 0.0 && y_hi > 0.0) plot_set_limits(p, 0.0, 1.05 * x_hi, 0.0, 1.25 * y_hi);
    }
    if (rc) {
        snprintf(err, errlen, "out of memory for the plot");
        goto done;
    }
    if (ferror(data.fp)) {
        snprintf(err, errlen, "%s: write failed", sw->plot_csv);
        rc = -1;
        goto done;
    }
    char ratio_png[OUTFILE_PATH_MAX + 8], ratio_svg[OUTFILE_PATH_MAX + 8];
    if (ratio) {
        if (sw->png) ratio_path(sw->png, ratio_png, sizeof ratio_png);
        if (sw->svg) ratio_path(sw->svg, ratio_svg, sizeof ratio_svg);
    }
    rc = outfile_commit(&data, err, errlen) ||
                 (sw->png && plot_write_png(p, sw->png, err, errlen)) ||
                 (sw->svg && plot_write_svg(p, sw->svg, err, errlen)) ||
                 (ratio && sw->png && plot_write_png(ratio, ratio_png, err, errlen)) ||
                 (ratio && sw->svg && plot_write_svg(ratio, ratio_svg, err, errlen))
             ? -1 : 0;
done:
    outfile_abort(&data);
    plot_destroy(p);
    plot_destroy(ratio);
    free(x);
    free(y);
    free(r);
    free(ref);
    return rc;
}

/* Point k's command line (no newline): the binary and every path absolute,
 * every setting spelled out; it writes DIR/DIGEST.csv. */
static int write_point_command(FILE *f, const sweep *sw, int k, setting *set, const char *self,
                               const char *dir, char *err, size_t errlen)
{
    int n = point_settings(sw, k, set, err, errlen);
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
        cli_print_shell_word(f, sw->vary_args[i]);
    }
    for (int i = 0; i < sw->set_count; i++) {
        fprintf(f, " --set ");
        cli_print_shell_word(f, sw->sets[i]);
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
static int print_commands(const sweep *sw, setting *set, char *err, size_t errlen)
{
    char self[OUTFILE_PATH_MAX], dir[OUTFILE_PATH_MAX];
    if (cli_self_path(self, sizeof self, err, errlen) ||
        cli_absolute_path(sw->result_dir, dir, sizeof dir, err, errlen))
        return -1;
    printf("# rodsim sweep: %d points of %s; each line runs one point into %s (skipped when "
           "its result file is there)\n",
           sw->point_count, sw->scene_path, dir);
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
static int write_snakefile(const sweep *sw, setting *set, const uint64_t *digests, char *err,
                           size_t errlen)
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
    fprintf(f, "# Snakefile written by rodsim %s sweep --snakefile: %d points of %s.\n",
            RODSIM_VERSION, sw->point_count, sw->scene_path);
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
static int write_sbatch(const sweep *sw, setting *set, char *err, size_t errlen)
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
    fprintf(f, "# Slurm job array written by rodsim %s sweep --sbatch: %d points of %s.\n"
               "# sbatch THIS_FILE: task i runs point i into its result file\n"
               "# %s/DIGEST.csv (an existing file is not run again);\n"
               "# sbatch --array=1-%d%%K THIS_FILE runs at most K at once (over 1000 tasks:\n"
               "# Slurm's MaxArraySize must allow them). When all are done,\n"
               "# assemble the CSV (or: sbatch --dependency=afterok:JOBID --wrap 'LINE'):\n"
               "# assemble: ",
            RODSIM_VERSION, sw->point_count, sw->scene_path, dir, sw->point_count);
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

/* Every point's scene read before anything runs: a value a key does not
 * accept is bad input naming the --vary argument. */
static int check_points(const sweep *sw, setting *set, uint64_t *digests, char *err,
                        size_t errlen)
{
    for (int k = 0; k < sw->point_count; k++) {
        char msg[SWEEP_ERR_LEN] = "";
        int n = point_settings(sw, k, set, err, errlen);
        if (n < 0) return -1;
        digests[k] = point_digest(sw, set, n);
        rod_model m = rod_model_default();
        run_output out;
        ini_doc *doc = point_doc(sw, set, n, msg, sizeof msg);
        int bad = !doc || run_read_scene(doc, &m, &out, msg, sizeof msg);
        if (!bad) rod_model_release(&m);
        ini_destroy(doc);
        if (!bad) continue;
        const char *arg = NULL;
        for (int i = 0; i < sw->vary_count && !arg; i++) {
            char named[SWEEP_KEY_LEN + 8];
            snprintf(named, sizeof named, "--set %s", sw->varies[i].key);
            if (strstr(msg, named)) arg = sw->varies[i].arg;
        }
        char what[512];
        describe_point(sw, k, what, sizeof what);
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
static int check_outputs(const sweep *sw, char *err, size_t errlen)
{
    /* --print-commands, --snakefile, --sbatch write no results now: only the script */
    int later = sw->print_commands || sw->snakefile || sw->sbatch;
    if (sw->result_dir && !later && outfile_check_dir(sw->result_dir, err, errlen))
        return -1;
    const char *files[6] = {sw->csv && strcmp(sw->csv, "-") != 0 ? sw->csv : NULL, sw->png,
                            sw->svg, sw->plot_arg ? sw->plot_csv : NULL, sw->snakefile,
                            sw->sbatch};
    for (int i = later ? 4 : 0; i < 6; i++) {
        if (!files[i]) continue;
        struct stat st;
        if (stat(files[i], &st) == 0 && S_ISDIR(st.st_mode)) {
            snprintf(err, errlen, "%s: is a directory, not a file", files[i]);
            return -1;
        }
        char dir[OUTFILE_PATH_MAX];
        const char *slash = strrchr(files[i], '/');
        if (!slash) snprintf(dir, sizeof dir, ".");
        else snprintf(dir, sizeof dir, "%.*s", (int)(slash - files[i] + 1), files[i]);
        if (outfile_check_dir(dir, err, errlen)) return -1;
    }
    return 0;
}

static int sweep_run(sweep *sw)
{
    char err[SWEEP_ERR_LEN] = "";
    int status = RUN_EXIT_BAD_INPUT;
    setting *set = calloc((size_t)(sw->set_count + sw->vary_count + 1), sizeof *set);
    progress pg = {.sw = sw};
    pg.rows = calloc((size_t)sw->point_count, sizeof *pg.rows);
    pg.digests = calloc((size_t)sw->point_count, sizeof *pg.digests);
    pg.done = calloc((size_t)sw->point_count, sizeof *pg.done);
    outfile csv = {.fd = -1, .slot = -1};
    if (!set || !pg.rows || !pg.digests || !pg.done) {
        fprintf(stderr, "rodsim sweep: out of memory for %d points\n", sw->point_count);
        status = RUN_EXIT_FAILURE;
        goto done;
    }
    if (check_outputs(sw, err, sizeof err) || read_scene(sw, err, sizeof err) ||
        read_bases(sw, err, sizeof err) || check_points(sw, set, pg.digests, err, sizeof err))
        goto fail;
    if (sw->print_commands) {
        status = print_commands(sw, set, err, sizeof err) ? RUN_EXIT_FAILURE : RUN_EXIT_OK;
        if (status) fprintf(stderr, "rodsim sweep: %s\n", err);
        goto done;
    }
    if (sw->snakefile) {
        if (write_snakefile(sw, set, pg.digests, err, sizeof err)) goto fail;
        if (!sw->quiet)
            fprintf(stderr, "rodsim sweep: wrote %s (%d points); run: snakemake -s %s "
                            "--cores N\n", sw->snakefile, sw->point_count, sw->snakefile);
        status = RUN_EXIT_OK;
        goto done;
    }
    if (sw->sbatch) {
        if (write_sbatch(sw, set, err, sizeof err)) goto fail;
        if (!sw->quiet)
            fprintf(stderr, "rodsim sweep: wrote %s (a job array of %d tasks); submit: sbatch "
                            "%s, then its # assemble: line\n", sw->sbatch, sw->point_count,
                    sw->sbatch);
        status = RUN_EXIT_OK;
        goto done;
    }
    status = RUN_EXIT_FAILURE;
    if (sw->result_dir) {
        if (outfile_mkdirs(sw->result_dir, err, sizeof err)) goto fail;
        int missing = 0, first_missing = -1;
        for (int k = 0; k < sw->point_count; k++) {
            int got = read_result(sw, pg.digests[k], &pg.rows[k], err, sizeof err);
            if (got < 0) goto fail;
            pg.done[k] = got;
            pg.reused += got;
            if (!got && missing++ == 0) first_missing = k;
        }
        if (sw->assemble && missing) {
            char what[512], path[OUTFILE_PATH_MAX];
            describe_point(sw, first_missing, what, sizeof what);
            result_path(sw, pg.digests[first_missing], path, sizeof path);
            fprintf(stderr, "rodsim sweep: %d of %d points have no result in %s (the first: "
                            "point %d%s%s%s, %s); run their commands (--print-commands), or "
                            "the sweep without --assemble; nothing was written\n",
                    missing, sw->point_count, sw->result_dir, first_missing + 1,
                    what[0] ? " (" : "", what, what[0] ? ")" : "", path);
            goto done;
        }
    }
    if (run_points(&pg, err, sizeof err)) goto fail;
    if (pg.failed_writes) {
        fprintf(stderr, "rodsim sweep: %d result files could not be written; nothing else "
                        "was written\n", pg.failed_writes);
        goto done;
    }
    int failed = 0;
    for (int k = 0; k < sw->point_count; k++) failed += pg.rows[k].status != POINT_OK;
    /* a point command (--result, no --vary, no --csv) writes only its result file */
    int to_stdout = sw->csv ? strcmp(sw->csv, "-") == 0 : !sw->result_dir || sw->vary_count > 0;
    /* the CSV, the figure and its data: all or none (outfile.h) */
    outfile_transaction_begin();
    if (sw->csv && !to_stdout) {
        if (outfile_open(&csv, sw->csv, err, sizeof err)) goto fail;
        write_csv(csv.fp, sw, pg.rows);
        if (ferror(csv.fp)) {
            snprintf(err, sizeof err, "%s: write failed (disk full?)", sw->csv);
            goto fail;
        }
        if (outfile_commit(&csv, err, sizeof err)) goto fail;
    }
    const point_result *rows = pg.rows;
    if (sw->plot_arg &&
        write_plot((const sweep *const *)&sw, &rows, 1, NULL, NULL, err, sizeof err))
        goto fail;
    if (outfile_transaction_commit(err, sizeof err)) goto fail;
    if (to_stdout) {
        write_csv(stdout, sw, pg.rows);
        if (fflush(stdout) != 0 || ferror(stdout)) {
            fprintf(stderr, "rodsim sweep: cannot write the CSV to standard output\n");
            goto done;
        }
    }
    if (!sw->quiet)
        fprintf(stderr, "rodsim sweep: %d points: %d run, %d from %s; %d not ok%s%s\n",
                sw->point_count, pg.ran, pg.reused, sw->result_dir ? sw->result_dir : "-",
                failed, sw->csv && !to_stdout ? "; wrote " : "",
                sw->csv && !to_stdout ? sw->csv : "");
    status = RUN_EXIT_OK;
    goto done;
fail:
    fprintf(stderr, "rodsim sweep: %s\n", err);
done:
    outfile_abort(&csv);
    if (outfile_transaction_active()) outfile_transaction_abort();
    free(set);
    free(pg.rows);
    free(pg.digests);
    free(pg.done);
    return status;
}

/* Figures (rodsim figure) ------------------------------------------------- */

#define FIGURE_MAX_ARGS 64

/* One part of a figure: its sweep, built from the arguments `rodsim sweep`
 * would be given, and its points' state. */
typedef struct figure_part {
    const char *argv[FIGURE_MAX_ARGS];
    int argc;
    char csv[OUTFILE_PATH_MAX], png[OUTFILE_PATH_MAX], svg[OUTFILE_PATH_MAX];
    char jobs[16], plot_arg[2 * SWEEP_KEY_LEN];
    sweep sw;
    setting *set;
    progress pg;
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
             o->jobs < 1 ? 1 : o->jobs > SWEEP_MAX_JOBS ? SWEEP_MAX_JOBS : o->jobs);
    const char *tail[] = {"--measure", fig->measure, "--plot", part->plot_arg, "--png", part->png,
                          "--svg", part->svg, "--csv", part->csv, "--jobs", part->jobs};
    for (size_t i = 0; i < sizeof tail / sizeof tail[0]; i++) part->argv[n++] = tail[i];
    if (o->result_dir) {
        part->argv[n++] = "--result";
        part->argv[n++] = o->result_dir;
    }
    part->argc = n;
    if (parse_args(n, (char **)part->argv, &part->sw, err, errlen)) return -1;
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
    printf("# rodsim figure %s: %d points; each line runs one into %s (skipped when its\n"
           "# result file is there); then the # assemble: line draws the figure\n",
           fig->name, total, dir);
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
            const vary *v = &sw->varies[sw->plot_x];
            double x = strtod(v->values[value_index(sw, point, sw->plot_x)], NULL);
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
            const point_result *r = &parts[k].pg.rows[point];
            double reference = parts[k].reference[point], computed = r->value[sw->plot_y];
            char what[512];
            describe_point(sw, point, what, sizeof what);
            printf("%s%s%s: %s: %s computed %.6e, reference %.6e, relative error %.2e\n",
                   fig->name, fig->part[k].label[0] ? " " : "", fig->part[k].label, what,
                   fig->measure, computed, reference, fabs(computed / reference - 1.0));
        }
    }
}

int sweep_figure_command(const figure_spec *fig, const sweep_figure_options *o)
{
    char err[SWEEP_ERR_LEN] = "";
    int status = RUN_EXIT_FAILURE, total = 0;
    figure_part *parts = calloc((size_t)fig->parts, sizeof *parts);
    if (!parts) {
        fprintf(stderr, "rodsim figure %s: out of memory\n", fig->name);
        return RUN_EXIT_FAILURE;
    }
    for (int k = 0; k < fig->parts; k++) {
        figure_files(fig, k, o->out_dir, o->print_sweep, &parts[k]);
        if (figure_argv(fig, k, o, &parts[k], err, sizeof err)) goto fail; /* the table's fault */
        total += parts[k].sw.point_count;
    }
    if (o->print_sweep) {
        status = figure_print_sweep(fig, parts);
        goto done;
    }
    if (o->point >= total) {
        fprintf(stderr, "rodsim figure %s: --point %d: accepted 0 .. %d%s\n", fig->name,
                o->point, total - 1, o->quick ? " (with --quick)" : "");
        status = RUN_EXIT_BAD_INPUT;
        goto done;
    }
    if (!o->print_commands && o->point < 0 && outfile_mkdirs(o->out_dir, err, sizeof err))
        goto fail;
    for (int k = 0; k < fig->parts; k++) {
        figure_part *part = &parts[k];
        sweep *sw = &part->sw;
        int n = sw->point_count;
        part->set = calloc((size_t)(sw->set_count + sw->vary_count + 1), sizeof *part->set);
        part->pg = (progress){.sw = sw};
        part->pg.rows = calloc((size_t)n, sizeof *part->pg.rows);
        part->pg.digests = calloc((size_t)n, sizeof *part->pg.digests);
        part->pg.done = calloc((size_t)n, sizeof *part->pg.done);
        if (!part->set || !part->pg.rows || !part->pg.digests || !part->pg.done) {
            snprintf(err, sizeof err, "out of memory for %d points", n);
            goto fail;
        }
        if ((!o->print_commands && o->point < 0 && check_outputs(sw, err, sizeof err)) ||
            read_bases(sw, err, sizeof err) ||
            check_points(sw, part->set, part->pg.digests, err, sizeof err))
            goto fail;
    }
    if (o->print_commands) {
        status = figure_print_commands(fig, parts, o);
        goto done;
    }
    if (o->result_dir && outfile_mkdirs(o->result_dir, err, sizeof err)) goto fail;
    for (int k = 0, first = 0; k < fig->parts; first += parts[k++].sw.point_count) {
        progress *pg = &parts[k].pg;
        const sweep *sw = pg->sw;
        for (int point = 0; point < sw->point_count; point++) {
            int got = 0;
            if (o->result_dir &&
                (got = read_result(sw, pg->digests[point], &pg->rows[point], err, sizeof err)) < 0)
                goto fail;
            /* --point K: only K is left to run */
            pg->done[point] = got || (o->point >= 0 && o->point != first + point);
            pg->reused += got;
        }
        if (run_points(pg, err, sizeof err)) goto fail;
        if (pg->failed_writes) {
            snprintf(err, sizeof err, "%d result files could not be written", pg->failed_writes);
            goto fail;
        }
    }
    if (o->point >= 0) {
        status = RUN_EXIT_OK;
        goto done;
    }
    for (int k = 0; k < fig->parts; k++)
        for (int point = 0; point < parts[k].sw.point_count; point++) {
            const point_result *r = &parts[k].pg.rows[point];
            if (r->status == POINT_OK) continue;
            char what[512];
            describe_point(&parts[k].sw, point, what, sizeof what);
            snprintf(err, sizeof err, "point %s: %s: %s; nothing drawn", what,
                     status_names[r->status], r->message);
            goto fail;
        }
    /* the parts' CSVs and the figure with its data: all or none (outfile.h) */
    if (figure_references(fig, parts, err, sizeof err)) goto fail;
    const sweep *sws[FIGURE_SPEC_MAX_PARTS];
    const point_result *rows[FIGURE_SPEC_MAX_PARTS];
    const double *references[FIGURE_SPEC_MAX_PARTS];
    outfile_transaction_begin();
    for (int k = 0; k < fig->parts; k++) {
        outfile csv = {.fd = -1, .slot = -1};
        sws[k] = &parts[k].sw;
        rows[k] = parts[k].pg.rows;
        references[k] = parts[k].reference;
        if (outfile_open(&csv, parts[k].sw.csv, err, sizeof err)) goto fail;
        write_csv(csv.fp, &parts[k].sw, parts[k].pg.rows);
        if (ferror(csv.fp)) {
            outfile_abort(&csv);
            snprintf(err, sizeof err, "%s: write failed (disk full?)", parts[k].sw.csv);
            goto fail;
        }
        if (outfile_commit(&csv, err, sizeof err)) goto fail;
    }
    if (write_plot(sws, rows, fig->parts, fig, references, err, sizeof err) ||
        outfile_transaction_commit(err, sizeof err))
        goto fail;
    print_figure_summary(fig, parts);
    for (int k = 0; k < fig->parts; k++) printf("wrote %s\n", parts[k].sw.csv);
    printf("wrote %s\nwrote %s\nwrote %s\n", parts[0].sw.png, parts[0].sw.svg,
           parts[0].sw.plot_csv);
    if (fig->ratio_divisor) {
        char path[OUTFILE_PATH_MAX + 8];
        ratio_path(parts[0].sw.png, path, sizeof path);
        printf("wrote %s\n", path);
        ratio_path(parts[0].sw.svg, path, sizeof path);
        printf("wrote %s\n", path);
    }
    status = RUN_EXIT_OK;
    goto done;
fail:
    fprintf(stderr, "rodsim figure %s: %s\n", fig->name, err);
    status = RUN_EXIT_FAILURE;
done:
    if (outfile_transaction_active()) outfile_transaction_abort();
    for (int k = 0; k < fig->parts; k++) {
        free(parts[k].set);
        free(parts[k].pg.rows);
        free(parts[k].pg.digests);
        free(parts[k].pg.done);
        free(parts[k].reference);
        free_sweep(&parts[k].sw);
    }
    free(parts);
    return status;
}

int sweep_command(int argc, char **argv)
{
    char err[SWEEP_ERR_LEN] = "";
    sweep sw;
    memset(&sw, 0, sizeof sw);
    int status = RUN_EXIT_BAD_INPUT;
    if (parse_args(argc, argv, &sw, err, sizeof err)) {
        fprintf(stderr, "rodsim sweep: %s\n", err);
        fprintf(stderr, "  (rodsim sweep --help for the options)\n");
    } else if (sw.help) {
        sweep_usage(stdout);
        status = RUN_EXIT_OK;
    } else {
        status = sweep_run(&sw);
    }
    free_sweep(&sw);
    return status;
}
