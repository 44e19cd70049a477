/* test_plot_axes.c: the y axes `sweep --plot X:Y` offers are the ones it
 * takes. An unknown y axis is refused (exit 2) with the accepted list, which
 * holds the numeric measures (tip_y, rope_in_knot_d) but not knot, the
 * knot's type: a name that --plot refuses (it stays a --measure, and
 * --plot X:knot says so); a near miss of "knot" is not offered it. */
#include <stdio.h>
#include <string.h>

#include "test.h"
#include "test_process.h"

#define SCENE RODSIM_SOURCE_DIR "/scenes/table2_450nN.ini"

/* Runs sweep --plot rod.nodes:Y into output; its exit status. */
static int plot(const char *y, char *output, size_t outlen)
{
    char axes[64];
    snprintf(axes, sizeof axes, "rod.nodes:%s", y);
    const char *args[] = {"sweep", SCENE, "--vary", "rod.nodes=11,21", "--plot", axes,
                          "--png", test_path("plot_axes.png"), NULL};
    return test_run_rodsim_within(args, 60, output, outlen);
}

/* Whether the ", "-separated list after "accepted: " (to the line's end)
 * has the item `name`. */
static int listed(const char *output, const char *name)
{
    const char *p = strstr(output, "accepted: ");
    if (!p) return 0;
    p += strlen("accepted: ");
    size_t n = strlen(name);
    while (*p && *p != '\n') {
        size_t len = strcspn(p, ",\n");
        if (len == n && strncmp(p, name, n) == 0) return 1;
        p += len;
        if (*p == ',') p += 2;
    }
    return 0;
}

int main(void)
{
    static char output[1 << 14];
    int rc = plot("foo", output, sizeof output);
    check(rc == 2 && strstr(output, "the y axis must be a measure") && listed(output, "tip_y") &&
              listed(output, "rope_in_knot_d") && listed(output, "cpu_s"),
          "--plot rod.nodes:foo: exit %d (want 2), the accepted y axes list tip_y, "
          "rope_in_knot_d, cpu_s", rc);
    check(!listed(output, "knot"), "the accepted y axes leave out knot (listed: %s)",
          listed(output, "knot") ? "yes" : "no");
    rc = plot("knto", output, sizeof output);
    check(rc == 2 && !strstr(output, "did you mean knot?") && !listed(output, "knot"),
          "--plot rod.nodes:knto: exit %d (want 2), knot neither suggested nor listed", rc);
    rc = plot("knot", output, sizeof output);
    check(rc == 2 && strstr(output, "the knot type is a name, not a number") &&
              strstr(output, "--measure knot"),
          "--plot rod.nodes:knot: exit %d (want 2), refused, pointing to --measure knot", rc);
    return test_finish();
}
