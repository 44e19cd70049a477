/* ini.c: strict INI scene files (see ini.h). */
#include "base/ini.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "base/suggest.h"
#include "base/textfile.h"

typedef struct ini_entry {
    char *section;
    int instance;
    char *key;
    char *value;
    int line;      /* 0 when it came from --set */
    int used;
} ini_entry;

typedef struct ini_section {
    char *name;
    int instance;
    int line;      /* 0 when created by --set */
} ini_section;

typedef struct ini_known {
    char *section;
    char *key;     /* NULL: the section itself was asked for */
    int max_index; /* section rows: the highest instance a key was asked of, or -1 */
} ini_known;

/* The most aliases a doc holds at once (ini_alias) */
#define INI_ALIASES 8

struct ini_doc {
    char *filename;
    char alias_from[INI_ALIASES][32], alias_to[INI_ALIASES][96]; /* ini_alias */
    int alias_count;
    ini_entry *entries;
    int entry_count, entry_cap;
    ini_section *sections;
    int section_count, section_cap;
    ini_known *known;
    int known_count, known_cap;
};

static char *dup_range(const char *begin, const char *end)
{
    size_t n = (size_t)(end - begin);
    char *s = malloc(n + 1);
    if (!s) return NULL;
    memcpy(s, begin, n);
    s[n] = '\0';
    return s;
}

static char *dup_string(const char *s) { return dup_range(s, s + strlen(s)); }

static int grow(void **array, int *cap, int need, size_t size)
{
    if (need <= *cap) return 0;
    int next = *cap ? *cap * 2 : 16;
    while (next < need) next *= 2;
    void *p = realloc(*array, (size_t)next * size);
    if (!p) return -1;
    *array = p;
    *cap = next;
    return 0;
}

static void trim(const char **begin, const char **end)
{
    while (*begin < *end && isspace((unsigned char)**begin)) (*begin)++;
    while (*end > *begin && isspace((unsigned char)(*end)[-1])) (*end)--;
}

static int valid_name(const char *begin, const char *end)
{
    if (begin == end) return 0;
    for (const char *p = begin; p < end; p++)
        if (!isalnum((unsigned char)*p) && *p != '_' && *p != '-') return 0;
    return 1;
}

/* A section's name: a word, or two words ([rod NAME]) separated by one space */
static int valid_section(const char *begin, const char *end)
{
    const char *space = memchr(begin, ' ', (size_t)(end - begin));
    return space ? valid_name(begin, space) && valid_name(space + 1, end) : valid_name(begin, end);
}

/* A scene's named set of --set assignments, [variant NAME]: its keys are
 * section.key (ini_set's forms), applied by --set variant=NAME. */
static int is_variant(const char *section)
{
    return strncmp(section, "variant ", 8) == 0;
}

/* A [variant NAME]'s key: ini_set's left-hand side, words joined by dots
 * (one space in a named section's word: "rod a.length") */
static int valid_assigned_key(const char *begin, const char *end)
{
    const char *dot = memchr(begin, '.', (size_t)(end - begin));
    if (!dot || dot == begin || dot + 1 == end) return 0;
    for (const char *p = begin; p < end; p++)
        if (!isalnum((unsigned char)*p) && *p != '_' && *p != '-' && *p != '.' && *p != ' ')
            return 0;
    return 1;
}

static int section_instances(const ini_doc *doc, const char *name)
{
    int n = 0;
    for (int i = 0; i < doc->section_count; i++)
        if (strcmp(doc->sections[i].name, name) == 0) n++;
    return n;
}

static const ini_section *find_section(const ini_doc *doc, const char *name, int instance)
{
    for (int i = 0; i < doc->section_count; i++)
        if (strcmp(doc->sections[i].name, name) == 0 && doc->sections[i].instance == instance)
            return &doc->sections[i];
    return NULL;
}

static ini_entry *find_entry(const ini_doc *doc, const char *section, int instance,
                             const char *key)
{
    for (int i = 0; i < doc->entry_count; i++) {
        ini_entry *e = &doc->entries[i];
        if (e->instance == instance && strcmp(e->section, section) == 0 &&
            strcmp(e->key, key) == 0)
            return e;
    }
    return NULL;
}

/* The section a lookup of `section` reads (ini_alias) */
static const char *resolve(const ini_doc *doc, const char *section)
{
    for (int i = 0; i < doc->alias_count; i++)
        if (strcmp(doc->alias_from[i], section) == 0) return doc->alias_to[i];
    return section;
}

int ini_alias(ini_doc *doc, const char *section, const char *actual)
{
    int at = 0;
    while (at < doc->alias_count && strcmp(doc->alias_from[at], section) != 0) at++;
    if (!actual) { /* remove: the last one takes its place */
        if (at < doc->alias_count) {
            doc->alias_count--;
            memcpy(doc->alias_from[at], doc->alias_from[doc->alias_count], sizeof doc->alias_from[at]);
            memcpy(doc->alias_to[at], doc->alias_to[doc->alias_count], sizeof doc->alias_to[at]);
        }
        return 0;
    }
    if (at == INI_ALIASES || strlen(section) >= sizeof doc->alias_from[0] ||
        strlen(actual) >= sizeof doc->alias_to[0])
        return -1;
    snprintf(doc->alias_from[at], sizeof doc->alias_from[at], "%s", section);
    snprintf(doc->alias_to[at], sizeof doc->alias_to[at], "%s", actual);
    if (at == doc->alias_count) doc->alias_count++;
    return 0;
}

int ini_section_names(const ini_doc *doc, const char *word, const char **names, int most)
{
    const size_t n = strlen(word);
    int count = 0;
    for (int i = 0; i < doc->section_count; i++) {
        const char *name = doc->sections[i].name;
        if (strncmp(name, word, n) != 0 || name[n] != ' ' || doc->sections[i].instance > 0)
            continue;
        if (count < most) names[count] = name + n + 1;
        count++;
    }
    return count;
}

static int add_section(ini_doc *doc, const char *name, int line)
{
    if (grow((void **)&doc->sections, &doc->section_cap, doc->section_count + 1,
             sizeof *doc->sections))
        return -1;
    ini_section *s = &doc->sections[doc->section_count];
    s->name = dup_string(name);
    if (!s->name) return -1;
    s->instance = section_instances(doc, name);
    s->line = line;
    doc->section_count++;
    return 0;
}

static int add_entry(ini_doc *doc, const char *section, int instance, const char *key,
                     const char *value, int line)
{
    if (grow((void **)&doc->entries, &doc->entry_cap, doc->entry_count + 1, sizeof *doc->entries))
        return -1;
    ini_entry *e = &doc->entries[doc->entry_count];
    e->section = dup_string(section);
    e->key = dup_string(key);
    e->value = dup_string(value);
    if (!e->section || !e->key || !e->value) {
        free(e->section); free(e->key); free(e->value);
        return -1;
    }
    e->instance = instance;
    e->line = line;
    e->used = 0;
    doc->entry_count++;
    return 0;
}

static void mark_known(ini_doc *doc, const char *section, const char *key)
{
    for (int i = 0; i < doc->known_count; i++) {
        ini_known *k = &doc->known[i];
        if (strcmp(k->section, section) != 0) continue;
        if ((key == NULL && k->key == NULL) || (key && k->key && strcmp(k->key, key) == 0)) return;
    }
    if (grow((void **)&doc->known, &doc->known_cap, doc->known_count + 1, sizeof *doc->known))
        return; /* only weakens the list of accepted keys in a message */
    ini_known *k = &doc->known[doc->known_count];
    k->section = dup_string(section);
    k->key = key ? dup_string(key) : NULL;
    k->max_index = -1;
    if (!k->section || (key && !k->key)) {
        free(k->section); free(k->key);
        return;
    }
    doc->known_count++;
}

static void set_error(char *err, size_t errlen, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static void set_error(char *err, size_t errlen, const char *fmt, ...)
{
    if (!err || errlen == 0) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
}

ini_doc *ini_parse(const char *name, const char *text, char *err, size_t errlen)
{
    ini_doc *doc = calloc(1, sizeof *doc);
    if (!doc || !(doc->filename = dup_string(name))) {
        free(doc);
        set_error(err, errlen, "%s: out of memory", name);
        return NULL;
    }
    const char *current = NULL; /* section name of the lines being read */
    char *current_owned = NULL;
    int line = 0;
    const char *p = textfile_skip_bom(text);
    while (*p) {
        line++;
        const char *eol = strchr(p, '\n');
        if (!eol) eol = p + strlen(p);
        /* cut the comment: '#' outside double quotes */
        const char *end = p;
        int quoted = 0;
        while (end < eol && (quoted || *end != '#')) {
            if (*end == '"') quoted = !quoted;
            end++;
        }
        const char *begin = p;
        trim(&begin, &end);
        p = *eol ? eol + 1 : eol;
        if (begin == end) continue;
        if (*begin == '[') {
            if (end[-1] != ']') {
                set_error(err, errlen, "%s:%d: section header must look like [name]", name, line);
                goto fail;
            }
            const char *nb = begin + 1, *ne = end - 1;
            trim(&nb, &ne);
            /* [word NAME]: a named instance (several rods: [rod a], [ends a]) */
            const char *wb = nb, *we = nb;
            while (we < ne && !isspace((unsigned char)*we)) we++;
            const char *mb = we, *me = ne;
            trim(&mb, &me);
            if (!valid_name(wb, we) || (mb < me && !valid_name(mb, me))) {
                set_error(err, errlen, "%s:%d: bad section name (letters, digits, _ and - only; "
                          "or two such words, [rod NAME])", name, line);
                goto fail;
            }
            if (we - wb == 7 && strncmp(wb, "variant", 7) == 0 && mb == me) {
                set_error(err, errlen, "%s:%d: [variant] needs a name: [variant NAME], chosen "
                          "by --set variant=NAME", name, line);
                goto fail;
            }
            free(current_owned);
            current_owned = malloc((size_t)(ne - nb) + 2);
            if (current_owned)
                snprintf(current_owned, (size_t)(ne - nb) + 2, "%.*s%s%.*s", (int)(we - wb), wb,
                         mb < me ? " " : "", (int)(me - mb), mb);
            if (!current_owned || add_section(doc, current_owned, line)) goto oom;
            current = current_owned;
            continue;
        }
        const char *eq = memchr(begin, '=', (size_t)(end - begin));
        if (!eq) {
            set_error(err, errlen, "%s:%d: expected 'key = value' or '[section]', got '%.*s'",
                      name, line, (int)(end - begin), begin);
            goto fail;
        }
        const char *kb = begin, *ke = eq, *vb = eq + 1, *ve = end;
        trim(&kb, &ke);
        trim(&vb, &ve);
        if (!current) {
            set_error(err, errlen, "%s:%d: key outside any section: %.*s comes before the first "
                      "[section] line; accepted before it: only blank lines and # comments (put "
                      "the key under the [section] it belongs to)",
                      name, line, (int)(ke - kb < 64 ? ke - kb : 64), kb);
            goto fail;
        }
        if (is_variant(current) ? !valid_assigned_key(kb, ke) : !valid_name(kb, ke)) {
            if (is_variant(current))
                set_error(err, errlen, "%s:%d: [%s]: bad key '%.*s'; accepted: section.key = "
                          "value, as --set takes it (e.g. ends.tip_motion = FILE.csv)",
                          name, line, current, (int)(ke - kb), kb);
            else
                set_error(err, errlen, "%s:%d: bad key name '%.*s' (letters, digits, _ and - "
                          "only)", name, line, (int)(ke - kb), kb);
            goto fail;
        }
        if (ve - vb >= 2 && *vb == '"' && ve[-1] == '"') { vb++; ve--; }
        char *key = dup_range(kb, ke), *value = dup_range(vb, ve);
        if (!key || !value) { free(key); free(value); goto oom; }
        int instance = section_instances(doc, current) - 1;
        ini_entry *twin = find_entry(doc, current, instance, key);
        if (twin) {
            set_error(err, errlen, "%s:%d: [%s] %s is given twice (first on line %d)", name, line,
                      current, key, twin->line);
            free(key); free(value);
            goto fail;
        }
        int rc = add_entry(doc, current, instance, key, value, line);
        free(key); free(value);
        if (rc) goto oom;
    }
    free(current_owned);
    return doc;
oom:
    set_error(err, errlen, "%s: out of memory", name);
fail:
    free(current_owned);
    ini_destroy(doc);
    return NULL;
}

ini_doc *ini_load(const char *path, char *err, size_t errlen)
{
    char *text;
    if (textfile_read(path, "scene", INI_MAX_BYTES, &text, NULL, err, errlen)) {
        /* "rodsim run my_rod" for my_rod.ini: name the file that is there */
        char with_ini[4096];
        size_t n = err ? strlen(err) : 0;
        if (err && n + 1 < errlen && access(path, F_OK) != 0 &&
            snprintf(with_ini, sizeof with_ini, "%s.ini", path) < (int)sizeof with_ini &&
            access(with_ini, R_OK) == 0)
            snprintf(err + n, errlen - n, "; did you mean %s?", with_ini);
        return NULL;
    }
    ini_doc *doc = ini_parse(path, text, err, errlen);
    free(text);
    return doc;
}

void ini_destroy(ini_doc *doc)
{
    if (!doc) return;
    for (int i = 0; i < doc->entry_count; i++) {
        free(doc->entries[i].section);
        free(doc->entries[i].key);
        free(doc->entries[i].value);
    }
    for (int i = 0; i < doc->section_count; i++) free(doc->sections[i].name);
    for (int i = 0; i < doc->known_count; i++) {
        free(doc->known[i].section);
        free(doc->known[i].key);
    }
    free(doc->entries);
    free(doc->sections);
    free(doc->known);
    free(doc->filename);
    free(doc);
}

/* The instance of a repeatable section whose `name` key is `name`, or -1. */
static int named_instance(const ini_doc *doc, const char *section, const char *name)
{
    for (int i = 0; find_section(doc, section, i); i++) {
        const ini_entry *e = find_entry(doc, section, i, "name");
        if (e && strcmp(e->value, name) == 0) return i;
    }
    return -1;
}

/* ini_set's "section.NAME.key=value": the instance named NAME. */
static int set_named(ini_doc *doc, const char *assignment, const char *dot, const char *dot2,
                     const char *eq, char *err, size_t errlen)
{
    char *section = dup_range(assignment, dot), *name = dup_range(dot + 1, dot2);
    int rc = -1;
    if (!section || !name) {
        set_error(err, errlen, "--set: out of memory");
    } else {
        const int instance = named_instance(doc, section, name);
        if (instance < 0) {
            set_error(err, errlen, "--set %.*s: no [%s] has name = %s", (int)(eq - assignment),
                      assignment, section, name);
        } else {
            char *key = dup_range(dot2 + 1, eq);
            const char *vb = eq + 1, *ve = eq + strlen(eq);
            trim(&vb, &ve);
            if (ve - vb >= 2 && *vb == '"' && ve[-1] == '"') { vb++; ve--; }
            char *value = dup_range(vb, ve);
            ini_entry *e = key && value ? find_entry(doc, section, instance, key) : NULL;
            if (!key || !value) {
                set_error(err, errlen, "--set: out of memory");
            } else if (e) {
                free(e->value);
                rc = (e->value = dup_string(value)) ? 0 : -1;
                e->line = 0;
            } else {
                rc = add_entry(doc, section, instance, key, value, 0);
            }
            if (rc && key && value) set_error(err, errlen, "--set: out of memory");
            free(key);
            free(value);
        }
    }
    free(section);
    free(name);
    return rc;
}

/* ini_set's "variant=NAME": the assignments of [variant NAME], in file
 * order, each at its own line (a bad value is reported there). */
static int set_variant(ini_doc *doc, const char *name, char *err, size_t errlen)
{
    char section[96];
    snprintf(section, sizeof section, "variant %s", name);
    if (!*name || strlen(name) + 9 > sizeof section || !find_section(doc, section, 0)) {
        char list[256] = "";
        size_t used = 0;
        for (int i = 0; i < doc->section_count; i++) {
            const char *s = doc->sections[i].name;
            if (!is_variant(s)) continue;
            int w = snprintf(list + used, sizeof list - used, "%s%s", used ? ", " : "", s + 8);
            if (w < 0 || used + (size_t)w >= sizeof list) break;
            used += (size_t)w;
        }
        set_error(err, errlen, "--set variant=%s: %s has no [variant %s]; accepted: %s", name,
                  doc->filename, name, used ? list : "none (the scene names no [variant NAME])");
        return -1;
    }
    for (int i = 0; i < doc->entry_count; i++) {
        if (strcmp(doc->entries[i].section, section) != 0) continue;
        const int line = doc->entries[i].line;
        const char *key = doc->entries[i].key;
        const size_t n = strlen(key) + strlen(doc->entries[i].value) + 2;
        char *assignment = malloc(n), inner[400];
        if (!assignment) {
            set_error(err, errlen, "--set: out of memory");
            return -1;
        }
        snprintf(assignment, n, "%s=%s", key, doc->entries[i].value);
        const int rc = is_variant(key) ? -1 : ini_set(doc, assignment, inner, sizeof inner);
        if (rc && is_variant(key))
            snprintf(inner, sizeof inner, "a variant sets no variant's key");
        /* a plain section.key: its value's messages name this line */
        const char *dot = strchr(assignment, '.'), *eq = strchr(assignment, '=');
        if (!rc && dot && eq && dot < eq && !memchr(dot + 1, '.', (size_t)(eq - dot - 1)) &&
            !memchr(assignment, ' ', (size_t)(dot - assignment))) {
            char *target = dup_range(assignment, dot), *keyname = dup_range(dot + 1, eq);
            ini_entry *e = target && keyname ? find_entry(doc, target, 0, keyname) : NULL;
            if (e) e->line = line;
            free(target);
            free(keyname);
        }
        free(assignment);
        if (rc) {
            set_error(err, errlen, "%s:%d: [%s]: %s", doc->filename, line, section, inner);
            return -1;
        }
    }
    return 0;
}

int ini_set(ini_doc *doc, const char *assignment, char *err, size_t errlen)
{
    const char *dot = strchr(assignment, '.');
    const char *eq = strchr(assignment, '=');
    if (eq && eq - assignment == 7 && strncmp(assignment, "variant", 7) == 0) {
        const char *vb = eq + 1, *ve = eq + strlen(eq);
        trim(&vb, &ve);
        char *name = dup_range(vb, ve);
        const int rc = name ? set_variant(doc, name, err, errlen) : -1;
        if (!name) set_error(err, errlen, "--set: out of memory");
        free(name);
        return rc;
    }
    const char *dot2 = dot && eq ? memchr(dot + 1, '.', (size_t)(eq - dot - 1)) : NULL;
    if (dot2 && valid_name(assignment, dot) && valid_name(dot + 1, dot2) && valid_name(dot2 + 1, eq))
        return set_named(doc, assignment, dot, dot2, eq, err, errlen);
    if (!dot || !eq || dot > eq || !valid_section(assignment, dot) || !valid_name(dot + 1, eq)) {
        set_error(err, errlen, "--set %s: expected section.key=value, e.g. solver.dt=0.01",
                  assignment);
        return -1;
    }
    char *section = dup_range(assignment, dot);
    char *key = dup_range(dot + 1, eq);
    const char *vb = eq + 1, *ve = eq + strlen(eq);
    trim(&vb, &ve);
    if (ve - vb >= 2 && *vb == '"' && ve[-1] == '"') { vb++; ve--; }
    char *value = dup_range(vb, ve);
    int rc = -1;
    if (!section || !key || !value) {
        set_error(err, errlen, "--set: out of memory");
        goto done;
    }
    if (!find_section(doc, section, 0) && add_section(doc, section, 0)) goto oom;
    ini_entry *e = find_entry(doc, section, 0, key);
    if (e) {
        free(e->value);
        if (!(e->value = dup_string(value))) goto oom;
        e->line = 0;
    } else if (add_entry(doc, section, 0, key, value, 0)) {
        goto oom;
    }
    rc = 0;
    goto done;
oom:
    set_error(err, errlen, "--set: out of memory");
done:
    free(section); free(key); free(value);
    return rc;
}

const char *ini_filename(const ini_doc *doc) { return doc->filename; }

void ini_scene_name(const ini_doc *doc, char *out, size_t outlen)
{
    const char *base = strrchr(doc->filename, '/');
    base = base ? base + 1 : doc->filename;
    const char *ext = strrchr(base, '.');
    size_t n = ext && ext > base ? (size_t)(ext - base) : strlen(base);
    snprintf(out, outlen, "%.*s", (int)n, base);
}

void ini_directory(const ini_doc *doc, char *out, size_t outlen)
{
    const char *slash = strrchr(doc->filename, '/');
    if (!slash) snprintf(out, outlen, ".");
    else if (slash == doc->filename) snprintf(out, outlen, "/");
    else snprintf(out, outlen, "%.*s", (int)(slash - doc->filename), doc->filename);
}

int ini_section_count(ini_doc *doc, const char *section)
{
    section = resolve(doc, section);
    mark_known(doc, section, NULL);
    return section_instances(doc, section);
}

int ini_section_line(const ini_doc *doc, const char *section, int index)
{
    const ini_section *s = find_section(doc, resolve(doc, section), index);
    return s ? s->line : 0;
}

/* "file:line: [section] key = value" or "--set section.key=value" */
static int describe(const ini_doc *doc, const ini_entry *e, const char *section, int index,
                    const char *key, char *out, size_t outlen)
{
    int instances = section_instances(doc, section);
    char which[32] = "";
    if (instances > 1) snprintf(which, sizeof which, " #%d", index + 1);
    if (e && e->line == 0)
        return snprintf(out, outlen, "--set %s.%s=%s", section, key, e->value);
    if (e)
        return snprintf(out, outlen, "%s:%d: [%s%s] %s = %s", doc->filename, e->line, section,
                         which, key, e->value);
    const ini_section *s = find_section(doc, section, index);
    if (s && s->line > 0)
        return snprintf(out, outlen, "%s:%d: [%s%s] %s", doc->filename, s->line, section, which,
                        key);
    return snprintf(out, outlen, "%s: [%s%s] %s", doc->filename, section, which, key);
}

int ini_error(const ini_doc *doc, const char *section, int index, const char *key, char *err,
              size_t errlen, const char *fmt, ...)
{
    if (!err || errlen == 0) return -1;
    section = resolve(doc, section);
    const ini_entry *e = find_entry(doc, section, index, key);
    int n = describe(doc, e, section, index, key, err, errlen);
    if (n < 0 || (size_t)n + 2 >= errlen) return -1;
    err[n] = ':';
    err[n + 1] = ' ';
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err + n + 2, errlen - (size_t)n - 2, fmt, ap);
    va_end(ap);
    return -1;
}

/* Notes that a key of instance `index` of `section` was asked for: a section
 * whose reader never asks past instance 0 is one it reads once. */
static void mark_instance(ini_doc *doc, const char *section, int index)
{
    for (int i = 0; i < doc->known_count; i++) {
        ini_known *k = &doc->known[i];
        if (!k->key && strcmp(k->section, section) == 0 && index > k->max_index)
            k->max_index = index;
    }
}

int ini_get_string(ini_doc *doc, const char *section, int index, const char *key,
                   const char **out, char *err, size_t errlen)
{
    (void)err; (void)errlen;
    section = resolve(doc, section);
    mark_known(doc, section, NULL);
    mark_instance(doc, section, index);
    mark_known(doc, section, key);
    ini_entry *e = find_entry(doc, section, index, key);
    if (!e) return 0;
    e->used = 1;
    *out = e->value;
    return 1;
}

/* Parses a double filling the whole [begin, end); 0 on success. */
static int parse_number(const char *begin, const char *end, double *out)
{
    if (begin == end) return -1;
    char buf[64];
    size_t n = (size_t)(end - begin);
    if (n >= sizeof buf) return -1;
    memcpy(buf, begin, n);
    buf[n] = '\0';
    char *stop;
    errno = 0;
    double v = strtod(buf, &stop);
    if (*stop != '\0' || errno == ERANGE || !isfinite(v)) return -1;
    /* strtod accepts hex floats and "inf"/"nan"; a scene wants plain decimals */
    for (const char *c = buf; *c; c++)
        if (!strchr("0123456789+-.eE", *c)) return -1;
    *out = v;
    return 0;
}

int ini_get_double(ini_doc *doc, const char *section, int index, const char *key, double *out,
                   char *err, size_t errlen)
{
    const char *text;
    int rc = ini_get_string(doc, section, index, key, &text, err, errlen);
    if (rc <= 0) return rc;
    double v;
    if (parse_number(text, text + strlen(text), &v))
        return ini_error(doc, section, index, key, err, errlen,
                         "not a number; expected a decimal such as 0.001 or 87.5e6");
    *out = v;
    return 1;
}

int ini_get_int(ini_doc *doc, const char *section, int index, const char *key, int *out,
                char *err, size_t errlen)
{
    const char *text;
    int rc = ini_get_string(doc, section, index, key, &text, err, errlen);
    if (rc <= 0) return rc;
    char *stop;
    errno = 0;
    long v = strtol(text, &stop, 10);
    if (*text == '\0' || *stop != '\0' || errno == ERANGE || v < -2147483647L || v > 2147483647L)
        return ini_error(doc, section, index, key, err, errlen,
                         "not a whole number; expected digits such as 51");
    *out = (int)v;
    return 1;
}

int ini_get_vector(ini_doc *doc, const char *section, int index, const char *key, double *out,
                   int n, char *err, size_t errlen)
{
    const char *text;
    int rc = ini_get_string(doc, section, index, key, &text, err, errlen);
    if (rc <= 0) return rc;
    double values[16];
    int count = 0;
    const char *p = text;
    for (;;) {
        while (*p && (isspace((unsigned char)*p) || *p == ',')) p++;
        if (!*p) break;
        const char *b = p;
        while (*p && !isspace((unsigned char)*p) && *p != ',') p++;
        if (count >= n || count >= 16 || parse_number(b, p, &values[count]))
            return ini_error(doc, section, index, key, err, errlen,
                             "expected %d number%s separated by spaces, e.g. '%s'", n,
                             n == 1 ? "" : "s",
                             n == 3 ? "0 4.5e-7 0" : n == 2 ? "0 -100" : "0");
        count++;
    }
    if (count != n)
        return ini_error(doc, section, index, key, err, errlen,
                         "expected %d number%s, got %d", n, n == 1 ? "" : "s", count);
    memcpy(out, values, (size_t)n * sizeof *out);
    return 1;
}

int ini_get_choice(ini_doc *doc, const char *section, int index, const char *key,
                   const char *const *choices, int *out, char *err, size_t errlen)
{
    const char *text;
    int rc = ini_get_string(doc, section, index, key, &text, err, errlen);
    if (rc <= 0) return rc;
    char list[256] = "";
    size_t used = 0;
    for (int i = 0; choices[i]; i++) {
        if (strcmp(text, choices[i]) == 0) {
            *out = i;
            return 1;
        }
        int w = snprintf(list + used, sizeof list - used, "%s%s", i ? " | " : "", choices[i]);
        if (w > 0 && used + (size_t)w < sizeof list) used += (size_t)w;
    }
    const char *near = suggest_nearest(text, choices);
    return ini_error(doc, section, index, key, err, errlen, "unknown value;%s%s%s accepted: %s",
                     near ? " did you mean " : "", near ? near : "", near ? "?" : "", list);
}

int ini_get_bool(ini_doc *doc, const char *section, int index, const char *key, int *out,
                 char *err, size_t errlen)
{
    static const char *const words[] = {"false", "true", "no", "yes", "off", "on", "0", "1", NULL};
    int which;
    int rc = ini_get_choice(doc, section, index, key, words, &which, err, errlen);
    if (rc == 1) *out = which % 2;
    return rc;
}

static int section_is_known(const ini_doc *doc, const char *section)
{
    for (int i = 0; i < doc->known_count; i++)
        if (strcmp(doc->known[i].section, section) == 0) return 1;
    return 0;
}

/* Whether the reader asked for keys of instance 0 of `section` only. */
static int section_read_once(const ini_doc *doc, const char *section)
{
    for (int i = 0; i < doc->known_count; i++)
        if (!doc->known[i].key && strcmp(doc->known[i].section, section) == 0)
            return doc->known[i].max_index == 0;
    return 0;
}

static void known_list(const ini_doc *doc, const char *section, char *out, size_t outlen)
{
    size_t used = 0;
    out[0] = '\0';
    for (int i = 0; i < doc->known_count; i++) {
        const ini_known *k = &doc->known[i];
        if (section ? (!k->key || strcmp(k->section, section) != 0) : k->key != NULL) continue;
        const char *word = section ? k->key : k->section;
        int w = snprintf(out + used, outlen - used, "%s%s", used ? ", " : "", word);
        if (w < 0 || used + (size_t)w >= outlen) break;
        used += (size_t)w;
    }
}

int ini_check_unused(const ini_doc *doc, char *err, size_t errlen)
{
    char list[512];
    for (int i = 0; i < doc->section_count; i++) {
        const ini_section *s = &doc->sections[i];
        if (s->instance > 0 && section_read_once(doc, s->name)) {
            const ini_section *first = find_section(doc, s->name, 0);
            set_error(err, errlen, "%s:%d: [%s] is given again (first on line %d); accepted: one "
                      "[%s] section holding all its keys (a second one would be ignored)",
                      doc->filename, s->line, s->name, first ? first->line : 0, s->name);
            return -1;
        }
        if (section_is_known(doc, s->name) || is_variant(s->name)) continue;
        known_list(doc, NULL, list, sizeof list);
        if (s->line > 0)
            set_error(err, errlen, "%s:%d: unknown section [%s]; accepted sections: %s",
                      doc->filename, s->line, s->name, list);
        else
            set_error(err, errlen, "--set: unknown section '%s'; accepted sections: %s", s->name,
                      list);
        return -1;
    }
    for (int i = 0; i < doc->entry_count; i++) {
        const ini_entry *e = &doc->entries[i];
        if (e->used || is_variant(e->section)) continue;
        int known = 0;
        for (int k = 0; k < doc->known_count; k++)
            if (doc->known[k].key && strcmp(doc->known[k].section, e->section) == 0 &&
                strcmp(doc->known[k].key, e->key) == 0)
                known = 1;
        known_list(doc, e->section, list, sizeof list);
        const char *what = known ? "is not used here" : "unknown key";
        if (e->line > 0)
            set_error(err, errlen, "%s:%d: [%s] %s: %s; accepted keys in [%s]: %s", doc->filename,
                      e->line, e->section, e->key, what, e->section, list);
        else
            set_error(err, errlen, "--set %s.%s: %s; accepted keys in [%s]: %s", e->section,
                      e->key, what, e->section, list);
        return -1;
    }
    return 0;
}

/* ---- key tables ----------------------------------------------------------- */

int ini_edit_distance(const char *a, const char *b) { return suggest_distance(a, b); }

/* The table's name of a section: a named instance [rod a] holds [rod]'s keys */
static int same_section(const char *table_section, const char *section)
{
    const size_t n = strlen(table_section);
    return strncmp(table_section, section, n) == 0 && (section[n] == '\0' || section[n] == ' ');
}

static int table_has_section(const ini_key *table, const char *section)
{
    for (const ini_key *k = table; k->section; k++)
        if (same_section(k->section, section)) return 1;
    return 0;
}

static const ini_key *table_find(const ini_key *table, const char *section, const char *key)
{
    for (const ini_key *k = table; k->section; k++)
        if (same_section(k->section, section) && strcmp(k->key, key) == 0) return k;
    return NULL;
}

/* Comma-separated sections (section NULL) or keys of one section, in table order. */
static void table_list(const ini_key *table, const char *section, char *out, size_t outlen)
{
    size_t used = 0;
    out[0] = '\0';
    for (const ini_key *k = table; k->section; k++) {
        const char *word;
        if (section) {
            if (!same_section(k->section, section)) continue;
            word = k->key;
        } else {
            int seen = 0; /* each section once */
            for (const ini_key *j = table; j < k; j++)
                if (strcmp(j->section, k->section) == 0) seen = 1;
            if (seen) continue;
            word = k->section;
        }
        int w = snprintf(out + used, outlen - used, "%s%s", used ? ", " : "", word);
        if (w < 0 || used + (size_t)w >= outlen) break;
        used += (size_t)w;
    }
}

/* The nearest section name to `word`, or NULL. */
static const char *nearest_section(const ini_key *table, const char *word)
{
    const char *best = NULL;
    int best_d = 1 << 20, d;
    for (const ini_key *k = table; k->section; k++)
        if (suggest_near(word, k->section, &d) && d < best_d) {
            best = k->section;
            best_d = d;
        }
    return best;
}

/* The nearest key of `section` to `word`; else the nearest key of another
 * section (*other_section set: "[rod] scheme" is [solver]'s); else NULL. */
static const ini_key *nearest_key(const ini_key *table, const char *section, const char *word,
                                  int *other_section)
{
    const ini_key *best = NULL;
    int best_d = 1 << 20, d;
    *other_section = 0;
    for (const ini_key *k = table; k->section; k++)
        if (same_section(k->section, section) && suggest_near(word, k->key, &d) && d < best_d) {
            best = k;
            best_d = d;
        }
    if (best) return best;
    for (const ini_key *k = table; k->section; k++)
        if (suggest_near(word, k->key, &d) && d < best_d) {
            best = k;
            best_d = d;
        }
    *other_section = best != NULL;
    return best;
}

/* The end of a plain decimal at p ([+-]digits[.digits][e[+-]digits]), or p. */
static const char *decimal_end(const char *p)
{
    const char *q = p;
    if (*q == '+' || *q == '-') q++;
    const char *digits = q;
    while (isdigit((unsigned char)*q)) q++;
    if (*q == '.') q++;
    while (isdigit((unsigned char)*q)) q++;
    if (q == digits || (q == digits + 1 && *digits == '.')) return p;
    if (*q == 'e' || *q == 'E') {
        const char *x = q + 1;
        if (*x == '+' || *x == '-') x++;
        if (isdigit((unsigned char)*x)) {
            while (isdigit((unsigned char)*x)) x++;
            q = x;
        }
    }
    return q;
}

/* A unit written with its symbols only: spaces, '*', '.', '^' and the middle
 * dot dropped ("N m" -> "Nm", "kg/m^3" -> "kg/m3"). */
static void unit_squeeze(const char *unit, char *out, size_t outlen)
{
    size_t n = 0;
    for (const char *c = unit; *c && n + 1 < outlen; c++) {
        if (*c == ' ' || *c == '*' || *c == '.' || *c == '^') continue;
        if ((unsigned char)c[0] == 0xC2 && (unsigned char)c[1] == 0xB7) { c++; continue; }
        out[n++] = *c;
    }
    out[n] = '\0';
}

/* The factor from `written` to the key's SI unit `si`: the same unit, or it
 * with an SI prefix (cm, MPa, uN, ms), or g/cm^3 for kg/m^3, Hz or fps for 1/s.
 * 0 when it is none of these. */
static double unit_factor(const char *written, const char *si)
{
    static const struct { const char *prefix; double factor; } prefixes[] = {
        {"", 1}, {"n", 1e-9}, {"u", 1e-6}, {"\xC2\xB5", 1e-6}, {"m", 1e-3}, {"c", 1e-2},
        {"k", 1e3}, {"M", 1e6}, {"G", 1e9},
    };
    char w[64], k[64];
    unit_squeeze(written, w, sizeof w);
    unit_squeeze(si, k, sizeof k);
    if (strcmp(k, "kg/m3") == 0 && strcmp(w, "g/cm3") == 0) return 1e3;
    if (strcmp(k, "1/s") == 0 && (strcmp(w, "Hz") == 0 || strcmp(w, "fps") == 0)) return 1;
    for (size_t i = 0; i < sizeof prefixes / sizeof prefixes[0]; i++) {
        size_t n = strlen(prefixes[i].prefix);
        if (strncmp(w, prefixes[i].prefix, n) == 0 && strcmp(w + n, k) == 0)
            return prefixes[i].factor;
    }
    return 0;
}

/* v to 12 digits, in the shorter of %g's forms that read back the same
 * (1140, 0.0005, 1e+08 rather than 100000000). */
static void shortest_number(double v, char *out, size_t outlen)
{
    char fixed[32];
    snprintf(fixed, sizeof fixed, "%.12g", v);
    double target = strtod(fixed, NULL);
    for (int digits = 1; digits < 12; digits++) {
        char shorter[32];
        snprintf(shorter, sizeof shorter, "%.*g", digits, v);
        if (strtod(shorter, NULL) == target && strlen(shorter) < strlen(fixed)) {
            snprintf(out, outlen, "%s", shorter);
            return;
        }
    }
    snprintf(out, outlen, "%s", fixed);
}

/* A value of numbers followed by a unit ("50 cm", "0.5mm", "0 -10 0 uN") for
 * a key whose table unit is `si`: a message saying to write the bare numbers
 * in `si`, converted when the unit is `si` with a prefix. 0 when the value
 * is not so. */
static int unit_after_numbers(const char *value, const char *si, char *out, size_t outlen)
{
    double numbers[16];
    int count = 0;
    const char *p = value;
    for (;;) {
        while (*p == ' ' || *p == '\t' || *p == ',') p++;
        const char *end = decimal_end(p);
        if (end == p || count == 16) break;
        char buf[64];
        size_t n = (size_t)(end - p);
        if (n >= sizeof buf) return 0;
        memcpy(buf, p, n);
        buf[n] = '\0';
        numbers[count++] = strtod(buf, NULL);
        p = end;
        if (*p && *p != ' ' && *p != '\t' && *p != ',') break; /* "0.5mm": glued */
    }
    const char *unit = p;
    if (count == 0 || !(isalpha((unsigned char)*unit) || (unsigned char)*unit >= 0x80))
        return 0;
    /* "5e": a cut exponent; "0 0 inf": not a finite number; neither is a unit */
    if (strcmp(unit, "e") == 0 || strcmp(unit, "E") == 0 || strncasecmp(unit, "inf", 3) == 0 ||
        strncasecmp(unit, "nan", 3) == 0)
        return 0;
    for (const char *c = unit; *c; c++)
        if (!isalnum((unsigned char)*c) && !strchr(" /^*.-", *c) && (unsigned char)*c < 0x80)
            return 0;
    const char *plural = count > 1 ? "s" : "";
    double factor = unit_factor(unit, si);
    if (factor == 0)
        return snprintf(out, outlen, "a unit after the number%s ('%s'); a scene's values are "
                        "bare numbers in the key's unit: write the number%s in %s, "
                        "without a unit",
                        plural, unit, plural, si) > 0;
    char converted[256] = "";
    size_t used = 0;
    for (int i = 0; i < count; i++) {
        char number[32];
        shortest_number(numbers[i] * factor, number, sizeof number);
        int w = snprintf(converted + used, sizeof converted - used, "%s%s", i ? " " : "",
                         number);
        if (w < 0 || used + (size_t)w >= sizeof converted) return 0;
        used += (size_t)w;
    }
    return snprintf(out, outlen, "a unit after the number%s ('%s'); a scene's values are bare "
                    "numbers in the key's unit: write %s (%s)", plural, unit,
                    converted, si) > 0;
}

int ini_check_keys(const ini_doc *doc, const ini_key *table, char *err, size_t errlen)
{
    /* the first offender in file order; --set ones (line 0) after the file's */
    const ini_section *bad_section = NULL;
    const ini_entry *bad_entry = NULL;
    long first = -1;
    for (int i = 0; i < doc->section_count; i++) {
        const ini_section *s = &doc->sections[i];
        long order = s->line > 0 ? s->line : 1L << 30;
        if (!table_has_section(table, s->name) && !is_variant(s->name) &&
            (first < 0 || order < first)) {
            bad_section = s;
            first = order;
        }
    }
    for (int i = 0; i < doc->entry_count; i++) {
        const ini_entry *e = &doc->entries[i];
        long order = e->line > 0 ? e->line : (1L << 30) + 1 + i;
        if (table_has_section(table, e->section) && !table_find(table, e->section, e->key) &&
            (first < 0 || order < first)) {
            bad_section = NULL;
            bad_entry = e;
            first = order;
        }
    }
    char list[768], hint[160] = "";
    if (bad_section) {
        const char *near = nearest_section(table, bad_section->name);
        if (near) snprintf(hint, sizeof hint, " did you mean [%s]?", near);
        table_list(table, NULL, list, sizeof list);
        if (bad_section->line > 0) {
            set_error(err, errlen, "%s:%d: unknown section [%s];%s accepted sections: %s",
                      doc->filename, bad_section->line, bad_section->name, hint, list);
        } else {
            const ini_entry *e = NULL; /* name the --set that made it */
            for (int i = 0; i < doc->entry_count && !e; i++)
                if (strcmp(doc->entries[i].section, bad_section->name) == 0) e = &doc->entries[i];
            set_error(err, errlen, "--set %s.%s=%s: unknown section [%s];%s accepted sections: %s",
                      bad_section->name, e ? e->key : "", e ? e->value : "", bad_section->name,
                      hint, list);
        }
        return -1;
    }
    if (bad_entry) {
        const ini_entry *e = bad_entry;
        int other = 0;
        const ini_key *near = nearest_key(table, e->section, e->key, &other);
        if (near && other && e->line > 0)
            snprintf(hint, sizeof hint, " did you mean [%s] %s?", near->section, near->key);
        else if (near && e->line > 0)
            snprintf(hint, sizeof hint, " did you mean %s?", near->key);
        else if (near)
            snprintf(hint, sizeof hint, " did you mean %s.%s?", near->section, near->key);
        table_list(table, e->section, list, sizeof list);
        if (e->line > 0)
            set_error(err, errlen, "%s:%d: [%s] %s: unknown key;%s accepted keys in [%s]: %s",
                      doc->filename, e->line, e->section, e->key, hint, e->section, list);
        else
            set_error(err, errlen, "--set %s.%s=%s: unknown key;%s accepted keys in [%s]: %s",
                      e->section, e->key, e->value, hint, e->section, list);
        return -1;
    }
    /* a value with a unit after it ("length = 50 cm"), the first in file order */
    const ini_entry *with_unit = NULL;
    char why[512] = "";
    first = -1;
    for (int i = 0; i < doc->entry_count; i++) {
        const ini_entry *e = &doc->entries[i];
        long order = e->line > 0 ? e->line : (1L << 30) + 1 + i;
        const ini_key *k = table_find(table, e->section, e->key);
        if (k && strcmp(k->unit, "-") != 0 && (first < 0 || order < first) &&
            unit_after_numbers(e->value, k->unit, why, sizeof why)) {
            with_unit = e;
            first = order;
        }
    }
    if (with_unit) {
        /* why: the message of the last match written, which is with_unit's */
        char where[512];
        describe(doc, with_unit, with_unit->section, with_unit->instance, with_unit->key, where,
                 sizeof where);
        set_error(err, errlen, "%s: %s", where, why);
        return -1;
    }
    return 0;
}

int ini_asked(const ini_doc *doc, int i, const char **section, const char **key)
{
    if (i < 0 || i >= doc->known_count) return 0;
    *section = doc->known[i].section;
    *key = doc->known[i].key;
    return 1;
}
