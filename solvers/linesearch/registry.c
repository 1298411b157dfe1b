/* Registry of the linesearch folder: one line per method. */
#include "elastopt/solver.h"

const void *const eo_registry_linesearch[] = {
    NULL,
};
