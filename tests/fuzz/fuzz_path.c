/* fuzz_path.c: libFuzzer harness for driven-end paths ([ends] root_motion,
 * tip_motion; a rodsim live record): rod_path_parse (sim/path.c), the parser
 * of the text that the file reader (base/textfile.c) hands it, then the
 * interpolant. Checks the contract (path.h): on failure a message naming the
 * file; on success 4 or 7 columns, a start not after the end, and a finite
 * pose (position, velocity, acceleration, rotation, angular velocity and
 * acceleration) at every row, between rows, before the first and after the
 * last. */
#include <math.h>

#include "fuzz.h"
#include "sim/path.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int finite_n(const double *v, int n)
{
    for (int k = 0; k < n; k++)
        if (!isfinite(v[k])) return 0;
    return 1;
}

static void check_pose(const rod_path *p, double t)
{
    rod_pose pose;
    rod_path_eval(p, t, &pose);
    char at[64];
    snprintf(at, sizeof at, "t = %.17g s", t);
    fuzz_require(finite_n(pose.position, 3) && finite_n(pose.velocity, 3) &&
                     finite_n(pose.acceleration, 3),
                 "a finite position, velocity and acceleration", at);
    fuzz_require(finite_n(pose.rotation, 9) && finite_n(pose.angular_velocity, 3) &&
                     finite_n(pose.angular_acceleration, 3),
                 "a finite rotation, angular velocity and acceleration", at);
    /* a rotation: its columns of unit length */
    for (int c = 0; c < 3; c++) {
        const double *R = pose.rotation;
        double n = R[c] * R[c] + R[3 + c] * R[3 + c] + R[6 + c] * R[6 + c];
        fuzz_require(fabs(n - 1.0) < 1e-9, "the rotation's columns are unit vectors", at);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char name[] = "fuzz_path.csv";
    char *text = fuzz_text(data, size);
    char err[1024] = "";
    rod_path *p = rod_path_parse(name, text, err, sizeof err);
    free(text);
    if (!p) {
        fuzz_require(fuzz_starts(err, name), "a path message names the file", err);
        return 0;
    }
    const int columns = rod_path_columns(p);
    const double start = rod_path_start(p), end = rod_path_end(p);
    fuzz_require(columns == 4 || columns == 7, "4 or 7 columns", NULL);
    fuzz_require(isfinite(start) && isfinite(end) && start <= end, "finite start <= end", NULL);
    check_pose(p, start);
    check_pose(p, end);
    check_pose(p, start - 1.0);
    check_pose(p, end + 1.0);
    for (int k = 1; k < 16; k++) check_pose(p, start + (end - start) * k / 16.0);
    rod_path_destroy(p);
    return 0;
}
