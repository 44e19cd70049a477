/* test_readme_figures.c: figures the README prints from a command are what
 * the command prints now. The study's table (overhand_tight.ini's rope in
 * the knot against rod.friction, one decimal: within 0.05 d) at frictions
 * 0.05, 0.2 and 0.6, each a run of about 0.5 s of CPU; and the accuracy
 * table's static tip_load_small errors at NS 11, 51, 201 (three significant
 * digits: within 0.5 %). The README's numbers are read from the README
 * itself, so a stale table fails here. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test.h"
#include "test_process.h"

#define README RODSIM_SOURCE_DIR "/README.md"

static char readme[65536];
static char output[1 << 16];

/* The cells of the Markdown row that starts with `start`: up to n numbers
 * after its first cell. Returns how many were read. */
static int row_numbers(const char *start, double *values, int n)
{
    const char *row = strstr(readme, start);
    if (!row) return 0;
    const char *end = strchr(row, '\n');
    const char *c = strchr(row + 1, '|'); /* past the first cell */
    int k = 0;
    while (c && (!end || c < end) && k < n) {
        char *after;
        double v = strtod(c + 1, &after);
        if (after != c + 1) values[k++] = v;
        c = strchr(c + 1, '|');
    }
    return k;
}

/* rope_in_knot_d of overhand_tight.ini's summary at this friction, or -1. */
static double rope_in_knot(double friction)
{
    char set[64];
    snprintf(set, sizeof set, "rod.friction=%g", friction);
    const char *args[] = {"run", RODSIM_SOURCE_DIR "/scenes/overhand_tight.ini", "--no-video",
                          "--quiet", "--set", set, "--summary", "-", NULL};
    if (test_run_rodsim(args, output, sizeof output) != 0) return -1;
    const char *at = strstr(output, "\"rope_in_knot_d\":");
    return at ? strtod(at + strlen("\"rope_in_knot_d\":"), NULL) : -1;
}

/* The relative error of validate's static tip_load_small row at NS, or -1. */
static double tip_load_error(const char *nodes)
{
    const char *args[] = {"validate", "--case", "tip_load_small", "--scheme", "static",
                          "--nodes", nodes, "--csv", "-", NULL};
    if (test_run_rodsim(args, output, sizeof output) != 0) return -1;
    const char *row = strstr(output, "\ntip_load_small,static,");
    if (!row) return -1;
    const char *c = row + 1;
    for (int i = 0; i < 6 && c; i++) c = strchr(c, ',') ? strchr(c, ',') + 1 : NULL;
    return c ? strtod(c, NULL) : -1;
}

int main(void)
{
    FILE *f = fopen(README, "rb");
    size_t got = f ? fread(readme, 1, sizeof readme - 1, f) : 0;
    readme[got] = '\0';
    if (f) fclose(f);

    double friction[8], rope[8];
    int nf = row_numbers("| rod.friction |", friction, 8);
    int nr = row_numbers("| rope in the knot (d) |", rope, 8);
    if (check(nf == 8 && nr == 8, "README's knot table: %d frictions, %d ropes (want 8, 8)", nf,
              nr)) {
        const int columns[] = {0, 3, 7}; /* 0.05, 0.2, 0.6 */
        for (int i = 0; i < 3; i++) {
            int k = columns[i];
            char what[96];
            snprintf(what, sizeof what, "overhand_tight.ini, friction %g: rope in the knot (d)",
                     friction[k]);
            check_abs(what, rope_in_knot(friction[k]), rope[k], 0.05);
        }
    }

    double errors[4];
    int ne = row_numbers("| tip_load_small (dead 4.5e-7 N", errors, 4);
    if (check(ne == 4, "README's accuracy row tip_load_small: %d numbers (want NS 11, 51, 201, "
              "order)", ne)) {
        const char *nodes[] = {"11", "51", "201"};
        for (int i = 0; i < 3; i++) {
            char what[96];
            snprintf(what, sizeof what, "validate tip_load_small static NS %s: relative error",
                     nodes[i]);
            check_rel(what, tip_load_error(nodes[i]), errors[i], 5e-3);
        }
    }
    return test_finish();
}
