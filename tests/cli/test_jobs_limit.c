/* test_jobs_limit.c: every command with --jobs N (sweep, figure, validate,
 * stability) accepts the same range, 1 .. 64 worker processes: 65 is
 * refused with exit 2 and a message naming "1 .. 64"; 64 is taken (figure
 * and sweep, with --print-commands, run nothing). */
#include <stdio.h>
#include <string.h>

#include "test.h"
#include "test_process.h"

#define SCENE RODSIM_SOURCE_DIR "/scenes/table2_450nN.ini"

int main(void)
{
    static char output[1 << 16];
    const char *result = test_path("result");
    /* figure's --out: a figure that took 65 would draw there, not in out/ */
    const char *refused[][8] = {{"sweep", SCENE, "--jobs", "65", NULL},
                                {"figure", "table2", "--jobs", "65", "--quick", "--out", result,
                                 NULL},
                                {"validate", "--jobs", "65", NULL},
                                {"stability", "--jobs", "65", NULL}};
    for (int i = 0; i < 4; i++) {
        int rc = test_run_rodsim_within(refused[i], 60, output, sizeof output);
        check(rc == 2 && strstr(output, "--jobs 65: accepted: a whole number 1 .. 64"),
              "%s --jobs 65: exit %d (want 2), names 1 .. 64: %s", refused[i][0], rc,
              strstr(output, "1 .. 64") ? "yes" : "no");
    }
    const char *sweep[] = {"sweep", SCENE, "--jobs", "64", "--result", result, "--print-commands",
                           NULL};
    int rc = test_run_rodsim_within(sweep, 60, output, sizeof output);
    check(rc == 0, "sweep --jobs 64 --print-commands: exit %d (want 0)", rc);
    const char *figure[] = {"figure", "table2", "--jobs", "64", "--quick", "--out", result,
                            "--print-commands", NULL};
    rc = test_run_rodsim_within(figure, 60, output, sizeof output);
    check(rc == 0, "figure table2 --jobs 64 --print-commands: exit %d (want 0)", rc);
    test_remove_tree(result);
    return test_finish();
}
