/* ini.h: strict INI scene files.
 *
 * Syntax: `[section]` headers, `key = value` lines, `#` starts a comment
 * (anywhere outside double quotes), blank lines ignored; a UTF-8 byte-order
 * mark at the start (some editors write one) is skipped. A section may
 * repeat (the FEM scene's [support] and [load]); each occurrence is an
 * instance, numbered from 0 in file order. A key may appear once per
 * instance. A section its reader reads once (only instance 0 is asked for)
 * but the file repeats is reported by ini_check_unused().
 *
 * Strictness is by use: every ini_get_* call records the section and key as
 * known, whether or not the file has them. After the consumer has read all
 * it understands, ini_check_unused() reports the first key or section the
 * file has that nobody asked for, naming file:line and the keys that are
 * accepted in that section.
 *
 * A consumer may also hold a table of every key it accepts (ini_key):
 * ini_check_keys() then reports an unknown section or key at its own line,
 * with the nearest accepted name, before any value is read.
 *
 * Every error message starts with "file:line: " when a line is known.
 */
#ifndef RODSIM_INI_H
#define RODSIM_INI_H

#include <stddef.h>

typedef struct ini_doc ini_doc;

/* The most bytes a scene file may hold (1 MiB, 200 times the largest shipped
 * scene): a device, an endless pipe or a huge file is refused, not read. */
#define INI_MAX_BYTES ((size_t)1 << 20)

/* Parses the file at path (base/textfile.h: a text file of at most
 * INI_MAX_BYTES). Returns NULL and writes a message into err on a missing
 * file, a directory or device, a file over the limit, or a syntax error. */
ini_doc *ini_load(const char *path, char *err, size_t errlen);
/* Parses text held in memory; `name` stands for the file name in messages. */
ini_doc *ini_parse(const char *name, const char *text, char *err, size_t errlen);
void ini_destroy(ini_doc *doc);

/* Applies "section.key=value" (command-line --set), replacing the value in
 * the first instance of the section, or adding the key (and the section)
 * when absent; "section.NAME.key=value" sets it in the instance of a
 * repeatable section whose `name` is NAME (an [instrument]'s), refused when
 * none is; "word NAME.key=value" sets it in the named section [word NAME]
 * (a rod of several: --set "rod a.length=0.3"). Messages about it name
 * "--set section.key" instead of a line. "variant=NAME" applies the lines
 * of the file's [variant NAME] section (keys written section.key, any form
 * above) in file order, each value's messages naming its line there; an
 * unknown NAME is refused, naming those the file has. ini_check_keys and
 * ini_check_unused pass over [variant NAME] sections: unchosen, unread. */
int ini_set(ini_doc *doc, const char *assignment, char *err, size_t errlen);

const char *ini_filename(const ini_doc *doc);
/* Scene name: the file's base name without directory and extension. */
void ini_scene_name(const ini_doc *doc, char *out, size_t outlen);
/* Directory of the file ("." when none), for paths relative to the scene. */
void ini_directory(const ini_doc *doc, char *out, size_t outlen);

/* Named instances: a header [word NAME] (two words) is the section
 * "word NAME" (several rods: [rod a], [ends a], [tip a]). The NAMEs of the
 * sections [word NAME] in file order into names (up to `most`; pointers
 * into doc); returns their count. */
int ini_section_names(const ini_doc *doc, const char *word, const char **names, int most);
/* While set, every lookup of `section` (ini_get_*, ini_section_count,
 * ini_section_line, ini_error) reads the section `actual` instead, and
 * messages name `actual` (a reader of [rod] reads [rod a]); actual NULL
 * removes the alias. Returns 0, or -1 when too many are set (8) or a name
 * is too long. */
int ini_alias(ini_doc *doc, const char *section, const char *actual);

/* Number of instances of a section in the file (marks it known). */
int ini_section_count(ini_doc *doc, const char *section);

/* The line of instance `index` of `section` (0 when absent or made by --set). */
int ini_section_line(const ini_doc *doc, const char *section, int index);

/* Lookups in instance `index` of `section`. Each returns 1 when the key is
 * present and parsed, 0 when absent (out untouched), -1 on a bad value
 * (message in err, naming file:line, section, key, and what is accepted). */
int ini_get_string(ini_doc *doc, const char *section, int index, const char *key,
                   const char **out, char *err, size_t errlen);
int ini_get_double(ini_doc *doc, const char *section, int index, const char *key,
                   double *out, char *err, size_t errlen);
int ini_get_int(ini_doc *doc, const char *section, int index, const char *key,
                int *out, char *err, size_t errlen);
/* Exactly n numbers separated by blanks or commas. */
int ini_get_vector(ini_doc *doc, const char *section, int index, const char *key,
                   double *out, int n, char *err, size_t errlen);
/* One of the words in `choices` (NULL-terminated); *out is its position. */
int ini_get_choice(ini_doc *doc, const char *section, int index, const char *key,
                   const char *const *choices, int *out, char *err, size_t errlen);
/* "true|false|yes|no|on|off|1|0" */
int ini_get_bool(ini_doc *doc, const char *section, int index, const char *key,
                 int *out, char *err, size_t errlen);

/* Writes "file:line: [section] key = value: " followed by the formatted
 * text into err, for range checks done by the consumer. Returns -1. */
int ini_error(const ini_doc *doc, const char *section, int index, const char *key,
              char *err, size_t errlen, const char *fmt, ...)
    __attribute__((format(printf, 7, 8)));

/* Reports the first section or key present in the file that no ini_get_*
 * or ini_section_count call asked for, or a second instance of a section of
 * which only instance 0 was read (a repeated [rod]). Returns 0 when all were
 * used. */
int ini_check_unused(const ini_doc *doc, char *err, size_t errlen);

/* One key a scene may hold, as its reference documents it (`rodsim help
 * scene` prints these rows). A table ends with a row whose section is NULL. */
typedef struct ini_key {
    const char *section;
    const char *key;
    const char *unit;     /* SI unit, or "-" */
    const char *fallback; /* the value used when the key is absent, written as a scene
                             would write it; or "required"; or "-": absence has the
                             meaning `meaning` gives */
    const char *accepted; /* the values accepted, in words */
    const char *meaning;
} ini_key;

/* Checks every section and key of the file (and of --set) against the table,
 * before anything is read. The first unknown one in file order (--set ones
 * last) is reported at its own line, with the nearest accepted name ("did you
 * mean density?") and the accepted list. Then a value of numbers followed by
 * a unit ("50 cm", for a key whose unit is not "-") is reported, with the
 * numbers converted to the key's unit when the unit is that one with an SI
 * prefix. Returns 0, or -1 with the message. */
int ini_check_keys(const ini_doc *doc, const ini_key *table, char *err, size_t errlen);

/* Edit distance between a and b (insertions, deletions, substitutions and
 * swaps of two neighbours each count 1), capped at 255. */
int ini_edit_distance(const char *a, const char *b);

/* The i-th (section, key) an ini_get_* or ini_section_count call asked for
 * (key NULL for a section-only ask). Returns 0 past the last. Lets a test hold
 * a reader to its ini_key table. */
int ini_asked(const ini_doc *doc, int i, const char **section, const char **key);

#endif
