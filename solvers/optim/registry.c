/* Registry of the optim folder: one line per method. */
#include "elastopt/solver.h"

const void *const eo_registry_optimizer[] = {
    NULL,
};
