/* Registry of the linesearch folder: one line per method. */
#include "elastopt/impl/method.h"
#include "../solver_registry.h"

const void *const eo_registry_linesearch[] = {
    &eo_linesearch_backtracking,
    &eo_linesearch_nonmonotone,
    &eo_linesearch_wolfe,
    &eo_linesearch_exact,
    &eo_linesearch_none,
    &eo_linesearch_barrier_filter,
    NULL,
};

static int check_linesearch(eo_ctx *ctx, const void *type)
{
    const eo_linesearch_type *t = type;
    if (!t->search) return eo_error(ctx, EO_ERR_INVALID, "register line search '%s': search is required", t->info.name);
    return EO_OK;
}

eo_registry eo_reg_linesearch = EO_REGISTRY_INIT(EO_KIND_LINESEARCH, eo_registry_linesearch, check_linesearch);
