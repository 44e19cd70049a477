/* test_near_names.c: a misspelt name given to an option is refused (exit 2)
 * with the nearest accepted name, as a misspelt scene key or command is:
 * validate --case and --scheme, stability --scheme, figure NAME, and sweep
 * --plot X:Y's axes. A word near none gets the list only. */
#include <stdio.h>
#include <string.h>

#include "test.h"
#include "test_process.h"

static void expect(const char *what, const char *const *args, const char *want)
{
    char output[8192];
    int status = test_run_rodsim(args, output, sizeof output);
    char *nl = strchr(output, '\n');
    if (nl) *nl = '\0';
    int suggests = strstr(output, "did you mean") != NULL;
    int ok = status == 2 && (want ? strstr(output, want) != NULL : !suggests);
    check(ok, "%s: exit %d (want 2), '%s' (want %s)", what, status, output,
          want ? want : "no suggestion");
}

int main(void)
{
    const char *vcase[] = {"validate", "--case", "tip_load_smal", NULL};
    expect("validate --case tip_load_smal", vcase, "did you mean tip_load_small?");
    const char *vscheme[] = {"validate", "--scheme", "implict", NULL};
    expect("validate --scheme implict", vscheme, "did you mean implicit?");
    const char *sscheme[] = {"stability", "--scheme", "statc", NULL};
    expect("stability --scheme statc", sscheme, "did you mean static?");
    const char *fig[] = {"figure", "tabel2", NULL};
    expect("figure tabel2", fig, "did you mean table2?");
    const char *plot_y[] = {"sweep", RODSIM_SOURCE_DIR "/scenes/table2_450nN.ini", "--vary",
                            "rod.nodes=11,21", "--plot", "rod.nodes:tip_yy", "--png",
                            test_path("near_names.png"), NULL};
    expect("sweep --plot rod.nodes:tip_yy", plot_y, "did you mean tip_y?");
    const char *plot_x[] = {"sweep", RODSIM_SOURCE_DIR "/scenes/table2_450nN.ini", "--vary",
                            "rod.nodes=11,21", "--plot", "rod.node:tip_y", "--png",
                            test_path("near_names.png"), NULL};
    expect("sweep --plot rod.node:tip_y", plot_x, "did you mean rod.nodes?");
    const char *far[] = {"validate", "--case", "qqq", NULL};
    expect("validate --case qqq (near none)", far, NULL);
    return test_finish();
}
