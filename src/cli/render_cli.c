/* render_cli.c: `rodsim render RECORD` (see render_cli.h).
 *
 * Decisions:
 *   - the video is the scene simulated again, driven by the recorded rows
 *     (the path with the velocities live gave them, or the load table), not
 *     a copy of live's states: the frames then fall at k/fps exactly, and a
 *     record stays small (one row per line); the forces agree with live's to
 *     the Newton tolerance when the lines came every 1/fps s, and to the
 *     scheme's time accuracy otherwise (test_live's replay);
 *   - outputs are named after the record, so two sessions of one scene do
 *     not overwrite each other's video;
 *   - a record without its closing line (a killed session) or ending in a
 *     line without its newline (killed while writing it) is rendered to its
 *     last complete row, with a note on stderr, not refused: that is the
 *     session as far as it was recorded.
 */
#define _GNU_SOURCE /* realpath */
#include "cli/render_cli.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/ini.h"
#include "cli/args.h"
#include "cli/live.h"
#include "cli/scene_outputs.h"
#include "sim/rod.h"

/* The longest line of a record: a data row is at most 13 numbers of
 * %.17g; a header line holds a path or a --set value. */
#define RECORD_LINE_MAX 8192

void render_usage(FILE *f)
{
    fprintf(f,
            "usage: rodsim render RECORD [--set render.key=value]... [-o DIR] [--allow-long]\n"
            "                            [--quiet]\n"
            "Turns a session recorded by rodsim live --record into the video and poster of\n"
            "rodsim run (DIR/NAME.mp4, DIR/NAME.png, NAME the record's file name without its\n"
            "extension): its scene simulated again, driven by the recorded rows, to the last\n"
            "complete row (a killed session renders as far as it was recorded).\n"
            "rodsim run RECORD does the same.\n"
            "  --set render.key=value  override the scene's [render] keys (repeatable)\n"
            "  -o DIR                  directory for the video (default out/)\n"
            "  --allow-long, --quiet   as for rodsim run\n"
            "Exit status: 0 success; 2 bad usage, a record or scene that cannot be read;\n"
            "1 any other failure; 130 SIGINT, 143 SIGTERM. Nothing is written unless the whole\n"
            "video is.\n");
}

/* What a record holds, read by record_scan. */
typedef struct live_record {
    char scene[PATH_MAX];
    int scene_line;
    char **sets;        /* the session's --set values, in order (owned) */
    int set_count;
    double dt;          /* s */
    int pose;           /* 1: a held tip's path; 0: the free tip's loads */
    int numbers;        /* per row: 7 or 13 (pose), 7 (loads) */
    long rows;          /* complete rows, the t = 0 row included */
    double end;         /* s, the last complete row's t */
    long complete_bytes; /* bytes up to the end of the last complete line */
    int truncated_line; /* > 0: the line number of a last line without its newline */
    int closed;         /* 1: the session's closing "# replay:" line is there */
} live_record;

static void record_release(live_record *r)
{
    for (int i = 0; i < r->set_count; i++) free(r->sets[i]);
    free(r->sets);
    r->sets = NULL;
    r->set_count = 0;
}

static int starts(const char *line, const char *prefix)
{
    return strncmp(line, prefix, strlen(prefix)) == 0;
}

/* Reads the record's header and counts its complete rows. 0, or -1 with
 * "FILE:LINE: ..." in err. */
static int record_scan(const char *path, live_record *r, char *err, size_t errlen)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(err, errlen, "%s: %s", path, strerror(errno));
        return -1;
    }
    char line[RECORD_LINE_MAX];
    int line_no = 0, header = 0, status = -1;
    while (fgets(line, sizeof line, f)) {
        line_no++;
        size_t len = strlen(line);
        if (len == 0 || line[len - 1] != '\n') {
            if (feof(f)) { /* killed while writing it: the rows before it stand */
                r->truncated_line = line_no;
                break;
            }
            snprintf(err, errlen, "%s:%d: line longer than %d bytes: not a rodsim live record",
                     path, line_no, RECORD_LINE_MAX - 1);
            goto done;
        }
        line[--len] = '\0';
        if (line_no == 1 && !starts(line, LIVE_RECORD_MAGIC)) {
            snprintf(err, errlen, "%s:1: not a rodsim live record (it starts '%.40s'); "
                     "accepted: a file written by rodsim live --record", path, line);
            goto done;
        }
        if (starts(line, LIVE_RECORD_SCENE)) {
            const char *scene = line + strlen(LIVE_RECORD_SCENE);
            if (strlen(scene) >= sizeof r->scene) {
                snprintf(err, errlen, "%s:%d: the scene's path is longer than %d bytes", path,
                         line_no, (int)sizeof r->scene - 1);
                goto done;
            }
            memcpy(r->scene, scene, strlen(scene) + 1);
            r->scene_line = line_no;
        } else if (starts(line, LIVE_RECORD_SET)) {
            char **grown = realloc(r->sets, (size_t)(r->set_count + 1) * sizeof *grown);
            char *copy = strdup(line + strlen(LIVE_RECORD_SET));
            if (!grown || !copy) {
                free(copy);
                if (grown) r->sets = grown;
                snprintf(err, errlen, "out of memory");
                goto done;
            }
            r->sets = grown;
            r->sets[r->set_count++] = copy;
        } else if (starts(line, LIVE_RECORD_DT)) {
            char *stop;
            r->dt = strtod(line + strlen(LIVE_RECORD_DT), &stop);
            if (*stop != '\0' || !isfinite(r->dt) || !(r->dt > 0.0)) {
                snprintf(err, errlen, "%s:%d: '%.60s': accepted: %s followed by a time step > 0 s",
                         path, line_no, line, LIVE_RECORD_DT);
                goto done;
            }
        } else if (starts(line, "# replay:")) {
            r->closed = 1;
        } else if (line[0] == '#' || line[0] == '\0') {
            continue;
        } else if (!header) {
            header = 1;
            r->pose = strcmp(line, "t,fx,fy,fz,mx,my,mz") != 0;
            if (!strcmp(line, "t,x,y,z,vx,vy,vz") || !r->pose) r->numbers = 7;
            else if (!strcmp(line, "t,x,y,z,rx,ry,rz,vx,vy,vz,vrx,vry,vrz")) r->numbers = 13;
            else {
                snprintf(err, errlen, "%s:%d: column header '%.60s': accepted: t,x,y,z,vx,vy,vz, "
                         "t,x,y,z,rx,ry,rz,vx,vy,vz,vrx,vry,vrz or t,fx,fy,fz,mx,my,mz",
                         path, line_no, line);
                goto done;
            }
        } else {
            int fields = 1;
            for (const char *c = line; *c; c++) fields += *c == ',';
            char *stop;
            double t = strtod(line, &stop);
            if (fields != r->numbers || stop == line || *stop != ',' || !isfinite(t) ||
                (r->rows > 0 && !(t > r->end))) {
                snprintf(err, errlen, "%s:%d: a row of %d numbers, t increasing, expected "
                         "(%d fields)", path, line_no, r->numbers, fields);
                goto done;
            }
            r->end = t;
            r->rows++;
        }
        r->complete_bytes = ftell(f);
    }
    if (ferror(f)) {
        snprintf(err, errlen, "%s: read error", path);
        goto done;
    }
    if (!r->scene[0] || !(r->dt > 0.0) || !header) {
        snprintf(err, errlen, "%s: no %s line before the rows: not a complete rodsim live "
                 "record header", path, !r->scene[0] ? "'# scene:'" : !(r->dt > 0.0) ? "'# dt:'"
                                                                       : "column header");
        goto done;
    }
    if (r->rows < 2) {
        snprintf(err, errlen, "%s: the session stepped no line (only its t = 0 row): nothing "
                 "to render", path);
        goto done;
    }
    status = 0;
done:
    fclose(f);
    return status;
}

/* The first complete_bytes of the record in a nameless temporary file, for
 * the scene reader (which refuses a broken last row): *copy owns it, its
 * name goes to name. 0, or -1 with err. */
static int complete_copy(const char *path, long complete_bytes, FILE **copy, char *name,
                         size_t namelen, char *err, size_t errlen)
{
    FILE *in = fopen(path, "rb");
    FILE *out = tmpfile();
    char buf[1 << 15];
    long left = complete_bytes;
    while (in && out && left > 0) {
        size_t want = left < (long)sizeof buf ? (size_t)left : sizeof buf;
        size_t got = fread(buf, 1, want, in);
        if (got == 0 || fwrite(buf, 1, got, out) != got) break;
        left -= (long)got;
    }
    if (in) fclose(in);
    if (!out || left > 0 || fflush(out) != 0) {
        snprintf(err, errlen, "%s: cannot copy its complete rows to a temporary file", path);
        if (out) fclose(out);
        return -1;
    }
    *copy = out;
    snprintf(name, namelen, "/proc/self/fd/%d", fileno(out));
    return 0;
}

/* NAME of DIR/NAME.EXT. */
static void record_stem(const char *path, char *out, size_t outlen)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    const char *dot = strrchr(base, '.');
    int len = dot && dot != base ? (int)(dot - base) : (int)strlen(base);
    snprintf(out, outlen, "%.*s", len, len > 0 ? base : "record");
}

/* The record's scene, its --set overrides and the session's inputs, then
 * the outputs as `rodsim run` makes them. Returns an exit status. */
static int render_record(const char *record, const cli_list *sets, scene_outputs_options *o)
{
    char err[1024] = "";
    int status = RUN_EXIT_BAD_INPUT;
    live_record r;
    memset(&r, 0, sizeof r);
    rod_model m = rod_model_default();
    run_output out;
    ini_doc *doc = NULL;
    FILE *copy = NULL;
    char inputs[PATH_MAX + 32], assignment[PATH_MAX + 64];
    if (record_scan(record, &r, err, sizeof err)) goto fail;
    if (r.truncated_line || !r.closed) {
        /* what the session recorded before it was cut short */
        if (r.truncated_line)
            fprintf(stderr, "%s: %s:%d: an incomplete last line (the session was "
                    "cut short while recording it): rendered to its last complete row, "
                    "t = %.9g s\n", o->command, record, r.truncated_line, r.end);
        else
            fprintf(stderr, "%s: %s: no closing '# replay:' line (the session was "
                    "killed): rendered to its last row, t = %.9g s\n", o->command, record, r.end);
    }
    if (r.truncated_line) {
        if (complete_copy(record, r.complete_bytes, &copy, inputs, sizeof inputs, err,
                          sizeof err)) {
            status = RUN_EXIT_FAILURE;
            goto fail;
        }
    } else if (!realpath(record, inputs)) {
        snprintf(err, sizeof err, "%s: %s", record, strerror(errno));
        goto fail;
    }
    if (!(doc = ini_load(r.scene, err, sizeof err))) {
        char why[sizeof err];
        snprintf(why, sizeof why, "%s", err);
        snprintf(err, sizeof err, "%.200s:%d: the session's scene: %.700s", record,
                 r.scene_line, why);
        goto fail;
    }
    for (int i = 0; i < r.set_count; i++)
        if (ini_set(doc, r.sets[i], err, sizeof err)) goto fail;
    for (int i = 0; i < sets->count; i++)
        if (ini_set(doc, sets->items[i], err, sizeof err)) goto fail;
    /* the session's length and step, and its inputs in place of the scene's */
    snprintf(assignment, sizeof assignment, "solver.duration=%.17g", r.end);
    if (ini_set(doc, assignment, err, sizeof err)) goto fail;
    snprintf(assignment, sizeof assignment, "solver.dt=%.17g", r.dt);
    if (ini_set(doc, assignment, err, sizeof err)) goto fail;
    if (r.pose) snprintf(assignment, sizeof assignment, "ends.tip_motion=%s", inputs);
    else snprintf(assignment, sizeof assignment, "tip.profile=table %s", inputs);
    if (ini_set(doc, assignment, err, sizeof err)) goto fail;
    if (run_read_scene(doc, &m, &out, err, sizeof err)) goto fail;
    if ((m.tip_end != ROD_END_FREE) != r.pose) {
        snprintf(err, sizeof err, "%s:%d: the scene now has a %s tip, the record drives %s: "
                 "the scene changed since the session", record, r.scene_line,
                 m.tip_end == ROD_END_FREE ? "free" : "held",
                 r.pose ? "a held tip's pose" : "a free tip's loads");
        goto fail;
    }
    char name[128];
    record_stem(record, name, sizeof name);
    o->label = record;
    if (scene_outputs_check(o, err, sizeof err)) goto fail;
    status = scene_outputs_write(o, name, &m, &out);
    goto done;
fail:
    fprintf(stderr, "%s: %s\n", o->command, err);
done:
    rod_model_release(&m);
    ini_destroy(doc);
    if (copy) fclose(copy);
    record_release(&r);
    return status;
}

/* Only the [render] keys of the scene may change: the session's physics
 * is the record's. 0, or -1 with a message. */
static int check_render_sets(const cli_list *sets, char *err, size_t errlen)
{
    for (int i = 0; i < sets->count; i++)
        if (strncmp(sets->items[i], "render.", 7) != 0) {
            snprintf(err, errlen, "--set %s: only render.KEY=VALUE is accepted (the "
                     "session's scene and physics are the record's)", sets->items[i]);
            return -1;
        }
    return 0;
}

int render_command(int argc, char **argv)
{
    char err[1024] = "";
    const char *record = NULL;
    cli_list sets = {0};
    /* argv[0] is "run" when `rodsim run` was given a record: its messages say run */
    char command[32];
    snprintf(command, sizeof command, "rodsim %s", argv[0]);
    scene_outputs_options o = {.out_dir = "out", .command = command};
    const cli_option options[] = {
        {.name = "--set", .value = CLI_SETTING, .target = &sets, .repeated = 1},
        {.name = "-o", .value = CLI_DIR, .target = &o.out_dir},
        {.name = "--allow-long", .value = CLI_FLAG, .target = &o.allow_long},
        {.name = "--quiet", .alias = "-q", .value = CLI_FLAG, .target = &o.quiet},
        {0}};
    const cli_operand operand = {.name = "RECORD",
                                 .hint = "a file written by rodsim live --record",
                                 .target = &record};
    int parsed = cli_parse(argc, argv, options, &operand, err, sizeof err);
    int status = RUN_EXIT_OK;
    if (parsed == CLI_HELP) render_usage(stdout);
    else if (parsed != CLI_PARSED || check_render_sets(&sets, err, sizeof err))
        status = cli_usage_error(argv[0], err);
    else
        status = render_record(record, &sets, &o);
    cli_release(options);
    return status;
}
