/* dtoa.h: a double as the shortest decimal text that reads back to the
 * same double, fast: for output whose every bit counts and whose cost counts
 * (rodsim run --csv writes 13 numbers per node per frame).
 *
 * The digits are the fewest (1..17) for which some decimal reads back
 * (strtod, round to nearest even) to exactly v, and of those the nearest to
 * v. Computed exactly in 128-bit integers for 1e-13 <= |v| < 1e14 (where
 * 10^k of the scaling is 5^k 2^k with 5^k below 2^64); outside that range,
 * and for subnormals, from the C library's correctly rounded %.Ne, tried at
 * N = 15, 16, 17 (the same digits, some ten times slower). */
#ifndef RODSIM_DTOA_H
#define RODSIM_DTOA_H

/* Room for any result, with its terminating '\0'. */
#define DTOA_MAX 32

/* Writes v into out (at least DTOA_MAX bytes), '\0'-terminated, in %g's
 * form with 17 as the precision: fixed when the decimal exponent is in
 * -4 .. 16 ("0.001", "-12.5", "3"), else d.ddde+XX ("1.5e-07"); 0 is "0",
 * -0 is "-0"; NaN and infinities as printf's %g writes them. Returns the
 * number of characters written (without the '\0'). */
int dtoa_shortest(char *out, double v);

#endif
