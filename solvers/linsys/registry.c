/* Registry of the linsys folder: one line per method. */
#include "elastopt/linsolve.h"

const void *const eo_registry_linsolve[] = {
    NULL,
};
