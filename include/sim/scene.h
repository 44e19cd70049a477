/* scene.h: a rod scene (INI; every key: `rodsim help scene`) read into a rod_model.
 *
 * The keys are the portable core keys of every rod scene plus the options of rod.h:
 *   [rod]     length, diameter, density, youngs_modulus, shear_modulus, nodes (all required),
 *             rotary_inertia_scale, origin, direction, shape, curvature, initial_velocity
 *   [solver]  scheme, dt, duration, theta, newton_tolerance, newton_max_iterations,
 *             exact_rotation
 *   [tip]     frame, force, moment, profile
 *   [loads]   gravity, distributed_force, linear_damping, angular_damping, distributed_moment
 *   [point_load] (repeatable) s, force, moment
 *   [ends]    root, tip, root_motion, tip_motion, root_slide, tip_slide, needle
 *   [physics] twist, rotary_inertia, gravity, damping, planar
 * Files named by the scene (profile table, shape, motion paths) are relative
 * to the scene file's folder unless absolute.
 * Every bad value is reported as "file:line: [section] key = value: what is accepted"
 * (ini_error), and nothing is half-filled on failure.
 */
#ifndef RODSIM_SCENE_H
#define RODSIM_SCENE_H

#include <stddef.h>

#include "base/ini.h"
#include "sim/rod.h"
#include "sim/rod_types.h"

/* Fills *m from the scene (starting from rod_model_default()), loads the
 * profile table, the starting shape (resampled to nodes exactly ds apart
 * along its polyline) and the motion paths the scene names, and calls
 * rod_model_derive() (its messages about the ends' and the start's inputs are reported at
 * the key's line). Returns 0, or -1 with a message in err; on
 * failure *m owns nothing. On success release with rod_model_release().
 * Marks every key it reads as known; the caller runs ini_check_unused()
 * after reading the sections it owns itself (e.g. [render]). */
int scene_read_rod(ini_doc *doc, rod_model *m, char *err, size_t errlen);

/* The same for a rod of several (sim/rod_set.h): `rod` its NAME (the
 * [puncture]s with rod = NAME and those naming no rod are its; NULL: the
 * scene's single rod, which refuses a [puncture] rod key) and `share`
 * another rod of the scene already read (NULL: none), whose elastic pad
 * this one shares (rod_surface.solid_shared) instead of making its own. */
int scene_read_rod_of(ini_doc *doc, rod_model *m, const char *rod, const rod_model *share,
                      char *err, size_t errlen);

/* -1 with a message saying to use `rodsim fem` when doc is a beam (FEM) scene
 * (beam sections and no [rod]); 0 otherwise. */
int scene_refuse_beam(ini_doc *doc, char *err, size_t errlen);

/* Reads a load table (CSV): one header line, then rows of 2 numbers
 * (t s, factor) or 7 numbers (t s, fx fy fz N, mx my mz N m), separated by
 * commas; blank lines and '#' comments are skipped; times strictly increase.
 * The file is a text file of at most 256 MiB (base/textfile.h: a device, a
 * directory or a larger file is refused unread). Fills *table (data owned by
 * the caller: free(table->data)). Returns 0, or -1 with "path:..." in err and
 * *table empty. An empty table is an error. */
int scene_load_table(const char *path, rod_table *table, char *err, size_t errlen);
/* The same from the file's text held in memory (NUL-terminated); `path`
 * names it in messages. */
int scene_parse_table(const char *path, const char *text, rod_table *table, char *err,
                      size_t errlen);

/* Reads a starting shape ([rod] shape = FILE.csv) from its text held in
 * memory: the header x,y,z, then rows of 3 finite numbers (m), no point
 * repeating the one before, 2 to 1e6 points; blank lines and '#' comments
 * skipped. Fills *points (count x 3, m, owned by the caller: free) and
 * *last_line (the line of the last point). Returns 0, or -1 with
 * "path:line: ..." in err and *points NULL. The scene reads the file (a text
 * file of at most 128 MiB) and checks its length against [rod] length. */
int scene_parse_shape(const char *path, const char *text, double **points, int *count,
                      int *last_line, char *err, size_t errlen);

#endif
