/* live.c: `rodsim live` (see live.h), the command: its options, the
 * record's journal opened and closed, standard input read into the session
 * (live_session.h) or a scene of named rods handed to live_rods.h. */
#include "cli/live.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "api/scene_read.h"
#include "base/ini.h"
#include "base/outfile.h"
#include "cli/args.h"
#include "cli/live_overlap.h"
#include "cli/live_rods.h"
#include "cli/live_session.h"
#include "sim/rod_set.h"

void live_usage(FILE *f)
{
    fprintf(f,
        "usage: rodsim live SCENE [--set section.key=value]... [--record FILE] [--centreline]\n"
        "                   [--realtime] [--on-error skip|stop] [--rod NAME]\n"
        "stdin, one line per step, t (s) increasing from > 0: a held tip's pose t,x,y,z\n"
        "[,rx,ry,rz] (m, rad), or a free tip's loads t,fx,fy,fz,mx,my,mz (N, N m); a\n"
        "leading NAME: names the rod (one bare [rod]: rod).\n"
        "stdout, a header, then per line, flushed: t,fx,fy,fz,mx,my,mz,status, what the\n"
        "thread exerts on the driven tip (free tip: its root); status ok | failed (moved\n"
        "part way, held, or none: stuck) | bad_input (over %d bytes, a NUL, not 4 or 7\n"
        "numbers, NaN, t not increasing or > %d steps ahead; --on-error stop: exit 2)\n"
        "  --centreline   x0,y0,z0,... of each node follow on the line\n"
        "  --record FILE  the session, row by row (rodsim render FILE: its video)\n"
        "  --realtime     pace to the wall clock, count overruns; mlock, SCHED_FIFO, pin\n"
        "INSTRUMENT:t,x,y,z,rx,ry,rz,jaw: answer NAME,t,fx,fy,fz,held|ROD,s,status\n"
        "Several rods ([rod NAME]): a line NAME:t,... drives rod NAME's tip as above (no\n"
        "NAME: --rod's rod, else the first), every rod stepped to t, the others' ends as\n"
        "their last lines left them; answer NAME,t,fx,..,mz,status for rod NAME (an empty\n"
        "NAME: bad_input, no such rod), --centreline: then every rod's, NAME.x0,...;\n"
        "--record: rodsim run's --csv (column rod), a frame a line ok.\n"
        "End of input, SIGINT, SIGTERM end it, the record kept: exit 0 (no line at all\n"
        "too); 2 if lines came and none was ok, 1 on an I/O error.\n",
        LIVE_LINE_MAX, LIVE_MAX_STEPS_AHEAD);
}

typedef struct live_args {
    const char *scene;
    const char **sets;
    int set_count;
    const char *record;
    const char *rod;        /* --rod NAME: the rod of lines without NAME: */
    int centreline, realtime, stop_on_error, help;
} live_args;

/* Parses argv (argv[0] == "live") through the shared parser (args.h);
 * a->sets holds argc entries. 0, or -1 with a message. */
static int parse_args(int argc, char **argv, live_args *a, char *err, size_t errlen)
{
    cli_list sets = {0};
    const char *on_error = "skip";
    const cli_option options[] = {
        {.name = "--set", .value = CLI_SETTING, .target = &sets, .repeated = 1},
        {.name = "--record", .value = CLI_FILE, .target = &a->record},
        {.name = "--centreline", .value = CLI_FLAG, .target = &a->centreline},
        {.name = "--realtime", .value = CLI_FLAG, .target = &a->realtime},
        {.name = "--on-error", .value = CLI_WORD, .noun = "skip or stop", .target = &on_error},
        {.name = "--rod", .value = CLI_WORD, .noun = "a rod's name", .target = &a->rod},
        {0}};
    const cli_operand scene = {.name = "SCENE", .target = &a->scene};
    int parsed = cli_parse(argc, argv, options, &scene, err, errlen);
    for (int i = 0; i < sets.count; i++) a->sets[a->set_count++] = sets.items[i];
    cli_release(options);
    if (parsed == CLI_HELP) a->help = 1;
    if (parsed != CLI_PARSED) return parsed == CLI_HELP ? 0 : -1;
    if (!strcmp(on_error, "skip")) a->stop_on_error = 0;
    else if (!strcmp(on_error, "stop")) a->stop_on_error = 1;
    else {
        snprintf(err, errlen, "--on-error %s: accepted: skip or stop", on_error);
        return -1;
    }
    return 0;
}

/* Opens the record (its directory made if needed), writes the lines that
 * say how to replay it (live.h LIVE_RECORD_*), the CSV header and the
 * first row. 0, or -1 with err. */
static int record_open(live_session *ls, const live_args *a, char *err, size_t errlen)
{
    for (int i = 0; i < a->set_count; i++)
        if (strpbrk(a->sets[i], "\r\n")) {
            snprintf(err, errlen, "--set '%s': a line break cannot be recorded (--record)",
                     a->sets[i]);
            return -1;
        }
    char dir[OUTFILE_PATH_MAX];
    snprintf(dir, sizeof dir, "%s", a->record);
    char *slash = strrchr(dir, '/');
    if (slash && slash != dir) {
        *slash = '\0';
        if (outfile_mkdirs(dir, err, errlen)) return -1;
    }
    char scene[PATH_MAX];
    if (!realpath(a->scene, scene)) snprintf(scene, sizeof scene, "%s", a->scene);
    if (!(ls->record = fopen(a->record, "w"))) {
        snprintf(err, errlen, "--record %s: %s", a->record, strerror(errno));
        return -1;
    }
    ls->record_name = a->record;
    FILE *f = ls->record;
    fprintf(f, "%s%s: %s\n", LIVE_RECORD_MAGIC, a->scene,
            ls->pose_mode ? "the driven tip's path, with the velocities the live path gave"
                          : "the tip loads (a 7-column load table)");
    fprintf(f, "%s%s\n", LIVE_RECORD_SCENE, scene);
    for (int i = 0; i < a->set_count; i++) fprintf(f, "%s%s\n", LIVE_RECORD_SET, a->sets[i]);
    fprintf(f, "%s%.17g\n", LIVE_RECORD_DT, ls->dt);
    if (ls->pose_mode) {
        fprintf(f, ls->columns == 7 ? "t,x,y,z,rx,ry,rz,vx,vy,vz,vrx,vry,vrz\n"
                                    : "t,x,y,z,vx,vy,vz\n");
        const double zero[6] = {0};
        live_record_row(ls, ls->last_row, zero);
    } else {
        fprintf(f, "t,fx,fy,fz,mx,my,mz\n");
        live_record_row(ls, ls->last_row, NULL);
    }
    if (!ls->record) { /* live_record_check said why */
        err[0] = '\0';
        return -1;
    }
    return 0;
}

/* The replay command, the record's last comment. */
static void record_replay_line(live_session *ls, const live_args *a)
{
    FILE *f = ls->record;
    fprintf(f, "# replay: rodsim run %s", a->scene);
    for (int i = 0; i < a->set_count; i++) fprintf(f, " --set '%s'", a->sets[i]);
    if (ls->pose_mode) fprintf(f, " --set ends.tip_motion=%s", a->record);
    else fprintf(f, " --set 'tip.profile=table %s'", a->record);
    fprintf(f, " --set solver.duration=%.17g --set solver.dt=%.17g", ls->state->time, ls->dt);
    /* the same steps as live when every gap is one frame interval 1/fps */
    double fps = ls->stepped_rows > 0 ? 1.0 / ls->first_gap : 0.0;
    if (ls->stepped_rows > 0 && ls->max_gap - ls->min_gap <= 1e-9 * ls->max_gap &&
        fabs(fps - round(fps)) <= 1e-6 * fps && round(fps) >= 1.0 && round(fps) <= 1000.0)
        fprintf(f, " --set render.fps=%.0f\n", round(fps));
    else
        fprintf(f, "\n# (the lines were not 1/N s apart, N <= 1000: the replay's steps differ "
                   "from the live ones; the forces agree to the scheme's time accuracy)\n");
}

/* Reads standard input into the session until its end, a read error, a
 * stop signal or the session's own end. 1 when the input ended, 0 when
 * not (ended otherwise), -1 on a read error (said). */
static int serve(live_session *ls)
{
    char chunk[LIVE_LINE_MAX + 1];
    for (;;) {
        if (live_stop_signal) return 0;
        ssize_t got = read(STDIN_FILENO, chunk, sizeof chunk);
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) {
            fprintf(stderr, "rodsim live: reading standard input after input line %ld: %s\n",
                    ls->line_no, strerror(errno));
            return -1;
        }
        if (got == 0) return 1;
        if (live_session_feed(ls, chunk, (size_t)got)) return 0;
    }
}

/* The session once the scene is read: the record, the signals, the lines,
 * the summary. Returns the exit status. */
static int run_session(live_session *ls, const live_args *a, const rod_model *m)
{
    char err[1024] = "";
    if (a->record && record_open(ls, a, err, sizeof err)) {
        if (err[0]) fprintf(stderr, "rodsim live: %s\n", err);
        return RUN_EXIT_FAILURE;
    }
    if (a->realtime) live_realtime_setup(live_heap_bytes(m->nodes));
    /* the session ends on these like at the end of input (the record is
     * kept); a read or a wait returns at once */
    live_stop_signals_install();
    fprintf(stderr, "rodsim live: %s, NS = %d, dt = %g s; input %s; answer: what the thread "
                    "exerts on its %s\n",
            a->scene, m->nodes, ls->dt,
            !ls->pose_mode ? "t,fx,fy,fz,mx,my,mz"
            : ls->columns == 7 ? "t,x,y,z[,rx,ry,rz]" : "t,x,y,z",
            ls->driven ? "tip" : "root");
    live_session_start(ls);
    const int input = serve(ls);
    if (input < 0 && ls->status == RUN_EXIT_OK) ls->status = RUN_EXIT_FAILURE;
    int status = live_session_finish(ls, input == 1);
    if (ls->record) {
        record_replay_line(ls, a);
        int failed = ferror(ls->record) != 0;
        failed |= fclose(ls->record) != 0;
        ls->record = NULL;
        if (failed) {
            fprintf(stderr, "rodsim live: record %s: write error (disk full?)\n", a->record);
            if (status == RUN_EXIT_OK) status = RUN_EXIT_FAILURE;
        }
    }
    return status;
}

int live_command(int argc, char **argv)
{
    char err[1024] = "";
    live_args a;
    memset(&a, 0, sizeof a);
    a.sets = calloc((size_t)argc, sizeof *a.sets);
    if (!a.sets) {
        fprintf(stderr, "rodsim live: out of memory\n");
        return RUN_EXIT_FAILURE;
    }
    if (parse_args(argc, argv, &a, err, sizeof err)) {
        free(a.sets);
        return cli_usage_error("live", err);
    }
    if (a.help) {
        live_usage(stdout);
        free(a.sets);
        return RUN_EXIT_OK;
    }
    /* before anything is opened: a closed descriptor 0 would be the next
     * file opened, and its bytes read as the lines */
    if (fcntl(STDIN_FILENO, F_GETFD) < 0) {
        fprintf(stderr, "rodsim live: standard input is closed: no lines to read\n");
        free(a.sets);
        return RUN_EXIT_FAILURE;
    }
    int status = RUN_EXIT_BAD_INPUT;
    rod_model m = rod_model_default();
    run_output out;
    live_session *ls = NULL;
    const live_settings settings = {.centreline = a.centreline, .realtime = a.realtime,
                                    .stop_on_error = a.stop_on_error, .answers = stdout,
                                    .messages = stderr};
    ini_doc *doc = ini_load(a.scene, err, sizeof err);
    if (!doc) goto fail;
    for (int i = 0; i < a.set_count; i++)
        if (ini_set(doc, a.sets[i], err, sizeof err)) goto fail;
    int named = 0;
    if (scene_has_named_rods(doc, &named)) { /* several rods: their own session */
        const live_rods_options o = {.default_rod = a.rod, .record = a.record,
                                     .stop_on_error = a.stop_on_error,
                                     .centreline = a.centreline, .realtime = a.realtime};
        status = live_rods_run(doc, a.scene, &o);
        goto done;
    }
    if (a.rod && strcmp(a.rod, "rod") != 0) {
        snprintf(err, sizeof err, "--rod %s: %s has one bare [rod], named rod", a.rod, a.scene);
        goto fail;
    }
    if (run_read_scene(doc, &m, &out, err, sizeof err)) goto fail;
    if (!(ls = live_session_create(&m, &settings, err, sizeof err)) ||
        live_overlap_start(&m, a.scene, err, sizeof err) ||
        live_jaws_start(&m, a.scene, err, sizeof err))
        goto fail;
    status = run_session(ls, &a, &m);
    goto done;
fail:
    fprintf(stderr, "rodsim live: %s\n", err);
done:
    live_session_destroy(ls);
    rod_model_release(&m);
    ini_destroy(doc);
    free(a.sets);
    return status;
}
