/* test_frame_schedule.c: slow motion ([render] slow_motion): the output
 * times are the regular k / rate outside each range and FACTOR times
 * closer inside it, their count gives the video's length (one video frame
 * each at render.fps: the range plays FACTOR times slower), every interval
 * is stepped in steps no longer than dt, and `rodsim run` writes its CSV
 * rows at exactly these times. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/ini.h"
#include "cli/frame_schedule.h"
#include "test.h"
#include "test_media.h"
#include "test_process.h"

static int read_slow(const char *value, render_options *o, char *err, size_t errlen)
{
    char text[256];
    snprintf(text, sizeof text, "[render]\nslow_motion = %s\n", value);
    render_options_default(o);
    ini_doc *doc = ini_parse("slow.ini", text, err, errlen);
    if (!doc) return -1;
    int rc = render_options_read(doc, o, err, errlen);
    ini_destroy(doc);
    return rc;
}

/* 1 when times[first..last] are evenly spaced by `spacing` (1e-9 relative). */
static int spaced(const double *times, int64_t first, int64_t last, double spacing)
{
    for (int64_t k = first + 1; k <= last; k++)
        if (fabs(times[k] - times[k - 1] - spacing) > 1e-9 * spacing) return 0;
    return 1;
}

static void test_one_range(void)
{
    render_options o;
    char err[512] = "";
    if (!check(read_slow("0.5 1.5 4", &o, err, sizeof err) == 0 && o.slow_count == 1,
               "slow_motion = 0.5 1.5 4 reads (%s)", err))
        return;
    frame_schedule fs;
    if (!check(frame_schedule_make(&o, 30, 5.0, &fs) == 0, "the schedule is made")) return;
    /* 5 s at 30 frames per s: 150 intervals; 0.5 .. 1.5 s is 30 of them, 120 when 4x closer */
    check(fs.count == 150 - 30 + 120 + 1, "frames: %lld (150 - 30 + 120 intervals + 1 = 241)",
          (long long)fs.count);
    check_abs("the first time (s)", fs.time[0], 0.0, 0);
    check_abs("the last time (s)", fs.time[fs.count - 1], 5.0, 1e-12);
    /* 0 .. 0.5 s: 15 intervals of 1/30; 0.5 .. 1.5: 120 of 1/120; then 1/30 to 5 s */
    check(spaced(fs.time, 0, 15, 1.0 / 30), "0 .. 0.5 s: frames 1/30 s apart");
    check_abs("frame 15 at the range's start (s)", fs.time[15], 0.5, 1e-12);
    check(spaced(fs.time, 15, 135, 1.0 / 120), "0.5 .. 1.5 s: frames 1/120 s apart (4x closer)");
    check_abs("frame 135 at the range's end (s)", fs.time[135], 1.5, 1e-12);
    check(spaced(fs.time, 135, fs.count - 1, 1.0 / 30), "1.5 .. 5 s: frames 1/30 s apart");
    /* the video: one frame each at fps 30; the range plays 4 x 1 s, the rest 4 s */
    check_rel("video length, intervals / fps (s): 4 s + 4 x 1 s", (double)(fs.count - 1) / 30,
              8.0, 1e-12);

    /* every interval stepped within dt: (1/30)/0.005 -> 7 steps, (1/120)/0.005 -> 2 */
    run_plan p;
    memset(&p, 0, sizeof p);
    frame_schedule_plan(&fs, 0.005, &p);
    check(p.frames == fs.count && p.intervals == fs.count - 1 && p.frame_times == fs.time,
          "the plan takes the schedule's %lld frames", (long long)p.frames);
    check(p.steps == 120 * 7 + 120 * 2, "steps: %lld (120 intervals x 7 + 120 x 2 = 1080)",
          (long long)p.steps);
    double longest = 0;
    for (int64_t k = 1; k < fs.count; k++) {
        double interval = fs.time[k] - fs.time[k - 1];
        longest = fmax(longest, interval / (double)run_interval_steps(interval, 0.005));
    }
    check(longest <= 0.005 && p.step == longest,
          "the longest step %.9g s is within dt = 0.005 s (plan: %.9g)", longest, p.step);
    frame_schedule_release(&fs);
}

static void test_edges(void)
{
    render_options o;
    char err[512] = "";
    frame_schedule fs;
    /* moved to the nearest frames; a factor of 2.5 over 3 intervals: round(7.5) = 8 */
    read_slow("0.101, 0.199, 2.5", &o, err, sizeof err);
    frame_schedule_make(&o, 30, 1.0, &fs);
    check(fs.count == 30 - 3 + 8 + 1, "0.101 .. 0.199 s at 2.5x: 3 intervals become 8, %lld "
                                      "frames (35)", (long long)fs.count);
    check_abs("the range moved to frame 3 (s)", fs.time[3], 0.1, 1e-12);
    check(spaced(fs.time, 3, 11, 0.1 / 8), "and split in 8 equal intervals to 0.2 s");
    frame_schedule_release(&fs);
    /* a duration off the grid keeps its end; two ranges, given in any order */
    read_slow("0.8 1.01 2; 0.1 0.2 3", &o, err, sizeof err);
    check(o.slow_count == 2 && o.slow[0].start == 0.1, "two ranges read, sorted (%s)", err);
    frame_schedule_make(&o, 10, 1.05, &fs);
    /* 10 regular intervals + the partial to 1.05; 0.1 .. 0.2: 1 -> 3; 0.8 .. 1.0: 2 -> 4 */
    check(fs.count == 10 + 1 + 1 + 2 + 2, "%lld frames (16)", (long long)fs.count);
    check_abs("the end (s)", fs.time[fs.count - 1], 1.05, 1e-12);
    int increasing = 1;
    for (int64_t k = 1; k < fs.count; k++) increasing &= fs.time[k] > fs.time[k - 1];
    check(increasing, "the times increase");
    check(fabs(render_slow_factor(&o, 0.15) - 3) == 0 && render_slow_factor(&o, 0.5) == 1 &&
              render_slow_factor(&o, 0.9) == 2,
          "the overlay's factor: 3 at 0.15 s, 1 at 0.5 s, 2 at 0.9 s");
    frame_schedule_release(&fs);
    check(read_slow("none", &o, err, sizeof err) == 0 && o.slow_count == 0,
          "slow_motion = none: no range (--set turns a scene's off)");
    check(read_slow("auto", &o, err, sizeof err) == 0 && o.slow_auto == 4 && o.slow_count == 0,
          "slow_motion = auto: factor 4 around the fastest tightening (%s)", err);
    check(read_slow("auto 2.5", &o, err, sizeof err) == 0 && o.slow_auto == 2.5,
          "slow_motion = auto 2.5: factor 2.5 (%s)", err);
    static const char *const bad[] = {"1 2", "1 2 1", "2 1 4", "0 1 2 0.5 1.5 2", "a b c",
                                      "auto 1", "auto x", "autox"};
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        err[0] = '\0';
        check(read_slow(bad[k], &o, err, sizeof err) == -1 && strstr(err, "slow.ini:2"),
              "slow_motion = %s refused: %s", bad[k], err);
    }
}

/* The run writes its rows at the schedule's times. */
static void test_run(void)
{
    char dir[] = "/tmp/rodsim_slowXXXXXX";
    if (!mkdtemp(dir)) return;
    char scene[256], csv[256], out[8192];
    snprintf(scene, sizeof scene, "%s/slow.ini", dir);
    snprintf(csv, sizeof csv, "%s/slow.csv", dir);
    FILE *f = fopen(scene, "w");
    fputs("[rod]\nlength = 1\ndiameter = 0.01\ndensity = 1000\nyoungs_modulus = 1e10\n"
          "shear_modulus = 4e9\nnodes = 21\n[loads]\ngravity = 0 0 -9.81\n"
          "[solver]\nduration = 1\ndt = 0.01\n[render]\nfps = 10\nslow_motion = 0.2 0.4 5\n",
          f);
    fclose(f);
    const char *args[] = {"run",          scene,          "--quiet",      "--csv",
                          csv,            "-o",           dir,            "--set",
                          "render.width=64", "--set",     "render.height=36", NULL};
    int rc = test_run_rodsim(args, out, sizeof out);
    if (check(rc == 0, "rodsim run with slow_motion exits 0 (%s)", out)) {
        f = fopen(csv, "r");
        char line[512];
        double times[64];
        int n = 0;
        while (f && fgets(line, sizeof line, f))
            if (strstr(line, ",0,0,") == strchr(line, ',') && n < 64) times[n++] = atof(line);
        if (f) fclose(f);
        /* 10 intervals, 2 of them (0.2 .. 0.4 s) 5x closer: 8 + 10 intervals, 19 rows */
        check(n == 19, "node 0's CSV rows: %d (19)", n);
        check(n == 19 && spaced(times, 2, 12, 0.02) && spaced(times, 12, 18, 0.1) &&
                  spaced(times, 0, 2, 0.1),
              "rows 0.1 s apart, 0.02 s apart within 0.2 .. 0.4 s");
        /* the video: a frame per row at 10 fps, 0.2 s simulated played over 1 s */
        char path[300];
        snprintf(path, sizeof path, "%s/slow.mp4", dir);
        decoded video;
        if (check(decode_video(path, &video) == 0, "the video decodes")) {
            check(video.frames == 19, "the video's frames: %d (19)", video.frames);
            check_rel("the video's duration (s): 19 frames at 10 fps, 1 s simulated + 0.2 s "
                      "played 5x slower",
                      video.duration, 1.9, 1e-6);
            decoded_release(&video);
        }
        unlink(path);
        snprintf(path, sizeof path, "%s/slow.png", dir);
        unlink(path);
    }
    const char *automatic[] = {"run",  scene, "--no-video", "--set", "render.slow_motion=auto",
                               NULL};
    rc = test_run_rodsim(automatic, out, sizeof out);
    check(rc == 0 && strstr(out, "auto: no knot tightens") && strstr(out, "11 frames"),
          "a rod with no knot, slow_motion = auto: none, 11 frames, and the summary says so");
    unlink(csv);
    unlink(scene);
    rmdir(dir);
}

/* slow_motion = auto: the knot of overhand_tight.ini, its first second at
 * 10 frames per s (10 intervals), is found tightening and slowed: more
 * frames, and the summary says where; a rod with no knot gets none. */
static void test_auto(void)
{
    char out[16384];
    const char *args[] = {"run", RODSIM_SOURCE_DIR "/scenes/overhand_tight.ini", "--no-video",
                          "--set", "solver.duration=1", "--set", "render.fps=10", "--set",
                          "render.slow_motion=auto", NULL};
    int rc = test_run_rodsim(args, out, sizeof out);
    const char *said = strstr(out, "auto: the knot tightens fastest between ");
    double from = -1, to = -1;
    if (said) sscanf(said, "auto: the knot tightens fastest between %lf and %lf", &from, &to);
    const char *frames = strstr(out, "output   1 s simulated, ");
    int count = frames ? atoi(frames + strlen("output   1 s simulated, ")) : 0;
    check(rc == 0 && said && from >= 0 && to > from && to <= 1,
          "overhand_tight.ini, 1 s, slow_motion = auto: the summary names %g .. %g s", from, to);
    /* each slowed interval of 0.1 s becomes 4: 11 frames + 3 per interval in the range */
    int slowed = (int)lround(to * 10) - (int)lround(from * 10);
    check(count == 11 + 3 * slowed, "frames: %d (11 + 3 x %d slowed intervals)", count, slowed);
}

int main(void)
{
    test_one_range();
    test_edges();
    test_run();
    test_auto();
    return test_finish();
}
