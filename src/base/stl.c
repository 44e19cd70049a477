/* stl.c: STL files, ASCII and binary, read into triangles (stl.h). */
#include "base/stl.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* 1: the triangle's area is below 1e-12 of its longest edge squared (a
 * needle or a point: no normal to touch it by). */
static int degenerate(const double *v)
{
    double e[3][3], longest = 0.0;
    for (int k = 0; k < 3; k++) {
        const double *a = &v[3 * k], *b = &v[3 * ((k + 1) % 3)];
        double len = 0.0;
        for (int c = 0; c < 3; c++) {
            e[k][c] = b[c] - a[c];
            len += e[k][c] * e[k][c];
        }
        if (len > longest) longest = len;
    }
    double cx = e[0][1] * e[1][2] - e[0][2] * e[1][1];
    double cy = e[0][2] * e[1][0] - e[0][0] * e[1][2];
    double cz = e[0][0] * e[1][1] - e[0][1] * e[1][0];
    return !(sqrt(cx * cx + cy * cy + cz * cz) > 1e-12 * longest);
}

/* ---- ASCII ---- */

/* The blanks between words (as isspace in the C locale). */
static int is_blank(unsigned char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
}

typedef struct ascii_reader {
    const char *name;
    const unsigned char *p, *end;
    int line, last_line; /* the line now; the line of the last word read */
    char token[64];
    char *err;
    size_t errlen;
} ascii_reader;

/* The next blank-separated word into r->token (truncated to 63 bytes); 0
 * at the end of the data. r->line is the word's line. */
static int next_token(ascii_reader *r)
{
    while (r->p < r->end && is_blank(*r->p)) {
        if (*r->p == '\n') r->line++;
        r->p++;
    }
    if (r->p >= r->end) return 0;
    size_t n = 0;
    while (r->p < r->end && !is_blank(*r->p)) {
        if (n + 1 < sizeof r->token) r->token[n++] = (char)(*r->p == '\0' ? '?' : *r->p);
        r->p++;
    }
    r->token[n] = '\0';
    r->last_line = r->line;
    return 1;
}

static int expect(ascii_reader *r, const char *word)
{
    if (!next_token(r)) {
        snprintf(r->err, r->errlen, "%s:%d: the file ends where '%s' was expected (an ASCII STL "
                 "facet: facet normal nx ny nz / outer loop / vertex x y z (3 times) / endloop / "
                 "endfacet; the file ends with endsolid)", r->name, r->last_line, word);
        return -1;
    }
    if (strcmp(r->token, word) != 0) {
        snprintf(r->err, r->errlen, "%s:%d: '%s' where '%s' was expected (an ASCII STL facet: "
                 "facet normal nx ny nz / outer loop / vertex x y z (3 times) / endloop / "
                 "endfacet)", r->name, r->line, r->token, word);
        return -1;
    }
    return 0;
}

/* A number; `finite` 1 refuses NaN and infinities (vertices), 0 takes them
 * (the normals, which are not used). */
static int read_number(ascii_reader *r, const char *what, int finite, double *out)
{
    if (!next_token(r)) {
        snprintf(r->err, r->errlen, "%s:%d: the file ends inside a %s (3 numbers expected)",
                 r->name, r->last_line, what);
        return -1;
    }
    char *stop;
    errno = 0;
    double v = strtod(r->token, &stop);
    if (stop == r->token || *stop != '\0') {
        snprintf(r->err, r->errlen, "%s:%d: '%s' in a %s is not a number", r->name, r->line,
                 r->token, what);
        return -1;
    }
    if (finite && !isfinite(v)) {
        snprintf(r->err, r->errlen, "%s:%d: '%s' in a %s: coordinates must be finite numbers "
                 "(NaN and infinity are refused)", r->name, r->line, r->token, what);
        return -1;
    }
    *out = v;
    return 0;
}

/* Facets of an ASCII file: the word "facet" with a blank (or the start)
 * before and after it ("endfacet" is not counted). */
static size_t count_facets(const unsigned char *data, size_t size)
{
    size_t count = 0;
    for (size_t i = 0; i + 5 <= size; i++) {
        if (data[i] != 'f' || memcmp(data + i, "facet", 5) != 0) continue;
        int before = i == 0 || is_blank(data[i - 1]);
        int after = i + 5 == size || is_blank(data[i + 5]);
        count += (size_t)(before && after);
    }
    return count;
}

static int parse_ascii(const char *name, const unsigned char *data, size_t size, int max_triangles,
                       const char *limit_key, stl_mesh *out, char *warn, size_t warnlen,
                       char *err, size_t errlen)
{
    size_t facets = count_facets(data, size);
    if (facets > (size_t)max_triangles) {
        snprintf(err, errlen, "%s: %zu facets, more than the %d accepted: raise %s, or simplify "
                 "the mesh", name, facets, max_triangles, limit_key);
        return -1;
    }
    ascii_reader r = {name, data, data + size, 1, 1, "", err, errlen};
    if (expect(&r, "solid")) return -1;
    /* the rest of the line is the solid's name */
    while (r.p < r.end && *r.p != '\n') r.p++;
    out->triangles = malloc((facets > 0 ? facets : 1) * 9 * sizeof(double));
    if (!out->triangles) {
        snprintf(err, errlen, "%s: out of memory for %zu triangles", name, facets);
        return -1;
    }
    for (;;) {
        if (!next_token(&r)) {
            snprintf(err, errlen, "%s:%d: the file ends before 'endsolid' (a truncated ASCII STL)",
                     name, r.last_line);
            return -1;
        }
        if (strcmp(r.token, "endsolid") == 0) break;
        if (strcmp(r.token, "facet") != 0) {
            snprintf(err, errlen, "%s:%d: '%s' where 'facet' or 'endsolid' was expected", name,
                     r.line, r.token);
            return -1;
        }
        const int line = r.line;
        double normal[3], v[9];
        if (expect(&r, "normal")) return -1;
        for (int c = 0; c < 3; c++)
            if (read_number(&r, "facet normal", 0, &normal[c])) return -1;
        if (expect(&r, "outer") || expect(&r, "loop")) return -1;
        for (int k = 0; k < 3; k++) {
            if (expect(&r, "vertex")) return -1;
            for (int c = 0; c < 3; c++)
                if (read_number(&r, "vertex", 1, &v[3 * k + c])) return -1;
        }
        if (expect(&r, "endloop") || expect(&r, "endfacet")) return -1;
        if (degenerate(v)) {
            if (out->dropped++ == 0 && warn)
                snprintf(warn, warnlen, "%s:%d: a degenerate facet (zero area) is left out", name,
                         line);
            continue;
        }
        /* count_facets counted every word "facet": there is room */
        if ((size_t)out->triangle_count >= facets) {
            snprintf(err, errlen, "%s:%d: more facets than counted (an internal error)", name, line);
            return -1;
        }
        memcpy(&out->triangles[9 * (size_t)out->triangle_count++], v, sizeof v);
    }
    return 0;
}

/* ---- binary ---- */

static uint32_t le32(const unsigned char *b)
{
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

static float le_float(const unsigned char *b)
{
    uint32_t bits = le32(b);
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

static int parse_binary(const char *name, const unsigned char *data, uint32_t count,
                        int max_triangles, const char *limit_key, stl_mesh *out, char *warn,
                        size_t warnlen, char *err, size_t errlen)
{
    if (count > (uint32_t)max_triangles) {
        snprintf(err, errlen, "%s: byte 80: the header counts %lu triangles, more than the %d "
                 "accepted: raise %s, or simplify the mesh", name, (unsigned long)count,
                 max_triangles, limit_key);
        return -1;
    }
    out->triangles = malloc((count > 0 ? (size_t)count : 1) * 9 * sizeof(double));
    if (!out->triangles) {
        snprintf(err, errlen, "%s: out of memory for %lu triangles", name, (unsigned long)count);
        return -1;
    }
    for (uint32_t i = 0; i < count; i++) {
        const size_t at = 84 + 50 * (size_t)i;
        double v[9];
        for (int k = 0; k < 9; k++) {
            v[k] = le_float(data + at + 12 + 4 * (size_t)k);
            if (!isfinite(v[k])) {
                snprintf(err, errlen, "%s: byte %zu: triangle %lu, vertex %d, coordinate %c is "
                         "not a finite number (NaN and infinity are refused)", name,
                         at + 12 + 4 * (size_t)k, (unsigned long)i, k / 3 + 1, "xyz"[k % 3]);
                return -1;
            }
        }
        if (degenerate(v)) {
            if (out->dropped++ == 0 && warn)
                snprintf(warn, warnlen, "%s: byte %zu: a degenerate triangle (zero area, number "
                         "%lu) is left out", name, at, (unsigned long)i);
            continue;
        }
        memcpy(&out->triangles[9 * (size_t)out->triangle_count++], v, sizeof v);
    }
    return 0;
}

int stl_parse(const char *name, const unsigned char *data, size_t size, int max_triangles,
              const char *limit_key, stl_mesh *out, char *warn, size_t warnlen, char *err,
              size_t errlen)
{
    memset(out, 0, sizeof *out);
    if (warn && warnlen) warn[0] = '\0';
    if (max_triangles < 1) max_triangles = 1;
    /* binary: the size agrees with the header's count (a binary header may
     * itself start with "solid") */
    const uint32_t count = size >= 84 ? le32(data + 80) : 0;
    const int binary = size >= 84 && (uint64_t)size == 84 + 50 * (uint64_t)count;
    size_t lead = 0;
    while (lead < size && is_blank(data[lead]))
        lead++;
    /* ASCII: "solid" first and no NUL byte (a binary file's counts have them) */
    const int ascii = !binary && size - lead >= 5 && memcmp(data + lead, "solid", 5) == 0 &&
                      !memchr(data, '\0', size);
    int rc;
    if (binary) {
        rc = parse_binary(name, data, count, max_triangles, limit_key, out, warn, warnlen, err,
                          errlen);
    } else if (ascii) {
        rc = parse_ascii(name, data, size, max_triangles, limit_key, out, warn, warnlen, err,
                         errlen);
    } else if (size < 84) {
        snprintf(err, errlen, "%s: byte 0: not an STL file: %zu bytes, too short for a binary STL "
                 "(an 84-byte header, then 50 bytes a triangle), and an ASCII STL starts with "
                 "'solid'", name, size);
        rc = -1;
    } else {
        snprintf(err, errlen, "%s: byte 80: the binary header counts %lu triangles, so the file "
                 "should hold 84 + 50 x %lu = %llu bytes, but it holds %zu (truncated or not "
                 "STL); an ASCII STL starts with 'solid'", name, (unsigned long)count,
                 (unsigned long)count, 84ull + 50ull * count, size);
        rc = -1;
    }
    if (rc == 0 && out->triangle_count == 0) {
        snprintf(err, errlen, "%s: no triangle%s: an obstacle needs at least one", name,
                 out->dropped ? " left after the degenerate ones (zero area) are dropped" : "");
        rc = -1;
    }
    if (rc) stl_release(out);
    return rc;
}

int stl_load(const char *path, int max_triangles, const char *limit_key, stl_mesh *out,
             char *warn, size_t warnlen, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    struct stat st;
    if (stat(path, &st) != 0) {
        snprintf(err, errlen, "%s: cannot open the STL file: %s", path, strerror(errno));
        return -1;
    }
    if (!S_ISREG(st.st_mode)) {
        snprintf(err, errlen, "%s: not a regular file (an STL file is expected)", path);
        return -1;
    }
    if ((unsigned long long)st.st_size > STL_MAX_BYTES) {
        snprintf(err, errlen, "%s: %lld bytes, more than the %zu MB an STL file may hold", path,
                 (long long)st.st_size, STL_MAX_BYTES >> 20);
        return -1;
    }
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(err, errlen, "%s: cannot open the STL file: %s", path, strerror(errno));
        return -1;
    }
    size_t size = (size_t)st.st_size;
    unsigned char *data = malloc(size > 0 ? size : 1);
    if (!data) {
        fclose(f);
        snprintf(err, errlen, "%s: out of memory (%zu bytes)", path, size);
        return -1;
    }
    size_t got = fread(data, 1, size, f);
    fclose(f);
    int rc;
    if (got != size) {
        snprintf(err, errlen, "%s: read %zu of its %zu bytes", path, got, size);
        rc = -1;
    } else {
        rc = stl_parse(path, data, size, max_triangles, limit_key, out, warn, warnlen, err,
                       errlen);
    }
    free(data);
    return rc;
}

void stl_release(stl_mesh *out)
{
    free(out->triangles);
    out->triangles = NULL;
    out->triangle_count = 0;
}
