/* edge_aa.c: FXAA over the boxes of a frame (see edge_aa.h). The names
 * follow the white paper: luma at the pixel (m) and its neighbours (n s w e,
 * n up), the edge's local contrast (range), the steps along it. */
#include "render/edge_aa.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* luma (0..255) below which a contrast is not an edge, and the fraction of
 * the brightest luma around a pixel a contrast must reach (FXAA 3.11's
 * defaults: 0.0833 and 0.166 of 1): the shading across a tube's facets stays
 * below them, a silhouette or the stripe's edge is far above */
#define EDGE_MIN 21.0f
#define EDGE_RELATIVE 0.166f
/* a neighbour must differ this much for a range of EDGE_MIN (half of it) */
#define CANDIDATE_MIN 11
/* how much of the sub-pixel blend is kept (FXAA's default 0.75) */
#define SUBPIXEL_QUALITY 0.75f

/* the steps along an edge, pixels (their sum is EDGE_AA_REACH) */
static const int edge_steps[] = {1, 1, 1, 1, 1, 2, 2, 2, 2, 4};
#define EDGE_STEP_COUNT ((int)(sizeof edge_steps / sizeof edge_steps[0]))

struct edge_aa {
    int width, height;
    unsigned char *backdrop_luma; /* (height x width) */
    unsigned char *luma;          /* (height x width): the frame's, the backdrop's outside boxes */
    int (*last)[4];               /* the last frame's boxes, whose luma is restored */
    int last_count, max_boxes;
    unsigned char *rows;          /* (2 x width x 3): the rows above and at the pixel, as drawn */
    unsigned char *candidate;     /* (width): pixels of a row that may be on an edge */
};

/* The "luma" edges are found in: (R + 2G + B) / 4 of the sRGB bytes. Not
 * Rec. 601's weights: with blue at 0.11 the amber stripe and the grey
 * background are nearly the same luma, and the stripe seen edge-on kept
 * its steps; green alone (FXAA's cheaper option) flattens a red arrow's
 * shading until its facets read as edges. */
static void luma_rows(const image *img, unsigned char *luma, int x, int y, int w, int h)
{
    for (int row = y; row < y + h; row++) {
        const unsigned char *p = img->rgb + ((size_t)row * (size_t)img->width + (size_t)x) * 3;
        unsigned char *l = luma + (size_t)row * (size_t)img->width + (size_t)x;
        for (int k = 0; k < w; k++, p += 3)
            l[k] = (unsigned char)((p[0] + 2u * p[1] + p[2] + 2u) >> 2);
    }
}

edge_aa *edge_aa_create(const image *backdrop, int max_boxes)
{
    edge_aa *a = calloc(1, sizeof *a);
    if (!a) return NULL;
    size_t pixels = (size_t)backdrop->width * (size_t)backdrop->height;
    a->width = backdrop->width;
    a->height = backdrop->height;
    a->max_boxes = max_boxes > 1 ? max_boxes : 1;
    a->backdrop_luma = malloc(pixels);
    a->luma = malloc(pixels);
    a->last = malloc((size_t)a->max_boxes * sizeof *a->last);
    a->rows = malloc((size_t)backdrop->width * 6);
    a->candidate = malloc((size_t)backdrop->width);
    if (!a->backdrop_luma || !a->luma || !a->last || !a->rows || !a->candidate) {
        edge_aa_destroy(a);
        return NULL;
    }
    luma_rows(backdrop, a->backdrop_luma, 0, 0, a->width, a->height);
    memcpy(a->luma, a->backdrop_luma, pixels);
    return a;
}

void edge_aa_destroy(edge_aa *a)
{
    if (!a) return;
    free(a->backdrop_luma);
    free(a->luma);
    free(a->last);
    free(a->rows);
    free(a->candidate);
    free(a);
}

/* luma at (x, y), clamped to the picture (its edge repeats) */
static float luma_at(const edge_aa *a, int x, int y)
{
    x = x < 0 ? 0 : x >= a->width ? a->width - 1 : x;
    y = y < 0 ? 0 : y >= a->height ? a->height - 1 : y;
    return a->luma[(size_t)y * (size_t)a->width + (size_t)x];
}

static float larger(float p, float q) { return p > q ? p : q; }
static float smaller(float p, float q) { return p < q ? p : q; }

/* The fraction (0 .. 0.5 from the edge, up to 0.75 sub-pixel) of the
 * neighbour across the edge that pixel (x, y) takes, and which neighbour
 * (*dx, *dy); 0 when the pixel is on no edge. */
static float blend_fraction(const edge_aa *a, int x, int y, int *dx, int *dy)
{
    float m = luma_at(a, x, y), n = luma_at(a, x, y - 1), s = luma_at(a, x, y + 1);
    float w = luma_at(a, x - 1, y), e = luma_at(a, x + 1, y);
    float hi = larger(larger(larger(n, s), larger(w, e)), m);
    float lo = smaller(smaller(smaller(n, s), smaller(w, e)), m), range = hi - lo;
    if (range < larger(EDGE_MIN, hi * EDGE_RELATIVE)) return 0;
    float nw = luma_at(a, x - 1, y - 1), ne = luma_at(a, x + 1, y - 1);
    float sw = luma_at(a, x - 1, y + 1), se = luma_at(a, x + 1, y + 1);
    /* second differences across: a horizontal edge changes along y */
    float across_y = fabsf(nw + sw - 2 * w) + 2 * fabsf(n + s - 2 * m) + fabsf(ne + se - 2 * e);
    float across_x = fabsf(nw + ne - 2 * n) + 2 * fabsf(w + e - 2 * m) + fabsf(sw + se - 2 * s);
    int horizontal = across_y >= across_x;
    /* the side of the steeper change: -1 (up or left) or +1 */
    float before = horizontal ? n : w, after = horizontal ? s : e;
    int side = fabsf(before - m) >= fabsf(after - m) ? -1 : 1;
    float gradient = 0.25f * larger(fabsf(before - m), fabsf(after - m));
    float local = 0.5f * ((side < 0 ? before : after) + m);
    *dx = horizontal ? 0 : side;
    *dy = horizontal ? side : 0;
    /* follow the edge both ways, half a pixel towards that side, until the
     * luma there leaves the edge's average by a quarter of the gradient */
    int along_x = horizontal, along_y = !horizontal;
    float end[2] = {0, 0};
    int distance[2] = {0, 0}, done[2] = {0, 0};
    for (int k = 0; k < EDGE_STEP_COUNT && !(done[0] && done[1]); k++)
        for (int way = 0; way < 2; way++) {
            if (done[way]) continue;
            distance[way] += edge_steps[k];
            int d = way ? distance[way] : -distance[way];
            int px = x + d * along_x, py = y + d * along_y;
            end[way] = 0.5f * (luma_at(a, px, py) + luma_at(a, px + *dx, py + *dy)) - local;
            done[way] = fabsf(end[way]) >= gradient;
        }
    /* the nearer end decides: the pixel is blended when the luma there varies
     * the other way than the centre does from the average */
    int nearer = distance[0] < distance[1] ? 0 : 1;
    float offset = 0.5f - (float)distance[nearer] / (float)(distance[0] + distance[1]);
    if ((end[nearer] < 0) == (m < local)) offset = 0;
    /* sub-pixel: a pixel unlike the average of its 3x3 (a thin line) */
    float average = (2 * (n + s + w + e) + nw + ne + sw + se) / 12;
    float sub = smaller(fabsf(average - m) / range, 1.0f);
    sub = (-2 * sub + 3) * sub * sub;
    return larger(offset, sub * sub * SUBPIXEL_QUALITY);
}

static unsigned char difference(unsigned char p, unsigned char q) { return p > q ? p - q : q - p; }

/* Marks in candidate[] (bytes, 1: look closer) the pixels x0 .. x1 - 1 of
 * row y (not at the picture's edge) that may be on an edge: some
 * neighbour's luma differs from theirs by CANDIDATE_MIN or more, and something was drawn there or beside (the
 * backdrop's own edges, its grid lines antialiased once, are left as they
 * are). A loop the compiler vectorises: most pixels stop here. */
static void candidates(const edge_aa *a, int y, int x0, int x1, unsigned char *candidate)
{
    int width = a->width;
    const unsigned char *l = a->luma + (size_t)y * (size_t)width;
    const unsigned char *b = a->backdrop_luma + (size_t)y * (size_t)width;
    for (int x = x0; x < x1; x++) {
        unsigned char d = difference(l[x], l[x - 1]), e = difference(l[x], l[x + 1]);
        unsigned char f = difference(l[x], l[x - width]), g = difference(l[x], l[x + width]);
        d = d > e ? d : e;
        f = f > g ? f : g;
        d = d > f ? d : f;
        unsigned char drawn = (l[x] != b[x]) | (l[x - 1] != b[x - 1]) | (l[x + 1] != b[x + 1]) |
                              (l[x - width] != b[x - width]) | (l[x + width] != b[x + width]);
        candidate[x] = (unsigned char)((d >= CANDIDATE_MIN) & drawn);
    }
}

/* Something drawn at or beside (x, y) (the picture's edge repeats). */
static int drawn_near(const edge_aa *a, int x, int y)
{
    static const int offsets[5][2] = {{0, 0}, {-1, 0}, {1, 0}, {0, -1}, {0, 1}};
    for (int k = 0; k < 5; k++) {
        int px = x + offsets[k][0], py = y + offsets[k][1];
        px = px < 0 ? 0 : px >= a->width ? a->width - 1 : px;
        py = py < 0 ? 0 : py >= a->height ? a->height - 1 : py;
        size_t at = (size_t)py * (size_t)a->width + (size_t)px;
        if (a->luma[at] != a->backdrop_luma[at]) return 1;
    }
    return 0;
}

void edge_aa_frame(edge_aa *a, image *img, const int (*boxes)[4], int count)
{
    int width = a->width, height = a->height;
    if (img->width != width || img->height != height) return;
    /* the luma: the backdrop's where the last frame drew, this frame's in its boxes */
    for (int b = 0; b < a->last_count; b++)
        for (int y = a->last[b][1]; y < a->last[b][1] + a->last[b][3]; y++) {
            size_t at = (size_t)y * (size_t)width + (size_t)a->last[b][0];
            memcpy(a->luma + at, a->backdrop_luma + at, (size_t)a->last[b][2]);
        }
    a->last_count = 0;
    for (int b = 0; b < count; b++) {
        int x = boxes[b][0], y = boxes[b][1], w = boxes[b][2], h = boxes[b][3];
        if (x < 0 || y < 0 || w <= 0 || h <= 0 || x + w > width || y + h > height) continue;
        luma_rows(img, a->luma, x, y, w, h);
        if (a->last_count < a->max_boxes) memcpy(a->last[a->last_count++], boxes[b], sizeof *a->last);
    }
    /* top down (renderer.c lists its boxes bottom up): each pixel blends with a
     * neighbour as drawn; the rows above and at it are kept before they change,
     * the ones below and to the right are not yet. Only above a box's first
     * row may a neighbour be smoothed already (a box above it): a blend of a
     * blend, at most half a pixel's difference, along a tile's edge. */
    for (int b = a->last_count - 1; b >= 0; b--) {
        int bx = a->last[b][0], by = a->last[b][1], bw = a->last[b][2], bh = a->last[b][3];
        unsigned char *saved[2] = {a->rows, a->rows + (size_t)width * 3};
        int next = 0;
        /* pixel x of the row above as drawn is above[3 x]: the picture's row
         * while nothing in it changed, else the copy made before it did */
        const unsigned char *above = by > 0 ? img->rgb + (size_t)(by - 1) * (size_t)width * 3 : NULL;
        for (int y = by; y < by + bh; y++) {
            unsigned char *row = img->rgb + (size_t)y * (size_t)width * 3;
            /* the picture's edge rows and columns: looked at one by one */
            unsigned char *candidate = a->candidate;
            int inner0 = bx > 0 ? bx : 1, inner1 = bx + bw < width ? bx + bw : width - 1;
            if (y == 0 || y == height - 1)
                for (int x = bx; x < bx + bw; x++) candidate[x] = (unsigned char)drawn_near(a, x, y);
            else {
                candidates(a, y, inner0, inner1, candidate);
                if (bx == 0) candidate[0] = (unsigned char)drawn_near(a, 0, y);
                if (bx + bw == width) candidate[width - 1] = (unsigned char)drawn_near(a, width - 1, y);
            }
            unsigned char *here = NULL;
            for (int x = bx; x < bx + bw; x++) {
                /* eight at a time over the flat stretches */
                while (x + 8 <= bx + bw) {
                    unsigned long long eight;
                    memcpy(&eight, candidate + x, 8);
                    if (eight) break;
                    x += 8;
                }
                if (x >= bx + bw) break;
                if (!candidate[x]) continue;
                int dx = 0, dy = 0;
                float f = blend_fraction(a, x, y, &dx, &dy);
                int qx = x + dx, qy = y + dy;
                if (!(f > 0) || qx < 0 || qx >= width || qy < 0 || qy >= height) continue;
                if (!here) { /* the row as drawn, before its first change */
                    here = saved[next];
                    next ^= 1;
                    memcpy(here + (size_t)bx * 3, row + (size_t)bx * 3, (size_t)bw * 3);
                }
                const unsigned char *p = here + (size_t)x * 3, *q;
                if (dy < 0) q = above + (size_t)qx * 3;
                else if (dy == 0 && dx < 0 && qx >= bx) q = here + (size_t)qx * 3;
                else q = img->rgb + ((size_t)qy * width + qx) * 3;
                for (int c = 0; c < 3; c++)
                    row[3 * x + c] = (unsigned char)(p[c] + f * ((float)q[c] - p[c]) + 0.5f);
            }
            above = here ? here : row;
        }
    }
}
