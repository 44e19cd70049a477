/* text.h: overlay text drawn on the CPU into an image (after GL read-back),
 * antialiased, with FreeType and DejaVu Sans (Debian fonts-dejavu-core),
 * whose file fontconfig finds (on Debian
 * /usr/share/fonts/truetype/dejavu/DejaVuSans.ttf).
 *
 * Coordinates are image pixels, y down. Printable ASCII is rendered once at
 * load; other UTF-8 characters are rendered when drawn. */
#ifndef RODSIM_TEXT_H
#define RODSIM_TEXT_H

#include <stddef.h>

#include "render/image.h"

typedef struct text_font text_font;

/* The DejaVu Sans (regular) file fontconfig finds, looked up once per
 * process; NULL with a message naming the Debian package to install when
 * fontconfig has no DejaVu Sans. Owned by this module. */
const char *text_font_file(char *err, size_t errlen);

/* Loads DejaVu Sans at pixel_height (pixels per em). NULL with a message. */
text_font *text_font_load(int pixel_height, char *err, size_t errlen);
void text_font_destroy(text_font *f);

/* Draws utf8 with its baseline at y_baseline starting at x, blending rgb
 * over the image by the glyph coverage; clipped to the image.
 * Returns the advance width in pixels. */
int text_draw(image *img, text_font *f, int x, int y_baseline, const char *utf8,
              const unsigned char rgb[3]);
/* From now on, text_draw lays a halo of rgb (NULL: none) 2 pixels wide
 * under the glyphs, so that text stays readable over a rod or a surface
 * (the overlay's: the background colour, invisible on the background). */
void text_set_halo(text_font *f, const unsigned char rgb[3]);
/* Advance width of utf8 in pixels (what text_draw returns). */
int text_width(text_font *f, const char *utf8);
/* Ascent and descent above/below the baseline, pixels (both >= 0). */
int text_ascent(const text_font *f);
int text_descent(const text_font *f);

/* Draws utf8 rotated 90 degrees counter-clockwise (reading bottom to top),
 * for vertical axis labels: the baseline is the column x, the text starts at
 * row y_start and runs upward. Returns the advance (pixels upward). */
int text_draw_vertical(image *img, text_font *f, int x, int y_start, const char *utf8,
                       const unsigned char rgb[3]);

#endif
