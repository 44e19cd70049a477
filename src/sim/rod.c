/* rod.c: the rod model, its state, tip loads and the scheme registry. */
#include "sim/rod.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3.h"

rod_model rod_model_default(void)
{
    rod_model m;
    memset(&m, 0, sizeof m);
    /* table 1 */
    m.length = 1.0;
    m.diameter = 0.001;
    m.density = 850.0;
    m.youngs_modulus = 87.5e6;
    m.shear_modulus = 31.25e6;
    m.nodes = 51;
    m.rotary_inertia_scale = 1.0;
    m.tip_frame = ROD_FRAME_DIRECTOR;
    m.root_end = ROD_END_CLAMPED;
    m.tip_end = ROD_END_FREE;
    m.direction[0] = 1.0; /* straight along +x from the origin (thesis 4.2) */
    m.physics = (rod_physics){.twist = 1, .rotary_inertia = 1, .gravity = 1, .damping = 1,
                              .planar = 1};
    m.profile.kind = ROD_PROFILE_STEP;
    m.options.scheme = ROD_SCHEME_IMPLICIT;
    m.options.dt = 0.0;
    m.options.duration = 10.0;
    m.options.theta = 1.0;
    m.options.newton_tolerance = 1e-8;
    m.options.newton_max_iterations = 25;
    m.options.exact_rotation = 1;
    return m;
}

static int positive(double x) { return isfinite(x) && x > 0.0; }

int rod_model_derive(rod_model *m, char *err, size_t errlen)
{
    const char *bad = NULL;
    if (!positive(m->length)) bad = "length must be > 0 m";
    else if (!positive(m->diameter)) bad = "diameter must be > 0 m";
    else if (m->diameter >= m->length) bad = "diameter must be smaller than the length (a rod is slender)";
    else if (!positive(m->density)) bad = "density must be > 0 kg/m^3";
    else if (!positive(m->youngs_modulus)) bad = "youngs_modulus must be > 0 Pa";
    else if (!positive(m->shear_modulus)) bad = "shear_modulus must be > 0 Pa";
    else if (m->nodes < 3) bad = "nodes must be >= 3";
    else if (m->nodes > 100001) bad = "nodes must be <= 100001";
    else if (!positive(m->rotary_inertia_scale)) bad = "rotary_inertia_scale must be > 0";
    else if (!(m->linear_damping >= 0.0) || !(m->angular_damping >= 0.0)) bad = "damping must be >= 0";
    else if (!(m->options.duration >= 0.0) || !isfinite(m->options.duration)) bad = "duration must be >= 0 s";
    else if (!(m->options.theta >= 0.5 && m->options.theta <= 1.0)) bad = "theta must be in [0.5, 1]";
    else if (m->root_end == ROD_END_FREE) bad = "the root (s = 0) must be clamped or pinned";
    if (bad) {
        snprintf(err, errlen, "%s", bad);
        return -1;
    }
    double d = m->diameter;
    m->ds = m->length / (m->nodes - 1);                 /* (4.1) */
    m->area = M_PI * d * d / 4.0;
    m->second_moment = M_PI * pow(d, 4) / 64.0;         /* I = pi d^4 / 64 */
    m->polar_moment = M_PI * pow(d, 4) / 32.0;          /* J = pi d^4 / 32 */
    m->stiffness[0] = m->youngs_modulus * m->second_moment; /* (3.5) B1 = E I1 */
    m->stiffness[1] = m->youngs_modulus * m->second_moment; /*       B2 = E I2 */
    m->stiffness[2] = m->shear_modulus * m->polar_moment;   /*       C  = G J  */
    m->mass_per_length = m->density * m->area;
    /* principal mass moments of inertia per length: rho I1, rho I2, rho J */
    m->rotary_inertia[0] = m->density * m->second_moment * m->rotary_inertia_scale;
    m->rotary_inertia[1] = m->density * m->second_moment * m->rotary_inertia_scale;
    m->rotary_inertia[2] = m->density * m->polar_moment * m->rotary_inertia_scale;
    if (!m->physics.twist) m->rotary_inertia[2] = 0.0;
    if (!m->physics.rotary_inertia) m->rotary_inertia[0] = m->rotary_inertia[1] = m->rotary_inertia[2] = 0.0;
    return 0;
}

int rod_model_loads_planar(const rod_model *m)
{
    /* out-of-plane components: force on d2 (global z), moment on d1/d3 (global x, y) */
    int force_z = m->tip_frame == ROD_FRAME_DIRECTOR ? 1 : 2;
    int moment_in = m->tip_frame == ROD_FRAME_DIRECTOR ? 1 : 2; /* the one allowed axis */
    const rod_profile *p = &m->profile;
    int table7 = p->kind == ROD_PROFILE_TABLE && p->table.columns == 7;
    for (int r = 0; r < (table7 ? p->table.rows : 1); r++) {
        const double *f = table7 ? &p->table.data[7 * r + 1] : m->tip_force;
        const double *mo = table7 ? &p->table.data[7 * r + 4] : m->tip_moment;
        if (f[force_z] != 0.0) return 0;
        for (int k = 0; k < 3; k++)
            if (k != moment_in && mo[k] != 0.0) return 0;
    }
    if (m->distributed_force[2] != 0.0) return 0;
    return m->root_end == ROD_END_CLAMPED; /* a pinned root may turn out of the plane */
}

void rod_model_release(rod_model *m)
{
    free(m->profile.table.data);
    m->profile.table.data = NULL;
    free(m->initial_shape);
    m->initial_shape = NULL;
    free(m->point_loads);
    m->point_loads = NULL;
    m->point_load_count = 0;
    m->profile.table.rows = 0;
}

int rod_model_require_cantilever(const rod_model *m, const char *scheme, char *err,
                                 size_t errlen)
{
    static const char *const names[] = {"clamped", "pinned", "free"};
    if (m->root_end == ROD_END_CLAMPED && m->tip_end == ROD_END_FREE) return 0;
    snprintf(err, errlen,
             "the %s scheme models a cantilever only (ends root = clamped, tip = free); this "
             "scene asks for root = %s, tip = %s: use a scheme that supports them",
             scheme, names[m->root_end], names[m->tip_end]);
    return -1;
}

/* Row index k with t_k <= t < t_{k+1} (clamped), and the weight of row k+1. */
static void table_locate(const rod_table *tab, double t, int *k, double *w)
{
    const double *d = tab->data;
    int c = tab->columns, n = tab->rows;
    if (n == 1 || t <= d[0]) { *k = 0; *w = 0.0; return; }
    if (t >= d[(n - 1) * c]) { *k = n - 1; *w = 0.0; return; }
    int lo = 0, hi = n - 1; /* d[lo] <= t < d[hi] */
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (d[mid * c] <= t) lo = mid; else hi = mid;
    }
    *k = lo;
    *w = (t - d[lo * c]) / (d[hi * c] - d[lo * c]);
}

static double table_value(const rod_table *tab, double t, int column)
{
    int k;
    double w;
    table_locate(tab, t, &k, &w);
    double a = tab->data[k * tab->columns + column];
    if (w == 0.0) return a;
    double b = tab->data[(k + 1) * tab->columns + column];
    return a + w * (b - a);
}

double rod_profile_factor(const rod_profile *p, double t)
{
    switch (p->kind) {
    case ROD_PROFILE_STEP:
        return 1.0;
    case ROD_PROFILE_RAMP:
        if (p->t1 <= 0.0) return 1.0;
        return t <= 0.0 ? 0.0 : (t >= p->t1 ? 1.0 : t / p->t1);
    case ROD_PROFILE_PULSE:
        return (t >= p->t1 && t < p->t2) ? 1.0 : 0.0;
    case ROD_PROFILE_IMPULSE:
        if (t >= 0.0 && t < p->t1) return 1.0;
        if (t >= p->t1 && t < 2.0 * p->t1) return -1.0;
        return 0.0;
    case ROD_PROFILE_TABLE:
        return p->table.rows > 0 && p->table.columns == 2 ? table_value(&p->table, t, 1) : 1.0;
    }
    return 1.0;
}

void rod_tip_load(const rod_model *m, double t, double force[3], double moment[3])
{
    const rod_profile *p = &m->profile;
    if (p->kind == ROD_PROFILE_TABLE && p->table.columns == 7 && p->table.rows > 0) {
        for (int k = 0; k < 3; k++) {
            force[k] = table_value(&p->table, t, 1 + k);
            moment[k] = table_value(&p->table, t, 4 + k);
        }
        return;
    }
    double f = rod_profile_factor(p, t);
    v3_scale(force, m->tip_force, f);
    v3_scale(moment, m->tip_moment, f);
}

double rod_first_bending_frequency(const rod_model *m)
{
    const double beta1 = 1.8751040687119611; /* first root of cos x cosh x = -1 */
    return beta1 * beta1 / (2.0 * M_PI * m->length * m->length) *
           sqrt(m->stiffness[0] / m->mass_per_length);
}

rod_state *rod_state_create(const rod_model *m)
{
    rod_state *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    size_t n = (size_t)m->nodes;
    s->nodes = m->nodes;
    s->position = calloc(n * 3, sizeof(double));
    s->frame = calloc(n * 9, sizeof(double));
    s->velocity = calloc(n * 3, sizeof(double));
    s->angular_velocity = calloc(n * 3, sizeof(double));
    s->darboux = calloc(n * 3, sizeof(double));
    s->contact_force = calloc(n * 3, sizeof(double));
    if (!s->position || !s->frame || !s->velocity || !s->angular_velocity || !s->darboux ||
        !s->contact_force) {
        rod_state_destroy(s);
        return NULL;
    }
    rod_state_reset(m, s);
    return s;
}

void rod_state_destroy(rod_state *s)
{
    if (!s) return;
    free(s->position);
    free(s->frame);
    free(s->velocity);
    free(s->angular_velocity);
    free(s->darboux);
    free(s->contact_force);
    free(s);
}

void rod_state_reset(const rod_model *m, rod_state *s)
{
    size_t n = (size_t)s->nodes;
    s->time = 0.0;
    memset(s->velocity, 0, n * 3 * sizeof(double));
    memset(s->angular_velocity, 0, n * 3 * sizeof(double));
    memset(s->darboux, 0, n * 3 * sizeof(double));
    memset(s->contact_force, 0, n * 3 * sizeof(double));
    /* thesis 4.2: d3 along x, d1 along y, d2 along z; columns of Q are d1 d2 d3 */
    static const double straight[9] = {0, 0, 1,
                                       1, 0, 0,
                                       0, 1, 0};
    for (size_t i = 0; i < n; i++) {
        memcpy(&s->frame[9 * i], straight, sizeof straight);
        v3_set(&s->position[3 * i], (double)i * m->ds, 0.0, 0.0);
    }
}

double rod_kinetic_energy(const rod_model *m, const rod_state *s)
{
    double e = 0.0;
    for (int i = 1; i < s->nodes; i++) {
        double w = (i == s->nodes - 1) ? 0.5 * m->ds : m->ds;
        const double *v = &s->velocity[3 * i], *om = &s->angular_velocity[3 * i];
        e += 0.5 * w * m->mass_per_length * v3_dot(v, v);
        for (int k = 0; k < 3; k++) e += 0.5 * w * m->rotary_inertia[k] * om[k] * om[k];
    }
    return e;
}

double rod_frame_orthonormality_error(const rod_state *s)
{
    double worst = 0.0;
    for (int i = 0; i < s->nodes; i++) {
        double qtq[9];
        m3_mul_tn(qtq, &s->frame[9 * i], &s->frame[9 * i]);
        for (int k = 0; k < 9; k++) {
            double e = fabs(qtq[k] - ((k % 4 == 0) ? 1.0 : 0.0));
            if (e > worst) worst = e;
        }
    }
    return worst;
}

double rod_segment_length_error(const rod_model *m, const rod_state *s)
{
    double worst = 0.0;
    for (int i = 0; i + 1 < s->nodes; i++) {
        double d[3];
        v3_sub(d, &s->position[3 * (i + 1)], &s->position[3 * i]);
        double e = fabs(v3_norm(d) - m->ds) / m->ds;
        if (e > worst) worst = e;
    }
    return worst;
}

static int all_finite(const double *a, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(a[i])) return 0;
    return 1;
}

int rod_state_is_finite(const rod_state *s)
{
    size_t n = (size_t)s->nodes;
    return isfinite(s->time) && all_finite(s->position, 3 * n) && all_finite(s->frame, 9 * n) &&
           all_finite(s->velocity, 3 * n) && all_finite(s->angular_velocity, 3 * n) &&
           all_finite(s->darboux, 3 * n) && all_finite(s->contact_force, 3 * n);
}

/* Schemes ------------------------------------------------------------- */

const rod_scheme_ops *rod_scheme_get(rod_scheme_kind kind)
{
    switch (kind) {
    case ROD_SCHEME_THESIS: return &rod_scheme_thesis;
    case ROD_SCHEME_IMPLICIT: return &rod_scheme_implicit;
    case ROD_SCHEME_STATIC: return &rod_scheme_static;
    case ROD_SCHEME_COUNT: break;
    }
    return NULL;
}

const rod_scheme_ops *rod_scheme_find(const char *name, rod_scheme_kind *kind)
{
    for (int k = 0; k < ROD_SCHEME_COUNT; k++) {
        const rod_scheme_ops *ops = rod_scheme_get((rod_scheme_kind)k);
        if (strcmp(ops->name, name) == 0) {
            if (kind) *kind = (rod_scheme_kind)k;
            return ops;
        }
    }
    return NULL;
}

int rod_solver_init(rod_solver *solver, const rod_model *m, char *err, size_t errlen)
{
    solver->ops = rod_scheme_get(m->options.scheme);
    solver->work = NULL;
    if (!solver->ops) {
        snprintf(err, errlen, "unknown scheme %d", (int)m->options.scheme);
        return -1;
    }
    solver->work = solver->ops->create(m, err, errlen);
    return solver->work ? 0 : -1;
}

rod_status rod_solver_step(rod_solver *solver, const rod_model *m, rod_state *s, double dt,
                           rod_report *report)
{
    report->message[0] = '\0';
    report->suggested_dt = 0.0;
    report->suggested_scale = 0.0;
    report->newton_iterations = 0;
    return solver->ops->step(solver->work, m, s, dt, report);
}

void rod_solver_release(rod_solver *solver)
{
    if (solver->ops && solver->work) solver->ops->destroy(solver->work);
    solver->work = NULL;
}

double rod_choose_dt(const rod_model *m, const char **why)
{
    if (m->options.dt > 0.0) {
        if (why) *why = "set in the scene";
        return m->options.dt;
    }
    if (m->options.scheme == ROD_SCHEME_STATIC) {
        /* no dynamics: one equilibrium solve per output frame (the run caps steps at 1/fps) */
        if (why) *why = "static: no time step, one equilibrium solve per output frame";
        return m->options.duration > 0.0 ? m->options.duration : 1.0;
    }
    /* The scheme's stability limit covers only the physics the scene turns on
     * (e.g. the thesis scheme has no twist cap with twist off or a planar load);
     * an unconditionally stable scheme is limited by accuracy alone. */
    const rod_scheme_ops *ops = rod_scheme_get(m->options.scheme);
    const char *const accuracy = "accuracy: 1/20 of the first bending period";
    double accuracy_dt = 1.0 / (20.0 * rod_first_bending_frequency(m));
    const char *limit = accuracy;
    double stable = ops && ops->stable_dt ? ops->stable_dt(m, &limit) : INFINITY;
    const double safety = 0.5; /* forward Euler near its limit amplifies round-off slowly */
    if (isfinite(stable) && safety * stable < accuracy_dt) {
        if (why) *why = limit; /* stable = 0: no stable dt exists; the limit says why */
        return safety * stable;
    }
    if (why) *why = isfinite(stable) ? accuracy
                                     : "accuracy: 1/20 of the first bending period (the scheme "
                                       "is unconditionally stable)";
    return accuracy_dt;
}
