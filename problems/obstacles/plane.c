/* Obstacle `plane`: the half-space behind a plane through `point` with unit `normal`
 * pointing to the free side,
 *
 *     d(x) = −(x − p)·n,   outward normal n,   κ = 0 (∇²d = 0).
 *
 * Penalty k/2 d² for d > 0: ∇ = −k d n, ∇² = k n nᵀ. */
#include <math.h>

#include "../obstacle.h"

static const char *setup(double *p, const char **key)
{
    eo_scene_plane_opts *pl = (eo_scene_plane_opts *)p;
    double s = sqrt(pl->normal[0] * pl->normal[0] + pl->normal[1] * pl->normal[1] + pl->normal[2] * pl->normal[2]);
    if (!(s > 0)) {
        *key = "normal";
        return "zero normal";
    }
    for (int k = 0; k < 3; k++) pl->normal[k] /= s;
    return NULL;
}

static double depth(const double *p, const double x[3], double n[3], double *kappa)
{
    const eo_scene_plane_opts *pl = (const eo_scene_plane_opts *)p;
    double d = 0;
    for (int k = 0; k < 3; k++) {
        d -= (x[k] - pl->point[k]) * pl->normal[k];
        n[k] = pl->normal[k];
    }
    *kappa = 0;
    return d;
}

const eo_obstacle_type eo_obstacle_plane = {
    .name = "plane",
    .summary = "half-space obstacle: its boundary plane {point, normal}; the normal points to the free side",
    .doc_path = "collisions.N.plane",
    .params = eo_scene_plane_opts_desc,
    .params_size = sizeof(eo_scene_plane_opts),
    .setup = setup,
    .depth = depth,
};
