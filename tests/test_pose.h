/* test_pose.h: an instrument's pose read from its path file, for tests
 * that measure the thread against the instrument's axes. */
#ifndef RODSIM_TEST_POSE_H
#define RODSIM_TEST_POSE_H

#include <math.h>
#include <stdio.h>

/* The pose at time t from an instrument's path file (t,x,y,z,rx,ry,rz,jaw;
 * the header then rows in time): the first row at or after t; its tip
 * into tip (m), its rotation (columns: local axes; x along the jaws to
 * their tip) into r. 0, or -1 (no such file or row). */
static inline int test_path_pose(const char *path, double t, double tip[3], double r[9])
{
    FILE *f = fopen(path, "r");
    char line[512];
    double v[8] = {0};
    int found = 0;
    if (f && fgets(line, sizeof line, f))
        while (!found && fgets(line, sizeof line, f))
            if (sscanf(line, "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3], &v[4],
                       &v[5], &v[6], &v[7]) == 8 && v[0] >= t - 1e-9)
                found = 1;
    if (f) fclose(f);
    if (!found) return -1;
    for (int c = 0; c < 3; c++) tip[c] = v[1 + c];
    /* Rodrigues: R = I + sin(a) K + (1 - cos(a)) K^2, K the unit axis' cross matrix */
    const double a = sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6]);
    const double k[3] = {a > 0 ? v[4] / a : 0, a > 0 ? v[5] / a : 0, a > 0 ? v[6] / a : 0};
    const double K[9] = {0, -k[2], k[1], k[2], 0, -k[0], -k[1], k[0], 0};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double k2 = 0.0;
            for (int m = 0; m < 3; m++) k2 += K[3 * i + m] * K[3 * m + j];
            r[3 * i + j] = (i == j) + sin(a) * K[3 * i + j] + (1.0 - cos(a)) * k2;
        }
    return 0;
}

#endif
