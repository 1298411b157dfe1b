/* Registry of the optim folder: one line per method. */
#include "elastopt/solver.h"

const void *const eo_registry_optimizer[] = {
    &eo_optimizer_newton,
    &eo_optimizer_gradient_descent,
    &eo_optimizer_lbfgs,
    NULL,
};
