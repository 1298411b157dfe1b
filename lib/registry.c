/* Registries: the generic mechanism (one eo_registry per kind, defined by the layer that
 * owns the kind: materials/registry.c, solvers/<kind>/registry.c, problems/registry.c).
 * This file knows no kind's tables: lookup with the "valid: ..." message, and run-time
 * additions kept in a merged, NULL-terminated array (plain malloc: registries are
 * process-wide, not owned by a context). */
#include "elastopt/registry.h"
#include "elastopt/suggest.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const kind_keys[EO_KIND_COUNT] = {
#define X(e, key, label) [e] = key,
    EO_KIND_LIST(X)
#undef X
};
static const char *const kind_labels[EO_KIND_COUNT] = {
#define X(e, key, label) [e] = label,
    EO_KIND_LIST(X)
#undef X
};

const char *eo_kind_key(eo_kind kind)
{
    return (unsigned)kind < EO_KIND_COUNT ? kind_keys[kind] : "?";
}
const char *eo_kind_label(eo_kind kind)
{
    return (unsigned)kind < EO_KIND_COUNT ? kind_labels[kind] : "?";
}

const void *const *eo_registry_types(const eo_registry *r)
{
    if (!r) return NULL;
    return r->all ? (const void *const *)r->all : r->builtin;
}

void eo_registry_name_list(const eo_registry *r, char *buf, size_t n)
{
    size_t k = 0;
    if (!n) return;
    buf[0] = 0;
    for (const void *const *t = eo_registry_types(r); t && *t && k < n; t++)
        k += (size_t)snprintf(buf + k, n - k, "%s%s", k ? ", " : "", eo_method_info_of(*t)->name);
}

int eo_registry_lookup(eo_ctx *ctx, const eo_registry *r, const char *name, const void **out)
{
    *out = NULL;
    for (const void *const *t = eo_registry_types(r); t && *t && name; t++)
        if (strcmp(eo_method_info_of(*t)->name, name) == 0) {
            *out = *t;
            return EO_OK;
        }
    char list[1024], hint[128];
    eo_registry_name_list(r, list, sizeof list);
    eo_suggest_hint(name, list, NULL, hint, sizeof hint);
    return eo_error(ctx, EO_ERR_UNKNOWN_NAME, "unknown %s '%s'%s; valid: %s", r ? eo_kind_label(r->kind) : "method",
                    name ? name : "(null)", hint, list[0] ? list : "(none built)");
}

static int valid_name(const char *s)
{
    if (!s || !*s || strlen(s) > 31) return 0;
    for (; *s; s++) {
        char c = *s;
        if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-'))
            return 0;
    }
    return 1;
}

int eo_registry_add(eo_ctx *ctx, eo_registry *r, const void *type)
{
    if (!r) return eo_error(ctx, EO_ERR_INVALID, "register: no such kind");
    const char *label = eo_kind_label(r->kind);
    if (!type) return eo_error(ctx, EO_ERR_INVALID, "register %s: NULL table", label);
    const eo_method_info *mi = eo_method_info_of(type);
    if (!valid_name(mi->name))
        return eo_error(ctx, EO_ERR_INVALID,
                        "register %s: name '%s' must be 1-31 letters, digits, '_' or '-'", label,
                        mi->name ? mi->name : "(null)");
    if (!mi->summary) return eo_error(ctx, EO_ERR_INVALID, "register %s '%s': no summary", label, mi->name);
    if ((mi->params != NULL) != (mi->params_size != 0))
        return eo_error(ctx, EO_ERR_INVALID, "register %s '%s': params and params_size must be set together",
                        label, mi->name);
    for (const void *const *t = eo_registry_types(r); t && *t; t++)
        if (*t == type || strcmp(eo_method_info_of(*t)->name, mi->name) == 0)
            return eo_error(ctx, EO_ERR_INVALID, "register %s '%s': a %s of that name is already registered",
                            label, mi->name, label);
    if (r->check) {
        int rc = r->check(ctx, type);
        if (rc < 0) return rc;
    }
    if (!r->all) { /* first addition: copy the built-ins into the merged array */
        int nb = 0;
        while (r->builtin && r->builtin[nb]) nb++;
        int cap = nb + 8;
        const void **a = malloc((size_t)cap * sizeof *a);
        if (!a) return eo_error(ctx, EO_ERR_NOMEM, "register: out of memory");
        for (int i = 0; i < nb; i++) a[i] = r->builtin[i];
        a[nb] = NULL;
        r->all = a;
        r->nall = nb;
        r->cap = cap;
    }
    if (r->nall + 2 > r->cap) {
        int cap = 2 * r->cap;
        const void **a = realloc(r->all, (size_t)cap * sizeof *a);
        if (!a) return eo_error(ctx, EO_ERR_NOMEM, "register: out of memory");
        r->all = a;
        r->cap = cap;
    }
    r->all[r->nall++] = type;
    r->all[r->nall] = NULL;
    return EO_OK;
}

int eo_registry_remove(eo_registry *r, const void *type)
{
    if (!r || !r->all) return EO_ERR_INVALID;
    for (const void *const *b = r->builtin; b && *b; b++)
        if (*b == type) return EO_ERR_INVALID;
    for (int i = 0; i < r->nall; i++)
        if (r->all[i] == type) {
            memmove(r->all + i, r->all + i + 1, (size_t)(r->nall - i) * sizeof *r->all);
            r->nall--;
            return EO_OK;
        }
    return EO_ERR_INVALID;
}
