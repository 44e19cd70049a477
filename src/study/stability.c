/* stability.c: largest stable dt by bisection over a grid of cases, each
 * trial optionally guarded by a child process with a wall-time limit. */
#include "study/stability.h"

#include <errno.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "base/clocks.h"
#include "base/worker.h"
#include "sim/rod.h"
#include "study/reference.h"

/* Kinetic energy past this multiple of (initial + the most work the dead tip
 * load can do) is growth no physics explains: numerical instability. */
#define GROWTH_LIMIT 100.0
/* Shear modulus as a fraction of E: table 1's 31.25 / 87.5 (nu = 0.4). */
#define SHEAR_RATIO (31.25 / 87.5)

static const char *const outcome_names[STABILITY_OUTCOME_COUNT] = {
    "stable", "reported", "no-convergence", "grew", "non-finite", "refused", "timeout", "crashed"};

const char *stability_outcome_name(stability_outcome outcome)
{
    return outcome >= 0 && outcome < STABILITY_OUTCOME_COUNT ? outcome_names[outcome] : "?";
}

int stability_outcome_is_finding(stability_outcome outcome)
{
    return outcome == STABILITY_NON_FINITE || outcome == STABILITY_TIMEOUT ||
           outcome == STABILITY_CRASHED;
}

stability_options stability_options_default(int quick)
{
    stability_options o;
    /* Trial length: above the thesis limit the top
     * mode grows by 1.11 to 1.26 per step at 0.1 % over and 1.33 to 1.39 at 1 %
     * (spectral radius of the step's Jacobian, NS 21 to 101), so the energy bound
     * (an amplitude x sqrt(100 NS)) is passed within ~60 steps at 0.1 % over and
     * ~20 at the bisection's 1 %: 400 and 2000 steps leave a wide margin. The slower
     * growths found (steps of changing size; an out-of-plane mode under load, at
     * any dt: scheme_thesis.c) are not dt limits: longer trials would only move
     * the measured "limit" down with the trial length. */
    o.steps = quick ? 400 : 2000;
    o.implicit_steps = quick ? 6 : 20;
    o.dt_max = 10.0;
    o.dt_min = 1e-7;
    o.relative_tolerance = quick ? 0.05 : 0.01;
    o.trial_wall_limit = quick ? 30.0 : 10.0;
    return o;
}

/* The grid ------------------------------------------------------------------ */

#define T1_E 87.5e6
#define T1_D 1e-3
#define T1_L 1.0
#define NONE STABILITY_LOAD_NONE, 0.0
#define TRANSVERSE(f) STABILITY_LOAD_TRANSVERSE, (f)
#define AXIAL(f) STABILITY_LOAD_AXIAL, (f)

static const stability_case full_grid[] = {
    /* resolution, table 1's rod (the map) */
    {"table1", T1_E, T1_D, T1_L, 11, NONE, 0},
    {"table1", T1_E, T1_D, T1_L, 21, NONE, 0},
    {"table1", T1_E, T1_D, T1_L, 51, NONE, 0},
    {"table1", T1_E, T1_D, T1_L, 101, NONE, 0},
    {"table1", T1_E, T1_D, T1_L, 201, NONE, 0},
    {"table1", T1_E, T1_D, T1_L, 501, NONE, 0},
    {"table1", T1_E, T1_D, T1_L, 1001, NONE, 0},
    {"table1 physical inertia", T1_E, T1_D, T1_L, 51, NONE, 1},
    /* material and size extremes, one at a time */
    {"E 1e5 Pa", 1e5, T1_D, T1_L, 51, NONE, 0},
    {"E 2e11 Pa", 2e11, T1_D, T1_L, 51, NONE, 0},
    {"d 0.1 mm", T1_E, 1e-4, T1_L, 51, NONE, 0},
    {"d 10 mm", T1_E, 1e-2, T1_L, 51, NONE, 0},
    {"L 1 cm", T1_E, T1_D, 0.01, 51, NONE, 0},
    {"L 100 m", T1_E, T1_D, 100.0, 51, NONE, 0},
    /* corners */
    {"soft thin long", 1e5, 1e-4, 100.0, 1001, NONE, 0},
    {"stiff thin short", 2e11, 1e-4, 0.01, 1001, NONE, 0},
    {"stiff thick long", 2e11, 1e-2, 100.0, 1001, NONE, 0},
    {"soft thick short", 1e5, 1e-2, 0.02, 11, NONE, 0},
    /* loads, in Euler loads pi^2 EI/(4 L^2) */
    {"table1 transverse x1", T1_E, T1_D, T1_L, 51, TRANSVERSE(1.0), 0},
    {"table1 transverse x100", T1_E, T1_D, T1_L, 51, TRANSVERSE(100.0), 0},
    {"table1 axial x1", T1_E, T1_D, T1_L, 51, AXIAL(1.0), 0},
    {"table1 axial x100", T1_E, T1_D, T1_L, 51, AXIAL(100.0), 0},
    {"table1 transverse x100", T1_E, T1_D, T1_L, 1001, TRANSVERSE(100.0), 0},
    {"table1 axial x100", T1_E, T1_D, T1_L, 1001, AXIAL(100.0), 0},
    {"stiff thin short axial x100", 2e11, 1e-4, 0.01, 101, AXIAL(100.0), 0},
    {"soft thin long transverse x100", 1e5, 1e-4, 100.0, 101, TRANSVERSE(100.0), 0},
};

static const stability_case quick_grid[] = {
    {"table1", T1_E, T1_D, T1_L, 11, NONE, 0},
    {"table1", T1_E, T1_D, T1_L, 21, NONE, 0},
    {"table1 physical inertia", T1_E, T1_D, T1_L, 11, NONE, 1},
    {"E 1e5 Pa", 1e5, T1_D, T1_L, 11, NONE, 0},
    {"E 2e11 Pa", 2e11, T1_D, T1_L, 11, NONE, 0},
    {"d 0.1 mm", T1_E, 1e-4, T1_L, 11, NONE, 0},
    {"d 10 mm", T1_E, 1e-2, T1_L, 11, NONE, 0},
    {"L 1 cm", T1_E, T1_D, 0.01, 11, NONE, 0},
    {"L 100 m", T1_E, T1_D, 100.0, 11, NONE, 0},
    {"table1 transverse x100", T1_E, T1_D, T1_L, 21, TRANSVERSE(100.0), 0},
    {"table1 axial x100", T1_E, T1_D, T1_L, 21, AXIAL(100.0), 0},
    {"stiff thin short axial x100", 2e11, 1e-4, 0.01, 11, AXIAL(100.0), 0},
};

const stability_case *stability_grid(int quick, int *count)
{
    if (quick) {
        *count = (int)(sizeof quick_grid / sizeof quick_grid[0]);
        return quick_grid;
    }
    *count = (int)(sizeof full_grid / sizeof full_grid[0]);
    return full_grid;
}

/* Model and predictions ----------------------------------------------------- */

static double thesis_scale(const stability_case *c)
{
    /* 2 x the threshold of scheme_thesis.c: a = m/(rho I s kappa_min^2) < 1 */
    return c->physical_inertia ? 1.0
                               : 2.0 * 64.0 * c->length * c->length / (M_PI * M_PI * c->diameter * c->diameter);
}

int stability_case_model(const stability_case *c, rod_scheme_kind scheme, rod_model *m,
                         char *err, size_t errlen)
{
    *m = rod_model_default();
    m->length = c->length;
    m->diameter = c->diameter;
    m->youngs_modulus = c->youngs_modulus;
    m->shear_modulus = SHEAR_RATIO * c->youngs_modulus;
    m->nodes = c->nodes;
    m->options.scheme = scheme;
    m->options.duration = 1e9;
    if (scheme == ROD_SCHEME_THESIS) m->rotary_inertia_scale = thesis_scale(c);
    double ei = c->youngs_modulus * M_PI * pow(c->diameter, 4) / 64.0;
    double force = c->load_factor * reference_euler_cantilever(ei, c->length);
    m->tip_frame = ROD_FRAME_GLOBAL;
    if (c->load == STABILITY_LOAD_TRANSVERSE) m->tip_force[1] = force;
    if (c->load == STABILITY_LOAD_AXIAL) {
        m->tip_force[0] = -force;
        m->tip_force[1] = 1e-3 * force;
    }
    return rod_model_derive(m, err, errlen);
}

void stability_predict(const stability_case *c, rod_scheme_kind scheme, stability_prediction *p)
{
    memset(p, 0, sizeof *p);
    rod_model m;
    char err[256];
    if (stability_case_model(c, ROD_SCHEME_THESIS, &m, err, sizeof err)) {
        snprintf(p->scheme_limit, sizeof p->scheme_limit, "%.190s", err);
        return;
    }
    double s = m.rotary_inertia_scale, ds = m.ds;
    p->rotary_inertia_scale = scheme == ROD_SCHEME_THESIS ? s : 1.0;
    p->euler_bernoulli_dt = 2.0 * ds * ds * sqrt(m.mass_per_length / m.stiffness[0]);
    p->twist_dt = 2.0 * ds / sqrt(m.shear_modulus / (m.density * s));
    p->rotation_wave_dt = 2.0 * ds * sqrt(m.density * s / m.youngs_modulus);
    p->rotary_inertia_gain = p->rotation_wave_dt / p->euler_bernoulli_dt;
    rod_model_release(&m);
    if (stability_case_model(c, scheme, &m, err, sizeof err)) return;
    const rod_scheme_ops *ops = rod_scheme_get(scheme);
    const char *limit = "";
    p->scheme_dt = ops->stable_dt ? ops->stable_dt(&m, &limit) : INFINITY;
    snprintf(p->scheme_limit, sizeof p->scheme_limit, "%.190s", limit);
    rod_model_release(&m);
}

/* One trial ------------------------------------------------------------------ */

/* Deterministic pseudo-random angular velocity, all components, nodes 1..NS-1. */
static void seed_perturbation(const rod_model *m, rod_state *s)
{
    /* rotations of about 1e-3 rad over a bending period: linear, yet well above the
       noise of a Newton solve (the implicit scheme's tolerance is relative to EI/L^2) */
    double amplitude = 1e-3 * sqrt(m->stiffness[0] / m->mass_per_length) / (m->length * m->length);
    unsigned seed = 2024u;
    for (int i = 1; i < m->nodes; i++)
        for (int c = 0; c < 3; c++) {
            seed = seed * 1103515245u + 12345u;
            s->angular_velocity[3 * i + c] = amplitude * (((seed >> 8) & 0xffff) / 65535.0 - 0.5);
        }
}

static void trial_in_process(const stability_case *c, rod_scheme_kind scheme, double dt,
                             const stability_options *o, stability_trial *t)
{
    memset(t, 0, sizeof *t);
    t->dt = dt;
    double start = wall_seconds();
    rod_model m;
    char err[sizeof t->message];
    if (stability_case_model(c, scheme, &m, err, sizeof err)) {
        t->outcome = STABILITY_REFUSED;
        snprintf(t->message, sizeof t->message, "%s", err);
        return;
    }
    rod_solver solver = {0};
    rod_state *s = NULL;
    if (rod_solver_init(&solver, &m, err, sizeof err)) {
        t->outcome = STABILITY_REFUSED;
        snprintf(t->message, sizeof t->message, "%s", err);
        goto done;
    }
    s = rod_state_create(&m);
    if (!s) {
        t->outcome = STABILITY_REFUSED;
        snprintf(t->message, sizeof t->message, "out of memory for %d nodes", m.nodes);
        goto done;
    }
    if (scheme != ROD_SCHEME_STATIC) seed_perturbation(&m, s);
    double force = sqrt(m.tip_force[0] * m.tip_force[0] + m.tip_force[1] * m.tip_force[1]);
    double energy_base = rod_kinetic_energy(&m, s) + force * 2.0 * m.length;
    int steps = scheme == ROD_SCHEME_STATIC ? 1
                : scheme == ROD_SCHEME_IMPLICIT ? o->implicit_steps : o->steps;
    rod_report report;
    t->outcome = STABILITY_STABLE;
    for (int k = 0; k < steps; k++) {
        rod_status status = rod_solver_step(&solver, &m, s, dt, &report);
        if (status != ROD_OK) {
            if (t->outcome == STABILITY_GREW) t->grew_first = 1;
            t->outcome = status == ROD_UNSTABLE ? STABILITY_REPORTED
                         : status == ROD_NO_CONVERGENCE ? STABILITY_NO_CONVERGENCE
                         : STABILITY_REFUSED;
            snprintf(t->message, sizeof t->message, "%.300s", report.message);
            break;
        }
        t->steps_done = k + 1;
        if (!rod_state_is_finite(s)) {
            t->outcome = STABILITY_NON_FINITE;
            snprintf(t->message, sizeof t->message,
                     "the state became non-finite at step %d and the scheme said nothing", k + 1);
            break;
        }
        double ratio = rod_kinetic_energy(&m, s) / energy_base;
        if (ratio > t->energy_ratio) t->energy_ratio = ratio;
        if (ratio > GROWTH_LIMIT && t->outcome == STABILITY_STABLE) {
            /* unstable; keep stepping (up to `steps` more) to see whether the
               scheme itself says so before anything becomes non-finite */
            t->outcome = STABILITY_GREW;
            snprintf(t->message, sizeof t->message,
                     "kinetic energy %.3g x (initial + 2 L |F|) at step %d; the scheme said "
                     "nothing within %d more steps", ratio, k + 1, steps);
            steps = k + 1 + steps;
        }
        if (o->trial_wall_limit > 0.0 && wall_seconds() - start > o->trial_wall_limit) {
            t->outcome = STABILITY_TIMEOUT;
            snprintf(t->message, sizeof t->message,
                     "%d of %d steps took more than %g s of wall time", k + 1, steps,
                     o->trial_wall_limit);
            break;
        }
    }
done:
    rod_state_destroy(s);
    rod_solver_release(&solver);
    rod_model_release(&m);
    t->wall_seconds = wall_seconds() - start;
}

/* Reads exactly n bytes (or fewer at end of file); returns the count. */
static size_t read_all(int fd, void *buffer, size_t n)
{
    size_t got = 0;
    while (got < n) {
        ssize_t r = read(fd, (char *)buffer + got, n - got);
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) break;
        got += (size_t)r;
    }
    return got;
}

static void write_all(int fd, const void *buffer, size_t n)
{
    size_t put = 0;
    while (put < n) {
        ssize_t w = write(fd, (const char *)buffer + put, n - put);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return;
        put += (size_t)w;
    }
}

/* The trial in a child process: a step that never returns, or a crash, is
 * reported instead of taking the sweep down. */
static void trial_guarded(const stability_case *c, rod_scheme_kind scheme, double dt,
                          const stability_options *o, stability_trial *t)
{
    int fd[2];
    if (pipe(fd) != 0) {
        trial_in_process(c, scheme, dt, o, t);
        return;
    }
    fflush(stdout);
    fflush(stderr);
    double start = wall_seconds();
    pid_t parent = getpid();
    pid_t pid = fork();
    if (pid < 0) {
        close(fd[0]);
        close(fd[1]);
        trial_in_process(c, scheme, dt, o, t);
        return;
    }
    if (pid == 0) {
        worker_begin(parent); /* dies with its parent */
        close(fd[0]);
        stability_trial result;
        trial_in_process(c, scheme, dt, o, &result);
        write_all(fd[1], &result, sizeof result);
        _exit(0);
    }
    close(fd[1]);
    /* the child's own limit ends a slow run between steps; this one ends a
     * step that never returns (2 x the limit + 1 s) */
    double limit = 2.0 * o->trial_wall_limit + 1.0;
    int ready = 0;
    for (;;) {
        double left = limit - (wall_seconds() - start);
        if (left <= 0.0) break;
        struct pollfd p = {.fd = fd[0], .events = POLLIN};
        int r = poll(&p, 1, (int)ceil(left * 1000.0));
        if (r < 0 && errno == EINTR) continue;
        ready = r > 0;
        break;
    }
    size_t got = ready ? read_all(fd[0], t, sizeof *t) : 0;
    close(fd[0]);
    int status = 0;
    if (!ready) kill(pid, SIGKILL);
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (got == sizeof *t) return;
    memset(t, 0, sizeof *t);
    t->dt = dt;
    t->wall_seconds = wall_seconds() - start;
    if (!ready) {
        t->outcome = STABILITY_TIMEOUT;
        snprintf(t->message, sizeof t->message,
                 "one step did not return within %.3g s of wall time (killed)", limit);
    } else {
        t->outcome = STABILITY_CRASHED;
        if (WIFSIGNALED(status))
            snprintf(t->message, sizeof t->message, "the trial died on signal %d (%s)",
                     WTERMSIG(status), strsignal(WTERMSIG(status)));
        else
            snprintf(t->message, sizeof t->message, "the trial exited with status %d, no result",
                     WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    }
}

void stability_trial_run(const stability_case *c, rod_scheme_kind scheme, double dt,
                         const stability_options *o, stability_trial *t)
{
    if (o->trial_wall_limit > 0.0) trial_guarded(c, scheme, dt, o, t);
    else trial_in_process(c, scheme, dt, o, t);
}

/* Bisection -------------------------------------------------------------------- */

static int try_dt(const stability_case *c, rod_scheme_kind scheme, double dt,
                  const stability_options *o, stability_row *row)
{
    stability_trial t;
    stability_trial_run(c, scheme, dt, o, &t);
    row->trials++;
    if (stability_outcome_is_finding(t.outcome)) row->finding = 1;
    if (t.outcome == STABILITY_STABLE) {
        if (dt > row->measured_dt) row->measured_dt = dt;
        return 1;
    }
    if (row->unstable_dt == 0.0 || dt < row->unstable_dt) {
        row->unstable_dt = dt;
        row->first_failure = t;
    }
    return 0;
}

void stability_find(const stability_case *c, rod_scheme_kind scheme, const stability_options *o,
                    stability_row *row)
{
    double start = wall_seconds();
    memset(row, 0, sizeof *row);
    row->c = *c;
    row->scheme = scheme;
    row->first_failure.outcome = STABILITY_STABLE;
    stability_predict(c, scheme, &row->predicted);
    if (scheme == ROD_SCHEME_STATIC) { /* no time step: one equilibrium solve */
        stability_trial t;
        stability_trial_run(c, scheme, 1.0, o, &t);
        row->trials = 1;
        row->first_failure = t;
        row->finding = stability_outcome_is_finding(t.outcome);
        row->wall_seconds = wall_seconds() - start;
        return;
    }
    double lo = o->dt_min, hi = o->dt_max;
    double predicted = row->predicted.scheme_dt;
    if (isfinite(predicted) && predicted > 0.0) {
        lo = fmax(lo, predicted / 100.0);
        hi = fmin(hi, predicted * 30.0);
    }
    if (try_dt(c, scheme, hi, o, row)) goto done; /* stable up to the largest dt tried */
    if (!try_dt(c, scheme, lo, o, row)) goto done; /* unstable even at the smallest */
    while (hi / lo > 1.0 + o->relative_tolerance) {
        double mid = sqrt(lo * hi);
        if (try_dt(c, scheme, mid, o, row)) lo = mid; else hi = mid;
    }
done:
    row->wall_seconds = wall_seconds() - start;
}

/* The sweep -------------------------------------------------------------------- */

typedef struct sweep_context {
    const stability_case *cases;
    const rod_scheme_kind *schemes;
    int n_schemes;
    const stability_options *o;
    stability_row *rows;
} sweep_context;

static int pool_find(void *context, int k, FILE *out)
{
    const sweep_context *c = context;
    stability_row row;
    stability_find(&c->cases[k / c->n_schemes], c->schemes[k % c->n_schemes], c->o, &row);
    return fwrite(&row, sizeof row, 1, out) == 1 ? 0 : 1;
}

static int pool_found(void *context, int k, const char *bytes, size_t n, int status)
{
    sweep_context *c = context;
    stability_row *r = &c->rows[k];
    if (status == 0 && n == sizeof *r) {
        memcpy(r, bytes, sizeof *r);
        return 0;
    }
    /* the worker died outside a guarded trial: keep the row's identity, say so */
    r->finding = 1;
    r->first_failure.outcome = STABILITY_CRASHED;
    snprintf(r->first_failure.message, sizeof r->first_failure.message,
             "the worker process ended without a result (status %d)", status);
    return 0;
}

int stability_sweep(const stability_case *cases, int n_cases, const rod_scheme_kind *schemes,
                    int n_schemes, const stability_options *o, int jobs, stability_row *rows,
                    char *err, size_t errlen)
{
    int n = n_cases * n_schemes;
    for (int k = 0; k < n; k++) {
        rows[k].c = cases[k / n_schemes];
        rows[k].scheme = schemes[k % n_schemes];
    }
    sweep_context c = {cases, schemes, n_schemes, o, rows};
    worker_pool pool = {.jobs = jobs, .context = &c, .run = pool_find, .done = pool_found};
    return worker_pool_run(&pool, NULL, n, err, errlen) ? -1 : 0;
}
