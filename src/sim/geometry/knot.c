/* knot.c: the knot type of a polygon from the Alexander polynomial of a
 * generic projection (knot.h).
 *
 * Closure of an open polygon: both ends are extended radially from the
 * centroid c to a sphere of radius R = 10 x the curve's extent (its largest
 * distance from c), and the two points there are joined along the great arc of
 * that sphere (chords of at most 10 degrees, so the arc stays beyond 0.99 R).
 * Everything added lies outside the ball that holds the curve except the two
 * radial rays, and the region outside a ball is simply connected: any other
 * path joining the rays' ends there gives the same knot. So for a knot tied
 * away from the ends, with the tails leaving it (ends pulled out, as a thread
 * in a suture), the closure does not change the type. A knot whose tails end
 * inside it (a loose end tucked back through a loop) has no type of its own:
 * the radial closure then picks one.
 *
 * Projection: along a fixed irrational-looking direction; a projection that
 * is not generic (a vertex within 1e-9 of another segment in the plane, nearly
 * collinear overlapping segments, two crossings at one point of a segment, or
 * strands at the same height at a crossing) is dropped and the next direction
 * of a fixed sequence tried, up to KNOT_TRIES.
 *
 * Crossings: segments are hashed into a 2-D grid of cells as large as the
 * longest segment, so only segments sharing a cell are tested (near linear in
 * the nodes); the few long segments of the closure are tested against all.
 *
 * Polynomial: the Alexander matrix of the diagram (Livingston, Knot Theory,
 * 1993, ch. 6: one row per crossing, one column per arc between
 * undercrossings; over arc k, under arcs i in, j out: (1 - t) at k, t at i,
 * -1 at j for a crossing of one sign, (1 - t) at k, -1 at i, t at j for the
 * other). Any (c-1) x (c-1) minor M(t) = A + t B has det M = +-t^k Delta(t),
 * whose coefficients are Delta's: small integers. det M is computed exactly
 * modulo two primes: M(t0 + s) = M(t0) (I + s C) with C = M(t0)^-1 B, and
 * det(I + s C) comes from the characteristic polynomial of -C (Hessenberg
 * reduction, O(c^3)); shifting back s = t - t0 gives det M(t). Each
 * coefficient is read in (-p/2, p/2); the two primes must agree.
 *
 * Signature: from the same diagram's Goeritz matrix (Gordon-Litherland, see
 * signature()); it names the square knot and the granny apart. */
#include "sim/geometry/knot.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define KNOT_TRIES 16
#define KNOT_CLOSURE_RADIUS 10.0   /* x the curve's extent */
#define KNOT_ARC_STEP 0.17453292519943295 /* rad, 10 degrees */
#define KNOT_PARAM_TOL 1e-9        /* segment parameter: a vertex on a segment */
#define KNOT_PARALLEL_TOL 1e-12    /* |sin| of the angle of two projected segments */
#define KNOT_HEIGHT_TOL 1e-10      /* x extent: strands at one height */
#define KNOT_MAX_TESTS 200000000LL /* segment pairs tested per projection */

static const uint64_t knot_primes[2] = {2147483647u, 1000000007u};

/* A crossing: segments seg[0] < seg[1] (of the closed polygon) at parameters
 * t; over: which of the two is on top; sign of the projected (over x under). */
typedef struct crossing {
    int seg[2];
    double t[2];
    int over, sign;
} crossing;

/* One passage of the curve through a crossing. */
typedef struct passage {
    int seg, crossing, under;
    double t;
} passage;

typedef struct projection {
    const double *p;       /* (count x 3) the closed polygon */
    int count;             /* vertices = segments */
    int knot_segments;     /* segments [0, knot_segments) are the curve's own (short) */
    int mid_lo, mid_hi;    /* and [mid_lo, mid_hi) (two threads joined: knot_across.h) */
    double *xy;            /* (count x 2) projected */
    double *z;             /* (count) height along the direction */
    double extent;         /* m, of the curve */
    crossing *x;
    int crossings, capacity;
    int degenerate;        /* 1: try another direction */
    int intersecting;      /* segments at one height at a crossing (a 3-D intersection) */
    int meet[2];
    long long tests;
    rod_knot_scratch *scratch;
} projection;

/* Scratch ------------------------------------------------------------------ */

/* One block reused from call to call: a call takes what it needs from it in
 * order (released per projection tried); what does not fit comes from malloc
 * for this call only, and the block grows to the call's peak for the next
 * one. A run identifying every output frame then allocates nothing once the
 * block has grown. */
typedef struct overflow_chunk {
    struct overflow_chunk *next;
} overflow_chunk;

struct rod_knot_scratch {
    unsigned char *base;
    size_t size, used;
    size_t live, peak;          /* bytes taken in this call (block and overflow) */
    overflow_chunk *overflow;
};

rod_knot_scratch *rod_knot_scratch_create(void) { return calloc(1, sizeof(rod_knot_scratch)); }

void rod_knot_scratch_destroy(rod_knot_scratch *s)
{
    if (!s) return;
    free(s->base);
    free(s);
}

/* bytes from the scratch (16-byte aligned), NULL out of memory */
static void *take(rod_knot_scratch *s, size_t bytes, int zero)
{
    bytes = (bytes + 15) & ~(size_t)15;
    void *p;
    if (s->used + bytes <= s->size) {
        p = s->base + s->used;
        s->used += bytes;
    } else {
        overflow_chunk *c = malloc(sizeof(overflow_chunk) + 16 + bytes);
        if (!c) return NULL;
        c->next = s->overflow;
        s->overflow = c;
        p = (unsigned char *)c + 16; /* header rounded up to keep the alignment */
    }
    s->live += bytes;
    if (s->live > s->peak) s->peak = s->live;
    if (zero) memset(p, 0, bytes);
    return p;
}

typedef struct scratch_mark {
    size_t used, live;
} scratch_mark;

static scratch_mark scratch_save(const rod_knot_scratch *s) { return (scratch_mark){s->used, s->live}; }
static void scratch_restore(rod_knot_scratch *s, scratch_mark m)
{
    s->used = m.used;
    s->live = m.live;
}

/* The end of a call: the overflow freed, the block grown to the peak. */
static void scratch_end(rod_knot_scratch *s)
{
    while (s->overflow) {
        overflow_chunk *next = s->overflow->next;
        free(s->overflow);
        s->overflow = next;
    }
    if (s->peak > s->size) {
        unsigned char *bigger = malloc(s->peak);
        if (bigger) {
            free(s->base);
            s->base = bigger;
            s->size = s->peak;
        }
    }
    s->used = s->live = s->peak = 0;
}

/* Modular arithmetic -------------------------------------------------- */

static uint64_t mod_mul(uint64_t a, uint64_t b, uint64_t p) { return a * b % p; }
static uint64_t mod_sub(uint64_t a, uint64_t b, uint64_t p) { return a >= b ? a - b : a + p - b; }
static uint64_t mod_add(uint64_t a, uint64_t b, uint64_t p) { return (a + b) % p; }
static uint64_t mod_of(long long v, uint64_t p)
{
    long long r = v % (long long)p;
    return (uint64_t)(r < 0 ? r + (long long)p : r);
}
static uint64_t mod_pow(uint64_t a, uint64_t e, uint64_t p)
{
    uint64_t r = 1;
    for (a %= p; e; e >>= 1, a = mod_mul(a, a, p))
        if (e & 1) r = mod_mul(r, a, p);
    return r;
}
static uint64_t mod_inv(uint64_t a, uint64_t p) { return mod_pow(a, p - 2, p); }

/* [M | C] -> [I | M^-1 C] by Gauss-Jordan elimination mod p; *det = det M
 * from the pivots. Returns 1 when M is singular mod p, else 0. */
static int invert_into_mod(uint64_t *M, uint64_t *C, int m, uint64_t p, uint64_t *det_out)
{
    uint64_t det = 1;
    int singular = 0;
    for (int col = 0; col < m && !singular; col++) {
        int piv = col;
        while (piv < m && M[(size_t)piv * m + col] == 0) piv++;
        if (piv == m) { singular = 1; break; }
        if (piv != col) {
            for (int k = 0; k < m; k++) {
                uint64_t a = M[(size_t)piv * m + k], b = C[(size_t)piv * m + k];
                M[(size_t)piv * m + k] = M[(size_t)col * m + k];
                C[(size_t)piv * m + k] = C[(size_t)col * m + k];
                M[(size_t)col * m + k] = a;
                C[(size_t)col * m + k] = b;
            }
            det = mod_sub(0, det, p);
        }
        uint64_t pivot = M[(size_t)col * m + col], inv = mod_inv(pivot, p);
        det = mod_mul(det, pivot, p);
        for (int k = 0; k < m; k++) {
            M[(size_t)col * m + k] = mod_mul(M[(size_t)col * m + k], inv, p);
            C[(size_t)col * m + k] = mod_mul(C[(size_t)col * m + k], inv, p);
        }
        for (int r = 0; r < m; r++) {
            uint64_t f = M[(size_t)r * m + col];
            if (r == col || f == 0) continue;
            for (int k = 0; k < m; k++) {
                M[(size_t)r * m + k] = mod_sub(M[(size_t)r * m + k],
                                               mod_mul(f, M[(size_t)col * m + k], p), p);
                C[(size_t)r * m + k] = mod_sub(C[(size_t)r * m + k],
                                               mod_mul(f, C[(size_t)col * m + k], p), p);
            }
        }
    }
    *det_out = det;
    return singular;
}

/* H (m x m) reduced to upper Hessenberg form by similarity, mod p */
static void hessenberg_mod(uint64_t *H, int m, uint64_t p)
{
    for (int j = 0; j + 2 < m; j++) {
        int piv = j + 1;
        while (piv < m && H[(size_t)piv * m + j] == 0) piv++;
        if (piv == m) continue;
        if (piv != j + 1) {
            for (int k = 0; k < m; k++) {
                uint64_t a = H[(size_t)piv * m + k];
                H[(size_t)piv * m + k] = H[(size_t)(j + 1) * m + k];
                H[(size_t)(j + 1) * m + k] = a;
            }
            for (int k = 0; k < m; k++) {
                uint64_t a = H[(size_t)k * m + piv];
                H[(size_t)k * m + piv] = H[(size_t)k * m + j + 1];
                H[(size_t)k * m + j + 1] = a;
            }
        }
        uint64_t inv = mod_inv(H[(size_t)(j + 1) * m + j], p);
        for (int i = j + 2; i < m; i++) {
            uint64_t u = mod_mul(H[(size_t)i * m + j], inv, p);
            if (u == 0) continue;
            for (int k = 0; k < m; k++)
                H[(size_t)i * m + k] =
                    mod_sub(H[(size_t)i * m + k], mod_mul(u, H[(size_t)(j + 1) * m + k], p), p);
            for (int k = 0; k < m; k++)
                H[(size_t)k * m + j + 1] =
                    mod_add(H[(size_t)k * m + j + 1], mod_mul(u, H[(size_t)k * m + i], p), p);
        }
    }
}

/* chi_k(lambda) = det(lambda I - H_k), H_k the leading k x k block of the
 * Hessenberg H, as rows k of chi ((m+1) x (m+1), coefficients by degree)
 * (Cohen, A Course in Computational Algebraic Number Theory, alg. 2.2.9) */
static void hessenberg_charpoly_mod(const uint64_t *H, int m, uint64_t p, uint64_t *chi)
{
    size_t w = (size_t)m + 1;
    memset(chi, 0, w * w * sizeof *chi);
    chi[0] = 1;
    for (int k = 1; k <= m; k++) {
        uint64_t *row = &chi[(size_t)k * w];
        const uint64_t *prev = &chi[(size_t)(k - 1) * w];
        uint64_t diag = H[(size_t)(k - 1) * m + k - 1];
        for (int d = 0; d <= k; d++) {
            uint64_t v = d > 0 ? prev[d - 1] : 0;
            row[d] = mod_sub(v, mod_mul(diag, prev[d], p), p);
        }
        uint64_t prod = 1;
        for (int i = k - 1; i >= 1; i--) {
            prod = mod_mul(prod, H[(size_t)i * m + i - 1], p);
            uint64_t f = mod_mul(H[(size_t)(i - 1) * m + k - 1], prod, p);
            if (f == 0) continue;
            const uint64_t *q = &chi[(size_t)(i - 1) * w];
            for (int d = 0; d < i; d++) row[d] = mod_sub(row[d], mod_mul(f, q[d], p), p);
        }
    }
}

/* det(M0 + s B) = det M0 sum_j chi_{m-j} s^j, chim = chi_m; then s = t - t0
 * (Horner) gives poly[0..m] in t */
static void shift_back_mod(uint64_t det, const uint64_t *chim, int m, uint64_t t0, uint64_t p,
                           uint64_t *poly)
{
    for (int d = 0; d <= m; d++) poly[d] = 0;
    for (int j = m; j >= 0; j--) {
        /* poly = poly (t - t0) + a_j */
        for (int d = m; d >= 1; d--)
            poly[d] = mod_sub(poly[d - 1], mod_mul(t0, poly[d], p), p);
        poly[0] = mod_sub(mod_mul(det, chim[m - j], p), mod_mul(t0, poly[0], p), p);
    }
}

/* det(A + t B) mod p as coefficients poly[0..m] (m x m, entries small
 * integers, row-major). Returns 0, or -1 when no shift t0 tried makes
 * A + t0 B invertible mod p. Scratch: 2 m^2 + (m+1)^2 words. */
static int det_polynomial_mod(rod_knot_scratch *sc, const long long *A, const long long *B,
                              int m, uint64_t p, uint64_t *poly)
{
    if (m == 0) {
        poly[0] = 1;
        return 0;
    }
    size_t mm = (size_t)m * m;
    scratch_mark mark = scratch_save(sc);
    uint64_t *M = take(sc, mm * sizeof *M, 0), *C = take(sc, mm * sizeof *C, 0);
    uint64_t *chi = take(sc, (size_t)(m + 1) * (m + 1) * sizeof *chi, 0);
    int rc = -1;
    if (!M || !C || !chi) goto done;
    for (uint64_t t0 = 7; t0 < 7 + 8 && rc; t0++) {
        for (size_t k = 0; k < mm; k++) {
            M[k] = mod_add(mod_of(A[k], p), mod_mul(t0, mod_of(B[k], p), p), p);
            C[k] = mod_of(B[k], p);
        }
        uint64_t det;
        if (invert_into_mod(M, C, m, p, &det)) continue;
        uint64_t *H = M; /* H = -C, in M's place */
        for (size_t k = 0; k < mm; k++) H[k] = mod_sub(0, C[k], p);
        hessenberg_mod(H, m, p);
        hessenberg_charpoly_mod(H, m, p, chi);
        shift_back_mod(det, &chi[(size_t)m * (m + 1)], m, t0, p, poly);
        rc = 0;
    }
done:
    scratch_restore(sc, mark);
    return rc;
}

/* Projection and crossings --------------------------------------------- */

static double cross2(const double *a, const double *b) { return a[0] * b[1] - a[1] * b[0]; }

static int adjacent(const projection *pr, int a, int b)
{
    int d = abs(a - b);
    return d <= 1 || d == pr->count - 1;
}

/* Tests segments a < b of the closed polygon; records a crossing. */
static void test_pair(projection *pr, int a, int b)
{
    if (a > b) { int s = a; a = b; b = s; }
    if (adjacent(pr, a, b) || pr->degenerate) return;
    pr->tests++;
    int a1 = (a + 1) % pr->count, b1 = (b + 1) % pr->count;
    const double *pa = &pr->xy[2 * a], *pb = &pr->xy[2 * b];
    double r[2] = {pr->xy[2 * a1] - pa[0], pr->xy[2 * a1 + 1] - pa[1]};
    double q[2] = {pr->xy[2 * b1] - pb[0], pr->xy[2 * b1 + 1] - pb[1]};
    double e[2] = {pb[0] - pa[0], pb[1] - pa[1]};
    double rl = hypot(r[0], r[1]), ql = hypot(q[0], q[1]);
    double denom = cross2(r, q);
    if (rl == 0.0 || ql == 0.0) { pr->degenerate = 1; return; } /* seen end-on */
    if (fabs(denom) <= KNOT_PARALLEL_TOL * rl * ql) {
        /* parallel: degenerate only when collinear and overlapping */
        double off = fabs(cross2(r, e)) / rl;
        if (off > KNOT_PARAM_TOL * pr->extent) return;
        double u0 = (e[0] * r[0] + e[1] * r[1]) / (rl * rl);
        double u1 = u0 + (q[0] * r[0] + q[1] * r[1]) / (rl * rl);
        if (fmax(u0, u1) >= -KNOT_PARAM_TOL && fmin(u0, u1) <= 1.0 + KNOT_PARAM_TOL)
            pr->degenerate = 1;
        return;
    }
    double t = cross2(e, q) / denom, u = cross2(e, r) / denom;
    const double lo = -KNOT_PARAM_TOL, hi = 1.0 + KNOT_PARAM_TOL;
    if (t < lo || t > hi || u < lo || u > hi) return;
    if (t < KNOT_PARAM_TOL || t > 1.0 - KNOT_PARAM_TOL || u < KNOT_PARAM_TOL ||
        u > 1.0 - KNOT_PARAM_TOL) {
        pr->degenerate = 1; /* a vertex on the other segment */
        return;
    }
    double za = pr->z[a] + t * (pr->z[a1] - pr->z[a]), zb = pr->z[b] + u * (pr->z[b1] - pr->z[b]);
    if (fabs(za - zb) <= KNOT_HEIGHT_TOL * pr->extent) {
        pr->degenerate = 1;
        pr->intersecting = 1;
        pr->meet[0] = a;
        pr->meet[1] = b;
        return;
    }
    if (pr->crossings == pr->capacity) {
        int bigger = pr->capacity ? 2 * pr->capacity : 64;
        crossing *x = take(pr->scratch, (size_t)bigger * sizeof *x, 0);
        if (!x) { pr->degenerate = 2; return; }
        if (pr->crossings) memcpy(x, pr->x, (size_t)pr->crossings * sizeof *x);
        pr->x = x;
        pr->capacity = bigger;
    }
    crossing *c = &pr->x[pr->crossings++];
    c->seg[0] = a;
    c->seg[1] = b;
    c->t[0] = t;
    c->t[1] = u;
    c->over = za > zb ? 0 : 1;
    /* sign of (over direction) x (under direction) in the plane */
    double s = c->over == 0 ? denom : -denom;
    c->sign = s > 0.0 ? 1 : -1;
}

typedef struct cell_entry {
    uint32_t bucket;
    int segment, ix, iy;
} cell_entry;

static uint32_t cell_hash(int ix, int iy, uint32_t mask)
{
    return ((uint32_t)ix * 73856093u ^ (uint32_t)iy * 19349663u) & mask;
}

/* Every crossing of the projection. Returns 0, or -1 out of memory. */
static int find_crossings(projection *pr)
{
    const int first = pr->knot_segments, n = first + (pr->mid_hi - pr->mid_lo);
    /* the short segments: [0, first), then [mid_lo, mid_hi) */
#define SHORT_SEGMENT(i) ((i) < first ? (i) : pr->mid_lo + (i) - first)
#define IS_SHORT(k) ((k) < first || ((k) >= pr->mid_lo && (k) < pr->mid_hi))
    /* cell: the longest short segment's projection (each covers <= 2 x 2 cells) */
    double h = 0.0;
    for (int i = 0; i < n; i++) {
        const int k = SHORT_SEGMENT(i);
        int k1 = (k + 1) % pr->count;
        h = fmax(h, hypot(pr->xy[2 * k1] - pr->xy[2 * k], pr->xy[2 * k1 + 1] - pr->xy[2 * k + 1]));
    }
    if (!(h > 0.0)) h = pr->extent > 0.0 ? pr->extent : 1.0;
    double x0 = pr->xy[0], y0 = pr->xy[1];
    cell_entry *cells = take(pr->scratch, (size_t)4 * (n > 0 ? n : 1) * sizeof *cells, 0);
    if (!cells) return -1;
    uint32_t size = 1;
    while (size < (uint32_t)(8 * (n > 0 ? n : 1))) size <<= 1;
    int count = 0;
    for (int i = 0; i < n; i++) {
        const int k = SHORT_SEGMENT(i);
        int k1 = (k + 1) % pr->count;
        double ax = pr->xy[2 * k] - x0, ay = pr->xy[2 * k + 1] - y0;
        double bx = pr->xy[2 * k1] - x0, by = pr->xy[2 * k1 + 1] - y0;
        int ix0 = (int)floor(fmin(ax, bx) / h), ix1 = (int)floor(fmax(ax, bx) / h);
        int iy0 = (int)floor(fmin(ay, by) / h), iy1 = (int)floor(fmax(ay, by) / h);
        for (int ix = ix0; ix <= ix1 && ix <= ix0 + 1; ix++)
            for (int iy = iy0; iy <= iy1 && iy <= iy0 + 1; iy++)
                cells[count++] = (cell_entry){cell_hash(ix, iy, size - 1), k, ix, iy};
    }
    /* counting sort by bucket, stable: each bucket's entries in segment order */
    cell_entry *sorted = take(pr->scratch, (size_t)(count > 0 ? count : 1) * sizeof *sorted, 0);
    uint32_t *start = take(pr->scratch, ((size_t)size + 1) * sizeof *start, 1);
    if (!sorted || !start) return -1;
    for (int e = 0; e < count; e++) start[cells[e].bucket + 1]++;
    for (uint32_t b = 0; b < size; b++) start[b + 1] += start[b];
    for (int e = 0; e < count; e++) sorted[start[cells[e].bucket]++] = cells[e];
    cells = sorted;
    for (int a = 0; a < count && !pr->degenerate; a++) {
        for (int b = a + 1; b < count && cells[b].bucket == cells[a].bucket; b++) {
            if (cells[b].ix != cells[a].ix || cells[b].iy != cells[a].iy) continue;
            /* a pair sharing several cells is tested in the first of them only */
            int sa = cells[a].segment, sb = cells[b].segment;
            /* the lowest cell both segments cover */
            int fx[2], fy[2];
            for (int s = 0; s < 2; s++) {
                int k = s ? sb : sa, k1 = (k + 1) % pr->count;
                double ax = pr->xy[2 * k] - x0, bx = pr->xy[2 * k1] - x0;
                double ay = pr->xy[2 * k + 1] - y0, by = pr->xy[2 * k1 + 1] - y0;
                fx[s] = (int)floor(fmin(ax, bx) / h);
                fy[s] = (int)floor(fmin(ay, by) / h);
            }
            int first_x = fx[0] > fx[1] ? fx[0] : fx[1];
            int first_y = fy[0] > fy[1] ? fy[0] : fy[1];
            if (cells[a].ix != first_x || cells[a].iy != first_y) continue;
            test_pair(pr, sa, sb);
            if (pr->tests > KNOT_MAX_TESTS || pr->crossings > ROD_KNOT_MAX_CROSSINGS) break;
        }
        if (pr->tests > KNOT_MAX_TESTS || pr->crossings > ROD_KNOT_MAX_CROSSINGS) break;
    }
    /* the closure's long segments against every segment whose box meets theirs */
    for (int a = first; a < pr->count && !pr->degenerate; a++) {
        if (IS_SHORT(a)) continue;
        int a1 = (a + 1) % pr->count;
        double lo[2], hi[2];
        for (int k = 0; k < 2; k++) {
            lo[k] = fmin(pr->xy[2 * a + k], pr->xy[2 * a1 + k]) - KNOT_PARAM_TOL * pr->extent;
            hi[k] = fmax(pr->xy[2 * a + k], pr->xy[2 * a1 + k]) + KNOT_PARAM_TOL * pr->extent;
        }
        for (int b = 0; b < pr->count && !pr->degenerate; b++) {
            if (!IS_SHORT(b) && b <= a) continue;
            int b1 = (b + 1) % pr->count, apart = 0;
            for (int k = 0; k < 2; k++)
                apart = apart || fmax(pr->xy[2 * b + k], pr->xy[2 * b1 + k]) < lo[k] ||
                        fmin(pr->xy[2 * b + k], pr->xy[2 * b1 + k]) > hi[k];
            if (!apart) test_pair(pr, a, b);
        }
    }
    return pr->degenerate == 2 ? -1 : 0;
#undef SHORT_SEGMENT
#undef IS_SHORT
}

static int passage_order(const void *a, const void *b)
{
    const passage *x = a, *y = b;
    if (x->seg != y->seg) return x->seg - y->seg;
    return (x->t > y->t) - (x->t < y->t);
}

/* Names ----------------------------------------------------------------- */

/* Delta(t), normalised (lowest term constant, positive). Several knots share
 * a polynomial; the name is that of the smallest (Rolfsen's table). Where
 * the polynomial names two composites that its signature tells apart, the
 * name for each |signature| (when it is known) follows. */
typedef struct signed_name {
    int abs_signature;
    const char *name;
} signed_name;

static const struct {
    const char *name;
    int crossing_number; /* of the knot named (Rolfsen's table; a composite's: the sum
                            of its parts', as for every alternating knot) */
    int terms;
    long long c[9];
    signed_name by_signature[2];
} known_knots[] = {
    {"unknot", 0, 1, {1}, {{0, NULL}}},
    {"trefoil", 3, 3, {1, -1, 1}, {{0, NULL}}},
    {"figure-eight", 4, 3, {1, -3, 1}, {{0, NULL}}},
    {"cinquefoil (5_1)", 5, 5, {1, -1, 1, -1, 1}, {{0, NULL}}},
    {"three-twist (5_2)", 5, 3, {2, -3, 2}, {{0, NULL}}},
    {"stevedore (6_1)", 6, 3, {2, -5, 2}, {{0, NULL}}},
    {"6_2", 6, 5, {1, -3, 3, -3, 1}, {{0, NULL}}},
    {"6_3", 6, 5, {1, -3, 5, -3, 1}, {{0, NULL}}},
    {"7_1", 7, 7, {1, -1, 1, -1, 1, -1, 1}, {{0, NULL}}},
    /* the Alexander polynomial cannot tell the square knot (trefoil # its mirror)
     * from the granny (trefoil # trefoil): both (t^2 - t + 1)^2; the signature
     * does (0 and +-4), when it is known */
    {"square or granny (composite of two trefoils)", 6, 5, {1, -2, 3, -2, 1},
     {{0, "square knot (trefoil # mirror trefoil)"}, {4, "granny knot (trefoil # trefoil)"}}},
    {"trefoil # figure-eight", 7, 5, {1, -4, 5, -4, 1}, {{0, NULL}}},
    /* Delta and signature of the surgical knots (KnotInfo, knotinfo.math.indiana.edu:
     * 3_1 1 - t + t^2, sigma -2; 5_1 1 - t + t^2 - t^3 + t^4, sigma -4, both for
     * the positive (right-handed) diagram; Rolfsen, Knots and Links, app. C):
     * Delta multiplies and sigma adds under #. The surgeon's knot: a double
     * throw (closed, the double overhand knot: the cinquefoil) and a single
     * one (the trefoil); no prime knot of up to
     * 8 crossings has this polynomial (Rolfsen's table). The signature tells
     * the surgeon's knot, whose throws turn opposite ways as a square knot's
     * (+-4 -+ 2 = +-2), from its granny (+-6) */
    {"cinquefoil # trefoil", 8, 7, {1, -2, 3, -3, 3, -2, 1},
     {{2, "surgeon's knot (cinquefoil # mirror trefoil)"},
      {6, "granny surgeon's knot (cinquefoil # trefoil)"}}},
    {"figure-eight # figure-eight", 8, 5, {1, -6, 11, -6, 1}, {{0, NULL}}},
};

void rod_knot_polynomial_text(const rod_knot *k, char *buf, size_t n)
{
    size_t used = 0;
    buf[0] = '\0';
    for (int d = 0; d < k->terms && used + 1 < n; d++) {
        long long c = k->coefficient[d];
        if (c == 0) continue;
        long long a = c < 0 ? -c : c;
        const char *sign = used == 0 ? (c < 0 ? "-" : "") : (c < 0 ? " - " : " + ");
        int w;
        if (d == 0) w = snprintf(buf + used, n - used, "%s%lld", sign, a);
        else if (a == 1) w = snprintf(buf + used, n - used, "%st%s", sign, d > 1 ? "^" : "");
        else w = snprintf(buf + used, n - used, "%s%lldt%s", sign, a, d > 1 ? "^" : "");
        if (w < 0) return;
        used += (size_t)w < n - used ? (size_t)w : n - used - 1;
        if (d > 1 && used + 1 < n) {
            w = snprintf(buf + used, n - used, "%d", d);
            if (w < 0) return;
            used += (size_t)w < n - used ? (size_t)w : n - used - 1;
        }
    }
    if (used == 0) snprintf(buf, n, "0");
}

/* Identification ----------------------------------------------------------- */

/* Unit direction number k of the fixed sequence (a golden-ratio spiral over
 * the sphere, started off every axis and symmetry plane). */
static void direction_of_try(int k, double w[3])
{
    double u = fmod(0.1234567 + 0.6180339887498949 * k, 1.0);
    double v = fmod(0.3183098861837907 + 0.7548776662466927 * k, 1.0);
    double cz = 1.0 - 2.0 * u, sz = sqrt(fmax(0.0, 1.0 - cz * cz)), phi = 2.0 * M_PI * v;
    w[0] = sz * cos(phi);
    w[1] = sz * sin(phi);
    w[2] = cz;
}

/* Signature ------------------------------------------------------------- */

/* Signs of the eigenvalues of a symmetric n x n matrix (row-major, destroyed):
 * symmetric elimination with Bunch-Parlett pivoting (a 1 x 1 pivot on the
 * largest diagonal entry when it is not much below the largest off-diagonal
 * one, else a 2 x 2 pivot on that), Sylvester's law of inertia. Returns the
 * number of pivots below 1e-9 of the largest entry (0 for a knot's Goeritz
 * matrix, whose determinant is the knot determinant). */
static int inertia(long double *a, int n, int *positive, int *negative)
{
    *positive = *negative = 0;
    long double largest = 0.0L;
    for (int i = 0; i < n * n; i++) largest = fmaxl(largest, fabsl(a[i]));
    long double tiny = 1e-9L * (largest > 0.0L ? largest : 1.0L);
    int k = 0;
    while (k < n) {
        int di = k, oi = k, oj = k;
        long double dmax = -1.0L, omax = -1.0L;
        for (int i = k; i < n; i++) {
            if (fabsl(a[i * n + i]) > dmax) { dmax = fabsl(a[i * n + i]); di = i; }
            for (int j = k; j < i; j++)
                if (fabsl(a[i * n + j]) > omax) { omax = fabsl(a[i * n + j]); oi = i; oj = j; }
        }
        if (dmax <= tiny && omax <= tiny) return n - k; /* the rest is zero */
        int block = dmax >= 0.6404L * omax ? 1 : 2;
        int pick[2] = {block == 1 ? di : oj, oi};
        for (int b = 0; b < block; b++) { /* swap row and column pick[b] <-> k + b */
            int i = pick[b], t = k + b;
            if (b == 0 && pick[1] == t) pick[1] = i; /* the second moves with the swap */
            if (i == t) continue;
            for (int j = 0; j < n; j++) {
                long double x = a[i * n + j];
                a[i * n + j] = a[t * n + j];
                a[t * n + j] = x;
            }
            for (int j = 0; j < n; j++) {
                long double x = a[j * n + i];
                a[j * n + i] = a[j * n + t];
                a[j * n + t] = x;
            }
        }
        if (block == 1) {
            long double p = a[k * n + k];
            if (p > 0) ++*positive; else ++*negative;
            for (int i = k + 1; i < n; i++) {
                long double f = a[i * n + k] / p;
                for (int j = k + 1; j < n; j++) a[i * n + j] -= f * a[k * n + j];
            }
        } else {
            long double p = a[k * n + k], q = a[k * n + k + 1], r = a[(k + 1) * n + k + 1];
            long double det = p * r - q * q;
            if (det < 0) { ++*positive; ++*negative; }
            else if (p + r > 0) *positive += 2;
            else *negative += 2;
            for (int i = k + 2; i < n; i++) {
                long double x = a[i * n + k], y = a[i * n + k + 1];
                /* [x y] inv([[p q] [q r]]) */
                long double u = (r * x - q * y) / det, v = (p * y - q * x) / det;
                for (int j = k + 2; j < n; j++)
                    a[i * n + j] -= u * a[k * n + j] + v * a[(k + 1) * n + j];
            }
        }
        k += block;
    }
    return 0;
}

/* The signature of the knot from the diagram (Gordon and Litherland, On the
 * signature of a link, Invent. Math. 47, 1978, theorem 6 and corollary 6'):
 * the regions of the diagram coloured as a chessboard, G the Goeritz matrix
 * of the white regions (one dropped), sigma = sign(G) - mu, mu the sum of
 * eta(c) over the crossings of type II. Computed for both colourings, which
 * must agree. Half-edges at a crossing: 0 over-out, 1 under-out, 2 over-in,
 * 3 under-in; counterclockwise 0 1 2 3 when (over x under) > 0, else 0 3 2 1.
 * Corner j lies counterclockwise after the j-th half-edge of that order.
 * Returns 0, or -1 (a diagram the face tracing does not understand). */
static int signature(projection *pr, const passage *pass, int *sigma)
{
    int c = pr->crossings, edges = 2 * c;
    *sigma = 0;
    if (c == 0) return 0;
    rod_knot_scratch *sc = pr->scratch;
    int *leave = take(sc, (size_t)4 * c * sizeof *leave, 0);       /* dart leaving by a slot */
    int *dart_face = take(sc, (size_t)2 * edges * sizeof *dart_face, 0);
    int *corner = take(sc, (size_t)4 * c * sizeof *corner, 0);     /* face of each corner */
    int faces_max = c + 2;
    int *colour = take(sc, (size_t)faces_max * sizeof *colour, 0);
    int *row = take(sc, (size_t)faces_max * sizeof *row, 0);
    long double *g = take(sc, (size_t)faces_max * faces_max * sizeof *g, 0);
    if (!leave || !dart_face || !corner || !colour || !row || !g) return -1;
    static const int orders[2][4] = {{0, 1, 2, 3}, {0, 3, 2, 1}};
    /* dart 2k: edge k forward (pass k -> pass k+1); 2k + 1: backward */
    for (int k = 0; k < edges; k++) {
        const passage *from = &pass[k], *to = &pass[(k + 1) % edges];
        leave[4 * from->crossing + (from->under ? 1 : 0)] = 2 * k;
        leave[4 * to->crossing + (to->under ? 3 : 2)] = 2 * k + 1;
    }
    for (int d = 0; d < 2 * edges; d++) dart_face[d] = -1;
    int faces = 0;
    for (int start = 0; start < 2 * edges; start++) {
        if (dart_face[start] >= 0) continue;
        if (faces == faces_max) return -1; /* not a plane diagram */
        int d = start, steps = 0;
        do {
            dart_face[d] = faces;
            int k = d / 2;
            const passage *at = d % 2 ? &pass[k] : &pass[(k + 1) % edges];
            int v = at->crossing;
            int arrive = d % 2 ? (at->under ? 1 : 0) : (at->under ? 3 : 2);
            const int *order = orders[pr->x[v].sign > 0 ? 0 : 1];
            int i = 0;
            while (order[i] != arrive) i++;
            int turn = (i + 3) % 4; /* the next half-edge clockwise */
            corner[4 * v + turn] = faces;
            d = leave[4 * v + order[turn]];
        } while (d != start && ++steps <= 2 * edges);
        if (d != start) return -1;
        faces++;
    }
    if (faces != c + 2) return -1; /* Euler: V - E + F = 2 */
    /* chessboard: corners j and j + 1 of a crossing differ */
    for (int f = 0; f < faces; f++) colour[f] = -1;
    colour[corner[0]] = 0;
    for (int changed = 1; changed;) {
        changed = 0;
        for (int v = 0; v < c; v++)
            for (int j = 0; j < 4; j++) {
                int a = corner[4 * v + j], b = corner[4 * v + (j + 1) % 4];
                if (colour[a] >= 0 && colour[b] < 0) { colour[b] = 1 - colour[a]; changed = 1; }
                else if (colour[b] >= 0 && colour[a] < 0) { colour[a] = 1 - colour[b]; changed = 1; }
                else if (colour[a] >= 0 && colour[a] == colour[b]) return -1;
            }
    }
    int result[2];
    for (int white = 0; white < 2; white++) {
        int n = 0;
        for (int f = 0; f < faces; f++) row[f] = colour[f] == white ? n++ : -1;
        for (int k = 0; k < n * n; k++) g[k] = 0.0L;
        int mu = 0;
        for (int v = 0; v < c; v++) {
            int first = colour[corner[4 * v]] == white ? 0 : 1; /* white corners first, first+2 */
            /* eta = -1 when the white corners lie counterclockwise after the
             * over half-edges (corners 0 and 2), +1 otherwise: the sign that
             * gives the right-handed trefoil (writhe +3) sigma = -2, as
             * sign(V + V^T) of its Seifert matrix V does */
            int eta = first == 0 ? -1 : 1;
            /* type II: the white corners lie between an in and an out half-edge
             * (as at a kink between its loop and the region opposite, whose
             * contribution to sign(G) mu must cancel); the same-sense corners
             * (both out, both in) are 0, 2 when (over x under) > 0 */
            int same = pr->x[v].sign > 0 ? 0 : 1;
            if (first != same) mu += eta;
            int i = row[corner[4 * v + first]], j = row[corner[4 * v + first + 2]];
            if (i == j) continue;
            g[i * n + j] -= eta;
            g[j * n + i] -= eta;
            g[i * n + i] += eta;
            g[j * n + j] += eta;
        }
        /* drop the first white region: G is the trailing (n-1) x (n-1) block */
        int m = n - 1;
        for (int i = 0; i < m; i++)
            for (int j = 0; j < m; j++) g[i * m + j] = g[(i + 1) * n + j + 1];
        int positive, negative;
        if (m > 0 && inertia(g, m, &positive, &negative)) return -1;
        if (m <= 0) positive = negative = 0;
        result[white] = positive - negative - mu;
    }
    if (result[0] != result[1]) return -1;
    *sigma = result[0];
    return 0;
}

/* The 2c passages through the crossings, in order along the curve. Returns
 * 1 (and marks the projection degenerate) when two crossings fall at one
 * point of a segment: a triple point. */
static int order_passages(projection *pr, passage *pass)
{
    int c = pr->crossings;
    for (int k = 0; k < c; k++)
        for (int s = 0; s < 2; s++)
            pass[2 * k + s] = (passage){pr->x[k].seg[s], k, pr->x[k].over != s, pr->x[k].t[s]};
    qsort(pass, (size_t)(2 * c), sizeof *pass, passage_order);
    for (int k = 0; k + 1 < 2 * c; k++)
        if (pass[k].seg == pass[k + 1].seg && pass[k + 1].t - pass[k].t < KNOT_PARAM_TOL) {
            pr->degenerate = 1;
            return 1;
        }
    return 0;
}

/* Arc k runs from the k-th undercrossing along the curve to the next: at
 * each crossing, the arc over it and the arcs in and out under it. */
static void label_arcs(const passage *pass, int c, int *arc_over, int *arc_in, int *arc_out)
{
    int unders = 0;
    for (int k = 0; k < 2 * c; k++) {
        const passage *q = &pass[k];
        if (q->under) {
            arc_in[q->crossing] = (unders - 1 + c) % c;
            arc_out[q->crossing] = unders;
            unders++;
        } else {
            arc_over[q->crossing] = (unders - 1 + c) % c;
        }
    }
}

/* The Alexander matrix A + t B (zeroed, m x m), its last row and column dropped. */
static void alexander_matrix(const projection *pr, const int *arc_over, const int *arc_in,
                             const int *arc_out, int m, long long *A, long long *B)
{
    int c = pr->crossings;
    for (int x = 0; x + 1 < c; x++) {
        int col[3] = {arc_over[x], arc_in[x], arc_out[x]};
        long long a[3] = {1, 0, -1}, b[3] = {-1, 1, 0};
        if (pr->x[x].sign < 0) {
            a[1] = -1; b[1] = 0;
            a[2] = 0; b[2] = 1;
        }
        for (int e = 0; e < 3; e++) {
            if (col[e] == c - 1) continue;
            A[(size_t)x * m + col[e]] += a[e];
            B[(size_t)x * m + col[e]] += b[e];
        }
    }
}

/* The coefficients value[0..m] from the two residues: each in (-p/2, p/2);
 * both primes must agree. 0, or -1 with a message. */
static int lift_coefficients(uint64_t *const poly[2], int m, int c, long long *value, char *err,
                             size_t errlen)
{
    for (int d = 0; d <= m; d++) {
        long long v[2];
        for (int q = 0; q < 2; q++) {
            uint64_t p = knot_primes[q];
            v[q] = poly[q][d] > p / 2 ? (long long)poly[q][d] - (long long)p : (long long)poly[q][d];
        }
        if (v[0] != v[1]) {
            snprintf(err, errlen, "the Alexander polynomial of %d crossings has a coefficient "
                     "beyond 5e8", c);
            return -1;
        }
        value[d] = v[0];
    }
    return 0;
}

/* Delta normalised into out (terms, coefficients, determinant) after the
 * checks a knot's polynomial passes: |Delta(1)| = 1, symmetric. Returns its
 * number of terms (degree + 1, before the ROD_KNOT_MAX_TERMS cap), or -1
 * with a message. */
static int normalise_polynomial(const long long *value, int m, int c, rod_knot *out, char *err,
                                size_t errlen)
{
    int lo = 0, hi = m;
    while (lo <= m && value[lo] == 0) lo++;
    while (hi >= 0 && value[hi] == 0) hi--;
    long long sum = 0;
    for (int d = lo; d <= hi; d++) sum += value[d];
    if (lo > hi || (sum != 1 && sum != -1)) {
        snprintf(err, errlen, "the Alexander polynomial of %d crossings has |Delta(1)| = %lld, "
                 "not 1: not a knot diagram", c, sum < 0 ? -sum : sum);
        return -1;
    }
    long long sign = value[lo] < 0 ? -1 : 1;
    for (int d = lo; d <= hi; d++)
        if (value[d] != value[hi - (d - lo)]) {
            snprintf(err, errlen, "the Alexander polynomial of %d crossings is not symmetric",
                     c);
            return -1;
        }
    int terms = hi - lo + 1;
    long long det = 0, alt = 1;
    for (int d = lo; d <= hi; d++, alt = -alt) det += alt * sign * value[d];
    out->determinant = det < 0 ? -det : det;
    out->terms = terms < ROD_KNOT_MAX_TERMS ? terms : ROD_KNOT_MAX_TERMS;
    for (int d = 0; d < out->terms; d++) out->coefficient[d] = sign * value[lo + d];
    return terms;
}

/* out->name from the table of known knots (the signature telling apart those
 * that share a polynomial, and its sign giving a chiral knot's hand: ",
 * right-handed" or ", left-handed" after the name), else "unknown (...)";
 * terms: of the whole Delta. */
static void name_knot(rod_knot *out, int terms)
{
    snprintf(out->name, sizeof out->name, "unknown (degree %d)", terms - 1);
    /* unnamed: a lower bound (a diagram of n crossings has Delta of degree
     * at most n - 1, its Alexander matrix being n - 1 square, linear in t) */
    out->crossing_number = terms;
    int named = 0;
    for (size_t k = 0; k < sizeof known_knots / sizeof known_knots[0] && !named; k++) {
        if (known_knots[k].terms != terms) continue;
        named = memcmp(known_knots[k].c, out->coefficient, (size_t)terms * sizeof(long long)) == 0;
        if (!named) continue;
        const char *name = known_knots[k].name;
        for (int v = 0; v < 2; v++) {
            const signed_name *sn = &known_knots[k].by_signature[v];
            if (sn->name && out->has_signature && abs(out->signature) == sn->abs_signature)
                name = sn->name;
        }
        /* a chiral knot's hand from its signature's sign, as Rolfsen's table:
         * negative for the right-handed trefoil (positive crossings), so the
         * hand of a composite is that of its dominant part (the surgeon's
         * knot's double throw) */
        const char *hand = !out->has_signature || out->signature == 0 ? ""
                           : out->signature < 0                       ? ", right-handed"
                                                                      : ", left-handed";
        snprintf(out->name, sizeof out->name, "%s%s", name, hand);
        out->crossing_number = known_knots[k].crossing_number;
    }
    if (!named && terms <= ROD_KNOT_MAX_TERMS) {
        char text[72];
        rod_knot_polynomial_text(out, text, sizeof text);
        snprintf(out->name, sizeof out->name, "unknown (Delta = %s)", text);
    }
}

/* Delta from the crossings; 0, 1 (a triple point: the projection is
 * degenerate), or -1 with a message. */
static int alexander(projection *pr, rod_knot *out, char *err, size_t errlen)
{
    int c = pr->crossings;
    rod_knot_scratch *sc = pr->scratch;
    passage *pass = take(sc, (size_t)(2 * c + 1) * sizeof *pass, 0);
    int *arc_over = take(sc, (size_t)(c + 1) * sizeof *arc_over, 0);
    int *arc_in = take(sc, (size_t)(c + 1) * sizeof *arc_in, 0);
    int *arc_out = take(sc, (size_t)(c + 1) * sizeof *arc_out, 0);
    int m = c > 0 ? c - 1 : 0;
    long long *A = take(sc, ((size_t)m * m + 1) * sizeof *A, 1);
    long long *B = take(sc, ((size_t)m * m + 1) * sizeof *B, 1);
    uint64_t *poly[2] = {take(sc, (size_t)(m + 1) * sizeof(uint64_t), 0),
                         take(sc, (size_t)(m + 1) * sizeof(uint64_t), 0)};
    long long *value = take(sc, (size_t)(m + 1) * sizeof *value, 0);
    if (!pass || !arc_over || !arc_in || !arc_out || !A || !B || !poly[0] || !poly[1] || !value) {
        snprintf(err, errlen, "out of memory for %d crossings", c);
        return -1;
    }
    if (order_passages(pr, pass)) return 1;
    label_arcs(pass, c, arc_over, arc_in, arc_out);
    scratch_mark mark = scratch_save(sc);
    int sigma;
    out->has_signature = signature(pr, pass, &sigma) == 0;
    out->signature = out->has_signature ? sigma : 0;
    scratch_restore(sc, mark);
    alexander_matrix(pr, arc_over, arc_in, arc_out, m, A, B);
    for (int q = 0; q < 2; q++)
        if (det_polynomial_mod(sc, A, B, m, knot_primes[q], poly[q])) {
            snprintf(err, errlen, "the Alexander matrix of %d crossings is singular at every "
                     "shift tried (not a knot diagram?)", c);
            return -1;
        }
    if (lift_coefficients(poly, m, c, value, err, errlen)) return -1;
    int terms = normalise_polynomial(value, m, c, out, err, errlen);
    if (terms < 0) return -1;
    out->crossings = c;
    out->writhe = 0;
    for (int x = 0; x < c; x++) out->writhe += pr->x[x].sign;
    name_knot(out, terms);
    return 0; /* the scratch is released by the caller, per projection */
}

/* The closed polygon (count x 3) and how many of its first segments are the
 * curve's own; NULL out of memory. */
static double *close_polygon(rod_knot_scratch *sc, const double *p, int nodes, int closed,
                             int closure, const double centre[3], double extent, int *count,
                             int *own)
{
    if (closed) {
        double *q = take(sc, (size_t)nodes * 3 * sizeof *q, 0);
        if (q) memcpy(q, p, (size_t)nodes * 3 * sizeof *q);
        *count = nodes;
        *own = nodes;
        return q;
    }
    double R = KNOT_CLOSURE_RADIUS * extent, dir[2][3];
    for (int e = 0; e < 2; e++) {
        const double *end = &p[3 * (e ? nodes - 1 : 0)], *next = &p[3 * (e ? nodes - 2 : 1)];
        /* out of the end: from the centroid (radial), along the end's own
         * segment (tangent), or away from the other end (apart) */
        const double *from = closure == ROD_KNOT_CLOSE_TANGENT ? next
                             : closure == ROD_KNOT_CLOSE_APART ? &p[3 * (e ? 0 : nodes - 1)]
                                                                : centre;
        double d[3], len = 0.0;
        for (int k = 0; k < 3; k++) {
            d[k] = end[k] - from[k];
            len += d[k] * d[k];
        }
        if (sqrt(len) <= 1e-9 * extent) { /* the end at the centroid: along its tangent */
            len = 0.0;
            for (int k = 0; k < 3; k++) {
                d[k] = end[k] - next[k];
                len += d[k] * d[k];
            }
        }
        for (int k = 0; k < 3; k++) dir[e][k] = d[k] / sqrt(len);
    }
    /* from the tip's direction dir[1] over the sphere to the root's dir[0] */
    double cosang = dir[0][0] * dir[1][0] + dir[0][1] * dir[1][1] + dir[0][2] * dir[1][2];
    double via[3];
    int antipodal = cosang < -0.99;
    if (antipodal) { /* through a direction perpendicular to both */
        int axis = fabs(dir[1][0]) < 0.6 ? 0 : fabs(dir[1][1]) < 0.6 ? 1 : 2;
        double e[3] = {0, 0, 0}, dot;
        e[axis] = 1.0;
        dot = e[0] * dir[1][0] + e[1] * dir[1][1] + e[2] * dir[1][2];
        double len = 0.0;
        for (int k = 0; k < 3; k++) {
            via[k] = e[k] - dot * dir[1][k];
            len += via[k] * via[k];
        }
        for (int k = 0; k < 3; k++) via[k] /= sqrt(len);
    }
    const double *legs[3][2] = {{dir[1], antipodal ? via : dir[0]}, {via, dir[0]}, {0, 0}};
    int leg_count = antipodal ? 2 : 1, steps[2], extra = 0;
    for (int l = 0; l < leg_count; l++) {
        const double *a = legs[l][0], *b = legs[l][1];
        double c = fmax(-1.0, fmin(1.0, a[0] * b[0] + a[1] * b[1] + a[2] * b[2]));
        steps[l] = (int)ceil(acos(c) / KNOT_ARC_STEP);
        if (steps[l] < 1) steps[l] = 1;
        extra += steps[l];
    }
    /* tip on the sphere, the arc's inner points, root on the sphere */
    *count = nodes + extra + 1;
    *own = nodes - 1;
    double *q = take(sc, (size_t)*count * 3 * sizeof *q, 0);
    if (!q) return NULL;
    memcpy(q, p, (size_t)nodes * 3 * sizeof *q);
    int at = nodes;
    for (int l = 0; l < leg_count; l++) {
        const double *a = legs[l][0], *b = legs[l][1];
        double c = fmax(-1.0, fmin(1.0, a[0] * b[0] + a[1] * b[1] + a[2] * b[2]));
        double angle = acos(c), s = sin(angle);
        for (int k = 0; k < steps[l]; k++) { /* k = 0: the leg's start */
            double f = (double)k / steps[l], wa, wb;
            if (s < 1e-12) { wa = 1.0 - f; wb = f; }
            else { wa = sin((1.0 - f) * angle) / s; wb = sin(f * angle) / s; }
            double u[3], len = 0.0;
            for (int j = 0; j < 3; j++) {
                u[j] = wa * a[j] + wb * b[j];
                len += u[j] * u[j];
            }
            for (int j = 0; j < 3; j++) q[3 * at + j] = centre[j] + R * u[j] / sqrt(len);
            at++;
        }
    }
    if (cosang < 1.0 - 1e-12) { /* else the tip's point on the sphere is the root's too */
        for (int j = 0; j < 3; j++) q[3 * at + j] = centre[j] + R * dir[0][j];
        at++;
    }
    *count = at;
    return q;
}

static int identify(rod_knot_scratch *sc, const double *points, int nodes, int closed,
                    int closure, const int *short_ranges, rod_knot *out, char *err,
                    size_t errlen)
{
    memset(out, 0, sizeof *out);
    if (!points || nodes < (closed ? 3 : 2) || nodes > ROD_KNOT_MAX_POINTS) {
        snprintf(err, errlen, "a knot needs %d to %d points, not %d", closed ? 3 : 2,
                 ROD_KNOT_MAX_POINTS, nodes);
        return -1;
    }
    double centre[3] = {0, 0, 0}, extent = 0.0;
    for (int i = 0; i < nodes; i++)
        for (int k = 0; k < 3; k++) {
            if (!isfinite(points[3 * i + k])) {
                snprintf(err, errlen, "point %d is not finite", i + 1);
                return -1;
            }
            centre[k] += points[3 * i + k] / nodes;
        }
    for (int i = 0; i < nodes; i++) {
        double d[3] = {points[3 * i] - centre[0], points[3 * i + 1] - centre[1],
                       points[3 * i + 2] - centre[2]};
        extent = fmax(extent, sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
    }
    if (!(extent > 0.0)) {
        snprintf(err, errlen, "all %d points coincide", nodes);
        return -1;
    }
    projection pr = {0};
    pr.extent = extent;
    pr.scratch = sc;
    double *q = close_polygon(sc, points, nodes, closed, closure, centre, extent, &pr.count,
                              &pr.knot_segments);
    if (short_ranges) { /* a closed polygon whose joins are long */
        pr.knot_segments = short_ranges[1];
        pr.mid_lo = short_ranges[2];
        pr.mid_hi = short_ranges[3];
    }
    pr.p = q;
    pr.xy = q ? take(sc, (size_t)pr.count * 2 * sizeof *pr.xy, 0) : NULL;
    pr.z = q ? take(sc, (size_t)pr.count * sizeof *pr.z, 0) : NULL;
    scratch_mark per_projection = scratch_save(sc);
    int rc = -1, fewest = -1, intersecting = 0, meet[2] = {0, 0};
    if (!q || !pr.xy || !pr.z) {
        snprintf(err, errlen, "out of memory for %d points", nodes);
        goto done;
    }
    for (int attempt = 0; attempt < KNOT_TRIES; attempt++) {
        double w[3], e1[3], e2[3];
        direction_of_try(attempt, w);
        /* e1 = w x (the axis least along w), e2 = w x e1: a right-handed frame */
        int axis = fabs(w[0]) < fabs(w[1]) ? (fabs(w[0]) < fabs(w[2]) ? 0 : 2)
                                           : (fabs(w[1]) < fabs(w[2]) ? 1 : 2);
        double a[3] = {0, 0, 0};
        a[axis] = 1.0;
        e1[0] = w[1] * a[2] - w[2] * a[1];
        e1[1] = w[2] * a[0] - w[0] * a[2];
        e1[2] = w[0] * a[1] - w[1] * a[0];
        double l = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
        for (int k = 0; k < 3; k++) e1[k] /= l;
        e2[0] = w[1] * e1[2] - w[2] * e1[1];
        e2[1] = w[2] * e1[0] - w[0] * e1[2];
        e2[2] = w[0] * e1[1] - w[1] * e1[0];
        for (int i = 0; i < pr.count; i++) {
            const double *r = &q[3 * i];
            double d[3] = {r[0] - centre[0], r[1] - centre[1], r[2] - centre[2]};
            pr.xy[2 * i] = d[0] * e1[0] + d[1] * e1[1] + d[2] * e1[2];
            pr.xy[2 * i + 1] = d[0] * e2[0] + d[1] * e2[1] + d[2] * e2[2];
            pr.z[i] = d[0] * w[0] + d[1] * w[1] + d[2] * w[2];
        }
        scratch_restore(sc, per_projection); /* the last projection's crossings and matrix */
        pr.x = NULL;
        pr.capacity = 0;
        pr.crossings = 0;
        pr.degenerate = 0;
        pr.intersecting = 0;
        pr.tests = 0;
        if (find_crossings(&pr)) {
            snprintf(err, errlen, "out of memory for the crossings of %d points", nodes);
            goto done;
        }
        if (pr.intersecting) {
            intersecting++;
            meet[0] = pr.meet[0];
            meet[1] = pr.meet[1];
        }
        if (pr.degenerate) continue;
        if (pr.crossings > ROD_KNOT_MAX_CROSSINGS || pr.tests > KNOT_MAX_TESTS) {
            if (fewest < 0 || pr.crossings < fewest) fewest = pr.crossings;
            continue;
        }
        int got = alexander(&pr, out, err, errlen);
        if (got == 1) continue; /* a triple point */
        if (got == 0) {
            memcpy(out->direction, w, sizeof w);
            out->tries = attempt + 1;
        }
        rc = got;
        goto done;
    }
    if (intersecting > KNOT_TRIES / 2) {
        int count = closed ? nodes : nodes - 1;
        snprintf(err, errlen, "the polygon passes through itself: segments %d and %d meet%s",
                 meet[0] + 1, meet[1] + 1,
                 meet[0] >= count || meet[1] >= count ? " (one of them the closure's)" : "");
    } else if (fewest >= 0) {
        snprintf(err, errlen, "more than %d crossings (or segment pairs to test) in every one "
                 "of %d projections: too tangled to identify in bounded time",
                 ROD_KNOT_MAX_CROSSINGS, KNOT_TRIES);
    } else {
        snprintf(err, errlen, "no generic projection among %d directions (a vertex on another "
                 "segment, or overlapping segments, in every one)", KNOT_TRIES);
    }
done:
    scratch_end(sc);
    return rc;
}

int rod_knot_identify_in(rod_knot_scratch *scratch, const double *points, int nodes, int closed,
                         rod_knot *out, char *err, size_t errlen)
{
    if (scratch)
        return identify(scratch, points, nodes, closed, ROD_KNOT_CLOSE_RADIAL, NULL, out, err,
                        errlen);
    rod_knot_scratch *own = rod_knot_scratch_create();
    if (!own) {
        memset(out, 0, sizeof *out);
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    int rc = identify(own, points, nodes, closed, ROD_KNOT_CLOSE_RADIAL, NULL, out, err, errlen);
    rod_knot_scratch_destroy(own);
    return rc;
}

int rod_knot_identify_joined(rod_knot_scratch *scratch, const double *points, int count,
                             const int short_ranges[4], rod_knot *out, char *err, size_t errlen)
{
    if (short_ranges[0] != 0 || short_ranges[1] < 0 || short_ranges[2] < short_ranges[1] ||
        short_ranges[3] < short_ranges[2] || short_ranges[3] > count) {
        memset(out, 0, sizeof *out);
        snprintf(err, errlen, "the short segments [%d, %d) and [%d, %d) are not in order",
                 short_ranges[0], short_ranges[1], short_ranges[2], short_ranges[3]);
        return -1;
    }
    if (scratch)
        return identify(scratch, points, count, 1, ROD_KNOT_CLOSE_RADIAL, short_ranges, out, err,
                        errlen);
    rod_knot_scratch *own = rod_knot_scratch_create();
    if (!own) {
        memset(out, 0, sizeof *out);
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    int rc = identify(own, points, count, 1, ROD_KNOT_CLOSE_RADIAL, short_ranges, out, err, errlen);
    rod_knot_scratch_destroy(own);
    return rc;
}

int rod_knot_identify(const double *points, int nodes, rod_knot *out, char *err, size_t errlen)
{
    return rod_knot_identify_in(NULL, points, nodes, 0, out, err, errlen);
}

int rod_knot_identify_closed(const double *points, int nodes, rod_knot *out, char *err,
                             size_t errlen)
{
    return rod_knot_identify_in(NULL, points, nodes, 1, out, err, errlen);
}

int rod_knot_identify_closure(rod_knot_scratch *scratch, const double *points, int nodes,
                              int closure, rod_knot *out, char *err, size_t errlen)
{
    if (scratch) return identify(scratch, points, nodes, 0, closure, NULL, out, err, errlen);
    rod_knot_scratch *own = rod_knot_scratch_create();
    if (!own) {
        memset(out, 0, sizeof *out);
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    int rc = identify(own, points, nodes, 0, closure, NULL, out, err, errlen);
    rod_knot_scratch_destroy(own);
    return rc;
}
