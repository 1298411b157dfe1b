/* Registry of the linesearch folder: one line per method. */
#include "elastopt/solver.h"

const void *const eo_registry_linesearch[] = {
    &eo_linesearch_backtracking,
    &eo_linesearch_exact,
    &eo_linesearch_none,
    NULL,
};
