/* test_stability.c: dt = auto per scheme and physics (rod_choose_dt), and the
 * stability sweep on a reduced grid: every run completes or stops with the
 * scheme's message (no crash, no hang, no NaN), the explicit scheme's
 * measured limit against the independent formula, the implicit scheme
 * stable at the largest dt tried, the wall-time guard, CSV and map. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "sim/rod.h"
#include "study/stability.h"
#include "cli/stability_cli.h"
#include "test.h"

/* Independent formulas ------------------------------------------------------ */

/* The bending rotation wave of the thesis scheme with rotary inertia scaled
 * by s: 2 ds sqrt(rho s/E) sqrt(1 - 16 ds^2/(d^2 s)) (von Neumann, kappa = 1/ds). */
static double formula_bending_dt(const rod_model *m)
{
    double ds = m->ds, d = m->diameter, s = m->rotary_inertia_scale;
    return 2.0 * ds * sqrt(m->density * s / m->youngs_modulus) *
           sqrt(1.0 - 16.0 * ds * ds / (d * d * s));
}

static double formula_twist_dt(const rod_model *m)
{
    return 2.0 * m->ds / sqrt(m->shear_modulus / (m->density * m->rotary_inertia_scale));
}

/* 1.8751^2 / (2 pi L^2) sqrt(EI / (rho A)), Hz */
static double formula_first_frequency(const rod_model *m)
{
    double d = m->diameter, L = m->length;
    double ei = m->youngs_modulus * M_PI * pow(d, 4) / 64.0;
    double mass = m->density * M_PI * d * d / 4.0;
    return 1.8751040687 * 1.8751040687 / (2.0 * M_PI * L * L) * sqrt(ei / mass);
}

static rod_model model(rod_scheme_kind scheme, double scale)
{
    rod_model m = rod_model_default();
    m.options.scheme = scheme;
    m.rotary_inertia_scale = scale;
    char err[256];
    if (rod_model_derive(&m, err, sizeof err)) printf("model: %s\n", err);
    return m;
}

static void derive(rod_model *m)
{
    char err[256];
    if (rod_model_derive(m, err, sizeof err)) printf("model: %s\n", err);
}

/* 1. dt = auto ---------------------------------------------------------------- */

static void test_dt_auto(void)
{
    const char *why = NULL;

    /* thesis, planar tip load, scale 2e7: half the bending rotation-wave limit */
    rod_model t = model(ROD_SCHEME_THESIS, 2e7);
    t.tip_force[0] = 1e-7; /* follower on d1: planar */
    derive(&t);
    double dt = rod_choose_dt(&t, &why);
    printf("thesis, planar: dt = %g s (%s)\n", dt, why);
    check_rel("dt auto, thesis, planar: 0.5 x 2 ds sqrt(rho s/E) sqrt(1 - 16 ds^2/(d^2 s))", dt,
              0.5 * formula_bending_dt(&t), 1e-9);
    check(strstr(why, "bending") != NULL, "the limit named is bending (%s)", why);

    /* G = 40 E makes twist the fastest wave: non-planar load, twist on -> twist
       decides; twist off -> bending decides; planar -> bending decides */
    rod_model g = model(ROD_SCHEME_THESIS, 2e7);
    g.shear_modulus = 40.0 * g.youngs_modulus;
    g.tip_moment[2] = 1e-8; /* a twisting load */
    derive(&g);
    dt = rod_choose_dt(&g, &why);
    printf("thesis, G = 40 E, twisting load: dt = %g s (%s)\n", dt, why);
    check_rel("dt auto, twist on, twisting load: 0.5 x 2 ds / sqrt(G/(rho s))", dt,
              0.5 * formula_twist_dt(&g), 1e-9);
    check(strstr(why, "twist") != NULL, "the limit named is twist (%s)", why);
    g.physics.twist = 0;
    derive(&g);
    dt = rod_choose_dt(&g, &why);
    printf("thesis, G = 40 E, twist off: dt = %g s (%s)\n", dt, why);
    check_rel("dt auto, twist off: 0.5 x the bending limit (no twist cap)", dt,
              0.5 * formula_bending_dt(&g), 1e-9);
    g.physics.twist = 1;
    g.tip_moment[2] = 0.0;
    g.tip_force[0] = 1e-7; /* planar: no twisting load, no initial twist */
    derive(&g);
    dt = rod_choose_dt(&g, &why);
    check_rel("dt auto, twist on but planar load (twist never excited): bending limit", dt,
              0.5 * formula_bending_dt(&g), 1e-9);

    /* a step chosen by dt = auto runs: 2000 steps, no report */
    rod_solver solver;
    char err[256];
    rod_state *s = rod_state_create(&t);
    rod_report report;
    rod_status status = ROD_FAILED;
    if (s && rod_solver_init(&solver, &t, err, sizeof err) == 0) {
        status = ROD_OK;
        for (int k = 0; k < 2000 && status == ROD_OK; k++)
            status = rod_solver_step(&solver, &t, s, rod_choose_dt(&t, NULL), &report);
        rod_solver_release(&solver);
    }
    check(status == ROD_OK && rod_state_is_finite(s),
          "thesis at its dt = auto: 2000 steps ran, state finite (%s)",
          status == ROD_OK ? "" : report.message);
    rod_state_destroy(s);

    /* thesis below the inertia threshold: no stable dt, and the reason */
    rod_model p = model(ROD_SCHEME_THESIS, 1.0);
    dt = rod_choose_dt(&p, &why);
    check(dt == 0.0 && strstr(why, "rotary inertia") != NULL,
          "thesis with physical inertia: dt = auto gives %g (no stable dt) because: %s", dt, why);

    /* implicit: unconditionally stable, accuracy decides */
    rod_model im = model(ROD_SCHEME_IMPLICIT, 1.0);
    dt = rod_choose_dt(&im, &why);
    printf("implicit: dt = %g s (%s)\n", dt, why);
    check_rel("dt auto, implicit: 1/20 of the first bending period 1/(20 f1)", dt,
              1.0 / (20.0 * formula_first_frequency(&im)), 1e-6);
    check(strstr(why, "accuracy") && strstr(why, "unconditionally"),
          "implicit: the reason names accuracy and unconditional stability (%s)", why);

    /* static: no time step */
    rod_model st = model(ROD_SCHEME_STATIC, 1.0);
    dt = rod_choose_dt(&st, &why);
    check(dt > 0.0 && strstr(why, "static") && strstr(why, "no time step"),
          "static: dt = %g, reason: %s", dt, why);

    /* set in the scene wins */
    im.options.dt = 0.0123;
    dt = rod_choose_dt(&im, &why);
    check(dt == 0.0123 && strcmp(why, "set in the scene") == 0, "dt set in the scene: %g (%s)",
          dt, why);
    rod_model_release(&t);
    rod_model_release(&g);
    rod_model_release(&p);
    rod_model_release(&im);
    rod_model_release(&st);
}

/* 2. the reduced grid ------------------------------------------------------ */

static void test_reduced_grid(void)
{
    int n_cases = 0;
    const stability_case *cases = stability_grid(1, &n_cases);
    static const rod_scheme_kind schemes[] = {ROD_SCHEME_THESIS, ROD_SCHEME_IMPLICIT,
                                              ROD_SCHEME_STATIC};
    const int n_schemes = 3, n = n_cases * n_schemes;
    stability_options o = stability_options_default(1);
    if (test_sanitized()) o.steps = 200;
    stability_row rows[64];
    if (n > 64) {
        check(0, "quick grid has %d rows (> 64)", n);
        return;
    }
    char err[256] = "";
    int rc = stability_sweep(cases, n_cases, schemes, n_schemes, &o, 2, rows, err, sizeof err);
    check(rc == 0, "sweep over the quick grid with 2 worker processes (%s)", err);
    stability_print_table(stdout, rows, n);

    int findings = 0, bad_outcome = 0;
    for (int k = 0; k < n; k++) {
        const stability_row *r = &rows[k];
        findings += r->finding;
        stability_outcome out = r->first_failure.outcome;
        /* allowed: completed, or stopped with the scheme's own message */
        if (!(out == STABILITY_STABLE || out == STABILITY_REPORTED ||
              out == STABILITY_NO_CONVERGENCE))
            bad_outcome++;
        if (out != STABILITY_STABLE && out != STABILITY_GREW)
            if (strlen(r->first_failure.message) < 20) bad_outcome++;
    }
    check(findings == 0, "no crash, no hang, no NaN without a message over %d runs (%d findings)",
          n, findings);
    check(bad_outcome == 0,
          "every run completed or stopped with the scheme's message (%d did not)", bad_outcome);

    for (int k = 0; k < n; k++) {
        const stability_row *r = &rows[k];
        if (r->c.load != STABILITY_LOAD_NONE) continue;
        if (r->scheme == ROD_SCHEME_IMPLICIT)
            check(r->measured_dt >= o.dt_max,
                  "implicit, %s, NS %d: stable at the largest dt tried (%g s >= %g s)", r->c.name,
                  r->c.nodes, r->measured_dt, o.dt_max);
        if (r->scheme != ROD_SCHEME_THESIS) continue;
        rod_model m;
        stability_case_model(&r->c, ROD_SCHEME_THESIS, &m, err, sizeof err);
        if (r->c.physical_inertia) {
            check(r->measured_dt == 0.0 && r->first_failure.outcome == STABILITY_REPORTED &&
                      strstr(r->first_failure.message, "rotary inertia"),
                  "thesis, physical inertia: no stable dt down to %g s; the scheme says why",
                  r->unstable_dt);
        } else if (r->unstable_dt > 0.0) {
            /* the bisection sits within 5 % of the instability (400 steps detect
               a growth of 1.006 per step); the formula is for kappa = 1/ds */
            char what[160];
            snprintf(what, sizeof what,
                     "thesis, %.40s, NS %d: largest stable dt, bisection vs 2 ds sqrt(rho s/E) "
                     "sqrt(1 - 16 ds^2/(d^2 s))", r->c.name, r->c.nodes);
            check_rel(what, r->measured_dt, formula_bending_dt(&m), 0.1);
        } else {
            check(r->predicted.scheme_dt > o.dt_max && r->measured_dt >= o.dt_max,
                  "thesis, %s: predicted limit %g s above dt_max, stable at %g s", r->c.name,
                  r->predicted.scheme_dt, r->measured_dt);
        }
        rod_model_release(&m);
    }

    /* CSV: a header and one line per row */
    char dir[] = "/tmp/rodsim_stability_XXXXXX";
    if (!mkdtemp(dir)) {
        check(0, "temporary directory");
        return;
    }
    char csv[256], png[256];
    snprintf(csv, sizeof csv, "%s/s.csv", dir);
    snprintf(png, sizeof png, "%s/map.png", dir);
    check(stability_write_csv(csv, rows, n, err, sizeof err) == 0, "CSV written (%s)", err);
    FILE *f = fopen(csv, "r");
    int lines = 0, nan_seen = 0;
    char line[1024];
    while (f && fgets(line, sizeof line, f)) {
        lines++;
        if (strstr(line, "nan") || strstr(line, "NaN")) nan_seen = 1;
    }
    if (f) fclose(f);
    check(lines == n + 1 && !nan_seen, "CSV: %d lines (expected %d), no NaN", lines, n + 1);
    plot *p = stability_map_create(rows, n);
    check(p != NULL, "map built from the table 1 rows");
    if (p) {
        int w = plot_write_png(p, png, err, sizeof err);
        struct stat st;
        check(w == 0 && stat(png, &st) == 0 && st.st_size > 1000, "map PNG written (%s)", err);
        plot_destroy(p);
    }
    unlink(csv);
    unlink(png);
    rmdir(dir);
}

/* 3. the wall-time guard -------------------------------------------------- */

static void test_wall_limit(void)
{
    /* an implicit run at NS = 1001 with a 10 ms limit cannot finish 1000 steps */
    stability_case c = {"guard", 87.5e6, 1e-3, 1.0, 1001, STABILITY_LOAD_TRANSVERSE, 1.0, 0};
    stability_options o = stability_options_default(1);
    o.implicit_steps = 1000;
    o.trial_wall_limit = 0.01;
    stability_trial t;
    stability_trial_run(&c, ROD_SCHEME_IMPLICIT, 0.01, &o, &t);
    printf("guarded trial: %s after %.3f s, %d steps: %s\n", stability_outcome_name(t.outcome),
           t.wall_seconds, t.steps_done, t.message);
    check(t.outcome == STABILITY_TIMEOUT && t.steps_done < 1000,
          "a trial over its wall-time limit ends as a timeout (a finding), not a hang");
    check(stability_outcome_is_finding(STABILITY_TIMEOUT) &&
              stability_outcome_is_finding(STABILITY_CRASHED) &&
              stability_outcome_is_finding(STABILITY_NON_FINITE) &&
              !stability_outcome_is_finding(STABILITY_REPORTED),
          "timeouts, crashes and silent NaN are findings; a reported instability is not");
}

int main(void)
{
    test_dt_auto();
    test_reduced_grid();
    test_wall_limit();
    return test_finish();
}
