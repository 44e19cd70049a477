/* band.c: banded LU with partial pivoting and its solves (band.h). */
#include "base/band.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/vec3_lanes.h"

/* Loops over a column of L shorter than this run this length
 * (band_factor_kl) */
#define SHORT_COLUMN 8
/* Right-hand sides band_solve_rows takes at a time: up to four vectors a
 * row (each pass over the factors serves them all) */
#define ROWS_WIDTH 4
#define ROWS_CHUNK (ROWS_WIDTH * LANES)

int band_lu_create(band_lu *lu, int n, int kl, int rows)
{
    memset(lu, 0, sizeof *lu);
    lu->n = n;
    lu->kl = kl;
    lu->ldab = 3 * kl + 1; /* 2 kl + ku + 1: U gains kl diagonals by pivoting */
    const size_t u = (size_t)n;
    lu->ab = calloc((size_t)lu->ldab * u, sizeof(double));
    lu->pivot = calloc(u, sizeof(int));
    lu->inv_diag = calloc(u, sizeof(double));
    lu->lower = calloc(u, sizeof(int));
    lu->upper = calloc(u, sizeof(int));
    /* a multiple of 32 bytes (aligned_alloc's size must be one of the
     * alignment) */
    if (rows) lu->rows = aligned_alloc(32, u * ROWS_CHUNK * sizeof(double));
    return lu->ab && lu->pivot && lu->inv_diag && lu->lower && lu->upper && (!rows || lu->rows)
               ? 0 : -1;
}

void band_lu_destroy(band_lu *lu)
{
    free(lu->ab);
    free(lu->pivot);
    free(lu->inv_diag);
    free(lu->lower);
    free(lu->upper);
    free(lu->rows);
    memset(lu, 0, sizeof *lu);
}

/* Solves A x = b in place with the factors of band_factor_kl (LAPACK band
 * storage, kl = ku) for count right-hand sides at once (column-major,
 * unknowns apart) whose rows above `first` are 0: the same arithmetic as
 * dgbtrs. Inlined with kl a constant, so that the inner
 * loops have fixed lengths where a column fills the band (unrolled,
 * vectorised); each column's loop runs over its factor's profile only
 * (lower, upper: band_factor_kl), the zeros outside left out. The
 * forward pass starts kl rows above `first` (a row interchange reaches at
 * most kl rows down, so the zeros above stay zero until then); each column
 * of the factors serves every right-hand side while it is in cache (their
 * serial chains interleave); in the back substitution the entry the next
 * column needs, b[j-1], is updated first: it alone is on the serial
 * critical path. */
static inline __attribute__((always_inline)) void band_solve_many_kl(const band_lu *lu,
                                                                    double *restrict b, int count,
                                                                    int first, const int kl)
{
    const int n = lu->n, kv = 2 * kl, ld = lu->ldab;
    const double *restrict ab = lu->ab;
    const double *restrict inv_diag = lu->inv_diag;
    const int *restrict pivot = lu->pivot;
    const size_t stride = (size_t)n;
    const int *restrict lower = lu->lower, *restrict upper = lu->upper;
    for (int j = first > kl ? first - kl : 0; j < n - 1; j++) {
        const int p = pivot[j] - 1, len = lower[j];
        const double *col = &ab[(size_t)j * ld + kv + 1];
        for (int c = 0; c < count; c++) {
            double *restrict bc = b + (size_t)c * stride, bj = bc[p];
            bc[p] = bc[j];
            bc[j] = bj;
            /* b[j+1], the next column's entry unless it pivots, updated on
             * its own first, as b[j-1] in the back substitution: out of
             * the vector loop, the next column need not wait for it */
            if (len == kl) {
                bc[j + 1] -= col[0] * bj;
                for (int i = 1; i < kl; i++) bc[j + 1 + i] -= col[i] * bj;
            } else if (len == SHORT_COLUMN) { /* fixed length: unrolled, vectorised */
                bc[j + 1] -= col[0] * bj;
                for (int i = 1; i < SHORT_COLUMN; i++) bc[j + 1 + i] -= col[i] * bj;
            } else {
                for (int i = 0; i < len; i++) bc[j + 1 + i] -= col[i] * bj;
            }
        }
    }
    for (int j = n - 1; j >= 0; j--) {
        const double *col = &ab[(size_t)j * ld + kv - j]; /* col[i] = U(i, j) */
        const int lo = upper[j];
        for (int c = 0; c < count; c++) {
            double *restrict bc = b + (size_t)c * stride, bj = bc[j] * inv_diag[j];
            bc[j] = bj;
            if (lo < j) {
                bc[j - 1] -= col[j - 1] * bj;
                for (int i = lo; i < j - 1; i++) bc[i] -= col[i] * bj;
            }
        }
    }
}

/* band_solve_many_kl for one right-hand side, b[j + 1] (b[j - 1] in the
 * back substitution) carried in a register to the next column, whose
 * value it is unless that column pivots: its serial chain then waits on
 * no store and load. The same operations in the same order. */
static inline __attribute__((always_inline)) void band_solve_one_kl(const band_lu *lu,
                                                                   double *restrict b,
                                                                   const int kl)
{
    const int n = lu->n, kv = 2 * kl, ld = lu->ldab;
    const double *restrict ab = lu->ab;
    const double *restrict inv_diag = lu->inv_diag;
    const int *restrict pivot = lu->pivot;
    const int *restrict lower = lu->lower, *restrict upper = lu->upper;
    double next = b[0]; /* b[j]'s value at column j */
    for (int j = 0; j < n - 1; j++) {
        const int p = pivot[j] - 1, len = lower[j];
        const double *col = &ab[(size_t)j * ld + kv + 1];
        double bj = next;
        if (p != j) {
            bj = b[p];
            b[p] = next;
        }
        b[j] = bj;
        if (len == kl) {
            next = b[j + 1] - col[0] * bj;
            b[j + 1] = next;
            for (int i = 1; i < kl; i++) b[j + 1 + i] -= col[i] * bj;
        } else if (len == SHORT_COLUMN) {
            next = b[j + 1] - col[0] * bj;
            b[j + 1] = next;
            for (int i = 1; i < SHORT_COLUMN; i++) b[j + 1 + i] -= col[i] * bj;
        } else if (len > 0) {
            next = b[j + 1] - col[0] * bj;
            b[j + 1] = next;
            for (int i = 1; i < len; i++) b[j + 1 + i] -= col[i] * bj;
        } else {
            next = b[j + 1];
        }
    }
    double here = b[n - 1]; /* b[j]'s value at column j */
    for (int j = n - 1; j >= 0; j--) {
        const double *col = &ab[(size_t)j * ld + kv - j]; /* col[i] = U(i, j) */
        const int lo = upper[j];
        const double bj = here * inv_diag[j];
        b[j] = bj;
        if (lo < j) {
            here = b[j - 1] - col[j - 1] * bj;
            b[j - 1] = here;
            for (int i = lo; i < j - 1; i++) b[i] -= col[i] * bj;
        } else if (j > 0) {
            here = b[j - 1];
        }
    }
}

/* band_solve_many_kl for `lanes` right-hand sides side by side, stored by
 * rows (t[LANES (i * width + v) + l] is row i of right-hand side
 * LANES v + l, width vectors a row): each step of the substitutions updates
 * a whole row of them at once, one vector operation for LANES numbers,
 * where the columns' own loops run 8 or 16 long and wait on the serial
 * chain from one step to the next. The same operations on each right-hand
 * side in the same order as band_solve_many_kl (no fused multiply-add), so
 * the same numbers. */
static inline __attribute__((always_inline)) void
band_solve_rows_kl(const band_lu *lu, lanes *restrict t, int first, const int kl,
                   const int width)
{
    const int n = lu->n, kv = 2 * kl, ld = lu->ldab;
    const double *restrict ab = lu->ab;
    const double *restrict inv_diag = lu->inv_diag;
    const int *restrict pivot = lu->pivot;
    const int *restrict lower = lu->lower, *restrict upper = lu->upper;
    for (int j = first > kl ? first - kl : 0; j < n - 1; j++) {
        const int p = pivot[j] - 1, len = lower[j];
        const double *col = &ab[(size_t)j * ld + kv + 1];
        lanes bj[ROWS_WIDTH];
        for (int v = 0; v < width; v++) {
            bj[v] = t[p * width + v];
            t[p * width + v] = t[j * width + v];
            t[j * width + v] = bj[v];
        }
        for (int i = 0; i < len; i++)
            for (int v = 0; v < width; v++) t[(j + 1 + i) * width + v] -= col[i] * bj[v];
    }
    for (int j = n - 1; j >= 0; j--) {
        const double *col = &ab[(size_t)j * ld + kv - j]; /* col[i] = U(i, j) */
        const int lo = upper[j];
        lanes bj[ROWS_WIDTH];
        for (int v = 0; v < width; v++) {
            bj[v] = t[j * width + v] * inv_diag[j];
            t[j * width + v] = bj[v];
        }
        for (int i = lo; i < j; i++)
            for (int v = 0; v < width; v++) t[i * width + v] -= col[i] * bj[v];
    }
}

/* The kernels inlined with kl a constant for the half bandwidths the
 * implicit rod scheme uses (5 in the plane, 8 in 3-D, 14 with punctures),
 * so that their loops over a full column have fixed lengths (unrolled,
 * vectorised); any other kl the same arithmetic with its lengths at run
 * time. */
static inline __attribute__((always_inline)) void
band_solve_rows_width(const band_lu *lu, lanes *t, int first, const int width)
{
    switch (lu->kl) {
    case 8: band_solve_rows_kl(lu, t, first, 8, width); break;
    case 14: band_solve_rows_kl(lu, t, first, 14, width); break;
    case 5: band_solve_rows_kl(lu, t, first, 5, width); break;
    default: band_solve_rows_kl(lu, t, first, lu->kl, width); break;
    }
}

/* A vector stored at any double's address */
typedef double lanes_unaligned __attribute__((vector_size(LANES * sizeof(double)), aligned(8)));

/* Columns c of t (n rows, `wide` a row) into b's columns (n apart), c <
 * cc: each LANES x LANES block of LANES rows and columns transposed in
 * registers (a column read down t alone touches a cache line a row) */
static inline __attribute__((always_inline)) void rows_copy_out(const double *t, int wide, int n,
                                                                double *b, int cc)
{
    const size_t w = (size_t)wide, stride = (size_t)n;
    int c0 = 0;
#if LANES == 4
    for (; c0 + 4 <= cc; c0 += 4) {
        double *b0 = b + (size_t)c0 * stride, *b1 = b0 + stride, *b2 = b1 + stride,
               *b3 = b2 + stride;
        int i = 0;
        for (; i + 4 <= n; i += 4) {
            const lanes *r = (const lanes *)(t + (size_t)i * w + (size_t)c0);
            const size_t v = w / 4; /* vectors a row */
            const lanes r0 = r[0], r1 = r[v], r2 = r[2 * v], r3 = r[3 * v];
            const lanes e0 = __builtin_shufflevector(r0, r1, 0, 4, 2, 6);
            const lanes e1 = __builtin_shufflevector(r0, r1, 1, 5, 3, 7);
            const lanes e2 = __builtin_shufflevector(r2, r3, 0, 4, 2, 6);
            const lanes e3 = __builtin_shufflevector(r2, r3, 1, 5, 3, 7);
            *(lanes_unaligned *)&b0[i] = __builtin_shufflevector(e0, e2, 0, 1, 4, 5);
            *(lanes_unaligned *)&b1[i] = __builtin_shufflevector(e1, e3, 0, 1, 4, 5);
            *(lanes_unaligned *)&b2[i] = __builtin_shufflevector(e0, e2, 2, 3, 6, 7);
            *(lanes_unaligned *)&b3[i] = __builtin_shufflevector(e1, e3, 2, 3, 6, 7);
        }
        for (; i < n; i++) {
            const double *ti = t + (size_t)i * w + (size_t)c0;
            b0[i] = ti[0], b1[i] = ti[1], b2[i] = ti[2], b3[i] = ti[3];
        }
    }
#endif
    for (int c = c0; c < cc; c++) {
        double *bc = b + (size_t)c * stride;
        for (int i = 0; i < n; i++) bc[i] = t[(size_t)i * w + (size_t)c];
    }
}

/* A chunk of band_solve_rows: its right-hand sides in t (`wide` a row,
 * cc of them in use) solved, and copied out into cc columns of b */
static inline __attribute__((always_inline)) void
rows_chunk_solve(const band_lu *lu, double *t, int wide, int first, double *b, int cc)
{
    const int n = lu->n;
    switch (wide / LANES) {
    case 4: band_solve_rows_width(lu, (lanes *)t, first, 4); break;
    case 3: band_solve_rows_width(lu, (lanes *)t, first, 3); break;
    case 2: band_solve_rows_width(lu, (lanes *)t, first, 2); break;
    default: band_solve_rows_width(lu, (lanes *)t, first, 1); break;
    }
    rows_copy_out(t, wide, n, b, cc);
}

/* band_solve_rows_kl, ROWS_CHUNK right-hand sides at a time (fewer in the
 * last chunk, up to LANES of them in one vector a row), copied into the rows
 * scratch and back: about half the time of the columns one at a time
 * (docs/decisions/0022-band-lu-profile.md). */
LANES_TARGET void band_solve_rows(const band_lu *lu, double *b, int count, int first)
{
    const int n = lu->n;
    const size_t stride = (size_t)n;
    double *t = lu->rows;
    for (int c0 = 0; c0 < count; c0 += ROWS_CHUNK) {
        const int cc = count - c0 < ROWS_CHUNK ? count - c0 : ROWS_CHUNK;
        const int wide = LANES * ((cc + LANES - 1) / LANES);
        /* rows above `first` are 0 in every column: the forward pass leaves
         * them so until kl rows above it, where it starts */
        for (int i = 0; i < n; i++) {
            double *ti = t + (size_t)i * (size_t)wide;
            int c = 0;
            for (; c < cc; c++) ti[c] = b[(size_t)(c0 + c) * stride + (size_t)i];
            for (; c < wide; c++) ti[c] = 0.0;
        }
        rows_chunk_solve(lu, t, wide, first, b + (size_t)c0 * stride, cc);
    }
}

/* band_solve_rows with the right-hand sides put into the rows scratch
 * from their entries: the scratch zeroed, each entry added at its row */
LANES_TARGET void band_solve_entries(const band_lu *lu, double *b, int count, int first,
                                     const int *start, const int *row, const double *value)
{
    const int n = lu->n;
    double *t = lu->rows;
    for (int c0 = 0; c0 < count; c0 += ROWS_CHUNK) {
        const int cc = count - c0 < ROWS_CHUNK ? count - c0 : ROWS_CHUNK;
        const int wide = LANES * ((cc + LANES - 1) / LANES);
        memset(t, 0, (size_t)n * (size_t)wide * sizeof(double));
        for (int c = 0; c < cc; c++)
            for (int k = start[c0 + c]; k < start[c0 + c + 1]; k++)
                t[(size_t)row[k] * (size_t)wide + (size_t)c] += value[k];
        rows_chunk_solve(lu, t, wide, first, b + (size_t)c0 * (size_t)n, cc);
    }
}

/* Step j's rank-1 update of columns j+c0 .. j+c1 (c0 >= 1) with L's
 * column j (col, its len entries below the diagonal; the diagonal entry at
 * col[0]), upper[] noting the first row of U that is not zero. The short
 * case from a copy of L's column: the columns it updates lie in the same
 * array, and the compiler, unable to rule out that they overlap it, left
 * the loop scalar (the same operations in the same order either way). */
static inline __attribute__((always_inline)) void
band_update(double *restrict col, int j, int c0, int c1, int len, int ld, int *restrict upper)
{
    if (len == SHORT_COLUMN) {
        double l[SHORT_COLUMN];
        for (int i = 0; i < SHORT_COLUMN; i++) l[i] = col[i + 1];
        for (int c = c0; c <= c1; c++) {
            double *a = &col[(size_t)c * (size_t)(ld - 1) + 1];
            const double u = a[-1]; /* U(j, j + c), final */
            if (u != 0.0) {
                if (upper[j + c] > j) upper[j + c] = j;
                for (int i = 0; i < SHORT_COLUMN; i++) a[i] -= l[i] * u;
            }
        }
    } else {
        for (int c = c0; c <= c1; c++) {
            double *a = &col[(size_t)c * (size_t)(ld - 1)];
            const double u = a[0];
            if (u != 0.0) {
                if (upper[j + c] > j) upper[j + c] = j;
                for (int i = 1; i <= len; i++) a[i] -= col[i] * u;
            }
        }
    }
}

/* Rows j and j + jp interchanged over columns j+c0 .. j+c1 (stride ld - 1
 * along a row) */
static inline __attribute__((always_inline)) void
band_swap(double *col, int jp, int c0, int c1, int ld)
{
    for (int c = c0; c <= c1; c++) {
        double *a = &col[(size_t)c * (size_t)(ld - 1)], t = a[0];
        a[0] = a[jp];
        a[jp] = t;
    }
}

/* LU of ab in place with partial pivoting: LAPACK's dgbtf2 (what dgbtrf
 * runs for kl below its block size), written out as band_solve_many_kl is:
 * its per-column dger, dswap and dscal calls cost more than their
 * arithmetic at this size. The same storage (kv = 2 kl rows above the
 * diagonal, U's fill-in in the top kl), 1-based pivots, and the first zero
 * pivot's column + 1 returned as LAPACK's info.
 * The band is as wide as the widest coupling but most columns may be
 * narrower: each column's L is trimmed of its trailing zeros before the
 * pivot search and the update (which only skips products with 0), and
 * lower / upper record the profile for the solves (the same numbers).
 * From column `from` on, the columns before it factored already (from > 0),
 * as the whole factorisation would factor them:
 * the columns from `from` on hold the matrix, and the steps before it whose
 * interchanges and updates reach them (at most 2 kl back) are applied to
 * them again from their pivots and L, then the steps go on from `from`. The
 * same operations on every entry in the same order as from 0, so the same
 * numbers. */
static inline __attribute__((always_inline)) int band_factor_kl(band_lu *lu, const int kl,
                                                               const int from)
{
    const int n = lu->n, kv = 2 * kl, ld = lu->ldab;
    double *restrict ab = lu->ab;
    int *restrict pivot = lu->pivot;
    int *restrict lower = lu->lower, *restrict upper = lu->upper;
    int info = 0, ju = 0;
    for (int j = from; j < n; j++) upper[j] = j; /* none above the diagonal yet */
    /* the fill-in rows of the first kl columns start at zero */
    for (int j = kl + 1 > from ? kl + 1 : from; j < kv && j < n; j++)
        for (int i = kv - j; i < kl; i++) ab[(size_t)j * ld + i] = 0.0;
    for (int j = 0; j < from; j++) { /* the steps before: their reach, and again on from.. */
        const int jp = pivot[j] - 1 - j;
        const int last = j + kl + jp < n - 1 ? j + kl + jp : n - 1;
        if (last > ju) ju = last;
        if (j + kv < n && j + kv >= from)
            for (int i = 0; i < kl; i++) ab[(size_t)(j + kv) * ld + i] = 0.0;
        if (ju < from) continue;
        double *col = &ab[(size_t)j * ld + kv];
        if (jp != 0) band_swap(col, jp, from - j, ju - j, ld);
        band_update(col, j, from - j, ju - j, lower[j], ld, upper);
    }
    for (int j = from; j < n; j++) {
        if (j + kv < n)
            for (int i = 0; i < kl; i++) ab[(size_t)(j + kv) * ld + i] = 0.0;
        int km = kl < n - 1 - j ? kl : n - 1 - j;
        double *col = &ab[(size_t)j * ld + kv]; /* col[i] = A(j + i, j) */
        while (km > 0 && col[km] == 0.0) km--;
        /* the loops over L run a fixed length of SHORT_COLUMN where km is
         * shorter and the band not narrower, over exact zeros past km (the same
         * numbers): a loop over km did not unroll or vectorise */
        const int len = kl >= SHORT_COLUMN && km < SHORT_COLUMN && j + SHORT_COLUMN < n
                            ? SHORT_COLUMN : km;
        lower[j] = len;
        int jp = 0;
        double big = fabs(col[0]);
        for (int i = 1; i <= km; i++)
            if (fabs(col[i]) > big) {
                big = fabs(col[i]);
                jp = i;
            }
        pivot[j] = j + jp + 1;
        if (col[jp] == 0.0) {
            if (info == 0) info = j + 1;
            continue;
        }
        const int last = j + kl + jp < n - 1 ? j + kl + jp : n - 1;
        if (last > ju) ju = last;
        if (jp != 0) band_swap(col, jp, 0, ju - j, ld); /* over columns j..ju */
        const double inv = 1.0 / col[0];
        for (int i = 1; i <= km; i++) col[i] *= inv;
        band_update(col, j, 1, ju - j, len, ld, upper); /* columns j+1..ju */
    }
    return info;
}

void band_solve_many(const band_lu *lu, double *b, int count, int first)
{
    if (lu->rows && count > 1) {
        band_solve_rows(lu, b, count, first);
        return;
    }
    switch (lu->kl) {
    case 8: band_solve_many_kl(lu, b, count, first, 8); break;
    case 14: band_solve_many_kl(lu, b, count, first, 14); break;
    case 5: band_solve_many_kl(lu, b, count, first, 5); break;
    default: band_solve_many_kl(lu, b, count, first, lu->kl); break;
    }
}

void band_solve(const band_lu *lu, double *b)
{
    switch (lu->kl) {
    case 8: band_solve_one_kl(lu, b, 8); break;
    case 14: band_solve_one_kl(lu, b, 14); break;
    case 5: band_solve_one_kl(lu, b, 5); break;
    default: band_solve_one_kl(lu, b, lu->kl); break;
    }
}

int band_factor(band_lu *lu, int from)
{
    int info;
    switch (lu->kl) {
    case 8: info = band_factor_kl(lu, 8, from); break;
    case 14: info = band_factor_kl(lu, 14, from); break;
    case 5: info = band_factor_kl(lu, 5, from); break;
    default: info = band_factor_kl(lu, lu->kl, from); break;
    }
    if (info == 0) {
        const int n = lu->n, kl = lu->kl, ku = lu->kl, ld = lu->ldab;
        for (int j = from; j < n; j++)
            lu->inv_diag[j] = 1.0 / lu->ab[(size_t)j * (size_t)ld + (size_t)(kl + ku)];
    }
    return info;
}
