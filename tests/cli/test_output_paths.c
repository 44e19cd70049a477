/* test_output_paths.c: an output path that cannot be used is refused before
 * any work (exit 2), and the message names the option the user gave for it
 * (a --csv under a file names --csv, not -o), and nothing is written.
 * --tissue-csv takes a file only: "-" is refused (it is no standard output
 * there), not written as a file named "-"; a --tissue-csv under a file, or
 * naming a directory, is refused up front like --csv (exit 2), not after
 * the run (exit 1). fem's --png FILE beside --no-png is refused (exit 2),
 * not silently drawn nowhere. validate's and stability's --csv are checked
 * before their runs (minutes of them), not after (exit 1). fem's --csv,
 * --md, --png, --svg and -o, and figure's --out, --csv and --result are
 * checked before the scene is solved or a point computed (nothing of the
 * work printed: no nodal table, no point line), not after (exit 1). A
 * device (/dev/null) is written in place, so it passes the check where its
 * folder is not writable (a user who is not root: /dev), and a device that
 * cannot be written is refused naming it. */
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <sys/wait.h>

#include "cli/args.h"
#include "test.h"
#include "test_process.h"

static char tmp_dir[] = "/tmp/rodsim_output_paths_XXXXXX";
static char blocker[96]; /* a plain file: no directory can be made under it */

static const char scene_text[] =
    "[rod]\nlength = 1.0\ndiameter = 0.001\ndensity = 850\nyoungs_modulus = 87.5e6\n"
    "shear_modulus = 31.25e6\nnodes = 11\n[solver]\nscheme = static\nduration = 0.1\n";

/* Runs args, expects exit 2 and a message holding `option` and not `other`. */
static void expect_named(const char *what, const char *const *args, const char *option,
                         const char *other)
{
    char output[4096];
    int status = test_run_rodsim(args, output, sizeof output);
    char *nl = strchr(output, '\n');
    if (nl) *nl = '\0';
    check(status == 2 && strstr(output, option) && !(other && strstr(output, other)),
          "%s: exit %d (want 2), message '%s' names '%s'%s%s", what, status, output, option,
          other ? ", not " : "", other ? other : "");
}

static void test_messages_name_the_option(const char *scene)
{
    char under[160];
    snprintf(under, sizeof under, "%s/sub/x.csv", blocker);
    const char *csv[] = {"run", scene, "--no-video", "--csv", under, NULL};
    expect_named("run --csv under a file", csv, "--csv", "-o ");
    char dir[160];
    snprintf(dir, sizeof dir, "%s/sub", blocker);
    const char *video[] = {"run", scene, "-o", dir, NULL};
    expect_named("run -o under a file", video, "-o ", NULL);
    const char *summary[] = {"run", scene, "--no-video", "--summary", under, NULL};
    expect_named("run --summary under a file", summary, "--summary", "-o ");
    const char *sweep_csv[] = {"sweep", scene, "--vary", "rod.nodes=11,21", "--csv", under, NULL};
    expect_named("sweep --csv under a file", sweep_csv, "--csv", "-o ");
    char png[160];
    snprintf(png, sizeof png, "%s/sub/x.png", blocker);
    const char *sweep_png[] = {"sweep",      scene, "--vary", "rod.nodes=11,21", "--plot",
                               "rod.nodes:tip_y", "--png", png, NULL};
    expect_named("sweep --png under a file", sweep_png, "--png", "-o ");
    const char *pad = RODSIM_SOURCE_DIR "/scenes/suture_elastic.ini";
    const char *tissue[] = {"run", pad, "--no-video", "--set", "solver.duration=0.02",
                            "--tissue-csv", under, NULL};
    expect_named("run --tissue-csv under a file", tissue, "--tissue-csv", "-o ");
    const char *tissue_dir[] = {"run", pad, "--no-video", "--set", "solver.duration=0.02",
                                "--tissue-csv", tmp_dir, NULL};
    expect_named("run --tissue-csv naming a directory", tissue_dir, "--tissue-csv", NULL);
    const char *validate[] = {"validate", "--case", "tip_load_small", "--scheme", "static",
                              "--nodes", "11", "--csv", under, NULL};
    expect_named("validate --csv under a file", validate, "--csv", "-o ");
    const char *stability[] = {"stability", "--scheme", "static", "--quick", "--csv", under,
                               NULL};
    expect_named("stability --csv under a file", stability, "--csv", "-o ");
    const char *result[] = {"sweep", scene, "--vary", "rod.nodes=11,21", "--result", dir, NULL};
    expect_named("sweep --result under a file", result, "--result", "-o ");
}

/* Runs args, expects exit 2 before any work: a message naming `option`
 * and `path`, and none of `work` (what the work prints first) */
static void expect_before_work(const char *what, const char *const *args, const char *option,
                               const char *path, const char *work)
{
    char output[8192];
    int status = test_run_rodsim(args, output, sizeof output);
    int worked = strstr(output, work) != NULL;
    char *nl = strchr(output, '\n');
    if (nl) *nl = '\0';
    check(status == 2 && strstr(output, option) && strstr(output, path) && !worked,
          "%s: exit %d (want 2), message '%s' names '%s' and the path; '%s' %s", what, status,
          output, option, work, worked ? "printed (the work was done)" : "not printed");
}

static void test_fem_and_figure(void)
{
    const char *fem_scene = RODSIM_SOURCE_DIR "/scenes/fishing_rod.ini";
    const char *table = "condition number"; /* the nodal table's heading */
    char under[4][160], dir[160];
    const char *const option[4] = {"--csv", "--md", "--png", "--svg"};
    for (int i = 0; i < 4; i++) {
        snprintf(under[i], sizeof under[i], "%s/sub/x.%s", blocker, option[i] + 2);
        const char *args[] = {"fem", fem_scene, option[i], under[i], NULL};
        char what[64];
        snprintf(what, sizeof what, "fem %s under a file", option[i]);
        expect_before_work(what, args, option[i], under[i], table);
    }
    snprintf(dir, sizeof dir, "%s/sub", blocker);
    const char *fem_dir[] = {"fem", fem_scene, "-o", dir, NULL};
    expect_before_work("fem -o under a file", fem_dir, "-o ", dir, table);
    const char *fem_csv_dir[] = {"fem", fem_scene, "--no-png", "--csv", tmp_dir, NULL};
    expect_before_work("fem --csv naming a directory", fem_csv_dir, "--csv", tmp_dir, table);
    /* each computes a point first, printing its count ("1 point") */
    const char *figure_out[] = {"figure", "impulse", "--quick", "--out", dir, NULL};
    expect_before_work("figure --out under a file", figure_out, "--out", dir, "point");
    const char *sweep_out[] = {"figure", "buckling-length", "--quick", "--out", dir, NULL};
    expect_before_work("figure (a sweep figure) --out under a file", sweep_out, "--out", dir,
                       "point");
    const char *figure_csv[] = {"figure", "impulse", "--quick", "--point", "0", "--csv",
                                under[0], NULL};
    expect_before_work("figure --point --csv under a file", figure_csv, "--csv", under[0],
                       "point 0");
    const char *figure_result[] = {"figure", "buckling-length", "--quick", "--point", "0",
                                   "--result", dir, NULL};
    expect_before_work("figure --point --result under a file", figure_result, "--result", dir,
                       "point 1");
}

/* The elastic pad's scene, run briefly in tmp_dir (cwd), so that a file
 * named "-" would land there. */
static void test_tissue_csv_dash(void)
{
    char output[4096], cwd[512];
    if (!getcwd(cwd, sizeof cwd) || chdir(tmp_dir)) {
        check(0, "chdir %s", tmp_dir);
        return;
    }
    const char *args[] = {"run", RODSIM_SOURCE_DIR "/scenes/suture_elastic.ini", "--no-video",
                          "--quiet", "--set", "solver.duration=0.02", "--tissue-csv", "-", NULL};
    int status = test_run_rodsim(args, output, sizeof output);
    char *nl = strchr(output, '\n');
    if (nl) *nl = '\0';
    int dash_written = access("-", F_OK) == 0;
    unlink("-");
    check(status == 2 && strstr(output, "--tissue-csv") && !dash_written,
          "run --tissue-csv -: exit %d (want 2), message '%s', a file named '-' %s", status,
          output, dash_written ? "written (want none)" : "not written");
    if (chdir(cwd)) check(0, "chdir back to %s", cwd);
}

static void test_fem_png_and_no_png(void)
{
    char png[128], output[4096];
    snprintf(png, sizeof png, "%s/rod.png", tmp_dir);
    const char *args[] = {"fem", RODSIM_SOURCE_DIR "/scenes/fishing_rod.ini", "--png", png,
                          "--no-png", NULL};
    int status = test_run_rodsim(args, output, sizeof output);
    char *nl = strchr(output, '\n');
    if (nl) *nl = '\0';
    check(status == 2 && strstr(output, "--no-png") && access(png, F_OK) != 0,
          "fem --png FILE --no-png: exit %d (want 2), '%s', no PNG", status, output);
}

/* The check as a user who may not write in /dev (root's children become
 * nobody, uid 65534; another user is one already): /dev/null is accepted,
 * /dev/rodsim-no-such-device refused naming the option and the path. The
 * child's verdicts come back as its exit status (bit 0, bit 1). */
static void test_device_output(void)
{
    pid_t pid = fork();
    if (pid == 0) {
        if (geteuid() == 0 && (setgid(65534) != 0 || setuid(65534) != 0)) _exit(4);
        if (access("/dev", W_OK) == 0) _exit(8); /* /dev writable: proves nothing */
        char err[512] = "";
        int null_ok = cli_check_output_file("--csv", "/dev/null", err, sizeof err) == 0;
        int missing_refused =
            cli_check_output_file("--csv", "/dev/rodsim-no-such-device", err, sizeof err) != 0 &&
            strstr(err, "--csv /dev/rodsim-no-such-device") != NULL;
        _exit((null_ok ? 0 : 1) | (missing_refused ? 0 : 2));
    }
    int status = -1;
    if (pid > 0) waitpid(pid, &status, 0);
    int code = pid > 0 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    check(code == 0 || code == 2, "--csv /dev/null, /dev not writable: accepted (child %d)", code);
    check(code == 0 || code == 1, "--csv /dev/rodsim-no-such-device: refused naming it (child %d)",
          code);
}

int main(void)
{
    test_device_output();
    if (!mkdtemp(tmp_dir)) {
        check(0, "mkdtemp %s", tmp_dir);
        return test_finish();
    }
    char scene[96];
    snprintf(scene, sizeof scene, "%s/rod.ini", tmp_dir);
    test_write_in(tmp_dir, "rod.ini", scene_text);
    snprintf(blocker, sizeof blocker, "%s/file", tmp_dir);
    test_write_in(tmp_dir, "file", "not a directory\n");

    test_messages_name_the_option(scene);
    test_tissue_csv_dash();
    test_fem_png_and_no_png();
    test_fem_and_figure();

    check(test_dir_entries(tmp_dir) == 2, "nothing written beside the scene and the file: %d "
          "entries (want 2)", test_dir_entries(tmp_dir));
    test_remove_tree(tmp_dir);
    return test_finish();
}
