/* scheme_implicit.c: the implicit scheme's face (scheme_implicit.h): its
 * rod_scheme_ops and the functions its tests check it with. The scheme
 * itself lives in src/sim/implicit/: work.c (what a run holds), residual.c
 * and planar.c (the equations), jacobian.c, newton.c, and the step's stages
 * start.c, accept.c, step.c; contact's laws in src/sim/contact/. */
#include "sim/scheme_implicit.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/band.h"
#include "sim/implicit/jacobian.h"
#include "sim/implicit/residual.h"
#include "sim/implicit/start.h"
#include "sim/implicit/step.h"
#include "sim/implicit/work.h"
#include "sim/rod.h"
#include "sim/tissue/tissue_coupling.h"

static void *create(const rod_model *m, char *err, size_t errlen)
{
    return implicit_create(m, err, errlen);
}

static void destroy(void *p)
{
    implicit_destroy(p);
}

/* The rod's step, and an elastic pad's equilibrium under the forces the
 * thread exerts at its punctures and on its surface (tissue_coupling.h) */
static rod_status step(void *p, const rod_model *m, rod_state *s, double dt, rod_report *report)
{
    const int pad = tissue_coupling_pad(m) >= 0;
    if (pad && tissue_coupling_link(m, s, report->message, sizeof report->message)) return ROD_FAILED;
    rod_status st = implicit_step(p, m, s, dt, report);
    implicit_work *w = p;
    if (st == ROD_OK && pad && !m->pad_by_set &&
        tissue_coupling_step(m, s, w->contact.pad_last, report->message, sizeof report->message))
        return ROD_FAILED;
    return st;
}

static int refresh(void *p, const rod_model *m, const rod_state *s, double dt)
{
    return implicit_refresh(p, m, s, dt);
}

static double stable_dt(const rod_model *m, const char **limit)
{
    (void)m;
    if (limit) *limit = "implicit: unconditionally stable (no stability limit)";
    return INFINITY;
}

void rod_implicit_link(void *work, struct rod_cross *cross)
{
    ((implicit_work *)work)->cross = cross;
}

double *rod_implicit_pad_record(void *work)
{
    return ((implicit_work *)work)->contact.pad_last;
}

const rod_scheme_ops rod_scheme_implicit = {"implicit", create, step, destroy, stable_dt,
                                             refresh};

/* The test functions' stage: the step of dt from s prepared up to Newton,
 * its first iterate in w->x (s read only). Returns 0, or non-zero when it
 * cannot be prepared. */
static int first_iterate(implicit_work *w, const rod_model *m, const rod_state *s, double dt,
                         rod_report *report)
{
    int continuing;
    return implicit_prepare_step(w, m, s, dt, report, 0, &continuing);
}

/* rod_implicit_jacobian_error and rod_implicit_contact_jacobian_error:
 * with_contact 0 compares the rod's part (contact, punctures and the
 * pairs' laws left out, steps of 1e-4 of each unknown's size), 1 the whole
 * Jacobian Newton uses with surfaces and punctures (the rod's part +
 * implicit_add_contact_jacobian; the pairs' laws left out, they join through
 * rod_self_contact_correct), by steps of 1e-7: friction turns within its
 * creep speed, which a larger step would straddle */
static double jacobian_error(const rod_model *m, const rod_state *s, double dt, double perturb,
                             int with_contact, int *column, double *floor)
{
    if (floor) *floor = 0.0;
    char err[256];
    implicit_work *w = implicit_create(m, err, sizeof err);
    double worst = NAN;
    if (column) *column = -1;
    if (!w || w->planar) goto done;
    rod_report report;
    memset(&report, 0, sizeof report);
    if (first_iterate(w, m, s, dt, &report)) goto done;
    /* away from the start-of-step guess, deterministically, by `perturb`
     * of each unknown's typical size */
    for (int i = 0; i < w->unknowns; i++)
        w->x[i] += perturb * w->var_scale[w->var_kind[i % BLOCK]] * sin(1.0 + 0.7 * i);
    /* central differences, one column at a time (O(h^2), and no colouring:
     * independent of fd_jacobian's grouping and of its one-sided error) */
    const int nu = w->unknowns, kl = w->lu.kl, ld = w->lu.ldab;
    const size_t size = (size_t)ld * (size_t)nu;
    double *fd = calloc(size, sizeof(double)), *plus = malloc((size_t)nu * sizeof(double));
    double *x0 = malloc((size_t)nu * sizeof(double)), *step = malloc((size_t)nu * sizeof(double));
    if (!fd || !plus || !x0 || !step) {
        free(fd);
        free(plus);
        free(x0);
        free(step);
        goto done;
    }
    memcpy(x0, w->x, (size_t)nu * sizeof(double));
    w->contact_off = !with_contact;
    w->self_off = 1;
    const double relative = with_contact ? 1e-7 : 1e-4;
    for (int col = 0; col < nu; col++) {
        const double h = step[col] =
            relative * fmax(fabs(x0[col]), w->var_scale[w->var_kind[col % BLOCK]]);
        w->x[col] = x0[col] + h;
        implicit_evaluate(w, m, w->x, s->time, dt, plus);
        w->x[col] = x0[col] - h;
        implicit_evaluate(w, m, w->x, s->time, dt, w->perturbed);
        w->x[col] = x0[col];
        for (int row = col - kl; row <= col + kl; row++)
            if (row >= 0 && row < nu)
                fd[(size_t)(2 * kl + row - col) + (size_t)col * (size_t)ld] =
                    (plus[row] - w->perturbed[row]) / (2.0 * h);
    }
    free(plus);
    free(x0);
    w->contact_off = 1;
    implicit_analytic_jacobian(w, m, s->time, dt);
    w->contact_off = 0;
    if (with_contact && w->has_contact) implicit_add_contact_jacobian(w, m, s->time, dt, 0);
    w->self_off = 0;
    /* per entry, the differences' rounding, about 1e-16 of the residual's
     * O(1) terms over h, is not held against the closed form */
    worst = 0.0;
    for (int col = 0; col < nu; col++) {
        const double noise = 3e-16 / step[col];
        double big = 0.0, diff = 0.0;
        for (int r = 0; r < ld; r++) {
            const size_t k = (size_t)r + (size_t)col * (size_t)ld;
            big = fmax(big, fabs(fd[k]));
            diff = fmax(diff, fabs(fd[k] - w->lu.ab[k]) - noise);
        }
        double e = big > 0.0 ? diff / big : diff;
        if (floor && big > 0.0) *floor = fmax(*floor, noise / big);
        if (!(e <= worst)) {
            worst = e;
            if (column) *column = col;
        }
    }
    free(fd);
    free(step);
done:
    implicit_destroy(w);
    return worst;
}

double rod_implicit_rows_solve_check(const rod_model *m, const rod_state *s, double dt, int count,
                                     int first, long *differ)
{
    char err[256];
    implicit_work *w = implicit_create(m, err, sizeof err);
    double worst = NAN;
    *differ = -1;
    if (!w || w->planar || !w->lu.rows || count < 1) goto done;
    rod_report report;
    memset(&report, 0, sizeof report);
    if (first_iterate(w, m, s, dt, &report)) goto done;
    w->contact_off = 1;
    implicit_analytic_jacobian(w, m, s->time, dt);
    w->contact_off = 0;
    const int nu = w->unknowns, kl = w->lu.kl, ld = w->lu.ldab;
    const size_t size = (size_t)ld * (size_t)nu, all = (size_t)nu * (size_t)count;
    double *a = malloc(size * sizeof(double)), *b = calloc(all, sizeof(double));
    double *x = malloc(all * sizeof(double)), *y = malloc(all * sizeof(double));
    /* the same right-hand sides by their entries (band_solve_entries) */
    double *z = malloc(all * sizeof(double)), *value = malloc(all * sizeof(double));
    int *start = malloc(((size_t)count + 1) * sizeof(int)), *row = malloc(all * sizeof(int));
    if (a && b && x && y && z && value && start && row) {
        memcpy(a, w->lu.ab, size * sizeof(double));
        if (implicit_factor_band(w, dt) == 0) {
            /* right-hand sides zero above row `first`, as the pairs' are */
            for (int c = 0; c < count; c++)
                for (int i = first; i < nu; i++)
                    b[(size_t)c * (size_t)nu + (size_t)i] = sin(1.0 + 0.37 * i + 1.3 * c);
            memcpy(x, b, all * sizeof(double));
            memcpy(y, b, all * sizeof(double));
            int entries = 0;
            for (int c = 0; c < count; c++) {
                start[c] = entries;
                for (int i = first; i < nu; i++, entries++)
                    row[entries] = i, value[entries] = b[(size_t)c * (size_t)nu + (size_t)i];
            }
            start[count] = entries;
            band_solve_rows(&w->lu, x, count, first);
            band_solve_entries(&w->lu, z, count, first, start, row, value);
            for (int c = 0; c < count; c++) band_solve(&w->lu, &y[(size_t)c * (size_t)nu]);
            *differ = 0;
            for (size_t k = 0; k < all; k++)
                *differ += memcmp(&x[k], &y[k], sizeof(double)) != 0 ||
                           memcmp(&z[k], &y[k], sizeof(double)) != 0;
            /* |A x - b| over b's largest entry, A the matrix before its factors */
            worst = 0.0;
            for (int c = 0; c < count; c++) {
                const double *xc = &x[(size_t)c * (size_t)nu], *bc = &b[(size_t)c * (size_t)nu];
                for (int i = 0; i < nu; i++) {
                    double r = -bc[i];
                    for (int j = i - kl; j <= i + kl; j++)
                        if (j >= 0 && j < nu)
                            r += a[(size_t)(2 * kl + i - j) + (size_t)j * (size_t)ld] * xc[j];
                    worst = fmax(worst, fabs(r));
                }
            }
        }
    }
    free(a);
    free(b);
    free(x);
    free(y);
    free(z);
    free(value);
    free(start);
    free(row);
done:
    implicit_destroy(w);
    return worst;
}

double rod_implicit_jacobian_error(const rod_model *m, const rod_state *s, double dt,
                                   double perturb, int *column, double *floor)
{
    return jacobian_error(m, s, dt, perturb, 0, column, floor);
}

double rod_implicit_contact_jacobian_error(const rod_model *m, const rod_state *s, double dt,
                                           double perturb, int *column, double *floor)
{
    return jacobian_error(m, s, dt, perturb, 1, column, floor);
}
