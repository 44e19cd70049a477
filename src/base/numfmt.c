/* numfmt.c: see numfmt.h. */
#include "base/numfmt.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* 10^k, exact in a double for k <= 22. */
static const double exact_power[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                       1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                       1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

/* a x 10^k for |k| <= 44: one or two exact factors, a rounding each. */
static double scale(double a, int k)
{
    if (k >= 0) return k <= 22 ? a * exact_power[k] : a * exact_power[22] * exact_power[k - 22];
    k = -k;
    return k <= 22 ? a / exact_power[k] : a / exact_power[22] / exact_power[k - 22];
}

int numfmt_g(char *out, double v, int digits)
{
    if (digits < 1) digits = 1;
    if (digits > 15) digits = 15;
    const double a = fabs(v);
    if (!(a >= 1e-30 && a <= 1e30)) { /* 0, tiny, huge, NaN, inf */
        if (v == 0.0) return snprintf(out, NUMFMT_MAX, signbit(v) ? "-0" : "0");
        return snprintf(out, NUMFMT_MAX, "%.*g", digits, v);
    }
    /* the integer m of `digits` digits with a = m 10^(e - digits + 1);
     * log10 may be one off near a power of ten: corrected by m's size */
    const long long low = (long long)exact_power[digits - 1], high = low * 10;
    int e = (int)floor(log10(a));
    long long m = llround(scale(a, digits - 1 - e));
    if (m >= high) m = llround(scale(a, digits - 1 - ++e));
    else if (m < low) m = llround(scale(a, digits - 1 - --e));
    if (m >= high) { /* rounding carried into a new digit: 9.99.. -> 10.0 */
        m /= 10;
        e++;
    }
    char digit[16];
    for (int i = digits - 1; i >= 0; i--, m /= 10) digit[i] = (char)('0' + m % 10);
    int used = digits; /* significant digits kept: trailing zeros dropped */
    while (used > 1 && digit[used - 1] == '0') used--;
    char *p = out;
    if (v < 0) *p++ = '-';
    if (e >= -4 && e < digits) {
        if (e < 0) { /* 0.000ddd */
            *p++ = '0';
            *p++ = '.';
            for (int i = 0; i < -e - 1; i++) *p++ = '0';
            memcpy(p, digit, (size_t)used);
            p += used;
        } else { /* ddd.ddd */
            for (int i = 0; i <= e; i++) *p++ = i < used ? digit[i] : '0';
            if (used > e + 1) {
                *p++ = '.';
                memcpy(p, digit + e + 1, (size_t)(used - e - 1));
                p += used - e - 1;
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
        *p++ = e < 0 ? '-' : '+';
        int x = e < 0 ? -e : e;
        if (x >= 10) *p++ = (char)('0' + x / 10);
        else *p++ = '0';
        *p++ = (char)('0' + x % 10);
    }
    *p = '\0';
    return (int)(p - out);
}

const char *numfmt_e_or_words(char *out, size_t n, double v, int digits)
{
    if (isnan(v)) snprintf(out, n, "not finite (NaN)");
    else if (isinf(v)) snprintf(out, n, "not finite (%sinfinity)", v > 0 ? "+" : "-");
    else snprintf(out, n, "%.*e", digits, v);
    return out;
}
