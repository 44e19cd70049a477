/* test_validate_csv.c: rodsim validate --csv gives each row's status in the
 * table's words (ok, n/a, FAILED; docs/output.md), not a bare code: a
 * static tip_load_small at NS 11 is ok, and its error is the table's
 * (2.49e-3 against the elastica, README). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test.h"
#include "test_process.h"

int main(void)
{
    char output[8192];
    const char *args[] = {"validate", "--case", "tip_load_small", "--scheme", "static",
                          "--nodes", "11", "--csv", "-", NULL};
    int status = test_run_rodsim(args, output, sizeof output);
    const char *row = strstr(output, "\ntip_load_small,static,11,");
    char cells[11][128] = {{0}};
    int n = 0;
    for (const char *c = row ? row + 1 : ""; *c && *c != '\n' && n < 11; n++) {
        size_t len = strcspn(c, ",\n");
        snprintf(cells[n], sizeof cells[n], "%.*s", (int)len, c);
        c += len;
        if (*c == ',') c++;
    }
    check(status == 0 && n >= 9 && strcmp(cells[8], "ok") == 0,
          "validate --csv -: exit %d, the row's status cell '%s' (want ok)", status, cells[8]);
    check_rel("its relative error against the elastica (README: 2.49e-3)", strtod(cells[6], NULL),
              2.49e-3, 2e-3);
    return test_finish();
}
