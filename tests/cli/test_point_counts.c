/* test_point_counts.c: the counts of points that sweep and figure print
 * read as English: "1 point", "2 points", never "1 points". A sweep without
 * --vary (one point), its --print-commands, --snakefile and --sbatch
 * headers, --assemble with the point missing ("1 of 1 point has"), a sweep
 * of two points, and figure --list's impulse figure (one point). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "test.h"
#include "test_process.h"

#define SCENE RODSIM_SOURCE_DIR "/scenes/table2_450nN.ini"

/* Runs rodsim; checks the exit status, that `want` is in what it printed
 * and that "1 points" is not. */
static void expect(const char *what, const char *const *args, int status, const char *want)
{
    static char output[1 << 16];
    int rc = test_run_rodsim_within(args, 120, output, sizeof output);
    int has = strstr(output, want) != NULL, wrong = strstr(output, "1 points") != NULL;
    check(rc == status && has && !wrong, "%s: exit %d (want %d), \"%s\" %s, \"1 points\" %s",
          what, rc, status, want, has ? "printed" : "MISSING", wrong ? "PRINTED" : "absent");
    if (!has || wrong) printf("%s\n", output);
}

/* Checks that the file at path holds `want` and not "1 points". */
static void expect_file(const char *path, const char *want)
{
    static char text[1 << 16];
    FILE *f = fopen(path, "r");
    size_t got = f ? fread(text, 1, sizeof text - 1, f) : 0;
    if (f) fclose(f);
    text[got] = '\0';
    int has = strstr(text, want) != NULL, wrong = strstr(text, "1 points") != NULL;
    check(has && !wrong, "%s: \"%s\" %s, \"1 points\" %s", path, want,
          has ? "written" : "MISSING", wrong ? "WRITTEN" : "absent");
}

int main(void)
{
    const char *one[] = {"sweep", SCENE, "--csv", test_path("one.csv"), NULL};
    expect("sweep without --vary", one, 0, "rodsim sweep: 1 point: 1 run;");
    const char *two[] = {"sweep", SCENE, "--vary", "rod.nodes=11,21", "--csv",
                         test_path("two.csv"), NULL};
    expect("sweep of two points", two, 0, "rodsim sweep: 2 points: 2 run;");
    const char *missing[] = {"sweep", SCENE, "--result", test_path("empty"), "--assemble", "--csv",
                             test_path("assembled.csv"), NULL};
    if (mkdir(test_path("empty"), 0700) != 0) return 1;
    expect("--assemble, the one point missing", missing, 1,
           "rodsim sweep: 1 of 1 point has no result");
    const char *commands[] = {"sweep", SCENE, "--result", test_path("res"), "--print-commands",
                              NULL};
    expect("--print-commands of one point", commands, 0, "# rodsim sweep: 1 point of ");
    const char *snake[] = {"sweep", SCENE, "--result", test_path("res"), "--csv",
                           test_path("snake.csv"), "--snakefile", test_path("Snakefile"), NULL};
    expect("--snakefile of one point", snake, 0, "Snakefile (1 point); run: snakemake");
    expect_file(test_path("Snakefile"), "--snakefile: 1 point of ");
    const char *sbatch[] = {"sweep", SCENE, "--result", test_path("res"), "--sbatch",
                            test_path("job.sh"), NULL};
    expect("--sbatch of one point", sbatch, 0, "");
    expect_file(test_path("job.sh"), "--sbatch: 1 point of ");
    const char *list[] = {"figure", "--list", NULL};
    expect("figure --list", list, 0, "impulse            1 point  (1 quick)");
    return test_finish();
}
