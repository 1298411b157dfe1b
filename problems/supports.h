/* The load-time support check of static scenes (problems/rigid_modes.c). Private to the
 * library. */
#ifndef EO_PROBLEMS_SUPPORTS_H
#define EO_PROBLEMS_SUPPORTS_H

#include "elastopt/scene.h"

/* For an integrator without inertia (`static`): every body (connected component) must
 * have no free rigid-body mode under the constrained set of the first step and of the
 * first step after each release within the run. EO_ERR_INVALID naming the free modes
 * (eo_scene_rigid_modes) at the `boundary` key (time.integrator if there is none),
 * EO_ERR_NOMEM; EO_OK for other integrators. */
int eo_scene_check_supports(eo_ctx *ctx, eo_cfg *cfg, const eo_scene *sc);

#endif
