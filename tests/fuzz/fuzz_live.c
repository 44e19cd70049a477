/* fuzz_live.c: libFuzzer harness for `rodsim live`'s input loop: the bytes
 * are a session's standard input, fed to live_session_feed (cli/live.h) in
 * chunks of a size the input chooses, so lines split anywhere; then
 * live_session_finish at the end of input. The first byte chooses the
 * scene (a clamped tip driven by its pose, a pinned tip, a free tip taking
 * loads, a clamped tip over a table: failed lines, partial moves) and
 * --on-error stop; a session is made afresh for each input (no state
 * carries over, so a crash replays from its input alone), 5 nodes, at
 * most 4 steps a line (live_settings.max_steps_ahead), the first 64 lines.
 *
 * Contracts (live.h): without --on-error stop, exactly one answer per line
 * (a newline ends one, and the end of input a last one without it); with
 * it, one per line up to the first refused one; every answer is
 * t,fx,fy,fz,mx,my,mz,status with finite numbers and status ok, failed or
 * bad_input; t never decreases; the exit status is 0 or 2. */
#define _GNU_SOURCE /* open_memstream */
#include <math.h>

#include "base/ini.h"
#include "cli/live.h"
#include "cli/scene_outputs.h"
#include "fuzz.h"
#include "sim/rod.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* The lines a session answers at most: a failed line costs up to its tries'
 * budgets, so a long input would take seconds */
#define FUZZ_LIVE_LINES 64

static const char scene_common[] =
    "[rod]\nlength = 0.5\ndiameter = 0.001\ndensity = 1000\nyoungs_modulus = 87.5e6\n"
    "shear_modulus = 31.25e6\nnodes = 5\ndirection = 0 0 1\n"
    "[solver]\nscheme = implicit\ndt = 0.01\nduration = 1\n"
    "[loads]\ngravity = 0 0 -9.81\n";
static const char *const scene_ends[4] = {
    "[ends]\nroot = free\ntip = clamped\n",
    "[ends]\nroot = free\ntip = pinned\n",
    "[ends]\nroot = clamped\ntip = free\n",
    ("[ends]\nroot = free\ntip = clamped\n"
     "[surface]\nshape = plane\ncenter = 0 0 -0.001\nnormal = 0.05 0 1\nfriction = 0.3\n"),
};

/* Checks one answer line (without its newline); *t the last answer's t. */
static void check_answer(const char *line, double *t)
{
    const char *p = line;
    double v[7];
    for (int k = 0; k < 7; k++) {
        char *end;
        v[k] = strtod(p, &end);
        fuzz_require(end != p && *end == ',', "an answer starts with 7 numbers", line);
        fuzz_require(isfinite(v[k]), "an answer's numbers are finite", line);
        p = end + 1;
    }
    fuzz_require(!strcmp(p, "ok") || !strcmp(p, "failed") || !strcmp(p, "bad_input"),
                 "an answer's status is ok, failed or bad_input", line);
    fuzz_require(v[0] >= *t, "the answers' t never decreases", line);
    *t = v[0];
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1) return 0;
    const unsigned scene = data[0] & 3, stop = (data[0] >> 2) & 1;
    const size_t chunk = 1 + (data[0] >> 3); /* 1 .. 32 bytes a feed */
    const char *bytes = (const char *)data + 1;
    size = size - 1;
    /* the first FUZZ_LIVE_LINES lines, or all and a last one without its newline */
    size_t lines = 0, end = 0; /* end: the bytes up to the last newline counted */
    for (size_t i = 0; i < size && lines < FUZZ_LIVE_LINES; i++)
        if (bytes[i] == '\n') {
            lines++;
            end = i + 1;
        }
    if (lines == FUZZ_LIVE_LINES) size = end;
    else if (end < size) lines++;

    static FILE *sink;
    if (!sink && !(sink = fopen("/dev/null", "w"))) abort();
    char text[1024], err[1024] = "";
    snprintf(text, sizeof text, "%s%s", scene_common, scene_ends[scene]);
    ini_doc *doc = ini_parse("fuzz_live.ini", text, err, sizeof err);
    fuzz_require(doc != NULL, "the harness' scene parses", err);
    rod_model m = rod_model_default();
    run_output out;
    fuzz_require(run_read_scene(doc, &m, &out, err, sizeof err) == 0,
                 "the harness' scene reads", err);
    char *answers = NULL;
    size_t answers_size = 0;
    FILE *answer_file = open_memstream(&answers, &answers_size);
    if (!answer_file) abort();
    const live_settings settings = {.stop_on_error = (int)stop, .max_steps_ahead = 4,
                                    .answers = answer_file, .messages = sink};
    live_session *ls = live_session_create(&m, &settings, err, sizeof err);
    fuzz_require(ls != NULL, "a session is made for the harness' scene", err);
    live_session_start(ls);
    for (size_t at = 0; at < size; at += chunk)
        if (live_session_feed(ls, bytes + at, size - at < chunk ? size - at : chunk)) break;
    const int status = live_session_finish(ls, 1);
    live_session_destroy(ls);
    fclose(answer_file);
    fuzz_require(status == 0 || status == 2, "the exit status is 0 or 2", NULL);

    /* the header, then one answer a line */
    static const char header[] = "t,fx,fy,fz,mx,my,mz,status\n";
    char *line = answers, *newline = strchr(line, '\n');
    fuzz_require(newline && !strncmp(line, header, sizeof header - 1), "the header comes first",
                 answers);
    line = newline + 1;
    size_t count = 0;
    double t = 0.0;
    while ((newline = strchr(line, '\n'))) {
        *newline = '\0';
        check_answer(line, &t);
        count++;
        line = newline + 1;
    }
    fuzz_require(*line == '\0', "every answer ends with a newline", line);
    char detail[96];
    snprintf(detail, sizeof detail, "%zu answers, %zu lines", count, lines);
    if (stop) fuzz_require(count <= lines, "at most one answer a line (--on-error stop)", detail);
    else fuzz_require(count == lines, "exactly one answer a line", detail);
    free(answers);
    rod_model_release(&m);
    ini_destroy(doc);
    return 0;
}
