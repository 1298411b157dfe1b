/* Registries: one NULL-terminated array per kind, each defined next to its methods
 * (materials/registry.c, solvers/<kind>/registry.c, problems/...). This file only
 * maps kinds to those arrays and implements lookup with the "valid: ..." message. */
#include "elastopt/registry.h"

#include <stdio.h>
#include <string.h>

extern const void *const eo_registry_material[];
extern const void *const eo_registry_optimizer[];
extern const void *const eo_registry_hessfix[];
extern const void *const eo_registry_linesearch[];
extern const void *const eo_registry_stop[];
extern const void *const eo_registry_linsolve[];
extern const void *const eo_registry_integrator[];
extern const void *const eo_registry_scene[];

static const void *const *const kind_arrays[EO_KIND_COUNT] = {
    [EO_KIND_MATERIAL] = eo_registry_material,
    [EO_KIND_OPTIMIZER] = eo_registry_optimizer,
    [EO_KIND_HESSFIX] = eo_registry_hessfix,
    [EO_KIND_LINESEARCH] = eo_registry_linesearch,
    [EO_KIND_STOP] = eo_registry_stop,
    [EO_KIND_LINSOLVE] = eo_registry_linsolve,
    [EO_KIND_INTEGRATOR] = eo_registry_integrator,
    [EO_KIND_SCENE] = eo_registry_scene,
};

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

const void *const *eo_registry_list(eo_kind kind)
{
    return (unsigned)kind < EO_KIND_COUNT ? kind_arrays[kind] : NULL;
}

void eo_registry_names(eo_kind kind, char *buf, size_t n)
{
    size_t k = 0;
    buf[0] = 0;
    for (const void *const *t = eo_registry_list(kind); t && *t && k < n; t++)
        k += (size_t)snprintf(buf + k, n - k, "%s%s", k ? ", " : "", eo_method_info_of(*t)->name);
}

int eo_registry_find(eo_ctx *ctx, eo_kind kind, const char *name, const void **out)
{
    *out = NULL;
    for (const void *const *t = eo_registry_list(kind); t && *t; t++)
        if (strcmp(eo_method_info_of(*t)->name, name) == 0) {
            *out = *t;
            return EO_OK;
        }
    char list[512];
    eo_registry_names(kind, list, sizeof list);
    return eo_error(ctx, EO_ERR_UNKNOWN_NAME, "unknown %s '%s'; valid: %s", eo_kind_label(kind),
                    name, list[0] ? list : "(none built)");
}
