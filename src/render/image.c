/* image.c: RGB images and PNG through libpng (see image.h). */
#include "render/image.h"

#include <math.h>
#include <png.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/outfile.h"

image *image_create(int width, int height)
{
    if (width <= 0 || height <= 0) return NULL;
    image *img = malloc(sizeof *img);
    if (!img) return NULL;
    img->width = width;
    img->height = height;
    img->changed = NULL;
    img->rgb = calloc((size_t)width * (size_t)height, 3);
    if (!img->rgb) {
        free(img);
        return NULL;
    }
    return img;
}

void image_destroy(image *img)
{
    if (!img) return;
    free(img->rgb);
    free(img->changed);
    free(img);
}

int image_track_changes(image *img)
{
    if (!img->changed) img->changed = malloc((size_t)img->height * 2 * sizeof(int));
    if (!img->changed) return -1;
    image_changes_reset(img);
    image_mark(img, 0, 0, img->width, img->height);
    return 0;
}

void image_mark(image *img, int x0, int y0, int x1, int y1)
{
    if (!img->changed) return;
    x0 = x0 < 0 ? 0 : x0, y0 = y0 < 0 ? 0 : y0;
    x1 = x1 > img->width ? img->width : x1, y1 = y1 > img->height ? img->height : y1;
    if (x0 >= x1) return;
    for (int y = y0; y < y1; y++) {
        int *span = &img->changed[2 * y];
        if (span[0] >= span[1]) {
            span[0] = x0;
            span[1] = x1;
        } else {
            span[0] = x0 < span[0] ? x0 : span[0];
            span[1] = x1 > span[1] ? x1 : span[1];
        }
    }
}

void image_changes_reset(image *img)
{
    for (int y = 0; img->changed && y < img->height; y++)
        img->changed[2 * y] = img->changed[2 * y + 1] = 0;
}

void image_fill(image *img, unsigned char r, unsigned char g, unsigned char b)
{
    size_t n = (size_t)img->width * (size_t)img->height;
    unsigned char *p = img->rgb;
    for (size_t i = 0; i < n; i++, p += 3) {
        p[0] = r;
        p[1] = g;
        p[2] = b;
    }
    image_mark(img, 0, 0, img->width, img->height);
}

void image_fill_rect(image *img, int x, int y, int w, int h, const unsigned char rgb[3],
                     double alpha)
{
    int x0 = x < 0 ? 0 : x, y0 = y < 0 ? 0 : y;
    int x1 = x + w > img->width ? img->width : x + w;
    int y1 = y + h > img->height ? img->height : y + h;
    int a = (int)lround((alpha < 0 ? 0 : alpha > 1 ? 1 : alpha) * 256.0);
    image_mark(img, x0, y0, x1, y1);
    for (int row = y0; row < y1; row++) {
        unsigned char *p = img->rgb + ((size_t)row * (size_t)img->width + (size_t)x0) * 3;
        for (int col = x0; col < x1; col++, p += 3)
            for (int c = 0; c < 3; c++) p[c] = (unsigned char)((p[c] * (256 - a) + rgb[c] * a) >> 8);
    }
}

/* libpng reports errors by longjmp; keep the message for the caller. */
typedef struct png_error_sink {
    char message[256];
} png_error_sink;

static void on_png_error(png_structp png, png_const_charp msg)
{
    png_error_sink *sink = png_get_error_ptr(png);
    snprintf(sink->message, sizeof sink->message, "%s", msg);
    png_longjmp(png, 1);
}

static void on_png_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;
}

int image_write_png_level(const image *img, const char *path, int compression, char *err,
                          size_t errlen)
{
    outfile out;
    if (outfile_open(&out, path, err, errlen)) return -1;
    png_error_sink sink = {{0}};
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &sink, on_png_error,
                                              on_png_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!png || !info) {
        snprintf(err, errlen, "%s: out of memory", path);
        png_destroy_write_struct(&png, &info);
        outfile_abort(&out);
        return -1;
    }
    if (setjmp(png_jmpbuf(png))) {
        snprintf(err, errlen, "%s: cannot write PNG: %s", path, sink.message);
        png_destroy_write_struct(&png, &info);
        outfile_abort(&out);
        return -1;
    }
    png_init_io(png, out.fp);
    if (compression >= 0) png_set_compression_level(png, compression > 9 ? 9 : compression);
    png_set_IHDR(png, info, (png_uint_32)img->width, (png_uint_32)img->height, 8,
                 PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int row = 0; row < img->height; row++)
        png_write_row(png, img->rgb + (size_t)row * (size_t)img->width * 3);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return outfile_commit(&out, err, errlen);
}

int image_write_png(const image *img, const char *path, char *err, size_t errlen)
{
    return image_write_png_level(img, path, -1, err, errlen);
}

image *image_read_png(const char *path, char *err, size_t errlen)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) {
        snprintf(err, errlen, "%s: cannot open", path);
        return NULL;
    }
    png_error_sink sink = {{0}};
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &sink, on_png_error,
                                             on_png_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    image *volatile img = NULL;
    if (!png || !info) {
        snprintf(err, errlen, "%s: out of memory", path);
        png_destroy_read_struct(&png, &info, NULL);
        fclose(fp);
        return NULL;
    }
    if (setjmp(png_jmpbuf(png))) {
        snprintf(err, errlen, "%s: cannot read PNG: %s", path, sink.message);
        png_destroy_read_struct(&png, &info, NULL);
        image_destroy(img);
        fclose(fp);
        return NULL;
    }
    png_init_io(png, fp);
    png_read_info(png, info);
    /* Normalise every 8/16-bit layout to 8-bit RGB. */
    png_set_strip_16(png);
    png_set_strip_alpha(png);
    png_set_palette_to_rgb(png);
    png_set_gray_to_rgb(png);
    png_set_expand_gray_1_2_4_to_8(png);
    png_read_update_info(png, info);
    int w = (int)png_get_image_width(png, info), h = (int)png_get_image_height(png, info);
    if (png_get_rowbytes(png, info) != (size_t)w * 3) {
        snprintf(err, errlen, "%s: unsupported PNG layout", path);
        png_destroy_read_struct(&png, &info, NULL);
        fclose(fp);
        return NULL;
    }
    img = image_create(w, h);
    if (!img) {
        snprintf(err, errlen, "%s: out of memory", path);
        png_destroy_read_struct(&png, &info, NULL);
        fclose(fp);
        return NULL;
    }
    for (int row = 0; row < h; row++) png_read_row(png, img->rgb + (size_t)row * (size_t)w * 3, NULL);
    png_read_end(png, NULL);
    png_destroy_read_struct(&png, &info, NULL);
    fclose(fp);
    return img;
}

double image_psnr(const image *a, const image *b)
{
    if (a->width != b->width || a->height != b->height) return NAN;
    size_t n = (size_t)a->width * (size_t)a->height * 3;
    double sum = 0;
    for (size_t i = 0; i < n; i++) {
        double d = (double)a->rgb[i] - (double)b->rgb[i];
        sum += d * d;
    }
    if (sum == 0) return INFINITY;
    return 10.0 * log10(255.0 * 255.0 / (sum / (double)n));
}
