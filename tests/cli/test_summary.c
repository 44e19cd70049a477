/* test_summary.c: what `rodsim run` tells a machine and a person, through
 * the real binary.
 *
 * --summary FILE: one JSON object whatever the outcome, read back by
 * tests/json.h: every field of its type; status and exit_code agree with
 * the process's exit status (ok 0, refused and unstable 2, failed 1); the
 * files it lists exist; the tip equals the last row of --csv; on a static
 * hanging rod the force on the clamp equals the weight plus the tip force
 * (rho A L g, by hand). Runs: a hanging rod (static scheme), a suture with a
 * puncture, an overhand knot (trefoil: Alexander 1 - t + t^2, determinant 3,
 * Rolfsen's table), a tiny video, a bad scene, an unstable run, a run refused
 * up front, a usage error.
 *
 * The prose: the progress line (with --progress on stderr, none without a
 * terminal; on a pseudo-terminal for a long run), CPU per simulated second,
 * the video's fps and playback speed, the CSV columns in --help, the knot
 * line only where the scene can knot, "did you mean" for a command, an
 * option, a scene value. */
#define _GNU_SOURCE
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli/summary.h"
#include "json.h"
#include "test.h"

static char tmp_dir[64];

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

/* The whole file into a new buffer ("" when missing). */
static char *read_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    char *text = NULL;
    size_t n = 0;
    if (f) {
        fseek(f, 0, SEEK_END);
        long size = ftell(f);
        rewind(f);
        text = malloc((size_t)(size > 0 ? size : 0) + 1);
        if (text) n = fread(text, 1, (size_t)(size > 0 ? size : 0), f);
        fclose(f);
    }
    if (!text) text = calloc(1, 1);
    else text[n] = '\0';
    return text;
}

/* What a run printed. */
typedef struct run_result {
    int status;  /* exit status, -1: did not exit */
    char *out;   /* stdout, owned */
    char *err;   /* stderr, owned */
} run_result;

static void result_free(run_result *r)
{
    free(r->out);
    free(r->err);
}

/* > 0: the files the next run_rodsim's child writes are limited to this
 * many bytes (a full disk: writes past it fail with EFBIG). */
static long file_size_limit;

/* Runs rodsim with args (NULL-terminated); stdout and stderr apart.
 * `env` ("NAME=VALUE") is set in the child when not NULL; tty_fd >= 0
 * becomes the child's stderr (a terminal) instead of a file. */
static run_result run_rodsim(const char *const *args, const char *env, int tty_fd)
{
    run_result r = {-1, NULL, NULL};
    char out_path[128], err_path[128];
    snprintf(out_path, sizeof out_path, "%s/stdout.txt", tmp_dir);
    snprintf(err_path, sizeof err_path, "%s/stderr.txt", tmp_dir);
    const char *argv[64];
    int n = 0;
    argv[n++] = RODSIM_BIN;
    for (int i = 0; args[i] && n < 63; i++) argv[n++] = args[i];
    argv[n] = NULL;
    fflush(stdout);
    pid_t pid = fork();
    if (pid == 0) {
        int out = open(out_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        int err = tty_fd >= 0 ? tty_fd : open(err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (out < 0 || err < 0) _exit(127);
        dup2(out, 1);
        dup2(err, 2);
        if (env) putenv((char *)env);
        if (file_size_limit > 0) {
            struct rlimit limit = {(rlim_t)file_size_limit, (rlim_t)file_size_limit};
            signal(SIGXFSZ, SIG_IGN);
            setrlimit(RLIMIT_FSIZE, &limit);
        }
        execv(RODSIM_BIN, (char *const *)argv);
        _exit(127);
    }
    int status = 0;
    if (pid > 0 && waitpid(pid, &status, 0) == pid && WIFEXITED(status))
        r.status = WEXITSTATUS(status);
    r.out = read_file(out_path);
    r.err = tty_fd >= 0 ? calloc(1, 1) : read_file(err_path);
    return r;
}

/* ---- the object's fields and their types ------------------------------ */

static int is_vector(const json_value *v) { return json_is_numbers(v, 3); }

/* Every string of an array (NULL: absent is fine when optional). */
static int is_string_list(const json_value *v)
{
    if (!json_is(v, JSON_ARRAY)) return 0;
    for (int i = 0; i < v->count; i++)
        if (v->items[i]->type != JSON_STRING) return 0;
    return 1;
}

static int ends_ok(const json_value *ends)
{
    if (!json_is(ends, JSON_OBJECT)) return 0;
    for (int i = 0; i < ends->count; i++) {
        const json_value *e = ends->items[i];
        if ((strcmp(ends->keys[i], "root") && strcmp(ends->keys[i], "tip")) ||
            !is_vector(json_get(e, "force")) || !is_vector(json_get(e, "moment")))
            return 0;
    }
    return 1;
}

static int knot_ok(const json_value *k)
{
    if (!k) return 1; /* only where the scene can knot */
    const json_value *changes = json_get(k, "changes"), *sig = json_get(k, "signature"),
                     *rope = json_get(k, "rope_in_knot_d");
    if (!json_is(json_get(k, "type"), JSON_STRING) ||
        !json_is_numbers(json_get(k, "alexander"), -1) ||
        !json_is(json_get(k, "determinant"), JSON_NUMBER) || (sig && sig->type != JSON_NUMBER) ||
        (rope && rope->type != JSON_NUMBER) || !json_is(changes, JSON_ARRAY))
        return 0;
    for (int i = 0; i < changes->count; i++) {
        const json_value *c = changes->items[i];
        /* exactly [t, type]: the fixed pairs */
        if (!json_is(c, JSON_ARRAY) || c->count != 2 || c->items[0]->type != JSON_NUMBER ||
            c->items[1]->type != JSON_STRING)
            return 0;
    }
    /* changes_how, when there: a string per change, in its order */
    const json_value *how = json_get(k, "changes_how");
    if (how && (!json_is(how, JSON_ARRAY) || how->count != changes->count)) return 0;
    for (int i = 0; how && i < how->count; i++)
        if (how->items[i]->type != JSON_STRING) return 0;
    return 1;
}

static int rods_ok(const json_value *rods)
{
    if (!rods) return 1;
    if (!json_is(rods, JSON_ARRAY) || rods->count != 1) return 0;
    const json_value *rod = rods->items[0], *name = json_get(rod, "name"),
                     *gap = json_get(rod, "min_strand_gap_d");
    return json_is(name, JSON_STRING) && strcmp(name->string, "rod") == 0 &&
           json_is(json_get(rod, "nodes"), JSON_NUMBER) && is_vector(json_get(rod, "tip")) &&
           ends_ok(json_get(rod, "ends")) && knot_ok(json_get(rod, "knot")) &&
           (!gap || gap->type == JSON_NUMBER);
}

static int punctures_ok(const json_value *p)
{
    if (!p) return 1;
    if (!json_is(p, JSON_ARRAY)) return 0;
    for (int i = 0; i < p->count; i++)
        if (!json_is(json_get(p->items[i], "t"), JSON_NUMBER) ||
            !is_vector(json_get(p->items[i], "point")) ||
            !is_vector(json_get(p->items[i], "force")))
            return 0;
    return 1;
}

/* An optional member is absent or of its type. */
static int optional(const json_value *doc, const char *key, json_type type)
{
    const json_value *v = json_get(doc, key);
    return !v || v->type == type;
}

/* Checks the object's fields against their types and the exit status;
 * returns the parsed object (NULL: not JSON), for the caller to free. */
static json_value *check_summary(const char *what, const char *text, int exit_status)
{
    char err[256];
    json_value *doc = json_parse(text, err, sizeof err);
    check(doc && doc->type == JSON_OBJECT, "%s: the summary is one JSON object%s%s", what,
          doc ? "" : ": ", doc ? "" : err);
    if (!doc) return NULL;
    const json_value *status = json_get(doc, "status"), *code = json_get(doc, "exit_code");
    static const char *const words[] = {"ok", "refused", "unstable", "failed"};
    static const int codes[] = {0, 2, 2, 1};
    int agree = 0;
    for (int i = 0; i < 4 && json_is(status, JSON_STRING); i++)
        if (strcmp(status->string, words[i]) == 0) agree = codes[i] == exit_status;
    check(agree && json_is(code, JSON_NUMBER) && code->number == exit_status,
          "%s: status '%s' and exit_code %g agree with the exit status %d", what,
          json_is(status, JSON_STRING) ? status->string : "?", json_is(code, JSON_NUMBER)
          ? code->number : -1.0, exit_status);
    static const char *const numbers[] = {"steps", "frames", "fps", "speed", "t_end",
                                          "cpu_s_per_sim_s", "cpu_us_per_step", NULL};
    int types = optional(doc, "message", JSON_STRING) &&
                is_string_list(json_get(doc, "warnings")) &&
                optional(doc, "scene", JSON_STRING) && optional(doc, "scheme", JSON_STRING) &&
                json_is(json_get(doc, "cpu_s"), JSON_NUMBER) &&
                json_is(json_get(doc, "wall_s"), JSON_NUMBER) &&
                is_string_list(json_get(doc, "files")) && rods_ok(json_get(doc, "rods")) &&
                punctures_ok(json_get(doc, "punctures"));
    for (int i = 0; numbers[i]; i++) types = types && optional(doc, numbers[i], JSON_NUMBER);
    const json_value *gl = json_get(doc, "gl");
    types = types && (!gl || (gl->type == JSON_STRING && (strcmp(gl->string, "egl") == 0 ||
                                                          strcmp(gl->string, "osmesa") == 0)));
    check(types, "%s: every field of its type (strings, numbers, [x,y,z], lists)", what);
    const json_value *message = json_get(doc, "message");
    if (exit_status != 0)
        check(json_is(message, JSON_STRING), "%s: a failed run says why in message: \"%.200s\"",
              what, json_is(message, JSON_STRING) ? message->string : "");
    const json_value *files = json_get(doc, "files");
    int exist = 1;
    for (int i = 0; files && i < files->count; i++) {
        struct stat st;
        exist = exist && stat(files->items[i]->string, &st) == 0 && S_ISREG(st.st_mode) &&
                st.st_size > 0;
    }
    check(exist, "%s: the %d files listed exist and are not empty", what, files ? files->count : 0);
    return doc;
}

/* The summary written to a file, read back. */
static json_value *summary_of(const char *what, const char *path, int exit_status)
{
    char *text = read_file(path);
    json_value *doc = check_summary(what, text, exit_status);
    free(text);
    unlink(path);
    return doc;
}

/* x,y,z of the last row of a --csv (its last node at the last time). */
static int last_csv_row(const char *path, double xyz[3])
{
    char *text = read_file(path);
    size_t n = strlen(text);
    while (n > 0 && text[n - 1] == '\n') text[--n] = '\0';
    char *line = strrchr(text, '\n');
    double t, s;
    int node;
    int ok = line && sscanf(line + 1, "%lf,%d,%lf,%lf,%lf,%lf", &t, &node, &s, &xyz[0], &xyz[1],
                            &xyz[2]) == 6;
    free(text);
    return ok;
}

static const json_value *first_rod(const json_value *doc)
{
    const json_value *rods = json_get(doc, "rods");
    return json_is(rods, JSON_ARRAY) && rods->count > 0 ? rods->items[0] : NULL;
}

/* The tip in the summary equals the last row of the CSV (%.10g there). */
static void check_tip_is_csv(const char *what, const json_value *doc, const char *csv)
{
    double row[3];
    const json_value *tip = json_get(first_rod(doc), "tip");
    int ok = last_csv_row(csv, row) && is_vector(tip);
    double worst = 0.0;
    for (int k = 0; ok && k < 3; k++)
        worst = fmax(worst, fabs(tip->items[k]->number - row[k]) / fmax(1e-12, fabs(row[k])));
    check(ok && worst < 1e-9, "%s: tip = the last row of --csv (largest relative difference "
          "%.2e, the CSV keeps 10 digits)", what, worst);
}

/* ---- the writer and the reader themselves ----------------------------- */

static void test_writer(void)
{
    static run_summary s;
    summary_init(&s);
    s.exit_code = 1;
    snprintf(s.message, sizeof s.message, "a \"quoted\" back\\slash,\nnew line and \x01");
    s.has_rod = 1;
    s.nodes = 3;
    s.tip[0] = NAN;
    s.tip[1] = 0.1 + 0.2; /* 0.30000000000000004: needs 17 digits */
    s.tip[2] = -0.0;
    FILE *f = tmpfile();
    if (!f) return;
    summary_print(f, &s);
    rewind(f);
    char text[4096] = "", err[256];
    size_t got = fread(text, 1, sizeof text - 1, f);
    text[got] = '\0';
    fclose(f);
    json_value *doc = json_parse(text, err, sizeof err);
    const json_value *message = json_get(doc, "message"), *tip = json_get(first_rod(doc), "tip");
    check(doc && json_is(message, JSON_STRING) && strcmp(message->string, s.message) == 0,
          "writer: a message with quotes, a backslash, a newline and a control character reads "
          "back the same");
    check(tip && tip->count == 3 && tip->items[0]->type == JSON_NULL &&
              tip->items[1]->number == 0.1 + 0.2 && tip->items[2]->number == 0.0,
          "writer: NaN as null, 0.1 + 0.2 read back as the same double, -0 as 0: %s", text);
    check(json_is(json_get(doc, "status"), JSON_STRING) &&
              strcmp(json_get(doc, "status")->string, "failed") == 0 && !json_get(doc, "scene"),
          "writer: exit code 1 is 'failed'; a scene never known is left out");
    json_free(doc);
    static const char *const bad[] = {"{\"a\":1,}", "[01]", "{'a':1}", "[1] x", "[1,]",
                                      "\"a\tb\"", "{\"a\" 1}", "tru", NULL};
    for (int i = 0; bad[i]; i++) {
        json_value *v = json_parse(bad[i], err, sizeof err);
        check(!v, "reader: refuses %s (%s)", bad[i], err);
        json_free(v);
    }
}

/* ---- runs ---------------------------------------------------------------- */

/* A rod hanging from a clamp, solved by the static scheme: the force on the
 * clamp is the weight rho (pi d^2 / 4) L g plus the (global) tip force. */
static void test_static_hanging(void)
{
    char scene[128], csv[128], json[128];
    snprintf(scene, sizeof scene, "%s/hang.ini", tmp_dir);
    snprintf(csv, sizeof csv, "%s/hang.csv", tmp_dir);
    snprintf(json, sizeof json, "%s/hang.json", tmp_dir);
    write_file(scene, "[rod]\nlength = 0.5\ndiameter = 0.001\ndensity = 850\n"
                      "youngs_modulus = 87.5e6\nshear_modulus = 31.25e6\nnodes = 21\n"
                      "direction = 0 0 -1\n[solver]\nscheme = static\nduration = 1\n"
                      "[tip]\nframe = global\nforce = 1e-4 2e-4 -3e-3\n"
                      "[loads]\ngravity = 0 0 -9.81\n[render]\nfps = 2\n");
    const char *args[] = {"run", scene, "--no-video", "--csv", csv, "--summary", json, NULL};
    run_result r = run_rodsim(args, NULL, -1);
    json_value *doc = summary_of("static hanging rod", json, r.status);
    const json_value *rod = first_rod(doc), *ends = json_get(rod, "ends");
    const json_value *root = json_get(json_get(ends, "root"), "force");
    double weight = 850.0 * M_PI * 0.001 * 0.001 / 4.0 * 0.5 * 9.81; /* N */
    const double expected[3] = {1e-4, 2e-4, -3e-3 - weight};
    double diff = 0.0, norm = 0.0;
    for (int k = 0; is_vector(root) && k < 3; k++) {
        diff += pow(root->items[k]->number - expected[k], 2);
        norm += expected[k] * expected[k];
    }
    double rel = is_vector(root) ? sqrt(diff / norm) : INFINITY;
    check(r.status == 0 && !json_get(ends, "tip") && rel <= 1e-6,
          "static hanging rod: force on the clamp (%.9g, %.9g, %.9g) N, reference weight + tip "
          "force (%.9g, %.9g, %.9g) N, relative error %.2e (tolerance 1e-6); the free tip has no "
          "entry", is_vector(root) ? root->items[0]->number : NAN,
          is_vector(root) ? root->items[1]->number : NAN,
          is_vector(root) ? root->items[2]->number : NAN, expected[0], expected[1], expected[2],
          rel);
    check_tip_is_csv("static hanging rod", doc, csv);
    const json_value *files = json_get(doc, "files"), *scheme = json_get(doc, "scheme");
    check(files && files->count == 1 && strcmp(files->items[0]->string, csv) == 0 &&
              json_is(scheme, JSON_STRING) && strcmp(scheme->string, "static") == 0 &&
              !json_get(doc, "gl") && !json_get(rod, "knot"),
          "static hanging rod: files = [the CSV], scheme static, no gl (--no-video), no knot "
          "(the static scheme has no self-contact)");
    json_free(doc);
    result_free(&r);
}

/* The suture: its needle makes a puncture before 4 s. */
static void test_suture_puncture(void)
{
    char csv[128], json[128];
    snprintf(csv, sizeof csv, "%s/suture.csv", tmp_dir);
    snprintf(json, sizeof json, "%s/suture.json", tmp_dir);
    const char *args[] = {"run", RODSIM_SOURCE_DIR "/scenes/suture.ini", "--no-video", "--quiet",
                          "--set", "solver.duration=4", "--csv", csv, "--summary", json, NULL};
    run_result r = run_rodsim(args, NULL, -1);
    json_value *doc = summary_of("suture, 4 s", json, r.status);
    const json_value *p = json_get(doc, "punctures"), *t_end = json_get(doc, "t_end");
    const json_value *t = p && p->count > 0 ? json_get(p->items[0], "t") : NULL;
    check(r.status == 0 && p && p->count >= 1 && t && t->number > 0.0 && t->number <= 4.0 &&
              t_end && t_end->number == 4.0,
          "suture, 4 s: %d puncture(s), the first made at t = %g s (in (0, 4] s), t_end %g s",
          p ? p->count : 0, t ? t->number : NAN, t_end ? t_end->number : NAN);
    check_tip_is_csv("suture, 4 s", doc, csv);
    const json_value *frames = json_get(doc, "frames"), *fps = json_get(doc, "fps");
    check(frames && fps && frames->number == 4.0 * fps->number + 1,
          "suture, 4 s: frames = 4 s x fps + 1 (t = 0 included): %g at %g fps",
          frames ? frames->number : NAN, fps ? fps->number : NAN);
    unlink(csv);
    json_free(doc);
    result_free(&r);
}

/* The overhand knot, 0.5 s: a trefoil all along. */
static void test_knot(void)
{
    char json[128];
    snprintf(json, sizeof json, "%s/overhand.json", tmp_dir);
    const char *args[] = {"run", RODSIM_SOURCE_DIR "/scenes/overhand.ini", "--no-video", "--quiet",
                          "--set", "solver.duration=0.5", "--summary", json, NULL};
    run_result r = run_rodsim(args, NULL, -1);
    json_value *doc = summary_of("overhand, 0.5 s", json, r.status);
    const json_value *rod = first_rod(doc), *knot = json_get(rod, "knot");
    const json_value *type = json_get(knot, "type"), *alex = json_get(knot, "alexander"),
                     *det = json_get(knot, "determinant"), *changes = json_get(knot, "changes"),
                     *gap = json_get(rod, "min_strand_gap_d");
    int alex_ok = json_is_numbers(alex, 3) && alex->items[0]->number == 1 &&
                  alex->items[1]->number == -1 && alex->items[2]->number == 1;
    check(r.status == 0 && json_is(type, JSON_STRING) && strncmp(type->string, "trefoil", 7) == 0 &&
              alex_ok && det && det->number == 3 && changes && changes->count == 0,
          "overhand, 0.5 s: knot %s, Alexander 1 - t + t^2, determinant %g (reference 3), %d "
          "changes", json_is(type, JSON_STRING) ? type->string : "?", det ? det->number : NAN,
          changes ? changes->count : -1);
    check(json_is(json_get(knot, "rope_in_knot_d"), JSON_NUMBER) && gap && gap->number > 0.0 &&
              gap->number < 2.0,
          "overhand, 0.5 s: the rope in the knot is measured; strands closest at %.3g diameters "
          "(in contact: about 1)", gap ? gap->number : NAN);
    json_free(doc);
    result_free(&r);
}

/* A tiny video: the backend that drew, the video and poster listed. */
static void test_video(void)
{
    char json[128];
    snprintf(json, sizeof json, "%s/video.json", tmp_dir);
    const char *args[] = {"run", RODSIM_SOURCE_DIR "/scenes/suture_gravity.ini", "-o", tmp_dir,
                          "--quiet", "--set", "solver.duration=0.2", "--set", "render.width=64",
                          "--set", "render.height=36", "--set", "render.fps=10",
                          "--summary", json, NULL};
    run_result r = run_rodsim(args, NULL, -1);
    json_value *doc = summary_of("video", json, r.status);
    const json_value *files = json_get(doc, "files"), *gl = json_get(doc, "gl");
    int mp4 = 0, png = 0;
    for (int i = 0; files && i < files->count; i++) {
        const char *f = files->items[i]->string;
        size_t n = strlen(f);
        mp4 += n > 4 && strcmp(f + n - 4, ".mp4") == 0;
        png += n > 4 && strcmp(f + n - 4, ".png") == 0;
        unlink(f);
    }
    check(r.status == 0 && mp4 == 1 && png == 1 && json_is(gl, JSON_STRING),
          "video: files list the video and the poster; drawn by '%s'",
          json_is(gl, JSON_STRING) ? gl->string : "?");
    json_free(doc);
    result_free(&r);
}

/* The summary of runs that fail, each for its reason. */
static void test_failures(void)
{
    char json[128];
    snprintf(json, sizeof json, "%s/fail.json", tmp_dir);
    struct {
        const char *what, *env, *status, *says;
        const char *args[16];
    } cases[] = {
        {"bad scene value", NULL, "refused", "did you mean implicit?",
         {"run", RODSIM_SOURCE_DIR "/scenes/suture_gravity.ini", "--no-video", "--set",
          "solver.scheme=implict", "--summary", json, NULL}},
        {"unstable run", NULL, "unstable", "became unstable",
         {"run", RODSIM_SOURCE_DIR "/scenes/suture_gravity.ini", "--no-video", "--set",
          "solver.scheme=thesis", "--set", "solver.dt=0.001", "--set", "solver.duration=1",
          "--summary", json, NULL}},
        {"refused up front", "RODSIM_TIME_LIMIT=0.001", "refused", "nothing was run",
         {"run", RODSIM_SOURCE_DIR "/scenes/suture_gravity.ini", "--no-video", "--summary", json,
          NULL}},
        {"usage error", NULL, "refused", "--set render.fps=60",
         {"run", RODSIM_SOURCE_DIR "/scenes/suture_gravity.ini", "--fps", "60", "--summary", json,
          NULL}},
        {"missing scene file", NULL, "refused", "no_such_scene.ini",
         {"run", "no_such_scene.ini", "--no-video", "--summary", json, NULL}},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        run_result r = run_rodsim(cases[i].args, cases[i].env, -1);
        json_value *doc = summary_of(cases[i].what, json, r.status);
        const json_value *status = json_get(doc, "status"), *message = json_get(doc, "message"),
                         *files = json_get(doc, "files");
        check(r.status == 2 && json_is(status, JSON_STRING) &&
                  strcmp(status->string, cases[i].status) == 0 && json_is(message, JSON_STRING) &&
                  strstr(message->string, cases[i].says) && files && files->count == 0,
              "%s: exit %d, status '%s' (expected %s), message says '%s', no files", cases[i].what,
              r.status, json_is(status, JSON_STRING) ? status->string : "?", cases[i].status,
              cases[i].says);
        json_free(doc);
        result_free(&r);
    }
}

/* A run whose CSV cannot be written (a full disk): failed, exit 1, the
 * summary (smaller than the limit) still written, no file listed. */
static void test_failed_run(void)
{
    char csv[128], json[128];
    snprintf(csv, sizeof csv, "%s/full.csv", tmp_dir);
    snprintf(json, sizeof json, "%s/full.json", tmp_dir);
    const char *args[] = {"run", RODSIM_SOURCE_DIR "/scenes/suture_gravity.ini", "--no-video",
                          "--quiet", "--set", "solver.duration=1", "--csv", csv, "--summary",
                          json, NULL};
    file_size_limit = 16384; /* bytes: the CSV needs about 3 MB, the summary 1 kB */
    run_result r = run_rodsim(args, NULL, -1);
    file_size_limit = 0;
    json_value *doc = summary_of("full disk", json, r.status);
    const json_value *status = json_get(doc, "status"), *message = json_get(doc, "message"),
                     *files = json_get(doc, "files");
    struct stat st;
    check(r.status == 1 && json_is(status, JSON_STRING) && strcmp(status->string, "failed") == 0 &&
              json_is(message, JSON_STRING) && strstr(message->string, "CSV") && files &&
              files->count == 0 && stat(csv, &st) != 0,
          "full disk: exit %d, status '%s' (expected failed, 1), the message names the CSV, "
          "no file listed or left", r.status, json_is(status, JSON_STRING) ? status->string : "?");
    json_free(doc);
    result_free(&r);
}

/* --summary -: standard output is the object alone, the prose on stderr. */
static void test_summary_stdout(void)
{
    const char *args[] = {"run", RODSIM_SOURCE_DIR "/scenes/table2_450nN.ini", "--no-video",
                          "--summary", "-", NULL};
    run_result r = run_rodsim(args, NULL, -1);
    json_value *doc = check_summary("--summary -", r.out, r.status);
    check(r.status == 0 && doc && strstr(r.err, "result: t = "),
          "--summary -: standard output is the JSON object alone; the prose went to stderr");
    json_free(doc);
    const char *dir[] = {"run", RODSIM_SOURCE_DIR "/scenes/table2_450nN.ini", "--no-video",
                         "--summary", tmp_dir, NULL};
    result_free(&r);
    r = run_rodsim(dir, NULL, -1);
    check(r.status == 2 && strstr(r.err, "names a directory, not a file") &&
              !strstr(r.err, "result:") && !strstr(r.out, "result:"),
          "--summary DIR: refused before the run (exit %d)", r.status);
    const char *both[] = {"run", RODSIM_SOURCE_DIR "/scenes/table2_450nN.ini", "--no-video",
                          "--summary", "-", "--csv", "-", NULL};
    result_free(&r);
    r = run_rodsim(both, NULL, -1);
    doc = check_summary("--summary - with --csv -", r.out, r.status);
    check(r.status == 2 && strstr(r.err, "give one of them a file"),
          "--summary - with --csv -: refused (exit %d), both want standard output", r.status);
    json_free(doc);
    result_free(&r);
}

/* ---- the prose -------------------------------------------------------- */

static void test_progress(void)
{
    /* suture_gravity is estimated at over 2 s (it takes less) */
    const char *forced[] = {"run", RODSIM_SOURCE_DIR "/scenes/suture_gravity.ini", "--no-video",
                            "--progress", NULL};
    run_result r = run_rodsim(forced, NULL, -1);
    const char *line = strstr(r.err, "CPU s per simulated s");
    size_t n = strlen(r.err);
    const char *last_cr = strrchr(r.err, '\r');
    check(r.status == 0 && line && strchr(r.err, '\r') && strstr(r.err, " left") &&
              strstr(r.err, "t = 10 of 10 s (100 %)") && last_cr && last_cr > r.err,
          "--progress: the progress line on stderr, rewritten with \\r, reaching t = 10 of 10 s");
    /* cleared at the end: the last \r ends a run of blanks that began at a \r */
    const char *p = last_cr - 1;
    while (p > r.err && *p == ' ') p--;
    check(last_cr && *p == '\r' && last_cr - p > 10 && (size_t)(last_cr - r.err) + 1 <= n,
          "--progress: the line is cleared at the end (%ld blanks between two \\r)",
          last_cr ? (long)(last_cr - p - 1) : -1L);
    result_free(&r);
    const char *plain[] = {"run", RODSIM_SOURCE_DIR "/scenes/suture_gravity.ini", "--no-video",
                           NULL};
    r = run_rodsim(plain, NULL, -1);
    check(r.status == 0 && !strchr(r.err, '\r') && !strstr(r.err, "CPU s per simulated s ("),
          "no terminal: no progress line on stderr");
    result_free(&r);
    /* on a terminal (a pseudo-terminal) a run estimated over 2 s shows it */
    int master = posix_openpt(O_RDWR | O_NOCTTY);
    int slave = -1;
    if (master >= 0 && grantpt(master) == 0 && unlockpt(master) == 0)
        slave = open(ptsname(master), O_RDWR | O_NOCTTY);
    if (slave < 0) {
        check(0, "a pseudo-terminal for stderr");
        return;
    }
    r = run_rodsim(plain, NULL, slave);
    close(slave);
    char seen[65536];
    size_t got = 0;
    ssize_t k;
    int flags = fcntl(master, F_GETFL);
    fcntl(master, F_SETFL, flags | O_NONBLOCK);
    while (got + 1 < sizeof seen && (k = read(master, seen + got, sizeof seen - 1 - got)) > 0)
        got += (size_t)k;
    seen[got] = '\0';
    close(master);
    check(r.status == 0 && strstr(seen, "CPU s per simulated s") && strchr(seen, '\r'),
          "on a terminal: the progress line appears without --progress (%zu bytes read)", got);
    result_free(&r);
    const char *quiet[] = {"run", RODSIM_SOURCE_DIR "/scenes/suture_gravity.ini", "--no-video",
                           "--quiet", NULL};
    r = run_rodsim(quiet, NULL, -1);
    check(r.status == 0 && r.err[0] == '\0', "--quiet: nothing on stderr");
    result_free(&r);
}

/* 1 when the run's prose has a knot line ("knot: ..." or "knot identification:
 * ..."); the word alone may be in a path (a checkout under .../knots/) */
static int knot_lines(const char *out)
{
    return strstr(out, "knot: ") != NULL || strstr(out, "knot identification") != NULL;
}

static void test_prose(void)
{
    const char *args[] = {"run", RODSIM_SOURCE_DIR "/scenes/suture_gravity.ini", "--no-video",
                          "--set", "solver.duration=1", "--set", "render.fps=24", "--set",
                          "render.speed=0.25", NULL};
    run_result r = run_rodsim(args, NULL, -1);
    /* 24 fps at speed 0.25: 96 frames per simulated s, 97 frames over 1 s: 4.04 s of video */
    check(r.status == 0 && strstr(r.out, "97 frames (96 per simulated s), a 24 fps video played "
                                         "at speed 0.25 (4.042 s long)"),
          "speed 0.25: the video's own fps (24) and the playback speed, not '96 fps'");
    check(strstr(r.out, "s CPU: ") && strstr(r.out, "CPU s (") && strstr(r.out, "wall s) per "
                                                                         "simulated s"),
          "closing prose: CPU s per simulated s beside the wall time");
    check(strstr(r.out, "knot: unknot") != NULL,
          "an implicit run with self-contact on a rod of 1000 diameters names its knot");
    result_free(&r);
    const char *still[] = {"run", RODSIM_SOURCE_DIR "/scenes/table2_450nN.ini", "--no-video",
                           NULL};
    r = run_rodsim(still, NULL, -1);
    check(r.status == 0 && !knot_lines(r.out),
          "the static scheme (no self-contact) says nothing of knots");
    result_free(&r);
    const char *short_rod[] = {"run", RODSIM_SOURCE_DIR "/scenes/suture_gravity.ini",
                               "--no-video", "--set", "rod.length=0.015", "--set", "rod.nodes=11",
                               "--set", "solver.duration=0.1", NULL};
    r = run_rodsim(short_rod, NULL, -1);
    check(r.status == 0 && !knot_lines(r.out),
          "a rod of 15 diameters (shorter than the 16.4 a trefoil takes) says nothing of knots");
    result_free(&r);
    /* --help lists the CSV's columns, as the CSV's header names them */
    char csv[128];
    snprintf(csv, sizeof csv, "%s/header.csv", tmp_dir);
    const char *run_csv[] = {"run", RODSIM_SOURCE_DIR "/scenes/table2_450nN.ini", "--no-video",
                             "--quiet", "--csv", csv, NULL};
    r = run_rodsim(run_csv, NULL, -1);
    result_free(&r);
    char *text = read_file(csv);
    text[strcspn(text, "\n")] = '\0';
    const char *help[] = {"run", "--help", NULL};
    r = run_rodsim(help, NULL, -1);
    check(text[0] && strstr(r.out, text) != NULL, "run --help lists the CSV's columns '%s'", text);
    free(text);
    unlink(csv);
    result_free(&r);
}

static void test_did_you_mean(void)
{
    const char *cmd[] = {"rnu", NULL};
    run_result r = run_rodsim(cmd, NULL, -1);
    check(r.status == 2 && strstr(r.err, "unknown command 'rnu'; did you mean run?"),
          "rodsim rnu: did you mean run? (exit %d)", r.status);
    result_free(&r);
    const char *option[] = {"run", "x.ini", "--cvs", "a.csv", NULL};
    r = run_rodsim(option, NULL, -1);
    check(r.status == 2 && strstr(r.err, "unknown option '--cvs'; did you mean --csv?"),
          "run --cvs: did you mean --csv?");
    result_free(&r);
    const char *other[] = {"sweep", "x.ini", "--job", "2", NULL};
    r = run_rodsim(other, NULL, -1);
    check(r.status == 2 && strstr(r.err, "unknown option '--job'; did you mean --jobs?"),
          "every command: sweep --job: did you mean --jobs?");
    result_free(&r);
    const char *key[] = {"run", "x.ini", "--duration=3", NULL};
    r = run_rodsim(key, NULL, -1);
    check(r.status == 2 && strstr(r.err, "--set solver.duration=3"),
          "run --duration=3: points to --set solver.duration=3");
    result_free(&r);
    const char *value[] = {"run", RODSIM_SOURCE_DIR "/scenes/suture_gravity.ini", "--no-video",
                           "--set", "render.color=curvatur", NULL};
    r = run_rodsim(value, NULL, -1);
    check(r.status == 2 && strstr(r.err, "did you mean curvature?"),
          "render.color = curvatur: did you mean curvature? (%.200s)", r.err);
    result_free(&r);
}

int main(void)
{
    snprintf(tmp_dir, sizeof tmp_dir, "/tmp/rodsim_summaryXXXXXX");
    if (!mkdtemp(tmp_dir)) return 1;
    test_writer();
    test_static_hanging();
    test_suture_puncture();
    test_knot();
    test_video();
    test_failures();
    test_failed_run();
    test_summary_stdout();
    test_progress();
    test_prose();
    test_did_you_mean();
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", tmp_dir);
    if (system(cmd) != 0) printf("could not remove %s\n", tmp_dir);
    return test_finish();
}
