/* test_fem_svg.c: `rodsim fem --svg`, through the real binary.
 *  - the SVG is valid XML (xmllint parses it) and written with the PNG, or
 *    alone with --no-png;
 *  - its node markers sit where the nodal CSV puts the nodes: the axes read
 *    off the SVG itself (x: the tick labels' positions; z: the horizontal
 *    grid lines, one per y tick label, in order), the undeformed nodes at
 *    (x, z), the deformed ones at (x + S u, z + S w), S the deformation
 *    scale `rodsim fem` prints; within 0.02 px (the SVG's coordinates have
 *    two decimals);
 *  - a path that cannot be written (under a file) is refused before the
 *    scene is solved (exit 2, the message naming --svg and the path, no
 *    nodal table printed), leaving no file, the PNG's neither;
 *  - a write that fails part way (/dev/full: the disk full) is exit 1, no
 *    PNG left. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "test.h"
#include "test_process.h"

#define OUTPUT_LEN 65536
#define MAX_NODES 64

static char output[OUTPUT_LEN];
static char scratch[256];

static char *read_text(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    char *text = calloc(1, 1 << 20);
    if (text) text[fread(text, 1, (1 << 20) - 1, f)] = '\0';
    fclose(f);
    return text;
}

/* A tick label's number: U+2212 read as '-'. */
static double label_number(const char *text)
{
    char plain[64];
    size_t n = 0;
    for (const char *c = text; *c && n + 1 < sizeof plain; c++) {
        if (strncmp(c, "\xe2\x88\x92", 3) == 0) {
            plain[n++] = '-';
            c += 2;
        } else {
            plain[n++] = *c;
        }
    }
    plain[n] = '\0';
    char *end;
    double v = strtod(plain, &end);
    return end != plain && *end == '\0' ? v : NAN;
}

/* The data -> pixel map the SVG's axes show: px = x0 + k x, py = z0 - k z
 * (one scale: the FEM figure has equal aspect). 0, or -1 when the axes
 * cannot be read. */
typedef struct axes_map {
    double x0, kx, z0, kz; /* px, px/m */
} axes_map;

static int read_axes(const char *svg, axes_map *map)
{
    /* x: tick labels centred under the axis (text-anchor="middle", a number) */
    double tx[16], tv[16], gy[16], yv[16];
    int nx = 0, ng = 0, ny = 0;
    for (const char *c = svg; (c = strstr(c, "<text ")); c++) {
        double x, y;
        char anchor[16], body[64];
        if (sscanf(c, "<text x=\"%lf\" y=\"%lf\" font-size=\"%*d\" "
                      "text-anchor=\"%15[a-z]\">%63[^<]", &x, &y, anchor, body) != 4)
            continue;
        double v = label_number(body);
        if (!isfinite(v)) continue;
        if (strcmp(anchor, "middle") == 0 && nx < 16) tx[nx] = x, tv[nx++] = v;
        if (strcmp(anchor, "end") == 0 && ny < 16) yv[ny++] = v;
    }
    /* the grid: the first <g> of light lines; horizontal ones have y1 == y2 */
    const char *grid = strstr(svg, "<g stroke=\"#e4e4e4\"");
    const char *grid_end = grid ? strstr(grid, "</g>") : NULL;
    for (const char *c = grid; c && c < grid_end && (c = strstr(c, "<line ")) && c < grid_end;
         c++) {
        double x1, y1, x2, y2;
        if (sscanf(c, "<line x1=\"%lf\" y1=\"%lf\" x2=\"%lf\" y2=\"%lf\"", &x1, &y1, &x2, &y2) ==
                4 && y1 == y2 && ng < 16)
            gy[ng++] = y1;
    }
    if (nx < 2 || ny < 2 || ng != ny) return -1;
    map->kx = (tx[nx - 1] - tx[0]) / (tv[nx - 1] - tv[0]);
    map->x0 = tx[0] - map->kx * tv[0];
    map->kz = (gy[0] - gy[ng - 1]) / (yv[ny - 1] - yv[0]);
    map->z0 = gy[0] + map->kz * yv[0];
    return 0;
}

/* The centres of the circles drawn with stroke `rgb`, in order. */
static int circles(const char *svg, const char *rgb, double *cx, double *cy, int max)
{
    int n = 0;
    char stroke[32];
    snprintf(stroke, sizeof stroke, "stroke=\"%s\"", rgb);
    for (const char *c = svg; n < max && (c = strstr(c, "<circle ")); c++) {
        const char *end = strchr(c, '>');
        const char *s = strstr(c, stroke);
        if (!end || !s || s > end) continue;
        if (sscanf(c, "<circle cx=\"%lf\" cy=\"%lf\"", &cx[n], &cy[n]) == 2) n++;
    }
    return n;
}

/* The nodal CSV: node,x,z,u,w,theta,displacement; how many rows. */
static int read_nodes(const char *path, double (*node)[4])
{
    char *text = read_text(path);
    int n = 0;
    for (const char *line = text ? strchr(text, '\n') : NULL; line && n < MAX_NODES;
         line = strchr(line + 1, '\n')) {
        int id;
        if (sscanf(line + 1, "%d,%lf,%lf,%lf,%lf", &id, &node[n][0], &node[n][1], &node[n][2],
                   &node[n][3]) == 5)
            n++;
    }
    free(text);
    return n;
}

static void test_scene(const char *name)
{
    char scene[400], svg[320], csv[320], png[320];
    snprintf(scene, sizeof scene, "%s/scenes/%s.ini", RODSIM_SOURCE_DIR, name);
    snprintf(svg, sizeof svg, "%s/%s.svg", scratch, name);
    snprintf(csv, sizeof csv, "%s/%s.csv", scratch, name);
    snprintf(png, sizeof png, "%s/%s.png", scratch, name);
    const char *args[] = {"fem", scene, "--svg", svg, "--csv", csv, "--png", png, NULL};
    int rc = test_run_rodsim(args, output, sizeof output);
    char command[400];
    snprintf(command, sizeof command, "xmllint --noout '%s'", svg);
    int xml = rc == 0 ? system(command) : -1;
    struct stat st;
    check(rc == 0 && xml == 0 && stat(png, &st) == 0,
          "%s: fem --svg --png (exit %d): xmllint parses the SVG (status %d), the PNG too",
          name, rc, xml);
    const char *scale_line = strstr(output, "displacements x ");
    double scale = scale_line ? strtod(scale_line + 16, NULL) : 1.0;
    char *text = read_text(svg);
    double node[MAX_NODES][4], ux[MAX_NODES], uy[MAX_NODES], dx[MAX_NODES], dy[MAX_NODES];
    int nodes = read_nodes(csv, node);
    axes_map map = {0};
    int axes = text ? read_axes(text, &map) : -1;
    /* undeformed nodes: grey (#8c8c8c); deformed: the deformed line's blue */
    int nu = text ? circles(text, "#8c8c8c", ux, uy, MAX_NODES) : 0;
    int nd = text ? circles(text, "#005ac8", dx, dy, MAX_NODES) : 0;
    /* the deformed nodes' legend entry is one marker more, after them */
    if (!check(axes == 0 && nodes >= 2 && nu == nodes && nd == nodes + 1,
               "%s: axes read off the SVG (%d), %d nodes in the CSV, %d undeformed and %d "
               "deformed node markers (one in the legend)", name, axes, nodes, nu, nd)) {
        free(text);
        return;
    }
    check_rel("equal aspect: px per m along x vs along z", map.kx, map.kz, 1e-4);
    double worst_u = 0.0, worst_d = 0.0;
    for (int i = 0; i < nodes; i++) {
        double x = node[i][0], z = node[i][1], u = node[i][2], w = node[i][3];
        worst_u = fmax(worst_u, hypot(ux[i] - (map.x0 + map.kx * x),
                                      uy[i] - (map.z0 - map.kz * z)));
        worst_d = fmax(worst_d, hypot(dx[i] - (map.x0 + map.kx * (x + scale * u)),
                                      dy[i] - (map.z0 - map.kz * (z + scale * w))));
    }
    char what[160];
    snprintf(what, sizeof what, "%s: undeformed node markers vs the CSV's (x, z), worst px", name);
    check_abs(what, worst_u, 0.0, 0.02);
    snprintf(what, sizeof what, "%s: deformed node markers vs (x + %g u, z + %g w), worst px",
             name, scale, scale);
    check_abs(what, worst_d, 0.0, 0.02);
    free(text);
}

static void test_svg_alone(void)
{
    char scene[400], svg[400], dir[320];
    snprintf(scene, sizeof scene, "%s/scenes/fishing_rod.ini", RODSIM_SOURCE_DIR);
    snprintf(dir, sizeof dir, "%s/alone", scratch);
    mkdir(dir, 0755);
    snprintf(svg, sizeof svg, "%s/figure.svg", dir);
    const char *args[] = {"fem", scene, "--no-png", "--svg", svg, "-o", dir, NULL};
    int rc = test_run_rodsim(args, output, sizeof output);
    check(rc == 0 && test_dir_entries(dir) == 1 && strstr(output, "wrote ") &&
              strstr(output, "figure.svg"),
          "--no-png --svg: the SVG alone (exit %d, %d files)", rc, test_dir_entries(dir));
    snprintf(svg, sizeof svg, "%s/figure.svg/x.svg", dir); /* under a file */
    char png[400];
    snprintf(png, sizeof png, "%s/figure.png", dir);
    unlink(png);
    const char *bad[] = {"fem", scene, "--svg", svg, "--png", png, NULL};
    rc = test_run_rodsim(bad, output, sizeof output);
    int solved = strstr(output, "condition number") != NULL; /* the table's heading */
    char *nl = strchr(output, '\n');
    if (nl) *nl = '\0';
    check(rc == 2 && !solved && strstr(output, "--svg") && strstr(output, svg) &&
              test_dir_entries(dir) == 1,
          "--svg where no file can go: exit %d (2), refused before solving (table printed: %d), "
          "no PNG left either (%d files): %s", rc, solved, test_dir_entries(dir), output);
    const char *full[] = {"fem", scene, "--svg", "/dev/full", "--png", png, NULL};
    rc = test_run_rodsim(full, output, sizeof output);
    check(rc == 1 && test_dir_entries(dir) == 1,
          "--svg /dev/full (the disk full part way): exit %d (1), no PNG left (%d files)", rc,
          test_dir_entries(dir));
}

int main(void)
{
    snprintf(scratch, sizeof scratch, "%s", test_dir());
    test_scene("fishing_rod");
    test_scene("fishing_rod_curved");
    test_svg_alone();
    return test_finish();
}
