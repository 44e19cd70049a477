/* spectrum.h: the frequency of a sampled signal's spectral peak, for impulse
 * responses (modal frequencies). A direct DFT evaluated at any frequency (not
 * only the FFT's bins), with a Hann window against leakage, maximised by a
 * scan then golden-section search: the peak is found to far better than the
 * bin width 1/(n dt) when the signal holds a few well-separated sinusoids.
 * Units: dt in s, frequencies in Hz. */
#ifndef RODSIM_SPECTRUM_H
#define RODSIM_SPECTRUM_H

/* |sum_k w_k y_k exp(-2 pi i f k dt)| with a Hann window w over the n samples
 * y (sampled every dt s); n >= 2. */
double spectrum_magnitude(const double *y, int n, double dt, double f);

/* Frequency (Hz) of the largest spectral peak in [f_lo, f_hi]: a scan of 200
 * intervals, then golden section on the best one to about 1e-10 of the band.
 * The band should hold one peak; f_lo < f_hi. */
double spectrum_peak(const double *y, int n, double dt, double f_lo, double f_hi);

#endif
