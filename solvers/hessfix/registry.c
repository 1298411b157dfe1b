/* Registry of the hessfix folder: one line per method. */
#include "elastopt/solver.h"
#include "../solver_registry.h"

const void *const eo_registry_hessfix[] = {
    &eo_hessfix_none,
    &eo_hessfix_shift,
    &eo_hessfix_clamp,
    &eo_hessfix_abs,
    NULL,
};

eo_registry eo_reg_hessfix = EO_REGISTRY_INIT(EO_KIND_HESSFIX, eo_registry_hessfix, NULL);
