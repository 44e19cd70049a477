/* rodsim.h: the library's public contract (librodsim.so, pkg-config rodsim).
 *
 * A rod scene (the INI files of `rodsim run`; every key: `rodsim help
 * scene`) loaded into an opaque handle, stepped in time, read as arrays,
 * driven at its ends, saved and restored, and drawn. The step control is
 * `rodsim run`'s: a stretch of time is split into equal steps no longer
 * than the scene's solver.dt, and rodsim_run() goes from output frame to
 * output frame (render.fps), so a scene run here has, bit for bit, the
 * states `rodsim run` steps through (and its --csv prints).
 *
 * Units are SI: m, s, N, N m, rad. Arrays are flat, row-major doubles.
 * Ownership: a handle is made by rodsim_load_* and freed by rodsim_free;
 * every other pointer is the caller's, except those the functions below say
 * are borrowed (valid until the next call that steps, restores or frees the
 * scene). A handle is used by one thread at a time; distinct handles may
 * step in distinct threads at once (rodsim_render draws in one thread at a
 * time: one GL context per process).
 *
 * Several rods: a scene of named rods ([rod NAME]) is stepped as `rodsim
 * run` steps it, all rods together (rodsim_rod_count, rodsim_rod_name; the
 * calls ending in _rod take the rod's index, 0-based in the scene's order).
 * The calls without a rod read and drive the first rod (index 0); a save
 * holds every rod; those that draw or set tip loads take a scene of one
 * rod only (RODSIM_BAD_INPUT, saying so).
 *
 * Errors: every function that can fail returns a rodsim_status; the message
 * for people is rodsim_last_error(scene) (or rodsim_last_error(NULL): the
 * last one of the calling thread, the only one when a load failed). A bad
 * scene gets the message `rodsim run` prints after "rodsim run: ", also a
 * scene whose instruments' paths take one through another (unless
 * instrument.may_overlap = yes) or drive the jaws deeper than
 * instrument.max_depth into a rigid surface.
 */
#ifndef RODSIM_H
#define RODSIM_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The version of this header: a new MINOR adds, a new MAJOR changes or
 * removes (and the library's soname, librodsim.so.MAJOR, follows it). */
#define RODSIM_API_VERSION_MAJOR 1
#define RODSIM_API_VERSION_MINOR 2
#define RODSIM_API_VERSION (RODSIM_API_VERSION_MAJOR * 1000 + RODSIM_API_VERSION_MINOR)

/* The library's version, MAJOR * 1000 + MINOR: compare with
 * RODSIM_API_VERSION (the major must match). */
int rodsim_api_version(void);

typedef enum rodsim_status {
    RODSIM_OK = 0,
    RODSIM_BAD_INPUT = 1,      /* a bad scene, override or argument: the message names it */
    RODSIM_UNSTABLE = 2,       /* the scheme diverged: the message says what would work */
    RODSIM_NO_CONVERGENCE = 3, /* Newton did not converge in a step */
    RODSIM_FAILED = 4          /* out of memory, a file not written, another failure */
} rodsim_status;

/* The ends of the rod: the root at s = 0, the tip at s = L. */
typedef enum rodsim_end { RODSIM_ROOT = 0, RODSIM_TIP = 1 } rodsim_end;

/* What rodsim_get and rodsim_view read; sizes for NS = rodsim_nodes(). */
typedef enum rodsim_field {
    RODSIM_POSITIONS = 0,  /* NS x 3, m, global x y z of the centreline's nodes */
    RODSIM_DIRECTORS = 1,  /* NS x 3 x 3: [i][k][j] = global component j of director
                              d_(k+1) at node i (rows d1, d2, d3; d3 the tangent) */
    RODSIM_VELOCITIES = 2, /* NS x 3, m/s, global */
    RODSIM_FORCES = 3      /* NS x 3, N, global: the internal force N(s) at each node, the
                              CSV's nx,ny,nz */
} rodsim_field;

typedef struct rodsim_scene rodsim_scene;

/* Loading ---------------------------------------------------------------- */

/* Reads the scene file `path`, applies the overrides ("section.key=value",
 * as `rodsim run --set`, in order; count may be 0 and overrides NULL) and
 * makes the scene at t = 0. Files the scene names are relative to its
 * folder. On success *scene is a new handle (free it with rodsim_free);
 * on failure *scene is NULL and rodsim_last_error(NULL) says why. */
rodsim_status rodsim_load_file(const char *path, const char *const *overrides, int count,
                               rodsim_scene **scene);

/* The same from the scene's INI text (NUL-terminated, copied); `name`
 * names it in messages and names its video (NULL: "scene"); files it names
 * are relative to the working directory. */
rodsim_status rodsim_load_text(const char *name, const char *text, const char *const *overrides,
                               int count, rodsim_scene **scene);

/* Frees the handle and everything it made; NULL is allowed. */
void rodsim_free(rodsim_scene *scene);

/* The message of the last failed call on `scene` ("" when none), or with
 * NULL the last failure of the calling thread. Borrowed: valid until the
 * next failing call (on that scene, or on this thread). */
const char *rodsim_last_error(const rodsim_scene *scene);

/* The scene ------------------------------------------------------------- */

int rodsim_nodes(const rodsim_scene *scene);        /* NS; after a cut ([cut], scissors), the
                                                       nodes left */
double rodsim_time(const rodsim_scene *scene);      /* s, of the state */
double rodsim_dt(const rodsim_scene *scene);        /* s, solver.dt (auto resolved) */
double rodsim_duration(const rodsim_scene *scene);  /* s, solver.duration */
double rodsim_frame_rate(const rodsim_scene *scene);/* output frames per simulated s */
double rodsim_length(const rodsim_scene *scene);    /* m, rod.length; after a cut, the length
                                                       left */

/* Stepping -------------------------------------------------------------- */

/* Advances the state by dt (s; dt <= 0: one step of solver.dt) in
 * ceil(dt / solver.dt) equal steps; a time within 1e-9 of a frame interval
 * of an output time k / fps is set to it. On failure (RODSIM_UNSTABLE,
 * RODSIM_NO_CONVERGENCE, RODSIM_FAILED) the scene is as it was before the
 * call and the message is in `rodsim run`'s words. */
rodsim_status rodsim_step(rodsim_scene *scene, double dt);

/* Advances the state to the time `until` (s; until < 0: solver.duration)
 * as `rodsim run` does: each output frame interval 1/fps split into equal
 * steps no longer than solver.dt, the time set to the frame's exactly at
 * its end, a final partial interval to `until`. Nothing when until <= t.
 * On failure, as rodsim_step. */
rodsim_status rodsim_run(rodsim_scene *scene, double until);

/* Reading the state ----------------------------------------------------- */

/* The number of doubles `field` holds (NS x 3 or NS x 9). */
size_t rodsim_field_size(const rodsim_scene *scene, rodsim_field field);

/* Copies `field` into out (count doubles, at least rodsim_field_size). */
rodsim_status rodsim_get(const rodsim_scene *scene, rodsim_field field, double *out,
                         size_t count);

/* The same, borrowed: the scene's own array, valid until the scene steps,
 * is restored or freed (a field other than RODSIM_POSITIONS is refilled at
 * each call for it). NULL for an unknown field. */
const double *rodsim_view(rodsim_scene *scene, rodsim_field field);

/* The force (N) and moment (N m) the rod exerts on what holds `end`
 * (global; a needle holder's force), 0 at a free end. Either may be NULL. */
rodsim_status rodsim_end_load(const rodsim_scene *scene, rodsim_end end, double force[3],
                              double moment[3]);

/* The knot type of the centreline ("unknot", "trefoil", ...) into
 * name (size bytes, NUL-terminated). */
rodsim_status rodsim_knot_type(const rodsim_scene *scene, char *name, size_t size);

/* Driving --------------------------------------------------------------- */

/* Drives a held end (ends.root / ends.tip pinned or clamped) to the pose
 * `position` (m, global) and, for a clamped end, `rotation` (the rotation
 * vector from the end's starting frame, rad; NULL: 0 0 0; a pinned end
 * takes NULL only). The end reaches the pose at the end of the next
 * rodsim_step or rodsim_run, moving along the live path `rodsim live`
 * uses (cubic between poses, velocities from the poses before). The end
 * must not follow a path of the scene (ends.tip_motion). */
rodsim_status rodsim_set_end_pose(rodsim_scene *scene, rodsim_end end, const double position[3],
                                  const double rotation[3]);

/* Sets the loads on a free tip from the next step on, held constant: force
 * (N) and moment (N m) on the scene's tip.frame (director or global);
 * they replace tip.force, tip.moment and tip.profile. NULL: 0 0 0. */
rodsim_status rodsim_set_tip_load(rodsim_scene *scene, const double force[3],
                                  const double moment[3]);

/* Several rods ---------------------------------------------------------- */

/* The rods: 1 for a scene of one bare [rod], else its [rod NAME] sections. */
int rodsim_rod_count(const rodsim_scene *scene);

/* Rod `rod`'s name ("rod" for a bare [rod]); borrowed, valid until the
 * scene is freed. NULL when rod is not 0 .. rodsim_rod_count() - 1. */
const char *rodsim_rod_name(const rodsim_scene *scene, int rod);

/* The index of the rod named `name`, or -1 with the message naming the
 * scene's rods (rodsim_last_error). */
int rodsim_rod_index(const rodsim_scene *scene, const char *name);

/* Rod `rod`'s NS (0 when there is no such rod). */
int rodsim_rod_nodes(const rodsim_scene *scene, int rod);

/* rodsim_get of rod `rod` (count at least its NS x 3, or NS x 9). */
rodsim_status rodsim_get_rod(const rodsim_scene *scene, int rod, rodsim_field field, double *out,
                             size_t count);

/* Rod `rod`'s nodes' arc lengths from its root, s_i (m, at rest; NS
 * doubles into out, count at least its NS): i L / (NS - 1) on a uniform
 * grid; on a graded grid (rod.refine: the segments `factor` times shorter
 * inside its intervals) the sums of the segments' rest lengths, not i
 * times a spacing. The s of `rodsim run`'s CSV; after a cut, the nodes
 * left keep the uncut thread's s. (Version 1.2.) */
rodsim_status rodsim_node_arc(const rodsim_scene *scene, int rod, double *out, size_t count);

/* rodsim_end_load of rod `rod`'s end. */
rodsim_status rodsim_end_load_rod(const rodsim_scene *scene, int rod, rodsim_end end,
                                  double force[3], double moment[3]);

/* rodsim_set_end_pose of rod `rod`'s held end. With several rods, the first
 * pose of an end starts the rods' scheme afresh (as a save does for one):
 * a contact reaction the earlier rod would take at its next step is
 * dropped. */
rodsim_status rodsim_set_end_pose_rod(rodsim_scene *scene, int rod, rodsim_end end,
                                      const double position[3], const double rotation[3]);

/* Saving ---------------------------------------------------------------- */

/* The bytes a saved state of this scene takes. */
size_t rodsim_state_size(const rodsim_scene *scene);

/* Writes the state (and the driven ends' paths, the loads set) into blob
 * (size bytes, the caller's; at least rodsim_state_size). The scheme starts
 * afresh after it (the implicit scheme rebuilds its Jacobian), as after
 * rodsim_restore, so stepping after a save and after its restore agree bit
 * for bit. */
rodsim_status rodsim_save(rodsim_scene *scene, void *blob, size_t size);

/* Puts the scene back into a state saved from a scene of the same file
 * and overrides. RODSIM_BAD_INPUT for a blob of another size or scene. */
rodsim_status rodsim_restore(rodsim_scene *scene, const void *blob, size_t size);

/* Drawing --------------------------------------------------------------- */

/* Writes the frames recorded so far (t = 0 and every output time, 1/fps
 * apart, that stepping passed) as out_dir/NAME.mp4 and the poster
 * out_dir/NAME.png, NAME the scene's (its file's base name), with the
 * scene's [render] options, as `rodsim run` draws them; out_dir is made
 * when missing. Nothing half-written is left on failure. */
rodsim_status rodsim_render(rodsim_scene *scene, const char *out_dir);

#ifdef __cplusplus
}
#endif

#endif
