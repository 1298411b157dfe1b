/* The registries of the problems layer (problems/registry.c): integrators, built-in
 * scenes, elements and the terms of the step problem. Private to the library: programs use eo_registry_of (registry.h). */
#ifndef EO_PROBLEMS_PROBLEM_REGISTRY_H
#define EO_PROBLEMS_PROBLEM_REGISTRY_H

#include "elastopt/registry.h"

extern eo_registry eo_reg_integrator, eo_reg_scene, eo_reg_element, eo_reg_term;

#endif
