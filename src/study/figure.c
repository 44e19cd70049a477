/* figure.c: the figures (see figure.h): those drawn from sweeps as
 * definitions (figure_spec, run by cli/sweep_figure.c), the others with their
 * points, CSV and worker processes. */
#include "study/figure.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "base/clocks.h"
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

/* ---- table2: tip deflection against the tip force, as a sweep ----------------- */

/* The scene's rod (E, L, d), compiled in: the references use the sweep's own values. */
static int scene_rod(const char *path, rod_model *m, char *err, size_t errlen)
{
    const char *text = embedded_text(path);
    if (!text) {
        snprintf(err, errlen, "%s: not compiled into this binary", path);
        return -1;
    }
    ini_doc *doc = ini_parse(path, text, err, errlen);
    if (!doc) return -1;
    int rc = scene_read_rod(doc, m, err, errlen);
    ini_destroy(doc);
    return rc;
}

/* EI of the scene's rod at diameter d (d <= 0: the scene's), N m^2. */
static double bending_stiffness(const rod_model *m, double d)
{
    if (d <= 0.0) d = m->diameter;
    return m->youngs_modulus * M_PI * pow(d, 4) / 64.0;
}

#define TABLE2_SCENE "scenes/table2_450nN.ini"
/* Thesis table 2: P (N) and its "simulated" tip deflections (m). */
static const double table2_loads[3] = {4.5e-7, 8e-7, 1e-6};
static const double table2_thesis_values[3] = {0.0352, 0.0627, 0.0782};

/* The dead-load elastica's tip deflection (reference.h) at P = x. */
static int table2_elastica(int part, double x, double *y, char *err, size_t errlen)
{
    (void)part;
    rod_model m;
    if (scene_rod(TABLE2_SCENE, &m, err, errlen)) return -1;
    elastica_tip tip;
    int rc = elastica_dead_load(m.stiffness[0], m.length, 0.0, x, 0.0, 8000, &tip);
    rod_model_release(&m);
    if (rc) {
        snprintf(err, errlen, "elastica: no solution bracketed at P = %g N", x);
        return -1;
    }
    *y = tip.y;
    return 0;
}

/* Linear theory, P L^3 / 3EI, m, at P = x; NAN when the scene cannot be read. */
static double table2_linear(double x)
{
    rod_model m;
    char err[256];
    if (scene_rod(TABLE2_SCENE, &m, err, sizeof err)) return NAN;
    double y = x * m.length * m.length * m.length / (3.0 * m.stiffness[0]);
    rod_model_release(&m);
    return y;
}

/* The linear theory as a dashed line and the thesis' own numbers (its table 2). */
static int table2_decorate(plot *p, int ratio, double x_last)
{
    enum { CURVE = 50 };
    double cx[CURVE], cy[CURVE];
    for (int i = 0; i < CURVE; i++) {
        double load = x_last * (i + 1e-3) / (CURVE - 1);
        cx[i] = load * 1e9; /* nN */
        cy[i] = ratio ? 1.0 : 1e3 * table2_linear(load);
    }
    plot_style theory = plot_style_line(120, 120, 120, 2.0, PLOT_DASHED);
    int rc = plot_add_line(p, cx, cy, CURVE, theory, "P L³ / 3 E I (linear)");
    double tx[3], ty[3];
    for (int i = 0; i < 3; i++) {
        tx[i] = table2_loads[i] * 1e9;
        ty[i] = ratio ? table2_thesis_values[i] / table2_linear(table2_loads[i])
                      : table2_thesis_values[i] * 1e3;
    }
    /* the thesis' values in the y axis' millimetres (the ratio figure's
     * points are labelled with the same deflections) */
    char text[3][24];
    const char *labels[3];
    for (int i = 0; i < 3; i++) {
        snprintf(text[i], sizeof text[i], "%.1f mm", table2_thesis_values[i] * 1e3);
        labels[i] = text[i];
    }
    plot_style thesis = plot_style_line(0, 150, 60, 2.5, PLOT_SOLID);
    thesis.marker_size = 14;
    thesis.filled = 0;
    rc |= plot_add_markers(p, tx, ty, 3, thesis, labels, ratio ? -40 : 22, ratio ? -22 : 30,
                           "thesis table 2 (its simulation)");
    return rc ? -1 : 0;
}

/* Table 1's rod, NS = 51, under a dead tip load P along +y (the frame
 * PL^3/3EI and the dead-load elastica assume), settled, one part per scheme:
 *   static:   the scene as it is (an equilibrium per output time);
 *   implicit: backward Euler, dt = 0.5 s, load ramped over 2 s, damping 4e-4
 *             N s/m^2 (about critical for mode 1), state at 150 s;
 *   thesis:   rotary_inertia_scale 1e7 (it diverges without), dt = 0.1 s,
 *             ramp 10 s, damping 1e-3, state at 300 s (scheme_thesis.c:
 *             minimum_scale). fps = 1/dt: one step per output time. */
#define TABLE2_LOADS_FULL "tip.force[1]=1e-7,2e-7,3e-7,4.5e-7,6e-7,8e-7,1e-6,1.2e-6"
#define TABLE2_LOADS_QUICK "tip.force[1]=4.5e-7,8e-7,1e-6"
#define TABLE2_IMPLICIT "--set", "solver.scheme=implicit", "--set", "solver.dt=0.5", "--set", \
    "solver.theta=1", "--set", "tip.profile=ramp 2", "--set", "loads.linear_damping=4e-4", \
    "--set", "solver.duration=150", "--set", "render.fps=2"
#define TABLE2_THESIS "--set", "solver.scheme=thesis", "--set", "solver.dt=0.1", "--set", \
    "rod.rotary_inertia_scale=1e7", "--set", "tip.profile=ramp 10", "--set", \
    "loads.linear_damping=1e-3", "--set", "solver.duration=300", "--set", "render.fps=10"
static const char *const table2_static_full[] = {"--vary", TABLE2_LOADS_FULL, NULL};
static const char *const table2_static_quick[] = {"--vary", TABLE2_LOADS_QUICK, NULL};
static const char *const table2_implicit_full[] = {TABLE2_IMPLICIT, "--vary", TABLE2_LOADS_FULL,
                                                   NULL};
static const char *const table2_implicit_quick[] = {TABLE2_IMPLICIT, "--vary",
                                                    TABLE2_LOADS_QUICK, NULL};
static const char *const table2_thesis_full[] = {TABLE2_THESIS, "--vary", TABLE2_LOADS_FULL,
                                                 NULL};
static const char *const table2_thesis_quick[] = {TABLE2_THESIS, "--vary", TABLE2_LOADS_QUICK,
                                                  NULL};

static const figure_spec sweep_table2 = {
    .name = "table2",
    .summary = "table 2: tip y against P, 3 schemes, elastica",
    .scene = TABLE2_SCENE,
    .measure = "tip_y",
    .x_key = "tip.force[1]",
    .file = "table2",
    .title = "Thesis table 2: cantilever tip deflection under a tip force "
             "(L = 1 m, d = 1 mm, NS = 51)",
    .x_label = "tip force P [nN]",
    .y_label = "tip deflection y [mm]",
    .x_scale = 1e9,
    .y_scale = 1e3,
    .parts = 3,
    .part = {{"static", "static scheme (simulated)", table2_static_full, table2_static_quick,
              "elastica (exact, dead load)", {0, 90, 200}},
             {"implicit", "implicit scheme (simulated)", table2_implicit_full,
              table2_implicit_quick, "elastica (exact, dead load)", {200, 30, 30}},
             {"thesis", "thesis scheme (simulated)", table2_thesis_full, table2_thesis_quick,
              "elastica (exact, dead load)", {200, 110, 0}}},
    .reference = table2_elastica,
    .one_reference = 1,
    .reference_samples = 50, /* an elastica is a shooting solve: 30 ms each */
    .ratio_divisor = table2_linear,
    .ratio_title = "Table 2 relative to linear theory: y / (P L³ / 3 E I)",
    .ratio_y_label = "y / (P L³ / 3 E I)",
    .decorate = table2_decorate,
};

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

/* The impulse run's samples, every IMPULSE_SAMPLE s. */
typedef struct impulse_samples {
    int n;
    double *t;              /* (n) s */
    double *tip, *mid;      /* (n) y, m */
    double *tip_mm, *mid_mm; /* (n) y, mm */
    double duration;        /* s: the last sample's time */
} impulse_samples;

/* The spectra plotted, IMPULSE_SPECTRUM frequencies up to IMPULSE_F_MAX. */
#define IMPULSE_SPECTRUM 801

/* EI (N m^2), mass per length (kg/m) and length (m) of scenes/impulse.ini. */
static int impulse_rod_constants(double *ei, double *mass, double *length, char *err,
                                 size_t errlen)
{
    ini_doc *doc = load_impulse_scene(err, errlen);
    if (!doc) return -1;
    rod_model m;
    int rc = scene_read_rod(doc, &m, err, errlen);
    ini_destroy(doc);
    if (rc) return -1;
    *ei = m.stiffness[0];
    *mass = m.mass_per_length;
    *length = m.length;
    rod_model_release(&m);
    return 0;
}

static void impulse_samples_fill(const figure_points *points, impulse_samples *s)
{
    for (int i = 0; i < s->n; i++) {
        const double *row = row_of(points, i);
        s->t[i] = row[1];
        s->tip[i] = row[2];
        s->mid[i] = row[3];
        s->tip_mm[i] = 1e3 * s->tip[i];
        s->mid_mm[i] = 1e3 * s->mid[i];
    }
    s->duration = s->t[s->n - 1];
}

/* Thesis fig. 11: tip and mid-point against time. 0, or -1 out of memory. */
static int impulse_motion_plot(plot *motion, const impulse_samples *s)
{
    char title[160];
    snprintf(title, sizeof title,
             "Thesis fig. 11: displacement after the impulse (scenes/impulse.ini, %g s)",
             s->duration);
    plot_set_title(motion, title);
    plot_set_axis_labels(motion, "time t [s]", "displacement y [mm]");
    int rc = 0;
    rc |= plot_add_line(motion, s->t, s->tip_mm, s->n, plot_style_line(200, 30, 30, 2, PLOT_SOLID),
                        "free end (tip)");
    rc |= plot_add_line(motion, s->t, s->mid_mm, s->n, plot_style_line(0, 90, 200, 2, PLOT_SOLID),
                        "mid-point (s = L/2)");
    rc |= plot_add_legend_note(motion, "implicit Crank-Nicolson, NS = 51, dt = 0.5 ms");
    return rc;
}

/* Spectra of the displacement samples (Hann-windowed DFT, spectrum.h) at
 * frequencies f (Hz); *lo, *hi: the amplitude range shown (mm). */
static void impulse_spectra(const impulse_samples *s, double *f, double *tip_spectrum,
                            double *mid_spectrum, double *lo_out, double *hi_out)
{
    int n = s->n;
    double lo = INFINITY, hi = 0;
    for (int i = 0; i < IMPULSE_SPECTRUM; i++) {
        f[i] = IMPULSE_F_MAX * (i + 1) / IMPULSE_SPECTRUM;
        /* a sinusoid of amplitude A gives |DFT| = A sum(w)/2 = A n/4 with Hann w */
        tip_spectrum[i] = 4.0 / n * spectrum_magnitude(s->tip_mm, n, IMPULSE_SAMPLE, f[i]);
        mid_spectrum[i] = 4.0 / n * spectrum_magnitude(s->mid_mm, n, IMPULSE_SAMPLE, f[i]);
        lo = fmin(lo, fmin(tip_spectrum[i], mid_spectrum[i]));
        hi = fmax(hi, fmax(tip_spectrum[i], mid_spectrum[i]));
    }
    *lo_out = fmax(lo, hi * 1e-6);
    *hi_out = hi;
}

/* The summary's line for a mode at fn (Hz): the peaks found near it. */
static void impulse_mode_summary(FILE *summary, const impulse_samples *s, int mode, double fn)
{
    int n = s->n;
    double resolution = 2.0 / s->duration; /* Hann main lobe half width, Hz */
    if (fn < 3.0 * resolution) {
        fprintf(summary, "impulse: mode %d: analytical %.4f Hz: not resolved in %g s "
                "(needs several periods)\n", mode, fn, s->duration);
        return;
    }
    double band = fmin(fmax(0.15 * fn, 1.5 * resolution), 0.5);
    double tip_peak = spectrum_peak(s->tip_mm, n, IMPULSE_SAMPLE, fn - band, fn + band);
    double mid_peak = spectrum_peak(s->mid_mm, n, IMPULSE_SAMPLE, fn - band, fn + band);
    /* a mode with a node near L/2 barely moves the mid-point: no peak there */
    double tip_level = spectrum_magnitude(s->tip_mm, n, IMPULSE_SAMPLE, tip_peak);
    double mid_level = spectrum_magnitude(s->mid_mm, n, IMPULSE_SAMPLE, fn);
    fprintf(summary, "impulse: mode %d: analytical %.4f Hz; tip peak %.4f Hz (%+.2e)",
            mode, fn, tip_peak, tip_peak / fn - 1.0);
    if (mid_level > 0.05 * tip_level)
        fprintf(summary, ", mid-point peak %.4f Hz (%+.2e)\n", mid_peak,
                mid_peak / fn - 1.0);
    else
        fprintf(summary, "; mid-point: no peak (%.2g of the tip's level: a node "
                "near L/2)\n", mid_level / tip_level);
}

/* The analytical modal frequencies, (beta_n L)^2/(2 pi L^2) sqrt(EI/m), as
 * dashed lines from lo to 3 hi (mm) labelled f1, f2, ... above them; each
 * mode's line in the summary. 0, or -1 out of memory. */
static int impulse_modal_marks(plot *spectrum, const impulse_samples *s, double ei, double mass,
                               double length, double lo, double hi, FILE *summary)
{
    double mark_f[IMPULSE_MODES], mark_y[IMPULSE_MODES];
    char label_text[IMPULSE_MODES][16];
    const char *labels[IMPULSE_MODES];
    int marks = 0, rc = 0;
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
        if (summary) impulse_mode_summary(summary, s, mode, fn);
    }
    plot_style mark = plot_style_line(0, 140, 60, 1.5, PLOT_SOLID);
    mark.marker_size = 1;
    rc |= plot_add_markers(spectrum, mark_f, mark_y, marks, mark, labels, 6, 0, NULL);
    return rc;
}

/* Thesis figs. 12-13: the spectra, with the modal frequencies marked.
 * 0, or -1 out of memory. */
static int impulse_spectrum_plot(plot *spectrum, const impulse_samples *s, double ei,
                                 double mass, double length, FILE *summary)
{
    double f[IMPULSE_SPECTRUM], tip_spectrum[IMPULSE_SPECTRUM], mid_spectrum[IMPULSE_SPECTRUM];
    double lo, hi;
    impulse_spectra(s, f, tip_spectrum, mid_spectrum, &lo, &hi);
    char title[160];
    snprintf(title, sizeof title,
             "Thesis figs. 12-13: spectrum of the tip and mid-point motion (%g s)", s->duration);
    plot_set_title(spectrum, title);
    plot_set_axis_labels(spectrum, "frequency f [Hz]", "amplitude 4 |DFT| / n, Hann window [mm]");
    plot_set_log(spectrum, 0, 1);
    plot_set_limits(spectrum, 0, IMPULSE_F_MAX, lo, hi * 300);
    int rc = 0;
    rc |= plot_add_line(spectrum, f, tip_spectrum, IMPULSE_SPECTRUM,
                        plot_style_line(200, 30, 30, 2, PLOT_SOLID), "free end (tip)");
    rc |= plot_add_line(spectrum, f, mid_spectrum, IMPULSE_SPECTRUM,
                        plot_style_line(0, 90, 200, 2, PLOT_SOLID), "mid-point");
    rc |= impulse_modal_marks(spectrum, s, ei, mass, length, lo, hi, summary);
    return rc;
}

/* The summary's line of the largest |y| of the tip and the mid-point. */
static void impulse_largest_summary(FILE *summary, const impulse_samples *s)
{
    double tip_max = 0, mid_max = 0;
    for (int i = 0; i < s->n; i++) {
        tip_max = fmax(tip_max, fabs(s->tip[i]));
        mid_max = fmax(mid_max, fabs(s->mid[i]));
    }
    fprintf(summary, "impulse: largest |y| over %g s: tip %.3f mm, mid-point %.3f mm\n",
            s->duration, 1e3 * tip_max, 1e3 * mid_max);
}

static int impulse_draw(const figure_points *points, int quick, const char *out_dir,
                        FILE *summary, char *err, size_t errlen)
{
    (void)quick;
    double ei, mass, length;
    if (impulse_rod_constants(&ei, &mass, &length, err, errlen)) return -1;
    int n = points->rows;
    impulse_samples s = {.n = n};
    s.t = malloc((size_t)n * sizeof *s.t);
    s.tip = malloc((size_t)n * sizeof *s.tip);
    s.mid = malloc((size_t)n * sizeof *s.mid);
    s.tip_mm = malloc((size_t)n * sizeof *s.tip_mm);
    s.mid_mm = malloc((size_t)n * sizeof *s.mid_mm);
    plot *motion = plot_create(1200, 800), *spectrum = plot_create(1200, 800);
    int rc = (!s.t || !s.tip || !s.mid || !s.tip_mm || !s.mid_mm || !motion || !spectrum ||
              n < 16) ? -1 : 0;
    if (rc) snprintf(err, errlen, n < 16 ? "impulse: %d samples, too few" : "out of memory", n);
    if (rc == 0) {
        impulse_samples_fill(points, &s);
        rc |= impulse_motion_plot(motion, &s);
        rc |= impulse_spectrum_plot(spectrum, &s, ei, mass, length, summary);
        if (rc) snprintf(err, errlen, "out of memory");
        if (summary) impulse_largest_summary(summary, &s);
    }
    if (rc == 0) rc = write_plot(motion, out_dir, "impulse.png", err, errlen);
    if (rc == 0) rc = write_plot(spectrum, out_dir, "impulse_spectrum.png", err, errlen);
    plot_destroy(motion);
    plot_destroy(spectrum);
    free(s.t);
    free(s.tip);
    free(s.mid);
    free(s.tip_mm);
    free(s.mid_mm);
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

/* One curve of a Pareto chart: count points, sorted by CPU time once drawn. */
typedef struct pareto_curve {
    double *x, *y, *lo, *hi;  /* (n) median CPU s, relative error, fastest and slowest CPU s */
    char (*label_text)[24];   /* (n) NS or dt, as text */
    const char **labels;      /* (n) into label_text */
    int count, varied;        /* points; of them, at a dt other than the default */
} pareto_curve;

/* Dt sweeps of the dynamic cases: sweep s > 0 is NS = this[s - 1]. */
static const int pareto_dt_sweep_nodes[3] = {51, 21, 11};

/* The points of one curve: sweep 0 is the scheme across NS at the default
 * dt, sweep s > 0 the scheme at NS = pareto_dt_sweep_nodes[s - 1] across dt.
 * extent (x_lo, x_hi, y_lo, y_hi) grows to take them in; each point's line
 * in the summary. */
static void pareto_gather(const figure_points *points, const char *case_name, int scheme,
                          int sweep, pareto_curve *c, double extent[4], FILE *summary)
{
    int case_index = validate_case_index(case_name);
    int dt_sweep_nodes = sweep > 0 ? pareto_dt_sweep_nodes[sweep - 1] : 0;
    c->count = c->varied = 0;
    for (int r = 0; r < points->rows; r++) {
        const double *row = row_of(points, r);
        if ((int)row[1] != case_index || (int)row[2] != scheme) continue;
        /* row: point, case, scheme, nodes, dt_factor, dt, computed, reference,
         * relative_error, cpu (median), cpu_min, cpu_max, repeats, status */
        int nodes = (int)row[3], is_default = row[4] == 1.0;
        double dt = row[5], error = row[8], cpu = row[9];
        if (sweep == 0 ? !is_default : nodes != dt_sweep_nodes) continue;
        if (row[13] != 0 || !(error > 0)) continue; /* diverged: no error to plot */
        c->varied += !is_default;
        extent[0] = fmin(extent[0], row[10]);
        extent[1] = fmax(extent[1], row[11]);
        extent[2] = fmin(extent[2], error);
        extent[3] = fmax(extent[3], error);
        int k = c->count++;
        c->x[k] = cpu;
        c->lo[k] = row[10];
        c->hi[k] = row[11];
        c->y[k] = error;
        if (sweep == 0) snprintf(c->label_text[k], sizeof c->label_text[k], "%d", nodes);
        else snprintf(c->label_text[k], sizeof c->label_text[k], "%.3g s", dt);
        c->labels[k] = c->label_text[k];
        if (summary && (sweep == 0 || !is_default))
            fprintf(summary, "pareto %s: %-8s NS = %3d dt = %-8.4g error %.3e, CPU "
                             "%.4f s (%.4f .. %.4f, %d repeats)\n",
                    case_name, scheme_names[scheme], nodes, dt, error, cpu, row[10],
                    row[11], (int)row[12]);
    }
}

/* sort by CPU time so the line runs left to right */
static void pareto_sort(pareto_curve *c)
{
    double *x = c->x, *y = c->y, *lo = c->lo, *hi = c->hi;
    const char **labels = c->labels;
    for (int i = 1; i < c->count; i++)
        for (int j = i; j > 0 && x[j] < x[j - 1]; j--) {
            double t = x[j]; x[j] = x[j - 1]; x[j - 1] = t;
            t = y[j]; y[j] = y[j - 1]; y[j - 1] = t;
            t = lo[j]; lo[j] = lo[j - 1]; lo[j - 1] = t;
            t = hi[j]; hi[j] = hi[j - 1]; hi[j - 1] = t;
            const char *l = labels[j]; labels[j] = labels[j - 1]; labels[j - 1] = l;
        }
}

/* A curve's line, error bars and labelled markers, with its legend.
 * 0, or -1 out of memory. */
static int pareto_add_curve(plot *p, const pareto_curve *c, int scheme, int sweep)
{
    static const unsigned char dt_sweep_rgb[3] = {120, 50, 170}; /* purple */
    int count = c->count, rc = 0;
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
                 scheme_names[scheme], pareto_dt_sweep_nodes[sweep - 1]);
    if (count >= 2) rc |= plot_add_line(p, c->x, c->y, count, line, NULL);
    rc |= pareto_error_bars(p, c->y, c->lo, c->hi, count, line);
    if (sweep == 0) {
        rc |= plot_add_markers(p, c->x, c->y, count, mark, c->labels, 9, -14, legend);
    } else {
        /* dt labels alternate below and above the points: neighbours
         * in wall time sit close together and their labels would overlap */
        const char *below[64] = {0}, *above[64] = {0};
        int shown = count < 64 ? count : 64;
        for (int i = 0; i < shown; i++) (i % 2 ? above : below)[i] = c->labels[i];
        rc |= plot_add_markers(p, c->x, c->y, shown, mark, below, -30, 18, legend);
        rc |= plot_add_markers(p, c->x, c->y, shown, mark, above, -30, -12, NULL);
    }
    return rc;
}

/* Axis limits of whole decades, at least 3 of them, with room for the
 * point labels, round extent (x_lo, x_hi, y_lo, y_hi). */
static void pareto_decade_limits(plot *p, const double extent[4])
{
    double x_lo = extent[0], x_hi = extent[1], y_lo = extent[2], y_hi = extent[3];
    double x0 = floor(log10(x_lo)), x1 = ceil(log10(x_hi) + 0.3);
    double y0 = floor(log10(y_lo) - 0.3), y1 = ceil(log10(y_hi) + 0.5);
    while (x1 - x0 < 3) x1 - log10(x_hi) < log10(x_lo) - x0 ? x1++ : x0--;
    while (y1 - y0 < 3) y1 - log10(y_hi) < log10(y_lo) - y0 ? y1++ : y0--;
    plot_set_limits(p, pow(10, x0), pow(10, x1), pow(10, y0), pow(10, y1));
}

static int pareto_chart(const figure_points *points, const char *case_name, const char *file,
                        const char *title, const char *out_dir, FILE *summary, char *err,
                        size_t errlen)
{
    int n = points->rows;
    pareto_curve c = {0};
    c.x = malloc((size_t)n * sizeof *c.x);
    c.y = malloc((size_t)n * sizeof *c.y);
    c.lo = malloc((size_t)n * sizeof *c.lo);
    c.hi = malloc((size_t)n * sizeof *c.hi);
    c.label_text = malloc((size_t)n * sizeof *c.label_text);
    c.labels = malloc((size_t)n * sizeof *c.labels);
    plot *p = plot_create(1200, 800);
    int rc = (!c.x || !c.y || !c.lo || !c.hi || !c.label_text || !c.labels || !p) ? -1 : 0;
    if (rc == 0) {
        plot_set_title(p, title);
        plot_set_axis_labels(p, "CPU time per run [s] (median of 3 to 9 repeats; bars: "
                                "fastest to slowest)",
                             "relative error");
        plot_set_log(p, 1, 1);
    }
    /* a curve per scheme across NS at the default dt; for dynamic cases also a
     * curve per NS across dt. Axes span whole decades (log ticks at 10^k). */
    double extent[4] = {INFINITY, 0, INFINITY, 0}; /* x_lo, x_hi, y_lo, y_hi */
    for (int scheme = 0; scheme < ROD_SCHEME_COUNT && rc == 0; scheme++)
        for (int sweep = 0; sweep < 4 && rc == 0; sweep++) {
            pareto_gather(points, case_name, scheme, sweep, &c, extent, summary);
            if (c.count == 0 || (sweep > 0 && (c.count < 2 || c.varied == 0))) continue;
            pareto_sort(&c);
            rc |= pareto_add_curve(p, &c, scheme, sweep);
        }
    if (rc == 0 && strcmp(case_name, PARETO_FREQUENCY) == 0)
        rc |= plot_add_legend_note(p, "thesis: rotary inertia x ~1e7 to run at all; halves f1");
    if (rc) snprintf(err, errlen, "out of memory");
    if (rc == 0 && extent[1] > 0 && extent[3] > 0) pareto_decade_limits(p, extent);
    if (rc == 0) rc = write_plot(p, out_dir, file, err, errlen);
    plot_destroy(p);
    free(c.x);
    free(c.y);
    free(c.lo);
    free(c.hi);
    free(c.label_text);
    free(c.labels);
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

/* ---- buckling: critical axial force and twisting moment, as sweeps ------------ */

/* Figures 7 to 9 are sweeps (figure.h: figure_spec; run by cli/sweep_figure.c):
 * the scene's small axial load scaled by the critical_load or
 * critical_moment measure (rod_buckling_factor) at each L or d. */
#define BUCKLING_SCENE "scenes/buckling_figure.ini"
#define TWIST_SCENE "scenes/twist_figure.ini"

/* Euler, clamped-free: pi^2 EI / (4 L^2), at L = x. */
static int euler_against_length(int part, double x, double *y, char *err, size_t errlen)
{
    (void)part;
    rod_model m;
    if (scene_rod(BUCKLING_SCENE, &m, err, errlen)) return -1;
    *y = reference_euler_cantilever(bending_stiffness(&m, 0.0), x);
    rod_model_release(&m);
    return 0;
}

/* Euler at d = x, the scene's L. */
static int euler_against_diameter(int part, double x, double *y, char *err, size_t errlen)
{
    (void)part;
    rod_model m;
    if (scene_rod(BUCKLING_SCENE, &m, err, errlen)) return -1;
    *y = reference_euler_cantilever(bending_stiffness(&m, x), m.length);
    rod_model_release(&m);
    return 0;
}

/* Greenhill at d = x: part 0 pinned ends 2 pi EI/L, part 1 clamped 8.9868 EI/L. */
static int greenhill_against_diameter(int part, double x, double *y, char *err, size_t errlen)
{
    rod_model m;
    if (scene_rod(TWIST_SCENE, &m, err, errlen)) return -1;
    double ei = bending_stiffness(&m, x);
    *y = part == 0 ? reference_greenhill_pinned(ei, m.length)
                   : reference_greenhill_clamped(ei, m.length);
    rod_model_release(&m);
    return 0;
}

static const char *const buckling_length_full[] = {
    "--vary", "rod.length=0.25,0.5,0.75,1,1.25,1.5,2,2.5,3", NULL};
static const char *const buckling_length_quick[] = {"--vary", "rod.length=0.5,1,2", NULL};
#define DIAMETERS_FULL "rod.diameter=0.25e-3,0.5e-3,0.75e-3,1e-3,1.25e-3,1.5e-3,2e-3,2.5e-3"
#define DIAMETERS_QUICK "rod.diameter=0.5e-3,1e-3,2e-3"
static const char *const diameters_full[] = {"--vary", DIAMETERS_FULL, NULL};
static const char *const diameters_quick[] = {"--vary", DIAMETERS_QUICK, NULL};
/* the scene's ends are pinned; the second part clamps both */
static const char *const clamped_full[] = {"--set", "ends.root=clamped", "--set",
                                           "ends.tip=clamped", "--vary", DIAMETERS_FULL, NULL};
static const char *const clamped_quick[] = {"--set", "ends.root=clamped", "--set",
                                            "ends.tip=clamped", "--vary", DIAMETERS_QUICK, NULL};

static const figure_spec sweep_buckling_length = {
    .name = "buckling-length",
    .summary = "fig. 8: buckling force against L, Euler",
    .scene = BUCKLING_SCENE,
    .measure = "critical_load",
    .x_key = "rod.length",
    .file = "buckling_length",
    .title = "Thesis fig. 8: axial tip force that buckles the rod, against its length",
    .x_label = "rod length L [m]",
    .y_label = "critical axial force [µN]",
    .note = "E = 87.5 MPa, d = 1 mm, dead axial force; free tip",
    .x_scale = 1.0,
    .y_scale = 1e6,
    .parts = 1,
    .part = {{"", "computed: rod_buckling_factor, static scheme, NS = 51",
              buckling_length_full, buckling_length_quick,
              "theory: Euler, clamped-free, π² E I / (4 L²)", {0, 0, 0}}},
    .reference = euler_against_length,
};

static const figure_spec sweep_buckling_diameter = {
    .name = "buckling-diameter",
    .summary = "fig. 9: buckling force against d, Euler",
    .scene = BUCKLING_SCENE,
    .measure = "critical_load",
    .x_key = "rod.diameter",
    .file = "buckling_diameter",
    .title = "Thesis fig. 9: axial tip force that buckles the rod, against its diameter",
    .x_label = "rod diameter d [mm]",
    .y_label = "critical axial force [µN]",
    .note = "E = 87.5 MPa, L = 1 m, dead axial force; free tip",
    .x_scale = 1e3,
    .y_scale = 1e6,
    .parts = 1,
    .part = {{"", "computed: rod_buckling_factor, static scheme, NS = 51", diameters_full,
              diameters_quick, "theory: Euler, clamped-free, π² E I / (4 L²)", {0, 0, 0}}},
    .reference = euler_against_diameter,
};

static const figure_spec sweep_twist_diameter = {
    .name = "twist-diameter",
    .summary = "fig. 7: buckling moment against d, Greenhill",
    .scene = TWIST_SCENE,
    .measure = "critical_moment",
    .x_key = "rod.diameter",
    .file = "twist_diameter",
    .title = "Thesis fig. 7: twisting moment that buckles the rod, against its diameter",
    .x_label = "rod diameter d [mm]",
    .y_label = "critical twisting moment [µN m]",
    .note = "E = 87.5 MPa, L = 1 m, dead axial moment; the tip slides along x",
    .x_scale = 1e3,
    .y_scale = 1e6,
    .parts = 2,
    .part = {{"pinned", "computed: pinned ends (NS = 51)", diameters_full, diameters_quick,
              "theory: Greenhill, pinned ends, 2π E I / L", {0, 0, 0}},
             {"clamped", "computed: clamped ends (NS = 51)", clamped_full, clamped_quick,
              "theory: Greenhill, clamped ends, 8.9868 E I / L", {0, 0, 0}}},
    .reference = greenhill_against_diameter,
};

/* The longest first, as figures[] below. */
static const figure_spec *const figure_specs[] = {
    &sweep_table2,
    &sweep_twist_diameter,
    &sweep_buckling_length,
    &sweep_buckling_diameter,
    NULL,
};

const figure_spec *const *figure_spec_list(void) { return figure_specs; }

const figure_spec *figure_spec_find(const char *name)
{
    for (int i = 0; figure_specs[i]; i++)
        if (strcmp(figure_specs[i]->name, name) == 0) return figure_specs[i];
    return NULL;
}

int figure_spec_points(const figure_spec *f, int part, int quick)
{
    const char *const *args = quick ? f->part[part].quick_args : f->part[part].args;
    int points = 1;
    for (int i = 0; args[i]; i++) {
        if (strcmp(args[i], "--vary") != 0 || !args[i + 1]) continue;
        int values = 1;
        for (const char *c = args[++i]; *c; c++) values += *c == ',';
        points *= values;
    }
    return points;
}

/* ---- the list ---------------------------------------------------------------- */


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

/* The longest point first: `all` then finishes sooner on few cores. */
static const figure_def *const figures[] = {
    &figure_impulse,
    &figure_pareto,
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
                figure_point_count(f, c->quick), c->done, c->total, wall_seconds() - c->start);
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
    sweep_context c = {figs, tasks, quick, total, 0, log, wall_seconds(), err, errlen};
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
