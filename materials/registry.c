/* Material registry: one line per model. */
#include "elastopt/material.h"

extern const eo_material_type eo_material_linear, eo_material_stvk, eo_material_corotated,
    eo_material_fixed_corotated, eo_material_neo_hookean, eo_material_stable_neo_hookean,
    eo_material_spring;

const void *const eo_registry_material[] = {
    &eo_material_linear,
    &eo_material_stvk,
    &eo_material_corotated,
    &eo_material_fixed_corotated,
    &eo_material_neo_hookean,
    &eo_material_stable_neo_hookean,
    &eo_material_spring,
    NULL,
};
