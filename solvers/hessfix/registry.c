/* Registry of the hessfix folder: one line per method. */
#include "elastopt/solver.h"

const void *const eo_registry_hessfix[] = {
    NULL,
};
