/* Material registry: one line per model. */
#include "elastopt/material.h"

const void *const eo_registry_material[] = {
    NULL,
};
