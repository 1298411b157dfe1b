/* Registry of the hessfix folder: one line per method. */
#include "elastopt/solver.h"

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
