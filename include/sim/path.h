/* path.h: a driven end's path (issue 10; scene [ends] root_motion and
 * tip_motion): rows t, x, y, z [, rx, ry, rz] from a CSV table, interpolated
 * so that position and rotation have continuous velocity and acceleration,
 * held after the last row (and before the first). The first row is the end's
 * starting position; the rotation vector (rad) is the end's rotation from its
 * initial frame, global components. */
#ifndef RODSIM_PATH_H
#define RODSIM_PATH_H

#include <stddef.h>

#include "sim/rod.h"

/* The pose of a driven end at one time, global components. */
typedef struct rod_pose {
    double position[3];             /* m */
    double velocity[3];             /* m/s */
    double acceleration[3];         /* m/s^2 */
    double rotation[9];             /* row-major 3x3: the rotation from the end's initial
                                       frame (identity for a 4-column path) */
    double angular_velocity[3];     /* rad/s, global */
    double angular_acceleration[3]; /* rad/s^2, global */
} rod_pose;

/* A path from `rows` rows of (t, x, y, z) or (t, x, y, z, rx, ry, rz):
 * `columns` 4 or 7, data row-major. Times strictly increase, values finite;
 * 1 to 1e6 rows (one row: a constant pose). NULL with a message naming the
 * row (1-based) and what is accepted. */
rod_path *rod_path_create(const double *data, int rows, int columns, char *err, size_t errlen);

/* Reads a CSV file with the header t,x,y,z or t,x,y,z,rx,ry,rz. NULL with a
 * message naming file:line and what is accepted. */
rod_path *rod_path_load(const char *filename, char *err, size_t errlen);

void rod_path_destroy(rod_path *p);

/* 4 or 7. */
int rod_path_columns(const rod_path *p);
/* The first and last row's time, s. */
double rod_path_start(const rod_path *p);
double rod_path_end(const rod_path *p);

/* 1 when every row has z = 0 (and rx = ry = 0): the end stays in the x-y
 * plane turning about z only (rod_model_loads_planar). */
int rod_path_planar(const rod_path *p);

/* The pose at time t (any t: held before the first and after the last row). */
void rod_path_eval(const rod_path *p, double t, rod_pose *pose);

#endif
