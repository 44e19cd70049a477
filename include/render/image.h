/* image.h: an RGB picture in memory, PNG in and out.
 *
 * Rows run top-down, 3 bytes per pixel (r g b), no padding. The renderer
 * reads a frame back from GL into an image, draws overlay text into it
 * (text.h), then hands it to the PNG writer or the video encoder.
 */
#ifndef RODSIM_IMAGE_H
#define RODSIM_IMAGE_H

#include <stddef.h>

typedef struct image {
    int width, height;  /* pixels */
    unsigned char *rgb; /* (height x width x 3), top row first */
    int *changed;       /* NULL: not tracked; else (height x 2): each row's columns
                           [lo, hi) written since image_changes_reset (image_track_changes) */
} image;

/* A w x h image filled with black. NULL when out of memory or size <= 0. */
image *image_create(int width, int height);
void image_destroy(image *img);
void image_fill(image *img, unsigned char r, unsigned char g, unsigned char b);
/* Fills the rectangle [x, x+w) x [y, y+h), clipped to the image, blending
 * rgb over the pixels with opacity alpha in [0, 1]. */
void image_fill_rect(image *img, int x, int y, int w, int h, const unsigned char rgb[3],
                     double alpha);

/* Change tracking, for a frame redrawn in place over a still backdrop:
 * image_fill, image_fill_rect and text.h's drawing mark the columns they
 * write in each row, and whoever writes rgb directly calls image_mark.
 * image_track_changes starts it with every pixel marked; 0, or -1 when out
 * of memory (the image then stays untracked). */
int image_track_changes(image *img);
/* Marks the pixels [x0, x1) x [y0, y1) (clipped) as written; nothing when untracked. */
void image_mark(image *img, int x0, int y0, int x1, int y1);
/* Every row unmarked. */
void image_changes_reset(image *img);

/* Writes a PNG atomically (temporary name, then rename: outfile.h).
 * compression: 0 (fastest, largest) .. 9 (smallest); -1 for libpng's default.
 * Returns 0, or -1 with a message naming the path. */
int image_write_png_level(const image *img, const char *path, int compression, char *err,
                          size_t errlen);
/* image_write_png_level with libpng's default compression. */
int image_write_png(const image *img, const char *path, char *err, size_t errlen);
/* Reads an 8-bit PNG (grey, RGB, with or without alpha: alpha is dropped).
 * NULL with a message on failure. */
image *image_read_png(const char *path, char *err, size_t errlen);

/* Peak signal-to-noise ratio of b against a over all channels, dB
 * (INFINITY when identical, NAN when the sizes differ). */
double image_psnr(const image *a, const image *b);

#endif
