/* vec3.c: 3x3 rotation utilities. */
#include "base/vec3.h"

#include <string.h>

void m3_identity(double r[9])
{
    memset(r, 0, 9 * sizeof *r);
    r[0] = r[4] = r[8] = 1.0;
}

void m3_orthonormalize(double q[9])
{
    /* Newton-Schulz steps towards the polar factor, q <- q (3 I - q^T q) / 2,
     * which converge quadratically near a rotation (one suffices after a step). */
    for (int it = 0; it < 2; it++) {
        double qtq[9], corr[9], out[9];
        m3_mul_tn(qtq, q, q);
        for (int i = 0; i < 9; i++) corr[i] = -0.5 * qtq[i];
        corr[0] += 1.5; corr[4] += 1.5; corr[8] += 1.5;
        m3_mul(out, q, corr);
        memcpy(q, out, sizeof out);
    }
}
