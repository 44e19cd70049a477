/* worker.c: see worker.h. */
#include "base/worker.h"

#include <signal.h>
#include <sys/prctl.h>
#include <unistd.h>

void worker_begin(pid_t parent)
{
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(1); /* the parent died before prctl */
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
}
