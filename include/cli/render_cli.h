/* render_cli.h: `rodsim render RECORD`: a session recorded by
 * `rodsim live --record` becomes the usual video and poster. The record
 * names its scene, the --set overrides and dt (live.h LIVE_RECORD_*), and
 * holds the inputs that were stepped; the scene is simulated again driven by
 * them, to the last complete row, and rendered with the scene's [render]
 * settings (--set render.KEY=VALUE overrides them; other keys are refused:
 * the session's physics is the record's). A record cut short (the session
 * killed, no closing line, or a last line without its newline) renders up to
 * its last complete row. Outputs are named after the record (rec.csv ->
 * DIR/rec.mp4, DIR/rec.png) and appear whole or not at all (outfile.h).
 */
#ifndef RODSIM_RENDER_CLI_H
#define RODSIM_RENDER_CLI_H

#include <stdio.h>

/* `rodsim render ...`: argv[0] is "render" (or "run": `rodsim run` given a
 * record, and its messages then say "rodsim run: "). Returns an exit status: 0, 2 on
 * bad usage or a record or scene that cannot be read, 1 on another failure.
 * Never calls exit(). */
int render_command(int argc, char **argv);

void render_usage(FILE *f);

#endif
