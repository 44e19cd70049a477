/* test_sweep_closing_line.c: rodsim sweep's closing line counts the points
 * run and, only with --result DIR, those read back from DIR: without it,
 * "2 points: 2 run; 0 not ok" (no "from -"); with it, a second sweep over
 * the same points says "2 points: 0 run, 2 from DIR". */
#include <stdio.h>
#include <string.h>

#include "test.h"
#include "test_process.h"

#define SCENE RODSIM_SOURCE_DIR "/scenes/table2_450nN.ini"

/* The line of output that starts with "rodsim sweep: N points", or "". */
static const char *closing_line(char *output)
{
    char *at = strstr(output, "rodsim sweep: 2 points");
    if (!at) return "";
    at[strcspn(at, "\n")] = '\0';
    return at;
}

int main(void)
{
    char output[8192], dir[] = "/tmp/rodsim_sweep_closing_XXXXXX";
    if (!check(mkdtemp(dir) != NULL, "scratch directory")) return test_finish();
    const char *plain[] = {"sweep", SCENE, "--vary", "rod.nodes=11,21", "--measure", "tip_y",
                           "--set", "solver.duration=0.1", NULL};
    int rc = test_run_rodsim(plain, output, sizeof output);
    const char *line = closing_line(output);
    check(rc == 0 && strstr(line, "2 points: 2 run; 0 not ok") && !strstr(line, "from"),
          "without --result: '%s' (want '2 points: 2 run; 0 not ok', no 'from'), exit %d", line,
          rc);
    char results[96];
    snprintf(results, sizeof results, "%s/results", dir);
    const char *kept[] = {"sweep", SCENE, "--vary", "rod.nodes=11,21", "--measure", "tip_y",
                          "--set", "solver.duration=0.1", "--result", results, NULL};
    rc = test_run_rodsim(kept, output, sizeof output);
    rc |= test_run_rodsim(kept, output, sizeof output);
    char want[160];
    snprintf(want, sizeof want, "2 points: 0 run, 2 from %s; 0 not ok", results);
    line = closing_line(output);
    check(rc == 0 && strstr(line, want), "with --result, run again: '%s' (want '%s'), exit %d",
          line, want, rc);
    test_remove_tree(dir);
    return test_finish();
}
