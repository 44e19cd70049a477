/* test_live_exit.c: rodsim live's exit status as its --help states it: a
 * session with no line at all (stdin closed at once) ends with exit 0, one
 * whose lines all came and none was ok ends with exit 2; --help says both. */
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "test.h"
#include "test_process.h"

#define SCENE RODSIM_SOURCE_DIR "/scenes/needle_lift.ini"

/* Runs rodsim live SCENE with `input` on stdin; its exit status. */
static int live_with(const char *input)
{
    char command[1024];
    snprintf(command, sizeof command, "printf '%s' | '%s' live '%s' >/dev/null 2>&1", input,
             RODSIM_BIN, SCENE);
    fflush(stdout);
    int status = system(command);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

int main(void)
{
    char help[8192];
    const char *args[] = {"live", "--help", NULL};
    test_run_rodsim(args, help, sizeof help);
    int empty = live_with("");
    check(empty == 0 && strstr(help, "exit 0 (no line at all"),
          "no line at all: exit %d (want 0), and --help says so", empty);
    int none_ok = live_with("0.01,abc\\n");
    check(none_ok == 2 && strstr(help, "2 if lines came and none was ok"),
          "one line, not ok: exit %d (want 2), and --help says so", none_ok);
    return test_finish();
}
