/* spectrum.c: Hann-windowed DFT magnitude at an arbitrary frequency and the
 * peak search (see spectrum.h). */
#include "base/spectrum.h"

#include <math.h>

double spectrum_magnitude(const double *y, int n, double dt, double f)
{
    double re = 0.0, im = 0.0;
    /* the phase advances by a fixed rotation per sample: a complex recurrence
     * instead of n sin/cos pairs; re-seeded every 1024 samples against drift */
    double step_cos = cos(2.0 * M_PI * f * dt), step_sin = sin(2.0 * M_PI * f * dt);
    double c = 1.0, s = 0.0;
    for (int k = 0; k < n; k++) {
        if ((k & 1023) == 0) {
            c = cos(2.0 * M_PI * f * k * dt);
            s = sin(2.0 * M_PI * f * k * dt);
        }
        double w = n > 1 ? 0.5 - 0.5 * cos(2.0 * M_PI * k / (n - 1)) : 1.0; /* Hann */
        re += w * y[k] * c;
        im -= w * y[k] * s;
        double c_next = c * step_cos - s * step_sin;
        s = s * step_cos + c * step_sin;
        c = c_next;
    }
    return hypot(re, im);
}

double spectrum_peak(const double *y, int n, double dt, double f_lo, double f_hi)
{
    const int scan = 200;
    double width = (f_hi - f_lo) / scan;
    double best = f_lo, best_magnitude = -1.0;
    for (int k = 0; k <= scan; k++) {
        double f = f_lo + width * k, magnitude = spectrum_magnitude(y, n, dt, f);
        if (magnitude > best_magnitude) {
            best_magnitude = magnitude;
            best = f;
        }
    }
    double a = fmax(f_lo, best - width), b = fmin(f_hi, best + width);
    const double golden = 0.5 * (sqrt(5.0) - 1.0);
    double c = b - golden * (b - a), d = a + golden * (b - a);
    double mag_c = spectrum_magnitude(y, n, dt, c), mag_d = spectrum_magnitude(y, n, dt, d);
    for (int it = 0; it < 80 && b - a > 1e-12 * (f_hi - f_lo); it++) {
        if (mag_c > mag_d) {
            b = d;
            d = c;
            mag_d = mag_c;
            c = b - golden * (b - a);
            mag_c = spectrum_magnitude(y, n, dt, c);
        } else {
            a = c;
            c = d;
            mag_c = mag_d;
            d = a + golden * (b - a);
            mag_d = spectrum_magnitude(y, n, dt, d);
        }
    }
    return 0.5 * (a + b);
}
