/* test_spectrum.c: the spectral peak finder against synthetic signals whose
 * frequencies are known exactly. */
#include <math.h>
#include <stdio.h>

#include "base/spectrum.h"
#include "test.h"

/* Two sines, 1.3 Hz (amplitude 1) and 3.7 Hz (amplitude 0.4), sampled at
 * 100 Hz for 60 s: each peak found to 1e-6 relative, far below the bin 1/60 Hz. */
static void test_two_sines(void)
{
    enum { n = 6000 };
    static double y[n];
    const double dt = 0.01, f1 = 1.3, f2 = 3.7;
    for (int k = 0; k < n; k++)
        y[k] = sin(2.0 * M_PI * f1 * k * dt + 0.3) + 0.4 * sin(2.0 * M_PI * f2 * k * dt + 1.1);
    check_rel("two sines: stronger peak in [0.5, 2.5] Hz vs 1.3 Hz", spectrum_peak(y, n, dt, 0.5, 2.5),
              f1, 1e-6);
    check_rel("two sines: weaker peak in [2.5, 5] Hz vs 3.7 Hz", spectrum_peak(y, n, dt, 2.5, 5.0),
              f2, 1e-6);
    check_rel("two sines: largest peak over [0.1, 10] Hz is the stronger one, 1.3 Hz",
              spectrum_peak(y, n, dt, 0.1, 10.0), f1, 1e-6);
}

/* The magnitude of a windowed sine at its own frequency: a Hann window sums
 * to (n-1)/2, so |sum w A e^{i phi}| / 2 = A (n-1)/4 (plus the tiny leak
 * of the negative-frequency image). Far from it the magnitude is small. */
static void test_magnitude(void)
{
    enum { n = 4001 };
    static double y[n];
    const double dt = 0.005, f = 2.0, amplitude = 0.7;
    for (int k = 0; k < n; k++) y[k] = amplitude * cos(2.0 * M_PI * f * k * dt);
    check_rel("Hann magnitude of a cosine at its frequency vs A (n-1)/4",
              spectrum_magnitude(y, n, dt, f), amplitude * (n - 1) / 4.0, 1e-6);
    double far = spectrum_magnitude(y, n, dt, 5.0) / spectrum_magnitude(y, n, dt, f);
    check(far < 1e-6, "Hann leakage 3 Hz (60 bins) away: %.2e of the peak (< 1e-6)", far);
}

/* A lightly damped oscillation, as an impulse response with damping:
 * e^{-a t} sin(2 pi f t) with a = 0.01 1/s, f = 0.5 Hz (the damping widens
 * the peak to ~a/pi Hz but barely moves it). */
static void test_damped(void)
{
    enum { n = 20000 };
    static double y[n];
    const double dt = 0.01, f = 0.5, decay = 0.01;
    for (int k = 0; k < n; k++) y[k] = exp(-decay * k * dt) * sin(2.0 * M_PI * f * k * dt);
    check_rel("lightly damped sine: peak vs its frequency 0.5 Hz", spectrum_peak(y, n, dt, 0.2, 1.0),
              f, 1e-4);
}

int main(void)
{
    test_two_sines();
    test_magnitude();
    test_damped();
    return test_finish();
}
