/* bench_startup.c: what rodsim costs before it simulates anything, and what
 * --csv adds to a run. A benchmark: it reports, never fails on time.
 *
 * Start-up: the CPU (user + sys, of the child process: wait4) of
 * `rodsim --version`, `rodsim help` and `rodsim run --no-video` of a tiny
 * scene (11 nodes, 0.01 s), median and lowest of BENCH_STARTUP_RUNS (20).
 *
 * CSV: scenes/suture.ini --no-video without and with --csv to a scratch
 * file, run in pairs (one after the other, so a slower spell of the shared
 * machine hits both), BENCH_CSV_PAIRS (3) pairs: the median CPU of each and
 * the median of the pairs' ratios. Then the cost of one number's text: 10^6
 * doubles of a simulation's sizes (1e-9 to 1 m, random mantissa) by
 * printf's %.10g and %.17g and by dtoa_shortest, the CSV's. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <sys/wait.h>
#include <unistd.h>

#include "base/dtoa.h"
#include "test.h"

#define NUMBERS 1000000

/* CPU seconds (user + sys) of RODSIM_BIN with args; -1 when it failed. */
static double child_cpu(const char *const *args)
{
    const char *argv[16];
    int n = 0;
    argv[n++] = RODSIM_BIN;
    for (int i = 0; args[i] && n < 15; i++) argv[n++] = args[i];
    argv[n] = NULL;
    fflush(stdout);
    pid_t pid = fork();
    if (pid < 0) return -1.0;
    if (pid == 0) {
        if (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr)) _exit(127);
        execv(RODSIM_BIN, (char *const *)argv);
        _exit(127);
    }
    int status;
    struct rusage use;
    if (wait4(pid, &status, 0, &use) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return -1.0;
    return (double)use.ru_utime.tv_sec + 1e-6 * (double)use.ru_utime.tv_usec +
           (double)use.ru_stime.tv_sec + 1e-6 * (double)use.ru_stime.tv_usec;
}

static double process_cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ns per number of %.10g, %.17g and dtoa_shortest over the same values. */
static void number_rows(void)
{
    double *value = malloc(NUMBERS * sizeof *value);
    if (!value) return;
    unsigned long long state = 0x9E3779B97F4A7C15ull;
    for (int i = 0; i < NUMBERS; i++) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        double mantissa = 1.0 + (double)(state >> 11) * 0x1p-53;
        value[i] = mantissa * pow(10.0, -9.0 + 9.0 * (double)(i % 997) / 997.0);
        if (state >> 63) value[i] = -value[i];
    }
    char text[64];
    long chars[3] = {0, 0, 0};
    double t0 = process_cpu();
    for (int i = 0; i < NUMBERS; i++) chars[0] += snprintf(text, sizeof text, "%.10g", value[i]);
    double t1 = process_cpu();
    for (int i = 0; i < NUMBERS; i++) chars[1] += snprintf(text, sizeof text, "%.17g", value[i]);
    double t2 = process_cpu();
    for (int i = 0; i < NUMBERS; i++) chars[2] += dtoa_shortest(text, value[i]);
    double t3 = process_cpu();
    printf("one number's text, %d doubles of 1e-9 to 1 (signed)\n", NUMBERS);
    printf("%-34s %10s %10s\n", "formatter", "ns each", "chars each");
    printf("%-34s %10.1f %10.2f\n", "printf %.10g (10 digits)", 1e9 * (t1 - t0) / NUMBERS,
           (double)chars[0] / NUMBERS);
    printf("%-34s %10.1f %10.2f\n", "printf %.17g (round trip)", 1e9 * (t2 - t1) / NUMBERS,
           (double)chars[1] / NUMBERS);
    printf("%-34s %10.1f %10.2f\n", "dtoa_shortest (round trip, CSV)", 1e9 * (t3 - t2) / NUMBERS,
           (double)chars[2] / NUMBERS);
    free(value);
}

static int compare(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, compare);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static int env_count(const char *name, int fallback)
{
    const char *s = getenv(name);
    int n = s ? atoi(s) : fallback;
    return n >= 1 && n <= 1000 ? n : fallback;
}

static void startup_row(const char *what, const char *const *args, int runs)
{
    double cpu[1000];
    for (int i = 0; i < runs; i++) {
        cpu[i] = child_cpu(args);
        if (cpu[i] < 0) {
            printf("%-34s failed\n", what);
            return;
        }
    }
    double med = median(cpu, runs);
    printf("%-34s %10.1f %10.1f\n", what, 1e3 * med, 1e3 * cpu[0]);
}

int main(void)
{
    const char *tiny_scene = test_path("tiny.ini");
    FILE *f = fopen(tiny_scene, "w");
    if (!f) {
        printf("bench_startup: cannot write %s\n", tiny_scene);
        return 1;
    }
    fprintf(f, "[rod]\nlength = 1.0\ndiameter = 0.001\ndensity = 850\nyoungs_modulus = 87.5e6\n"
               "shear_modulus = 31.25e6\nnodes = 11\n[solver]\nduration = 0.01\n");
    fclose(f);
    const int runs = env_count("BENCH_STARTUP_RUNS", 20);
    printf("rodsim start-up: CPU (user + sys) of the process, %d runs each\n", runs);
    printf("%-34s %10s %10s\n", "command", "median ms", "lowest ms");
    const char *version[] = {"--version", NULL};
    const char *help[] = {"help", NULL};
    const char *tiny[] = {"run", tiny_scene, "--no-video", "--quiet", NULL};
    startup_row("rodsim --version", version, runs);
    startup_row("rodsim help", help, runs);
    startup_row("rodsim run --no-video (11 nodes)", tiny, runs);
    remove(tiny_scene);

    const int pairs = env_count("BENCH_CSV_PAIRS", 3);
    const char *csv = test_path("suture.csv");
    const char *plain[] = {"run", RODSIM_SOURCE_DIR "/scenes/suture.ini", "--no-video", "--quiet",
                           NULL};
    const char *with_csv[] = {"run", RODSIM_SOURCE_DIR "/scenes/suture.ini", "--no-video", "--quiet",
                              "--csv", csv, NULL};
    printf("rodsim run --csv: scenes/suture.ini --no-video without and with --csv, %d pairs\n",
           pairs);
    printf("%10s %10s %10s\n", "plain s", "csv s", "ratio");
    double a[1000], b[1000], ratio[1000];
    for (int i = 0; i < pairs; i++) {
        a[i] = child_cpu(plain);
        b[i] = child_cpu(with_csv);
        if (a[i] <= 0 || b[i] <= 0) {
            printf("  failed\n");
            test_dir_remove();
            return 1;
        }
        ratio[i] = b[i] / a[i];
        printf("%10.3f %10.3f %9.3fx\n", a[i], b[i], ratio[i]);
    }
    FILE *c = fopen(csv, "rb");
    long bytes = 0;
    if (c) {
        fseek(c, 0, SEEK_END);
        bytes = ftell(c);
        fclose(c);
    }
    remove(csv);
    double ma = median(a, pairs), mb = median(b, pairs), mr = median(ratio, pairs);
    printf("median: %.3f s without, %.3f s with --csv (%.1f MB): ratio %.3fx, the CSV %.3f s\n",
           ma, mb, 1e-6 * (double)bytes, mr, mb - ma);
    number_rows();
    test_dir_remove();
    return 0;
}
