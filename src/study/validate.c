/* validate.c: the validation cases (see validate.h). Each case builds table
 * 1's rod, loads it, runs the scheme and compares one number with an
 * independent reference from reference.h. */
#include "study/validate.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/clocks.h"
#include "sim/rod.h"
#include "study/reference.h"
#include "base/spectrum.h"
#include "base/vec3.h"

/* The most steps one validation run may take (the finest default runs take
 * under 1e5; 4e6 is minutes at NS = 201). */
#define VALIDATE_MAX_STEPS 4e6

/* rod_buckling_factor (owner: ends) is linked in when its header exists. */
#if defined(__has_include)
#if __has_include("study/buckling.h")
#include "study/buckling.h"
#define VALIDATE_HAVE_BUCKLING 1
#endif
#endif
#ifndef VALIDATE_HAVE_BUCKLING
#define VALIDATE_HAVE_BUCKLING 0
#endif

typedef enum {
    CASE_SETTLE,    /* a static load: the static scheme solves it, dynamic ones settle */
    CASE_BUCKLING,  /* rod_buckling_factor on the straight rod */
    CASE_FREQUENCY  /* impulse response, spectral peak */
} case_kind;

typedef enum {
    LOAD_TIP_SMALL, LOAD_TIP_LARGE, LOAD_FULL_CIRCLE,             /* CASE_SETTLE */
    BUCKLE_AXIAL, BUCKLE_TWIST_PINNED, BUCKLE_TWIST_CLAMPED,      /* CASE_BUCKLING */
    MODE_BENDING_1, MODE_BENDING_2, MODE_BENDING_3, MODE_TORSION  /* CASE_FREQUENCY */
} case_id;

typedef struct case_def {
    const char *name;
    case_kind kind;
    case_id id;
    const char *quantity; /* with unit */
} case_def;

static const case_def cases[] = {
    {"tip_load_small", CASE_SETTLE, LOAD_TIP_SMALL, "tip y, dead 4.5e-7 N along +y, m"},
    {"tip_load_large", CASE_SETTLE, LOAD_TIP_LARGE, "tip y, dead PL^2/EI = 10 along +y, m"},
    {"full_circle", CASE_SETTLE, LOAD_FULL_CIRCLE, "|r_tip|/L, tip moment ML/EI = 2 pi"},
    {"buckling_axial", CASE_BUCKLING, BUCKLE_AXIAL, "critical axial tip force, N"},
    {"buckling_twist_pinned", CASE_BUCKLING, BUCKLE_TWIST_PINNED,
     "critical twisting moment, pinned ends, N m"},
    {"buckling_twist_clamped", CASE_BUCKLING, BUCKLE_TWIST_CLAMPED,
     "critical twisting moment, clamped ends, N m"},
    {"bending_frequency_1", CASE_FREQUENCY, MODE_BENDING_1, "1st bending frequency, Hz"},
    {"bending_frequency_2", CASE_FREQUENCY, MODE_BENDING_2, "2nd bending frequency, Hz"},
    {"bending_frequency_3", CASE_FREQUENCY, MODE_BENDING_3, "3rd bending frequency, Hz"},
    {"torsion_frequency", CASE_FREQUENCY, MODE_TORSION, "1st torsional frequency, Hz"},
};
enum { case_count = (int)(sizeof cases / sizeof cases[0]) };

const char *const *validate_case_names(void)
{
    static const char *names[case_count + 1];
    for (int c = 0; c < case_count; c++) names[c] = cases[c].name;
    names[case_count] = NULL;
    return names;
}

int validate_case_index(const char *case_name)
{
    for (int c = 0; c < case_count; c++)
        if (strcmp(cases[c].name, case_name) == 0) return c;
    return -1;
}

int validate_case_depends_on_dt(const char *case_name, rod_scheme_kind scheme)
{
    int c = validate_case_index(case_name);
    return c >= 0 && cases[c].kind == CASE_FREQUENCY && scheme != ROD_SCHEME_STATIC;
}

double validate_order_fit(const double *h, const double *error, int n)
{
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int used = 0;
    for (int k = 0; k < n; k++) {
        if (!(error[k] > 0.0) || !(h[k] > 0.0) || !isfinite(error[k])) continue;
        double x = log(h[k]), y = log(error[k]);
        sx += x; sy += y; sxx += x * x; sxy += x * y;
        used++;
    }
    double denominator = used * sxx - sx * sx;
    if (used < 2 || fabs(denominator) < 1e-12) return NAN;
    return (used * sxy - sx * sy) / denominator;
}

/* Helpers --------------------------------------------------------------- */

static void note(validate_row *row, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void note(validate_row *row, const char *fmt, ...)
{
    size_t used = strlen(row->note);
    if (used + 3 >= sizeof row->note) return;
    if (used) {
        strcpy(row->note + used, "; ");
        used += 2;
    }
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(row->note + used, sizeof row->note - used, fmt, ap);
    va_end(ap);
}

static void set_result(validate_row *row, double computed, double reference)
{
    row->computed = computed;
    row->reference = reference;
    row->relative_error = fabs(computed - reference) / fabs(reference);
}

static const double *tip_position(const rod_state *s) { return &s->position[3 * (s->nodes - 1)]; }

/* Table 1's rod for the scheme, `nodes` nodes. */
static rod_model table1(rod_scheme_kind scheme, int nodes)
{
    rod_model m = rod_model_default();
    m.nodes = nodes;
    m.options.scheme = scheme;
    return m;
}

static int derive(rod_model *m, validate_row *row)
{
    char err[256];
    if (rod_model_derive(m, err, sizeof err) == 0) return 0;
    row->status = 2;
    note(row, "model: %s", err);
    return -1;
}

/* Steps the model from rest for `duration` s; calls `sample` after every
 * step when not NULL. Returns the state (caller destroys) or NULL with the
 * row marked failed. */
typedef void (*sample_fn)(const rod_model *m, const rod_state *s, void *context);

static rod_state *simulate(const rod_model *m, double dt, double duration, sample_fn sample,
                           void *context, validate_row *row, rod_report *report)
{
    char err[256];
    rod_solver solver;
    rod_state *s = rod_state_create(m);
    if (!s || rod_solver_init(&solver, m, err, sizeof err) != 0) {
        row->status = 2;
        note(row, "%s", s ? err : "out of memory");
        rod_state_destroy(s);
        return NULL;
    }
    memset(report, 0, sizeof *report);
    /* A dt beyond the duration would run no step and report the initial
     * state as the answer; one far below it would overflow the count or run
     * for days: either is a failed row, checked before the cast. */
    double step_count = ceil(duration / dt - 1e-9);
    if (!(step_count >= 1.0 && step_count <= VALIDATE_MAX_STEPS)) {
        rod_solver_release(&solver);
        rod_state_destroy(s);
        row->status = 2;
        note(row, "dt %g s gives %.3g steps for %g s; accepted: 1 to %.0f steps", dt, fmax(step_count, 0.0),
             duration, VALIDATE_MAX_STEPS);
        return NULL;
    }
    long steps = (long)step_count;
    rod_status status = ROD_OK;
    for (long k = 0; k < steps && status == ROD_OK; k++) {
        status = rod_solver_step(&solver, m, s, dt, report);
        if (status == ROD_OK && !rod_state_is_finite(s)) status = ROD_UNSTABLE;
        if (status == ROD_OK && sample) sample(m, s, context);
    }
    rod_solver_release(&solver);
    if (status != ROD_OK) {
        row->status = 2;
        note(row, "%s at t = %.4g s: %.100s", status == ROD_UNSTABLE ? "unstable" : "failed",
             s->time, report->message);
        rod_state_destroy(s);
        return NULL;
    }
    return s;
}

/* The thesis scheme diverges with physical rotary inertia (scheme_thesis.c:
 * minimum_scale); its report suggests a scale. A short probe of the case's own
 * model reads it, and the case runs with it (said in the note). */
static void thesis_scale_from_report(rod_model *m, validate_row *row)
{
    rod_model probe = *m;
    probe.rotary_inertia_scale = 1.0;
    char err[256];
    if (rod_model_derive(&probe, err, sizeof err) != 0) return;
    const char *why = NULL;
    double dt = rod_choose_dt(&probe, &why);
    if (!(dt > 0.0) || !isfinite(dt)) dt = 1e-3;
    validate_row scratch = {0};
    rod_report report;
    rod_state *s = simulate(&probe, dt, 20.0 * dt, NULL, NULL, &scratch, &report);
    rod_state_destroy(s);
    if (!s && report.suggested_scale > 0.0) {
        m->rotary_inertia_scale = report.suggested_scale;
        note(row, "rotary inertia x %.3g (the scheme's suggestion)", report.suggested_scale);
    }
}

/* Settled static loads -------------------------------------------------- */

static void run_settle(const case_def *c, rod_scheme_kind scheme, int nodes, double dt,
                       validate_row *row)
{
    rod_model m = table1(scheme, nodes);
    if (derive(&m, row)) return;
    const double ei = m.stiffness[0], length = m.length;
    double reference = 0.0;
    elastica_tip exact = {0};
    if (c->id == LOAD_FULL_CIRCLE) {
        m.tip_moment[1] = 2.0 * M_PI * ei / length; /* about d2 = +z: the rod curls toward +y */
    } else {
        double force = c->id == LOAD_TIP_SMALL ? 4.5e-7 : 10.0 * ei / (length * length);
        m.tip_frame = ROD_FRAME_GLOBAL;
        m.tip_force[1] = force;
        if (elastica_dead_load(ei, length, 0.0, force, 0.0, 8000, &exact) != 0) {
            row->status = 2;
            note(row, "elastica reference: no root bracketed");
            return;
        }
        reference = exact.y;
    }
    double duration = 1.0;
    if (scheme == ROD_SCHEME_STATIC) {
        dt = 0.0; /* one equilibrium solve at the full load */
    } else {
        /* ramp the load and let damping settle the rod (tests/sim/test_scheme_implicit.c) */
        int large = c->id != LOAD_TIP_SMALL;
        m.profile.kind = ROD_PROFILE_RAMP;
        if (scheme == ROD_SCHEME_IMPLICIT) {
            m.profile.t1 = large ? 20.0 : 2.0;
            m.linear_damping = 4e-4; /* about critical for the first mode */
            duration = large ? 300.0 : 150.0;
            if (dt <= 0.0) dt = 0.5;
        } else {
            thesis_scale_from_report(&m, row);
            m.profile.t1 = large ? 60.0 : 10.0;
            m.linear_damping = 1e-3; /* settles the slowed first mode in ~100 s */
            duration = large ? 600.0 : 300.0;
        }
        if (derive(&m, row)) return;
        if (dt <= 0.0) {
            const char *limit = NULL;
            dt = fmin(0.5 * rod_scheme_thesis.stable_dt(&m, &limit), 0.1);
        }
    }
    row->dt = dt;
    rod_report report;
    double start = wall_seconds(), cpu_start = cpu_seconds();
    rod_state *s = simulate(&m, scheme == ROD_SCHEME_STATIC ? 1.0 : dt, duration, NULL, NULL,
                            row, &report);
    row->wall_seconds = wall_seconds() - start;
    row->cpu_seconds = cpu_seconds() - cpu_start;
    if (!s) {
        rod_model_release(&m);
        return;
    }
    const double *tip = tip_position(s);
    if (c->id == LOAD_FULL_CIRCLE) {
        /* the tip returns to the root: the error is |r_tip| itself, in units of L */
        row->computed = v3_norm(tip) / length;
        row->reference = 0.0;
        row->relative_error = row->computed;
        note(row, "absolute error relative to L");
    } else {
        set_result(row, tip[1], reference);
        if (c->id == LOAD_TIP_SMALL)
            note(row, "PL^3/3EI = %.6g m (small-deflection limit)",
                 4.5e-7 * pow(length, 3) / (3.0 * ei));
    }
    if (scheme != ROD_SCHEME_STATIC) {
        double speed = v3_norm(&s->velocity[3 * (s->nodes - 1)]);
        note(row, "settled %.0f s, tip speed %.1e m/s", duration, speed);
    }
    rod_state_destroy(s);
    rod_model_release(&m);
}

/* Buckling ---------------------------------------------------------------- */

static void run_buckling(const case_def *c, rod_scheme_kind scheme, int nodes, validate_row *row)
{
    rod_model m = table1(ROD_SCHEME_STATIC, nodes);
    if (derive(&m, row)) return;
    const double ei = m.stiffness[0], length = m.length;
    double unit = 0.0, reference = 0.0;
    m.tip_frame = ROD_FRAME_GLOBAL; /* dead loads: conservative, so the static criterion holds */
    if (c->id == BUCKLE_AXIAL) {
        reference = reference_euler_cantilever(ei, length);
        unit = ei / (length * length);
        m.tip_force[0] = -unit; /* compression along -x */
    } else {
        int pinned = c->id == BUCKLE_TWIST_PINNED;
        reference = pinned ? reference_greenhill_pinned(ei, length)
                           : reference_greenhill_clamped(ei, length);
        unit = ei / length;
        m.tip_moment[0] = unit; /* twisting moment about the rod's axis x */
        m.root_end = pinned ? ROD_END_PINNED : ROD_END_CLAMPED;
        m.tip_end = pinned ? ROD_END_PINNED : ROD_END_CLAMPED;
        m.tip_slide[0] = 1.0; /* Greenhill's tip slides along the axis: explicit) */
    }
    row->reference = reference;
    (void)scheme; /* not_applicable() leaves only the static scheme here */
    if (derive(&m, row)) return;
#if VALIDATE_HAVE_BUCKLING
    char err[256];
    double lambda = 0.0;
    double start = wall_seconds(), cpu_start = cpu_seconds();
    int failed = rod_buckling_factor(&m, 20.0, 1e-7, &lambda, err, sizeof err);
    row->wall_seconds = wall_seconds() - start;
    row->cpu_seconds = cpu_seconds() - cpu_start;
    if (failed) {
        row->status = 2;
        note(row, "rod_buckling_factor: %.120s", err);
    } else {
        set_result(row, lambda * unit, reference);
    }
#else
    (void)unit; /* not_applicable() stops here first */
#endif
    rod_model_release(&m);
}

/* Frequencies from an impulse response ------------------------------------ */

typedef struct signal {
    double *samples;
    int count, capacity;
    int torsion;
} signal;

/* Tip transverse velocity (d1) for bending, tip spin (omega3) for torsion:
 * after an impulse at the tip every mode has about the same velocity
 * amplitude there (the displacement falls as 1/omega_n), so higher modes
 * stand out of the spectrum as clearly as the first. */
static void sample_tip(const rod_model *m, const rod_state *s, void *context)
{
    (void)m;
    signal *sig = context;
    if (sig->count >= sig->capacity) return;
    int tip = s->nodes - 1;
    sig->samples[sig->count++] =
        sig->torsion ? s->angular_velocity[3 * tip + 2] : s->velocity[3 * tip + 0];
}

/* Lowering of the n-th bending frequency by a rotary inertia rho I s per
 * length (Rayleigh beam): 1/sqrt(1 + rho I s k^2/m), k = beta_n. Used only to
 * centre the search band and to explain the thesis scheme's rows. */
static double rayleigh_factor(const rod_model *m, int mode)
{
    double k = reference_cantilever_root(mode) / m->length;
    return 1.0 / sqrt(1.0 + m->rotary_inertia[0] * k * k / m->mass_per_length);
}

/* Table 1's rod for a frequency case: Crank-Nicolson for the implicit
 * scheme, the suggested rotary inertia scale for the thesis scheme. Fills
 * the reference, the frequency expected of the model solved (the search band
 * is centred on it) and dt (when *dt <= 0, the default: 2000 steps per
 * period, so Crank-Nicolson's phase error (2 pi/2000)^2/12 = 8e-7 stays below
 * the error in ds at NS = 201; for the thesis scheme at most half its stable
 * limit). Returns 0, or -1 with the row marked. */
static int frequency_prepare(const case_def *c, rod_scheme_kind scheme, int nodes, double *dt,
                             rod_model *m, double *reference, double *expected,
                             validate_row *row)
{
    *m = table1(scheme, nodes);
    m->options.theta = 0.5; /* Crank-Nicolson: second order, no numerical damping */
    if (derive(m, row)) return -1;
    int torsion = c->id == MODE_TORSION, mode = torsion ? 1 : 1 + (int)(c->id - MODE_BENDING_1);
    *reference =
        torsion ? reference_torsion_frequency(m->shear_modulus, m->density, m->length)
                : reference_cantilever_frequency(mode, m->stiffness[0], m->mass_per_length,
                                                 m->length);
    *expected = *reference;
    if (scheme == ROD_SCHEME_THESIS) {
        /* a small pulse to read the scale the scheme needs */
        m->tip_force[0] = 1e-9;
        m->profile.kind = ROD_PROFILE_PULSE;
        m->profile.t2 = 1.0;
        thesis_scale_from_report(m, row);
        m->tip_force[0] = 0.0;
        m->profile.kind = ROD_PROFILE_STEP;
        if (derive(m, row)) return -1;
        if (torsion) {
            /* the scaled inertia rho J s is the model solved: its exact frequency */
            *reference = reference_torsion_frequency(
                m->shear_modulus, m->density * m->rotary_inertia_scale, m->length);
            *expected = *reference;
            note(row, "reference sqrt(G/(rho s))/(4L) of the scaled model");
        } else {
            *expected = *reference * rayleigh_factor(m, mode);
            note(row, "Rayleigh beam with that inertia: f x %.3f", rayleigh_factor(m, mode));
        }
    }
    if (*dt <= 0.0) {
        *dt = 1.0 / (2000.0 * *expected);
        if (scheme == ROD_SCHEME_THESIS) {
            const char *limit = NULL;
            *dt = fmin(*dt, 0.5 * rod_scheme_thesis.stable_dt(m, &limit));
        }
    }
    return 0;
}

double validate_default_dt(const char *case_name, rod_scheme_kind scheme, int nodes)
{
    if (!validate_case_depends_on_dt(case_name, scheme)) return 0.0;
    validate_row scratch = {0};
    rod_model m;
    double dt = 0.0, reference, expected;
    int c = validate_case_index(case_name);
    if (frequency_prepare(&cases[c], scheme, nodes, &dt, &m, &reference, &expected, &scratch))
        dt = 0.0;
    rod_model_release(&m);
    return dt;
}

static void run_frequency(const case_def *c, rod_scheme_kind scheme, int nodes, double dt,
                          validate_row *row)
{
    rod_model m;
    double reference, expected;
    int torsion = c->id == MODE_TORSION;
    if (frequency_prepare(c, scheme, nodes, &dt, &m, &reference, &expected, row)) {
        rod_model_release(&m);
        return;
    }
    row->reference = reference;
    row->dt = dt;
    double period = 1.0 / expected;
    /* The Hann-windowed peak of a record of P periods is biased by the
     * neighbouring mode and the negative-frequency image: measured on two
     * synthetic sines, 2.5e-5 at P = 8, 1.5e-6 at 16, 9e-8 at 32 (as P^-4).
     * 24 periods: ~3e-7. Modes 2 and 3 get 48: their records hold only a few
     * periods of the lower modes, whose leakage (measured) flattened the
     * order in ds at NS = 201 with 24. */
    const double periods = c->id == MODE_BENDING_2 || c->id == MODE_BENDING_3 ? 48.0 : 24.0;
    double duration = periods * period;
    double step_count = ceil(duration / dt - 1e-9);
    if (!(step_count >= 1.0 && step_count <= VALIDATE_MAX_STEPS)) {
        row->status = 2;
        note(row, "dt %g s gives %.3g steps for %g periods; accepted: 1 to %.0f steps", dt,
             step_count, periods, VALIDATE_MAX_STEPS);
        rod_model_release(&m);
        return;
    }
    long steps = (long)step_count;
    /* a short pulse (a tenth of the period) of small impulse: linear response.
     * Target amplitude: tip deflection ~1e-4 L (bending), twist ~1e-3 rad */
    double pulse = fmax(0.1 * period, 2.0 * dt);
    m.profile.kind = ROD_PROFILE_PULSE;
    m.profile.t1 = 0.0;
    m.profile.t2 = pulse;
    double omega = 2.0 * M_PI * expected;
    if (torsion) {
        double inertia = m.rotary_inertia[2] > 0.0 ? m.rotary_inertia[2]
                                                   : m.density * m.polar_moment;
        m.tip_moment[2] = 1e-3 * inertia * m.length * omega / 4.0 / pulse;
    } else {
        m.tip_force[0] = 1e-4 * m.mass_per_length * m.length * m.length * omega / 4.0 / pulse;
    }
    if (derive(&m, row)) return;
    signal sig = {.samples = malloc(sizeof(double) * (size_t)steps), .capacity = (int)steps,
                  .torsion = torsion};
    if (!sig.samples) {
        row->status = 2;
        note(row, "out of memory");
        rod_model_release(&m);
        return;
    }
    rod_report report;
    double start = wall_seconds(), cpu_start = cpu_seconds();
    rod_state *s = simulate(&m, dt, duration, sample_tip, &sig, row, &report);
    if (s) {
        /* search from the pulse's end: the forced part is not free vibration */
        int skip = (int)ceil(pulse / dt);
        double lo = 0.75 * expected, hi = 1.25 * expected;
        double f = spectrum_peak(sig.samples + skip, sig.count - skip, dt, lo, hi);
        set_result(row, f, reference);
        if (f < lo + 1e-3 * (hi - lo) || f > hi - 1e-3 * (hi - lo)) {
            row->status = 2;
            note(row, "no peak inside the band [%.4g, %.4g] Hz", lo, hi);
        }
        note(row, "%ld steps%s", steps, scheme == ROD_SCHEME_IMPLICIT ? ", Crank-Nicolson" : "");
    }
    row->wall_seconds = wall_seconds() - start;
    row->cpu_seconds = cpu_seconds() - cpu_start;
    rod_state_destroy(s);
    free(sig.samples);
    rod_model_release(&m);
}

/* Why a case does not apply to a scheme, or NULL when it does. */
static const char *not_applicable(const case_def *c, rod_scheme_kind scheme)
{
    if (c->kind == CASE_FREQUENCY && scheme == ROD_SCHEME_STATIC)
        return "the static scheme has no dynamics: no frequencies";
    if (c->kind == CASE_BUCKLING && scheme != ROD_SCHEME_STATIC)
        return "buckling is found on the static equilibrium (rod_buckling_factor), not by "
               "time stepping: see the static row";
    if (c->kind == CASE_BUCKLING && !VALIDATE_HAVE_BUCKLING)
        return "not yet available: rod_buckling_factor (include/study/buckling.h) not merged";
    return NULL;
}

static void row_start(validate_row *row, const char *case_name, rod_scheme_kind scheme,
                      int nodes)
{
    memset(row, 0, sizeof *row);
    snprintf(row->case_name, sizeof row->case_name, "%s", case_name);
    const rod_scheme_ops *ops = rod_scheme_get(scheme);
    snprintf(row->scheme, sizeof row->scheme, "%s", ops ? ops->name : "?");
    row->nodes = nodes;
    row->computed = row->reference = row->relative_error = NAN;
}

int validate_applicable(const char *case_name, rod_scheme_kind scheme, validate_row *row)
{
    int c = validate_case_index(case_name);
    row_start(row, case_name, scheme, 0);
    if (c < 0 || !rod_scheme_get(scheme)) {
        row->status = 2;
        note(row, c < 0 ? "unknown case" : "unknown scheme");
        return 0;
    }
    snprintf(row->quantity, sizeof row->quantity, "%s", cases[c].quantity);
    const char *why = not_applicable(&cases[c], scheme);
    if (!why) return 1;
    row->status = 1;
    note(row, "%s", why);
    return 0;
}

int validate_run(const char *case_name, rod_scheme_kind scheme, int nodes, double dt,
                 validate_row *row)
{
    int c = validate_case_index(case_name);
    if (!validate_applicable(case_name, scheme, row)) {
        row->nodes = nodes;
        return row->status == 1 ? 1 : -1;
    }
    row->nodes = nodes;
    switch (cases[c].kind) {
    case CASE_SETTLE: run_settle(&cases[c], scheme, nodes, dt, row); break;
    case CASE_BUCKLING: run_buckling(&cases[c], scheme, nodes, row); break;
    case CASE_FREQUENCY: run_frequency(&cases[c], scheme, nodes, dt, row); break;
    }
    if (row->status != 0 && row->status != 1) row->status = 2;
    return row->status;
}
