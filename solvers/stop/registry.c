/* Registry of the stop folder: one line per method. */
#include "elastopt/solver.h"

const void *const eo_registry_stop[] = {
    &eo_stop_newton_decrement,
    &eo_stop_gradient,
    NULL,
};
