/* Registry of the stop folder: one line per method. */
#include "elastopt/impl/method.h"
#include "../solver_registry.h"

const void *const eo_registry_stop[] = {
    &eo_stop_relative_decrement,
    &eo_stop_newton_decrement,
    &eo_stop_gradient,
    &eo_stop_characteristic_gradient,
    NULL,
};

static int check_stop(eo_ctx *ctx, const void *type)
{
    const eo_stop_type *t = type;
    if (!t->check) return eo_error(ctx, EO_ERR_INVALID, "register stopping rule '%s': check is required", t->info.name);
    return EO_OK;
}

eo_registry eo_reg_stop = EO_REGISTRY_INIT(EO_KIND_STOP, eo_registry_stop, check_stop);
