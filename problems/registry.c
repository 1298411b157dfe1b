/* Integrator and scene registries: one line per method. */
#include "elastopt/registry.h"
#include "elastopt/scene.h"
#include "elastopt/step.h"

#include <stddef.h>

extern const eo_integrator_type eo_integrator_newmark, eo_integrator_backward_euler,
    eo_integrator_static;
extern const eo_scene_type eo_scene_cantilever, eo_scene_cantilever_static, eo_scene_twist,
    eo_scene_stretch, eo_scene_freefall, eo_scene_inverted;

const void *const eo_registry_integrator[] = {
    &eo_integrator_newmark,
    &eo_integrator_backward_euler,
    &eo_integrator_static,
    NULL,
};

const void *const eo_registry_scene[] = {
    &eo_scene_cantilever,
    &eo_scene_cantilever_static,
    &eo_scene_twist,
    &eo_scene_stretch,
    &eo_scene_freefall,
    &eo_scene_inverted,
    NULL,
};
