/* test_fem_help.c: `rodsim fem --help` says what `--csv -` does, and it
 * does it: the help's --csv entry names "-" and standard output, and
 * `fem SCENE --csv - --no-png` puts the nodal table alone on standard output
 * (its header first, one row per node), the prose on standard error. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test.h"
#include "test_process.h"

#define SCENE RODSIM_SOURCE_DIR "/scenes/fishing_rod.ini"
#define HEADER "node,x,z,u,w,theta,displacement"

/* Standard output alone of a shell command into out; its exit status. */
static int stdout_of(const char *command, char *out, size_t outlen)
{
    FILE *p = popen(command, "r");
    if (!p) return -1;
    size_t got = fread(out, 1, outlen - 1, p);
    out[got] = '\0';
    return pclose(p);
}

int main(void)
{
    static char output[1 << 16];
    const char *help[] = {"fem", "--help", NULL};
    int rc = test_run_rodsim(help, output, sizeof output);
    const char *entry = strstr(output, "  --csv FILE");
    const char *next = entry ? strstr(entry + 1, "\n  --") : NULL;
    const char *dash = entry ? strstr(entry, "- writes it to standard output") : NULL;
    check(rc == 0 && entry && next && dash && dash < next,
          "rodsim fem --help: exit %d, its --csv entry says '- writes it to standard output' "
          "(%s)", rc, dash && next && dash < next ? "said" : "not said");
    rc = stdout_of("'" RODSIM_BIN "' fem '" SCENE "' --csv - --no-png 2>/dev/null", output,
                   sizeof output);
    int rows = 0, numeric = 0;
    for (const char *line = strchr(output, '\n'); line && line[1]; line = strchr(line + 1, '\n')) {
        rows++;
        int node;
        if (sscanf(line + 1, "%d,", &node) == 1) numeric++;
    }
    check(rc == 0 && strncmp(output, HEADER, strlen(HEADER)) == 0 && rows > 1 && numeric == rows,
          "fem --csv -: exit %d, standard output starts with the CSV header, then %d rows, "
          "%d of them numbered nodes (all, and no prose)", rc, rows, numeric);
    return test_finish();
}
