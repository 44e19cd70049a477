/* sweep_spec.h: what a `rodsim sweep` is before anything runs: its options
 * (--vary lists, --measure, --plot, the outputs), its scene's bytes, and the
 * points of the product of the --vary lists, each a sorted list of settings
 * with a digest.
 *
 * A point is the scene read with the --set overrides and the point's values
 * applied (sweep_point_doc), so it equals the single run `rodsim run SCENE
 * --set ...` bit for bit. Its digest, the FNV-1a 64 of the version, the
 * scene file's bytes and the point's sorted settings, names its result file
 * DIR/DIGEST.csv (sweep.h): a point whose file exists is not run again. */
#ifndef RODSIM_SWEEP_SPEC_H
#define RODSIM_SWEEP_SPEC_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "base/ini.h"
#include "base/outfile.h"
#include "cli/args.h"

#define SWEEP_ERR_LEN 2048
#define SWEEP_MAX_POINTS 1000000
#define SWEEP_VALUE_LEN 1024 /* a setting's value, bytes */
#define SWEEP_KEY_LEN 128

/* FNV-1a 64 offset basis; sweep_fnv1a64(SWEEP_FNV_BASIS, ...) starts a digest. */
#define SWEEP_FNV_BASIS 0xcbf29ce484222325ULL

/* Continues the FNV-1a 64 digest h over n bytes. */
uint64_t sweep_fnv1a64(uint64_t h, const void *bytes, size_t n);

#define SWEEP_PUNCTURE_SLOTS 16 /* ROD_MAX_PUNCTURES */
#define SWEEP_MAX_RODS 8        /* ROD_SET_MAX */
#define SWEEP_ROD_MEASURES 11   /* tip_x .. tip_fz, root_f, tip_f (sweep_rod_slot) */
#define SWEEP_ROD_NAME_LEN 32   /* ROD_NAME_LEN */

/* The measures of a point, in the order of a result file's columns. */
enum {
    SWEEP_M_TIP_X, SWEEP_M_TIP_Y, SWEEP_M_TIP_Z,
    SWEEP_M_ROOT_FX, SWEEP_M_ROOT_FY, SWEEP_M_ROOT_FZ,
    SWEEP_M_TIP_FX, SWEEP_M_TIP_FY, SWEEP_M_TIP_FZ,
    SWEEP_M_MAX_CURVATURE, SWEEP_M_FIRST_FREQUENCY, SWEEP_M_CRITICAL_LOAD,
    SWEEP_M_CRITICAL_MOMENT,
    SWEEP_M_ROOT_F, SWEEP_M_TIP_F, /* magnitudes of the end forces */
    SWEEP_M_KNOT,                  /* text: the knot type's name (sweep_point_result.knot) */
    SWEEP_M_ROPE_IN_KNOT, SWEEP_M_MIN_STRAND_GAP,
    SWEEP_M_PUNCTURE_COUNT,
    SWEEP_M_PUNCTURE_F, /* puncture_f[0]: the first of SWEEP_PUNCTURE_SLOTS, one per puncture */
    SWEEP_M_STEPS = SWEEP_M_PUNCTURE_F + SWEEP_PUNCTURE_SLOTS, SWEEP_M_WALL, SWEEP_M_CPU,
    SWEEP_M_COUNT
};
/* In a --measure list: puncture_f, a column per puncture the run ends with
 * (as many as the most any point has), after the measures' own columns. */
#define SWEEP_M_PUNCTURE_COLUMNS SWEEP_M_COUNT
extern const char *const sweep_measure_names[SWEEP_M_COUNT];
extern const char *const sweep_measure_units[SWEEP_M_COUNT]; /* for plot axes */
/* The name a plot's axis gives a measure ("rope in knot"), without its unit. */
extern const char *const sweep_measure_labels[SWEEP_M_COUNT];

typedef enum {
    SWEEP_POINT_OK = 0, SWEEP_POINT_UNSTABLE, SWEEP_POINT_NO_CONVERGENCE, SWEEP_POINT_REFUSED,
    SWEEP_POINT_FAILED,
    SWEEP_POINT_STATUS_COUNT
} sweep_point_status;
extern const char *const sweep_status_names[SWEEP_POINT_STATUS_COUNT];

/* One point's outcome: every measure (NAN where none), so a result file
 * serves any --measure list. Sent whole through a pipe (< PIPE_BUF). */
typedef struct sweep_point_result {
    double value[SWEEP_M_COUNT];
    int status; /* sweep_point_status */
    char knot[96]; /* the knot type at the end (rod_knot.name), "" where none */
    char message[2048]; /* a failure's, or the warnings (run_warnings_join) */
    /* several rods: each named rod's tip (m) and end forces (N), NAN none;
     * [k][sweep_rod_slot(m)] holds measure m of rod k */
    double rod_value[SWEEP_MAX_RODS][SWEEP_ROD_MEASURES];
} sweep_point_result;

/* The slot of measure m in sweep_point_result.rod_value (a column per named
 * rod: tip_x .. tip_fz, root_f, tip_f), or -1 for a measure of the run. */
int sweep_rod_slot(int m);

/* One --vary: a key (or one component of a vector key) and its values. */
typedef struct sweep_vary {
    const char *arg;          /* the --vary argument, for messages */
    char key[SWEEP_KEY_LEN];  /* section.key */
    char name[SWEEP_KEY_LEN]; /* the CSV column: section.key or section.key[i] */
    int component;            /* -1: the whole value; else 0-based component */
    char **values;            /* owned */
    int count;
    char base[SWEEP_VALUE_LEN]; /* component: the scene's value of key (or the default) */
} sweep_vary;

/* A point's setting, as ini_set takes it (key=value). */
typedef struct sweep_setting {
    char key[SWEEP_KEY_LEN];
    char value[SWEEP_VALUE_LEN];
} sweep_setting;

typedef struct sweep {
    const char *scene_arg;
    char scene_path[OUTFILE_PATH_MAX]; /* absolute */
    char *text;     /* the scene file's bytes, read once; owned */
    size_t text_len;
    cli_list sets;  /* --set arguments */
    sweep_vary *varies; /* owned, vary_count of them */
    int vary_count;
    int measures[SWEEP_M_COUNT + 1]; /* the columns, in order (SWEEP_M_PUNCTURE_COLUMNS too) */
    int measure_count;
    int jobs, quiet, allow_long, print_commands, assemble;
    int critical; /* critical_load or critical_moment asked for (--measure, --plot) */
    const char *csv;        /* NULL: standard output */
    const char *result_dir;
    const char *snakefile;  /* --snakefile FILE */
    const char *sbatch;     /* --sbatch FILE */
    cli_list vary_args;     /* as given, for the assemble line */
    const char *measure_arg;
    int point_count;
    /* a scene of named rods ([rod NAME]): their names, in the scene's order;
     * 0 for one bare [rod] (sweep_read_bases) */
    int rod_count;
    char rod_names[SWEEP_MAX_RODS][SWEEP_ROD_NAME_LEN];
    const char *plot_arg, *png, *svg, *log_axes; /* --plot X:Y, --png, --svg, --log */
    const char *title, *xlabel, *ylabel;   /* --title, --xlabel, --ylabel: NULL, the default */
    const char *xformat, *yformat;         /* --xformat, --yformat: tick labels, or NULL */
    int plot_x;       /* the varied key on the x axis */
    int plot_y;       /* the measure on the y axis */
    char plot_csv[OUTFILE_PATH_MAX]; /* the plotted data, beside the PNG */
} sweep;

/* Parses `rodsim sweep` arguments (argv[0] "sweep") into *sw, which must be
 * zeroed: every value checked (keys against the scene key table, lists,
 * measures, the plot's axes, which outputs go together). CLI_PARSED,
 * CLI_HELP, or CLI_ERROR with a message (args.h). */
int sweep_parse_args(int argc, char **argv, sweep *sw, char *err, size_t errlen);
/* Frees what the sweep owns. */
void sweep_release(sweep *sw);

/* Reads the scene's bytes once (they are also the digest's input). 0, or
 * -1 with a message. */
int sweep_read_scene(sweep *sw, char *err, size_t errlen);
/* A component --vary starts from the key's value in the scene, or else its
 * default (scene_keys.c). 0, or -1 with a message. */
int sweep_read_bases(sweep *sw, char *err, size_t errlen);

/* The point's index in the list of --vary `which`: the first varies slowest. */
int sweep_value_index(const sweep *sw, int point, int which);
/* The point's settings: the --set ones (the last of a key wins), then the
 * point's values, a component put into its key's whole value; sorted by
 * key. Returns how many, or -1 with a message. `out` holds sets.count +
 * vary_count entries. */
int sweep_point_settings(const sweep *sw, int point, sweep_setting *out, char *err,
                         size_t errlen);
/* The point's scene: the file's text with its n settings applied; NULL with
 * a message. The caller destroys it. */
ini_doc *sweep_point_doc(const sweep *sw, const sweep_setting *s, int n, char *err,
                         size_t errlen);
/* The digest of a point's inputs: version, scene bytes, sorted settings. */
uint64_t sweep_point_digest(const sweep *sw, const sweep_setting *s, int n);
/* "key=value, key=value" of the point's varied values, for messages. */
void sweep_describe_point(const sweep *sw, int point, char *out, size_t n);

/* Every point's scene read before anything runs: a value a key does not
 * accept is bad input naming the --vary argument. Fills digests (one per
 * point); `set` is scratch of sets.count + vary_count + 1 entries. 0, or -1
 * with a message. */
int sweep_check_points(const sweep *sw, sweep_setting *set, uint64_t *digests, char *err,
                       size_t errlen);
/* Checks where the outputs go before any work. 0, or -1 with a message. */
int sweep_check_outputs(const sweep *sw, char *err, size_t errlen);

/* Shortest "%.*g" (15..17 digits) that reads back as x: exact, and short
 * when the value is; "" for NAN (an empty CSV field: no value). */
void sweep_format_double(double x, char *out, size_t n);
/* A CSV field per RFC 4180: quoted when it holds a comma, quote or line
 * break (quotes doubled), or always when `quote`. */
void sweep_csv_field(FILE *f, const char *text, int quote);

#endif
