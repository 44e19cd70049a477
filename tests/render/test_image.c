/* test_image.c: the graphics base: PNG round trip, text placement, the
 * headless GL context, shader loading and the multisampled target. */
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "render/gl_api.h"
#include "render/gl_context.h"
#include "render/gl_util.h"
#include "render/image.h"
#include "test.h"
#include "render/text.h"

static void test_png_round_trip(void)
{
    char err[512];
    image *img = image_create(37, 23);
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++) {
            unsigned char *p = img->rgb + (y * img->width + x) * 3;
            p[0] = (unsigned char)(x * 7);
            p[1] = (unsigned char)(y * 11);
            p[2] = (unsigned char)(x * y);
        }
    char path[256];
    snprintf(path, sizeof path, "%s/a.png", test_path("image")); /* a folder not made yet */
    int written = image_write_png(img, path, err, sizeof err);
    check(written == 0, "PNG written to %s (%s)", path, written ? err : "ok");
    image *back = image_read_png(path, err, sizeof err);
    check(back && back->width == 37 && back->height == 23, "PNG read back at 37x23");
    if (back)
        check(memcmp(back->rgb, img->rgb, 37 * 23 * 3) == 0,
              "PNG round trip is lossless (PSNR %.1f dB)", image_psnr(img, back));
    image_destroy(back);
    unlink(path);
    rmdir(test_path("image"));

    /* an unwritable place leaves nothing and says why */
    int failed = image_write_png(img, "/proc/rodsim_cannot_write/x.png", err, sizeof err);
    check(failed == -1 && strstr(err, "/proc/rodsim_cannot_write") != NULL,
          "unwritable PNG path fails with a message naming it: %s", err);
    image_destroy(img);

    image *missing = image_read_png("/nonexistent/none.png", err, sizeof err);
    check(missing == NULL && strstr(err, "/nonexistent/none.png"), "missing PNG: %s", err);
}

/* Bounding box of the pixels that differ from the background. */
static int ink_box(const image *img, const unsigned char bg[3], int box[4])
{
    int count = 0;
    box[0] = img->width; box[1] = img->height; box[2] = -1; box[3] = -1;
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++) {
            const unsigned char *p = img->rgb + (y * img->width + x) * 3;
            if (p[0] == bg[0] && p[1] == bg[1] && p[2] == bg[2]) continue;
            count++;
            if (x < box[0]) box[0] = x;
            if (y < box[1]) box[1] = y;
            if (x > box[2]) box[2] = x;
            if (y > box[3]) box[3] = y;
        }
    return count;
}

static void test_text(void)
{
    char err[512];
    text_font *font = text_font_load(20, err, sizeof err);
    if (!check(font != NULL, "DejaVu Sans loads at 20 px (%s)", font ? "ok" : err)) return;
    const unsigned char white[3] = {255, 255, 255}, black[3] = {0, 0, 0};
    image *img = image_create(200, 60);
    image_fill(img, 255, 255, 255);
    const char *label = "t = 1.25 s";
    int x = 10, baseline = 40;
    int width = text_width(font, label);
    int advance = text_draw(img, font, x, baseline, label, black);
    check(advance == width && width > 50 && width < 150,
          "text advance %d equals text_width %d and is plausible for 10 characters at 20 px",
          advance, width);
    int box[4];
    int ink = ink_box(img, white, box);
    check(ink > 100, "text drew %d non-background pixels", ink);
    check(box[0] >= x && box[2] <= x + width && box[1] >= baseline - text_ascent(font) &&
              box[3] <= baseline + text_descent(font),
          "ink box x %d..%d y %d..%d lies within the measured box x %d..%d y %d..%d", box[0],
          box[2], box[1], box[3], x, x + width, baseline - text_ascent(font),
          baseline + text_descent(font));

    /* vertical text: the same ink, turned: tall and narrow, left of... the baseline column */
    image_fill(img, 255, 255, 255);
    image *tall = image_create(60, 200);
    image_fill(tall, 255, 255, 255);
    int up = text_draw_vertical(tall, font, 40, 190, label, black);
    ink_box(tall, white, box);
    check(up == width && box[1] >= 190 - width && box[3] <= 190 && box[2] <= 40 + text_descent(font) &&
              box[0] >= 40 - text_ascent(font) && box[3] - box[1] > 2 * (box[2] - box[0]),
          "vertical text box x %d..%d y %d..%d runs upward from row 190 left of column 40",
          box[0], box[2], box[1], box[3]);
    /* non-ASCII goes through the slot path */
    check(text_width(font, "\xc3\x97") > 0, "the multiplication sign has a width (%d px)",
          text_width(font, "\xc3\x97"));
    /* the halo: dark ink over a dark band (a rod under the overlay) stays
     * readable: light pixels ring the strokes there, none without a halo,
     * and on the light background the halo (its colour) changes nothing */
    const unsigned char light[3] = {246, 247, 249}, dark[3] = {30, 40, 90}, ink_rgb[3] = {34, 34, 34};
    int lit[2] = {0, 0}, changed[2] = {0, 0};
    for (int halo = 0; halo < 2; halo++) {
        image_fill(img, light[0], light[1], light[2]);
        for (int y = 0; y < 60; y++)
            for (int xx = 0; xx < 100; xx++)
                memcpy(img->rgb + ((size_t)y * 200 + (size_t)xx) * 3, dark, 3);
        text_set_halo(font, halo ? light : NULL);
        text_draw(img, font, x, baseline, label, ink_rgb);
        for (int y = 0; y < 60; y++)
            for (int xx = 0; xx < 200; xx++) {
                const unsigned char *p = img->rgb + ((size_t)y * 200 + (size_t)xx) * 3;
                if (xx < 100 && p[0] + p[1] + p[2] > 3 * 200) lit[halo]++;
                if (xx >= 100 && (p[0] != light[0] || p[1] != light[1] || p[2] != light[2]))
                    changed[halo]++;
            }
    }
    text_set_halo(font, NULL);
    check(lit[0] == 0 && lit[1] > 100,
          "over a dark band the halo lights %d pixels around the strokes (%d without it)", lit[1],
          lit[0]);
    check(changed[1] == changed[0] && changed[0] > 50,
          "on the background the halo changes nothing: %d pixels inked with it, %d without",
          changed[1], changed[0]);
    image_destroy(tall);
    image_destroy(img);
    text_font_destroy(font);
}

static void test_gl(void)
{
    char err[1024];
    gl_context *ctx = gl_context_create(64, 48, err, sizeof err);
    if (!check(ctx != NULL, "GL context: %s", ctx ? gl_context_description(ctx) : err)) return;
    /* the scene shader as the renderer compiles it: one program per kind of
     * shading (gl_render.c); without its defines it names what is missing */
    static const char *const variants[] = {"#define LIT 0\n#define FADING 0\n",
                                           "#define LIT 1\n#define FADING 0\n",
                                           "#define LIT 2\n#define FADING 0\n",
                                           "#define LIT 2\n#define FADING 1\n"};
    unsigned program = 0;
    for (int v = 0; v < 4; v++) {
        program = gl_program_load_defined("scene", variants[v], err, sizeof err);
        check(program != 0, "shaders/scene.vert+frag, shading variant %d of 4, compile and link (%s)",
              v + 1, program ? "ok" : err);
    }
    unsigned bare = gl_program_load("scene", err, sizeof err);
    check(bare == 0 && strstr(err, "LIT"), "scene.frag without its defines is refused naming LIT");
    unsigned none = gl_program_load("no_such_shader", err, sizeof err);
    check(none == 0 && strstr(err, "no_such_shader.vert"), "missing shader named: %s", err);

    gl_target *target = gl_target_create(64, 48, 4, err, sizeof err);
    if (check(target != NULL, "4x multisampled target (%d samples)",
              target ? gl_target_samples(target) : -1)) {
        gl_target_bind(target);
        glClearColor(0.2f, 0.4f, 0.6f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        /* the bottom half another colour, to check the flip to top-down rows */
        glEnable(GL_SCISSOR_TEST);
        glScissor(0, 0, 64, 24);
        glClearColor(1.0f, 0.0f, 0.0f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        glDisable(GL_SCISSOR_TEST);
        image *img = image_create(64, 48);
        int read = gl_target_read(target, img);
        const unsigned char *top = img->rgb, *bottom = img->rgb + (47 * 64) * 3;
        check(read == 0 && abs(top[0] - 51) <= 1 && abs(top[1] - 102) <= 1 && abs(top[2] - 153) <= 1,
              "top row has the clear colour (%d %d %d, expected 51 102 153)", top[0], top[1], top[2]);
        check(bottom[0] == 255 && bottom[1] == 0 && bottom[2] == 0,
              "bottom row has the scissored colour (%d %d %d): rows are top-down", bottom[0],
              bottom[1], bottom[2]);
        image_destroy(img);
        gl_target_destroy(target);
    }
    if (program) glDeleteProgram(program);
    gl_context_destroy(ctx);
}

int main(void)
{
    test_png_round_trip();
    test_text();
    test_gl();
    return test_finish();
}
