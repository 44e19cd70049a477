/* text.c: FreeType text into an image (see text.h). */
#include "render/text.h"

#include <fontconfig/fontconfig.h>
#include <ft2build.h>
#include FT_FREETYPE_H
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TEXT_FONT_FAMILY "DejaVu Sans"
#define TEXT_CACHE_FIRST 32
#define TEXT_CACHE_LAST 126

typedef struct glyph {
    int width, rows;         /* bitmap size, pixels */
    int left, top;           /* bitmap offset from the pen: right, up */
    int advance;             /* pixels */
    unsigned char *coverage; /* (rows x width), 0..255; NULL when empty */
} glyph;

struct text_font {
    FT_Library library;
    FT_Face face;
    int ascent, descent;
    int halo;                  /* 1: a halo of halo_rgb under the glyphs */
    unsigned char halo_rgb[3];
    glyph cache[TEXT_CACHE_LAST - TEXT_CACHE_FIRST + 1];
};

/* Next code point of a UTF-8 string; advances *s. Invalid bytes give '?'. */
static unsigned next_code_point(const char **s)
{
    const unsigned char *p = (const unsigned char *)*s;
    unsigned c = p[0];
    int extra = c < 0x80 ? 0 : (c & 0xE0) == 0xC0 ? 1 : (c & 0xF0) == 0xE0 ? 2 : (c & 0xF8) == 0xF0 ? 3 : -1;
    if (extra < 0) {
        *s += 1;
        return '?';
    }
    unsigned code = extra == 0 ? c : extra == 1 ? (c & 0x1F) : extra == 2 ? (c & 0x0F) : (c & 0x07);
    for (int i = 1; i <= extra; i++) {
        if ((p[i] & 0xC0) != 0x80) {
            *s += i;
            return '?';
        }
        code = (code << 6) | (p[i] & 0x3F);
    }
    *s += 1 + extra;
    return code;
}

/* Renders one character into the face's glyph slot; fills g without copying
 * the bitmap (g->coverage points into the slot until the next render). */
static int render_slot(text_font *f, unsigned code, glyph *g)
{
    if (FT_Load_Char(f->face, code, FT_LOAD_RENDER | FT_LOAD_TARGET_LIGHT)) return -1;
    FT_GlyphSlot slot = f->face->glyph;
    g->width = (int)slot->bitmap.width;
    g->rows = (int)slot->bitmap.rows;
    g->left = slot->bitmap_left;
    g->top = slot->bitmap_top;
    g->advance = (int)((slot->advance.x + 32) >> 6);
    g->coverage = slot->bitmap.buffer;
    /* the slot's pitch may exceed the width: only trust tightly packed rows */
    if (slot->bitmap.pitch != (int)slot->bitmap.width && g->rows > 0) return -1;
    return 0;
}

/* The font's file, looked up once per process (plots load five sizes). */
static pthread_once_t font_once = PTHREAD_ONCE_INIT;
static char font_file[4096]; /* "" when not found */
static int font_index;       /* the face in the file */
static char font_error[512];

/* Asks fontconfig for DejaVu Sans (regular); fontconfig answers its nearest
 * font when the family is missing, so the family it names is checked. */
static void find_font(void)
{
    FcConfig *config = FcInitLoadConfigAndFonts();
    FcPattern *pattern = FcNameParse((const FcChar8 *)TEXT_FONT_FAMILY);
    FcPattern *match = NULL;
    if (config && pattern && FcConfigSubstitute(config, pattern, FcMatchPattern)) {
        FcDefaultSubstitute(pattern);
        FcResult result;
        match = FcFontMatch(config, pattern, &result);
    }
    FcChar8 *family = NULL, *file = NULL;
    if (match && FcPatternGetString(match, FC_FAMILY, 0, &family) == FcResultMatch &&
        strcmp((const char *)family, TEXT_FONT_FAMILY) == 0 &&
        FcPatternGetString(match, FC_FILE, 0, &file) == FcResultMatch &&
        strlen((const char *)file) < sizeof font_file) {
        snprintf(font_file, sizeof font_file, "%s", (const char *)file);
        if (FcPatternGetInteger(match, FC_INDEX, 0, &font_index) != FcResultMatch) font_index = 0;
    } else {
        snprintf(font_error, sizeof font_error,
                 "text: fontconfig finds no %s font%s%s%s (install the Debian package "
                 "fonts-dejavu-core)",
                 TEXT_FONT_FAMILY, family ? " (its nearest is " : "",
                 family ? (const char *)family : "", family ? ")" : "");
    }
    if (match) FcPatternDestroy(match);
    if (pattern) FcPatternDestroy(pattern);
    if (config) FcConfigDestroy(config);
}

const char *text_font_file(char *err, size_t errlen)
{
    pthread_once(&font_once, find_font);
    if (!font_file[0]) {
        snprintf(err, errlen, "%s", font_error);
        return NULL;
    }
    return font_file;
}

text_font *text_font_load(int pixel_height, char *err, size_t errlen)
{
    if (pixel_height < 4 || pixel_height > 512) {
        snprintf(err, errlen, "text: font size %d pixels is outside 4..512", pixel_height);
        return NULL;
    }
    text_font *f = calloc(1, sizeof *f);
    if (!f) {
        snprintf(err, errlen, "text: out of memory");
        return NULL;
    }
    if (FT_Init_FreeType(&f->library)) {
        snprintf(err, errlen, "text: FreeType failed to initialise");
        free(f);
        return NULL;
    }
    const char *file = text_font_file(err, errlen);
    if (!file || FT_New_Face(f->library, file, font_index, &f->face)) {
        if (file)
            snprintf(err, errlen, "%s: FreeType cannot load this font (reinstall the Debian "
                     "package fonts-dejavu-core)", file);
        FT_Done_FreeType(f->library);
        free(f);
        return NULL;
    }
    FT_Set_Pixel_Sizes(f->face, 0, (FT_UInt)pixel_height);
    f->ascent = (int)((f->face->size->metrics.ascender + 63) >> 6);
    f->descent = (int)((-f->face->size->metrics.descender + 63) >> 6);
    for (unsigned c = TEXT_CACHE_FIRST; c <= TEXT_CACHE_LAST; c++) {
        glyph *g = &f->cache[c - TEXT_CACHE_FIRST];
        glyph slot_glyph;
        if (render_slot(f, c, &slot_glyph)) continue;
        *g = slot_glyph;
        g->coverage = NULL;
        size_t n = (size_t)g->width * (size_t)g->rows;
        if (n == 0) continue;
        g->coverage = malloc(n);
        if (!g->coverage) {
            snprintf(err, errlen, "text: out of memory");
            text_font_destroy(f);
            return NULL;
        }
        memcpy(g->coverage, slot_glyph.coverage, n);
    }
    return f;
}

void text_font_destroy(text_font *f)
{
    if (!f) return;
    for (int i = 0; i <= TEXT_CACHE_LAST - TEXT_CACHE_FIRST; i++) free(f->cache[i].coverage);
    FT_Done_Face(f->face);
    FT_Done_FreeType(f->library);
    free(f);
}

int text_ascent(const text_font *f) { return f->ascent; }
int text_descent(const text_font *f) { return f->descent; }

/* The glyph of code: cached, or rendered into the slot (valid until the next). */
static int get_glyph(text_font *f, unsigned code, glyph *out)
{
    if (code >= TEXT_CACHE_FIRST && code <= TEXT_CACHE_LAST) {
        *out = f->cache[code - TEXT_CACHE_FIRST];
        return 0;
    }
    return render_slot(f, code, out);
}

static void blend(unsigned char *p, const unsigned char rgb[3], unsigned coverage)
{
    for (int c = 0; c < 3; c++)
        p[c] = (unsigned char)((p[c] * (255 - coverage) + rgb[c] * coverage + 127) / 255);
}

/* Draws one glyph with its pen at (x, y); vertical: rotated 90 degrees CCW. */
static void draw_glyph(image *img, const glyph *g, int x, int y, int vertical,
                       const unsigned char rgb[3])
{
    if (vertical)
        image_mark(img, x - g->top, y - g->left - g->width + 1, x - g->top + g->rows, y - g->left + 1);
    else
        image_mark(img, x + g->left, y - g->top, x + g->left + g->width, y - g->top + g->rows);
    for (int row = 0; row < g->rows; row++) {
        for (int col = 0; col < g->width; col++) {
            unsigned coverage = g->coverage[row * g->width + col];
            if (!coverage) continue;
            /* horizontal offset from the pen: (dx, dy), y down */
            int dx = g->left + col, dy = row - g->top;
            /* rotating (dx, dy) by 90 degrees CCW on screen gives (dy, -dx) */
            int px = vertical ? x + dy : x + dx;
            int py = vertical ? y - dx : y + dy;
            if (px < 0 || py < 0 || px >= img->width || py >= img->height) continue;
            blend(img->rgb + ((size_t)py * (size_t)img->width + (size_t)px) * 3, rgb, coverage);
        }
    }
}

/* The halo of one glyph: its coverage, spread 2 pixels each way (12
 * offsets), blended at 0.6 of the coverage per offset, so it is nearly
 * opaque next to a stroke and fades out 2 pixels away. */
static void draw_glyph_halo(image *img, const glyph *g, int x, int y, const unsigned char rgb[3])
{
    /* where the glyph's box, grown by the halo, holds only colours near the
     * halo's (the overlay's background, its grid lines), the ink reads
     * without it: skipped (most of the overlay, most frames). */
    int x0 = x + g->left - 2, x1 = x + g->left + g->width + 2;
    int y0 = y - g->top - 2, y1 = y - g->top + g->rows + 2, other = 0;
    x0 = x0 < 0 ? 0 : x0, y0 = y0 < 0 ? 0 : y0;
    x1 = x1 > img->width ? img->width : x1, y1 = y1 > img->height ? img->height : y1;
    for (int py = y0; py < y1 && !other; py += 2) { /* every other pixel: what the halo
                                                      is for (a rod, a surface) is wider */
        const unsigned char *p = img->rgb + ((size_t)py * (size_t)img->width + (size_t)x0) * 3;
        for (int px = x0; px < x1 && !other; px += 2, p += 6)
            other = abs(p[0] - rgb[0]) > 40 || abs(p[1] - rgb[1]) > 40 || abs(p[2] - rgb[2]) > 40;
    }
    if (!other) return;
    image_mark(img, x0, y0, x1, y1);
    static const int offset[12][2] = {{1, 0}, {-1, 0}, {0, 1},  {0, -1}, {1, 1},  {1, -1},
                                      {-1, 1}, {-1, -1}, {2, 0}, {-2, 0}, {0, 2}, {0, -2}};
    for (int row = 0; row < g->rows; row++) {
        for (int col = 0; col < g->width; col++) {
            unsigned coverage = g->coverage[row * g->width + col] * 3u / 5u;
            if (!coverage) continue;
            for (int k = 0; k < 12; k++) {
                int px = x + g->left + col + offset[k][0], py = y + row - g->top + offset[k][1];
                if (px < 0 || py < 0 || px >= img->width || py >= img->height) continue;
                blend(img->rgb + ((size_t)py * (size_t)img->width + (size_t)px) * 3, rgb, coverage);
            }
        }
    }
}

static int draw_string(image *img, text_font *f, int x, int y, const char *utf8, int vertical,
                       const unsigned char rgb[3])
{
    int advance = 0;
    const char *s = utf8;
    if (img && f->halo && !vertical) { /* the halo first, under every glyph of the string */
        while (*s) {
            glyph g;
            if (get_glyph(f, next_code_point(&s), &g)) continue;
            if (g.coverage) draw_glyph_halo(img, &g, x + advance, y, f->halo_rgb);
            advance += g.advance;
        }
        advance = 0;
        s = utf8;
    }
    while (*s) {
        glyph g;
        if (get_glyph(f, next_code_point(&s), &g)) continue;
        if (img && g.coverage)
            draw_glyph(img, &g, vertical ? x : x + advance, vertical ? y - advance : y, vertical, rgb);
        advance += g.advance;
    }
    return advance;
}

int text_draw(image *img, text_font *f, int x, int y_baseline, const char *utf8,
              const unsigned char rgb[3])
{
    return draw_string(img, f, x, y_baseline, utf8, 0, rgb);
}

void text_set_halo(text_font *f, const unsigned char rgb[3])
{
    f->halo = rgb != NULL;
    if (rgb)
        for (int c = 0; c < 3; c++) f->halo_rgb[c] = rgb[c];
}

int text_width(text_font *f, const char *utf8)
{
    return draw_string(NULL, f, 0, 0, utf8, 0, NULL);
}

int text_draw_vertical(image *img, text_font *f, int x, int y_start, const char *utf8,
                       const unsigned char rgb[3])
{
    return draw_string(img, f, x, y_start, utf8, 1, rgb);
}
