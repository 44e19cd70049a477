/* test_rods_run.c: `rodsim run` of a scene of several rods ([rod NAME]):
 * two identical ropes far apart give, each, the CSV rows of that rope run
 * alone (the column rod added, and nothing else); the summary lists each
 * rod by name; a single-rod scene's CSV has no column rod. Each rod's knot
 * is named: an overhand-knotted rod beside a straight one gives a trefoil
 * (Alexander polynomial 1 - t + t^2, determinant 3, the hand the same rod
 * gets run alone) and an unknot (1, determinant 1). A [cut] of rod b: the
 * summary's cut names the rod and the piece removed, rods[] and the CSV
 * the thread left (its nodes numbered as on the uncut rod), the text the
 * cut under rod b. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "test.h"
#include "test_process.h"

#define ROPE "length = 0.3\ndiameter = 0.004\ndensity = 1100\nyoungs_modulus = 5e7\n" \
             "shear_modulus = 1.9e7\nnodes = 31\ndirection = 1 0 0.1\nfriction = 0.3\n"
#define SHARED "[solver]\nscheme = implicit\ndt = 0.002\nduration = 0.5\n" \
               "[loads]\ngravity = 0 0 -9.81\nlinear_damping = 0.01\n" \
               "[surface]\nshape = plane\ncenter = 0 0 0\nnormal = 0 0 1\nfriction = 0.4\n"

static int write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (!f) return -1;
    fputs(text, f);
    return fclose(f);
}

static char *read_all(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    rewind(f);
    char *text = malloc((size_t)n + 1);
    if (text && fread(text, 1, (size_t)n, f) != (size_t)n) {
        free(text);
        text = NULL;
    }
    if (text) text[n] = '\0';
    fclose(f);
    return text;
}

/* The largest difference of the numbers of the rows of rod `name` in the
 * two-rod CSV (its y less y_offset) from the rows of the single rod's CSV,
 * over the columns after node; -1 when the rows do not pair up */
static double csv_difference(const char *two, const char *one, const char *name, double y_offset)
{
    double worst = 0.0;
    const char *p = strchr(two, '\n') + 1, *q = strchr(one, '\n') + 1;
    int rows = 0;
    while (*p && *q) {
        const char *end = strchr(p, '\n');
        char rod[32];
        double t2, v2[12], t1, v1[12];
        int node2, node1;
        if (sscanf(p, "%lf,%31[^,],%d,", &t2, rod, &node2) != 3) return -1;
        if (strcmp(rod, name) != 0) {
            p = end + 1;
            continue;
        }
        const char *after2 = strchr(strchr(strchr(p, ',') + 1, ',') + 1, ',') + 1;
        const char *after1 = strchr(strchr(q, ',') + 1, ',') + 1;
        if (sscanf(q, "%lf,%d,", &t1, &node1) != 2 || t1 != t2 || node1 != node2) return -1;
        for (int k = 0; k < 11; k++) {
            if (sscanf(after2, "%lf", &v2[k]) != 1 || sscanf(after1, "%lf", &v1[k]) != 1)
                return -1;
            if (k == 2) v2[k] -= y_offset;
            worst = fmax(worst, fabs(v2[k] - v1[k]));
            after2 = strchr(after2, ',') + 1;
            after1 = strchr(after1, ',') + 1;
        }
        rows++;
        p = end + 1;
        q = strchr(q, '\n') + 1;
    }
    return rows > 0 && !*q ? worst : -1;
}

/* The overhand knot's rod (scenes/overhand_shape.csv, pinned ends; the
 * cord of scenes/overhand.ini) as [rod NAME], NAME "" for a bare [rod] */
static void overhand_rod(char *buf, size_t n, const char *name)
{
    snprintf(buf, n, "[rod%s%s]\nlength = 0.609684253\ndiameter = 0.004\ndensity = 1100\n"
             "youngs_modulus = 5e7\nshear_modulus = 2e7\nnodes = 241\n"
             "shape = %s/scenes/overhand_shape.csv\nfriction = 0.2\n[ends%s%s]\nroot = pinned\n"
             "tip = pinned\n", name[0] ? " " : "", name, RODSIM_SOURCE_DIR, name[0] ? " " : "",
             name);
}

#define SHORT_RUN "[solver]\nscheme = implicit\ndt = 0.005\nduration = 0.02\n[render]\nfps = 100\n"

/* rod a tied in an overhand knot, rod b straight 0.5 m beside it: the
 * summary (JSON and text) names each rod's knot; 4 steps, 3 frames */
static void check_knots(const char *dir)
{
    char path[512], cmd[2048], text[4096];
    snprintf(path, sizeof path, "%s/knots.ini", dir);
    overhand_rod(text, sizeof text, "a");
    FILE *f = fopen(path, "w");
    if (!f) {
        check(0, "writing %s", path);
        return;
    }
    fprintf(f, "%s[rod b]\n" ROPE "origin = -0.15 0.5 0\n[ends b]\nroot = pinned\ntip = free\n"
            SHORT_RUN, text);
    fclose(f);
    snprintf(path, sizeof path, "%s/alone.ini", dir);
    overhand_rod(text, sizeof text, "");
    f = fopen(path, "w");
    if (!f) {
        check(0, "writing %s", path);
        return;
    }
    fprintf(f, "%s" SHORT_RUN, text);
    fclose(f);
    snprintf(cmd, sizeof cmd,
             "%s run %s/knots.ini --no-video --summary %s/knots.json > %s/knots.txt && "
             "%s run %s/alone.ini --no-video --quiet --summary %s/alone.json",
             RODSIM_BIN, dir, dir, dir, RODSIM_BIN, dir, dir);
    int status = system(cmd);
    check(status == 0, "the knotted and the straight rod, and the knotted one alone: exit 0 "
          "(status %d)", status);
    snprintf(path, sizeof path, "%s/knots.json", dir);
    char *json = read_all(path);
    snprintf(path, sizeof path, "%s/alone.json", dir);
    char *alone = read_all(path);
    snprintf(path, sizeof path, "%s/knots.txt", dir);
    char *said = read_all(path);
    if (!json || !alone || !said) {
        check(0, "the knot run's outputs are readable");
    } else {
        /* the knot rod a gets alone: its type, with the hand */
        const char *t = strstr(alone, "\"knot\":{\"type\":\"");
        char type[96] = "";
        if (t) sscanf(t + 16, "%95[^\"]", type);
        char a_knot[256], b_knot[256];
        snprintf(a_knot, sizeof a_knot, "\"knot\":{\"type\":\"%s\",\"alexander\":[1,-1,1],"
                 "\"determinant\":3,", type);
        snprintf(b_knot, sizeof b_knot, "\"knot\":{\"type\":\"unknot\",\"alexander\":[1],"
                 "\"determinant\":1,\"signature\":0,\"changes\":[]}");
        const char *rod_b = strstr(json, "{\"name\":\"b\"");
        const char *in_a = strstr(json, a_knot);
        check(strncmp(type, "trefoil, ", 9) == 0, "the overhand rod alone: %s (reference: a "
              "trefoil with its hand)", type);
        check(in_a && rod_b && in_a < rod_b, "rod a's knot in the JSON: %s (Alexander 1 -1 1, "
              "determinant 3: the trefoil's)", type);
        check(rod_b && strstr(rod_b, b_knot), "rod b's knot in the JSON: unknot (Alexander 1, "
              "determinant 1, signature 0, no change)");
        const char *line_a = strstr(said, "rod a:"), *line_b = strstr(said, "rod b:");
        const char *knot_a = line_a ? strstr(line_a, "knot: trefoil") : NULL;
        const char *knot_b = line_b ? strstr(line_b, "knot: unknot") : NULL;
        check(knot_a && line_b && knot_a < line_b && knot_b, "the text names rod a's knot "
              "trefoil and rod b's unknot under each rod");
    }
    free(json);
    free(alone);
    free(said);
}

/* The two ropes of two.ini, rod b cut at 0.2 s at s = 0.1 m: its root's
 * side (the shorter, 0.1 m) goes */
static void check_cut(const char *dir)
{
    char path[512], cmd[2048];
    snprintf(path, sizeof path, "%s/cut.ini", dir);
    write_text(path, "[rod a]\n" ROPE "origin = -0.15 0 0.01\n[ends a]\nroot = free\ntip = free\n"
                     "[rod b]\n" ROPE "origin = -0.15 1 0.01\n[ends b]\nroot = free\ntip = free\n"
                     SHARED "[cut]\nrod = b\nt = 0.2\ns = 0.1\n");
    snprintf(cmd, sizeof cmd, "%s run %s --no-video --csv %s/cut.csv --summary %s/cut.json > "
             "%s/cut.txt", RODSIM_BIN, path, dir, dir, dir);
    int status = system(cmd);
    check(status == 0, "two rods, rod b cut: exit 0 (status %d)", status);
    snprintf(path, sizeof path, "%s/cut.json", dir);
    char *json = read_all(path);
    snprintf(path, sizeof path, "%s/cut.csv", dir);
    char *csv = read_all(path);
    snprintf(path, sizeof path, "%s/cut.txt", dir);
    char *said = read_all(path);
    if (!json || !csv || !said) {
        check(0, "the cut run's outputs are readable");
    } else {
        const char *cut = strstr(json, "\"cuts\":[{\"rod\":\"b\",\"t\":");
        double t = NAN, s = NAN, removed = NAN;
        if (cut) sscanf(cut + 24, "%lf,\"s\":%lf,\"removed\":%lf", &t, &s, &removed);
        check(cut && fabs(t - 0.2) < 1e-9 && fabs(s - 0.1) < 1e-12 && fabs(removed - 0.1) < 1e-12,
              "the summary's cut names rod b: t = %.9g s, s = %.9g m, removed %.9g m (0.2, 0.1, "
              "0.1: node 10, the root's side)", t, s, removed);
        check(strstr(json, "{\"name\":\"a\",\"nodes\":31,") &&
                  strstr(json, "{\"name\":\"b\",\"nodes\":21,"),
              "rods[]: a whole (31 nodes), b the thread left (21)");
        /* the last frame's rows of rod b: nodes 10 .. 30 of the uncut rod */
        const char *last = strrchr(csv, '\n');
        while (last > csv && last[-1] != '\n') last--; /* the last row */
        double t_last;
        sscanf(last, "%lf", &t_last);
        int rows_b = 0, first = -1;
        for (const char *p = strchr(csv, '\n') + 1; *p; p = strchr(p, '\n') + 1) {
            double tr;
            char rod[32];
            int node;
            if (sscanf(p, "%lf,%31[^,],%d,", &tr, rod, &node) == 3 && tr == t_last &&
                strcmp(rod, "b") == 0) {
                if (first < 0) first = node;
                rows_b++;
            }
        }
        check(rows_b == 21 && first == 10, "the CSV's last frame: %d rows of rod b from node %d "
              "(21 from node 10)", rows_b, first);
        const char *rod_b = strstr(said, "rod b:");
        check(rod_b && strstr(rod_b, "cut by the scene's [cut]: at t = 0.2 s, rod b at s = 0.1 m, "
                              "0.1 m taken away from its root's side"),
              "the text tells the cut under rod b");
    }
    free(json);
    free(csv);
    free(said);
}

int main(void)
{
    char dir[] = "/tmp/rodsim_rodsXXXXXX", path[512], cmd[2048];
    if (!mkdtemp(dir)) return check(0, "mkdtemp"), test_finish();
    snprintf(path, sizeof path, "%s/two.ini", dir);
    write_text(path, "[rod a]\n" ROPE "origin = -0.15 0 0.01\n[ends a]\nroot = free\ntip = free\n"
                     "[rod b]\n" ROPE "origin = -0.15 1 0.01\n[ends b]\nroot = free\ntip = free\n"
                     SHARED);
    snprintf(path, sizeof path, "%s/one.ini", dir);
    write_text(path, "[rod]\n" ROPE "origin = -0.15 0 0.01\n[ends]\nroot = free\ntip = free\n" SHARED);
    snprintf(cmd, sizeof cmd,
             "%s run %s/two.ini --no-video --quiet --csv %s/two.csv --summary %s/two.json && "
             "%s run %s/one.ini --no-video --quiet --csv %s/one.csv",
             RODSIM_BIN, dir, dir, dir, RODSIM_BIN, dir, dir);
    int status = system(cmd);
    check(status == 0, "rodsim run of two rods and of one exit 0 (status %d)", status);
    snprintf(path, sizeof path, "%s/two.csv", dir);
    char *two = read_all(path);
    snprintf(path, sizeof path, "%s/one.csv", dir);
    char *one = read_all(path);
    snprintf(path, sizeof path, "%s/two.json", dir);
    char *json = read_all(path);
    if (two && one && json) {
        check(strncmp(two, "t,rod,node,s,x,y,z,", 19) == 0, "two rods: the CSV's header has "
              "the column rod after t");
        check(strncmp(one, "t,node,s,x,y,z,", 15) == 0, "one rod: no column rod");
        const double da = csv_difference(two, one, "a", 0.0);
        const double db = csv_difference(two, one, "b", 1.0);
        check(da >= 0.0 && da <= 1e-12, "rod a's rows against the rope alone: largest "
              "difference %.3g (every column after node; round-off: <= 1e-12)", da);
        check(db >= 0.0 && db <= 1e-12, "rod b's rows (1 m away, y less 1 m) against the rope "
              "alone: largest difference %.3g", db);
        check(strstr(json, "\"rods\":[{\"name\":\"a\",\"nodes\":31,") &&
                  strstr(json, "{\"name\":\"b\",\"nodes\":31,") &&
                  strstr(json, "\"contact_force\":[0,0,0]"),
              "the summary lists rods a and b, no contact force between them");
    } else {
        check(0, "the outputs are readable");
    }
    free(two);
    free(one);
    free(json);
    check_knots(dir);
    check_cut(dir);
    /* a bad key of a named rod is reported at its line, with the rod's section */
    snprintf(path, sizeof path, "%s/bad.ini", dir);
    write_text(path, "[rod a]\n" ROPE "origin = 0 0 0.01\n[rod b]\n" ROPE "origin = 0 1 0.01\n"
                     "nodes_typo = 3\n" SHARED);
    snprintf(cmd, sizeof cmd, "%s run %s --no-video > %s/bad.txt 2>&1", RODSIM_BIN, path, dir);
    status = system(cmd);
    snprintf(path, sizeof path, "%s/bad.txt", dir);
    char *said = read_all(path);
    check(WIFEXITED(status) && WEXITSTATUS(status) == 2 && said &&
              strstr(said, "bad.ini:21: [rod b] nodes_typo: unknown key"),
          "an unknown key of [rod b]: exit 2 naming line and section (%s)", said ? said : "");
    free(said);
    test_remove_tree(dir);
    return test_finish();
}
