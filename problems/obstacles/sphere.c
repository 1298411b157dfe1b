/* Obstacle `sphere`: a solid ball of `radius` r about `center` c,
 *
 *     ρ = |x − c|,   d(x) = r − ρ,   n = (x − c)/ρ,   ∇²d = −(I − n nᵀ)/ρ  (κ = 1/ρ).
 *
 * Penalty k/2 d² for d > 0: ∇ = −k d n, ∇² = k (n nᵀ − (d/ρ)(I − n nᵀ)), whose
 * tangential eigenvalue −k d/ρ is negative (clamped to 0, or |·|, by the projections). */
#include <math.h>
#include <stddef.h>

#include "../obstacle.h"

typedef struct sphere_opts {
    double center[3];   /* m. Default [0, 0, 0]. */
    double radius;      /* m, > 0. Default 1. */
} sphere_opts;

static const eo_param_desc sphere_desc[] = {
    {.key = "center", .kind = EO_PARAM_VEC3, .offset = offsetof(sphere_opts, center), .def.v = {0, 0, 0},
     .help = "centre of the ball (m)"},
    {.key = "radius", .kind = EO_PARAM_DOUBLE, .offset = offsetof(sphere_opts, radius), .def.d = 1, .min = 0,
     .range = EO_RANGE_POSITIVE, .help = "radius of the ball (m)"},
    {0},
};

static double depth(const double *p, const double x[3], double n[3], double *kappa)
{
    const sphere_opts *s = (const sphere_opts *)p;
    double r[3], rho = 0;
    for (int k = 0; k < 3; k++) {
        r[k] = x[k] - s->center[k];
        rho += r[k] * r[k];
    }
    rho = sqrt(rho);
    if (!(rho > 0)) { /* at the centre: any direction; ∇d is undefined there */
        n[0] = n[1] = 0, n[2] = 1;
        *kappa = 0;
        return s->radius;
    }
    for (int k = 0; k < 3; k++) n[k] = r[k] / rho;
    *kappa = 1 / rho;
    return s->radius - rho;
}

const eo_obstacle_type eo_obstacle_sphere = {
    .name = "sphere",
    .summary = "solid ball obstacle {center, radius}: depth r - |x - c|",
    .doc_path = "collisions.N.sphere",
    .params = sphere_desc,
    .params_size = sizeof(sphere_opts),
    .depth = depth,
};
