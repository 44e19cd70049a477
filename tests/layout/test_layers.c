/* test_layers.c: who may include what (README "Layout", STYLE.md 2).
 *
 * Every file under src/ and include/ belongs to the layer named by its first
 * folder. The rules, checked on every #include line:
 *
 *  L0 Every file lies in a known layer folder: base, sim, fem, render, plot,
 *     study, api, cli (a new layer is added to the table below first); the
 *     one exception is include/rodsim.h, the library's public contract,
 *     which belongs to api.
 *  L1 Our own headers are included by layer: "layer/name.h" (and the
 *     public "rodsim.h", api's, which only api and cli include).
 *  L2 Layer order: a layer includes itself and only the layers listed here
 *     (a partial order; sim and fem are peers that do not see each other):
 *       base   -> (nothing)
 *       sim    -> base
 *       fem    -> base
 *       render -> base, sim
 *       plot   -> base, sim, render
 *       study  -> base, sim, fem, render, plot
 *       api    -> base, sim, fem, render, plot, study (the library: rodsim.h)
 *       cli    -> every layer
 *  L3 The simulation does not draw: base, sim and fem include no OpenGL
 *     (GL/, GLES*, EGL/, KHR/), PNG (png*.h), FreeType (ft2build.h,
 *     freetype*, FT_* macros) or libav* / libsw* header, nor render/ or plot/.
 *  L4 The renderer gets a plain snapshot: of sim, render includes only
 *     sim/recording.h (rod_recording: centreline, director frames, twist,
 *     time, tip loads), and the room sim/geometry/ (knot.h, proximity.h:
 *     pure geometry on a polygon: the overlay's knot type, the strands'
 *     shading; it includes nothing of the rod).
 *     Not sim/rod.h (the model and
 *     state; it comes along inside recording.h, but render does not use it),
 *     a scheme's header (sim/scheme_*.h), sim/rod_geometry.h or sim/scene.h.
 *  L5 Only src/render/gl_context.c includes OSMesa (GL/osmesa.h) or EGL, so
 *     another context can replace it.
 *  L6 Only src/render/video.c includes libav* / libsw* (tests may: they
 *     decode video; tests/ is not scanned).
 *  L7 OpenGL headers only in files named gl_*.c and in
 *     include/render/gl_api.h (the GL function table), which in turn only
 *     gl_*.c files include; other headers, gl_*.h included, stay free of GL
 *     types.
 *  L8 An #include names its header: a macro include is allowed only for
 *     FreeType's FT_* (then L3 treats it as FreeType).
 *
 *  L9 The names, not only the includes: a file of render or plot uses no
 *     name (function, type, macro, enum constant) that a sim header declares
 *     unless a header L4 allows declares it; what the picture needs
 *     of the model travels in the recording.
 *
 * The checker runs first on synthetic lines (each rule must catch its case,
 * and allowed lines must pass), then on the tree at RODSIM_SOURCE_DIR. */
#include <ctype.h>
#include <dirent.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "test.h"

#define PATH_LEN 1024

static const char *const layers[] = {"base", "sim", "fem", "render", "plot", "study", "api",
                                     "cli"};
#define LAYER_COUNT ((int)(sizeof layers / sizeof layers[0]))
#define LAYER_API 6

/* may_include[a][b]: layer a may include headers of layer b (L2). Order of
 * the rows and columns as in `layers`. */
static const int may_include[LAYER_COUNT][LAYER_COUNT] = {
    /*           base sim fem render plot study api cli */
    /* base   */ {1, 0, 0, 0, 0, 0, 0, 0},
    /* sim    */ {1, 1, 0, 0, 0, 0, 0, 0},
    /* fem    */ {1, 0, 1, 0, 0, 0, 0, 0},
    /* render */ {1, 1, 0, 1, 0, 0, 0, 0},
    /* plot   */ {1, 1, 0, 1, 1, 0, 0, 0},
    /* study  */ {1, 1, 1, 1, 1, 1, 0, 0},
    /* api    */ {1, 1, 1, 1, 1, 1, 1, 0},
    /* cli    */ {1, 1, 1, 1, 1, 1, 1, 1},
};

/* Collects the violations of the lines given to it. */
typedef struct {
    int count;
    char last[PATH_LEN + 256]; /* the last message */
    int print;                 /* print each as a FAIL line (the real tree) */
} sink;

static void report(sink *s, const char *file, int line, const char *header, const char *rule)
{
    s->count++;
    snprintf(s->last, sizeof s->last, "%s:%d: %s%s: %s", file, line,
             strncmp(rule, "L9", 2) == 0 ? "name " : "#include ", header, rule);
    if (s->print) check(0, "%s", s->last);
}

static int starts(const char *s, const char *prefix)
{
    return strncmp(s, prefix, strlen(prefix)) == 0;
}

/* Layer index of the first folder of a path like "src/sim/rod.c", -1 if none. */
static int layer_of_path(const char *path)
{
    if (strcmp(path, "include/rodsim.h") == 0) return LAYER_API; /* the public contract */
    const char *p = strchr(path, '/');
    if (!p) return -1;
    p++;
    for (int k = 0; k < LAYER_COUNT; k++) {
        size_t n = strlen(layers[k]);
        if (strncmp(p, layers[k], n) == 0 && p[n] == '/') return k;
    }
    return -1;
}

static int layer_index(const char *name, size_t n)
{
    for (int k = 0; k < LAYER_COUNT; k++)
        if (strlen(layers[k]) == n && strncmp(name, layers[k], n) == 0) return k;
    return -1;
}

static int is_gl(const char *h)
{
    return starts(h, "GL/") || starts(h, "GLES") || starts(h, "EGL/") || starts(h, "KHR/");
}
static int is_context(const char *h) { return starts(h, "GL/osmesa") || starts(h, "EGL/"); }
static int is_png(const char *h) { return starts(h, "png"); }
static int is_freetype(const char *h)
{
    return starts(h, "ft2build") || starts(h, "freetype") || starts(h, "FT_");
}
static int is_libav(const char *h) { return starts(h, "libav") || starts(h, "libsw"); }

/* Checks one source line of `file` (path from the source root); reports each
 * include that breaks a rule (the first rule it breaks). Returns 1 if the
 * line is an #include. */
static int check_line(sink *s, const char *file, int line_no, const char *text)
{
    const char *p = text;
    while (*p == ' ' || *p == '\t') p++;
    if (*p != '#') return 0;
    p++;
    while (*p == ' ' || *p == '\t') p++;
    if (!starts(p, "include")) return 0;
    p += strlen("include");
    while (*p == ' ' || *p == '\t') p++;
    char header[256];
    int quoted = *p == '"', macro = !(*p == '"' || *p == '<');
    size_t n = 0;
    if (macro) {
        while (p[n] && (isalnum((unsigned char)p[n]) || p[n] == '_')) n++;
    } else {
        const char *close = strchr(p + 1, quoted ? '"' : '>');
        p++;
        n = close ? (size_t)(close - p) : strlen(p);
    }
    if (n >= sizeof header) n = sizeof header - 1;
    memcpy(header, p, n);
    header[n] = '\0';

    const char *base = strrchr(file, '/');
    base = base ? base + 1 : file;
    size_t base_len = strlen(base);
    int is_gl_c = starts(base, "gl_") && base_len > 2 && strcmp(base + base_len - 2, ".c") == 0;
    int layer = layer_of_path(file);
    const char *slash = strchr(header, '/');
    int target = quoted && slash ? layer_index(header, (size_t)(slash - header)) : -1;
    if (quoted && strcmp(header, "rodsim.h") == 0) target = LAYER_API; /* the public header */
    char shown[300];
    snprintf(shown, sizeof shown, macro ? "%s" : quoted ? "\"%s\"" : "<%s>", header);

    if (layer < 0) {
        report(s, file, line_no, shown, "L0: the file lies in no known layer folder");
    } else if (macro && !is_freetype(header)) {
        report(s, file, line_no, shown, "L8: an include names its header (no macro)");
    } else if (quoted && target < 0) {
        report(s, file, line_no, shown, "L1: our headers are included as \"layer/name.h\"");
    } else if ((layer == 0 || layer == 1 || layer == 2) &&
               (is_gl(header) || is_png(header) || is_freetype(header) || is_libav(header) ||
                starts(header, "render/") || starts(header, "plot/"))) {
        report(s, file, line_no, shown,
               "L3: base, sim and fem do not draw (no OpenGL, PNG, FreeType, libav*, render/, plot/)");
    } else if (layer == 3 && starts(header, "sim/") && strcmp(header, "sim/recording.h") != 0 &&
               !starts(header, "sim/geometry/")) {
        report(s, file, line_no, shown,
               "L4: render takes a plain snapshot: of sim only sim/recording.h (and the "
               "polygon geometry of sim/geometry/)");
    } else if (is_context(header) && strcmp(file, "src/render/gl_context.c") != 0) {
        report(s, file, line_no, shown, "L5: OSMesa/EGL only in src/render/gl_context.c");
    } else if (is_libav(header) && strcmp(file, "src/render/video.c") != 0) {
        report(s, file, line_no, shown, "L6: libav*/libsw* only in src/render/video.c");
    } else if ((is_gl(header) && !is_gl_c && strcmp(file, "include/render/gl_api.h") != 0) ||
               (strcmp(header, "render/gl_api.h") == 0 && !is_gl_c)) {
        report(s, file, line_no, shown,
               "L7: OpenGL headers (and render/gl_api.h) only in files named gl_*.c");
    } else if (target >= 0 && !may_include[layer][target]) {
        char rule[160];
        snprintf(rule, sizeof rule, "L2: layer %s may not include layer %s (layer order)",
                 layers[layer], layers[target]);
        report(s, file, line_no, shown, rule);
    }
    return 1;
}

/* The checker catches each rule's case and passes the allowed lines. */
static void test_synthetic(void)
{
    static const struct {
        const char *file, *line, *rule; /* rule NULL: the line is allowed */
    } cases[] = {
        {"src/sim/x.c", "#include \"render/render.h\"", "L3"},
        {"src/sim/x.c", "#include <GL/gl.h>", "L3"},
        {"src/base/x.c", "#include <png.h>", "L3"},
        {"src/fem/x.c", "#include <ft2build.h>", "L3"},
        {"src/fem/x.c", "#include FT_FREETYPE_H", "L3"},
        {"include/sim/x.h", "#  include <libavcodec/avcodec.h>", "L3"},
        {"include/base/x.h", "# include \"plot/plot.h\"", "L3"},
        {"src/render/x.c", "#include \"sim/scheme_static.h\"", "L4"},
        {"src/render/x.c", "#include \"sim/rod_geometry.h\"", "L4"},
        {"include/render/x.h", "#include \"sim/scene.h\"", "L4"},
        {"src/render/gl_util.c", "#include <GL/osmesa.h>", "L5"},
        {"src/plot/gl_plot.c", "#include <EGL/egl.h>", "L5"},
        {"src/render/image.c", "#include <libavutil/frame.h>", "L6"},
        {"src/cli/run.c", "#include <libswscale/swscale.h>", "L6"},
        {"src/render/render.c", "#include <GL/gl.h>", "L7"},
        {"include/render/gl_util.h", "#include <GL/glext.h>", "L7"},
        {"src/render/render.c", "#include \"render/gl_api.h\"", "L7"},
        {"include/render/gl_api.h", "#include <GL/glcorearb.h>", NULL},
        {"src/render/gl_util.c", "#include \"render/gl_api.h\"", NULL},
        {"src/sim/rod.c", "#include \"study/validate.h\"", "L2"},
        {"src/fem/fem.c", "#include \"sim/rod.h\"", "L2"},
        {"src/sim/rod.c", "#include \"fem/fem.h\"", "L2"},
        {"src/render/x.c", "#include \"plot/plot.h\"", "L2"},
        {"src/plot/plot.c", "#include \"study/figure.h\"", "L2"},
        {"src/study/x.c", "#include \"cli/run.h\"", "L2"},
        {"src/study/x.c", "#include \"rodsim.h\"", "L2"},
        {"src/api/x.c", "#include \"cli/run.h\"", "L2"},
        {"src/api/rodsim.c", "#include \"rodsim.h\"", NULL},
        {"src/cli/live.c", "#include \"rodsim.h\"", NULL},
        {"include/rodsim.h", "#include <stddef.h>", NULL},
        {"include/x.h", "#include <stddef.h>", "L0"},
        {"src/sim/x.c", "#include \"rod.h\"", "L1"},
        {"src/sim/x.c", "#include \"tools/x.h\"", "L1"},
        {"src/sim/x.c", "#include SOME_HEADER", "L8"},
        {"src/tools/x.c", "#include <stdio.h>", "L0"},
        {"src/render/render.c", "#include \"sim/recording.h\"", NULL},
        {"src/render/render.c", "#include \"sim/geometry/knot.h\"", NULL},
        {"src/render/render.c", "#include \"sim/geometry/proximity.h\"", NULL},
        {"src/render/render.c", "#include \"sim/knot.h\"", "L4"},
        {"include/render/render.h", "#include \"sim/rod.h\"", "L4"},
        {"src/render/gl_render.c", "#include <GL/gl.h>", NULL},
        {"src/render/gl_context.c", "#include <GL/osmesa.h>", NULL},
        {"src/render/gl_context.c", "#include <EGL/egl.h>", NULL},
        {"src/render/video.c", "#include <libavcodec/avcodec.h>", NULL},
        {"src/render/text.c", "#include FT_FREETYPE_H", NULL},
        {"src/render/image.c", "#include <png.h>", NULL},
        {"src/sim/scheme_static.c", "#include <lapacke.h>", NULL},
        {"src/study/figure.c", "#include \"plot/plot.h\"", NULL},
        {"src/study/x.c", "#include \"fem/fem.h\"", NULL},
        {"src/cli/run.c", "#include \"render/render.h\"", NULL},
        {"src/sim/x.c", " * #include \"render/render.h\" in a comment", NULL},
        {"src/sim/x.c", "#define INCLUDE_GL 1", NULL},
    };
    int caught = 0, wrong = 0;
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        sink s = {0, "", 0};
        check_line(&s, cases[k].file, 7, cases[k].line);
        char where[PATH_LEN + 8];
        snprintf(where, sizeof where, "%s:7: ", cases[k].file);
        int ok;
        if (cases[k].rule) {
            ok = s.count == 1 && starts(s.last, where) && strstr(s.last, cases[k].rule) != NULL;
            caught += ok;
        } else {
            ok = s.count == 0;
        }
        if (!ok) {
            wrong++;
            check(0, "synthetic %s '%s': expected %s, got %s", cases[k].file, cases[k].line,
                  cases[k].rule ? cases[k].rule : "no violation", s.count ? s.last : "none");
        }
    }
    check(wrong == 0, "checker on %zu synthetic lines: %d violations caught with file:line and "
          "rule, the allowed lines pass", sizeof cases / sizeof cases[0], caught);
}

typedef struct {
    int files[LAYER_COUNT], unknown_files, includes;
} scan_totals;

/* Calls fn on every .c and .h file under root/rel, folders recursively, in
 * readdir order (rel: the path from the source root). */
typedef void (*file_fn)(void *context, const char *root, const char *rel);
static void walk_files(const char *root, const char *rel, file_fn fn, void *context)
{
    char full[2 * PATH_LEN];
    snprintf(full, sizeof full, "%s/%s", root, rel);
    DIR *d = opendir(full);
    if (!d) {
        check(0, "%s: cannot open the folder", full);
        return;
    }
    struct dirent *e;
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.') continue;
        char child[PATH_LEN], child_full[2 * PATH_LEN + 2];
        snprintf(child, sizeof child, "%s/%s", rel, e->d_name);
        snprintf(child_full, sizeof child_full, "%s/%s", root, child);
        struct stat st;
        if (stat(child_full, &st) != 0) continue;
        size_t n = strlen(e->d_name);
        if (S_ISDIR(st.st_mode))
            walk_files(root, child, fn, context);
        else if (n > 2 && (strcmp(e->d_name + n - 2, ".c") == 0 ||
                           strcmp(e->d_name + n - 2, ".h") == 0))
            fn(context, root, child);
    }
    closedir(d);
}

static void scan_file(sink *s, const char *root, const char *rel, scan_totals *t)
{
    char full[2 * PATH_LEN];
    snprintf(full, sizeof full, "%s/%s", root, rel);
    FILE *f = fopen(full, "r");
    if (!f) {
        check(0, "%s: cannot open", full);
        return;
    }
    int layer = layer_of_path(rel);
    if (layer >= 0) t->files[layer]++;
    else t->unknown_files++;
    char line[4096];
    int line_no = 0, any = 0;
    while (fgets(line, sizeof line, f)) {
        line_no++;
        t->includes += check_line(s, rel, line_no, line);
        any = 1;
    }
    fclose(f);
    /* a file without includes still has to lie in a layer */
    if (layer < 0 && !any) report(s, rel, 1, "(none)", "L0: the file lies in no known layer folder");
}

typedef struct {
    sink *s;
    scan_totals *t;
} tree_scan;

static void scan_one(void *context, const char *root, const char *rel)
{
    tree_scan *ts = context;
    scan_file(ts->s, root, rel, ts->t);
}

static void test_tree(void)
{
    sink s = {0, "", 1};
    scan_totals t = {{0}, 0, 0};
    tree_scan ts = {&s, &t};
    walk_files(RODSIM_SOURCE_DIR, "src", scan_one, &ts);
    walk_files(RODSIM_SOURCE_DIR, "include", scan_one, &ts);
    int files = t.unknown_files;
    for (int k = 0; k < LAYER_COUNT; k++) files += t.files[k];
    /* guards against a vacuous pass: every layer has files, and the tree is
     * about the size it was when the rules were written (60+ files) */
    int every_layer = 1;
    for (int k = 0; k < LAYER_COUNT; k++) every_layer &= t.files[k] > 0;
    check(every_layer && files >= 40 && t.includes >= 200,
          "scanned %d files (base %d, sim %d, fem %d, render %d, plot %d, study %d, api %d, "
          "cli %d) with %d #include lines under %s", files, t.files[0], t.files[1], t.files[2],
          t.files[3], t.files[4], t.files[5], t.files[6], t.files[7], t.includes,
          RODSIM_SOURCE_DIR);
    check(s.count == 0, "src/ and include/ follow the include rules L0-L8: %d violations",
          s.count);
}

/* ---- L9: the names a render or plot file uses ------------------------- */

#define MAX_NAMES 4096
#define NAME_LEN 64

/* Names declared by the sim headers, each with whether an L4 header (the
 * renderer's allowed view) declares it and the header that does. */
typedef struct {
    int count;
    char name[MAX_NAMES][NAME_LEN];
    char header[MAX_NAMES][NAME_LEN];
    int allowed[MAX_NAMES];
} name_table;

static int is_allowed_header(const char *rel)
{
    return strcmp(rel, "include/sim/recording.h") == 0 || starts(rel, "include/sim/geometry/");
}

static int name_index(const name_table *t, const char *name)
{
    for (int k = 0; k < t->count; k++)
        if (strcmp(t->name[k], name) == 0) return k;
    return -1;
}

static void add_name(name_table *t, const char *name, size_t n, const char *rel)
{
    char word[NAME_LEN];
    if (n == 0 || n >= sizeof word) return;
    memcpy(word, name, n);
    word[n] = '\0';
    static const char *const keywords[] = {"if", "for", "while", "return", "sizeof", "switch",
                                           "struct", "enum", "typedef", "const", "void"};
    for (size_t k = 0; k < sizeof keywords / sizeof keywords[0]; k++)
        if (strcmp(word, keywords[k]) == 0) return;
    int at = name_index(t, word), allowed = is_allowed_header(rel);
    if (at < 0 && t->count < MAX_NAMES) {
        at = t->count++;
        snprintf(t->name[at], NAME_LEN, "%s", word);
        snprintf(t->header[at], NAME_LEN, "%s", rel + strlen("include/"));
        t->allowed[at] = 0;
    }
    if (at >= 0 && allowed) t->allowed[at] = 1;
}

static size_t ident_len(const char *p)
{
    size_t n = 0;
    if (!(isalpha((unsigned char)p[0]) || p[0] == '_')) return 0;
    while (isalnum((unsigned char)p[n]) || p[n] == '_') n++;
    return n;
}

/* The declarations of one header line, outside comments (the caller strips
 * them): `#define NAME`, `} NAME;`, `typedef ... NAME;`, a prototype
 * `TYPE NAME(` at the start of a line, an enum constant `    NAME = ` or
 * `    NAME,` in capitals. */
static void declared_names(name_table *t, const char *line, const char *rel)
{
    const char *p = line;
    while (*p == ' ' || *p == '\t') p++;
    if (starts(p, "#define")) {
        p += strlen("#define");
        while (*p == ' ') p++;
        add_name(t, p, ident_len(p), rel);
        return;
    }
    if (*p == '}') {
        p++;
        while (*p == ' ') p++;
        add_name(t, p, ident_len(p), rel);
        return;
    }
    const char *semi = strrchr(p, ';');
    if (starts(p, "typedef") && semi) {
        const char *e = semi;
        while (e > p && !(isalnum((unsigned char)e[-1]) || e[-1] == '_')) e--;
        const char *b = e;
        while (b > p && (isalnum((unsigned char)b[-1]) || b[-1] == '_')) b--;
        add_name(t, b, (size_t)(e - b), rel);
        return;
    }
    if (line[0] != ' ' && line[0] != '\t' && line[0] != '#') {
        const char *paren = strchr(line, '(');
        if (paren) {
            const char *e = paren;
            while (e > line && e[-1] == ' ') e--;
            const char *b = e;
            while (b > line && (isalnum((unsigned char)b[-1]) || b[-1] == '_')) b--;
            if (b > line) add_name(t, b, (size_t)(e - b), rel);
        }
        return;
    }
    size_t n = ident_len(p);
    if (n > 3 && isupper((unsigned char)p[0])) {
        int capitals = 1;
        for (size_t k = 0; k < n; k++) capitals &= !islower((unsigned char)p[k]);
        const char *after = p + n;
        while (*after == ' ') after++;
        if (capitals && (*after == '=' || *after == ',' || *after == '\n' || *after == '\0'))
            add_name(t, p, n, rel);
    }
}

/* Removes comments and string literals from a line in place; *in_comment
 * carries a block comment across lines. */
static void strip_line(char *line, int *in_comment)
{
    char *out = line;
    for (char *p = line; *p;) {
        if (*in_comment) {
            if (p[0] == '*' && p[1] == '/') {
                *in_comment = 0;
                p += 2;
            } else {
                p++;
            }
        } else if (p[0] == '/' && p[1] == '*') {
            *in_comment = 1;
            p += 2;
        } else if (p[0] == '/' && p[1] == '/') {
            break;
        } else if (*p == '"' || *p == '\'') {
            char quote = *p++;
            while (*p && *p != quote) p += (*p == '\\' && p[1]) ? 2 : 1;
            if (*p) p++;
            *out++ = ' ';
        } else {
            *out++ = *p++;
        }
    }
    *out = '\0';
}

/* Reports each name of `text` (one line, stripped) that a sim header
 * declares outside the renderer's view (L9). */
static void check_names(sink *s, const name_table *t, const char *file, int line_no,
                        const char *text)
{
    for (const char *p = text; *p;) {
        size_t n = ident_len(p);
        if (!n || (p > text && (isalnum((unsigned char)p[-1]) || p[-1] == '_'))) {
            p += n ? n : 1;
            continue;
        }
        char word[NAME_LEN];
        if (n < sizeof word) {
            memcpy(word, p, n);
            word[n] = '\0';
            int at = name_index(t, word);
            if (at >= 0 && !t->allowed[at]) {
                char rule[NAME_LEN * 2 + 128];
                snprintf(rule, sizeof rule, "L9: render and plot take a plain snapshot: %s is "
                         "declared in %s, not in the recording", word, t->header[at]);
                report(s, file, line_no, word, rule);
            }
        }
        p += n;
    }
}

typedef void (*line_fn)(void *context, const char *rel, int line_no, char *text);

typedef struct {
    line_fn fn;
    void *context;
} line_walk;

/* Calls the line_walk's fn on every line of one file, comments and strings
 * stripped. */
static void file_lines(void *context, const char *root, const char *rel)
{
    const line_walk *w = context;
    char full[2 * PATH_LEN + 2];
    snprintf(full, sizeof full, "%s/%s", root, rel);
    FILE *f = fopen(full, "r");
    if (!f) return;
    char line[4096];
    int line_no = 0, in_comment = 0;
    while (fgets(line, sizeof line, f)) {
        strip_line(line, &in_comment);
        w->fn(w->context, rel, ++line_no, line);
    }
    fclose(f);
}

/* Calls fn on every stripped line of the .c and .h files under root/rel. */
static void walk_lines(const char *root, const char *rel, line_fn fn, void *context)
{
    line_walk w = {fn, context};
    walk_files(root, rel, file_lines, &w);
}

static void collect_line(void *context, const char *rel, int line_no, char *text)
{
    (void)line_no;
    declared_names(context, text, rel);
}

typedef struct {
    sink *s;
    const name_table *t;
    int lines;
} names_scan;

static void names_line(void *context, const char *rel, int line_no, char *text)
{
    names_scan *n = context;
    n->lines++;
    check_names(n->s, n->t, rel, line_no, text);
}

static void test_names(void)
{
    static name_table t;
    t.count = 0;
    walk_lines(RODSIM_SOURCE_DIR, "include/sim", collect_line, &t);
    int allowed = 0;
    for (int k = 0; k < t.count; k++) allowed += t.allowed[k];
    int has_state = name_index(&t, "rod_state"), has_recording = name_index(&t, "rod_recording");
    check(t.count > 100 && has_state >= 0 && !t.allowed[has_state] && has_recording >= 0 &&
              t.allowed[has_recording],
          "L9: %d names declared by the sim headers, %d of them in the renderer's view "
          "(rod_state outside it, rod_recording inside)", t.count, allowed);
    /* the checker on synthetic lines */
    sink probe = {0, "", 0};
    char line[] = "    const rod_state *s = rod_recording_frame(r); /* rod_model */";
    int in_comment = 0;
    strip_line(line, &in_comment);
    check_names(&probe, &t, "src/render/x.c", 3, line);
    check(probe.count == 1 && strstr(probe.last, "rod_state is declared in sim/rod_types.h") != NULL,
          "L9 on a synthetic line: a sim name outside the recording is caught (%s), the "
          "recording's name and a name in a comment are not", probe.last);
    /* the tree */
    sink s = {0, "", 1};
    names_scan scan = {&s, &t, 0};
    walk_lines(RODSIM_SOURCE_DIR, "src/render", names_line, &scan);
    walk_lines(RODSIM_SOURCE_DIR, "include/render", names_line, &scan);
    walk_lines(RODSIM_SOURCE_DIR, "src/plot", names_line, &scan);
    walk_lines(RODSIM_SOURCE_DIR, "include/plot", names_line, &scan);
    check(scan.lines > 1000 && s.count == 0,
          "L9: the %d lines of render and plot use no sim name outside the recording: %d "
          "violations", scan.lines, s.count);
}

int main(void)
{
    test_synthetic();
    test_tree();
    test_names();
    return test_finish();
}
