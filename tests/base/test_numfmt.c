/* test_numfmt.c: numfmt_g against the C library's printf %.Ng, the
 * reference: hand-checked forms (fixed and exponent ranges, carries,
 * trailing zeros, signs), and over a million pseudo-random values from
 * 1e-29 to 1e29 the same text as snprintf in all but a few (the last digit
 * one off where the value sits within a rounding of half a unit), each of
 * those within one unit of the last digit and reading back within half a
 * unit plus the scaling's rounding (2^-52 of a 12-digit integer: 2e-4 of a
 * unit). Values with 13 significant decimals ending in 5 (3409654335.095)
 * are such ties: printf rounds the binary value just below, numfmt_g the
 * scaled one, rounded onto the tie. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/numfmt.h"
#include "test.h"

static void test_forms(void)
{
    const struct { double v; int digits; const char *text; } cases[] = {
        {0.0, 12, "0"},           {1.0, 12, "1"},
        {-1.0, 12, "-1"},         {0.5, 12, "0.5"},
        {1e-5, 12, "1e-05"},      {0.0001, 12, "0.0001"},
        {4.5e-10, 12, "4.5e-10"}, {123456789012.0, 12, "123456789012"},
        {1234567890123.0, 12, "1.23456789012e+12"},
        {9.9999999999995, 12, "10"}, {-0.00123456789012345, 12, "-0.00123456789012"},
        {1e22, 12, "1e+22"},      {2.5e-300, 12, "2.5e-300"},
        {100.0, 12, "100"},       {0.1, 12, "0.1"},
        {1.0 / 3.0, 6, "0.333333"}, {2.0 / 3.0, 3, "0.667"},
        {123456.0, 3, "1.23e+05"}, {-9.87654321e-7, 12, "-9.87654321e-07"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char text[NUMFMT_MAX];
        int n = numfmt_g(text, cases[i].v, cases[i].digits);
        check(strcmp(text, cases[i].text) == 0 && n == (int)strlen(text),
              "numfmt_g(%.17g, %d) = \"%s\" (expected \"%s\")", cases[i].v, cases[i].digits, text,
              cases[i].text);
    }
    char text[NUMFMT_MAX], ref[64];
    numfmt_g(text, NAN, 12);
    snprintf(ref, sizeof ref, "%.12g", NAN);
    check(strcmp(text, ref) == 0, "NaN as printf: \"%s\"", text);
    numfmt_g(text, -INFINITY, 12);
    check(strcmp(text, "-inf") == 0, "-inf as printf: \"%s\"", text);
}

/* xorshift64: a fixed sequence, no wall time or seed */
static uint64_t next_random(uint64_t *state)
{
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    return *state;
}

static void test_random(int digits)
{
    uint64_t state = 0x9e3779b97f4a7c15ull;
    const long count = 1000000;
    long same = 0, near = 0, total = 0;
    double worst = 0.0;
    for (long i = 0; i < count; i++) {
        double unit = (double)(next_random(&state) >> 11) / 9007199254740992.0; /* [0, 1) */
        double exponent = -29.0 + 58.0 * (double)(next_random(&state) >> 11) / 9007199254740992.0;
        double v = (0.1 + 0.9 * unit) * pow(10.0, exponent) * (i % 2 ? -1.0 : 1.0);
        if (i % 7 == 0) v = round(v * 1e3) / 1e3; /* short decimals too, as a sensor writes */
        if (v == 0.0) continue;
        total++;
        char text[NUMFMT_MAX], ref[64];
        numfmt_g(text, v, digits);
        snprintf(ref, sizeof ref, "%.*g", digits, v);
        if (strcmp(text, ref) == 0) {
            same++;
            continue;
        }
        /* one unit of the last digit: 10^(e - digits + 1) of the value */
        double back = strtod(text, NULL), expected = strtod(ref, NULL);
        double last_unit = pow(10.0, floor(log10(fabs(v))) - digits + 1);
        double off = fabs(back - expected) / last_unit, error = fabs(back - v) / last_unit;
        if (off <= 1.0 + 1e-3 && error <= 0.5 + 1e-3) near++; /* + roundings, 2e-4 units */
        worst = fmax(worst, off);
    }
    check(same + near == total && same >= total - total / 1000,
          "%%.%dg: %ld of %ld values as printf writes them, the other %ld one unit of the last "
          "digit off at a half-unit tie (largest difference %.3g units)",
          digits, same, total, near, worst);
}

/* A measure for a sentence: printf's %.3e when finite, words otherwise */
static void test_e_or_words(void)
{
    char out[NUMFMT_WORDS_MAX], ref[NUMFMT_WORDS_MAX];
    static const double finite[] = {0.0, 1.25e-8, -3.5, 1.7976931348623157e308};
    int same = 0;
    for (int i = 0; i < 4; i++) {
        snprintf(ref, sizeof ref, "%.3e", finite[i]);
        same += strcmp(numfmt_e_or_words(out, sizeof out, finite[i], 3), ref) == 0;
    }
    check(same == 4, "finite values as %%.3e writes them (%d of 4; DBL_MAX: %s)", same, out);
    check(strcmp(numfmt_e_or_words(out, sizeof out, NAN, 3), "not finite (NaN)") == 0,
          "NaN in words: '%s'", out);
    check(strcmp(numfmt_e_or_words(out, sizeof out, INFINITY, 2), "not finite (+infinity)") == 0,
          "+inf in words: '%s'", out);
    check(strcmp(numfmt_e_or_words(out, sizeof out, -INFINITY, 2), "not finite (-infinity)") == 0,
          "-inf in words: '%s'", out);
}

int main(void)
{
    test_e_or_words();
    test_forms();
    test_random(12);
    test_random(6);
    return test_finish();
}
