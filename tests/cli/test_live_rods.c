/* test_live_rods.c: `rodsim live` of several rods with --record and
 * --centreline. Two rods hanging from pinned tips (test_hanging_rods.h),
 * held still for 4 s by lines naming each in turn: the record is the CSV
 * of `rodsim run --csv` (its column rod), a frame at t = 0 and one per line
 * answered ok, each frame the rods' node counts of rows (16 + 26), both
 * names in it; at rest each rod's recorded internal force at its held tip
 * is its weight rho A g L (a closed form, independent of the code); every
 * answer carries both rods' centrelines, equal to the record's last frame. A record that cannot be
 * made: exit 1, no answer. --realtime paces the lines of two rods to the
 * wall clock: 0.2 s of lines take at least 0.2 s. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "test.h"
#include "test_hanging_rods.h"
#include "test_process.h"

#define LINES 400   /* lines, 0.01 s apart: t = 4 s at the end */
#define ROWS (16 + 26) /* a frame's rows: the two rods' nodes */

static char text[1 << 21]; /* the answers: some 1.5 kB each */

static long read_file(const char *path, char *buf, size_t n)
{
    FILE *f = fopen(path, "r");
    if (!f) return -1;
    size_t got = fread(buf, 1, n - 1, f);
    buf[got] = '\0';
    fclose(f);
    return (long)got;
}

/* Reads the record: the header checked, each frame's row count and rods,
 * the last frame's rows kept. */
typedef struct record_summary {
    int header_ok, frames, frames_right, names_both;
    double last_t;
    double last[ROWS][11]; /* s, x, y, z, d3x..z, twist, nx, ny, nz of the last frame */
    char last_rod[ROWS][8];
} record_summary;

static void read_record(const char *path, record_summary *r)
{
    memset(r, 0, sizeof *r);
    FILE *f = fopen(path, "r");
    if (!f) return;
    char line[1024];
    r->header_ok = fgets(line, sizeof line, f) &&
                   strcmp(line, "t,rod,node,s,x,y,z,d3x,d3y,d3z,twist,nx,ny,nz\n") == 0;
    double frame_t = -1.0;
    int rows = 0, shorts = 0, longs = 0;
    for (;;) {
        double t = 0.0, v[11];
        char rod[8] = "";
        int node = -1;
        const int got = fgets(line, sizeof line, f)
                            ? sscanf(line, "%lf,%7[^,],%d,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,"
                                     "%lf,%lf", &t, rod, &node, &v[0], &v[1], &v[2], &v[3], &v[4],
                                     &v[5], &v[6], &v[7], &v[8], &v[9], &v[10])
                            : 0;
        if (got != 14 || t != frame_t) { /* a frame ends */
            if (frame_t >= 0.0) {
                r->frames++;
                r->frames_right += rows == ROWS && shorts == 16 && longs == 26;
                r->names_both += shorts > 0 && longs > 0;
            }
            if (got != 14) break;
            frame_t = t;
            rows = shorts = longs = 0;
        }
        shorts += strcmp(rod, "short") == 0;
        longs += strcmp(rod, "long") == 0;
        if (rows < ROWS) {
            memcpy(r->last[rows], v, sizeof v);
            snprintf(r->last_rod[rows], sizeof r->last_rod[rows], "%s", rod);
        }
        rows++;
        r->last_t = t;
    }
    fclose(f);
}

static void test_record_and_centreline(void)
{
    FILE *in = fopen(test_path("in.txt"), "w");
    if (!check(in != NULL, "wrote the input lines")) return;
    for (int i = 1; i <= LINES; i++) {
        if (i == 100) fprintf(in, "middle:%.2f,0,0,0\n", i * 0.01); /* bad: no frame */
        fprintf(in, i % 2 ? "short:%.2f,0,0,0\n" : "long:%.2f,0.2,0,0\n", i * 0.01);
    }
    fclose(in);
    const int rc = system(RODSIM_BIN " live $RODSIM_TEST_DIR/rods.ini --centreline --record "
                          "$RODSIM_TEST_DIR/out/rec.csv < $RODSIM_TEST_DIR/in.txt > "
                          "$RODSIM_TEST_DIR/answers.txt 2> $RODSIM_TEST_DIR/stderr.txt");
    check(rc == 0, "rodsim live --centreline --record of two rods: exit %d (0)", rc);
    record_summary *r = calloc(1, sizeof *r);
    if (!r) return;
    read_record(test_path("out/rec.csv"), r);
    check(r->header_ok, "the record's header: t,rod,node,s,x,y,z,...,nx,ny,nz (rodsim run --csv)");
    check(r->frames == LINES + 1 && r->frames_right == r->frames && r->names_both == r->frames,
          "%d frames (%d: t = 0 and the %d lines ok, not the bad one); %d of them of %d rows "
          "(16 short + 26 long), %d naming both rods",
          r->frames, LINES + 1, LINES, r->frames_right, ROWS, r->names_both);
    check_abs("the last frame's t, s", r->last_t, LINES * 0.01, 1e-12);
    /* the held tips: the last node of each rod (rows 15 and 41) */
    const double w_short = hanging_rod_weight(0.3, 1000.0), w_long = hanging_rod_weight(0.5, 1000.0);
    printf("recorded nz at the held tips: short %.12g N (rho A g L %.12g), long %.12g N "
           "(%.12g)\n", r->last[15][10], w_short, r->last[41][10], w_long);
    check(strcmp(r->last_rod[15], "short") == 0 && strcmp(r->last_rod[41], "long") == 0,
          "rows 16 and 42 of a frame: the tips of short and long");
    check_rel("short's recorded internal force at its held tip, nz (N): rho A g L", r->last[15][10],
              w_short, 1e-6);
    check_rel("long's recorded internal force at its held tip, nz (N): rho A g L", r->last[41][10],
              w_long, 1e-6);
    check_abs("long's horizontal internal force at its tip, N", hypot(r->last[41][8],
              r->last[41][9]), 0.0, 1e-6 * w_long);
    /* the answers: both centrelines after each, the last equal to the record's */
    long got = read_file(test_path("answers.txt"), text, sizeof text);
    const char *header = text, *last = NULL;
    int answers = 0;
    for (char *c = text; got > 0 && *c; c++)
        if (*c == '\n') {
            *c = '\0';
            if (c[1]) last = c + 1, answers++;
        }
    int columns = 1;
    for (const char *c = header; *c; c++) columns += *c == ',';
    check(columns == 9 + 3 * ROWS && strstr(header, "status,short.x0,short.y0,short.z0,") &&
              strstr(header, ",long.x25,long.y25,long.z25") != NULL,
          "--centreline header: %d columns (9 + 3 x %d), short.x0 ... long.z25", columns, ROWS);
    check(answers == LINES + 1, "%d answers (%d lines)", answers, LINES + 1);
    double worst = 0.0;
    int fields = 0;
    if (last && strncmp(last, "long,4,", 7) == 0) {
        const char *p = last;
        for (int c = 0; c < 9 && p; c++) p = strchr(p, ',') ? strchr(p, ',') + 1 : NULL;
        for (int row = 0; p && row < ROWS; row++)
            for (int j = 0; j < 3 && p; j++) {
                const double v = strtod(p, NULL), ref = r->last[row][1 + j];
                worst = fmax(worst, fabs(v - ref));
                fields++;
                p = strchr(p, ',') ? strchr(p, ',') + 1 : NULL;
            }
    }
    check(fields == 3 * ROWS && worst <= 1e-12,
          "the last answer's %d centreline numbers (both rods) = the record's last frame: "
          "largest difference %.3g m (12 digits printed: 1e-12)", fields, worst);
    free(r);
}

static void test_refused(void)
{
    char out[4096];
    const char *bad_dir[] = {"live", test_path("rods.ini"), "--record", test_path("rods.ini/r.csv"),
                             NULL};
    int rc = test_run_rodsim_within(bad_dir, 30, out, sizeof out);
    check(rc == 1 && strstr(out, "rods.ini") && !strstr(out, "rod,t,"),
          "--record under a file: exit %d (1), no answer: %s", rc, out);
}

/* --realtime: 100 lines 2 ms apart (the two rods in turn) take at least
 * their 0.2 s of wall clock, each answered ok, the overruns counted */
static void test_realtime(void)
{
    FILE *f = fopen(test_path("paced.txt"), "w");
    if (!f) return;
    for (int i = 1; i <= 100; i++)
        fprintf(f, i % 2 ? "short:%.3f,0,0,0\n" : "long:%.3f,0.2,0,0\n", i * 2e-3);
    fclose(f);
    struct timespec a, b;
    clock_gettime(CLOCK_MONOTONIC, &a);
    const int rc = system(RODSIM_BIN " live $RODSIM_TEST_DIR/rods.ini --realtime < "
                          "$RODSIM_TEST_DIR/paced.txt > $RODSIM_TEST_DIR/paced_out.txt 2> "
                          "$RODSIM_TEST_DIR/stderr.txt");
    clock_gettime(CLOCK_MONOTONIC, &b);
    const double wall = (double)(b.tv_sec - a.tv_sec) + 1e-9 * (double)(b.tv_nsec - a.tv_nsec);
    long got = read_file(test_path("paced_out.txt"), text, sizeof text);
    int ok = 0;
    for (const char *c = text; got > 0 && (c = strstr(c, ",ok\n")); c++) ok++;
    char err[4096] = "";
    read_file(test_path("stderr.txt"), err, sizeof err);
    printf("%s", err);
    check(rc == 0 && ok == 100 && wall >= 0.2 && strstr(err, "realtime overruns") != NULL,
          "--realtime, two rods: 100 lines 2 ms apart answered ok (%d) in %.3f s >= 0.2 s, "
          "overruns counted, exit %d", ok, wall, rc);
}

int main(void)
{
    if (!check(hanging_rods_write(test_path("rods.ini")) == 0, "wrote the two rods' scene"))
        return 1;
    test_record_and_centreline();
    test_refused();
    test_realtime();
    return test_finish();
}
