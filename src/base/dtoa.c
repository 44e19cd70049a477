/* dtoa.c: see dtoa.h.
 *
 * Why it is shortest: any decimal of at most 15 significant digits survives
 * decimal -> double -> decimal at 15 digits (DBL_DIG), so if a decimal of
 * at most 15 digits reads back to v, it is v rounded to 15 digits with its
 * trailing zeros dropped. Hence: v rounded to 15 digits, if it reads back,
 * else to 16, else to 17 (17 always reads back). A tie is rounded up, away
 * from zero: at a power of two the gap below is the narrower, so of two
 * equally near candidates the one above reads back whenever either does
 * (printf rounds ties to even: 2^-24 is 5.960464477539063e-08 here, 17
 * digits by printf alone). Subnormals hold fewer digits: tried from 1. */
#include "base/dtoa.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

__extension__ typedef unsigned __int128 u128;

/* 10^k for k = 0..17 */
static const uint64_t power10[18] = {
    1ull,          10ull,          100ull,          1000ull,          10000ull,
    100000ull,     1000000ull,     10000000ull,     100000000ull,     1000000000ull,
    10000000000ull, 100000000000ull, 1000000000000ull, 10000000000000ull,
    100000000000000ull, 1000000000000000ull, 10000000000000000ull, 100000000000000000ull};

#define DTOA_MAX_K 27 /* 5^27 < 2^63: f 5^k fits 117 bits */

/* 5^k for k = 0..DTOA_MAX_K */
static const uint64_t power5[DTOA_MAX_K + 1] = {
    1ull, 5ull, 25ull, 125ull, 625ull, 3125ull, 15625ull, 78125ull, 390625ull, 1953125ull,
    9765625ull, 48828125ull, 244140625ull, 1220703125ull, 6103515625ull, 30517578125ull,
    152587890625ull, 762939453125ull, 3814697265625ull, 19073486328125ull, 95367431640625ull,
    476837158203125ull, 2384185791015625ull, 11920928955078125ull, 59604644775390625ull,
    298023223876953125ull, 1490116119384765625ull, 7450580596923828125ull};

/* v = f 2^e (f of 53 bits) rounded to `digits` significant digits: m, an
 * integer of that many digits, with v ~ m 10^(e10 - digits + 1). Returns
 * 1 when m reads back to v exactly (strtod's rounding, ties to even), 0 when
 * it does not, -1 when the scaling leaves the exact range. narrow_below: v
 * is a power of two, so the gap to the double below is half the one above. */
static int round_exact(uint64_t f, int e, int narrow_below, int digits, int *e10, uint64_t *m)
{
    for (int attempt = 0; attempt < 3; attempt++) {
        int k = digits - 1 - *e10; /* m = v 10^k */
        if (k < 1 || k > DTOA_MAX_K) return -1;
        uint64_t five = power5[k];
        u128 x = (u128)f * five; /* v 10^k = x 2^(e + k) */
        int shift = -(e + k);
        if (shift < 1 || shift > 120) return -1;
        u128 r = (x + ((u128)1 << (shift - 1))) >> shift;
        if (r >= power10[digits]) { /* the estimate of e10 was one low */
            if (attempt == 0) {
                ++*e10;
                continue;
            }
            if (r != power10[digits]) return -1;
            r /= 10; /* 9.99..95 rounded up to 10.00..0 */
            ++*e10;
            k--;
            x = (u128)f * power5[k];
            shift = -(e + k);
            five = power5[k];
        }
        if (r < power10[digits - 1]) return -1; /* not reached: the estimate is never high */
        *m = (uint64_t)r;
        /* in units of 2^-(shift + 2) of 10^k: v is 4x, the neighbours' midpoints
         * 2 5^k above and 2 5^k (or 5^k, narrow_below) below */
        if ((uint64_t)(r >> (125 - shift)) != 0) return -1; /* r << (shift + 2) would overflow */
        u128 candidate = r << (shift + 2), value = x << 2;
        u128 above = (u128)five << 1, below = narrow_below ? (u128)five : (u128)five << 1;
        int even = (f & 1) == 0;
        if (candidate >= value) {
            u128 d = candidate - value;
            return d < above || (d == above && even);
        }
        u128 d = value - candidate;
        return d < below || (d == below && even);
    }
    return -1;
}

/* The C library's route (outside the exact range): %.Ne is correctly
 * rounded; m and e10 read off its text. */
static int round_printf(double v, int digits, int *e10, uint64_t *m)
{
    char text[40];
    snprintf(text, sizeof text, "%.*e", digits - 1, v);
    if (strtod(text, NULL) != v) return 0;
    const char *p = text[0] == '-' ? text + 1 : text;
    uint64_t value = 0;
    for (; *p && *p != 'e'; p++)
        if (*p >= '0' && *p <= '9') value = value * 10 + (uint64_t)(*p - '0');
    *m = value;
    *e10 = atoi(p + 1);
    return 1;
}

/* Writes the digits of m (`digits` of them, trailing zeros dropped) at
 * decimal exponent e10 in %g's form with precision 17. */
static int layout(char *out, int negative, uint64_t m, int digits, int e10)
{
    char digit[17];
    for (int i = digits - 1; i >= 0; i--, m /= 10) digit[i] = (char)('0' + m % 10);
    int used = digits;
    while (used > 1 && digit[used - 1] == '0') used--;
    char *p = out;
    if (negative) *p++ = '-';
    if (e10 >= -4 && e10 < 17) {
        if (e10 < 0) { /* 0.000ddd */
            *p++ = '0';
            *p++ = '.';
            for (int i = 0; i < -e10 - 1; i++) *p++ = '0';
            memcpy(p, digit, (size_t)used);
            p += used;
        } else { /* ddd.ddd */
            for (int i = 0; i <= e10; i++) *p++ = i < used ? digit[i] : '0';
            if (used > e10 + 1) {
                *p++ = '.';
                memcpy(p, digit + e10 + 1, (size_t)(used - e10 - 1));
                p += used - e10 - 1;
            }
        }
    } else { /* d.ddde+XX, at least two exponent digits as printf */
        *p++ = digit[0];
        if (used > 1) {
            *p++ = '.';
            memcpy(p, digit + 1, (size_t)(used - 1));
            p += used - 1;
        }
        *p++ = 'e';
        *p++ = e10 < 0 ? '-' : '+';
        int x = e10 < 0 ? -e10 : e10;
        if (x >= 100) *p++ = (char)('0' + x / 100);
        *p++ = (char)('0' + x / 10 % 10);
        *p++ = (char)('0' + x % 10);
    }
    *p = '\0';
    return (int)(p - out);
}

int dtoa_shortest(char *out, double v)
{
    uint64_t bits;
    memcpy(&bits, &v, sizeof bits);
    const int negative = (int)(bits >> 63);
    const int biased = (int)(bits >> 52 & 0x7ff);
    const uint64_t fraction = bits & ((1ull << 52) - 1);
    if (biased == 0x7ff) return snprintf(out, DTOA_MAX, "%g", v); /* NaN, inf */
    if (biased == 0 && fraction == 0) return snprintf(out, DTOA_MAX, negative ? "-0" : "0");
    uint64_t m = 0;
    int e10 = 0;
    if (biased > 0) {
        const uint64_t f = fraction | 1ull << 52;
        const int e = biased - 1075; /* |v| = f 2^e */
        const int e2 = biased - 1023; /* 2^e2 <= |v| < 2^(e2 + 1) */
        /* floor(e2 log10 2), one low at most: 78913 / 2^18 = log10 2 - 1e-7 */
        const int estimate = e2 >= 0 ? (e2 * 78913) >> 18 : -((-e2 * 78913 + (1 << 18) - 1) >> 18);
        const int narrow_below = fraction == 0 && biased > 1;
        for (int digits = 15; digits <= 17; digits++) {
            e10 = estimate;
            int found = round_exact(f, e, narrow_below, digits, &e10, &m);
            if (found < 0) break;
            if (found) return layout(out, negative, m, digits, e10);
        }
    }
    /* a subnormal holds fewer digits than DBL_DIG: from 1 (5e-324) */
    for (int digits = biased > 0 ? 15 : 1; digits <= 17; digits++)
        if (round_printf(v, digits, &e10, &m)) return layout(out, negative, m, digits, e10);
    return snprintf(out, DTOA_MAX, "%.17g", v); /* not reached: 17 digits read back */
}
