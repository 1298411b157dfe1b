/* Descriptor-driven parameter structs: defaults, JSON loading, checks, echo, help.
 *
 * One table per params struct (see params.h) is the single source of every key, type,
 * default, range and help line; nothing here knows any particular struct. */
#include "elastopt/params.h"
#include "elastopt/io.h"
#include "elastopt/registry.h"
#include "elastopt/suggest.h"

#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FIELD(obj, p, T) ((T *)((char *)(obj) + (p)->offset))
#define CFIELD(obj, p, T) ((const T *)((const char *)(obj) + (p)->offset))

size_t eo_params_count(const eo_param_desc *d)
{
    size_t n = 0;
    while (d && d[n].kind != EO_PARAM_END) n++;
    return n;
}

const eo_param_desc *eo_params_find(const eo_param_desc *d, const char *key)
{
    for (; d && d->kind != EO_PARAM_END; d++)
        if (strcmp(d->key, key) == 0) return d;
    return NULL;
}

static void set_string(const eo_param_desc *p, void *obj, const char *s)
{
    char *dst = FIELD(obj, p, char);
    snprintf(dst, p->size, "%s", s ? s : "");
}

void eo_params_default(const eo_param_desc *d, void *obj)
{
    for (; d && d->kind != EO_PARAM_END; d++) {
        switch (d->kind) {
        case EO_PARAM_INT: *FIELD(obj, d, int) = (int)d->def.i; break;
        case EO_PARAM_BOOL: *FIELD(obj, d, int) = d->def.i ? 1 : 0; break;
        case EO_PARAM_DOUBLE: *FIELD(obj, d, double) = d->def.d; break;
        case EO_PARAM_STRING:
        case EO_PARAM_CHOICE:
        case EO_PARAM_METHOD: set_string(d, obj, d->def.s); break;
        case EO_PARAM_VEC3: memcpy(FIELD(obj, d, double), d->def.v, 3 * sizeof(double)); break;
        case EO_PARAM_END: break;
        }
    }
}

static const char *kind_name(eo_param_kind k)
{
    switch (k) {
    case EO_PARAM_INT: return "integer";
    case EO_PARAM_DOUBLE: return "number";
    case EO_PARAM_BOOL: return "boolean";
    case EO_PARAM_STRING: return "string";
    case EO_PARAM_CHOICE: return "choice";
    case EO_PARAM_METHOD: return "name";
    case EO_PARAM_VEC3: return "3-vector";
    case EO_PARAM_END: break;
    }
    return "?";
}

const char *eo_json_type_name(const json_t *v)
{
    if (!v) return "nothing";
    switch (json_typeof(v)) {
    case JSON_OBJECT: return "object";
    case JSON_ARRAY: return "array";
    case JSON_STRING: return "string";
    case JSON_INTEGER: return "integer";
    case JSON_REAL: return "number";
    case JSON_TRUE:
    case JSON_FALSE: return "boolean";
    case JSON_NULL: return "null";
    }
    return "?";
}

char *eo_json_dumps(const json_t *j, size_t flags)
{
    char *text = json_dumps(j, (flags & ~(size_t)JSON_REAL_PRECISION(31)) | JSON_REAL_PRECISION(17));
    if (!text) return NULL;
    size_t n = strlen(text);
    char *out = malloc(2 * n + 1), *o = out;
    if (!out) {
        free(text);
        return NULL;
    }
    for (const char *p = text; *p;) {
        if (*p == '"') { /* a string: copied as is */
            *o++ = *p++;
            while (*p && *p != '"') {
                if (*p == '\\' && p[1]) *o++ = *p++;
                *o++ = *p++;
            }
            if (*p) *o++ = *p++;
            continue;
        }
        if (*p == '-' || (*p >= '0' && *p <= '9')) {
            size_t k = strspn(p, "+-.0123456789eE");
            if (memchr(p, '.', k) || memchr(p, 'e', k) || memchr(p, 'E', k)) { /* a real */
                char buf[32];
                eo_fmt_double(buf, strtod(p, NULL));
                size_t m = strlen(buf);
                memcpy(o, buf, m);
                o += m;
                if (!strpbrk(buf, ".en")) { /* "1" -> "1.0": stays a real */
                    *o++ = '.';
                    *o++ = '0';
                }
            } else {
                memcpy(o, p, k);
                o += k;
            }
            p += k;
            continue;
        }
        *o++ = *p++;
    }
    *o = 0;
    free(text);
    return out;
}

const char *eo_json_describe(const json_t *v, char *buf, size_t n)
{
    if (!buf || !n) return "";
    if (json_is_array(v)) {
        size_t k = json_array_size(v);
        if (k == 0) snprintf(buf, n, "an empty array");
        else snprintf(buf, n, "an array of %zu", k);
    } else if (!v || json_is_null(v)) {
        snprintf(buf, n, "%s", eo_json_type_name(v));
    } else {
        const char *t = eo_json_type_name(v);
        snprintf(buf, n, "%s %s", strchr("aeiou", t[0]) ? "an" : "a", t);
    }
    return buf;
}

/* Error located at "<section path>.<key>": the file line if the text has it. */
static int perr(eo_ctx *ctx, int status, const eo_param_src *src, const char *key,
                const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;
static int perr(eo_ctx *ctx, int status, const eo_param_src *src, const char *key,
                const char *fmt, ...)
{
    char full[512], text[768];
    const char *path = src && src->path ? src->path : "";
    if (key) snprintf(full, sizeof full, "%s%s%s", path, *path ? "." : "", key);
    else snprintf(full, sizeof full, "%s", path);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    eo_errloc loc = EO_ERRLOC_NONE;
    char needle[520];
    snprintf(needle, sizeof needle, "\n%s\n", full);
    if (src && src->overridden && strstr(src->overridden, needle)) {
        return eo_error_at(ctx, status, loc, "command line -o %s: %s", full, text);
    }
    if (src && src->file) {
        loc.file = src->file;
        if (src->text) eo_json_locate(src->text, full, &loc.line, &loc.column);
    }
    return eo_error_at(ctx, status, loc, "key '%s': %s", full, text);
}

static void format_range(const eo_param_desc *p, char *buf, size_t n)
{
    buf[0] = 0;
    if (p->kind != EO_PARAM_INT && p->kind != EO_PARAM_DOUBLE) return;
    const char *lo = (p->range & EO_RANGE_MIN_OPEN) ? "(" : "[";
    const char *hi = (p->range & EO_RANGE_MAX_OPEN) ? ")" : "]";
    int has_lo = (p->range & (EO_RANGE_MIN | EO_RANGE_MIN_OPEN)) != 0;
    int has_hi = (p->range & (EO_RANGE_MAX | EO_RANGE_MAX_OPEN)) != 0;
    if (!has_lo && !has_hi) return;
    char a[32] = "-inf", b[32] = "inf";
    if (has_lo) snprintf(a, sizeof a, "%.6g", p->min);
    if (has_hi) snprintf(b, sizeof b, "%.6g", p->max);
    snprintf(buf, n, "%s%s, %s%s", has_lo ? lo : "(", a, b, has_hi ? hi : ")");
}

static int in_range(const eo_param_desc *p, double v)
{
    if (!isfinite(v)) return 0;
    if ((p->range & EO_RANGE_MIN) && !(v >= p->min)) return 0;
    if ((p->range & EO_RANGE_MIN_OPEN) && !(v > p->min)) return 0;
    if ((p->range & EO_RANGE_MAX) && !(v <= p->max)) return 0;
    if ((p->range & EO_RANGE_MAX_OPEN) && !(v < p->max)) return 0;
    return 1;
}

static void choices_list(const eo_param_desc *p, char *buf, size_t n)
{
    size_t k = 0;
    buf[0] = 0;
    if (p->kind == EO_PARAM_METHOD) { /* the registered names, then the extra values */
        eo_registry_name_list(p->registry, buf, n);
        k = strlen(buf);
    }
    for (const char *const *c = p->choices; c && *c && k < n; c++)
        k += (size_t)snprintf(buf + k, n - k, "%s%s", k == 0 ? "" : ", ", *c);
}

static int check_name(eo_ctx *ctx, const eo_param_desc *p, const char *s, const eo_param_src *src)
{
    char list[512];
    if (p->kind == EO_PARAM_CHOICE) {
        for (const char *const *c = p->choices; c && *c; c++)
            if (strcmp(*c, s) == 0) return EO_OK;
    } else if (p->kind == EO_PARAM_METHOD) {
        for (const void *const *t = eo_registry_types(p->registry); t && *t; t++)
            if (strcmp(eo_method_info_of(*t)->name, s) == 0) return EO_OK;
        for (const char *const *c = p->choices; c && *c; c++) /* extra values ("auto") */
            if (strcmp(*c, s) == 0) return EO_OK;
    } else {
        return EO_OK;
    }
    char hint[128];
    choices_list(p, list, sizeof list);
    eo_suggest_hint(s, list, NULL, hint, sizeof hint);
    if (p->kind == EO_PARAM_METHOD)
        return perr(ctx, EO_ERR_UNKNOWN_NAME, src, p->key, "unknown %s '%s'%s; valid: %s",
                    p->registry ? eo_kind_label(p->registry->kind) : "method", s, hint, list);
    return perr(ctx, EO_ERR_UNKNOWN_NAME, src, p->key, "unknown value '%s'%s; valid: %s", s, hint, list);
}

int eo_params_check(eo_ctx *ctx, const eo_param_desc *d, const void *obj, const eo_param_src *src)
{
    char r[96];
    for (const eo_param_desc *p = d; p && p->kind != EO_PARAM_END; p++) {
        double v;
        switch (p->kind) {
        case EO_PARAM_INT:
        case EO_PARAM_DOUBLE:
            v = p->kind == EO_PARAM_INT ? (double)*CFIELD(obj, p, int) : *CFIELD(obj, p, double);
            if (!in_range(p, v)) {
                format_range(p, r, sizeof r);
                return perr(ctx, EO_ERR_RANGE, src, p->key, "value %.17g out of range %s", v,
                            r[0] ? r : "(finite)");
            }
            break;
        case EO_PARAM_VEC3:
            for (int i = 0; i < 3; i++)
                if (!isfinite(CFIELD(obj, p, double)[i]))
                    return perr(ctx, EO_ERR_RANGE, src, p->key, "component %d is not finite", i);
            break;
        case EO_PARAM_CHOICE:
        case EO_PARAM_METHOD: {
            int rc = check_name(ctx, p, CFIELD(obj, p, char), src);
            if (rc < 0) return rc;
            break;
        }
        default: break;
        }
    }
    return EO_OK;
}

int eo_params_set_json(eo_ctx *ctx, const eo_param_desc *p, void *obj, const json_t *v,
                       const eo_param_src *src)
{
    char r[96];
    switch (p->kind) {
    case EO_PARAM_INT: {
        double dv;
        if (json_is_integer(v)) dv = (double)json_integer_value(v);
        else if (json_is_real(v) && json_real_value(v) == floor(json_real_value(v)))
            dv = json_real_value(v);
        else
            return perr(ctx, EO_ERR_TYPE, src, p->key, "expected an integer, got %s",
                        eo_json_type_name(v));
        if (!in_range(p, dv) || fabs(dv) > 2147483647.0) {
            format_range(p, r, sizeof r);
            return perr(ctx, EO_ERR_RANGE, src, p->key, "value %.17g out of range %s", dv,
                        r[0] ? r : "(int)");
        }
        *FIELD(obj, p, int) = (int)dv;
        return EO_OK;
    }
    case EO_PARAM_DOUBLE: {
        if (!json_is_number(v))
            return perr(ctx, EO_ERR_TYPE, src, p->key, "expected a number, got %s",
                        eo_json_type_name(v));
        double dv = json_number_value(v);
        if (!in_range(p, dv)) {
            format_range(p, r, sizeof r);
            return perr(ctx, EO_ERR_RANGE, src, p->key, "value %.17g out of range %s", dv,
                        r[0] ? r : "(finite)");
        }
        *FIELD(obj, p, double) = dv;
        return EO_OK;
    }
    case EO_PARAM_BOOL:
        if (!json_is_boolean(v))
            return perr(ctx, EO_ERR_TYPE, src, p->key, "expected true or false, got %s",
                        eo_json_type_name(v));
        *FIELD(obj, p, int) = json_is_true(v);
        return EO_OK;
    case EO_PARAM_STRING:
    case EO_PARAM_CHOICE:
    case EO_PARAM_METHOD: {
        if (!json_is_string(v))
            return perr(ctx, EO_ERR_TYPE, src, p->key, "expected a string, got %s",
                        eo_json_type_name(v));
        const char *s = json_string_value(v);
        if (strlen(s) >= p->size)
            return perr(ctx, EO_ERR_RANGE, src, p->key, "string longer than %zu characters",
                        p->size - 1);
        int rc = check_name(ctx, p, s, src);
        if (rc < 0) return rc;
        set_string(p, obj, s);
        return EO_OK;
    }
    case EO_PARAM_VEC3: {
        char got[32];
        if (!json_is_array(v) || json_array_size(v) != 3)
            return perr(ctx, EO_ERR_TYPE, src, p->key, "expected an array of 3 numbers, got %s",
                        eo_json_describe(v, got, sizeof got));
        double t[3];
        for (int i = 0; i < 3; i++) {
            json_t *e = json_array_get(v, (size_t)i);
            if (!json_is_number(e))
                return perr(ctx, EO_ERR_TYPE, src, p->key,
                            "expected an array of 3 numbers, item %d is %s", i, eo_json_describe(e, got, sizeof got));
            t[i] = json_number_value(e);
            if (!isfinite(t[i]))
                return perr(ctx, EO_ERR_RANGE, src, p->key, "component %d is not finite", i);
        }
        memcpy(FIELD(obj, p, double), t, sizeof t);
        return EO_OK;
    }
    case EO_PARAM_END: break;
    }
    return EO_ERR_INTERNAL;
}

void eo_params_keys(const eo_param_desc *d, const char *const *extra, char *buf, size_t n)
{
    size_t k = 0;
    buf[0] = 0;
    for (const eo_param_desc *p = d; p && p->kind != EO_PARAM_END && k < n; p++)
        k += (size_t)snprintf(buf + k, n - k, "%s%s", k ? ", " : "", p->key);
    for (const char *const *e = extra; e && *e && k < n; e++)
        k += (size_t)snprintf(buf + k, n - k, "%s%s", k ? ", " : "", *e);
}

static int is_extra(const char *const *extra, const char *key)
{
    for (; extra && *extra; extra++)
        if (strcmp(*extra, key) == 0) return 1;
    return 0;
}

int eo_params_load(eo_ctx *ctx, const eo_param_desc *d, void *obj, const json_t *section,
                   const char *const *extra_keys, const eo_param_src *src)
{
    if (!section) return EO_OK;
    if (!json_is_object(section))
        return perr(ctx, EO_ERR_TYPE, src, NULL, "expected an object, got %s",
                    eo_json_type_name(section));
    const char *key;
    json_t *v;
    json_object_foreach((json_t *)section, key, v) {
        const eo_param_desc *p = eo_params_find(d, key);
        if (!p) {
            if (is_extra(extra_keys, key)) continue;
            char list[1024], prefix[256], hint[384];
            eo_params_keys(d, extra_keys, list, sizeof list);
            snprintf(prefix, sizeof prefix, "%s%s", src && src->path ? src->path : "",
                     src && src->path && *src->path ? "." : "");
            eo_suggest_hint(key, list, prefix, hint, sizeof hint);
            return perr(ctx, EO_ERR_UNKNOWN_KEY, src, key, "unknown key%s; valid keys here: %s", hint,
                        list[0] ? list : "(none)");
        }
        int rc = eo_params_set_json(ctx, p, obj, v, src);
        if (rc < 0) return rc;
    }
    return EO_OK;
}

json_t *eo_params_to_json(const eo_param_desc *d, const void *obj)
{
    json_t *o = json_object();
    for (const eo_param_desc *p = d; p && p->kind != EO_PARAM_END; p++) {
        json_t *v = NULL;
        switch (p->kind) {
        case EO_PARAM_INT: v = json_integer(*CFIELD(obj, p, int)); break;
        case EO_PARAM_BOOL: v = json_boolean(*CFIELD(obj, p, int)); break;
        case EO_PARAM_DOUBLE: v = json_real(*CFIELD(obj, p, double)); break;
        case EO_PARAM_STRING:
        case EO_PARAM_CHOICE:
        case EO_PARAM_METHOD: v = json_string(CFIELD(obj, p, char)); break;
        case EO_PARAM_VEC3: {
            const double *a = CFIELD(obj, p, double);
            v = json_pack("[fff]", a[0], a[1], a[2]);
            break;
        }
        case EO_PARAM_END: break;
        }
        if (v) json_object_set_new(o, p->key, v);
    }
    return o;
}

void eo_params_help(FILE *f, const eo_param_desc *d, const char *prefix)
{
    for (const eo_param_desc *p = d; p && p->kind != EO_PARAM_END; p++) {
        char key[160], def[96], rng[96], ch[512];
        snprintf(key, sizeof key, "%s%s%s", prefix && *prefix ? prefix : "",
                 prefix && *prefix ? "." : "", p->key);
        switch (p->kind) {
        case EO_PARAM_INT:
        case EO_PARAM_BOOL:
            if (p->kind == EO_PARAM_BOOL) snprintf(def, sizeof def, "%s", p->def.i ? "true" : "false");
            else snprintf(def, sizeof def, "%ld", p->def.i);
            break;
        case EO_PARAM_DOUBLE: snprintf(def, sizeof def, "%g", p->def.d); break;
        case EO_PARAM_VEC3:
            snprintf(def, sizeof def, "[%g, %g, %g]", p->def.v[0], p->def.v[1], p->def.v[2]);
            break;
        default: snprintf(def, sizeof def, "\"%s\"", p->def.s ? p->def.s : ""); break;
        }
        format_range(p, rng, sizeof rng);
        fprintf(f, "  %-34s %-8s default %-14s %s%s%s\n", key, kind_name(p->kind), def,
                p->help ? p->help : "", rng[0] ? "; range " : "", rng);
        if (p->kind == EO_PARAM_CHOICE || p->kind == EO_PARAM_METHOD) {
            choices_list(p, ch, sizeof ch);
            fprintf(f, "  %-34s %-8s one of: %s\n", "", "", ch);
        }
    }
}

/* JSON Schema (draft 2020-12) of one parameter. */
static json_t *param_schema(const eo_param_desc *p)
{
    json_t *o = json_object();
    switch (p->kind) {
    case EO_PARAM_INT: json_object_set_new(o, "type", json_string("integer")); break;
    case EO_PARAM_DOUBLE: json_object_set_new(o, "type", json_string("number")); break;
    case EO_PARAM_BOOL: json_object_set_new(o, "type", json_string("boolean")); break;
    case EO_PARAM_STRING: json_object_set_new(o, "type", json_string("string")); break;
    case EO_PARAM_CHOICE:
    case EO_PARAM_METHOD: {
        json_object_set_new(o, "type", json_string("string"));
        json_t *e = json_array();
        if (p->kind == EO_PARAM_CHOICE)
            for (const char *const *c = p->choices; c && *c; c++) json_array_append_new(e, json_string(*c));
        else {
            for (const void *const *t = eo_registry_types(p->registry); t && *t; t++)
                json_array_append_new(e, json_string(eo_method_info_of(*t)->name));
            for (const char *const *c = p->choices; c && *c; c++) json_array_append_new(e, json_string(*c));
        }
        json_object_set_new(o, "enum", e);
        break;
    }
    case EO_PARAM_VEC3:
        json_object_set_new(o, "type", json_string("array"));
        json_object_set_new(o, "items", json_pack("{s:s}", "type", "number"));
        json_object_set_new(o, "minItems", json_integer(3));
        json_object_set_new(o, "maxItems", json_integer(3));
        break;
    default: break;
    }
    if (p->kind == EO_PARAM_INT || p->kind == EO_PARAM_DOUBLE) {
        if (p->range & EO_RANGE_MIN) json_object_set_new(o, "minimum", json_real(p->min));
        if (p->range & EO_RANGE_MIN_OPEN) json_object_set_new(o, "exclusiveMinimum", json_real(p->min));
        if (p->range & EO_RANGE_MAX) json_object_set_new(o, "maximum", json_real(p->max));
        if (p->range & EO_RANGE_MAX_OPEN) json_object_set_new(o, "exclusiveMaximum", json_real(p->max));
    }
    switch (p->kind) {
    case EO_PARAM_INT: json_object_set_new(o, "default", json_integer(p->def.i)); break;
    case EO_PARAM_BOOL: json_object_set_new(o, "default", json_boolean(p->def.i)); break;
    case EO_PARAM_DOUBLE: json_object_set_new(o, "default", json_real(p->def.d)); break;
    case EO_PARAM_VEC3:
        json_object_set_new(o, "default", json_pack("[fff]", p->def.v[0], p->def.v[1], p->def.v[2]));
        break;
    default: json_object_set_new(o, "default", json_string(p->def.s ? p->def.s : "")); break;
    }
    if (p->help) json_object_set_new(o, "description", json_string(p->help));
    return o;
}

json_t *eo_params_schema(const eo_param_desc *d, const char *description)
{
    json_t *o = json_object(), *props = json_object();
    json_object_set_new(o, "type", json_string("object"));
    if (description) json_object_set_new(o, "description", json_string(description));
    for (const eo_param_desc *p = d; p && p->kind != EO_PARAM_END; p++)
        json_object_set_new(props, p->key, param_schema(p));
    json_object_set_new(o, "properties", props);
    json_object_set_new(o, "additionalProperties", json_false());
    return o;
}

long eo_utf8_invalid_at(const char *s)
{
    const unsigned char *p = (const unsigned char *)s, *b = p;
    while (*p) {
        unsigned c = *p;
        int len = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
        if (!len) return (long)(p - b);
        unsigned cp = len == 1 ? c : len == 2 ? c & 0x1f : len == 3 ? c & 0x0f : c & 0x07;
        for (int i = 1; i < len; i++) {
            if ((p[i] & 0xc0) != 0x80) return (long)(p - b);
            cp = (cp << 6) | (p[i] & 0x3f);
        }
        /* overlong forms, surrogates, beyond U+10FFFF */
        if ((len == 2 && cp < 0x80) || (len == 3 && cp < 0x800) || (len == 4 && cp < 0x10000) ||
            (cp >= 0xd800 && cp <= 0xdfff) || cp > 0x10ffff)
            return (long)(p - b);
        p += len;
    }
    return -1;
}

json_t *eo_json_from_override(const char *text)
{
    json_error_t err;
    json_t *v = json_loads(text, JSON_DECODE_ANY, &err);
    if (v) return v;
    return json_string(text);
}

/* ---- locating a key path in JSON text ------------------------------------------
 * A small scanner that walks the text with a stack of containers, tracking the key
 * path of the value being scanned. It reports the position of the key (for object
 * members) or of the value (for array items) whose path equals `path`. */
typedef struct {
    const char *s;
    long line, col;
} jscan;

static void js_adv(jscan *j)
{
    if (*j->s == '\n') {
        j->line++;
        j->col = 1;
    } else {
        j->col++;
    }
    j->s++;
}

static void js_ws(jscan *j)
{
    while (*j->s == ' ' || *j->s == '\t' || *j->s == '\n' || *j->s == '\r') js_adv(j);
}

/* reads a string into buf (truncated), s at the opening quote */
static int js_string(jscan *j, char *buf, size_t n)
{
    size_t k = 0;
    if (*j->s != '"') return -1;
    js_adv(j);
    while (*j->s && *j->s != '"') {
        if (*j->s == '\\' && j->s[1]) {
            js_adv(j);
        }
        if (k + 1 < n) buf[k++] = *j->s;
        js_adv(j);
    }
    if (*j->s != '"') return -1;
    js_adv(j);
    buf[k] = 0;
    return 0;
}

static int js_value(jscan *j, const char *path, const char *want, long *line, long *col, int depth);

static int js_check(const char *path, const char *want, long l, long c, long *line, long *col)
{
    if (strcmp(path, want) == 0) {
        *line = l;
        *col = c;
        return 1;
    }
    return 0;
}

static int js_value(jscan *j, const char *path, const char *want, long *line, long *col, int depth)
{
    char sub[512], key[256];
    if (depth > 64) return -1;
    js_ws(j);
    if (*j->s == '{') {
        js_adv(j);
        js_ws(j);
        if (*j->s == '}') {
            js_adv(j);
            return 0;
        }
        for (;;) {
            js_ws(j);
            long kl = j->line, kc = j->col;
            if (js_string(j, key, sizeof key) < 0) return -1;
            snprintf(sub, sizeof sub, "%s%s%s", path, *path ? "." : "", key);
            if (js_check(sub, want, kl, kc, line, col)) return 1;
            js_ws(j);
            if (*j->s != ':') return -1;
            js_adv(j);
            int r = js_value(j, sub, want, line, col, depth + 1);
            if (r) return r;
            js_ws(j);
            if (*j->s == ',') {
                js_adv(j);
                continue;
            }
            if (*j->s == '}') {
                js_adv(j);
                return 0;
            }
            return -1;
        }
    } else if (*j->s == '[') {
        js_adv(j);
        js_ws(j);
        if (*j->s == ']') {
            js_adv(j);
            return 0;
        }
        for (int i = 0;; i++) {
            js_ws(j);
            snprintf(sub, sizeof sub, "%s%s%d", path, *path ? "." : "", i);
            if (js_check(sub, want, j->line, j->col, line, col)) return 1;
            int r = js_value(j, sub, want, line, col, depth + 1);
            if (r) return r;
            js_ws(j);
            if (*j->s == ',') {
                js_adv(j);
                continue;
            }
            if (*j->s == ']') {
                js_adv(j);
                return 0;
            }
            return -1;
        }
    } else if (*j->s == '"') {
        return js_string(j, key, sizeof key) < 0 ? -1 : 0;
    } else {
        if (!*j->s) return -1;
        while (*j->s && !strchr(",]} \t\r\n", *j->s)) js_adv(j);
        return 0;
    }
}

int eo_json_locate(const char *text, const char *path, long *line, long *col)
{
    jscan j = {text, 1, 1};
    long l = -1, c = -1;
    int r = js_value(&j, "", path, &l, &c, 0);
    if (r == 1) {
        *line = l;
        *col = c;
        return 0;
    }
    return -1;
}
