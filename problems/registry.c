/* Integrator and scene registries: one line per method. */
#include "elastopt/registry.h"
#include "elastopt/scene.h"
#include "elastopt/step.h"

#include <stddef.h>

extern const eo_integrator_type eo_integrator_newmark, eo_integrator_backward_euler,
    eo_integrator_static, eo_integrator_forward_euler, eo_integrator_symplectic_euler,
    eo_integrator_heun, eo_integrator_midpoint, eo_integrator_rk4, eo_integrator_verlet,
    eo_integrator_leapfrog;
extern const eo_scene_type eo_scene_cantilever, eo_scene_cantilever_static, eo_scene_twist,
    eo_scene_stretch, eo_scene_freefall, eo_scene_inverted, eo_scene_drop;

const void *const eo_registry_integrator[] = {
    &eo_integrator_newmark,
    &eo_integrator_backward_euler,
    &eo_integrator_static,
    &eo_integrator_forward_euler,
    &eo_integrator_symplectic_euler,
    &eo_integrator_heun,
    &eo_integrator_midpoint,
    &eo_integrator_rk4,
    &eo_integrator_verlet,
    &eo_integrator_leapfrog,
    NULL,
};

const void *const eo_registry_scene[] = {
    &eo_scene_cantilever,
    &eo_scene_cantilever_static,
    &eo_scene_twist,
    &eo_scene_stretch,
    &eo_scene_freefall,
    &eo_scene_inverted,
    &eo_scene_drop,
    NULL,
};
