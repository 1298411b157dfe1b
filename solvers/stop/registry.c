/* Registry of the stop folder: one line per method. */
#include "elastopt/solver.h"

const void *const eo_registry_stop[] = {
    NULL,
};
