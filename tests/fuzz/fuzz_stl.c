/* fuzz_stl.c: libFuzzer harness for the STL reader (base/stl.c): stl_parse
 * on the bytes as they are, then the mesh made of what it accepts
 * (sim/contact/mesh.c) and a distance query. Checks the contract (stl.h):
 * on failure a message naming the file and no triangles; on success 1 to
 * the limit of triangles, every coordinate finite, none degenerate kept,
 * and a finite signed distance with a unit normal. */
#include <math.h>

#include "base/stl.h"
#include "fuzz.h"
#include "sim/contact/mesh.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define LIMIT 4096

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char name[] = "fuzz.stl";
    char err[1024] = "", warn[512] = "";
    stl_mesh out;
    int rc = stl_parse(name, data, size, LIMIT, "surface.max_triangles", &out, warn, sizeof warn,
                       err, sizeof err);
    if (rc) {
        fuzz_require(fuzz_starts(err, name), "an STL message names the file", err);
        fuzz_require(out.triangles == NULL && out.triangle_count == 0, "no triangles on failure",
                     err);
        return 0;
    }
    fuzz_require(out.triangle_count >= 1 && out.triangle_count <= LIMIT,
                 "1 to the limit of triangles", NULL);
    fuzz_require(out.dropped == 0 || fuzz_starts(warn, name), "a warning names the file", warn);
    for (int k = 0; k < 9 * out.triangle_count; k++)
        fuzz_require(isfinite(out.triangles[k]), "finite coordinates", NULL);
    rod_mesh *m = rod_mesh_create(out.triangles, out.triangle_count, NULL, err, sizeof err);
    fuzz_require(m != NULL, "a mesh of what the reader accepts", err);
    double lo[3], hi[3], p[3], n[3], near[3];
    rod_mesh_bounds(m, lo, hi);
    for (int c = 0; c < 3; c++) p[c] = 0.5 * (lo[c] + hi[c]) + 0.1 * (hi[c] - lo[c]);
    double d = rod_mesh_distance(m, p, n, near);
    if (isfinite(hi[0] - lo[0]) && isfinite(hi[1] - lo[1]) && isfinite(hi[2] - lo[2])) {
        fuzz_require(isfinite(d), "a finite distance", NULL);
        fuzz_require(fabs(sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) - 1.0) < 1e-9,
                     "a unit normal", NULL);
    }
    rod_mesh_destroy(m);
    stl_release(&out);
    return 0;
}
