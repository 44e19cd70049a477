/* test_stl.c: the STL reader (base/stl.c): a cube written as ASCII and as
 * binary reads back as the same 12 triangles, the cube's own; a degenerate
 * triangle is dropped with a warning naming its place; malformed files
 * (truncated, a wrong word, NaN, a binary whose size disagrees with its
 * header, too many triangles) are refused with messages naming the file and
 * the line or byte. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "base/stl.h"
#include "test.h"

/* The cube [-1, 0.5]^3 (exact in float and in decimal): 12 triangles,
 * outward counter-clockwise. */
static void cube(double tri[12][9])
{
    static const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                    {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (int f = 0; f < 6; f++) {
        const int order[2][3] = {{0, 1, 2}, {0, 2, 3}};
        for (int h = 0; h < 2; h++)
            for (int k = 0; k < 3; k++) {
                int corner = quads[f][order[h][k]];
                for (int c = 0; c < 3; c++) tri[2 * f + h][3 * k + c] = corner >> c & 1 ? 0.5 : -1.0;
            }
    }
}

static size_t ascii_of(double tri[][9], int count, char *out, size_t size)
{
    size_t n = (size_t)snprintf(out, size, "solid cube\n");
    for (int t = 0; t < count; t++) {
        n += (size_t)snprintf(out + n, size - n, "  facet normal 0 0 0\n    outer loop\n");
        for (int k = 0; k < 3; k++)
            n += (size_t)snprintf(out + n, size - n, "      vertex %.17g %.17g %.17g\n",
                                  tri[t][3 * k], tri[t][3 * k + 1], tri[t][3 * k + 2]);
        n += (size_t)snprintf(out + n, size - n, "    endloop\n  endfacet\n");
    }
    n += (size_t)snprintf(out + n, size - n, "endsolid cube\n");
    return n;
}

static void put32(unsigned char *b, uint32_t v)
{
    for (int k = 0; k < 4; k++) b[k] = (unsigned char)(v >> (8 * k));
}

static size_t binary_of(double tri[][9], int count, unsigned char *out)
{
    memset(out, 0, 84);
    memcpy(out, "solid but binary", 16); /* a header may start with "solid" */
    put32(out + 80, (uint32_t)count);
    for (int t = 0; t < count; t++) {
        unsigned char *rec = out + 84 + 50 * t;
        memset(rec, 0, 50);
        for (int k = 0; k < 9; k++) {
            float f = (float)tri[t][k];
            uint32_t bits;
            memcpy(&bits, &f, 4);
            put32(rec + 12 + 4 * k, bits);
        }
    }
    return 84 + 50 * (size_t)count;
}

static void test_cube(void)
{
    double tri[12][9];
    cube(tri);
    static char text[8192];
    static unsigned char bin[84 + 50 * 12];
    size_t tn = ascii_of(tri, 12, text, sizeof text), bn = binary_of(tri, 12, bin);
    stl_mesh a, b;
    char err[512] = "", warn[256] = "";
    int ra = stl_parse("cube_ascii.stl", (const unsigned char *)text, tn, 100, "max", &a, warn,
                       sizeof warn, err, sizeof err);
    check(ra == 0 && a.triangle_count == 12, "ASCII cube: %d triangles read (12) %s", a.triangle_count, err);
    int rb = stl_parse("cube_binary.stl", bin, bn, 100, "max", &b, warn, sizeof warn, err, sizeof err);
    check(rb == 0 && b.triangle_count == 12, "binary cube: %d triangles read (12) %s", b.triangle_count, err);
    double diff = 0.0, own = 0.0, volume = 0.0;
    for (int t = 0; ra == 0 && rb == 0 && t < 12; t++) {
        for (int k = 0; k < 9; k++) {
            diff = fmax(diff, fabs(a.triangles[9 * t + k] - b.triangles[9 * t + k]));
            own = fmax(own, fabs(a.triangles[9 * t + k] - tri[t][k]));
        }
        /* the divergence theorem: V = sum a . (b x c) / 6 (outward order) */
        const double *p = &a.triangles[9 * t];
        volume += (p[0] * (p[4] * p[8] - p[5] * p[7]) - p[1] * (p[3] * p[8] - p[5] * p[6]) +
                   p[2] * (p[3] * p[7] - p[4] * p[6])) / 6.0;
    }
    check_abs("cube: ASCII vs binary triangles, largest coordinate difference, m", diff, 0.0, 0.0);
    check_abs("cube: ASCII triangles vs the cube written, largest difference, m", own, 0.0, 0.0);
    check_rel("cube: enclosed volume (divergence theorem, outward order) vs 1.5^3, m^3", volume,
              3.375, 1e-15);
    stl_release(&a);
    stl_release(&b);
    /* a degenerate facet (its 3rd vertex on the line of the first two) is dropped */
    double bad[13][9];
    memcpy(bad, tri, sizeof tri);
    const double needle[9] = {0, 0, 0, 1, 1, 1, 2, 2, 2};
    memcpy(bad[12], needle, sizeof needle);
    tn = ascii_of(bad, 13, text, sizeof text);
    ra = stl_parse("cube_needle.stl", (const unsigned char *)text, tn, 100, "max", &a, warn,
                   sizeof warn, err, sizeof err);
    check(ra == 0 && a.triangle_count == 12 && a.dropped == 1 &&
              strstr(warn, "cube_needle.stl:86:") && strstr(warn, "degenerate"),
          "a degenerate facet dropped with a warning: %d kept, %d dropped: %s", a.triangle_count,
          a.dropped, warn);
    stl_release(&a);
}

/* Parses text (ASCII) and expects a refusal whose message holds each of
 * the words. */
static void refused(const char *what, const unsigned char *data, size_t size, int max,
                    const char *want1, const char *want2)
{
    stl_mesh out;
    char err[512] = "";
    int rc = stl_parse("bad.stl", data, size, max, "surface.max_triangles", &out, NULL, 0, err,
                       sizeof err);
    check(rc == -1 && out.triangles == NULL && strstr(err, want1) && strstr(err, want2),
          "%s: refused: %s", what, err);
}

static void test_malformed(void)
{
    static const char truncated[] = "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                                    "vertex 1 0 0\n";
    refused("ASCII cut inside a facet", (const unsigned char *)truncated, strlen(truncated), 10,
            "bad.stl:5:", "'vertex' was expected");
    static const char word[] = "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                               "vertex 1 0 0\nvertx 0 1 0\nendloop\nendfacet\nendsolid\n";
    refused("ASCII misspelt word", (const unsigned char *)word, strlen(word), 10, "bad.stl:6:",
            "'vertx'");
    static const char nan_text[] = "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                                   "vertex 1 nan 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n";
    refused("ASCII NaN vertex", (const unsigned char *)nan_text, strlen(nan_text), 10,
            "bad.stl:5:", "finite");
    static const char inf_text[] = "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                                   "vertex 1 0 0\nvertex 0 1e999 0\nendloop\nendfacet\nendsolid\n";
    refused("ASCII overflowing vertex", (const unsigned char *)inf_text, strlen(inf_text), 10,
            "bad.stl:6:", "finite");
    static const char no_end[] = "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                                 "vertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
    refused("ASCII without endsolid", (const unsigned char *)no_end, strlen(no_end), 10,
            "bad.stl:8:", "endsolid");
    static const char empty[] = "solid x\nendsolid x\n";
    refused("ASCII with no facet", (const unsigned char *)empty, strlen(empty), 10, "bad.stl",
            "no triangle");
    double tri[12][9];
    cube(tri);
    static char text[8192];
    size_t tn = ascii_of(tri, 12, text, sizeof text);
    refused("ASCII cube over a limit of 11", (const unsigned char *)text, tn, 11, "12 facets",
            "surface.max_triangles");
    static unsigned char bin[84 + 50 * 12];
    size_t bn = binary_of(tri, 12, bin);
    refused("binary cube over a limit of 11", bin, bn, 11, "byte 80", "surface.max_triangles");
    refused("binary cut short by one byte", bin, bn - 1, 100, "byte 80", "holds 683");
    unsigned char nan_bin[84 + 50 * 12];
    memcpy(nan_bin, bin, bn);
    put32(nan_bin + 84 + 50 * 3 + 12 + 4 * 4, 0x7fc00000u); /* triangle 3, vertex 2, y */
    refused("binary NaN coordinate", nan_bin, bn, 100, "byte 262", "not a finite number");
    refused("a short file that is neither", (const unsigned char *)"hello", 5, 10, "bad.stl: byte 0",
            "not an STL file");
    stl_mesh out;
    char err[512];
    check(stl_load("/nonexistent/none.stl", 10, "k", &out, NULL, 0, err, sizeof err) == -1 &&
              strstr(err, "/nonexistent/none.stl"),
          "a missing file: %s", err);
}

int main(void)
{
    test_cube();
    test_malformed();
    return test_finish();
}
