/* Registry of the hessfix folder: one line per method. */
#include "elastopt/impl/method.h"
#include "../solver_registry.h"

const void *const eo_registry_hessfix[] = {
    &eo_hessfix_none,
    &eo_hessfix_shift,
    &eo_hessfix_clamp,
    &eo_hessfix_abs,
    &eo_hessfix_project_on_demand,
    &eo_hessfix_progressive,
    &eo_hessfix_trust_region_filter,
    NULL,
};

static int check_hessfix(eo_ctx *ctx, const void *type)
{
    const eo_hessfix_type *t = type;
    if (!t->factor)
        return eo_error(ctx, EO_ERR_INVALID, "register Hessian fix '%s': factor is required", t->info.name);
    if (t->info.params && !t->info.params_size)
        return eo_error(ctx, EO_ERR_INVALID, "register Hessian fix '%s': params without params_size",
                        t->info.name);
    return EO_OK;
}

eo_registry eo_reg_hessfix = EO_REGISTRY_INIT(EO_KIND_HESSFIX, eo_registry_hessfix, check_hessfix);
