/* static_buckling.c: the static scheme's support for rod_buckling_factor
 * (buckling.h), which finds where the straight rod stops being stable from
 * the complex determinant of this scheme's Jacobian there (scheme_static.h
 * says why complex). */
#include "sim/scheme_static.h"

#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sim/static/static_internal.h"
#include "sim/static/static_solve.h"
#include "base/vec3.h"

/* Entry (row, col) of the Jacobian of static_build_jacobian, before its LU. */
static double jacobian_entry(const static_work *w, int row, int col)
{
    int nb = w->band_unknowns;
    if (row < nb && col < nb) {
        if (row - col > BAND_LOWER || col - row > BAND_UPPER) return 0.0;
        return w->band[(size_t)col * w->band_rows + (BAND_LOWER + BAND_UPPER + row - col)];
    }
    if (row < nb) return w->border_columns[(size_t)(col - nb) * nb + row];
    if (col < nb) return w->border_rows[(size_t)(row - nb) * nb + col];
    return 0.0;
}

/* The transverse pairs of a block of 6: unknowns (phi_1, phi_2) on d1, d2
 * (y, z at the straight rod, turned by its twist) and (N_y, N_z); rows
 * (force y, z) and (moment y, z, or their replacements). The border is one
 * more pair of each. The axial rest (phi_3, N_x, force x, moment x) does not
 * couple to them by the symmetry and never becomes singular. */
static int transverse_unknown(const static_work *w, int k, int *second)
{
    int block = k / 2, pair = k % 2;
    if (block * UNKNOWNS_PER_NODE >= w->band_unknowns) {
        *second = w->band_unknowns + 1;
        return w->band_unknowns;
    }
    int first = block * UNKNOWNS_PER_NODE + (pair == 0 ? 0 : 4);
    *second = first + 1;
    return first;
}

static int transverse_row(const static_work *w, int k, int *second)
{
    int block = k / 2, pair = k % 2;
    if (block * UNKNOWNS_PER_NODE >= w->band_unknowns) {
        *second = w->band_unknowns + 1;
        return w->band_unknowns;
    }
    /* a pinned root's block 0 has its pair in rows 1, 2; rows 4, 5 are identity */
    int first = block * UNKNOWNS_PER_NODE + (pair == 0 ? 1 : 4);
    *second = first + 1;
    return first;
}

/* The Newton base point at the straight rod along +x from 0, twisted
 * uniformly by the axial tip moment and carrying the axial tip force, under
 * lambda times the model's tip load (the caller checks the model is that
 * rod), and its load into *load. Returns the twist rate u3, 1/m. */
static double place_straight_rod(static_work *w, const rod_model *m, double lambda,
                                 static_load *load)
{
    int n = w->nodes;
    memset(load, 0, sizeof *load);
    v3_scale(load->tip_force, m->tip_force, lambda);
    v3_scale(load->tip_moment, m->tip_moment, lambda);
    /* axial components: on d3 = x for a follower load, global x for a dead one */
    int axis = m->tip_frame == ROD_FRAME_DIRECTOR ? 2 : 0;
    double twist_rate = load->tip_moment[axis] / m->stiffness[2]; /* u3 = M3 / C, 1/m */
    for (int i = 0; i < n; i++) { /* Q_i = exp(u3 s_i [e_x]) Q_init: straight, twisted */
        double turn[3] = {twist_rate * m->ds * i, 0.0, 0.0}, rot[9];
        m3_exp(rot, turn);
        m3_mul(&w->frame[9 * i], rot, straight_frame);
    }
    for (int j = 0; j + 1 < n; j++) v3_set(&w->force[3 * j], load->tip_force[axis], 0.0, 0.0);
    memset(w->reaction, 0, sizeof w->reaction);
    load->curvature = 1.0;
    m3_identity(load->root_rotation);
    m3_identity(load->tip_rotation);
    v3_set(load->tip_position, m->length, 0.0, 0.0);
    return twist_rate;
}

/* w->tangent (size x size, made on first use) = A + i B from the real 2 x 2
 * blocks [[A, -B], [B, A]] of the Jacobian just built; -1 with a message
 * when the blocks do not have that form (the load is not purely axial). */
static int fill_complex_tangent(static_work *w, int size, char *err, size_t errlen)
{
    if (!w->tangent) {
        w->tangent = malloc((size_t)size * (size_t)size * sizeof *w->tangent);
        if (!w->tangent) {
            snprintf(err, errlen, "static: out of memory for the %d x %d tangent", size, size);
            return -1;
        }
    }
    double largest = 0.0, asymmetry = 0.0;
    for (int r = 0; r < size; r++) {
        int ry2, ry = transverse_row(w, r, &ry2);
        for (int c = 0; c < size; c++) {
            int cy2, cy = transverse_unknown(w, c, &cy2);
            double a = jacobian_entry(w, ry, cy), b = jacobian_entry(w, ry2, cy);
            double a2 = jacobian_entry(w, ry2, cy2), minus_b = jacobian_entry(w, ry, cy2);
            largest = fmax(largest, fmax(fabs(a), fabs(b)));
            asymmetry = fmax(asymmetry, fmax(fabs(a - a2), fabs(b + minus_b)));
            w->tangent[(size_t)r * size + c] = a + I * b;
        }
    }
    if (asymmetry > 1e-4 * largest) {
        snprintf(err, errlen,
                 "static: the tangent at the straight rod is not symmetric about the x axis "
                 "(largest deviation %.2e of %.2e): the load is not purely axial", asymmetry,
                 largest);
        return -1;
    }
    return 0;
}

/* The determinant of the size x size matrix a (destroyed) by LU with
 * partial pivoting, det = (-1)^swaps prod pivots: *log_sum the natural log
 * of its modulus, *angle its argument (rad, not reduced). Returns 1 when a
 * pivot is exactly zero (det = 0), else 0. */
static int complex_log_determinant(double complex *a, int size, double *log_sum, double *angle)
{
    *log_sum = 0.0;
    *angle = 0.0;
    for (int k = 0; k < size; k++) {
        int pivot = k;
        for (int r = k + 1; r < size; r++)
            if (cabs(a[(size_t)r * size + k]) > cabs(a[(size_t)pivot * size + k])) pivot = r;
        if (pivot != k) {
            for (int c = 0; c < size; c++) {
                double complex t = a[(size_t)k * size + c];
                a[(size_t)k * size + c] = a[(size_t)pivot * size + c];
                a[(size_t)pivot * size + c] = t;
            }
            *angle += M_PI;
        }
        double complex p = a[(size_t)k * size + k];
        if (cabs(p) == 0.0) return 1;
        *log_sum += log(cabs(p));
        *angle += carg(p);
        for (int r = k + 1; r < size; r++) {
            double complex f = a[(size_t)r * size + k] / p;
            if (f == 0.0) continue;
            for (int c = k + 1; c < size; c++) a[(size_t)r * size + c] -= f * a[(size_t)k * size + c];
        }
    }
    return 0;
}

int static_straight_determinant(static_work *w, const rod_model *m, double lambda,
                                double *log_abs, double *phase, double *residual, char *err,
                                size_t errlen)
{
    int n = w->nodes;
    static_load load;
    double twist_rate = place_straight_rod(w, m, lambda, &load);
    static_build_jacobian(w, m, &load);
    *residual = max_abs(w->residual, w->unknowns);
    int size = 2 * n + (w->border ? 1 : 0);
    if (fill_complex_tangent(w, size, err, errlen) != 0) return -1;
    double log_sum, angle;
    if (complex_log_determinant(w->tangent, size, &log_sum, &angle)) {
        *log_abs = -INFINITY;
        *phase = 0.0;
        return 0;
    }
    /* The phi unknowns are on the twisted directors: w_global = e^{i theta_i} w_director
     * with theta_i = u3 s_i, so det K_director = det K_global e^{i sum theta_i}; report
     * the global one, whose phase does not wind with the twist. */
    for (int i = 0; i < n; i++) angle -= twist_rate * m->ds * i;
    *log_abs = log_sum;
    *phase = remainder(angle, 2.0 * M_PI);
    return 0;
}
