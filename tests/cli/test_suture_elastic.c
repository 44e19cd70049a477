/* test_suture_elastic.c: scenes/suture_elastic.ini's first bite goes into
 * the elastic skin as it sits. Held at its sides and stretched 30 % across
 * the wound, the pad's top sinks some 4.6 mm under the plane z = 0 of its
 * box; the needle's path (suture_elastic_path.py) is made for that sunken
 * top. Through the real binary, over the first bite (0 to 4.8 s):
 *  - the run ends without warnings, with four punctures: the entry before
 *    the wound (y < 0), the exit beyond it, and one in each wall of the
 *    gaping wound, where the needle crosses its opening;
 *  - every puncture lies on the needle's circle (radius RN = 5 mm, centred
 *    RN - D over the top at the holes, D = 3 mm the bite's depth), within
 *    0.3 mm, at the bite's x = -12 mm within 0.5 mm;
 *  - the two holes in the skin lie on the pad's top as the run's own
 *    --tissue-csv gives it at t = 0 (the top-face nodes, interpolated by
 *    this file: inverse-distance weights of the nodes within 8 mm), within
 *    0.1 mm, not on the box's top (over 4 mm below z = 0), at |y| =
 *    sqrt(RN^2 - (RN - D)^2) = sqrt(21) mm within 0.5 mm;
 *  - the thread's lowest point between the holes (the --csv at 4.8 s) is D
 *    under the top at the wound, within 0.5 mm. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"
#include "test.h"
#include "test_csv.h"
#include "test_process.h"

#define RN 0.005      /* m: the needle's radius */
#define DEPTH 0.003   /* m: the bite's depth under the skin */
#define BITE_X -0.012 /* m: the first bite's place along the wound */
#define NODES 81
#define T_END 4.8 /* s: the first bite made and pulled half out */

/* The pad's top z at (x, y) from the --tissue-csv rows at t = 0 (text):
 * inverse-distance-squared weights of the top nodes within 8 mm */
static double top_z(const char *text, double x, double y)
{
    double wsum = 0.0, zsum = 0.0;
    char cell[64];
    for (int row = 1; csv_cell(text, row, 0, cell, sizeof cell) == 0; row++) {
        if (atof(cell) != 0.0) break; /* the first frame only */
        double p[3];
        for (int c = 0; c < 3; c++) {
            csv_cell(text, row, 2 + c, cell, sizeof cell);
            p[c] = atof(cell);
        }
        const double d2 = (p[0] - x) * (p[0] - x) + (p[1] - y) * (p[1] - y);
        if (d2 > 0.008 * 0.008) continue;
        const double w = 1.0 / (d2 + 1e-12);
        wsum += w;
        zsum += w * p[2];
    }
    return wsum > 0.0 ? zsum / wsum : NAN;
}

/* The thread's lowest z between the holes (|y| < the hole's) at the last
 * frame of the --csv text */
static double lowest_between(const char *text, double hole_y)
{
    char cell[64];
    int rows = 0;
    while (csv_cell(text, rows + 1, 0, cell, sizeof cell) == 0 && cell[0]) rows++;
    double low = INFINITY;
    for (int row = rows - NODES + 1; row <= rows; row++) {
        double p[3];
        for (int c = 0; c < 3; c++) {
            csv_cell(text, row, 3 + c, cell, sizeof cell);
            p[c] = atof(cell);
        }
        if (fabs(p[0] - BITE_X) < 0.003 && fabs(p[1]) < hole_y) low = fmin(low, p[2]);
    }
    return low;
}

int main(void)
{
    const char *csv = test_path("suture_elastic.csv"),
               *pad = test_path("suture_elastic_pad.csv"),
               *summary = test_path("suture_elastic.json");
    char duration[64];
    snprintf(duration, sizeof duration, "solver.duration=%g", T_END);
    const char *args[] = {"run", "scenes/suture_elastic.ini", "--no-video", "--quiet", "--csv", csv,
                          "--tissue-csv", pad, "--summary", summary, "--set", duration,
                          "--set", "render.fps=5", NULL}; /* 5 frames a second: the CSVs small */
    char output[16384];
    int status = test_run_rodsim(args, output, sizeof output);
    check(status == 0, "suture_elastic.ini to %g s: the run completes (exit %d)", T_END, status);
    char *json_text = read_text(summary), *pad_text = read_text(pad), *csv_text = read_text(csv);
    char err[256] = "";
    json_value *v = json_text ? json_parse(json_text, err, sizeof err) : NULL;
    if (check(v && pad_text && csv_text, "summary, --tissue-csv and --csv read (%s)", err)) {
        const json_value *warnings = json_get(v, "warnings"), *p = json_get(v, "punctures");
        check(json_is(warnings, JSON_ARRAY) && warnings->count == 0, "no warnings (%d)",
              warnings ? warnings->count : -1);
        const double hole = sqrt(RN * RN - (RN - DEPTH) * (RN - DEPTH));
        /* the needle's circle: centred RN - DEPTH over the mean top at the holes */
        const double zc = 0.5 * (top_z(pad_text, BITE_X, -hole) + top_z(pad_text, BITE_X, hole)) +
                          (RN - DEPTH);
        int count = json_is(p, JSON_ARRAY) ? p->count : -1, skin = 0, wall = 0;
        check(count == 4, "four punctures: the two holes in the skin, one in each wall of the "
              "open wound (%d)", count);
        for (int k = 0; k < count; k++) {
            const json_value *point = json_get(p->items[k], "point");
            const json_value *force = json_get(p->items[k], "force");
            if (!check(json_is_numbers(point, 3) && json_is_numbers(force, 3), "puncture %d read", k))
                continue;
            const double x = point->items[0]->number, y = point->items[1]->number,
                         z = point->items[2]->number;
            const double f = sqrt(force->items[0]->number * force->items[0]->number +
                                  force->items[1]->number * force->items[1]->number +
                                  force->items[2]->number * force->items[2]->number);
            const double top = top_z(pad_text, x, y);
            printf("  puncture %d at (%.5f, %.5f, %.5f) m, %.2f mm under the top, force on the "
                   "skin %.4g N\n", k, x, y, z, 1e3 * (top - z), f);
            check_abs("puncture along the wound, x (m)", x, BITE_X, 5e-4);
            check_abs("puncture on the needle's circle: its distance from the centre (m)",
                      sqrt(y * y + (z - zc) * (z - zc)), RN, 3e-4);
            if (fabs(y) > 0.003) { /* a hole in the skin */
                skin += y < 0.0 ? 1 : 2;
                check_abs("hole on the pad's settled top, z (m)", z, top, 1e-4);
                check(z < -0.004, "hole %d under the box's top: z %.5f m below -0.004", k, z);
                check_abs("hole across the wound, |y| (m)", fabs(y), hole, 5e-4);
            } else {
                wall += y < 0.0 ? 1 : 2;
            }
        }
        check(skin == 3 && wall == 3, "the entry before the wound (y < 0), the exit beyond it, "
              "a hole in each of the wound's walls (%d, %d; 3, 3 expected)", skin, wall);
        const double depth = top_z(pad_text, BITE_X, 0.0) - lowest_between(csv_text, hole);
        check_abs("the bite's depth under the skin at the wound (m)", depth, DEPTH, 5e-4);
    }
    json_free(v);
    free(json_text);
    free(pad_text);
    free(csv_text);
    remove(csv);
    remove(pad);
    remove(summary);
    return test_finish();
}
