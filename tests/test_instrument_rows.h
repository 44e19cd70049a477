/* test_instrument_rows.h: an instrument made from rows in a test, and the
 * rotation vector of a frame (tests/sim/test_instrument.c,
 * tests/sim/test_grid_instrument.c). */
#ifndef RODSIM_TEST_INSTRUMENT_ROWS_H
#define RODSIM_TEST_INSTRUMENT_ROWS_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"
#include "sim/instrument.h"
#include "sim/path.h"

/* An instrument from rows (t, x, y, z, rx, ry, rz, jaw); NULL paths on failure. */
static inline rod_instrument instrument(rod_instrument_kind kind, double size, const double *rows,
                                        int count, double friction, double grip)
{
    rod_instrument in;
    memset(&in, 0, sizeof in);
    in.kind = kind;
    snprintf(in.name, sizeof in.name, "%s", rod_instrument_kind_name(kind));
    in.size = size;
    in.friction = friction;
    in.grip = grip;
    double *pose = malloc((size_t)count * 7 * sizeof(double));
    double *jaw = malloc((size_t)count * 7 * sizeof(double));
    for (int r = 0; pose && jaw && r < count; r++) {
        memcpy(&pose[7 * r], &rows[8 * r], 7 * sizeof(double));
        const double o[7] = {rows[8 * r], rows[8 * r + 7], 0.0, 0.0, 0.0, 0.0, 0.0};
        memcpy(&jaw[7 * r], o, sizeof o);
    }
    char err[256];
    if (pose && jaw) {
        in.pose = rod_path_create(pose, count, 7, err, sizeof err);
        in.jaw = rod_instrument_jaw_path(jaw, count, err, sizeof err);
    }
    free(pose);
    free(jaw);
    return in;
}

/* The rotation vector of the rotation whose columns are a, b, c. */
static inline void rotation_vector(const double a[3], const double b[3], const double c[3],
                                   double rv[3])
{
    double r[9];
    for (int i = 0; i < 3; i++) {
        r[3 * i] = a[i];
        r[3 * i + 1] = b[i];
        r[3 * i + 2] = c[i];
    }
    m3_log(rv, r);
}

#endif
