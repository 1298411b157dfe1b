/* Integrator and scene registries: one line per method. */
#include "elastopt/registry.h"

#include <stddef.h>

const void *const eo_registry_integrator[] = {
    NULL,
};

const void *const eo_registry_scene[] = {
    NULL,
};
