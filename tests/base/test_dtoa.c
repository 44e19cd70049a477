/* test_dtoa.c: dtoa_shortest against the C library's strtod and printf,
 * the reference: hand-checked texts (0, -0, 0.1, integers, powers of two,
 * the ends of the range, subnormals, the carry 9.99.. -> 10), then for
 * millions of doubles drawn as random bit patterns (every exponent, every
 * mantissa) and as random values of the sizes a simulation writes (1e-9 to
 * 1e3): the text reads back to the identical double. For a smaller sample,
 * the digits are compared with the shortest decimal found by printf alone
 * (%.Ne for N = 1, 2, .. until strtod gives v back): the same count of
 * significant digits and the same value. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/dtoa.h"
#include "test.h"

static uint64_t state = 0x9E3779B97F4A7C15ull;

static uint64_t next_random(void) /* xorshift64* */
{
    state ^= state >> 12;
    state ^= state << 25;
    state ^= state >> 27;
    return state * 2685821657736338717ull;
}

static double from_bits(uint64_t bits)
{
    double v;
    memcpy(&v, &bits, sizeof v);
    return v;
}

static int same_double(double a, double b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

/* Significant digits of a decimal text (leading zeros and the exponent not counted). */
static int significant_digits(const char *text)
{
    int count = 0, started = 0, trailing_zeros = 0;
    for (const char *p = text; *p && *p != 'e'; p++) {
        if (*p < '0' || *p > '9') continue;
        if (*p != '0') started = 1;
        if (!started) continue;
        count++;
        trailing_zeros = *p == '0' ? trailing_zeros + 1 : 0;
    }
    return count - trailing_zeros;
}

/* The shortest %.Ne (N + 1 significant digits) that reads back to v. */
static int printf_shortest(double v, char *text, size_t len)
{
    for (int digits = 1; digits <= 17; digits++) {
        snprintf(text, len, "%.*e", digits - 1, v);
        if (same_double(strtod(text, NULL), v)) return digits;
    }
    return -1;
}

static void test_texts(void)
{
    const struct { double v; const char *text; } cases[] = {
        {0.0, "0"}, {-0.0, "-0"}, {0.1, "0.1"}, {-0.1, "-0.1"}, {1.0, "1"},
        {3.0, "3"}, {100.0, "100"}, {123456789.0, "123456789"}, {0.5, "0.5"},
        {0.3, "0.3"}, {1.0 / 3.0, "0.3333333333333333"}, {2.0 / 3.0, "0.6666666666666666"},
        {0.1 + 0.2, "0.30000000000000004"}, {1e-5, "1e-05"}, {0.0001, "0.0001"},
        {1.5e-7, "1.5e-07"}, {1e-300, "1e-300"}, {1e300, "1e+300"}, {-2.5e-300, "-2.5e-300"},
        {1e16, "10000000000000000"}, {1e17, "1e+17"}, {9007199254740993.0, "9007199254740992"},
        {5e-324, "5e-324"}, {2.2250738585072014e-308, "2.2250738585072014e-308"},
        {2.225073858507201e-308, "2.225073858507201e-308"}, {1.7976931348623157e308, "1.7976931348623157e+308"},
        {0.015, "0.015"}, {9.999999999999998, "9.999999999999998"}, {0.00015, "0.00015"},
        {4.35e-6, "4.35e-06"}, {0.7996077937, "0.7996077937"}, {1024.0, "1024"},
        {0.0009765625, "0.0009765625"}, {-123.456, "-123.456"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char text[DTOA_MAX];
        int n = dtoa_shortest(text, cases[i].v);
        check(strcmp(text, cases[i].text) == 0 && n == (int)strlen(text),
              "dtoa_shortest(%.17g) = \"%s\" (expected \"%s\")", cases[i].v, text, cases[i].text);
    }
    char text[DTOA_MAX];
    dtoa_shortest(text, INFINITY);
    check(strcmp(text, "inf") == 0, "dtoa_shortest(inf) = \"%s\" (expected \"inf\")", text);
    dtoa_shortest(text, -INFINITY);
    check(strcmp(text, "-inf") == 0, "dtoa_shortest(-inf) = \"%s\" (expected \"-inf\")", text);
    dtoa_shortest(text, NAN);
    check(strstr(text, "nan") != NULL, "dtoa_shortest(nan) = \"%s\" (expected a nan)", text);
}

/* n doubles from draw(): each text reads back to the identical double. */
static void test_round_trip(const char *what, int n, double (*draw)(void))
{
    int bad = 0, first_bad = -1;
    double bad_value = 0.0;
    char text[DTOA_MAX], bad_text[DTOA_MAX] = "";
    for (int i = 0; i < n; i++) {
        double v = draw();
        if (!isfinite(v)) continue;
        dtoa_shortest(text, v);
        if (!same_double(strtod(text, NULL), v)) {
            if (bad++ == 0) {
                first_bad = i;
                bad_value = v;
                memcpy(bad_text, text, sizeof text);
            }
        }
    }
    check(bad == 0, "%s: %d doubles, %d read back different (first: #%d %.17g as \"%s\")", what,
          n, bad, first_bad, bad_value, bad_text);
}

/* n doubles from draw(): at most as many significant digits as printf's
 * shortest and, with as many, the same value. Fewer happen at an exact
 * decimal tie beside a power of two: printf rounds the tie to even, onto the
 * narrow side below, where it does not read back; dtoa_shortest rounds it up
 * (both texts read back: test_round_trip). */
static void test_shortest(const char *what, int n, double (*draw)(void))
{
    int longer = 0, other = 0, shorter = 0;
    char text[DTOA_MAX], reference[40], example[120] = "none";
    for (int i = 0; i < n; i++) {
        double v = draw();
        if (!isfinite(v) || v == 0.0) continue;
        dtoa_shortest(text, v);
        int digits = printf_shortest(v, reference, sizeof reference);
        int got = significant_digits(text);
        if (got < digits) {
            shorter++;
            continue;
        }
        if (got > digits) longer++;
        else if (strtod(text, NULL) != strtod(reference, NULL)) other++;
        else continue;
        if (longer + other == 1)
            snprintf(example, sizeof example, "%.17g: \"%s\" against \"%s\"", v, text, reference);
    }
    check(longer == 0 && other == 0,
          "%s: %d doubles, %d longer than printf's shortest, %d other digits, %d shorter "
          "(first fault: %s)", what, n, longer, other, shorter, example);
}

static double draw_bits(void)
{
    return from_bits(next_random());
}

/* Mantissa and sign random, magnitude 1e-9 .. 1e3 (log-uniform). */
static double draw_simulation(void)
{
    double magnitude = pow(10.0, -9.0 + 12.0 * (double)(next_random() >> 11) * 0x1p-53);
    double v = magnitude * (1.0 + (double)(next_random() >> 11) * 0x1p-53);
    return next_random() & 1 ? -v : v;
}

/* Short decimals: n / 10^k, the values a scene file writes (0.015, 2.5e-4). */
static double draw_short(void)
{
    uint64_t r = next_random();
    double n = (double)(r % 100000);
    int k = (int)(r >> 40) % 12;
    return n / pow(10.0, k);
}

/* Random subnormals (biased exponent 0). */
static double draw_subnormal(void)
{
    return from_bits(next_random() & ((1ull << 52) - 1));
}

/* Neighbours of powers of two, where the gap below is half the gap above. */
static double draw_power_of_two(void)
{
    uint64_t r = next_random();
    double v = ldexp(1.0, (int)(r % 2000) - 1000);
    int step = (int)(r >> 32) % 3 - 1;
    return step < 0 ? nextafter(v, 0.0) : step > 0 ? nextafter(v, INFINITY) : v;
}

int main(void)
{
    test_texts();
    test_round_trip("random bit patterns", 2000000, draw_bits);
    test_round_trip("simulation-sized values 1e-9..1e3", 3000000, draw_simulation);
    test_round_trip("short decimals", 500000, draw_short);
    test_round_trip("subnormals", 100000, draw_subnormal);
    test_round_trip("powers of two and neighbours", 100000, draw_power_of_two);
    test_shortest("random bit patterns", 50000, draw_bits);
    test_shortest("simulation-sized values", 100000, draw_simulation);
    test_shortest("short decimals", 50000, draw_short);
    test_shortest("powers of two and neighbours", 20000, draw_power_of_two);
    return test_finish();
}
