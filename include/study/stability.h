/* stability.h: the largest stable time step of each scheme, measured by
 * bisection, over a grid of resolutions, materials, sizes and loads, against
 * the predicted limits (stability at the extremes).
 *
 * A trial runs a scheme for a number of steps of one dt from a small
 * perturbation (a deterministic pseudo-random angular velocity in all three
 * components at every node) under the case's tip load. It is stable when
 * every step returns ROD_OK, the state stays finite and the kinetic energy
 * stays bounded: below GROWTH_LIMIT x (initial kinetic energy + the most
 * work the dead tip load can do, |F| 2L). Every trial may run in a child
 * process with a wall-time limit, so a hang or a crash is reported as such
 * (a finding) instead of stopping the sweep.
 *
 * Units: SI (s, Pa, m, N). */
#ifndef RODSIM_STABILITY_H
#define RODSIM_STABILITY_H

#include "sim/rod.h"

typedef enum {
    STABILITY_LOAD_NONE = 0,
    STABILITY_LOAD_TRANSVERSE, /* dead tip force along +y */
    STABILITY_LOAD_AXIAL       /* dead compressive tip force along -x, with 1e-3 of it along +y */
} stability_load;

typedef struct stability_case {
    char name[40];
    double youngs_modulus; /* E, Pa; G = E / 2.8 (table 1's ratio), rho = 850 kg/m^3 */
    double diameter;       /* d, m */
    double length;         /* L, m */
    int nodes;             /* NS */
    stability_load load;
    double load_factor;    /* |tip force| / (pi^2 EI / (4 L^2)), the Euler load */
    int physical_inertia;  /* thesis scheme: 1 = rotary_inertia_scale 1 (unstable at
                              every dt), 0 = 2 x the threshold 64 L^2/(pi^2 d^2) */
} stability_case;

typedef enum {
    STABILITY_STABLE = 0,
    STABILITY_REPORTED, /* the scheme stopped with its message (ROD_UNSTABLE) */
    STABILITY_NO_CONVERGENCE, /* Newton did not converge (message) */
    STABILITY_GREW,     /* kinetic energy grew past the bound without a message */
    STABILITY_NON_FINITE, /* NaN/Inf in the state without a message: a finding */
    STABILITY_REFUSED,  /* the scheme would not start for this model (message) */
    STABILITY_TIMEOUT,  /* the trial exceeded its wall-time limit: a finding */
    STABILITY_CRASHED,  /* the trial's process died on a signal: a finding */
    STABILITY_OUTCOME_COUNT
} stability_outcome;

/* Short name of an outcome ("stable", "reported", ...). */
const char *stability_outcome_name(stability_outcome outcome);
/* 1 for the outcomes the issue forbids: NaN without a message, hang, crash. */
int stability_outcome_is_finding(stability_outcome outcome);

typedef struct stability_trial {
    stability_outcome outcome;
    double dt;             /* s */
    int steps_done;
    double energy_ratio;   /* largest kinetic energy / its bound's base (see above) */
    int grew_first;        /* REPORTED after the energy had passed the bound */
    double wall_seconds;
    char message[320];     /* the scheme's message, or what happened */
} stability_trial;

typedef struct stability_options {
    int steps;               /* per trial, explicit scheme */
    int implicit_steps;      /* per trial, implicit scheme (each step costs Newton solves) */
    double dt_max;           /* s, largest dt tried (the implicit scheme starts there) */
    double dt_min;           /* s, smallest dt tried */
    double relative_tolerance; /* bisection stops when hi/lo < 1 + this */
    double trial_wall_limit; /* s per trial; > 0 runs each trial in a child process killed
                                after it; 0 runs trials in this process (no hang guard) */
} stability_options;

/* Defaults: quick = 0 for the full sweep, 1 for a short one (tests). */
stability_options stability_options_default(int quick);

/* The grid of cases (static storage). quick = 1: NS <= 21 and the extremes. */
const stability_case *stability_grid(int quick, int *count);

/* Predicted limits for a case (independent of measurement), s. */
typedef struct stability_prediction {
    double rotary_inertia_scale;  /* used by the thesis scheme for this case */
    double euler_bernoulli_dt;    /* 2 ds^2 sqrt(m/EI): an explicit beam without rotary inertia */
    double twist_dt;              /* 2 ds / sqrt(G/(rho s)) */
    double rotation_wave_dt;      /* 2 ds sqrt(rho s/E): bending with rotary inertia */
    double rotary_inertia_gain;   /* rotation_wave_dt / euler_bernoulli_dt = sqrt(s I/A)/ds */
    double scheme_dt;             /* the scheme's stable_dt (thesis: the derived criterion over
                                     the discrete modes; 0: none; INFINITY: unconditional) */
    char scheme_limit[200];       /* which limit decides scheme_dt */
} stability_prediction;

/* The model of a case for a scheme (derived). 0, or -1 with a message. */
int stability_case_model(const stability_case *c, rod_scheme_kind scheme, rod_model *m,
                         char *err, size_t errlen);
void stability_predict(const stability_case *c, rod_scheme_kind scheme, stability_prediction *p);

/* One trial of `scheme` on case c at time step dt. */
void stability_trial_run(const stability_case *c, rod_scheme_kind scheme, double dt,
                         const stability_options *o, stability_trial *t);

typedef struct stability_row {
    stability_case c;
    rod_scheme_kind scheme;
    stability_prediction predicted;
    double measured_dt;       /* s: the largest dt found stable (0 when none was) */
    double unstable_dt;       /* s: the smallest dt found unstable (0 when none was) */
    int trials;
    stability_trial first_failure; /* the failing trial at unstable_dt (outcome STABLE if none) */
    int finding;              /* a trial ended in a finding outcome (crash, hang, silent NaN) */
    double wall_seconds;
} stability_row;

/* Bisection for the largest stable dt of a time-stepping scheme, in
 * [dt_min, dt_max] (thesis: around the prediction). The static scheme gets
 * one solve (measured_dt 0, status in first_failure). */
void stability_find(const stability_case *c, rod_scheme_kind scheme, const stability_options *o,
                    stability_row *row);

/* Every (case, scheme) pair, up to `jobs` rows at a time in child processes
 * (jobs <= 1: in this process; worker.h). rows has n_cases x n_schemes
 * entries, case major. Returns 0, or -1 when out of memory (message). */
int stability_sweep(const stability_case *cases, int n_cases, const rod_scheme_kind *schemes,
                    int n_schemes, const stability_options *o, int jobs, stability_row *rows,
                    char *err, size_t errlen);

#endif
