/* test_render_cli.c: `rodsim render` turns a `rodsim live --record` session
 * into the video and poster. A session fed line by line through
 * pipes (a hanging thread whose held tip is carried 3 cm sideways in
 * 0.4 s) is killed outright (SIGKILL) after its last answer: its record
 * survives with every row, and renders to the frame count the formula
 * floor(T fps) + 1 (+ 1 for a partial interval) gives for T = the last row's
 * t; the last frame shows the rod's colour where live's own --centreline
 * answer at T projects (and not where the thread started). A record cut in
 * the middle of a row renders to the row before, also through `rodsim run`;
 * a file that is not a record, and a --set outside [render], are refused
 * with exit 2. Its summary, warnings and errors name the command typed:
 * "rodsim render: ", and the same record through `rodsim run`, "rodsim run: ". */
#define DECODE_KEEP 16
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "base/ini.h"
#include "cli/scene_outputs.h"
#include "render/image.h"
#include "render/render.h"
#include "test.h"
#include "test_media.h"
#include "test_process.h"
#include "sim/rod.h"

#define NODES 21
#define LINES 400 /* 1 kHz: T = 0.4 s */
#define FPS 30
static const char scene_text[] =
    "[rod]\nlength = 0.5\ndiameter = 0.001\ndensity = 1000\nyoungs_modulus = 87.5e6\n"
    "shear_modulus = 31.25e6\nnodes = 21\ndirection = 0 0 1\n"
    "[solver]\nscheme = implicit\ndt = 0.001\nduration = 1\n"
    "[loads]\ngravity = 0 0 -9.81\n[ends]\nroot = free\ntip = clamped\n";

/* what the test draws with: plain colours, nothing over the rod */
static const char *const render_sets[] = {
    "render.width=320", "render.height=240", "render.fps=30", "render.overlay=false",
    "render.grid=false", "render.arrows=false", "render.stripe=off", "render.shadows=false",
    "render.ground=no", "render.frames_png=true"};
#define RENDER_SETS (int)(sizeof render_sets / sizeof render_sets[0])

/* live's centreline answer at each line (row 0: the straight start), m */
static double centreline[LINES + 1][3 * NODES];

/* The tube's blue (render.rod_color 2e66c7, shaded down to navy where it
 * turns from the light; the video's halved chroma greys it a little): blue
 * above red and green, and dark; the background is light grey, the clamp
 * block grey. */
static int is_rod_colour(const unsigned char *p)
{
    return p[2] >= p[0] + 20 && p[2] > p[1] && p[0] + p[1] + p[2] < 3 * 160;
}

/* Rod-coloured pixels within `r` pixels of (x, y). */
static int rod_pixels_near(const image *img, double x, double y, int r)
{
    int count = 0;
    for (int j = (int)y - r; j <= (int)y + r; j++)
        for (int i = (int)x - r; i <= (int)x + r; i++)
            if (i >= 0 && j >= 0 && i < img->width && j < img->height)
                count += is_rod_colour(img->rgb + ((size_t)j * img->width + i) * 3);
    return count;
}

/* Complete data rows of a record (not comments, not the column header). */
static int record_rows(const char *path)
{
    FILE *f = fopen(path, "r");
    if (!f) return -1;
    char line[1024];
    int rows = 0;
    while (fgets(line, sizeof line, f))
        rows += line[0] != '#' && line[0] != 't' && strchr(line, '\n') != NULL;
    fclose(f);
    return rows;
}

/* The tip's sideways path: 3 cm along x, smooth, in 0.4 s. */
static double tip_x(double t)
{
    double u = t / 0.4;
    return 0.03 * u * u * (3.0 - 2.0 * u);
}

/* Runs the session and kills it after the last answer; 0 when every line
 * was answered ok and its centreline kept. */
static int killed_session(void)
{
    int to[2], from[2];
    if (pipe(to) || pipe(from)) return -1;
    const char *stderr_path = test_path("live_stderr.txt"), *scene = test_path("hang.ini");
    const char *record = test_path("rec.csv");
    fflush(stdout);
    pid_t pid = fork();
    if (pid == 0) {
        dup2(to[0], 0);
        dup2(from[1], 1);
        int e = open(stderr_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (e >= 0) dup2(e, 2);
        close(to[0]); close(to[1]); close(from[0]); close(from[1]);
        alarm(120);
        execl(RODSIM_BIN, RODSIM_BIN, "live", scene, "--centreline", "--record", record,
              (char *)NULL);
        _exit(127);
    }
    close(to[0]);
    close(from[1]);
    FILE *in = fdopen(to[1], "w"), *out = fdopen(from[0], "r");
    static char answer[1 << 14];
    int ok = in && out && fgets(answer, sizeof answer, out) != NULL, answered = 0;
    for (int i = 0; i < NODES; i++) centreline[0][3 * i + 2] = 0.5 * i / (NODES - 1);
    for (int k = 1; ok && k <= LINES; k++) {
        fprintf(in, "%.3f,%.9f,0,0.5\n", k * 1e-3, tip_x(k * 1e-3));
        fflush(in);
        if (!fgets(answer, sizeof answer, out)) break;
        /* t,fx,fy,fz,mx,my,mz,status,x0,y0,z0,... */
        char *p = answer;
        for (int c = 0; c < 8 && p; c++) p = strchr(p, ',') ? strchr(p, ',') + 1 : NULL;
        if (!p) break;
        int got = 0;
        for (; got < 3 * NODES && p; got++) {
            char *end;
            centreline[k][got] = strtod(p, &end);
            p = *end == ',' ? end + 1 : NULL;
        }
        answered += got == 3 * NODES && strstr(answer, ",ok,") != NULL;
    }
    /* the last row is written just after its answer: wait for it, then kill */
    for (int wait = 0; wait < 2000 && record_rows(record) < LINES + 1; wait++) {
        struct timespec ts = {0, 10000000};
        nanosleep(&ts, NULL);
    }
    kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    if (in) fclose(in);
    if (out) fclose(out);
    check(answered == LINES && WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL,
          "live session: %d of %d lines answered ok with their centreline, then killed by "
          "SIGKILL", answered, LINES);
    return answered == LINES ? 0 : -1;
}

/* Output frames of a run of T s at fps (run.h: k/fps <= T, plus T when it
 * is not one of them). */
static int expected_frames(double duration, int fps)
{
    double whole = floor(duration * fps + 1e-9);
    return (int)whole + 1 + (duration - whole / fps > 1e-9 ? 1 : 0);
}

/* The camera of the render, fitted to live's own centreline at the video's
 * frame times (the nearest line, within 0.5 ms); the scene's options as
 * the render read them (the same keys). 0 or -1. */
static int fit_camera(render_camera *cam, int frames)
{
    char err[1024];
    ini_doc *doc = ini_load(test_path("hang.ini"), err, sizeof err);
    if (!doc) return -1;
    for (int i = 0; i < RENDER_SETS; i++) ini_set(doc, render_sets[i], err, sizeof err);
    char tip_motion[600];
    snprintf(tip_motion, sizeof tip_motion, "ends.tip_motion=%s", test_path("rec.csv"));
    ini_set(doc, tip_motion, err, sizeof err);
    rod_model m = rod_model_default();
    run_output out;
    int rc = run_read_scene(doc, &m, &out, err, sizeof err);
    ini_destroy(doc);
    if (rc) {
        printf("fit_camera: %s\n", err);
        return -1;
    }
    rod_recording *rec = rod_recording_create(&m, "rec", frames);
    rod_state *s = rod_state_create(&m);
    if (!rec || !s) return -1;
    rod_state_reset(&m, s);
    for (int f = 0; f < frames; f++) {
        double t = fmin((double)f / FPS, LINES * 1e-3);
        int k = (int)lround(t * 1e3);
        rec->time[f] = t;
        memcpy(&rec->position[(size_t)f * 3 * NODES], centreline[k], sizeof centreline[k]);
        memcpy(&rec->frame[(size_t)f * 9 * NODES], s->frame, 9 * NODES * sizeof(double));
        memset(&rec->tip_force[3 * f], 0, 3 * sizeof(double));
        memset(&rec->tip_moment[3 * f], 0, 3 * sizeof(double));
        if (rec->puncture_count) rec->puncture_count[f] = 0;
    }
    rec->frame_count = frames;
    render_camera_fit(cam, rec, &out.render);
    rod_recording_destroy(rec);
    rod_state_destroy(s);
    rod_model_release(&m);
    return 0;
}

/* The last frame shows the rod where live's centreline at T projects
 * (within `r` pixels: 1 in a PNG, 2 in the video, whose chroma is halved),
 * and not where the thread hung at the start: node NODES - 4, 1.5 cm from
 * the carried tip, has moved with it (the clamp block covers the nodes
 * after it). */
static void check_last_frame(const image *img, const render_camera *cam, int r, const char *what)
{
    int on = 0, checked = 0;
    for (int i = 0; i <= NODES - 4; i += 2) {
        double px[2];
        render_project(cam, &centreline[LINES][3 * i], px);
        int near = rod_pixels_near(img, px[0], px[1], r) > 0;
        if (!near)
            printf("  node %d at (%.1f, %.1f): no rod colour within %d px\n", i, px[0], px[1], r);
        on += near;
        checked++;
    }
    check(on == checked, "%s: the rod's colour at %d of %d nodes of live's centreline at "
          "t = 0.4 s, projected", what, on, checked);
    double now_px[2], start_px[2];
    render_project(cam, &centreline[LINES][3 * (NODES - 4)], now_px);
    render_project(cam, &centreline[0][3 * (NODES - 4)], start_px);
    double moved = hypot(now_px[0] - start_px[0], now_px[1] - start_px[1]);
    check(moved > 4.0 * r + 4.0 && rod_pixels_near(img, start_px[0], start_px[1], r) == 0,
          "%s: node %d is drawn at (%.0f, %.0f), %.0f px from where it started (%.0f, %.0f), "
          "where no rod is", what, NODES - 4, now_px[0], now_px[1], moved, start_px[0],
          start_px[1]);
}

static void test_killed_session_renders(void)
{
    if (killed_session()) return;
    int rows = record_rows(test_path("rec.csv"));
    check(rows == LINES + 1, "the killed session's record kept its t = 0 row and all %d "
          "stepped rows: %d", LINES, rows);
    const char *args[4 + 2 * RENDER_SETS + 1];
    int n = 0;
    args[n++] = "render";
    args[n++] = test_path("rec.csv");
    args[n++] = "-o";
    args[n++] = test_path("out");
    for (int i = 0; i < RENDER_SETS; i++) {
        args[n++] = "--set";
        args[n++] = render_sets[i];
    }
    args[n] = NULL;
    static char output[1 << 16];
    int rc = test_run_rodsim_within(args, 300, output, sizeof output);
    if (!check(rc == 0 && strstr(output, "no closing") != NULL,
               "rodsim render of the killed session: exit %d, says it was cut short", rc)) {
        printf("%s\n", output);
        return;
    }
    const int frames = expected_frames(LINES * 1e-3, FPS);
    decoded d;
    if (!check(decode_video(test_path("out/rec.mp4"), &d) == 0, "out/rec.mp4 decodes")) return;
    check(d.frames == frames && d.width == 320 && d.height == 240,
          "the video has %d frames of 320x240 (floor(0.4 x 30) + 1 = %d)", d.frames, frames);
    check_abs("video duration, s (frames / fps)", d.duration, (double)frames / FPS, 0.5 / FPS);
    check(test_dir_entries(test_path("out/rec_frames")) == frames, "%d PNG frames written (%d)",
          test_dir_entries(test_path("out/rec_frames")), frames);
    render_camera cam;
    char err[512], path[600];
    if (check(fit_camera(&cam, frames) == 0, "camera fitted to live's centreline")) {
        snprintf(path, sizeof path, "%s/out/rec_frames/%05d.png", test_dir(), frames - 1);
        image *last = image_read_png(path, err, sizeof err);
        if (!last) snprintf(path, sizeof path, "%s/out/rec_frames/%05d.png", test_dir(), frames);
        if (!last) last = image_read_png(path, err, sizeof err);
        image *poster = image_read_png(test_path("out/rec.png"), err, sizeof err);
        if (check(last && poster, "the last PNG frame and the poster read")) {
            check_last_frame(last, &cam, 1, "last PNG frame");
            check_last_frame(poster, &cam, 1, "poster");
        }
        if (d.frames == frames && frames <= DECODE_KEEP)
            check_last_frame(d.picked[frames - 1], &cam, 2, "last video frame");
        image_destroy(last);
        image_destroy(poster);
    }
    decoded_release(&d);
}

/* A record cut in the middle of a row (killed while writing it) renders
 * to the row before: T = 0.3 s, 10 frames. */
static void test_cut_row(void)
{
    FILE *in = fopen(test_path("rec.csv"), "r"), *out = fopen(test_path("cut.csv"), "w");
    if (!in || !out) {
        if (in) fclose(in);
        if (out) fclose(out);
        return;
    }
    char line[1024];
    while (fgets(line, sizeof line, in)) {
        if (strncmp(line, "0.30099999999999999,", 20) == 0) {
            fwrite(line, 1, 25, out); /* half a row, no newline */
            break;
        }
        fputs(line, out);
    }
    fclose(in);
    fclose(out);
    const char *args[] = {"render", test_path("cut.csv"), "-o", test_path("out"), "--set",
                          "render.width=64", "--set", "render.height=48", "--set", "render.fps=30",
                          NULL};
    static char output[1 << 16];
    int rc = test_run_rodsim_within(args, 300, output, sizeof output);
    decoded d;
    int frames = rc == 0 && decode_video(test_path("out/cut.mp4"), &d) == 0 ? d.frames : -1;
    check(rc == 0 && strstr(output, "cut.csv:") && strstr(output, "incomplete last line") &&
              frames == expected_frames(0.3, FPS),
          "a record cut inside the row of t = 0.301 s: exit %d, named, rendered to t = 0.3 s: "
          "%d frames (%d)", rc, frames, expected_frames(0.3, FPS));
    if (frames >= 0) decoded_release(&d);
}

/* `rodsim run` on a record renders it as `rodsim render` does. */
static void test_run_on_record(void)
{
    const char *args[] = {"run", test_path("cut.csv"), "-o", test_path("run_out"), "--set",
                          "render.width=64", "--set", "render.height=48", "--quiet", NULL};
    static char output[1 << 16];
    int rc = test_run_rodsim_within(args, 300, output, sizeof output);
    decoded d;
    int frames = rc == 0 && decode_video(test_path("run_out/cut.mp4"), &d) == 0 ? d.frames : -1;
    check(rc == 0 && frames == expected_frames(0.3, FPS),
          "rodsim run on a record: exit %d, run_out/cut.mp4 with %d frames (%d)", rc, frames,
          expected_frames(0.3, FPS));
    if (frames >= 0) decoded_release(&d);
}

/* The command the user typed heads the summary and the errors: a render
 * and a render refused over the time limit say "rodsim render: ", never
 * "rodsim run: "; the same refusal through `rodsim run` says "rodsim run: ". */
static void test_command_named(void)
{
    static char output[1 << 16];
    char render_refused[700], run_refused[700];
    snprintf(render_refused, sizeof render_refused,
             "rodsim render: %s: this run would take about", test_path("cut.csv"));
    snprintf(run_refused, sizeof run_refused, "rodsim run: %s: this run would take about",
             test_path("cut.csv"));
    const char *render[] = {"render", test_path("cut.csv"), "-o", test_path("named"), "--set",
                            "render.width=64", "--set", "render.height=48", NULL};
    int rc = test_run_rodsim_within(render, 300, output, sizeof output);
    const char *head = strstr(output, "\nrodsim render: cut (");
    check(rc == 0 && head && strstr(output, "rodsim run") == NULL,
          "rodsim render's summary line starts \"rodsim render: cut (\", no \"rodsim run\": "
          "exit %d, \"%.24s\"", rc, head ? head + 1 : output);
    setenv("RODSIM_TIME_LIMIT", "1e-9", 1); /* every run is over the limit */
    rc = test_run_rodsim_within(render, 60, output, sizeof output);
    check(rc == 2 && strstr(output, render_refused) &&
              strstr(output, "rodsim run") == NULL,
          "a render over the time limit: exit %d, \"rodsim render: ...would take about\", "
          "no \"rodsim run\"", rc);
    const char *run[] = {"run", test_path("cut.csv"), "-o", test_path("named"), NULL};
    rc = test_run_rodsim_within(run, 60, output, sizeof output);
    check(rc == 2 && strstr(output, run_refused) &&
              strstr(output, "rodsim render") == NULL,
          "the same through rodsim run: exit %d, \"rodsim run: ...would take about\", no "
          "\"rodsim render\"", rc);
    unsetenv("RODSIM_TIME_LIMIT");
}

static void test_refused(void)
{
    static char output[1 << 14];
    int before = test_dir_entries(test_path("out"));
    const char *scene[] = {"render", test_path("hang.ini"), "-o", test_path("out"), NULL};
    int rc = test_run_rodsim_within(scene, 60, output, sizeof output);
    check(rc == 2 && strstr(output, "hang.ini:1: not a rodsim live record") != NULL,
          "a scene given to render: exit %d, named at line 1", rc);
    const char *physics[] = {"render", test_path("rec.csv"), "--set", "rod.nodes=5", NULL};
    rc = test_run_rodsim_within(physics, 60, output, sizeof output);
    check(rc == 2 && strstr(output, "only render.KEY=VALUE") != NULL,
          "render --set rod.nodes=5: exit %d, only [render] keys", rc);
    check(test_dir_entries(test_path("out")) == before, "the refused renders wrote nothing to out/ "
          "(%d entries, %d before)", test_dir_entries(test_path("out")), before);
}

int main(void)
{
    signal(SIGPIPE, SIG_IGN);
    FILE *f = fopen(test_path("hang.ini"), "w");
    if (!f) return 1;
    fputs(scene_text, f);
    fclose(f);
    test_killed_session_renders();
    test_cut_row();
    test_run_on_record();
    test_command_named();
    test_refused();
    return test_finish();
}
