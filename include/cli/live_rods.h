/* live_rods.h: `rodsim live` of a scene of named rods ([rod NAME];
 * sim/rod_set.h): each input line drives one rod's held tip, all rods
 * stepped together to the line's t, and is answered with that rod's tip
 * force.
 *
 * A line is NAME:t,x,y,z (or NAME:t,x,y,z,rx,ry,rz for a clamped tip):
 * rod NAME's held tip's pose at t, as a single rod's line, or, for a free
 * tip, NAME:t,fx,fy,fz,mx,my,mz, its loads on [tip NAME] frame, linear
 * from the state's time to t; without "NAME:" it drives the rod of --rod,
 * else the first rod. Every other rod's tip stays where its last line put
 * it (at rest), or keeps its last loads: a rod's path gets a row at rest at
 * the state's time before its next line's row, so its tip moves
 * continuously. The answer: NAME,t,fx,fy,fz,mx,my,mz,status, the force (N)
 * and moment (N m) rod NAME exerts on what holds its tip (a free tip: its
 * root), global; status ok, failed (the step failed: the last good state
 * answered, the row dropped) or bad_input (an empty NAME: the line named no
 * rod of the scene). With centreline, every answer is followed by every
 * rod's centreline, scene order (x0,y0,z0,... of each node, m; columns
 * NAME.x0,...): a client drawing the scene needs them all, and a line that
 * moves one rod moves the others through their contact. With record, the
 * CSV `rodsim run --csv` writes of the scene (its column rod when there
 * are several), a frame at t = 0 and after each line answered ok, through
 * outfile.h: it appears whole at the session's end (a signal's too). With
 * realtime, as for one rod: each line waits until its t on the wall clock
 * from the header's time (live_realtime_setup first), and a line whose work
 * took longer than its gap of simulated time is counted an overrun.
 * Why this syntax: docs/decisions/0089-rod-surfaces.md. */
#ifndef RODSIM_CLI_LIVE_RODS_H
#define RODSIM_CLI_LIVE_RODS_H

#include "base/ini.h"

typedef struct live_rods_options {
    const char *default_rod; /* the rod of lines without "NAME:" (NULL: the first) */
    const char *record;      /* --record FILE, or NULL */
    int stop_on_error;       /* a refused line ends the session (exit 2) */
    int centreline;          /* every rod's centreline after each answer */
    int realtime;            /* each line waits for its t on the wall clock */
} live_rods_options;

/* The session on standard input and output, messages on standard error:
 * doc (its --set applied) read as `rodsim run` reads several rods, o as
 * above. Returns an exit status: 0, 2 for a bad scene or --rod, or lines
 * none of which was ok, 1 when the answers or the record cannot be
 * written. */
int live_rods_run(ini_doc *doc, const char *scene, const live_rods_options *o);

#endif
