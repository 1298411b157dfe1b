/* The registries of the solver layer's kinds (defined in solvers/<kind>/registry.c, one
 * line per built-in method there). Private to the library: programs use eo_registry_of
 * (registry.h). */
#ifndef EO_SOLVERS_SOLVER_REGISTRY_H
#define EO_SOLVERS_SOLVER_REGISTRY_H

#include "elastopt/registry.h"

extern eo_registry eo_reg_optimizer, eo_reg_hessfix, eo_reg_linesearch, eo_reg_stop, eo_reg_linsolve;

#endif
