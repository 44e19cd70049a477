/* json.h: a small JSON reader for tests (recursive descent, no dependency):
 * enough to check what rodsim writes (objects, arrays, strings with their
 * escapes, numbers, true, false, null). Strict: trailing commas, bare words,
 * single quotes, leading zeros, control characters in strings and text after
 * the value are refused. Header-only, tests only.
 *
 *   json_value *v = json_parse(text, err, sizeof err);   NULL: err says where
 *   json_get(v, "status")->string ...   json_free(v);
 */
#ifndef RODSIM_TEST_JSON_H
#define RODSIM_TEST_JSON_H

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef enum json_type {
    JSON_NULL,
    JSON_BOOL,
    JSON_NUMBER,
    JSON_STRING,
    JSON_ARRAY,
    JSON_OBJECT
} json_type;

typedef struct json_value {
    json_type type;
    int boolean;
    double number;
    char *string;             /* JSON_STRING, decoded (UTF-8), owned */
    int count;                /* JSON_ARRAY, JSON_OBJECT: members */
    struct json_value **items;/* (count), owned */
    char **keys;              /* JSON_OBJECT: (count), owned */
} json_value;

typedef struct json_reader {
    const char *text, *at;
    char *err;
    size_t errlen;
    int depth;
} json_reader;

static inline void json_free(json_value *v)
{
    if (!v) return;
    for (int i = 0; i < v->count; i++) {
        json_free(v->items[i]);
        if (v->keys) free(v->keys[i]);
    }
    free(v->items);
    free(v->keys);
    free(v->string);
    free(v);
}

static inline json_value *json_fail(json_reader *r, const char *what)
{
    if (r->err[0] == '\0')
        snprintf(r->err, r->errlen, "offset %ld: %s", (long)(r->at - r->text), what);
    return NULL;
}

static inline void json_space(json_reader *r)
{
    while (*r->at == ' ' || *r->at == '\t' || *r->at == '\n' || *r->at == '\r') r->at++;
}

static inline json_value *json_new(json_type type)
{
    json_value *v = (json_value *)calloc(1, sizeof *v);
    if (v) v->type = type;
    return v;
}

static inline void json_utf8(char *out, size_t *n, unsigned code)
{
    if (code < 0x80) {
        out[(*n)++] = (char)code;
    } else if (code < 0x800) {
        out[(*n)++] = (char)(0xC0 | (code >> 6));
        out[(*n)++] = (char)(0x80 | (code & 0x3F));
    } else {
        out[(*n)++] = (char)(0xE0 | (code >> 12));
        out[(*n)++] = (char)(0x80 | ((code >> 6) & 0x3F));
        out[(*n)++] = (char)(0x80 | (code & 0x3F));
    }
}

/* A string at r->at (its opening quote), decoded into a new buffer. */
static inline char *json_string_text(json_reader *r)
{
    const char *p = r->at + 1;
    size_t cap = 16, n = 0;
    char *out = (char *)malloc(cap);
    while (out) {
        if (n + 4 >= cap) {
            char *bigger = (char *)realloc(out, cap *= 2);
            if (!bigger) break;
            out = bigger;
        }
        unsigned char c = (unsigned char)*p;
        if (c == '"') {
            out[n] = '\0';
            r->at = p + 1;
            return out;
        }
        if (c == '\0' || c < 0x20) break;
        if (c != '\\') {
            out[n++] = (char)c;
            p++;
            continue;
        }
        p++;
        switch (*p) {
        case '"': out[n++] = '"'; break;
        case '\\': out[n++] = '\\'; break;
        case '/': out[n++] = '/'; break;
        case 'b': out[n++] = '\b'; break;
        case 'f': out[n++] = '\f'; break;
        case 'n': out[n++] = '\n'; break;
        case 'r': out[n++] = '\r'; break;
        case 't': out[n++] = '\t'; break;
        case 'u': {
            unsigned code = 0;
            for (int k = 1; k <= 4; k++) {
                if (!isxdigit((unsigned char)p[k])) goto bad;
                code = code * 16 + (unsigned)(isdigit((unsigned char)p[k])
                                                  ? p[k] - '0'
                                                  : tolower((unsigned char)p[k]) - 'a' + 10);
            }
            json_utf8(out, &n, code); /* surrogate pairs: not needed by rodsim */
            p += 4;
            break;
        }
        default: goto bad;
        }
        p++;
    }
bad:
    free(out);
    r->at = p;
    return NULL;
}

static inline json_value *json_value_at(json_reader *r);

static inline json_value *json_number_at(json_reader *r)
{
    const char *p = r->at;
    if (*p == '-') p++;
    if (*p == '0') p++;
    else if (isdigit((unsigned char)*p)) while (isdigit((unsigned char)*p)) p++;
    else return json_fail(r, "expected a value");
    if (*p == '.') {
        p++;
        if (!isdigit((unsigned char)*p)) return json_fail(r, "a digit after '.'");
        while (isdigit((unsigned char)*p)) p++;
    }
    if (*p == 'e' || *p == 'E') {
        p++;
        if (*p == '+' || *p == '-') p++;
        if (!isdigit((unsigned char)*p)) return json_fail(r, "a digit in the exponent");
        while (isdigit((unsigned char)*p)) p++;
    }
    json_value *v = json_new(JSON_NUMBER);
    if (!v) return json_fail(r, "out of memory");
    v->number = strtod(r->at, NULL);
    r->at = p;
    return v;
}

/* An array or object at r->at ('[' or '{'). */
static inline json_value *json_members_at(json_reader *r, int object)
{
    json_value *v = json_new(object ? JSON_OBJECT : JSON_ARRAY);
    if (!v) return json_fail(r, "out of memory");
    const char close = object ? '}' : ']';
    r->at++;
    json_space(r);
    if (*r->at == close) {
        r->at++;
        return v;
    }
    for (;;) {
        char *key = NULL;
        json_space(r);
        if (object) {
            if (*r->at != '"' || !(key = json_string_text(r))) {
                json_free(v);
                return json_fail(r, "expected a key (a string)");
            }
            json_space(r);
            if (*r->at != ':') {
                free(key);
                json_free(v);
                return json_fail(r, "expected ':'");
            }
            r->at++;
        }
        json_value *item = json_value_at(r);
        json_value **items = item ? (json_value **)realloc(v->items, (size_t)(v->count + 1) *
                                                                         sizeof *items)
                                  : NULL;
        char **keys = items && object ? (char **)realloc(v->keys, (size_t)(v->count + 1) *
                                                                       sizeof *keys)
                                      : NULL;
        if (items) v->items = items;
        if (keys) v->keys = keys;
        if (!items || (object && !keys)) {
            free(key);
            json_free(item);
            json_free(v);
            return json_fail(r, "expected a value");
        }
        v->items[v->count] = item;
        if (object) v->keys[v->count] = key;
        v->count++;
        json_space(r);
        if (*r->at == ',') {
            r->at++;
            json_space(r);
            if (*r->at == close) {
                json_free(v);
                return json_fail(r, "a trailing comma");
            }
            continue;
        }
        if (*r->at == close) {
            r->at++;
            return v;
        }
        json_free(v);
        return json_fail(r, object ? "expected ',' or '}'" : "expected ',' or ']'");
    }
}

static inline json_value *json_value_at(json_reader *r)
{
    json_space(r);
    if (++r->depth > 64) return json_fail(r, "nested too deep");
    json_value *v = NULL;
    char c = *r->at;
    if (c == '{' || c == '[') {
        v = json_members_at(r, c == '{');
    } else if (c == '"') {
        v = json_new(JSON_STRING);
        if (v && !(v->string = json_string_text(r))) {
            json_free(v);
            v = json_fail(r, "a bad string");
        }
    } else if (strncmp(r->at, "true", 4) == 0 || strncmp(r->at, "false", 5) == 0) {
        v = json_new(JSON_BOOL);
        if (v) v->boolean = c == 't';
        r->at += c == 't' ? 4 : 5;
    } else if (strncmp(r->at, "null", 4) == 0) {
        v = json_new(JSON_NULL);
        r->at += 4;
    } else {
        v = json_number_at(r);
    }
    r->depth--;
    return v;
}

/* The value of the whole text (nothing but white space after it), or NULL
 * with a message in err. */
static inline json_value *json_parse(const char *text, char *err, size_t errlen)
{
    json_reader r = {text, text, err, errlen, 0};
    err[0] = '\0';
    json_value *v = json_value_at(&r);
    if (!v) return NULL;
    json_space(&r);
    if (*r.at != '\0') {
        json_free(v);
        return json_fail(&r, "text after the value");
    }
    return v;
}

/* The member `key` of an object, or NULL (also when v is not an object). */
static inline const json_value *json_get(const json_value *v, const char *key)
{
    if (!v || v->type != JSON_OBJECT) return NULL;
    for (int i = 0; i < v->count; i++)
        if (strcmp(v->keys[i], key) == 0) return v->items[i];
    return NULL;
}

/* 1 when v is a value of that type (NULL is not). */
static inline int json_is(const json_value *v, json_type type) { return v && v->type == type; }

/* 1 when v is an array of n numbers (n < 0: any count). */
static inline int json_is_numbers(const json_value *v, int n)
{
    if (!json_is(v, JSON_ARRAY) || (n >= 0 && v->count != n)) return 0;
    for (int i = 0; i < v->count; i++)
        if (v->items[i]->type != JSON_NUMBER) return 0;
    return 1;
}

#endif
