/* fuzz_fem_scene.c: libFuzzer harness for beam FEM scenes, the path of
 * `rodsim fem` up to the figure: ini_parse -> fem_scene_read (cli/fem_cli.c,
 * which checks the model and runs ini_check_unused) -> fem_solve. */
#include "base/ini.h"
#include "cli/fem_cli.h"
#include "fem/fem.h"
#include "fuzz.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Larger models are read but not solved: the banded solve is O(n) but would
 * slow every such input down to milliseconds. */
#define SOLVE_MAX_NODES 2000

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char name[] = "fuzz_fem.ini";
    char *text = fuzz_text(data, size);
    char err[1024] = "";
    ini_doc *doc = ini_parse(name, text, err, sizeof err);
    if (!doc) {
        fuzz_require(fuzz_starts(err, name), "an ini_parse message names the file", err);
        free(text);
        return 0;
    }
    fem_figure_options figure;
    fem_model *m = fem_scene_read(doc, &figure, err, sizeof err);
    if (!m) {
        fuzz_require(fuzz_starts(err, name), "a fem_scene_read message names the file", err);
    } else {
        fuzz_require(m->node_count >= 2, "a read model has 2 nodes or more", NULL);
        for (int i = 0; i < m->support_count; i++)
            fuzz_require(m->supports[i].node >= 0 && m->supports[i].node < m->node_count,
                         "supports lie on nodes", NULL);
        for (int i = 0; i < m->load_count; i++)
            fuzz_require(m->loads[i].node >= 0 && m->loads[i].node < m->node_count,
                         "loads lie on nodes", NULL);
        if (m->node_count <= SOLVE_MAX_NODES) {
            fem_solution *s = fem_solution_create(m->node_count);
            if (!s) abort();
            char solve_err[768] = "";
            fem_status st = fem_solve(m, s, solve_err, sizeof solve_err);
            fuzz_require(st == FEM_OK || solve_err[0] != '\0', "a failed solve says why", NULL);
            fem_solution_destroy(s);
        }
        fem_model_destroy(m);
    }
    ini_destroy(doc);
    free(text);
    return 0;
}
