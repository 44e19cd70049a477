/* path.h: a driven end's path (scene [ends] root_motion and
 * tip_motion): rows t, x, y, z [, rx, ry, rz] from a CSV table, interpolated
 * so that position and rotation have continuous velocity and acceleration,
 * held after the last row (and before the first). The first row is the end's
 * starting position; the rotation vector (rad) is the end's rotation from its
 * initial frame, global components. */
#ifndef RODSIM_PATH_H
#define RODSIM_PATH_H

#include <stddef.h>

#include "sim/rod.h"
#include "sim/rod_types.h"

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
 * 1 to 1e6 rows (one row: a constant pose). The motion stays in range, so
 * that every pose rod_path_eval() gives is finite: values within 1e12 (m,
 * rad) and, between rows, velocities and accelerations within 1e50 (per s,
 * per s^2; rows 1 m apart 1e-300 s apart are refused). NULL with a message
 * naming the row (1-based) and what is accepted. */
rod_path *rod_path_create(const double *data, int rows, int columns, char *err, size_t errlen);

/* A path whose velocity is given at every row: rows of the pose columns
 * (`columns` 4 or 7, as above), then their rates (vx, vy, vz m/s and, with
 * 7 columns, vrx, vry, vrz, the rotation vector's rate, rad/s): 7 or 13
 * numbers a row. Each interval is the cubic Hermite polynomial through its
 * rows' positions and velocities (velocity continuous, acceleration steps at
 * the rows); held at rest before the first and after the last row, the
 * given velocity exactly at a row. In range as above (given velocities
 * within 1e50). NULL with a message naming the row. */
rod_path *rod_path_create_with_velocity(const double *data, int rows, int columns, char *err,
                                        size_t errlen);

/* A live path (rodsim live): starts with one row `first_row` (t, x, y, z
 * [, rx, ry, rz]; `columns` 4 or 7) at rest; rod_path_push() appends rows as
 * they arrive, each with the velocity of the backward three-point difference
 * through it and the two rows before (a first difference at the second row),
 * and evaluates as rod_path_create_with_velocity() would on the same rows
 * and velocities. Causal: a pushed row and its velocity never change, so a
 * record of them replays exactly. Keeps the last 4 rows: evaluate it only at
 * times from the third-newest row on. No allocation after create. */
rod_path *rod_path_create_live(int columns, const double *first_row, char *err, size_t errlen);
/* Appends `row` (columns numbers, t first) to a live path and writes its
 * velocity (columns - 1 numbers) to `velocity` (may be NULL). Returns 0, or
 * -1 with a message when a number is not finite or t does not increase. */
int rod_path_push(rod_path *p, const double *row, double *velocity, char *err, size_t errlen);
/* rod_path_push with the row's velocity given (columns - 1 numbers, m/s
 * and rad/s) instead of the backward difference: rodsim live holds an end
 * with zero. The rows after it take their differences as usual. */
int rod_path_push_with_velocity(rod_path *p, const double *row, const double *velocity,
                                char *err, size_t errlen);
/* Removes a live path's newest row (the step to it failed); the first row stays. */
void rod_path_pop(rod_path *p);
/* A live path's rows as numbers, to save and restore it exactly: at most
 * ROD_PATH_LIVE_NUMBERS doubles (its row count, then per row t, the pose,
 * its velocity). rod_path_live_save writes them into out and returns how
 * many; rod_path_live_restore reads them back into a live path of the same
 * columns: 0, or -1 when they are not such a path's. No allocation. */
#define ROD_PATH_LIVE_NUMBERS (1 + 4 * 13)
int rod_path_live_save(const rod_path *p, double *out);
int rod_path_live_restore(rod_path *p, const double *in, int count);
/* 1 when the path's velocity is given (with velocity, or live). */
int rod_path_has_velocity(const rod_path *p);

/* Reads a CSV file with the header t,x,y,z or t,x,y,z,rx,ry,rz, or, with
 * velocities given (rod_path_create_with_velocity: a rodsim live record),
 * t,x,y,z,vx,vy,vz or t,x,y,z,rx,ry,rz,vx,vy,vz,vrx,vry,vrz. The file is a
 * text file of at most 512 MiB (base/textfile.h: a device, a directory or a
 * larger file is refused unread). NULL with a message naming file:line and
 * what is accepted. */
rod_path *rod_path_load(const char *filename, char *err, size_t errlen);
/* The same from the file's text held in memory (NUL-terminated); `filename`
 * names it in messages. */
rod_path *rod_path_parse(const char *filename, const char *text, char *err, size_t errlen);

void rod_path_destroy(rod_path *p);

/* Moves every row's position by shift (m, global); rotations unchanged. */
void rod_path_translate(rod_path *p, const double shift[3]);

/* 4 or 7. */
int rod_path_columns(const rod_path *p);
/* The first and last row's time, s. */
double rod_path_start(const rod_path *p);
double rod_path_end(const rod_path *p);

/* 1 when every row has z = 0 (and rx = ry = 0): the end stays in the x-y
 * plane turning about z only (rod_model_loads_planar). */
int rod_path_planar(const rod_path *p);

/* A copy of the path (its own rows); NULL when out of memory. */
rod_path *rod_path_copy(const rod_path *p);

/* A path handed over at time `at` (s): `before`'s poses before it, then
 * `after` carrying the pose before had at `at` rigidly, as `after` held it
 * then (the needle handed from one instrument's jaws to another's: its pose
 * continuous at `at`, its velocity that of the new jaws). Both paths of 7
 * columns, `at` after before's start. Takes both (destroyed with it; on
 * failure the caller keeps them); NULL with a message. Chains: `before`
 * may itself be handed over. */
rod_path *rod_path_handover(rod_path *before, double at, rod_path *after, char *err,
                            size_t errlen);

/* The pose at time t (any t: held before the first and after the last row). */
void rod_path_eval(const rod_path *p, double t, rod_pose *pose);

#endif
