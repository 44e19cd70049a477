/* test_live_exit.c: rodsim live's exit status as its --help states it: a
 * session with no line at all (stdin closed at once) ends with exit 0, one
 * whose lines all came and none was ok ends with exit 2; --help says both.
 * A session --on-error stop ends at its first line, a bad one, times no
 * line: its closing line's percentiles are 0, not the histogram's last bin
 * (20000 us). */
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "test.h"
#include "test_process.h"

#define SCENE RODSIM_SOURCE_DIR "/scenes/needle_lift.ini"

/* Runs rodsim live SCENE [OPTION] with `input` on stdin; its exit status;
 * stderr into `log` when not NULL. */
static int live_with(const char *input, const char *option, const char *log)
{
    char command[1024];
    snprintf(command, sizeof command, "printf '%s' | '%s' live '%s' %s >/dev/null 2>%s", input,
             RODSIM_BIN, SCENE, option, log ? log : "/dev/null");
    fflush(stdout);
    int status = system(command);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

int main(void)
{
    char help[8192];
    const char *args[] = {"live", "--help", NULL};
    test_run_rodsim(args, help, sizeof help);
    int empty = live_with("", "", NULL);
    check(empty == 0 && strstr(help, "exit 0 (no line at all"),
          "no line at all: exit %d (want 0), and --help says so", empty);
    int none_ok = live_with("0.01,abc\\n", "", NULL);
    check(none_ok == 2 && strstr(help, "2 if lines came and none was ok"),
          "one line, not ok: exit %d (want 2), and --help says so", none_ok);
    char log[] = "/tmp/rodsim_live_exit_XXXXXX";
    int fd = mkstemp(log);
    if (fd >= 0) close(fd);
    int stopped = live_with("0.01,abc\\n0.02,0,0,0.3\\n", "--on-error stop", log);
    FILE *f = fopen(log, "r");
    static char text[16384];
    size_t got = f ? fread(text, 1, sizeof text - 1, f) : 0;
    text[got] = '\0';
    if (f) fclose(f);
    unlink(log);
    const char *work = strstr(text, "work per line");
    const char *cpu = strstr(text, "CPU per line");
    check(stopped == 2 && work && cpu && !strstr(text, "20000"),
          "--on-error stop at a bad first line: exit %d (want 2), percentiles '%.60s', '%.50s' "
          "(want no 20000)", stopped, work ? work : "", cpu ? cpu : "");
    return test_finish();
}
