/* fuzz_shape.c: libFuzzer harness for starting shapes ([rod] shape =
 * FILE.csv): scene_parse_shape (sim/scene.c), the parser of the text that
 * the scene's file reader (base/textfile.c) hands it. Checks its contract
 * (scene.h): on failure a message naming the file and nothing owned; on
 * success 2 to 1e6 finite points, no point repeating the one before, the
 * last point's line after the header's. */
#include <math.h>

#include "fuzz.h"
#include "sim/scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char name[] = "fuzz_shape.csv";
    char *text = fuzz_text(data, size);
    char err[1024] = "";
    double *points = (double *)&err; /* not NULL: the parser must set it */
    int count = -1, last_line = 0;
    if (scene_parse_shape(name, text, &points, &count, &last_line, err, sizeof err) != 0) {
        fuzz_require(fuzz_starts(err, name), "a shape message names the file", err);
        fuzz_require(points == NULL && count == 0, "a failed read owns nothing", err);
        free(text);
        return 0;
    }
    fuzz_require(points != NULL && count >= 2 && count <= 1000000, "2 to 1e6 points", NULL);
    fuzz_require(last_line >= count + 1, "the last point's line follows the header and the rows",
                 NULL);
    double polyline = 0.0;
    for (int i = 0; i < count; i++) {
        const double *p = &points[3 * i];
        fuzz_require(isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]), "every point is finite",
                     NULL);
        if (i > 0) {
            const double *q = p - 3;
            fuzz_require(p[0] != q[0] || p[1] != q[1] || p[2] != q[2],
                         "no point repeats the one before", NULL);
            polyline += hypot(hypot(p[0] - q[0], p[1] - q[1]), p[2] - q[2]);
        }
    }
    fuzz_require(!isnan(polyline), "the polyline's length is a number (inf when it overflows)",
                 NULL);
    free(points);
    free(text);
    return 0;
}
