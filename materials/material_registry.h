/* The material registry (materials/registry.c). Private to the library: programs use
 * eo_registry_of(EO_KIND_MATERIAL) (registry.h). */
#ifndef EO_MATERIALS_MATERIAL_REGISTRY_H
#define EO_MATERIALS_MATERIAL_REGISTRY_H

#include "elastopt/registry.h"

extern eo_registry eo_reg_material;

#endif
