/* worker.h: the start of a forked worker process (rodsim figure, validate and
 * stability run points in children that send their results through a pipe). */
#ifndef RODSIM_WORKER_H
#define RODSIM_WORKER_H

#include <sys/types.h>

/* Call first in the child of fork(), with the parent's pid taken before the
 * fork. The worker stays in its parent's process group (a Ctrl-C reaches
 * both) and dies with its parent: PR_SET_PDEATHSIG covers SIGTERM and kill -9
 * of the parent, which can run no cleanup; a parent that died before the call
 * ends the worker at once. The parent's signal handlers (which remove the
 * parent's temporary files) are reset to the default. */
void worker_begin(pid_t parent);

#endif
