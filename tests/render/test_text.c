/* test_text.c: the overlay's font is found through fontconfig. The file
 * text_font_file names is the one fontconfig's own command (fc-match, the
 * reference) gives for DejaVu Sans, a DejaVuSans.ttf; a font loaded from it
 * at 40 pixels per em advances "A" by 27 pixels (DejaVu Sans' A: 1401 of
 * 2048 font units, 27.4 pixels, rounded by the hinting by at most one). Where fontconfig knows no
 * fonts (FONTCONFIG_FILE: a configuration without font folders), drawing
 * text fails with a message naming the Debian package fonts-dejavu-core,
 * and no file is left in the output folder. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/text.h"
#include "test.h"
#include "test_process.h"

static void test_found(void)
{
    char err[512] = "";
    const char *file = text_font_file(err, sizeof err);
    char reference[4096] = "";
    FILE *p = popen("fc-match -f '%{file}' 'DejaVu Sans' 2>/dev/null", "r");
    if (p) {
        if (!fgets(reference, sizeof reference, p)) reference[0] = '\0';
        pclose(p);
    }
    check(file && strcmp(file, reference) == 0, "font file: \"%s\" (fc-match: \"%s\") %s",
          file ? file : "(none)", reference, err);
    const char *base = file ? strrchr(file, '/') : NULL;
    check(base && strcmp(base, "/DejaVuSans.ttf") == 0, "the file is DejaVuSans.ttf: %s",
          file ? file : "(none)");
    text_font *f = text_font_load(40, err, sizeof err);
    if (!check(f != NULL, "text_font_load(40): %s", f ? "loaded" : err)) return;
    int width = text_width(f, "A");
    check(width >= 26 && width <= 28,
          "advance of \"A\" at 40 pixels per em: %d pixels (reference 27.4, within 1)", width);
    text_font_destroy(f);
}

static void test_missing(void)
{
    char dir[] = "/tmp/rodsim_text_XXXXXX";
    if (!check(mkdtemp(dir) != NULL, "scratch directory")) return;
    char conf[600], out[600];
    snprintf(conf, sizeof conf, "%s/fonts.conf", dir);
    snprintf(out, sizeof out, "%s/out", dir);
    FILE *f = fopen(conf, "w");
    if (!check(f != NULL, "write %s", conf)) return;
    fprintf(f, "<?xml version=\"1.0\"?>\n<!DOCTYPE fontconfig SYSTEM \"fonts.dtd\">\n"
               "<fontconfig><cachedir>%s/cache</cachedir></fontconfig>\n", dir);
    fclose(f);
    setenv("FONTCONFIG_FILE", conf, 1);
    char output[8192];
    const char *args[] = {"figure", "impulse", "--quick", "--out", out, NULL};
    int status = test_run_rodsim_within(args, 120, output, sizeof output);
    unsetenv("FONTCONFIG_FILE");
    const char *line = strstr(output, "text:");
    check(status != 0 && strstr(output, "fonts-dejavu-core") != NULL,
          "no font known to fontconfig: exit %d, message \"%.200s\"", status,
          line ? line : output);
    check(test_dir_entries(out) <= 0, "nothing left in the output folder (%d entries)",
          test_dir_entries(out));
    test_remove_tree(dir);
}

int main(void)
{
    test_found();
    test_missing();
    return test_finish();
}
