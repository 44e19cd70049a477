/* live.h: `rodsim live`: the thread driven line by line from
 * standard input (a sensor bridge, a haptic device), each line answered at
 * once on standard output with the force and moment the thread exerts on
 * its driven end.
 *
 * A scene whose tip is held (pinned or clamped) is driven by its tip's pose:
 * input t,x,y,z (or t,x,y,z,rx,ry,rz for a clamped tip), global m and the
 * rotation vector from the tip's starting frame, rad; the pose replaces
 * ends.tip_motion and is interpolated causally (sim/path.h, rod_path_push).
 * A scene whose tip is free takes t,fx,fy,fz,mx,my,mz, the tip loads on
 * tip.frame (N, N m), linear between lines; its answer is what the thread
 * exerts on its root. The scheme advances to each line's t in equal steps no
 * longer than solver.dt.
 *
 * Output: a header, then one line per input line, flushed:
 * t,fx,fy,fz,mx,my,mz,status[,x0,y0,z0,...] with status ok, failed (the
 * step failed: the last good state, the line dropped from the driven path)
 * or bad_input (the line was refused and skipped). Everything else goes to
 * standard error. --record writes a path (or load table) with velocities
 * that `rodsim run` replays and `rodsim render` turns into the video
 * (render_cli.h), row by row as the session goes.
 */
#ifndef RODSIM_LIVE_H
#define RODSIM_LIVE_H

#include <stdio.h>

/* The record's first lines (then the CSV header and rows): the magic and
 * the scene given, the scene's absolute path, one line per --set (in order),
 * solver.dt (s). */
#define LIVE_RECORD_MAGIC "# rodsim live record of "
#define LIVE_RECORD_SCENE "# scene: "
#define LIVE_RECORD_SET "# set: "
#define LIVE_RECORD_DT "# dt: "

/* Longest input line, bytes with its newline: a longer one is refused. */
#define LIVE_LINE_MAX 4096

/* `rodsim live ...`: argv[0] is "live". Returns an exit status: 0 at the end
 * of input, 2 on bad usage or scene, or a bad line under --on-error stop, 1
 * on another failure. Never calls exit(). */
int live_command(int argc, char **argv);

void live_usage(FILE *f);

#endif
