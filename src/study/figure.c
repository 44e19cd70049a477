/* figure.c: the sweep machinery (points, CSV, parallel processes) and the
 * figures themselves (see figure.h). */
#include "study/figure.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>

#include "base/embedded.h"
#include "base/outfile.h"
#include "base/worker.h"
#include "plot/plot.h"
#include "study/buckling.h"
#include "base/ini.h"
#include "study/reference.h"
#include "sim/rod.h"
#include "sim/scene.h"
#include "base/spectrum.h"
#include "study/validate.h"

struct figure_def {
    const char *name;
    const char *summary;
    const char *columns; /* CSV header, "point," then the value columns */
    int value_columns;
    int full_points, quick_points;
    const char *const *outputs;
    int (*compute)(int point, int quick, figure_points *out, char *err, size_t errlen);
    int (*draw)(const figure_points *points, int quick, const char *out_dir, FILE *summary,
                char *err, size_t errlen);
};

/* ---- rows ------------------------------------------------------------------ */

void figure_points_init(figure_points *p, const figure_def *f)
{
    memset(p, 0, sizeof *p);
    p->columns = f->value_columns;
}

void figure_points_release(figure_points *p)
{
    free(p->data);
    memset(p, 0, sizeof *p);
}

int figure_points_add(figure_points *p, int point, const double *values)
{
    int width = 1 + p->columns;
    if (p->rows == p->capacity) {
        int capacity = p->capacity ? 2 * p->capacity : 64;
        double *data = realloc(p->data, (size_t)capacity * (size_t)width * sizeof *data);
        if (!data) return -1;
        p->data = data;
        p->capacity = capacity;
    }
    double *row = &p->data[(size_t)p->rows * (size_t)width];
    row[0] = point;
    memcpy(row + 1, values, (size_t)p->columns * sizeof *values);
    p->rows++;
    return 0;
}

static const double *row_of(const figure_points *p, int r)
{
    return &p->data[(size_t)r * (size_t)(1 + p->columns)];
}

/* ---- simulations shared by the figures -------------------------------------- */

static double now_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Steps the model from rest to t_end with steps of dt. 0, or -1 with the scheme's message. */
static int settle(const rod_model *m, rod_state *s, double t_end, double dt, char *err,
                  size_t errlen)
{
    rod_solver solver;
    if (rod_solver_init(&solver, m, err, errlen)) return -1;
    rod_report report = {0};
    rod_status status = ROD_OK;
    long steps = lround(ceil((t_end - s->time) / dt - 1e-9));
    for (long k = 0; k < steps && status == ROD_OK; k++)
        status = rod_solver_step(&solver, m, s, dt, &report);
    rod_solver_release(&solver);
    if (status != ROD_OK || !rod_state_is_finite(s)) {
        snprintf(err, errlen, "%s scheme failed at t = %g s: %s", m->options.scheme ==
                 ROD_SCHEME_THESIS ? "thesis" : m->options.scheme == ROD_SCHEME_IMPLICIT
                 ? "implicit" : "static", s->time, report.message);
        return -1;
    }
    return 0;
}

static const unsigned char scheme_rgb[ROD_SCHEME_COUNT][3] = {
    {200, 110, 0},  /* thesis: orange */
    {200, 30, 30},  /* implicit: red */
    {0, 90, 200},   /* static: blue */
};
static const char *const scheme_names[ROD_SCHEME_COUNT] = {"thesis", "implicit", "static"};

static plot_style marker_style(const unsigned char rgb[3], double size, int filled)
{
    plot_style s = plot_style_line(rgb[0], rgb[1], rgb[2], 2.0, PLOT_SOLID);
    s.marker_size = size;
    s.filled = 1;
    if (filled) memcpy(s.fill_rgb, rgb, 3);
    else s.fill_rgb[0] = s.fill_rgb[1] = s.fill_rgb[2] = 255;
    return s;
}

static int write_plot(plot *p, const char *out_dir, const char *file, char *err, size_t errlen)
{
    char path[OUTFILE_PATH_MAX];
    snprintf(path, sizeof path, "%s/%s", out_dir, file);
    return plot_write_png(p, path, err, errlen);
}

/* ---- table2: tip deflection against the tip force ---------------------------- */

/* Thesis table 2: P (N) and its "simulated" tip deflections (m). */
static const double table2_loads[3] = {4.5e-7, 8e-7, 1e-6};
static const double table2_thesis_values[3] = {0.0352, 0.0627, 0.0782};
static const double table2_full_loads[] = {1e-7, 2e-7, 3e-7, 4.5e-7, 6e-7, 8e-7, 1e-6, 1.2e-6};
#define TABLE2_FULL_LOADS ((int)(sizeof table2_full_loads / sizeof table2_full_loads[0]))
#define TABLE2_NODES 51
static const rod_scheme_kind table2_schemes[3] = {ROD_SCHEME_STATIC, ROD_SCHEME_IMPLICIT,
                                                  ROD_SCHEME_THESIS};
static const char *const table2_outputs[] = {"table2.png", "table2_ratio.png", NULL};

/* Table 1's rod, NS = 51, under a dead tip load P along +y (scenes/table2_*.ini:
 * the frame PL^3/3EI and the dead-load elastica assume), settled:
 *   static:   one equilibrium solve;
 *   implicit: backward Euler, dt = 0.5 s, load ramped over 2 s, damping 4e-4
 *             N s/m^2 (about critical for mode 1), state at 150 s;
 *   thesis:   rotary_inertia_scale 1e7 (it diverges without), dt = 0.1 s,
 *             ramp 10 s, damping 1e-3, state at 300 s (scheme_thesis.c: minimum_scale). */
static int table2_compute(int point, int quick, figure_points *out, char *err, size_t errlen)
{
    rod_scheme_kind scheme = table2_schemes[point % 3];
    double load = quick ? table2_loads[point / 3] : table2_full_loads[point / 3];
    rod_model m = rod_model_default();
    m.nodes = TABLE2_NODES;
    m.tip_frame = ROD_FRAME_GLOBAL;
    m.tip_force[1] = load;
    m.options.scheme = scheme;
    double t_end = 1.0, dt = 1.0;
    if (scheme == ROD_SCHEME_IMPLICIT) {
        m.options.theta = 1.0;
        m.profile.kind = ROD_PROFILE_RAMP;
        m.profile.t1 = 2.0;
        m.linear_damping = 4e-4;
        t_end = 150.0;
        dt = 0.5;
    } else if (scheme == ROD_SCHEME_THESIS) {
        m.rotary_inertia_scale = 1e7;
        m.profile.kind = ROD_PROFILE_RAMP;
        m.profile.t1 = 10.0;
        m.linear_damping = 1e-3;
        t_end = 300.0;
        dt = 0.1;
    }
    m.options.dt = dt;
    if (rod_model_derive(&m, err, errlen)) return -1;
    rod_state *s = rod_state_create(&m);
    if (!s) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    int rc = settle(&m, s, t_end, dt, err, errlen);
    if (rc == 0) {
        const double *tip = &s->position[3 * (s->nodes - 1)];
        double values[4] = {(double)scheme, load, tip[0], tip[1]};
        rc = figure_points_add(out, point, values);
    }
    rod_state_destroy(s);
    return rc;
}

static int table2_draw(const figure_points *points, int quick, const char *out_dir,
                       FILE *summary, char *err, size_t errlen)
{
    (void)quick;
    rod_model m = rod_model_default();
    if (rod_model_derive(&m, err, errlen)) return -1;
    double ei = m.stiffness[0], length = m.length;
    double cubic = length * length * length / (3.0 * ei); /* PL^3/3EI per newton */

    /* independent curves: linear theory and the dead-load elastica */
    enum { CURVE = 50 };
    double p_max = 1.25e-6;
    double cx[CURVE], linear[CURVE], elastica[CURVE], elastica_ratio[CURVE], ones[CURVE];
    for (int i = 0; i < CURVE; i++) {
        double load = p_max * (i + 1e-3) / (CURVE - 1); /* from ~0: the ratio is 0/0 at 0 */
        elastica_tip tip;
        if (elastica_dead_load(ei, length, 0.0, load, 0.0, 8000, &tip)) {
            snprintf(err, errlen, "elastica: no solution bracketed at P = %g N", load);
            return -1;
        }
        cx[i] = load * 1e9;                 /* nN */
        linear[i] = load * cubic * 1e3;     /* mm */
        elastica[i] = tip.y * 1e3;
        elastica_ratio[i] = tip.y / (load * cubic);
        ones[i] = 1.0;
    }

    /* simulated points, per scheme */
    int n = points->rows;
    double *sx = malloc((size_t)(n + 1) * sizeof *sx);
    double *sy = malloc((size_t)(n + 1) * sizeof *sy);
    double *sr = malloc((size_t)(n + 1) * sizeof *sr);
    plot *deflection = plot_create(1200, 800), *ratio = plot_create(1200, 800);
    int rc = (!sx || !sy || !sr || !deflection || !ratio) ? -1 : 0;
    if (rc) snprintf(err, errlen, "out of memory");

    if (rc == 0) {
        plot_set_title(deflection, "Thesis table 2: cantilever tip deflection under a tip force "
                                   "(L = 1 m, d = 1 mm, NS = 51)");
        plot_set_axis_labels(deflection, "tip force P [nN]", "tip deflection y [mm]");
        plot_set_limits(deflection, 0, 1300, 0, 100);
        plot_set_title(ratio, "Table 2 relative to linear theory: y / (P L^3 / 3 E I)");
        plot_set_axis_labels(ratio, "tip force P [nN]", "y / (P L^3 / 3 E I)");
        plot_set_limits(ratio, 0, 1300, 0.98, 1.025);
        plot_style theory = plot_style_line(120, 120, 120, 2.0, PLOT_DASHED);
        plot_style exact = plot_style_line(0, 0, 0, 2.0, PLOT_SOLID);
        rc |= plot_add_line(deflection, cx, linear, CURVE, theory, "P L^3 / 3 E I (linear)");
        rc |= plot_add_line(deflection, cx, elastica, CURVE, exact, "elastica (exact, dead load)");
        rc |= plot_add_line(ratio, cx, ones, CURVE, theory, "P L^3 / 3 E I (linear)");
        rc |= plot_add_line(ratio, cx, elastica_ratio, CURVE, exact,
                            "elastica (exact, dead load)");
        static const double sizes[3] = {16, 11, 7};
        for (int k = 0; k < 3 && rc == 0; k++) {
            rod_scheme_kind scheme = table2_schemes[k];
            int count = 0;
            for (int r = 0; r < n; r++) {
                const double *row = row_of(points, r);
                if ((int)row[1] != (int)scheme) continue;
                double load = row[2], y = row[4];
                sx[count] = load * 1e9;
                sy[count] = y * 1e3;
                sr[count] = y / (load * cubic);
                count++;
                elastica_tip tip;
                elastica_dead_load(ei, length, 0.0, load, 0.0, 8000, &tip);
                if (summary)
                    fprintf(summary,
                            "table2: %-8s P = %.3g N: tip y = %.6f m; PL^3/3EI %.6f (%+.2f%%), "
                            "elastica %.6f (%+.2e)\n",
                            scheme_names[scheme], load, y, load * cubic,
                            100.0 * (y / (load * cubic) - 1.0), tip.y, y / tip.y - 1.0);
            }
            if (count == 0) continue;
            char legend[64];
            snprintf(legend, sizeof legend, "%s scheme (simulated)", scheme_names[scheme]);
            plot_style style = marker_style(scheme_rgb[scheme], sizes[k], k != 0);
            rc |= plot_add_markers(deflection, sx, sy, count, style, NULL, 0, 0, legend);
            rc |= plot_add_markers(ratio, sx, sr, count, style, NULL, 0, 0, legend);
        }
        /* the thesis' own numbers (its table 2) */
        double tx[3], ty[3], tr[3];
        for (int i = 0; i < 3; i++) {
            tx[i] = table2_loads[i] * 1e9;
            ty[i] = table2_thesis_values[i] * 1e3;
            tr[i] = table2_thesis_values[i] / (table2_loads[i] * cubic);
        }
        static const char *const labels[3] = {"0.0352 m", "0.0627 m", "0.0782 m"};
        plot_style thesis = plot_style_line(0, 150, 60, 2.5, PLOT_SOLID);
        thesis.marker_size = 14;
        thesis.filled = 0;
        rc |= plot_add_markers(deflection, tx, ty, 3, thesis, labels, 22, 30,
                               "thesis table 2 (its simulation)");
        rc |= plot_add_markers(ratio, tx, tr, 3, thesis, labels, -40, -22,
                               "thesis table 2 (its simulation)");
        if (rc) snprintf(err, errlen, "out of memory");
    }
    if (rc == 0) rc = write_plot(deflection, out_dir, "table2.png", err, errlen);
    if (rc == 0) rc = write_plot(ratio, out_dir, "table2_ratio.png", err, errlen);
    plot_destroy(deflection);
    plot_destroy(ratio);
    free(sx);
    free(sy);
    free(sr);
    return rc;
}

/* ---- impulse: tip and mid-point after the impulse, and their spectra --------- */

/* compiled in (base/embedded.h): `rodsim figure` needs no checkout */
#define IMPULSE_SCENE "scenes/impulse.ini"
#define IMPULSE_SAMPLE 0.01      /* s between samples: 100 Hz, Nyquist 50 Hz */
#define IMPULSE_FULL_DURATION 30.0 /* s: the thesis shows 10 s; 30 s resolves 1/30 Hz */
#define IMPULSE_QUICK_DURATION 1.0
#define IMPULSE_MODES 6
#define IMPULSE_F_MAX 4.0        /* Hz shown: modes 1 .. 6 (3.8 Hz) */
static ini_doc *load_impulse_scene(char *err, size_t errlen)
{
    const char *text = embedded_text(IMPULSE_SCENE);
    if (!text) {
        snprintf(err, errlen, "%s: not compiled into this binary", IMPULSE_SCENE);
        return NULL;
    }
    return ini_parse(IMPULSE_SCENE, text, err, errlen);
}

static const char *const impulse_outputs[] = {"impulse.png", "impulse_spectrum.png", NULL};

/* scenes/impulse.ini as it is (implicit Crank-Nicolson, NS = 51, dt = 0.5 ms,
 * N1 = 2.5e-3 N on d1 for 5 ms then -N1 for 5 ms), run for the duration
 * above; rows: t (s), tip y (m), mid-point y (m) every IMPULSE_SAMPLE s. */
static int impulse_compute(int point, int quick, figure_points *out, char *err, size_t errlen)
{
    (void)point;
    ini_doc *doc = load_impulse_scene(err, errlen);
    if (!doc) return -1;
    rod_model m;
    int rc = scene_read_rod(doc, &m, err, errlen);
    ini_destroy(doc);
    if (rc) return -1;
    m.options.duration = quick ? IMPULSE_QUICK_DURATION : IMPULSE_FULL_DURATION;
    double dt = m.options.dt;
    long per_sample = lround(IMPULSE_SAMPLE / dt);
    rod_state *s = rod_state_create(&m);
    rod_solver solver;
    if (!s || per_sample < 1 || fabs(per_sample * dt - IMPULSE_SAMPLE) > 1e-12) {
        snprintf(err, errlen, s ? "%s: dt = %g s does not divide the %g s sampling interval"
                                : "out of memory", IMPULSE_SCENE, dt, IMPULSE_SAMPLE);
        rod_state_destroy(s);
        rod_model_release(&m);
        return -1;
    }
    if (rod_solver_init(&solver, &m, err, errlen)) {
        rod_state_destroy(s);
        rod_model_release(&m);
        return -1;
    }
    rod_state_reset(&m, s);
    int tip = m.nodes - 1, mid = (m.nodes - 1) / 2;
    long steps = lround(m.options.duration / dt);
    rod_report report = {0};
    for (long k = 0; k <= steps && rc == 0; k++) {
        if (k % per_sample == 0) {
            double row[3] = {k * dt, s->position[3 * tip + 1], s->position[3 * mid + 1]};
            rc = figure_points_add(out, 0, row);
            if (rc) snprintf(err, errlen, "out of memory");
        }
        if (k == steps || rc) break;
        if (rod_solver_step(&solver, &m, s, dt, &report) != ROD_OK || !rod_state_is_finite(s)) {
            snprintf(err, errlen, "implicit step failed at t = %g s: %s", s->time,
                     report.message);
            rc = -1;
        }
    }
    rod_solver_release(&solver);
    rod_state_destroy(s);
    rod_model_release(&m);
    return rc;
}

static int impulse_draw(const figure_points *points, int quick, const char *out_dir,
                        FILE *summary, char *err, size_t errlen)
{
    (void)quick;
    ini_doc *doc = load_impulse_scene(err, errlen);
    if (!doc) return -1;
    rod_model m;
    int rc = scene_read_rod(doc, &m, err, errlen);
    ini_destroy(doc);
    if (rc) return -1;
    double ei = m.stiffness[0], mass = m.mass_per_length, length = m.length;
    rod_model_release(&m);

    enum { SPECTRUM = 801 };
    int n = points->rows;
    double *t = malloc((size_t)n * sizeof *t);
    double *tip = malloc((size_t)n * sizeof *tip);
    double *mid = malloc((size_t)n * sizeof *mid);
    double *tip_mm = malloc((size_t)n * sizeof *tip_mm);
    double *mid_mm = malloc((size_t)n * sizeof *mid_mm);
    double f[SPECTRUM], tip_spectrum[SPECTRUM], mid_spectrum[SPECTRUM];
    plot *motion = plot_create(1200, 800), *spectrum = plot_create(1200, 800);
    rc = (!t || !tip || !mid || !tip_mm || !mid_mm || !motion || !spectrum || n < 16) ? -1 : 0;
    if (rc) snprintf(err, errlen, n < 16 ? "impulse: %d samples, too few" : "out of memory", n);
    if (rc == 0) {
        for (int i = 0; i < n; i++) {
            const double *row = row_of(points, i);
            t[i] = row[1];
            tip[i] = row[2];
            mid[i] = row[3];
            tip_mm[i] = 1e3 * tip[i];
            mid_mm[i] = 1e3 * mid[i];
        }
        double duration = t[n - 1];
        char title[160];
        snprintf(title, sizeof title,
                 "Thesis fig. 11: displacement after the impulse (scenes/impulse.ini, %g s)",
                 duration);
        plot_set_title(motion, title);
        plot_set_axis_labels(motion, "time t [s]", "displacement y [mm]");
        rc |= plot_add_line(motion, t, tip_mm, n, plot_style_line(200, 30, 30, 2, PLOT_SOLID),
                            "free end (tip)");
        rc |= plot_add_line(motion, t, mid_mm, n, plot_style_line(0, 90, 200, 2, PLOT_SOLID),
                            "mid-point (s = L/2)");
        rc |= plot_add_legend_note(motion, "implicit Crank-Nicolson, NS = 51, dt = 0.5 ms");

        /* spectra of the displacement samples (Hann-windowed DFT, spectrum.h) */
        double lo = INFINITY, hi = 0;
        for (int i = 0; i < SPECTRUM; i++) {
            f[i] = IMPULSE_F_MAX * (i + 1) / SPECTRUM;
            /* a sinusoid of amplitude A gives |DFT| = A sum(w)/2 = A n/4 with Hann w */
            tip_spectrum[i] = 4.0 / n * spectrum_magnitude(tip_mm, n, IMPULSE_SAMPLE, f[i]);
            mid_spectrum[i] = 4.0 / n * spectrum_magnitude(mid_mm, n, IMPULSE_SAMPLE, f[i]);
            lo = fmin(lo, fmin(tip_spectrum[i], mid_spectrum[i]));
            hi = fmax(hi, fmax(tip_spectrum[i], mid_spectrum[i]));
        }
        lo = fmax(lo, hi * 1e-6);
        snprintf(title, sizeof title,
                 "Thesis figs. 12-13: spectrum of the tip and mid-point motion (%g s)", duration);
        plot_set_title(spectrum, title);
        plot_set_axis_labels(spectrum, "frequency f [Hz]", "amplitude 4 |DFT| / n, Hann window [mm]");
        plot_set_log(spectrum, 0, 1);
        plot_set_limits(spectrum, 0, IMPULSE_F_MAX, lo, hi * 300);
        rc |= plot_add_line(spectrum, f, tip_spectrum, SPECTRUM,
                            plot_style_line(200, 30, 30, 2, PLOT_SOLID), "free end (tip)");
        rc |= plot_add_line(spectrum, f, mid_spectrum, SPECTRUM,
                            plot_style_line(0, 90, 200, 2, PLOT_SOLID), "mid-point");
        /* the analytical modal frequencies, (beta_n L)^2/(2 pi L^2) sqrt(EI/m) */
        double mark_f[IMPULSE_MODES], mark_y[IMPULSE_MODES];
        char label_text[IMPULSE_MODES][16];
        const char *labels[IMPULSE_MODES];
        int marks = 0;
        double resolution = 2.0 / duration; /* Hann main lobe half width, Hz */
        for (int mode = 1; mode <= IMPULSE_MODES; mode++) {
            double fn = reference_cantilever_frequency(mode, ei, mass, length);
            if (fn > IMPULSE_F_MAX) break;
            double vx[2] = {fn, fn}, vy[2] = {lo, hi * 3};
            rc |= plot_add_line(spectrum, vx, vy, 2, plot_style_line(0, 140, 60, 1.5, PLOT_DASHED),
                                mode == 1 ? "analytical modal frequencies f_n" : NULL);
            mark_f[marks] = fn;
            mark_y[marks] = hi * 6;
            snprintf(label_text[marks], sizeof label_text[marks], "f%d", mode);
            labels[marks] = label_text[marks];
            marks++;
            if (summary) {
                if (fn < 3.0 * resolution) {
                    fprintf(summary, "impulse: mode %d: analytical %.4f Hz: not resolved in %g s "
                            "(needs several periods)\n", mode, fn, duration);
                    continue;
                }
                double band = fmin(fmax(0.15 * fn, 1.5 * resolution), 0.5);
                double tip_peak = spectrum_peak(tip_mm, n, IMPULSE_SAMPLE, fn - band, fn + band);
                double mid_peak = spectrum_peak(mid_mm, n, IMPULSE_SAMPLE, fn - band, fn + band);
                /* a mode with a node near L/2 barely moves the mid-point: no peak there */
                double tip_level = spectrum_magnitude(tip_mm, n, IMPULSE_SAMPLE, tip_peak);
                double mid_level = spectrum_magnitude(mid_mm, n, IMPULSE_SAMPLE, fn);
                fprintf(summary, "impulse: mode %d: analytical %.4f Hz; tip peak %.4f Hz (%+.2e)",
                        mode, fn, tip_peak, tip_peak / fn - 1.0);
                if (mid_level > 0.05 * tip_level)
                    fprintf(summary, ", mid-point peak %.4f Hz (%+.2e)\n", mid_peak,
                            mid_peak / fn - 1.0);
                else
                    fprintf(summary, "; mid-point: no peak (%.2g of the tip's level: a node "
                            "near L/2)\n", mid_level / tip_level);
            }
        }
        plot_style mark = plot_style_line(0, 140, 60, 1.5, PLOT_SOLID);
        mark.marker_size = 1;
        rc |= plot_add_markers(spectrum, mark_f, mark_y, marks, mark, labels, 6, 0, NULL);
        if (rc) snprintf(err, errlen, "out of memory");
        if (summary) {
            double tip_max = 0, mid_max = 0;
            for (int i = 0; i < n; i++) {
                tip_max = fmax(tip_max, fabs(tip[i]));
                mid_max = fmax(mid_max, fabs(mid[i]));
            }
            fprintf(summary, "impulse: largest |y| over %g s: tip %.3f mm, mid-point %.3f mm\n",
                    duration, 1e3 * tip_max, 1e3 * mid_max);
        }
    }
    if (rc == 0) rc = write_plot(motion, out_dir, "impulse.png", err, errlen);
    if (rc == 0) rc = write_plot(spectrum, out_dir, "impulse_spectrum.png", err, errlen);
    plot_destroy(motion);
    plot_destroy(spectrum);
    free(t);
    free(tip);
    free(mid);
    free(tip_mm);
    free(mid_mm);
    return rc;
}

/* ---- pareto: error against CPU time -------------------------------------------- */

/* One run of validate_run: a case, a scheme, NS and a dt factor (times the
 * case's default dt; 1 for settled cases, whose answer does not depend on dt). */
typedef struct pareto_run {
    const char *case_name;
    rod_scheme_kind scheme;
    int nodes;
    double dt_factor;
} pareto_run;

#define PARETO_DEFLECTION "tip_load_small"
#define PARETO_FREQUENCY "bending_frequency_1"
static const pareto_run pareto_full[] = {
    {PARETO_DEFLECTION, ROD_SCHEME_STATIC, 11, 1}, {PARETO_DEFLECTION, ROD_SCHEME_STATIC, 21, 1},
    {PARETO_DEFLECTION, ROD_SCHEME_STATIC, 51, 1}, {PARETO_DEFLECTION, ROD_SCHEME_STATIC, 101, 1},
    {PARETO_DEFLECTION, ROD_SCHEME_STATIC, 201, 1}, {PARETO_DEFLECTION, ROD_SCHEME_STATIC, 401, 1},
    {PARETO_DEFLECTION, ROD_SCHEME_IMPLICIT, 11, 1}, {PARETO_DEFLECTION, ROD_SCHEME_IMPLICIT, 21, 1},
    {PARETO_DEFLECTION, ROD_SCHEME_IMPLICIT, 51, 1}, {PARETO_DEFLECTION, ROD_SCHEME_IMPLICIT, 101, 1},
    {PARETO_DEFLECTION, ROD_SCHEME_IMPLICIT, 201, 1}, {PARETO_DEFLECTION, ROD_SCHEME_IMPLICIT, 401, 1},
    {PARETO_DEFLECTION, ROD_SCHEME_THESIS, 11, 1}, {PARETO_DEFLECTION, ROD_SCHEME_THESIS, 21, 1},
    {PARETO_DEFLECTION, ROD_SCHEME_THESIS, 51, 1}, {PARETO_DEFLECTION, ROD_SCHEME_THESIS, 101, 1},
    {PARETO_DEFLECTION, ROD_SCHEME_THESIS, 201, 1},
    {PARETO_FREQUENCY, ROD_SCHEME_IMPLICIT, 11, 1}, {PARETO_FREQUENCY, ROD_SCHEME_IMPLICIT, 21, 1},
    {PARETO_FREQUENCY, ROD_SCHEME_IMPLICIT, 51, 1}, {PARETO_FREQUENCY, ROD_SCHEME_IMPLICIT, 101, 1},
    {PARETO_FREQUENCY, ROD_SCHEME_IMPLICIT, 201, 1},
    {PARETO_FREQUENCY, ROD_SCHEME_IMPLICIT, 51, 8}, {PARETO_FREQUENCY, ROD_SCHEME_IMPLICIT, 51, 4},
    {PARETO_FREQUENCY, ROD_SCHEME_IMPLICIT, 51, 2}, {PARETO_FREQUENCY, ROD_SCHEME_IMPLICIT, 51, 0.5},
    {PARETO_FREQUENCY, ROD_SCHEME_THESIS, 11, 1}, {PARETO_FREQUENCY, ROD_SCHEME_THESIS, 21, 1},
    {PARETO_FREQUENCY, ROD_SCHEME_THESIS, 51, 1}, {PARETO_FREQUENCY, ROD_SCHEME_THESIS, 101, 1},
};
static const pareto_run pareto_quick[] = {
    {PARETO_DEFLECTION, ROD_SCHEME_STATIC, 11, 1}, {PARETO_DEFLECTION, ROD_SCHEME_STATIC, 21, 1},
    {PARETO_DEFLECTION, ROD_SCHEME_IMPLICIT, 11, 1},
    {PARETO_FREQUENCY, ROD_SCHEME_IMPLICIT, 11, 1}, {PARETO_FREQUENCY, ROD_SCHEME_IMPLICIT, 11, 4},
};
#define PARETO_FULL ((int)(sizeof pareto_full / sizeof pareto_full[0]))
#define PARETO_QUICK ((int)(sizeof pareto_quick / sizeof pareto_quick[0]))
static const char *const pareto_outputs[] = {"pareto.png", "pareto_frequency.png", NULL};

/* Repeats of a Pareto point: at least PARETO_MIN_REPEATS, more while the
 * repeats so far took under PARETO_REPEAT_BUDGET s of CPU. */
#define PARETO_MIN_REPEATS 3
#define PARETO_MAX_REPEATS 9
#define PARETO_REPEAT_BUDGET 0.5

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* validate_run, repeated, each timed by the process's CPU clock over its
 * simulation (validate_row.cpu_seconds; a point runs in its own worker
 * process, so that is this run's CPU): the median and the range of the
 * repeats. CPU time, not wall time: on a shared machine the
 * wall clock counts the other processes too and reorders the curves (issue
 * 15). The computed values repeat exactly; a diverged run is not repeated. */
static int pareto_compute(int point, int quick, figure_points *out, char *err, size_t errlen)
{
    const pareto_run *run = quick ? &pareto_quick[point] : &pareto_full[point];
    double dt = run->dt_factor * validate_default_dt(run->case_name, run->scheme, run->nodes);
    validate_row row;
    double cpu[PARETO_MAX_REPEATS], spent = 0;
    int repeats = 0;
    while (repeats < PARETO_MAX_REPEATS &&
           (repeats < PARETO_MIN_REPEATS || spent < PARETO_REPEAT_BUDGET)) {
        memset(&row, 0, sizeof row);
        int status = validate_run(run->case_name, run->scheme, run->nodes, dt, &row);
        cpu[repeats] = row.cpu_seconds; /* the simulation only, not the reference */
        spent += cpu[repeats++];
        if (status < 0 || status == 1) {
            snprintf(err, errlen, "validate_run(%s, %s, NS %d): %s", run->case_name,
                     scheme_names[run->scheme], run->nodes, row.note);
            return -1;
        }
        if (row.status != 0) break; /* a diverged run: data, not repeated */
    }
    qsort(cpu, (size_t)repeats, sizeof cpu[0], compare_doubles);
    double median = repeats % 2 ? cpu[repeats / 2]
                                : 0.5 * (cpu[repeats / 2 - 1] + cpu[repeats / 2]);
    double values[13] = {(double)validate_case_index(run->case_name), (double)run->scheme,
                         (double)run->nodes, run->dt_factor, row.dt, row.computed,
                         row.reference, row.relative_error, median, cpu[0],
                         cpu[repeats - 1], (double)repeats, (double)row.status};
    if (figure_points_add(out, point, values)) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    return 0;
}

/* Horizontal error bars at y[i] from lo[i] to hi[i], with end caps of
 * +-cap decades of y (a log axis). 0, or -1 when out of memory. */
static int pareto_error_bars(plot *p, const double *y, const double *lo, const double *hi,
                             int n, plot_style style)
{
    const double cap = pow(10.0, 0.035);
    int rc = 0;
    style.dash = PLOT_SOLID;
    style.width = 1.5;
    for (int i = 0; i < n && rc == 0; i++) {
        if (!(hi[i] > lo[i])) continue; /* one repeat, or all equal: no bar */
        double bx[2] = {lo[i], hi[i]}, by[2] = {y[i], y[i]};
        double cy[2] = {y[i] / cap, y[i] * cap};
        double lx[2] = {lo[i], lo[i]}, hx[2] = {hi[i], hi[i]};
        rc |= plot_add_line(p, bx, by, 2, style, NULL);
        rc |= plot_add_line(p, lx, cy, 2, style, NULL);
        rc |= plot_add_line(p, hx, cy, 2, style, NULL);
    }
    return rc;
}

static int pareto_chart(const figure_points *points, const char *case_name, const char *file,
                        const char *title, const char *out_dir, FILE *summary, char *err,
                        size_t errlen)
{
    int case_index = validate_case_index(case_name), n = points->rows;
    double *x = malloc((size_t)n * sizeof *x), *y = malloc((size_t)n * sizeof *y);
    double *lo = malloc((size_t)n * sizeof *lo), *hi = malloc((size_t)n * sizeof *hi);
    char (*label_text)[24] = malloc((size_t)n * sizeof *label_text);
    const char **labels = malloc((size_t)n * sizeof *labels);
    plot *p = plot_create(1200, 800);
    int rc = (!x || !y || !lo || !hi || !label_text || !labels || !p) ? -1 : 0;
    if (rc == 0) {
        plot_set_title(p, title);
        plot_set_axis_labels(p, "CPU time per run [s] (median of 3 to 9 repeats; bars: "
                                "fastest to slowest)",
                             "relative error");
        plot_set_log(p, 1, 1);
    }
    /* a curve per scheme across NS at the default dt; for dynamic cases also a
     * curve per NS across dt. Axes span whole decades (log ticks at 10^k). */
    double x_lo = INFINITY, x_hi = 0, y_lo = INFINITY, y_hi = 0;
    for (int scheme = 0; scheme < ROD_SCHEME_COUNT && rc == 0; scheme++) {
        static const int dt_sweep_nodes_list[3] = {51, 21, 11};
        static const unsigned char dt_sweep_rgb[3] = {120, 50, 170}; /* purple */
        for (int sweep = 0; sweep < 4 && rc == 0; sweep++) {
            int count = 0, varied = 0;
            int dt_sweep_nodes = sweep > 0 ? dt_sweep_nodes_list[sweep - 1] : 0;
            for (int r = 0; r < n; r++) {
                const double *row = row_of(points, r);
                if ((int)row[1] != case_index || (int)row[2] != scheme) continue;
                /* row: point, case, scheme, nodes, dt_factor, dt, computed, reference,
                 * relative_error, cpu (median), cpu_min, cpu_max, repeats, status */
                int nodes = (int)row[3], is_default = row[4] == 1.0;
                double dt = row[5], error = row[8], cpu = row[9];
                if (sweep == 0 ? !is_default : nodes != dt_sweep_nodes) continue;
                if (row[13] != 0 || !(error > 0)) continue; /* diverged: no error to plot */
                varied += !is_default;
                x_lo = fmin(x_lo, row[10]);
                x_hi = fmax(x_hi, row[11]);
                y_lo = fmin(y_lo, error);
                y_hi = fmax(y_hi, error);
                x[count] = cpu;
                lo[count] = row[10];
                hi[count] = row[11];
                y[count] = error;
                if (sweep == 0) snprintf(label_text[count], sizeof label_text[count], "%d", nodes);
                else snprintf(label_text[count], sizeof label_text[count], "%.3g s", dt);
                labels[count] = label_text[count];
                count++;
                if (summary && (sweep == 0 || !is_default))
                    fprintf(summary, "pareto %s: %-8s NS = %3d dt = %-8.4g error %.3e, CPU "
                                     "%.4f s (%.4f .. %.4f, %d repeats)\n",
                            case_name, scheme_names[scheme], nodes, dt, error, cpu, row[10],
                            row[11], (int)row[12]);
            }
            if (count == 0 || (sweep > 0 && (count < 2 || varied == 0))) continue;
            /* sort by CPU time so the line runs left to right */
            for (int i = 1; i < count; i++)
                for (int j = i; j > 0 && x[j] < x[j - 1]; j--) {
                    double t = x[j]; x[j] = x[j - 1]; x[j - 1] = t;
                    t = y[j]; y[j] = y[j - 1]; y[j - 1] = t;
                    t = lo[j]; lo[j] = lo[j - 1]; lo[j - 1] = t;
                    t = hi[j]; hi[j] = hi[j - 1]; hi[j - 1] = t;
                    const char *l = labels[j]; labels[j] = labels[j - 1]; labels[j - 1] = l;
                }
            char legend[96];
            const unsigned char *rgb = sweep == 0 ? scheme_rgb[scheme] : dt_sweep_rgb;
            plot_style line = plot_style_line(rgb[0], rgb[1], rgb[2], 2.0,
                                              sweep == 0 ? PLOT_SOLID : PLOT_DASHED);
            plot_style mark = marker_style(rgb, 10, sweep == 0);
            if (sweep == 0)
                snprintf(legend, sizeof legend, "%s: NS = 11 ... (labels), default dt",
                         scheme_names[scheme]);
            else
                snprintf(legend, sizeof legend, "%s: NS = %d, dt varied (labels)",
                         scheme_names[scheme], dt_sweep_nodes);
            if (count >= 2) rc |= plot_add_line(p, x, y, count, line, NULL);
            rc |= pareto_error_bars(p, y, lo, hi, count, line);
            if (sweep == 0) {
                rc |= plot_add_markers(p, x, y, count, mark, labels, 9, -14, legend);
            } else {
                /* dt labels alternate below and above the points: neighbours
                 * in wall time sit close together and their labels would overlap */
                const char *below[64] = {0}, *above[64] = {0};
                int shown = count < 64 ? count : 64;
                for (int i = 0; i < shown; i++) (i % 2 ? above : below)[i] = labels[i];
                rc |= plot_add_markers(p, x, y, shown, mark, below, -30, 18, legend);
                rc |= plot_add_markers(p, x, y, shown, mark, above, -30, -12, NULL);
            }
        }
    }
    if (rc == 0 && strcmp(case_name, PARETO_FREQUENCY) == 0)
        rc |= plot_add_legend_note(p, "thesis: rotary inertia x ~1e7 to run at all; halves f1");
    if (rc) snprintf(err, errlen, "out of memory");
    if (rc == 0 && x_hi > 0 && y_hi > 0) {
        /* whole decades, at least 3 of them, with room for the point labels */
        double x0 = floor(log10(x_lo)), x1 = ceil(log10(x_hi) + 0.3);
        double y0 = floor(log10(y_lo) - 0.3), y1 = ceil(log10(y_hi) + 0.5);
        while (x1 - x0 < 3) x1 - log10(x_hi) < log10(x_lo) - x0 ? x1++ : x0--;
        while (y1 - y0 < 3) y1 - log10(y_hi) < log10(y_lo) - y0 ? y1++ : y0--;
        plot_set_limits(p, pow(10, x0), pow(10, x1), pow(10, y0), pow(10, y1));
    }
    if (rc == 0) rc = write_plot(p, out_dir, file, err, errlen);
    plot_destroy(p);
    free(x);
    free(y);
    free(lo);
    free(hi);
    free(label_text);
    free(labels);
    return rc;
}

static int pareto_draw(const figure_points *points, int quick, const char *out_dir,
                       FILE *summary, char *err, size_t errlen)
{
    (void)quick;
    int rc = pareto_chart(points, PARETO_DEFLECTION, "pareto.png",
                          "Error against cost: tip deflection under P = 4.5e-7 N (vs elastica)",
                          out_dir, summary, err, errlen);
    if (rc == 0)
        rc = pareto_chart(points, PARETO_FREQUENCY, "pareto_frequency.png",
                          "Error against cost: first bending frequency vs (beta_1 L)^2 sqrt(EI/m) / (2 pi L^2)",
                          out_dir, summary, err, errlen);
    return rc;
}

/* ---- buckling: critical axial force and twisting moment ------------------------ */

typedef enum { BUCKLE_AXIAL = 0, BUCKLE_TWIST_PINNED, BUCKLE_TWIST_CLAMPED } buckle_kind;

#define BUCKLING_NODES 51
static const double buckling_lengths_full[] = {0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 2.0, 2.5, 3.0};
static const double buckling_lengths_quick[] = {0.5, 1.0, 2.0};
static const double buckling_diameters_full[] = {0.25e-3, 0.5e-3, 0.75e-3, 1e-3, 1.25e-3,
                                                 1.5e-3, 2e-3, 2.5e-3};
static const double buckling_diameters_quick[] = {0.5e-3, 1e-3, 2e-3};
#define COUNT(a) ((int)(sizeof a / sizeof a[0]))
static const char *const buckling_length_outputs[] = {"buckling_length.png", NULL};
static const char *const buckling_diameter_outputs[] = {"buckling_diameter.png", NULL};
static const char *const twist_diameter_outputs[] = {"twist_diameter.png", NULL};

/* The theory: Euler's clamped-free load, Greenhill's pinned or clamped moment. */
static double buckling_theory(buckle_kind kind, double ei, double length)
{
    return kind == BUCKLE_AXIAL ? reference_euler_cantilever(ei, length)
         : kind == BUCKLE_TWIST_PINNED ? reference_greenhill_pinned(ei, length)
                                       : reference_greenhill_clamped(ei, length);
}

/* Table 1's rod at length L and diameter d, NS = 51: rod_buckling_factor on a
 * unit dead load (axial force -EI/L^2 along x at a free tip of a clamped root,
 * or an axial twisting moment EI/L with both ends pinned or both clamped, the
 * tip sliding along x: buckling.h). Row: kind, L (m), d (m), critical load
 * (N or N m), theory (same unit). */
static int buckling_point(buckle_kind kind, double length, double diameter, int point,
                          figure_points *out, char *err, size_t errlen)
{
    rod_model m = rod_model_default();
    m.nodes = BUCKLING_NODES;
    m.length = length;
    m.diameter = diameter;
    m.options.scheme = ROD_SCHEME_STATIC;
    m.tip_frame = ROD_FRAME_GLOBAL;
    if (rod_model_derive(&m, err, errlen)) return -1;
    double ei = m.stiffness[0], unit;
    if (kind == BUCKLE_AXIAL) {
        unit = ei / (length * length);
        m.tip_force[0] = -unit;
    } else {
        unit = ei / length;
        m.tip_moment[0] = unit;
        m.root_end = m.tip_end = kind == BUCKLE_TWIST_PINNED ? ROD_END_PINNED : ROD_END_CLAMPED;
        m.tip_slide[0] = 1.0; /* Greenhill's tip slides along the axis (issue 10: explicit) */
    }
    if (rod_model_derive(&m, err, errlen)) return -1;
    double lambda = 0;
    if (rod_buckling_factor(&m, 20.0, 1e-7, &lambda, err, errlen)) return -1;
    double values[5] = {(double)kind, length, diameter, lambda * unit,
                        buckling_theory(kind, ei, length)};
    if (figure_points_add(out, point, values)) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    return 0;
}

static int buckling_length_compute(int point, int quick, figure_points *out, char *err,
                                   size_t errlen)
{
    double length = quick ? buckling_lengths_quick[point] : buckling_lengths_full[point];
    return buckling_point(BUCKLE_AXIAL, length, 1e-3, point, out, err, errlen);
}

static int buckling_diameter_compute(int point, int quick, figure_points *out, char *err,
                                     size_t errlen)
{
    double d = quick ? buckling_diameters_quick[point] : buckling_diameters_full[point];
    return buckling_point(BUCKLE_AXIAL, 1.0, d, point, out, err, errlen);
}

/* Points alternate pinned, clamped at each diameter. */
static int twist_diameter_compute(int point, int quick, figure_points *out, char *err,
                                  size_t errlen)
{
    double d = quick ? buckling_diameters_quick[point / 2] : buckling_diameters_full[point / 2];
    return buckling_point(point % 2 ? BUCKLE_TWIST_CLAMPED : BUCKLE_TWIST_PINNED, 1.0, d, point,
                          out, err, errlen);
}

/* One chart: x = L (m) or d (mm), y = the critical load in micro-units; the
 * theory as a curve over the points' range, the computed loads as markers. */
static int buckling_chart(const figure_points *points, int against_diameter, const char *file,
                          const char *title, const char *y_label, const char *out_dir,
                          FILE *summary, char *err, size_t errlen)
{
    enum { CURVE = 200 };
    int n = points->rows;
    double *x = malloc((size_t)n * sizeof *x), *y = malloc((size_t)n * sizeof *y);
    double cx[CURVE], cy[CURVE];
    plot *p = plot_create(1200, 800);
    int rc = (!x || !y || !p || n < 1) ? -1 : 0;
    if (rc == 0) {
        plot_set_title(p, title);
        plot_set_axis_labels(p, against_diameter ? "rod diameter d [mm]" : "rod length L [m]",
                             y_label);
    }
    rod_model base = rod_model_default();
    double lo = INFINITY, hi = 0, y_hi = 0;
    for (int r = 0; r < n; r++) {
        const double *row = row_of(points, r);
        double v = against_diameter ? row[3] : row[2];
        lo = fmin(lo, v);
        hi = fmax(hi, v);
        y_hi = fmax(y_hi, fmax(row[4], row[5]));
    }
    static const unsigned char kind_rgb[3][3] = {{0, 90, 200}, {0, 90, 200}, {200, 30, 30}};
    static const char *const kind_theory[3] = {
        "theory: Euler, clamped-free, pi^2 E I / (4 L^2)",
        "theory: Greenhill, pinned ends, 2 pi E I / L",
        "theory: Greenhill, clamped ends, 8.9868 E I / L"};
    static const char *const kind_computed[3] = {
        "computed: rod_buckling_factor, static scheme, NS = 51",
        "computed: pinned ends (NS = 51)", "computed: clamped ends (NS = 51)"};
    for (int kind = 0; kind < 3 && rc == 0; kind++) {
        int count = 0;
        for (int r = 0; r < n; r++) {
            const double *row = row_of(points, r);
            if ((int)row[1] != kind) continue;
            x[count] = against_diameter ? 1e3 * row[3] : row[2];
            y[count] = 1e6 * row[4];
            count++;
            if (summary)
                fprintf(summary, "%s: L = %g m, d = %g mm: computed %.6e, theory %.6e "
                        "(relative error %.2e)\n", file, row[2], 1e3 * row[3], row[4], row[5],
                        fabs(row[4] / row[5] - 1.0));
        }
        if (count == 0) continue;
        for (int i = 0; i < CURVE; i++) {
            double v = lo + (hi - lo) * i / (CURVE - 1.0);
            double length = against_diameter ? 1.0 : v, d = against_diameter ? v : 1e-3;
            double ei = base.youngs_modulus * M_PI * pow(d, 4) / 64.0;
            cx[i] = against_diameter ? 1e3 * v : v;
            cy[i] = 1e6 * buckling_theory((buckle_kind)kind, ei, length);
        }
        const unsigned char *rgb = kind_rgb[kind];
        rc |= plot_add_line(p, cx, cy, CURVE, plot_style_line(rgb[0], rgb[1], rgb[2], 2.0,
                                                               PLOT_SOLID), kind_theory[kind]);
        rc |= plot_add_markers(p, x, y, count, marker_style(rgb, 12, 0), NULL, 0, 0,
                               kind_computed[kind]);
    }
    if (rc == 0) {
        char note[160];
        int twist = strncmp(file, "twist", 5) == 0;
        snprintf(note, sizeof note, "E = %.3g MPa, %s, dead %s", 1e-6 * base.youngs_modulus,
                 against_diameter ? "L = 1 m" : "d = 1 mm",
                 twist ? "axial moment; the tip slides along x" : "axial force; free tip");
        rc |= plot_add_legend_note(p, note);
        double x0 = against_diameter ? 1e3 * lo : lo, x1 = against_diameter ? 1e3 * hi : hi;
        plot_set_limits(p, 0, x1 + 0.05 * (x1 - x0), 0, 1e6 * y_hi * 1.25);
    }
    if (rc) snprintf(err, errlen, n < 1 ? "no points" : "out of memory");
    if (rc == 0) rc = write_plot(p, out_dir, file, err, errlen);
    plot_destroy(p);
    free(x);
    free(y);
    return rc;
}

static int buckling_length_draw(const figure_points *points, int quick, const char *out_dir,
                                FILE *summary, char *err, size_t errlen)
{
    (void)quick;
    return buckling_chart(points, 0, "buckling_length.png",
                          "Thesis fig. 8: axial tip force that buckles the rod, against its length",
                          "critical axial force [uN]", out_dir, summary, err, errlen);
}

static int buckling_diameter_draw(const figure_points *points, int quick, const char *out_dir,
                                  FILE *summary, char *err, size_t errlen)
{
    (void)quick;
    return buckling_chart(points, 1, "buckling_diameter.png",
                          "Thesis fig. 9: axial tip force that buckles the rod, against its "
                          "diameter", "critical axial force [uN]", out_dir, summary, err, errlen);
}

static int twist_diameter_draw(const figure_points *points, int quick, const char *out_dir,
                               FILE *summary, char *err, size_t errlen)
{
    (void)quick;
    return buckling_chart(points, 1, "twist_diameter.png",
                          "Thesis fig. 7: twisting moment that buckles the rod, against its "
                          "diameter", "critical twisting moment [uN m]", out_dir, summary, err,
                          errlen);
}

/* ---- the list ---------------------------------------------------------------- */

static const figure_def figure_table2 = {
    .name = "table2",
    .summary = "table 2: tip deflection against P, schemes, PL^3/3EI, elastica",
    .columns = "point,scheme,load_N,tip_x_m,tip_y_m",
    .value_columns = 4,
    .full_points = 3 * TABLE2_FULL_LOADS,
    .quick_points = 9,
    .outputs = table2_outputs,
    .compute = table2_compute,
    .draw = table2_draw,
};

static const figure_def figure_impulse = {
    .name = "impulse",
    .summary = "figs. 11-13: impulse response and spectra, modal frequencies",
    .columns = "point,t_s,tip_y_m,mid_y_m",
    .value_columns = 3,
    .full_points = 1,
    .quick_points = 1,
    .outputs = impulse_outputs,
    .compute = impulse_compute,
    .draw = impulse_draw,
};

static const figure_def figure_pareto = {
    .name = "pareto",
    .summary = "error against CPU time per scheme across NS and dt",
    .columns = "point,case,scheme,nodes,dt_factor,dt_s,computed,reference,relative_error,"
               "cpu_s,cpu_min_s,cpu_max_s,repeats,status",
    .value_columns = 13,
    .full_points = PARETO_FULL,
    .quick_points = PARETO_QUICK,
    .outputs = pareto_outputs,
    .compute = pareto_compute,
    .draw = pareto_draw,
};

#define BUCKLING_COLUMNS "point,kind,length_m,diameter_m,critical,theory"
static const figure_def figure_buckling_length = {
    .name = "buckling-length",
    .summary = "fig. 8: axial buckling force against L, pi^2 EI/(4L^2)",
    .columns = BUCKLING_COLUMNS,
    .value_columns = 5,
    .full_points = COUNT(buckling_lengths_full),
    .quick_points = COUNT(buckling_lengths_quick),
    .outputs = buckling_length_outputs,
    .compute = buckling_length_compute,
    .draw = buckling_length_draw,
};

static const figure_def figure_buckling_diameter = {
    .name = "buckling-diameter",
    .summary = "fig. 9: axial buckling force against d, pi^2 EI/(4L^2)",
    .columns = BUCKLING_COLUMNS,
    .value_columns = 5,
    .full_points = COUNT(buckling_diameters_full),
    .quick_points = COUNT(buckling_diameters_quick),
    .outputs = buckling_diameter_outputs,
    .compute = buckling_diameter_compute,
    .draw = buckling_diameter_draw,
};

static const figure_def figure_twist_diameter = {
    .name = "twist-diameter",
    .summary = "fig. 7: buckling twisting moment against d, Greenhill",
    .columns = BUCKLING_COLUMNS,
    .value_columns = 5,
    .full_points = 2 * COUNT(buckling_diameters_full),
    .quick_points = 2 * COUNT(buckling_diameters_quick),
    .outputs = twist_diameter_outputs,
    .compute = twist_diameter_compute,
    .draw = twist_diameter_draw,
};

/* The longest point first: `all` then finishes sooner on few cores. */
static const figure_def *const figures[] = {
    &figure_impulse,
    &figure_pareto,
    &figure_table2,
    &figure_twist_diameter,
    &figure_buckling_length,
    &figure_buckling_diameter,
    NULL,
};

const figure_def *const *figure_list(void) { return figures; }

const figure_def *figure_find(const char *name)
{
    for (int i = 0; figures[i]; i++)
        if (strcmp(figures[i]->name, name) == 0) return figures[i];
    return NULL;
}

const char *figure_name(const figure_def *f) { return f->name; }
const char *figure_summary(const figure_def *f) { return f->summary; }
const char *figure_columns(const figure_def *f) { return f->columns; }
const char *const *figure_outputs(const figure_def *f) { return f->outputs; }
int figure_point_count(const figure_def *f, int quick)
{
    return quick ? f->quick_points : f->full_points;
}

int figure_compute_point(const figure_def *f, int point, int quick, figure_points *out,
                         char *err, size_t errlen)
{
    int count = figure_point_count(f, quick);
    if (point < 0 || point >= count) {
        snprintf(err, errlen, "figure %s has points 0 .. %d%s; no point %d", f->name, count - 1,
                 quick ? " with --quick" : "", point);
        return -1;
    }
    return f->compute(point, quick, out, err, errlen);
}

int figure_draw(const figure_def *f, const figure_points *points, int quick,
                const char *out_dir, FILE *summary, char *err, size_t errlen)
{
    /* every point must have contributed: a lost CSV must not draw a thinner figure */
    int count = figure_point_count(f, quick);
    char *seen = calloc((size_t)count, 1);
    if (!seen) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    for (int r = 0; r < points->rows; r++) {
        int k = (int)row_of(points, r)[0];
        if (k >= 0 && k < count) seen[k] = 1;
    }
    int missing = -1;
    for (int k = 0; k < count && missing < 0; k++)
        if (!seen[k]) missing = k;
    free(seen);
    if (missing >= 0) {
        snprintf(err, errlen, "figure %s: no rows for point %d (of 0 .. %d)", f->name, missing,
                 count - 1);
        return -1;
    }
    if (outfile_mkdirs(out_dir, err, errlen)) return -1;
    return f->draw(points, quick, out_dir, summary, err, errlen);
}

/* ---- CSV --------------------------------------------------------------------- */

int figure_points_write_csv(const figure_def *f, const figure_points *points, FILE *out)
{
    fprintf(out, "%s\n", f->columns);
    for (int r = 0; r < points->rows; r++) {
        const double *row = row_of(points, r);
        fprintf(out, "%d", (int)row[0]);
        for (int c = 1; c <= points->columns; c++) fprintf(out, ",%.17g", row[c]);
        fputc('\n', out);
    }
    return ferror(out) ? -1 : 0;
}

/* Rows from an open stream; `path` names it in messages. */
static int read_csv_stream(const figure_def *f, FILE *in, const char *path,
                           figure_points *points, char *err, size_t errlen)
{
    char line[4096];
    int line_number = 0, rc = 0;
    double values[64];
    if (!fgets(line, sizeof line, in) || (line_number = 1, strcspn(line, "\r\n") !=
                                          strlen(f->columns)) ||
        strncmp(line, f->columns, strlen(f->columns)) != 0) {
        snprintf(err, errlen, "%s:1: expected the header \"%s\" of figure %s", path, f->columns,
                 f->name);
        rc = -1;
    }
    while (rc == 0 && fgets(line, sizeof line, in)) {
        line_number++;
        if (line[strspn(line, " \t\r\n")] == '\0') continue;
        char *p = line, *end;
        errno = 0;
        long point = strtol(p, &end, 10);
        int ok = end != p && point >= 0 && point < 1000000;
        p = end;
        for (int c = 0; ok && c < points->columns; c++) {
            if (*p != ',') { ok = 0; break; }
            p++;
            values[c] = strtod(p, &end);
            if (end == p) ok = 0;
            p = end;
        }
        if (ok && p[strspn(p, " \t\r\n")] != '\0') ok = 0;
        if (!ok) {
            snprintf(err, errlen, "%s:%d: expected a point index and %d numbers separated by "
                     "commas (columns %s)", path, line_number, points->columns, f->columns);
            rc = -1;
        } else if (figure_points_add(points, (int)point, values)) {
            snprintf(err, errlen, "out of memory");
            rc = -1;
        }
    }
    return rc;
}

int figure_points_read_csv(const figure_def *f, const char *path, figure_points *points,
                           char *err, size_t errlen)
{
    FILE *in = fopen(path, "r");
    if (!in) {
        snprintf(err, errlen, "%s: cannot read: %s", path, strerror(errno));
        return -1;
    }
    int rc = read_csv_stream(f, in, path, points, err, errlen);
    fclose(in);
    return rc;
}

/* ---- parallel sweep ------------------------------------------------------------ */

/* The workers (worker.h) send their rows back through a pipe, as CSV text:
 * no temporary directory, so nothing is left behind on any exit path, kill
 * -9 included. */
typedef struct sweep_task {
    int figure; /* index into figs */
    int point;
    char *text; /* the worker's CSV, as received */
    size_t length;
} sweep_task;

typedef struct sweep_context {
    const figure_def *const *figs;
    sweep_task *tasks;
    int quick, total, done;
    FILE *log;
    double start;
    char *err;
    size_t errlen;
} sweep_context;

/* Computes the task's point and writes its CSV; a failure's message goes to
 * stderr (from a worker, it has no other way out). */
static int pool_compute(void *context, int task, FILE *out)
{
    const sweep_context *c = context;
    const sweep_task *t = &c->tasks[task];
    const figure_def *f = c->figs[t->figure];
    char err[1024] = "";
    figure_points rows;
    figure_points_init(&rows, f);
    int rc = figure_compute_point(f, t->point, c->quick, &rows, err, sizeof err);
    if (rc == 0 && figure_points_write_csv(f, &rows, out)) {
        snprintf(err, sizeof err, "cannot send the point's rows to the parent");
        rc = -1;
    }
    if (rc) fprintf(stderr, "rodsim figure %s: point %d: %s\n", f->name, t->point, err);
    figure_points_release(&rows);
    return rc ? 1 : 0;
}

/* Keeps the task's text; the first failure stops the sweep. */
static int pool_computed(void *context, int task, const char *bytes, size_t n, int status)
{
    sweep_context *c = context;
    sweep_task *t = &c->tasks[task];
    const figure_def *f = c->figs[t->figure];
    c->done++;
    if (status != 0) {
        snprintf(c->err, c->errlen, "figure %s, point %d failed (%s; its message is above)",
                 f->name, t->point,
                 WIFSIGNALED(status) ? strsignal(WTERMSIG(status)) : "exit status 1");
        return 1;
    }
    if (!(t->text = malloc(n + 1))) {
        snprintf(c->err, c->errlen, "out of memory for the points' rows");
        return 1;
    }
    memcpy(t->text, bytes, n + 1);
    t->length = n;
    if (c->log)
        fprintf(c->log, "  %s point %d/%d done (%d of %d, %.1f s)\n", f->name, t->point + 1,
                figure_point_count(f, c->quick), c->done, c->total, now_seconds() - c->start);
    return 0;
}

int figure_sweep(const figure_def *const *figs, int n, int quick, int jobs, FILE *log,
                 figure_points *out, char *err, size_t errlen)
{
    int total = 0;
    for (int k = 0; k < n; k++) {
        figure_points_init(&out[k], figs[k]);
        total += figure_point_count(figs[k], quick);
    }
    sweep_task *tasks = calloc((size_t)total + 1, sizeof *tasks);
    if (!tasks) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    int t = 0;
    for (int k = 0; k < n; k++)
        for (int i = 0; i < figure_point_count(figs[k], quick); i++, t++) {
            tasks[t].figure = k;
            tasks[t].point = i;
        }
    sweep_context c = {figs, tasks, quick, total, 0, log, now_seconds(), err, errlen};
    worker_pool pool = {.jobs = jobs, .context = &c, .run = pool_compute, .done = pool_computed};
    int rc = worker_pool_run(&pool, NULL, total, err, errlen) ? -1 : 0;
    /* collect in point order */
    for (int i = 0; i < total; i++) {
        if (rc == 0) {
            char name[256];
            snprintf(name, sizeof name, "figure %s, point %d (from its process)",
                     figs[tasks[i].figure]->name, tasks[i].point);
            FILE *in = tasks[i].length ? fmemopen(tasks[i].text, tasks[i].length, "r") : NULL;
            if (!in) {
                snprintf(err, errlen, "%s: no rows received", name);
                rc = -1;
            } else {
                rc = read_csv_stream(figs[tasks[i].figure], in, name, &out[tasks[i].figure], err,
                                     errlen);
                fclose(in);
            }
        }
        free(tasks[i].text);
    }
    free(tasks);
    return rc;
}
