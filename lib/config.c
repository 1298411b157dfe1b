/* Configuration documents: JSON text + -o overrides, consumed section by section.
 *
 * Consumption is tracked per dotted path in a jansson object used as a map:
 *   1 = partially consumed (a section or the parent of something read): its members
 *       must each be consumed too;
 *   2 = consumed whole (read as raw JSON by the caller).
 * eo_cfg_finish walks the document and reports the first member with no mark. */
#include "elastopt/config.h"
#include "elastopt/io.h"
#include "elastopt/suggest.h"

#include <stdarg.h>
#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct eo_cfg {
    json_t *root;
    json_t *marks;   /* path -> 1|2 */
    json_t *valid;   /* level path -> "k1, k2, ..." valid keys recorded by section loads */
    char *file;      /* eo_malloc'd */
    char *text;      /* file text (eo_malloc'd), NULL for overrides-only */
    char *overridden;/* "\npath\n..." */
    size_t overridden_len;
    eo_ctx *ctx;                       ///< context it was created with (its destroy uses it)
};

#define PATH_MAX_LEN 512

int eo_cfg_create_empty(eo_ctx *ctx, eo_cfg **out)
{
    *out = NULL;
    eo_cfg *c = eo_calloc(ctx, 1, sizeof *c);
    if (c) c->ctx = ctx;
    if (!c) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    c->root = json_object();
    c->marks = json_object();
    c->valid = json_object();
    c->file = eo_strdup(ctx, "<builtin>");
    c->overridden = eo_strdup(ctx, "\n");
    if (!c->root || !c->marks || !c->valid || !c->file || !c->overridden) {
        eo_cfg_destroy(&c);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    }
    c->overridden_len = 1;
    *out = c;
    return EO_OK;
}

void eo_cfg_destroy(eo_cfg **cfg)
{
    eo_ctx *ctx = cfg && *cfg ? (*cfg)->ctx : NULL;
    if (!cfg || !*cfg) return;
    eo_cfg *c = *cfg;
    json_decref(c->root);
    json_decref(c->marks);
    json_decref(c->valid);
    eo_free(ctx, c->file);
    eo_free(ctx, c->text);
    eo_free(ctx, c->overridden);
    eo_free(ctx, c);
    *cfg = NULL;
}

int eo_cfg_load(eo_ctx *ctx, const char *path, const char *builtin_text, eo_cfg **out)
{
    eo_cfg *c = NULL;
    int rc = eo_cfg_create_empty(ctx, &c);
    if (rc < 0) return rc;
    if (path) {
        size_t len;
        rc = eo_read_file_max(ctx, path, EO_CFG_MAX_BYTES, "a configuration file (EO_CFG_MAX_BYTES)", &c->text,
                              &len);
        if (rc < 0) goto fail;
        if (strlen(c->text) != len) {
            rc = eo_error_at(ctx, EO_ERR_PARSE, EO_ERRLOC_FILE(path, -1),
                             "config contains a NUL byte; expected JSON text");
            goto fail;
        }
        eo_free(ctx, c->file);
        c->file = eo_strdup(ctx, path);
        if (!c->file) {
            rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory");
            goto fail;
        }
    } else {
        c->text = eo_strdup(ctx, builtin_text ? builtin_text : "{}");
        if (!c->text) {
            rc = eo_error(ctx, EO_ERR_NOMEM, "out of memory");
            goto fail;
        }
    }
    json_error_t err;
    json_t *root = json_loads(c->text, JSON_REJECT_DUPLICATES, &err);
    if (!root) {
        eo_errloc loc = {c->file, err.line, err.column, NULL, -1};
        rc = eo_error_at(ctx, EO_ERR_PARSE, loc, "malformed JSON: %s", err.text);
        goto fail;
    }
    if (!json_is_object(root)) {
        json_decref(root);
        rc = eo_error_at(ctx, EO_ERR_TYPE, EO_ERRLOC_FILE(c->file, 1),
                         "expected a JSON object at the top level");
        goto fail;
    }
    json_decref(c->root);
    c->root = root;
    *out = c;
    return EO_OK;
fail:
    eo_cfg_destroy(&c);
    return rc;
}

static int is_index(const char *s)
{
    if (!*s) return 0;
    for (; *s; s++)
        if (*s < '0' || *s > '9') return 0;
    return 1;
}

int eo_cfg_override(eo_ctx *ctx, eo_cfg *cfg, const char *assignment)
{
    long bad = eo_utf8_invalid_at(assignment);
    if (bad >= 0)
        return eo_error(ctx, EO_ERR_INVALID, "command line -o: invalid UTF-8 at byte %ld of '%.*s...'", bad + 1,
                        (int)(bad < 64 ? bad : 64), assignment);
    size_t alen = strnlen(assignment, EO_CFG_MAX_BYTES + 1);
    if (alen > EO_CFG_MAX_BYTES)
        return eo_error(ctx, EO_ERR_RANGE, "command line -o '%.40s...': more than %zu bytes (EO_CFG_MAX_BYTES)",
                        assignment, EO_CFG_MAX_BYTES);
    const char *eq = strchr(assignment, '=');
    if (!eq || eq == assignment)
        return eo_error(ctx, EO_ERR_INVALID, "override '%s': expected key=value", assignment);
    size_t klen = (size_t)(eq - assignment);
    if (klen >= PATH_MAX_LEN)
        return eo_error(ctx, EO_ERR_INVALID, "override '%.40s...': key too long (%zu bytes, at most %d)",
                        assignment, klen, PATH_MAX_LEN - 1);
    char key[PATH_MAX_LEN];
    memcpy(key, assignment, klen);
    key[klen] = 0;
    /* every dotted component must be non-empty: "time..dt", ".dt", "time.dt." are errors */
    for (size_t i = 0; i <= klen; i++)
        if ((i == klen || key[i] == '.') && (i == 0 || key[i - 1] == '.'))
            return eo_error(ctx, EO_ERR_INVALID, "command line -o %s: empty key component (%s)", key,
                            i == 0 ? "leading '.'" : i == klen ? "trailing '.'" : "'..'");
    json_t *value = eo_json_from_override(eq + 1);
    if (!value) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");

    /* walk/create the containers; the key has no empty component */
    json_t *node = cfg->root;
    char work[PATH_MAX_LEN];
    memcpy(work, key, klen + 1);
    char prefix[PATH_MAX_LEN + 8] = ""; /* a prefix of the key: never truncated */
    for (char *part = work;;) {
        char *dot = strchr(part, '.');
        char *next = NULL;
        if (dot) {
            *dot = 0;
            next = dot + 1;
        }
        if (json_is_array(node)) {
            if (!is_index(part) || (size_t)atol(part) >= json_array_size(node)) {
                json_decref(value);
                return eo_error(ctx, EO_ERR_INVALID,
                                "command line -o %s: '%s' is a list of %zu items; expected an index",
                                key, prefix, json_array_size(node));
            }
            size_t i = (size_t)atol(part);
            if (!next) {
                if (json_array_set_new(node, i, value) < 0)
                    return eo_error(ctx, EO_ERR_NOMEM, "command line -o %s: cannot set the item", key);
                goto done;
            }
            node = json_array_get(node, i);
        } else if (json_is_object(node)) {
            if (!next) {
                /* json_object_set_new consumes value even when it fails */
                if (json_object_set_new(node, part, value) < 0)
                    return eo_error(ctx, EO_ERR_INVALID, "command line -o %s: key '%s' rejected", key, part);
                goto done;
            }
            json_t *child = json_object_get(node, part);
            if (!child) {
                child = json_object();
                if (!child || json_object_set_new(node, part, child) < 0) {
                    json_decref(value);
                    return eo_error(ctx, EO_ERR_INVALID, "command line -o %s: key '%s' rejected", key, part);
                }
            }
            node = child;
        } else {
            json_decref(value);
            return eo_error(ctx, EO_ERR_TYPE, "command line -o %s: '%s' is a %s, not a section", key,
                            prefix, eo_json_type_name(node));
        }
        size_t pl = strlen(prefix), ql = strlen(part);
        if (pl + ql + 2 < sizeof prefix) {
            if (pl) prefix[pl++] = '.';
            memcpy(prefix + pl, part, ql + 1);
        }
        part = next;
    }
done: {
    size_t need = cfg->overridden_len + klen + 2;
    char *o = eo_realloc(ctx, cfg->overridden, need);
    if (!o) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    memcpy(o + cfg->overridden_len, key, klen);
    o[cfg->overridden_len + klen] = '\n';
    o[need - 1] = 0;
    cfg->overridden = o;
    cfg->overridden_len = need - 1;
    return EO_OK;
}
}

static json_t *lookup(json_t *root, const char *path)
{
    char work[PATH_MAX_LEN], *save = NULL;
    if (!*path) return root;
    snprintf(work, sizeof work, "%s", path);
    json_t *node = root;
    for (char *p = strtok_r(work, ".", &save); p && node; p = strtok_r(NULL, ".", &save)) {
        if (json_is_object(node)) node = json_object_get(node, p);
        else if (json_is_array(node) && is_index(p)) node = json_array_get(node, (size_t)atol(p));
        else node = NULL;
    }
    return node;
}

static void mark(eo_cfg *cfg, const char *path, int how)
{
    char work[PATH_MAX_LEN];
    snprintf(work, sizeof work, "%s", path);
    json_t *old = json_object_get(cfg->marks, work);
    if (!old || json_integer_value(old) < how) json_object_set_new(cfg->marks, work, json_integer(how));
    for (char *dot = strrchr(work, '.'); dot; dot = strrchr(work, '.')) {
        *dot = 0;
        if (!json_object_get(cfg->marks, work)) json_object_set_new(cfg->marks, work, json_integer(1));
    }
}

json_t *eo_cfg_get(eo_cfg *cfg, const char *path)
{
    json_t *v = lookup(cfg->root, path);
    if (v) mark(cfg, path, 2);
    return v;
}

void eo_cfg_expect(eo_cfg *cfg, const char *path, const char *const *keys)
{
    char list[1024];
    eo_params_keys(NULL, keys, list, sizeof list);
    json_object_set_new(cfg->valid, path, json_string(list));
}

void eo_cfg_consume(eo_cfg *cfg, const char *path) { mark(cfg, path, 2); }

eo_param_src eo_cfg_src(eo_cfg *cfg, const char *path)
{
    eo_param_src s = {cfg->file, cfg->text, path, cfg->overridden};
    return s;
}

int eo_cfg_section(eo_ctx *ctx, eo_cfg *cfg, const char *path, const eo_param_desc *d,
                   void *obj, const char *const *extra)
{
    char list[1024];
    eo_params_keys(d, extra, list, sizeof list);
    json_object_set_new(cfg->valid, path, json_string(list));
    json_t *sec = lookup(cfg->root, path);
    if (!sec) return EO_OK;
    mark(cfg, path, 1);
    eo_param_src src = eo_cfg_src(cfg, path);
    int rc = eo_params_load(ctx, d, obj, sec, extra, &src);
    if (rc < 0) return rc;
    const char *key;
    json_t *v;
    json_object_foreach(sec, key, v) {
        if (eo_params_find(d, key)) {
            char sub[PATH_MAX_LEN];
            snprintf(sub, sizeof sub, "%s%s%s", path, *path ? "." : "", key);
            mark(cfg, sub, 2);
        }
    }
    return EO_OK;
}

static int walk(eo_ctx *ctx, eo_cfg *cfg, json_t *node, const char *path)
{
    char sub[PATH_MAX_LEN];
    if (json_is_object(node)) {
        const char *key;
        json_t *v;
        json_object_foreach(node, key, v) {
            snprintf(sub, sizeof sub, "%s%s%s", path, *path ? "." : "", key);
            json_t *m = json_object_get(cfg->marks, sub);
            if (!m) {
                json_t *valid = json_object_get(cfg->valid, path);
                char prefix[PATH_MAX_LEN + 1], hint[2 * PATH_MAX_LEN];
                snprintf(prefix, sizeof prefix, "%s%s", path, *path ? "." : "");
                eo_suggest_hint(key, valid ? json_string_value(valid) : "", prefix, hint, sizeof hint);
                eo_param_src src = eo_cfg_src(cfg, path);
                eo_errloc loc = EO_ERRLOC_NONE;
                char needle[PATH_MAX_LEN + 2];
                snprintf(needle, sizeof needle, "\n%s\n", sub);
                if (strstr(cfg->overridden, needle))
                    return eo_error(ctx, EO_ERR_UNKNOWN_KEY,
                                    "command line -o %s: unknown key%s; valid keys here: %s", sub, hint,
                                    valid ? json_string_value(valid) : "(none)");
                loc.file = src.file;
                if (cfg->text) eo_json_locate(cfg->text, sub, &loc.line, &loc.column);
                return eo_error_at(ctx, EO_ERR_UNKNOWN_KEY, loc, "unknown key '%s'%s; valid keys here: %s",
                                   sub, hint, valid ? json_string_value(valid) : "(none)");
            }
            if (json_integer_value(m) == 1) {
                int rc = walk(ctx, cfg, v, sub);
                if (rc < 0) return rc;
            }
        }
    } else if (json_is_array(node)) {
        size_t i;
        json_t *v;
        json_array_foreach(node, i, v) {
            snprintf(sub, sizeof sub, "%s%s%zu", path, *path ? "." : "", i);
            json_t *m = json_object_get(cfg->marks, sub);
            if (m && json_integer_value(m) == 1) {
                int rc = walk(ctx, cfg, v, sub);
                if (rc < 0) return rc;
            }
        }
    }
    return EO_OK;
}

int eo_cfg_finish(eo_ctx *ctx, eo_cfg *cfg) { return walk(ctx, cfg, cfg->root, ""); }

json_t *eo_cfg_root(eo_cfg *cfg) { return cfg->root; }
const char *eo_cfg_file(const eo_cfg *cfg) { return cfg->file; }

/* ---- errors located at a key (file:line of the document, or the -o override) */

int eo_cfg_error(eo_ctx *ctx, eo_cfg *cfg, const char *path, int status, const char *fmt, ...)
{
    char text[768];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    eo_param_src src = eo_cfg_src(cfg, path);
    char needle[600];
    snprintf(needle, sizeof needle, "\n%s", path);
    const char *o = src.overridden ? strstr(src.overridden, needle) : NULL;
    if (o && (o[strlen(needle)] == '\n' || o[strlen(needle)] == '.'))
        return eo_error(ctx, status, "command line -o %s: %s", path, text);
    eo_errloc loc = EO_ERRLOC_NONE;
    loc.file = src.file;
    if (src.text) eo_json_locate(src.text, path, &loc.line, &loc.column);
    return eo_error_at(ctx, status, loc, "key '%s': %s", path, text);
}
