/* numfmt.h: a number as text, fast, the way printf's %.Ng writes it, for
 * output whose cost counts (rodsim live answers a line of up to 3 NS + 7
 * numbers at 1 kHz: glibc's %.12g takes about 1 us a number, this some
 * 50 ns).
 *
 * The value is scaled to an N-digit integer by exact powers of ten and
 * rounded there, so the last digit may differ from printf's by one where the
 * value lies within a rounding error of half a unit of that digit (about
 * one value in 10^4 at N = 12; never more than one unit of the N-th digit).
 * Values beyond 1e-30 .. 1e30 in magnitude, NaN and infinities are handed to
 * snprintf. */
#ifndef RODSIM_NUMFMT_H
#define RODSIM_NUMFMT_H

#include <stddef.h>

/* Room for any result, with its terminating '\0'. */
#define NUMFMT_MAX 32

/* Writes v with `digits` significant digits (1..15) into out (at least
 * NUMFMT_MAX bytes), '\0'-terminated, in %g's form: fixed when the decimal
 * exponent is in -4 .. digits - 1, else d.ddde+XX; trailing zeros dropped.
 * Returns the number of characters written (without the '\0'). */
int numfmt_g(char *out, double v, int digits);

/* v for a sentence, as printf's "%.*e" writes it with `digits` after the
 * point, or, when v is NaN or infinite, words in its place ("not finite
 * (NaN)", "not finite (+infinity)"): a message that prints a measure
 * gone wrong reads "residual not finite (NaN)", not "residual nan" or
 * "1.8e+308". Into out (n bytes); returns out. */
#define NUMFMT_WORDS_MAX 32
const char *numfmt_e_or_words(char *out, size_t n, double v, int digits);

#endif
