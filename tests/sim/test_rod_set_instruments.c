/* test_rod_set_instruments.c: instruments in a scene of several rods
 * (sim/rod_set.h): forceps closing on the upper of two crossing threads
 * take it (the nearest rod), lift it off the pads and hold it in the air:
 * the grasped material point follows the jaws' motion within 5 % of d, the
 * jaws carry the lifted thread's weight rho A L g (closed form) and the
 * lower thread does not move; the same forceps kept to the lower rod (rod =
 * lower) close on nothing and say so; rod = NAME naming no rod is refused
 * with the names accepted, scissors are read; a single named rod steps as
 * the bare [rod]. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/ini.h"
#include "base/vec3.h"
#include "sim/instrument.h"
#include "sim/rod_set.h"
#include "test.h"
#include "test_rod_set.h"

#define GRAVITY 9.81 /* m/s^2 */
#define DIAMETER 0.0005 /* m */
#define DENSITY 850.0   /* kg/m^3 */
#define LENGTH 0.2      /* m, the upper thread */

static char path_file[64];

/* Forceps pointing down over the gap between the pads (as grasp_lift.ini):
 * down to 8 mm under the threads by 0.8 s, closed by 1 s, lifted 13 cm
 * from 1.2 to 3.2 s, then held */
static int write_path(void)
{
    snprintf(path_file, sizeof path_file, "%s", test_path("holder.csv"));
    FILE *f = fopen(path_file, "w");
    if (!f) return -1;
    const char *rv = "1.2091996,1.2091996,-1.2091996";
    fprintf(f, "t,x,y,z,rx,ry,rz,jaw\n0,0.1,0,0.03,%s,1\n0.3,0.1,0,0.03,%s,1\n"
            "0.8,0.1,0,-0.008,%s,1\n1,0.1,0,-0.008,%s,0\n1.2,0.1,0,-0.008,%s,0\n"
            "3.2,0.1,0,0.122,%s,0\n", rv, rv, rv, rv, rv, rv);
    return fclose(f);
}

#define THREAD "diameter = 0.0005\ndensity = 850\nyoungs_modulus = 87.5e6\n" \
               "shear_modulus = 31.25e6\n"
/* Two pads 2 cm apart (their tops at z = 0), gravity, the forceps */
#define SHARED "[surface]\nshape = box\ncenter = 0 0 -0.005\nsize = 0.18 0.1 0.01\nfriction = 0.3\n" \
               "[surface]\nshape = box\ncenter = 0.2 0 -0.005\nsize = 0.18 0.1 0.01\nfriction = 0.3\n" \
               "[solver]\nscheme = implicit\ndt = 0.001\nduration = 5\n" \
               "[loads]\ngravity = 0 0 -9.81\nlinear_damping = 4e-4\n"

/* The upper thread along x over the lower one (along y at x = 0.04) on
 * the left pad; the instrument of `kind`, `extra`: more of its keys */
static void two_threads(char *out, size_t n, const char *kind, const char *extra)
{
    snprintf(out, n,
             "[rod upper]\nlength = 0.2\n" THREAD "nodes = 41\norigin = 0 0 0.00075\n"
             "direction = 1 0 0\n[ends upper]\nroot = free\ntip = free\n"
             "[rod lower]\nlength = 0.1\n" THREAD "nodes = 21\norigin = 0.04 -0.05 0.00025\n"
             "direction = 0 1 0\n[ends lower]\nroot = free\ntip = free\n" SHARED
             "[instrument]\nkind = %s\nname = forceps\npath = %s\nsize = 0.12\n"
             "friction = 0.3\ngrip = 2\n%s",
             kind, path_file, extra);
}

/* The thread's point at arc length s (m) */
static void point_at(const rod_model *m, const rod_state *s, double arc, double p[3])
{
    double u = arc / m->ds;
    int j = (int)floor(u);
    if (j > m->nodes - 2) j = m->nodes - 2;
    const double f = u - j;
    for (int c = 0; c < 3; c++)
        p[c] = (1.0 - f) * s->position[3 * j + c] + f * s->position[3 * (j + 1) + c];
}

static void test_lift_upper(void)
{
    char text[4096], err[1024];
    two_threads(text, sizeof text, "forceps", "");
    rod_set set;
    rod_set_run run;
    int ok = test_read_set(text, &set, err, sizeof err) == 0;
    if (!check(ok, "two threads and forceps read (%s)", ok ? "ok" : err)) return;
    if (!check(rod_set_run_create(&set, &run, err, sizeof err) == 0, "run made (%s)", err)) {
        rod_set_release(&set);
        return;
    }
    const rod_model *up = &set.model[0], *low = &set.model[1];
    const rod_instrument *in = &up->instruments[0];
    const double dt = 0.001;
    rod_report report;
    memset(&report, 0, sizeof report);
    int failed = 0, grasp_step = -1;
    double held_s = 0.0, start_point[3] = {0}, start_tip[3] = {0}, follow = 0.0;
    double *low_rest = malloc(sizeof(double) * 3 * (size_t)low->nodes), low_moved = 0.0;
    double force_sum = 0.0;
    int force_count = 0;
    for (int i = 0; i < 5000 && !failed; i++) {
        failed = rod_set_step(&set, &run, dt, &report) != ROD_OK;
        const rod_state *su = run.state[0], *sl = run.state[1];
        const rod_grasp_state *g = &su->grasp[0];
        if (i == 899) memcpy(low_rest, sl->position, sizeof(double) * 3 * (size_t)low->nodes);
        if (i > 899)
            for (int b = 0; b < low->nodes; b++) {
                double d[3];
                v3_sub(d, &sl->position[3 * b], &low_rest[3 * b]);
                low_moved = fmax(low_moved, v3_norm(d));
            }
        rod_pose pose;
        rod_instrument_pose(in, su->time, &pose, NULL);
        if (grasp_step < 0 && g->held) {
            grasp_step = i;
            held_s = g->s;
            point_at(up, su, held_s, start_point);
            v3_copy(start_tip, pose.position);
        } else if (grasp_step >= 0 && su->time <= 3.2 + 1e-9) {
            /* the jaws only translate: the held point moves as their tip */
            double p[3], expect[3], d[3];
            point_at(up, su, held_s, p);
            v3_sub(expect, pose.position, start_tip);
            v3_add(expect, expect, start_point);
            v3_sub(d, p, expect);
            follow = fmax(follow, v3_norm(d));
        }
        if (su->time > 4.5) {
            force_sum += v3_norm(g->force);
            force_count++;
        }
    }
    check(!failed, "5 s stepped (%s)", failed ? report.message : "ok");
    const rod_state *su = run.state[0], *sl = run.state[1];
    check(su->grasp[0].held && !sl->grasp[0].held,
          "the forceps hold the upper thread (%d), not the lower (%d)", su->grasp[0].held,
          sl->grasp[0].held);
    check(grasp_step >= 0 && fabs(held_s - 0.1) < 0.005,
          "grasped at s = %.5f m, under the jaws at 0.1 m, at t = %.4f s", held_s,
          grasp_step >= 0 ? (grasp_step + 1) * dt : -1.0);
    check(follow < 0.05 * DIAMETER,
          "the grasped point follows the jaws while lifted 13 cm: %.3g m off, %.3g d "
          "(at most 0.05 d)", follow, follow / DIAMETER);
    const double weight = DENSITY * 0.25 * acos(-1.0) * DIAMETER * DIAMETER * LENGTH * GRAVITY;
    const double force = force_count ? force_sum / force_count : 0.0;
    check(fabs(force - weight) < 0.02 * weight,
          "jaws carry the lifted thread (4.5 .. 5 s): %.6g N, rho A L g = %.6g N, rel %.2e "
          "(within 2 %%)", force, weight, fabs(force - weight) / weight);
    double lowest = INFINITY;
    for (int b = 0; b < up->nodes; b++) lowest = fmin(lowest, su->position[3 * b + 2]);
    check(lowest > 0.01, "the upper thread is off the pad: its lowest point at z = %.4f m",
          lowest);
    check(low_moved < 0.1 * DIAMETER,
          "the lower thread stays: its nodes move %.3g m (%.3g d) from 0.9 s on (at most 0.1 d)",
          low_moved, low_moved / DIAMETER);
    check(su->grasp_log_count == 1 && sl->grasp_log_count == 0,
          "one grasp logged, on the upper thread (%d, %d)", su->grasp_log_count,
          sl->grasp_log_count);
    free(low_rest);
    rod_set_run_destroy(&run);
    rod_set_release(&set);
}

/* rod = lower: the jaws close 6 cm from the lower thread, on nothing */
static void test_kept_to_lower(void)
{
    char text[4096], err[1024];
    two_threads(text, sizeof text, "forceps", "rod = lower\n");
    rod_set set;
    rod_set_run run;
    int ok = test_read_set(text, &set, err, sizeof err) == 0;
    if (!check(ok, "rod = lower read (%s)", ok ? "ok" : err)) return;
    if (!check(rod_set_run_create(&set, &run, err, sizeof err) == 0, "run made (%s)", err)) {
        rod_set_release(&set);
        return;
    }
    rod_report report;
    memset(&report, 0, sizeof report);
    char warning[sizeof report.warning] = "";
    int failed = 0;
    for (int i = 0; i < 1100 && !failed; i++) {
        failed = rod_set_step(&set, &run, 0.001, &report) != ROD_OK;
        if (report.warning[0] && !warning[0]) snprintf(warning, sizeof warning, "%s", report.warning);
    }
    check(!failed && !run.state[0]->grasp[0].held && !run.state[1]->grasp[0].held,
          "rod = lower: neither thread grasped");
    check(strstr(warning, "closed its jaws") && strstr(warning, "on nothing"),
          "a warning: %s", warning);
    rod_set_run_destroy(&run);
    rod_set_release(&set);
}

static void test_refusals(void)
{
    char text[4096], err[1024] = "";
    rod_set set;
    two_threads(text, sizeof text, "forceps", "rod = middle\n");
    int rc = test_read_set(text, &set, err, sizeof err);
    check(rc != 0 && strstr(err, "test.ini:") && strstr(err, "rod") &&
              strstr(err, "'middle' names no rod") && strstr(err, "upper lower"),
          "rod = middle refused: %s", err);
    /* scissors cut the rod nearest them (test_rod_set_cut) */
    two_threads(text, sizeof text, "scissors", "");
    err[0] = '\0';
    rc = test_read_set(text, &set, err, sizeof err);
    if (rc == 0) rod_set_release(&set);
    check(rc == 0, "scissors with several rods read: %s", rc == 0 ? "ok" : err);
}

/* One named rod with the forceps steps exactly as the bare [rod] */
static void test_one_named(void)
{
    char named[4096], bare[4096], err[1024];
    const char *form = "[%s]\nlength = 0.2\n" THREAD "nodes = 41\norigin = 0 0 0.00025\n"
                       "direction = 1 0 0\n[%s]\nroot = free\ntip = free\n" SHARED
                       "[instrument]\nkind = forceps\npath = %s\nsize = 0.12\ngrip = 2\n%s";
    snprintf(named, sizeof named, form, "rod thread", "ends thread", path_file, "rod = thread\n");
    snprintf(bare, sizeof bare, form, "rod", "ends", path_file, "");
    rod_set a, b;
    rod_set_run ra, rb;
    if (!check(test_read_set(named, &a, err, sizeof err) == 0, "one named rod read (%s)", err)) return;
    if (!check(test_read_set(bare, &b, err, sizeof err) == 0, "bare rod read (%s)", err)) {
        rod_set_release(&a);
        return;
    }
    rod_set_run_create(&a, &ra, err, sizeof err);
    rod_set_run_create(&b, &rb, err, sizeof err);
    rod_report report;
    int failed = 0;
    for (int i = 0; i < 1500 && !failed; i++)
        failed = rod_set_step(&a, &ra, 0.001, &report) != ROD_OK ||
                 rod_set_step(&b, &rb, 0.001, &report) != ROD_OK;
    double worst = 0.0;
    for (int k = 0; k < 3 * a.model[0].nodes; k++)
        worst = fmax(worst, fabs(ra.state[0]->position[k] - rb.state[0]->position[k]));
    check(!failed && ra.state[0]->grasp[0].held && rb.state[0]->grasp[0].held && worst == 0.0,
          "one named rod, grasped and lifted to 1.5 s: positions differ from the bare [rod]'s "
          "by %.3g m", worst);
    rod_set_run_destroy(&ra);
    rod_set_run_destroy(&rb);
    rod_set_release(&a);
    rod_set_release(&b);
}

int main(void)
{
    if (!check(write_path() == 0, "the forceps' path written")) return test_finish();
    test_lift_upper();
    test_kept_to_lower();
    test_refusals();
    test_one_named();
    unlink(path_file);
    return test_finish();
}
